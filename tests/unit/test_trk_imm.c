/* The default tracker (trackerd's `mode = imm`) against theory and worked
 * cases: the expected detection probability in and out of the clutter
 * notch, against the closed form and against mtid's own chain, and behind
 * a ridge; the IMM's
 * mixing against a case worked by hand; the mode probabilities switching to
 * "stopped" within two scans of a halt, and the track surviving the halt;
 * a target crossing the radar's line of sight (in the notch) coasting
 * through instead of dying; the filter's consistency (NEES and NIS of
 * straight-line targets inside their 95% chi-square bands, Monte Carlo);
 * identity carried to a new track after a deletion; two crossing targets;
 * the checkpoint of the models; the existence of two tracks that share one
 * hit, weighed over the k best joint hypotheses (JIPDA). */
#include "cgs_ckpt.h"
#include "cgs_util.h"
#include "mti_radar.h"
#include "trk_checkpoint.h"
#include "trk_imm.h"
#include "trk_params.h"
#include "trk_pd.h"
#include "trk_tracker.h"

#include <errno.h>
#include <gsl/gsl_cdf.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "test_util.h"

#define S_PI 3.14159265358979323846

/* Gaussian noise: Box-Muller over a 64-bit LCG. */
static double s_gauss (uint64_t *s)
{
    double u[2];
    for (int i = 0; i < 2; i++) {
        *s = *s * 6364136223846793005ull + 1442695040888963407ull;
        u[i] = ((double)(*s >> 11) + 0.5) / 9007199254740992.0;
    }
    return sqrt (-2 * log (u[0])) * cos (2 * S_PI * u[1]);
}

static trk_params_t s_defaults (void)
{
    trk_params_t p;
    trk_params_defaults (&p);
    assert_int_equal (p.filter.mode, TRK_FILTER_IMM);
    return p;
}

/* The radar of these tests: at the origin, 1200 m up, flying east at 40 m/s. */
static const double s_radar_pos[3] = {0, 0, 1200};

static trk_scan_t s_scan_of (uint32_t k)
{
    return (trk_scan_t){.uav_id = 1,
                        .scan_number = k + 1,
                        .start_s = 10.0 * k,
                        .end_s = 10.0 * k + 10,
                        .full_revolution = true,
                        .platform = {0, 0},
                        .platform_up_m = 1200,
                        .platform_velocity = {40, 0}};
}

/* A hit of a target at (e, n) moving at (ve, vn), seen at time t with
 * position noise sigma (0: exact) and radial velocity noise 0.5 m/s. */
static trk_hit_t s_hit (uint32_t id, double t, double e, double n, double ve, double vn,
                        double sigma, uint64_t *rng)
{
    double de = e, dn = n, du = -1200, slant = sqrt (de * de + dn * dn + du * du);
    double vr = (de * ve + dn * vn) / slant;
    double ze = e + (sigma > 0 ? sigma * s_gauss (rng) : 0);
    double zn = n + (sigma > 0 ? sigma * s_gauss (rng) : 0);
    double az = atan2 (ze, zn) * 180 / S_PI;
    return trk_hit_from_mti (id, t, (cgs_enu_t){ze, zn, 0}, (cgs_enu_t){0, 0, 1200}, az, 0, 0,
                             vr + (sigma > 0 ? 0.5 * s_gauss (rng) : 0));
}

static trk_scan_out_t s_run (trk_tracker_t *t, uint32_t k, const trk_hit_t *h, size_t n)
{
    trk_scan_t sc = s_scan_of (k);
    trk_scan_out_t o;
    assert_int_equal (trk_tracker_scan (t, &sc, h, n, &o), 0);
    return o;
}

/* ---- detection probability ------------------------------------------------------- */

static trk_pd_radar_t s_pd_radar (void)
{
    return (trk_pd_radar_t){.position = {s_radar_pos[0], s_radar_pos[1], s_radar_pos[2]},
                            .velocity = {40, 0},
                            .full_revolution = true};
}

/* Pd of a target at ground range g (8 km unless said) in direction az_deg,
 * radial velocity vr (over the ground, along the slant line of sight),
 * sigma_vr 0. */
static double s_pd_at_range (const trk_params_t *p, double az_deg, double vr, double g)
{
    trk_pd_radar_t r = s_pd_radar ();
    double az = az_deg * S_PI / 180, slant = hypot (g, 1200);
    double x[3] = {g * sin (az), g * cos (az), 0};
    double v[2] = {vr * slant / g * sin (az), vr * slant / g * cos (az)};
    return trk_pd_of (&p->detection, &r, x, v, 0);
}

static double s_pd_at (const trk_params_t *p, double az_deg, double vr)
{
    return s_pd_at_range (p, az_deg, vr, 8000);
}

static void test_pd_notch_closed_form (void **state)
{
    (void)state;
    trk_params_t p = s_defaults ();
    const trk_pd_params_t *d = &p.detection;
    // Clear of the notch, by slant range: pd near, half of it at
    // half_range, pd / (1 + 2^k) at twice that.
    assert_near (trk_pd_at_range (d, 0), d->pd, 1e-12);
    assert_near (trk_pd_at_range (d, d->half_range_m), d->pd / 2, 1e-12);
    assert_near (trk_pd_at_range (d, 2 * d->half_range_m), d->pd / (1 + pow (2, d->range_exponent)),
                 1e-12);
    // The targets below are 8 km from the radar along the ground, 1200 m
    // under it: pd8 clear of the notch.
    const double pd8 = trk_pd_at_range (d, hypot (8000, 1200));
    assert_true (pd8 > 0.95 && pd8 < 0.99);
    // The MDV across the platform's motion and along it.
    assert_near (trk_pd_mdv (d, S_PI / 2), d->mdv_across_mps, 1e-12);
    assert_near (trk_pd_mdv (d, 0), d->mdv_along_mps, 1e-12);
    assert_near (
        trk_pd_mdv (d, S_PI / 4),
        sqrt ((d->mdv_along_mps * d->mdv_along_mps + d->mdv_across_mps * d->mdv_across_mps) / 2),
        1e-12);
    // North of the radar (across its motion): half of pd at the MDV, none
    // at rest, all of pd well clear, none at the blind speed.
    assert_true (s_pd_at (&p, 0, 0) < 1e-6);
    assert_near (s_pd_at (&p, 0, d->mdv_across_mps), pd8 / 2, 1e-9);
    assert_near (s_pd_at (&p, 0, -d->mdv_across_mps), pd8 / 2, 1e-9);
    assert_near (s_pd_at (&p, 0, 8), pd8, 1e-6);
    assert_true (s_pd_at (&p, 0, d->span_mps) < 1e-6);
    assert_near (s_pd_at (&p, 0, d->span_mps + 8), pd8, 1e-6);
    // One standard deviation of the edge above the MDV: pd Φ(1).
    assert_near (s_pd_at (&p, 0, d->mdv_across_mps + d->width_mps), pd8 * 0.841344746068543, 1e-9);
    // East of it (along its motion): the narrower notch.
    assert_near (s_pd_at (&p, 90, d->mdv_along_mps), pd8 / 2, 1e-9);
    assert_true (s_pd_at (&p, 90, 2.2) > 0.85 * pd8);
    // A vehicle driving across the line of sight is in the notch.
    trk_pd_radar_t r = s_pd_radar ();
    double x[3] = {0, 8000, 0}, across[2] = {12, 0}, away[2] = {0, 12};
    assert_true (trk_pd_of (d, &r, x, across, 0) < 1e-6);
    assert_near (trk_pd_of (d, &r, x, away, 0), pd8, 1e-6);
    // An uncertain radial velocity at the edge: the same half, a wider edge.
    assert_near (
        trk_pd_of (d, &r, x, (double[2]){0, d->mdv_across_mps * hypot (8000, 1200) / 8000}, 1.0),
        pd8 / 2, 1e-9);
    // Outside the range window, and outside the sector swept: nothing.
    double far[3] = {0, 25000, 0}, near[3] = {0, 300, 0};
    assert_true (trk_pd_of (d, &r, far, away, 0) == 0);
    assert_true (trk_pd_of (d, &r, near, away, 0) == 0);
    r.full_revolution = false;
    r.sector_center_deg = 180;
    r.sector_width_deg = 90;
    assert_true (trk_pd_of (d, &r, x, away, 0) == 0);
    r.sector_center_deg = 10;
    assert_near (trk_pd_of (d, &r, x, away, 0), pd8, 1e-6);
}

/* Terrain: a ridge 1 km high across the line of sight, 4 km north of the
 * radar, hides a target 8 km north (Pd zero); the same target 8 km east,
 * clear of the ridge, keeps its Pd; without the terrain the ridge is not
 * known. */
static void test_pd_terrain_masking (void **state)
{
    (void)state;
    trk_params_t p = s_defaults ();
    enum { C = 101, R = 101 };
    static float h[C * R];
    for (int r = 0; r < R; r++)
        for (int c = 0; c < C; c++) {
            double n = -10000 + 200.0 * r, e = -10000 + 200.0 * c;
            h[r * C + c] = (float)((fabs (n - 4000) < 300 && e > -2000 && e < 2000) ? 1000 : 0);
        }
    cgs_terrain_t *ter = cgs_terrain_new_grid (C, R, -10000, -10000, 200, h);
    assert_non_null (ter);
    trk_pd_radar_t r = s_pd_radar ();
    double north[3] = {0, 8000, 0}, east[3] = {8000, 0, 0};
    double away_n[2] = {0, 12}, away_e[2] = {12, 0};
    double pd8 = trk_pd_at_range (&p.detection, hypot (8000, 1200));
    assert_near (trk_pd_of (&p.detection, &r, north, away_n, 0), pd8, 1e-6);
    r.terrain = ter;
    assert_true (trk_pd_of (&p.detection, &r, north, away_n, 0) == 0);
    double pd_e = trk_pd_of (&p.detection, &r, east, away_e, 0);
    assert_true (pd_e > 0.8 * pd8);
    cgs_terrain_destroy (&ter);
}

/* The tracker's expectation against mtid's chain itself (the default radar,
 * flat ground, the default targets: Swerling II from one coherent interval
 * to the next): the dwell detection rate of a target at several ranges
 * (4 to 16 km, clear of the notch) and, at 8 km, at several radial
 * velocities, across and along the platform's motion, within 0.06 beyond
 * the 99% spread of 400 dwells. */
static void test_pd_against_mtid_chain (void **state)
{
    (void)state;
    trk_params_t p = s_defaults ();
    mti_params_t mp;
    mti_params_defaults (&mp);
    mti_radar_t *radar = mti_radar_new (&mp, NULL, 11);
    assert_non_null (radar);
    uint32_t D = mti_radar_dwells_per_scan (radar);
    double worst = 0;
    const struct {
        double az_deg, vr, R;
    } cases[] = {{20, 0.5, 8000}, {20, 2.2, 8000}, {20, 4, 8000},   {20, 10, 8000},
                 {90, 0.3, 8000}, {90, 0.8, 8000}, {70, 6, 8000},   {20, 10, 4000},
                 {20, 10, 10000}, {20, 10, 11000}, {20, 10, 12000}, {20, 10, 13000},
                 {20, 10, 14000}, {20, 10, 16000}, {0, 1.5, 8000},  {0, 2.0, 8000}};
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
        double az = cases[c].az_deg * S_PI / 180, R = cases[c].R, vr = cases[c].vr;
        int seen = 0, det = 0;
        double truth_pd = 0; // mtid's own dwell Pd, from theory, summed
        for (int s = 0; s < 400; s++)
            for (uint32_t k = 0; k < D; k++) {
                mti_dwell_t dw;
                mti_radar_schedule (radar, (uint64_t)s * D + k, 0, &dw);
                if (fabs (dw.az_center_deg - cases[c].az_deg) > dw.width_deg)
                    continue;
                mti_platform_t pl = {.position = {0, 0, 1200}, .velocity = {40, 0, 0}};
                double slant = hypot (R, 1200), vg = vr * slant / R;
                mti_target_t tg = {.id = 1,
                                   .position = {R * sin (az), R * cos (az), 0},
                                   .velocity = {vg * sin (az), vg * cos (az), 0}};
                mti_dwell_out_t o;
                assert_int_equal (mti_radar_dwell (radar, &dw, &pl, &tg, 1, &o), 0);
                for (size_t i = 0; i < o.truth_count; i++) {
                    seen++;
                    det += o.truth[i].detected;
                    truth_pd += o.truth[i].pd;
                }
            }
        assert_true (seen >= 400);
        double measured = (double)det / seen, expected = s_pd_at_range (&p, cases[c].az_deg, vr, R);
        // The model's error (0.06 at most) and the count's 99% spread.
        double allowed = 0.06 + 2.58 * sqrt (expected * (1 - expected) / seen);
        truth_pd /= seen;
        print_message ("az %2.0f deg, v_r %4.1f m/s, %2.0f km: mtid %.3f (%d dwells; its truth "
                       "says %.3f), tracker expects %.3f (+-%.3f)\n",
                       cases[c].az_deg, vr, R / 1000, measured, seen, truth_pd, expected, allowed);
        worst = fmax (worst, fabs (measured - expected) / allowed);
        // mtid's truth Pd (the dwell's, by the target's model) against its own count.
        assert_true (fabs (measured - truth_pd) <=
                     0.04 + 2.58 * sqrt (truth_pd * (1 - truth_pd) / seen));
    }
    assert_true (worst <= 1);
    mti_radar_destroy (&radar);
}

/* ---- the IMM ---------------------------------------------------------------------- */

/* Mixing worked by hand: sojourns of 10 s over dt = 10 ln 2 s keep each
 * model with probability 1/2 and split the rest evenly, so Π has 1/2 on
 * its diagonal and 1/4 elsewhere. With μ = (0.6, 0.3, 0.1):
 *   c = Πᵀ μ = (0.4, 0.325, 0.275);
 *   the CV model's mixing weights μ_i|1 = Π_i1 μ_i / c_1 = (0.75, 0.1875, 0.0625);
 * with x_1 = (0, 0, 10, 0), x_2 = (10, 0, 0, 0), x_3 = 0 and P_i = i·I:
 *   x_01 = (1.875, 0, 7.5, 0),
 *   P_01[e][e] = Σ μ_i|1 (P_i + (x_i,e − 1.875)²) = 16.546875,
 *   P_01[e][ve] = −14.0625, P_01[ve][ve] = 20.0625, P_01[n][n] = 1.3125. */
static void test_imm_mixing_worked_example (void **state)
{
    (void)state;
    trk_imm_params_t p = {.sigma_mps2 = {0.2, 1.5},
                          .stopped_sigma_mps = 0.05,
                          .sojourn_s = {10, 10, 10},
                          .exit = {{0, 0.5, 0.5}, {0.5, 0, 0.5}, {0.5, 0.5, 0}}};
    double pi[9];
    trk_imm_transition (&p, 10 * log (2), pi);
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            assert_near (pi[i * 3 + j], i == j ? 0.5 : 0.25, 1e-12);
    trk_imm_t s;
    memset (&s, 0, sizeof s);
    s.mu[0] = 0.6, s.mu[1] = 0.3, s.mu[2] = 0.1;
    s.m[0].x[2] = 10;
    s.m[1].x[0] = 10;
    for (int j = 0; j < 3; j++)
        for (int a = 0; a < 4; a++)
            s.m[j].P[a * 5] = j + 1;
    trk_imm_t mx;
    trk_imm_mix (&p, &s, 10 * log (2), &mx);
    assert_near (mx.mu[0], 0.4, 1e-12);
    assert_near (mx.mu[1], 0.325, 1e-12);
    assert_near (mx.mu[2], 0.275, 1e-12);
    const trk_estimate_t *m = &mx.m[0];
    assert_near (m->x[0], 1.875, 1e-12);
    assert_near (m->x[1], 0, 1e-12);
    assert_near (m->x[2], 7.5, 1e-12);
    assert_near (m->P[0], 16.546875, 1e-12);
    assert_near (m->P[2], -14.0625, 1e-12);
    assert_near (m->P[8], -14.0625, 1e-12);
    assert_near (m->P[10], 20.0625, 1e-12);
    assert_near (m->P[5], 1.3125, 1e-12);
    // The combination is the same moment matching with μ itself.
    trk_estimate_t c;
    trk_imm_combine (&s, &c);
    assert_near (c.x[0], 3, 1e-12);
    assert_near (c.x[2], 6, 1e-12);
    assert_near (c.P[0], 0.6 * (1 + 9) + 0.3 * (2 + 49) + 0.1 * (3 + 9), 1e-12);
    // The stopped model holds the position and zeroes the velocity.
    trk_estimate_t e = s.m[0], pr;
    e.x[0] = 100, e.x[2] = 10;
    trk_imm_predict_model (&p, TRK_MODEL_STOPPED, &e, 30, &pr);
    assert_near (pr.x[0], 100, 0);
    assert_near (pr.x[2], 0, 0);
    assert_near (pr.P[0], 1, 1e-12);
    assert_near (pr.P[10], 0.05 * 0.05, 1e-15);
    assert_near (pr.P[2], 0, 0);
    // A missed scan: μ_j ∝ μ_j (1 − pd_j).
    trk_imm_t q = s;
    trk_imm_miss (&q, (double[3]){0.9, 0.9, 0});
    double z = 0.6 * 0.1 + 0.3 * 0.1 + 0.1;
    assert_near (q.mu[2], 0.1 / z, 1e-12);
    assert_near (q.mu[0], 0.06 / z, 1e-12);
}

/* A position-and-radial-velocity update equals the Kalman update worked
 * with the 3×3 innovation covariance, and a hit is evidence against the
 * stopped model. */
static void test_imm_update (void **state)
{
    (void)state;
    trk_estimate_t e;
    memset (&e, 0, sizeof e);
    e.P[0] = e.P[5] = 100;
    e.P[10] = e.P[15] = 4;
    e.x[3] = 10; // north at 10 m/s
    trk_meas_t m = {.z = {10, 0},
                    .R = {100, 0, 0, 100},
                    .has_radial = true,
                    .radial_mps = 12,
                    .los = {0, 1},
                    .radial_var = 4};
    // Axes decouple: east sees P 100 against R 100 (gain 1/2); the north
    // velocity sees P 4 against 4 (gain 1/2), the north position nothing new.
    double ld, d2 = trk_meas_distance (&e, &m, &ld);
    assert_near (d2, 10.0 * 10 / 200 + 2.0 * 2 / 8, 1e-12);
    assert_near (ld, log (200.0 * 200 * 8), 1e-12);
    trk_estimate_t u = e;
    assert_int_equal (trk_meas_update (&u, &m), 0);
    assert_near (u.x[0], 5, 1e-12);
    assert_near (u.x[3], 11, 1e-12);
    assert_near (u.P[0], 50, 1e-12);
    assert_near (u.P[15], 2, 1e-12);
    assert_near (u.P[5], 50, 1e-12);
    // Across the ambiguity: a radial velocity one span away is the same.
    trk_meas_t w = m;
    w.radial_mps += 46.875;
    w.span_mps = 46.875;
    assert_near (trk_meas_distance (&e, &w, NULL), d2, 1e-9);
    // The models: a hit where the stopped model expected none.
    trk_imm_t s;
    trk_imm_init (&s, &e, (double[3]){0.5, 0.2, 0.3});
    s.m[2].x[3] = 0;
    s.m[2].P[15] = 0.0025;
    assert_int_equal (trk_imm_update (&s, &m, (double[3]){0.9, 0.9, 0}, NULL), 0);
    assert_near (s.mu[2], 0, 1e-12);
    assert_near (s.mu[0] + s.mu[1], 1, 1e-12);
    // A non-positive covariance is refused and changes nothing.
    trk_estimate_t bad = e;
    bad.P[0] = -1000;
    trk_meas_t m2 = m;
    m2.has_radial = false;
    assert_true (trk_meas_distance (&bad, &m2, NULL) < 0);
    assert_int_equal (trk_meas_update (&bad, &m2), -EDOM);
    assert_near (bad.x[0], 0, 0);
}

/* ---- the tracker ------------------------------------------------------------------ */

/* A target driving north, away from the radar (clear of the notch), halts
 * for two minutes (the longest halt of the stop-go family), then drives on:
 * the stopped model is the likeliest two missed scans into the halt (and
 * more likely than not at three), the track coasts through the halt, and the
 * target's hits after it continue the same track. */
static void test_halt_switches_to_stopped (void **state)
{
    (void)state;
    trk_params_t p = s_defaults ();
    trk_tracker_t *t = trk_tracker_new (&p);
    assert_non_null (t);
    uint64_t rng = 5;
    double n = 6000;
    uint32_t k = 0, hid = 1, id = 0;
    for (; k < 12; k++, n += 100) {
        trk_hit_t h = s_hit (hid++, 10.0 * k + 5, 2000, n, 0, 10, 20, &rng);
        s_run (t, k, &h, 1);
    }
    assert_int_equal (trk_tracker_count (t), 1);
    const trk_track_t *tr = trk_tracker_at (t, 0);
    id = tr->id;
    assert_int_equal (tr->status, TRK_CONFIRMED);
    assert_true (tr->imm.mu[TRK_MODEL_STOPPED] < 0.1);
    assert_true (tr->pd > 0.8);
    // Halted at n: nothing from the radar.
    n -= 50;
    for (uint32_t j = 1; j <= 12; j++, k++) {
        s_run (t, k, NULL, 0);
        tr = trk_tracker_find (t, id);
        assert_non_null (tr);
        if (j == 2 || j == 3) {
            print_message ("%u scans into the halt: mode probabilities %.3f %.3f %.3f\n", j,
                           tr->imm.mu[0], tr->imm.mu[1], tr->imm.mu[2]);
            // Two scans in, stopped is the likeliest model; three in, more
            // likely than not.
            assert_true (tr->imm.mu[TRK_MODEL_STOPPED] > tr->imm.mu[TRK_MODEL_CV] &&
                         tr->imm.mu[TRK_MODEL_STOPPED] > tr->imm.mu[TRK_MODEL_MANEUVER]);
            if (j == 3)
                assert_true (tr->imm.mu[TRK_MODEL_STOPPED] > 0.5);
        }
        if (j >= 2)
            assert_int_equal (tr->status, TRK_COASTING);
    }
    print_message ("after 120 s halted: existence %.3f, speed %.2f m/s, stopped %.3f\n",
                   tr->existence, hypot (tr->est.x[2], tr->est.x[3]),
                   tr->imm.mu[TRK_MODEL_STOPPED]);
    assert_true (hypot (tr->est.x[2], tr->est.x[3]) < 1);
    assert_true (hypot (tr->est.x[0] - 2000, tr->est.x[1] - n) < 100);
    // Off again: the same track takes it.
    for (uint32_t j = 0; j < 4; j++, k++, n += 100) {
        trk_hit_t h = s_hit (hid++, 10.0 * k + 5, 2000, n + 50, 0, 10, 20, &rng);
        trk_scan_out_t o = s_run (t, k, &h, 1);
        assert_int_equal (o.born, 0);
    }
    tr = trk_tracker_find (t, id);
    assert_non_null (tr);
    assert_int_equal (tr->status, TRK_CONFIRMED);
    assert_true (tr->imm.mu[TRK_MODEL_STOPPED] < 0.1);
    trk_tracker_destroy (&t);
}

/* A target that turns across the radar's line of sight (radial velocity
 * zero: in the notch, unseen for 60 s) coasts through, and its first hit
 * after the coast is confirmed by the second; the paper's tracker deletes
 * it after three misses. */
static void test_notch_crossing_coasts (void **state)
{
    (void)state;
    for (int mode = 0; mode < 2; mode++) {
        trk_params_t p = s_defaults ();
        if (mode == 1)
            p.filter.mode = TRK_FILTER_PAPER;
        trk_tracker_t *t = trk_tracker_new (&p);
        uint64_t rng = 9;
        uint32_t k = 0, hid = 1;
        // North-east at 10 m/s for 100 s, then due east (across the line of
        // sight of a radar due south) for 60 s, unseen, then north-east again.
        double e = 0, n = 8000, ve = 7.071, vn = 7.071;
        for (; k < 10; k++, e += ve * 10, n += vn * 10) {
            trk_hit_t h = s_hit (hid++, 10.0 * k + 5, e, n, ve, vn, 20, &rng);
            s_run (t, k, &h, 1);
        }
        uint32_t id = trk_tracker_at (t, 0)->id;
        for (int j = 0; j < 6; j++, k++, e += 100)
            s_run (t, k, NULL, 0);
        const trk_track_t *tr = trk_tracker_find (t, id);
        if (mode == 1) {
            assert_null (tr); // the paper's: three misses
        } else {
            assert_non_null (tr);
            print_message ("after 60 s in the notch: existence %.3f, expected pd %.3f\n",
                           tr->existence, tr->pd);
            for (int j = 0; j < 4; j++, k++, e += ve * 10, n += vn * 10) {
                trk_hit_t h = s_hit (hid++, 10.0 * k + 5, e, n, ve, vn, 20, &rng);
                s_run (t, k, &h, 1);
                // The first hit after the coast leaves it coasting: its
                // velocity is confirmed by the second.
                if (j < 2)
                    assert_int_equal (trk_tracker_find (t, id)->status,
                                      j == 0 ? TRK_COASTING : TRK_CONFIRMED);
            }
            tr = trk_tracker_find (t, id);
            assert_non_null (tr);
            assert_int_equal (tr->status, TRK_CONFIRMED);
            assert_int_equal (tr->history[tr->history_count - 1].hit_id, hid - 1);
        }
        trk_tracker_destroy (&t);
    }
}

/* The stop-go family's lost intercepts: a vehicle halts, its track coasts
 * believing it stopped, and a false alarm 600 m off (moving, as the
 * manoeuvre model's spread after a long coast allows) comes before the
 * vehicle drives on. The track takes it, but keeps the branch in which it
 * was not its target's; the vehicle's next hits, where it stopped, make
 * that branch the likelier, and the track (same id, the false alarm gone
 * from its history) follows the vehicle: no new track is born for it. */
static void test_false_alarm_after_halt_branches (void **state)
{
    (void)state;
    trk_params_t p = s_defaults ();
    trk_tracker_t *t = trk_tracker_new (&p);
    uint64_t rng = 11;
    double n = 6000;
    uint32_t k = 0, hid = 1;
    for (; k < 12; k++, n += 100) {
        trk_hit_t h = s_hit (hid++, 10.0 * k + 5, 2000, n, 0, 10, 20, &rng);
        s_run (t, k, &h, 1);
    }
    uint32_t id = trk_tracker_at (t, 0)->id;
    n -= 50; // halted here
    size_t branched = 0, swaps = 0;
    for (uint32_t j = 1; j <= 6; j++, k++)
        s_run (t, k, NULL, 0);
    // The false alarm: 600 m south-west of the halt, moving south-west.
    uint32_t fa = hid++;
    trk_hit_t hf = s_hit (fa, 10.0 * k + 5, 2000 - 420, n - 430, -7, -7, 0, &rng);
    trk_scan_out_t o = s_run (t, k++, &hf, 1);
    const trk_track_t *tr = trk_tracker_find (t, id);
    assert_non_null (tr);
    print_message ("false alarm: branched %zu, born %zu; the track at %.0f m from the halt, "
                   "last hit %u\n",
                   o.branched, o.born, hypot (tr->est.x[0] - 2000, tr->est.x[1] - n),
                   tr->history[tr->history_count - 1].hit_id);
    assert_int_equal (tr->history[tr->history_count - 1].hit_id, fa); // it took it
    branched += o.branched;
    assert_int_equal (branched, 1);
    // Off again, north, from the halt.
    for (uint32_t j = 0; j < 5; j++, k++, n += 100) {
        trk_hit_t h = s_hit (hid++, 10.0 * k + 5, 2000, n + 50, 0, 10, 20, &rng);
        o = s_run (t, k, &h, 1);
        swaps += o.alt_swaps;
        assert_int_equal (o.born, 0);
    }
    tr = trk_tracker_find (t, id);
    assert_non_null (tr);
    assert_int_equal (swaps, 1);
    assert_int_equal (tr->status, TRK_CONFIRMED);
    assert_true (hypot (tr->est.x[0] - 2000, tr->est.x[1] - (n - 50)) < 100);
    for (uint32_t i = 0; i < tr->history_count; i++)
        assert_int_not_equal (tr->history[i].hit_id, fa);
    assert_int_equal (tr->history[tr->history_count - 1].hit_id, hid - 1);
    assert_int_equal (trk_tracker_count (t), 1);
    trk_tracker_destroy (&t);
}

/* The default scene's lost intercepts: an APC turns back on its zig-zag
 * route sharper than the manoeuvre model expects; its hits fall outside
 * its track's gate (the radial velocity changed sign) and start a new
 * track, while the old one coasts on, believing its target halted. When
 * the new track is confirmed, it continues the coasting one (whose
 * existence fell with the misses), and that one is deleted in the same
 * scan: the target's identity goes on under one link. A vehicle that
 * crosses the MTI notch is not expected to be seen: its track keeps its
 * existence, and a stranger's new track near it continues nothing. */
static void test_turn_reacquired (void **state)
{
    (void)state;
    trk_params_t p = s_defaults ();
    // A manoeuvre model of gentler turns: the U-turn below is sharper.
    p.imm.sigma_mps2[1] = 0.5;
    trk_tracker_t *t = trk_tracker_new (&p);
    uint64_t rng = 21;
    uint32_t k = 0, hid = 1;
    double e = 3000, n = 6000;
    for (; k < 12; k++, n += 100) {
        trk_hit_t h = s_hit (hid++, 10.0 * k + 5, e, n, 0, 10, 20, &rng);
        s_run (t, k, &h, 1);
    }
    assert_int_equal (trk_tracker_count (t), 1);
    uint32_t old = trk_tracker_at (t, 0)->id;
    n -= 200; // turned back at the last hit: south, 10 m/s
    uint32_t fresh = 0;
    size_t reacquired = 0, deleted_old = 0;
    for (uint32_t j = 0; j < 6; j++, k++, n -= 100) {
        trk_hit_t h = s_hit (hid++, 10.0 * k + 5, e, n, 0, -10, 20, &rng);
        trk_scan_out_t o = s_run (t, k, &h, 1);
        reacquired += o.reacquired;
        for (size_t d = 0; d < o.deleted_count; d++)
            if (o.deleted_tracks[d].id == old) {
                deleted_old++;
                assert_int_equal (o.reacquired, 1);
            }
    }
    assert_int_equal (reacquired, 1);
    assert_int_equal (deleted_old, 1);
    assert_int_equal (trk_tracker_count (t), 1);
    const trk_track_t *tr = trk_tracker_at (t, 0);
    fresh = tr->id;
    print_message ("after the turn: track %u continues %u with probability %.3f\n", fresh,
                   tr->continues, tr->continues_p);
    assert_int_not_equal (fresh, old);
    assert_int_equal (tr->continues, old);
    assert_true (tr->continues_p >= p.continue_probability);
    assert_true (hypot (tr->est.x[0] - e, tr->est.x[1] - (n + 100)) < 100);
    trk_tracker_destroy (&t);

    // In the notch: east at 10 m/s, due north of a radar flying east.
    t = trk_tracker_new (&p);
    e = 0, n = 8000, k = 0;
    for (; k < 10; k++, e += 100) {
        trk_hit_t h = s_hit (hid++, 10.0 * k + 5, e, n, 10, 0, 20, &rng);
        s_run (t, k, &h, 1);
    }
    old = trk_tracker_at (t, 0)->id;
    // Unseen; a stranger 300 m south of it drives east too, seen every scan.
    for (uint32_t j = 0; j < 5; j++, k++, e += 100) {
        trk_hit_t h = s_hit (hid++, 10.0 * k + 5, e - 100, n - 300, 10, 0, 20, &rng);
        trk_scan_out_t o = s_run (t, k, &h, 1);
        assert_int_equal (o.reacquired, 0);
    }
    tr = trk_tracker_find (t, old);
    assert_non_null (tr);
    print_message ("in the notch: existence %.3f; %zu tracks\n", tr->existence,
                   trk_tracker_count (t));
    assert_int_equal (trk_tracker_count (t), 2);
    for (size_t i = 0; i < trk_tracker_count (t); i++)
        assert_int_equal (trk_tracker_at (t, i)->continues, 0);
    trk_tracker_destroy (&t);
}

/* The filter's consistency on straight legs (Monte Carlo, Bar-Shalom's
 * tests): N runs of a target moving at constant velocity with the CV
 * model's own process noise; at each scan after the first few, the average
 * over the runs of the NEES of the combined estimate (4 degrees of freedom)
 * and of the NIS of the likeliest model's filter (3: position and radial
 * velocity) lie inside their two-sided 95% chi-square bands in at least 90%
 * of the scans. */
static void test_nees_nis_straight (void **state)
{
    (void)state;
    trk_params_t p = s_defaults ();
    // The truth's velocity is a random walk (σ_mod over 400 s takes it past
    // any ground vehicle's speed now and then): the speed bound, which is
    // not the model, stays out of the way (100 m/s, beyond seven standard
    // deviations of the walk; it also sizes a one-hit track's gate, which at 1000 m/s
    // would hold so much ground that a second hit in it is no evidence).
    p.max_speed_mps = 100;
    enum { RUNS = 100, SCANS = 40, SKIP = 8 };
    double nees[SCANS] = {0}, nis[SCANS] = {0}, nis_mix[SCANS] = {0};
    uint64_t rng = 21;
    double q = p.filter.sigma_mod_mps2[0];
    for (int r = 0; r < RUNS; r++) {
        trk_tracker_t *t = trk_tracker_new (&p);
        // Truth: from 7 km north-east, away from the radar at about 10 m/s,
        // with white acceleration held over each scan (the CV model's).
        double x[4] = {5000, 5000, 7 + s_gauss (&rng), 7 + s_gauss (&rng)};
        uint32_t id = 0;
        for (uint32_t k = 0; k < SCANS; k++) {
            double tk = 10.0 * k + 5;
            trk_hit_t h = s_hit (1000u * r + k + 1, tk, x[0], x[1], x[2], x[3], 25, &rng);
            trk_estimate_t pred;
            const trk_track_t *tr = id ? trk_tracker_find (t, id) : NULL;
            if (tr && tr->hits >= 2) {
                trk_meas_t m = {.z = {h.z[0], h.z[1]},
                                .R = {625, 0, 0, 625},
                                .has_radial = true,
                                .radial_mps = h.radial_mps,
                                .los = {h.los[0], h.los[1]},
                                .radial_var = p.radial_sigma_mps * p.radial_sigma_mps,
                                .span_mps = p.radial_span_mps};
                // The likeliest model's own innovation (its filter's NIS),
                // and the mixture's.
                trk_imm_t mx;
                trk_imm_mix (&p.imm, &tr->imm, tk - tr->est.t_s, &mx);
                int j = 0;
                for (int i = 1; i < TRK_IMM_MODELS; i++)
                    if (mx.mu[i] > mx.mu[j])
                        j = i;
                trk_imm_predict_model (&p.imm, (trk_model_t)j, &mx.m[j], tk, &pred);
                nis[k] += trk_meas_distance (&pred, &m, NULL) / RUNS;
                trk_tracker_predict (t, tr, tk, &pred);
                nis_mix[k] += trk_meas_distance (&pred, &m, NULL) / RUNS;
            }
            s_run (t, k, &h, 1);
            if (!id && trk_tracker_count (t) == 1)
                id = trk_tracker_at (t, 0)->id;
            tr = trk_tracker_find (t, id);
            assert_non_null (tr);
            // NEES of the updated estimate against the truth.
            double d[4] = {tr->est.x[0] - x[0], tr->est.x[1] - x[1], tr->est.x[2] - x[2],
                           tr->est.x[3] - x[3]};
            double P[16], inv[16];
            memcpy (P, tr->est.P, sizeof P);
            // Gauss-Jordan inverse of the 4×4 covariance.
            for (int i = 0; i < 16; i++)
                inv[i] = (i % 5) == 0;
            for (int c = 0; c < 4; c++) {
                double piv = P[c * 5];
                assert_true (piv > 0);
                for (int j = 0; j < 4; j++) {
                    P[c * 4 + j] /= piv;
                    inv[c * 4 + j] /= piv;
                }
                for (int i = 0; i < 4; i++)
                    if (i != c) {
                        double f = P[i * 4 + c];
                        for (int j = 0; j < 4; j++) {
                            P[i * 4 + j] -= f * P[c * 4 + j];
                            inv[i * 4 + j] -= f * inv[c * 4 + j];
                        }
                    }
            }
            double e2 = 0;
            for (int i = 0; i < 4; i++)
                for (int j = 0; j < 4; j++)
                    e2 += d[i] * inv[i * 4 + j] * d[j];
            nees[k] += e2 / RUNS;
            // The truth moves on to the next hit.
            for (int a = 0; a < 2; a++) {
                double acc = q * s_gauss (&rng);
                x[a] += x[a + 2] * 10 + acc * 50;
                x[a + 2] += acc * 10;
            }
        }
        trk_tracker_destroy (&t);
    }
    double nees_lo = gsl_cdf_chisq_Pinv (0.025, 4.0 * RUNS) / RUNS;
    double nees_hi = gsl_cdf_chisq_Pinv (0.975, 4.0 * RUNS) / RUNS;
    double nis_lo = gsl_cdf_chisq_Pinv (0.025, 3.0 * RUNS) / RUNS;
    double nis_hi = gsl_cdf_chisq_Pinv (0.975, 3.0 * RUNS) / RUNS;
    int in_nees = 0, in_nis = 0, n = 0;
    double mean_nees = 0, mean_nis = 0, mean_mix = 0;
    for (int k = SKIP; k < SCANS; k++, n++) {
        mean_mix += nis_mix[k] / (SCANS - SKIP);
        in_nees += nees[k] >= nees_lo && nees[k] <= nees_hi;
        in_nis += nis[k] >= nis_lo && nis[k] <= nis_hi;
        mean_nees += nees[k] / (SCANS - SKIP);
        mean_nis += nis[k] / (SCANS - SKIP);
    }
    print_message (
        "NEES mean %.2f (band %.2f-%.2f) inside in %d of %d scans; NIS of the likeliest "
        "model mean %.2f (band %.2f-%.2f) inside in %d of %d; NIS of the models' mixture "
        "mean %.2f\n",
        mean_nees, nees_lo, nees_hi, in_nees, n, mean_nis, nis_lo, nis_hi, in_nis, n, mean_mix);
    // The mixture's innovation covariance holds the manoeuvre model's share
    // too, so its NIS lies below the band: conservative, not inconsistent.
    assert_true (mean_mix < nis_hi);
    assert_true (in_nees >= 0.9 * n);
    assert_true (in_nis >= 0.9 * n);
}

/* A vehicle halts long enough for its track to be deleted, then drives on
 * from where it stood: the new track says it continues the old one. A
 * vehicle elsewhere starts a track that continues nothing. With friendly,
 * a BCIS fix marks the old track friendly before the halt. Returns the
 * tracker, the old track's id and the new one's. */
static trk_tracker_t *s_halt_and_go (const trk_params_t *p, bool friendly, uint32_t *ret_old,
                                     uint32_t *ret_fresh)
{
    trk_tracker_t *t = trk_tracker_new (p);
    uint64_t rng = 3;
    uint32_t k = 0, hid = 1;
    double n = 6000;
    for (; k < 8; k++, n += 120) {
        trk_hit_t h = s_hit (hid++, 10.0 * k + 5, 3000, n, 0, 12, 20, &rng);
        s_run (t, k, &h, 1);
    }
    uint32_t old = trk_tracker_at (t, 0)->id;
    if (friendly) {
        trk_bcis_reply_t r = {
            .t_s = 76, .z = {3000, n - 108}, .R = {100, 0, 0, 100}, .responder_id = 5};
        assert_int_equal (trk_tracker_bcis (t, &r), 1);
        assert_true (trk_tracker_find (t, old)->friendly);
    }
    bool deleted = false;
    n -= 60; // stands where it braked to
    for (int j = 0; j < 10; j++, k++) {
        trk_scan_out_t o = s_run (t, k, NULL, 0);
        deleted = deleted || (o.deleted == 1 && o.deleted_tracks[0].id == old);
    }
    assert_true (deleted);
    assert_int_equal (trk_tracker_count (t), 0);
    uint32_t fresh = 0;
    for (int j = 0; j < 4; j++, k++) {
        double d = 30.0 + 120.0 * j; // pulling away
        trk_hit_t h[2] = {s_hit (hid++, 10.0 * k + 5, 3000, n + d, 0, 12, 20, &rng),
                          s_hit (hid++, 10.0 * k + 6, -9000, 4000 + 100.0 * j, 0, 10, 20, &rng)};
        s_run (t, k, h, 2);
    }
    assert_int_equal (trk_tracker_count (t), 2);
    for (size_t i = 0; i < trk_tracker_count (t); i++) {
        const trk_track_t *tr = trk_tracker_at (t, i);
        assert_int_equal (tr->status, TRK_CONFIRMED);
        if (tr->est.x[0] > 0) {
            fresh = tr->id;
            print_message ("track %u continues %u with probability %.3f\n", tr->id, tr->continues,
                           tr->continues_p);
            assert_int_equal (tr->continues, old);
            assert_true (tr->continues_p >= p->continue_probability);
        } else {
            assert_int_equal (tr->continues, 0);
        }
    }
    assert_true (fresh != 0 && fresh != old);
    *ret_old = old;
    *ret_fresh = fresh;
    return t;
}

static void test_continuation (void **state)
{
    (void)state;
    trk_params_t p = s_defaults ();
    // A stopped vehicle the radar cannot see is believed there for
    // stopped_lifetime_s: shortened here so the track dies within the halt.
    p.stopped_lifetime_s = 10;
    uint32_t old, fresh;
    trk_tracker_t *t = s_halt_and_go (&p, false, &old, &fresh);
    // The checkpoint keeps the models, the existence and the link.
    uint8_t *buf = NULL;
    size_t len = 0;
    assert_int_equal (trk_checkpoint_save (t, &buf, &len), 0);
    trk_tracker_t *r = trk_tracker_new (&p);
    char err[256];
    assert_int_equal (trk_checkpoint_restore (r, buf, len, err, sizeof err), 0);
    const trk_track_t *a = trk_tracker_find (t, fresh), *b = trk_tracker_find (r, fresh);
    assert_non_null (b);
    assert_int_equal (b->continues, old);
    assert_true (memcmp (&a->imm, &b->imm, sizeof a->imm) == 0);
    assert_true (a->existence == b->existence && a->pd == b->pd);
    // A damaged mode probability is refused: by the checksum, and sealed
    // again, by the decoder.
    size_t off =
        len - CGS_CKPT_TAIL - (8 + 8 + 1 + 4 + 8) - 8; // the last track's stopped-model probability
    uint8_t *keep = malloc (len);
    memcpy (keep, buf, len);
    double bad = 2;
    memcpy (buf + off, &bad, 8);
    trk_tracker_t *r2 = trk_tracker_new (&p);
    assert_int_equal (trk_checkpoint_restore (r2, buf, len, err, sizeof err), -EBADMSG);
    uint32_t crc = cgs_crc32 (buf + CGS_CKPT_HEAD, len - CGS_CKPT_HEAD - CGS_CKPT_TAIL);
    for (int i = 0; i < 4; i++)
        buf[len - 4 + i] = (uint8_t)(crc >> (8 * i));
    assert_int_equal (trk_checkpoint_restore (r2, buf, len, err, sizeof err), -EINVAL);
    assert_non_null (strstr (err, "is damaged"));
    assert_int_equal (trk_tracker_count (r2), 0);
    memcpy (buf, keep, len);
    free (keep);
    assert_int_equal (trk_checkpoint_restore (r2, buf, len, err, sizeof err), 0);
    free (buf);
    trk_tracker_destroy (&r);
    trk_tracker_destroy (&r2);
    trk_tracker_destroy (&t);
}

/* Two vehicles crossing at 60° (each 10 m/s, noise 25 m): both keep their
 * tracks through the crossing in every one of 40 trials. */
static void test_crossing_keeps_ids (void **state)
{
    (void)state;
    trk_params_t p = s_defaults ();
    uint64_t rng = 17;
    int swaps = 0, trials = 40;
    for (int tr = 0; tr < trials; tr++) {
        trk_tracker_t *t = trk_tracker_new (&p);
        double a1 = 30 * S_PI / 180, a2 = 90 * S_PI / 180; // headings from north
        double c[2] = {4000, 7000};
        uint32_t id1 = 0, id2 = 0;
        for (uint32_t k = 0; k < 24; k++) {
            double dt = 10.0 * k + 5 - 120; // crossing at t = 120 s
            double e1 = c[0] + 10 * sin (a1) * dt, n1 = c[1] + 10 * cos (a1) * dt;
            double e2 = c[0] + 10 * sin (a2) * dt, n2 = c[1] + 10 * cos (a2) * dt;
            trk_hit_t h[2] = {
                s_hit (2 * k + 1, 10.0 * k + 5, e1, n1, 10 * sin (a1), 10 * cos (a1), 25, &rng),
                s_hit (2 * k + 2, 10.0 * k + 5.2, e2, n2, 10 * sin (a2), 10 * cos (a2), 25, &rng)};
            s_run (t, k, h, 2);
            for (size_t i = 0; i < trk_tracker_count (t); i++) {
                const trk_track_t *x = trk_tracker_at (t, i);
                uint32_t last = x->history[x->history_count - 1].hit_id;
                if (k == 6 && last == 2 * k + 1)
                    id1 = x->id;
                if (k == 6 && last == 2 * k + 2)
                    id2 = x->id;
                if (k == 23 &&
                    ((last == 2 * k + 1 && x->id != id1) || (last == 2 * k + 2 && x->id != id2)))
                    swaps++;
            }
        }
        assert_true (id1 && id2);
        trk_tracker_destroy (&t);
    }
    print_message ("%d of %d crossings changed a track\n", swaps, trials);
    assert_int_equal (swaps, 0);
}

/* JIPDA on two tracks and one hit between them: two vehicles side by side
 * (80 m apart, 10 m/s north), both seen for eight scans, then unseen for
 * four (their existence falls), then one hit midway. With the best
 * hypothesis alone (hypotheses = 1) one track takes the hit and is certain
 * again, the other counts a miss; weighing the k best, each track had the
 * hit with probability about one half, and both end between those two
 * values, close to each other (the noise makes them not quite symmetric). */
static void s_shared_hit (int hypotheses, double ex[2])
{
    trk_params_t p = s_defaults ();
    p.hypotheses = hypotheses;
    trk_tracker_t *t = trk_tracker_new (&p);
    uint64_t rng = 5;
    uint32_t k = 0;
    for (; k < 12; k++) {
        double tk = 10.0 * k + 5, n = 6000 + 10 * tk;
        trk_hit_t h[2] = {s_hit (2 * k + 1, tk, 3000, n, 0, 10, 10, &rng),
                          s_hit (2 * k + 2, tk + 0.1, 3080, n, 0, 10, 10, &rng)};
        s_run (t, k, h, k < 8 ? 2 : 0);
    }
    assert_int_equal (trk_tracker_count (t), 2);
    double tk = 10.0 * k + 5;
    trk_hit_t mid = s_hit (99, tk, 3040, 6000 + 10 * tk, 0, 10, 0, &rng);
    s_run (t, k, &mid, 1);
    assert_int_equal (trk_tracker_count (t), 2);
    for (int i = 0; i < 2; i++)
        ex[i] = trk_tracker_at (t, (size_t)i)->existence;
    if (ex[0] > ex[1]) {
        double x = ex[0];
        ex[0] = ex[1];
        ex[1] = x;
    }
    trk_tracker_destroy (&t);
}

static void test_shared_hit_existence (void **state)
{
    (void)state;
    double hard[2], soft[2];
    s_shared_hit (1, hard);
    s_shared_hit (16, soft);
    print_message ("# existence after a shared hit: best hypothesis %.3f and %.3f, "
                   "16 best %.3f and %.3f\n",
                   hard[0], hard[1], soft[0], soft[1]);
    assert_true (hard[1] >= 0.99);
    assert_true (hard[0] < 0.7);
    for (int i = 0; i < 2; i++)
        assert_true (soft[i] > hard[0] + 0.1 && soft[i] < hard[1] - 0.1);
    assert_true (soft[1] - soft[0] < 0.1);
}

/* A continuing track takes the friendly identity of the one it continues
 * only when the link is at least identity_min_probability likely: an
 * identity is not handed on a coin toss. */
static void test_continuation_identity (void **state)
{
    (void)state;
    trk_params_t p = s_defaults ();
    p.stopped_lifetime_s = 10;
    p.identity_timeout_s = 1000; // the identity would otherwise age out in the halt
    uint32_t old, fresh;
    trk_tracker_t *t = s_halt_and_go (&p, true, &old, &fresh);
    double pc = trk_tracker_find (t, fresh)->continues_p;
    trk_tracker_destroy (&t);
    const double below = pc - 0.01, above = pc + 0.01;
    p.identity_min_probability = below; // the link is likely enough
    t = s_halt_and_go (&p, true, &old, &fresh);
    assert_true (trk_tracker_find (t, fresh)->friendly);
    assert_int_equal (trk_tracker_find (t, fresh)->friendly_id, 5);
    trk_tracker_destroy (&t);
    if (above <= 1) {
        p.identity_min_probability = above; // not likely enough: unknown
        t = s_halt_and_go (&p, true, &old, &fresh);
        assert_true (trk_tracker_find (t, fresh)->continues == old);
        assert_false (trk_tracker_find (t, fresh)->friendly);
        trk_tracker_destroy (&t);
    }
}

int main (void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test (test_pd_notch_closed_form),
        cmocka_unit_test (test_pd_terrain_masking),
        cmocka_unit_test (test_pd_against_mtid_chain),
        cmocka_unit_test (test_imm_mixing_worked_example),
        cmocka_unit_test (test_imm_update),
        cmocka_unit_test (test_halt_switches_to_stopped),
        cmocka_unit_test (test_notch_crossing_coasts),
        cmocka_unit_test (test_false_alarm_after_halt_branches),
        cmocka_unit_test (test_turn_reacquired),
        cmocka_unit_test (test_nees_nis_straight),
        cmocka_unit_test (test_continuation),
        cmocka_unit_test (test_continuation_identity),
        cmocka_unit_test (test_crossing_keeps_ids),
        cmocka_unit_test (test_shared_hit_existence),
    };
    return cmocka_run_group_tests (tests, NULL, NULL);
}
