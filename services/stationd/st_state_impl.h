/* st_state_impl — the picture's insides, shared by st_state.c (taking
 * messages) and st_view.c (its JSON) and by no one else: the tables kept of
 * each topic and struct st_state. Its function takes the internal prefix
 * st_state__ (as cgs_terrain_impl.h's). Tests and main.c include st_state.h
 * only. */
#ifndef ST_STATE_IMPL_H
#define ST_STATE_IMPL_H

#include "st_state.h"

#include "cgs_entities.h"

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#define ST_RADARS_MAX 16    // radars (UAVs with an MTI) whose hits are kept
#define ST_UAVS_MAX   16    // UAVs and intercepts
#define ST_BCIS_MAX   20000 // BCIS replies kept at once (the oldest go first)
#define ST_PATH_MAX   4096

typedef struct {
    double e, n;
} st_xy_t;

/* One MTI hit: where, and its id (unique within the radar's epoch). */
typedef struct {
    double e, n;
    uint32_t id;
} st_hit_t;

/* One scan of one radar's hits. */
typedef struct {
    uint32_t number;
    bool complete; // mti.scan said it ended
    st_hit_t *hits;
    size_t count, cap;
} st_scan_t;

/* One radar: its scans, oldest first. */
typedef struct {
    uint32_t uav_id;
    uint64_t epoch;   // its publisher's, to start afresh when mtid restarts
    st_scan_t *scans; // history_scans + 2 slots
    size_t count;
    double heard_s; // simulation time it was last heard of
} st_radar_t;

typedef struct {
    uint32_t uav_id, id;
    char marking[32];
    double e, n, time_s;
} st_bcis_t;

typedef struct {
    uint32_t id, uav_id;
    int status;   // CGS__TRACK_STATUS__*
    int identity; // CGS__TRACK_IDENTITY__*
    double e, n, heading_deg, speed_mps;
    uint32_t hits, friendly_id;
    bool has_last_hit;
    st_xy_t last_hit; // the track's newest hit
    uint32_t last_hit_id;
    double updated_s;
    uint64_t epoch; // trackerd's
} st_track_t;

/* How the UAV's imaging sensor is set, from `uav.sensor`. */
typedef struct {
    double depression_deg;     // below the body's forward axis
    double hfov_deg, vfov_deg; // fields of view
    bool stabilized;
    int stare;      // CGS__STARE_MODE__*
    bool has_point; // stare_point given
    st_xy_t point;  // where it stares (POINT: the point; TARGET: the estimate)
    bool staring;   // turned to the stare point now
    bool at_limit;  // held at the gimbal's limit
    double az_limit_deg, el_min_deg, el_max_deg; // the gimbal's limits
} st_camera_t;

typedef struct {
    bool valid;
    uint32_t id;
    char name[32];
    double e, n, alt_agl_m, heading_deg, airspeed_mps, ground_speed_mps;
    double cmd_alt_agl_m, cmd_airspeed_mps;
    int mode;
    double loiter_e, loiter_n, loiter_radius_m;
    bool has_camera; // the message carried the sensor
    st_camera_t camera;
    double heard_s;
} st_uav_t;

/* A UAV's imaging sensor mode, as its latest `image` message says. */
typedef struct {
    bool valid;
    uint32_t uav_id;
    int mode; // CGS__IMAGE_MODE__*
    double heard_s;
} st_sensor_mode_t;

typedef struct {
    bool valid;
    uint32_t uav_id, track_id;
    int state, method;
    st_xy_t *route;
    size_t route_count, route_cap;
    bool has_footprint;
    double footprint[8], center[2];
    unsigned scale;
    bool has_waypoint, has_secondary;
    st_xy_t waypoint, secondary;
    double time_to_go_s, t_pred_s;
    uint32_t replans;
    char reason[256];
    bool target_in_footprint;
    uint64_t designation;
    double heard_s;
} st_intercept_t;

struct st_state {
    st_state_params_t p;
    double now_s;
    bool have_clock;      // a clock was heard: only it moves time
    uint64_t clock_epoch; // its publisher's
    st_radar_t radars[ST_RADARS_MAX];
    size_t radar_count;
    st_bcis_t *bcis; // oldest first
    size_t bcis_count;
    st_track_t *tracks;
    size_t track_count, track_cap;
    st_uav_t uavs[ST_UAVS_MAX];
    st_intercept_t intercepts[ST_UAVS_MAX];
    st_sensor_mode_t sensor_modes[ST_UAVS_MAX];
    cgs_entities_t *truth;
    bool has_image;
    bool image_shown;           // st_state_image_shown was told of a frame
    uint64_t image_shown_frame; // that frame
    uint32_t image_uav;
    uint64_t image_frame;
    int image_mode;
    bool image_target_in_view;
    char image_path[ST_PATH_MAX];
    bool has_image_fp;          // the image UAV's newest footprint, from its `image` messages
    double image_fp[8];         // its corners, east/north metres, as the message gives them
    uint64_t image_fp_frame;    // the frame it is of
    bool has_video;             // video of the picture's UAV is relayed (not stale)
    bool video_ever;            // some video was relayed since start
    uint32_t video_uav;         // the UAV whose video is relayed
    uint64_t video_epoch;       // its publisher's epoch (0 unknown)
    uint64_t video_frames;      // frames of it relayed
    double video_heard_s;       // simulation time of its newest frame
    double video_t_s;           // its frame's own simulation time (NAN: none yet)
    double video_period_s;      // simulation seconds between its frames, smoothed (0 unknown)
    double time_scale;          // the clock's: simulation seconds per wall second (0 unknown)
    bool paused;                // the clock's
    struct json_object *replay; // a replay's position and marks, as the page gets it (NULL: live)
    uint32_t replay_generation;
};

/* The track of that id, or NULL. */
st_track_t *st_state__track_find (st_state_t *self, uint32_t id);

#endif
