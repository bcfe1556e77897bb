/* cgs_sensor — what the per-UAV sensor services (mtid, bcisd) share around
 * their models: the UAV they serve (the instance's `uav =`), the exercise
 * frame, the scenario with that UAV's section, the terrain, a seed for the
 * model, and the UAV as last heard on `uav`. Pure: no logging; errors name
 * the files and sections involved. */
#ifndef CGS_SENSOR_H
#define CGS_SENSOR_H

#include "cgs_port.h"
#include "cgs_scan.h"
#include "cgs_scenario.h"
#include "cgs_service.h"
#include "world.pb-c.h"

#include <stdbool.h>
#include <stdint.h>

typedef struct {
    char uav_name[CGS_NAME_MAX];
    cgs_geo_t *frame;
    cgs_scenario_t *scenario;
    const cgs_scenario_uav_t *uav; // its section in the scenario
    cgs_terrain_t *terrain;
    bool borrowed; // frame, scenario and terrain belong to the caller (cgs_sensor_attach)
    uint64_t seed; // for the model: from the exercise seed, the UAV's id and the service's salt
    /* The UAV as last heard on `uav`. */
    uint32_t uav_id;    // its entity id, 0 until the first message
    cgs_enu_t position; // antenna, local frame
    cgs_enu_t velocity; // metres per second
    double heading_deg; // clockwise from north
    double time_s;      // simulation time of that state
} cgs_sensor_t;

/* Read what a sensor service of program (for messages) needs: the
 * instance's UAV, the scenario (cgs_service_scenario_path), the UAV's section in it and
 * the terrain. 0, or -errno with the reason in err; cgs_sensor_fini frees
 * what was built either way. */
int cgs_sensor_setup (cgs_sensor_t *self, const cgs_service_t *svc, const char *program,
                      uint64_t salt, char *err, size_t errlen);
/* The same over a frame, scenario and terrain the caller keeps (the
 * lockstep engine shares one of each among all its services): for UAV
 * uav_name, with the exercise's seed and the service's salt. 0, or -EINVAL
 * with the reason in err when the scenario has no such UAV. */
int cgs_sensor_attach (cgs_sensor_t *self, const char *uav_name, cgs_geo_t *frame,
                       cgs_scenario_t *scenario, cgs_terrain_t *terrain, uint64_t exercise_seed,
                       uint64_t salt, char *err, size_t errlen);
/* Free what setup built (nothing that attach borrowed); safe on a
 * half-built or zeroed one. */
void cgs_sensor_fini (cgs_sensor_t *self);
/* Take a `uav` message of time t_s: 1 when it is another UAV's (ignored),
 * -EINVAL when it lacks a valid time, position, velocity or heading
 * (nothing taken), else 0 and *ret_new_id (may be NULL) says whether the
 * UAV's entity id is new. */
int cgs_sensor_take_uav (cgs_sensor_t *self, const Cgs__Uav *u, double t_s, bool *ret_new_id);
/* A `uav` message of time t_s for a scanning sensor (what: "radar",
 * "interrogator"): taken as cgs_sensor_take_uav does (another UAV's: false),
 * a malformed one reported as the port's bad input (false), a new UAV and
 * time going back logged through the port; then the scan is paced to t_s
 * (cgs_scan_pace, keeping history_s of dwells), dwells skipped reported as
 * the port's error and a warning. True when the dwells pace->next up to
 * *ret_end (excluded) have ended by t_s and are to run. */
bool cgs_sensor_on_uav (cgs_sensor_t *self, const Cgs__Uav *u, double t_s, const cgs_scan_t *scan,
                        cgs_scan_pace_t *pace, double history_s, const char *what,
                        const cgs_port_t *port, uint64_t *ret_end);
/* The UAV moved on along its velocity to time t_s. */
cgs_enu_t cgs_sensor_uav_at (const cgs_sensor_t *self, double t_s);

#endif
