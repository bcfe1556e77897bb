/* test_mti_azimuth — the radar's azimuth measurement: the beam-splitting
 * fit against a worked example and against a Monte Carlo of its own
 * error (the echo of each interval drawn here, independently of mti_radar:
 * a Rayleigh or constant amplitude through the two-way Gaussian pattern,
 * plus complex Gaussian noise), and the monopulse form against Barton's. */
#include "mti_azimuth.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>

#include "test_util.h"

/* The default radar: 3 degree beam, 3 degree dwell, 4 intervals. */
#define S_TH 3.0
#define S_W  3.0
#define S_N  4

static void s_looks (double *x)
{
    for (int c = 0; c < S_N; c++)
        x[c] = mti_azimuth_look_deg (S_W, S_N, c);
}

/* The looks of 4 intervals across 3 degrees, from the dwell's centre. */
static void test_looks (void **state)
{
    (void)state;
    double x[S_N];
    s_looks (x);
    assert_near (x[0], -1.125, 1e-12);
    assert_near (x[1], -0.375, 1e-12);
    assert_near (x[2], 0.375, 1e-12);
    assert_near (x[3], 1.125, 1e-12);
}

/* Worked by hand. Powers that follow the pattern exactly give the target's
 * direction whatever their common scale. With every power very large the
 * weights are all 1/(π²/6) = 0.6079; Σ (x − x̄)² = 2 (0.375² + 1.125²) =
 * 2.8125; b = 8 ln 2 / 9 = 0.61614; σ = 1 / (2 b √(0.6079 × 2.8125)) =
 * 1 / (1.23228 × 1.30757) = 0.62062 degrees: the floor. */
static void test_worked_example (void **state)
{
    (void)state;
    double x[S_N], y[S_N], u = 0.4, b = 8 * M_LN2 / (S_TH * S_TH), est, sigma;
    s_looks (x);
    for (double scale = 1e8; scale < 1e13; scale *= 100) {
        for (int c = 0; c < S_N; c++)
            y[c] = scale * exp (-b * (u - x[c]) * (u - x[c]));
        assert_int_equal (
            mti_azimuth_beam_split (y, x, S_N, S_TH, S_W, MTI_AZIMUTH_LN_EXP_VAR, &est, &sigma), 0);
        assert_near (est, 0.4, 1e-9);
        assert_near (sigma, 0.62062, 2e-5);
    }
    // Without the fluctuation allowance, the noise alone: at y = 1e8 each
    // weight is about y/2, σ tiny.
    assert_int_equal (mti_azimuth_beam_split (y, x, S_N, S_TH, S_W, 0, &est, &sigma), 0);
    assert_near (est, 0.4, 1e-9);
    assert_true (sigma < 1e-3);
    // Powers rising steeply to one side: the estimate is held to the dwell
    // and half a beam, 3 degrees from the centre.
    for (int c = 0; c < S_N; c++)
        y[c] = exp (10.0 * c);
    assert_int_equal (mti_azimuth_beam_split (y, x, S_N, S_TH, S_W, 1, &est, &sigma), 0);
    assert_near (est, 3.0, 1e-12);
    // Bad arguments.
    assert_int_equal (mti_azimuth_beam_split (y, x, 1, S_TH, S_W, 1, &est, &sigma), -EINVAL);
    y[2] = 0;
    assert_int_equal (mti_azimuth_beam_split (y, x, S_N, S_TH, S_W, 1, &est, &sigma), -EINVAL);
    y[2] = 1;
    assert_int_equal (mti_azimuth_beam_split (y, x, S_N, 0, S_W, 1, &est, &sigma), -EINVAL);
    double same[S_N] = {0.5, 0.5, 0.5, 0.5};
    assert_int_equal (mti_azimuth_beam_split (y, same, S_N, S_TH, S_W, 1, &est, &sigma), -EINVAL);
}

/* Barton's thermal-noise error of monopulse, θ / (1.6 √(2 SINR)), held to
 * the uniform spread over the beam. */
static void test_monopulse (void **state)
{
    (void)state;
    assert_near (mti_azimuth_monopulse_sigma (3, 100), 3 / (1.6 * sqrt (200)), 1e-12);
    assert_near (mti_azimuth_monopulse_sigma (3, 0.01), 3 / sqrt (12), 1e-12);
}

/* Fluctuation models the Monte Carlo draws. */
enum { S_CONSTANT, S_DWELL, S_INTERVAL };

/* Monte Carlo of the fit: trials targets uniform across the dwell, each
 * interval's echo of mean SINR snr at the beam's centre through the
 * pattern, plus unit complex noise. Returns rms error (degrees) and rms of
 * error / reported sigma. */
static void s_mc (gsl_rng *rng, int model, double snr_db, int trials, double *ret_deg,
                  double *ret_z)
{
    double x[S_N], y[S_N], b = 8 * M_LN2 / (S_TH * S_TH), s = pow (10, snr_db / 10);
    s_looks (x);
    double e2 = 0, z2 = 0;
    for (int i = 0; i < trials; i++) {
        double u = S_W * (gsl_rng_uniform (rng) - 0.5);
        double f = model == S_DWELL ? gsl_ran_exponential (rng, 1) : 1;
        for (int c = 0; c < S_N; c++) {
            if (model == S_INTERVAL)
                f = gsl_ran_exponential (rng, 1);
            double a = sqrt (s * f * exp (-b * (u - x[c]) * (u - x[c])));
            double re = a + gsl_ran_gaussian (rng, M_SQRT1_2),
                   im = gsl_ran_gaussian (rng, M_SQRT1_2);
            y[c] = re * re + im * im;
        }
        double est, sigma;
        assert_int_equal (
            mti_azimuth_beam_split (y, x, S_N, S_TH, S_W, MTI_AZIMUTH_LN_EXP_VAR, &est, &sigma), 0);
        e2 += (est - u) * (est - u);
        z2 += (est - u) * (est - u) / (sigma * sigma);
    }
    *ret_deg = sqrt (e2 / trials);
    *ret_z = sqrt (z2 / trials);
}

/* A target drawn anew each interval (the radar hops): the reported sigma is
 * the spread (rms of error / sigma within 10% of 1) and the error does not
 * fall below the floor as the SNR grows. A target steady over the dwell:
 * the reported sigma is cautious (never below the spread), and the error
 * falls with the SNR (at
 * 30 dB within 15% of the fit's linearised error). 20,000 trials a case: the rms of a unit-variance
 * ratio has a standard error under 1% there. */
static void test_monte_carlo (void **state)
{
    (void)state;
    gsl_rng *rng = gsl_rng_alloc (gsl_rng_mt19937);
    gsl_rng_set (rng, 26);
    const int trials = 20000;
    double deg, z;
    const double snrs[] = {13, 20, 30};
    for (size_t i = 0; i < sizeof snrs / sizeof snrs[0]; i++) {
        s_mc (rng, S_INTERVAL, snrs[i], trials, &deg, &z);
        print_message ("# interval fluctuation, %2.0f dB: rms %.3f deg, error/sigma %.3f\n",
                       snrs[i], deg, z);
        assert_near (z, 1.0, 0.1);
        assert_true (deg > 0.55 && deg < 0.9);
    }
    double prev = INFINITY;
    for (size_t i = 0; i < sizeof snrs / sizeof snrs[0]; i++) {
        s_mc (rng, S_DWELL, snrs[i], trials, &deg, &z);
        print_message ("# dwell fluctuation,    %2.0f dB: rms %.3f deg, error/sigma %.3f "
                       "(monopulse at that SINR: %.3f deg)\n",
                       snrs[i], deg, z, mti_azimuth_monopulse_sigma (S_TH, pow (10, snrs[i] / 10)));
        assert_true (z < 1.0 && deg < prev);
        prev = deg;
        s_mc (rng, S_CONSTANT, snrs[i], trials, &deg, &z);
        print_message ("# constant,             %2.0f dB: rms %.3f deg, error/sigma %.3f\n",
                       snrs[i], deg, z);
        assert_true (z < 0.8);
    }
    // The constant target at 30 dB against the linearised error of the fit
    // it makes (uniform weights, as the allowance makes them): û is
    // Σ (x_c − x̄) z_c / (2 b Σ (x − x̄)²), z_c of variance 2 / ȳ_c (at most
    // π²/6), ȳ_c the pattern's mean power; averaged over the target's place.
    double x[S_N], b = 8 * M_LN2 / (S_TH * S_TH), s = 1000, v = 0, sxx = 0;
    s_looks (x);
    for (int c = 0; c < S_N; c++)
        sxx += x[c] * x[c]; // x̄ = 0
    const int places = 300;
    for (int k = 0; k < places; k++) {
        double u = S_W * ((k + 0.5) / places - 0.5);
        for (int c = 0; c < S_N; c++) {
            double y = 1 + s * exp (-b * (u - x[c]) * (u - x[c]));
            double g = x[c] / (2 * b * sxx);
            v += g * g * fmin (2 / y, MTI_AZIMUTH_LN_EXP_VAR) / places;
        }
    }
    s_mc (rng, S_CONSTANT, 30, trials, &deg, &z);
    print_message ("# constant, 30 dB: rms %.3f deg; linearised %.3f deg\n", deg, sqrt (v));
    assert_near (deg / sqrt (v), 1.0, 0.15);
    gsl_rng_free (rng);
}

int main (void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test (test_looks),
        cmocka_unit_test (test_worked_example),
        cmocka_unit_test (test_monopulse),
        cmocka_unit_test (test_monte_carlo),
    };
    return cmocka_run_group_tests (tests, NULL, NULL);
}
