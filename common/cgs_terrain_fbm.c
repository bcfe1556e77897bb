/* cgs_terrain_fbm — generated terrain (see cgs_terrain.h): fBm of gradient
 * noise from a seed, the same grid on every platform. Its field also places
 * the woods. */
#include "cgs_terrain.h"
#include "cgs_terrain_impl.h"
#include "cgs_util.h"

#include <assert.h>
#include <math.h>
#include <stdint.h>

/* --- procedural terrain -----------------------------------------------------
 * Gradient (Perlin) noise on an integer lattice whose gradients come from a
 * hash of the lattice point, the seed and the octave: no permutation table,
 * so no period. Every step is IEEE add/multiply/floor on doubles and integer
 * hashing, so the same seed gives the same grid on every platform (the file
 * is built without -ffast-math and without fused multiply-adds, see
 * cgs_terrain_impl.h). */

static uint64_t s_mix64 (uint64_t z)
{
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
}

#define S_DIAG 0.70710678118654752440
static const double s_gradients[8][2] = {{1, 0},
                                         {-1, 0},
                                         {0, 1},
                                         {0, -1},
                                         {S_DIAG, S_DIAG},
                                         {-S_DIAG, S_DIAG},
                                         {S_DIAG, -S_DIAG},
                                         {-S_DIAG, -S_DIAG}};

static double s_grad_dot (uint64_t key, int64_t ix, int64_t iy, double fx, double fy)
{
    uint64_t h = s_mix64 (s_mix64 (key ^ (uint64_t)ix) ^ (uint64_t)iy);
    const double *g = s_gradients[h >> 61];
    return g[0] * fx + g[1] * fy;
}

static double s_fade (double t)
{
    return t * t * t * (t * (t * 6 - 15) + 10);
}

/* Perlin gradient noise at (x, y), lattice units; about [-0.7, 0.7]. */
static double s_perlin (uint64_t key, double x, double y)
{
    double x0 = floor (x), y0 = floor (y);
    int64_t ix = (int64_t)x0, iy = (int64_t)y0;
    double fx = x - x0, fy = y - y0;
    double n00 = s_grad_dot (key, ix, iy, fx, fy);
    double n10 = s_grad_dot (key, ix + 1, iy, fx - 1, fy);
    double n01 = s_grad_dot (key, ix, iy + 1, fx, fy - 1);
    double n11 = s_grad_dot (key, ix + 1, iy + 1, fx - 1, fy - 1);
    double u = s_fade (fx), v = s_fade (fy);
    double nx0 = n00 + u * (n10 - n00), nx1 = n01 + u * (n11 - n01);
    return nx0 + v * (nx1 - nx0);
}

void cgs_terrain__fbm_field (const cgs_terrain_t *self, uint64_t seed, double feature_m,
                             int octaves, double persistence, float *out)
{
    uint64_t state = seed, key[16];
    double off_x[16], off_y[16], freq[16], amp[16];
    for (int k = 0; k < octaves; k++) {
        key[k] = cgs_splitmix64 (&state);
        off_x[k] = (double)(cgs_splitmix64 (&state) >> 11) * 0x1p-53 * 1024;
        off_y[k] = (double)(cgs_splitmix64 (&state) >> 11) * 0x1p-53 * 1024;
        freq[k] = ldexp (1, k) / feature_m;
        amp[k] = k == 0 ? 1 : amp[k - 1] * persistence;
    }
    for (int r = 0; r < self->rows; r++) {
        double n_m = self->n0_m + r * self->res_m;
        for (int c = 0; c < self->cols; c++) {
            double e_m = self->e0_m + c * self->res_m, sum = 0;
            for (int k = 0; k < octaves; k++)
                sum +=
                    amp[k] * s_perlin (key[k], e_m * freq[k] + off_x[k], n_m * freq[k] + off_y[k]);
            out[(size_t)r * self->cols + c] = (float)sum;
        }
    }
}

void cgs_terrain_fbm_defaults (cgs_terrain_fbm_t *p)
{
    assert (p);
    *p = (cgs_terrain_fbm_t){
        .seed = 0,
        .size_m = 20000,
        .resolution_m = 30,
        .relief_m = 200,
        .base_height_m = 0,
        .feature_m = 4000,
        .octaves = 6,
        .persistence = 0.5,
    };
}

/* The grid is floor(size / resolution) + 1 nodes a side (so it never exceeds
 * size_m), centred on the origin. */
cgs_terrain_t *cgs_terrain_new_fbm (const cgs_terrain_fbm_t *p)
{
    if (!p || !isfinite (p->size_m) || !isfinite (p->resolution_m) || !isfinite (p->relief_m) ||
        !isfinite (p->base_height_m) || !isfinite (p->feature_m) || !isfinite (p->persistence))
        return NULL;
    if (p->size_m <= 0 || p->resolution_m <= 0 || p->relief_m < 0 || p->feature_m <= 0)
        return NULL;
    if (p->octaves < 1 || p->octaves > 16 || !(p->persistence > 0 && p->persistence <= 1))
        return NULL;
    double n_d = floor (p->size_m / p->resolution_m + 1e-9) + 1;
    if (n_d < 2 || n_d * n_d > (double)CGS_TERRAIN_MAX_NODES)
        return NULL;
    // Keep lattice coordinates far inside int64 and exact in a double.
    if (p->size_m / p->feature_m * ldexp (1, p->octaves) > ldexp (1, 40))
        return NULL;
    if (!isfinite (p->base_height_m + p->relief_m))
        return NULL;

    int n = (int)n_d;
    double half_m = 0.5 * (n - 1) * p->resolution_m;
    cgs_terrain_t *self = cgs_terrain__new (n, n, -half_m, -half_m, p->resolution_m);
    if (!self)
        return NULL;

    cgs_terrain__fbm_field (self, p->seed, p->feature_m, p->octaves, p->persistence, self->h_m);
    // Rescale so the lowest node is base exactly and the highest base + relief.
    cgs_terrain__finish (self);
    double lo = self->min_m, span = self->max_m - self->min_m;
    for (size_t i = 0; i < (size_t)n * n; i++) {
        double f = span > 0 ? (self->h_m[i] - lo) / span : 0;
        self->h_m[i] = (float)(p->base_height_m + p->relief_m * f);
    }
    cgs_terrain__finish (self);
    return self;
}
