/* ms_cmd_admin — the commands around an exercise: `mscgs snapshot`
 * (imagerd writes its next frames as PNG files), `fault` (the debug-only
 * fault channel of a test build, cgs_fault.h) and `keygen` (a CURVE key
 * pair and the exercise file's lines for it). */
#include "ms_cmd_admin.h"

#include "cgs_cmd.h"
#include "cgs_fault.h"
#include "cgs_lifecycle.h"
#include "cgs_seal.h"
#include "ms_opts.h"
#include "ms_tool.h"

#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <zmq.h>

/* ---- snapshot ------------------------------------------------------------------------ */

int ms_snapshot_main (int argc, char **argv)
{
    const char *exercise = NULL, *to = NULL;
    Cgs__Snapshot snap = CGS__SNAPSHOT__INIT;
    const ms_opt_t opts[] = {
        MS_TOOL_OPT_TO (&to),
        MS_TOOL_OPT_UAV (&snap.uav_id),
        MS_TOOL_OPT_EXERCISE (&exercise),
        MS_OPTS_HELP,
        MS_OPTS_END,
    };
    const ms_cmd_t spec = {
        .name = "snapshot",
        .operands = "[N]",
        .about = "imagerd writes its next N frames (1..1000, default 1) as PNG files\n"
                 "(snapshot-NNNNNNNN.png) in its output folder.\n",
        .opts = opts,
    };
    int nargs = ms_opts_parse (&spec, argc, argv);
    if (nargs < 0)
        return ms_opts_exit_code (nargs);
    if (nargs > 1) {
        fprintf (stderr, "mscgs snapshot: takes one number of frames at most\n");
        return 2;
    }
    snap.frames = 1;
    if (nargs == 1 && ms_opts_u32 ("snapshot", "a number of frames", argv[1], &snap.frames) < 0)
        return 2;
    if (snap.frames < 1 || snap.frames > 1000) {
        fprintf (stderr,
                 "mscgs snapshot: 1 frame at least, at most 1000 frames a request, got %u\n",
                 snap.frames);
        return 2;
    }
    cgs_exercise_t *ex = ms_tool_load_exercise (exercise);
    if (!ex)
        return 1;
    Cgs__Command cmd = CGS__COMMAND__INIT;
    cmd.body_case = CGS__COMMAND__BODY_SNAPSHOT;
    cmd.snapshot = &snap;
    int rc = ms_tool_send ("snapshot", ex, to, "imagerd", &cmd, MS_TOOL_WAIT_S);
    cgs_exercise_destroy (&ex);
    return rc;
}

/* ---- fault: the debug-only fault channel ---------------------------------------------- */

/* mscgs fault INSTANCE crash | hang [S] | slow MS [S] (cgs_fault.h). */
int ms_fault_main (int argc, char **argv)
{
    const char *exercise = NULL, *state_dir = NULL;
    const ms_opt_t opts[] = {
        MS_TOOL_OPT_EXERCISE (&exercise),
        {.name = "state-dir",
         .value = "DIR",
         .help = "the service's state folder (default the exercise's)",
         .str = &state_dir},
        MS_OPTS_HELP,
        MS_OPTS_END,
    };
    const ms_cmd_t spec = {
        .name = "fault",
        .synopsis = "usage: mscgs fault INSTANCE crash | hang [S] | slow MS [S] [--state-dir DIR]\n"
                    "                   [--exercise F]\n",
        .about = "The debug-only fault channel of a service built with FAULT=1 (the test build):\n"
                 "after its reply the service\n"
                 "  crash        aborts, as a crash would;\n"
                 "  hang [S]     blocks its event loop S seconds (default: until killed);\n"
                 "  slow MS [S]  stalls its event loop MS ms (1..90) in every 100 ms, S seconds\n"
                 "               (default: until it ends).\n"
                 "The channel is ipc://DIR/INSTANCE.fault; DIR is the service's state folder\n"
                 "(default the exercise's state_dir).\n",
        .opts = opts,
    };
    int nargs = ms_opts_parse (&spec, argc, argv);
    if (nargs < 0)
        return ms_opts_exit_code (nargs);
#ifndef CGS_FAULT
    (void)exercise;
    (void)state_dir;
    fprintf (stderr, "mscgs fault: this mscgs was built without the fault channel (FAULT=1 "
                     "builds have it; the test build does)\n");
    return 2;
#else
    char **args = argv + 1;
    Cgs__Fault fault = CGS__FAULT__INIT;
    const char *action = nargs >= 2 ? args[1] : "";
    if (strcmp (action, "crash") == 0 && nargs == 2) {
        fault.action = CGS__FAULT_ACTION__FAULT_ACTION_CRASH;
    } else if (strcmp (action, "hang") == 0 && (nargs == 2 || nargs == 3)) {
        fault.action = CGS__FAULT_ACTION__FAULT_ACTION_HANG;
        if (nargs == 3 && ms_opts_number ("hang", args[2], &fault.seconds) < 0)
            return 2;
    } else if (strcmp (action, "slow") == 0 && (nargs == 3 || nargs == 4)) {
        fault.action = CGS__FAULT_ACTION__FAULT_ACTION_SLOW;
        if (ms_opts_u32 ("slow", "a stall in ms", args[2], &fault.stall_ms) < 0 ||
            (nargs == 4 && ms_opts_number ("slow", args[3], &fault.seconds) < 0))
            return 2;
    } else {
        ms_opts_usage (&spec, stderr);
        return 2;
    }
    cgs_fault_t check = {0};
    char why[256];
    if (cgs_fault_request (&check, &fault, 0, why, sizeof why) < 0) {
        fprintf (stderr, "mscgs fault: %s\n", why);
        return 2;
    }
    cgs_exercise_t *ex = ms_tool_load_exercise (exercise);
    if (!ex)
        return 1;
    int rc = 1;
    char dir[PATH_MAX], path[PATH_MAX + 200], ep[PATH_MAX + 210];
    if (!cgs_exercise_find (ex, args[0])) {
        fprintf (stderr, "mscgs fault: %s is not in the exercise\n", args[0]);
        rc = 2;
        goto done;
    }
    if (!realpath (state_dir ? state_dir : cgs_exercise_state_dir (ex), dir)) {
        fprintf (stderr, "mscgs fault: state folder %s: %s\n",
                 state_dir ? state_dir : cgs_exercise_state_dir (ex), strerror (errno));
        goto done;
    }
    snprintf (path, sizeof path, "%s/%s.fault", dir, args[0]);
    snprintf (ep, sizeof ep, "ipc://%s", path);
    if (access (path, F_OK) < 0) {
        fprintf (stderr,
                 "mscgs fault: no fault channel at %s: is %s running, built with FAULT=1, with "
                 "state folder %s (--state-dir)?\n",
                 path, args[0], dir);
        goto done;
    }
    void *ctx = zmq_ctx_new ();
    cgs_cmd_client_t *cl = cgs_cmd_client_new (ctx, ep, "mscgs-fault");
    if (!cl) {
        fprintf (stderr, "mscgs fault: %s\n", strerror (errno));
        zmq_ctx_term (ctx);
        goto done;
    }
    Cgs__Command cmd = CGS__COMMAND__INIT;
    cmd.body_case = CGS__COMMAND__BODY_FAULT;
    cmd.fault = &fault;
    Cgs__Reply *reply = NULL;
    char err[512];
    cgs_lifecycle_init ();
    // One attempt: a retried crash would crash the restarted service too.
    if (cgs_cmd_client_call (cl, &cmd, 2000, 1, &reply, err, sizeof err) < 0)
        fprintf (stderr, "mscgs fault: %s\n", err);
    else {
        bool ok = reply->status == CGS__REPLY_STATUS__REPLY_STATUS_OK;
        fprintf (ok ? stdout : stderr, "%s: %s: %s\n", reply->server, ok ? "ok" : "refused",
                 ok ? reply->detail : reply->error);
        rc = ok ? 0 : 1;
        cgs_cmd_reply_free (&reply);
    }
    cgs_cmd_client_destroy (&cl);
    zmq_ctx_term (ctx);
done:
    cgs_exercise_destroy (&ex);
    return rc;
#endif
}

/* ---- keygen ---------------------------------------------------------------------------- */

/* mscgs keygen --group [NAME]: the exercise's group key for a sealed bus
 * in DIR/NAME.key (default group.key; mode 0600, never overwritten), and
 * the [bus] line that names it. */
static int s_keygen_group (const char *dir, const char *name)
{
    char path[PATH_MAX], text[CGS_SEAL_KEY_TEXT_MAX];
    snprintf (path, sizeof path, "%s/%s.key", dir, name);
    cgs_seal_key_t key;
    if (cgs_seal_key_new (&key) < 0) {
        fprintf (stderr, "mscgs keygen: libsodium failed to start\n");
        return 1;
    }
    cgs_seal_key_format (&key, text, sizeof text);
    explicit_bzero (&key, sizeof key);
    int fd = open (path, O_WRONLY | O_CREAT | O_EXCL, 0600);
    if (fd < 0) {
        fprintf (stderr, "mscgs keygen: cannot create %s: %s%s\n", path, strerror (errno),
                 errno == EEXIST ? " (a key is never overwritten: remove it first)" : "");
        explicit_bzero (text, sizeof text);
        return 1;
    }
    size_t n = strlen (text);
    bool ok = write (fd, text, n) == (ssize_t)n;
    ok = close (fd) == 0 && ok;
    explicit_bzero (text, sizeof text);
    if (!ok) {
        fprintf (stderr, "mscgs keygen: cannot write %s\n", path);
        return 1;
    }
    printf ("; the exercise's group key: copy %s to every host, then paste into [bus]\n"
            "key_file = %s\n",
            path, path);
    return 0;
}

/* mscgs keygen NAME [--dir DIR]: a CURVE key pair, the secret in DIR/NAME.key
 * (mode 0600, never overwritten) and the public key in DIR/NAME.pub and on
 * stdout, as the exercise file's lines. With --group, the group key of a
 * sealed bus instead (s_keygen_group). */
int ms_keygen_main (int argc, char **argv)
{
    const char *dir = ".";
    bool group = false;
    const ms_opt_t opts[] = {
        {.name = "dir", .value = "DIR", .help = "where the key files go (default .)", .str = &dir},
        {.name = "group",
         .help = "the exercise's group key that seals the bus ([bus] key_file), in\n"
                 "DIR/NAME.key (NAME default group)",
         .flag = &group},
        MS_OPTS_END, // no --help: it has never had one
    };
    const ms_cmd_t spec = {.name = "keygen", .operands = "NAME", .opts = opts};
    int nargs = ms_opts_parse (&spec, argc, argv);
    if (nargs < 0)
        return ms_opts_exit_code (nargs);
    if (group && nargs <= 1 && (nargs == 0 || (*argv[1] && !strchr (argv[1], '/'))))
        return s_keygen_group (dir, nargs ? argv[1] : "group");
    if (nargs != 1 || !*argv[1] || strchr (argv[1], '/')) {
        fprintf (stderr, "usage: mscgs keygen NAME [--dir DIR]   (NAME without '/')\n"
                         "       mscgs keygen --group [NAME] [--dir DIR]\n");
        return 2;
    }
    const char *name = argv[1];
    char pub[41], secret[41], spath[PATH_MAX], ppath[PATH_MAX];
    if (zmq_curve_keypair (pub, secret) != 0) {
        fprintf (stderr, "mscgs keygen: %s (libzmq without CURVE?)\n", zmq_strerror (zmq_errno ()));
        return 1;
    }
    snprintf (spath, sizeof spath, "%s/%s.key", dir, name);
    snprintf (ppath, sizeof ppath, "%s/%s.pub", dir, name);
    int fd = open (spath, O_WRONLY | O_CREAT | O_EXCL, 0600);
    if (fd < 0) {
        fprintf (stderr, "mscgs keygen: cannot create %s: %s%s\n", spath, strerror (errno),
                 errno == EEXIST ? " (a key is never overwritten: remove it first)" : "");
        return 1;
    }
    char line[64];
    int n = snprintf (line, sizeof line, "%s\n", secret);
    bool ok = write (fd, line, (size_t)n) == n;
    ok = close (fd) == 0 && ok;
    FILE *f = ok ? fopen (ppath, "w") : NULL;
    ok = f && fprintf (f, "%s\n", pub) > 0;
    ok = f && fclose (f) == 0 && ok;
    memset (secret, 0, sizeof secret);
    memset (line, 0, sizeof line);
    if (!ok) {
        fprintf (stderr, "mscgs keygen: cannot write the key files in %s\n", dir);
        return 1;
    }
    printf ("; %s: paste into its [service] section (or [curve] for the tools:\n"
            "; client_public_key / client_secret_key_file)\npublic_key = %s\nsecret_key_file = "
            "%s\n",
            name, pub, spath);
    return 0;
}
