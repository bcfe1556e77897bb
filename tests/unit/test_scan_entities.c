/* The shared scan schedule (cgs_scan) and entity table (cgs_entities): dwell
 * widths and times against the beamwidth and rate, sectors across north,
 * membership at the edges, refused parameters; entities taken, replaced,
 * refused when malformed, found, iterated and evicted. */
#include "cgs_entities.h"
#include "cgs_scan.h"
#include "cgs_sensor.h"

#include <errno.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "test_util.h"

static void test_scan_full (void **state)
{
    (void)state;
    cgs_scan_params_t p = {.mode = CGS_SCAN_FULL, .beamwidth_deg = 7, .rate_dps = 70};
    cgs_scan_t s;
    assert_int_equal (cgs_scan_init (&p, &s), 0);
    // floor(360 / 7) = 51 dwells of 360/51 degrees, each lasting width / rate.
    assert_int_equal (s.dwells, 51);
    assert_near (s.dwell_deg, 360.0 / 51, 1e-12);
    assert_near (s.dwell_s, 360.0 / 51 / 70, 1e-12);
    cgs_dwell_t d;
    cgs_scan_dwell (&s, 51 * 3 + 50, 0, &d);
    assert_int_equal (d.scan, 4);
    assert_true (d.scan_end);
    assert_near (d.end_s, 4 * 360.0 / 70, 1e-9); // four revolutions at 70 deg/s
    assert_near (d.az_to_deg, 0, 1e-9);
    assert_true (cgs_dwell_contains (&d, 359.9));
    assert_false (cgs_dwell_contains (&d, 0.0)); // [lo, lo + width)
    assert_int_equal (cgs_scan_dwell_at (&s, d.start_s + 1e-9), d.index);
    assert_int_equal (cgs_scan_dwell_at (&s, -5), 0);
    assert_int_equal (cgs_scan_dwell_at (&s, NAN), 0);
}

static void test_scan_sector_across_north (void **state)
{
    (void)state;
    cgs_scan_params_t p = {.mode = CGS_SCAN_SECTOR,
                           .sector_center_deg = 10,
                           .sector_width_deg = 40,
                           .beamwidth_deg = 10,
                           .rate_dps = 20};
    cgs_scan_t s;
    assert_int_equal (cgs_scan_init (&p, &s), 0);
    assert_int_equal (s.dwells, 4);
    cgs_dwell_t d;
    // Pass 1 clockwise from 350, pass 2 back from 30.
    cgs_scan_dwell (&s, 0, 0, &d);
    assert_near (d.az_from_deg, 350, 1e-9);
    assert_near (cgs_dwell_lo_deg (&d), 350, 1e-9);
    assert_true (cgs_dwell_contains (&d, 355) && !cgs_dwell_contains (&d, 5));
    cgs_scan_dwell (&s, 4, 0, &d);
    assert_int_equal (d.scan, 2);
    assert_near (d.az_from_deg, 30, 1e-9);
    assert_near (d.az_to_deg, 20, 1e-9);
    assert_near (cgs_dwell_lo_deg (&d), 20, 1e-9);
    assert_true (cgs_dwell_contains (&d, 25) && !cgs_dwell_contains (&d, 15));
    // Heading-referenced: the same sector turned with the platform.
    p.sector_ref = CGS_SECTOR_HEADING;
    assert_int_equal (cgs_scan_init (&p, &s), 0);
    cgs_scan_dwell (&s, 0, 90, &d);
    assert_near (d.az_from_deg, 80, 1e-9);
}

static void test_scan_refused (void **state)
{
    (void)state;
    cgs_scan_t s = {.dwells = 99};
    cgs_scan_params_t bad[] = {
        {.mode = CGS_SCAN_FULL, .beamwidth_deg = 0, .rate_dps = 10},
        {.mode = CGS_SCAN_FULL, .beamwidth_deg = 3, .rate_dps = -1},
        {.mode = CGS_SCAN_FULL, .beamwidth_deg = NAN, .rate_dps = 10},
        {.mode = CGS_SCAN_SECTOR, .sector_width_deg = 2, .beamwidth_deg = 3, .rate_dps = 10},
        {.mode = CGS_SCAN_SECTOR, .sector_width_deg = 400, .beamwidth_deg = 3, .rate_dps = 10},
        {.mode = (cgs_scan_mode_t)7, .beamwidth_deg = 3, .rate_dps = 10},
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++)
        assert_int_equal (cgs_scan_init (&bad[i], &s), -EINVAL);
    assert_int_equal (s.dwells, 99); // untouched on failure
}

/* Pacing: each ended dwell once; a start and a step back run nothing; a
 * jump ahead catches up no more than the history (or a scan) allows. */
static void test_scan_pace (void **state)
{
    (void)state;
    cgs_scan_params_t p = {.mode = CGS_SCAN_FULL, .beamwidth_deg = 6, .rate_dps = 60};
    cgs_scan_t s;
    assert_int_equal (cgs_scan_init (&p, &s), 0); // 60 dwells of 0.1 s
    cgs_scan_pace_t pace = {0};
    uint64_t end, skipped;
    assert_int_equal (cgs_scan_pace (&s, &pace, 5.05, 10, &end, &skipped), CGS_PACE_START);
    assert_int_equal (pace.next, 51); // dwell 50 is in progress: the next to run is 51
    assert_int_equal (end, 51);
    // 0.1 s on: dwell 51 is in progress, nothing has ended since.
    assert_int_equal (cgs_scan_pace (&s, &pace, 5.15, 10, &end, &skipped), CGS_PACE_RUN);
    assert_int_equal (end, 51);
    // At 5.55 s dwells 51..54 have ended.
    assert_int_equal (cgs_scan_pace (&s, &pace, 5.55, 10, &end, &skipped), CGS_PACE_RUN);
    assert_int_equal (end, 55);
    assert_int_equal (skipped, 0);
    pace.next = end; // the caller ran them
    // A jump of 100 s: only the last scan (60 dwells, under the 10 s history) is run.
    assert_int_equal (cgs_scan_pace (&s, &pace, 105.55, 10, &end, &skipped), CGS_PACE_RUN);
    assert_int_equal (end, 1055);
    assert_int_equal (pace.next, 1055 - 60);
    assert_int_equal (skipped, 1055 - 60 - 55);
    assert_int_equal (pace.skipped, skipped);
    // A shorter history bounds it more: 2 s is 20 dwells.
    pace.next = end;
    assert_int_equal (cgs_scan_pace (&s, &pace, 205.55, 2, &end, &skipped), CGS_PACE_RUN);
    assert_int_equal (end - pace.next, 20);
    pace.next = end;
    // Time went back (a restarted clock): nothing to run, the scan follows from there.
    assert_int_equal (cgs_scan_pace (&s, &pace, 3.05, 10, &end, &skipped), CGS_PACE_BACK);
    assert_int_equal (pace.next, 31);
    assert_int_equal (end, 31);
}

static Cgs__Entity *s_entity (uint32_t id, double e, double n)
{
    Cgs__Entity *x = calloc (1, sizeof *x);
    Cgs__Enu *p = calloc (1, sizeof *p);
    Cgs__EnuVelocity *v = calloc (1, sizeof *v);
    cgs__entity__init (x);
    cgs__enu__init (p);
    cgs__enu_velocity__init (v);
    p->east_m = e;
    p->north_m = n;
    v->east_mps = 3;
    x->entity_id = id;
    x->position = p;
    x->velocity = v;
    x->force = CGS__FORCE__FORCE_FRIENDLY;
    x->bcis_transponder = true;
    x->active = true;
    x->marking = "ALPHA";
    x->rcs_class = "tank";
    return x;
}

static void s_free (Cgs__Entity *x)
{
    free (x->position);
    free (x->velocity);
    free (x);
}

static void test_entities (void **state)
{
    (void)state;
    cgs_entities_t *t = cgs_entities_new ();
    assert_non_null (t);
    enum { N = 3000 }; // grows past the first table
    Cgs__Entity **es = calloc (N, sizeof *es);
    for (uint32_t i = 0; i < N; i++)
        es[i] = s_entity (i + 1, i, -1.0 * i);
    es[10]->position->north_m = NAN; // refused
    es[11]->entity_id = 0;           // refused
    Cgs__EntityBatch b = CGS__ENTITY_BATCH__INIT;
    b.entities = es;
    b.n_entities = N;
    size_t bad = 99;
    assert_int_equal (cgs_entities_update (t, &b, 5.0, &bad), 0);
    assert_int_equal (bad, 2);
    assert_int_equal (cgs_entities_count (t), N - 2);
    assert_near (cgs_entities_latest_s (t), 5.0, 0);
    const cgs_entity_state_t *s = cgs_entities_find (t, 101);
    assert_non_null (s);
    assert_near (s->position.e_m, 100, 0);
    assert_int_equal (s->force, CGS_FORCE_FRIENDLY);
    assert_true (s->bcis_transponder);
    assert_string_equal (s->marking, "ALPHA");
    assert_string_equal (s->rcs_class, "tank");
    assert_null (cgs_entities_find (t, 11)); // es[10]
    // A newer state replaces the old one; the others keep theirs.
    b.n_entities = 200;
    es[100]->position->east_m = -7;
    assert_int_equal (cgs_entities_update (t, &b, 20.0, &bad), 0);
    assert_near (cgs_entities_find (t, 101)->position.e_m, -7, 0);
    assert_near (cgs_entities_find (t, 101)->time_s, 20.0, 0);
    size_t cursor = 0, seen = 0;
    while (cgs_entities_next (t, &cursor))
        seen++;
    assert_int_equal (seen, N - 2);
    // A non-finite time refuses the whole batch.
    assert_int_equal (cgs_entities_update (t, &b, INFINITY, &bad), 0);
    assert_int_equal (bad, 200);
    // Evict what is older than 10 s before t = 25: only the 198 refreshed at 20 s stay.
    cgs_entities_evict (t, 25.0, 10.0);
    assert_int_equal (cgs_entities_count (t), 198);
    assert_non_null (cgs_entities_find (t, 1));
    assert_null (cgs_entities_find (t, 1000));
    for (uint32_t i = 0; i < N; i++)
        s_free (es[i]);
    free (es);
    cgs_entities_destroy (&t);
    assert_null (t);
    cgs_entities_destroy (&t);
}

/* A sensor's UAV: only its own `uav` messages are taken, malformed ones
 * refused whole, and its position moved on along its velocity. */
static void test_sensor_uav (void **state)
{
    (void)state;
    cgs_sensor_t s = {.uav_name = "uav1"};
    Cgs__Enu pos = CGS__ENU__INIT;
    Cgs__EnuVelocity vel = CGS__ENU_VELOCITY__INIT;
    pos.east_m = 100, pos.north_m = -50, pos.up_m = 1500;
    vel.east_mps = 30, vel.up_mps = -1;
    Cgs__Uav u = CGS__UAV__INIT;
    u.name = "uav2";
    u.entity_id = 4;
    u.position = &pos;
    u.velocity = &vel;
    u.heading_deg = 90;
    bool new_id = false;
    assert_int_equal (cgs_sensor_take_uav (&s, &u, 10, &new_id), 1); // another UAV's
    assert_int_equal (s.uav_id, 0);
    u.name = "uav1";
    assert_int_equal (cgs_sensor_take_uav (&s, &u, 10, &new_id), 0);
    assert_true (new_id);
    assert_int_equal (s.uav_id, 4);
    assert_int_equal (cgs_sensor_take_uav (&s, &u, 11, &new_id), 0);
    assert_false (new_id);
    cgs_enu_t at = cgs_sensor_uav_at (&s, 13);
    assert_near (at.e_m, 100 + 30 * 2, 1e-12);
    assert_near (at.n_m, -50, 1e-12);
    assert_near (at.u_m, 1500 - 2, 1e-12);
    // Malformed: nothing taken.
    u.heading_deg = NAN;
    assert_int_equal (cgs_sensor_take_uav (&s, &u, 12, &new_id), -EINVAL);
    u.heading_deg = 90;
    pos.east_m = INFINITY;
    assert_int_equal (cgs_sensor_take_uav (&s, &u, 12, &new_id), -EINVAL);
    pos.east_m = 100;
    assert_int_equal (cgs_sensor_take_uav (&s, &u, -1, &new_id), -EINVAL);
    u.velocity = NULL;
    assert_int_equal (cgs_sensor_take_uav (&s, &u, 12, &new_id), -EINVAL);
    assert_near (s.time_s, 11, 0);
    cgs_sensor_fini (&s); // nothing built: safe
}

int main (void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test (test_scan_full),    cmocka_unit_test (test_scan_sector_across_north),
        cmocka_unit_test (test_scan_refused), cmocka_unit_test (test_scan_pace),
        cmocka_unit_test (test_entities),     cmocka_unit_test (test_sensor_uav),
    };
    return cmocka_run_group_tests (tests, NULL, NULL);
}
