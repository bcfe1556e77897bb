/* stationd — the UAV control station's tactical map, served to browsers:
 * takes every topic the map shows into its picture (st_state), pushes the
 * picture to every open page at push_hz, relays the imaging sensor's live
 * video (topic `video`) to the pages that play it, and turns each page's
 * operator actions into guidanced, uavsim and imagerd commands (st_request),
 * answering that page with the result. The web server is st_web (CivetWeb);
 * the terrain's shaded relief is made once at start (st_relief). This file
 * wires them to the bus. */
#include "cgs_geo.h"
#include "cgs_log.h"
#include "cgs_scenario.h"
#include "cgs_service.h"
#include "st_params.h"
#include "st_relief.h"
#include "st_request.h"
#include "st_state.h"
#include "st_web.h"

#include <errno.h>
#include <inttypes.h>
#include <json-c/json.h>
#include <limits.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

typedef struct {
    cgs_service_t *svc;
    st_params_t p;
    cgs_geo_t *frame;
    cgs_scenario_t *scenario;
    cgs_terrain_t *terrain;
    st_relief_t relief;
    bool have_relief;
    st_state_t *state;
    st_web_t *web;
    const cgs_instance_t *guidanced, *uavsim; // command endpoints ("" none)
    const cgs_instance_t *replay; // a replay exercise's `replay` (mscgs replay); NULL: live
    st_state_params_t state_params;
    uint64_t seq;
    uint64_t image_frame;     // of the path handed to the web server
    uint64_t video_other_uav; // video frames of a UAV whose picture is not shown
    char listen_override[64];
    long port_override; // -1 none
    char web_error[256];
    /* Counted in pages' threads. */
    uint64_t commands_ok, commands_refused, commands_unanswered, bad_requests, unauthorised;
} s_app_t;

/* Each open page's command clients, one per instance it commanded, made on
 * its first command to it. */
#define S_PAGE_CLIENTS 20 // guidanced, uavsim and an imagerd per UAV (the oldest is reused)

typedef struct {
    struct {
        const cgs_instance_t *to;
        cgs_cmd_client_t *client;
    } clients[S_PAGE_CLIENTS];
} s_page_t;

static void s_count (uint64_t *counter)
{
    __atomic_add_fetch (counter, 1, __ATOMIC_RELAXED);
}

static uint64_t s_read (uint64_t *counter)
{
    return __atomic_load_n (counter, __ATOMIC_RELAXED);
}

/* ---- bus ------------------------------------------------------------------------- */

static void s_took (s_app_t *app, int rc, const char *what)
{
    if (rc == -EINVAL)
        cgs_service_bad_input (app->svc, what);
    else if (rc == -ENOSPC)
        cgs_health_set_error (cgs_service_health (app->svc),
                              "the map's table of UAVs or radars is full: a message was dropped");
    else if (rc == -ENOMEM)
        cgs_health_set_error (cgs_service_health (app->svc),
                              "out of memory: the map dropped part of a message");
}

static void s_on_clock (void *arg, const char *topic, const ProtobufCMessage *msg,
                        const Cgs__Header *hdr)
{
    (void)topic;
    s_app_t *app = arg;
    const Cgs__Clock *c = (const Cgs__Clock *)msg;
    st_state_set_clock (app->state, c->sim_time_s, hdr ? hdr->epoch : 0);
    st_state_set_time_scale (app->state, c->time_scale, c->paused);
}

/* A replay's position. A seek starts the picture over: what was drawn
 * before is of another time. */
static void s_on_replay (void *arg, const char *topic, const ProtobufCMessage *msg,
                         const Cgs__Header *hdr)
{
    (void)topic, (void)hdr;
    s_app_t *app = arg;
    const Cgs__ReplayState *m = (const Cgs__ReplayState *)msg;
    bool fresh = false;
    if (st_state_take_replay (app->state, m, &fresh) == 0 && fresh) {
        st_state_t *s = st_state_new (&app->state_params);
        if (!s)
            return;
        st_state_destroy (&app->state);
        app->state = s;
        st_state_take_replay (app->state, m, NULL);
        st_web_video_restart (app->web);
        cgs_log (LOG_INFO, "replay: at %.1f s (generation %u): the picture starts over", m->t_s,
                 m->generation);
    }
}

static void s_on_entity (void *arg, const char *topic, const ProtobufCMessage *msg,
                         const Cgs__Header *hdr)
{
    (void)topic;
    s_app_t *app = arg;
    s_took (app, st_state_take_entities (app->state, (const Cgs__EntityBatch *)msg, hdr),
            "an entity without a valid id, position or velocity");
}

static void s_on_uav (void *arg, const char *topic, const ProtobufCMessage *msg,
                      const Cgs__Header *hdr)
{
    (void)topic;
    s_app_t *app = arg;
    s_took (app, st_state_take_uav (app->state, (const Cgs__Uav *)msg, hdr),
            "a uav message without an entity id, position or heading");
}

static void s_on_mti (void *arg, const char *topic, const ProtobufCMessage *msg,
                      const Cgs__Header *hdr)
{
    (void)topic;
    s_app_t *app = arg;
    s_took (app, st_state_take_mti (app->state, (const Cgs__Mti *)msg, hdr),
            "an mti message without a UAV id, or a hit without a position");
}

static void s_on_mti_scan (void *arg, const char *topic, const ProtobufCMessage *msg,
                           const Cgs__Header *hdr)
{
    (void)topic;
    s_app_t *app = arg;
    s_took (app, st_state_take_mti_scan (app->state, (const Cgs__MtiScan *)msg, hdr),
            "an mti.scan message without a UAV id");
}

static void s_on_bcis (void *arg, const char *topic, const ProtobufCMessage *msg,
                       const Cgs__Header *hdr)
{
    (void)topic;
    s_app_t *app = arg;
    s_took (app, st_state_take_bcis (app->state, (const Cgs__Bcis *)msg, hdr),
            "a bcis message without a UAV id, or a reply without a position or time");
}

static void s_on_track (void *arg, const char *topic, const ProtobufCMessage *msg,
                        const Cgs__Header *hdr)
{
    (void)topic;
    s_app_t *app = arg;
    s_took (app, st_state_take_tracks (app->state, (const Cgs__TrackBatch *)msg, hdr),
            "a track without an id, position or heading");
}

static void s_on_intercept (void *arg, const char *topic, const ProtobufCMessage *msg,
                            const Cgs__Header *hdr)
{
    (void)topic;
    s_app_t *app = arg;
    s_took (app, st_state_take_intercept (app->state, (const Cgs__Intercept *)msg, hdr),
            "an intercept without a UAV id, or with a route point without a position");
}

static void s_on_image (void *arg, const char *topic, const ProtobufCMessage *msg,
                        const Cgs__Header *hdr)
{
    (void)topic;
    s_app_t *app = arg;
    s_took (app, st_state_take_image (app->state, (const Cgs__Image *)msg, hdr),
            "an image message whose latest_path is not an absolute path");
    uint64_t frame;
    const char *path = st_state_image_path (app->state, &frame);
    // imagerd writes the file after it announces it: shown once it is there.
    if (*path && frame != app->image_frame && access (path, R_OK) == 0) {
        st_web_set_image (app->web, path);
        st_state_image_shown (app->state, frame);
        app->image_frame = frame;
    }
}

/* A video frame: its bytes to the /video pages when it is of the UAV whose
 * picture is shown; a stream that changed starts every page over. */
static void s_on_video (void *arg, const char *topic, const ProtobufCMessage *msg,
                        const Cgs__Header *hdr)
{
    (void)topic;
    s_app_t *app = arg;
    const Cgs__VideoFrame *m = (const Cgs__VideoFrame *)msg;
    bool relay = false, restart = false;
    int rc = st_state_take_video (app->state, m, hdr, &relay, &restart);
    if (rc < 0) {
        s_took (app, rc,
                "a video message without transport stream bytes (whole 188-byte packets, each "
                "starting 0x47)");
        return;
    }
    if (!relay) {
        app->video_other_uav++;
        return;
    }
    if (restart) {
        cgs_log (LOG_INFO, "video: a new stream (uav %u, frame %" PRIu64 "): the pages start over",
                 m->uav_id, m->frame_number);
        st_web_video_restart (app->web);
    }
    st_web_video_publish (app->web, m->ts.data, m->ts.len, m->keyframe);
}

/* The push tick: the picture to every page, and the counters into health. */
static void s_on_push (void *arg)
{
    s_app_t *app = arg;
    st_state_prune (app->state);
    size_t len = 0;
    char *json = st_state_json (app->state, ++app->seq, &len);
    if (json)
        st_web_publish (app->web, json, len);
    else
        cgs_health_set_error (cgs_service_health (app->svc), "out of memory: a push was skipped");
    st_web_stats_t ws;
    char err[256];
    st_web_stats (app->web, &ws, err, sizeof err);
    if (*err && strcmp (err, app->web_error) != 0) {
        cgs_log (LOG_WARNING, "web server: %s", err);
        snprintf (app->web_error, sizeof app->web_error, "%s", err);
    }
    cgs_health_t *h = cgs_service_health (app->svc);
    cgs_health_set_counter (h, "http_port", (uint64_t)st_web_port (app->web));
    cgs_health_set_counter (h, "pages", ws.pages);
    cgs_health_set_counter (h, "pages_total", ws.pages_total);
    cgs_health_set_counter (h, "pushes", ws.pushes);
    cgs_health_set_counter (h, "pushes_skipped", ws.skipped);
    cgs_health_set_counter (h, "push_bytes_max", ws.max_push_bytes);
    cgs_health_set_counter (h, "write_errors", ws.write_errors);
    cgs_health_set_counter (h, "origin_refused", ws.refused);
    cgs_health_set_counter (h, "pages_refused_full", ws.full);
    cgs_health_set_counter (h, "oversized_requests", ws.oversized);
    cgs_health_set_counter (h, "requests", ws.requests);
    cgs_health_set_counter (h, "commands_ok", s_read (&app->commands_ok));
    cgs_health_set_counter (h, "commands_refused", s_read (&app->commands_refused));
    cgs_health_set_counter (h, "commands_unanswered", s_read (&app->commands_unanswered));
    cgs_health_set_counter (h, "unauthorised", s_read (&app->unauthorised));
    cgs_health_set_counter (h, "bad_requests", s_read (&app->bad_requests));
    cgs_health_set_counter (h, "video_pages", ws.video_pages);
    cgs_health_set_counter (h, "video_pages_total", ws.video_pages_total);
    cgs_health_set_counter (h, "video_frames", ws.video_frames);
    cgs_health_set_counter (h, "video_other_uav", app->video_other_uav);
    cgs_health_set_counter (h, "video_sent", ws.video_sent);
    cgs_health_set_counter (h, "video_bytes", ws.video_bytes);
    cgs_health_set_counter (h, "video_dropped", ws.video_dropped);
    cgs_health_set_counter (h, "video_behind", ws.video_behind);
    cgs_health_set_counter (h, "video_restarts", ws.video_restarts);
    cgs_health_set_counter (h, "hits", st_state_hit_count (app->state));
    cgs_health_set_counter (h, "tracks", st_state_track_count (app->state));
}

/* ---- pages' requests (each in its page's own thread) ----------------------------- */

/* Send a JSON object to the page and release it. */
static void s_answer (st_web_conn_t *conn, json_object *o)
{
    size_t len = 0;
    const char *text = json_object_to_json_string_length (o, JSON_C_TO_STRING_PLAIN, &len);
    if (text)
        st_web_send (conn, text, len);
    json_object_put (o);
}

static json_object *s_reply_head (const char *type, int64_t req, const char *op)
{
    json_object *o = json_object_new_object ();
    json_object_object_add (o, "type", json_object_new_string (type));
    json_object_object_add (o, "req", json_object_new_int64 (req));
    if (op)
        json_object_object_add (o, "op", json_object_new_string (op));
    return o;
}

static void s_refuse (st_web_conn_t *conn, int64_t req, const char *op, const char *why)
{
    json_object *o = s_reply_head ("reply", req, op);
    json_object_object_add (o, "ok", json_object_new_boolean (0));
    json_object_object_add (o, "error", json_object_new_string (why));
    s_answer (conn, o);
}

/* A protocol error: the page sent something stationd cannot read. */
static void s_bad_request (s_app_t *app, st_web_conn_t *conn, const char *why)
{
    s_count (&app->bad_requests);
    json_object *o = json_object_new_object ();
    json_object_object_add (o, "type", json_object_new_string ("error"));
    json_object_object_add (o, "error", json_object_new_string (why));
    s_answer (conn, o);
}

static void s_mgrs (s_app_t *app, st_web_conn_t *conn, json_object *req, int64_t n)
{
    double e, no;
    json_object *o = s_reply_head ("mgrs", n, NULL);
    cgs_geodetic_t g;
    char grid[64];
    if (!st_request_number (req, "e", &e) || !st_request_number (req, "n", &no) || fabs (e) > 1e7 ||
        fabs (no) > 1e7) {
        json_object_object_add (o, "error", json_object_new_string ("mgrs needs numbers e and n"));
    } else if (cgs_geo_enu_to_geodetic (app->frame, (cgs_enu_t){e, no, 0}, &g) < 0 ||
               cgs_geo_to_mgrs (g, 5, grid, sizeof grid) < 0) {
        json_object_object_add (o, "error", json_object_new_string ("no MGRS for that point"));
    } else {
        json_object_object_add (o, "mgrs", json_object_new_string (grid));
        json_object_object_add (o, "lat_deg", json_object_new_double (g.lat_deg));
        json_object_object_add (o, "lon_deg", json_object_new_double (g.lon_deg));
    }
    s_answer (conn, o);
}

/* The page's client slot for instance to: its own, else a free one, else
 * the last one (its client closed for the new instance's). */
static cgs_cmd_client_t **s_client (s_page_t *page, const cgs_instance_t *to)
{
    size_t i = 0;
    while (i + 1 < S_PAGE_CLIENTS && page->clients[i].to && page->clients[i].to != to)
        i++;
    if (page->clients[i].to != to) {
        cgs_cmd_client_destroy (&page->clients[i].client);
        page->clients[i].to = to;
    }
    return &page->clients[i].client;
}

/* Send cmd to the instance and answer the page with the result. */
static void s_command (s_app_t *app, st_web_conn_t *conn, s_page_t *page, int64_t n, const char *op,
                       const cgs_instance_t *to, Cgs__Command *cmd)
{
    if (!to) {
        s_count (&app->commands_unanswered);
        return s_refuse (conn, n, op, "the exercise names no instance to take that command");
    }
    cgs_cmd_client_t **client = s_client (page, to);
    if (!*client &&
        (!(*client = cgs_cmd_client_new (cgs_service_ctx (app->svc), to->command, "stationd")) ||
         cgs_curve_protect_client (cgs_service_curve (app->svc), *client, to->public_key) < 0)) {
        cgs_cmd_client_destroy (client); // never left unprotected for the next command
        s_count (&app->commands_unanswered);
        return s_refuse (conn, n, op, "cannot make a command client");
    }
    Cgs__Reply *reply = NULL;
    char err[512];
    int rc = cgs_cmd_client_call (*client, cmd, (int)(app->p.command_timeout_s * 1000),
                                  app->p.command_attempts, &reply, err, sizeof err);
    if (rc < 0) {
        s_count (&app->commands_unanswered);
        cgs_log (LOG_WARNING, "page %s: %s: %s", st_web_conn_peer (conn), op, err);
        return s_refuse (conn, n, op, err);
    }
    bool ok = reply->status == CGS__REPLY_STATUS__REPLY_STATUS_OK;
    s_count (ok ? &app->commands_ok : &app->commands_refused);
    cgs_log (LOG_INFO, "page %s: %s: %s %s%s%s", st_web_conn_peer (conn), op, reply->server,
             ok ? "ok" : "refused", ok ? "" : ": ",
             ok ? "" : (*reply->error ? reply->error : "no reason given"));
    json_object *o = s_reply_head ("reply", n, op);
    json_object_object_add (o, "ok", json_object_new_boolean (ok));
    json_object_object_add (o, "server", json_object_new_string (reply->server));
    if (ok)
        json_object_object_add (o, "detail", json_object_new_string (reply->detail));
    else
        json_object_object_add (
            o, "error",
            json_object_new_string (*reply->error ? reply->error : "refused, no reason given"));
    cgs_cmd_reply_free (&reply);
    s_answer (conn, o);
}

static void s_on_request (void *arg, st_web_conn_t *conn, const char *text, size_t len,
                          bool operator)
{
    s_app_t *app = arg;
    json_tokener *tok = json_tokener_new ();
    json_object *req =
        tok ? json_tokener_parse_ex (tok, text, (int)(len < INT_MAX ? len : 0)) : NULL;
    bool complete = tok && json_tokener_get_error (tok) == json_tokener_success &&
                    json_tokener_get_parse_end (tok) == len;
    json_tokener_free (tok);
    json_object *v;
    const char *op = NULL;
    if (!req || !complete || !json_object_is_type (req, json_type_object) ||
        !json_object_object_get_ex (req, "op", &v) || !json_object_is_type (v, json_type_string)) {
        json_object_put (req);
        return s_bad_request (app, conn, "expected a JSON object with a string \"op\"");
    }
    op = json_object_get_string (v);
    int64_t n = json_object_object_get_ex (req, "req", &v) ? json_object_get_int64 (v) : 0;
    if (strcmp (op, "mgrs") == 0) {
        s_mgrs (app, conn, req, n);
        json_object_put (req);
        return;
    }
    if (!st_request_is_command (op)) {
        char why[160];
        snprintf (why, sizeof why, "unknown op \"%.40s\"", op);
        s_bad_request (app, conn, why);
        json_object_put (req);
        return;
    }
    if (!operator) {
        s_count (&app->unauthorised);
        s_refuse (conn, n, op,
                  "commands need the operators' access token: open the page with ?token=...");
        json_object_put (req);
        return;
    }
    // A replay's page drives its timeline; an operator's command reaches nothing.
    if (app->replay && !st_request_is_replay (op)) {
        s_count (&app->commands_refused);
        s_refuse (conn, n, op, "this is a replay: an operator's command reaches nothing");
        json_object_put (req);
        return;
    }
    if (!app->replay && st_request_is_replay (op)) {
        s_count (&app->bad_requests);
        s_refuse (conn, n, op, "this is a live exercise, not a replay: it has no timeline");
        json_object_put (req);
        return;
    }
    s_page_t *page = st_web_conn_user (conn);
    if (!page) {
        if (!(page = calloc (1, sizeof *page))) {
            s_refuse (conn, n, op, "out of memory");
            json_object_put (req);
            return;
        }
        st_web_conn_set_user (conn, page);
    }
    st_command_t c;
    char why[512];
    if (st_request_command (req, op, &c, why, sizeof why) < 0) {
        s_count (&app->bad_requests);
        s_refuse (conn, n, op, why);
    } else if (c.to == ST_TO_IMAGERD) {
        // The imagerd of the command's UAV (the exercise and the scenario
        // are read only, so the page's thread may look).
        const cgs_instance_t *to = NULL;
        if (st_request_imagerd (cgs_service_exercise (app->svc), app->scenario, c.uav_id, &to, why,
                                sizeof why) < 0) {
            s_count (&app->commands_unanswered);
            s_refuse (conn, n, op, why);
        } else {
            s_command (app, conn, page, n, op, to, &c.cmd);
        }
    } else {
        s_command (app, conn, page, n, op,
                   c.to == ST_TO_REPLAY   ? app->replay
                   : c.to == ST_TO_UAVSIM ? app->uavsim
                                          : app->guidanced,
                   &c.cmd);
    }
    json_object_put (req);
}

static void s_on_page_closed (void *arg, void *user)
{
    (void)arg;
    s_page_t *page = user;
    for (size_t i = 0; i < S_PAGE_CLIENTS; i++)
        cgs_cmd_client_destroy (&page->clients[i].client);
    free (page);
}

/* ---- start-up -------------------------------------------------------------------- */

static int s_on_option (void *arg, const char *name, const char *value, char *why, size_t whylen)
{
    s_app_t *app = arg;
    if (strcmp (name, "listen") == 0) {
        if (strlen (value) >= sizeof app->listen_override) {
            snprintf (why, whylen, "--listen: address too long");
            return -EINVAL;
        }
        snprintf (app->listen_override, sizeof app->listen_override, "%s", value);
        return 0;
    }
    char *end;
    errno = 0;
    long port = strtol (value, &end, 10);
    if (errno || end == value || *end || port < 0 || port > 65535) {
        snprintf (why, whylen, "--port: expected 0..65535, got '%s'", value);
        return -EINVAL;
    }
    app->port_override = port;
    return 0;
}

/* The page's folder: the parameter's, else the one built or installed beside
 * the program (BIN/../web in the build tree, BIN/../share/mscgs/web installed). */
static void s_web_root (const s_app_t *app, char *ret, size_t size)
{
    if (*app->p.web_root) {
        snprintf (ret, size, "%s", app->p.web_root);
        return;
    }
    char exe[PATH_MAX];
    ssize_t n = readlink ("/proc/self/exe", exe, sizeof exe - 1);
    exe[n > 0 ? n : 0] = '\0';
    char *slash = strrchr (exe, '/');
    if (slash)
        *slash = '\0';
    struct stat st;
    snprintf (ret, size, "%s/../web", exe);
    if (stat (ret, &st) == 0 && S_ISDIR (st.st_mode))
        return;
    snprintf (ret, size, "%s/../share/mscgs/web", exe);
}

/* The first instance of program, if it takes commands; else NULL. */
static const cgs_instance_t *s_commanded (const cgs_exercise_t *ex, const char *program)
{
    const cgs_instance_t *in = cgs_exercise_first_of (ex, program);
    return in && *in->command ? in : NULL;
}

static char *s_hello (s_app_t *app, bool operator)
{
    json_object *o = json_object_new_object ();
    cgs_geodetic_t g = cgs_exercise_origin (cgs_service_exercise (app->svc));
    json_object_object_add (o, "type", json_object_new_string ("hello"));
    json_object_object_add (o, "version", json_object_new_int (1));
    json_object_object_add (o, "operator", json_object_new_boolean (operator));
    json_object_object_add (o, "token_required", json_object_new_boolean (app->p.token[0] != 0));
    json_object_object_add (o, "replay", json_object_new_boolean (app->replay != NULL));
    json_object_object_add (
        o, "exercise",
        json_object_new_string (cgs_exercise_name (cgs_service_exercise (app->svc))));
    json_object *origin = json_object_new_object ();
    json_object_object_add (origin, "lat_deg", json_object_new_double (g.lat_deg));
    json_object_object_add (origin, "lon_deg", json_object_new_double (g.lon_deg));
    json_object_object_add (origin, "height_m", json_object_new_double (g.height_m));
    json_object_object_add (o, "origin", origin);
    if (app->have_relief) {
        json_object *r = json_object_new_object (), *ext = json_object_new_array ();
        json_object_object_add (r, "url", json_object_new_string ("/relief.png"));
        for (int i = 0; i < 4; i++)
            json_object_array_add (ext, json_object_new_double (app->relief.extent[i]));
        json_object_object_add (r, "extent", ext);
        json_object_object_add (o, "relief", r);
    } else {
        json_object_object_add (o, "relief", NULL);
    }
    json_object_object_add (o, "history_scans", json_object_new_int (app->p.history_scans));
    json_object_object_add (o, "bcis_timeout_s", json_object_new_double (app->p.bcis_timeout_s));
    json_object_object_add (o, "push_hz", json_object_new_double (app->p.push_hz));
    char *out = strdup (json_object_to_json_string_ext (o, JSON_C_TO_STRING_PLAIN));
    json_object_put (o);
    return out;
}

static int s_setup (s_app_t *app, char *err, size_t errlen)
{
    st_params_defaults (&app->p);
    const char *params = cgs_service_params_path (app->svc);
    if (*params) {
        int rc = st_params_load (params, &app->p, err, errlen);
        if (rc < 0)
            return rc;
        cgs_log (LOG_INFO, "station parameters from %s", params);
    }
    if (*app->listen_override) {
        if (!st_params_is_loopback (app->listen_override) && !app->p.token[0]) {
            snprintf (err, errlen,
                      "--listen %s (not loopback) needs an operators' access token: give "
                      "`token` or `token_file` in the parameter file's [http]",
                      app->listen_override);
            return -EINVAL;
        }
        snprintf (app->p.listen_address, sizeof app->p.listen_address, "%s", app->listen_override);
    }
    if (app->port_override >= 0)
        app->p.port = (int)app->port_override;
    if (*cgs_service_scenario_path (app->svc)) {
        int rc = cgs_service_load_scene (app->svc, &app->frame, &app->scenario, &app->terrain, err,
                                         errlen);
        if (rc < 0)
            return rc;
    } else {
        cgs_geodetic_t o = cgs_exercise_origin (cgs_service_exercise (app->svc));
        if (!(app->frame = cgs_geo_new (o.lat_deg, o.lon_deg, o.height_m))) {
            snprintf (err, errlen, "the exercise origin is not usable");
            return -EINVAL;
        }
    }
    app->guidanced = s_commanded (cgs_service_exercise (app->svc), "guidanced");
    app->uavsim = s_commanded (cgs_service_exercise (app->svc), "uavsim");
    app->replay = s_commanded (cgs_service_exercise (app->svc), "replay");
    st_state_params_t sp = {app->p.history_scans, app->p.bcis_timeout_s, app->p.track_stale_s,
                            app->p.truth_stale_s};
    app->state_params = sp;
    if (!(app->state = st_state_new (&sp))) {
        snprintf (err, errlen, "out of memory");
        return -ENOMEM;
    }
    if (cgs_service_check_only (app->svc))
        return 0;
    if (app->terrain) {
        double t0 = cgs_loop_now ();
        st_relief_params_t rp = {app->p.sun_azimuth_deg, app->p.sun_elevation_deg, app->p.z_factor,
                                 app->p.max_pixels};
        int rc = st_relief_make (app->terrain, &rp, &app->relief, err, errlen);
        if (rc < 0)
            return rc;
        app->have_relief = true;
        cgs_log (LOG_INFO, "shaded relief %d x %d px (%zu bytes) in %.2f s", app->relief.width,
                 app->relief.height, app->relief.png_len, cgs_loop_now () - t0);
    } else {
        cgs_log (LOG_WARNING, "no scenario, so no terrain: the map has no shaded relief");
    }
    char root[PATH_MAX];
    s_web_root (app, root, sizeof root);
    char *hello_op = s_hello (app, true), *hello_view = s_hello (app, false);
    if (!hello_op || !hello_view) {
        free (hello_op);
        free (hello_view);
        snprintf (err, errlen, "out of memory");
        return -ENOMEM;
    }
    st_web_config_t wc = {.listen_address = app->p.listen_address,
                          .port = app->p.port,
                          .web_root = root,
                          .threads = app->p.threads,
                          .write_timeout_s = app->p.write_timeout_s,
                          .token = app->p.token,
                          .relief_png = app->have_relief ? app->relief.png : NULL,
                          .relief_len = app->have_relief ? app->relief.png_len : 0,
                          .hello_operator = hello_op,
                          .hello_viewer = hello_view};
    app->web = st_web_new (&wc, s_on_request, s_on_page_closed, app, err, errlen);
    free (hello_op);
    free (hello_view);
    if (!app->web)
        return -EIO;
    bool v6 = strchr (app->p.listen_address, ':') != NULL;
    cgs_log (LOG_INFO, "tactical map at http://%s%s%s:%d/ (page folder %s); operators %s",
             v6 ? "[" : "", app->p.listen_address, v6 ? "]" : "", st_web_port (app->web), root,
             app->p.token[0] ? "need the access token (?token=...)" : "are every local page");
    return 0;
}

int main (int argc, char **argv)
{
    static s_app_t app;
    app.port_override = -1;
    static const cgs_service_option_t options[] = {
        {"listen", true, "ADDR",
         "address the web server binds (default: the parameters', 127.0.0.1)"},
        {"port", true, "N", "its TCP port (default: the parameters', 8080; 0: any free port)"},
        {NULL, false, NULL, NULL},
    };
    cgs_service_info_t info = {
        .program = "stationd",
        .summary = "The UAV control station's tactical map, served to browsers.",
        .options = options,
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
        printf ("%s: parameters are good (listening on %s:%d, %s)\n",
                cgs_service_instance_name (app.svc), app.p.listen_address, app.p.port,
                app.p.token[0] ? "operators need the token" : "no token");
        exit_code = 0;
        goto done;
    }
    if (cgs_loop_add_timer (cgs_service_loop (app.svc), 1.0 / app.p.push_hz, s_on_push, &app) < 0) {
        cgs_log (LOG_ERR, "out of memory");
        goto done;
    }
    static const struct {
        const char *topic;
        cgs_sub_fn *fn;
    } subs[] = {{"clock", s_on_clock}, {"entity", s_on_entity},       {"uav", s_on_uav},
                {"mti", s_on_mti},     {"mti.scan", s_on_mti_scan},   {"bcis", s_on_bcis},
                {"track", s_on_track}, {"intercept", s_on_intercept}, {"image", s_on_image},
                {"video", s_on_video}};
    for (size_t i = 0; i < sizeof subs / sizeof subs[0]; i++)
        if (cgs_service_subscribe (app.svc, subs[i].topic, subs[i].fn, &app) < 0)
            goto done;
    // A replay's exercise (mscgs replay) has its `replay` to hear; a live one none.
    if (app.replay && cgs_service_subscribe (app.svc, "replay", s_on_replay, &app) < 0)
        goto done;
    exit_code = cgs_service_run (app.svc);
    st_web_stats_t ws;
    st_web_stats (app.web, &ws, NULL, 0);
    cgs_log (LOG_INFO,
             "%" PRIu64 " pages served, %" PRIu64 " pictures pushed (%" PRIu64 " skipped), %" PRIu64
             " commands ok, %" PRIu64 " refused, %" PRIu64 " unanswered",
             ws.pages_total, ws.pushes, ws.skipped, s_read (&app.commands_ok),
             s_read (&app.commands_refused), s_read (&app.commands_unanswered));
    cgs_log (LOG_INFO,
             "video: %" PRIu64 " pages served, %" PRIu64 " frames in, %" PRIu64
             " written to pages (%" PRIu64 " bytes), %" PRIu64 " dropped for pages behind",
             ws.video_pages_total, ws.video_frames, ws.video_sent, ws.video_bytes,
             ws.video_dropped);
done:
    st_web_destroy (&app.web); // first: no page thread may run after what it uses is freed
    st_state_destroy (&app.state);
    st_relief_fini (&app.relief);
    cgs_terrain_destroy (&app.terrain);
    cgs_scenario_destroy (&app.scenario);
    cgs_geo_destroy (&app.frame);
    cgs_service_destroy (&app.svc);
    return exit_code;
}
