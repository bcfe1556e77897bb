/* test_ms_metrics — the tracking-quality metrics: GOSPA (alpha = 2) against
 * hand-worked cases, against brute force over every assignment of small sets
 * and against an independent min-cost-flow solver on 40 x 40 sets, its
 * errors, its speed at 300 x 300 and its running mean; the SIAP-style
 * figures over a scripted run of five scans with two truths and three tracks,
 * every figure worked by hand below, the primary-track rules, empty and
 * refused input, pooling runs with ms_siap_merge, and the identification
 * figures over two hand-worked scans (right, wrong and hostile marks). */
#include <setjmp.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "ms_gospa.h"
#include "ms_siap.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "test_util.h"

/* splitmix64: the same points on every machine. */
static uint64_t s_next (uint64_t *s)
{
    uint64_t z = (*s += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

static double s_uniform (uint64_t *s, double lo, double hi)
{
    return lo + (hi - lo) * (double)(s_next (s) >> 11) / 9007199254740992.0;
}

static void s_random_points (uint64_t *s, ms_point_t *pt, size_t n, double side_m)
{
    for (size_t i = 0; i < n; i++)
        pt[i] = (ms_point_t){s_uniform (s, 0, side_m), s_uniform (s, 0, side_m)};
}

static double s_dist (ms_point_t a, ms_point_t b)
{
    return hypot (a.e - b.e, a.n - b.n);
}

/* ---- GOSPA -------------------------------------------------------------- */

// The GOSPA sum (distance^p) of an assignment, from the definition:
// Σ d^p over assigned pairs + (c^p / 2)(|X| + |Y| − 2|γ|).
static double s_gospa_sum (const ms_point_t *x, size_t nx, const ms_point_t *y, size_t ny, double c,
                           double p, const long *assign)
{
    double sum = 0;
    size_t pairs = 0;
    for (size_t j = 0; j < ny; j++)
        if (assign[j] >= 0) {
            sum += pow (s_dist (x[assign[j]], y[j]), p);
            pairs++;
        }
    return sum + pow (c, p) / 2 * (double)(nx + ny - 2 * pairs);
}

// Least GOSPA sum by trying every assignment: estimate j goes to no truth or
// to any truth not yet taken (pairs at or beyond c included, to check that
// leaving them apart is never worse).
static double s_brute (const ms_point_t *x, size_t nx, const ms_point_t *y, size_t ny, double c,
                       double p, size_t j, long *assign, bool *taken)
{
    if (j == ny)
        return s_gospa_sum (x, nx, y, ny, c, p, assign);
    assign[j] = -1;
    double best = s_brute (x, nx, y, ny, c, p, j + 1, assign, taken);
    for (size_t i = 0; i < nx; i++) {
        if (taken[i])
            continue;
        taken[i] = true;
        assign[j] = (long)i;
        double v = s_brute (x, nx, y, ny, c, p, j + 1, assign, taken);
        if (v < best)
            best = v;
        taken[i] = false;
        assign[j] = -1;
    }
    return best;
}

// Least GOSPA sum by a different exact method: min-cost flow, source -> truth
// -> estimate -> sink, unit capacities, an edge truth->estimate of cost
// d^p − c^p for each pair closer than c (what pairing them saves), augmented
// along Bellman-Ford shortest paths while a path still saves something.
// GOSPA sum = (c^p / 2)(|X| + |Y|) + Σ costs of the flow.
#define S_MCF_NODES 128
#define S_MCF_EDGES 8192
typedef struct {
    int to[S_MCF_EDGES], cap[S_MCF_EDGES];
    double cost[S_MCF_EDGES];
    int n_edges;
} s_mcf_t;

static void s_mcf_edge (s_mcf_t *g, int a, int b, double cost)
{
    assert_true (g->n_edges + 2 <= S_MCF_EDGES);
    // Edge 2k is forward, 2k + 1 its residual; the tail of edge e is to[e ^ 1].
    g->to[g->n_edges] = b, g->cap[g->n_edges] = 1, g->cost[g->n_edges] = cost;
    g->to[g->n_edges + 1] = a, g->cap[g->n_edges + 1] = 0, g->cost[g->n_edges + 1] = -cost;
    g->n_edges += 2;
}

static double s_min_cost_flow (const ms_point_t *x, size_t nx, const ms_point_t *y, size_t ny,
                               double c, double p)
{
    static s_mcf_t g;
    g.n_edges = 0;
    int nodes = (int)(nx + ny) + 2, src = nodes - 2, sink = nodes - 1;
    assert_true (nodes <= S_MCF_NODES);
    const double cp = pow (c, p);
    for (size_t i = 0; i < nx; i++)
        s_mcf_edge (&g, src, (int)i, 0);
    for (size_t j = 0; j < ny; j++)
        s_mcf_edge (&g, (int)(nx + j), sink, 0);
    for (size_t i = 0; i < nx; i++)
        for (size_t j = 0; j < ny; j++) {
            double d = s_dist (x[i], y[j]);
            if (d < c)
                s_mcf_edge (&g, (int)i, (int)(nx + j), pow (d, p) - cp);
        }
    double total = cp / 2 * (double)(nx + ny);
    for (;;) {
        double dist[S_MCF_NODES];
        int via[S_MCF_NODES];
        for (int v = 0; v < nodes; v++)
            dist[v] = INFINITY, via[v] = -1;
        dist[src] = 0;
        for (int round = 0; round < nodes; round++) {
            bool changed = false;
            for (int e = 0; e < g.n_edges; e++) {
                int a = g.to[e ^ 1], b = g.to[e];
                if (g.cap[e] > 0 && dist[a] + g.cost[e] < dist[b] - 1e-12) {
                    dist[b] = dist[a] + g.cost[e];
                    via[b] = e;
                    changed = true;
                }
            }
            if (!changed)
                break;
        }
        if (!(dist[sink] < 0))
            break; // no path that lowers the cost: optimal
        for (int v = sink; v != src; v = g.to[via[v] ^ 1]) {
            g.cap[via[v]]--;
            g.cap[via[v] ^ 1]++;
        }
        total += dist[sink];
    }
    return total;
}

// The reported figures agree with each other and with the assignment given.
static void s_check_consistent (const ms_point_t *x, size_t nx, const ms_point_t *y, size_t ny,
                                const ms_gospa_t *g, const long *assign)
{
    const double cp = pow (g->c, g->p);
    bool taken[512] = {false};
    size_t pairs = 0;
    double loc = 0;
    for (size_t j = 0; j < ny; j++) {
        if (assign[j] < 0)
            continue;
        assert_true ((size_t)assign[j] < nx);
        assert_false (taken[assign[j]]); // each truth at most once
        taken[assign[j]] = true;
        double d = s_dist (x[assign[j]], y[j]);
        assert_true (d < g->c); // only pairs closer than c
        loc += pow (d, g->p);
        pairs++;
    }
    assert_int_equal (g->assigned, pairs);
    assert_int_equal (g->missed_count, nx - pairs);
    assert_int_equal (g->false_count, ny - pairs);
    assert_near (g->localisation, loc, 1e-9 * (1 + loc));
    assert_near (g->missed, cp / 2 * (double)(nx - pairs), 1e-9 * cp);
    assert_near (g->false_, cp / 2 * (double)(ny - pairs), 1e-9 * cp);
    double sum = g->localisation + g->missed + g->false_;
    assert_near (g->distance, pow (sum, 1 / g->p), 1e-9 * (1 + g->distance));
}

// Empty sets: distance 0, nothing assigned, nothing written to ret_assign.
static void test_gospa_empty (void **state)
{
    (void)state;
    ms_gospa_t g;
    memset (&g, 0x5a, sizeof g);
    assert_int_equal (ms_gospa (NULL, 0, NULL, 0, 500, 2, &g, NULL), 0);
    assert_true (g.distance == 0 && g.localisation == 0 && g.missed == 0 && g.false_ == 0);
    assert_int_equal (g.assigned, 0);
    assert_int_equal (g.missed_count, 0);
    assert_int_equal (g.false_count, 0);
    assert_true (g.c == 500 && g.p == 2);
}

// One truth, no estimate, c = 500: missed only, c^p / 2, distance (c^p / 2)^(1/p):
//   p = 2: missed = 250000 / 2 = 125000 m², distance = sqrt(125000) = 353.5534 m;
//   p = 1: missed = 500 / 2 = 250 m, distance 250 m.
// And the mirror, one estimate and no truth: false only, the same numbers.
static void test_gospa_missed_only (void **state)
{
    (void)state;
    ms_point_t x = {100, 200};
    ms_gospa_t g;
    assert_int_equal (ms_gospa (&x, 1, NULL, 0, 500, 2, &g, NULL), 0);
    assert_near (g.missed, 125000, 1e-9);
    assert_near (g.distance, 353.5533905932738, 1e-9);
    assert_true (g.localisation == 0 && g.false_ == 0);
    assert_int_equal (g.missed_count, 1);
    assert_int_equal (g.false_count, 0);
    assert_int_equal (g.assigned, 0);
    assert_int_equal (ms_gospa (&x, 1, NULL, 0, 500, 1, &g, NULL), 0);
    assert_near (g.missed, 250, 1e-12);
    assert_near (g.distance, 250, 1e-12);
    long assign = 7;
    assert_int_equal (ms_gospa (NULL, 0, &x, 1, 500, 2, &g, &assign), 0);
    assert_near (g.false_, 125000, 1e-9);
    assert_near (g.distance, 353.5533905932738, 1e-9);
    assert_int_equal (g.false_count, 1);
    assert_int_equal (g.missed_count, 0);
    assert_int_equal (assign, -1);
}

// One pair 30 m apart (a 18-24-30 triangle), c = 500, p = 2: assigned,
// localisation 30² = 900 m², distance sqrt(900) = 30 m. With p = 1: 30, 30.
static void test_gospa_one_pair (void **state)
{
    (void)state;
    ms_point_t x = {1000, 2000}, y = {1018, 2024};
    ms_gospa_t g;
    long assign = 7;
    assert_int_equal (ms_gospa (&x, 1, &y, 1, 500, 2, &g, &assign), 0);
    assert_near (g.localisation, 900, 1e-9);
    assert_near (g.distance, 30, 1e-12);
    assert_true (g.missed == 0 && g.false_ == 0);
    assert_int_equal (g.assigned, 1);
    assert_int_equal (assign, 0);
    assert_int_equal (ms_gospa (&x, 1, &y, 1, 500, 1, &g, &assign), 0);
    assert_near (g.localisation, 30, 1e-12);
    assert_near (g.distance, 30, 1e-12);
}

// One pair 600 m apart, c = 500, p = 2: 600² = 360000 > 500² = 250000, so not
// assigned: missed 125000 + false 125000 = 250000 m², distance 500 m = c.
static void test_gospa_pair_beyond_cutoff (void **state)
{
    (void)state;
    ms_point_t x = {0, 0}, y = {360, 480};
    ms_gospa_t g;
    long assign = 7;
    assert_int_equal (ms_gospa (&x, 1, &y, 1, 500, 2, &g, &assign), 0);
    assert_true (g.localisation == 0);
    assert_near (g.missed, 125000, 1e-9);
    assert_near (g.false_, 125000, 1e-9);
    assert_near (g.distance, 500, 1e-9);
    assert_int_equal (g.assigned, 0);
    assert_int_equal (g.missed_count, 1);
    assert_int_equal (g.false_count, 1);
    assert_int_equal (assign, -1);
}

// Three truths, two estimates, c = 20, p = 2 (c^p / 2 = 200 m²):
//   x0 = (0, 0), x1 = (8, 0), x2 = (0, 1000); y0 = (5, 0), y1 = (13, 0).
//   d(x0,y0) = 5, d(x0,y1) = 13, d(x1,y0) = 3, d(x1,y1) = 5, x2 beyond c.
//   Greedy, nearest pair first: x1-y0 (3), then x0-y1 (13), x2 missed:
//     9 + 169 + 200 = 378 m², distance 19.442 m.
//   Optimal: x0-y0, x1-y1, x2 missed: 25 + 25 + 200 = 250 m², 15.811 m.
static void test_gospa_greedy_loses (void **state)
{
    (void)state;
    ms_point_t x[3] = {{0, 0}, {8, 0}, {0, 1000}}, y[2] = {{5, 0}, {13, 0}};
    ms_gospa_t g;
    long assign[2] = {7, 7};
    assert_int_equal (ms_gospa (x, 3, y, 2, 20, 2, &g, assign), 0);
    assert_near (g.localisation, 50, 1e-9);
    assert_near (g.missed, 200, 1e-9);
    assert_true (g.false_ == 0);
    assert_near (g.distance, sqrt (250), 1e-12);
    assert_int_equal (assign[0], 0);
    assert_int_equal (assign[1], 1);
    assert_int_equal (g.assigned, 2);
    assert_int_equal (g.missed_count, 1);
    long greedy[2] = {1, 0};
    assert_near (s_gospa_sum (x, 3, y, 2, 20, 2, greedy), 378, 1e-9);
    assert_true (g.distance < sqrt (378));
    // The same sets the other way round: truths and estimates swap roles.
    assert_int_equal (ms_gospa (y, 2, x, 3, 20, 2, &g, NULL), 0);
    assert_near (g.distance, sqrt (250), 1e-12);
    assert_near (g.false_, 200, 1e-9);
}

// Random sets of up to 7 a side (square and rectangular, c small enough that
// some pairs are beyond it) against brute force over every assignment.
static void test_gospa_brute_force (void **state)
{
    (void)state;
    uint64_t s = 42;
    for (int trial = 0; trial < 120; trial++) {
        size_t nx = 1 + (size_t)(s_next (&s) % 7), ny = 1 + (size_t)(s_next (&s) % 7);
        if (trial < 20)
            nx = ny = 7;
        double c = s_uniform (&s, 50, 400), p = trial % 3 == 0 ? 1 : trial % 3 == 1 ? 2 : 3.5;
        ms_point_t x[7], y[7];
        s_random_points (&s, x, nx, 1000);
        s_random_points (&s, y, ny, 1000);
        ms_gospa_t g;
        long assign[7], work[7];
        bool taken[7] = {false};
        assert_int_equal (ms_gospa (x, nx, y, ny, c, p, &g, assign), 0);
        double best = s_brute (x, nx, y, ny, c, p, 0, work, taken);
        assert_near (pow (g.distance, p), best, 1e-9 * best);
        s_check_consistent (x, nx, y, ny, &g, assign);
        assert_near (s_gospa_sum (x, nx, y, ny, c, p, assign), best, 1e-9 * best);
    }
}

// Random 40 x 40 sets (and 40 x 25, 25 x 40) against min-cost flow.
static void test_gospa_min_cost_flow (void **state)
{
    (void)state;
    uint64_t s = 7;
    static const size_t shapes[][2] = {{40, 40}, {40, 25}, {25, 40}};
    for (int trial = 0; trial < 12; trial++) {
        size_t nx = shapes[trial % 3][0], ny = shapes[trial % 3][1];
        double c = trial < 6 ? 100 : 400, p = trial % 2 ? 1 : 2;
        ms_point_t x[40], y[40];
        s_random_points (&s, x, nx, 1000);
        for (size_t j = 0; j < ny; j++) // estimates near some truths, plus clutter
            y[j] = j < nx && j % 4 != 3
                       ? (ms_point_t){x[j].e + s_uniform (&s, -120, 120),
                                      x[j].n + s_uniform (&s, -120, 120)}
                       : (ms_point_t){s_uniform (&s, 0, 1000), s_uniform (&s, 0, 1000)};
        ms_gospa_t g;
        long assign[40];
        assert_int_equal (ms_gospa (x, nx, y, ny, c, p, &g, assign), 0);
        double best = s_min_cost_flow (x, nx, y, ny, c, p);
        assert_near (pow (g.distance, p), best, 1e-9 * best);
        s_check_consistent (x, nx, y, ny, &g, assign);
        assert_true (g.assigned > 0);
        if (c == 100) // the cut-off bites: more left unpaired than the sizes force
            assert_true (g.missed_count + g.false_count > (nx > ny ? nx - ny : ny - nx));
    }
}

// 300 x 300, c = 500 m in a 10 km square: well under 100 ms at -O2; here
// (sanitisers, -O1) allowed a second.
static void test_gospa_speed (void **state)
{
    (void)state;
    enum { N = 300 };
    static ms_point_t x[N], y[N];
    static long assign[N];
    uint64_t s = 99;
    s_random_points (&s, x, N, 10000);
    for (size_t j = 0; j < N; j++)
        y[j] = (ms_point_t){x[(j * 7) % N].e + s_uniform (&s, -200, 200),
                            x[(j * 7) % N].n + s_uniform (&s, -200, 200)};
    struct timespec t0, t1;
    clock_gettime (CLOCK_MONOTONIC, &t0);
    ms_gospa_t g;
    assert_int_equal (ms_gospa (x, N, y, N, 500, 2, &g, assign), 0);
    clock_gettime (CLOCK_MONOTONIC, &t1);
    double ms = (double)(t1.tv_sec - t0.tv_sec) * 1e3 + (double)(t1.tv_nsec - t0.tv_nsec) / 1e6;
    print_message ("      300 x 300: %.1f ms, %zu assigned, GOSPA %.1f m\n", ms, g.assigned,
                   g.distance);
    assert_true (ms < 1000);
    s_check_consistent (x, N, y, N, &g, assign);
    assert_true (g.assigned >= N * 9 / 10);
}

// Refused input leaves *ret and ret_assign alone.
static void test_gospa_errors (void **state)
{
    (void)state;
    ms_point_t x = {0, 0}, y = {3, 4}, bad = {NAN, 0}, inf = {0, INFINITY};
    ms_gospa_t g, before;
    memset (&g, 0x5a, sizeof g);
    before = g;
    long assign = 7;
    assert_int_equal (ms_gospa (&x, 1, &y, 1, 0, 2, &g, &assign), -EINVAL);
    assert_int_equal (ms_gospa (&x, 1, &y, 1, -1, 2, &g, &assign), -EINVAL);
    assert_int_equal (ms_gospa (&x, 1, &y, 1, NAN, 2, &g, &assign), -EINVAL);
    assert_int_equal (ms_gospa (&x, 1, &y, 1, INFINITY, 2, &g, &assign), -EINVAL);
    assert_int_equal (ms_gospa (&x, 1, &y, 1, 500, 0.5, &g, &assign), -EINVAL);
    assert_int_equal (ms_gospa (&x, 1, &y, 1, 500, NAN, &g, &assign), -EINVAL);
    assert_int_equal (ms_gospa (&x, 1, &y, 1, 500, INFINITY, &g, &assign), -EINVAL);
    assert_int_equal (ms_gospa (&x, 1, &y, 1, 1e200, 2, &g, &assign), -EINVAL); // c^p overflows
    assert_int_equal (ms_gospa (&bad, 1, &y, 1, 500, 2, &g, &assign), -EINVAL);
    assert_int_equal (ms_gospa (&x, 1, &inf, 1, 500, 2, &g, &assign), -EINVAL);
    assert_int_equal (ms_gospa (&bad, 1, NULL, 0, 500, 2, &g, &assign), -EINVAL);
    assert_int_equal (ms_gospa (NULL, 1, &y, 1, 500, 2, &g, &assign), -EINVAL);
    assert_int_equal (ms_gospa (&x, 1, NULL, 1, 500, 2, &g, &assign), -EINVAL);
    assert_memory_equal (&g, &before, sizeof g);
    assert_int_equal (assign, 7);
}

// Mean over scans, c = 500, p = 2: the 30 m pair (900 m², 30 m) and the lone
// truth (missed 125000 m², 353.5534 m): mean distance (30 + 353.5534) / 2 =
// 191.7767 m, localisation 450, missed 62500, false 0, assigned 0.5, missed
// count 0.5. Merged from two halves: the same. Another c is refused.
static void test_gospa_mean (void **state)
{
    (void)state;
    ms_point_t x = {1000, 2000}, y = {1018, 2024};
    ms_gospa_t a, b, other;
    assert_int_equal (ms_gospa (&x, 1, &y, 1, 500, 2, &a, NULL), 0);
    assert_int_equal (ms_gospa (&x, 1, NULL, 0, 500, 2, &b, NULL), 0);
    assert_int_equal (ms_gospa (&x, 1, &y, 1, 400, 2, &other, NULL), 0);
    ms_gospa_mean_t m = {0}, h1 = {0}, h2 = {0}, empty = {0};
    ms_gospa_avg_t avg;
    ms_gospa_mean_finish (&m, &avg);
    assert_int_equal (avg.scans, 0);
    assert_true (isnan (avg.distance) && isnan (avg.localisation) && isnan (avg.false_count));
    assert_int_equal (ms_gospa_mean_add (&m, &a), 0);
    assert_int_equal (ms_gospa_mean_add (&m, &b), 0);
    assert_int_equal (ms_gospa_mean_add (&m, &other), -EINVAL);
    ms_gospa_mean_finish (&m, &avg);
    assert_int_equal (avg.scans, 2);
    assert_near (avg.distance, (30 + 353.5533905932738) / 2, 1e-9);
    assert_near (avg.localisation, 450, 1e-9);
    assert_near (avg.missed, 62500, 1e-9);
    assert_true (avg.false_ == 0 && avg.false_count == 0);
    assert_near (avg.assigned, 0.5, 1e-15);
    assert_near (avg.missed_count, 0.5, 1e-15);
    assert_int_equal (ms_gospa_mean_add (&h1, &a), 0);
    assert_int_equal (ms_gospa_mean_add (&h2, &b), 0);
    assert_int_equal (ms_gospa_mean_merge (&h1, &empty), 0);
    assert_int_equal (ms_gospa_mean_merge (&h1, &h2), 0);
    assert_memory_equal (&h1, &m, sizeof m);
    assert_int_equal (ms_gospa_mean_merge (&empty, &h1), 0);
    assert_memory_equal (&empty, &m, sizeof m);
    ms_gospa_mean_t o = {0};
    assert_int_equal (ms_gospa_mean_add (&o, &other), 0);
    assert_int_equal (ms_gospa_mean_merge (&h1, &o), -EINVAL);
    assert_memory_equal (&h1, &m, sizeof m);
}

/* ---- SIAP --------------------------------------------------------------- */

// Every count and figure equal (NaN equal to NaN).
static void s_result_equal (const ms_siap_result_t *a, const ms_siap_result_t *b)
{
#define S_SAME(f)                                                                                  \
    do {                                                                                           \
        double x_ = (double)a->f, y_ = (double)b->f;                                               \
        if (!(x_ == y_ || (isnan (x_) && isnan (y_))))                                             \
            fail_msg ("%s: %.17g != %.17g", #f, x_, y_);                                           \
    } while (0)
    S_SAME (runs);
    S_SAME (scans);
    S_SAME (truth_scans);
    S_SAME (tracked_truth_scans);
    S_SAME (track_scans);
    S_SAME (associated_track_scans);
    S_SAME (unknown_truth_scans);
    S_SAME (unseen_track_scans);
    S_SAME (position_error_m);
    S_SAME (truth_time_s);
    S_SAME (run_time_s);
    S_SAME (swaps);
    S_SAME (breaks);
    S_SAME (tracks);
    S_SAME (false_tracks);
    S_SAME (completeness);
    S_SAME (ambiguity);
    S_SAME (spuriousness);
    S_SAME (spuriousness_unseen);
    S_SAME (position_accuracy_m);
    S_SAME (swaps_per_truth_hour);
    S_SAME (breaks_per_truth_hour);
    S_SAME (false_tracks_per_hour);
    S_SAME (id.identifiable);
    S_SAME (id.identifiable_marked);
    S_SAME (id.marked);
    S_SAME (id.correct);
    S_SAME (id.wrong);
    S_SAME (id.hostile_marked);
    S_SAME (id_completeness);
    S_SAME (id_correctness);
    S_SAME (id_wrong_fraction);
#undef S_SAME
}

/* The scripted run: truths T1 (id 1) and T2 (id 2), tracks 10, 11, 12, five
 * scans 60 s apart. "10→T1 5" is track 10 associated to T1, 5 m from it.
 *
 *  k  t_s  truths   tracks                              J JT N NA  events
 *  1    0  T1 T2    10→T1 5, 11→T2 10                   2  2 2  2  T1 primary 10, T2 11
 *  2   60  T1 T2    10→T1 5, 11→T2 10, 12→none          2  2 3  2
 *  3  120  T1 T2    10→none, 11→T1 10, 12→none          2  1 3  1  T1 10→11: swap;
 *                                                                  T2 lost 11: break
 *  4  180  T1 T2    10→T1 20, 11→T1 5, 12→none          2  1 3  2  T1 keeps 11 (not the
 *                                                                  lower 10): no swap
 *  5  240  T1       10→T2 (absent), 11→none             1  0 2  0  T1 lost 11: break;
 *                                                                  10 names an absent truth
 *  Σ                                                    9  6 13 7
 *
 *  completeness  6 / 9 = 0.666667        ambiguity 7 / 6 = 1.166667
 *  spuriousness  (13 − 7) / 13 = 0.461538
 *  PA            (5 + 10 + 5 + 10 + 10 + 20 + 5) / 7 = 65 / 7 = 9.285714 m (mean)
 *  truth time    scan 1: 0; scans 2-4: 60 s × 2; scan 5: 60 s × 1 = 420 s = 0.116667 h
 *  swaps 1       → 1 / 0.116667 h = 8.571429 per truth-hour
 *  breaks 2      → 2 / 0.116667 h = 17.142857 per truth-hour
 *  false tracks  12 only (10 and 11 were associated): 1 in 240 s = 1/15 h → 15 per hour
 *  tracks 3, unknown-truth track-scans 1, runs 1, scans 5.
 *  The caller flags two tracks as holding an unseen vehicle: 10 at scan 5
 *  (unassociated: counted) and 10 at scan 1 (associated: not counted):
 *  unseen track-scans 1, spuriousness_unseen 1 / 13. */
static ms_siap_truth_t s_t (uint32_t id, double e, double n)
{
    return (ms_siap_truth_t){.id = id, .pos = {e, n}};
}

static ms_siap_track_t s_k (uint32_t id, uint32_t truth, double e, double n)
{
    return (ms_siap_track_t){.id = id, .truth_id = truth, .pos = {e, n}};
}

static ms_siap_track_t s_ku (uint32_t id, uint32_t truth, double e, double n)
{
    return (ms_siap_track_t){.id = id, .truth_id = truth, .pos = {e, n}, .truth_unseen = true};
}

static void s_feed_run (ms_siap_t *acc, int first_scan, int last_scan)
{
    ms_siap_truth_t tr[5][2] = {
        {s_t (1, 0, 0), s_t (2, 1000, 0)},
        {s_t (1, 100, 0), s_t (2, 1100, 0)},
        {s_t (1, 200, 0), s_t (2, 1200, 0)},
        {s_t (1, 300, 0), s_t (2, 1300, 0)},
        {s_t (1, 400, 0)},
    };
    size_t n_tr[5] = {2, 2, 2, 2, 1};
    ms_siap_track_t tk[5][3] = {
        {s_ku (10, 1, 3, 4), s_k (11, 2, 1006, 8)},
        {s_k (10, 1, 100, 5), s_k (11, 2, 1100, 10), s_k (12, 0, 500, 500)},
        {s_k (10, 0, 260, 0), s_k (11, 1, 206, 8), s_k (12, 0, 600, 600)},
        {s_k (10, 1, 300, 20), s_k (11, 1, 303, 4), s_k (12, 0, 700, 700)},
        {s_ku (10, 2, 400, 30), s_k (11, 0, 450, 0)},
    };
    size_t n_tk[5] = {2, 3, 3, 3, 2};
    for (int k = first_scan; k <= last_scan; k++)
        assert_int_equal (
            ms_siap_add (acc, 60.0 * (k - 1), tr[k - 1], n_tr[k - 1], tk[k - 1], n_tk[k - 1]), 0);
}

static void test_siap_scripted (void **state)
{
    (void)state;
    ms_siap_t *acc = ms_siap_new ();
    assert_non_null (acc);
    s_feed_run (acc, 1, 5);
    ms_siap_result_t r;
    ms_siap_result (acc, &r);
    assert_int_equal (r.runs, 1);
    assert_int_equal (r.scans, 5);
    assert_int_equal (r.truth_scans, 9);
    assert_int_equal (r.tracked_truth_scans, 6);
    assert_int_equal (r.track_scans, 13);
    assert_int_equal (r.associated_track_scans, 7);
    assert_int_equal (r.unknown_truth_scans, 1);
    assert_near (r.position_error_m, 65, 1e-12);
    assert_near (r.truth_time_s, 420, 1e-12);
    assert_near (r.run_time_s, 240, 1e-12);
    assert_int_equal (r.swaps, 1);
    assert_int_equal (r.breaks, 2);
    assert_int_equal (r.tracks, 3);
    assert_int_equal (r.false_tracks, 1);
    assert_near (r.completeness, 6.0 / 9, 1e-15);
    assert_near (r.ambiguity, 7.0 / 6, 1e-15);
    assert_near (r.spuriousness, 6.0 / 13, 1e-15);
    assert_int_equal (r.unseen_track_scans, 1);
    assert_near (r.spuriousness_unseen, 1.0 / 13, 1e-15);
    assert_near (r.position_accuracy_m, 65.0 / 7, 1e-12);
    assert_near (r.swaps_per_truth_hour, 60.0 / 7, 1e-12);
    assert_near (r.breaks_per_truth_hour, 120.0 / 7, 1e-12);
    assert_near (r.false_tracks_per_hour, 15, 1e-12);
    // No identity given (zero-initialised): no identification count, NaN figures.
    assert_int_equal (r.id.identifiable, 0);
    assert_int_equal (r.id.marked, 0);
    assert_true (isnan (r.id_completeness) && isnan (r.id_correctness));
    // Ending the run changes no figure.
    ms_siap_end_run (acc);
    ms_siap_result_t after;
    ms_siap_result (acc, &after);
    s_result_equal (&after, &r);
    ms_siap_destroy (&acc);
    assert_null (acc);
    ms_siap_destroy (&acc);
}

/* The primary-track rules, one truth (id 1), scans 1 s apart, every track on
 * the truth's position (PA 0):
 *  k  t_s  truth  tracks on T1   primary  events
 *  1   0   T1     5              5        first primary: no swap
 *  2   1   T1     -              (5)      break
 *  3   2   T1     5              5        remembered across the gap: no swap
 *  4   3   T1     7, 3           3        5 gone, lowest id: swap 5→3
 *  5   4   T1     3, 1           3        kept although 1 is lower: no swap
 *  6   5   -      3→T1 (absent)           unassociated, no break (T1 absent)
 * J 5, JT 4, N 1+0+1+2+2+1 = 7, NA 6: completeness 0.8, ambiguity 1.5,
 * spuriousness 1/7; truth time 4 × 1 s = 4 s: swaps 1 and breaks 1, each
 * 1 / (4/3600 h) = 900 per truth-hour; tracks 5, 7, 3, 1 all associated: no
 * false track, 0 per hour over 5 s. */
static void s_feed_rules (ms_siap_t *acc)
{
    ms_siap_truth_t t1 = s_t (1, 50, 50);
    ms_siap_track_t k5 = s_k (5, 1, 50, 50), k34[2] = {s_k (7, 1, 50, 50), s_k (3, 1, 50, 50)},
                    k31[2] = {s_k (3, 1, 50, 50), s_k (1, 1, 50, 50)}, k3 = s_k (3, 1, 60, 60);
    assert_int_equal (ms_siap_add (acc, 0, &t1, 1, &k5, 1), 0);
    assert_int_equal (ms_siap_add (acc, 1, &t1, 1, NULL, 0), 0);
    assert_int_equal (ms_siap_add (acc, 2, &t1, 1, &k5, 1), 0);
    assert_int_equal (ms_siap_add (acc, 3, &t1, 1, k34, 2), 0);
    assert_int_equal (ms_siap_add (acc, 4, &t1, 1, k31, 2), 0);
    assert_int_equal (ms_siap_add (acc, 5, NULL, 0, &k3, 1), 0);
}

static void test_siap_primary_rules (void **state)
{
    (void)state;
    ms_siap_t *acc = ms_siap_new ();
    assert_non_null (acc);
    s_feed_rules (acc);
    ms_siap_result_t r;
    ms_siap_result (acc, &r);
    assert_int_equal (r.swaps, 1);
    assert_int_equal (r.breaks, 1);
    assert_int_equal (r.truth_scans, 5);
    assert_int_equal (r.tracked_truth_scans, 4);
    assert_int_equal (r.track_scans, 7);
    assert_int_equal (r.associated_track_scans, 6);
    assert_int_equal (r.unknown_truth_scans, 1);
    assert_near (r.completeness, 0.8, 1e-15);
    assert_near (r.ambiguity, 1.5, 1e-15);
    assert_near (r.spuriousness, 1.0 / 7, 1e-15);
    assert_true (r.position_accuracy_m == 0);
    assert_near (r.truth_time_s, 4, 1e-12);
    assert_near (r.swaps_per_truth_hour, 900, 1e-9);
    assert_near (r.breaks_per_truth_hour, 900, 1e-9);
    assert_int_equal (r.tracks, 4);
    assert_int_equal (r.false_tracks, 0);
    assert_true (r.false_tracks_per_hour == 0);
    ms_siap_destroy (&acc);
}

// No scan: every count 0, every figure NaN. One scan: run time 0, so false
// tracks per hour (and per truth-hour rates) NaN, not a division by zero.
static void test_siap_empty (void **state)
{
    (void)state;
    ms_siap_t *acc = ms_siap_new ();
    assert_non_null (acc);
    ms_siap_result_t r;
    ms_siap_result (acc, &r);
    assert_int_equal (r.runs, 0);
    assert_int_equal (r.scans, 0);
    assert_int_equal (r.tracks, 0);
    assert_true (isnan (r.completeness) && isnan (r.ambiguity) && isnan (r.spuriousness));
    assert_true (isnan (r.position_accuracy_m) && isnan (r.swaps_per_truth_hour));
    assert_true (isnan (r.breaks_per_truth_hour) && isnan (r.false_tracks_per_hour));
    assert_true (isnan (r.id_completeness) && isnan (r.id_correctness));
    assert_true (isnan (r.id_wrong_fraction) && r.id.marked == 0 && r.id.identifiable == 0);
    ms_siap_end_run (acc); // nothing under way: no run counted
    ms_siap_result (acc, &r);
    assert_int_equal (r.runs, 0);
    ms_siap_track_t k = s_k (4, 0, 0, 0);
    assert_int_equal (ms_siap_add (acc, 10, NULL, 0, &k, 1), 0);
    ms_siap_result (acc, &r);
    assert_int_equal (r.runs, 1);
    assert_int_equal (r.false_tracks, 1);
    assert_true (r.spuriousness == 1);
    assert_true (isnan (r.completeness) && isnan (r.false_tracks_per_hour));
    assert_true (r.run_time_s == 0);
    ms_siap_destroy (&acc);
    ms_siap_destroy (NULL);
}

// Refused scans change nothing: an accumulator fed the run with refused scans
// among its scans ends equal to one fed the run alone.
static void test_siap_errors (void **state)
{
    (void)state;
    ms_siap_t *acc = ms_siap_new (), *ref = ms_siap_new ();
    assert_non_null (acc);
    assert_non_null (ref);
    s_feed_run (ref, 1, 5);
    s_feed_run (acc, 1, 2);
    ms_siap_truth_t t2[2] = {s_t (1, 0, 0), s_t (9, 0, 0)}, dup[2] = {s_t (9, 0, 0), s_t (9, 1, 1)};
    ms_siap_truth_t zero = s_t (0, 0, 0), nan_t = s_t (3, NAN, 0);
    ms_siap_track_t k2[2] = {s_k (10, 1, 0, 0), s_k (12, 0, 0, 0)};
    ms_siap_track_t kdup[2] = {s_k (10, 1, 0, 0), s_k (10, 9, 0, 0)};
    ms_siap_track_t kzero = s_k (0, 1, 0, 0), kinf = s_k (10, 1, 0, -INFINITY);
    assert_int_equal (ms_siap_add (acc, 60, t2, 2, k2, 2), -EINVAL);       // not later
    assert_int_equal (ms_siap_add (acc, 30, t2, 2, k2, 2), -EINVAL);       // earlier
    assert_int_equal (ms_siap_add (acc, NAN, t2, 2, k2, 2), -EINVAL);      // not finite
    assert_int_equal (ms_siap_add (acc, INFINITY, t2, 2, k2, 2), -EINVAL); // not finite
    assert_int_equal (ms_siap_add (acc, 100, dup, 2, k2, 2), -EINVAL);     // truth repeated
    assert_int_equal (ms_siap_add (acc, 100, &zero, 1, k2, 2), -EINVAL);   // truth id 0
    assert_int_equal (ms_siap_add (acc, 100, &nan_t, 1, k2, 2), -EINVAL);  // position
    assert_int_equal (ms_siap_add (acc, 100, t2, 2, kdup, 2), -EINVAL);    // track repeated
    assert_int_equal (ms_siap_add (acc, 100, t2, 2, &kzero, 1), -EINVAL);  // track id 0
    assert_int_equal (ms_siap_add (acc, 100, t2, 2, &kinf, 1), -EINVAL);   // position
    assert_int_equal (ms_siap_add (acc, 100, NULL, 1, k2, 2), -EINVAL);    // NULL truths
    assert_int_equal (ms_siap_add (acc, 100, t2, 2, NULL, 2), -EINVAL);    // NULL tracks
    assert_int_equal (ms_siap_merge (acc, acc), -EINVAL);
    s_feed_run (acc, 3, 5);
    ms_siap_result_t a, b;
    ms_siap_result (acc, &a);
    ms_siap_result (ref, &b);
    s_result_equal (&a, &b);
    ms_siap_destroy (&acc);
    ms_siap_destroy (&ref);
}

/* Pooling two runs: run A, the scripted run (swaps 1, breaks 2, J 9, JT 6,
 * N 13, NA 7, unknown 1, error 65 m, truth time 420 s, run time 240 s,
 * tracks 3, false 1), and run B, the rules run (swaps 1, breaks 1, J 5, JT 4,
 * N 7, NA 6, unknown 1, error 0, truth time 4 s, run time 5 s, tracks 4,
 * false 0). B reuses truth id 1 and restarts its clock at 0: the run's end
 * must forget T1's primary (11), or B's first scan would count a swap.
 * Whole (A, end of run, B) = merge of an accumulator of A and one of B, in
 * either order: runs 2, swaps 2, breaks 3, J 14, JT 10, N 20, NA 13, unknown
 * 2, error 65 m, truth time 424 s, run time 245 s, tracks 7, false 1;
 * completeness 10/14, ambiguity 13/10, spuriousness 7/20, PA 65/13 = 5 m,
 * swaps 2 / (424/3600 h) = 16.98, breaks 3 / (424/3600 h) = 25.47 per
 * truth-hour, false 1 / (245/3600 h) = 14.69 per hour.
 *
 * What does not pool: run A split after its scan 2 into two accumulators.
 * The first saw scans 1-2, the second 3-5 as a run of its own: the swap and
 * T2's break at scan 3 are lost (T1 and T2 are new there), T1's break at scan
 * 5 stays; the 60 s from scan 2 to 3 is lost: run time 60 + 120 = 180 s,
 * truth time 60·2 + (60·2 + 60·1) = 300 s; track 12 is counted in both parts:
 * tracks 3 + 3 = 6, false 1 + 1 = 2; the per-scan counts (J 9, JT 6, N 13,
 * NA 7, error 65 m) pool exactly. */
/* Results of whole runs pooled by their raw counts (as Monte Carlo worker
 * processes send them back) equal the accumulators merged. */
static void test_siap_result_pool (void **state)
{
    (void)state;
    ms_siap_t *whole = ms_siap_new (), *a = ms_siap_new (), *b = ms_siap_new ();
    assert_true (whole && a && b);
    s_feed_run (whole, 1, 5);
    ms_siap_end_run (whole);
    s_feed_rules (whole);
    s_feed_run (a, 1, 5);
    ms_siap_end_run (a);
    s_feed_rules (b);
    ms_siap_end_run (b);
    ms_siap_result_t w, ra, rb, pooled = {0};
    ms_siap_result (whole, &w);
    ms_siap_result (a, &ra);
    ms_siap_result (b, &rb);
    ms_siap_result_pool (&pooled, &ra);
    ms_siap_result_pool (&pooled, &rb);
    s_result_equal (&pooled, &w);
    ms_siap_destroy (&whole);
    ms_siap_destroy (&a);
    ms_siap_destroy (&b);
}

static void test_siap_merge (void **state)
{
    (void)state;
    ms_siap_t *whole = ms_siap_new (), *a = ms_siap_new (), *b = ms_siap_new ();
    ms_siap_t *a2 = ms_siap_new (), *b2 = ms_siap_new ();
    assert_true (whole && a && b && a2 && b2);
    s_feed_run (whole, 1, 5);
    ms_siap_end_run (whole);
    s_feed_rules (whole);
    s_feed_run (a, 1, 5);
    s_feed_rules (b);
    s_feed_run (a2, 1, 5);
    s_feed_rules (b2);
    assert_int_equal (ms_siap_merge (a, b), 0);
    assert_int_equal (ms_siap_merge (b2, a2), 0);
    ms_siap_result_t w, m, m2;
    ms_siap_result (whole, &w);
    ms_siap_result (a, &m);
    ms_siap_result (b2, &m2);
    s_result_equal (&m, &w);
    s_result_equal (&m2, &w);
    assert_int_equal (w.runs, 2);
    assert_int_equal (w.swaps, 2);
    assert_int_equal (w.breaks, 3);
    assert_int_equal (w.truth_scans, 14);
    assert_int_equal (w.tracked_truth_scans, 10);
    assert_int_equal (w.track_scans, 20);
    assert_int_equal (w.associated_track_scans, 13);
    assert_int_equal (w.unknown_truth_scans, 2);
    assert_int_equal (w.tracks, 7);
    assert_int_equal (w.false_tracks, 1);
    assert_near (w.truth_time_s, 424, 1e-12);
    assert_near (w.run_time_s, 245, 1e-12);
    assert_near (w.completeness, 10.0 / 14, 1e-15);
    assert_near (w.ambiguity, 1.3, 1e-15);
    assert_near (w.spuriousness, 0.35, 1e-15);
    assert_near (w.position_accuracy_m, 5, 1e-12);
    assert_near (w.swaps_per_truth_hour, 2 * 3600.0 / 424, 1e-9);
    assert_near (w.breaks_per_truth_hour, 3 * 3600.0 / 424, 1e-9);
    assert_near (w.false_tracks_per_hour, 3600.0 / 245, 1e-9);
    // dst's own run goes on after a merge: a's run under way is still A (last
    // scan at 240 s), so an earlier scan is refused and a later one taken, and
    // T1's primary there (11) is remembered: track 9 alone on T1 is a swap.
    ms_siap_truth_t t1 = s_t (1, 0, 0);
    ms_siap_track_t k9 = s_k (9, 1, 3, 4);
    assert_int_equal (ms_siap_add (a, 100, &t1, 1, &k9, 1), -EINVAL);
    assert_int_equal (ms_siap_add (a, 300, &t1, 1, &k9, 1), 0);
    ms_siap_result (a, &m);
    assert_int_equal (m.swaps, 3);
    assert_int_equal (m.runs, 2);

    // One run split in two does not pool.
    ms_siap_t *p1 = ms_siap_new (), *p2 = ms_siap_new ();
    assert_true (p1 && p2);
    s_feed_run (p1, 1, 2);
    s_feed_run (p2, 3, 5);
    assert_int_equal (ms_siap_merge (p1, p2), 0);
    ms_siap_result_t s;
    ms_siap_result (p1, &s);
    assert_int_equal (s.runs, 2);
    assert_int_equal (s.swaps, 0);
    assert_int_equal (s.breaks, 1);
    assert_near (s.run_time_s, 180, 1e-12);
    assert_near (s.truth_time_s, 300, 1e-12);
    assert_int_equal (s.tracks, 6);
    assert_int_equal (s.false_tracks, 2);
    assert_int_equal (s.truth_scans, 9);
    assert_int_equal (s.tracked_truth_scans, 6);
    assert_int_equal (s.track_scans, 13);
    assert_int_equal (s.associated_track_scans, 7);
    assert_near (s.position_error_m, 65, 1e-12);
    ms_siap_destroy (&p1);
    ms_siap_destroy (&p2);
    ms_siap_destroy (&whole);
    ms_siap_destroy (&a);
    ms_siap_destroy (&b);
    ms_siap_destroy (&a2);
    ms_siap_destroy (&b2);
}

/* Identification, by hand. Truths: T1 (id 1) friendly with a transponder,
 * identity 1; T2 (id 2) hostile, no identity; T3 (id 3) friendly without
 * a transponder, no identity. "10→T1 c1" is track 10 associated to T1,
 * claiming identity 1 (c0: claiming none). Every track on its truth.
 *
 *  k  t_s  tracks                               identifiable  marked  correct  wrong  hostile
 *  1   0   10→T1 c1   right                     10            10      10
 *          11→T1 c7   another id                11            11               11
 *          12→T2 c1   hostile marked friendly                 12               12     12
 *          13→T3 c0   nothing claimed, none due
 *          14→none c1 unassociated: not counted
 *  2  10   10→T1 c0   identifiable, unmarked    10
 *          12→T2 c0   nothing claimed
 *          13→T3 c3   claims what T3 cannot say                        13
 *          15→T9 c9   T9 absent: not counted
 *  Σ  identifiable 3 (of which marked 2: 10 and 11 at scan 1), marked 4,
 *     correct 1, wrong 3, hostile marked 1
 *  ID completeness 2/3, ID correctness 1/4, ID wrong 3/4. */
static void s_feed_identity (ms_siap_t *acc)
{
    ms_siap_truth_t tr[3] = {s_t (1, 0, 0), s_t (2, 1000, 0), s_t (3, 2000, 0)};
    tr[0].identity = 1;
    tr[1].hostile = true;
    ms_siap_track_t k1[5] = {s_k (10, 1, 0, 0), s_k (11, 1, 0, 0), s_k (12, 2, 1000, 0),
                             s_k (13, 3, 2000, 0), s_k (14, 0, 5000, 0)};
    const uint32_t c1[5] = {1, 7, 1, 0, 1};
    for (int j = 0; j < 5; j++)
        k1[j].claimed_id = c1[j];
    ms_siap_track_t k2[4] = {s_k (10, 1, 0, 0), s_k (12, 2, 1000, 0), s_k (13, 3, 2000, 0),
                             s_k (15, 9, 0, 0)};
    k2[2].claimed_id = 3;
    k2[3].claimed_id = 9;
    assert_int_equal (ms_siap_add (acc, 0, tr, 3, k1, 5), 0);
    assert_int_equal (ms_siap_add (acc, 10, tr, 3, k2, 4), 0);
}

static void test_siap_identity (void **state)
{
    (void)state;
    ms_siap_t *acc = ms_siap_new (), *whole = ms_siap_new (), *b = ms_siap_new (),
              *c = ms_siap_new ();
    assert_true (acc && whole && b && c);
    s_feed_identity (acc);
    ms_siap_result_t r;
    ms_siap_result (acc, &r);
    assert_int_equal (r.associated_track_scans, 7);
    assert_int_equal (r.unknown_truth_scans, 1);
    // identifiable, of those marked, marked, correct, wrong, hostile marked:
    // one run, and two runs of it.
    const ms_siap_id_t one = {3, 2, 4, 1, 3, 1}, two = {6, 4, 8, 2, 6, 2};
    assert_memory_equal (&r.id, &one, sizeof one);
    assert_near (r.id_completeness, 2.0 / 3, 1e-15);
    assert_near (r.id_correctness, 0.25, 1e-15);
    assert_near (r.id_wrong_fraction, 0.75, 1e-15);

    // Two accumulators of one run each, merged (either way) or their results
    // pooled, count what one accumulator fed both runs counts: every count
    // doubled, the same figures.
    s_feed_identity (whole);
    ms_siap_end_run (whole);
    s_feed_identity (whole);
    s_feed_identity (b);
    s_feed_identity (c);
    ms_siap_result_t w, rb, pooled = {0}, merged;
    ms_siap_result (whole, &w);
    assert_memory_equal (&w.id, &two, sizeof two);
    assert_true (w.id_completeness == r.id_completeness && w.id_correctness == r.id_correctness &&
                 w.id_wrong_fraction == r.id_wrong_fraction);
    ms_siap_result (b, &rb);
    ms_siap_result_pool (&pooled, &r);
    ms_siap_result_pool (&pooled, &rb);
    s_result_equal (&pooled, &w);
    assert_int_equal (ms_siap_merge (b, acc), 0);
    ms_siap_result (b, &merged);
    s_result_equal (&merged, &w);
    assert_int_equal (ms_siap_merge (acc, c), 0);
    ms_siap_result (acc, &merged);
    s_result_equal (&merged, &w);
    ms_siap_destroy (&acc);
    ms_siap_destroy (&whole);
    ms_siap_destroy (&b);
    ms_siap_destroy (&c);
}

// Hundreds of truths and thousands of track ids: the tables grow, and
// completeness and the false-track count come out as constructed. 300
// truths (ids 1..300) for 50 scans 10 s apart; truth i is tracked by track
// 100000 + i on even-numbered truths only; each scan adds 20 new false
// tracks (ids 1..1000 never reused): J 15000, JT 7500, N 50·150 + 1000 =
// 8500, NA 7500, false 1000 over 490 s.
static void test_siap_growth (void **state)
{
    (void)state;
    ms_siap_t *acc = ms_siap_new ();
    assert_non_null (acc);
    static ms_siap_truth_t tr[300];
    static ms_siap_track_t tk[170];
    for (int k = 0; k < 50; k++) {
        size_t n = 0;
        for (uint32_t i = 1; i <= 300; i++) {
            tr[i - 1] = s_t (i, 100.0 * i, 10.0 * k);
            if (i % 2 == 0)
                tk[n++] = s_k (100000 + i, i, 100.0 * i, 10.0 * k + 3);
        }
        for (uint32_t f = 0; f < 20; f++)
            tk[n++] = s_k (1 + (uint32_t)k * 20 + f, 0, -1000, 0);
        assert_int_equal (ms_siap_add (acc, 10.0 * k, tr, 300, tk, n), 0);
    }
    ms_siap_result_t r;
    ms_siap_result (acc, &r);
    assert_int_equal (r.truth_scans, 15000);
    assert_int_equal (r.tracked_truth_scans, 7500);
    assert_int_equal (r.track_scans, 8500);
    assert_int_equal (r.associated_track_scans, 7500);
    assert_int_equal (r.tracks, 1150);
    assert_int_equal (r.false_tracks, 1000);
    assert_int_equal (r.swaps, 0);
    assert_int_equal (r.breaks, 0);
    assert_near (r.completeness, 0.5, 1e-15);
    assert_near (r.position_accuracy_m, 3, 1e-12);
    assert_near (r.false_tracks_per_hour, 1000 * 3600.0 / 490, 1e-9);
    ms_siap_destroy (&acc);
}

int main (void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test (test_gospa_empty),
        cmocka_unit_test (test_gospa_missed_only),
        cmocka_unit_test (test_gospa_one_pair),
        cmocka_unit_test (test_gospa_pair_beyond_cutoff),
        cmocka_unit_test (test_gospa_greedy_loses),
        cmocka_unit_test (test_gospa_brute_force),
        cmocka_unit_test (test_gospa_min_cost_flow),
        cmocka_unit_test (test_gospa_speed),
        cmocka_unit_test (test_gospa_errors),
        cmocka_unit_test (test_gospa_mean),
        cmocka_unit_test (test_siap_scripted),
        cmocka_unit_test (test_siap_primary_rules),
        cmocka_unit_test (test_siap_empty),
        cmocka_unit_test (test_siap_errors),
        cmocka_unit_test (test_siap_merge),
        cmocka_unit_test (test_siap_result_pool),
        cmocka_unit_test (test_siap_growth),
        cmocka_unit_test (test_siap_identity),
    };
    return cmocka_run_group_tests (tests, NULL, NULL);
}
