/* trk_params — trackerd's parameter file: an ASCII INI file read at start
 * with documented defaults (deploy/params/tracker.ini): the filter (the
 * paper's σ_meas and σ_mod per axis, the nominal scan interval, the paper's
 * constant gains or a full Kalman filter), association (gate, M of N,
 * misses to delete, hit history), identity from BCIS and turn detection.
 * Every value is range-checked and the set for consistency; every error
 * names the file, the line, the section and key, and what was expected.
 * Pure: no logging, no globals.
 *
 * Sections: [filter], [detection], [association], [identity], [turn]. */
#ifndef TRK_PARAMS_H
#define TRK_PARAMS_H

#include "trk_filter.h"
#include "trk_imm.h"
#include "trk_pd.h"

#include <stdbool.h>
#include <stddef.h>

#define TRK_HISTORY_MAX 64 // most scans of hit history a track can keep

typedef enum {
    TRK_NOISE_PARAMETERS = 0, // R = diag(σ_meas_x², σ_meas_y²), the paper's
    TRK_NOISE_HIT = 1,        // R from each hit's range and azimuth standard deviations
} trk_noise_t;

typedef struct {
    trk_filter_params_t filter;
    trk_noise_t measurement_noise; // which R the covariance, gates and Kalman gains use
    double gate_probability;       // probability that a track's own hit falls in its gate
    double max_speed_mps;          // fastest target: sizes a one-hit track's gate
    double maneuver_accel_mps2;    // a target may accelerate this much between hits: widens gates
    bool radial_velocity;          // use the hits' radial velocity in association
    double radial_sigma_mps;       // its standard deviation
    double radial_span_mps;        // unambiguous span (λ·PRF/2); 0: no ambiguity
    int confirm_m, confirm_n;      // confirm with M hits in the last N scans
    int delete_misses;             // consecutive misses that delete a confirmed track
    int history_scans;             // scans of hit history kept per track
    double bcis_sigma_m;           // σ of a BCIS reply's position fix per axis, when it gives none
    double identity_min_probability;   // a reply marks a track at least this likely its responder
    double identity_untracked_per_km2; // density of responders no track follows
    double identity_timeout_s;         // friendly for this long after the last reply
    double turn_threshold_deg;         // τ = cos(turn_threshold_deg)
    double turn_min_speed_mps;         // no turn detection below this estimated speed
    int turn_settle_updates;           // updates after initiation before turns are looked for
    // The IMM tracker (mode = imm).
    trk_imm_params_t imm;         // its models (σ_cv: the larger of filter.sigma_mod_mps2)
    bool radial_update;           // the filter takes the hits' radial velocity too
    trk_pd_params_t detection;    // what the radar can see ([detection]; span: radial_span_mps)
    double false_alarms_per_scan; // when the radar does not say (clutter density of the costs)
    int hypotheses;               // joint association hypotheses weighed per cluster (k best)
    double delete_existence;      // a confirmed track whose existence falls below this is deleted
    double lifetime_s;            // mean time a moving target stays in the scene
    double stopped_lifetime_s;    // ... a stopped one, unseen, is believed to
    double max_sigma_m;           // a coasting track this vague (largest position σ) is deleted
    double continue_window_s;     // a new track may continue one deleted this long before
    double continue_probability;  // the least probability that names it as continued
    double birth_density;         // new targets per m² against which continuation is weighed
} trk_params_t;

/* The defaults (deploy/params/tracker.ini documents each). */
void trk_params_defaults (trk_params_t *p);
/* Read a parameter file over the values in *p (usually the defaults); on
 * error *p is unchanged. 0, or a negative errno with err filled. */
int trk_params_load (const char *path, trk_params_t *p, char *err, size_t errlen);
/* The same from text (name stands for the file name in errors). */
int trk_params_load_string (const char *name, const char *text, trk_params_t *p, char *err,
                            size_t errlen);
/* Check a set built in code; 0 or -EINVAL with err filled. */
int trk_params_check (const trk_params_t *p, char *err, size_t errlen);
/* The filter mode's name in the parameter file ("paper", "kalman", "imm"). */
const char *trk_params_mode_name (trk_filter_mode_t mode);
/* The chi-square gate G of two degrees of freedom: −2 ln(1 − P_G). */
double trk_params_gate (const trk_params_t *p);
/* The gate of three (position and radial velocity): the χ²₃ quantile of P_G. */
double trk_params_gate3 (const trk_params_t *p);

#endif
