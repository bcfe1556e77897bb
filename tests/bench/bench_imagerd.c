/* bench_imagerd — frames per second of imagerd's renderer (the build's
 * RENDER backend, llvmpipe) at 640 × 480 and 1280 × 720, with a 257 × 257
 * terrain and 100 vehicles in and around the view, as imagerd draws a frame:
 * draw, read back, overlay (and the infrared post-processing in that mode);
 * and the latency from an entity update to the frame that shows it (the
 * entity moved, then one frame drawn and read back). Medians of R runs of
 * F frames each, the camera flying a loiter circle so every frame differs.
 * Goal: at least 30 frames per second at 640 × 480 on a 2-core machine.
 *
 * Then the video (issue: 640 × 480 at 30 frames a second, encoded in real
 * time on one core, with the render): each frame drawn as above, its
 * footprint and MISB ST 0601 KLV packet made, and H.264-encoded and muxed
 * into MPEG-TS (im_video, libx264 veryfast, zero-latency, one thread, 2000
 * kbit/s, a keyframe a second) at 30 frames per second of frame time: fps,
 * the process's CPU seconds per frame (llvmpipe's threads included) and per
 * part (render, encode), and the CPU share of one core at 30 frames a
 * second. Run it pinned (`taskset -c 0`) to see one core's frame rate.
 *
 * Usage: bench_imagerd [--runs R] [--frames F] (other options, meant for
 * other benchmarks, are ignored). */
#include "bench_util.h"
#include "cgs_util.h"
#include "cgs_camera.h"
#include "im_ctx.h"
#include "im_frame.h"
#include "im_post.h"
#include "im_render.h"
#include "im_scene.h"
#include "im_video.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define S_N        257
#define S_RES      30.0
#define S_VEHICLES 100

static cgs_terrain_t *s_terrain (void)
{
    cgs_terrain_fbm_t f;
    cgs_terrain_fbm_defaults (&f);
    f.seed = 1;
    f.size_m = (S_N - 1) * S_RES;
    f.resolution_m = S_RES;
    return cgs_terrain_new_fbm (&f);
}

/* The UAV on a 3 km loiter circle at 1200 m, 45° down, 10° × 7.5°; frame k. */
static cgs_camera_t s_camera (const cgs_terrain_t *t, int w, int h, int k)
{
    double a = k * 0.01, r = 3000;
    cgs_camera_in_t in = {
        .position = {r * sin (a), -r * cos (a), cgs_terrain_height_clamped (t, 0, 0) + 1200},
        .heading_deg = fmod (a * 180 / M_PI + 90, 360),
        .roll_deg = 20,
        .depression_deg = 45,
        .hfov_deg = 10,
        .vfov_deg = 7.5,
        .width_px = w,
        .height_px = h,
        .near_m = 5,
        .far_m = 20000,
    };
    cgs_camera_t cam;
    cgs_camera_make (&in, &cam);
    return cam;
}

static int s_bench (const cgs_terrain_t *t, const im_terrain_mesh_t *mesh, int w, int h,
                    im_mode_t mode, int runs, int frames)
{
    char err[512] = "";
    im_renderer_t *r = im_renderer_new (w, h, mesh, err, sizeof err);
    im_post_t post;
    uint8_t *rgba = malloc ((size_t)w * h * 4);
    if (!r || !rgba || im_post_init (&post, w, h, 1) < 0) {
        fprintf (stderr, "bench_imagerd: %s\n", *err ? err : "out of memory");
        free (rgba);
        im_renderer_destroy (&r);
        return 1;
    }
    im_params_t p;
    im_params_defaults (&p);
    p.width_px = w, p.height_px = h, p.mode = mode;
    // 100 vehicles: a quarter near the footprint's track, the rest spread over the map.
    im_entity_t ents[S_VEHICLES];
    uint64_t rng = 7;
    for (int i = 0; i < S_VEHICLES; i++) {
        double e, n;
        if (i < 25) {
            double a = cgs_uniform01 (&rng) * 2 * M_PI;
            e = 1800 * sin (a) + 200 * (cgs_uniform01 (&rng) - 0.5);
            n = -1800 * cos (a) + 200 * (cgs_uniform01 (&rng) - 0.5);
        } else {
            e = (cgs_uniform01 (&rng) - 0.5) * (S_N - 1) * S_RES;
            n = (cgs_uniform01 (&rng) - 0.5) * (S_N - 1) * S_RES;
        }
        ents[i] = (im_entity_t){.id = (uint32_t)i + 2,
                                .kind = (cgs_kind_t)(1 + i % 2),
                                .position = {e, n, cgs_terrain_height_clamped (t, e, n)},
                                .heading_deg = cgs_uniform01 (&rng) * 360,
                                .running = i % 3 != 0};
    }
    double *fps = calloc ((size_t)runs, sizeof *fps), *lat = calloc ((size_t)runs, sizeof *lat);
    size_t tris = 0, drawn = 0;
    for (int run = 0; run < runs; run++) {
        double t0 = bench_wall_s ();
        for (int k = 0; k < frames; k++) {
            cgs_camera_t cam = s_camera (t, w, h, k);
            im_renderer_draw (r, &cam, &p, ents, S_VEHICLES, rgba, err, sizeof err);
            if (mode == IM_MODE_INFRARED)
                im_post_infrared (&post, rgba, &p);
            cgs_footprint_t fp;
            cgs_camera_footprint (&cam, t, p.max_range_m, &fp);
            im_uav_t u = {.valid = true, .altitude_agl_m = 1200};
            char lines[4][96];
            im_frame_overlay (k * 0.2, &u, &cam, &fp, NULL, lines);
            const char *l[4] = {lines[0], lines[1], lines[2], lines[3]};
            im_post_overlay (rgba, w, h, l, 4);
        }
        fps[run] = frames / (bench_wall_s () - t0);
        im_render_stats_t st;
        im_renderer_stats (r, &st);
        tris = st.triangles, drawn = st.chunks_drawn;
        // Latency: an entity moves; the next frame with it drawn and read back.
        double l0 = bench_wall_s ();
        for (int k = 0; k < 10; k++) {
            ents[0].position.e_m += 1.0;
            cgs_camera_t cam = s_camera (t, w, h, 0);
            im_renderer_draw (r, &cam, &p, ents, S_VEHICLES, rgba, err, sizeof err);
        }
        lat[run] = (bench_wall_s () - l0) / 10;
    }
    double f = bench_median (fps, runs), l = bench_median (lat, runs);
    printf ("%dx%d %s: fps=%.1f (median of %d runs of %d frames), entity_to_frame_ms=%.1f, "
            "triangles=%zu, chunks_drawn=%zu\n",
            w, h, mode == IM_MODE_INFRARED ? "infrared" : "visible", f, runs, frames, 1e3 * l, tris,
            drawn);
    if (w == 640 && mode == IM_MODE_VISIBLE)
        printf ("verdict: %s (goal: at least 30 fps at 640x480)\n", f >= 30 ? "met" : "NOT met");
    free (fps);
    free (lat);
    free (rgba);
    im_post_fini (&post);
    im_renderer_destroy (&r);
    return 0;
}

static void s_count (void *arg, const uint8_t *ts, size_t len)
{
    (void)ts;
    *(size_t *)arg += len;
}

static int s_bench_video (const cgs_terrain_t *t, const im_terrain_mesh_t *mesh, int runs,
                          int frames)
{
    enum { W = 640, H = 480 };
    char err[512] = "";
    im_renderer_t *r = im_renderer_new (W, H, mesh, err, sizeof err);
    uint8_t *rgba = malloc ((size_t)W * H * 4);
    cgs_geo_t *geo = cgs_geo_new (35.96, -121.23, 0);
    if (!r || !rgba || !geo) {
        fprintf (stderr, "bench_imagerd: %s\n", *err ? err : "out of memory");
        free (rgba);
        im_renderer_destroy (&r);
        cgs_geo_destroy (&geo);
        return 1;
    }
    im_params_t p;
    im_params_defaults (&p);
    im_entity_t ents[S_VEHICLES];
    uint64_t rng = 7;
    for (int i = 0; i < S_VEHICLES; i++) {
        double a = cgs_uniform01 (&rng) * 2 * M_PI;
        double e = 1800 * sin (a), n = -1800 * cos (a);
        ents[i] = (im_entity_t){.id = (uint32_t)i + 2,
                                .kind = (cgs_kind_t)(1 + i % 2),
                                .position = {e, n, cgs_terrain_height_clamped (t, e, n)},
                                .running = true};
    }
    double *fps = calloc ((size_t)runs, sizeof *fps), *cpu = calloc ((size_t)runs, sizeof *cpu);
    double *ren = calloc ((size_t)runs, sizeof *ren), *enc = calloc ((size_t)runs, sizeof *enc);
    size_t bytes = 0;
    int rc = 0;
    for (int run = 0; run < runs && rc == 0; run++) {
        im_video_config_t vc = {.width_px = W,
                                .height_px = H,
                                .frame_rate_hz = 30,
                                .bitrate_kbps = 2000,
                                .keyframe_s = 1,
                                .preset = "veryfast",
                                .threads = 1};
        bytes = 0;
        im_video_t *v = im_video_new (&vc, s_count, &bytes, err, sizeof err);
        if (!v) {
            fprintf (stderr, "bench_imagerd: %s\n", err);
            rc = 1;
            break;
        }
        double w0 = bench_wall_s (), c0 = bench_cpu_s (), tr = 0, te = 0;
        for (int k = 0; k < frames; k++) {
            double a0 = bench_wall_s ();
            cgs_camera_t cam = s_camera (t, W, H, k);
            im_renderer_draw (r, &cam, &p, ents, S_VEHICLES, rgba, err, sizeof err);
            cgs_footprint_t fp;
            cgs_camera_footprint (&cam, t, p.max_range_m, &fp);
            im_uav_t u = {.valid = true, .altitude_agl_m = 1200, .hfov_deg = 10, .vfov_deg = 7.5};
            char lines[4][96];
            im_frame_overlay (k / 30.0, &u, &cam, &fp, NULL, lines);
            const char *l[4] = {lines[0], lines[1], lines[2], lines[3]};
            im_post_overlay (rgba, W, H, l, 4);
            double a1 = bench_wall_s ();
            im_klv_frame_t kf;
            uint8_t klv[IM_KLV_MAX_PACKET];
            size_t kl = 0;
            if (im_frame_klv (&cam, &fp, &u, geo, 1.7e9 + k / 30.0, "bench", true,
                              cgs_footprint_center_enu (&fp), 7, &kf) == 0)
                kl = im_klv_encode (&kf, klv, sizeof klv);
            if (im_video_frame (v, rgba, 10 + k / 30.0, klv, kl, NULL, err, sizeof err) < 0) {
                fprintf (stderr, "bench_imagerd: %s\n", err);
                rc = 1;
                break;
            }
            double a2 = bench_wall_s ();
            tr += a1 - a0, te += a2 - a1;
        }
        double wall = bench_wall_s () - w0, c = bench_cpu_s () - c0;
        fps[run] = frames / wall;
        cpu[run] = c / frames;
        ren[run] = tr / frames;
        enc[run] = te / frames;
        im_video_destroy (&v);
    }
    if (rc == 0) {
        double f = bench_median (fps, runs), c = bench_median (cpu, runs);
        printf ("640x480 video (render + KLV + H.264 veryfast + MPEG-TS): fps=%.1f, "
                "cpu_per_frame_ms=%.1f (render %.1f ms, encode %.1f ms wall), one core at 30 fps: "
                "%.0f%%, stream %.0f kbit/s at 30 fps (median of %d runs of %d frames)\n",
                f, 1e3 * c, 1e3 * bench_median (ren, runs), 1e3 * bench_median (enc, runs),
                100 * c * 30, 8.0 * (double)bytes * 30 / frames / 1e3, runs, frames);
        printf ("verdict: %s (goal: 640x480 at 30 fps encoded in real time on one core, with the "
                "render)\n",
                f >= 30 && c * 30 <= 1.0 ? "met" : "NOT met");
    }
    free (fps);
    free (cpu);
    free (ren);
    free (enc);
    free (rgba);
    cgs_geo_destroy (&geo);
    im_renderer_destroy (&r);
    return rc;
}

int main (int argc, char **argv)
{
    int runs = 5, frames = 60;
    for (int i = 1; i < argc; i++) {
        if (strcmp (argv[i], "--runs") == 0 && i + 1 < argc)
            runs = atoi (argv[++i]);
        else if (strcmp (argv[i], "--frames") == 0 && i + 1 < argc)
            frames = atoi (argv[++i]);
        else if (strncmp (argv[i], "--", 2) == 0 && i + 1 < argc && argv[i + 1][0] != '-')
            i++;
    }
    if (runs < 1 || frames < 1) {
        fprintf (stderr, "bench_imagerd: bad --runs or --frames\n");
        return 2;
    }
    char err[512] = "";
    im_ctx_t *ctx = im_ctx_new (1280, 720, err, sizeof err);
    cgs_terrain_t *t = s_terrain ();
    im_terrain_mesh_t mesh;
    if (!ctx || !t || im_terrain_mesh_build (t, 32, 5, &mesh) < 0) {
        fprintf (stderr, "bench_imagerd: %s\n", *err ? err : "no terrain");
        cgs_terrain_destroy (&t);
        im_ctx_destroy (&ctx);
        return 1;
    }
    printf ("backend=%s, terrain %dx%d nodes at %.0f m, %zu chunks, %d vehicles\n",
            im_ctx_backend (), mesh.cols, mesh.rows, S_RES, mesh.nchunks, S_VEHICLES);
    int rc = s_bench (t, &mesh, 640, 480, IM_MODE_VISIBLE, runs, frames);
    rc |= s_bench (t, &mesh, 1280, 720, IM_MODE_VISIBLE, runs, frames);
    rc |= s_bench (t, &mesh, 640, 480, IM_MODE_INFRARED, runs, frames);
    rc |= s_bench_video (t, &mesh, runs, frames * 2);
    im_terrain_mesh_fini (&mesh);
    cgs_terrain_destroy (&t);
    im_ctx_destroy (&ctx);
    return rc;
}
