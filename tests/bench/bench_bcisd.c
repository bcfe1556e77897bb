/* bench_bcisd — the BCIS interrogator's cost with the 1,000-vehicle scenario
 * (deploy/scenarios/bench-1000.ini: 333 friendly vehicles with transponders,
 * 667 others, over its hills) at the default parameters
 * (deploy/params/bcis.ini: a revolution of 60 dwells in 6 s). Every vehicle
 * stands at its first route point; the UAV at its start, 1,200 m above the
 * ground. Each dwell looks at all 1,000 vehicles; each friendly transponder in
 * the beam is one interrogation modelled: line of sight over the terrain,
 * foliage along the path, the link budget both ways and the messages drawn
 * symbol by symbol. Two worlds: the scenario's terrain as it is (no woods),
 * and with woods over 20% of it (each path's foliage measured). Timed on one
 * core (CPU time) over R revolutions; figures are medians over revolutions.
 * Usage: bench_bcisd [--runs R] (other options, meant for other benchmarks,
 * are ignored). */
#include "bench_util.h"
#include "bcis_interrogator.h"
#include "bcis_params.h"
#include "cgs_scenario.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

typedef struct {
    double scan_cpu_s; // one revolution, median
    double
        interrogations_per_s; // friendly transponders in the beam modelled per CPU second, median
    size_t interrogations;    // per revolution
    size_t in_beam, replies, blocked;
} s_result_t;

static s_result_t s_run (const bcis_params_t *p, const cgs_terrain_t *terrain, cgs_enu_t uav,
                         const bcis_entity_t *e, size_t n, int runs)
{
    bcis_interrogator_t *b = bcis_interrogator_new (p, terrain, 3);
    double *cpu = calloc ((size_t)runs, sizeof *cpu), *rate = calloc ((size_t)runs, sizeof *rate);
    if (!b || !cpu || !rate) {
        fprintf (stderr, "bench_bcisd: out of memory\n");
        exit (1);
    }
    const cgs_scan_t *s = bcis_interrogator_scan (b);
    s_result_t res = {0};
    for (int r = 0; r < runs; r++) {
        size_t asked = 0, in_beam = 0, replies = 0, blocked = 0;
        double c0 = bench_cpu_s ();
        for (uint32_t k = 0; k < s->dwells; k++) {
            cgs_dwell_t d;
            bcis_dwell_out_t out;
            cgs_scan_dwell (s, (uint64_t)r * s->dwells + k, 90, &d);
            if (bcis_interrogator_dwell (b, &d, uav, e, n, &out) < 0) {
                fprintf (stderr, "bench_bcisd: dwell failed\n");
                exit (1);
            }
            asked += out.truth_count;
            in_beam += out.in_beam;
            replies += out.reply_count;
            for (size_t i = 0; i < out.truth_count; i++)
                blocked += out.truth[i].blocked;
        }
        cpu[r] = bench_cpu_s () - c0;
        rate[r] = asked / cpu[r];
        res.interrogations = asked;
        res.in_beam = in_beam;
        res.replies = replies;
        res.blocked = blocked;
    }
    res.scan_cpu_s = bench_median (cpu, runs);
    res.interrogations_per_s = bench_median (rate, runs);
    free (cpu);
    free (rate);
    bcis_interrogator_destroy (&b);
    return res;
}

int main (int argc, char **argv)
{
    int runs = 9;
    for (int i = 1; i < argc; i++) {
        if (strcmp (argv[i], "--runs") == 0 && i + 1 < argc)
            runs = atoi (argv[++i]);
        else if (strncmp (argv[i], "--", 2) == 0 && i + 1 < argc && argv[i + 1][0] != '-')
            i++;
    }
    if (runs < 1 || runs > 100) {
        fprintf (stderr, "bench_bcisd: bad --runs\n");
        return 2;
    }
    const char *root = getenv ("CGS_ROOT");
    char path[4096], err[1024];
    snprintf (path, sizeof path, "%s/deploy/scenarios/bench-1000.ini", root ? root : ".");
    cgs_geo_t *frame = cgs_geo_new (35.96, -121.23, 0);
    cgs_scenario_t *sc = NULL;
    cgs_terrain_t *hills = NULL;
    if (!frame || cgs_scenario_load (path, frame, 1, &sc, err, sizeof err) < 0 ||
        cgs_scenario_terrain (sc, frame, &hills, err, sizeof err) < 0) {
        fprintf (stderr, "bench_bcisd: %s\n", err);
        return 1;
    }
    snprintf (path, sizeof path, "%s/deploy/params/bcis.ini", root ? root : ".");
    bcis_params_t p;
    bcis_params_defaults (&p);
    if (bcis_params_load (path, &p, err, sizeof err) < 0) {
        fprintf (stderr, "bench_bcisd: %s\n", err);
        return 1;
    }
    size_t n = sc->vehicle_count, friendly = 0;
    bcis_entity_t *e = calloc (n, sizeof *e);
    if (!e)
        return 1;
    for (size_t i = 0; i < n; i++) {
        const cgs_scenario_vehicle_t *v = &sc->vehicles[i];
        cgs_enu_t pos = v->points[0].position;
        pos.u_m = cgs_terrain_height_clamped (hills, pos.e_m, pos.n_m);
        e[i] = (bcis_entity_t){.id = v->id,
                               .position = pos,
                               .force = v->force,
                               .transponder = v->bcis_transponder,
                               .marking = v->marking};
        friendly += v->bcis_transponder && v->force == CGS_FORCE_FRIENDLY;
    }
    cgs_enu_t uav = sc->uavs[0].position;
    uav.u_m = cgs_terrain_height_clamped (hills, uav.e_m, uav.n_m) + sc->uavs[0].altitude_agl_m;
    cgs_scan_t scan;
    cgs_scan_params_t sp = bcis_params_scan (&p);
    if (cgs_scan_init (&sp, &scan) < 0) {
        fprintf (stderr, "bench_bcisd: bad scan parameters\n");
        return 1;
    }
    double scan_s = scan.dwells * scan.dwell_s;
    printf ("bench_bcisd: %s, %zu vehicles (%zu friendly transponders), %.0f GHz, %u dwells a "
            "revolution of %.1f s, %d revolutions per world, one core\n",
            "bench-1000.ini", n, friendly, p.frequency_hz / 1e9, scan.dwells, scan_s, runs);
    const char *names[] = {"open", "woods"};
    double worst_rate = 0, worst_rt = 0;
    for (int w = 0; w < 2; w++) {
        if (w == 1) {
            cgs_vegetation_t v;
            cgs_vegetation_defaults (&v);
            v.cover = 0.2;
            v.seed = 7;
            if (cgs_terrain_grow_vegetation (hills, &v) < 0) {
                fprintf (stderr, "bench_bcisd: cannot grow the woods\n");
                return 1;
            }
        }
        s_result_t r = s_run (&p, hills, uav, e, n, runs);
        double rt = scan_s / r.scan_cpu_s;
        printf ("  %-5s: a revolution: %zu vehicles in the beam, %zu interrogations of friendly "
                "transponders (%zu behind terrain), %zu replies\n",
                names[w], r.in_beam, r.interrogations, r.blocked, r.replies);
        printf ("bcisd_%s_revolution_cpu_s=%.5f\n", names[w], r.scan_cpu_s);
        printf ("bcisd_%s_interrogations_per_s=%.0f\n", names[w], r.interrogations_per_s);
        printf ("bcisd_%s_realtime_factor=%.0f\n", names[w], rt);
        if (w == 0 || r.interrogations_per_s < worst_rate)
            worst_rate = r.interrogations_per_s;
        if (w == 0 || rt < worst_rt)
            worst_rt = rt;
    }
    printf ("verdict: %.0f interrogations modelled per second on one core (the slower world); the "
            "1,000-vehicle scenario scanned %.0f times faster than real time\n",
            worst_rate, worst_rt);
    free (e);
    cgs_terrain_destroy (&hills);
    cgs_scenario_destroy (&sc);
    cgs_geo_destroy (&frame);
    return 0;
}
