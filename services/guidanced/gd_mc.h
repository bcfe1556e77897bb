/* gd_mc — Monte Carlo runs of whole intercepts: the cores of uavsim (the
 * UAV's flight model and a ground vehicle), mtid (the MTI radar), trackerd
 * (the tracker) and guidanced (the intercept) wired together in one
 * process, in lockstep, with no sockets. Each run is a random geometry: the
 * UAV 5 to 9 km from the target in any direction with any heading (so both
 * signs of y'_u occur), target speed 5 to 20 m/s on any heading, and in a
 * share of the runs a turn of 45 to 120 degrees (either side) some time
 * after the designation. The radar and tracker run from the start; the
 * track nearest the target is designated once one is confirmed (after a
 * pre-roll); a geometry with no confirmed track of the target within 60 s
 * of the pre-roll is drawn again (and counted), so every run is a whole
 * intercept; the UAV flies the tasks the intercept gives it. Each geometry
 * has its own radar noise, both from the seed and its number alone, so any
 * run can be repeated by itself (gd_mc_trace). Each run is
 * judged from ground truth (gd_score): was the target inside the true
 * footprint at some moment before the time limit. Flat ground. Pure:
 * seeded, no logging (progress through a callback). */
#ifndef GD_MC_H
#define GD_MC_H

#include "gd_intercept.h"

#include <stddef.h>
#include <stdint.h>

typedef struct {
    size_t runs; // whole intercepts wanted
    uint64_t seed;
    gd_method_t method;
    double range_min_m, range_max_m;           // UAV from the target at designation
    double speed_min_mps, speed_max_mps;       // target speed
    double turn_fraction;                      // share of runs whose target turns
    double turn_min_deg, turn_max_deg;         // its turn
    double turn_after_min_s, turn_after_max_s; // when, after the designation
    double preroll_s;                          // radar and tracker run this long before designating
    double limit_s;                            // a run ends this long after the designation
} gd_mc_config_t;

/* One moment of a traced run (every second of simulation time after the
 * designation, and at each change of phase). */
typedef struct {
    double t_s;
    gd_v2_t target; // ground truth
    gd_v2_t target_vel;
    bool has_track; // the designated track's latest update
    uint32_t track_id;
    gd_v2_t track_pos; // predicted to t_s
    gd_v2_t track_vel;
    gd_v2_t uav;
    double uav_heading_deg;
    const gd_status_t *status;
    const gd_track_t *nearby; // other confirmed or coasting tracks within 3 km of the target
    size_t nearby_count;
} gd_mc_sample_t;

typedef void (gd_mc_trace_fn) (void *arg, const gd_mc_sample_t *s);

/* One run's outcome. */
typedef struct {
    size_t index;    // the geometry's number (gd_mc_trace repeats it)
    bool designated; // a confirmed track of the target existed in time
    bool imaged;     // inside the true footprint at some moment
    bool ahead;      // first plan's y'_u > 0
    bool turned;     // the target turned
    double speed_mps;
    double turn_deg;  // signed, clockwise positive; 0 without a turn
    double closest_m; // closest distance of the target to the footprint centre
    double miss_m;    // closest distance to the footprint (0 when imaged)
    double time_to_image_s;
    uint32_t replans;
    int final_phase; // gd_phase_t at the end
} gd_mc_run_t;

typedef struct {
    size_t drawn;      // geometries drawn
    size_t designated; // of them with a confirmed track of the target in time: the runs
    size_t imaged;
    size_t ahead, ahead_imaged, behind, behind_imaged;
    size_t turned, turned_imaged, straight, straight_imaged;
    double closest_p50_m, closest_p90_m, closest_p95_m, closest_max_m; // of every designated run
    double miss_p95_m, miss_p99_m, miss_max_m;
    double time_to_image_p50_s, time_to_image_p95_s;
    double replans_mean;
} gd_mc_result_t;

/* Fill c with the defaults: 200 runs, seed 1, head-on, 5–9 km, 5–20 m/s,
 * half the runs turning 45–120° 20–120 s after designation, 90 s pre-roll,
 * 1500 s limit. */
void gd_mc_defaults (gd_mc_config_t *c);

/* Progress: called after each geometry with the number of whole intercepts
 * so far and its outcome (run->designated false: it is drawn again). */
typedef void (gd_mc_progress_fn) (void *arg, size_t done, const gd_mc_run_t *run);

/* Run them: geometries are drawn until c->runs of them were designated (at
 * most 2·runs + 50 draws; ret->designated tells how many were). runs_out
 * (may be NULL) receives each designated run's outcome (up to c->runs).
 * 0, -EINVAL (bad configuration), -ENOMEM. */
int gd_mc_run (const gd_mc_config_t *c, gd_mc_run_t *runs_out, gd_mc_progress_fn *progress,
               void *arg, gd_mc_result_t *ret);

/* Geometries gd_mc_run draws at most for c: 2·runs + 50 (a set where most
 * draw no confirmed track is broken, not unlucky). */
size_t gd_mc_draw_cap (const gd_mc_config_t *c);

/* Run only geometry number `run` (from 0; gd_mc_run_t.index) of the set c describes, exactly as
 * gd_mc_run would, calling fn with its samples. 0, -EINVAL, -ENOMEM. */
int gd_mc_trace (const gd_mc_config_t *c, size_t run, gd_mc_trace_fn *fn, void *arg,
                 gd_mc_run_t *ret);

/* `guidanced --monte-carlo [options]`: runs and prints text and a JSON line. */
int gd_mc_main (int argc, char **argv);

#endif
