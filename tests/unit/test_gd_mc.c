/* test_gd_mc — the Monte Carlo of whole intercepts, small: the cores of
 * uavsim, mtid, trackerd and guidanced together image most targets, with
 * the UAV both ahead of and behind the waypoint and targets that turn. The
 * full 200-run figure is `make montecarlo`. */
#include "gd_mc.h"

#include <errno.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>

#include <cmocka.h>

static void test_small_run (void **state)
{
    (void)state;
    gd_mc_config_t c;
    gd_mc_defaults (&c);
    c.runs = 24;
    gd_mc_run_t runs[24];
    gd_mc_result_t r;
    assert_int_equal (gd_mc_run (&c, runs, NULL, NULL, &r), 0);
    printf ("# %zu runs: %zu designated, %zu imaged; ahead %zu/%zu, behind %zu/%zu, turned "
            "%zu/%zu; closest median %.1f m\n",
            r.runs, r.designated, r.imaged, r.ahead_imaged, r.ahead, r.behind_imaged, r.behind,
            r.turned_imaged, r.turned, r.closest_p50_m);
    assert_int_equal (r.runs, 24);
    // Both signs of y'_u and both kinds of target occur.
    assert_true (r.ahead > 0 && r.behind > 0);
    assert_true (r.turned > 0 && r.straight > 0);
    // Most designated targets pass through the true footprint (200 runs give
    // about 87%; 24 runs at 70% leave room for the sample's spread).
    assert_true (r.designated >= 20);
    assert_true ((double)r.imaged >= 0.7 * (double)r.designated);
    // An imaged run has miss 0 and a time to image; the counts agree.
    size_t imaged = 0;
    for (size_t i = 0; i < c.runs; i++) {
        if (runs[i].imaged) {
            imaged++;
            assert_true (runs[i].miss_m == 0);
            assert_true (runs[i].time_to_image_s > 0);
        } else if (runs[i].designated) {
            assert_true (runs[i].miss_m > 0);
        }
    }
    assert_int_equal (imaged, r.imaged);
    // The median closest approach of the footprint centre is well inside
    // the footprint's half-width (about 150 m at 1200 m and 10 degrees).
    assert_true (r.closest_p50_m < 150);
}

static void test_same_seed_same_result (void **state)
{
    (void)state;
    gd_mc_config_t c;
    gd_mc_defaults (&c);
    c.runs = 4;
    gd_mc_run_t a[4], b[4];
    gd_mc_result_t ra, rb;
    assert_int_equal (gd_mc_run (&c, a, NULL, NULL, &ra), 0);
    assert_int_equal (gd_mc_run (&c, b, NULL, NULL, &rb), 0);
    for (int i = 0; i < 4; i++) {
        assert_int_equal (a[i].imaged, b[i].imaged);
        assert_true (a[i].closest_m == b[i].closest_m ||
                     (isnan (a[i].closest_m) && isnan (b[i].closest_m)));
    }
}

static void test_bad_config (void **state)
{
    (void)state;
    gd_mc_config_t c;
    gd_mc_result_t r;
    gd_mc_defaults (&c);
    c.runs = 0;
    assert_int_equal (gd_mc_run (&c, NULL, NULL, NULL, &r), -EINVAL);
    gd_mc_defaults (&c);
    c.speed_max_mps = 40; // faster than the model's tracker allows
    assert_int_equal (gd_mc_run (&c, NULL, NULL, NULL, &r), -EINVAL);
    gd_mc_defaults (&c);
    c.turn_fraction = 1.5;
    assert_int_equal (gd_mc_run (&c, NULL, NULL, NULL, &r), -EINVAL);
}

int main (void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test (test_small_run),
        cmocka_unit_test (test_same_seed_same_result),
        cmocka_unit_test (test_bad_config),
    };
    return cmocka_run_group_tests (tests, NULL, NULL);
}
