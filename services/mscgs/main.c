/* mscgs — the command-line tool: run an exercise on this machine, echo a
 * topic, show every service's health, send operator commands.
 *
 *   mscgs run [--exercise F] [--scenario F] [--speed X] [--duration S] [--out DIR]
 *             [--resume] [--stop-after-intercept S]
 *   mscgs echo TOPIC [--json] [--count N] [--timeout S] [--exercise F]
 *   mscgs status [--wait S] [--exercise F]
 *   mscgs ping INSTANCE [--exercise F]
 *   mscgs topics
 *   mscgs keygen NAME [--dir DIR]
 *   mscgs loiter|goto|route|altitude|speed|pause|resume|time-scale ...   (uavsim)
 *   mscgs designate|cancel|footprint-scale|intercept-mode ...            (guidanced)
 */
#include "cgs_bus.h"
#include "cgs_config.h"
#include "cgs_cmd.h"
#include "cgs_curve.h"
#include "cgs_exercise.h"
#include "cgs_iface.h"
#include "cgs_lifecycle.h"
#include "cgs_loop.h"
#include "cgs_service.h"
#include "cgs_util.h"
#include "cgs_state.h"
#include "cgs_topics.h"
#include "ms_cmd_admin.h"
#include "ms_cmd_operator.h"
#include "ms_cmd_status.h"
#include "ms_health.h"
#include "ms_metrics.h"
#include "ms_montecarlo.h"
#include "ms_observer.h"
#include "ms_tool.h"
#include "gw_params.h"
#include "st_params.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <getopt.h>
#include <limits.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/prctl.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>
#include <zmq.h>

#define MS_MAX_INSTANCES 64

static void s_usage (FILE *f)
{
    fprintf (f, "usage: mscgs COMMAND [options]\n"
                "The mscgs multisensor Common Ground Station simulation.\n\n"
                "commands:\n"
                "  run      start every built service of the exercise on this machine\n"
                "           --exercise F   exercise file\n"
                "           --scenario F   scenario file (default: the exercise's)\n"
                "           --speed X      time scale, simulation seconds per second\n"
                "           --duration S   stop after S seconds of simulation time\n"
                "                          (wall time while no clock is published)\n"
                "           --out DIR      logs, state and outputs (default ./out)\n"
                "           --resume       keep the state the previous run left\n"
                "           --stop-after-intercept S  stop S seconds of simulation time\n"
                "                          after the intercept ends (DONE, LOST, CANCELLED)\n"
                "  echo     print the messages of a topic: echo TOPIC [--json] [--count N]\n"
                "           [--timeout S]\n"
                "  status   a table of every service's health [--wait S]\n"
                "  ping     ask a service's command endpoint for a reply: ping INSTANCE\n"
                "  topics   list the bus topics\n"
                "  keygen   make a CURVE key pair: keygen NAME [--dir DIR]\n"
                "  loiter, goto, route, altitude, speed task a UAV (uavsim); --help for each\n"
                "  pause, resume, time-scale X          the simulation clock (uavsim)\n"
                "  designate TRACK_ID | designate --at POS, cancel, footprint-scale 1|5|10,\n"
                "  intercept-mode head-on|mti-hits      the intercept (guidanced); --help\n"
                "  snapshot [N]  write the imaging sensor's next N frames (default 1) as PNG\n"
                "           files in imagerd's output folder [--to INSTANCE] [--uav ID]\n"
                "  fault INSTANCE crash | hang [S] | slow MS [S]   the debug-only fault\n"
                "           channel of a test build (FAULT=1); --help\n"
                "  montecarlo  whole scenes in lockstep, many runs, with the imaged rate and\n"
                "           tracking metrics: [--scenario F] [--runs N] [--seed S] [--jobs J];\n"
                "           --help\n"
                "Commands to a service try for --wait S seconds (default 3) before they\n"
                "report no reply; a retry is never applied twice.\n\n"
                "The exercise file is --exercise F, else $MSCGS_EXERCISE, else\n"
                "/etc/mscgs/exercise.ini, else the installed or source tree's default exercise.\n");
}

/* ---- shared helpers ------------------------------------------------------------- */

static double s_parse_positive (const char *opt, const char *text)
{
    char *end = NULL;
    double v = strtod (text, &end);
    if (!end || *end || !(v > 0) || !isfinite (v)) {
        fprintf (stderr, "mscgs: %s: expected a positive number, got '%s'\n", opt, text);
        exit (2);
    }
    return v;
}

/* ---- uavsim's task and clock commands ------------------------------------------------ */

/* Where a stationd instance serves the tactical map, from its parameters,
 * on port (its parameters' when 0). Returns false, having said so, when the
 * parameters leave the port to the system (port = 0): the address is known
 * once stationd reports the port it was given (its http_port counter). */
static bool s_print_map_address (const cgs_instance_t *in, int port)
{
    st_params_t p;
    char err[512];
    st_params_defaults (&p);
    if (*in->params && st_params_load (in->params, &p, err, sizeof err) < 0)
        return true; // stationd itself reports the error in its log
    if (port == 0 && p.port == 0) {
        printf ("mscgs run: tactical map (%s) on a free port the system chooses: its address "
                "follows when %s reports it\n",
                in->name, in->name);
        return false;
    }
    const char *host =
        strcmp (p.listen_address, "0.0.0.0") == 0 || strcmp (p.listen_address, "::") == 0
            ? in->host
            : p.listen_address;
    bool v6 = strchr (host, ':') != NULL;
    printf ("mscgs run: tactical map (%s) at http://%s%s%s:%d/%s\n", in->name, v6 ? "[" : "", host,
            v6 ? "]" : "", port ? port : p.port,
            p.token[0] ? "?token=... (the configured token)" : "");
    return true;
}

/* Where a gateway instance sends DIS, from its parameters, and whether that
 * leaves this machine (its interface looked up here, as the gateway does). */
static void s_print_dis_destination (const cgs_instance_t *in)
{
    gw_params_t p;
    char err[512], where[160];
    gw_params_defaults (&p);
    if (*in->params && gw_params_load (in->params, &p, err, sizeof err) < 0)
        return; // the gateway itself reports the error in its log
    gw_params_describe (&p, where, sizeof where);
    cgs_iface_t ifc = {0};
    bool known = !*p.interface || cgs_iface_find (p.interface, &ifc) == 0;
    printf ("mscgs run: DIS (%s) %s: %s\n", in->name, where,
            !known                                     ? "no such interface here (see its log)"
            : gw_params_leaves_host (&p, ifc.loopback) ? "LEAVES THIS MACHINE, onto the network"
                                                       : "this machine only");
}

/* A number; exits 2 if not. */
static double s_number (const char *what, const char *text)
{
    double v = 0;
    if (ms_opts_number (what, text, &v) < 0)
        exit (2);
    return v;
}

/* ---- run ------------------------------------------------------------------------------ */

typedef struct {
    const cgs_instance_t *instance;
    char binary[PATH_MAX];
    pid_t pid;
    int restarts;
    double next_start; // monotonic; when to (re)start it
    double started_at;
    int quick_failures; // exits within 10 s of starting, in a row
    bool given_up;
    int last_status;
    bool map_auto;     // a stationd whose map port the system chooses (port = 0)
    uint64_t map_told; // ... the port last printed for it (0: none yet)
} s_child_t;

typedef struct {
    cgs_exercise_t *ex;
    const char *exercise_path;
    const char *scenario;
    double speed;
    double duration_s;
    double stop_after_intercept_s; // stop this long after the intercept ends; < 0: never
    bool resume;                   // keep the state of the previous run in OUT/state
    char out[PATH_MAX];
    char logs[PATH_MAX + 8];
    char state[PATH_MAX + 8];
    s_child_t children[MS_MAX_INSTANCES];
    size_t nchildren;
    ms_health_t table;
    ms_icpt_t icpt;
    ms_metrics_t *metrics; // tracking quality against ground truth
    cgs_sub_t *sub;
    double start;
    bool tty;
} s_run_t;

static void s_child_start (s_run_t *run, s_child_t *ch)
{
    char log[PATH_MAX + 80];
    snprintf (log, sizeof log, "%s/%s.log", run->logs, ch->instance->name);
    char speed[32];
    snprintf (speed, sizeof speed, "%g", run->speed);
    pid_t pid = fork ();
    if (pid < 0) {
        fprintf (stderr, "mscgs run: cannot start %s: %s\n", ch->instance->name, strerror (errno));
        ch->next_start = cgs_loop_now () + 1.0;
        return;
    }
    if (pid == 0) {
        int fd = open (log, O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0644);
        if (fd >= 0) {
            dup2 (fd, STDOUT_FILENO);
            dup2 (fd, STDERR_FILENO);
        }
        int devnull = open ("/dev/null", O_RDONLY);
        if (devnull >= 0)
            dup2 (devnull, STDIN_FILENO);
        setpgid (0, 0); // Ctrl-C reaches mscgs, which stops the children in order
        prctl (PR_SET_PDEATHSIG, SIGTERM); // and if mscgs dies, they stop too
        signal (SIGPIPE, SIG_DFL);
        const char *argv[16];
        int n = 0;
        argv[n++] = ch->binary;
        argv[n++] = "--exercise";
        argv[n++] = run->exercise_path;
        argv[n++] = "--instance";
        argv[n++] = ch->instance->name;
        argv[n++] = "--state-dir";
        argv[n++] = run->state;
        if (run->scenario) {
            argv[n++] = "--scenario";
            argv[n++] = run->scenario;
        }
        if (run->speed > 0) {
            argv[n++] = "--time-scale";
            argv[n++] = speed;
        }
        char images[sizeof run->out + 16];
        if (strcmp (ch->instance->program, "imagerd") == 0) { // its frames beside the summary
            snprintf (images, sizeof images, "%s/images", run->out);
            argv[n++] = "--out";
            argv[n++] = images;
        }
        argv[n] = NULL;
        execv (ch->binary, (char *const *)argv);
        fprintf (stderr, "mscgs run: cannot execute %s: %s\n", ch->binary, strerror (errno));
        _exit (127);
    }
    ch->pid = pid;
    ch->started_at = cgs_loop_now ();
}

static void s_reap (s_run_t *run)
{
    int status;
    pid_t pid;
    while ((pid = waitpid (-1, &status, WNOHANG)) > 0) {
        for (size_t i = 0; i < run->nchildren; i++) {
            s_child_t *ch = &run->children[i];
            if (ch->pid != pid)
                continue;
            ch->pid = 0;
            ch->last_status = status;
            if (cgs_lifecycle_stopping ())
                break;
            double now = cgs_loop_now ();
            char how[64];
            if (WIFEXITED (status))
                snprintf (how, sizeof how, "exited with status %d", WEXITSTATUS (status));
            else
                snprintf (how, sizeof how, "was killed by %s", strsignal (WTERMSIG (status)));
            ch->quick_failures = now - ch->started_at < 10.0 ? ch->quick_failures + 1 : 0;
            // As systemd's start limit: five quick failures in a row, stop trying.
            if (ch->quick_failures >= 5) {
                ch->given_up = true;
                fprintf (stderr,
                         "mscgs run: %s %s; it failed 5 times in a row within 10 s of "
                         "starting, so it stays down (see %s/%s.log)\n",
                         ch->instance->name, how, run->logs, ch->instance->name);
                break;
            }
            double delay =
                ch->quick_failures > 0 ? fmin (10.0, 1.0 * (1 << ch->quick_failures)) : 1.0;
            ch->restarts++;
            ch->next_start = now + delay;
            fprintf (stderr, "mscgs run: %s %s; restarting in %.0f s (restart %d, log %s/%s.log)\n",
                     ch->instance->name, how, delay, ch->restarts, run->logs, ch->instance->name);
        }
    }
}

/* The address of a map on a port the system chose, once its stationd has
 * reported the port, and again when a restarted one reports another (on its
 * own line, even between progress lines). */
static void s_tell_map_ports (s_run_t *run)
{
    for (size_t i = 0; i < run->nchildren; i++) {
        s_child_t *ch = &run->children[i];
        if (!ch->map_auto)
            continue;
        for (size_t j = 0; j < run->table.nrows; j++) {
            const ms_health_row_t *r = &run->table.rows[j];
            if (strcmp (r->instance, ch->instance->name) != 0 || r->http_port == 0 ||
                r->http_port > 65535 || r->http_port == ch->map_told)
                continue;
            if (run->tty)
                fputs ("\r\033[K", stdout);
            s_print_map_address (ch->instance, (int)r->http_port);
            fflush (stdout);
            ch->map_told = r->http_port;
        }
    }
}

static void s_progress (s_run_t *run)
{
    double now = cgs_loop_now ();
    size_t up = 0, running = 0;
    double in = 0;
    uint64_t gaps = 0, drops = 0, malformed = 0;
    const char *error_from = NULL, *error = NULL;
    for (size_t i = 0; i < run->table.nrows; i++) {
        const ms_health_row_t *r = &run->table.rows[i];
        if (r->seen && now - r->seen_at < 3.0) {
            up++;
            in += r->in_per_s;
            gaps += r->gaps;
            drops += r->drops;
            malformed += r->malformed;
            if (*r->last_error) {
                error_from = r->instance;
                error = r->last_error;
            }
        }
    }
    for (size_t i = 0; i < run->nchildren; i++)
        running += run->children[i].pid > 0;
    char sim[64];
    if (run->table.have_clock)
        snprintf (sim, sizeof sim, "sim %.1f s x%.3g%s", run->table.sim_time_s,
                  run->table.time_scale, run->table.paused ? " paused" : "");
    else
        snprintf (sim, sizeof sim, "no clock yet");
    char icpt[64] = "";
    const ms_icpt_t *ic = &run->icpt;
    if (ic->seen && (ic->track_id != 0 || ic->state != CGS__INTERCEPT_STATE__INTERCEPT_STATE_IDLE))
        snprintf (icpt, sizeof icpt, " | intercept %s track %u", ms_icpt_state_name (ic->state),
                  ic->track_id);
    fprintf (stdout,
             "%s[%6.1f s] %s | %zu/%zu running, %zu reporting | in %.0f msg/s | gaps %llu drops "
             "%llu malformed %llu%s%s%s%s%s",
             run->tty ? "\r\033[K" : "", now - run->start, sim, running, run->nchildren, up, in,
             (unsigned long long)gaps, (unsigned long long)drops, (unsigned long long)malformed,
             icpt, error ? " | " : "", error_from ? error_from : "", error ? ": " : "",
             error ? error : "");
    if (!run->tty)
        fputc ('\n', stdout);
    fflush (stdout);
}

/* DIR/summary.txt: the run, the services, their last health and the
 * intercept. 0 or -errno. */
static int s_write_summary_text (s_run_t *run, const char *path)
{
    FILE *f = fopen (path, "w");
    if (!f)
        return -errno;
    fprintf (f, "mscgs run of exercise %s (%s)\n", cgs_exercise_name (run->ex), run->exercise_path);
    fprintf (f, "wall time %.1f s", cgs_loop_now () - run->start);
    if (run->table.have_clock)
        fprintf (f, ", simulation time %.1f s", run->table.sim_time_s);
    fprintf (f, "\n\nservices started:\n");
    for (size_t i = 0; i < run->nchildren; i++)
        fprintf (f, "  %-16s %s, %d restart%s%s\n", run->children[i].instance->name,
                 run->children[i].binary, run->children[i].restarts,
                 run->children[i].restarts == 1 ? "" : "s",
                 run->children[i].given_up ? ", gave up" : "");
    fprintf (f, "\nlast health:\n");
    ms_health_print (&run->table, f);
    fprintf (f, "\n");
    ms_icpt_print (&run->icpt, f);
    if (run->metrics) {
        fprintf (f, "\n");
        ms_metrics_print (run->metrics, f);
    }
    int rc = ferror (f) ? -EIO : 0;
    if (fclose (f) != 0 && rc == 0)
        rc = -errno;
    return rc;
}

/* DIR/summary.json: the intercept's members, then the tracking figures
 * under "tracking" (left out without memory). 0 or -errno. */
static int s_write_summary_json (s_run_t *run, const char *path)
{
    json_object *o = ms_icpt_json (&run->icpt);
    if (!o)
        return -ENOMEM;
    json_object *tracking = run->metrics ? ms_metrics_json (run->metrics) : NULL;
    if (tracking)
        cgs_json_add (o, "tracking", tracking);
    FILE *f = fopen (path, "w");
    int rc =
        f ? cgs_json_print (f, o, JSON_C_TO_STRING_PRETTY | JSON_C_TO_STRING_SPACED, "\n") : -errno;
    json_object_put (o);
    if (f && fclose (f) != 0 && rc == 0)
        rc = -errno;
    return rc;
}

/* DIR/summary.txt and DIR/summary.json; the intercept's part to stdout too. */
static void s_write_summary (s_run_t *run)
{
    char path[PATH_MAX + 16];
    snprintf (path, sizeof path, "%s/summary.txt", run->out);
    int rc = s_write_summary_text (run, path);
    if (rc < 0)
        fprintf (stderr, "mscgs run: cannot write %s: %s\n", path, strerror (-rc));
    snprintf (path, sizeof path, "%s/summary.json", run->out);
    rc = s_write_summary_json (run, path);
    if (rc < 0)
        fprintf (stderr, "mscgs run: cannot write %s: %s\n", path, strerror (-rc));
    ms_icpt_print (&run->icpt, stdout);
    if (run->metrics)
        ms_metrics_print (run->metrics, stdout);
}

/* The observer's handlers, then the metrics' (which read the observer's
 * hit attribution). */
static void s_run_on_track (void *arg, const char *topic, const ProtobufCMessage *msg,
                            const Cgs__Header *hdr)
{
    s_run_t *run = arg;
    ms_icpt_on_track (&run->icpt, topic, msg, hdr);
    if (run->metrics)
        ms_metrics_on_track (run->metrics, topic, msg, hdr);
}

static void s_run_on_mti_truth (void *arg, const char *topic, const ProtobufCMessage *msg,
                                const Cgs__Header *hdr)
{
    s_run_t *run = arg;
    ms_icpt_on_mti_truth (&run->icpt, topic, msg, hdr);
    if (run->metrics)
        ms_metrics_on_mti_truth (run->metrics, topic, msg, hdr);
}

static void s_run_on_entity (void *arg, const char *topic, const ProtobufCMessage *msg,
                             const Cgs__Header *hdr)
{
    s_run_t *run = arg;
    ms_icpt_on_entity (&run->icpt, topic, msg, hdr);
    if (run->metrics)
        ms_metrics_on_entity (run->metrics, topic, msg, hdr);
}

/* True when --duration has passed, or --stop-after-intercept's time after
 * the intercept ended (simulation time: the clock's, or the latest the
 * intercept and entity messages carried while nobody publishes clock). */
static bool s_run_over (const s_run_t *run)
{
    if (run->duration_s > 0) {
        double elapsed =
            run->table.have_clock ? run->table.sim_time_s : cgs_loop_now () - run->start;
        if (elapsed >= run->duration_s)
            return true;
    }
    if (run->stop_after_intercept_s >= 0 && run->icpt.final) {
        double sim_s = run->table.have_clock ? run->table.sim_time_s : run->icpt.latest_s;
        if (sim_s >= run->icpt.final_s + run->stop_after_intercept_s)
            return true;
    }
    return false;
}

/* Remove the plain files of a folder (the services' state files). */
static void s_clear_folder (const char *dir)
{
    DIR *d = opendir (dir);
    if (!d)
        return;
    struct dirent *e;
    while ((e = readdir (d)) != NULL) {
        char path[PATH_MAX + 300];
        snprintf (path, sizeof path, "%s/%s", dir, e->d_name);
        struct stat st;
        if (lstat (path, &st) == 0 && S_ISREG (st.st_mode))
            unlink (path);
    }
    closedir (d);
}

static int s_cmd_run (int argc, char **argv)
{
    static s_run_t run;
    const char *exercise = NULL;
    snprintf (run.out, sizeof run.out, "out");
    run.stop_after_intercept_s = -1;
    static const struct option opts[] = {{"exercise", required_argument, NULL, 'e'},
                                         {"scenario", required_argument, NULL, 's'},
                                         {"speed", required_argument, NULL, 'x'},
                                         {"duration", required_argument, NULL, 'd'},
                                         {"out", required_argument, NULL, 'o'},
                                         {"resume", no_argument, NULL, 'R'},
                                         {"stop-after-intercept", required_argument, NULL, 'I'},
                                         {"help", no_argument, NULL, 'h'},
                                         {NULL, 0, NULL, 0}};
    int c;
    while ((c = getopt_long (argc, argv, "h", opts, NULL)) != -1) {
        switch (c) {
        case 'e':
            exercise = optarg;
            break;
        case 's':
            run.scenario = optarg;
            break;
        case 'x':
            run.speed = s_parse_positive ("--speed", optarg);
            break;
        case 'd':
            run.duration_s = s_parse_positive ("--duration", optarg);
            break;
        case 'o':
            snprintf (run.out, sizeof run.out, "%s", optarg);
            break;
        case 'R':
            run.resume = true;
            break;
        case 'I':
            run.stop_after_intercept_s = s_number ("--stop-after-intercept", optarg);
            if (run.stop_after_intercept_s < 0) {
                fprintf (stderr, "mscgs run: --stop-after-intercept: expected seconds >= 0\n");
                return 2;
            }
            break;
        default:
            fprintf (c == 'h' ? stdout : stderr,
                     "usage: mscgs run [--exercise F] [--scenario F] [--speed X] [--duration S] "
                     "[--out DIR] [--resume]\n"
                     "                 [--stop-after-intercept S]\n"
                     "Start every enabled service of the exercise whose program is built (beside\n"
                     "this mscgs), restart any that dies, show progress, and stop them all on\n"
                     "Ctrl-C, after --duration, or --stop-after-intercept S seconds of simulation\n"
                     "time after the intercept ends (DONE, LOST or CANCELLED). Logs go to\n"
                     "DIR/logs, state to DIR/state, a summary to DIR/summary.txt (with how the\n"
                     "intercept imaged its true target, also in DIR/summary.json). A run starts\n"
                     "from the scenario; --resume keeps the state the previous run left in\n"
                     "DIR/state.\n");
            return c == 'h' ? 0 : 2;
        }
    }
    if (run.scenario && access (run.scenario, R_OK) != 0) {
        fprintf (stderr, "mscgs run: --scenario %s: %s\n", run.scenario, strerror (errno));
        return 2;
    }
    char buf[PATH_MAX];
    const char *path = ms_tool_exercise_path (exercise, buf, sizeof buf);
    static char abs_path[PATH_MAX];
    if (!realpath (path, abs_path))
        snprintf (abs_path, sizeof abs_path, "%s", path);
    run.exercise_path = abs_path;
    run.ex = ms_tool_load_exercise (abs_path);
    if (!run.ex)
        return 1;
    static char abs_scenario[PATH_MAX];
    if (run.scenario && realpath (run.scenario, abs_scenario))
        run.scenario = abs_scenario;
    if (cgs_state_mkdir (run.out) < 0 || !realpath (run.out, buf)) {
        fprintf (stderr, "mscgs run: cannot create %s: %s\n", run.out, strerror (errno));
        return 1;
    }
    snprintf (run.out, sizeof run.out, "%s", buf);
    snprintf (run.logs, sizeof run.logs, "%s/logs", run.out);
    snprintf (run.state, sizeof run.state, "%s/state", run.out);
    cgs_state_mkdir (run.logs);
    cgs_state_mkdir (run.state);
    if (!run.resume)
        s_clear_folder (run.state); // a new run starts from the scenario

    for (size_t i = 0; i < cgs_exercise_instance_count (run.ex) && run.nchildren < MS_MAX_INSTANCES;
         i++) {
        const cgs_instance_t *in = cgs_exercise_instance (run.ex, i);
        if (!in->enabled || strcmp (in->program, "mscgs") == 0)
            continue;
        s_child_t *ch = &run.children[run.nchildren];
        snprintf (ch->binary, sizeof ch->binary, "%s/%s", ms_tool_exe_dir (), in->program);
        if (access (ch->binary, X_OK) != 0)
            continue; // not built yet
        ch->instance = in;
        run.nchildren++;
    }
    printf ("mscgs run: exercise %s, %zu of %zu services built here; out %s\n",
            cgs_exercise_name (run.ex), run.nchildren, cgs_exercise_instance_count (run.ex),
            run.out);
    if (run.nchildren == 0)
        printf ("mscgs run: no service program is built yet in %s; only watching the bus\n",
                ms_tool_exe_dir ());
    for (size_t i = 0; i < run.nchildren; i++)
        if (strcmp (run.children[i].instance->program, "stationd") == 0)
            run.children[i].map_auto = !s_print_map_address (run.children[i].instance, 0);
        else if (strcmp (run.children[i].instance->program, "gateway") == 0)
            s_print_dis_destination (run.children[i].instance);

    cgs_lifecycle_init ();
    void *ctx = NULL;
    run.sub = ms_tool_open_sub (run.ex, &ctx);
    if (!run.sub)
        return 1;
    ms_health_init (&run.table, run.ex);
    ms_icpt_init (&run.icpt);
    cgs_sub_on (run.sub, "health", ms_health_on_health, &run.table);
    cgs_sub_on (run.sub, "clock", ms_health_on_clock, &run.table);
    run.metrics = ms_metrics_new (&run.icpt);
    cgs_sub_on (run.sub, "intercept", ms_icpt_on_intercept, &run.icpt);
    cgs_sub_on (run.sub, "track", s_run_on_track, &run);
    cgs_sub_on (run.sub, "mti.truth", s_run_on_mti_truth, &run);
    cgs_sub_on (run.sub, "entity", s_run_on_entity, &run);
    ms_tool_connect_publishers (run.sub, run.ex, "health"); // every service publishes health
    run.start = cgs_loop_now ();
    run.tty = isatty (STDOUT_FILENO);
    for (size_t i = 0; i < run.nchildren; i++)
        s_child_start (&run, &run.children[i]);

    double next_progress = run.start + 1.0;
    double progress_every = run.tty ? 1.0 : 5.0;
    while (!cgs_lifecycle_stopping ()) {
        if (cgs_lifecycle_take_reload ()) {
            printf ("\nmscgs run: SIGHUP (terminal closed?): stopping\n");
            break;
        }
        cgs_sub_poll (run.sub, 100);
        s_reap (&run);
        s_tell_map_ports (&run);
        double now = cgs_loop_now ();
        for (size_t i = 0; i < run.nchildren; i++) {
            s_child_t *ch = &run.children[i];
            if (ch->pid == 0 && !ch->given_up && ch->next_start > 0 && now >= ch->next_start) {
                ch->next_start = 0;
                s_child_start (&run, ch);
            }
        }
        if (now >= next_progress) {
            s_progress (&run);
            next_progress = now + progress_every;
        }
        if (s_run_over (&run))
            break;
    }
    if (run.tty)
        fputc ('\n', stdout);
    if (run.icpt.final && run.stop_after_intercept_s >= 0)
        printf ("mscgs run: the intercept ended (%s) at sim %.1f s\n",
                ms_icpt_state_name (run.icpt.desig_state), run.icpt.final_s);
    else if (run.duration_s > 0 && s_run_over (&run))
        printf ("mscgs run: --duration %g s reached: the safety stop, before %s\n", run.duration_s,
                run.icpt.designated ? "the intercept ended" : "any target was designated");
    printf ("mscgs run: stopping %zu services\n", run.nchildren);
    for (size_t i = 0; i < run.nchildren; i++)
        if (run.children[i].pid > 0)
            kill (run.children[i].pid, SIGTERM);
    double deadline = cgs_loop_now () + 10.0;
    for (;;) {
        size_t alive = 0;
        for (size_t i = 0; i < run.nchildren; i++) {
            s_child_t *ch = &run.children[i];
            if (ch->pid > 0 && waitpid (ch->pid, &ch->last_status, WNOHANG) == ch->pid)
                ch->pid = 0;
            alive += ch->pid > 0;
        }
        if (alive == 0)
            break;
        if (cgs_loop_now () > deadline) {
            for (size_t i = 0; i < run.nchildren; i++)
                if (run.children[i].pid > 0) {
                    fprintf (stderr, "mscgs run: %s did not stop in 10 s; killing it\n",
                             run.children[i].instance->name);
                    kill (run.children[i].pid, SIGKILL);
                    waitpid (run.children[i].pid, NULL, 0);
                    run.children[i].pid = 0;
                }
            break;
        }
        usleep (20000);
    }
    s_write_summary (&run);
    printf ("mscgs run: done; logs in %s, summary in %s/summary.txt\n", run.logs, run.out);
    cgs_sub_destroy (&run.sub);
    ms_metrics_destroy (&run.metrics);
    zmq_ctx_term (ctx);
    cgs_exercise_destroy (&run.ex);
    return 0;
}

int main (int argc, char **argv)
{
    ms_tool_init ();
    if (argc < 2) {
        s_usage (stderr);
        return 2;
    }
    const char *cmd = argv[1];
    // Each command parses its own options from argv[1] on.
    argc--;
    argv++;
    optind = 1;
    if (strcmp (cmd, "run") == 0)
        return s_cmd_run (argc, argv);
    if (strcmp (cmd, "echo") == 0)
        return ms_echo_main (argc, argv);
    if (strcmp (cmd, "status") == 0)
        return ms_status_main (argc, argv);
    if (strcmp (cmd, "ping") == 0)
        return ms_ping_main (argc, argv);
    if (strcmp (cmd, "topics") == 0)
        return ms_topics_main (argc, argv);
    if (strcmp (cmd, "keygen") == 0)
        return ms_keygen_main (argc, argv);
    if (strcmp (cmd, "snapshot") == 0)
        return ms_snapshot_main (argc, argv);
    if (strcmp (cmd, "fault") == 0)
        return ms_fault_main (argc, argv);
    if (strcmp (cmd, "montecarlo") == 0)
        return ms_montecarlo_main (argc, argv);
    const char *tasks[] = {"loiter", "goto",  "route",  "altitude",
                           "speed",  "pause", "resume", "time-scale"};
    for (size_t i = 0; i < sizeof tasks / sizeof tasks[0]; i++)
        if (strcmp (cmd, tasks[i]) == 0)
            return ms_task_main (argc, argv);
    const char *guide[] = {"designate", "cancel", "footprint-scale", "intercept-mode"};
    for (size_t i = 0; i < sizeof guide / sizeof guide[0]; i++)
        if (strcmp (cmd, guide[i]) == 0)
            return ms_guide_main (argc, argv);
    if (strcmp (cmd, "help") == 0 || strcmp (cmd, "-h") == 0 || strcmp (cmd, "--help") == 0) {
        s_usage (stdout);
        return 0;
    }
    if (strcmp (cmd, "--version") == 0) {
        printf ("mscgs %s\n", CGS_VERSION);
        return 0;
    }
    fprintf (stderr, "mscgs: unknown command '%s'\n\n", cmd);
    s_usage (stderr);
    return 2;
}
