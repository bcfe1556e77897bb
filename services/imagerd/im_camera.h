/* im_camera — the imaging sensor as a pinhole camera: where it is and where
 * it looks (the UAV's position and attitude, the sensor's depression angle ε
 * and fields of view γ × β), the matrices that render its view, the
 * projection of a point to a pixel and its footprint on the ground.
 *
 * Axes follow guidanced's footprint (gd_footprint), so the map and the image
 * agree: body forward f = (sin h cos θ, cos h cos θ, sin θ), level right
 * r0 = (cos h, −sin h, 0), up u0 = r0 × f, rolled by φ (right wing down
 * positive); the camera is the body pitched down by ε. Pixels: x to the
 * right, y down, (0, 0) the top-left corner of the image, a pixel's centre
 * at +0.5. Pure: no GL, no logging. */
#ifndef IM_CAMERA_H
#define IM_CAMERA_H

#include "cgs_geo.h"
#include "cgs_terrain.h"

#include <stdbool.h>

typedef struct {
    cgs_enu_t position;    // the sensor (the UAV), local frame, absolute up
    double heading_deg;    // UAV, clockwise from north
    double pitch_deg;      // nose up positive
    double roll_deg;       // right wing down positive
    double depression_deg; // ε: boresight below the body's forward axis
    double hfov_deg;       // γ
    double vfov_deg;       // β
    int width_px, height_px;
    double near_m, far_m; // depth range rendered
    bool stabilized;      // levelled against bank: the roll is taken out
} im_camera_in_t;

typedef struct {
    cgs_enu_t eye;
    cgs_enu_t forward, right, up; // orthonormal, local frame
    double tan_h, tan_v;          // tan(γ/2), tan(β/2)
    int width_px, height_px;
    double near_m, far_m;
    float view[16], proj[16]; // column-major, OpenGL's conventions
    /* The boresight's own angles (for the `image` message). */
    double heading_deg, pitch_deg, roll_deg;
} im_camera_t;

/* Build the camera; 0 or -EINVAL (a non-finite pose, ε outside (−90, 90),
 * a field of view outside (0, 180), a size below 1 or a depth range not
 * 0 < near < far). */
int im_camera_make (const im_camera_in_t *in, im_camera_t *ret);
/* Staring: turn the camera to look at target (kept level: no roll about the
 * boresight). -EINVAL when the target is at the eye or straight below or
 * above it, the camera unchanged. */
int im_camera_stare (im_camera_t *cam, cgs_enu_t target);
/* Where p falls in the image: true when it is in front of the camera (beyond
 * the near plane), with *x, *y its pixel position (may lie outside the
 * image) and *depth its distance along the boresight. */
bool im_camera_project (const im_camera_t *cam, cgs_enu_t p, double *x, double *y, double *depth);
/* True when p is in front of the camera and within the image. */
bool im_camera_in_view (const im_camera_t *cam, cgs_enu_t p);
/* The direction (unit) of the ray through pixel position (x, y). */
cgs_enu_t im_camera_ray (const im_camera_t *cam, double x, double y);

/* The image's corners and centre on the ground. */
typedef struct {
    cgs_enu_t corner[4]; // clockwise seen from above: near-left, far-left, far-right, near-right
    cgs_enu_t center;    // where the boresight meets the ground
    bool clipped;        // a ray met no ground within max_range (its point is at max_range)
} im_footprint_t;

/* The footprint: the rays through the image's corners and centre met with
 * the terrain (NULL: flat ground at 0). */
void im_camera_footprint (const im_camera_t *cam, const cgs_terrain_t *terrain, double max_range_m,
                          im_footprint_t *ret);

/* Six planes (a, b, c, d: inside when a·e + b·n + c·u + d ≥ 0) bounding what
 * the camera sees; and whether the box [lo, hi] lies wholly outside one. */
void im_camera_frustum (const im_camera_t *cam, double planes[6][4]);
bool im_frustum_culls (const double planes[6][4], cgs_enu_t lo, cgs_enu_t hi);

#endif
