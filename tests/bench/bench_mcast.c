/* bench_mcast — the bus over UDP multicast, and what sealing costs.
 *
 *   bench_mcast                      the sealing cost (make bench runs this)
 *   bench_mcast seal                 the same
 *   bench_mcast pub OPTIONS          one publisher (tests/bench/multicast.sh)
 *   bench_mcast sub OPTIONS          one subscriber (tests/bench/multicast.sh)
 *
 * seal: nanoseconds per message to seal (cgs_seal) and to open (cgs_seal_open)
 * 100-byte and 2-kB payloads under one key, median of 7 runs of 20000.
 *
 * pub: the project's publisher (cgs_pub) bound to every --endpoint, with the
 * epgm options of [bus] (--rate-kbps), sealing under --key when given; after
 * --wait seconds it sends --messages cgs.Blob messages of --size bytes on
 * topic "bench" at --per-s a second (0: as fast as it can), then keeps its socket --linger seconds
 * (for the transport's repairs). It prints sent=, cpu_s=
 * (its CPU time while sending) and wall_s=.
 *
 * sub: the project's subscriber (cgs_sub) connected to --endpoint, opening
 * with --key when given; it counts what arrives until nothing has for
 * --idle seconds and prints received=, gaps= (by sequence number, from the
 * first it got), unauthenticated=, first_seq=, last_seq= and span_s= (from
 * the first message to the last).
 *
 * Exit 0, 1 when something broke, 2 on bad usage. */
#include "bench_util.h"
#include "cgs_bus.h"
#include "cgs_seal.h"
#include "tracking.pb-c.h"

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <zmq.h>

#define S_MAX_ENDPOINTS 4
#define S_TOPIC         "bench"

typedef struct {
    const char *endpoint[S_MAX_ENDPOINTS];
    int nendpoints;
    const char *key_file;
    long messages, size, per_s, rate_kbps, idle_s, wait_s, linger_s;
} s_opts_t;

static int s_usage (void)
{
    fprintf (stderr,
             "usage: bench_mcast [seal]\n"
             "       bench_mcast pub --endpoint EP [--endpoint EP ...] [--messages N] [--size B]\n"
             "                   [--per-s R] [--rate-kbps K] [--wait S] [--linger S]\n"
             "                   [--key FILE]\n"
             "       bench_mcast sub --endpoint EP [--idle S] [--key FILE]\n");
    return 2;
}

static int s_parse (int argc, char **argv, s_opts_t *o)
{
    *o = (s_opts_t){.messages = 20000,
                    .size = 100,
                    .per_s = 5000,
                    .rate_kbps = 100000,
                    .idle_s = 3,
                    .wait_s = 2,
                    .linger_s = 2};
    for (int i = 2; i < argc; i++) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        long *n = NULL, min = 1, max = 1000000000;
        if (strcmp (a, "--endpoint") == 0 && v && o->nendpoints < S_MAX_ENDPOINTS)
            o->endpoint[o->nendpoints++] = v;
        else if (strcmp (a, "--key") == 0 && v)
            o->key_file = v;
        else if (strcmp (a, "--messages") == 0)
            n = &o->messages;
        else if (strcmp (a, "--size") == 0)
            n = &o->size, max = 1000000;
        else if (strcmp (a, "--per-s") == 0)
            n = &o->per_s, min = 0;
        else if (strcmp (a, "--rate-kbps") == 0)
            n = &o->rate_kbps;
        else if (strcmp (a, "--idle") == 0)
            n = &o->idle_s, max = 3600;
        else if (strcmp (a, "--wait") == 0)
            n = &o->wait_s, min = 0, max = 3600;
        else if (strcmp (a, "--linger") == 0)
            n = &o->linger_s, min = 0, max = 3600;
        else
            return -1;
        if (n && !bench_parse_long (v, min, max, n))
            return -1;
        i++;
    }
    return o->nendpoints > 0 ? 0 : -1;
}

static int s_key (const s_opts_t *o, cgs_seal_key_t *key)
{
    char err[512];
    if (cgs_seal_key_load (o->key_file, key, err, sizeof err) < 0) {
        fprintf (stderr, "bench_mcast: %s\n", err);
        return -1;
    }
    return 0;
}

static int s_pub (const s_opts_t *o)
{
    void *ctx = zmq_ctx_new ();
    cgs_pub_t *pub = cgs_pub_new (ctx, "bench", 1);
    if (!pub)
        return 1;
    cgs_seal_key_t key;
    if (o->key_file && (s_key (o, &key) < 0 || cgs_pub_set_seal (pub, &key) < 0))
        return 1;
    cgs_bus_set_multicast (cgs_pub_socket (pub), (int)o->rate_kbps, 5000, 1);
    for (int i = 0; i < o->nendpoints; i++)
        if (cgs_pub_bind (pub, o->endpoint[i]) < 0) {
            fprintf (stderr, "bench_mcast: cannot bind %s: %s\n", o->endpoint[i],
                     zmq_strerror (zmq_errno ()));
            return 1;
        }
    sleep ((unsigned)o->wait_s);
    uint8_t *data = calloc (1, (size_t)o->size);
    Cgs__Blob b = CGS__BLOB__INIT;
    b.data.data = data;
    b.data.len = (size_t)o->size;
    double t0 = bench_wall_s (), c0 = bench_cpu_s ();
    double dt = o->per_s > 0 ? 1.0 / (double)o->per_s : 0;
    long sent = 0;
    for (long i = 0; i < o->messages; i++) {
        double due = t0 + (double)i * dt, now = dt > 0 ? bench_wall_s () : due;
        if (due > now)
            usleep ((useconds_t)((due - now) * 1e6));
        sent += cgs_pub_send (pub, S_TOPIC, &b.base, (double)i) == 0;
    }
    double cpu = bench_cpu_s () - c0, wall = bench_wall_s () - t0;
    printf ("sent=%ld drops=%llu cpu_s=%.4f wall_s=%.3f\n", sent,
            (unsigned long long)cgs_pub_drops (pub), cpu, wall);
    fflush (stdout);
    sleep ((unsigned)o->linger_s); // the transport repairs what it can before the socket goes
    free (data);
    cgs_pub_destroy (&pub);
    zmq_ctx_term (ctx);
    return sent == o->messages ? 0 : 1;
}

typedef struct {
    uint64_t n, first, last;
    double t_first, t_last; // wall time of the first and the last, seconds
} s_count_t;

static void s_on_blob (void *arg, const char *topic, const ProtobufCMessage *msg,
                       const Cgs__Header *h)
{
    (void)topic, (void)msg;
    s_count_t *c = arg;
    c->t_last = bench_wall_s ();
    if (c->n++ == 0) {
        c->first = h->seq;
        c->t_first = c->t_last;
    }
    c->last = h->seq;
}

static int s_sub (const s_opts_t *o)
{
    void *ctx = zmq_ctx_new ();
    cgs_sub_t *sub = cgs_sub_new (ctx);
    if (!sub)
        return 1;
    cgs_seal_key_t key;
    if (o->key_file && (s_key (o, &key) < 0 || cgs_sub_set_seal (sub, &key, 0) < 0))
        return 1;
    s_count_t c = {0};
    cgs_bus_set_multicast (cgs_sub_socket (sub), (int)o->rate_kbps, 5000, 1);
    if (cgs_sub_on_type (sub, S_TOPIC, &cgs__blob__descriptor, s_on_blob, &c) < 0 ||
        cgs_sub_connect (sub, o->endpoint[0]) < 0) {
        fprintf (stderr, "bench_mcast: cannot connect %s\n", o->endpoint[0]);
        return 1;
    }
    double last = bench_wall_s ();
    uint64_t seen = 0;
    // Wait up to a minute for the first message, then until idle.
    while (bench_wall_s () - last < (c.n ? (double)o->idle_s : 60.0)) {
        cgs_sub_poll (sub, 100);
        if (c.n != seen) {
            seen = c.n;
            last = bench_wall_s ();
        }
    }
    printf ("received=%llu gaps=%llu unauthenticated=%llu first_seq=%llu last_seq=%llu "
            "span_s=%.4f\n",
            (unsigned long long)c.n, (unsigned long long)cgs_sub_gaps (sub),
            (unsigned long long)cgs_sub_unauthenticated (sub), (unsigned long long)c.first,
            (unsigned long long)c.last, c.t_last - c.t_first);
    cgs_sub_destroy (&sub);
    zmq_ctx_term (ctx);
    return 0;
}

/* Nanoseconds per seal and per open of size-byte payloads: median of 7. */
static int s_seal_cost (size_t size, double *seal_ns, double *open_ns)
{
    enum { RUNS = 7, N = 20000 };
    cgs_seal_key_t key;
    if (cgs_seal_key_new (&key) < 0)
        return -1;
    uint8_t *plain = calloc (1, size), *sealed = malloc (size + 200), *out = malloc (size + 200);
    if (!plain || !sealed || !out)
        return -1;
    cgs_seal_header_t h = {.exercise_id = 1, .epoch = 7, .wall_time_s = 1.7e9};
    snprintf (h.source, sizeof h.source, "mtid.uav1");
    double s[RUNS], op[RUNS];
    size_t len = 0, n = 0;
    int rc = 0;
    for (int r = 0; r < RUNS; r++) {
        double t0 = bench_cpu_s ();
        for (int i = 0; i < N; i++) {
            h.seq = (uint64_t)i;
            rc |= cgs_seal (&key, "entity", &h, plain, size, sealed, size + 200, &len);
        }
        double t1 = bench_cpu_s ();
        for (int i = 0; i < N; i++)
            rc |= cgs_seal_open (&key, "entity", sealed, len, &h, out, size + 200, &n);
        double t2 = bench_cpu_s ();
        s[r] = (t1 - t0) / N * 1e9;
        op[r] = (t2 - t1) / N * 1e9;
    }
    *seal_ns = bench_median (s, RUNS);
    *open_ns = bench_median (op, RUNS);
    free (plain);
    free (sealed);
    free (out);
    return rc || n != size ? -1 : 0;
}

static int s_seal (void)
{
    const size_t sizes[] = {100, 2048};
    printf ("sealing (XChaCha20-Poly1305, libsodium), CPU time per message, median of 7 runs "
            "of 20000:\n");
    for (size_t i = 0; i < 2; i++) {
        double s, o;
        if (s_seal_cost (sizes[i], &s, &o) < 0) {
            fprintf (stderr, "bench_mcast: sealing failed\n");
            return 1;
        }
        printf ("  %4zu-byte payload: seal %.0f ns, open %.0f ns (+%zu bytes on the wire)\n",
                sizes[i], s, o, cgs_seal_size (0, "mtid.uav1"));
        printf ("seal_ns_%zu=%.0f\nopen_ns_%zu=%.0f\n", sizes[i], s, sizes[i], o);
    }
    printf ("the multicast figures need root and namespaces: tests/bench/multicast.sh "
            "(make bench-multicast)\n");
    return 0;
}

int main (int argc, char **argv)
{
    const char *mode = argc > 1 ? argv[1] : "seal";
    if (strcmp (mode, "pub") == 0 || strcmp (mode, "sub") == 0) {
        s_opts_t o;
        if (s_parse (argc, argv, &o) < 0)
            return s_usage ();
        return mode[0] == 'p' ? s_pub (&o) : s_sub (&o);
    }
    // seal, or the runner's options (BENCH_ARGS), which do not apply here
    if (strcmp (mode, "--help") == 0 || strcmp (mode, "-h") == 0)
        return s_usage ();
    return s_seal ();
}
