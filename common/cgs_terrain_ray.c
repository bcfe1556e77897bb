/* cgs_terrain_ray — lines and rays over the terrain (see cgs_terrain.h): a
 * line of sight exact for the bilinear surface, its clearance, where a ray
 * first meets the ground, and the ground point at a slant range. */
#include "cgs_terrain.h"
#include "cgs_terrain_impl.h"

#include <assert.h>
#include <math.h>
#include <stdbool.h>

/* --- line of sight ----------------------------------------------------------
 * The segment is p(t) = a + t (b - a), t in [0, 1]. In grid coordinates
 * (node units) it is clipped to the grid, then walked cell by cell
 * (Amanatides-Woo: the next crossing of a column line and of a row line).
 * Inside one cell the bilinear surface along a straight line is a quadratic in
 * t and the segment's height is linear, so the smallest clearance over the
 * piece is at an end of the piece or at the quadratic's vertex: exact, not
 * sampled. Endpoints are not treated specially: a point exactly on the ground
 * touches it and so blocks; callers raise their endpoints (a vehicle's sensor
 * or antenna, e.g. 2 m above the ground). */

typedef struct {
    double xa, ya, za; // start, grid coordinates and height (metres)
    double dx, dy, dz; // b - a, in the same units
} s_seg_t;

/* Smallest (segment - surface) over t in [ta, tb], all within one cell. */
static double s_piece_min (const cgs_terrain_t *self, const s_seg_t *s, double ta, double tb)
{
    double tm = 0.5 * (ta + tb);
    double xm = s->xa + s->dx * tm, ym = s->ya + s->dy * tm, zm = s->za + s->dz * tm;
    int c = (int)floor (xm), r = (int)floor (ym);
    c = c < 0 ? 0 : c > self->cols - 2 ? self->cols - 2 : c;
    r = r < 0 ? 0 : r > self->rows - 2 ? self->rows - 2 : r;
    double h00 = cgs_terrain__node (self, c, r), h10 = cgs_terrain__node (self, c + 1, r);
    double h01 = cgs_terrain__node (self, c, r + 1), h11 = cgs_terrain__node (self, c + 1, r + 1);
    double A = h10 - h00, B = h01 - h00, C = h00 - h10 - h01 + h11;
    double um = xm - c, vm = ym - r;
    // Surface along the piece, in s = t - tm: H0 + H1 s + H2 s^2.
    double H0 = h00 + A * um + B * vm + C * um * vm;
    double H1 = A * s->dx + B * s->dy + C * (um * s->dy + vm * s->dx);
    double H2 = C * s->dx * s->dy;
    // Clearance f(s) = q0 + q1 s + q2 s^2.
    double q0 = zm - H0, q1 = s->dz - H1, q2 = -H2;
    double sa = ta - tm, sb = tb - tm;
    double fa = q0 + (q1 + q2 * sa) * sa, fb = q0 + (q1 + q2 * sb) * sb;
    double f = fmin (fa, fb);
    if (q2 > 0) {
        double sv = -q1 / (2 * q2);
        if (sv > sa && sv < sb)
            f = fmin (f, q0 + (q1 + q2 * sv) * sv);
    }
    return f;
}

/* Clip t in [*t0, *t1] to lo <= x0 + d t <= hi; false when nothing is left. */
static bool s_clip (double x0, double d, double lo, double hi, double *t0, double *t1)
{
    if (d == 0)
        return x0 >= lo && x0 <= hi;
    double ta = (lo - x0) / d, tb = (hi - x0) / d;
    if (ta > tb) {
        double tmp = ta;
        ta = tb;
        tb = tmp;
    }
    if (ta > *t0)
        *t0 = ta;
    if (tb < *t1)
        *t1 = tb;
    return *t0 <= *t1;
}

/* Smallest clearance along a-b over the grid (+INFINITY when the segment
 * misses the grid); with stop_blocked, returns as soon as it is <= 0. */
static double s_los (const cgs_terrain_t *self, cgs_enu_t a, cgs_enu_t b, bool stop_blocked)
{
    s_seg_t s = {
        .xa = (a.e_m - self->e0_m) / self->res_m,
        .ya = (a.n_m - self->n0_m) / self->res_m,
        .za = a.u_m,
        .dx = (b.e_m - a.e_m) / self->res_m,
        .dy = (b.n_m - a.n_m) / self->res_m,
        .dz = b.u_m - a.u_m,
    };
    if (!isfinite (s.xa) || !isfinite (s.ya) || !isfinite (s.za) || !isfinite (s.dx) ||
        !isfinite (s.dy) || !isfinite (s.dz))
        return NAN;
    double t0 = 0, t1 = 1;
    if (!s_clip (s.xa, s.dx, 0, self->cols - 1, &t0, &t1) ||
        !s_clip (s.ya, s.dy, 0, self->rows - 1, &t0, &t1))
        return INFINITY;

    // First column / row line crossed after t0, as integers.
    double x0 = s.xa + s.dx * t0, y0 = s.ya + s.dy * t0;
    int sx = s.dx > 0 ? 1 : -1, sy = s.dy > 0 ? 1 : -1;
    double kx = s.dx > 0 ? floor (x0) + 1 : ceil (x0) - 1;
    double ky = s.dy > 0 ? floor (y0) + 1 : ceil (y0) - 1;
    double best = INFINITY, ta = t0;
    for (;;) {
        double tx = s.dx != 0 ? (kx - s.xa) / s.dx : INFINITY;
        double ty = s.dy != 0 ? (ky - s.ya) / s.dy : INFINITY;
        double tb = fmin (fmin (tx, ty), t1);
        if (tb >= ta) {
            best = fmin (best, s_piece_min (self, &s, ta, tb));
            if (stop_blocked && best <= 0)
                return best;
            ta = tb;
        }
        if (tb >= t1)
            break;
        if (tx <= tb)
            kx += sx;
        if (ty <= tb)
            ky += sy;
    }
    return best;
}

bool cgs_terrain_los_clearance (const cgs_terrain_t *self, cgs_enu_t a, cgs_enu_t b,
                                double *ret_clearance_m)
{
    assert (self);
    double c = s_los (self, a, b, false);
    if (ret_clearance_m)
        *ret_clearance_m = c;
    return c > 0; // false for NaN (non-finite input)
}

bool cgs_terrain_at_slant_range (const cgs_terrain_t *self, cgs_enu_t p, double az_deg, double r_m,
                                 cgs_enu_t *ret)
{
    double se = sin (az_deg * M_PI / 180), ce = cos (az_deg * M_PI / 180);
    double h = p.u_m - (self ? cgs_terrain_height_clamped (self, p.e_m, p.n_m) : 0);
    bool reaches = r_m > h;
    double g = sqrt (fmax (r_m * r_m - h * h, 0));
    cgs_enu_t q = p;
    for (int it = 0; it < 4; it++) {
        q.e_m = p.e_m + g * se;
        q.n_m = p.n_m + g * ce;
        q.u_m = self ? cgs_terrain_height_clamped (self, q.e_m, q.n_m) : 0;
        h = p.u_m - q.u_m;
        reaches = r_m > h;
        g = sqrt (fmax (r_m * r_m - h * h, 0));
    }
    *ret = q;
    return reaches;
}

bool cgs_terrain_los (const cgs_terrain_t *self, cgs_enu_t a, cgs_enu_t b)
{
    assert (self);
    return s_los (self, a, b, true) > 0;
}

/* --- rays ------------------------------------------------------------------ */

static double s_ray_h (const cgs_terrain_t *t, double e, double n)
{
    return t ? cgs_terrain_height_clamped (t, e, n) : 0.0;
}

bool cgs_terrain_ray (const cgs_terrain_t *self, cgs_enu_t p, cgs_enu_t d, double max_range_m,
                      cgs_enu_t *ret)
{
    enum { BISECT = 60 };
    double len = sqrt (d.e_m * d.e_m + d.n_m * d.n_m + d.u_m * d.u_m);
    if (len > 0)
        d = (cgs_enu_t){d.e_m / len, d.n_m / len, d.u_m / len};
    double ground = s_ray_h (self, p.e_m, p.n_m);
    if (p.u_m - ground <= 0) {
        *ret = (cgs_enu_t){p.e_m, p.n_m, ground};
        return true;
    }
    if (!self) {
        if (d.u_m < 0 && (p.u_m - ground) / -d.u_m <= max_range_m) {
            double s = (p.u_m - ground) / -d.u_m;
            *ret = (cgs_enu_t){p.e_m + s * d.e_m, p.n_m + s * d.n_m, 0.0};
            return true;
        }
    } else if (len > 0) {
        double step = fmax (1.0, cgs_terrain_resolution (self) / 2.0);
        double s_lo = 0, s_hi = -1;
        for (double s = step;; s += step) {
            if (s > max_range_m)
                s = max_range_m;
            if (p.u_m + s * d.u_m <= s_ray_h (self, p.e_m + s * d.e_m, p.n_m + s * d.n_m)) {
                s_hi = s;
                break;
            }
            s_lo = s;
            if (s >= max_range_m)
                break;
        }
        if (s_hi > 0) {
            for (int k = 0; k < BISECT; k++) {
                double m = 0.5 * (s_lo + s_hi);
                if (p.u_m + m * d.u_m <= s_ray_h (self, p.e_m + m * d.e_m, p.n_m + m * d.n_m))
                    s_hi = m;
                else
                    s_lo = m;
            }
            *ret = (cgs_enu_t){p.e_m + s_hi * d.e_m, p.n_m + s_hi * d.n_m, p.u_m + s_hi * d.u_m};
            return true;
        }
    }
    // No ground within range: cut at max range along the ray's ground track.
    double hl = hypot (d.e_m, d.n_m);
    double e = p.e_m + (hl > 0 ? max_range_m * d.e_m / hl : 0);
    double n = p.n_m + (hl > 0 ? max_range_m * d.n_m / hl : 0);
    *ret = (cgs_enu_t){e, n, s_ray_h (self, e, n)};
    return false;
}
