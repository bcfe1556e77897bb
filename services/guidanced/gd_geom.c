/* gd_geom — intercept geometry, Dubins paths and the sensor footprint. */
#include "gd_geom.h"
#include "cgs_camera.h"

#include <errno.h>
#include <float.h>
#include <math.h>

#define S_PI             3.14159265358979323846
#define S_TWO_PI         (2.0 * S_PI)
#define S_DEG            (S_PI / 180.0)
#define S_ITER_MAX       200 // fixed-point iterations of t_pred
#define S_T_TOL_S        1e-6
#define S_ROUTE_TOL_S    0.5 // the route's time and t_pred agree this closely
#define S_ROUTE_ITER_MAX 100 // steps of the route timing before it is given up
#define S_ROUTE_T_MAX_S  1e5 // a t_pred beyond this is divergence

/* ---- vectors ------------------------------------------------------------------------ */

gd_v2_t gd_v2 (double e, double n)
{
    gd_v2_t v = {e, n};
    return v;
}

gd_v2_t gd_add (gd_v2_t a, gd_v2_t b)
{
    return gd_v2 (a.e + b.e, a.n + b.n);
}

gd_v2_t gd_sub (gd_v2_t a, gd_v2_t b)
{
    return gd_v2 (a.e - b.e, a.n - b.n);
}

gd_v2_t gd_scale (gd_v2_t a, double k)
{
    return gd_v2 (a.e * k, a.n * k);
}

double gd_dot (gd_v2_t a, gd_v2_t b)
{
    return a.e * b.e + a.n * b.n;
}

double gd_cross (gd_v2_t a, gd_v2_t b)
{
    return a.e * b.n - a.n * b.e;
}

double gd_norm (gd_v2_t a)
{
    return hypot (a.e, a.n);
}

gd_v2_t gd_heading_unit (double heading_deg)
{
    return gd_v2 (sin (heading_deg * S_DEG), cos (heading_deg * S_DEG));
}

double gd_heading_of (gd_v2_t v)
{
    double h = atan2 (v.e, v.n) / S_DEG;
    if (h < 0)
        h += 360.0;
    return h >= 360.0 ? 0.0 : h;
}

double gd_heading_diff (double a_deg, double b_deg)
{
    double d = fmod (b_deg - a_deg, 360.0);
    if (d <= -180.0)
        d += 360.0;
    else if (d > 180.0)
        d -= 360.0;
    return d;
}

static double s_mod2pi (double a)
{
    double m = fmod (a, S_TWO_PI);
    return m < 0 ? m + S_TWO_PI : m;
}

static bool s_finite2 (gd_v2_t v)
{
    return isfinite (v.e) && isfinite (v.n);
}

/* ---- the arc that joins the UAV to a point ----------------------------------------- */

/* Length of a turn of side `left` from (p, math angle th) with radius r, then
 * the tangent to q; INFINITY when q lies inside that turn circle. */
static double s_turn_then_straight (gd_v2_t p, double th, double r, gd_v2_t q, bool left)
{
    // Centre of the turn: left of the velocity for an anticlockwise turn.
    double sgn = left ? 1.0 : -1.0;
    gd_v2_t c = gd_v2 (p.e - sgn * r * sin (th), p.n + sgn * r * cos (th));
    gd_v2_t v = gd_sub (q, c);
    double dist = gd_norm (v);
    if (dist < r * (1 - 1e-9))
        return INFINITY; // inside the circle (a point on it, within rounding, is reached by the
                         // arc)
    double tangent = sqrt (fmax (0.0, dist * dist - r * r));
    double ang_v = atan2 (v.n, v.e);
    // Exit direction u: q − c = r·(u turned towards the centre's opposite) + T·u.
    double ang_u = ang_v + sgn * atan2 (r, tangent);
    double turn = left ? s_mod2pi (ang_u - th) : s_mod2pi (th - ang_u);
    if (turn > S_TWO_PI - 1e-9)
        turn = 0; // already heading at it
    return r * turn + tangent;
}

double gd_arc_length (gd_v2_t p, double heading_deg, double r_m, gd_v2_t q)
{
    double th = (90.0 - heading_deg) * S_DEG;
    double l = s_turn_then_straight (p, th, r_m, q, true);
    double r = s_turn_then_straight (p, th, r_m, q, false);
    double best = fmin (l, r);
    if (isfinite (best))
        return best;
    // Inside both circles: away and around.
    return S_TWO_PI * r_m + gd_norm (gd_sub (q, p));
}

/* ---- waypoint initialisation --------------------------------------------------------- */

void gd_to_target_frame (gd_v2_t o, gd_v2_t dir, gd_v2_t q, double *ret_x, double *ret_y)
{
    gd_v2_t d = gd_sub (q, o);
    *ret_x = dir.n * d.e - dir.e * d.n;
    *ret_y = dir.e * d.e + dir.n * d.n;
}

gd_v2_t gd_secondary_point (const gd_engage_t *in, gd_v2_t waypoint, gd_v2_t dir)
{
    double x, y;
    gd_to_target_frame (waypoint, dir, in->uav, &x, &y);
    if (in->offset_max_m > 0) // abeam, but no farther than this from the target's line
        x = fmax (-in->offset_max_m, fmin (x, in->offset_max_m));
    gd_v2_t right = gd_v2 (dir.n, -dir.e);
    if (in->secondary_paper) // Δ = Rᵀ diag(1, 0) R: the cross-track projection
        return gd_add (waypoint, gd_scale (right, x));
    // Δ = Rᵀ diag(1, −k) R, at least the lead-in ahead
    double y2 = fmax (in->secondary_scale * -y, in->lead_in_m);
    return gd_add (waypoint, gd_add (gd_scale (right, x), gd_scale (dir, y2)));
}

int gd_waypoint (const gd_engage_t *in, gd_waypoint_t *ret)
{
    if (!in || !ret || !s_finite2 (in->uav) || !s_finite2 (in->target) ||
        !s_finite2 (in->target_vel) || !isfinite (in->uav_heading_deg))
        return -EINVAL;
    double vt = gd_norm (in->target_vel);
    double s = in->uav_speed_mps;
    if (!(s > vt) || !isfinite (s) || !(in->turn_radius_m > 0) || !isfinite (in->turn_radius_m) ||
        !(in->agl_m > 0) || !isfinite (in->agl_m) ||
        !(in->depression_deg > 0 && in->depression_deg < 90) || !(in->secondary_scale >= 0) ||
        !isfinite (in->secondary_scale) || !(in->lead_in_m >= 0) || !isfinite (in->lead_in_m) ||
        !(in->settle_m >= 0) || !isfinite (in->settle_m) || !(in->horizon_s >= 0))
        return -EINVAL;
    gd_waypoint_t w = {0};
    w.lookahead_m = in->agl_m / tan (in->depression_deg * S_DEG);
    if (vt > 0) {
        w.dir = gd_scale (in->target_vel, 1.0 / vt);
    } else { // standing still: come in along the line from the UAV
        gd_v2_t away = gd_sub (in->uav, in->target);
        double d = gd_norm (away);
        w.dir = d > 0 ? gd_scale (away, 1.0 / d) : gd_v2 (0, 1);
    }
    // t_pred: fixed point of t = L(P_T + V_T·t) / s_ug.
    double t = gd_arc_length (in->uav, in->uav_heading_deg, in->turn_radius_m, in->target) / s;
    double prev = t;
    int k = 0;
    for (k = 1; k <= S_ITER_MAX; k++) {
        gd_v2_t q = gd_add (in->target, gd_scale (in->target_vel, t));
        double next = gd_arc_length (in->uav, in->uav_heading_deg, in->turn_radius_m, q) / s;
        prev = t;
        t = next;
        if (fabs (t - prev) <= S_T_TOL_S * (1.0 + t))
            break;
    }
    if (k > S_ITER_MAX)
        t = fmax (t, prev); // oscillating about a jump of the arc (a side switch): the later
    if (isfinite (in->min_t_pred_s) && t < in->min_t_pred_s)
        t = in->min_t_pred_s;
    bool limited = in->horizon_s > 0 && t > in->horizon_s;
    if (limited)
        t = in->horizon_s;
    if (!isfinite (t))
        return -EINVAL;
    w.t_pred_s = t;
    w.limited = limited;
    w.iterations = k > S_ITER_MAX ? S_ITER_MAX : k;
    w.meet = gd_add (in->target, gd_scale (in->target_vel, t));
    w.waypoint = gd_add (w.meet, gd_scale (w.dir, w.lookahead_m));       // equation 1
    gd_to_target_frame (w.waypoint, w.dir, in->uav, &w.x_u_m, &w.y_u_m); // equation 2
    w.secondary = !(w.y_u_m > 0);
    if (w.secondary)
        w.second = gd_secondary_point (in, w.waypoint, w.dir);
    // The straight run into the waypoint: at most half the way from P_2 (or
    // from a UAV ahead of the waypoint) to it, so the last turn has room.
    double room = w.secondary ? gd_norm (gd_sub (w.second, w.waypoint)) : w.y_u_m;
    w.settle_m = fmax (0.0, fmin (in->settle_m, 0.5 * room));
    *ret = w;
    return 0;
}

void gd_waypoint_headings (const gd_waypoint_t *w, double *ret_second_deg, double *ret_final_deg)
{
    double h_final = gd_heading_of (gd_scale (w->dir, -1.0));
    gd_v2_t to_wp = gd_sub (w->waypoint, w->second);
    *ret_final_deg = h_final;
    *ret_second_deg = gd_norm (to_wp) > 1 ? gd_heading_of (to_wp) : h_final;
}

double gd_route_length (const gd_engage_t *in, const gd_waypoint_t *w)
{
    double h2, hf;
    gd_waypoint_headings (w, &h2, &hf);
    gd_dubins_t d;
    double len = 0;
    gd_v2_t from = in->uav;
    double h = in->uav_heading_deg;
    if (w->secondary) {
        if (gd_dubins (from, h, w->second, h2, in->turn_radius_m, &d) < 0)
            return NAN;
        len += gd_dubins_length (&d);
        from = w->second;
        h = h2;
    }
    if (gd_dubins (from, h, gd_waypoint_settle_point (w), hf, in->turn_radius_m, &d) < 0)
        return NAN;
    return len + gd_dubins_length (&d) + w->settle_m;
}

gd_v2_t gd_waypoint_settle_point (const gd_waypoint_t *w)
{
    return gd_add (w->waypoint, gd_scale (w->dir, w->settle_m));
}

int gd_waypoint_flyable (const gd_engage_t *in, gd_waypoint_t *ret)
{
    if (!ret)
        return -EINVAL;
    gd_waypoint_t w0;
    int rc = gd_waypoint (in, &w0);
    if (rc < 0)
        return rc;
    gd_engage_t e = *in;
    gd_waypoint_t w = w0;
    double len0 = gd_route_length (&e, &w0), len = len0;
    bool settled = !isfinite (len);
    for (int k = 0; k < S_ROUTE_ITER_MAX && !settled; k++) {
        double t = len / in->uav_speed_mps;
        if (t <= w.t_pred_s + S_ROUTE_TOL_S) {
            settled = true;
            break;
        }
        e.min_t_pred_s = t;
        if (t > S_ROUTE_T_MAX_S || gd_waypoint (&e, &w) < 0)
            break;
        len = gd_route_length (&e, &w);
        settled = !isfinite (len) || w.limited; // the horizon: no later waypoint
    }
    if (!settled || !isfinite (len)) { // no fixed point: equation 1's plan
        w = w0;
        len = len0;
    }
    w.route_m = isfinite (len) ? len : 0;
    *ret = w;
    return 0;
}

gd_v2_t gd_precision_step (gd_v2_t p, gd_v2_t target, gd_v2_t uv, double speed_mps, double dt_s)
{
    double along = gd_dot (gd_sub (p, target), uv);
    gd_v2_t on_line = gd_add (target, gd_scale (uv, along));
    return gd_sub (on_line, gd_scale (uv, speed_mps * dt_s));
}

/* ---- Dubins paths -------------------------------------------------------------------- */

/* Segment kinds of each word: 'L' anticlockwise, 'R' clockwise, 'S' straight. */
static const char *const s_words[6] = {"LSL", "LSR", "RSL", "RSR", "RLR", "LRL"};

/* Normalised lengths (t, p, q) of word w for the standard form (d, alpha,
 * beta); false when the word does not exist for this geometry. */
static bool s_word (int w, double d, double a, double b, double out[3])
{
    double sa = sin (a), sb = sin (b), ca = cos (a), cb = cos (b), cab = cos (a - b);
    double p2, tmp, t, p, q;
    switch (w) {
    case GD_LSL:
        p2 = 2 + d * d - 2 * cab + 2 * d * (sa - sb);
        if (p2 < 0)
            return false;
        tmp = atan2 (cb - ca, d + sa - sb);
        t = s_mod2pi (tmp - a);
        p = sqrt (p2);
        q = s_mod2pi (b - tmp);
        break;
    case GD_RSR:
        p2 = 2 + d * d - 2 * cab + 2 * d * (sb - sa);
        if (p2 < 0)
            return false;
        tmp = atan2 (ca - cb, d - sa + sb);
        t = s_mod2pi (a - tmp);
        p = sqrt (p2);
        q = s_mod2pi (tmp - b);
        break;
    case GD_LSR:
        p2 = -2 + d * d + 2 * cab + 2 * d * (sa + sb);
        if (p2 < 0)
            return false;
        p = sqrt (p2);
        tmp = atan2 (-ca - cb, d + sa + sb) - atan2 (-2.0, p);
        t = s_mod2pi (tmp - a);
        q = s_mod2pi (tmp - b);
        break;
    case GD_RSL:
        p2 = -2 + d * d + 2 * cab - 2 * d * (sa + sb);
        if (p2 < 0)
            return false;
        p = sqrt (p2);
        tmp = atan2 (ca + cb, d - sa - sb) - atan2 (2.0, p);
        t = s_mod2pi (a - tmp);
        q = s_mod2pi (b - tmp);
        break;
    case GD_RLR:
        tmp = (6 - d * d + 2 * cab + 2 * d * (sa - sb)) / 8;
        if (fabs (tmp) > 1)
            return false;
        p = s_mod2pi (S_TWO_PI - acos (tmp));
        t = s_mod2pi (a - atan2 (ca - cb, d - sa + sb) + p / 2);
        q = s_mod2pi (a - b - t + p);
        break;
    default: // GD_LRL
        tmp = (6 - d * d + 2 * cab + 2 * d * (sb - sa)) / 8;
        if (fabs (tmp) > 1)
            return false;
        p = s_mod2pi (S_TWO_PI - acos (tmp));
        t = s_mod2pi (-a - atan2 (ca - cb, d + sa - sb) + p / 2);
        q = s_mod2pi (b - a - t + p);
        break;
    }
    out[0] = t;
    out[1] = p;
    out[2] = q;
    return true;
}

/* Move (x, y, th) (math angle) along a segment of kind k for length s. */
static void s_move (char k, double r, double s, double *x, double *y, double *th)
{
    if (k == 'S') {
        *x += s * cos (*th);
        *y += s * sin (*th);
        return;
    }
    double phi = s / r;
    if (k == 'L') {
        *x += r * (sin (*th + phi) - sin (*th));
        *y += r * (cos (*th) - cos (*th + phi));
        *th += phi;
    } else {
        *x += r * (sin (*th) - sin (*th - phi));
        *y += r * (cos (*th - phi) - cos (*th));
        *th -= phi;
    }
}

static void s_end (gd_v2_t p0, double h0_deg, int w, double r, const double len[3], gd_v2_t *ret_p,
                   double *ret_th)
{
    double x = p0.e, y = p0.n, th = (90.0 - h0_deg) * S_DEG;
    for (int i = 0; i < 3; i++)
        s_move (s_words[w][i], r, len[i], &x, &y, &th);
    *ret_p = gd_v2 (x, y);
    *ret_th = th;
}

int gd_dubins (gd_v2_t p0, double h0_deg, gd_v2_t p1, double h1_deg, double r_m, gd_dubins_t *ret)
{
    if (!ret || !s_finite2 (p0) || !s_finite2 (p1) || !isfinite (h0_deg) || !isfinite (h1_deg) ||
        !(r_m > 0) || !isfinite (r_m))
        return -EINVAL;
    double dx = p1.e - p0.e, dy = p1.n - p0.n;
    double d = hypot (dx, dy) / r_m;
    double th0 = (90.0 - h0_deg) * S_DEG, th1 = (90.0 - h1_deg) * S_DEG;
    // Same place: measure the angles from the start heading, so the same
    // pose gives the empty path exactly.
    double phi = d > 1e-12 ? atan2 (dy, dx) : th0;
    double a = s_mod2pi (th0 - phi), b = s_mod2pi (th1 - phi);
    double best = INFINITY;
    int best_w = -1;
    double best_len[3] = {0, 0, 0};
    double tol = 1e-6 * (1.0 + hypot (dx, dy));
    for (int w = 0; w < 6; w++) {
        double n[3];
        if (!s_word (w, d, a, b, n))
            continue;
        double len[3] = {n[0] * r_m, n[1] * r_m, n[2] * r_m};
        double total = len[0] + len[1] + len[2];
        if (!(total < best))
            continue;
        // Keep only a word that really ends at the goal with the goal's heading.
        gd_v2_t e;
        double th;
        s_end (p0, h0_deg, w, r_m, len, &e, &th);
        double dh = fabs (remainder (th - th1, S_TWO_PI));
        if (gd_norm (gd_sub (e, p1)) > tol + 1e-6 * r_m || dh > 1e-6)
            continue;
        best = total;
        best_w = w;
        for (int i = 0; i < 3; i++)
            best_len[i] = len[i];
    }
    if (best_w < 0)
        return -EINVAL;
    gd_dubins_t out = {p0, h0_deg, r_m, (gd_dubins_word_t)best_w, {0, 0, 0}};
    for (int i = 0; i < 3; i++)
        out.len[i] = best_len[i];
    *ret = out;
    return 0;
}

double gd_dubins_length (const gd_dubins_t *d)
{
    return d->len[0] + d->len[1] + d->len[2];
}

void gd_dubins_at (const gd_dubins_t *d, double s, gd_v2_t *ret_p, double *ret_h_deg)
{
    double x = d->p0.e, y = d->p0.n, th = (90.0 - d->h0_deg) * S_DEG;
    double left = fmax (0.0, s);
    for (int i = 0; i < 3 && left > 0; i++) {
        double step = fmin (left, d->len[i]);
        s_move (s_words[d->word][i], d->r_m, step, &x, &y, &th);
        left -= step;
    }
    *ret_p = gd_v2 (x, y);
    double h = 90.0 - th / S_DEG;
    h = fmod (h, 360.0);
    *ret_h_deg = h < 0 ? h + 360.0 : h;
}

size_t gd_dubins_sample (const gd_dubins_t *d, double step_deg, gd_v2_t *out, size_t max)
{
    if (max == 0)
        return 0;
    size_t n = 0;
    double s0 = 0;
    double step = (step_deg > 0 ? step_deg : 10.0) * S_DEG * d->r_m;
    for (int i = 0; i < 3; i++) {
        double len = d->len[i];
        if (len <= 1e-9)
            continue;
        size_t parts = 1;
        if (s_words[d->word][i] != 'S')
            parts = (size_t)fmax (2.0, ceil (len / step));
        for (size_t k = 1; k <= parts; k++) {
            gd_v2_t p;
            double h;
            gd_dubins_at (d, s0 + len * (double)k / (double)parts, &p, &h);
            out[n < max ? n : max - 1] = p; // when full, the last slot keeps the latest
            if (n < max)
                n++;
        }
        s0 += len;
    }
    if (n == 0) { // a path of length zero: its end is its start
        out[0] = d->p0;
        n = 1;
    }
    return n;
}

/* ---- footprint ----------------------------------------------------------------------- */

int gd_footprint (const gd_sensor_t *s, const cgs_terrain_t *terrain, gd_footprint_t *ret)
{
    if (!s || !ret || !(s->max_range_m > 0))
        return -EINVAL;
    // The pixel size does not matter to the footprint: the corner rays are
    // the image's corners whatever its size.
    cgs_camera_in_t in = {
        .position = s->position,
        .heading_deg = s->heading_deg,
        .pitch_deg = s->pitch_deg,
        .roll_deg = s->roll_deg,
        .depression_deg = s->depression_deg,
        .hfov_deg = s->hfov_deg,
        .vfov_deg = s->vfov_deg,
        .width_px = 640,
        .height_px = 480,
        .near_m = 1,
        .far_m = fmax (2, s->max_range_m),
        .point = s->point,
    };
    cgs_camera_t cam;
    int rc = cgs_camera_make (&in, &cam);
    if (rc < 0)
        return rc;
    cgs_camera_footprint (&cam, terrain, s->max_range_m, ret);
    return 0;
}
