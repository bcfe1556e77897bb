/* gd_geom — the geometry of the head-on intercept (paper, sections 4.1 and
 * 4.3) on the ground plane of the exercise's local frame, the flyable routes
 * it becomes (Dubins paths), and the imaging sensor's footprint on the
 * terrain. Pure: no globals, no logging, no clock.
 *
 * Notation (paper): P_T, V_T the target's position and velocity, D_T = V_T /
 * |V_T| its direction, P_ug the UAV's ground position, z_u its height above
 * the terrain, ε the sensor's depression angle, s_ug the UAV's ground speed.
 * The sensor's boresight meets flat ground z_u·cot ε ahead of the UAV (the
 * look-ahead), so a UAV at P_T + (z_u·cot ε)·D_T heading along −D_T has the
 * target at its footprint centre.
 *
 * Equation 1: P_waypt = P_T + V_T·t_pred + (z_u·cot ε)·D_T.
 *   t_pred is the time the UAV needs to fly the arc that joins its ground
 *   position to the target: a turn of the planning radius towards the point,
 *   then the straight tangent to it (gd_arc_length), flown at s_ug; adjusted
 *   for the target's motion by fixed-point iteration, t ← L(P_T + V_T·t)/s_ug,
 *   which converges when |V_T| < s_ug.
 * Equations 2–3: the rotation into the target's frame, x' to the right of its
 *   direction and y' along it: x' = D_n·dx − D_e·dn, y' = D_e·dx + D_n·dn for
 *   d = P_ug − P_waypt. y'_u > 0 (the UAV ahead of the waypoint): fly to the
 *   waypoint, then along −D_T. y'_u ≤ 0: first through the secondary
 *   waypoint P_2 = Δ(P_ug − P_waypt) + P_waypt. The paper's Δ, for D_T =
 *   (d_x, d_y), is [[d_y², −d_x·d_y], [−d_x·d_y, d_x²]] = Rᵀ·diag(1, 0)·R,
 *   the projection onto the cross-track axis: P_2 lies abeam the waypoint at
 *   the UAV's cross-track offset (secondary_paper). The extension (the
 *   default) takes Δ = Rᵀ·diag(1, −k)·R: the cross-track offset is kept and
 *   the UAV's along-track distance behind the waypoint becomes k times that
 *   distance ahead of it (k = secondary_scale; k = 1 reflects the UAV across
 *   the waypoint's cross-track line, which is not the paper's), never less
 *   than the lead-in distance (room to turn in).
 * Equation 9 (precision approach): P_close^(n+1) = P_close^(n) − s_ug·dt·UV_n^p,
 *   UV_n^p the target's unit velocity predicted at scan n.
 */
#ifndef GD_GEOM_H
#define GD_GEOM_H

#include "cgs_camera.h"
#include "cgs_footprint.h"
#include "cgs_geo.h"
#include "cgs_terrain.h"

#include <stdbool.h>
#include <stddef.h>

/* A point or vector on the ground plane: east, north, metres (or m/s). */
typedef cgs_v2_t gd_v2_t;

/* ---- small vector helpers ---------------------------------------------------------- */
gd_v2_t gd_v2 (double e, double n);
gd_v2_t gd_add (gd_v2_t a, gd_v2_t b);
gd_v2_t gd_sub (gd_v2_t a, gd_v2_t b);
gd_v2_t gd_scale (gd_v2_t a, double k);
double gd_dot (gd_v2_t a, gd_v2_t b);
/* a × b (east-north plane): positive when b is anticlockwise of a. */
double gd_cross (gd_v2_t a, gd_v2_t b);
double gd_norm (gd_v2_t a);
/* Unit vector of a heading (degrees clockwise from north), and back. */
gd_v2_t gd_heading_unit (double heading_deg);
double gd_heading_of (gd_v2_t v);
/* Signed change from heading a to heading b, degrees in (−180, 180],
 * clockwise positive. */
double gd_heading_diff (double a_deg, double b_deg);

/* ---- the arc that joins the UAV to a point ----------------------------------------- */

/* Length of the shortest path that leaves p heading heading_deg, turns with
 * radius r_m towards q (either side) and then flies straight to q: the arc
 * of the turn plus the tangent. A q inside both turn circles (too close to
 * reach by turning one way) is reached by a turn the other way, away and
 * around: its length is that of the longer way (at most 2π·r + |q − p|). */
double gd_arc_length (gd_v2_t p, double heading_deg, double r_m, gd_v2_t q);

/* ---- waypoint initialisation (equations 1–3) ---------------------------------------- */

typedef struct {
    gd_v2_t uav;            // P_ug
    double uav_heading_deg; // its course, clockwise from north
    double uav_speed_mps;   // s_ug, > |V_T|
    double turn_radius_m;   // planning radius, > 0
    double agl_m;           // z_u, > 0
    double depression_deg;  // ε, (0, 90)
    gd_v2_t target;         // P_T
    gd_v2_t target_vel;     // V_T (m/s); zero: a target standing still, for which
                            // D_T is taken from the target towards the UAV
    bool secondary_paper;   // equation 3 as the paper has it (no k, no lead-in)
    double secondary_scale; // else: k of Δ = Rᵀ·diag(1, −k)·R
    double lead_in_m;       // else: least distance of P_2 ahead of the waypoint
    double offset_max_m;    // P_2's cross-track offset at most this (0: the UAV's, unbounded)
    double settle_m;        // straight run into the waypoint after the last turn (0: none)
    double min_t_pred_s;    // t_pred at least this (0: equation 1's alone)
    double horizon_s;       // t_pred at most this (0: no bound); beats min_t_pred_s
} gd_engage_t;

typedef struct {
    double lookahead_m; // z_u·cot ε
    gd_v2_t dir;        // D_T
    double t_pred_s;
    int iterations;   // of the fixed point
    gd_v2_t waypoint; // P_waypt
    double x_u_m;     // the UAV in the target's frame about the waypoint (eq. 2)
    double y_u_m;
    bool secondary;  // y'_u ≤ 0: go through P_2 first
    gd_v2_t second;  // P_2 (when secondary)
    gd_v2_t meet;    // P_T + V_T·t_pred: where the target should be at the waypoint time
    double settle_m; // the route's straight run into the waypoint along −D_T (≤ settle_m asked)
    double route_m;  // gd_waypoint_flyable: the flyable route's length (else 0)
    bool limited;    // t_pred cut to the horizon: the UAV cannot meet the target sooner
} gd_waypoint_t;

/* Equation 3's secondary waypoint P_2 for a UAV (in->uav) behind the
 * waypoint of a target moving along the unit vector dir: the paper's
 * projection when in->secondary_paper, else the extension (above); with
 * in->offset_max_m > 0 its cross-track offset is cut to that (the UAV
 * closes on the target's line instead of flying abeam it at its start
 * distance, out where its radar barely sees the target). */
gd_v2_t gd_secondary_point (const gd_engage_t *in, gd_v2_t waypoint, gd_v2_t dir);
/* Equations 1–3. 0, or -EINVAL (bad input; a target not slower than the UAV;
 * no convergence). *ret written only on success. */
int gd_waypoint (const gd_engage_t *in, gd_waypoint_t *ret);

/* The heading the route holds into P_2 (towards the waypoint) and into the
 * waypoint (−D_T), degrees. */
void gd_waypoint_headings (const gd_waypoint_t *w, double *ret_second_deg, double *ret_final_deg);

/* Where the route's last turn ends: w->settle_m before the waypoint on the
 * line along −D_T (the waypoint itself when settle_m is 0). */
gd_v2_t gd_waypoint_settle_point (const gd_waypoint_t *w);

/* Length of the flyable route of plan w: Dubins paths of radius
 * in->turn_radius_m from the UAV through P_2 (when w has one, arriving with
 * the heading towards the waypoint) into the settle point heading −D_T, then
 * straight on to the waypoint. NaN when a leg cannot be built. */
double gd_route_length (const gd_engage_t *in, const gd_waypoint_t *w);

/* Equations 1–3 with t_pred lengthened, where it is too short, to the time
 * the flyable route takes (gd_route_length at the UAV's speed): equation 1
 * times the arc straight to the target, but a UAV behind the target goes
 * through P_2 first, and without this the target reaches the waypoint long
 * before the UAV does. Iterated, t ← route(t)/s, until the route takes at
 * most t + 0.5 s. Behind the target the route grows by about (1 + 2k)·|V_T|
 * per second of t_pred (P_2 runs k·|y'_u| ahead of the waypoint), so the
 * iteration settles only for targets slower than s/(1 + 2k) (25 m/s at
 * k = 0.25 and 38 m/s); when it does not settle within 100 steps,
 * equation 1's plan is returned. ret->route_m the returned plan's route
 * length (0 when a leg cannot be built). 0 or -EINVAL as gd_waypoint. */
int gd_waypoint_flyable (const gd_engage_t *in, gd_waypoint_t *ret);

/* Equation 2: q in the frame of direction dir (unit) about origin o:
 * ret x' (right of dir), y' (along dir). */
void gd_to_target_frame (gd_v2_t o, gd_v2_t dir, gd_v2_t q, double *ret_x, double *ret_y);

/* Equation 9: one step of the precision approach. p the present P_close,
 * uv the target's unit velocity, speed the UAV's ground speed, dt the time
 * between scans. The point is first put on the target's present line
 * (through target along uv), keeping its along-track coordinate, so a
 * cross-track error of the earlier estimate is corrected; then moved by
 * −s_ug·dt·uv. */
gd_v2_t gd_precision_step (gd_v2_t p, gd_v2_t target, gd_v2_t uv, double speed_mps, double dt_s);

/* ---- Dubins paths -------------------------------------------------------------------- */

typedef enum {
    GD_LSL = 0,
    GD_LSR,
    GD_RSL,
    GD_RSR,
    GD_RLR,
    GD_LRL,
} gd_dubins_word_t;

/* A shortest path of bounded curvature from (p0, h0) to (p1, h1): three
 * segments, each a turn of radius r (L anticlockwise, R clockwise) or a
 * straight (S), of lengths len[0..2] in metres. */
typedef struct {
    gd_v2_t p0;
    double h0_deg;
    double r_m;
    gd_dubins_word_t word;
    double len[3];
} gd_dubins_t;

/* The shortest of the six words (Dubins 1957; Shkel and Lumelsky 2001). 0, or
 * -EINVAL (r ≤ 0 or non-finite input). */
int gd_dubins (gd_v2_t p0, double h0_deg, gd_v2_t p1, double h1_deg, double r_m, gd_dubins_t *ret);
/* Its total length, metres. */
double gd_dubins_length (const gd_dubins_t *d);
/* The point and heading at distance s along it (0 ≤ s ≤ length). */
void gd_dubins_at (const gd_dubins_t *d, double s, gd_v2_t *ret_p, double *ret_h_deg);
/* Points along it for a waypoint follower: arcs sampled every step_deg of
 * turn (at least two points an arc), the end of each segment, and the end;
 * the start is not included. Writes at most max points; returns how many it
 * wrote (the path's end is always the last one written). */
size_t gd_dubins_sample (const gd_dubins_t *d, double step_deg, gd_v2_t *out, size_t max);

/* ---- the imaging sensor's footprint ----------------------------------------------------- */

typedef struct {
    cgs_enu_t position;       // the sensor (the UAV), local frame, absolute up
    double heading_deg;       // UAV heading, clockwise from north
    double pitch_deg;         // nose up positive
    double roll_deg;          // right wing down positive
    double depression_deg;    // ε: boresight below the body's forward axis
    double hfov_deg;          // γ
    double vfov_deg;          // β
    double max_range_m;       // a ray that meets no ground within this is cut there
    cgs_camera_point_t point; // stabilization, stare point, gimbal
} gd_sensor_t;

/* The footprint (common/cgs_footprint.h: its corners, centre, and the
 * tests of a point inside it and its distance, shared with the scoring). */
typedef cgs_footprint_t gd_footprint_t;

/* The four ground vertices of the footprint trapezoid: the rays through
 * the corners of the image (pinhole camera: forward ± tan(γ/2)·right ±
 * tan(β/2)·up in the camera's axes) and the boresight, each met with the
 * terrain (terrain NULL: flat ground at height 0): common/cgs_camera's
 * camera and footprint, the ones imagerd renders. 0 or -EINVAL. */
int gd_footprint (const gd_sensor_t *s, const cgs_terrain_t *terrain, gd_footprint_t *ret);

#endif
