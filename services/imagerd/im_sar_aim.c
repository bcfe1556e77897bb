/* im_sar_aim — see im_sar_aim.h. */
#include "im_sar_aim.h"

#include <errno.h>
#include <math.h>
#include <string.h>

#include "cgs_util.h"

static double s_ground_up (const cgs_terrain_t *t, double e, double n)
{
    return t ? cgs_terrain_height_clamped (t, e, n) : 0.0;
}

/* uᵀ A u for the 2 × 2 block of the 4 × 4 row-major m at row and column k0. */
static double s_quad (const double *m, int k0, double ue, double un)
{
    return fmax (m[k0 * 4 + k0] * ue * ue + (m[k0 * 4 + k0 + 1] + m[(k0 + 1) * 4 + k0]) * ue * un +
                     m[(k0 + 1) * 4 + k0 + 1] * un * un,
                 0);
}

/* The horizontal unit part of v, false when it has none. */
static bool s_unit_h (cgs_enu_t v, double *ret_e, double *ret_n)
{
    double h = hypot (v.e_m, v.n_m);
    if (!(h > 0))
        return false;
    *ret_e = v.e_m / h, *ret_n = v.n_m / h;
    return true;
}

/* The chip centre that puts the return of a target at p moving at vel at
 * the centre: a fixed point over the chip's geometry, which depends on where
 * it looks. */
static int s_center (const im_sar_t *sar, cgs_enu_t radar, cgs_enu_t radar_vel,
                     const cgs_terrain_t *terrain, cgs_enu_t p, cgs_enu_t vel, cgs_enu_t *ret,
                     im_sar_chip_t *ret_chip)
{
    cgs_enu_t center = p;
    int rc = -EDOM;
    for (int it = 0; it < 8; it++) {
        im_sar_geom_t g = {.radar = radar, .radar_vel = radar_vel, .center = center};
        im_sar_chip_t c;
        cgs_enu_t seen;
        if ((rc = im_sar_plan (sar, &g, &c)) < 0)
            break;
        *ret_chip = c;
        if (!im_sar_apparent (&c, p, vel, terrain, &seen)) {
            rc = -EDOM;
            break;
        }
        double moved = hypot (seen.e_m - center.e_m, seen.n_m - center.n_m);
        center = seen;
        if (moved < c.pixel_m)
            break;
    }
    *ret = center;
    return rc;
}

int im_sar_aim (const im_sar_t *sar, cgs_enu_t radar, cgs_enu_t radar_vel,
                const cgs_terrain_t *terrain, const im_sar_track_t *trk, const im_sar_gmti_t *gm,
                double t, double max_widen, im_sar_aim_t *ret)
{
    const im_sar_params_t *sp = im_sar_params (sar);
    im_sar_aim_t a = {.widen = 1};
    double dt = t - trk->t_s;
    a.vel = (cgs_enu_t){trk->vel.e_m, trk->vel.n_m, 0};
    a.target = (cgs_enu_t){trk->pos.e_m + a.vel.e_m * dt, trk->pos.n_m + a.vel.n_m * dt, 0};
    double age = gm && gm->have ? t - gm->t_s : INFINITY;
    double ge = 0, gn = 0;
    a.by_gmti = fabs (age) <= IM_SAR_AIM_MAX_AGE && s_unit_h (gm->los, &ge, &gn);
    if (a.by_gmti) {
        // The track's velocity with its part along the measured line of sight
        // replaced by the measurement, from the measured place.
        double along = a.vel.e_m * ge + a.vel.n_m * gn;
        a.vel.e_m += ge * (gm->vr_mps - along), a.vel.n_m += gn * (gm->vr_mps - along);
        a.target = (cgs_enu_t){gm->pos.e_m + a.vel.e_m * age, gm->pos.n_m + a.vel.n_m * age, 0};
    }
    a.target.u_m = s_ground_up (terrain, a.target.e_m, a.target.n_m);
    a.center = a.target;
    im_sar_chip_t c;
    int rc = s_center (sar, radar, radar_vel, terrain, a.target, a.vel, &a.center, &c);
    if (rc < 0) {
        *ret = a;
        return rc;
    }
    // The covariance carried to t along the velocity (F P Fᵀ, F = [I dt·I; 0 I]).
    double P[16] = {0};
    if (trk->has_cov) {
        memcpy (P, trk->cov, sizeof P);
        for (int i = 0; i < 2; i++)
            for (int j = 0; j < 2; j++)
                P[i * 4 + j] +=
                    dt * (P[i * 4 + j + 2] + P[(i + 2) * 4 + j]) + dt * dt * P[(i + 2) * 4 + j + 2];
    }
    double ce, cn, re, rn, le, ln;
    if (!s_unit_h (c.cross_dir, &ce, &cn) || !s_unit_h (c.range_dir, &re, &rn) ||
        !s_unit_h (c.los, &le, &ln)) {
        *ret = a;
        return 0;
    }
    // Metres the return moves per m/s of radial velocity, from the geometry.
    cgs_enu_t pa, pb, vp = a.vel, vm = a.vel;
    vp.e_m += le, vp.n_m += ln, vm.e_m -= le, vm.n_m -= ln;
    if (!im_sar_apparent (&c, a.target, vp, terrain, &pa) ||
        !im_sar_apparent (&c, a.target, vm, terrain, &pb)) {
        *ret = a;
        return 0;
    }
    double per_mps = hypot (pa.e_m - pb.e_m, pa.n_m - pb.n_m) / 2;
    double var_cross, var_range;
    if (a.by_gmti) {
        // The measured place and radial velocity (their errors cancel in the
        // return's place), drifting; the track's velocity across the line of
        // sight carries the place on.
        double s_vr = hypot (gm->sigma_mps, IM_SAR_AIM_VR_DRIFT * fabs (age));
        // The track's velocity across the measured line of sight is left
        // as it was: its error moves the place on, and leaks into the radial
        // velocity as far as the line of sight has turned since.
        double var_vx = trk->has_cov ? s_quad (trk->cov, 2, -gn, ge) : 0;
        double leak = fabs (-gn * le + ge * ln); // sin of the turn
        s_vr = sqrt (s_vr * s_vr + leak * leak * var_vx);
        var_cross = per_mps * per_mps * s_vr * s_vr + age * age * var_vx;
        var_range = age * age * s_vr * s_vr + c.range_res_m * c.range_res_m;
    } else if (trk->has_cov) {
        var_cross = s_quad (P, 0, ce, cn) + per_mps * per_mps * s_quad (P, 2, le, ln);
        var_range = s_quad (P, 0, re, rn);
    } else {
        *ret = a;
        return 0;
    }
    a.sigma_m = sqrt (fmax (var_cross, var_range));
    double w = 2 * (IM_SAR_AIM_SIGMAS * a.sigma_m + IM_SAR_AIM_MARGIN_M) / sp->scene_m;
    if (w > 1) {
        w = pow (M_SQRT2, ceil (log (w) / log (M_SQRT2) - 1e-9));
        a.widen = fmax (1, fmin (w, fmin (max_widen, IM_SAR_WIDEN_MAX)));
    }
    *ret = a;
    return 0;
}

static double s_gauss (uint64_t *rng)
{
    double u1 = cgs_uniform01 (rng), u2 = cgs_uniform01 (rng);
    return sqrt (-2 * log (fmax (u1, 1e-300))) * cos (2 * M_PI * u2);
}

bool im_sar_gmti_measure (const im_sar_chip_t *c, const cgs_terrain_t *terrain, cgs_enu_t p,
                          cgs_enu_t vel, double t_s, double sigma_mps, uint64_t *rng,
                          im_sar_gmti_t *ret)
{
    double x, y, le, ln;
    if (!im_sar_chip_to_px (c, p, vel, &x, &y) || !s_unit_h (c->los, &le, &ln))
        return false;
    cgs_enu_t top = {p.e_m, p.n_m, p.u_m + 2.0};
    if (terrain && !cgs_terrain_los (terrain, c->radar, top))
        return false;
    double vr = vel.e_m * le + vel.n_m * ln + sigma_mps * s_gauss (rng);
    // The place it gives: where a target moving at the measured radial
    // velocity would have to be for its return to fall where this one does.
    cgs_enu_t vm = vel, seen, seen_m;
    double along = vel.e_m * le + vel.n_m * ln;
    vm.e_m += le * (vr - along), vm.n_m += ln * (vr - along);
    if (!im_sar_apparent (c, p, vel, terrain, &seen) ||
        !im_sar_apparent (c, p, vm, terrain, &seen_m))
        return false;
    cgs_enu_t at = {p.e_m + seen.e_m - seen_m.e_m, p.n_m + seen.n_m - seen_m.n_m, 0};
    at.u_m = s_ground_up (terrain, at.e_m, at.n_m);
    *ret = (im_sar_gmti_t){.have = true,
                           .t_s = t_s,
                           .pos = at,
                           .los = {le, ln, 0},
                           .vr_mps = vr,
                           .sigma_mps = sigma_mps};
    return true;
}
