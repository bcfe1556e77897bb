/* The BCIS interrogator model: its parameter file; the link budget against a
 * hand-worked example, term by term; rain attenuation against ITU-R P.838-3's
 * published coefficients; Weissberger's foliage loss; bit-error and message
 * probabilities against their formulas; Monte Carlo message and reply rates
 * within their 99% binomial intervals; terrain blocking, the range at which
 * the link closes, transponders and forces; the sector scan. */
#include "bcis_interrogator.h"
#include "bcis_link.h"
#include "bcis_params.h"
#include "cgs_terrain.h"

#include <errno.h>
#include <gsl/gsl_cdf.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "test_util.h"

static bcis_params_t s_defaults (void)
{
    bcis_params_t p;
    bcis_params_defaults (&p);
    return p;
}

/* The 99% two-sided interval of a binomial count: [lo, hi] with at most
 * 0.5% below lo and at most 0.5% above hi. */
static void s_interval99 (double p, unsigned int n, unsigned int *lo, unsigned int *hi)
{
    unsigned int k = 0;
    while (k < n && gsl_cdf_binomial_P (k, p, n) < 0.005)
        k++;
    *lo = k;
    while (k < n && gsl_cdf_binomial_Q (k, p, n) > 0.005)
        k++;
    *hi = k;
}

/* --- parameters -------------------------------------------------------------- */

/* Two parameter sets hold the same values (padding aside). */
static bool s_same (const bcis_params_t *a, const bcis_params_t *b)
{
#define S_EQ(f) (a->f == b->f)
    return S_EQ (frequency_hz) && S_EQ (transmit_power_w) && S_EQ (antenna_gain_db) &&
           S_EQ (azimuth_beamwidth_deg) && S_EQ (elevation_beamwidth_deg) &&
           S_EQ (beam_depression_deg) && S_EQ (noise_figure_db) && S_EQ (losses_db) &&
           S_EQ (min_range_m) && S_EQ (max_range_m) && S_EQ (range_sigma_m) && S_EQ (scan_mode) &&
           S_EQ (sector_center_deg) && S_EQ (sector_width_deg) && S_EQ (sector_ref) &&
           S_EQ (scan_rate_dps) && S_EQ (transponder_power_w) && S_EQ (transponder_gain_db) &&
           S_EQ (transponder_noise_figure_db) && S_EQ (transponder_losses_db) &&
           S_EQ (antenna_height_m) && S_EQ (reports_position) && S_EQ (position_sigma_m) &&
           S_EQ (modulation) && S_EQ (data_rate_bps) && S_EQ (interrogation_bits) &&
           S_EQ (reply_bits) && S_EQ (correctable_bits) && S_EQ (noise_temperature_k) &&
           S_EQ (atmospheric_db_per_km) && S_EQ (rain_rate_mmph) && S_EQ (rain_height_m) &&
           S_EQ (polarization) && S_EQ (foliage);
#undef S_EQ
}

static void test_params (void **state)
{
    (void)state;
    bcis_params_t p = s_defaults ();
    assert_near (p.frequency_hz, 38e9, 0);
    assert_int_equal (p.modulation, BCIS_MOD_BFSK);
    assert_int_equal (bcis_params_check (&p, NULL, 0), 0);
    // The shipped file holds the defaults.
    char path[4096], err[512] = "";
    const char *root = getenv ("CGS_ROOT");
    snprintf (path, sizeof path, "%s/deploy/params/bcis.ini", root ? root : ".");
    bcis_params_t q;
    bcis_params_defaults (&q);
    q.frequency_hz = 1; // the file must set it back
    bcis_params_defaults (&p);
    p.frequency_hz = 1;
    if (bcis_params_load (path, &q, err, sizeof err) != 0)
        fail_msg ("%s", err);
    p.frequency_hz = 38e9;
    assert_true (s_same (&p, &q));
    // Values over the defaults.
    assert_int_equal (bcis_params_load_string ("b.ini",
                                               "[scan]\nmode = sector\nsector_center_deg = 45\n"
                                               "sector_width_deg = 60\nrate_dps = 30\n"
                                               "[link]\nmodulation = bpsk\ncorrectable_bits = 3\n"
                                               "[propagation]\nrain_rate_mmph = 12.5\n"
                                               "polarization = circular\nfoliage = no\n",
                                               &q, err, sizeof err),
                      0);
    assert_int_equal (q.scan_mode, CGS_SCAN_SECTOR);
    assert_near (q.sector_width_deg, 60, 0);
    assert_int_equal (q.modulation, BCIS_MOD_BPSK);
    assert_int_equal (q.correctable_bits, 3);
    assert_near (q.rain_rate_mmph, 12.5, 0);
    assert_int_equal (q.polarization, BCIS_POL_CIRCULAR);
    assert_false (q.foliage);
    assert_near (q.transmit_power_w, 1, 0); // untouched
}

static void s_refused (const char *text, const char *expected)
{
    bcis_params_t p = s_defaults (), before = p;
    char err[512] = "";
    assert_int_equal (bcis_params_load_string ("b.ini", text, &p, err, sizeof err), -EINVAL);
    assert_true (s_same (&p, &before)); // nothing written
    assert_string_equal (err, expected);
}

static void test_params_errors (void **state)
{
    (void)state;
    s_refused (
        "[interrogator]\nfrequency_hz = 120e9\n",
        "b.ini:2: [interrogator] frequency_hz: expected a number in [1000000000, 95000000000], got "
        "'120e9'");
    s_refused ("[link]\nmodulation = ook\n",
               "b.ini:2: [link] modulation: expected one of 'bpsk', 'qpsk', 'bfsk', got 'ook'");
    s_refused ("[link]\nbaud = 9600\n", "b.ini:2: [link] unknown key 'baud'");
    s_refused ("[interrogator]\nmin_range_m = 5000\nmax_range_m = 4000\n",
               "b.ini:3: [interrogator] max_range_m: must exceed min_range_m (5000 m), got 4000 m");
    s_refused ("[link]\ncorrectable_bits = 64\n",
               "b.ini:2: [link] correctable_bits: must be fewer than the bits of either message "
               "(64 and 128), got 64");
    s_refused ("[scan]\nmode = sector\nsector_width_deg = 4\n",
               "b.ini:3: [scan] sector_width_deg: must be at least the azimuth beamwidth (6 deg), "
               "got 4 deg");
    s_refused ("[scan]\nrate_dps = 10\n[link]\n[scan]\n",
               "b.ini:4: [scan] given twice (first at line 1)");
    s_refused ("[propagation]\nfoliage = maybe\n",
               "b.ini:2: [propagation] foliage: expected true/false, yes/no, on/off or 1/0, got "
               "'maybe'");
    // A struct checked on its own names the key.
    bcis_params_t p = s_defaults ();
    p.data_rate_bps = 0;
    char err[256];
    assert_int_equal (bcis_params_check (&p, err, sizeof err), -EINVAL);
    assert_string_equal (err, "[link] data_rate_bps: expected a number in [1, 1e+10], got 0");
}

/* --- the link ---------------------------------------------------------------- */

/* A hand-worked budget at the defaults: 6 km, path elevation 10 degrees, 2
 * mm/h of rain over 3 km of it, 5 m of woods, 1.5 degrees off the beam in
 * azimuth and 3 in elevation. Worked out separately, term by term:
 *   free space  20 log10(4 pi 6000 38e9 / 299792458)          = 139.6064802 dB
 *   gases       0.12 dB/km x 6 km                              =   0.72 dB
 *   rain        P.838-3 at 38 GHz: kH 0.400108, aH 0.881557, kV 0.384403,
 *               aV 0.855219; vertical (tau 90), 10 degrees: cos^2 10 cos 180 =
 *               -0.969846: k = 0.3846402, alpha = 0.8556322; gamma = k 2^alpha
 *               = 0.6960263 dB/km, over 3 km                   =   2.088079 dB
 *   foliage     0.45 x 38^0.284 x 5                            =   6.321804 dB
 *   pattern     12 (1.5/6)^2 + 12 (3/40)^2                     =   0.8175 dB
 *   path        139.6064802 + 0.72 + 2.088079 + 6.321804       = 148.7363635 dB
 *   up          EIRP 0 dBW + 25 - 2 - 0.8175 = 22.1825 dBW; at the transponder
 *               22.1825 - 148.7363635 + 3 - 2 = -125.5538635 dBW; noise
 *               10 log10(k 290) + 6 + 60 = -137.9751872 dBW; Eb/N0 12.4213237 dB
 *   down        EIRP 10 log10 0.5 + 3 - 2 = -2.0103000 dBW; at the interrogator
 *               -2.0103 - 148.7363635 + 25 - 0.8175 - 2 = -128.5641635 dBW;
 *               noise -138.9751872 dBW; Eb/N0 10.4110237 dB
 *   BFSK        Pb up exp(-17.4532/2)/2 = 8.068815e-5, down 2.050910e-3
 *   messages    (1 - 8.068815e-5)^64 = 0.9948491, (1 - 2.050910e-3)^128 = 0.7689064
 *   reply       0.9948491 x 0.7689064 = 0.7649458 */
static void test_budget_hand_worked (void **state)
{
    (void)state;
    bcis_params_t p = s_defaults ();
    p.rain_rate_mmph = 2;
    bcis_geometry_t g = {.range_m = 6000,
                         .elevation_deg = 10,
                         .rain_path_m = 3000,
                         .foliage_m = 5,
                         .az_off_deg = 1.5,
                         .el_off_deg = 3};
    bcis_budget_t b;
    bcis_budget (&p, &g, &b);
    assert_near (b.fspl_db, 139.6064802, 1e-6);
    assert_near (b.atmospheric_db, 0.72, 1e-12);
    assert_near (b.rain_db_per_km, 0.6960262923, 1e-8);
    assert_near (b.rain_db, 2.088078877, 1e-8);
    assert_near (b.foliage_db, 6.321804475, 1e-8);
    assert_near (b.pattern_db, 0.8175, 1e-12);
    assert_near (b.path_loss_db, 148.7363635, 1e-6);
    assert_near (b.up_eirp_dbw, 22.1825, 1e-9);
    assert_near (b.up_rx_dbw, -125.5538635, 1e-6);
    assert_near (b.up_noise_dbw, -137.9751872, 1e-6);
    assert_near (b.up_ebn0_db, 12.42132368, 1e-6);
    assert_near (b.down_eirp_dbw, -2.010299957, 1e-8);
    assert_near (b.down_rx_dbw, -128.5641635, 1e-6);
    assert_near (b.down_noise_dbw, -138.9751872, 1e-6);
    assert_near (b.down_ebn0_db, 10.41102372, 1e-6);
    assert_near (b.up_ber, 8.068814586e-05, 1e-11);
    assert_near (b.down_ber, 0.002050909707, 1e-10);
    assert_near (b.p_up, 0.9948490621, 1e-8);
    assert_near (b.p_down, 0.7689064181, 1e-8);
    assert_near (b.p_reply, 0.7649458289, 1e-8);
    // Foliage off: no foliage term, all else the same.
    p.foliage = false;
    bcis_budget (&p, &g, &b);
    assert_near (b.foliage_db, 0, 0);
    assert_near (b.path_loss_db, 148.7363635 - 6.321804475, 1e-6);
}

/* ITU-R P.838-3 table 5 (coefficients published to four or five figures) at
 * 10, 20, 30 and 40 GHz; and gamma = k R^alpha with the path and polarisation
 * combination of its equations 4 and 5. */
static void test_rain_p838 (void **state)
{
    (void)state;
    static const struct {
        double f, kh, ah, kv, av;
    } table[] = {
        {10, 0.01217, 1.2571, 0.01129, 1.2156},
        {20, 0.09164, 1.0568, 0.09611, 0.9847},
        {30, 0.2403, 0.9485, 0.2291, 0.9129},
        {40, 0.4431, 0.8673, 0.4274, 0.8421},
    };
    for (size_t i = 0; i < sizeof table / sizeof table[0]; i++) {
        double kh, ah, kv, av;
        bcis_p838 (table[i].f, &kh, &ah, &kv, &av);
        print_message ("# %2.0f GHz: kH %.5f (table %.5f) aH %.4f (%.4f) kV %.5f (%.5f) aV %.4f "
                       "(%.4f)\n",
                       table[i].f, kh, table[i].kh, ah, table[i].ah, kv, table[i].kv, av,
                       table[i].av);
        assert_near (kh, table[i].kh, 0.5e-4 * (table[i].kh < 0.1 ? 0.1 : 1));
        assert_near (kv, table[i].kv, 0.5e-4 * (table[i].kv < 0.1 ? 0.1 : 1));
        assert_near (ah, table[i].ah, 0.5e-4);
        assert_near (av, table[i].av, 0.5e-4);
    }
    // Horizontal path, horizontal polarisation: gamma = kH R^aH; vertical: kV R^aV.
    double kh, ah, kv, av;
    bcis_p838 (10, &kh, &ah, &kv, &av);
    assert_near (bcis_rain_db_per_km (10, 25, 0, 0), kh * pow (25, ah), 1e-12);
    assert_near (bcis_rain_db_per_km (10, 25, 0, 90), kv * pow (25, av), 1e-12);
    // 10 GHz, 25 mm/h, horizontal: 0.01217 x 25^1.2571 = 0.6735 dB/km from the table.
    assert_near (bcis_rain_db_per_km (10, 25, 0, 0), 0.01217 * pow (25, 1.2571), 2e-4);
    // 40 GHz, 50 mm/h, vertical: 0.4274 x 50^0.8421 = 11.05 dB/km from the table.
    assert_near (bcis_rain_db_per_km (40, 50, 0, 90), 0.4274 * pow (50, 0.8421), 5e-3);
    // A vertical path sees both polarisations alike (cos^2 90 = 0): the mean k.
    bcis_p838 (40, &kh, &ah, &kv, &av);
    double k = (kh + kv) / 2, a = (kh * ah + kv * av) / (2 * k);
    assert_near (bcis_rain_db_per_km (40, 10, 90, 0), k * pow (10, a), 1e-12);
    assert_near (bcis_rain_db_per_km (40, 10, 90, 90), k * pow (10, a), 1e-12);
    assert_near (bcis_rain_db_per_km (40, 0, 0, 0), 0, 0); // dry
}

/* Weissberger: 0.45 f^0.284 d up to 14 m, 1.33 f^0.284 d^0.588 beyond. */
static void test_foliage (void **state)
{
    (void)state;
    assert_near (bcis_foliage_db (38, 0), 0, 0);
    assert_near (bcis_foliage_db (38, 10), 0.45 * pow (38, 0.284) * 10, 1e-12);
    assert_near (bcis_foliage_db (38, 10), 12.643608949, 1e-8);
    assert_near (bcis_foliage_db (38, 100), 1.33 * pow (38, 0.284) * pow (100, 0.588), 1e-12);
    assert_near (bcis_foliage_db (38, 100), 56.0416, 1e-3);
    assert_near (bcis_foliage_db (1, 14), 6.3, 1e-12);
    // The two branches nearly meet at 14 m (6.30 against 6.27 dB at 1 GHz).
    assert_near (bcis_foliage_db (1, 14.0001), 6.3, 0.05);
}

static void test_ber_and_message (void **state)
{
    (void)state;
    // BPSK at 9.59 dB: the textbook 1e-5; Eb/N0 = 1: Q(sqrt 2) = 0.0786496.
    assert_near (bcis_ber (BCIS_MOD_BPSK, pow (10, 0.959)), 1.0e-5, 0.02e-5);
    assert_near (bcis_ber (BCIS_MOD_BPSK, 1), 0.07864960352514, 1e-12);
    assert_near (bcis_ber (BCIS_MOD_QPSK, 1), 0.07864960352514, 1e-12);
    // Non-coherent BFSK: exp(-g/2)/2; 1e-3 at g = 2 ln 500 = 12.429 (10.94 dB).
    assert_near (bcis_ber (BCIS_MOD_BFSK, 2 * log (500)), 1e-3, 1e-15);
    assert_near (bcis_ber (BCIS_MOD_BFSK, 0), 0.5, 0);
    // Message: the binomial sum, against a direct sum of its terms.
    for (int t = 0; t <= 3; t++) {
        double p = 0.01, sum = 0, c = 1; // c = C(100, i)
        for (int i = 0; i <= t; i++) {
            sum += c * pow (p, i) * pow (1 - p, 100 - i);
            c = c * (100 - i) / (i + 1);
        }
        assert_near (bcis_message_p (p, 100, t), sum, 1e-12);
    }
    assert_near (bcis_message_p (0.01, 100, 0), pow (0.99, 100), 1e-14);
    assert_near (bcis_message_p (0, 100, 0), 1, 0);
}

/* Messages simulated symbol by symbol arrive at the rate the formulas give,
 * within the 99% binomial interval of 20,000 tries, for each modulation,
 * with and without error correction. */
static void test_monte_carlo_messages (void **state)
{
    (void)state;
    static const struct {
        bcis_modulation_t m;
        int bits, t;
        double ebn0_db;
    } cases[] = {
        {BCIS_MOD_BFSK, 64, 0, 10.0},
        {BCIS_MOD_BFSK, 128, 2, 9.0},
        {BCIS_MOD_BPSK, 64, 0, 5.5},
        {BCIS_MOD_QPSK, 128, 3, 4.0},
    };
    const unsigned int trials = 20000;
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        bcis_params_t p = s_defaults ();
        p.modulation = cases[i].m;
        p.correctable_bits = cases[i].t;
        bcis_interrogator_t *b = bcis_interrogator_new (&p, NULL, 11 + i);
        assert_non_null (b);
        unsigned int ok = 0;
        for (unsigned int k = 0; k < trials; k++)
            ok += bcis_interrogator_send (b, cases[i].ebn0_db, cases[i].bits);
        double theory = bcis_message_p (bcis_ber (p.modulation, pow (10, cases[i].ebn0_db / 10)),
                                        cases[i].bits, cases[i].t);
        unsigned int lo, hi;
        s_interval99 (theory, trials, &lo, &hi);
        print_message ("# modulation %d, %d bits, %d correctable, %.1f dB: %u of %u whole, "
                       "theory %.4f, 99%% [%u, %u]\n",
                       (int)cases[i].m, cases[i].bits, cases[i].t, cases[i].ebn0_db, ok, trials,
                       theory, lo, hi);
        assert_true (theory > 0.2 && theory < 0.95); // a point where the rate can be wrong
        assert_in_range (ok, lo, hi);
        bcis_interrogator_destroy (&b);
    }
}

/* Flat open ground with a ridge along north = 5000 m, 300 m high, optional. */
static cgs_terrain_t *s_ground (bool ridge)
{
    enum { N = 241 }; // 100 m spacing, -12 km .. 12 km
    float *h = calloc (N * N, sizeof *h);
    assert_non_null (h);
    for (int r = 0; r < N; r++)
        for (int c = 0; c < N; c++) {
            double n = -12000 + r * 100.0;
            h[r * N + c] = ridge && fabs (n - 5000) <= 200 ? 300.0f : 0.0f;
        }
    cgs_terrain_t *t = cgs_terrain_new_grid (N, N, -12000, -12000, 100, h);
    free (h);
    assert_non_null (t);
    return t;
}

/* A point on the ground at range r_m and azimuth az_deg from the origin. */
static cgs_enu_t s_at (double r_m, double az_deg)
{
    return (cgs_enu_t){r_m * sin (az_deg * M_PI / 180), r_m * cos (az_deg * M_PI / 180), 0};
}

/* The dwell of the full scan whose sector holds azimuth az. */
static cgs_dwell_t s_dwell_at (const bcis_interrogator_t *b, double az, uint64_t scan)
{
    const cgs_scan_t *s = bcis_interrogator_scan (b);
    cgs_dwell_t d;
    for (uint32_t k = 0; k < s->dwells; k++) {
        cgs_scan_dwell (s, scan * s->dwells + k, 0, &d);
        if (cgs_dwell_contains (&d, az))
            return d;
    }
    fail_msg ("no dwell holds azimuth %g", az);
    return d;
}

/* Answers of one entity over tries interrogations of the dwell holding az. */
static unsigned int s_answers (bcis_interrogator_t *b, cgs_enu_t uav, bcis_entity_t e, double az,
                               unsigned int tries, bcis_truth_t *ret_truth)
{
    unsigned int n = 0;
    for (unsigned int k = 0; k < tries; k++) {
        cgs_dwell_t d = s_dwell_at (b, az, k);
        bcis_dwell_out_t out;
        assert_int_equal (bcis_interrogator_dwell (b, &d, uav, &e, 1, &out), 0);
        assert_int_equal (out.truth_count, 1); // in the beam, interrogated
        n += out.reply_count;
        if (out.reply_count) {
            assert_int_equal (out.replies[0].responder_id, e.id);
            assert_string_equal (out.replies[0].marking, e.marking ? e.marking : "");
        }
        if (ret_truth && out.truth_count)
            *ret_truth = out.truth[0];
    }
    return n;
}

/* A friendly behind a ridge does not answer; in the open it does; beyond
 * the range where the link closes it does not; and the reply rate at a
 * range where the link is marginal matches the budget's. */
static void test_terrain_and_range (void **state)
{
    (void)state;
    cgs_terrain_t *ridge = s_ground (true);
    bcis_params_t p = s_defaults ();
    bcis_interrogator_t *b = bcis_interrogator_new (&p, ridge, 5);
    assert_non_null (b);
    cgs_enu_t uav = {0, 0, 600};
    // Both on a dwell's centre azimuth (3 and 183 degrees), 6 km out.
    bcis_entity_t behind = {.id = 7,
                            .position = s_at (6000, 3),
                            .force = CGS_FORCE_FRIENDLY,
                            .transponder = true,
                            .marking = "F7"};
    bcis_entity_t open = {.id = 8,
                          .position = s_at (6000, 183),
                          .force = CGS_FORCE_FRIENDLY,
                          .transponder = true,
                          .marking = "F8"};
    bcis_truth_t tr;
    assert_int_equal (s_answers (b, uav, behind, 3, 200, &tr), 0);
    assert_true (tr.blocked);
    assert_int_equal (s_answers (b, uav, open, 183, 200, &tr), 200);
    assert_false (tr.blocked);
    assert_true (tr.budget.p_reply > 0.9999);
    bcis_interrogator_destroy (&b);
    cgs_terrain_destroy (&ridge);

    // Where the link closes, on open flat ground: with the transmitters 10 dB
    // weaker it closes near 6 km; at 9 km (inside max_range_m) nobody answers.
    cgs_terrain_t *flat = s_ground (false);
    p.transmit_power_w = 0.1;
    p.transponder_power_w = 0.05;
    b = bcis_interrogator_new (&p, flat, 6);
    assert_non_null (b);
    bcis_entity_t far = {
        .id = 9, .position = s_at (9000, 93), .force = CGS_FORCE_FRIENDLY, .transponder = true};
    assert_int_equal (s_answers (b, uav, far, 93, 300, &tr), 0);
    assert_true (tr.budget.p_reply < 1e-6);
    bcis_entity_t near = {
        .id = 10, .position = s_at (3000, 93), .force = CGS_FORCE_FRIENDLY, .transponder = true};
    assert_int_equal (s_answers (b, uav, near, 93, 300, &tr), 300);
    // At a marginal range the reply rate follows the budget (99% interval of 4,000).
    bcis_entity_t edge = {
        .id = 11, .position = s_at (5500, 93), .force = CGS_FORCE_FRIENDLY, .transponder = true};
    const unsigned int tries = 4000;
    unsigned int got = s_answers (b, uav, edge, 93, tries, &tr), lo, hi;
    s_interval99 (tr.budget.p_reply, tries, &lo, &hi);
    print_message ("# 5.5 km at a tenth of the power: %u of %u replies, budget %.4f (up %.4f, down "
                   "%.4f), 99%% [%u, %u]\n",
                   got, tries, tr.budget.p_reply, tr.budget.p_up, tr.budget.p_down, lo, hi);
    assert_true (tr.budget.p_reply > 0.1 && tr.budget.p_reply < 0.9);
    assert_in_range (got, lo, hi);
    bcis_interrogator_destroy (&b);
    cgs_terrain_destroy (&flat);
}

/* Only friendly transponders answer: a hostile, neutral or unknown entity
 * never does (with a transponder or without), nor a friendly without one. */
static void test_who_answers (void **state)
{
    (void)state;
    bcis_params_t p = s_defaults ();
    bcis_interrogator_t *b = bcis_interrogator_new (&p, NULL, 8);
    assert_non_null (b);
    cgs_enu_t uav = {0, 0, 1000};
    bcis_entity_t e[] = {
        {.id = 1, .position = s_at (3000, 93.0), .force = CGS_FORCE_FRIENDLY, .transponder = true},
        {.id = 2, .position = s_at (3000, 93.2), .force = CGS_FORCE_FRIENDLY, .transponder = false},
        {.id = 3, .position = s_at (3000, 93.4), .force = CGS_FORCE_HOSTILE, .transponder = true},
        {.id = 4, .position = s_at (3000, 93.6), .force = CGS_FORCE_NEUTRAL, .transponder = true},
        {.id = 5, .position = s_at (3000, 93.8), .force = CGS_FORCE_UNKNOWN, .transponder = true},
        {.id = 6, .position = s_at (3000, 94.0), .force = CGS_FORCE_HOSTILE, .transponder = false},
    };
    unsigned int answers[7] = {0};
    for (unsigned int k = 0; k < 500; k++) {
        cgs_dwell_t d = s_dwell_at (b, 93, k);
        bcis_dwell_out_t out;
        assert_int_equal (bcis_interrogator_dwell (b, &d, uav, e, 6, &out), 0);
        assert_int_equal (out.in_beam, 6);
        assert_int_equal (out.truth_count, 1); // only the friendly transponder is interrogated
        for (size_t i = 0; i < out.reply_count; i++)
            answers[out.replies[i].responder_id]++;
    }
    assert_int_equal (answers[1], 500);
    for (int id = 2; id <= 6; id++)
        assert_int_equal (answers[id], 0);
    bcis_interrogator_destroy (&b);
}

/* A transponder that reports its position: the reply carries its position
 * fix and the range, with the stated noise. */
static void test_reply_measurements (void **state)
{
    (void)state;
    bcis_params_t p = s_defaults ();
    p.reports_position = true;
    bcis_interrogator_t *b = bcis_interrogator_new (&p, NULL, 9);
    cgs_enu_t uav = {0, 0, 1000};
    bcis_entity_t e = {.id = 1,
                       .position = {0, 4000, 0},
                       .force = CGS_FORCE_FRIENDLY,
                       .transponder = true,
                       .marking = "ALPHA-1"};
    double se = 0, se2 = 0, sn = 0, sn2 = 0, sr = 0, sr2 = 0,
           range = hypot (4000, 1000 - p.antenna_height_m);
    const int n = 4000;
    for (int k = 0; k < n; k++) {
        cgs_dwell_t d = s_dwell_at (b, 0, (uint64_t)k);
        bcis_dwell_out_t out;
        assert_int_equal (bcis_interrogator_dwell (b, &d, uav, &e, 1, &out), 0);
        assert_int_equal (out.reply_count, 1);
        const bcis_reply_t *r = &out.replies[0];
        assert_near (r->azimuth_deg, d.az_center_deg, 0);
        assert_true (r->position_fix);
        assert_near (r->position_sigma_m, p.position_sigma_m, 0);
        se += r->position.e_m, se2 += r->position.e_m * r->position.e_m;
        sn += r->position.n_m - 4000, sn2 += (r->position.n_m - 4000) * (r->position.n_m - 4000);
        sr += r->range_m - range, sr2 += (r->range_m - range) * (r->range_m - range);
    }
    double me = se / n, sde = sqrt (se2 / n - me * me), mr = sr / n, sdr = sqrt (sr2 / n - mr * mr);
    print_message ("# position fix: mean %.2f m, sd %.2f m (sigma %g); range error mean %.2f m, sd "
                   "%.2f m (sigma %g)\n",
                   me, sde, p.position_sigma_m, mr, sdr, p.range_sigma_m);
    assert_near (me, 0, 4 * p.position_sigma_m / sqrt (n));
    assert_near (sde, p.position_sigma_m, 0.05 * p.position_sigma_m);
    double mn = sn / n, sdn = sqrt (sn2 / n - mn * mn);
    assert_near (mn, 0, 4 * p.position_sigma_m / sqrt (n));
    assert_near (sdn, p.position_sigma_m, 0.05 * p.position_sigma_m);
    assert_near (mr, 0, 4 * p.range_sigma_m / sqrt (n));
    assert_near (sdr, p.range_sigma_m, 0.05 * p.range_sigma_m);
    bcis_interrogator_destroy (&b);
}

/* By default (as the paper's BCIS) a reply gives what the interrogation
 * measured: the range (σ range_sigma_m) and the beam's azimuth. The
 * responder lies anywhere in the dwell's sector, so the azimuth's stated σ
 * (the dwell's width over √12) is the spread of the truth about it, checked
 * over responders all round. The reply puts the responder where that range
 * and azimuth meet the (here flat) ground. */
static void test_reply_geometry (void **state)
{
    (void)state;
    bcis_params_t p = s_defaults ();
    bcis_interrogator_t *b = bcis_interrogator_new (&p, NULL, 9);
    cgs_enu_t uav = {0, 0, 1000};
    const int n = 3600;
    double sa = 0, sa2 = 0, sigma = 0;
    for (int k = 0; k < n; k++) {
        double az = 360.0 * (k + 0.5) / n, rg = 4000;
        bcis_entity_t e = {.id = 1,
                           .position = {rg * sin (az * M_PI / 180), rg * cos (az * M_PI / 180), 0},
                           .force = CGS_FORCE_FRIENDLY,
                           .transponder = true};
        cgs_dwell_t d = s_dwell_at (b, az, 0);
        bcis_dwell_out_t out;
        assert_int_equal (bcis_interrogator_dwell (b, &d, uav, &e, 1, &out), 0);
        assert_int_equal (out.reply_count, 1);
        const bcis_reply_t *r = &out.replies[0];
        assert_false (r->position_fix);
        assert_near (r->azimuth_deg, d.az_center_deg, 0);
        assert_near (r->range_sigma_m, p.range_sigma_m, 0);
        assert_near (r->azimuth_sigma_deg, d.width_deg / sqrt (12), 1e-12);
        sigma = r->azimuth_sigma_deg;
        // On the ground, along the beam's azimuth, at the measured slant range.
        assert_near (r->position.u_m, 0, 1e-9);
        double ground = hypot (r->position.e_m, r->position.n_m);
        assert_near (hypot (ground, 1000), r->range_m, 1e-6);
        double paz = atan2 (r->position.e_m, r->position.n_m) * 180 / M_PI;
        assert_near (remainder (paz - r->azimuth_deg, 360), 0, 1e-9);
        double err = remainder (az - r->azimuth_deg, 360);
        sa += err, sa2 += err * err;
    }
    double m = sa / n, sd = sqrt (sa2 / n - m * m);
    print_message ("# azimuth of the responder about the beam's: mean %.3f, sd %.3f deg (stated "
                   "%.3f)\n",
                   m, sd, sigma);
    assert_near (m, 0, 0.05);
    assert_near (sd, sigma, 0.02 * sigma);
    bcis_interrogator_destroy (&b);
}

/* Woods on the path: the budget carries Weissberger's loss for the depth the
 * terrain module measures, and a transponder deep in them is not heard. */
static void test_foliage_on_path (void **state)
{
    (void)state;
    cgs_terrain_t *t = s_ground (false);
    // A wood 15 m tall over the whole area south of north = -2000.
    float *c = calloc (241 * 241, sizeof *c);
    for (int r = 0; r < 241; r++)
        for (int k = 0; k < 241; k++)
            c[r * 241 + k] = -12000 + r * 100.0 < -2000 ? 15.0f : 0.0f;
    assert_int_equal (cgs_terrain_set_canopy (t, c), 0);
    free (c);
    bcis_params_t p = s_defaults ();
    bcis_interrogator_t *b = bcis_interrogator_new (&p, t, 10);
    cgs_enu_t uav = {0, 0, 1000};
    // Under the trees at 4 km: the path enters the canopy 12.5 m above the
    // antenna, (15 - 2.5) / sin(elevation) metres from it.
    bcis_entity_t in = {
        .id = 1, .position = {0, -4000, 0}, .force = CGS_FORCE_FRIENDLY, .transponder = true};
    bcis_truth_t tr;
    s_answers (b, uav, in, 180, 1, &tr);
    double el = atan2 (1000 - 2.5, 4000);
    assert_near (tr.geometry.foliage_m, 12.5 / sin (el), 1.0);
    assert_near (tr.budget.foliage_db, bcis_foliage_db (38, tr.geometry.foliage_m), 1e-12);
    // In the open at the same range: no foliage.
    bcis_entity_t out = {
        .id = 2, .position = {0, 4000, 0}, .force = CGS_FORCE_FRIENDLY, .transponder = true};
    bcis_truth_t tr2;
    s_answers (b, uav, out, 0, 1, &tr2);
    assert_near (tr2.geometry.foliage_m, 0, 0);
    assert_near (tr.budget.up_ebn0_db, tr2.budget.up_ebn0_db - tr.budget.foliage_db, 1e-9);
    print_message ("# under 15 m of trees at 4 km: %.1f m of foliage, %.1f dB; Eb/N0 up %.1f dB "
                   "(%.1f in the open), reply %.3f (%.3f)\n",
                   tr.geometry.foliage_m, tr.budget.foliage_db, tr.budget.up_ebn0_db,
                   tr2.budget.up_ebn0_db, tr.budget.p_reply, tr2.budget.p_reply);
    // Deep in the wood, far off: the path runs long under the canopy; no reply.
    bcis_entity_t deep = {
        .id = 3, .position = {0, -9000, 0}, .force = CGS_FORCE_FRIENDLY, .transponder = true};
    assert_int_equal (s_answers (b, uav, deep, 180, 100, &tr), 0);
    assert_true (tr.budget.foliage_db > 20);
    bcis_interrogator_destroy (&b);
    cgs_terrain_destroy (&t);
}

/* A sector scan visits only its sector, back and forth, at its rate. */
static void test_sector_scan (void **state)
{
    (void)state;
    bcis_params_t p = s_defaults ();
    p.scan_mode = CGS_SCAN_SECTOR;
    p.sector_center_deg = 45;
    p.sector_width_deg = 60;
    p.scan_rate_dps = 30;
    bcis_interrogator_t *b = bcis_interrogator_new (&p, NULL, 12);
    assert_non_null (b);
    const cgs_scan_t *s = bcis_interrogator_scan (b);
    assert_int_equal (s->dwells, 10); // 60 / 6
    assert_near (s->dwell_s, 0.2, 1e-12);
    cgs_enu_t uav = {0, 0, 1000};
    // One friendly in the sector at 30 deg, one outside it at 120 deg.
    bcis_entity_t e[] = {
        {.id = 1,
         .position = {5000 * sin (30 * M_PI / 180), 5000 * cos (30 * M_PI / 180), 0},
         .force = CGS_FORCE_FRIENDLY,
         .transponder = true},
        {.id = 2,
         .position = {5000 * sin (120 * M_PI / 180), 5000 * cos (120 * M_PI / 180), 0},
         .force = CGS_FORCE_FRIENDLY,
         .transponder = true},
    };
    unsigned int asked[3] = {0};
    double last_t[3] = {-1, -1, -1};
    double gap = 0;
    for (uint64_t k = 0; k < 10 * 20; k++) { // 20 passes
        cgs_dwell_t d;
        cgs_scan_dwell (s, k, 0, &d);
        // Every dwell inside [15, 75], its width the sector's tenth, its time width / rate.
        assert_true (d.az_center_deg > 15 && d.az_center_deg < 75);
        assert_near (d.end_s - d.start_s, 6.0 / 30, 1e-9);
        assert_near (d.start_s, k * 0.2, 1e-9);
        assert_int_equal (d.scan, k / 10 + 1);
        bcis_dwell_out_t out;
        assert_int_equal (bcis_interrogator_dwell (b, &d, uav, e, 2, &out), 0);
        for (size_t i = 0; i < out.truth_count; i++) {
            uint32_t id = out.truth[i].entity_id;
            // 30 deg lies in dwell 2 of a clockwise pass from 15 deg ([27, 33))
            // and in dwell 7 of an anticlockwise pass from 75 deg.
            uint64_t pass = k / 10;
            assert_int_equal (k, pass * 10 + (pass % 2 == 0 ? 2 : 7));
            asked[id]++;
            if (last_t[id] >= 0 && d.start_s - last_t[id] > gap)
                gap = d.start_s - last_t[id];
            last_t[id] = d.start_s;
        }
    }
    assert_int_equal (asked[1], 20); // once a pass
    assert_int_equal (asked[2], 0);  // never: outside the sector
    // Back and forth: visited 15 dwells (3 s) and 5 dwells (1 s) apart in turn.
    assert_near (gap, 15 * 0.2, 1e-9);
    bcis_interrogator_destroy (&b);
    // Referenced to the heading: centre 90 deg off the nose; flying east
    // (heading 90) the sector is 150..210 deg, and only it is visited.
    p.sector_center_deg = 90;
    p.sector_ref = CGS_SECTOR_HEADING;
    b = bcis_interrogator_new (&p, NULL, 13);
    assert_non_null (b);
    s = bcis_interrogator_scan (b);
    bcis_entity_t south = {
        .id = 1, .position = {0, -5000, 0}, .force = CGS_FORCE_FRIENDLY, .transponder = true};
    unsigned int south_asked = 0;
    for (uint64_t k = 0; k < 10 * 6; k++) {
        cgs_dwell_t d;
        cgs_scan_dwell (s, k, 90, &d);
        assert_true (d.az_center_deg > 150 && d.az_center_deg < 210);
        bcis_dwell_out_t out;
        assert_int_equal (bcis_interrogator_dwell (b, &d, uav, &south, 1, &out), 0);
        south_asked += (unsigned int)out.truth_count;
    }
    assert_int_equal (south_asked, 6); // once a pass
    bcis_interrogator_destroy (&b);
}

int main (void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test (test_params),
        cmocka_unit_test (test_params_errors),
        cmocka_unit_test (test_budget_hand_worked),
        cmocka_unit_test (test_rain_p838),
        cmocka_unit_test (test_foliage),
        cmocka_unit_test (test_ber_and_message),
        cmocka_unit_test (test_monte_carlo_messages),
        cmocka_unit_test (test_terrain_and_range),
        cmocka_unit_test (test_who_answers),
        cmocka_unit_test (test_reply_measurements),
        cmocka_unit_test (test_reply_geometry),
        cmocka_unit_test (test_foliage_on_path),
        cmocka_unit_test (test_sector_scan),
    };
    return cmocka_run_group_tests (tests, NULL, NULL);
}
