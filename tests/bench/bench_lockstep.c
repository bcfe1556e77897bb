/* bench_lockstep — how fast the lockstep engine runs whole scenes: the CPU
 * seconds of one run of the default exercise and scenario (every service's
 * adapter, every vehicle, terrain, BCIS, the operator's designation, to the
 * intercept's end or the limit), the median over --runs runs of a Monte
 * Carlo set (each its own variation, as `mscgs montecarlo` draws them), and
 * the wall-clock speed-up of the same set on --jobs processes over one.
 * Goal (issue: lockstep Monte Carlo): under 2 CPU seconds a run, so 500 runs
 * take minutes on two cores.
 *
 *   bench_lockstep [--runs N] [--jobs J] [--scenario F]
 */
#include "bench_util.h"
#include "ls_mc.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int main (int argc, char **argv)
{
    long runs = 6, jobs = 2;
    const char *scenario = NULL;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        if (strcmp (a, "--runs") == 0 && bench_parse_long (v, 1, 1000, &runs))
            i++;
        else if (strcmp (a, "--jobs") == 0 && bench_parse_long (v, 2, 64, &jobs))
            i++;
        else if (strcmp (a, "--scenario") == 0 && v)
            scenario = argv[++i];
        else if (strcmp (a, "--help") == 0) {
            printf ("usage: bench_lockstep [--runs N] [--jobs J] [--scenario F]\n");
            return 0;
        } else if (strncmp (a, "--", 2) == 0 && v && strncmp (v, "--", 2) != 0) {
            i++; // another benchmark's option (BENCH_ARGS goes to every one)
        }
    }
    const char *root = getenv ("CGS_ROOT");
    char exercise[4096];
    snprintf (exercise, sizeof exercise, "%s/deploy/exercises/default.ini", root ? root : ".");
    ls_mc_config_t c = {.exercise_path = exercise,
                        .scenario_path = scenario,
                        .runs = (size_t)runs,
                        .seed = 1,
                        .spread_s = 30,
                        .jobs = 1};
    double *cpu = calloc ((size_t)runs, sizeof *cpu);
    ls_mc_run_t *set = calloc ((size_t)runs, sizeof *set);
    if (!cpu || !set)
        return 1;
    char err[1024];
    double sim = 0, w0 = bench_wall_s ();
    for (long i = 0; i < runs; i++) {
        double c0 = bench_cpu_s ();
        if (ls_mc_one (&c, (size_t)i, NULL, &set[i], err, sizeof err) < 0) {
            printf ("bench_lockstep: FAILED: %s\n", err);
            return 1;
        }
        cpu[i] = bench_cpu_s () - c0;
        sim += set[i].end_s;
    }
    double wall1 = bench_wall_s () - w0;
    double med = bench_median (cpu, (int)runs);
    printf ("runs=%ld simulated_s_per_run=%.0f cpu_s_per_run_median=%.3f cpu_s_per_run_max=%.3f "
            "sim_per_cpu_s=%.0f\n",
            runs, sim / (double)runs, med, cpu[runs - 1], sim / (wall1 > 0 ? wall1 : 1));
    c.jobs = (int)jobs;
    ls_mc_result_t r;
    w0 = bench_wall_s ();
    if (ls_mc_run (&c, set, NULL, NULL, &r, err, sizeof err) < 0) {
        printf ("bench_lockstep: FAILED: %s\n", err);
        return 1;
    }
    double wallj = bench_wall_s () - w0;
    printf ("wall_s_jobs1=%.2f wall_s_jobs%ld=%.2f speedup=%.2f imaged=%zu/%zu\n", wall1, jobs,
            wallj, wall1 / wallj, r.imaged, r.runs);
    printf ("verdict: %s (goal: under 2 CPU s a run of the default scene)\n",
            med < 2.0 ? "met" : "NOT met");
    free (cpu);
    free (set);
    return 0;
}
