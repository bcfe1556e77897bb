/* test_uavsim_uav — the UAV flight model against theory: the radius of a
 * steady bank-limited turn is V²/(g·tan(bank)) (circle fitted to the flown
 * track), a loiter orbit is captured from outside and inside and held at its
 * radius in the commanded direction, L1 guidance holds a straight leg to a few
 * metres after an offset, angled start, a route is flown point by point and
 * ends in a loiter over its last point, altitude above a sloped terrain climbs
 * no faster than the limit and settles, tasks replace each other, airspeed
 * changes at its limited rate, and a saved state continues bit-identically.
 * Needs -Iservices/uavsim (and -Icommon) on the include path. */
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

#include "uavsim_uav.h"
#include "cgs_ckpt.h"
#include "cgs_util.h"
#include "test_util.h"

#define PI   3.14159265358979323846
#define G    9.80665
#define DT_S 0.1 // the service's step
// A UAV checkpoint's payload without its route (uavsim_uav.c).
#define S_PAYLOAD_FIXED (11 * 8 + 1 + 8 + 5 + 5 * 8 + 4 + 4)

/* --- helpers ------------------------------------------------------------------- */

static uavsim_uav_model_t *s_uav (const uavsim_uav_params_t *p, double e, double n, double u,
                                  double heading_deg, double v, double agl)
{
    uavsim_uav_init_t init = {
        .position = {e, n, u},
        .heading_deg = heading_deg,
        .airspeed_mps = v,
        .agl_m = agl,
        .loiter_radius_m = 0,
        .loiter_clockwise = true,
    };
    uavsim_uav_model_t *uav = uavsim_uav_new (p, &init);
    assert_non_null (uav);
    return uav;
}

static uavsim_uav_state_t s_st (const uavsim_uav_model_t *uav)
{
    uavsim_uav_state_t s;
    uavsim_uav_state (uav, &s);
    return s;
}

/* Step for t_s seconds over flat ground at height 0. */
static void s_fly (uavsim_uav_model_t *uav, double t_s)
{
    long n = lround (t_s / DT_S);
    for (long i = 0; i < n; i++)
        assert_int_equal (uavsim_uav_step (uav, DT_S, 0), 0);
}

/* Least-squares circle (Kasa fit) through points; radius and RMS residual. */
typedef struct {
    double sx, sy, sxx, syy, sxy, sxz, syz, sz;
    double x0, y0;
    long n;
    double xs[20000], ys[20000];
} s_fit_t;

static void s_fit_add (s_fit_t *f, double x, double y)
{
    assert_true (f->n < 20000);
    f->xs[f->n] = x;
    f->ys[f->n] = y;
    f->n++;
}

static double s_fit (const s_fit_t *f, double *ret_ce, double *ret_cn, double *ret_rms)
{
    // Centre the data for conditioning, then solve the 3x3 normal equations of
    // x² + y² + D x + E y + F = 0 by Cramer's rule.
    double mx = 0, my = 0;
    for (long i = 0; i < f->n; i++) {
        mx += f->xs[i];
        my += f->ys[i];
    }
    mx /= f->n;
    my /= f->n;
    double a[3][3] = {{0}}, b[3] = {0};
    for (long i = 0; i < f->n; i++) {
        double x = f->xs[i] - mx, y = f->ys[i] - my, z = -(x * x + y * y);
        double v[3] = {x, y, 1};
        for (int r = 0; r < 3; r++) {
            for (int c = 0; c < 3; c++)
                a[r][c] += v[r] * v[c];
            b[r] += v[r] * z;
        }
    }
    double det = a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) -
                 a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
                 a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
    double sol[3];
    for (int k = 0; k < 3; k++) {
        double m[3][3];
        memcpy (m, a, sizeof m);
        for (int r = 0; r < 3; r++)
            m[r][k] = b[r];
        sol[k] = (m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
                  m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                  m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])) /
                 det;
    }
    double ce = -sol[0] / 2, cn = -sol[1] / 2;
    double r = sqrt (ce * ce + cn * cn - sol[2]);
    double ss = 0;
    for (long i = 0; i < f->n; i++) {
        double d = hypot (f->xs[i] - mx - ce, f->ys[i] - my - cn) - r;
        ss += d * d;
    }
    *ret_ce = ce + mx;
    *ret_cn = cn + my;
    *ret_rms = sqrt (ss / f->n);
    return r;
}

/* Signed angular momentum about c: positive anticlockwise seen from above. */
static double s_circulation (const uavsim_uav_state_t *s, double ce, double cn)
{
    double we = s->position.e_m - ce, wn = s->position.n_m - cn;
    return we * s->velocity.n_m - wn * s->velocity.e_m;
}

/* --- turns --------------------------------------------------------------------- */

/* Loiter about a point far behind: the UAV turns about 150° at the bank limit
 * toward the orbit's tangent point before the L1 law eases off. The part flown at the limit is an
 * arc of radius V²/(g·tan(bank limit)): checked by a circle fitted to the flown track and by V over
 * the course rate. */
static void s_check_turn (double v, double bank_deg)
{
    uavsim_uav_params_t p;
    uavsim_uav_params_defaults (&p);
    p.bank_limit_deg = bank_deg;
    uavsim_uav_model_t *uav = s_uav (&p, 0, 0, 1000, 0, v, 1000);
    assert_int_equal (uavsim_uav_loiter (uav, (cgs_enu_t){0, -30000, 0}, 1000, false), 0);
    double expect = v * v / (G * tan (bank_deg * PI / 180));
    assert_near (uavsim_uav_min_turn_radius (uav, v), expect, 1e-9);

    static s_fit_t f;
    memset (&f, 0, sizeof f);
    double turned = 0, t_s = 0;
    for (int i = 0; i < 1200; i++) {
        uavsim_uav_state_t s0 = s_st (uav);
        assert_int_equal (uavsim_uav_step (uav, DT_S, 0), 0);
        uavsim_uav_state_t s1 = s_st (uav);
        assert_near (s1.airspeed_mps, v, 1e-9);
        assert_true (fabs (s1.roll_deg) <= bank_deg + 1e-9);
        // Steps that start and end at the bank limit.
        if (fabs (s0.roll_deg) >= bank_deg - 1e-9 && fabs (s1.roll_deg) >= bank_deg - 1e-9) {
            if (f.n == 0)
                s_fit_add (&f, s0.position.e_m, s0.position.n_m);
            s_fit_add (&f, s1.position.e_m, s1.position.n_m);
            double d = s1.heading_deg - s0.heading_deg;
            d -= 360 * floor (d / 360 + 0.5);
            turned += d;
            t_s += DT_S;
        } else if (f.n > 0) {
            break; // the turn is over: one arc only
        }
    }
    // A long arc, turning left: the anticlockwise orbit's tangent point lies west.
    assert_true (turned < -120);
    double ce, cn, rms;
    double r_fit = s_fit (&f, &ce, &cn, &rms);
    double r_rate = v / (fabs (turned) * PI / 180 / t_s); // V / course rate
    double err_fit = fabs (r_fit - expect) / expect, err_rate = fabs (r_rate - expect) / expect;
    printf ("  turn V=%g bank=%g over %.0f deg: theory %.3f m, fitted %.3f m (%.4f%%, rms "
            "%.2e m), V/course-rate %.3f m (%.4f%%)\n",
            v, bank_deg, turned, expect, r_fit, 100 * err_fit, rms, r_rate, 100 * err_rate);
    assert_true (err_fit < 0.02);
    assert_true (err_rate < 0.02);
    assert_true (rms < 0.001 * expect); // a circle, not a wobble
    uavsim_uav_destroy (&uav);
    assert_null (uav);
}

static void test_turn_radius (void **state)
{
    (void)state;
    s_check_turn (30, 30);
    s_check_turn (50, 45);
    s_check_turn (22, 20);
}

/* --- loiter -------------------------------------------------------------------- */

/* Loiter about (ce, cn) from (e, n): once captured the distance from the
 * centre stays within 5% of the radius, circulating the commanded way. */
static void s_check_loiter (double e, double n, double heading, double ce, double cn, double r,
                            bool cw)
{
    uavsim_uav_params_t p;
    uavsim_uav_params_defaults (&p);
    uavsim_uav_model_t *uav = s_uav (&p, e, n, 500, heading, 35, 500);
    assert_int_equal (uavsim_uav_loiter (uav, (cgs_enu_t){ce, cn, 0}, r, cw), 0);
    assert_int_equal (s_st (uav).mode, UAVSIM_UAV_MODE_TRANSIT);
    s_fly (uav, 400);
    assert_int_equal (s_st (uav).mode, UAVSIM_UAV_MODE_LOITER);
    double worst = 0, sum = 0;
    int n_s = 0;
    for (int i = 0; i < 4000; i++) { // 400 s: more than two orbits
        uavsim_uav_state_t s = s_st (uav);
        double d = hypot (s.position.e_m - ce, s.position.n_m - cn);
        worst = fmax (worst, fabs (d - r) / r);
        sum += d;
        n_s++;
        double c = s_circulation (&s, ce, cn);
        assert_true (cw ? c < 0 : c > 0);
        assert_int_equal (s.mode, UAVSIM_UAV_MODE_LOITER);
        assert_int_equal (uavsim_uav_step (uav, DT_S, 0), 0);
    }
    printf ("  loiter from (%g, %g) %s r=%g: mean radius %.6f m, worst error %.2e%%\n", e, n,
            cw ? "cw" : "acw", r, sum / n_s, 100 * worst);
    assert_true (worst < 0.05);
    uavsim_uav_destroy (&uav);
}

static void test_loiter_capture_and_hold (void **state)
{
    (void)state;
    s_check_loiter (-4000, 1000, 0, 0, 0, 1000, true);      // from outside, clockwise
    s_check_loiter (-4000, 1000, 0, 0, 0, 1000, false);     // from outside, anticlockwise
    s_check_loiter (0, 0, 45, 0, 0, 1000, true);            // from the centre
    s_check_loiter (300, -200, 200, 0, 0, 1000, false);     // from inside
    s_check_loiter (5000, 5000, 90, 1000, 2000, 600, true); // heading away, tighter orbit
}

/* --- straight legs ------------------------------------------------------------- */

/* Start off the leg P0 -> P1 (the east axis), at an angle, with P0 already
 * reached: the cross-track error settles under 10 m. */
static void s_check_leg (double e, double n, double heading, double switch_m)
{
    uavsim_uav_params_t p;
    uavsim_uav_params_defaults (&p);
    p.switch_distance_m = switch_m; // so that P0 counts as reached at once
    uavsim_uav_model_t *uav = s_uav (&p, e, n, 500, heading, 40, 500);
    cgs_enu_t pts[] = {{0, 0, 0}, {40000, 0, 0}};
    assert_int_equal (uavsim_uav_route (uav, pts, 2, true, 0, true), 0);
    assert_int_equal (s_st (uav).route_index, 1);
    double peak = 0, steady = 0;
    for (int i = 0; i < 3000; i++) { // 300 s
        assert_int_equal (uavsim_uav_step (uav, DT_S, 0), 0);
        double xt = fabs (s_st (uav).position.n_m);
        if (i < 1500)
            peak = fmax (peak, xt);
        else
            steady = fmax (steady, xt); // after 150 s
    }
    uavsim_uav_state_t s = s_st (uav);
    assert_int_equal (s.route_index, 1);
    assert_near (s.heading_deg, 90, 0.5);
    printf ("  leg from (%g, %g) heading %g: start offset %g m, peak %.1f m, steady %.2e m\n", e, n,
            heading, fabs (n), peak, steady);
    assert_true (steady < 10);
    uavsim_uav_destroy (&uav);
}

static void test_straight_leg_cross_track (void **state)
{
    (void)state;
    s_check_leg (-200, 600, 60, 1000);     // 600 m left of the leg, 30° across it
    s_check_leg (0, -2000, 200, 3000);     // 2 km right, heading away from it
    s_check_leg (100, 150, 90 + 40, 1000); // near, crossing at 40°
}

/* --- routes -------------------------------------------------------------------- */

/* Fly a route with sharp turns: each point is reached in order, within the
 * switching distance (plus a few metres of tracking error), then the UAV
 * loiters about the last point at the tasked radius and direction. */
static void s_check_route (double switch_m, double expect_best_m)
{
    uavsim_uav_params_t p;
    uavsim_uav_params_defaults (&p);
    p.switch_distance_m = switch_m;
    uavsim_uav_model_t *uav = s_uav (&p, 0, 0, 800, 90, 40, 800);
    cgs_enu_t pts[] = {{4000, 0, 0}, {4000, 4000, 0}, {-1000, 3000, 0}, {2000, -2000, 0}};
    size_t np = sizeof pts / sizeof pts[0];
    assert_int_equal (uavsim_uav_route (uav, pts, np, true, 800, false), 0);
    uavsim_uav_state_t s = s_st (uav);
    assert_int_equal (s.mode, UAVSIM_UAV_MODE_ROUTE);
    assert_int_equal (s.route_count, np);
    assert_int_equal (s.route_index, 0);
    size_t n_pts;
    const cgs_enu_t *rp = uavsim_uav_route_points (uav, &n_pts);
    assert_int_equal (n_pts, np);
    assert_true (rp[2].e_m == -1000 && rp[2].n_m == 3000);

    double best[4] = {INFINITY, INFINITY, INFINITY, INFINITY};
    size_t index = 0;
    double t_done = -1;
    for (int i = 0; i < 12000 && t_done < 0; i++) {
        assert_int_equal (uavsim_uav_step (uav, DT_S, 0), 0);
        s = s_st (uav);
        if (index < np)
            best[index] = fmin (best[index], hypot (s.position.e_m - pts[index].e_m,
                                                    s.position.n_m - pts[index].n_m));
        if (s.route_count == 0) { // finished: loitering about the last point
            assert_int_equal (index, np - 1);
            t_done = (i + 1) * DT_S;
        } else {
            assert_true (s.route_index == index || s.route_index == index + 1); // in order
            if (s.route_index == index + 1)
                assert_true (best[index] <= expect_best_m); // reached close by
            index = s.route_index;
        }
    }
    assert_true (t_done > 0);
    printf ("  route (switch at %g m) done at %.1f s; closest approaches %.2f %.2f %.2f %.2f m\n",
            switch_m, t_done, best[0], best[1], best[2], best[3]);
    for (size_t k = 0; k < np; k++)
        assert_true (best[k] <= expect_best_m);

    // Then the loiter about the last point, anticlockwise, radius 800.
    s = s_st (uav);
    assert_true (s.loiter_center.e_m == 2000 && s.loiter_center.n_m == -2000);
    assert_near (s.loiter_radius_m, 800, 0);
    assert_false (s.loiter_clockwise);
    assert_null (uavsim_uav_route_points (uav, &n_pts));
    s_fly (uav, 300);
    assert_int_equal (s_st (uav).mode, UAVSIM_UAV_MODE_LOITER);
    double worst = 0;
    for (int i = 0; i < 3000; i++) {
        s = s_st (uav);
        double d = hypot (s.position.e_m - 2000, s.position.n_m + 2000);
        worst = fmax (worst, fabs (d - 800) / 800);
        assert_true (s_circulation (&s, 2000, -2000) > 0);
        s_fly (uav, DT_S);
    }
    printf ("  end loiter: worst radius error %.2e%%\n", 100 * worst);
    assert_true (worst < 0.05);
    uavsim_uav_destroy (&uav);
}

static void test_route_then_loiter (void **state)
{
    (void)state;
    s_check_route (50, 55); // the default: turns begin 50 m short of each point
    s_check_route (0, 5);   // bisector only: flies over each point
}

/* The step the service uses is accurate: the same route flown at 0.1 s and at
 * 0.01 s stays within a few metres. */
static void test_step_size (void **state)
{
    (void)state;
    uavsim_uav_params_t p;
    uavsim_uav_params_defaults (&p);
    uavsim_uav_model_t *a = s_uav (&p, 0, 0, 800, 90, 40, 800);
    uavsim_uav_model_t *b = s_uav (&p, 0, 0, 800, 90, 40, 800);
    cgs_enu_t pts[] = {{4000, 0, 0}, {4000, 4000, 0}, {-1000, 3000, 0}, {2000, -2000, 0}};
    assert_int_equal (uavsim_uav_route (a, pts, 4, true, 800, false), 0);
    assert_int_equal (uavsim_uav_route (b, pts, 4, true, 800, false), 0);
    double worst = 0;
    for (int i = 0; i < 8000; i++) { // 800 s: the route and the loiter
        assert_int_equal (uavsim_uav_step (a, 0.1, 0), 0);
        for (int k = 0; k < 10; k++)
            assert_int_equal (uavsim_uav_step (b, 0.01, 0), 0);
        uavsim_uav_state_t sa = s_st (a), sb = s_st (b);
        worst = fmax (worst,
                      hypot (sa.position.e_m - sb.position.e_m, sa.position.n_m - sb.position.n_m));
    }
    printf ("  dt 0.1 s vs 0.01 s: largest separation %.3f m\n", worst);
    assert_true (worst < 5);
    uavsim_uav_destroy (&a);
    uavsim_uav_destroy (&b);
}

static void test_goto_and_fly_on (void **state)
{
    (void)state;
    uavsim_uav_params_t p;
    uavsim_uav_params_defaults (&p);
    uavsim_uav_model_t *uav = s_uav (&p, 0, 0, 800, 0, 40, 800);
    // Go to a point behind: turn, fly over it, then loiter about it.
    assert_int_equal (uavsim_uav_goto (uav, (cgs_enu_t){-3000, -3000, 0}, 0, true), 0);
    uavsim_uav_state_t s = s_st (uav);
    assert_int_equal (s.mode, UAVSIM_UAV_MODE_TRANSIT);
    assert_int_equal (s.route_count, 1);
    double best = INFINITY;
    for (int i = 0; i < 2000 && s_st (uav).route_count; i++) {
        s_fly (uav, DT_S);
        s = s_st (uav);
        best = fmin (best, hypot (s.position.e_m + 3000, s.position.n_m + 3000));
    }
    assert_int_equal (s_st (uav).route_count, 0);
    assert_true (best <= p.switch_distance_m + 5);
    s_fly (uav, 400);
    s = s_st (uav);
    assert_int_equal (s.mode, UAVSIM_UAV_MODE_LOITER);
    assert_near (hypot (s.position.e_m + 3000, s.position.n_m + 3000), p.loiter_radius_m,
                 0.05 * p.loiter_radius_m);
    assert_true (s_circulation (&s, -3000, -3000) < 0);

    // A route without the loiter flies on along its last leg.
    cgs_enu_t pts[] = {{s.position.e_m + 2000, s.position.n_m, 0},
                       {s.position.e_m + 2000, s.position.n_m + 3000, 0}};
    assert_int_equal (uavsim_uav_route (uav, pts, 2, false, 0, true), 0);
    s_fly (uav, 600);
    s = s_st (uav);
    assert_int_equal (s.mode, UAVSIM_UAV_MODE_ROUTE);
    assert_int_equal (s.route_index, 2);
    assert_near (s.position.e_m, pts[1].e_m, 10);
    assert_true (s.position.n_m > pts[1].n_m + 10000);
    assert_near (fmod (s.heading_deg + 180, 360), 180, 0.5); // north
    uavsim_uav_destroy (&uav);
}

/* --- altitude ------------------------------------------------------------------ */

static double s_slope (double e, double n)
{
    return 100 + 0.04 * e + 0.03 * n;
}

static void test_altitude_over_slope (void **state)
{
    (void)state;
    uavsim_uav_params_t p;
    uavsim_uav_params_defaults (&p);
    uavsim_uav_model_t *uav = s_uav (&p, 1000, 0, s_slope (1000, 0) + 300, 0, 35, 300);
    assert_int_equal (uavsim_uav_loiter (uav, (cgs_enu_t){0, 0, 0}, 1000, true), 0);
    assert_int_equal (uavsim_uav_set_altitude (uav, 800), 0);
    double max_rate = 0, worst = 0, u_prev = s_st (uav).position.u_m;
    double t_reach = -1;
    for (int i = 0; i < 6000; i++) { // 600 s
        uavsim_uav_state_t s = s_st (uav);
        double h = s_slope (s.position.e_m, s.position.n_m);
        assert_int_equal (uavsim_uav_step (uav, DT_S, h), 0);
        s = s_st (uav);
        double rate = (s.position.u_m - u_prev) / DT_S;
        u_prev = s.position.u_m;
        max_rate = fmax (max_rate, fabs (rate));
        assert_true (fabs (s.climb_rate_mps) <= p.climb_rate_mps + 1e-9);
        assert_near (s.velocity.u_m, rate, 1e-6);
        assert_near (s.pitch_deg, asin (rate / s.airspeed_mps) * 180 / PI, 1e-6);
        double agl = s.position.u_m - s_slope (s.position.e_m, s.position.n_m);
        if (t_reach < 0 && agl > 790)
            t_reach = (i + 1) * DT_S;
        if (i >= 3000)
            worst = fmax (worst, fabs (agl - 800));
        if (i == 200) // a climb at the limit while far below
            assert_near (rate, p.climb_rate_mps, 1e-6);
    }
    // 500 m at 5 m/s takes 100 s; the terrain moves under the loiter too.
    printf ("  climb: fastest %.4f m/s, 790 m AGL at %.1f s, settled error %.4f m\n", max_rate,
            t_reach, worst);
    assert_true (max_rate <= p.climb_rate_mps + 1e-9);
    assert_true (t_reach > 490.0 / (p.climb_rate_mps + 0.04 * 35 + 0.03 * 35));
    assert_true (worst < 1.0);

    // Descend: no faster than the limit, settles at the new AGL.
    assert_int_equal (uavsim_uav_set_altitude (uav, 200), 0);
    worst = 0;
    for (int i = 0; i < 6000; i++) {
        uavsim_uav_state_t s = s_st (uav);
        assert_int_equal (uavsim_uav_step (uav, DT_S, s_slope (s.position.e_m, s.position.n_m)), 0);
        s = s_st (uav);
        assert_true (s.climb_rate_mps >= -p.climb_rate_mps - 1e-9);
        if (i >= 3000)
            worst = fmax (worst,
                          fabs (s.position.u_m - s_slope (s.position.e_m, s.position.n_m) - 200));
    }
    printf ("  descent: settled error %.4f m\n", worst);
    assert_true (worst < 1.0);
    uavsim_uav_destroy (&uav);
}

/* --- tasks and speed ----------------------------------------------------------- */

static void test_tasks_replace_and_speed (void **state)
{
    (void)state;
    uavsim_uav_params_t p;
    uavsim_uav_params_defaults (&p);
    uavsim_uav_model_t *uav = s_uav (&p, 0, 0, 500, 0, 30, 500);
    uavsim_uav_state_t s = s_st (uav);
    assert_int_equal (s.task_number, 0);
    assert_int_equal (s.mode, UAVSIM_UAV_MODE_TRANSIT); // at the centre of its start orbit
    assert_near (s.loiter_radius_m, p.loiter_radius_m, 0);

    cgs_enu_t pts[] = {{5000, 0, 0}, {5000, 5000, 0}};
    assert_int_equal (uavsim_uav_route (uav, pts, 2, true, 0, true), 0);
    assert_int_equal (s_st (uav).task_number, 1);
    s_fly (uav, 10);
    // Altitude and speed commands leave the route running.
    assert_int_equal (uavsim_uav_set_altitude (uav, 700), 0);
    assert_int_equal (uavsim_uav_set_speed (uav, 50), 0);
    s = s_st (uav);
    assert_int_equal (s.task_number, 3);
    assert_int_equal (s.mode, UAVSIM_UAV_MODE_ROUTE);
    assert_int_equal (s.route_count, 2);
    assert_near (s.commanded_agl_m, 700, 0);
    assert_near (s.commanded_airspeed_mps, 50, 0);
    // Airspeed at 1 m/s²: 30 -> 35 in 5 s, 50 after 20 s, and no further.
    s_fly (uav, 5);
    assert_near (s_st (uav).airspeed_mps, 35, 1e-9);
    s_fly (uav, 10);
    assert_near (s_st (uav).airspeed_mps, 45, 1e-9);
    s_fly (uav, 10);
    assert_near (s_st (uav).airspeed_mps, 50, 1e-9);
    assert_int_equal (uavsim_uav_set_speed (uav, 25), 0);
    s_fly (uav, 3);
    assert_near (s_st (uav).airspeed_mps, 47, 1e-9);

    // A newer lateral task replaces the route.
    assert_int_equal (uavsim_uav_loiter (uav, (cgs_enu_t){-2000, 0, 0}, 1500, false), 0);
    s = s_st (uav);
    assert_int_equal (s.task_number, 5);
    assert_int_equal (s.route_count, 0);
    assert_int_equal (s.mode, UAVSIM_UAV_MODE_TRANSIT);
    assert_true (s.loiter_center.e_m == -2000 && s.loiter_radius_m == 1500 && !s.loiter_clockwise);
    assert_null (uavsim_uav_route_points (uav, &(size_t){0}));
    // Loiter here centres on the present position.
    assert_int_equal (uavsim_uav_loiter_here (uav, 0, true), 0);
    s = s_st (uav);
    assert_int_equal (s.task_number, 6);
    assert_true (s.loiter_center.e_m == s.position.e_m && s.loiter_center.n_m == s.position.n_m);
    assert_true (s.loiter_clockwise);
    assert_int_equal (uavsim_uav_goto (uav, (cgs_enu_t){0, 9000, 0}, 700, false), 0);
    assert_int_equal (s_st (uav).task_number, 7);

    // Bad tasks are refused and change nothing.
    cgs_enu_t bad[] = {{0, NAN, 0}};
    assert_int_equal (uavsim_uav_set_speed (uav, p.airspeed_max_mps + 1), -EINVAL);
    assert_int_equal (uavsim_uav_set_speed (uav, p.airspeed_min_mps - 1), -EINVAL);
    assert_int_equal (uavsim_uav_set_speed (uav, NAN), -EINVAL);
    assert_int_equal (uavsim_uav_set_altitude (uav, 0), -EINVAL);
    assert_int_equal (uavsim_uav_set_altitude (uav, INFINITY), -EINVAL);
    assert_int_equal (uavsim_uav_set_altitude (uav, UAVSIM_UAV_AGL_MAX_M + 1), -EINVAL);
    assert_int_equal (uavsim_uav_loiter (uav, (cgs_enu_t){0, 0, 0}, -5, true), -EINVAL);
    assert_int_equal (uavsim_uav_loiter (uav, (cgs_enu_t){NAN, 0, 0}, 500, true), -EINVAL);
    assert_int_equal (uavsim_uav_loiter_here (uav, NAN, true), -EINVAL);
    assert_int_equal (uavsim_uav_goto (uav, (cgs_enu_t){INFINITY, 0, 0}, 0, true), -EINVAL);
    assert_int_equal (uavsim_uav_route (uav, pts, 0, true, 0, true), -EINVAL);
    assert_int_equal (uavsim_uav_route (uav, NULL, 2, true, 0, true), -EINVAL);
    assert_int_equal (uavsim_uav_route (uav, bad, 1, true, 0, true), -EINVAL);
    assert_int_equal (uavsim_uav_route (uav, pts, UAVSIM_UAV_ROUTE_MAX + 1, true, 0, true),
                      -EINVAL);
    s = s_st (uav);
    assert_int_equal (s.task_number, 7);
    assert_int_equal (s.mode, UAVSIM_UAV_MODE_TRANSIT);
    assert_true (s.loiter_center.n_m == 9000 && s.loiter_radius_m == 700);
    assert_int_equal (s.route_count, 1);
    uavsim_uav_destroy (&uav);
    uavsim_uav_destroy (&uav); // idempotent
    uavsim_uav_destroy (NULL);
}

/* --- save and restore ---------------------------------------------------------- */

/* Seal a forged frame again: its payload's CRC-32 in the last 4 bytes. */
static void s_reseal (uint8_t *b, size_t len)
{
    uint32_t c = cgs_crc32 (b + CGS_CKPT_HEAD, len - CGS_CKPT_HEAD - CGS_CKPT_TAIL);
    for (int i = 0; i < 4; i++)
        b[len - 4 + i] = (uint8_t)(c >> (8 * i));
}

/* uav's checkpoint, copied into buf (of size bytes). */
static size_t s_save (const uavsim_uav_model_t *uav, uint8_t *buf, size_t size)
{
    uint8_t *b = NULL;
    size_t len = 0;
    assert_int_equal (uavsim_uav_save (uav, &b, &len), 0);
    assert_true (len <= size);
    memcpy (buf, b, len);
    free (b);
    return len;
}

static void test_save_restore (void **state)
{
    (void)state;
    uavsim_uav_params_t p;
    uavsim_uav_params_defaults (&p);
    uavsim_uav_model_t *a = s_uav (&p, 0, 0, s_slope (0, 0) + 400, 10, 35, 400);
    cgs_enu_t pts[] = {{3000, 500, 0}, {3500, 4000, 0}, {0, 2000, 0}};
    assert_int_equal (uavsim_uav_route (a, pts, 3, true, 900, false), 0);
    assert_int_equal (uavsim_uav_set_speed (a, 45), 0);
    assert_int_equal (uavsim_uav_set_altitude (a, 600), 0);
    for (int i = 0; i < 1500; i++) { // mid-route, mid-climb, mid-acceleration... then some
        uavsim_uav_state_t s = s_st (a);
        assert_int_equal (uavsim_uav_step (a, DT_S, s_slope (s.position.e_m, s.position.n_m)), 0);
    }
    assert_int_equal (s_st (a).route_index, 1);

    static uint8_t buf[4096], buf2[4096], buf3[4096];
    size_t len = s_save (a, buf, sizeof buf);
    // The frame: a fixed payload and the route's points.
    assert_int_equal (len, CGS_CKPT_HEAD + S_PAYLOAD_FIXED + 3 * 24 + CGS_CKPT_TAIL);
    assert_memory_equal (buf, "UUAV", 4);

    // Restore into a UAV somewhere else doing something else.
    uavsim_uav_model_t *b = s_uav (&p, -9000, 7000, 3000, 270, 22, 900);
    char err[256] = "";
    assert_int_equal (uavsim_uav_restore (b, buf, len, err, sizeof err), 0);
    assert_int_equal (s_save (b, buf2, sizeof buf2), len);
    assert_memory_equal (buf, buf2, len);

    // Both continue bit-identically through the rest of the route and the loiter.
    for (int i = 0; i < 6000; i++) {
        uavsim_uav_state_t sa = s_st (a), sb = s_st (b);
        assert_memory_equal (&sa, &sb, sizeof sa);
        double h = s_slope (sa.position.e_m, sa.position.n_m);
        assert_int_equal (uavsim_uav_step (a, DT_S, h), 0);
        assert_int_equal (uavsim_uav_step (b, DT_S, h), 0);
    }
    assert_int_equal (s_st (a).route_count, 0); // the route was finished on the way
    size_t la = s_save (a, buf2, sizeof buf2), lb = s_save (b, buf3, sizeof buf3);
    assert_int_equal (la, lb);
    assert_memory_equal (buf2, buf3, la);

    // Damage: every single-bit flip (refused by the frame: magic, version,
    // length, else the checksum), every truncation, trailing bytes.
    size_t before = s_save (b, buf3, sizeof buf3);
    for (size_t i = 0; i < len; i++)
        for (int bit = 0; bit < 8; bit++) {
            buf[i] ^= (uint8_t)(1u << bit);
            int want = i < 4 ? -EPROTO : i < 8 ? -ENOTSUP : i < 16 ? -EINVAL : -EBADMSG;
            assert_int_equal (uavsim_uav_restore (b, buf, len, err, sizeof err), want);
            buf[i] ^= (uint8_t)(1u << bit);
        }
    for (size_t l = 0; l < len; l++)
        assert_int_equal (uavsim_uav_restore (b, buf, l, err, sizeof err), -EINVAL);
    buf[len] = 0;
    assert_int_equal (uavsim_uav_restore (b, buf, len + 1, err, sizeof err), -EINVAL);
    // Well sealed but wrong: version, airspeed, flags, route index past the end.
    const size_t pl = CGS_CKPT_HEAD; // the payload's first byte
    uint8_t forged[4096];
    memcpy (forged, buf, len);
    forged[4] = 2;
    assert_int_equal (uavsim_uav_restore (b, forged, len, err, sizeof err), -ENOTSUP);
    assert_non_null (strstr (err, "another version"));
    memcpy (forged, buf, len);
    forged[pl + 4 * 8 + 7] = 0xC0; // airspeed's sign and exponent: -2.x
    s_reseal (forged, len);
    assert_int_equal (uavsim_uav_restore (b, forged, len, err, sizeof err), -EINVAL);
    assert_non_null (strstr (err, "values no UAV can have"));
    memcpy (forged, buf, len);
    forged[pl + 11 * 8] = 2; // have_terrain neither 0 nor 1
    s_reseal (forged, len);
    assert_int_equal (uavsim_uav_restore (b, forged, len, err, sizeof err), -EINVAL);
    memcpy (forged, buf, len);
    forged[pl + 11 * 8 + 1 + 8 + 5 + 5 * 8 + 4] = 9; // index 9 of 3 points
    s_reseal (forged, len);
    assert_int_equal (uavsim_uav_restore (b, forged, len, err, sizeof err), -EINVAL);
    memcpy (forged, buf, len);
    s_reseal (forged, len); // resealing an intact state changes nothing: still good
    assert_int_equal (uavsim_uav_restore (b, forged, len, err, sizeof err), 0);
    // Back to where b was.
    assert_int_equal (uavsim_uav_restore (b, buf3, before, err, sizeof err), 0);
    assert_int_equal (uavsim_uav_restore (b, NULL, 0, err, sizeof err), -EINVAL);
    assert_int_equal (uavsim_uav_restore (NULL, buf, len, err, sizeof err), -EINVAL);
    // A checkpoint of the format before cgs_ckpt ("UAVS", version 1) is refused.
    memcpy (forged, "UAVS\x01\x00\x00\x00", 8);
    assert_int_equal (uavsim_uav_restore (b, forged, len, err, sizeof err), -EPROTO);
    assert_non_null (strstr (err, "it begins \"UAVS\""));
    // Failed restores left b as it was.
    assert_int_equal (s_save (b, buf2, sizeof buf2), before);
    assert_memory_equal (buf2, buf3, before);
    uavsim_uav_destroy (&a);
    uavsim_uav_destroy (&b);
}

/* --- bad input ----------------------------------------------------------------- */

static void test_bad_parameters (void **state)
{
    (void)state;
    uavsim_uav_params_t d, p;
    uavsim_uav_params_defaults (&d);
    assert_int_equal (uavsim_uav_params_check (&d), 0);
    assert_int_equal (uavsim_uav_params_check (NULL), -EINVAL);
    uavsim_uav_init_t init = {{0, 0, 500}, 0, 30, 500, 0, true};

#define BAD(field, value)                                                                          \
    do {                                                                                           \
        p = d;                                                                                     \
        p.field = (value);                                                                         \
        assert_int_equal (uavsim_uav_params_check (&p), -EINVAL);                                  \
        assert_null (uavsim_uav_new (&p, &init));                                                  \
    } while (0)
    BAD (bank_limit_deg, 0);
    BAD (bank_limit_deg, 85);
    BAD (bank_limit_deg, NAN);
    BAD (roll_rate_dps, 0);
    BAD (roll_rate_dps, -20);
    BAD (climb_rate_mps, 0);
    BAD (climb_rate_mps, 25); // not below the slowest airspeed
    BAD (airspeed_min_mps, 0);
    BAD (airspeed_min_mps, 70); // above the fastest
    BAD (airspeed_max_mps, INFINITY);
    BAD (airspeed_accel_mps2, 0);
    BAD (l1_period_s, 0);
    BAD (l1_damping, 0);
    BAD (l1_damping, 3);
    BAD (altitude_tau_s, -1);
    BAD (loiter_radius_m, 0);
    BAD (loiter_radius_m, 2 * UAVSIM_UAV_RADIUS_MAX_M);
    BAD (switch_distance_m, -1);
    BAD (switch_distance_m, NAN);
#undef BAD

    assert_null (uavsim_uav_new (NULL, &init));
    assert_null (uavsim_uav_new (&d, NULL));
    uavsim_uav_init_t bad = init;
    bad.airspeed_mps = 10; // below the slowest
    assert_null (uavsim_uav_new (&d, &bad));
    bad = init;
    bad.agl_m = 0;
    assert_null (uavsim_uav_new (&d, &bad));
    bad = init;
    bad.position.n_m = NAN;
    assert_null (uavsim_uav_new (&d, &bad));
    bad = init;
    bad.heading_deg = INFINITY;
    assert_null (uavsim_uav_new (&d, &bad));
    bad = init;
    bad.loiter_radius_m = -1;
    assert_null (uavsim_uav_new (&d, &bad));

    uavsim_uav_model_t *uav = uavsim_uav_new (&d, &init);
    assert_non_null (uav);
    assert_int_equal (uavsim_uav_step (uav, 0, 0), -EINVAL);
    assert_int_equal (uavsim_uav_step (uav, -0.1, 0), -EINVAL);
    assert_int_equal (uavsim_uav_step (uav, NAN, 0), -EINVAL);
    assert_int_equal (uavsim_uav_step (uav, 0.1, NAN), -EINVAL);
    assert_int_equal (uavsim_uav_step (NULL, 0.1, 0), -EINVAL);
    uavsim_uav_state_t s = s_st (uav);
    assert_true (s.position.e_m == 0 && s.position.n_m == 0 && s.position.u_m == 500);
    uavsim_uav_destroy (&uav);
}

int main (void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test (test_turn_radius),
        cmocka_unit_test (test_loiter_capture_and_hold),
        cmocka_unit_test (test_straight_leg_cross_track),
        cmocka_unit_test (test_route_then_loiter),
        cmocka_unit_test (test_step_size),
        cmocka_unit_test (test_goto_and_fly_on),
        cmocka_unit_test (test_altitude_over_slope),
        cmocka_unit_test (test_tasks_replace_and_speed),
        cmocka_unit_test (test_save_restore),
        cmocka_unit_test (test_bad_parameters),
    };
    return cmocka_run_group_tests (tests, NULL, NULL);
}
