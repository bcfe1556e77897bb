/* uavsim_vehicle — a ground vehicle driving its route: a path of straights and
 * circular corner arcs built once from the route, a speed profile with
 * look-ahead braking that is integrated exactly between the points where the
 * speed limit changes, turns in place where the route doubles back, halts on
 * the points that ask for one, a seeded lateral wander on the straights,
 * heights and attitude from the terrain, and a checksummed checkpoint of the
 * dynamic state. Pure: no globals, no logging.
 *
 * The vehicle's place is (element, direction, lap, x): element k runs from the
 * middle of the corner arc at point k to the middle of the one at point k+1
 * (from and to the point itself where there is no arc), x is the distance
 * driven along it. Each element is at most three pieces in a row — half an
 * arc, the straight, half an arc — each with its own speed limit. */
#include "uavsim_vehicle.h"
#include "cgs_ckpt.h"
#include "cgs_util.h"

#include <assert.h>
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The track must come out the same everywhere: no fused multiply-adds. */
#if defined(__clang__)
#pragma STDC FP_CONTRACT OFF
#endif

#define S_PI             3.14159265358979323846
#define S_DEG            (S_PI / 180.0)
#define S_MAX_POINTS     100000        // longest route
#define S_MAX_COORD_M    1e8           // farthest point from the origin, metres
#define S_MAX_SPEED_MPS  300.0         // fastest vehicle, m/s
#define S_MAX_DEV_M      10000.0       // largest wander, metres
#define S_MIN_LEG_M      0.01          // shortest leg, metres
#define S_PIVOT_RAD      (170 * S_DEG) // corners this sharp are turned in place
#define S_STRAIGHT_RAD   1e-6          // corners this slight are driven straight through
#define S_DEV_WAVES      3             // sinusoids in the wander
#define S_DEV_MIN_WAVE_M 100.0         // shortest wavelength drawn, metres
#define S_DEV_MAX_WAVE_M 500.0         // longest wavelength drawn, metres
#define S_MAX_HALT_S     1e6           // longest halt, seconds
#define S_SAVE_MAGIC     "UVHC"        // cgs_ckpt kind of a vehicle's checkpoint
#define S_SAVE_VERSION   1u
#define S_SAVE_WHAT      "vehicle checkpoint"

typedef enum { S_WAIT = 0, S_DRIVE = 1, S_PIVOT = 2, S_DONE = 3, S_HALT = 4 } s_phase_t;

/* What happens at a route point. */
typedef enum {
    S_VX_START,    // first point of a stop route: never driven into
    S_VX_STOP,     // last point of a stop route
    S_VX_PIVOT,    // stop on the point (halt there if it has one) and turn in place
    S_VX_STRAIGHT, // legs in line: driven straight through
    S_VX_ARC,      // rounded by a circular arc
} s_vx_kind_t;

typedef struct {
    s_vx_kind_t kind;
    double e_m, n_m;     // the point, metres
    double theta_rad;    // deflection between the legs, radians [0, pi]
    double sigma;        // +1 left (anticlockwise) turn, -1 right
    double r_m;          // arc radius, metres
    double t_m;          // tangent length: arc start and end from the point, metres
    double half_m;       // half the arc's length, metres
    double vc_mps;       // corner speed on the arc, m/s (0 where the vehicle stops)
    double ae_m, an_m;   // arc start, on the incoming leg
    double be_m, bn_m;   // arc end, on the outgoing leg
    double ce_m, cn_m;   // arc centre
    double r0e_m, r0n_m; // centre to arc start
    double uie, uin;     // incoming leg direction (unit)
    double halt_s;       // halt on arriving, seconds (0: none; > 0 only on S_VX_PIVOT)
} s_vertex_t;

typedef struct {
    double ue, un;    // direction from its first point to its second (unit)
    double len_m;     // length, metres
    double speed_mps; // speed limit, m/s
    double cum_m;     // length of the route before this leg, metres
} s_leg_t;

/* The current draw of the wander. */
typedef struct {
    double k_rpm[S_DEV_WAVES];     // wavenumber, radians per metre
    double phase_rad[S_DEV_WAVES]; // phase, radians
    double weight[S_DEV_WAVES];    // weights, summing to 1
} s_dev_t;

struct uavsim_vehicle {
    // Built from the parameters, fixed.
    uavsim_vehicle_end_t end;
    int npts;             // route points (a loop's repeated last point dropped)
    int nlegs;            // npts - 1, or npts for a loop
    s_vertex_t *vx;       // npts points
    s_leg_t *legs;        // nlegs legs; leg k from point k to point (k+1) % npts
    double start_time_s;  // when it sets off
    double dev_m;         // wander bound, metres
    double lat_mps2;      // lateral acceleration limit
    double omega_rps;     // turn rate limit, radians/s
    double acc_mps2;      // acceleration
    double dec_mps2;      // deceleration
    double vmax_mps;      // fastest leg
    uint64_t fingerprint; // hash of the parameters, checked by restore

    // Dynamic state (all of it is in the checkpoint).
    s_phase_t phase;
    int k;              // element (leg) index
    int dir;            // +1 along the route, -1 back
    uint64_t lap;       // laps or passes completed
    double x_m;         // distance along the element, metres
    double v_mps;       // speed, m/s
    double heading_rad; // heading, radians clockwise from north
    double pivot_rad;   // turn in place still to do, radians (+ clockwise)
    double halt_left_s; // halt still to stand, seconds (S_HALT only, else 0)
    uint64_t rng[4];    // xoshiro256** state
    s_dev_t dev;        // current wander

    uavsim_vehicle_state_t out; // state after the latest step
};

/* One element laid out: lengths in route order and pieces in driving order. */
typedef struct {
    int k, dir;
    uint64_t lap;
    double a0_m, s_m, a1_m; // half arc at the first point, straight, half arc at the second
    double t0_m, t1_m;      // leg length taken by the arcs at the first and second point
    double len_m;           // a0 + s + a1
    double seg_m[3];        // piece lengths in driving order
    double lim_mps[3];      // piece speed limits in driving order
    int seg_kind[3];        // 0 arc at the first point, 1 straight, 2 arc at the second
    s_vx_kind_t end_kind;   // kind of the point it is driven into
} s_elem_t;

static void s_update_out (uavsim_vehicle_t *self);

/* --- random numbers: xoshiro256** seeded through splitmix64 ------------------- */

static uint64_t s_splitmix (uint64_t *x)
{
    uint64_t z = (*x += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
}

static uint64_t s_rotl (uint64_t x, int k)
{
    return (x << k) | (x >> (64 - k));
}

static uint64_t s_next_u64 (uint64_t s[4])
{
    uint64_t result = s_rotl (s[1] * 5, 7) * 9;
    uint64_t t = s[1] << 17;
    s[2] ^= s[0];
    s[3] ^= s[1];
    s[1] ^= s[2];
    s[0] ^= s[3];
    s[2] ^= t;
    s[3] = s_rotl (s[3], 45);
    return result;
}

/* Uniform in [0, 1). */
static double s_uniform (uint64_t s[4])
{
    return (double)(s_next_u64 (s) >> 11) * (1.0 / 9007199254740992.0);
}

/* A new draw of the wander. */
static void s_dev_draw (uavsim_vehicle_t *self)
{
    double sum = 0;
    for (int i = 0; i < S_DEV_WAVES; i++) {
        double wave_m =
            S_DEV_MIN_WAVE_M + (S_DEV_MAX_WAVE_M - S_DEV_MIN_WAVE_M) * s_uniform (self->rng);
        self->dev.k_rpm[i] = 2 * S_PI / wave_m;
        self->dev.phase_rad[i] = 2 * S_PI * s_uniform (self->rng);
        self->dev.weight[i] = 0.5 + 0.5 * s_uniform (self->rng);
        sum += self->dev.weight[i];
    }
    for (int i = 0; i < S_DEV_WAVES; i++)
        self->dev.weight[i] /= sum;
}

/* --- parameters ------------------------------------------------------------------- */

void uavsim_vehicle_params_defaults (uavsim_vehicle_params_t *p)
{
    assert (p);
    *p = (uavsim_vehicle_params_t){
        .points = NULL,
        .n_points = 0,
        .speed_mps = 10,
        .start_time_s = 0,
        .end = UAVSIM_VEHICLE_END_STOP,
        .deviation_m = 0,
        .seed = 0,
        .lat_accel_mps2 = 2,
        .turn_rate_dps = 30,
        .accel_mps2 = 1.5,
        .decel_mps2 = 2,
        .corner_cut_m = 10,
        .halt_s = NULL,
    };
}

static bool s_positive (double x, double max)
{
    return isfinite (x) && x > 0 && x <= max;
}

int uavsim_vehicle_params_check (const uavsim_vehicle_params_t *p, char *err, size_t errlen)
{
    if (!p) {
        cgs_errf (err, errlen, "no parameters");
        return -EINVAL;
    }
    if (!p->points || p->n_points < 2) {
        cgs_errf (err, errlen, "a route needs at least 2 points");
        return -EINVAL;
    }
    if (p->n_points > S_MAX_POINTS) {
        cgs_errf (err, errlen, "a route has at most %d points", S_MAX_POINTS);
        return -EINVAL;
    }
    for (size_t i = 0; i < p->n_points; i++) {
        const uavsim_vehicle_point_t *q = &p->points[i];
        if (!isfinite (q->e_m) || !isfinite (q->n_m) || fabs (q->e_m) > S_MAX_COORD_M ||
            fabs (q->n_m) > S_MAX_COORD_M) {
            cgs_errf (err, errlen, "point %zu: position not finite or too far", i + 1);
            return -EINVAL;
        }
        if (!isfinite (q->speed_mps) || q->speed_mps < 0 || q->speed_mps > S_MAX_SPEED_MPS) {
            cgs_errf (err, errlen, "point %zu: speed must be 0 to %g m/s", i + 1, S_MAX_SPEED_MPS);
            return -EINVAL;
        }
        if (i > 0 &&
            hypot (q->e_m - p->points[i - 1].e_m, q->n_m - p->points[i - 1].n_m) < S_MIN_LEG_M) {
            cgs_errf (err, errlen, "point %zu repeats point %zu", i + 1, i);
            return -EINVAL;
        }
    }
    for (size_t i = 0; p->halt_s && i < p->n_points; i++) {
        double h = p->halt_s[i];
        if (!isfinite (h) || h < 0 || h > S_MAX_HALT_S) {
            cgs_errf (err, errlen, "point %zu: halt must be 0 to %g s", i + 1, S_MAX_HALT_S);
            return -EINVAL;
        }
        if (h == 0)
            continue;
        if (p->end == UAVSIM_VEHICLE_END_STOP && (i == 0 || i == p->n_points - 1)) {
            cgs_errf (err, errlen, "point %zu: a stop route %s, so it takes no halt", i + 1,
                      i == 0 ? "never returns to its first point" : "ends on its last point");
            return -EINVAL;
        }
        if (p->end == UAVSIM_VEHICLE_END_LOOP && i > 0 && i == p->n_points - 1 &&
            hypot (p->points[i].e_m - p->points[0].e_m, p->points[i].n_m - p->points[0].n_m) <
                S_MIN_LEG_M) {
            cgs_errf (err, errlen, "point %zu repeats point 1 to close the loop: halt on point 1",
                      i + 1);
            return -EINVAL;
        }
    }
    if (p->end == UAVSIM_VEHICLE_END_LOOP && p->n_points == 2) {
        const uavsim_vehicle_point_t *a = &p->points[0], *b = &p->points[1];
        if (hypot (a->e_m - b->e_m, a->n_m - b->n_m) < S_MIN_LEG_M) {
            cgs_errf (err, errlen, "a loop needs 2 distinct points");
            return -EINVAL;
        }
    }
    if (!s_positive (p->speed_mps, S_MAX_SPEED_MPS)) {
        cgs_errf (err, errlen, "speed must be above 0 and at most %g m/s", S_MAX_SPEED_MPS);
        return -EINVAL;
    }
    if (!isfinite (p->start_time_s)) {
        cgs_errf (err, errlen, "start time must be finite");
        return -EINVAL;
    }
    if (p->end != UAVSIM_VEHICLE_END_STOP && p->end != UAVSIM_VEHICLE_END_LOOP &&
        p->end != UAVSIM_VEHICLE_END_REVERSE) {
        cgs_errf (err, errlen, "end must be stop, loop or reverse");
        return -EINVAL;
    }
    if (!isfinite (p->deviation_m) || p->deviation_m < 0 || p->deviation_m > S_MAX_DEV_M) {
        cgs_errf (err, errlen, "deviation must be 0 to %g m", S_MAX_DEV_M);
        return -EINVAL;
    }
    if (!s_positive (p->lat_accel_mps2, 100) || !s_positive (p->turn_rate_dps, 360) ||
        !s_positive (p->accel_mps2, 100) || !s_positive (p->decel_mps2, 100) ||
        !s_positive (p->corner_cut_m, 1e6)) {
        cgs_errf (err, errlen,
                  "lateral acceleration, turn rate, acceleration, deceleration and corner cut "
                  "must be positive (at most 100 m/s^2, 360 deg/s, 1e6 m)");
        return -EINVAL;
    }
    return 0;
}

static uint64_t s_fnv (uint64_t h, uint64_t x)
{
    for (int i = 0; i < 8; i++) {
        h ^= (x >> (8 * i)) & 0xff;
        h *= 0x100000001b3ULL;
    }
    return h;
}

static uint64_t s_bits (double x)
{
    uint64_t u;
    memcpy (&u, &x, sizeof u);
    return u;
}

static uint64_t s_fingerprint (const uavsim_vehicle_params_t *p)
{
    uint64_t h = 0xcbf29ce484222325ULL;
    h = s_fnv (h, p->n_points);
    for (size_t i = 0; i < p->n_points; i++) {
        h = s_fnv (h, s_bits (p->points[i].e_m));
        h = s_fnv (h, s_bits (p->points[i].n_m));
        h = s_fnv (h, s_bits (p->points[i].speed_mps));
    }
    const double d[] = {p->speed_mps,     p->start_time_s, p->deviation_m, p->lat_accel_mps2,
                        p->turn_rate_dps, p->accel_mps2,   p->decel_mps2,  p->corner_cut_m};
    for (size_t i = 0; i < sizeof d / sizeof d[0]; i++)
        h = s_fnv (h, s_bits (d[i]));
    h = s_fnv (h, (uint64_t)p->end);
    h = s_fnv (h, p->seed);
    // Halts only where there are some: a route without them keeps the
    // fingerprint it had before halts existed.
    for (size_t i = 0; p->halt_s && i < p->n_points; i++)
        if (p->halt_s[i] > 0) {
            h = s_fnv (h, i);
            h = s_fnv (h, s_bits (p->halt_s[i]));
        }
    return h;
}

/* --- building the path -------------------------------------------------------------- */

/* Round the corner at point i (loop, or an interior point), given its legs. */
static void s_corner (uavsim_vehicle_t *self, double cut_m, int i)
{
    s_vertex_t *v = &self->vx[i];
    const s_leg_t *in = &self->legs[(i - 1 + self->nlegs) % self->nlegs];
    const s_leg_t *out = &self->legs[i];
    double cross = in->ue * out->un - in->un * out->ue;
    double dot = in->ue * out->ue + in->un * out->un;
    v->theta_rad = atan2 (fabs (cross), dot);
    v->sigma = cross > 0 ? 1 : -1;
    v->uie = in->ue;
    v->uin = in->un;
    if (v->halt_s > 0) { // stops on the point, whatever the angle
        v->kind = S_VX_PIVOT;
        return;
    }
    if (v->theta_rad < S_STRAIGHT_RAD) {
        v->kind = S_VX_STRAIGHT;
        return;
    }
    if (v->theta_rad >= S_PIVOT_RAD) {
        v->kind = S_VX_PIVOT;
        return;
    }
    v->kind = S_VX_ARC;
    double speed = fmin (in->speed_mps, out->speed_mps);
    double half = v->theta_rad / 2, tan_half = tan (half);
    double r_nat = fmax (speed * speed / self->lat_mps2, speed / self->omega_rps);
    double r_cut = cut_m / (1 / cos (half) - 1);
    double r_room = 0.5 * fmin (in->len_m, out->len_m) / tan_half;
    double r = fmin (r_nat, fmin (r_cut, r_room));
    v->r_m = r;
    v->vc_mps = fmin (speed, fmin (sqrt (self->lat_mps2 * r), self->omega_rps * r));
    v->t_m = r * tan_half;
    v->half_m = r * half;
    v->ae_m = v->e_m - v->t_m * in->ue;
    v->an_m = v->n_m - v->t_m * in->un;
    v->be_m = v->e_m + v->t_m * out->ue;
    v->bn_m = v->n_m + v->t_m * out->un;
    // Centre: r to the turn's side of the incoming leg (left of (ue, un) is (-un, ue)).
    v->ce_m = v->ae_m - v->sigma * r * in->un;
    v->cn_m = v->an_m + v->sigma * r * in->ue;
    v->r0e_m = v->ae_m - v->ce_m;
    v->r0n_m = v->an_m - v->cn_m;
}

int uavsim_vehicle_new (const uavsim_vehicle_params_t *p, uavsim_vehicle_t **ret_v)
{
    assert (ret_v);
    int rc = uavsim_vehicle_params_check (p, NULL, 0);
    if (rc < 0)
        return rc;
    uavsim_vehicle_t *self = calloc (1, sizeof *self);
    if (!self)
        return -ENOMEM;
    size_t n = p->n_points;
    if (p->end == UAVSIM_VEHICLE_END_LOOP &&
        hypot (p->points[n - 1].e_m - p->points[0].e_m, p->points[n - 1].n_m - p->points[0].n_m) <
            S_MIN_LEG_M)
        n--; // a closed route: its last point is its first
    self->end = p->end;
    self->npts = (int)n;
    self->nlegs = p->end == UAVSIM_VEHICLE_END_LOOP ? (int)n : (int)n - 1;
    self->vx = calloc (n, sizeof *self->vx);
    self->legs = calloc (n, sizeof *self->legs);
    if (!self->vx || !self->legs)
        goto fail;
    self->start_time_s = p->start_time_s;
    self->dev_m = p->deviation_m;
    self->lat_mps2 = p->lat_accel_mps2;
    self->omega_rps = p->turn_rate_dps * S_DEG;
    self->acc_mps2 = p->accel_mps2;
    self->dec_mps2 = p->decel_mps2;
    self->fingerprint = s_fingerprint (p);

    for (int i = 0; i < self->npts; i++) {
        self->vx[i].e_m = p->points[i].e_m;
        self->vx[i].n_m = p->points[i].n_m;
        self->vx[i].halt_s = p->halt_s ? p->halt_s[i] : 0;
    }
    double cum = 0;
    for (int k = 0; k < self->nlegs; k++) {
        s_leg_t *leg = &self->legs[k];
        const s_vertex_t *a = &self->vx[k], *b = &self->vx[(k + 1) % self->npts];
        double de = b->e_m - a->e_m, dn = b->n_m - a->n_m;
        leg->len_m = hypot (de, dn);
        leg->ue = de / leg->len_m;
        leg->un = dn / leg->len_m;
        double sp = p->points[k].speed_mps;
        leg->speed_mps = sp > 0 ? sp : p->speed_mps;
        leg->cum_m = cum;
        cum += leg->len_m;
        if (leg->speed_mps > self->vmax_mps)
            self->vmax_mps = leg->speed_mps;
    }
    for (int i = 0; i < self->npts; i++) {
        bool first = i == 0, last = i == self->npts - 1;
        if (p->end == UAVSIM_VEHICLE_END_STOP && (first || last))
            self->vx[i].kind = first ? S_VX_START : S_VX_STOP;
        else if (p->end == UAVSIM_VEHICLE_END_REVERSE && (first || last))
            self->vx[i].kind = S_VX_PIVOT;
        else
            s_corner (self, p->corner_cut_m, i);
    }

    uint64_t seed = p->seed;
    for (int i = 0; i < 4; i++)
        self->rng[i] = s_splitmix (&seed);
    s_dev_draw (self);
    self->phase = S_WAIT;
    self->k = 0;
    self->dir = 1;
    self->lap = 0;
    self->x_m = 0;
    self->v_mps = 0;
    self->heading_rad = atan2 (self->legs[0].ue, self->legs[0].un);
    self->pivot_rad = 0;
    self->halt_left_s = 0;
    s_update_out (self);
    *ret_v = self;
    return 0;
fail:
    uavsim_vehicle_destroy (&self);
    return -ENOMEM;
}

void uavsim_vehicle_destroy (uavsim_vehicle_t **self_p)
{
    if (!self_p || !*self_p)
        return;
    uavsim_vehicle_t *self = *self_p;
    free (self->vx);
    free (self->legs);
    free (self);
    *self_p = NULL;
}

int uavsim_vehicle_points (const uavsim_vehicle_t *self)
{
    assert (self);
    return self->npts;
}

void uavsim_vehicle_corner (const uavsim_vehicle_t *self, int i, double *ret_radius_m,
                            double *ret_speed_mps)
{
    assert (self && i >= 0 && i < self->npts);
    const s_vertex_t *v = &self->vx[i];
    bool arc = v->kind == S_VX_ARC;
    if (ret_radius_m)
        *ret_radius_m = arc ? v->r_m : 0;
    if (ret_speed_mps)
        *ret_speed_mps = arc ? v->vc_mps : 0;
}

/* --- elements ----------------------------------------------------------------------- */

static const s_vertex_t *s_vx_at (const uavsim_vehicle_t *self, int i)
{
    return &self->vx[i % self->npts];
}

/* Lay out element k driven in direction dir on lap lap. */
static void s_elem (const uavsim_vehicle_t *self, int k, int dir, uint64_t lap, s_elem_t *el)
{
    const s_leg_t *leg = &self->legs[k];
    const s_vertex_t *v0 = s_vx_at (self, k), *v1 = s_vx_at (self, k + 1);
    // A loop's first lap sets off from the first point itself, not from its arc.
    bool from_start = self->end == UAVSIM_VEHICLE_END_LOOP && lap == 0 && k == 0;
    bool arc0 = v0->kind == S_VX_ARC && !from_start, arc1 = v1->kind == S_VX_ARC;
    el->k = k;
    el->dir = dir;
    el->lap = lap;
    el->a0_m = arc0 ? v0->half_m : 0;
    el->t0_m = arc0 ? v0->t_m : 0;
    el->a1_m = arc1 ? v1->half_m : 0;
    el->t1_m = arc1 ? v1->t_m : 0;
    el->s_m = fmax (0, leg->len_m - el->t0_m - el->t1_m);
    el->len_m = el->a0_m + el->s_m + el->a1_m;
    const double len[3] = {el->a0_m, el->s_m, el->a1_m};
    const double lim[3] = {arc0 ? v0->vc_mps : leg->speed_mps, leg->speed_mps,
                           arc1 ? v1->vc_mps : leg->speed_mps};
    for (int i = 0; i < 3; i++) {
        int j = dir > 0 ? i : 2 - i;
        el->seg_m[i] = len[j];
        el->lim_mps[i] = lim[j];
        el->seg_kind[i] = j;
    }
    el->end_kind = (dir > 0 ? v1 : v0)->kind;
}

/* The element after el: false at the end of a stop route. */
static bool s_elem_next (const uavsim_vehicle_t *self, const s_elem_t *el, s_elem_t *ret)
{
    int k = el->k, dir = el->dir;
    uint64_t lap = el->lap;
    if (el->end_kind == S_VX_STOP)
        return false;
    if (dir > 0) {
        if (k + 1 < self->nlegs)
            k++;
        else if (self->end == UAVSIM_VEHICLE_END_LOOP) {
            k = 0;
            lap++;
        } else { // reverse at the last point
            dir = -1;
            lap++;
        }
    } else {
        if (k > 0)
            k--;
        else { // reverse at the first point
            dir = 1;
            lap++;
        }
    }
    s_elem (self, k, dir, lap, ret);
    return true;
}

/* Highest speed now such that, braking at the deceleration, the vehicle is at
 * or below lim_mps on reaching a point d_m ahead, given that this interval of
 * rem_s starts at v_mps and speed changes linearly over it: the root of
 * v^2 + dec rem v = lim^2 + 2 dec (d - v0 rem / 2); lim itself once the point
 * is within this interval's reach. */
static double s_brake (const uavsim_vehicle_t *self, double d_m, double lim_mps, double v_mps,
                       double rem_s)
{
    double b = self->dec_mps2 * rem_s;
    double c = lim_mps * lim_mps + 2 * self->dec_mps2 * d_m - b * v_mps;
    double disc = b * b + 4 * c;
    if (disc <= 0)
        return lim_mps;
    return fmax (lim_mps, 0.5 * (sqrt (disc) - b));
}

/* Speed limit just past the end of piece j of el. */
static double s_lim_after (const uavsim_vehicle_t *self, const s_elem_t *el, int j)
{
    for (int i = j + 1; i < 3; i++)
        if (el->seg_m[i] > 0)
            return el->lim_mps[i];
    if (el->end_kind == S_VX_STOP || el->end_kind == S_VX_PIVOT)
        return 0;
    s_elem_t nx;
    if (!s_elem_next (self, el, &nx))
        return 0;
    for (int i = 0; i < 3; i++)
        if (nx.seg_m[i] > 0)
            return nx.lim_mps[i];
    return 0;
}

/* The speed cap over this interval: piece j's limit and braking for every
 * lower limit within braking reach; b_m is the distance to piece j's end. */
static double s_cap (const uavsim_vehicle_t *self, const s_elem_t *el0, int j0, double b_m,
                     double v_mps, double rem_s)
{
    double cap = el0->lim_mps[j0];
    double reach_m =
        self->vmax_mps * self->vmax_mps / (2 * self->dec_mps2) + self->vmax_mps * rem_s + 1;
    s_elem_t el = *el0;
    int j = j0;
    double d = b_m;
    for (int guard = 0; guard < 3 * self->nlegs + 9; guard++) {
        // Next piece, in this element or the next.
        int nj = j + 1;
        while (nj < 3 && el.seg_m[nj] <= 0)
            nj++;
        if (nj == 3) {
            if (el.end_kind == S_VX_STOP || el.end_kind == S_VX_PIVOT) {
                cap = fmin (cap, s_brake (self, d, 0, v_mps, rem_s));
                break;
            }
            s_elem_t nx;
            if (!s_elem_next (self, &el, &nx))
                break;
            el = nx;
            nj = 0;
            while (nj < 3 && el.seg_m[nj] <= 0)
                nj++;
            if (nj == 3)
                break; // cannot happen: every element has length
        }
        j = nj;
        if (el.lim_mps[j] < cap)
            cap = fmin (cap, s_brake (self, d, el.lim_mps[j], v_mps, rem_s));
        d += el.seg_m[j];
        if (d > reach_m)
            break;
    }
    return cap;
}

/* --- geometry ----------------------------------------------------------------------- */

/* Lateral offset d (left of the leg) and its slope along the leg at xs metres
 * along the straight of el (s_m long); see the header for the construction. */
static void s_dev_eval (const uavsim_vehicle_t *self, const s_elem_t *el, double xs, double *ret_d,
                        double *ret_dd)
{
    *ret_d = 0;
    *ret_dd = 0;
    double s = el->s_m;
    if (self->dev_m <= 0 || s <= 0)
        return;
    const s_leg_t *leg = &self->legs[el->k];
    double v = leg->speed_mps;
    // Curvature the wander may use: half the turn-rate and lateral-acceleration budget.
    double kappa = 0.5 * fmin (self->omega_rps / v, self->lat_mps2 / (v * v));
    double k2 = 0, kmax = 0;
    for (int i = 0; i < S_DEV_WAVES; i++) {
        k2 += self->dev.weight[i] * self->dev.k_rpm[i] * self->dev.k_rpm[i];
        kmax = fmax (kmax, self->dev.k_rpm[i]);
    }
    // Stretch the waves so that they use at most half of that at full amplitude.
    double stretch = fmax (1, sqrt (self->dev_m * k2 / (0.5 * kappa)));
    double ramp = fmin (S_PI * sqrt (2 * self->dev_m / kappa), 0.5 * s);
    // |d''| <= A (|w''| + 2 |w'| |g'| + |g''|) <= A c; choose A so that A c <= kappa.
    double c =
        k2 / (stretch * stretch) + S_PI * S_PI / (2 * ramp * ramp) + S_PI * kmax / (stretch * ramp);
    double amp = fmin (self->dev_m, kappa / c);
    double xi = leg->cum_m + el->t0_m + xs, g = 0, dg = 0;
    for (int i = 0; i < S_DEV_WAVES; i++) {
        double k = self->dev.k_rpm[i] / stretch, ph = k * xi + self->dev.phase_rad[i];
        g += self->dev.weight[i] * sin (ph);
        dg += self->dev.weight[i] * k * cos (ph);
    }
    double w = 1, dw = 0;
    if (xs < ramp) {
        double a = S_PI * xs / ramp;
        w = 0.5 * (1 - cos (a));
        dw = 0.5 * S_PI / ramp * sin (a);
    } else if (xs > s - ramp) {
        double a = S_PI * (s - xs) / ramp;
        w = 0.5 * (1 - cos (a));
        dw = -0.5 * S_PI / ramp * sin (a);
    }
    *ret_d = amp * w * g;
    *ret_dd = amp * (dw * g + w * dg);
}

/* Point phi radians into the arc at v, and the direction there (route order). */
static void s_arc (const s_vertex_t *v, double phi, double *e, double *n, double *te, double *tn)
{
    double a = v->sigma * phi, c = cos (a), s = sin (a);
    *e = v->ce_m + (v->r0e_m * c - v->r0n_m * s);
    *n = v->cn_m + (v->r0e_m * s + v->r0n_m * c);
    *te = v->uie * c - v->uin * s;
    *tn = v->uie * s + v->uin * c;
}

typedef struct {
    double e_m, n_m; // position
    double te, tn;   // unit direction of travel
    double dev_m;    // lateral offset, + left of travel
    double stretch;  // path length per metre of x (>= 1, from the wander)
    bool straight;   // on the straight
} s_pose_t;

/* Where the vehicle is at x metres along el. */
static void s_pose (const uavsim_vehicle_t *self, const s_elem_t *el, double x, s_pose_t *p)
{
    const s_leg_t *leg = &self->legs[el->k];
    const s_vertex_t *v0 = s_vx_at (self, el->k), *v1 = s_vx_at (self, el->k + 1);
    double xf = el->dir > 0 ? x : el->len_m - x;
    double te, tn;
    p->dev_m = 0;
    p->stretch = 1;
    p->straight = false;
    if (xf < el->a0_m) {
        s_arc (v0, 0.5 * v0->theta_rad + xf / v0->r_m, &p->e_m, &p->n_m, &te, &tn);
    } else if (xf <= el->a0_m + el->s_m || el->a1_m <= 0) {
        double xs = fmin (fmax (xf - el->a0_m, 0), el->s_m);
        double q0e = el->t0_m > 0 ? v0->be_m : v0->e_m, q0n = el->t0_m > 0 ? v0->bn_m : v0->n_m;
        double q1e = el->t1_m > 0 ? v1->ae_m : v1->e_m, q1n = el->t1_m > 0 ? v1->an_m : v1->n_m;
        double u = el->s_m > 0 ? xs / el->s_m : 0;
        double d, dd;
        s_dev_eval (self, el, xs, &d, &dd);
        p->e_m = q0e * (1 - u) + q1e * u - d * leg->un;
        p->n_m = q0n * (1 - u) + q1n * u + d * leg->ue;
        double h = sqrt (1 + dd * dd);
        te = (leg->ue - dd * leg->un) / h;
        tn = (leg->un + dd * leg->ue) / h;
        p->dev_m = d * el->dir;
        p->stretch = h;
        p->straight = true;
    } else {
        double phi = fmin ((xf - el->a0_m - el->s_m) / v1->r_m, 0.5 * v1->theta_rad);
        s_arc (v1, phi, &p->e_m, &p->n_m, &te, &tn);
    }
    p->te = te * el->dir;
    p->tn = tn * el->dir;
}

static double s_wrap_rad (double a)
{
    a = fmod (a, 2 * S_PI);
    return a < 0 ? a + 2 * S_PI : a;
}

static void s_update_out (uavsim_vehicle_t *self)
{
    s_elem_t el;
    s_elem (self, self->k, self->dir, self->lap, &el);
    s_pose_t p;
    s_pose (self, &el, self->x_m, &p);
    bool halted = self->phase == S_HALT;
    if (self->phase != S_PIVOT && !halted)
        self->heading_rad = s_wrap_rad (atan2 (p.te, p.tn));
    uavsim_vehicle_state_t *o = &self->out;
    o->e_m = p.e_m;
    o->n_m = p.n_m;
    o->speed_mps = self->v_mps;
    if (halted) { // standing still, facing the way it came
        o->ve_mps = 0;
        o->vn_mps = 0;
    } else if (self->phase == S_PIVOT) {
        o->ve_mps = self->v_mps * sin (self->heading_rad);
        o->vn_mps = self->v_mps * cos (self->heading_rad);
    } else { // (te, tn) is the unit direction the heading was taken from
        o->ve_mps = self->v_mps * p.te;
        o->vn_mps = self->v_mps * p.tn;
    }
    double deg = self->heading_rad / S_DEG;
    o->heading_deg = deg >= 360 ? deg - 360 : deg;
    o->dev_m = p.dev_m;
    o->active = self->phase != S_WAIT;
    o->finished = self->phase == S_DONE;
    o->turning_in_place = self->phase == S_PIVOT;
    o->leg = self->k;
    o->next_point = self->dir > 0 ? (self->k + 1) % self->npts : self->k;
    o->direction = self->dir;
    o->lap = self->lap;
    o->halted = halted;
    o->halt_left_s = halted ? self->halt_left_s : 0;
}

/* --- motion --------------------------------------------------------------------------- */

/* The point element el starts from when driven its way. */
static const s_vertex_t *s_elem_start (const uavsim_vehicle_t *self, const s_elem_t *el)
{
    return s_vx_at (self, el->dir > 0 ? el->k : el->k + 1);
}

/* At the end of the current element: stop, halt, turn in place, or drive on. */
static void s_arrive (uavsim_vehicle_t *self, const s_elem_t *el)
{
    s_elem_t nx;
    if (!s_elem_next (self, el, &nx)) {
        self->phase = S_DONE;
        self->x_m = el->len_m;
        self->v_mps = 0;
        return;
    }
    if (nx.lap != self->lap)
        s_dev_draw (self);
    self->k = nx.k;
    self->dir = nx.dir;
    self->lap = nx.lap;
    self->x_m = 0;
    if (el->end_kind != S_VX_PIVOT)
        return;
    // Turn in place from the leg driven in to the leg driven out, the short way
    // (clockwise when it is exactly about).
    const s_leg_t *a = &self->legs[el->k], *b = &self->legs[nx.k];
    double from = atan2 (a->ue * el->dir, a->un * el->dir);
    double to = atan2 (b->ue * nx.dir, b->un * nx.dir);
    double turn = remainder (to - from, 2 * S_PI);
    if (fabs (turn) > S_PI - 1e-9)
        turn = S_PI;
    self->v_mps = 0;
    self->heading_rad = s_wrap_rad (from);
    self->pivot_rad = turn;
    self->phase = S_PIVOT;
    // A halt comes first; the turn in place waits for its end.
    double halt_s = s_elem_start (self, &nx)->halt_s;
    if (halt_s > 0) {
        self->halt_left_s = halt_s;
        self->phase = S_HALT;
    }
}

/* Stand for up to rem_s of the halt; returns the time left over. */
static double s_halt (uavsim_vehicle_t *self, double rem_s)
{
    if (self->halt_left_s <= rem_s) {
        rem_s -= self->halt_left_s;
        self->halt_left_s = 0;
        self->phase = S_PIVOT; // then the turn in place (perhaps none) to the next leg
        return rem_s;
    }
    self->halt_left_s -= rem_s;
    return 0;
}

/* Turn in place for up to rem_s; returns the time left over. */
static double s_pivot (uavsim_vehicle_t *self, double rem_s)
{
    double need_s = fabs (self->pivot_rad) / self->omega_rps;
    if (need_s <= rem_s) {
        self->heading_rad = s_wrap_rad (self->heading_rad + self->pivot_rad);
        self->pivot_rad = 0;
        self->phase = S_DRIVE;
        return rem_s - need_s;
    }
    double turn = copysign (self->omega_rps * rem_s, self->pivot_rad);
    self->heading_rad = s_wrap_rad (self->heading_rad + turn);
    self->pivot_rad -= turn;
    return 0;
}

/* Drive for rem_s: each pass moves to the end of the current piece or to the
 * end of the interval, with the speed changing linearly in between. */
static void s_drive (uavsim_vehicle_t *self, double rem_s)
{
    for (int guard = 0; rem_s > 1e-9 && guard < 100000; guard++) {
        if (self->phase == S_HALT) {
            rem_s = s_halt (self, rem_s);
            continue;
        }
        if (self->phase == S_PIVOT) {
            rem_s = s_pivot (self, rem_s);
            continue;
        }
        if (self->phase != S_DRIVE)
            break;
        s_elem_t el;
        s_elem (self, self->k, self->dir, self->lap, &el);
        int j = -1;
        double end = 0;
        for (int i = 0; i < 3; i++) {
            if (el.seg_m[i] <= 0)
                continue;
            end += el.seg_m[i];
            if (self->x_m < end) {
                j = i;
                break;
            }
        }
        if (j < 0) {
            s_arrive (self, &el);
            continue;
        }
        double b = end - self->x_m, v = self->v_mps;
        double cap = s_cap (self, &el, j, b, v, rem_s);
        double v1 = fmin (v + self->acc_mps2 * rem_s, cap);
        // Reaching the cap by accelerating: stop the interval there, so the
        // speed is exact (the cap for a shorter interval is no lower).
        double tau = rem_s;
        if (v1 > v && v1 < v + self->acc_mps2 * rem_s)
            tau = fmin (rem_s, (v1 - v) / self->acc_mps2);
        double stretch = 1;
        if (el.seg_kind[j] == 1 && self->dev_m > 0) {
            s_pose_t p;
            s_pose (self, &el, self->x_m, &p);
            stretch = p.stretch;
        }
        double ds = 0.5 * (v + v1) * tau; // path length this interval
        if (ds >= b * stretch) {
            // Reach the end of the piece, no faster than the next piece allows.
            double a = (v1 - v) / tau;
            double vb = sqrt (fmax (0, v * v + 2 * a * b * stretch));
            vb = fmin (vb, s_lim_after (self, &el, j));
            double tb = v + vb > 0 ? 2 * b * stretch / (v + vb) : 0;
            self->x_m = end;
            self->v_mps = vb;
            rem_s -= fmin (tb, tau);
        } else {
            self->x_m += ds / stretch;
            self->v_mps = v1;
            rem_s -= tau;
        }
    }
    // Settle an arrival at the element's end reached exactly at the interval's end.
    if (self->phase == S_DRIVE) {
        s_elem_t el;
        s_elem (self, self->k, self->dir, self->lap, &el);
        if (self->x_m >= el.len_m)
            s_arrive (self, &el);
    }
}

int uavsim_vehicle_step (uavsim_vehicle_t *self, double t_s, double dt_s)
{
    assert (self);
    if (!isfinite (t_s) || !isfinite (dt_s) || dt_s <= 0)
        return -EINVAL;
    double rem_s = dt_s;
    if (self->phase == S_WAIT) {
        double t1 = t_s + dt_s;
        if (t1 <= self->start_time_s)
            return 0;
        if (t_s < self->start_time_s)
            rem_s = t1 - self->start_time_s;
        self->phase = S_DRIVE;
    }
    s_drive (self, rem_s);
    s_update_out (self);
    return 0;
}

void uavsim_vehicle_state (const uavsim_vehicle_t *self, uavsim_vehicle_state_t *ret_s)
{
    assert (self && ret_s);
    *ret_s = self->out;
}

/* --- terrain ---------------------------------------------------------------------------- */

void uavsim_vehicle_ground (const cgs_terrain_t *terrain, const uavsim_vehicle_state_t *s,
                            uavsim_vehicle_ground_t *ret_g)
{
    assert (terrain && s && ret_g);
    cgs_enu_t nrm = cgs_terrain_normal (terrain, s->e_m, s->n_m);
    double dh_de = -nrm.e_m / nrm.u_m, dh_dn = -nrm.n_m / nrm.u_m;
    double psi = s->heading_deg * S_DEG, se = sin (psi), ce = cos (psi);
    double slope = dh_de * se + dh_dn * ce; // rise per metre along the heading
    double h = sqrt (1 + slope * slope);
    double fe = se / h, fn = ce / h;
    ret_g->up_m = cgs_terrain_height_clamped (terrain, s->e_m, s->n_m);
    ret_g->vu_mps = dh_de * s->ve_mps + dh_dn * s->vn_mps;
    ret_g->pitch_deg = atan (slope) / S_DEG;
    // Body axes: x along the surface at the heading, z down the normal; then
    // sin(roll) cos(pitch) = (normal x forward) . up, cos(roll) cos(pitch) = normal . up.
    ret_g->roll_deg = atan2 (nrm.e_m * fn - nrm.n_m * fe, nrm.u_m) / S_DEG;
}

/* --- checkpoint --------------------------------------------------------------------------- */

/* A cgs_ckpt frame "UVHC", version 1. Payload: fingerprint u64, phase u32,
 * direction i32, element u32, lap u64, x f64, speed f64, heading f64, turn
 * left f64, generator 4 x u64, wander 3 x (wavenumber, phase, weight) f64,
 * halt left f64: 172 bytes. */
int uavsim_vehicle_save (const uavsim_vehicle_t *self, uint8_t **ret_buf, size_t *ret_len)
{
    cgs_ckpt_writer_t w;
    cgs_ckpt_writer_init (&w, S_SAVE_MAGIC, S_SAVE_VERSION);
    cgs_ckpt_put_u64 (&w, self->fingerprint);
    cgs_ckpt_put_u32 (&w, (uint32_t)self->phase);
    cgs_ckpt_put_u32 (&w, (uint32_t)self->dir);
    cgs_ckpt_put_u32 (&w, (uint32_t)self->k);
    cgs_ckpt_put_u64 (&w, self->lap);
    cgs_ckpt_put_f64 (&w, self->x_m);
    cgs_ckpt_put_f64 (&w, self->v_mps);
    cgs_ckpt_put_f64 (&w, self->heading_rad);
    cgs_ckpt_put_f64 (&w, self->pivot_rad);
    for (int i = 0; i < 4; i++)
        cgs_ckpt_put_u64 (&w, self->rng[i]);
    for (int i = 0; i < S_DEV_WAVES; i++) {
        cgs_ckpt_put_f64 (&w, self->dev.k_rpm[i]);
        cgs_ckpt_put_f64 (&w, self->dev.phase_rad[i]);
        cgs_ckpt_put_f64 (&w, self->dev.weight[i]);
    }
    cgs_ckpt_put_f64 (&w, self->halt_left_s);
    return cgs_ckpt_writer_finish (&w, ret_buf, ret_len);
}

static bool s_in (double x, double lo, double hi)
{
    return isfinite (x) && x >= lo && x <= hi;
}

/* Whether the decoded state t (a copy of self, given its phase, direction
 * and element here) is one this vehicle can be in. */
static bool s_restorable (const uavsim_vehicle_t *self, uavsim_vehicle_t *t, uint32_t phase,
                          int32_t dir, uint32_t k)
{
    double wsum = 0;
    for (int i = 0; i < S_DEV_WAVES; i++) {
        if (!s_in (t->dev.k_rpm[i], 2 * S_PI / S_DEV_MAX_WAVE_M * (1 - 1e-12),
                   2 * S_PI / S_DEV_MIN_WAVE_M * (1 + 1e-12)) ||
            !s_in (t->dev.phase_rad[i], 0, 2 * S_PI) || !s_in (t->dev.weight[i], 0, 1))
            return false;
        wsum += t->dev.weight[i];
    }
    if (phase > S_HALT || (dir != 1 && dir != -1) || k >= (uint32_t)self->nlegs)
        return false;
    if (dir < 0 && self->end != UAVSIM_VEHICLE_END_REVERSE)
        return false;
    if (fabs (wsum - 1) > 1e-9 || (t->rng[0] | t->rng[1] | t->rng[2] | t->rng[3]) == 0)
        return false;
    t->phase = (s_phase_t)phase;
    t->dir = dir;
    t->k = (int)k;
    s_elem_t el;
    s_elem (t, t->k, t->dir, t->lap, &el);
    if (!s_in (t->x_m, 0, el.len_m) || !s_in (t->v_mps, 0, self->vmax_mps) ||
        !s_in (t->heading_rad, 0, 2 * S_PI) || !s_in (t->pivot_rad, -S_PI, S_PI))
        return false;
    if (t->phase == S_WAIT &&
        (t->k != 0 || t->dir != 1 || t->lap != 0 || t->x_m != 0 || t->v_mps != 0))
        return false;
    if (t->phase == S_DONE && (self->end != UAVSIM_VEHICLE_END_STOP || t->v_mps != 0))
        return false;
    if (t->phase == S_PIVOT && t->v_mps != 0)
        return false;
    // A halt: standing at the start of its element, on a point that halts,
    // for no longer than that point's halt.
    if (t->phase == S_HALT) {
        double halt_s = s_elem_start (t, &el)->halt_s;
        if (halt_s <= 0 || t->v_mps != 0 || t->x_m != 0 || !(t->halt_left_s > 0) ||
            !s_in (t->halt_left_s, 0, halt_s))
            return false;
    } else if (t->halt_left_s != 0)
        return false;
    return true;
}

int uavsim_vehicle_restore (uavsim_vehicle_t *self, const void *buf, size_t len, char *err,
                            size_t errlen)
{
    cgs_ckpt_reader_t r;
    int rc = cgs_ckpt_open (&r, buf, len, S_SAVE_MAGIC, S_SAVE_VERSION, S_SAVE_WHAT, err, errlen);
    if (rc < 0)
        return rc;
    if (cgs_ckpt_get_u64 (&r) != self->fingerprint) {
        cgs_errf (err, errlen, "a %s of another vehicle (its route or parameters differ)",
                  S_SAVE_WHAT);
        return -EPROTO;
    }
    uavsim_vehicle_t t = *self; // decoded into a copy; self untouched on failure
    uint32_t phase = cgs_ckpt_get_u32 (&r);
    int32_t dir = (int32_t)cgs_ckpt_get_u32 (&r);
    uint32_t k = cgs_ckpt_get_u32 (&r);
    t.lap = cgs_ckpt_get_u64 (&r);
    t.x_m = cgs_ckpt_get_f64 (&r);
    t.v_mps = cgs_ckpt_get_f64 (&r);
    t.heading_rad = cgs_ckpt_get_f64 (&r);
    t.pivot_rad = cgs_ckpt_get_f64 (&r);
    for (int i = 0; i < 4; i++)
        t.rng[i] = cgs_ckpt_get_u64 (&r);
    for (int i = 0; i < S_DEV_WAVES; i++) {
        t.dev.k_rpm[i] = cgs_ckpt_get_f64 (&r);
        t.dev.phase_rad[i] = cgs_ckpt_get_f64 (&r);
        t.dev.weight[i] = cgs_ckpt_get_f64 (&r);
    }
    t.halt_left_s = cgs_ckpt_get_f64 (&r);
    if ((rc = cgs_ckpt_end (&r, S_SAVE_WHAT, err, errlen)) < 0)
        return rc;
    if (!s_restorable (self, &t, phase, dir, k)) {
        cgs_errf (err, errlen, "a %s with a state no vehicle on this route can be in", S_SAVE_WHAT);
        return -EINVAL;
    }
    *self = t;
    s_update_out (self);
    return 0;
}
