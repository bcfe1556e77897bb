/* ls_mc — Monte Carlo runs of one whole scene in lockstep (ls_run): run i
 * of a set is the scene with its own variation, drawn from the set's seed
 * and i alone (so any run can be repeated by itself): the exercise seed
 * (radar noise, BCIS, vehicle wander), a shift of the operator's
 * designation times uniform in ±spread, and the UAVs' start point on their
 * loiter orbits, uniform in bearing. Runs go to several processes when
 * asked (fork: FFTW's planner is not thread-safe); the results are the same
 * bytes whatever the number of processes, pooled in the order of the runs. */
#ifndef LS_MC_H
#define LS_MC_H

#include "ms_gospa.h"
#include "ms_siap.h"

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

typedef struct {
    const char *exercise_path; // required
    const char *scenario_path; // NULL: the exercise's
    size_t runs;               // at least 1
    uint64_t seed;             // the set's seed
    double spread_s;           // designation time shift, uniform in ±spread_s (default 30)
    double limit_s;            // per run, as ls_run (<= 0: its default)
    int jobs;                  // processes (1: this one)
    bool seeds_only;           // run i is the scene as it stands with exercise seed seed + i
                               // (no shift, no start point drawn): as `mscgs run` runs it
    FILE *timeline;            // ls_mc_one: CSV rows of the run (LS_MC_TIMELINE_HEADER), or NULL
} ls_mc_config_t;

/* The columns of a run's timeline: kind is entity (a vehicle or a UAV, once
 * a second), truth (the radar's truth of a vehicle in its beam: radial
 * velocity in ve, detected or missed in status, its hit id in hits, the
 * model's Pd in pd, "masked" in note when terrain hid it, "merged" when
 * another target's echo in its range-Doppler cell stood for it), track (one per
 * track of a batch: continues and its probability, existence, the Pd the
 * tracker expected, position standard deviation sd, the stopped mode's
 * probability) or intercept (the designated track in id, the state
 * number of InterceptState in status). */
#define LS_MC_TIMELINE_HEADER                                                                      \
    "kind,t,id,e,n,ve,vn,status,hits,misses,continues,cont_p,existence,pd,sd,p_stopped,note"

/* Why a run did not image the designated vehicle. */
typedef enum {
    LS_MC_IMAGED = 0,
    LS_MC_NOT_DESIGNATED, // no track qualified for the operator's designation
    LS_MC_WRONG_VEHICLE,  // the designated track ended up following another vehicle
    LS_MC_LOST,           // the intercept ended LOST (track deleted or not updated)
    LS_MC_MISSED,         // the footprint passed the vehicle by
    LS_MC_UNFINISHED,     // the time limit came first
} ls_mc_outcome_t;

/* One run's result. */
typedef struct {
    size_t index;
    int rc; // 0, or the negative errno the run failed with (first_error says why)
    uint64_t exercise_seed;
    double designation_shift_s;
    double uav_phase_deg;
    ls_mc_outcome_t outcome;
    bool designated, imaged, wrong_vehicle, lost;
    double miss_m;          // distance of the vehicle from the footprint at closest (0 imaged)
    double closest_m;       // from the footprint centre
    double time_to_image_s; // designation to first inside (NaN when not imaged)
    double end_s;           // simulation time the run ended
    uint32_t replans;
    uint32_t target_entity_id;
    uint32_t other_entity_id; // wrong vehicle: the one the designated track follows instead
    double other_since_s;     // its hits of that vehicle since (NaN when none)
    double other_unseen_s;    // the track's time without a hit before the first of them
    double other_gap_m;       // that first hit's distance from the designated vehicle
    char final_state[16];
    uint64_t bad_inputs, errors, failures; // 0 in a sound run
    char first_error[128];
    ms_siap_result_t siap; // this run's tracking figures (raw counts pool)
    ms_gospa_mean_t gospa; // this run's GOSPA sums
} ls_mc_run_t;

/* The set's pooled result. */
typedef struct {
    size_t runs, designated, imaged, wrong_vehicle, lost, not_designated, unfinished;
    double imaged_pct, imaged_lo_pct, imaged_hi_pct; // and its 95% (Clopper-Pearson) interval
    double miss_p50_m, miss_p95_m;                   // over the runs not imaged... and all
    double time_to_image_p50_s, time_to_image_p95_s;
    ms_gospa_avg_t gospa;  // mean per scan over every run
    ms_siap_result_t siap; // counts summed over the runs, figures from the sums
    uint64_t bad_inputs, errors, failures;
} ls_mc_result_t;

/* The variation of run i of a set (its exercise seed, designation shift and
 * UAV start bearing, NaN when the scenario's start stands). */
void ls_mc_variation (const ls_mc_config_t *c, size_t i, uint64_t *ret_seed, double *ret_shift_s,
                      double *ret_phase_deg);
/* Run i alone, its adapters' log lines to log (may be NULL); 0 or a
 * negative errno with the reason in err. */
int ls_mc_one (const ls_mc_config_t *c, size_t i, FILE *log, ls_mc_run_t *ret, char *err,
               size_t errlen);
/* Called as runs finish (in any order), with how many are done. */
typedef void (ls_mc_progress_fn) (void *arg, size_t done, const ls_mc_run_t *run);
/* Every run of the set into runs[0..c->runs) (in index order), pooled into
 * *ret; 0 or a negative errno with the reason in err. */
int ls_mc_run (const ls_mc_config_t *c, ls_mc_run_t *runs, ls_mc_progress_fn *progress, void *arg,
               ls_mc_result_t *ret, char *err, size_t errlen);
/* The outcome's name ("imaged", "wrong-vehicle", ...). */
const char *ls_mc_outcome_name (ls_mc_outcome_t o);

#endif
