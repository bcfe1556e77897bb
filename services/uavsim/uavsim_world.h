/* uavsim_world — the simulated world of uavsim: the terrain, every UAV and
 * ground vehicle of a scenario, and simulation time advanced in fixed steps.
 * Tasks reach the UAVs through it; it saves and restores its complete dynamic
 * state (a checkpoint) so a restarted uavsim continues where it was. Pure: no
 * sockets, clocks, globals or logging. */
#ifndef UAVSIM_WORLD_H
#define UAVSIM_WORLD_H

#include "cgs_scenario.h"
#include "uavsim_camera.h"
#include "uavsim_uav.h"
#include "uavsim_vehicle.h"

#include <stddef.h>
#include <stdint.h>

typedef struct uavsim_world uavsim_world_t;

/* A world at time 0 from a scenario, which it takes over (and frees); the
 * terrain is read or generated from it. 0, or -errno with the reason in err
 * (the scenario is freed then too). */
int uavsim_world_new (cgs_scenario_t *scenario, const cgs_geo_t *frame, uavsim_world_t **ret_w,
                      char *err, size_t errlen);
/* Free; accepts NULL; sets *self_p to NULL. */
void uavsim_world_destroy (uavsim_world_t **self_p);

/* Advance one fixed step (the scenario's step_s). */
void uavsim_world_step (uavsim_world_t *self);
/* Simulation time, seconds, and steps taken. */
double uavsim_world_time (const uavsim_world_t *self);
uint64_t uavsim_world_tick (const uavsim_world_t *self);
double uavsim_world_step_s (const uavsim_world_t *self);

const cgs_scenario_t *uavsim_world_scenario (const uavsim_world_t *self);
const cgs_terrain_t *uavsim_world_terrain (const uavsim_world_t *self);
/* The flight model of UAV i (scenario order), and vehicle i's model. */
uavsim_uav_model_t *uavsim_world_uav (uavsim_world_t *self, size_t i);
const uavsim_vehicle_t *uavsim_world_vehicle (const uavsim_world_t *self, size_t i);
/* UAV i's imaging sensor settings (NULL past the last UAV). */
uavsim_camera_t *uavsim_world_camera (uavsim_world_t *self, size_t i);
/* Index of the UAV with entity id (0: the only UAV, when there is one); -ENOENT. */
int uavsim_world_find_uav (const uavsim_world_t *self, uint32_t entity_id);

/* Serialise the dynamic state (time, every UAV, every vehicle, every UAV's
 * camera settings) into a new
 * malloc'd cgs_ckpt frame ("UWLD", each entity's own frame inside); 0 or
 * -ENOMEM. */
int uavsim_world_save (const uavsim_world_t *self, uint8_t **ret_buf, size_t *ret_len);
/* Restore a saved state into a world built from the same scenario; 0, or
 * one of cgs_ckpt's errors with the reason in err (-EPROTO also for a
 * checkpoint of another scenario; an entity's own error, its name in err,
 * for an entity its model refuses). The world is left unchanged. */
int uavsim_world_restore (uavsim_world_t *self, const uint8_t *buf, size_t len, char *err,
                          size_t errlen);

#endif
