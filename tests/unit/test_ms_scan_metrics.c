/* test_ms_scan_metrics — ms_metrics from messages, one radar scan worked by
 * hand. Radar 1's scan 1: `mti.truth` says vehicle 5 was detected (hit 101)
 * and was in the beam and visible; vehicle 6 was in the beam and visible
 * but never detected (not yet a truth); vehicle 7 was detected but not
 * visible in this scan (masked: not a truth of the scan). `entity` puts 5
 * at (1000, 0) at t = 9.5 s moving east at 10 m/s, so at the scan's end
 * (t = 10 s) it is at (1005, 0). The `track` batch of scan 1 has track 10
 * at (1005, 30) whose history holds hit 101 (so it stands for vehicle 5,
 * 30 m away), track 11 at (3000, 0) with no attributed hit (a false
 * track), and tentative track 12 (not counted).
 *   GOSPA (c = 500, p = 2): X = {(1005, 0)}, Y = {(1005, 30), (3000, 0)}:
 *   5 pairs with 10 (30 m), 11 is false: 900 + 500²/2 = 125900, distance
 *   √125900 = 354.82 m; localisation 900, missed 0, false 125000.
 *   SIAP: J = 1, JT = 1, N = 2, NA = 1: completeness 1, ambiguity 1,
 *   spuriousness 0.5, position accuracy 30 m.
 * A second batch split in two (batch_count 2) is taken only when both
 * halves are in.
 *
 * Identification: vehicle 5 is friendly with a BCIS transponder (identity
 * 5) and track 10 is marked friendly with responder id 5: of 1 associated
 * track, identifiable 1, marked 1, correct 1: ID completeness 1, ID
 * correctness 1, ID wrong 0. Then the same scan with vehicle 5 hostile
 * (no identity) and track 10 still marked 5: identifiable 0, marked 1,
 * wrong 1, hostile marked 1: ID completeness NaN (null in JSON), ID
 * correctness 0, ID wrong 1. Track 11 (unassociated) marked friendly counts
 * in neither.
 *
 * A track holding an unseen vehicle: vehicle 7 (detected, masked in scan 1)
 * stands at (5000, 0). Track 14 at (5000, 100) has hit 102 of vehicle 7:
 * unassociated (7 is no truth of the scan), and within the gate (100 m of
 * 500) of a vehicle the radar could not see: unseen. Track 15 at
 * (5600, 0), also with hit 102, is 600 m from it: not unseen. With track
 * 10 (vehicle 5): N = 3, NA = 1, spuriousness 2/3, of it unseen 1/3. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "ms_metrics.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static void s_truth (ms_icpt_t *ic, ms_metrics_t *m)
{
    Cgs__MtiTruthItem it[3], *ip[3];
    uint32_t ids[3] = {5, 6, 7}, hits[3] = {101, 0, 102};
    bool visible[3] = {true, true, false}, detected[3] = {true, false, true};
    for (int i = 0; i < 3; i++) {
        cgs__mti_truth_item__init (&it[i]);
        it[i].entity_id = ids[i];
        it[i].in_beam = true;
        it[i].visible = visible[i];
        it[i].detected = detected[i];
        it[i].hit_id = hits[i];
        ip[i] = &it[i];
    }
    Cgs__MtiTruth t = CGS__MTI_TRUTH__INIT;
    t.uav_id = 1;
    t.scan_number = 1;
    t.n_items = 3;
    t.items = ip;
    Cgs__Header h = CGS__HEADER__INIT;
    h.sim_time_s = 9.0;
    h.epoch = 1;
    ms_icpt_on_mti_truth (ic, "mti.truth", &t.base, &h);
    ms_metrics_on_mti_truth (m, "mti.truth", &t.base, &h);
}

/* `entity` at t = 9.5 s: vehicle id at (east_m, 0) moving east at ve. */
static void s_entity (ms_metrics_t *m, uint32_t id, double east_m, double ve, Cgs__Force force,
                      bool transponder)
{
    Cgs__Enu p = CGS__ENU__INIT;
    Cgs__EnuVelocity v = CGS__ENU_VELOCITY__INIT;
    p.east_m = east_m;
    v.east_mps = ve;
    Cgs__Entity e = CGS__ENTITY__INIT, *ep = &e;
    e.entity_id = id;
    e.position = &p;
    e.velocity = &v;
    e.active = true;
    e.kind = CGS__ENTITY_KIND__ENTITY_KIND_WHEELED;
    e.force = force;
    e.bcis_transponder = transponder;
    Cgs__EntityBatch b = CGS__ENTITY_BATCH__INIT;
    b.n_entities = 1;
    b.entities = &ep;
    Cgs__Header h = CGS__HEADER__INIT;
    h.sim_time_s = 9.5;
    ms_metrics_on_entity (m, "entity", &b.base, &h);
}

static void s_entities (ms_metrics_t *m, Cgs__Force force, bool transponder)
{
    s_entity (m, 5, 1000, 10, force, transponder);
}

/* Track batch k of n of scan 1 with the tracks given (ids 10, 11, 12),
 * tracks 10 and 11 marked friendly with responder id friendly_id (0: not). */
static void s_tracks (ms_icpt_t *ic, ms_metrics_t *m, uint32_t k, uint32_t n, const int *which,
                      size_t count, uint32_t friendly_id)
{
    Cgs__Track t[3], *tp[3];
    Cgs__Enu pos[3];
    Cgs__TrackHistoryPoint hp = CGS__TRACK_HISTORY_POINT__INIT, *hpp = &hp;
    hp.hit_id = 101;
    const double e[3] = {1005, 3000, 500}, nn[3] = {30, 0, 0};
    for (size_t j = 0; j < count; j++) {
        int i = which[j];
        cgs__track__init (&t[j]);
        cgs__enu__init (&pos[j]);
        pos[j].east_m = e[i];
        pos[j].north_m = nn[i];
        t[j].track_id = (uint32_t)(10 + i);
        t[j].uav_id = 1;
        t[j].position = &pos[j];
        t[j].status = i == 2 ? CGS__TRACK_STATUS__TRACK_STATUS_TENTATIVE
                             : CGS__TRACK_STATUS__TRACK_STATUS_CONFIRMED;
        if (i == 0) {
            t[j].n_history = 1;
            t[j].history = &hpp;
        }
        if (i < 2 && friendly_id) {
            t[j].identity = CGS__TRACK_IDENTITY__TRACK_IDENTITY_FRIENDLY;
            t[j].friendly_id = friendly_id;
        }
        tp[j] = &t[j];
    }
    Cgs__TrackBatch b = CGS__TRACK_BATCH__INIT;
    b.uav_id = 1;
    b.scan_number = 1;
    b.batch_index = k;
    b.batch_count = n;
    b.n_tracks = count;
    b.tracks = tp;
    Cgs__Header h = CGS__HEADER__INIT;
    h.sim_time_s = 10.0;
    ms_metrics_on_track (m, "track", &b.base, &h);
    (void)ic;
}

/* Metrics over a new observer (*ret_ic, the caller's to free) fed radar 1's
 * `mti.truth` of scan 1 and vehicle 5 of the force given. */
static ms_metrics_t *s_metrics (ms_icpt_t **ret_ic, Cgs__Force force, bool transponder)
{
    ms_icpt_t *ic = calloc (1, sizeof *ic);
    assert_non_null (ic);
    ms_icpt_init (ic);
    ms_metrics_t *m = ms_metrics_new (ic);
    assert_non_null (m);
    s_truth (ic, m);
    s_entities (m, force, transponder);
    *ret_ic = ic;
    return m;
}

/* What the scan hook was told. */
static ms_metrics_scan_t s_scan_seen;
static int s_scans_seen;
static void s_on_scan (void *arg, const ms_metrics_scan_t *sc)
{
    (void)arg;
    s_scan_seen = *sc;
    s_scans_seen++;
}

static void test_one_scan (void **state)
{
    (void)state;
    ms_icpt_t *ic;
    ms_metrics_t *m = s_metrics (&ic, CGS__FORCE__FORCE_FRIENDLY, true);
    s_scans_seen = 0;
    ms_metrics_on_scan (m, s_on_scan, NULL);
    // Batch 1 of 2: nothing yet.
    const int first[] = {0, 2};
    s_tracks (ic, m, 0, 2, first, 2, 5);
    assert_int_equal (ms_metrics_gospa (m)->scans, 0);
    const int second[] = {1};
    s_tracks (ic, m, 1, 2, second, 1, 5);
    const ms_gospa_mean_t *g = ms_metrics_gospa (m);
    assert_int_equal (g->scans, 1);
    assert_true (fabs (g->distance - sqrt (125900.0)) < 1e-9);
    assert_true (fabs (g->localisation - 900) < 1e-9);
    assert_true (g->missed == 0);
    assert_true (fabs (g->false_ - 125000) < 1e-9);
    // The hook heard the scan once, with the same figures.
    assert_int_equal (s_scans_seen, 1);
    assert_int_equal (s_scan_seen.uav_id, 1);
    assert_true (s_scan_seen.t_s == 10.0);
    assert_true (fabs (s_scan_seen.gospa.distance - sqrt (125900.0)) < 1e-9);
    assert_int_equal (s_scan_seen.truths, 1);
    assert_int_equal (s_scan_seen.tracks, 2);
    assert_int_equal (s_scan_seen.tracked_truths, 1);
    assert_int_equal (s_scan_seen.unassociated, 1);
    ms_siap_result_t r;
    ms_siap_result (ms_metrics_siap (m), &r);
    assert_int_equal (r.truth_scans, 1);
    assert_int_equal (r.tracked_truth_scans, 1);
    assert_int_equal (r.track_scans, 2);
    assert_int_equal (r.associated_track_scans, 1);
    assert_true (r.completeness == 1 && r.ambiguity == 1 && r.spuriousness == 0.5);
    assert_true (fabs (r.position_accuracy_m - 30) < 1e-9);
    const ms_siap_id_t id = {
        .identifiable = 1, .identifiable_marked = 1, .marked = 1, .correct = 1};
    assert_memory_equal (&r.id, &id, sizeof id);
    assert_true (r.id_completeness == 1 && r.id_correctness == 1 && r.id_wrong_fraction == 0);
    assert_int_equal (ms_metrics_failures (m), 0);
    json_object *o = ms_metrics_json (m);
    assert_non_null (o);
    const char *json = json_object_to_json_string_ext (o, JSON_C_TO_STRING_PLAIN);
    assert_non_null (strstr (json, "{\"scans\":1,\"gospa_m\":354.8239,"));
    assert_non_null (strstr (json, "\"spuriousness\":0.5000,\"spuriousness_unseen\":0.0000,"));
    assert_non_null (strstr (json, "\"false_tracks_per_hour\":null,\"id_completeness\":1.0000,"
                                   "\"id_correctness\":1.0000,\"id_wrong_fraction\":0.0000,"
                                   "\"id_hostile_marked\":0}"));
    json_object_put (o);
    ms_metrics_destroy (&m);
    assert_null (m);
    free (ic);
}

// The same scan with vehicle 5 hostile: track 10's mark is the dangerous
// error, printed and in the JSON.
static void test_hostile_marked (void **state)
{
    (void)state;
    ms_icpt_t *ic;
    ms_metrics_t *m = s_metrics (&ic, CGS__FORCE__FORCE_HOSTILE, false);
    const int all[] = {0, 1, 2};
    s_tracks (ic, m, 0, 1, all, 3, 5);
    ms_siap_result_t r;
    ms_siap_result (ms_metrics_siap (m), &r);
    assert_int_equal (r.associated_track_scans, 1);
    const ms_siap_id_t id = {.marked = 1, .wrong = 1, .hostile_marked = 1};
    assert_memory_equal (&r.id, &id, sizeof id);
    assert_true (isnan (r.id_completeness) && r.id_correctness == 0 && r.id_wrong_fraction == 1);
    json_object *o = ms_metrics_json (m);
    assert_non_null (o);
    assert_non_null (strstr (json_object_to_json_string_ext (o, JSON_C_TO_STRING_PLAIN),
                             "\"id_completeness\":null,\"id_correctness\":0.0000,"
                             "\"id_wrong_fraction\":1.0000,\"id_hostile_marked\":1}"));
    json_object_put (o);
    char *text = NULL;
    size_t len = 0;
    FILE *f = open_memstream (&text, &len);
    assert_non_null (f);
    ms_metrics_print (m, f);
    assert_int_equal (fclose (f), 0);
    assert_non_null (
        strstr (text, "\n  completeness      1.000  ambiguity 1.000  spuriousness 0.500 (0.000 "
                      "tracks of vehicles the radar could not see)\n"));
    assert_non_null (strstr (text,
                             "\n  identification    ID completeness nan  ID correctness 0.000  "
                             "ID wrong 1.000; hostile marked friendly 1 (track-scans)\n"));
    free (text);
    ms_metrics_destroy (&m);
    free (ic);
}

/* A confirmed track of radar 1's scan 1 at (e, n) whose history holds hit_id. */
static void s_track_at (Cgs__Track *t, Cgs__Enu *pos, Cgs__TrackHistoryPoint *hp,
                        Cgs__TrackHistoryPoint **hpp, uint32_t id, double e, double n,
                        uint32_t hit_id)
{
    cgs__track__init (t);
    cgs__enu__init (pos);
    cgs__track_history_point__init (hp);
    pos->east_m = e;
    pos->north_m = n;
    hp->hit_id = hit_id;
    *hpp = hp;
    t->track_id = id;
    t->uav_id = 1;
    t->position = pos;
    t->status = CGS__TRACK_STATUS__TRACK_STATUS_COASTING;
    t->n_history = 1;
    t->history = hpp;
}

static void test_unseen_vehicle (void **state)
{
    (void)state;
    ms_icpt_t *ic;
    ms_metrics_t *m = s_metrics (&ic, CGS__FORCE__FORCE_HOSTILE, false);
    s_entity (m, 7, 5000, 0, CGS__FORCE__FORCE_HOSTILE, false);
    Cgs__Header h = CGS__HEADER__INIT;

    Cgs__Track t[3], *tp[3];
    Cgs__Enu pos[3];
    Cgs__TrackHistoryPoint hp[3], *hpp[3];
    s_track_at (&t[0], &pos[0], &hp[0], &hpp[0], 10, 1005, 30, 101);
    s_track_at (&t[1], &pos[1], &hp[1], &hpp[1], 14, 5000, 100, 102);
    s_track_at (&t[2], &pos[2], &hp[2], &hpp[2], 15, 5600, 0, 102);
    for (int i = 0; i < 3; i++)
        tp[i] = &t[i];
    Cgs__TrackBatch b = CGS__TRACK_BATCH__INIT;
    b.uav_id = 1;
    b.scan_number = 1;
    b.batch_count = 1;
    b.n_tracks = 3;
    b.tracks = tp;
    h.sim_time_s = 10.0;
    ms_metrics_on_track (m, "track", &b.base, &h);

    ms_siap_result_t r;
    ms_siap_result (ms_metrics_siap (m), &r);
    assert_int_equal (r.track_scans, 3);
    assert_int_equal (r.associated_track_scans, 1);
    assert_int_equal (r.unseen_track_scans, 1);
    assert_true (fabs (r.spuriousness - 2.0 / 3) < 1e-12);
    assert_true (fabs (r.spuriousness_unseen - 1.0 / 3) < 1e-12);
    json_object *o = ms_metrics_json (m);
    assert_non_null (o);
    assert_non_null (strstr (json_object_to_json_string_ext (o, JSON_C_TO_STRING_PLAIN),
                             "\"spuriousness\":0.6667,\"spuriousness_unseen\":0.3333,"));
    json_object_put (o);
    char *text = NULL;
    size_t len = 0;
    FILE *f = open_memstream (&text, &len);
    assert_non_null (f);
    ms_metrics_print (m, f);
    assert_int_equal (fclose (f), 0);
    assert_non_null (strstr (text, "  spuriousness 0.667 (0.333 tracks of vehicles the radar "
                                   "could not see)\n"));
    free (text);
    assert_int_equal (ms_metrics_failures (m), 0);
    ms_metrics_destroy (&m);
    free (ic);
}

int main (void)
{
    const struct CMUnitTest tests[] = {cmocka_unit_test (test_one_scan),
                                       cmocka_unit_test (test_hostile_marked),
                                       cmocka_unit_test (test_unseen_vehicle)};
    return cmocka_run_group_tests (tests, NULL, NULL);
}
