/* The MTI radar around the chain: the scan schedule (full revolution and
 * sector, at the sweep rate), the radar equation and clutter model against
 * hand-worked numbers, the clutter spread terms, terrain masking, hit
 * measurement noise against the sigmas it reports, and the drawn false
 * alarms against their binomial rate. */
#include "cgs_stats.h"
#include "cgs_terrain.h"
#include "mti_params.h"
#include "mti_radar.h"
#include "mti_theory.h"

#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "test_util.h"

static mti_params_t s_defaults (void)
{
    mti_params_t p;
    mti_params_defaults (&p);
    return p;
}

static void test_full_scan_schedule (void **state)
{
    (void)state;
    mti_params_t p = s_defaults ();
    mti_radar_t *r = mti_radar_new (&p, NULL, 1);
    assert_non_null (r);
    assert_int_equal (mti_radar_dwells_per_scan (r), 120);
    assert_near (mti_radar_dwell_s (r), 3.0 / 36.0, 1e-12);
    mti_dwell_t d;
    mti_radar_schedule (r, 0, 0, &d);
    assert_int_equal (d.scan, 1);
    assert_int_equal (d.dwell, 0);
    assert_true (d.scan_start && !d.scan_end);
    assert_near (d.az_from_deg, 0, 1e-9);
    assert_near (d.az_to_deg, 3, 1e-9);
    mti_radar_schedule (r, 119, 0, &d);
    assert_int_equal (d.scan, 1);
    assert_true (d.scan_end);
    assert_near (d.end_s, 10.0, 1e-9); // a revolution at 36 deg/s
    mti_radar_schedule (r, 120 * 7 + 30, 0, &d);
    assert_int_equal (d.scan, 8);
    assert_near (d.az_center_deg, 91.5, 1e-9);
    assert_int_equal (mti_radar_dwell_at (r, 10.0 + 1e-9), 120);
    assert_int_equal (mti_radar_dwell_at (r, 0.05), 0);
    assert_int_equal (mti_radar_dwell_at (r, NAN), 0); // bad times from the bus: no UB
    assert_int_equal (mti_radar_dwell_at (r, -5), 0);
    assert_int_equal (mti_radar_dwell_at (r, INFINITY), 0);
    // A target at any azimuth is in the beam in exactly one dwell per scan.
    mti_platform_t plat = {.position = {0, 0, 1500}};
    for (double az = 0.5; az < 360; az += 7.3) {
        mti_target_t t = {
            .id = 5, .position = {8000 * sin (az * M_PI / 180), 8000 * cos (az * M_PI / 180), 0}};
        int seen = 0;
        for (uint64_t k = 120; k < 240; k++) {
            mti_dwell_out_t out;
            mti_radar_schedule (r, k, 0, &d);
            assert_int_equal (mti_radar_dwell (r, &d, &plat, &t, 1, &out), 0);
            if (out.truth_count) {
                seen++;
                assert_true (fabs (remainder (az - d.az_center_deg, 360)) <= 1.5 + 1e-9);
            }
        }
        assert_int_equal (seen, 1);
    }
    mti_radar_destroy (&r);
    mti_radar_destroy (&r);
}

static void test_sector_scan (void **state)
{
    (void)state;
    mti_params_t p = s_defaults ();
    p.scan_mode = MTI_SCAN_SECTOR;
    p.sector_center_deg = 350;
    p.sector_width_deg = 31; // ten dwells of 3.1 deg
    mti_radar_t *r = mti_radar_new (&p, NULL, 1);
    assert_non_null (r);
    assert_int_equal (mti_radar_dwells_per_scan (r), 10);
    assert_near (mti_radar_dwell_s (r), 3.1 / 36, 1e-12);
    double t_prev = 0;
    for (uint64_t k = 0; k < 40; k++) {
        mti_dwell_t d;
        mti_radar_schedule (r, k, 0, &d);
        assert_int_equal (d.scan, k / 10 + 1);
        // Only the sector is visited: every dwell centre within it.
        assert_true (fabs (remainder (d.az_center_deg - 350, 360)) <= 15.5 - 1.55 + 1e-9);
        // Back and forth: forward passes go clockwise, the others back.
        double step = remainder (d.az_to_deg - d.az_from_deg, 360);
        double expect = (k / 10) % 2 == 0 ? 3.1 : -3.1;
        assert_near (step, expect, 1e-9);
        // At its rate: the beam moves 3.1 deg in each dwell's time.
        assert_near (d.end_s - d.start_s, 3.1 / 36, 1e-12);
        assert_near (d.start_s, t_prev, 1e-9);
        t_prev = d.end_s;
    }
    mti_dwell_t d;
    mti_radar_schedule (r, 0, 0, &d);
    assert_near (d.az_from_deg, 334.5, 1e-9);
    mti_radar_schedule (r, 10, 0, &d);
    assert_near (d.az_from_deg, 5.5, 1e-9);
    mti_radar_destroy (&r);
    // Referenced to the heading: the sector turns with the UAV.
    p.sector_ref = MTI_SECTOR_HEADING;
    p.sector_center_deg = 90; // off the right wing
    r = mti_radar_new (&p, NULL, 1);
    mti_radar_schedule (r, 5, 45, &d);
    assert_near (d.az_from_deg, 135 - 15.5 + 5 * 3.1, 1e-9);
    mti_radar_destroy (&r);
}

/* The radar equation, worked by hand: 20 kW, 200 ns, 24 dB, 16 GHz
 * (lambda = 0.018737 m), 4 dB noise figure, 5 dB losses, 290 K: a 10 m^2
 * target at 10 km has SNR 1.47 dB per pulse (19.5 dB after 64 pulses). */
static void test_radar_equation (void **state)
{
    (void)state;
    mti_params_t p = s_defaults ();
    mti_radar_t *r = mti_radar_new (&p, NULL, 1);
    double snr = mti_radar_snr (r, 10, 10000, 0);
    assert_near (10 * log10 (snr), 1.4735, 0.001);
    // R^-4, and the two-way elevation pattern: -6 dB at half the one-way beamwidth...
    assert_near (mti_radar_snr (r, 10, 20000, 0), snr / 16, snr * 1e-12);
    assert_near (10 * log10 (mti_radar_snr (r, 10, 10000, 30) / snr), -6.0206, 0.001);
    // Clutter, constant gamma -15 dB at 10 deg grazing: sigma0 A = 87.59 m^2,
    // CNR 10.90 dB per pulse.
    double cnr = mti_radar_cnr (r, 10000, 10, 0);
    assert_near (10 * log10 (cnr), 10.898, 0.001);
    assert_near (cnr / snr, 87.5868 / 10, 1e-4);
    assert_near (mti_radar_cnr (r, 10000, 0, 0), 0, 0);  // grazing 0: none
    assert_near (mti_radar_cnr (r, 10000, -5, 0), 0, 0); // facing away: none
    // Spread: internal 0.1 m/s -> 10.67 Hz, scan 0.265 * 36/3 = 3.18 Hz,
    // platform 38 m/s broadside 0.3 * 3 deg * 2 * 38 / lambda = 63.71 Hz.
    assert_near (mti_radar_clutter_sigma_hz (r, 0, 0), hypot (10.674, 3.18), 0.01);
    assert_near (mti_radar_clutter_sigma_hz (r, 38, 90),
                 sqrt (10.674 * 10.674 + 3.18 * 3.18 + 63.714 * 63.714), 0.01);
    assert_near (mti_radar_clutter_sigma_hz (r, 38, 0), hypot (10.674, 3.18), 0.01);
    mti_radar_destroy (&r);
}

/* A ridge 600 m high runs north-south at 4 km east; the UAV flies 1 km up
 * at the origin. A mover 3 km east answers; one 7 km east, in the ridge's
 * shadow, never does. */
static void test_terrain_masks (void **state)
{
    (void)state;
    int cols = 401, rows = 401;
    float *h = calloc ((size_t)cols * rows, sizeof *h);
    for (int rr = 0; rr < rows; rr++)
        for (int c = 0; c < cols; c++) {
            double e = -10000 + c * 50.0;
            h[rr * cols + c] = (float)(600 * exp (-pow ((e - 4000) / 300, 2)));
        }
    cgs_terrain_t *t = cgs_terrain_new_grid (cols, rows, -10000, -10000, 50, h);
    free (h);
    assert_non_null (t);
    mti_params_t p = s_defaults ();
    mti_radar_t *r = mti_radar_new (&p, t, 3);
    mti_platform_t plat = {.position = {0, 0, 1000}, .velocity = {0, 30, 0}};
    mti_target_t tg[2] = {
        {.id = 1, .position = {3000, 0, 0}, .velocity = {-10, 0, 0}, .rcs_class = "vehicle"},
        {.id = 2, .position = {7000, 0, 0}, .velocity = {-10, 0, 0}, .rcs_class = "vehicle"},
    };
    int det[3] = {0}, vis[3] = {0}, seen[3] = {0};
    for (int scan = 0; scan < 30; scan++) {
        mti_dwell_t d;
        mti_radar_schedule (r, (uint64_t)scan * 120 + 30, 0, &d); // the dwell looking east
        mti_dwell_out_t out;
        assert_int_equal (mti_radar_dwell (r, &d, &plat, tg, 2, &out), 0);
        for (size_t i = 0; i < out.truth_count; i++) {
            uint32_t id = out.truth[i].entity_id;
            seen[id]++;
            vis[id] += out.truth[i].visible;
            det[id] += out.truth[i].detected;
        }
        for (size_t i = 0; i < out.hit_count; i++)
            assert_int_not_equal (out.hits[i].entity_id, 2);
    }
    print_message ("# in the open: seen %d, visible %d, detected %d; behind the ridge: seen %d, "
                   "visible %d, detected %d\n",
                   seen[1], vis[1], det[1], seen[2], vis[2], det[2]);
    assert_int_equal (seen[1], 30);
    assert_int_equal (vis[1], 30);
    assert_true (det[1] >= 25);
    assert_int_equal (seen[2], 30);
    assert_int_equal (vis[2], 0);
    assert_int_equal (det[2], 0);
    mti_radar_destroy (&r);
    cgs_terrain_destroy (&t);
}

/* Hits of a strong target of class cls, azimuth measured by method: the
 * range is its gate's centre, the radial velocity within a Doppler bin, the
 * position on the ground where they point. Returns the rms of azimuth error
 * over reported sigma, and the rms azimuth error in degrees. */
static void s_hit_measurement (mti_azimuth_t method, const char *cls, double *ret_z,
                               double *ret_deg)
{
    mti_params_t p = s_defaults ();
    p.clutter_gamma_db = -80; // no clutter to speak of
    p.azimuth = method;
    p.classes[p.class_count++] = (mti_class_t){"bright", 1000, MTI_SWERLING_2};
    mti_radar_t *r = mti_radar_new (&p, NULL, 4);
    mti_platform_t plat = {.position = {0, 0, 2000}};
    double rg = 8000;
    double slant = hypot (rg, 2000), vbin = mti_params_wavelength_m (&p) * p.prf_hz / (2 * 64);
    int n = 0;
    double sum_z2 = 0, sum_e2 = 0;
    for (int scan = 0; scan < 400; scan++) {
        // Anywhere in the dwell from 39 to 42 degrees.
        double az = 39.0 + 3.0 * (scan + 0.5) / 400;
        mti_target_t t = {.id = 9,
                          .position = {rg * sin (az * M_PI / 180), rg * cos (az * M_PI / 180), 0},
                          .velocity = {6 * sin (az * M_PI / 180), 6 * cos (az * M_PI / 180), 0},
                          .rcs_class = cls};
        mti_dwell_t d;
        mti_radar_schedule (r, (uint64_t)scan * 120 + 13, 0, &d);
        mti_dwell_out_t out;
        assert_int_equal (mti_radar_dwell (r, &d, &plat, &t, 1, &out), 0);
        for (size_t i = 0; i < out.hit_count; i++) {
            const mti_hit_t *h = &out.hits[i];
            if (h->entity_id != 9)
                continue;
            n++;
            assert_near (h->range_m, (floor (slant / 30) + 0.5) * 30, 1e-9);
            assert_near (h->range_sigma_m, 30 / sqrt (12), 1e-9);
            assert_near (h->radial_velocity_mps, 6 * rg / slant, vbin / 2 + 1e-9);
            double e = remainder (h->azimuth_deg - az, 360), z = e / h->azimuth_sigma_deg;
            sum_z2 += z * z;
            sum_e2 += e * e;
            double ground = sqrt (h->range_m * h->range_m - 2000.0 * 2000.0);
            assert_near (hypot (h->position.e_m, h->position.n_m), ground, 0.5);
            assert_near (h->position.u_m, 0, 1e-9);
        }
    }
    *ret_z = sqrt (sum_z2 / n);
    *ret_deg = sqrt (sum_e2 / n);
    print_message ("# %s, %s: %d hits; azimuth error rms %.3f deg, / reported sigma %.3f\n",
                   method == MTI_AZIMUTH_MONOPULSE ? "monopulse" : "beam split", cls, n, *ret_deg,
                   *ret_z);
    assert_true (n >= 380);
    mti_radar_destroy (&r);
}

/* Beam splitting on a target that fluctuates from interval to interval
 * reports the spread it has (the floor of about 0.62 degrees, mti_azimuth.h);
 * on a constant target it is better than it says (it allows for the
 * fluctuation it cannot tell is absent). Monopulse reports what it has. */
static void test_hit_measurement (void **state)
{
    (void)state;
    double z, deg;
    s_hit_measurement (MTI_AZIMUTH_BEAM_SPLIT, "bright", &z, &deg);
    assert_near (z, 1.0, 0.12);
    assert_near (deg, 0.62, 0.08);
    s_hit_measurement (MTI_AZIMUTH_BEAM_SPLIT, "reflector", &z, &deg);
    assert_true (z < 0.5 && deg < 0.3);
    s_hit_measurement (MTI_AZIMUTH_MONOPULSE, "reflector", &z, &deg);
    assert_near (z, 1.0, 0.12);
}

/* With no targets, each dwell's false alarms are binomial over its gates at
 * the probability the CFAR design and m-of-n give; they lie in the dwell. */
static void test_false_alarm_rate (void **state)
{
    (void)state;
    mti_params_t p = s_defaults ();
    p.pfa = 1e-3;
    mti_radar_t *r = mti_radar_new (&p, NULL, 6);
    double pc = mti_radar_cpi_pfa (r), indep = 1 - pow (1 - 1e-3, 64);
    // The Hamming window correlates neighbouring bins: a little below independence.
    assert_true (pc < indep && pc > 0.85 * indep);
    double pg = mti_theory_m_of_n (pc, 2, 4);
    assert_near (mti_radar_gate_pfa (r), pg, 1e-12);
    assert_int_equal (mti_radar_gates (r), (uint32_t)((20000 - 500) / 30));
    mti_platform_t plat = {.position = {0, 0, 1500}};
    unsigned long total = 0, dwells = 300;
    for (uint64_t k = 0; k < dwells; k++) {
        mti_dwell_t d;
        mti_dwell_out_t out;
        mti_radar_schedule (r, k, 0, &d);
        assert_int_equal (mti_radar_dwell (r, &d, &plat, NULL, 0, &out), 0);
        assert_int_equal (out.hit_count, out.false_alarms);
        total += out.false_alarms;
        for (size_t i = 0; i < out.hit_count; i++) {
            assert_int_equal (out.hits[i].entity_id, 0);
            // Not nearer than the UAV's 1500 m height: such gates reach no ground.
            assert_true (out.hits[i].range_m > 1500 && out.hits[i].range_m <= 20000);
            assert_true (fabs (remainder (out.hits[i].azimuth_deg - d.az_center_deg, 360)) <=
                         1.5 + 5 * out.hits[i].azimuth_sigma_deg);
        }
    }
    unsigned long lo, hi;
    unsigned long reach = mti_radar_gates (r) - (unsigned long)ceil ((1500.0 - 500) / 30);
    assert_int_equal (cgs_binomial_count_interval (pg, dwells * reach, 0.99, &lo, &hi), 0);
    print_message ("# %lu false alarms in %lu dwells of %lu gates beyond the height (expected "
                   "%.1f, 99%% [%lu, %lu])\n",
                   total, dwells, reach, pg * dwells * reach, lo, hi);
    assert_in_range (total, lo, hi);
    mti_radar_destroy (&r);
}

/* Two targets the radar does not resolve (one range gate, one Doppler bin,
 * one beam) give one hit, between them in azimuth, and the weaker's truth
 * names it (three: both weaker ones); apart in range by two gates, or in radial velocity by several
 * bins, they give two. 4 km out, where each is detected every time. */
static void test_unresolved_targets_merge (void **state)
{
    (void)state;
    mti_params_t p = s_defaults ();
    mti_radar_t *r = mti_radar_new (&p, NULL, 3);
    assert_non_null (r);
    mti_platform_t plat = {.position = {0, 0, 1200}};
    const double g = 4000, S = M_PI / 180;
    const struct {
        double dg_m, vr2; // the second target: farther along the ground, radial speed
        size_t hits;
    } cases[] = {{0, 8, 1}, {2 * 30 * 4000 / hypot (4000, 1200) + 1, 8, 2}, {0, -8, 2}};
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
        int dwells = 0;
        for (uint64_t k = 15; k < 120 * 30; k += 120) { // dwell 15: 45 to 48 deg
            mti_dwell_t d;
            mti_radar_schedule (r, k, 0, &d);
            double a1 = 46.0 * S, a2 = 47.0 * S, g2 = g + cases[c].dg_m;
            mti_target_t t[2] = {
                {.id = 7,
                 .position = {g * sin (a1), g * cos (a1), 0},
                 .velocity = {8 * sin (a1), 8 * cos (a1), 0}},
                {.id = 9,
                 .position = {g2 * sin (a2), g2 * cos (a2), 0},
                 .velocity = {cases[c].vr2 * sin (a2), cases[c].vr2 * cos (a2), 0}},
            };
            mti_dwell_out_t o;
            assert_int_equal (mti_radar_dwell (r, &d, &plat, t, 2, &o), 0);
            assert_int_equal (o.truth_count, 2);
            size_t from_targets = 0;
            const mti_hit_t *h = NULL;
            for (size_t i = 0; i < o.hit_count; i++)
                if (o.hits[i].entity_id) {
                    from_targets++;
                    h = &o.hits[i];
                }
            if (from_targets != cases[c].hits)
                fail_msg ("case %zu, dwell %llu: %zu hits of the two targets, expected %zu", c,
                          (unsigned long long)k, from_targets, cases[c].hits);
            const mti_truth_t *a = &o.truth[0], *b = &o.truth[1];
            if (cases[c].hits == 1) {
                // One detected, the other merged into its hit; the hit between them.
                const mti_truth_t *seen = a->detected ? a : b, *hid = a->detected ? b : a;
                assert_true (seen->detected && !hid->detected);
                assert_int_equal (seen->hit_id, h->hit_id);
                assert_int_equal (hid->merged_into, h->hit_id);
                assert_int_equal (hid->hit_id, 0);
                assert_true (h->azimuth_deg > 46.0 - 3 * h->azimuth_sigma_deg &&
                             h->azimuth_deg < 47.0 + 3 * h->azimuth_sigma_deg);
            } else {
                assert_true (a->detected && b->detected);
                assert_int_equal (a->merged_into, 0);
                assert_int_equal (b->merged_into, 0);
                assert_int_not_equal (a->hit_id, b->hit_id);
            }
            dwells++;
        }
        assert_int_equal (dwells, 30);
    }
    // Three in one cell: one hit, both others' truth naming it.
    for (uint64_t k = 15; k < 120 * 10; k += 120) {
        mti_dwell_t d;
        mti_radar_schedule (r, k, 0, &d);
        mti_target_t t[3];
        for (int i = 0; i < 3; i++) {
            double a = (46.0 + 0.5 * i) * S;
            t[i] = (mti_target_t){.id = 20 + (uint32_t)i,
                                  .position = {g * sin (a), g * cos (a), 0},
                                  .velocity = {8 * sin (a), 8 * cos (a), 0}};
        }
        mti_dwell_out_t o;
        assert_int_equal (mti_radar_dwell (r, &d, &plat, t, 3, &o), 0);
        const mti_hit_t *h = NULL;
        size_t hits = 0, merged = 0, seen = 0;
        for (size_t i = 0; i < o.hit_count; i++)
            if (o.hits[i].entity_id)
                h = &o.hits[i], hits++;
        assert_int_equal (hits, 1);
        for (size_t i = 0; i < o.truth_count; i++) {
            merged += o.truth[i].merged_into == h->hit_id && !o.truth[i].detected;
            seen += o.truth[i].detected && o.truth[i].hit_id == h->hit_id;
        }
        assert_int_equal (seen, 1);
        assert_int_equal (merged, 2);
    }
    mti_radar_destroy (&r);
}

/* The truth's Pd (the dwell's, from theory) against the detections it
 * stands for, for each fluctuation model: a target 11 km out along the
 * platform's motion (Pd in mid-range, where the models differ most), 600
 * dwells; the mean Pd the truth gives within 0.05 beyond the 99% spread of
 * the count (the truth takes the target's own Doppler bin, the detection
 * any bin its echo reaches). */
static void test_truth_pd_matches_detections (void **state)
{
    (void)state;
    const mti_swerling_t models[] = {MTI_SWERLING_0, MTI_SWERLING_1, MTI_SWERLING_2};
    double mean[3];
    for (int k = 0; k < 3; k++) {
        mti_params_t p = s_defaults ();
        p.classes[0].swerling = models[k]; // "vehicle"
        mti_radar_t *r = mti_radar_new (&p, NULL, 21 + (uint64_t)k);
        assert_non_null (r);
        mti_platform_t plat = {.position = {0, 0, 1200}, .velocity = {40, 0, 0}};
        const double S = M_PI / 180, a = 46.5 * S, g = 11000;
        mti_target_t t = {.id = 1,
                          .position = {g * sin (a), g * cos (a), 0},
                          .velocity = {8 * sin (a), 8 * cos (a), 0},
                          .rcs_class = "vehicle"};
        int seen = 0, det = 0;
        double sum = 0;
        for (uint64_t d = 15; d < 120 * 600; d += 120) { // dwell 15: 45 to 48 deg
            mti_dwell_t dw;
            mti_radar_schedule (r, d, 0, &dw);
            mti_dwell_out_t o;
            assert_int_equal (mti_radar_dwell (r, &dw, &plat, &t, 1, &o), 0);
            assert_int_equal (o.truth_count, 1);
            seen++;
            det += o.truth[0].detected;
            sum += o.truth[0].pd;
        }
        double measured = (double)det / seen;
        mean[k] = sum / seen;
        print_message ("# Swerling %d at 11 km: detected %.3f of %d dwells, the truth's Pd %.3f\n",
                       (int)models[k], measured, seen, mean[k]);
        assert_true (fabs (measured - mean[k]) <=
                     0.05 + 2.58 * sqrt (mean[k] * (1 - mean[k]) / seen));
        mti_radar_destroy (&r);
    }
    // Mid-range, the models differ: the hop's diversity beats one draw a dwell.
    assert_true (mean[2] > mean[1] + 0.05);
}

int main (void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test (test_full_scan_schedule),
        cmocka_unit_test (test_sector_scan),
        cmocka_unit_test (test_radar_equation),
        cmocka_unit_test (test_terrain_masks),
        cmocka_unit_test (test_hit_measurement),
        cmocka_unit_test (test_false_alarm_rate),
        cmocka_unit_test (test_unresolved_targets_merge),
        cmocka_unit_test (test_truth_pd_matches_detections),
    };
    return cmocka_run_group_tests (tests, NULL, NULL);
}
