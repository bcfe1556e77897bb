/* bench_bus — how fast the bus and the command channel are.
 *
 *   bench_bus [all|pubsub|cmd] [options]     (--help lists them)
 *
 * pubsub: throughput of the project's publisher and subscriber (cgs_pub_*,
 * cgs_sub_*) for 100-byte payloads over ipc://, beside raw libzmq in the same
 * run. Publisher and subscriber are separate processes (fork), as in libzmq's
 * perf/local_thr and remote_thr. Ours sends a cgs.Blob whose encoded size,
 * header included, is 100 bytes; raw sends the same two frames (topic "bench",
 * a 100-byte body). Both publishers refuse to drop (ZMQ_XPUB_NODROP and a
 * blocking send), both sides use the same high-water marks, the subscriber
 * times from the first message to the last and checks that every message
 * arrived in order; a run that loses anything fails the benchmark. Runs of
 * raw and ours alternate; the median, min and max of each are reported.
 *
 * cmd: round-trip latency of cgs_cmd_client_call with a Ping against a
 * cgs_cmd_server in another process, with the reply cache in memory, call by
 * call in turn with raw libzmq DEALER/ROUTER moving the same bytes (the
 * baseline); then with the reply cache persisted to a state file, which the
 * server rewrites with fsync before each reply.
 *
 * Output: readable lines, then a block of key=value figures and a verdict
 * against the goals. Exit 0 whether or not the goals are met; 1 when
 * something broke (lost messages, errors); 2 on bad usage. */
#include "bench_util.h"
#include "cgs_bus.h"
#include "cgs_cmd.h"

#include <assert.h>
#include <errno.h>
#include <linux/magic.h>
#include <poll.h>
#include <signal.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/statfs.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>
#include <zmq.h>

#define S_TOPIC           "bench"  // timed messages
#define S_WARM_TOPIC      "warmup" // sent until the subscriber is receiving
#define S_SOURCE          "bench"  // publisher's source name, in every header
#define S_SEND_TIMEOUT_MS 10000    // a send blocked this long at the HWM fails
#define S_IDLE_LIMIT_S    10.0     // a subscriber idle this long fails
#define S_MAX_RUNS        64
#define S_GOAL_MSGS_PER_S 1000000.0
#define S_GOAL_RATIO      0.7

typedef struct {
    long messages;      // timed messages per throughput run
    int runs;           // runs of each of raw and ours
    int hwm;            // send and receive high-water marks, messages
    size_t size;        // payload size on the wire, bytes
    bool ours, raw;     // which throughput sides to run
    long calls;         // timed command calls, reply cache in memory
    long durable_calls; // timed command calls, reply cache persisted
    const char *state_dir;
} s_opts_t;

/* What the publisher process reports to the subscriber at the end. */
typedef struct {
    int err; // 0, or a positive errno
    uint64_t sent, drops;
} s_pub_report_t;

/* One throughput run as the subscriber saw it. */
typedef struct {
    double msgs_per_s;
    uint64_t received;
    size_t encoded_min, encoded_max; // payload bytes of the first and last message
} s_run_t;

static double s_now_s (void)
{
    struct timespec ts;
    clock_gettime (CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + ts.tv_nsec * 1e-9;
}

static int s_cmp_double (const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

/* The q-quantile (0..1) of sorted values, nearest rank. */
static double s_quantile (const double *sorted, size_t n, double q)
{
    size_t rank = (size_t)(q * (double)n + 0.999999);
    if (rank < 1)
        rank = 1;
    if (rank > n)
        rank = n;
    return sorted[rank - 1];
}

/* ---- control channel between the two processes -------------------------------- */

/* Send bytes on the control socket; 0 or -errno. */
static int s_ctl_send (int fd, const void *data, size_t len)
{
    const char *p = data;
    while (len > 0) {
        ssize_t n = send (fd, p, len, MSG_NOSIGNAL);
        if (n < 0 && errno == EINTR)
            continue;
        if (n < 0)
            return -errno;
        p += n;
        len -= (size_t)n;
    }
    return 0;
}

/* Wait up to timeout_ms (-1: forever) for exactly len bytes; 0, -ETIMEDOUT,
 * -EPIPE when the peer closed, or -errno. */
static int s_ctl_recv (int fd, void *data, size_t len, int timeout_ms)
{
    char *p = data;
    double deadline = s_now_s () + timeout_ms / 1000.0;
    while (len > 0) {
        int wait_ms = -1;
        if (timeout_ms >= 0) {
            wait_ms = (int)((deadline - s_now_s ()) * 1000.0);
            if (wait_ms < 0)
                wait_ms = 0;
        }
        struct pollfd pfd = {fd, POLLIN, 0};
        int rc = poll (&pfd, 1, wait_ms);
        if (rc < 0 && errno == EINTR)
            continue;
        if (rc < 0)
            return -errno;
        if (rc == 0)
            return -ETIMEDOUT;
        ssize_t n = recv (fd, p, len, 0);
        if (n < 0 && errno == EINTR)
            continue;
        if (n < 0)
            return -errno;
        if (n == 0)
            return -EPIPE;
        p += n;
        len -= (size_t)n;
    }
    return 0;
}

/* Fork a child that runs fn (fd) and exits with its result; the parent keeps
 * the other end of a socket pair in *ret_fd. Returns the pid or -errno. */
static pid_t s_spawn (int (*fn) (int fd, const void *arg, const char *endpoint), const void *arg,
                      const char *endpoint, int *ret_fd)
{
    int sv[2];
    if (socketpair (AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, sv) < 0)
        return -errno;
    fflush (NULL);
    pid_t pid = fork ();
    if (pid < 0) {
        int e = errno;
        close (sv[0]);
        close (sv[1]);
        return -e;
    }
    if (pid == 0) {
        close (sv[0]);
        int rc = fn (sv[1], arg, endpoint);
        close (sv[1]);
        _exit (rc == 0 ? 0 : 1);
    }
    close (sv[1]);
    *ret_fd = sv[0];
    return pid;
}

/* Wait for a child; 0 when it exited 0, -ECHILD otherwise. */
static int s_reap (pid_t pid)
{
    int status = 0;
    while (waitpid (pid, &status, 0) < 0)
        if (errno != EINTR)
            return -ECHILD;
    return WIFEXITED (status) && WEXITSTATUS (status) == 0 ? 0 : -ECHILD;
}

/* A fresh folder under TMPDIR (or /tmp); 0 or -errno. */
static int s_tmpdir (char *buf, size_t size, const char *parent, const char *what)
{
    if (!parent)
        parent = getenv ("TMPDIR") && *getenv ("TMPDIR") ? getenv ("TMPDIR") : "/tmp";
    if (snprintf (buf, size, "%s/cgs-bench-%s-XXXXXX", parent, what) >= (int)size)
        return -ENAMETOOLONG;
    return mkdtemp (buf) ? 0 : -errno;
}

static void s_rmtree (const char *dir)
{
    char cmd[4200];
    snprintf (cmd, sizeof cmd, "rm -rf '%s'", dir);
    if (system (cmd) != 0)
        fprintf (stderr, "bench_bus: could not remove %s\n", dir);
}

/* ---- publishers (child processes) ---------------------------------------------- */

/* Wait for the subscriber's 'R' (receiving) while warm calls send(arg) every
 * millisecond; 0 when ready, or -errno. */
static int s_pub_warm_up (int fd, int (*send_warm) (void *arg), void *arg)
{
    double deadline = s_now_s () + S_IDLE_LIMIT_S;
    while (s_now_s () < deadline) {
        int rc = send_warm (arg);
        if (rc < 0)
            return rc;
        char c = 0;
        rc = s_ctl_recv (fd, &c, 1, 1);
        if (rc == 0)
            return c == 'R' ? 0 : -EPROTO;
        if (rc != -ETIMEDOUT)
            return rc;
    }
    return -ETIMEDOUT;
}

/* After the timed messages: wait for the subscriber's 'D' (done) before the
 * socket closes (linger is 0), then report. */
static int s_pub_finish (int fd, s_pub_report_t *report)
{
    char c = 0;
    int rc = s_ctl_recv (fd, &c, 1, (int)(S_IDLE_LIMIT_S * 3000));
    if (rc == 0 && c != 'D')
        rc = -EPROTO;
    if (rc < 0 && !report->err)
        report->err = -rc;
    s_ctl_send (fd, report, sizeof *report);
    return report->err ? -report->err : 0;
}

typedef struct {
    cgs_pub_t *pub;
    Cgs__Blob *blob;
} s_ours_warm_t;

static int s_ours_send_warm (void *arg)
{
    s_ours_warm_t *w = arg;
    return cgs_pub_send (w->pub, S_WARM_TOPIC, &w->blob->base, 1.0);
}

/* The data length that makes a Blob, with the header the publisher stamps on
 * message number seq, encode to size bytes; 0 or -EINVAL. */
static int s_blob_data_len (const cgs_pub_t *pub, uint64_t seq, size_t size, size_t *ret_len)
{
    static uint8_t zeros[4096];
    Cgs__Header h = CGS__HEADER__INIT;
    h.source = S_SOURCE;
    h.exercise_id = 1;
    h.epoch = cgs_pub_epoch (pub);
    h.seq = seq;
    h.sim_time_s = 1.0;
    h.wall_time_s = cgs_bus_wall_time ();
    Cgs__Blob b = CGS__BLOB__INIT;
    b.header = &h;
    b.data.data = zeros;
    for (size_t n = 0; n < sizeof zeros && n <= size; n++) {
        b.data.len = n;
        if (cgs_msg_size (&b.base) == size) {
            *ret_len = n;
            return 0;
        }
    }
    return -EINVAL;
}

/* Our publisher: warm up on S_WARM_TOPIC, then o->messages Blobs on S_TOPIC. */
static int s_pub_ours (int fd, const void *arg, const char *endpoint)
{
    const s_opts_t *o = arg;
    s_pub_report_t report = {0};
    void *ctx = zmq_ctx_new ();
    cgs_pub_t *pub = ctx ? cgs_pub_new (ctx, S_SOURCE, 1) : NULL;
    uint8_t *data = NULL;
    int rc = pub ? 0 : -errno;
    if (rc == 0) {
        cgs_pub_set_hwm (pub, o->hwm);
        cgs_pub_set_block (pub, S_SEND_TIMEOUT_MS);
        rc = cgs_pub_bind (pub, endpoint);
    }
    // Sized for the bulk of the run: the sequence number's varint is a byte
    // or two shorter for the first 16383 messages.
    size_t len = 0;
    if (rc == 0)
        rc = s_blob_data_len (pub, (uint64_t)o->messages, o->size, &len);
    if (rc == 0 && !(data = malloc (len ? len : 1)))
        rc = -ENOMEM;
    Cgs__Blob blob = CGS__BLOB__INIT;
    if (rc == 0) {
        memset (data, 'x', len);
        blob.data.data = data;
        blob.data.len = len;
        s_ours_warm_t warm = {pub, &blob};
        rc = s_pub_warm_up (fd, s_ours_send_warm, &warm);
    }
    for (long i = 1; rc == 0 && i <= o->messages; i++)
        rc = cgs_pub_send (pub, S_TOPIC, &blob.base, 1.0);
    if (pub) {
        report.sent = cgs_pub_sent (pub);
        report.drops = cgs_pub_drops (pub);
    }
    report.err = rc < 0 ? -rc : 0;
    rc = s_pub_finish (fd, &report);
    free (data);
    cgs_pub_destroy (&pub);
    if (ctx)
        zmq_ctx_term (ctx);
    if (rc < 0)
        fprintf (stderr, "bench_bus: our publisher: %s\n", strerror (-rc));
    return rc;
}

typedef struct {
    void *socket;
    uint8_t *body;
    size_t size;
} s_raw_warm_t;

static int s_raw_send (void *socket, const char *topic, const uint8_t *body, size_t size)
{
    if (zmq_send (socket, topic, strlen (topic), ZMQ_SNDMORE) < 0 ||
        zmq_send (socket, body, size, 0) < 0)
        return -zmq_errno ();
    return 0;
}

static int s_raw_send_warm (void *arg)
{
    s_raw_warm_t *w = arg;
    return s_raw_send (w->socket, S_WARM_TOPIC, w->body, w->size);
}

/* Raw libzmq publisher: the same frames, the first 8 body bytes a sequence
 * number so the subscriber can check order and loss as ours does. */
static int s_pub_raw (int fd, const void *arg, const char *endpoint)
{
    const s_opts_t *o = arg;
    s_pub_report_t report = {0};
    void *ctx = zmq_ctx_new ();
    void *s = ctx ? zmq_socket (ctx, ZMQ_PUB) : NULL;
    uint8_t *body = malloc (o->size);
    int rc = s && body ? 0 : -ENOMEM;
    if (rc == 0) {
        int linger = 0, nodrop = 1, timeout = S_SEND_TIMEOUT_MS;
        zmq_setsockopt (s, ZMQ_LINGER, &linger, sizeof linger);
        zmq_setsockopt (s, ZMQ_SNDHWM, &o->hwm, sizeof o->hwm);
        zmq_setsockopt (s, ZMQ_XPUB_NODROP, &nodrop, sizeof nodrop);
        zmq_setsockopt (s, ZMQ_SNDTIMEO, &timeout, sizeof timeout);
        rc = cgs_bus_prepare_endpoint (endpoint);
        if (rc == 0 && zmq_bind (s, endpoint) < 0)
            rc = -zmq_errno ();
    }
    if (rc == 0) {
        memset (body, 'x', o->size);
        uint64_t zero = 0;
        memcpy (body, &zero, sizeof zero);
        s_raw_warm_t warm = {s, body, o->size};
        rc = s_pub_warm_up (fd, s_raw_send_warm, &warm);
    }
    for (uint64_t i = 1; rc == 0 && i <= (uint64_t)o->messages; i++) {
        memcpy (body, &i, sizeof i);
        rc = s_raw_send (s, S_TOPIC, body, o->size);
        if (rc == 0)
            report.sent++;
        else if (rc == -EAGAIN)
            report.drops++;
    }
    report.err = rc < 0 ? -rc : 0;
    rc = s_pub_finish (fd, &report);
    free (body);
    if (s)
        zmq_close (s);
    if (ctx)
        zmq_ctx_term (ctx);
    if (rc < 0)
        fprintf (stderr, "bench_bus: raw publisher: %s\n", strerror (-rc));
    return rc;
}

/* ---- subscribers (the parent process) ------------------------------------------ */

typedef struct {
    uint64_t count;    // timed messages received
    uint64_t target;   // timed messages expected
    uint64_t bad_size; // timed messages of the wrong size (raw)
    uint64_t bad_seq;  // timed messages out of order (raw)
    bool warm_seen;
    double t_first, t_last;
    size_t encoded_first, encoded_last;
} s_sub_state_t;

static void s_on_bench (void *arg, const char *topic, const ProtobufCMessage *msg,
                        const Cgs__Header *hdr)
{
    (void)topic;
    (void)hdr;
    s_sub_state_t *st = arg;
    st->count++;
    if (st->count == 1) {
        st->t_first = s_now_s ();
        st->encoded_first = cgs_msg_size (msg);
    }
    if (st->count == st->target) {
        st->t_last = s_now_s ();
        st->encoded_last = cgs_msg_size (msg);
    }
}

static void s_on_warm (void *arg, const char *topic, const ProtobufCMessage *msg,
                       const Cgs__Header *hdr)
{
    (void)topic;
    (void)msg;
    (void)hdr;
    ((s_sub_state_t *)arg)->warm_seen = true;
}

/* End a run: tell the publisher we are done, take its report, reap it. */
static int s_sub_finish (int fd, pid_t pid, s_pub_report_t *report, char *err, size_t errlen)
{
    int rc = s_ctl_send (fd, "D", 1);
    if (rc == 0)
        rc = s_ctl_recv (fd, report, sizeof *report, 5000);
    close (fd);
    int reap = s_reap (pid);
    if (rc < 0 && !*err)
        snprintf (err, errlen, "no report from the publisher: %s", strerror (-rc));
    else if (report->err && !*err)
        snprintf (err, errlen, "publisher failed: %s", strerror (report->err));
    else if (report->drops && !*err)
        snprintf (err, errlen, "publisher dropped %llu messages at the HWM",
                  (unsigned long long)report->drops);
    else if (reap < 0 && !*err)
        snprintf (err, errlen, "publisher exited abnormally");
    return *err ? -EIO : 0;
}

/* Wait for the timed messages with our subscriber. */
static int s_sub_ours (int fd, pid_t pid, const s_opts_t *o, const char *endpoint, s_run_t *ret,
                       char *err, size_t errlen)
{
    s_sub_state_t st = {.target = (uint64_t)o->messages};
    void *ctx = zmq_ctx_new ();
    cgs_sub_t *sub = ctx ? cgs_sub_new (ctx) : NULL;
    if (!sub)
        snprintf (err, errlen, "cannot make a subscriber: %s", strerror (errno));
    else {
        cgs_sub_set_hwm (sub, o->hwm);
        // The timed topic first: once warm-up arrives, its subscription is in.
        int rc = cgs_sub_on_type (sub, S_TOPIC, &cgs__blob__descriptor, s_on_bench, &st);
        if (rc == 0)
            rc = cgs_sub_on_type (sub, S_WARM_TOPIC, &cgs__blob__descriptor, s_on_warm, &st);
        if (rc == 0)
            rc = cgs_sub_connect (sub, endpoint);
        if (rc < 0)
            snprintf (err, errlen, "cannot subscribe to %s: %s", endpoint, strerror (-rc));
    }
    bool signalled = false;
    int idle_polls = 0; // consecutive 100 ms waits with nothing received
    while (!*err && st.count < st.target) {
        int n = cgs_sub_poll (sub, 100);
        if (n < 0 && n != -EINTR) {
            snprintf (err, errlen, "receive failed: %s", strerror (-n));
            break;
        }
        if (st.warm_seen && !signalled)
            signalled = s_ctl_send (fd, "R", 1) == 0;
        if (n > 0) {
            idle_polls = 0;
            continue;
        }
        struct pollfd pfd = {fd, POLLIN, 0};
        if (poll (&pfd, 1, 0) > 0)
            snprintf (err, errlen, "publisher stopped after %llu of %llu messages",
                      (unsigned long long)st.count, (unsigned long long)st.target);
        else if (++idle_polls * 0.1 > S_IDLE_LIMIT_S)
            snprintf (err, errlen, "nothing received for %.0f s (%llu of %llu messages)",
                      S_IDLE_LIMIT_S, (unsigned long long)st.count, (unsigned long long)st.target);
    }
    if (!*err && sub) {
        const cgs_topic_stats_t *ts = cgs_sub_topic_stats (sub, 0);
        if (cgs_sub_gaps (sub) || cgs_sub_malformed (sub) || cgs_sub_restarts (sub) || ts->stale ||
            ts->messages != st.target)
            snprintf (err, errlen,
                      "subscriber counted %llu gaps, %llu malformed, %llu restarts, %llu stale, "
                      "%llu of %llu messages",
                      (unsigned long long)cgs_sub_gaps (sub),
                      (unsigned long long)cgs_sub_malformed (sub),
                      (unsigned long long)cgs_sub_restarts (sub), (unsigned long long)ts->stale,
                      (unsigned long long)ts->messages, (unsigned long long)st.target);
    }
    cgs_sub_destroy (&sub);
    if (ctx)
        zmq_ctx_term (ctx);
    s_pub_report_t report = {0};
    int rc = s_sub_finish (fd, pid, &report, err, errlen);
    if (rc < 0)
        return rc;
    ret->received = st.count;
    ret->msgs_per_s = (double)(st.count - 1) / (st.t_last - st.t_first);
    ret->encoded_min = st.encoded_first;
    ret->encoded_max = st.encoded_last;
    return 0;
}

/* Wait for the timed messages with a raw libzmq SUB socket. */
static int s_sub_raw (int fd, pid_t pid, const s_opts_t *o, const char *endpoint, s_run_t *ret,
                      char *err, size_t errlen)
{
    s_sub_state_t st = {.target = (uint64_t)o->messages};
    void *ctx = zmq_ctx_new ();
    void *s = ctx ? zmq_socket (ctx, ZMQ_SUB) : NULL;
    if (!s)
        snprintf (err, errlen, "cannot make a SUB socket: %s", zmq_strerror (zmq_errno ()));
    else {
        int linger = 0, timeout = 100;
        zmq_setsockopt (s, ZMQ_LINGER, &linger, sizeof linger);
        zmq_setsockopt (s, ZMQ_RCVHWM, &o->hwm, sizeof o->hwm);
        zmq_setsockopt (s, ZMQ_RCVTIMEO, &timeout, sizeof timeout);
        zmq_setsockopt (s, ZMQ_SUBSCRIBE, S_TOPIC, strlen (S_TOPIC));
        zmq_setsockopt (s, ZMQ_SUBSCRIBE, S_WARM_TOPIC, strlen (S_WARM_TOPIC));
        if (zmq_connect (s, endpoint) < 0)
            snprintf (err, errlen, "cannot connect to %s: %s", endpoint,
                      zmq_strerror (zmq_errno ()));
    }
    zmq_msg_t topic, body;
    zmq_msg_init (&topic);
    zmq_msg_init (&body);
    bool signalled = false;
    int idle_polls = 0; // consecutive 100 ms waits with nothing received
    size_t tlen = strlen (S_TOPIC);
    while (!*err && st.count < st.target) {
        if (zmq_msg_recv (&topic, s, 0) < 0) {
            int e = zmq_errno ();
            if (e != EAGAIN && e != EINTR) {
                snprintf (err, errlen, "receive failed: %s", zmq_strerror (e));
                break;
            }
            struct pollfd pfd = {fd, POLLIN, 0};
            if (poll (&pfd, 1, 0) > 0)
                snprintf (err, errlen, "publisher stopped after %llu of %llu messages",
                          (unsigned long long)st.count, (unsigned long long)st.target);
            else if (++idle_polls * 0.1 > S_IDLE_LIMIT_S)
                snprintf (err, errlen, "nothing received for %.0f s", S_IDLE_LIMIT_S);
            continue;
        }
        idle_polls = 0;
        if (!zmq_msg_more (&topic) || zmq_msg_recv (&body, s, 0) < 0 || zmq_msg_more (&body)) {
            snprintf (err, errlen, "a message that is not two frames");
            break;
        }
        if (zmq_msg_size (&topic) != tlen || memcmp (zmq_msg_data (&topic), S_TOPIC, tlen) != 0) {
            st.warm_seen = true;
            if (!signalled)
                signalled = s_ctl_send (fd, "R", 1) == 0;
            continue;
        }
        st.count++;
        uint64_t seq = 0;
        if (zmq_msg_size (&body) != o->size)
            st.bad_size++;
        else {
            memcpy (&seq, zmq_msg_data (&body), sizeof seq);
            st.bad_seq += seq != st.count;
        }
        if (st.count == 1)
            st.t_first = s_now_s ();
    }
    st.t_last = s_now_s ();
    zmq_msg_close (&topic);
    zmq_msg_close (&body);
    if (s)
        zmq_close (s);
    if (ctx)
        zmq_ctx_term (ctx);
    if (!*err && (st.bad_size || st.bad_seq))
        snprintf (err, errlen, "%llu messages of the wrong size, %llu out of order or lost",
                  (unsigned long long)st.bad_size, (unsigned long long)st.bad_seq);
    s_pub_report_t report = {0};
    int rc = s_sub_finish (fd, pid, &report, err, errlen);
    if (rc < 0)
        return rc;
    ret->received = st.count;
    ret->msgs_per_s = (double)(st.count - 1) / (st.t_last - st.t_first);
    ret->encoded_min = ret->encoded_max = o->size;
    return 0;
}

/* One run of one side: a publisher process, this process subscribing. */
static int s_throughput_run (bool ours, const s_opts_t *o, s_run_t *ret, char *err, size_t errlen)
{
    char dir[256], endpoint[300];
    int rc = s_tmpdir (dir, sizeof dir, NULL, "bus");
    if (rc < 0) {
        snprintf (err, errlen, "cannot make a temporary folder: %s", strerror (-rc));
        return rc;
    }
    snprintf (endpoint, sizeof endpoint, "ipc://%s/bus", dir);
    int fd = -1;
    pid_t pid = s_spawn (ours ? s_pub_ours : s_pub_raw, o, endpoint, &fd);
    if (pid < 0) {
        snprintf (err, errlen, "cannot fork: %s", strerror (-pid));
        rc = pid;
    } else
        rc = ours ? s_sub_ours (fd, pid, o, endpoint, ret, err, errlen)
                  : s_sub_raw (fd, pid, o, endpoint, ret, err, errlen);
    s_rmtree (dir);
    return rc;
}

typedef struct {
    double median, min, max;
} s_spread_t;

static s_spread_t s_spread (const double *v, int n)
{
    double sorted[S_MAX_RUNS];
    memcpy (sorted, v, (size_t)n * sizeof *v);
    qsort (sorted, (size_t)n, sizeof *sorted, s_cmp_double);
    s_spread_t s = {sorted[n / 2], sorted[0], sorted[n - 1]};
    if (n % 2 == 0)
        s.median = (sorted[n / 2 - 1] + sorted[n / 2]) / 2;
    return s;
}

/* The throughput figures, filled by s_bench_pubsub. */
typedef struct {
    bool have_ours, have_raw;
    s_spread_t ours, raw;
} s_pubsub_result_t;

static int s_bench_pubsub (const s_opts_t *o, s_pubsub_result_t *res)
{
    printf ("pubsub: %ld messages of %zu bytes per run, %d runs of each side, HWM %d both ways, "
            "ipc://, publisher and subscriber in separate processes\n",
            o->messages, o->size, o->runs, o->hwm);
    double ours[S_MAX_RUNS], raw[S_MAX_RUNS];
    for (int r = 0; r < o->runs; r++) {
        // Alternate which side goes first so a warm or cold machine favours neither.
        for (int k = 0; k < 2; k++) {
            bool is_ours = (k == 0) == (r % 2 == 1);
            if ((is_ours && !o->ours) || (!is_ours && !o->raw))
                continue;
            s_run_t run = {0};
            char err[512] = "";
            if (s_throughput_run (is_ours, o, &run, err, sizeof err) < 0) {
                printf ("pubsub: run %d %s: FAILED: %s\n", r + 1, is_ours ? "ours" : "raw", err);
                return -EIO;
            }
            printf ("  run %d %-4s %10.0f msg/s  (%llu received, none lost; payload %zu..%zu "
                    "bytes)\n",
                    r + 1, is_ours ? "ours" : "raw", run.msgs_per_s,
                    (unsigned long long)run.received, run.encoded_min, run.encoded_max);
            fflush (stdout);
            (is_ours ? ours : raw)[r] = run.msgs_per_s;
        }
    }
    if (o->ours) {
        res->have_ours = true;
        res->ours = s_spread (ours, o->runs);
        printf ("pubsub ours (cgs_pub/cgs_sub, cgs.Blob): median %.0f msg/s, min %.0f, max %.0f\n",
                res->ours.median, res->ours.min, res->ours.max);
    }
    if (o->raw) {
        res->have_raw = true;
        res->raw = s_spread (raw, o->runs);
        printf ("pubsub raw  (libzmq PUB/SUB, 2 frames):   median %.0f msg/s, min %.0f, max %.0f\n",
                res->raw.median, res->raw.min, res->raw.max);
    }
    if (o->ours && o->raw)
        printf ("pubsub ratio ours/raw (medians): %.3f\n", res->ours.median / res->raw.median);
    return 0;
}

/* ---- command round trip ---------------------------------------------------------- */

typedef enum {
    S_RTT_RAW,    // raw libzmq DEALER to ROUTER echo of same-sized bytes
    S_RTT_MEMORY, // cgs_cmd, reply cache in memory
    S_RTT_DURABLE // cgs_cmd, reply cache persisted to a state file
} s_rtt_mode_t;

/* What the server process is to do, and what it reports at the end. */
typedef struct {
    s_rtt_mode_t mode;
    size_t reply_size; // raw echo: bytes of each reply
} s_srv_opts_t;

typedef struct {
    int err; // 0, or a positive errno
    uint64_t applied, duplicates, malformed, write_errors;
} s_srv_report_t;

static void s_ping_handler (void *arg, const Cgs__Command *cmd, Cgs__Reply *reply)
{
    (void)arg;
    (void)cmd;
    reply->detail = "pong";
}

/* A Ping as cgs_cmd_client_call sends it, and the reply the server sends:
 * their encoded sizes, for the raw echo to move the same bytes. */
static void s_cmd_sizes (size_t *ret_request, size_t *ret_reply)
{
    Cgs__Ping ping = CGS__PING__INIT;
    ping.text = "bench";
    Cgs__Command cmd = CGS__COMMAND__INIT;
    cmd.client_id = "bench-client";
    cmd.command_number = 1000;
    cmd.sent_wall_time_s = cgs_bus_wall_time ();
    cmd.body_case = CGS__COMMAND__BODY_PING;
    cmd.ping = &ping;
    Cgs__Reply reply = CGS__REPLY__INIT;
    reply.client_id = cmd.client_id;
    reply.command_number = cmd.command_number;
    reply.detail = "pong";
    reply.server = "bench";
    *ret_request = cgs_msg_size (&cmd.base);
    *ret_reply = cgs_msg_size (&reply.base);
}

/* Wait on the server socket and the control socket; 1 when the socket is
 * readable, 0 when the parent said 'Q' or went away, or -errno. */
static int s_srv_wait (void *socket, int fd)
{
    for (;;) {
        zmq_pollitem_t items[2] = {{socket, 0, ZMQ_POLLIN, 0}, {NULL, fd, ZMQ_POLLIN, 0}};
        if (zmq_poll (items, 2, -1) < 0) {
            if (zmq_errno () == EINTR)
                continue;
            return -zmq_errno ();
        }
        if (items[0].revents & ZMQ_POLLIN)
            return 1;
        if (items[1].revents)
            return 0;
    }
}

/* Take the parent's 'Q' (if not yet read) and send it the report. */
static void s_srv_report (int fd, s_srv_report_t *report)
{
    char c;
    s_ctl_recv (fd, &c, 1, 1000);
    s_ctl_send (fd, report, sizeof *report);
}

/* A cgs_cmd_server process, its reply cache in memory or in DIR/replies
 * (endpoint is ipc://DIR/cmd); serves until the parent says 'Q'. */
static int s_cmd_server (int fd, const void *arg, const char *endpoint)
{
    const s_srv_opts_t *so = arg;
    s_srv_report_t report = {0};
    char cache[300] = "";
    if (so->mode == S_RTT_DURABLE) {
        const char *dir = endpoint + strlen ("ipc://");
        snprintf (cache, sizeof cache, "%.*s/replies", (int)(strrchr (dir, '/') - dir), dir);
    }
    void *ctx = zmq_ctx_new ();
    cgs_cmd_server_t *srv =
        ctx ? cgs_cmd_server_new (ctx, "bench", *cache ? cache : NULL, s_ping_handler, NULL) : NULL;
    int rc = srv ? cgs_cmd_server_bind (srv, endpoint) : -ENOMEM;
    if (rc == 0)
        rc = s_ctl_send (fd, "R", 1);
    while (rc == 0 && (rc = s_srv_wait (cgs_cmd_server_socket (srv), fd)) == 1) {
        int n = cgs_cmd_server_dispatch (srv, 100);
        rc = n < 0 ? n : 0;
    }
    if (srv) {
        report.applied = cgs_cmd_server_applied (srv);
        report.duplicates = cgs_cmd_server_duplicates (srv);
        report.malformed = cgs_cmd_server_malformed (srv);
        report.write_errors = cgs_cmd_server_write_errors (srv);
    }
    report.err = rc < 0 ? -rc : 0;
    s_srv_report (fd, &report);
    cgs_cmd_server_destroy (&srv);
    if (ctx)
        zmq_ctx_term (ctx);
    if (rc < 0)
        fprintf (stderr, "bench_bus: command server: %s\n", strerror (-rc));
    return rc;
}

/* A raw ROUTER process: answers each request with reply_size bytes. */
static int s_raw_echo_server (int fd, const void *arg, const char *endpoint)
{
    const s_srv_opts_t *so = arg;
    s_srv_report_t report = {0};
    void *ctx = zmq_ctx_new ();
    void *s = ctx ? zmq_socket (ctx, ZMQ_ROUTER) : NULL;
    uint8_t *reply = calloc (1, so->reply_size);
    int rc = s && reply ? 0 : -ENOMEM;
    if (rc == 0) {
        int linger = 0;
        zmq_setsockopt (s, ZMQ_LINGER, &linger, sizeof linger);
        rc = cgs_bus_prepare_endpoint (endpoint);
        if (rc == 0 && zmq_bind (s, endpoint) < 0)
            rc = -zmq_errno ();
    }
    if (rc == 0)
        rc = s_ctl_send (fd, "R", 1);
    zmq_msg_t id, body;
    zmq_msg_init (&id);
    zmq_msg_init (&body);
    while (rc == 0 && (rc = s_srv_wait (s, fd)) == 1) {
        rc = 0;
        while (rc == 0 && zmq_msg_recv (&id, s, ZMQ_DONTWAIT) >= 0) {
            if (!zmq_msg_more (&id) || zmq_msg_recv (&body, s, 0) < 0 || zmq_msg_more (&body)) {
                rc = -EPROTO;
                break;
            }
            if (zmq_send (s, zmq_msg_data (&id), zmq_msg_size (&id), ZMQ_SNDMORE) < 0 ||
                zmq_send (s, reply, so->reply_size, 0) < 0)
                rc = -zmq_errno ();
            report.applied++;
        }
    }
    zmq_msg_close (&id);
    zmq_msg_close (&body);
    report.err = rc < 0 ? -rc : 0;
    s_srv_report (fd, &report);
    free (reply);
    if (s)
        zmq_close (s);
    if (ctx)
        zmq_ctx_term (ctx);
    if (rc < 0)
        fprintf (stderr, "bench_bus: raw echo server: %s\n", strerror (-rc));
    return rc;
}

/* The client side of one round trip, either kind. */
typedef struct {
    s_rtt_mode_t mode;
    cgs_cmd_client_t *client; // cgs_cmd
    void *dealer;             // raw
    uint8_t *request;         // raw: bytes to send
    size_t request_size, reply_size;
} s_caller_t;

/* One Ping round trip; 0, or -errno with a reason in err. */
static int s_call (s_caller_t *c, long i, char *err, size_t errlen)
{
    if (c->mode == S_RTT_RAW) {
        if (zmq_send (c->dealer, c->request, c->request_size, 0) < 0) {
            snprintf (err, errlen, "call %ld: send: %s", i, zmq_strerror (zmq_errno ()));
            return -EIO;
        }
        zmq_pollitem_t item = {c->dealer, 0, ZMQ_POLLIN, 0};
        zmq_msg_t m;
        zmq_msg_init (&m);
        int rc = zmq_poll (&item, 1, 5000) == 1 ? zmq_msg_recv (&m, c->dealer, ZMQ_DONTWAIT) : -1;
        bool ok = rc == (int)c->reply_size && !zmq_msg_more (&m);
        zmq_msg_close (&m);
        if (!ok)
            snprintf (err, errlen, "call %ld: no reply or a wrong one", i);
        return ok ? 0 : -EIO;
    }
    Cgs__Ping ping = CGS__PING__INIT;
    ping.text = "bench";
    Cgs__Command cmd = CGS__COMMAND__INIT;
    cmd.body_case = CGS__COMMAND__BODY_PING;
    cmd.ping = &ping;
    Cgs__Reply *reply = NULL;
    char why[256] = "";
    int rc = cgs_cmd_client_call (c->client, &cmd, 5000, 1, &reply, why, sizeof why);
    if (rc < 0)
        snprintf (err, errlen, "call %ld: %s", i, why);
    else if (reply->status != CGS__REPLY_STATUS__REPLY_STATUS_OK || reply->duplicate) {
        snprintf (err, errlen, "call %ld: status %d%s", i, reply->status,
                  reply->duplicate ? ", answered as a duplicate" : "");
        rc = -EIO;
    }
    cgs_cmd_reply_free (&reply);
    return rc;
}

typedef struct {
    bool have;
    long calls;
    double median_us, p99_us, min_us, max_us, mean_us;
} s_rtt_t;

static const char *s_fs_name (const char *path)
{
    struct statfs sf;
    if (statfs (path, &sf) < 0)
        return "unknown filesystem";
    switch ((unsigned long)sf.f_type) {
    case EXT4_SUPER_MAGIC:
        return "ext2/3/4";
    case TMPFS_MAGIC:
        return "tmpfs: in memory, so fsync costs nothing";
    case XFS_SUPER_MAGIC:
        return "xfs";
    case BTRFS_SUPER_MAGIC:
        return "btrfs";
    case OVERLAYFS_SUPER_MAGIC:
        return "overlayfs";
    default:
        return "other filesystem";
    }
}

/* One kind of round trip being measured: its server process and its client. */
typedef struct {
    s_rtt_mode_t mode;
    char dir[256], endpoint[300];
    pid_t pid;
    int fd;         // control socket to the server process
    const char *fs; // filesystem of dir, found before it is removed
    s_caller_t caller;
    double *lat; // per timed call, microseconds
    char err[512];
} s_rtt_side_t;

static const char *s_rtt_what[] = {"raw libzmq DEALER/ROUTER echo", "reply cache in memory",
                                   "reply cache persisted"};

/* Make the side's folder, start its server, connect its client; 0 or -EIO
 * with a reason in side->err. */
static int s_rtt_open (s_rtt_side_t *side, const s_opts_t *o, void *ctx, long calls)
{
    char dir[sizeof side->dir];
    int rc = s_tmpdir (dir, sizeof dir, side->mode == S_RTT_DURABLE ? o->state_dir : NULL, "cmd");
    if (rc < 0) {
        snprintf (side->err, sizeof side->err, "cannot make a temporary folder: %s",
                  strerror (-rc));
        return -EIO;
    }
    memcpy (side->dir, dir, sizeof dir);
    snprintf (side->endpoint, sizeof side->endpoint, "ipc://%s/cmd", dir);
    side->fs = s_fs_name (dir);
    s_caller_t *c = &side->caller;
    c->mode = side->mode;
    s_cmd_sizes (&c->request_size, &c->reply_size);
    s_srv_opts_t so = {side->mode, c->reply_size};
    side->lat = malloc ((size_t)calls * sizeof *side->lat);
    c->request = calloc (1, c->request_size);
    if (!side->lat || !c->request) {
        snprintf (side->err, sizeof side->err, "out of memory");
        return -EIO;
    }
    side->pid = s_spawn (side->mode == S_RTT_RAW ? s_raw_echo_server : s_cmd_server, &so,
                         side->endpoint, &side->fd);
    char ready = 0;
    if (side->pid < 0) {
        snprintf (side->err, sizeof side->err, "cannot start the server: %s",
                  strerror (-side->pid));
        return -EIO;
    }
    if ((rc = s_ctl_recv (side->fd, &ready, 1, 5000)) < 0) {
        snprintf (side->err, sizeof side->err, "server did not start: %s", strerror (-rc));
        return -EIO;
    }
    if (side->mode == S_RTT_RAW) {
        c->dealer = zmq_socket (ctx, ZMQ_DEALER);
        int linger = 0;
        if (c->dealer)
            zmq_setsockopt (c->dealer, ZMQ_LINGER, &linger, sizeof linger);
        if (c->dealer && zmq_connect (c->dealer, side->endpoint) < 0) {
            zmq_close (c->dealer);
            c->dealer = NULL;
        }
    } else
        c->client = cgs_cmd_client_new (ctx, side->endpoint, "bench-client");
    if (!c->dealer && !c->client) {
        snprintf (side->err, sizeof side->err, "cannot make a client: %s", strerror (errno));
        return -EIO;
    }
    return 0;
}

/* Close the side's client, stop its server and check what it counted
 * (expected: requests handled), remove its folder. 0 or -EIO. */
static int s_rtt_close (s_rtt_side_t *side, uint64_t expected)
{
    s_caller_t *c = &side->caller;
    cgs_cmd_client_destroy (&c->client);
    if (c->dealer)
        zmq_close (c->dealer);
    c->dealer = NULL;
    free (c->request);
    c->request = NULL;
    if (side->pid > 0) {
        s_srv_report_t report = {0};
        int rc = s_ctl_send (side->fd, "Q", 1);
        if (rc == 0)
            rc = s_ctl_recv (side->fd, &report, sizeof report, 5000);
        close (side->fd);
        int reap = s_reap (side->pid);
        side->pid = 0;
        if (*side->err)
            ;
        else if (rc < 0 || reap < 0)
            snprintf (side->err, sizeof side->err, "server failed or sent no report");
        else if (report.err || report.write_errors || report.duplicates || report.malformed ||
                 report.applied != expected)
            snprintf (side->err, sizeof side->err,
                      "server: error %d, %llu handled of %llu, %llu duplicates, %llu malformed, "
                      "%llu state-file write failures",
                      report.err, (unsigned long long)report.applied, (unsigned long long)expected,
                      (unsigned long long)report.duplicates, (unsigned long long)report.malformed,
                      (unsigned long long)report.write_errors);
    }
    if (*side->dir)
        s_rmtree (side->dir);
    return *side->err ? -EIO : 0;
}

/* Median, p99, min, max and mean of the side's timed calls, printed. */
static void s_rtt_summary (s_rtt_side_t *side, long calls, long warm, s_rtt_t *ret)
{
    double *lat = side->lat;
    qsort (lat, (size_t)calls, sizeof *lat, s_cmp_double);
    double sum = 0;
    for (long i = 0; i < calls; i++)
        sum += lat[i];
    *ret = (s_rtt_t){true,
                     calls,
                     s_quantile (lat, (size_t)calls, 0.5),
                     s_quantile (lat, (size_t)calls, 0.99),
                     lat[0],
                     lat[calls - 1],
                     sum / (double)calls};
    if (side->mode == S_RTT_DURABLE)
        printf ("cmd rtt, cgs_cmd, reply cache persisted (state file in %s, %s; every command "
                "rewrites it with fsync of the file and the folder before the reply):\n",
                side->dir, side->fs);
    else if (side->mode == S_RTT_MEMORY)
        printf ("cmd rtt, cgs_cmd, reply cache in memory (no state file):\n");
    else
        printf ("cmd rtt, raw libzmq DEALER/ROUTER echo of the same sizes (%zu bytes out, %zu "
                "back; the baseline):\n",
                side->caller.request_size, side->caller.reply_size);
    printf ("  %ld calls after %ld warm-up: median %.1f us, p99 %.1f us, "
            "min %.1f, max %.1f, mean %.1f\n",
            calls, warm, ret->median_us, ret->p99_us, ret->min_us, ret->max_us, ret->mean_us);
}

/* Time `calls` Ping round trips of each of n kinds, after a warm-up, each
 * against its own server process. The kinds take turns call by call, so a
 * machine that is noisier at one moment than another favours none. */
static int s_cmd_rtt (const s_opts_t *o, const s_rtt_mode_t *modes, int n, long calls,
                      s_rtt_t *rets)
{
    s_rtt_side_t sides[3] = {0};
    assert (n >= 1 && n <= 3);
    long warm = calls / 10 < 200 ? calls / 10 : 200;
    void *ctx = zmq_ctx_new ();
    bool broke = ctx == NULL;
    for (int k = 0; k < n; k++) {
        sides[k].mode = modes[k];
        if (!broke)
            broke = s_rtt_open (&sides[k], o, ctx, calls) < 0;
    }
    for (long i = 0; !broke && i < warm + calls; i++)
        for (int j = 0; !broke && j < n; j++) {
            s_rtt_side_t *side = &sides[(i + j) % n];
            double t0 = s_now_s ();
            broke = s_call (&side->caller, i + 1, side->err, sizeof side->err) < 0;
            if (!broke && i >= warm)
                side->lat[i - warm] = (s_now_s () - t0) * 1e6;
        }
    for (int k = 0; k < n; k++)
        if (s_rtt_close (&sides[k], broke ? 0 : (uint64_t)(warm + calls)) < 0)
            broke = true;
    if (ctx)
        zmq_ctx_term (ctx);
    for (int k = 0; k < n; k++) {
        if (*sides[k].err)
            printf ("cmd (%s): FAILED: %s\n", s_rtt_what[sides[k].mode], sides[k].err);
        else if (!broke)
            s_rtt_summary (&sides[k], calls, warm, &rets[k]);
        free (sides[k].lat);
    }
    return broke ? -EIO : 0;
}

/* ---- main ------------------------------------------------------------------------ */

static void s_usage (FILE *f)
{
    fprintf (f,
             "usage: bench_bus [all|pubsub|cmd] [options]\n"
             "  --messages N       timed messages per throughput run (default 2000000)\n"
             "  --runs R           throughput runs of each side, alternating (default 7)\n"
             "  --hwm H            send and receive high-water marks (default %d)\n"
             "  --size B           payload bytes on the wire (default 100)\n"
             "  --only ours|raw    run one throughput side (for profiling)\n"
             "  --calls N          timed command calls, reply cache in memory (default 20000)\n"
             "  --durable-calls N  timed command calls, cache persisted with fsync (default "
             "1000; 0 skips)\n"
             "  --state-dir DIR    parent of the state file's folder (default $TMPDIR or /tmp)\n",
             CGS_BUS_DEFAULT_SNDHWM);
}

int main (int argc, char **argv)
{
    s_opts_t o = {.messages = 2000000,
                  .runs = 7,
                  .hwm = CGS_BUS_DEFAULT_SNDHWM,
                  .size = 100,
                  .ours = true,
                  .raw = true,
                  .calls = 20000,
                  .durable_calls = 1000};
    const char *mode = "all";
    int i = 1;
    if (i < argc && argv[i][0] != '-')
        mode = argv[i++];
    if (strcmp (mode, "all") && strcmp (mode, "pubsub") && strcmp (mode, "cmd")) {
        s_usage (stderr);
        return 2;
    }
    for (; i < argc; i += 2) { // every option but --help takes a value
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        if (!strcmp (a, "--help") || !strcmp (a, "-h")) {
            s_usage (stdout);
            return 0;
        }
        long n = 0;
        bool ok = v != NULL;
        if (!ok)
            ;
        else if (!strcmp (a, "--messages"))
            ok = bench_parse_long (v, 2, 1000000000, &o.messages);
        else if (!strcmp (a, "--runs") && (ok = bench_parse_long (v, 1, S_MAX_RUNS, &n)))
            o.runs = (int)n;
        else if (!strcmp (a, "--hwm") && (ok = bench_parse_long (v, 0, 100000000, &n)))
            o.hwm = (int)n;
        else if (!strcmp (a, "--size") && (ok = bench_parse_long (v, 64, 4096, &n)))
            o.size = (size_t)n;
        else if (!strcmp (a, "--only") && (ok = !strcmp (v, "ours") || !strcmp (v, "raw"))) {
            o.ours = !strcmp (v, "ours");
            o.raw = !o.ours;
        } else if (!strcmp (a, "--calls"))
            ok = bench_parse_long (v, 1, 100000000, &o.calls);
        else if (!strcmp (a, "--durable-calls"))
            ok = bench_parse_long (v, 0, 100000000, &o.durable_calls);
        else if (!strcmp (a, "--state-dir"))
            o.state_dir = v;
        else if (strcmp (a, "--runs") && strcmp (a, "--hwm") && strcmp (a, "--size") &&
                 strcmp (a, "--only"))
            ok = false; // not an option
        if (!ok) {
            fprintf (stderr, "bench_bus: bad option or value: %s %s\n", a, v ? v : "");
            s_usage (stderr);
            return 2;
        }
    }
    signal (SIGPIPE, SIG_IGN);

    int major = 0, minor = 0, patch = 0;
    zmq_version (&major, &minor, &patch);
    long cores = sysconf (_SC_NPROCESSORS_ONLN);
    printf ("bench_bus: libzmq %d.%d.%d, %ld cores online (publisher, subscriber and their "
            "libzmq I/O threads share them: four busy threads on %ld cores)\n",
            major, minor, patch, cores, cores);
    fflush (stdout);

    bool broke = false;
    s_pubsub_result_t ps = {0};
    if (strcmp (mode, "cmd") != 0)
        broke |= s_bench_pubsub (&o, &ps) < 0;
    s_rtt_t rtt[2] = {{0}}, dur = {0};
    s_rtt_t *raw_rtt = &rtt[0], *mem = &rtt[1];
    if (strcmp (mode, "pubsub") != 0) {
        const s_rtt_mode_t pair[2] = {S_RTT_RAW, S_RTT_MEMORY}, durable[1] = {S_RTT_DURABLE};
        broke |= s_cmd_rtt (&o, pair, 2, o.calls, rtt) < 0;
        if (o.durable_calls > 0)
            broke |= s_cmd_rtt (&o, durable, 1, o.durable_calls, &dur) < 0;
    }

    printf ("\n--- figures ---\n");
    printf ("cores=%ld\n", cores);
    printf ("zmq_version=%d.%d.%d\n", major, minor, patch);
    if (ps.have_ours || ps.have_raw)
        printf ("payload_bytes=%zu\nmessages_per_run=%ld\nruns=%d\nhwm=%d\n", o.size, o.messages,
                o.runs, o.hwm);
    if (ps.have_ours)
        printf ("pubsub_msgs_per_s=%.0f\npubsub_msgs_per_s_min=%.0f\npubsub_msgs_per_s_max=%.0f\n",
                ps.ours.median, ps.ours.min, ps.ours.max);
    if (ps.have_raw)
        printf ("raw_msgs_per_s=%.0f\nraw_msgs_per_s_min=%.0f\nraw_msgs_per_s_max=%.0f\n",
                ps.raw.median, ps.raw.min, ps.raw.max);
    double ratio = ps.have_ours && ps.have_raw ? ps.ours.median / ps.raw.median : 0;
    if (ps.have_ours && ps.have_raw)
        printf ("ratio=%.3f\n", ratio);
    if (mem->have)
        printf ("cmd_rtt_median_us=%.1f\ncmd_rtt_p99_us=%.1f\n", mem->median_us, mem->p99_us);
    if (raw_rtt->have)
        printf ("cmd_rtt_raw_median_us=%.1f\ncmd_rtt_raw_p99_us=%.1f\n", raw_rtt->median_us,
                raw_rtt->p99_us);
    if (dur.have)
        printf ("cmd_rtt_fsync_median_us=%.1f\ncmd_rtt_fsync_p99_us=%.1f\n", dur.median_us,
                dur.p99_us);
    if (broke)
        printf ("verdict=FAIL (a measurement broke; see above)\n");
    else if (ps.have_ours && ps.have_raw) {
        bool fast = ps.ours.median >= S_GOAL_MSGS_PER_S, close = ratio >= S_GOAL_RATIO;
        printf ("goal_pubsub_msgs_per_s=%.0f\ngoal_ratio=%.2f\n", S_GOAL_MSGS_PER_S, S_GOAL_RATIO);
        printf ("verdict=%s\n", fast && close ? "PASS" : "BELOW-GOAL");
        if (!fast || !close)
            printf ("  (%s%s%s)\n", fast ? "" : "below 1,000,000 msg/s",
                    !fast && !close ? "; " : "", close ? "" : "below 0.7 of raw libzmq");
    }
    return broke ? 1 : 0;
}
