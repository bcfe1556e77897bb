/* bcisd — the scanning BCIS interrogator of one UAV: follows the UAV (`uav`)
 * and the ground entities (`entity`), interrogates once a dwell as its scan
 * sweeps and simulation time passes, and publishes each interrogation's
 * replies and the end of each scan on `bcis`. The model is in bcis_*.c, the
 * handling of its inputs and outputs in bcis_adapter.c; this file wires the
 * adapter to the bus. */
#include "bcis_adapter.h"
#include "bcis_params.h"
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

typedef struct {
    cgs_service_t *svc;
    cgs_sensor_t sensor; // its UAV, scenario and terrain
    bcis_params_t params;
    bcis_adapter_t *adapter;
} s_app_t;

static void s_on_message (void *arg, const char *topic, const ProtobufCMessage *msg,
                          const Cgs__Header *hdr)
{
    s_app_t *app = arg;
    bcis_adapter_on_message (app->adapter, topic, msg, hdr);
}

static int s_setup (s_app_t *app, char *err, size_t errlen)
{
    int rc = cgs_sensor_setup (&app->sensor, app->svc, "bcisd", 0xC2B2AE3D27D4EB4Full, err, errlen);
    if (rc < 0)
        return rc;
    const cgs_scenario_uav_t *u = app->sensor.uav;
    // Parameters: --params, else the instance's `params =`, else the UAV's bcis_params.
    const char *params = cgs_service_params_path (app->svc);
    if (!*params)
        params = u->bcis_params;
    bcis_params_defaults (&app->params);
    if (params && *params) {
        if ((rc = bcis_params_load (params, &app->params, err, errlen)) < 0)
            return rc;
        cgs_log (LOG_INFO, "BCIS parameters from %s", params);
    } else {
        cgs_log (LOG_INFO, "BCIS parameters: the built-in defaults (no parameter file named)");
    }
    cgs_port_t port = cgs_service_port (app->svc);
    app->adapter = bcis_adapter_new (&app->params, &app->sensor, &port);
    if (!app->adapter) {
        snprintf (err, errlen, "out of memory");
        return -ENOMEM;
    }
    const cgs_scan_t *scan = bcis_adapter_scan (app->adapter);
    const bcis_params_t *p = &app->params;
    static const char *const mods[] = {"BPSK", "QPSK", "non-coherent BFSK"};
    cgs_log (LOG_INFO,
             "%s: %.1f GHz, %g x %g deg beam at %g deg/s, %u dwells of %.1f ms per %s, %s at "
             "%g bit/s, messages %d/%d bits, range %.0f..%.0f m, rain %g mm/h, foliage %s",
             app->sensor.uav_name, p->frequency_hz / 1e9, p->azimuth_beamwidth_deg,
             p->elevation_beamwidth_deg, p->scan_rate_dps, scan->dwells, scan->dwell_s * 1e3,
             p->scan_mode == CGS_SCAN_FULL ? "revolution" : "sector pass", mods[p->modulation],
             p->data_rate_bps, p->interrogation_bits, p->reply_bits, p->min_range_m, p->max_range_m,
             p->rain_rate_mmph, p->foliage ? "on" : "off");
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
    for (size_t i = 0; bcis_adapter_topics[i]; i++)
        if (cgs_service_subscribe (app.svc, bcis_adapter_topics[i], s_on_message, &app) < 0)
            goto done;
    exit_code = cgs_service_run (app.svc);
    const bcis_adapter_stats_t *st = bcis_adapter_stats (app.adapter);
    cgs_log (LOG_INFO,
             "%llu interrogations (one a dwell; %llu dwells skipped): %llu transponders in the "
             "beam, %llu behind terrain, %llu replies",
             (unsigned long long)st->dwells_run, (unsigned long long)st->skipped,
             (unsigned long long)st->interrogated, (unsigned long long)st->blocked,
             (unsigned long long)st->replies);
done:
    bcis_adapter_destroy (&app.adapter);
    cgs_sensor_fini (&app.sensor);
    cgs_service_destroy (&app.svc);
    return exit_code;
}
