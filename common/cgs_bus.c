/* cgs_bus — ZeroMQ publisher and subscriber with stamped headers and
 * sequence-gap counting. */
#include "cgs_bus.h"
#include "cgs_topics.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/random.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>
#include <zmq.h>

#define S_SOURCE_MAX 64

double cgs_bus_wall_time (void)
{
    struct timespec ts;
    clock_gettime (CLOCK_REALTIME, &ts);
    return (double)ts.tv_sec + ts.tv_nsec * 1e-9;
}

static int s_mkdir_p (const char *dir)
{
    char tmp[4096];
    size_t n = strlen (dir);
    if (n == 0 || n >= sizeof tmp)
        return n ? -ENAMETOOLONG : 0;
    memcpy (tmp, dir, n + 1);
    for (char *p = tmp + 1; *p; p++) {
        if (*p == '/') {
            *p = '\0';
            if (mkdir (tmp, 0755) < 0 && errno != EEXIST)
                return -errno;
            *p = '/';
        }
    }
    if (mkdir (tmp, 0755) < 0 && errno != EEXIST)
        return -errno;
    return 0;
}

int cgs_bus_prepare_endpoint (const char *endpoint)
{
    if (strncmp (endpoint, "ipc://", 6) != 0)
        return 0;
    const char *path = endpoint + 6;
    const char *slash = strrchr (path, '/');
    if (!slash || slash == path || path[0] == '@')
        return 0; // no folder, or an abstract socket
    char dir[4096];
    size_t n = (size_t)(slash - path);
    if (n >= sizeof dir)
        return -ENAMETOOLONG;
    memcpy (dir, path, n);
    dir[n] = '\0';
    return s_mkdir_p (dir);
}

/* ---- liveness -------------------------------------------------------------------
 * Without these options a tcp:// connection whose network goes silent (a
 * cable pulled, a switch, a route or a host down: nothing tells either end)
 * stays "connected" to ZeroMQ for as long as TCP keeps retransmitting into
 * the void (about 15 minutes), backing off exponentially (0.2, 0.4, 0.8 ...
 * s), and a reconnect whose SYN was lost waits for the kernel's SYN retries
 * (1, 3, 7, 15 ... s after it started). So after a cut of 10 s traffic came
 * back only at the next retransmission, 3 to 7 s after the network did
 * (tests/integration/hosts.sh: 6.3 s). With them both ends drop a silent
 * connection after 3 s, the connecting end tries a fresh one about once a
 * second, and the first one after the network returns gets through: traffic
 * resumes within about a second of it.
 *
 * The checks are the kernel's (TCP keepalive, TCP_USER_TIMEOUT), not
 * ZeroMQ's heartbeats (ZMQ_HEARTBEAT_IVL, _TIMEOUT, _TTL): a subscriber whose
 * receive queue is full stops reading its socket, so it cannot see the
 * publisher's PINGs, its heartbeat times out, and libzmq (4.3.4, and master
 * at the time of writing: zeromq/libzmq#3937) then aborts the process on an
 * assertion (`_input_stopped`, stream_engine_base.cpp) when it reconnects. A
 * subscriber held 8 s in its handler during a burst did exactly that. The
 * kernel answers keepalives whatever the process does.
 *
 * All options exist since libzmq 4.2 (Debian 12 has 4.3.4); ipc:// and
 * inproc:// ignore the tcp ones. */

/* Keepalive probes once a connection has received nothing for 1 s, then
 * every second: the end that only listens (a subscriber, which sends nothing
 * after its subscriptions) finds a silent network this way. On a busy
 * connection nothing is sent: the traffic itself shows the peer is there. */
#define S_KEEPALIVE_IDLE_S  1
#define S_KEEPALIVE_INTVL_S 1
#define S_KEEPALIVE_CNT     3 // unanswered probes that end it (the user timeout below comes first)
/* TCP_USER_TIMEOUT: a connection is dead once what it sent (data, or the
 * keepalive probes above) has stayed unacknowledged for 3 s; this also ends
 * the keepalive probing at 3 s of silence. The end that sends (a publisher)
 * finds a silent network this way, where keepalives do not help (they are
 * not sent while data is in flight). It also ends a connection whose peer
 * has advertised a zero window for 3 s (Linux >= 5.11): a subscriber whose
 * receive queue stayed full that long, already losing messages at its
 * high-water mark, is dropped and reconnects at once, and what the publisher
 * had queued for it counts as gaps. Far above any acknowledgement delay of
 * a healthy network (a LAN's are well under a millisecond). */
#define S_TCP_USER_TIMEOUT_MS 3000
/* A connect whose SYN (or SYN-ACK) was lost gives up after 1.5 s instead of
 * waiting for the kernel's SYN retries (3, 7, 15 ... s after it started),
 * and a fresh attempt follows. 1.5 s lets the kernel's first retry (at 1 s)
 * go out first, so while the peer is unreachable a SYN leaves at least once
 * a second (at 0 and 1 s, then 0.1 to 0.2 s after the 1.5 s timeout, ...),
 * and the first after the network returns gets through; with 1 s the
 * kernel's retry raced the timeout and the gaps were up to 1.2 s. A LAN's
 * connect takes well under a millisecond; 1.5 s also covers a loaded or
 * long-haul link. */
#define S_CONNECT_TIMEOUT_MS 1500
/* The next attempt 100 to 200 ms (libzmq adds up to one interval at random)
 * after a failed or lost connection: libzmq's default, set here because the
 * recovery time depends on it. No ZMQ_RECONNECT_IVL_MAX: a back-off would add
 * up to its maximum to the recovery after a long outage, to save one SYN a
 * second per peer that is down. */
#define S_RECONNECT_IVL_MS 100

int cgs_bus_set_liveness (void *socket)
{
    static const struct {
        int option, value;
    } opts[] = {
        {ZMQ_TCP_KEEPALIVE, 1},
        {ZMQ_TCP_KEEPALIVE_IDLE, S_KEEPALIVE_IDLE_S},
        {ZMQ_TCP_KEEPALIVE_INTVL, S_KEEPALIVE_INTVL_S},
        {ZMQ_TCP_KEEPALIVE_CNT, S_KEEPALIVE_CNT},
        {ZMQ_TCP_MAXRT, S_TCP_USER_TIMEOUT_MS}, // TCP_USER_TIMEOUT on Linux
        {ZMQ_CONNECT_TIMEOUT, S_CONNECT_TIMEOUT_MS},
        {ZMQ_RECONNECT_IVL, S_RECONNECT_IVL_MS},
    };
    for (size_t i = 0; i < sizeof opts / sizeof opts[0]; i++)
        if (zmq_setsockopt (socket, opts[i].option, &opts[i].value, sizeof opts[i].value) < 0)
            return -zmq_errno ();
    return 0;
}

int cgs_bus_set_multicast (void *socket, int rate_kbps, int recovery_ms, int hops)
{
    const int opts[][2] = {
        {ZMQ_RATE, rate_kbps},
        {ZMQ_RECOVERY_IVL, recovery_ms},
        {ZMQ_MULTICAST_HOPS, hops},
    };
    for (size_t i = 0; i < sizeof opts / sizeof opts[0]; i++)
        if (zmq_setsockopt (socket, opts[i][0], &opts[i][1], sizeof opts[i][1]) < 0)
            return -zmq_errno ();
    return 0;
}

/* A new epoch: 32 random bits (a short varint on the wire; two starts of one
 * publisher share an epoch with odds of one in four billion). */
static uint64_t s_new_epoch (void)
{
    uint32_t r = 0;
    if (getrandom (&r, sizeof r, 0) != (ssize_t)sizeof r) {
        struct timespec ts;
        clock_gettime (CLOCK_REALTIME, &ts);
        r = (uint32_t)ts.tv_nsec ^ (uint32_t)ts.tv_sec ^ ((uint32_t)getpid () << 16);
    }
    return r ? r : 1;
}

/* ---- publisher ------------------------------------------------------------------ */

typedef struct {
    cgs_topic_stats_t stats;
    uint64_t seq;                           // last sequence number sent
    const ProtobufCMessageDescriptor *desc; // the catalogue's type for it, NULL if none
} s_pub_topic_t;

struct cgs_pub {
    void *socket;
    char source[S_SOURCE_MAX];
    uint32_t exercise_id;
    uint64_t epoch;
    int block_ms; // wait for room at the HWM, 0 = drop
    s_pub_topic_t *topics;
    size_t ntopics, captopics;
    size_t last;  // index of the last topic used (cache)
    uint8_t *buf; // encode buffer, grown as needed
    size_t bufcap;
    cgs_seal_key_t *seal; // the group key, NULL: in the clear
    uint8_t *sbuf;        // sealing buffer, grown as needed
    size_t sbufcap;
    uint64_t sent, drops;
};

cgs_pub_t *cgs_pub_new (void *ctx, const char *source, uint32_t exercise_id)
{
    cgs_pub_t *self = calloc (1, sizeof *self);
    if (!self)
        return NULL;
    snprintf (self->source, sizeof self->source, "%s", source ? source : "");
    self->exercise_id = exercise_id;
    self->epoch = s_new_epoch ();
    self->socket = zmq_socket (ctx, ZMQ_PUB);
    if (!self->socket)
        goto fail;
    int linger = 0;
    zmq_setsockopt (self->socket, ZMQ_LINGER, &linger, sizeof linger);
    int rc = cgs_bus_set_liveness (self->socket);
    if (rc < 0) {
        errno = -rc;
        goto fail;
    }
    cgs_pub_set_hwm (self, CGS_BUS_DEFAULT_SNDHWM);
    self->bufcap = 4096;
    self->buf = malloc (self->bufcap);
    if (!self->buf)
        goto fail;
    return self;
fail:;
    int saved = errno;
    cgs_pub_destroy (&self);
    errno = saved;
    return NULL;
}

void cgs_pub_destroy (cgs_pub_t **self_p)
{
    if (!self_p || !*self_p)
        return;
    cgs_pub_t *self = *self_p;
    if (self->socket)
        zmq_close (self->socket);
    free (self->topics);
    free (self->buf);
    free (self->sbuf);
    if (self->seal)
        explicit_bzero (self->seal, sizeof *self->seal);
    free (self->seal);
    free (self);
    *self_p = NULL;
}

/* A copy of key in *slot (freed and cleared when key is NULL); 0 or -ENOMEM. */
static int s_set_key (cgs_seal_key_t **slot, const cgs_seal_key_t *key)
{
    if (!key) {
        if (*slot)
            explicit_bzero (*slot, sizeof **slot);
        free (*slot);
        *slot = NULL;
        return 0;
    }
    if (!*slot && !(*slot = malloc (sizeof **slot)))
        return -ENOMEM;
    **slot = *key;
    return 0;
}

/* Grow *buf to at least n bytes; 0 or -ENOMEM. */
static int s_grow (uint8_t **buf, size_t *cap, size_t n)
{
    if (n <= *cap)
        return 0;
    size_t c = *cap ? *cap : 4096;
    while (c < n)
        c *= 2;
    uint8_t *b = realloc (*buf, c);
    if (!b)
        return -ENOMEM;
    *buf = b;
    *cap = c;
    return 0;
}

int cgs_pub_set_seal (cgs_pub_t *self, const cgs_seal_key_t *key)
{
    return s_set_key (&self->seal, key);
}

void cgs_pub_set_hwm (cgs_pub_t *self, int messages)
{
    zmq_setsockopt (self->socket, ZMQ_SNDHWM, &messages, sizeof messages);
}

void cgs_pub_set_block (cgs_pub_t *self, int timeout_ms)
{
    // Blocking mode refuses at the HWM instead of dropping for one subscriber,
    // so the wait (and a drop after it) applies to every subscriber at once.
    int nodrop = timeout_ms > 0;
    zmq_setsockopt (self->socket, ZMQ_XPUB_NODROP, &nodrop, sizeof nodrop);
    if (timeout_ms > 0)
        zmq_setsockopt (self->socket, ZMQ_SNDTIMEO, &timeout_ms, sizeof timeout_ms);
    self->block_ms = timeout_ms;
}

int cgs_pub_bind (cgs_pub_t *self, const char *endpoint)
{
    int rc = cgs_bus_prepare_endpoint (endpoint);
    if (rc < 0)
        return rc;
    if (zmq_bind (self->socket, endpoint) < 0)
        return -zmq_errno ();
    return 0;
}

uint64_t cgs_pub_epoch (const cgs_pub_t *self)
{
    return self->epoch;
}
void *cgs_pub_socket (cgs_pub_t *self)
{
    return self->socket;
}
size_t cgs_pub_topic_count (const cgs_pub_t *self)
{
    return self->ntopics;
}
const cgs_topic_stats_t *cgs_pub_topic_stats (const cgs_pub_t *self, size_t i)
{
    return i < self->ntopics ? &self->topics[i].stats : NULL;
}
uint64_t cgs_pub_sent (const cgs_pub_t *self)
{
    return self->sent;
}
uint64_t cgs_pub_drops (const cgs_pub_t *self)
{
    return self->drops;
}

static s_pub_topic_t *s_pub_topic (cgs_pub_t *self, const char *topic)
{
    if (self->last < self->ntopics && strcmp (self->topics[self->last].stats.topic, topic) == 0)
        return &self->topics[self->last];
    for (size_t i = 0; i < self->ntopics; i++)
        if (strcmp (self->topics[i].stats.topic, topic) == 0) {
            self->last = i;
            return &self->topics[i];
        }
    if (strlen (topic) >= CGS_TOPIC_MAX || !*topic)
        return NULL;
    if (self->ntopics == self->captopics) {
        size_t cap = self->captopics ? self->captopics * 2 : 8;
        s_pub_topic_t *t = realloc (self->topics, cap * sizeof *t);
        if (!t)
            return NULL;
        self->topics = t;
        self->captopics = cap;
    }
    s_pub_topic_t *t = &self->topics[self->ntopics];
    memset (t, 0, sizeof *t);
    snprintf (t->stats.topic, sizeof t->stats.topic, "%s", topic);
    const cgs_topic_t *known = cgs_topics_find (topic);
    t->desc = known ? known->message : NULL;
    self->last = self->ntopics++;
    return t;
}

/* Encode msg under header h (sealed when the publisher seals) and send it
 * on topic t. */
static int s_pub_emit (cgs_pub_t *self, s_pub_topic_t *t, const char *topic, ProtobufCMessage *msg,
                       const Cgs__Header *h)
{
    size_t len = 0;
    int rc = cgs_msg_encode_stamped_grow (msg, h, &self->buf, &self->bufcap, &len);
    if (rc < 0)
        return rc;
    const uint8_t *out = self->buf;
    if (self->seal) {
        cgs_seal_header_t sh = {.exercise_id = h->exercise_id,
                                .epoch = h->epoch,
                                .seq = h->seq,
                                .wall_time_s = h->wall_time_s};
        snprintf (sh.source, sizeof sh.source, "%s", h->source ? h->source : "");
        size_t sealed = 0;
        if ((rc = s_grow (&self->sbuf, &self->sbufcap, cgs_seal_size (len, sh.source))) < 0 ||
            (rc = cgs_seal (self->seal, topic, &sh, self->buf, len, self->sbuf, self->sbufcap,
                            &sealed)) < 0)
            return rc;
        out = self->sbuf;
        len = sealed;
    }

    size_t tlen = strlen (topic);
    int flags = self->block_ms > 0 ? 0 : ZMQ_DONTWAIT;
    if (zmq_send (self->socket, topic, tlen, flags | ZMQ_SNDMORE) < 0) {
        int e = zmq_errno ();
        if (e == EAGAIN) {
            t->stats.drops++;
            self->drops++;
        }
        return -e;
    }
    // The first frame was accepted, so the rest of the message will be too.
    if (zmq_send (self->socket, out, len, 0) < 0)
        return -zmq_errno ();
    t->stats.messages++;
    self->sent++;
    return 0;
}

/* The topic's entry for a message of msg's type; NULL and *rc when refused. */
static s_pub_topic_t *s_pub_topic_for (cgs_pub_t *self, const char *topic,
                                       const ProtobufCMessage *msg, int *rc)
{
    s_pub_topic_t *t = s_pub_topic (self, topic);
    if (!t)
        *rc = strlen (topic) >= CGS_TOPIC_MAX || !*topic ? -EINVAL : -ENOMEM;
    else if (t->desc && msg->descriptor != t->desc)
        *rc = -EINVAL; // a catalogue topic carries only its own type
    return t && *rc == 0 ? t : NULL;
}

int cgs_pub_send (cgs_pub_t *self, const char *topic, ProtobufCMessage *msg, double sim_time_s)
{
    if (!cgs_msg_header_slot (msg))
        return -EINVAL;
    int rc = 0;
    s_pub_topic_t *t = s_pub_topic_for (self, topic, msg, &rc);
    if (!t)
        return rc;
    Cgs__Header h = CGS__HEADER__INIT;
    h.source = self->source;
    h.exercise_id = self->exercise_id;
    h.epoch = self->epoch;
    h.seq = ++t->seq; // a dropped message keeps its number: subscribers see the gap
    h.sim_time_s = sim_time_s;
    h.wall_time_s = cgs_bus_wall_time ();
    return s_pub_emit (self, t, topic, msg, &h);
}

int cgs_pub_forward (cgs_pub_t *self, const char *topic, ProtobufCMessage *msg, uint64_t epoch_xor)
{
    Cgs__Header **slot = cgs_msg_header_slot (msg);
    if (!slot || !*slot)
        return -EINVAL;
    int rc = 0;
    s_pub_topic_t *t = s_pub_topic_for (self, topic, msg, &rc);
    if (!t)
        return rc;
    Cgs__Header h = **slot;
    h.exercise_id = self->exercise_id;
    h.epoch ^= epoch_xor;
    if (h.seq > t->seq)
        t->seq = h.seq;
    return s_pub_emit (self, t, topic, msg, &h);
}

/* ---- subscriber ----------------------------------------------------------------- */

#define S_RETIRED 4 // epochs a source has left, remembered to refuse their replay

typedef struct {
    char source[S_SOURCE_MAX];
    uint64_t epoch;
    uint64_t seq;
    uint64_t retired[S_RETIRED]; // epochs it has left, newest at retired[(nretired-1) % S_RETIRED]
    size_t nretired;
} s_source_t;

typedef struct {
    cgs_topic_stats_t stats;
    size_t tlen;
    const ProtobufCMessageDescriptor *desc;
    cgs_sub_fn *fn;
    void *arg;
    s_source_t *sources;
    size_t nsources, capsources;
    size_t last; // index of the last source seen (cache)
} s_sub_topic_t;

struct cgs_sub {
    void *socket;
    s_sub_topic_t *topics;
    size_t ntopics, captopics;
    cgs_msg_arena_t *arena;
    uint32_t exercise_id; // accept only this exercise's messages; 0: any
    Cgs__Header hdr;      // header of the message being handled
    char hdr_source[S_SOURCE_MAX];
    uint64_t received, malformed_unrouted;
    cgs_seal_key_t *seal;   // the group key: only sealed payloads; NULL: only clear ones
    double replay_window_s; // sealed: refuse what was sent longer ago than this (0: no limit)
    uint8_t *obuf;          // opened payloads, grown as needed
    size_t obufcap;
};

cgs_sub_t *cgs_sub_new (void *ctx)
{
    cgs_sub_t *self = calloc (1, sizeof *self);
    if (!self)
        return NULL;
    self->socket = zmq_socket (ctx, ZMQ_SUB);
    if (!self->socket)
        goto fail;
    int linger = 0;
    zmq_setsockopt (self->socket, ZMQ_LINGER, &linger, sizeof linger);
    int rc = cgs_bus_set_liveness (self->socket);
    if (rc < 0) {
        errno = -rc;
        goto fail;
    }
    cgs_sub_set_hwm (self, CGS_BUS_DEFAULT_RCVHWM);
    self->arena = cgs_msg_arena_new (64 * 1024);
    if (!self->arena)
        goto fail;
    return self;
fail:;
    int saved = errno;
    cgs_sub_destroy (&self);
    errno = saved ? saved : ENOMEM;
    return NULL;
}

void cgs_sub_destroy (cgs_sub_t **self_p)
{
    if (!self_p || !*self_p)
        return;
    cgs_sub_t *self = *self_p;
    if (self->socket)
        zmq_close (self->socket);
    for (size_t i = 0; i < self->ntopics; i++)
        free (self->topics[i].sources);
    free (self->topics);
    cgs_msg_arena_destroy (&self->arena);
    s_set_key (&self->seal, NULL);
    free (self->obuf);
    free (self);
    *self_p = NULL;
}

void cgs_sub_set_hwm (cgs_sub_t *self, int messages)
{
    zmq_setsockopt (self->socket, ZMQ_RCVHWM, &messages, sizeof messages);
}

void cgs_sub_set_exercise (cgs_sub_t *self, uint32_t exercise_id)
{
    self->exercise_id = exercise_id;
}

uint64_t cgs_sub_foreign (const cgs_sub_t *self)
{
    uint64_t n = 0;
    for (size_t i = 0; i < self->ntopics; i++)
        n += self->topics[i].stats.foreign;
    return n;
}

int cgs_sub_set_seal (cgs_sub_t *self, const cgs_seal_key_t *key, double replay_window_s)
{
    self->replay_window_s = replay_window_s > 0 ? replay_window_s : 0;
    return s_set_key (&self->seal, key);
}

int cgs_sub_connect (cgs_sub_t *self, const char *endpoint)
{
    if (zmq_connect (self->socket, endpoint) < 0)
        return -zmq_errno ();
    return 0;
}

int cgs_sub_on_type (cgs_sub_t *self, const char *topic, const ProtobufCMessageDescriptor *desc,
                     cgs_sub_fn *fn, void *arg)
{
    if (!topic || !*topic || strlen (topic) >= CGS_TOPIC_MAX || !desc || !fn)
        return -EINVAL;
    for (size_t i = 0; i < self->ntopics; i++)
        if (strcmp (self->topics[i].stats.topic, topic) == 0)
            return -EEXIST;
    if (self->ntopics == self->captopics) {
        size_t cap = self->captopics ? self->captopics * 2 : 8;
        s_sub_topic_t *t = realloc (self->topics, cap * sizeof *t);
        if (!t)
            return -ENOMEM;
        self->topics = t;
        self->captopics = cap;
    }
    s_sub_topic_t *t = &self->topics[self->ntopics];
    memset (t, 0, sizeof *t);
    snprintf (t->stats.topic, sizeof t->stats.topic, "%s", topic);
    t->tlen = strlen (topic);
    t->desc = desc;
    t->fn = fn;
    t->arg = arg;
    // ZeroMQ filters by prefix: "mti" also lets "mti.scan" through, which
    // dispatch then matches exactly.
    if (zmq_setsockopt (self->socket, ZMQ_SUBSCRIBE, topic, t->tlen) < 0)
        return -zmq_errno ();
    self->ntopics++;
    return 0;
}

int cgs_sub_on (cgs_sub_t *self, const char *topic, cgs_sub_fn *fn, void *arg)
{
    const cgs_topic_t *t = cgs_topics_find (topic);
    if (!t)
        return -ENOENT;
    return cgs_sub_on_type (self, topic, t->message, fn, arg);
}

void *cgs_sub_socket (cgs_sub_t *self)
{
    return self->socket;
}
size_t cgs_sub_topic_count (const cgs_sub_t *self)
{
    return self->ntopics;
}
const cgs_topic_stats_t *cgs_sub_topic_stats (const cgs_sub_t *self, size_t i)
{
    return i < self->ntopics ? &self->topics[i].stats : NULL;
}
uint64_t cgs_sub_received (const cgs_sub_t *self)
{
    return self->received;
}

#define S_SUM(field)                                                                               \
    uint64_t n = 0;                                                                                \
    for (size_t i = 0; i < self->ntopics; i++)                                                     \
        n += self->topics[i].stats.field;                                                          \
    return n

uint64_t cgs_sub_gaps (const cgs_sub_t *self)
{
    S_SUM (gaps);
}
uint64_t cgs_sub_restarts (const cgs_sub_t *self)
{
    S_SUM (restarts);
}
uint64_t cgs_sub_unauthenticated (const cgs_sub_t *self)
{
    S_SUM (unauthenticated);
}
uint64_t cgs_sub_replayed (const cgs_sub_t *self)
{
    S_SUM (replayed);
}
uint64_t cgs_sub_malformed (const cgs_sub_t *self)
{
    uint64_t n = self->malformed_unrouted;
    for (size_t i = 0; i < self->ntopics; i++)
        n += self->topics[i].stats.malformed;
    return n;
}

static s_sub_topic_t *s_sub_route (cgs_sub_t *self, const void *data, size_t len)
{
    for (size_t i = 0; i < self->ntopics; i++)
        if (self->topics[i].tlen == len && memcmp (self->topics[i].stats.topic, data, len) == 0)
            return &self->topics[i];
    return NULL;
}

typedef enum { S_SEQ_DELIVER, S_SEQ_STALE, S_SEQ_FAIL, S_SEQ_FOREIGN, S_SEQ_FORGED } s_seq_t;

/* On a sealed bus, open *data[*size] in place of it (into self->obuf), its
 * clear header into *sh; a payload that is not sealed, fails authentication
 * or was sent outside the replay window is counted and refused (-1). On a
 * clear bus a sealed payload cannot be read: counted and refused. */
static int s_sub_open (cgs_sub_t *self, s_sub_topic_t *t, const uint8_t **data, size_t *size,
                       cgs_seal_header_t *sh)
{
    bool sealed = cgs_seal_is_sealed (*data, *size);
    if (!self->seal) {
        if (sealed)
            t->stats.unauthenticated++;
        return sealed ? -1 : 0;
    }
    size_t n = 0;
    if (!sealed || s_grow (&self->obuf, &self->obufcap, *size) < 0 ||
        cgs_seal_open (self->seal, t->stats.topic, *data, *size, sh, self->obuf, self->obufcap,
                       &n) < 0) {
        t->stats.unauthenticated++;
        return -1;
    }
    if (self->replay_window_s > 0 &&
        !(fabs (cgs_bus_wall_time () - sh->wall_time_s) <= self->replay_window_s)) {
        t->stats.replayed++;
        return -1;
    }
    *data = self->obuf;
    *size = n;
    return 0;
}

/* The decoded header says what the authenticated clear one says. */
static bool s_same_header (const Cgs__Header *h, const cgs_seal_header_t *sh)
{
    return h->exercise_id == sh->exercise_id && h->epoch == sh->epoch && h->seq == sh->seq &&
           strcmp (h->source ? h->source : "", sh->source) == 0;
}

/* Account for a header's sequence number: deliver, drop a repeat, or fail. */
static s_seq_t s_sub_sequence (s_sub_topic_t *t, const Cgs__Header *h)
{
    const char *src = h->source ? h->source : "";
    s_source_t *s = NULL;
    if (t->last < t->nsources && strcmp (t->sources[t->last].source, src) == 0)
        s = &t->sources[t->last];
    for (size_t i = 0; !s && i < t->nsources; i++)
        if (strcmp (t->sources[i].source, src) == 0) {
            s = &t->sources[i];
            t->last = i;
        }
    if (!s) {
        if (t->nsources == t->capsources) {
            size_t cap = t->capsources ? t->capsources * 2 : 4;
            s_source_t *ns = realloc (t->sources, cap * sizeof *ns);
            if (!ns)
                return S_SEQ_FAIL;
            t->sources = ns;
            t->capsources = cap;
        }
        s = &t->sources[t->nsources];
        snprintf (s->source, sizeof s->source, "%s", src);
        s->epoch = h->epoch;
        s->seq = h->seq;
        t->last = t->nsources++;
        return S_SEQ_DELIVER;
    }
    if (s->epoch != h->epoch) {
        // An epoch the source has left: an old message repeated, not a restart.
        for (size_t i = 0; i < s->nretired && i < S_RETIRED; i++)
            if (s->retired[i] == h->epoch)
                return S_SEQ_STALE;
        s->retired[s->nretired++ % S_RETIRED] = s->epoch;
        // A restarted publisher numbers from 1: what came before this one was missed.
        t->stats.restarts++;
        if (h->seq > 1)
            t->stats.gaps += h->seq - 1;
        s->epoch = h->epoch;
    } else if (h->seq > s->seq + 1) {
        t->stats.gaps += h->seq - s->seq - 1;
    } else if (h->seq <= s->seq) {
        return S_SEQ_STALE; // a repeat or reordering: not delivered twice
    }
    s->seq = h->seq;
    return S_SEQ_DELIVER;
}

int cgs_sub_dispatch (cgs_sub_t *self, int max)
{
    int count = 0;
    zmq_msg_t topic, payload;
    zmq_msg_init (&topic);
    zmq_msg_init (&payload);
    while (count < max) {
        if (zmq_msg_recv (&topic, self->socket, ZMQ_DONTWAIT) < 0) {
            int e = zmq_errno ();
            zmq_msg_close (&topic);
            zmq_msg_close (&payload);
            return e == EAGAIN ? count : (count ? count : -e);
        }
        count++;
        self->received++;
        if (!zmq_msg_more (&topic)) {
            self->malformed_unrouted++; // a single frame: not ours
            continue;
        }
        zmq_msg_recv (&payload, self->socket, 0);
        bool extra = zmq_msg_more (&payload);
        while (zmq_msg_more (&payload)) // drain a message with too many frames
            zmq_msg_recv (&payload, self->socket, 0);
        s_sub_topic_t *t = s_sub_route (self, zmq_msg_data (&topic), zmq_msg_size (&topic));
        if (!t)
            continue; // a longer topic that shares our prefix
        const uint8_t *data = zmq_msg_data (&payload);
        size_t size = zmq_msg_size (&payload);
        cgs_seal_header_t sh;
        if (!extra && s_sub_open (self, t, &data, &size, &sh) < 0)
            continue; // counted
        ProtobufCMessage *m = NULL;
        const Cgs__Header *h = NULL;
        s_seq_t verdict = S_SEQ_FAIL;
        if (!extra &&
            cgs_msg_decode_stamped (t->desc, data, size, self->arena, &self->hdr, self->hdr_source,
                                    sizeof self->hdr_source, &m) == 0 &&
            (h = cgs_msg_header (m)) != NULL) {
            if (self->seal && !s_same_header (h, &sh))
                verdict = S_SEQ_FORGED;
            else if (self->exercise_id && h->exercise_id != self->exercise_id)
                verdict = S_SEQ_FOREIGN;
            else
                verdict = s_sub_sequence (t, h);
        }
        if (verdict == S_SEQ_FOREIGN)
            t->stats.foreign++;
        if (verdict == S_SEQ_FORGED)
            t->stats.unauthenticated++;
        // A repeat: on a sealed bus, where only a key holder could have sent
        // it, a replay.
        if (verdict == S_SEQ_STALE)
            *(self->seal ? &t->stats.replayed : &t->stats.stale) += 1;
        if (verdict != S_SEQ_DELIVER) {
            if (verdict == S_SEQ_FAIL)
                t->stats.malformed++;
            cgs_msg_arena_reset (self->arena);
            continue;
        }
        t->stats.messages++;
        t->fn (t->arg, t->stats.topic, m, h);
        cgs_msg_arena_reset (self->arena);
    }
    zmq_msg_close (&topic);
    zmq_msg_close (&payload);
    return count;
}

int cgs_sub_poll (cgs_sub_t *self, int timeout_ms)
{
    zmq_pollitem_t item = {self->socket, 0, ZMQ_POLLIN, 0};
    int rc = zmq_poll (&item, 1, timeout_ms);
    if (rc < 0)
        return -zmq_errno ();
    if (rc == 0)
        return 0;
    return cgs_sub_dispatch (self, 1000000);
}
