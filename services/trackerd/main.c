/* trackerd — tracks from the MTI hits of every radar (`mti`, one radar scan
 * at a time, closed by `mti.scan`), identity from BCIS replies (`bcis`);
 * publishes every track of a radar after each of its scans (`track`) and
 * each turn the filter sees (`track.turn`). Tracks are checkpointed in the
 * state folder, so their ids outlive a restart. `trackerd --monte-carlo`
 * runs the tracker on synthetic targets instead. The tracker is in
 * trk_*.c, and what is done to its inputs and outputs in trk_adapter.c;
 * this file wires the adapter to the bus and keeps the checkpoint file. */
#include "cgs_lifecycle.h"
#include "cgs_log.h"
#include "cgs_service.h"
#include "cgs_util.h"
#include "cgs_state.h"
#include "trk_adapter.h"
#include "trk_checkpoint.h"
#include "trk_mc.h"
#include "trk_params.h"
#include "trk_tracker.h"

#include <errno.h>
#include <getopt.h>
#include <gsl/gsl_errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define S_CHECKPOINT_S   1.0        // at most one checkpoint write per wall-clock second
#define S_CHECKPOINT_MAX (1u << 30) // a checkpoint file larger than this is refused

typedef struct {
    cgs_service_t *svc;
    trk_params_t params;
    trk_adapter_t *adapter; // scans, the tracker, the output messages
    bool fresh;             // --fresh: ignore the checkpoint
    char checkpoint[4200];
    bool unsaved; // tracks changed since the last checkpoint written
    // The exercise's scenario and its terrain, when it names one: the IMM
    // tracker expects nothing of a target the terrain hides.
    cgs_geo_t *frame;
    cgs_scenario_t *scenario;
    cgs_terrain_t *terrain;
} s_app_t;

/* A message of one of the adapter's topics. */
static void s_on_message (void *arg, const char *topic, const ProtobufCMessage *msg,
                          const Cgs__Header *hdr)
{
    s_app_t *app = arg;
    trk_adapter_on_message (app->adapter, topic, msg, hdr);
}

/* ---- checkpoint ----------------------------------------------------------------------- */

/* The adapter's tracker. */
static trk_tracker_t *s_trk (s_app_t *app)
{
    return trk_adapter_tracker (app->adapter);
}

/* Write the checkpoint now; 0, or -errno (the health's last error). */
static int s_checkpoint (s_app_t *app)
{
    uint8_t *buf;
    size_t len;
    int rc = trk_checkpoint_save (s_trk (app), &buf, &len);
    if (rc == 0) {
        rc = cgs_state_write (app->checkpoint, buf, len);
        free (buf);
    }
    if (rc < 0) {
        char why[4400];
        snprintf (why, sizeof why, "cannot write %s: %s", app->checkpoint, strerror (-rc));
        cgs_health_set_error (cgs_service_health (app->svc), why);
        return rc;
    }
    app->unsaved = false;
    return 0;
}

static void s_on_checkpoint_timer (void *arg)
{
    s_app_t *app = arg;
    if (trk_adapter_take_dirty (app->adapter))
        app->unsaved = true;
    if (app->unsaved && s_checkpoint (app) < 0)
        cgs_log (LOG_WARNING, "checkpoint not written (see health)");
    const trk_adapter_stats_t *st = trk_adapter_stats (app->adapter);
    cgs_notify_status ("%zu tracks, %llu scans, %llu hits", trk_tracker_count (s_trk (app)),
                       (unsigned long long)st->scans, (unsigned long long)st->hits);
}

static void s_restore (s_app_t *app)
{
    void *data = NULL;
    size_t len = 0;
    int rc = cgs_state_read (app->checkpoint, S_CHECKPOINT_MAX, &data, &len);
    if (rc == -ENOENT) {
        cgs_log (LOG_INFO, "no checkpoint at %s: starting with no tracks", app->checkpoint);
        return;
    }
    char err[512] = "";
    uint32_t next_id = 0;
    if (rc == 0 && app->fresh) {
        cgs_log (LOG_NOTICE, "--fresh: the checkpoint %s is ignored", app->checkpoint);
    } else if (rc == 0 && trk_checkpoint_restore (s_trk (app), data, len, err, sizeof err) == 0) {
        cgs_log (LOG_NOTICE, "resumed %zu tracks from %s (next track id %u)",
                 trk_tracker_count (s_trk (app)), app->checkpoint,
                 trk_tracker_next_id (s_trk (app)));
    } else {
        char why[1024];
        snprintf (why, sizeof why, "checkpoint %s ignored: %s", app->checkpoint,
                  rc < 0 ? strerror (-rc) : err);
        cgs_log (LOG_WARNING, "%s; starting with no tracks", why);
        cgs_health_set_error (cgs_service_health (app->svc), why);
        // Keep the damaged file for a look; the next checkpoint takes its name.
        char aside[4300];
        snprintf (aside, sizeof aside, "%s.damaged", app->checkpoint);
        if (rc == 0 && rename (app->checkpoint, aside) == 0)
            cgs_log (LOG_NOTICE, "the damaged checkpoint is kept as %s", aside);
    }
    // Whatever was refused, ids it had given are not given again.
    if (rc == 0 && trk_tracker_count (s_trk (app)) == 0 &&
        trk_checkpoint_next_id (data, len, &next_id) == 0) {
        trk_tracker_raise_next_id (s_trk (app), next_id);
        cgs_log (LOG_INFO, "new track ids start at %u", trk_tracker_next_id (s_trk (app)));
    }
    free (data);
}

/* ---- --monte-carlo ------------------------------------------------------------------- */

static int s_number (const char *opt, const char *s, double lo, double hi, double *ret)
{
    char *end;
    double v = strtod (s, &end);
    if (end == s || *end || !(v >= lo && v <= hi)) {
        fprintf (stderr, "trackerd: --%s: expected a number in [%g, %g], got '%s'\n", opt, lo, hi,
                 s);
        return -EINVAL;
    }
    *ret = v;
    return 0;
}

/* A whole number lo..hi in decimal digits; -EINVAL after saying why. */
static int s_count (const char *what, const char *text, uint64_t lo, uint64_t hi, uint64_t *ret)
{
    uint64_t v = 0;
    if (cgs_parse_u64 (text, hi, &v) < 0 || v < lo) {
        fprintf (stderr, "trackerd: --%s: expected a whole number %llu..%llu, got '%s'\n", what,
                 (unsigned long long)lo, (unsigned long long)hi, text);
        return -EINVAL;
    }
    *ret = v;
    return 0;
}

static int s_monte_carlo (int argc, char **argv)
{
    static const struct option opts[] = {
        {"monte-carlo", no_argument, NULL, 'M'},
        {"params", required_argument, NULL, 'p'},
        {"speed", required_argument, NULL, 'v'},
        {"turn-deg", required_argument, NULL, 'a'},
        {"sigma-meas", required_argument, NULL, 'm'},
        {"targets", required_argument, NULL, 'n'},
        {"scans", required_argument, NULL, 'k'},
        {"seed", required_argument, NULL, 'S'},
        {"help", no_argument, NULL, 'h'},
        {NULL, 0, NULL, 0},
    };
    trk_params_t p;
    trk_params_defaults (&p);
    const char *params = NULL;
    double speed = 15, turn = 90, sigma = NAN;
    uint64_t targets = 3000, scans = 32, seed = 1;
    int o;
    optind = 1;
    while ((o = getopt_long (argc, argv, "h", opts, NULL)) != -1) {
        int rc = 0;
        switch (o) {
        case 'M':
            break;
        case 'p':
            params = optarg;
            break;
        case 'v':
            rc = s_number ("speed", optarg, 0, 1000, &speed);
            break;
        case 'a':
            rc = s_number ("turn-deg", optarg, 0, 180, &turn);
            break;
        case 'm':
            rc = s_number ("sigma-meas", optarg, 0.01, 1e5, &sigma);
            break;
        case 'n':
            rc = s_count ("targets", optarg, 1, 1000000, &targets);
            break;
        case 'k':
            rc = s_count ("scans", optarg, 12, 1000000, &scans);
            break;
        case 'S':
            rc = s_count ("seed", optarg, 0, UINT64_MAX, &seed);
            break;
        case 'h':
            printf ("usage: trackerd --monte-carlo [--params F] [--speed MPS] [--turn-deg A]\n"
                    "                [--sigma-meas M] [--targets N] [--scans N] [--seed S]\n"
                    "Runs the tracker on N synthetic targets, 5 km apart on one heading at\n"
                    "--speed, hit once a scan with Gaussian noise of --sigma-meas per axis\n"
                    "(default: the parameters' sigma_meas_x_m) and no false alarms. With\n"
                    "--turn-deg A > 0 each target turns A degrees (left or right at random)\n"
                    "between its hits of scans --scans - 6 and --scans - 5, and the result\n"
                    "gives the turns flagged within 2 scans and the false turns per\n"
                    "straight-leg scan; with --turn-deg 0 the targets go straight and the\n"
                    "result gives the RMSE of position and velocity beside the constant-gain\n"
                    "filter's steady-state values. Prints one line of JSON. Defaults: speed\n"
                    "15, turn 90, 3000 targets, 32 scans, seed 1.\n");
            return 0;
        default:
            return 2;
        }
        if (rc < 0)
            return 2;
    }
    if (optind < argc) {
        fprintf (stderr, "trackerd: unexpected argument '%s'\n", argv[optind]);
        return 2;
    }
    char err[1024];
    if (params && trk_params_load (params, &p, err, sizeof err) < 0) {
        fprintf (stderr, "trackerd: %s\n", err);
        return 2;
    }
    if (!isfinite (sigma))
        sigma = p.filter.sigma_meas_m[0];
    trk_mc_config_t c = {
        .targets = (size_t)targets,
        .scans = (size_t)scans,
        .settle_scans = 8,
        .speed_mps = speed,
        .sigma_meas_m = {sigma, sigma},
        .turn_scan = turn > 0 ? (size_t)scans - 6 : 0,
        .turn_deg = turn,
        .seed = seed,
    };
    trk_mc_result_t r;
    int rc = trk_mc_run (&p, &c, &r);
    if (rc < 0) {
        fprintf (stderr, "trackerd: --monte-carlo: %s\n",
                 rc == -ENOMEM ? "out of memory" : "invalid configuration");
        return 2;
    }
    trk_gains_t g;
    trk_gains_paper (p.filter.sigma_meas_m[0], p.filter.sigma_mod_mps2[0], p.filter.dt_s, &g);
    double pv = NAN, vv = NAN;
    trk_filter_steady_error (&g, p.filter.dt_s, sigma, &pv, &vv);
    printf ("{\"mode\":\"%s\",\"sigma_meas_m\":%g,\"sigma_mod_mps2\":%g,\"scan_period_s\":%g,"
            "\"r\":%.6g,\"g\":%.6f,\"g_d_hz\":%.6f,\"threshold_deg\":%g,\"speed_mps\":%g,"
            "\"turn_deg\":%g,\"targets\":%zu,\"scans\":%zu,\"seed\":%llu,\"lost\":%zu,",
            trk_params_mode_name (p.filter.mode), sigma, p.filter.sigma_mod_mps2[0], p.filter.dt_s,
            g.r, g.g, g.gd_hz, p.turn_threshold_deg, speed, turn, c.targets, c.scans,
            (unsigned long long)c.seed, r.lost);
    if (turn > 0)
        printf ("\"turns\":%zu,\"detected_within_2_scans\":%zu,\"detection_rate\":%.5f,"
                "\"straight_scans\":%zu,\"false_turns\":%zu,\"false_turn_rate\":%.6f,"
                "\"completed\":%zu,\"right_side\":%zu,\"angle_mean_deg\":%.2f,"
                "\"angle_sd_deg\":%.2f}\n",
                r.turns, r.detected, r.turns ? (double)r.detected / (double)r.turns : 0,
                r.straight_scans, r.false_turns,
                r.straight_scans ? (double)r.false_turns / (double)r.straight_scans : 0,
                r.completed, r.right_side, r.angle_mean_deg, r.angle_sd_deg);
    else
        printf ("\"samples\":%zu,\"rmse_position_m\":[%.3f,%.3f],\"rmse_velocity_mps\":[%.4f,"
                "%.4f],\"theory_position_m\":%.3f,\"theory_velocity_mps\":%.4f}\n",
                r.samples, r.rmse_pos_m[0], r.rmse_pos_m[1], r.rmse_vel_mps[0], r.rmse_vel_mps[1],
                sqrt (pv), sqrt (vv));
    return 0;
}

/* ---- main ---------------------------------------------------------------------------- */

static const cgs_service_option_t s_options[] = {
    {"fresh", false, NULL, "start with no tracks, ignoring the checkpoint"},
    {"monte-carlo", false, NULL, "run the tracker on synthetic targets (see --monte-carlo --help)"},
    {NULL, false, NULL, NULL},
};

static int s_on_option (void *arg, const char *name, const char *value, char *why, size_t whylen)
{
    (void)value;
    s_app_t *app = arg;
    if (strcmp (name, "fresh") == 0) {
        app->fresh = true;
        return 0;
    }
    snprintf (why, whylen, "unknown option --%s", name);
    return -EINVAL;
}

static int s_setup (s_app_t *app, char *err, size_t errlen)
{
    trk_params_defaults (&app->params);
    const char *params = cgs_service_params_path (app->svc);
    if (*params) {
        int rc = trk_params_load (params, &app->params, err, errlen);
        if (rc < 0)
            return rc;
        cgs_log (LOG_INFO, "tracker parameters from %s", params);
    } else {
        cgs_log (LOG_INFO, "tracker parameters: the built-in defaults (no parameter file named)");
    }
    cgs_port_t port = cgs_service_port (app->svc);
    app->adapter = trk_adapter_new (&app->params, &port);
    if (!app->adapter) {
        snprintf (err, errlen, "out of memory");
        return -ENOMEM;
    }
    if (app->params.filter.mode == TRK_FILTER_IMM && *cgs_service_scenario_path (app->svc)) {
        int rc = cgs_service_load_scene (app->svc, &app->frame, &app->scenario, &app->terrain, err,
                                         errlen);
        if (rc < 0)
            return rc;
        trk_tracker_set_terrain (trk_adapter_tracker (app->adapter), app->terrain);
        cgs_log (LOG_INFO, "terrain of %s: a target it hides from a radar is not expected seen",
                 cgs_service_scenario_path (app->svc));
    } else if (app->params.filter.mode == TRK_FILTER_IMM) {
        cgs_log (LOG_INFO, "no scenario named: no terrain in the expected detection probability");
    }
    if (cgs_state_path (app->checkpoint, sizeof app->checkpoint, cgs_service_state_dir (app->svc),
                        cgs_service_instance_name (app->svc)) < 0 ||
        strlen (app->checkpoint) + 8 > sizeof app->checkpoint) {
        snprintf (err, errlen, "state folder path too long");
        return -ENAMETOOLONG;
    }
    strcat (app->checkpoint, ".tracks");
    const trk_params_t *p = &app->params;
    trk_adapter_set_verbose (app->adapter, cgs_service_verbose (app->svc) != 0);
    trk_adapter_set_params_path (app->adapter, params);
    if (p->filter.mode == TRK_FILTER_IMM) {
        cgs_log (LOG_INFO,
                 "filter imm: sigma_meas %g/%g m, models CV %g m/s2, manoeuvre %g m/s2, stopped; "
                 "pd %g (half at %g m), JIPDA over %d hypotheses; gate %.3f (%.1f), M/N %d/%d, "
                 "delete below existence %g, turn threshold %g deg",
                 p->filter.sigma_meas_m[0], p->filter.sigma_meas_m[1], p->imm.sigma_mps2[0],
                 p->imm.sigma_mps2[1], p->detection.pd, p->detection.half_range_m, p->hypotheses,
                 p->gate_probability, trk_params_gate3 (p), p->confirm_m, p->confirm_n,
                 p->delete_existence, p->turn_threshold_deg);
        return 0;
    }
    const trk_gains_t *g = trk_tracker_gains (s_trk (app));
    cgs_log (LOG_INFO,
             "filter %s: sigma_meas %g/%g m, sigma_mod %g/%g m/s2, scan %s%g s: r %.4g/%.4g, "
             "g %.4f/%.4f, g_d %.5f/%.5f 1/s; gate %.3f (%.1f), M/N %d/%d, delete after %d "
             "misses, turn threshold %g deg",
             trk_params_mode_name (p->filter.mode), p->filter.sigma_meas_m[0],
             p->filter.sigma_meas_m[1], p->filter.sigma_mod_mps2[0], p->filter.sigma_mod_mps2[1],
             p->filter.dt_auto ? "each update's own interval, at the nominal " : "", p->filter.dt_s,
             g[0].r, g[1].r, g[0].g, g[1].g, g[0].gd_hz, g[1].gd_hz, p->gate_probability,
             trk_params_gate (p), p->confirm_m, p->confirm_n, p->delete_misses,
             p->turn_threshold_deg);
    return 0;
}

int main (int argc, char **argv)
{
    gsl_set_error_handler_off (); // GSL reports through return codes; its handler would abort
    for (int i = 1; i < argc; i++)
        if (strcmp (argv[i], "--monte-carlo") == 0)
            return s_monte_carlo (argc, argv);
    static s_app_t app;
    cgs_service_info_t info = {
        .program = "trackerd",
        .summary = "Tracks from MTI hits, BCIS identity, the paper's Track & Update filter, "
                   "turn detection.",
        .options = s_options,
        .on_option = s_on_option,
        .option_arg = &app,
    };
    int rc = cgs_service_new (&info, argc, argv, &app.svc);
    if (rc != 0)
        return rc > 0 ? 0 : 1;
    int exit_code = 1;
    char err[1024] = "";
    if (s_setup (&app, err, sizeof err) < 0) {
        cgs_log (LOG_ERR, "%s", err);
        goto done;
    }
    if (cgs_service_check_only (app.svc)) {
        printf ("%s: parameters are good\n", cgs_service_instance_name (app.svc));
        exit_code = 0;
        goto done;
    }
    s_restore (&app);
    for (const char *const *topic = trk_adapter_topics; *topic; topic++)
        if (cgs_service_subscribe (app.svc, *topic, s_on_message, &app) < 0)
            goto done;
    cgs_loop_add_timer (cgs_service_loop (app.svc), S_CHECKPOINT_S, s_on_checkpoint_timer, &app);
    exit_code = cgs_service_run (app.svc);
    if (s_checkpoint (&app) == 0)
        cgs_log (LOG_INFO, "saved %zu tracks to %s", trk_tracker_count (s_trk (&app)),
                 app.checkpoint);
    const trk_adapter_stats_t *st = trk_adapter_stats (app.adapter);
    cgs_log (LOG_INFO,
             "%llu scans (%llu closed without their end marker, %llu stale ignored), %llu hits, "
             "%llu tracks started, %llu deleted, %llu turns, %llu BCIS replies matched a track",
             (unsigned long long)st->scans, (unsigned long long)st->implicit_scans,
             (unsigned long long)st->stale_scans, (unsigned long long)st->hits,
             (unsigned long long)st->born, (unsigned long long)st->deleted,
             (unsigned long long)st->turns, (unsigned long long)st->bcis_marks);
done:
    trk_adapter_destroy (&app.adapter);
    cgs_terrain_destroy (&app.terrain);
    cgs_scenario_destroy (&app.scenario);
    cgs_geo_destroy (&app.frame);
    cgs_service_destroy (&app.svc);
    return exit_code;
}
