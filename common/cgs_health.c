/* cgs_health — the 1 Hz health message. */
#include "cgs_health.h"
#include "cgs_loop.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define S_MAX_SUBS     8
#define S_MAX_TOPICS   64
#define S_MAX_COUNTERS 48 // the gateway sets 30 with every translator on (32 with CURVE)

struct cgs_health {
    char program[64], instance[64], version[32], host[64], machine[64];
    char last_error[512];
    double last_error_wall_s;
    Cgs__ServiceState state;
    const cgs_pub_t *pub;
    const cgs_sub_t *subs[S_MAX_SUBS];
    size_t nsubs;
    const cgs_cmd_server_t *cmd;
    uint64_t extra_malformed;
    bool sealed;
    char counter_names[S_MAX_COUNTERS][32];
    uint64_t counter_values[S_MAX_COUNTERS];
    size_t ncounters;
    double start, last; // monotonic seconds
    uint64_t prev_in, prev_out;
    // Message counts at the last publish, per source and topic index (a
    // publisher's and a subscriber's topics only ever append).
    uint64_t prev_pub[S_MAX_TOPICS];
    uint64_t prev_sub[S_MAX_SUBS][S_MAX_TOPICS];
};

cgs_health_t *cgs_health_new (const char *program, const char *instance, const char *version,
                              const char *host)
{
    cgs_health_t *self = calloc (1, sizeof *self);
    if (!self)
        return NULL;
    snprintf (self->program, sizeof self->program, "%s", program ? program : "");
    snprintf (self->instance, sizeof self->instance, "%s", instance ? instance : "");
    snprintf (self->version, sizeof self->version, "%s", version ? version : "");
    snprintf (self->host, sizeof self->host, "%s", host ? host : "");
    gethostname (self->machine, sizeof self->machine - 1);
    self->start = self->last = cgs_loop_now ();
    self->state = CGS__SERVICE_STATE__SERVICE_STATE_STARTING;
    return self;
}

void cgs_health_destroy (cgs_health_t **self_p)
{
    if (!self_p || !*self_p)
        return;
    free (*self_p);
    *self_p = NULL;
}

void cgs_health_watch_pub (cgs_health_t *self, const cgs_pub_t *pub)
{
    self->pub = pub;
}

int cgs_health_watch_sub (cgs_health_t *self, const cgs_sub_t *sub)
{
    if (self->nsubs == S_MAX_SUBS)
        return -ENOSPC;
    self->subs[self->nsubs++] = sub;
    return 0;
}

void cgs_health_watch_cmd (cgs_health_t *self, const cgs_cmd_server_t *cmd)
{
    self->cmd = cmd;
}
void cgs_health_set_state (cgs_health_t *self, Cgs__ServiceState state)
{
    self->state = state;
}
void cgs_health_set_sealed (cgs_health_t *self, bool sealed)
{
    self->sealed = sealed;
}

void cgs_health_add_malformed (cgs_health_t *self, uint64_t n)
{
    self->extra_malformed += n;
}

void cgs_health_set_error (cgs_health_t *self, const char *error)
{
    snprintf (self->last_error, sizeof self->last_error, "%s", error ? error : "");
    self->last_error_wall_s = cgs_bus_wall_time ();
}

/* Messages per second between two counts; never negative. */
static double s_rate (uint64_t now, uint64_t before, double dt)
{
    return now > before ? (double)(now - before) / dt : 0.0;
}

void cgs_health_set_counter (cgs_health_t *self, const char *name, uint64_t value)
{
    size_t i = 0;
    while (i < self->ncounters && strcmp (self->counter_names[i], name) != 0)
        i++;
    if (i == self->ncounters) {
        if (i == S_MAX_COUNTERS)
            return;
        snprintf (self->counter_names[i], sizeof self->counter_names[i], "%s", name);
        self->ncounters++;
    }
    self->counter_values[i] = value;
}

int cgs_health_publish (cgs_health_t *self, cgs_pub_t *pub, double sim_time_s)
{
    double now = cgs_loop_now ();
    double dt = now - self->last;
    if (dt <= 0)
        dt = 1e-9;
    Cgs__Health h = CGS__HEALTH__INIT;
    Cgs__TopicStats ts[S_MAX_TOPICS];
    Cgs__TopicStats *tp[S_MAX_TOPICS];
    size_t nt = 0;
    uint64_t foreign = 0;
    uint64_t in = 0, out = 0, gaps = 0, malformed = self->extra_malformed, restarts = 0, drops = 0;
    uint64_t unauthenticated = 0, replayed = 0;

    if (self->pub) {
        for (size_t i = 0; i < cgs_pub_topic_count (self->pub) && nt < S_MAX_TOPICS; i++) {
            const cgs_topic_stats_t *s = cgs_pub_topic_stats (self->pub, i);
            Cgs__TopicStats *t = &ts[nt];
            cgs__topic_stats__init (t);
            t->topic = (char *)s->topic;
            t->outbound = true;
            t->messages = s->messages;
            t->drops = s->drops;
            t->rate_hz = s_rate (s->messages, self->prev_pub[i], dt);
            self->prev_pub[i] = s->messages;
            tp[nt] = t;
            nt++;
        }
        out = cgs_pub_sent (self->pub);
        drops = cgs_pub_drops (self->pub);
    }
    for (size_t k = 0; k < self->nsubs; k++) {
        const cgs_sub_t *sub = self->subs[k];
        for (size_t i = 0; i < cgs_sub_topic_count (sub) && nt < S_MAX_TOPICS; i++) {
            const cgs_topic_stats_t *s = cgs_sub_topic_stats (sub, i);
            Cgs__TopicStats *t = &ts[nt];
            cgs__topic_stats__init (t);
            t->topic = (char *)s->topic;
            t->messages = s->messages;
            t->gaps = s->gaps;
            t->malformed = s->malformed;
            t->unauthenticated = s->unauthenticated;
            t->replayed = s->replayed;
            if (i < S_MAX_TOPICS) {
                t->rate_hz = s_rate (s->messages, self->prev_sub[k][i], dt);
                self->prev_sub[k][i] = s->messages;
            }
            in += s->messages;
            tp[nt] = t;
            nt++;
        }
        gaps += cgs_sub_gaps (sub);
        malformed += cgs_sub_malformed (sub);
        restarts += cgs_sub_restarts (sub);
        foreign += cgs_sub_foreign (sub);
        unauthenticated += cgs_sub_unauthenticated (sub);
        replayed += cgs_sub_replayed (sub);
    }
    h.program = self->program;
    h.instance = self->instance;
    h.version = self->version;
    h.host = self->host;
    h.machine = self->machine;
    h.pid = (uint32_t)getpid ();
    h.state = self->state;
    h.uptime_s = now - self->start;
    h.msgs_in = in;
    h.msgs_out = out;
    h.msgs_in_per_s = s_rate (in, self->prev_in, dt);
    h.msgs_out_per_s = s_rate (out, self->prev_out, dt);
    h.drops = drops;
    h.gaps = gaps;
    h.malformed = malformed;
    h.restarts_seen = restarts;
    h.foreign = foreign;
    h.sealed = self->sealed;
    h.unauthenticated = unauthenticated;
    h.replayed = replayed;
    if (self->cmd) {
        h.commands = cgs_cmd_server_applied (self->cmd) + cgs_cmd_server_duplicates (self->cmd);
        h.malformed += cgs_cmd_server_malformed (self->cmd);
    }
    h.last_error = self->last_error;
    h.last_error_wall_time_s = self->last_error_wall_s;
    h.n_topics = nt;
    h.topics = tp;
    Cgs__Counter cs[S_MAX_COUNTERS];
    Cgs__Counter *cp[S_MAX_COUNTERS];
    for (size_t i = 0; i < self->ncounters; i++) {
        cgs__counter__init (&cs[i]);
        cs[i].name = self->counter_names[i];
        cs[i].value = self->counter_values[i];
        cp[i] = &cs[i];
    }
    h.n_counters = self->ncounters;
    h.counters = cp;
    self->prev_in = in;
    self->prev_out = out;
    self->last = now;
    return cgs_pub_send (pub, "health", &h.base, sim_time_s);
}
