/* test_cgs_score — the intercept score against hand computation: a target
 * driving straight through a square footprint at a known speed (time inside,
 * first-inside time, closest approach to the centre, time to image); a
 * footprint that goes stale or is withdrawn (NULL) judges nothing; a target
 * that never enters is not imaged and keeps its true distance to the edge.
 *
 * The footprint is the square |e| ≤ 50, |n| ≤ 50 about the origin, as seen
 * by a UAV looking north. The target drives east along n = 10 at 10 m/s,
 * sampled every 0.1 s (1 m a sample): sample i is at t = i/10 s,
 * e = −200.5 + i m, so no sample lies on an edge. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <math.h>
#include <stdio.h>

#include "cgs_score.h"
#include "test_util.h"

#define HALF_M   50.0   // half the footprint's side
#define ROAD_N_M 10.0   // the target's northing
#define START_E  -200.5 // the target's easting at t = 0
#define SAMPLES  401    // t = 0 .. 40 s
#define DESIG_S  5.0    // designation time

/* The square footprint, corners clockwise seen from above: near-left,
 * far-left, far-right, near-right (looking north). */
static cgs_footprint_t s_square (void)
{
    cgs_footprint_t f = {0};
    f.corner[0] = (cgs_v2_t){-HALF_M, -HALF_M};
    f.corner[1] = (cgs_v2_t){-HALF_M, HALF_M};
    f.corner[2] = (cgs_v2_t){HALF_M, HALF_M};
    f.corner[3] = (cgs_v2_t){HALF_M, -HALF_M};
    f.center = (cgs_v2_t){0, 0};
    return f;
}

static double s_t (int i)
{
    return i / 10.0;
}

/* Drive the target east along north_m, with the footprint shown every 0.5 s
 * while t ≤ fp_until_s, withdrawn (NULL) once after that. */
static void s_drive (cgs_score_t *sc, double start_e, double north_m, double fp_until_s)
{
    bool withdrawn = false;
    for (int i = 0; i < SAMPLES; i++) {
        double t = s_t (i);
        if (i % 5 == 0 && t <= fp_until_s) {
            cgs_footprint_t f = s_square ();
            cgs_score_footprint (sc, t, &f);
        } else if (t > fp_until_s && !withdrawn) {
            cgs_score_footprint (sc, t, NULL);
            withdrawn = true;
        }
        cgs_score_target (sc, t, (cgs_v2_t){start_e + i, north_m});
    }
}

static void test_init (void **state)
{
    (void)state;
    cgs_score_t sc;
    cgs_score_init (&sc);
    assert_near (sc.max_age_s, 0.5, 0);
    assert_true (isinf (sc.closest_m) && sc.closest_m > 0);
    assert_true (isinf (sc.closest_edge_m) && sc.closest_edge_m > 0);
    assert_false (sc.designated);
    assert_false (sc.imaged);
    assert_true (isnan (cgs_score_time_to_image (&sc)));
    // Only the first designation counts.
    cgs_score_designated (&sc, 3.0);
    cgs_score_designated (&sc, 7.0);
    assert_true (sc.designated);
    assert_near (sc.designation_s, 3.0, 0);
}

/* Inside: e from −49.5 (i = 151, t = 15.1 s) to 49.5 (i = 250, t = 25.0 s),
 * 100 samples and 99 intervals of 0.1 s: 9.9 s inside (the true crossing
 * takes 100 m / 10 m/s = 10 s; the samples see 0.1 s less). Closest to the
 * centre: e = ±0.5, sqrt(0.5² + 10²) m, first at i = 200 (t = 20 s). */
static void test_drive_through (void **state)
{
    (void)state;
    cgs_score_t sc;
    cgs_score_init (&sc);
    cgs_score_designated (&sc, DESIG_S);
    s_drive (&sc, START_E, ROAD_N_M, INFINITY);
    assert_int_equal (sc.samples, SAMPLES);
    assert_int_equal (sc.judged, SAMPLES);
    assert_true (sc.imaged);
    assert_near (sc.first_inside_s, 15.1, 1e-12);
    assert_near (sc.inside_s, 9.9, 1e-9);
    assert_near (sc.closest_m, sqrt (0.25 + ROAD_N_M * ROAD_N_M), 1e-9);
    assert_near (sc.closest_s, 20.0, 1e-12);
    assert_near (sc.closest_edge_m, 0.0, 0);
    assert_near (cgs_score_time_to_image (&sc), 15.1 - DESIG_S, 1e-12);
}

/* Not designated: imaged, but no time to image. */
static void test_not_designated (void **state)
{
    (void)state;
    cgs_score_t sc;
    cgs_score_init (&sc);
    s_drive (&sc, START_E, ROAD_N_M, INFINITY);
    assert_true (sc.imaged);
    assert_true (isnan (cgs_score_time_to_image (&sc)));
}

/* One footprint at t = 0, then none newer: only samples within 0.5 s of it
 * (t = 0 .. 0.5, far outside the square) are judged; the pass is not. */
static void test_stale_footprint (void **state)
{
    (void)state;
    cgs_score_t sc;
    cgs_score_init (&sc);
    cgs_score_designated (&sc, DESIG_S);
    cgs_footprint_t f = s_square ();
    cgs_score_footprint (&sc, 0.0, &f);
    for (int i = 0; i < SAMPLES; i++)
        cgs_score_target (&sc, s_t (i), (cgs_v2_t){START_E + i, ROAD_N_M});
    assert_int_equal (sc.samples, SAMPLES);
    assert_int_equal (sc.judged, 6);
    assert_false (sc.imaged);
    assert_near (sc.inside_s, 0, 0);
    // The last judged sample, t = 0.5 s at e = −195.5, is the closest.
    assert_near (sc.closest_edge_m, 195.5 - HALF_M, 1e-9);
    assert_near (sc.closest_s, 0.5, 1e-12);
    assert_true (isnan (cgs_score_time_to_image (&sc)));

    // A shorter max_age_s judges fewer.
    cgs_score_init (&sc);
    sc.max_age_s = 0.25;
    cgs_score_footprint (&sc, 0.0, &f);
    for (int i = 0; i < SAMPLES; i++)
        cgs_score_target (&sc, s_t (i), (cgs_v2_t){START_E + i, ROAD_N_M});
    assert_int_equal (sc.judged, 3);
}

/* No footprint shown at all (NULL): nothing is judged. */
static void test_no_footprint (void **state)
{
    (void)state;
    cgs_score_t sc;
    cgs_score_init (&sc);
    cgs_score_designated (&sc, DESIG_S);
    cgs_footprint_t f = s_square ();
    cgs_score_footprint (&sc, 0.0, &f);
    for (int i = 0; i < SAMPLES; i++) {
        cgs_score_footprint (&sc, s_t (i), NULL);
        cgs_score_target (&sc, s_t (i), (cgs_v2_t){START_E + i, ROAD_N_M});
    }
    assert_int_equal (sc.judged, 0);
    assert_false (sc.imaged);
    assert_true (isinf (sc.closest_m));
    assert_true (isinf (sc.closest_edge_m));
    assert_near (sc.inside_s, 0, 0);
}

/* The footprint is shown until t = 20 s and withdrawn at 20.1 s: inside
 * from 15.1 s to 20.0 s, 49 intervals, 4.9 s. */
static void test_footprint_withdrawn (void **state)
{
    (void)state;
    cgs_score_t sc;
    cgs_score_init (&sc);
    cgs_score_designated (&sc, DESIG_S);
    s_drive (&sc, START_E, ROAD_N_M, 20.0);
    assert_int_equal (sc.judged, 201); // t = 0 .. 20 s
    assert_true (sc.imaged);
    assert_near (sc.first_inside_s, 15.1, 1e-12);
    assert_near (sc.inside_s, 4.9, 1e-9);
    assert_near (sc.closest_m, sqrt (0.25 + ROAD_N_M * ROAD_N_M), 1e-9);
}

/* A target on n = 80, 30 m north of the far edge, e = −200 .. 200: never
 * inside; closest to the edge 30 m (while |e| ≤ 50), to the centre 80 m
 * (at e = 0, i = 200, t = 20 s). */
static void test_never_enters (void **state)
{
    (void)state;
    cgs_score_t sc;
    cgs_score_init (&sc);
    cgs_score_designated (&sc, DESIG_S);
    s_drive (&sc, -200.0, 80.0, INFINITY);
    assert_int_equal (sc.judged, SAMPLES);
    assert_false (sc.imaged);
    assert_near (sc.inside_s, 0, 0);
    assert_near (sc.closest_edge_m, 30.0, 1e-9);
    assert_near (sc.closest_m, 80.0, 1e-9);
    assert_near (sc.closest_s, 20.0, 1e-12);
    assert_true (isnan (cgs_score_time_to_image (&sc)));

    // Past the corner: at (−200, 80) the nearest point is the corner (−50, 50).
    cgs_score_init (&sc);
    cgs_footprint_t f = s_square ();
    cgs_score_footprint (&sc, 0.0, &f);
    cgs_score_target (&sc, 0.0, (cgs_v2_t){-200.0, 80.0});
    assert_near (sc.closest_edge_m, hypot (150.0, 30.0), 1e-9);
}

int main (void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test (test_init),           cmocka_unit_test (test_drive_through),
        cmocka_unit_test (test_not_designated), cmocka_unit_test (test_stale_footprint),
        cmocka_unit_test (test_no_footprint),   cmocka_unit_test (test_footprint_withdrawn),
        cmocka_unit_test (test_never_enters),
    };
    return cmocka_run_group_tests (tests, NULL, NULL);
}
