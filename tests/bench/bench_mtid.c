/* bench_mtid — the MTI model's cost at the nominal parameters (the defaults,
 * deploy/params/radar.ini): one full scan (a revolution of 10 s at 36°/s,
 * 120 dwells) over T ground movers spread at random 1 to 19 km from the UAV
 * of the default scenario, moving at 3 to 15 m/s, timed on one core over R
 * scans. Two worlds: flat ground (every mover in view: each goes through the
 * whole chain — the worst case) and the default scenario's hills (line of
 * sight cuts some off, but every target and clutter cell costs a line-of-sight
 * query over the terrain grid). Figures: the cost of one dwell per target in
 * microseconds (median over runs), the FFT's share of it (FFTW's execute
 * timed alone, times the transforms a dwell does), and the ground movers
 * mtid keeps up with in real time on one core: scan time / cost per mover
 * per scan, for the slower of the two worlds. Goal: at least 10,000.
 * Usage: bench_mtid [--runs R] [--movers T]
 * (other options, meant for other benchmarks, are ignored). */
#include "bench_util.h"
#include "cgs_scenario.h"
#include "mti_params.h"
#include "mti_radar.h"

#include <complex.h>
#include <fftw3.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define S_GOAL 10000.0

/* A FFTW plan of the chain's size, executed alone: seconds per transform. */
static double s_fft_cost (int n)
{
    fftw_complex *b = fftw_malloc (sizeof (fftw_complex) * n);
    fftw_plan p = fftw_plan_dft_1d (n, b, b, FFTW_FORWARD, FFTW_ESTIMATE);
    for (int i = 0; i < n; i++)
        ((double complex *)b)[i] = cos (i) + I * sin (2 * i);
    int reps = 2000000;
    double c0 = bench_cpu_s ();
    for (int r = 0; r < reps; r++)
        fftw_execute (p);
    double t = (bench_cpu_s () - c0) / reps;
    fftw_destroy_plan (p);
    fftw_free (b);
    return t;
}

typedef struct {
    double scan_s;           // CPU seconds per scan, median
    double per_target_us;    // per target through the chain, median
    size_t in_beam, chained; // per scan
    uint64_t hits, fas;
} s_result_t;

static s_result_t s_run (const mti_params_t *p, const cgs_terrain_t *terrain, cgs_enu_t uav,
                         size_t movers, int runs)
{
    mti_radar_t *radar = mti_radar_new (p, terrain, 7);
    mti_target_t *tg = calloc (movers, sizeof *tg);
    if (!radar || !tg) {
        fprintf (stderr, "bench_mtid: out of memory\n");
        exit (1);
    }
    srand (3);
    for (size_t i = 0; i < movers; i++) {
        double r = 1000 + 18000 * sqrt ((double)rand () / RAND_MAX),
               a = 2 * M_PI * rand () / RAND_MAX;
        double e = uav.e_m + r * sin (a), n = uav.n_m + r * cos (a);
        double v = 3 + 12.0 * rand () / RAND_MAX, h = 2 * M_PI * rand () / RAND_MAX;
        double z = terrain ? cgs_terrain_height_clamped (terrain, e, n) : 0;
        tg[i] = (mti_target_t){.id = (uint32_t)i + 10,
                               .position = {e, n, z},
                               .velocity = {v * sin (h), v * cos (h), 0},
                               .rcs_class = "vehicle"};
    }
    mti_platform_t plat = {.position = uav, .velocity = {38, 0, 0}, .heading_deg = 90};
    uint32_t dwells = mti_radar_dwells_per_scan (radar);
    double *scan = calloc ((size_t)runs, sizeof *scan), *per = calloc ((size_t)runs, sizeof *per);
    s_result_t res = {0};
    for (int r = 0; r < runs; r++) {
        size_t in_beam = 0, chained = 0;
        double c0 = bench_cpu_s ();
        for (uint32_t k = 0; k < dwells; k++) {
            mti_dwell_t d;
            mti_dwell_out_t out;
            mti_radar_schedule (radar, (uint64_t)r * dwells + k, 90, &d);
            if (mti_radar_dwell (radar, &d, &plat, tg, movers, &out) < 0) {
                fprintf (stderr, "bench_mtid: dwell failed\n");
                exit (1);
            }
            in_beam += out.truth_count;
            for (size_t i = 0; i < out.truth_count; i++)
                chained += out.truth[i].visible;
            res.hits += out.hit_count - out.false_alarms;
            res.fas += out.false_alarms;
        }
        scan[r] = bench_cpu_s () - c0;
        per[r] = scan[r] / (chained ? chained : 1) * 1e6;
        res.in_beam = in_beam;
        res.chained = chained;
    }
    res.scan_s = bench_median (scan, runs);
    res.per_target_us = bench_median (per, runs);
    free (scan);
    free (per);
    free (tg);
    mti_radar_destroy (&radar);
    return res;
}

int main (int argc, char **argv)
{
    int runs = 5;
    size_t movers = 2000;
    for (int i = 1; i < argc; i++) {
        if (strcmp (argv[i], "--runs") == 0 && i + 1 < argc)
            runs = atoi (argv[++i]);
        else if (strcmp (argv[i], "--movers") == 0 && i + 1 < argc)
            movers = (size_t)atol (argv[++i]);
        else if (strncmp (argv[i], "--", 2) == 0 && i + 1 < argc && argv[i + 1][0] != '-')
            i++;
    }
    if (runs < 1 || runs > 50 || movers < 1 || movers > 1000000) {
        fprintf (stderr, "bench_mtid: bad --runs or --movers\n");
        return 2;
    }
    mti_params_t p;
    mti_params_defaults (&p);
    const char *root = getenv ("CGS_ROOT");
    char path[4096], err[1024];
    snprintf (path, sizeof path, "%s/deploy/scenarios/default.ini", root ? root : ".");
    cgs_geo_t *frame = cgs_geo_new (35.96, -121.23, 0);
    cgs_scenario_t *sc = NULL;
    cgs_terrain_t *hills = NULL;
    if (!frame || cgs_scenario_load (path, frame, 1, &sc, err, sizeof err) < 0 ||
        cgs_scenario_terrain (sc, frame, &hills, err, sizeof err) < 0) {
        fprintf (stderr, "bench_mtid: %s\n", err);
        return 1;
    }
    cgs_enu_t uav = sc->uavs[0].position;
    uav.u_m = cgs_terrain_height_clamped (hills, uav.e_m, uav.n_m) + sc->uavs[0].altitude_agl_m;
    mti_radar_t *probe = mti_radar_new (&p, NULL, 1);
    double scan_time = mti_radar_dwell_s (probe) * mti_radar_dwells_per_scan (probe);
    mti_radar_destroy (&probe);
    int ffts_per_target = p.n * (1 + p.ref_cells);
    printf ("bench_mtid: nominal parameters (%.0f GHz, PRF %.0f Hz, %g deg/s, scan %.1f s, FFT %d, "
            "%d CPIs x %d cells), %zu movers, %d scans per world, one core\n",
            p.frequency_hz / 1e9, p.prf_hz, p.sweep_rate_dps, scan_time, p.fft_size, p.n,
            1 + p.ref_cells, movers, runs);
    double fft_s = s_fft_cost (p.fft_size);
    const char *names[] = {"flat", "hills"};
    const cgs_terrain_t *worlds[] = {NULL, hills};
    double worst = 0;
    for (int w = 0; w < 2; w++) {
        s_result_t r = s_run (&p, worlds[w], uav, movers, runs);
        double per_mover_s = r.scan_s / movers;
        double keep_up = scan_time / per_mover_s;
        double fft_share = ffts_per_target * fft_s * 1e6 / r.per_target_us;
        printf ("  %-5s: %zu in the beam per scan, %zu through the chain, %llu hits, %llu false "
                "alarms in all\n",
                names[w], r.in_beam, r.chained, (unsigned long long)r.hits,
                (unsigned long long)r.fas);
        printf ("mtid_%s_dwell_per_target_us=%.1f\n", names[w], r.per_target_us);
        printf ("mtid_%s_fft_share=%.3f\n", names[w], fft_share);
        printf ("mtid_%s_scan_cpu_s=%.3f\n", names[w], r.scan_s);
        printf ("mtid_%s_movers_real_time=%.0f\n", names[w], keep_up);
        if (w == 0 || keep_up < worst)
            worst = keep_up;
    }
    printf ("mtid_fft_us=%.3f (one %d-point transform)\n", fft_s * 1e6, p.fft_size);
    printf ("verdict: %.0f ground movers in real time on one core, the slower world (goal %.0f): "
            "%s\n",
            worst, S_GOAL, worst >= S_GOAL ? "met" : "NOT met");
    cgs_terrain_destroy (&hills);
    cgs_scenario_destroy (&sc);
    cgs_geo_destroy (&frame);
    return 0;
}
