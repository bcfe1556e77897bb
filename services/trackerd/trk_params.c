/* trk_params — trackerd's parameter file (see trk_params.h). */
#include "trk_params.h"
#include "cgs_config.h"

#include <errno.h>
#include <gsl/gsl_cdf.h>
#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <strings.h>

#define S_DT_NOMINAL_S 10 // a revolution at 36 deg/s: the nominal scan until the radar's says

void trk_params_defaults (trk_params_t *p)
{
    *p = (trk_params_t){
        .filter =
            {
                .mode = TRK_FILTER_IMM,
                .sigma_meas_m = {25, 25},
                .sigma_mod_mps2 = {0.2, 0.2},
                .dt_s = S_DT_NOMINAL_S,
                .dt_auto = true,
            },
        .measurement_noise = TRK_NOISE_HIT,
        .gate_probability = 0.999,
        .max_speed_mps = 30,
        .maneuver_accel_mps2 = 3,
        .radial_velocity = true,
        .radial_sigma_mps = 0.5,
        .radial_span_mps = 46.875,
        .confirm_m = 3,
        .confirm_n = 4,
        .delete_misses = 3,
        .history_scans = 20,
        .bcis_sigma_m = 10,
        .identity_min_probability = 0.9,
        .identity_untracked_per_km2 = 1,
        .identity_timeout_s = 20,
        .turn_threshold_deg = 20,
        .turn_min_speed_mps = 3,
        .turn_settle_updates = 3,
        .imm =
            {
                .sigma_mps2 = {0.2, 1.5},
                .stopped_sigma_mps = 0.05,
                .sojourn_s = {200, 20, 60},
                .exit = {{0, 0.6, 0.4}, {0.8, 0, 0.2}, {0.4, 0.6, 0}},
            },
        .radial_update = true,
        .detection =
            {
                .pd = 0.995,
                .half_range_m = 11800,
                .range_exponent = 10.8,
                .mdv_along_mps = 0.58,
                .mdv_across_mps = 1.8,
                .width_mps = 0.2,
                .span_mps = 46.875,
                .min_range_m = 500,
                .max_range_m = 20000,
            },
        .false_alarms_per_scan = 5,
        .hypotheses = 16,
        .delete_existence = 0.1,
        .lifetime_s = 3600,
        .stopped_lifetime_s = 120,
        .max_sigma_m = 1000,
        .continue_window_s = 300,
        .continue_probability = 0.5,
        .birth_density = 1e-8,
    };
}

#define S_R(sec, k, field, lo, hi)                                                                 \
    {                                                                                              \
        sec, k, offsetof (trk_params_t, field), lo, hi                                             \
    }
static const cgs_config_real_t s_reals[] = {
    S_R ("filter", "sigma_meas_x_m", filter.sigma_meas_m[0], 0.01, 1e5),
    S_R ("filter", "sigma_meas_y_m", filter.sigma_meas_m[1], 0.01, 1e5),
    S_R ("filter", "sigma_mod_x_mps2", filter.sigma_mod_mps2[0], 1e-6, 100),
    S_R ("filter", "sigma_mod_y_mps2", filter.sigma_mod_mps2[1], 1e-6, 100),
    S_R ("association", "gate_probability", gate_probability, 0.5, 0.999999),
    S_R ("association", "max_speed_mps", max_speed_mps, 0.1, 1000),
    S_R ("association", "maneuver_accel_mps2", maneuver_accel_mps2, 0, 1000),
    S_R ("association", "radial_sigma_mps", radial_sigma_mps, 0.001, 1000),
    S_R ("association", "radial_span_mps", radial_span_mps, 0, 1e5),
    S_R ("filter", "sigma_maneuver_mps2", imm.sigma_mps2[1], 1e-6, 100),
    S_R ("filter", "stopped_sigma_mps", imm.stopped_sigma_mps, 1e-6, 100),
    S_R ("filter", "cv_sojourn_s", imm.sojourn_s[0], 0.1, 1e6),
    S_R ("filter", "maneuver_sojourn_s", imm.sojourn_s[1], 0.1, 1e6),
    S_R ("filter", "stopped_sojourn_s", imm.sojourn_s[2], 0.1, 1e6),
    S_R ("detection", "pd", detection.pd, 0.01, 1),
    S_R ("detection", "half_range_m", detection.half_range_m, 1, 1e7),
    S_R ("detection", "range_exponent", detection.range_exponent, 0.1, 40),
    S_R ("detection", "mdv_along_mps", detection.mdv_along_mps, 0, 1000),
    S_R ("detection", "mdv_across_mps", detection.mdv_across_mps, 0, 1000),
    S_R ("detection", "mdv_width_mps", detection.width_mps, 0.001, 1000),
    S_R ("detection", "min_range_m", detection.min_range_m, 0, 1e7),
    S_R ("detection", "max_range_m", detection.max_range_m, 1, 1e7),
    S_R ("detection", "false_alarms_per_scan", false_alarms_per_scan, 1e-6, 1e7),
    S_R ("association", "delete_existence", delete_existence, 1e-6, 0.9),
    S_R ("association", "lifetime_s", lifetime_s, 1, 1e9),
    S_R ("association", "stopped_lifetime_s", stopped_lifetime_s, 1, 1e9),
    S_R ("association", "max_sigma_m", max_sigma_m, 1, 1e7),
    S_R ("association", "continue_window_s", continue_window_s, 0, 86400),
    S_R ("association", "continue_probability", continue_probability, 0.01, 1),
    S_R ("association", "birth_density", birth_density, 1e-15, 1),
    S_R ("identity", "bcis_sigma_m", bcis_sigma_m, 0.01, 1e5),
    S_R ("identity", "min_probability", identity_min_probability, 0, 1),
    S_R ("identity", "untracked_per_km2", identity_untracked_per_km2, 0, 1e6),
    S_R ("identity", "timeout_s", identity_timeout_s, 0.01, 86400),
    S_R ("turn", "threshold_deg", turn_threshold_deg, 0.1, 179),
    S_R ("turn", "min_speed_mps", turn_min_speed_mps, 0, 1000),
};
#undef S_R

static const cgs_config_int_t s_ints[] = {
    {"association", "confirm_m", offsetof (trk_params_t, confirm_m), 1, 32},
    {"association", "confirm_n", offsetof (trk_params_t, confirm_n), 1, 32},
    {"association", "delete_misses", offsetof (trk_params_t, delete_misses), 1, 1000},
    {"association", "history_scans", offsetof (trk_params_t, history_scans), 1, TRK_HISTORY_MAX},
    {"association", "hypotheses", offsetof (trk_params_t, hypotheses), 1, 1000},
    {"turn", "settle_updates", offsetof (trk_params_t, turn_settle_updates), 0, 1000},
};

#define S_NREALS (sizeof s_reals / sizeof s_reals[0])
#define S_NINTS  (sizeof s_ints / sizeof s_ints[0])

static const char *const s_mode_names[] = {"paper", "kalman", "imm", NULL};
static const char *const s_noise_names[] = {"parameters", "hit", NULL};

/* The consistency of the set, after each value's own range. cfg (may be
 * NULL) places the error on the key's line. */
static int s_check (cgs_config_t *cfg, const trk_params_t *p, char *err, size_t errlen)
{
    const char *sec = NULL, *key = NULL;
    char msg[256] = "";
    cgs_config_table_out_of_range (s_reals, S_NREALS, s_ints, S_NINTS, p, &sec, &key, msg,
                                   sizeof msg);
    if (key) {
    } else if (!(p->filter.dt_s >= 0.01 && p->filter.dt_s <= 3600)) {
        sec = "filter", key = "scan_period_s";
        snprintf (msg, sizeof msg, "expected auto or a number in [0.01, 3600], got %.15g",
                  p->filter.dt_s);
    } else if (p->confirm_m > p->confirm_n) {
        sec = "association", key = "confirm_m";
        snprintf (msg, sizeof msg, "must be at most confirm_n (%d), got %d", p->confirm_n,
                  p->confirm_m);
    } else if ((unsigned)p->filter.mode > TRK_FILTER_IMM) {
        sec = "filter", key = "mode";
        snprintf (msg, sizeof msg, "expected paper, kalman or imm, got value %d",
                  (int)p->filter.mode);
    } else if (p->detection.min_range_m >= p->detection.max_range_m) {
        sec = "detection", key = "min_range_m";
        snprintf (msg, sizeof msg, "must be below max_range_m (%g), got %g",
                  p->detection.max_range_m, p->detection.min_range_m);
    } else if ((unsigned)p->measurement_noise > TRK_NOISE_HIT) {
        sec = "filter", key = "measurement_noise";
        snprintf (msg, sizeof msg, "expected parameters or hit, got value %d",
                  (int)p->measurement_noise);
    }
    return key ? cgs_config_value_error (cfg, sec, key, msg, err, errlen) : 0;
}

int trk_params_check (const trk_params_t *p, char *err, size_t errlen)
{
    return s_check (NULL, p, err, errlen);
}

static int s_read (cgs_config_t *cfg, void *arg, char *err, size_t errlen)
{
    trk_params_t *out = arg, p = *out;
    int rc = cgs_config_check_repeated (cfg, err, errlen);
    if (rc == 0)
        rc = cgs_config_get_table (cfg, s_reals, S_NREALS, s_ints, S_NINTS, &p, err, errlen);
    // The paper's gains: per update from the radar's revisit (auto), or fixed.
    const char *period = NULL;
    if (rc == 0)
        rc = cgs_config_get_string (cfg, "filter", "scan_period_s", NULL, &period, err, errlen);
    if (rc == 0 && period && strcasecmp (period, "auto") == 0) {
        p.filter.dt_auto = true;
        p.filter.dt_s = S_DT_NOMINAL_S; // until the radar's scans say
    } else if (rc == 0 && period) {
        p.filter.dt_auto = false;
        char *end = NULL;
        double v = strtod (period, &end);
        if (end == period || *end || !(v >= 0.01 && v <= 3600))
            rc = cgs_config_error (cfg, "filter", "scan_period_s", 0, err, errlen,
                                   "expected auto or a number in [0.01, 3600], got '%s'", period);
        else
            p.filter.dt_s = v;
    }
    int mode = p.filter.mode, noise = p.measurement_noise;
    if (rc == 0)
        rc = cgs_config_get_enum (cfg, "filter", "mode", s_mode_names, mode, &mode, err, errlen);
    // A file that names the mode but not the noise gets the mode's own: each
    // hit's covariance for imm, the paper's constant one for paper and kalman.
    if (rc == 0 && cgs_config_has (cfg, "filter", "mode"))
        noise = mode == TRK_FILTER_IMM ? TRK_NOISE_HIT : TRK_NOISE_PARAMETERS;
    if (rc == 0)
        rc = cgs_config_get_enum (cfg, "filter", "measurement_noise", s_noise_names, noise, &noise,
                                  err, errlen);
    if (rc == 0)
        rc = cgs_config_get_bool (cfg, "association", "radial_velocity", p.radial_velocity,
                                  &p.radial_velocity, err, errlen);
    if (rc == 0)
        rc = cgs_config_get_bool (cfg, "filter", "radial_update", p.radial_update, &p.radial_update,
                                  err, errlen);
    if (rc == 0)
        rc = cgs_config_check_unused (cfg, err, errlen);
    if (rc < 0)
        return rc;
    p.imm.sigma_mps2[0] = p.filter.sigma_mod_mps2[0];
    p.detection.span_mps = p.radial_span_mps;
    p.filter.mode = (trk_filter_mode_t)mode;
    p.measurement_noise = (trk_noise_t)noise;
    if ((rc = s_check (cfg, &p, err, errlen)) < 0)
        return rc;
    *out = p;
    return 0;
}

int trk_params_load (const char *path, trk_params_t *p, char *err, size_t errlen)
{
    return cgs_config_read (path, NULL, s_read, p, err, errlen);
}

int trk_params_load_string (const char *name, const char *text, trk_params_t *p, char *err,
                            size_t errlen)
{
    return cgs_config_read (name, text, s_read, p, err, errlen);
}

const char *trk_params_mode_name (trk_filter_mode_t mode)
{
    return (unsigned)mode <= TRK_FILTER_IMM ? s_mode_names[mode] : "?";
}

double trk_params_gate (const trk_params_t *p)
{
    return -2 * log1p (-p->gate_probability);
}

double trk_params_gate3 (const trk_params_t *p)
{
    return gsl_cdf_chisq_Pinv (p->gate_probability, 3);
}
