/* cgs_stats: the Clopper-Pearson interval at every count of the Monte
 * Carlo's run counts (500 runs of the default scene, 1000, 2000), where
 * GSL's own beta inverse fails to converge for some (484 of 500 imaged
 * aborted `mscgs montecarlo` after its last run); each end checked against
 * its defining equation with GSL's binomial distribution, and the ends at
 * k = 0 and k = n against their closed forms. */
#include "cgs_stats.h"
#include "test_util.h"

#include <errno.h>
#include <gsl/gsl_cdf.h>
#include <math.h>

static void test_every_count (void **state)
{
    (void)state;
    const unsigned long ns[] = {20, 100, 500, 1000, 2000};
    for (size_t i = 0; i < sizeof ns / sizeof ns[0]; i++) {
        unsigned long n = ns[i];
        double prev_lo = -1, prev_hi = -1;
        for (unsigned long k = 0; k <= n; k++) {
            double lo = NAN, hi = NAN;
            if (cgs_binomial_interval (k, n, 0.95, &lo, &hi) != 0)
                fail_msg ("no interval for %lu of %lu", k, n);
            double p = (double)k / (double)n;
            if (!(lo >= 0 && lo <= p && p <= hi && hi <= 1) || !(lo > prev_lo) || !(hi > prev_hi))
                fail_msg ("%lu of %lu: [%g, %g] after [%g, %g]", k, n, lo, hi, prev_lo, prev_hi);
            // The ends solve P(X >= k | lo) = 0.025 and P(X <= k | hi) = 0.025.
            if (k > 0)
                assert_rel (gsl_cdf_binomial_Q ((unsigned)k - 1, lo, (unsigned)n), 0.025, 1e-6);
            if (k < n)
                assert_rel (gsl_cdf_binomial_P ((unsigned)k, hi, (unsigned)n), 0.025, 1e-6);
            prev_lo = lo;
            prev_hi = hi;
        }
        double lo, hi;
        assert_int_equal (cgs_binomial_interval (n, n, 0.95, &lo, &hi), 0);
        assert_rel (lo, pow (0.025, 1.0 / (double)n), 1e-9);
        assert_true (hi == 1);
        assert_int_equal (cgs_binomial_interval (0, n, 0.95, &lo, &hi), 0);
        assert_true (lo == 0);
        assert_rel (hi, 1 - pow (0.025, 1.0 / (double)n), 1e-9);
    }
}

static void test_bad_arguments (void **state)
{
    (void)state;
    double lo = 7, hi = 7;
    assert_int_equal (cgs_binomial_interval (11, 10, 0.95, &lo, &hi), -EINVAL);
    assert_int_equal (cgs_binomial_interval (5, 10, 1.0, &lo, &hi), -EINVAL);
    assert_int_equal (cgs_binomial_interval (5, 10, 0.0, &lo, &hi), -EINVAL);
    assert_true (lo == 7 && hi == 7); // written only on success
}

int main (void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test (test_every_count),
        cmocka_unit_test (test_bad_arguments),
    };
    return cmocka_run_group_tests (tests, NULL, NULL);
}
