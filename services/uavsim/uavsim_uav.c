/* uavsim_uav — fixed-wing UAV flight model: L1 guidance (Park, Deyst and How)
 * on straight legs and loiter circles, coordinated turns with bank and roll
 * rate limits, airspeed and altitude-above-ground hold, tasks, and an exact
 * save/restore of the dynamic state. See uavsim_uav.h for the laws.
 * Pure: no globals, no clocks, no logging. */
#include "uavsim_uav.h"
#include "cgs_ckpt.h"
#include "cgs_util.h"

#include <assert.h>
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Saved states must continue bit-identically on any build: no fused multiply-adds. */
#if defined(__clang__)
#pragma STDC FP_CONTRACT OFF
#endif

#define S_PI           3.14159265358979323846
#define S_DEG          (S_PI / 180.0)
#define S_TWO_PI       (2.0 * S_PI)
#define S_DT_MAX_S     10.0               // longest step accepted, s
#define S_CYCLE_S      0.02               // longest autopilot cycle (guidance at 50 Hz), s
#define S_TINY_M       1e-6               // legs and distances shorter than this are points, metres
#define S_CAPTURE_FRAC 0.05               // the orbit is captured within 5% of its radius ...
#define S_CAPTURE_M    10.0               // ... plus 10 m ...
#define S_CAPTURE_COS  0.8660254037844386 // ... flying within 30° of its tangent

#define S_SAVE_MAGIC   "UUAV" // cgs_ckpt kind of a UAV's checkpoint
#define S_SAVE_VERSION 1u
#define S_SAVE_WHAT    "UAV checkpoint"

typedef enum {
    S_TASK_LOITER = 0, // circling (or joining) the loiter orbit
    S_TASK_ROUTE = 1,  // flying the route (goto is a one-point route)
} s_task_t;

struct uavsim_uav_model {
    uavsim_uav_params_t p; // parameters (copied)

    double e_m, n_m, u_m;  // position, local ENU, metres
    double course_rad;     // course = heading, clockwise from north, [0, 2pi)
    double v_mps;          // airspeed = ground speed along the flight path, m/s
    double bank_rad;       // bank, right wing down positive, radians
    double climb_mps;      // rate of climb over the last step, m/s
    double gamma_rad;      // flight-path angle, radians
    double agl_cmd_m;      // commanded altitude above ground, metres
    double v_cmd_mps;      // commanded airspeed, m/s
    double terrain_prev_m; // terrain height the last step was given, metres
    bool have_terrain;     // terrain_prev_m is set

    uint64_t task_number;    // increments with every accepted task
    s_task_t task;           // lateral task
    double lc_e_m, lc_n_m;   // loiter centre (now, or at the route's end), metres
    double lr_m;             // loiter radius, metres
    bool lcw;                // loiter clockwise
    bool captured;           // the orbit has been joined (mode LOITER rather than TRANSIT)
    bool is_goto;            // the route is a go-to (mode TRANSIT rather than ROUTE)
    bool loiter_at_end;      // the route ends in a loiter about its last point
    cgs_enu_t *route;        // route points (count of them)
    size_t count;            // route points
    size_t index;            // next route point; count once past the last
    double org_e_m, org_n_m; // where the UAV was when the route was tasked (start of leg 0)
};

/* --- parameters ---------------------------------------------------------------- */

void uavsim_uav_params_defaults (uavsim_uav_params_t *p)
{
    p->bank_limit_deg = 30;
    p->roll_rate_dps = 20;
    p->climb_rate_mps = 5;
    p->airspeed_min_mps = 20;
    p->airspeed_max_mps = 60;
    p->airspeed_accel_mps2 = 1;
    p->l1_period_s = 20;
    p->l1_damping = 0.75;
    p->altitude_tau_s = 5;
    p->loiter_radius_m = 1000;
    p->switch_distance_m = 50;
}

static bool s_pos (double x)
{
    return isfinite (x) && x > 0;
}

int uavsim_uav_params_check (const uavsim_uav_params_t *p)
{
    if (!p)
        return -EINVAL;
    if (!s_pos (p->bank_limit_deg) || p->bank_limit_deg > 80)
        return -EINVAL;
    if (!s_pos (p->roll_rate_dps) || !s_pos (p->airspeed_accel_mps2))
        return -EINVAL;
    if (!s_pos (p->airspeed_min_mps) || !s_pos (p->airspeed_max_mps) ||
        p->airspeed_min_mps > p->airspeed_max_mps)
        return -EINVAL;
    // The flight path cannot climb faster than the UAV flies.
    if (!s_pos (p->climb_rate_mps) || p->climb_rate_mps >= p->airspeed_min_mps)
        return -EINVAL;
    if (!s_pos (p->l1_period_s) || !s_pos (p->l1_damping) || p->l1_damping > 2)
        return -EINVAL;
    if (!s_pos (p->altitude_tau_s))
        return -EINVAL;
    if (!s_pos (p->loiter_radius_m) || p->loiter_radius_m > UAVSIM_UAV_RADIUS_MAX_M)
        return -EINVAL;
    if (!isfinite (p->switch_distance_m) || p->switch_distance_m < 0)
        return -EINVAL;
    return 0;
}

/* --- small helpers ------------------------------------------------------------- */

static double s_clamp (double x, double lo, double hi)
{
    return x < lo ? lo : x > hi ? hi : x;
}

/* x moved toward target by at most step. */
static double s_toward (double x, double target, double step)
{
    return target > x + step ? x + step : target < x - step ? x - step : target;
}

static double s_wrap_2pi (double a)
{
    a = fmod (a, S_TWO_PI);
    if (a < 0)
        a += S_TWO_PI;
    if (a >= S_TWO_PI)
        a = 0;
    return a;
}

/* A radius argument: 0 means the default; else finite, positive, at most the maximum. */
static int s_radius (const uavsim_uav_model_t *self, double radius_m, double *ret_r)
{
    if (!isfinite (radius_m) || radius_m < 0 || radius_m > UAVSIM_UAV_RADIUS_MAX_M)
        return -EINVAL;
    *ret_r = radius_m > 0 ? radius_m : self->p.loiter_radius_m;
    return 0;
}

static bool s_agl_ok (double agl_m)
{
    return isfinite (agl_m) && agl_m > 0 && agl_m <= UAVSIM_UAV_AGL_MAX_M;
}

/* --- life cycle ---------------------------------------------------------------- */

uavsim_uav_model_t *uavsim_uav_new (const uavsim_uav_params_t *p, const uavsim_uav_init_t *init)
{
    if (uavsim_uav_params_check (p) != 0 || !init)
        return NULL;
    if (!isfinite (init->position.e_m) || !isfinite (init->position.n_m) ||
        !isfinite (init->position.u_m) || !isfinite (init->heading_deg))
        return NULL;
    if (!isfinite (init->airspeed_mps) || init->airspeed_mps < p->airspeed_min_mps ||
        init->airspeed_mps > p->airspeed_max_mps || !s_agl_ok (init->agl_m))
        return NULL;
    uavsim_uav_model_t *self = calloc (1, sizeof *self);
    if (!self)
        return NULL;
    self->p = *p;
    self->e_m = init->position.e_m;
    self->n_m = init->position.n_m;
    self->u_m = init->position.u_m;
    self->course_rad = s_wrap_2pi (init->heading_deg * S_DEG);
    self->v_mps = init->airspeed_mps;
    self->v_cmd_mps = init->airspeed_mps;
    self->agl_cmd_m = init->agl_m;
    self->task = S_TASK_LOITER;
    self->lc_e_m = self->e_m;
    self->lc_n_m = self->n_m;
    self->lcw = init->loiter_clockwise;
    if (s_radius (self, init->loiter_radius_m, &self->lr_m) != 0)
        goto fail;
    return self;
fail:
    uavsim_uav_destroy (&self);
    return NULL;
}

void uavsim_uav_destroy (uavsim_uav_model_t **self_p)
{
    if (!self_p || !*self_p)
        return;
    free ((*self_p)->route);
    free (*self_p);
    *self_p = NULL;
}

/* --- guidance ------------------------------------------------------------------ */

static double s_l1_m (const uavsim_uav_model_t *self)
{
    return self->p.l1_damping * self->p.l1_period_s * self->v_mps / S_PI;
}

/* Lateral acceleration (right positive) that steers toward the reference point
 * (aim_e, aim_n) at distance L: 2·V²/min(L, L1)·sin(eta), as if at L1 when
 * it is farther (so a far point is turned to as briskly as a near one), and
 * with sin(eta) = ±1 when it lies behind. */
static double s_accel_toward (const uavsim_uav_model_t *self, double aim_e, double aim_n)
{
    double re = aim_e - self->e_m, rn = aim_n - self->n_m;
    double len = hypot (re, rn);
    if (len < S_TINY_M)
        return 0;
    double ve = sin (self->course_rad), vn = cos (self->course_rad);
    double eta = atan2 (vn * re - ve * rn, ve * re + vn * rn); // right of the velocity positive
    double k = 2.0 * self->v_mps * self->v_mps / fmin (len, s_l1_m (self));
    if (fabs (eta) > S_PI / 2)
        return eta > 0 ? k : -k;
    return k * sin (eta);
}

/* Lateral acceleration that tracks the line through a toward b. */
static double s_accel_line (const uavsim_uav_model_t *self, double ae, double an, double be,
                            double bn)
{
    double de = be - ae, dn = bn - an, len = hypot (de, dn);
    if (len < S_TINY_M)
        return 0;
    double ue = de / len, un = dn / len;
    double we = self->e_m - ae, wn = self->n_m - an;
    double along = we * ue + wn * un;
    double xt = we * un - wn * ue; // right of the line positive
    double l1 = s_l1_m (self);
    double ahead = fabs (xt) < l1 ? sqrt (l1 * l1 - xt * xt) : 0;
    double s = along + ahead;
    return s_accel_toward (self, ae + s * ue, an + s * un);
}

/* Lateral acceleration that joins and holds the loiter orbit. */
static double s_accel_circle (const uavsim_uav_model_t *self)
{
    double ce = self->lc_e_m, cn = self->lc_n_m, r = self->lr_m;
    double we = self->e_m - ce, wn = self->n_m - cn, d = hypot (we, wn);
    double ue, un; // unit vector from the centre toward the UAV
    if (d > S_TINY_M) {
        ue = we / d;
        un = wn / d;
    } else { // at the centre: as if just behind it along the course
        ue = sin (self->course_rad);
        un = cos (self->course_rad);
    }
    // Unit vector a quarter turn from u in the direction of circulation
    // (anticlockwise seen from above: rotate +90° in east-north).
    double sgn = self->lcw ? -1.0 : 1.0;
    double pe = -un * sgn, pn = ue * sgn;
    double l1 = s_l1_m (self);
    double ca, sa; // the reference point is centre + r·(ca·u + sa·p)
    if (d >= fabs (r - l1) && d <= r + l1 && d > S_TINY_M) {
        // The L1 circle about the UAV meets the orbit: the meeting point ahead.
        double a = (d * d + r * r - l1 * l1) / (2 * d);
        ca = s_clamp (a / r, -1, 1);
        sa = sqrt (1 - ca * ca);
    } else if (d > r + l1) {
        // Far outside: the tangent point on the side of circulation.
        ca = r / d;
        sa = sqrt (1 - ca * ca);
    } else if (d < r - l1) {
        // Well inside: a point ahead whose direction has an outward part
        // (R·ca - d = (R - d)/2 > 0), so following it spirals out to the orbit.
        ca = (d + r) / (2 * r);
        sa = sqrt (1 - ca * ca);
    } else {
        // An orbit smaller than L1 and the UAV near it: a quarter turn ahead.
        ca = 0;
        sa = 1;
    }
    return s_accel_toward (self, ce + r * (ca * ue + sa * pe), cn + r * (ca * un + sa * pn));
}

/* Start of the leg that ends at route point i. */
static void s_leg_start (const uavsim_uav_model_t *self, size_t i, double *ret_e, double *ret_n)
{
    if (i == 0) {
        *ret_e = self->org_e_m;
        *ret_n = self->org_n_m;
    } else {
        *ret_e = self->route[i - 1].e_m;
        *ret_n = self->route[i - 1].n_m;
    }
}

/* Commanded lateral acceleration for the present task, m/s², right positive. */
static double s_guidance (const uavsim_uav_model_t *self)
{
    if (self->task == S_TASK_LOITER)
        return s_accel_circle (self);
    double ae, an;
    if (self->index < self->count) {
        s_leg_start (self, self->index, &ae, &an);
        return s_accel_line (self, ae, an, self->route[self->index].e_m,
                             self->route[self->index].n_m);
    }
    // Past the last point without a loiter: on along the last leg of any length.
    for (size_t i = self->count; i-- > 0;) {
        s_leg_start (self, i, &ae, &an);
        if (hypot (self->route[i].e_m - ae, self->route[i].n_m - an) >= S_TINY_M)
            return s_accel_line (self, ae, an, self->route[i].e_m, self->route[i].n_m);
    }
    return 0;
}

/* --- task progress ------------------------------------------------------------- */

/* Has the UAV reached route point i (within the switching distance, or past
 * the bisector of the turn there)? */
static bool s_reached (const uavsim_uav_model_t *self, size_t i)
{
    double ae, an;
    s_leg_start (self, i, &ae, &an);
    double be = self->route[i].e_m, bn = self->route[i].n_m;
    double l_in = hypot (be - ae, bn - an);
    double d = hypot (self->e_m - be, self->n_m - bn);
    if (l_in < S_TINY_M || d <= self->p.switch_distance_m)
        return true;
    double ne = (be - ae) / l_in, nn = (bn - an) / l_in;
    if (i + 1 < self->count) {
        double oe = self->route[i + 1].e_m - be, on = self->route[i + 1].n_m - bn;
        double l_out = hypot (oe, on);
        if (l_out >= S_TINY_M) {
            double me = ne + oe / l_out, mn = nn + on / l_out;
            if (hypot (me, mn) > 1e-9) { // not a hairpin
                ne = me;
                nn = mn;
            }
        }
    }
    return (self->e_m - be) * ne + (self->n_m - bn) * nn >= 0;
}

/* Switch route legs and latch orbit capture after a move. */
static void s_progress (uavsim_uav_model_t *self)
{
    while (self->task == S_TASK_ROUTE && self->index < self->count &&
           s_reached (self, self->index)) {
        self->index++;
        if (self->index == self->count && self->loiter_at_end) {
            self->task = S_TASK_LOITER;
            self->captured = false;
            self->is_goto = false;
            free (self->route);
            self->route = NULL;
            self->count = 0;
            self->index = 0;
        }
    }
    if (self->task == S_TASK_LOITER && !self->captured) {
        double we = self->e_m - self->lc_e_m, wn = self->n_m - self->lc_n_m;
        double d = hypot (we, wn);
        if (d > S_TINY_M && fabs (d - self->lr_m) <= S_CAPTURE_FRAC * self->lr_m + S_CAPTURE_M) {
            double sgn = self->lcw ? -1.0 : 1.0;
            double te = -wn / d * sgn, tn = we / d * sgn;
            if (sin (self->course_rad) * te + cos (self->course_rad) * tn >= S_CAPTURE_COS)
                self->captured = true;
        }
    }
}

/* --- step ---------------------------------------------------------------------- */

/* One autopilot cycle of h seconds: guidance sampled at its start, roll and
 * airspeed at their limited rates, then the move along the exact arc of the
 * coordinated turn at the midpoint bank and speed, with the climb rate fixed. */
static void s_substep (uavsim_uav_model_t *self, double h_s, double climb_mps)
{
    const uavsim_uav_params_t *p = &self->p;
    double g = UAVSIM_UAV_G_MPS2;
    double bank_max = p->bank_limit_deg * S_DEG;
    double bank_cmd = s_clamp (atan (s_guidance (self) / g), -bank_max, bank_max);

    double bank0 = self->bank_rad, v0 = self->v_mps;
    double bank1 = s_toward (bank0, bank_cmd, p->roll_rate_dps * S_DEG * h_s);
    double v1 = s_toward (v0, self->v_cmd_mps, p->airspeed_accel_mps2 * h_s);
    double bank_mid = 0.5 * (bank0 + bank1), v_mid = 0.5 * (v0 + v1);

    double vh = sqrt (v_mid * v_mid - climb_mps * climb_mps); // horizontal speed
    double dchi = g * tan (bank_mid) / v_mid * h_s;
    double half = 0.5 * dchi;
    double sinc = fabs (half) < 1e-6 ? 1 - half * half / 6 : sin (half) / half;
    double chord = vh * h_s * sinc;
    double dir = self->course_rad + half;
    self->e_m += chord * sin (dir);
    self->n_m += chord * cos (dir);
    self->course_rad = s_wrap_2pi (self->course_rad + dchi);
    self->bank_rad = bank1;
    self->v_mps = v1;
    s_progress (self);
}

int uavsim_uav_step (uavsim_uav_model_t *self, double dt_s, double terrain_h_m)
{
    if (!self || !isfinite (dt_s) || dt_s <= 0 || dt_s > S_DT_MAX_S || !isfinite (terrain_h_m))
        return -EINVAL;
    const uavsim_uav_params_t *p = &self->p;

    // Altitude, once per step: first order toward terrain + AGL, with the
    // terrain's rise since the last step fed forward (expected again in this
    // one), limited by the climb rate; exact exponential over the step.
    double ff = self->have_terrain ? (terrain_h_m - self->terrain_prev_m) : 0;
    double target = terrain_h_m + self->agl_cmd_m;
    double du = ff + (target - self->u_m) * -expm1 (-dt_s / p->altitude_tau_s);
    double du_max = p->climb_rate_mps * dt_s;
    du = s_clamp (du, -du_max, du_max);
    double climb = du / dt_s;

    // Lateral guidance and flight in autopilot cycles of at most S_CYCLE_S.
    int n = (int)ceil (dt_s / S_CYCLE_S - 1e-9);
    if (n < 1)
        n = 1;
    for (int i = 0; i < n; i++)
        s_substep (self, dt_s / n, climb);

    self->u_m += du;
    self->climb_mps = climb;
    self->gamma_rad = asin (climb / self->v_mps);
    self->terrain_prev_m = terrain_h_m;
    self->have_terrain = true;
    return 0;
}

/* --- tasks --------------------------------------------------------------------- */

/* Replace the lateral task with a loiter about (e, n). */
static void s_set_loiter (uavsim_uav_model_t *self, double e_m, double n_m, double r_m, bool cw)
{
    free (self->route);
    self->route = NULL;
    self->count = 0;
    self->index = 0;
    self->task = S_TASK_LOITER;
    self->is_goto = false;
    self->loiter_at_end = false;
    self->lc_e_m = e_m;
    self->lc_n_m = n_m;
    self->lr_m = r_m;
    self->lcw = cw;
    self->captured = false;
    self->task_number++;
    s_progress (self);
}

int uavsim_uav_loiter (uavsim_uav_model_t *self, cgs_enu_t centre, double radius_m, bool clockwise)
{
    double r;
    if (!self || !isfinite (centre.e_m) || !isfinite (centre.n_m) ||
        s_radius (self, radius_m, &r) != 0)
        return -EINVAL;
    s_set_loiter (self, centre.e_m, centre.n_m, r, clockwise);
    return 0;
}

int uavsim_uav_loiter_here (uavsim_uav_model_t *self, double radius_m, bool clockwise)
{
    double r;
    if (!self || s_radius (self, radius_m, &r) != 0)
        return -EINVAL;
    s_set_loiter (self, self->e_m, self->n_m, r, clockwise);
    return 0;
}

/* Replace the lateral task with a route (copied). */
static int s_set_route (uavsim_uav_model_t *self, const cgs_enu_t *points, size_t count,
                        bool loiter_at_end, double radius_m, bool clockwise, bool is_goto)
{
    double r;
    if (!self || !points || count < 1 || count > UAVSIM_UAV_ROUTE_MAX ||
        s_radius (self, radius_m, &r) != 0)
        return -EINVAL;
    for (size_t i = 0; i < count; i++)
        if (!isfinite (points[i].e_m) || !isfinite (points[i].n_m) || !isfinite (points[i].u_m))
            return -EINVAL;
    cgs_enu_t *copy = malloc (count * sizeof *copy);
    if (!copy)
        return -ENOMEM;
    memcpy (copy, points, count * sizeof *copy);
    free (self->route);
    self->route = copy;
    self->count = count;
    self->index = 0;
    self->org_e_m = self->e_m;
    self->org_n_m = self->n_m;
    self->task = S_TASK_ROUTE;
    self->is_goto = is_goto;
    self->loiter_at_end = loiter_at_end;
    self->lc_e_m = points[count - 1].e_m;
    self->lc_n_m = points[count - 1].n_m;
    self->lr_m = r;
    self->lcw = clockwise;
    self->captured = false;
    self->task_number++;
    s_progress (self);
    return 0;
}

int uavsim_uav_goto (uavsim_uav_model_t *self, cgs_enu_t point, double radius_m, bool clockwise)
{
    return s_set_route (self, &point, 1, true, radius_m, clockwise, true);
}

int uavsim_uav_route (uavsim_uav_model_t *self, const cgs_enu_t *points, size_t count,
                      bool loiter_at_end, double radius_m, bool clockwise)
{
    return s_set_route (self, points, count, loiter_at_end, radius_m, clockwise, false);
}

int uavsim_uav_set_altitude (uavsim_uav_model_t *self, double agl_m)
{
    if (!self || !s_agl_ok (agl_m))
        return -EINVAL;
    self->agl_cmd_m = agl_m;
    self->task_number++;
    return 0;
}

int uavsim_uav_set_speed (uavsim_uav_model_t *self, double airspeed_mps)
{
    if (!self || !isfinite (airspeed_mps) || airspeed_mps < self->p.airspeed_min_mps ||
        airspeed_mps > self->p.airspeed_max_mps)
        return -EINVAL;
    self->v_cmd_mps = airspeed_mps;
    self->task_number++;
    return 0;
}

/* --- queries ------------------------------------------------------------------- */

void uavsim_uav_state (const uavsim_uav_model_t *self, uavsim_uav_state_t *ret_s)
{
    assert (self && ret_s);
    uavsim_uav_state_t s;
    memset (&s, 0, sizeof s);
    s.position = (cgs_enu_t){self->e_m, self->n_m, self->u_m};
    double vh = sqrt (self->v_mps * self->v_mps - self->climb_mps * self->climb_mps);
    s.velocity =
        (cgs_enu_t){vh * sin (self->course_rad), vh * cos (self->course_rad), self->climb_mps};
    s.heading_deg = self->course_rad / S_DEG;
    if (s.heading_deg >= 360)
        s.heading_deg = 0;
    s.pitch_deg = self->gamma_rad / S_DEG;
    s.roll_deg = self->bank_rad / S_DEG;
    s.airspeed_mps = self->v_mps;
    s.climb_rate_mps = self->climb_mps;
    s.commanded_agl_m = self->agl_cmd_m;
    s.commanded_airspeed_mps = self->v_cmd_mps;
    if (self->task == S_TASK_LOITER)
        s.mode = self->captured ? UAVSIM_UAV_MODE_LOITER : UAVSIM_UAV_MODE_TRANSIT;
    else
        s.mode = self->is_goto && self->index < self->count ? UAVSIM_UAV_MODE_TRANSIT
                                                            : UAVSIM_UAV_MODE_ROUTE;
    s.task_number = self->task_number;
    s.loiter_center = (cgs_enu_t){self->lc_e_m, self->lc_n_m, 0};
    s.loiter_radius_m = self->lr_m;
    s.loiter_clockwise = self->lcw;
    s.route_count = self->count;
    s.route_index = self->index;
    s.route_loiter_at_end = self->task == S_TASK_ROUTE && self->loiter_at_end;
    *ret_s = s;
}

const cgs_enu_t *uavsim_uav_route_points (const uavsim_uav_model_t *self, size_t *ret_count)
{
    assert (self && ret_count);
    *ret_count = self->count;
    return self->count ? self->route : NULL;
}

const uavsim_uav_params_t *uavsim_uav_params (const uavsim_uav_model_t *self)
{
    assert (self);
    return &self->p;
}

double uavsim_uav_min_turn_radius (const uavsim_uav_model_t *self, double v_mps)
{
    assert (self);
    return cgs_flight_turn_radius (v_mps, self->p.bank_limit_deg);
}

/* --- save and restore ---------------------------------------------------------- */

/* A cgs_ckpt frame "UUAV", version 1. Payload: 11 f64 (e, n, u, course,
 * airspeed, bank, climb, flight-path angle, AGL command, airspeed command,
 * previous terrain), u8 have_terrain, u64 task number, u8 task, u8 captured,
 * u8 is_goto, u8 loiter_at_end, u8 clockwise, 5 f64 (loiter centre e, n,
 * radius, route origin e, n), u32 count, u32 index, count × 3 f64 (e, n, u). */

int uavsim_uav_save (const uavsim_uav_model_t *self, uint8_t **ret_buf, size_t *ret_len)
{
    if (!self)
        return -EINVAL;
    cgs_ckpt_writer_t w;
    cgs_ckpt_writer_init (&w, S_SAVE_MAGIC, S_SAVE_VERSION);
    const double f1[] = {self->e_m,       self->n_m,       self->u_m,           self->course_rad,
                         self->v_mps,     self->bank_rad,  self->climb_mps,     self->gamma_rad,
                         self->agl_cmd_m, self->v_cmd_mps, self->terrain_prev_m};
    for (size_t i = 0; i < sizeof f1 / sizeof f1[0]; i++)
        cgs_ckpt_put_f64 (&w, f1[i]);
    cgs_ckpt_put_bool (&w, self->have_terrain);
    cgs_ckpt_put_u64 (&w, self->task_number);
    cgs_ckpt_put_u8 (&w, (uint8_t)self->task);
    cgs_ckpt_put_bool (&w, self->captured);
    cgs_ckpt_put_bool (&w, self->is_goto);
    cgs_ckpt_put_bool (&w, self->loiter_at_end);
    cgs_ckpt_put_bool (&w, self->lcw);
    const double f2[] = {self->lc_e_m, self->lc_n_m, self->lr_m, self->org_e_m, self->org_n_m};
    for (size_t i = 0; i < sizeof f2 / sizeof f2[0]; i++)
        cgs_ckpt_put_f64 (&w, f2[i]);
    cgs_ckpt_put_u32 (&w, (uint32_t)self->count);
    cgs_ckpt_put_u32 (&w, (uint32_t)self->index);
    for (size_t i = 0; i < self->count; i++) {
        cgs_ckpt_put_f64 (&w, self->route[i].e_m);
        cgs_ckpt_put_f64 (&w, self->route[i].n_m);
        cgs_ckpt_put_f64 (&w, self->route[i].u_m);
    }
    return cgs_ckpt_writer_finish (&w, ret_buf, ret_len);
}

int uavsim_uav_restore (uavsim_uav_model_t *self, const void *buf, size_t len, char *err,
                        size_t errlen)
{
    if (!self)
        return -EINVAL;
    cgs_ckpt_reader_t r;
    int rc = cgs_ckpt_open (&r, buf, len, S_SAVE_MAGIC, S_SAVE_VERSION, S_SAVE_WHAT, err, errlen);
    if (rc < 0)
        return rc;
    uavsim_uav_model_t t = *self; // parameters kept; everything dynamic replaced
    t.route = NULL;
    double *f1[] = {&t.e_m,       &t.n_m,       &t.u_m,           &t.course_rad,
                    &t.v_mps,     &t.bank_rad,  &t.climb_mps,     &t.gamma_rad,
                    &t.agl_cmd_m, &t.v_cmd_mps, &t.terrain_prev_m};
    for (size_t i = 0; i < sizeof f1 / sizeof f1[0]; i++)
        *f1[i] = cgs_ckpt_get_finite (&r);
    t.have_terrain = cgs_ckpt_get_bool (&r);
    t.task_number = cgs_ckpt_get_u64 (&r);
    uint8_t task = cgs_ckpt_get_u8 (&r);
    t.task = task <= S_TASK_ROUTE ? (s_task_t)task : S_TASK_LOITER;
    t.captured = cgs_ckpt_get_bool (&r);
    t.is_goto = cgs_ckpt_get_bool (&r);
    t.loiter_at_end = cgs_ckpt_get_bool (&r);
    t.lcw = cgs_ckpt_get_bool (&r);
    double *f2[] = {&t.lc_e_m, &t.lc_n_m, &t.lr_m, &t.org_e_m, &t.org_n_m};
    for (size_t i = 0; i < sizeof f2 / sizeof f2[0]; i++)
        *f2[i] = cgs_ckpt_get_finite (&r);
    t.count = cgs_ckpt_get_u32 (&r);
    t.index = cgs_ckpt_get_u32 (&r);
    // Physically possible values only.
    bool ok = cgs_ckpt_ok (&r) && task <= S_TASK_ROUTE;
    ok = ok && t.v_mps > 0 && t.v_cmd_mps > 0 && fabs (t.climb_mps) < t.v_mps;
    ok = ok && t.course_rad >= 0 && t.course_rad < S_TWO_PI && fabs (t.bank_rad) < S_PI / 2;
    ok = ok && fabs (t.gamma_rad) < S_PI / 2 && s_agl_ok (t.agl_cmd_m);
    ok = ok && t.lr_m > 0 && t.lr_m <= UAVSIM_UAV_RADIUS_MAX_M;
    ok = ok && t.count <= UAVSIM_UAV_ROUTE_MAX && t.index <= t.count;
    ok = ok && (t.task == S_TASK_ROUTE ? t.count >= 1 : t.count == 0);
    if (!ok) {
        cgs_errf (err, errlen, "a %s with values no UAV can have", S_SAVE_WHAT);
        return -EINVAL;
    }
    if (t.count) {
        t.route = malloc (t.count * sizeof *t.route);
        if (!t.route)
            return -ENOMEM;
        for (size_t i = 0; i < t.count; i++) {
            t.route[i].e_m = cgs_ckpt_get_finite (&r);
            t.route[i].n_m = cgs_ckpt_get_finite (&r);
            t.route[i].u_m = cgs_ckpt_get_finite (&r);
        }
    }
    if ((rc = cgs_ckpt_end (&r, S_SAVE_WHAT, err, errlen)) < 0) {
        free (t.route);
        return rc;
    }
    free (self->route);
    *self = t;
    return 0;
}
