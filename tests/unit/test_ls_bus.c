/* test_ls_bus — the lockstep engine's in-process bus: messages reach the
 * subscribers of their topic, in publication order, messages published by a
 * subscriber during delivery come after those already queued (breadth
 * first, as a real bus would deliver them), each carries the header the bus
 * would stamp (source, exercise id, epoch 1, a sequence number per source
 * and topic, the simulation time; wall time = simulation time), a message
 * of the wrong type for its topic or an unknown topic is refused, and the
 * sources' bad inputs and errors are added up. Two identical runs deliver
 * identical bytes. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "cgs_msg.h"
#include "ls_bus.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define S_MAX 64

typedef struct {
    char log[S_MAX][96]; // "topic source seq t"
    size_t n;
    cgs_port_t echo;     // a subscriber that republishes a `track.turn` per `track`
    uint8_t bytes[4096]; // every delivered message re-encoded, end to end
    size_t nbytes;
} s_seen_t;

static void s_record (void *arg, const char *topic, const ProtobufCMessage *msg,
                      const Cgs__Header *hdr)
{
    s_seen_t *s = arg;
    assert_true (s->n < S_MAX);
    snprintf (s->log[s->n++], sizeof s->log[0], "%s %s %llu %.1f %.1f %u", topic, hdr->source,
              (unsigned long long)hdr->seq, hdr->sim_time_s, hdr->wall_time_s,
              (unsigned)hdr->exercise_id);
    assert_int_equal (hdr->epoch, 1);
    size_t len = cgs_msg_size (msg);
    assert_true (s->nbytes + len <= sizeof s->bytes);
    s->nbytes += cgs_msg_encode (msg, s->bytes + s->nbytes);
}

static void s_echo (void *arg, const char *topic, const ProtobufCMessage *msg,
                    const Cgs__Header *hdr)
{
    (void)topic, (void)msg;
    s_seen_t *s = arg;
    Cgs__TrackTurn t = CGS__TRACK_TURN__INIT;
    t.track_id = 7;
    assert_int_equal (cgs_port_publish (&s->echo, "track.turn", &t.base, hdr->sim_time_s + 0.5), 0);
}

static void s_run (s_seen_t *s)
{
    memset (s, 0, sizeof *s);
    ls_bus_t *bus = ls_bus_new (9);
    assert_non_null (bus);
    ls_source_t *a = ls_bus_source (bus, "uavsim"), *b = ls_bus_source (bus, "trackerd");
    cgs_port_t pa = ls_bus_port (a), pb = ls_bus_port (b);
    s->echo = ls_bus_port (b);
    assert_int_equal (ls_bus_subscribe (bus, "clock", s_record, s), 0);
    assert_int_equal (ls_bus_subscribe (bus, "track", s_echo, s), 0);
    assert_int_equal (ls_bus_subscribe (bus, "track", s_record, s), 0);
    assert_int_equal (ls_bus_subscribe (bus, "track.turn", s_record, s), 0);
    assert_int_equal (ls_bus_subscribe (bus, "no.such.topic", s_record, s), -EINVAL);
    Cgs__Clock c = CGS__CLOCK__INIT;
    Cgs__TrackBatch tb = CGS__TRACK_BATCH__INIT;
    assert_int_equal (cgs_port_publish (&pa, "clock", &c.base, 1.0), 0);
    assert_int_equal (cgs_port_publish (&pb, "track", &tb.base, 2.0), 0);
    assert_int_equal (cgs_port_publish (&pa, "clock", &c.base, 3.0), 0);
    // Refused: a type that is not the topic's, a topic not in the catalogue.
    assert_int_equal (cgs_port_publish (&pa, "track", &c.base, 3.0), -EINVAL);
    assert_int_equal (cgs_port_publish (&pa, "nonsense", &c.base, 3.0), -EINVAL);
    assert_int_equal (ls_bus_drain (bus), 4); // two clocks, the batch, the echoed turn
    assert_int_equal (ls_bus_drain (bus), 0);
    assert_true (ls_bus_time (bus) == 2.5);
    assert_int_equal (ls_bus_source_stats (a)->published, 2);
    assert_int_equal (ls_bus_source_stats (b)->published, 2);
    pb.bad_input (pb.arg, "a track without a position");
    pa.error (pa.arg, "out of memory");
    pb.error (pb.arg, "later");
    uint64_t bad = 0, errors = 0;
    char first[128];
    ls_bus_report (bus, &bad, &errors, first, sizeof first);
    assert_int_equal (bad, 1);
    assert_int_equal (errors, 2);
    assert_string_equal (first, "uavsim: out of memory");
    assert_int_equal (ls_bus_failures (bus), 0);
    ls_bus_destroy (&bus);
    assert_null (bus);
    ls_bus_destroy (&bus);
}

static void test_order_and_headers (void **state)
{
    (void)state;
    s_seen_t *s = calloc (1, sizeof *s);
    assert_non_null (s);
    s_run (s);
    assert_int_equal (s->n, 4);
    // Publication order; the turn published during the batch's delivery comes last.
    assert_string_equal (s->log[0], "clock uavsim 1 1.0 1.0 9");
    assert_string_equal (s->log[1], "track trackerd 1 2.0 2.0 9");
    assert_string_equal (s->log[2], "clock uavsim 2 3.0 3.0 9");
    assert_string_equal (s->log[3], "track.turn trackerd 1 2.5 2.5 9");
    free (s);
}

static void test_deterministic (void **state)
{
    (void)state;
    s_seen_t *a = calloc (1, sizeof *a), *b = calloc (1, sizeof *b);
    assert_non_null (a);
    assert_non_null (b);
    s_run (a);
    s_run (b);
    assert_int_equal (a->nbytes, b->nbytes);
    assert_memory_equal (a->bytes, b->bytes, a->nbytes);
    free (a);
    free (b);
}

int main (void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test (test_order_and_headers),
        cmocka_unit_test (test_deterministic),
    };
    return cmocka_run_group_tests (tests, NULL, NULL);
}
