/* cgs_terrain — the terrain database every service queries: a regular float
 * height grid in the exercise's local east-north-up frame, with bilinear
 * heights, normals, bounds and statistics. This is the core; the rest of
 * cgs_terrain.h is, by concern:
 *   cgs_terrain_fbm.c    generated (fBm) terrain
 *   cgs_terrain_woods.c  vegetation: canopy and foliage
 *   cgs_terrain_ray.c    line of sight, rays, the slant-range ground point
 *   cgs_terrain_dem.c    the DEM import, the only file that sees GDAL
 * and cgs_terrain_impl.h holds the struct and the helpers they share.
 * Pure: no globals, no logging. */
#include "cgs_terrain.h"
#include "cgs_terrain_impl.h"

#include <assert.h>
#include <errno.h>
#include <math.h>
#include <stdlib.h>

/* --- grid ------------------------------------------------------------------ */

cgs_terrain_t *cgs_terrain__new (int cols, int rows, double e0_m, double n0_m, double res_m)
{
    if (cols < 2 || rows < 2 || (size_t)cols * (size_t)rows > CGS_TERRAIN_MAX_NODES)
        return NULL;
    if (!isfinite (e0_m) || !isfinite (n0_m) || !isfinite (res_m) || res_m <= 0)
        return NULL;
    cgs_terrain_t *self = calloc (1, sizeof *self);
    if (!self)
        goto fail;
    self->cols = cols;
    self->rows = rows;
    self->e0_m = e0_m;
    self->n0_m = n0_m;
    self->res_m = res_m;
    self->h_m = calloc ((size_t)cols * (size_t)rows, sizeof *self->h_m);
    if (!self->h_m)
        goto fail;
    return self;
fail:
    cgs_terrain_destroy (&self);
    return NULL;
}

void cgs_terrain__finish (cgs_terrain_t *self)
{
    size_t n = (size_t)self->cols * (size_t)self->rows;
    float lo = self->h_m[0], hi = self->h_m[0];
    for (size_t i = 1; i < n; i++) {
        if (self->h_m[i] < lo)
            lo = self->h_m[i];
        if (self->h_m[i] > hi)
            hi = self->h_m[i];
    }
    self->min_m = lo;
    self->max_m = hi;
}

cgs_terrain_t *cgs_terrain_new_grid (int cols, int rows, double e0_m, double n0_m, double res_m,
                                     const float *heights_m)
{
    if (!heights_m)
        return NULL;
    cgs_terrain_t *self = cgs_terrain__new (cols, rows, e0_m, n0_m, res_m);
    if (!self)
        return NULL;
    size_t n = (size_t)cols * (size_t)rows;
    for (size_t i = 0; i < n; i++) {
        if (!isfinite (heights_m[i]))
            goto fail;
        self->h_m[i] = heights_m[i];
    }
    cgs_terrain__finish (self);
    return self;
fail:
    cgs_terrain_destroy (&self);
    return NULL;
}

void cgs_terrain_destroy (cgs_terrain_t **self_p)
{
    if (!self_p || !*self_p)
        return;
    cgs_terrain_t *self = *self_p;
    free (self->h_m);
    free (self->canopy_m);
    free (self);
    *self_p = NULL;
}

/* Bilinear height at grid coordinates (x, y) (node units), which must lie in
 * [0, cols-1] x [0, rows-1]. */
static double s_bilinear (const cgs_terrain_t *self, double x, double y)
{
    int c = (int)floor (x), r = (int)floor (y);
    if (c > self->cols - 2)
        c = self->cols - 2;
    if (r > self->rows - 2)
        r = self->rows - 2;
    if (c < 0)
        c = 0;
    if (r < 0)
        r = 0;
    double u = x - c, v = y - r;
    double h00 = cgs_terrain__node (self, c, r), h10 = cgs_terrain__node (self, c + 1, r);
    double h01 = cgs_terrain__node (self, c, r + 1), h11 = cgs_terrain__node (self, c + 1, r + 1);
    return (h00 * (1 - u) + h10 * u) * (1 - v) + (h01 * (1 - u) + h11 * u) * v;
}

int cgs_terrain_height (const cgs_terrain_t *self, double e_m, double n_m, double *ret_h_m)
{
    assert (self);
    double x = (e_m - self->e0_m) / self->res_m, y = (n_m - self->n0_m) / self->res_m;
    double max_e, max_n;
    cgs_terrain_bounds (self, NULL, NULL, &max_e, &max_n);
    if (!(e_m >= self->e0_m && e_m <= max_e && n_m >= self->n0_m && n_m <= max_n))
        return -ERANGE; // also NaN
    double h = s_bilinear (self, cgs_terrain__clamp (x, 0, self->cols - 1),
                           cgs_terrain__clamp (y, 0, self->rows - 1));
    if (ret_h_m)
        *ret_h_m = h;
    return 0;
}

double cgs_terrain_height_clamped (const cgs_terrain_t *self, double e_m, double n_m)
{
    assert (self);
    double x = (e_m - self->e0_m) / self->res_m, y = (n_m - self->n0_m) / self->res_m;
    if (isnan (x))
        x = 0;
    if (isnan (y))
        y = 0;
    return s_bilinear (self, cgs_terrain__clamp (x, 0, self->cols - 1),
                       cgs_terrain__clamp (y, 0, self->rows - 1));
}

/* Central differences one node spacing either side, one-sided at the edges. */
cgs_enu_t cgs_terrain_normal (const cgs_terrain_t *self, double e_m, double n_m)
{
    assert (self);
    double min_e, min_n, max_e, max_n;
    cgs_terrain_bounds (self, &min_e, &min_n, &max_e, &max_n);
    double e = cgs_terrain__clamp (e_m, min_e, max_e), n = cgs_terrain__clamp (n_m, min_n, max_n);
    double e_lo = fmax (e - self->res_m, min_e), e_hi = fmin (e + self->res_m, max_e);
    double n_lo = fmax (n - self->res_m, min_n), n_hi = fmin (n + self->res_m, max_n);
    double dh_de =
        (cgs_terrain_height_clamped (self, e_hi, n) - cgs_terrain_height_clamped (self, e_lo, n)) /
        (e_hi - e_lo);
    double dh_dn =
        (cgs_terrain_height_clamped (self, e, n_hi) - cgs_terrain_height_clamped (self, e, n_lo)) /
        (n_hi - n_lo);
    double len = sqrt (dh_de * dh_de + dh_dn * dh_dn + 1);
    return (cgs_enu_t){-dh_de / len, -dh_dn / len, 1 / len};
}

int cgs_terrain_cols (const cgs_terrain_t *self)
{
    assert (self);
    return self->cols;
}

int cgs_terrain_rows (const cgs_terrain_t *self)
{
    assert (self);
    return self->rows;
}

double cgs_terrain_resolution (const cgs_terrain_t *self)
{
    assert (self);
    return self->res_m;
}

void cgs_terrain_bounds (const cgs_terrain_t *self, double *ret_min_e, double *ret_min_n,
                         double *ret_max_e, double *ret_max_n)
{
    assert (self);
    if (ret_min_e)
        *ret_min_e = self->e0_m;
    if (ret_min_n)
        *ret_min_n = self->n0_m;
    if (ret_max_e)
        *ret_max_e = self->e0_m + (self->cols - 1) * self->res_m;
    if (ret_max_n)
        *ret_max_n = self->n0_m + (self->rows - 1) * self->res_m;
}

void cgs_terrain_height_range (const cgs_terrain_t *self, double *ret_min_m, double *ret_max_m)
{
    assert (self);
    if (ret_min_m)
        *ret_min_m = self->min_m;
    if (ret_max_m)
        *ret_max_m = self->max_m;
}

float cgs_terrain_node (const cgs_terrain_t *self, int col, int row)
{
    assert (self);
    assert (col >= 0 && col < self->cols && row >= 0 && row < self->rows);
    return self->h_m[(size_t)row * (size_t)self->cols + (size_t)col];
}
