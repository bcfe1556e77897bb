/* Unit tests of cgs_loop (timers, socket watches, stop) and cgs_health (the
 * health message's counts and per-topic figures). */
#include "cgs_health.h"
#include "cgs_lifecycle.h"
#include "cgs_loop.h"

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>
#include <math.h>
#include <string.h>
#include <unistd.h>
#include <zmq.h>

typedef struct {
    cgs_loop_t *loop;
    int fast, slow, reads;
    void *socket;
} s_ctx_t;

static void s_fast (void *arg)
{
    s_ctx_t *c = arg;
    if (++c->fast == 5)
        cgs_loop_stop (c->loop);
}

static void s_slow (void *arg)
{
    ((s_ctx_t *)arg)->slow++;
}

static void test_timers_fire_and_stop_from_a_callback (void **state)
{
    (void)state;
    s_ctx_t c = {.loop = cgs_loop_new ()};
    assert_non_null (c.loop);
    assert_true (cgs_loop_add_timer (c.loop, 0.005, s_fast, &c) > 0);
    assert_true (cgs_loop_add_timer (c.loop, 60.0, s_slow, &c) > 0);
    assert_int_equal (cgs_loop_add_timer (c.loop, 0, s_slow, &c), -EINVAL);
    assert_int_equal (cgs_loop_add_timer (c.loop, -1, s_slow, &c), -EINVAL);
    assert_int_equal (cgs_loop_run (c.loop), 0);
    assert_int_equal (c.fast, 5); // stopped from inside the fifth call
    assert_int_equal (c.slow, 0);
    cgs_loop_destroy (&c.loop);
    assert_null (c.loop);
    cgs_loop_destroy (&c.loop);
}

static void s_on_read (void *arg)
{
    s_ctx_t *c = arg;
    char buf[16];
    while (zmq_recv (c->socket, buf, sizeof buf, ZMQ_DONTWAIT) >= 0)
        c->reads++;
    if (c->reads >= 3)
        cgs_loop_stop (c->loop);
}

/* Two watches on readable sockets; the first removes the second from its
 * callback: the second must not be called with stale readiness. */
typedef struct {
    cgs_loop_t *loop;
    void *a, *b;
    int a_calls, b_calls;
} s_rm_t;

static void s_on_a (void *arg)
{
    s_rm_t *r = arg;
    char buf[8];
    zmq_recv (r->a, buf, sizeof buf, ZMQ_DONTWAIT);
    r->a_calls++;
    cgs_loop_remove (r->loop, r->b, -1);
    cgs_loop_stop (r->loop);
}

static void s_on_b (void *arg)
{
    ((s_rm_t *)arg)->b_calls++;
}

static void test_remove_from_a_callback (void **state)
{
    (void)state;
    void *ctx = zmq_ctx_new ();
    void *a_in = zmq_socket (ctx, ZMQ_PAIR), *a_out = zmq_socket (ctx, ZMQ_PAIR);
    void *b_in = zmq_socket (ctx, ZMQ_PAIR), *b_out = zmq_socket (ctx, ZMQ_PAIR);
    zmq_bind (a_in, "inproc://rm-a");
    zmq_connect (a_out, "inproc://rm-a");
    zmq_bind (b_in, "inproc://rm-b");
    zmq_connect (b_out, "inproc://rm-b");
    s_rm_t r = {.loop = cgs_loop_new (), .a = a_in, .b = b_in};
    assert_int_equal (cgs_loop_add_socket (r.loop, a_in, s_on_a, &r), 0);
    assert_int_equal (cgs_loop_add_socket (r.loop, b_in, s_on_b, &r), 0);
    zmq_send (a_out, "x", 1, 0);
    zmq_send (b_out, "x", 1, 0);
    usleep (20000);
    assert_int_equal (cgs_loop_run (r.loop), 0);
    assert_int_equal (r.a_calls, 1);
    assert_int_equal (r.b_calls, 0);
    cgs_loop_destroy (&r.loop);
    zmq_close (a_in);
    zmq_close (a_out);
    zmq_close (b_in);
    zmq_close (b_out);
    zmq_ctx_term (ctx);
}

static void s_send_later (void *arg)
{
    void *out = arg;
    zmq_send (out, "x", 1, 0);
}

static void test_socket_watch_and_remove (void **state)
{
    (void)state;
    void *ctx = zmq_ctx_new ();
    void *in = zmq_socket (ctx, ZMQ_PAIR), *out = zmq_socket (ctx, ZMQ_PAIR);
    assert_int_equal (zmq_bind (in, "inproc://loop"), 0);
    assert_int_equal (zmq_connect (out, "inproc://loop"), 0);
    s_ctx_t c = {.loop = cgs_loop_new (), .socket = in};
    assert_int_equal (cgs_loop_add_socket (c.loop, in, s_on_read, &c), 0);
    assert_true (cgs_loop_add_timer (c.loop, 0.002, s_send_later, out) > 0);
    assert_int_equal (cgs_loop_run (c.loop), 0);
    assert_int_equal (c.reads, 3);
    // Once removed, the socket no longer wakes the loop: a lifecycle stop ends it.
    cgs_loop_remove (c.loop, in, -1);
    zmq_send (out, "x", 1, 0);
    cgs_lifecycle_request_stop ();
    assert_int_equal (cgs_loop_run (c.loop), 0);
    assert_int_equal (c.reads, 3);
    cgs_loop_destroy (&c.loop);
    zmq_close (in);
    zmq_close (out);
    zmq_ctx_term (ctx);
}

typedef struct {
    int n;
    Cgs__ServiceState state;
    char instance[64], error[64], host[64], machine[64];
    uint64_t out, clock_msgs;
    bool has_clock;
    uint32_t pid;
    double clock_rate, max_rate, uav_rate, health_in_rate;
} s_seen_t;

static void s_on_health (void *arg, const char *topic, const ProtobufCMessage *msg,
                         const Cgs__Header *h)
{
    (void)topic;
    (void)h;
    s_seen_t *s = arg;
    const Cgs__Health *hm = (const Cgs__Health *)msg;
    s->n++;
    s->state = hm->state;
    snprintf (s->instance, sizeof s->instance, "%s", hm->instance);
    snprintf (s->error, sizeof s->error, "%s", hm->last_error);
    s->out = hm->msgs_out;
    s->pid = hm->pid;
    snprintf (s->host, sizeof s->host, "%s", hm->host ? hm->host : "");
    snprintf (s->machine, sizeof s->machine, "%s", hm->machine ? hm->machine : "");
    s->has_clock = false;
    s->max_rate = 0;
    for (size_t i = 0; i < hm->n_topics; i++)
        if (hm->topics[i]->rate_hz > s->max_rate)
            s->max_rate = hm->topics[i]->rate_hz;
    for (size_t i = 0; i < hm->n_topics; i++)
        if (strcmp (hm->topics[i]->topic, "clock") == 0 && hm->topics[i]->outbound) {
            s->has_clock = true;
            s->clock_msgs = hm->topics[i]->messages;
            s->clock_rate = hm->topics[i]->rate_hz;
        }
    for (size_t i = 0; i < hm->n_topics; i++) {
        if (strcmp (hm->topics[i]->topic, "uav") == 0 && hm->topics[i]->outbound)
            s->uav_rate = hm->topics[i]->rate_hz;
        if (strcmp (hm->topics[i]->topic, "health") == 0 && !hm->topics[i]->outbound)
            s->health_in_rate = hm->topics[i]->rate_hz;
    }
}

static void test_health_reports_counts_state_and_error (void **state)
{
    (void)state;
    void *ctx = zmq_ctx_new ();
    cgs_pub_t *pub = cgs_pub_new (ctx, "svc.a", 1);
    assert_int_equal (cgs_pub_bind (pub, "inproc://health"), 0);
    cgs_sub_t *sub = cgs_sub_new (ctx);
    assert_int_equal (cgs_sub_connect (sub, "inproc://health"), 0);
    s_seen_t seen = {0};
    assert_int_equal (cgs_sub_on (sub, "health", s_on_health, &seen), 0);
    cgs_health_t *h = cgs_health_new ("svc", "svc.a", "1.0", "lab-b");
    cgs_health_watch_pub (h, pub);
    assert_int_equal (cgs_health_watch_sub (h, sub), 0); // inbound topics follow the outbound
    for (int i = 0; i < 200 && seen.n == 0; i++) {
        cgs_health_publish (h, pub, 0);
        cgs_sub_poll (sub, 5);
    }
    assert_true (seen.n > 0);
    assert_int_equal (seen.state, CGS__SERVICE_STATE__SERVICE_STATE_STARTING);
    Cgs__Clock c = CGS__CLOCK__INIT;
    for (int i = 0; i < 7; i++)
        assert_int_equal (cgs_pub_send (pub, "clock", &c.base, 0), 0);
    cgs_health_set_state (h, CGS__SERVICE_STATE__SERVICE_STATE_DEGRADED);
    cgs_health_set_error (h, "terrain.tif: no such file");
    uint64_t health_sent = cgs_pub_topic_stats (pub, 0)->messages;
    seen.n = 0;
    assert_int_equal (cgs_health_publish (h, pub, 12.5), 0);
    for (int i = 0; i < 100 && seen.n == 0; i++)
        cgs_sub_poll (sub, 5);
    assert_int_equal (seen.n, 1);
    assert_string_equal (seen.instance, "svc.a");
    assert_int_equal (seen.state, CGS__SERVICE_STATE__SERVICE_STATE_DEGRADED);
    assert_string_equal (seen.error, "terrain.tif: no such file");
    assert_true (seen.has_clock);
    assert_int_equal (seen.clock_msgs, 7);
    assert_int_equal (seen.out, health_sent + 7); // counted before this health went out
    assert_int_equal (seen.pid, (uint32_t)getpid ());
    // The exercise's host for the instance, and the machine it runs on.
    char machine[64] = "";
    gethostname (machine, sizeof machine - 1);
    assert_string_equal (seen.host, "lab-b");
    assert_string_equal (seen.machine, machine);
    // A topic that appears between two health messages does not shift the
    // others' rates (they were once compared against the wrong counts).
    Cgs__Uav uav = CGS__UAV__INIT;
    assert_int_equal (cgs_pub_send (pub, "uav", &uav.base, 0), 0);
    seen.n = 0;
    assert_int_equal (cgs_health_publish (h, pub, 13), 0);
    for (int i = 0; i < 100 && seen.n == 0; i++)
        cgs_sub_poll (sub, 5);
    assert_int_equal (seen.n, 1);
    assert_true (seen.clock_rate == 0.0); // no clock sent since the last health
    assert_true (seen.max_rate < 1e6);
    // One uav message out and one health message in since the last health,
    // over the same interval: the same rate.
    assert_true (seen.uav_rate > 0);
    assert_true (fabs (seen.health_in_rate - seen.uav_rate) < 1e-9 * seen.uav_rate);
    cgs_health_destroy (&h);
    assert_null (h);
    cgs_sub_destroy (&sub);
    cgs_pub_destroy (&pub);
    zmq_ctx_term (ctx);
}

int main (void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test (test_timers_fire_and_stop_from_a_callback),
        cmocka_unit_test (test_remove_from_a_callback),
        cmocka_unit_test (test_socket_watch_and_remove), // leaves the lifecycle stop flag set
        cmocka_unit_test (test_health_reports_counts_state_and_error),
    };
    return cmocka_run_group_tests (tests, NULL, NULL);
}
