/* test_st_relief — the map's shaded relief against the physics of a lit
 * plane: for a planar slope h = a·east + b·north lit from azimuth φ
 * (clockwise from north) and elevation θ, the brightness is the cosine of the
 * angle between the surface normal (−a, −b, 1)/√(1+a²+b²) and the sun
 * (sin φ cos θ, cos φ cos θ, sin θ), which GDAL's hillshade scales to
 * 1 + 254·cos i (1 in shadow). A picture turned upside down or mirrored
 * would light the slopes differently (by 48 grey levels for the north-west
 * facing one), so this also checks north is up and east is right. The extent is the outer edges of
 * the grid's pixels; a grid larger than max_pixels is scaled down keeping its aspect and extent;
 * the vertical exaggeration multiplies the slope. Border pixels are GDAL's own estimate
 * (-compute_edges) and are left out of the comparison. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "st_relief.h"

#include <cpl_vsi.h>
#include <gdal.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

/* The expected pixel value for slope (a, b) in the light of p. */
static double s_expected (double a, double b, const st_relief_params_t *p)
{
    double phi = p->sun_azimuth_deg * M_PI / 180, th = p->sun_elevation_deg * M_PI / 180;
    a *= p->z_factor;
    b *= p->z_factor;
    double cos_i = (-a * sin (phi) * cos (th) - b * cos (phi) * cos (th) + sin (th)) /
                   sqrt (1 + a * a + b * b);
    return cos_i <= 0 ? 1 : 1 + 254 * cos_i;
}

/* Decode the PNG with GDAL; its pixels into a malloc'd buffer. */
static uint8_t *s_decode (const st_relief_t *r, int *ret_w, int *ret_h)
{
    const char *name = "/vsimem/test_st_relief.png";
    VSILFILE *f = VSIFileFromMemBuffer (name, r->png, r->png_len, FALSE);
    assert_non_null (f);
    VSIFCloseL (f);
    GDALDatasetH ds = GDALOpen (name, GA_ReadOnly);
    assert_non_null (ds);
    int w = GDALGetRasterXSize (ds), h = GDALGetRasterYSize (ds);
    uint8_t *px = malloc ((size_t)w * (size_t)h);
    assert_int_equal (
        GDALRasterIO (GDALGetRasterBand (ds, 1), GF_Read, 0, 0, w, h, px, w, h, GDT_Byte, 0, 0),
        CE_None);
    GDALClose (ds);
    VSIUnlink (name);
    *ret_w = w;
    *ret_h = h;
    return px;
}

/* A plane h = a*east + b*north on a cols x rows grid at res, from (e0, n0). */
static cgs_terrain_t *s_plane (int cols, int rows, double e0, double n0, double res, double a,
                               double b)
{
    float *h = malloc ((size_t)cols * (size_t)rows * sizeof *h);
    for (int r = 0; r < rows; r++)
        for (int c = 0; c < cols; c++)
            h[(size_t)r * (size_t)cols + (size_t)c] =
                (float)(500 + a * (e0 + c * res) + b * (n0 + r * res));
    cgs_terrain_t *t = cgs_terrain_new_grid (cols, rows, e0, n0, res, h);
    free (h);
    assert_non_null (t);
    return t;
}

/* Every pixel of a plane's relief within one grey level of the closed form. */
static void s_check_plane (double a, double b, const st_relief_params_t *p)
{
    cgs_terrain_t *t = s_plane (40, 30, -1000, -500, 50, a, b);
    st_relief_t r = {0};
    char err[256] = "";
    if (st_relief_make (t, p, &r, err, sizeof err) != 0)
        fail_msg ("%s", err);
    int w, h;
    uint8_t *px = s_decode (&r, &w, &h);
    assert_int_equal (w, 40);
    assert_int_equal (h, 30);
    assert_int_equal (r.width, 40);
    assert_int_equal (r.height, 30);
    // Inside the border: a border pixel's slope is GDAL's estimate from the
    // pixels it has (-compute_edges), not the plane's.
    double want = s_expected (a, b, p), worst = 0;
    for (int y = 1; y < h - 1; y++)
        for (int x = 1; x < w - 1; x++)
            worst = fmax (worst, fabs (px[y * w + x] - want));
    if (worst > 1.0)
        fail_msg ("slope (%g, %g), sun %g/%g, z %g: worst pixel %.2f levels off %.2f", a, b,
                  p->sun_azimuth_deg, p->sun_elevation_deg, p->z_factor, worst, want);
    free (px);
    st_relief_fini (&r);
    cgs_terrain_destroy (&t);
}

static void test_plane_against_lambert (void **state)
{
    (void)state;
    st_relief_params_t p = {315, 45, 1, 4096};
    s_check_plane (0, 0, &p);       // flat: 1 + 254 sin 45° = 180.6
    s_check_plane (0.3, -0.2, &p);  // facing north-west, towards the sun
    s_check_plane (-0.3, 0.2, &p);  // facing south-east, away from it
    s_check_plane (0.0, 0.5, &p);   // rising to the north: facing south
    s_check_plane (0.5, 0.0, &p);   // rising to the east: facing west
    s_check_plane (-2.0, -2.0, &p); // steep, facing north-east
    p.sun_azimuth_deg = 135;
    p.sun_elevation_deg = 30;
    s_check_plane (0.3, -0.2, &p);
    s_check_plane (-0.4, 0.1, &p);
    // In shadow: the slope faces away steeper than the sun is high.
    p.sun_azimuth_deg = 0;
    p.sun_elevation_deg = 10;
    s_check_plane (0, 1.0, &p);
    p = (st_relief_params_t){315, 45, 2.5, 4096};
    s_check_plane (0.1, -0.15, &p);
}

static void test_extent_and_scaling_down (void **state)
{
    (void)state;
    cgs_terrain_t *t = s_plane (301, 151, -3000, -1000, 20, 0.1, 0.0);
    st_relief_params_t p = {315, 45, 1, 4096};
    st_relief_t r = {0};
    char err[256];
    assert_int_equal (st_relief_make (t, &p, &r, err, sizeof err), 0);
    // Nodes -3000..3000 east, -1000..2000 north; pixels reach half a cell beyond.
    assert_true (fabs (r.extent[0] - -3010) < 1e-9);
    assert_true (fabs (r.extent[1] - -1010) < 1e-9);
    assert_true (fabs (r.extent[2] - 3010) < 1e-9);
    assert_true (fabs (r.extent[3] - 2010) < 1e-9);
    assert_int_equal (r.width, 301);
    assert_int_equal (r.height, 151);
    st_relief_fini (&r);
    p.max_pixels = 100;
    assert_int_equal (st_relief_make (t, &p, &r, err, sizeof err), 0);
    int w, h;
    uint8_t *px = s_decode (&r, &w, &h);
    assert_int_equal (w, 100);
    assert_int_equal (h, 50);
    assert_int_equal (r.width, 100);
    assert_true (fabs (r.extent[2] - 3010) < 1e-9); // the same ground
    double want = s_expected (0.1, 0, &p);
    for (int y = 1; y < h - 1; y++)
        for (int x = 1; x < w - 1; x++)
            assert_true (fabs (px[y * w + x] - want) <= 1.0);
    free (px);
    st_relief_fini (&r);
    st_relief_fini (&r); // a freed one is zeroed
    assert_null (r.png);
    cgs_terrain_destroy (&t);
}

int main (void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test (test_plane_against_lambert),
        cmocka_unit_test (test_extent_and_scaling_down),
    };
    return cmocka_run_group_tests (tests, NULL, NULL);
}
