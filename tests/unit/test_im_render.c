/* Render tests of imagerd, headless, on the backend this binary was built
 * with (test_im_render: the build's RENDER; test_im_render@ALT: the other):
 * golden images of a fixed scene within a small tolerance, a target's
 * rendered position against the camera's projection within a pixel, a view
 * with nothing in it drawing terrain only, the footprint (guidanced's, the
 * map's) at the rendered image's corners, the infrared mode's temperatures
 * and polarity, and a refused GALLIUM_DRIVER. Goldens are in
 * tests/data/golden; CGS_UPDATE_GOLDEN=1 writes them anew from this run. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "cgs_camera.h"
#include "gd_geom.h"
#include "im_ctx.h"
#include "im_frame.h"
#include "im_png.h"
#include "im_post.h"
#include "im_render.h"
#include "im_scene.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define S_W 320
#define S_H 240

static im_ctx_t *s_ctx;
static char s_err[512];

/* Gentle analytic hills: 129 × 129 nodes, 20 m apart, about the origin. */
static cgs_terrain_t *s_hills (void)
{
    enum { N = 129 };
    static float h[N * N];
    for (int r = 0; r < N; r++)
        for (int c = 0; c < N; c++) {
            double e = (c - 64) * 20.0, n = (r - 64) * 20.0;
            h[r * N + c] = (float)(100.0 + 40.0 * sin (e / 300.0) * cos (n / 400.0) + 0.02 * n);
        }
    return cgs_terrain_new_grid (N, N, -64 * 20.0, -64 * 20.0, 20.0, h);
}

static cgs_terrain_t *s_flat (double height)
{
    enum { N = 65 };
    static float h[N * N];
    for (int i = 0; i < N * N; i++)
        h[i] = (float)height;
    return cgs_terrain_new_grid (N, N, -32 * 50.0, -32 * 50.0, 50.0, h);
}

static im_renderer_t *s_renderer (const cgs_terrain_t *t, int w, int h, int chunk)
{
    im_terrain_mesh_t mesh;
    assert_int_equal (im_terrain_mesh_build (t, chunk, 4, &mesh), 0);
    im_renderer_t *r = im_renderer_new (w, h, &mesh, s_err, sizeof s_err);
    if (!r)
        fail_msg ("%s", s_err);
    im_terrain_mesh_fini (&mesh);
    return r;
}

static im_params_t s_params (int w, int h)
{
    im_params_t p;
    im_params_defaults (&p);
    p.width_px = w;
    p.height_px = h;
    p.noise_k = 0; // goldens are deterministic
    return p;
}

static cgs_camera_t s_camera (cgs_enu_t eye, double heading, double roll, double depression,
                              double hfov, int w, int h)
{
    cgs_camera_in_t in = {
        .position = eye,
        .heading_deg = heading,
        .roll_deg = roll,
        .depression_deg = depression,
        .hfov_deg = hfov,
        .vfov_deg = hfov * h / w,
        .width_px = w,
        .height_px = h,
        .near_m = 1,
        .far_m = 20000,
    };
    cgs_camera_t cam;
    assert_int_equal (cgs_camera_make (&in, &cam), 0);
    return cam;
}

static int s_setup (void **state)
{
    (void)state;
    s_ctx = im_ctx_new (1280, 720, s_err, sizeof s_err);
    if (!s_ctx) {
        fprintf (stderr, "no context: %s\n", s_err);
        return -1;
    }
    return 0;
}

static int s_teardown (void **state)
{
    (void)state;
    im_ctx_destroy (&s_ctx);
    return 0;
}

/* ---- the context ------------------------------------------------------------------- */

static void test_context_is_core_33_or_later (void **state)
{
    (void)state;
    cgs_terrain_t *t = s_flat (0);
    im_renderer_t *r = s_renderer (t, 64, 48, 16);
    const char *gl = im_renderer_gl (r);
    const char *v = strstr (gl, "OpenGL ");
    assert_non_null (v);
    int major = 0, minor = 0;
    assert_int_equal (sscanf (v, "OpenGL %d.%d", &major, &minor), 2);
    assert_true (major * 10 + minor >= 33);
    assert_non_null (strstr (gl, "Core Profile"));
    const char *b = im_ctx_backend ();
    assert_true (strcmp (b, "osmesa") == 0 || strcmp (b, "egl") == 0);
    im_renderer_destroy (&r);
    cgs_terrain_destroy (&t);
}

static void test_bad_gallium_driver_is_refused (void **state)
{
    (void)state;
    const char *old = getenv ("GALLIUM_DRIVER");
    char *saved = old ? strdup (old) : NULL;
    setenv ("GALLIUM_DRIVER", "zink", 1);
    char err[512] = "";
    im_ctx_t *c = im_ctx_new (64, 48, err, sizeof err);
    assert_null (c);
    assert_non_null (strstr (err, "GALLIUM_DRIVER=zink is refused"));
    if (saved)
        setenv ("GALLIUM_DRIVER", saved, 1);
    else
        unsetenv ("GALLIUM_DRIVER");
    free (saved);
    assert_int_equal (im_ctx_check_driver ("llvmpipe", err, sizeof err), 0);
    assert_int_equal (im_ctx_check_driver ("softpipe", err, sizeof err), 0);
    assert_int_equal (im_ctx_check_driver ("", err, sizeof err), 0);
    assert_int_equal (im_ctx_check_driver (NULL, err, sizeof err), 0);
    assert_int_equal (im_ctx_check_driver ("d3d12", err, sizeof err), -EINVAL);
}

/* ---- golden images ------------------------------------------------------------------ */

static const im_entity_t s_scene_ents[] = {
    {.id = 11, .kind = CGS_KIND_TRACKED, .heading_deg = 30, .running = true},
    {.id = 12, .kind = CGS_KIND_WHEELED, .heading_deg = 200, .running = false},
    {.id = 13, .kind = CGS_KIND_PERSON, .heading_deg = 0, .running = false},
    {.id = 14, .kind = CGS_KIND_OTHER, .heading_deg = 90, .running = true},
};

/* The fixed scene: hills, four entities on the ground about where the
 * boresight meets it, seen from 800 m up, 45° down, heading north, a 6°
 * field of view. */
static void s_render_scene (im_mode_t mode, im_polarity_t pol, uint8_t *rgba)
{
    cgs_terrain_t *t = s_hills ();
    im_renderer_t *r = s_renderer (t, S_W, S_H, 16);
    double ground = cgs_terrain_height_clamped (t, 0, 0);
    cgs_camera_t cam = s_camera ((cgs_enu_t){0, 0, ground + 800}, 0, 0, 45, 6, S_W, S_H);
    cgs_enu_t aim;
    assert_true (cgs_terrain_ray (t, cam.eye, cam.forward, 1e4, &aim));
    im_entity_t ents[4];
    memcpy (ents, s_scene_ents, sizeof ents);
    const double at[4][2] = {{0, 0}, {25, -20}, {-15, 10}, {-30, -30}};
    for (int i = 0; i < 4; i++) {
        ents[i].position.e_m = aim.e_m + at[i][0];
        ents[i].position.n_m = aim.n_m + at[i][1];
        ents[i].position.u_m =
            cgs_terrain_height_clamped (t, ents[i].position.e_m, ents[i].position.n_m);
        assert_true (cgs_camera_in_view (&cam, ents[i].position));
    }
    im_params_t p = s_params (S_W, S_H);
    p.mode = mode;
    p.polarity = pol;
    assert_int_equal (im_renderer_draw (r, &cam, &p, ents, 4, rgba, s_err, sizeof s_err), 0);
    if (mode == IM_MODE_INFRARED) {
        im_post_t post;
        assert_int_equal (im_post_init (&post, S_W, S_H, 1), 0);
        im_post_infrared (&post, rgba, &p);
        im_post_fini (&post);
    }
    im_render_stats_t st;
    im_renderer_stats (r, &st);
    assert_int_equal (st.entities_drawn, 4);
    im_renderer_destroy (&r);
    cgs_terrain_destroy (&t);
}

static void s_golden (const char *name, const uint8_t *rgba)
{
    char path[4200];
    snprintf (path, sizeof path, "%s/tests/data/golden/%s",
              getenv ("CGS_ROOT") ? getenv ("CGS_ROOT") : ".", name);
    const char *upd = getenv ("CGS_UPDATE_GOLDEN");
    if (upd && strcmp (upd, "1") == 0) {
        assert_int_equal (im_png_write (path, rgba, S_W, S_H, s_err, sizeof s_err), 0);
        fprintf (stderr, "wrote %s\n", path);
        return;
    }
    uint8_t *gold = NULL;
    int w = 0, h = 0;
    if (im_png_read (path, &gold, &w, &h, s_err, sizeof s_err) < 0)
        fail_msg ("%s (CGS_UPDATE_GOLDEN=1 writes it)", s_err);
    assert_int_equal (w, S_W);
    assert_int_equal (h, S_H);
    // Tolerance: a mean absolute difference under one level, and no more than
    // 0.5% of the channel values more than 8 levels off (rasterization may move
    // an edge by a pixel between Mesa builds).
    size_t n = (size_t)S_W * S_H * 4, off = 0;
    double sum = 0;
    for (size_t i = 0; i < n; i++) {
        int d = abs ((int)rgba[i] - (int)gold[i]);
        sum += d;
        off += d > 8;
    }
    free (gold);
    double mean = sum / (double)n;
    print_message ("# %s: mean difference %.3f levels, %zu of %zu values more than 8 off\n", name,
                   mean, off, n);
    assert_true (mean < 1.0);
    assert_true (off <= n / 200);
}

static void test_golden_visible (void **state)
{
    (void)state;
    uint8_t *rgba = malloc (S_W * S_H * 4);
    s_render_scene (IM_MODE_VISIBLE, IM_WHITE_HOT, rgba);
    s_golden ("im_visible.png", rgba);
    free (rgba);
}

static void test_golden_infrared (void **state)
{
    (void)state;
    uint8_t *rgba = malloc (S_W * S_H * 4);
    s_render_scene (IM_MODE_INFRARED, IM_WHITE_HOT, rgba);
    s_golden ("im_infrared.png", rgba);
    free (rgba);
}

/* Black-hot is white-hot inverted, pixel for pixel (no noise). */
static void test_black_hot_inverts (void **state)
{
    (void)state;
    uint8_t *a = malloc (S_W * S_H * 4), *b = malloc (S_W * S_H * 4);
    s_render_scene (IM_MODE_INFRARED, IM_WHITE_HOT, a);
    s_render_scene (IM_MODE_INFRARED, IM_BLACK_HOT, b);
    for (size_t i = 0; i < (size_t)S_W * S_H * 4; i += 4)
        assert_int_equal (a[i] + b[i], 255);
    free (a);
    free (b);
}

/* ---- one target, alone on flat ground ---------------------------------------------- */

/* Render with and without the entity; the pixels that differ are its
 * silhouette: their count and centroid (pixel centres at +0.5). */
static size_t s_silhouette (im_renderer_t *r, const cgs_camera_t *cam, const im_params_t *p,
                            const im_entity_t *e, double *cx, double *cy)
{
    size_t bytes = (size_t)p->width_px * (size_t)p->height_px * 4;
    uint8_t *with = malloc (bytes), *without = malloc (bytes);
    assert_int_equal (im_renderer_draw (r, cam, p, e, 1, with, s_err, sizeof s_err), 0);
    assert_int_equal (im_renderer_draw (r, cam, p, NULL, 0, without, s_err, sizeof s_err), 0);
    size_t n = 0;
    double sx = 0, sy = 0;
    for (int y = 0; y < p->height_px; y++)
        for (int x = 0; x < p->width_px; x++) {
            size_t i = 4 * ((size_t)y * (size_t)p->width_px + (size_t)x);
            if (memcmp (with + i, without + i, 3) != 0) {
                n++;
                sx += x + 0.5;
                sy += y + 0.5;
            }
        }
    free (with);
    free (without);
    *cx = n ? sx / (double)n : NAN;
    *cy = n ? sy / (double)n : NAN;
    return n;
}

/* The rendered target's centre lies within one pixel of where the camera
 * projects its model's centre (a one-box model, whose silhouette's centroid
 * is the projection of its centre up to perspective terms of size/range),
 * across the image, with roll and at several headings. */
static void test_target_pixel_matches_projection (void **state)
{
    (void)state;
    const int w = 640, h = 480;
    cgs_terrain_t *t = s_flat (50);
    im_renderer_t *r = s_renderer (t, w, h, 16);
    im_params_t p = s_params (w, h);
    p.visibility_m = 1e7; // no haze: the silhouette is crisp
    const struct {
        double heading, roll, de, dn; // camera heading, roll; target offset from the aim point
    } cases[] = {
        {0, 0, 0, 0},     {0, 0, 4, 3},     {0, 0, -5, -3.5}, {37, 0, 3, -2},
        {120, 15, -4, 2}, {250, -20, 5, 3}, {300, 5, -5, -3},
    };
    double worst = 0;
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        // 250 m up, 45° down, a 3° field of view: about 0.02 m a pixel.
        double hd = cases[k].heading * M_PI / 180;
        cgs_enu_t eye = {0, 0, 50 + 250};
        cgs_camera_t cam = s_camera (eye, cases[k].heading, cases[k].roll, 45, 3, w, h);
        cgs_enu_t aim;
        cgs_terrain_ray (t, cam.eye, cam.forward, 1e4, &aim);
        im_entity_t e = {
            .id = 1,
            .kind = CGS_KIND_PERSON,
            .position = {aim.e_m + cases[k].de * cos (hd) + cases[k].dn * sin (hd),
                         aim.n_m - cases[k].de * sin (hd) + cases[k].dn * cos (hd), 50},
            .heading_deg = 10.0 * (double)k,
        };
        double cx, cy;
        size_t n = s_silhouette (r, &cam, &p, &e, &cx, &cy);
        assert_true (n > 200);
        im_target_t tg;
        im_frame_target (&cam, t, &e, 1, true, e.position, 10, &tg);
        assert_true (tg.known && tg.in_view && tg.projected);
        double d = hypot (cx - tg.px_x, cy - tg.px_y);
        print_message ("# case %zu: %zu px, centroid (%.2f, %.2f), projection (%.2f, %.2f), "
                       "%.3f px apart\n",
                       k, n, cx, cy, tg.px_x, tg.px_y, d);
        worst = fmax (worst, d);
        assert_true (d <= 1.0);
    }
    print_message ("# worst %.3f px\n", worst);
    im_renderer_destroy (&r);
    cgs_terrain_destroy (&t);
}

/* One camera model: the footprint guidanced plans with (gd_footprint, the
 * map's and the score's) is where the rendered image's corners meet the
 * ground. A small model placed 10% inside each footprint corner (towards the
 * centre) is drawn in that corner of the image; one placed 10% outside is
 * not drawn at all. Over hills, for level flight, a banked turn, the same
 * turn stabilized, and staring at a point (gimbal limited). */
static void test_footprint_matches_image_corners (void **state)
{
    (void)state;
    const int w = 640, h = 480;
    cgs_terrain_t *t = s_hills ();
    im_renderer_t *r = s_renderer (t, w, h, 16);
    im_params_t p = s_params (w, h);
    p.visibility_m = 1e7;
    p.status_blocks = false;
    const struct {
        const char *what;
        double heading, pitch, roll;
        bool stabilized, staring;
    } cases[] = {
        {"level", 30, 0, 0, false, false},
        {"banked turn", 200, 3, 25, false, false},
        {"banked, stabilized", 200, 3, 25, true, false},
        {"staring", 75, 2, -20, false, true},
    };
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        gd_sensor_t sn = {
            .position = {-150, -120, 100 + 300},
            .heading_deg = cases[k].heading,
            .pitch_deg = cases[k].pitch,
            .roll_deg = cases[k].roll,
            .depression_deg = 45,
            .hfov_deg = 4,
            .vfov_deg = 3,
            .max_range_m = 20000,
            .point = {.stabilized = cases[k].stabilized,
                      .staring = cases[k].staring,
                      .stare_at = {60, -40, cgs_terrain_height_clamped (t, 60, -40)},
                      .gimbal_limited = true,
                      .gimbal_azimuth_deg = 150,
                      .gimbal_elevation_min_deg = -90,
                      .gimbal_elevation_max_deg = 0},
        };
        gd_footprint_t fp;
        assert_int_equal (gd_footprint (&sn, t, &fp), 0);
        assert_false (fp.clipped);
        cgs_camera_in_t in = {
            .position = sn.position,
            .heading_deg = sn.heading_deg,
            .pitch_deg = sn.pitch_deg,
            .roll_deg = sn.roll_deg,
            .depression_deg = sn.depression_deg,
            .hfov_deg = sn.hfov_deg,
            .vfov_deg = sn.vfov_deg,
            .width_px = w,
            .height_px = h,
            .near_m = 1,
            .far_m = 20000,
            .point = sn.point,
        };
        cgs_camera_t cam;
        assert_int_equal (cgs_camera_make (&in, &cam), 0);
        // Image corners of near-left, far-left, far-right, near-right.
        const double px[4][2] = {{0, h}, {0, 0}, {w, 0}, {w, h}};
        for (int c = 0; c < 4; c++) {
            for (int side = -1; side <= 1; side += 2) { // -1 inside, +1 outside
                double f = 1 + 0.1 * side;
                double e = fp.center.e + f * (fp.corner[c].e - fp.center.e);
                double n = fp.center.n + f * (fp.corner[c].n - fp.center.n);
                im_entity_t ent = {
                    .id = 1,
                    .kind = CGS_KIND_PERSON,
                    .position = {e, n, cgs_terrain_height_clamped (t, e, n)},
                };
                double cx, cy;
                size_t npx = s_silhouette (r, &cam, &p, &ent, &cx, &cy);
                if (side > 0) {
                    if (npx != 0)
                        fail_msg ("%s, corner %d: a model 10%% outside the footprint drew %zu px",
                                  cases[k].what, c, npx);
                    continue;
                }
                double d = hypot (cx - px[c][0], cy - px[c][1]);
                print_message ("# %s, corner %d: %zu px at (%.1f, %.1f), %.1f px from the "
                               "image corner\n",
                               cases[k].what, c, npx, cx, cy, d);
                assert_true (npx > 10);
                // 10% in along the ground is about 10% in across the image.
                assert_true (d < 0.2 * hypot (w, h) / 2);
                // A quarter in (clear of the image's edges), it is drawn where the
                // camera projects it (the image message's target pixel).
                ent.position.e_m = fp.center.e + 0.75 * (fp.corner[c].e - fp.center.e);
                ent.position.n_m = fp.center.n + 0.75 * (fp.corner[c].n - fp.center.n);
                ent.position.u_m =
                    cgs_terrain_height_clamped (t, ent.position.e_m, ent.position.n_m);
                assert_true (s_silhouette (r, &cam, &p, &ent, &cx, &cy) > 10);
                im_target_t tg;
                im_frame_target (&cam, t, &ent, 1, true, ent.position, 10, &tg);
                assert_true (tg.known && tg.in_view);
                double dp = hypot (cx - tg.px_x, cy - tg.px_y);
                print_message ("#   a quarter in: %.2f px from its projection\n", dp);
                assert_true (dp <= 1.5);
            }
        }
        print_message ("# %s: boresight %.1f deg az, %.1f deg el, roll %.1f deg\n", cases[k].what,
                       cam.heading_deg, cam.pitch_deg, cam.roll_deg);
    }
    im_renderer_destroy (&r);
    cgs_terrain_destroy (&t);
}

/* A view with every entity outside it draws terrain only: the image equals
 * one without entities, and none was drawn. */
static void test_nothing_in_view_draws_terrain_only (void **state)
{
    (void)state;
    cgs_terrain_t *t = s_hills ();
    im_renderer_t *r = s_renderer (t, S_W, S_H, 16);
    im_params_t p = s_params (S_W, S_H);
    im_entity_t ents[3];
    memcpy (ents, s_scene_ents, sizeof ents);
    const double at[3][2] = {{0, -900}, {-900, 0}, {600, 100}}; // behind and beside the view
    for (int i = 0; i < 3; i++) {
        ents[i].position.e_m = at[i][0];
        ents[i].position.n_m = at[i][1];
        ents[i].position.u_m = cgs_terrain_height_clamped (t, at[i][0], at[i][1]);
    }
    double ground = cgs_terrain_height_clamped (t, 0, 0);
    cgs_camera_t cam = s_camera ((cgs_enu_t){0, 0, ground + 800}, 0, 0, 45, 6, S_W, S_H);
    for (int i = 0; i < 3; i++)
        assert_false (cgs_camera_in_view (&cam, ents[i].position));
    size_t bytes = (size_t)S_W * S_H * 4;
    uint8_t *a = malloc (bytes), *b = malloc (bytes);
    assert_int_equal (im_renderer_draw (r, &cam, &p, ents, 3, a, s_err, sizeof s_err), 0);
    im_render_stats_t st;
    im_renderer_stats (r, &st);
    assert_int_equal (st.entities_drawn, 0);
    assert_true (st.chunks_drawn > 0);
    assert_true (st.chunks_culled > 0); // chunks behind the camera are not drawn
    assert_int_equal (im_renderer_draw (r, &cam, &p, NULL, 0, b, s_err, sizeof s_err), 0);
    assert_memory_equal (a, b, bytes);
    // And terrain fills the view: no pixel has the sky's colour in a look 45°
    // down. The sky's colour is read from a look 20° up, whose top row is sky.
    cgs_camera_t up = s_camera ((cgs_enu_t){0, 0, ground + 800}, 0, 0, -20, 6, S_W, S_H);
    assert_int_equal (im_renderer_draw (r, &up, &p, NULL, 0, b, s_err, sizeof s_err), 0);
    const uint8_t *sky_rgb = b + 4 * (S_W / 2);
    size_t sky_up = 0;
    for (size_t i = 0; i < bytes; i += 4)
        sky_up += memcmp (b + i, sky_rgb, 3) == 0;
    assert_true (sky_up > bytes / 4 / 2); // most of a look up is sky
    size_t sky = 0;
    for (size_t i = 0; i < bytes; i += 4)
        sky += memcmp (a + i, sky_rgb, 3) == 0;
    assert_int_equal (sky, 0);
    free (a);
    free (b);
    im_renderer_destroy (&r);
    cgs_terrain_destroy (&t);
}

/* Infrared: a running vehicle's engine deck is the hottest thing in view,
 * a stopped one is not; range attenuation pulls the ground toward the sky's
 * temperature, as exp(−a R) says. */
static void test_infrared_temperatures (void **state)
{
    (void)state;
    const int w = 640, h = 480;
    cgs_terrain_t *t = s_flat (0);
    im_renderer_t *r = s_renderer (t, w, h, 16);
    im_params_t p = s_params (w, h);
    p.mode = IM_MODE_INFRARED;
    p.sun_elevation_deg = -10; // night: the ground is at ambient everywhere
    p.blur_px = 0;
    cgs_camera_t cam = s_camera ((cgs_enu_t){0, 0, 300}, 0, 0, 89, 4, w, h); // looking down
    im_entity_t e = {.id = 1, .kind = CGS_KIND_TRACKED, .position = {0, 5.2, 0}, .running = true};
    uint8_t *img = malloc ((size_t)w * h * 4);
    assert_int_equal (im_renderer_draw (r, &cam, &p, &e, 1, img, s_err, sizeof s_err), 0);
    int hottest = 0;
    for (size_t i = 0; i < (size_t)w * h * 4; i += 4)
        hottest = img[i] > hottest ? img[i] : hottest;
    // The engine deck at 360 K, through 300 m of air, clips at white.
    assert_int_equal (hottest, 255);
    // The ground straight below: ambient seen through 300 m, in grey levels.
    double tau = exp (-p.attenuation_per_km * 0.3);
    double want = (tau * p.ambient_k + (1 - tau) * p.sky_k - p.display_min_k) /
                  (p.display_max_k - p.display_min_k) * 255;
    int ground = img[4 * ((size_t)(h - 5) * w + 5)];
    print_message ("# ground %d, expected %.2f\n", ground, want);
    assert_true (fabs (ground - want) <= 1.5);
    e.running = false;
    assert_int_equal (im_renderer_draw (r, &cam, &p, &e, 1, img, s_err, sizeof s_err), 0);
    hottest = 0;
    for (size_t i = 0; i < (size_t)w * h * 4; i += 4)
        hottest = img[i] > hottest ? img[i] : hottest;
    assert_true (hottest < 200); // engine off: a little over ambient
    free (img);
    im_renderer_destroy (&r);
    cgs_terrain_destroy (&t);
}

/* The status blocks' vehicles: the camera 1 km up and 1 km south of the
 * origin, looking north 45° down with a 30° field: the vehicles at the
 * origin and at (100, 300) are in view, nearest first; one behind the
 * camera, the UAV (air) and one behind a ridge 200 m high across its line of
 * sight are not; at most cap of them, the nearest; and a block's lines. */
static void test_status_labels (void **state)
{
    (void)state;
    enum { N = 65 };
    static float hgt[N * N];
    for (int r = 0; r < N; r++)
        for (int c = 0; c < N; c++) {
            double e = -1600 + 50.0 * c, n = -1600 + 50.0 * r;
            hgt[r * N + c] = (float)(e >= -300 && e <= -50 && n >= 200 && n <= 250 ? 200 : 0);
        }
    cgs_terrain_t *t = cgs_terrain_new_grid (N, N, -1600, -1600, 50, hgt);
    assert_non_null (t);
    cgs_camera_t cam = s_camera ((cgs_enu_t){0, -1000, 1000}, 0, 0, 45, 30, 640, 480);
    im_entity_t e[] = {
        {.id = 1, .kind = CGS_KIND_WHEELED, .position = {100, 300, 0}, .marking = "FAR"},
        {.id = 2, .kind = CGS_KIND_TRACKED, .position = {0, -1500, 0}, .marking = "BEHIND"},
        {.id = 3, .kind = CGS_KIND_AIR, .position = {0, 0, 0}, .marking = "UAV"},
        {.id = 4, .kind = CGS_KIND_TRACKED, .position = {-100, 400, 0}, .marking = "RIDGE"},
        {.id = 5,
         .kind = CGS_KIND_TRACKED,
         .position = {0, 0, 0},
         .marking = "APC1",
         .force = CGS_FORCE_HOSTILE,
         .speed_mps = 8.9},
    };
    im_label_t l[IM_LABELS_MAX];
    size_t n = im_frame_labels (&cam, t, e, 5, l, IM_LABELS_MAX);
    assert_int_equal (n, 2);
    assert_int_equal (l[0].entity->id, 5);
    assert_int_equal (l[1].entity->id, 1);
    // The one at the origin, on the boresight, sits at the image's centre
    // (its model's top a little above: up the image).
    assert_true (fabs (l[0].px_x - 320) < 1 && l[0].px_y < 240 && l[0].px_y > 230);
    assert_true (l[1].px_x > 320 && l[1].px_y < l[0].px_y);
    // Without the terrain the ridge hides nothing.
    assert_int_equal (im_frame_labels (&cam, NULL, e, 5, l, IM_LABELS_MAX), 3);
    // At most cap, the nearest.
    assert_int_equal (im_frame_labels (&cam, t, e, 5, l, 1), 1);
    assert_int_equal (l[0].entity->id, 5);
    assert_int_equal (im_frame_labels (&cam, t, e, 5, l, 0), 0);
    char lines[3][24];
    im_frame_status_lines (&e[4], lines);
    assert_string_equal (lines[0], "APC1");
    assert_string_equal (lines[1], "HOSTILE");
    assert_string_equal (lines[2], "32 KM/H");
    im_frame_status_lines (&e[0], lines);
    assert_string_equal (lines[1], "UNKNOWN");
    assert_string_equal (lines[2], "0 KM/H");
    cgs_terrain_destroy (&t);
}

int main (void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test (test_bad_gallium_driver_is_refused),
        cmocka_unit_test (test_context_is_core_33_or_later),
        cmocka_unit_test (test_golden_visible),
        cmocka_unit_test (test_golden_infrared),
        cmocka_unit_test (test_black_hot_inverts),
        cmocka_unit_test (test_target_pixel_matches_projection),
        cmocka_unit_test (test_footprint_matches_image_corners),
        cmocka_unit_test (test_nothing_in_view_draws_terrain_only),
        cmocka_unit_test (test_infrared_temperatures),
        cmocka_unit_test (test_status_labels),
    };
    return cmocka_run_group_tests (tests, s_setup, s_teardown);
}
