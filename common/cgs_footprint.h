/* cgs_footprint — the imaging sensor's footprint on the ground as the
 * programs that judge it share it: a convex quadrilateral (the trapezoid the
 * image's corner rays meet the terrain in) and its centre (where the
 * boresight meets it). guidanced computes it, draws and plans with it;
 * mscgs scores intercepts with it (cgs_score). Pure. */
#ifndef CGS_FOOTPRINT_H
#define CGS_FOOTPRINT_H

#include "cgs_geo.h"

#include <stdbool.h>

/* A point or vector on the ground plane: east, north, metres (or m/s). */
typedef struct {
    double e, n;
} cgs_v2_t;

typedef struct {
    cgs_v2_t corner[4]; // clockwise seen from above: near-left, far-left, far-right, near-right
    double corner_up_m[4];
    cgs_v2_t center; // where the boresight meets the ground
    double center_up_m;
    bool clipped; // a ray met no ground within the sensor's range (its point is at that range)
} cgs_footprint_t;

/* Corner i (0..3), and the centre, as points of the local frame. */
cgs_enu_t cgs_footprint_corner_enu (const cgs_footprint_t *f, int i);
cgs_enu_t cgs_footprint_center_enu (const cgs_footprint_t *f);
/* Scale a footprint about its centre by k (the display scale). */
void cgs_footprint_scale (const cgs_footprint_t *f, double k, cgs_footprint_t *ret);
/* True when p lies inside (or on the edge of) the convex quadrilateral. */
bool cgs_footprint_contains (const cgs_footprint_t *f, cgs_v2_t p);
/* Distance from p to the quadrilateral (0 inside). */
double cgs_footprint_distance (const cgs_footprint_t *f, cgs_v2_t p);
/* Distance from p to the quadrilateral's edge, negative inside. */
double cgs_footprint_signed_distance (const cgs_footprint_t *f, cgs_v2_t p);

#endif
