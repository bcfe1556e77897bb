/* cgs_bus — the publish/subscribe bus over ZeroMQ. No broker: each publishing
 * service binds one PUB endpoint; consumers connect a SUB socket to every
 * publisher of the topics they need. Frame 1 is the topic, frame 2 the
 * protobuf payload whose common header the publisher stamps (source, exercise,
 * epoch, per-topic sequence number, simulation and wall time). Subscribers
 * count gaps by sequence number, restarts by epoch, and malformed payloads,
 * which are dropped, never fatal. Pure of logging and global state. */
#ifndef CGS_BUS_H
#define CGS_BUS_H

#include "cgs_msg.h"
#include "cgs_seal.h"
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#define CGS_BUS_DEFAULT_SNDHWM 100000 // messages queued per subscriber before drops
#define CGS_BUS_DEFAULT_RCVHWM 100000 // messages queued in a subscriber before drops
#define CGS_TOPIC_MAX          32     // longest topic name + 1

/* Traffic on one topic. */
typedef struct {
    char topic[CGS_TOPIC_MAX];
    uint64_t messages;        // sent, or received and handled
    uint64_t drops;           // outbound: refused at the high-water mark
    uint64_t gaps;            // inbound: messages missed, by sequence number
    uint64_t malformed;       // inbound: payloads that failed to decode
    uint64_t restarts;        // inbound: publisher epochs that changed
    uint64_t stale;           // inbound: repeated or out-of-order sequence numbers
    uint64_t foreign;         // inbound: from another exercise (dropped)
    uint64_t unauthenticated; // inbound, sealed bus: failed authentication, or not sealed
    uint64_t replayed;        // inbound, sealed bus: an (epoch, seq) seen before, a retired
                              // epoch, or sent longer ago than the replay window (dropped)
} cgs_topic_stats_t;

/* ---- publisher ------------------------------------------------------------------ */

typedef struct cgs_pub cgs_pub_t;

/* Publisher for source instance `source` in exercise `exercise_id`, with a new
 * epoch; NULL with errno on failure. ctx is a zmq context the caller owns. */
cgs_pub_t *cgs_pub_new (void *ctx, const char *source, uint32_t exercise_id);
/* Close and free; accepts NULL; nulls the pointer. */
void cgs_pub_destroy (cgs_pub_t **self_p);
/* Set the send high-water mark (before bind). */
void cgs_pub_set_hwm (cgs_pub_t *self, int messages);
/* By default the publisher never waits: a subscriber that falls behind by
 * its high-water mark loses messages, and counts them as gaps. With
 * timeout_ms > 0 the publisher waits that long for room at every subscriber
 * and then drops (counted here) for all of them (benchmarks, bulk tools). */
void cgs_pub_set_block (cgs_pub_t *self, int timeout_ms);
/* Bind the PUB socket (creates the folder of an ipc:// path); 0 or -errno. */
int cgs_pub_bind (cgs_pub_t *self, const char *endpoint);
/* A topic of the catalogue (cgs_topics) takes only its own message type
 * (-EINVAL otherwise); other topics take any type with a header.
 * Stamp a header (the publisher's own, put in msg's header field for the
 * call; msg is left as it was) and send msg on topic. 0; -EAGAIN when dropped
 * in blocking mode (counted; the sequence number is used, so subscribers see
 * the gap); -EINVAL if the type has no header or the topic is bad. */
int cgs_pub_send (cgs_pub_t *self, const char *topic, ProtobufCMessage *msg, double sim_time_s);
/* Send msg as another publisher sent it (a replay): its own header is kept
 * (source, epoch, sequence number, simulation and wall time) but for the
 * exercise id, which becomes this publisher's, and the epoch, XORed with
 * epoch_xor (0 keeps it: a replay that goes back in time changes it, or the
 * subscribers would drop what they take for repeats). Sealed like
 * cgs_pub_send. 0, or the errors of cgs_pub_send; -EINVAL when msg has no
 * header. */
int cgs_pub_forward (cgs_pub_t *self, const char *topic, ProtobufCMessage *msg, uint64_t epoch_xor);
/* Seal every payload from now on under key (cgs_seal: XChaCha20-Poly1305,
 * the header as associated data); NULL: send in the clear. 0 or -ENOMEM. */
int cgs_pub_set_seal (cgs_pub_t *self, const cgs_seal_key_t *key);
/* The publisher's epoch. */
uint64_t cgs_pub_epoch (const cgs_pub_t *self);
/* The underlying socket, for options such as CURVE before bind. */
void *cgs_pub_socket (cgs_pub_t *self);
/* Number of topics seen so far, and stats of topic i. */
size_t cgs_pub_topic_count (const cgs_pub_t *self);
const cgs_topic_stats_t *cgs_pub_topic_stats (const cgs_pub_t *self, size_t i);
/* Totals over all topics. */
uint64_t cgs_pub_sent (const cgs_pub_t *self);
uint64_t cgs_pub_drops (const cgs_pub_t *self);

/* ---- subscriber ----------------------------------------------------------------- */

typedef struct cgs_sub cgs_sub_t;

/* Called for every well-formed message on a subscribed topic. msg and hdr
 * live until the handler returns. */
typedef void (cgs_sub_fn) (void *arg, const char *topic, const ProtobufCMessage *msg,
                           const Cgs__Header *hdr);

/* Subscriber; NULL with errno on failure. ctx is a zmq context the caller owns. */
cgs_sub_t *cgs_sub_new (void *ctx);
/* Close and free; accepts NULL; nulls the pointer. */
void cgs_sub_destroy (cgs_sub_t **self_p);
/* Set the receive high-water mark (before connect). */
void cgs_sub_set_hwm (cgs_sub_t *self, int messages);
/* Accept only messages of this exercise (others are counted and dropped);
 * 0 (the default) accepts any. */
void cgs_sub_set_exercise (cgs_sub_t *self, uint32_t exercise_id);
/* Messages dropped because they came from another exercise. */
uint64_t cgs_sub_foreign (const cgs_sub_t *self);
/* Accept only payloads sealed under key (NULL: only clear ones; a sealed
 * payload is then unreadable and counted as unauthenticated), and, when
 * replay_window_s > 0, only those sent at most that long before (or after)
 * this machine's clock says (their wall time is authenticated). Whatever
 * fails authentication, or repeats an (epoch, seq) of its source and topic,
 * or belongs to an epoch that source has left, is dropped and counted
 * (unauthenticated, replayed); no handler sees it. 0 or -ENOMEM. */
int cgs_sub_set_seal (cgs_sub_t *self, const cgs_seal_key_t *key, double replay_window_s);
uint64_t cgs_sub_unauthenticated (const cgs_sub_t *self);
uint64_t cgs_sub_replayed (const cgs_sub_t *self);
/* Connect to one more publisher; 0 or -errno. */
int cgs_sub_connect (cgs_sub_t *self, const char *endpoint);
/* Subscribe to a catalogue topic (cgs_topics) with its handler; 0, -ENOENT for
 * a topic not in the catalogue, -EEXIST if already subscribed. */
int cgs_sub_on (cgs_sub_t *self, const char *topic, cgs_sub_fn *fn, void *arg);
/* Subscribe to any topic whose payload is of type desc (tests, benchmarks). */
int cgs_sub_on_type (cgs_sub_t *self, const char *topic, const ProtobufCMessageDescriptor *desc,
                     cgs_sub_fn *fn, void *arg);
/* Handle up to max waiting messages without blocking; returns how many were
 * received (handled or dropped as malformed), or -errno. */
int cgs_sub_dispatch (cgs_sub_t *self, int max);
/* Wait up to timeout_ms for a message, then dispatch what is waiting; returns
 * the number received, 0 on timeout, or -errno (-EINTR on a signal). */
int cgs_sub_poll (cgs_sub_t *self, int timeout_ms);
/* The underlying socket, for zmq_poll and options such as CURVE. */
void *cgs_sub_socket (cgs_sub_t *self);
/* Number of subscribed topics, and stats of topic i. */
size_t cgs_sub_topic_count (const cgs_sub_t *self);
const cgs_topic_stats_t *cgs_sub_topic_stats (const cgs_sub_t *self, size_t i);
/* Totals over all topics. */
uint64_t cgs_sub_received (const cgs_sub_t *self);
uint64_t cgs_sub_gaps (const cgs_sub_t *self);
uint64_t cgs_sub_malformed (const cgs_sub_t *self);
uint64_t cgs_sub_restarts (const cgs_sub_t *self);

/* Set the options that make a tcp:// connection over a network that went
 * silent fail and reconnect within seconds (TCP keepalive and user timeout,
 * connect timeout, reconnect interval; values and reasons in cgs_bus.c),
 * before bind or connect. Every publisher and subscriber has them, and
 * every command client and server (cgs_cmd); 0 or -errno. */
int cgs_bus_set_liveness (void *socket);
/* The epgm transport's options on a socket, before it binds or connects a
 * multicast endpoint: ZMQ_RATE (kbit/s), ZMQ_RECOVERY_IVL (ms),
 * ZMQ_MULTICAST_HOPS. NORM takes none of them in libzmq 4.3 (it runs its
 * own congestion control, with a TTL of 255). 0 or -errno. */
int cgs_bus_set_multicast (void *socket, int rate_kbps, int recovery_ms, int hops);
/* Wall-clock time now, Unix seconds. */
double cgs_bus_wall_time (void);
/* Create the folder an ipc:// endpoint's path lives in; 0 or -errno. */
int cgs_bus_prepare_endpoint (const char *endpoint);

#endif
