/* bench_gateway — how fast the DIS gateway's cores are, on one core.
 *
 *   bench_gateway [options]     (--help lists them)
 *
 * The process pins itself to the core it starts on; every figure is the
 * median over R runs (default 5), printed with the runs' min and max. The
 * runs interleave the figures (run 1 of each, then run 2 of each, ...), so a
 * machine that gets busier or quieter during the benchmark favours none.
 *
 * 1. espdu_send: Entity State PDUs encoded AND sent per second. Each PDU is
 *    filled (id, timestamp, location, velocity, orientation and marking
 *    vary with its number, so the compiler can fold nothing), encoded with
 *    gw_pdu_encode_espdu (version 7, as the gateway sends by default) into
 *    one of B buffers (default 64), and every B PDUs go out in one sendmmsg
 *    call, each message addressed as the gateway addresses them (msg_name
 *    set, unconnected socket), to 127.0.0.1 on an ephemeral port that a
 *    receiving socket of the benchmark's own holds: nothing is ever sent to a
 *    port nobody listens on, so no ICMP errors. The receiving socket belongs
 *    to a forked drain process, pinned to another core when there is one,
 *    that reads everything with recvmmsg and counts what it got (UDP is
 *    lossy: what its full receive buffer drops is reported, not a failure).
 *    Wall-clock time of the sending loop: on loopback the kernel delivers
 *    the datagram to the receiving socket inside the sender's system call,
 *    so the figure includes that delivery (a real network card's driver
 *    would cost something else). Goal: 200,000 PDUs/s.
 * 2. espdu_encode: the same fill and encode, without sending (CPU time), for
 *    comparison: the difference with 1 is the system calls' cost.
 * 3. espdu_decode: Entity State PDUs decoded per second (CPU time): a buffer
 *    of 8,192 encoded PDUs of versions 4, 5, 6 and 7 in turn, grouped in
 *    datagrams of 1 to 4 PDUs, walked with gw_pdu_walk, each PDU decoded with
 *    gw_pdu_decode_espdu (which reads and checks the header itself), over
 *    and over until the run's count is reached. Every PDU must decode.
 *    Goal: 1,000,000 PDUs/s.
 * 4. outbound: the gateway's whole outbound path for one entity update (CPU
 *    time): gw_out_truth from a Cgs__Entity (local frame about 35.96 N,
 *    121.23 W, cgs_geo_new), gw_out_update (dead reckoning against what was
 *    last sent, at the default thresholds: 1 m, 3 degrees, 5 s heartbeat),
 *    and when a PDU is due gw_out_fill and gw_pdu_encode_espdu. N entities
 *    (default 10,000; half ground vehicles, half aircraft) drive or fly
 *    circles of 300 m to 3 km at 5 to 20 m/s (aircraft 60 to 120 m/s,
 *    banked), updated at 10 Hz of simulation time, T ticks (default 20) a
 *    run; moving the entities between ticks is not timed. Figure: entity
 *    updates per second, with the share of updates that sent a PDU.
 * 5. outbound_all: the same with a heartbeat of 0 s, so that every update
 *    sends a PDU: the path's worst case, fill and encode always included.
 *    Neither 4 nor 5 has a goal; for reference, N = 10,000 entities at
 *    10 Hz are 100,000 updates a second.
 * 6. s4607_reports: STANAG 4607 target reports per second (CPU time): the
 *    gateway's whole path from `mti` messages (gw_gmti_on_mti, truth tags
 *    off: each hit's position to latitude, longitude and height with
 *    GeographicLib, the dwell segment encoded, the packet handed to a
 *    callback that folds its bytes), dwells of H hits (default 20) spread
 *    over 20 km, 4,000 dwells a run. No goal; for reference, the
 *    1,000-vehicle scenario's radar makes about 1,100 hits a 10 s scan.
 * 7. cot_xml, cot_proto: Cursor on Target events per second (CPU time): a
 *    batch of N tracks (default 1,000) through gw_cotout_on_tracks, every
 *    one due (the clock steps a second a batch), each event encoded by
 *    gw_cot_encode_xml, or gw_cot_encode_proto, in the emit callback. No
 *    goal; for reference, 1,000 tracks at the default 1 Hz are 1,000
 *    events a second.
 *
 * Output: readable lines, one per figure (median, min, max, goal met or
 * not), then a block of key=value figures and a verdict against the goals.
 * Exit 0 whether or not the goals are met; 1 when a measurement broke (a
 * send failed, a PDU did not encode or decode, the drain received nothing);
 * 2 on bad usage.
 *
 * Departures from the style guide, as in the other benchmarks: it prints to
 * stdout (its output is the product) and forks a child that never returns
 * into main. */
#include "bench_util.h"
#include "cgs_geo.h"
#include "gw_cot.h"
#include "gw_cotout.h"
#include "gw_gmti.h"
#include "gw_out.h"
#include "gw_params.h"
#include "gw_pdu.h"
#include "sensors.pb-c.h"
#include "tracking.pb-c.h"
#include "world.pb-c.h"

#include <arpa/inet.h>
#include <errno.h>
#include <math.h>
#include <netinet/in.h>
#include <poll.h>
#include <sched.h>
#include <signal.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#define S_PI                3.14159265358979323846
#define S_MAX_RUNS          64
#define S_MAX_BATCH         1024
#define S_DECODE_PDUS       8192       // PDUs in the decode buffer
#define S_RCVBUF            (32 << 20) // asked for the drain's receive buffer, bytes
#define S_GOAL_SEND_PER_S   200000.0
#define S_GOAL_DECODE_PER_S 1000000.0
#define S_REF_UPDATES_PER_S 100000.0 // 10,000 entities at 10 Hz

typedef struct {
    int runs;
    long pdus;      // PDUs encoded and decoded per run (figures 2 and 3)
    long send_pdus; // PDUs encoded and sent per run (figure 1)
    int batch;      // PDUs per sendmmsg call
    long entities;  // outbound entities (figures 4 and 5)
    int ticks;      // timed 10 Hz ticks per run (figures 4 and 5)
    long hits;      // hits a dwell (figure 6)
    long tracks;    // tracks a batch (figure 7)
} s_opts_t;

/* One figure over the runs. */
typedef struct {
    double v[S_MAX_RUNS];
    int n;
    double median, min, max;
} s_fig_t;

static void s_fig_add (s_fig_t *f, double v)
{
    f->v[f->n++] = v;
}

static void s_fig_done (s_fig_t *f)
{
    double tmp[S_MAX_RUNS];
    memcpy (tmp, f->v, (size_t)f->n * sizeof *tmp);
    f->median = bench_median (tmp, f->n);
    f->min = tmp[0];
    f->max = tmp[f->n - 1];
}

/* Defeats dead-code elimination: every result is folded in here. */
static volatile uint64_t s_sink;

/* ---- the PDUs ------------------------------------------------------------------------------ */

/* Fill PDU number i: every field the decoder reads varies with i. */
static void s_fill (gw_espdu_t *p, uint64_t i, uint8_t version)
{
    memset (p, 0, sizeof *p);
    p->hdr.version = version;
    p->hdr.exercise = 1;
    p->hdr.timestamp = (uint32_t)(i << 1);
    p->hdr.status = version >= 7 ? GW_STATUS_LVC_CONSTRUCTIVE : 0;
    p->id = (gw_id_t){1, 1, (uint16_t)(1 + i % 65000)};
    p->force = (uint8_t)(1 + i % 3);
    p->type = (gw_type_t){1, 1, 225, (uint8_t)(1 + i % 9), 1, 0, 0};
    p->alt_type = p->type;
    double k = (double)(i % 100000);
    p->velocity[0] = (float)(3.0 + k * 1e-3);
    p->velocity[1] = (float)(-4.0 + k * 2e-3);
    p->velocity[2] = (float)(k * 1e-4);
    p->location[0] = -2678000.0 + k * 0.37;
    p->location[1] = -4400000.0 - k * 0.21;
    p->location[2] = 3728000.0 + k * 0.05;
    p->orientation[0] = (float)(k * 1e-4);
    p->orientation[1] = (float)(0.01 + k * 1e-6);
    p->orientation[2] = (float)(-0.02 + k * 1e-6);
    p->dr_algorithm = (uint8_t)(i & 1 ? GW_DR_RVW : GW_DR_FPW);
    p->acceleration[0] = (float)(k * 1e-5);
    p->angular_velocity[2] = (float)(k * 1e-6);
    p->marking_charset = 1;
    p->marking[0] = 'E'; // E and six digits of i, written by hand: snprintf would cost more
    uint64_t d = i;      // than the encoding being measured
    for (int k = 6; k >= 1; k--, d /= 10)
        p->marking[k] = (char)('0' + d % 10);
}

/* ---- figure 2: encode only ----------------------------------------------------------------- */

/* PDUs per CPU second, or -1 when a PDU did not encode. */
static double s_encode (const s_opts_t *o, uint8_t (*bufs)[GW_ESPDU_LEN], uint64_t *next)
{
    uint64_t sum = 0;
    gw_espdu_t p;
    double t0 = bench_cpu_s ();
    for (long i = 0; i < o->pdus; i++) {
        s_fill (&p, (*next)++, 7);
        uint8_t *b = bufs[i % o->batch];
        if (gw_pdu_encode_espdu (&p, b, GW_ESPDU_LEN) != GW_ESPDU_LEN)
            return -1;
        sum += b[20] ^ b[75] ^ b[140];
    }
    double dt = bench_cpu_s () - t0;
    s_sink += sum;
    return (double)o->pdus / dt;
}

/* ---- figure 1: encode and send ------------------------------------------------------------- */

/* The drain (child process): read everything on fd until 'Q' comes on ctl;
 * on each 'C' report the datagrams received so far (after reading what is
 * queued). Datagrams that are not one Entity State PDU are counted apart. */
static int s_drain (int fd, int ctl)
{
    enum { N = 256 };
    static uint8_t bufs[N][GW_ESPDU_LEN + 16];
    struct mmsghdr mm[N];
    struct iovec iov[N];
    uint64_t got[2] = {0, 0}; // received, of them not an Entity State PDU of 144 bytes
    for (;;) {
        struct pollfd pfd[2] = {{fd, POLLIN, 0}, {ctl, POLLIN, 0}};
        if (poll (pfd, 2, 10000) < 0) {
            if (errno == EINTR)
                continue;
            return -errno;
        }
        for (;;) { // everything queued
            for (int i = 0; i < N; i++) {
                iov[i] = (struct iovec){bufs[i], sizeof bufs[i]};
                memset (&mm[i], 0, sizeof mm[i]);
                mm[i].msg_hdr.msg_iov = &iov[i];
                mm[i].msg_hdr.msg_iovlen = 1;
            }
            int n = recvmmsg (fd, mm, N, MSG_DONTWAIT, NULL);
            if (n < 0 && errno == EINTR)
                continue;
            if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK))
                break;
            if (n < 0)
                return -errno;
            for (int i = 0; i < n; i++) {
                got[0]++;
                if (mm[i].msg_len != GW_ESPDU_LEN || bufs[i][2] != GW_PDU_ENTITY_STATE)
                    got[1]++;
            }
        }
        if (pfd[1].revents) {
            char c = 0;
            ssize_t r = read (ctl, &c, 1);
            if (r <= 0 || c == 'Q')
                return 0;
            if (write (ctl, got, sizeof got) != (ssize_t)sizeof got)
                return -EIO;
        }
    }
}

typedef struct {
    int fd;    // sending socket
    int ctl;   // control socket to the drain
    pid_t pid; // the drain
    struct sockaddr_in to;
    int rcvbuf; // the drain socket's receive buffer as the kernel set it, bytes
    int drain_cpu;
} s_sender_t;

/* The CPUs this process may run on, the one it runs on first. */
static int s_cpus (int *ret, int max)
{
    cpu_set_t set;
    int n = 0, here = sched_getcpu ();
    if (sched_getaffinity (0, sizeof set, &set) < 0)
        return 0;
    if (here >= 0 && CPU_ISSET (here, &set))
        ret[n++] = here;
    for (int c = 0; c < CPU_SETSIZE && n < max; c++)
        if (CPU_ISSET (c, &set) && c != here)
            ret[n++] = c;
    return n;
}

static void s_pin (int cpu)
{
    cpu_set_t set;
    CPU_ZERO (&set);
    CPU_SET (cpu, &set);
    sched_setaffinity (0, sizeof set, &set); // best effort: the figures stand without it
}

/* Bind the receiving socket, fork the drain that owns it, open the sending
 * socket; 0 or -errno with a reason in err. */
static int s_sender_open (s_sender_t *s, const int *cpus, int ncpus, char *err, size_t errlen)
{
    *s = (s_sender_t){.fd = -1, .ctl = -1, .pid = -1, .drain_cpu = -1};
    int rx = socket (AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
    if (rx < 0) {
        snprintf (err, errlen, "socket: %s", strerror (errno));
        return -errno;
    }
    int size = S_RCVBUF;
    // SO_RCVBUFFORCE passes net.core.rmem_max when privileged; else the capped SO_RCVBUF.
    if (setsockopt (rx, SOL_SOCKET, SO_RCVBUFFORCE, &size, sizeof size) < 0)
        setsockopt (rx, SOL_SOCKET, SO_RCVBUF, &size, sizeof size);
    socklen_t sl = sizeof s->rcvbuf;
    getsockopt (rx, SOL_SOCKET, SO_RCVBUF, &s->rcvbuf, &sl);
    struct sockaddr_in a = {.sin_family = AF_INET, .sin_port = 0};
    a.sin_addr.s_addr = htonl (INADDR_LOOPBACK);
    socklen_t al = sizeof a;
    if (bind (rx, (struct sockaddr *)&a, sizeof a) < 0 ||
        getsockname (rx, (struct sockaddr *)&a, &al) < 0) {
        snprintf (err, errlen, "bind 127.0.0.1:0: %s", strerror (errno));
        close (rx);
        return -EIO;
    }
    s->to = a;
    int sv[2];
    if (socketpair (AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, sv) < 0) {
        snprintf (err, errlen, "socketpair: %s", strerror (errno));
        close (rx);
        return -EIO;
    }
    s->drain_cpu = ncpus > 1 ? cpus[1] : -1;
    fflush (NULL);
    s->pid = fork ();
    if (s->pid == 0) {
        close (sv[0]);
        if (s->drain_cpu >= 0)
            s_pin (s->drain_cpu);
        int rc = s_drain (rx, sv[1]);
        _exit (rc == 0 ? 0 : 1);
    }
    close (rx);
    close (sv[1]);
    if (s->pid < 0) {
        snprintf (err, errlen, "fork: %s", strerror (errno));
        close (sv[0]);
        return -EIO;
    }
    s->ctl = sv[0];
    s->fd = socket (AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
    if (s->fd < 0) {
        snprintf (err, errlen, "socket: %s", strerror (errno));
        return -EIO;
    }
    size = 4 << 20;
    setsockopt (s->fd, SOL_SOCKET, SO_SNDBUF, &size, sizeof size);
    return 0;
}

/* The datagrams the drain has received so far, and of them the bad ones; 0 or -EIO. */
static int s_sender_count (s_sender_t *s, uint64_t ret[2])
{
    uint64_t got[2];
    if (write (s->ctl, "C", 1) != 1)
        return -EIO;
    size_t have = 0;
    while (have < sizeof got) {
        struct pollfd pfd = {s->ctl, POLLIN, 0};
        if (poll (&pfd, 1, 10000) <= 0)
            return -EIO;
        ssize_t r = read (s->ctl, (char *)got + have, sizeof got - have);
        if (r <= 0)
            return -EIO;
        have += (size_t)r;
    }
    ret[0] = got[0];
    ret[1] = got[1];
    return 0;
}

/* Stop the drain; 0 when it exited cleanly. */
static int s_sender_close (s_sender_t *s)
{
    int rc = 0;
    if (s->fd >= 0)
        close (s->fd);
    if (s->ctl >= 0) {
        if (write (s->ctl, "Q", 1) != 1)
            rc = -EIO;
        close (s->ctl);
    }
    if (s->pid > 0) {
        int status = 0;
        while (waitpid (s->pid, &status, 0) < 0)
            if (errno != EINTR) {
                rc = -ECHILD;
                break;
            }
        if (!WIFEXITED (status) || WEXITSTATUS (status) != 0)
            rc = -ECHILD;
    }
    return rc;
}

/* Encode and send o->send_pdus PDUs in batches; PDUs per wall-clock second,
 * or -1 with a reason in err. */
static double s_send (const s_opts_t *o, s_sender_t *s, uint8_t (*bufs)[GW_ESPDU_LEN],
                      uint64_t *next, char *err, size_t errlen)
{
    struct mmsghdr mm[S_MAX_BATCH];
    struct iovec iov[S_MAX_BATCH];
    gw_espdu_t p;
    double t0 = bench_wall_s ();
    long done = 0;
    while (done < o->send_pdus) {
        int k = 0;
        for (; k < o->batch && done + k < o->send_pdus; k++) {
            s_fill (&p, (*next)++, 7);
            if (gw_pdu_encode_espdu (&p, bufs[k], GW_ESPDU_LEN) != GW_ESPDU_LEN) {
                snprintf (err, errlen, "an Entity State PDU did not encode");
                return -1;
            }
            iov[k] = (struct iovec){bufs[k], GW_ESPDU_LEN};
            memset (&mm[k], 0, sizeof mm[k]);
            mm[k].msg_hdr.msg_name = &s->to;
            mm[k].msg_hdr.msg_namelen = sizeof s->to;
            mm[k].msg_hdr.msg_iov = &iov[k];
            mm[k].msg_hdr.msg_iovlen = 1;
        }
        int at = 0;
        while (at < k) {
            int n = sendmmsg (s->fd, mm + at, (unsigned)(k - at), 0);
            if (n < 0 && errno == EINTR)
                continue;
            if (n <= 0) {
                snprintf (err, errlen, "sendmmsg: %s", n < 0 ? strerror (errno) : "sent nothing");
                return -1;
            }
            at += n;
        }
        done += k;
    }
    return (double)o->send_pdus / (bench_wall_s () - t0);
}

/* ---- figure 3: decode ---------------------------------------------------------------------- */

typedef struct {
    uint8_t *buf;
    size_t *off, *len; // datagrams: offset and length in buf
    size_t ndgram;
} s_dgrams_t;

/* S_DECODE_PDUS PDUs of versions 4..7 in turn, in datagrams of 1..4 PDUs; 0 or -1. */
static int s_dgrams_new (s_dgrams_t *d)
{
    d->buf = malloc ((size_t)S_DECODE_PDUS * GW_ESPDU_LEN);
    d->off = calloc (S_DECODE_PDUS, sizeof *d->off);
    d->len = calloc (S_DECODE_PDUS, sizeof *d->len);
    if (!d->buf || !d->off || !d->len)
        return -1;
    size_t at = 0, i = 0;
    d->ndgram = 0;
    while (i < S_DECODE_PDUS) {
        size_t n = 1 + d->ndgram % 4;
        if (n > S_DECODE_PDUS - i)
            n = S_DECODE_PDUS - i;
        d->off[d->ndgram] = at;
        for (size_t k = 0; k < n; k++, i++) {
            gw_espdu_t p;
            s_fill (&p, 7919 * i + 13, (uint8_t)(GW_VERSION_MIN + i % 4));
            if (gw_pdu_encode_espdu (&p, d->buf + at, GW_ESPDU_LEN) != GW_ESPDU_LEN)
                return -1;
            at += GW_ESPDU_LEN;
        }
        d->len[d->ndgram++] = n * GW_ESPDU_LEN;
    }
    return 0;
}

static void s_dgrams_free (s_dgrams_t *d)
{
    free (d->buf);
    free (d->off);
    free (d->len);
}

typedef struct {
    uint64_t decoded, failed;
    double sum;
} s_decode_state_t;

static void s_on_pdu (void *arg, const uint8_t *pdu, size_t len)
{
    s_decode_state_t *st = arg;
    gw_espdu_t e;
    if (gw_pdu_decode_espdu (pdu, len, &e, NULL) < 0) {
        st->failed++;
        return;
    }
    st->decoded++;
    st->sum += e.location[0] + e.velocity[1] + e.id.entity + e.hdr.version;
}

/* Decode at least o->pdus PDUs (whole datagrams); PDUs per CPU second, or -1
 * when one did not walk or decode. */
static double s_decode (const s_opts_t *o, const s_dgrams_t *d, size_t *cursor)
{
    s_decode_state_t st = {0};
    uint64_t walked = 0;
    double t0 = bench_cpu_s ();
    while (walked < (uint64_t)o->pdus) {
        size_t j = (*cursor)++ % d->ndgram;
        int n = gw_pdu_walk (d->buf + d->off[j], d->len[j], s_on_pdu, &st, NULL);
        if (n < 0)
            return -1;
        walked += (uint64_t)n;
    }
    double dt = bench_cpu_s () - t0;
    s_sink += (uint64_t)st.sum;
    if (st.failed || st.decoded != walked)
        return -1;
    return (double)st.decoded / dt;
}

/* ---- figures 4 and 5: outbound ------------------------------------------------------------- */

typedef struct {
    double cx, cy, r_m, w_rps, phase, up_m; // circle centre and radius, turn rate, phase
    bool air;
} s_mover_t;

typedef struct {
    long n;
    s_mover_t *mv;
    Cgs__Entity *msg;
    Cgs__Enu *pos;
    Cgs__EnuVelocity *vel;
    Cgs__EntityType *type;
    char (*marking)[GW_MARKING_LEN + 1];
    cgs_geo_t *geo;
    gw_out_t *out[2]; // default parameters; heartbeat 0 (every update sends)
    uint8_t (*queue)[GW_ESPDU_LEN];
    uint64_t sent[2], updates[2];
    double t_s; // simulation time of the next tick
} s_world_t;

static uint64_t s_rng = 0x853c49e6748fea9bull;
static double s_uniform (void)
{
    s_rng = s_rng * 6364136223846793005ull + 1442695040888963407ull;
    return ((double)(s_rng >> 11) + 0.5) / 9007199254740992.0;
}

static void s_world_free (s_world_t *w)
{
    free (w->mv);
    free (w->msg);
    free (w->pos);
    free (w->vel);
    free (w->type);
    free (w->marking);
    free (w->queue);
    gw_out_destroy (&w->out[0]);
    gw_out_destroy (&w->out[1]);
    cgs_geo_destroy (&w->geo);
}

static int s_world_new (s_world_t *w, long n)
{
    memset (w, 0, sizeof *w);
    w->n = n;
    w->mv = calloc ((size_t)n, sizeof *w->mv);
    w->msg = calloc ((size_t)n, sizeof *w->msg);
    w->pos = calloc ((size_t)n, sizeof *w->pos);
    w->vel = calloc ((size_t)n, sizeof *w->vel);
    w->type = calloc ((size_t)n, sizeof *w->type);
    w->marking = calloc ((size_t)n, sizeof *w->marking);
    w->queue = calloc (256, sizeof *w->queue);
    w->geo = cgs_geo_new (35.96, -121.23, 0);
    gw_out_params_t p;
    gw_out_params_defaults (&p);
    w->out[0] = gw_out_new (&p);
    p.heartbeat_s = 0;
    w->out[1] = gw_out_new (&p);
    if (!w->mv || !w->msg || !w->pos || !w->vel || !w->type || !w->marking || !w->queue ||
        !w->geo || !w->out[0] || !w->out[1])
        return -1;
    for (long i = 0; i < n; i++) {
        s_mover_t *m = &w->mv[i];
        m->air = i % 2 == 1;
        double speed = m->air ? 60 + 60 * s_uniform () : 5 + 15 * s_uniform ();
        m->r_m = 300 + 2700 * s_uniform ();
        m->w_rps = speed / m->r_m * (s_uniform () < 0.5 ? -1 : 1);
        m->cx = -20000 + 40000 * s_uniform ();
        m->cy = -20000 + 40000 * s_uniform ();
        m->phase = 2 * S_PI * s_uniform ();
        m->up_m = m->air ? 1000 + 3000 * s_uniform () : 50 * s_uniform ();
        Cgs__Entity *e = &w->msg[i];
        cgs__entity__init (e);
        cgs__enu__init (&w->pos[i]);
        cgs__enu_velocity__init (&w->vel[i]);
        cgs__entity_type__init (&w->type[i]);
        w->type[i].kind = 1;
        w->type[i].domain = m->air ? 2 : 1;
        w->type[i].country = 225;
        w->type[i].category = m->air ? 1 : 6;
        snprintf (w->marking[i], sizeof w->marking[i], "%s%05ld", m->air ? "A" : "G", i);
        e->entity_id = (uint32_t)(i + 1);
        e->marking = w->marking[i];
        e->force = CGS__FORCE__FORCE_HOSTILE;
        e->dis_type = &w->type[i];
        e->kind =
            m->air ? CGS__ENTITY_KIND__ENTITY_KIND_AIR : CGS__ENTITY_KIND__ENTITY_KIND_WHEELED;
        e->position = &w->pos[i];
        e->velocity = &w->vel[i];
        e->active = true;
    }
    return 0;
}

/* Move every entity to simulation time t_s (not timed). */
static void s_world_move (s_world_t *w, double t_s)
{
    for (long i = 0; i < w->n; i++) {
        const s_mover_t *m = &w->mv[i];
        double a = m->phase + m->w_rps * t_s, r = m->r_m, c = cos (a), s = sin (a);
        w->pos[i].east_m = m->cx + r * c;
        w->pos[i].north_m = m->cy + r * s;
        w->pos[i].up_m = m->up_m;
        double ve = -r * m->w_rps * s, vn = r * m->w_rps * c;
        w->vel[i].east_mps = ve;
        w->vel[i].north_mps = vn;
        w->vel[i].up_mps = 0;
        double hdg = atan2 (ve, vn) * 180 / S_PI;
        w->msg[i].heading_deg = hdg < 0 ? hdg + 360 : hdg;
        w->msg[i].pitch_deg = 0;
        // A coordinated turn banks atan(v w / g), right wing down turning right (w < 0).
        w->msg[i].roll_deg =
            m->air ? atan (-r * m->w_rps * fabs (m->w_rps) / 9.81) * 180 / S_PI : 0;
        w->msg[i].speed_mps = r * fabs (m->w_rps);
    }
}

/* One tick through table k: every entity's full outbound path; 0, or -1 when
 * an entity's truth, update or encoding failed. */
static int s_world_tick (s_world_t *w, int k, double t_s)
{
    gw_out_t *out = w->out[k];
    size_t queued = 0;
    uint64_t sum = 0;
    for (long i = 0; i < w->n; i++) {
        gw_truth_t truth;
        if (gw_out_truth (w->geo, &w->msg[i], &truth) < 0)
            return -1;
        gw_send_t send;
        gw_dr_t dr;
        if (gw_out_update (out, &truth, t_s, t_s, &send, &dr) < 0)
            return -1;
        w->updates[k]++;
        if (send == GW_SEND_NONE)
            continue;
        gw_espdu_t pdu;
        pdu.hdr = (gw_header_t){.version = 7, .exercise = 1, .status = GW_STATUS_LVC_CONSTRUCTIVE};
        pdu.hdr.timestamp = gw_pdu_timestamp (t_s, false);
        gw_out_fill (&truth, &dr, (gw_id_t){1, 1, (uint16_t)truth.entity_id}, &pdu);
        uint8_t *b = w->queue[queued];
        if (gw_pdu_encode_espdu (&pdu, b, GW_ESPDU_LEN) != GW_ESPDU_LEN)
            return -1;
        sum += b[30] ^ b[60];
        queued = (queued + 1) % 256;
        w->sent[k]++;
    }
    s_sink += sum;
    return 0;
}

/* o->ticks ticks of 0.1 s through both tables; entity updates per CPU second
 * of each into ret[2], or -1. */
static int s_outbound (const s_opts_t *o, s_world_t *w, double ret[2])
{
    double cpu[2] = {0, 0};
    for (int t = 0; t < o->ticks; t++) {
        s_world_move (w, w->t_s);
        for (int k = 0; k < 2; k++) {
            int kk = (t + k) % 2; // which table goes first alternates
            double t0 = bench_cpu_s ();
            if (s_world_tick (w, kk, w->t_s) < 0)
                return -1;
            cpu[kk] += bench_cpu_s () - t0;
        }
        w->t_s += 0.1;
    }
    for (int k = 0; k < 2; k++)
        ret[k] = (double)w->n * o->ticks / cpu[k];
    return 0;
}

/* ---- STANAG 4607 and Cursor on Target ------------------------------------------------------ */

#define S_4607_DWELLS 4000 // dwells a run (figure 6)
#define S_COT_BATCHES 20   // track batches a run (figure 7)

static void s_on_packet (void *arg, const uint8_t *packet, size_t len)
{
    (void)arg;
    s_sink += packet[len - 1] + len;
}

/* Figure 6: S_4607_DWELLS dwells of o->hits hits through gw_gmti; target
 * reports per CPU second, or -1. */
static double s_4607 (const s_opts_t *o, gw_gmti_t *g, uint32_t *scan)
{
    static Cgs__MtiHit hit[4096];
    static Cgs__MtiHit *hp[4096];
    static Cgs__Enu pos[4096];
    long n = o->hits;
    Cgs__Enu plat = CGS__ENU__INIT;
    plat.east_m = -6000, plat.north_m = -5200, plat.up_m = 1500;
    for (long i = 0; i < n; i++) {
        cgs__mti_hit__init (&hit[i]);
        cgs__enu__init (&pos[i]);
        hit[i].position = &pos[i];
        hit[i].range_sigma_m = 15;
        hit[i].azimuth_sigma_deg = 0.3;
        hp[i] = &hit[i];
    }
    Cgs__Mti m = CGS__MTI__INIT;
    m.uav_id = 1;
    m.platform_position = &plat;
    m.hits = hp;
    m.n_hits = (size_t)n;
    m.wrap_velocity_mps = 46.875;
    m.min_range_m = 500, m.max_range_m = 20000, m.azimuth_beamwidth_deg = 3;
    m.radial_velocity_sigma_mps = 0.2;
    double cpu = 0;
    for (int d = 0; d < S_4607_DWELLS; d++) {
        // Not timed: the dwell's hits, spread over 20 km.
        m.scan_number = *scan;
        m.dwell_number = (uint32_t)d % 120;
        m.beam_azimuth_deg = 3.0 * (d % 120);
        m.dwell_start_s = 0.0833 * d, m.dwell_end_s = m.dwell_start_s + 0.0833;
        for (long i = 0; i < n; i++) {
            pos[i].east_m = 20000 * s_uniform () - 10000;
            pos[i].north_m = 20000 * s_uniform () - 10000;
            pos[i].up_m = 300 + 200 * s_uniform ();
            hit[i].hit_id = (uint32_t)(d * n + i + 1);
            hit[i].range_m = 5000 + 10000 * s_uniform ();
            hit[i].radial_velocity_mps = 30 * s_uniform () - 15;
            hit[i].snr_db = 10 + 20 * s_uniform ();
        }
        double t0 = bench_cpu_s ();
        if (gw_gmti_on_mti (g, &m) < 0)
            return -1;
        cpu += bench_cpu_s () - t0;
    }
    (*scan)++;
    return (double)S_4607_DWELLS * (double)n / cpu;
}

typedef struct {
    bool proto;
    uint64_t events, failed;
    uint8_t buf[GW_COT_ENCODED_MAX];
} s_cot_sink_t;

static void s_on_event (void *arg, const gw_cot_event_t *e)
{
    s_cot_sink_t *k = arg;
    size_t len = k->proto ? gw_cot_encode_proto (e, k->buf, sizeof k->buf)
                          : gw_cot_encode_xml (e, (char *)k->buf, sizeof k->buf);
    if (len == 0)
        k->failed++;
    s_sink += len;
    k->events++;
}

/* Figure 7: S_COT_BATCHES batches of o->tracks tracks through gw_cotout, the
 * events encoded in the callback; events per CPU second, or -1. */
static double s_cot (const s_opts_t *o, gw_cotout_t *c, s_cot_sink_t *k, double *now)
{
    long n = o->tracks;
    Cgs__Track *tr = calloc ((size_t)n, sizeof *tr);
    Cgs__Track **tp = calloc ((size_t)n, sizeof *tp);
    Cgs__Enu *pos = calloc ((size_t)n, sizeof *pos);
    double (*cov)[16] = calloc ((size_t)n, sizeof *cov);
    if (!tr || !tp || !pos || !cov) {
        free (tr), free (tp), free (pos), free (cov);
        return -1;
    }
    for (long i = 0; i < n; i++) {
        cgs__track__init (&tr[i]);
        cgs__enu__init (&pos[i]);
        tr[i].track_id = (uint32_t)i + 1;
        tr[i].status = CGS__TRACK_STATUS__TRACK_STATUS_CONFIRMED;
        tr[i].identity = i % 5 ? CGS__TRACK_IDENTITY__TRACK_IDENTITY_UNKNOWN
                               : CGS__TRACK_IDENTITY__TRACK_IDENTITY_FRIENDLY;
        tr[i].position = &pos[i];
        cov[i][0] = 400, cov[i][5] = 900, cov[i][1] = cov[i][4] = 100;
        cov[i][10] = cov[i][15] = 4;
        tr[i].covariance = cov[i];
        tr[i].n_covariance = 16;
        tp[i] = &tr[i];
    }
    Cgs__TrackBatch b = CGS__TRACK_BATCH__INIT;
    b.tracks = tp;
    b.n_tracks = (size_t)n;
    double cpu = 0;
    uint64_t before = k->events;
    for (int r = 0; r < S_COT_BATCHES; r++) {
        for (long i = 0; i < n; i++) { // not timed
            pos[i].east_m = 20000 * s_uniform () - 10000;
            pos[i].north_m = 20000 * s_uniform () - 10000;
            pos[i].up_m = 300 + 200 * s_uniform ();
            tr[i].heading_deg = 360 * s_uniform ();
            tr[i].speed_mps = 15 * s_uniform ();
        }
        *now += 1.0;
        double t0 = bench_cpu_s ();
        gw_cotout_on_tracks (c, &b, *now);
        cpu += bench_cpu_s () - t0;
    }
    free (tr), free (tp), free (pos), free (cov);
    return (double)(k->events - before) / cpu;
}

/* ---- main ---------------------------------------------------------------------------------- */

static void s_usage (FILE *f)
{
    fprintf (f,
             "usage: bench_gateway [options]\n"
             "  --runs R        runs of each figure; medians, min and max over them (default 5)\n"
             "  --pdus N        PDUs encoded, and PDUs decoded, per run (default 2000000)\n"
             "  --send-pdus N   PDUs encoded and sent per run (default 300000)\n"
             "  --batch B       PDUs per sendmmsg call (default 64)\n"
             "  --entities N    outbound entities (default 10000)\n"
             "  --ticks T       timed 10 Hz ticks of the outbound entities per run (default 20)\n"
             "  --hits H        hits a dwell for the STANAG 4607 figure (default 20, up to 4096)\n"
             "  --tracks N      tracks a batch for the Cursor on Target figures (default 1000)\n"
             "Other options that take a value (meant for other benchmarks) are ignored.\n");
}

static void s_print (const char *what, const s_fig_t *f, const char *unit, double goal)
{
    printf ("  %-44s median %12.0f %s (min %.0f, max %.0f)", what, f->median, unit, f->min, f->max);
    if (goal > 0)
        printf (": goal %.0f/s %s\n", goal, f->median >= goal ? "met" : "NOT met");
    else
        printf (": no goal\n");
}

static void s_keys (const char *key, const s_fig_t *f)
{
    printf ("%s=%.0f\n%s_min=%.0f\n%s_max=%.0f\n", key, f->median, key, f->min, key, f->max);
}

int main (int argc, char **argv)
{
    s_opts_t o = {.runs = 5,
                  .pdus = 2000000,
                  .send_pdus = 300000,
                  .batch = 64,
                  .entities = 10000,
                  .ticks = 20,
                  .hits = 20,
                  .tracks = 1000};
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        if (!strcmp (a, "--help") || !strcmp (a, "-h")) {
            s_usage (stdout);
            return 0;
        }
        long n = 0;
        bool ok = true;
        if (!strcmp (a, "--runs") && (ok = bench_parse_long (v, 1, S_MAX_RUNS, &n)))
            o.runs = (int)n;
        else if (!strcmp (a, "--pdus"))
            ok = bench_parse_long (v, 1, 1000000000, &o.pdus);
        else if (!strcmp (a, "--send-pdus"))
            ok = bench_parse_long (v, 1, 1000000000, &o.send_pdus);
        else if (!strcmp (a, "--batch") && (ok = bench_parse_long (v, 1, S_MAX_BATCH, &n)))
            o.batch = (int)n;
        else if (!strcmp (a, "--entities"))
            ok = bench_parse_long (v, 1, 65000, &o.entities);
        else if (!strcmp (a, "--ticks") && (ok = bench_parse_long (v, 1, 100000, &n)))
            o.ticks = (int)n;
        else if (!strcmp (a, "--hits"))
            ok = bench_parse_long (v, 1, 4096, &o.hits);
        else if (!strcmp (a, "--tracks"))
            ok = bench_parse_long (v, 1, 100000, &o.tracks);
        else if (strncmp (a, "--", 2) != 0 || !v)
            ok = false; // not an option, or one without its value
        if (!ok) {
            fprintf (stderr, "bench_gateway: bad option or value: %s %s\n", a, v ? v : "");
            s_usage (stderr);
            return 2;
        }
        i++; // every option takes a value
    }
    signal (SIGPIPE, SIG_IGN);

    int cpus[2] = {-1, -1};
    int ncpus = s_cpus (cpus, 2);
    if (ncpus > 0)
        s_pin (cpus[0]);
    long cores = sysconf (_SC_NPROCESSORS_ONLN);

    char err[256] = "";
    bool broke = false;
    s_sender_t snd;
    s_dgrams_t dg = {0};
    s_world_t world;
    uint8_t (*bufs)[GW_ESPDU_LEN] = calloc (S_MAX_BATCH, sizeof *bufs);
    int wrc = s_world_new (&world, o.entities);
    if (!bufs || wrc < 0 || s_dgrams_new (&dg) < 0) {
        fprintf (stderr, "bench_gateway: out of memory, or the exercise frame or the decode "
                         "buffer could not be made\n");
        free (bufs);
        s_dgrams_free (&dg);
        s_world_free (&world);
        return 1;
    }
    if (s_sender_open (&snd, cpus, ncpus, err, sizeof err) < 0) {
        printf ("bench_gateway: FAILED to set up the sockets: %s\n", err);
        broke = true;
    }

    printf ("bench_gateway: %ld cores online; pinned to cpu %d; the drain on %s; %d runs of each "
            "figure\n",
            cores, cpus[0], snd.drain_cpu >= 0 ? "another core" : "the same core (only one)",
            o.runs);
    if (!broke)
        printf ("  send: %ld Entity State PDUs (v7, %d bytes) a run, %d per sendmmsg, to "
                "127.0.0.1:%u (the drain's socket, receive buffer %d bytes)\n",
                o.send_pdus, GW_ESPDU_LEN, o.batch, ntohs (snd.to.sin_port), snd.rcvbuf);
    printf ("  encode and decode: %ld PDUs a run; decode buffer %d PDUs (versions 4-7) in %zu "
            "datagrams of 1-4\n",
            o.pdus, S_DECODE_PDUS, dg.ndgram);
    printf ("  outbound: %ld entities (half ground, half air), %d ticks of 0.1 s a run\n",
            o.entities, o.ticks);
    fflush (stdout);

    // Warm-up: the first tick sends every entity (never sent), the second
    // gives the aircraft a previous state; caches and the drain get going.
    uint64_t next = 1;
    size_t cursor = 0;
    s_world_move (&world, world.t_s);
    if (s_world_tick (&world, 0, world.t_s) < 0 || s_world_tick (&world, 1, world.t_s) < 0) {
        snprintf (err, sizeof err, "an outbound entity failed (truth, update or encode)");
        broke = true;
    }
    world.t_s += 0.1;
    world.sent[0] = world.sent[1] = world.updates[0] = world.updates[1] = 0;

    // The translators, as the default exercise's parameters have them.
    gw_params_t gp;
    gw_params_defaults (&gp);
    gp.s4607_file = true;
    static s_cot_sink_t cot_xml = {.proto = false}, cot_proto = {.proto = true};
    gw_gmti_t *gmti = gw_gmti_new (&gp, world.geo, 1, s_on_packet, NULL);
    gw_cotout_t *cx = gw_cotout_new (&gp, world.geo, 1, s_on_event, &cot_xml);
    gw_cotout_t *cp = gw_cotout_new (&gp, world.geo, 1, s_on_event, &cot_proto);
    if (!gmti || !cx || !cp) {
        snprintf (err, sizeof err, "out of memory for the translators");
        broke = true;
    }
    uint32_t scan = 1;
    double now_x = 1.8e9, now_p = 1.8e9;
    printf ("  STANAG 4607: %d dwells of %ld hits a run; CoT: %d batches of %ld tracks a run\n",
            S_4607_DWELLS, o.hits, S_COT_BATCHES, o.tracks);
    s_fig_t send = {0}, enc = {0}, dec = {0}, outb = {0}, outb_all = {0}, f4607 = {0}, fxml = {0},
            fproto = {0};
    uint64_t sent_total = 0, got[2] = {0, 0};
    for (int r = 0; r < o.runs && !broke; r++) {
        double v = s_encode (&o, bufs, &next);
        if (v < 0) {
            snprintf (err, sizeof err, "an Entity State PDU did not encode");
            broke = true;
            break;
        }
        s_fig_add (&enc, v);
        v = s_send (&o, &snd, bufs, &next, err, sizeof err);
        if (v < 0) {
            broke = true;
            break;
        }
        sent_total += (uint64_t)o.send_pdus;
        s_fig_add (&send, v);
        v = s_decode (&o, &dg, &cursor);
        if (v < 0) {
            snprintf (err, sizeof err, "a prepared PDU did not walk or decode");
            broke = true;
            break;
        }
        s_fig_add (&dec, v);
        double ob[2];
        if (s_outbound (&o, &world, ob) < 0) {
            snprintf (err, sizeof err, "an outbound entity failed (truth, update or encode)");
            broke = true;
            break;
        }
        s_fig_add (&outb, ob[0]);
        s_fig_add (&outb_all, ob[1]);
        double r4607 = s_4607 (&o, gmti, &scan);
        double rx = s_cot (&o, cx, &cot_xml, &now_x);
        double rp = s_cot (&o, cp, &cot_proto, &now_p);
        if (r4607 < 0 || rx < 0 || rp < 0 || cot_xml.failed || cot_proto.failed) {
            snprintf (err, sizeof err, "a dwell or a CoT event did not encode");
            broke = true;
            break;
        }
        s_fig_add (&f4607, r4607);
        s_fig_add (&fxml, rx);
        s_fig_add (&fproto, rp);
    }
    const gw_gmti_stats_t *gs = gmti ? gw_gmti_stats (gmti) : NULL;
    if (!broke && s_sender_count (&snd, got) < 0) {
        snprintf (err, sizeof err, "no count from the drain");
        broke = true;
    }
    if (!broke && got[0] == 0) {
        snprintf (err, sizeof err, "the drain received nothing of %llu PDUs sent",
                  (unsigned long long)sent_total);
        broke = true;
    }
    if (!broke && got[1] > 0) {
        snprintf (err, sizeof err,
                  "the drain received %llu datagrams that were not one Entity "
                  "State PDU",
                  (unsigned long long)got[1]);
        broke = true;
    }
    if (s_sender_close (&snd) < 0 && !broke) {
        snprintf (err, sizeof err, "the drain process failed");
        broke = true;
    }

    if (!broke) {
        s_fig_done (&send);
        s_fig_done (&enc);
        s_fig_done (&dec);
        s_fig_done (&outb);
        s_fig_done (&outb_all);
        s_fig_done (&f4607);
        s_fig_done (&fxml);
        s_fig_done (&fproto);
        double share = world.updates[0] ? (double)world.sent[0] / (double)world.updates[0] : 0;
        printf ("\n");
        s_print ("Entity State PDUs encoded and sent", &send, "PDUs/s", S_GOAL_SEND_PER_S);
        if (got[0] < sent_total)
            printf ("    (the drain received %llu of %llu sent; the rest dropped at its full "
                    "receive buffer: UDP is lossy, not a failure)\n",
                    (unsigned long long)got[0], (unsigned long long)sent_total);
        else
            printf ("    (the drain received all %llu sent)\n", (unsigned long long)sent_total);
        s_print ("Entity State PDUs encoded only", &enc, "PDUs/s", 0);
        s_print ("Entity State PDUs walked and decoded", &dec, "PDUs/s", S_GOAL_DECODE_PER_S);
        s_print ("outbound entity updates, default thresholds", &outb, "upd/s", 0);
        printf ("    (%.1f%% of updates sent a PDU; for reference %ld entities at 10 Hz are "
                "%.0f updates/s: %s)\n",
                100 * share, o.entities, (double)o.entities * 10,
                outb.median >= (double)o.entities * 10 ? "kept up with" : "NOT kept up with");
        s_print ("outbound entity updates, every one sends", &outb_all, "upd/s", 0);
        if (outb_all.median > 0 && outb.median > 0)
            printf ("    (%.2f us an update that sends, %.2f us one at the default thresholds)\n",
                    1e6 / outb_all.median, 1e6 / outb.median);

        s_print ("STANAG 4607 target reports (gw_gmti)", &f4607, "rpt/s", 0);
        printf ("    (%.2f us a report with its share of the dwell segment; %llu packets, %llu "
                "reports in all)\n",
                1e6 / f4607.median, (unsigned long long)gs->packets,
                (unsigned long long)gs->reports);
        s_print ("CoT track events, XML (gw_cotout)", &fxml, "evt/s", 0);
        s_print ("CoT track events, TAK protobuf", &fproto, "evt/s", 0);
        printf ("    (%.2f us an XML event, %.2f us a protobuf one)\n", 1e6 / fxml.median,
                1e6 / fproto.median);
        printf ("\n--- figures ---\n");
        printf ("cores=%ld\nruns=%d\nsend_pdus_per_run=%ld\nbatch=%d\npdus_per_run=%ld\n"
                "entities=%ld\nticks_per_run=%d\n",
                cores, o.runs, o.send_pdus, o.batch, o.pdus, o.entities, o.ticks);
        s_keys ("gateway_espdu_send_per_s", &send);
        printf ("gateway_espdu_send_received=%llu\ngateway_espdu_send_sent=%llu\n",
                (unsigned long long)got[0], (unsigned long long)sent_total);
        s_keys ("gateway_espdu_encode_per_s", &enc);
        s_keys ("gateway_espdu_decode_per_s", &dec);
        s_keys ("gateway_outbound_updates_per_s", &outb);
        printf ("gateway_outbound_send_share=%.4f\n", share);
        s_keys ("gateway_outbound_all_send_updates_per_s", &outb_all);
        s_keys ("gateway_s4607_reports_per_s", &f4607);
        printf ("s4607_hits_per_dwell=%ld\n", o.hits);
        s_keys ("gateway_cot_xml_events_per_s", &fxml);
        s_keys ("gateway_cot_proto_events_per_s", &fproto);
        printf ("goal_espdu_send_per_s=%.0f\ngoal_espdu_decode_per_s=%.0f\n", S_GOAL_SEND_PER_S,
                S_GOAL_DECODE_PER_S);
        bool send_ok = send.median >= S_GOAL_SEND_PER_S, dec_ok = dec.median >= S_GOAL_DECODE_PER_S;
        printf ("verdict=%s\n", send_ok && dec_ok ? "PASS" : "BELOW-GOAL");
        printf ("  (send goal %s, decode goal %s)\n", send_ok ? "met" : "NOT met",
                dec_ok ? "met" : "NOT met");
    } else {
        printf ("\n--- figures ---\nverdict=FAIL (%s)\n", err);
    }
    gw_gmti_destroy (&gmti);
    gw_cotout_destroy (&cx);
    gw_cotout_destroy (&cp);
    free (bufs);
    s_dgrams_free (&dg);
    s_world_free (&world);
    return broke ? 1 : 0;
}
