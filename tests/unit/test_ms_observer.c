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
              "\"target_marking\":null,\"handed_over_to_entity_id\":null,"
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
              "\"target_marking\":\"U3 \\\"\xc3\xa9\\\"\",\"handed_over_to_entity_id\":null,"
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
    ic->other_entity_id = 9;
    char *text = s_text (ic);
    assert_non_null (strstr (text, "\"target_entity_id\":null,\"target_marking\":null,"
                                   "\"handed_over_to_entity_id\":9,"));
    free (text);
    assert_null (cgs_json_fixed (NAN, 2));
    assert_null (cgs_json_fixed (-INFINITY, 2));
    json_object *n = cgs_json_fixed (-0.125, 2);
    assert_string_equal (json_object_to_json_string (n), "-0.12");
    json_object_put (n);
}

int main (void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test (test_nothing_designated),
        cmocka_unit_test (test_designated_and_imaged),
        cmocka_unit_test (test_hand_over_and_numbers),
    };
    return cmocka_run_group_tests (tests, NULL, NULL);
}
