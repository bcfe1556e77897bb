/* gd_params — guidanced's parameter file: an ASCII INI file read at start
 * with documented defaults (deploy/params/guidance.ini). Every value is
 * range-checked; every error names the file, the line, the section and key,
 * and what was expected. Pure: no logging, no globals.
 *
 * Sections: [plan], [replan], [approach], [designation], [footprint]. */
#ifndef GD_PARAMS_H
#define GD_PARAMS_H

#include <stddef.h>

/* How t_pred is timed. */
typedef enum {
    GD_TIMING_ROUTE = 0, // the flyable route's time, through P_2 when it has one (default)
    GD_TIMING_ARC = 1,   // the paper's equation 1: the arc straight to the target
} gd_timing_t;

/* Where equation 3 puts the secondary waypoint P_2 (gd_geom.h). */
typedef enum {
    GD_SECONDARY_EXTENDED = 0, // the UAV's offset kept, k·|y'_u| (at least lead_in_m) ahead
    GD_SECONDARY_PAPER = 1,    // the paper's projection: abeam the waypoint, no lead-in (default)
} gd_secondary_t;

/* Who may take over a deleted designated track from a tracker that links
 * successors itself (TrackBatch.links_continuation). */
typedef enum {
    GD_HANDOVER_NEAR,  // its links first, then a new track near the prediction
    GD_HANDOVER_LINKS, // its links alone
} gd_handover_t;

typedef struct {
    // [plan]
    gd_timing_t timing;
    double turn_radius_factor;     // planning radius = this × the UAV's smallest turn radius
    gd_secondary_t secondary;      // equation 3 as the paper has it, or extended
    double secondary_scale;        // extended: k of Δ = Rᵀ·diag(1, −k)·R
    double lead_in_m;              // extended: least distance of P_2 ahead of the waypoint
    double secondary_offset_max_m; // P_2 at most this far abeam the target's line (0: no bound)
    double settle_m;               // straight run into the waypoint after the last turn, metres
    double horizon_s;              // t_pred at most this: the prediction horizon, seconds
    double runout_m;               // route goes on this far past the target's meeting point
    double arc_step_deg;           // turns are sent as route points this many degrees apart
    double min_target_speed_mps;   // slower targets are taken as standing still
    double max_target_speed_mps;   // a track faster than this has a broken velocity: not used
    // [replan]
    double threshold_deg; // re-plan when the target's direction changed by more
    double offset_m;      // re-plan when the target left the planned line by more
    double significance;  // ... and by more than this many of the track's standard deviations
    // [approach]
    double align_deg;           // on final approach: heading within this of the target's reverse
    double lost_after_s;        // no update of the designated track for this long: lost
    double handover_m;          // a deleted track's target is taken up by a new track this near
    double handover_growth_mps; // ... plus this much per second since its last update
    gd_handover_t handover;  // near: nearness hands over too; links: a linking tracker's word alone
    double confirm_margin_m; // an overflight counts when the target's hit, carried back to
                             // it, lies within this of the footprint
    // [designation]
    double pick_radius_m; // a designation by point takes a track whose newest hit is this near
    // [footprint]
    double max_range_m; // a sensor ray that meets no ground within this is cut there
} gd_params_t;

/* The defaults (deploy/params/guidance.ini documents each). */
void gd_params_defaults (gd_params_t *p);
/* Read a parameter file over *p; on error *p is unchanged. 0, or a
 * negative errno with err filled ("file:line: [section] key: ..."). */
int gd_params_load (const char *path, gd_params_t *p, char *err, size_t errlen);
/* The same from text (name stands for the file name in errors). */
int gd_params_load_string (const char *name, const char *text, gd_params_t *p, char *err,
                           size_t errlen);
/* Check a set built in code; 0 or -EINVAL with err filled. */
int gd_params_check (const gd_params_t *p, char *err, size_t errlen);

#endif
