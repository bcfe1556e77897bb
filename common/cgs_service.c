/* cgs_service — the shell shared by every service's main.c. */
#include "cgs_service.h"
#include "cgs_entities.h"
#include "cgs_lifecycle.h"
#include "cgs_log.h"
#include "cgs_state.h"
#include "cgs_topics.h"

#include <errno.h>
#include <sys/file.h>
#include <fcntl.h>
#include <getopt.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <zmq.h>

#define S_DEFAULT_EXERCISE "/etc/mscgs/exercise.ini"

struct cgs_service {
    const cgs_service_info_t *info;
    char instance_name[CGS_NAME_MAX];
    char exercise_path[4096];
    char scenario[4096];   // "" when none given (and none in the exercise)
    char params[4096];     // "" when none given (and none in the instance)
    char state_dir[4096];  // absolute, created
    double time_scale;     // --time-scale, else the exercise's
    bool time_scale_given; // --time-scale was on the command line
    bool check_only;       // --check: validate and exit
    int verbose;
    void *ctx; // ZeroMQ context
    cgs_exercise_t *exercise;
    const cgs_instance_t *instance;
    cgs_loop_t *loop;
    cgs_pub_t *pub;        // NULL when the instance has no publish endpoint
    cgs_sub_t *sub;        // created by the first cgs_service_subscribe
    cgs_cmd_server_t *cmd; // created by cgs_service_serve_commands
    cgs_health_t *health;
    cgs_curve_t *curve; // CURVE keys and the ZAP handler; NULL when the exercise names none
    double sim_time_s;  // latest simulation time, stamped on health
    char connected[64][CGS_ENDPOINT_MAX]; // endpoints the subscriber connected to
    int lock_fd;                 // STATE_DIR/INSTANCE.lock, held for the process's life (-1 before)
    uint64_t bad_inputs;         // messages the service could not use (cgs_service_bad_input)
    cgs_cmd_server_t *fault_cmd; // the fault channel (built with CGS_FAULT only), else NULL
    cgs_fault_t fault;           // its requests and schedule
    bool cmd_held;               // cgs_service_hold_commands
    size_t nconnected;
    cgs_seal_key_t seal; // the exercise's group key ([bus] key_file)
    bool sealed;         // every payload is sealed with it
};

#ifdef CGS_FAULT
/* ---- the debug-only fault channel (cgs_fault.h) ---------------------------------------- */

static void s_on_fault_command (void *arg, const Cgs__Command *cmd, Cgs__Reply *reply)
{
    cgs_service_t *svc = arg;
    static char text[256];
    if (cmd->body_case != CGS__COMMAND__BODY_FAULT) {
        reply->status = CGS__REPLY_STATUS__REPLY_STATUS_UNSUPPORTED;
        reply->error = "the fault channel takes fault requests only";
        return;
    }
    if (cgs_fault_request (&svc->fault, cmd->fault, cgs_loop_now (), text, sizeof text) < 0) {
        reply->status = CGS__REPLY_STATUS__REPLY_STATUS_ERROR;
        reply->error = text;
        return;
    }
    const Cgs__Fault *f = cmd->fault;
    if (f->action == CGS__FAULT_ACTION__FAULT_ACTION_SLOW && f->seconds > 0)
        snprintf (text, sizeof text, "stalling %u ms in every %.0f ms for %g s", f->stall_ms,
                  CGS_FAULT_PERIOD_S * 1e3, f->seconds);
    else if (f->action == CGS__FAULT_ACTION__FAULT_ACTION_SLOW)
        snprintf (text, sizeof text, "stalling %u ms in every %.0f ms until the end", f->stall_ms,
                  CGS_FAULT_PERIOD_S * 1e3);
    else if (f->action == CGS__FAULT_ACTION__FAULT_ACTION_HANG && f->seconds > 0)
        snprintf (text, sizeof text, "hanging for %g s after this reply", f->seconds);
    else if (f->action == CGS__FAULT_ACTION__FAULT_ACTION_HANG)
        snprintf (text, sizeof text, "hanging until killed, after this reply");
    else
        snprintf (text, sizeof text, "crashing after this reply");
    cgs_log (LOG_WARNING, "fault channel: %s", text);
    reply->detail = text;
}

/* After the replies went out: do a pending crash or hang. */
static void s_on_fault (void *arg)
{
    cgs_service_t *svc = arg;
    cgs_cmd_server_dispatch (svc->fault_cmd, 10);
    double hang_s = 0;
    switch (cgs_fault_take (&svc->fault, &hang_s)) {
    case CGS__FAULT_ACTION__FAULT_ACTION_CRASH:
        usleep (200000); // lets ZeroMQ's I/O thread send the reply
        abort ();
    case CGS__FAULT_ACTION__FAULT_ACTION_HANG: {
        double end = cgs_loop_now () + hang_s;
        while (hang_s <= 0 || cgs_loop_now () < end)
            usleep (10000); // deaf to signals but SIGKILL, like a real hang
        cgs_log (LOG_WARNING, "fault channel: the hang of %g s is over", hang_s);
        break;
    }
    default:
        break;
    }
}

static void s_on_fault_slow (void *arg)
{
    cgs_service_t *svc = arg;
    bool was = svc->fault.stall_ms > 0;
    unsigned ms = cgs_fault_stall_ms (&svc->fault, cgs_loop_now ());
    if (ms > 0)
        usleep (ms * 1000u);
    else if (was)
        cgs_log (LOG_WARNING, "fault channel: the slow-down is over");
}

/* Open the fault channel on ipc://STATE_DIR/INSTANCE.fault; 0 or -errno (logged). */
static int s_fault_open (cgs_service_t *svc)
{
    char ep[4300];
    snprintf (ep, sizeof ep, "ipc://%s/%s.fault", svc->state_dir, svc->instance_name);
    svc->fault_cmd =
        cgs_cmd_server_new (svc->ctx, svc->instance_name, NULL, s_on_fault_command, svc);
    int rc = svc->fault_cmd ? cgs_cmd_server_bind (svc->fault_cmd, ep) : -errno;
    if (rc == 0)
        rc = cgs_loop_add_socket (svc->loop, cgs_cmd_server_socket (svc->fault_cmd), s_on_fault,
                                  svc);
    if (rc == 0 && cgs_loop_add_timer (svc->loop, CGS_FAULT_PERIOD_S, s_on_fault_slow, svc) < 0)
        rc = -ENOMEM;
    if (rc < 0)
        cgs_log (LOG_ERR, "cannot open the fault channel %s: %s", ep, zmq_strerror (-rc));
    else
        cgs_log (LOG_NOTICE, "debug build: fault channel on %s", ep);
    return rc;
}
#endif

static void s_usage (const cgs_service_info_t *info, FILE *f)
{
    fprintf (f, "usage: %s [options]\n%s\n\n", info->program, info->summary);
    fprintf (
        f,
        "  --exercise FILE        exercise file (default $MSCGS_EXERCISE, else %s)\n"
        "  --instance NAME        service instance in the exercise (default %s)\n"
        "  --scenario FILE        scenario file (default: the exercise's)\n"
        "  --params FILE          model parameter file (default: the instance's)\n"
        "  --state-dir DIR        state folder (default: the exercise's)\n"
        "  --time-scale X         simulation seconds per wall second (default: the exercise's)\n"
        "  --check                read and check the configuration, then exit\n"
        "  -v, --verbose          log debug messages\n"
        "  -h, --help             show this help\n"
        "  --version              show the version\n",
        S_DEFAULT_EXERCISE, info->program);
    for (const cgs_service_option_t *o = info->options; o && o->name; o++) {
        char left[64];
        snprintf (left, sizeof left, "--%s%s%s", o->name, o->has_arg ? " " : "",
                  o->has_arg ? (o->arg_name ? o->arg_name : "VALUE") : "");
        fprintf (f, "  %-22s %s\n", left, o->help);
    }
}

static int s_parse (cgs_service_t *svc, int argc, char **argv)
{
    const cgs_service_info_t *info = svc->info;
    enum {
        O_EXERCISE = 1000,
        O_INSTANCE,
        O_SCENARIO,
        O_PARAMS,
        O_STATE,
        O_CHECK,
        O_VERSION,
        O_SCALE,
        O_EXTRA
    };
    struct option opts[64];
    size_t n = 0;
    opts[n++] = (struct option){"exercise", required_argument, NULL, O_EXERCISE};
    opts[n++] = (struct option){"instance", required_argument, NULL, O_INSTANCE};
    opts[n++] = (struct option){"scenario", required_argument, NULL, O_SCENARIO};
    opts[n++] = (struct option){"params", required_argument, NULL, O_PARAMS};
    opts[n++] = (struct option){"state-dir", required_argument, NULL, O_STATE};
    opts[n++] = (struct option){"check", no_argument, NULL, O_CHECK};
    opts[n++] = (struct option){"time-scale", required_argument, NULL, O_SCALE};
    opts[n++] = (struct option){"verbose", no_argument, NULL, 'v'};
    opts[n++] = (struct option){"help", no_argument, NULL, 'h'};
    opts[n++] = (struct option){"version", no_argument, NULL, O_VERSION};
    size_t first_extra = n;
    for (const cgs_service_option_t *o = info->options; o && o->name && n < 62; o++) {
        int val = O_EXTRA + (int)(n - first_extra);
        opts[n++] =
            (struct option){o->name, o->has_arg ? required_argument : no_argument, NULL, val};
    }
    opts[n] = (struct option){NULL, 0, NULL, 0};

    const char *env = getenv ("MSCGS_EXERCISE");
    snprintf (svc->exercise_path, sizeof svc->exercise_path, "%s",
              env && *env ? env : S_DEFAULT_EXERCISE);
    snprintf (svc->instance_name, sizeof svc->instance_name, "%s", info->program);
    optind = 1;
    int c;
    while ((c = getopt_long (argc, argv, "vh", opts, NULL)) != -1) {
        switch (c) {
        case O_EXERCISE:
            snprintf (svc->exercise_path, sizeof svc->exercise_path, "%s", optarg);
            break;
        case O_INSTANCE:
            snprintf (svc->instance_name, sizeof svc->instance_name, "%s", optarg);
            break;
        case O_SCENARIO:
            snprintf (svc->scenario, sizeof svc->scenario, "%s", optarg);
            break;
        case O_PARAMS:
            snprintf (svc->params, sizeof svc->params, "%s", optarg);
            break;
        case O_STATE:
            snprintf (svc->state_dir, sizeof svc->state_dir, "%s", optarg);
            break;
        case O_CHECK:
            svc->check_only = true;
            break;
        case O_SCALE: {
            char *end = NULL;
            svc->time_scale = strtod (optarg, &end);
            svc->time_scale_given = true;
            if (!end || *end || !(svc->time_scale > 0) || svc->time_scale > 1000) {
                fprintf (stderr, "%s: --time-scale: expected a number in (0, 1000], got '%s'\n",
                         info->program, optarg);
                return -EINVAL;
            }
            break;
        }
        case 'v':
            svc->verbose++;
            break;
        case 'h':
            s_usage (info, stdout);
            return 1;
        case O_VERSION:
            printf ("%s (mscgs) %s\n", info->program, CGS_VERSION);
            return 1;
        default:
            if (c >= O_EXTRA && info->on_option) {
                const cgs_service_option_t *o = &info->options[c - O_EXTRA];
                char why[512] = "";
                if (info->on_option (info->option_arg, o->name, optarg, why, sizeof why) < 0) {
                    fprintf (stderr, "%s: --%s: %s\n", info->program, o->name, why);
                    return -EINVAL;
                }
                break;
            }
            fprintf (stderr, "Try '%s --help'.\n", info->program);
            return -EINVAL;
        }
    }
    if (optind < argc) {
        fprintf (stderr, "%s: unexpected argument '%s'\nTry '%s --help'.\n", info->program,
                 argv[optind], info->program);
        return -EINVAL;
    }
    return 0;
}

static void s_on_zap (void *arg)
{
    cgs_service_t *svc = arg;
    cgs_curve_zap_handle (svc->curve);
}

/* Everything cgs_service_new does after allocating svc; on failure the
 * caller destroys the half-built service. */
static int s_init (cgs_service_t *svc, const cgs_service_info_t *info, int argc, char **argv)
{
    svc->info = info;
    int rc = s_parse (svc, argc, argv);
    if (rc != 0)
        return rc;
    cgs_log_init (svc->instance_name, svc->verbose ? LOG_DEBUG : LOG_INFO);

    char err[1024] = "";
    rc = cgs_exercise_load (svc->exercise_path, &svc->exercise, err, sizeof err);
    if (rc < 0) {
        cgs_log (LOG_ERR, "%s", err);
        return rc;
    }
    svc->instance = cgs_exercise_find (svc->exercise, svc->instance_name);
    if (!svc->instance) {
        cgs_log (LOG_ERR, "%s: no [service %s] section; the instances are:", svc->exercise_path,
                 svc->instance_name);
        for (size_t i = 0; i < cgs_exercise_instance_count (svc->exercise); i++)
            cgs_log (LOG_ERR, "  %s", cgs_exercise_instance (svc->exercise, i)->name);
        return -ENOENT;
    }
    if (strcmp (svc->instance->program, info->program) != 0) {
        cgs_log (LOG_ERR, "%s: [service %s] is a %s, not a %s", svc->exercise_path,
                 svc->instance_name, svc->instance->program, info->program);
        return -EINVAL;
    }
    if (!*svc->scenario)
        snprintf (svc->scenario, sizeof svc->scenario, "%s", cgs_exercise_scenario (svc->exercise));
    if (!*svc->params)
        snprintf (svc->params, sizeof svc->params, "%s", svc->instance->params);
    if (!(svc->time_scale > 0))
        svc->time_scale = cgs_exercise_time_scale (svc->exercise);
    if (!*svc->state_dir)
        snprintf (svc->state_dir, sizeof svc->state_dir, "%s",
                  cgs_exercise_state_dir (svc->exercise));
    if (svc->check_only)
        return 0;
    if ((rc = cgs_state_mkdir (svc->state_dir)) < 0) {
        cgs_log (LOG_ERR, "cannot create state folder %s: %s", svc->state_dir, strerror (-rc));
        return rc;
    }
    char abs_dir[PATH_MAX];
    if (realpath (svc->state_dir, abs_dir))
        snprintf (svc->state_dir, sizeof svc->state_dir, "%s", abs_dir);
    // One process per instance: a second copy would take over the first one's
    // ipc endpoints silently and share its state file.
    char lock_path[4200];
    snprintf (lock_path, sizeof lock_path, "%s/%s.lock", svc->state_dir, svc->instance_name);
    svc->lock_fd = open (lock_path, O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (svc->lock_fd < 0) {
        rc = -errno;
        cgs_log (LOG_ERR, "cannot open %s: %s", lock_path, strerror (-rc));
        return rc;
    }
    if (flock (svc->lock_fd, LOCK_EX | LOCK_NB) < 0) {
        rc = -errno;
        cgs_log (LOG_ERR, "%s is already running with state folder %s (%s is locked)%s",
                 svc->instance_name, svc->state_dir, lock_path,
                 rc == -EWOULDBLOCK ? "" : strerror (-rc));
        return rc == -EWOULDBLOCK ? -EBUSY : rc;
    }
    if ((rc = cgs_lifecycle_init ()) < 0) {
        cgs_log (LOG_ERR, "cannot install signal handlers: %s", strerror (-rc));
        return rc;
    }
    svc->ctx = zmq_ctx_new ();
    svc->loop = cgs_loop_new ();
    svc->health = cgs_health_new (info->program, svc->instance_name, CGS_VERSION,
                                  svc->instance ? svc->instance->host : NULL);
    if (!svc->ctx || !svc->loop || !svc->health) {
        cgs_log (LOG_ERR, "out of memory");
        return -ENOMEM;
    }
    char why[1024];
    if ((rc = cgs_curve_load (svc->exercise, svc->instance_name, &svc->curve, why, sizeof why)) <
        0) {
        cgs_log (LOG_ERR, "%s", why);
        return rc;
    }
    if (svc->curve) { // the ZAP handler first: no server socket may admit anyone before it
        if ((rc = cgs_curve_zap_bind (svc->curve, svc->ctx)) < 0 ||
            (rc = cgs_loop_add_socket (svc->loop, cgs_curve_zap_socket (svc->curve), s_on_zap,
                                       svc)) < 0) {
            cgs_log (LOG_ERR, "cannot start the ZAP handler: %s", zmq_strerror (-rc));
            return rc;
        }
        cgs_log (LOG_INFO, "CURVE on every socket, as %s", cgs_curve_public_key (svc->curve));
    }
    const cgs_bus_params_t *bus = cgs_exercise_bus (svc->exercise);
    if (*bus->key_file) {
        if ((rc = cgs_seal_key_load (bus->key_file, &svc->seal, why, sizeof why)) < 0) {
            cgs_log (LOG_ERR, "the bus's group key: %s", why);
            return rc;
        }
        svc->sealed = true;
    }
    cgs_health_set_sealed (svc->health, svc->sealed);
    if (*svc->instance->publish) {
        svc->pub = cgs_pub_new (svc->ctx, svc->instance_name, cgs_exercise_id (svc->exercise));
        if (!svc->pub)
            return -errno;
        cgs_pub_set_hwm (svc->pub, svc->instance->hwm);
        if ((rc = cgs_curve_server (svc->curve, cgs_pub_socket (svc->pub))) < 0) {
            cgs_log (LOG_ERR, "cannot make %s a CURVE server: %s", svc->instance->publish,
                     zmq_strerror (-rc));
            return rc;
        }
        if ((rc = cgs_pub_bind (svc->pub, svc->instance->publish)) < 0) {
            cgs_log (LOG_ERR, "cannot bind %s: %s", svc->instance->publish, zmq_strerror (-rc));
            return rc;
        }
        char mc[CGS_ENDPOINT_MAX];
        if (cgs_exercise_endpoint_for (svc->instance, svc->instance, mc, sizeof mc)) {
            if ((rc = cgs_bus_set_multicast (cgs_pub_socket (svc->pub), bus->rate_kbps,
                                             bus->recovery_ms, bus->hops)) < 0 ||
                (rc = cgs_pub_bind (svc->pub, mc)) < 0) {
                cgs_log (LOG_ERR, "cannot bind %s: %s", mc, zmq_strerror (-rc));
                return rc;
            }
            cgs_log (LOG_INFO, "also publishing on %s", mc);
        }
        if (svc->sealed && (rc = cgs_pub_set_seal (svc->pub, &svc->seal)) < 0)
            return rc;
        cgs_health_watch_pub (svc->health, svc->pub);
    }
    if (svc->sealed)
        cgs_log (LOG_INFO, "bus: every payload sealed with the group key of %s", bus->key_file);
    else if (cgs_exercise_uses_multicast (svc->exercise))
        cgs_log (LOG_WARNING, "bus: multicast in the clear ([bus] key_file names no group key)");
#ifdef CGS_FAULT
    if ((rc = s_fault_open (svc)) < 0)
        return rc;
#endif
    cgs_log (LOG_INFO, "exercise %s (id %u), instance %s, publishing on %s",
             cgs_exercise_name (svc->exercise), cgs_exercise_id (svc->exercise), svc->instance_name,
             *svc->instance->publish ? svc->instance->publish : "(nothing)");
    return 0;
}

int cgs_service_new (const cgs_service_info_t *info, int argc, char **argv, cgs_service_t **ret_svc)
{
    cgs_service_t *svc = calloc (1, sizeof *svc);
    if (!svc) {
        fprintf (stderr, "%s: out of memory\n", info->program);
        return -ENOMEM;
    }
    svc->lock_fd = -1;
    int rc = s_init (svc, info, argc, argv);
    if (rc != 0) {
        cgs_service_destroy (&svc);
        return rc;
    }
    *ret_svc = svc;
    return 0;
}

static void s_on_sub (void *arg)
{
    cgs_service_t *svc = arg;
    cgs_sub_dispatch (svc->sub, 1000);
}

int cgs_service_subscribe (cgs_service_t *svc, const char *topic, cgs_sub_fn *fn, void *arg)
{
    if (!svc->sub) {
        svc->sub = cgs_sub_new (svc->ctx);
        if (!svc->sub)
            return -errno;
        cgs_sub_set_hwm (svc->sub, svc->instance->hwm);
        cgs_sub_set_exercise (svc->sub, cgs_exercise_id (svc->exercise));
        const cgs_bus_params_t *bus = cgs_exercise_bus (svc->exercise);
        int rc = svc->sealed ? cgs_sub_set_seal (svc->sub, &svc->seal, bus->replay_window_s) : 0;
        if (rc == 0 && cgs_exercise_uses_multicast (svc->exercise))
            rc = cgs_bus_set_multicast (cgs_sub_socket (svc->sub), bus->rate_kbps, bus->recovery_ms,
                                        bus->hops);
        if (rc < 0)
            return rc;
        cgs_health_watch_sub (svc->health, svc->sub);
        cgs_loop_add_socket (svc->loop, cgs_sub_socket (svc->sub), s_on_sub, svc);
    }
    int rc = cgs_sub_on (svc->sub, topic, fn, arg);
    if (rc < 0) {
        cgs_log (LOG_ERR, "cannot subscribe to %s: %s", topic, strerror (-rc));
        return rc;
    }
    const cgs_instance_t *pubs[64];
    size_t n = cgs_exercise_publishers_of (svc->exercise, topic, pubs, 64);
    if (n > 64)
        n = 64;
    for (size_t i = 0; i < n; i++) {
        char ep[CGS_ENDPOINT_MAX];
        cgs_exercise_endpoint_for (pubs[i], svc->instance, ep, sizeof ep);
        if (!*ep)
            continue;
        bool seen = false;
        for (size_t k = 0; k < svc->nconnected && !seen; k++)
            seen = strcmp (svc->connected[k], ep) == 0;
        if (seen || svc->nconnected == 64)
            continue;
        if ((rc = cgs_curve_client (svc->curve, cgs_sub_socket (svc->sub), pubs[i]->public_key)) <
                0 ||
            (rc = cgs_sub_connect (svc->sub, ep)) < 0) {
            cgs_log (LOG_ERR, "cannot connect to %s (%s): %s", ep, pubs[i]->name,
                     zmq_strerror (-rc));
            return rc;
        }
        snprintf (svc->connected[svc->nconnected++], CGS_ENDPOINT_MAX, "%s", ep);
    }
    if (n == 0)
        cgs_log (LOG_WARNING, "no instance in %s publishes %s", svc->exercise_path, topic);
    return 0;
}

static void s_on_cmd (void *arg)
{
    cgs_service_t *svc = arg;
    uint64_t failures = cgs_cmd_server_write_errors (svc->cmd);
    cgs_cmd_server_dispatch (svc->cmd, 100);
    if (cgs_cmd_server_write_errors (svc->cmd) != failures) {
        cgs_log (LOG_ERR, "%s", cgs_cmd_server_last_error (svc->cmd));
        cgs_health_set_error (svc->health, cgs_cmd_server_last_error (svc->cmd));
        cgs_health_set_state (svc->health, CGS__SERVICE_STATE__SERVICE_STATE_DEGRADED);
    }
}

int cgs_service_serve_commands (cgs_service_t *svc, cgs_cmd_handler_fn *handler,
                                cgs_cmd_save_fn *save, void *arg)
{
    if (!*svc->instance->command) {
        cgs_log (LOG_ERR, "%s: [service %s] has no command endpoint", svc->exercise_path,
                 svc->instance_name);
        return -EINVAL;
    }
    char cache[4200];
    snprintf (cache, sizeof cache, "%s/%s.state", svc->state_dir, svc->instance_name);
    svc->cmd = cgs_cmd_server_new (svc->ctx, svc->instance_name, cache, handler, arg);
    if (!svc->cmd) {
        int rc = -errno;
        cgs_log (LOG_ERR, "cannot read the state file %s: %s", cache, strerror (-rc));
        return rc;
    }
    cgs_cmd_server_set_save (svc->cmd, save);
    if (*cgs_cmd_server_load_error (svc->cmd)) {
        cgs_log (LOG_WARNING, "saved state ignored: %s", cgs_cmd_server_load_error (svc->cmd));
        cgs_health_set_error (svc->health, cgs_cmd_server_load_error (svc->cmd));
    }
    int rc = cgs_curve_server (svc->curve, cgs_cmd_server_socket (svc->cmd));
    if (rc == 0)
        rc = cgs_cmd_server_bind (svc->cmd, svc->instance->command);
    if (rc < 0) {
        cgs_log (LOG_ERR, "cannot bind %s: %s", svc->instance->command, zmq_strerror (-rc));
        return rc;
    }
    cgs_health_watch_cmd (svc->health, svc->cmd);
    return cgs_loop_add_socket (svc->loop, cgs_cmd_server_socket (svc->cmd), s_on_cmd, svc);
}

void cgs_service_hold_commands (cgs_service_t *svc, bool hold)
{
    if (!svc->cmd || hold == svc->cmd_held)
        return;
    if (hold)
        cgs_loop_remove (svc->loop, cgs_cmd_server_socket (svc->cmd), -1);
    else if (cgs_loop_add_socket (svc->loop, cgs_cmd_server_socket (svc->cmd), s_on_cmd, svc) < 0) {
        cgs_log (LOG_ERR, "out of memory: commands stay held");
        return;
    }
    svc->cmd_held = hold;
}

void cgs_service_saved_state (const cgs_service_t *svc, const uint8_t **ret_buf, size_t *ret_len)
{
    *ret_buf = NULL;
    *ret_len = 0;
    if (svc->cmd)
        cgs_cmd_server_saved_state (svc->cmd, ret_buf, ret_len);
}

int cgs_service_save_state (cgs_service_t *svc)
{
    if (!svc->cmd)
        return -ENOTCONN;
    int rc = cgs_cmd_server_save_now (svc->cmd);
    if (rc < 0) {
        char why[256];
        snprintf (why, sizeof why, "cannot write the state file: %s", strerror (-rc));
        cgs_health_set_error (svc->health, why);
    }
    return rc;
}

int cgs_service_publish (cgs_service_t *svc, const char *topic, ProtobufCMessage *msg)
{
    if (!svc->pub)
        return -ENOTCONN;
    int rc = cgs_pub_send (svc->pub, topic, msg, svc->sim_time_s);
    if (rc < 0 && rc != -EAGAIN) {
        char why[256];
        snprintf (why, sizeof why, "publish %s: %s", topic, zmq_strerror (-rc));
        cgs_health_set_error (svc->health, why);
    }
    return rc;
}

static int s_port_publish (void *arg, const char *topic, ProtobufCMessage *msg, double sim_time_s)
{
    cgs_service_t *svc = arg;
    svc->sim_time_s = sim_time_s;
    return cgs_service_publish (svc, topic, msg);
}

static void s_port_log (void *arg, int priority, const char *line)
{
    (void)arg;
    cgs_log (priority, "%s", line);
}

static void s_port_bad_input (void *arg, const char *what)
{
    cgs_service_bad_input (arg, what);
}

static void s_port_error (void *arg, const char *why)
{
    cgs_service_t *svc = arg;
    cgs_health_set_error (svc->health, why);
}

int cgs_service_load_scene (const cgs_service_t *svc, cgs_geo_t **ret_frame,
                            cgs_scenario_t **ret_scenario, cgs_terrain_t **ret_terrain, char *err,
                            size_t errlen)
{
    *ret_frame = NULL;
    *ret_scenario = NULL;
    *ret_terrain = NULL;
    if (!*svc->scenario) {
        snprintf (err, errlen, "no scenario: give --scenario FILE or `scenario =` in %s",
                  svc->exercise_path);
        return -EINVAL;
    }
    cgs_geodetic_t o = cgs_exercise_origin (svc->exercise);
    cgs_geo_t *frame = cgs_geo_new (o.lat_deg, o.lon_deg, o.height_m);
    if (!frame) {
        snprintf (err, errlen, "%s: the exercise origin is not usable", svc->exercise_path);
        return -EINVAL;
    }
    cgs_scenario_t *sc = NULL;
    cgs_terrain_t *ter = NULL;
    int rc = cgs_scenario_load (svc->scenario, frame, cgs_exercise_seed (svc->exercise), &sc, err,
                                errlen);
    if (rc == 0)
        rc = cgs_scenario_terrain (sc, frame, &ter, err, errlen);
    if (rc < 0) {
        cgs_scenario_destroy (&sc);
        cgs_geo_destroy (&frame);
        return rc;
    }
    *ret_frame = frame;
    *ret_scenario = sc;
    *ret_terrain = ter;
    return 0;
}

cgs_port_t cgs_service_port (cgs_service_t *svc)
{
    return (cgs_port_t){
        .arg = svc,
        .publish = s_port_publish,
        .log = s_port_log,
        .bad_input = s_port_bad_input,
        .error = s_port_error,
    };
}

static void s_on_health (void *arg)
{
    cgs_service_t *svc = arg;
    if (svc->curve) {
        cgs_health_set_counter (svc->health, "curve_admitted", cgs_curve_admitted (svc->curve));
        cgs_health_set_counter (svc->health, "curve_refused", cgs_curve_refused (svc->curve));
    }
    if (cgs_lifecycle_take_reload ())
        cgs_log (LOG_NOTICE,
                 "SIGHUP: nothing to reload (restart the service to read changed files)");
    if (svc->pub)
        cgs_health_publish (svc->health, svc->pub, svc->sim_time_s);
}

static void s_on_watchdog (void *arg)
{
    (void)arg;
    cgs_notify_watchdog ();
}

int cgs_service_run (cgs_service_t *svc)
{
    cgs_loop_add_timer (svc->loop, 1.0, s_on_health, svc);
    uint64_t wd = cgs_notify_watchdog_usec ();
    if (wd > 0)
        cgs_loop_add_timer (svc->loop, (double)wd / 2e6, s_on_watchdog, svc);
    cgs_health_set_state (svc->health, CGS__SERVICE_STATE__SERVICE_STATE_RUNNING);
    s_on_health (svc);
    cgs_notify_ready ("running");
    int rc = cgs_loop_run (svc->loop);
    cgs_notify_stopping ();
    cgs_health_set_state (svc->health, CGS__SERVICE_STATE__SERVICE_STATE_STOPPING);
    s_on_health (svc);
    if (rc < 0) {
        cgs_log (LOG_ERR, "event loop failed: %s", zmq_strerror (-rc));
        return 1;
    }
    int sig = cgs_lifecycle_stop_signal ();
    cgs_log (LOG_INFO, "stopping%s%s", sig ? " on " : "", sig ? strsignal (sig) : "");
    return 0;
}

void cgs_service_destroy (cgs_service_t **self_p)
{
    if (!self_p || !*self_p)
        return;
    cgs_service_t *svc = *self_p;
    cgs_cmd_server_destroy (&svc->cmd);
    cgs_cmd_server_destroy (&svc->fault_cmd);
    cgs_sub_destroy (&svc->sub);
    cgs_pub_destroy (&svc->pub);
    cgs_curve_destroy (&svc->curve);
    explicit_bzero (&svc->seal, sizeof svc->seal);
    cgs_health_destroy (&svc->health);
    cgs_loop_destroy (&svc->loop);
    cgs_exercise_destroy (&svc->exercise);
    if (svc->ctx) {
        zmq_ctx_term (svc->ctx);
        svc->ctx = NULL;
    }
    if (svc->lock_fd >= 0)
        close (svc->lock_fd); // releases the lock
    free (svc);
    *self_p = NULL;
}

const char *cgs_service_instance_name (const cgs_service_t *svc)
{
    return svc->instance_name;
}

const char *cgs_service_exercise_path (const cgs_service_t *svc)
{
    return svc->exercise_path;
}

const char *cgs_service_scenario_path (const cgs_service_t *svc)
{
    return svc->scenario;
}

const char *cgs_service_params_path (const cgs_service_t *svc)
{
    return svc->params;
}

const char *cgs_service_state_dir (const cgs_service_t *svc)
{
    return svc->state_dir;
}

double cgs_service_time_scale (const cgs_service_t *svc)
{
    return svc->time_scale;
}

bool cgs_service_time_scale_given (const cgs_service_t *svc)
{
    return svc->time_scale_given;
}

bool cgs_service_check_only (const cgs_service_t *svc)
{
    return svc->check_only;
}

int cgs_service_verbose (const cgs_service_t *svc)
{
    return svc->verbose;
}

const cgs_exercise_t *cgs_service_exercise (const cgs_service_t *svc)
{
    return svc->exercise;
}

const cgs_instance_t *cgs_service_instance (const cgs_service_t *svc)
{
    return svc->instance;
}

void *cgs_service_ctx (cgs_service_t *svc)
{
    return svc->ctx;
}

cgs_loop_t *cgs_service_loop (cgs_service_t *svc)
{
    return svc->loop;
}

cgs_health_t *cgs_service_health (cgs_service_t *svc)
{
    return svc->health;
}

cgs_curve_t *cgs_service_curve (cgs_service_t *svc)
{
    return svc->curve;
}

cgs_pub_t *cgs_service_pub (cgs_service_t *svc)
{
    return svc->pub;
}

cgs_sub_t *cgs_service_sub (cgs_service_t *svc)
{
    return svc->sub;
}

cgs_cmd_server_t *cgs_service_cmd_server (cgs_service_t *svc)
{
    return svc->cmd;
}

bool cgs_service_commands_held (const cgs_service_t *svc)
{
    return svc->cmd_held;
}

void cgs_service_set_sim_time (cgs_service_t *svc, double sim_time_s)
{
    svc->sim_time_s = sim_time_s;
}

void cgs_service_bad_input (cgs_service_t *svc, const char *what)
{
    if (svc->bad_inputs++ == 0)
        cgs_log (LOG_WARNING, "ignored %s (further ones are only counted in health)", what);
    cgs_health_add_malformed (svc->health, 1);
}

void cgs_service_take_entities (cgs_service_t *svc, struct cgs_entities *ents,
                                const ProtobufCMessage *msg, const Cgs__Header *hdr)
{
    cgs_port_t port = cgs_service_port (svc);
    cgs_entities_take (ents, msg, hdr, &port);
}
