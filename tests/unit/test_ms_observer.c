/* test_ms_observer — the intercept summary as JSON (summary.json's
 * members), from a filled ms_icpt_t: with nothing designated every member
 * but the two booleans is null; with a designation the ids, the state and
 * the times to the millisecond (designation at 120 s, first inside at
 * 250.1234 s: 130.123 s to image; 3.25 s inside; closest 1.23456 m at
 * 251 s), the marking escaped by json-c and its byte beyond ASCII (0xe9,
 * Latin-1 e-acute) read as Latin-1, so the text stays valid UTF-8 and
 * parses back. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "ms_observer.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* An intercept with nothing seen (free it). */
static ms_icpt_t *s_icpt (void)
{
    ms_icpt_t *ic = calloc (1, sizeof *ic);
    assert_non_null (ic);
    ms_icpt_init (ic);
    return ic;
}

/* ic's summary as JSON text on one line (free it); ic is freed. */
static char *s_text (ms_icpt_t *ic)
{
    json_object *o = ms_icpt_json (ic);
    assert_non_null (o);
    char *text = strdup (json_object_to_json_string_ext (o, JSON_C_TO_STRING_PLAIN));
    assert_non_null (text);
    json_object_put (o);
    free (ic);
    return text;
}

static void test_nothing_designated (void **state)
{
    (void)state;
    char *text = s_text (s_icpt ());
    assert_string_equal (
        text, "{\"designated\":false,\"track_id\":null,\"target_entity_id\":null,"
              "\"target_marking\":null,\"follows_entity_id\":null,"
              "\"handed_over_to_entity_id\":null,\"follows_since_s\":null,"
              "\"follows_after_unseen_s\":null,\"follows_gap_m\":null,"
              "\"designation_time_s\":null,\"final_state\":null,\"replans\":null,"
              "\"imaged\":false,\"time_in_footprint_s\":null,\"closest_approach_m\":null,"
              "\"closest_approach_time_s\":null,\"designation_to_overflight_s\":null}");
    free (text);
}

static void test_designated_and_imaged (void **state)
{
    (void)state;
    ms_icpt_t *ic = s_icpt ();
    ic->designated = true;
    ic->desig_track_id = 12;
    ic->entity_id = 4;
    snprintf (ic->marking, sizeof ic->marking, "U3 \"\xe9\"");
    ic->desig_state = CGS__INTERCEPT_STATE__INTERCEPT_STATE_DONE;
    ic->replans = 2;
    cgs_score_t *sc = &ic->score;
    sc->designated = true;
    sc->designation_s = 120;
    sc->imaged = true;
    sc->first_inside_s = 250.1234;
    sc->inside_s = 3.25;
    sc->closest_m = 1.23456;
    sc->closest_s = 251;
    char *text = s_text (ic);
    assert_string_equal (
        text, "{\"designated\":true,\"track_id\":12,\"target_entity_id\":4,"
              "\"target_marking\":\"U3 \\\"\xc3\xa9\\\"\",\"follows_entity_id\":null,"
              "\"handed_over_to_entity_id\":null,\"follows_since_s\":null,"
              "\"follows_after_unseen_s\":null,\"follows_gap_m\":null,"
              "\"designation_time_s\":120.000,\"final_state\":\"DONE\",\"replans\":2,"
              "\"imaged\":true,\"time_in_footprint_s\":3.250,\"closest_approach_m\":1.235,"
              "\"closest_approach_time_s\":251.000,\"designation_to_overflight_s\":130.123}");
    json_object *back = json_tokener_parse (text);
    assert_non_null (back);
    json_object *m;
    assert_true (json_object_object_get_ex (back, "target_marking", &m));
    assert_string_equal (json_object_get_string (m), "U3 \"\xc3\xa9\"");
    json_object_put (back);
    free (text);
}

/* A hand-over to another vehicle names it; a number that is not finite is
 * null, one that is prints its decimals. */
static void test_hand_over_and_numbers (void **state)
{
    (void)state;
    ms_icpt_t *ic = s_icpt ();
    ic->designated = true;
    ic->first_track_id = 7;
    ic->desig_track_id = 8; // track 8 took over from 7
    ic->other_entity_id = 9;
    char *text = s_text (ic);
    assert_non_null (strstr (text, "\"target_entity_id\":null,\"target_marking\":null,"
                                   "\"follows_entity_id\":9,\"handed_over_to_entity_id\":9,"));
    free (text);
    assert_null (cgs_json_fixed (NAN, 2));
    assert_null (cgs_json_fixed (-INFINITY, 2));
    json_object *n = cgs_json_fixed (-0.125, 2);
    assert_string_equal (json_object_to_json_string (n), "-0.12");
    json_object_put (n);
}

/* One scan's truth of radar 1: hit 100 + i came from entity[i]. */
static void s_feed_truth (ms_icpt_t *ic, const uint32_t *entity, size_t n)
{
    Cgs__MtiTruthItem it[8], *ip[8];
    for (size_t i = 0; i < n; i++) {
        cgs__mti_truth_item__init (&it[i]);
        it[i].entity_id = entity[i];
        it[i].detected = true;
        it[i].hit_id = (uint32_t)(100 + i);
        ip[i] = &it[i];
    }
    Cgs__MtiTruth t = CGS__MTI_TRUTH__INIT;
    t.uav_id = 1;
    t.n_items = n;
    t.items = ip;
    Cgs__Header h = CGS__HEADER__INIT;
    h.sim_time_s = 10;
    h.epoch = 1;
    ms_icpt_on_mti_truth (ic, "mti.truth", &t.base, &h);
}

/* Track `id` of radar 1 whose history holds hits 100 + first .. 100 + last,
 * hit 100 + k at 10·k s, 50·k m east of the origin. */
static void s_feed_track (ms_icpt_t *ic, uint32_t id, uint32_t first, uint32_t last, double t_s)
{
    Cgs__TrackHistoryPoint hp[8], *hpp[8];
    Cgs__Enu at[8];
    size_t n = 0;
    for (uint32_t k = first; k <= last; k++, n++) {
        cgs__track_history_point__init (&hp[n]);
        cgs__enu__init (&at[n]);
        at[n].east_m = 50.0 * k;
        hp[n].hit_id = 100 + k;
        hp[n].sim_time_s = 10.0 * k;
        hp[n].position = &at[n];
        hpp[n] = &hp[n];
    }
    Cgs__Track tr = CGS__TRACK__INIT, *trp = &tr;
    tr.track_id = id;
    tr.uav_id = 1;
    tr.n_history = n;
    tr.history = hpp;
    Cgs__TrackBatch b = CGS__TRACK_BATCH__INIT;
    b.uav_id = 1;
    b.n_tracks = 1;
    b.tracks = &trp;
    Cgs__Header h = CGS__HEADER__INIT;
    h.sim_time_s = t_s;
    ms_icpt_on_track (ic, "track", &b.base, &h);
}

/* The operator designates track `id` at t_s. */
static void s_designate (ms_icpt_t *ic, uint32_t id, double t_s)
{
    Cgs__Intercept m = CGS__INTERCEPT__INIT;
    m.track_id = id;
    m.designation_number = 1;
    Cgs__Header h = CGS__HEADER__INIT;
    h.sim_time_s = t_s;
    ms_icpt_on_intercept (ic, "intercept", &m.base, &h);
}

/* Entities 5 and 6 at time t_s, at (0, 0) and (e6, n6). */
static void s_feed_entities (ms_icpt_t *ic, double t_s, double e6, double n6)
{
    Cgs__Entity en[2], *enp[2];
    Cgs__Enu pos[2];
    static char *marking[2] = {"U APC1", "U APC2"};
    for (int i = 0; i < 2; i++) {
        cgs__entity__init (&en[i]);
        cgs__enu__init (&pos[i]);
        en[i].entity_id = (uint32_t)(5 + i);
        en[i].active = true;
        en[i].position = &pos[i];
        en[i].marking = marking[i];
        enp[i] = &en[i];
    }
    pos[1].east_m = e6;
    pos[1].north_m = n6;
    Cgs__EntityBatch b = CGS__ENTITY_BATCH__INIT;
    b.n_entities = 2;
    b.entities = enp;
    Cgs__Header h = CGS__HEADER__INIT;
    h.sim_time_s = t_s;
    ms_icpt_on_entity (ic, "entity", &b.base, &h);
}

/* The designated track itself changes vehicle (most of its kept hits come
 * from another): the run is on the wrong vehicle as much as after a
 * hand-over (mscgs montecarlo counted only hand-overs), and the summary
 * says which; when its hits are the designated vehicle's again, it is not. */
static void test_track_changes_vehicle (void **state)
{
    (void)state;
    ms_icpt_t *ic = s_icpt ();
    const uint32_t entity[6] = {5, 5, 5, 6, 6, 6}; // hits 100-102 of 5, 103-105 of 6
    s_feed_truth (ic, entity, 6);
    s_designate (ic, 10, 11);
    s_feed_track (ic, 10, 0, 2, 11);
    assert_int_equal (ic->entity_id, 5);
    assert_int_equal (ic->other_entity_id, 0);
    // The designated vehicle (5) stands at the origin from 20 s on (once
    // every half second remembered), 6 drives.
    for (int k = 0; k <= 40; k++)
        s_feed_entities (ic, 20 + 0.25 * k, 30 + k, 0);
    s_feed_track (ic, 10, 1, 5, 52); // two hits of 5, three of 6
    assert_int_equal (ic->other_entity_id, 6);
    // Its hits of 6 since the first of them (hit 103 at 30 s, 150 m east),
    // 10 s after its hit before (of 5), 150 m from where 5 was then.
    assert_true (ic->other_since_s == 30 && ic->other_unseen_s == 10);
    assert_true (fabs (ic->other_gap_m - 150) < 1e-9);
    s_feed_entities (ic, 53, 300, 0); // its marking, and nothing else changes
    assert_true (fabs (ic->other_gap_m - 150) < 1e-9);
    char *line = NULL;
    size_t len = 0;
    FILE *f = open_memstream (&line, &len);
    assert_non_null (f);
    ms_icpt_print (ic, f);
    fclose (f);
    assert_non_null (strstr (line, "changed vehicle   track 10 now follows entity 6 \"U APC2\""));
    assert_non_null (strstr (line, "its hits of it since sim 30.0 s (the first after 10 s without "
                                   "a hit), the first 150 m from the designated target"));
    free (line);
    s_feed_track (ic, 10, 0, 4, 13); // three of 5, two of 6: back on it
    assert_int_equal (ic->other_entity_id, 0);
    assert_true (isnan (ic->other_since_s) && isnan (ic->other_gap_m));
    s_feed_track (ic, 10, 3, 5, 14);
    char *text = s_text (ic);
    assert_non_null (strstr (text, "\"follows_entity_id\":6,\"handed_over_to_entity_id\":null,"
                                   "\"follows_since_s\":30.000,\"follows_after_unseen_s\":null,"
                                   "\"follows_gap_m\":150.0,"));
    free (text);
}

/* The track's hits turned to another vehicle and its newest hit is the
 * designated one's again (most are still the other's): the change is dated
 * from the first hit of the latest run of the other's, not the message. */
static void test_changed_vehicle_then_a_hit_back (void **state)
{
    (void)state;
    ms_icpt_t *ic = s_icpt ();
    const uint32_t entity[6] = {5, 5, 6, 6, 6, 5}; // hits 100-101 of 5, 102-104 of 6, 105 of 5
    s_feed_truth (ic, entity, 6);
    s_designate (ic, 10, 11);
    s_feed_track (ic, 10, 0, 1, 11);
    assert_int_equal (ic->entity_id, 5);
    s_feed_track (ic, 10, 1, 5, 60); // one of 5, three of 6, then one of 5
    assert_int_equal (ic->other_entity_id, 6);
    // Since hit 102 at 20 s, 10 s after hit 101 (before, its message's
    // time and no interval: the newest hit is not 6's).
    assert_true (ic->other_since_s == 20 && ic->other_unseen_s == 10);
    free (ic);
}

int main (void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test (test_nothing_designated),
        cmocka_unit_test (test_designated_and_imaged),
        cmocka_unit_test (test_hand_over_and_numbers),
        cmocka_unit_test (test_track_changes_vehicle),
        cmocka_unit_test (test_changed_vehicle_then_a_hit_back),
    };
    return cmocka_run_group_tests (tests, NULL, NULL);
}
