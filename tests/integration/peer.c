/* peer — the test service of the integration tests (tests/integration/ scripts;
 * see README.md there). Test code only.
 *
 * As a service it runs on the same shell as every service's main.c
 * (common/cgs_service.h): it publishes `clock` at a rate or in a burst,
 * subscribes to topics and counts what arrives, and serves commands. Its
 * service state is the list of commands it applied ("client number kind"
 * lines): the handler adds to it in memory, the command server saves it with
 * the stored replies (s_save) before it replies, and a restarted peer restores
 * it from the saved state. The handler also appends each command to an apply
 * log of its own (--apply-log): a side effect outside the saved state. Its
 * counters go to a one-line report file (key=value ...) and its state to a
 * state report, both rewritten atomically when they change and once more on
 * stop, so a test can poll them.
 *
 *   peer [--as PROGRAM] [service options] [peer options]
 *
 * --as PROGRAM (first) runs the peer under another program name, e.g. uavsim,
 * the program the topic catalogue names as the publisher of `clock`.
 *
 * Two more modes stand alone, without the service shell:
 *
 *   peer --call ping --endpoint EP [--client-id ID] [--text T]
 *        [--timeout-ms MS] [--attempts N]
 *       send one command and print its reply on one line (exit 0 OK,
 *       1 another status, 2 no reply);
 *   peer --send-garbage EP [--wait-ms MS]
 *       bind an XPUB socket at EP, wait for a `clock` subscriber, send it
 *       valid and malformed `clock` messages (see s_garbage_main), exit 0. */
#include "cgs_cmd.h"
#include "cgs_lifecycle.h"
#include "cgs_log.h"
#include "cgs_service.h"
#include "cgs_state.h"

#include <errno.h>
#include <fcntl.h>
#include <getopt.h>
#include <inttypes.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>
#include <zmq.h>

#define S_MAX_TOPICS 4

/* SIGUSR1: "go" for a publisher started with --wait-go, "release" for a
 * subscriber holding in its handler (--slow-ms). */
static volatile sig_atomic_t s_usr1;

static void s_on_usr1 (int sig)
{
    (void)sig;
    s_usr1++;
}

typedef struct {
    cgs_service_t *svc;
    /* options */
    uint64_t publish_n; // --publish-clock: messages to publish from the rate timer
    double rate_hz;     // --rate
    uint64_t burst_n;   // --burst: messages to publish at once
    double tail_s;      // --tail-s: after a burst, one more message every tail_s
    bool wait_go;       // --wait-go: publish only after SIGUSR1
    char topics[S_MAX_TOPICS][CGS_TOPIC_MAX]; // --subscribe; the first is counted
    size_t ntopics;
    int slow_ms;             // --slow-ms: hold in the handler this long (or until SIGUSR1)
    uint64_t slow_count;     // --slow-count: ... for this many first messages
    char report[4096];       // --report FILE
    bool serve;              // --serve-commands
    char apply_log[4096];    // --apply-log FILE
    uint64_t die_after;      // --die-after-apply N: _exit (3) after the Nth apply
    int apply_delay_ms;      // --apply-delay-ms: a slow handler
    char state_report[4096]; // --state-report FILE
    /* state */
    bool going; // publishing has started
    bool burst_done;
    uint64_t published;  // clock messages published (the last tick)
    uint64_t pub_errors; // publish calls that failed
    uint64_t seen;       // messages of the first topic handled
    uint64_t first_seq, last_seq;
    uint64_t last_epoch;      // publisher epoch of the last message of the first topic
    uint64_t epochs;          // epochs seen on the first topic
    uint64_t epoch_first_seq; // sequence number of the first message of the latest epoch
    uint64_t mismatch;        // clock messages whose tick is not their sequence number
    uint64_t health;          // health messages handled, from other instances
    uint64_t held;            // holds entered (--slow-ms)
    uint64_t applied;         // commands applied by this process (the handler)
    /* the service state: "client number kind\n" per applied command, in order */
    char *state;
    size_t state_len, state_cap;
    uint64_t state_count; // lines in state
    uint64_t restored;    // ... of which restored from the saved state at start
    char detail[512];     // the last reply's detail
    char last_report[1024];
} peer_t;

static int s_parse_u64 (const char *s, uint64_t min, uint64_t *ret, char *why, size_t whylen)
{
    char *end = NULL;
    errno = 0;
    unsigned long long v = strtoull (s, &end, 10);
    if (!*s || *s == '-' || errno || !end || *end || v < min) {
        snprintf (why, whylen, "expected a whole number of at least %" PRIu64 ", got '%s'", min, s);
        return -EINVAL;
    }
    *ret = v;
    return 0;
}

static int s_on_option (void *arg, const char *name, const char *value, char *why, size_t whylen)
{
    peer_t *p = arg;
    uint64_t v = 0;
    if (strcmp (name, "publish-clock") == 0)
        return s_parse_u64 (value, 1, &p->publish_n, why, whylen);
    if (strcmp (name, "burst") == 0)
        return s_parse_u64 (value, 1, &p->burst_n, why, whylen);
    if (strcmp (name, "rate") == 0 || strcmp (name, "tail-s") == 0) {
        char *end = NULL;
        double d = strtod (value, &end);
        if (!end || *end || !(d > 0) || d > 1e6) {
            snprintf (why, whylen, "expected a positive number, got '%s'", value);
            return -EINVAL;
        }
        if (strcmp (name, "rate") == 0)
            p->rate_hz = d;
        else
            p->tail_s = d;
        return 0;
    }
    if (strcmp (name, "wait-go") == 0) {
        p->wait_go = true;
        return 0;
    }
    if (strcmp (name, "subscribe") == 0) {
        if (p->ntopics == S_MAX_TOPICS || !*value || strlen (value) >= CGS_TOPIC_MAX) {
            snprintf (why, whylen, "at most %d topics of fewer than %d characters", S_MAX_TOPICS,
                      CGS_TOPIC_MAX);
            return -EINVAL;
        }
        snprintf (p->topics[p->ntopics++], CGS_TOPIC_MAX, "%s", value);
        return 0;
    }
    if (strcmp (name, "slow-ms") == 0 || strcmp (name, "apply-delay-ms") == 0) {
        if (s_parse_u64 (value, 0, &v, why, whylen) < 0 || v > 600000) {
            snprintf (why, whylen, "expected milliseconds in [0, 600000], got '%s'", value);
            return -EINVAL;
        }
        *(strcmp (name, "slow-ms") == 0 ? &p->slow_ms : &p->apply_delay_ms) = (int)v;
        return 0;
    }
    if (strcmp (name, "slow-count") == 0)
        return s_parse_u64 (value, 1, &p->slow_count, why, whylen);
    if (strcmp (name, "report") == 0 || strcmp (name, "apply-log") == 0 ||
        strcmp (name, "state-report") == 0) {
        char *dst = strcmp (name, "report") == 0      ? p->report
                    : strcmp (name, "apply-log") == 0 ? p->apply_log
                                                      : p->state_report;
        if (!*value || strlen (value) >= sizeof p->report) {
            snprintf (why, whylen, "expected a file name");
            return -EINVAL;
        }
        snprintf (dst, sizeof p->report, "%s", value);
        return 0;
    }
    if (strcmp (name, "serve-commands") == 0) {
        p->serve = true;
        return 0;
    }
    if (strcmp (name, "die-after-apply") == 0)
        return s_parse_u64 (value, 1, &p->die_after, why, whylen);
    snprintf (why, whylen, "unknown option");
    return -EINVAL;
}

static const cgs_service_option_t s_options[] = {
    {"publish-clock", true, "N", "publish N clock messages (tick 1..N) from a timer"},
    {"rate", true, "HZ", "... at this rate (default 100)"},
    {"burst", true, "N", "publish N clock messages at once, then one more every --tail-s"},
    {"tail-s", true, "S", "seconds between the messages after a burst (default 0.5)"},
    {"wait-go", false, NULL, "start publishing on SIGUSR1, not at start"},
    {"subscribe", true, "TOPIC", "subscribe and count (repeatable; the first is reported)"},
    {"slow-ms", true, "MS", "hold in the handler MS ms (or until SIGUSR1) ..."},
    {"slow-count", true, "K", "... for the first K messages of the first topic (default 1)"},
    {"report", true, "FILE", "write the counters to FILE when they change and on stop"},
    {"serve-commands", false, NULL, "serve commands; the state is the list of those applied"},
    {"apply-log", true, "FILE", "also append each applied command to FILE (fsync'd)"},
    {"die-after-apply", true, "N", "_exit (3) right after applying the Nth command"},
    {"apply-delay-ms", true, "MS", "take MS ms to apply each command"},
    {"state-report", true, "FILE", "write the state (restored, then as saved) to FILE"},
    {NULL, false, NULL, NULL},
};

/* ---- report ------------------------------------------------------------------------ */

static void s_report (peer_t *p, bool force)
{
    if (!*p->report)
        return;
    cgs_topic_stats_t st = {0};
    cgs_sub_t *sub = cgs_service_sub (p->svc);
    for (size_t i = 0; sub && p->ntopics && i < cgs_sub_topic_count (sub); i++)
        if (strcmp (cgs_sub_topic_stats (sub, i)->topic, p->topics[0]) == 0)
            st = *cgs_sub_topic_stats (sub, i);
    cgs_cmd_server_t *cmd = cgs_service_cmd_server (p->svc);
    cgs_pub_t *pub = cgs_service_pub (p->svc);
    char line[1024];
    snprintf (line, sizeof line,
              "received=%" PRIu64 " gaps=%" PRIu64 " restarts=%" PRIu64 " stale=%" PRIu64
              " malformed=%" PRIu64 " first_seq=%" PRIu64 " last_seq=%" PRIu64 " epochs=%" PRIu64
              " epoch_first_seq=%" PRIu64 " mismatch=%" PRIu64 " health=%" PRIu64 " held=%" PRIu64
              " published=%" PRIu64 " pub_errors=%" PRIu64 " drops=%" PRIu64 " applied=%" PRIu64
              " restored=%" PRIu64 " state=%" PRIu64 " server_applied=%" PRIu64
              " duplicates=%" PRIu64 " cmd_malformed=%" PRIu64 " write_errors=%" PRIu64
              " pid=%ld\n",
              st.messages, st.gaps, st.restarts, st.stale, sub ? cgs_sub_malformed (sub) : 0,
              p->first_seq, p->last_seq, p->epochs, p->epoch_first_seq, p->mismatch, p->health,
              p->held, p->published, p->pub_errors, pub ? cgs_pub_drops (pub) : 0, p->applied,
              p->restored, p->state_count, cmd ? cgs_cmd_server_applied (cmd) : 0,
              cmd ? cgs_cmd_server_duplicates (cmd) : 0, cmd ? cgs_cmd_server_malformed (cmd) : 0,
              cmd ? cgs_cmd_server_write_errors (cmd) : 0, (long)getpid ());
    if (!force && strcmp (line, p->last_report) == 0)
        return;
    int rc = cgs_state_write (p->report, line, strlen (line));
    if (rc < 0)
        cgs_log (LOG_WARNING, "cannot write %s: %s", p->report, strerror (-rc));
    else
        snprintf (p->last_report, sizeof p->last_report, "%s", line);
}

static void s_on_report_timer (void *arg)
{
    s_report (arg, false);
}

/* ---- publishing -------------------------------------------------------------------- */

static void s_publish_clock (peer_t *p)
{
    double step_s = p->rate_hz > 0 ? 1.0 / p->rate_hz : 0.01;
    cgs_geodetic_t o = cgs_exercise_origin (cgs_service_exercise (p->svc));
    Cgs__Geodetic origin = CGS__GEODETIC__INIT;
    origin.lat_deg = o.lat_deg;
    origin.lon_deg = o.lon_deg;
    origin.height_m = o.height_m;
    Cgs__Clock clock = CGS__CLOCK__INIT;
    clock.tick = ++p->published;
    clock.step_s = step_s;
    clock.sim_time_s = (double)clock.tick * step_s;
    clock.time_scale = 1;
    clock.origin = &origin;
    cgs_service_set_sim_time (p->svc, clock.sim_time_s);
    if (cgs_service_publish (p->svc, "clock", &clock.base) < 0)
        p->pub_errors++;
}

static void s_on_go_timer (void *arg)
{
    peer_t *p = arg;
    if (p->going || (p->wait_go && !s_usr1))
        return;
    p->going = true;
    cgs_log (LOG_INFO, "publishing");
    if (p->burst_n) {
        double t0 = cgs_loop_now ();
        for (uint64_t i = 0; i < p->burst_n; i++)
            s_publish_clock (p);
        p->burst_done = true;
        cgs_log (LOG_INFO, "burst of %" PRIu64 " clock messages in %.2f s", p->burst_n,
                 cgs_loop_now () - t0);
        s_report (p, false);
    }
}

static void s_on_rate_timer (void *arg)
{
    peer_t *p = arg;
    if (p->going && p->published < p->publish_n)
        s_publish_clock (p);
}

static void s_on_tail_timer (void *arg)
{
    peer_t *p = arg;
    if (p->burst_done)
        s_publish_clock (p);
}

/* ---- subscribing ------------------------------------------------------------------- */

/* Hold (a slow subscriber) until SIGUSR1, a stop, or slow_ms. */
static void s_hold (peer_t *p)
{
    p->held++;
    s_report (p, true); // so the test sees the hold while the loop is blocked
    sig_atomic_t start = s_usr1;
    double end = cgs_loop_now () + p->slow_ms / 1000.0;
    while (s_usr1 == start && !cgs_lifecycle_stopping () && cgs_loop_now () < end)
        nanosleep (&(struct timespec){0, 5000000}, NULL);
}

static void s_on_message (void *arg, const char *topic, const ProtobufCMessage *msg,
                          const Cgs__Header *hdr)
{
    peer_t *p = arg;
    if (strcmp (topic, p->topics[0]) == 0) {
        p->seen++;
        if (p->seen == 1)
            p->first_seq = hdr->seq;
        p->last_seq = hdr->seq;
        if (hdr->epoch != p->last_epoch) {
            p->epochs++;
            p->epoch_first_seq = hdr->seq;
            p->last_epoch = hdr->epoch;
        }
        if (strcmp (topic, "clock") == 0 && ((const Cgs__Clock *)msg)->tick != hdr->seq)
            p->mismatch++;
        if (p->slow_ms > 0 && p->seen <= p->slow_count)
            s_hold (p);
    }
    // Health from others only: its own health comes back over its own
    // publisher and says nothing about the other connections.
    if (strcmp (topic, "health") == 0 &&
        strcmp (hdr->source, cgs_service_instance_name (p->svc)) != 0)
        p->health++;
}

/* ---- commands ---------------------------------------------------------------------- */

/* Append len bytes of text to the state (one or more whole lines). */
static int s_state_append (peer_t *p, const char *text, size_t len)
{
    if (p->state_len + len + 1 > p->state_cap) {
        size_t cap = p->state_cap ? p->state_cap : 1024;
        while (cap < p->state_len + len + 1)
            cap *= 2;
        char *n = realloc (p->state, cap);
        if (!n)
            return -ENOMEM;
        p->state = n;
        p->state_cap = cap;
    }
    memcpy (p->state + p->state_len, text, len);
    p->state_len += len;
    p->state[p->state_len] = '\0';
    for (size_t i = 0; i < len; i++)
        p->state_count += text[i] == '\n';
    return 0;
}

/* The state report: "pid=P restored=R commands=N", then the N lines of the
 * state. Written at start (the restored state), by s_save (the state being
 * saved) and on stop. */
static void s_state_report (peer_t *p)
{
    if (!*p->state_report)
        return;
    char head[128];
    int n = snprintf (head, sizeof head, "pid=%ld restored=%" PRIu64 " commands=%" PRIu64 "\n",
                      (long)getpid (), p->restored, p->state_count);
    char *buf = malloc ((size_t)n + p->state_len + 1);
    int rc = -ENOMEM;
    if (buf) {
        memcpy (buf, head, (size_t)n);
        if (p->state_len)
            memcpy (buf + n, p->state, p->state_len);
        rc = cgs_state_write (p->state_report, buf, (size_t)n + p->state_len);
        free (buf);
    }
    if (rc < 0)
        cgs_log (LOG_WARNING, "cannot write %s: %s", p->state_report, strerror (-rc));
}

/* The save callback: the state as it is now (the command server writes it
 * with the stored replies before it replies). */
static int s_save (void *arg, uint8_t **ret_buf, size_t *ret_len)
{
    peer_t *p = arg;
    uint8_t *buf = malloc (p->state_len ? p->state_len : 1);
    if (!buf)
        return -ENOMEM;
    if (p->state_len)
        memcpy (buf, p->state, p->state_len);
    *ret_buf = buf;
    *ret_len = p->state_len;
    s_state_report (p);
    return 0;
}

/* Restore the state the previous run saved: whole lines, as s_save wrote them. */
static int s_restore (peer_t *p)
{
    const uint8_t *buf = NULL;
    size_t len = 0;
    cgs_service_saved_state (p->svc, &buf, &len);
    if (!len)
        return 0;
    if (buf[len - 1] != '\n' || memchr (buf, '\0', len)) {
        cgs_log (LOG_ERR, "saved state: not a list of lines (%zu bytes)", len);
        return -EPROTO;
    }
    for (size_t i = 0; i < len;) {
        const char *line = (const char *)buf + i;
        size_t n = (size_t)((const char *)memchr (line, '\n', len - i) - line) + 1;
        if (n == 1) {
            cgs_log (LOG_ERR, "saved state: empty line %" PRIu64, p->state_count + 1);
            return -EPROTO;
        }
        int rc = s_state_append (p, line, n);
        if (rc < 0)
            return rc;
        cgs_log (LOG_INFO, "restored: %.*s", (int)(n - 1), line);
        i += n;
    }
    p->restored = p->state_count;
    cgs_log (LOG_INFO, "restored %" PRIu64 " applied commands from the saved state", p->restored);
    return 0;
}

/* Append one line to the apply log and fsync it: an external side effect of
 * the command, outside the saved state. */
static int s_append_applied (const char *path, const char *line)
{
    int fd = open (path, O_WRONLY | O_APPEND | O_CREAT | O_CLOEXEC, 0644);
    if (fd < 0)
        return -errno;
    size_t len = strlen (line);
    ssize_t n = write (fd, line, len);
    int rc = n < 0 ? -errno : (size_t)n != len ? -EIO : 0;
    if (rc == 0 && fsync (fd) < 0)
        rc = -errno;
    close (fd);
    return rc;
}

/* Apply a command: add it to the state (in memory; the server saves it after
 * this returns) and append it to the apply log. */
static void s_on_command (void *arg, const Cgs__Command *cmd, Cgs__Reply *reply)
{
    peer_t *p = arg;
    const char *kind = cgs_cmd_name (cmd);
    if (p->apply_delay_ms > 0) {
        int ms = p->apply_delay_ms;
        nanosleep (&(struct timespec){ms / 1000, (ms % 1000) * 1000000L}, NULL);
    }
    char line[400];
    int n = snprintf (line, sizeof line, "%s %" PRIu64 " %s\n", cmd->client_id, cmd->command_number,
                      kind);
    const char *what = "the state";
    int rc = n < 0 || (size_t)n >= sizeof line ? -ENAMETOOLONG : 0; // a client id too long
    if (rc == 0)
        rc = s_state_append (p, line, (size_t)n);
    if (rc == 0 && *p->apply_log) {
        what = p->apply_log;
        rc = s_append_applied (p->apply_log, line);
    }
    if (rc < 0) {
        // The state holds the command unless it was the state that failed.
        snprintf (p->detail, sizeof p->detail, "cannot record the command in %s: %s", what,
                  strerror (-rc));
        reply->status = CGS__REPLY_STATUS__REPLY_STATUS_ERROR;
        reply->error = p->detail;
        cgs_log (LOG_ERR, "%s", p->detail);
        return;
    }
    p->applied++;
    cgs_log (LOG_INFO, "applied %s from %s %" PRIu64, kind, cmd->client_id, cmd->command_number);
    if (p->die_after && p->applied == p->die_after) {
        cgs_log (LOG_WARNING, "dying after apply %" PRIu64 " (--die-after-apply)", p->applied);
        _exit (3);
    }
    snprintf (
        p->detail, sizeof p->detail,
        "applied %s %s %" PRIu64 " as apply %" PRIu64 " of pid %ld (state: %" PRIu64 " commands)",
        kind, cmd->client_id, cmd->command_number, p->applied, (long)getpid (), p->state_count);
    reply->detail = p->detail;
}

/* ---- the service ------------------------------------------------------------------- */

static int s_service_main (int argc, char **argv)
{
    // The program name: --as PROGRAM, else the name the peer was started
    // under (a copy named uavsim runs as uavsim, as `mscgs run` starts it).
    const char *program = strrchr (argv[0], '/') ? strrchr (argv[0], '/') + 1 : argv[0];
    if (argc >= 3 && strcmp (argv[1], "--as") == 0) {
        program = argv[2];
        argv[2] = argv[0];
        argv += 2;
        argc -= 2;
    }
    peer_t *p = calloc (1, sizeof *p);
    if (!p) {
        fprintf (stderr, "peer: out of memory\n");
        return 1;
    }
    p->rate_hz = 100;
    p->tail_s = 0.5;
    p->slow_count = 1;
    cgs_service_info_t info = {
        .program = program,
        .summary = "test peer: publishes clock, subscribes and counts, serves commands",
        .options = s_options,
        .on_option = s_on_option,
        .option_arg = p,
    };
    int exit_code = 1;
    int rc = cgs_service_new (&info, argc, argv, &p->svc);
    cgs_service_t *svc = p->svc;
    if (rc != 0 || cgs_service_check_only (svc)) {
        exit_code = rc < 0 ? 1 : 0;
        goto done;
    }
    struct sigaction sa;
    memset (&sa, 0, sizeof sa);
    sa.sa_handler = s_on_usr1;
    sigemptyset (&sa.sa_mask);
    sigaction (SIGUSR1, &sa, NULL);

    for (size_t i = 0; i < p->ntopics; i++)
        if (cgs_service_subscribe (svc, p->topics[i], s_on_message, p) < 0)
            goto done;
    if (p->serve) {
        if (cgs_service_serve_commands (svc, s_on_command, s_save, p) < 0 || s_restore (p) < 0)
            goto done;
        s_state_report (p);
    }
    cgs_loop_t *loop = cgs_service_loop (svc);
    if (p->publish_n || p->burst_n) {
        if (!cgs_service_pub (svc)) {
            cgs_log (LOG_ERR, "[service %s] has no publish endpoint",
                     cgs_service_instance_name (svc));
            goto done;
        }
        cgs_loop_add_timer (loop, 0.01, s_on_go_timer, p);
        if (p->publish_n)
            cgs_loop_add_timer (loop, 1.0 / p->rate_hz, s_on_rate_timer, p);
        if (p->burst_n)
            cgs_loop_add_timer (loop, p->tail_s, s_on_tail_timer, p);
    }
    if (*p->report)
        cgs_loop_add_timer (loop, 0.1, s_on_report_timer, p);
    s_report (p, false);
    exit_code = cgs_service_run (svc);
    s_report (p, true);
    if (p->serve)
        s_state_report (p);
done:
    cgs_service_destroy (&p->svc);
    free (p->state);
    free (p);
    return exit_code;
}

/* ---- --call: a command client ------------------------------------------------------ */

static const char *s_status_name (Cgs__ReplyStatus s)
{
    switch (s) {
    case CGS__REPLY_STATUS__REPLY_STATUS_OK:
        return "OK";
    case CGS__REPLY_STATUS__REPLY_STATUS_ERROR:
        return "ERROR";
    case CGS__REPLY_STATUS__REPLY_STATUS_BAD_REQUEST:
        return "BAD_REQUEST";
    case CGS__REPLY_STATUS__REPLY_STATUS_UNSUPPORTED:
        return "UNSUPPORTED";
    default:
        return "UNKNOWN";
    }
}

static int s_call_main (int argc, char **argv)
{
    const char *kind = NULL, *endpoint = NULL, *client_id = NULL, *text = "peer";
    long timeout_ms = CGS_CMD_DEFAULT_TIMEOUT_MS, attempts = CGS_CMD_DEFAULT_ATTEMPTS;
    static const struct option opts[] = {
        {"call", required_argument, NULL, 'c'},
        {"endpoint", required_argument, NULL, 'e'},
        {"client-id", required_argument, NULL, 'i'},
        {"text", required_argument, NULL, 't'},
        {"timeout-ms", required_argument, NULL, 'T'},
        {"attempts", required_argument, NULL, 'a'},
        {NULL, 0, NULL, 0},
    };
    int c;
    optind = 1;
    while ((c = getopt_long (argc, argv, "", opts, NULL)) != -1) {
        switch (c) {
        case 'c':
            kind = optarg;
            break;
        case 'e':
            endpoint = optarg;
            break;
        case 'i':
            client_id = optarg;
            break;
        case 't':
            text = optarg;
            break;
        case 'T':
            timeout_ms = strtol (optarg, NULL, 10);
            break;
        case 'a':
            attempts = strtol (optarg, NULL, 10);
            break;
        default:
            return 2;
        }
    }
    if (!kind || strcmp (kind, "ping") != 0 || !endpoint || optind < argc || timeout_ms <= 0 ||
        timeout_ms > 600000 || attempts <= 0 || attempts > 10000) {
        fprintf (stderr, "usage: peer --call ping --endpoint EP [--client-id ID] [--text T] "
                         "[--timeout-ms MS] [--attempts N]\n");
        return 2;
    }
    void *ctx = zmq_ctx_new ();
    // --client-id: exactly that id, numbered from 1 (as a retry from another process would be).
    cgs_cmd_client_t *client = !ctx        ? NULL
                               : client_id ? cgs_cmd_client_new_exact (ctx, endpoint, client_id, 1)
                                           : cgs_cmd_client_new (ctx, endpoint, "peer");
    if (!client) {
        fprintf (stderr, "peer --call: cannot create a client for %s: %s\n", endpoint,
                 strerror (errno));
        if (ctx)
            zmq_ctx_term (ctx);
        return 2;
    }
    Cgs__Ping ping = CGS__PING__INIT;
    ping.text = (char *)text;
    Cgs__Command cmd = CGS__COMMAND__INIT;
    cmd.body_case = CGS__COMMAND__BODY_PING;
    cmd.ping = &ping;
    Cgs__Reply *reply = NULL;
    char err[512] = "";
    double t0 = cgs_loop_now ();
    int rc =
        cgs_cmd_client_call (client, &cmd, (int)timeout_ms, (int)attempts, &reply, err, sizeof err);
    double elapsed_ms = (cgs_loop_now () - t0) * 1000.0;
    int exit_code = 2;
    if (rc < 0) {
        fprintf (stderr, "peer --call: %s\n", err);
        printf ("noreply client=%s number=%" PRIu64 " elapsed_ms=%.0f error=%s\n",
                cgs_cmd_client_id (client), cmd.command_number, elapsed_ms, strerror (-rc));
    } else {
        printf ("reply status=%s duplicate=%s server=%s client=%s number=%" PRIu64
                " elapsed_ms=%.0f detail=%s error=%s\n",
                s_status_name (reply->status), reply->duplicate ? "yes" : "no", reply->server,
                reply->client_id, reply->command_number, elapsed_ms, reply->detail, reply->error);
        exit_code = reply->status == CGS__REPLY_STATUS__REPLY_STATUS_OK ? 0 : 1;
        cgs_cmd_reply_free (&reply);
    }
    cgs_cmd_client_destroy (&client);
    zmq_ctx_term (ctx);
    return exit_code;
}

/* ---- --send-garbage: a raw sender of malformed messages ---------------------------- */

static int s_send_frames (void *sock, const char *const *frames, const size_t *lens, size_t n)
{
    for (size_t i = 0; i < n; i++)
        if (zmq_send (sock, frames[i], lens[i], i + 1 < n ? ZMQ_SNDMORE : 0) < 0)
            return -zmq_errno ();
    return 0;
}

/* A `clock` message as cgs_pub would send it (header included, unless seq is 0). */
static int s_send_clock (void *sock, uint32_t exercise_id, uint64_t epoch, uint64_t seq,
                         const char *extra_frame)
{
    Cgs__Header h = CGS__HEADER__INIT;
    h.source = "peer.garbage";
    h.exercise_id = exercise_id;
    h.epoch = epoch;
    h.seq = seq;
    h.wall_time_s = cgs_bus_wall_time ();
    Cgs__Clock clock = CGS__CLOCK__INIT;
    clock.header = seq ? &h : NULL;
    clock.tick = seq ? seq : 99;
    uint8_t *buf = NULL;
    size_t len = 0;
    int rc = cgs_msg_encode_alloc (&clock.base, &buf, &len);
    if (rc < 0)
        return rc;
    const char *frames[] = {"clock", (const char *)buf, extra_frame};
    const size_t lens[] = {5, len, extra_frame ? strlen (extra_frame) : 0};
    rc = s_send_frames (sock, frames, lens, extra_frame ? 3 : 2);
    free (buf);
    return rc;
}

/* Send, in order: valid clock #1; five malformed clock messages (a lone topic
 * frame, a truncated protobuf payload, an empty payload, a payload without a
 * header, a valid message with a third frame); valid clock #2 and #3; a valid
 * #4 of another exercise. A subscriber of exercise N should count 3 received,
 * 0 gaps, 5 malformed, and drop the last. */
static int s_garbage_main (int argc, char **argv)
{
    const char *endpoint = NULL;
    long wait_ms = 10000;
    uint32_t exercise = 1;
    static const struct option opts[] = {
        {"send-garbage", required_argument, NULL, 'g'},
        {"exercise-id", required_argument, NULL, 'x'},
        {"wait-ms", required_argument, NULL, 'w'},
        {NULL, 0, NULL, 0},
    };
    int c;
    optind = 1;
    while ((c = getopt_long (argc, argv, "", opts, NULL)) != -1) {
        switch (c) {
        case 'g':
            endpoint = optarg;
            break;
        case 'w':
            wait_ms = strtol (optarg, NULL, 10);
            break;
        case 'x':
            exercise = (uint32_t)strtoul (optarg, NULL, 10);
            break;
        default:
            return 2;
        }
    }
    if (!endpoint || optind < argc || wait_ms <= 0) {
        fprintf (stderr, "usage: peer --send-garbage ENDPOINT [--wait-ms MS] [--exercise-id N]\n");
        return 2;
    }
    cgs_log_init ("peer.garbage", LOG_INFO);
    void *ctx = zmq_ctx_new ();
    void *sock = ctx ? zmq_socket (ctx, ZMQ_XPUB) : NULL;
    int exit_code = 1;
    if (!sock) {
        cgs_log (LOG_ERR, "cannot create an XPUB socket: %s", zmq_strerror (zmq_errno ()));
        goto done;
    }
    int linger = 5000;
    zmq_setsockopt (sock, ZMQ_LINGER, &linger, sizeof linger);
    if (cgs_bus_prepare_endpoint (endpoint) < 0 || zmq_bind (sock, endpoint) < 0) {
        cgs_log (LOG_ERR, "cannot bind %s: %s", endpoint, zmq_strerror (zmq_errno ()));
        goto done;
    }
    // XPUB hands us each subscription: wait for the subscriber's "clock".
    double end = cgs_loop_now () + wait_ms / 1000.0;
    bool subscribed = false;
    while (!subscribed && cgs_loop_now () < end) {
        zmq_pollitem_t item = {sock, 0, ZMQ_POLLIN, 0};
        if (zmq_poll (&item, 1, 50) <= 0)
            continue;
        char sub[64];
        int n = zmq_recv (sock, sub, sizeof sub, ZMQ_DONTWAIT);
        subscribed = n == 6 && sub[0] == 1 && memcmp (sub + 1, "clock", 5) == 0;
    }
    if (!subscribed) {
        cgs_log (LOG_ERR, "no subscriber to clock at %s within %ld ms", endpoint, wait_ms);
        goto done;
    }
    uint64_t epoch = 0x5eed;
    static const char truncated[] = {0x0a, 0x50, 0x01}; // header of 80 bytes, 1 present
    const char *lone[] = {"clock"};
    const size_t lone_len[] = {5};
    const char *trunc[] = {"clock", truncated};
    const size_t trunc_len[] = {5, sizeof truncated};
    const char *empty[] = {"clock", ""};
    const size_t empty_len[] = {5, 0};
    int rc = s_send_clock (sock, exercise, epoch, 1, NULL);
    if (rc == 0)
        rc = s_send_frames (sock, lone, lone_len, 1);
    if (rc == 0)
        rc = s_send_frames (sock, trunc, trunc_len, 2);
    if (rc == 0)
        rc = s_send_frames (sock, empty, empty_len, 2);
    if (rc == 0)
        rc = s_send_clock (sock, exercise, epoch, 0, NULL); // no header
    if (rc == 0)
        rc = s_send_clock (sock, exercise, epoch, 2, "extra"); // a third frame: seq 2 is not used
    if (rc == 0)
        rc = s_send_clock (sock, exercise, epoch, 2, NULL);
    if (rc == 0)
        rc = s_send_clock (sock, exercise, epoch, 3, NULL);
    if (rc == 0) // well formed, but of another exercise: dropped, not received
        rc = s_send_clock (sock, exercise + 100, epoch, 4, NULL);
    if (rc < 0) {
        cgs_log (LOG_ERR, "send failed: %s", zmq_strerror (-rc));
        goto done;
    }
    cgs_log (LOG_INFO, "sent 3 valid and 5 malformed clock messages to %s", endpoint);
    exit_code = 0;
done:
    if (sock)
        zmq_close (sock); // lingers until the messages are out
    if (ctx)
        zmq_ctx_term (ctx);
    return exit_code;
}

int main (int argc, char **argv)
{
    if (argc > 1 && strcmp (argv[1], "--call") == 0)
        return s_call_main (argc, argv);
    if (argc > 1 && strcmp (argv[1], "--send-garbage") == 0)
        return s_garbage_main (argc, argv);
    return s_service_main (argc, argv);
}
