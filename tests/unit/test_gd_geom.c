/* test_gd_geom — guidanced's intercept geometry against theory and hand
 * computation:
 *   - the vector and heading helpers;
 *   - gd_arc_length (turn of radius r, then the tangent): straight ahead, a
 *     quarter circle, a point abeam, a point behind and a point inside one
 *     turn circle, each worked out by hand; a point exactly on a turn circle;
 *     mirror and rotation symmetry;
 *   - equation 1 (P_waypt = P_T + V_T·t_pred + (z_u·cot ε)·D_T) on cases where
 *     t_pred has a closed form: a target receding along the UAV's heading
 *     (t = d/(s − v)), one coming head-on (t = d/(s + v)) and one crossing so
 *     that the meeting point is straight ahead (t = d/s); a target standing
 *     still; the fixed point t_pred·s = L(P_T + V_T·t_pred);
 *   - min_t_pred_s (t_pred at least it); the flyable route's timing
 *     (gd_waypoint_flyable, gd_route_length): a straight route ahead, shorter
 *     than the arc, keeps equation 1; a UAV behind the target, heading away,
 *     whose route (U-turn, straight to P_2, U-turn, straight to the
 *     waypoint) has the closed form R(t) = W + 2·y2 + 2π·r and lengthens
 *     t_pred to R(t_pred)/s within 0.5 s; bad input; a geometry with no
 *     fixed point (-EINVAL or a route that fits) and a NULL result (both
 *     fail at present: see the cases);
 *   - equations 2–3: the target frame on hand examples; the paper's
 *     equation 3 (Δ the projection onto the cross-track axis) worked by
 *     hand; the extension's secondary waypoint as the reflection of the UAV
 *     (k = 1), its lead-in clamp, its scale k, and the matrix form
 *     Δ = Rᵀ·diag(1, −k)·R for a general direction;
 *   - equation 9 (gd_precision_step): the step, the projection onto the
 *     target's line, n steps;
 *   - Dubins paths: a semicircle, the U-turn in place (7πr/3), the same
 *     heading one diameter abeam ((2π + 2)·r), straight ahead, start and
 *     goal the same pose (length 0); random poses
 *     against an independent geometric enumeration of the six words
 *     (tangent lines between the turn circles, and the circle tangent to
 *     both); the sampler's points on the path, their spacing, truncation;
 *   - the imaging sensor's footprint: the pinhole rays through the image's
 *     corners met with flat ground, worked out by hand; heading, roll and
 *     pitch; a level and a tilted terrain plane; a ray above the horizon cut
 *     at max range; containment, distance and scale on the hand trapezoid.
 * Needs -Iservices/guidanced (and -Icommon) on the include path. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cgs_terrain.h"
#include "gd_geom.h"
#include "test_util.h"

/* Two ground points equal within tol metres, east and north. */
#define assert_v2_near(a, b, tol)                                                                  \
    do {                                                                                           \
        gd_v2_t a_ = (a), b_ = (b);                                                                \
        test_util_near_v ((double[]){a_.e, a_.n}, (double[]){b_.e, b_.n}, 2, (tol), #a, __FILE__,  \
                          __LINE__);                                                               \
    } while (0)

#define PI  3.14159265358979323846
#define DEG (PI / 180.0)

/* ---- helpers ----------------------------------------------------------------------- */

/* xorshift64*: the same sequence on every machine. */
static uint64_t s_rng = 0x9E3779B97F4A7C15ull;
static double s_uniform (double lo, double hi)
{
    s_rng ^= s_rng >> 12;
    s_rng ^= s_rng << 25;
    s_rng ^= s_rng >> 27;
    uint64_t x = s_rng * 0x2545F4914F6CDD1Dull;
    return lo + (hi - lo) * (double)(x >> 11) / 9007199254740992.0;
}

/* |a − b| between two headings, degrees, in [0, 180]. */
static double s_heading_err (double a_deg, double b_deg)
{
    return fabs (remainder (a_deg - b_deg, 360.0));
}

static double s_wrap2pi (double a)
{
    double m = fmod (a, 2 * PI);
    return m < 0 ? m + 2 * PI : m;
}

/* The default engagement of the worked examples: UAV at the origin heading
 * east at 40 m/s, 500 m turns, 1200 m above the ground, 45° depression. */
static gd_engage_t s_engage (void)
{
    gd_engage_t in = {0};
    in.uav = gd_v2 (0, 0);
    in.uav_heading_deg = 90.0;
    in.uav_speed_mps = 40.0;
    in.turn_radius_m = 500.0;
    in.agl_m = 1200.0;
    in.depression_deg = 45.0;
    in.secondary_scale = 1.0;
    in.lead_in_m = 0.0;
    return in;
}

/* The fixed point of equation 1: the UAV flies the arc to the meeting point
 * in t_pred. Stopping when successive t differ by 1e-6·(1 + t) leaves, for a
 * contraction of ratio v/s ≤ 1/4, |t − L/s| ≤ 0.25e-6·(1 + t): within 1e-6
 * relative. */
static void s_assert_fixed_point (const gd_engage_t *in, const gd_waypoint_t *w)
{
    double l = gd_arc_length (in->uav, in->uav_heading_deg, in->turn_radius_m, w->meet);
    assert_near (w->t_pred_s * in->uav_speed_mps, l, 1e-6 * l);
    assert_v2_near (w->meet, gd_add (in->target, gd_scale (in->target_vel, w->t_pred_s)), 1e-9);
    assert_v2_near (w->waypoint, gd_add (w->meet, gd_scale (w->dir, w->lookahead_m)), 1e-9);
}

/* ---- vector and heading helpers ------------------------------------------------------ */

/* Headings are clockwise from north: 90° is east, (0, −1) is 180°; the
 * signed difference is clockwise positive in (−180, 180]. */
static void test_vector_helpers (void **state)
{
    (void)state;
    assert_v2_near (gd_heading_unit (0), gd_v2 (0, 1), 1e-15);
    assert_v2_near (gd_heading_unit (90), gd_v2 (1, 0), 1e-15);
    assert_v2_near (gd_heading_unit (210), gd_v2 (-0.5, -sqrt (3) / 2), 1e-15);
    assert_near (gd_heading_of (gd_v2 (0, -1)), 180.0, 1e-12);
    assert_near (gd_heading_of (gd_v2 (-1, 1)), 315.0, 1e-12);
    assert_near (gd_heading_of (gd_v2 (1, 0)), 90.0, 1e-12);
    assert_near (gd_heading_diff (350, 10), 20.0, 1e-12);
    assert_near (gd_heading_diff (10, 350), -20.0, 1e-12);
    assert_near (gd_heading_diff (0, 180), 180.0, 1e-12);
    assert_near (gd_heading_diff (180, 0), 180.0, 1e-12); // −180 is outside (−180, 180]
    // b anticlockwise of a: east × north = +1.
    assert_near (gd_cross (gd_v2 (1, 0), gd_v2 (0, 1)), 1.0, 0);
    assert_near (gd_dot (gd_v2 (3, 4), gd_v2 (-4, 3)), 0.0, 0);
    assert_near (gd_norm (gd_v2 (3, 4)), 5.0, 1e-15);
}

/* ---- gd_arc_length ------------------------------------------------------------------- */

/* Straight ahead: no turn, the length is the distance. A UAV heading north
 * that turns right a quarter round its circle (centre (r, 0)) is at (r, r)
 * heading east; a point 100 m further east, (r + 100, r), is reached by that
 * quarter turn and 100 m of tangent: π·r/2 + 100. (−r − 100, r) is the same
 * on the left. */
static void test_arc_length_straight_and_quarter (void **state)
{
    (void)state;
    const double r = 500.0;
    assert_near (gd_arc_length (gd_v2 (10, 20), 0.0, r, gd_v2 (10, 1020)), 1000.0, 1e-6);
    assert_near (gd_arc_length (gd_v2 (10, 20), 90.0, r, gd_v2 (2010, 20)), 2000.0, 1e-6);
    // Heading 30°: 4000 m along (sin 30°, cos 30°) = (0.5, √3/2).
    assert_near (gd_arc_length (gd_v2 (0, 0), 30.0, r, gd_v2 (2000, 2000 * sqrt (3))), 4000.0,
                 1e-6);
    assert_near (gd_arc_length (gd_v2 (0, 0), 0.0, r, gd_v2 (r + 100, r)), PI * r / 2 + 100, 1e-6);
    assert_near (gd_arc_length (gd_v2 (0, 0), 0.0, r, gd_v2 (-r - 100, r)), PI * r / 2 + 100, 1e-6);
    // The same from a UAV at (100, 100) heading east: its right circle is
    // centred at (100, −400), the quarter ends at (600, −400) heading south.
    assert_near (gd_arc_length (gd_v2 (100, 100), 90.0, r, gd_v2 (100 + r, 100 - r - 100)),
                 PI * r / 2 + 100, 1e-6);
}

/* A point exactly where a quarter turn ends, (r, r) from a UAV heading north
 * (on the right turn circle, at its top), is reached by the quarter turn
 * alone: π·r/2, with no tangent. The same for the left quarter, (−r, r), and
 * for every heading (the points rotated with the UAV). A point on a turn
 * circle is not inside it. */
static void test_arc_length_on_turn_circle (void **state)
{
    (void)state;
    const double r = 500.0;
    assert_near (gd_arc_length (gd_v2 (0, 0), 0.0, r, gd_v2 (r, r)), PI * r / 2, 1e-6);
    assert_near (gd_arc_length (gd_v2 (0, 0), 0.0, r, gd_v2 (-r, r)), PI * r / 2, 1e-6);
    for (double h = 0; h < 360; h += 15) {
        gd_v2_t f = gd_heading_unit (h), right = gd_v2 (f.n, -f.e);
        gd_v2_t ql = gd_add (gd_scale (f, r), gd_scale (right, -r));
        gd_v2_t qr = gd_add (gd_scale (f, r), gd_scale (right, r));
        double l = gd_arc_length (gd_v2 (0, 0), h, r, ql),
               rr = gd_arc_length (gd_v2 (0, 0), h, r, qr);
        if (!(fabs (l - PI * r / 2) <= 1e-6 && fabs (rr - PI * r / 2) <= 1e-6))
            fail_msg ("heading %g: left quarter %.9g, right quarter %.9g, expected %.9g", h, l, rr,
                      PI * r / 2);
    }
}

/* Hand geometry, UAV at the origin heading north, r = 500:
 *
 * Abeam at q = (D, 0), D = 2000: the right circle's centre c = (r, 0),
 * |q − c| = D − r = 1500. The tangent from q touches the circle at angle
 * acos(r/1500) above the east axis; the UAV starts at angle π (west of c)
 * and turns clockwise to it: φ = π − acos(1/3). L = r·φ + √(1500² − r²)
 *   = 500·(π − 1.2309594) + 1414.2136 = 955.3166 + 1414.2136 = 2369.5302.
 *
 * Behind at q = (0, −D), D = 3000: c = (r, 0), |q − c|² = r² + D², so the
 * tangent is exactly D. After a clockwise turn φ the point is
 * c + r(cos(π − φ), sin(π − φ)), the heading (cos(π/2 − φ), sin(π/2 − φ));
 * reaching q after D more metres: r(1 − cos φ) + D sin φ = 0 and
 * r sin φ + D cos φ = −D. With φ = π + ψ: r(1 + cos ψ) = D sin ψ, i.e.
 * tan(ψ/2) = r/D (which also satisfies the second). So
 * L = r·(π + 2·atan(r/D)) + D = 500·(π + 0.3302974) + 3000 = 4735.9450.
 * The left turn is the mirror image: the same length.
 *
 * Inside the right circle, q = (r, 0) (its centre): no right turn reaches
 * it; the left circle (centre (−r, 0)) is 2r away, the tangent √3·r, and the
 * tangent point at angle atan(r/√3r) = 30° from the centre-to-q line: the
 * UAV turns anticlockwise from the heading north (90° math) round to the
 * heading 30° (math), 300°. L = 5πr/3 + √3·r = 3484.0193. */
static void test_arc_length_abeam_behind_inside (void **state)
{
    (void)state;
    const double r = 500.0;
    double abeam = r * (PI - acos (r / (2000.0 - r))) + sqrt (1500.0 * 1500.0 - r * r);
    assert_near (abeam, 2369.5302, 1e-4); // the arithmetic of the comment
    assert_near (gd_arc_length (gd_v2 (0, 0), 0.0, r, gd_v2 (2000, 0)), abeam, 1e-6);
    assert_near (gd_arc_length (gd_v2 (0, 0), 0.0, r, gd_v2 (-2000, 0)), abeam, 1e-6);

    double behind = r * (PI + 2 * atan (r / 3000.0)) + 3000.0;
    assert_near (behind, 4735.9450, 1e-4);
    assert_near (gd_arc_length (gd_v2 (0, 0), 0.0, r, gd_v2 (0, -3000)), behind, 1e-6);
    // The same geometry rotated: UAV at (1000, −500) heading 135° (south-east);
    // "behind" is 3000 m towards 315°.
    gd_v2_t back = gd_scale (gd_heading_unit (315.0), 3000.0);
    assert_near (gd_arc_length (gd_v2 (1000, -500), 135.0, r, gd_add (gd_v2 (1000, -500), back)),
                 behind, 1e-6);

    double inside = 5 * PI * r / 3 + sqrt (3) * r;
    assert_near (inside, 3484.0193, 1e-4);
    assert_near (gd_arc_length (gd_v2 (0, 0), 0.0, r, gd_v2 (r, 0)), inside, 1e-6);
    assert_near (gd_arc_length (gd_v2 (0, 0), 0.0, r, gd_v2 (-r, 0)), inside, 1e-6);
}

/* The arc is a property of the geometry: mirroring q across the UAV's track
 * swaps the left and right turns and keeps the length; moving and rotating
 * the UAV and q together keeps it too; and it is never shorter than the
 * straight distance. */
static void test_arc_length_symmetry (void **state)
{
    (void)state;
    s_rng = 12345;
    for (int i = 0; i < 2000; i++) {
        double r = s_uniform (50, 1500);
        gd_v2_t q = gd_v2 (s_uniform (-4000, 4000), s_uniform (-4000, 4000));
        double l = gd_arc_length (gd_v2 (0, 0), 0.0, r, q);
        assert_true (l >= gd_norm (q) - 1e-9);
        assert_near (gd_arc_length (gd_v2 (0, 0), 0.0, r, gd_v2 (-q.e, q.n)), l, 1e-6);
        // Rotate into heading h: north → (sin h, cos h), east → (cos h, −sin h).
        double h = s_uniform (0, 360);
        gd_v2_t fwd = gd_heading_unit (h), right = gd_v2 (fwd.n, -fwd.e);
        gd_v2_t p = gd_v2 (s_uniform (-1e4, 1e4), s_uniform (-1e4, 1e4));
        gd_v2_t q2 = gd_add (p, gd_add (gd_scale (right, q.e), gd_scale (fwd, q.n)));
        assert_near (gd_arc_length (p, h, r, q2), l, 1e-6 * (1 + l));
    }
}

/* ---- equation 1 ---------------------------------------------------------------------- */

/* Target 8000 m straight ahead, moving away along the UAV's heading at
 * 10 m/s: the meeting point stays straight ahead, L = 8000 + 10·t, and
 * t = L/s gives t = d/(s − v) = 8000/30 = 266.667 s. meet = (8000 + 10·t, 0)
 * = (10666.667, 0); ε = 45°: look-ahead z_u·cot ε = 1200 m along D_T = (1, 0):
 * P_waypt = (11866.667, 0). The UAV at the origin is behind it (y'_u =
 * −11866.667 < 0), on the target's line (x'_u = 0): secondary, and with
 * k = 1 the mirror across the waypoint: P_2 = (23733.333, 0). */
static void test_waypoint_target_receding (void **state)
{
    (void)state;
    gd_engage_t in = s_engage ();
    in.target = gd_v2 (8000, 0);
    in.target_vel = gd_v2 (10, 0);
    gd_waypoint_t w;
    assert_int_equal (gd_waypoint (&in, &w), 0);
    double t = 8000.0 / (40.0 - 10.0);
    // A contraction of ratio 1/4 stopped at a step of 1e-6·(1 + t) is within
    // (1/3)·1e-6·(1 + t) of its fixed point.
    assert_near (w.t_pred_s, t, 1e-6 * (1 + t));
    assert_near (w.lookahead_m, 1200.0, 1e-9);
    assert_v2_near (w.dir, gd_v2 (1, 0), 1e-15);
    assert_v2_near (w.meet, gd_v2 (8000 + 10 * t, 0), 1e-2);
    assert_v2_near (w.waypoint, gd_v2 (8000 + 10 * t + 1200, 0), 1e-2);
    assert_near (w.meet.e, 10666.667, 1e-2);
    assert_near (w.waypoint.e, 11866.667, 1e-2);
    s_assert_fixed_point (&in, &w);
    assert_true (w.iterations >= 1);
    // Equations 2–3.
    assert_near (w.x_u_m, 0.0, 1e-9);
    assert_near (w.y_u_m, -w.waypoint.e, 1e-9);
    assert_true (w.secondary);
    assert_v2_near (w.second, gd_v2 (2 * w.waypoint.e, 0), 1e-9);
    assert_near (w.second.e, 23733.333, 2e-2);
}

/* Target 8000 m straight ahead coming head-on at 10 m/s: L = 8000 − 10·t,
 * t = d/(s + v) = 8000/50 = 160 s; meet = (8000 − 1600, 0) = (6400, 0);
 * D_T = (−1, 0); ε = 30°: look-ahead 1200·cot 30° = 1200·√3 = 2078.461 m;
 * P_waypt = (6400 − 2078.461, 0) = (4321.539, 0). The UAV is ahead of the
 * waypoint in the target's frame (y'_u = (−1)·(0 − 4321.539) = +4321.539):
 * no secondary waypoint. */
static void test_waypoint_target_head_on (void **state)
{
    (void)state;
    gd_engage_t in = s_engage ();
    in.depression_deg = 30.0;
    in.target = gd_v2 (8000, 0);
    in.target_vel = gd_v2 (-10, 0);
    gd_waypoint_t w;
    assert_int_equal (gd_waypoint (&in, &w), 0);
    assert_near (w.t_pred_s, 160.0, 1e-6 * 161);
    assert_near (w.lookahead_m, 1200 * sqrt (3), 1e-9);
    assert_near (w.lookahead_m, 2078.461, 1e-3);
    assert_v2_near (w.dir, gd_v2 (-1, 0), 1e-15);
    assert_v2_near (w.meet, gd_v2 (6400, 0), 1e-2);
    assert_v2_near (w.waypoint, gd_v2 (6400 - 1200 * sqrt (3), 0), 1e-2);
    assert_near (w.waypoint.e, 4321.539, 1e-2);
    s_assert_fixed_point (&in, &w);
    assert_near (w.x_u_m, 0.0, 1e-9);
    assert_near (w.y_u_m, w.waypoint.e, 1e-9);
    assert_false (w.secondary);
}

/* A crossing target timed to be straight ahead: UAV heading east at 40 m/s,
 * target at (8000, −2000) moving north at 10 m/s. At t = 200 s it is at
 * (8000, 0), straight ahead at 8000 m = 40·200: t = 200 is the fixed point
 * (any other meeting point is off the track, where L > |q|, and solving
 * |q(t)| = 40·t gives 1500t² + 40000t − 6.8e7 = 0, root 200). meet =
 * (8000, 0); D_T = (0, 1), look-ahead 1200: P_waypt = (8000, 1200).
 * The UAV relative to it: d = (−8000, −1200); x' = D_n·d_e − D_e·d_n = −8000,
 * y' = D_e·d_e + D_n·d_n = −1200: behind, secondary. Δ keeps x' and puts the
 * UAV k·1200 ahead (at least lead_in): k = 1, lead-in 0 → P_2 = (0, 2400),
 * the UAV's mirror across the line n = 1200; lead-in 2000 → (0, 3200);
 * k = 2 → (0, 3600); k = 0.5 → (0, 1800). */
static void test_waypoint_crossing_target (void **state)
{
    (void)state;
    gd_engage_t in = s_engage ();
    in.target = gd_v2 (8000, -2000);
    in.target_vel = gd_v2 (0, 10);
    gd_waypoint_t w;
    assert_int_equal (gd_waypoint (&in, &w), 0);
    assert_near (w.t_pred_s, 200.0, 1e-6 * 201);
    assert_v2_near (w.meet, gd_v2 (8000, 0), 2e-3);
    assert_v2_near (w.waypoint, gd_v2 (8000, 1200), 2e-3);
    s_assert_fixed_point (&in, &w);
    assert_near (w.x_u_m, -w.waypoint.e, 1e-9);
    assert_near (w.y_u_m, -w.waypoint.n, 1e-9);
    assert_true (w.secondary);
    assert_v2_near (w.second, gd_v2 (0, 2400), 5e-3);
    // Exactly the mirror of the UAV across n = waypoint.n.
    assert_v2_near (w.second, gd_v2 (0, 2 * w.waypoint.n), 1e-9);

    in.lead_in_m = 2000.0; // the UAV only 1200 m behind: clamped to the lead-in
    assert_int_equal (gd_waypoint (&in, &w), 0);
    assert_v2_near (w.second, gd_v2 (0, 3200), 5e-3);
    assert_v2_near (w.second, gd_v2 (0, w.waypoint.n + 2000), 1e-9);

    in.lead_in_m = 1000.0; // less than k·1200: not binding
    assert_int_equal (gd_waypoint (&in, &w), 0);
    assert_v2_near (w.second, gd_v2 (0, 2400), 5e-3);

    in.lead_in_m = 0.0;
    in.secondary_scale = 2.0;
    assert_int_equal (gd_waypoint (&in, &w), 0);
    assert_v2_near (w.second, gd_v2 (0, 3600), 5e-3);
    assert_v2_near (w.second, gd_v2 (0, 3 * w.waypoint.n), 1e-9);

    in.secondary_scale = 0.5;
    assert_int_equal (gd_waypoint (&in, &w), 0);
    assert_v2_near (w.second, gd_v2 (0, 1800), 5e-3);

    // The UAV put north of the waypoint line (ahead of it): no secondary.
    in.secondary_scale = 1.0;
    in.uav = gd_v2 (0, 3000);
    assert_int_equal (gd_waypoint (&in, &w), 0);
    assert_true (w.y_u_m > 0);
    assert_false (w.secondary);
    s_assert_fixed_point (&in, &w);
}

/* A general direction, V_T = (−6, 8) (10 m/s towards 323.13°): D_T =
 * (−0.6, 0.8). The fixed point holds; equation 2 is the rotation
 * R = [D_n −D_e; D_e D_n] of P_ug − P_waypt, and equation 3 is
 * P_2 = Rᵀ·diag(1, −k)·R·(P_ug − P_waypt) + P_waypt, built here as matrices.
 * With k = 1, Δ is a reflection: |P_2 − P_waypt| = |P_ug − P_waypt| and the
 * midpoint of P_ug and P_2 lies on the line through the waypoint
 * perpendicular to D_T. The UAV at the origin is south-east of a waypoint
 * that lies north-west of the target, so y'_u = 0.6·wp_e − 0.8·wp_n < 0. */
static void test_waypoint_general_direction (void **state)
{
    (void)state;
    const double ks[3] = {1.0, 0.7, 1.8};
    for (int i = 0; i < 3; i++) {
        gd_engage_t in = s_engage ();
        in.uav_heading_deg = 45.0;
        in.target = gd_v2 (3000, 6000);
        in.target_vel = gd_v2 (-6, 8);
        in.secondary_scale = ks[i];
        gd_waypoint_t w;
        assert_int_equal (gd_waypoint (&in, &w), 0);
        assert_v2_near (w.dir, gd_v2 (-0.6, 0.8), 1e-15);
        s_assert_fixed_point (&in, &w);
        gd_v2_t d = gd_sub (in.uav, w.waypoint);
        double R[2][2] = {{0.8, 0.6}, {-0.6, 0.8}}; // [D_n −D_e; D_e D_n]
        double x = R[0][0] * d.e + R[0][1] * d.n, y = R[1][0] * d.e + R[1][1] * d.n;
        assert_near (w.x_u_m, x, 1e-9);
        assert_near (w.y_u_m, y, 1e-9);
        assert_true (y < 0);
        assert_true (w.secondary);
        double dy = -ks[i] * y; // diag(1, −k)
        gd_v2_t p2 = gd_v2 (R[0][0] * x + R[1][0] * dy, R[0][1] * x + R[1][1] * dy); // Rᵀ
        assert_v2_near (w.second, gd_add (p2, w.waypoint), 1e-6);
        if (ks[i] == 1.0) {
            assert_near (gd_norm (gd_sub (w.second, w.waypoint)), gd_norm (d), 1e-6);
            gd_v2_t mid = gd_scale (gd_add (w.second, in.uav), 0.5);
            assert_near (gd_dot (gd_sub (mid, w.waypoint), w.dir), 0.0, 1e-6);
        }
    }
    // And a target moving north while the UAV heads east (no closed form):
    // the fixed point still holds.
    gd_engage_t in = s_engage ();
    in.target = gd_v2 (8000, 0);
    in.target_vel = gd_v2 (0, 15);
    gd_waypoint_t w;
    assert_int_equal (gd_waypoint (&in, &w), 0);
    s_assert_fixed_point (&in, &w);
    assert_true (w.meet.n > 0);
}

/* Equation 3 as the paper writes it, worked by hand. D_T = (d_x, d_y) =
 * (0.6, 0.8) (east, north); Δ = [[d_y², −d_x·d_y], [−d_x·d_y, d_x²]] =
 * [[0.64, −0.48], [−0.48, 0.36]]. Waypoint (1000, 2000), UAV (−3000, 500):
 * P_ug − P_waypt = (−4000, −1500); Δ·(−4000, −1500) = (0.64·−4000 +
 * 0.48·1500, 0.48·4000 − 0.36·1500) = (−2560 + 720, 1920 − 540) =
 * (−1840, 1380); P_2 = (1000 − 1840, 2000 + 1380) = (−840, 3380). Δ is the
 * projection onto the cross-track axis (0.8, −0.6): the UAV's cross-track
 * offset x' = 0.8·−4000 − 0.6·−1500 = −2300, P_2 = P_waypt − 2300·(0.8, −0.6),
 * abeam the waypoint (no along-track part: no lead-in, no k), and Δ² = Δ.
 * The extension on the same numbers (k = 0.25, lead-in 2000): y' = 0.6·−4000
 * + 0.8·−1500 = −3600, ahead max(0.25·3600, 2000) = 2000: P_2 = (−840, 3380)
 * + 2000·(0.6, 0.8) = (360, 4980). And on the crossing case of
 * test_waypoint_crossing_target (waypoint (8000, 1200), D_T north, UAV at
 * the origin): the paper's P_2 = (0, 1200), beside the waypoint. */
static void test_equation3_paper (void **state)
{
    (void)state;
    gd_engage_t in = s_engage ();
    in.secondary_paper = true;
    in.secondary_scale = 0.25; // ignored by the paper's
    in.lead_in_m = 2000;       // ignored by the paper's
    in.uav = gd_v2 (-3000, 500);
    gd_v2_t wp = gd_v2 (1000, 2000), dir = gd_v2 (0.6, 0.8);
    gd_v2_t p2 = gd_secondary_point (&in, wp, dir);
    assert_v2_near (p2, gd_v2 (-840, 3380), 1e-9);
    // Δ as the paper's matrix, applied by hand.
    double dx = 0.6, dy = 0.8, ve = -4000, vn = -1500;
    gd_v2_t m = gd_v2 (dy * dy * ve - dx * dy * vn, -dx * dy * ve + dx * dx * vn);
    assert_v2_near (p2, gd_add (wp, m), 1e-9);
    // Abeam: no along-track part; a projection: the UAV put at P_2 maps to P_2.
    assert_near (gd_dot (gd_sub (p2, wp), dir), 0.0, 1e-9);
    in.uav = p2;
    assert_v2_near (gd_secondary_point (&in, wp, dir), p2, 1e-9);
    // The extension on the same numbers.
    in.uav = gd_v2 (-3000, 500);
    in.secondary_paper = false;
    assert_v2_near (gd_secondary_point (&in, wp, dir), gd_v2 (360, 4980), 1e-9);
    // The offset bounded: the UAV is x' = -2300 m abeam (right = (0.8, -0.6));
    // at most 1000 m: P_2 = wp - 1000 right = (200, 2600) for the paper's,
    // that plus the lead-in 2000 dir = (1400, 4200) for the extension; a
    // bound wider than the offset changes nothing.
    in.offset_max_m = 1000;
    assert_v2_near (gd_secondary_point (&in, wp, dir), gd_v2 (1400, 4200), 1e-9);
    in.secondary_paper = true;
    assert_v2_near (gd_secondary_point (&in, wp, dir), gd_v2 (200, 2600), 1e-9);
    in.offset_max_m = 2300.5;
    assert_v2_near (gd_secondary_point (&in, wp, dir), gd_v2 (-840, 3380), 1e-9);
    in.offset_max_m = 0;
    // Through gd_waypoint, on the crossing case (t_pred 200 s, waypoint
    // (8000, 1200)): P_2 = (0, 1200).
    in = s_engage ();
    in.secondary_paper = true;
    in.lead_in_m = 2000;
    in.target = gd_v2 (8000, -2000);
    in.target_vel = gd_v2 (0, 10);
    gd_waypoint_t w;
    assert_int_equal (gd_waypoint (&in, &w), 0);
    assert_true (w.secondary);
    assert_v2_near (w.waypoint, gd_v2 (8000, 1200), 2e-3);
    assert_v2_near (w.second, gd_v2 (0, w.waypoint.n), 1e-9);
    // The straight run into the waypoint fits in half the way from P_2.
    in.settle_m = 800;
    assert_int_equal (gd_waypoint (&in, &w), 0);
    assert_near (w.settle_m, 800, 1e-9);
    in.settle_m = 5000;
    assert_int_equal (gd_waypoint (&in, &w), 0);
    assert_near (w.settle_m, 0.5 * gd_norm (gd_sub (w.second, w.waypoint)), 1e-9);
}

/* The prediction horizon: the crossing case (t_pred 200 s) with a horizon of
 * 150 s meets the target where it is at 150 s, (8000, −500), the waypoint
 * 1200 m on along D_T, (8000, 700), and says it is limited; a horizon of
 * 250 s or none (0) leaves t_pred at 200 s. The flyable route into the
 * waypoint of a receding target takes longer than equation 1's t_pred
 * (the UAV must go past it and turn back): a horizon below both cuts the
 * route timing too. */
static void test_horizon (void **state)
{
    (void)state;
    gd_engage_t in = s_engage ();
    in.target = gd_v2 (8000, -2000);
    in.target_vel = gd_v2 (0, 10);
    gd_waypoint_t w;
    in.horizon_s = 150;
    assert_int_equal (gd_waypoint (&in, &w), 0);
    assert_true (w.limited);
    assert_near (w.t_pred_s, 150, 1e-12);
    assert_v2_near (w.meet, gd_v2 (8000, -500), 1e-9);
    assert_v2_near (w.waypoint, gd_v2 (8000, 700), 1e-9);
    in.horizon_s = 250;
    assert_int_equal (gd_waypoint (&in, &w), 0);
    assert_false (w.limited);
    assert_near (w.t_pred_s, 200, 1e-6 * 201);
    in.horizon_s = 0;
    assert_int_equal (gd_waypoint (&in, &w), 0);
    assert_false (w.limited);
    in.horizon_s = NAN;
    assert_int_equal (gd_waypoint (&in, &w), -EINVAL);
    in.horizon_s = -1;
    assert_int_equal (gd_waypoint (&in, &w), -EINVAL);
    // Receding: 8000 m ahead at 10 m/s, equation 1's t_pred 266.7 s, the
    // flyable route's longer; a horizon of 300 s cuts the route's.
    in = s_engage ();
    in.target = gd_v2 (8000, 0);
    in.target_vel = gd_v2 (10, 0);
    in.lead_in_m = 2000;
    assert_int_equal (gd_waypoint_flyable (&in, &w), 0);
    assert_false (w.limited);
    double free_t = w.t_pred_s;
    assert_true (free_t > 300);
    in.horizon_s = 300;
    assert_int_equal (gd_waypoint_flyable (&in, &w), 0);
    assert_true (w.limited);
    assert_near (w.t_pred_s, 300, 1e-12);
    assert_v2_near (w.meet, gd_v2 (11000, 0), 1e-9);
}

/* A target standing still (V_T = 0): D_T is taken from the target towards
 * the UAV, so the UAV comes in along the line joining them, and t_pred is
 * the arc to the target itself (the fixed point at once).
 * Target (8000, 0) ahead of a UAV at the origin heading east: D_T = (−1, 0),
 * t = 8000/40 = 200 s, P_waypt = (8000 − 1200, 0) = (6800, 0); the UAV is
 * ahead of it in the target's frame (y' = 6800): no secondary.
 * Target (−3000, 0) behind: D_T = (1, 0), t = L/40 with L the turn-around of
 * test_arc_length_abeam_behind_inside, r(π + 2·atan(r/3000)) + 3000 =
 * 4735.9450 m: t = 118.3986 s; P_waypt = (−1800, 0), y' = 1800: no
 * secondary. */
static void test_waypoint_target_standing (void **state)
{
    (void)state;
    gd_engage_t in = s_engage ();
    in.target = gd_v2 (8000, 0);
    in.target_vel = gd_v2 (0, 0);
    gd_waypoint_t w;
    assert_int_equal (gd_waypoint (&in, &w), 0);
    assert_v2_near (w.dir, gd_v2 (-1, 0), 1e-15);
    assert_near (w.t_pred_s, 200.0, 1e-9);
    assert_v2_near (w.meet, gd_v2 (8000, 0), 0);
    assert_v2_near (w.waypoint, gd_v2 (6800, 0), 1e-9);
    assert_near (w.y_u_m, 6800.0, 1e-9);
    assert_false (w.secondary);

    in.target = gd_v2 (-3000, 0);
    assert_int_equal (gd_waypoint (&in, &w), 0);
    double r = in.turn_radius_m;
    assert_v2_near (w.dir, gd_v2 (1, 0), 1e-15);
    assert_near (w.t_pred_s, (r * (PI + 2 * atan (r / 3000.0)) + 3000.0) / 40.0, 1e-9);
    assert_near (w.t_pred_s, 118.3986, 1e-4);
    assert_v2_near (w.waypoint, gd_v2 (-1800, 0), 1e-9);
    assert_near (w.y_u_m, 1800.0, 1e-9);
    assert_false (w.secondary);
}

/* Bad input is refused and the result left alone: a target as fast as the
 * UAV (no fixed point), ε out of (0°, 90°), no turn radius, no height,
 * non-finite positions. */
static void test_waypoint_rejects_bad_input (void **state)
{
    (void)state;
    gd_engage_t good = s_engage ();
    good.target = gd_v2 (8000, 0);
    good.target_vel = gd_v2 (-10, 0);
    gd_waypoint_t w, before;
    memset (&w, 0x5a, sizeof w);
    before = w;
    gd_engage_t in = good;
    in.target_vel = gd_v2 (-40, 0);
    assert_int_equal (gd_waypoint (&in, &w), -EINVAL);
    in.target_vel = gd_v2 (30, 30); // 42.4 m/s
    assert_int_equal (gd_waypoint (&in, &w), -EINVAL);
    in = good;
    in.depression_deg = 0;
    assert_int_equal (gd_waypoint (&in, &w), -EINVAL);
    in.depression_deg = 90;
    assert_int_equal (gd_waypoint (&in, &w), -EINVAL);
    in = good;
    in.turn_radius_m = 0;
    assert_int_equal (gd_waypoint (&in, &w), -EINVAL);
    in = good;
    in.agl_m = -1;
    assert_int_equal (gd_waypoint (&in, &w), -EINVAL);
    in = good;
    in.uav.e = NAN;
    assert_int_equal (gd_waypoint (&in, &w), -EINVAL);
    in = good;
    in.settle_m = -1;
    assert_int_equal (gd_waypoint (&in, &w), -EINVAL);
    in.settle_m = NAN;
    assert_int_equal (gd_waypoint (&in, &w), -EINVAL);
    assert_int_equal (gd_waypoint (NULL, &w), -EINVAL);
    assert_int_equal (gd_waypoint (&good, NULL), -EINVAL);
    assert_memory_equal (&w, &before, sizeof w);
}

/* ---- the flyable route's timing (gd_waypoint_flyable, gd_route_length) ------------------ */

/* min_t_pred_s: t_pred is at least it. The head-on target of 8000 m ahead
 * (ε = 45°: look-ahead 1200 m) has equation 1's t_pred = 8000/50 = 160 s;
 * with min_t_pred_s = 300 s, t_pred = 300 s: meet = (8000 − 3000, 0) =
 * (5000, 0), waypoint (3800, 0), y'_u = 3800 > 0. A minimum below 160 s, or
 * 0, leaves equation 1 alone. gd_waypoint's route_m is 0. */
static void test_waypoint_min_t_pred (void **state)
{
    (void)state;
    gd_engage_t in = s_engage ();
    in.target = gd_v2 (8000, 0);
    in.target_vel = gd_v2 (-10, 0);
    gd_waypoint_t w;
    in.min_t_pred_s = 300;
    assert_int_equal (gd_waypoint (&in, &w), 0);
    assert_near (w.t_pred_s, 300, 0);
    assert_v2_near (w.meet, gd_v2 (5000, 0), 1e-9);
    assert_v2_near (w.waypoint, gd_v2 (3800, 0), 1e-9);
    assert_near (w.y_u_m, 3800, 1e-9);
    assert_false (w.secondary);
    assert_near (w.route_m, 0, 0);
    const double below[2] = {100, 0};
    for (int i = 0; i < 2; i++) {
        in.min_t_pred_s = below[i];
        assert_int_equal (gd_waypoint (&in, &w), 0);
        assert_near (w.t_pred_s, 160, 1e-6 * 161);
        assert_v2_near (w.waypoint, gd_v2 (5200, 0), 2e-3);
        s_assert_fixed_point (&in, &w);
    }
}

/* Ahead, a straight route: UAV at the origin heading east, the target
 * 8000 m ahead coming head-on at 10 m/s (ε = 45°). Equation 1: t_pred =
 * 160 s, waypoint (6400 − 1200, 0) = (5200, 0), entered heading −D_T =
 * east, the UAV's own heading: the Dubins path is the straight 5200 m,
 * 130 s at 40 m/s, within equation 1's 160 s, so gd_waypoint_flyable keeps
 * equation 1's plan, with route_m = 5200. */
static void test_flyable_straight (void **state)
{
    (void)state;
    gd_engage_t in = s_engage ();
    in.target = gd_v2 (8000, 0);
    in.target_vel = gd_v2 (-10, 0);
    gd_waypoint_t w0, w;
    assert_int_equal (gd_waypoint (&in, &w0), 0);
    assert_near (gd_route_length (&in, &w0), 5200, 2e-3);
    assert_int_equal (gd_waypoint_flyable (&in, &w), 0);
    assert_near (w.route_m, 5200, 2e-3);
    assert_near (w.route_m, gd_route_length (&in, &w0), 1e-9);
    assert_true (w.t_pred_s == w0.t_pred_s);
    assert_near (w.t_pred_s, 160, 1e-6 * 161);
    assert_v2_near (w.waypoint, w0.waypoint, 0);
    assert_int_equal (w.iterations, w0.iterations);
    assert_false (w.secondary);
}

/* Behind, through P_2: the UAV at the origin heading west (away from the
 * target), the target 8000 m east receding east at 10 m/s; k = 0, lead-in
 * 2000 m, r = 500 m, ε = 45°. For a t_pred t: waypoint (W, 0), W = 8000 +
 * 10·t + 1200; y'_u = −W: P_2 = (W + 2000, 0) (k·|y'_u| = 0 < lead-in).
 * The route: from (0, 0) heading west to P_2 heading west (towards the
 * waypoint), a goal straight behind with the same heading: a U-turn (π·r),
 * the straight W + 2000 east, a U-turn (π·r); then the straight 2000 m into
 * the waypoint, heading west = −D_T: R(t) = W + 4000 + 2π·r = 13 200 +
 * 10·t + 1000π. Equation 1's arc (turning round to the target) gives about
 * 320 s; the route then takes far longer, so t is lengthened: t ← R(t)/40,
 * ratio 1/4, rising to t* = (13 200 + 1000π)/30 ≈ 544.72 s and stopping once
 * R(t)/40 ≤ t + 0.5, within 0.5/(1 − 1/4) = 2/3 s below t*. The result is
 * equations 1–3 at that t_pred, and route_m = R(t_pred). */
static void test_flyable_behind (void **state)
{
    (void)state;
    gd_engage_t in = s_engage ();
    in.uav_heading_deg = 270;
    in.target = gd_v2 (8000, 0);
    in.target_vel = gd_v2 (10, 0);
    in.secondary_scale = 0;
    in.lead_in_m = 2000;
    double r = in.turn_radius_m;
    gd_waypoint_t arc, w;
    assert_int_equal (gd_waypoint (&in, &arc), 0);
    s_assert_fixed_point (&in, &arc);
    assert_true (arc.secondary);
    assert_near (gd_route_length (&in, &arc), 13200 + 10 * arc.t_pred_s + 1000 * PI, 1e-6);

    assert_int_equal (gd_waypoint_flyable (&in, &w), 0);
    double ts = (13200 + 1000 * PI) / 30;
    if (!(w.t_pred_s <= ts + 1e-9 && w.t_pred_s >= ts - 2.0 / 3 - 1e-9))
        fail_msg ("t_pred %.9g s, expected within 2/3 s below %.9g s", w.t_pred_s, ts);
    assert_true (w.t_pred_s > arc.t_pred_s + 100);
    assert_near (w.route_m, 13200 + 10 * w.t_pred_s + 2 * PI * r, 1e-6);
    assert_near (w.route_m, gd_route_length (&in, &w), 0);
    assert_true (w.route_m / 40 >= w.t_pred_s && w.route_m / 40 <= w.t_pred_s + 0.5);
    // Equations 1–3 at the lengthened t_pred.
    assert_v2_near (w.dir, gd_v2 (1, 0), 0);
    assert_v2_near (w.meet, gd_v2 (8000 + 10 * w.t_pred_s, 0), 1e-9);
    assert_v2_near (w.waypoint, gd_v2 (9200 + 10 * w.t_pred_s, 0), 1e-9);
    assert_near (w.y_u_m, -w.waypoint.e, 1e-9);
    assert_true (w.secondary);
    assert_v2_near (w.second, gd_v2 (w.waypoint.e + 2000, 0), 1e-9);
    // gd_waypoint with that t_pred as its minimum makes the same plan.
    gd_waypoint_t again;
    in.min_t_pred_s = w.t_pred_s;
    assert_int_equal (gd_waypoint (&in, &again), 0);
    assert_v2_near (again.waypoint, w.waypoint, 0);
    assert_v2_near (again.second, w.second, 0);
}

/* The straight run into the waypoint (settle_m). Head-on and ahead, as in
 * test_flyable_straight: waypoint (5200, 0), y'_u = 5200; a settle of 800 m
 * (less than half of 5200) ends the last turn at (4400, 0), and the route,
 * straight throughout, is still 5200 m. The target 2500 m ahead instead:
 * t_pred = 2500/50 = 50 s, meeting point (2000, 0), waypoint (800, 0),
 * y'_u = 800: the settle is cut to half of it, 400 m, the settle point
 * (400, 0). Behind and across, as test_flyable_behind with the target
 * 3000 m north: P_2 keeps the cross-track offset, 2000 m ahead of the
 * waypoint (k = 0), and the settle is 800 m (less than half of
 * |P_2 − waypoint|); the route is the Dubins path to P_2, the Dubins path
 * from P_2 into the settle point heading −D_T, and the 800 m straight, and
 * it is no shorter than the route that turns in at the waypoint itself. */
static void test_settle (void **state)
{
    (void)state;
    gd_engage_t in = s_engage ();
    in.target = gd_v2 (8000, 0);
    in.target_vel = gd_v2 (-10, 0);
    in.settle_m = 800;
    gd_waypoint_t w;
    assert_int_equal (gd_waypoint (&in, &w), 0);
    assert_false (w.secondary);
    assert_near (w.settle_m, 800, 0);
    assert_v2_near (gd_waypoint_settle_point (&w), gd_v2 (4400, 0), 2e-3);
    assert_near (gd_route_length (&in, &w), 5200, 2e-3);

    in.target = gd_v2 (2500, 0);
    assert_int_equal (gd_waypoint (&in, &w), 0);
    assert_false (w.secondary);
    assert_near (w.t_pred_s, 50, 1e-4);
    assert_near (w.y_u_m, 800, 1e-3);
    assert_near (w.settle_m, 0.5 * w.y_u_m, 1e-12);
    assert_v2_near (gd_waypoint_settle_point (&w), gd_v2 (0.5 * w.waypoint.e, 0), 1e-9);

    in = s_engage ();
    in.uav_heading_deg = 270;
    in.target = gd_v2 (8000, 3000);
    in.target_vel = gd_v2 (10, 0);
    in.secondary_scale = 0;
    in.lead_in_m = 2000;
    in.settle_m = 800;
    assert_int_equal (gd_waypoint (&in, &w), 0);
    assert_true (w.secondary);
    assert_near (gd_norm (gd_sub (w.second, w.waypoint)), hypot (w.x_u_m, 2000), 1e-9);
    assert_near (w.settle_m, 800, 0);
    gd_v2_t settle = gd_waypoint_settle_point (&w);
    assert_v2_near (settle, gd_v2 (w.waypoint.e + 800, w.waypoint.n), 1e-9);
    double h2, hf;
    gd_waypoint_headings (&w, &h2, &hf);
    assert_near (hf, 270, 1e-9);
    gd_dubins_t a, b, c;
    assert_int_equal (gd_dubins (in.uav, in.uav_heading_deg, w.second, h2, 500, &a), 0);
    assert_int_equal (gd_dubins (w.second, h2, settle, hf, 500, &b), 0);
    assert_int_equal (gd_dubins (w.second, h2, w.waypoint, hf, 500, &c), 0);
    double len = gd_route_length (&in, &w);
    assert_near (len, gd_dubins_length (&a) + gd_dubins_length (&b) + 800, 1e-9);
    assert_true (len >= gd_dubins_length (&a) + gd_dubins_length (&c) - 1e-9);
    // Without a settle, the route turns in at the waypoint.
    in.settle_m = 0;
    gd_waypoint_t w0;
    assert_int_equal (gd_waypoint (&in, &w0), 0);
    assert_near (w0.settle_m, 0, 0);
    assert_v2_near (gd_waypoint_settle_point (&w0), w0.waypoint, 0);
    assert_near (gd_route_length (&in, &w0), gd_dubins_length (&a) + gd_dubins_length (&c), 1e-9);
}

/* Bad input: gd_waypoint_flyable refuses what gd_waypoint refuses and
 * leaves the result alone; gd_route_length is NaN when a leg cannot be
 * built (no turn radius, a non-finite position). */
static void test_flyable_rejects_bad_input (void **state)
{
    (void)state;
    gd_engage_t good = s_engage ();
    good.target = gd_v2 (8000, 0);
    good.target_vel = gd_v2 (-10, 0);
    gd_waypoint_t w, before;
    memset (&w, 0x5a, sizeof w);
    before = w;
    gd_engage_t in = good;
    in.target_vel = gd_v2 (-40, 0); // as fast as the UAV
    assert_int_equal (gd_waypoint_flyable (&in, &w), -EINVAL);
    in = good;
    in.depression_deg = 90;
    assert_int_equal (gd_waypoint_flyable (&in, &w), -EINVAL);
    in = good;
    in.turn_radius_m = 0;
    assert_int_equal (gd_waypoint_flyable (&in, &w), -EINVAL);
    in = good;
    in.target.n = INFINITY;
    assert_int_equal (gd_waypoint_flyable (&in, &w), -EINVAL);
    assert_int_equal (gd_waypoint_flyable (NULL, &w), -EINVAL);
    assert_memory_equal (&w, &before, sizeof w);
    // (No result pointer: test_flyable_null_result, run last.)

    gd_waypoint_t ok;
    assert_int_equal (gd_waypoint (&good, &ok), 0);
    in = good;
    in.turn_radius_m = 0;
    assert_true (isnan (gd_route_length (&in, &ok)));
    in = good;
    in.uav.e = NAN;
    assert_true (isnan (gd_route_length (&in, &ok)));
}

/* No fixed point: behind the target the route grows by about (1 + 2k)·v per
 * second of t_pred; with k = 1 and v = 15 m/s that is 45 m/s against the
 * UAV's 40, so t ← route(t)/s runs away. gd_waypoint_flyable then returns
 * equation 1's plan unchanged (gd_waypoint's), with that plan's route
 * length — which takes longer than its t_pred. */
static void test_flyable_no_fixed_point (void **state)
{
    (void)state;
    gd_engage_t in = s_engage ();
    in.target = gd_v2 (8000, 0);
    in.target_vel = gd_v2 (15, 0);
    gd_waypoint_t w, eq1;
    assert_int_equal (gd_waypoint_flyable (&in, &w), 0);
    assert_int_equal (gd_waypoint (&in, &eq1), 0);
    assert_true (eq1.secondary);
    assert_near (w.t_pred_s, eq1.t_pred_s, 0);
    assert_v2_near (w.waypoint, eq1.waypoint, 0);
    assert_v2_near (w.second, eq1.second, 0);
    assert_near (w.route_m, gd_route_length (&in, &eq1), 1e-9);
    assert_true (w.route_m / in.uav_speed_mps > w.t_pred_s + 0.5);
    // Slower than s/(1 + 2k) = 13.3 m/s it settles: the route takes t_pred.
    in.target_vel = gd_v2 (12, 0);
    assert_int_equal (gd_waypoint_flyable (&in, &w), 0);
    assert_true (w.t_pred_s > eq1.t_pred_s);
    assert_true (w.route_m / in.uav_speed_mps <= w.t_pred_s + 0.5);
}

/* gd_waypoint_flyable refuses a NULL result as gd_waypoint does. Run last:
 * if it writes through the pointer the sanitizer ends the program. */
static void test_flyable_null_result (void **state)
{
    (void)state;
    gd_engage_t good = s_engage ();
    good.target = gd_v2 (8000, 0);
    good.target_vel = gd_v2 (-10, 0);
    assert_int_equal (gd_waypoint (&good, NULL), -EINVAL);
    assert_int_equal (gd_waypoint_flyable (&good, NULL), -EINVAL);
}

/* ---- equation 2 ---------------------------------------------------------------------- */

/* x' is to the right of the direction, y' along it. Origin (100, 200), point
 * (130, 250), offset (30, 50): direction north → x' = 30 (east), y' = 50
 * (north); direction east → x' = −50 (north is to the left), y' = 30;
 * direction south → (−30, −50); direction north-east (√½, √½) → x' =
 * √½·(30 − 50) = −14.142, y' = √½·80 = 56.569. The rotation keeps lengths. */
static void test_target_frame (void **state)
{
    (void)state;
    gd_v2_t o = gd_v2 (100, 200), q = gd_v2 (130, 250);
    double x, y;
    gd_to_target_frame (o, gd_v2 (0, 1), q, &x, &y);
    assert_near (x, 30.0, 1e-12);
    assert_near (y, 50.0, 1e-12);
    gd_to_target_frame (o, gd_v2 (1, 0), q, &x, &y);
    assert_near (x, -50.0, 1e-12);
    assert_near (y, 30.0, 1e-12);
    gd_to_target_frame (o, gd_v2 (0, -1), q, &x, &y);
    assert_near (x, -30.0, 1e-12);
    assert_near (y, -50.0, 1e-12);
    gd_to_target_frame (o, gd_v2 (sqrt (0.5), sqrt (0.5)), q, &x, &y);
    assert_near (x, -20 * sqrt (0.5), 1e-12);
    assert_near (y, 80 * sqrt (0.5), 1e-12);
    assert_near (x, -14.142, 1e-3);
    assert_near (y, 56.569, 1e-3);
    s_rng = 77;
    for (int i = 0; i < 200; i++) {
        gd_v2_t dir = gd_heading_unit (s_uniform (0, 360));
        gd_v2_t p = gd_v2 (s_uniform (-1e4, 1e4), s_uniform (-1e4, 1e4));
        gd_to_target_frame (o, dir, p, &x, &y);
        assert_near (hypot (x, y), gd_norm (gd_sub (p, o)), 1e-8);
        // Back: o + x'·right + y'·dir.
        gd_v2_t back = gd_add (o, gd_add (gd_scale (gd_v2 (dir.n, -dir.e), x), gd_scale (dir, y)));
        assert_v2_near (back, p, 1e-8);
    }
}

/* ---- equation 9 ---------------------------------------------------------------------- */

/* Target at (1000, 2000) moving along UV = (0.6, 0.8). A point on its line,
 * 500 m ahead (1300, 2400), moves s·dt = 40·10 = 400 m against UV: to 100 m
 * ahead, (1060, 2080). The same point 30 m to the right of the line (right =
 * (0.8, −0.6): (1324, 2382)) is first put back on the line with its
 * along-track 500 kept: the same result. Five steps from (1300, 2400): 500 −
 * 5·400 = −1500 along, (1000 − 900, 2000 − 1200) = (100, 800), 2000 m from
 * the start. */
static void test_precision_step (void **state)
{
    (void)state;
    gd_v2_t target = gd_v2 (1000, 2000), uv = gd_v2 (0.6, 0.8);
    gd_v2_t on = gd_v2 (1300, 2400), off = gd_v2 (1324, 2382);
    assert_v2_near (gd_precision_step (on, target, uv, 40, 10), gd_v2 (1060, 2080), 1e-9);
    assert_near (gd_norm (gd_sub (gd_precision_step (on, target, uv, 40, 10), on)), 400.0, 1e-9);
    assert_v2_near (gd_precision_step (off, target, uv, 40, 10), gd_v2 (1060, 2080), 1e-9);
    // 30 m to the left instead: (1300 − 24, 2400 + 18).
    assert_v2_near (gd_precision_step (gd_v2 (1276, 2418), target, uv, 40, 10), gd_v2 (1060, 2080),
                    1e-9);
    gd_v2_t p = on;
    for (int n = 1; n <= 5; n++) {
        p = gd_precision_step (p, target, uv, 40, 10);
        assert_near (gd_norm (gd_sub (p, on)), 400.0 * n, 1e-9);
    }
    assert_v2_near (p, gd_v2 (100, 800), 1e-9);
    // dt = 0: only the projection.
    assert_v2_near (gd_precision_step (off, target, uv, 40, 0), on, 1e-9);
}

/* ---- Dubins paths ------------------------------------------------------------------ */

/* The segment kinds of each word, in the header's order. */
static const char *const s_kinds[6] = {"LSL", "LSR", "RSL", "RSR", "RLR", "LRL"};

/* Centre of the turn circle on side k ('L' or 'R') of pose (p, math angle th). */
static gd_v2_t s_centre (gd_v2_t p, double th, double r, char k)
{
    double sg = k == 'L' ? 1.0 : -1.0;
    return gd_v2 (p.e - sg * r * sin (th), p.n + sg * r * cos (th));
}

/* Turn from math angle a to b on side k, radians in [0, 2π). */
static double s_turn (double a, double b, char k)
{
    return k == 'L' ? s_wrap2pi (b - a) : s_wrap2pi (a - b);
}

/* An independent enumeration of the Dubins candidates, by plane geometry:
 * CSC from the tangent lines between the start's and the goal's turn
 * circles (outer for LSL/RSR: the straight is parallel to c1 − c0, length
 * |c1 − c0|; inner for LSR/RSL: with u the straight's direction,
 * c1 − c0 = L·u ∓ 2r·left(u), so u is c1 − c0 turned by ±atan(2r/L),
 * L = √(|c1 − c0|² − 4r²)); CCC from the circle of radius r tangent to both
 * (its centre 2r from each: two choices), every turn in [0, 2π). Every
 * candidate is a flyable path; Dubins showed the shortest is among them, so
 * their minimum is the shortest length. */
static double s_brute_dubins (gd_v2_t p0, double h0, gd_v2_t p1, double h1, double r)
{
    double t0 = (90 - h0) * DEG, t1 = (90 - h1) * DEG;
    double best = INFINITY;
    const char sides[2] = {'L', 'R'};
    for (int i = 0; i < 2; i++)
        for (int j = 0; j < 2; j++) {
            char a = sides[i], b = sides[j];
            gd_v2_t c0 = s_centre (p0, t0, r, a), c1 = s_centre (p1, t1, r, b);
            gd_v2_t v = gd_sub (c1, c0);
            double d = gd_norm (v), psi, len;
            if (a == b) {
                if (d < 1e-12) { // the same circle: one turn
                    best = fmin (best, r * s_turn (t0, t1, a));
                    continue;
                }
                psi = atan2 (v.n, v.e);
                len = d;
            } else {
                if (d < 2 * r)
                    continue;
                len = sqrt (d * d - 4 * r * r);
                psi = atan2 (v.n, v.e) + (a == 'L' ? 1 : -1) * atan2 (2 * r, len);
            }
            best = fmin (best, r * (s_turn (t0, psi, a) + s_turn (psi, t1, b)) + len);
        }
    for (int i = 0; i < 2; i++) {
        char a = sides[i], m = sides[1 - i];
        gd_v2_t c0 = s_centre (p0, t0, r, a), c1 = s_centre (p1, t1, r, a);
        gd_v2_t v = gd_sub (c1, c0);
        double d = gd_norm (v);
        if (d > 4 * r || d < 1e-12)
            continue;
        double off = sqrt (4 * r * r - d * d / 4);
        gd_v2_t mid = gd_scale (gd_add (c0, c1), 0.5), nrm = gd_v2 (-v.n / d, v.e / d);
        for (int sgn = -1; sgn <= 1; sgn += 2) {
            gd_v2_t cm = gd_add (mid, gd_scale (nrm, sgn * off));
            // On a circle travelled anticlockwise the heading is the radius's
            // angle + π/2, clockwise − π/2.
            double g = a == 'L' ? PI / 2 : -PI / 2;
            gd_v2_t r1 = gd_sub (cm, c0), r2 = gd_sub (c1, cm);
            double ha = atan2 (r1.n, r1.e) + g; // at the first tangency
            double hb = atan2 (r2.n, r2.e) - g; // at the second, on the middle circle
            best = fmin (best, r * (s_turn (t0, ha, a) + s_turn (ha, hb, m) + s_turn (hb, t1, a)));
        }
    }
    return best;
}

/* A pose moved along a segment, by rotating about the turn's centre. */
static void s_advance (char k, double r, double len, gd_v2_t *p, double *th)
{
    if (k == 'S') {
        *p = gd_add (*p, gd_scale (gd_v2 (cos (*th), sin (*th)), len));
        return;
    }
    gd_v2_t c = s_centre (*p, *th, r, k);
    double phi = (k == 'L' ? 1 : -1) * len / r;
    gd_v2_t rel = gd_sub (*p, c);
    *p = gd_add (
        c, gd_v2 (rel.e * cos (phi) - rel.n * sin (phi), rel.e * sin (phi) + rel.n * cos (phi)));
    *th += phi;
}

/* Every sample lies on the path, in order: each on a segment at or after the
 * previous one's, strictly further along it; each arc has at least two
 * samples no more than step_deg of turn apart (chord ≤ 2r·sin(step/2)), a
 * straight one, at its end; each segment's last sample is its end; the last
 * sample is the goal. */
static void s_check_samples (const gd_dubins_t *d, double step_deg, const gd_v2_t *pts, size_t n,
                             gd_v2_t goal)
{
    gd_v2_t start[3], end[3];
    double th_start[3];
    gd_v2_t p = d->p0;
    double th = (90 - d->h0_deg) * DEG;
    for (int i = 0; i < 3; i++) {
        start[i] = p;
        th_start[i] = th;
        s_advance (s_kinds[d->word][i], d->r_m, d->len[i], &p, &th);
        end[i] = p;
    }
    const double r = d->r_m, chord = 2 * r * sin (step_deg * DEG / 2) + 1e-6;
    int seg = 0, count[3] = {0, 0, 0};
    double prev_param = 0;
    gd_v2_t prev = d->p0, last[3];
    assert_true (n >= 1);
    for (size_t j = 0; j < n; j++) {
        gd_v2_t q = pts[j];
        bool placed = false;
        while (seg < 3 && !placed) {
            double len = d->len[seg];
            char k = s_kinds[d->word][seg];
            double param = -1;
            if (len > 1e-9) {
                if (k == 'S') {
                    gd_v2_t u = gd_v2 (cos (th_start[seg]), sin (th_start[seg]));
                    gd_v2_t w = gd_sub (q, start[seg]);
                    if (fabs (gd_cross (u, w)) <= 1e-6)
                        param = gd_dot (u, w);
                } else {
                    gd_v2_t c = s_centre (start[seg], th_start[seg], r, k);
                    gd_v2_t a = gd_sub (start[seg], c), b = gd_sub (q, c);
                    if (fabs (gd_norm (b) - r) <= 1e-6) {
                        double ang = atan2 (gd_cross (a, b), gd_dot (a, b)); // anticlockwise
                        param = r * s_wrap2pi (k == 'L' ? ang : -ang);
                        if (param > len + 1e-6 && param > 2 * PI * r - 1e-6)
                            param = 0; // the start, seen a whole turn on
                    }
                }
            }
            bool first = count[seg] == 0;
            if (param > 1e-7 && param <= len + 1e-6 && (first || param > prev_param + 1e-9)) {
                if (k != 'S')
                    assert_true (gd_norm (gd_sub (q, first ? start[seg] : prev)) <= chord);
                prev_param = param;
                count[seg]++;
                last[seg] = q;
                placed = true;
            } else {
                seg++;
            }
        }
        if (!placed)
            fail_msg ("sample %zu (%.9g, %.9g) is not on the path after segment %d", j, q.e, q.n,
                      seg);
        prev = q;
    }
    for (int i = 0; i < 3; i++) {
        if (d->len[i] <= 1e-9)
            continue;
        assert_true (count[i] >= (s_kinds[d->word][i] == 'S' ? 1 : 2));
        assert_v2_near (last[i], end[i], 1e-6);
    }
    assert_v2_near (pts[n - 1], goal, 1e-6);
}

/* From (0, 0) heading north to (2r, 0) heading south: half a right turn
 * round (r, 0), π·r, passing (r, r) heading east halfway. */
static void test_dubins_semicircle (void **state)
{
    (void)state;
    const double r = 300.0;
    gd_dubins_t d;
    assert_int_equal (gd_dubins (gd_v2 (0, 0), 0.0, gd_v2 (2 * r, 0), 180.0, r, &d), 0);
    assert_near (gd_dubins_length (&d), PI * r, 1e-6);
    gd_v2_t p;
    double h;
    gd_dubins_at (&d, PI * r / 2, &p, &h);
    assert_v2_near (p, gd_v2 (r, r), 1e-6);
    assert_true (s_heading_err (h, 90.0) < 1e-6);
    gd_dubins_at (&d, PI * r, &p, &h);
    assert_v2_near (p, gd_v2 (2 * r, 0), 1e-6);
    assert_true (s_heading_err (h, 180.0) < 1e-6);
    gd_v2_t pts[64];
    size_t n = gd_dubins_sample (&d, 10.0, pts, 64);
    assert_true (n >= 18 && n <= 20); // 180° in 10° steps (+1 an arc when the quotient rounds up)
    s_check_samples (&d, 10.0, pts, n, gd_v2 (2 * r, 0));
}

/* The U-turn in place, (0, 0) north to (0, 0) south: the CSC words need a
 * full extra turn (LSL/RSR: 3π/2 + 2r + 3π/2; LSR/RSL: the two circles
 * coincide, no inner tangent), so the shortest is CCC: right circle
 * (r, 0), goal's right circle (−r, 0), middle circle centred (0, √3·r),
 * 2r from both. Turns: 60° right, 300° left, 60° right: 7π·r/3 — the
 * "light bulb" turn. LRL is its mirror, the same length.
 *
 * (0, 0) north to (2r, 0) north: RSR turns 90° right to (r, r) heading east,
 * flies 2r, turns 270° right round (3r, 0): (2π + 2)·r = 8.283·r; LSL the
 * mirror; LSR: 300° + 2√3·r + 300°; RLR/LRL: the middle circle at
 * (2r, ±√3·r): 8π/3·r = 8.378·r at best. So (2π + 2)·r. */
static void test_dubins_u_turns (void **state)
{
    (void)state;
    const double r = 250.0;
    gd_dubins_t d;
    assert_int_equal (gd_dubins (gd_v2 (0, 0), 0.0, gd_v2 (0, 0), 180.0, r, &d), 0);
    assert_near (gd_dubins_length (&d), 7 * PI * r / 3, 1e-6);
    assert_true (d.word == GD_RLR || d.word == GD_LRL);
    assert_near (d.len[0], PI * r / 3, 1e-6);
    assert_near (d.len[1], 5 * PI * r / 3, 1e-6);
    assert_near (d.len[2], PI * r / 3, 1e-6);
    assert_near (s_brute_dubins (gd_v2 (0, 0), 0.0, gd_v2 (0, 0), 180.0, r), 7 * PI * r / 3, 1e-6);
    gd_v2_t p;
    double h;
    gd_dubins_at (&d, gd_dubins_length (&d), &p, &h);
    assert_v2_near (p, gd_v2 (0, 0), 1e-6);
    assert_true (s_heading_err (h, 180.0) < 1e-6);

    assert_int_equal (gd_dubins (gd_v2 (0, 0), 0.0, gd_v2 (2 * r, 0), 0.0, r, &d), 0);
    assert_near (gd_dubins_length (&d), (2 * PI + 2) * r, 1e-6);
    assert_true (d.word == GD_RSR || d.word == GD_LSL);
    assert_near (d.len[1], 2 * r, 1e-6);
    assert_near (s_brute_dubins (gd_v2 (0, 0), 0.0, gd_v2 (2 * r, 0), 0.0, r), (2 * PI + 2) * r,
                 1e-6);
}

/* Goal straight ahead with the same heading: the straight line, for any
 * heading (not just the axes, where the angles come out exact). */
static void test_dubins_straight_ahead (void **state)
{
    (void)state;
    const double headings[] = {0, 30, 45, 90, 137.5, 180, 200, 271, 315, 359};
    for (size_t i = 0; i < sizeof headings / sizeof headings[0]; i++) {
        double h = headings[i];
        gd_v2_t p0 = gd_v2 (100, -200);
        gd_v2_t p1 = gd_add (p0, gd_scale (gd_heading_unit (h), 3000.0));
        gd_dubins_t d;
        assert_int_equal (gd_dubins (p0, h, p1, h, 400.0, &d), 0);
        if (!(fabs (gd_dubins_length (&d) - 3000.0) <= 1e-6))
            fail_msg ("heading %g: length %.9g (word %s, %.9g %.9g %.9g), expected 3000", h,
                      gd_dubins_length (&d), s_kinds[d.word], d.len[0], d.len[1], d.len[2]);
    }
}

/* Start and goal the same pose: the empty path, length 0, and the sampler
 * gives the goal alone. */
static void test_dubins_zero_length (void **state)
{
    (void)state;
    const double headings[] = {0, 30, 45, 90, 137.5, 180, 200, 271, 315};
    for (size_t i = 0; i < sizeof headings / sizeof headings[0]; i++) {
        double h = headings[i];
        gd_dubins_t d;
        assert_int_equal (gd_dubins (gd_v2 (500, 700), h, gd_v2 (500, 700), h, 400.0, &d), 0);
        if (!(gd_dubins_length (&d) <= 1e-6))
            fail_msg ("heading %g: length %.9g (word %s, %.9g %.9g %.9g), expected 0", h,
                      gd_dubins_length (&d), s_kinds[d.word], d.len[0], d.len[1], d.len[2]);
        gd_v2_t pts[4];
        assert_int_equal (gd_dubins_sample (&d, 10.0, pts, 4), 1);
        assert_v2_near (pts[0], gd_v2 (500, 700), 1e-6);
    }
}

/* Random start and goal poses: the path ends at the goal with the goal's
 * heading, is no shorter than the straight distance, and is as short as the
 * shortest candidate of the independent enumeration (neither shorter —
 * the enumeration holds the optimum — nor longer); its samples lie on it. */
static void test_dubins_random (void **state)
{
    (void)state;
    s_rng = 20240601;
    gd_v2_t pts[1024];
    for (int i = 0; i < 1000; i++) {
        double r = s_uniform (50, 800);
        double spread = i % 2 ? 4 * r : 5000; // half of them close: CCC words
        gd_v2_t p0 = gd_v2 (s_uniform (-spread, spread), s_uniform (-spread, spread));
        gd_v2_t p1 = gd_v2 (s_uniform (-spread, spread), s_uniform (-spread, spread));
        double h0 = s_uniform (0, 360), h1 = s_uniform (0, 360);
        gd_dubins_t d;
        assert_int_equal (gd_dubins (p0, h0, p1, h1, r, &d), 0);
        double len = gd_dubins_length (&d);
        gd_v2_t e;
        double he;
        gd_dubins_at (&d, len, &e, &he);
        assert_v2_near (e, p1, 1e-6);
        assert_true (s_heading_err (he, h1) < 1e-6);
        gd_dubins_at (&d, 0, &e, &he);
        assert_v2_near (e, p0, 1e-9);
        assert_true (s_heading_err (he, h0) < 1e-9);
        assert_true (len >= gd_norm (gd_sub (p1, p0)) - 1e-9);
        double best = s_brute_dubins (p0, h0, p1, h1, r);
        if (!(fabs (len - best) <= 1e-6 * (1 + best)))
            fail_msg ("case %d: length %.9g (%s), the shortest candidate %.9g", i, len,
                      s_kinds[d.word], best);
        double step = s_uniform (3, 45);
        size_t n = gd_dubins_sample (&d, step, pts, 1024);
        assert_true (n < 1024);
        s_check_samples (&d, step, pts, n, p1);
    }
}

/* Truncation: with room for max points the sampler writes max, the last
 * being the goal, the ones before it the path's first points; nothing is
 * written past max. */
static void test_dubins_sample_truncation (void **state)
{
    (void)state;
    const double r = 100.0;
    gd_dubins_t d;
    assert_int_equal (gd_dubins (gd_v2 (0, 0), 0.0, gd_v2 (0, 0), 180.0, r, &d), 0);
    gd_v2_t all[128];
    size_t n = gd_dubins_sample (&d, 10.0, all, 128);
    // 60°, 300°, 60° in 10° steps: 6 + 30 + 6 = 42 (one more per arc when the
    // quotient rounds just above a whole number).
    assert_true (n >= 42 && n <= 45);
    s_check_samples (&d, 10.0, all, n, gd_v2 (0, 0));
    const size_t maxes[3] = {1, 3, 10};
    for (int i = 0; i < 3; i++) {
        gd_v2_t out[12];
        for (int j = 0; j < 12; j++)
            out[j] = gd_v2 (-1e9, -1e9);
        assert_int_equal (gd_dubins_sample (&d, 10.0, out, maxes[i]), maxes[i]);
        assert_v2_near (out[maxes[i] - 1], gd_v2 (0, 0), 1e-6);
        for (size_t j = 0; j + 1 < maxes[i]; j++)
            assert_v2_near (out[j], all[j], 1e-12);
        assert_v2_near (out[maxes[i]], gd_v2 (-1e9, -1e9), 0);
    }
    assert_int_equal (gd_dubins_sample (&d, 10.0, all, 0), 0);
}

/* No path without a turn radius or with non-finite input; the result left
 * alone. */
static void test_dubins_rejects_bad_input (void **state)
{
    (void)state;
    gd_dubins_t d, before;
    memset (&d, 0x5a, sizeof d);
    before = d;
    assert_int_equal (gd_dubins (gd_v2 (0, 0), 0, gd_v2 (1000, 0), 90, 0.0, &d), -EINVAL);
    assert_int_equal (gd_dubins (gd_v2 (0, 0), 0, gd_v2 (1000, 0), 90, -100.0, &d), -EINVAL);
    assert_int_equal (gd_dubins (gd_v2 (0, 0), 0, gd_v2 (1000, 0), 90, NAN, &d), -EINVAL);
    assert_int_equal (gd_dubins (gd_v2 (0, 0), 0, gd_v2 (1000, 0), 90, INFINITY, &d), -EINVAL);
    assert_int_equal (gd_dubins (gd_v2 (NAN, 0), 0, gd_v2 (1000, 0), 90, 100, &d), -EINVAL);
    assert_int_equal (gd_dubins (gd_v2 (0, 0), INFINITY, gd_v2 (1000, 0), 90, 100, &d), -EINVAL);
    assert_int_equal (gd_dubins (gd_v2 (0, 0), 0, gd_v2 (1000, 0), 90, 100, NULL), -EINVAL);
    assert_memory_equal (&d, &before, sizeof d);
}

/* ---- the footprint ------------------------------------------------------------------- */

/* The worked example: the sensor 1000 m above flat ground heading north,
 * level, ε = 45°, γ = 10°, β = 7.5°.
 *
 * Camera axes: forward fc = (0, cos ε, −sin ε), right (1, 0, 0), up
 * uc = (0, sin ε, cos ε). A corner ray is fc + sa·tan(γ/2)·right +
 * sb·tan(β/2)·uc (sa = −1 left, +1 right; sb = −1 near, +1 far). Its
 * vertical-plane part: forward cos ε + sb·tan(β/2)·sin ε = cos(ε − sb·β/2) /
 * cos(β/2), down sin ε − sb·tan(β/2)·cos ε = sin(ε − sb·β/2) / cos(β/2): the
 * corner ray is depressed ε − sb·β/2 in the vertical plane through the
 * boresight (41.25° far, 48.75° near). It meets the ground at a north
 * distance h·cot(ε − sb·β/2) and an east offset sa·tan(γ/2)·h·cos(β/2) /
 * sin(ε − sb·β/2):
 *   far:  n = 1000·cot 41.25° = 1140.2815, e = ±1000·tan 5°·cos 3.75°/sin 41.25° = ±132.4060
 *   near: n = 1000·cot 48.75° =  876.9765, e = ±1000·tan 5°·cos 3.75°/sin 48.75° = ±116.1169
 * and the boresight at (0, 1000·cot 45°) = (0, 1000). */
#define FP_H    1000.0
#define FP_EPS  45.0
#define FP_HFOV 10.0
#define FP_VFOV 7.5

/* The corner (sa, sb) of the hand formula for a level sensor at height h
 * with depression eps, on the plane height = slope·north below it (slope 0:
 * flat): the ray d = (sa·tan(γ/2), cos ε + sb·tan(β/2)·sin ε, −sin ε +
 * sb·tan(β/2)·cos ε) from (0, 0, h) meets up = slope·n at s = h/(−d_u +
 * slope·d_n). */
static gd_v2_t s_hand_corner (double h, double eps_deg, double sa, double sb, double slope)
{
    double a = tan (FP_HFOV * DEG / 2), b = tan (FP_VFOV * DEG / 2), e = eps_deg * DEG;
    double de = sa * a, dn = cos (e) + sb * b * sin (e), du = -sin (e) + sb * b * cos (e);
    double s = h / (-du + slope * dn);
    return gd_v2 (s * de, s * dn);
}

/* The four hand corners, in the footprint's order: near-left, far-left,
 * far-right, near-right. */
static void s_hand_corners (double h, double eps_deg, double slope, gd_v2_t ret[4])
{
    const double sa[4] = {-1, -1, 1, 1}, sb[4] = {-1, 1, 1, -1};
    for (int i = 0; i < 4; i++)
        ret[i] = s_hand_corner (h, eps_deg, sa[i], sb[i], slope);
}

static gd_sensor_t s_sensor (void)
{
    gd_sensor_t s = {0};
    s.position.u_m = FP_H;
    s.depression_deg = FP_EPS;
    s.hfov_deg = FP_HFOV;
    s.vfov_deg = FP_VFOV;
    s.max_range_m = 1e5;
    return s;
}

static void test_footprint_flat_level (void **state)
{
    (void)state;
    gd_v2_t c[4];
    s_hand_corners (FP_H, FP_EPS, 0, c);
    // The formula of the comment, in its other form, and its numbers.
    double hb = FP_VFOV / 2 * DEG, hg = FP_HFOV / 2 * DEG, e = FP_EPS * DEG;
    assert_v2_near (c[1], gd_v2 (-FP_H * tan (hg) * cos (hb) / sin (e - hb), FP_H / tan (e - hb)),
                    1e-9);
    assert_v2_near (c[3], gd_v2 (FP_H * tan (hg) * cos (hb) / sin (e + hb), FP_H / tan (e + hb)),
                    1e-9);
    assert_v2_near (c[0], gd_v2 (-116.1169, 876.9765), 1e-4);
    assert_v2_near (c[1], gd_v2 (-132.4060, 1140.2815), 1e-4);
    assert_v2_near (c[2], gd_v2 (132.4060, 1140.2815), 1e-4);
    assert_v2_near (c[3], gd_v2 (116.1169, 876.9765), 1e-4);

    gd_sensor_t s = s_sensor ();
    gd_footprint_t f;
    assert_int_equal (gd_footprint (&s, NULL, &f), 0);
    assert_false (f.clipped);
    assert_v2_near (f.center, gd_v2 (0, 1000), 1e-6);
    assert_near (f.center_up_m, 0.0, 1e-9);
    for (int i = 0; i < 4; i++) {
        assert_v2_near (f.corner[i], c[i], 1e-6);
        assert_near (f.corner_up_m[i], 0.0, 1e-9);
    }
    // Near-left: west of the track and nearer than the far corners; the
    // order is clockwise seen from above (negative signed area).
    assert_true (f.corner[0].e < 0 && f.corner[0].n < f.corner[1].n);
    double area2 = 0;
    for (int i = 0; i < 4; i++)
        area2 += gd_cross (f.corner[i], f.corner[(i + 1) % 4]);
    assert_true (area2 < 0);

    // The same sensor 300 m east and 200 m south: everything moves with it.
    s.position.e_m = 300;
    s.position.n_m = -200;
    assert_int_equal (gd_footprint (&s, NULL, &f), 0);
    assert_v2_near (f.center, gd_v2 (300, 800), 1e-6);
    for (int i = 0; i < 4; i++)
        assert_v2_near (f.corner[i], gd_add (c[i], gd_v2 (300, -200)), 1e-6);
}

/* Heading 90° turns the picture clockwise a quarter: ahead becomes east and
 * right becomes south, (e, n) → (n, −e); heading 180°: (e, n) → (−e, −n).
 * The corners keep their roles (near-left stays first). */
static void test_footprint_heading (void **state)
{
    (void)state;
    gd_v2_t c[4];
    s_hand_corners (FP_H, FP_EPS, 0, c);
    gd_sensor_t s = s_sensor ();
    gd_footprint_t f;
    s.heading_deg = 90;
    assert_int_equal (gd_footprint (&s, NULL, &f), 0);
    assert_v2_near (f.center, gd_v2 (1000, 0), 1e-6);
    for (int i = 0; i < 4; i++)
        assert_v2_near (f.corner[i], gd_v2 (c[i].n, -c[i].e), 1e-6);
    s.heading_deg = 180;
    assert_int_equal (gd_footprint (&s, NULL, &f), 0);
    assert_v2_near (f.center, gd_v2 (0, -1000), 1e-6);
    for (int i = 0; i < 4; i++)
        assert_v2_near (f.corner[i], gd_v2 (-c[i].e, -c[i].n), 1e-6);
}

/* Roll φ (right wing down) turns the body's up towards the right:
 * up = (sin φ, 0, cos φ) heading north, so the boresight cos ε·forward −
 * sin ε·up = (−sin ε·sin φ, cos ε, −sin ε·cos φ) swings left and meets the
 * ground at s = h/(sin ε·cos φ): centre (−h·tan φ, h·cot ε/cos φ); φ = 20°:
 * (−363.9702, 1064.1778).
 * Pitch θ (nose up) tilts the whole camera: the boresight is depressed
 * ε − θ, so nose down 10° adds 10° of depression: centre 1000·cot 55° =
 * 700.2075 north; nose up 10°: 1000·cot 35° = 1428.1480. The corners are
 * those of a level sensor with depression ε − θ. */
static void test_footprint_roll_pitch (void **state)
{
    (void)state;
    gd_sensor_t s = s_sensor ();
    gd_footprint_t f;
    s.roll_deg = 20;
    assert_int_equal (gd_footprint (&s, NULL, &f), 0);
    double phi = 20 * DEG, e = FP_EPS * DEG;
    assert_v2_near (f.center, gd_v2 (-FP_H * tan (phi), FP_H / tan (e) / cos (phi)), 1e-6);
    assert_v2_near (f.center, gd_v2 (-363.9702, 1064.1778), 1e-4);
    s.roll_deg = -20; // left wing down: the mirror
    assert_int_equal (gd_footprint (&s, NULL, &f), 0);
    assert_v2_near (f.center, gd_v2 (363.9702, 1064.1778), 1e-4);

    s.roll_deg = 0;
    const double pitches[2] = {-10, 10}, centres[2] = {700.2075, 1428.1480};
    for (int i = 0; i < 2; i++) {
        s.pitch_deg = pitches[i];
        assert_int_equal (gd_footprint (&s, NULL, &f), 0);
        assert_v2_near (f.center, gd_v2 (0, centres[i]), 1e-4);
        assert_v2_near (f.center, gd_v2 (0, FP_H / tan ((FP_EPS - pitches[i]) * DEG)), 1e-6);
        gd_v2_t c[4];
        s_hand_corners (FP_H, FP_EPS - pitches[i], 0, c);
        for (int k = 0; k < 4; k++)
            assert_v2_near (f.corner[k], c[k], 1e-6);
    }
}

/* A terrain of 121 × 121 nodes 50 m apart, ±3000 m about the origin, with
 * node heights base + slope·north. Bilinear interpolation of a plane is the
 * plane. */
static cgs_terrain_t *s_plane (double base, double slope)
{
    enum { N = 121 };
    static float h[N * N];
    for (int r = 0; r < N; r++)
        for (int c = 0; c < N; c++)
            h[r * N + c] = (float)(base + slope * (-3000.0 + 50.0 * r));
    return cgs_terrain_new_grid (N, N, -3000.0, -3000.0, 50.0, h);
}

/* A level plane at 100 m with the sensor at 1100 m is flat ground 1000 m
 * below: the same corners. A plane rising northward, up = n/10, sensor at
 * 1000 m: the boresight (0, s·cos ε, 1000 − s·sin ε) meets it where
 * 1000 − s·sin ε = s·cos ε/10, so north = 1000/(tan ε + 0.1) = 909.0909 and
 * up = 90.9091; the corners by the same intersection along their rays
 * (s_hand_corner with slope 0.1), nearer than on flat ground. */
static void test_footprint_terrain (void **state)
{
    (void)state;
    cgs_terrain_t *t = s_plane (100.0, 0.0);
    assert_non_null (t);
    gd_sensor_t s = s_sensor ();
    s.position.u_m = 1100.0;
    gd_footprint_t f;
    assert_int_equal (gd_footprint (&s, t, &f), 0);
    assert_false (f.clipped);
    gd_v2_t c[4];
    s_hand_corners (FP_H, FP_EPS, 0, c);
    assert_v2_near (f.center, gd_v2 (0, 1000), 1e-6);
    assert_near (f.center_up_m, 100.0, 1e-6);
    for (int i = 0; i < 4; i++) {
        assert_v2_near (f.corner[i], c[i], 1e-6);
        assert_near (f.corner_up_m[i], 100.0, 1e-6);
    }
    cgs_terrain_destroy (&t);
    assert_null (t);

    t = s_plane (0.0, 0.1);
    assert_non_null (t);
    s.position.u_m = 1000.0;
    assert_int_equal (gd_footprint (&s, t, &f), 0);
    assert_false (f.clipped);
    assert_v2_near (f.center, gd_v2 (0, 1000.0 / 1.1), 1e-6);
    assert_near (f.center.n, 909.0909, 1e-4);
    assert_near (f.center_up_m, 100.0 / 1.1, 1e-6);
    s_hand_corners (FP_H, FP_EPS, 0.1, c);
    for (int i = 0; i < 4; i++) {
        assert_v2_near (f.corner[i], c[i], 1e-6);
        assert_near (f.corner_up_m[i], c[i].n / 10, 1e-6);
    }
    cgs_terrain_destroy (&t);
}

/* ε = 5°, β = 20°: the far rays point 5° above the horizon (−sin 5° +
 * tan 10°·cos 5° = 0.0885 > 0) and meet no flat ground: cut at max range
 * (5000 m) along their ground track (±tan 5°, cos 5° + tan 10°·sin 5°),
 * clipped. The boresight (5° down) meets the ground 1000/sin 5° = 11474 m
 * away, beyond 5000: cut at (0, 5000). The near rays, 15° down in the
 * vertical plane, still land: north 1000·cot 15° = 3732.0508, east
 * ±1000·tan 5°·cos 10°/sin 15° = ±332.9. */
static void test_footprint_clipped (void **state)
{
    (void)state;
    gd_sensor_t s = s_sensor ();
    s.depression_deg = 5;
    s.vfov_deg = 20;
    s.max_range_m = 5000;
    gd_footprint_t f;
    assert_int_equal (gd_footprint (&s, NULL, &f), 0);
    assert_true (f.clipped);
    double a = tan (5 * DEG), b = tan (10 * DEG);
    gd_v2_t track = gd_v2 (a, cos (5 * DEG) + b * sin (5 * DEG));
    track = gd_scale (track, 1 / gd_norm (track));
    assert_v2_near (f.corner[1], gd_v2 (-5000 * track.e, 5000 * track.n), 1e-6);
    assert_v2_near (f.corner[2], gd_v2 (5000 * track.e, 5000 * track.n), 1e-6);
    assert_v2_near (f.center, gd_v2 (0, 5000), 1e-6);
    double near_n = 1000 / tan (15 * DEG), near_e = 1000 * a * cos (10 * DEG) / sin (15 * DEG);
    assert_near (near_n, 3732.0508, 1e-4);
    assert_near (near_e, 332.9, 0.05);
    assert_v2_near (f.corner[0], gd_v2 (-near_e, near_n), 1e-6);
    assert_v2_near (f.corner[3], gd_v2 (near_e, near_n), 1e-6);

    // Bad sensors are refused.
    gd_footprint_t before = f;
    s = s_sensor ();
    s.hfov_deg = 0;
    assert_int_equal (gd_footprint (&s, NULL, &f), -EINVAL);
    s = s_sensor ();
    s.max_range_m = 0;
    assert_int_equal (gd_footprint (&s, NULL, &f), -EINVAL);
    s = s_sensor ();
    s.position.u_m = NAN;
    assert_int_equal (gd_footprint (&s, NULL, &f), -EINVAL);
    assert_int_equal (gd_footprint (NULL, NULL, &f), -EINVAL);
    assert_memory_equal (&f, &before, sizeof f);
}

/* The hand trapezoid of test_footprint_flat_level (built from the formula,
 * not from gd_footprint). Its edges, clockwise: left NL→FL, far FL→FR
 * (n = 1140.2815), right FR→NR, near NR→NL (n = 876.9765); the outward
 * normal of an edge a→b of a clockwise polygon is its left normal
 * (−(b−a)_n, (b−a)_e)/|b − a|. A point 10 µm out from an edge's midpoint
 * is outside, 10 µm in is inside; 30 m out its distance is 30 (the foot of the
 * perpendicular is the midpoint, and the other edges are over 100 m away).
 * Beyond the far edge at (0, far + 50): 50. Beyond the far-right corner by
 * (30, 40), between the far edge's normal (0, 1) and the right edge's (about
 * east): the distance is to the corner, 50. Scaled by 5 about (0, 1000),
 * each corner's offset from the centre is five times as long. */
static void test_footprint_contains_distance_scale (void **state)
{
    (void)state;
    gd_footprint_t f = {0};
    s_hand_corners (FP_H, FP_EPS, 0, f.corner);
    f.center = gd_v2 (0, 1000);
    assert_true (cgs_footprint_contains (&f, f.center));
    assert_near (cgs_footprint_distance (&f, f.center), 0.0, 0);
    for (int i = 0; i < 4; i++) {
        gd_v2_t a = f.corner[i], b = f.corner[(i + 1) % 4], ab = gd_sub (b, a);
        gd_v2_t out = gd_scale (gd_v2 (-ab.n, ab.e), 1 / gd_norm (ab));
        gd_v2_t mid = gd_scale (gd_add (a, b), 0.5);
        assert_true (cgs_footprint_contains (&f, mid)); // on the edge counts
        assert_true (cgs_footprint_contains (&f, a));
        assert_true (cgs_footprint_contains (&f, gd_add (mid, gd_scale (out, -1e-5))));
        assert_false (cgs_footprint_contains (&f, gd_add (mid, gd_scale (out, 1e-5))));
        assert_near (cgs_footprint_distance (&f, gd_add (mid, gd_scale (out, 30))), 30.0, 1e-9);
        assert_near (cgs_footprint_distance (&f, gd_add (mid, gd_scale (out, -5))), 0.0, 0);
        // Signed: outside as above, inside minus the distance to the nearest edge
        // (5 m in from the middle of an edge at least 60 m from the others).
        assert_near (cgs_footprint_signed_distance (&f, gd_add (mid, gd_scale (out, 30))), 30.0,
                     1e-9);
        assert_near (cgs_footprint_signed_distance (&f, gd_add (mid, gd_scale (out, -5))), -5.0,
                     1e-9);
    }
    // The centre, inside, is minus its distance to the nearest edge line
    // (the feet of its perpendiculars all lie on the edges): 123.02 m to the
    // near edge, 140.28 m to the far one, and to each side.
    double dmin = INFINITY;
    for (int i = 0; i < 4; i++) {
        gd_v2_t a = f.corner[i], ab = gd_sub (f.corner[(i + 1) % 4], a), ap = gd_sub (f.center, a);
        dmin = fmin (dmin, fabs (ab.e * ap.n - ab.n * ap.e) / gd_norm (ab));
    }
    assert_true (dmin <= 1000 - 876.9765 + 1e-3);
    assert_near (cgs_footprint_signed_distance (&f, f.center), -dmin, 1e-9);
    // The outward normals are what the comment says: near edge south, far north.
    double far_n = 1140.2815, near_n = 876.9765;
    assert_false (cgs_footprint_contains (&f, gd_v2 (0, far_n + 0.01)));
    assert_false (cgs_footprint_contains (&f, gd_v2 (0, near_n - 0.01)));
    assert_true (cgs_footprint_contains (&f, gd_v2 (0, far_n - 0.01)));
    assert_near (cgs_footprint_distance (&f, gd_v2 (0, f.corner[1].n + 50)), 50.0, 1e-9);
    assert_near (cgs_footprint_distance (&f, gd_v2 (0, f.corner[0].n - 20)), 20.0, 1e-9);
    assert_near (cgs_footprint_distance (&f, gd_add (f.corner[2], gd_v2 (30, 40))), 50.0, 1e-9);
    // West of the track at the centre's northing: beyond the left edge.
    assert_false (cgs_footprint_contains (&f, gd_v2 (-140, 1000)));
    assert_true (cgs_footprint_contains (&f, gd_v2 (-110, 1000)));

    gd_footprint_t g;
    cgs_footprint_scale (&f, 5.0, &g);
    assert_v2_near (g.center, f.center, 0);
    for (int i = 0; i < 4; i++)
        assert_v2_near (gd_sub (g.corner[i], g.center),
                        gd_scale (gd_sub (f.corner[i], f.center), 5.0), 1e-9);
    // Far corner: 1000 + 5·140.2815 = 1701.4073 north, 5·132.4060 = 662.03 east.
    assert_v2_near (g.corner[2], gd_v2 (662.0300, 1701.4073), 1e-3);
    assert_true (cgs_footprint_contains (&g, gd_v2 (0, far_n + 50)));
    assert_false (cgs_footprint_contains (&f, gd_v2 (0, far_n + 50)));
    // 50 m beyond the scaled far edge: 50.
    assert_near (cgs_footprint_distance (&g, gd_v2 (0, g.corner[1].n + 50)), 50.0, 1e-9);
}

int main (void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test (test_vector_helpers),
        cmocka_unit_test (test_arc_length_straight_and_quarter),
        cmocka_unit_test (test_arc_length_on_turn_circle),
        cmocka_unit_test (test_arc_length_abeam_behind_inside),
        cmocka_unit_test (test_arc_length_symmetry),
        cmocka_unit_test (test_waypoint_target_receding),
        cmocka_unit_test (test_waypoint_target_head_on),
        cmocka_unit_test (test_waypoint_crossing_target),
        cmocka_unit_test (test_waypoint_general_direction),
        cmocka_unit_test (test_equation3_paper),
        cmocka_unit_test (test_horizon),
        cmocka_unit_test (test_waypoint_target_standing),
        cmocka_unit_test (test_waypoint_rejects_bad_input),
        cmocka_unit_test (test_waypoint_min_t_pred),
        cmocka_unit_test (test_flyable_straight),
        cmocka_unit_test (test_flyable_behind),
        cmocka_unit_test (test_settle),
        cmocka_unit_test (test_flyable_rejects_bad_input),
        cmocka_unit_test (test_target_frame),
        cmocka_unit_test (test_precision_step),
        cmocka_unit_test (test_dubins_semicircle),
        cmocka_unit_test (test_dubins_u_turns),
        cmocka_unit_test (test_dubins_straight_ahead),
        cmocka_unit_test (test_dubins_zero_length),
        cmocka_unit_test (test_dubins_random),
        cmocka_unit_test (test_dubins_sample_truncation),
        cmocka_unit_test (test_dubins_rejects_bad_input),
        cmocka_unit_test (test_footprint_flat_level),
        cmocka_unit_test (test_footprint_heading),
        cmocka_unit_test (test_footprint_roll_pitch),
        cmocka_unit_test (test_footprint_terrain),
        cmocka_unit_test (test_footprint_clipped),
        cmocka_unit_test (test_footprint_contains_distance_scale),
        cmocka_unit_test (test_flyable_no_fixed_point),
        cmocka_unit_test (test_flyable_null_result), // last: a failure aborts the program
    };
    return cmocka_run_group_tests (tests, NULL, NULL);
}
