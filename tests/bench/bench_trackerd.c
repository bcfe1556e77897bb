/* bench_trackerd — the cost of one radar scan in trackerd's core: gating,
 * the assignment and the filter updates, tentative tracks born and killed,
 * with N targets and N confirmed tracks plus false alarms (10% of N, spread
 * uniformly), at the default parameters (deploy/params/tracker.ini).
 * Targets move at 5..20 m/s in random directions, hit every scan with 25 m
 * noise per axis and a radial velocity; the tracker runs 12 scans to settle,
 * then each of R scans is timed on one core (CPU time) and the median kept.
 * Two densities: constant density (one target per square kilometre, the
 * area grows with N), and one fixed area (the radar's 20 km disc, about
 * 1,260 km², so the targets crowd and clusters grow with N). Goals: under
 * 20 ms for 1,000 tracks and 1,000 hits (+ false alarms), and growth to
 * 10,000 near-linear (time per track within 2x of the 1,000 case).
 * Usage: bench_trackerd [--runs R] (other options, meant for other
 * benchmarks, are ignored). */
#include "bench_util.h"
#include "trk_params.h"
#include "trk_tracker.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define S_PI 3.14159265358979323846

static uint64_t s_state = 0x853c49e6748fea9bull;
static double s_uniform (void)
{
    s_state = s_state * 6364136223846793005ull + 1442695040888963407ull;
    return ((double)(s_state >> 11) + 0.5) / 9007199254740992.0;
}
static double s_gauss (void)
{
    return sqrt (-2 * log (s_uniform ())) * cos (2 * S_PI * s_uniform ());
}

typedef struct {
    double p[2], v[2], offset_s;
} s_target_t;

typedef struct {
    double scan_cpu_s;   // median
    size_t tracks, hits; // in the timed scans (last one)
    size_t largest;      // largest cluster
    size_t greedy;       // clusters assigned greedily (too large to solve optimally)
} s_result_t;

/* One configuration: n targets over a square of side side_m. 0, -ENOMEM, or
 * what trk_tracker_scan returned. */
static int s_run (const trk_params_t *p, size_t n, double side_m, int runs, s_result_t *ret)
{
    trk_tracker_t *trk = trk_tracker_new (p);
    size_t nfa = n / 10;
    s_target_t *tg = calloc (n, sizeof *tg);
    trk_hit_t *hits = calloc (n + nfa, sizeof *hits);
    double *times = calloc ((size_t)runs, sizeof *times);
    int rc = 0;
    if (!trk || !tg || !hits || !times) {
        rc = -ENOMEM;
        goto done;
    }
    double radar[2] = {side_m / 2, -5000};
    for (size_t i = 0; i < n; i++) {
        double h = 2 * S_PI * s_uniform (), s = 5 + 15 * s_uniform ();
        tg[i] = (s_target_t){{side_m * s_uniform (), side_m * s_uniform ()},
                             {s * sin (h), s * cos (h)},
                             9 * s_uniform ()};
    }
    int warm = 12;
    uint32_t id = 1;
    s_result_t r = {0};
    for (int k = 0; k < warm + runs; k++) {
        size_t m = 0;
        for (size_t i = 0; i < n; i++) {
            double t = 10.0 * k + tg[i].offset_s;
            double x = tg[i].p[0] + tg[i].v[0] * t, y = tg[i].p[1] + tg[i].v[1] * t;
            double de = x - radar[0], dn = y - radar[1], rr = hypot (de, dn);
            hits[m++] = (trk_hit_t){
                .hit_id = id++,
                .t_s = t,
                .z = {x + 25 * s_gauss (), y + 25 * s_gauss ()},
                .has_radial = true,
                .los = {de / rr, dn / rr},
                .radial_mps = (de * tg[i].v[0] + dn * tg[i].v[1]) / rr + 0.3 * s_gauss (),
            };
        }
        for (size_t i = 0; i < nfa; i++) {
            double x = side_m * s_uniform (), y = side_m * s_uniform ();
            double de = x - radar[0], dn = y - radar[1], rr = hypot (de, dn);
            hits[m++] = (trk_hit_t){.hit_id = id++,
                                    .t_s = 10.0 * k + 9 * s_uniform (),
                                    .z = {x, y},
                                    .has_radial = true,
                                    .los = {de / rr, dn / rr},
                                    .radial_mps = 20 * (s_uniform () - 0.5)};
        }
        trk_scan_t scan = {.uav_id = 1,
                           .scan_number = (uint32_t)k + 1,
                           .start_s = 10.0 * k,
                           .end_s = 10.0 * k + 10,
                           .full_revolution = true,
                           .platform = {radar[0], radar[1]}};
        trk_scan_out_t out;
        double t0 = bench_cpu_s ();
        rc = trk_tracker_scan (trk, &scan, hits, m, &out);
        if (rc < 0)
            goto done;
        double dt = bench_cpu_s () - t0;
        if (k >= warm) {
            times[k - warm] = dt;
            r.tracks = trk_tracker_count (trk);
            r.hits = m;
            if (out.largest_cluster > r.largest)
                r.largest = out.largest_cluster;
            r.greedy += out.greedy_clusters;
        }
    }
    r.scan_cpu_s = bench_median (times, runs);
    *ret = r;
done:
    trk_tracker_destroy (&trk);
    free (tg);
    free (hits);
    free (times);
    return rc;
}

int main (int argc, char **argv)
{
    int runs = 7;
    for (int i = 1; i + 1 < argc; i++)
        if (strcmp (argv[i], "--runs") == 0)
            runs = atoi (argv[i + 1]);
    if (runs < 1)
        runs = 1;
    char path[4096], err[512];
    const char *root = getenv ("CGS_ROOT");
    snprintf (path, sizeof path, "%s/deploy/params/tracker.ini", root ? root : ".");
    trk_params_t p;
    trk_params_defaults (&p);
    if (trk_params_load (path, &p, err, sizeof err) < 0) {
        fprintf (stderr, "bench_trackerd: %s\n", err);
        return 1;
    }
    printf ("bench_trackerd: one scan of N targets (+10%% false alarms), %s filter, median of %d "
            "scans on one core\n",
            p.filter.mode == TRK_FILTER_IMM      ? "IMM (three models)"
            : p.filter.mode == TRK_FILTER_KALMAN ? "Kalman"
                                                 : "paper's",
            runs);
    const size_t ns[] = {1000, 2000, 5000, 10000};
    double per_track[2][4];
    const char *dens[] = {"density", "area"};
    for (int d = 0; d < 2; d++)
        for (size_t i = 0; i < 4; i++) {
            size_t n = ns[i];
            // Constant density: 1 per km²; fixed area: the radar's 20 km disc as a square.
            double side = d == 0 ? sqrt ((double)n) * 1000 : sqrt (S_PI) * 20000;
            s_result_t r;
            int rc = s_run (&p, n, side, runs, &r);
            if (rc < 0) {
                fprintf (stderr, "bench_trackerd: %s N=%zu: the scan failed: %s\n", dens[d], n,
                         strerror (-rc));
                printf ("verdict=FAIL: the scan of %zu targets (%s) failed: %s\n", n, dens[d],
                        strerror (-rc));
                return 1;
            }
            per_track[d][i] = r.scan_cpu_s / (double)n;
            printf ("  %-7s N=%5zu over %6.0f km2: %zu hits, %zu tracks, largest cluster %zu%s: "
                    "%.2f ms a scan (%.2f us a track)\n",
                    dens[d], n, side * side / 1e6, r.hits, r.tracks, r.largest,
                    r.greedy ? " (assigned greedily)" : "", r.scan_cpu_s * 1e3,
                    per_track[d][i] * 1e6);
            printf ("trackerd_%s_%zu_scan_ms=%.3f\n", dens[d], n, r.scan_cpu_s * 1e3);
        }
    double ms1000 = per_track[0][0] * 1000 * 1e3;
    double growth = per_track[0][3] / per_track[0][0];
    double growth_area = per_track[1][3] / per_track[1][0];
    printf ("trackerd_growth_1000_to_10000=%.2f\n", growth);
    printf ("trackerd_growth_1000_to_10000_fixed_area=%.2f\n", growth_area);
    printf ("verdict: a scan of 1,000 tracks and 1,100 hits takes %.2f ms (goal under 20 ms: %s); "
            "time per track grows %.2fx from 1,000 to 10,000 at constant density (goal within "
            "2x, near-linear: %s), %.2fx when they crowd one area\n",
            ms1000, ms1000 < 20 ? "met" : "NOT met", growth, growth < 2 ? "met" : "NOT met",
            growth_area);
    return 0;
}
