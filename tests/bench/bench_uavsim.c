/* bench_uavsim — uavsim's real-time factor with the 1,000-vehicle scenario
 * (deploy/scenarios/bench-1000.ini): the world stepped at its fixed step and
 * every entity, the UAV and the clock encoded and published through the
 * project's publisher (ipc://, nobody subscribed) at the scenario's rates
 * (10 Hz of simulation time), as fast as one core goes, once every vehicle
 * has set off (an untimed warm-up past the latest start time), over R
 * consecutive windows of S simulated seconds. Goal: at least 50 times real
 * time.
 * Usage: bench_uavsim [--runs R] [--sim-seconds S] [--scenario FILE]
 * (other options, meant for other benchmarks, are ignored). */
#include "bench_util.h"
#include "cgs_bus.h"
#include "uavsim_msgs.h"
#include "uavsim_world.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>
#include <zmq.h>

#define S_GOAL 50.0

int main (int argc, char **argv)
{
    int runs = 5;
    double sim_s = 120;
    char scenario[4096];
    const char *root = getenv ("CGS_ROOT");
    snprintf (scenario, sizeof scenario, "%s/deploy/scenarios/bench-1000.ini", root ? root : ".");
    for (int i = 1; i < argc; i++) {
        if (strcmp (argv[i], "--runs") == 0 && i + 1 < argc)
            runs = atoi (argv[++i]);
        else if (strcmp (argv[i], "--sim-seconds") == 0 && i + 1 < argc)
            sim_s = atof (argv[++i]);
        else if (strcmp (argv[i], "--scenario") == 0 && i + 1 < argc)
            snprintf (scenario, sizeof scenario, "%s", argv[++i]);
        else if (strncmp (argv[i], "--", 2) == 0 && i + 1 < argc && argv[i + 1][0] != '-')
            i++; // another benchmark's option and its value
    }
    if (runs < 1 || runs > 50 || !(sim_s > 0)) {
        fprintf (stderr, "bench_uavsim: bad --runs or --sim-seconds\n");
        return 2;
    }
    cgs_geo_t *frame = cgs_geo_new (35.96, -121.23, 0);
    char dir[] = "/tmp/cgs-bench-uavsim-XXXXXX";
    if (!frame || !mkdtemp (dir))
        return 1;
    char ep[128];
    snprintf (ep, sizeof ep, "ipc://%s/uavsim.pub", dir);
    void *ctx = zmq_ctx_new ();
    cgs_pub_t *pub = cgs_pub_new (ctx, "uavsim", 1);
    if (!pub || cgs_pub_bind (pub, ep) < 0) {
        fprintf (stderr, "bench_uavsim: cannot bind %s\n", ep);
        return 1;
    }
    double *factor = calloc ((size_t)runs, sizeof *factor);
    uint64_t entities = 0, batches = 0;
    size_t vehicles = 0;
    double step_s = 0, rate_hz = 0, cpu_total = 0, wall_total = 0;
    printf ("bench_uavsim: %s, %.0f s of simulation time per window, %d windows, one process\n",
            scenario, sim_s, runs);
    cgs_scenario_t *sc = NULL;
    uavsim_world_t *w = NULL;
    char err[1024];
    if (cgs_scenario_load (scenario, frame, 1, &sc, err, sizeof err) < 0 ||
        uavsim_world_new (sc, frame, &w, err, sizeof err) < 0) {
        fprintf (stderr, "bench_uavsim: %s\n", err);
        return 1;
    }
    const cgs_scenario_t *s = uavsim_world_scenario (w);
    vehicles = s->vehicle_count;
    step_s = s->settings.step_s;
    rate_hz = s->settings.entity_rate_hz;
    // Every vehicle has set off by then (start times go up to 300 s): time the
    // steady state, not a half-empty world.
    double latest_start = 0;
    for (size_t i = 0; i < s->vehicle_count; i++)
        if (s->vehicles[i].start_time_s > latest_start)
            latest_start = s->vehicles[i].start_time_s;
    uavsim_msgs_t *m = uavsim_msgs_new (w);
    uint64_t every = (uint64_t)llround (1.0 / (rate_hz * step_s));
    uint64_t warm = (uint64_t)ceil (latest_start / step_s) + 1;
    double tw = bench_wall_s ();
    for (uint64_t k = 0; k < warm; k++)
        uavsim_world_step (w);
    printf ("  warm-up: %.0f s of simulation (every vehicle started) in %.2f s\n",
            uavsim_world_time (w), bench_wall_s () - tw);
    for (int r = 0; r < runs; r++) {
        uint64_t steps = (uint64_t)llround (sim_s / step_s);
        double t0 = bench_wall_s (), c0 = bench_cpu_s ();
        for (uint64_t k = 1; k <= steps; k++) {
            uavsim_world_step (w);
            if (uavsim_world_tick (w) % every)
                continue;
            double t = uavsim_world_time (w);
            size_t nb = uavsim_msgs_entities (m, w);
            for (size_t b = 0; b < nb; b++) {
                Cgs__EntityBatch *batch = uavsim_msgs_batch (m, b);
                if (cgs_pub_send (pub, "entity", &batch->base, t) < 0)
                    return 1;
                entities += batch->n_entities;
                batches++;
            }
            for (size_t i = 0; i < s->uav_count; i++)
                cgs_pub_send (pub, "uav", &uavsim_msgs_uav (m, w, i)->base, t);
            cgs_pub_send (
                pub, "clock",
                &uavsim_msgs_clock (m, w, 1, false, (cgs_geodetic_t){35.96, -121.23, 0})->base, t);
        }
        double wall = bench_wall_s () - t0, cpu = bench_cpu_s () - c0;
        factor[r] = sim_s / wall;
        cpu_total += cpu;
        wall_total += wall;
        printf (
            "  run %d: t=%.0f..%.0f s simulated in %.3f s wall (%.3f s CPU): %.1f x real time\n",
            r + 1, uavsim_world_time (w) - sim_s, uavsim_world_time (w), wall, cpu, factor[r]);
    }
    uavsim_msgs_destroy (&m);
    uavsim_world_destroy (&w);
    qsort (factor, (size_t)runs, sizeof *factor, bench_cmp_double);
    double median = factor[runs / 2];
    printf ("uavsim: %zu vehicles, step %.3f s, entities published at %.0f Hz of simulation time "
            "(%.0f entity states per wall second at the median)\n",
            vehicles, step_s, rate_hz, median * rate_hz * (double)(vehicles + 1));
    printf ("\n--- figures ---\n");
    printf ("vehicles=%zu\nstep_s=%g\nentity_rate_hz=%g\nsim_seconds_per_run=%g\nruns=%d\n",
            vehicles, step_s, rate_hz, sim_s, runs);
    printf ("realtime_factor_median=%.1f\nrealtime_factor_min=%.1f\nrealtime_factor_max=%.1f\n",
            median, factor[0], factor[runs - 1]);
    printf ("cpu_per_wall=%.2f\n", cpu_total / wall_total);
    printf ("entity_messages=%llu\nentity_states=%llu\n", (unsigned long long)batches,
            (unsigned long long)entities);
    printf ("goal_realtime_factor=%.0f\nverdict=%s\n", S_GOAL,
            median >= S_GOAL ? "PASS" : "BELOW-GOAL");
    free (factor);
    cgs_pub_destroy (&pub);
    zmq_ctx_term (ctx);
    cgs_geo_destroy (&frame);
    char cmd[128];
    snprintf (cmd, sizeof cmd, "rm -rf '%s'", dir);
    return system (cmd) == 0 ? 0 : 1;
}
