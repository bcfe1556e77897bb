/* cgs_footprint — the sensor's footprint on the ground (see cgs_footprint.h). */
#include "cgs_footprint.h"

#include <math.h>

static cgs_v2_t s_sub (cgs_v2_t a, cgs_v2_t b)
{
    return (cgs_v2_t){a.e - b.e, a.n - b.n};
}

static double s_norm (cgs_v2_t a)
{
    return hypot (a.e, a.n);
}

void cgs_footprint_scale (const cgs_footprint_t *f, double k, cgs_footprint_t *ret)
{
    cgs_footprint_t out = *f;
    for (int i = 0; i < 4; i++) {
        cgs_v2_t d = s_sub (f->corner[i], f->center);
        out.corner[i] = (cgs_v2_t){f->center.e + k * d.e, f->center.n + k * d.n};
    }
    *ret = out;
}

bool cgs_footprint_contains (const cgs_footprint_t *f, cgs_v2_t p)
{
    // Clockwise seen from above: the inside is on the right of every edge.
    double scale = 0;
    for (int i = 0; i < 4; i++)
        scale = fmax (scale, s_norm (s_sub (f->corner[i], f->center)));
    double tol = 1e-9 * (1.0 + scale);
    for (int i = 0; i < 4; i++) {
        cgs_v2_t a = f->corner[i], b = f->corner[(i + 1) % 4];
        cgs_v2_t ab = s_sub (b, a), ap = s_sub (p, a);
        double len = s_norm (ab);
        if (ab.e * ap.n - ab.n * ap.e > tol * (len > 0 ? len : 1.0))
            return false;
    }
    return true;
}

/* Distance from p to the segment ab. */
static double s_seg_dist (cgs_v2_t p, cgs_v2_t a, cgs_v2_t b)
{
    cgs_v2_t ab = s_sub (b, a), ap = s_sub (p, a);
    double l2 = ab.e * ab.e + ab.n * ab.n;
    double t = l2 > 0 ? (ap.e * ab.e + ap.n * ab.n) / l2 : 0;
    t = t < 0 ? 0 : (t > 1 ? 1 : t);
    return s_norm ((cgs_v2_t){ap.e - t * ab.e, ap.n - t * ab.n});
}

double cgs_footprint_distance (const cgs_footprint_t *f, cgs_v2_t p)
{
    return fmax (0.0, cgs_footprint_signed_distance (f, p));
}

double cgs_footprint_signed_distance (const cgs_footprint_t *f, cgs_v2_t p)
{
    double d = INFINITY;
    for (int i = 0; i < 4; i++)
        d = fmin (d, s_seg_dist (p, f->corner[i], f->corner[(i + 1) % 4]));
    return cgs_footprint_contains (f, p) ? -d : d;
}

cgs_enu_t cgs_footprint_corner_enu (const cgs_footprint_t *f, int i)
{
    return (cgs_enu_t){f->corner[i].e, f->corner[i].n, f->corner_up_m[i]};
}

cgs_enu_t cgs_footprint_center_enu (const cgs_footprint_t *f)
{
    return (cgs_enu_t){f->center.e, f->center.n, f->center_up_m};
}
