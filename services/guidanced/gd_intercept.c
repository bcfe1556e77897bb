/* gd_intercept — one UAV's intercept of a designated track (see gd_intercept.h). */
#include "gd_intercept.h"
#include "gd_intercept_impl.h"
#include "cgs_flight.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define S_DEG         (3.14159265358979323846 / 180.0)
#define S_PASS_M      80.0 // a route point within this is reached
#define S_OUT_S       2.0  // the target out of the footprint this long after overflight: done
#define S_MISS_M      50.0 // behind the footprint's near edge by this much: missed
#define S_TRAIL_GAP_M 50.0 // trail points closer than this to the previous are dropped

static bool s_active (gd_phase_t ph)
{
    return ph == GD_TO_SECONDARY || ph == GD_TO_WAYPOINT || ph == GD_APPROACH ||
           ph == GD_PRECISION || ph == GD_OVERFLIGHT;
}

static void s_reason (gd_intercept_t *self, const char *fmt, ...)
    __attribute__ ((format (printf, 2, 3)));
static void s_reason (gd_intercept_t *self, const char *fmt, ...)
{
    va_list ap;
    va_start (ap, fmt);
    vsnprintf (self->reason, sizeof self->reason, fmt, ap);
    va_end (ap);
    self->changes++;
}

/* After a plan's reason: say when the horizon cut the plan short, so the
 * operator knows the waypoint is where the target will be then, not where
 * the UAV can meet it. */
static void s_note_horizon (gd_intercept_t *self)
{
    if (!self->has_plan || !self->wp.limited)
        return;
    size_t n = strlen (self->reason);
    snprintf (self->reason + n, sizeof self->reason - n,
              "; the waypoint is at the %.0f s prediction horizon: no sooner meeting is "
              "possible",
              self->p.horizon_s);
}

const char *gd_phase_name (gd_phase_t p)
{
    static const char *const names[] = {"IDLE",     "TO_SECONDARY", "TO_WAYPOINT",
                                        "APPROACH", "PRECISION",    "OVERFLIGHT",
                                        "DONE",     "CANCELLED",    "LOST"};
    return (unsigned)p <= GD_LOST ? names[p] : "?";
}

gd_intercept_t *gd_intercept_new (const gd_params_t *p, const cgs_terrain_t *terrain)
{
    char err[256];
    if (!p || gd_params_check (p, err, sizeof err) < 0)
        return NULL;
    gd_intercept_t *self = calloc (1, sizeof *self);
    if (!self)
        return NULL;
    self->p = *p;
    self->terrain = terrain;
    self->scale = 1;
    self->overflight_s = NAN;
    self->time_to_go_s = NAN;
    self->designation_s = NAN;
    self->heard_hit_s = -INFINITY;
    self->heard_s = -INFINITY;
    snprintf (self->reason, sizeof self->reason, "nothing designated");
    return self;
}

void gd_intercept_destroy (gd_intercept_t **self_p)
{
    if (!self_p || !*self_p)
        return;
    free (*self_p);
    *self_p = NULL;
}

/* ---- geometry of the present state --------------------------------------------------- */

static gd_v2_t s_uav_ground (const gd_intercept_t *self)
{
    return gd_v2 (self->uav.position.e_m, self->uav.position.n_m);
}

static double s_uav_speed (const gd_intercept_t *self)
{
    return fmax (self->uav.ground_speed_mps, 1.0);
}

/* The speed a plan is made for: the commanded airspeed when known (the UAV
 * reaches it at 1 m/s² within seconds; no wind in the simulation), else the
 * present ground speed. */
static double s_plan_speed (const gd_intercept_t *self)
{
    return self->uav.airspeed_mps > 1 ? self->uav.airspeed_mps : s_uav_speed (self);
}

/* The height the UAV flies at: the commanded one when known (it climbs or
 * descends to it within a minute, long before the waypoint). */
static double s_uav_agl (const gd_uav_t *u)
{
    return u->commanded_agl_m > 0 ? u->commanded_agl_m : u->agl_m;
}

double gd_intercept_turn_radius (const gd_intercept_t *self)
{
    if (!self->have_uav)
        return 0;
    double v = fmax (self->uav.airspeed_mps, self->uav.ground_speed_mps);
    double bank = self->uav.bank_limit_deg > 1 ? self->uav.bank_limit_deg : 30.0;
    return self->p.turn_radius_factor * cgs_flight_turn_radius (v, bank);
}

/* The target's position predicted to t_s from its latest track update. */
static gd_v2_t s_target_at (const gd_intercept_t *self, double t_s)
{
    return gd_add (self->track.pos, gd_scale (self->track.vel, t_s - self->track.t_s));
}

/* The target's direction now, or false when it is too slow to have one. */
static bool s_target_dir (const gd_intercept_t *self, gd_v2_t vel, gd_v2_t *ret)
{
    double v = gd_norm (vel);
    if (v < self->p.min_target_speed_mps)
        return false;
    *ret = gd_scale (vel, 1.0 / v);
    return true;
}

/* The variance of a covariance c (east², east·north, north²) along unit u. */
static double s_var_along (const double c[3], gd_v2_t u)
{
    return fmax (0.0, u.e * u.e * c[0] + 2 * u.e * u.n * c[1] + u.n * u.n * c[2]);
}

/* The standard deviation of t's direction of motion, degrees (0 when its
 * covariance is unknown): its velocity's spread across the velocity,
 * over the speed. */
static double s_dir_sigma_deg (const gd_track_t *t)
{
    double v = gd_norm (t->vel);
    if (!t->has_cov || !(v > 0))
        return 0;
    gd_v2_t across = gd_v2 (-t->vel.n / v, t->vel.e / v);
    return fmin (180.0, sqrt (s_var_along (t->vel_cov, across)) / v / S_DEG);
}

/* Is a change of the target's direction by turned degrees, or of its
 * distance off the planned line by off metres, one to re-plan on: beyond
 * the threshold and beyond `significance` standard deviations of t? */
static bool s_turned (const gd_intercept_t *self, const gd_track_t *t, double turned)
{
    return turned > self->p.threshold_deg && turned > self->p.significance * s_dir_sigma_deg (t);
}

static bool s_left_line (const gd_intercept_t *self, const gd_track_t *t, double off)
{
    double sigma = 0;
    if (t->has_cov)
        sigma = sqrt (s_var_along (t->pos_cov, gd_v2 (self->wp.dir.n, -self->wp.dir.e)));
    return off > self->p.offset_m && off > self->p.significance * sigma;
}

/* Angle between two unit vectors, degrees. */
static double s_angle (gd_v2_t a, gd_v2_t b)
{
    return fabs (atan2 (gd_cross (a, b), gd_dot (a, b))) / S_DEG;
}

/* ---- tasks ----------------------------------------------------------------------------- */

static void s_task_loiter_here (gd_intercept_t *self)
{
    self->task.number++;
    self->task.kind = GD_TASK_LOITER_HERE;
    self->task.count = 0;
}

static bool s_push (gd_task_t *t, gd_v2_t p)
{
    if (t->count >= GD_ROUTE_MAX)
        return false;
    t->points[t->count++] = p;
    return true;
}

/* Append the Dubins path from (p, h) to (q, hq), sampled; false when it
 * cannot be built or does not fit. */
static bool s_push_dubins (gd_intercept_t *self, gd_task_t *t, gd_v2_t p, double h, gd_v2_t q,
                           double hq, double r)
{
    gd_dubins_t d;
    if (gd_dubins (p, h, q, hq, r, &d) < 0)
        return false;
    size_t room = GD_ROUTE_MAX - t->count;
    if (room < 2)
        return false;
    size_t n = gd_dubins_sample (&d, self->p.arc_step_deg, t->points + t->count, room);
    t->count += n;
    return true;
}

/* The reversed hit trail for "Intercept by MTI TGT Hits": each hit, newest
 * first, moved by the look-ahead along the trail's direction there, so the
 * footprint centre runs along the trail while the UAV flies it; only points
 * beyond the waypoint (along −D_T) are taken. */
static void s_push_trail (gd_intercept_t *self, gd_task_t *t)
{
    const gd_track_t *tr = &self->track;
    size_t n = tr->history_count;
    gd_v2_t back = gd_scale (self->wp.dir, -1.0);
    for (size_t k = n; k-- > 0;) {
        size_t a = k > 0 ? k - 1 : 0, b = k > 0 ? k : (n > 1 ? 1 : 0);
        gd_v2_t d = gd_sub (tr->history[b], tr->history[a]);
        double len = gd_norm (d);
        gd_v2_t dir = len > 1e-6 ? gd_scale (d, 1.0 / len) : self->wp.dir;
        gd_v2_t pt = gd_add (tr->history[k], gd_scale (dir, self->wp.lookahead_m));
        if (gd_dot (gd_sub (pt, self->wp.waypoint), back) <= 0)
            continue;
        if (gd_norm (gd_sub (pt, t->points[t->count - 1])) < S_TRAIL_GAP_M)
            continue;
        if (!s_push (t, pt))
            return;
    }
}

/* ---- planning ---------------------------------------------------------------------------- */

/* A new plan from the UAV's present state and the latest track. */
static void s_plan (gd_intercept_t *self)
{
    if (!self->have_uav || !self->have_track) {
        self->need_plan = true;
        return;
    }
    self->need_plan = false;
    double t = self->uav.t_s;
    gd_v2_t dir;
    bool moving = s_target_dir (self, self->track.vel, &dir);
    double r = gd_intercept_turn_radius (self);
    gd_engage_t in = {
        .uav = s_uav_ground (self),
        .uav_heading_deg = self->uav.heading_deg,
        .uav_speed_mps = s_plan_speed (self),
        .turn_radius_m = r,
        .agl_m = s_uav_agl (&self->uav),
        .depression_deg = self->uav.depression_deg,
        .target = s_target_at (self, t),
        .target_vel = moving ? self->track.vel : gd_v2 (0, 0),
        .secondary_paper = self->p.secondary == GD_SECONDARY_PAPER,
        .secondary_scale = self->p.secondary_scale,
        .lead_in_m = fmax (self->p.lead_in_m, 4 * r),
        .offset_max_m =
            self->p.secondary_offset_max_m > 0 ? fmax (self->p.secondary_offset_max_m, 4 * r) : 0,
        .settle_m = self->p.settle_m,
        .horizon_s = self->p.horizon_s,
    };
    gd_waypoint_t wp;
    int rc =
        self->p.timing == GD_TIMING_ARC ? gd_waypoint (&in, &wp) : gd_waypoint_flyable (&in, &wp);
    if (rc < 0) {
        s_reason (self,
                  "no plan: the target (%.1f m/s) is not slower than the UAV (%.1f m/s), "
                  "or the UAV's state is incomplete",
                  gd_norm (self->track.vel), in.uav_speed_mps);
        self->need_plan = true;
        return;
    }
    gd_task_t *tk = &self->task;
    gd_task_t old = *tk;
    tk->count = 0;
    double h2, h_final;
    gd_waypoint_headings (&wp, &h2, &h_final);
    gd_v2_t cur = in.uav;
    double cur_h = in.uav_heading_deg;
    bool ok = true;
    size_t i_second = 0;
    if (wp.secondary) {
        ok = s_push_dubins (self, tk, cur, cur_h, wp.second, h2, r);
        i_second = tk->count - 1;
        cur = wp.second;
        cur_h = h2;
    }
    if (wp.settle_m > 0) {
        ok = ok && s_push_dubins (self, tk, cur, cur_h, gd_waypoint_settle_point (&wp), h_final, r);
        ok = ok && s_push (tk, wp.waypoint);
    } else {
        ok = ok && s_push_dubins (self, tk, cur, cur_h, wp.waypoint, h_final, r);
    }
    size_t i_waypoint = tk->count ? tk->count - 1 : 0;
    self->wp = wp; // the trail needs it
    if (ok && self->method == GD_MTI_HITS && self->track.history_count >= 2)
        s_push_trail (self, tk);
    gd_v2_t end = gd_sub (wp.waypoint, gd_scale (wp.dir, wp.lookahead_m + self->p.runout_m));
    if (ok && (self->method == GD_HEAD_ON || tk->count == i_waypoint + 1))
        ok = s_push (tk, end);
    if (!ok) {
        *tk = old;
        s_reason (self, "no plan: the route does not fit in %d points", GD_ROUTE_MAX);
        return;
    }
    tk->number = old.number + 1;
    tk->kind = GD_TASK_ROUTE;
    self->has_plan = true;
    self->plan_s = t;
    self->plan_airspeed_mps = self->uav.airspeed_mps;
    self->plan_agl_m = self->uav.commanded_agl_m;
    self->i_second = i_second;
    self->i_waypoint = i_waypoint;
    self->progress = 0;
    self->inside = false;
    self->out_since_s = NAN;
    self->confirming = false;
    self->n_samples = 0;
    self->phase = wp.secondary ? GD_TO_SECONDARY : GD_TO_WAYPOINT;
}

static void s_replan (gd_intercept_t *self, const char *why)
{
    char keep[sizeof self->reason];
    snprintf (keep, sizeof keep, "%s", why);
    self->replans++;
    s_plan (self);
    if (self->has_plan && !self->need_plan) {
        s_reason (self, "re-planned (%s)", keep);
        s_note_horizon (self);
    }
}

/* ---- phases ----------------------------------------------------------------------------- */

/* Established on the final approach: heading along −D_T, near the target's
 * line, and the footprint still in front of the target. */
static bool s_on_final (const gd_intercept_t *self, gd_v2_t target, gd_v2_t dir)
{
    double want = gd_heading_of (gd_scale (dir, -1.0));
    if (fabs (gd_heading_diff (self->uav.heading_deg, want)) > self->p.align_deg)
        return false;
    double x, y;
    gd_to_target_frame (target, dir, s_uav_ground (self), &x, &y);
    return fabs (x) < self->p.offset_m && y > 0.8 * self->wp.lookahead_m;
}

/* Has the UAV reached route point k (coming from point k − 1)? */
static bool s_reached (const gd_intercept_t *self, size_t k)
{
    const gd_task_t *t = &self->task;
    gd_v2_t u = s_uav_ground (self), pk = t->points[k];
    double d = gd_norm (gd_sub (u, pk));
    if (d < S_PASS_M)
        return true;
    gd_v2_t prev = k > 0 ? t->points[k - 1] : pk;
    gd_v2_t in = gd_sub (pk, prev);
    double len = gd_norm (in);
    if (k == 0 || len < 1e-6)
        return false;
    // Past the perpendicular at the point, and not far from it.
    return gd_dot (gd_sub (u, pk), in) >= 0 && d < 2 * len + 2 * gd_intercept_turn_radius (self);
}

static void s_enter_precision (gd_intercept_t *self, gd_v2_t start, const char *why)
{
    self->phase = GD_PRECISION;
    self->p_close = start;
    self->close_s = self->uav.t_s;
    s_reason (self, "%s", why);
}

/* Keep a moment of the overflight (the target predicted at target). */
static void s_sample (gd_intercept_t *self, gd_v2_t target)
{
    gd_sample_t now = {self->uav.t_s, self->fp};
    double d = gd_norm (gd_sub (target, self->fp.center));
    if (self->n_samples == 0) {
        self->samples[0] = self->samples[1] = self->samples[2] = now;
        self->n_samples = GD_SAMPLES;
        self->best_d = d;
        return;
    }
    if (d < self->best_d) {
        self->samples[1] = now;
        self->best_d = d;
    }
    self->samples[2] = now;
}

static void s_try_confirm (gd_intercept_t *self);

static void s_update_time_to_go (gd_intercept_t *self, gd_v2_t target)
{
    double s = s_uav_speed (self);
    self->time_to_go_s = NAN;
    if (self->phase == GD_OVERFLIGHT) {
        self->time_to_go_s = 0;
    } else if ((self->phase == GD_TO_SECONDARY || self->phase == GD_TO_WAYPOINT) &&
               self->task.kind == GD_TASK_ROUTE && self->progress <= self->i_waypoint) {
        const gd_task_t *t = &self->task;
        double len = gd_norm (gd_sub (t->points[self->progress], s_uav_ground (self)));
        for (size_t k = self->progress + 1; k <= self->i_waypoint && k < t->count; k++)
            len += gd_norm (gd_sub (t->points[k], t->points[k - 1]));
        self->time_to_go_s = len / s;
    } else if ((self->phase == GD_PRECISION || self->phase == GD_APPROACH) && self->have_fp) {
        gd_v2_t h = gd_heading_unit (self->uav.heading_deg);
        double gap = gd_dot (gd_sub (target, self->fp.center), h);
        double closing = s - gd_dot (self->track.vel, h);
        if (closing > 0.1 && gap >= 0)
            self->time_to_go_s = gap / closing;
    }
}

/* The operator changed the UAV's airspeed or height since the plan was
 * made: its look-ahead z_u·cot ε and its timing no longer hold, so it is made
 * again (before the final approach; a pass under way keeps its geometry
 * and the next plan takes the new values). A plan restored from a
 * checkpoint, which does not keep them, takes the present ones. */
static void s_commanded_changed (gd_intercept_t *self)
{
    // The commanded height only: the present one follows the terrain, and
    // its changes are not the operator's (0: no command known).
    double v = self->uav.airspeed_mps, z = self->uav.commanded_agl_m;
    if (self->need_plan)
        return; // a plan is being made anyway, with these values
    bool v_known = self->plan_airspeed_mps > 0, z_known = self->plan_agl_m > 0 && z > 0;
    if (!v_known)
        self->plan_airspeed_mps = v;
    if (!z_known)
        self->plan_agl_m = z;
    if (self->phase != GD_TO_SECONDARY && self->phase != GD_TO_WAYPOINT &&
        self->phase != GD_APPROACH)
        return;
    char why[128];
    if (v_known && fabs (v - self->plan_airspeed_mps) >= 0.5)
        snprintf (why, sizeof why, "the airspeed was changed from %.0f to %.0f m/s",
                  self->plan_airspeed_mps, v);
    else if (z_known && fabs (z - self->plan_agl_m) >= 5)
        snprintf (why, sizeof why, "the altitude was changed from %.0f to %.0f m above ground",
                  self->plan_agl_m, z);
    else
        return;
    s_replan (self, why);
}

void gd_intercept_uav (gd_intercept_t *self, const gd_uav_t *u)
{
    if (!u || !isfinite (u->t_s) || !isfinite (u->position.e_m) || !isfinite (u->position.n_m) ||
        !isfinite (u->heading_deg))
        return;
    self->uav = *u;
    self->have_uav = true;
    gd_sensor_t s;
    gd_uav_sensor (u, self->p.max_range_m, &s);
    self->have_fp = gd_footprint (&s, self->terrain, &self->fp) == 0;
    if (self->need_plan && s_active (self->phase))
        s_plan (self);
    if (!s_active (self->phase) || !self->has_plan)
        return;
    s_commanded_changed (self);
    const gd_task_t *t = &self->task;
    while (t->kind == GD_TASK_ROUTE && self->progress < t->count &&
           s_reached (self, self->progress))
        self->progress++;
    gd_v2_t target = s_target_at (self, u->t_s);
    gd_v2_t dir = self->wp.dir;
    s_target_dir (self, self->track.vel, &dir);
    bool inside = self->have_fp && cgs_footprint_contains (&self->fp, target);
    self->inside = inside;
    switch (self->phase) {
    case GD_TO_SECONDARY:
        if (self->progress > self->i_second) {
            self->phase = GD_TO_WAYPOINT;
            s_reason (self, "passed the secondary waypoint");
        }
        break;
    case GD_TO_WAYPOINT:
        if (self->progress > self->i_waypoint) {
            if (self->method == GD_MTI_HITS) {
                self->phase = GD_APPROACH;
                s_reason (self, "passed the waypoint: flying the reversed hit trail");
            } else {
                s_enter_precision (self, self->wp.waypoint, "passed the waypoint");
            }
        } else if (self->method == GD_HEAD_ON && s_on_final (self, target, dir)) {
            double along = gd_dot (gd_sub (s_uav_ground (self), target), dir);
            s_enter_precision (self, gd_add (target, gd_scale (dir, along)),
                               "on the final approach with the target in front");
        }
        break;
    default:
        break;
    }
    if (inside) {
        if (self->phase != GD_OVERFLIGHT || self->confirming) {
            if (self->phase != GD_OVERFLIGHT || !self->was_inside)
                self->n_samples = 0;
            self->phase = GD_OVERFLIGHT;
            if (!self->was_inside)
                self->overflight_s = u->t_s;
            self->was_inside = true;
            self->confirming = false;
            s_reason (self, "the target is in the footprint");
        }
        self->out_since_s = NAN;
        s_sample (self, target);
    } else if (self->phase == GD_OVERFLIGHT && !self->confirming) {
        if (!isfinite (self->out_since_s))
            self->out_since_s = u->t_s;
        else if (u->t_s - self->out_since_s >= S_OUT_S) {
            self->confirming = true;
            s_reason (self, "the target left the footprint: waiting for its next hit to confirm "
                            "the overflight");
            s_try_confirm (self);
        }
    } else if ((self->phase == GD_PRECISION || self->phase == GD_APPROACH) && self->have_fp) {
        // Missed: the target is behind the footprint's near edge.
        gd_v2_t h = gd_heading_unit (u->heading_deg), g = s_uav_ground (self);
        double near = fmin (gd_dot (gd_sub (self->fp.corner[0], g), h),
                            gd_dot (gd_sub (self->fp.corner[3], g), h));
        if (gd_dot (gd_sub (target, g), h) < near - S_MISS_M) {
            // How far to the side of the footprint's centre line it went by.
            gd_v2_t right = gd_v2 (h.n, -h.e);
            double side = gd_dot (gd_sub (target, self->fp.center), right);
            char why[96];
            snprintf (why, sizeof why,
                      "the target went by %.0f m %s of the footprint's centre: another pass",
                      fabs (side), side < 0 ? "left" : "right");
            s_replan (self, why);
        }
    }
    s_update_time_to_go (self, target);
}

/* ---- track updates ----------------------------------------------------------------------- */

/* Has t a hit newer than any heard of the designated track? */
static bool s_fresh (const gd_intercept_t *self, const gd_track_t *t)
{
    if (t->status != CGS_TRACK_CONFIRMED)
        return false;
    return !isfinite (t->last_hit_s) || !(t->last_hit_s <= self->heard_hit_s);
}

/* Does t disagree with ref: a direction more than the re-plan threshold
 * apart, or a position more than offset_m from ref's prediction? */
static bool s_jumps (const gd_intercept_t *self, const gd_track_t *ref, const gd_track_t *t)
{
    gd_v2_t a, b;
    if (s_target_dir (self, ref->vel, &a) && s_target_dir (self, t->vel, &b) &&
        s_angle (a, b) > self->p.threshold_deg)
        return true;
    gd_v2_t at = gd_add (ref->pos, gd_scale (ref->vel, t->t_s - ref->t_s));
    return gd_norm (gd_sub (t->pos, at)) > self->p.offset_m;
}

/* Is p, seen at t_s, where ref's target could be: within handover_m, plus
 * handover_growth_mps for each second since ref's latest hit, of its
 * prediction? */
static bool s_near_prediction (const gd_intercept_t *self, const gd_track_t *ref, gd_v2_t p,
                               double t_s)
{
    double seen =
        isfinite (ref->last_hit_s) && ref->last_hit_s < ref->t_s ? ref->last_hit_s : ref->t_s;
    double age = fmax (0.0, t_s - seen);
    gd_v2_t at = gd_add (ref->pos, gd_scale (ref->vel, t_s - ref->t_s));
    return gd_norm (gd_sub (p, at)) <= self->p.handover_m + self->p.handover_growth_mps * age;
}

/* A new track of the designated target after its own was deleted: the one
 * the tracker says continues it. A tracker that links successors itself
 * (the IMM tracker: `links_continuation`) has weighed every new track
 * against the deleted one with its motion models; with `handover = links`
 * one it did not link is another vehicle as far as it can tell, and
 * nearness alone (a column's next vehicle is near) does not make it the
 * target. Otherwise (the default, and from a tracker that does not link): a
 * confirmed or coasting one with a credible velocity, not older than the
 * loss, whose first hit or present position is where the target could be
 * (s_near_prediction of the trusted estimate, or of a held one). Its age
 * comes from its hit history when that is known (hits > 0): a track whose
 * oldest kept hit is from before the deleted track's last hit follows
 * another vehicle; its first hit is judged only when the history is whole
 * (hits ≤ history kept), else only its present position. A track BCIS
 * identifies otherwise (friendly for an unknown target, or the reverse) is
 * another vehicle. */
static bool s_takes_over (const gd_intercept_t *self, const gd_track_t *t)
{
    if (!self->orphan || !s_active (self->phase) || t->id == self->orphan_id ||
        (t->status != CGS_TRACK_CONFIRMED && t->status != CGS_TRACK_COASTING) ||
        gd_norm (t->vel) > self->p.max_target_speed_mps ||
        t->friendly != self->track.friendly) // BCIS says it is another vehicle
        return false;
    if (t->continues == self->orphan_id)
        return true; // the tracker says it is the same target
    if (t->continues != 0)
        return false; // the tracker says it continues another track: another vehicle
    if (t->linked && self->p.handover == GD_HANDOVER_LINKS)
        return false; // the tracker, which links successors, names none: another vehicle
    const gd_track_t *refs[2] = {&self->track, self->holding ? &self->held : NULL};
    bool whole = t->hits > 0 && t->hits <= t->history_count;
    if (t->hits > 0 && isfinite (self->track.last_hit_s) &&
        !(t->history_count > 0 && t->history_t_s[0] > self->track.last_hit_s))
        return false;
    for (size_t k = 0; k < 2; k++) {
        if (!refs[k])
            continue;
        if (s_near_prediction (self, refs[k], t->pos, t->t_s) ||
            (whole && s_near_prediction (self, refs[k], t->history[0], t->history_t_s[0])))
            return true;
    }
    return false;
}

/* The overflight's confirmation: the track's hit nearest in time to the
 * overflight (one after the target was predicted to enter the footprint),
 * carried along the track's velocity to each recorded moment of the
 * overflight, against the footprint of that moment. NAN when the track has
 * no such hit yet; else the smallest signed distance to the footprint's
 * edge (negative inside). */
static double s_confirm_distance (const gd_intercept_t *self, const gd_track_t *t)
{
    if (self->n_samples == 0)
        return NAN;
    double t_in = self->samples[0].t_s, t_best = self->samples[1].t_s;
    gd_v2_t hit = gd_v2 (0, 0);
    double t_hit = NAN;
    for (size_t k = 0; k < t->history_count; k++)
        if (t->history_t_s[k] > t_in &&
            !(fabs (t->history_t_s[k] - t_best) >= fabs (t_hit - t_best))) {
            hit = t->history[k];
            t_hit = t->history_t_s[k];
        }
    if (!isfinite (t_hit)) {
        if (t->history_count > 0 || t->status != CGS_TRACK_CONFIRMED || !(t->t_s > t_in))
            return NAN;
        hit = t->pos; // no history: its filtered position at a hit
        t_hit = t->t_s;
    }
    double best = INFINITY;
    for (size_t k = 0; k < self->n_samples; k++) {
        gd_v2_t p = gd_add (hit, gd_scale (t->vel, self->samples[k].t_s - t_hit));
        best = fmin (best, cgs_footprint_signed_distance (&self->samples[k].fp, p));
    }
    return best;
}

/* While waiting for the confirmation: decide on the track's latest word. */
static void s_try_confirm (gd_intercept_t *self)
{
    if (self->phase != GD_OVERFLIGHT || !self->confirming)
        return;
    double d = s_confirm_distance (self, &self->track);
    if (isnan (d))
        return;
    self->confirming = false;
    if (d <= self->p.confirm_margin_m) {
        self->phase = GD_DONE;
        s_reason (self, "the target passed through the footprint (its hits confirm it): "
                        "loitering at the route's end");
        return;
    }
    char why[128];
    if (d > 0)
        snprintf (why, sizeof why,
                  "its hits show the target passed %.0f m outside the footprint: another pass", d);
    else
        snprintf (why, sizeof why,
                  "its hits show the target passed only %.0f m inside the footprint's edge: "
                  "another pass",
                  -d);
    self->was_inside = false;
    self->overflight_s = NAN;
    self->n_samples = 0;
    self->out_since_s = NAN;
    // Out of OVERFLIGHT even if no new plan can be made now (it is tried
    // again on each UAV update while need_plan is set).
    self->phase = GD_TO_WAYPOINT;
    self->need_plan = true;
    s_replan (self, why);
}

void gd_intercept_track (gd_intercept_t *self, const gd_track_t *t)
{
    if (!t || self->track_id == 0 || !isfinite (t->t_s) || !isfinite (t->pos.e) ||
        !isfinite (t->pos.n) || !isfinite (t->vel.e) || !isfinite (t->vel.n))
        return;
    if (t->id != self->track_id) {
        if (!s_takes_over (self, t))
            return;
        s_reason (self, "track %u was deleted; its target goes on as track %u", self->orphan_id,
                  t->id);
        self->track_id = t->id;
        self->orphan = false;
        self->holding = false;
        self->heard_hit_s = -INFINITY;
        self->heard_s = t->t_s;
        self->last_status = CGS_TRACK_CONFIRMED;
    } else if (self->orphan) {
        return; // the deleted track's last word
    }
    bool active = s_active (self->phase) && self->have_track;
    if (active && t->status == CGS_TRACK_DELETED) {
        // Keep flying on the trusted estimate; a new track of the target near
        // it takes over (s_takes_over); none within lost_after_s: lost.
        self->orphan = true;
        self->orphan_id = t->id;
        s_reason (self, "track %u was deleted: flying on its prediction", t->id);
        return;
    }
    if (active) {
        // A hit that ends a coast and moves the target far from its trusted
        // estimate may be clutter the widened gate took in: it is held until
        // a second hit agrees with it (a real manoeuvre) or disagrees.
        bool fresh = s_fresh (self, t);
        int before = self->last_status;
        self->last_status = t->status;
        self->heard_s = fmax (self->heard_s, t->t_s);
        if (self->holding && !fresh)
            return; // the held estimate, coasting
        if (fresh)
            self->heard_hit_s = t->last_hit_s;
        if (fresh && (before == 2 || self->holding) && s_jumps (self, &self->track, t) &&
            !(self->holding && !s_jumps (self, &self->held, t))) {
            self->held = *t;
            self->held.history_count = 0;
            self->holding = true;
            s_reason (self, "track %u's hit after a coast is held until another confirms it",
                      t->id);
            return;
        }
        self->holding = false;
    }
    double prev_t = self->track.t_s;
    gd_v2_t prev_vel = self->track.vel;
    bool had = self->have_track;
    self->track = *t;
    self->have_track = true;
    // A velocity no ground vehicle has: the estimate is broken (a false
    // alarm taken into the track); keep the previous one and plan nothing on it.
    bool credible = gd_norm (t->vel) <= self->p.max_target_speed_mps;
    if (!credible && had)
        self->track.vel = prev_vel;
    if (!s_active (self->phase))
        return;
    if (self->need_plan) {
        s_plan (self);
        return;
    }
    if (self->phase == GD_OVERFLIGHT) {
        s_try_confirm (self);
        return;
    }
    if (!self->has_plan || !credible)
        return;
    gd_v2_t dir;
    bool moving = s_target_dir (self, t->vel, &dir);
    gd_v2_t target = s_target_at (self, self->have_uav ? self->uav.t_s : t->t_s);
    double turned = moving ? s_angle (self->wp.dir, dir) : 0;
    char why[128];
    if (s_turned (self, t, turned)) {
        snprintf (why, sizeof why, "the target's direction changed by %.0f°", turned);
        s_replan (self, why);
        return;
    }
    if (self->phase == GD_PRECISION) {
        double dt = t->t_s - (self->close_s > prev_t ? self->close_s : prev_t);
        if (!(dt > 0) || !moving)
            return;
        // Equation 9, on the target's present line.
        self->p_close = gd_precision_step (self->p_close, target, dir, s_uav_speed (self), dt);
        self->close_s = t->t_s;
        // The UAV joins that line two planning turn radii ahead of P_close, or
        // of itself when it is farther on: P_close is where the UAV was at the
        // track's time, behind it by the time the task arrives, and steering
        // to a point abeam or behind turns the UAV away from the target.
        gd_v2_t g = self->have_uav ? s_uav_ground (self) : self->p_close;
        double along =
            fmin (gd_dot (gd_sub (self->p_close, target), dir), gd_dot (gd_sub (g, target), dir));
        gd_v2_t join = gd_add (target, gd_scale (dir, along - 2 * gd_intercept_turn_radius (self)));
        gd_task_t *tk = &self->task;
        tk->number++;
        tk->kind = GD_TASK_ROUTE;
        tk->count = 0;
        s_push (tk, join);
        s_push (tk, gd_sub (join, gd_scale (dir, self->wp.lookahead_m + self->p.runout_m)));
        self->progress = 0;
        self->i_waypoint = 0;
        return;
    }
    if (self->phase == GD_APPROACH)
        return;
    double x, y;
    gd_to_target_frame (self->wp.meet, self->wp.dir, target, &x, &y);
    if (s_left_line (self, t, fabs (x))) {
        snprintf (why, sizeof why, "the target left the planned line by %.0f m", fabs (x));
        s_replan (self, why);
        return;
    }
    gd_to_target_frame (self->wp.waypoint, self->wp.dir, target, &x, &y);
    if (y > 0 && !(self->have_uav && s_on_final (self, target, self->wp.dir)))
        s_replan (self, "the target passed the waypoint first");
}

void gd_intercept_turn (gd_intercept_t *self, uint32_t track_id, double t_s, gd_v2_t vel_after,
                        double angle_deg)
{
    (void)angle_deg;
    // A turn seen at a hit that ends a coast is judged with that track
    // update (which may hold it: gd_intercept_track).
    if (track_id == 0 || track_id != self->track_id || !s_active (self->phase) ||
        self->phase == GD_OVERFLIGHT || !self->has_plan || self->orphan || self->holding ||
        self->last_status == CGS_TRACK_COASTING || !isfinite (vel_after.e) ||
        !isfinite (vel_after.n) || !isfinite (t_s))
        return;
    gd_v2_t dir;
    if (!s_target_dir (self, vel_after, &dir) || gd_norm (vel_after) > self->p.max_target_speed_mps)
        return;
    double turned = s_angle (self->wp.dir, dir);
    gd_track_t after = self->track;
    after.vel = vel_after;
    if (!s_turned (self, &after, turned))
        return;
    // The filter's velocity after the turn, from the latest position.
    self->track.pos = s_target_at (self, t_s);
    self->track.t_s = t_s;
    self->track.vel = vel_after;
    char why[128];
    snprintf (why, sizeof why, "turn event: direction changed by %.0f°", turned);
    s_replan (self, why);
}

void gd_intercept_tick (gd_intercept_t *self, double t_s)
{
    if (!s_active (self->phase) || !self->have_track)
        return;
    // Held updates count as heard: the track is alive.
    double heard = self->holding ? fmax (self->track.t_s, self->heard_s) : self->track.t_s;
    if (t_s - heard > self->p.lost_after_s) {
        self->phase = GD_LOST;
        s_task_loiter_here (self);
        s_reason (self, "track %u not updated for %.0f s: loitering here", self->track_id,
                  t_s - heard);
    }
}

/* *t at most t_s; unknown (NaN) or −∞ stay so (fmin would make NaN t_s). */
static void s_not_after (double *t, double t_s)
{
    if (*t > t_s)
        *t = t_s;
}

void gd_intercept_time_back (gd_intercept_t *self, double t_s)
{
    if (!isfinite (t_s))
        return;
    s_not_after (&self->track.last_hit_s, t_s);
    s_not_after (&self->held.last_hit_s, t_s);
    s_not_after (&self->heard_hit_s, t_s);
    s_not_after (&self->heard_s, t_s);
    if (!s_active (self->phase) ||
        !(self->plan_s > t_s || self->close_s > t_s || self->overflight_s > t_s))
        return;
    // The UAV is back where it was at t_s: the route, the pass and its
    // samples were of a time that did not happen.
    self->phase = GD_TO_WAYPOINT;
    self->need_plan = true;
    self->confirming = false;
    self->was_inside = false;
    self->inside = false;
    self->overflight_s = NAN;
    self->n_samples = 0;
    self->close_s = NAN;
    s_reason (self,
              "the simulation went back to %.1f s (a service resumed from its saved state): "
              "planning again",
              t_s);
}

/* ---- commands ----------------------------------------------------------------------------- */

int gd_intercept_designate (gd_intercept_t *self, const gd_track_t *t, double t_s, char *why,
                            size_t whylen)
{
    if (!t || t->id == 0 || !isfinite (t->pos.e) || !isfinite (t->pos.n) || !isfinite (t->vel.e) ||
        !isfinite (t->vel.n) || !isfinite (t->t_s)) {
        snprintf (why, whylen, "the track has no valid position or velocity");
        return -EINVAL;
    }
    if (t->status == CGS_TRACK_DELETED) {
        snprintf (why, whylen, "track %u was deleted", t->id);
        return -EINVAL;
    }
    if (t->status == CGS_TRACK_TENTATIVE) {
        snprintf (why, whylen, "track %u is tentative (not yet confirmed)", t->id);
        return -EINVAL;
    }
    if (gd_norm (t->vel) > self->p.max_target_speed_mps) {
        snprintf (why, whylen, "track %u's velocity (%.0f m/s) is not credible", t->id,
                  gd_norm (t->vel));
        return -EINVAL;
    }
    uint32_t before = s_active (self->phase) ? self->track_id : 0;
    self->track_id = t->id;
    self->track = *t;
    self->have_track = true;
    self->designation_number++;
    self->designation_s = t_s;
    self->replans = 0;
    self->was_inside = false;
    self->inside = false;
    self->overflight_s = NAN;
    self->time_to_go_s = NAN;
    self->has_plan = false;
    self->orphan = false;
    self->last_status = t->status;
    self->heard_hit_s = isfinite (t->last_hit_s) ? t->last_hit_s : -INFINITY;
    self->heard_s = t->t_s;
    self->holding = false;
    self->confirming = false;
    self->n_samples = 0;
    self->phase = GD_TO_WAYPOINT;
    s_plan (self);
    if (before && before != t->id)
        s_reason (self, "designated track %u (pre-empts track %u)", t->id, before);
    else
        s_reason (self, "designated track %u", t->id);
    s_note_horizon (self);
    return 0;
}

int gd_intercept_cancel (gd_intercept_t *self, double t_s)
{
    (void)t_s;
    if (self->phase == GD_IDLE || self->phase == GD_CANCELLED)
        return -EALREADY;
    self->phase = GD_CANCELLED;
    self->need_plan = false;
    self->confirming = false;
    self->holding = false;
    s_task_loiter_here (self);
    s_reason (self, "cancelled by the operator: loitering here");
    return 0;
}

void gd_intercept_set_method (gd_intercept_t *self, gd_method_t m)
{
    if (m != GD_HEAD_ON && m != GD_MTI_HITS)
        return;
    bool changed = m != self->method;
    self->method = m;
    if (changed && s_active (self->phase) && self->phase != GD_OVERFLIGHT)
        s_replan (self, m == GD_HEAD_ON ? "method: head-on" : "method: MTI hits");
}

int gd_intercept_set_scale (gd_intercept_t *self, uint32_t scale)
{
    if (scale != 1 && scale != 5 && scale != 10)
        return -EINVAL;
    self->scale = scale;
    return 0;
}

/* ---- queries ------------------------------------------------------------------------------ */

const gd_task_t *gd_intercept_task (const gd_intercept_t *self)
{
    return &self->task;
}

uint64_t gd_intercept_changes (const gd_intercept_t *self)
{
    return self->changes;
}

void gd_intercept_status (const gd_intercept_t *self, gd_status_t *ret)
{
    gd_status_t s = {0};
    s.phase = self->phase;
    s.method = self->method;
    s.track_id = self->phase == GD_IDLE ? 0 : self->track_id;
    s.designation_number = self->designation_number;
    s.has_plan = self->has_plan && s_active (self->phase);
    s.waypoint = self->wp.waypoint;
    s.has_secondary = s.has_plan && self->wp.secondary;
    s.secondary = self->wp.second;
    s.route = self->task.kind == GD_TASK_ROUTE ? self->task.points : NULL;
    s.route_count = self->task.kind == GD_TASK_ROUTE ? self->task.count : 0;
    s.t_pred_s = self->wp.t_pred_s;
    s.has_footprint = self->have_fp && s_active (self->phase);
    s.footprint = self->fp;
    s.display_scale = self->scale;
    s.target_in_footprint = s_active (self->phase) && self->inside;
    s.time_to_go_s = s_active (self->phase) ? self->time_to_go_s : NAN;
    s.replans = self->replans;
    s.reason = self->reason;
    s.designation_s = self->designation_s;
    s.overflight_s = self->overflight_s;
    s.has_target = s_active (self->phase) && self->have_track;
    s.target = self->track.pos;
    s.target_vel = self->track.vel;
    s.target_t_s = self->track.t_s;
    s.y_u_m = self->wp.y_u_m;
    *ret = s;
}

int gd_pick_nearest (const gd_track_t *tracks, size_t n, gd_v2_t p, gd_pick_t pick, double *ret_d_m)
{
    int best = -ENOENT;
    double best_d = INFINITY;
    for (size_t i = 0; i < n; i++) {
        const gd_track_t *t = &tracks[i];
        if (t->status != CGS_TRACK_CONFIRMED && t->status != CGS_TRACK_COASTING)
            continue;
        if ((pick == GD_PICK_UNKNOWN && t->friendly) || (pick == GD_PICK_FRIENDLY && !t->friendly))
            continue;
        gd_v2_t at = t->history_count ? t->history[t->history_count - 1] : t->pos;
        double d = gd_norm (gd_sub (at, p));
        if (d < best_d) {
            best_d = d;
            best = (int)i;
        }
    }
    if (best >= 0 && ret_d_m)
        *ret_d_m = best_d;
    return best;
}

void gd_uav_sensor (const gd_uav_t *u, double max_range_m, gd_sensor_t *ret)
{
    *ret = (gd_sensor_t){
        .position = u->position,
        .heading_deg = u->heading_deg,
        .pitch_deg = u->pitch_deg,
        .roll_deg = u->roll_deg,
        .depression_deg = u->depression_deg,
        .hfov_deg = u->hfov_deg,
        .vfov_deg = u->vfov_deg,
        .max_range_m = max_range_m,
        .point = u->camera,
    };
}
