/* ms_run — `mscgs run`, the supervisor: every enabled service of the
 * exercise built beside mscgs started with its options, restarted when it
 * dies (backing off; given up after five quick failures), progress shown,
 * the intercept and the tracking judged from ground truth (ms_observer,
 * ms_metrics), all stopped in order at the end, and the summary written. */
#include "ms_run.h"

#include "cgs_iface.h"
#include "cgs_json.h"
#include "cgs_lifecycle.h"
#include "cgs_loop.h"
#include "cgs_state.h"
#include "gw_params.h"
#include "im_params.h"
#include "ms_health.h"
#include "ms_metrics.h"
#include "ms_observer.h"
#include "ms_tool.h"
#include "st_params.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/prctl.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>
#include <zmq.h>

/* ---- where the map and DIS are ---------------------------------------------------------- */

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
static const char *s_udp_reach (const gw_udp_t *u)
{
    cgs_iface_t ifc = {0};
    bool known =
        u->mode != GW_UDP_MULTICAST || !*u->interface || cgs_iface_find (u->interface, &ifc) == 0;
    return !known                                        ? "no such interface here (see its log)"
           : gw_params_udp_leaves_host (u, ifc.loopback) ? "LEAVES THIS MACHINE, onto the network"
                                                         : "this machine only";
}

/* Where a gateway instance sends DIS, from its parameters, and whether that
 * leaves this machine (its interface looked up here, as the gateway does);
 * and its STANAG 4607 file and UDP, and its Cursor on Target, when on. */
static void s_print_dis_destination (const cgs_instance_t *in, const char *out)
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
    if (p.s4607_file)
        printf ("mscgs run: STANAG 4607 (%s) to %s/%s.4607\n", in->name, out, in->name);
    if (p.s4607_udp.mode != GW_UDP_OFF) {
        gw_params_describe_udp (&p.s4607_udp, where, sizeof where);
        printf ("mscgs run: STANAG 4607 (%s) %s: %s\n", in->name, where,
                s_udp_reach (&p.s4607_udp));
    }
    if (p.cot_udp.mode != GW_UDP_OFF) {
        gw_params_describe_udp (&p.cot_udp, where, sizeof where);
        printf ("mscgs run: Cursor on Target (%s, %s) %s: %s; designations from clients %s\n",
                in->name, p.cot_protobuf ? "TAK protobuf" : "XML", where, s_udp_reach (&p.cot_udp),
                p.cot_designate ? "taken" : "off");
    }
}

/* Where an imagerd instance's video goes, from its parameters. */
static void s_print_video_destination (const cgs_instance_t *in, const char *out)
{
    im_params_t p;
    char err[512];
    im_params_defaults (&p);
    if ((*in->params && im_params_load (in->params, &p, err, sizeof err) < 0) || !p.video)
        return; // an error is the imagerd's to report, in its log
    if (p.video_file)
        printf ("mscgs run: video (%s, H.264 + KLV in MPEG-TS) to %s/images/%s.ts\n", in->name, out,
                in->name);
    char host[64];
    int port;
    if (p.video_udp[0] && im_params_parse_udp (p.video_udp, host, sizeof host, &port) == 0)
        printf ("mscgs run: video (%s) over UDP to %s:%d (ffplay udp://%s:%d)\n", in->name, host,
                port, host, port);
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
    bool record;                   // `mscgs record` into OUT/recording.mcap
    pid_t rec_pid;                 // the recorder (0: none running)
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

/* In a child about to exec: its output appended to log, its input
 * /dev/null, in a process group of its own, stopped when mscgs dies. */
static void s_child_stdio (const char *log)
{
    int fd = open (log, O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0644);
    if (fd >= 0) {
        dup2 (fd, STDOUT_FILENO);
        dup2 (fd, STDERR_FILENO);
    }
    int devnull = open ("/dev/null", O_RDONLY);
    if (devnull >= 0)
        dup2 (devnull, STDIN_FILENO);
    setpgid (0, 0);                    // Ctrl-C reaches mscgs, which stops the children in order
    prctl (PR_SET_PDEATHSIG, SIGTERM); // and if mscgs dies, they stop too
    signal (SIGPIPE, SIG_DFL);
}

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
        s_child_stdio (log);
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
        if (strcmp (ch->instance->program, "gateway") == 0) { // its STANAG 4607 file too
            argv[n++] = "--out";
            argv[n++] = run->out;
        }
        argv[n] = NULL;
        execv (ch->binary, (char *const *)argv);
        fprintf (stderr, "mscgs run: cannot execute %s: %s\n", ch->binary, strerror (errno));
        _exit (127);
    }
    ch->pid = pid;
    ch->started_at = cgs_loop_now ();
}

/* --record: `mscgs record` (this program) into OUT/recording.mcap, its
 * log OUT/logs/record.log; started before the services, stopped after. */
static void s_recorder_start (s_run_t *run)
{
    char log[PATH_MAX + 80], file[PATH_MAX + 32], self[PATH_MAX + 16];
    snprintf (log, sizeof log, "%s/record.log", run->logs);
    snprintf (file, sizeof file, "%s/recording.mcap", run->out);
    snprintf (self, sizeof self, "%s/mscgs", ms_tool_exe_dir ());
    pid_t pid = fork ();
    if (pid < 0) {
        fprintf (stderr, "mscgs run: cannot start the recorder: %s\n", strerror (errno));
        return;
    }
    if (pid == 0) {
        s_child_stdio (log);
        execl (self, self, "record", "--exercise", run->exercise_path, "--out", file, (char *)NULL);
        fprintf (stderr, "mscgs run: cannot execute %s: %s\n", self, strerror (errno));
        _exit (127);
    }
    run->rec_pid = pid;
    printf ("mscgs run: recording every topic into %s\n", file);
    usleep (300000); // its subscriptions out before the services' first messages
}

/* Stop the recorder (after the services: their last words are recorded). */
static void s_recorder_stop (s_run_t *run)
{
    if (run->rec_pid <= 0)
        return;
    kill (run->rec_pid, SIGTERM);
    int status = 0;
    double deadline = cgs_loop_now () + 10.0;
    while (waitpid (run->rec_pid, &status, WNOHANG) == 0) {
        if (cgs_loop_now () > deadline) {
            fprintf (stderr, "mscgs run: the recorder did not stop in 10 s; killing it\n");
            kill (run->rec_pid, SIGKILL);
            waitpid (run->rec_pid, &status, 0);
            break;
        }
        usleep (20000);
    }
    run->rec_pid = 0;
    if (WIFEXITED (status) && WEXITSTATUS (status) == 0)
        printf ("mscgs run: recording in %s/recording.mcap\n", run->out);
    else
        fprintf (stderr, "mscgs run: the recorder failed (see %s/record.log)\n", run->logs);
}

static void s_reap (s_run_t *run)
{
    int status;
    pid_t pid;
    while ((pid = waitpid (-1, &status, WNOHANG)) > 0) {
        if (pid == run->rec_pid) {
            fprintf (stderr, "mscgs run: the recorder stopped (see %s/record.log)\n", run->logs);
            run->rec_pid = 0;
            continue;
        }
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

static s_run_t s_run;          // the run (big: not on the stack), its options' storage
static const char *s_exercise; // --exercise F
static const char *s_out;      // --out DIR

/* --stop-after-intercept S: seconds >= 0. */
static int s_read_stop_after (const ms_opt_t *opt, const char *value)
{
    double v = 0;
    if (ms_opts_number ("--stop-after-intercept", value, &v) < 0)
        return -EINVAL;
    if (v < 0) {
        fprintf (stderr, "mscgs run: --stop-after-intercept: expected seconds >= 0\n");
        return -EINVAL;
    }
    *(double *)opt->arg = v;
    return 0;
}

static const ms_opt_t s_opts[] = {
    MS_TOOL_OPT_EXERCISE (&s_exercise),
    {.name = "scenario",
     .value = "F",
     .help = "scenario file (default: the exercise's)",
     .str = &s_run.scenario},
    {.name = "speed",
     .value = "X",
     .help = "time scale, simulation seconds per second",
     .fn = ms_opts_read_positive,
     .arg = &s_run.speed},
    {.name = "duration",
     .value = "S",
     .help = "stop after S seconds of simulation time\n(wall time while no clock is published)",
     .fn = ms_opts_read_positive,
     .arg = &s_run.duration_s},
    {.name = "out",
     .value = "DIR",
     .help = "logs, state and outputs (default ./out)",
     .str = &s_out},
    {.name = "resume", .help = "keep the state the previous run left", .flag = &s_run.resume},
    {.name = "record",
     .help = "record every topic into DIR/recording.mcap (mscgs record)",
     .flag = &s_run.record},
    {.name = "stop-after-intercept",
     .value = "S",
     .help = "stop S seconds of simulation time\nafter the intercept ends (DONE, LOST, CANCELLED)",
     .fn = s_read_stop_after,
     .arg = &s_run.stop_after_intercept_s},
    MS_OPTS_HELP,
    MS_OPTS_END,
};

static const ms_cmd_t s_spec = {
    .name = "run",
    .about = "Start every enabled service of the exercise whose program is built (beside\n"
             "this mscgs), restart any that dies, show progress, and stop them all on\n"
             "Ctrl-C, after --duration, or --stop-after-intercept S seconds of simulation\n"
             "time after the intercept ends (DONE, LOST or CANCELLED). Logs go to\n"
             "DIR/logs, state to DIR/state, a summary to DIR/summary.txt (with how the\n"
             "intercept imaged its true target, also in DIR/summary.json). A run starts\n"
             "from the scenario; --resume keeps the state the previous run left in\n"
             "DIR/state. --record records every topic into DIR/recording.mcap.\n",
    .opts = s_opts,
};

const ms_opt_t *ms_run_options (void)
{
    return s_opts;
}

int ms_run_main (int argc, char **argv)
{
    s_run.stop_after_intercept_s = -1;
    int nargs = ms_opts_parse (&s_spec, argc, argv);
    if (nargs < 0)
        return ms_opts_exit_code (nargs);
    snprintf (s_run.out, sizeof s_run.out, "%s", s_out ? s_out : "out");
    if (s_run.scenario && access (s_run.scenario, R_OK) != 0) {
        fprintf (stderr, "mscgs run: --scenario %s: %s\n", s_run.scenario, strerror (errno));
        return 2;
    }
    char buf[PATH_MAX];
    const char *path = ms_tool_exercise_path (s_exercise, buf, sizeof buf);
    static char abs_path[PATH_MAX];
    if (!realpath (path, abs_path))
        snprintf (abs_path, sizeof abs_path, "%s", path);
    s_run.exercise_path = abs_path;
    s_run.ex = ms_tool_load_exercise (abs_path);
    if (!s_run.ex)
        return 1;
    static char abs_scenario[PATH_MAX];
    if (s_run.scenario && realpath (s_run.scenario, abs_scenario))
        s_run.scenario = abs_scenario;
    if (cgs_state_mkdir (s_run.out) < 0 || !realpath (s_run.out, buf)) {
        fprintf (stderr, "mscgs run: cannot create %s: %s\n", s_run.out, strerror (errno));
        return 1;
    }
    snprintf (s_run.out, sizeof s_run.out, "%s", buf);
    snprintf (s_run.logs, sizeof s_run.logs, "%s/logs", s_run.out);
    snprintf (s_run.state, sizeof s_run.state, "%s/state", s_run.out);
    cgs_state_mkdir (s_run.logs);
    cgs_state_mkdir (s_run.state);
    if (!s_run.resume)
        s_clear_folder (s_run.state); // a new run starts from the scenario

    for (size_t i = 0;
         i < cgs_exercise_instance_count (s_run.ex) && s_run.nchildren < MS_MAX_INSTANCES; i++) {
        const cgs_instance_t *in = cgs_exercise_instance (s_run.ex, i);
        if (!in->enabled || strcmp (in->program, "mscgs") == 0)
            continue;
        s_child_t *ch = &s_run.children[s_run.nchildren];
        snprintf (ch->binary, sizeof ch->binary, "%s/%s", ms_tool_exe_dir (), in->program);
        if (access (ch->binary, X_OK) != 0)
            continue; // not built yet
        ch->instance = in;
        s_run.nchildren++;
    }
    printf ("mscgs run: exercise %s, %zu of %zu services built here; out %s\n",
            cgs_exercise_name (s_run.ex), s_run.nchildren, cgs_exercise_instance_count (s_run.ex),
            s_run.out);
    if (s_run.nchildren == 0)
        printf ("mscgs run: no service program is built yet in %s; only watching the bus\n",
                ms_tool_exe_dir ());
    for (size_t i = 0; i < s_run.nchildren; i++)
        if (strcmp (s_run.children[i].instance->program, "stationd") == 0)
            s_run.children[i].map_auto = !s_print_map_address (s_run.children[i].instance, 0);
        else if (strcmp (s_run.children[i].instance->program, "gateway") == 0)
            s_print_dis_destination (s_run.children[i].instance, s_run.out);
        else if (strcmp (s_run.children[i].instance->program, "imagerd") == 0)
            s_print_video_destination (s_run.children[i].instance, s_run.out);

    cgs_lifecycle_init ();
    void *ctx = NULL;
    s_run.sub = ms_tool_open_sub (s_run.ex, &ctx);
    if (!s_run.sub)
        return 1;
    ms_health_init (&s_run.table, s_run.ex);
    ms_icpt_init (&s_run.icpt);
    cgs_sub_on (s_run.sub, "health", ms_health_on_health, &s_run.table);
    cgs_sub_on (s_run.sub, "clock", ms_health_on_clock, &s_run.table);
    s_run.metrics = ms_metrics_new (&s_run.icpt);
    cgs_sub_on (s_run.sub, "intercept", ms_icpt_on_intercept, &s_run.icpt);
    cgs_sub_on (s_run.sub, "track", s_run_on_track, &s_run);
    cgs_sub_on (s_run.sub, "mti.truth", s_run_on_mti_truth, &s_run);
    cgs_sub_on (s_run.sub, "entity", s_run_on_entity, &s_run);
    ms_tool_connect_publishers (s_run.sub, s_run.ex, "health"); // every service publishes health
    if (s_run.record)
        s_recorder_start (&s_run);
    s_run.start = cgs_loop_now ();
    s_run.tty = isatty (STDOUT_FILENO);
    for (size_t i = 0; i < s_run.nchildren; i++)
        s_child_start (&s_run, &s_run.children[i]);

    double next_progress = s_run.start + 1.0;
    double progress_every = s_run.tty ? 1.0 : 5.0;
    while (!cgs_lifecycle_stopping ()) {
        if (cgs_lifecycle_take_reload ()) {
            printf ("\nmscgs run: SIGHUP (terminal closed?): stopping\n");
            break;
        }
        cgs_sub_poll (s_run.sub, 100);
        s_reap (&s_run);
        s_tell_map_ports (&s_run);
        double now = cgs_loop_now ();
        for (size_t i = 0; i < s_run.nchildren; i++) {
            s_child_t *ch = &s_run.children[i];
            if (ch->pid == 0 && !ch->given_up && ch->next_start > 0 && now >= ch->next_start) {
                ch->next_start = 0;
                s_child_start (&s_run, ch);
            }
        }
        if (now >= next_progress) {
            s_progress (&s_run);
            next_progress = now + progress_every;
        }
        if (s_run_over (&s_run))
            break;
    }
    if (s_run.tty)
        fputc ('\n', stdout);
    if (s_run.icpt.final && s_run.stop_after_intercept_s >= 0)
        printf ("mscgs run: the intercept ended (%s) at sim %.1f s\n",
                ms_icpt_state_name (s_run.icpt.desig_state), s_run.icpt.final_s);
    else if (s_run.duration_s > 0 && s_run_over (&s_run))
        printf ("mscgs run: --duration %g s reached: the safety stop, before %s\n",
                s_run.duration_s,
                s_run.icpt.designated ? "the intercept ended" : "any target was designated");
    printf ("mscgs run: stopping %zu services\n", s_run.nchildren);
    for (size_t i = 0; i < s_run.nchildren; i++)
        if (s_run.children[i].pid > 0)
            kill (s_run.children[i].pid, SIGTERM);
    double deadline = cgs_loop_now () + 10.0;
    for (;;) {
        size_t alive = 0;
        for (size_t i = 0; i < s_run.nchildren; i++) {
            s_child_t *ch = &s_run.children[i];
            if (ch->pid > 0 && waitpid (ch->pid, &ch->last_status, WNOHANG) == ch->pid)
                ch->pid = 0;
            alive += ch->pid > 0;
        }
        if (alive == 0)
            break;
        if (cgs_loop_now () > deadline) {
            for (size_t i = 0; i < s_run.nchildren; i++)
                if (s_run.children[i].pid > 0) {
                    fprintf (stderr, "mscgs run: %s did not stop in 10 s; killing it\n",
                             s_run.children[i].instance->name);
                    kill (s_run.children[i].pid, SIGKILL);
                    waitpid (s_run.children[i].pid, NULL, 0);
                    s_run.children[i].pid = 0;
                }
            break;
        }
        usleep (20000);
    }
    s_recorder_stop (&s_run);
    s_write_summary (&s_run);
    printf ("mscgs run: done; logs in %s, summary in %s/summary.txt\n", s_run.logs, s_run.out);
    cgs_sub_destroy (&s_run.sub);
    ms_metrics_destroy (&s_run.metrics);
    zmq_ctx_term (ctx);
    cgs_exercise_destroy (&s_run.ex);
    return 0;
}
