/* trk_pd — the detection probability the tracker expects (see trk_pd.h). */
#include "trk_pd.h"

#include <math.h>

#define S_PI 3.14159265358979323846

double trk_pd_mdv (const trk_pd_params_t *p, double alpha_rad)
{
    double s = sin (alpha_rad), a = p->mdv_along_mps, c = p->mdv_across_mps;
    return sqrt (a * a + (c * c - a * a) * s * s);
}

double trk_pd_at_range (const trk_pd_params_t *p, double r_m)
{
    if (!(p->half_range_m > 0))
        return p->pd;
    return p->pd / (1 + pow (fmax (r_m, 0.0) / p->half_range_m, p->range_exponent));
}

bool trk_pd_covered (const trk_pd_radar_t *r, double e, double n)
{
    if (r->full_revolution || !(r->sector_width_deg < 360))
        return true;
    double az = atan2 (e - r->position[0], n - r->position[1]) * 180 / S_PI;
    double off = fmod (az - r->sector_center_deg, 360.0);
    if (off > 180)
        off -= 360;
    if (off < -180)
        off += 360;
    return fabs (off) <= r->sector_width_deg / 2;
}

double trk_pd_of (const trk_pd_params_t *p, const trk_pd_radar_t *r, const double x[3],
                  const double v[2], double sigma_vr)
{
    double de = x[0] - r->position[0], dn = x[1] - r->position[1], du = x[2] - r->position[2];
    double ground = hypot (de, dn), slant = sqrt (ground * ground + du * du);
    if (!(ground >= p->min_range_m && ground <= p->max_range_m) || !(slant > 0) ||
        !trk_pd_covered (r, x[0], x[1]))
        return 0;
    if (r->terrain) {
        cgs_enu_t a = {r->position[0], r->position[1], r->position[2]};
        cgs_enu_t b = {x[0], x[1], cgs_terrain_height_clamped (r->terrain, x[0], x[1]) + 2};
        if (!cgs_terrain_los (r->terrain, a, b))
            return 0; // behind the hill
    }
    // Radial velocity over the ground: the target's velocity along the unit
    // line of sight (its ground part, ground / slant long).
    double ue = de / slant, un = dn / slant;
    double vr = ue * v[0] + un * v[1];
    if (p->span_mps > 0)
        vr -= p->span_mps * round (vr / p->span_mps); // distance to the nearest blind speed
    double vp = hypot (r->velocity[0], r->velocity[1]), alpha = S_PI / 2;
    if (vp > 1e-6 && ground > 0) {
        double c = (r->velocity[0] * de + r->velocity[1] * dn) / (vp * ground);
        alpha = acos (fmax (-1.0, fmin (1.0, c)));
    }
    double w = sqrt (p->width_mps * p->width_mps + sigma_vr * sigma_vr);
    double z = (fabs (vr) - trk_pd_mdv (p, alpha)) / w;
    return trk_pd_at_range (p, slant) * 0.5 * erfc (-z / sqrt (2.0));
}
