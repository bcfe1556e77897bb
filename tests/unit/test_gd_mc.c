/* test_gd_mc — the Monte Carlo of whole intercepts, small: the cores of
 * uavsim, mtid, trackerd and guidanced together image most targets, with
 * the UAV both ahead of and behind the waypoint and targets that turn, by
 * both methods; any run can be repeated alone and gives the same outcome.
 * The full 200-run figure is `make montecarlo`. */
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
    printf ("# %zu intercepts from %zu geometries, %zu imaged; ahead %zu/%zu, behind %zu/%zu, "
            "turned %zu/%zu; closest median %.1f m\n",
            r.designated, r.drawn, r.imaged, r.ahead_imaged, r.ahead, r.behind_imaged, r.behind,
            r.turned_imaged, r.turned, r.closest_p50_m);
    // Every run is a whole intercept: geometries without a confirmed track
    // in time are drawn again.
    assert_int_equal (r.designated, 24);
    assert_true (r.drawn >= 24);
    // Both signs of y'_u and both kinds of target occur.
    assert_true (r.ahead > 0 && r.behind > 0);
    assert_int_equal (r.ahead + r.behind, 24);
    assert_true (r.turned > 0 && r.straight > 0);
    // Most targets pass through the true footprint (200 runs give about
    // 98%; 24 runs at 85% leave room for the sample's spread).
    assert_true ((double)r.imaged >= 0.85 * 24);
    // An imaged run has miss 0 and a time to image; the counts agree; the
    // geometry numbers increase.
    size_t imaged = 0;
    for (size_t i = 0; i < c.runs; i++) {
        assert_true (runs[i].designated);
        if (i > 0)
            assert_true (runs[i].index > runs[i - 1].index);
        if (runs[i].imaged) {
            imaged++;
            assert_true (runs[i].miss_m == 0);
            assert_true (runs[i].time_to_image_s > 0);
        } else {
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
        assert_int_equal (a[i].index, b[i].index);
        assert_int_equal (a[i].imaged, b[i].imaged);
        assert_true (a[i].closest_m == b[i].closest_m);
    }
}

/* What a trace saw. */
typedef struct {
    size_t samples;
    double last_t;
    bool ordered;
    bool approach, overflight; // phases seen
    uint32_t track_id;
} s_seen_t;

static void s_seen (void *arg, const gd_mc_sample_t *s)
{
    s_seen_t *v = arg;
    if (v->samples > 0 && !(s->t_s > v->last_t))
        v->ordered = false;
    v->samples++;
    v->last_t = s->t_s;
    v->approach |= s->status->phase == GD_APPROACH;
    v->overflight |= s->status->phase == GD_OVERFLIGHT;
    if (s->has_track)
        v->track_id = s->track_id;
}

/* A run repeated alone (gd_mc_trace) has the outcome it had in the set:
 * each geometry's radar noise depends on its number only. */
static void test_trace_repeats_a_run (void **state)
{
    (void)state;
    gd_mc_config_t c;
    gd_mc_defaults (&c);
    c.runs = 5;
    gd_mc_run_t runs[5];
    gd_mc_result_t r;
    assert_int_equal (gd_mc_run (&c, runs, NULL, NULL, &r), 0);
    for (size_t i = 2; i < 5; i++) {
        s_seen_t v = {.ordered = true};
        gd_mc_run_t one;
        assert_int_equal (gd_mc_trace (&c, runs[i].index, s_seen, &v, &one), 0);
        assert_int_equal (one.imaged, runs[i].imaged);
        assert_true (one.closest_m == runs[i].closest_m);
        assert_int_equal (one.replans, runs[i].replans);
        assert_int_equal (one.final_phase, runs[i].final_phase);
        // About one sample a second from the designation to the end.
        assert_true (v.ordered);
        assert_true (v.samples > 60);
        assert_true (v.track_id > 0);
        if (one.imaged)
            assert_true (v.overflight);
    }
    gd_mc_run_t one;
    s_seen_t v = {0};
    assert_int_equal (gd_mc_trace (&c, 100000, s_seen, &v, &one), -EINVAL);
}

/* Section 5's method: the UAV flies the reversed hit trail (phase
 * APPROACH) and images the target as often. */
static void test_mti_hits_method (void **state)
{
    (void)state;
    gd_mc_config_t c;
    gd_mc_defaults (&c);
    c.runs = 12;
    c.method = GD_MTI_HITS;
    gd_mc_run_t runs[12];
    gd_mc_result_t r;
    assert_int_equal (gd_mc_run (&c, runs, NULL, NULL, &r), 0);
    printf ("# MTI hits: %zu intercepts, %zu imaged, closest median %.1f m\n", r.designated,
            r.imaged, r.closest_p50_m);
    assert_int_equal (r.designated, 12);
    assert_true ((double)r.imaged >= 0.85 * 12);
    size_t flew_trail = 0;
    for (size_t i = 0; i < 12; i++) {
        if (!runs[i].imaged)
            continue;
        s_seen_t v = {.ordered = true};
        gd_mc_run_t one;
        assert_int_equal (gd_mc_trace (&c, runs[i].index, s_seen, &v, &one), 0);
        flew_trail += v.approach;
        if (flew_trail >= 3)
            break;
    }
    assert_true (flew_trail >= 3);
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
        cmocka_unit_test (test_small_run),           cmocka_unit_test (test_same_seed_same_result),
        cmocka_unit_test (test_trace_repeats_a_run), cmocka_unit_test (test_mti_hits_method),
        cmocka_unit_test (test_bad_config),
    };
    return cmocka_run_group_tests (tests, NULL, NULL);
}
