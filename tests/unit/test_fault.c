/* test_fault — the fault channel's checks and schedule (cgs_fault): a crash
 * or a hang waits for cgs_fault_take and is taken once; a second one while
 * one is pending is refused; a slow-down stalls every period until its end
 * and no longer (0 seconds: for ever); out-of-range seconds and stalls, and
 * unknown actions, are refused with the reason and change nothing. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "cgs_fault.h"

#include <errno.h>
#include <math.h>
#include <string.h>

static Cgs__Fault s_fault (Cgs__FaultAction a, double seconds, unsigned stall_ms)
{
    Cgs__Fault f = CGS__FAULT__INIT;
    f.action = a;
    f.seconds = seconds;
    f.stall_ms = stall_ms;
    return f;
}

static void test_crash_and_hang_taken_once (void **state)
{
    (void)state;
    cgs_fault_t fl = {0};
    char why[256] = "";
    double hang = -1;
    assert_int_equal (cgs_fault_take (&fl, &hang), CGS__FAULT_ACTION__FAULT_ACTION_UNSPECIFIED);
    Cgs__Fault crash = s_fault (CGS__FAULT_ACTION__FAULT_ACTION_CRASH, 0, 0);
    assert_int_equal (cgs_fault_request (&fl, &crash, 5.0, why, sizeof why), 0);
    Cgs__Fault h = s_fault (CGS__FAULT_ACTION__FAULT_ACTION_HANG, 12.5, 0);
    assert_int_equal (cgs_fault_request (&fl, &h, 5.0, why, sizeof why), -EINVAL);
    assert_non_null (strstr (why, "a crash is already pending"));
    assert_int_equal (cgs_fault_take (&fl, &hang), CGS__FAULT_ACTION__FAULT_ACTION_CRASH);
    assert_int_equal (cgs_fault_take (&fl, &hang), CGS__FAULT_ACTION__FAULT_ACTION_UNSPECIFIED);
    assert_int_equal (cgs_fault_request (&fl, &h, 6.0, why, sizeof why), 0);
    assert_int_equal (cgs_fault_take (&fl, &hang), CGS__FAULT_ACTION__FAULT_ACTION_HANG);
    assert_true (hang == 12.5);
    assert_int_equal (fl.requests, 2);
    // Neither slows the loop.
    assert_int_equal (cgs_fault_stall_ms (&fl, 6.0), 0);
}

static void test_slow_until_its_end (void **state)
{
    (void)state;
    cgs_fault_t fl = {0};
    char why[256] = "";
    Cgs__Fault f = s_fault (CGS__FAULT_ACTION__FAULT_ACTION_SLOW, 2.0, 40);
    assert_int_equal (cgs_fault_request (&fl, &f, 100.0, why, sizeof why), 0);
    // Every period from 100 s to just before 102 s stalls 40 ms: 20 periods.
    unsigned total = 0;
    for (int k = 0; k < 30; k++)
        total += cgs_fault_stall_ms (&fl, 100.0 + k * CGS_FAULT_PERIOD_S + 1e-9);
    assert_int_equal (total, 20 * 40);
    assert_int_equal (cgs_fault_stall_ms (&fl, 101.0), 0); // ended stays ended
    // 0 seconds: until the process ends; a new request replaces the stall.
    Cgs__Fault ever = s_fault (CGS__FAULT_ACTION__FAULT_ACTION_SLOW, 0, 90);
    assert_int_equal (cgs_fault_request (&fl, &ever, 200.0, why, sizeof why), 0);
    assert_int_equal (cgs_fault_stall_ms (&fl, 1e9), 90);
    Cgs__Fault less = s_fault (CGS__FAULT_ACTION__FAULT_ACTION_SLOW, 1.0, 1);
    assert_int_equal (cgs_fault_request (&fl, &less, 300.0, why, sizeof why), 0);
    assert_int_equal (cgs_fault_stall_ms (&fl, 300.5), 1);
    assert_int_equal (cgs_fault_stall_ms (&fl, 301.0), 0);
}

static void s_refused (Cgs__Fault f, const char *reason)
{
    cgs_fault_t fl = {0};
    char why[256] = "";
    assert_int_equal (cgs_fault_request (&fl, &f, 1.0, why, sizeof why), -EINVAL);
    if (!strstr (why, reason))
        fail_msg ("'%s' does not say '%s'", why, reason);
    double hang = 0;
    assert_int_equal (cgs_fault_take (&fl, &hang), CGS__FAULT_ACTION__FAULT_ACTION_UNSPECIFIED);
    assert_int_equal (cgs_fault_stall_ms (&fl, 1.0), 0);
    assert_int_equal (fl.requests, 0);
}

static void test_bad_requests (void **state)
{
    (void)state;
    s_refused (s_fault (CGS__FAULT_ACTION__FAULT_ACTION_SLOW, 5, 0), "1 to 90 ms");
    s_refused (s_fault (CGS__FAULT_ACTION__FAULT_ACTION_SLOW, 5, 91), "got 91 ms");
    s_refused (s_fault (CGS__FAULT_ACTION__FAULT_ACTION_HANG, -1, 0), "got -1");
    s_refused (s_fault (CGS__FAULT_ACTION__FAULT_ACTION_HANG, 3601, 0), "0 (until the process");
    s_refused (s_fault (CGS__FAULT_ACTION__FAULT_ACTION_SLOW, NAN, 10), "got nan");
    s_refused (s_fault (CGS__FAULT_ACTION__FAULT_ACTION_UNSPECIFIED, 0, 0),
               "unknown fault action 0");
    s_refused (s_fault ((Cgs__FaultAction)7, 0, 0), "unknown fault action 7");
    cgs_fault_t fl = {0};
    char why[64];
    assert_int_equal (cgs_fault_request (&fl, NULL, 0, why, sizeof why), -EINVAL);
    assert_string_equal (cgs_fault_name (CGS__FAULT_ACTION__FAULT_ACTION_SLOW), "slow");
    assert_string_equal (cgs_fault_name ((Cgs__FaultAction)9), "?");
}

int main (void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test (test_crash_and_hang_taken_once),
        cmocka_unit_test (test_slow_until_its_end),
        cmocka_unit_test (test_bad_requests),
    };
    return cmocka_run_group_tests (tests, NULL, NULL);
}
