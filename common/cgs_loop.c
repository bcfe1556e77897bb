/* cgs_loop — zmq_poll event loop with timers. */
#include "cgs_loop.h"
#include "cgs_lifecycle.h"

#include <errno.h>
#include <math.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <zmq.h>

typedef struct {
    void *socket;
    int fd;
    cgs_loop_fn *fn;
    void *arg;
    bool removed; // removed during a dispatch: compacted after it
} s_watch_t;

typedef struct {
    int id;
    double interval_s;
    double due; // monotonic seconds
    cgs_loop_fn *fn;
    void *arg;
} s_timer_t;

struct cgs_loop {
    s_watch_t *watches;
    size_t nwatches, capwatches;
    s_timer_t *timers;
    size_t ntimers, captimers;
    int next_id;
    bool stop;
};

double cgs_loop_now (void)
{
    struct timespec ts;
    clock_gettime (CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + ts.tv_nsec * 1e-9;
}

cgs_loop_t *cgs_loop_new (void)
{
    return calloc (1, sizeof (cgs_loop_t));
}

void cgs_loop_destroy (cgs_loop_t **self_p)
{
    if (!self_p || !*self_p)
        return;
    free ((*self_p)->watches);
    free ((*self_p)->timers);
    free (*self_p);
    *self_p = NULL;
}

static int s_add_watch (cgs_loop_t *self, void *socket, int fd, cgs_loop_fn *fn, void *arg)
{
    if (self->nwatches == self->capwatches) {
        size_t cap = self->capwatches ? self->capwatches * 2 : 8;
        s_watch_t *w = realloc (self->watches, cap * sizeof *w);
        if (!w)
            return -ENOMEM;
        self->watches = w;
        self->capwatches = cap;
    }
    self->watches[self->nwatches++] = (s_watch_t){socket, fd, fn, arg, false};
    return 0;
}

int cgs_loop_add_socket (cgs_loop_t *self, void *socket, cgs_loop_fn *fn, void *arg)
{
    return s_add_watch (self, socket, -1, fn, arg);
}

int cgs_loop_add_fd (cgs_loop_t *self, int fd, cgs_loop_fn *fn, void *arg)
{
    return s_add_watch (self, NULL, fd, fn, arg);
}

void cgs_loop_remove (cgs_loop_t *self, void *socket, int fd)
{
    // Only marked here: the loop may be walking the list; it compacts it.
    for (size_t i = 0; i < self->nwatches; i++) {
        s_watch_t *w = &self->watches[i];
        if (!w->removed && ((socket && w->socket == socket) || (!socket && w->fd == fd))) {
            w->removed = true;
            return;
        }
    }
}

static void s_compact (cgs_loop_t *self)
{
    size_t k = 0;
    for (size_t i = 0; i < self->nwatches; i++)
        if (!self->watches[i].removed)
            self->watches[k++] = self->watches[i];
    self->nwatches = k;
}

int cgs_loop_add_timer (cgs_loop_t *self, double interval_s, cgs_loop_fn *fn, void *arg)
{
    if (!(interval_s > 0) || !isfinite (interval_s) || !fn)
        return -EINVAL;
    if (self->ntimers == self->captimers) {
        size_t cap = self->captimers ? self->captimers * 2 : 8;
        s_timer_t *t = realloc (self->timers, cap * sizeof *t);
        if (!t)
            return -ENOMEM;
        self->timers = t;
        self->captimers = cap;
    }
    int id = ++self->next_id;
    self->timers[self->ntimers++] =
        (s_timer_t){id, interval_s, cgs_loop_now () + interval_s, fn, arg};
    return id;
}

void cgs_loop_set_interval (cgs_loop_t *self, int timer_id, double interval_s)
{
    if (!(interval_s > 0) || !isfinite (interval_s))
        return;
    for (size_t i = 0; i < self->ntimers; i++)
        if (self->timers[i].id == timer_id) {
            self->timers[i].interval_s = interval_s;
            self->timers[i].due = cgs_loop_now () + interval_s;
        }
}

void cgs_loop_stop (cgs_loop_t *self)
{
    self->stop = true;
}

int cgs_loop_run (cgs_loop_t *self)
{
    zmq_pollitem_t *items = NULL;
    size_t capitems = 0;
    int rc = 0;
    self->stop = false;
    while (!self->stop && !cgs_lifecycle_stopping ()) {
        double now = cgs_loop_now ();
        double next = now + 1.0;
        for (size_t i = 0; i < self->ntimers; i++)
            if (self->timers[i].due < next)
                next = self->timers[i].due;
        long timeout_ms = (long)ceil ((next - now) * 1000.0);
        if (timeout_ms < 0)
            timeout_ms = 0;
        if (self->nwatches > capitems) {
            zmq_pollitem_t *n = realloc (items, self->nwatches * sizeof *n);
            if (!n) {
                rc = -ENOMEM;
                break;
            }
            items = n;
            capitems = self->nwatches;
        }
        s_compact (self);
        size_t nitems = self->nwatches;
        for (size_t i = 0; i < nitems; i++)
            items[i] =
                (zmq_pollitem_t){self->watches[i].socket, self->watches[i].fd, ZMQ_POLLIN, 0};
        int n = zmq_poll (items, (int)nitems, timeout_ms);
        if (n < 0) {
            if (zmq_errno () == EINTR)
                continue;
            rc = -zmq_errno ();
            break;
        }
        for (size_t i = 0; n > 0 && i < nitems && i < self->nwatches && !self->stop; i++)
            if ((items[i].revents & ZMQ_POLLIN) && !self->watches[i].removed)
                self->watches[i].fn (self->watches[i].arg);
        now = cgs_loop_now ();
        for (size_t i = 0; i < self->ntimers && !self->stop; i++) {
            s_timer_t *t = &self->timers[i];
            if (t->due > now)
                continue;
            // Keep the cadence, but never try to catch up a backlog of ticks.
            t->due += t->interval_s;
            if (t->due < now)
                t->due = now + t->interval_s;
            t->fn (t->arg);
        }
    }
    free (items);
    return rc;
}
