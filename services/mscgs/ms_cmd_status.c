/* ms_cmd_status — the commands that look at the bus: `mscgs status` (every
 * instance's health), `echo` (a topic's messages), `ping` (an instance's
 * command endpoint) and `topics` (the catalogue). */
#include "ms_cmd_status.h"

#include "cgs_cmd.h"
#include "cgs_lifecycle.h"
#include "cgs_loop.h"
#include "cgs_topics.h"
#include "ms_health.h"
#include "ms_opts.h"
#include "ms_tool.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <zmq.h>

/* ---- status ------------------------------------------------------------------------ */

int ms_status_main (int argc, char **argv)
{
    const char *exercise = NULL;
    double wait_s = 2.5;
    const ms_opt_t opts[] = {
        MS_TOOL_OPT_EXERCISE (&exercise),
        {.name = "wait",
         .value = "S",
         .help = "listen S seconds at most (default 2.5)",
         .fn = ms_opts_read_positive,
         .arg = &wait_s},
        MS_OPTS_HELP,
        MS_OPTS_END,
    };
    const ms_cmd_t spec = {
        .name = "status",
        .about = "Listen to every service's 1 Hz health for S seconds (default 2.5) and\n"
                 "print a table. Exit 0 when every enabled instance is up, 3 if not.\n",
        .opts = opts,
    };
    int nargs = ms_opts_parse (&spec, argc, argv);
    if (nargs < 0)
        return ms_opts_exit_code (nargs);
    cgs_exercise_t *ex = ms_tool_load_exercise (exercise);
    if (!ex)
        return 1;
    void *ctx = NULL;
    cgs_sub_t *sub = ms_tool_open_sub (ex, &ctx);
    if (!sub) {
        cgs_exercise_destroy (&ex);
        return 1;
    }
    static ms_health_t table;
    ms_health_init (&table, ex);
    cgs_sub_on (sub, "health", ms_health_on_health, &table);
    ms_tool_connect_publishers (sub, ex, "health");
    double end = cgs_loop_now () + wait_s;
    cgs_lifecycle_init ();
    while (cgs_loop_now () < end && !cgs_lifecycle_stopping ()) {
        bool all = true;
        for (size_t i = 0; i < table.nrows; i++)
            all = all && (table.rows[i].seen || !table.rows[i].enabled);
        if (all)
            break;
        cgs_sub_poll (sub, 50);
    }
    printf ("exercise %s (id %u), %s\n", cgs_exercise_name (ex), cgs_exercise_id (ex),
            cgs_exercise_path (ex));
    ms_health_print (&table, stdout);
    int rc = 0;
    double now = cgs_loop_now ();
    for (size_t i = 0; i < table.nrows; i++)
        if (table.rows[i].enabled && strcmp (ms_health_state (&table.rows[i], now), "up") != 0)
            rc = 3;
    cgs_sub_destroy (&sub);
    zmq_ctx_term (ctx);
    cgs_exercise_destroy (&ex);
    return rc;
}

/* ---- echo -------------------------------------------------------------------------- */

typedef struct {
    bool json;
    long count;
    long seen;
} s_echo_t;

static void s_on_echo (void *arg, const char *topic, const ProtobufCMessage *msg,
                       const Cgs__Header *hdr)
{
    s_echo_t *e = arg;
    if (e->count > 0 && e->seen >= e->count)
        return;
    e->seen++;
    if (e->json) {
        cgs_msg_print_json (stdout, msg);
    } else {
        char *json = NULL;
        if (cgs_msg_to_json (msg, &json) == 0) {
            printf ("%s from %s #%llu sim %.3f s: %s\n", topic, hdr->source,
                    (unsigned long long)hdr->seq, hdr->sim_time_s, json);
            free (json);
        }
    }
    fflush (stdout);
}

/* --count N: a whole number of messages. */
static int s_read_count (const ms_opt_t *opt, const char *value)
{
    double n = 0;
    if (ms_opts_positive ("--count", value, &n) < 0)
        return -EINVAL;
    if (n != floor (n) || n > 1e12) {
        fprintf (stderr, "mscgs echo: --count: expected a whole number, got '%s'\n", value);
        return -EINVAL;
    }
    *(long *)opt->arg = (long)n;
    return 0;
}

int ms_echo_main (int argc, char **argv)
{
    const char *exercise = NULL;
    s_echo_t echo = {0};
    double timeout_s = 0;
    const char *multicast = NULL;
    const ms_opt_t opts[] = {
        {.name = "json", .letter = 'j', .help = "one JSON object a line", .flag = &echo.json},
        {.name = "count",
         .letter = 'n',
         .value = "N",
         .help = "stop after N messages",
         .fn = s_read_count,
         .arg = &echo.count},
        {.name = "timeout",
         .value = "S",
         .help = "stop after S seconds",
         .fn = ms_opts_read_positive,
         .arg = &timeout_s},
        {.name = "multicast",
         .value = "IFACE",
         .help = "receive over the publishers' multicast endpoints ([bus]),\n"
                 "joining on IFACE, where they have one",
         .str = &multicast},
        MS_TOOL_OPT_EXERCISE (&exercise),
        MS_OPTS_HELP,
        MS_OPTS_END,
    };
    const ms_cmd_t spec = {
        .name = "echo",
        .operands = "TOPIC",
        .missing = "which topic? (`mscgs topics` lists them)",
        .about = "Print each message of TOPIC from every publisher of it, as text with its\n"
                 "header, or as one line of JSON each. Stop after N messages, S seconds\n"
                 "(exit 4 if fewer than N came), or Ctrl-C. `mscgs topics` lists topics.\n",
        .opts = opts,
    };
    int nargs = ms_opts_parse (&spec, argc, argv);
    if (nargs < 0)
        return ms_opts_exit_code (nargs);
    const char *topic = argv[1];
    if (!cgs_topics_find (topic)) {
        fprintf (stderr, "mscgs echo: unknown topic '%s'; the topics are:", topic);
        for (size_t i = 0; i < cgs_topics_count (); i++)
            fprintf (stderr, " %s", cgs_topics_at (i)->name);
        fprintf (stderr, "\n");
        return 2;
    }
    cgs_exercise_t *ex = ms_tool_load_exercise (exercise);
    if (!ex)
        return 1;
    void *ctx = NULL;
    cgs_sub_t *sub = ms_tool_open_sub (ex, &ctx);
    if (!sub) {
        cgs_exercise_destroy (&ex);
        return 1;
    }
    cgs_sub_on (sub, topic, s_on_echo, &echo);
    ms_tool_set_multicast (multicast);
    if (ms_tool_connect_publishers (sub, ex, topic) == 0)
        fprintf (stderr, "mscgs echo: no instance in %s publishes %s\n", cgs_exercise_path (ex),
                 topic);
    cgs_lifecycle_init ();
    double end = timeout_s > 0 ? cgs_loop_now () + timeout_s : INFINITY;
    while (!cgs_lifecycle_stopping () && cgs_loop_now () < end &&
           !(echo.count > 0 && echo.seen >= echo.count))
        cgs_sub_poll (sub, 100);
    int rc = echo.count > 0 && echo.seen < echo.count ? 4 : 0;
    if (cgs_sub_gaps (sub) || cgs_sub_malformed (sub))
        fprintf (stderr, "mscgs echo: %llu messages missed (gaps), %llu malformed\n",
                 (unsigned long long)cgs_sub_gaps (sub),
                 (unsigned long long)cgs_sub_malformed (sub));
    if (cgs_sub_unauthenticated (sub) || cgs_sub_replayed (sub))
        fprintf (stderr, "mscgs echo: %llu unauthenticated, %llu replayed: dropped\n",
                 (unsigned long long)cgs_sub_unauthenticated (sub),
                 (unsigned long long)cgs_sub_replayed (sub));
    cgs_sub_destroy (&sub);
    zmq_ctx_term (ctx);
    cgs_exercise_destroy (&ex);
    return rc;
}

/* ---- ping ---------------------------------------------------------------------------- */

int ms_ping_main (int argc, char **argv)
{
    const char *exercise = NULL;
    const ms_opt_t opts[] = {MS_TOOL_OPT_EXERCISE (&exercise), MS_OPTS_HELP, MS_OPTS_END};
    const ms_cmd_t spec = {
        .name = "ping",
        .operands = "INSTANCE",
        .missing = "which instance?",
        .about = "Send a ping command to INSTANCE's command endpoint and print the reply.\n",
        .opts = opts,
    };
    int nargs = ms_opts_parse (&spec, argc, argv);
    if (nargs < 0)
        return ms_opts_exit_code (nargs);
    cgs_exercise_t *ex = ms_tool_load_exercise (exercise);
    if (!ex)
        return 1;
    const cgs_instance_t *in = cgs_exercise_find (ex, argv[1]);
    if (!in || !*in->command) {
        fprintf (stderr, "mscgs ping: %s %s\n", argv[1],
                 in ? "takes no commands (no command endpoint)" : "is not in the exercise");
        cgs_exercise_destroy (&ex);
        return 2;
    }
    void *ctx = zmq_ctx_new ();
    cgs_cmd_client_t *cl = cgs_cmd_client_new (ctx, in->command, NULL);
    if (cl)
        cgs_curve_protect_client (ms_tool_curve (), cl, in->public_key);
    Cgs__Ping ping = CGS__PING__INIT;
    ping.text = "mscgs ping";
    Cgs__Command cmd = CGS__COMMAND__INIT;
    cmd.body_case = CGS__COMMAND__BODY_PING;
    cmd.ping = &ping;
    Cgs__Reply *reply = NULL;
    char err[512];
    double t0 = cgs_loop_now ();
    cgs_lifecycle_init ();
    int rc = cgs_cmd_client_call (cl, &cmd, 1000, 3, &reply, err, sizeof err);
    if (rc < 0) {
        fprintf (stderr, "mscgs ping: %s\n", err);
        rc = 1;
    } else {
        printf ("%s: %s in %.1f ms%s%s\n", reply->server,
                reply->status == CGS__REPLY_STATUS__REPLY_STATUS_OK ? "ok" : "error",
                (cgs_loop_now () - t0) * 1e3, *reply->error ? ": " : "", reply->error);
        rc = reply->status == CGS__REPLY_STATUS__REPLY_STATUS_OK ? 0 : 1;
        cgs_cmd_reply_free (&reply);
    }
    cgs_cmd_client_destroy (&cl);
    zmq_ctx_term (ctx);
    cgs_exercise_destroy (&ex);
    return rc;
}

/* ---- topics -------------------------------------------------------------------------- */

int ms_topics_main (int argc, char **argv)
{
    (void)argc;
    (void)argv;
    printf ("%-12s %-16s %-20s %s\n", "TOPIC", "MESSAGE", "PUBLISHED BY", "WHAT");
    for (size_t i = 0; i < cgs_topics_count (); i++) {
        const cgs_topic_t *t = cgs_topics_at (i);
        printf ("%-12s %-16s %-20s %s\n", t->name, t->message->name,
                strcmp (t->publishers, "*") == 0 ? "every service" : t->publishers, t->what);
    }
    return 0;
}
