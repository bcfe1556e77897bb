/* cgs_terrain_impl — the terrain's insides, shared by the files that make up
 * cgs_terrain (cgs_terrain*.c) and by no one else: the grid's struct, the
 * helpers more than one of them needs, and the rule on floating point. Its
 * internal names take the prefix cgs_terrain__ (as libuv's uv__). Services
 * and tests include cgs_terrain.h only. */
#ifndef CGS_TERRAIN_IMPL_H
#define CGS_TERRAIN_IMPL_H

#include "cgs_terrain.h"

#include <stddef.h>
#include <stdint.h>

/* Terrain must come out the same everywhere: no fused multiply-adds. GCC
 * keeps them off in ISO C mode (-std=c11) and does not know this pragma;
 * clang needs it. It holds for the rest of each file that includes this. */
#if defined(__clang__)
#pragma STDC FP_CONTRACT OFF
#endif

#define CGS_TERRAIN_MAX_NODES ((size_t)1 << 26) // most nodes in one grid

struct cgs_terrain {
    int cols;            // nodes west to east
    int rows;            // nodes south to north
    double e0_m;         // east of node (0, 0), metres
    double n0_m;         // north of node (0, 0), metres
    double res_m;        // node spacing, metres
    double min_m;        // lowest node, metres (local up)
    double max_m;        // highest node, metres (local up)
    float *h_m;          // rows * cols heights, row 0 southernmost, metres (local up)
    float *canopy_m;     // rows * cols vegetation heights above the ground, 0 open; NULL: none
    double canopy_max_m; // tallest vegetation, metres
};

/* An empty grid of the given shape; NULL on bad shape or no memory. */
cgs_terrain_t *cgs_terrain__new (int cols, int rows, double e0_m, double n0_m, double res_m);
/* Record the height range once the nodes are filled in. */
void cgs_terrain__finish (cgs_terrain_t *self);
/* fBm of the given octaves over the terrain's nodes into out (rows * cols). */
void cgs_terrain__fbm_field (const cgs_terrain_t *self, uint64_t seed, double feature_m,
                             int octaves, double persistence, float *out);

/* Height of node (c, r), which must be inside the grid. */
static inline double cgs_terrain__node (const cgs_terrain_t *self, int c, int r)
{
    return self->h_m[(size_t)r * (size_t)self->cols + (size_t)c];
}

/* x limited to [lo, hi]. */
static inline double cgs_terrain__clamp (double x, double lo, double hi)
{
    return x < lo ? lo : x > hi ? hi : x;
}

#endif
