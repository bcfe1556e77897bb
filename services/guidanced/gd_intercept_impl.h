/* gd_intercept_impl — the intercept's state, for gd_intercept.c (the
 * model) and gd_checkpoint.c (its checkpoint) only: every other file sees
 * gd_intercept_t as opaque. */
#ifndef GD_INTERCEPT_IMPL_H
#define GD_INTERCEPT_IMPL_H

#include "gd_intercept.h"

#define GD_SAMPLES 3 // moments of an overflight kept for its confirmation

/* One moment of an overflight: the footprint then. */
typedef struct {
    double t_s;
    gd_footprint_t fp;
} gd_sample_t;

struct gd_intercept {
    gd_params_t p;
    const cgs_terrain_t *terrain;
    gd_method_t method;
    uint32_t scale;
    // The UAV.
    bool have_uav;
    gd_uav_t uav;
    bool have_fp;
    gd_footprint_t fp;
    // The designation.
    gd_phase_t phase;
    uint32_t track_id;
    uint64_t designation_number;
    double designation_s;
    bool have_track;
    gd_track_t track;
    bool need_plan;
    bool orphan;        // its track was deleted: waiting for a new track of the target
    uint32_t orphan_id; // the deleted track
    int last_status;    // of the designated track's latest update
    double heard_hit_s; // its newest hit heard (held or not)
    double heard_s;     // its latest update heard (held or not)
    bool holding;       // a hit after a coast is held until another confirms it
    gd_track_t held;    // that update (no history)
    // The plan.
    bool has_plan;
    gd_waypoint_t wp;
    double plan_s;
    double plan_airspeed_mps, plan_agl_m; // the commanded airspeed and height it was made for
    size_t i_second, i_waypoint;          // their indices in the task's points
    size_t progress;                      // the route point the UAV flies to next
    // Precision approach and overflight.
    gd_v2_t p_close;
    double close_s;
    bool inside, was_inside;
    double overflight_s;
    double out_since_s;
    bool confirming; // out of the footprint: waiting for a hit to confirm the overflight
    size_t n_samples;
    gd_sample_t samples[GD_SAMPLES]; // entering, nearest the centre, latest inside
    double best_d;                   // predicted target to the footprint's centre at samples[1]
    uint32_t replans;
    double time_to_go_s;
    char reason[256];
    uint64_t changes; // reasons given: gd_intercept_changes
    gd_task_t task;
};

#endif
