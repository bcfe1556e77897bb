/* mtid — the MTI radar processing model of one UAV: follows the UAV (`uav`)
 * and the ground entities (`entity`), runs the radar's dwells as simulation
 * time passes, and publishes each dwell's hits (`mti`), what it saw of each
 * entity (`mti.truth`, for scoring) and each completed scan (`mti.scan`).
 * `mtid --monte-carlo` runs the detector against the closed forms instead.
 * The model is in mti_*.c; this file wires it to the bus. */
#include "cgs_entities.h"
#include "cgs_log.h"
#include "cgs_scenario.h"
#include "cgs_sensor.h"
#include "cgs_service.h"
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

#define S_STALE_S    10.0 // an entity not heard of for this long (simulation time) is forgotten
#define S_WARNED_MAX 16   // unknown cross-section classes remembered for logging once

typedef struct {
    cgs_service_t svc;
    cgs_sensor_t sensor; // its UAV, scenario and terrain
    mti_params_t params;
    mti_radar_t *radar;
    cgs_scan_pace_t pace; // the next dwell to run
    cgs_entities_t *ents;
    mti_target_t *targets;
    size_t target_cap;
    /* The scan in progress. */
    uint32_t scan;
    double scan_start_s;
    uint32_t scan_hits, scan_fas;
    uint64_t dwells_run;
    char warned[S_WARNED_MAX][CGS_ENTITY_CLASS_MAX]; // unknown classes already logged
    size_t warned_count;
    /* Output messages, reused. */
    Cgs__MtiHit *hit_msgs;
    Cgs__MtiHit **hit_ptrs;
    Cgs__Enu *hit_pos;
    size_t hit_cap;
    Cgs__MtiTruthItem *truth_msgs;
    Cgs__MtiTruthItem **truth_ptrs;
    size_t truth_cap;
} s_app_t;

/* ---- entities ------------------------------------------------------------------------ */

/* A message the model cannot use: counted in health, logged the first time. */
static void s_bad (s_app_t *app, const char *what)
{
    cgs_service_bad_input (&app->svc, what);
}

static void s_on_entity (void *arg, const char *topic, const ProtobufCMessage *msg,
                         const Cgs__Header *hdr)
{
    (void)topic;
    s_app_t *app = arg;
    cgs_service_take_entities (&app->svc, app->ents, msg, hdr);
}

/* Log each unknown cross-section class once (the first S_WARNED_MAX of them). */
static void s_warn_class (s_app_t *app, const cgs_entity_state_t *s)
{
    for (size_t i = 0; i < app->warned_count; i++)
        if (strcmp (app->warned[i], s->rcs_class) == 0)
            return;
    if (app->warned_count == S_WARNED_MAX)
        return;
    snprintf (app->warned[app->warned_count++], CGS_ENTITY_CLASS_MAX, "%s", s->rcs_class);
    const mti_class_t *c = mti_params_class (&app->params, s->rcs_class, NULL);
    cgs_log (LOG_WARNING,
             "entity %u: radar cross-section class '%s' is not in the parameters; "
             "seen as class '%s'",
             s->id, s->rcs_class, c->name);
}

/* The ground entities as they are at time t (moved on along their velocity). */
static size_t s_targets_at (s_app_t *app, double t)
{
    size_t count = cgs_entities_count (app->ents);
    if (app->target_cap < count) {
        mti_target_t *tg = realloc (app->targets, count * sizeof *tg);
        if (!tg) {
            cgs_health_set_error (app->svc.health, "out of memory for targets: a dwell ran empty");
            return 0;
        }
        app->targets = tg;
        app->target_cap = count;
    }
    size_t n = 0, cursor = 0;
    const cgs_entity_state_t *s;
    while ((s = cgs_entities_next (app->ents, &cursor))) {
        if (s->kind == CGS_KIND_AIR || !s->active || s->id == app->sensor.uav_id)
            continue;
        double dt = t - s->time_s;
        if (dt > S_STALE_S || dt < -S_STALE_S)
            continue;
        // Moved on along its velocity, on the ground there.
        double east = s->position.e_m + s->velocity.e_m * dt,
               north = s->position.n_m + s->velocity.n_m * dt;
        bool known;
        mti_params_class (&app->params, s->rcs_class, &known);
        if (!known)
            s_warn_class (app, s);
        app->targets[n++] = (mti_target_t){
            .id = s->id,
            .position = {east, north,
                         cgs_terrain_height_clamped (app->sensor.terrain, east, north)},
            .velocity = s->velocity,
            .rcs_class = s->rcs_class,
        };
    }
    return n;
}

/* ---- publication --------------------------------------------------------------------- */

static int s_reserve_out (s_app_t *app, size_t hits, size_t truth)
{
    if (hits > app->hit_cap) {
        size_t cap = hits * 2;
        free (app->hit_msgs);
        free (app->hit_ptrs);
        free (app->hit_pos);
        app->hit_msgs = calloc (cap, sizeof *app->hit_msgs);
        app->hit_ptrs = calloc (cap, sizeof *app->hit_ptrs);
        app->hit_pos = calloc (cap, sizeof *app->hit_pos);
        app->hit_cap = app->hit_msgs && app->hit_ptrs && app->hit_pos ? cap : 0;
        if (!app->hit_cap)
            return -ENOMEM;
    }
    if (truth > app->truth_cap) {
        size_t cap = truth * 2;
        free (app->truth_msgs);
        free (app->truth_ptrs);
        app->truth_msgs = calloc (cap, sizeof *app->truth_msgs);
        app->truth_ptrs = calloc (cap, sizeof *app->truth_ptrs);
        app->truth_cap = app->truth_msgs && app->truth_ptrs ? cap : 0;
        if (!app->truth_cap)
            return -ENOMEM;
    }
    return 0;
}

static void s_publish_dwell (s_app_t *app, const mti_dwell_t *d, const mti_dwell_out_t *out)
{
    if (s_reserve_out (app, out->hit_count, out->truth_count) < 0) {
        cgs_health_set_error (app->svc.health, "out of memory for a dwell's messages");
        return;
    }
    double t = (d->start_s + d->end_s) / 2;
    app->svc.sim_time_s = t;
    for (size_t i = 0; i < out->hit_count; i++) {
        const mti_hit_t *h = &out->hits[i];
        Cgs__MtiHit *m = &app->hit_msgs[i];
        cgs__mti_hit__init (m);
        cgs__enu__init (&app->hit_pos[i]);
        app->hit_pos[i].east_m = h->position.e_m;
        app->hit_pos[i].north_m = h->position.n_m;
        app->hit_pos[i].up_m = h->position.u_m;
        m->hit_id = h->hit_id;
        m->position = &app->hit_pos[i];
        m->range_m = h->range_m;
        m->azimuth_deg = h->azimuth_deg;
        m->radial_velocity_mps = h->radial_velocity_mps;
        m->snr_db = h->snr_db;
        m->range_sigma_m = h->range_sigma_m;
        m->azimuth_sigma_deg = h->azimuth_sigma_deg;
        m->sim_time_s = t;
        app->hit_ptrs[i] = m;
    }
    Cgs__Enu plat = CGS__ENU__INIT;
    plat.east_m = app->sensor.position.e_m;
    plat.north_m = app->sensor.position.n_m;
    plat.up_m = app->sensor.position.u_m;
    Cgs__Mti mti = CGS__MTI__INIT;
    mti.uav_id = app->sensor.uav_id;
    mti.scan_number = d->scan;
    mti.dwell_number = d->dwell;
    mti.beam_azimuth_deg = d->az_center_deg;
    mti.platform_position = &plat;
    mti.n_hits = out->hit_count;
    mti.hits = app->hit_ptrs;
    cgs_service_publish (&app->svc, "mti", &mti.base);

    for (size_t i = 0; i < out->truth_count; i++) {
        const mti_truth_t *tr = &out->truth[i];
        Cgs__MtiTruthItem *m = &app->truth_msgs[i];
        cgs__mti_truth_item__init (m);
        m->entity_id = tr->entity_id;
        m->in_beam = true;
        m->visible = tr->visible;
        m->snr_db = isfinite (tr->snr_db) ? tr->snr_db : -999.0;
        m->pd = tr->pd;
        m->detected = tr->detected;
        m->hit_id = tr->hit_id;
        m->radial_velocity_mps = tr->radial_velocity_mps;
        m->range_m = tr->range_m;
        app->truth_ptrs[i] = m;
    }
    Cgs__MtiTruth truth = CGS__MTI_TRUTH__INIT;
    truth.uav_id = app->sensor.uav_id;
    truth.scan_number = d->scan;
    truth.dwell_number = d->dwell;
    truth.n_items = out->truth_count;
    truth.false_alarms = out->false_alarms;
    truth.items = app->truth_ptrs;
    cgs_service_publish (&app->svc, "mti.truth", &truth.base);
}

static void s_publish_scan (s_app_t *app, const mti_dwell_t *d)
{
    Cgs__MtiScan m = CGS__MTI_SCAN__INIT;
    m.uav_id = app->sensor.uav_id;
    m.scan_number = d->scan;
    m.scan_start_s = app->scan_start_s;
    m.scan_end_s = d->end_s;
    m.full_revolution = app->params.scan_mode == MTI_SCAN_FULL;
    m.sector_center_deg = app->params.sector_center_deg;
    if (app->params.sector_ref == MTI_SECTOR_HEADING) // as an azimuth, at the scan's end
        m.sector_center_deg = fmod (m.sector_center_deg + app->sensor.heading_deg + 720.0, 360.0);
    m.sector_width_deg = m.full_revolution ? 360.0 : app->params.sector_width_deg;
    m.hit_count = app->scan_hits;
    m.false_alarm_count = app->scan_fas;
    m.expected_false_alarms = mti_radar_gate_pfa (app->radar) * mti_radar_gates (app->radar) *
                              mti_radar_dwells_per_scan (app->radar);
    app->svc.sim_time_s = d->end_s;
    cgs_service_publish (&app->svc, "mti.scan", &m.base);
}

/* ---- the radar ----------------------------------------------------------------------- */

static void s_run_dwell (s_app_t *app, uint64_t k)
{
    mti_dwell_t d;
    mti_radar_schedule (app->radar, k, app->sensor.heading_deg, &d);
    if (d.scan != app->scan || d.scan_start) {
        app->scan = d.scan;
        app->scan_start_s = d.start_s;
        app->scan_hits = app->scan_fas = 0;
    }
    double t = (d.start_s + d.end_s) / 2;
    mti_platform_t plat = {.position = cgs_sensor_uav_at (&app->sensor, t),
                           .velocity = app->sensor.velocity,
                           .heading_deg = app->sensor.heading_deg};
    size_t n = s_targets_at (app, t);
    mti_dwell_out_t out;
    int rc = mti_radar_dwell (app->radar, &d, &plat, app->targets, n, &out);
    if (rc < 0) {
        char why[128];
        snprintf (why, sizeof why, "dwell %llu not run: %s", (unsigned long long)k, strerror (-rc));
        cgs_health_set_error (app->svc.health, why);
        return;
    }
    app->dwells_run++;
    app->scan_hits += (uint32_t)out.hit_count;
    app->scan_fas += out.false_alarms;
    s_publish_dwell (app, &d, &out);
    if (d.scan_end) {
        s_publish_scan (app, &d);
        cgs_entities_evict (app->ents, t, S_STALE_S);
    }
}

static void s_on_uav (void *arg, const char *topic, const ProtobufCMessage *msg,
                      const Cgs__Header *hdr)
{
    (void)topic;
    s_app_t *app = arg;
    const Cgs__Uav *u = (const Cgs__Uav *)msg;
    double t = hdr->sim_time_s;
    bool new_id = false;
    int rc = cgs_sensor_take_uav (&app->sensor, u, t, &new_id);
    if (rc > 0)
        return; // another UAV's
    if (rc < 0) {
        s_bad (app, "a uav message without a valid time, position, velocity or heading");
        return;
    }
    if (new_id)
        cgs_log (LOG_INFO, "radar on %s (entity %u) at t=%.2f s", app->sensor.uav_name,
                 app->sensor.uav_id, t);
    uint64_t end, skipped;
    cgs_pace_t how =
        cgs_scan_pace (mti_radar_scan (app->radar), &app->pace, t, S_STALE_S, &end, &skipped);
    if (how == CGS_PACE_BACK)
        cgs_log (LOG_NOTICE, "simulation time went back to %.2f s; the scan follows", t);
    if (skipped) {
        char why[160];
        snprintf (why, sizeof why, "fell behind: %llu dwells skipped in all",
                  (unsigned long long)app->pace.skipped);
        cgs_health_set_error (app->svc.health, why);
        cgs_log (LOG_WARNING, "%s", why);
    }
    // Run every dwell that has ended by now.
    while (app->pace.next < end)
        s_run_dwell (app, app->pace.next++);
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
            if (strcmp (optarg, "0") && strcmp (optarg, "1") && strcmp (optarg, "2")) {
                fprintf (stderr, "mtid: --swerling: expected 0 (constant), 1 or 2, got '%s'\n",
                         optarg);
                return 2;
            }
            c.swerling = (mti_swerling_t)atoi (optarg);
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
            printf ("usage: mtid --monte-carlo [--swerling 0|1|2] [--snr-db X] [--trials N]\n"
                    "            [--ref-cells N] [--pfa P] [--fft-size N] [--seed S]\n"
                    "Runs coherent intervals through the radar's processing chain (noise\n"
                    "only, target on a Doppler bin centre) and prints, as JSON, the measured\n"
                    "detection and false-alarm probabilities of the CA-CFAR detector with their\n"
                    "99%% intervals and the closed-form values. --snr-db is the SNR in the\n"
                    "Doppler cell of a coherently integrating target (default 10); a Swerling\n"
                    "II target gets the per-pulse SNR only (cell_snr_db). Defaults: Swerling 1,\n"
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
    printf ("{\"swerling\":%d,\"snr_db\":%g,\"cell_snr_db\":%.4f,\"trials\":%lu,"
            "\"reference_cells\":%d,\"fft_size\":%d,\"pfa_design\":%g,\"threshold_t\":%.6f,"
            "\"pd_measured\":%.5f,\"pd_interval_99\":%s,\"pd_theory\":%.5f,"
            "\"false_alarm_cells\":%lu,\"false_alarms\":%lu,\"pfa_measured\":%.6g,"
            "\"false_alarms_interval_99\":%s,\"seed\":%llu}\n",
            (int)c.swerling, c.snr_db, r.cell_snr_db, c.trials, c.ref_cells, c.fft_size, c.pfa,
            r.threshold, r.pd, pd_int, r.pd_theory, r.fa_cells, r.false_alarms, r.pfa_measured,
            fa_int, (unsigned long long)c.seed);
    return 0;
}

/* ---- main ---------------------------------------------------------------------------- */

static int s_setup (s_app_t *app, char *err, size_t errlen)
{
    int rc = cgs_sensor_setup (&app->sensor, &app->svc, "mtid", 0xD1B54A32D192ED03ull, err, errlen);
    if (rc < 0)
        return rc;
    const cgs_scenario_uav_t *u = app->sensor.uav;
    // Parameters: --params, else the instance's `params =`, else the UAV's radar_params.
    const char *params = *app->svc.params ? app->svc.params : u->radar_params;
    mti_params_defaults (&app->params);
    if (params && *params) {
        if ((rc = mti_params_load (params, &app->params, err, errlen)) < 0)
            return rc;
        cgs_log (LOG_INFO, "radar parameters from %s", params);
    } else {
        cgs_log (LOG_INFO, "radar parameters: the built-in defaults (no parameter file named)");
    }
    app->radar = mti_radar_new (&app->params, app->sensor.terrain, app->sensor.seed);
    app->ents = cgs_entities_new ();
    if (!app->radar || !app->ents) {
        snprintf (err, errlen, "out of memory");
        return -ENOMEM;
    }
    const mti_params_t *p = &app->params;
    cgs_log (LOG_INFO,
             "%s: %.1f GHz, PRF %.0f Hz, %g x %g deg beam at %g deg/s, %u dwells of %.1f ms "
             "per scan, FFT %d, %s, CFAR %d+%d cells Pfa %g, %d of %d, range %.0f..%.0f m",
             app->sensor.uav_name, p->frequency_hz / 1e9, p->prf_hz, p->azimuth_beamwidth_deg,
             p->elevation_beamwidth_deg, p->sweep_rate_dps, mti_radar_dwells_per_scan (app->radar),
             mti_radar_dwell_s (app->radar) * 1e3, p->fft_size,
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
    int rc = cgs_service_init (&app.svc, &info, argc, argv);
    if (rc != 0) {
        cgs_service_fini (&app.svc);
        return rc > 0 ? 0 : 1;
    }
    int exit_code = 1;
    char err[1024] = "";
    if (s_setup (&app, err, sizeof err) < 0) {
        cgs_log (LOG_ERR, "%s", err);
        goto done;
    }
    if (app.svc.check_only) {
        printf ("%s: parameters and scenario are good\n", app.svc.instance_name);
        exit_code = 0;
        goto done;
    }
    if (cgs_service_subscribe (&app.svc, "entity", s_on_entity, &app) < 0 ||
        cgs_service_subscribe (&app.svc, "uav", s_on_uav, &app) < 0)
        goto done;
    exit_code = cgs_service_run (&app.svc);
    cgs_log (LOG_INFO, "%llu dwells run, %llu skipped", (unsigned long long)app.dwells_run,
             (unsigned long long)app.pace.skipped);
done:
    mti_radar_destroy (&app.radar);
    cgs_sensor_fini (&app.sensor);
    cgs_entities_destroy (&app.ents);
    free (app.targets);
    free (app.hit_msgs);
    free (app.hit_ptrs);
    free (app.hit_pos);
    free (app.truth_msgs);
    free (app.truth_ptrs);
    cgs_service_fini (&app.svc);
    return exit_code;
}
