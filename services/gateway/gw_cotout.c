/* gw_cotout — the exercise as Cursor on Target events (see gw_cotout.h). */
#include "gw_cotout.h"

#include "cgs_util.h"
#include "gw_index.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define S_UAV_MAX   64
#define S_ROUTE_MAX 64 // a drawing's vertices (gw_cot_event_t's links)
#define S_UNKNOWN   GW_COT_UNKNOWN_M

typedef struct {
    uint32_t track_id;
    bool friendly;
    uint32_t friendly_id;
    cgs_enu_t position;
    double course_deg, speed_mps;
    double ce_m;
    double heard_s;         // when a batch last carried it
    double sent_s;          // when it last went out (-inf: never)
    uint32_t designated_by; // the UAV whose intercept it is (0: none)
} s_track_t;

typedef struct {
    uint32_t entity_id;
    char name[64];
    cgs_enu_t position;
    double course_deg, speed_mps;
    double sensor_az_deg, sensor_el_deg, hfov_deg, vfov_deg;
    double heard_s, sent_s;
    // Its intercept's drawings.
    bool active; // an intercept under way
    bool drawn;  // its drawings went out (and must be removed when it ends)
    cgs_enu_t route[S_ROUTE_MAX];
    size_t nroute;
    cgs_enu_t footprint[4];
    bool has_footprint;
    cgs_enu_t footprint_center;
    uint32_t track_id;
    double drawn_s; // when the drawings last went out
} s_uav_t;

struct gw_cotout {
    gw_params_t p;
    const cgs_geo_t *geo;
    uint32_t exercise;
    char prefix[64]; // PREFIX-EX.
    gw_cotout_emit_fn *emit;
    void *arg;
    s_track_t *tracks;
    size_t ntracks, cap;
    gw_index_t *index; // track id -> position in tracks
    s_uav_t uavs[S_UAV_MAX];
    size_t nuav;
    gw_cotout_stats_t stats;
};

gw_cotout_t *gw_cotout_new (const gw_params_t *p, const cgs_geo_t *geo, uint32_t exercise_id,
                            gw_cotout_emit_fn *emit, void *arg)
{
    gw_cotout_t *self = calloc (1, sizeof *self);
    if (!self)
        return NULL;
    self->p = *p;
    self->geo = geo;
    self->exercise = exercise_id;
    self->emit = emit;
    self->arg = arg;
    snprintf (self->prefix, sizeof self->prefix, "%s-%u.", p->cot_uid_prefix, exercise_id);
    if (!(self->index = gw_index_new ()))
        gw_cotout_destroy (&self);
    return self;
}

void gw_cotout_destroy (gw_cotout_t **self_p)
{
    if (!self_p || !*self_p)
        return;
    gw_index_destroy (&(*self_p)->index);
    free ((*self_p)->tracks);
    free (*self_p);
    *self_p = NULL;
}

const gw_cotout_stats_t *gw_cotout_stats (const gw_cotout_t *self)
{
    return &self->stats;
}

bool gw_cotout_is_ours (const gw_cotout_t *self, const char *uid)
{
    return strncmp (uid, self->prefix, strlen (self->prefix)) == 0;
}

/* ---- events -------------------------------------------------------------------------------- */

/* An event of type at position p, sent at now_s, stale after stale_s (0: at once). */
static bool s_event (gw_cotout_t *self, gw_cot_event_t *e, const char *type, cgs_enu_t p,
                     double now_s, double stale_s)
{
    gw_cot_event_init (e);
    cgs_geodetic_t g;
    if (cgs_geo_enu_to_geodetic (self->geo, p, &g) < 0 || !isfinite (g.lat_deg) ||
        !isfinite (g.lon_deg)) {
        self->stats.unplaceable++;
        return false;
    }
    snprintf (e->type, sizeof e->type, "%s", type);
    snprintf (e->how, sizeof e->how, "m-p");
    snprintf (e->opex, sizeof e->opex, "s-%s", self->p.cot_uid_prefix);
    e->time_s = e->start_s = now_s;
    e->stale_s = now_s + stale_s;
    e->point = (gw_cot_point_t){g.lat_deg, g.lon_deg, g.height_m};
    e->ce_m = e->le_m = S_UNKNOWN;
    return true;
}

static void s_emit (gw_cotout_t *self, const gw_cot_event_t *e)
{
    self->emit (self->arg, e);
    self->stats.events++;
}

/* ---- tracks -------------------------------------------------------------------------------- */

static s_track_t *s_track (gw_cotout_t *self, uint32_t id, bool add)
{
    size_t at;
    if (gw_index_get (self->index, id, &at))
        return &self->tracks[at];
    if (!add)
        return NULL;
    if (cgs_grow ((void **)&self->tracks, &self->cap, self->ntracks + 1, sizeof *self->tracks) < 0)
        return NULL;
    if (gw_index_put (self->index, id, self->ntracks) < 0)
        return NULL;
    s_track_t *t = &self->tracks[self->ntracks++];
    memset (t, 0, sizeof *t);
    t->track_id = id;
    t->sent_s = -INFINITY;
    return t;
}

/* Remove tracks[i] (the last takes its place; the index is rebuilt). */
static void s_track_remove (gw_cotout_t *self, size_t i)
{
    self->tracks[i] = self->tracks[--self->ntracks];
    gw_index_clear (self->index);
    for (size_t k = 0; k < self->ntracks; k++)
        gw_index_put (self->index, self->tracks[k].track_id, k); // cannot grow: it held more
}

static void s_track_send (gw_cotout_t *self, s_track_t *t, double now_s, bool removing)
{
    gw_cot_event_t e;
    // Stale stale_s after the batch that last carried it: a client drops a
    // track the tracker no longer reports stale_s after its last report.
    double stale = removing ? 0 : fmax (t->heard_s + self->p.cot_stale_s - now_s, 0);
    if (!s_event (self, &e, t->friendly ? "a-f-G-E-V" : "a-u-G", t->position, now_s, stale))
        return;
    snprintf (e.uid, sizeof e.uid, "%strack.%u", self->prefix, t->track_id);
    snprintf (e.callsign, sizeof e.callsign, "T%u", t->track_id);
    e.ce_m = t->ce_m;
    e.has_track = true;
    e.course_deg = t->course_deg;
    e.speed_mps = t->speed_mps;
    int n = snprintf (e.remarks, sizeof e.remarks, "mscgs track %u", t->track_id);
    if (t->friendly && t->friendly_id && n > 0 && (size_t)n < sizeof e.remarks)
        n += snprintf (e.remarks + n, sizeof e.remarks - (size_t)n, ", BCIS responder %u",
                       t->friendly_id);
    if (t->designated_by && n > 0 && (size_t)n < sizeof e.remarks) {
        for (size_t i = 0; i < self->nuav; i++)
            if (self->uavs[i].entity_id == t->designated_by)
                snprintf (e.remarks + n, sizeof e.remarks - (size_t)n, ", designated for %s",
                          self->uavs[i].name);
    }
    if (removing)
        snprintf (e.remarks, sizeof e.remarks, "mscgs track %u deleted", t->track_id);
    s_emit (self, &e);
    t->sent_s = now_s;
    if (removing)
        self->stats.removed++;
    else
        self->stats.tracks++;
}

/* The 1-sigma radius of the major axis of a 2x2 position covariance. */
static double s_ce (const Cgs__Track *t)
{
    if (t->n_covariance < 16)
        return S_UNKNOWN;
    double a = t->covariance[0], b = t->covariance[1], c = t->covariance[5];
    double mean = (a + c) / 2, d = sqrt ((a - c) * (a - c) / 4 + b * b);
    double lmax = mean + d;
    return isfinite (lmax) && lmax >= 0 ? sqrt (lmax) : S_UNKNOWN;
}

void gw_cotout_on_tracks (gw_cotout_t *self, const Cgs__TrackBatch *b, double now_s)
{
    for (size_t i = 0; i < b->n_tracks; i++) {
        const Cgs__Track *m = b->tracks[i];
        if (!m || !m->position)
            continue;
        bool shown = m->status == CGS__TRACK_STATUS__TRACK_STATUS_CONFIRMED ||
                     m->status == CGS__TRACK_STATUS__TRACK_STATUS_COASTING;
        bool deleted = m->status == CGS__TRACK_STATUS__TRACK_STATUS_DELETED;
        s_track_t *t = s_track (self, m->track_id, shown);
        if (!t)
            continue;
        t->position = (cgs_enu_t){m->position->east_m, m->position->north_m, m->position->up_m};
        t->friendly = m->identity == CGS__TRACK_IDENTITY__TRACK_IDENTITY_FRIENDLY;
        t->friendly_id = m->friendly_id;
        t->course_deg = isfinite (m->heading_deg) ? fmod (m->heading_deg + 360.0, 360.0) : 0;
        t->speed_mps = isfinite (m->speed_mps) ? m->speed_mps : 0;
        t->ce_m = s_ce (m);
        t->heard_s = now_s;
        if (deleted || !shown) {
            // Gone, or tentative again: drop it from the clients if they have it.
            if (isfinite (t->sent_s))
                s_track_send (self, t, now_s, true);
            size_t at;
            if (gw_index_get (self->index, m->track_id, &at))
                s_track_remove (self, at);
            continue;
        }
        if (now_s - t->sent_s >= 1.0 / self->p.cot_rate_hz)
            s_track_send (self, t, now_s, false);
    }
}

/* ---- UAVs and their intercepts ------------------------------------------------------------- */

static s_uav_t *s_uav (gw_cotout_t *self, uint32_t id, bool add)
{
    for (size_t i = 0; i < self->nuav; i++)
        if (self->uavs[i].entity_id == id)
            return &self->uavs[i];
    if (!add || self->nuav == S_UAV_MAX)
        return NULL;
    s_uav_t *u = &self->uavs[self->nuav++];
    memset (u, 0, sizeof *u);
    u->entity_id = id;
    u->sent_s = u->drawn_s = -INFINITY;
    return u;
}

static void s_uav_send (gw_cotout_t *self, s_uav_t *u, double now_s)
{
    gw_cot_event_t e;
    if (!s_event (self, &e, "a-f-A-M-F-Q", u->position, now_s, self->p.cot_stale_s))
        return;
    snprintf (e.how, sizeof e.how, "m-g"); // its own navigation's position
    snprintf (e.uid, sizeof e.uid, "%suav.%s", self->prefix, u->name);
    snprintf (e.callsign, sizeof e.callsign, "%s", u->name);
    e.ce_m = 10;
    e.le_m = 10;
    e.has_track = true;
    e.course_deg = u->course_deg;
    e.speed_mps = u->speed_mps;
    e.has_sensor = true;
    e.sensor_azimuth_deg = u->sensor_az_deg;
    e.sensor_elevation_deg = u->sensor_el_deg;
    e.sensor_fov_deg = u->hfov_deg;
    e.sensor_vfov_deg = u->vfov_deg;
    // The range to the footprint's centre, or where the boresight meets a
    // flat ground at the UAV's height above the exercise origin.
    double range = 0;
    if (u->has_footprint) {
        double de = u->footprint_center.e_m - u->position.e_m;
        double dn = u->footprint_center.n_m - u->position.n_m;
        double du = u->footprint_center.u_m - u->position.u_m;
        range = sqrt (de * de + dn * dn + du * du);
    } else if (u->sensor_el_deg < -0.5 && u->position.u_m > 0) {
        range = u->position.u_m / sin (-u->sensor_el_deg * M_PI / 180);
    }
    e.sensor_range_m = range;
    snprintf (e.remarks, sizeof e.remarks, "mscgs UAV %s (entity %u)", u->name, u->entity_id);
    s_emit (self, &e);
    u->sent_s = now_s;
    self->stats.uavs++;
}

void gw_cotout_on_uav (gw_cotout_t *self, const Cgs__Uav *m, double now_s)
{
    if (!m->entity_id || !m->position || !m->name || !*m->name)
        return;
    s_uav_t *u = s_uav (self, m->entity_id, true);
    if (!u)
        return;
    snprintf (u->name, sizeof u->name, "%s", m->name);
    u->position = (cgs_enu_t){m->position->east_m, m->position->north_m, m->position->up_m};
    double ve = m->velocity ? m->velocity->east_mps : 0,
           vn = m->velocity ? m->velocity->north_mps : 0;
    u->speed_mps = hypot (ve, vn);
    u->course_deg = u->speed_mps > 0.1 ? fmod (atan2 (ve, vn) * 180 / M_PI + 360.0, 360.0)
                                       : fmod (m->heading_deg + 360.0, 360.0);
    u->sensor_az_deg = fmod (m->sensor_azimuth_deg + 360.0, 360.0);
    u->sensor_el_deg = m->sensor_elevation_deg;
    u->hfov_deg = m->sensor ? m->sensor->hfov_deg : 0;
    u->vfov_deg = m->sensor ? m->sensor->vfov_deg : 0;
    u->heard_s = now_s;
    if (now_s - u->sent_s >= 1.0 / self->p.cot_rate_hz)
        s_uav_send (self, u, now_s);
}

static void s_drawing (gw_cotout_t *self, s_uav_t *u, bool footprint, double now_s, bool removing)
{
    const cgs_enu_t *pts = footprint ? u->footprint : u->route;
    size_t n = footprint ? (u->has_footprint ? 4 : 0) : u->nroute;
    if (n == 0 && !removing)
        return;
    gw_cot_event_t e;
    cgs_enu_t at = n ? pts[0] : u->position;
    if (!s_event (self, &e, "u-d-f", at, now_s, removing ? 0 : self->p.cot_stale_s))
        return;
    snprintf (e.how, sizeof e.how, "h-e"); // drawn by a planner: entered, not measured
    snprintf (e.uid, sizeof e.uid, "%s%s.%s", self->prefix, footprint ? "footprint" : "route",
              u->name);
    snprintf (e.callsign, sizeof e.callsign, "%s %s", u->name,
              footprint ? "sensor footprint" : "intercept route");
    // ARGB as TAK writes it: the route yellow, the footprint cyan.
    snprintf (e.stroke_color, sizeof e.stroke_color, "%d", footprint ? -16711681 : -256);
    for (size_t i = 0; i < n && e.n_links < sizeof e.links / sizeof e.links[0]; i++) {
        cgs_geodetic_t g;
        if (cgs_geo_enu_to_geodetic (self->geo, pts[i], &g) < 0) {
            self->stats.unplaceable++;
            return;
        }
        e.links[e.n_links++] = (gw_cot_point_t){g.lat_deg, g.lon_deg, g.height_m};
    }
    e.closed = footprint && e.n_links >= 3;
    snprintf (e.remarks, sizeof e.remarks, "%s of %s, intercept of track %u%s",
              footprint ? "imaging sensor footprint" : "intercept route", u->name, u->track_id,
              removing ? ": ended" : "");
    s_emit (self, &e);
    self->stats.drawings++;
}

static void s_draw (gw_cotout_t *self, s_uav_t *u, double now_s, bool removing)
{
    s_drawing (self, u, false, now_s, removing);
    s_drawing (self, u, true, now_s, removing);
    u->drawn = !removing;
    u->drawn_s = now_s;
}

void gw_cotout_on_intercept (gw_cotout_t *self, const Cgs__Intercept *m, double now_s)
{
    s_uav_t *u = s_uav (self, m->uav_id, false);
    if (!u)
        return; // its UAV not heard of yet: its name makes the uids
    // The designated track is marked in its remarks.
    for (size_t i = 0; i < self->ntracks; i++)
        if (self->tracks[i].designated_by == m->uav_id)
            self->tracks[i].designated_by = 0;
    bool active = m->track_id != 0 && m->state != CGS__INTERCEPT_STATE__INTERCEPT_STATE_IDLE &&
                  m->state != CGS__INTERCEPT_STATE__INTERCEPT_STATE_DONE &&
                  m->state != CGS__INTERCEPT_STATE__INTERCEPT_STATE_CANCELLED &&
                  m->state != CGS__INTERCEPT_STATE__INTERCEPT_STATE_LOST;
    if (active) {
        s_track_t *t = s_track (self, m->track_id, false);
        if (t)
            t->designated_by = m->uav_id;
    }
    u->track_id = m->track_id;
    u->nroute = 0;
    for (size_t i = 0; i < m->n_route && u->nroute < S_ROUTE_MAX; i++)
        if (m->route[i])
            u->route[u->nroute++] =
                (cgs_enu_t){m->route[i]->east_m, m->route[i]->north_m, m->route[i]->up_m};
    u->has_footprint = m->footprint && m->footprint->n_corners == 4 && m->footprint->center;
    if (u->has_footprint) {
        for (size_t k = 0; k < 4; k++) {
            const Cgs__Enu *c = m->footprint->corners[k];
            u->footprint[k] = c ? (cgs_enu_t){c->east_m, c->north_m, c->up_m} : u->position;
        }
        const Cgs__Enu *c = m->footprint->center;
        u->footprint_center = (cgs_enu_t){c->east_m, c->north_m, c->up_m};
    }
    if (!active) {
        if (u->drawn)
            s_draw (self, u, now_s, true);
        u->active = false;
        return;
    }
    u->active = true;
    if (now_s - u->drawn_s >= 1.0 / self->p.cot_rate_hz)
        s_draw (self, u, now_s, false);
}

void gw_cotout_tick (gw_cotout_t *self, double now_s)
{
    double period = 1.0 / self->p.cot_rate_hz;
    for (size_t i = 0; i < self->ntracks;) {
        s_track_t *t = &self->tracks[i];
        if (now_s - t->heard_s >= self->p.cot_stale_s) { // no longer reported: it is stale
            s_track_remove (self, i);
            continue;
        }
        if (now_s - t->sent_s >= period)
            s_track_send (self, t, now_s, false);
        i++;
    }
    for (size_t i = 0; i < self->nuav; i++) {
        s_uav_t *u = &self->uavs[i];
        if (now_s - u->heard_s > self->p.cot_stale_s)
            continue;
        if (now_s - u->sent_s >= period)
            s_uav_send (self, u, now_s);
        if (u->active && now_s - u->drawn_s >= period)
            s_draw (self, u, now_s, false);
    }
}

uint32_t gw_cotout_uav_id (const gw_cotout_t *self, const char *name_or_uid)
{
    if (!name_or_uid || !*name_or_uid)
        return self->nuav ? self->uavs[0].entity_id : 0;
    const char *name = name_or_uid;
    size_t pl = strlen (self->prefix);
    if (strncmp (name, self->prefix, pl) == 0 && strncmp (name + pl, "uav.", 4) == 0)
        name += pl + 4;
    for (size_t i = 0; i < self->nuav; i++)
        if (strcmp (self->uavs[i].name, name) == 0)
            return self->uavs[i].entity_id;
    return 0;
}

void gw_cotout_uav_uid (const gw_cotout_t *self, uint32_t uav_id, char *buf, size_t len)
{
    if (len)
        *buf = '\0';
    for (size_t i = 0; i < self->nuav; i++)
        if (self->uavs[i].entity_id == uav_id)
            snprintf (buf, len, "%suav.%s", self->prefix, self->uavs[i].name);
}
