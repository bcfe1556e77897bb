/* ms_cmd_replay — `mscgs replay FILE`: a recording (`mscgs record`) played
 * back onto a bus of its own.
 *
 * The replay exercise. From the exercise the recording came from, replay
 * writes another (--replay-exercise, default beside the recording): its own
 * id (--id, default the recorded one + 100), every endpoint an ipc:// socket
 * in a folder of its own (--dir), no multicast and no CURVE, every service
 * `enabled = no` but those that run for real in the replay (--live, default
 * stationd), and one more instance, `replay`, that publishes the `replay`
 * topic and takes the timeline's commands. A live exercise is never
 * disturbed: nothing it listens to is bound or sent to.
 *
 * The replay stands in for every service that is not live: it binds each
 * one's publish endpoint and sends each recorded message from its source's
 * socket with the header it was recorded with (cgs_pub_forward: source,
 * epoch, sequence number, simulation and wall time), only the exercise id
 * made the replay's. So a replay recorded again gives the same messages but
 * for that id. It binds their command endpoints too: uavsim's and its own
 * take pause, resume, time scale (the replay's speed) and seek, as
 * `mscgs pause | resume | time-scale X | seek T` send them; every other
 * command is refused: an operator's command reaches nothing.
 *
 * Timing: a message recorded at t (its receive time, seconds after the
 * first message) goes out when the replay's clock reaches t; the clock runs
 * at --speed recorded seconds per wall second from --from. A seek sends
 * the --preroll seconds before the new time at once (the map's history),
 * and changes every forwarded epoch (a subscriber would take messages from
 * before for repeats, and drop them); the `replay` message's generation says
 * the picture before is stale. */
#include "ms_cmd_replay.h"

#include "cgs_bus.h"
#include "cgs_cmd.h"
#include "cgs_exercise.h"
#include "cgs_lifecycle.h"
#include "cgs_loop.h"
#include "cgs_mcap.h"
#include "cgs_topics.h"
#include "intercept.pb-c.h"
#include "ms_marks.h"
#include "ms_opts.h"
#include "ms_tool.h"
#include "replay.pb-c.h"

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <sys/prctl.h>
#include <sys/random.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>
#include <zmq.h>

#define S_STATE_PERIOD_S 0.5  // the `replay` message, wall seconds
#define S_MAX_SPEED      1000 // recorded seconds per wall second
#define S_SOURCES        MS_MAX_INSTANCES
#define S_SERVERS        MS_MAX_INSTANCES
#define S_NEW_PICTURE_S  0.2 // after a seek: the new generation reaches the map before its messages

typedef struct {
    char name[CGS_NAME_MAX];
    cgs_pub_t *pub;
} s_source_t;

typedef struct {
    cgs_cmd_server_t *server;
    bool clock; // takes pause, resume, time scale and seek
} s_server_t;

typedef struct {
    const char *file;
    cgs_mcap_reader_t *rd;
    const cgs_topic_t *topic_of[65536]; // channel id -> catalogue topic (NULL: not ours)
    uint64_t t0_ns, t1_ns;              // the first and last log time
    uint64_t messages;                  // in the file
    uint32_t recorded_id;               // the recorded exercise's id
    ms_marks_t marks;

    cgs_exercise_t *ex; // the replay exercise
    void *ctx;
    s_source_t src[S_SOURCES];
    size_t nsrc;
    cgs_pub_t *state_pub;
    s_server_t srv[S_SERVERS];
    size_t nsrv;

    // the clock
    double pos_s;    // where the replay is (recorded seconds)
    double anchor_s; // recorded time at anchor_wall
    double anchor_wall;
    double speed;
    bool paused, ended, once;
    bool hold; // started paused: nothing is sent, not even what is due at the start
    uint32_t generation;
    uint64_t salt;          // this replay's, for the epochs after a seek
    uint64_t video_skipped; // video frames not sent: older than 0.5 s when due (a burst, a lag)
    double preroll_s;
    double sim_time_s; // of the last message sent
    double play_wall;  // when it started playing (after --delay, and a --paused start's resume)
    double play_cpu;   // the CPU time used by then, s

    // the record read ahead: due when its time comes
    bool have;
    double next_t;
    uint16_t next_channel;
    const uint8_t *next_data;
    size_t next_len;

    uint64_t sent, unknown_source, unknown_channel, malformed, dropped;
    char why_source[CGS_NAME_MAX]; // the first source not stood in for
    char reply[160];
} s_replay_t;

static s_replay_t *s_r; // for the commands' handler (one replay per process)

/* What the forwarded epochs are XORed with: nothing in generation 0 (the
 * recorded epochs, exactly), else a value of this replay's salt and the
 * generation (splitmix64), so that no generation's epoch is one a
 * subscriber saw before, even when the recording is itself of a replay. */
static uint64_t s_epoch_xor (const s_replay_t *r)
{
    if (!r->generation)
        return 0;
    uint64_t z = r->salt + 0x9e3779b97f4a7c15ull * r->generation;
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    z ^= z >> 31;
    return z ? z : 1;
}

/* CPU time this process has used, user and system, seconds. */
static double s_cpu_s (void)
{
    struct rusage ru;
    if (getrusage (RUSAGE_SELF, &ru) < 0)
        return NAN;
    return (double)ru.ru_utime.tv_sec + (double)ru.ru_utime.tv_usec / 1e6 +
           (double)ru.ru_stime.tv_sec + (double)ru.ru_stime.tv_usec / 1e6;
}

/* ---- the recording ----------------------------------------------------------------- */

/* Read the next message record into r->next; false at the end. */
static bool s_read_next (s_replay_t *r)
{
    cgs_mcap_record_t rec;
    char err[256];
    int rc;
    while ((rc = cgs_mcap_reader_next (r->rd, &rec, err, sizeof err)) == 1) {
        if (rec.kind == CGS_MCAP_CHANNEL) {
            const cgs_topic_t *t = cgs_topics_find (rec.name);
            r->topic_of[rec.id] = t && strcmp (rec.encoding, "protobuf") == 0 ? t : NULL;
            continue;
        }
        if (rec.kind != CGS_MCAP_MESSAGE)
            continue;
        r->next_t = (double)(rec.log_time_ns - r->t0_ns) / 1e9;
        r->next_channel = rec.id;
        r->next_data = rec.data;
        r->next_len = rec.len;
        return r->have = true;
    }
    if (rc < 0)
        fprintf (stderr, "mscgs replay: %s: %s (the replay ends there)\n", r->file, err);
    return r->have = false;
}

/* The first pass: span, count, the recorded exercise, the marks. */
static int s_scan (s_replay_t *r)
{
    cgs_mcap_record_t rec;
    char err[256];
    int rc;
    bool first = true;
    while ((rc = cgs_mcap_reader_next (r->rd, &rec, err, sizeof err)) == 1) {
        if (rec.kind == CGS_MCAP_CHANNEL) {
            const cgs_topic_t *t = cgs_topics_find (rec.name);
            r->topic_of[rec.id] = t && strcmp (rec.encoding, "protobuf") == 0 ? t : NULL;
        }
        if (rec.kind != CGS_MCAP_MESSAGE)
            continue;
        if (first || rec.log_time_ns < r->t0_ns)
            r->t0_ns = rec.log_time_ns;
        if (first || rec.log_time_ns > r->t1_ns)
            r->t1_ns = rec.log_time_ns;
        first = false;
        r->messages++;
        const cgs_topic_t *t = r->topic_of[rec.id];
        if (!t || (r->recorded_id && strcmp (t->name, "intercept") != 0))
            continue;
        ProtobufCMessage *m = protobuf_c_message_unpack (t->message, NULL, rec.len, rec.data);
        if (!m)
            continue;
        const Cgs__Header *h = cgs_msg_header (m);
        if (h && !r->recorded_id)
            r->recorded_id = h->exercise_id;
        if (strcmp (t->name, "intercept") == 0)
            ms_marks_add (&r->marks, (const Cgs__Intercept *)m, (double)rec.log_time_ns / 1e9);
        protobuf_c_message_free_unpacked (m, NULL);
    }
    if (rc < 0) {
        fprintf (stderr, "mscgs replay: %s: %s\n", r->file, err);
        if (!r->messages)
            return -1;
        fprintf (stderr, "mscgs replay: replaying the %llu messages before it\n",
                 (unsigned long long)r->messages);
    }
    if (!r->messages) {
        fprintf (stderr, "mscgs replay: %s holds no messages\n", r->file);
        return -1;
    }
    if (!cgs_mcap_reader_complete (r->rd))
        fprintf (stderr,
                 "mscgs replay: %s has no footer (its recorder was stopped hard): its whole "
                 "chunks are replayed\n",
                 r->file);
    // The marks' times, from the first message (t0 was not final when they were taken).
    for (size_t i = 0; i < r->marks.n; i++)
        r->marks.marks[i].t_s -= (double)r->t0_ns / 1e9;
    return 0;
}

/* ---- the replay exercise ----------------------------------------------------------- */

/* Is name in the comma-separated list ("none": nothing)? */
static bool s_listed (const char *list, const char *name)
{
    size_t n = strlen (name);
    for (const char *p = list; *p;) {
        const char *e = strchr (p, ',');
        size_t len = e ? (size_t)(e - p) : strlen (p);
        if (len == n && strncmp (p, name, n) == 0)
            return true;
        p += len + (e ? 1 : 0);
    }
    return false;
}

/* Write the replay exercise of ex into path: 0, or -1 after saying why. */
static int s_write_exercise (const cgs_exercise_t *ex, const char *path, uint32_t id,
                             const char *dir, const char *live)
{
    char tmp[PATH_MAX + 8];
    snprintf (tmp, sizeof tmp, "%s.tmp", path);
    FILE *f = fopen (tmp, "w");
    if (!f) {
        fprintf (stderr, "mscgs replay: cannot write %s: %s\n", tmp, strerror (errno));
        return -1;
    }
    cgs_geodetic_t o = cgs_exercise_origin (ex);
    fprintf (f,
             "; The replay exercise of %s, written by `mscgs replay`: its own id and\n"
             "; endpoints (ipc:// sockets in %s), so that a live exercise is never\n"
             "; disturbed. The replay stands in for every service with `enabled = no`;\n"
             "; the others run for real (`stationd --exercise THIS_FILE`).\n\n",
             cgs_exercise_path (ex), dir);
    fprintf (f, "[exercise]\nid = %u\nname = %s-replay\norigin = geo %.10f %.10f %.4f\n", id,
             cgs_exercise_name (ex), o.lat_deg, o.lon_deg, o.height_m);
    fprintf (f, "time_scale = %.17g\nseed = %llu\nstate_dir = %s/state\n",
             cgs_exercise_time_scale (ex), (unsigned long long)cgs_exercise_seed (ex), dir);
    if (*cgs_exercise_scenario (ex))
        fprintf (f, "scenario = %s\n", cgs_exercise_scenario (ex));
    for (size_t i = 0; i < cgs_exercise_instance_count (ex); i++) {
        const cgs_instance_t *in = cgs_exercise_instance (ex, i);
        if (strcmp (in->program, "replay") == 0)
            continue;
        fprintf (f, "\n[service %s]\nprogram = %s\nhost = localhost\nhwm = %d\n", in->name,
                 in->program, in->hwm);
        if (*in->publish)
            fprintf (f, "publish = ipc://%s/%s.pub\n", dir, in->name);
        if (*in->command)
            fprintf (f, "command = ipc://%s/%s.cmd\n", dir, in->name);
        if (*in->uav)
            fprintf (f, "uav = %s\n", in->uav);
        if (*in->params)
            fprintf (f, "params = %s\n", in->params);
        fprintf (f, "enabled = %s\n", s_listed (live, in->name) ? "yes" : "no");
    }
    if (!cgs_exercise_first_of (ex, "stationd") && s_listed (live, "stationd"))
        fprintf (f,
                 "\n; The map of the replay (the recorded exercise had none).\n"
                 "[service stationd]\nprogram = stationd\nhost = localhost\n"
                 "publish = ipc://%s/stationd.pub\nenabled = yes\n",
                 dir);
    fprintf (f,
             "\n; The replay itself: the `replay` topic, and the timeline's commands.\n"
             "[service replay]\nprogram = replay\nhost = localhost\n"
             "publish = ipc://%s/replay.pub\ncommand = ipc://%s/replay.cmd\nenabled = no\n",
             dir, dir);
    if (fclose (f) != 0 || rename (tmp, path) != 0) {
        fprintf (stderr, "mscgs replay: cannot write %s: %s\n", path, strerror (errno));
        unlink (tmp);
        return -1;
    }
    return 0;
}

/* ---- sending ----------------------------------------------------------------------- */

static cgs_pub_t *s_source_pub (s_replay_t *r, const char *name)
{
    for (size_t i = 0; i < r->nsrc; i++)
        if (strcmp (r->src[i].name, name) == 0)
            return r->src[i].pub;
    return NULL;
}

/* Send the record read ahead (or skip it: a video frame in a seek's burst). */
static void s_send_next (s_replay_t *r, bool skip_video)
{
    const cgs_topic_t *t = r->topic_of[r->next_channel];
    if (!t) {
        r->unknown_channel++;
        return;
    }
    if (skip_video && strcmp (t->name, "video") == 0) {
        r->video_skipped++;
        return;
    }
    ProtobufCMessage *m = protobuf_c_message_unpack (t->message, NULL, r->next_len, r->next_data);
    const Cgs__Header *h = m ? cgs_msg_header (m) : NULL;
    if (!h) {
        r->malformed++;
        if (m)
            protobuf_c_message_free_unpacked (m, NULL);
        return;
    }
    cgs_pub_t *pub = s_source_pub (r, h->source ? h->source : "");
    if (!pub) {
        if (!r->unknown_source++)
            snprintf (r->why_source, sizeof r->why_source, "%s", h->source ? h->source : "");
    } else {
        r->sim_time_s = h->sim_time_s;
        int rc = cgs_pub_forward (pub, t->name, m, s_epoch_xor (r));
        if (rc == 0)
            r->sent++;
        else
            r->dropped++;
    }
    protobuf_c_message_free_unpacked (m, NULL);
}

static double s_span (const s_replay_t *r)
{
    return (double)(r->t1_ns - r->t0_ns) / 1e9;
}

static void s_publish_state (s_replay_t *r)
{
    Cgs__ReplayState st = CGS__REPLAY_STATE__INIT;
    st.file = (char *)r->file;
    st.t_s = r->pos_s;
    st.span_s = s_span (r);
    st.speed = r->speed;
    st.paused = r->paused;
    st.generation = r->generation;
    st.sent = r->sent;
    st.recorded_exercise_id = r->recorded_id;
    st.sim_time_s = r->sim_time_s;
    st.ended = r->ended;
    size_t n = r->marks.n;
    Cgs__ReplayMark *marks = n ? calloc (n, sizeof *marks) : NULL;
    Cgs__ReplayMark **pm = n ? calloc (n, sizeof *pm) : NULL;
    if (n && (!marks || !pm))
        n = 0;
    for (size_t i = 0; i < n; i++) {
        cgs__replay_mark__init (&marks[i]);
        marks[i].t_s = r->marks.marks[i].t_s;
        marks[i].kind = r->marks.marks[i].kind;
        marks[i].text = r->marks.marks[i].text;
        pm[i] = &marks[i];
    }
    st.n_marks = n;
    st.marks = pm;
    cgs_pub_send (r->state_pub, "replay", &st.base, r->sim_time_s);
    free (marks);
    free (pm);
}

/* Re-anchor the clock at the position now (a change of speed or pause). */
static void s_anchor (s_replay_t *r)
{
    r->anchor_s = r->pos_s;
    r->anchor_wall = cgs_loop_now ();
}

/* Put the reader at t less the preroll: from the start again when t is
 * behind what was read. */
static void s_goto (s_replay_t *r, double t)
{
    double from = fmax (0, t - r->preroll_s);
    if (!r->have || r->next_t > from) {
        cgs_mcap_reader_rewind (r->rd);
        s_read_next (r);
    }
    while (r->have && r->next_t < from)
        s_read_next (r);
    r->pos_s = t;
    r->ended = false;
}

/* Go to t, a new generation. */
static void s_seek (s_replay_t *r, double t)
{
    t = fmax (0, fmin (t, s_span (r)));
    r->generation++;
    s_goto (r, t);
    s_anchor (r);
    // The new generation first, so the map clears before the burst.
    s_publish_state (r);
    usleep ((useconds_t)(S_NEW_PICTURE_S * 1e6));
    s_anchor (r);
}

/* ---- commands ---------------------------------------------------------------------- */

static void s_on_command (void *arg, const Cgs__Command *cmd, Cgs__Reply *reply)
{
    const s_server_t *srv = arg;
    s_replay_t *r = s_r;
    const char *name = cgs_cmd_name (cmd);
    if (cmd->body_case == CGS__COMMAND__BODY_PING) {
        snprintf (r->reply, sizeof r->reply, "replay of %s at %.1f s of %.1f s, speed %g%s",
                  r->file, r->pos_s, s_span (r), r->speed, r->paused ? ", paused" : "");
        reply->detail = r->reply;
        return;
    }
    bool clock = cmd->body_case == CGS__COMMAND__BODY_PAUSE ||
                 cmd->body_case == CGS__COMMAND__BODY_RESUME ||
                 cmd->body_case == CGS__COMMAND__BODY_SET_TIME_SCALE ||
                 cmd->body_case == CGS__COMMAND__BODY_SEEK;
    if (!clock || !srv->clock) {
        reply->status = CGS__REPLY_STATUS__REPLY_STATUS_ERROR;
        snprintf (r->reply, sizeof r->reply,
                  "this is a replay of %s: an operator's command (%s) reaches nothing", r->file,
                  name);
        reply->error = r->reply;
        return;
    }
    switch (cmd->body_case) {
    case CGS__COMMAND__BODY_PAUSE:
        r->paused = true;
        s_anchor (r);
        snprintf (r->reply, sizeof r->reply, "paused at %.1f s", r->pos_s);
        break;
    case CGS__COMMAND__BODY_RESUME:
        if (r->hold)
            r->play_wall = cgs_loop_now (), r->play_cpu = s_cpu_s ();
        r->paused = r->hold = false;
        s_anchor (r);
        snprintf (r->reply, sizeof r->reply, "playing from %.1f s at %gx", r->pos_s, r->speed);
        break;
    case CGS__COMMAND__BODY_SET_TIME_SCALE: {
        double x = cmd->set_time_scale->time_scale;
        if (!(x > 0 && x <= S_MAX_SPEED)) {
            reply->status = CGS__REPLY_STATUS__REPLY_STATUS_ERROR;
            snprintf (r->reply, sizeof r->reply, "speed %g is not in (0, %d]", x, S_MAX_SPEED);
            reply->error = r->reply;
            return;
        }
        r->speed = x;
        s_anchor (r);
        snprintf (r->reply, sizeof r->reply, "speed %gx", x);
        break;
    }
    default: { // SEEK
        double t = cmd->seek->t_s;
        if (!isfinite (t) || t < 0 || t > s_span (r) + 1e-9) {
            reply->status = CGS__REPLY_STATUS__REPLY_STATUS_ERROR;
            snprintf (r->reply, sizeof r->reply, "%g s is not in the recording (0 to %.1f s)", t,
                      s_span (r));
            reply->error = r->reply;
            return;
        }
        r->hold = false;
        s_seek (r, t);
        snprintf (r->reply, sizeof r->reply, "at %.1f s (generation %u)", r->pos_s, r->generation);
        break;
    }
    }
    reply->detail = r->reply;
    s_publish_state (r);
}

/* ---- start-up ---------------------------------------------------------------------- */

static int s_bind_all (s_replay_t *r)
{
    if (!(r->ctx = zmq_ctx_new ()))
        return -1;
    for (size_t i = 0; i < cgs_exercise_instance_count (r->ex); i++) {
        const cgs_instance_t *in = cgs_exercise_instance (r->ex, i);
        if (in->enabled)
            continue; // runs for real in the replay
        bool self = strcmp (in->program, "replay") == 0;
        if (*in->publish) {
            cgs_pub_t *p = cgs_pub_new (r->ctx, in->name, cgs_exercise_id (r->ex));
            int rc = p ? cgs_pub_bind (p, in->publish) : -ENOMEM;
            if (rc < 0) {
                fprintf (stderr, "mscgs replay: cannot bind %s for %s: %s\n", in->publish, in->name,
                         strerror (-rc));
                cgs_pub_destroy (&p);
                return -1;
            }
            if (self)
                r->state_pub = p;
            else if (r->nsrc < S_SOURCES) {
                snprintf (r->src[r->nsrc].name, sizeof r->src[r->nsrc].name, "%s", in->name);
                r->src[r->nsrc++].pub = p;
            } else
                cgs_pub_destroy (&p);
        }
        if (*in->command && r->nsrv < S_SERVERS) {
            s_server_t *s = &r->srv[r->nsrv];
            s->clock = self || strcmp (in->program, "uavsim") == 0;
            s->server = cgs_cmd_server_new (r->ctx, in->name, NULL, s_on_command, s);
            int rc = s->server ? cgs_cmd_server_bind (s->server, in->command) : -ENOMEM;
            if (rc < 0) {
                fprintf (stderr, "mscgs replay: cannot bind %s for %s: %s\n", in->command, in->name,
                         strerror (-rc));
                cgs_cmd_server_destroy (&s->server);
                return -1;
            }
            r->nsrv++;
        }
    }
    if (!r->state_pub) {
        fprintf (stderr, "mscgs replay: the replay exercise has no `replay` instance\n");
        return -1;
    }
    return 0;
}

static pid_t s_start_station (const char *exercise, const char *port, const char *log)
{
    char bin[PATH_MAX + 16];
    snprintf (bin, sizeof bin, "%s/stationd", ms_tool_exe_dir ());
    fflush (stdout); // not written twice by the child
    fflush (stderr);
    pid_t pid = fork ();
    if (pid == 0) {
        FILE *f = freopen (log, "a", stdout);
        if (f)
            dup2 (fileno (stdout), STDERR_FILENO);
        setpgid (0, 0);
        prctl (PR_SET_PDEATHSIG, SIGTERM);
        execl (bin, bin, "--exercise", exercise, "--instance", "stationd", "--port", port,
               (char *)NULL);
        fprintf (stderr, "mscgs replay: cannot execute %s: %s\n", bin, strerror (errno));
        _exit (127);
    }
    return pid;
}

static int s_read_speed (const ms_opt_t *opt, const char *value)
{
    char *end;
    double x = strtod (value, &end);
    if (*end || !(x > 0 && x <= S_MAX_SPEED)) {
        fprintf (stderr, "mscgs replay: --%s %s: expected a speed in (0, %d]\n", opt->name, value,
                 S_MAX_SPEED);
        return -EINVAL;
    }
    *(double *)opt->arg = x;
    return 0;
}

static int s_read_id (const ms_opt_t *opt, const char *value)
{
    char *end;
    long v = strtol (value, &end, 10);
    if (*end || v < 1 || v > 255) {
        fprintf (stderr, "mscgs replay: --%s %s: expected an exercise id 1..255\n", opt->name,
                 value);
        return -EINVAL;
    }
    *(int *)opt->arg = (int)v;
    return 0;
}

int ms_replay_main (int argc, char **argv)
{
    static s_replay_t r; // big (the channel table): not on the stack
    memset (&r, 0, sizeof r);
    s_r = &r;
    const char *exercise = NULL, *replay_ex = NULL, *dir = NULL, *live = "stationd",
               *station = NULL;
    double speed = 1, from = 0, preroll = 20, delay = 1;
    int id = 0;
    bool paused = false;
    const ms_opt_t opts[] = {
        {.name = "speed",
         .value = "X",
         .help = "recorded seconds per wall second (default 1)",
         .fn = s_read_speed,
         .arg = &speed},
        {.name = "from",
         .value = "S",
         .help = "start S seconds into the recording (default 0)",
         .fn = ms_opts_read_number,
         .arg = &from},
        {.name = "paused", .help = "start paused (resume by command)", .flag = &paused},
        {.name = "once",
         .help = "exit at the end (default: wait there for a seek)",
         .flag = &r.once},
        {.name = "id",
         .value = "N",
         .help = "the replay exercise's id (default the recorded one + 100)",
         .fn = s_read_id,
         .arg = &id},
        {.name = "dir",
         .value = "DIR",
         .help = "the replay's ipc:// sockets (default /tmp/mscgs-replay-ID)",
         .str = &dir},
        {.name = "replay-exercise",
         .value = "F",
         .help = "write the replay exercise here (default FILE's folder/replay.ini)",
         .str = &replay_ex},
        {.name = "live",
         .value = "I,I..",
         .help = "instances that run for real in the replay (default stationd; none: none)",
         .str = &live},
        {.name = "station",
         .value = "PORT",
         .help = "start a stationd on the replay, its map on this port",
         .str = &station},
        {.name = "preroll",
         .value = "S",
         .help = "after a seek, send the S seconds before at once (default 20)",
         .fn = ms_opts_read_number,
         .arg = &preroll},
        {.name = "delay",
         .value = "S",
         .help = "wait S seconds for subscribers before the first message (default 1)",
         .fn = ms_opts_read_number,
         .arg = &delay},
        MS_TOOL_OPT_EXERCISE (&exercise),
        MS_OPTS_HELP,
        MS_OPTS_END,
    };
    const ms_cmd_t spec = {
        .name = "replay",
        .operands = "FILE",
        .missing = "which recording? (an MCAP file of `mscgs record`)",
        .about = "Play a recording back onto a bus of its own: a replay exercise (its own id,\n"
                 "ipc:// endpoints in DIR) is written from the recorded one (--exercise), and\n"
                 "every recorded message is sent from its service's endpoint with its recorded\n"
                 "header, when the replay's clock reaches its time. stationd on the replay\n"
                 "exercise shows it with a timeline (--station PORT starts one). By command\n"
                 "(mscgs pause | resume | time-scale X | seek T --exercise REPLAY):\n"
                 "pause, resume, speed and seek; an operator's command reaches nothing.\n",
        .opts = opts,
    };
    int nargs = ms_opts_parse (&spec, argc, argv);
    if (nargs < 0)
        return ms_opts_exit_code (nargs);
    r.file = argv[1];
    if (nargs > 1) {
        fprintf (stderr, "mscgs replay: one recording at a time\n");
        return 2;
    }
    if (from < 0 || preroll < 0 || delay < 0) {
        fprintf (stderr, "mscgs replay: --from, --preroll and --delay take seconds >= 0\n");
        return 2;
    }
    char err[512] = "";
    if (!(r.rd = cgs_mcap_reader_open (r.file, err, sizeof err))) {
        fprintf (stderr, "mscgs replay: %s\n", err);
        return 1;
    }
    int rc = 1;
    cgs_exercise_t *orig = NULL;
    pid_t station_pid = 0;
    if (s_scan (&r) < 0)
        goto done;
    if (from > s_span (&r)) {
        fprintf (stderr, "mscgs replay: --from %g: the recording is %.1f s long\n", from,
                 s_span (&r));
        rc = 2;
        goto done;
    }
    if (!(orig = ms_tool_load_exercise (exercise)))
        goto done;
    if (r.recorded_id && r.recorded_id != cgs_exercise_id (orig))
        fprintf (stderr, "mscgs replay: warning: %s was recorded in exercise %u, not %s's %u\n",
                 r.file, r.recorded_id, cgs_exercise_path (orig), cgs_exercise_id (orig));
    uint32_t rid = id ? (uint32_t)id : (cgs_exercise_id (orig) + 99) % 255 + 1;
    if (rid == cgs_exercise_id (orig) || (r.recorded_id && rid == r.recorded_id)) {
        fprintf (stderr, "mscgs replay: --id %u is the recorded exercise's: a replay has its own\n",
                 rid);
        rc = 2;
        goto done;
    }
    char dirbuf[PATH_MAX], exbuf[PATH_MAX + 16];
    if (!dir) {
        snprintf (dirbuf, sizeof dirbuf, "/tmp/mscgs-replay-%u", rid);
        dir = dirbuf;
    }
    if (mkdir (dir, 0755) < 0 && errno != EEXIST) {
        fprintf (stderr, "mscgs replay: cannot make %s: %s\n", dir, strerror (errno));
        goto done;
    }
    if (!replay_ex) {
        const char *slash = strrchr (r.file, '/');
        snprintf (exbuf, sizeof exbuf, "%.*sreplay.ini", slash ? (int)(slash - r.file + 1) : 0,
                  r.file);
        replay_ex = exbuf;
    }
    if (s_write_exercise (orig, replay_ex, rid, dir, strcmp (live, "none") == 0 ? "" : live) < 0)
        goto done;
    if (cgs_exercise_load (replay_ex, &r.ex, err, sizeof err) < 0) {
        fprintf (stderr, "mscgs replay: %s\n", err);
        goto done;
    }
    cgs_lifecycle_init ();
    if (s_bind_all (&r) < 0)
        goto done;
    printf ("mscgs replay: %s: %llu messages over %.1f s (exercise %u), %zu marks\n", r.file,
            (unsigned long long)r.messages, s_span (&r), r.recorded_id, r.marks.n);
    printf ("mscgs replay: on exercise %u (%s), standing in for %zu services\n", rid, replay_ex,
            r.nsrc);
    if (station) {
        char log[PATH_MAX + 32];
        snprintf (log, sizeof log, "%s/stationd.log", dir);
        station_pid = s_start_station (replay_ex, station, log);
        printf ("mscgs replay: the map: http://127.0.0.1:%s/ (log %s)\n", station, log);
    } else {
        printf ("mscgs replay: the map: stationd --exercise %s\n", replay_ex);
    }
    fflush (stdout);

    if (getrandom (&r.salt, sizeof r.salt, 0) != (ssize_t)sizeof r.salt)
        r.salt = (uint64_t)time (NULL) * 0x9e3779b97f4a7c15ull ^ (uint64_t)getpid ();
    r.speed = speed;
    r.paused = r.hold = paused;
    r.preroll_s = preroll;
    cgs_mcap_reader_rewind (r.rd);
    s_read_next (&r);
    // Subscribers connect (and send their subscriptions) before anything is sent.
    double wait_until = cgs_loop_now () + delay, next_state = 0;
    while (!cgs_lifecycle_stopping () && cgs_loop_now () < wait_until) {
        for (size_t i = 0; i < r.nsrv; i++)
            cgs_cmd_server_dispatch (r.srv[i].server, 16);
        usleep (20000);
    }
    if (r.generation == 0) // a seek while waiting stands
        s_goto (&r, from); // a start is not a seek: the recorded epochs as they were
    s_anchor (&r);
    r.play_wall = cgs_loop_now ();
    r.play_cpu = s_cpu_s ();

    zmq_pollitem_t items[S_SERVERS];
    for (size_t i = 0; i < r.nsrv; i++)
        items[i] = (zmq_pollitem_t){cgs_cmd_server_socket (r.srv[i].server), 0, ZMQ_POLLIN, 0};
    double progress_at = cgs_loop_now () + 10;
    while (!cgs_lifecycle_stopping ()) {
        double now = cgs_loop_now ();
        if (!r.paused && !r.ended)
            r.pos_s = fmin (r.anchor_s + (now - r.anchor_wall) * r.speed, s_span (&r));
        // Everything due: what a seek's burst holds goes at once.
        int budget = 20000; // then a look at the commands
        while (!r.hold && r.have && r.next_t <= r.pos_s && budget-- > 0) {
            s_send_next (&r, r.next_t < r.pos_s - 0.5);
            s_read_next (&r);
        }
        if (!r.have && !r.ended) {
            r.ended = true;
            r.pos_s = s_span (&r);
            s_publish_state (&r);
            double wall = cgs_loop_now () - r.play_wall, cpu = s_cpu_s () - r.play_cpu;
            printf ("mscgs replay: the end (%.1f s), %llu messages sent in %.3f s of wall time "
                    "(%.0f messages/s, cpu %.0f %% of one core)\n",
                    r.pos_s, (unsigned long long)r.sent, wall, wall > 0 ? (double)r.sent / wall : 0,
                    wall > 0 ? 100 * cpu / wall : 0);
            fflush (stdout);
            if (r.once)
                break;
        }
        if (now >= next_state) {
            s_publish_state (&r);
            next_state = now + S_STATE_PERIOD_S;
        }
        if (now >= progress_at) {
            fprintf (stderr, "mscgs replay: %.0f of %.0f s, %llu messages sent%s\n", r.pos_s,
                     s_span (&r), (unsigned long long)r.sent, r.paused ? " (paused)" : "");
            progress_at = now + 10;
        }
        // Sleep until the next message is due, a command comes, or 50 ms.
        double wait = 0.05;
        if (r.have && !r.paused && !r.ended)
            wait = fmin (wait, fmax (0, (r.next_t - r.pos_s) / r.speed));
        if (budget <= 0)
            wait = 0;
        int n = zmq_poll (items, (int)r.nsrv, (long)(wait * 1000));
        if (n > 0)
            for (size_t i = 0; i < r.nsrv; i++)
                if (items[i].revents & ZMQ_POLLIN)
                    cgs_cmd_server_dispatch (r.srv[i].server, 16);
    }
    printf ("mscgs replay: %llu messages sent", (unsigned long long)r.sent);
    if (r.unknown_source)
        printf (", %llu not (their sources run for real in the replay, e.g. %s)",
                (unsigned long long)r.unknown_source, r.why_source);
    if (r.video_skipped)
        printf (", %llu video frames skipped (over 0.5 s late when due: a seek's burst, or "
                "a replay that fell behind)",
                (unsigned long long)r.video_skipped);
    if (r.unknown_channel || r.malformed || r.dropped)
        printf (", %llu on channels not of the catalogue, %llu malformed, %llu dropped",
                (unsigned long long)r.unknown_channel, (unsigned long long)r.malformed,
                (unsigned long long)r.dropped);
    printf ("\n");
    rc = 0;
    // Let the last messages leave before the sockets close.
    usleep (200000);
done:
    if (station_pid > 0) {
        kill (station_pid, SIGTERM);
        waitpid (station_pid, NULL, 0);
    }
    for (size_t i = 0; i < r.nsrc; i++)
        cgs_pub_destroy (&r.src[i].pub);
    cgs_pub_destroy (&r.state_pub);
    for (size_t i = 0; i < r.nsrv; i++)
        cgs_cmd_server_destroy (&r.srv[i].server);
    if (r.ctx)
        zmq_ctx_term (r.ctx);
    cgs_exercise_destroy (&r.ex);
    cgs_exercise_destroy (&orig);
    cgs_mcap_reader_destroy (&r.rd);
    ms_marks_clear (&r.marks);
    return rc;
}
