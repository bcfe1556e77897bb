/* test_flight — the coordinated-turn radius V²/(g·tan φ) against worked
 * examples: 38 m/s banked 30° turns in 1444 / (9.80665 × 0.577350) =
 * 255.04 m; 20 m/s at 45° in 400 / 9.80665 = 40.789 m; doubling the speed
 * quadruples the radius. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "cgs_flight.h"

#include <math.h>

static void test_turn_radius (void **state)
{
    (void)state;
    assert_true (fabs (cgs_flight_turn_radius (38, 30) - 255.04) < 0.01);
    assert_true (fabs (cgs_flight_turn_radius (20, 45) - 40.789) < 0.001);
    double r = cgs_flight_turn_radius (25, 20);
    assert_true (fabs (cgs_flight_turn_radius (50, 20) / r - 4.0) < 1e-12);
}

int main (void)
{
    const struct CMUnitTest tests[] = {cmocka_unit_test (test_turn_radius)};
    return cmocka_run_group_tests (tests, NULL, NULL);
}
