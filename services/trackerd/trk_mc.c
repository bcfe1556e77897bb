/* trk_mc — Monte Carlo runs of the tracker (see trk_mc.h). */
#include "trk_mc.h"
#include "trk_tracker.h"
#include "cgs_util.h"

#include <errno.h>
#include <math.h>
#include <stdbool.h>
#include <stdlib.h>

#define S_PI        3.14159265358979323846
#define S_SPACING_M 5000.0 // between targets

/* One target's truth and what the tracker made of it. */
typedef struct {
    double p0[2], v1[2], v2[2]; // start, velocity before and after the turn
    double offset_s;            // its hit time within each scan
    double turn_s;              // time of the turn (INFINITY: none)
    double side;                // +1 turns right (clockwise), −1 left
    uint32_t track_id;          // its track, 0 before it has one
    bool settled;               // its track id is fixed from here on
    bool completed;             // its turn's completion was counted
} s_target_t;

typedef struct {
    uint64_t s;
    bool have;
    double spare;
} s_rng_t;

static double s_uniform (s_rng_t *r)
{
    return cgs_uniform01 (&r->s);
}

static double s_gauss (s_rng_t *r)
{
    if (r->have) {
        r->have = false;
        return r->spare;
    }
    double u = s_uniform (r), v = s_uniform (r), m = sqrt (-2 * log (u));
    r->spare = m * sin (2 * S_PI * v);
    r->have = true;
    return m * cos (2 * S_PI * v);
}

static void s_truth (const s_target_t *g, double t, double pos[2], double vel[2])
{
    for (int a = 0; a < 2; a++) {
        if (t <= g->turn_s) {
            pos[a] = g->p0[a] + g->v1[a] * t;
            vel[a] = g->v1[a];
        } else {
            pos[a] = g->p0[a] + g->v1[a] * g->turn_s + g->v2[a] * (t - g->turn_s);
            vel[a] = g->v2[a];
        }
    }
}

static size_t s_target_of (const s_target_t *g, size_t n, uint32_t track_id)
{
    for (size_t i = 0; i < n; i++)
        if (g[i].track_id == track_id)
            return i;
    return SIZE_MAX;
}

int trk_mc_run (const trk_params_t *p, const trk_mc_config_t *cfg, trk_mc_result_t *ret)
{
    size_t n = cfg->targets;
    double T = p->filter.dt_s;
    if (n == 0 || n > 1000000 || cfg->scans < 3 || (double)n * (double)cfg->scans >= 4e9 ||
        cfg->settle_scans >= cfg->scans || !(cfg->speed_mps >= 0) || !(cfg->sigma_meas_m[0] > 0) ||
        !(cfg->sigma_meas_m[1] > 0) ||
        (cfg->turn_scan && (cfg->turn_scan <= cfg->settle_scans || cfg->turn_scan >= cfg->scans)))
        return -EINVAL;
    trk_tracker_t *trk = trk_tracker_new (p);
    s_target_t *g = calloc (n, sizeof *g);
    trk_hit_t *hits = calloc (n, sizeof *hits);
    if (!trk || !g || !hits) {
        trk_tracker_destroy (&trk);
        free (g);
        free (hits);
        return -ENOMEM;
    }
    s_rng_t rng = {.s = cfg->seed};
    size_t side = (size_t)ceil (sqrt ((double)n));
    // One heading for all, so the targets keep their spacing however long the run.
    double h = 2 * S_PI * s_uniform (&rng);
    for (size_t i = 0; i < n; i++) {
        s_target_t *t = &g[i];
        t->p0[0] = (double)(i % side) * S_SPACING_M;
        t->p0[1] = (double)(i / side) * S_SPACING_M;
        t->v1[0] = cfg->speed_mps * sin (h);
        t->v1[1] = cfg->speed_mps * cos (h);
        t->offset_s = 0.9 * T * s_uniform (&rng);
        t->turn_s = INFINITY;
        t->side = s_uniform (&rng) < 0.5 ? -1 : 1;
        if (cfg->turn_scan) {
            double a = h + t->side * cfg->turn_deg * S_PI / 180;
            t->v2[0] = cfg->speed_mps * sin (a);
            t->v2[1] = cfg->speed_mps * cos (a);
            double before = (double)(cfg->turn_scan - 1) * T + t->offset_s;
            t->turn_s = before + T * s_uniform (&rng);
        }
    }
    trk_mc_result_t r = {0};
    double se[2] = {0, 0}, sv[2] = {0, 0}, asum = 0, asum2 = 0;
    int rc = 0;
    for (size_t k = 0; k < cfg->scans && rc == 0; k++) {
        for (size_t i = 0; i < n; i++) {
            double t = (double)k * T + g[i].offset_s, pos[2], vel[2];
            s_truth (&g[i], t, pos, vel);
            hits[i] = (trk_hit_t){
                .hit_id = (uint32_t)(k * n + i + 1),
                .t_s = t,
                .z = {pos[0] + cfg->sigma_meas_m[0] * s_gauss (&rng),
                      pos[1] + cfg->sigma_meas_m[1] * s_gauss (&rng)},
            };
        }
        trk_scan_t scan = {
            .uav_id = 1,
            .scan_number = (uint32_t)k + 1,
            .start_s = (double)k * T,
            .end_s = (double)(k + 1) * T,
            .full_revolution = true,
        };
        trk_scan_out_t out;
        if ((rc = trk_tracker_scan (trk, &scan, hits, n, &out)) < 0)
            break;
        // Which track took which target's hit.
        for (size_t j = 0; j < trk_tracker_count (trk); j++) {
            const trk_track_t *tr = trk_tracker_at (trk, j);
            if (tr->last_scan != scan.scan_number || tr->history_count == 0)
                continue;
            uint32_t hid = tr->history[tr->history_count - 1].hit_id;
            if (hid == 0 || (hid - 1) / n != k)
                continue;
            size_t i = (hid - 1) % n;
            s_target_t *tg = &g[i];
            if (tg->settled && tg->track_id != tr->id)
                r.lost++;
            tg->track_id = tr->id;
            tg->settled = k >= cfg->settle_scans;
            double pos[2], vel[2];
            s_truth (tg, tr->est.t_s, pos, vel);
            bool straight = tr->est.t_s <= tg->turn_s;
            if (k >= cfg->settle_scans && straight && tr->updates > 0) {
                for (int a = 0; a < 2; a++) {
                    se[a] += (tr->est.x[a] - pos[a]) * (tr->est.x[a] - pos[a]);
                    sv[a] += (tr->est.x[a + 2] - vel[a]) * (tr->est.x[a + 2] - vel[a]);
                }
                r.samples++;
            }
        }
        for (size_t i = 0; i < n; i++)
            if (k >= cfg->settle_scans && (double)k * T + g[i].offset_s <= g[i].turn_s)
                r.straight_scans++;
        for (size_t e = 0; e < out.turn_count; e++) {
            const trk_turn_t *ev = &out.turns[e];
            size_t i = s_target_of (g, n, ev->track_id);
            if (i == SIZE_MAX)
                continue;
            bool after = ev->t_s > g[i].turn_s;
            if (!ev->complete) {
                if (after && (k == cfg->turn_scan || k == cfg->turn_scan + 1))
                    r.detected++;
                else if (!after && k >= cfg->settle_scans)
                    r.false_turns++;
            } else if (after && !g[i].completed) { // the first completion after the turn
                g[i].completed = true;
                r.completed++;
                if (ev->angle_deg * g[i].side > 0)
                    r.right_side++;
                asum += fabs (ev->angle_deg);
                asum2 += ev->angle_deg * ev->angle_deg;
            }
        }
    }
    if (rc == 0) {
        r.turns = cfg->turn_scan ? n : 0;
        for (int a = 0; a < 2 && r.samples; a++) {
            r.rmse_pos_m[a] = sqrt (se[a] / (double)r.samples);
            r.rmse_vel_mps[a] = sqrt (sv[a] / (double)r.samples);
        }
        if (r.completed) {
            r.angle_mean_deg = asum / (double)r.completed;
            double var = asum2 / (double)r.completed - r.angle_mean_deg * r.angle_mean_deg;
            r.angle_sd_deg = sqrt (var > 0 ? var : 0);
        }
        *ret = r;
    }
    trk_tracker_destroy (&trk);
    free (g);
    free (hits);
    return rc;
}
