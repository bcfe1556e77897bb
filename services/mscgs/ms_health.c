/* ms_health — every instance's latest health and the simulation clock, for
 * `mscgs status` and `mscgs run`. */
#include "ms_health.h"

#include "cgs_loop.h"

#include <string.h>

void ms_health_init (ms_health_t *t, const cgs_exercise_t *ex)
{
    memset (t, 0, sizeof *t);
    for (size_t i = 0; i < cgs_exercise_instance_count (ex) && t->nrows < MS_MAX_INSTANCES; i++) {
        const cgs_instance_t *in = cgs_exercise_instance (ex, i);
        ms_health_row_t *r = &t->rows[t->nrows++];
        snprintf (r->instance, sizeof r->instance, "%s", in->name);
        snprintf (r->program, sizeof r->program, "%s", in->program);
        snprintf (r->host, sizeof r->host, "%s", in->host);
        r->enabled = in->enabled;
    }
    const cgs_bus_params_t *b = cgs_exercise_bus (ex);
    t->sealed = *b->key_file != '\0';
    snprintf (t->bus, sizeof t->bus, "%s%s, %s",
              cgs_exercise_uses_multicast (ex) ? "multicast " : "",
              cgs_exercise_uses_multicast (ex) ? b->transport : "tcp/ipc",
              t->sealed ? "sealed (group key)" : "in the clear");
}

void ms_health_on_health (void *arg, const char *topic, const ProtobufCMessage *msg,
                          const Cgs__Header *hdr)
{
    (void)topic;
    (void)hdr;
    ms_health_t *t = arg;
    const Cgs__Health *h = (const Cgs__Health *)msg;
    ms_health_row_t *r = NULL;
    for (size_t i = 0; i < t->nrows && !r; i++)
        if (strcmp (t->rows[i].instance, h->instance) == 0)
            r = &t->rows[i];
    if (!r && t->nrows < MS_MAX_INSTANCES) { // not in the exercise file: show it anyway
        r = &t->rows[t->nrows++];
        snprintf (r->instance, sizeof r->instance, "%s", h->instance);
        snprintf (r->program, sizeof r->program, "%s", h->program);
    }
    if (!r)
        return;
    r->seen = true;
    r->seen_at = cgs_loop_now ();
    r->state = h->state;
    if (h->host && *h->host)
        snprintf (r->host, sizeof r->host, "%s", h->host);
    snprintf (r->machine, sizeof r->machine, "%s", h->machine ? h->machine : "");
    r->pid = h->pid;
    r->uptime_s = h->uptime_s;
    r->in_per_s = h->msgs_in_per_s;
    r->out_per_s = h->msgs_out_per_s;
    r->gaps = h->gaps;
    r->drops = h->drops;
    r->malformed = h->malformed;
    r->commands = h->commands;
    r->sealed = h->sealed;
    r->unauthenticated = h->unauthenticated;
    r->replayed = h->replayed;
    snprintf (r->last_error, sizeof r->last_error, "%s", h->last_error);
    size_t used = 0;
    r->counters[0] = '\0';
    for (size_t i = 0; i < h->n_counters; i++)
        if (strcmp (h->counters[i]->name, "http_port") == 0)
            r->http_port = h->counters[i]->value;
    for (size_t i = 0; i < h->n_counters && used < sizeof r->counters; i++) {
        int n = snprintf (r->counters + used, sizeof r->counters - used, "%s%s=%llu", i ? " " : "",
                          h->counters[i]->name, (unsigned long long)h->counters[i]->value);
        if (n < 0)
            break;
        used += (size_t)n;
    }
}

void ms_health_on_clock (void *arg, const char *topic, const ProtobufCMessage *msg,
                         const Cgs__Header *hdr)
{
    (void)topic;
    (void)hdr;
    ms_health_t *t = arg;
    const Cgs__Clock *c = (const Cgs__Clock *)msg;
    t->sim_time_s = c->sim_time_s;
    t->time_scale = c->time_scale;
    t->paused = c->paused;
    t->have_clock = true;
}

const char *ms_health_state (const ms_health_row_t *r, double now)
{
    if (!r->seen)
        return "down";
    if (now - r->seen_at > 3.0)
        return "silent";
    switch (r->state) {
    case CGS__SERVICE_STATE__SERVICE_STATE_STARTING:
        return "starting";
    case CGS__SERVICE_STATE__SERVICE_STATE_RUNNING:
        return "up";
    case CGS__SERVICE_STATE__SERVICE_STATE_DEGRADED:
        return "degraded";
    case CGS__SERVICE_STATE__SERVICE_STATE_STOPPING:
        return "stopping";
    default:
        return "?";
    }
}

void ms_health_print (const ms_health_t *t, FILE *f)
{
    double now = cgs_loop_now ();
    fprintf (f, "bus: %s\n", t->bus);
    fprintf (f, "%-16s %-9s %-12s %-12s %8s %9s %9s %9s %7s %7s %9s  %s\n", "INSTANCE", "STATE",
             "HOST", "MACHINE", "PID", "UPTIME_S", "IN/S", "OUT/S", "GAPS", "DROPS", "MALFORMED",
             "LAST ERROR");
    for (size_t i = 0; i < t->nrows; i++) {
        const ms_health_row_t *r = &t->rows[i];
        if (!r->seen) {
            fprintf (f, "%-16s %-9s %-12.12s\n", r->instance, r->enabled ? "down" : "disabled",
                     r->host);
            continue;
        }
        fprintf (f, "%-16s %-9s %-12.12s %-12.12s %8u %9.1f %9.1f %9.1f %7llu %7llu %9llu  %s\n",
                 r->instance, ms_health_state (r, now), r->host, r->machine, r->pid, r->uptime_s,
                 r->in_per_s, r->out_per_s, (unsigned long long)r->gaps,
                 (unsigned long long)r->drops, (unsigned long long)r->malformed, r->last_error);
        char extra[128] = "";
        if (r->unauthenticated || r->replayed || r->sealed != t->sealed)
            snprintf (extra, sizeof extra, "%sunauthenticated=%llu replayed=%llu%s",
                      *r->counters ? " " : "", (unsigned long long)r->unauthenticated,
                      (unsigned long long)r->replayed,
                      r->sealed == t->sealed ? "" : (r->sealed ? " sealed" : " in-the-clear"));
        if (*r->counters || *extra)
            fprintf (f, "%-16s %s%s\n", "", r->counters, extra);
    }
}
