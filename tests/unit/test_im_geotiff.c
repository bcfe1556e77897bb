/* test_im_geotiff — a SAR chip written as a GeoTIFF and read back through
 * GDAL: four bright points at known places in the exercise's frame are
 * found in the raster, taken through its GeoTransform and projection to
 * latitude and longitude (OSR), and land within about a pixel of where
 * cgs_geo puts their positions; the projection is the centre's UTM zone;
 * outside the chip is nodata (0), declared so; the metadata carries the
 * time and the chip's grazing angle and resolutions; a second write
 * replaces the file and leaves no temporary behind; an unwritable path and
 * a missing chip are refused with a reason. One of the Makefile's GDAL_SRCS. */
#include "im_geotiff.h"
#include "im_sar.h"
#include "test_util.h"

#include <cpl_conv.h>
#include <gdal.h>
#include <ogr_srs_api.h>

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define S_DEG (M_PI / 180)

static char s_dir[512];

static int s_setup (void **state)
{
    (void)state;
    const char *t = getenv ("TMPDIR");
    snprintf (s_dir, sizeof s_dir, "%s/test_im_geotiff-XXXXXX", t && *t ? t : "/tmp");
    return mkdtemp (s_dir) ? 0 : -1;
}

static int s_teardown (void **state)
{
    (void)state;
    char cmd[600];
    snprintf (cmd, sizeof cmd, "rm -rf '%s'", s_dir);
    return system (cmd) == 0 ? 0 : -1;
}

/* Metres between two geodetic points (small distances). */
static double s_metres (double lat1, double lon1, double lat2, double lon2)
{
    double dn = (lat2 - lat1) * S_DEG * 6371000;
    double de = (lon2 - lon1) * S_DEG * 6371000 * cos (lat1 * S_DEG);
    return hypot (dn, de);
}

static void test_round_trip (void **state)
{
    (void)state;
    cgs_geo_t *frame = cgs_geo_new (47.3, 8.5, 400);
    assert_non_null (frame);
    im_sar_params_t p;
    im_sar_params_defaults (&p);
    p.size_px = 128, p.scene_m = 128;
    p.display_max_db = 35, p.dynamic_range_db = 50; // the points' peaks unsaturated
    char err[512] = "";
    im_sar_t *sar = im_sar_new (&p, 3, err, sizeof err);
    if (!sar)
        fail_msg ("%s", err);
    char path[600];
    snprintf (path, sizeof path, "%s/chip.tif", s_dir);
    assert_int_equal (im_geotiff_write (path, sar, frame, NULL, 0, err, sizeof err), -EINVAL);
    assert_non_null (strstr (err, "no chip"));
    // Looking 35° east of north, from 5 km at 30° grazing, the chip 1.6 km
    // east and 0.8 km south of the frame's origin.
    cgs_enu_t c = {1600, -800, 0};
    double az = 35 * S_DEG, psi = 30 * S_DEG, r = 5000;
    im_sar_geom_t g = {
        .radar = {c.e_m - r * cos (psi) * sin (az), c.n_m - r * cos (psi) * cos (az),
                  r * sin (psi)},
        .radar_vel = {80 * cos (az), -80 * sin (az), 0},
        .center = c,
    };
    im_sar_point_t pts[4] = {
        {.position = {c.e_m - 30, c.n_m + 20, 0}, .rcs_m2 = 1000},
        {.position = {c.e_m + 25, c.n_m + 35, 0}, .rcs_m2 = 1000},
        {.position = {c.e_m - 10, c.n_m - 40, 0}, .rcs_m2 = 1000},
        {.position = {c.e_m + 40, c.n_m - 15, 0}, .rcs_m2 = 1000},
    };
    im_sar_scene_t sc = {.points = pts, .npoints = 4};
    im_sar_chip_t chip;
    assert_int_equal (im_sar_image (sar, &g, &sc, &chip), 0);
    const double when = 1700000000.25; // 2023-11-14 22:13:20.250 UTC
    if (im_geotiff_write (path, sar, frame, NULL, when, err, sizeof err) != 0)
        fail_msg ("%s", err);
    // Read it back.
    GDALAllRegister ();
    GDALDatasetH ds = GDALOpen (path, GA_ReadOnly);
    assert_non_null (ds);
    int w = GDALGetRasterXSize (ds), h = GDALGetRasterYSize (ds);
    assert_int_equal (GDALGetRasterCount (ds), 1);
    GDALRasterBandH band = GDALGetRasterBand (ds, 1);
    assert_int_equal (GDALGetRasterDataType (band), GDT_Byte);
    int has = 0;
    assert_true (GDALGetRasterNoDataValue (band, &has) == 0 && has);
    double gt[6];
    assert_int_equal (GDALGetGeoTransform (ds, gt), CE_None);
    assert_near (gt[1], 1, 1e-9); // 1 m, north up
    assert_near (gt[5], -1, 1e-9);
    assert_true (gt[2] == 0 && gt[4] == 0);
    OGRSpatialReferenceH srs = OSRNewSpatialReference (GDALGetProjectionRef (ds));
    OGRSpatialReferenceH wgs = OSRNewSpatialReference (NULL);
    assert_non_null (srs);
    assert_int_equal (OSRSetWellKnownGeogCS (wgs, "WGS84"), OGRERR_NONE);
    int north = 0;
    assert_true (OSRIsProjected (srs));
    assert_int_equal (OSRGetUTMZone (srs, &north), 32); // 8.5° E
    assert_true (north);
    OSRSetAxisMappingStrategy (srs, OAMS_TRADITIONAL_GIS_ORDER);
    OSRSetAxisMappingStrategy (wgs, OAMS_TRADITIONAL_GIS_ORDER);
    OGRCoordinateTransformationH ct = OCTNewCoordinateTransformation (srs, wgs);
    assert_non_null (ct);
    uint8_t *px = malloc ((size_t)w * h);
    assert_non_null (px);
    assert_int_equal (GDALRasterIO (band, GF_Read, 0, 0, w, h, px, w, h, GDT_Byte, 0, 0), CE_None);
    // Nodata outside the chip: the raster's corners (the chip is turned 35°).
    size_t zeros = 0;
    for (int i = 0; i < w * h; i++)
        zeros += px[i] == 0;
    assert_int_equal (px[0], 0);
    assert_int_equal (px[(size_t)w * h - 1], 0);
    assert_true (zeros > (size_t)(w * h) / 10 && zeros < (size_t)(w * h) / 2);
    // The four brightest spots, each a centroid about its maximum.
    uint8_t *work = malloc ((size_t)w * h);
    assert_non_null (work);
    memcpy (work, px, (size_t)w * h);
    for (int k = 0; k < 4; k++) {
        int best = 0;
        for (int i = 1; i < w * h; i++)
            if (work[i] > work[best])
                best = i;
        int bx = best % w, by = best / w;
        double sw = 0, sx = 0, sy = 0;
        for (int y = by - 2; y <= by + 2; y++)
            for (int x = bx - 2; x <= bx + 2; x++) {
                double v = px[(size_t)y * w + x] - 100.0; // the peak's top only
                if (v > 0)
                    sw += v, sx += v * (x + 0.5), sy += v * (y + 0.5);
            }
        for (int y = by - 8; y <= by + 8; y++)
            for (int x = bx - 8; x <= bx + 8; x++)
                if (x >= 0 && y >= 0 && x < w && y < h)
                    work[(size_t)y * w + x] = 0;
        double e = gt[0] + gt[1] * sx / sw, n = gt[3] + gt[5] * sy / sw, z = 0;
        assert_true (OCTTransform (ct, 1, &e, &n, &z));
        // The nearest known point, by cgs_geo.
        double dmin = INFINITY;
        for (int q = 0; q < 4; q++) {
            cgs_geodetic_t gq;
            assert_int_equal (cgs_geo_enu_to_geodetic (frame, pts[q].position, &gq), 0);
            dmin = fmin (dmin, s_metres (gq.lat_deg, gq.lon_deg, n, e));
        }
        printf ("# bright spot %d at %.6f N %.6f E: %.2f m from its known place\n", k, n, e, dmin);
        assert_true (dmin < 1.0);
    }
    // Metadata.
    assert_string_equal (GDALGetMetadataItem (ds, "TIFFTAG_DATETIME", NULL), "2023:11:14 22:13:20");
    assert_string_equal (GDALGetMetadataItem (ds, "SAR_TIME", NULL), "2023-11-14T22:13:20.250Z");
    assert_near (strtod (GDALGetMetadataItem (ds, "SAR_GRAZING_DEG", NULL), NULL), chip.grazing_deg,
                 1e-6);
    assert_near (strtod (GDALGetMetadataItem (ds, "SAR_RANGE_RES_M", NULL), NULL), chip.range_res_m,
                 1e-6);
    assert_near (strtod (GDALGetMetadataItem (ds, "SAR_CROSS_RES_M", NULL), NULL), chip.cross_res_m,
                 1e-6);
    assert_string_equal (GDALGetMetadataItem (ds, "SAR_GEOMETRY", NULL), "ground");
    OCTDestroyCoordinateTransformation (ct);
    OSRDestroySpatialReference (srs);
    OSRDestroySpatialReference (wgs);
    GDALClose (ds);
    free (px);
    free (work);
    // Again over it: replaced, nothing left behind.
    assert_int_equal (im_sar_image (sar, &g, &sc, NULL), 0);
    assert_int_equal (im_geotiff_write (path, sar, frame, NULL, when + 1, err, sizeof err), 0);
    char tmp[700];
    snprintf (tmp, sizeof tmp, "%s.tmp", path);
    assert_int_equal (access (tmp, F_OK), -1);
    ds = GDALOpen (path, GA_ReadOnly);
    assert_non_null (ds);
    assert_string_equal (GDALGetMetadataItem (ds, "TIFFTAG_DATETIME", NULL), "2023:11:14 22:13:21");
    GDALClose (ds);
    // An unwritable place.
    int rc = im_geotiff_write ("/nonexistent-mscgs-folder/chip.tif", sar, frame, NULL, when, err,
                               sizeof err);
    assert_int_equal (rc, -ENOENT);
    if (!strstr (err, "/nonexistent-mscgs-folder") || !strstr (err, "No such file"))
        fail_msg ("unclear: %s", err);
    im_sar_destroy (&sar);
    cgs_geo_destroy (&frame);
}

/* Over terrain: a hill's points land where the terrain puts them
 * (orthorectified), not displaced by their layover. */
static void test_terrain (void **state)
{
    (void)state;
    cgs_geo_t *frame = cgs_geo_new (-33.9, 151.2, 0); // south of the equator: zone 56S
    assert_non_null (frame);
    enum { N = 201 };
    float *z = malloc (sizeof *z * N * N);
    assert_non_null (z);
    for (int r = 0; r < N; r++)
        for (int c = 0; c < N; c++) // a 40 m hill, 60 m wide, about (0, 0)
            z[r * N + c] =
                (float)(40 * exp (-(pow ((c - 100) * 2.0, 2) + pow ((r - 100) * 2.0, 2)) /
                                  (2 * 30.0 * 30.0)));
    cgs_terrain_t *t = cgs_terrain_new_grid (N, N, -200, -200, 2, z);
    free (z);
    assert_non_null (t);
    im_sar_params_t p;
    im_sar_params_defaults (&p);
    p.size_px = 128, p.scene_m = 128;
    p.display_max_db = 35, p.dynamic_range_db = 50;
    char err[512] = "";
    im_sar_t *sar = im_sar_new (&p, 5, err, sizeof err);
    assert_non_null (sar);
    double top = cgs_terrain_height_clamped (t, 0, 0), psi = 35 * S_DEG, r = 4000;
    im_sar_geom_t g = {
        .radar = {0, -r * cos (psi), r * sin (psi)}, .radar_vel = {70, 0, 0}, .center = {0, 0, 0}};
    im_sar_point_t pt = {.position = {0, 0, top}, .rcs_m2 = 1000};
    im_sar_scene_t sc = {.terrain = t, .points = &pt, .npoints = 1};
    assert_int_equal (im_sar_image (sar, &g, &sc, NULL), 0);
    char path[600];
    snprintf (path, sizeof path, "%s/hill.tif", s_dir);
    if (im_geotiff_write (path, sar, frame, t, 0, err, sizeof err) != 0)
        fail_msg ("%s", err);
    GDALDatasetH ds = GDALOpen (path, GA_ReadOnly);
    assert_non_null (ds);
    int w = GDALGetRasterXSize (ds), h = GDALGetRasterYSize (ds);
    uint8_t *px = malloc ((size_t)w * h);
    assert_non_null (px);
    assert_int_equal (
        GDALRasterIO (GDALGetRasterBand (ds, 1), GF_Read, 0, 0, w, h, px, w, h, GDT_Byte, 0, 0),
        CE_None);
    double gt[6];
    assert_int_equal (GDALGetGeoTransform (ds, gt), CE_None);
    OGRSpatialReferenceH srs = OSRNewSpatialReference (GDALGetProjectionRef (ds));
    int north = 1;
    assert_int_equal (OSRGetUTMZone (srs, &north), 56);
    assert_false (north);
    OGRSpatialReferenceH wgs = OSRNewSpatialReference (NULL);
    OSRSetWellKnownGeogCS (wgs, "WGS84");
    OSRSetAxisMappingStrategy (srs, OAMS_TRADITIONAL_GIS_ORDER);
    OSRSetAxisMappingStrategy (wgs, OAMS_TRADITIONAL_GIS_ORDER);
    OGRCoordinateTransformationH ct = OCTNewCoordinateTransformation (srs, wgs);
    int best = 0;
    for (int i = 1; i < w * h; i++)
        if (px[i] > px[best])
            best = i;
    double e = gt[0] + gt[1] * (best % w + 0.5), n = gt[3] + gt[5] * (best / w + 0.5), zz = 0;
    assert_true (OCTTransform (ct, 1, &e, &n, &zz));
    cgs_geodetic_t gq;
    assert_int_equal (cgs_geo_enu_to_geodetic (frame, pt.position, &gq), 0);
    double d = s_metres (gq.lat_deg, gq.lon_deg, n, e);
    printf ("# hilltop point: %.2f m from its place (its layover: %.1f m)\n", d, top * tan (psi));
    assert_true (d < 1.5);
    OCTDestroyCoordinateTransformation (ct);
    OSRDestroySpatialReference (srs);
    OSRDestroySpatialReference (wgs);
    GDALClose (ds);
    free (px);
    im_sar_destroy (&sar);
    cgs_terrain_destroy (&t);
    cgs_geo_destroy (&frame);
}

int main (void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test (test_round_trip),
        cmocka_unit_test (test_terrain),
    };
    return cmocka_run_group_tests (tests, s_setup, s_teardown);
}
