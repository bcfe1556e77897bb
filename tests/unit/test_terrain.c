/* test_terrain — cgs_terrain against hand-worked values: bilinear heights and
 * normals on small grids, fBm determinism and scaling, exact line of sight
 * (flat ground, a ridge, a saddle that only the in-cell check sees, and a
 * dense-sampling cross-check), and DEMs written by GDAL here (GeoTIFF in
 * EPSG:4326, ESRI ASCII grid in UTM) read back through the local frame. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <dirent.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <cpl_conv.h>
#include <gdal.h>
#include <ogr_srs_api.h>

#include "cgs_geo.h"
#include "cgs_terrain.h"
#include "test_util.h"

#define EARTH_R_M 6.3e6 // a lower bound on the earth's radii of curvature, metres

/* --- small grids --------------------------------------------------------------- */

/* 3 x 2 nodes at 10 m from (100, 200):
 *   row 1 (n = 210):  20  40  50
 *   row 0 (n = 200):   0  10  30                                          */
static cgs_terrain_t *s_small_grid (void)
{
    const float h[] = {0, 10, 30, 20, 40, 50};
    cgs_terrain_t *t = cgs_terrain_new_grid (3, 2, 100, 200, 10, h);
    assert_non_null (t);
    return t;
}

static double s_h (const cgs_terrain_t *t, double e, double n)
{
    double h = NAN;
    assert_int_equal (cgs_terrain_height (t, e, n, &h), 0);
    return h;
}

static void test_grid_bilinear (void **state)
{
    (void)state;
    cgs_terrain_t *t = s_small_grid ();
    assert_int_equal (cgs_terrain_cols (t), 3);
    assert_int_equal (cgs_terrain_rows (t), 2);
    assert_true (cgs_terrain_resolution (t) == 10);
    double e0, n0, e1, n1, lo, hi;
    cgs_terrain_bounds (t, &e0, &n0, &e1, &n1);
    assert_true (e0 == 100 && n0 == 200 && e1 == 120 && n1 == 210);
    cgs_terrain_height_range (t, &lo, &hi);
    assert_true (lo == 0 && hi == 50);
    assert_true (cgs_terrain_node (t, 2, 1) == 50);
    assert_true (cgs_terrain_node (t, 1, 0) == 10);

    // Nodes, including the far edges and corner.
    assert_near (s_h (t, 100, 200), 0, 1e-12);
    assert_near (s_h (t, 110, 200), 10, 1e-12);
    assert_near (s_h (t, 120, 200), 30, 1e-12);
    assert_near (s_h (t, 100, 210), 20, 1e-12);
    assert_near (s_h (t, 110, 210), 40, 1e-12);
    assert_near (s_h (t, 120, 210), 50, 1e-12);
    // Cell midpoints: the mean of the four corners.
    assert_near (s_h (t, 105, 205), (0 + 10 + 20 + 40) / 4.0, 1e-12);
    assert_near (s_h (t, 115, 205), (10 + 30 + 40 + 50) / 4.0, 1e-12);
    // Edge midpoint: the mean of its two nodes.
    assert_near (s_h (t, 115, 210), 45, 1e-12);
    // (102, 207): u = 0.2, v = 0.7 -> (0*.8 + 10*.2)*.3 + (20*.8 + 40*.2)*.7 = 17.4.
    assert_near (s_h (t, 102, 207), 17.4, 1e-12);

    // Outside: -ERANGE, and the output is left alone.
    const double out[][2] = {{99.999, 205}, {120.001, 205}, {105, 199.999}, {105, 210.5}};
    for (size_t i = 0; i < sizeof out / sizeof out[0]; i++) {
        double h = 1234;
        assert_int_equal (cgs_terrain_height (t, out[i][0], out[i][1], &h), -ERANGE);
        assert_true (h == 1234);
    }
    double h = 1234;
    assert_int_equal (cgs_terrain_height (t, NAN, 205, &h), -ERANGE);
    assert_true (h == 1234);

    // Clamped: the nearest edge point.
    assert_near (cgs_terrain_height_clamped (t, 90, 190), 0, 1e-12);
    assert_near (cgs_terrain_height_clamped (t, 500, 500), 50, 1e-12);
    assert_near (cgs_terrain_height_clamped (t, 115, 1000), 45, 1e-12);
    assert_near (cgs_terrain_height_clamped (t, 102, 207), 17.4, 1e-12);
    cgs_terrain_destroy (&t);
    assert_null (t);
}

/* A 5 x 5 grid from (-20, -20) at 10 m spacing with h = a + b e + c n. */
static cgs_terrain_t *s_plane (double a, double b, double c)
{
    float h[25];
    for (int r = 0; r < 5; r++)
        for (int col = 0; col < 5; col++)
            h[r * 5 + col] = (float)(a + b * (-20 + 10 * col) + c * (-20 + 10 * r));
    cgs_terrain_t *t = cgs_terrain_new_grid (5, 5, -20, -20, 10, h);
    assert_non_null (t);
    return t;
}

static void s_check_normal (cgs_enu_t v, double x, double y, double z)
{
    double len = sqrt (x * x + y * y + z * z);
    assert_near (v.e_m, x / len, 1e-9);
    assert_near (v.n_m, y / len, 1e-9);
    assert_near (v.u_m, z / len, 1e-9);
}

static void test_grid_normal (void **state)
{
    (void)state;
    // h = 0.1 e: normal along (-0.1, 0, 1), inside, at edges and corners, outside.
    cgs_terrain_t *t = s_plane (0, 0.1, 0);
    const double at[][2] = {{0, 0}, {3, -7}, {-20, -20}, {20, 5}, {-20, 20}, {50, -90}};
    for (size_t i = 0; i < sizeof at / sizeof at[0]; i++)
        s_check_normal (cgs_terrain_normal (t, at[i][0], at[i][1]), -0.1, 0, 1);
    cgs_terrain_destroy (&t);
    // h = 7 - 0.2 n + 0.05 e: normal along (-0.05, 0.2, 1).
    t = s_plane (7, 0.05, -0.2);
    for (size_t i = 0; i < sizeof at / sizeof at[0]; i++)
        s_check_normal (cgs_terrain_normal (t, at[i][0], at[i][1]), -0.05, 0.2, 1);
    // Flat in between: a sloped plane gives its height exactly, too.
    assert_near (s_h (t, 3, -7), 7 - 0.2 * -7 + 0.05 * 3, 1e-5);
    cgs_terrain_destroy (&t);
}

static void test_grid_bad (void **state)
{
    (void)state;
    const float h[6] = {0, 1, 2, 3, 4, 5};
    const float bad[6] = {0, 1, NAN, 3, 4, 5};
    assert_null (cgs_terrain_new_grid (1, 6, 0, 0, 10, h));
    assert_null (cgs_terrain_new_grid (6, 1, 0, 0, 10, h));
    assert_null (cgs_terrain_new_grid (3, 0, 0, 0, 10, h));
    assert_null (cgs_terrain_new_grid (3, 2, 0, 0, 0, h));
    assert_null (cgs_terrain_new_grid (3, 2, 0, 0, -1, h));
    assert_null (cgs_terrain_new_grid (3, 2, 0, 0, NAN, h));
    assert_null (cgs_terrain_new_grid (3, 2, INFINITY, 0, 10, h));
    assert_null (cgs_terrain_new_grid (3, 2, 0, 0, 10, NULL));
    assert_null (cgs_terrain_new_grid (3, 2, 0, 0, 10, bad));
    assert_null (cgs_terrain_new_grid (1 << 14, 1 << 13, 0, 0, 10, h)); // 2^27 nodes
    cgs_terrain_t *t = NULL;
    cgs_terrain_destroy (&t);
    cgs_terrain_destroy (NULL);
}

/* --- fBm ------------------------------------------------------------------------- */

static cgs_terrain_fbm_t s_small_fbm (uint64_t seed)
{
    cgs_terrain_fbm_t p;
    cgs_terrain_fbm_defaults (&p);
    p.seed = seed;
    p.size_m = 3000;
    p.resolution_m = 30;
    p.feature_m = 1000;
    return p;
}

static void test_fbm_deterministic (void **state)
{
    (void)state;
    cgs_terrain_fbm_t p = s_small_fbm (42);
    cgs_terrain_t *a = cgs_terrain_new_fbm (&p);
    cgs_terrain_t *b = cgs_terrain_new_fbm (&p);
    p.seed = 43;
    cgs_terrain_t *c = cgs_terrain_new_fbm (&p);
    assert_non_null (a);
    assert_non_null (b);
    assert_non_null (c);
    int n = cgs_terrain_cols (a), differ = 0;
    assert_int_equal (n, 101); // floor(3000 / 30) + 1
    assert_int_equal (cgs_terrain_cols (c), n);
    for (int r = 0; r < n; r++)
        for (int col = 0; col < n; col++) {
            float ha = cgs_terrain_node (a, col, r);
            assert_memory_equal (&ha, &(float){cgs_terrain_node (b, col, r)}, sizeof ha);
            differ += ha != cgs_terrain_node (c, col, r);
        }
    assert_true (differ > n * n * 9 / 10);
    // Pinned values of this seed, bit for bit: the generator is integer
    // hashing and plain IEEE double arithmetic, so every platform and
    // compiler must give these (a change to the generator must update them).
    assert_true (cgs_terrain_node (a, 37, 61) == 0x1.d4e864p+5f); // 58.613472
    assert_true (cgs_terrain_node (a, 0, 0) == 0x1.79fb26p+6f);   // 94.495262
    cgs_terrain_destroy (&a);
    cgs_terrain_destroy (&b);
    cgs_terrain_destroy (&c);
}

static void test_fbm_range_and_shape (void **state)
{
    (void)state;
    cgs_terrain_fbm_t p;
    cgs_terrain_fbm_defaults (&p);
    assert_true (p.size_m == 20000 && p.resolution_m == 30 && p.relief_m == 200 &&
                 p.base_height_m == 0 && p.feature_m == 4000 && p.octaves == 6 &&
                 p.persistence == 0.5);
    cgs_terrain_t *t = cgs_terrain_new_fbm (&p);
    assert_non_null (t);
    // floor(20000 / 30) + 1 = 667 nodes, spanning 666 * 30 = 19980 m about the origin.
    assert_int_equal (cgs_terrain_cols (t), 667);
    assert_int_equal (cgs_terrain_rows (t), 667);
    double e0, n0, e1, n1, lo, hi;
    cgs_terrain_bounds (t, &e0, &n0, &e1, &n1);
    assert_near (e0, -9990, 1e-9);
    assert_near (n0, -9990, 1e-9);
    assert_near (e1, 9990, 1e-9);
    assert_near (n1, 9990, 1e-9);
    cgs_terrain_height_range (t, &lo, &hi);
    assert_true (lo == 0);
    assert_true (hi == 200);
    // It is hilly, not two spikes on a plain: a good spread of heights.
    double sum = 0, sum2 = 0;
    int n = 667 * 667;
    for (int r = 0; r < 667; r++)
        for (int c = 0; c < 667; c++) {
            double h = cgs_terrain_node (t, c, r);
            sum += h;
            sum2 += h * h;
        }
    double sd = sqrt (sum2 / n - (sum / n) * (sum / n));
    assert_true (sd > 15 && sd < 80);
    cgs_terrain_destroy (&t);

    // Base and relief are hit exactly (both representable as floats).
    p = s_small_fbm (7);
    p.base_height_m = 150;
    p.relief_m = 75.5;
    t = cgs_terrain_new_fbm (&p);
    assert_non_null (t);
    cgs_terrain_height_range (t, &lo, &hi);
    assert_true (lo == 150);
    assert_true (hi == 225.5);
    cgs_terrain_destroy (&t);

    // 1000 m at 30 m: floor(33.3) + 1 = 34 nodes, 990 m wide about the origin.
    p.size_m = 1000;
    t = cgs_terrain_new_fbm (&p);
    assert_non_null (t);
    assert_int_equal (cgs_terrain_cols (t), 34);
    assert_int_equal (cgs_terrain_rows (t), 34);
    cgs_terrain_bounds (t, &e0, &n0, &e1, &n1);
    assert_near (e0, -495, 1e-9);
    assert_near (e1, 495, 1e-9);
    cgs_terrain_destroy (&t);

    // No relief: flat at the base height.
    p.relief_m = 0;
    t = cgs_terrain_new_fbm (&p);
    assert_non_null (t);
    cgs_terrain_height_range (t, &lo, &hi);
    assert_true (lo == 150 && hi == 150);
    cgs_terrain_destroy (&t);
}

static void test_fbm_bad (void **state)
{
    (void)state;
    assert_null (cgs_terrain_new_fbm (NULL));
    const cgs_terrain_fbm_t ok = s_small_fbm (1);
    cgs_terrain_fbm_t p;
#define BAD(field, value)                                                                          \
    do {                                                                                           \
        p = ok;                                                                                    \
        p.field = value;                                                                           \
        assert_null (cgs_terrain_new_fbm (&p));                                                    \
    } while (0)
    BAD (size_m, 0);
    BAD (size_m, -100);
    BAD (size_m, NAN);
    BAD (size_m, INFINITY);
    BAD (resolution_m, 0);
    BAD (resolution_m, -30);
    BAD (resolution_m, NAN);
    BAD (resolution_m, 5000); // larger than the square
    BAD (relief_m, -1);
    BAD (relief_m, NAN);
    BAD (base_height_m, INFINITY);
    BAD (feature_m, 0);
    BAD (feature_m, NAN);
    BAD (octaves, 0);
    BAD (octaves, 17);
    BAD (persistence, 0);
    BAD (persistence, -0.5);
    BAD (persistence, 1.5);
    BAD (persistence, NAN);
#undef BAD
    p = ok;
    p.size_m = 1e6; // 10001^2 nodes > 2^26
    p.resolution_m = 100;
    assert_null (cgs_terrain_new_fbm (&p));
    // The edges of the accepted range.
    p = ok;
    p.octaves = 16;
    p.persistence = 1;
    cgs_terrain_t *t = cgs_terrain_new_fbm (&p);
    assert_non_null (t);
    cgs_terrain_destroy (&t);
    p = ok;
    p.octaves = 1;
    t = cgs_terrain_new_fbm (&p);
    assert_non_null (t);
    cgs_terrain_destroy (&t);
}

/* --- line of sight ---------------------------------------------------------------- */

static cgs_enu_t P (double e, double n, double u)
{
    return (cgs_enu_t){e, n, u};
}

/* 11 x 11 nodes from (0, 0) at 10 m, all at h, one column (e = 50) at ridge. */
static cgs_terrain_t *s_ridge_grid (float h, float ridge)
{
    float z[121];
    for (int r = 0; r < 11; r++)
        for (int c = 0; c < 11; c++)
            z[r * 11 + c] = c == 5 ? ridge : h;
    cgs_terrain_t *t = cgs_terrain_new_grid (11, 11, 0, 0, 10, z);
    assert_non_null (t);
    return t;
}

/* Checks the clearance and that both entry points agree. */
static void s_check_los (const cgs_terrain_t *t, cgs_enu_t a, cgs_enu_t b, bool clear,
                         double clearance, double tol)
{
    double c = NAN;
    assert_int_equal (cgs_terrain_los_clearance (t, a, b, &c), clear);
    assert_int_equal (cgs_terrain_los_clearance (t, b, a, NULL), clear);
    assert_int_equal (cgs_terrain_los (t, a, b), clear);
    assert_int_equal (cgs_terrain_los (t, b, a), clear);
    if (isinf (clearance))
        assert_true (isinf (c) && c > 0);
    else
        assert_near (c, clearance, tol);
}

static void test_los_flat (void **state)
{
    (void)state;
    cgs_terrain_t *t = s_ridge_grid (100, 100);
    // Two points raised 3 m and 7 m: the lower end is the closest approach.
    s_check_los (t, P (10, 10, 103), P (80, 60, 107), true, 3, 1e-9);
    // Two vehicles on the ground with their antennas 2 m up: clear by 2 m.
    s_check_los (t, P (20, 30, 102), P (90, 75, 102), true, 2, 1e-9);
    // The same vehicles with endpoints on the ground touch it: blocked.
    s_check_los (t, P (20, 30, 100), P (90, 75, 100), false, 0, 1e-9);
    // From below the ground outside the grid: only the part over the grid is
    // checked; it enters at e = 0 (t = 0.5) at 50 + 60 * 0.5 = 80 m.
    s_check_los (t, P (-50, 50, 50), P (50, 50, 110), false, -20, 1e-9);
    // Entirely outside: nothing to check.
    s_check_los (t, P (-50, -50, 0), P (-10, 200, 0), true, INFINITY, 0);
    // Vertical segments.
    s_check_los (t, P (55, 55, 101), P (55, 55, 150), true, 1, 1e-9);
    s_check_los (t, P (55, 55, 90), P (55, 55, 150), false, -10, 1e-9);
    // Along a grid line and through nodes.
    s_check_los (t, P (0, 40, 104), P (100, 40, 104), true, 4, 1e-9);
    s_check_los (t, P (0, 0, 101), P (100, 100, 105), true, 1, 1e-9);
    // Non-finite input is never clear.
    double c = 0;
    assert_false (cgs_terrain_los_clearance (t, P (NAN, 0, 0), P (10, 10, 200), &c));
    assert_true (isnan (c));
    cgs_terrain_destroy (&t);
}

static void test_los_ridge (void **state)
{
    (void)state;
    cgs_terrain_t *t = s_ridge_grid (0, 50);
    // Across the 50 m ridge at 2 m: blocked by 48 m.
    s_check_los (t, P (10, 50, 2), P (90, 50, 2), false, -48, 1e-9);
    // Grazing the crest: blocked (touching counts).
    s_check_los (t, P (10, 50, 50), P (90, 50, 50), false, 0, 1e-9);
    // Above the crest: clear by 2 m.
    s_check_los (t, P (10, 50, 52), P (90, 50, 52), true, 2, 1e-9);
    // Slanted, crossing the ridge where the segment is at 60 m: clear by 10 m
    // there; elsewhere the ground is 0 and the segment higher.
    s_check_los (t, P (20, 3, 45), P (80, 91, 75), true, 10, 1e-9);
    // Both ends on the same side: the ridge is not in the way.
    s_check_los (t, P (0, 0, 2), P (40, 100, 2), true, 2, 1e-9);
    // Ending above the ridge's slope (from e = 40 to 50 the ground rises
    // 5 m per metre): the segment climbs 20 m over 35 m, the ground faster,
    // so the closest approach is the end at e = 45: 30 - 25 = 5 m.
    s_check_los (t, P (10, 50, 10), P (45, 50, 30), true, 5, 1e-9);
    cgs_terrain_destroy (&t);
}

/* The saddle: 4 x 4 nodes at 10 m, all 0 but cell (1, 1) whose corners are
 * 0 (SW), 10 (SE), 10 (NW), 0 (NE). Along that cell's SW-NE diagonal the
 * bilinear surface is H = 20 s - 20 s^2 (s from 0 to 1 across the cell):
 * 0 at both corners, 5 in the middle. A segment 1 m up along the diagonal
 * clears every grid-line crossing (all at nodes of height 0) by 1 m, yet the
 * surface rises 4 m above it mid-cell. */
static void test_los_saddle (void **state)
{
    (void)state;
    float z[16] = {0};
    z[1 * 4 + 2] = 10; // (c = 2, r = 1), SE corner of cell (1, 1)
    z[2 * 4 + 1] = 10; // (c = 1, r = 2), NW corner
    cgs_terrain_t *t = cgs_terrain_new_grid (4, 4, 0, 0, 10, z);
    assert_non_null (t);
    assert_near (s_h (t, 15, 15), 5, 1e-12);

    // What a check at the grid-line crossings alone would see: clear by 1 m.
    for (int k = 0; k <= 3; k++)
        assert_near (1 - s_h (t, 10 * k, 10 * k), 1, 1e-12);
    s_check_los (t, P (-5, -5, 1), P (35, 35, 1), false, -4, 1e-9);
    // 6 m up: clear, by exactly 1 m at the cell centre.
    s_check_los (t, P (-5, -5, 6), P (35, 35, 6), true, 1, 1e-9);
    // Rising through the cell: u = 2 + 4 s across it, H = 20 s - 20 s^2;
    // clearance 2 - 16 s + 20 s^2, smallest at s = 0.4: 2 - 3.2 = -1.2.
    s_check_los (t, P (10, 10, 2), P (20, 20, 6), false, -1.2, 1e-9);
    // Along the other diagonal (NW to SE, corners 10) the surface sags to 5.
    s_check_los (t, P (10, 20, 10.5), P (20, 10, 10.5), true, 0.5, 1e-9);
    cgs_terrain_destroy (&t);
}

/* A small deterministic generator for the test's own random cases. */
static double s_rand01 (uint64_t *s)
{
    *s = *s * 6364136223846793005ULL + 1442695040888963407ULL;
    return (double)(*s >> 11) * 0x1p-53;
}

/* The analytic clearance never exceeds any sampled clearance, and dense
 * sampling gets within the sampling error of it. */
static void test_los_vs_sampling (void **state)
{
    (void)state;
    cgs_terrain_fbm_t p = s_small_fbm (99);
    p.size_m = 2000;
    p.resolution_m = 20;
    p.relief_m = 100;
    p.feature_m = 800;
    cgs_terrain_t *t = cgs_terrain_new_fbm (&p);
    assert_non_null (t);
    // Largest slope of the bilinear surface: the steepest node difference / res.
    double slope = 0;
    for (int r = 0; r + 1 < cgs_terrain_rows (t); r++)
        for (int c = 0; c + 1 < cgs_terrain_cols (t); c++) {
            double h = cgs_terrain_node (t, c, r);
            slope = fmax (slope, fabs (cgs_terrain_node (t, c + 1, r) - h) / 20);
            slope = fmax (slope, fabs (cgs_terrain_node (t, c, r + 1) - h) / 20);
        }
    slope *= 2; // the bilinear gradient is at most the sum of the two
    uint64_t s = 12345;
    int blocked = 0, clear = 0;
    enum { SAMPLES = 20000 };
    for (int i = 0; i < 300; i++) {
        cgs_enu_t a = P (-1100 + 2200 * s_rand01 (&s), -1100 + 2200 * s_rand01 (&s), 0);
        cgs_enu_t b = P (-1100 + 2200 * s_rand01 (&s), -1100 + 2200 * s_rand01 (&s), 0);
        a.u_m = cgs_terrain_height_clamped (t, a.e_m, a.n_m) + 60 * s_rand01 (&s);
        b.u_m = cgs_terrain_height_clamped (t, b.e_m, b.n_m) + 60 * s_rand01 (&s);
        double c;
        bool ok = cgs_terrain_los_clearance (t, a, b, &c);
        assert_int_equal (ok, cgs_terrain_los (t, a, b));
        assert_int_equal (ok, c > 0);
        double sampled = INFINITY;
        for (int k = 0; k <= SAMPLES; k++) {
            double f = (double)k / SAMPLES, h;
            double e = a.e_m + f * (b.e_m - a.e_m), n = a.n_m + f * (b.n_m - a.n_m);
            if (cgs_terrain_height (t, e, n, &h) == 0)
                sampled = fmin (sampled, a.u_m + f * (b.u_m - a.u_m) - h);
        }
        if (isinf (sampled)) {
            assert_true (isinf (c));
            continue;
        }
        double len = hypot (b.e_m - a.e_m, b.n_m - a.n_m);
        double tol = (fabs (b.u_m - a.u_m) + slope * len) / SAMPLES + 1e-9;
        assert_true (c <= sampled + 1e-9);
        assert_true (c >= sampled - tol);
        blocked += !ok;
        clear += ok;
    }
    assert_true (blocked > 20 && clear > 20);
    cgs_terrain_destroy (&t);
}

/* --- DEMs through GDAL ---------------------------------------------------------------- */

typedef struct {
    char dir[64]; // scratch folder for the rasters
} s_fixture_t;

static int s_setup (void **state)
{
    s_fixture_t *f = calloc (1, sizeof *f);
    if (!f)
        return -1;
    snprintf (f->dir, sizeof f->dir, "/tmp/test_terrain_XXXXXX");
    if (!mkdtemp (f->dir)) {
        free (f);
        return -1;
    }
    GDALAllRegister ();
    *state = f;
    return 0;
}

static int s_teardown (void **state)
{
    s_fixture_t *f = *state;
    DIR *d = opendir (f->dir);
    if (d) {
        struct dirent *ent;
        char path[512];
        while ((ent = readdir (d)))
            if (strcmp (ent->d_name, ".") && strcmp (ent->d_name, "..")) {
                snprintf (path, sizeof path, "%s/%s", f->dir, ent->d_name);
                unlink (path);
            }
        closedir (d);
    }
    rmdir (f->dir);
    free (f);
    return 0;
}

/* Height function of raster coordinates (X, Y) in its own CRS. */
typedef double (*s_fn_t) (double X, double Y, void *ctx);

/* Write a one-band Float32 raster through a MEM dataset and CreateCopy:
 * values from fn at pixel centres, and where is_nodata says so -9999, marked
 * as no-data. */
static void s_write_raster (const char *driver, const char *path, int w, int h, const double gt[6],
                            int epsg, s_fn_t fn, void *ctx, bool (*is_nodata) (int i, int j))
{
    GDALDriverH mem = GDALGetDriverByName ("MEM");
    GDALDriverH out = GDALGetDriverByName (driver);
    assert_non_null (mem);
    assert_non_null (out);
    // SRTM HGT and DTED hold 16-bit integers only.
    bool int16 = !strcmp (driver, "SRTMHGT") || !strcmp (driver, "DTED");
    GDALDatasetH ds = GDALCreate (mem, "", w, h, 1, int16 ? GDT_Int16 : GDT_Float32, NULL);
    assert_non_null (ds);
    assert_int_equal (GDALSetGeoTransform (ds, (double *)gt), CE_None);
    if (epsg) {
        OGRSpatialReferenceH srs = OSRNewSpatialReference (NULL);
        assert_int_equal (OSRImportFromEPSG (srs, epsg), OGRERR_NONE);
        assert_int_equal (GDALSetSpatialRef (ds, srs), CE_None);
        OSRRelease (srs);
    }
    float *v = malloc ((size_t)w * h * sizeof *v);
    assert_non_null (v);
    for (int j = 0; j < h; j++)
        for (int i = 0; i < w; i++) {
            double X = gt[0] + (i + 0.5) * gt[1], Y = gt[3] + (j + 0.5) * gt[5];
            v[(size_t)j * w + i] = is_nodata && is_nodata (i, j) ? -9999.0f : (float)fn (X, Y, ctx);
        }
    GDALRasterBandH band = GDALGetRasterBand (ds, 1);
    if (is_nodata)
        assert_int_equal (GDALSetRasterNoDataValue (band, -9999), CE_None);
    assert_int_equal (GDALRasterIO (band, GF_Write, 0, 0, w, h, v, w, h, GDT_Float32, 0, 0),
                      CE_None);
    free (v);
    GDALDatasetH copy = GDALCreateCopy (out, path, ds, FALSE, NULL, NULL, NULL);
    assert_non_null (copy);
    GDALClose (copy);
    GDALClose (ds);
}

/* The local point of the DEM surface above (e, n): iterate (e, n, u) ->
 * lat/lon -> height -> back to local until u settles. ret_p is that point
 * (its e, n within micrometres of the request), including the earth's
 * curvature through cgs_geo. */
typedef double (*s_geo_fn_t) (double lon, double lat, void *ctx);

static cgs_enu_t s_surface (const cgs_geo_t *frame, double e, double n, s_geo_fn_t fn, void *ctx)
{
    cgs_enu_t p = {e, n, 0};
    for (int i = 0; i < 5; i++) {
        cgs_geodetic_t g;
        assert_int_equal (cgs_geo_enu_to_geodetic (frame, (cgs_enu_t){e, n, p.u_m}, &g), 0);
        double h = fn (g.lon_deg, g.lat_deg, ctx);
        assert_int_equal (
            cgs_geo_geodetic_to_enu (frame, (cgs_geodetic_t){g.lat_deg, g.lon_deg, h}, &p), 0);
    }
    return p;
}

/* Compare the terrain with the surface at (e, n). */
static void s_check_surface (const cgs_terrain_t *t, const cgs_geo_t *frame, double e, double n,
                             s_geo_fn_t fn, void *ctx)
{
    cgs_enu_t p = s_surface (frame, e, n, fn, ctx);
    double res = cgs_terrain_resolution (t);
    // Bilinear interpolation of the curvature term (1/R per metre^2) over a
    // cell errs by up to res^2 / (8 R); floats keep ~1e-4 m at these heights.
    double tol = 1e-3 + res * res / (4 * EARTH_R_M);
    // p is within micrometres of (e, n) horizontally (where the surface's
    // slope makes no difference) but may fall just outside the grid's edge.
    assert_true (fabs (p.e_m - e) < 1e-6 && fabs (p.n_m - n) < 1e-6);
    double h;
    assert_int_equal (cgs_terrain_height (t, e, n, &h), 0);
    if (fabs (h - p.u_m) > tol)
        fail_msg ("at (%.1f, %.1f): terrain %.6f, expected %.6f (tol %.6f)", e, n, h, p.u_m, tol);
}

/* EPSG:4326 raster: lon 6.75..7.25, lat 44.75..45.25, 1/120 degree pixels. */
static const double s_geo_gt[6] = {6.75, 1.0 / 120, 0, 45.25, 0, -1.0 / 120};

static double s_geo_plane (double lon, double lat, void *ctx)
{
    (void)ctx;
    return 300 + 2000 * (lon - 7) + 1000 * (lat - 45);
}

static void test_load_geotiff (void **state)
{
    s_fixture_t *f = *state;
    char path[256], err[512];
    snprintf (path, sizeof path, "%s/plane.tif", f->dir);
    s_write_raster ("GTiff", path, 60, 60, s_geo_gt, 4326, s_geo_plane, NULL, NULL);
    cgs_geo_t *frame = cgs_geo_new (45.02, 7.03, 150);
    assert_non_null (frame);

    // A 10 km half-extent square at 200 m: nodes at multiples of 200 m.
    cgs_terrain_t *t = NULL;
    int rc = cgs_terrain_load (path, frame, 200, 10000, &t, err, sizeof err);
    if (rc)
        fail_msg ("load: %d %s", rc, err);
    assert_non_null (t);
    assert_int_equal (cgs_terrain_cols (t), 101);
    assert_int_equal (cgs_terrain_rows (t), 101);
    double e0, n0, e1, n1;
    cgs_terrain_bounds (t, &e0, &n0, &e1, &n1);
    assert_near (e0, -10000, 1e-6);
    assert_near (n0, -10000, 1e-6);
    assert_near (e1, 10000, 1e-6);
    assert_near (n1, 10000, 1e-6);
    // At the origin the surface is 300 + 2000 * 0.03 + 1000 * 0.02 = 380 m
    // above the ellipsoid, 230 m above the 150 m origin.
    double h;
    assert_int_equal (cgs_terrain_height (t, 0, 0, &h), 0);
    assert_near (h, 230, 1e-3);
    const double pts[][2] = {{0, 0},           {5000, -3000}, {-9000, 9500}, {10000, 10000},
                             {-10000, -10000}, {1234, 5678},  {-7777, 333},  {9999, -4321}};
    for (size_t i = 0; i < sizeof pts / sizeof pts[0]; i++)
        s_check_surface (t, frame, pts[i][0], pts[i][1], s_geo_plane, NULL);
    // The curvature is in the grid: 10 km out the surface drops about
    // d^2 / (2 R) = 7.8 m below the plain height difference.
    cgs_geodetic_t g;
    assert_int_equal (cgs_geo_enu_to_geodetic (frame, (cgs_enu_t){0, 10000, 0}, &g), 0);
    assert_int_equal (cgs_terrain_height (t, 0, 10000, &h), 0);
    double drop = s_geo_plane (g.lon_deg, g.lat_deg, NULL) - 150 - h;
    assert_true (drop > 7.6 && drop < 8.1);
    cgs_terrain_destroy (&t);

    // The whole raster at its own spacing: 1/120 degree of longitude at the
    // origin's latitude is the smaller pixel side, about 657 m.
    rc = cgs_terrain_load (path, frame, 0, 0, &t, err, sizeof err);
    if (rc)
        fail_msg ("load: %d %s", rc, err);
    cgs_enu_t w, east;
    assert_int_equal (
        cgs_geo_geodetic_to_enu (frame, (cgs_geodetic_t){45.02, 7.03 - 1.0 / 240, 0}, &w), 0);
    assert_int_equal (
        cgs_geo_geodetic_to_enu (frame, (cgs_geodetic_t){45.02, 7.03 + 1.0 / 240, 0}, &east), 0);
    double res = cgs_terrain_resolution (t);
    assert_near (res, hypot (east.e_m - w.e_m, east.n_m - w.n_m), 1e-6);
    assert_true (res > 650 && res < 665);
    // Every corner in the usable area (between the outermost pixel centres),
    // and the grid covers most of it.
    cgs_terrain_bounds (t, &e0, &n0, &e1, &n1);
    const double corners[][2] = {{e0, n0}, {e0, n1}, {e1, n0}, {e1, n1}};
    for (int i = 0; i < 4; i++) {
        assert_int_equal (
            cgs_geo_enu_to_geodetic (frame, (cgs_enu_t){corners[i][0], corners[i][1], 0}, &g), 0);
        assert_true (g.lon_deg >= 6.75 + 1.0 / 240 - 1e-9 && g.lon_deg <= 7.25 - 1.0 / 240 + 1e-9);
        assert_true (g.lat_deg >= 44.75 + 1.0 / 240 - 1e-9 &&
                     g.lat_deg <= 45.25 - 1.0 / 240 + 1e-9);
    }
    assert_int_equal (
        cgs_geo_geodetic_to_enu (frame, (cgs_geodetic_t){45.02, 6.75 + 1.0 / 240, 0}, &w), 0);
    assert_int_equal (
        cgs_geo_geodetic_to_enu (frame, (cgs_geodetic_t){45.02, 7.25 - 1.0 / 240, 0}, &east), 0);
    cgs_enu_t s, nn;
    assert_int_equal (
        cgs_geo_geodetic_to_enu (frame, (cgs_geodetic_t){44.75 + 1.0 / 240, 7.03, 0}, &s), 0);
    assert_int_equal (
        cgs_geo_geodetic_to_enu (frame, (cgs_geodetic_t){45.25 - 1.0 / 240, 7.03, 0}, &nn), 0);
    assert_true (e1 - e0 > 0.95 * (east.e_m - w.e_m));
    assert_true (n1 - n0 > 0.95 * (nn.n_m - s.n_m));
    for (int r = 0; r < cgs_terrain_rows (t); r += 5)
        for (int c = 0; c < cgs_terrain_cols (t); c += 5)
            s_check_surface (t, frame, e0 + c * res, n0 + r * res, s_geo_plane, NULL);
    s_check_surface (t, frame, 12345, -23456, s_geo_plane, NULL);
    cgs_terrain_destroy (&t);
    cgs_geo_destroy (&frame);
}

/* UTM zone 32N raster: 200 x 200 pixels of 100 m, centred on the pixel
 * centre (xc, yc) nearest the origin; h = 200 + 0.01 (X - xc) + 0.02 (Y - yc),
 * whole metres at every pixel centre, so the text grid is exact. */
typedef struct {
    OGRCoordinateTransformationH to_utm;
    double xc, yc;
} s_utm_t;

static double s_utm_plane (double X, double Y, void *ctx)
{
    const s_utm_t *u = ctx;
    return 200 + 0.01 * (X - u->xc) + 0.02 * (Y - u->yc);
}

static double s_utm_plane_geo (double lon, double lat, void *ctx)
{
    s_utm_t *u = ctx;
    double x = lon, y = lat;
    assert_true (OCTTransform (u->to_utm, 1, &x, &y, NULL));
    return 200 + 0.01 * (x - u->xc) + 0.02 * (y - u->yc);
}

static void test_load_aaigrid_utm (void **state)
{
    s_fixture_t *f = *state;
    char path[256], err[512];
    s_utm_t s_utm;
    snprintf (path, sizeof path, "%s/plane.asc", f->dir);
    OGRSpatialReferenceH wgs = OSRNewSpatialReference (NULL), utm = OSRNewSpatialReference (NULL);
    assert_int_equal (OSRImportFromEPSG (wgs, 4326), OGRERR_NONE);
    assert_int_equal (OSRImportFromEPSG (utm, 32632), OGRERR_NONE);
    OSRSetAxisMappingStrategy (wgs, OAMS_TRADITIONAL_GIS_ORDER);
    OSRSetAxisMappingStrategy (utm, OAMS_TRADITIONAL_GIS_ORDER);
    s_utm.to_utm = OCTNewCoordinateTransformation (wgs, utm);
    assert_non_null (s_utm.to_utm);
    double x = 7.03, y = 45.02;
    assert_true (OCTTransform (s_utm.to_utm, 1, &x, &y, NULL));
    s_utm.xc = round (x / 100) * 100 + 50;
    s_utm.yc = round (y / 100) * 100 + 50;
    const double gt[6] = {s_utm.xc - 10050, 100, 0, s_utm.yc + 10050, 0, -100};
    s_write_raster ("AAIGrid", path, 200, 200, gt, 32632, s_utm_plane, &s_utm, NULL);
    char prj[256];
    snprintf (prj, sizeof prj, "%s/plane.prj", f->dir);
    assert_int_equal (access (prj, R_OK), 0);

    cgs_geo_t *frame = cgs_geo_new (45.02, 7.03, 0);
    assert_non_null (frame);
    cgs_terrain_t *t = NULL;
    int rc = cgs_terrain_load (path, frame, 0, 0, &t, err, sizeof err);
    if (rc)
        fail_msg ("load: %d %s", rc, err);
    // About 100 m: UTM's scale factor 2 degrees from the central meridian is
    // within 0.1 % of 1.
    double res = cgs_terrain_resolution (t);
    assert_true (res > 99.9 && res < 100.1);
    // The raster is turned by the grid convergence (about 1.4 degrees) in the
    // local frame; the grid is an axis-aligned rectangle inside it, so every
    // corner must be in the usable area and the loss small.
    double e0, n0, e1, n1;
    cgs_terrain_bounds (t, &e0, &n0, &e1, &n1);
    const double corners[][2] = {{e0, n0}, {e0, n1}, {e1, n0}, {e1, n1}};
    for (int i = 0; i < 4; i++) {
        cgs_geodetic_t g;
        assert_int_equal (
            cgs_geo_enu_to_geodetic (frame, (cgs_enu_t){corners[i][0], corners[i][1], 0}, &g), 0);
        double X = g.lon_deg, Y = g.lat_deg;
        assert_true (OCTTransform (s_utm.to_utm, 1, &X, &Y, NULL));
        assert_true (X >= gt[0] + 50 - 1e-6 && X <= gt[0] + 19950 + 1e-6);
        assert_true (Y <= gt[3] - 50 + 1e-6 && Y >= gt[3] - 19950 - 1e-6);
    }
    assert_true ((e1 - e0) * (n1 - n0) > 0.9 * 19900.0 * 19900.0);
    for (int r = 0; r < cgs_terrain_rows (t); r += 7)
        for (int c = 0; c < cgs_terrain_cols (t); c += 7)
            s_check_surface (t, frame, e0 + c * res, n0 + r * res, s_utm_plane_geo, &s_utm);
    s_check_surface (t, frame, 3333.3, -4444.4, s_utm_plane_geo, &s_utm);
    cgs_terrain_destroy (&t);

    // The same grid without its .prj: no coordinate system, refused.
    assert_int_equal (unlink (prj), 0);
    t = NULL;
    assert_int_equal (cgs_terrain_load (path, frame, 0, 0, &t, err, sizeof err), -EINVAL);
    assert_null (t);
    assert_non_null (strstr (err, path));
    assert_non_null (strstr (err, "no coordinate system"));

    cgs_geo_destroy (&frame);
    OCTDestroyCoordinateTransformation (s_utm.to_utm);
    OSRRelease (wgs);
    OSRRelease (utm);
}

/* 40 x 40 pixels of 0.005 degree from (6.9 E, 45.1 N): 500 m, one pixel of
 * 400 m (the lowest valid), and a 10 x 10 block of no-data. */
static const double s_nd_gt[6] = {6.9, 0.005, 0, 45.1, 0, -0.005};

static double s_nd_height (double lon, double lat, void *ctx)
{
    (void)ctx;
    int i = (int)floor ((lon - s_nd_gt[0]) / s_nd_gt[1]);
    int j = (int)floor ((lat - s_nd_gt[3]) / s_nd_gt[5]);
    return i == 5 && j == 5 ? 400 : 500;
}

static bool s_nd_block (int i, int j)
{
    return i >= 20 && i < 30 && j >= 20 && j < 30;
}

static bool s_nd_all (int i, int j)
{
    (void)i;
    (void)j;
    return true;
}

static double s_const_ctx (double lon, double lat, void *ctx)
{
    (void)lon;
    (void)lat;
    return *(double *)ctx;
}

static void test_load_nodata (void **state)
{
    s_fixture_t *f = *state;
    char path[256], err[512];
    snprintf (path, sizeof path, "%s/holes.tif", f->dir);
    s_write_raster ("GTiff", path, 40, 40, s_nd_gt, 4326, s_nd_height, NULL, s_nd_block);
    // The block's pixel centres span pixel coordinates 20.5 .. 29.5; its
    // middle, pixel coordinate 25, is at 7.025 E, 44.975 N. Within 4.5 pixels
    // (about 1.7 km east-west, 2.5 km north-south) every sample is no-data
    // and takes the lowest valid height, 400 m.
    cgs_geo_t *frame = cgs_geo_new (44.975, 7.025, 0);
    assert_non_null (frame);
    cgs_terrain_t *t = NULL;
    int rc = cgs_terrain_load (path, frame, 50, 1000, &t, err, sizeof err);
    if (rc)
        fail_msg ("load: %d %s", rc, err);
    double h400 = 400, h500 = 500;
    assert_int_equal (cgs_terrain_cols (t), 41);
    assert_near (cgs_terrain_node (t, 20, 20), 400, 1e-3); // the origin
    s_check_surface (t, frame, 800, -900, s_const_ctx, &h400);
    s_check_surface (t, frame, -1000, 1000, s_const_ctx, &h400);
    cgs_terrain_destroy (&t);
    // The whole raster: away from the block and the low pixel, 500 m.
    rc = cgs_terrain_load (path, frame, 100, 0, &t, err, sizeof err);
    if (rc)
        fail_msg ("load: %d %s", rc, err);
    cgs_enu_t p;
    assert_int_equal (cgs_geo_geodetic_to_enu (frame, (cgs_geodetic_t){45.03, 6.99, 0}, &p), 0);
    s_check_surface (t, frame, p.e_m, p.n_m, s_const_ctx, &h500);
    assert_int_equal (cgs_geo_geodetic_to_enu (frame, (cgs_geodetic_t){44.95, 7.07, 0}, &p), 0);
    s_check_surface (t, frame, p.e_m, p.n_m, s_const_ctx, &h500);
    cgs_terrain_destroy (&t);

    // No valid height at all.
    snprintf (path, sizeof path, "%s/empty.tif", f->dir);
    s_write_raster ("GTiff", path, 40, 40, s_nd_gt, 4326, s_nd_height, NULL, s_nd_all);
    assert_int_equal (cgs_terrain_load (path, frame, 100, 0, &t, err, sizeof err), -EINVAL);
    assert_null (t);
    assert_non_null (strstr (err, path));
    assert_non_null (strstr (err, "band 1 has no valid heights"));
    cgs_geo_destroy (&frame);
}

/* One-degree tiles as SRTM HGT and DTED level 1 hold them: 1201 x 1201
 * posts on whole 3-arcsecond lines (N45..46, E7..8), integer metres:
 * h = 100 + 1200 (lon - 7) + 1200 (lat - 45) is whole at every post. */
static double s_tile_plane (double lon, double lat, void *ctx)
{
    (void)ctx;
    return 100 + 1200 * (lon - 7) + 1200 * (lat - 45);
}

static void test_load_srtm_dted (void **state)
{
    s_fixture_t *f = *state;
    const double gt[6] = {7 - 0.5 / 1200, 1.0 / 1200, 0, 46 + 0.5 / 1200, 0, -1.0 / 1200};
    const char *drivers[][2] = {{"SRTMHGT", "N45E007.hgt"}, {"DTED", "n45.dt1"}};
    cgs_geo_t *frame = cgs_geo_new (45.5, 7.5, 0);
    assert_non_null (frame);
    for (int k = 0; k < 2; k++) {
        char path[256], err[512];
        snprintf (path, sizeof path, "%s/%s", f->dir, drivers[k][1]);
        s_write_raster (drivers[k][0], path, 1201, 1201, gt, 4326, s_tile_plane, NULL, NULL);
        cgs_terrain_t *t = NULL;
        int rc = cgs_terrain_load (path, frame, 100, 5000, &t, err, sizeof err);
        if (rc)
            fail_msg ("%s: load: %d %s", drivers[k][0], rc, err);
        assert_int_equal (cgs_terrain_cols (t), 101);
        // At the origin: 100 + 600 + 600.
        assert_near (cgs_terrain_node (t, 50, 50), 1300, 1e-3);
        const double pts[][2] = {{0, 0}, {4000, -2500}, {-5000, 5000}, {1234.5, 4321}};
        for (size_t i = 0; i < sizeof pts / sizeof pts[0]; i++)
            s_check_surface (t, frame, pts[i][0], pts[i][1], s_tile_plane, NULL);
        cgs_terrain_destroy (&t);
    }
    cgs_geo_destroy (&frame);
}

static void test_load_errors (void **state)
{
    s_fixture_t *f = *state;
    char path[256], err[512];
    int dummy;
    cgs_terrain_t *const untouched = (cgs_terrain_t *)&dummy;
    cgs_terrain_t *t = untouched;
    cgs_geo_t *frame = cgs_geo_new (45.02, 7.03, 0);
    assert_non_null (frame);

    snprintf (path, sizeof path, "%s/terrain.tif", f->dir);
    assert_int_equal (cgs_terrain_load (path, frame, 0, 0, &t, err, sizeof err), -ENOENT);
    assert_true (t == untouched);
    char want[300];
    snprintf (want, sizeof want, "%s: no such file", path);
    assert_string_equal (err, want);

    snprintf (path, sizeof path, "%s/garbage.tif", f->dir);
    FILE *fp = fopen (path, "w");
    assert_non_null (fp);
    fputs ("this is not a raster, only some text\n", fp);
    fclose (fp);
    assert_int_equal (cgs_terrain_load (path, frame, 0, 0, &t, err, sizeof err), -EINVAL);
    assert_true (t == untouched);
    assert_true (strncmp (err, path, strlen (path)) == 0);

    // The origin far from the raster.
    snprintf (path, sizeof path, "%s/plane.tif", f->dir);
    s_write_raster ("GTiff", path, 60, 60, s_geo_gt, 4326, s_geo_plane, NULL, NULL);
    cgs_geo_t *far = cgs_geo_new (50, 10, 0);
    assert_non_null (far);
    assert_int_equal (cgs_terrain_load (path, far, 0, 0, &t, err, sizeof err), -EINVAL);
    assert_true (t == untouched);
    assert_true (strncmp (err, path, strlen (path)) == 0);
    assert_non_null (strstr (err, "the exercise origin"));
    assert_non_null (strstr (err, "is outside the raster"));
    cgs_geo_destroy (&far);

    // A half extent under one grid cell.
    assert_int_equal (cgs_terrain_load (path, frame, 100, 50, &t, err, sizeof err), -EINVAL);
    assert_true (t == untouched);
    assert_non_null (strstr (err, "half extent"));
    // Bad arguments; a NULL error buffer is allowed.
    assert_int_equal (cgs_terrain_load (path, frame, -1, 0, &t, err, sizeof err), -EINVAL);
    assert_int_equal (cgs_terrain_load (path, frame, 0, NAN, &t, NULL, 0), -EINVAL);
    assert_int_equal (cgs_terrain_load (path, NULL, 0, 0, &t, err, sizeof err), -EINVAL);
    assert_int_equal (cgs_terrain_load (NULL, frame, 0, 0, &t, err, sizeof err), -EINVAL);
    assert_true (t == untouched);
    // A tiny buffer is truncated, not overrun.
    char small[8];
    assert_int_equal (cgs_terrain_load ("nope.tif", frame, 0, 0, &t, small, sizeof small), -ENOENT);
    assert_string_equal (small, "nope.ti");
    cgs_geo_destroy (&frame);
}

/* Woods: a strip of forest on flat ground crossed level and from above,
 * lengths against the geometry; grown woods cover the fraction asked. */
static void test_vegetation (void **state)
{
    (void)state;
    // 101 x 101 nodes, 10 m apart, flat at 50 m; forest 20 m tall on the
    // nodes of columns 40..59 (cells from east 395 to 595 m: 200 m wide).
    enum { N = 101 };
    float *h = calloc (N * N, sizeof *h), *c = calloc (N * N, sizeof *c);
    assert_non_null (h);
    assert_non_null (c);
    for (int i = 0; i < N * N; i++) {
        h[i] = 50;
        c[i] = (i % N >= 40 && i % N <= 59) ? 20.0f : 0.0f;
    }
    cgs_terrain_t *t = cgs_terrain_new_grid (N, N, 0, 0, 10, h);
    assert_non_null (t);
    assert_near (cgs_terrain_foliage_m (t, (cgs_enu_t){0, 500, 52}, (cgs_enu_t){1000, 500, 52}), 0,
                 0); // no vegetation yet
    assert_int_equal (cgs_terrain_set_canopy (t, c), 0);
    assert_near (cgs_terrain_canopy (t, 500, 300), 20, 0);
    assert_near (cgs_terrain_canopy (t, 390, 300), 0, 0);
    assert_near (cgs_terrain_canopy (t, 5000, 300), 0, 0); // off the grid
    assert_near (cgs_terrain_vegetated_fraction (t), 20.0 / N, 1e-12);
    // Level, 2 m above the ground, across the strip: 200 m in the trees.
    double step = 10.0 / 4;
    assert_near (cgs_terrain_foliage_m (t, (cgs_enu_t){0, 500, 52}, (cgs_enu_t){1000, 500, 52}),
                 200, step);
    // Diagonally across it at 45 degrees in plan: 200 * sqrt 2.
    assert_near (cgs_terrain_foliage_m (t, (cgs_enu_t){300, 300, 52}, (cgs_enu_t){700, 700, 52}),
                 200 * sqrt (2), 2 * step);
    // Above the treetops: nothing.
    assert_near (cgs_terrain_foliage_m (t, (cgs_enu_t){0, 500, 71}, (cgs_enu_t){1000, 500, 71}), 0,
                 0);
    // From 1,000 m above to a point 2 m up in the middle of the wood at 30
    // degrees elevation: inside from 70 m (the treetops) down to 52 m, 18 m
    // of height, 18 / sin 30 = 36 m of path (its plan extent, 31 m, stays in the wood).
    double el = 30 * M_PI / 180, dz = 1000 - 2;
    cgs_enu_t top = {495 - dz / tan (el) * 0.0, 500 - dz / tan (el), 50 + 1000};
    assert_near (cgs_terrain_foliage_m (t, top, (cgs_enu_t){495, 500, 52}), 36, 0.2);
    // Reversed, the same.
    assert_near (cgs_terrain_foliage_m (t, (cgs_enu_t){495, 500, 52}, top), 36, 0.2);
    // Over a slope (a plane rising 1 m in 10 east) under 20 m of wood
    // everywhere, from 500 m up at east 0 down to 2.5 m above the ground at
    // east 600: the height above the ground falls as 500 - 497.5 t along the
    // path, so it is inside from t = 480 / 497.5 to 1, of a path of
    // sqrt(600^2 + 437.5^2) m: 26.12 m.
    {
        float *hs = calloc (N * N, sizeof *hs), *cs = calloc (N * N, sizeof *cs);
        assert_non_null (hs);
        assert_non_null (cs);
        for (int i = 0; i < N * N; i++) {
            hs[i] = (float)((i % N) * 1.0);
            cs[i] = 20;
        }
        cgs_terrain_t *slope = cgs_terrain_new_grid (N, N, 0, 0, 10, hs);
        assert_non_null (slope);
        assert_int_equal (cgs_terrain_set_canopy (slope, cs), 0);
        double want = (1 - 480 / 497.5) * sqrt (600.0 * 600 + 437.5 * 437.5);
        assert_near (want, 26.12, 0.01);
        assert_near (
            cgs_terrain_foliage_m (slope, (cgs_enu_t){0, 500, 500}, (cgs_enu_t){600, 500, 62.5}),
            want, 0.5);
        cgs_terrain_destroy (&slope);
        free (hs);
        free (cs);
    }
    // Bad canopies refused, the old one kept.
    c[7] = -1;
    assert_int_equal (cgs_terrain_set_canopy (t, c), -EINVAL);
    c[7] = NAN;
    assert_int_equal (cgs_terrain_set_canopy (t, c), -EINVAL);
    assert_near (cgs_terrain_canopy (t, 500, 300), 20, 0);
    // Grown woods: the fraction asked, repeatable by seed, in patches.
    cgs_vegetation_t v;
    cgs_vegetation_defaults (&v);
    v.cover = 0.3;
    v.seed = 9;
    v.feature_m = 300;
    assert_int_equal (cgs_terrain_grow_vegetation (t, &v), 0);
    assert_near (cgs_terrain_vegetated_fraction (t), 0.3, 1.0 / (N * N));
    float first = (float)cgs_terrain_canopy (t, 333, 777);
    assert_int_equal (cgs_terrain_grow_vegetation (t, &v), 0);
    assert_near (cgs_terrain_canopy (t, 333, 777), first, 0);
    // Patches: a vegetated node's east neighbour is vegetated far more often than 30%.
    int pairs = 0, both = 0;
    for (double n = 0; n <= 1000; n += 10)
        for (double e = 0; e < 1000; e += 10)
            if (cgs_terrain_canopy (t, e, n) > 0) {
                pairs++;
                both += cgs_terrain_canopy (t, e + 10, n) > 0;
            }
    assert_true (both > 0.8 * pairs);
    v.cover = 1.5;
    assert_int_equal (cgs_terrain_grow_vegetation (t, &v), -EINVAL);
    v.cover = 0;
    assert_int_equal (cgs_terrain_grow_vegetation (t, &v), 0);
    assert_near (cgs_terrain_vegetated_fraction (t), 0, 0);
    cgs_terrain_destroy (&t);
    free (h);
    free (c);
}

int main (void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test (test_grid_bilinear),
        cmocka_unit_test (test_grid_normal),
        cmocka_unit_test (test_grid_bad),
        cmocka_unit_test (test_fbm_deterministic),
        cmocka_unit_test (test_fbm_range_and_shape),
        cmocka_unit_test (test_fbm_bad),
        cmocka_unit_test (test_los_flat),
        cmocka_unit_test (test_los_ridge),
        cmocka_unit_test (test_los_saddle),
        cmocka_unit_test (test_los_vs_sampling),
        cmocka_unit_test (test_load_geotiff),
        cmocka_unit_test (test_load_aaigrid_utm),
        cmocka_unit_test (test_load_nodata),
        cmocka_unit_test (test_load_srtm_dted),
        cmocka_unit_test (test_load_errors),
        cmocka_unit_test (test_vegetation),
    };
    return cmocka_run_group_tests (tests, s_setup, s_teardown);
}
