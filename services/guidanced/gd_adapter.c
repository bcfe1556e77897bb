/* gd_adapter — guidanced's track table, intercepts per UAV, operator
 * commands and script, `intercept` messages, task bookkeeping and state
 * (see gd_adapter.h). */
#include "gd_adapter.h"

#include "cgs_ckpt.h"
#include "cgs_cmd.h"
#include "cgs_util.h"
#include "gd_checkpoint.h"

#include <assert.h>
#include <errno.h>
#include <inttypes.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <syslog.h>

#define S_STATE_MAGIC   "GDST" // cgs_ckpt kind of guidanced's state
#define S_STATE_VERSION 1u
#define S_STATE_WHAT    "guidanced state"
#define S_TIME_BACK_S   1.0 // simulation time this far behind the latest heard: it went back

const char *const gd_adapter_topics[] = {"uav", "track", "track.turn", NULL};

typedef struct {
    uint32_t entity_id;
    char name[64];
    gd_intercept_t *core;
    uint64_t delivered;    // task number uavsim has answered
    uint64_t pending_task; // task number being delivered
    uint64_t pending_seq;  // the command number it goes under
    int logged_phase;      // phase, re-plans, track and reason last written to the log
    uint32_t logged_replans;
    uint32_t logged_track;
    uint64_t logged_designation;
    char logged_reason[160];
} s_uav_t;

struct gd_adapter {
    gd_params_t params;
    const cgs_scenario_t *scenario; // the caller's
    const cgs_terrain_t *terrain;   // the caller's; NULL: flat ground at 0
    cgs_port_t port;
    s_uav_t uavs[GD_ADAPTER_UAVS_MAX];
    size_t uav_count;
    // Tracks as last heard.
    gd_track_t *tracks;
    size_t track_count, track_cap;
    bool heard_tracks; // a track batch with a time has come
    // Numbering of the commands to uavsim.
    char client_id[128];
    uint64_t send_seq; // the last command number used
    // The operator's script.
    size_t script_done;  // lines done (run or skipped)
    bool operator_acted; // an operator designated or cancelled
    bool script_waiting_logged;
    double sim_time_s; // latest heard
    bool dirty;        // state to save (gd_adapter_take_dirty)
    char detail[512];  // the latest reply's text
    // The intercept message being built.
    Cgs__Enu route_pts[GD_ROUTE_MAX];
    Cgs__Enu *route_ptr[GD_ROUTE_MAX];
    // The task command being built (gd_adapter_next_task).
    Cgs__Command task_cmd;
    Cgs__TaskRoute task_route;
    Cgs__Loiter task_loiter;
    Cgs__Enu task_pts[GD_ROUTE_MAX];
    Cgs__Enu *task_ptr[GD_ROUTE_MAX];
};

gd_adapter_t *gd_adapter_new (const gd_params_t *params, const cgs_scenario_t *scenario,
                              const cgs_terrain_t *terrain, const cgs_port_t *port,
                              bool *ret_too_many)
{
    if (ret_too_many)
        *ret_too_many = false;
    if (scenario->uav_count > GD_ADAPTER_UAVS_MAX) {
        if (ret_too_many)
            *ret_too_many = true;
        return NULL;
    }
    gd_adapter_t *self = calloc (1, sizeof *self);
    if (!self)
        return NULL;
    self->params = *params;
    self->scenario = scenario;
    self->terrain = terrain;
    if (port)
        self->port = *port;
    snprintf (self->client_id, sizeof self->client_id, "guidanced");
    for (size_t i = 0; i < scenario->uav_count; i++) {
        s_uav_t *u = &self->uavs[self->uav_count];
        u->entity_id = scenario->uavs[i].id;
        snprintf (u->name, sizeof u->name, "%s", scenario->uavs[i].name);
        u->core = gd_intercept_new (&self->params, terrain);
        if (!u->core)
            goto fail;
        self->uav_count++;
    }
    return self;
fail:
    gd_adapter_destroy (&self);
    return NULL;
}

void gd_adapter_destroy (gd_adapter_t **self_p)
{
    if (!self_p || !*self_p)
        return;
    gd_adapter_t *self = *self_p;
    for (size_t i = 0; i < self->uav_count; i++)
        gd_intercept_destroy (&self->uavs[i].core);
    free (self->tracks);
    free (self);
    *self_p = NULL;
}

/* The UAV of entity id, or the only one for id 0 when there is one. */
static s_uav_t *s_uav_by_id (gd_adapter_t *self, uint32_t id)
{
    if (id == 0)
        return self->uav_count == 1 ? &self->uavs[0] : NULL;
    for (size_t i = 0; i < self->uav_count; i++)
        if (self->uavs[i].entity_id == id)
            return &self->uavs[i];
    return NULL;
}

static double s_height (const gd_adapter_t *self, gd_v2_t p)
{
    return self->terrain ? cgs_terrain_height_clamped (self->terrain, p.e, p.n) : 0.0;
}

static void s_enu (const gd_adapter_t *self, Cgs__Enu *m, gd_v2_t p)
{
    cgs__enu__init (m);
    m->east_m = p.e;
    m->north_m = p.n;
    m->up_m = s_height (self, p);
}

/* ---- publication ------------------------------------------------------------------------ */

/* Log u's changes of phase, plan, track and reason, then publish its `intercept`. */
static void s_publish (gd_adapter_t *self, s_uav_t *u)
{
    gd_status_t st;
    gd_intercept_status (u->core, &st);
    if (st.track_id != u->logged_track && u->logged_track != 0 && st.track_id != 0 &&
        st.designation_number == u->logged_designation)
        cgs_port_log (&self->port, LOG_NOTICE,
                      "%s: hand-over, t=%.1f s: track %u was deleted; its target goes on as "
                      "track %u",
                      u->name, self->sim_time_s, u->logged_track, st.track_id);
    if ((int)st.phase != u->logged_phase || st.replans != u->logged_replans ||
        st.track_id != u->logged_track || strcmp (st.reason, u->logged_reason) != 0) {
        cgs_port_log (&self->port, LOG_NOTICE, "%s: %s, track %u, t=%.1f s: %s", u->name,
                      gd_phase_name (st.phase), st.track_id, self->sim_time_s, st.reason);
        u->logged_phase = (int)st.phase;
        u->logged_replans = st.replans;
        u->logged_track = st.track_id;
        u->logged_designation = st.designation_number;
        snprintf (u->logged_reason, sizeof u->logged_reason, "%s", st.reason);
    }
    Cgs__Intercept m;
    cgs__intercept__init (&m);
    m.uav_id = u->entity_id;
    m.track_id = st.track_id;
    m.state = (Cgs__InterceptState)st.phase;
    m.method = (Cgs__InterceptMethod)st.method;
    Cgs__Enu wp, sec, corners[4], centre;
    Cgs__Enu *cptr[4];
    Cgs__Footprint fp;
    if (st.has_plan) {
        s_enu (self, &wp, st.waypoint);
        m.waypoint = &wp;
        m.t_pred_s = st.t_pred_s;
        if (st.has_secondary) {
            s_enu (self, &sec, st.secondary);
            m.secondary_waypoint = &sec;
            m.has_secondary = true;
        }
    }
    size_t n = st.route_count < GD_ROUTE_MAX ? st.route_count : GD_ROUTE_MAX;
    for (size_t k = 0; k < n; k++) {
        s_enu (self, &self->route_pts[k], st.route[k]);
        self->route_ptr[k] = &self->route_pts[k];
    }
    m.n_route = n;
    m.route = self->route_ptr;
    if (st.has_footprint) {
        cgs__footprint__init (&fp);
        for (int k = 0; k < 4; k++) {
            cgs__enu__init (&corners[k]);
            corners[k].east_m = st.footprint.corner[k].e;
            corners[k].north_m = st.footprint.corner[k].n;
            corners[k].up_m = st.footprint.corner_up_m[k];
            cptr[k] = &corners[k];
        }
        cgs__enu__init (&centre);
        centre.east_m = st.footprint.center.e;
        centre.north_m = st.footprint.center.n;
        centre.up_m = st.footprint.center_up_m;
        fp.n_corners = 4;
        fp.corners = cptr;
        fp.center = &centre;
        fp.display_scale = st.display_scale;
        m.footprint = &fp;
    }
    m.target_in_footprint = st.target_in_footprint;
    m.time_to_go_s = isfinite (st.time_to_go_s) ? st.time_to_go_s : -1;
    m.replans = st.replans;
    m.reason = (char *)st.reason;
    m.designation_number = st.designation_number;
    Cgs__Enu target;
    Cgs__EnuVelocity target_vel;
    if (st.has_target) {
        // At the message's time: where a camera staring at the target looks.
        s_enu (self, &target,
               gd_add (st.target, gd_scale (st.target_vel, self->sim_time_s - st.target_t_s)));
        cgs__enu_velocity__init (&target_vel);
        target_vel.east_mps = st.target_vel.e;
        target_vel.north_mps = st.target_vel.n;
        m.has_target = true;
        m.target = &target;
        m.target_velocity = &target_vel;
    }
    cgs_port_publish (&self->port, "intercept", &m.base, self->sim_time_s);
}

/* ---- tracks ------------------------------------------------------------------------------ */

static gd_track_t *s_track_find (gd_adapter_t *self, uint32_t id)
{
    for (size_t i = 0; i < self->track_count; i++)
        if (self->tracks[i].id == id)
            return &self->tracks[i];
    return NULL;
}

static void s_track_forget (gd_adapter_t *self, uint32_t id)
{
    for (size_t i = 0; i < self->track_count; i++)
        if (self->tracks[i].id == id) {
            self->tracks[i] = self->tracks[self->track_count - 1];
            self->track_count--;
            return;
        }
}

/* Track id's place in the table, new when it is not there; NULL without memory. */
static gd_track_t *s_track_slot (gd_adapter_t *self, uint32_t id)
{
    gd_track_t *t = s_track_find (self, id);
    if (t)
        return t;
    if (self->track_count == self->track_cap) {
        size_t cap = self->track_cap ? self->track_cap * 2 : 64;
        gd_track_t *nt = realloc (self->tracks, cap * sizeof *nt);
        if (!nt)
            return NULL;
        self->tracks = nt;
        self->track_cap = cap;
    }
    return &self->tracks[self->track_count++];
}

/* A track message as the intercept takes it; false when it is unusable. */
static bool s_track_from_msg (const Cgs__Track *m, double t_s, gd_track_t *ret)
{
    if (!m->track_id || !m->position || !m->velocity || !isfinite (m->position->east_m) ||
        !isfinite (m->position->north_m) || !isfinite (m->velocity->east_mps) ||
        !isfinite (m->velocity->north_mps) || !isfinite (t_s) ||
        (int)m->status > (int)CGS_TRACK_STATUS_MAX)
        return false;
    ret->id = m->track_id;
    ret->status = (int)m->status;
    ret->friendly = m->identity == CGS__TRACK_IDENTITY__TRACK_IDENTITY_FRIENDLY;
    ret->t_s = t_s;
    ret->pos = gd_v2 (m->position->east_m, m->position->north_m);
    ret->vel = gd_v2 (m->velocity->east_mps, m->velocity->north_mps);
    ret->hits = m->hit_count;
    ret->last_hit_s = isfinite (m->last_hit_time_s) ? m->last_hit_time_s : NAN;
    ret->continues = m->continues;
    ret->radar_id = m->uav_id;
    ret->last_scan = m->last_scan_number;
    ret->continues_p = isfinite (m->continues_probability) ? m->continues_probability : 0;
    // Covariance: 4 × 4 row-major over (east, north, v_east, v_north).
    const double *P = m->covariance;
    ret->has_cov = m->n_covariance == 16 && isfinite (P[0]) && isfinite (P[1]) && isfinite (P[5]) &&
                   isfinite (P[10]) && isfinite (P[11]) && isfinite (P[15]) && P[0] >= 0 &&
                   P[5] >= 0 && P[10] >= 0 && P[15] >= 0;
    if (ret->has_cov) {
        ret->pos_cov[0] = P[0];
        ret->pos_cov[1] = P[1];
        ret->pos_cov[2] = P[5];
        ret->vel_cov[0] = P[10];
        ret->vel_cov[1] = P[11];
        ret->vel_cov[2] = P[15];
    }
    size_t n = m->n_history, skip = n > GD_HISTORY_MAX ? n - GD_HISTORY_MAX : 0;
    ret->history_count = 0;
    for (size_t k = skip; k < n; k++) {
        const Cgs__TrackHistoryPoint *h = m->history[k];
        if (!h->position || !isfinite (h->position->east_m) || !isfinite (h->position->north_m))
            continue;
        ret->history[ret->history_count] = gd_v2 (h->position->east_m, h->position->north_m);
        ret->history_hit_id[ret->history_count] = h->hit_id;
        ret->history_scan[ret->history_count] = h->scan_number;
        ret->history_t_s[ret->history_count++] = h->sim_time_s;
    }
    return true;
}

/* ---- the operator's script ------------------------------------------------------------- */

/* The scenario's `[operator]` lines whose time has come, while no operator
 * has designated: the nearest qualifying track is designated for the first
 * UAV (or the line waits for one); after an operator's designation the
 * lines are skipped. Each line done makes the state dirty. */
static void s_run_script (gd_adapter_t *self)
{
    const cgs_scenario_t *sc = self->scenario;
    while (self->script_done < sc->designation_count && self->uav_count > 0) {
        const cgs_designation_t *d = &sc->designations[self->script_done];
        if (self->sim_time_s < d->time_s)
            return;
        if (self->operator_acted) {
            cgs_port_log (&self->port, LOG_NOTICE,
                          "operator script line %d skipped: an operator designated already",
                          d->line);
            self->script_done++;
            self->dirty = true;
            continue;
        }
        gd_pick_t pick = d->pick == CGS_PICK_UNKNOWN    ? GD_PICK_UNKNOWN
                         : d->pick == CGS_PICK_FRIENDLY ? GD_PICK_FRIENDLY
                                                        : GD_PICK_ANY;
        double dist = 0;
        int i = gd_pick_nearest (self->tracks, self->track_count, gd_v2 (d->near.e_m, d->near.n_m),
                                 pick, &dist);
        if (i < 0 || dist > self->params.pick_radius_m) {
            if (!self->script_waiting_logged)
                cgs_port_log (&self->port, LOG_INFO,
                              "operator script line %d: no track qualifies within %.0f m of "
                              "(%.0f, %.0f) yet; waiting",
                              d->line, self->params.pick_radius_m, d->near.e_m, d->near.n_m);
            self->script_waiting_logged = true;
            return;
        }
        s_uav_t *u = &self->uavs[0];
        char why[256];
        if (gd_intercept_designate (u->core, &self->tracks[i], self->sim_time_s, why, sizeof why) <
            0) {
            cgs_port_log (&self->port, LOG_WARNING, "operator script line %d: %s", d->line, why);
        } else {
            cgs_port_log (&self->port, LOG_NOTICE,
                          "operator script line %d: %s designates track %u, %.0f m from (%.0f, "
                          "%.0f), at t=%.1f s",
                          d->line, u->name, self->tracks[i].id, dist, d->near.e_m, d->near.n_m,
                          self->sim_time_s);
        }
        self->script_done++;
        self->script_waiting_logged = false;
        self->dirty = true;
        s_publish (self, u);
    }
}

/* ---- inputs ------------------------------------------------------------------------------ */

static void s_on_track (gd_adapter_t *self, const Cgs__TrackBatch *b, const Cgs__Header *hdr)
{
    double t = hdr ? hdr->sim_time_s : NAN;
    if (!isfinite (t)) {
        cgs_port_bad_input (&self->port, "a track batch without a simulation time");
        return;
    }
    if (t > self->sim_time_s)
        self->sim_time_s = t;
    for (size_t i = 0; i < b->n_tracks; i++) {
        gd_track_t tr;
        if (!s_track_from_msg (b->tracks[i], t, &tr)) {
            cgs_port_bad_input (&self->port, "a track without an id, a valid position or velocity");
            continue;
        }
        tr.linked = b->links_continuation;
        for (size_t k = 0; k < self->uav_count; k++)
            gd_intercept_track (self->uavs[k].core, &tr);
        if (tr.status == CGS_TRACK_DELETED) {
            s_track_forget (self, tr.id);
            continue;
        }
        gd_track_t *slot = s_track_slot (self, tr.id);
        if (!slot) {
            cgs_port_error (&self->port, "out of memory: a track was not kept");
            continue;
        }
        *slot = tr;
    }
    self->heard_tracks = true;
    s_run_script (self);
    for (size_t k = 0; k < self->uav_count; k++)
        s_publish (self, &self->uavs[k]);
}

static void s_on_turn (gd_adapter_t *self, const Cgs__TrackTurn *m)
{
    if (!m->track_id || !m->velocity_after || !isfinite (m->sim_time_s) ||
        !isfinite (m->velocity_after->east_mps) || !isfinite (m->velocity_after->north_mps)) {
        cgs_port_bad_input (&self->port, "a turn event without a track, time or velocity");
        return;
    }
    gd_v2_t v = gd_v2 (m->velocity_after->east_mps, m->velocity_after->north_mps);
    for (size_t k = 0; k < self->uav_count; k++)
        gd_intercept_turn (self->uavs[k].core, m->track_id, m->sim_time_s, v, m->turn_angle_deg);
}

static void s_on_uav (gd_adapter_t *self, const Cgs__Uav *m, const Cgs__Header *hdr)
{
    s_uav_t *u = s_uav_by_id (self, m->entity_id);
    if (!u || m->entity_id == 0)
        return; // a UAV of another scenario or exercise: not ours
    const Cgs__Enu *p = m->position;
    const Cgs__ImagingSensor *sn = m->sensor;
    if (!hdr || !p || !isfinite (p->east_m) || !isfinite (p->north_m) || !isfinite (p->up_m) ||
        !isfinite (m->heading_deg) || !isfinite (m->pitch_deg) || !isfinite (m->roll_deg) ||
        !isfinite (m->ground_speed_mps) || !isfinite (m->airspeed_mps) ||
        !isfinite (m->commanded_airspeed_mps) || !isfinite (hdr->sim_time_s) || !sn ||
        !(sn->depression_deg > 0 && sn->depression_deg < 90) ||
        !(sn->hfov_deg > 0 && sn->hfov_deg < 180) || !(sn->vfov_deg > 0 && sn->vfov_deg < 180)) {
        cgs_port_bad_input (&self->port,
                            "a uav message without a valid position, attitude, speed, time or "
                            "imaging sensor (depression in (0, 90), fields of view in (0, 180) "
                            "degrees)");
        return;
    }
    double t = hdr->sim_time_s;
    if (t < self->sim_time_s - S_TIME_BACK_S) {
        // uavsim resumed from its saved state: the intercepts forget what
        // they heard of the time that did not happen.
        cgs_port_log (&self->port, LOG_NOTICE,
                      "simulation time went back from %.2f to %.2f s: the intercepts take back "
                      "what they heard since",
                      self->sim_time_s, t);
        for (size_t k = 0; k < self->uav_count; k++)
            gd_intercept_time_back (self->uavs[k].core, t);
        self->sim_time_s = t;
    }
    if (t > self->sim_time_s)
        self->sim_time_s = t;
    gd_uav_t g = {
        .t_s = t,
        .position = {p->east_m, p->north_m, p->up_m},
        .heading_deg = m->heading_deg,
        .pitch_deg = m->pitch_deg,
        .roll_deg = m->roll_deg,
        .ground_speed_mps = m->ground_speed_mps,
        .airspeed_mps = m->commanded_airspeed_mps > 0 ? m->commanded_airspeed_mps : m->airspeed_mps,
        .agl_m = m->altitude_agl_m > 1 ? m->altitude_agl_m : 1,
        .commanded_agl_m = m->commanded_altitude_agl_m > 1 && isfinite (m->commanded_altitude_agl_m)
                               ? m->commanded_altitude_agl_m
                               : 0,
        .bank_limit_deg = m->bank_limit_deg,
        .depression_deg = sn->depression_deg,
        .hfov_deg = sn->hfov_deg,
        .vfov_deg = sn->vfov_deg,
    };
    cgs_camera_in_t cam = {0};
    if (cgs_msg_uav_camera (m, &cam) == 0) {
        g.camera = cam.point;
    }
    gd_intercept_uav (u->core, &g);
    s_publish (self, u);
}

/* The intercepts' changes so far (gd_intercept_changes), summed. */
static uint64_t s_changes (const gd_adapter_t *self)
{
    uint64_t n = 0;
    for (size_t i = 0; i < self->uav_count; i++)
        n += gd_intercept_changes (self->uavs[i].core);
    return n;
}

/* An intercept that changed on its own (a deletion, a hand-over, a phase or
 * a plan) makes the state dirty: what the tracker said once must survive a
 * restart. */
static void s_dirty_if_changed (gd_adapter_t *self, uint64_t before)
{
    if (s_changes (self) != before)
        self->dirty = true;
}

void gd_adapter_on_message (gd_adapter_t *self, const char *topic, const ProtobufCMessage *msg,
                            const Cgs__Header *hdr)
{
    uint64_t before = s_changes (self);
    if (strcmp (topic, "uav") == 0)
        s_on_uav (self, (const Cgs__Uav *)msg, hdr);
    else if (strcmp (topic, "track") == 0)
        s_on_track (self, (const Cgs__TrackBatch *)msg, hdr);
    else if (strcmp (topic, "track.turn") == 0)
        s_on_turn (self, (const Cgs__TrackTurn *)msg);
    s_dirty_if_changed (self, before);
}

void gd_adapter_tick (gd_adapter_t *self)
{
    uint64_t before = s_changes (self);
    for (size_t i = 0; i < self->uav_count; i++)
        gd_intercept_tick (self->uavs[i].core, self->sim_time_s);
    s_dirty_if_changed (self, before);
}

/* ---- commands ---------------------------------------------------------------------------- */

static void s_refuse (gd_adapter_t *self, Cgs__Reply *reply, const char *fmt, ...)
    __attribute__ ((format (printf, 3, 4)));
static void s_refuse (gd_adapter_t *self, Cgs__Reply *reply, const char *fmt, ...)
{
    va_list ap;
    va_start (ap, fmt);
    vsnprintf (self->detail, sizeof self->detail, fmt, ap);
    va_end (ap);
    reply->status = CGS__REPLY_STATUS__REPLY_STATUS_ERROR;
    reply->error = self->detail;
}

static s_uav_t *s_cmd_uav (gd_adapter_t *self, uint32_t id, Cgs__Reply *reply)
{
    s_uav_t *u = s_uav_by_id (self, id);
    if (!u)
        s_refuse (self, reply, "no UAV with entity id %u%s", id,
                  id == 0 ? " (give one: the scenario has several)" : "");
    return u;
}

static void s_designate (gd_adapter_t *self, const Cgs__Designate *d, Cgs__Reply *reply)
{
    s_uav_t *u = s_cmd_uav (self, d->uav_id, reply);
    if (!u)
        return;
    const gd_track_t *t = NULL;
    if (d->target_case == CGS__DESIGNATE__TARGET_TRACK_ID) {
        t = s_track_find (self, d->track_id);
        if (!t)
            return s_refuse (self, reply, "no track %u (%zu live tracks known)", d->track_id,
                             self->track_count);
    } else if (d->target_case == CGS__DESIGNATE__TARGET_POINT && d->point &&
               isfinite (d->point->east_m) && isfinite (d->point->north_m)) {
        gd_v2_t p = gd_v2 (d->point->east_m, d->point->north_m);
        double dist = 0;
        int i = gd_pick_nearest (self->tracks, self->track_count, p, GD_PICK_ANY, &dist);
        if (i < 0)
            return s_refuse (self, reply, "no confirmed track to designate");
        if (dist > self->params.pick_radius_m)
            return s_refuse (self, reply,
                             "no track's newest hit within %.0f m of (%.0f, %.0f): the nearest is "
                             "track %u, %.0f m away",
                             self->params.pick_radius_m, p.e, p.n, self->tracks[i].id, dist);
        t = &self->tracks[i];
    } else if (d->target_case == CGS__DESIGNATE__TARGET_HIT && d->hit && d->hit->hit_id) {
        // The clicked hit: exactly the track that took it, or a refusal.
        uint32_t id = d->hit->hit_id, radar = d->hit->radar_uav_id;
        size_t k = 0;
        for (size_t i = 0; i < self->track_count && !t; i++)
            if (radar == 0 || self->tracks[i].radar_id == radar)
                for (k = 0; k < self->tracks[i].history_count; k++)
                    if (self->tracks[i].history_hit_id[k] == id) {
                        t = &self->tracks[i];
                        break;
                    }
        if (!t)
            return s_refuse (self, reply,
                             "hit %u is in no track: a false alarm, or a hit no track has taken",
                             id);
        if (t->friendly)
            return s_refuse (self, reply, "hit %u is track %u's, which BCIS says is friendly", id,
                             t->id);
        if (t->status == CGS_TRACK_TENTATIVE)
            return s_refuse (self, reply,
                             "hit %u is track %u's, which is tentative (not yet "
                             "confirmed)",
                             id, t->id);
        if (t->last_scan > t->history_scan[k] + 1)
            return s_refuse (self, reply,
                             "hit %u is track %u's of scan %u, %u scans before its newest: click "
                             "its current (yellow) hit",
                             id, t->id, t->history_scan[k], t->last_scan - t->history_scan[k]);
    } else {
        return s_refuse (self, reply, "designate needs a track id, a point or a hit");
    }
    char why[256];
    if (gd_intercept_designate (u->core, t, self->sim_time_s, why, sizeof why) < 0)
        return s_refuse (self, reply, "%s", why);
    self->operator_acted = true;
    self->dirty = true;
    gd_status_t st;
    gd_intercept_status (u->core, &st);
    if (st.has_plan)
        snprintf (self->detail, sizeof self->detail,
                  "%s: %s; %s, waypoint (%.0f, %.0f), t_pred %.0f s%s", u->name, st.reason,
                  gd_phase_name (st.phase), st.waypoint.e, st.waypoint.n, st.t_pred_s,
                  st.has_secondary ? ", through a secondary waypoint" : "");
    else
        snprintf (self->detail, sizeof self->detail, "%s: %s; planned when the UAV is heard",
                  u->name, st.reason);
    reply->detail = self->detail;
}

int gd_adapter_command (gd_adapter_t *self, const Cgs__Command *cmd, Cgs__Reply *reply)
{
    s_uav_t *u = NULL;
    switch (cmd->body_case) {
    case CGS__COMMAND__BODY_DESIGNATE:
        s_designate (self, cmd->designate, reply);
        u = s_uav_by_id (self, cmd->designate->uav_id);
        break;
    case CGS__COMMAND__BODY_CANCEL:
        if (!(u = s_cmd_uav (self, cmd->cancel->uav_id, reply)))
            return 0;
        if (gd_intercept_cancel (u->core, self->sim_time_s) < 0) {
            s_refuse (self, reply, "%s: no intercept to cancel", u->name);
            return 0;
        }
        self->operator_acted = true;
        self->dirty = true;
        snprintf (self->detail, sizeof self->detail, "%s: intercept cancelled; loitering here",
                  u->name);
        reply->detail = self->detail;
        break;
    case CGS__COMMAND__BODY_SET_FOOTPRINT_SCALE:
        if (!(u = s_cmd_uav (self, cmd->set_footprint_scale->uav_id, reply)))
            return 0;
        if (gd_intercept_set_scale (u->core, cmd->set_footprint_scale->scale) < 0) {
            s_refuse (self, reply, "footprint scale must be 1, 5 or 10, got %u",
                      cmd->set_footprint_scale->scale);
            return 0;
        }
        snprintf (self->detail, sizeof self->detail, "%s: footprint shown %u times", u->name,
                  cmd->set_footprint_scale->scale);
        reply->detail = self->detail;
        break;
    case CGS__COMMAND__BODY_SET_INTERCEPT_MODE: {
        if (!(u = s_cmd_uav (self, cmd->set_intercept_mode->uav_id, reply)))
            return 0;
        int m = (int)cmd->set_intercept_mode->method;
        if (m != GD_HEAD_ON && m != GD_MTI_HITS) {
            s_refuse (self, reply, "unknown intercept method %d", m);
            return 0;
        }
        gd_intercept_set_method (u->core, (gd_method_t)m);
        snprintf (self->detail, sizeof self->detail, "%s: intercept method %s", u->name,
                  m == GD_HEAD_ON ? "head-on waypoint" : "Intercept by MTI TGT Hits");
        reply->detail = self->detail;
        break;
    }
    case CGS__COMMAND__BODY_SET_ALTITUDE:
    case CGS__COMMAND__BODY_SET_SPEED:
        return 1; // uavsim's to judge: the caller forwards it
    case CGS__COMMAND__BODY_PING:
        return 0;
    default:
        reply->status = CGS__REPLY_STATUS__REPLY_STATUS_UNSUPPORTED;
        snprintf (self->detail, sizeof self->detail, "guidanced does not handle %s",
                  cgs_cmd_name (cmd));
        reply->error = self->detail;
        return 0;
    }
    if (reply->status == CGS__REPLY_STATUS__REPLY_STATUS_OK || reply->status == 0)
        cgs_port_log (&self->port, LOG_INFO, "%s (from %s #%llu)", self->detail,
                      cmd->client_id ? cmd->client_id : "",
                      (unsigned long long)cmd->command_number);
    if (u)
        s_publish (self, u); // the task goes to uavsim at the caller's next delivery
    return 0;
}

/* ---- tasks for uavsim -------------------------------------------------------------------- */

/* The command for task t of u, in the adapter's own message buffers. */
static const Cgs__Command *s_task_command (gd_adapter_t *self, const s_uav_t *u, const gd_task_t *t)
{
    Cgs__Command *cmd = &self->task_cmd;
    cgs__command__init (cmd);
    if (t->kind == GD_TASK_ROUTE) {
        Cgs__TaskRoute *route = &self->task_route;
        cgs__task_route__init (route);
        route->uav_id = u->entity_id;
        size_t n = t->count < GD_ROUTE_MAX ? t->count : GD_ROUTE_MAX;
        for (size_t k = 0; k < n; k++) {
            s_enu (self, &self->task_pts[k], t->points[k]);
            self->task_ptr[k] = &self->task_pts[k];
        }
        route->n_waypoints = n;
        route->waypoints = self->task_ptr;
        route->loiter_at_end = true;
        cmd->body_case = CGS__COMMAND__BODY_TASK_ROUTE;
        cmd->task_route = route;
    } else {
        Cgs__Loiter *loiter = &self->task_loiter;
        cgs__loiter__init (loiter);
        loiter->uav_id = u->entity_id;
        loiter->at_present_position = true;
        loiter->clockwise = true;
        cmd->body_case = CGS__COMMAND__BODY_LOITER;
        cmd->loiter = loiter;
    }
    return cmd;
}

bool gd_adapter_next_task (gd_adapter_t *self, size_t *cursor, gd_adapter_task_t *ret)
{
    for (size_t i = *cursor; i < self->uav_count; i++) {
        s_uav_t *u = &self->uavs[i];
        const gd_task_t *t = gd_intercept_task (u->core);
        if (t->kind == GD_TASK_NONE || t->number <= u->delivered)
            continue;
        bool new_number = false;
        if (u->pending_task != t->number) {
            // Numbered once, before it is first sent: a resend after a
            // timeout or a restart is a duplicate to uavsim.
            u->pending_task = t->number;
            u->pending_seq = ++self->send_seq;
            new_number = true;
        }
        *ret = (gd_adapter_task_t){
            .command = s_task_command (self, u, t),
            .command_number = u->pending_seq,
            .task_number = t->number,
            .uav = i,
            .new_number = new_number,
        };
        *cursor = i + 1;
        return true;
    }
    *cursor = self->uav_count;
    return false;
}

void gd_adapter_task_answered (gd_adapter_t *self, const gd_adapter_task_t *task,
                               const Cgs__Reply *reply)
{
    assert (task && task->uav < self->uav_count);
    if (!reply)
        return; // tried again at the next delivery
    s_uav_t *u = &self->uavs[task->uav];
    if (reply->status == CGS__REPLY_STATUS__REPLY_STATUS_BAD_REQUEST && !reply->duplicate) {
        // The number was taken (a forwarded command used it, and the state
        // that counted it was lost in a crash): the task goes again under a
        // new number at the next delivery.
        cgs_port_log (&self->port, LOG_NOTICE,
                      "%s: task %" PRIu64 ": uavsim: %s; sending it under a new number", u->name,
                      task->task_number, reply->error ? reply->error : "bad request");
        if (u->pending_task == task->task_number)
            u->pending_task = 0;
        return;
    }
    if (reply->status != CGS__REPLY_STATUS__REPLY_STATUS_OK &&
        reply->status != CGS__REPLY_STATUS__REPLY_STATUS_NOT_SAVED) {
        char why[384];
        snprintf (why, sizeof why, "uavsim refused %s task %" PRIu64 ": %s", u->name,
                  task->task_number, reply->error ? reply->error : "no reason");
        cgs_port_log (&self->port, LOG_WARNING, "%s", why);
        cgs_port_error (&self->port, "%s", why);
    } else {
        bool route = task->command->body_case == CGS__COMMAND__BODY_TASK_ROUTE;
        cgs_port_log (&self->port, LOG_INFO, "%s: task %" PRIu64 " (%s, %zu points) delivered%s",
                      u->name, task->task_number, route ? "route" : "loiter here",
                      route ? task->command->task_route->n_waypoints : (size_t)0,
                      reply->duplicate ? " (uavsim had it already)" : "");
    }
    if (task->task_number > u->delivered)
        u->delivered = task->task_number;
}

uint64_t gd_adapter_take_number (gd_adapter_t *self)
{
    return ++self->send_seq;
}

/* ---- state --------------------------------------------------------------------------------
 * A cgs_ckpt frame "GDST", version 1: the command client id (string), the
 * last command number (u64), script lines done (u64), whether an operator
 * acted (u8), the UAV count (u32), then per UAV its entity id (u32), the
 * task numbers delivered and pending and the pending one's command number
 * (3 u64), and its intercept's own checkpoint (bytes, gd_checkpoint). */

void gd_adapter_set_client_id (gd_adapter_t *self, const char *client_id)
{
    snprintf (self->client_id, sizeof self->client_id, "%s", client_id);
    self->send_seq = 0; // a new id numbers its commands from 1
}

const char *gd_adapter_client_id (const gd_adapter_t *self)
{
    return self->client_id;
}

uint64_t gd_adapter_last_number (const gd_adapter_t *self)
{
    return self->send_seq;
}

bool gd_adapter_take_dirty (gd_adapter_t *self)
{
    bool dirty = self->dirty;
    self->dirty = false;
    return dirty;
}

int gd_adapter_save (const gd_adapter_t *self, uint8_t **ret_buf, size_t *ret_len)
{
    cgs_ckpt_writer_t w;
    cgs_ckpt_writer_init (&w, S_STATE_MAGIC, S_STATE_VERSION);
    cgs_ckpt_put_str (&w, self->client_id);
    cgs_ckpt_put_u64 (&w, self->send_seq);
    cgs_ckpt_put_u64 (&w, self->script_done);
    cgs_ckpt_put_bool (&w, self->operator_acted);
    cgs_ckpt_put_u32 (&w, (uint32_t)self->uav_count);
    for (size_t i = 0; i < self->uav_count; i++) {
        const s_uav_t *u = &self->uavs[i];
        uint8_t *core = NULL;
        size_t clen = 0;
        if (gd_checkpoint_save (u->core, &core, &clen) < 0) {
            cgs_ckpt_writer_fini (&w);
            return -ENOMEM;
        }
        cgs_ckpt_put_u32 (&w, u->entity_id);
        cgs_ckpt_put_u64 (&w, u->delivered);
        cgs_ckpt_put_u64 (&w, u->pending_task);
        cgs_ckpt_put_u64 (&w, u->pending_seq);
        cgs_ckpt_put_bytes (&w, core, clen);
        free (core);
    }
    return cgs_ckpt_writer_finish (&w, ret_buf, ret_len);
}

static int s_restore (gd_adapter_t *self, const uint8_t *buf, size_t len, char *err, size_t errlen)
{
    cgs_ckpt_reader_t r;
    int rc =
        cgs_ckpt_open (&r, buf, len, S_STATE_MAGIC, S_STATE_VERSION, S_STATE_WHAT, err, errlen);
    if (rc < 0)
        return rc;
    char id[sizeof self->client_id];
    cgs_ckpt_get_str (&r, id, sizeof id);
    uint64_t seq = cgs_ckpt_get_u64 (&r), done = cgs_ckpt_get_u64 (&r);
    bool acted = cgs_ckpt_get_bool (&r);
    uint32_t count = cgs_ckpt_get_u32 (&r);
    if (!cgs_ckpt_ok (&r)) {
        cgs_errf (err, errlen, "a %s with damaged counters", S_STATE_WHAT);
        return -EINVAL;
    }
    snprintf (self->client_id, sizeof self->client_id, "%s", id);
    self->send_seq = seq;
    self->script_done = (size_t)done;
    self->operator_acted = acted;
    for (uint32_t i = 0; i < count; i++) {
        uint32_t uid = cgs_ckpt_get_u32 (&r);
        uint64_t delivered = cgs_ckpt_get_u64 (&r), pending = cgs_ckpt_get_u64 (&r),
                 pseq = cgs_ckpt_get_u64 (&r);
        size_t clen = 0;
        const uint8_t *core = cgs_ckpt_get_bytes (&r, &clen);
        if (!cgs_ckpt_ok (&r)) {
            cgs_errf (err, errlen, "a %s whose UAV record %u of %u is damaged", S_STATE_WHAT, i + 1,
                      count);
            return -EINVAL;
        }
        s_uav_t *u = s_uav_by_id (self, uid);
        if (!u) {
            cgs_port_log (&self->port, LOG_WARNING,
                          "saved intercept of UAV %u ignored: not in the scenario", uid);
            continue;
        }
        char why[256] = "";
        if ((rc = gd_checkpoint_restore (u->core, core, clen, why, sizeof why)) < 0) {
            cgs_errf (err, errlen, "UAV %u: %s", uid, why);
            return rc;
        }
        u->delivered = delivered;
        u->pending_task = pending;
        u->pending_seq = pseq;
    }
    return cgs_ckpt_end (&r, S_STATE_WHAT, err, errlen);
}

int gd_adapter_restore (gd_adapter_t *self, const uint8_t *buf, size_t len, char *err,
                        size_t errlen)
{
    char client_id[sizeof self->client_id];
    snprintf (client_id, sizeof client_id, "%s", self->client_id);
    uint64_t send_seq = self->send_seq;
    int rc = s_restore (self, buf, len, err, errlen);
    if (rc < 0) {
        // Idle, numbering on from where it was under the same client id.
        snprintf (self->client_id, sizeof self->client_id, "%s", client_id);
        self->send_seq = send_seq;
        gd_adapter_reset (self);
    }
    return rc;
}

/* The client id and its numbering stay: a command number is never used
 * twice under one id (gd_adapter_set_client_id starts a new numbering). */
void gd_adapter_reset (gd_adapter_t *self)
{
    for (size_t i = 0; i < self->uav_count; i++) {
        s_uav_t *u = &self->uavs[i];
        gd_intercept_t *core = gd_intercept_new (&self->params, self->terrain);
        if (core) {
            gd_intercept_destroy (&u->core);
            u->core = core;
        } else {
            cgs_port_error (&self->port, "out of memory: the intercept of %s was not reset",
                            u->name);
        }
        u->delivered = u->pending_task = u->pending_seq = 0;
    }
    self->script_done = 0;
    self->operator_acted = false;
    self->script_waiting_logged = false;
    self->dirty = false;
}

/* ---- what it knows ----------------------------------------------------------------------- */

size_t gd_adapter_uav_count (const gd_adapter_t *self)
{
    return self->uav_count;
}

const gd_intercept_t *gd_adapter_intercept (const gd_adapter_t *self, size_t i)
{
    assert (i < self->uav_count);
    return self->uavs[i].core;
}

const char *gd_adapter_uav_name (const gd_adapter_t *self, size_t i)
{
    assert (i < self->uav_count);
    return self->uavs[i].name;
}

uint32_t gd_adapter_uav_id (const gd_adapter_t *self, size_t i)
{
    assert (i < self->uav_count);
    return self->uavs[i].entity_id;
}

size_t gd_adapter_track_count (const gd_adapter_t *self)
{
    return self->track_count;
}

bool gd_adapter_heard_tracks (const gd_adapter_t *self)
{
    return self->heard_tracks;
}

double gd_adapter_time (const gd_adapter_t *self)
{
    return self->sim_time_s;
}
