/* bcis_adapter — bcisd's pure layer (see bcis_adapter.h). */
#include "bcis_adapter.h"

#include "cgs_entities.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <syslog.h>

const char *const bcis_adapter_topics[] = {"entity", "uav", NULL};

struct bcis_adapter {
    cgs_port_t port;
    cgs_sensor_t *sensor; // its UAV, scenario and terrain (the caller's)
    bcis_params_t params;
    bcis_interrogator_t *bcis;
    const cgs_scan_t *scan;
    cgs_scan_pace_t pace; // the next dwell to run
    cgs_entities_t *ents;
    bcis_entity_t *targets;
    size_t target_cap;
    bcis_adapter_stats_t stats;
    /* Output messages, reused. */
    Cgs__BcisReply *reply_msgs;
    Cgs__BcisReply **reply_ptrs;
    Cgs__Enu *reply_pos;
    size_t reply_cap;
};

bcis_adapter_t *bcis_adapter_new (const bcis_params_t *params, cgs_sensor_t *sensor,
                                  const cgs_port_t *port)
{
    bcis_adapter_t *self = calloc (1, sizeof *self);
    if (!self)
        return NULL;
    self->port = *port;
    self->sensor = sensor;
    self->params = *params;
    self->bcis = bcis_interrogator_new (&self->params, sensor->terrain, sensor->seed);
    self->ents = cgs_entities_new ();
    if (!self->bcis || !self->ents) {
        bcis_adapter_destroy (&self);
        return NULL;
    }
    self->scan = bcis_interrogator_scan (self->bcis);
    return self;
}

void bcis_adapter_destroy (bcis_adapter_t **self_p)
{
    bcis_adapter_t *self = *self_p;
    if (!self)
        return;
    bcis_interrogator_destroy (&self->bcis);
    cgs_entities_destroy (&self->ents);
    free (self->targets);
    free (self->reply_msgs);
    free (self->reply_ptrs);
    free (self->reply_pos);
    free (self);
    *self_p = NULL;
}

const cgs_scan_t *bcis_adapter_scan (const bcis_adapter_t *self)
{
    return self->scan;
}

const bcis_adapter_stats_t *bcis_adapter_stats (const bcis_adapter_t *self)
{
    return &self->stats;
}

/* The ground entities as they are at time t (moved on along their velocity). */
static size_t s_targets_at (bcis_adapter_t *self, double t)
{
    size_t count = cgs_entities_count (self->ents);
    if (self->target_cap < count) {
        bcis_entity_t *tg = realloc (self->targets, count * sizeof *tg);
        if (!tg) {
            cgs_port_error (&self->port, "out of memory for entities: a dwell ran empty");
            return 0;
        }
        self->targets = tg;
        self->target_cap = count;
    }
    size_t n = 0, cursor = 0;
    const cgs_entity_state_t *s;
    while ((s = cgs_entities_next (self->ents, &cursor))) {
        cgs_enu_t p;
        if (s->kind == CGS_KIND_AIR || s->id == self->sensor->uav_id ||
            !cgs_entity_at (s, t, BCIS_ADAPTER_STALE_S, self->sensor->terrain, &p))
            continue;
        self->targets[n++] = (bcis_entity_t){
            .id = s->id,
            .position = p,
            .force = s->force,
            .transponder = s->bcis_transponder,
            .marking = s->marking,
        };
    }
    return n;
}

static int s_reserve (bcis_adapter_t *self, size_t n)
{
    if (n <= self->reply_cap)
        return 0;
    size_t cap = n * 2;
    free (self->reply_msgs);
    free (self->reply_ptrs);
    free (self->reply_pos);
    self->reply_msgs = calloc (cap, sizeof *self->reply_msgs);
    self->reply_ptrs = calloc (cap, sizeof *self->reply_ptrs);
    self->reply_pos = calloc (cap, sizeof *self->reply_pos);
    self->reply_cap = self->reply_msgs && self->reply_ptrs && self->reply_pos ? cap : 0;
    return self->reply_cap ? 0 : -ENOMEM;
}

/* The scan marker: scan d->scan is complete. */
static void s_publish_marker (bcis_adapter_t *self, const cgs_dwell_t *d)
{
    Cgs__Bcis m = CGS__BCIS__INIT;
    m.uav_id = self->sensor->uav_id;
    m.scan_number = d->scan;
    m.scan_time_s = d->end_s;
    m.beam_azimuth_deg = d->az_to_deg;
    m.scan_end = true;
    cgs_port_publish (&self->port, "bcis", &m.base, d->end_s);
}

/* The dwell's interrogation and its replies. */
static void s_publish (bcis_adapter_t *self, const cgs_dwell_t *d, cgs_enu_t uav,
                       const bcis_dwell_out_t *out)
{
    if (s_reserve (self, out->reply_count) < 0) {
        cgs_port_error (&self->port, "out of memory for a dwell's replies");
        return;
    }
    double t = (d->start_s + d->end_s) / 2;
    for (size_t i = 0; i < out->reply_count; i++) {
        const bcis_reply_t *r = &out->replies[i];
        Cgs__BcisReply *m = &self->reply_msgs[i];
        cgs__bcis_reply__init (m);
        cgs__enu__init (&self->reply_pos[i]);
        self->reply_pos[i].east_m = r->position.e_m;
        self->reply_pos[i].north_m = r->position.n_m;
        self->reply_pos[i].up_m = r->position.u_m;
        m->responder_id = r->responder_id;
        m->marking = (char *)r->marking;
        m->position = &self->reply_pos[i];
        m->sim_time_s = t;
        m->azimuth_deg = r->azimuth_deg;
        m->range_m = r->range_m;
        m->snr_up_db = r->snr_up_db;
        m->snr_down_db = r->snr_down_db;
        m->range_sigma_m = r->range_sigma_m;
        m->azimuth_sigma_deg = r->azimuth_sigma_deg;
        m->position_fix = r->position_fix;
        m->position_sigma_m = r->position_sigma_m;
        self->reply_ptrs[i] = m;
    }
    Cgs__Bcis b = CGS__BCIS__INIT;
    b.uav_id = self->sensor->uav_id;
    b.scan_number = d->scan;
    b.scan_time_s = t;
    b.beam_azimuth_deg = d->az_center_deg;
    Cgs__Enu at = CGS__ENU__INIT;
    at.east_m = uav.e_m;
    at.north_m = uav.n_m;
    at.up_m = uav.u_m;
    b.interrogator = &at;
    b.n_replies = out->reply_count;
    b.replies = self->reply_ptrs;
    cgs_port_publish (&self->port, "bcis", &b.base, t);
}

static void s_run_dwell (bcis_adapter_t *self, uint64_t k)
{
    cgs_dwell_t d;
    cgs_scan_dwell (self->scan, k, self->sensor->heading_deg, &d);
    double t = (d.start_s + d.end_s) / 2;
    cgs_enu_t uav = cgs_sensor_uav_at (self->sensor, t);
    size_t n = s_targets_at (self, t);
    bcis_dwell_out_t out;
    if (bcis_interrogator_dwell (self->bcis, &d, uav, self->targets, n, &out) < 0) {
        cgs_port_error (&self->port, "out of memory: an interrogation was not modelled");
    } else {
        self->stats.dwells_run++;
        self->stats.interrogated += out.truth_count;
        self->stats.replies += out.reply_count;
        for (size_t i = 0; i < out.truth_count; i++)
            self->stats.blocked += out.truth[i].blocked;
        s_publish (self, &d, uav, &out);
    }
    if (d.scan_end) { // the scan ends even when a dwell of it could not be modelled
        s_publish_marker (self, &d);
        cgs_entities_evict (self->ents, t, BCIS_ADAPTER_STALE_S);
    }
}

static void s_on_uav (bcis_adapter_t *self, const Cgs__Uav *u, double t)
{
    uint64_t end;
    if (!cgs_sensor_on_uav (self->sensor, u, t, self->scan, &self->pace, BCIS_ADAPTER_STALE_S,
                            "interrogator", &self->port, &end))
        return;
    self->stats.skipped = self->pace.skipped;
    // Run every dwell that has ended by now.
    while (self->pace.next < end)
        s_run_dwell (self, self->pace.next++);
}

void bcis_adapter_on_message (bcis_adapter_t *self, const char *topic, const ProtobufCMessage *msg,
                              const Cgs__Header *hdr)
{
    if (strcmp (topic, "entity") == 0)
        cgs_entities_take (self->ents, msg, hdr, &self->port);
    else if (strcmp (topic, "uav") == 0)
        s_on_uav (self, (const Cgs__Uav *)msg, hdr->sim_time_s);
}
