/* uavsim — ground truth: reads the scenario, builds the terrain, flies the
 * UAVs and drives the ground vehicles in fixed simulation steps paced by the
 * time scale, publishes `clock`, `entity` and `uav`, serves the task and
 * clock commands, and checkpoints the world so a restarted uavsim continues
 * where it was. The models are in uavsim_*.c, the stepping, publication and
 * UAV commands in uavsim_adapter.c; this file paces the adapter by the wall
 * clock and wires it to the bus. */
#include "cgs_ckpt.h"
#include "cgs_lifecycle.h"
#include "cgs_log.h"
#include "cgs_service.h"
#include "uavsim_adapter.h"
#include "uavsim_world.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#define S_TICK_S   0.005 // pacing timer, wall seconds
#define S_BUDGET_S 0.010 // most wall time one pacing tick may spend stepping

typedef struct {
    cgs_service_t *svc;
    cgs_geo_t *frame;
    uavsim_world_t *world;
    uavsim_adapter_t *adapter;
    bool fresh; // --fresh: ignore the saved state
    double time_scale;
    bool paused;
    double anchor_wall_s;      // monotonic wall time when pacing was last anchored
    uint64_t anchor_tick;      // world tick then
    uint64_t lag_events;       // times the simulation fell behind and re-anchored
    double next_paused_wall_s; // while paused: wall time of the next republication
    char detail[256];
} s_app_t;

static int s_on_option (void *arg, const char *name, const char *value, char *why, size_t whylen)
{
    s_app_t *app = arg;
    (void)value;
    (void)why;
    (void)whylen;
    if (strcmp (name, "fresh") == 0)
        app->fresh = true;
    return 0;
}

static const cgs_service_option_t s_options[] = {
    {"fresh", false, NULL, "start from the scenario, ignoring the saved state"},
    {NULL, false, NULL, NULL},
};

static void s_anchor (s_app_t *app)
{
    app->anchor_wall_s = cgs_loop_now ();
    app->anchor_tick = uavsim_world_tick (app->world);
}

static void s_publish_clock (s_app_t *app)
{
    uavsim_adapter_set_pacing (app->adapter, app->time_scale, app->paused);
    uavsim_adapter_publish_clock (app->adapter);
}

static void s_publish_due (s_app_t *app, bool all)
{
    uavsim_adapter_set_pacing (app->adapter, app->time_scale, app->paused);
    uavsim_adapter_publish_due (app->adapter, all);
}

/* ---- pacing ------------------------------------------------------------------------- */

static void s_on_tick (void *arg)
{
    s_app_t *app = arg;
    if (app->paused) {
        // Time stands still, but the state is still republished (1 Hz), so a
        // subscriber that starts now sees the world and the paused clock.
        double now = cgs_loop_now ();
        if (now >= app->next_paused_wall_s) {
            s_publish_due (app, true);
            app->next_paused_wall_s = now + 1.0;
        }
        return;
    }
    double step = uavsim_world_step_s (app->world);
    double elapsed = cgs_loop_now () - app->anchor_wall_s;
    uint64_t target = app->anchor_tick + (uint64_t)floor (elapsed * app->time_scale / step);
    uint64_t tick = uavsim_world_tick (app->world);
    if (target <= tick)
        return;
    uint64_t behind = target - tick;
    // Run what is due, but never hold the loop for more than S_BUDGET_S: it
    // must go on serving commands, signals, health and the watchdog. What did
    // not fit is dropped (simulation time slips) rather than piled up.
    double start = cgs_loop_now ();
    uint64_t done = 0;
    uavsim_adapter_set_pacing (app->adapter, app->time_scale, app->paused);
    while (done < behind) {
        uavsim_adapter_step (app->adapter);
        done++;
        if ((done & 15) == 0 && cgs_loop_now () - start > S_BUDGET_S)
            break;
    }
    if (done < behind) {
        s_anchor (app);
        if (app->lag_events++ == 0 || app->lag_events % 1000 == 0) {
            char why[160];
            snprintf (
                why, sizeof why,
                "the simulation cannot keep time scale %g: it runs slower (lagged %llu times)",
                app->time_scale, (unsigned long long)app->lag_events);
            cgs_log (LOG_WARNING, "%s", why);
            cgs_health_set_error (cgs_service_health (app->svc), why);
        }
    }
}

/* ---- state (the checkpoint) ----------------------------------------------------------
 * Saved state: a cgs_ckpt frame "USIM", version 1, of the time scale (f64),
 * whether paused (u8) and the world's own frame (bytes). */

#define S_STATE_MAGIC   "USIM"
#define S_STATE_VERSION 1u
#define S_STATE_WHAT    "uavsim state"

static int s_save (void *arg, uint8_t **ret_buf, size_t *ret_len)
{
    s_app_t *app = arg;
    uint8_t *world = NULL;
    size_t len = 0;
    int rc = uavsim_world_save (app->world, &world, &len);
    if (rc < 0)
        return rc;
    cgs_ckpt_writer_t w;
    cgs_ckpt_writer_init (&w, S_STATE_MAGIC, S_STATE_VERSION);
    cgs_ckpt_put_f64 (&w, app->time_scale);
    cgs_ckpt_put_bool (&w, app->paused);
    cgs_ckpt_put_bytes (&w, world, len);
    free (world);
    return cgs_ckpt_writer_finish (&w, ret_buf, ret_len);
}

static int s_restore (s_app_t *app, const uint8_t *buf, size_t len, char *err, size_t errlen)
{
    cgs_ckpt_reader_t r;
    int rc =
        cgs_ckpt_open (&r, buf, len, S_STATE_MAGIC, S_STATE_VERSION, S_STATE_WHAT, err, errlen);
    if (rc < 0)
        return rc;
    double scale = cgs_ckpt_get_f64 (&r);
    bool paused = cgs_ckpt_get_bool (&r);
    size_t world_len = 0;
    const uint8_t *world = cgs_ckpt_get_bytes (&r, &world_len);
    if ((rc = cgs_ckpt_end (&r, S_STATE_WHAT, err, errlen)) < 0)
        return rc;
    if (!(scale > 0) || scale > 1000) {
        snprintf (err, errlen, "a %s with time scale %g, not in (0, 1000]", S_STATE_WHAT, scale);
        return -EINVAL;
    }
    if ((rc = uavsim_world_restore (app->world, world, world_len, err, errlen)) < 0)
        return rc;
    app->time_scale = scale;
    app->paused = paused;
    return 0;
}

/* ---- commands ----------------------------------------------------------------------- */

static void s_on_command (void *arg, const Cgs__Command *cmd, Cgs__Reply *reply)
{
    s_app_t *app = arg;
    if (uavsim_adapter_command (app->adapter, cmd, reply) == 0 ||
        reply->status == CGS__REPLY_STATUS__REPLY_STATUS_UNSUPPORTED)
        return; // a UAV's command (judged and logged there), or not uavsim's
    switch (cmd->body_case) {
    case CGS__COMMAND__BODY_PAUSE:
        app->paused = true;
        s_publish_clock (app);
        break;
    case CGS__COMMAND__BODY_RESUME:
        app->paused = false;
        s_anchor (app);
        s_publish_clock (app);
        break;
    case CGS__COMMAND__BODY_SET_TIME_SCALE: {
        double x = cmd->set_time_scale->time_scale;
        if (!(x > 0) || x > 1000) {
            snprintf (app->detail, sizeof app->detail, "time scale must be in (0, 1000]");
            reply->status = CGS__REPLY_STATUS__REPLY_STATUS_ERROR;
            reply->error = app->detail;
            return;
        }
        app->time_scale = x;
        s_anchor (app);
        s_publish_clock (app);
        break;
    }
    default: // PING
        break;
    }
    snprintf (app->detail, sizeof app->detail, "%s at t=%.2f s, time scale %g%s",
              cgs_cmd_name (cmd), uavsim_world_time (app->world), app->time_scale,
              app->paused ? ", paused" : "");
    cgs_log (LOG_INFO, "%s (from %s #%llu)", app->detail, cmd->client_id,
             (unsigned long long)cmd->command_number);
    reply->detail = app->detail;
}

/* guidanced's target estimate, for a camera staring at the target. */
static void s_on_intercept (void *arg, const char *topic, const ProtobufCMessage *msg,
                            const Cgs__Header *hdr)
{
    (void)topic;
    s_app_t *app = arg;
    uavsim_adapter_on_intercept (app->adapter, (const Cgs__Intercept *)msg, hdr->sim_time_s);
}

static void s_on_checkpoint (void *arg)
{
    s_app_t *app = arg;
    if (cgs_service_save_state (app->svc) < 0)
        cgs_log (LOG_WARNING, "checkpoint not written (see health)");
    cgs_notify_status ("t=%.1f s, x%g%s", uavsim_world_time (app->world), app->time_scale,
                       app->paused ? " paused" : "");
}

/* ---- main ------------------------------------------------------------------------------ */

int main (int argc, char **argv)
{
    static s_app_t app;
    cgs_service_info_t info = {
        .program = "uavsim",
        .summary = "Ground truth: terrain, UAVs, ground vehicles and the simulation clock.",
        .options = s_options,
        .on_option = s_on_option,
        .option_arg = &app,
    };
    int rc = cgs_service_new (&info, argc, argv, &app.svc);
    if (rc != 0)
        return rc > 0 ? 0 : 1;
    int exit_code = 1;
    char err[1024] = "";
    const char *scenario = cgs_service_scenario_path (app.svc);
    if (!*scenario) {
        cgs_log (LOG_ERR, "no scenario: give --scenario FILE or `scenario =` in %s",
                 cgs_service_exercise_path (app.svc));
        goto done;
    }
    cgs_geodetic_t o = cgs_exercise_origin (cgs_service_exercise (app.svc));
    app.frame = cgs_geo_new (o.lat_deg, o.lon_deg, o.height_m);
    cgs_scenario_t *sc = NULL;
    if (!app.frame ||
        cgs_scenario_load (scenario, app.frame, cgs_exercise_seed (cgs_service_exercise (app.svc)),
                           &sc, err, sizeof err) < 0 ||
        uavsim_world_new (sc, app.frame, &app.world, err, sizeof err) < 0) {
        cgs_log (LOG_ERR, "%s", *err ? err : "bad exercise origin");
        goto done;
    }
    const cgs_scenario_t *scn = uavsim_world_scenario (app.world);
    cgs_log (LOG_INFO, "scenario %s: %zu UAV%s, %zu vehicles, terrain %dx%d at %.0f m", scenario,
             scn->uav_count, scn->uav_count == 1 ? "" : "s", scn->vehicle_count,
             cgs_terrain_cols (uavsim_world_terrain (app.world)),
             cgs_terrain_rows (uavsim_world_terrain (app.world)),
             cgs_terrain_resolution (uavsim_world_terrain (app.world)));
    // Stand-off: a warning, at start and with --check.
    cgs_standoff_t near[16];
    size_t n_near = cgs_scenario_standoff (scn, near, 16);
    for (size_t i = 0; i < n_near && i < 16; i++) {
        char w[512];
        cgs_scenario_standoff_text (scn, &near[i], w, sizeof w);
        cgs_log (LOG_WARNING, "%s", w);
        if (cgs_service_check_only (app.svc))
            printf ("%s: warning: %s\n", cgs_service_instance_name (app.svc), w);
    }
    if (n_near > 16)
        cgs_log (LOG_WARNING, "%zu more loiter orbits within their stand-off of a route",
                 n_near - 16);
    if (cgs_service_check_only (app.svc)) {
        printf ("%s: scenario %s is good\n", cgs_service_instance_name (app.svc), scenario);
        exit_code = 0;
        goto done;
    }
    cgs_port_t port = cgs_service_port (app.svc);
    app.adapter = uavsim_adapter_new (app.world, o, &port);
    if (!app.adapter) {
        cgs_log (LOG_ERR, "out of memory");
        goto done;
    }
    app.time_scale = cgs_service_time_scale (app.svc);
    if (cgs_service_serve_commands (app.svc, s_on_command, s_save, &app) < 0)
        goto done;
    const uint8_t *saved = NULL;
    size_t saved_len = 0;
    cgs_service_saved_state (app.svc, &saved, &saved_len);
    if (saved_len > 0 && app.fresh) {
        cgs_log (LOG_NOTICE, "--fresh: the saved state is ignored; starting from the scenario");
    } else if (saved_len > 0) {
        if (s_restore (&app, saved, saved_len, err, sizeof err) < 0) {
            cgs_log (LOG_WARNING, "saved state ignored (%s); starting from the scenario", err);
            cgs_health_set_error (cgs_service_health (app.svc), err);
        } else {
            cgs_log (LOG_NOTICE, "resumed from the saved state at t=%.2f s (tick %llu)",
                     uavsim_world_time (app.world),
                     (unsigned long long)uavsim_world_tick (app.world));
        }
    }
    if (cgs_service_time_scale_given (app.svc))
        app.time_scale = cgs_service_time_scale (app.svc); // --time-scale on the command line wins
    s_anchor (&app);
    s_publish_due (&app, true);
    // guidanced's target estimates, for a camera staring at the target (an
    // exercise without a guidanced has none to hear).
    const cgs_instance_t *gd[1];
    if (cgs_exercise_publishers_of (cgs_service_exercise (app.svc), "intercept", gd, 1) > 0 &&
        cgs_service_subscribe (app.svc, "intercept", s_on_intercept, &app) < 0)
        goto done;
    cgs_loop_t *loop = cgs_service_loop (app.svc);
    cgs_loop_add_timer (loop, S_TICK_S, s_on_tick, &app);
    cgs_loop_add_timer (loop, scn->settings.checkpoint_interval_s, s_on_checkpoint, &app);
    exit_code = cgs_service_run (app.svc);
    // A clean stop saves the world as it is, so a restart continues from here.
    if (cgs_service_save_state (app.svc) == 0)
        cgs_log (LOG_INFO, "saved the world at t=%.2f s", uavsim_world_time (app.world));
done:
    uavsim_adapter_destroy (&app.adapter);
    uavsim_world_destroy (&app.world);
    cgs_geo_destroy (&app.frame);
    cgs_service_destroy (&app.svc);
    return exit_code;
}
