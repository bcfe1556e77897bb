/* uavsim_uav — the flight model of one fixed-wing UAV in the exercise's local
 * east-north-up frame (metres), with no wind (airspeed = ground speed,
 * heading = course). Coordinated turns (turn rate g·tan(bank)/V) with a bank
 * limit and a roll rate; airspeed held at a limited acceleration; altitude
 * above ground held by a first-order law limited by the climb rate; straight
 * legs and loiter circles tracked with the nonlinear L1 guidance law of Park,
 * Deyst and How (AIAA GNC 2004; JGCD 2007).
 *
 * Guidance (an autopilot cycle of at most 0.02 s: a step is split into equal
 * cycles; each samples guidance at its start):
 *   L1 = (1/pi)·damping·period·V; a reference point on the path at distance L1
 *   from the UAV, ahead; eta = angle from the velocity to that point;
 *   a_cmd = 2·V²/L·sin(eta), L the distance to the point when nearer than L1
 *   (on the L1 circle, L = L1), else L1; sin(eta) taken as ±1 when |eta| > 90°;
 *   bank_cmd = atan(a_cmd/g), limited to ±bank_limit; the bank follows it at
 *   no more than the roll rate.
 *   - Straight leg A->B: the point on the line AB, ahead, L1 from the UAV; the
 *     foot of the perpendicular when the UAV is more than L1 off the line.
 *   - Loiter circle: the point on the circle, L1 from the UAV, ahead in the
 *     direction of circulation (on the circle this gives exactly V²/R). When
 *     the L1 circle does not meet the orbit: from outside, the tangent point
 *     on the circulation side; from well inside (d < R - L1), the orbit point
 *     at angle acos((d + R)/2R) ahead of the UAV, whose direction points
 *     outward, so the UAV spirals out; near an orbit smaller than L1, the
 *     orbit point a quarter turn ahead (which still gives V²/R on it). A circle
 *     tighter than the bank limit allows is flown as tight as it allows.
 * Altitude: up_cmd = terrain + commanded AGL; climb = terrain rate + (up_cmd -
 * up)/tau (exact exponential over the step), limited to ±climb rate. The
 * terrain rate is the change of the caller's terrain height between steps, so
 * on a constant slope the AGL settles exactly. Airspeed moves to its command
 * at no more than the airspeed acceleration.
 * Integration, per cycle: bank and speed at the cycle's midpoint, course and
 * position along the exact circular arc, so a steady turn is a true circle at
 * any step; altitude once per step with the climb rate held over it.
 *
 * Tasks: loiter (about a centre, or the present position), go to a point (fly
 * over it, then loiter about it), follow a route (fly over each point in turn,
 * then loiter about the last, or fly on along the last leg), set altitude, set
 * speed. A newer lateral task (loiter, go to, route) replaces the present one;
 * set altitude and set speed replace the previous altitude or speed command and
 * leave the lateral task running. Every accepted task increments the task number.
 * Route legs: leg i runs from point i-1 (for i = 0, from where the UAV was when
 * the route was tasked) to point i. Point i counts as reached, and the next leg
 * begins, when the UAV comes within the switching distance of it, or crosses
 * the bisector of the turn at it (the line through the point perpendicular to
 * the mean of the incoming and outgoing leg directions; at the last point, the
 * perpendicular to the last leg). The up component of route points and loiter
 * centres is ignored: height comes from the AGL command.
 *
 * Pure: no globals, no clocks, no logging. */
#ifndef UAVSIM_UAV_H
#define UAVSIM_UAV_H

#include "cgs_flight.h"
#include "cgs_geo.h"

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#define UAVSIM_UAV_G_MPS2       CGS_FLIGHT_G_MPS2 // standard gravity, m/s²
#define UAVSIM_UAV_ROUTE_MAX    1024              // most points in a route
#define UAVSIM_UAV_AGL_MAX_M    20000.0           // highest commanded altitude above ground, metres
#define UAVSIM_UAV_RADIUS_MAX_M 1e6               // largest loiter radius, metres

/* The UAV's mode, with the numbers of proto/world.proto's enum UavMode. */
typedef enum {
    UAVSIM_UAV_MODE_LOITER = 0,  // on the loiter orbit
    UAVSIM_UAV_MODE_ROUTE = 1,   // flying a tasked route (or on along its last leg)
    UAVSIM_UAV_MODE_TRANSIT = 2, // flying to a point or to the loiter orbit, not yet on it
} uavsim_uav_mode_t;
/* A loiter is TRANSIT until the UAV is within 5% of the radius + 10 m of the
 * orbit, flying within 30° of its tangent the commanded way; then LOITER until
 * the next lateral task. A go-to is TRANSIT until it reaches its point. */

/* Flight parameters; the defaults are in brackets. */
typedef struct {
    double bank_limit_deg;      // largest bank, degrees, (0, 80] [30]
    double roll_rate_dps;       // largest roll rate, degrees/s [20]
    double climb_rate_mps;      // largest climb or descent rate, m/s [5]
    double airspeed_min_mps;    // slowest commanded airspeed, m/s [20]
    double airspeed_max_mps;    // fastest commanded airspeed, m/s [60]
    double airspeed_accel_mps2; // largest airspeed change rate, m/s² [1]
    double l1_period_s;         // L1 period T, s [20]
    double l1_damping;          // L1 damping zeta, (0, 2] [0.75]
    double altitude_tau_s;      // time constant of the AGL hold, s [5]
    double loiter_radius_m;     // loiter radius when a task gives 0, metres [1000]
    double switch_distance_m;   // route point reached within this distance, metres, >= 0 [50]
} uavsim_uav_params_t;

/* Where and how the UAV starts. */
typedef struct {
    cgs_enu_t position;     // local frame, metres (up is absolute: terrain + AGL)
    double heading_deg;     // clockwise from north
    double airspeed_mps;    // within the airspeed limits; also the commanded airspeed
    double agl_m;           // commanded altitude above ground, metres, (0, 20000]
    double loiter_radius_m; // first task: loiter about the start position; 0 = default
    bool loiter_clockwise;  // its direction
} uavsim_uav_init_t;

/* A snapshot of the UAV's state and task (for the `uav` and `entity` messages). */
typedef struct {
    cgs_enu_t position;     // local frame, metres
    cgs_enu_t velocity;     // m/s, east north up
    double heading_deg;     // course = heading (no wind), clockwise from north, [0, 360)
    double pitch_deg;       // flight-path angle, nose up positive
    double roll_deg;        // bank, right wing down positive
    double airspeed_mps;    // = ground speed
    double climb_rate_mps;  // up positive
    double commanded_agl_m; // commanded altitude above ground
    double commanded_airspeed_mps;
    uavsim_uav_mode_t mode;
    uint64_t task_number;    // increments with every accepted task
    cgs_enu_t loiter_center; // the orbit flown now, or to be flown at the route's end (up 0)
    double loiter_radius_m;
    bool loiter_clockwise;
    size_t route_count;       // points in the tasked route (0 when loitering)
    size_t route_index;       // next route point; route_count once past the last
    bool route_loiter_at_end; // the route ends in a loiter about its last point
} uavsim_uav_state_t;

typedef struct uavsim_uav_model uavsim_uav_model_t;

/* Fill p with the documented defaults. */
void uavsim_uav_params_defaults (uavsim_uav_params_t *p);
/* 0 when every parameter is finite and in range, else -EINVAL. */
int uavsim_uav_params_check (const uavsim_uav_params_t *p);

/* A UAV loitering about its start position (task number 0); NULL on bad
 * parameters or a bad start. Copies the parameters. */
uavsim_uav_model_t *uavsim_uav_new (const uavsim_uav_params_t *p, const uavsim_uav_init_t *init);
/* Free; accepts NULL and *self_p == NULL; sets *self_p to NULL. */
void uavsim_uav_destroy (uavsim_uav_model_t **self_p);

/* Advance by dt_s (> 0, at most 1 s is accurate) with terrain_h_m the terrain
 * height under the UAV at the start of the step. 0 or -EINVAL (state unchanged). */
int uavsim_uav_step (uavsim_uav_model_t *self, double dt_s, double terrain_h_m);

/* Loiter about centre (radius 0 = default); replaces the lateral task. 0 or -EINVAL. */
int uavsim_uav_loiter (uavsim_uav_model_t *self, cgs_enu_t centre, double radius_m, bool clockwise);
/* Loiter about the present position. 0 or -EINVAL. */
int uavsim_uav_loiter_here (uavsim_uav_model_t *self, double radius_m, bool clockwise);
/* Fly over point, then loiter about it (radius 0 = default). 0 or -EINVAL. */
int uavsim_uav_goto (uavsim_uav_model_t *self, cgs_enu_t point, double radius_m, bool clockwise);
/* Fly over points[0..count-1] in order (1 <= count <= UAVSIM_UAV_ROUTE_MAX, copied),
 * then loiter about the last (radius 0 = default) when loiter_at_end, else fly on
 * along the last leg. 0 or -EINVAL. */
int uavsim_uav_route (uavsim_uav_model_t *self, const cgs_enu_t *points, size_t count,
                      bool loiter_at_end, double radius_m, bool clockwise);
/* Command the altitude above ground, (0, UAVSIM_UAV_AGL_MAX_M]. 0 or -EINVAL. */
int uavsim_uav_set_altitude (uavsim_uav_model_t *self, double agl_m);
/* Command the airspeed, within the limits. 0 or -EINVAL. */
int uavsim_uav_set_speed (uavsim_uav_model_t *self, double airspeed_mps);

/* The present state and task. */
void uavsim_uav_state (const uavsim_uav_model_t *self, uavsim_uav_state_t *ret_s);
/* The tasked route's points (*ret_count of them; NULL and 0 when none). */
const cgs_enu_t *uavsim_uav_route_points (const uavsim_uav_model_t *self, size_t *ret_count);
/* The parameters it flies with. */
const uavsim_uav_params_t *uavsim_uav_params (const uavsim_uav_model_t *self);
/* Smallest turn radius at airspeed v_mps and the bank limit, metres. */
double uavsim_uav_min_turn_radius (const uavsim_uav_model_t *self, double v_mps);

/* Serialise the complete dynamic state (kinematics, commands, task, route)
 * into a new malloc'd cgs_ckpt frame ("UUAV"). 0 or -ENOMEM / -EINVAL.
 * Parameters are not saved. */
int uavsim_uav_save (const uavsim_uav_model_t *self, uint8_t **ret_buf, size_t *ret_len);
/* Replace the dynamic state with a saved one, exactly (a restored UAV steps
 * bit-identically to the saved one, given the same parameters). 0, or one of
 * cgs_ckpt's errors with the reason in err (-EINVAL also for out-of-range
 * values; self unchanged), -EINVAL for a NULL self. */
int uavsim_uav_restore (uavsim_uav_model_t *self, const void *buf, size_t len, char *err,
                        size_t errlen);

#endif
