/* cgs_terrain_woods — vegetation over the terrain's grid (see
 * cgs_terrain.h): a canopy height per node, grown from a seeded fBm field or
 * given, and the length of a line of sight that runs through it. */
#include "cgs_terrain.h"
#include "cgs_terrain_impl.h"

#include <assert.h>
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* --- vegetation --------------------------------------------------------------
 * A canopy height per node (0 where the ground is open). A point belongs to
 * the nearest node's cell; it is inside the vegetation when it is above the
 * ground and less than that cell's canopy height above it. */

void cgs_vegetation_defaults (cgs_vegetation_t *v)
{
    assert (v);
    *v = (cgs_vegetation_t){.seed = 0, .cover = 0, .canopy_m = 15, .feature_m = 600};
}

static int s_cmp_float (const void *a, const void *b)
{
    float x = *(const float *)a, y = *(const float *)b;
    return x < y ? -1 : x > y;
}

int cgs_terrain_set_canopy (cgs_terrain_t *self, const float *canopy_m)
{
    size_t n = (size_t)self->cols * (size_t)self->rows;
    float *c = malloc (n * sizeof *c);
    if (!c)
        return -ENOMEM;
    double top = 0;
    for (size_t i = 0; i < n; i++) {
        if (!isfinite (canopy_m[i]) || canopy_m[i] < 0 || canopy_m[i] > 1000) {
            free (c);
            return -EINVAL;
        }
        c[i] = canopy_m[i];
        if (c[i] > top)
            top = c[i];
    }
    free (self->canopy_m);
    self->canopy_m = c;
    self->canopy_max_m = top;
    return 0;
}

int cgs_terrain_grow_vegetation (cgs_terrain_t *self, const cgs_vegetation_t *v)
{
    if (!v || !isfinite (v->cover) || v->cover < 0 || v->cover > 1 || !isfinite (v->canopy_m) ||
        v->canopy_m <= 0 || v->canopy_m > 1000 || !isfinite (v->feature_m) || v->feature_m <= 0)
        return -EINVAL;
    size_t n = (size_t)self->cols * (size_t)self->rows;
    float *field = malloc (n * sizeof *field), *sorted = malloc (n * sizeof *sorted);
    if (!field || !sorted) {
        free (field);
        free (sorted);
        return -ENOMEM;
    }
    // Woods where a seeded fBm field is highest: the top `cover` of its nodes.
    cgs_terrain__fbm_field (self, v->seed, v->feature_m, 4, 0.5, field);
    memcpy (sorted, field, n * sizeof *field);
    qsort (sorted, n, sizeof *sorted, s_cmp_float);
    size_t k = (size_t)llround (v->cover * (double)n);
    float threshold = k ? sorted[n - k] : INFINITY;
    for (size_t i = 0; i < n; i++)
        field[i] = field[i] >= threshold ? (float)v->canopy_m : 0.0f;
    free (sorted);
    free (self->canopy_m);
    self->canopy_m = field;
    self->canopy_max_m = k ? v->canopy_m : 0;
    return 0;
}

double cgs_terrain_canopy (const cgs_terrain_t *self, double e_m, double n_m)
{
    if (!self->canopy_m || !isfinite (e_m) || !isfinite (n_m))
        return 0;
    double c = floor ((e_m - self->e0_m) / self->res_m + 0.5),
           r = floor ((n_m - self->n0_m) / self->res_m + 0.5);
    if (c < 0 || r < 0 || c >= self->cols || r >= self->rows)
        return 0;
    return self->canopy_m[(size_t)r * self->cols + (size_t)c];
}

double cgs_terrain_vegetated_fraction (const cgs_terrain_t *self)
{
    if (!self->canopy_m)
        return 0;
    size_t n = (size_t)self->cols * (size_t)self->rows, v = 0;
    for (size_t i = 0; i < n; i++)
        v += self->canopy_m[i] > 0;
    return (double)v / (double)n;
}

double cgs_terrain_foliage_m (const cgs_terrain_t *self, cgs_enu_t a, cgs_enu_t b)
{
    if (!self->canopy_m || self->canopy_max_m <= 0)
        return 0;
    double de = b.e_m - a.e_m, dn = b.n_m - a.n_m, du = b.u_m - a.u_m;
    double len = sqrt (de * de + dn * dn + du * du);
    if (!isfinite (len) || len <= 0)
        return 0;
    // Only the part of the segment below the highest treetop can be inside.
    double top = self->max_m + self->canopy_max_m, t0 = 0, t1 = 1;
    if (a.u_m > top && b.u_m > top)
        return 0;
    if (du != 0) {
        double tc = (top - a.u_m) / du; // where the segment crosses the treetops' height
        if (du > 0)
            t1 = tc < 1 ? tc : 1;
        else
            t0 = tc > 0 ? tc : 0;
    }
    double span_m = (t1 - t0) * len;
    if (span_m <= 0)
        return 0;
    // Midpoint samples a quarter of a cell apart, and close enough that the
    // path climbs at most 0.25 m between them (at most 100,000).
    double step_m = self->res_m / 4;
    if (du != 0 && 0.25 * len / fabs (du) < step_m)
        step_m = 0.25 * len / fabs (du);
    double steps = ceil (span_m / step_m);
    if (steps > 100000)
        steps = 100000;
    int n = (int)steps;
    int inside = 0;
    for (int i = 0; i < n; i++) {
        double t = t0 + (t1 - t0) * (i + 0.5) / n;
        double e = a.e_m + t * de, nn = a.n_m + t * dn, u = a.u_m + t * du;
        double c = cgs_terrain_canopy (self, e, nn);
        if (c <= 0)
            continue;
        double above = u - cgs_terrain_height_clamped (self, e, nn);
        inside += above >= 0 && above < c;
    }
    return span_m * inside / n;
}
