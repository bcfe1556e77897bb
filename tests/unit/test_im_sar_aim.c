/* test_im_sar_aim — where a SAR chip looks for a designated mover, and how
 * wide it is made (im_sar_aim), against the geometry worked by hand:
 *   - broadside over flat ground, a mover's return moves R/V metres along
 *     cross range per m/s of radial velocity (R·cos ψ/V per m/s of ground
 *     velocity toward the radar); the return's standard deviation is
 *     √(σ_x² + (R·cos ψ/V·σ_v)²) from a track's covariance, and the
 *     widening the smallest power of √2 that holds 2.5 of them (and the
 *     vehicle), capped;
 *   - the chip is centred where the mover's return falls;
 *   - without a covariance the chip is not widened;
 *   - the moving-target channel: a chip that holds the return measures the
 *     radial velocity, and the next chip aimed by it holds the return within
 *     its stated standard deviation as often as a normal law says (over many
 *     noise draws, with a track whose radial velocity is 2 m/s wrong);
 *     a chip that does not hold it, or a hidden target, measures nothing. */
#include "im_sar_aim.h"
#include "test_util.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#define S_DEG (M_PI / 180)
#define S_R   10000.0            // slant range
#define S_V   40.0               // platform speed
#define S_PSI 30.0               // grazing angle
#define S_COS 0.8660254037844387 // its cosine: a ground velocity's share of the radial one

static im_sar_t *s_sar (void)
{
    im_sar_params_t p;
    im_sar_params_defaults (&p);
    p.size_px = 128, p.scene_m = 128, p.speckle = false;
    char err[256] = "";
    im_sar_t *sar = im_sar_new (&p, 1, err, sizeof err);
    if (!sar)
        fail_msg ("im_sar_new: %s", err);
    return sar;
}

/* The radar south of the origin at S_R and S_PSI, flying east at S_V
 * (broadside). */
static const cgs_enu_t s_radar = {0, -S_R * 0.8660254037844387, S_R * 0.5};
static const cgs_enu_t s_vel = {S_V, 0, 0};

static void s_track (im_sar_track_t *t, cgs_enu_t pos, cgs_enu_t vel, double sx, double sv)
{
    *t = (im_sar_track_t){.pos = pos, .vel = vel, .t_s = 0, .has_cov = true};
    t->cov[0] = t->cov[5] = sx * sx;
    t->cov[10] = t->cov[15] = sv * sv;
}

/* Where the return of a target at p moving at v falls for a chip at center. */
static cgs_enu_t s_seen (const im_sar_t *sar, cgs_enu_t center, double widen, cgs_enu_t p,
                         cgs_enu_t v, im_sar_chip_t *ret)
{
    im_sar_geom_t g = {.radar = s_radar, .radar_vel = s_vel, .center = center, .widen = widen};
    assert_int_equal (im_sar_plan (sar, &g, ret), 0);
    cgs_enu_t seen;
    assert_true (im_sar_apparent (ret, p, v, NULL, &seen));
    return seen;
}

static void test_widen_closed_form (void **state)
{
    (void)state;
    im_sar_t *sar = s_sar ();
    const double scene = im_sar_params (sar)->scene_m;
    // A mover at the origin, 3 m/s north (away from the radar): radial
    // velocity 3·cos ψ, its return R·v_r/V = 650 m along cross range.
    cgs_enu_t p = {0, 0, 0}, v = {0, 3, 0};
    double sx[] = {5, 20, 40, 10}, sv[] = {0.05, 0.2, 1.0, 3.0};
    for (int k = 0; k < 4; k++) {
        im_sar_track_t trk;
        s_track (&trk, p, v, sx[k], sv[k]);
        im_sar_aim_t a;
        assert_int_equal (im_sar_aim (sar, s_radar, s_vel, NULL, &trk, NULL, 0, 64, &a), 0);
        assert_false (a.by_gmti);
        // Centred on the return.
        im_sar_chip_t c;
        cgs_enu_t seen = s_seen (sar, a.center, 1, p, v, &c);
        assert_true (hypot (seen.e_m - a.center.e_m, seen.n_m - a.center.n_m) < c.pixel_m);
        assert_near (fabs (a.center.e_m), S_R * 3 * S_COS / S_V, 0.01 * S_R * 3 / S_V);
        // R·cos ψ/V metres per m/s of ground velocity along the line of
        // sight; σ from the covariance.
        double want = sqrt (sx[k] * sx[k] + pow (S_R * S_COS / S_V * sv[k], 2));
        assert_rel (a.sigma_m, want, 0.01);
        double need = 2 * (IM_SAR_AIM_SIGMAS * want + IM_SAR_AIM_MARGIN_M) / scene;
        if (need <= 1)
            assert_near (a.widen, 1, 0);
        else {
            assert_true (a.widen >= need * 0.99 && a.widen < need * M_SQRT2 * 1.01);
            double e = log (a.widen) / log (M_SQRT2);
            assert_near (e, round (e), 1e-9);
        }
        printf ("# σ_x %g m, σ_vr %g m/s: return σ %.1f m (hand %.1f), widened %g\n", sx[k], sv[k],
                a.sigma_m, want, a.widen);
        // Capped.
        assert_int_equal (im_sar_aim (sar, s_radar, s_vel, NULL, &trk, NULL, 0, 2, &a), 0);
        assert_true (a.widen <= 2);
    }
    // No covariance: not widened.
    im_sar_track_t trk = {.pos = p, .vel = v};
    im_sar_aim_t a;
    assert_int_equal (im_sar_aim (sar, s_radar, s_vel, NULL, &trk, NULL, 0, 64, &a), 0);
    assert_near (a.widen, 1, 0);
    im_sar_destroy (&sar);
}

/* A mover at constant velocity; the track's radial velocity 2 m/s wrong.
 * The first chip (widened by the track) holds the return and measures it;
 * the next, 2 s later, aimed by the measurement, holds the return within
 * its stated σ as a normal law says. */
static void test_gmti (void **state)
{
    (void)state;
    im_sar_t *sar = s_sar ();
    cgs_enu_t p0 = {30, -20, 0}, v = {4, 5, 0};
    im_sar_track_t trk;
    s_track (&trk, p0, (cgs_enu_t){4, 3, 0}, 20, 2.0);
    uint64_t rng = 7;
    int n = 400, within1 = 0, within25 = 0, measured = 0, narrower = 0;
    for (int i = 0; i < n; i++) {
        im_sar_aim_t a;
        assert_int_equal (im_sar_aim (sar, s_radar, s_vel, NULL, &trk, NULL, 0, 64, &a), 0);
        im_sar_chip_t c;
        s_seen (sar, a.center, a.widen, p0, v, &c);
        im_sar_gmti_t gm;
        if (!im_sar_gmti_measure (&c, NULL, p0, v, 0, 0.25, &rng, &gm))
            continue;
        measured++;
        assert_near (gm.los.e_m * c.los.e_m + gm.los.n_m * c.los.n_m, hypot (c.los.e_m, c.los.n_m),
                     1e-9);
        double t = 2.0;
        cgs_enu_t p = {p0.e_m + v.e_m * t, p0.n_m + v.n_m * t, 0};
        im_sar_track_t trk2 = trk;
        im_sar_aim_t b;
        assert_int_equal (im_sar_aim (sar, s_radar, s_vel, NULL, &trk2, &gm, t, 64, &b), 0);
        assert_true (b.by_gmti);
        if (b.widen < a.widen)
            narrower++;
        im_sar_chip_t c2;
        cgs_enu_t seen = s_seen (sar, b.center, b.widen, p, v, &c2);
        double off = hypot (seen.e_m - b.center.e_m, seen.n_m - b.center.n_m);
        within1 += off <= b.sigma_m;
        within25 += off <= IM_SAR_AIM_SIGMAS * b.sigma_m;
    }
    printf ("# moving-target channel: %d of %d chips measured; the next chip's return within "
            "1σ %d, 2.5σ %d; narrower %d\n",
            measured, n, within1, within25, narrower);
    assert_int_equal (measured, n); // the widened first chip holds it
    assert_int_equal (narrower, n);
    // The stated σ is no smaller than the errors (drift allowed for: at
    // least 68% within 1σ, 98.8% within 2.5σ).
    assert_true (within1 >= 0.68 * n);
    assert_true (within25 >= 0.98 * n);
    // A chip that does not hold the return measures nothing.
    im_sar_chip_t far;
    s_seen (sar, (cgs_enu_t){3000, 0, 0}, 1, p0, v, &far);
    im_sar_gmti_t gm;
    assert_false (im_sar_gmti_measure (&far, NULL, p0, v, 0, 0.25, &rng, &gm));
    // Nor one whose target a ridge hides.
    int nn = 64;
    float z[64 * 64];
    for (int i = 0; i < nn * nn; i++) {
        int row = i / nn; // north from -3200 m, 100 m cells
        double north = -3200 + row * 100.0;
        z[i] = north > -1500 && north < -1000 ? 3000.0f : 0.0f;
    }
    cgs_terrain_t *ridge = cgs_terrain_new_grid (nn, nn, -3200, -3200, 100, z);
    assert_non_null (ridge);
    im_sar_aim_t a;
    assert_int_equal (im_sar_aim (sar, s_radar, s_vel, NULL, &trk, NULL, 0, 64, &a), 0);
    im_sar_chip_t c;
    s_seen (sar, a.center, a.widen, p0, v, &c);
    assert_true (im_sar_gmti_measure (&c, NULL, p0, v, 0, 0.25, &rng, &gm));
    assert_false (im_sar_gmti_measure (&c, ridge, p0, v, 0, 0.25, &rng, &gm));
    cgs_terrain_destroy (&ridge);
    // Too old a measurement is not used.
    assert_true (im_sar_gmti_measure (&c, NULL, p0, v, 0, 0.25, &rng, &gm));
    im_sar_aim_t b;
    assert_int_equal (
        im_sar_aim (sar, s_radar, s_vel, NULL, &trk, &gm, IM_SAR_AIM_MAX_AGE + 1, 64, &b), 0);
    assert_false (b.by_gmti);
    im_sar_destroy (&sar);
}

int main (void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test (test_widen_closed_form),
        cmocka_unit_test (test_gmti),
    };
    return cmocka_run_group_tests (tests, NULL, NULL);
}
