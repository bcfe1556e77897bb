/* ms_montecarlo — `mscgs montecarlo`: whole scenes in lockstep (ls_mc),
 * with a progress bar on a terminal, each run that did not image its
 * designated vehicle listed with the reason and the command that replays it
 * alone with a trace, per-run JSON and CSV files on request, and one JSON
 * object as the last line of standard output. */
#include "ms_montecarlo.h"

#include "cgs_json.h"
#include "cgs_util.h"
#include "ls_mc.h"
#include "ms_opts.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define S_DEFAULT_EXERCISE "deploy/exercises/default.ini"

static const char s_synopsis[] =
    "usage: mscgs montecarlo [--scenario F] [--exercise F] [--runs N] [--seed S]\n"
    "                        [--jobs J] [--spread S] [--limit S] [--json F] [--csv F]\n"
    "                        [--trace RUN [--timeline F]] [--seeds-only] [--quiet]\n";

static const char s_about[] =
    "Runs N whole exercises (default 100) in lockstep, in this process and J-1\n"
    "others: the adapters of uavsim, mtid, bcisd, trackerd and guidanced over an\n"
    "in-process bus, every vehicle, the terrain, the BCIS and the scenario's\n"
    "[operator] designation. Run i varies, from the seed and i alone: the exercise\n"
    "seed (radar noise, vehicle wander), the designation time (uniform in\n"
    "+-spread s, default 30) and the UAV's start point on its loiter orbit\n"
    "(--seeds-only: run i is the scene as it stands with exercise seed S + i, as\n"
    "`mscgs run` runs it with that seed). A run\n"
    "images when the designated vehicle (the one the designated track followed\n"
    "first) is inside the true footprint at least once, as `mscgs run` judges it.\n"
    "Prints each run that did not image, with the command that replays it\n"
    "(--trace RUN: that run alone, with every service's log lines; --timeline F\n"
    "writes its vehicles, radar truth, tracks and intercept states to F as CSV,\n"
    "to see why it missed), then one JSON\n"
    "object: runs, imaged, imaged_pct and its 95% interval, wrong_vehicle, lost,\n"
    "miss and time-to-image quantiles, GOSPA, SIAP and identification figures.\n"
    "--json and --csv write every run. Exit code 0, 1 when a run reported bad\n"
    "input or an error (a defect), 2 for bad options.\n"
    "Defaults: --exercise " S_DEFAULT_EXERCISE
    ", the exercise's scenario, seed 1, 1 job, --limit:\n"
    "1500 s after the last designation.\n";

static int s_number (const char *what, const char *text, double lo, double hi, double *ret)
{
    char *end;
    double v = strtod (text, &end);
    if (end == text || *end || !(v >= lo && v <= hi)) {
        fprintf (stderr, "mscgs montecarlo: --%s: expected a number in [%g, %g], got '%s'\n", what,
                 lo, hi, text);
        return -EINVAL;
    }
    *ret = v;
    return 0;
}

static int s_count (const char *what, const char *text, uint64_t lo, uint64_t hi, uint64_t *ret)
{
    uint64_t v;
    if (cgs_parse_u64 (text, hi, &v) < 0 || v < lo) {
        fprintf (stderr, "mscgs montecarlo: --%s: expected a whole number %llu..%llu, got '%s'\n",
                 what, (unsigned long long)lo, (unsigned long long)hi, text);
        return -EINVAL;
    }
    *ret = v;
    return 0;
}

/* A number option's range, and where its value goes. */
typedef struct {
    double lo, hi;
    double *ret;
} s_number_opt_t;

static int s_read_number (const ms_opt_t *opt, const char *value)
{
    const s_number_opt_t *n = opt->arg;
    return s_number (opt->name, value, n->lo, n->hi, n->ret);
}

/* A whole-number option's range, and where its value goes. */
typedef struct {
    uint64_t lo, hi;
    uint64_t *ret;
} s_count_opt_t;

static int s_read_count (const ms_opt_t *opt, const char *value)
{
    const s_count_opt_t *n = opt->arg;
    return s_count (opt->name, value, n->lo, n->hi, n->ret);
}

/* ---- output ------------------------------------------------------------------------- */

typedef struct {
    const ls_mc_config_t *c;
    bool bar;   // a progress bar on standard error (a terminal)
    bool quiet; // no progress at all
} s_progress_t;

static void s_progress (void *arg, size_t done, const ls_mc_run_t *run)
{
    const s_progress_t *p = arg;
    (void)run;
    if (p->quiet)
        return;
    size_t n = p->c->runs;
    if (p->bar) {
        int width = 40, filled = (int)(width * done / n);
        fprintf (stderr, "\r[%.*s%*s] %zu/%zu runs", filled,
                 "########################################", width - filled, "", done, n);
        if (done == n)
            fputc ('\n', stderr);
    } else if (done % 10 == 0 || done == n) {
        fprintf (stderr, "mscgs montecarlo: %zu/%zu runs\n", done, n);
    }
}

/* The replay command of run i. */
static void s_replay (FILE *f, const ls_mc_config_t *c, size_t i)
{
    fprintf (f, "mscgs montecarlo --exercise %s", c->exercise_path);
    if (c->scenario_path)
        fprintf (f, " --scenario %s", c->scenario_path);
    fprintf (f, " --seed %llu --spread %g%s", (unsigned long long)c->seed, c->spread_s,
             c->seeds_only ? " --seeds-only" : "");
    if (c->limit_s > 0)
        fprintf (f, " --limit %g", c->limit_s);
    fprintf (f, " --trace %zu", i);
}

/* One run as a new JSON object; NULL without memory. */
static json_object *s_run_json (const ls_mc_run_t *r)
{
    json_object *o = json_object_new_object ();
    if (!o)
        return NULL;
    cgs_json_add (o, "run", json_object_new_uint64 (r->index));
    cgs_json_add (o, "exercise_seed", json_object_new_uint64 (r->exercise_seed));
    cgs_json_add (o, "designation_shift_s", cgs_json_fixed (r->designation_shift_s, 3));
    cgs_json_add (o, "uav_phase_deg", cgs_json_fixed (r->uav_phase_deg, 3));
    cgs_json_add (o, "outcome", json_object_new_string (ls_mc_outcome_name (r->outcome)));
    cgs_json_add (o, "final_state", json_object_new_string (r->final_state));
    cgs_json_add (o, "designated", json_object_new_boolean (r->designated));
    cgs_json_add (o, "imaged", json_object_new_boolean (r->imaged));
    cgs_json_add (o, "miss_m", cgs_json_fixed (r->miss_m, 2));
    cgs_json_add (o, "closest_m", cgs_json_fixed (r->closest_m, 2));
    cgs_json_add (o, "time_to_image_s", cgs_json_fixed (r->time_to_image_s, 2));
    cgs_json_add (o, "end_s", cgs_json_fixed (r->end_s, 2));
    cgs_json_add (o, "replans", json_object_new_int64 (r->replans));
    cgs_json_add (o, "target_entity_id", json_object_new_int64 (r->target_entity_id));
    cgs_json_add (o, "follows_entity_id",
                  r->other_entity_id ? json_object_new_int64 (r->other_entity_id) : NULL);
    cgs_json_add (o, "follows_since_s", cgs_json_fixed (r->other_since_s, 2));
    cgs_json_add (o, "follows_after_unseen_s", cgs_json_fixed (r->other_unseen_s, 2));
    cgs_json_add (o, "follows_gap_m", cgs_json_fixed (r->other_gap_m, 1));
    cgs_json_add (o, "bad_inputs", json_object_new_uint64 (r->bad_inputs));
    cgs_json_add (o, "errors", json_object_new_uint64 (r->errors));
    return o;
}

/* One run as one line of JSON text, then end, to f; 0, -ENOMEM or -EIO. */
static int s_run_print (FILE *f, const ls_mc_run_t *r, const char *end)
{
    json_object *o = s_run_json (r);
    int rc = o ? cgs_json_print (f, o, JSON_C_TO_STRING_PLAIN, end) : -ENOMEM;
    json_object_put (o);
    return rc;
}

static int s_write_runs (const char *json, const char *csv, const ls_mc_run_t *runs, size_t n)
{
    if (json) {
        FILE *f = fopen (json, "w");
        if (!f) {
            fprintf (stderr, "mscgs montecarlo: %s: %s\n", json, strerror (errno));
            return -errno;
        }
        // One array, a run a line: written run by run, not built whole (a
        // million runs would hold tens of millions of json-c objects).
        int rc = fputs ("[\n", f) == EOF ? -EIO : 0;
        for (size_t i = 0; i < n && rc == 0; i++)
            rc = s_run_print (f, &runs[i], i + 1 < n ? ",\n" : "\n");
        if (rc == 0 && fputs ("]\n", f) == EOF)
            rc = -EIO;
        if (fclose (f) != 0 && rc == 0)
            rc = -errno;
        if (rc < 0) {
            fprintf (stderr, "mscgs montecarlo: %s: %s\n", json, strerror (-rc));
            return rc;
        }
    }
    if (csv) {
        FILE *f = fopen (csv, "w");
        if (!f) {
            fprintf (stderr, "mscgs montecarlo: %s: %s\n", csv, strerror (errno));
            return -errno;
        }
        fputs ("run,exercise_seed,designation_shift_s,uav_phase_deg,outcome,final_state,imaged,"
               "miss_m,closest_m,time_to_image_s,end_s,replans,target_entity_id,follows_entity_id,"
               "follows_since_s,follows_after_unseen_s,follows_gap_m\n",
               f);
        for (size_t i = 0; i < n; i++) {
            const ls_mc_run_t *r = &runs[i];
            fprintf (f, "%zu,%llu,%.3f,%.3f,%s,%s,%d,%.2f,%.2f,%.2f,%.2f,%u,%u,%u,%.2f,%.2f,%.1f\n",
                     r->index, (unsigned long long)r->exercise_seed, r->designation_shift_s,
                     r->uav_phase_deg, ls_mc_outcome_name (r->outcome), r->final_state, r->imaged,
                     r->miss_m, r->closest_m, r->time_to_image_s, r->end_s, r->replans,
                     r->target_entity_id, r->other_entity_id, r->other_since_s, r->other_unseen_s,
                     r->other_gap_m);
        }
        if (fclose (f) != 0)
            return -errno;
    }
    return 0;
}

/* The set's figures as a new JSON object; NULL without memory. */
static json_object *s_summary_json (const ls_mc_config_t *c, const ls_mc_result_t *r)
{
    json_object *o = json_object_new_object ();
    json_object *ci95 = json_object_new_array_ext (2);
    if (!o || !ci95) {
        json_object_put (o);
        json_object_put (ci95);
        return NULL;
    }
    cgs_json_add (o, "runs", json_object_new_uint64 (r->runs));
    cgs_json_add (o, "seed", json_object_new_uint64 (c->seed));
    cgs_json_add (o, "jobs", json_object_new_int64 (c->jobs));
    cgs_json_add (o, "imaged", json_object_new_uint64 (r->imaged));
    cgs_json_add (o, "imaged_pct", cgs_json_fixed (r->imaged_pct, 2));
    json_object_array_add (ci95, cgs_json_fixed (r->imaged_lo_pct, 2));
    json_object_array_add (ci95, cgs_json_fixed (r->imaged_hi_pct, 2));
    cgs_json_add (o, "imaged_pct_ci95", ci95);
    const struct {
        const char *key;
        size_t n;
    } counts[] = {
        {"designated", r->designated},
        {"wrong_vehicle", r->wrong_vehicle},
        {"lost", r->lost},
        {"not_designated", r->not_designated},
        {"unfinished", r->unfinished},
    };
    for (size_t i = 0; i < sizeof counts / sizeof counts[0]; i++)
        cgs_json_add (o, counts[i].key, json_object_new_uint64 (counts[i].n));
    const struct {
        const char *key;
        double v;
        int decimals;
    } figures[] = {
        {"miss_p50_m", r->miss_p50_m, 2},
        {"miss_p95_m", r->miss_p95_m, 2},
        {"time_to_image_p50_s", r->time_to_image_p50_s, 1},
        {"time_to_image_p95_s", r->time_to_image_p95_s, 1},
        {"gospa_m", r->gospa.distance, 2},
        {"gospa_localisation_m2", r->gospa.localisation, 1},
        {"gospa_missed_m2", r->gospa.missed, 1},
        {"gospa_false_m2", r->gospa.false_, 1},
        {"completeness", r->siap.completeness, 4},
        {"ambiguity", r->siap.ambiguity, 4},
        {"spuriousness", r->siap.spuriousness, 4},
        {"spuriousness_unseen", r->siap.spuriousness_unseen, 4},
        {"position_accuracy_m", r->siap.position_accuracy_m, 2},
        {"swaps_per_truth_hour", r->siap.swaps_per_truth_hour, 3},
        {"breaks_per_truth_hour", r->siap.breaks_per_truth_hour, 3},
        {"false_tracks_per_hour", r->siap.false_tracks_per_hour, 3},
        {"id_completeness", r->siap.id_completeness, 4},
        {"id_correctness", r->siap.id_correctness, 4},
        {"id_wrong_fraction", r->siap.id_wrong_fraction, 4},
    };
    for (size_t i = 0; i < sizeof figures / sizeof figures[0]; i++)
        cgs_json_add (o, figures[i].key, cgs_json_fixed (figures[i].v, figures[i].decimals));
    cgs_json_add (o, "id_hostile_marked", json_object_new_uint64 (r->siap.id.hostile_marked));
    cgs_json_add (o, "bad_inputs", json_object_new_uint64 (r->bad_inputs));
    cgs_json_add (o, "errors", json_object_new_uint64 (r->errors));
    cgs_json_add (o, "failures", json_object_new_uint64 (r->failures));
    return o;
}

/* ---- the command ---------------------------------------------------------------------- */

int ms_montecarlo_main (int argc, char **argv)
{
    ls_mc_config_t c = {
        .exercise_path = S_DEFAULT_EXERCISE,
        .runs = 100,
        .seed = 1,
        .spread_s = 30,
        .jobs = 1,
    };
    const char *json = NULL, *csv = NULL, *timeline = NULL;
    uint64_t nruns = c.runs, seed = c.seed, jobs = (uint64_t)c.jobs, trace_run = UINT64_MAX;
    bool quiet = false;
    s_count_opt_t runs_opt = {1, 1000000, &nruns}, seed_opt = {0, UINT64_MAX / 2, &seed},
                  jobs_opt = {1, 64, &jobs}, trace_opt = {0, 999999, &trace_run};
    s_number_opt_t spread_opt = {0, 3600, &c.spread_s}, limit_opt = {1, 1e6, &c.limit_s};
    const ms_opt_t opts[] = {
        {.name = "scenario",
         .value = "F",
         .help = "scenario file (default: the exercise's)",
         .str = &c.scenario_path},
        {.name = "exercise", .value = "F", .help = "exercise file", .str = &c.exercise_path},
        {.name = "runs",
         .value = "N",
         .help = "runs (default 100)",
         .fn = s_read_count,
         .arg = &runs_opt},
        {.name = "seed",
         .value = "S",
         .help = "the set's seed (default 1)",
         .fn = s_read_count,
         .arg = &seed_opt},
        {.name = "jobs",
         .value = "J",
         .help = "processes (default 1)",
         .fn = s_read_count,
         .arg = &jobs_opt},
        {.name = "spread",
         .value = "S",
         .help = "designation time shift, uniform in +-S s (default 30)",
         .fn = s_read_number,
         .arg = &spread_opt},
        {.name = "limit",
         .value = "S",
         .help = "a run's end, simulation seconds",
         .fn = s_read_number,
         .arg = &limit_opt},
        {.name = "json", .value = "F", .help = "every run as JSON to F", .str = &json},
        {.name = "csv", .value = "F", .help = "every run as CSV to F", .str = &csv},
        {.name = "trace",
         .value = "RUN",
         .help = "that run alone, with every service's log lines",
         .fn = s_read_count,
         .arg = &trace_opt},
        {.name = "quiet", .help = "no progress shown", .flag = &quiet},
        MS_OPTS_HELP,
        {.name = "seeds-only", .help = "exercise seeds S, S+1, ...", .flag = &c.seeds_only},
        {.name = "timeline",
         .value = "F",
         .help = "with --trace: the run's entities, truth, tracks and states to F",
         .str = &timeline},
        MS_OPTS_END,
    };
    const ms_cmd_t spec = {
        .name = "montecarlo", .synopsis = s_synopsis, .about = s_about, .opts = opts};
    int nargs = ms_opts_parse (&spec, argc, argv);
    if (nargs < 0)
        return ms_opts_exit_code (nargs);
    if (nargs > 0) {
        fprintf (stderr, "mscgs montecarlo: unexpected argument '%s' (see --help)\n", argv[1]);
        return 2;
    }
    c.runs = (size_t)nruns;
    c.seed = seed;
    c.jobs = (int)jobs;
    long trace = trace_run == UINT64_MAX ? -1 : (long)trace_run;
    if (timeline && trace < 0) {
        fprintf (stderr, "mscgs montecarlo: --timeline needs --trace RUN\n");
        return 2;
    }
    char err[1024] = "";
    if (trace >= 0) {
        ls_mc_run_t run;
        if (timeline && !(c.timeline = fopen (timeline, "w"))) {
            fprintf (stderr, "mscgs montecarlo: %s: %s\n", timeline, strerror (errno));
            return 1;
        }
        int rc = ls_mc_one (&c, (size_t)trace, stdout, &run, err, sizeof err);
        if (c.timeline && fclose (c.timeline) != 0 && rc >= 0) {
            fprintf (stderr, "mscgs montecarlo: %s: %s\n", timeline, strerror (errno));
            return 1;
        }
        if (rc < 0) {
            fprintf (stderr, "mscgs montecarlo: %s\n", err);
            return 1;
        }
        printf ("run %ld (exercise seed %llu, designation %+.1f s, UAV at %.0f deg on its "
                "orbit, NaN: as the scenario): %s, final state %s, miss %.1f m\n",
                trace, (unsigned long long)run.exercise_seed, run.designation_shift_s,
                run.uav_phase_deg, ls_mc_outcome_name (run.outcome), run.final_state, run.miss_m);
        int prc = s_run_print (stdout, &run, "\n");
        if (prc < 0) {
            fprintf (stderr, "mscgs montecarlo: cannot print run %ld: %s\n", trace,
                     strerror (-prc));
            return 1;
        }
        return run.bad_inputs || run.errors || run.failures ? 1 : 0;
    }
    ls_mc_run_t *runs = calloc (c.runs, sizeof *runs);
    if (!runs) {
        fprintf (stderr, "mscgs montecarlo: out of memory\n");
        return 1;
    }
    s_progress_t pr = {.c = &c, .bar = isatty (STDERR_FILENO), .quiet = quiet};
    ls_mc_result_t r;
    int rc = ls_mc_run (&c, runs, s_progress, &pr, &r, err, sizeof err);
    if (rc < 0) {
        fprintf (stderr, "mscgs montecarlo: %s\n", err);
        free (runs);
        return 1;
    }
    for (size_t i = 0; i < c.runs; i++) {
        const ls_mc_run_t *o = &runs[i];
        if (o->imaged)
            continue;
        printf ("run %zu: %s (final state %s", i, ls_mc_outcome_name (o->outcome), o->final_state);
        if (o->designated && isfinite (o->miss_m))
            printf (", %.0f m from the footprint at closest", o->miss_m);
        if (o->other_entity_id) {
            printf ("; the track follows entity %u, not %u", o->other_entity_id,
                    o->target_entity_id);
            if (isfinite (o->other_since_s))
                printf (", since %.0f s", o->other_since_s);
            if (isfinite (o->other_unseen_s))
                printf (" after %.0f s without a hit", o->other_unseen_s);
            if (isfinite (o->other_gap_m))
                printf (", its first hit of it %.0f m from the designated one", o->other_gap_m);
        }
        printf ("); replay: ");
        s_replay (stdout, &c, i);
        printf ("\n");
    }
    for (size_t i = 0; i < c.runs; i++)
        if (runs[i].bad_inputs || runs[i].errors || runs[i].failures)
            printf ("run %zu: %llu bad inputs, %llu errors, %llu failures (%s)\n", i,
                    (unsigned long long)runs[i].bad_inputs, (unsigned long long)runs[i].errors,
                    (unsigned long long)runs[i].failures, runs[i].first_error);
    int wrc = s_write_runs (json, csv, runs, c.runs);
    free (runs);
    json_object *summary = s_summary_json (&c, &r);
    int src = summary ? cgs_json_print (stdout, summary, JSON_C_TO_STRING_PLAIN, "\n") : -ENOMEM;
    json_object_put (summary);
    if (src < 0)
        fprintf (stderr, "mscgs montecarlo: cannot print the summary: %s\n", strerror (-src));
    if (wrc < 0 || src < 0)
        return 1;
    return r.bad_inputs || r.errors || r.failures ? 1 : 0;
}
