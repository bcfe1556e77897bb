/* guidanced — the UAV control station's intercept logic: serves the
 * operator's designate, cancel and settings commands, keeps the latest
 * tracks, runs one intercept per UAV (gd_intercept), delivers the UAV's
 * tasks to uavsim, publishes `intercept`, runs the scenario's operator
 * script when no operator designates, and keeps all of it in its state file
 * so a restart resumes the intercept. What is done to the inputs, the
 * commands, the tasks and the state is in gd_adapter.c; this file wires the
 * adapter to the bus and to uavsim's command endpoint, and keeps the state
 * file. Whole intercepts in lockstep are `mscgs montecarlo`. */
#include "cgs_lifecycle.h"
#include "cgs_log.h"
#include "cgs_scenario.h"
#include "cgs_service.h"
#include "gd_adapter.h"
#include "gd_intercept.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/time.h>

#define S_DELIVER_S  0.2 // wall seconds between delivery attempts
#define S_HOLD_S     5.0 // wall seconds commands wait for the tracker after a start
#define S_SEND_MS    400 // how long one delivery waits for uavsim
#define S_FORWARD_MS 500 // altitude and speed commands forwarded to uavsim

typedef struct {
    cgs_service_t *svc;
    bool fresh;
    gd_params_t params;
    cgs_geo_t *frame;
    cgs_scenario_t *scenario;
    cgs_terrain_t *terrain;
    gd_adapter_t *adapter; // tracks, intercepts, commands, script, tasks, state
    // Delivery to uavsim.
    const cgs_instance_t *uavsim;
    cgs_cmd_client_t *client;
    char detail[512]; // a forwarded command's reply
    // Commands wait until the tracker is heard after a start (S_HOLD_S at most).
    double hold_until;
} s_app_t;

/* ---- delivery of tasks to uavsim ----------------------------------------------------------- */

static int s_save_now (s_app_t *app)
{
    int rc = cgs_service_save_state (app->svc);
    if (rc < 0)
        cgs_log (LOG_WARNING, "state not written (see health)");
    return rc;
}

/* Send each task not yet delivered to uavsim once (under the command
 * number it was given, so a resend after a timeout or a restart is a
 * duplicate to uavsim, never a second task). */
static void s_deliver (s_app_t *app)
{
    if (!app->client)
        return;
    size_t cursor = 0;
    gd_adapter_task_t task;
    while (gd_adapter_next_task (app->adapter, &cursor, &task)) {
        if (task.new_number && s_save_now (app) < 0)
            continue;                     // the number must be on disk before it is used
        Cgs__Command cmd = *task.command; // the client fills in its id and number
        Cgs__Reply *reply = NULL;
        char err[256];
        cgs_cmd_client_set_next_number (app->client, task.command_number);
        if (cgs_cmd_client_call (app->client, &cmd, S_SEND_MS, 1, &reply, err, sizeof err) < 0) {
            cgs_health_set_error (cgs_service_health (app->svc), err);
            gd_adapter_task_answered (app->adapter, &task, NULL); // tried again later
            continue;
        }
        gd_adapter_task_answered (app->adapter, &task, reply);
        cgs_cmd_reply_free (&reply);
    }
}

/* Save the state when the adapter changed it on its own (a script line). */
static void s_save_if_dirty (s_app_t *app)
{
    if (gd_adapter_take_dirty (app->adapter))
        s_save_now (app);
}

static void s_on_deliver (void *arg)
{
    s_app_t *app = arg;
    gd_adapter_tick (app->adapter);
    s_save_if_dirty (app);
    s_deliver (app);
}

/* ---- the bus ----------------------------------------------------------------------------- */

/* A message of one of the adapter's topics: into the adapter, then the
 * state saved if it changed, the tasks delivered, and the held commands
 * taken once the tracker is heard. */
static void s_on_message (void *arg, const char *topic, const ProtobufCMessage *msg,
                          const Cgs__Header *hdr)
{
    s_app_t *app = arg;
    gd_adapter_on_message (app->adapter, topic, msg, hdr);
    s_save_if_dirty (app);
    s_deliver (app);
    if (cgs_service_commands_held (app->svc) && gd_adapter_heard_tracks (app->adapter)) {
        cgs_service_hold_commands (app->svc, false);
        cgs_log (LOG_INFO, "taking commands: the tracker's picture is heard (%zu tracks)",
                 gd_adapter_track_count (app->adapter));
    }
}

/* The tracker not heard within S_HOLD_S of the start: take commands anyway. */
static void s_on_hold (void *arg)
{
    s_app_t *app = arg;
    if (cgs_service_commands_held (app->svc) && cgs_loop_now () >= app->hold_until) {
        cgs_service_hold_commands (app->svc, false);
        cgs_log (LOG_WARNING, "taking commands without the tracker's picture (none in %.0f s)",
                 S_HOLD_S);
    }
}

/* ---- commands ---------------------------------------------------------------------------- */

static void s_refuse (s_app_t *app, Cgs__Reply *reply, const char *why)
{
    snprintf (app->detail, sizeof app->detail, "%s", why);
    reply->status = CGS__REPLY_STATUS__REPLY_STATUS_ERROR;
    reply->error = app->detail;
}

/* Forward altitude or speed to uavsim and answer with its verdict. */
static void s_forward (s_app_t *app, const Cgs__Command *cmd, Cgs__Reply *reply)
{
    if (!app->client)
        return s_refuse (app, reply, "the exercise has no uavsim command endpoint");
    Cgs__Command fwd = *cmd;
    Cgs__Reply *r = NULL;
    char err[256];
    cgs_cmd_client_set_next_number (app->client, gd_adapter_take_number (app->adapter));
    if (cgs_cmd_client_call (app->client, &fwd, S_FORWARD_MS, 2, &r, err, sizeof err) < 0)
        return s_refuse (app, reply, err);
    if (r->status != CGS__REPLY_STATUS__REPLY_STATUS_OK) {
        snprintf (app->detail, sizeof app->detail, "uavsim: %s", r->error ? r->error : "refused");
        reply->status = CGS__REPLY_STATUS__REPLY_STATUS_ERROR;
        reply->error = app->detail;
    } else {
        snprintf (app->detail, sizeof app->detail, "uavsim: %s", r->detail ? r->detail : "ok");
        reply->detail = app->detail;
    }
    cgs_cmd_reply_free (&r);
}

/* A command: judged by the adapter, or forwarded to uavsim. The command
 * server writes the state after this, before the reply goes out; the task a
 * designation makes goes out at the next delivery tick, after that. */
static void s_on_command (void *arg, const Cgs__Command *cmd, Cgs__Reply *reply)
{
    s_app_t *app = arg;
    if (gd_adapter_command (app->adapter, cmd, reply) == 1)
        s_forward (app, cmd, reply);
    (void)gd_adapter_take_dirty (app->adapter); // saved by the command server
}

/* ---- state ------------------------------------------------------------------------------- */

static int s_save (void *arg, uint8_t **ret_buf, size_t *ret_len)
{
    s_app_t *app = arg;
    return gd_adapter_save (app->adapter, ret_buf, ret_len);
}

static void s_on_checkpoint (void *arg)
{
    s_app_t *app = arg;
    for (size_t i = 0; i < gd_adapter_uav_count (app->adapter); i++) {
        gd_status_t st;
        gd_intercept_status (gd_adapter_intercept (app->adapter, i), &st);
        cgs_notify_status ("t=%.1f s, %s %s track %u", gd_adapter_time (app->adapter),
                           gd_adapter_uav_name (app->adapter, i), gd_phase_name (st.phase),
                           st.track_id);
    }
    s_save_now (app);
}

/* ---- setup and main
 * ------------------------------------------------------------------------------ */

static const cgs_service_option_t s_options[] = {
    {"fresh", false, NULL, "start idle, ignoring the saved intercept"},
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
    gd_params_defaults (&app->params);
    const char *params = cgs_service_params_path (app->svc);
    if (*params) {
        int rc = gd_params_load (params, &app->params, err, errlen);
        if (rc < 0)
            return rc;
        cgs_log (LOG_INFO, "guidance parameters from %s", params);
    } else {
        cgs_log (LOG_INFO, "guidance parameters: the built-in defaults (no parameter file named)");
    }
    int rc =
        cgs_service_load_scene (app->svc, &app->frame, &app->scenario, &app->terrain, err, errlen);
    if (rc < 0)
        return rc;
    cgs_port_t port = cgs_service_port (app->svc);
    bool too_many = false;
    app->adapter = gd_adapter_new (&app->params, app->scenario, app->terrain, &port, &too_many);
    if (!app->adapter) {
        if (too_many)
            snprintf (err, errlen, "%s: guidanced serves at most %d UAVs",
                      cgs_service_scenario_path (app->svc), GD_ADAPTER_UAVS_MAX);
        else
            snprintf (err, errlen, "out of memory");
        return too_many ? -EINVAL : -ENOMEM;
    }
    // uavsim takes the tasks.
    app->uavsim = cgs_exercise_first_of (cgs_service_exercise (app->svc), "uavsim");
    if (app->uavsim && !*app->uavsim->command)
        app->uavsim = NULL;
    if (!app->uavsim)
        cgs_log (LOG_WARNING, "the exercise names no uavsim with a command endpoint: intercepts "
                              "are planned and published but not flown");
    return 0;
}

/* A client id for uavsim that outlives restarts (kept in the state) and
 * differs from any earlier run's, so numbers never collide. */
static void s_new_client_id (s_app_t *app)
{
    struct timeval tv;
    gettimeofday (&tv, NULL);
    char id[128];
    snprintf (id, sizeof id, "%s@%lld.%06ld", cgs_service_instance_name (app->svc),
              (long long)tv.tv_sec, (long)tv.tv_usec);
    gd_adapter_set_client_id (app->adapter, id);
}

int main (int argc, char **argv)
{
    static s_app_t app;
    cgs_service_info_t info = {
        .program = "guidanced",
        .summary = "UAV control station intercept logic: designation, head-on waypoint, "
                   "precision approach, footprint.",
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
    size_t uavs = gd_adapter_uav_count (app.adapter);
    cgs_log (LOG_INFO, "%zu UAV%s, %zu operator script line%s; uavsim at %s", uavs,
             uavs == 1 ? "" : "s", app.scenario->designation_count,
             app.scenario->designation_count == 1 ? "" : "s",
             app.uavsim ? app.uavsim->command : "(none)");
    if (cgs_service_check_only (app.svc)) {
        printf ("%s: configuration is good\n", cgs_service_instance_name (app.svc));
        exit_code = 0;
        goto done;
    }
    if (cgs_service_serve_commands (app.svc, s_on_command, s_save, &app) < 0)
        goto done;
    s_new_client_id (&app);
    const uint8_t *saved = NULL;
    size_t saved_len = 0;
    cgs_service_saved_state (app.svc, &saved, &saved_len);
    if (saved_len > 0 && app.fresh) {
        cgs_log (LOG_NOTICE, "--fresh: the saved intercept is ignored; starting idle");
    } else if (saved_len > 0) {
        if (gd_adapter_restore (app.adapter, saved, saved_len, err, sizeof err) < 0) {
            // The adapter is idle again.
            cgs_log (LOG_WARNING, "saved state ignored (%s); starting idle", err);
            cgs_health_set_error (cgs_service_health (app.svc), err);
            s_new_client_id (&app);
        } else {
            for (size_t i = 0; i < uavs; i++) {
                gd_status_t st;
                gd_intercept_status (gd_adapter_intercept (app.adapter, i), &st);
                cgs_log (LOG_NOTICE, "resumed %s: %s, track %u (%s)",
                         gd_adapter_uav_name (app.adapter, i), gd_phase_name (st.phase),
                         st.track_id, st.reason);
            }
        }
    }
    if (app.uavsim) {
        app.client = cgs_cmd_client_new_exact (cgs_service_ctx (app.svc), app.uavsim->command,
                                               gd_adapter_client_id (app.adapter),
                                               gd_adapter_last_number (app.adapter) + 1);
        if (!app.client || cgs_curve_protect_client (cgs_service_curve (app.svc), app.client,
                                                     app.uavsim->public_key) < 0) {
            cgs_log (LOG_ERR, "cannot make a command client for %s", app.uavsim->command);
            goto done;
        }
    }
    for (const char *const *t = gd_adapter_topics; *t; t++)
        if (cgs_service_subscribe (app.svc, *t, s_on_message, &app) < 0)
            goto done;
    cgs_loop_t *loop = cgs_service_loop (app.svc);
    cgs_loop_add_timer (loop, S_DELIVER_S, s_on_deliver, &app);
    cgs_loop_add_timer (loop, 5.0, s_on_checkpoint, &app);
    // A designation needs the tracks: until the tracker is heard (its next
    // batch), commands wait unanswered rather than be refused for want of them.
    cgs_service_hold_commands (app.svc, true);
    app.hold_until = cgs_loop_now () + S_HOLD_S;
    cgs_loop_add_timer (loop, 0.1, s_on_hold, &app);
    exit_code = cgs_service_run (app.svc);
    s_save_now (&app);
done:
    gd_adapter_destroy (&app.adapter);
    cgs_cmd_client_destroy (&app.client);
    cgs_terrain_destroy (&app.terrain);
    cgs_scenario_destroy (&app.scenario);
    cgs_geo_destroy (&app.frame);
    cgs_service_destroy (&app.svc);
    return exit_code;
}
