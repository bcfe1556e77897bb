/* uavsim_world — terrain, UAVs and vehicles of a scenario in fixed steps. */
#include "uavsim_world.h"
#include "cgs_ckpt.h"
#include "cgs_util.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#define S_MAGIC   "UWLD" // cgs_ckpt kind of the world's checkpoint
#define S_VERSION 2u     // 2: each UAV's camera settings after the entities
#define S_WHAT    "uavsim world checkpoint"

struct uavsim_world {
    cgs_scenario_t *scenario;
    cgs_terrain_t *terrain;
    uavsim_uav_model_t **uavs;
    uavsim_camera_t *cameras; // each UAV's imaging sensor settings
    uavsim_vehicle_t **vehicles;
    double step_s;
    uint64_t tick;        // steps taken
    double time_s;        // tick * step_s, kept as a product so it never drifts
    uint64_t fingerprint; // of the scenario's entities, to match checkpoints
};

void uavsim_world_destroy (uavsim_world_t **self_p)
{
    if (!self_p || !*self_p)
        return;
    uavsim_world_t *self = *self_p;
    if (self->scenario) {
        for (size_t i = 0; self->uavs && i < self->scenario->uav_count; i++)
            uavsim_uav_destroy (&self->uavs[i]);
        for (size_t i = 0; self->vehicles && i < self->scenario->vehicle_count; i++)
            uavsim_vehicle_destroy (&self->vehicles[i]);
    }
    free (self->uavs);
    free (self->cameras);
    free (self->vehicles);
    cgs_terrain_destroy (&self->terrain);
    cgs_scenario_destroy (&self->scenario);
    free (self);
    *self_p = NULL;
}

static uint64_t s_bits (double d)
{
    uint64_t b;
    memcpy (&b, &d, sizeof b);
    return b;
}

/* FNV-1a over what a checkpoint must match: the step, the terrain, the UAVs'
 * limits, the entity ids, names and route sizes (each vehicle also checks its
 * own parameters). */
static uint64_t s_fingerprint (const cgs_scenario_t *sc)
{
    uint64_t h = 1469598103934665603ull;
#define S_MIX(v)                                                                                   \
    do {                                                                                           \
        h ^= (uint64_t)(v);                                                                        \
        h *= 1099511628211ull;                                                                     \
    } while (0)
    S_MIX (sc->uav_count);
    S_MIX (sc->vehicle_count);
    // What the dynamic state depends on besides the entities: the step, the
    // terrain and every UAV's flight limits.
    S_MIX (s_bits (sc->settings.step_s));
    S_MIX (sc->terrain.source);
    S_MIX (sc->terrain.fbm.seed);
    S_MIX (s_bits (sc->terrain.fbm.size_m));
    S_MIX (s_bits (sc->terrain.fbm.resolution_m));
    S_MIX (s_bits (sc->terrain.fbm.relief_m));
    S_MIX (s_bits (sc->terrain.fbm.base_height_m));
    S_MIX (s_bits (sc->terrain.resolution_m));
    S_MIX (s_bits (sc->terrain.half_extent_m));
    for (const char *c = sc->terrain.dem_path ? sc->terrain.dem_path : ""; *c; c++)
        S_MIX ((unsigned char)*c);
    for (size_t i = 0; i < sc->uav_count; i++) {
        S_MIX (s_bits (sc->uavs[i].bank_limit_deg));
        S_MIX (s_bits (sc->uavs[i].climb_rate_mps));
        S_MIX (s_bits (sc->uavs[i].airspeed_mps));
        S_MIX (s_bits (sc->uavs[i].loiter_radius_m));
        S_MIX (s_bits (sc->uavs[i].airspeed_min_mps));
        S_MIX (s_bits (sc->uavs[i].airspeed_max_mps));
    }
    for (size_t i = 0; i < sc->uav_count; i++) {
        S_MIX (sc->uavs[i].id);
        for (const char *c = sc->uavs[i].name; *c; c++)
            S_MIX ((unsigned char)*c);
    }
    for (size_t i = 0; i < sc->vehicle_count; i++) {
        S_MIX (sc->vehicles[i].id);
        S_MIX (sc->vehicles[i].point_count);
        for (const char *c = sc->vehicles[i].name; *c; c++)
            S_MIX ((unsigned char)*c);
    }
#undef S_MIX
    return h;
}

static int s_build_terrain (uavsim_world_t *self, const cgs_geo_t *frame, char *err, size_t errlen)
{
    return cgs_scenario_terrain (self->scenario, frame, &self->terrain, err, errlen);
}

static int s_build_uav (uavsim_world_t *self, size_t i, char *err, size_t errlen)
{
    const cgs_scenario_uav_t *u = &self->scenario->uavs[i];
    uavsim_uav_params_t p;
    uavsim_uav_params_defaults (&p);
    p.bank_limit_deg = u->bank_limit_deg;
    p.climb_rate_mps = u->climb_rate_mps;
    p.loiter_radius_m = u->loiter_radius_m;
    p.airspeed_min_mps = u->airspeed_min_mps;
    p.airspeed_max_mps = u->airspeed_max_mps;
    uavsim_uav_init_t init = {0};
    init.position = u->position;
    init.position.u_m =
        cgs_terrain_height_clamped (self->terrain, u->position.e_m, u->position.n_m) +
        u->altitude_agl_m;
    init.heading_deg = u->heading_deg;
    init.airspeed_mps = u->airspeed_mps;
    init.agl_m = u->altitude_agl_m;
    init.loiter_radius_m = u->loiter_radius_m;
    init.loiter_clockwise = u->loiter_clockwise;
    self->uavs[i] = uavsim_uav_new (&p, &init);
    if (!self->uavs[i]) {
        cgs_errf (err, errlen, "%s:%d: [uav %s]: the flight model refused these values",
                  self->scenario->path, u->line, u->name);
        return -EINVAL;
    }
    // Its first task: the scenario's loiter orbit.
    if (uavsim_uav_loiter (self->uavs[i], u->loiter_center, u->loiter_radius_m,
                           u->loiter_clockwise) < 0) {
        cgs_errf (err, errlen, "%s:%d: [uav %s]: the loiter orbit cannot be flown",
                  self->scenario->path, u->line, u->name);
        return -EINVAL;
    }
    return 0;
}

static int s_build_vehicle (uavsim_world_t *self, size_t i, char *err, size_t errlen)
{
    const cgs_scenario_vehicle_t *v = &self->scenario->vehicles[i];
    uavsim_vehicle_point_t *pts = calloc (v->point_count, sizeof *pts);
    if (!pts)
        return -ENOMEM;
    for (size_t k = 0; k < v->point_count; k++) {
        pts[k].e_m = v->points[k].position.e_m;
        pts[k].n_m = v->points[k].position.n_m;
        pts[k].speed_mps = v->points[k].speed_mps;
    }
    double *halts = calloc (v->point_count, sizeof *halts);
    if (!halts) {
        free (pts);
        return -ENOMEM;
    }
    for (size_t k = 0; k < v->point_count; k++)
        halts[k] = v->points[k].halt_s;
    uavsim_vehicle_params_t p;
    uavsim_vehicle_params_defaults (&p);
    p.halt_s = halts;
    p.points = pts;
    p.n_points = v->point_count;
    p.speed_mps = v->speed_mps;
    p.start_time_s = v->start_time_s;
    p.end = v->end == CGS_END_LOOP      ? UAVSIM_VEHICLE_END_LOOP
            : v->end == CGS_END_REVERSE ? UAVSIM_VEHICLE_END_REVERSE
                                        : UAVSIM_VEHICLE_END_STOP;
    p.deviation_m = v->deviation_m;
    p.seed = v->deviation_seed;
    if (v->kind == CGS_KIND_PERSON) {
        p.lat_accel_mps2 = 1.0;
        p.turn_rate_dps = 90;
        p.accel_mps2 = 0.5;
        p.decel_mps2 = 1.0;
        p.corner_cut_m = 1;
    }
    char why[256] = "";
    int rc = uavsim_vehicle_params_check (&p, why, sizeof why);
    if (rc == 0)
        rc = uavsim_vehicle_new (&p, &self->vehicles[i]);
    free (pts);
    free (halts);
    if (rc < 0) {
        cgs_errf (err, errlen, "%s:%d: [vehicle %s]: %s", self->scenario->path, v->line, v->name,
                  *why ? why : "the vehicle model refused these values");
        return rc;
    }
    return 0;
}

int uavsim_world_new (cgs_scenario_t *scenario, const cgs_geo_t *frame, uavsim_world_t **ret_w,
                      char *err, size_t errlen)
{
    if (!scenario || !ret_w)
        return -EINVAL;
    int rc = -ENOMEM;
    uavsim_world_t *self = calloc (1, sizeof *self);
    if (!self) {
        cgs_scenario_destroy (&scenario);
        return -ENOMEM;
    }
    self->scenario = scenario;
    self->step_s = scenario->settings.step_s;
    self->fingerprint = s_fingerprint (scenario);
    self->uavs = calloc (scenario->uav_count ? scenario->uav_count : 1, sizeof *self->uavs);
    self->cameras = calloc (scenario->uav_count ? scenario->uav_count : 1, sizeof *self->cameras);
    self->vehicles =
        calloc (scenario->vehicle_count ? scenario->vehicle_count : 1, sizeof *self->vehicles);
    for (size_t i = 0; self->cameras && i < scenario->uav_count; i++)
        uavsim_camera_init (&self->cameras[i], &scenario->uavs[i]);
    if (!self->uavs || !self->cameras || !self->vehicles)
        goto fail;
    if ((rc = s_build_terrain (self, frame, err, errlen)) < 0)
        goto fail;
    for (size_t i = 0; i < scenario->uav_count; i++)
        if ((rc = s_build_uav (self, i, err, errlen)) < 0)
            goto fail;
    for (size_t i = 0; i < scenario->vehicle_count; i++)
        if ((rc = s_build_vehicle (self, i, err, errlen)) < 0)
            goto fail;
    *ret_w = self;
    return 0;
fail:
    if (rc == -ENOMEM)
        cgs_errf (err, errlen, "out of memory");
    uavsim_world_destroy (&self);
    return rc;
}

void uavsim_world_step (uavsim_world_t *self)
{
    double t = self->time_s;
    for (size_t i = 0; i < self->scenario->uav_count; i++) {
        uavsim_uav_state_t s;
        uavsim_uav_state (self->uavs[i], &s);
        double h = cgs_terrain_height_clamped (self->terrain, s.position.e_m, s.position.n_m);
        uavsim_uav_step (self->uavs[i], self->step_s, h);
    }
    for (size_t i = 0; i < self->scenario->vehicle_count; i++)
        uavsim_vehicle_step (self->vehicles[i], t, self->step_s);
    self->tick++;
    self->time_s = (double)self->tick * self->step_s;
}

double uavsim_world_time (const uavsim_world_t *self)
{
    return self->time_s;
}
uint64_t uavsim_world_tick (const uavsim_world_t *self)
{
    return self->tick;
}
double uavsim_world_step_s (const uavsim_world_t *self)
{
    return self->step_s;
}
const cgs_scenario_t *uavsim_world_scenario (const uavsim_world_t *self)
{
    return self->scenario;
}
const cgs_terrain_t *uavsim_world_terrain (const uavsim_world_t *self)
{
    return self->terrain;
}

uavsim_camera_t *uavsim_world_camera (uavsim_world_t *self, size_t i)
{
    return i < self->scenario->uav_count ? &self->cameras[i] : NULL;
}

uavsim_uav_model_t *uavsim_world_uav (uavsim_world_t *self, size_t i)
{
    return i < self->scenario->uav_count ? self->uavs[i] : NULL;
}

const uavsim_vehicle_t *uavsim_world_vehicle (const uavsim_world_t *self, size_t i)
{
    return i < self->scenario->vehicle_count ? self->vehicles[i] : NULL;
}

int uavsim_world_find_uav (const uavsim_world_t *self, uint32_t entity_id)
{
    if (entity_id == 0)
        return self->scenario->uav_count == 1 ? 0 : -ENOENT;
    for (size_t i = 0; i < self->scenario->uav_count; i++)
        if (self->scenario->uavs[i].id == entity_id)
            return (int)i;
    return -ENOENT;
}

/* ---- checkpoint -------------------------------------------------------------------
 * A cgs_ckpt frame "UWLD", version 2. Payload: u64 fingerprint, u64 tick,
 * u32 uav count, u32 vehicle count, then each UAV's and each vehicle's own
 * frame (as bytes: its model decodes and checks it), then each UAV's camera
 * settings (uavsim_camera_save). */

int uavsim_world_save (const uavsim_world_t *self, uint8_t **ret_buf, size_t *ret_len)
{
    const cgs_scenario_t *sc = self->scenario;
    cgs_ckpt_writer_t w;
    cgs_ckpt_writer_init (&w, S_MAGIC, S_VERSION);
    cgs_ckpt_put_u64 (&w, self->fingerprint);
    cgs_ckpt_put_u64 (&w, self->tick);
    cgs_ckpt_put_u32 (&w, (uint32_t)sc->uav_count);
    cgs_ckpt_put_u32 (&w, (uint32_t)sc->vehicle_count);
    for (size_t i = 0; i < sc->uav_count + sc->vehicle_count; i++) {
        uint8_t *b = NULL;
        size_t n = 0;
        int rc = i < sc->uav_count
                     ? uavsim_uav_save (self->uavs[i], &b, &n)
                     : uavsim_vehicle_save (self->vehicles[i - sc->uav_count], &b, &n);
        if (rc < 0) {
            cgs_ckpt_writer_fini (&w);
            return rc;
        }
        cgs_ckpt_put_bytes (&w, b, n);
        free (b);
    }
    for (size_t i = 0; i < sc->uav_count; i++) {
        uint8_t cam[UAVSIM_CAMERA_SAVED];
        uavsim_camera_save (&self->cameras[i], cam);
        cgs_ckpt_put_bytes (&w, cam, sizeof cam);
    }
    return cgs_ckpt_writer_finish (&w, ret_buf, ret_len);
}

/* The payload's fields before the entities' frames. */
typedef struct {
    uint64_t fingerprint, tick;
    uint32_t uavs, vehicles;
} s_head_t;

static s_head_t s_get_head (cgs_ckpt_reader_t *r)
{
    s_head_t h;
    h.fingerprint = cgs_ckpt_get_u64 (r);
    h.tick = cgs_ckpt_get_u64 (r);
    h.uavs = cgs_ckpt_get_u32 (r);
    h.vehicles = cgs_ckpt_get_u32 (r);
    return h;
}

/* Restore every entity, in order, from r (past the header); 0, or the first
 * failure with its reason in err (the entities before it are restored). */
static int s_restore_entities (uavsim_world_t *self, cgs_ckpt_reader_t *r, char *err, size_t errlen)
{
    const cgs_scenario_t *sc = self->scenario;
    for (size_t i = 0; i < sc->uav_count + sc->vehicle_count; i++) {
        size_t n = 0;
        const uint8_t *b = cgs_ckpt_get_bytes (r, &n);
        char why[256] = "";
        bool uav = i < sc->uav_count;
        int rc =
            uav ? uavsim_uav_restore (self->uavs[i], b, n, why, sizeof why)
                : uavsim_vehicle_restore (self->vehicles[i - sc->uav_count], b, n, why, sizeof why);
        if (rc < 0) {
            cgs_errf (err, errlen, "%s %s: %s", uav ? "uav" : "vehicle",
                      uav ? sc->uavs[i].name : sc->vehicles[i - sc->uav_count].name, why);
            return rc;
        }
    }
    for (size_t i = 0; i < sc->uav_count; i++) {
        size_t n = 0;
        const uint8_t *b = cgs_ckpt_get_bytes (r, &n);
        uavsim_camera_t *c = &self->cameras[i];
        if (uavsim_camera_load (c, &sc->uavs[i], b, n) < 0) {
            cgs_errf (err, errlen, "uav %s: its camera settings are damaged", sc->uavs[i].name);
            return -EPROTO;
        }
        c->stare_point.u_m =
            cgs_terrain_height_clamped (self->terrain, c->stare_point.e_m, c->stare_point.n_m);
    }
    return 0;
}

int uavsim_world_restore (uavsim_world_t *self, const uint8_t *buf, size_t len, char *err,
                          size_t errlen)
{
    const cgs_scenario_t *sc = self->scenario;
    cgs_ckpt_reader_t r;
    int rc = cgs_ckpt_open (&r, buf, len, S_MAGIC, S_VERSION, S_WHAT, err, errlen);
    if (rc < 0)
        return rc;
    s_head_t h = s_get_head (&r);
    if (cgs_ckpt_ok (&r) && (h.fingerprint != self->fingerprint || h.uavs != sc->uav_count ||
                             h.vehicles != sc->vehicle_count)) {
        cgs_errf (err, errlen, "a %s of another scenario (its entities differ)", S_WHAT);
        return -EPROTO;
    }
    // Every entity's frame is there, and nothing after them, before any is touched.
    cgs_ckpt_reader_t entities = r;
    for (size_t i = 0; i < 2 * sc->uav_count + sc->vehicle_count; i++) {
        size_t n;
        (void)cgs_ckpt_get_bytes (&r, &n);
    }
    if ((rc = cgs_ckpt_end (&r, S_WHAT, err, errlen)) < 0)
        return rc;
    // Each model leaves itself unchanged when its own frame is refused; save
    // the present state so a failure part way through can be rolled back.
    uint8_t *before = NULL;
    size_t before_len = 0;
    if ((rc = uavsim_world_save (self, &before, &before_len)) < 0)
        return rc;
    rc = s_restore_entities (self, &entities, err, errlen);
    if (rc < 0) {
        cgs_ckpt_reader_t back;
        if (cgs_ckpt_open (&back, before, before_len, S_MAGIC, S_VERSION, S_WHAT, NULL, 0) == 0) {
            (void)s_get_head (&back);
            (void)s_restore_entities (self, &back, NULL, 0);
        }
        free (before);
        return rc;
    }
    free (before);
    self->tick = h.tick;
    self->time_s = (double)self->tick * self->step_s;
    return 0;
}
