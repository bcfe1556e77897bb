/* st_state — the tactical map's picture (see st_state.h): what is kept of
 * each topic and for how long. Its JSON view is st_view.c; the tables both
 * read are in st_state_impl.h. */
#include "st_state.h"
#include "st_state_impl.h"

#include "cgs_entities.h"
#include "cgs_json.h"

#include <errno.h>
#include <json-c/json.h>
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

st_state_t *st_state_new (const st_state_params_t *p)
{
    st_state_t *self = calloc (1, sizeof *self);
    if (!self)
        return NULL;
    self->p = *p;
    if (self->p.history_scans < 0)
        self->p.history_scans = 0;
    self->bcis = malloc (ST_BCIS_MAX * sizeof *self->bcis);
    self->truth = cgs_entities_new ();
    if (!self->bcis || !self->truth)
        st_state_destroy (&self);
    return self;
}

static void s_radar_free (st_radar_t *r)
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
    for (size_t i = 0; i < ST_UAVS_MAX; i++)
        free (self->intercepts[i].route);
    free (self->bcis);
    free (self->tracks);
    cgs_entities_destroy (&self->truth);
    json_object_put (self->replay);
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
    for (int i = 0; i < ST_UAVS_MAX; i++) {
        self->uavs[i].heard_s = fmin (self->uavs[i].heard_s, t_s);
        self->intercepts[i].heard_s = fmin (self->intercepts[i].heard_s, t_s);
        self->sensor_modes[i].heard_s = fmin (self->sensor_modes[i].heard_s, t_s);
    }
    self->video_heard_s = fmin (self->video_heard_s, t_s);
}

int st_state_take_replay (st_state_t *self, const Cgs__ReplayState *m, bool *ret_new)
{
    if (ret_new)
        *ret_new = false;
    if (!isfinite (m->t_s) || !isfinite (m->span_s) || m->span_s < 0 || !isfinite (m->speed) ||
        !isfinite (m->sim_time_s))
        return -EINVAL;
    json_object *o = json_object_new_object ();
    json_object *marks = json_object_new_array ();
    if (!o || !marks) {
        json_object_put (o);
        json_object_put (marks);
        return -ENOMEM;
    }
    cgs_json_add (o, "file", json_object_new_string (m->file ? m->file : ""));
    cgs_json_add (o, "t_s", cgs_json_fixed (m->t_s, 2));
    cgs_json_add (o, "span_s", cgs_json_fixed (m->span_s, 2));
    cgs_json_add (o, "speed", cgs_json_fixed (m->speed, 3));
    cgs_json_add (o, "paused", json_object_new_boolean (m->paused));
    cgs_json_add (o, "ended", json_object_new_boolean (m->ended));
    cgs_json_add (o, "generation", json_object_new_int64 (m->generation));
    cgs_json_add (o, "sim_time_s", cgs_json_fixed (m->sim_time_s, 2));
    cgs_json_add (o, "recorded_exercise_id", json_object_new_int64 (m->recorded_exercise_id));
    for (size_t i = 0; i < m->n_marks; i++) {
        const Cgs__ReplayMark *k = m->marks[i];
        if (!isfinite (k->t_s))
            continue;
        json_object *j = json_object_new_object ();
        cgs_json_add (j, "t_s", cgs_json_fixed (k->t_s, 2));
        cgs_json_add (j, "kind", json_object_new_string (k->kind ? k->kind : ""));
        cgs_json_add (j, "text", json_object_new_string (k->text ? k->text : ""));
        json_object_array_add (marks, j);
    }
    cgs_json_add (o, "marks", marks);
    bool fresh = self->replay && m->generation != self->replay_generation;
    json_object_put (self->replay);
    self->replay = o;
    self->replay_generation = m->generation;
    if (ret_new)
        *ret_new = fresh;
    return 0;
}

void st_state_set_time_scale (st_state_t *self, double time_scale, bool paused)
{
    self->time_scale = isfinite (time_scale) && time_scale > 0 ? time_scale : 0;
    self->paused = paused;
}

double st_state_time (const st_state_t *self)
{
    return self->now_s;
}

/* ---- UAVs and intercepts ---------------------------------------------------------- */

/* The slot of a UAV's id in a table of ST_UAVS_MAX (found, or the first free),
 * or -1 when the table is full. */
static int s_uav_slot (const st_state_t *self, uint32_t id)
{
    int free_slot = -1;
    for (int i = 0; i < ST_UAVS_MAX; i++) {
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
    st_uav_t *u = &self->uavs[i];
    *u = (st_uav_t){.valid = true, .id = m->entity_id, .heard_s = self->now_s};
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
    const Cgs__ImagingSensor *c = m->sensor;
    if (c) {
        // Values that are not finite are shown as unknown (null).
        u->has_camera = true;
        u->camera = (st_camera_t){.depression_deg = c->depression_deg,
                                  .hfov_deg = c->hfov_deg,
                                  .vfov_deg = c->vfov_deg,
                                  .stabilized = c->stabilized,
                                  .stare = c->stare,
                                  .has_point = s_enu_ok (c->stare_point),
                                  .staring = c->staring,
                                  .at_limit = c->at_gimbal_limit,
                                  .az_limit_deg = c->gimbal_azimuth_limit_deg,
                                  .el_min_deg = c->gimbal_elevation_min_deg,
                                  .el_max_deg = c->gimbal_elevation_max_deg};
        if (u->camera.has_point)
            u->camera.point = (st_xy_t){c->stare_point->east_m, c->stare_point->north_m};
    }
    return 0;
}

static int s_intercept_slot (const st_state_t *self, uint32_t uav_id)
{
    int free_slot = -1;
    for (int i = 0; i < ST_UAVS_MAX; i++) {
        if (self->intercepts[i].valid && self->intercepts[i].uav_id == uav_id)
            return i;
        if (!self->intercepts[i].valid && free_slot < 0)
            free_slot = i;
    }
    return free_slot;
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
    st_intercept_t *x = &self->intercepts[slot];
    if (m->n_route > x->route_cap) {
        st_xy_t *r = realloc (x->route, m->n_route * sizeof *r);
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
        x->route[i] = (st_xy_t){m->route[i]->east_m, m->route[i]->north_m};
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
        x->waypoint = (st_xy_t){m->waypoint->east_m, m->waypoint->north_m};
    x->has_secondary = m->has_secondary && s_enu_ok (m->secondary_waypoint);
    if (x->has_secondary)
        x->secondary = (st_xy_t){m->secondary_waypoint->east_m, m->secondary_waypoint->north_m};
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

static st_radar_t *s_radar (st_state_t *self, uint32_t uav_id, uint64_t epoch, int *ret_rc)
{
    *ret_rc = 0;
    st_radar_t *r = NULL;
    for (size_t i = 0; i < self->radar_count; i++)
        if (self->radars[i].uav_id == uav_id)
            r = &self->radars[i];
    if (!r) {
        if (self->radar_count == ST_RADARS_MAX) {
            *ret_rc = -ENOSPC;
            return NULL;
        }
        st_scan_t *scans = calloc ((size_t)self->p.history_scans + 2, sizeof *scans);
        if (!scans) {
            *ret_rc = -ENOMEM;
            return NULL;
        }
        r = &self->radars[self->radar_count++];
        *r = (st_radar_t){.uav_id = uav_id, .epoch = epoch, .scans = scans};
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
static st_scan_t *s_scan (st_state_t *self, st_radar_t *r, uint32_t number)
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
    st_scan_t *s = &r->scans[r->count++];
    *s = (st_scan_t){.number = number};
    return s;
}

/* Keep at most history_scans complete scans behind the newest complete one
 * (and any scan in progress after it). */
static void s_trim (st_state_t *self, st_radar_t *r)
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
    st_radar_t *r = s_radar (self, m->uav_id, hdr ? hdr->epoch : 0, &rc);
    if (!r)
        return rc;
    st_scan_t *s = s_scan (self, r, m->scan_number);
    if (!s)
        return 0;
    if (s->count + m->n_hits > s->cap) {
        size_t cap = s->cap ? s->cap : 64;
        while (cap < s->count + m->n_hits)
            cap *= 2;
        st_hit_t *h = realloc (s->hits, cap * sizeof *h);
        if (!h)
            return -ENOMEM;
        s->hits = h;
        s->cap = cap;
    }
    for (size_t i = 0; i < m->n_hits; i++)
        s->hits[s->count++] = (st_hit_t){m->hits[i]->position->east_m,
                                         m->hits[i]->position->north_m, m->hits[i]->hit_id};
    s_trim (self, r);
    return 0;
}

int st_state_take_mti_scan (st_state_t *self, const Cgs__MtiScan *m, const Cgs__Header *hdr)
{
    if (!m || m->uav_id == 0)
        return -EINVAL;
    int rc;
    s_time_from (self, hdr);
    st_radar_t *r = s_radar (self, m->uav_id, hdr ? hdr->epoch : 0, &rc);
    if (!r)
        return rc;
    st_scan_t *s = s_scan (self, r, m->scan_number);
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
        if (self->bcis_count == ST_BCIS_MAX) {
            memmove (&self->bcis[0], &self->bcis[1], (ST_BCIS_MAX - 1) * sizeof self->bcis[0]);
            self->bcis_count--;
        }
        st_bcis_t *b = &self->bcis[self->bcis_count++];
        *b = (st_bcis_t){.uav_id = m->uav_id,
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

st_track_t *st_state__track_find (st_state_t *self, uint32_t id)
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
        st_track_t *k = st_state__track_find (self, t->track_id);
        if (t->status == CGS__TRACK_STATUS__TRACK_STATUS_DELETED) {
            if (k)
                s_track_remove (self, (size_t)(k - self->tracks));
            continue;
        }
        if (!k) {
            if (self->track_count == self->track_cap) {
                size_t cap = self->track_cap ? 2 * self->track_cap : 256;
                st_track_t *a = realloc (self->tracks, cap * sizeof *a);
                if (!a)
                    return -ENOMEM;
                self->tracks = a;
                self->track_cap = cap;
            }
            k = &self->tracks[self->track_count++];
        }
        *k = (st_track_t){.id = t->track_id,
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
                k->last_hit = (st_xy_t){h->position->east_m, h->position->north_m};
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

/* The footprint of an image message of the picture's UAV (any UAV's
 * before a picture is shown): kept when it has four finite corners. */
static void s_image_footprint (st_state_t *self, const Cgs__Image *m)
{
    if (self->has_image && m->uav_id != self->image_uav)
        return;
    const Cgs__Footprint *f = m->footprint;
    if (!f || f->n_corners != 4) {
        self->has_image_fp = false;
        return;
    }
    double c[8];
    for (size_t i = 0; i < 4; i++) {
        if (!f->corners[i] || !isfinite (f->corners[i]->east_m) ||
            !isfinite (f->corners[i]->north_m)) {
            self->has_image_fp = false;
            return;
        }
        c[2 * i] = f->corners[i]->east_m;
        c[2 * i + 1] = f->corners[i]->north_m;
    }
    memcpy (self->image_fp, c, sizeof c);
    self->image_fp_frame = m->frame_number;
    self->has_image_fp = true;
}

/* The mode of the UAV's sensor, from each of its image messages (a full
 * table forgets nothing: the mode of a UAV beyond it is not shown). */
static void s_sensor_mode (st_state_t *self, const Cgs__Image *m)
{
    if (m->uav_id == 0)
        return;
    st_sensor_mode_t *free_slot = NULL;
    for (int i = 0; i < ST_UAVS_MAX; i++) {
        st_sensor_mode_t *s = &self->sensor_modes[i];
        if (s->valid && s->uav_id == m->uav_id) {
            free_slot = s;
            break;
        }
        if (!s->valid && !free_slot)
            free_slot = s;
    }
    if (free_slot)
        *free_slot = (st_sensor_mode_t){
            .valid = true, .uav_id = m->uav_id, .mode = m->mode, .heard_s = self->now_s};
}

int st_state_take_image (st_state_t *self, const Cgs__Image *m, const Cgs__Header *hdr)
{
    if (!m)
        return -EINVAL;
    s_time_from (self, hdr);
    s_sensor_mode (self, m);
    if (!m->latest_path || !m->latest_path[0]) {
        s_image_footprint (self, m);
        return 0; // a frame that did not refresh latest.png: nothing new to show
    }
    if (strlen (m->latest_path) >= sizeof self->image_path || m->latest_path[0] != '/')
        return -EINVAL;
    self->has_image = true;
    self->image_uav = m->uav_id;
    self->image_frame = m->frame_number;
    self->image_mode = m->mode;
    self->image_target_in_view = m->target_in_view;
    snprintf (self->image_path, sizeof self->image_path, "%s", m->latest_path);
    s_image_footprint (self, m);
    return 0;
}

/* ---- video ------------------------------------------------------------------------ */

#define S_TS_PACKET 188 // bytes of an MPEG transport stream packet
#define S_TS_SYNC   0x47

int st_state_take_video (st_state_t *self, const Cgs__VideoFrame *m, const Cgs__Header *hdr,
                         bool *ret_relay, bool *ret_restart)
{
    if (!m || !m->ts.data || m->ts.len == 0 || m->ts.len % S_TS_PACKET != 0)
        return -EINVAL;
    for (size_t i = 0; i < m->ts.len; i += S_TS_PACKET)
        if (m->ts.data[i] != S_TS_SYNC)
            return -EINVAL;
    s_time_from (self, hdr);
    uint32_t want = self->has_image   ? self->image_uav
                    : self->has_video ? self->video_uav
                                      : m->uav_id;
    if (m->uav_id != want) {
        *ret_relay = false;
        *ret_restart = false;
        return 0;
    }
    uint64_t epoch = hdr ? hdr->epoch : 0;
    // Another stream than the pages have: another UAV's, a restarted
    // imagerd's, or one that went stale and came back.
    bool restart = self->video_ever && (!self->has_video || self->video_uav != want ||
                                        (epoch && self->video_epoch && epoch != self->video_epoch));
    if (restart || !self->has_video) {
        self->video_frames = 0;
        self->video_t_s = NAN;
        self->video_period_s = 0;
    }
    // The frames' spacing, for the page's buffer: a moving mean of the steps
    // between frames (a step over a gap or back in time is not one).
    double t = hdr && isfinite (hdr->sim_time_s) ? hdr->sim_time_s : NAN;
    double step = t - self->video_t_s;
    if (step > 0 && (self->video_period_s == 0 || step < 4 * self->video_period_s))
        self->video_period_s =
            self->video_period_s == 0 ? step : 0.8 * self->video_period_s + 0.2 * step;
    if (isfinite (t))
        self->video_t_s = t;
    self->has_video = self->video_ever = true;
    self->video_uav = want;
    if (epoch)
        self->video_epoch = epoch;
    self->video_frames++;
    self->video_heard_s = self->now_s;
    *ret_relay = true;
    *ret_restart = restart;
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
        st_radar_t *r = &self->radars[i];
        if (now - r->heard_s > self->p.track_stale_s) {
            for (size_t j = 0; j < r->count; j++)
                free (r->scans[j].hits);
            memset (r->scans, 0, ((size_t)self->p.history_scans + 2) * sizeof *r->scans);
            r->count = 0;
        }
    }
    for (int i = 0; i < ST_UAVS_MAX; i++) {
        if (self->uavs[i].valid && now - self->uavs[i].heard_s > self->p.track_stale_s)
            self->uavs[i].valid = false;
        if (self->intercepts[i].valid && now - self->intercepts[i].heard_s > self->p.track_stale_s)
            self->intercepts[i].valid = false;
        if (self->sensor_modes[i].valid &&
            now - self->sensor_modes[i].heard_s > self->p.track_stale_s)
            self->sensor_modes[i].valid = false; // its imagerd stopped
    }
    if (self->has_video && now - self->video_heard_s > self->p.track_stale_s)
        self->has_video = false; // its imagerd stopped: a new stream will start over
    cgs_entities_evict (self->truth, now, self->p.truth_stale_s);
}
