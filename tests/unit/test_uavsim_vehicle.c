/* test_uavsim_vehicle — the ground-vehicle model against what its speeds and
 * limits imply: arrival times at route points from leg lengths, leg speeds and
 * the documented corner and acceleration allowances; turn rate and lateral
 * acceleration per step; corner arcs that pass the documented distance from
 * the corner; heights and attitude on a sloping plane; start time; stop, loop
 * and reverse; halts on route points (timed from the same allowances, on
 * every lap and pass); seeded wander within its bound; exact checkpoint and
 * restore, in a halt; checkpoints of the formats before cgs_ckpt refused. */
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

#include "cgs_ckpt.h"
#include "cgs_terrain.h"
#include "cgs_util.h"
#include "uavsim_vehicle.h"
#include "test_util.h"

#define DEG       (M_PI / 180.0)
#define DT_S      0.1  // simulation step, s
#define LAT_MPS2  2.0  // default lateral acceleration limit
#define OMEGA_DPS 30.0 // default turn rate limit
#define ACC_MPS2  1.5  // default acceleration
#define DEC_MPS2  2.0  // default deceleration
#define CUT_M     10.0 // default corner cut
// A vehicle checkpoint (uavsim_vehicle.c): its bytes, and where fields are.
#define CK_BYTES   (CGS_CKPT_HEAD + 172 + CGS_CKPT_TAIL)
#define CK_PHASE   (CGS_CKPT_HEAD + 8)
#define CK_ELEMENT (CGS_CKPT_HEAD + 16)
#define CK_SPEED   (CGS_CKPT_HEAD + 36)
#define CK_HALT    (CGS_CKPT_HEAD + 164)

/* The test route: east 1000 m at 10 m/s, a right angle (left) onto north 800 m
 * at 8 m/s, a 150-degree turn (left) onto 600 m at 6 m/s heading 210. */
static const uavsim_vehicle_point_t s_route[] = {
    {0, 0, 10},
    {1000, 0, 8},
    {1000, 800, 6},
    {1000 - 300, 800 - 519.6152422706632, 0},
};
#define S_ROUTE_N 4

static void s_params (uavsim_vehicle_params_t *p, const uavsim_vehicle_point_t *pts, size_t n)
{
    uavsim_vehicle_params_defaults (p);
    p->points = pts;
    p->n_points = n;
}

static uavsim_vehicle_t *s_new (const uavsim_vehicle_params_t *p)
{
    uavsim_vehicle_t *v = NULL;
    assert_int_equal (uavsim_vehicle_new (p, &v), 0);
    assert_non_null (v);
    return v;
}

static uavsim_vehicle_state_t s_state (const uavsim_vehicle_t *v)
{
    uavsim_vehicle_state_t s;
    uavsim_vehicle_state (v, &s);
    return s;
}

/* Heading change in degrees, wrapped to [-180, 180]. */
static double s_dheading (double a, double b)
{
    return remainder (b - a, 360.0);
}

/* Bit-for-bit equality of two states. */
static bool s_same (const uavsim_vehicle_state_t *a, const uavsim_vehicle_state_t *b)
{
    const double da[] = {a->e_m,         a->n_m,       a->ve_mps, a->vn_mps,
                         a->heading_deg, a->speed_mps, a->dev_m};
    const double db[] = {b->e_m,         b->n_m,       b->ve_mps, b->vn_mps,
                         b->heading_deg, b->speed_mps, b->dev_m};
    return memcmp (da, db, sizeof da) == 0 && a->active == b->active &&
           a->finished == b->finished && a->turning_in_place == b->turning_in_place &&
           a->leg == b->leg && a->next_point == b->next_point && a->direction == b->direction &&
           a->lap == b->lap && a->halted == b->halted &&
           memcmp (&a->halt_left_s, &b->halt_left_s, sizeof a->halt_left_s) == 0;
}

/* The documented corner: radius, speed, tangent length and half-arc length. */
typedef struct {
    double r_m, vc_mps, t_m, half_m;
} s_corner_t;

static s_corner_t s_corner_expected (double theta_rad, double vin, double vout, double lin,
                                     double lout)
{
    double v = fmin (vin, vout), w = OMEGA_DPS * DEG;
    double r = fmax (v * v / LAT_MPS2, v / w);
    r = fmin (r, CUT_M / (1 / cos (theta_rad / 2) - 1));
    r = fmin (r, 0.5 * fmin (lin, lout) / tan (theta_rad / 2));
    s_corner_t c = {r, fmin (v, fmin (sqrt (LAT_MPS2 * r), w * r)), r * tan (theta_rad / 2),
                    r * theta_rad / 2};
    return c;
}

/* Distance from (e, n) to segment a-b. */
static double s_seg_dist (double e, double n, double ae, double an, double be, double bn)
{
    double de = be - ae, dn = bn - an, l2 = de * de + dn * dn;
    double u = ((e - ae) * de + (n - an) * dn) / l2;
    u = u < 0 ? 0 : u > 1 ? 1 : u;
    return hypot (e - (ae + u * de), n - (an + u * dn));
}

static double s_route_dist (const uavsim_vehicle_point_t *pts, size_t n, double e, double nn)
{
    double best = INFINITY;
    for (size_t i = 0; i + 1 < n; i++)
        best =
            fmin (best, s_seg_dist (e, nn, pts[i].e_m, pts[i].n_m, pts[i + 1].e_m, pts[i + 1].n_m));
    return best;
}

/* --- parameters -------------------------------------------------------------------------- */

static void test_bad_params (void **state)
{
    (void)state;
    uavsim_vehicle_params_t p;
    uavsim_vehicle_t *v = (uavsim_vehicle_t *)&p; // must stay untouched
    uavsim_vehicle_t *const untouched = v;
    char err[128];

    s_params (&p, s_route, 1);
    assert_int_equal (uavsim_vehicle_new (&p, &v), -EINVAL);
    assert_int_equal (uavsim_vehicle_params_check (&p, err, sizeof err), -EINVAL);
    assert_non_null (strstr (err, "2 points"));
    assert_int_equal (uavsim_vehicle_new (NULL, &v), -EINVAL);
    s_params (&p, NULL, 4);
    assert_int_equal (uavsim_vehicle_new (&p, &v), -EINVAL);

    uavsim_vehicle_point_t pts[S_ROUTE_N];
    const struct {
        int point;    // which point to spoil, or -1
        int field;    // 0 east, 1 north, 2 speed
        double value; // the bad value
    } bad_points[] = {
        {1, 0, NAN}, {2, 1, INFINITY}, {1, 2, -1},
        {0, 2, NAN}, {3, 0, 1e9},      {1, 0, 0}, // repeats point 0 (with north 0)
    };
    for (size_t i = 0; i < sizeof bad_points / sizeof bad_points[0]; i++) {
        memcpy (pts, s_route, sizeof pts);
        double *f = bad_points[i].field == 0   ? &pts[bad_points[i].point].e_m
                    : bad_points[i].field == 1 ? &pts[bad_points[i].point].n_m
                                               : &pts[bad_points[i].point].speed_mps;
        *f = bad_points[i].value;
        s_params (&p, pts, S_ROUTE_N);
        assert_int_equal (uavsim_vehicle_new (&p, &v), -EINVAL);
        assert_int_equal (uavsim_vehicle_params_check (&p, err, sizeof err), -EINVAL);
        assert_non_null (strstr (err, "point"));
    }
    // Scalars.
    struct {
        double *field;
        double value;
    } bad[] = {
        {&p.speed_mps, 0},      {&p.speed_mps, -5},      {&p.speed_mps, NAN},
        {&p.start_time_s, NAN}, {&p.deviation_m, -1},    {&p.deviation_m, INFINITY},
        {&p.lat_accel_mps2, 0}, {&p.turn_rate_dps, -30}, {&p.turn_rate_dps, NAN},
        {&p.accel_mps2, 0},     {&p.decel_mps2, -1},     {&p.corner_cut_m, 0},
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        s_params (&p, s_route, S_ROUTE_N);
        *bad[i].field = bad[i].value;
        assert_int_equal (uavsim_vehicle_new (&p, &v), -EINVAL);
    }
    s_params (&p, s_route, S_ROUTE_N);
    p.end = (uavsim_vehicle_end_t)7;
    assert_int_equal (uavsim_vehicle_new (&p, &v), -EINVAL);
    // A loop of two copies of one point.
    const uavsim_vehicle_point_t same[] = {{5, 5, 0}, {5, 5.001, 0}};
    s_params (&p, same, 2);
    p.end = UAVSIM_VEHICLE_END_LOOP;
    assert_int_equal (uavsim_vehicle_new (&p, &v), -EINVAL);
    assert_true (v == untouched);

    // A good vehicle refuses bad steps; destroy accepts NULL and nulls.
    s_params (&p, s_route, S_ROUTE_N);
    assert_int_equal (uavsim_vehicle_params_check (&p, err, sizeof err), 0);
    v = s_new (&p);
    assert_int_equal (uavsim_vehicle_step (v, 0, 0), -EINVAL);
    assert_int_equal (uavsim_vehicle_step (v, 0, -0.1), -EINVAL);
    assert_int_equal (uavsim_vehicle_step (v, NAN, 0.1), -EINVAL);
    assert_int_equal (uavsim_vehicle_step (v, 0, INFINITY), -EINVAL);
    uavsim_vehicle_destroy (&v);
    assert_null (v);
    uavsim_vehicle_destroy (&v);
    uavsim_vehicle_destroy (NULL);
}

/* --- timing, speeds, turns ----------------------------------------------------------------- */

/* Drive the test route (deviation dev_m) to the end; check the turn rate and
 * lateral acceleration on every step; return the arrival times at points 1, 2
 * (leg changes) and 3 (finished), the closest approach to points 1 and 2, and
 * the highest speed on each leg. */
typedef struct {
    double arrive_s[4];
    double closest_m[4];
    double vmax_mps[3];
    double max_rate_dps;  // largest heading change per step / dt
    double max_lat_mps2;  // largest heading rate x mean speed
    int turning_steps[3]; // steps with heading change near points 1 and 2
} s_drive_t;

static s_drive_t s_drive_route (double dev_m, uint64_t seed)
{
    uavsim_vehicle_params_t p;
    s_params (&p, s_route, S_ROUTE_N);
    p.deviation_m = dev_m;
    p.seed = seed;
    uavsim_vehicle_t *v = s_new (&p);
    s_drive_t r;
    memset (&r, 0, sizeof r);
    for (int i = 0; i < 4; i++)
        r.closest_m[i] = INFINITY;
    uavsim_vehicle_state_t prev = s_state (v);
    int steps = 0;
    for (; steps < 20000; steps++) {
        double t = steps * DT_S;
        assert_int_equal (uavsim_vehicle_step (v, t, DT_S), 0);
        uavsim_vehicle_state_t s = s_state (v);
        if (s.leg != prev.leg)
            r.arrive_s[s.leg] = t + DT_S;
        if (s.leg < 3)
            r.vmax_mps[s.leg] = fmax (r.vmax_mps[s.leg], s.speed_mps);
        for (int i = 1; i <= 2; i++)
            r.closest_m[i] =
                fmin (r.closest_m[i], hypot (s.e_m - s_route[i].e_m, s.n_m - s_route[i].n_m));
        double dh = fabs (s_dheading (prev.heading_deg, s.heading_deg));
        r.max_rate_dps = fmax (r.max_rate_dps, dh / DT_S);
        r.max_lat_mps2 =
            fmax (r.max_lat_mps2, dh * DEG / DT_S * 0.5 * (s.speed_mps + prev.speed_mps));
        if (dh > 0.5 && s.leg >= 0) {
            int near = hypot (s.e_m - s_route[1].e_m, s.n_m - s_route[1].n_m) < 100 ? 1 : 2;
            r.turning_steps[near]++;
        }
        // Speeds never above the leg's (leg −1: not yet on the route).
        assert_true (s.leg < 0 || s.leg == 3 || s.speed_mps <= s_route[s.leg].speed_mps + 1e-9);
        prev = s;
        if (s.finished) {
            r.arrive_s[3] = t + DT_S;
            break;
        }
    }
    assert_true (prev.finished);
    uavsim_vehicle_destroy (&v);
    return r;
}

static void test_arrival_times (void **state)
{
    (void)state;
    const double v0 = 10, v1 = 8, v2 = 6, l0 = 1000, l1 = 800, l2 = 600;
    s_corner_t c1 = s_corner_expected (90 * DEG, v0, v1, l0, l1);
    s_corner_t c2 = s_corner_expected (150 * DEG, v1, v2, l1, l2);
    // Times from the documented allowances (see uavsim_vehicle.h).
    double t1 = v0 / (2 * ACC_MPS2) + (l0 - c1.t_m) / v0 +
                (v0 - c1.vc_mps) * (v0 - c1.vc_mps) / (2 * DEC_MPS2 * v0) + c1.half_m / c1.vc_mps;
    double t2 = t1 + c1.half_m / c1.vc_mps +
                (v1 - c1.vc_mps) * (v1 - c1.vc_mps) / (2 * ACC_MPS2 * v1) +
                (l1 - c1.t_m - c2.t_m) / v1 +
                (v1 - c2.vc_mps) * (v1 - c2.vc_mps) / (2 * DEC_MPS2 * v1) + c2.half_m / c2.vc_mps;
    double t3 = t2 + c2.half_m / c2.vc_mps +
                (v2 - c2.vc_mps) * (v2 - c2.vc_mps) / (2 * ACC_MPS2 * v2) + (l2 - c2.t_m) / v2 +
                v2 / (2 * DEC_MPS2);
    s_drive_t r = s_drive_route (0, 1);
    const double want[4] = {0, t1, t2, t3};
    const double bare[4] = {0, l0 / v0, l0 / v0 + l1 / v1, l0 / v0 + l1 / v1 + l2 / v2};
    for (int i = 1; i <= 3; i++) {
        print_message ("point %d: arrived in step ending %.1f s, expected %.3f s (bare sum of "
                       "leg/speed %.1f s), step end - expected %+.3f s\n",
                       i, r.arrive_s[i], want[i], bare[i], r.arrive_s[i] - want[i]);
        // The arrival lies within the step that reports it (to 20 ms).
        assert_true (r.arrive_s[i] - want[i] >= -0.02);
        assert_true (r.arrive_s[i] - want[i] <= DT_S + 0.02);
        // And the allowances are small: within 5% of the bare leg-length / leg-speed sum.
        assert_true (fabs (r.arrive_s[i] - bare[i]) <= 0.05 * bare[i]);
    }
    // Per-point speeds honoured: each leg reaches its own speed and no more.
    const double legv[3] = {v0, v1, v2};
    for (int k = 0; k < 3; k++) {
        print_message ("leg %d: top speed %.9f m/s, leg speed %.1f m/s\n", k, r.vmax_mps[k],
                       legv[k]);
        assert_near (r.vmax_mps[k], legv[k], 1e-9);
    }
    // The model's corners are the documented ones.
    uavsim_vehicle_params_t p;
    s_params (&p, s_route, S_ROUTE_N);
    uavsim_vehicle_t *v = s_new (&p);
    double rad, vc;
    uavsim_vehicle_corner (v, 1, &rad, &vc);
    assert_near (rad, c1.r_m, 1e-9);
    assert_near (vc, c1.vc_mps, 1e-9);
    uavsim_vehicle_corner (v, 2, &rad, &vc);
    assert_near (rad, c2.r_m, 1e-9);
    assert_near (vc, c2.vc_mps, 1e-9);
    print_message ("corner 1 (90 deg): R %.2f m, %.2f m/s; corner 2 (150 deg): R %.2f m, "
                   "%.2f m/s\n",
                   c1.r_m, c1.vc_mps, c2.r_m, c2.vc_mps);
    uavsim_vehicle_destroy (&v);

    // Wandering lengthens the drive a little, by well under 2%.
    s_drive_t w = s_drive_route (15, 42);
    print_message ("with 15 m wander: arrival at the end %.1f s vs %.1f s on the line\n",
                   w.arrive_s[3], r.arrive_s[3]);
    assert_true (w.arrive_s[3] >= r.arrive_s[3] - 1e-9);
    assert_true (w.arrive_s[3] <= 1.02 * r.arrive_s[3]);
}

static void test_turn_rate_and_corners (void **state)
{
    (void)state;
    s_corner_t c1 = s_corner_expected (90 * DEG, 10, 8, 1000, 800);
    s_corner_t c2 = s_corner_expected (150 * DEG, 8, 6, 800, 600);
    const double devs[] = {0, 15, 40};
    for (size_t d = 0; d < sizeof devs / sizeof devs[0]; d++) {
        s_drive_t r = s_drive_route (devs[d], 7 + d);
        print_message ("deviation %2.0f m: max turn rate %.6f deg/s (limit %.0f), max lateral "
                       "accel %.6f m/s^2 (limit %.0f); closest to corners %.4f m, %.4f m; turning "
                       "steps %d, %d\n",
                       devs[d], r.max_rate_dps, OMEGA_DPS, r.max_lat_mps2, LAT_MPS2, r.closest_m[1],
                       r.closest_m[2], r.turning_steps[1], r.turning_steps[2]);
        assert_true (r.max_rate_dps <= OMEGA_DPS * (1 + 1e-9));
        assert_true (r.max_lat_mps2 <= LAT_MPS2 * (1 + 1e-6));
        // Rounded corners: the arc passes the documented distance from the corner
        // (R (1/cos(theta/2) - 1) = the corner cut, 10 m here), not through it.
        assert_true (r.closest_m[1] >= CUT_M - 1e-6 && r.closest_m[1] <= CUT_M + 0.02);
        assert_true (r.closest_m[2] >= CUT_M - 1e-6 && r.closest_m[2] <= CUT_M + 0.02);
        // The turn is spread over the arc's duration, not one step.
        assert_true (r.turning_steps[1] >= (int)(0.9 * 2 * c1.half_m / c1.vc_mps / DT_S));
        assert_true (r.turning_steps[2] >= (int)(0.9 * 2 * c2.half_m / c2.vc_mps / DT_S));
    }
    // The sharp corner is taken at the turn-rate limit: the heading rate there is the limit.
    s_drive_t r = s_drive_route (0, 1);
    assert_near (r.max_rate_dps, OMEGA_DPS, 1e-6);
}

/* --- terrain ------------------------------------------------------------------------------ */

static void test_heights_follow_terrain (void **state)
{
    (void)state;
    // A plane h = 50 + 0.03 e - 0.02 n on a 41 x 41 grid at 50 m from (-500, -500).
    const double a = 50, b = 0.03, c = -0.02;
    float h[41 * 41];
    for (int r = 0; r < 41; r++)
        for (int col = 0; col < 41; col++)
            h[r * 41 + col] = (float)(a + b * (-500 + 50 * col) + c * (-500 + 50 * r));
    cgs_terrain_t *t = cgs_terrain_new_grid (41, 41, -500, -500, 50, h);
    assert_non_null (t);
    uavsim_vehicle_params_t p;
    s_params (&p, s_route, S_ROUTE_N);
    p.deviation_m = 20;
    p.seed = 3;
    uavsim_vehicle_t *v = s_new (&p);
    double worst_up = 0, worst_vu = 0, worst_pitch = 0, worst_roll = 0;
    int n = 0;
    for (int i = 0; i < 4000; i++, n++) {
        assert_int_equal (uavsim_vehicle_step (v, i * DT_S, DT_S), 0);
        uavsim_vehicle_state_t s = s_state (v);
        uavsim_vehicle_ground_t g;
        uavsim_vehicle_ground (t, &s, &g);
        double want = a + b * s.e_m + c * s.n_m;
        worst_up = fmax (worst_up, fabs (g.up_m - want));
        worst_vu = fmax (worst_vu, fabs (g.vu_mps - (b * s.ve_mps + c * s.vn_mps)));
        // Pitch: the slope along the heading. Roll (yaw-pitch-roll Euler angles):
        // the body's right axis y = forward x normal has up component
        // -sin(roll) cos(pitch).
        double psi = s.heading_deg * DEG, slope = b * sin (psi) + c * cos (psi);
        double fl = sqrt (1 + slope * slope), pitch = atan (slope);
        double fe = sin (psi) / fl, fn = cos (psi) / fl;
        double nl = sqrt (b * b + c * c + 1), ne = -b / nl, nn = -c / nl;
        double yu = fe * nn - fn * ne;
        worst_pitch = fmax (worst_pitch, fabs (g.pitch_deg - pitch / DEG));
        worst_roll = fmax (worst_roll, fabs (g.roll_deg - asin (-yu / cos (pitch)) / DEG));
        if (s.finished)
            break;
    }
    print_message ("%d steps on a plane: up %.2e m, up velocity %.2e m/s, pitch %.2e deg, roll "
                   "%.2e deg from the plane's\n",
                   n, worst_up, worst_vu, worst_pitch, worst_roll);
    assert_true (worst_up <= 1e-3);
    assert_true (worst_vu <= 1e-5);
    assert_true (worst_pitch <= 1e-3);
    assert_true (worst_roll <= 1e-3);
    // A hand-worked case: heading north on ground rising 0.03 to the east rolls
    // left (right side up) by atan(0.03); pitch atan(-0.02) (downhill).
    uavsim_vehicle_state_t s = {.e_m = 100, .n_m = 100, .heading_deg = 0, .vn_mps = 5};
    uavsim_vehicle_ground_t g;
    uavsim_vehicle_ground (t, &s, &g);
    assert_near (g.up_m, 51, 1e-4);
    assert_near (g.roll_deg, -atan (0.03 / sqrt (1 + 0.02 * 0.02)) / DEG, 1e-4);
    assert_near (g.pitch_deg, atan (-0.02) / DEG, 1e-4);
    assert_near (g.vu_mps, -0.1, 1e-6);
    uavsim_vehicle_destroy (&v);
    cgs_terrain_destroy (&t);
}

/* --- start time, end behaviours ---------------------------------------------------------- */

static void test_start_time (void **state)
{
    (void)state;
    uavsim_vehicle_params_t p;
    s_params (&p, s_route, S_ROUTE_N);
    p.start_time_s = 30.03;
    uavsim_vehicle_t *v = s_new (&p);
    uavsim_vehicle_state_t s = s_state (v);
    assert_false (s.active);
    int i = 0;
    for (; (i + 1) * DT_S <= 30.0 + 1e-9; i++) {
        assert_int_equal (uavsim_vehicle_step (v, i * DT_S, DT_S), 0);
        s = s_state (v);
        assert_false (s.active);
        assert_true (s.e_m == 0 && s.n_m == 0 && s.speed_mps == 0);
        assert_near (s.heading_deg, 90, 1e-12);
        assert_int_equal (s.leg, 0);
    }
    // Step 300 covers 30.0 - 30.1: active for 0.07 s of it.
    assert_int_equal (uavsim_vehicle_step (v, i * DT_S, DT_S), 0);
    s = s_state (v);
    assert_true (s.active);
    assert_near (s.speed_mps, ACC_MPS2 * 0.07, 1e-9);
    assert_near (s.e_m, 0.5 * ACC_MPS2 * 0.07 * 0.07, 1e-9);
    // 10.07 s after the start: 10/1.5 s accelerating (33.33 m), then 10 m/s.
    for (i++; i < 401; i++)
        assert_int_equal (uavsim_vehicle_step (v, i * DT_S, DT_S), 0);
    s = s_state (v);
    double ta = 10 / ACC_MPS2, want = 0.5 * 10 * ta + 10 * (40.1 - 30.03 - ta);
    print_message ("at 40.1 s: %.9f m east (expected %.9f), %.3f m/s\n", s.e_m, want, s.speed_mps);
    assert_near (s.e_m, want, 1e-6);
    assert_near (s.n_m, 0, 1e-12);
    assert_near (s.speed_mps, 10, 1e-12);
    uavsim_vehicle_destroy (&v);
}

static void test_end_stop (void **state)
{
    (void)state;
    uavsim_vehicle_params_t p;
    s_params (&p, s_route, S_ROUTE_N);
    uavsim_vehicle_t *v = s_new (&p);
    int i = 0;
    uavsim_vehicle_state_t s;
    for (;; i++) {
        assert_int_equal (uavsim_vehicle_step (v, i * DT_S, DT_S), 0);
        s = s_state (v);
        if (s.finished)
            break;
        assert_true (i < 10000);
    }
    // On the last point exactly, stopped, and it stays there.
    for (int j = 0; j < 200; j++, i++) {
        assert_true (s.e_m == s_route[3].e_m && s.n_m == s_route[3].n_m);
        assert_true (s.speed_mps == 0 && s.ve_mps == 0 && s.vn_mps == 0);
        assert_true (s.finished && s.active);
        assert_int_equal (s.leg, 2);
        assert_int_equal (s.next_point, 3);
        assert_near (s.heading_deg, 210, 1e-9);
        assert_int_equal (uavsim_vehicle_step (v, (i + 1) * DT_S, DT_S), 0);
        s = s_state (v);
    }
    uavsim_vehicle_destroy (&v);
}

static void test_end_loop (void **state)
{
    (void)state;
    // A 600 m square at 8 m/s, with the first point repeated at the end (dropped).
    const uavsim_vehicle_point_t sq[] = {
        {0, 0, 0}, {600, 0, 0}, {600, 600, 0}, {0, 600, 0}, {0, 0, 0}};
    uavsim_vehicle_params_t p;
    s_params (&p, sq, 5);
    p.speed_mps = 8;
    p.end = UAVSIM_VEHICLE_END_LOOP;
    uavsim_vehicle_t *v = s_new (&p);
    assert_int_equal (uavsim_vehicle_points (v), 4);
    s_corner_t c = s_corner_expected (90 * DEG, 8, 8, 600, 600);
    double lap_s =
        4 * ((600 - 2 * c.t_m) / 8 + (8 - c.vc_mps) * (8 - c.vc_mps) / (2 * DEC_MPS2 * 8) +
             (8 - c.vc_mps) * (8 - c.vc_mps) / (2 * ACC_MPS2 * 8) + 2 * c.half_m / c.vc_mps);
    uavsim_vehicle_state_t prev = s_state (v);
    double lap_at[4] = {0};
    double closest0 = INFINITY;
    int legs_seen = 0;
    for (int i = 0; i < 20000 && prev.lap < 3; i++) {
        assert_int_equal (uavsim_vehicle_step (v, i * DT_S, DT_S), 0);
        uavsim_vehicle_state_t s = s_state (v);
        if (s.leg != prev.leg) {
            // Legs in order 0 1 2 3 0 ..., the closing leg last.
            assert_int_equal (s.leg, (prev.leg + 1) % 4);
            assert_int_equal (s.next_point, (s.leg + 1) % 4);
            legs_seen++;
        }
        if (s.lap != prev.lap) {
            assert_int_equal (s.lap, prev.lap + 1);
            assert_int_equal (s.leg, 0);
            lap_at[s.lap] = (i + 1) * DT_S;
        }
        if (s.lap >= 1)
            closest0 = fmin (closest0, hypot (s.e_m, s.n_m));
        assert_false (s.finished);
        prev = s;
    }
    assert_int_equal (prev.lap, 3);
    assert_int_equal (legs_seen, 12);
    print_message ("loop: laps end at %.1f, %.1f, %.1f s; laps 2 and 3 took %.1f and %.1f s, "
                   "expected %.3f s; closest to point 0 after lap 1: %.4f m\n",
                   lap_at[1], lap_at[2], lap_at[3], lap_at[2] - lap_at[1], lap_at[3] - lap_at[2],
                   lap_s, closest0);
    assert_true (fabs (lap_at[2] - lap_at[1] - lap_s) <= DT_S + 0.02);
    assert_true (fabs (lap_at[3] - lap_at[2] - lap_s) <= DT_S + 0.02);
    // Point 0 is a rounded corner once the loop closes.
    assert_true (closest0 >= CUT_M - 1e-6 && closest0 <= CUT_M + 0.02);
    uavsim_vehicle_destroy (&v);
}

static void test_end_reverse (void **state)
{
    (void)state;
    const uavsim_vehicle_point_t pts[] = {{0, 0, 0}, {500, 0, 0}, {500, 400, 0}};
    uavsim_vehicle_params_t p;
    s_params (&p, pts, 3);
    p.speed_mps = 8;
    p.end = UAVSIM_VEHICLE_END_REVERSE;
    uavsim_vehicle_t *v = s_new (&p);
    uavsim_vehicle_state_t prev = s_state (v);
    double pivot_start[3] = {0}, pivot_end[3] = {0};
    int pivot_steps[3] = {0};
    for (int i = 0; i < 20000 && !(prev.lap == 2 && !prev.turning_in_place); i++) {
        double t = i * DT_S;
        assert_int_equal (uavsim_vehicle_step (v, t, DT_S), 0);
        uavsim_vehicle_state_t s = s_state (v);
        double dh = fabs (s_dheading (prev.heading_deg, s.heading_deg));
        assert_true (dh <= OMEGA_DPS * DT_S * (1 + 1e-9));
        if (s.turning_in_place) {
            int lap = (int)s.lap;
            if (!prev.turning_in_place) {
                pivot_start[lap] = t + DT_S;
                // Stopped exactly on the end point, facing the way it came.
                const uavsim_vehicle_point_t *end = lap == 1 ? &pts[2] : &pts[0];
                assert_true (s.e_m == end->e_m && s.n_m == end->n_m);
                assert_true (s.speed_mps == 0);
                assert_int_equal (s.direction, lap == 1 ? -1 : 1);
            }
            pivot_steps[lap]++;
        } else if (prev.turning_in_place) {
            pivot_end[prev.lap] = t + DT_S;
        }
        if (s.direction < 0 && !s.turning_in_place)
            assert_true (s.next_point <= prev.next_point);
        prev = s;
    }
    assert_int_equal (prev.lap, 2);
    double t_fwd = pivot_start[1];                 // start to the far end
    double t_back = pivot_start[2] - pivot_end[1]; // far end back to the start
    print_message ("reverse: forward pass %.1f s, back %.1f s; turns in place %d and %d steps "
                   "(180 deg at %.0f deg/s = %.0f steps)\n",
                   t_fwd, t_back, pivot_steps[1], pivot_steps[2], OMEGA_DPS,
                   180 / OMEGA_DPS / DT_S);
    // Each turn in place takes 180 / 30 = 6 s; the pass back mirrors the pass out.
    assert_true (abs (pivot_steps[1] - 60) <= 1 && abs (pivot_steps[2] - 60) <= 1);
    assert_true (fabs (t_back - t_fwd) <= 2 * DT_S + 0.02);
    uavsim_vehicle_destroy (&v);
}

/* --- wander --------------------------------------------------------------------------------- */

static void test_wander_seeded (void **state)
{
    (void)state;
    const double dev = 25;
    uavsim_vehicle_params_t p;
    s_params (&p, s_route, S_ROUTE_N);
    p.deviation_m = dev;
    p.seed = 11;
    uavsim_vehicle_t *a = s_new (&p), *b = s_new (&p);
    p.seed = 12;
    uavsim_vehicle_t *c = s_new (&p);
    p.deviation_m = 0;
    uavsim_vehicle_t *z = s_new (&p);
    double max_dev = 0, max_diff = 0, max_route = 0, max_line = 0, max_near_pts = 0;
    bool done = false;
    for (int i = 0; i < 20000 && !done; i++) {
        double t = i * DT_S;
        assert_int_equal (uavsim_vehicle_step (a, t, DT_S), 0);
        assert_int_equal (uavsim_vehicle_step (b, t, DT_S), 0);
        assert_int_equal (uavsim_vehicle_step (c, t, DT_S), 0);
        assert_int_equal (uavsim_vehicle_step (z, t, DT_S), 0);
        uavsim_vehicle_state_t sa = s_state (a), sb = s_state (b), sc = s_state (c),
                               sz = s_state (z);
        assert_true (s_same (&sa, &sb)); // same seed: bit for bit
        max_diff = fmax (max_diff, hypot (sa.e_m - sc.e_m, sa.n_m - sc.n_m));
        assert_true (fabs (sa.dev_m) <= dev);
        max_dev = fmax (max_dev, fabs (sa.dev_m));
        // Off the route by no more than the wander (or the corner cut on arcs).
        max_route = fmax (max_route, s_route_dist (s_route, S_ROUTE_N, sa.e_m, sa.n_m));
        // No wander at the route points: within 2 m beyond a corner's arc the
        // offset has tapered to (nearly) nothing.
        for (int k = 0; k < S_ROUTE_N; k++) {
            double tk = 0;
            if (k == 1)
                tk = s_corner_expected (90 * DEG, 10, 8, 1000, 800).t_m;
            if (k == 2)
                tk = s_corner_expected (150 * DEG, 8, 6, 800, 600).t_m;
            if (hypot (sa.e_m - s_route[k].e_m, sa.n_m - s_route[k].n_m) <= tk + 2)
                max_near_pts = fmax (max_near_pts, fabs (sa.dev_m));
        }
        // Deviation 0: on the line exactly, away from the corner arcs.
        assert_true (sz.dev_m == 0);
        for (int k = 0; k < S_ROUTE_N - 1; k++) {
            double d = s_seg_dist (sz.e_m, sz.n_m, s_route[k].e_m, s_route[k].n_m,
                                   s_route[k + 1].e_m, s_route[k + 1].n_m);
            if (sz.leg == k && hypot (sz.e_m - s_route[k].e_m, sz.n_m - s_route[k].n_m) > 30 &&
                hypot (sz.e_m - s_route[k + 1].e_m, sz.n_m - s_route[k + 1].n_m) > 30)
                max_line = fmax (max_line, d);
        }
        done = sa.finished && sc.finished && sz.finished;
    }
    assert_true (done);
    print_message ("wander %.0f m: largest offset %.3f m, farthest from the route %.3f m, largest "
                   "offset near route points %.2e m, seeds 11 vs 12 differ by up to %.1f m; "
                   "no wander: %.2e m off the line\n",
                   dev, max_dev, max_route, max_near_pts, max_diff, max_line);
    assert_true (max_dev >= 0.25 * dev);
    assert_true (max_route <= dev + 1e-9);
    assert_true (max_near_pts <= 0.02);
    assert_true (max_diff > 1);
    assert_true (max_line <= 1e-9);
    uavsim_vehicle_destroy (&a);
    uavsim_vehicle_destroy (&b);
    uavsim_vehicle_destroy (&c);
    uavsim_vehicle_destroy (&z);
}

/* --- random routes ------------------------------------------------------------------------- */

static double s_rand (uint64_t *x, double lo, double hi)
{
    uint64_t z = (*x += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    z ^= z >> 31;
    return lo + (hi - lo) * (double)(z >> 11) * (1.0 / 9007199254740992.0);
}

/* Random routes (legs from 0.5 m to 1 km, any corner up to doubling back, all
 * end behaviours, steps 0.05-0.1 s): limits hold on every step, stop routes
 * finish on their last point within a bound from their legs, and a corner of
 * 175 degrees is taken by stopping on the point. */
static void test_random_routes (void **state)
{
    (void)state;
    uint64_t rs = 2024;
    int finished = 0, stops = 0, pivots = 0;
    double worst_rate = 0, worst_lat = 0;
    for (int trial = 0; trial < 300; trial++) {
        uavsim_vehicle_point_t pts[8];
        size_t n = 2 + (size_t)s_rand (&rs, 0, 6.999);
        double e = 0, nn = 0, hd = s_rand (&rs, 0, 2 * M_PI), bare_s = 0;
        uavsim_vehicle_params_t p;
        uavsim_vehicle_params_defaults (&p);
        p.speed_mps = s_rand (&rs, 1, 20);
        for (size_t i = 0; i < n; i++) {
            pts[i] =
                (uavsim_vehicle_point_t){e, nn, s_rand (&rs, 0, 1) < 0.5 ? 0 : s_rand (&rs, 1, 20)};
            double len = s_rand (&rs, 0, 1) < 0.2 ? s_rand (&rs, 0.5, 10) : s_rand (&rs, 10, 1000);
            hd += s_rand (&rs, -M_PI, M_PI);
            e += len * sin (hd);
            nn += len * cos (hd);
            if (i + 1 < n)
                bare_s += hypot (e - pts[i].e_m, nn - pts[i].n_m) /
                          (pts[i].speed_mps > 0 ? pts[i].speed_mps : p.speed_mps);
        }
        p.points = pts;
        p.n_points = n;
        p.end = (uavsim_vehicle_end_t)(trial % 3);
        p.deviation_m = s_rand (&rs, 0, 1) < 0.3 ? 0 : s_rand (&rs, 0, 60);
        p.seed = (uint64_t)trial;
        p.turn_rate_dps = s_rand (&rs, 10, 60);
        p.lat_accel_mps2 = s_rand (&rs, 0.5, 4);
        p.accel_mps2 = s_rand (&rs, 0.5, 3);
        p.decel_mps2 = s_rand (&rs, 0.5, 4);
        p.corner_cut_m = s_rand (&rs, 1, 40);
        double dt = s_rand (&rs, 0.05, 0.1);
        double vmax = p.speed_mps;
        for (size_t i = 0; i < n; i++)
            vmax = fmax (vmax, pts[i].speed_mps);
        uavsim_vehicle_t *v = s_new (&p);
        uavsim_vehicle_state_t prev = s_state (v);
        // Generous bound for stop routes: each corner may cost a stop, a turn
        // in place and a start.
        double bound_s =
            2 * bare_s +
            (double)n * (vmax / p.accel_mps2 + vmax / p.decel_mps2 + 180 / p.turn_rate_dps) + 10;
        int steps = (int)(fmin (bound_s, 3000) / dt);
        for (int i = 0; i < steps; i++) {
            assert_int_equal (uavsim_vehicle_step (v, i * dt, dt), 0);
            uavsim_vehicle_state_t s = s_state (v);
            assert_true (isfinite (s.e_m) && isfinite (s.n_m) && isfinite (s.heading_deg));
            assert_true (s.speed_mps >= 0 && s.speed_mps <= vmax + 1e-9);
            assert_true (fabs (s.dev_m) <= p.deviation_m);
            double dh = fabs (s_dheading (prev.heading_deg, s.heading_deg));
            worst_rate = fmax (worst_rate, dh / dt / p.turn_rate_dps);
            worst_lat = fmax (worst_lat, dh * DEG / dt * 0.5 * (s.speed_mps + prev.speed_mps) /
                                             p.lat_accel_mps2);
            if (s.turning_in_place && !prev.turning_in_place)
                pivots++;
            prev = s;
        }
        if (p.end == UAVSIM_VEHICLE_END_STOP) {
            stops++;
            if (!prev.finished)
                fail_msg ("trial %d: not finished after %.0f s", trial, steps * dt);
            assert_true (prev.e_m == pts[n - 1].e_m && prev.n_m == pts[n - 1].n_m);
            finished++;
        }
        uavsim_vehicle_destroy (&v);
    }
    print_message ("300 random routes: worst turn rate %.9f of the limit, worst lateral "
                   "acceleration %.9f of the limit; %d/%d stop routes finished on their last "
                   "point; %d turns in place\n",
                   worst_rate, worst_lat, finished, stops, pivots);
    assert_true (worst_rate <= 1 + 1e-9);
    assert_true (worst_lat <= 1 + 1e-6);

    // A 175-degree corner: stop on the point, turn in place, drive on.
    const uavsim_vehicle_point_t hair[] = {
        {0, 0, 0}, {0, 500, 0}, {500 * sin (175 * DEG), 500 + 500 * cos (175 * DEG), 0}};
    uavsim_vehicle_params_t p;
    s_params (&p, hair, 3);
    uavsim_vehicle_t *v = s_new (&p);
    double r;
    uavsim_vehicle_corner (v, 1, &r, NULL);
    assert_true (r == 0);
    bool seen = false;
    for (int i = 0; i < 3000; i++) {
        uavsim_vehicle_step (v, i * DT_S, DT_S);
        uavsim_vehicle_state_t s = s_state (v);
        if (s.turning_in_place && !seen) {
            seen = true;
            assert_true (s.e_m == 0 && s.n_m == 500 && s.speed_mps == 0);
            assert_int_equal (s.leg, 1);
        }
    }
    assert_true (seen && s_state (v).finished);
    uavsim_vehicle_destroy (&v);
}

/* --- checkpoint ----------------------------------------------------------------------------- */

/* Run a to t_save, checkpoint, restore into a fresh b, run both to t_end in lockstep. */
static void s_check_restore (const uavsim_vehicle_params_t *p, double t_save, double t_end,
                             uint64_t *ret_laps_after)
{
    uavsim_vehicle_t *a = s_new (p), *b = s_new (p);
    int i = 0;
    for (; i * DT_S < t_save; i++)
        assert_int_equal (uavsim_vehicle_step (a, i * DT_S, DT_S), 0);
    uint8_t *buf = NULL;
    size_t n = 0;
    assert_int_equal (uavsim_vehicle_save (a, &buf, &n), 0);
    assert_int_equal (n, CK_BYTES);
    char err[256] = "";
    assert_int_equal (uavsim_vehicle_restore (b, buf, n, err, sizeof err), 0);
    free (buf);
    uavsim_vehicle_state_t sa = s_state (a), sb = s_state (b);
    assert_true (s_same (&sa, &sb));
    uint64_t lap0 = sa.lap;
    for (; i * DT_S < t_end; i++) {
        assert_int_equal (uavsim_vehicle_step (a, i * DT_S, DT_S), 0);
        assert_int_equal (uavsim_vehicle_step (b, i * DT_S, DT_S), 0);
        sa = s_state (a);
        sb = s_state (b);
        assert_true (s_same (&sa, &sb));
    }
    *ret_laps_after = sa.lap - lap0;
    uavsim_vehicle_destroy (&a);
    uavsim_vehicle_destroy (&b);
}

static void test_save_restore (void **state)
{
    (void)state;
    const uavsim_vehicle_point_t sq[] = {{0, 0, 0}, {900, 0, 12}, {900, 700, 0}, {0, 700, 5}};
    uavsim_vehicle_params_t p;
    s_params (&p, sq, 4);
    p.speed_mps = 9;
    p.deviation_m = 30;
    p.seed = 99;
    p.end = UAVSIM_VEHICLE_END_LOOP;
    uint64_t laps = 0;
    // Mid-leg on the first lap; three laps follow, each drawing a new wander.
    s_check_restore (&p, 123.4, 1500, &laps);
    print_message ("loop restored at 123.4 s: %llu laps (new draws) followed, bit-identical\n",
                   (unsigned long long)laps);
    assert_true (laps >= 2);
    // A reversing vehicle restored while it turns in place at the far end.
    const uavsim_vehicle_point_t line[] = {{0, 0, 0}, {300, 0, 0}, {300, 200, 0}};
    s_params (&p, line, 3);
    p.speed_mps = 10;
    p.deviation_m = 10;
    p.end = UAVSIM_VEHICLE_END_REVERSE;
    uavsim_vehicle_t *probe = s_new (&p);
    double t_pivot = -1;
    for (int i = 0; i < 5000 && t_pivot < 0; i++) {
        uavsim_vehicle_step (probe, i * DT_S, DT_S);
        if (s_state (probe).turning_in_place)
            t_pivot = (i + 1) * DT_S;
    }
    assert_true (t_pivot > 0);
    s_check_restore (&p, t_pivot + 2, 600, &laps);
    assert_true (laps >= 2);
    // Waiting before its start time.
    p.start_time_s = 50;
    s_check_restore (&p, 20, 200, &laps);
    uavsim_vehicle_destroy (&probe);
}

/* Seal a forged checkpoint again: its payload's CRC-32 in the last 4 bytes. */
static void s_reseal (uint8_t *b, size_t n)
{
    uint32_t crc = cgs_crc32 (b + CGS_CKPT_HEAD, n - CGS_CKPT_HEAD - CGS_CKPT_TAIL);
    for (int i = 0; i < 4; i++)
        b[n - 4 + i] = (uint8_t)(crc >> (8 * i));
}

/* v's checkpoint, copied into buf (CK_BYTES of it). */
static size_t s_save_into (const uavsim_vehicle_t *v, uint8_t *buf)
{
    uint8_t *b = NULL;
    size_t n = 0;
    assert_int_equal (uavsim_vehicle_save (v, &b, &n), 0);
    assert_int_equal (n, CK_BYTES);
    memcpy (buf, b, n);
    free (b);
    return n;
}

static void test_restore_damaged (void **state)
{
    (void)state;
    uavsim_vehicle_params_t p;
    s_params (&p, s_route, S_ROUTE_N);
    p.deviation_m = 10;
    p.seed = 5;
    uavsim_vehicle_t *a = s_new (&p), *b = s_new (&p);
    for (int i = 0; i < 1234; i++)
        uavsim_vehicle_step (a, i * DT_S, DT_S);
    for (int i = 0; i < 77; i++)
        uavsim_vehicle_step (b, i * DT_S, DT_S);
    uavsim_vehicle_state_t before = s_state (b);
    uint8_t buf[CK_BYTES + 1], bad[CK_BYTES + 1];
    size_t n = s_save_into (a, buf);
    char err[256] = "";
    // Every single-bit flip is caught (by the frame: magic, version, length,
    // else the checksum), and b is left as it was.
    for (size_t i = 0; i < n; i++)
        for (int bit = 0; bit < 8; bit++) {
            memcpy (bad, buf, n);
            bad[i] ^= (uint8_t)(1u << bit);
            int want = i < 4 ? -EPROTO : i < 8 ? -ENOTSUP : i < 16 ? -EINVAL : -EBADMSG;
            assert_int_equal (uavsim_vehicle_restore (b, bad, n, err, sizeof err), want);
        }
    uavsim_vehicle_state_t after = s_state (b);
    assert_true (s_same (&before, &after));
    // Truncated, extended, missing.
    for (size_t l = 0; l < n; l++)
        assert_int_equal (uavsim_vehicle_restore (b, buf, l, err, sizeof err), -EINVAL);
    buf[n] = 0;
    assert_int_equal (uavsim_vehicle_restore (b, buf, n + 1, err, sizeof err), -EINVAL);
    assert_int_equal (uavsim_vehicle_restore (b, NULL, n, err, sizeof err), -EINVAL);
    assert_int_equal (uavsim_vehicle_restore (b, buf, 0, err, sizeof err), -EINVAL);
    // Well-formed but impossible: a leg past the route's end, a negative speed
    // (checksum recomputed, so only the validation can catch them).
    memcpy (bad, buf, n);
    bad[CK_ELEMENT] = 9;
    s_reseal (bad, n);
    assert_int_equal (uavsim_vehicle_restore (b, bad, n, err, sizeof err), -EINVAL);
    assert_non_null (strstr (err, "no vehicle on this route can be in"));
    memcpy (bad, buf, n);
    bad[CK_SPEED + 7] ^= 0x80; // speed's sign bit
    s_reseal (bad, n);
    assert_int_equal (uavsim_vehicle_restore (b, bad, n, err, sizeof err), -EINVAL);
    // From a vehicle with other parameters.
    p.seed = 6;
    uavsim_vehicle_t *c = s_new (&p);
    assert_int_equal (uavsim_vehicle_restore (c, buf, n, err, sizeof err), -EPROTO);
    assert_non_null (strstr (err, "of another vehicle"));
    after = s_state (b);
    assert_true (s_same (&before, &after));
    // The intact checkpoint still restores.
    assert_int_equal (uavsim_vehicle_restore (b, buf, n, err, sizeof err), 0);
    uavsim_vehicle_state_t sa = s_state (a), sb = s_state (b);
    assert_true (s_same (&sa, &sb));
    uavsim_vehicle_destroy (&a);
    uavsim_vehicle_destroy (&b);
    uavsim_vehicle_destroy (&c);
}

/* --- halts ------------------------------------------------------------------------------------ */

static void test_halt_params (void **state)
{
    (void)state;
    uavsim_vehicle_params_t p;
    uavsim_vehicle_t *v = NULL;
    char err[128];
    double halts[S_ROUTE_N] = {0};
    const double bad[] = {NAN, -1, INFINITY, 2e6};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        s_params (&p, s_route, S_ROUTE_N);
        halts[1] = bad[i];
        p.halt_s = halts;
        assert_int_equal (uavsim_vehicle_new (&p, &v), -EINVAL);
        assert_int_equal (uavsim_vehicle_params_check (&p, err, sizeof err), -EINVAL);
        assert_non_null (strstr (err, "point 2: halt"));
    }
    // A stop route never comes back to its first point, and ends on its last.
    for (int end = 0; end < 2; end++) {
        memset (halts, 0, sizeof halts);
        halts[end ? S_ROUTE_N - 1 : 0] = 10;
        s_params (&p, s_route, S_ROUTE_N);
        p.halt_s = halts;
        assert_int_equal (uavsim_vehicle_params_check (&p, err, sizeof err), -EINVAL);
        assert_non_null (strstr (err, "stop route"));
        // Loop and reverse routes come back to both.
        p.end = UAVSIM_VEHICLE_END_LOOP;
        assert_int_equal (uavsim_vehicle_params_check (&p, err, sizeof err), 0);
        p.end = UAVSIM_VEHICLE_END_REVERSE;
        assert_int_equal (uavsim_vehicle_params_check (&p, err, sizeof err), 0);
    }
    // A loop's repeated last point is dropped: its halt belongs on the first.
    const uavsim_vehicle_point_t closed[] = {{0, 0, 0}, {500, 0, 0}, {500, 500, 0}, {0, 0, 0}};
    const double closed_halts[] = {0, 0, 0, 5};
    s_params (&p, closed, 4);
    p.end = UAVSIM_VEHICLE_END_LOOP;
    p.halt_s = closed_halts;
    assert_int_equal (uavsim_vehicle_params_check (&p, err, sizeof err), -EINVAL);
    assert_non_null (strstr (err, "point 4 repeats point 1"));
    assert_null (v);
    // Halts only where they are: a halt point is stopped on, not rounded.
    memset (halts, 0, sizeof halts);
    halts[2] = 30;
    s_params (&p, s_route, S_ROUTE_N);
    p.halt_s = halts;
    v = s_new (&p);
    double r, vc;
    uavsim_vehicle_corner (v, 1, &r, &vc);
    assert_true (r > 0 && vc > 0);
    uavsim_vehicle_corner (v, 2, &r, &vc);
    assert_true (r == 0 && vc == 0);
    uavsim_vehicle_destroy (&v);
}

/* One halt seen while stepping: a run of halted steps. */
typedef struct {
    double e_m, n_m;    // where it stood
    double heading_deg; // facing
    double from_s;      // arrival, from the first halted step's time left
    int steps;          // halted steps
    uint64_t lap;       // lap or pass, as the state says during the halt
    int direction;      // direction of the leg after it
    bool then_pivot;    // the step after it turned in place
} s_halt_seen_t;

/* Step v on a DT_S grid up to t_end_s, recording each halt (at most max);
 * every halted step must be still, on one spot, and count down by the step. */
static size_t s_run_halts (uavsim_vehicle_t *v, double t_end_s, const double *halts,
                           s_halt_seen_t *seen, size_t max)
{
    size_t n = 0;
    uavsim_vehicle_state_t prev = s_state (v);
    for (int i = 0; i * DT_S < t_end_s; i++) {
        double t1 = (i + 1) * DT_S;
        assert_int_equal (uavsim_vehicle_step (v, i * DT_S, DT_S), 0);
        uavsim_vehicle_state_t s = s_state (v);
        assert_true (fabs (s_dheading (prev.heading_deg, s.heading_deg)) <=
                     OMEGA_DPS * DT_S * (1 + 1e-9));
        if (s.halted) {
            assert_true (s.speed_mps == 0 && s.ve_mps == 0 && s.vn_mps == 0);
            assert_false (s.turning_in_place || s.finished);
            if (!prev.halted) {
                assert_true (n < max);
                // Where it stands: a route point with a halt, given by next_point and direction.
                int at = s.direction > 0 ? s.leg : s.leg + 1;
                assert_true (halts[at] > 0);
                assert_true (s.halt_left_s > halts[at] - DT_S - 1e-9 && s.halt_left_s <= halts[at]);
                seen[n] =
                    (s_halt_seen_t){s.e_m, s.n_m, s.heading_deg, t1 - (halts[at] - s.halt_left_s),
                                    0,     s.lap, s.direction,   false};
                n++;
            } else {
                assert_true (s.e_m == prev.e_m && s.n_m == prev.n_m);
                assert_true (s.heading_deg == prev.heading_deg);
                assert_near (s.halt_left_s, prev.halt_left_s - DT_S, 1e-9);
            }
            seen[n - 1].steps++;
        } else {
            assert_true (s.halt_left_s == 0);
            if (prev.halted)
                seen[n - 1].then_pivot = s.turning_in_place;
        }
        prev = s;
    }
    return n;
}

/* A halt on a straight: brake to a stop on the point exactly, stand still
 * for the time given, then set off, each within the step it falls in;
 * the times from the documented allowances. */
static void test_halt_on_point (void **state)
{
    (void)state;
    const uavsim_vehicle_point_t pts[] = {{0, 0, 0}, {1000, 0, 0}, {1600, 0, 0}};
    const double halts[] = {0, 45, 0};
    uavsim_vehicle_params_t p;
    s_params (&p, pts, 3);
    p.halt_s = halts;
    uavsim_vehicle_t *v = s_new (&p);
    const double V = 10;
    double t_arrive = V / (2 * ACC_MPS2) + 1000 / V + V / (2 * DEC_MPS2);
    double t_leave = t_arrive + halts[1];
    double t_end = t_leave + V / (2 * ACC_MPS2) + 600 / V + V / (2 * DEC_MPS2);
    uavsim_vehicle_state_t prev = s_state (v);
    int halted_steps = 0, braking_steps = 0;
    double finished_s = -1, arrived_s = -1;
    for (int i = 0; i < 3000 && finished_s < 0; i++) {
        double t1 = (i + 1) * DT_S;
        assert_int_equal (uavsim_vehicle_step (v, i * DT_S, DT_S), 0);
        uavsim_vehicle_state_t s = s_state (v);
        if (s.halted && !prev.halted) {
            // Arrived on time (the braking is planned step by step: to 20 ms);
            // from here on the halt is timed from the arrival exactly.
            arrived_s = t1 - (halts[1] - s.halt_left_s);
            print_message ("halt: arrived at %.6f s, expected %.6f s\n", arrived_s, t_arrive);
            assert_near (arrived_s, t_arrive, 0.02);
            t_arrive = arrived_s;
            t_leave = t_arrive + halts[1];
            t_end = t_leave + V / (2 * ACC_MPS2) + 600 / V + V / (2 * DEC_MPS2);
        }
        if (t1 < t_arrive - 0.02) {
            assert_false (s.halted);
            assert_true (s.e_m < 1000 && s.halt_left_s == 0);
            if (t1 > t_arrive - V / DEC_MPS2 + 0.02) { // braking to the point
                assert_near (s.speed_mps, DEC_MPS2 * (t_arrive - t1), 0.05);
                braking_steps++;
            }
        } else if (arrived_s >= 0 && t1 < t_leave - 1e-6) {
            // On the point exactly, still, facing the way it came.
            assert_true (s.halted && s.active);
            assert_false (s.turning_in_place || s.finished);
            assert_true (s.e_m == 1000 && s.n_m == 0);
            assert_true (s.speed_mps == 0 && s.ve_mps == 0 && s.vn_mps == 0);
            assert_near (s.heading_deg, 90, 1e-12);
            assert_near (s.halt_left_s, t_leave - t1, 1e-9);
            assert_int_equal (s.leg, 1);
            halted_steps++;
        } else if (t1 > t_leave + 1e-6 && !s.finished) {
            assert_false (s.halted);
            assert_true (s.e_m > 1000 && s.halt_left_s == 0);
            if (prev.halted) { // set off from rest within the step the halt ended in
                double dt = t1 - t_leave;
                print_message ("halt: arrived at %.4f s, left at %.4f s; %.4f s into the step "
                               "after: %.6f m/s, %.6f m past the point\n",
                               t_arrive, t_leave, dt, s.speed_mps, s.e_m - 1000);
                assert_near (s.speed_mps, ACC_MPS2 * dt, 1e-9);
                assert_near (s.e_m - 1000, 0.5 * ACC_MPS2 * dt * dt, 1e-9);
            }
        }
        if (s.finished)
            finished_s = t1;
        prev = s;
    }
    print_message ("halt of %.0f s: %d halted steps, %d braking steps; finished in the step ending "
                   "%.1f s, expected %.3f s\n",
                   halts[1], halted_steps, braking_steps, finished_s, t_end);
    assert_true (arrived_s > 0 && abs (halted_steps - 450) <= 1);
    assert_true (braking_steps >= 45);
    assert_true (finished_s - t_end >= -0.02 && finished_s - t_end <= DT_S + 0.02);
    assert_true (prev.e_m == 1600 && prev.n_m == 0);
    uavsim_vehicle_destroy (&v);

    // All-zero halts are no halts: the same motion, bit for bit, as none.
    const double zeros[] = {0, 0, 0};
    p.halt_s = zeros;
    uavsim_vehicle_t *a = s_new (&p);
    p.halt_s = NULL;
    uavsim_vehicle_t *b = s_new (&p);
    for (int i = 0; i < 1500; i++) {
        uavsim_vehicle_step (a, i * DT_S, DT_S);
        uavsim_vehicle_step (b, i * DT_S, DT_S);
        uavsim_vehicle_state_t sa = s_state (a), sb = s_state (b);
        assert_true (s_same (&sa, &sb));
        assert_false (sa.halted);
    }
    uavsim_vehicle_destroy (&a);
    uavsim_vehicle_destroy (&b);
}

/* A halt on a corner: no arc; stop on the point, halt, turn in place, drive on. */
static void test_halt_on_corner (void **state)
{
    (void)state;
    const uavsim_vehicle_point_t pts[] = {{0, 0, 0}, {1000, 0, 0}, {1000, 800, 0}};
    const double halts[] = {0, 20, 0};
    uavsim_vehicle_params_t p;
    s_params (&p, pts, 3);
    p.halt_s = halts;
    uavsim_vehicle_t *v = s_new (&p);
    const double V = 10, turn_s = 90 / OMEGA_DPS;
    double t_arrive = V / (2 * ACC_MPS2) + 1000 / V + V / (2 * DEC_MPS2);
    double t_leave = t_arrive + halts[1];
    double t_end = t_leave + turn_s + V / (2 * ACC_MPS2) + 800 / V + V / (2 * DEC_MPS2);
    s_halt_seen_t seen[4];
    size_t n = s_run_halts (v, t_end + 1, halts, seen, 4);
    uavsim_vehicle_state_t s = s_state (v);
    assert_int_equal (n, 1);
    assert_true (seen[0].e_m == 1000 && seen[0].n_m == 0);
    assert_near (seen[0].heading_deg, 90, 1e-12);
    assert_near (seen[0].from_s, t_arrive, 0.02);
    assert_true (abs (seen[0].steps - 200) <= 1);
    assert_true (seen[0].then_pivot);
    assert_true (s.finished && s.e_m == 1000 && s.n_m == 800);
    uavsim_vehicle_destroy (&v);
    // Finished on time: step again and watch for the end.
    v = s_new (&p);
    double finished_s = -1, pivot_steps = 0;
    for (int i = 0; i < 3000 && finished_s < 0; i++) {
        uavsim_vehicle_step (v, i * DT_S, DT_S);
        s = s_state (v);
        pivot_steps += s.turning_in_place;
        if (s.finished)
            finished_s = (i + 1) * DT_S;
    }
    print_message ("halt on a corner: finished in the step ending %.1f s, expected %.3f s; %.0f "
                   "steps turning in place (90 deg at %.0f deg/s)\n",
                   finished_s, t_end, pivot_steps, OMEGA_DPS);
    assert_true (finished_s - t_end >= -0.02 && finished_s - t_end <= DT_S + 0.02);
    assert_true (fabs (pivot_steps - turn_s / DT_S) <= 1);
    uavsim_vehicle_destroy (&v);
}

/* Loop: the halts come round on every lap, the first point's at the end of each. */
static void test_halt_loop (void **state)
{
    (void)state;
    const uavsim_vehicle_point_t sq[] = {{0, 0, 0}, {600, 0, 0}, {600, 600, 0}, {0, 600, 0}};
    const double halts[] = {10, 0, 20, 0};
    uavsim_vehicle_params_t p;
    s_params (&p, sq, 4);
    p.speed_mps = 8;
    p.end = UAVSIM_VEHICLE_END_LOOP;
    p.halt_s = halts;
    uavsim_vehicle_t *v = s_new (&p);
    // A lap: two legs from a halt to a rounded corner and two from a corner to a halt.
    const double V = 8;
    s_corner_t c = s_corner_expected (90 * DEG, V, V, 600, 600);
    double leg_s = V / (2 * ACC_MPS2) + (600 - c.t_m) / V +
                   (V - c.vc_mps) * (V - c.vc_mps) / (2 * DEC_MPS2 * V) + c.half_m / c.vc_mps;
    double leg2_s = c.half_m / c.vc_mps + (V - c.vc_mps) * (V - c.vc_mps) / (2 * ACC_MPS2 * V) +
                    (600 - c.t_m) / V + V / (2 * DEC_MPS2);
    double lap_s = 2 * (leg_s + leg2_s) + halts[0] + halts[2] + 2 * 90 / OMEGA_DPS;
    s_halt_seen_t seen[16];
    size_t n = s_run_halts (v, 3.5 * lap_s, halts, seen, 16);
    print_message ("loop with halts: %zu halts in %.0f s; lap expected %.3f s, laps measured "
                   "%.3f, %.3f s\n",
                   n, 3.5 * lap_s, lap_s, seen[3].from_s - seen[1].from_s,
                   seen[5].from_s - seen[3].from_s);
    assert_int_equal (n, 7); // point 2, then point 0 and point 2 on each lap
    for (size_t i = 0; i < n; i++) {
        int at = i % 2 == 0 ? 2 : 0;
        assert_true (seen[i].e_m == sq[at].e_m && seen[i].n_m == sq[at].n_m);
        if (i + 1 < n) { // (the run ends in the last)
            assert_true (abs (seen[i].steps - (int)(halts[at] / DT_S)) <= 1);
            assert_true (seen[i].then_pivot); // 90 degrees to turn after each
        }
        assert_int_equal (seen[i].lap, (i + 1) / 2);
        if (i >= 3)
            assert_near (seen[i].from_s - seen[i - 2].from_s, lap_s, 0.02);
    }
    uavsim_vehicle_destroy (&v);
}

/* Reverse: the middle point halts both ways, each end before the turn about. */
static void test_halt_reverse (void **state)
{
    (void)state;
    const uavsim_vehicle_point_t pts[] = {{0, 0, 0}, {500, 0, 0}, {500, 400, 0}};
    const double halts[] = {15, 25, 35};
    uavsim_vehicle_params_t p;
    s_params (&p, pts, 3);
    p.speed_mps = 8;
    p.end = UAVSIM_VEHICLE_END_REVERSE;
    p.halt_s = halts;
    uavsim_vehicle_t *v = s_new (&p);
    const double V = 8;
    // Point 0 to point 2 and back: each leg from rest to rest, a halt and a
    // turn in place (90 degrees at point 1, 180 at the ends) at each point.
    double pass_s = 2 * V / (2 * ACC_MPS2) + 2 * V / (2 * DEC_MPS2) + 900 / V + halts[1] +
                    90 / OMEGA_DPS + 180 / OMEGA_DPS;
    s_halt_seen_t seen[16];
    size_t n = s_run_halts (v, 3 * pass_s + halts[0] + halts[2] + 30, halts, seen, 16);
    // Points 1, 2 (end), 1, 0 (end), 1, 2, ...; the direction is the next leg's.
    static const int order[] = {1, 2, 1, 0, 1, 2}, dirs[] = {1, -1, -1, 1, 1, -1};
    print_message ("reverse with halts: %zu halts; passes expected %.3f s, measured %.3f s\n", n,
                   pass_s + halts[2], seen[3].from_s - seen[1].from_s);
    assert_true (n >= 6);
    for (size_t i = 0; i < 6; i++) {
        int at = order[i];
        assert_true (seen[i].e_m == pts[at].e_m && seen[i].n_m == pts[at].n_m);
        assert_true (abs (seen[i].steps - (int)(halts[at] / DT_S)) <= 1);
        assert_true (seen[i].then_pivot);
        assert_int_equal (seen[i].direction, dirs[i]);
        if (at != 1) // at an end, facing the way it came in, before turning about
            assert_near (seen[i].heading_deg, at == 2 ? 0 : 270, 1e-9);
    }
    assert_near (seen[3].from_s - seen[1].from_s, pass_s + halts[2], 0.02);
    assert_near (seen[5].from_s - seen[3].from_s, pass_s + halts[0], 0.02);
    uavsim_vehicle_destroy (&v);
}

/* Restored in the middle of a halt (with its turn still to come), it stands
 * for the rest of the halt and drives on bit for bit as the original. */
static void test_halt_save_restore (void **state)
{
    (void)state;
    const uavsim_vehicle_point_t pts[] = {{0, 0, 0}, {500, 0, 0}, {500, 400, 0}};
    const double halts[] = {15, 25, 35};
    uavsim_vehicle_params_t p;
    s_params (&p, pts, 3);
    p.speed_mps = 8;
    p.deviation_m = 12;
    p.seed = 8;
    p.end = UAVSIM_VEHICLE_END_REVERSE;
    p.halt_s = halts;
    // Find a time in the halt at each point.
    uavsim_vehicle_t *probe = s_new (&p);
    double t_in[3] = {-1, -1, -1};
    for (int i = 0; i < 20000 && t_in[0] < 0; i++) {
        uavsim_vehicle_step (probe, i * DT_S, DT_S);
        uavsim_vehicle_state_t s = s_state (probe);
        int at = s.direction > 0 ? s.leg : s.leg + 1;
        if (s.halted && t_in[at] < 0 && s.halt_left_s < 0.5 * halts[at])
            t_in[at] = (i + 1) * DT_S;
    }
    uavsim_vehicle_destroy (&probe);
    for (int at = 0; at < 3; at++) {
        assert_true (t_in[at] > 0);
        uavsim_vehicle_t *a = s_new (&p);
        int i = 0;
        for (; i * DT_S < t_in[at] - 1e-9; i++)
            uavsim_vehicle_step (a, i * DT_S, DT_S);
        assert_true (s_state (a).halted);
        uavsim_vehicle_destroy (&a);
        uint64_t laps;
        s_check_restore (&p, t_in[at], t_in[at] + 400, &laps);
        assert_true (laps >= 1);
    }

    // A halted checkpoint: impossible halts refused (checksum recomputed), and
    // a vehicle with another halt there refuses it.
    uavsim_vehicle_t *a = s_new (&p), *b = s_new (&p);
    int i = 0;
    for (; (i + 1) * DT_S <= t_in[1]; i++)
        uavsim_vehicle_step (a, i * DT_S, DT_S);
    uint8_t buf[CK_BYTES], bad[CK_BYTES];
    size_t n = s_save_into (a, buf);
    char err[256] = "";
    const double bad_left[] = {0, -1, 25.5, NAN};
    for (size_t k = 0; k < sizeof bad_left / sizeof bad_left[0]; k++) {
        memcpy (bad, buf, n);
        uint64_t u;
        memcpy (&u, &bad_left[k], 8);
        for (int j = 0; j < 8; j++)
            bad[CK_HALT + j] = (uint8_t)(u >> (8 * j));
        s_reseal (bad, n);
        assert_int_equal (uavsim_vehicle_restore (b, bad, n, err, sizeof err), -EINVAL);
    }
    memcpy (bad, buf, n);
    bad[CK_PHASE] = 1; // phase: driving, with a halt left
    s_reseal (bad, n);
    assert_int_equal (uavsim_vehicle_restore (b, bad, n, err, sizeof err), -EINVAL);
    assert_false (s_state (b).active); // untouched
    double other[] = {15, 26, 35};
    p.halt_s = other;
    uavsim_vehicle_t *c = s_new (&p);
    assert_int_equal (uavsim_vehicle_restore (c, buf, n, err, sizeof err), -EPROTO);
    assert_int_equal (uavsim_vehicle_restore (b, buf, n, err, sizeof err), 0);
    uavsim_vehicle_state_t sa = s_state (a), sb = s_state (b);
    assert_true (s_same (&sa, &sb) && sb.halted);
    uavsim_vehicle_destroy (&a);
    uavsim_vehicle_destroy (&b);
    uavsim_vehicle_destroy (&c);
}

/* Checkpoints of the formats before cgs_ckpt (format 1, 180 bytes, by the
 * model of commit 564cda9: test_restore_damaged's vehicle after 1234 steps;
 * format 2 the same with a halt) are refused with the reason, not misread,
 * and leave the vehicle as it was. */
static void test_restore_old_formats_refused (void **state)
{
    (void)state;
    static const uint8_t old[180] = {
        0x55, 0x56, 0x45, 0x48, 0x01, 0x00, 0x00, 0x00, 0x4c, 0xf9, 0x79, 0xd8, 0xef, 0x3f, 0x56,
        0x73, 0x01, 0x00, 0x00, 0x00, 0x01, 0x00, 0x00, 0x00, 0x01, 0x00, 0x00, 0x00, 0x00, 0x00,
        0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x13, 0x8b, 0xb6, 0xa4, 0xde,
        0xeb, 0x62, 0x40, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x20, 0x40, 0x35, 0x07, 0xab, 0xd7,
        0x6a, 0xdc, 0x18, 0x40, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0xe1, 0x3a, 0x3e,
        0x1b, 0xa7, 0xfa, 0x12, 0x0d, 0xca, 0x34, 0x01, 0x5f, 0x99, 0xb0, 0xb4, 0x8d, 0xb2, 0xc7,
        0x5a, 0x41, 0x25, 0x28, 0xc0, 0x3e, 0x1f, 0xda, 0x80, 0xad, 0xf3, 0xb2, 0xe9, 0x9b, 0xe4,
        0x72, 0x45, 0x22, 0xf6, 0xdf, 0x9d, 0x3f, 0x33, 0xd4, 0x62, 0xd0, 0x92, 0x43, 0x0e, 0x40,
        0xf4, 0x50, 0xe3, 0x42, 0x6f, 0x02, 0xd6, 0x3f, 0x46, 0x47, 0x18, 0x35, 0x97, 0x05, 0x8e,
        0x3f, 0x30, 0xe9, 0x2c, 0x48, 0x0e, 0xf9, 0x09, 0x40, 0xeb, 0x2a, 0xde, 0x90, 0x7b, 0xcf,
        0xd7, 0x3f, 0xd5, 0x2f, 0xcd, 0xbf, 0x00, 0x56, 0x95, 0x3f, 0xc0, 0xaa, 0x84, 0xf8, 0xe9,
        0x52, 0x14, 0x40, 0x20, 0x84, 0x3e, 0x2c, 0x15, 0x2e, 0xd2, 0x3f, 0x92, 0x5c, 0xa3, 0x39,
    };
    uavsim_vehicle_params_t p;
    s_params (&p, s_route, S_ROUTE_N);
    p.deviation_m = 10;
    p.seed = 5;
    uavsim_vehicle_t *b = s_new (&p);
    for (int i = 0; i < 77; i++)
        uavsim_vehicle_step (b, i * DT_S, DT_S);
    uavsim_vehicle_state_t before = s_state (b);
    char err[256] = "";
    assert_int_equal (uavsim_vehicle_restore (b, old, sizeof old, err, sizeof err), -EPROTO);
    assert_string_equal (err, "not a vehicle checkpoint: it begins \"UVEH\", not \"UVHC\" "
                              "(another kind of file, or one saved before mscgs's common "
                              "checkpoint format)");
    uint8_t v2[188] = {0};
    memcpy (v2, old, 176);
    v2[4] = 2; // format 2: 8 bytes of halt and the CRC after the same fields
    uint32_t crc = cgs_crc32 (v2, 184);
    for (int j = 0; j < 4; j++)
        v2[184 + j] = (uint8_t)(crc >> (8 * j));
    assert_int_equal (uavsim_vehicle_restore (b, v2, sizeof v2, err, sizeof err), -EPROTO);
    uavsim_vehicle_state_t after = s_state (b);
    assert_true (s_same (&before, &after));
    uavsim_vehicle_destroy (&b);
}

/* Random routes with random halts: the limits hold on every step, every halt
 * is on its point, and a stop route finishes on its last point within the
 * bound of test_random_routes plus its halts. */
static void test_halt_random (void **state)
{
    (void)state;
    uint64_t rs = 77;
    int halts_seen = 0, finished = 0;
    for (int trial = 0; trial < 150; trial++) {
        uavsim_vehicle_point_t pts[8];
        double halts[8] = {0};
        size_t n = 2 + (size_t)s_rand (&rs, 0, 6.999);
        double e = 0, nn = 0, hd = s_rand (&rs, 0, 2 * M_PI), bare_s = 0, halt_sum = 0;
        uavsim_vehicle_params_t p;
        uavsim_vehicle_params_defaults (&p);
        p.speed_mps = s_rand (&rs, 1, 20);
        p.end = (uavsim_vehicle_end_t)(trial % 3);
        for (size_t i = 0; i < n; i++) {
            pts[i] =
                (uavsim_vehicle_point_t){e, nn, s_rand (&rs, 0, 1) < 0.5 ? 0 : s_rand (&rs, 1, 20)};
            bool stop_end = p.end == UAVSIM_VEHICLE_END_STOP && (i == 0 || i == n - 1);
            if (!stop_end && s_rand (&rs, 0, 1) < 0.4)
                halt_sum += halts[i] = s_rand (&rs, 0.05, 30);
            double len = s_rand (&rs, 0, 1) < 0.2 ? s_rand (&rs, 0.5, 10) : s_rand (&rs, 10, 1000);
            hd += s_rand (&rs, -M_PI, M_PI);
            e += len * sin (hd);
            nn += len * cos (hd);
            if (i + 1 < n)
                bare_s += hypot (e - pts[i].e_m, nn - pts[i].n_m) /
                          (pts[i].speed_mps > 0 ? pts[i].speed_mps : p.speed_mps);
        }
        p.points = pts;
        p.n_points = n;
        p.halt_s = halts;
        p.deviation_m = s_rand (&rs, 0, 1) < 0.3 ? 0 : s_rand (&rs, 0, 60);
        p.seed = (uint64_t)trial;
        p.turn_rate_dps = s_rand (&rs, 10, 60);
        p.lat_accel_mps2 = s_rand (&rs, 0.5, 4);
        p.accel_mps2 = s_rand (&rs, 0.5, 3);
        p.decel_mps2 = s_rand (&rs, 0.5, 4);
        double dt = s_rand (&rs, 0.05, 0.1);
        double vmax = p.speed_mps;
        for (size_t i = 0; i < n; i++)
            vmax = fmax (vmax, pts[i].speed_mps);
        uavsim_vehicle_t *v = s_new (&p);
        uavsim_vehicle_state_t prev = s_state (v);
        double bound_s =
            2 * bare_s + halt_sum +
            (double)n * (vmax / p.accel_mps2 + vmax / p.decel_mps2 + 180 / p.turn_rate_dps) + 10;
        int steps = (int)(fmin (bound_s, 3000) / dt);
        for (int i = 0; i < steps; i++) {
            assert_int_equal (uavsim_vehicle_step (v, i * dt, dt), 0);
            uavsim_vehicle_state_t s = s_state (v);
            assert_true (s.speed_mps >= 0 && s.speed_mps <= vmax + 1e-9);
            double dh = fabs (s_dheading (prev.heading_deg, s.heading_deg));
            assert_true (dh <= p.turn_rate_dps * dt * (1 + 1e-9));
            if (s.halted) {
                int at = s.direction > 0 ? s.leg : (s.leg + 1) % (int)n;
                assert_true (halts[at] > 0 && s.halt_left_s <= halts[at]);
                assert_near (s.e_m, pts[at].e_m, 1e-9);
                assert_near (s.n_m, pts[at].n_m, 1e-9);
                assert_true (s.speed_mps == 0);
                halts_seen += !prev.halted;
            }
            prev = s;
        }
        if (p.end == UAVSIM_VEHICLE_END_STOP) {
            if (!prev.finished)
                fail_msg ("trial %d: not finished after %.0f s", trial, steps * dt);
            // (To the last bit only where the last leg starts without an arc: the
            // arc's length is taken off the element's and back.)
            assert_near (prev.e_m, pts[n - 1].e_m, 1e-9);
            assert_near (prev.n_m, pts[n - 1].n_m, 1e-9);
            finished++;
        }
        uavsim_vehicle_destroy (&v);
    }
    print_message ("150 random routes with halts: %d halts seen, %d stop routes finished\n",
                   halts_seen, finished);
    assert_true (halts_seen > 100 && finished == 50);
}

int main (void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test (test_bad_params),
        cmocka_unit_test (test_arrival_times),
        cmocka_unit_test (test_turn_rate_and_corners),
        cmocka_unit_test (test_heights_follow_terrain),
        cmocka_unit_test (test_start_time),
        cmocka_unit_test (test_end_stop),
        cmocka_unit_test (test_end_loop),
        cmocka_unit_test (test_end_reverse),
        cmocka_unit_test (test_wander_seeded),
        cmocka_unit_test (test_random_routes),
        cmocka_unit_test (test_save_restore),
        cmocka_unit_test (test_restore_damaged),
        cmocka_unit_test (test_halt_params),
        cmocka_unit_test (test_halt_on_point),
        cmocka_unit_test (test_halt_on_corner),
        cmocka_unit_test (test_halt_loop),
        cmocka_unit_test (test_halt_reverse),
        cmocka_unit_test (test_halt_save_restore),
        cmocka_unit_test (test_restore_old_formats_refused),
        cmocka_unit_test (test_halt_random),
    };
    return cmocka_run_group_tests (tests, NULL, NULL);
}
