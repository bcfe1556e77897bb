/* Unit tests of gd_params: the defaults, the shipped parameter file (which
 * must give exactly the defaults and document every key), every key read
 * from text, and every kind of error with its file, line, section and key;
 * a refused file leaves the parameters as they were. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "cgs_config.h"
#include "gd_params.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

// Every key the file takes, by section (the shipped file must give them all).
static const char *const s_keys[][2] = {
    {"plan", "timing"},
    {"plan", "turn_radius_factor"},
    {"plan", "secondary"},
    {"plan", "secondary_scale"},
    {"plan", "lead_in_m"},
    {"plan", "settle_m"},
    {"plan", "horizon_s"},
    {"plan", "runout_m"},
    {"plan", "arc_step_deg"},
    {"plan", "min_target_speed_mps"},
    {"plan", "max_target_speed_mps"},
    {"replan", "threshold_deg"},
    {"replan", "offset_m"},
    {"replan", "significance"},
    {"approach", "align_deg"},
    {"approach", "lost_after_s"},
    {"approach", "handover_m"},
    {"approach", "handover_growth_mps"},
    {"approach", "handover"},
    {"approach", "confirm_margin_m"},
    {"designation", "pick_radius_m"},
    {"footprint", "max_range_m"},
};

static void s_assert_equal (const gd_params_t *a, const gd_params_t *b)
{
#define S_SAME(f)                                                                                  \
    do {                                                                                           \
        if (a->f != b->f)                                                                          \
            fail_msg ("%s: %.17g != %.17g", #f, (double)a->f, (double)b->f);                       \
    } while (0)
    S_SAME (timing);
    S_SAME (turn_radius_factor);
    S_SAME (secondary);
    S_SAME (secondary_scale);
    S_SAME (lead_in_m);
    S_SAME (settle_m);
    S_SAME (horizon_s);
    S_SAME (runout_m);
    S_SAME (arc_step_deg);
    S_SAME (min_target_speed_mps);
    S_SAME (max_target_speed_mps);
    S_SAME (threshold_deg);
    S_SAME (offset_m);
    S_SAME (significance);
    S_SAME (align_deg);
    S_SAME (lost_after_s);
    S_SAME (handover_m);
    S_SAME (handover_growth_mps);
    S_SAME (handover);
    S_SAME (confirm_margin_m);
    S_SAME (pick_radius_m);
    S_SAME (max_range_m);
#undef S_SAME
}

static void s_load (const char *text, gd_params_t *p)
{
    char err[512] = "";
    if (gd_params_load_string ("g.ini", text, p, err, sizeof err) != 0)
        fail_msg ("load failed: %s", err);
}

// Loading text as "g.ini" fails with -EINVAL, exactly the message expected,
// and leaves *p alone.
static void s_fails (const char *text, const char *expected)
{
    gd_params_t p, before;
    gd_params_defaults (&p);
    p.lead_in_m = 1234; // not a default: a partial write would show
    before = p;
    char err[512] = "";
    int rc = gd_params_load_string ("g.ini", text, &p, err, sizeof err);
    if (rc != -EINVAL)
        fail_msg ("expected -EINVAL, got %d (%s) for:\n%s", rc, err, text);
    s_assert_equal (&p, &before);
    assert_string_equal (err, expected);
}

static void test_defaults (void **state)
{
    (void)state;
    gd_params_t p;
    memset (&p, 0x5a, sizeof p);
    gd_params_defaults (&p);
    assert_int_equal (p.timing, GD_TIMING_ROUTE);
    assert_true (p.turn_radius_factor == 1.5);
    assert_int_equal (p.secondary, GD_SECONDARY_PAPER);
    assert_true (p.secondary_scale == 0.25);
    assert_true (p.lead_in_m == 2000);
    assert_true (p.settle_m == 800);
    assert_true (p.horizon_s == 900);
    assert_true (p.runout_m == 1500);
    assert_true (p.arc_step_deg == 15);
    assert_true (p.min_target_speed_mps == 1);
    assert_true (p.max_target_speed_mps == 30);
    assert_true (p.threshold_deg == 20);
    assert_true (p.offset_m == 150);
    assert_true (p.significance == 2);
    assert_true (p.align_deg == 20);
    assert_true (p.lost_after_s == 300);
    assert_true (p.handover_m == 400);
    assert_true (p.handover_growth_mps == 20);
    assert_int_equal (p.handover, GD_HANDOVER_LINKS);
    assert_true (p.confirm_margin_m == -25);
    assert_true (p.pick_radius_m == 2000);
    assert_true (p.max_range_m == 20000);
    char err[256] = "";
    assert_int_equal (gd_params_check (&p, err, sizeof err), 0);
}

// The shipped file gives every key, and exactly the defaults.
static void test_shipped_file (void **state)
{
    (void)state;
    const char *root = getenv ("CGS_ROOT");
    char path[1024], err[512] = "";
    snprintf (path, sizeof path, "%s/deploy/params/guidance.ini", root ? root : ".");
    gd_params_t p, def;
    gd_params_defaults (&def);
    memset (&p, 0, sizeof p);
    p.timing = GD_TIMING_ARC; // loading over a non-default set writes every field back
    if (gd_params_load (path, &p, err, sizeof err) != 0)
        fail_msg ("%s", err);
    s_assert_equal (&p, &def);
    gd_params_t over = def;
    over.timing = GD_TIMING_ARC;
    over.lead_in_m = 1;
    if (gd_params_load (path, &over, err, sizeof err) != 0)
        fail_msg ("%s", err);
    s_assert_equal (&over, &def);
    cgs_config_t *cfg = NULL;
    if (cgs_config_load (path, &cfg, err, sizeof err) != 0)
        fail_msg ("%s", err);
    for (size_t i = 0; i < sizeof s_keys / sizeof s_keys[0]; i++)
        if (!cgs_config_has (cfg, s_keys[i][0], s_keys[i][1]))
            fail_msg ("%s has no [%s] %s", path, s_keys[i][0], s_keys[i][1]);
    assert_int_equal (cgs_config_section_count (cfg), 5);
    cgs_config_destroy (&cfg);
}

// Every key read from text lands in its field; a key left out keeps its value.
static void test_values (void **state)
{
    (void)state;
    gd_params_t p;
    gd_params_defaults (&p);
    s_load ("[plan]\n"
            "timing = ARC\n"
            "turn_radius_factor = 2\n"
            "secondary = extended\n"
            "secondary_scale = 1\n"
            "lead_in_m = 3000\n"
            "settle_m = 400\n"
            "horizon_s = 1200\n"
            "runout_m = 500\n"
            "arc_step_deg = 5\n"
            "min_target_speed_mps = 0.5\n"
            "max_target_speed_mps = 40\n"
            "[replan]\n"
            "threshold_deg = 30\n"
            "offset_m = 100\n"
            "significance = 0.5\n"
            "[approach]\n"
            "align_deg = 10\n"
            "lost_after_s = 120\n"
            "handover_m = 250\n"
            "handover_growth_mps = 12.5\n"
            "handover = near\n"
            "confirm_margin_m = 30\n"
            "[designation]\n"
            "pick_radius_m = 800\n"
            "[footprint]\n"
            "max_range_m = 9000\n",
            &p);
    gd_params_t want = {
        .timing = GD_TIMING_ARC,
        .turn_radius_factor = 2,
        .secondary = GD_SECONDARY_EXTENDED,
        .secondary_scale = 1,
        .lead_in_m = 3000,
        .settle_m = 400,
        .horizon_s = 1200,
        .runout_m = 500,
        .arc_step_deg = 5,
        .min_target_speed_mps = 0.5,
        .max_target_speed_mps = 40,
        .threshold_deg = 30,
        .offset_m = 100,
        .significance = 0.5,
        .align_deg = 10,
        .lost_after_s = 120,
        .handover_m = 250,
        .handover_growth_mps = 12.5,
        .handover = GD_HANDOVER_NEAR,
        .confirm_margin_m = 30,
        .pick_radius_m = 800,
        .max_range_m = 9000,
    };
    s_assert_equal (&p, &want);
    s_load ("[plan]\ntiming = route\n", &p);
    want.timing = GD_TIMING_ROUTE;
    s_assert_equal (&p, &want);
}

static void test_errors (void **state)
{
    (void)state;
    s_fails ("[plan]\ntiming = sideways\n",
             "g.ini:2: [plan] timing: expected one of 'route', 'arc', got 'sideways'");
    s_fails ("[plan]\nsecondary = mirror\n",
             "g.ini:2: [plan] secondary: expected one of 'extended', 'paper', got 'mirror'");
    s_fails ("[plan]\n\nturn_radius_factor = 0.5\n",
             "g.ini:3: [plan] turn_radius_factor: expected a number in [1, 10], got '0.5'");
    s_fails ("[plan]\nlead_in_m = abc\n",
             "g.ini:2: [plan] lead_in_m: expected a number in [0, 100000], got 'abc'");
    s_fails ("[plan]\nhorizon_s = 5\n",
             "g.ini:2: [plan] horizon_s: expected a number in [10, 86400], got '5'");
    s_fails ("[plan]\nsettle_m = -1\n",
             "g.ini:2: [plan] settle_m: expected a number in [0, 10000], got '-1'");
    s_fails ("[approach]\nconfirm_margin_m = -1001\n",
             "g.ini:2: [approach] confirm_margin_m: expected a number in [-1000, 10000], got "
             "'-1001'");
    s_fails ("[plan]\nfoo = 1\n", "g.ini:2: [plan] unknown key 'foo'");
    s_fails ("[bogus]\nx = 1\n", "g.ini:1: unknown section [bogus]");
    s_fails ("[plan]\ntiming = arc\ntiming = route\n",
             "g.ini:3: [plan] timing: given twice (first at line 2)");
    // The file is missing.
    gd_params_t p;
    gd_params_defaults (&p);
    char err[512] = "";
    assert_true (gd_params_load ("/nonexistent/guidance.ini", &p, err, sizeof err) < 0);
    assert_non_null (strstr (err, "/nonexistent/guidance.ini"));
}

// A set built in code is checked too.
static void test_check (void **state)
{
    (void)state;
    gd_params_t p;
    char err[256] = "";
    gd_params_defaults (&p);
    p.timing = (gd_timing_t)7;
    assert_int_equal (gd_params_check (&p, err, sizeof err), -EINVAL);
    assert_string_equal (err, "[plan] timing: expected route or arc, got 7");
    gd_params_defaults (&p);
    p.secondary = (gd_secondary_t)3;
    assert_int_equal (gd_params_check (&p, err, sizeof err), -EINVAL);
    assert_string_equal (err, "[plan] secondary: expected extended or paper, got 3");
    gd_params_defaults (&p);
    p.handover_growth_mps = 101;
    assert_int_equal (gd_params_check (&p, err, sizeof err), -EINVAL);
    assert_non_null (strstr (err, "[approach] handover_growth_mps"));
}

int main (void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test (test_defaults), cmocka_unit_test (test_shipped_file),
        cmocka_unit_test (test_values),   cmocka_unit_test (test_errors),
        cmocka_unit_test (test_check),
    };
    return cmocka_run_group_tests (tests, NULL, NULL);
}
