/* uavsim_world — terrain, UAVs and vehicles of a scenario in fixed steps. */
#include "uavsim_world.h"
#include "cgs_util.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#define S_MAGIC   "UAVSIMW1" // checkpoint format, 8 bytes
#define S_VERSION 1u

struct uavsim_world {
    cgs_scenario_t *scenario;
    cgs_terrain_t *terrain;
    uavsim_uav_model_t **uavs;
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
    self->vehicles =
        calloc (scenario->vehicle_count ? scenario->vehicle_count : 1, sizeof *self->vehicles);
    if (!self->uavs || !self->vehicles)
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
 * "UAVSIMW1", u32 version, u64 fingerprint, u64 tick, u32 uav count, u32
 * vehicle count, then for each UAV and each vehicle a u32 length and its
 * model's own blob (each model checks its own integrity). Little-endian. */

static void s_put_u32 (uint8_t *p, uint32_t v)
{
    for (int i = 0; i < 4; i++)
        p[i] = (uint8_t)(v >> (8 * i));
}

static void s_put_u64 (uint8_t *p, uint64_t v)
{
    for (int i = 0; i < 8; i++)
        p[i] = (uint8_t)(v >> (8 * i));
}

static uint32_t s_get_u32 (const uint8_t *p)
{
    uint32_t v = 0;
    for (int i = 0; i < 4; i++)
        v |= (uint32_t)p[i] << (8 * i);
    return v;
}

static uint64_t s_get_u64 (const uint8_t *p)
{
    uint64_t v = 0;
    for (int i = 0; i < 8; i++)
        v |= (uint64_t)p[i] << (8 * i);
    return v;
}

#define S_HEAD (8 + 4 + 8 + 8 + 4 + 4)

int uavsim_world_save (const uavsim_world_t *self, uint8_t **ret_buf, size_t *ret_len)
{
    const cgs_scenario_t *sc = self->scenario;
    size_t total = S_HEAD;
    for (size_t i = 0; i < sc->uav_count; i++)
        total += 4 + uavsim_uav_save_size (self->uavs[i]);
    for (size_t i = 0; i < sc->vehicle_count; i++)
        total += 4 + uavsim_vehicle_save_size (self->vehicles[i]);
    uint8_t *buf = malloc (total);
    if (!buf)
        return -ENOMEM;
    memcpy (buf, S_MAGIC, 8);
    s_put_u32 (buf + 8, S_VERSION);
    s_put_u64 (buf + 12, self->fingerprint);
    s_put_u64 (buf + 20, self->tick);
    s_put_u32 (buf + 28, (uint32_t)sc->uav_count);
    s_put_u32 (buf + 32, (uint32_t)sc->vehicle_count);
    size_t off = S_HEAD;
    for (size_t i = 0; i < sc->uav_count + sc->vehicle_count; i++) {
        size_t n = 0;
        int rc = i < sc->uav_count
                     ? uavsim_uav_save (self->uavs[i], buf + off + 4, total - off - 4, &n)
                     : uavsim_vehicle_save (self->vehicles[i - sc->uav_count], buf + off + 4,
                                            total - off - 4, &n);
        if (rc < 0) {
            free (buf);
            return rc;
        }
        s_put_u32 (buf + off, (uint32_t)n);
        off += 4 + n;
    }
    *ret_buf = buf;
    *ret_len = off;
    return 0;
}

int uavsim_world_restore (uavsim_world_t *self, const uint8_t *buf, size_t len, char *err,
                          size_t errlen)
{
    const cgs_scenario_t *sc = self->scenario;
    if (len < S_HEAD || memcmp (buf, S_MAGIC, 8) != 0 || s_get_u32 (buf + 8) != S_VERSION) {
        cgs_errf (err, errlen, "not a uavsim checkpoint of this version");
        return -EPROTO;
    }
    if (s_get_u64 (buf + 12) != self->fingerprint || s_get_u32 (buf + 28) != sc->uav_count ||
        s_get_u32 (buf + 32) != sc->vehicle_count) {
        cgs_errf (err, errlen, "the checkpoint is of another scenario (its entities differ)");
        return -EPROTO;
    }
    // Restore into fresh models first, so a damaged checkpoint leaves the world as it was.
    size_t n = sc->uav_count + sc->vehicle_count;
    int rc = 0;
    // Check every blob's framing before touching anything.
    size_t off = S_HEAD;
    for (size_t i = 0; i < n; i++) {
        if (len - off < 4 || s_get_u32 (buf + off) > len - off - 4) {
            cgs_errf (err, errlen, "the checkpoint is truncated (entity %zu of %zu)", i + 1, n);
            return -EPROTO;
        }
        off += 4 + s_get_u32 (buf + off);
    }
    if (off != len) {
        cgs_errf (err, errlen, "the checkpoint has %zu bytes too many", len - off);
        return -EPROTO;
    }
    // Each model leaves itself unchanged when its own blob is damaged; save
    // the present state so a failure part way through can be rolled back.
    uint8_t *before = NULL;
    size_t before_len = 0;
    if ((rc = uavsim_world_save (self, &before, &before_len)) < 0)
        return rc;
    off = S_HEAD;
    for (size_t i = 0; i < n && rc == 0; i++) {
        uint32_t bl = s_get_u32 (buf + off);
        rc = i < sc->uav_count
                 ? uavsim_uav_restore (self->uavs[i], buf + off + 4, bl)
                 : uavsim_vehicle_restore (self->vehicles[i - sc->uav_count], buf + off + 4, bl);
        if (rc < 0)
            cgs_errf (err, errlen, "the checkpoint of %s %s is damaged",
                      i < sc->uav_count ? "uav" : "vehicle",
                      i < sc->uav_count ? sc->uavs[i].name : sc->vehicles[i - sc->uav_count].name);
        off += 4 + bl;
    }
    if (rc < 0) {
        off = S_HEAD; // roll back what was restored
        for (size_t i = 0; i < n; i++) {
            uint32_t bl = s_get_u32 (before + off);
            if (i < sc->uav_count)
                uavsim_uav_restore (self->uavs[i], before + off + 4, bl);
            else
                uavsim_vehicle_restore (self->vehicles[i - sc->uav_count], before + off + 4, bl);
            off += 4 + bl;
        }
        free (before);
        return -EPROTO;
    }
    free (before);
    self->tick = s_get_u64 (buf + 20);
    self->time_s = (double)self->tick * self->step_s;
    return 0;
}
