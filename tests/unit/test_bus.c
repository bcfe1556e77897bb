/* Unit tests of cgs_msg and cgs_bus: JSON printing, the arena, header
 * stamping, exact topic routing, gap and restart counting, malformed payloads,
 * the sealed bus (forgery and replay refused). */
#include "cgs_bus.h"
#include "cgs_topics.h"

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <zmq.h>

static void test_enum_short_names (void **state)
{
    (void)state;
    static const char *const states[] = {"IDLE",     "TO_SECONDARY", "TO_WAYPOINT",
                                         "APPROACH", "PRECISION",    "OVERFLIGHT",
                                         "DONE",     "CANCELLED",    "LOST"};
    for (int i = 0; i < 9; i++)
        assert_string_equal (cgs_msg_enum_short (&cgs__intercept_state__descriptor, i, "?"),
                             states[i]);
    assert_string_equal (cgs_msg_enum_short (&cgs__intercept_state__descriptor, 9, "?"), "?");
    assert_string_equal (cgs_msg_enum_short (&cgs__intercept_state__descriptor, -1, "?"), "?");
    assert_string_equal (cgs_msg_enum_short (&cgs__track_status__descriptor, 2, "?"), "COASTING");
    assert_string_equal (cgs_msg_enum_short (&cgs__uav_mode__descriptor, 1, "?"), "ROUTE");
    assert_string_equal (cgs_msg_enum_short (&cgs__force__descriptor, 2, "?"), "HOSTILE");
}

static void test_json_prints_fields_enums_and_oneofs (void **state)
{
    (void)state;
    Cgs__Enu pos = CGS__ENU__INIT;
    pos.east_m = 1.5;
    pos.north_m = -2;
    Cgs__Entity e = CGS__ENTITY__INIT;
    e.entity_id = 7;
    e.marking = "T72 \"A\"";
    e.force = CGS__FORCE__FORCE_HOSTILE;
    e.position = &pos;
    e.bcis_transponder = true;
    char *json = NULL;
    assert_int_equal (cgs_msg_to_json (&e.base, &json), 0);
    assert_string_equal (
        json, "{\"entity_id\":7,\"marking\":\"T72 \\\"A\\\"\",\"force\":\"FORCE_HOSTILE\","
              "\"position\":{\"east_m\":1.5,\"north_m\":-2},\"bcis_transponder\":true}");
    free (json);

    Cgs__Designate d = CGS__DESIGNATE__INIT;
    d.target_case = CGS__DESIGNATE__TARGET_TRACK_ID;
    d.track_id = 17;
    Cgs__Command c = CGS__COMMAND__INIT;
    c.command_number = 12345678901234ull;
    c.body_case = CGS__COMMAND__BODY_DESIGNATE;
    c.designate = &d;
    assert_int_equal (cgs_msg_to_json (&c.base, &json), 0);
    assert_string_equal (json,
                         "{\"command_number\":\"12345678901234\",\"designate\":{\"track_id\":17}}");
    free (json);

    uint8_t bytes[] = {0xff, 0x00, 0x10, 'a'};
    Cgs__Blob b = CGS__BLOB__INIT;
    b.data.data = bytes;
    b.data.len = sizeof bytes;
    assert_int_equal (cgs_msg_to_json (&b.base, &json), 0);
    assert_string_equal (json, "{\"data\":\"/wAQYQ==\"}"); // base64 of ff 00 10 61
    free (json);
}

static void test_arena_decodes_and_resets (void **state)
{
    (void)state;
    Cgs__Track t = CGS__TRACK__INIT;
    t.track_id = 99;
    Cgs__TrackHistoryPoint pts[300], *pp[300];
    Cgs__Enu where = CGS__ENU__INIT;
    where.east_m = 10;
    for (int i = 0; i < 300; i++) {
        cgs__track_history_point__init (&pts[i]);
        pts[i].position = &where;
        pts[i].scan_number = (uint32_t)i;
        pp[i] = &pts[i];
    }
    t.n_history = 300;
    t.history = pp;
    uint8_t *buf = NULL;
    size_t len = 0;
    assert_int_equal (cgs_msg_encode_alloc (&t.base, &buf, &len), 0);
    cgs_msg_arena_t *arena = cgs_msg_arena_new (256); // small: forces overflow blocks
    assert_non_null (arena);
    for (int round = 0; round < 3; round++) {
        ProtobufCMessage *m = NULL;
        assert_int_equal (cgs_msg_decode (&cgs__track__descriptor, buf, len, arena, &m), 0);
        Cgs__Track *d = (Cgs__Track *)m;
        assert_int_equal (d->track_id, 99);
        assert_int_equal (d->n_history, 300);
        assert_int_equal (d->history[299]->scan_number, 299);
        assert_true (d->history[5]->position->east_m == 10.0);
        cgs_msg_arena_reset (arena);
    }
    ProtobufCMessage *m = NULL;
    uint8_t junk[] = {0xff, 0xff, 0xff};
    assert_int_equal (cgs_msg_decode (&cgs__track__descriptor, junk, sizeof junk, arena, &m),
                      -EPROTO);
    cgs_msg_arena_destroy (&arena);
    assert_null (arena);
    cgs_msg_arena_destroy (&arena);
    free (buf);
}

static void test_header_slot (void **state)
{
    (void)state;
    Cgs__Clock clock = CGS__CLOCK__INIT;
    assert_non_null (cgs_msg_header_slot (&clock.base));
    Cgs__Command cmd = CGS__COMMAND__INIT;
    assert_null (cgs_msg_header_slot (&cmd.base));
    // Every catalogue topic's type has the common header as field 1.
    for (size_t i = 0; i < cgs_topics_count (); i++) {
        const ProtobufCMessageDescriptor *d = cgs_topics_at (i)->message;
        ProtobufCMessage *m = calloc (1, d->sizeof_message);
        d->message_init (m);
        assert_non_null (cgs_msg_header_slot (m));
        free (m);
    }
}

/* The hand-written header is byte for byte what protobuf-c writes, for every
 * topic's type, and decodes back to the same values; odd payloads fall back
 * to protobuf-c and still decode as protobuf says. */
static void test_stamped_header_matches_protobuf_c (void **state)
{
    (void)state;
    Cgs__Header h = CGS__HEADER__INIT;
    h.source = "mtid.uav1";
    h.exercise_id = 200;
    h.epoch = 0xfedcba9876543210ull;
    h.seq = 300;
    h.sim_time_s = 1234.5;
    h.wall_time_s = 1.7e9 + 0.25;
    cgs_msg_arena_t *arena = cgs_msg_arena_new (1024);
    for (size_t i = 0; i < cgs_topics_count (); i++) {
        const ProtobufCMessageDescriptor *d = cgs_topics_at (i)->message;
        ProtobufCMessage *m = calloc (1, d->sizeof_message);
        d->message_init (m);
        Cgs__Header **slot = cgs_msg_header_slot (m);
        for (int variant = 0; variant < 2; variant++) {
            Cgs__Header hv = h;
            if (variant == 1) { // zero fields are left out, as proto3 does
                hv.exercise_id = 0;
                hv.sim_time_s = 0;
                hv.source = "";
            }
            *slot = &hv;
            uint8_t want[512], got[512];
            size_t want_len = cgs_msg_encode (m, want), got_len = 0;
            *slot = NULL;
            assert_int_equal (cgs_msg_encode_stamped (m, &hv, got, sizeof got, &got_len), 0);
            assert_null (*slot); // the caller's message is left as it was
            assert_int_equal (got_len, want_len);
            assert_memory_equal (got, want, want_len);
            size_t need = 0;
            assert_int_equal (cgs_msg_encode_stamped (m, &hv, got, 3, &need), -ENOBUFS);
            assert_int_equal (need >= want_len, 1);

            Cgs__Header out;
            char src[64];
            ProtobufCMessage *dm = NULL;
            assert_int_equal (
                cgs_msg_decode_stamped (d, got, got_len, arena, &out, src, sizeof src, &dm), 0);
            const Cgs__Header *dh = cgs_msg_header (dm);
            assert_ptr_equal (dh, &out);
            assert_string_equal (dh->source, hv.source);
            assert_int_equal (dh->exercise_id, hv.exercise_id);
            assert_true (dh->epoch == hv.epoch && dh->seq == hv.seq);
            assert_true (dh->sim_time_s == hv.sim_time_s && dh->wall_time_s == hv.wall_time_s);
            cgs_msg_arena_reset (arena);
        }
        free (m);
    }
    // A payload whose header is repeated later: protobuf merges the two, and
    // the fallback gives the same answer as protobuf-c.
    Cgs__Clock c = CGS__CLOCK__INIT;
    c.header = &h;
    c.tick = 9;
    uint8_t buf[256];
    size_t n = cgs_msg_encode (&c.base, buf);
    Cgs__Header h2 = CGS__HEADER__INIT;
    h2.seq = 301;
    Cgs__Clock c2 = CGS__CLOCK__INIT;
    c2.header = &h2;
    n += cgs_msg_encode (&c2.base, buf + n);
    Cgs__Header out;
    char src[64];
    ProtobufCMessage *dm = NULL;
    assert_int_equal (
        cgs_msg_decode_stamped (&cgs__clock__descriptor, buf, n, arena, &out, src, sizeof src, &dm),
        0);
    const Cgs__Header *dh = cgs_msg_header (dm);
    assert_int_equal (dh->seq, 301);
    assert_string_equal (dh->source, "mtid.uav1");
    assert_int_equal (((Cgs__Clock *)dm)->tick, 9);
    cgs_msg_arena_reset (arena);
    // A source longer than the caller's buffer also falls back.
    char tiny[4];
    assert_int_equal (cgs_msg_decode_stamped (&cgs__clock__descriptor, buf, n, arena, &out, tiny,
                                              sizeof tiny, &dm),
                      0);
    assert_string_equal (cgs_msg_header (dm)->source, "mtid.uav1");
    cgs_msg_arena_reset (arena);
    // Truncated payloads are refused.
    for (size_t cut = 1; cut < 12; cut++)
        assert_int_equal (cgs_msg_decode_stamped (&cgs__clock__descriptor, buf, cut, arena, &out,
                                                  src, sizeof src, &dm),
                          -EPROTO);
    cgs_msg_arena_destroy (&arena);
}

/* ---- pub/sub over inproc ---- */

typedef struct {
    int n;
    uint64_t last_seq;
    double last_sim;
    char source[64];
    char topic[32];
    uint64_t tick_sum;
    uint64_t last_epoch;
    uint32_t last_exercise;
    double last_wall;
} s_rx_t;

static void s_on_clock (void *arg, const char *topic, const ProtobufCMessage *msg,
                        const Cgs__Header *h)
{
    s_rx_t *rx = arg;
    const Cgs__Clock *c = (const Cgs__Clock *)msg;
    rx->n++;
    rx->last_seq = h->seq;
    rx->last_sim = h->sim_time_s;
    rx->last_epoch = h->epoch;
    rx->last_exercise = h->exercise_id;
    rx->last_wall = h->wall_time_s;
    rx->tick_sum += c->tick;
    snprintf (rx->source, sizeof rx->source, "%s", h->source);
    snprintf (rx->topic, sizeof rx->topic, "%s", topic);
}

static void s_drain (cgs_sub_t *sub, int want_total, s_rx_t *rx)
{
    for (int i = 0; i < 200 && rx->n < want_total; i++)
        cgs_sub_poll (sub, 10);
}

/* Send until the subscriber sees one (the slow-joiner handshake). */
static void s_handshake (cgs_pub_t *pub, cgs_sub_t *sub, s_rx_t *rx)
{
    Cgs__Clock c = CGS__CLOCK__INIT;
    for (int i = 0; i < 500 && rx->n == 0; i++) {
        cgs_pub_send (pub, "clock", &c.base, 0);
        cgs_sub_poll (sub, 5);
    }
    assert_true (rx->n > 0);
    cgs_sub_poll (sub, 20);
}

static void test_pubsub_stamps_and_routes_exactly (void **state)
{
    (void)state;
    void *ctx = zmq_ctx_new ();
    cgs_pub_t *pub = cgs_pub_new (ctx, "uavsim", 3);
    assert_non_null (pub);
    assert_int_equal (cgs_pub_bind (pub, "inproc://t1"), 0);
    cgs_sub_t *sub = cgs_sub_new (ctx);
    assert_int_equal (cgs_sub_connect (sub, "inproc://t1"), 0);
    s_rx_t rx = {0};
    assert_int_equal (cgs_sub_on (sub, "clock", s_on_clock, &rx), 0);
    assert_int_equal (cgs_sub_on (sub, "clock", s_on_clock, &rx), -EEXIST);
    assert_int_equal (cgs_sub_on (sub, "no.such.topic", s_on_clock, &rx), -ENOENT);
    s_handshake (pub, sub, &rx);
    rx = (s_rx_t){0};
    uint64_t base_seq = cgs_pub_topic_stats (pub, 0)->messages;

    Cgs__Clock c = CGS__CLOCK__INIT;
    for (int i = 1; i <= 100; i++) {
        c.tick = (uint64_t)i;
        assert_int_equal (cgs_pub_send (pub, "clock", &c.base, i * 0.5), 0);
        // "clockwork" shares the prefix "clock": the subscriber must not take it.
        assert_int_equal (cgs_pub_send (pub, "clockwork", &c.base, 0), 0);
    }
    assert_null (c.header); // the caller's message is left as it was
    s_drain (sub, 100, &rx);
    assert_int_equal (rx.n, 100);
    assert_int_equal (rx.tick_sum, 5050);
    assert_int_equal (rx.last_seq, base_seq + 100);
    assert_true (rx.last_sim == 50.0);
    assert_string_equal (rx.source, "uavsim");
    assert_string_equal (rx.topic, "clock");
    assert_int_equal (cgs_sub_gaps (sub), 0);
    assert_int_equal (cgs_sub_malformed (sub), 0);

    // A message type without a header cannot be published.
    Cgs__Command cmd = CGS__COMMAND__INIT;
    assert_int_equal (cgs_pub_send (pub, "clock", &cmd.base, 0), -EINVAL);
    // A catalogue topic takes only its own type; other topics take any.
    Cgs__Uav uav = CGS__UAV__INIT;
    assert_int_equal (cgs_pub_send (pub, "clock", &uav.base, 0), -EINVAL);
    assert_int_equal (cgs_pub_send (pub, "test.anything", &uav.base, 0), 0);
    cgs_sub_destroy (&sub);
    cgs_pub_destroy (&pub);
    assert_null (pub);
    cgs_pub_destroy (&pub);
    zmq_ctx_term (ctx);
}

/* cgs_pub_forward: a recorded message goes out with its own header (source,
 * epoch, sequence number, simulation and wall time) in the forwarding
 * publisher's exercise; an epoch XORed is a new epoch to subscribers, so
 * what came before is not taken for repeats. */
static void test_forward_keeps_the_recorded_header (void **state)
{
    (void)state;
    void *ctx = zmq_ctx_new ();
    cgs_pub_t *pub = cgs_pub_new (ctx, "replay", 9);
    assert_int_equal (cgs_pub_bind (pub, "inproc://tfwd"), 0);
    cgs_sub_t *sub = cgs_sub_new (ctx);
    cgs_sub_set_exercise (sub, 9);
    assert_int_equal (cgs_sub_connect (sub, "inproc://tfwd"), 0);
    s_rx_t rx = {0};
    assert_int_equal (cgs_sub_on (sub, "clock", s_on_clock, &rx), 0);
    s_handshake (pub, sub, &rx);
    rx = (s_rx_t){0};
    Cgs__Header h = CGS__HEADER__INIT;
    h.source = "uavsim";
    h.exercise_id = 3;
    h.epoch = 77;
    h.sim_time_s = 1.5;
    h.wall_time_s = 1234.5;
    Cgs__Clock c = CGS__CLOCK__INIT;
    c.header = &h;
    for (uint64_t seq = 5; seq <= 7; seq++) {
        h.seq = seq;
        c.tick = seq;
        assert_int_equal (cgs_pub_forward (pub, "clock", &c.base, 0), 0);
    }
    s_drain (sub, 3, &rx);
    assert_int_equal (rx.n, 3);
    assert_int_equal (rx.tick_sum, 5 + 6 + 7);
    assert_string_equal (rx.source, "uavsim");
    assert_int_equal (rx.last_seq, 7);
    assert_int_equal (rx.last_epoch, 77);
    assert_int_equal (rx.last_exercise, 9); // the forwarding publisher's exercise
    assert_true (rx.last_sim == 1.5 && rx.last_wall == 1234.5);
    assert_int_equal (h.exercise_id, 3); // the caller's header is left as it was
    assert_int_equal (cgs_sub_gaps (sub), 0);
    // The same numbers again, in a new epoch: delivered.
    h.seq = 5;
    assert_int_equal (cgs_pub_forward (pub, "clock", &c.base, (uint64_t)1 << 32), 0);
    s_drain (sub, 4, &rx);
    assert_int_equal (rx.n, 4);
    assert_int_equal (rx.last_epoch, 77 | (uint64_t)1 << 32);
    // In the old epoch, once left: a repeat, dropped.
    h.seq = 8;
    assert_int_equal (cgs_pub_forward (pub, "clock", &c.base, 0), 0);
    for (int i = 0; i < 20; i++)
        cgs_sub_poll (sub, 5);
    assert_int_equal (rx.n, 4);
    assert_int_equal (cgs_sub_topic_stats (sub, 0)->stale, 1);
    // Nothing to keep without a header; a catalogue topic takes its own type only.
    c.header = NULL;
    assert_int_equal (cgs_pub_forward (pub, "clock", &c.base, 0), -EINVAL);
    Cgs__Uav uav = CGS__UAV__INIT;
    uav.header = &h;
    assert_int_equal (cgs_pub_forward (pub, "clock", &uav.base, 0), -EINVAL);
    cgs_sub_destroy (&sub);
    cgs_pub_destroy (&pub);
    zmq_ctx_term (ctx);
}

static void test_malformed_payloads_are_counted_and_dropped (void **state)
{
    (void)state;
    void *ctx = zmq_ctx_new ();
    void *raw = zmq_socket (ctx, ZMQ_PUB);
    assert_int_equal (zmq_bind (raw, "inproc://t2"), 0);
    cgs_sub_t *sub = cgs_sub_new (ctx);
    assert_int_equal (cgs_sub_connect (sub, "inproc://t2"), 0);
    s_rx_t rx = {0};
    assert_int_equal (cgs_sub_on (sub, "clock", s_on_clock, &rx), 0);
    usleep (50000);
    const uint8_t junk[] = {0x0a, 0xff, 0xff, 0xff, 0xff}; // field 1, absurd length
    zmq_send (raw, "clock", 5, ZMQ_SNDMORE);
    zmq_send (raw, junk, sizeof junk, 0);
    zmq_send (raw, "clock", 5, ZMQ_SNDMORE); // valid payload but no header
    zmq_send (raw, "", 0, 0);
    zmq_send (raw, "clock", 5, 0);           // a single frame
    zmq_send (raw, "clock", 5, ZMQ_SNDMORE); // three frames
    zmq_send (raw, "", 0, ZMQ_SNDMORE);
    zmq_send (raw, "", 0, 0);
    // Then a good one, which must still arrive.
    Cgs__Header h = CGS__HEADER__INIT;
    h.source = "x";
    h.seq = 1;
    h.epoch = 5;
    Cgs__Clock c = CGS__CLOCK__INIT;
    c.header = &h;
    c.tick = 42;
    uint8_t buf[256];
    size_t len = cgs_msg_encode (&c.base, buf);
    zmq_send (raw, "clock", 5, ZMQ_SNDMORE);
    zmq_send (raw, buf, len, 0);
    for (int i = 0; i < 100 && rx.n == 0; i++)
        cgs_sub_poll (sub, 10);
    assert_int_equal (rx.n, 1);
    assert_int_equal (rx.tick_sum, 42);
    assert_int_equal (cgs_sub_malformed (sub), 4);
    cgs_sub_destroy (&sub);
    zmq_close (raw);
    zmq_ctx_term (ctx);
}

/* Gaps: a publisher whose numbers skip (as when a subscriber falls behind and
 * messages are lost) and a publisher restart (new epoch). */
static void test_gaps_and_restarts_are_counted (void **state)
{
    (void)state;
    void *ctx = zmq_ctx_new ();
    void *raw = zmq_socket (ctx, ZMQ_PUB);
    assert_int_equal (zmq_bind (raw, "inproc://t3"), 0);
    cgs_sub_t *sub = cgs_sub_new (ctx);
    assert_int_equal (cgs_sub_connect (sub, "inproc://t3"), 0);
    s_rx_t rx = {0};
    assert_int_equal (cgs_sub_on (sub, "clock", s_on_clock, &rx), 0);
    usleep (50000);
    struct {
        const char *src;
        uint64_t epoch, seq;
    } seqs[] = {
        {"a", 1, 10}, {"a", 1, 11}, {"a", 1, 15}, /* 3 missed */
        {"b", 9, 1},  {"a", 1, 16}, {"b", 9, 3},  /* 1 missed */
        {"a", 2, 1},                              /* restart of a: not a gap */
        {"a", 2, 2},  {"a", 2, 2},                /* repeat: stale */
        {"a", 2, 10},                             /* 7 missed */
        {"b", 10, 3},                             /* restart of b, its first 2 missed */
    };
    cgs_sub_set_exercise (sub, 5);
    for (size_t i = 0; i < sizeof seqs / sizeof seqs[0] + 1; i++) {
        Cgs__Header h = CGS__HEADER__INIT;
        h.exercise_id = 5;
        if (i == sizeof seqs / sizeof seqs[0]) { // one more, of another exercise: dropped
            h.source = "a";
            h.exercise_id = 6;
            h.epoch = 2;
            h.seq = 11;
            Cgs__Clock c = CGS__CLOCK__INIT;
            c.header = &h;
            uint8_t buf[128];
            size_t len = cgs_msg_encode (&c.base, buf);
            zmq_send (raw, "clock", 5, ZMQ_SNDMORE);
            zmq_send (raw, buf, len, 0);
            continue;
        }
        h.source = (char *)seqs[i].src;
        h.epoch = seqs[i].epoch;
        h.seq = seqs[i].seq;
        Cgs__Clock c = CGS__CLOCK__INIT;
        c.header = &h;
        uint8_t buf[128];
        size_t len = cgs_msg_encode (&c.base, buf);
        zmq_send (raw, "clock", 5, ZMQ_SNDMORE);
        zmq_send (raw, buf, len, 0);
    }
    s_drain (sub, 10, &rx);
    assert_int_equal (rx.n, 10); // the stale repeat is counted, not delivered
    assert_int_equal (cgs_sub_gaps (sub), 3 + 1 + 7 + 2);
    assert_int_equal (cgs_sub_restarts (sub), 2);
    assert_int_equal (cgs_sub_topic_stats (sub, 0)->stale, 1);
    for (int i = 0; i < 50 && cgs_sub_foreign (sub) == 0; i++)
        cgs_sub_poll (sub, 10);
    assert_int_equal (cgs_sub_foreign (sub), 1);
    assert_int_equal (rx.n, 10); // not delivered
    cgs_sub_destroy (&sub);
    zmq_close (raw);
    zmq_ctx_term (ctx);
}

/* A subscriber that does not read while the publisher floods loses messages
 * at its high-water mark and counts exactly those as gaps. */
static void test_slow_subscriber_counts_its_losses (void **state)
{
    (void)state;
    void *ctx = zmq_ctx_new ();
    cgs_pub_t *pub = cgs_pub_new (ctx, "p", 1);
    cgs_pub_set_hwm (pub, 100);
    assert_int_equal (cgs_pub_bind (pub, "inproc://t4"), 0);
    cgs_sub_t *sub = cgs_sub_new (ctx);
    cgs_sub_set_hwm (sub, 100);
    assert_int_equal (cgs_sub_connect (sub, "inproc://t4"), 0);
    s_rx_t rx = {0};
    assert_int_equal (cgs_sub_on (sub, "clock", s_on_clock, &rx), 0);
    s_handshake (pub, sub, &rx);
    rx = (s_rx_t){0};
    uint64_t first = cgs_pub_topic_stats (pub, 0)->messages + 1;
    Cgs__Clock c = CGS__CLOCK__INIT;
    const int N = 5000;
    for (int i = 0; i < N; i++)
        assert_int_equal (cgs_pub_send (pub, "clock", &c.base, 0), 0);
    for (int i = 0; i < 50; i++)
        cgs_sub_poll (sub, 2);
    assert_int_equal (cgs_pub_send (pub, "clock", &c.base, 0), 0); // a last one after the drain
    for (int i = 0; i < 50; i++)
        cgs_sub_poll (sub, 2);
    uint64_t last = first + (uint64_t)N;
    assert_int_equal (rx.last_seq, last);
    assert_true (cgs_sub_gaps (sub) > 0);
    // Everything sent after the first is either received or counted missing.
    assert_int_equal ((uint64_t)rx.n + cgs_sub_gaps (sub), last - first + 1);
    cgs_sub_destroy (&sub);
    cgs_pub_destroy (&pub);
    zmq_ctx_term (ctx);
}

/* One message a raw socket received: its topic and payload. */
typedef struct {
    char topic[32];
    uint8_t data[512];
    size_t len;
} s_frame_t;

static void s_tap (void *tap, s_frame_t *f, size_t n)
{
    for (size_t i = 0; i < n; i++) {
        int t = zmq_recv (tap, f[i].topic, sizeof f[i].topic - 1, 0);
        assert_true (t > 0);
        f[i].topic[t] = '\0';
        int len = zmq_recv (tap, f[i].data, sizeof f[i].data, 0);
        assert_true (len > 0);
        f[i].len = (size_t)len;
    }
}

static void s_raw_send (void *raw, const s_frame_t *f)
{
    zmq_send (raw, f->topic, strlen (f->topic), ZMQ_SNDMORE);
    zmq_send (raw, f->data, f->len, 0);
}

/* Poll sub until its count *counter reaches want (or 1 s). */
static void s_until (cgs_sub_t *sub, uint64_t (*counter) (const cgs_sub_t *), uint64_t want)
{
    for (int i = 0; i < 100 && counter (sub) < want; i++)
        cgs_sub_poll (sub, 10);
}

/* A sealed bus: the subscriber with the group key gets every message; one
 * without a key, or with another key, gets none and counts each as
 * unauthenticated; a captured message sent again (a replay), a changed
 * byte, a clear payload, a message of an epoch its source has left and one
 * sent outside the replay window are dropped and counted, and none reaches
 * a handler. The wire never carries the payload in the clear. */
static void test_sealed_bus_refuses_forgery_and_replay (void **state)
{
    (void)state;
    cgs_seal_key_t key, other;
    assert_int_equal (cgs_seal_key_new (&key), 0);
    assert_int_equal (cgs_seal_key_new (&other), 0);
    void *ctx = zmq_ctx_new ();
    cgs_pub_t *pub = cgs_pub_new (ctx, "uavsim", 5);
    assert_int_equal (cgs_pub_set_seal (pub, &key), 0);
    assert_int_equal (cgs_pub_bind (pub, "inproc://s1"), 0);
    void *tap = zmq_socket (ctx, ZMQ_SUB);
    assert_int_equal (zmq_connect (tap, "inproc://s1"), 0);
    zmq_setsockopt (tap, ZMQ_SUBSCRIBE, "clock", 5);
    void *raw = zmq_socket (ctx, ZMQ_PUB);
    assert_int_equal (zmq_bind (raw, "inproc://s2"), 0);
    cgs_sub_t *good = cgs_sub_new (ctx), *clear = cgs_sub_new (ctx), *wrong = cgs_sub_new (ctx);
    assert_int_equal (cgs_sub_set_seal (good, &key, 30), 0);
    assert_int_equal (cgs_sub_set_seal (wrong, &other, 30), 0);
    s_rx_t rx = {0}, rx_clear = {0}, rx_wrong = {0};
    assert_int_equal (cgs_sub_on (good, "clock", s_on_clock, &rx), 0);
    assert_int_equal (cgs_sub_on (clear, "clock", s_on_clock, &rx_clear), 0);
    assert_int_equal (cgs_sub_on (wrong, "clock", s_on_clock, &rx_wrong), 0);
    cgs_sub_set_exercise (good, 5);
    assert_int_equal (cgs_sub_connect (good, "inproc://s1"), 0);
    assert_int_equal (cgs_sub_connect (good, "inproc://s2"), 0);
    assert_int_equal (cgs_sub_connect (clear, "inproc://s1"), 0);
    assert_int_equal (cgs_sub_connect (wrong, "inproc://s1"), 0);
    usleep (50000);

    Cgs__Clock c = CGS__CLOCK__INIT;
    s_frame_t f[10];
    for (int i = 1; i <= 10; i++) {
        c.tick = (uint64_t)i;
        assert_int_equal (cgs_pub_send (pub, "clock", &c.base, i), 0);
    }
    s_tap (tap, f, 10);
    s_drain (good, 10, &rx);
    assert_int_equal (rx.n, 10);
    assert_int_equal (rx.tick_sum, 55);
    assert_string_equal (rx.source, "uavsim");
    s_until (clear, cgs_sub_unauthenticated, 10);
    s_until (wrong, cgs_sub_unauthenticated, 10);
    assert_int_equal (cgs_sub_unauthenticated (clear), 10);
    assert_int_equal (cgs_sub_unauthenticated (wrong), 10);
    assert_int_equal (rx_clear.n + rx_wrong.n, 0);
    assert_int_equal (cgs_sub_malformed (clear) + cgs_sub_malformed (wrong), 0);
    for (int i = 0; i < 10; i++)
        assert_true (cgs_seal_is_sealed (f[i].data, f[i].len));

    // A replay of message 5, then of message 10 (the newest): both refused.
    s_raw_send (raw, &f[4]);
    s_raw_send (raw, &f[9]);
    s_until (good, cgs_sub_replayed, 2);
    assert_int_equal (cgs_sub_replayed (good), 2);
    // A changed byte (in the ciphertext, in the clear sequence number).
    s_frame_t t = f[9];
    t.data[t.len - 20] ^= 1;
    s_raw_send (raw, &t);
    t = f[9];
    t.data[24] ^= 1; // the sequence number's low byte: 10 becomes 11
    s_raw_send (raw, &t);
    // A clear payload with a fresh header.
    Cgs__Header h = CGS__HEADER__INIT;
    h.source = "uavsim";
    h.exercise_id = 5;
    h.epoch = cgs_pub_epoch (pub);
    h.seq = 11;
    c.header = &h;
    s_frame_t plain = {.topic = "clock"};
    plain.len = cgs_msg_encode (&c.base, plain.data);
    c.header = NULL;
    s_raw_send (raw, &plain);
    s_until (good, cgs_sub_unauthenticated, 3);
    assert_int_equal (cgs_sub_unauthenticated (good), 3);
    assert_int_equal (rx.n, 10);

    // The publisher restarts (a new epoch); then its old epoch's messages
    // come again, the newest first: refused as replays, not a restart.
    cgs_pub_destroy (&pub);
    pub = cgs_pub_new (ctx, "uavsim", 5);
    assert_int_equal (cgs_pub_set_seal (pub, &key), 0);
    assert_int_equal (cgs_pub_bind (pub, "inproc://s3"), 0);
    assert_int_equal (cgs_sub_connect (good, "inproc://s3"), 0);
    usleep (50000);
    for (int i = 0; i < 200 && rx.n < 11; i++) {
        cgs_pub_send (pub, "clock", &c.base, 0);
        cgs_sub_poll (good, 5);
    }
    cgs_sub_poll (good, 20);
    uint64_t delivered = rx.n;
    assert_true (delivered >= 11);
    assert_int_equal (cgs_sub_restarts (good), 1);
    s_raw_send (raw, &f[9]);
    s_raw_send (raw, &f[2]);
    s_until (good, cgs_sub_replayed, 4);
    assert_int_equal (cgs_sub_replayed (good), 4);
    assert_int_equal (cgs_sub_restarts (good), 1);

    // Sealed with the key but sent 100 s ago (another source, so no sequence
    // rule applies): outside the 30 s window.
    cgs_seal_header_t sh = {
        .exercise_id = 5, .epoch = 77, .seq = 1, .wall_time_s = cgs_bus_wall_time () - 100};
    snprintf (sh.source, sizeof sh.source, "bcisd.uav1");
    h.source = sh.source;
    h.epoch = 77;
    h.seq = 1;
    h.wall_time_s = sh.wall_time_s;
    c.header = &h;
    uint8_t inner[256];
    size_t n = cgs_msg_encode (&c.base, inner);
    c.header = NULL;
    s_frame_t old = {.topic = "clock"};
    assert_int_equal (cgs_seal (&key, "clock", &sh, inner, n, old.data, sizeof old.data, &old.len),
                      0);
    s_raw_send (raw, &old);
    s_until (good, cgs_sub_replayed, 5);
    assert_int_equal (cgs_sub_replayed (good), 5);
    // The same, sent now: taken.
    sh.wall_time_s = h.wall_time_s = cgs_bus_wall_time ();
    c.header = &h;
    n = cgs_msg_encode (&c.base, inner);
    c.header = NULL;
    assert_int_equal (cgs_seal (&key, "clock", &sh, inner, n, old.data, sizeof old.data, &old.len),
                      0);
    s_raw_send (raw, &old);
    s_drain (good, (int)delivered + 1, &rx);
    assert_int_equal (rx.n, delivered + 1);
    assert_string_equal (rx.source, "bcisd.uav1");
    assert_int_equal (cgs_sub_malformed (good), 0);
    assert_int_equal (cgs_sub_unauthenticated (good), 3);

    cgs_sub_destroy (&good);
    cgs_sub_destroy (&clear);
    cgs_sub_destroy (&wrong);
    cgs_pub_destroy (&pub);
    zmq_close (tap);
    zmq_close (raw);
    zmq_ctx_term (ctx);
}

static void test_prepare_endpoint_creates_ipc_folder (void **state)
{
    (void)state;
    char dir[] = "/tmp/cgs-bus-XXXXXX";
    assert_non_null (mkdtemp (dir));
    char ep[256];
    snprintf (ep, sizeof ep, "ipc://%s/a/b/pub", dir);
    assert_int_equal (cgs_bus_prepare_endpoint (ep), 0);
    char sub[256];
    snprintf (sub, sizeof sub, "%s/a/b", dir);
    assert_int_equal (access (sub, W_OK), 0);
    void *ctx = zmq_ctx_new ();
    cgs_pub_t *pub = cgs_pub_new (ctx, "p", 1);
    assert_int_equal (cgs_pub_bind (pub, ep), 0);
    cgs_pub_t *pub2 = cgs_pub_new (ctx, "p", 1);
    assert_true (cgs_pub_bind (pub2, "tcp://not a host:1") < 0);
    assert_true (cgs_pub_epoch (pub) != cgs_pub_epoch (pub2));
    cgs_pub_destroy (&pub);
    cgs_pub_destroy (&pub2);
    zmq_ctx_term (ctx);
    char cmd[300];
    snprintf (cmd, sizeof cmd, "rm -rf %s", dir);
    assert_int_equal (system (cmd), 0);
}

int main (void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test (test_enum_short_names),
        cmocka_unit_test (test_json_prints_fields_enums_and_oneofs),
        cmocka_unit_test (test_arena_decodes_and_resets),
        cmocka_unit_test (test_header_slot),
        cmocka_unit_test (test_stamped_header_matches_protobuf_c),
        cmocka_unit_test (test_pubsub_stamps_and_routes_exactly),
        cmocka_unit_test (test_forward_keeps_the_recorded_header),
        cmocka_unit_test (test_malformed_payloads_are_counted_and_dropped),
        cmocka_unit_test (test_gaps_and_restarts_are_counted),
        cmocka_unit_test (test_slow_subscriber_counts_its_losses),
        cmocka_unit_test (test_sealed_bus_refuses_forgery_and_replay),
        cmocka_unit_test (test_prepare_endpoint_creates_ipc_folder),
    };
    return cmocka_run_group_tests (tests, NULL, NULL);
}
