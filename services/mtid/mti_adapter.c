/* mti_adapter — mtid's pure layer (see mti_adapter.h). */
#include "mti_adapter.h"

#include "cgs_entities.h"
#include "cgs_scan.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <syslog.h>

#define S_WARNED_MAX 16 // unknown cross-section classes remembered for logging once

const char *const mti_adapter_topics[] = {"entity", "uav", NULL};

struct mti_adapter {
    cgs_port_t port;
    cgs_sensor_t *sensor; // its UAV, scenario and terrain (the caller's)
    mti_params_t params;
    mti_radar_t *radar;
    cgs_scan_pace_t pace; // the next dwell to run
    cgs_entities_t *ents;
    mti_target_t *targets;
    size_t target_cap;
    /* The scan in progress. */
    uint32_t scan;
    double scan_start_s;
    uint32_t scan_hits, scan_fas;
    mti_adapter_stats_t stats;
    char warned[S_WARNED_MAX][CGS_ENTITY_CLASS_MAX]; // unknown classes already reported
    size_t warned_count;
    /* Output messages, reused. */
    Cgs__MtiHit *hit_msgs;
    Cgs__MtiHit **hit_ptrs;
    Cgs__Enu *hit_pos;
    size_t hit_cap;
    Cgs__MtiTruthItem *truth_msgs;
    Cgs__MtiTruthItem **truth_ptrs;
    size_t truth_cap;
};

mti_adapter_t *mti_adapter_new (const mti_params_t *params, cgs_sensor_t *sensor,
                                const cgs_port_t *port)
{
    mti_adapter_t *self = calloc (1, sizeof *self);
    if (!self)
        return NULL;
    self->port = *port;
    self->sensor = sensor;
    self->params = *params;
    self->radar = mti_radar_new (&self->params, sensor->terrain, sensor->seed);
    self->ents = cgs_entities_new ();
    if (!self->radar || !self->ents)
        mti_adapter_destroy (&self); // NULL
    return self;
}

void mti_adapter_destroy (mti_adapter_t **self_p)
{
    mti_adapter_t *self = *self_p;
    if (!self)
        return;
    mti_radar_destroy (&self->radar);
    cgs_entities_destroy (&self->ents);
    free (self->targets);
    free (self->hit_msgs);
    free (self->hit_ptrs);
    free (self->hit_pos);
    free (self->truth_msgs);
    free (self->truth_ptrs);
    free (self);
    *self_p = NULL;
}

const mti_radar_t *mti_adapter_radar (const mti_adapter_t *self)
{
    return self->radar;
}

const mti_adapter_stats_t *mti_adapter_stats (const mti_adapter_t *self)
{
    return &self->stats;
}

/* ---- entities ------------------------------------------------------------------------ */

/* Report each unknown cross-section class once (the first S_WARNED_MAX of them). */
static void s_warn_class (mti_adapter_t *self, const cgs_entity_state_t *s)
{
    for (size_t i = 0; i < self->warned_count; i++)
        if (strcmp (self->warned[i], s->rcs_class) == 0)
            return;
    if (self->warned_count == S_WARNED_MAX)
        return;
    snprintf (self->warned[self->warned_count++], CGS_ENTITY_CLASS_MAX, "%s", s->rcs_class);
    const mti_class_t *c = mti_params_class (&self->params, s->rcs_class, NULL);
    cgs_port_log (&self->port, LOG_WARNING,
                  "entity %u: radar cross-section class '%s' is not in the parameters; "
                  "seen as class '%s'",
                  s->id, s->rcs_class, c->name);
}

/* The ground entities as they are at time t (moved on along their velocity). */
static size_t s_targets_at (mti_adapter_t *self, double t)
{
    size_t count = cgs_entities_count (self->ents);
    if (self->target_cap < count) {
        mti_target_t *tg = realloc (self->targets, count * sizeof *tg);
        if (!tg) {
            cgs_port_error (&self->port, "out of memory for targets: a dwell ran empty");
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
            !cgs_entity_at (s, t, MTI_ADAPTER_STALE_S, self->sensor->terrain, &p))
            continue;
        bool known;
        mti_params_class (&self->params, s->rcs_class, &known);
        if (!known)
            s_warn_class (self, s);
        self->targets[n++] = (mti_target_t){
            .id = s->id,
            .position = p,
            .velocity = s->velocity,
            .rcs_class = s->rcs_class,
        };
    }
    return n;
}

/* ---- publication --------------------------------------------------------------------- */

static int s_reserve_out (mti_adapter_t *self, size_t hits, size_t truth)
{
    if (hits > self->hit_cap) {
        size_t cap = hits * 2;
        free (self->hit_msgs);
        free (self->hit_ptrs);
        free (self->hit_pos);
        self->hit_msgs = calloc (cap, sizeof *self->hit_msgs);
        self->hit_ptrs = calloc (cap, sizeof *self->hit_ptrs);
        self->hit_pos = calloc (cap, sizeof *self->hit_pos);
        self->hit_cap = self->hit_msgs && self->hit_ptrs && self->hit_pos ? cap : 0;
        if (!self->hit_cap)
            return -ENOMEM;
    }
    if (truth > self->truth_cap) {
        size_t cap = truth * 2;
        free (self->truth_msgs);
        free (self->truth_ptrs);
        self->truth_msgs = calloc (cap, sizeof *self->truth_msgs);
        self->truth_ptrs = calloc (cap, sizeof *self->truth_ptrs);
        self->truth_cap = self->truth_msgs && self->truth_ptrs ? cap : 0;
        if (!self->truth_cap)
            return -ENOMEM;
    }
    return 0;
}

static void s_publish_dwell (mti_adapter_t *self, const mti_dwell_t *d, const mti_dwell_out_t *out)
{
    if (s_reserve_out (self, out->hit_count, out->truth_count) < 0) {
        cgs_port_error (&self->port, "out of memory for a dwell's messages");
        return;
    }
    double t = (d->start_s + d->end_s) / 2;
    for (size_t i = 0; i < out->hit_count; i++) {
        const mti_hit_t *h = &out->hits[i];
        Cgs__MtiHit *m = &self->hit_msgs[i];
        cgs__mti_hit__init (m);
        cgs__enu__init (&self->hit_pos[i]);
        self->hit_pos[i].east_m = h->position.e_m;
        self->hit_pos[i].north_m = h->position.n_m;
        self->hit_pos[i].up_m = h->position.u_m;
        m->hit_id = h->hit_id;
        m->position = &self->hit_pos[i];
        m->range_m = h->range_m;
        m->azimuth_deg = h->azimuth_deg;
        m->radial_velocity_mps = h->radial_velocity_mps;
        m->snr_db = h->snr_db;
        m->range_sigma_m = h->range_sigma_m;
        m->azimuth_sigma_deg = h->azimuth_sigma_deg;
        m->sim_time_s = t;
        self->hit_ptrs[i] = m;
    }
    const cgs_sensor_t *sn = self->sensor;
    Cgs__Enu plat = CGS__ENU__INIT;
    plat.east_m = sn->position.e_m;
    plat.north_m = sn->position.n_m;
    plat.up_m = sn->position.u_m;
    Cgs__Mti mti = CGS__MTI__INIT;
    mti.uav_id = sn->uav_id;
    mti.scan_number = d->scan;
    mti.dwell_number = d->dwell;
    mti.beam_azimuth_deg = d->az_center_deg;
    mti.platform_position = &plat;
    mti.n_hits = out->hit_count;
    mti.hits = self->hit_ptrs;
    const mti_params_t *p = &self->params;
    mti.dwell_start_s = d->start_s;
    mti.dwell_end_s = d->end_s;
    mti.last_of_scan = d->scan_end;
    mti.wrap_velocity_mps = mti_params_wavelength_m (p) * p->prf_hz / 2;
    mti.min_range_m = p->min_range_m;
    mti.max_range_m = p->max_range_m;
    mti.azimuth_beamwidth_deg = p->azimuth_beamwidth_deg;
    mti.frequency_hz = p->frequency_hz;
    mti.radial_velocity_sigma_mps = mti.wrap_velocity_mps / p->fft_size / sqrt (12.0);
    cgs_port_publish (&self->port, "mti", &mti.base, t);

    for (size_t i = 0; i < out->truth_count; i++) {
        const mti_truth_t *tr = &out->truth[i];
        Cgs__MtiTruthItem *m = &self->truth_msgs[i];
        cgs__mti_truth_item__init (m);
        m->entity_id = tr->entity_id;
        m->in_beam = true;
        m->visible = tr->visible;
        m->snr_db = isfinite (tr->snr_db) ? tr->snr_db : -999.0;
        m->pd = tr->pd;
        m->detected = tr->detected;
        m->hit_id = tr->hit_id;
        m->merged_into = tr->merged_into;
        m->radial_velocity_mps = tr->radial_velocity_mps;
        m->range_m = tr->range_m;
        self->truth_ptrs[i] = m;
    }
    Cgs__MtiTruth truth = CGS__MTI_TRUTH__INIT;
    truth.uav_id = sn->uav_id;
    truth.scan_number = d->scan;
    truth.dwell_number = d->dwell;
    truth.n_items = out->truth_count;
    truth.false_alarms = out->false_alarms;
    truth.items = self->truth_ptrs;
    cgs_port_publish (&self->port, "mti.truth", &truth.base, t);
}

static void s_publish_scan (mti_adapter_t *self, const mti_dwell_t *d)
{
    const mti_params_t *p = &self->params;
    Cgs__MtiScan m = CGS__MTI_SCAN__INIT;
    m.uav_id = self->sensor->uav_id;
    m.scan_number = d->scan;
    m.scan_start_s = self->scan_start_s;
    m.scan_end_s = d->end_s;
    m.full_revolution = p->scan_mode == MTI_SCAN_FULL;
    m.sector_center_deg = p->sector_center_deg;
    if (p->sector_ref == MTI_SECTOR_HEADING) // as an azimuth, at the scan's end
        m.sector_center_deg = fmod (m.sector_center_deg + self->sensor->heading_deg + 720.0, 360.0);
    m.sector_width_deg = m.full_revolution ? 360.0 : p->sector_width_deg;
    m.hit_count = self->scan_hits;
    m.false_alarm_count = self->scan_fas;
    m.expected_false_alarms = mti_radar_gate_pfa (self->radar) * mti_radar_gates (self->radar) *
                              mti_radar_dwells_per_scan (self->radar);
    cgs_port_publish (&self->port, "mti.scan", &m.base, d->end_s);
}

/* ---- the radar ----------------------------------------------------------------------- */

static void s_run_dwell (mti_adapter_t *self, uint64_t k)
{
    mti_dwell_t d;
    mti_radar_schedule (self->radar, k, self->sensor->heading_deg, &d);
    if (d.scan != self->scan || d.scan_start) {
        self->scan = d.scan;
        self->scan_start_s = d.start_s;
        self->scan_hits = self->scan_fas = 0;
    }
    double t = (d.start_s + d.end_s) / 2;
    mti_platform_t plat = {.position = cgs_sensor_uav_at (self->sensor, t),
                           .velocity = self->sensor->velocity,
                           .heading_deg = self->sensor->heading_deg};
    size_t n = s_targets_at (self, t);
    mti_dwell_out_t out;
    int rc = mti_radar_dwell (self->radar, &d, &plat, self->targets, n, &out);
    if (rc < 0) {
        cgs_port_error (&self->port, "dwell %llu not run: %s", (unsigned long long)k,
                        strerror (-rc));
        return;
    }
    self->stats.dwells_run++;
    self->scan_hits += (uint32_t)out.hit_count;
    self->scan_fas += out.false_alarms;
    s_publish_dwell (self, &d, &out);
    if (d.scan_end) {
        s_publish_scan (self, &d);
        cgs_entities_evict (self->ents, t, MTI_ADAPTER_STALE_S);
    }
}

static void s_on_uav (mti_adapter_t *self, const Cgs__Uav *u, double t)
{
    uint64_t end;
    if (!cgs_sensor_on_uav (self->sensor, u, t, mti_radar_scan (self->radar), &self->pace,
                            MTI_ADAPTER_STALE_S, "radar", &self->port, &end))
        return;
    self->stats.skipped = self->pace.skipped;
    // Run every dwell that has ended by now.
    while (self->pace.next < end)
        s_run_dwell (self, self->pace.next++);
}

void mti_adapter_on_message (mti_adapter_t *self, const char *topic, const ProtobufCMessage *msg,
                             const Cgs__Header *hdr)
{
    if (strcmp (topic, "entity") == 0)
        cgs_entities_take (self->ents, msg, hdr, &self->port);
    else if (strcmp (topic, "uav") == 0)
        s_on_uav (self, (const Cgs__Uav *)msg, hdr->sim_time_s);
}
