/* ls_mc — Monte Carlo runs of one scene in lockstep (see ls_mc.h). */
#include "ls_mc.h"

#include "cgs_stats.h"
#include "cgs_util.h"
#include "ls_run.h"
#include "ms_metrics.h"

#include <errno.h>
#include <math.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#define S_JOBS_MAX 64

const char *ls_mc_outcome_name (ls_mc_outcome_t o)
{
    static const char *const names[] = {"imaged", "not-designated", "wrong-vehicle",
                                        "lost",   "missed",         "unfinished"};
    return (unsigned)o < sizeof names / sizeof names[0] ? names[o] : "?";
}

void ls_mc_variation (const ls_mc_config_t *c, size_t i, uint64_t *ret_seed, double *ret_shift_s,
                      double *ret_phase_deg)
{
    if (c->seeds_only) { // the exercise seed c->seed + i, nothing else varied
        *ret_seed = c->seed + (uint64_t)i;
        *ret_shift_s = 0;
        *ret_phase_deg = NAN;
        return;
    }
    uint64_t s = c->seed * 0x100000001b3ull + (uint64_t)i + 1;
    *ret_seed = cgs_splitmix64 (&s) % 1000000000ull + 1; // a seed a person can type
    *ret_shift_s = c->spread_s * (2 * cgs_uniform01 (&s) - 1);
    *ret_phase_deg = 360 * cgs_uniform01 (&s);
}

/* ---- one run ----------------------------------------------------------------------------- */

typedef struct {
    ms_icpt_t *ic;
    ms_metrics_t *metrics;
    FILE *timeline;      // c->timeline: every run's vehicles, radar truth, tracks, intercepts
    double entity_due_s; // the next second to write entities at (one a second)
    double entity_t_s;   // the time being written (every batch of that time)
} s_watch_t;

/* The timeline: one CSV row per entity a second, per radar truth
 * item, per track and per intercept message, with the columns of
 * LS_MC_TIMELINE_HEADER. */
static void s_timeline (s_watch_t *w, const char *topic, const ProtobufCMessage *msg,
                        const Cgs__Header *hdr)
{
    FILE *f = w->timeline;
    double t = hdr ? hdr->sim_time_s : 0;
    if (strcmp (topic, "entity") == 0) {
        if (t != w->entity_t_s) { // uavsim's batches of one time go out together
            if (t + 1e-9 < w->entity_due_s)
                return;
            w->entity_t_s = t;
            w->entity_due_s = floor (t) + 1;
        }
        const Cgs__EntityBatch *b = (const Cgs__EntityBatch *)msg;
        for (size_t i = 0; i < b->n_entities; i++) {
            const Cgs__Entity *e = b->entities[i];
            if (!e->position || !e->velocity)
                continue;
            fprintf (f, "entity,%.2f,%u,%.1f,%.1f,%.2f,%.2f,,,,,,,,,,\n", t, e->entity_id,
                     e->position->east_m, e->position->north_m, e->velocity->east_mps,
                     e->velocity->north_mps);
        }
    } else if (strcmp (topic, "mti.truth") == 0) {
        const Cgs__MtiTruth *m = (const Cgs__MtiTruth *)msg;
        for (size_t i = 0; i < m->n_items; i++) {
            const Cgs__MtiTruthItem *it = m->items[i];
            if (!it->in_beam)
                continue;
            fprintf (f, "truth,%.2f,%u,,,%.2f,,%s,%u,,,,,%.3f,,,%s\n", t, it->entity_id,
                     it->radial_velocity_mps, it->detected ? "detected" : "missed", it->hit_id,
                     it->pd,
                     !it->visible      ? "masked"
                     : it->merged_into ? "merged"
                                       : "");
        }
    } else if (strcmp (topic, "track") == 0) {
        const Cgs__TrackBatch *b = (const Cgs__TrackBatch *)msg;
        for (size_t i = 0; i < b->n_tracks; i++) {
            const Cgs__Track *k = b->tracks[i];
            if (!k->position || !k->velocity)
                continue;
            double sd =
                k->n_covariance >= 16 ? sqrt (fmax (0, k->covariance[0] + k->covariance[5])) : NAN;
            double ps = k->n_mode_probabilities >= 3 ? k->mode_probabilities[2] : NAN;
            fprintf (f, "track,%.2f,%u,%.1f,%.1f,%.2f,%.2f,%s,%u,%u,%u,%.2f,%.3f,%.3f,%.1f,%.3f,\n",
                     t, k->track_id, k->position->east_m, k->position->north_m,
                     k->velocity->east_mps, k->velocity->north_mps,
                     k->status == CGS__TRACK_STATUS__TRACK_STATUS_CONFIRMED  ? "confirmed"
                     : k->status == CGS__TRACK_STATUS__TRACK_STATUS_COASTING ? "coasting"
                     : k->status == CGS__TRACK_STATUS__TRACK_STATUS_DELETED  ? "deleted"
                                                                             : "tentative",
                     k->hit_count, k->miss_count, k->continues, k->continues_probability,
                     k->existence_probability, k->detection_probability, sd, ps);
        }
    } else if (strcmp (topic, "intercept") == 0) {
        const Cgs__Intercept *m = (const Cgs__Intercept *)msg;
        fprintf (f, "intercept,%.2f,%u,,,,,%d,,,,,,,,,\n", t, m->track_id, (int)m->state);
    }
}

/* The metrics see every message after the observer (the run's own, fed first). */
static void s_watch (void *arg, const char *topic, const ProtobufCMessage *msg,
                     const Cgs__Header *hdr)
{
    s_watch_t *w = arg;
    if (w->timeline)
        s_timeline (w, topic, msg, hdr);
    if (!w->metrics)
        return;
    if (strcmp (topic, "entity") == 0)
        ms_metrics_on_entity (w->metrics, topic, msg, hdr);
    else if (strcmp (topic, "mti.truth") == 0)
        ms_metrics_on_mti_truth (w->metrics, topic, msg, hdr);
    else if (strcmp (topic, "track") == 0)
        ms_metrics_on_track (w->metrics, topic, msg, hdr);
}

int ls_mc_one (const ls_mc_config_t *c, size_t i, FILE *log, ls_mc_run_t *ret, char *err,
               size_t errlen)
{
    ls_mc_run_t out = {.index = i, .miss_m = NAN, .closest_m = NAN, .time_to_image_s = NAN};
    ls_mc_variation (c, i, &out.exercise_seed, &out.designation_shift_s, &out.uav_phase_deg);
    ls_run_result_t *res = calloc (1, sizeof *res);
    if (!res)
        return -ENOMEM;
    s_watch_t w = {.ic = &res->icpt, .timeline = c->timeline, .entity_t_s = NAN};
    if (w.timeline)
        fputs (LS_MC_TIMELINE_HEADER "\n", w.timeline);
    ls_run_config_t rc = {
        .exercise_path = c->exercise_path,
        .scenario_path = c->scenario_path,
        .seed_given = true,
        .seed = out.exercise_seed,
        .designation_shift_s = out.designation_shift_s,
        .uav_phase_given = isfinite (out.uav_phase_deg),
        .uav_phase_deg = out.uav_phase_deg,
        .limit_s = c->limit_s,
        .log = log,
        .watch = s_watch,
        .watch_arg = &w,
    };
    // The metrics read the observer's hit attribution: made before the run,
    // pointed at the observer the run fills.
    w.metrics = ms_metrics_new (&res->icpt);
    if (!w.metrics) {
        free (res);
        return -ENOMEM;
    }
    int rcode = ls_run (&rc, res, err, errlen);
    if (rcode == 0) {
        const ms_icpt_t *ic = &res->icpt;
        const cgs_score_t *sc = &ic->score;
        out.designated = ic->designated;
        out.imaged = ic->designated && sc->imaged;
        out.wrong_vehicle = ic->designated && ic->other_entity_id != 0;
        out.lost = ic->designated && ic->desig_state == CGS__INTERCEPT_STATE__INTERCEPT_STATE_LOST;
        out.miss_m = ic->designated ? (sc->imaged ? 0 : sc->closest_edge_m) : NAN;
        out.closest_m = sc->closest_m;
        out.time_to_image_s = cgs_score_time_to_image (sc);
        out.end_s = res->end_s;
        out.replans = ic->replans;
        out.target_entity_id = ic->entity_id;
        out.other_entity_id = out.wrong_vehicle ? ic->other_entity_id : 0;
        out.other_since_s = out.wrong_vehicle ? ic->other_since_s : NAN;
        out.other_unseen_s = out.wrong_vehicle ? ic->other_unseen_s : NAN;
        out.other_gap_m = out.wrong_vehicle ? ic->other_gap_m : NAN;
        snprintf (out.final_state, sizeof out.final_state, "%s",
                  ic->designated ? ms_icpt_state_name (ic->desig_state) : "NONE");
        out.outcome = !ic->designated     ? LS_MC_NOT_DESIGNATED
                      : out.imaged        ? LS_MC_IMAGED
                      : out.wrong_vehicle ? LS_MC_WRONG_VEHICLE
                      : out.lost          ? LS_MC_LOST
                      : ic->final         ? LS_MC_MISSED
                                          : LS_MC_UNFINISHED;
        out.bad_inputs = res->bad_inputs;
        out.errors = res->errors;
        out.failures = res->failures + ms_metrics_failures (w.metrics);
        snprintf (out.first_error, sizeof out.first_error, "%s", res->first_error);
        ms_siap_end_run (ms_metrics_siap (w.metrics));
        ms_siap_result (ms_metrics_siap (w.metrics), &out.siap);
        out.gospa = *ms_metrics_gospa (w.metrics);
        *ret = out;
    }
    ms_metrics_destroy (&w.metrics);
    free (res);
    return rcode;
}

/* ---- the set ---------------------------------------------------------------------------- */

static int s_cmp (const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* The q-quantile (nearest rank) of v[0..n-1], sorted in place; NaN when n = 0. */
static double s_quantile (double *v, size_t n, double q)
{
    if (n == 0)
        return NAN;
    qsort (v, n, sizeof *v, s_cmp);
    size_t k = (size_t)ceil (q * (double)n);
    return v[k == 0 ? 0 : k - 1];
}

/* Pool the runs, in index order. */
static int s_pool (const ls_mc_config_t *c, const ls_mc_run_t *runs, ls_mc_result_t *ret)
{
    ls_mc_result_t r = {.runs = c->runs};
    double *miss = calloc (c->runs, sizeof *miss), *tti = calloc (c->runs, sizeof *tti);
    if (!miss || !tti) {
        free (miss);
        free (tti);
        return -ENOMEM;
    }
    size_t nm = 0, nt = 0;
    ms_gospa_mean_t g = {0};
    for (size_t i = 0; i < c->runs; i++) {
        const ls_mc_run_t *o = &runs[i];
        r.designated += o->designated;
        r.imaged += o->imaged;
        r.wrong_vehicle += o->outcome == LS_MC_WRONG_VEHICLE;
        r.lost += o->outcome == LS_MC_LOST;
        r.not_designated += o->outcome == LS_MC_NOT_DESIGNATED;
        r.unfinished += o->outcome == LS_MC_UNFINISHED;
        if (o->designated && isfinite (o->miss_m))
            miss[nm++] = o->miss_m;
        if (o->imaged)
            tti[nt++] = o->time_to_image_s;
        ms_siap_result_pool (&r.siap, &o->siap);
        ms_gospa_mean_merge (&g, &o->gospa);
        r.bad_inputs += o->bad_inputs;
        r.errors += o->errors;
        r.failures += o->failures;
    }
    // Imaged out of every run: a run without a designation counts as a miss.
    double n = (double)r.runs, k = (double)r.imaged;
    r.imaged_pct = 100 * k / n;
    double lo = NAN, hi = NAN; // left NAN (null in the JSON) where no interval can be had
    if (cgs_binomial_interval (r.imaged, r.runs, 0.95, &lo, &hi) == 0) {
        r.imaged_lo_pct = 100 * lo;
        r.imaged_hi_pct = 100 * hi;
    } else {
        r.imaged_lo_pct = r.imaged_hi_pct = NAN;
    }
    r.miss_p50_m = s_quantile (miss, nm, 0.5);
    r.miss_p95_m = s_quantile (miss, nm, 0.95);
    r.time_to_image_p50_s = s_quantile (tti, nt, 0.5);
    r.time_to_image_p95_s = s_quantile (tti, nt, 0.95);
    ms_gospa_mean_finish (&g, &r.gospa);
    free (miss);
    free (tti);
    *ret = r;
    return 0;
}

/* A worker process: runs j, j + jobs, ... each sent back whole on fd. */
static void s_worker (const ls_mc_config_t *c, int j, int fd)
{
    char err[512];
    for (size_t i = (size_t)j; i < c->runs; i += (size_t)c->jobs) {
        ls_mc_run_t run;
        int rc = ls_mc_one (c, i, NULL, &run, err, sizeof err);
        if (rc < 0) {
            run = (ls_mc_run_t){.index = i, .rc = rc};
            snprintf (run.first_error, sizeof run.first_error, "%s", err);
        }
        if (cgs_write_all (fd, &run, sizeof run) < 0)
            _exit (2);
    }
    _exit (0);
}

int ls_mc_run (const ls_mc_config_t *c, ls_mc_run_t *runs, ls_mc_progress_fn *progress, void *arg,
               ls_mc_result_t *ret, char *err, size_t errlen)
{
    if (!c || c->runs == 0 || c->jobs < 1 || c->jobs > S_JOBS_MAX || !c->exercise_path) {
        cgs_errf (err, errlen, "a Monte Carlo set needs runs >= 1 and 1..%d jobs", S_JOBS_MAX);
        return -EINVAL;
    }
    size_t done = 0;
    if (c->jobs == 1) {
        for (size_t i = 0; i < c->runs; i++) {
            int rc = ls_mc_one (c, i, NULL, &runs[i], err, errlen);
            if (rc < 0)
                return rc;
            if (progress)
                progress (arg, ++done, &runs[i]);
        }
        return s_pool (c, runs, ret);
    }
    int fds[S_JOBS_MAX];
    pid_t pids[S_JOBS_MAX];
    int jobs = c->jobs;
    fflush (NULL); // nothing buffered is written twice
    for (int j = 0; j < jobs; j++) {
        int p[2];
        if (pipe (p) < 0) {
            cgs_errf (err, errlen, "pipe: %s", strerror (errno));
            jobs = j;
            goto fail;
        }
        pid_t pid = fork ();
        if (pid < 0) {
            cgs_errf (err, errlen, "fork: %s", strerror (errno));
            close (p[0]);
            close (p[1]);
            jobs = j;
            goto fail;
        }
        if (pid == 0) {
            close (p[0]);
            for (int k = 0; k < j; k++)
                close (fds[k]);
            s_worker (c, j, p[1]);
        }
        close (p[1]);
        fds[j] = p[0];
        pids[j] = pid;
    }
    // Run i comes from worker i mod jobs, which sends its runs in order: read
    // them in index order (a worker ahead of the others waits in its pipe).
    for (size_t i = 0; i < c->runs; i++) {
        int j = (int)(i % (size_t)jobs);
        ls_mc_run_t run;
        size_t got = 0;
        while (got < sizeof run) {
            ssize_t n = read (fds[j], (char *)&run + got, sizeof run - got);
            if (n < 0 && errno == EINTR)
                continue;
            if (n <= 0)
                break;
            got += (size_t)n;
        }
        if (got < sizeof run || run.index != i) {
            cgs_errf (err, errlen, "Monte Carlo worker %d died before run %zu", j, i);
            goto fail;
        }
        if (run.rc < 0) {
            cgs_errf (err, errlen, "%s", run.first_error);
            goto fail;
        }
        runs[i] = run;
        if (progress)
            progress (arg, ++done, &runs[i]);
    }
    for (int j = 0; j < jobs; j++) {
        close (fds[j]);
        waitpid (pids[j], NULL, 0);
    }
    return s_pool (c, runs, ret);
fail:
    for (int j = 0; j < jobs; j++) {
        close (fds[j]);
        kill (pids[j], SIGTERM);
        waitpid (pids[j], NULL, 0);
    }
    return -EIO;
}
