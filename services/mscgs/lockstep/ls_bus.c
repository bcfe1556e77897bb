/* ls_bus — the lockstep engine's in-process bus (see ls_bus.h). */
#include "ls_bus.h"

#include "cgs_msg.h"
#include "cgs_topics.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define S_SOURCE_MAX 64
#define S_TOPICS_MAX 32 // catalogue topics a source publishes on

struct ls_source {
    ls_bus_t *bus;
    char name[S_SOURCE_MAX];
    struct {
        const cgs_topic_t *topic;
        uint64_t seq;
    } seqs[S_TOPICS_MAX];
    size_t nseqs;
    ls_source_stats_t stats;
    uint64_t first_error; // the bus's count of errors when it reported its first
    ls_source_t *next;
};

/* A message waiting for delivery. */
typedef struct {
    const cgs_topic_t *topic;
    uint8_t *data;
    size_t len;
} s_queued_t;

typedef struct {
    const cgs_topic_t *topic;
    cgs_sub_fn *fn;
    void *arg;
} s_sub_t;

struct ls_bus {
    uint32_t exercise_id;
    ls_source_t *sources;
    s_queued_t *queue;
    size_t head, tail, cap; // queue[head..tail) waits
    s_sub_t *subs;
    size_t nsubs, subcap;
    uint8_t *buf;
    size_t bufcap;
    cgs_msg_arena_t *arena;
    FILE *log;
    double time_s;
    uint64_t failures;
    uint64_t errors_seen; // sources that have reported an error, in order
};

ls_bus_t *ls_bus_new (uint32_t exercise_id)
{
    ls_bus_t *self = calloc (1, sizeof *self);
    if (!self)
        return NULL;
    self->exercise_id = exercise_id;
    self->bufcap = 1 << 16;
    self->buf = malloc (self->bufcap);
    self->arena = cgs_msg_arena_new (1 << 16);
    if (!self->buf || !self->arena)
        ls_bus_destroy (&self); // NULL
    return self;
}

void ls_bus_destroy (ls_bus_t **self_p)
{
    ls_bus_t *self = *self_p;
    if (!self)
        return;
    while (self->sources) {
        ls_source_t *s = self->sources;
        self->sources = s->next;
        free (s);
    }
    for (size_t i = self->head; i < self->tail; i++)
        free (self->queue[i].data);
    free (self->queue);
    free (self->subs);
    free (self->buf);
    cgs_msg_arena_destroy (&self->arena);
    free (self);
    *self_p = NULL;
}

void ls_bus_set_log (ls_bus_t *self, FILE *f)
{
    self->log = f;
}

double ls_bus_time (const ls_bus_t *self)
{
    return self->time_s;
}

uint64_t ls_bus_failures (const ls_bus_t *self)
{
    return self->failures;
}

/* ---- publishing ------------------------------------------------------------------------ */

static int s_enqueue (ls_bus_t *self, const cgs_topic_t *topic, const uint8_t *data, size_t len)
{
    if (self->tail == self->cap) {
        if (self->head > 0) { // slide what waits to the front
            memmove (self->queue, self->queue + self->head,
                     (self->tail - self->head) * sizeof *self->queue);
            self->tail -= self->head;
            self->head = 0;
        }
        if (self->tail == self->cap) {
            size_t cap = self->cap ? self->cap * 2 : 256;
            s_queued_t *q = realloc (self->queue, cap * sizeof *q);
            if (!q)
                return -ENOMEM;
            self->queue = q;
            self->cap = cap;
        }
    }
    uint8_t *copy = malloc (len ? len : 1);
    if (!copy)
        return -ENOMEM;
    memcpy (copy, data, len);
    self->queue[self->tail++] = (s_queued_t){topic, copy, len};
    return 0;
}

static int s_publish (void *arg, const char *topic_name, ProtobufCMessage *msg, double sim_time_s)
{
    ls_source_t *src = arg;
    ls_bus_t *self = src->bus;
    const cgs_topic_t *topic = cgs_topics_find (topic_name);
    if (!topic || msg->descriptor != topic->message)
        return -EINVAL; // a catalogue topic carries only its own type, as on the bus
    size_t k = 0;
    while (k < src->nseqs && src->seqs[k].topic != topic)
        k++;
    if (k == src->nseqs) {
        if (k == S_TOPICS_MAX)
            return -ENOMEM;
        src->seqs[src->nseqs++].topic = topic;
    }
    Cgs__Header h = CGS__HEADER__INIT;
    h.source = src->name;
    h.exercise_id = self->exercise_id;
    h.epoch = 1;
    h.seq = ++src->seqs[k].seq;
    h.sim_time_s = sim_time_s;
    h.wall_time_s = sim_time_s; // deterministic
    size_t len = 0;
    int rc = cgs_msg_encode_stamped_grow (msg, &h, &self->buf, &self->bufcap, &len);
    if (rc == 0)
        rc = s_enqueue (self, topic, self->buf, len);
    if (rc < 0) {
        self->failures++;
        return rc;
    }
    src->stats.published++;
    return 0;
}

static void s_log (void *arg, int priority, const char *line)
{
    (void)priority;
    ls_source_t *src = arg;
    if (src->bus->log)
        fprintf (src->bus->log, "[%9.2f] %s: %s\n", src->bus->time_s, src->name, line);
}

static void s_bad_input (void *arg, const char *what)
{
    ls_source_t *src = arg;
    src->stats.bad_inputs++;
    s_log (arg, 4, what);
}

static void s_error (void *arg, const char *why)
{
    ls_source_t *src = arg;
    if (src->stats.errors == 0)
        src->first_error = ++src->bus->errors_seen;
    src->stats.errors++;
    snprintf (src->stats.last_error, sizeof src->stats.last_error, "%s", why);
    s_log (arg, 3, why);
}

ls_source_t *ls_bus_source (ls_bus_t *self, const char *source)
{
    ls_source_t *s = calloc (1, sizeof *s);
    if (!s)
        return NULL;
    s->bus = self;
    snprintf (s->name, sizeof s->name, "%s", source);
    s->next = self->sources;
    self->sources = s;
    return s;
}

cgs_port_t ls_bus_port (ls_source_t *src)
{
    return (cgs_port_t){
        .arg = src,
        .publish = s_publish,
        .log = s_log,
        .bad_input = s_bad_input,
        .error = s_error,
    };
}

void ls_bus_report (const ls_bus_t *self, uint64_t *ret_bad_inputs, uint64_t *ret_errors,
                    char *first, size_t firstlen)
{
    uint64_t bad = 0, errors = 0;
    const ls_source_t *earliest = NULL;
    for (const ls_source_t *s = self->sources; s; s = s->next) {
        bad += s->stats.bad_inputs;
        errors += s->stats.errors;
        if (s->stats.errors && (!earliest || s->first_error < earliest->first_error))
            earliest = s;
    }
    *ret_bad_inputs = bad;
    *ret_errors = errors;
    if (first && firstlen)
        snprintf (first, firstlen, "%s%s%s", earliest ? earliest->name : "", earliest ? ": " : "",
                  earliest ? earliest->stats.last_error : "");
}

const ls_source_stats_t *ls_bus_source_stats (const ls_source_t *src)
{
    return &src->stats;
}

/* ---- delivering ------------------------------------------------------------------------ */

int ls_bus_subscribe (ls_bus_t *self, const char *topic, cgs_sub_fn *fn, void *arg)
{
    const cgs_topic_t *t = cgs_topics_find (topic);
    if (!t)
        return -EINVAL;
    if (self->nsubs == self->subcap) {
        size_t cap = self->subcap ? self->subcap * 2 : 16;
        s_sub_t *n = realloc (self->subs, cap * sizeof *n);
        if (!n)
            return -ENOMEM;
        self->subs = n;
        self->subcap = cap;
    }
    self->subs[self->nsubs++] = (s_sub_t){t, fn, arg};
    return 0;
}

size_t ls_bus_drain (ls_bus_t *self)
{
    size_t delivered = 0;
    while (self->head < self->tail) {
        s_queued_t q = self->queue[self->head++];
        Cgs__Header hdr;
        char source[S_SOURCE_MAX];
        ProtobufCMessage *m = NULL;
        cgs_msg_arena_reset (self->arena);
        if (cgs_msg_decode_stamped (q.topic->message, q.data, q.len, self->arena, &hdr, source,
                                    sizeof source, &m) < 0) {
            self->failures++;
            free (q.data);
            continue;
        }
        self->time_s = hdr.sim_time_s;
        // Subscribers may publish: the queue may move, so q is a copy.
        for (size_t i = 0; i < self->nsubs; i++)
            if (self->subs[i].topic == q.topic)
                self->subs[i].fn (self->subs[i].arg, q.topic->name, m, &hdr);
        free (q.data);
        delivered++;
    }
    self->head = self->tail = 0;
    return delivered;
}
