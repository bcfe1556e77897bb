/* cgs_camera — the imaging sensor as a pinhole camera (see cgs_camera.h). */
#include "cgs_camera.h"

#include <errno.h>
#include <math.h>

#define S_DEG (M_PI / 180.0)

static cgs_enu_t s_v (double e, double n, double u)
{
    return (cgs_enu_t){e, n, u};
}

static cgs_enu_t s_comb (double a, cgs_enu_t x, double b, cgs_enu_t y)
{
    return s_v (a * x.e_m + b * y.e_m, a * x.n_m + b * y.n_m, a * x.u_m + b * y.u_m);
}

static double s_dot (cgs_enu_t a, cgs_enu_t b)
{
    return a.e_m * b.e_m + a.n_m * b.n_m + a.u_m * b.u_m;
}

static cgs_enu_t s_cross (cgs_enu_t a, cgs_enu_t b)
{
    return s_v (a.n_m * b.u_m - a.u_m * b.n_m, a.u_m * b.e_m - a.e_m * b.u_m,
                a.e_m * b.n_m - a.n_m * b.e_m);
}

static cgs_enu_t s_unit (cgs_enu_t a)
{
    double l = sqrt (s_dot (a, a));
    return l > 0 ? s_v (a.e_m / l, a.n_m / l, a.u_m / l) : a;
}

static void s_matrices (cgs_camera_t *c)
{
    // View: rows right, up, −forward; the eye at the origin.
    const cgs_enu_t r = c->right, u = c->up, f = c->forward, e = c->eye;
    float *v = c->view;
    v[0] = (float)r.e_m, v[4] = (float)r.n_m, v[8] = (float)r.u_m;
    v[1] = (float)u.e_m, v[5] = (float)u.n_m, v[9] = (float)u.u_m;
    v[2] = (float)-f.e_m, v[6] = (float)-f.n_m, v[10] = (float)-f.u_m;
    v[3] = v[7] = v[11] = 0.0f;
    v[12] = (float)-s_dot (r, e);
    v[13] = (float)-s_dot (u, e);
    v[14] = (float)s_dot (f, e);
    v[15] = 1.0f;
    double n = c->near_m, fa = c->far_m;
    float *p = c->proj;
    for (int i = 0; i < 16; i++)
        p[i] = 0.0f;
    p[0] = (float)(1.0 / c->tan_h);
    p[5] = (float)(1.0 / c->tan_v);
    p[10] = (float)(-(fa + n) / (fa - n));
    p[11] = -1.0f;
    p[14] = (float)(-2.0 * fa * n / (fa - n));
    // The boresight's own angles.
    // Straight down or up the boresight has no azimuth of its own: the
    // camera's up (or down) axis gives it.
    double he = f.e_m, hn = f.n_m;
    if (hypot (he, hn) < 1e-9)
        he = f.u_m < 0 ? u.e_m : -u.e_m, hn = f.u_m < 0 ? u.n_m : -u.n_m;
    double az = atan2 (he, hn);
    c->heading_deg = fmod (az / S_DEG + 360.0, 360.0);
    c->pitch_deg = asin (fmax (-1.0, fmin (1.0, f.u_m))) / S_DEG;
    cgs_enu_t r0 = s_v (cos (az), -sin (az), 0); // level right of the boresight
    c->roll_deg = atan2 (-s_dot (r, s_cross (r0, f)), s_dot (r, r0)) / S_DEG;
}

int cgs_camera_make (const cgs_camera_in_t *in, cgs_camera_t *ret)
{
    if (!in || !ret || !isfinite (in->position.e_m) || !isfinite (in->position.n_m) ||
        !isfinite (in->position.u_m) || !isfinite (in->heading_deg) || !isfinite (in->pitch_deg) ||
        !isfinite (in->roll_deg) || !(in->depression_deg > -90 && in->depression_deg < 90) ||
        !(in->hfov_deg > 0 && in->hfov_deg < 180) || !(in->vfov_deg > 0 && in->vfov_deg < 180) ||
        in->width_px < 1 || in->height_px < 1 || !(in->near_m > 0) || !(in->far_m > in->near_m))
        return -EINVAL;
    if (in->point.staring && in->point.gimbal_limited &&
        (!(in->point.gimbal_azimuth_deg > 0 && in->point.gimbal_azimuth_deg <= 180) ||
         !(in->point.gimbal_elevation_min_deg >= -90 &&
           in->point.gimbal_elevation_min_deg <= in->point.gimbal_elevation_max_deg &&
           in->point.gimbal_elevation_max_deg <= 90)))
        return -EINVAL;
    double h = in->heading_deg * S_DEG, th = in->pitch_deg * S_DEG;
    double ph = in->point.stabilized ? 0.0 : in->roll_deg * S_DEG, ep = in->depression_deg * S_DEG;
    cgs_enu_t f = s_v (sin (h) * cos (th), cos (h) * cos (th), sin (th));
    cgs_enu_t r0 = s_v (cos (h), -sin (h), 0);
    cgs_enu_t u0 = s_cross (r0, f);
    cgs_enu_t r = s_comb (cos (ph), r0, -sin (ph), u0);
    cgs_enu_t u = s_comb (sin (ph), r0, cos (ph), u0);
    cgs_camera_t c = {
        .eye = in->position,
        .forward = s_unit (s_comb (cos (ep), f, -sin (ep), u)),
        .right = s_unit (r),
        .up = s_unit (s_comb (sin (ep), f, cos (ep), u)),
        .tan_h = tan (in->hfov_deg * S_DEG / 2),
        .tan_v = tan (in->vfov_deg * S_DEG / 2),
        .width_px = in->width_px,
        .height_px = in->height_px,
        .near_m = in->near_m,
        .far_m = in->far_m,
    };
    s_matrices (&c);
    if (in->point.staring) {
        // The body's axes (with its roll: the gimbal is fixed to the body).
        cgs_enu_t rb = s_comb (cos (in->roll_deg * S_DEG), r0, -sin (in->roll_deg * S_DEG), u0);
        cgs_enu_t ub = s_comb (sin (in->roll_deg * S_DEG), r0, cos (in->roll_deg * S_DEG), u0);
        cgs_enu_t d = s_v (in->point.stare_at.e_m - c.eye.e_m, in->point.stare_at.n_m - c.eye.n_m,
                           in->point.stare_at.u_m - c.eye.u_m);
        double len = sqrt (s_dot (d, d));
        if (len > 0 && isfinite (len) && in->point.gimbal_limited) {
            double az = atan2 (s_dot (d, rb), s_dot (d, f)) / S_DEG;
            double el = asin (fmax (-1.0, fmin (1.0, s_dot (d, ub) / len))) / S_DEG;
            double caz =
                fmax (-in->point.gimbal_azimuth_deg, fmin (in->point.gimbal_azimuth_deg, az));
            double cel = fmax (in->point.gimbal_elevation_min_deg,
                               fmin (in->point.gimbal_elevation_max_deg, el));
            if (caz != az || cel != el) {
                c.at_gimbal_limit = true;
                double ca = caz * S_DEG, ce = cel * S_DEG;
                d = s_comb (cos (ce), s_comb (cos (ca), f, sin (ca), rb), sin (ce), ub);
                d = s_v (c.eye.e_m + d.e_m, c.eye.n_m + d.n_m, c.eye.u_m + d.u_m);
            } else {
                d = in->point.stare_at;
            }
        } else {
            d = in->point.stare_at;
        }
        if (cgs_camera_stare (&c, d) < 0)
            c.at_gimbal_limit = false; // straight below: the fixed boresight
    }
    *ret = c;
    return 0;
}

int cgs_camera_make_attitude (const cgs_camera_attitude_t *a, cgs_camera_t *ret)
{
    if (!a || !ret || !isfinite (a->position.e_m) || !isfinite (a->position.n_m) ||
        !isfinite (a->position.u_m) || !isfinite (a->azimuth_deg) ||
        !(a->elevation_deg >= -90 && a->elevation_deg <= 90) || !isfinite (a->roll_deg) ||
        !(a->hfov_deg > 0 && a->hfov_deg < 180) || !(a->vfov_deg > 0 && a->vfov_deg < 180) ||
        a->width_px < 1 || a->height_px < 1 || !(a->near_m > 0) || !(a->far_m > a->near_m))
        return -EINVAL;
    double az = a->azimuth_deg * S_DEG, el = a->elevation_deg * S_DEG, ph = a->roll_deg * S_DEG;
    cgs_enu_t f = s_v (sin (az) * cos (el), cos (az) * cos (el), sin (el));
    cgs_enu_t r0 = s_v (cos (az), -sin (az), 0);
    cgs_enu_t u0 = s_cross (r0, f);
    cgs_camera_t c = {
        .eye = a->position,
        .forward = s_unit (f),
        .right = s_unit (s_comb (cos (ph), r0, -sin (ph), u0)),
        .up = s_unit (s_comb (sin (ph), r0, cos (ph), u0)),
        .tan_h = tan (a->hfov_deg * S_DEG / 2),
        .tan_v = tan (a->vfov_deg * S_DEG / 2),
        .width_px = a->width_px,
        .height_px = a->height_px,
        .near_m = a->near_m,
        .far_m = a->far_m,
    };
    s_matrices (&c);
    *ret = c;
    return 0;
}

int cgs_camera_stare (cgs_camera_t *cam, cgs_enu_t target)
{
    cgs_enu_t d =
        s_v (target.e_m - cam->eye.e_m, target.n_m - cam->eye.n_m, target.u_m - cam->eye.u_m);
    double len = sqrt (s_dot (d, d)), hl = hypot (d.e_m, d.n_m);
    if (!(len > 0) || !(hl > 1e-9 * len) || !isfinite (len))
        return -EINVAL;
    cgs_enu_t f = s_unit (d);
    cgs_enu_t r = s_unit (s_v (f.n_m, -f.e_m, 0));
    cam->forward = f;
    cam->right = r;
    cam->up = s_cross (r, f);
    s_matrices (cam);
    return 0;
}

bool cgs_camera_project (const cgs_camera_t *cam, cgs_enu_t p, double *x, double *y, double *depth)
{
    cgs_enu_t d = s_v (p.e_m - cam->eye.e_m, p.n_m - cam->eye.n_m, p.u_m - cam->eye.u_m);
    double z = s_dot (d, cam->forward);
    if (!(z > cam->near_m))
        return false;
    double nx = s_dot (d, cam->right) / z / cam->tan_h;
    double ny = s_dot (d, cam->up) / z / cam->tan_v;
    *x = 0.5 * cam->width_px * (1.0 + nx);
    *y = 0.5 * cam->height_px * (1.0 - ny);
    *depth = z;
    return true;
}

bool cgs_camera_in_view (const cgs_camera_t *cam, cgs_enu_t p)
{
    double x, y, z;
    return cgs_camera_project (cam, p, &x, &y, &z) && z <= cam->far_m && x >= 0 &&
           x <= cam->width_px && y >= 0 && y <= cam->height_px;
}

cgs_enu_t cgs_camera_ray (const cgs_camera_t *cam, double x, double y)
{
    double nx = 2.0 * x / cam->width_px - 1.0, ny = 1.0 - 2.0 * y / cam->height_px;
    return s_unit (s_comb (1.0, cam->forward, 1.0,
                           s_comb (nx * cam->tan_h, cam->right, ny * cam->tan_v, cam->up)));
}

void cgs_camera_footprint (const cgs_camera_t *cam, const cgs_terrain_t *terrain,
                           double max_range_m, cgs_footprint_t *ret)
{
    // The corner rays by the pinhole's own formula (exact at the corners).
    const double sa[4] = {-1, -1, 1, 1}; // near-left, far-left, far-right, near-right
    const double sb[4] = {-1, 1, 1, -1};
    cgs_footprint_t out = {0};
    bool all = true;
    cgs_enu_t hit;
    for (int i = 0; i < 4; i++) {
        cgs_enu_t d = s_comb (1.0, cam->forward, 1.0,
                              s_comb (sa[i] * cam->tan_h, cam->right, sb[i] * cam->tan_v, cam->up));
        all &= cgs_terrain_ray (terrain, cam->eye, d, max_range_m, &hit);
        out.corner[i] = (cgs_v2_t){hit.e_m, hit.n_m};
        out.corner_up_m[i] = hit.u_m;
    }
    all &= cgs_terrain_ray (terrain, cam->eye, cam->forward, max_range_m, &hit);
    out.center = (cgs_v2_t){hit.e_m, hit.n_m};
    out.center_up_m = hit.u_m;
    out.clipped = !all;
    *ret = out;
}

void cgs_camera_frustum (const cgs_camera_t *cam, double planes[6][4])
{
    const cgs_enu_t f = cam->forward, r = cam->right, u = cam->up, e = cam->eye;
    // Inward normals of the four side planes through the eye, then near and far.
    cgs_enu_t n[6] = {
        s_unit (s_comb (cam->tan_h, f, 1.0, r)),  // left plane
        s_unit (s_comb (cam->tan_h, f, -1.0, r)), // right
        s_unit (s_comb (cam->tan_v, f, 1.0, u)),  // bottom
        s_unit (s_comb (cam->tan_v, f, -1.0, u)), // top
        f,
        s_comb (-1.0, f, 0.0, f),
    };
    for (int i = 0; i < 6; i++) {
        planes[i][0] = n[i].e_m;
        planes[i][1] = n[i].n_m;
        planes[i][2] = n[i].u_m;
        planes[i][3] = -s_dot (n[i], e);
    }
    planes[4][3] -= cam->near_m;
    planes[5][3] += cam->far_m;
}

bool cgs_frustum_culls (const double planes[6][4], cgs_enu_t lo, cgs_enu_t hi)
{
    for (int i = 0; i < 6; i++) {
        const double *p = planes[i];
        // The box's corner farthest along the plane's normal.
        double e = p[0] >= 0 ? hi.e_m : lo.e_m, n = p[1] >= 0 ? hi.n_m : lo.n_m;
        double u = p[2] >= 0 ? hi.u_m : lo.u_m;
        if (p[0] * e + p[1] * n + p[2] * u + p[3] < 0)
            return true;
    }
    return false;
}
