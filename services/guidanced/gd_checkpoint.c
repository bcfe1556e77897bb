/* gd_checkpoint — an intercept's checkpoint (see gd_checkpoint.h).
 *
 * A cgs_ckpt frame "GDIC", version 1. Payload, in records:
 *   settings  u8 method, u32 display scale
 *   uav       u8 have, 14 f64 (time, e, n, u, heading, pitch, roll, ground
 *             speed, airspeed, height above ground, bank limit, depression,
 *             horizontal and vertical field of view)
 *   designation  u8 phase, u32 track, u64 number, f64 time, u8 need_plan,
 *             u8 have_track, u8 orphan, u32 orphan's track
 *   track     u32 id, u8 status, u8 friendly, 5 f64 (time, position e, n,
 *             velocity e, n), u32 hits, f64 last hit time, u32 history
 *             count and per hit 3 f64 (e, n, time)
 *   held      u8 holding, u8 last status, f64 newest hit heard, f64 latest
 *             update heard, then the held update: u32 id, u8 status, 5 f64
 *             as the track's, u32 hits, f64 last hit time
 *   plan      u8 has, 4 f64 (look-ahead, direction e, n, t_pred), u32
 *             iterations, 4 f64 (waypoint e, n, x_u, y_u), u8 secondary, 5
 *             f64 (P_2 e, n, meeting point e, n, plan time), u32 indices of
 *             P_2 and the waypoint, u32 route point flown to
 *   approach  3 f64 (P_close e, n, its time), u8 inside, u8 was_inside, 2
 *             f64 (overflight time, out since), u32 re-plans, f64 time to go
 *   confirm   u8 confirming, u32 samples (0 or 3), f64 best distance, per
 *             sample 11 f64 (time, 4 corners e, n, centre e, n)
 *   task      u64 number, u8 kind, u32 count, per point 2 f64
 *   reason    the text (u32 length and bytes). */
#include "gd_checkpoint.h"
#include "cgs_ckpt.h"
#include "cgs_util.h"
#include "gd_intercept_impl.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#define S_MAGIC   "GDIC"
#define S_VERSION 1u
#define S_WHAT    "guidanced intercept checkpoint"

/* Time, position and velocity of a track update. */
static void s_put_motion (cgs_ckpt_writer_t *w, const gd_track_t *t)
{
    const double v[] = {t->t_s, t->pos.e, t->pos.n, t->vel.e, t->vel.n};
    for (size_t i = 0; i < 5; i++)
        cgs_ckpt_put_f64 (w, v[i]);
}

int gd_checkpoint_save (const gd_intercept_t *ic, uint8_t **ret_buf, size_t *ret_len)
{
    const gd_uav_t *u = &ic->uav;
    const gd_track_t *t = &ic->track, *h = &ic->held;
    const gd_waypoint_t *wp = &ic->wp;
    cgs_ckpt_writer_t w;
    cgs_ckpt_writer_init (&w, S_MAGIC, S_VERSION);
    // settings
    cgs_ckpt_put_u8 (&w, (uint8_t)ic->method);
    cgs_ckpt_put_u32 (&w, ic->scale);
    // uav
    cgs_ckpt_put_bool (&w, ic->have_uav);
    const double uv[] = {u->t_s,          u->position.e_m, u->position.n_m,   u->position.u_m,
                         u->heading_deg,  u->pitch_deg,    u->roll_deg,       u->ground_speed_mps,
                         u->airspeed_mps, u->agl_m,        u->bank_limit_deg, u->depression_deg,
                         u->hfov_deg,     u->vfov_deg};
    for (size_t i = 0; i < sizeof uv / sizeof uv[0]; i++)
        cgs_ckpt_put_f64 (&w, uv[i]);
    // designation
    cgs_ckpt_put_u8 (&w, (uint8_t)ic->phase);
    cgs_ckpt_put_u32 (&w, ic->track_id);
    cgs_ckpt_put_u64 (&w, ic->designation_number);
    cgs_ckpt_put_f64 (&w, ic->designation_s);
    cgs_ckpt_put_bool (&w, ic->need_plan);
    cgs_ckpt_put_bool (&w, ic->have_track);
    cgs_ckpt_put_bool (&w, ic->orphan);
    cgs_ckpt_put_u32 (&w, ic->orphan_id);
    // track
    cgs_ckpt_put_u32 (&w, t->id);
    cgs_ckpt_put_u8 (&w, (uint8_t)t->status);
    cgs_ckpt_put_bool (&w, t->friendly);
    s_put_motion (&w, t);
    cgs_ckpt_put_u32 (&w, t->hits);
    cgs_ckpt_put_f64 (&w, t->last_hit_s);
    cgs_ckpt_put_u32 (&w, (uint32_t)t->history_count);
    for (size_t k = 0; k < t->history_count; k++) {
        cgs_ckpt_put_f64 (&w, t->history[k].e);
        cgs_ckpt_put_f64 (&w, t->history[k].n);
        cgs_ckpt_put_f64 (&w, t->history_t_s[k]);
    }
    // held
    cgs_ckpt_put_bool (&w, ic->holding);
    cgs_ckpt_put_u8 (&w, (uint8_t)ic->last_status);
    cgs_ckpt_put_f64 (&w, ic->heard_hit_s);
    cgs_ckpt_put_f64 (&w, ic->heard_s);
    cgs_ckpt_put_u32 (&w, h->id);
    cgs_ckpt_put_u8 (&w, (uint8_t)h->status);
    s_put_motion (&w, h);
    cgs_ckpt_put_u32 (&w, h->hits);
    cgs_ckpt_put_f64 (&w, h->last_hit_s);
    // plan
    cgs_ckpt_put_bool (&w, ic->has_plan);
    const double p1[] = {wp->lookahead_m, wp->dir.e, wp->dir.n, wp->t_pred_s};
    for (size_t i = 0; i < 4; i++)
        cgs_ckpt_put_f64 (&w, p1[i]);
    cgs_ckpt_put_u32 (&w, (uint32_t)wp->iterations);
    const double p2[] = {wp->waypoint.e, wp->waypoint.n, wp->x_u_m, wp->y_u_m};
    for (size_t i = 0; i < 4; i++)
        cgs_ckpt_put_f64 (&w, p2[i]);
    cgs_ckpt_put_bool (&w, wp->secondary);
    const double p3[] = {wp->second.e, wp->second.n, wp->meet.e, wp->meet.n, ic->plan_s};
    for (size_t i = 0; i < 5; i++)
        cgs_ckpt_put_f64 (&w, p3[i]);
    cgs_ckpt_put_u32 (&w, (uint32_t)ic->i_second);
    cgs_ckpt_put_u32 (&w, (uint32_t)ic->i_waypoint);
    cgs_ckpt_put_u32 (&w, (uint32_t)ic->progress);
    // approach
    cgs_ckpt_put_f64 (&w, ic->p_close.e);
    cgs_ckpt_put_f64 (&w, ic->p_close.n);
    cgs_ckpt_put_f64 (&w, ic->close_s);
    cgs_ckpt_put_bool (&w, ic->inside);
    cgs_ckpt_put_bool (&w, ic->was_inside);
    cgs_ckpt_put_f64 (&w, ic->overflight_s);
    cgs_ckpt_put_f64 (&w, ic->out_since_s);
    cgs_ckpt_put_u32 (&w, ic->replans);
    cgs_ckpt_put_f64 (&w, ic->time_to_go_s);
    // confirm
    cgs_ckpt_put_bool (&w, ic->confirming);
    cgs_ckpt_put_u32 (&w, (uint32_t)ic->n_samples);
    cgs_ckpt_put_f64 (&w, ic->best_d);
    for (size_t k = 0; k < ic->n_samples; k++) {
        const gd_sample_t *m = &ic->samples[k];
        cgs_ckpt_put_f64 (&w, m->t_s);
        for (int c = 0; c < 4; c++) {
            cgs_ckpt_put_f64 (&w, m->fp.corner[c].e);
            cgs_ckpt_put_f64 (&w, m->fp.corner[c].n);
        }
        cgs_ckpt_put_f64 (&w, m->fp.center.e);
        cgs_ckpt_put_f64 (&w, m->fp.center.n);
    }
    // task
    cgs_ckpt_put_u64 (&w, ic->task.number);
    cgs_ckpt_put_u8 (&w, (uint8_t)ic->task.kind);
    cgs_ckpt_put_u32 (&w, (uint32_t)ic->task.count);
    for (size_t k = 0; k < ic->task.count; k++) {
        cgs_ckpt_put_f64 (&w, ic->task.points[k].e);
        cgs_ckpt_put_f64 (&w, ic->task.points[k].n);
    }
    // reason
    cgs_ckpt_put_str (&w, ic->reason);
    return cgs_ckpt_writer_finish (&w, ret_buf, ret_len);
}

static bool s_finite_all (const double *v, size_t n)
{
    for (size_t i = 0; i < n; i++)
        if (!isfinite (v[i]))
            return false;
    return true;
}

static void s_get_motion (cgs_ckpt_reader_t *r, gd_track_t *t)
{
    t->t_s = cgs_ckpt_get_f64 (r);
    t->pos.e = cgs_ckpt_get_f64 (r);
    t->pos.n = cgs_ckpt_get_f64 (r);
    t->vel.e = cgs_ckpt_get_f64 (r);
    t->vel.n = cgs_ckpt_get_f64 (r);
}

/* Decode r into x (a copy of the intercept): NULL, or the record that is
 * bad or cut short. */
static const char *s_decode (cgs_ckpt_reader_t *r, gd_intercept_t *x)
{
    gd_uav_t *u = &x->uav;
    gd_track_t *t = &x->track, *h = &x->held;
    gd_waypoint_t *wp = &x->wp;
    // settings
    uint8_t method = cgs_ckpt_get_u8 (r);
    x->scale = cgs_ckpt_get_u32 (r);
    if (!cgs_ckpt_ok (r) || method > GD_MTI_HITS ||
        (x->scale != 1 && x->scale != 5 && x->scale != 10))
        return "settings";
    x->method = (gd_method_t)method;
    // uav
    x->have_uav = cgs_ckpt_get_bool (r);
    double *uv[] = {&u->t_s,          &u->position.e_m, &u->position.n_m,   &u->position.u_m,
                    &u->heading_deg,  &u->pitch_deg,    &u->roll_deg,       &u->ground_speed_mps,
                    &u->airspeed_mps, &u->agl_m,        &u->bank_limit_deg, &u->depression_deg,
                    &u->hfov_deg,     &u->vfov_deg};
    for (size_t i = 0; i < sizeof uv / sizeof uv[0]; i++)
        *uv[i] = cgs_ckpt_get_f64 (r);
    if (!cgs_ckpt_ok (r) ||
        (x->have_uav &&
         !s_finite_all ((const double[]){u->t_s, u->position.e_m, u->position.n_m, u->heading_deg},
                        4)))
        return "uav";
    // designation
    uint8_t phase = cgs_ckpt_get_u8 (r);
    x->track_id = cgs_ckpt_get_u32 (r);
    x->designation_number = cgs_ckpt_get_u64 (r);
    x->designation_s = cgs_ckpt_get_f64 (r);
    x->need_plan = cgs_ckpt_get_bool (r);
    x->have_track = cgs_ckpt_get_bool (r);
    x->orphan = cgs_ckpt_get_bool (r);
    x->orphan_id = cgs_ckpt_get_u32 (r);
    if (!cgs_ckpt_ok (r) || phase > GD_LOST)
        return "designation";
    x->phase = (gd_phase_t)phase;
    // track
    t->id = cgs_ckpt_get_u32 (r);
    uint8_t status = cgs_ckpt_get_u8 (r);
    t->friendly = cgs_ckpt_get_bool (r);
    s_get_motion (r, t);
    t->hits = cgs_ckpt_get_u32 (r);
    t->last_hit_s = cgs_ckpt_get_f64 (r);
    uint32_t hn = cgs_ckpt_get_u32 (r);
    if (!cgs_ckpt_ok (r) || status > CGS_TRACK_STATUS_MAX || hn > GD_HISTORY_MAX ||
        !s_finite_all ((const double[]){t->pos.e, t->pos.n, t->vel.e, t->vel.n, t->t_s}, 5))
        return "track";
    t->status = (cgs_track_status_t)status;
    t->history_count = hn;
    for (size_t k = 0; k < hn; k++) {
        t->history[k].e = cgs_ckpt_get_f64 (r);
        t->history[k].n = cgs_ckpt_get_f64 (r);
        t->history_t_s[k] = cgs_ckpt_get_f64 (r);
    }
    if (!cgs_ckpt_ok (r))
        return "a hit";
    // held
    x->holding = cgs_ckpt_get_bool (r);
    uint8_t last_status = cgs_ckpt_get_u8 (r);
    x->heard_hit_s = cgs_ckpt_get_f64 (r);
    x->heard_s = cgs_ckpt_get_f64 (r);
    h->id = cgs_ckpt_get_u32 (r);
    uint8_t held_status = cgs_ckpt_get_u8 (r);
    s_get_motion (r, h);
    h->hits = cgs_ckpt_get_u32 (r);
    h->last_hit_s = cgs_ckpt_get_f64 (r);
    if (!cgs_ckpt_ok (r) || last_status > CGS_TRACK_STATUS_MAX ||
        held_status > CGS_TRACK_STATUS_MAX ||
        (x->holding &&
         !s_finite_all ((const double[]){h->t_s, h->pos.e, h->pos.n, h->vel.e, h->vel.n}, 5)))
        return "held";
    x->last_status = last_status;
    h->status = (cgs_track_status_t)held_status;
    h->history_count = 0;
    // plan
    x->has_plan = cgs_ckpt_get_bool (r);
    wp->lookahead_m = cgs_ckpt_get_f64 (r);
    wp->dir.e = cgs_ckpt_get_f64 (r);
    wp->dir.n = cgs_ckpt_get_f64 (r);
    wp->t_pred_s = cgs_ckpt_get_f64 (r);
    wp->iterations = (int)(int32_t)cgs_ckpt_get_u32 (r);
    wp->waypoint.e = cgs_ckpt_get_f64 (r);
    wp->waypoint.n = cgs_ckpt_get_f64 (r);
    wp->x_u_m = cgs_ckpt_get_f64 (r);
    wp->y_u_m = cgs_ckpt_get_f64 (r);
    wp->secondary = cgs_ckpt_get_bool (r);
    wp->second.e = cgs_ckpt_get_f64 (r);
    wp->second.n = cgs_ckpt_get_f64 (r);
    wp->meet.e = cgs_ckpt_get_f64 (r);
    wp->meet.n = cgs_ckpt_get_f64 (r);
    x->plan_s = cgs_ckpt_get_f64 (r);
    x->i_second = cgs_ckpt_get_u32 (r);
    x->i_waypoint = cgs_ckpt_get_u32 (r);
    x->progress = cgs_ckpt_get_u32 (r);
    if (!cgs_ckpt_ok (r))
        return "plan";
    // approach
    x->p_close.e = cgs_ckpt_get_f64 (r);
    x->p_close.n = cgs_ckpt_get_f64 (r);
    x->close_s = cgs_ckpt_get_f64 (r);
    x->inside = cgs_ckpt_get_bool (r);
    x->was_inside = cgs_ckpt_get_bool (r);
    x->overflight_s = cgs_ckpt_get_f64 (r);
    x->out_since_s = cgs_ckpt_get_f64 (r);
    x->replans = cgs_ckpt_get_u32 (r);
    x->time_to_go_s = cgs_ckpt_get_f64 (r);
    if (!cgs_ckpt_ok (r))
        return "approach";
    // confirm
    x->confirming = cgs_ckpt_get_bool (r);
    uint32_t sn = cgs_ckpt_get_u32 (r);
    x->best_d = cgs_ckpt_get_f64 (r);
    if (!cgs_ckpt_ok (r) || (sn != 0 && sn != GD_SAMPLES))
        return "confirm";
    x->n_samples = sn;
    for (size_t k = 0; k < sn; k++) {
        gd_sample_t *m = &x->samples[k];
        memset (m, 0, sizeof *m);
        m->t_s = cgs_ckpt_get_finite (r);
        for (int c = 0; c < 4; c++) {
            m->fp.corner[c].e = cgs_ckpt_get_finite (r);
            m->fp.corner[c].n = cgs_ckpt_get_finite (r);
        }
        m->fp.center.e = cgs_ckpt_get_finite (r);
        m->fp.center.n = cgs_ckpt_get_finite (r);
    }
    if (!cgs_ckpt_ok (r))
        return "a sample";
    // task
    x->task.number = cgs_ckpt_get_u64 (r);
    uint8_t kind = cgs_ckpt_get_u8 (r);
    uint32_t tn = cgs_ckpt_get_u32 (r);
    if (!cgs_ckpt_ok (r) || kind > GD_TASK_LOITER_HERE || tn > GD_ROUTE_MAX)
        return "task";
    x->task.kind = (gd_task_kind_t)kind;
    x->task.count = tn;
    for (size_t k = 0; k < tn; k++) {
        x->task.points[k].e = cgs_ckpt_get_finite (r);
        x->task.points[k].n = cgs_ckpt_get_finite (r);
    }
    if (!cgs_ckpt_ok (r))
        return "a route point";
    // reason
    cgs_ckpt_get_str (r, x->reason, sizeof x->reason);
    if (!cgs_ckpt_ok (r))
        return "reason";
    if (x->has_plan && x->task.kind == GD_TASK_ROUTE &&
        (x->i_waypoint >= GD_ROUTE_MAX || x->i_second >= GD_ROUTE_MAX ||
         x->progress > x->task.count))
        return "indices";
    if (x->has_plan && !s_finite_all ((const double[]){wp->lookahead_m, wp->dir.e, wp->dir.n,
                                                       wp->waypoint.e, wp->waypoint.n, wp->meet.e,
                                                       wp->meet.n, x->p_close.e, x->p_close.n},
                                      9))
        return "plan (a value not finite)";
    return NULL;
}

int gd_checkpoint_restore (gd_intercept_t *ic, const uint8_t *buf, size_t len, char *err,
                           size_t errlen)
{
    cgs_ckpt_reader_t r;
    int rc = cgs_ckpt_open (&r, buf, len, S_MAGIC, S_VERSION, S_WHAT, err, errlen);
    if (rc < 0)
        return rc;
    gd_intercept_t *x = malloc (sizeof *x);
    if (!x)
        return -ENOMEM;
    *x = *ic;
    const char *bad = s_decode (&r, x);
    if (bad) {
        cgs_errf (err, errlen, "a %s with a bad or missing %s", S_WHAT, bad);
        rc = -EINVAL;
    } else if ((rc = cgs_ckpt_end (&r, S_WHAT, err, errlen)) == 0) {
        // The footprint follows from the UAV's state.
        const gd_uav_t *u = &x->uav;
        x->have_fp = false;
        if (x->have_uav) {
            gd_sensor_t s;
            gd_uav_sensor (u, x->p.max_range_m, &s);
            x->have_fp = gd_footprint (&s, x->terrain, &x->fp) == 0;
        }
        *ic = *x;
    }
    free (x);
    return rc;
}
