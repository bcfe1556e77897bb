/* uavsim_adapter — uavsim's pure layer (see uavsim_adapter.h). */
#include "uavsim_adapter.h"

#include "cgs_cmd.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <syslog.h>

struct uavsim_adapter {
    cgs_port_t port;
    uavsim_world_t *world; // the caller's
    uavsim_msgs_t *msgs;
    cgs_geodetic_t origin;
    double time_scale;
    bool paused;
    double next_entity_s, next_uav_s, next_clock_s; // simulation times of the next publications
    char detail[256];
};

uavsim_adapter_t *uavsim_adapter_new (uavsim_world_t *world, cgs_geodetic_t origin,
                                      const cgs_port_t *port)
{
    uavsim_adapter_t *self = calloc (1, sizeof *self);
    if (!self)
        return NULL;
    self->port = *port;
    self->world = world;
    self->origin = origin;
    self->time_scale = 1;
    if (!(self->msgs = uavsim_msgs_new (world)))
        uavsim_adapter_destroy (&self); // NULL
    return self;
}

void uavsim_adapter_destroy (uavsim_adapter_t **self_p)
{
    uavsim_adapter_t *self = *self_p;
    if (!self)
        return;
    uavsim_msgs_destroy (&self->msgs);
    free (self);
    *self_p = NULL;
}

uavsim_world_t *uavsim_adapter_world (uavsim_adapter_t *self)
{
    return self->world;
}

void uavsim_adapter_set_pacing (uavsim_adapter_t *self, double time_scale, bool paused)
{
    self->time_scale = time_scale;
    self->paused = paused;
}

/* ---- publication ------------------------------------------------------------------- */

static void s_publish_entities (uavsim_adapter_t *self, double t)
{
    size_t n = uavsim_msgs_entities (self->msgs, self->world);
    for (size_t k = 0; k < n; k++)
        cgs_port_publish (&self->port, "entity", &uavsim_msgs_batch (self->msgs, k)->base, t);
}

static void s_publish_uavs (uavsim_adapter_t *self, double t)
{
    for (size_t i = 0; i < uavsim_world_scenario (self->world)->uav_count; i++)
        cgs_port_publish (&self->port, "uav", &uavsim_msgs_uav (self->msgs, self->world, i)->base,
                          t);
}

void uavsim_adapter_publish_clock (uavsim_adapter_t *self)
{
    Cgs__Clock *c =
        uavsim_msgs_clock (self->msgs, self->world, self->time_scale, self->paused, self->origin);
    cgs_port_publish (&self->port, "clock", &c->base, uavsim_world_time (self->world));
}

void uavsim_adapter_publish_due (uavsim_adapter_t *self, bool all)
{
    const cgs_uavsim_settings_t *set = &uavsim_world_scenario (self->world)->settings;
    double t = uavsim_world_time (self->world);
    double eps = 1e-9;
    if (all || t + eps >= self->next_entity_s) {
        s_publish_entities (self, t);
        self->next_entity_s = floor (t * set->entity_rate_hz + eps + 1) / set->entity_rate_hz;
    }
    if (all || t + eps >= self->next_uav_s) {
        s_publish_uavs (self, t);
        self->next_uav_s = floor (t * set->uav_rate_hz + eps + 1) / set->uav_rate_hz;
    }
    if (all || t + eps >= self->next_clock_s) {
        uavsim_adapter_publish_clock (self);
        self->next_clock_s = floor (t * set->clock_rate_hz + eps + 1) / set->clock_rate_hz;
    }
}

void uavsim_adapter_step (uavsim_adapter_t *self)
{
    uavsim_world_step (self->world);
    uavsim_adapter_publish_due (self, false);
}

/* ---- commands ----------------------------------------------------------------------- */

static void s_refuse (uavsim_adapter_t *self, Cgs__Reply *reply, const char *why)
{
    snprintf (self->detail, sizeof self->detail, "%s", why);
    reply->status = CGS__REPLY_STATUS__REPLY_STATUS_ERROR;
    reply->error = self->detail;
}

static int s_uav (uavsim_adapter_t *self, uint32_t id, Cgs__Reply *reply)
{
    int i = uavsim_world_find_uav (self->world, id);
    if (i < 0) {
        snprintf (self->detail, sizeof self->detail, "no UAV with entity id %u%s", id,
                  id == 0 ? " (give one: the scenario has several)" : "");
        reply->status = CGS__REPLY_STATUS__REPLY_STATUS_ERROR;
        reply->error = self->detail;
    }
    return i;
}

static cgs_enu_t s_enu (const Cgs__Enu *p)
{
    cgs_enu_t e = {0, 0, 0};
    if (p) {
        e.e_m = p->east_m;
        e.n_m = p->north_m;
        e.u_m = p->up_m;
    }
    return e;
}

/* 0 when the UAV can fly an orbit of radius_m (0: its default) at its
 * commanded airspeed, else refuse with the smallest radius it can fly. */
static int s_radius_ok (uavsim_adapter_t *self, uavsim_uav_model_t *uav, double radius_m,
                        Cgs__Reply *reply)
{
    uavsim_uav_state_t st;
    uavsim_uav_state (uav, &st);
    double min_r = uavsim_uav_min_turn_radius (uav, st.commanded_airspeed_mps);
    if (radius_m == 0 || radius_m >= min_r)
        return 0;
    snprintf (self->detail, sizeof self->detail,
              "a %.0f m orbit is tighter than the UAV can turn at %.0f m/s (at least %.0f m)",
              radius_m, st.commanded_airspeed_mps, ceil (min_r));
    reply->status = CGS__REPLY_STATUS__REPLY_STATUS_ERROR;
    reply->error = self->detail;
    return -EINVAL;
}

/* A route task: speed, altitude and route applied together, or none of them. */
static uavsim_uav_model_t *s_route (uavsim_adapter_t *self, const Cgs__TaskRoute *t,
                                    Cgs__Reply *reply)
{
    int i = s_uav (self, t->uav_id, reply);
    if (i < 0)
        return NULL;
    uavsim_uav_model_t *uav = uavsim_world_uav (self->world, (size_t)i);
    if (t->n_waypoints == 0 || t->n_waypoints > UAVSIM_UAV_ROUTE_MAX) {
        snprintf (self->detail, sizeof self->detail, "a route needs 1 to %d points",
                  UAVSIM_UAV_ROUTE_MAX);
        reply->status = CGS__REPLY_STATUS__REPLY_STATUS_ERROR;
        reply->error = self->detail;
        return NULL;
    }
    cgs_enu_t *pts = calloc (t->n_waypoints, sizeof *pts);
    uint8_t *before = NULL; // the UAV as it was, so a refused route changes nothing
    size_t before_len = 0;
    if (!pts || uavsim_uav_save (uav, &before, &before_len) < 0) {
        free (pts);
        s_refuse (self, reply, "out of memory");
        return NULL;
    }
    for (size_t k = 0; k < t->n_waypoints; k++)
        pts[k] = s_enu (t->waypoints[k]);
    const char *why = NULL;
    if (t->airspeed_mps > 0 && uavsim_uav_set_speed (uav, t->airspeed_mps) < 0)
        why = "route refused: the airspeed is outside the UAV's limits";
    else if (t->altitude_agl_m > 0 && uavsim_uav_set_altitude (uav, t->altitude_agl_m) < 0)
        why = "route refused: the altitude must be in (0, 20000] m above ground";
    else if (t->loiter_at_end && s_radius_ok (self, uav, t->loiter_radius_m, reply) < 0)
        why = "route refused: its end orbit is tighter than the UAV can turn";
    else if (uavsim_uav_route (uav, pts, t->n_waypoints, t->loiter_at_end, t->loiter_radius_m,
                               !t->loiter_anticlockwise) < 0)
        why = "route refused: a point is out of range";
    if (why)
        uavsim_uav_restore (uav, before, before_len, NULL, 0);
    free (pts);
    free (before);
    if (why) {
        s_refuse (self, reply, why);
        return NULL;
    }
    return uav;
}

int uavsim_adapter_command (uavsim_adapter_t *self, const Cgs__Command *cmd, Cgs__Reply *reply)
{
    int i = -1;
    uavsim_uav_model_t *uav = NULL;
    int rc = 0;
    switch (cmd->body_case) {
    case CGS__COMMAND__BODY_TASK_ROUTE:
        if (!(uav = s_route (self, cmd->task_route, reply)))
            return 0;
        break;
    case CGS__COMMAND__BODY_GO_TO: {
        const Cgs__GoTo *g = cmd->go_to;
        if ((i = s_uav (self, g->uav_id, reply)) < 0)
            return 0;
        uav = uavsim_world_uav (self->world, (size_t)i);
        if (s_radius_ok (self, uav, g->radius_m, reply) < 0)
            return 0;
        if (uavsim_uav_goto (uav, s_enu (g->point), g->radius_m, !g->anticlockwise) < 0) {
            s_refuse (self, reply, "go to refused: bad point or radius");
            return 0;
        }
        break;
    }
    case CGS__COMMAND__BODY_LOITER: {
        const Cgs__Loiter *l = cmd->loiter;
        if ((i = s_uav (self, l->uav_id, reply)) < 0)
            return 0;
        uav = uavsim_world_uav (self->world, (size_t)i);
        if (s_radius_ok (self, uav, l->radius_m, reply) < 0)
            return 0;
        rc = l->at_present_position
                 ? uavsim_uav_loiter_here (uav, l->radius_m, l->clockwise)
                 : uavsim_uav_loiter (uav, s_enu (l->center), l->radius_m, l->clockwise);
        if (rc < 0) {
            s_refuse (self, reply, "loiter refused: bad centre or radius");
            return 0;
        }
        break;
    }
    case CGS__COMMAND__BODY_SET_ALTITUDE:
        if ((i = s_uav (self, cmd->set_altitude->uav_id, reply)) < 0)
            return 0;
        uav = uavsim_world_uav (self->world, (size_t)i);
        if (uavsim_uav_set_altitude (uav, cmd->set_altitude->altitude_agl_m) < 0) {
            s_refuse (self, reply, "altitude must be in (0, 20000] m above ground");
            return 0;
        }
        break;
    case CGS__COMMAND__BODY_SET_SPEED:
        if ((i = s_uav (self, cmd->set_speed->uav_id, reply)) < 0)
            return 0;
        uav = uavsim_world_uav (self->world, (size_t)i);
        if (uavsim_uav_set_speed (uav, cmd->set_speed->airspeed_mps) < 0) {
            s_refuse (self, reply, "airspeed outside the UAV's limits");
            return 0;
        }
        break;
    case CGS__COMMAND__BODY_SET_CAMERA: {
        const Cgs__SetCamera *c = cmd->set_camera;
        if ((i = s_uav (self, c->uav_id, reply)) < 0)
            return 0;
        uavsim_camera_cmd_t cc = {
            .set = c->set,
            .depression_deg = c->depression_deg,
            .hfov_deg = c->hfov_deg,
            .stabilized = c->stabilized,
            .stare = (uavsim_stare_t)c->stare,
            .stare_point = c->stare_point ? s_enu (c->stare_point) : (cgs_enu_t){NAN, NAN, 0},
        };
        char why[200];
        const cgs_scenario_t *sc = uavsim_world_scenario (self->world);
        uavsim_camera_t *cam = uavsim_world_camera (self->world, (size_t)i);
        if (uavsim_camera_set (cam, &sc->uavs[i], uavsim_world_terrain (self->world), &cc, why,
                               sizeof why) < 0) {
            s_refuse (self, reply, why);
            return 0;
        }
        static const char *const stares[] = {"off", "at a point", "at the designated target"};
        snprintf (self->detail, sizeof self->detail,
                  "camera of %s: depression %.1f deg, field of view %.2f x %.2f deg, %s, staring "
                  "%s, at t=%.2f s",
                  sc->uavs[i].name, cam->depression_deg, cam->hfov_deg, cam->vfov_deg,
                  cam->stabilized ? "stabilized" : "not stabilized", stares[cam->stare],
                  uavsim_world_time (self->world));
        s_publish_uavs (self, uavsim_world_time (self->world));
        cgs_port_log (&self->port, LOG_INFO, "%s (from %s #%llu)", self->detail,
                      cmd->client_id ? cmd->client_id : "",
                      (unsigned long long)cmd->command_number);
        reply->detail = self->detail;
        return 0;
    }
    case CGS__COMMAND__BODY_PING:
    case CGS__COMMAND__BODY_PAUSE:
    case CGS__COMMAND__BODY_RESUME:
    case CGS__COMMAND__BODY_SET_TIME_SCALE:
        return 1;
    default:
        reply->status = CGS__REPLY_STATUS__REPLY_STATUS_UNSUPPORTED;
        snprintf (self->detail, sizeof self->detail, "uavsim does not handle %s",
                  cgs_cmd_name (cmd));
        reply->error = self->detail;
        return 1;
    }
    uavsim_uav_state_t s;
    uavsim_uav_state (uav, &s);
    snprintf (self->detail, sizeof self->detail, "%s: task %llu accepted at t=%.2f s",
              cgs_cmd_name (cmd), (unsigned long long)s.task_number,
              uavsim_world_time (self->world));
    s_publish_uavs (self, uavsim_world_time (self->world));
    cgs_port_log (&self->port, LOG_INFO, "%s (from %s #%llu)", self->detail,
                  cmd->client_id ? cmd->client_id : "", (unsigned long long)cmd->command_number);
    reply->detail = self->detail;
    return 0;
}

void uavsim_adapter_on_intercept (uavsim_adapter_t *self, const Cgs__Intercept *m, double t_s)
{
    int i = m->uav_id ? uavsim_world_find_uav (self->world, m->uav_id) : -1;
    if (i < 0)
        return;
    bool have = m->track_id != 0 && m->has_target && m->target && m->target_velocity;
    cgs_enu_t p = have ? s_enu (m->target) : (cgs_enu_t){0, 0, 0};
    cgs_enu_t v = have ? (cgs_enu_t){m->target_velocity->east_mps, m->target_velocity->north_mps, 0}
                       : (cgs_enu_t){0, 0, 0};
    uavsim_camera_target (uavsim_world_camera (self->world, (size_t)i), have, p, v, t_s);
}
