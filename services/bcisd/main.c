/* bcisd — the scanning BCIS interrogator of one UAV: follows the UAV (`uav`)
 * and the ground entities (`entity`), interrogates once a dwell as its scan
 * sweeps and simulation time passes, and publishes each interrogation's
 * replies and the end of each scan on `bcis`. The model is in bcis_*.c; this
 * file wires it to the bus. */
#include "bcis_interrogator.h"
#include "bcis_params.h"
#include "cgs_entities.h"
#include "cgs_log.h"
#include "cgs_scenario.h"
#include "cgs_sensor.h"
#include "cgs_service.h"

#include <errno.h>
#include <gsl/gsl_errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define S_STALE_S 10.0 // an entity not heard of for this long (simulation time) is forgotten

typedef struct {
    cgs_service_t svc;
    cgs_sensor_t sensor; // its UAV, scenario and terrain
    bcis_params_t params;
    bcis_interrogator_t *bcis;
    const cgs_scan_t *scan;
    cgs_scan_pace_t pace; // the next dwell to run
    cgs_entities_t *ents;
    bcis_entity_t *targets;
    size_t target_cap;
    uint64_t dwells_run, interrogated, replies, blocked;
    /* Output messages, reused. */
    Cgs__BcisReply *reply_msgs;
    Cgs__BcisReply **reply_ptrs;
    Cgs__Enu *reply_pos;
    size_t reply_cap;
} s_app_t;

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

/* An entity moved on along its velocity by dt, on the ground there. */
static cgs_enu_t s_moved (const s_app_t *app, const cgs_entity_state_t *s, double dt)
{
    double e = s->position.e_m + s->velocity.e_m * dt, n = s->position.n_m + s->velocity.n_m * dt;
    return (cgs_enu_t){e, n, cgs_terrain_height_clamped (app->sensor.terrain, e, n)};
}

/* The ground entities as they are at time t (moved on along their velocity). */
static size_t s_targets_at (s_app_t *app, double t)
{
    size_t count = cgs_entities_count (app->ents);
    if (app->target_cap < count) {
        bcis_entity_t *tg = realloc (app->targets, count * sizeof *tg);
        if (!tg) {
            cgs_health_set_error (app->svc.health, "out of memory for entities: a dwell ran empty");
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
        app->targets[n++] = (bcis_entity_t){
            .id = s->id,
            .position = s_moved (app, s, dt),
            .force = s->force,
            .transponder = s->bcis_transponder,
            .marking = s->marking,
        };
    }
    return n;
}

static int s_reserve (s_app_t *app, size_t n)
{
    if (n <= app->reply_cap)
        return 0;
    size_t cap = n * 2;
    free (app->reply_msgs);
    free (app->reply_ptrs);
    free (app->reply_pos);
    app->reply_msgs = calloc (cap, sizeof *app->reply_msgs);
    app->reply_ptrs = calloc (cap, sizeof *app->reply_ptrs);
    app->reply_pos = calloc (cap, sizeof *app->reply_pos);
    app->reply_cap = app->reply_msgs && app->reply_ptrs && app->reply_pos ? cap : 0;
    return app->reply_cap ? 0 : -ENOMEM;
}

/* The scan marker: scan d->scan is complete. */
static void s_publish_marker (s_app_t *app, const cgs_dwell_t *d)
{
    Cgs__Bcis m = CGS__BCIS__INIT;
    m.uav_id = app->sensor.uav_id;
    m.scan_number = d->scan;
    m.scan_time_s = d->end_s;
    m.beam_azimuth_deg = d->az_to_deg;
    m.scan_end = true;
    app->svc.sim_time_s = d->end_s;
    cgs_service_publish (&app->svc, "bcis", &m.base);
}

/* The dwell's interrogation and its replies. */
static void s_publish (s_app_t *app, const cgs_dwell_t *d, const bcis_dwell_out_t *out)
{
    if (s_reserve (app, out->reply_count) < 0) {
        cgs_health_set_error (app->svc.health, "out of memory for a dwell's replies");
        return;
    }
    double t = (d->start_s + d->end_s) / 2;
    for (size_t i = 0; i < out->reply_count; i++) {
        const bcis_reply_t *r = &out->replies[i];
        Cgs__BcisReply *m = &app->reply_msgs[i];
        cgs__bcis_reply__init (m);
        cgs__enu__init (&app->reply_pos[i]);
        app->reply_pos[i].east_m = r->position.e_m;
        app->reply_pos[i].north_m = r->position.n_m;
        app->reply_pos[i].up_m = r->position.u_m;
        m->responder_id = r->responder_id;
        m->marking = (char *)r->marking;
        m->position = &app->reply_pos[i];
        m->sim_time_s = t;
        m->azimuth_deg = r->azimuth_deg;
        m->range_m = r->range_m;
        m->snr_up_db = r->snr_up_db;
        m->snr_down_db = r->snr_down_db;
        app->reply_ptrs[i] = m;
    }
    Cgs__Bcis b = CGS__BCIS__INIT;
    b.uav_id = app->sensor.uav_id;
    b.scan_number = d->scan;
    b.scan_time_s = t;
    b.beam_azimuth_deg = d->az_center_deg;
    b.n_replies = out->reply_count;
    b.replies = app->reply_ptrs;
    app->svc.sim_time_s = t;
    cgs_service_publish (&app->svc, "bcis", &b.base);
}

static void s_run_dwell (s_app_t *app, uint64_t k)
{
    cgs_dwell_t d;
    cgs_scan_dwell (app->scan, k, app->sensor.heading_deg, &d);
    double t = (d.start_s + d.end_s) / 2;
    cgs_enu_t uav = cgs_sensor_uav_at (&app->sensor, t);
    size_t n = s_targets_at (app, t);
    bcis_dwell_out_t out;
    if (bcis_interrogator_dwell (app->bcis, &d, uav, app->targets, n, &out) < 0) {
        cgs_health_set_error (app->svc.health, "out of memory: an interrogation was not modelled");
    } else {
        app->dwells_run++;
        app->interrogated += out.truth_count;
        app->replies += out.reply_count;
        for (size_t i = 0; i < out.truth_count; i++)
            app->blocked += out.truth[i].blocked;
        s_publish (app, &d, &out);
    }
    if (d.scan_end) { // the scan ends even when a dwell of it could not be modelled
        s_publish_marker (app, &d);
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
        cgs_log (LOG_INFO, "interrogator on %s (entity %u) at t=%.2f s", app->sensor.uav_name,
                 app->sensor.uav_id, t);
    uint64_t end, skipped;
    cgs_pace_t how = cgs_scan_pace (app->scan, &app->pace, t, S_STALE_S, &end, &skipped);
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

static int s_setup (s_app_t *app, char *err, size_t errlen)
{
    int rc =
        cgs_sensor_setup (&app->sensor, &app->svc, "bcisd", 0xC2B2AE3D27D4EB4Full, err, errlen);
    if (rc < 0)
        return rc;
    const cgs_scenario_uav_t *u = app->sensor.uav;
    // Parameters: --params, else the instance's `params =`, else the UAV's bcis_params.
    const char *params = *app->svc.params ? app->svc.params : u->bcis_params;
    bcis_params_defaults (&app->params);
    if (params && *params) {
        if ((rc = bcis_params_load (params, &app->params, err, errlen)) < 0)
            return rc;
        cgs_log (LOG_INFO, "BCIS parameters from %s", params);
    } else {
        cgs_log (LOG_INFO, "BCIS parameters: the built-in defaults (no parameter file named)");
    }
    app->bcis = bcis_interrogator_new (&app->params, app->sensor.terrain, app->sensor.seed);
    app->ents = cgs_entities_new ();
    if (!app->bcis || !app->ents) {
        snprintf (err, errlen, "out of memory");
        return -ENOMEM;
    }
    app->scan = bcis_interrogator_scan (app->bcis);
    const bcis_params_t *p = &app->params;
    static const char *const mods[] = {"BPSK", "QPSK", "non-coherent BFSK"};
    cgs_log (LOG_INFO,
             "%s: %.1f GHz, %g x %g deg beam at %g deg/s, %u dwells of %.1f ms per %s, %s at "
             "%g bit/s, messages %d/%d bits, range %.0f..%.0f m, rain %g mm/h, foliage %s",
             app->sensor.uav_name, p->frequency_hz / 1e9, p->azimuth_beamwidth_deg,
             p->elevation_beamwidth_deg, p->scan_rate_dps, app->scan->dwells,
             app->scan->dwell_s * 1e3, p->scan_mode == CGS_SCAN_FULL ? "revolution" : "sector pass",
             mods[p->modulation], p->data_rate_bps, p->interrogation_bits, p->reply_bits,
             p->min_range_m, p->max_range_m, p->rain_rate_mmph, p->foliage ? "on" : "off");
    return 0;
}

int main (int argc, char **argv)
{
    gsl_set_error_handler_off (); // GSL reports through return codes; its handler would abort
    static s_app_t app;
    cgs_service_info_t info = {
        .program = "bcisd",
        .summary = "Scanning BCIS interrogator model of one UAV.",
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
    cgs_log (LOG_INFO,
             "%llu interrogations (one a dwell; %llu dwells skipped): %llu transponders in the "
             "beam, %llu behind terrain, %llu replies",
             (unsigned long long)app.dwells_run, (unsigned long long)app.pace.skipped,
             (unsigned long long)app.interrogated, (unsigned long long)app.blocked,
             (unsigned long long)app.replies);
done:
    bcis_interrogator_destroy (&app.bcis);
    cgs_entities_destroy (&app.ents);
    cgs_sensor_fini (&app.sensor);
    free (app.targets);
    free (app.reply_msgs);
    free (app.reply_ptrs);
    free (app.reply_pos);
    cgs_service_fini (&app.svc);
    return exit_code;
}
