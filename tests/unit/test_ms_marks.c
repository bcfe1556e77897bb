/* test_ms_marks — the intercept's changes as marks on a time line
 * (ms_marks), from a hand-made sequence of `intercept` messages of two
 * UAVs: a designation and its first phase, a phase change with its reason,
 * a re-plan, a hand-over to another track of the same designation, a
 * cancel, a second designation; nothing for a message that changes none of
 * them, nor for a first message that is idle. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "ms_marks.h"

#include <string.h>

static void s_take (ms_marks_t *m, uint32_t uav, uint64_t designation, uint32_t track,
                    Cgs__InterceptState state, uint32_t replans, const char *reason, double t)
{
    Cgs__Intercept i = CGS__INTERCEPT__INIT;
    i.uav_id = uav;
    i.designation_number = designation;
    i.track_id = track;
    i.state = state;
    i.replans = replans;
    i.reason = (char *)reason;
    assert_int_equal (ms_marks_add (m, &i, t), 0);
}

static void s_is (const ms_marks_t *m, size_t k, double t, const char *kind, const char *text,
                  uint32_t uav)
{
    assert_true (k < m->n);
    assert_true (m->marks[k].t_s == t);
    assert_string_equal (m->marks[k].kind, kind);
    assert_string_equal (m->marks[k].text, text);
    assert_int_equal (m->marks[k].uav_id, uav);
}

static void test_marks (void **state)
{
    (void)state;
    ms_marks_t m = {0};
    s_take (&m, 1, 0, 0, CGS__INTERCEPT_STATE__INTERCEPT_STATE_IDLE, 0, "", 1);
    s_take (&m, 1, 0, 0, CGS__INTERCEPT_STATE__INTERCEPT_STATE_IDLE, 0, "", 2);
    assert_int_equal (m.n, 0); // idle from the start: nothing happened
    s_take (&m, 1, 1, 49, CGS__INTERCEPT_STATE__INTERCEPT_STATE_TO_SECONDARY, 0, "designated", 3);
    assert_int_equal (m.n, 2);
    s_is (&m, 0, 3, "designate", "designate track 49", 1);
    s_is (&m, 1, 3, "phase", "TO_SECONDARY: designated", 1);
    s_take (&m, 1, 1, 49, CGS__INTERCEPT_STATE__INTERCEPT_STATE_TO_SECONDARY, 0, "designated", 4);
    assert_int_equal (m.n, 2); // no change
    s_take (&m, 1, 1, 49, CGS__INTERCEPT_STATE__INTERCEPT_STATE_TO_SECONDARY, 1, "", 5);
    s_is (&m, 2, 5, "replan", "re-plan 1", 1);
    s_take (&m, 1, 1, 52, CGS__INTERCEPT_STATE__INTERCEPT_STATE_APPROACH, 1, "", 6);
    s_is (&m, 3, 6, "handover", "track 49 to 52", 1);
    s_is (&m, 4, 6, "phase", "APPROACH", 1);
    // Another UAV's intercept is its own.
    s_take (&m, 2, 7, 8, CGS__INTERCEPT_STATE__INTERCEPT_STATE_TO_WAYPOINT, 3, "", 7);
    s_is (&m, 5, 7, "designate", "designate track 8", 2);
    s_is (&m, 6, 7, "phase", "TO_WAYPOINT", 2);
    assert_int_equal (m.n, 7); // its first message's re-plans are not a re-plan
    s_take (&m, 1, 1, 52, CGS__INTERCEPT_STATE__INTERCEPT_STATE_CANCELLED, 1, "operator", 8);
    s_is (&m, 7, 8, "cancel", "CANCELLED: operator", 1);
    // A new designation, of the same track: a designation, not a hand-over.
    s_take (&m, 1, 2, 52, CGS__INTERCEPT_STATE__INTERCEPT_STATE_TO_SECONDARY, 0, "", 9);
    s_is (&m, 8, 9, "designate", "designate track 52", 1);
    s_is (&m, 9, 9, "phase", "TO_SECONDARY", 1);
    assert_int_equal (m.n, 10);
    ms_marks_clear (&m);
    assert_int_equal (m.n, 0);
    assert_null (m.marks);
}

int main (void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test (test_marks),
    };
    return cmocka_run_group_tests (tests, NULL, NULL);
}
