/* test_gd_intercept — guidanced's intercept core (gd_intercept) against
 * hand computation and the paper's equations, driven by hand-built UAV and
 * track states over flat ground (terrain NULL) with the default parameters.
 *
 * The UAV of every case: 1200 m above the ground (agl 1200), sensor
 * depression ε = 45° (look-ahead z_u·cot ε = 1200 m), fields of view 10° ×
 * 7.5°, bank limit 30°, 38 m/s ground and air speed. Its planning turn
 * radius is turn_radius_factor·V²/(g·tan 30°) = 1.5·38²/(9.80665·0.57735)
 * ≈ 382.6 m, so 4 r ≈ 1530 m is below the default lead-in (2000 m).
 *
 * Geometries with a closed form for t_pred (equation 1's fixed point
 * t = L(P_T + V_T·t)/s_ug) are used wherever the check is by hand: the
 * meeting point straight ahead of the UAV, where the arc is a straight line
 * (a target coming head-on, t = d/(s + v); receding, t = d/(s − v);
 * crossing so that it meets the UAV's line ahead, t = d_cross/v = d/s).
 *
 * Cases:
 *   - designation: equation 1 (and a target standing still), the route (secondary, waypoint,
 * run-out along −D_T, no turn sharper than the sampling step), equations 2–3 for both signs of
 * y'_u, the secondary's along-track distance in each of its three regimes (k·|y'_u|, lead-in, 4 r);
 *   - re-planning on a direction change (track update, turn event) and not on
 *     a small one;
 *   - cancel, pre-emption, refused designations;
 *   - save and restore, and damaged saves;
 *   - the precision approach (equation 9) and its time to go;
 *   - overflight, done; a deleted track flown on its prediction, the
 *     hand-over to a new track (the radius growing with age), lost;
 *   - gd_pick_nearest, the display scale, the constructor and names. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <errno.h>
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "gd_geom.h"
#include "gd_intercept.h"
#include "gd_params.h"

/* cmocka 1.1 compares only integers; doubles need their own check. */
#define assert_near(a, b, tol)                                                                     \
    do {                                                                                           \
        double a_ = (a), b_ = (b), t_ = (tol);                                                     \
        if (!(fabs (a_ - b_) <= t_))                                                               \
            fail_msg ("%s = %.12g, expected %.12g (tolerance %g)", #a, a_, b_, t_);                \
    } while (0)

/* Two ground points equal within tol metres. */
#define assert_v2_near(a, b, tol)                                                                  \
    do {                                                                                           \
        gd_v2_t a_ = (a), b_ = (b);                                                                \
        double t_ = (tol);                                                                         \
        if (!(fabs (a_.e - b_.e) <= t_ && fabs (a_.n - b_.n) <= t_))                               \
            fail_msg ("%s = (%.12g, %.12g), expected (%.12g, %.12g) (tolerance %g)", #a, a_.e,     \
                      a_.n, b_.e, b_.n, t_);                                                       \
    } while (0)

#define assert_has(str, sub)                                                                       \
    do {                                                                                           \
        const char *s_ = (str);                                                                    \
        if (!s_ || !strstr (s_, (sub)))                                                            \
            fail_msg ("%s = \"%s\" does not contain \"%s\"", #str, s_ ? s_ : "(null)", (sub));     \
    } while (0)

#define PI  3.14159265358979323846
#define DEG (PI / 180.0)
#define G   9.80665

#define UAV_SPEED 38.0
#define LOOKAHEAD 1200.0 // z_u·cot ε = 1200·cot 45°

/* ---- helpers ------------------------------------------------------------------------ */

static gd_params_t s_params (void)
{
    gd_params_t p;
    gd_params_defaults (&p);
    return p;
}

/* The planning turn radius by hand: factor·V²/(g·tan(bank)). */
static double s_radius (const gd_params_t *p)
{
    return p->turn_radius_factor * UAV_SPEED * UAV_SPEED / (G * tan (30.0 * DEG));
}

static gd_uav_t s_uav (double t_s, double e, double n, double heading_deg)
{
    gd_uav_t u = {0};
    u.t_s = t_s;
    u.position.e_m = e;
    u.position.n_m = n;
    u.position.u_m = 1200; // flat ground at 0
    u.heading_deg = heading_deg;
    u.ground_speed_mps = UAV_SPEED;
    u.airspeed_mps = UAV_SPEED;
    u.agl_m = 1200;
    u.bank_limit_deg = 30;
    u.depression_deg = 45;
    u.hfov_deg = 10;
    u.vfov_deg = 7.5;
    return u;
}

static gd_track_t s_track (uint32_t id, int status, double t_s, double e, double n, double ve,
                           double vn)
{
    gd_track_t t;
    memset (&t, 0, sizeof t);
    t.id = id;
    t.status = status;
    t.t_s = t_s;
    t.pos = gd_v2 (e, n);
    t.vel = gd_v2 (ve, vn);
    return t;
}

/* A velocity of speed v along a heading (degrees clockwise from north). */
static gd_v2_t s_vel (double v, double heading_deg)
{
    return gd_v2 (v * sin (heading_deg * DEG), v * cos (heading_deg * DEG));
}

static gd_status_t s_status (const gd_intercept_t *ic)
{
    gd_status_t st;
    gd_intercept_status (ic, &st);
    return st;
}

static gd_intercept_t *s_new (const gd_params_t *p)
{
    gd_intercept_t *ic = gd_intercept_new (p, NULL);
    assert_non_null (ic);
    return ic;
}

static void s_designate (gd_intercept_t *ic, const gd_track_t *t, double t_s)
{
    char why[160] = "";
    int rc = gd_intercept_designate (ic, t, t_s, why, sizeof why);
    if (rc != 0)
        fail_msg ("designation of track %u refused (%d): %s", t->id, rc, why);
}

/* Equation 1 with the status's t_pred: P_waypt = P_T + V_T·t_pred + L·D_T,
 * P_T the track predicted to the UAV's time t_uav. Together with the fixed
 * point check below this pins the waypoint down when no closed form is at
 * hand. */
static gd_v2_t s_eq1 (const gd_track_t *t, double t_uav, double t_pred)
{
    gd_v2_t p = gd_add (t->pos, gd_scale (t->vel, t_uav - t->t_s));
    gd_v2_t d = gd_scale (t->vel, 1.0 / gd_norm (t->vel));
    return gd_add (gd_add (p, gd_scale (t->vel, t_pred)), gd_scale (d, LOOKAHEAD));
}

/* t_pred is the fixed point: the UAV flies the arc (turn of the planning
 * radius, then the tangent) to P_T + V_T·t_pred in t_pred. The iteration stops
 * when successive values differ by 1e-6·(1 + t); the residual is below that
 * times the contraction ratio, so 1e-5·(1 + t) seconds is ample. */
static void s_assert_fixed_point (const gd_track_t *t, const gd_uav_t *u, double r, double t_pred)
{
    gd_v2_t p = gd_add (t->pos, gd_scale (t->vel, u->t_s - t->t_s));
    gd_v2_t meet = gd_add (p, gd_scale (t->vel, t_pred));
    double l = gd_arc_length (gd_v2 (u->position.e_m, u->position.n_m), u->heading_deg, r, meet);
    assert_near (t_pred, l / UAV_SPEED, 1e-5 * (1 + t_pred));
}

/* Heading of a chord, degrees clockwise from north, computed here. */
static double s_heading (gd_v2_t d)
{
    double h = atan2 (d.e, d.n) / DEG;
    return h < 0 ? h + 360 : h;
}

/* No two consecutive legs of the route (starting from the UAV's own position
 * and heading) differ in heading by more than max_deg: the Dubins arcs are
 * sampled every arc_step_deg of turn, so a leg inside an arc turns by at most
 * one step, and at a junction of an arc and a straight by half a step. Legs
 * shorter than a metre (a straight of zero length) have no heading. */
static void s_assert_flyable (const gd_v2_t *pts, size_t n, gd_v2_t start, double h0_deg,
                              double max_deg)
{
    gd_v2_t prev = start;
    double h = h0_deg;
    for (size_t i = 0; i < n; i++) {
        gd_v2_t d = gd_sub (pts[i], prev);
        prev = pts[i];
        if (gd_norm (d) < 1.0)
            continue;
        double hc = s_heading (d);
        double dh = fabs (remainder (hc - h, 360.0));
        if (dh > max_deg)
            fail_msg ("route leg %zu turns by %.3f° (more than %.3f°)", i, dh, max_deg);
        h = hc;
    }
}

/* The crossing geometry: UAV at the origin heading north at t = 100; the
 * target 3000 m west of the UAV's line and 11 400 m north, crossing east at
 * 10 m/s. The UAV needs 11 400 / 38 = 300 s to the point (0, 11 400) straight
 * ahead; the target needs 3000 / 10 = 300 s to get there: t_pred = 300 s,
 * meet = (0, 11 400), waypoint = meet + 1200·(1, 0) = (1200, 11 400). The
 * track's time is 98 s (position 20 m further west), so the plan must
 * predict it to the UAV's time. */
static gd_track_t s_crossing_track (uint32_t id)
{
    return s_track (id, 1, 98, -3020, 11400, 10, 0);
}

static gd_intercept_t *s_crossing (const gd_params_t *p, uint32_t id)
{
    gd_intercept_t *ic = s_new (p);
    gd_uav_t u = s_uav (100, 0, 0, 0);
    gd_intercept_uav (ic, &u);
    gd_track_t t = s_crossing_track (id);
    s_designate (ic, &t, 100);
    return ic;
}

/* ---- designation and the plan ----------------------------------------------------------- */

/* Equation 1 by hand on the crossing geometry (see s_crossing); equations
 * 2–3: d = P_ug − P_waypt = (−1200, −11 400), D_T = (1, 0):
 * x' = D_n·d_e − D_e·d_n = 11 400, y' = D_e·d_e + D_n·d_n = −1200 ≤ 0, so a
 * secondary waypoint first, at along-track max(0.25·1200, max(2000, 4 r)) =
 * 2000 ahead of the waypoint with the cross-track offset kept:
 * P_2 = (1200, 11 400) + 11 400·(0, −1) + 2000·(1, 0) = (3200, 0). The route
 * ends (look-ahead + run-out) = 2700 m past the waypoint along −D_T:
 * (1200 − 2700, 11 400) = (−1500, 11 400). (Numbers for the default
 * parameters; the checks take them from gd_params_defaults.) */
static void test_designate_plan_eq1 (void **state)
{
    (void)state;
    gd_params_t p = s_params ();
    gd_intercept_t *ic = s_new (&p);
    gd_uav_t u = s_uav (100, 0, 0, 0);
    gd_intercept_uav (ic, &u);
    gd_status_t st = s_status (ic);
    assert_int_equal (st.phase, GD_IDLE);
    assert_int_equal (st.track_id, 0);
    assert_false (st.has_footprint); // nothing under way
    assert_int_equal (gd_intercept_task (ic)->kind, GD_TASK_NONE);

    gd_track_t t = s_crossing_track (7);
    s_designate (ic, &t, 100);
    st = s_status (ic);
    assert_int_equal (st.phase, GD_TO_SECONDARY);
    assert_int_equal (st.track_id, 7);
    assert_int_equal (st.designation_number, 1);
    assert_int_equal (st.replans, 0);
    assert_near (st.designation_s, 100, 0);
    assert_true (st.has_plan);
    assert_true (st.has_footprint);
    assert_true (isnan (st.overflight_s));
    assert_has (st.reason, "designated track 7");
    // Equation 1: the meeting point straight ahead makes t_pred exact (the
    // arc's derivative across the line is zero there, so the iteration
    // converges fast): 300 s to 1e-3 s, the waypoint to 1 cm.
    assert_near (st.t_pred_s, 300.0, 1e-3);
    assert_v2_near (st.waypoint, gd_v2 (1200, 11400), 0.01);
    assert_v2_near (st.waypoint, s_eq1 (&t, 100, st.t_pred_s), 1e-6);
    s_assert_fixed_point (&t, &u, s_radius (&p), st.t_pred_s);
    // Equations 2–3.
    assert_near (st.y_u_m, -1200, 0.01);
    assert_true (st.has_secondary);
    double y2 = fmax (p.secondary_scale * 1200, fmax (p.lead_in_m, 4 * s_radius (&p)));
    assert_v2_near (st.secondary, gd_v2 (1200 + y2, 0), 0.01);

    // The task: a route; the waypoint is the point before the end (head-on
    // routes are: Dubins to P_2, Dubins to the waypoint, the end point).
    const gd_task_t *tk = gd_intercept_task (ic);
    assert_int_equal (tk->kind, GD_TASK_ROUTE);
    assert_int_equal (tk->number, 1);
    assert_true (tk->count >= 4);
    assert_int_equal (st.route_count, tk->count);
    assert_ptr_equal (st.route, tk->points);
    assert_v2_near (tk->points[tk->count - 2], st.waypoint, 1e-6);
    size_t i2 = tk->count;
    for (size_t i = 0; i + 2 < tk->count; i++)
        if (gd_norm (gd_sub (tk->points[i], st.secondary)) < 1e-6)
            i2 = i;
    if (i2 == tk->count)
        fail_msg ("the secondary waypoint is not a route point before the waypoint");
    // The end: on the line through the waypoint along −D_T, 2700 m beyond.
    gd_v2_t end = tk->points[tk->count - 1];
    gd_v2_t dt = gd_v2 (1, 0);
    assert_near (gd_cross (dt, gd_sub (end, st.waypoint)), 0, 1e-6);
    assert_near (gd_dot (dt, gd_sub (end, st.waypoint)), -(LOOKAHEAD + p.runout_m), 1e-6);
    assert_v2_near (end, gd_v2 (1200 - LOOKAHEAD - p.runout_m, 11400), 0.01);
    // The last leg into the waypoint and the run-out head along −D_T (west).
    assert_near (s_heading (gd_sub (end, tk->points[tk->count - 2])), 270, 1e-6);
    s_assert_flyable (tk->points, tk->count, gd_v2 (0, 0), 0, p.arc_step_deg + 1e-6);
    gd_intercept_destroy (&ic);
    assert_null (ic);
}

/* y'_u > 0: the UAV far ahead of the target on its line, the target coming
 * head-on at 10 m/s from 20 000 m north (track time 95 s, so 19 950 m at the
 * UAV's time 100 s). Meeting straight ahead: 38·t = 19 950 − 10·t,
 * t_pred = 19 950 / 48 = 415.625 s, meet = (0, 15 793.75), waypoint =
 * meet + 1200·(0, −1) = (0, 14 593.75); y'_u = D_T·(P_ug − P_waypt) =
 * 14 593.75 > 0: straight to the waypoint, no secondary. */
static void test_uav_ahead_no_secondary (void **state)
{
    (void)state;
    gd_params_t p = s_params ();
    gd_intercept_t *ic = s_new (&p);
    gd_uav_t u = s_uav (100, 0, 0, 0);
    gd_intercept_uav (ic, &u);
    gd_track_t t = s_track (3, 1, 95, 0, 20000, 0, -10);
    s_designate (ic, &t, 100);
    gd_status_t st = s_status (ic);
    double tp = 19950.0 / (UAV_SPEED + 10);
    assert_int_equal (st.phase, GD_TO_WAYPOINT);
    assert_false (st.has_secondary);
    assert_near (st.t_pred_s, tp, 1e-3);
    assert_v2_near (st.waypoint, gd_v2 (0, 19950 - 10 * tp - LOOKAHEAD), 0.02);
    assert_near (st.y_u_m, 19950 - 10 * tp - LOOKAHEAD, 0.02);
    const gd_task_t *tk = gd_intercept_task (ic);
    assert_int_equal (tk->kind, GD_TASK_ROUTE);
    assert_true (tk->count >= 2);
    assert_v2_near (tk->points[tk->count - 2], st.waypoint, 1e-6);
    assert_v2_near (tk->points[tk->count - 1], gd_v2 (0, st.waypoint.n + LOOKAHEAD + p.runout_m),
                    1e-6);
    s_assert_flyable (tk->points, tk->count, gd_v2 (0, 0), 0, p.arc_step_deg + 1e-6);
    gd_intercept_destroy (&ic);
}

/* y'_u ≤ 0: the UAV behind a target that recedes north at 10 m/s from d
 * metres ahead. Meeting straight ahead: 38·t = d + 10·t, t = d/28; waypoint
 * = (0, d + 10·t + 1200); y'_u = −waypoint.n; x'_u = 0, so P_2 lies on the
 * line, along-track max(0.25·|y'_u|, max(lead_in, 4 r)) ahead of the
 * waypoint. Three cases, one for each term of the max. */
static void s_behind_case (gd_params_t p, double d, double want_y2)
{
    gd_intercept_t *ic = s_new (&p);
    gd_uav_t u = s_uav (100, 0, 0, 0);
    gd_intercept_uav (ic, &u);
    gd_track_t t = s_track (4, 1, 100, 0, d, 0, 10);
    s_designate (ic, &t, 100);
    gd_status_t st = s_status (ic);
    double tp = d / (UAV_SPEED - 10);
    double wn = d + 10 * tp + LOOKAHEAD;
    assert_int_equal (st.phase, GD_TO_SECONDARY);
    assert_true (st.has_secondary);
    assert_near (st.t_pred_s, tp, 1e-2);
    assert_v2_near (st.waypoint, gd_v2 (0, wn), 0.1);
    assert_near (st.y_u_m, -wn, 0.1);
    assert_v2_near (st.secondary, gd_v2 (0, wn + want_y2), 0.1);
    // The route: P_2 then the waypoint, then the run-out south of it.
    const gd_task_t *tk = gd_intercept_task (ic);
    assert_v2_near (tk->points[tk->count - 2], st.waypoint, 1e-6);
    assert_v2_near (tk->points[tk->count - 1], gd_v2 (0, st.waypoint.n - LOOKAHEAD - p.runout_m),
                    1e-6);
    bool found = false;
    for (size_t i = 0; i + 2 < tk->count; i++)
        found |= gd_norm (gd_sub (tk->points[i], st.secondary)) < 1e-6;
    assert_true (found);
    s_assert_flyable (tk->points, tk->count, gd_v2 (0, 0), 0, p.arc_step_deg + 1e-6);
    gd_intercept_destroy (&ic);
}

static void test_uav_behind_secondary (void **state)
{
    (void)state;
    gd_params_t p = s_params ();
    double r = s_radius (&p), k = p.secondary_scale;
    // The regimes below rely on the defaults' k = 0.25, lead-in 2000 > 4 r.
    assert_true (p.lead_in_m > 4 * r);
    // d = 20 000: y'_u = −28 342.86, 0.25·|y'_u| = 7085.7 beats the lead-in.
    double wn = 20000 + 10 * 20000 / 28.0 + LOOKAHEAD;
    assert_true (k * wn > p.lead_in_m);
    s_behind_case (p, 20000, k * wn);
    // d = 1000: |y'_u| = 2557.1, 0.25·|y'_u| = 639.3 < 2000: the lead-in.
    wn = 1000 + 10 * 1000 / 28.0 + LOOKAHEAD;
    assert_true (k * wn < p.lead_in_m);
    s_behind_case (p, 1000, p.lead_in_m);
    // The same with no lead-in: 4 r = 1530.2 (room to turn in).
    assert_true (k * wn < 4 * r);
    p.lead_in_m = 0;
    s_behind_case (p, 1000, 4 * r);
}

/* A target slower than min_target_speed_mps is taken as standing still: D_T
 * is then the direction from the target to the UAV. Target at (0, 10 000)
 * creeping east at 0.5 m/s, UAV at the origin heading north: D_T = (0, −1),
 * t_pred = 10 000 / 38 (straight ahead, the target not moving), waypoint =
 * P_T + 1200·D_T = (0, 8800), y'_u = 8800 > 0; the run-out ends 2700 m past
 * it, at (0, 11 500). A later update, still creeping, keeps the plan. */
static void test_standing_target (void **state)
{
    (void)state;
    gd_params_t p = s_params ();
    assert_true (p.min_target_speed_mps > 0.5);
    gd_intercept_t *ic = s_new (&p);
    gd_uav_t u = s_uav (100, 0, 0, 0);
    gd_intercept_uav (ic, &u);
    gd_track_t t = s_track (6, 1, 100, 0, 10000, 0.5, 0);
    s_designate (ic, &t, 100);
    gd_status_t st = s_status (ic);
    assert_int_equal (st.phase, GD_TO_WAYPOINT);
    assert_false (st.has_secondary);
    assert_near (st.t_pred_s, 10000.0 / UAV_SPEED, 1e-6);
    assert_v2_near (st.waypoint, gd_v2 (0, 10000 - LOOKAHEAD), 1e-6);
    assert_near (st.y_u_m, 10000 - LOOKAHEAD, 1e-6);
    const gd_task_t *tk = gd_intercept_task (ic);
    assert_v2_near (tk->points[tk->count - 1], gd_v2 (0, 10000 + p.runout_m), 1e-6);
    t = s_track (6, 1, 110, 5, 10000, 0.5, 0);
    gd_intercept_track (ic, &t);
    assert_int_equal (gd_intercept_task (ic)->number, 1);
    assert_int_equal (s_status (ic).replans, 0);
    gd_intercept_destroy (&ic);
}

/* ---- re-planning --------------------------------------------------------------------------- */

/* On the crossing geometry (plan direction east, 90°): a track update at
 * 10° (heading 100°) keeps the plan; one at 30° (120°) makes a new plan whose
 * waypoint lies 1200 m along the new direction from P_T + V_T·t_pred; a turn
 * event of 60° from that plan (to 180°) makes another; a turn event of 10°
 * does not. */
static void test_replan_on_direction_change (void **state)
{
    (void)state;
    gd_params_t p = s_params ();
    gd_intercept_t *ic = s_crossing (&p, 7);
    gd_uav_t u = s_uav (100, 0, 0, 0);
    assert_int_equal (gd_intercept_task (ic)->number, 1);
    gd_v2_t wp0 = s_status (ic).waypoint;
    assert_true (p.threshold_deg > 10 && p.threshold_deg < 30); // the default, 20°

    // 10°: below the threshold (20°); the target stays within 2 m of the
    // planned line and behind the waypoint: nothing changes.
    gd_v2_t v10 = s_vel (10, 100);
    gd_track_t t = s_track (7, 1, 101, -2990, 11400, v10.e, v10.n);
    gd_intercept_track (ic, &t);
    gd_status_t st = s_status (ic);
    assert_int_equal (gd_intercept_task (ic)->number, 1);
    assert_int_equal (st.replans, 0);
    assert_v2_near (st.waypoint, wp0, 0);

    // 30°: a new plan with the new direction.
    gd_v2_t v30 = s_vel (10, 120);
    t = s_track (7, 1, 102, -2980, 11400, v30.e, v30.n);
    gd_intercept_track (ic, &t);
    st = s_status (ic);
    assert_int_equal (gd_intercept_task (ic)->number, 2);
    assert_int_equal (st.replans, 1);
    assert_has (st.reason, "re-planned");
    assert_has (st.reason, "direction changed by 30");
    assert_true (st.has_plan);
    assert_v2_near (st.waypoint, s_eq1 (&t, 100, st.t_pred_s), 1e-6);
    s_assert_fixed_point (&t, &u, s_radius (&p), st.t_pred_s);
    // (waypoint − meet)/L is D_T = (sin 120°, cos 120°).
    gd_v2_t meet =
        gd_add (gd_add (t.pos, gd_scale (t.vel, 100 - t.t_s)), gd_scale (t.vel, st.t_pred_s));
    assert_v2_near (gd_scale (gd_sub (st.waypoint, meet), 1.0 / LOOKAHEAD),
                    gd_v2 (sqrt (3) / 2, -0.5), 1e-9);
    const gd_task_t *tk = gd_intercept_task (ic);
    assert_v2_near (tk->points[tk->count - 2], st.waypoint, 1e-6);
    assert_v2_near (
        tk->points[tk->count - 1],
        gd_sub (st.waypoint, gd_scale (gd_v2 (sqrt (3) / 2, -0.5), LOOKAHEAD + p.runout_m)), 1e-6);

    // A turn event of another track, and one of 10° from the plan: nothing.
    gd_intercept_turn (ic, 8, 103, s_vel (10, 180), 60);
    gd_intercept_turn (ic, 7, 103, s_vel (10, 130), 10);
    assert_int_equal (gd_intercept_task (ic)->number, 2);
    assert_int_equal (s_status (ic).replans, 1);

    // A turn event of 60° (120° → 180°, south) at 103 s: the target goes on
    // from its prediction, (−2980, 11 400) + 1 s·(8.66, −5), now southwards.
    gd_intercept_turn (ic, 7, 103, s_vel (10, 180), 60);
    st = s_status (ic);
    assert_int_equal (gd_intercept_task (ic)->number, 3);
    assert_int_equal (st.replans, 2);
    assert_has (st.reason, "turn event");
    gd_track_t after = s_track (7, 1, 103, -2980 + v30.e, 11400 + v30.n, 0, -10);
    assert_v2_near (st.waypoint, s_eq1 (&after, 100, st.t_pred_s), 1e-6);
    s_assert_fixed_point (&after, &u, s_radius (&p), st.t_pred_s);
    tk = gd_intercept_task (ic);
    assert_v2_near (tk->points[tk->count - 1],
                    gd_v2 (st.waypoint.e, st.waypoint.n + LOOKAHEAD + p.runout_m), 1e-6);
    gd_intercept_destroy (&ic);
}

/* ---- commands -------------------------------------------------------------------------------- */

static void test_cancel (void **state)
{
    (void)state;
    gd_params_t p = s_params ();
    gd_intercept_t *ic = s_new (&p);
    assert_int_equal (gd_intercept_cancel (ic, 50), -EALREADY); // idle
    assert_int_equal (s_status (ic).phase, GD_IDLE);
    assert_int_equal (gd_intercept_task (ic)->kind, GD_TASK_NONE);
    assert_int_equal (gd_intercept_task (ic)->number, 0);
    gd_intercept_destroy (&ic);

    ic = s_crossing (&p, 7);
    assert_true (s_status (ic).has_footprint);
    uint64_t n = gd_intercept_task (ic)->number;
    assert_int_equal (gd_intercept_cancel (ic, 120), 0);
    gd_status_t st = s_status (ic);
    assert_int_equal (st.phase, GD_CANCELLED);
    assert_false (st.has_footprint);
    assert_false (st.has_plan);
    assert_false (st.target_in_footprint);
    assert_int_equal (st.route_count, 0);
    assert_has (st.reason, "cancelled");
    const gd_task_t *tk = gd_intercept_task (ic);
    assert_int_equal (tk->kind, GD_TASK_LOITER_HERE);
    assert_int_equal (tk->number, n + 1);
    assert_int_equal (gd_intercept_cancel (ic, 121), -EALREADY);
    assert_int_equal (gd_intercept_task (ic)->number, n + 1);
    assert_int_equal (s_status (ic).phase, GD_CANCELLED);
    // Updates of the cancelled track change nothing.
    gd_track_t t = s_track (7, 1, 130, -2700, 11400, 0, -10);
    gd_intercept_track (ic, &t);
    gd_intercept_tick (ic, 1000);
    assert_int_equal (s_status (ic).phase, GD_CANCELLED);
    assert_int_equal (gd_intercept_task (ic)->number, n + 1);
    gd_intercept_destroy (&ic);
}

/* A second designation pre-empts the first: a fresh plan for the new track
 * (equation 1 for it), the replans count reset, the old track ignored. */
static void test_preempt (void **state)
{
    (void)state;
    gd_params_t p = s_params ();
    gd_intercept_t *ic = s_crossing (&p, 7);
    gd_uav_t u = s_uav (100, 0, 0, 0);
    gd_v2_t v30 = s_vel (10, 120);
    gd_track_t t7 = s_track (7, 1, 102, -2980, 11400, v30.e, v30.n);
    gd_intercept_track (ic, &t7);
    assert_int_equal (s_status (ic).replans, 1);
    assert_int_equal (gd_intercept_task (ic)->number, 2);

    gd_track_t t9 = s_track (9, 2, 100, 5000, 5000, 0, 10); // coasting may be designated
    s_designate (ic, &t9, 105);
    gd_status_t st = s_status (ic);
    assert_int_equal (st.designation_number, 2);
    assert_int_equal (st.track_id, 9);
    assert_int_equal (st.replans, 0);
    assert_near (st.designation_s, 105, 0);
    assert_has (st.reason, "pre-empts track 7");
    assert_has (st.reason, "track 9");
    assert_int_equal (gd_intercept_task (ic)->number, 3);
    assert_v2_near (st.waypoint, s_eq1 (&t9, 100, st.t_pred_s), 1e-6);
    s_assert_fixed_point (&t9, &u, s_radius (&p), st.t_pred_s);
    // Track 7 turning hard is no longer our business.
    t7 = s_track (7, 1, 106, -2940, 11380, 0, -10);
    gd_intercept_track (ic, &t7);
    gd_intercept_turn (ic, 7, 106, gd_v2 (-10, 0), 90);
    assert_int_equal (gd_intercept_task (ic)->number, 3);
    assert_int_equal (s_status (ic).track_id, 9);
    assert_int_equal (s_status (ic).replans, 0);
    gd_intercept_destroy (&ic);
}

static void s_refused (gd_intercept_t *ic, const gd_track_t *t, const char *want)
{
    char why[160] = "";
    assert_int_equal (gd_intercept_designate (ic, t, 100, why, sizeof why), -EINVAL);
    assert_has (why, want);
    gd_status_t st = s_status (ic);
    assert_int_equal (st.phase, GD_IDLE);
    assert_int_equal (st.designation_number, 0);
    assert_int_equal (st.track_id, 0);
    assert_int_equal (gd_intercept_task (ic)->kind, GD_TASK_NONE);
}

static void test_refusals (void **state)
{
    (void)state;
    gd_params_t p = s_params ();
    gd_intercept_t *ic = s_new (&p);
    gd_uav_t u = s_uav (100, 0, 0, 0);
    gd_intercept_uav (ic, &u);
    gd_track_t t = s_crossing_track (7);
    t.status = 0;
    s_refused (ic, &t, "tentative");
    t.status = 3;
    s_refused (ic, &t, "deleted");
    // Faster than max_target_speed_mps (30): 1 m/s more is refused.
    assert_true (p.max_target_speed_mps < UAV_SPEED - 1);
    t = s_track (7, 1, 100, -3000, 11400, p.max_target_speed_mps + 1, 0);
    s_refused (ic, &t, "not credible");
    t = s_track (7, 1, 100, NAN, 11400, 10, 0);
    s_refused (ic, &t, "no valid position");
    t = s_track (0, 1, 100, -3000, 11400, 10, 0);
    s_refused (ic, &t, "no valid position");
    // At the limit it is taken.
    t = s_track (7, 1, 100, -3000, 11400, p.max_target_speed_mps, 0);
    s_designate (ic, &t, 100);
    assert_int_equal (s_status (ic).designation_number, 1);
    assert_int_equal (s_status (ic).track_id, 7);
    gd_intercept_destroy (&ic);
}

/* ---- save and restore --------------------------------------------------------------------------
 */

static void s_assert_same_status (const gd_intercept_t *a, const gd_intercept_t *b)
{
    gd_status_t x = s_status (a), y = s_status (b);
    assert_int_equal (x.phase, y.phase);
    assert_int_equal (x.method, y.method);
    assert_int_equal (x.track_id, y.track_id);
    assert_int_equal (x.designation_number, y.designation_number);
    assert_int_equal (x.has_plan, y.has_plan);
    assert_memory_equal (&x.waypoint, &y.waypoint, sizeof x.waypoint);
    assert_int_equal (x.has_secondary, y.has_secondary);
    assert_memory_equal (&x.secondary, &y.secondary, sizeof x.secondary);
    assert_int_equal (x.route_count, y.route_count);
    if (x.route_count)
        assert_memory_equal (x.route, y.route, x.route_count * sizeof x.route[0]);
    assert_true (x.t_pred_s == y.t_pred_s);
    assert_int_equal (x.has_footprint, y.has_footprint);
    for (int i = 0; i < 4; i++)
        assert_v2_near (x.footprint.corner[i], y.footprint.corner[i], 0);
    assert_int_equal (x.display_scale, y.display_scale);
    assert_int_equal (x.target_in_footprint, y.target_in_footprint);
    assert_true (x.time_to_go_s == y.time_to_go_s ||
                 (isnan (x.time_to_go_s) && isnan (y.time_to_go_s)));
    assert_int_equal (x.replans, y.replans);
    assert_string_equal (x.reason, y.reason);
    assert_true (x.designation_s == y.designation_s);
    assert_true (x.overflight_s == y.overflight_s ||
                 (isnan (x.overflight_s) && isnan (y.overflight_s)));
    assert_true (x.y_u_m == y.y_u_m);
    const gd_task_t *ta = gd_intercept_task (a), *tb = gd_intercept_task (b);
    assert_int_equal (ta->number, tb->number);
    assert_int_equal (ta->kind, tb->kind);
    assert_int_equal (ta->count, tb->count);
    if (ta->count)
        assert_memory_equal (ta->points, tb->points, ta->count * sizeof ta->points[0]);
}

/* A copy of buf with the first occurrence of from replaced by to (NUL-terminated). */
static char *s_replace (const uint8_t *buf, size_t len, const char *from, const char *to,
                        size_t *ret_len)
{
    char *s = malloc (len + 1);
    assert_non_null (s);
    memcpy (s, buf, len);
    s[len] = '\0';
    char *at = strstr (s, from);
    if (!at)
        fail_msg ("\"%s\" is not in the saved text", from);
    size_t head = (size_t)(at - s), fl = strlen (from), tl = strlen (to);
    char *out = malloc (len - fl + tl + 1);
    assert_non_null (out);
    memcpy (out, s, head);
    memcpy (out + head, to, tl);
    memcpy (out + head + tl, at + fl, len - head - fl + 1);
    free (s);
    *ret_len = len - fl + tl;
    return out;
}

static void s_save (const gd_intercept_t *ic, uint8_t **ret, size_t *ret_len)
{
    assert_int_equal (gd_intercept_save (ic, ret, ret_len), 0);
    assert_non_null (*ret);
    assert_true (*ret_len > 0);
}

/* Restore damaged text into victim: -EPROTO, a reason, victim unchanged
 * (its own save is byte for byte what it was). */
static void s_damaged (gd_intercept_t *victim, const void *buf, size_t len, const char *want)
{
    uint8_t *before, *after;
    size_t nb, na;
    s_save (victim, &before, &nb);
    char err[256] = "";
    assert_int_equal (gd_intercept_restore (victim, buf, len, err, sizeof err), -EPROTO);
    assert_has (err, "not a guidanced intercept");
    assert_has (err, want);
    s_save (victim, &after, &na);
    assert_int_equal (na, nb);
    assert_memory_equal (after, before, nb);
    free (before);
    free (after);
}

static void test_save_restore (void **state)
{
    (void)state;
    gd_params_t p = s_params ();
    gd_intercept_t *a = s_crossing (&p, 7);
    assert_int_equal (gd_intercept_set_scale (a, 5), 0);
    // Mid-intercept: the UAV has flown on, the target turned (a re-plan).
    gd_uav_t u = s_uav (110, 30, 380, 5);
    gd_intercept_uav (a, &u);
    gd_v2_t v30 = s_vel (10, 120);
    gd_track_t t = s_track (7, 1, 111, -2890, 11395, v30.e, v30.n);
    gd_intercept_track (a, &t);
    gd_status_t sa = s_status (a);
    assert_int_equal (sa.replans, 1);
    assert_true (sa.phase == GD_TO_SECONDARY || sa.phase == GD_TO_WAYPOINT);
    unsigned long long saved_task = (unsigned long long)gd_intercept_task (a)->number;
    assert_int_equal (saved_task, 2);

    uint8_t *buf;
    size_t len;
    s_save (a, &buf, &len);
    gd_intercept_t *b = s_new (&p);
    char err[256] = "";
    if (gd_intercept_restore (b, buf, len, err, sizeof err) != 0)
        fail_msg ("restore failed: %s", err);
    s_assert_same_status (a, b);
    assert_int_equal (s_status (b).display_scale, 5);
    assert_near (gd_intercept_turn_radius (b), gd_intercept_turn_radius (a), 0);
    // Saved again, the text is the same.
    uint8_t *buf2;
    size_t len2;
    s_save (b, &buf2, &len2);
    assert_int_equal (len2, len);
    assert_memory_equal (buf2, buf, len);
    free (buf2);

    // The same inputs from here on give the same tasks.
    gd_uav_t u2 = s_uav (120, 150, 760, 20);
    gd_intercept_uav (a, &u2);
    gd_intercept_uav (b, &u2);
    gd_track_t t2 = s_track (7, 1, 121, -2800, 11340, 0, -10); // 60° more: a re-plan
    gd_intercept_track (a, &t2);
    gd_intercept_track (b, &t2);
    assert_int_equal (s_status (a).replans, 2);
    s_assert_same_status (a, b);
    gd_intercept_turn (a, 7, 125, gd_v2 (-10, 0), 90);
    gd_intercept_turn (b, 7, 125, gd_v2 (-10, 0), 90);
    gd_intercept_tick (a, 130);
    gd_intercept_tick (b, 130);
    s_assert_same_status (a, b);
    assert_int_equal (s_status (a).replans, 3);

    // Damaged text into an intercept of its own (track 9 designated).
    gd_intercept_t *c = s_new (&p);
    gd_intercept_uav (c, &u);
    gd_track_t t9 = s_track (9, 1, 110, 5000, 5000, 0, 10);
    s_designate (c, &t9, 110);
    s_damaged (c, buf, len / 2, "line");
    s_damaged (c, buf, len - 4, "end"); // "end\n" cut off
    s_damaged (c, buf, 0, "line 0");
    s_damaged (c, "", 0, "the header");
    size_t n;
    char *bad = s_replace (buf, len, "gd_intercept 1\n", "gd_intercept 2\n", &n);
    s_damaged (c, bad, n, "line 1: bad or missing the header");
    free (bad);
    bad = s_replace (buf, len, "settings 0 5\n", "settings 0 3\n", &n); // no such scale
    s_damaged (c, bad, n, "line 2: bad or missing settings");
    free (bad);
    char from[64], to[64];
    snprintf (from, sizeof from, "\ndesignation %d ", (int)sa.phase);
    bad = s_replace (buf, len, from, "\ndesignation x ", &n);
    s_damaged (c, bad, n, "line 4: bad or missing designation");
    free (bad);
    bad = s_replace (buf, len, "\ndesignation ", "\ndesignation 99", &n); // phase 99x: no such
    s_damaged (c, bad, n, "designation");
    free (bad);
    bad = s_replace (buf, len, "\npoint ", "\npoint nan ", &n);
    s_damaged (c, bad, n, "a route point");
    free (bad);
    bad = s_replace (buf, len, "\nuav 1 ", "\nuav 1 x", &n);
    s_damaged (c, bad, n, "line 3: bad or missing uav");
    free (bad);
    // The task record (a route, kind 1) with kind 7.
    snprintf (from, sizeof from, "\ntask %llu 1 ", saved_task);
    snprintf (to, sizeof to, "\ntask %llu 7 ", saved_task);
    bad = s_replace (buf, len, from, to, &n);
    s_damaged (c, bad, n, "task");
    free (bad);
    // The intercept restored from the good text still works after all that.
    char err2[256] = "";
    assert_int_equal (gd_intercept_restore (c, buf, len, err2, sizeof err2), 0);
    free (buf);
    gd_intercept_destroy (&a);
    gd_intercept_destroy (&b);
    gd_intercept_destroy (&c);
}

/* ---- precision approach ------------------------------------------------------------------------
 */

/* The UAV on the final approach: at the origin heading north (−D_T), the
 * target 20 000 m north on the same line coming south at 10 m/s. Its first
 * state after the designation makes the plan (TO_WAYPOINT) and, the UAV
 * being aligned (0° ≤ align 20°), on the line (x' = 0 < offset 150) and
 * 20 000 m > 0.8·look-ahead in front of the target, PRECISION with P_close the
 * UAV's projection on the target's line, (0, 0). A track update 10 s later
 * with the same velocity: equation 9, P_close ← P_close − s_ug·dt·D_T =
 * (0, 0) − 380·(0, −1) = (0, 380); the task: P_close, then 2700 m on along
 * −D_T, (0, 3080). */
static void test_precision_eq9 (void **state)
{
    (void)state;
    gd_params_t p = s_params ();
    gd_intercept_t *ic = s_new (&p);
    gd_track_t t = s_track (5, 1, 100, 0, 20000, 0, -10);
    s_designate (ic, &t, 100); // no UAV yet: planned on its first state
    gd_status_t st = s_status (ic);
    assert_false (st.has_plan);
    assert_int_equal (gd_intercept_task (ic)->kind, GD_TASK_NONE);
    assert_near (gd_intercept_turn_radius (ic), 0, 0);

    gd_uav_t u = s_uav (100, 0, 0, 0);
    gd_intercept_uav (ic, &u);
    assert_near (gd_intercept_turn_radius (ic), s_radius (&p), 1e-9);
    st = s_status (ic);
    assert_true (st.has_plan);
    assert_int_equal (st.phase, GD_PRECISION);
    assert_has (st.reason, "final approach");
    assert_int_equal (gd_intercept_task (ic)->number, 1);
    // Time to go on the approach: the target (0, 20 000) is 18 800 m past the
    // footprint centre (0, 1200), closing at 38 + 10 m/s.
    assert_near (st.time_to_go_s, 18800.0 / 48.0, 1e-6);

    t = s_track (5, 1, 110, 0, 19900, 0, -10);
    gd_intercept_track (ic, &t);
    const gd_task_t *tk = gd_intercept_task (ic);
    assert_int_equal (tk->number, 2);
    assert_int_equal (tk->kind, GD_TASK_ROUTE);
    assert_int_equal (tk->count, 2);
    gd_v2_t want = gd_precision_step (gd_v2 (0, 0), gd_v2 (0, 20000), gd_v2 (0, -1), 38, 10);
    assert_v2_near (want, gd_v2 (0, 380), 1e-9);
    assert_v2_near (tk->points[0], gd_v2 (0, 380), 1e-9);
    assert_v2_near (tk->points[1], gd_v2 (0, 380 + LOOKAHEAD + p.runout_m), 1e-9);
    st = s_status (ic);
    assert_int_equal (st.phase, GD_PRECISION);
    assert_int_equal (st.replans, 0);
    assert_int_equal (st.route_count, 2);

    // The UAV flew there; the next update 10 s on finds the target's line 30
    // m further east (within offset and threshold): P_close goes onto the new
    // line, then 380 m on: (30, 760).
    u = s_uav (110, 0, 380, 0);
    gd_intercept_uav (ic, &u);
    assert_int_equal (s_status (ic).phase, GD_PRECISION);
    // At 110 s: the target (0, 19 900), the footprint centre (0, 1580).
    assert_near (s_status (ic).time_to_go_s, (19900.0 - 1580.0) / 48.0, 1e-6);
    t = s_track (5, 1, 120, 30, 19800, 0, -10);
    gd_intercept_track (ic, &t);
    tk = gd_intercept_task (ic);
    assert_int_equal (tk->number, 3);
    assert_int_equal (tk->count, 2);
    want = gd_precision_step (gd_v2 (0, 380), gd_v2 (30, 19900), gd_v2 (0, -1), 38, 10);
    assert_v2_near (want, gd_v2 (30, 760), 1e-9);
    assert_v2_near (tk->points[0], gd_v2 (30, 760), 1e-9);
    assert_v2_near (tk->points[1], gd_v2 (30, 760 + LOOKAHEAD + p.runout_m), 1e-9);

    // A 30° turn of the target during the approach: a new plan (the UAV must turn).
    gd_v2_t v = s_vel (10, 210);
    t = s_track (5, 1, 125, 30 + v.e * 5, 19750 + v.n * 5, v.e, v.n);
    gd_intercept_track (ic, &t);
    st = s_status (ic);
    assert_int_equal (st.replans, 1);
    assert_int_equal (gd_intercept_task (ic)->number, 4);
    assert_true (st.phase == GD_TO_WAYPOINT || st.phase == GD_TO_SECONDARY);
    gd_intercept_destroy (&ic);
}

/* ---- overflight, done -------------------------------------------------------------------------
 */

/* Overflight: the geometry of test_precision_eq9; at 200 s the target is at
 * (0, 19 000) and the UAV at (0, 17 800) heading north, so the boresight
 * meets the ground 1200 m ahead, right on the target. The footprint by hand
 * (flat ground, level flight): the image's near edge (3.75° below the
 * boresight, b = tan 3.75°) meets the ground 1200·(1 − b)/(1 + b) ≈ 1052 m
 * ahead, the far edge 1200·(1 + b)/(1 − b) ≈ 1368 m. Then the UAV flies on:
 * at 210 s the target is 720 m ahead of it (behind the near edge): out; at
 * 211.5 s still within the 2 s grace; at 212.5 s done. */
static void test_overflight_done (void **state)
{
    (void)state;
    gd_params_t p = s_params ();
    gd_intercept_t *ic = s_new (&p);
    gd_uav_t u = s_uav (100, 0, 0, 0);
    gd_intercept_uav (ic, &u);
    gd_track_t t = s_track (5, 1, 100, 0, 20000, 0, -10);
    s_designate (ic, &t, 100);
    uint64_t n = gd_intercept_task (ic)->number;

    u = s_uav (200, 0, 17800, 0);
    gd_intercept_uav (ic, &u);
    gd_status_t st = s_status (ic);
    assert_int_equal (st.phase, GD_OVERFLIGHT);
    assert_true (st.target_in_footprint);
    assert_true (st.has_footprint);
    assert_near (st.overflight_s, 200, 0);
    assert_near (st.time_to_go_s, 0, 0);
    assert_has (st.reason, "in the footprint");
    double b = tan (3.75 * DEG), a = tan (5.0 * DEG);
    assert_v2_near (st.footprint.center, gd_v2 (0, 19000), 1e-6);
    double near = 1200 * (1 - b) / (1 + b), far = 1200 * (1 + b) / (1 - b);
    // Near-left: east −a·(slant of the ray to the ground) = −a·1200·√2/(1 + b).
    assert_v2_near (st.footprint.corner[0], gd_v2 (-a * 1200 * sqrt (2) / (1 + b), 17800 + near),
                    1e-6);
    assert_v2_near (st.footprint.corner[2], gd_v2 (a * 1200 * sqrt (2) / (1 - b), 17800 + far),
                    1e-6);

    u = s_uav (210, 0, 18180, 0); // target (0, 18 900): 720 m ahead < 1052
    gd_intercept_uav (ic, &u);
    st = s_status (ic);
    assert_int_equal (st.phase, GD_OVERFLIGHT);
    assert_false (st.target_in_footprint);
    u = s_uav (211.5, 0, 18237, 0);
    gd_intercept_uav (ic, &u);
    assert_int_equal (s_status (ic).phase, GD_OVERFLIGHT);
    u = s_uav (212.5, 0, 18275, 0);
    gd_intercept_uav (ic, &u);
    st = s_status (ic);
    assert_int_equal (st.phase, GD_DONE);
    assert_false (st.has_footprint);
    assert_false (st.target_in_footprint);
    assert_near (st.overflight_s, 200, 0);
    assert_has (st.reason, "passed through");
    // Done: the route stands (the UAV loiters above its end); no new task.
    assert_int_equal (gd_intercept_task (ic)->number, n);
    assert_int_equal (gd_intercept_task (ic)->kind, GD_TASK_ROUTE);
    // Nothing to do any more: ticks and updates leave it done.
    gd_intercept_tick (ic, 1000);
    assert_int_equal (s_status (ic).phase, GD_DONE);
    gd_intercept_destroy (&ic);
}

/* ---- deleted track: hand-over, lost -------------------------------------------------------------
 */

/* The crossing geometry (track 7 at (−3000, 11 400) at 100 s, east at
 * 10 m/s). Deleted at 110 s: the phase stays, the plan is flown on the
 * prediction. At 115 s the target should be at (−2850, 11 400); a new track
 * takes over within R = handover_m + handover_growth_mps·age of it, age the
 * 15 s since the last good update (400 + 10·15 = 550 m with the defaults):
 * one R + 15 m away does not, one R − 15 m away (beyond the bare
 * handover_m) does. */
static void test_deleted_handover (void **state)
{
    (void)state;
    gd_params_t p = s_params ();
    gd_intercept_t *ic = s_new (&p);
    gd_uav_t u = s_uav (100, 0, 0, 0);
    gd_intercept_uav (ic, &u);
    gd_track_t t = s_track (7, 1, 100, -3000, 11400, 10, 0);
    s_designate (ic, &t, 100);
    gd_status_t st0 = s_status (ic);
    uint64_t n = gd_intercept_task (ic)->number;

    t = s_track (7, 3, 110, -2900, 11400, 10, 0);
    gd_intercept_track (ic, &t);
    gd_status_t st = s_status (ic);
    assert_int_equal (st.phase, st0.phase);
    assert_int_equal (st.track_id, 7);
    assert_has (st.reason, "deleted");
    assert_int_equal (gd_intercept_task (ic)->number, n);

    double r = p.handover_m + p.handover_growth_mps * 15;
    assert_true (r - 15 > p.handover_m); // the growth matters below
    gd_track_t far = s_track (12, 1, 115, -2850 + r + 15, 11400, 10, 0);
    gd_intercept_track (ic, &far);
    assert_int_equal (s_status (ic).track_id, 7);
    gd_track_t tent = s_track (13, 0, 115, -2850 + 100, 11400, 10, 0); // tentative: no
    gd_intercept_track (ic, &tent);
    assert_int_equal (s_status (ic).track_id, 7);
    gd_track_t fast = s_track (14, 1, 115, -2850 + 100, 11400, p.max_target_speed_mps + 5, 0);
    gd_intercept_track (ic, &fast); // not credible: no
    assert_int_equal (s_status (ic).track_id, 7);

    gd_track_t near = s_track (15, 1, 115, -2850 + r - 15, 11400, 10, 0);
    gd_intercept_track (ic, &near);
    st = s_status (ic);
    assert_int_equal (st.track_id, 15);
    assert_int_equal (st.phase, st0.phase);
    assert_has (st.reason, "track 7 was deleted");
    assert_has (st.reason, "track 15");
    assert_int_equal (st.designation_number, 1);
    // From now on the new track's updates count: a 40° turn re-plans.
    assert_true (p.threshold_deg < 40);
    gd_v2_t v = s_vel (10, 130);
    near = s_track (15, 1, 116, -2850 + r - 5, 11400, v.e, v.n);
    gd_intercept_track (ic, &near);
    assert_int_equal (s_status (ic).replans, 1);
    assert_int_equal (gd_intercept_task (ic)->number, n + 1);
    // And it is lost when silent for lost_after_s after its update at 116 s.
    gd_intercept_tick (ic, 116 + p.lost_after_s - 0.5);
    assert_true (s_status (ic).phase != GD_LOST);
    gd_intercept_tick (ic, 116 + p.lost_after_s + 0.5);
    assert_int_equal (s_status (ic).phase, GD_LOST);
    gd_intercept_destroy (&ic);
}

/* Deleted and no new track: lost lost_after_s after its last good update
 * (100 s), the UAV told to loiter where it is. */
static void test_deleted_lost (void **state)
{
    (void)state;
    gd_params_t p = s_params ();
    gd_intercept_t *ic = s_new (&p);
    gd_uav_t u = s_uav (100, 0, 0, 0);
    gd_intercept_uav (ic, &u);
    gd_track_t t = s_track (7, 1, 100, -3000, 11400, 10, 0);
    s_designate (ic, &t, 100);
    uint64_t n = gd_intercept_task (ic)->number;
    t = s_track (7, 3, 110, -2900, 11400, 10, 0);
    gd_intercept_track (ic, &t);
    // The deleted track's later word is ignored.
    t = s_track (7, 1, 200, 0, 0, 0, -10);
    gd_intercept_track (ic, &t);
    assert_int_equal (gd_intercept_task (ic)->number, n);
    gd_intercept_tick (ic, 100 + p.lost_after_s - 1);
    gd_status_t st = s_status (ic);
    assert_true (st.phase == GD_TO_SECONDARY || st.phase == GD_TO_WAYPOINT);
    assert_int_equal (gd_intercept_task (ic)->number, n);
    gd_intercept_tick (ic, 100 + p.lost_after_s + 1);
    st = s_status (ic);
    assert_int_equal (st.phase, GD_LOST);
    assert_false (st.has_footprint);
    assert_false (st.has_plan);
    assert_has (st.reason, "not updated");
    const gd_task_t *tk = gd_intercept_task (ic);
    assert_int_equal (tk->kind, GD_TASK_LOITER_HERE);
    assert_int_equal (tk->number, n + 1);
    assert_int_equal (st.route_count, 0);
    // Lost is not active: another tick is no new task.
    gd_intercept_tick (ic, 100 + 3 * p.lost_after_s);
    assert_int_equal (gd_intercept_task (ic)->number, n + 1);
    gd_intercept_destroy (&ic);
}

/* ---- gd_pick_nearest ------------------------------------------------------------------------- */

static void test_pick_nearest (void **state)
{
    (void)state;
    gd_track_t tr[6];
    gd_v2_t p = gd_v2 (1000, 1000);
    // 0: filtered position far (3000 m), but its newest hit 100 m from p
    //    (its oldest hit is on p: the newest counts, not the oldest).
    tr[0] = s_track (1, 1, 10, 4000, 1000, 0, 0);
    tr[0].history[0] = gd_v2 (1000, 1000);
    tr[0].history[1] = gd_v2 (1000, 1100);
    tr[0].history_count = 2;
    // 1: filtered position 50 m from p, newest hit 300 m.
    tr[1] = s_track (2, 2, 10, 1050, 1000, 0, 0);
    tr[1].history[0] = gd_v2 (1300, 1000);
    tr[1].history_count = 1;
    // 2, 3: tentative and deleted, right on p.
    tr[2] = s_track (3, 0, 10, 1000, 1000, 0, 0);
    tr[3] = s_track (4, 3, 10, 1000, 1000, 0, 0);
    // 4: friendly, no history, 200 m (3-4-5: (120, 160)).
    tr[4] = s_track (5, 1, 10, 1120, 1160, 0, 0);
    tr[4].friendly = true;
    // 5: friendly coasting, 500 m.
    tr[5] = s_track (6, 2, 10, 1000, 500, 0, 0);
    tr[5].friendly = true;

    double d = -1;
    assert_int_equal (gd_pick_nearest (tr, 6, p, GD_PICK_ANY, &d), 0);
    assert_near (d, 100, 1e-9);
    assert_int_equal (gd_pick_nearest (tr, 6, p, GD_PICK_UNKNOWN, &d), 0);
    assert_near (d, 100, 1e-9);
    assert_int_equal (gd_pick_nearest (tr, 6, p, GD_PICK_FRIENDLY, &d), 4);
    assert_near (d, 200, 1e-9);
    // Without track 0, track 1 by its newest hit (300 m) loses to the friendly 200 m.
    assert_int_equal (gd_pick_nearest (tr + 1, 5, p, GD_PICK_ANY, &d), 3);
    assert_near (d, 200, 1e-9);
    assert_int_equal (gd_pick_nearest (tr + 1, 5, p, GD_PICK_UNKNOWN, &d), 0);
    assert_near (d, 300, 1e-9);
    // Only the friendly coasting one left of the friendlies.
    assert_int_equal (gd_pick_nearest (tr + 5, 1, p, GD_PICK_FRIENDLY, &d), 0);
    assert_near (d, 500, 1e-9);
    // Nothing qualifies: -ENOENT, the distance untouched; NULL distance is fine.
    d = -7;
    assert_int_equal (gd_pick_nearest (tr + 2, 2, p, GD_PICK_ANY, &d), -ENOENT);
    assert_near (d, -7, 0);
    assert_int_equal (gd_pick_nearest (tr + 4, 2, p, GD_PICK_UNKNOWN, &d), -ENOENT);
    assert_near (d, -7, 0);
    assert_int_equal (gd_pick_nearest (tr, 2, p, GD_PICK_FRIENDLY, &d), -ENOENT);
    assert_int_equal (gd_pick_nearest (tr, 0, p, GD_PICK_ANY, &d), -ENOENT);
    assert_near (d, -7, 0);
    assert_int_equal (gd_pick_nearest (tr, 6, p, GD_PICK_ANY, NULL), 0);
}

/* ---- small things ------------------------------------------------------------------------------
 */

static void test_set_scale (void **state)
{
    (void)state;
    gd_params_t p = s_params ();
    gd_intercept_t *ic = s_new (&p);
    assert_int_equal (s_status (ic).display_scale, 1);
    const uint32_t good[] = {5, 10, 1};
    for (size_t i = 0; i < 3; i++) {
        assert_int_equal (gd_intercept_set_scale (ic, good[i]), 0);
        assert_int_equal (s_status (ic).display_scale, good[i]);
    }
    assert_int_equal (gd_intercept_set_scale (ic, 10), 0);
    const uint32_t bad[] = {0, 2, 3, 4, 6, 9, 11, 50, 100, UINT32_MAX};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        assert_int_equal (gd_intercept_set_scale (ic, bad[i]), -EINVAL);
        assert_int_equal (s_status (ic).display_scale, 10);
    }
    gd_intercept_destroy (&ic);
}

static void test_new_destroy_names (void **state)
{
    (void)state;
    assert_null (gd_intercept_new (NULL, NULL));
    gd_params_t p = s_params ();
    p.turn_radius_factor = 0.5; // below its range (1..10)
    assert_null (gd_intercept_new (&p, NULL));
    gd_intercept_t *ic = NULL;
    gd_intercept_destroy (&ic);
    gd_intercept_destroy (NULL);
    p = s_params ();
    ic = s_new (&p);
    gd_status_t st = s_status (ic);
    assert_int_equal (st.phase, GD_IDLE);
    assert_int_equal (st.method, GD_HEAD_ON);
    assert_true (isnan (st.time_to_go_s));
    assert_true (isnan (st.overflight_s));
    assert_has (st.reason, "nothing designated");
    gd_intercept_destroy (&ic);
    assert_null (ic);
    assert_string_equal (gd_phase_name (GD_IDLE), "IDLE");
    assert_string_equal (gd_phase_name (GD_TO_SECONDARY), "TO_SECONDARY");
    assert_string_equal (gd_phase_name (GD_PRECISION), "PRECISION");
    assert_string_equal (gd_phase_name (GD_DONE), "DONE");
    assert_string_equal (gd_phase_name (GD_LOST), "LOST");
    assert_string_equal (gd_phase_name ((gd_phase_t)9), "?");
}

int main (void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test (test_designate_plan_eq1),
        cmocka_unit_test (test_uav_ahead_no_secondary),
        cmocka_unit_test (test_uav_behind_secondary),
        cmocka_unit_test (test_standing_target),
        cmocka_unit_test (test_replan_on_direction_change),
        cmocka_unit_test (test_cancel),
        cmocka_unit_test (test_preempt),
        cmocka_unit_test (test_refusals),
        cmocka_unit_test (test_save_restore),
        cmocka_unit_test (test_precision_eq9),
        cmocka_unit_test (test_overflight_done),
        cmocka_unit_test (test_deleted_handover),
        cmocka_unit_test (test_deleted_lost),
        cmocka_unit_test (test_pick_nearest),
        cmocka_unit_test (test_set_scale),
        cmocka_unit_test (test_new_destroy_names),
    };
    return cmocka_run_group_tests (tests, NULL, NULL);
}
