/* im_frame — what a frame is made of besides its pixels: the camera at the
 * UAV as it is at the frame's time, which ground entity the designated
 * track is, where that target falls in the image (pixel position of its
 * model's centre, size in pixels, in view or not), and the overlay's lines.
 * Pure: no GL, no logging. */
#ifndef IM_FRAME_H
#define IM_FRAME_H

#include "cgs_camera.h"
#include "im_klv.h"
#include "im_params.h"
#include "im_render.h"

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#define IM_LABELS_MAX 64 // status blocks in one frame, nearest first

/* The UAV as last heard on `uav`. */
typedef struct {
    bool valid;
    uint32_t id;
    cgs_enu_t position, velocity;
    double heading_deg, pitch_deg, roll_deg;
    double altitude_agl_m;
    double depression_deg, hfov_deg, vfov_deg; // its imaging sensor
    /* The camera as the message sets it (cgs_msg_uav_camera): stabilization,
     * the stare point and the gimbal's limits. */
    cgs_camera_point_t point;
    double time_s;
} im_uav_t;

/* The camera for a frame at time t (common/cgs_camera's, as every service
 * builds it): the UAV moved on along its velocity, its attitude and the
 * sensor's settings as heard. -EINVAL when they cannot make a camera. */
int im_frame_camera (const im_params_t *p, const im_uav_t *u, double t, cgs_camera_t *ret);

typedef struct {
    bool known;         // a ground entity answers to the designated track
    uint32_t entity_id; // which
    bool in_view;       // its model's centre is in the image and not behind terrain
    bool occluded;      // in the image but behind terrain
    double px_x, px_y;  // pixel position of its model's centre (valid when projected)
    bool projected;     // in front of the camera
    double size_px;     // its model's length across the image, pixels
    double slant_m;     // eye to its centre
} im_target_t;

/* The designated target: the entity of ents (not of kind air) nearest to
 * track_at, within gate_m of it (none when have_track is false), and where
 * it falls in the camera's image. terrain may be NULL (nothing blocks). */
void im_frame_target (const cgs_camera_t *cam, const cgs_terrain_t *terrain,
                      const im_entity_t *ents, size_t n, bool have_track, cgs_enu_t track_at,
                      double gate_m, im_target_t *ret);

/* A ground vehicle's status block: where its model's top falls in the image. */
typedef struct {
    const im_entity_t *entity;
    double px_x, px_y;
} im_label_t;

/* The ground vehicles of ents in view (their model's top in the image, in
 * front of the camera and not behind terrain; terrain may be NULL), nearest
 * the camera first, at most cap of them, into ret; how many. */
size_t im_frame_labels (const cgs_camera_t *cam, const cgs_terrain_t *terrain,
                        const im_entity_t *ents, size_t n, im_label_t *ret, size_t cap);
/* A status block's lines: the marking, the force, the speed in km/h. */
void im_frame_status_lines (const im_entity_t *e, char lines[3][24]);

/* The overlay's lines into lines[0..3] (each size bytes): simulation time,
 * UAV altitude, slant range to the image centre, the image centre in MGRS
 * (frame NULL or a failed conversion: local metres). */
void im_frame_overlay (double t_s, const im_uav_t *u, const cgs_camera_t *cam,
                       const cgs_footprint_t *fp, const cgs_geo_t *frame, char lines[4][96]);

/* The frame's MISB ST 0601 metadata, from the same camera and footprint as
 * its `image` message: unix_time_s and mission_id as given; the platform's
 * heading, pitch and roll (u); the sensor at the camera's eye; the fields of
 * view; the camera's azimuth, elevation and roll relative to the platform's
 * body axes (azimuth clockwise from the nose, elevation negative down, roll
 * right side down positive; a fixed camera is at 0, −ε, 0); the slant range
 * and the frame centre where the boresight meets the ground; the corners
 * (image upper left, upper right, lower right, lower left: the footprint's
 * far-left, far-right, near-right, near-left); the target and its track id
 * when has_target. Heights: the exercise takes the terrain's heights as
 * above the ellipsoid (the geoid separation is ignored), so the true
 * altitude (MSL) and the ellipsoid height are one value. A footprint with a
 * ray that met no ground (clipped) gives no slant range, frame centre or
 * corners: those tags are left out. Angles are in the
 * exercise's local frame (its north at the origin). -EINVAL when the eye
 * cannot be placed on the earth. */
int im_frame_klv (const cgs_camera_t *cam, const cgs_footprint_t *fp, const im_uav_t *u,
                  const cgs_geo_t *frame, double unix_time_s, const char *mission_id,
                  bool has_target, cgs_enu_t target, uint32_t track_id, im_klv_frame_t *ret);

#endif
