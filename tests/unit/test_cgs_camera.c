/* test_cgs_camera — the shared pinhole camera (imagerd's image, guidanced's,
 * the map's and the score's footprint) against theory:
 *   - the worked example (UAV 1000 m up heading north, level, ε = 45°,
 *     γ = 10°, β = 7.5°, 640 × 480): its axes by hand, the boresight on the
 *     ground at (0, 1000, 0) projecting to the image centre (320, 240), and
 *     ground points projecting where the closed-form pinhole formula
 *     x = w/2·(1 + (d·r)/(d·f)/tan(γ/2)), y = h/2·(1 − (d·u)/(d·f)/tan(β/2))
 *     puts them;
 *   - random poses: the camera's axes equal those built independently by
 *     rotations (yaw about up, pitch about right, roll about forward,
 *     depression about right), and projection follows the formula; the
 *     boresight's own angles with no depression equal the UAV's;
 *   - cgs_camera_ray and cgs_camera_project are inverses;
 *   - the footprint on flat ground where independently rotated corner rays
 *     meet the plane (and guidanced's gd_footprint is it), and a ground point
 *     is in view exactly when it lies inside that footprint;
 *   - the attitude a camera reports builds the same camera again;
 *   - staring within and beyond the gimbal's limits;
 *   - stabilized takes the roll out; staring centres the target, level;
 *   - the frustum planes and box culling;
 *   - the view and projection matrices agree with cgs_camera_project;
 *   - bad input is refused.
 * Needs -Iservices/imagerd, -Iservices/guidanced (and -Icommon). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cgs_terrain.h"
#include "gd_geom.h"
#include "cgs_camera.h"
#include "test_util.h"

/* Two vectors equal within tol, each component. */
#define assert_enu_near(a, b, tol)                                                                 \
    do {                                                                                           \
        cgs_enu_t a_ = (a), b_ = (b);                                                              \
        test_util_near_v ((double[]){a_.e_m, a_.n_m, a_.u_m}, (double[]){b_.e_m, b_.n_m, b_.u_m},  \
                          3, (tol), #a, __FILE__, __LINE__);                                       \
    } while (0)

#define PI  3.14159265358979323846
#define DEG (PI / 180.0)

/* ---- helpers ----------------------------------------------------------------------- */

/* xorshift64*: the same sequence on every machine. */
static uint64_t s_rng = 0x9E3779B97F4A7C15ull;
static double s_uniform (double lo, double hi)
{
    s_rng ^= s_rng >> 12;
    s_rng ^= s_rng << 25;
    s_rng ^= s_rng >> 27;
    uint64_t x = s_rng * 0x2545F4914F6CDD1Dull;
    return lo + (hi - lo) * (double)(x >> 11) / 9007199254740992.0;
}

static cgs_enu_t s_v (double e, double n, double u)
{
    return (cgs_enu_t){e, n, u};
}

static cgs_enu_t s_add (cgs_enu_t a, cgs_enu_t b)
{
    return s_v (a.e_m + b.e_m, a.n_m + b.n_m, a.u_m + b.u_m);
}

static cgs_enu_t s_sub (cgs_enu_t a, cgs_enu_t b)
{
    return s_v (a.e_m - b.e_m, a.n_m - b.n_m, a.u_m - b.u_m);
}

static cgs_enu_t s_mul (double k, cgs_enu_t a)
{
    return s_v (k * a.e_m, k * a.n_m, k * a.u_m);
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

static double s_norm (cgs_enu_t a)
{
    return sqrt (s_dot (a, a));
}

/* Rodrigues: v turned by angle a (right-handed) about the unit axis k. */
static cgs_enu_t s_rotate (cgs_enu_t v, cgs_enu_t k, double a)
{
    return s_add (s_add (s_mul (cos (a), v), s_mul (sin (a), s_cross (k, v))),
                  s_mul (s_dot (k, v) * (1 - cos (a)), k));
}

/* The camera's axes built by rotations, each about the body's present axis,
 * starting from level and facing north (right east, forward north, up up):
 * heading h clockwise from north (a turn of −h about up), pitch θ nose up
 * (+θ about right), roll φ right wing down (+φ about forward: the right
 * axis dips below the horizon), then the sensor's depression ε (−ε about
 * right). */
typedef struct {
    cgs_enu_t f, r, u;
} s_axes_t;

static s_axes_t s_axes (double h_deg, double pitch_deg, double roll_deg, double eps_deg)
{
    s_axes_t a = {s_v (0, 1, 0), s_v (1, 0, 0), s_v (0, 0, 1)};
    const cgs_enu_t up = s_v (0, 0, 1);
    a.f = s_rotate (a.f, up, -h_deg * DEG);
    a.r = s_rotate (a.r, up, -h_deg * DEG);
    a.f = s_rotate (a.f, a.r, pitch_deg * DEG);
    a.u = s_rotate (a.u, a.r, pitch_deg * DEG);
    a.r = s_rotate (a.r, a.f, roll_deg * DEG);
    a.u = s_rotate (a.u, a.f, roll_deg * DEG);
    a.f = s_rotate (a.f, a.r, -eps_deg * DEG);
    a.u = s_rotate (a.u, a.r, -eps_deg * DEG);
    return a;
}

/* The closed-form pinhole projection of p through a camera at eye with axes
 * a, fields of view γ × β and size w × h. */
static void s_pinhole (cgs_enu_t eye, s_axes_t a, double hfov_deg, double vfov_deg, int w, int h,
                       cgs_enu_t p, double *x, double *y)
{
    cgs_enu_t d = s_sub (p, eye);
    double df = s_dot (d, a.f);
    *x = w / 2.0 * (1 + s_dot (d, a.r) / df / tan (hfov_deg * DEG / 2));
    *y = h / 2.0 * (1 - s_dot (d, a.u) / df / tan (vfov_deg * DEG / 2));
}

/* The worked example's pose. */
static cgs_camera_in_t s_example (void)
{
    return (cgs_camera_in_t){
        .position = {0, 0, 1000},
        .depression_deg = 45,
        .hfov_deg = 10,
        .vfov_deg = 7.5,
        .width_px = 640,
        .height_px = 480,
        .near_m = 1,
        .far_m = 1e5,
    };
}

/* A random pose: anywhere over a 20 km square, 100–5000 m up, any heading,
 * pitch within ±15°, roll within ±40°, ε 5–85°, fields of view 1–40° by
 * 1–30°, one of a few image sizes. */
static cgs_camera_in_t s_random_in (void)
{
    static const int sizes[][2] = {{640, 480}, {1280, 720}, {320, 240}, {101, 77}};
    int k = (int)s_uniform (0, 4);
    k = k > 3 ? 3 : k;
    return (cgs_camera_in_t){
        .position = {s_uniform (-1e4, 1e4), s_uniform (-1e4, 1e4), s_uniform (100, 5000)},
        .heading_deg = s_uniform (0, 360),
        .pitch_deg = s_uniform (-15, 15),
        .roll_deg = s_uniform (-40, 40),
        .depression_deg = s_uniform (5, 85),
        .hfov_deg = s_uniform (1, 40),
        .vfov_deg = s_uniform (1, 30),
        .width_px = sizes[k][0],
        .height_px = sizes[k][1],
        .near_m = 1,
        .far_m = 1e6,
    };
}

static gd_sensor_t s_sensor_of (const cgs_camera_in_t *in, double max_range_m)
{
    return (gd_sensor_t){
        .position = in->position,
        .heading_deg = in->heading_deg,
        .pitch_deg = in->pitch_deg,
        .roll_deg = in->roll_deg,
        .depression_deg = in->depression_deg,
        .hfov_deg = in->hfov_deg,
        .vfov_deg = in->vfov_deg,
        .max_range_m = max_range_m,
    };
}

/* Distance from p to the nearest edge of the footprint quadrilateral
 * (inside or out). */
static double s_seg_dist (gd_v2_t p, gd_v2_t a, gd_v2_t b)
{
    double abe = b.e - a.e, abn = b.n - a.n, l2 = abe * abe + abn * abn;
    double t = l2 > 0 ? ((p.e - a.e) * abe + (p.n - a.n) * abn) / l2 : 0;
    t = t < 0 ? 0 : t > 1 ? 1 : t;
    return hypot (p.e - (a.e + t * abe), p.n - (a.n + t * abn));
}

static double s_edge_dist (const gd_footprint_t *f, gd_v2_t p)
{
    double d = INFINITY;
    for (int i = 0; i < 4; i++)
        d = fmin (d, s_seg_dist (p, f->corner[i], f->corner[(i + 1) % 4]));
    return d;
}

/* ---- the worked example -------------------------------------------------------------- */

/* Heading north, level, ε = 45°: forward (0, cos 45°, −sin 45°), right
 * (1, 0, 0), up (0, sin 45°, cos 45°). The boresight meets the ground
 * 1000·cot 45° = 1000 m north, at depth 1000·√2, and falls on the image's
 * centre. The ground point (50, 1100, 0) is d = (50, 1100, −1000) from the
 * eye: d·f = 2100/√2 = 1484.9242, d·r = 50, d·u = 100/√2 = 70.7107, so
 * x = 320·(1 + 0.0336718/tan 5°) = 443.158, y = 240·(1 − 0.0476190/tan 3.75°)
 * = 65.634. */
static void test_worked_example (void **state)
{
    (void)state;
    cgs_camera_in_t in = s_example ();
    cgs_camera_t cam;
    assert_int_equal (cgs_camera_make (&in, &cam), 0);
    const double c = sqrt (0.5);
    assert_enu_near (cam.eye, s_v (0, 0, 1000), 0);
    assert_enu_near (cam.forward, s_v (0, c, -c), 1e-12);
    assert_enu_near (cam.right, s_v (1, 0, 0), 1e-12);
    assert_enu_near (cam.up, s_v (0, c, c), 1e-12);
    assert_near (cam.tan_h, tan (5 * DEG), 1e-15);
    assert_near (cam.tan_v, tan (3.75 * DEG), 1e-15);
    assert_near (cam.heading_deg, 0, 1e-9);
    assert_near (cam.pitch_deg, -45, 1e-9);
    assert_near (cam.roll_deg, 0, 1e-9);

    double x, y, z;
    assert_true (cgs_camera_project (&cam, s_v (0, 1000, 0), &x, &y, &z));
    assert_near (x, 320, 1e-9);
    assert_near (y, 240, 1e-9);
    assert_near (z, 1000 * sqrt (2), 1e-9);
    assert_true (cgs_camera_in_view (&cam, s_v (0, 1000, 0)));

    // The boresight's footprint centre is the same point.
    cgs_footprint_t fp;
    cgs_camera_footprint (&cam, NULL, 1e5, &fp);
    assert_false (fp.clipped);
    assert_enu_near (cgs_footprint_center_enu (&fp), s_v (0, 1000, 0), 1e-6);

    // The hand numbers of the comment.
    assert_true (cgs_camera_project (&cam, s_v (50, 1100, 0), &x, &y, &z));
    assert_near (x, 320 * (1 + 50 / (2100 / sqrt (2)) / tan (5 * DEG)), 1e-9);
    assert_near (y, 240 * (1 - (100 / sqrt (2)) / (2100 / sqrt (2)) / tan (3.75 * DEG)), 1e-9);
    assert_near (x, 443.158, 1e-3);
    assert_near (y, 65.634, 1e-3);
    assert_near (z, 2100 / sqrt (2), 1e-9);
    assert_true (cgs_camera_in_view (&cam, s_v (50, 1100, 0)));

    // Ground points over the footprint against the formula with the hand axes.
    const s_axes_t a = {s_v (0, c, -c), s_v (1, 0, 0), s_v (0, c, c)};
    for (int i = 0; i < 200; i++) {
        cgs_enu_t p = s_v (s_uniform (-300, 300), s_uniform (700, 1400), 0);
        double xe, ye;
        s_pinhole (in.position, a, 10, 7.5, 640, 480, p, &xe, &ye);
        assert_true (cgs_camera_project (&cam, p, &x, &y, &z));
        assert_near (x, xe, 1e-8);
        assert_near (y, ye, 1e-8);
        assert_near (z, s_dot (s_sub (p, in.position), a.f), 1e-8);
        bool inside = xe >= 0 && xe <= 640 && ye >= 0 && ye <= 480;
        assert_int_equal (cgs_camera_in_view (&cam, p), inside);
    }
    // Left of the track is left in the image; nearer is lower.
    assert_true (cgs_camera_project (&cam, s_v (-50, 1000, 0), &x, &y, &z));
    assert_true (x < 320);
    assert_true (cgs_camera_project (&cam, s_v (0, 950, 0), &x, &y, &z));
    assert_true (y > 240);
    // Behind the camera: not projected.
    assert_false (cgs_camera_project (&cam, s_v (0, -1000, 0), &x, &y, &z));
    assert_false (cgs_camera_in_view (&cam, s_v (0, -1000, 0)));
}

/* Random poses: the axes equal those built by rotations, they are
 * orthonormal and right-handed (right × forward = up), projection follows
 * the closed-form formula, and the footprint's centre projects to the
 * image's centre. */
static void test_random_poses_formula (void **state)
{
    (void)state;
    for (int i = 0; i < 2000; i++) {
        cgs_camera_in_t in = s_random_in ();
        cgs_camera_t cam;
        assert_int_equal (cgs_camera_make (&in, &cam), 0);
        s_axes_t a = s_axes (in.heading_deg, in.pitch_deg, in.roll_deg, in.depression_deg);
        assert_enu_near (cam.forward, a.f, 1e-12);
        assert_enu_near (cam.right, a.r, 1e-12);
        assert_enu_near (cam.up, a.u, 1e-12);
        assert_near (s_norm (cam.forward), 1, 1e-12);
        assert_near (s_dot (cam.forward, cam.right), 0, 1e-12);
        assert_enu_near (s_cross (cam.right, cam.forward), cam.up, 1e-12);
        for (int k = 0; k < 10; k++) {
            // A point in front of the camera, within about twice the field.
            double depth = s_uniform (10, 20000);
            cgs_enu_t p = s_add (
                s_add (in.position, s_mul (depth, a.f)),
                s_add (s_mul (s_uniform (-2, 2) * depth * tan (in.hfov_deg * DEG / 2), a.r),
                       s_mul (s_uniform (-2, 2) * depth * tan (in.vfov_deg * DEG / 2), a.u)));
            double x, y, z, xe, ye;
            s_pinhole (in.position, a, in.hfov_deg, in.vfov_deg, in.width_px, in.height_px, p, &xe,
                       &ye);
            assert_true (cgs_camera_project (&cam, p, &x, &y, &z));
            assert_near (x, xe, 1e-6 * in.width_px);
            assert_near (y, ye, 1e-6 * in.height_px);
            assert_near (z, depth, 1e-6 * depth);
        }
    }
}

/* With no depression the boresight is the body's forward axis: its heading,
 * pitch and roll are the UAV's. With depression and no roll it is the
 * heading, pitched down by ε, unrolled. */
static void test_boresight_angles (void **state)
{
    (void)state;
    for (int i = 0; i < 500; i++) {
        cgs_camera_in_t in = s_random_in ();
        in.depression_deg = 0;
        cgs_camera_t cam;
        assert_int_equal (cgs_camera_make (&in, &cam), 0);
        assert_near (fabs (remainder (cam.heading_deg - in.heading_deg, 360)), 0, 1e-9);
        assert_true (cam.heading_deg >= 0 && cam.heading_deg < 360);
        assert_near (cam.pitch_deg, in.pitch_deg, 1e-9);
        assert_near (cam.roll_deg, in.roll_deg, 1e-9);

        in = s_random_in ();
        in.roll_deg = 0;
        in.depression_deg = s_uniform (1, 60);
        assert_int_equal (cgs_camera_make (&in, &cam), 0);
        assert_near (fabs (remainder (cam.heading_deg - in.heading_deg, 360)), 0, 1e-9);
        assert_near (cam.pitch_deg, in.pitch_deg - in.depression_deg, 1e-9);
        assert_near (cam.roll_deg, 0, 1e-9);
    }
}

/* ---- ray and projection ---------------------------------------------------------------- */

/* A point along the ray through (x, y) projects back to (x, y) at the
 * depth of its distance times the ray's cosine to the boresight; the ray is
 * a unit vector; the ray through the centre is the boresight. */
static void test_ray_project_inverse (void **state)
{
    (void)state;
    for (int i = 0; i < 1000; i++) {
        cgs_camera_in_t in = s_random_in ();
        in.point.stabilized = s_uniform (0, 1) < 0.5;
        cgs_camera_t cam;
        assert_int_equal (cgs_camera_make (&in, &cam), 0);
        assert_enu_near (cgs_camera_ray (&cam, in.width_px / 2.0, in.height_px / 2.0), cam.forward,
                         1e-12);
        for (int k = 0; k < 20; k++) {
            double x = s_uniform (0, in.width_px), y = s_uniform (0, in.height_px);
            double s = s_uniform (2, 50000);
            cgs_enu_t d = cgs_camera_ray (&cam, x, y);
            assert_near (s_norm (d), 1, 1e-12);
            double xb, yb, zb;
            assert_true (cgs_camera_project (&cam, s_add (cam.eye, s_mul (s, d)), &xb, &yb, &zb));
            assert_near (xb, x, 1e-7);
            assert_near (yb, y, 1e-7);
            assert_near (zb, s * s_dot (d, cam.forward), 1e-9 * s);
        }
        // And the other way round: a point projects to a pixel whose ray runs
        // through it.
        for (int k = 0; k < 20; k++) {
            cgs_enu_t p = s_add (cam.eye, s_v (s_uniform (-5000, 5000), s_uniform (-5000, 5000),
                                               s_uniform (-5000, 5000)));
            double x, y, z;
            if (!cgs_camera_project (&cam, p, &x, &y, &z))
                continue;
            cgs_enu_t d = s_sub (p, cam.eye);
            cgs_enu_t ray = cgs_camera_ray (&cam, x, y);
            assert_near (s_norm (s_cross (ray, d)) / s_norm (d), 0, 1e-9);
            assert_true (s_dot (ray, d) > 0);
        }
    }
}

/* ---- the footprint: the map and the image agree ---------------------------------------- */

/* For many random poses (rays above the horizon included) the footprint on
 * flat ground is where the corner rays, built independently by rotations
 * (s_axes: f ± tan(γ/2)·r ± tan(β/2)·u), meet the plane u = 0: exactly,
 * when they meet it within the range; clipped when one does not. And
 * guidanced's gd_footprint is this very footprint. */
static void test_footprint_closed_form (void **state)
{
    (void)state;
    int clipped = 0, n = 3000;
    for (int i = 0; i < n; i++) {
        cgs_camera_in_t in = s_random_in ();
        if (i % 5 == 0) // shallow looks, some of them above the horizon
            in.depression_deg = s_uniform (-10, 15);
        double max_range = s_uniform (5000, 50000);
        cgs_camera_t cam;
        assert_int_equal (cgs_camera_make (&in, &cam), 0);
        cgs_footprint_t fp;
        cgs_camera_footprint (&cam, NULL, max_range, &fp);
        s_axes_t a = s_axes (in.heading_deg, in.pitch_deg, in.roll_deg, in.depression_deg);
        double ta = tan (in.hfov_deg * DEG / 2), tb = tan (in.vfov_deg * DEG / 2);
        const double sa[5] = {-1, -1, 1, 1, 0}, sb[5] = {-1, 1, 1, -1, 0};
        bool any_clipped = false;
        for (int k = 0; k < 5; k++) {
            cgs_enu_t d = s_add (a.f, s_add (s_mul (sa[k] * ta, a.r), s_mul (sb[k] * tb, a.u)));
            d = s_mul (1 / s_norm (d), d);
            double t = d.u_m < 0 ? -in.position.u_m / d.u_m : INFINITY;
            if (!(t <= max_range)) {
                any_clipped = true;
                continue;
            }
            cgs_enu_t want = s_add (in.position, s_mul (t, d));
            cgs_enu_t got =
                k < 4 ? cgs_footprint_corner_enu (&fp, k) : cgs_footprint_center_enu (&fp);
            // cgs_terrain_ray bisects to a millimetre or so on flat ground.
            assert_enu_near (got, want, 1e-2 + 1e-6 * t);
        }
        assert_int_equal (fp.clipped, any_clipped);
        clipped += fp.clipped;
        gd_sensor_t s = s_sensor_of (&in, max_range);
        gd_footprint_t g;
        assert_int_equal (gd_footprint (&s, NULL, &g), 0);
        assert_memory_equal (&g, &fp, sizeof g);
    }
    // Both kinds were met.
    assert_true (clipped > 20 && clipped < n - 20);
}

/* The attitude (azimuth, elevation, roll) a camera reports builds the same
 * camera again (cgs_camera_make_attitude): how every service rebuilds it
 * from the `uav` message. Random poses, stabilized and staring ones too. */
static void test_attitude_round_trip (void **state)
{
    (void)state;
    for (int i = 0; i < 3000; i++) {
        cgs_camera_in_t in = s_random_in ();
        in.point.stabilized = i % 3 == 1;
        in.point.staring = i % 3 == 2;
        in.point.stare_at = s_v (in.position.e_m + s_uniform (-3000, 3000),
                                 in.position.n_m + s_uniform (-3000, 3000), 0);
        cgs_camera_t cam, back;
        assert_int_equal (cgs_camera_make (&in, &cam), 0);
        cgs_camera_attitude_t at = {
            .position = cam.eye,
            .azimuth_deg = cam.heading_deg,
            .elevation_deg = cam.pitch_deg,
            .roll_deg = cam.roll_deg,
            .hfov_deg = in.hfov_deg,
            .vfov_deg = in.vfov_deg,
            .width_px = in.width_px,
            .height_px = in.height_px,
            .near_m = in.near_m,
            .far_m = in.far_m,
        };
        assert_int_equal (cgs_camera_make_attitude (&at, &back), 0);
        assert_enu_near (back.forward, cam.forward, 1e-9);
        assert_enu_near (back.right, cam.right, 1e-9);
        assert_enu_near (back.up, cam.up, 1e-9);
    }
    // Straight down: the azimuth comes from the camera's up axis.
    cgs_camera_attitude_t down = {.position = s_v (0, 0, 1000),
                                  .azimuth_deg = 30,
                                  .elevation_deg = -90,
                                  .hfov_deg = 10,
                                  .vfov_deg = 7.5,
                                  .width_px = 64,
                                  .height_px = 48,
                                  .near_m = 1,
                                  .far_m = 5000};
    cgs_camera_t c;
    assert_int_equal (cgs_camera_make_attitude (&down, &c), 0);
    assert_near (c.heading_deg, 30, 1e-9);
    assert_near (c.pitch_deg, -90, 1e-9);
    down.elevation_deg = -91;
    assert_int_equal (cgs_camera_make_attitude (&down, &c), -EINVAL);
}

/* Staring within the gimbal's limits looks straight at the point; beyond
 * them the camera is held at the limit (its direction in the body axes at
 * the limiting azimuth or elevation) and says so. */
static void test_gimbal_limits (void **state)
{
    (void)state;
    cgs_camera_in_t in = s_example (); // 1000 m up, heading north, level
    in.point.staring = true;
    in.point.gimbal_limited = true;
    in.point.gimbal_azimuth_deg = 90;
    in.point.gimbal_elevation_min_deg = -80;
    in.point.gimbal_elevation_max_deg = -10;
    cgs_camera_t cam;
    // Ahead and to the right, 45° down: within the limits.
    in.point.stare_at = s_v (1000, 1000 * sqrt (2), 0);
    assert_int_equal (cgs_camera_make (&in, &cam), 0);
    assert_false (cam.at_gimbal_limit);
    double x, y, z;
    assert_true (cgs_camera_project (&cam, in.point.stare_at, &x, &y, &z));
    assert_near (x, in.width_px / 2.0, 1e-6);
    assert_near (y, in.height_px / 2.0, 1e-6);
    // Behind: azimuth 180° relative, held at 90° (to the right: atan2 gives +180).
    in.point.stare_at = s_v (1, -1000, 0);
    assert_int_equal (cgs_camera_make (&in, &cam), 0);
    assert_true (cam.at_gimbal_limit);
    assert_near (cam.heading_deg, 90, 1e-6);
    assert_near (cam.pitch_deg, -45, 1e-4); // elevation kept: about atan(1000/1000)
    // Straight below is beyond -80°: held at -80°.
    in.point.stare_at = s_v (0, 1, 0);
    assert_int_equal (cgs_camera_make (&in, &cam), 0);
    assert_true (cam.at_gimbal_limit);
    assert_near (cam.pitch_deg, -80, 1e-6);
    // Near the horizon: above -10°, held at -10°.
    in.point.stare_at = s_v (0, 100000, 0);
    assert_int_equal (cgs_camera_make (&in, &cam), 0);
    assert_true (cam.at_gimbal_limit);
    assert_near (cam.pitch_deg, -10, 1e-6);
    // Limits out of order are refused.
    in.point.gimbal_elevation_min_deg = 0;
    assert_int_equal (cgs_camera_make (&in, &cam), -EINVAL);
}

/* On flat ground, a point is in view exactly when it lies inside the
 * footprint (points within 1 cm of an edge left out). Poses whose footprint
 * is clipped (a corner ray meets no ground) are skipped: there the
 * quadrilateral is not the image's outline. */
static void test_in_view_matches_footprint (void **state)
{
    (void)state;
    long agree = 0, inside = 0, outside = 0, poses = 0, edge = 0;
    for (int i = 0; poses < 400 && i < 5000; i++) {
        cgs_camera_in_t in = s_random_in ();
        in.depression_deg = s_uniform (20, 85);
        const double max_range = 50000;
        cgs_camera_t cam;
        assert_int_equal (cgs_camera_make (&in, &cam), 0);
        gd_sensor_t s = s_sensor_of (&in, max_range);
        gd_footprint_t g;
        assert_int_equal (gd_footprint (&s, NULL, &g), 0);
        if (g.clipped)
            continue;
        poses++;
        double lo_e = INFINITY, hi_e = -INFINITY, lo_n = INFINITY, hi_n = -INFINITY;
        for (int k = 0; k < 4; k++) {
            lo_e = fmin (lo_e, g.corner[k].e), hi_e = fmax (hi_e, g.corner[k].e);
            lo_n = fmin (lo_n, g.corner[k].n), hi_n = fmax (hi_n, g.corner[k].n);
        }
        double me = 0.3 * (hi_e - lo_e), mn = 0.3 * (hi_n - lo_n);
        for (int k = 0; k < 100; k++) {
            gd_v2_t p = gd_v2 (s_uniform (lo_e - me, hi_e + me), s_uniform (lo_n - mn, hi_n + mn));
            if (s_edge_dist (&g, p) < 0.01) {
                edge++;
                continue;
            }
            bool in_fp = cgs_footprint_contains (&g, p);
            bool in_img = cgs_camera_in_view (&cam, s_v (p.e, p.n, 0));
            if (in_fp != in_img)
                fail_msg ("pose %d point (%.3f, %.3f): footprint says %d, image says %d "
                          "(edge distance %.4f m)",
                          i, p.e, p.n, in_fp, in_img, s_edge_dist (&g, p));
            agree++;
            inside += in_fp;
            outside += !in_fp;
        }
    }
    assert_int_equal (poses, 400);
    assert_int_equal (agree, inside + outside);
    assert_true (agree >= 400 * 100 - edge);
    // A meaningful share on each side.
    assert_true (inside > 5000);
    assert_true (outside > 5000);
}

/* ---- stabilized and staring -------------------------------------------------------------- */

static void s_assert_same_camera (const cgs_camera_t *a, const cgs_camera_t *b, double tol)
{
    assert_enu_near (a->eye, b->eye, 0);
    assert_enu_near (a->forward, b->forward, tol);
    assert_enu_near (a->right, b->right, tol);
    assert_enu_near (a->up, b->up, tol);
    for (int i = 0; i < 16; i++) {
        assert_near (a->view[i], b->view[i], tol * (1 + fabs (b->view[i])));
        assert_near (a->proj[i], b->proj[i], tol * (1 + fabs (b->proj[i])));
    }
    assert_near (a->heading_deg, b->heading_deg, 1e-9);
    assert_near (a->pitch_deg, b->pitch_deg, 1e-9);
    assert_near (a->roll_deg, b->roll_deg, 1e-9);
}

/* Stabilized, a bank of 30° changes nothing: the camera equals the one at
 * roll 0 (stabilized or not); not stabilized it does change. */
static void test_stabilized_removes_roll (void **state)
{
    (void)state;
    for (int i = 0; i < 200; i++) {
        cgs_camera_in_t in = s_random_in ();
        in.roll_deg = i == 0 ? 30 : s_uniform (-60, 60);
        if (fabs (in.roll_deg) < 1)
            in.roll_deg = 30;
        cgs_camera_in_t level = in;
        level.roll_deg = 0;
        in.point.stabilized = true;
        cgs_camera_t a, b, c, d;
        assert_int_equal (cgs_camera_make (&in, &a), 0);
        assert_int_equal (cgs_camera_make (&level, &b), 0);
        level.point.stabilized = true;
        assert_int_equal (cgs_camera_make (&level, &c), 0);
        s_assert_same_camera (&a, &b, 0);
        s_assert_same_camera (&a, &c, 0);
        in.point.stabilized = false;
        assert_int_equal (cgs_camera_make (&in, &d), 0);
        assert_true (s_norm (s_sub (d.right, a.right)) > 1e-3);
        // Stabilized, the image's right is level.
        assert_near (a.right.u_m, 0, 1e-12);
    }
}

/* Staring at a target puts it on the image's centre with the camera level
 * (no roll: right is horizontal, up points up); the boresight's angles are
 * the bearing and elevation of the target. */
static void test_stare (void **state)
{
    (void)state;
    for (int i = 0; i < 1000; i++) {
        cgs_camera_in_t in = s_random_in ();
        cgs_camera_t cam;
        assert_int_equal (cgs_camera_make (&in, &cam), 0);
        cgs_enu_t t = s_v (in.position.e_m + s_uniform (-8000, 8000),
                           in.position.n_m + s_uniform (-8000, 8000), s_uniform (-100, 300));
        assert_int_equal (cgs_camera_stare (&cam, t), 0);
        double x, y, z;
        assert_true (cgs_camera_project (&cam, t, &x, &y, &z));
        assert_near (x, in.width_px / 2.0, 1e-6);
        assert_near (y, in.height_px / 2.0, 1e-6);
        cgs_enu_t d = s_sub (t, in.position);
        assert_near (z, s_norm (d), 1e-6);
        assert_true (cgs_camera_in_view (&cam, t));
        assert_near (cam.roll_deg, 0, 1e-9);
        assert_near (cam.right.u_m, 0, 1e-12);
        assert_true (cam.up.u_m > 0);
        assert_near (s_norm (cam.right), 1, 1e-12);
        assert_near (s_norm (cam.up), 1, 1e-12);
        assert_near (s_dot (cam.right, cam.forward), 0, 1e-12);
        assert_near (s_dot (cam.up, cam.forward), 0, 1e-12);
        assert_enu_near (s_cross (cam.right, cam.forward), cam.up, 1e-12);
        // The image's right is to the right of the line of sight.
        assert_true (s_dot (s_cross (cam.forward, cam.right), s_v (0, 0, 1)) < 0);
        double bearing = atan2 (d.e_m, d.n_m) / DEG;
        assert_near (fabs (remainder (cam.heading_deg - bearing, 360)), 0, 1e-9);
        assert_near (cam.pitch_deg, atan2 (d.u_m, hypot (d.e_m, d.n_m)) / DEG, 1e-9);
        // The matrices follow the new axes.
        double m[4] = {0};
        for (int r = 0; r < 4; r++)
            m[r] = cam.view[r] * t.e_m + cam.view[4 + r] * t.n_m + cam.view[8 + r] * t.u_m +
                   cam.view[12 + r];
        assert_near (m[0], 0, 1e-3 * (1 + s_norm (d)) + 2e-3 * s_norm (t));
        assert_near (m[1], 0, 1e-3 * (1 + s_norm (d)) + 2e-3 * s_norm (t));
        assert_near (-m[2], s_norm (d), 1e-3 * (1 + s_norm (d)) + 2e-3 * s_norm (t));
    }
    // Straight below, straight above and at the eye: refused, unchanged.
    cgs_camera_in_t in = s_example ();
    cgs_camera_t cam, before;
    assert_int_equal (cgs_camera_make (&in, &cam), 0);
    before = cam;
    assert_int_equal (cgs_camera_stare (&cam, s_v (0, 0, 0)), -EINVAL);
    assert_memory_equal (&cam, &before, sizeof cam);
    assert_int_equal (cgs_camera_stare (&cam, s_v (0, 0, 2000)), -EINVAL);
    assert_memory_equal (&cam, &before, sizeof cam);
    assert_int_equal (cgs_camera_stare (&cam, s_v (0, 0, 1000)), -EINVAL);
    assert_memory_equal (&cam, &before, sizeof cam);
    assert_int_equal (cgs_camera_stare (&cam, s_v (NAN, 0, 0)), -EINVAL);
    assert_memory_equal (&cam, &before, sizeof cam);
    // Nearly below (1 m off at 1000 m) is still a bearing.
    assert_int_equal (cgs_camera_stare (&cam, s_v (1, 0, 0)), 0);
    assert_near (cam.heading_deg, 90, 1e-9);
}

/* ---- frustum culling ------------------------------------------------------------------- */

static void s_box (cgs_enu_t c, double half, cgs_enu_t *lo, cgs_enu_t *hi)
{
    *lo = s_v (c.e_m - half, c.n_m - half, c.u_m - half);
    *hi = s_v (c.e_m + half, c.n_m + half, c.u_m + half);
}

/* The worked example's frustum: a box about the boresight's ground point is
 * kept, one behind the camera, one beyond the far plane and one well to the
 * side are culled; a box holding the eye, or straddling the far plane, is
 * kept. The planes' normals are unit vectors and each plane passes through
 * the frustum's edge. */
static void test_frustum_example (void **state)
{
    (void)state;
    cgs_camera_in_t in = s_example ();
    in.far_m = 5000;
    cgs_camera_t cam;
    assert_int_equal (cgs_camera_make (&in, &cam), 0);
    double pl[6][4];
    cgs_camera_frustum (&cam, pl);
    for (int i = 0; i < 6; i++)
        assert_near (sqrt (pl[i][0] * pl[i][0] + pl[i][1] * pl[i][1] + pl[i][2] * pl[i][2]), 1,
                     1e-12);
    cgs_enu_t lo, hi;
    s_box (s_v (0, 1000, 0), 5, &lo, &hi);
    assert_false (cgs_frustum_culls (pl, lo, hi));
    s_box (s_sub (cam.eye, s_mul (500, cam.forward)), 5, &lo, &hi);
    assert_true (cgs_frustum_culls (pl, lo, hi));
    s_box (s_add (cam.eye, s_mul (5100, cam.forward)), 5, &lo, &hi);
    assert_true (cgs_frustum_culls (pl, lo, hi));
    s_box (s_add (cam.eye, s_mul (5000, cam.forward)), 20, &lo, &hi);
    assert_false (cgs_frustum_culls (pl, lo, hi));
    // At 1414 m depth the image is ±123.7 m wide: 300 m east is out.
    s_box (s_v (300, 1000, 0), 5, &lo, &hi);
    assert_true (cgs_frustum_culls (pl, lo, hi));
    s_box (s_v (-300, 1000, 0), 5, &lo, &hi);
    assert_true (cgs_frustum_culls (pl, lo, hi));
    // A box about the eye reaches past the near plane into the view.
    s_box (cam.eye, 10, &lo, &hi);
    assert_false (cgs_frustum_culls (pl, lo, hi));
    // A big box (a terrain chunk) overlapping the view from outside the
    // side planes on both sides.
    lo = s_v (-2000, 900, -10);
    hi = s_v (2000, 1100, 10);
    assert_false (cgs_frustum_culls (pl, lo, hi));

    // The plane through the eye of the left side contains the ray through
    // the left edge of the image; the near and far planes sit at depth near and far.
    cgs_enu_t dl = cgs_camera_ray (&cam, 0, s_uniform (0, 480));
    cgs_enu_t p = s_add (cam.eye, s_mul (700, dl));
    int on = 0;
    for (int i = 0; i < 4; i++)
        on += fabs (pl[i][0] * p.e_m + pl[i][1] * p.n_m + pl[i][2] * p.u_m + pl[i][3]) < 1e-6;
    assert_int_equal (on, 1);
    p = s_add (cam.eye, s_mul (in.near_m, cam.forward));
    assert_near (pl[4][0] * p.e_m + pl[4][1] * p.n_m + pl[4][2] * p.u_m + pl[4][3], 0, 1e-9);
    p = s_add (cam.eye, s_mul (in.far_m, cam.forward));
    assert_near (pl[5][0] * p.e_m + pl[5][1] * p.n_m + pl[5][2] * p.u_m + pl[5][3], 0, 1e-9);
}

/* Random poses and points: a small box about a point in view is never
 * culled; about a point clearly out of view (outside the image by more than
 * a pixel, behind the near plane or beyond the far plane) it always is. */
static void test_frustum_random (void **state)
{
    (void)state;
    long kept = 0, culled = 0;
    for (int i = 0; i < 500; i++) {
        cgs_camera_in_t in = s_random_in ();
        in.near_m = s_uniform (0.5, 20);
        in.far_m = s_uniform (2000, 30000);
        in.point.stabilized = s_uniform (0, 1) < 0.5;
        cgs_camera_t cam;
        assert_int_equal (cgs_camera_make (&in, &cam), 0);
        double pl[6][4];
        cgs_camera_frustum (&cam, pl);
        for (int k = 0; k < 100; k++) {
            // Points about the view: along rays through pixels up to half the
            // image outside it, at depths to 1.2 × far; some behind.
            double x = s_uniform (-0.5, 1.5) * in.width_px,
                   y = s_uniform (-0.5, 1.5) * in.height_px;
            double s = s_uniform (-0.1, 1.2) * in.far_m;
            cgs_enu_t p = s_add (cam.eye, s_mul (s, cgs_camera_ray (&cam, x, y)));
            double z = s * s_dot (cgs_camera_ray (&cam, x, y), cam.forward);
            cgs_enu_t lo, hi;
            s_box (p, 1e-4, &lo, &hi);
            double mx = fmax (-x, x - in.width_px), my = fmax (-y, y - in.height_px);
            if (cgs_camera_in_view (&cam, p) && z > in.near_m + 0.01 && z < in.far_m - 0.01 &&
                mx < -1 && my < -1) {
                assert_false (cgs_frustum_culls (pl, lo, hi));
                kept++;
            } else if (z < in.near_m - 0.01 || z > in.far_m + 0.01 || mx > 1 || my > 1) {
                assert_true (cgs_frustum_culls (pl, lo, hi));
                culled++;
            }
        }
    }
    assert_true (kept > 5000 && culled > 5000);
}

/* ---- the matrices ----------------------------------------------------------------------- */

/* proj·view·(p, 1) divided by w gives normalised device coordinates that
 * map to the pixel cgs_camera_project gives (x = (ndc_x + 1)/2·w, y = (1 −
 * ndc_y)/2·h); w is the depth; ndc_z is OpenGL's depth, −1 at near and +1
 * at far. The view matrix's upper 3 × 3 is a rotation (rows right, up,
 * −forward). Matrices are float: tolerances follow. */
static void test_matrices (void **state)
{
    (void)state;
    for (int i = 0; i < 500; i++) {
        cgs_camera_in_t in = s_random_in ();
        in.position.e_m /= 4, in.position.n_m /= 4;
        in.near_m = s_uniform (0.5, 20);
        in.far_m = s_uniform (5000, 30000);
        in.point.stabilized = s_uniform (0, 1) < 0.5;
        cgs_camera_t cam;
        assert_int_equal (cgs_camera_make (&in, &cam), 0);
        const float *v = cam.view, *pr = cam.proj;
        assert_near (v[0], cam.right.e_m, 1e-7);
        assert_near (v[4], cam.right.n_m, 1e-7);
        assert_near (v[8], cam.right.u_m, 1e-7);
        assert_near (v[1], cam.up.e_m, 1e-7);
        assert_near (v[2], -cam.forward.e_m, 1e-7);
        assert_near (v[3], 0, 0);
        assert_near (v[7], 0, 0);
        assert_near (v[11], 0, 0);
        assert_near (v[15], 1, 0);
        // The eye goes to the origin.
        for (int r = 0; r < 3; r++)
            assert_near (v[r] * cam.eye.e_m + v[4 + r] * cam.eye.n_m + v[8 + r] * cam.eye.u_m +
                             v[12 + r],
                         0, 2e-3);
        for (int k = 0; k < 50; k++) {
            double x = s_uniform (0, in.width_px), y = s_uniform (0, in.height_px);
            double s = s_uniform (in.near_m * 2 + 1, in.far_m * 0.9);
            cgs_enu_t p = s_add (cam.eye, s_mul (s, cgs_camera_ray (&cam, x, y)));
            double px, py, depth;
            assert_true (cgs_camera_project (&cam, p, &px, &py, &depth));
            double e[4], c[4];
            for (int r = 0; r < 4; r++)
                e[r] = v[r] * p.e_m + v[4 + r] * p.n_m + v[8 + r] * p.u_m + v[12 + r];
            for (int r = 0; r < 4; r++)
                c[r] = pr[r] * e[0] + pr[4 + r] * e[1] + pr[8 + r] * e[2] + pr[12 + r] * e[3];
            assert_near (c[3], depth, 1e-5 * depth + 5e-3);
            double nx = c[0] / c[3], ny = c[1] / c[3], nz = c[2] / c[3];
            // Float matrices: a relative error of a few 1e-7 in the eye's
            // coordinates and the point's, seen at depth z through the field.
            double rel = 4e-7 * (s_norm (cam.eye) + s) / depth;
            assert_near ((nx + 1) / 2 * in.width_px, px, 0.02 + rel * in.width_px / 2 / cam.tan_h);
            assert_near ((1 - ny) / 2 * in.height_px, py,
                         0.02 + rel * in.height_px / 2 / cam.tan_v);
            // OpenGL's depth: (f + n)/(f − n) − 2fn/((f − n)·z).
            double f = in.far_m, n = in.near_m;
            assert_near (nz, (f + n) / (f - n) - 2 * f * n / ((f - n) * depth), 1e-4);
            assert_true (nz > -1 && nz < 1);
        }
        // The near and far planes map to −1 and +1.
        double n = in.near_m, f = in.far_m;
        double zn = pr[10] * -n + pr[14], wn = pr[11] * -n;
        double zf = pr[10] * -f + pr[14], wf = pr[11] * -f;
        assert_near (zn / wn, -1, 1e-4);
        assert_near (zf / wf, 1, 1e-4);
    }
}

/* ---- bad input --------------------------------------------------------------------------- */

static void test_make_rejects_bad_input (void **state)
{
    (void)state;
    cgs_camera_t cam;
    cgs_camera_in_t in = s_example ();
    assert_int_equal (cgs_camera_make (&in, &cam), 0);
    assert_int_equal (cgs_camera_make (NULL, &cam), -EINVAL);
    assert_int_equal (cgs_camera_make (&in, NULL), -EINVAL);
#define S_BAD(field, value)                                                                        \
    do {                                                                                           \
        cgs_camera_in_t b_ = s_example ();                                                         \
        b_.field = (value);                                                                        \
        if (cgs_camera_make (&b_, &cam) != -EINVAL)                                                \
            fail_msg ("%s = %s accepted", #field, #value);                                         \
    } while (0)
    S_BAD (position.e_m, NAN);
    S_BAD (position.n_m, INFINITY);
    S_BAD (position.u_m, -INFINITY);
    S_BAD (heading_deg, NAN);
    S_BAD (pitch_deg, INFINITY);
    S_BAD (roll_deg, NAN);
    S_BAD (depression_deg, 90);
    S_BAD (depression_deg, -90);
    S_BAD (depression_deg, 120);
    S_BAD (depression_deg, NAN);
    S_BAD (hfov_deg, 0);
    S_BAD (hfov_deg, -5);
    S_BAD (hfov_deg, 180);
    S_BAD (hfov_deg, NAN);
    S_BAD (vfov_deg, 0);
    S_BAD (vfov_deg, 180);
    S_BAD (vfov_deg, NAN);
    S_BAD (width_px, 0);
    S_BAD (width_px, -640);
    S_BAD (height_px, 0);
    S_BAD (near_m, 0);
    S_BAD (near_m, -1);
    S_BAD (near_m, NAN);
    S_BAD (far_m, 1);   // equal to near
    S_BAD (far_m, 0.5); // below near
    S_BAD (far_m, NAN);
#undef S_BAD
    // The edges that are allowed.
    in.depression_deg = -89.9;
    assert_int_equal (cgs_camera_make (&in, &cam), 0);
    in.depression_deg = 89.9;
    assert_int_equal (cgs_camera_make (&in, &cam), 0);
    in.width_px = in.height_px = 1;
    in.hfov_deg = in.vfov_deg = 179;
    assert_int_equal (cgs_camera_make (&in, &cam), 0);
}

int main (void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test (test_worked_example),
        cmocka_unit_test (test_random_poses_formula),
        cmocka_unit_test (test_boresight_angles),
        cmocka_unit_test (test_ray_project_inverse),
        cmocka_unit_test (test_footprint_closed_form),
        cmocka_unit_test (test_attitude_round_trip),
        cmocka_unit_test (test_gimbal_limits),
        cmocka_unit_test (test_in_view_matches_footprint),
        cmocka_unit_test (test_stabilized_removes_roll),
        cmocka_unit_test (test_stare),
        cmocka_unit_test (test_frustum_example),
        cmocka_unit_test (test_frustum_random),
        cmocka_unit_test (test_matrices),
        cmocka_unit_test (test_make_rejects_bad_input),
    };
    return cmocka_run_group_tests (tests, NULL, NULL);
}
