/* cgs_terrain — the terrain database every service queries: a regular height
 * grid in the exercise's local frame, read through GDAL (DTED, GeoTIFF, SRTM
 * HGT, ESRI ASCII grid, anything GDAL reads) or generated procedurally (fBm
 * from a seed). Bilinear height; line of sight that no terrain cell may cut.
 * Pure: no globals, no logging. */
#ifndef CGS_TERRAIN_H
#define CGS_TERRAIN_H

#include "cgs_geo.h"
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

typedef struct cgs_terrain cgs_terrain_t;

/* Parameters of procedural terrain: a square centred on the origin. */
typedef struct {
    uint64_t seed;        // same seed, same terrain
    double size_m;        // side of the square, metres (default 20000)
    double resolution_m;  // grid spacing, metres (default 30)
    double relief_m;      // highest minus lowest point, metres (default 200)
    double base_height_m; // height of the lowest point, metres (default 0)
    double feature_m;     // wavelength of the largest hills, metres (default 4000)
    int octaves;          // fBm octaves (default 6)
    double persistence;   // amplitude ratio between octaves (default 0.5)
} cgs_terrain_fbm_t;

/* Fill p with the documented defaults (seed 0). */
void cgs_terrain_fbm_defaults (cgs_terrain_fbm_t *p);
/* Procedural terrain; NULL on bad parameters (non-positive sizes, over 2^26 cells).
 * The grid has floor(size / resolution) + 1 nodes a side, centred on the origin. */
cgs_terrain_t *cgs_terrain_new_fbm (const cgs_terrain_fbm_t *p);
/* A grid from heights (row 0 is the southernmost row, column 0 the westernmost);
 * node (c, r) is at east = e0_m + c*res_m, north = n0_m + r*res_m. Copies heights.
 * NULL unless cols, rows >= 2, res_m > 0 and every height is finite. */
cgs_terrain_t *cgs_terrain_new_grid (int cols, int rows, double e0_m, double n0_m, double res_m,
                                     const float *heights_m);
/* Read a DEM through GDAL and resample it (bilinear) onto a local grid in the
 * frame: resolution_m 0 means about the raster's own spacing; half_extent_m 0
 * means the whole raster, else a square of that half-width about the origin,
 * clipped to the raster. Nodes sit at multiples of the resolution from the
 * origin; the grid is the largest rectangle of them about the origin that lies
 * wholly between the raster's outermost pixel centres. Heights are converted
 * to the local up axis (so the earth's curvature is in the grid); DEM heights
 * are taken as above the ellipsoid (geoid separation ignored). No-data cells
 * take the band's lowest valid height. A raster without a coordinate system is
 * refused. 0, or -ENOENT/-EINVAL/-ENOMEM with a reason naming the file in err
 * (err may be NULL). */
int cgs_terrain_load (const char *path, const cgs_geo_t *frame, double resolution_m,
                      double half_extent_m, cgs_terrain_t **ret_t, char *err, size_t errlen);
/* Free; accepts NULL; sets *self_p to NULL. */
void cgs_terrain_destroy (cgs_terrain_t **self_p);

/* Bilinear height (local up, metres) at (e, n); 0 or -ERANGE outside the grid. */
int cgs_terrain_height (const cgs_terrain_t *self, double e_m, double n_m, double *ret_h_m);
/* Height at (e, n), clamped to the nearest edge outside the grid. */
double cgs_terrain_height_clamped (const cgs_terrain_t *self, double e_m, double n_m);
/* Unit surface normal (local frame) at (e, n), clamped at the edges. */
cgs_enu_t cgs_terrain_normal (const cgs_terrain_t *self, double e_m, double n_m);
/* True when the straight segment a-b passes above the terrain surface all the
 * way (touching counts as blocked); parts outside the grid are not checked.
 * Exact for the bilinear surface. An endpoint on the ground touches it, so
 * callers raise endpoints to the sensor or antenna (e.g. a vehicle + 2 m). */
bool cgs_terrain_los (const cgs_terrain_t *self, cgs_enu_t a, cgs_enu_t b);
/* Like cgs_terrain_los, and *ret_clearance_m (may be NULL) is the smallest
 * height of the segment above the terrain (negative when blocked; +INFINITY
 * when no part is over the grid; NaN, and blocked, for non-finite input). */
bool cgs_terrain_los_clearance (const cgs_terrain_t *self, cgs_enu_t a, cgs_enu_t b,
                                double *ret_clearance_m);
/* Where the ray from p along d (any length) first meets the ground (self
 * NULL: flat ground at height 0): true with the point in *ret; false when it
 * meets none within max_range_m, with *ret the point max_range_m along the
 * ray's ground track, on the ground. A p at or below the ground meets it at
 * once. Marches in steps of half a cell, then bisects. */
bool cgs_terrain_ray (const cgs_terrain_t *self, cgs_enu_t p, cgs_enu_t d, double max_range_m,
                      cgs_enu_t *ret);
/* The ground point (self NULL: flat ground at height 0) at slant range r_m
 * from p toward azimuth az_deg (clockwise from north): where a radar puts a
 * range and an azimuth. The ground range g = sqrt(r² − h²), h the height of p
 * above the point, found by four fixed-point steps over the terrain. True
 * when the range reaches the ground (r above h); false with the point below
 * p (g = 0) otherwise. */
bool cgs_terrain_at_slant_range (const cgs_terrain_t *self, cgs_enu_t p, double az_deg, double r_m,
                                 cgs_enu_t *ret);

/* Vegetation (woods) grown procedurally over the terrain's grid. */
typedef struct {
    uint64_t seed;    // same seed, same woods
    double cover;     // fraction of the ground under vegetation, 0..1 (default 0: none)
    double canopy_m;  // height of the vegetation above the ground, metres (default 15)
    double feature_m; // size of the largest woods, metres (default 600)
} cgs_vegetation_t;

/* Fill v with the documented defaults (seed 0, no cover). */
void cgs_vegetation_defaults (cgs_vegetation_t *v);
/* Woods over round(cover * nodes) nodes: those where a seeded fBm field is
 * highest, so they come in patches of about feature_m; each node's canopy is
 * canopy_m. Replaces any vegetation. 0, -EINVAL (bad values), -ENOMEM. */
int cgs_terrain_grow_vegetation (cgs_terrain_t *self, const cgs_vegetation_t *v);
/* Canopy heights per node (rows * cols, as the grid; 0 = open), copied.
 * 0, -EINVAL (negative, over 1000 m or non-finite), -ENOMEM. */
int cgs_terrain_set_canopy (cgs_terrain_t *self, const float *canopy_m);
/* Canopy height above the ground at (e, n): the nearest node's, 0 where the
 * ground is open, outside the grid or without vegetation. */
double cgs_terrain_canopy (const cgs_terrain_t *self, double e_m, double n_m);
/* Fraction of the nodes under vegetation. */
double cgs_terrain_vegetated_fraction (const cgs_terrain_t *self);
/* Length (metres) of the segment a-b that runs inside vegetation: above the
 * ground and below the canopy of the cell it is over. Sampled at midpoints
 * along the part of the segment below the highest treetop, a quarter of a
 * grid cell apart and never more than 0.25 m of climb apart (at most 100,000
 * samples): within half a sample per edge crossed (a wood's side, its top or
 * the ground). 0 without vegetation or for a degenerate segment. */
double cgs_terrain_foliage_m (const cgs_terrain_t *self, cgs_enu_t a, cgs_enu_t b);

/* Grid geometry and statistics. */
int cgs_terrain_cols (const cgs_terrain_t *self);
int cgs_terrain_rows (const cgs_terrain_t *self);
double cgs_terrain_resolution (const cgs_terrain_t *self);
void cgs_terrain_bounds (const cgs_terrain_t *self, double *ret_min_e, double *ret_min_n,
                         double *ret_max_e, double *ret_max_n);
void cgs_terrain_height_range (const cgs_terrain_t *self, double *ret_min_m, double *ret_max_m);
/* Height of node (c, r), which must be inside the grid. */
float cgs_terrain_node (const cgs_terrain_t *self, int col, int row);

#endif
