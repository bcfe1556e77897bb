/* gd_intercept — one UAV's intercept of a designated track, as the UAV
 * control station runs it (paper, sections 4 and 5): designation,
 * waypoint initialisation (equations 1–3) into a flyable route, Track &
 * Update re-planning, the precision approach (equation 9), overflight,
 * loiter. It decides the UAV's lateral task (a route, or a loiter) and its
 * altitude and speed commands; the caller delivers them to uavsim. Pure: no
 * sockets, clocks, globals or logging; inputs carry their simulation times.
 *
 * Phases (proto InterceptState):
 *   IDLE          nothing designated.
 *   TO_SECONDARY  head-on plan with y'_u ≤ 0: flying to P_2.
 *   TO_WAYPOINT   flying the route into the waypoint, heading −D_T there.
 *   APPROACH      "Intercept by MTI TGT Hits": flying the reversed hit trail.
 *   PRECISION     head-on, past the waypoint (or established on the final
 *                 approach with the target in front): each track update
 *                 moves P_close by equation 9 and re-tasks the UAV to it and
 *                 on along the target's reverse direction.
 *   OVERFLIGHT    the target's predicted position is inside the footprint.
 *   DONE          the target has passed through the footprint; the UAV
 *                 loiters above the end of its route; no footprint shown.
 *   CANCELLED     the operator cancelled: loiter about the present position.
 *   LOST          the track was deleted or not updated for lost_after_s:
 *                 loiter about the present position.
 *
 * Re-planning (sections 4.2): before the precision approach, a track update
 * or turn event whose direction differs from the plan's by more than the
 * threshold, a target that left the planned line by more than offset_m, or
 * a target that has gone past the waypoint while the UAV is not yet on its
 * final approach makes a new plan from the UAV's present state. During the
 * precision approach a direction change beyond the threshold also makes a
 * new plan (the UAV must turn). A target that passes the UAV's footprint
 * without entering it makes a new plan too (another pass). */
#ifndef GD_INTERCEPT_H
#define GD_INTERCEPT_H

#include "cgs_track_status.h"
#include "gd_geom.h"
#include "gd_params.h"

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#define GD_ROUTE_MAX   512 // points in a route task (uavsim takes up to 1024)
#define GD_HISTORY_MAX 64  // hits of a track's history used by the MTI-hits method

/* The numbers of proto InterceptState and InterceptMethod. */
typedef enum {
    GD_IDLE = 0,
    GD_TO_SECONDARY = 1,
    GD_TO_WAYPOINT = 2,
    GD_APPROACH = 3,
    GD_PRECISION = 4,
    GD_OVERFLIGHT = 5,
    GD_DONE = 6,
    GD_CANCELLED = 7,
    GD_LOST = 8,
} gd_phase_t;

typedef enum {
    GD_HEAD_ON = 0,  // section 4
    GD_MTI_HITS = 1, // section 5
} gd_method_t;

/* The UAV as heard on `uav`. */
typedef struct {
    double t_s;
    cgs_enu_t position; // absolute up
    double heading_deg, pitch_deg, roll_deg;
    double ground_speed_mps;
    double airspeed_mps;       // commanded airspeed when known, else present
    double agl_m;              // height above the terrain under it
    double commanded_agl_m;    // the height commanded (0: unknown, taken as agl_m)
    double bank_limit_deg;     // for the smallest turn radius
    double depression_deg;     // imaging sensor: ε
    double hfov_deg, vfov_deg; // γ, β
    cgs_camera_point_t camera; // stabilization, stare point, gimbal (as `uav` has them)
} gd_uav_t;

/* A track as heard on `track`. */
typedef struct {
    uint32_t id;
    cgs_track_status_t status;
    bool friendly;
    double t_s;  // time of position and velocity
    gd_v2_t pos; // filtered
    gd_v2_t vel;
    gd_v2_t history[GD_HISTORY_MAX]; // past hits, oldest first
    double history_t_s[GD_HISTORY_MAX];
    uint32_t history_hit_id[GD_HISTORY_MAX]; // their MTI hit ids (0: unknown)
    uint32_t history_scan[GD_HISTORY_MAX];   // and scans
    size_t history_count;
    uint32_t radar_id;  // the radar that feeds it (its UAV's entity id; 0: unknown)
    uint32_t last_scan; // the radar's latest scan it has seen
    uint32_t hits;      // hits it has taken in all (0: unknown)
    double last_hit_s;  // time of its newest hit (NaN: unknown)
    uint32_t continues; // the deleted track whose target the tracker says this one is (0: none)
    double continues_p; // with this probability
    bool linked;        // its tracker links successors itself: no continues, no successor
    bool has_cov;       // the covariances below are known
    double pos_cov[3];  // position covariance: east², east·north, north² (m²)
    double vel_cov[3];  // velocity covariance, the same ((m/s)²)
} gd_track_t;

typedef enum {
    GD_TASK_NONE = 0,
    GD_TASK_ROUTE = 1,       // fly points, then loiter about the last
    GD_TASK_LOITER_HERE = 2, // loiter about the present position
} gd_task_kind_t;

/* The UAV's lateral task as guidanced wants it; number increments with
 * every new task. */
typedef struct {
    uint64_t number;
    gd_task_kind_t kind;
    gd_v2_t points[GD_ROUTE_MAX];
    size_t count;
} gd_task_t;

/* What the `intercept` message shows. Pointers valid until the next call. */
typedef struct {
    gd_phase_t phase;
    gd_method_t method;
    uint32_t track_id; // 0 when none
    uint64_t designation_number;
    bool has_plan;
    gd_v2_t waypoint;
    bool has_secondary;
    gd_v2_t secondary;
    const gd_v2_t *route; // the present task's points
    size_t route_count;
    double t_pred_s;
    bool has_footprint; // shown while an intercept is under way
    gd_footprint_t footprint;
    uint32_t display_scale; // 1, 5 or 10
    bool target_in_footprint;
    double time_to_go_s; // predicted time to overflight (NaN when unknown)
    uint32_t replans;
    const char *reason; // why the latest change of phase or plan happened
    double designation_s;
    double overflight_s; // first time in the footprint (NaN before)
    bool has_target;     // the designated target's estimate (an active intercept with a track)
    gd_v2_t target;      // its position at target_t_s
    gd_v2_t target_vel;
    double target_t_s;
    double y_u_m; // of the latest plan (eq. 2)
} gd_status_t;

typedef struct gd_intercept gd_intercept_t;

/* An idle intercept for one UAV over terrain (borrowed; NULL: flat ground
 * at height 0). NULL on bad parameters or no memory. */
gd_intercept_t *gd_intercept_new (const gd_params_t *p, const cgs_terrain_t *terrain);
void gd_intercept_destroy (gd_intercept_t **self_p);

/* Designate a track at t_s (pre-empts any intercept). 0, or -EINVAL with the
 * reason in why (deleted or tentative track, no position). */
int gd_intercept_designate (gd_intercept_t *self, const gd_track_t *t, double t_s, char *why,
                            size_t whylen);
/* Cancel: the UAV loiters about its present position (also after DONE or
 * LOST: it leaves the route's end or the place it lost the track). 0, or
 * -EALREADY when idle or already cancelled. */
int gd_intercept_cancel (gd_intercept_t *self, double t_s);
/* The method of the next plans (a running intercept is re-planned with it). */
void gd_intercept_set_method (gd_intercept_t *self, gd_method_t m);
/* Footprint display scale: 1, 5 or 10; else -EINVAL. */
int gd_intercept_set_scale (gd_intercept_t *self, uint32_t scale);

/* The UAV's latest state: footprint, progress along the route, phase
 * changes that depend on where the UAV is. */
void gd_intercept_uav (gd_intercept_t *self, const gd_uav_t *u);
/* The imaging sensor of u, as gd_footprint takes it. */
void gd_uav_sensor (const gd_uav_t *u, double max_range_m, gd_sensor_t *ret);
/* A track update (any track: others are ignored). */
void gd_intercept_track (gd_intercept_t *self, const gd_track_t *t);
/* A turn event of a track (paper, equation 8): velocity after the turn. */
void gd_intercept_turn (gd_intercept_t *self, uint32_t track_id, double t_s, gd_v2_t vel_after,
                        double angle_deg);
/* Time has come to t_s: a designated track silent for lost_after_s is lost. */
void gd_intercept_tick (gd_intercept_t *self, double t_s);
/* Simulation time went back to t_s (uavsim resumed from its saved state):
 * what the intercept heard after t_s did not happen. Its hits and updates
 * are taken as heard at t_s at the latest (so that a new track of the
 * target, whose hits now come after t_s, can take over from a track the
 * tracker deleted for being from later times), and a plan made after t_s
 * (for a UAV that is now elsewhere) is made again on the next UAV update. */
void gd_intercept_time_back (gd_intercept_t *self, double t_s);

/* The lateral task wanted now (kind NONE until the first). */
const gd_task_t *gd_intercept_task (const gd_intercept_t *self);
/* How many changes of phase, plan or designated track it has made (each
 * with its reason): one that moves changed what a restart must find (the
 * designated track's deletion and its successor are said once by the
 * tracker, never again), so its owner saves the state. */
uint64_t gd_intercept_changes (const gd_intercept_t *self);
/* The present status. */
void gd_intercept_status (const gd_intercept_t *self, gd_status_t *ret);
/* The UAV's planning turn radius (metres) at its present speed; 0 before any UAV state. */
double gd_intercept_turn_radius (const gd_intercept_t *self);

/* Its checkpoint: gd_checkpoint.h. */

/* Which tracks an operator's pick may take. */
typedef enum {
    GD_PICK_ANY = 0,
    GD_PICK_UNKNOWN = 1, // not identified as friendly
    GD_PICK_FRIENDLY = 2,
} gd_pick_t;

/* Of tracks[0..n-1] (confirmed or coasting ones only, of the kind pick),
 * the index of the one whose newest hit (its filtered position when it has
 * no history) is nearest p; -ENOENT when none qualifies. *ret_d_m the
 * distance. */
int gd_pick_nearest (const gd_track_t *tracks, size_t n, gd_v2_t p, gd_pick_t pick,
                     double *ret_d_m);

/* Names of phases and methods, as in the proto enums' suffixes ("DONE"). */
const char *gd_phase_name (gd_phase_t p);

#endif
