/* trk_mc — Monte Carlo runs of the tracker on synthetic hits, for the tests
 * and `trackerd --monte-carlo`: many targets at once, 5 km apart on one
 * heading (so they keep their spacing), each hit
 * once a scan at its own time within the scan with Gaussian measurement
 * noise and no false alarms; the real tracker (association, filter, turn
 * detection) processes them. Pure: seeded, no logging. */
#ifndef TRK_MC_H
#define TRK_MC_H

#include "trk_params.h"

#include <stddef.h>
#include <stdint.h>

typedef struct {
    size_t targets;      // run at once, 5 km apart
    size_t scans;        // scans in all
    size_t settle_scans; // scans before errors (or false turns) are counted
    double speed_mps;
    double sigma_meas_m[2]; // the hits' true noise per axis (east, north)
    size_t turn_scan;       // 0: straight lines; else each target turns once,
                            // at a random time between its hits of scans
                            // turn_scan − 1 and turn_scan (numbered from 0)
    double turn_deg;        // the turn (its side is random per target)
    uint64_t seed;
} trk_mc_config_t;

typedef struct {
    size_t samples;       // estimates compared with the truth
    double rmse_pos_m[2]; // per axis (east, north)
    double rmse_vel_mps[2];
    size_t lost; // a target's track changed id after settling
    // With a turn:
    size_t straight_scans; // target-scans on the straight leg after settling
    size_t false_turns;    // turns flagged on them
    size_t turns;          // targets that turned
    size_t detected;       // flagged at the first or second hit after the turn
    size_t completed;      // targets whose turn completed before the run ended (first completion)
    size_t right_side;     // completed turns whose angle has the true turn's sign
    double angle_mean_deg; // mean |angle| of the completed turns
    double angle_sd_deg;
} trk_mc_result_t;

/* Run; 0, -EINVAL on a bad configuration, -ENOMEM. */
int trk_mc_run (const trk_params_t *p, const trk_mc_config_t *cfg, trk_mc_result_t *ret);

#endif
