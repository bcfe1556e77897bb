/* bench_sar — the SAR mode's cost (im_sar, the fast path imagerd runs live):
 * milliseconds per chip of 256 × 256 pixels (256 m) and 512 × 512 (512 m)
 * at the default 1 m resolution, one look, over an fBm terrain (8 km, 10 m
 * grid, 150 m relief) with 30% woods and 40 vehicles in and about the chip,
 * the radar at 8 km and 30° grazing, each chip from a new place along its
 * aperture (new speckle each time). Medians of R runs of C chips each, CPU
 * time of this one thread (FFTW plans for one thread); chips per second
 * from that. Then the reference path (im_sar_ref: phase history and
 * backprojection) on the tests' chip, 128 × 128 pixels (64 m) with three
 * point targets, beside the fast path on the same chip. Goal: a 256 × 256
 * chip in under 200 ms on one core (imagerd's 5 frames a second).
 *
 * Usage: bench_sar [--runs R] [--chips C] (other options, meant for other
 * benchmarks, are ignored). Pin it (`taskset -c 0`) to see one core. */
#include "bench_util.h"
#include "cgs_util.h"
#include "im_sar.h"
#include "im_sar_ref.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define S_VEHICLES 40
#define S_DEG      (M_PI / 180)

static cgs_terrain_t *s_terrain (void)
{
    cgs_terrain_fbm_t f;
    cgs_terrain_fbm_defaults (&f);
    f.seed = 3, f.size_m = 8000, f.resolution_m = 10, f.relief_m = 150, f.feature_m = 1500;
    cgs_terrain_t *t = cgs_terrain_new_fbm (&f);
    cgs_vegetation_t v;
    cgs_vegetation_defaults (&v);
    v.seed = 4, v.cover = 0.3, v.feature_m = 200;
    if (t && cgs_terrain_grow_vegetation (t, &v) < 0)
        cgs_terrain_destroy (&t);
    return t;
}

/* The radar at 8 km and 30° grazing, south of the centre, k steps along its track. */
static im_sar_geom_t s_geom (const cgs_terrain_t *t, int k)
{
    double psi = 30 * S_DEG, r = 8000, hc = cgs_terrain_height_clamped (t, 0, 0);
    return (im_sar_geom_t){.radar = {-100 + 10.0 * k, -r * cos (psi), hc + r * sin (psi)},
                           .radar_vel = {60, 0, 0},
                           .center = {0, 0, hc}};
}

/* Median CPU milliseconds per chip. */
static int s_bench (const cgs_terrain_t *t, const im_entity_t *ents, int size, int runs, int chips,
                    double *ret_ms, im_sar_chip_t *ret_chip)
{
    im_sar_params_t p;
    im_sar_params_defaults (&p);
    p.size_px = size, p.scene_m = size;
    char err[256] = "";
    double t0 = bench_cpu_s ();
    im_sar_t *sar = im_sar_new (&p, 1, err, sizeof err);
    double plan_ms = 1e3 * (bench_cpu_s () - t0);
    if (!sar) {
        fprintf (stderr, "bench_sar: %s\n", err);
        return 1;
    }
    im_sar_scene_t sc = {.terrain = t, .ents = ents, .nents = S_VEHICLES};
    double *ms = calloc ((size_t)runs, sizeof *ms);
    int rc = 0, k = 0;
    for (int run = 0; run < runs && rc == 0; run++) {
        double c0 = bench_cpu_s ();
        for (int i = 0; i < chips && rc == 0; i++) {
            im_sar_geom_t g = s_geom (t, k++);
            if (im_sar_image (sar, &g, &sc, ret_chip) < 0)
                rc = 1;
        }
        ms[run] = 1e3 * (bench_cpu_s () - c0) / chips;
    }
    if (rc == 0) {
        *ret_ms = bench_median (ms, runs);
        printf ("%dx%d chip (%d m, 1 look): %.1f ms a chip (median of %d runs of %d), %.1f "
                "chips/s, %zu scatterers, set-up (FFTW plans) %.0f ms\n",
                size, size, size, *ret_ms, runs, chips, 1e3 / *ret_ms, ret_chip->scatterers,
                plan_ms);
    } else {
        fprintf (stderr, "bench_sar: a chip failed\n");
    }
    free (ms);
    im_sar_destroy (&sar);
    return rc;
}

/* The reference against the fast path on the tests' chip: seconds each. */
static int s_bench_ref (double *ret_ref_s, double *ret_fast_ms)
{
    im_sar_params_t p;
    im_sar_params_defaults (&p);
    p.size_px = 128, p.scene_m = 64, p.speckle = false;
    double psi = 30 * S_DEG, r = 5000;
    im_sar_geom_t g = {
        .radar = {0, -r * cos (psi), r * sin (psi)}, .radar_vel = {100, 0, 0}, .center = {0, 0, 0}};
    im_sar_point_t pts[3] = {{.position = {-12, 10, 0}, .rcs_m2 = 5},
                             {.position = {9, -14, 0}, .rcs_m2 = 50},
                             {.position = {14, 12, 15}, .rcs_m2 = 20}};
    im_sar_scene_t sc = {.points = pts, .npoints = 3, .no_clutter = true};
    char err[256] = "";
    im_sar_t *sar = im_sar_new (&p, 1, err, sizeof err);
    im_sar_chip_t c;
    if (!sar || im_sar_image (sar, &g, &sc, &c) < 0) {
        fprintf (stderr, "bench_sar: %s\n", *err ? err : "the fast chip failed");
        im_sar_destroy (&sar);
        return 1;
    }
    double t0 = bench_cpu_s ();
    for (int i = 0; i < 10; i++)
        im_sar_image (sar, &g, &sc, &c);
    *ret_fast_ms = 1e3 * (bench_cpu_s () - t0) / 10;
    const int n = c.size_px;
    cgs_enu_t *px = malloc (sizeof *px * n * n);
    double *out = malloc (sizeof *out * 2 * n * n);
    t0 = bench_cpu_s ();
    im_sar_ref_t *ref = im_sar_ref_new (&p, &g, pts, 3, 50, err, sizeof err);
    if (!ref || !px || !out) {
        fprintf (stderr, "bench_sar: %s\n", *err ? err : "out of memory");
        free (px);
        free (out);
        im_sar_destroy (&sar);
        return 1;
    }
    for (int y = 0; y < n; y++)
        for (int x = 0; x < n; x++)
            im_sar_chip_px_to_plane (&c, x + 0.5, y + 0.5, &px[y * n + x]);
    im_sar_ref_backproject (ref, &c, px, (size_t)n * n, out);
    *ret_ref_s = bench_cpu_s () - t0;
    printf ("reference (phase history of 3 points, %d pulses x %d frequencies, backprojected "
            "onto %dx%d pixels): %.2f s a chip; the fast path on the same chip: %.2f ms\n",
            im_sar_ref_pulses (ref), im_sar_ref_freqs (ref), n, n, *ret_ref_s, *ret_fast_ms);
    im_sar_ref_destroy (&ref);
    im_sar_destroy (&sar);
    free (px);
    free (out);
    return 0;
}

int main (int argc, char **argv)
{
    long runs = 5, chips = 5;
    for (int i = 1; i < argc; i++) {
        if (strcmp (argv[i], "--runs") == 0 && i + 1 < argc) {
            if (!bench_parse_long (argv[++i], 1, 1000, &runs))
                return fprintf (stderr, "bench_sar: bad --runs\n"), 2;
        } else if (strcmp (argv[i], "--chips") == 0 && i + 1 < argc) {
            if (!bench_parse_long (argv[++i], 1, 1000, &chips))
                return fprintf (stderr, "bench_sar: bad --chips\n"), 2;
        } else if (strncmp (argv[i], "--", 2) == 0 && i + 1 < argc && argv[i + 1][0] != '-') {
            i++;
        }
    }
    cgs_terrain_t *t = s_terrain ();
    if (!t) {
        fprintf (stderr, "bench_sar: no terrain\n");
        return 1;
    }
    // 40 vehicles: tracked and wheeled, half moving, within 300 m of the centre.
    im_entity_t ents[S_VEHICLES];
    uint64_t rng = 7;
    for (int i = 0; i < S_VEHICLES; i++) {
        double e = (cgs_uniform01 (&rng) - 0.5) * 600, n = (cgs_uniform01 (&rng) - 0.5) * 600;
        ents[i] = (im_entity_t){.id = (uint32_t)i + 2,
                                .kind = (cgs_kind_t)(1 + i % 2),
                                .position = {e, n, cgs_terrain_height_clamped (t, e, n)},
                                .heading_deg = cgs_uniform01 (&rng) * 360,
                                .speed_mps = i % 2 ? 8 : 0,
                                .running = true};
    }
    double ms256 = 0, ms512 = 0, ref_s = 0, fast_ms = 0;
    im_sar_chip_t c256, c512;
    int rc = s_bench (t, ents, 256, (int)runs, (int)chips, &ms256, &c256);
    rc |= s_bench (t, ents, 512, (int)runs, (int)chips, &ms512, &c512);
    rc |= s_bench_ref (&ref_s, &fast_ms);
    cgs_terrain_destroy (&t);
    if (rc) {
        printf ("verdict=FAIL (a chip failed)\n");
        return 1;
    }
    printf ("sar_256_ms=%.1f\nsar_256_chips_per_s=%.1f\nsar_512_ms=%.1f\nsar_512_chips_per_s=%.1f\n"
            "sar_ref_128_s=%.2f\nsar_fast_128_ms=%.2f\nsar_aperture_s=%.2f\n",
            ms256, 1e3 / ms256, ms512, 1e3 / ms512, ref_s, fast_ms, c256.aperture_s);
    printf ("verdict: %s (goal: a 256x256 chip in under 200 ms on one core)\n",
            ms256 < 200 ? "met" : "NOT met");
    return 0;
}
