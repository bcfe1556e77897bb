/* ms_tool — what mscgs's commands share: the exercise file with the tools'
 * CURVE keys, a subscriber to its bus, a command to one of its services, a
 * position on the command line. */
#include "ms_tool.h"

#include "cgs_cmd.h"
#include "cgs_config.h"
#include "cgs_lifecycle.h"

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <zmq.h>

static char s_exe_dir[PATH_MAX];

/* The tools' CURVE keys of the exercise loaded last; NULL without keys. */
static cgs_curve_t *s_curve;

void ms_tool_init (void)
{
    ssize_t n = readlink ("/proc/self/exe", s_exe_dir, sizeof s_exe_dir - 1);
    if (n <= 0) {
        snprintf (s_exe_dir, sizeof s_exe_dir, ".");
        return;
    }
    s_exe_dir[n] = '\0';
    char *slash = strrchr (s_exe_dir, '/');
    if (slash)
        *slash = '\0';
}

const char *ms_tool_exe_dir (void)
{
    return s_exe_dir;
}

const char *ms_tool_exercise_path (const char *given, char *buf, size_t size)
{
    if (given)
        return given;
    const char *env = getenv ("MSCGS_EXERCISE");
    if (env && *env)
        return env;
    if (access ("/etc/mscgs/exercise.ini", R_OK) == 0)
        return "/etc/mscgs/exercise.ini";
    // An install (PREFIX/bin/mscgs: PREFIX/share/mscgs), or a source tree
    // (build/bin/mscgs or build/<variant>/bin/mscgs).
    const char *up[] = {"/../share/mscgs/exercises/default.ini",
                        "/../../deploy/exercises/default.ini",
                        "/../../../deploy/exercises/default.ini"};
    for (size_t i = 0; i < sizeof up / sizeof up[0]; i++) {
        snprintf (buf, size, "%s%s", s_exe_dir, up[i]);
        char real[PATH_MAX];
        if (access (buf, R_OK) == 0) {
            if (realpath (buf, real))
                snprintf (buf, size, "%s", real);
            return buf;
        }
    }
    return "/etc/mscgs/exercise.ini";
}

cgs_exercise_t *ms_tool_load_exercise (const char *given)
{
    char buf[PATH_MAX];
    const char *path = ms_tool_exercise_path (given, buf, sizeof buf);
    char err[1024];
    cgs_exercise_t *ex = NULL;
    if (cgs_exercise_load (path, &ex, err, sizeof err) < 0) {
        fprintf (stderr, "mscgs: %s\n", err);
        return NULL;
    }
    // The tools' CURVE pair, when the exercise names keys.
    cgs_curve_destroy (&s_curve);
    if (cgs_curve_load (ex, NULL, &s_curve, err, sizeof err) < 0) {
        fprintf (stderr, "mscgs: %s\n", err);
        cgs_exercise_destroy (&ex);
        return NULL;
    }
    return ex;
}

cgs_curve_t *ms_tool_curve (void)
{
    return s_curve;
}

cgs_sub_t *ms_tool_open_sub (const cgs_exercise_t *ex, void **ret_ctx)
{
    void *ctx = zmq_ctx_new ();
    cgs_sub_t *sub = ctx ? cgs_sub_new (ctx) : NULL;
    if (!sub) {
        fprintf (stderr, "mscgs: %s\n", strerror (errno ? errno : ENOMEM));
        if (ctx)
            zmq_ctx_term (ctx);
        return NULL;
    }
    cgs_sub_set_exercise (sub, cgs_exercise_id (ex));
    // A sealed bus: the tools read it with the group key too.
    const cgs_bus_params_t *bus = cgs_exercise_bus (ex);
    if (*bus->key_file) {
        cgs_seal_key_t key;
        char err[1024];
        int rc = cgs_seal_key_load (bus->key_file, &key, err, sizeof err);
        if (rc == 0)
            rc = cgs_sub_set_seal (sub, &key, bus->replay_window_s);
        explicit_bzero (&key, sizeof key);
        if (rc < 0) {
            fprintf (stderr, "mscgs: the bus's group key: %s\n", *err ? err : strerror (-rc));
            cgs_sub_destroy (&sub);
            zmq_ctx_term (ctx);
            return NULL;
        }
    }
    *ret_ctx = ctx;
    return sub;
}

static char s_multicast_iface[CGS_NAME_MAX]; // --multicast IFACE, "" when not given

void ms_tool_set_multicast (const char *iface)
{
    snprintf (s_multicast_iface, sizeof s_multicast_iface, "%s", iface ? iface : "");
}

size_t ms_tool_connect_publishers (cgs_sub_t *sub, const cgs_exercise_t *ex, const char *topic)
{
    // With --multicast, the tool joins like an instance on a host of its own.
    cgs_instance_t self = {.host = "(the tool)"};
    snprintf (self.interface, sizeof self.interface, "%s", s_multicast_iface);
    const cgs_bus_params_t *bus = cgs_exercise_bus (ex);
    if (*s_multicast_iface)
        cgs_bus_set_multicast (cgs_sub_socket (sub), bus->rate_kbps, bus->recovery_ms, bus->hops);
    const cgs_instance_t *pubs[MS_MAX_INSTANCES];
    size_t n = cgs_exercise_publishers_of (ex, topic, pubs, MS_MAX_INSTANCES);
    if (n > MS_MAX_INSTANCES)
        n = MS_MAX_INSTANCES;
    for (size_t i = 0; i < n; i++) {
        char ep[CGS_ENDPOINT_MAX];
        cgs_exercise_endpoint_for (pubs[i], *s_multicast_iface ? &self : NULL, ep, sizeof ep);
        if (cgs_curve_client (s_curve, cgs_sub_socket (sub), pubs[i]->public_key) < 0 ||
            cgs_sub_connect (sub, ep) < 0)
            fprintf (stderr, "mscgs: cannot connect to %s (%s)\n", ep, pubs[i]->name);
    }
    return n;
}

int ms_tool_send (const char *tool, cgs_exercise_t *ex, const char *to, const char *program,
                  Cgs__Command *cmd, double wait_s)
{
    const cgs_instance_t *in =
        to ? cgs_exercise_find (ex, to) : cgs_exercise_first_of (ex, program);
    if (!in || !*in->command) {
        fprintf (stderr, "mscgs %s: %s\n", tool,
                 !in ? (to ? "no such instance in the exercise"
                           : "no instance of that program in the exercise")
                     : "that instance takes no commands (no command endpoint)");
        return 2;
    }
    void *ctx = zmq_ctx_new ();
    cgs_cmd_client_t *cl = cgs_cmd_client_new (ctx, in->command, "mscgs");
    if (cl)
        cgs_curve_protect_client (s_curve, cl, in->public_key);
    if (!cl) {
        zmq_ctx_term (ctx);
        fprintf (stderr, "mscgs %s: %s\n", tool, strerror (errno));
        return 1;
    }
    Cgs__Reply *reply = NULL;
    char err[512];
    cgs_lifecycle_init ();
    int rc = cgs_cmd_client_call (cl, cmd, 1000, (int)ceil (wait_s), &reply, err, sizeof err);
    if (rc < 0) {
        fprintf (stderr, "mscgs %s: %s\n", tool, err);
        rc = 1;
    } else {
        bool ok = reply->status == CGS__REPLY_STATUS__REPLY_STATUS_OK;
        fprintf (ok ? stdout : stderr, "%s: %s%s%s\n", reply->server, ok ? "ok" : "refused",
                 *reply->detail ? ": " : "", *reply->detail ? reply->detail : "");
        if (*reply->error)
            fprintf (stderr, "%s: %s\n", reply->server, reply->error);
        rc = ok ? 0 : 1;
        cgs_cmd_reply_free (&reply);
    }
    cgs_cmd_client_destroy (&cl);
    zmq_ctx_term (ctx);
    return rc;
}

int ms_tool_position (const cgs_exercise_t *ex, const char *text, Cgs__Enu *ret)
{
    char buf[256];
    snprintf (buf, sizeof buf, "%s", text);
    for (char *c = buf; *c; c++)
        if (*c == ',')
            *c = ' ';
    cgs_geodetic_t o = cgs_exercise_origin (ex);
    cgs_geo_t *frame = cgs_geo_new (o.lat_deg, o.lon_deg, o.height_m);
    cgs_enu_t p;
    char why[256];
    int rc = frame ? cgs_config_parse_position (buf, frame, &p, why, sizeof why) : -ENOMEM;
    cgs_geo_destroy (&frame);
    if (rc < 0) {
        fprintf (stderr, "mscgs: position '%s': %s\n", text, why);
        return rc;
    }
    cgs__enu__init (ret);
    ret->east_m = p.e_m;
    ret->north_m = p.n_m;
    ret->up_m = p.u_m;
    return 0;
}

int ms_tool_read_wait (const ms_opt_t *opt, const char *value)
{
    double v = 0;
    if (ms_opts_number ("--wait", value, &v) < 0)
        return -EINVAL;
    if (v < 1 || v > 3600) {
        fprintf (stderr, "mscgs: --wait: 1 to 3600 seconds, got '%s'\n", value);
        return -EINVAL;
    }
    *(double *)opt->arg = v;
    return 0;
}
