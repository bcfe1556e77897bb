/* cgs_sensor — the UAV, scenario and terrain of a sensor service (see cgs_sensor.h). */
#include "cgs_sensor.h"
#include "cgs_util.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <syslog.h>

/* The model's seed: from the exercise seed, the UAV's id and the service's salt. */
static uint64_t s_seed (uint64_t exercise_seed, uint32_t uav_id, uint64_t salt)
{
    return exercise_seed * 0x9E3779B97F4A7C15ull ^ (uint64_t)uav_id * salt;
}

int cgs_sensor_setup (cgs_sensor_t *self, const cgs_service_t *svc, const char *program,
                      uint64_t salt, char *err, size_t errlen)
{
    if (!*cgs_service_instance (svc)->uav) {
        cgs_errf (err, errlen, "%s: [service %s] names no `uav =`: %s serves one UAV",
                  cgs_service_exercise_path (svc), cgs_service_instance_name (svc), program);
        return -EINVAL;
    }
    snprintf (self->uav_name, sizeof self->uav_name, "%s", cgs_service_instance (svc)->uav);
    if (!*cgs_service_scenario_path (svc)) {
        cgs_errf (err, errlen,
                  "no scenario (its terrain is needed): give --scenario FILE or `scenario =` in %s",
                  cgs_service_exercise_path (svc));
        return -EINVAL;
    }
    cgs_geodetic_t o = cgs_exercise_origin (cgs_service_exercise (svc));
    if (!(self->frame = cgs_geo_new (o.lat_deg, o.lon_deg, o.height_m))) {
        cgs_errf (err, errlen, "%s: bad exercise origin", cgs_service_exercise_path (svc));
        return -EINVAL;
    }
    uint64_t seed = cgs_exercise_seed (cgs_service_exercise (svc));
    int rc = cgs_scenario_load (cgs_service_scenario_path (svc), self->frame, seed, &self->scenario,
                                err, errlen);
    if (rc < 0)
        return rc;
    if (!(self->uav = cgs_scenario_uav (self->scenario, self->uav_name))) {
        cgs_errf (err, errlen, "%s: no [uav %s] (named by [service %s] in %s)",
                  cgs_service_scenario_path (svc), self->uav_name, cgs_service_instance_name (svc),
                  cgs_service_exercise_path (svc));
        return -EINVAL;
    }
    self->seed = s_seed (seed, self->uav->id, salt);
    return cgs_scenario_terrain (self->scenario, self->frame, &self->terrain, err, errlen);
}

int cgs_sensor_attach (cgs_sensor_t *self, const char *uav_name, cgs_geo_t *frame,
                       cgs_scenario_t *scenario, cgs_terrain_t *terrain, uint64_t exercise_seed,
                       uint64_t salt, char *err, size_t errlen)
{
    const cgs_scenario_uav_t *u = cgs_scenario_uav (scenario, uav_name);
    if (!u) {
        cgs_errf (err, errlen, "the scenario has no [uav %s]", uav_name);
        return -EINVAL;
    }
    memset (self, 0, sizeof *self);
    snprintf (self->uav_name, sizeof self->uav_name, "%s", uav_name);
    self->borrowed = true;
    self->frame = frame;
    self->scenario = scenario;
    self->terrain = terrain;
    self->uav = u;
    self->seed = s_seed (exercise_seed, u->id, salt);
    return 0;
}

void cgs_sensor_fini (cgs_sensor_t *self)
{
    if (self->borrowed) {
        self->terrain = NULL;
        self->scenario = NULL;
        self->frame = NULL;
    }
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

bool cgs_sensor_on_uav (cgs_sensor_t *self, const Cgs__Uav *u, double t_s, const cgs_scan_t *scan,
                        cgs_scan_pace_t *pace, double history_s, const char *what,
                        const cgs_port_t *port, uint64_t *ret_end)
{
    bool new_id = false;
    int rc = cgs_sensor_take_uav (self, u, t_s, &new_id);
    if (rc > 0)
        return false; // another UAV's
    if (rc < 0) {
        cgs_port_bad_input (port, "a uav message without a valid time, position, velocity or "
                                  "heading");
        return false;
    }
    if (new_id)
        cgs_port_log (port, LOG_INFO, "%s on %s (entity %u) at t=%.2f s", what, self->uav_name,
                      self->uav_id, t_s);
    uint64_t skipped;
    cgs_pace_t how = cgs_scan_pace (scan, pace, t_s, history_s, ret_end, &skipped);
    if (how == CGS_PACE_BACK)
        cgs_port_log (port, LOG_NOTICE, "simulation time went back to %.2f s; the scan follows",
                      t_s);
    if (skipped) {
        cgs_port_error (port, "fell behind: %llu dwells skipped in all",
                        (unsigned long long)pace->skipped);
        cgs_port_log (port, LOG_WARNING, "fell behind: %llu dwells skipped in all",
                      (unsigned long long)pace->skipped);
    }
    return true;
}
