/* uavsim_vehicle — the ground-vehicle model of uavsim: a vehicle that drives a
 * piecewise-linear route in the local east-north frame at its speed profile,
 * rounds corners at a bounded turn rate and lateral acceleration, slows for
 * sharp corners, wanders off the line as obstacle avoidance would (a seeded,
 * band-limited lateral offset), halts on points where the route says so,
 * and stops, loops or reverses at the end.
 * Heights come from the terrain through uavsim_vehicle_ground. Pure: no
 * globals, clocks or logging; randomness from a generator kept in the object.
 *
 * Conventions (the unit test checks each against these formulas):
 * - Speeds: the speed given with point i applies on the leg from point i to
 *   point i+1 (0 means the vehicle's speed), whichever way the vehicle drives
 *   it; in a loop the closing leg takes the last point's speed.
 * - Corners: at an interior point with deflection theta the path is a circular
 *   arc tangent to both legs. With V the lower of the two leg speeds, the radius
 *   is R = max(V^2 / lat_accel, V / turn_rate), reduced so that the arc passes
 *   no further than max_corner_cut_m from the point and its tangent length
 *   R tan(theta/2) uses at most half of either leg; the corner speed is then
 *   Vc = min(V, sqrt(lat_accel R), turn_rate R). The vehicle brakes (decel) so
 *   that it enters the arc at Vc and accelerates (accel) after it. A point is
 *   "reached" at the middle of its arc. Corners of 170 degrees or more, and
 *   the ends of a reversing route, are taken by stopping on the point and
 *   turning in place at the turn rate.
 * - Time allowances: starting from rest costs V/(2 accel) s; stopping V/(2 decel);
 *   slowing from V to Vc costs (V-Vc)^2/(2 decel V); speeding up from Vc to V
 *   (V-Vc)^2/(2 accel V); each arc is driven at Vc; a turn in place takes
 *   angle / turn_rate.
 * - Halts: a point with a halt (halt_s[i] > 0) is driven into like a turn in
 *   place: no arc, the vehicle brakes (decel) to stop exactly on the point,
 *   stands there halt_s[i] s facing the way it came (speed and velocity 0),
 *   then turns in place to the next leg (if it bends) and accelerates
 *   (accel) away. It halts each time it reaches the point: every lap of a
 *   loop, both ways on a reversing route (at a reversing route's ends before
 *   its turn about). A stop route never comes back to its first point and
 *   ends on its last, so neither takes a halt. Time allowance: stopping
 *   V/(2 decel), the halt, the turn in place, starting V/(2 accel).
 * - Deviation: on the straight part of each leg the vehicle is offset to the
 *   left by d = A w(x) g(x): g a sum of three sinusoids with seeded wavelengths
 *   100-500 m, phases and weights (|g| <= 1), w a raised-cosine taper to 0
 *   (value and slope) at both ends of the straight; A <= deviation_m, reduced
 *   and the wavelengths stretched so that the wander never needs more than half
 *   the turn-rate and lateral-acceleration budget at the leg's speed. Arcs and
 *   points carry no offset. A new draw is made at each lap (loop) or pass
 *   (reverse). deviation_m = 0 keeps the vehicle exactly on the line. */
#ifndef UAVSIM_VEHICLE_H
#define UAVSIM_VEHICLE_H

#include "cgs_terrain.h"
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

typedef struct uavsim_vehicle uavsim_vehicle_t;

/* What a vehicle does at the end of its route. */
typedef enum {
    UAVSIM_VEHICLE_END_STOP = 0,    // stop on the last point (finished)
    UAVSIM_VEHICLE_END_LOOP = 1,    // drive on from the last point back to the first, forever
    UAVSIM_VEHICLE_END_REVERSE = 2, // turn in place at each end and drive the route back
} uavsim_vehicle_end_t;

/* One route point. */
typedef struct {
    double e_m;       // east of the exercise origin, metres
    double n_m;       // north of the exercise origin, metres
    double speed_mps; // speed on the leg that starts here, m/s; 0 = the vehicle's speed
} uavsim_vehicle_point_t;

/* Parameters of one vehicle. */
typedef struct {
    const uavsim_vehicle_point_t *points; // route, at least 2 points (copied)
    size_t n_points;                      // number of points
    double speed_mps;                     // the vehicle's speed, m/s (> 0; default 10)
    double start_time_s;                  // simulation time it sets off, s (default 0)
    uavsim_vehicle_end_t end;             // end behaviour (default stop)
    double deviation_m;                   // most lateral wander off the route, m (default 0)
    uint64_t seed;                        // seeds the wander (default 0)
    double lat_accel_mps2;                // most lateral acceleration, m/s^2 (default 2)
    double turn_rate_dps;                 // most turn rate, degrees/s (default 30)
    double accel_mps2;                    // acceleration, m/s^2 (default 1.5)
    double decel_mps2;                    // braking deceleration, m/s^2 (default 2)
    double corner_cut_m;  // farthest an arc passes from its corner point, m (default 10)
    const double *halt_s; // seconds it halts on reaching each point, n_points values, 0 = none
                          // (copied); NULL = no halts (default)
} uavsim_vehicle_params_t;

/* State for the entity message, after the latest step. */
typedef struct {
    double e_m, n_m;       // position, metres (local east, north)
    double ve_mps, vn_mps; // velocity, m/s (east, north)
    double heading_deg;    // direction of travel (or facing), degrees clockwise from north [0, 360)
    double speed_mps;      // ground speed, m/s
    double dev_m;          // lateral offset from the nominal path, metres (+ = left of travel)
    bool active;           // the start time has come (a finished vehicle stays active)
    bool finished;         // stopped on the last point (end behaviour stop)
    bool turning_in_place; // stopped on a point, turning to the next leg
    int leg;               // current leg: from point leg to point leg+1 (loop: n-1 closes)
    int next_point;        // the route point it is driving to
    int direction;         // +1 along the route, -1 back along it (reverse)
    uint64_t lap;          // laps (loop) or passes (reverse) completed
    bool halted;           // standing on a route point for its halt
    double halt_left_s;    // of that halt, seconds still to stand (0 when not halted)
} uavsim_vehicle_state_t;

/* Height and attitude on the terrain. */
typedef struct {
    double up_m;      // terrain height at the vehicle, metres (local up)
    double vu_mps;    // up velocity from the slope, m/s
    double pitch_deg; // nose up +, degrees
    double roll_deg;  // right side down +, degrees
} uavsim_vehicle_ground_t;

/* Fill p with the defaults above (no route). */
void uavsim_vehicle_params_defaults (uavsim_vehicle_params_t *p);
/* 0, or -EINVAL with a reason in err (may be NULL): a route of fewer than 2
 * points, non-finite values, negative or excessive speeds or halts,
 * consecutive points closer than 1 cm, non-positive limits, an unknown end
 * behaviour, a halt where the vehicle never arrives (a stop route's first or
 * last point, a loop's repeated last point). */
int uavsim_vehicle_params_check (const uavsim_vehicle_params_t *p, char *err, size_t errlen);
/* A vehicle waiting at its first point; 0, -EINVAL (bad parameters) or -ENOMEM. */
int uavsim_vehicle_new (const uavsim_vehicle_params_t *p, uavsim_vehicle_t **ret_v);
/* Free; accepts NULL; sets *self_p to NULL. */
void uavsim_vehicle_destroy (uavsim_vehicle_t **self_p);

/* Advance from simulation time t_s to t_s + dt_s (deterministic); 0 or -EINVAL
 * for a non-finite time or a step that is not positive and finite. */
int uavsim_vehicle_step (uavsim_vehicle_t *self, double t_s, double dt_s);
/* The state after the latest step (or as built). */
void uavsim_vehicle_state (const uavsim_vehicle_t *self, uavsim_vehicle_state_t *ret_s);
/* Route geometry as built: number of points (a loop's last point is dropped
 * when it repeats the first), corner radius and corner speed at point i
 * (0 where the vehicle stops on the point or drives straight through). */
int uavsim_vehicle_points (const uavsim_vehicle_t *self);
void uavsim_vehicle_corner (const uavsim_vehicle_t *self, int i, double *ret_radius_m,
                            double *ret_speed_mps);

/* Height, up velocity and attitude of a vehicle in state s on the terrain. */
void uavsim_vehicle_ground (const cgs_terrain_t *terrain, const uavsim_vehicle_state_t *s,
                            uavsim_vehicle_ground_t *ret_g);

/* The full dynamic state (position on the route, speed, turn, laps, the
 * generator, the current wander and the halt under way) as a new malloc'd
 * cgs_ckpt frame ("UVHC"); 0 or -ENOMEM. */
int uavsim_vehicle_save (const uavsim_vehicle_t *self, uint8_t **ret_buf, size_t *ret_len);
/* Restore a checkpoint into a vehicle built from the same parameters; 0, or
 * one of cgs_ckpt's errors with the reason in err (self unchanged): -EPROTO
 * also for a checkpoint of a vehicle with other parameters, -EINVAL for a
 * state this vehicle cannot be in. */
int uavsim_vehicle_restore (uavsim_vehicle_t *self, const void *buf, size_t len, char *err,
                            size_t errlen);

#endif
