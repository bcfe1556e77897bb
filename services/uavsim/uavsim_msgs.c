/* uavsim_msgs — the world as entity, uav and clock messages. */
#include "uavsim_msgs.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct {
    Cgs__Entity e;
    Cgs__Enu pos;
    Cgs__EnuVelocity vel;
    Cgs__EntityType type;
} s_slot_t;

struct uavsim_msgs {
    s_slot_t *slots;
    Cgs__Entity **ptrs; // into slots, in entity order
    size_t n;
    Cgs__EntityBatch *batches;
    size_t nbatches;
    // one `uav` message
    Cgs__Uav uav;
    Cgs__Enu uav_pos, loiter_center;
    Cgs__EnuVelocity uav_vel;
    Cgs__LoiterOrbit loiter;
    Cgs__ImagingSensor sensor;
    Cgs__Enu stare_point;
    Cgs__Enu route[UAVSIM_UAV_ROUTE_MAX];
    Cgs__Enu *route_ptrs[UAVSIM_UAV_ROUTE_MAX];
    Cgs__Clock clock;
    Cgs__Geodetic origin;
};

void uavsim_msgs_destroy (uavsim_msgs_t **self_p)
{
    if (!self_p || !*self_p)
        return;
    free ((*self_p)->slots);
    free ((*self_p)->ptrs);
    free ((*self_p)->batches);
    free (*self_p);
    *self_p = NULL;
}

static void s_type (Cgs__EntityType *t, const cgs_dis_type_t *d)
{
    cgs__entity_type__init (t);
    t->kind = d->kind;
    t->domain = d->domain;
    t->country = d->country;
    t->category = d->category;
    t->subcategory = d->subcategory;
    t->specific = d->specific;
    t->extra = d->extra;
}

uavsim_msgs_t *uavsim_msgs_new (const uavsim_world_t *world)
{
    const cgs_scenario_t *sc = uavsim_world_scenario (world);
    uavsim_msgs_t *self = calloc (1, sizeof *self);
    if (!self)
        return NULL;
    self->n = sc->uav_count + sc->vehicle_count;
    self->nbatches = (self->n + UAVSIM_MSGS_BATCH - 1) / UAVSIM_MSGS_BATCH;
    self->slots = calloc (self->n, sizeof *self->slots);
    self->ptrs = calloc (self->n, sizeof *self->ptrs);
    self->batches = calloc (self->nbatches ? self->nbatches : 1, sizeof *self->batches);
    if (!self->slots || !self->ptrs || !self->batches) {
        uavsim_msgs_destroy (&self);
        return NULL;
    }
    // The parts that never change: identity, force, type, marking.
    for (size_t i = 0; i < self->n; i++) {
        s_slot_t *s = &self->slots[i];
        cgs__entity__init (&s->e);
        cgs__enu__init (&s->pos);
        cgs__enu_velocity__init (&s->vel);
        s->e.position = &s->pos;
        s->e.velocity = &s->vel;
        s->e.dis_type = &s->type;
        s->e.active = true;
        if (i < sc->uav_count) {
            const cgs_scenario_uav_t *u = &sc->uavs[i];
            s->e.entity_id = u->id;
            s->e.marking = (char *)u->marking;
            s->e.force = CGS__FORCE__FORCE_FRIENDLY;
            s->e.kind = CGS__ENTITY_KIND__ENTITY_KIND_AIR;
            s->e.rcs_class = "uav";
            s_type (&s->type, &u->dis_type);
        } else {
            const cgs_scenario_vehicle_t *v = &sc->vehicles[i - sc->uav_count];
            s->e.entity_id = v->id;
            s->e.marking = (char *)v->marking;
            s->e.force = (Cgs__Force)v->force;
            s->e.kind = (Cgs__EntityKind)v->kind;
            s->e.bcis_transponder = v->bcis_transponder;
            s->e.rcs_class = v->rcs_class;
            s_type (&s->type, &v->dis_type);
        }
        self->ptrs[i] = &s->e;
    }
    for (size_t k = 0; k < self->nbatches; k++) {
        Cgs__EntityBatch *b = &self->batches[k];
        cgs__entity_batch__init (b);
        b->entities = &self->ptrs[k * UAVSIM_MSGS_BATCH];
        size_t left = self->n - k * UAVSIM_MSGS_BATCH;
        b->n_entities = left < UAVSIM_MSGS_BATCH ? left : UAVSIM_MSGS_BATCH;
        b->batch_index = (uint32_t)k;
        b->batch_count = (uint32_t)self->nbatches;
    }
    cgs__uav__init (&self->uav);
    cgs__clock__init (&self->clock);
    return self;
}

static double s_wrap360 (double deg)
{
    double h = fmod (deg, 360.0);
    return h < 0 ? h + 360.0 : h;
}

size_t uavsim_msgs_entities (uavsim_msgs_t *self, uavsim_world_t *world)
{
    const cgs_scenario_t *sc = uavsim_world_scenario (world);
    const cgs_terrain_t *terrain = uavsim_world_terrain (world);
    for (size_t i = 0; i < sc->uav_count; i++) {
        s_slot_t *s = &self->slots[i];
        uavsim_uav_state_t u;
        uavsim_uav_state (uavsim_world_uav (world, i), &u);
        s->pos.east_m = u.position.e_m;
        s->pos.north_m = u.position.n_m;
        s->pos.up_m = u.position.u_m;
        s->vel.east_mps = u.velocity.e_m;
        s->vel.north_mps = u.velocity.n_m;
        s->vel.up_mps = u.velocity.u_m;
        s->e.heading_deg = u.heading_deg;
        s->e.pitch_deg = u.pitch_deg;
        s->e.roll_deg = u.roll_deg;
        s->e.speed_mps = u.airspeed_mps;
    }
    for (size_t i = 0; i < sc->vehicle_count; i++) {
        s_slot_t *s = &self->slots[sc->uav_count + i];
        uavsim_vehicle_state_t v;
        uavsim_vehicle_state (uavsim_world_vehicle (world, i), &v);
        uavsim_vehicle_ground_t g;
        uavsim_vehicle_ground (terrain, &v, &g);
        s->pos.east_m = v.e_m;
        s->pos.north_m = v.n_m;
        s->pos.up_m = g.up_m;
        s->vel.east_mps = v.ve_mps;
        s->vel.north_mps = v.vn_mps;
        s->vel.up_mps = g.vu_mps;
        s->e.heading_deg = s_wrap360 (v.heading_deg);
        s->e.pitch_deg = g.pitch_deg;
        s->e.roll_deg = g.roll_deg;
        s->e.speed_mps = v.speed_mps;
        // Before its start time a vehicle is not yet in the exercise.
        s->e.active = v.active;
    }
    return self->nbatches;
}

Cgs__EntityBatch *uavsim_msgs_batch (uavsim_msgs_t *self, size_t k)
{
    return k < self->nbatches ? &self->batches[k] : NULL;
}

void uavsim_msgs_boresight (double heading_deg, double pitch_deg, double roll_deg,
                            double depression_deg, double *ret_azimuth_deg,
                            double *ret_elevation_deg)
{
    const double r = M_PI / 180.0;
    double ch = cos (heading_deg * r), sh = sin (heading_deg * r);
    double cp = cos (pitch_deg * r), sp = sin (pitch_deg * r);
    double cr = cos (roll_deg * r), sr = sin (roll_deg * r);
    // Boresight in the body (x forward, y right, z down), depressed by d.
    double bx = cos (depression_deg * r), by = 0, bz = sin (depression_deg * r);
    // Body to north-east-down: yaw (heading), pitch, roll (aerospace ZYX).
    double n = ch * cp * bx + (ch * sp * sr - sh * cr) * by + (ch * sp * cr + sh * sr) * bz;
    double e = sh * cp * bx + (sh * sp * sr + ch * cr) * by + (sh * sp * cr - ch * sr) * bz;
    double d = -sp * bx + cp * sr * by + cp * cr * bz;
    double az = atan2 (e, n) / r;
    *ret_azimuth_deg = az < 0 ? az + 360.0 : az;
    *ret_elevation_deg = -asin (fmax (-1.0, fmin (1.0, d))) / r;
}

Cgs__Uav *uavsim_msgs_uav (uavsim_msgs_t *self, uavsim_world_t *world, size_t i)
{
    const cgs_scenario_t *sc = uavsim_world_scenario (world);
    if (i >= sc->uav_count)
        return NULL;
    const cgs_scenario_uav_t *su = &sc->uavs[i];
    uavsim_uav_model_t *model = uavsim_world_uav (world, i);
    uavsim_uav_state_t u;
    uavsim_uav_state (model, &u);
    Cgs__Uav *m = &self->uav;
    cgs__uav__init (m);
    cgs__enu__init (&self->uav_pos);
    cgs__enu_velocity__init (&self->uav_vel);
    cgs__enu__init (&self->loiter_center);
    cgs__loiter_orbit__init (&self->loiter);
    cgs__imaging_sensor__init (&self->sensor);
    self->uav_pos.east_m = u.position.e_m;
    self->uav_pos.north_m = u.position.n_m;
    self->uav_pos.up_m = u.position.u_m;
    self->uav_vel.east_mps = u.velocity.e_m;
    self->uav_vel.north_mps = u.velocity.n_m;
    self->uav_vel.up_mps = u.velocity.u_m;
    m->entity_id = su->id;
    m->name = (char *)su->name;
    m->position = &self->uav_pos;
    m->velocity = &self->uav_vel;
    m->heading_deg = u.heading_deg;
    m->pitch_deg = u.pitch_deg;
    m->roll_deg = u.roll_deg;
    m->airspeed_mps = u.airspeed_mps;
    m->ground_speed_mps = hypot (u.velocity.e_m, u.velocity.n_m);
    m->altitude_agl_m =
        u.position.u_m -
        cgs_terrain_height_clamped (uavsim_world_terrain (world), u.position.e_m, u.position.n_m);
    m->commanded_altitude_agl_m = u.commanded_agl_m;
    m->commanded_airspeed_mps = u.commanded_airspeed_mps;
    m->mode = (Cgs__UavMode)u.mode;
    self->loiter_center.east_m = u.loiter_center.e_m;
    self->loiter_center.north_m = u.loiter_center.n_m;
    self->loiter.center = &self->loiter_center;
    self->loiter.radius_m = u.loiter_radius_m;
    self->loiter.clockwise = u.loiter_clockwise;
    m->loiter = &self->loiter;
    size_t n = 0;
    const cgs_enu_t *pts = uavsim_uav_route_points (model, &n);
    for (size_t k = 0; k < n && k < UAVSIM_UAV_ROUTE_MAX; k++) {
        cgs__enu__init (&self->route[k]);
        self->route[k].east_m = pts[k].e_m;
        self->route[k].north_m = pts[k].n_m;
        self->route_ptrs[k] = &self->route[k];
    }
    m->n_route = n;
    m->route = self->route_ptrs;
    m->route_index = (uint32_t)u.route_index;
    const uavsim_camera_t *cs = uavsim_world_camera (world, i);
    const cgs_terrain_t *terrain = uavsim_world_terrain (world);
    cgs__enu__init (&self->stare_point);
    self->sensor.depression_deg = cs->depression_deg;
    self->sensor.hfov_deg = cs->hfov_deg;
    self->sensor.vfov_deg = cs->vfov_deg;
    self->sensor.stabilized = cs->stabilized;
    self->sensor.stare = (Cgs__StareMode)cs->stare;
    self->sensor.gimbal_azimuth_limit_deg = su->gimbal_azimuth_limit_deg;
    self->sensor.gimbal_elevation_min_deg = su->gimbal_elevation_min_deg;
    self->sensor.gimbal_elevation_max_deg = su->gimbal_elevation_max_deg;
    cgs_enu_t stare_at;
    bool staring = uavsim_camera_stare_at (cs, terrain, uavsim_world_time (world), &stare_at);
    if (staring) {
        self->stare_point.east_m = stare_at.e_m;
        self->stare_point.north_m = stare_at.n_m;
        self->stare_point.up_m = stare_at.u_m;
        self->sensor.stare_point = &self->stare_point;
    }
    self->sensor.staring = staring;
    m->sensor = &self->sensor;
    m->bank_limit_deg = su->bank_limit_deg;
    m->radar_params = su->radar_params ? su->radar_params : "";
    m->bcis_params = su->bcis_params ? su->bcis_params : "";
    m->task_number = u.task_number;
    // The camera's attitude, as every service will build the camera from this message.
    cgs_camera_in_t in = {.width_px = 2, .height_px = 2, .near_m = 1, .far_m = 2};
    cgs_camera_t cam;
    if (cgs_msg_uav_camera (m, &in) == 0 && cgs_camera_make (&in, &cam) == 0) {
        m->sensor_azimuth_deg = cam.heading_deg;
        m->sensor_elevation_deg = cam.pitch_deg;
        m->sensor_roll_deg = cam.roll_deg;
        self->sensor.at_gimbal_limit = cam.at_gimbal_limit;
    } else {
        uavsim_msgs_boresight (u.heading_deg, u.pitch_deg, u.roll_deg, cs->depression_deg,
                               &m->sensor_azimuth_deg, &m->sensor_elevation_deg);
    }
    return m;
}

Cgs__Clock *uavsim_msgs_clock (uavsim_msgs_t *self, const uavsim_world_t *world, double time_scale,
                               bool paused, cgs_geodetic_t origin)
{
    Cgs__Clock *c = &self->clock;
    cgs__clock__init (c);
    cgs__geodetic__init (&self->origin);
    self->origin.lat_deg = origin.lat_deg;
    self->origin.lon_deg = origin.lon_deg;
    self->origin.height_m = origin.height_m;
    c->sim_time_s = uavsim_world_time (world);
    c->time_scale = time_scale;
    c->paused = paused;
    c->tick = uavsim_world_tick (world);
    c->step_s = uavsim_world_step_s (world);
    c->origin = &self->origin;
    return c;
}
