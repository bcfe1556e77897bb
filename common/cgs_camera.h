/* cgs_camera — the imaging sensor as a pinhole camera, the one model every
 * service shares: uavsim points it (from the UAV's attitude and the sensor's
 * settings: depression angle, stabilization, a stare point within the
 * gimbal's limits) and publishes its attitude on `uav`; imagerd renders its
 * view, guidanced plans with its footprint, the map draws it and mscgs scores
 * with it, each rebuilding the same camera from that attitude
 * (cgs_camera_make_attitude). Also the matrices that render its view, the
 * projection of a point to a pixel and its footprint on the terrain.
 *
 * Axes: body forward f = (sin h cos θ, cos h cos θ, sin θ), level right
 * r0 = (cos h, −sin h, 0), up u0 = r0 × f, rolled by φ (right wing down
 * positive); the fixed camera is the body pitched down by ε. Pixels: x to the
 * right, y down, (0, 0) the top-left corner of the image, a pixel's centre
 * at +0.5. Pure: no GL, no logging. */
#ifndef CGS_CAMERA_H
#define CGS_CAMERA_H

#include "cgs_footprint.h"
#include "cgs_geo.h"
#include "cgs_terrain.h"

#include <stdbool.h>

/* How the camera is turned besides the body's attitude and ε: what uavsim
 * sets at run time and `uav` carries (cgs_msg_uav_camera). */
typedef struct {
    bool stabilized; // levelled against bank: the roll is taken out
    bool staring;    // turned to stare_at (kept level), within the gimbal's limits
    cgs_enu_t stare_at;
    bool gimbal_limited;       // staring: the limits below apply (else the gimbal turns freely)
    double gimbal_azimuth_deg; // either side of the nose, (0, 180]
    double gimbal_elevation_min_deg,
        gimbal_elevation_max_deg; // below (negative) or above the body's plane
} cgs_camera_point_t;

typedef struct {
    cgs_enu_t position;    // the sensor (the UAV), local frame, absolute up
    double heading_deg;    // UAV, clockwise from north
    double pitch_deg;      // nose up positive
    double roll_deg;       // right wing down positive
    double depression_deg; // ε: boresight below the body's forward axis
    double hfov_deg;       // γ
    double vfov_deg;       // β
    int width_px, height_px;
    double near_m, far_m;     // depth range rendered
    cgs_camera_point_t point; // stabilization, stare, gimbal
} cgs_camera_in_t;

typedef struct {
    cgs_enu_t eye;
    cgs_enu_t forward, right, up; // orthonormal, local frame
    double tan_h, tan_v;          // tan(γ/2), tan(β/2)
    int width_px, height_px;
    double near_m, far_m;
    float view[16], proj[16]; // column-major, OpenGL's conventions
    /* The camera's attitude: the boresight's azimuth (clockwise from north)
     * and elevation, and the roll of its right axis below the horizontal
     * (what `uav` carries as sensor_azimuth_deg, _elevation_deg, _roll_deg). */
    double heading_deg, pitch_deg, roll_deg;
    bool at_gimbal_limit; // staring: the stare point lies beyond the gimbal's limits
} cgs_camera_t;

/* Build the camera; 0 or -EINVAL (a non-finite pose, ε outside (−90, 90),
 * a field of view outside (0, 180), a size below 1, a depth range not
 * 0 < near < far, or gimbal limits out of order). A staring camera whose
 * stare point is at the eye or straight above or below it keeps the fixed
 * (or stabilized) boresight. */
int cgs_camera_make (const cgs_camera_in_t *in, cgs_camera_t *ret);

/* What builds a camera from its attitude alone. */
typedef struct {
    cgs_enu_t position;   // the eye
    double azimuth_deg;   // the boresight, clockwise from north
    double elevation_deg; // the boresight above the horizontal, [−90, 90]
    double roll_deg;      // the right axis below the horizontal
    double hfov_deg, vfov_deg;
    int width_px, height_px;
    double near_m, far_m;
} cgs_camera_attitude_t;

/* The camera of an attitude (as cgs_camera_make reports it in heading_deg,
 * pitch_deg and roll_deg): the same axes to rounding. 0 or -EINVAL. */
int cgs_camera_make_attitude (const cgs_camera_attitude_t *a, cgs_camera_t *ret);
/* Staring: turn the camera to look at target (kept level: no roll about the
 * boresight). -EINVAL when the target is at the eye or straight below or
 * above it, the camera unchanged. */
int cgs_camera_stare (cgs_camera_t *cam, cgs_enu_t target);
/* Where p falls in the image: true when it is in front of the camera (beyond
 * the near plane), with *x, *y its pixel position (may lie outside the
 * image) and *depth its distance along the boresight. */
bool cgs_camera_project (const cgs_camera_t *cam, cgs_enu_t p, double *x, double *y, double *depth);
/* True when p is in front of the camera and within the image. */
bool cgs_camera_in_view (const cgs_camera_t *cam, cgs_enu_t p);
/* The direction (unit) of the ray through pixel position (x, y). */
cgs_enu_t cgs_camera_ray (const cgs_camera_t *cam, double x, double y);

/* The footprint (common/cgs_footprint.h): the rays through the image's
 * corners (near-left, far-left, far-right, near-right: the bottom-left,
 * top-left, top-right and bottom-right pixels' outer corners) and its centre
 * met with the terrain (NULL: flat ground at 0); a ray that meets none
 * within max_range_m is cut there and the footprint marked clipped. */
void cgs_camera_footprint (const cgs_camera_t *cam, const cgs_terrain_t *terrain,
                           double max_range_m, cgs_footprint_t *ret);

/* Six planes (a, b, c, d: inside when a·e + b·n + c·u + d ≥ 0) bounding what
 * the camera sees; and whether the box [lo, hi] lies wholly outside one. */
void cgs_camera_frustum (const cgs_camera_t *cam, double planes[6][4]);
bool cgs_frustum_culls (const double planes[6][4], cgs_enu_t lo, cgs_enu_t hi);

#endif
