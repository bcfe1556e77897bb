/* uavsim_camera — how each UAV's imaging sensor is set: its depression
 * angle, fields of view, stabilization and stare (off, a point, or the
 * designated target as guidanced estimates it on `intercept`), starting from
 * the scenario and changed by the camera command within the scenario's
 * limits. uavsim publishes it on `uav`, with the stare point it looks at and
 * the camera's attitude (common/cgs_camera.h), so that every service builds
 * the same camera. Pure: no logging. */
#ifndef UAVSIM_CAMERA_H
#define UAVSIM_CAMERA_H

#include "cgs_geo.h"
#include "cgs_scenario.h"
#include "cgs_terrain.h"

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

typedef enum {
    UAVSIM_STARE_OFF = 0,    // fixed in the body
    UAVSIM_STARE_POINT = 1,  // at a point on the ground
    UAVSIM_STARE_TARGET = 2, // at the designated target
} uavsim_stare_t;

/* What a camera command may set (its `set` bits). */
#define UAVSIM_CAMERA_SET_DEPRESSION 1u
#define UAVSIM_CAMERA_SET_FOV        2u
#define UAVSIM_CAMERA_SET_STABILIZED 4u
#define UAVSIM_CAMERA_SET_STARE      8u

typedef struct {
    double depression_deg;
    double hfov_deg, vfov_deg; // the vertical keeps the scenario's aspect
    bool stabilized;
    uavsim_stare_t stare;
    cgs_enu_t stare_point; // STARE_POINT: on the ground
    /* STARE_TARGET: guidanced's latest estimate (not saved: the next
     * `intercept` brings it again). */
    bool have_target;
    cgs_enu_t target, target_vel;
    double target_t_s;
} uavsim_camera_t;

/* The scenario's settings for UAV su. */
void uavsim_camera_init (uavsim_camera_t *c, const cgs_scenario_uav_t *su);

/* A camera command's settings, the fields named in set. */
typedef struct {
    uint32_t set;
    double depression_deg;
    double hfov_deg;
    bool stabilized;
    uavsim_stare_t stare;
    cgs_enu_t stare_point; // its up is taken from the terrain
} uavsim_camera_cmd_t;

/* Apply cmd to c, whole or not at all: 0, or -EINVAL with why (a value
 * outside the scenario's limits, an unknown stare mode, a stare point off
 * the terrain or not finite, nothing set) and c unchanged. */
int uavsim_camera_set (uavsim_camera_t *c, const cgs_scenario_uav_t *su,
                       const cgs_terrain_t *terrain, const uavsim_camera_cmd_t *cmd, char *why,
                       size_t whylen);

/* guidanced's estimate of the designated target at time t_s (have false:
 * none designated). */
void uavsim_camera_target (uavsim_camera_t *c, bool have, cgs_enu_t p, cgs_enu_t v, double t_s);

/* Where the camera stares at time t_s: true with the point (the target's
 * estimate moved on along its velocity to t_s, on the terrain), false when it
 * does not stare or has no target. */
bool uavsim_camera_stare_at (const uavsim_camera_t *c, const cgs_terrain_t *terrain, double t_s,
                             cgs_enu_t *ret);

/* The settings as a byte string for the world's checkpoint (fixed size),
 * and back: 0 or -EPROTO. */
#define UAVSIM_CAMERA_SAVED 48
void uavsim_camera_save (const uavsim_camera_t *c, uint8_t out[UAVSIM_CAMERA_SAVED]);
int uavsim_camera_load (uavsim_camera_t *c, const cgs_scenario_uav_t *su, const uint8_t *buf,
                        size_t len);

#endif
