/* cgs_sensor — the UAV, scenario and terrain of a sensor service (see cgs_sensor.h). */
#include "cgs_sensor.h"
#include "cgs_util.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

int cgs_sensor_setup (cgs_sensor_t *self, const cgs_service_t *svc, const char *program,
                      uint64_t salt, char *err, size_t errlen)
{
    if (!*svc->instance->uav) {
        cgs_errf (err, errlen, "%s: [service %s] names no `uav =`: %s serves one UAV",
                  svc->exercise_path, svc->instance_name, program);
        return -EINVAL;
    }
    snprintf (self->uav_name, sizeof self->uav_name, "%s", svc->instance->uav);
    if (!*svc->scenario) {
        cgs_errf (err, errlen,
                  "no scenario (its terrain is needed): give --scenario FILE or `scenario =` in %s",
                  svc->exercise_path);
        return -EINVAL;
    }
    cgs_geodetic_t o = cgs_exercise_origin (svc->exercise);
    if (!(self->frame = cgs_geo_new (o.lat_deg, o.lon_deg, o.height_m))) {
        cgs_errf (err, errlen, "%s: bad exercise origin", svc->exercise_path);
        return -EINVAL;
    }
    uint64_t seed = cgs_exercise_seed (svc->exercise);
    int rc = cgs_scenario_load (svc->scenario, self->frame, seed, &self->scenario, err, errlen);
    if (rc < 0)
        return rc;
    if (!(self->uav = cgs_scenario_uav (self->scenario, self->uav_name))) {
        cgs_errf (err, errlen, "%s: no [uav %s] (named by [service %s] in %s)", svc->scenario,
                  self->uav_name, svc->instance_name, svc->exercise_path);
        return -EINVAL;
    }
    self->seed = seed * 0x9E3779B97F4A7C15ull ^ (uint64_t)self->uav->id * salt;
    return cgs_scenario_terrain (self->scenario, self->frame, &self->terrain, err, errlen);
}

void cgs_sensor_fini (cgs_sensor_t *self)
{
    cgs_terrain_destroy (&self->terrain);
    cgs_scenario_destroy (&self->scenario);
    cgs_geo_destroy (&self->frame);
    self->uav = NULL;
}

static bool s_finite3 (double a, double b, double c)
{
    return isfinite (a) && isfinite (b) && isfinite (c);
}

int cgs_sensor_take_uav (cgs_sensor_t *self, const Cgs__Uav *u, double t_s, bool *ret_new_id)
{
    if (!u->name || strcmp (u->name, self->uav_name) != 0)
        return 1;
    if (!u->position || !u->velocity || !isfinite (t_s) || t_s < 0 || !isfinite (u->heading_deg) ||
        !s_finite3 (u->position->east_m, u->position->north_m, u->position->up_m) ||
        !s_finite3 (u->velocity->east_mps, u->velocity->north_mps, u->velocity->up_mps))
        return -EINVAL;
    if (ret_new_id)
        *ret_new_id = self->uav_id != u->entity_id;
    self->uav_id = u->entity_id;
    self->position = (cgs_enu_t){u->position->east_m, u->position->north_m, u->position->up_m};
    self->velocity =
        (cgs_enu_t){u->velocity->east_mps, u->velocity->north_mps, u->velocity->up_mps};
    self->heading_deg = u->heading_deg;
    self->time_s = t_s;
    return 0;
}

cgs_enu_t cgs_sensor_uav_at (const cgs_sensor_t *self, double t_s)
{
    double dt = t_s - self->time_s;
    return (cgs_enu_t){self->position.e_m + self->velocity.e_m * dt,
                       self->position.n_m + self->velocity.n_m * dt,
                       self->position.u_m + self->velocity.u_m * dt};
}
