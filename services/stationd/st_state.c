/* st_state — the tactical map's picture (see st_state.h). */
#include "st_state.h"
#include "cgs_json.h"

#include "cgs_entities.h"
#include "cgs_msg.h"

#include <errno.h>
#include <json-c/json.h>
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define S_RADARS_MAX 16    // radars (UAVs with an MTI) whose hits are kept
#define S_UAVS_MAX   16    // UAVs and intercepts
#define S_BCIS_MAX   20000 // BCIS replies kept at once (the oldest go first)
#define S_PATH_MAX   4096

typedef struct {
    double e, n;
} s_xy_t;

/* One MTI hit: where, and its id (unique within the radar's epoch). */
typedef struct {
    double e, n;
    uint32_t id;
} s_hit_t;

/* One scan of one radar's hits. */
typedef struct {
    uint32_t number;
    bool complete; // mti.scan said it ended
    s_hit_t *hits;
    size_t count, cap;
} s_scan_t;

/* One radar: its scans, oldest first. */
typedef struct {
    uint32_t uav_id;
    uint64_t epoch;  // its publisher's, to start afresh when mtid restarts
    s_scan_t *scans; // history_scans + 2 slots
    size_t count;
    double heard_s; // simulation time it was last heard of
} s_radar_t;

typedef struct {
    uint32_t uav_id, id;
    char marking[32];
    double e, n, time_s;
} s_bcis_t;

typedef struct {
    uint32_t id, uav_id;
    int status;   // CGS__TRACK_STATUS__*
    int identity; // CGS__TRACK_IDENTITY__*
    double e, n, heading_deg, speed_mps;
    uint32_t hits, friendly_id;
    bool has_last_hit;
    s_xy_t last_hit; // the track's newest hit
    uint32_t last_hit_id;
    double updated_s;
    uint64_t epoch; // trackerd's
} s_track_t;

typedef struct {
    bool valid;
    uint32_t id;
    char name[32];
    double e, n, alt_agl_m, heading_deg, airspeed_mps, ground_speed_mps;
    double cmd_alt_agl_m, cmd_airspeed_mps;
    int mode;
    double loiter_e, loiter_n, loiter_radius_m;
    double heard_s;
} s_uav_t;

typedef struct {
    bool valid;
    uint32_t uav_id, track_id;
    int state, method;
    s_xy_t *route;
    size_t route_count, route_cap;
    bool has_footprint;
    double footprint[8], center[2];
    unsigned scale;
    bool has_waypoint, has_secondary;
    s_xy_t waypoint, secondary;
    double time_to_go_s, t_pred_s;
    uint32_t replans;
    char reason[256];
    bool target_in_footprint;
    uint64_t designation;
    double heard_s;
} s_intercept_t;

struct st_state {
    st_state_params_t p;
    double now_s;
    bool have_clock;      // a clock was heard: only it moves time
    uint64_t clock_epoch; // its publisher's
    s_radar_t radars[S_RADARS_MAX];
    size_t radar_count;
    s_bcis_t *bcis; // oldest first
    size_t bcis_count;
    s_track_t *tracks;
    size_t track_count, track_cap;
    s_uav_t uavs[S_UAVS_MAX];
    s_intercept_t intercepts[S_UAVS_MAX];
    cgs_entities_t *truth;
    bool has_image;
    bool image_shown;           // st_state_image_shown was told of a frame
    uint64_t image_shown_frame; // that frame
    uint32_t image_uav;
    uint64_t image_frame;
    int image_mode;
    bool image_target_in_view;
    char image_path[S_PATH_MAX];
};

st_state_t *st_state_new (const st_state_params_t *p)
{
    st_state_t *self = calloc (1, sizeof *self);
    if (!self)
        return NULL;
    self->p = *p;
    if (self->p.history_scans < 0)
        self->p.history_scans = 0;
    self->bcis = malloc (S_BCIS_MAX * sizeof *self->bcis);
    self->truth = cgs_entities_new ();
    if (!self->bcis || !self->truth)
        st_state_destroy (&self);
    return self;
}

static void s_radar_free (s_radar_t *r)
{
    for (size_t i = 0; i < r->count; i++)
        free (r->scans[i].hits);
    free (r->scans);
    memset (r, 0, sizeof *r);
}

void st_state_destroy (st_state_t **self_p)
{
    st_state_t *self = self_p ? *self_p : NULL;
    if (!self)
        return;
    for (size_t i = 0; i < self->radar_count; i++)
        s_radar_free (&self->radars[i]);
    for (size_t i = 0; i < S_UAVS_MAX; i++)
        free (self->intercepts[i].route);
    free (self->bcis);
    free (self->tracks);
    cgs_entities_destroy (&self->truth);
    free (self);
    *self_p = NULL;
}

static bool s_finite2 (double a, double b)
{
    return isfinite (a) && isfinite (b);
}

static bool s_enu_ok (const Cgs__Enu *p)
{
    return p && s_finite2 (p->east_m, p->north_m);
}

static void s_advance (st_state_t *self, double t_s)
{
    if (isfinite (t_s) && t_s > self->now_s)
        self->now_s = t_s;
}

/* A message's own time moves time only while no clock is heard. */
static void s_time_from (st_state_t *self, const Cgs__Header *hdr)
{
    if (hdr && !self->have_clock)
        s_advance (self, hdr->sim_time_s);
}

void st_state_set_time (st_state_t *self, double sim_time_s)
{
    s_advance (self, sim_time_s);
}

void st_state_set_clock (st_state_t *self, double t_s, uint64_t epoch)
{
    if (!isfinite (t_s))
        return;
    bool restarted = self->have_clock && epoch != self->clock_epoch && t_s < self->now_s;
    self->have_clock = true;
    self->clock_epoch = epoch;
    if (!restarted) {
        s_advance (self, t_s);
        return;
    }
    // A restarted exercise: time goes back; nothing may stay "from the future".
    self->now_s = t_s;
    self->bcis_count = 0;
    for (size_t i = 0; i < self->track_count; i++)
        self->tracks[i].updated_s = fmin (self->tracks[i].updated_s, t_s);
    for (size_t i = 0; i < self->radar_count; i++)
        self->radars[i].heard_s = fmin (self->radars[i].heard_s, t_s);
    for (int i = 0; i < S_UAVS_MAX; i++) {
        self->uavs[i].heard_s = fmin (self->uavs[i].heard_s, t_s);
        self->intercepts[i].heard_s = fmin (self->intercepts[i].heard_s, t_s);
    }
}

double st_state_time (const st_state_t *self)
{
    return self->now_s;
}

/* ---- UAVs and intercepts ---------------------------------------------------------- */

/* The slot of a UAV's id in a table of S_UAVS_MAX (found, or the first free),
 * or -1 when the table is full. */
static int s_uav_slot (const st_state_t *self, uint32_t id)
{
    int free_slot = -1;
    for (int i = 0; i < S_UAVS_MAX; i++) {
        if (self->uavs[i].valid && self->uavs[i].id == id)
            return i;
        if (!self->uavs[i].valid && free_slot < 0)
            free_slot = i;
    }
    return free_slot;
}

int st_state_take_uav (st_state_t *self, const Cgs__Uav *m, const Cgs__Header *hdr)
{
    if (!m || m->entity_id == 0 || !s_enu_ok (m->position) || !isfinite (m->heading_deg))
        return -EINVAL;
    int i = s_uav_slot (self, m->entity_id);
    if (i < 0)
        return -ENOSPC;
    s_time_from (self, hdr);
    s_uav_t *u = &self->uavs[i];
    *u = (s_uav_t){.valid = true, .id = m->entity_id, .heard_s = self->now_s};
    snprintf (u->name, sizeof u->name, "%s", m->name ? m->name : "");
    u->e = m->position->east_m;
    u->n = m->position->north_m;
    u->alt_agl_m = m->altitude_agl_m;
    u->heading_deg = m->heading_deg;
    u->airspeed_mps = m->airspeed_mps;
    u->ground_speed_mps = m->ground_speed_mps;
    u->cmd_alt_agl_m = m->commanded_altitude_agl_m;
    u->cmd_airspeed_mps = m->commanded_airspeed_mps;
    u->mode = m->mode;
    if (m->loiter && s_enu_ok (m->loiter->center)) {
        u->loiter_e = m->loiter->center->east_m;
        u->loiter_n = m->loiter->center->north_m;
        u->loiter_radius_m = m->loiter->radius_m;
    }
    return 0;
}

static int s_intercept_slot (const st_state_t *self, uint32_t uav_id)
{
    int free_slot = -1;
    for (int i = 0; i < S_UAVS_MAX; i++) {
        if (self->intercepts[i].valid && self->intercepts[i].uav_id == uav_id)
            return i;
        if (!self->intercepts[i].valid && free_slot < 0)
            free_slot = i;
    }
    return free_slot;
}

void st_footprint_scaled (const double corners_en[8], const double center_en[2], unsigned scale,
                          double ret_en[8])
{
    double k = (scale == 5 || scale == 10) ? (double)scale : 1.0;
    for (int i = 0; i < 4; i++) {
        ret_en[2 * i] = center_en[0] + k * (corners_en[2 * i] - center_en[0]);
        ret_en[2 * i + 1] = center_en[1] + k * (corners_en[2 * i + 1] - center_en[1]);
    }
}

int st_state_take_intercept (st_state_t *self, const Cgs__Intercept *m, const Cgs__Header *hdr)
{
    if (!m || m->uav_id == 0)
        return -EINVAL;
    for (size_t i = 0; i < m->n_route; i++)
        if (!s_enu_ok (m->route[i]))
            return -EINVAL;
    int slot = s_intercept_slot (self, m->uav_id);
    if (slot < 0)
        return -ENOSPC;
    s_intercept_t *x = &self->intercepts[slot];
    if (m->n_route > x->route_cap) {
        s_xy_t *r = realloc (x->route, m->n_route * sizeof *r);
        if (!r)
            return -ENOMEM;
        x->route = r;
        x->route_cap = m->n_route;
    }
    x->valid = true;
    x->uav_id = m->uav_id;
    x->track_id = m->track_id;
    x->state = m->state;
    x->method = m->method;
    for (size_t i = 0; i < m->n_route; i++)
        x->route[i] = (s_xy_t){m->route[i]->east_m, m->route[i]->north_m};
    x->route_count = m->n_route;
    x->has_footprint =
        m->footprint && m->footprint->n_corners == 4 && s_enu_ok (m->footprint->center);
    for (size_t i = 0; x->has_footprint && i < 4; i++)
        x->has_footprint = s_enu_ok (m->footprint->corners[i]);
    if (x->has_footprint) {
        for (int i = 0; i < 4; i++) {
            x->footprint[2 * i] = m->footprint->corners[i]->east_m;
            x->footprint[2 * i + 1] = m->footprint->corners[i]->north_m;
        }
        x->center[0] = m->footprint->center->east_m;
        x->center[1] = m->footprint->center->north_m;
        x->scale = m->footprint->display_scale;
    }
    x->has_waypoint = m->track_id != 0 && s_enu_ok (m->waypoint);
    if (x->has_waypoint)
        x->waypoint = (s_xy_t){m->waypoint->east_m, m->waypoint->north_m};
    x->has_secondary = m->has_secondary && s_enu_ok (m->secondary_waypoint);
    if (x->has_secondary)
        x->secondary = (s_xy_t){m->secondary_waypoint->east_m, m->secondary_waypoint->north_m};
    x->time_to_go_s = m->time_to_go_s;
    x->t_pred_s = m->t_pred_s;
    x->replans = m->replans;
    snprintf (x->reason, sizeof x->reason, "%s", m->reason ? m->reason : "");
    x->target_in_footprint = m->target_in_footprint;
    x->designation = m->designation_number;
    s_time_from (self, hdr);
    x->heard_s = self->now_s;
    return 0;
}

/* ---- MTI hits --------------------------------------------------------------------- */

static s_radar_t *s_radar (st_state_t *self, uint32_t uav_id, uint64_t epoch, int *ret_rc)
{
    *ret_rc = 0;
    s_radar_t *r = NULL;
    for (size_t i = 0; i < self->radar_count; i++)
        if (self->radars[i].uav_id == uav_id)
            r = &self->radars[i];
    if (!r) {
        if (self->radar_count == S_RADARS_MAX) {
            *ret_rc = -ENOSPC;
            return NULL;
        }
        s_scan_t *scans = calloc ((size_t)self->p.history_scans + 2, sizeof *scans);
        if (!scans) {
            *ret_rc = -ENOMEM;
            return NULL;
        }
        r = &self->radars[self->radar_count++];
        *r = (s_radar_t){.uav_id = uav_id, .epoch = epoch, .scans = scans};
    } else if (epoch && r->epoch && epoch != r->epoch) {
        // The radar restarted: its scan numbers start again.
        for (size_t i = 0; i < r->count; i++)
            free (r->scans[i].hits);
        memset (r->scans, 0, ((size_t)self->p.history_scans + 2) * sizeof *r->scans);
        r->count = 0;
    }
    if (epoch)
        r->epoch = epoch;
    r->heard_s = self->now_s;
    return r;
}

/* The radar's scan of that number, made (dropping the oldest when full) if it
 * is newer than every scan kept; NULL for a scan older than those kept. */
static s_scan_t *s_scan (st_state_t *self, s_radar_t *r, uint32_t number)
{
    for (size_t i = r->count; i-- > 0;)
        if (r->scans[i].number == number)
            return &r->scans[i];
    if (r->count > 0 && number < r->scans[r->count - 1].number)
        return NULL; // late hits of a scan already dropped, or of an older one
    size_t slots = (size_t)self->p.history_scans + 2;
    if (r->count == slots) {
        free (r->scans[0].hits);
        memmove (&r->scans[0], &r->scans[1], (slots - 1) * sizeof r->scans[0]);
        r->count--;
    }
    s_scan_t *s = &r->scans[r->count++];
    *s = (s_scan_t){.number = number};
    return s;
}

/* Keep at most history_scans complete scans behind the newest complete one
 * (and any scan in progress after it). */
static void s_trim (st_state_t *self, s_radar_t *r)
{
    size_t complete = 0;
    for (size_t i = 0; i < r->count; i++)
        complete += r->scans[i].complete;
    size_t keep = (size_t)self->p.history_scans + 1;
    while (complete > keep || (r->count > 0 && r->count > keep + 1)) {
        complete -= r->scans[0].complete;
        free (r->scans[0].hits);
        memmove (&r->scans[0], &r->scans[1], (r->count - 1) * sizeof r->scans[0]);
        r->count--;
    }
}

int st_state_take_mti (st_state_t *self, const Cgs__Mti *m, const Cgs__Header *hdr)
{
    if (!m || m->uav_id == 0)
        return -EINVAL;
    for (size_t i = 0; i < m->n_hits; i++)
        if (!m->hits[i] || !s_enu_ok (m->hits[i]->position))
            return -EINVAL;
    int rc;
    s_time_from (self, hdr);
    s_radar_t *r = s_radar (self, m->uav_id, hdr ? hdr->epoch : 0, &rc);
    if (!r)
        return rc;
    s_scan_t *s = s_scan (self, r, m->scan_number);
    if (!s)
        return 0;
    if (s->count + m->n_hits > s->cap) {
        size_t cap = s->cap ? s->cap : 64;
        while (cap < s->count + m->n_hits)
            cap *= 2;
        s_hit_t *h = realloc (s->hits, cap * sizeof *h);
        if (!h)
            return -ENOMEM;
        s->hits = h;
        s->cap = cap;
    }
    for (size_t i = 0; i < m->n_hits; i++)
        s->hits[s->count++] = (s_hit_t){m->hits[i]->position->east_m, m->hits[i]->position->north_m,
                                        m->hits[i]->hit_id};
    s_trim (self, r);
    return 0;
}

int st_state_take_mti_scan (st_state_t *self, const Cgs__MtiScan *m, const Cgs__Header *hdr)
{
    if (!m || m->uav_id == 0)
        return -EINVAL;
    int rc;
    s_time_from (self, hdr);
    s_radar_t *r = s_radar (self, m->uav_id, hdr ? hdr->epoch : 0, &rc);
    if (!r)
        return rc;
    s_scan_t *s = s_scan (self, r, m->scan_number);
    if (s)
        s->complete = true;
    s_trim (self, r);
    return 0;
}

size_t st_state_hit_count (const st_state_t *self)
{
    size_t n = 0;
    for (size_t i = 0; i < self->radar_count; i++)
        for (size_t j = 0; j < self->radars[i].count; j++)
            n += self->radars[i].scans[j].count;
    return n;
}

/* ---- BCIS ------------------------------------------------------------------------- */

int st_state_take_bcis (st_state_t *self, const Cgs__Bcis *m, const Cgs__Header *hdr)
{
    if (!m || m->uav_id == 0)
        return -EINVAL;
    for (size_t i = 0; i < m->n_replies; i++)
        if (!m->replies[i] || !s_enu_ok (m->replies[i]->position) ||
            !isfinite (m->replies[i]->sim_time_s))
            return -EINVAL;
    s_time_from (self, hdr);
    for (size_t i = 0; i < m->n_replies; i++) {
        const Cgs__BcisReply *rp = m->replies[i];
        if (self->bcis_count == S_BCIS_MAX) {
            memmove (&self->bcis[0], &self->bcis[1], (S_BCIS_MAX - 1) * sizeof self->bcis[0]);
            self->bcis_count--;
        }
        s_bcis_t *b = &self->bcis[self->bcis_count++];
        *b = (s_bcis_t){.uav_id = m->uav_id,
                        .id = rp->responder_id,
                        .e = rp->position->east_m,
                        .n = rp->position->north_m,
                        .time_s = rp->sim_time_s};
        snprintf (b->marking, sizeof b->marking, "%s", rp->marking ? rp->marking : "");
        if (!self->have_clock)
            s_advance (self, rp->sim_time_s);
    }
    return 0;
}

/* ---- tracks ----------------------------------------------------------------------- */

static s_track_t *s_track_find (st_state_t *self, uint32_t id)
{
    for (size_t i = 0; i < self->track_count; i++)
        if (self->tracks[i].id == id)
            return &self->tracks[i];
    return NULL;
}

static void s_track_remove (st_state_t *self, size_t i)
{
    self->tracks[i] = self->tracks[--self->track_count];
}

int st_state_take_tracks (st_state_t *self, const Cgs__TrackBatch *m, const Cgs__Header *hdr)
{
    if (!m)
        return -EINVAL;
    for (size_t i = 0; i < m->n_tracks; i++) {
        const Cgs__Track *t = m->tracks[i];
        if (!t || t->track_id == 0 || !s_enu_ok (t->position) || !isfinite (t->heading_deg))
            return -EINVAL;
    }
    uint64_t epoch = hdr ? hdr->epoch : 0;
    s_time_from (self, hdr);
    double t_s = hdr && isfinite (hdr->sim_time_s) ? hdr->sim_time_s : self->now_s;
    // A new epoch of trackerd: its track ids start again, so forget its old tracks.
    for (size_t i = self->track_count; epoch && i-- > 0;)
        if (self->tracks[i].epoch && self->tracks[i].epoch != epoch)
            s_track_remove (self, i);
    for (size_t i = 0; i < m->n_tracks; i++) {
        const Cgs__Track *t = m->tracks[i];
        s_track_t *k = s_track_find (self, t->track_id);
        if (t->status == CGS__TRACK_STATUS__TRACK_STATUS_DELETED) {
            if (k)
                s_track_remove (self, (size_t)(k - self->tracks));
            continue;
        }
        if (!k) {
            if (self->track_count == self->track_cap) {
                size_t cap = self->track_cap ? 2 * self->track_cap : 256;
                s_track_t *a = realloc (self->tracks, cap * sizeof *a);
                if (!a)
                    return -ENOMEM;
                self->tracks = a;
                self->track_cap = cap;
            }
            k = &self->tracks[self->track_count++];
        }
        *k = (s_track_t){.id = t->track_id,
                         .uav_id = t->uav_id ? t->uav_id : m->uav_id,
                         .status = t->status,
                         .identity = t->identity,
                         .e = t->position->east_m,
                         .n = t->position->north_m,
                         .heading_deg = t->heading_deg,
                         .speed_mps = isfinite (t->speed_mps) ? t->speed_mps : 0,
                         .hits = t->hit_count,
                         .friendly_id = t->friendly_id,
                         .updated_s = t_s,
                         .epoch = epoch};
        // The history runs oldest to newest: its last point is the newest hit.
        for (size_t j = t->n_history; j-- > 0;) {
            const Cgs__TrackHistoryPoint *h = t->history[j];
            if (h && s_enu_ok (h->position)) {
                k->has_last_hit = true;
                k->last_hit = (s_xy_t){h->position->east_m, h->position->north_m};
                k->last_hit_id = h->hit_id;
                break;
            }
        }
    }
    return 0;
}

size_t st_state_track_count (const st_state_t *self)
{
    return self->track_count;
}

/* ---- ground truth and image ------------------------------------------------------- */

int st_state_take_entities (st_state_t *self, const Cgs__EntityBatch *m, const Cgs__Header *hdr)
{
    if (!m)
        return -EINVAL;
    double t_s = hdr && isfinite (hdr->sim_time_s) ? hdr->sim_time_s : self->now_s;
    size_t bad = 0;
    int rc = cgs_entities_update (self->truth, m, t_s, &bad);
    if (rc < 0)
        return rc;
    s_time_from (self, hdr);
    return bad ? -EINVAL : 0;
}

int st_state_take_image (st_state_t *self, const Cgs__Image *m, const Cgs__Header *hdr)
{
    if (!m)
        return -EINVAL;
    s_time_from (self, hdr);
    if (!m->latest_path || !m->latest_path[0])
        return 0; // a frame that did not refresh latest.png: nothing new to show
    if (strlen (m->latest_path) >= sizeof self->image_path || m->latest_path[0] != '/')
        return -EINVAL;
    self->has_image = true;
    self->image_uav = m->uav_id;
    self->image_frame = m->frame_number;
    self->image_mode = m->mode;
    self->image_target_in_view = m->target_in_view;
    snprintf (self->image_path, sizeof self->image_path, "%s", m->latest_path);
    return 0;
}

void st_state_image_shown (st_state_t *self, uint64_t frame)
{
    self->image_shown = true;
    self->image_shown_frame = frame;
}

const char *st_state_image_path (const st_state_t *self, uint64_t *ret_frame)
{
    if (ret_frame)
        *ret_frame = self->image_frame;
    return self->has_image ? self->image_path : "";
}

/* ---- ageing ----------------------------------------------------------------------- */

void st_state_prune (st_state_t *self)
{
    double now = self->now_s;
    size_t w = 0;
    for (size_t i = 0; i < self->bcis_count; i++)
        if (now - self->bcis[i].time_s <= self->p.bcis_timeout_s)
            self->bcis[w++] = self->bcis[i];
    self->bcis_count = w;
    for (size_t i = self->track_count; i-- > 0;)
        if (now - self->tracks[i].updated_s > self->p.track_stale_s)
            s_track_remove (self, i);
    // A radar, UAV or intercept no longer heard of (its service stopped).
    for (size_t i = 0; i < self->radar_count; i++) {
        s_radar_t *r = &self->radars[i];
        if (now - r->heard_s > self->p.track_stale_s) {
            for (size_t j = 0; j < r->count; j++)
                free (r->scans[j].hits);
            memset (r->scans, 0, ((size_t)self->p.history_scans + 2) * sizeof *r->scans);
            r->count = 0;
        }
    }
    for (int i = 0; i < S_UAVS_MAX; i++) {
        if (self->uavs[i].valid && now - self->uavs[i].heard_s > self->p.track_stale_s)
            self->uavs[i].valid = false;
        if (self->intercepts[i].valid && now - self->intercepts[i].heard_s > self->p.track_stale_s)
            self->intercepts[i].valid = false;
    }
    cgs_entities_evict (self->truth, now, self->p.truth_stale_s);
}

/* ---- JSON ------------------------------------------------------------------------- */

static const char *s_status_name (int s)
{
    switch (s) {
    case CGS__TRACK_STATUS__TRACK_STATUS_CONFIRMED:
        return "confirmed";
    case CGS__TRACK_STATUS__TRACK_STATUS_COASTING:
        return "coasting";
    default:
        return "tentative";
    }
}

static const char *s_mode_name (int m)
{
    switch (m) {
    case CGS__UAV_MODE__UAV_MODE_ROUTE:
        return "route";
    case CGS__UAV_MODE__UAV_MODE_TRANSIT:
        return "transit";
    default:
        return "loiter";
    }
}

static const char *s_intercept_state_name (int s)
{
    return cgs_msg_enum_short (&cgs__intercept_state__descriptor, s, "IDLE");
}

static const char *s_force_name (cgs_force_t f)
{
    switch (f) {
    case CGS_FORCE_FRIENDLY:
        return "friendly";
    case CGS_FORCE_HOSTILE:
        return "opposing";
    case CGS_FORCE_NEUTRAL:
        return "neutral";
    default:
        return "other";
    }
}

static const char *s_kind_name (cgs_kind_t k)
{
    switch (k) {
    case CGS_KIND_TRACKED:
        return "tracked";
    case CGS_KIND_WHEELED:
        return "wheeled";
    case CGS_KIND_AIR:
        return "air";
    case CGS_KIND_PERSON:
        return "person";
    default:
        return "other";
    }
}

static json_object *s_m (double v) // metres, to the decimetre
{
    return cgs_json_fixed (v, 1);
}

static json_object *s_xy (s_xy_t p)
{
    json_object *a = json_object_new_array_ext (2);
    json_object_array_add (a, s_m (p.e));
    json_object_array_add (a, s_m (p.n));
    return a;
}

static json_object *s_json_uavs (const st_state_t *self)
{
    json_object *a = json_object_new_array ();
    for (int i = 0; i < S_UAVS_MAX; i++) {
        const s_uav_t *u = &self->uavs[i];
        if (!u->valid)
            continue;
        json_object *o = json_object_new_object ();
        cgs_json_add (o, "id", json_object_new_int64 (u->id));
        cgs_json_add (o, "name", json_object_new_string (u->name));
        cgs_json_add (o, "e", s_m (u->e));
        cgs_json_add (o, "n", s_m (u->n));
        cgs_json_add (o, "alt_agl_m", s_m (u->alt_agl_m));
        cgs_json_add (o, "heading_deg", cgs_json_fixed (u->heading_deg, 1));
        cgs_json_add (o, "airspeed_mps", cgs_json_fixed (u->airspeed_mps, 1));
        cgs_json_add (o, "ground_speed_mps", cgs_json_fixed (u->ground_speed_mps, 1));
        cgs_json_add (o, "cmd_alt_agl_m", s_m (u->cmd_alt_agl_m));
        cgs_json_add (o, "cmd_airspeed_mps", cgs_json_fixed (u->cmd_airspeed_mps, 1));
        cgs_json_add (o, "mode", json_object_new_string (s_mode_name (u->mode)));
        json_object *l = json_object_new_object ();
        cgs_json_add (l, "e", s_m (u->loiter_e));
        cgs_json_add (l, "n", s_m (u->loiter_n));
        cgs_json_add (l, "radius_m", s_m (u->loiter_radius_m));
        cgs_json_add (o, "loiter", l);
        json_object_array_add (a, o);
    }
    return a;
}

static json_object *s_json_hits (const st_state_t *self)
{
    json_object *a = json_object_new_array ();
    for (size_t i = 0; i < self->radar_count; i++) {
        const s_radar_t *r = &self->radars[i];
        // As the paper's display: the current scan yellow, the ones before
        // it grey. The current scan is the newest that has ended (its end
        // marker came, or a later scan began: the marker was lost); a scan
        // still in progress is drawn when it ends, so that each vehicle has
        // one yellow hit.
        size_t shown = r->count;
        if (shown > 0 && !r->scans[shown - 1].complete)
            shown--;
        for (size_t j = 0; j < shown; j++) {
            const s_scan_t *s = &r->scans[j];
            json_object *o = json_object_new_object ();
            cgs_json_add (o, "uav_id", json_object_new_int64 (r->uav_id));
            cgs_json_add (o, "scan", json_object_new_int64 (s->number));
            cgs_json_add (o, "current", json_object_new_boolean (j + 1 == shown));
            json_object *xy = json_object_new_array_ext ((int)(2 * s->count));
            for (size_t k = 0; k < s->count; k++) {
                json_object_array_add (xy, s_m (s->hits[k].e));
                json_object_array_add (xy, s_m (s->hits[k].n));
            }
            cgs_json_add (o, "xy", xy);
            json_object *ids = json_object_new_array_ext ((int)s->count);
            for (size_t k = 0; k < s->count; k++)
                json_object_array_add (ids, json_object_new_int64 (s->hits[k].id));
            cgs_json_add (o, "ids", ids);
            json_object_array_add (a, o);
        }
    }
    return a;
}

static json_object *s_json_bcis (const st_state_t *self)
{
    json_object *a = json_object_new_array ();
    for (size_t i = 0; i < self->bcis_count; i++) {
        const s_bcis_t *b = &self->bcis[i];
        json_object *o = json_object_new_object ();
        cgs_json_add (o, "uav_id", json_object_new_int64 (b->uav_id));
        cgs_json_add (o, "id", json_object_new_int64 (b->id));
        cgs_json_add (o, "marking", json_object_new_string (b->marking));
        cgs_json_add (o, "e", s_m (b->e));
        cgs_json_add (o, "n", s_m (b->n));
        cgs_json_add (o, "age_s", cgs_json_fixed (fmax (0, self->now_s - b->time_s), 2));
        json_object_array_add (a, o);
    }
    return a;
}

static json_object *s_json_tracks (const st_state_t *self)
{
    json_object *a = json_object_new_array_ext ((int)self->track_count);
    for (size_t i = 0; i < self->track_count; i++) {
        const s_track_t *t = &self->tracks[i];
        json_object *o = json_object_new_object ();
        cgs_json_add (o, "id", json_object_new_int64 (t->id));
        cgs_json_add (o, "uav_id", json_object_new_int64 (t->uav_id));
        cgs_json_add (o, "status", json_object_new_string (s_status_name (t->status)));
        cgs_json_add (o, "identity",
                      json_object_new_string (
                          t->identity == CGS__TRACK_IDENTITY__TRACK_IDENTITY_FRIENDLY ? "friendly"
                                                                                      : "unknown"));
        cgs_json_add (o, "e", s_m (t->e));
        cgs_json_add (o, "n", s_m (t->n));
        cgs_json_add (o, "heading_deg", cgs_json_fixed (t->heading_deg, 1));
        cgs_json_add (o, "speed_mps", cgs_json_fixed (t->speed_mps, 1));
        cgs_json_add (o, "hits", json_object_new_int64 (t->hits));
        cgs_json_add (o, "last_hit", t->has_last_hit ? s_xy (t->last_hit) : NULL);
        cgs_json_add (o, "last_hit_id",
                      t->has_last_hit ? json_object_new_int64 (t->last_hit_id) : NULL);
        cgs_json_add (o, "friendly_id", json_object_new_int64 (t->friendly_id));
        json_object_array_add (a, o);
    }
    return a;
}

static const s_uav_t *s_uav_find (const st_state_t *self, uint32_t id)
{
    for (int i = 0; i < S_UAVS_MAX; i++)
        if (self->uavs[i].valid && self->uavs[i].id == id)
            return &self->uavs[i];
    return NULL;
}

static json_object *s_corners (const double en[8])
{
    json_object *a = json_object_new_array_ext (8);
    for (int i = 0; i < 8; i++)
        json_object_array_add (a, s_m (en[i]));
    return a;
}

static json_object *s_json_intercepts (st_state_t *self)
{
    json_object *a = json_object_new_array ();
    for (int i = 0; i < S_UAVS_MAX; i++) {
        const s_intercept_t *x = &self->intercepts[i];
        if (!x->valid)
            continue;
        json_object *o = json_object_new_object ();
        cgs_json_add (o, "uav_id", json_object_new_int64 (x->uav_id));
        cgs_json_add (o, "track_id", json_object_new_int64 (x->track_id));
        cgs_json_add (o, "state", json_object_new_string (s_intercept_state_name (x->state)));
        cgs_json_add (
            o, "method",
            json_object_new_string (x->method == CGS__INTERCEPT_METHOD__INTERCEPT_METHOD_MTI_HITS
                                        ? "mti-hits"
                                        : "head-on"));
        json_object *route = json_object_new_array_ext ((int)(2 * x->route_count));
        for (size_t k = 0; k < x->route_count; k++) {
            json_object_array_add (route, s_m (x->route[k].e));
            json_object_array_add (route, s_m (x->route[k].n));
        }
        cgs_json_add (o, "route", route);
        if (x->has_footprint) {
            double shown[8];
            st_footprint_scaled (x->footprint, x->center, x->scale, shown);
            cgs_json_add (o, "footprint", s_corners (x->footprint));
            cgs_json_add (o, "footprint_display", s_corners (shown));
        } else {
            cgs_json_add (o, "footprint", NULL);
            cgs_json_add (o, "footprint_display", NULL);
        }
        cgs_json_add (o, "scale",
                      json_object_new_int64 (x->scale == 5 || x->scale == 10 ? x->scale : 1));
        cgs_json_add (o, "waypoint", x->has_waypoint ? s_xy (x->waypoint) : NULL);
        cgs_json_add (o, "secondary", x->has_secondary ? s_xy (x->secondary) : NULL);
        cgs_json_add (o, "time_to_go_s", cgs_json_fixed (x->time_to_go_s, 1));
        cgs_json_add (o, "t_pred_s", cgs_json_fixed (x->t_pred_s, 1));
        cgs_json_add (o, "replans", json_object_new_int64 (x->replans));
        cgs_json_add (o, "reason", json_object_new_string (x->reason));
        cgs_json_add (o, "target_in_footprint", json_object_new_boolean (x->target_in_footprint));
        // Ground range from the UAV to the designated track, when both are known.
        const s_uav_t *u = s_uav_find (self, x->uav_id);
        const s_track_t *t = x->track_id ? s_track_find (self, x->track_id) : NULL;
        cgs_json_add (o, "range_m", u && t ? s_m (hypot (t->e - u->e, t->n - u->n)) : NULL);
        cgs_json_add (o, "designation", json_object_new_int64 ((int64_t)x->designation));
        json_object_array_add (a, o);
    }
    return a;
}

static json_object *s_json_truth (const st_state_t *self)
{
    json_object *a = json_object_new_array ();
    size_t cursor = 0;
    const cgs_entity_state_t *s;
    while ((s = cgs_entities_next (self->truth, &cursor))) {
        if (!s->active || s_uav_find (self, s->id))
            continue;
        json_object *o = json_object_new_object ();
        cgs_json_add (o, "id", json_object_new_int64 (s->id));
        cgs_json_add (o, "marking", json_object_new_string (s->marking));
        cgs_json_add (o, "force", json_object_new_string (s_force_name (s->force)));
        cgs_json_add (o, "kind", json_object_new_string (s_kind_name (s->kind)));
        cgs_json_add (o, "e", s_m (s->position.e_m));
        cgs_json_add (o, "n", s_m (s->position.n_m));
        cgs_json_add (o, "heading_deg", cgs_json_fixed (s->heading_deg, 1));
        cgs_json_add (o, "speed_mps", cgs_json_fixed (hypot (s->velocity.e_m, s->velocity.n_m), 1));
        cgs_json_add (o, "external", json_object_new_boolean (s->external));
        json_object_array_add (a, o);
    }
    return a;
}

static json_object *s_json_image (const st_state_t *self)
{
    if (!self->has_image || !self->image_shown)
        return NULL;
    json_object *o = json_object_new_object ();
    char url[96];
    snprintf (url, sizeof url, "/image/latest.png?frame=%llu",
              (unsigned long long)self->image_shown_frame);
    cgs_json_add (o, "uav_id", json_object_new_int64 (self->image_uav));
    cgs_json_add (o, "frame", json_object_new_int64 ((int64_t)self->image_shown_frame));
    cgs_json_add (o, "url", json_object_new_string (url));
    cgs_json_add (o, "mode",
                  json_object_new_string (self->image_mode == CGS__IMAGE_MODE__IMAGE_MODE_INFRARED
                                              ? "infrared"
                                              : "visible"));
    cgs_json_add (o, "target_in_view", json_object_new_boolean (self->image_target_in_view));
    return o;
}

char *st_state_json (st_state_t *self, uint64_t seq, size_t *ret_len)
{
    json_object *o = json_object_new_object ();
    if (!o)
        return NULL;
    cgs_json_add (o, "type", json_object_new_string ("state"));
    cgs_json_add (o, "seq", json_object_new_int64 ((int64_t)seq));
    cgs_json_add (o, "sim_time_s", cgs_json_fixed (self->now_s, 2));
    cgs_json_add (o, "uavs", s_json_uavs (self));
    cgs_json_add (o, "hits", s_json_hits (self));
    cgs_json_add (o, "bcis", s_json_bcis (self));
    cgs_json_add (o, "tracks", s_json_tracks (self));
    cgs_json_add (o, "intercepts", s_json_intercepts (self));
    cgs_json_add (o, "truth", s_json_truth (self));
    cgs_json_add (o, "image", s_json_image (self));
    size_t len = 0;
    const char *text = json_object_to_json_string_length (o, JSON_C_TO_STRING_PLAIN, &len);
    char *out = text ? malloc (len + 1) : NULL;
    if (out) {
        memcpy (out, text, len + 1);
        if (ret_len)
            *ret_len = len;
    }
    json_object_put (o);
    return out;
}
