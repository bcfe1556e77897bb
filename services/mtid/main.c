/* mtid — the MTI radar processing model of one UAV: follows the UAV (`uav`)
 * and the ground entities (`entity`), runs the radar's dwells as simulation
 * time passes, and publishes each dwell's hits (`mti`), what it saw of each
 * entity (`mti.truth`, for scoring) and each completed scan (`mti.scan`).
 * `mtid --monte-carlo` runs the detector against the closed forms instead.
 * The model is in mti_*.c, the handling of its inputs and outputs in
 * mti_adapter.c; this file wires the adapter to the bus. */
#include "cgs_log.h"
#include "cgs_scenario.h"
#include "cgs_sensor.h"
#include "cgs_service.h"
#include "mti_adapter.h"
#include "mti_mc.h"
#include "mti_params.h"
#include "mti_radar.h"

#include <errno.h>
#include <getopt.h>
#include <gsl/gsl_errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct {
    cgs_service_t *svc;
    cgs_sensor_t sensor; // its UAV, scenario and terrain
    mti_params_t params;
    mti_adapter_t *adapter;
} s_app_t;

static void s_on_message (void *arg, const char *topic, const ProtobufCMessage *msg,
                          const Cgs__Header *hdr)
{
    s_app_t *app = arg;
    mti_adapter_on_message (app->adapter, topic, msg, hdr);
}

/* ---- --monte-carlo ------------------------------------------------------------------- */

static int s_parse_double (const char *opt, const char *s, double *ret)
{
    char *end;
    double v = strtod (s, &end);
    if (end == s || *end || !isfinite (v)) {
        fprintf (stderr, "mtid: --%s: expected a number, got '%s'\n", opt, s);
        return -EINVAL;
    }
    *ret = v;
    return 0;
}

static int s_monte_carlo (int argc, char **argv)
{
    static const struct option opts[] = {
        {"monte-carlo", no_argument, NULL, 'M'},
        {"swerling", required_argument, NULL, 's'},
        {"snr-db", required_argument, NULL, 'r'},
        {"trials", required_argument, NULL, 't'},
        {"ref-cells", required_argument, NULL, 'n'},
        {"pfa", required_argument, NULL, 'p'},
        {"fft-size", required_argument, NULL, 'f'},
        {"seed", required_argument, NULL, 'S'},
        {"help", no_argument, NULL, 'h'},
        {NULL, 0, NULL, 0},
    };
    mti_mc_config_t c;
    mti_mc_defaults (&c);
    int o;
    double v;
    optind = 1;
    while ((o = getopt_long (argc, argv, "h", opts, NULL)) != -1) {
        switch (o) {
        case 'M':
            break;
        case 's':
            if (mti_swerling_parse (optarg, &c.swerling) < 0) {
                fprintf (stderr,
                         "mtid: --swerling: expected 0 (constant), 1, 2 or 2-pulse, got '%s'\n",
                         optarg);
                return 2;
            }
            break;
        case 'r':
            if (s_parse_double ("snr-db", optarg, &c.snr_db) < 0)
                return 2;
            break;
        case 't':
            if (s_parse_double ("trials", optarg, &v) < 0)
                return 2;
            if (v < 1 || v > 1e10 || v != floor (v)) {
                fprintf (stderr, "mtid: --trials: expected a whole number 1..1e10\n");
                return 2;
            }
            c.trials = (unsigned long)v;
            break;
        case 'n':
        case 'f':
            if (s_parse_double (o == 'n' ? "ref-cells" : "fft-size", optarg, &v) < 0)
                return 2;
            if (v != floor (v) || v < 1 || v > 4096) {
                fprintf (stderr, "mtid: --%s: expected a whole number\n",
                         o == 'n' ? "ref-cells" : "fft-size");
                return 2;
            }
            *(o == 'n' ? &c.ref_cells : &c.fft_size) = (int)v;
            break;
        case 'p':
            if (s_parse_double ("pfa", optarg, &c.pfa) < 0)
                return 2;
            break;
        case 'S':
            if (s_parse_double ("seed", optarg, &v) < 0)
                return 2;
            c.seed = (uint64_t)fabs (v);
            break;
        case 'h':
            printf (
                "usage: mtid --monte-carlo [--swerling 0|1|2|2-pulse] [--snr-db X] [--trials N]\n"
                "            [--ref-cells N] [--pfa P] [--fft-size N] [--seed S]\n"
                "Runs coherent intervals through the radar's processing chain (noise\n"
                "only, target on a Doppler bin centre) and prints, as JSON, the measured\n"
                "detection and false-alarm probabilities of the CA-CFAR detector with their\n"
                "99%% intervals and the closed-form values. --snr-db is the SNR in the\n"
                "Doppler cell of a coherently integrating target (default 10); in one\n"
                "interval Swerling 2 (a new draw each interval) is Swerling 1; a target\n"
                "fluctuating pulse to pulse (2-pulse) gets the per-pulse SNR only\n"
                "(cell_snr_db). Defaults: Swerling 1,\n"
                "10000 trials, 16 reference cells, Pfa 1e-4, FFT 64, seed 1.\n");
            return 0;
        default:
            return 2;
        }
    }
    if (optind < argc) {
        fprintf (stderr, "mtid: unexpected argument '%s'\n", argv[optind]);
        return 2;
    }
    mti_mc_result_t r;
    char err[512];
    int rc = mti_mc_run (&c, &r, err, sizeof err);
    if (rc < 0) {
        fprintf (stderr, "mtid: --monte-carlo: %s\n", rc == -ENOMEM ? "out of memory" : err);
        return 2;
    }
    // An interval GSL cannot compute (huge trial counts) is null, not a number.
    char pd_int[64] = "null", fa_int[64] = "null";
    if (r.pd_interval_ok)
        snprintf (pd_int, sizeof pd_int, "[%.5f,%.5f]", r.pd_lo, r.pd_hi);
    if (r.fa_interval_ok)
        snprintf (fa_int, sizeof fa_int, "[%lu,%lu]", r.fa_lo, r.fa_hi);
    printf ("{\"swerling\":\"%s\",\"snr_db\":%g,\"cell_snr_db\":%.4f,\"trials\":%lu,"
            "\"reference_cells\":%d,\"fft_size\":%d,\"pfa_design\":%g,\"threshold_t\":%.6f,"
            "\"pd_measured\":%.5f,\"pd_interval_99\":%s,\"pd_theory\":%.5f,"
            "\"false_alarm_cells\":%lu,\"false_alarms\":%lu,\"pfa_measured\":%.6g,"
            "\"false_alarms_interval_99\":%s,\"seed\":%llu}\n",
            mti_swerling_name (c.swerling), c.snr_db, r.cell_snr_db, c.trials, c.ref_cells,
            c.fft_size, c.pfa, r.threshold, r.pd, pd_int, r.pd_theory, r.fa_cells, r.false_alarms,
            r.pfa_measured, fa_int, (unsigned long long)c.seed);
    return 0;
}

/* ---- main ---------------------------------------------------------------------------- */

static int s_setup (s_app_t *app, char *err, size_t errlen)
{
    int rc = cgs_sensor_setup (&app->sensor, app->svc, "mtid", 0xD1B54A32D192ED03ull, err, errlen);
    if (rc < 0)
        return rc;
    const cgs_scenario_uav_t *u = app->sensor.uav;
    // Parameters: --params, else the instance's `params =`, else the UAV's radar_params.
    const char *params = cgs_service_params_path (app->svc);
    if (!*params)
        params = u->radar_params;
    mti_params_defaults (&app->params);
    if (params && *params) {
        if ((rc = mti_params_load (params, &app->params, err, errlen)) < 0)
            return rc;
        cgs_log (LOG_INFO, "radar parameters from %s", params);
    } else {
        cgs_log (LOG_INFO, "radar parameters: the built-in defaults (no parameter file named)");
    }
    cgs_port_t port = cgs_service_port (app->svc);
    app->adapter = mti_adapter_new (&app->params, &app->sensor, &port);
    if (!app->adapter) {
        snprintf (err, errlen, "out of memory");
        return -ENOMEM;
    }
    const mti_radar_t *radar = mti_adapter_radar (app->adapter);
    const mti_params_t *p = &app->params;
    cgs_log (LOG_INFO,
             "%s: %.1f GHz, PRF %.0f Hz, %g x %g deg beam at %g deg/s, %u dwells of %.1f ms "
             "per scan, FFT %d, %s, CFAR %d+%d cells Pfa %g, %d of %d, range %.0f..%.0f m",
             app->sensor.uav_name, p->frequency_hz / 1e9, p->prf_hz, p->azimuth_beamwidth_deg,
             p->elevation_beamwidth_deg, p->sweep_rate_dps, mti_radar_dwells_per_scan (radar),
             mti_radar_dwell_s (radar) * 1e3, p->fft_size,
             p->canceller == MTI_CANCELLER_THREE ? "three-pulse canceller"
             : p->canceller == MTI_CANCELLER_TWO ? "two-pulse canceller"
                                                 : "no canceller",
             p->ref_cells, p->guard_cells, p->pfa, p->m, p->n, p->min_range_m, p->max_range_m);
    return 0;
}

int main (int argc, char **argv)
{
    // GSL reports through return codes (the theory module checks them); its
    // default handler would abort the process.
    gsl_set_error_handler_off ();
    for (int i = 1; i < argc; i++)
        if (strcmp (argv[i], "--monte-carlo") == 0)
            return s_monte_carlo (argc, argv);
    static s_app_t app;
    cgs_service_info_t info = {
        .program = "mtid",
        .summary = "MTI radar processing model of one UAV (--monte-carlo: check the detector; "
                   "see mtid --monte-carlo --help).",
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
        printf ("%s: parameters and scenario are good\n", cgs_service_instance_name (app.svc));
        exit_code = 0;
        goto done;
    }
    for (size_t i = 0; mti_adapter_topics[i]; i++)
        if (cgs_service_subscribe (app.svc, mti_adapter_topics[i], s_on_message, &app) < 0)
            goto done;
    exit_code = cgs_service_run (app.svc);
    const mti_adapter_stats_t *st = mti_adapter_stats (app.adapter);
    cgs_log (LOG_INFO, "%llu dwells run, %llu skipped", (unsigned long long)st->dwells_run,
             (unsigned long long)st->skipped);
done:
    mti_adapter_destroy (&app.adapter);
    cgs_sensor_fini (&app.sensor);
    cgs_service_destroy (&app.svc);
    return exit_code;
}
