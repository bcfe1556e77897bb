/* gd_mc — Monte Carlo runs of whole intercepts (see gd_mc.h). */
#include "gd_mc.h"
#include "cgs_util.h"
#include "gd_score.h"
#include "mti_radar.h"
#include "trk_tracker.h"
#include "uavsim_uav.h"
#include "uavsim_vehicle.h"

#include <errno.h>
#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define S_PI     3.14159265358979323846
#define S_STEP_S 0.05 // simulation step (uavsim's default)
#define S_UAV_S  0.1  // the intercept hears the UAV at 10 Hz, as on `uav`
#define S_UAV_ID 1
#define S_TGT_ID 2
#define S_PICK_M 500.0 // the designated track is the confirmed one nearest the target, this near

typedef struct {
    uint64_t s;
} s_rng_t;

static double s_uniform (s_rng_t *r, double lo, double hi)
{
    return lo + (hi - lo) * cgs_uniform01 (&r->s);
}

void gd_mc_defaults (gd_mc_config_t *c)
{
    *c = (gd_mc_config_t){
        .runs = 200,
        .seed = 1,
        .method = GD_HEAD_ON,
        .range_min_m = 5000,
        .range_max_m = 9000,
        .speed_min_mps = 5,
        .speed_max_mps = 20,
        .turn_fraction = 0.5,
        .turn_min_deg = 45,
        .turn_max_deg = 120,
        .turn_after_min_s = 20,
        .turn_after_max_s = 120,
        .preroll_s = 90,
        .limit_s = 1500,
    };
}

static int s_check (const gd_mc_config_t *c)
{
    bool ok = c->runs > 0 && c->range_min_m > 0 && c->range_max_m >= c->range_min_m &&
              c->speed_min_mps > 0 && c->speed_max_mps >= c->speed_min_mps &&
              c->speed_max_mps < 30 && c->turn_fraction >= 0 && c->turn_fraction <= 1 &&
              c->turn_min_deg >= 0 && c->turn_max_deg >= c->turn_min_deg &&
              c->turn_max_deg <= 170 && c->turn_after_min_s >= 0 &&
              c->turn_after_max_s >= c->turn_after_min_s && c->preroll_s >= 30 && c->limit_s > 0 &&
              (c->method == GD_HEAD_ON || c->method == GD_MTI_HITS);
    return ok ? 0 : -EINVAL;
}

/* Everything one run needs. */
typedef struct {
    mti_radar_t *radar; // its own noise (seeded by the run's number)
    trk_tracker_t *trk;
    gd_intercept_t *gd;
    uavsim_uav_model_t *uav;
    uavsim_vehicle_t *veh;
    trk_hit_t *hits;
    size_t nhits, cap;
    gd_track_t gt;
} s_run_t;

static void s_free_run (s_run_t *r)
{
    trk_tracker_destroy (&r->trk);
    gd_intercept_destroy (&r->gd);
    uavsim_uav_destroy (&r->uav);
    uavsim_vehicle_destroy (&r->veh);
    r->nhits = 0;
}

static void s_gd_track (const trk_tracker_t *trk, const trk_track_t *t, double t_s, gd_track_t *g)
{
    trk_estimate_t e;
    trk_tracker_predict (trk, t, t_s, &e);
    g->id = t->id;
    g->status = (int)t->status;
    g->friendly = t->friendly;
    g->t_s = t_s;
    g->pos = gd_v2 (e.x[0], e.x[1]);
    g->vel = gd_v2 (e.x[2], e.x[3]);
    g->hits = t->hits;
    g->last_hit_s = t->last_hit_s;
    g->history_count = 0;
    for (uint32_t k = 0; k < t->history_count && k < GD_HISTORY_MAX; k++) {
        g->history[k] = gd_v2 (t->history[k].e_m, t->history[k].n_m);
        g->history_t_s[k] = t->history[k].t_s;
        g->history_count++;
    }
}

static int s_add_hit (s_run_t *r, const mti_hit_t *h, const mti_platform_t *pl, double t_s)
{
    if (r->nhits == r->cap) {
        size_t cap = r->cap ? r->cap * 2 : 256;
        trk_hit_t *n = realloc (r->hits, cap * sizeof *n);
        if (!n)
            return -ENOMEM;
        r->hits = n;
        r->cap = cap;
    }
    r->hits[r->nhits++] =
        trk_hit_from_mti (h->hit_id, t_s, h->position, pl->position, h->azimuth_deg,
                          h->range_sigma_m, h->azimuth_sigma_deg, h->radial_velocity_mps);
    return 0;
}

/* Give the UAV the intercept's task when it is new. */
static void s_apply_task (s_run_t *r, uint64_t *applied)
{
    const gd_task_t *t = gd_intercept_task (r->gd);
    if (t->kind == GD_TASK_NONE || t->number == *applied)
        return;
    *applied = t->number;
    if (t->kind == GD_TASK_LOITER_HERE) {
        uavsim_uav_loiter_here (r->uav, 0, true);
        return;
    }
    cgs_enu_t pts[GD_ROUTE_MAX];
    for (size_t k = 0; k < t->count; k++)
        pts[k] = (cgs_enu_t){t->points[k].e, t->points[k].n, 0};
    uavsim_uav_route (r->uav, pts, t->count, true, 0, true);
}

static void s_uav_for_gd (const uavsim_uav_model_t *m, double t_s, gd_uav_t *ret)
{
    uavsim_uav_state_t s;
    uavsim_uav_state (m, &s);
    *ret = (gd_uav_t){
        .t_s = t_s,
        .position = s.position,
        .heading_deg = s.heading_deg,
        .pitch_deg = s.pitch_deg,
        .roll_deg = s.roll_deg,
        .ground_speed_mps = s.airspeed_mps,
        .airspeed_mps = s.commanded_airspeed_mps,
        .agl_m = s.position.u_m,
        .bank_limit_deg = uavsim_uav_params (m)->bank_limit_deg,
        .depression_deg = 45,
        .hfov_deg = 10,
        .vfov_deg = 7.5,
    };
}

static void s_gd_track (const trk_tracker_t *trk, const trk_track_t *t, double t_s, gd_track_t *g);

static void s_trace (const s_run_t *r, double t, const uavsim_vehicle_state_t *vs,
                     const uavsim_uav_state_t *us, const gd_status_t *st, gd_mc_trace_fn *fn,
                     void *arg)
{
    gd_mc_sample_t s = {
        .t_s = t,
        .target = gd_v2 (vs->e_m, vs->n_m),
        .target_vel = gd_v2 (vs->ve_mps, vs->vn_mps),
        .track_id = st->track_id,
        .uav = gd_v2 (us->position.e_m, us->position.n_m),
        .uav_heading_deg = us->heading_deg,
        .status = st,
    };
    gd_track_t nearby[8];
    for (size_t k = 0; k < trk_tracker_count (r->trk); k++) {
        const trk_track_t *tt = trk_tracker_at (r->trk, k);
        trk_estimate_t e;
        trk_tracker_predict (r->trk, tt, t, &e);
        if (tt->id == st->track_id) {
            s.has_track = true;
            s.track_pos = gd_v2 (e.x[0], e.x[1]);
            s.track_vel = gd_v2 (e.x[2], e.x[3]);
        } else if (tt->status != TRK_TENTATIVE && s.nearby_count < 8 &&
                   hypot (e.x[0] - vs->e_m, e.x[1] - vs->n_m) < 3000) {
            s_gd_track (r->trk, tt, t, &nearby[s.nearby_count++]);
        }
    }
    s.nearby = nearby;
    fn (arg, &s);
}

/* One run. */
static int s_one (const gd_mc_config_t *c, mti_radar_t *radar, s_rng_t *rng, s_run_t *r,
                  gd_mc_trace_fn *trace, void *trace_arg, gd_mc_run_t *out)
{
    *out = (gd_mc_run_t){.closest_m = INFINITY, .miss_m = INFINITY, .time_to_image_s = NAN};
    // The target: straight from the origin, perhaps turning once.
    double psi = s_uniform (rng, 0, 360), v = s_uniform (rng, c->speed_min_mps, c->speed_max_mps);
    bool turns = s_uniform (rng, 0, 1) < c->turn_fraction;
    double turn = s_uniform (rng, c->turn_min_deg, c->turn_max_deg);
    if (s_uniform (rng, 0, 1) < 0.5)
        turn = -turn;
    double t_turn = c->preroll_s + s_uniform (rng, c->turn_after_min_s, c->turn_after_max_s);
    gd_v2_t d0 = gd_heading_unit (psi);
    uavsim_vehicle_point_t pts[3];
    size_t npts = 0;
    pts[npts++] = (uavsim_vehicle_point_t){0, 0, 0};
    if (turns) {
        gd_v2_t corner = gd_scale (d0, v * t_turn);
        gd_v2_t after = gd_add (corner, gd_scale (gd_heading_unit (psi + turn), 40000));
        pts[npts++] = (uavsim_vehicle_point_t){corner.e, corner.n, 0};
        pts[npts++] = (uavsim_vehicle_point_t){after.e, after.n, 0};
    } else {
        gd_v2_t far = gd_scale (d0, 60000);
        pts[npts++] = (uavsim_vehicle_point_t){far.e, far.n, 0};
    }
    uavsim_vehicle_params_t vp;
    uavsim_vehicle_params_defaults (&vp);
    vp.points = pts;
    vp.n_points = npts;
    vp.speed_mps = v;
    vp.corner_cut_m = 30;
    // The UAV: range_min..range_max from where the target will be at the designation.
    gd_v2_t at_des = gd_scale (d0, v * c->preroll_s);
    double bearing = s_uniform (rng, 0, 360),
           range = s_uniform (rng, c->range_min_m, c->range_max_m);
    gd_v2_t up = gd_add (at_des, gd_scale (gd_heading_unit (bearing), range));
    uavsim_uav_params_t upar;
    uavsim_uav_params_defaults (&upar);
    uavsim_uav_init_t ui = {
        .position = {up.e, up.n, 1200},
        .heading_deg = s_uniform (rng, 0, 360),
        .airspeed_mps = 38,
        .agl_m = 1200,
        .loiter_radius_m = 1800,
        .loiter_clockwise = true,
    };
    trk_params_t tp;
    trk_params_defaults (&tp);
    gd_params_t gp;
    gd_params_defaults (&gp);
    r->radar = radar;
    r->trk = trk_tracker_new (&tp);
    r->gd = gd_intercept_new (&gp, NULL);
    r->uav = uavsim_uav_new (&upar, &ui);
    if (!r->trk || !r->gd || !r->uav || uavsim_vehicle_new (&vp, &r->veh) < 0)
        return -ENOMEM;
    gd_intercept_set_method (r->gd, c->method);
    out->speed_mps = v;
    out->turned = turns;
    out->turn_deg = turns ? turn : 0;
    gd_score_t score;
    gd_score_init (&score);
    uint64_t dwell = 0, applied = 0;
    uint32_t track_id = 0;
    bool designated = false, first_plan = false;
    double t = 0, next_uav = 0, t_des = NAN, scan_start = 0, next_trace = 0;
    gd_phase_t traced = GD_IDLE;
    double end_s = c->preroll_s + 60 + c->limit_s;
    r->nhits = 0;
    while (t < end_s) {
        uavsim_uav_step (r->uav, S_STEP_S, 0);
        uavsim_vehicle_step (r->veh, t, S_STEP_S);
        t += S_STEP_S;
        uavsim_vehicle_state_t vs;
        uavsim_vehicle_state (r->veh, &vs);
        uavsim_uav_state_t us;
        uavsim_uav_state (r->uav, &us);
        // The radar's dwells that ended by now.
        mti_dwell_t d;
        for (mti_radar_schedule (radar, dwell, us.heading_deg, &d); d.end_s <= t;
             mti_radar_schedule (radar, ++dwell, us.heading_deg, &d)) {
            double tc = (d.start_s + d.end_s) / 2;
            mti_platform_t pl = {us.position, us.velocity, us.heading_deg};
            mti_target_t tg = {S_TGT_ID, {vs.e_m, vs.n_m, 0}, {vs.ve_mps, vs.vn_mps, 0}, NULL};
            mti_dwell_out_t o;
            if (d.scan_start)
                scan_start = d.start_s;
            if (mti_radar_dwell (radar, &d, &pl, &tg, 1, &o) < 0)
                return -ENOMEM;
            for (size_t k = 0; k < o.hit_count; k++)
                if (s_add_hit (r, &o.hits[k], &pl, tc) < 0)
                    return -ENOMEM;
            if (!d.scan_end)
                continue;
            trk_scan_t scan = {
                .uav_id = S_UAV_ID,
                .scan_number = d.scan,
                .start_s = scan_start,
                .end_s = d.end_s,
                .full_revolution = true,
                .platform = {us.position.e_m, us.position.n_m},
            };
            trk_scan_out_t so;
            if (trk_tracker_scan (r->trk, &scan, r->hits, r->nhits, &so) < 0)
                return -ENOMEM;
            r->nhits = 0;
            if (!designated && t >= c->preroll_s) {
                // The operator clicks the target's track.
                gd_track_t best = {0};
                double best_d = S_PICK_M;
                for (size_t k = 0; k < trk_tracker_count (r->trk); k++) {
                    const trk_track_t *tt = trk_tracker_at (r->trk, k);
                    if (tt->status != TRK_CONFIRMED)
                        continue;
                    s_gd_track (r->trk, tt, d.end_s, &r->gt);
                    double dd = gd_norm (gd_sub (r->gt.pos, gd_v2 (vs.e_m, vs.n_m)));
                    if (dd < best_d) {
                        best_d = dd;
                        best = r->gt;
                    }
                }
                char why[128];
                if (best.id && gd_intercept_designate (r->gd, &best, t, why, sizeof why) == 0) {
                    designated = true;
                    track_id = best.id;
                    t_des = t;
                    gd_score_designated (&score, t);
                }
            } else if (designated) {
                // As trackerd publishes them: turns, then every track, the
                // deleted ones once.
                gd_status_t ds;
                gd_intercept_status (r->gd, &ds);
                track_id = ds.track_id;
                for (size_t k = 0; k < so.turn_count; k++)
                    if (so.turns[k].track_id == track_id)
                        gd_intercept_turn (r->gd, track_id, so.turns[k].t_s,
                                           gd_v2 (so.turns[k].v_after[0], so.turns[k].v_after[1]),
                                           so.turns[k].angle_deg);
                for (size_t k = 0; k < so.deleted_count; k++) {
                    s_gd_track (r->trk, &so.deleted_tracks[k], d.end_s, &r->gt);
                    r->gt.status = 3;
                    gd_intercept_track (r->gd, &r->gt);
                }
                for (size_t k = 0; k < trk_tracker_count (r->trk); k++) {
                    s_gd_track (r->trk, trk_tracker_at (r->trk, k), d.end_s, &r->gt);
                    gd_intercept_track (r->gd, &r->gt);
                }
            }
        }
        if (!designated && t > c->preroll_s + 60)
            break; // no confirmed track of the target in time
        if (designated && t + 1e-9 >= next_uav) {
            gd_uav_t gu;
            s_uav_for_gd (r->uav, t, &gu);
            gd_intercept_uav (r->gd, &gu);
            gd_intercept_tick (r->gd, t);
            next_uav = t + S_UAV_S;
            gd_status_t st;
            gd_intercept_status (r->gd, &st);
            if (!first_plan && st.has_plan) {
                first_plan = true;
                out->ahead = st.y_u_m > 0;
            }
            gd_score_footprint (&score, t, st.has_footprint ? &st.footprint : NULL);
            gd_score_target (&score, t, gd_v2 (vs.e_m, vs.n_m));
            s_apply_task (r, &applied);
            if (trace && (t + 1e-9 >= next_trace || st.phase != traced)) {
                s_trace (r, t, &vs, &us, &st, trace, trace_arg);
                next_trace = floor (t) + 1;
                traced = st.phase;
            }
            if (st.phase == GD_DONE || st.phase == GD_LOST || t - t_des > c->limit_s)
                break;
        }
    }
    gd_status_t st;
    gd_intercept_status (r->gd, &st);
    out->designated = designated;
    out->imaged = score.imaged;
    out->closest_m = score.closest_m;
    out->miss_m = score.imaged ? 0 : score.closest_edge_m;
    out->time_to_image_s = gd_score_time_to_image (&score);
    out->replans = st.replans;
    out->final_phase = (int)st.phase;
    return 0;
}

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

/* Run number i of the set: its own geometry and its own radar noise, both
 * from the seed and i alone, so any run can be repeated by itself. */
static int s_run_number (const gd_mc_config_t *c, mti_radar_t *radar, size_t i, s_run_t *r,
                         gd_mc_trace_fn *trace, void *trace_arg, gd_mc_run_t *out)
{
    uint64_t base = c->seed * 0x100000001b3ull + i;
    s_rng_t rng = {base};
    uint64_t mix = base ^ 0x6d6331ull;
    mti_radar_reseed (radar, cgs_splitmix64 (&mix));
    int rc = s_one (c, radar, &rng, r, trace, trace_arg, out);
    s_free_run (r);
    return rc;
}

static mti_radar_t *s_radar (void)
{
    mti_params_t mp;
    mti_params_defaults (&mp);
    return mti_radar_new (&mp, NULL, 1);
}

size_t gd_mc_draw_cap (const gd_mc_config_t *c)
{
    return 2 * c->runs + 50;
}

int gd_mc_run (const gd_mc_config_t *c, gd_mc_run_t *runs_out, gd_mc_progress_fn *progress,
               void *arg, gd_mc_result_t *ret)
{
    if (!c || !ret || s_check (c) < 0)
        return -EINVAL;
    mti_radar_t *radar = s_radar ();
    double *closest = calloc (c->runs, sizeof *closest);
    double *miss = calloc (c->runs, sizeof *miss);
    double *tti = calloc (c->runs, sizeof *tti);
    s_run_t r = {0};
    int rc = radar && closest && miss && tti ? 0 : -ENOMEM;
    gd_mc_result_t res = {0};
    size_t nc = 0, nt = 0;
    double replans = 0;
    size_t cap = gd_mc_draw_cap (c);
    for (size_t i = 0; rc == 0 && res.designated < c->runs && i < cap; i++) {
        gd_mc_run_t one;
        rc = s_run_number (c, radar, i, &r, NULL, NULL, &one);
        if (rc < 0)
            break;
        one.index = i;
        res.drawn++;
        if (one.designated)
            res.designated++;
        if (progress)
            progress (arg, res.designated, &one);
        if (!one.designated)
            continue;
        if (runs_out)
            runs_out[res.designated - 1] = one;
        res.imaged += one.imaged;
        if (one.ahead) {
            res.ahead++;
            res.ahead_imaged += one.imaged;
        } else {
            res.behind++;
            res.behind_imaged += one.imaged;
        }
        if (one.turned) {
            res.turned++;
            res.turned_imaged += one.imaged;
        } else {
            res.straight++;
            res.straight_imaged += one.imaged;
        }
        closest[nc] = one.closest_m;
        miss[nc++] = one.miss_m;
        if (one.imaged)
            tti[nt++] = one.time_to_image_s;
        replans += one.replans;
    }
    if (rc == 0) {
        res.closest_p50_m = s_quantile (closest, nc, 0.5);
        res.closest_p90_m = s_quantile (closest, nc, 0.9);
        res.closest_p95_m = s_quantile (closest, nc, 0.95);
        res.closest_max_m = s_quantile (closest, nc, 1.0);
        res.miss_p95_m = s_quantile (miss, nc, 0.95);
        res.miss_p99_m = s_quantile (miss, nc, 0.99);
        res.miss_max_m = s_quantile (miss, nc, 1.0);
        res.time_to_image_p50_s = s_quantile (tti, nt, 0.5);
        res.time_to_image_p95_s = s_quantile (tti, nt, 0.95);
        res.replans_mean = res.designated ? replans / (double)res.designated : NAN;
        *ret = res;
    }
    free (r.hits);
    free (closest);
    free (miss);
    free (tti);
    mti_radar_destroy (&radar);
    return rc;
}

int gd_mc_trace (const gd_mc_config_t *c, size_t run, gd_mc_trace_fn *fn, void *arg,
                 gd_mc_run_t *ret)
{
    if (!c || !fn || !ret || s_check (c) < 0 || run >= gd_mc_draw_cap (c))
        return -EINVAL;
    mti_radar_t *radar = s_radar ();
    if (!radar)
        return -ENOMEM;
    s_run_t r = {0};
    int rc = s_run_number (c, radar, run, &r, fn, arg, ret);
    free (r.hits);
    mti_radar_destroy (&radar);
    return rc;
}

/* ---- the command line ---------------------------------------------------------------------- */

static void s_progress (void *arg, size_t done, const gd_mc_run_t *run)
{
    const gd_mc_config_t *c = arg;
    if (!run->designated)
        fprintf (stderr, "  run %zu: no confirmed track of the target in time: drawn again\n",
                 run->index);
    else if (!run->imaged)
        fprintf (stderr,
                 "  run %zu: missed by %.0f m (speed %.1f m/s, %s, turn %+.0f deg, %u re-plans, "
                 "ended %s)\n",
                 run->index, run->miss_m, run->speed_mps, run->ahead ? "ahead" : "behind",
                 run->turn_deg, run->replans, gd_phase_name ((gd_phase_t)run->final_phase));
    if (run->designated && (done % 20 == 0 || done == c->runs))
        fprintf (stderr, "monte carlo: %zu/%zu intercepts\n", done, c->runs);
}

static void s_print_sample (void *arg, const gd_mc_sample_t *s)
{
    (void)arg;
    const gd_status_t *st = s->status;
    printf ("%8.1f %-12s target %8.0f %8.0f v %5.1f %5.1f", s->t_s, gd_phase_name (st->phase),
            s->target.e, s->target.n, s->target_vel.e, s->target_vel.n);
    if (s->has_track)
        printf (" | track %u %8.0f %8.0f v %5.1f %5.1f", s->track_id, s->track_pos.e,
                s->track_pos.n, s->track_vel.e, s->track_vel.n);
    else
        printf (" | track %u none%34s", s->track_id, "");
    printf (" | uav %8.0f %8.0f hdg %5.1f", s->uav.e, s->uav.n, s->uav_heading_deg);
    if (st->has_footprint) {
        gd_v2_t c = st->footprint.center;
        printf (" | fp %8.0f %8.0f", c.e, c.n);
    }
    printf (" | %s", st->reason);
    for (size_t k = 0; k < s->nearby_count; k++) {
        const gd_track_t *o = &s->nearby[k];
        printf (" | other track %u (%s, %u hits, first at %.0f s) %.0f %.0f v %.1f %.1f", o->id,
                o->status == 1 ? "confirmed" : "coasting", o->hits,
                o->history_count ? o->history_t_s[0] : NAN, o->pos.e, o->pos.n, o->vel.e, o->vel.n);
    }
    printf ("\n");
}

static double s_pct (size_t a, size_t b)
{
    return b ? 100.0 * (double)a / (double)b : NAN;
}

int gd_mc_main (int argc, char **argv)
{
    gd_mc_config_t c;
    gd_mc_defaults (&c);
    bool quiet = false;
    long trace = -1;
    static const struct option opts[] = {
        {"monte-carlo", no_argument, NULL, 'M'},
        {"runs", required_argument, NULL, 'n'},
        {"seed", required_argument, NULL, 's'},
        {"method", required_argument, NULL, 'm'},
        {"turn-fraction", required_argument, NULL, 't'},
        {"quiet", no_argument, NULL, 'q'},
        {"trace", required_argument, NULL, 'T'},
        {"help", no_argument, NULL, 'h'},
        {NULL, 0, NULL, 0},
    };
    int o;
    char *end = NULL;
    uint64_t u = 0;
    optind = 1;
    while ((o = getopt_long (argc, argv, "n:s:m:t:qT:h", opts, NULL)) != -1) {
        switch (o) {
        case 'M':
            break;
        case 'n':
            if (cgs_parse_u64 (optarg, 1000000, &u) < 0 || u == 0) {
                fprintf (stderr, "guidanced: --runs: expected a count 1..1000000, got '%s'\n",
                         optarg);
                return 2;
            }
            c.runs = (size_t)u;
            break;
        case 's':
            if (cgs_parse_u64 (optarg, UINT64_MAX, &c.seed) < 0) {
                fprintf (stderr, "guidanced: --seed: expected an integer, got '%s'\n", optarg);
                return 2;
            }
            break;
        case 'm':
            if (strcmp (optarg, "head-on") == 0)
                c.method = GD_HEAD_ON;
            else if (strcmp (optarg, "mti-hits") == 0)
                c.method = GD_MTI_HITS;
            else {
                fprintf (stderr, "guidanced: --method: expected head-on or mti-hits, got '%s'\n",
                         optarg);
                return 2;
            }
            break;
        case 't':
            c.turn_fraction = strtod (optarg, &end);
            if (end == optarg || *end || !(c.turn_fraction >= 0 && c.turn_fraction <= 1)) {
                fprintf (stderr, "guidanced: --turn-fraction: expected 0..1, got '%s'\n", optarg);
                return 2;
            }
            break;
        case 'q':
            quiet = true;
            break;
        case 'T':
            if (cgs_parse_u64 (optarg, 999999, &u) < 0) {
                fprintf (stderr, "guidanced: --trace: expected a run number, got '%s'\n", optarg);
                return 2;
            }
            trace = (long)u;
            break;
        case 'h':
            printf ("usage: guidanced --monte-carlo [--runs N] [--seed S] [--method "
                    "head-on|mti-hits]\n"
                    "                 [--turn-fraction F] [--quiet] [--trace RUN]\n"
                    "Runs N whole intercepts (default 200) with the cores of uavsim, mtid, "
                    "trackerd and\nguidanced in lockstep over random geometries and prints how "
                    "many imaged their\ntarget, with the miss distances; the last line is JSON.\n"
                    "--trace RUN repeats run RUN (from 0) alone and prints its target, track, UAV "
                    "and\nfootprint every second after the designation.\n");
            return 0;
        default:
            return 2;
        }
    }
    if (optind < argc) {
        fprintf (stderr, "guidanced: --monte-carlo takes no argument '%s' (see --help)\n",
                 argv[optind]);
        return 2;
    }
    if (trace >= 0 && (size_t)trace >= gd_mc_draw_cap (&c)) {
        fprintf (stderr,
                 "guidanced: --trace: run %ld is beyond the %zu geometries --runs %zu may draw\n",
                 trace, gd_mc_draw_cap (&c), c.runs);
        return 2;
    }
    if (trace >= 0) {
        gd_mc_run_t one;
        int rc = gd_mc_trace (&c, (size_t)trace, s_print_sample, NULL, &one);
        if (rc < 0) {
            fprintf (stderr, "guidanced: monte carlo failed: %s\n", strerror (-rc));
            return 1;
        }
        printf ("run %ld: %s, closest %.0f m to the footprint centre, miss %.0f m, ended %s\n",
                trace, one.imaged ? "imaged" : "not imaged", one.closest_m, one.miss_m,
                gd_phase_name ((gd_phase_t)one.final_phase));
        return one.imaged ? 0 : 3;
    }
    gd_mc_result_t r;
    gd_mc_run_t *runs = calloc (c.runs, sizeof *runs);
    int rc = runs ? gd_mc_run (&c, runs, quiet ? NULL : s_progress, &c, &r) : -ENOMEM;
    if (rc < 0) {
        fprintf (stderr, "guidanced: monte carlo failed: %s\n", strerror (-rc));
        free (runs);
        return 1;
    }
    if (r.designated < c.runs)
        fprintf (stderr,
                 "guidanced: only %zu of %zu geometries had a confirmed track of the target in "
                 "time\n",
                 r.designated, r.drawn);
    printf ("%zu intercepts (seed %llu, %s): %zu imaged (%.1f%%); %zu geometries drawn, %zu "
            "without a confirmed track of the target in time\n",
            r.designated, (unsigned long long)c.seed,
            c.method == GD_HEAD_ON ? "head-on" : "MTI hits", r.imaged,
            s_pct (r.imaged, r.designated), r.drawn, r.drawn - r.designated);
    printf ("  UAV ahead (y'_u > 0): %zu/%zu imaged; behind (y'_u <= 0): %zu/%zu\n", r.ahead_imaged,
            r.ahead, r.behind_imaged, r.behind);
    printf ("  straight: %zu/%zu imaged; turning 45-120 deg after designation: %zu/%zu\n",
            r.straight_imaged, r.straight, r.turned_imaged, r.turned);
    printf ("  closest approach to the footprint centre: median %.1f m, 90%% %.1f m, 95%% %.1f m, "
            "max %.1f m\n",
            r.closest_p50_m, r.closest_p90_m, r.closest_p95_m, r.closest_max_m);
    printf ("  miss distance (outside the footprint, 0 when imaged): 95%% %.1f m, 99%% %.1f m, max "
            "%.1f m",
            r.miss_p95_m, r.miss_p99_m, r.miss_max_m);
    size_t listed = 0;
    for (size_t i = 0; i < r.designated && listed < 20; i++)
        if (!runs[i].imaged)
            printf ("%s run %zu %.0f m", listed++ ? "," : "; missed:", runs[i].index,
                    runs[i].miss_m);
    printf ("\n");
    free (runs);
    printf ("  designation to imaging: median %.0f s, 95%% %.0f s; re-plans per run %.2f\n",
            r.time_to_image_p50_s, r.time_to_image_p95_s, r.replans_mean);
    printf ("{\"drawn\":%zu,\"runs\":%zu,\"imaged\":%zu,\"imaged_pct\":%.2f,\"ahead\":%zu,"
            "\"ahead_imaged\":%zu,\"behind\":%zu,\"behind_imaged\":%zu,\"turned\":%zu,"
            "\"turned_imaged\":%zu,\"closest_p50_m\":%.2f,\"closest_p90_m\":%.2f,"
            "\"closest_p95_m\":%.2f,\"closest_max_m\":%.2f,\"miss_p95_m\":%.2f,\"miss_p99_m\":%.2f,"
            "\"miss_max_m\":%.2f,"
            "\"time_to_image_p50_s\":%.1f,\"time_to_image_p95_s\":%.1f,\"replans_mean\":%.3f}\n",
            r.drawn, r.designated, r.imaged, s_pct (r.imaged, r.designated), r.ahead,
            r.ahead_imaged, r.behind, r.behind_imaged, r.turned, r.turned_imaged, r.closest_p50_m,
            r.closest_p90_m, r.closest_p95_m, r.closest_max_m, r.miss_p95_m, r.miss_p99_m,
            r.miss_max_m, r.time_to_image_p50_s, r.time_to_image_p95_s, r.replans_mean);
    return 0;
}
