/* guidanced — the UAV control station's intercept logic: serves the
 * operator's designate, cancel and settings commands, keeps the latest
 * tracks, runs one intercept per UAV (gd_intercept), delivers the UAV's
 * tasks to uavsim, publishes `intercept`, runs the scenario's operator
 * script when no operator designates, and keeps all of it in its state file
 * so a restart resumes the intercept. `--monte-carlo` runs the cores of
 * uavsim, mtid, trackerd and guidanced together instead (gd_mc). */
#include "cgs_lifecycle.h"
#include "cgs_log.h"
#include "cgs_scenario.h"
#include "cgs_service.h"
#include "gd_intercept.h"
#include "gd_mc.h"

#include <errno.h>
#include <inttypes.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/time.h>

#define S_UAVS_MAX    16
#define S_DELIVER_S   0.2 // wall seconds between delivery attempts
#define S_HOLD_S      5.0 // wall seconds commands wait for the tracker after a start
#define S_SEND_MS     400 // how long one delivery waits for uavsim
#define S_FORWARD_MS  500 // altitude and speed commands forwarded to uavsim
#define S_STATE_MAGIC "guidanced 1"

typedef struct {
    uint32_t entity_id;
    char name[64];
    gd_intercept_t *core;
    uint64_t delivered;    // task number uavsim has answered
    uint64_t pending_task; // task number being delivered
    uint64_t pending_seq;  // the command number it goes under
    double last_uav_s;
    int logged_phase; // phase and re-plans last written to the log
    uint32_t logged_replans;
    uint32_t logged_track;
    uint64_t logged_designation;
    char logged_reason[160];
} s_uav_t;

typedef struct {
    cgs_service_t svc;
    bool fresh;
    gd_params_t params;
    cgs_geo_t *frame;
    cgs_scenario_t *scenario;
    cgs_terrain_t *terrain;
    s_uav_t uavs[S_UAVS_MAX];
    size_t uav_count;
    // Tracks as last heard.
    gd_track_t *tracks;
    uint32_t *track_uav; // radar of each
    size_t track_count, track_cap;
    // Delivery to uavsim.
    const cgs_instance_t *uavsim;
    cgs_cmd_client_t *client;
    char client_id[128];
    uint64_t send_seq;
    // The operator's script.
    size_t script_done;
    bool operator_acted;
    bool script_waiting_logged;
    double sim_time_s;
    char detail[512];
    // Commands wait until the tracker is heard after a start (S_HOLD_S at most).
    double hold_until;
    // The message being built.
    Cgs__Enu route_pts[GD_ROUTE_MAX];
    Cgs__Enu *route_ptr[GD_ROUTE_MAX];
} s_app_t;

static void s_bad (s_app_t *app, const char *what)
{
    cgs_service_bad_input (&app->svc, what);
}

static s_uav_t *s_uav_by_id (s_app_t *app, uint32_t id)
{
    if (id == 0)
        return app->uav_count == 1 ? &app->uavs[0] : NULL;
    for (size_t i = 0; i < app->uav_count; i++)
        if (app->uavs[i].entity_id == id)
            return &app->uavs[i];
    return NULL;
}

static double s_height (const s_app_t *app, gd_v2_t p)
{
    return app->terrain ? cgs_terrain_height_clamped (app->terrain, p.e, p.n) : 0.0;
}

/* ---- publication ------------------------------------------------------------------------ */

static void s_enu (const s_app_t *app, Cgs__Enu *m, gd_v2_t p)
{
    cgs__enu__init (m);
    m->east_m = p.e;
    m->north_m = p.n;
    m->up_m = s_height (app, p);
}

static void s_publish (s_app_t *app, s_uav_t *u)
{
    gd_status_t st;
    gd_intercept_status (u->core, &st);
    if (st.track_id != u->logged_track && u->logged_track != 0 && st.track_id != 0 &&
        st.designation_number == u->logged_designation)
        cgs_log (LOG_NOTICE,
                 "%s: hand-over, t=%.1f s: track %u was deleted; its target goes on as "
                 "track %u",
                 u->name, app->sim_time_s, u->logged_track, st.track_id);
    if ((int)st.phase != u->logged_phase || st.replans != u->logged_replans ||
        st.track_id != u->logged_track || strcmp (st.reason, u->logged_reason) != 0) {
        cgs_log (LOG_NOTICE, "%s: %s, track %u, t=%.1f s: %s", u->name, gd_phase_name (st.phase),
                 st.track_id, app->sim_time_s, st.reason);
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
        s_enu (app, &wp, st.waypoint);
        m.waypoint = &wp;
        m.t_pred_s = st.t_pred_s;
        if (st.has_secondary) {
            s_enu (app, &sec, st.secondary);
            m.secondary_waypoint = &sec;
            m.has_secondary = true;
        }
    }
    size_t n = st.route_count < GD_ROUTE_MAX ? st.route_count : GD_ROUTE_MAX;
    for (size_t k = 0; k < n; k++) {
        s_enu (app, &app->route_pts[k], st.route[k]);
        app->route_ptr[k] = &app->route_pts[k];
    }
    m.n_route = n;
    m.route = app->route_ptr;
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
    app->svc.sim_time_s = app->sim_time_s;
    cgs_service_publish (&app->svc, "intercept", &m.base);
}

/* ---- delivery of tasks to uavsim ----------------------------------------------------------- */

static int s_save_now (s_app_t *app)
{
    int rc = cgs_service_save_state (&app->svc);
    if (rc < 0)
        cgs_log (LOG_WARNING, "state not written (see health)");
    return rc;
}

/* Send u's present task to uavsim once (under the command number it was
 * given, so a resend after a timeout or a restart is a duplicate to
 * uavsim, never a second task). */
static void s_deliver (s_app_t *app, s_uav_t *u)
{
    const gd_task_t *t = gd_intercept_task (u->core);
    if (t->kind == GD_TASK_NONE || t->number <= u->delivered || !app->client)
        return;
    if (u->pending_task != t->number) {
        u->pending_task = t->number;
        u->pending_seq = ++app->send_seq;
        if (s_save_now (app) < 0)
            return; // the number must be on disk before it is used
    }
    Cgs__Command cmd;
    cgs__command__init (&cmd);
    Cgs__TaskRoute route;
    Cgs__Loiter loiter;
    Cgs__Enu pts[GD_ROUTE_MAX];
    Cgs__Enu *ptr[GD_ROUTE_MAX];
    if (t->kind == GD_TASK_ROUTE) {
        cgs__task_route__init (&route);
        route.uav_id = u->entity_id;
        for (size_t k = 0; k < t->count; k++) {
            s_enu (app, &pts[k], t->points[k]);
            ptr[k] = &pts[k];
        }
        route.n_waypoints = t->count;
        route.waypoints = ptr;
        route.loiter_at_end = true;
        cmd.body_case = CGS__COMMAND__BODY_TASK_ROUTE;
        cmd.task_route = &route;
    } else {
        cgs__loiter__init (&loiter);
        loiter.uav_id = u->entity_id;
        loiter.at_present_position = true;
        loiter.clockwise = true;
        cmd.body_case = CGS__COMMAND__BODY_LOITER;
        cmd.loiter = &loiter;
    }
    Cgs__Reply *reply = NULL;
    char err[256];
    cgs_cmd_client_set_next_number (app->client, u->pending_seq);
    int rc = cgs_cmd_client_call (app->client, &cmd, S_SEND_MS, 1, &reply, err, sizeof err);
    if (rc < 0) {
        cgs_health_set_error (app->svc.health, err);
        return; // tried again at the next delivery tick
    }
    if (reply->status == CGS__REPLY_STATUS__REPLY_STATUS_BAD_REQUEST && !reply->duplicate) {
        // The number was taken (a forwarded command used it, and the state
        // that counted it was lost in a crash): the task goes again under a
        // new number at the next delivery tick.
        cgs_log (LOG_NOTICE, "%s: task %" PRIu64 ": uavsim: %s; sending it under a new number",
                 u->name, t->number, reply->error ? reply->error : "bad request");
        u->pending_task = 0;
        cgs_cmd_reply_free (&reply);
        return;
    }
    if (reply->status != CGS__REPLY_STATUS__REPLY_STATUS_OK &&
        reply->status != CGS__REPLY_STATUS__REPLY_STATUS_NOT_SAVED) {
        char why[384];
        snprintf (why, sizeof why, "uavsim refused %s task %" PRIu64 ": %s", u->name, t->number,
                  reply->error ? reply->error : "no reason");
        cgs_log (LOG_WARNING, "%s", why);
        cgs_health_set_error (app->svc.health, why);
    } else {
        cgs_log (LOG_INFO, "%s: task %" PRIu64 " (%s, %zu points) delivered%s", u->name, t->number,
                 t->kind == GD_TASK_ROUTE ? "route" : "loiter here", t->count,
                 reply->duplicate ? " (uavsim had it already)" : "");
    }
    u->delivered = t->number;
    cgs_cmd_reply_free (&reply);
}

static void s_on_deliver (void *arg)
{
    s_app_t *app = arg;
    for (size_t i = 0; i < app->uav_count; i++) {
        gd_intercept_tick (app->uavs[i].core, app->sim_time_s);
        s_deliver (app, &app->uavs[i]);
    }
}

/* ---- tracks ------------------------------------------------------------------------------------
 */

static gd_track_t *s_track_find (s_app_t *app, uint32_t id)
{
    for (size_t i = 0; i < app->track_count; i++)
        if (app->tracks[i].id == id)
            return &app->tracks[i];
    return NULL;
}

static void s_track_forget (s_app_t *app, uint32_t id)
{
    for (size_t i = 0; i < app->track_count; i++)
        if (app->tracks[i].id == id) {
            app->tracks[i] = app->tracks[app->track_count - 1];
            app->track_uav[i] = app->track_uav[app->track_count - 1];
            app->track_count--;
            return;
        }
}

static gd_track_t *s_track_slot (s_app_t *app, uint32_t id, uint32_t uav_id)
{
    gd_track_t *t = s_track_find (app, id);
    if (t)
        return t;
    if (app->track_count == app->track_cap) {
        size_t cap = app->track_cap ? app->track_cap * 2 : 64;
        gd_track_t *nt = realloc (app->tracks, cap * sizeof *nt);
        if (!nt)
            return NULL;
        app->tracks = nt;
        uint32_t *nu = realloc (app->track_uav, cap * sizeof *nu);
        if (!nu)
            return NULL;
        app->track_uav = nu;
        app->track_cap = cap;
    }
    app->track_uav[app->track_count] = uav_id;
    return &app->tracks[app->track_count++];
}

/* A track message as the intercept takes it; false when it is unusable. */
static bool s_track_from_msg (const Cgs__Track *m, double t_s, gd_track_t *ret)
{
    if (!m->track_id || !m->position || !m->velocity || !isfinite (m->position->east_m) ||
        !isfinite (m->position->north_m) || !isfinite (m->velocity->east_mps) ||
        !isfinite (m->velocity->north_mps) || !isfinite (t_s) || m->status > 3)
        return false;
    ret->id = m->track_id;
    ret->status = (int)m->status;
    ret->friendly = m->identity == CGS__TRACK_IDENTITY__TRACK_IDENTITY_FRIENDLY;
    ret->t_s = t_s;
    ret->pos = gd_v2 (m->position->east_m, m->position->north_m);
    ret->vel = gd_v2 (m->velocity->east_mps, m->velocity->north_mps);
    ret->hits = m->hit_count;
    ret->last_hit_s = isfinite (m->last_hit_time_s) ? m->last_hit_time_s : NAN;
    size_t n = m->n_history, skip = n > GD_HISTORY_MAX ? n - GD_HISTORY_MAX : 0;
    ret->history_count = 0;
    for (size_t k = skip; k < n; k++) {
        const Cgs__TrackHistoryPoint *h = m->history[k];
        if (!h->position || !isfinite (h->position->east_m) || !isfinite (h->position->north_m))
            continue;
        ret->history[ret->history_count] = gd_v2 (h->position->east_m, h->position->north_m);
        ret->history_t_s[ret->history_count++] = h->sim_time_s;
    }
    return true;
}

static void s_run_script (s_app_t *app);

static void s_on_track (void *arg, const char *topic, const ProtobufCMessage *msg,
                        const Cgs__Header *hdr)
{
    (void)topic;
    s_app_t *app = arg;
    const Cgs__TrackBatch *b = (const Cgs__TrackBatch *)msg;
    double t = hdr->sim_time_s;
    if (!isfinite (t)) {
        s_bad (app, "a track batch without a simulation time");
        return;
    }
    if (t > app->sim_time_s)
        app->sim_time_s = t;
    for (size_t i = 0; i < b->n_tracks; i++) {
        gd_track_t tr;
        if (!s_track_from_msg (b->tracks[i], t, &tr)) {
            s_bad (app, "a track without an id, a valid position or velocity");
            continue;
        }
        for (size_t k = 0; k < app->uav_count; k++)
            gd_intercept_track (app->uavs[k].core, &tr);
        if (tr.status == 3) {
            s_track_forget (app, tr.id);
            continue;
        }
        gd_track_t *slot = s_track_slot (app, tr.id, b->uav_id);
        if (!slot) {
            cgs_health_set_error (app->svc.health, "out of memory: a track was not kept");
            continue;
        }
        *slot = tr;
    }
    s_run_script (app);
    for (size_t k = 0; k < app->uav_count; k++) {
        s_deliver (app, &app->uavs[k]);
        s_publish (app, &app->uavs[k]);
    }
    if (app->svc.cmd_held) {
        cgs_service_hold_commands (&app->svc, false);
        cgs_log (LOG_INFO, "taking commands: the tracker's picture is heard (%zu tracks)",
                 app->track_count);
    }
}

/* The tracker not heard within S_HOLD_S of the start: take commands anyway. */
static void s_on_hold (void *arg)
{
    s_app_t *app = arg;
    if (app->svc.cmd_held && cgs_loop_now () >= app->hold_until) {
        cgs_service_hold_commands (&app->svc, false);
        cgs_log (LOG_WARNING, "taking commands without the tracker's picture (none in %.0f s)",
                 S_HOLD_S);
    }
}

static void s_on_turn (void *arg, const char *topic, const ProtobufCMessage *msg,
                       const Cgs__Header *hdr)
{
    (void)topic;
    (void)hdr;
    s_app_t *app = arg;
    const Cgs__TrackTurn *m = (const Cgs__TrackTurn *)msg;
    if (!m->track_id || !m->velocity_after || !isfinite (m->sim_time_s) ||
        !isfinite (m->velocity_after->east_mps) || !isfinite (m->velocity_after->north_mps)) {
        s_bad (app, "a turn event without a track, time or velocity");
        return;
    }
    gd_v2_t v = gd_v2 (m->velocity_after->east_mps, m->velocity_after->north_mps);
    for (size_t k = 0; k < app->uav_count; k++) {
        gd_intercept_turn (app->uavs[k].core, m->track_id, m->sim_time_s, v, m->turn_angle_deg);
        s_deliver (app, &app->uavs[k]);
    }
}

static void s_on_uav (void *arg, const char *topic, const ProtobufCMessage *msg,
                      const Cgs__Header *hdr)
{
    (void)topic;
    s_app_t *app = arg;
    const Cgs__Uav *m = (const Cgs__Uav *)msg;
    s_uav_t *u = s_uav_by_id (app, m->entity_id);
    if (!u || m->entity_id == 0)
        return; // a UAV of another scenario or exercise: not ours
    const Cgs__Enu *p = m->position;
    const Cgs__ImagingSensor *sn = m->sensor;
    if (!p || !isfinite (p->east_m) || !isfinite (p->north_m) || !isfinite (p->up_m) ||
        !isfinite (m->heading_deg) || !isfinite (m->pitch_deg) || !isfinite (m->roll_deg) ||
        !isfinite (m->ground_speed_mps) || !isfinite (m->airspeed_mps) ||
        !isfinite (m->commanded_airspeed_mps) || !isfinite (hdr->sim_time_s) || !sn ||
        !(sn->depression_deg > 0 && sn->depression_deg < 90) ||
        !(sn->hfov_deg > 0 && sn->hfov_deg < 180) || !(sn->vfov_deg > 0 && sn->vfov_deg < 180)) {
        s_bad (app, "a uav message without a valid position, attitude, speed, time or imaging "
                    "sensor (depression in (0, 90), fields of view in (0, 180) degrees)");
        return;
    }
    double t = hdr->sim_time_s;
    if (t > app->sim_time_s)
        app->sim_time_s = t;
    gd_uav_t g = {
        .t_s = t,
        .position = {p->east_m, p->north_m, p->up_m},
        .heading_deg = m->heading_deg,
        .pitch_deg = m->pitch_deg,
        .roll_deg = m->roll_deg,
        .ground_speed_mps = m->ground_speed_mps,
        .airspeed_mps = m->commanded_airspeed_mps > 0 ? m->commanded_airspeed_mps : m->airspeed_mps,
        .agl_m = m->altitude_agl_m > 1 ? m->altitude_agl_m : 1,
        .bank_limit_deg = m->bank_limit_deg,
        .depression_deg = m->sensor->depression_deg,
        .hfov_deg = m->sensor->hfov_deg,
        .vfov_deg = m->sensor->vfov_deg,
    };
    gd_intercept_uav (u->core, &g);
    u->last_uav_s = t;
    s_deliver (app, u);
    s_publish (app, u);
}

/* ---- the operator's script --------------------------------------------------------------------
 */

static void s_run_script (s_app_t *app)
{
    const cgs_scenario_t *sc = app->scenario;
    while (app->script_done < sc->designation_count && app->uav_count > 0) {
        const cgs_designation_t *d = &sc->designations[app->script_done];
        if (app->sim_time_s < d->time_s)
            return;
        if (app->operator_acted) {
            cgs_log (LOG_NOTICE, "operator script line %d skipped: an operator designated already",
                     d->line);
            app->script_done++;
            s_save_now (app);
            continue;
        }
        gd_pick_t pick = d->pick == CGS_PICK_UNKNOWN    ? GD_PICK_UNKNOWN
                         : d->pick == CGS_PICK_FRIENDLY ? GD_PICK_FRIENDLY
                                                        : GD_PICK_ANY;
        double dist = 0;
        int i = gd_pick_nearest (app->tracks, app->track_count, gd_v2 (d->near.e_m, d->near.n_m),
                                 pick, &dist);
        if (i < 0 || dist > app->params.pick_radius_m) {
            if (!app->script_waiting_logged)
                cgs_log (LOG_INFO,
                         "operator script line %d: no track qualifies within %.0f m of (%.0f, "
                         "%.0f) yet; waiting",
                         d->line, app->params.pick_radius_m, d->near.e_m, d->near.n_m);
            app->script_waiting_logged = true;
            return;
        }
        s_uav_t *u = &app->uavs[0];
        char why[256];
        if (gd_intercept_designate (u->core, &app->tracks[i], app->sim_time_s, why, sizeof why) <
            0) {
            cgs_log (LOG_WARNING, "operator script line %d: %s", d->line, why);
        } else {
            cgs_log (LOG_NOTICE,
                     "operator script line %d: %s designates track %u, %.0f m from (%.0f, %.0f), "
                     "at t=%.1f s",
                     d->line, u->name, app->tracks[i].id, dist, d->near.e_m, d->near.n_m,
                     app->sim_time_s);
        }
        app->script_done++;
        app->script_waiting_logged = false;
        s_save_now (app);
        s_deliver (app, u);
        s_publish (app, u);
    }
}

/* ---- commands
 * ------------------------------------------------------------------------------------ */

static void s_refuse (s_app_t *app, Cgs__Reply *reply, const char *fmt, ...)
    __attribute__ ((format (printf, 3, 4)));
static void s_refuse (s_app_t *app, Cgs__Reply *reply, const char *fmt, ...)
{
    va_list ap;
    va_start (ap, fmt);
    vsnprintf (app->detail, sizeof app->detail, fmt, ap);
    va_end (ap);
    reply->status = CGS__REPLY_STATUS__REPLY_STATUS_ERROR;
    reply->error = app->detail;
}

static s_uav_t *s_cmd_uav (s_app_t *app, uint32_t id, Cgs__Reply *reply)
{
    s_uav_t *u = s_uav_by_id (app, id);
    if (!u)
        s_refuse (app, reply, "no UAV with entity id %u%s", id,
                  id == 0 ? " (give one: the scenario has several)" : "");
    return u;
}

static void s_designate (s_app_t *app, const Cgs__Designate *d, Cgs__Reply *reply)
{
    s_uav_t *u = s_cmd_uav (app, d->uav_id, reply);
    if (!u)
        return;
    const gd_track_t *t = NULL;
    if (d->target_case == CGS__DESIGNATE__TARGET_TRACK_ID) {
        t = s_track_find (app, d->track_id);
        if (!t)
            return s_refuse (app, reply, "no track %u (%zu live tracks known)", d->track_id,
                             app->track_count);
    } else if (d->target_case == CGS__DESIGNATE__TARGET_POINT && d->point &&
               isfinite (d->point->east_m) && isfinite (d->point->north_m)) {
        gd_v2_t p = gd_v2 (d->point->east_m, d->point->north_m);
        double dist = 0;
        int i = gd_pick_nearest (app->tracks, app->track_count, p, GD_PICK_ANY, &dist);
        if (i < 0)
            return s_refuse (app, reply, "no confirmed track to designate");
        if (dist > app->params.pick_radius_m)
            return s_refuse (app, reply,
                             "no track's newest hit within %.0f m of (%.0f, %.0f): the nearest is "
                             "track %u, %.0f m away",
                             app->params.pick_radius_m, p.e, p.n, app->tracks[i].id, dist);
        t = &app->tracks[i];
    } else {
        return s_refuse (app, reply, "designate needs a track id or a point");
    }
    char why[256];
    if (gd_intercept_designate (u->core, t, app->sim_time_s, why, sizeof why) < 0)
        return s_refuse (app, reply, "%s", why);
    app->operator_acted = true;
    gd_status_t st;
    gd_intercept_status (u->core, &st);
    if (st.has_plan)
        snprintf (app->detail, sizeof app->detail,
                  "%s: %s; %s, waypoint (%.0f, %.0f), t_pred %.0f s%s", u->name, st.reason,
                  gd_phase_name (st.phase), st.waypoint.e, st.waypoint.n, st.t_pred_s,
                  st.has_secondary ? ", through a secondary waypoint" : "");
    else
        snprintf (app->detail, sizeof app->detail, "%s: %s; planned when the UAV is heard", u->name,
                  st.reason);
    reply->detail = app->detail;
}

/* Forward altitude or speed to uavsim and answer with its verdict. */
static void s_forward (s_app_t *app, const Cgs__Command *cmd, Cgs__Reply *reply)
{
    if (!app->client)
        return s_refuse (app, reply, "the exercise has no uavsim command endpoint");
    Cgs__Command fwd = *cmd;
    Cgs__Reply *r = NULL;
    char err[256];
    cgs_cmd_client_set_next_number (app->client, ++app->send_seq);
    if (cgs_cmd_client_call (app->client, &fwd, S_FORWARD_MS, 2, &r, err, sizeof err) < 0)
        return s_refuse (app, reply, "%s", err);
    if (r->status != CGS__REPLY_STATUS__REPLY_STATUS_OK)
        s_refuse (app, reply, "uavsim: %s", r->error ? r->error : "refused");
    else {
        snprintf (app->detail, sizeof app->detail, "uavsim: %s", r->detail ? r->detail : "ok");
        reply->detail = app->detail;
    }
    cgs_cmd_reply_free (&r);
}

static void s_on_command (void *arg, const Cgs__Command *cmd, Cgs__Reply *reply)
{
    s_app_t *app = arg;
    s_uav_t *u = NULL;
    switch (cmd->body_case) {
    case CGS__COMMAND__BODY_DESIGNATE:
        s_designate (app, cmd->designate, reply);
        u = s_uav_by_id (app, cmd->designate->uav_id);
        break;
    case CGS__COMMAND__BODY_CANCEL:
        if (!(u = s_cmd_uav (app, cmd->cancel->uav_id, reply)))
            return;
        if (gd_intercept_cancel (u->core, app->sim_time_s) < 0)
            return s_refuse (app, reply, "%s: no intercept to cancel", u->name);
        app->operator_acted = true;
        snprintf (app->detail, sizeof app->detail, "%s: intercept cancelled; loitering here",
                  u->name);
        reply->detail = app->detail;
        break;
    case CGS__COMMAND__BODY_SET_FOOTPRINT_SCALE:
        if (!(u = s_cmd_uav (app, cmd->set_footprint_scale->uav_id, reply)))
            return;
        if (gd_intercept_set_scale (u->core, cmd->set_footprint_scale->scale) < 0)
            return s_refuse (app, reply, "footprint scale must be 1, 5 or 10, got %u",
                             cmd->set_footprint_scale->scale);
        snprintf (app->detail, sizeof app->detail, "%s: footprint shown %u times", u->name,
                  cmd->set_footprint_scale->scale);
        reply->detail = app->detail;
        break;
    case CGS__COMMAND__BODY_SET_INTERCEPT_MODE: {
        if (!(u = s_cmd_uav (app, cmd->set_intercept_mode->uav_id, reply)))
            return;
        int m = (int)cmd->set_intercept_mode->method;
        if (m != GD_HEAD_ON && m != GD_MTI_HITS)
            return s_refuse (app, reply, "unknown intercept method %d", m);
        gd_intercept_set_method (u->core, (gd_method_t)m);
        snprintf (app->detail, sizeof app->detail, "%s: intercept method %s", u->name,
                  m == GD_HEAD_ON ? "head-on waypoint" : "Intercept by MTI TGT Hits");
        reply->detail = app->detail;
        break;
    }
    case CGS__COMMAND__BODY_SET_ALTITUDE:
    case CGS__COMMAND__BODY_SET_SPEED:
        s_forward (app, cmd, reply);
        return;
    case CGS__COMMAND__BODY_PING:
        return;
    default:
        reply->status = CGS__REPLY_STATUS__REPLY_STATUS_UNSUPPORTED;
        snprintf (app->detail, sizeof app->detail, "guidanced does not handle %s",
                  cgs_cmd_name (cmd));
        reply->error = app->detail;
        return;
    }
    if (reply->status == CGS__REPLY_STATUS__REPLY_STATUS_OK || reply->status == 0)
        cgs_log (LOG_INFO, "%s (from %s #%llu)", app->detail, cmd->client_id,
                 (unsigned long long)cmd->command_number);
    if (u)
        s_publish (app, u); // the task goes out at the next delivery tick, after the state is saved
}

/* ---- state --------------------------------------------------------------------------------------
 * A header line, a line of the service's own counters, then per UAV a
 * line "uav ENTITY_ID DELIVERED PENDING_TASK PENDING_SEQ LEN" followed by
 * LEN bytes of the intercept's own save. */

static int s_save (void *arg, uint8_t **ret_buf, size_t *ret_len)
{
    s_app_t *app = arg;
    size_t cap = 512, len = 0;
    uint8_t *buf = malloc (cap);
    if (!buf)
        return -ENOMEM;
    len = (size_t)snprintf ((char *)buf, cap, "%s\nclient %s %" PRIu64 " %zu %d\n", S_STATE_MAGIC,
                            app->client_id, app->send_seq, app->script_done,
                            app->operator_acted ? 1 : 0);
    for (size_t i = 0; i < app->uav_count; i++) {
        s_uav_t *u = &app->uavs[i];
        uint8_t *core = NULL;
        size_t clen = 0;
        if (gd_intercept_save (u->core, &core, &clen) < 0) {
            free (buf);
            return -ENOMEM;
        }
        char head[160];
        int hn = snprintf (head, sizeof head, "uav %u %" PRIu64 " %" PRIu64 " %" PRIu64 " %zu\n",
                           u->entity_id, u->delivered, u->pending_task, u->pending_seq, clen);
        if (len + (size_t)hn + clen + 1 > cap) {
            cap = (len + (size_t)hn + clen + 1) * 2;
            uint8_t *nb = realloc (buf, cap);
            if (!nb) {
                free (core);
                free (buf);
                return -ENOMEM;
            }
            buf = nb;
        }
        memcpy (buf + len, head, (size_t)hn);
        len += (size_t)hn;
        memcpy (buf + len, core, clen);
        len += clen;
        free (core);
    }
    *ret_buf = buf;
    *ret_len = len;
    return 0;
}

static int s_restore (s_app_t *app, const uint8_t *buf, size_t len, char *err, size_t errlen)
{
    const char *cur = (const char *)buf, *end = cur + len;
    char line[256];
    // Header and counters.
    for (int k = 0; k < 2; k++) {
        const char *nl = memchr (cur, '\n', (size_t)(end - cur));
        size_t n = nl ? (size_t)(nl - cur) : 0;
        if (!nl || n >= sizeof line) {
            snprintf (err, errlen, "not a guidanced state (truncated header)");
            return -EPROTO;
        }
        memcpy (line, cur, n);
        line[n] = '\0';
        cur = nl + 1;
        int acted = 0;
        char id[128];
        if (k == 0 && strcmp (line, S_STATE_MAGIC) != 0) {
            snprintf (err, errlen, "not a guidanced state (header \"%.40s\")", line);
            return -EPROTO;
        }
        if (k == 1 && (sscanf (line, "client %127s %" SCNu64 " %zu %d", id, &app->send_seq,
                               &app->script_done, &acted) != 4)) {
            snprintf (err, errlen, "not a guidanced state (bad counters line)");
            return -EPROTO;
        }
        if (k == 1) {
            snprintf (app->client_id, sizeof app->client_id, "%s", id);
            app->operator_acted = acted != 0;
        }
    }
    while (cur < end) {
        const char *nl = memchr (cur, '\n', (size_t)(end - cur));
        size_t n = nl ? (size_t)(nl - cur) : 0;
        if (!nl || n >= sizeof line) {
            snprintf (err, errlen, "damaged UAV record");
            return -EPROTO;
        }
        memcpy (line, cur, n);
        line[n] = '\0';
        cur = nl + 1;
        uint32_t id = 0;
        uint64_t delivered = 0, pending = 0, seq = 0;
        size_t clen = 0;
        if (sscanf (line, "uav %u %" SCNu64 " %" SCNu64 " %" SCNu64 " %zu", &id, &delivered,
                    &pending, &seq, &clen) != 5 ||
            clen > (size_t)(end - cur)) {
            snprintf (err, errlen, "damaged UAV record \"%.60s\"", line);
            return -EPROTO;
        }
        s_uav_t *u = s_uav_by_id (app, id);
        if (!u) {
            cgs_log (LOG_WARNING, "saved intercept of UAV %u ignored: not in the scenario", id);
        } else {
            int rc = gd_intercept_restore (u->core, (const uint8_t *)cur, clen, err, errlen);
            if (rc < 0)
                return rc;
            u->delivered = delivered;
            u->pending_task = pending;
            u->pending_seq = seq;
        }
        cur += clen;
    }
    return 0;
}

static void s_on_checkpoint (void *arg)
{
    s_app_t *app = arg;
    for (size_t i = 0; i < app->uav_count; i++) {
        gd_status_t st;
        gd_intercept_status (app->uavs[i].core, &st);
        cgs_notify_status ("t=%.1f s, %s %s track %u", app->sim_time_s, app->uavs[i].name,
                           gd_phase_name (st.phase), st.track_id);
    }
    s_save_now (app);
}

/* ---- setup and main
 * ------------------------------------------------------------------------------ */

static const cgs_service_option_t s_options[] = {
    {"fresh", false, NULL, "start idle, ignoring the saved intercept"},
    {"monte-carlo", false, NULL,
     "run the Monte Carlo of whole intercepts (see --monte-carlo --help)"},
    {NULL, false, NULL, NULL},
};

static int s_on_option (void *arg, const char *name, const char *value, char *why, size_t whylen)
{
    (void)value;
    s_app_t *app = arg;
    if (strcmp (name, "fresh") == 0) {
        app->fresh = true;
        return 0;
    }
    snprintf (why, whylen, "unknown option --%s", name);
    return -EINVAL;
}

static int s_setup (s_app_t *app, char *err, size_t errlen)
{
    gd_params_defaults (&app->params);
    if (*app->svc.params) {
        int rc = gd_params_load (app->svc.params, &app->params, err, errlen);
        if (rc < 0)
            return rc;
        cgs_log (LOG_INFO, "guidance parameters from %s", app->svc.params);
    } else {
        cgs_log (LOG_INFO, "guidance parameters: the built-in defaults (no parameter file named)");
    }
    if (!*app->svc.scenario) {
        snprintf (err, errlen,
                  "no scenario (its UAVs and terrain are needed): give --scenario FILE "
                  "or `scenario =` in %s",
                  app->svc.exercise_path);
        return -EINVAL;
    }
    cgs_geodetic_t o = cgs_exercise_origin (app->svc.exercise);
    app->frame = cgs_geo_new (o.lat_deg, o.lon_deg, o.height_m);
    if (!app->frame) {
        snprintf (err, errlen, "bad exercise origin");
        return -EINVAL;
    }
    int rc = cgs_scenario_load (app->svc.scenario, app->frame,
                                cgs_exercise_seed (app->svc.exercise), &app->scenario, err, errlen);
    if (rc < 0)
        return rc;
    if ((rc = cgs_scenario_terrain (app->scenario, app->frame, &app->terrain, err, errlen)) < 0)
        return rc;
    if (app->scenario->uav_count > S_UAVS_MAX) {
        snprintf (err, errlen, "%s: guidanced serves at most %d UAVs", app->svc.scenario,
                  S_UAVS_MAX);
        return -EINVAL;
    }
    for (size_t i = 0; i < app->scenario->uav_count; i++) {
        s_uav_t *u = &app->uavs[app->uav_count];
        u->entity_id = app->scenario->uavs[i].id;
        snprintf (u->name, sizeof u->name, "%s", app->scenario->uavs[i].name);
        u->core = gd_intercept_new (&app->params, app->terrain);
        if (!u->core) {
            snprintf (err, errlen, "out of memory");
            return -ENOMEM;
        }
        app->uav_count++;
    }
    // uavsim takes the tasks.
    app->uavsim = cgs_exercise_first_of (app->svc.exercise, "uavsim");
    if (app->uavsim && !*app->uavsim->command)
        app->uavsim = NULL;
    if (!app->uavsim)
        cgs_log (LOG_WARNING, "the exercise names no uavsim with a command endpoint: intercepts "
                              "are planned and published but not flown");
    return 0;
}

/* A client id for uavsim that outlives restarts (kept in the state) and
 * differs from any earlier run's, so numbers never collide. */
static void s_new_client_id (s_app_t *app)
{
    struct timeval tv;
    gettimeofday (&tv, NULL);
    snprintf (app->client_id, sizeof app->client_id, "%s@%lld.%06ld", app->svc.instance_name,
              (long long)tv.tv_sec, (long)tv.tv_usec);
    app->send_seq = 0;
}

int main (int argc, char **argv)
{
    for (int i = 1; i < argc; i++)
        if (strcmp (argv[i], "--monte-carlo") == 0)
            return gd_mc_main (argc, argv);
    static s_app_t app;
    cgs_service_info_t info = {
        .program = "guidanced",
        .summary = "UAV control station intercept logic: designation, head-on waypoint, "
                   "precision approach, footprint.",
        .options = s_options,
        .on_option = s_on_option,
        .option_arg = &app,
    };
    int rc = cgs_service_init (&app.svc, &info, argc, argv);
    if (rc != 0) {
        cgs_service_fini (&app.svc);
        return rc > 0 ? 0 : 1;
    }
    int exit_code = 1;
    char err[1024] = "";
    if (s_setup (&app, err, sizeof err) < 0) {
        cgs_log (LOG_ERR, "%s", err);
        goto done;
    }
    cgs_log (LOG_INFO, "%zu UAV%s, %zu operator script line%s; uavsim at %s", app.uav_count,
             app.uav_count == 1 ? "" : "s", app.scenario->designation_count,
             app.scenario->designation_count == 1 ? "" : "s",
             app.uavsim ? app.uavsim->command : "(none)");
    if (app.svc.check_only) {
        printf ("%s: configuration is good\n", app.svc.instance_name);
        exit_code = 0;
        goto done;
    }
    if (cgs_service_serve_commands (&app.svc, s_on_command, s_save, &app) < 0)
        goto done;
    s_new_client_id (&app);
    const uint8_t *saved = NULL;
    size_t saved_len = 0;
    cgs_service_saved_state (&app.svc, &saved, &saved_len);
    if (saved_len > 0 && app.fresh) {
        cgs_log (LOG_NOTICE, "--fresh: the saved intercept is ignored; starting idle");
    } else if (saved_len > 0) {
        if (s_restore (&app, saved, saved_len, err, sizeof err) < 0) {
            cgs_log (LOG_WARNING, "saved state ignored (%s); starting idle", err);
            cgs_health_set_error (app.svc.health, err);
            for (size_t i = 0; i < app.uav_count; i++) {
                gd_intercept_destroy (&app.uavs[i].core);
                app.uavs[i].core = gd_intercept_new (&app.params, app.terrain);
                app.uavs[i].delivered = app.uavs[i].pending_task = app.uavs[i].pending_seq = 0;
            }
            s_new_client_id (&app);
            app.script_done = 0;
            app.operator_acted = false;
        } else {
            for (size_t i = 0; i < app.uav_count; i++) {
                gd_status_t st;
                gd_intercept_status (app.uavs[i].core, &st);
                cgs_log (LOG_NOTICE, "resumed %s: %s, track %u (%s)", app.uavs[i].name,
                         gd_phase_name (st.phase), st.track_id, st.reason);
            }
        }
    }
    if (app.uavsim) {
        app.client = cgs_cmd_client_new_exact (app.svc.ctx, app.uavsim->command, app.client_id,
                                               app.send_seq + 1);
        if (!app.client ||
            cgs_curve_protect_client (app.svc.curve, app.client, app.uavsim->public_key) < 0) {
            cgs_log (LOG_ERR, "cannot make a command client for %s", app.uavsim->command);
            goto done;
        }
    }
    if (cgs_service_subscribe (&app.svc, "uav", s_on_uav, &app) < 0 ||
        cgs_service_subscribe (&app.svc, "track", s_on_track, &app) < 0 ||
        cgs_service_subscribe (&app.svc, "track.turn", s_on_turn, &app) < 0)
        goto done;
    cgs_loop_add_timer (app.svc.loop, S_DELIVER_S, s_on_deliver, &app);
    cgs_loop_add_timer (app.svc.loop, 5.0, s_on_checkpoint, &app);
    // A designation needs the tracks: until the tracker is heard (its next
    // batch), commands wait unanswered rather than be refused for want of them.
    cgs_service_hold_commands (&app.svc, true);
    app.hold_until = cgs_loop_now () + S_HOLD_S;
    cgs_loop_add_timer (app.svc.loop, 0.1, s_on_hold, &app);
    exit_code = cgs_service_run (&app.svc);
    s_save_now (&app);
done:
    for (size_t i = 0; i < app.uav_count; i++)
        gd_intercept_destroy (&app.uavs[i].core);
    cgs_cmd_client_destroy (&app.client);
    free (app.tracks);
    free (app.track_uav);
    cgs_terrain_destroy (&app.terrain);
    cgs_scenario_destroy (&app.scenario);
    cgs_geo_destroy (&app.frame);
    cgs_service_fini (&app.svc);
    return exit_code;
}
