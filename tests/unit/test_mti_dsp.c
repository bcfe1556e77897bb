/* The MTI processing chain checked against detection theory: the CA-CFAR
 * threshold and its false-alarm rate, Pd against SNR for Swerling I/II and
 * the constant target, pulse-to-pulse Swerling II's lack of coherent gain,
 * the cancellers' improvement factors on Gaussian clutter, m-of-n against
 * the binomial sum, the 2-of-4 dwell of Swerling I and interval Swerling II,
 * slow and fast targets in strong clutter, the chain's mean power against its
 * exact response, and the statistical false-alarm model against full
 * processing of a strip of range cells. Each Monte Carlo figure is compared
 * with the closed form written out here or in mti_theory (itself checked
 * against published values in test_mti_theory). */
#include "cgs_stats.h"
#include "mti_dsp.h"
#include "mti_mc.h"
#include "mti_params.h"
#include "mti_theory.h"

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

/* Pd of Swerling I/II under CA-CFAR, written out from the textbook. */
static double s_pd_sw (double snr, double t, int n)
{
    return pow (1.0 + t / (1.0 + snr), -n);
}

static mti_mc_result_t s_mc (mti_swerling_t sw, double snr_db, unsigned long trials, double pfa,
                             uint64_t seed)
{
    mti_mc_config_t c;
    mti_mc_defaults (&c);
    c.swerling = sw;
    c.snr_db = snr_db;
    c.trials = trials;
    c.pfa = pfa;
    c.seed = seed;
    mti_mc_result_t r;
    char err[256];
    assert_int_equal (mti_mc_run (&c, &r, err, sizeof err), 0);
    return r;
}

/* T = Pfa^(-1/N) - 1, and the measured Pfa over >= 100 expected false
 * alarms falls in the 99% binomial interval of the design value. */
static void test_cfar_threshold_and_pfa (void **state)
{
    (void)state;
    double pfa = 1e-3;
    mti_mc_result_t r = s_mc (MTI_SWERLING_1, 10, 4000, pfa, 11);
    assert_near (r.threshold, pow (pfa, -1.0 / 16) - 1.0, 1e-12);
    double expected = pfa * r.fa_cells;
    assert_true (expected >= 100);
    print_message (
        "# Pfa design %g: %lu false alarms in %lu cells (expected %.0f, 99%% [%lu, %lu])\n", pfa,
        r.false_alarms, r.fa_cells, expected, r.fa_lo, r.fa_hi);
    assert_in_range (r.false_alarms, r.fa_lo, r.fa_hi);
    // The same at the default 1e-4 over 128 expected.
    r = s_mc (MTI_SWERLING_1, 10, 32000, 1e-4, 12);
    assert_true (1e-4 * r.fa_cells >= 100);
    print_message ("# Pfa design 1e-4: %lu false alarms in %lu cells (99%% [%lu, %lu])\n",
                   r.false_alarms, r.fa_cells, r.fa_lo, r.fa_hi);
    assert_in_range (r.false_alarms, r.fa_lo, r.fa_hi);
}

/* Swerling I in one Doppler cell: Pd = (1 + T/(1+SNR))^-N within 0.02, 10,000 trials a point. */
static void test_pd_swerling1 (void **state)
{
    (void)state;
    const double snrs[] = {5, 10, 15, 20, 25};
    for (size_t i = 0; i < sizeof snrs / sizeof *snrs; i++) {
        mti_mc_result_t r = s_mc (MTI_SWERLING_1, snrs[i], 10000, 1e-4, 100 + i);
        double th = s_pd_sw (pow (10, snrs[i] / 10), r.threshold, 16);
        print_message ("# Swerling I  %4.1f dB: Pd %.4f, theory %.4f\n", snrs[i], r.pd, th);
        assert_near (r.pd_theory, th, 1e-12);
        assert_near (r.pd, th, 0.02);
    }
}

/* The constant target against Marcum's Q averaged over the CA-CFAR sum. */
static void test_pd_constant (void **state)
{
    (void)state;
    const double snrs[] = {8, 11, 13, 15, 17};
    for (size_t i = 0; i < sizeof snrs / sizeof *snrs; i++) {
        mti_mc_result_t r = s_mc (MTI_SWERLING_0, snrs[i], 10000, 1e-4, 200 + i);
        double th = mti_theory_pd_constant_cacfar (pow (10, snrs[i] / 10), r.threshold, 16);
        print_message ("# constant    %4.1f dB: Pd %.4f, theory %.4f\n", snrs[i], r.pd, th);
        assert_near (r.pd, th, 0.02);
    }
}

/* Swerling II pulse to pulse: the FFT gathers none of its energy into one
 * bin, so its Pd is that of the per-pulse SNR, far below Swerling I's. */
static void test_swerling2_no_coherent_gain (void **state)
{
    (void)state;
    const double snrs[] = {20, 27, 32};
    for (size_t i = 0; i < sizeof snrs / sizeof *snrs; i++) {
        mti_mc_result_t r2 = s_mc (MTI_SWERLING_2_PULSE, snrs[i], 10000, 1e-4, 300 + i);
        mti_mc_result_t r1 = s_mc (MTI_SWERLING_1, snrs[i], 10000, 1e-4, 310 + i);
        double pulse_snr = pow (10, snrs[i] / 10) / 64;
        double th = s_pd_sw (pulse_snr, r2.threshold, 16);
        print_message ("# cell SNR %4.1f dB: Swerling II Pd %.4f (theory at the per-pulse "
                       "SNR %.1f dB: %.4f), Swerling I Pd %.4f\n",
                       snrs[i], r2.pd, 10 * log10 (pulse_snr), th, r1.pd);
        assert_near (r2.cell_snr_db, 10 * log10 (pulse_snr), 1e-9);
        assert_near (r2.pd, th, 0.02);
        assert_true (r1.pd > r2.pd + 0.3);
    }
}

static mti_params_t s_params (int fft, mti_canceller_t canc, mti_window_t win)
{
    mti_params_t p;
    mti_params_defaults (&p);
    p.fft_size = fft;
    p.canceller = canc;
    p.window = win;
    return p;
}

/* Improvement factor of a canceller measured through the chain itself
 * (mti_dsp_filter with a rectangular window, so by Parseval the bins' total
 * power is fft_size times the canceller's output power):
 * (signal gain averaged over Doppler) / (clutter power out / clutter power in). */
static double s_measure_improvement (mti_canceller_t canc, double sigma_hz)
{
    mti_params_t p = s_params (64, canc, MTI_WINDOW_RECT);
    mti_dsp_t *dsp = mti_dsp_new (&p, 77 + (uint64_t)canc);
    assert_non_null (dsp);
    assert_int_equal (mti_dsp_set_clutter (dsp, sigma_hz), 0);
    int np = mti_dsp_cpi_pulses (dsp);
    assert_int_equal (np, 64 + (int)canc - 1);
    double complex x[80];
    double pw[64];
    double gain = canc == MTI_CANCELLER_THREE ? 6 : 2; // sum of the squared coefficients
    double pin = 0, pout = 0, cnr = 1e14;              // receiver noise is negligible
    for (int trial = 0; trial < 20000; trial++) {
        mti_dsp_cell (dsp, cnr, NULL, x);
        mti_dsp_filter (dsp, x, pw);
        for (int k = 0; k < np; k++)
            pin += creal (x[k] * conj (x[k])) / np;
        for (int k = 0; k < 64; k++)
            pout += pw[k] / (64.0 * 64.0);
    }
    mti_dsp_destroy (&dsp);
    return gain / (pout / pin);
}

static void test_canceller_improvement (void **state)
{
    (void)state;
    const double sigmas[] = {25, 60, 150};
    for (size_t i = 0; i < sizeof sigmas / sizeof *sigmas; i++)
        for (int pulses = 2; pulses <= 3; pulses++) {
            double meas = s_measure_improvement ((mti_canceller_t)pulses, sigmas[i]);
            // Closed form for a Gaussian spectrum, written out.
            double rho1 = exp (-2 * M_PI * M_PI * sigmas[i] * sigmas[i] / (5000.0 * 5000.0));
            double rho2 = pow (rho1, 4);
            double th = pulses == 2 ? 1 / (1 - rho1) : 6 / (6 - 8 * rho1 + 2 * rho2);
            assert_near (mti_theory_canceller_improvement (pulses, sigmas[i], 5000), th, th * 1e-9);
            double d_db = 10 * log10 (meas / th);
            print_message ("# %d-pulse canceller, sigma %5.1f Hz: I measured %.2f dB, closed "
                           "form %.2f dB (%+.2f dB)\n",
                           pulses, sigmas[i], 10 * log10 (meas), 10 * log10 (th), d_db);
            assert_true (fabs (d_db) <= 0.5);
        }
}

/* m of n over independent CPIs is the binomial sum of the per-CPI probability. */
static void test_m_of_n_binomial (void **state)
{
    (void)state;
    mti_params_t p = s_params (16, MTI_CANCELLER_NONE, MTI_WINDOW_RECT);
    p.pfa = 1.0 - pow (0.7, 1.0 / 16); // p per CPI (any of 16 bins) = 0.3
    p.m = 2;
    p.n = 4;
    mti_dsp_t *dsp = mti_dsp_new (&p, 5);
    assert_non_null (dsp);
    double cnr[17] = {0};
    mti_dsp_input_t in = {.snr = 0, .clutter_sigma_hz = 10, .cnr = cnr};
    unsigned long dwells = 20000, det = 0, cross = 0;
    for (unsigned long i = 0; i < dwells; i++) {
        mti_dsp_result_t r;
        assert_int_equal (mti_dsp_dwell (dsp, &in, &r), 0);
        det += r.detected;
        cross += (unsigned long)r.crossings;
    }
    double p_cpi = 1 - pow (1 - p.pfa, 16);
    double pmn = 0; // the binomial sum, written out for 2 of 4
    for (int k = 2; k <= 4; k++)
        pmn += (k == 2 ? 6 : k == 3 ? 4 : 1) * pow (p_cpi, k) * pow (1 - p_cpi, 4 - k);
    assert_near (mti_theory_m_of_n (p_cpi, 2, 4), pmn, 1e-12);
    unsigned long lo, hi, clo, chi;
    assert_int_equal (cgs_binomial_count_interval (pmn, dwells, 0.99, &lo, &hi), 0);
    assert_int_equal (cgs_binomial_count_interval (p_cpi, dwells * 4, 0.99, &clo, &chi), 0);
    print_message ("# per CPI %.4f (theory %.4f), 2 of 4: %.4f (binomial sum %.4f, 99%% "
                   "[%.4f, %.4f])\n",
                   (double)cross / (dwells * 4), p_cpi, (double)det / dwells, pmn,
                   (double)lo / dwells, (double)hi / dwells);
    assert_in_range (cross, clo, chi);
    assert_in_range (det, lo, hi);
    mti_dsp_destroy (&dsp);
}

/* A 2-of-4 dwell on a fluctuating target against the closed forms: a
 * Swerling II target (the radar hops its frequency between intervals, each
 * interval its own draw) detects as the binomial sum over independent
 * intervals, m-of-n(Pd_Swerling(SNR)); a Swerling I target (one draw for
 * the dwell) as that sum over constant-target intervals averaged over the
 * draw. At high SNR the hop's diversity wins: the intervals no longer fade
 * together. */
static void test_dwell_fluctuation_m_of_n (void **state)
{
    (void)state;
    mti_params_t p = s_params (64, MTI_CANCELLER_NONE, MTI_WINDOW_RECT);
    p.pfa = 1e-6; // noise crossings in the other bins: under 7e-5 an interval
    p.m = 2;
    p.n = 4;
    mti_dsp_t *dsp = mti_dsp_new (&p, 17);
    assert_non_null (dsp);
    double t = mti_dsp_threshold (dsp), cnr[17] = {0};
    const double snrs_db[] = {10, 16, 20};
    const unsigned long dwells = 6000;
    for (size_t i = 0; i < sizeof snrs_db / sizeof *snrs_db; i++) {
        double snr = pow (10, snrs_db[i] / 10);
        double pd[2];
        for (int k = 0; k < 2; k++) {
            mti_swerling_t model = k ? MTI_SWERLING_2 : MTI_SWERLING_1;
            mti_dsp_input_t in = {.snr = snr / 64, // per pulse: the FFT gathers 64 of it
                                  .doppler_hz = mti_dsp_bin_hz (dsp, 16),
                                  .swerling = model,
                                  .cnr = cnr};
            unsigned long det = 0;
            for (unsigned long d = 0; d < dwells; d++) {
                mti_dsp_result_t r;
                assert_int_equal (mti_dsp_dwell (dsp, &in, &r), 0);
                det += r.detected;
            }
            double th = k ? mti_theory_m_of_n (s_pd_sw (snr, t, 16), 2, 4)
                          : mti_theory_pd_swerling1_m_of_n (snr, t, 16, 2, 4);
            unsigned long lo, hi;
            assert_int_equal (cgs_binomial_count_interval (th, dwells, 0.99, &lo, &hi), 0);
            print_message ("# %4.1f dB, 2 of 4, Swerling %s: Pd %.4f, theory %.4f (99%% "
                           "[%.4f, %.4f])\n",
                           snrs_db[i], k ? "II (interval)" : "I (dwell)", (double)det / dwells, th,
                           (double)lo / dwells, (double)hi / dwells);
            assert_in_range (det, lo, hi);
            pd[k] = th;
        }
        if (snrs_db[i] >= 16)
            assert_true (pd[1] > pd[0] + 0.05);
    }
    mti_dsp_destroy (&dsp);
}

/* Against strong clutter a target slower than the clutter's spread is not
 * detected; the same target faster is. */
static void test_slow_and_fast_targets_in_clutter (void **state)
{
    (void)state;
    mti_params_t p;
    mti_params_defaults (&p); // 64-point FFT, Hamming, two-pulse canceller, 2 of 4
    mti_dsp_t *dsp = mti_dsp_new (&p, 9);
    assert_non_null (dsp);
    double cnr[17];
    for (int i = 0; i < 17; i++)
        cnr[i] = 1e4;  // 40 dB per pulse
    double sigma = 60; // Hz
    int slow = 0, fast = 0, trials = 300;
    for (int i = 0; i < trials; i++) {
        mti_dsp_result_t r;
        mti_dsp_input_t in = {.snr = 1.0,
                              .doppler_hz = 30,
                              .swerling = MTI_SWERLING_0,
                              .clutter_sigma_hz = sigma,
                              .cnr = cnr};
        assert_int_equal (mti_dsp_dwell (dsp, &in, &r), 0);
        slow += r.detected;
        in.doppler_hz = 900;
        assert_int_equal (mti_dsp_dwell (dsp, &in, &r), 0);
        fast += r.detected;
    }
    print_message ("# CNR 40 dB, clutter spread 60 Hz, SNR 0 dB a pulse: detected at 30 Hz "
                   "%d/%d, at 900 Hz %d/%d\n",
                   slow, trials, fast, trials);
    assert_true (slow <= trials / 20);
    assert_true (fast >= trials * 95 / 100);
    mti_dsp_destroy (&dsp);
}

/* The simulated mean power in a Doppler bin equals the chain's exact
 * response to its noise, clutter and target. */
static void test_bin_power_matches_response (void **state)
{
    (void)state;
    mti_params_t p;
    mti_params_defaults (&p);
    mti_dsp_t *dsp = mti_dsp_new (&p, 21);
    assert_non_null (dsp);
    assert_int_equal (mti_dsp_set_clutter (dsp, 50), 0);
    double f = 700, snr = 0.5, cnr = 100;
    int bins[] = {0, 1, mti_dsp_bin_of (dsp, f)};
    double pw[64], sum[3] = {0};
    double complex x[80];
    int trials = 20000;
    for (int t = 0; t < trials; t++) {
        mti_dsp_target_t tgt = {.amplitude = sqrt (snr), .doppler_hz = f};
        mti_dsp_cell (dsp, cnr, &tgt, x);
        mti_dsp_filter (dsp, x, pw);
        for (int i = 0; i < 3; i++)
            sum[i] += pw[bins[i]];
    }
    for (int i = 0; i < 3; i++) {
        double nz, cl, sg;
        mti_dsp_bin_response (dsp, bins[i], f, false, &nz, &cl, &sg);
        double expect = nz + cnr * cl + snr * sg, got = sum[i] / trials;
        print_message ("# bin %2d: mean power %.2f, exact %.2f\n", bins[i], got, expect);
        assert_near (got / expect, 1.0, 0.04);
    }
    mti_dsp_destroy (&dsp);
}

/* The statistical false-alarm model (a gate declares one with
 * m_of_n(p_cpi), p_cpi from mti_dsp_any_bin_probability) against full
 * processing of a strip of range cells, with and without clutter. */
static void test_strip_matches_statistical_rate (void **state)
{
    (void)state;
    mti_params_t p;
    mti_params_defaults (&p);
    p.pfa = 1e-3;
    for (int with_clutter = 0; with_clutter <= 1; with_clutter++) {
        mti_dsp_t *dsp = mti_dsp_new (&p, 31 + (uint64_t)with_clutter);
        assert_non_null (dsp);
        assert_int_equal (mti_dsp_set_clutter (dsp, 40), 0);
        enum { NC = 520 };
        double cnr[NC];
        bool det[NC];
        for (int i = 0; i < NC; i++)
            cnr[i] = with_clutter ? 300 : 0;
        unsigned long tested = 0, fa = 0;
        for (int d = 0; d < 25; d++) {
            int n = mti_dsp_strip (dsp, NC, cnr, det);
            assert_true (n > 0);
            tested += (unsigned long)n;
            for (int i = 0; i < NC; i++)
                fa += det[i];
        }
        double pg = mti_theory_m_of_n (mti_dsp_any_bin_probability (dsp, 4000), p.m, p.n);
        unsigned long lo, hi;
        assert_int_equal (cgs_binomial_count_interval (pg, tested, 0.99, &lo, &hi), 0);
        print_message ("# strip %s: %lu false dwells in %lu gate-dwells, statistical model "
                       "expects %.1f (99%% [%lu, %lu])\n",
                       with_clutter ? "in clutter (CNR 25 dB)" : "in noise", fa, tested,
                       pg * tested, lo, hi);
        assert_true (pg * tested >= 100);
        assert_in_range (fa, lo, hi);
        mti_dsp_destroy (&dsp);
    }
}

/* The any-bin crossing probability of a CPI: the union estimator against a
 * direct count, with the Hamming window and canceller that correlate the
 * bins (so it is below the independent-bin 1 - (1 - Pfa)^bins), and equal
 * to that for the rectangular window with no canceller (independent bins). */
static void test_any_bin_probability (void **state)
{
    (void)state;
    for (int w = 0; w < 2; w++) {
        mti_params_t p = s_params (16, w ? MTI_CANCELLER_TWO : MTI_CANCELLER_NONE,
                                   w ? MTI_WINDOW_HAMMING : MTI_WINDOW_RECT);
        p.pfa = 0.01;
        mti_dsp_t *dsp = mti_dsp_new (&p, 41 + (uint64_t)w);
        assert_non_null (dsp);
        double est = mti_dsp_any_bin_probability (dsp, 20000);
        double cnr[17] = {0}, x[16], z[16], t = mti_dsp_threshold (dsp);
        unsigned long trials = 60000, any = 0;
        for (unsigned long i = 0; i < trials; i++) {
            mti_dsp_cpi (dsp, cnr, NULL, x, z);
            bool a = false;
            for (int k = 0; k < 16; k++)
                a |= x[k] > t * z[k];
            any += a;
        }
        unsigned long lo, hi;
        assert_int_equal (cgs_binomial_count_interval (est, trials, 0.99, &lo, &hi), 0);
        double indep = 1 - pow (1 - p.pfa, 16);
        print_message ("# %s: any-bin crossing %.4f counted, %.4f estimated, %.4f if the bins "
                       "were independent\n",
                       w ? "Hamming, two-pulse canceller" : "rectangular, no canceller",
                       (double)any / trials, est, indep);
        assert_in_range (any, lo, hi);
        if (w)
            assert_true (est < indep * 0.98);
        else
            assert_near (est, indep, indep * 0.02);
        mti_dsp_destroy (&dsp);
    }
}

static void test_bins (void **state)
{
    (void)state;
    mti_params_t p;
    mti_params_defaults (&p);
    mti_dsp_t *dsp = mti_dsp_new (&p, 1);
    assert_non_null (dsp);
    assert_int_equal (mti_dsp_bins (dsp), 64);
    assert_int_equal (mti_dsp_cpi_pulses (dsp), 65);
    assert_near (mti_dsp_bin_hz (dsp, 1), 5000.0 / 64, 1e-9);
    assert_near (mti_dsp_bin_hz (dsp, 63), -5000.0 / 64, 1e-9);
    assert_near (mti_dsp_bin_hz (dsp, 32), -2500.0, 1e-9);
    assert_int_equal (mti_dsp_bin_of (dsp, -5000.0 / 64), 63);
    assert_int_equal (mti_dsp_bin_of (dsp, 5000.0 + 2 * 5000.0 / 64), 2); // aliased
    assert_int_equal (mti_dsp_set_clutter (dsp, -1), -EINVAL);
    assert_int_equal (mti_dsp_set_clutter (dsp, NAN), -EINVAL);
    mti_dsp_destroy (&dsp);
    mti_dsp_destroy (&dsp); // idempotent
    p.fft_size = 48;        // not a power of two
    assert_null (mti_dsp_new (&p, 1));
}

int main (void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test (test_bins),
        cmocka_unit_test (test_cfar_threshold_and_pfa),
        cmocka_unit_test (test_pd_swerling1),
        cmocka_unit_test (test_pd_constant),
        cmocka_unit_test (test_swerling2_no_coherent_gain),
        cmocka_unit_test (test_canceller_improvement),
        cmocka_unit_test (test_m_of_n_binomial),
        cmocka_unit_test (test_dwell_fluctuation_m_of_n),
        cmocka_unit_test (test_slow_and_fast_targets_in_clutter),
        cmocka_unit_test (test_bin_power_matches_response),
        cmocka_unit_test (test_any_bin_probability),
        cmocka_unit_test (test_strip_matches_statistical_rate),
    };
    return cmocka_run_group_tests (tests, NULL, NULL);
}
