/* gw_gmti — the radars' bus messages as STANAG 4607 packets (see gw_gmti.h). */
#include "gw_gmti.h"

#include "cgs_util.h"
#include "gw_s4607.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define S_RADARS_MAX   64
#define S_Y2000        946684800.0 // 2000-01-01T00:00:00Z, seconds since the Unix epoch
#define S_DEG          (M_PI / 180)
#define S_JOB_REPEAT_S 60.0 // mission and job segments again, simulated seconds

typedef struct {
    uint32_t uav_id;
    char name[11]; // the packet header's platform id (10 characters)
    // The UAV as last heard on `uav`.
    bool heard;
    cgs_enu_t position, velocity;
    double heading_deg, pitch_deg, roll_deg;
    // The job.
    bool started;           // mission and job segments went out
    double last_platform_s; // simulation time of the last platform location segment
    double job_sent_s;      // and of the last mission and job segments
    // The dwell waiting for its truth.
    bool pending;
    int age; // gw_gmti_tick calls it has waited through
    uint32_t scan, dwell;
    double t_s; // its centre
    gw_s4607_dwell_t d;
    gw_s4607_report_t *reports;
    uint32_t *hit_ids;
    size_t nreports, cap, ids_cap;
    double max_range_m, range_sigma_m, azimuth_sigma_deg, velocity_sigma_mps, dwell_s,
        beamwidth_deg;
} s_radar_t;

struct gw_gmti {
    gw_params_t p;
    const cgs_geo_t *geo;
    uint32_t exercise;
    gw_gmti_emit_fn *emit;
    void *arg;
    bool clock_set;
    double utc_at_s, sim_at_s;
    bool dated;        // the reference date is fixed (at the first packet)
    double midnight_s; // its midnight, UTC
    int year, month, day;
    s_radar_t radars[S_RADARS_MAX];
    size_t nradars;
    uint8_t buf[GW_GMTI_PACKET_MAX];
    gw_gmti_stats_t stats;
};

gw_gmti_t *gw_gmti_new (const gw_params_t *p, const cgs_geo_t *geo, uint32_t exercise_id,
                        gw_gmti_emit_fn *emit, void *arg)
{
    gw_gmti_t *self = calloc (1, sizeof *self);
    if (!self)
        return NULL;
    self->p = *p;
    self->geo = geo;
    self->exercise = exercise_id;
    self->emit = emit;
    self->arg = arg;
    return self;
}

void gw_gmti_destroy (gw_gmti_t **self_p)
{
    if (!self_p || !*self_p)
        return;
    gw_gmti_t *self = *self_p;
    for (size_t i = 0; i < self->nradars; i++) {
        free (self->radars[i].reports);
        free (self->radars[i].hit_ids);
    }
    free (self);
    *self_p = NULL;
}

const gw_gmti_stats_t *gw_gmti_stats (const gw_gmti_t *self)
{
    return &self->stats;
}

void gw_gmti_set_clock (gw_gmti_t *self, double utc_s, double sim_s)
{
    self->clock_set = true;
    self->utc_at_s = utc_s;
    self->sim_at_s = sim_s;
}

/* ---- time ---------------------------------------------------------------------------------- */

static double s_utc (const gw_gmti_t *self, double t_s)
{
    return self->clock_set ? self->utc_at_s + (t_s - self->sim_at_s) : S_Y2000 + t_s;
}

/* Seconds since the reference date's midnight of simulation time t_s; the
 * date is the first packet's. */
static double s_time (gw_gmti_t *self, double t_s)
{
    double utc = s_utc (self, t_s);
    if (!self->dated) {
        self->dated = true;
        self->midnight_s = floor (utc / 86400.0) * 86400.0;
        time_t mt = (time_t)self->midnight_s;
        struct tm tm;
        gmtime_r (&mt, &tm);
        self->year = tm.tm_year + 1900;
        self->month = tm.tm_mon + 1;
        self->day = tm.tm_mday;
    }
    return utc - self->midnight_s;
}

/* ---- radars -------------------------------------------------------------------------------- */

static s_radar_t *s_radar (gw_gmti_t *self, uint32_t uav_id)
{
    for (size_t i = 0; i < self->nradars; i++)
        if (self->radars[i].uav_id == uav_id)
            return &self->radars[i];
    if (self->nradars == S_RADARS_MAX || uav_id == 0)
        return NULL;
    s_radar_t *r = &self->radars[self->nradars++];
    memset (r, 0, sizeof *r);
    r->uav_id = uav_id;
    r->last_platform_s = -INFINITY;
    snprintf (r->name, sizeof r->name, "uav%u", uav_id);
    return r;
}

static int s_begin (gw_gmti_t *self, const s_radar_t *r, gw_s4607_packet_t *pk)
{
    gw_s4607_header_t h = {0};
    memcpy (h.nationality, self->p.s4607_nationality, sizeof h.nationality);
    memcpy (h.class_system, self->p.s4607_class_system, sizeof h.class_system);
    h.classification = (uint8_t)self->p.s4607_classification;
    h.exercise_indicator = GW_S4607_EXERCISE_SIMULATED;
    snprintf (h.platform_id, sizeof h.platform_id, "%s", r->name);
    h.mission_id = self->exercise;
    h.job_id = r->uav_id;
    return gw_s4607_packet_begin (pk, self->buf, sizeof self->buf, &h);
}

static void s_emit (gw_gmti_t *self, gw_s4607_packet_t *pk)
{
    size_t len = gw_s4607_packet_end (pk);
    self->emit (self->arg, self->buf, len);
    self->stats.packets++;
}

static bool s_geodetic (gw_gmti_t *self, cgs_enu_t p, cgs_geodetic_t *g)
{
    if (cgs_geo_enu_to_geodetic (self->geo, p, g) < 0 || !isfinite (g->lat_deg)) {
        self->stats.unplaceable++;
        return false;
    }
    return true;
}

/* The mission and job segments of a radar's first packet. */
static int s_add_job (gw_gmti_t *self, s_radar_t *r, gw_s4607_packet_t *pk)
{
    gw_s4607_mission_t m = {0};
    snprintf (m.mission_plan, sizeof m.mission_plan, "mscgs ex %u", self->exercise);
    snprintf (m.flight_plan, sizeof m.flight_plan, "%s", r->name);
    m.platform_type = GW_S4607_PLATFORM_UAV_ARMY;
    snprintf (m.platform_config, sizeof m.platform_config, "MTI radar");
    m.year = (uint16_t)self->year;
    m.month = (uint8_t)self->month;
    m.day = (uint8_t)self->day;
    int rc = gw_s4607_add_mission (pk, &m);
    if (rc < 0)
        return rc;
    gw_s4607_job_t j = {0};
    j.job_id = r->uav_id;
    j.sensor_type = GW_S4607_SENSOR_OTHER;
    snprintf (j.sensor_model, sizeof j.sensor_model, "MSCGS");
    j.priority = 1;
    // The bounding area: the square of the radar's range about the UAV now.
    double d = r->max_range_m;
    static const double corner[4][2] = {{-1, 1}, {1, 1}, {1, -1}, {-1, -1}}; // NW, NE, SE, SW
    for (int k = 0; k < 4; k++) {
        cgs_geodetic_t g;
        cgs_enu_t c = {r->position.e_m + corner[k][0] * d, r->position.n_m + corner[k][1] * d, 0};
        if (!s_geodetic (self, c, &g))
            return -EINVAL;
        j.bounds[k] = (gw_s4607_point_t){g.lat_deg, g.lon_deg};
    }
    j.radar_mode = GW_S4607_MODE_MTI;
    // A full revolution: the dwell's time for each beamwidth of 360 degrees.
    j.revisit_interval_s = r->beamwidth_deg > 0 ? r->dwell_s * 360.0 / r->beamwidth_deg : 0;
    if (!(j.revisit_interval_s <= 6553.5))
        j.revisit_interval_s = 6553.5;
    j.along_track_unc_m = j.cross_track_unc_m = j.altitude_unc_m = NAN;
    j.track_unc_deg = j.speed_unc_mps = NAN;
    j.slant_range_sd_m = r->range_sigma_m > 0 ? r->range_sigma_m : NAN;
    j.cross_range_sd_deg = r->azimuth_sigma_deg > 0 ? r->azimuth_sigma_deg : NAN;
    j.los_velocity_sd_mps = r->velocity_sigma_mps > 0 ? r->velocity_sigma_mps : NAN;
    j.mdv_mps = self->p.s4607_mdv_mps;
    j.detection_probability = NAN;
    j.false_alarm_density_db = NAN;
    j.terrain_model = GW_S4607_TERRAIN_NONE;
    j.geoid_model = GW_S4607_GEOID_NONE;
    if ((rc = gw_s4607_add_job (pk, &j)) < 0)
        return rc;
    self->stats.missions++;
    return 0;
}

/* ---- platform ------------------------------------------------------------------------------ */

static void s_platform (gw_gmti_t *self, s_radar_t *r, double t_s)
{
    cgs_geodetic_t g;
    if (!s_geodetic (self, r->position, &g))
        return;
    gw_s4607_platform_t pl = {0};
    pl.time_s = s_time (self, t_s);
    pl.lat_deg = g.lat_deg;
    pl.lon_deg = g.lon_deg;
    pl.alt_m = g.height_m;
    pl.track_deg = atan2 (r->velocity.e_m, r->velocity.n_m) / S_DEG;
    pl.speed_mps = hypot (r->velocity.e_m, r->velocity.n_m);
    pl.vertical_velocity_mps = r->velocity.u_m;
    gw_s4607_packet_t pk;
    if (s_begin (self, r, &pk) < 0) {
        self->stats.unplaceable++;
        return;
    }
    // The mission and job again now and then, for a receiver that joined late.
    if (t_s - r->job_sent_s >= S_JOB_REPEAT_S) {
        if (s_add_job (self, r, &pk) < 0) {
            self->stats.unplaceable++;
            return;
        }
        r->job_sent_s = t_s;
    }
    if (gw_s4607_add_platform (&pk, &pl) < 0) {
        self->stats.unplaceable++;
        return;
    }
    s_emit (self, &pk);
    self->stats.platforms++;
    r->last_platform_s = t_s;
}

void gw_gmti_on_uav (gw_gmti_t *self, const Cgs__Uav *u, double t_s)
{
    s_radar_t *r = s_radar (self, u->entity_id);
    if (!r || !u->position || !u->velocity || !isfinite (t_s))
        return;
    if (u->name && *u->name)
        snprintf (r->name, sizeof r->name, "%s", u->name);
    r->heard = true;
    r->position = (cgs_enu_t){u->position->east_m, u->position->north_m, u->position->up_m};
    r->velocity = (cgs_enu_t){u->velocity->east_mps, u->velocity->north_mps, u->velocity->up_mps};
    r->heading_deg = u->heading_deg;
    r->pitch_deg = u->pitch_deg;
    r->roll_deg = u->roll_deg;
    // Platform locations once the job is under way (its first dwell starts it).
    if (r->started && t_s - r->last_platform_s >= 1.0 / self->p.s4607_platform_rate_hz - 1e-9)
        s_platform (self, r, t_s);
}

/* ---- dwells -------------------------------------------------------------------------------- */

/* Send the radar's pending dwell: in one packet, or split over several.
 * Untagged (its truth did not come): without the truth tag fields, which
 * would otherwise say "no entity" (a false alarm) of every report. */
static void s_send_dwell (gw_gmti_t *self, s_radar_t *r, bool tagged)
{
    if (!r->pending)
        return;
    r->pending = false;
    if (!tagged)
        r->d.report_fields &= ~(uint32_t)GW_S4607_R_TRUTH_TAG;
    bool last = r->d.last_dwell;
    size_t at = 0;
    do {
        gw_s4607_packet_t pk;
        if (s_begin (self, r, &pk) < 0)
            return;
        if (!r->started) {
            if (s_add_job (self, r, &pk) < 0) {
                self->stats.unplaceable++;
                return;
            }
            r->started = true;
            r->job_sent_s = r->t_s;
        }
        // As many reports as fit in this packet.
        size_t room = sizeof self->buf - pk.len;
        size_t base = gw_s4607_dwell_size (&r->d, r->reports, 0);
        size_t each = r->nreports ? gw_s4607_dwell_size (&r->d, r->reports, 1) - base : 0;
        size_t n = r->nreports - at;
        if (each && base + n * each > room)
            n = room > base ? (room - base) / each : 0;
        if (n > GW_S4607_REPORTS_MAX)
            n = GW_S4607_REPORTS_MAX;
        r->d.last_dwell = last && at + n == r->nreports;
        int rc = gw_s4607_add_dwell (&pk, &r->d, r->reports + at, n);
        if (rc < 0) {
            self->stats.unplaceable++;
            return;
        }
        s_emit (self, &pk);
        self->stats.dwells++;
        self->stats.reports += n;
        at += n;
    } while (at < r->nreports);
}

int gw_gmti_on_mti (gw_gmti_t *self, const Cgs__Mti *m)
{
    if (!m->platform_position || !isfinite (m->dwell_start_s) || !isfinite (m->dwell_end_s) ||
        m->dwell_end_s < m->dwell_start_s || !isfinite (m->beam_azimuth_deg))
        return -EINVAL;
    s_radar_t *r = s_radar (self, m->uav_id);
    if (!r)
        return -EINVAL;
    if (r->pending && self->p.s4607_truth_tag)
        self->stats.untagged++;
    s_send_dwell (self, r, false); // the previous one, untagged: its truth did not come
    if (!r->heard)
        self->stats.no_uav++;
    cgs_enu_t plat = {m->platform_position->east_m, m->platform_position->north_m,
                      m->platform_position->up_m};
    cgs_geodetic_t pg;
    if (!s_geodetic (self, plat, &pg))
        return -EINVAL;
    if (cgs_grow ((void **)&r->reports, &r->cap, m->n_hits, sizeof *r->reports) < 0 ||
        cgs_grow ((void **)&r->hit_ids, &r->ids_cap, m->n_hits, sizeof *r->hit_ids) < 0)
        return -ENOMEM;
    double t = (m->dwell_start_s + m->dwell_end_s) / 2;
    r->max_range_m = m->max_range_m;
    r->dwell_s = m->dwell_end_s - m->dwell_start_s;
    r->beamwidth_deg = m->azimuth_beamwidth_deg;
    r->velocity_sigma_mps = m->radial_velocity_sigma_mps;
    gw_s4607_dwell_t *d = &r->d;
    memset (d, 0, sizeof *d);
    d->revisit_index = (uint16_t)m->scan_number;
    d->dwell_index = (uint16_t)m->dwell_number;
    d->last_dwell = m->last_of_scan;
    d->time_s = s_time (self, t);
    d->sensor_lat_deg = pg.lat_deg;
    d->sensor_lon_deg = pg.lon_deg;
    d->sensor_alt_m = pg.height_m;
    d->along_track_unc_m = d->cross_track_unc_m = d->alt_unc_m = NAN;
    d->track_unc_deg = d->speed_unc_mps = d->vertical_velocity_unc_mps = NAN;
    d->track_deg = d->speed_mps = d->vertical_velocity_mps = NAN;
    d->platform_heading_deg = d->platform_pitch_deg = d->platform_roll_deg = NAN;
    if (r->heard) {
        d->track_deg = atan2 (r->velocity.e_m, r->velocity.n_m) / S_DEG;
        d->speed_mps = hypot (r->velocity.e_m, r->velocity.n_m);
        d->vertical_velocity_mps = r->velocity.u_m;
        d->platform_heading_deg = r->heading_deg;
        d->platform_pitch_deg = r->pitch_deg;
        d->platform_roll_deg = r->roll_deg;
    }
    // The dwell area: the beam's footprint on flat ground at the exercise
    // origin's height, between the range window's ground ranges.
    double h = plat.u_m;
    double gmin = sqrt (fmax (m->min_range_m * m->min_range_m - h * h, 0));
    double gmax = sqrt (fmax (m->max_range_m * m->max_range_m - h * h, 0));
    double gc = (gmin + gmax) / 2, az = m->beam_azimuth_deg * S_DEG;
    cgs_geodetic_t ag;
    if (!s_geodetic (self, (cgs_enu_t){plat.e_m + gc * sin (az), plat.n_m + gc * cos (az), 0}, &ag))
        return -EINVAL;
    d->area_lat_deg = ag.lat_deg;
    d->area_lon_deg = ag.lon_deg;
    d->range_half_extent_m = fmin ((gmax - gmin) / 2, 255990.0);
    d->angle_half_extent_deg = fmin (fmax (m->azimuth_beamwidth_deg / 2, 0), 180);
    d->sensor_heading_deg = d->sensor_pitch_deg = d->sensor_roll_deg = NAN;
    d->mdv_mps = self->p.s4607_mdv_mps;
    d->report_fields = GW_S4607_R_INDEX | GW_S4607_R_HEIGHT | GW_S4607_R_VELOCITY | GW_S4607_R_SNR |
                       GW_S4607_R_CLASS | GW_S4607_R_UNCERTAINTY |
                       (self->p.s4607_truth_tag ? GW_S4607_R_TRUTH_TAG : 0);
    // A report a hit.
    size_t n = 0;
    for (size_t i = 0; i < m->n_hits; i++) {
        const Cgs__MtiHit *hit = m->hits[i];
        cgs_geodetic_t g;
        if (!hit || !hit->position) {
            self->stats.unplaceable++;
            continue;
        }
        if (!s_geodetic (
                self,
                (cgs_enu_t){hit->position->east_m, hit->position->north_m, hit->position->up_m},
                &g))
            continue;
        gw_s4607_report_t *rep = &r->reports[n];
        memset (rep, 0, sizeof *rep);
        rep->index = (uint16_t)n;
        rep->lat_deg = g.lat_deg;
        rep->lon_deg = g.lon_deg;
        rep->height_m = g.height_m;
        rep->los_velocity_mps = hit->radial_velocity_mps;
        rep->wrap_velocity_mps = m->wrap_velocity_mps;
        rep->snr_db = hit->snr_db;
        rep->classification = GW_S4607_TARGET_NO_INFO_SIM;
        rep->slant_range_unc_m = hit->range_sigma_m;
        rep->cross_range_unc_m = hit->range_m * hit->azimuth_sigma_deg * S_DEG;
        // Sent with the slant and cross range's (tshark 4.0 reads D32.12-15
        // as one group). The hit is placed on the terrain: its height error
        // is the terrain's height change over its position error, not known
        // here; the slant range's is given.
        rep->height_unc_m = hit->range_sigma_m;
        rep->los_velocity_unc_mps = m->radial_velocity_sigma_mps;
        r->hit_ids[n] = hit->hit_id;
        n++;
        if (i == 0) {
            r->range_sigma_m = hit->range_sigma_m;
            r->azimuth_sigma_deg = hit->azimuth_sigma_deg;
        }
    }
    r->nreports = n;
    r->scan = m->scan_number;
    r->dwell = m->dwell_number;
    r->t_s = t;
    r->pending = true;
    r->age = 0;
    if (!self->p.s4607_truth_tag)
        s_send_dwell (self, r, false);
    return 0;
}

void gw_gmti_on_truth (gw_gmti_t *self, const Cgs__MtiTruth *t)
{
    s_radar_t *r = NULL;
    for (size_t i = 0; i < self->nradars; i++)
        if (self->radars[i].uav_id == t->uav_id)
            r = &self->radars[i];
    if (!r || !r->pending || r->scan != t->scan_number || r->dwell != t->dwell_number)
        return;
    for (size_t i = 0; i < t->n_items; i++) {
        const Cgs__MtiTruthItem *it = t->items[i];
        if (!it || !it->hit_id)
            continue;
        for (size_t k = 0; k < r->nreports; k++)
            if (r->hit_ids[k] == it->hit_id) {
                r->reports[k].truth_application = (uint8_t)self->p.application;
                r->reports[k].truth_entity = (uint32_t)self->p.entity_id_base + it->entity_id;
                self->stats.tagged++;
            }
    }
    s_send_dwell (self, r, true);
}

void gw_gmti_tick (gw_gmti_t *self)
{
    for (size_t i = 0; i < self->nradars; i++) {
        s_radar_t *r = &self->radars[i];
        if (r->pending && r->age++ >= 1) {
            self->stats.untagged++;
            s_send_dwell (self, r, false);
        }
    }
}

void gw_gmti_flush (gw_gmti_t *self)
{
    for (size_t i = 0; i < self->nradars; i++) {
        if (self->radars[i].pending && self->p.s4607_truth_tag)
            self->stats.untagged++;
        s_send_dwell (self, &self->radars[i], false);
    }
}
