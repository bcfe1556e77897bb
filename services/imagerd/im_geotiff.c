/* im_geotiff — a SAR chip as a GeoTIFF (see im_geotiff.h). The map grid is
 * in UTM through GDAL's OSR (PROJ); between geodetic and the exercise's
 * frame, cgs_geo (GeographicLib). One of the Makefile's GDAL_SRCS. */
#include "im_geotiff.h"
#include "cgs_util.h"

#include <cpl_conv.h>
#include <cpl_error.h>
#include <gdal.h>
#include <ogr_srs_api.h>

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#define S_BORDER 32 // samples along each edge of the chip for its footprint

static const char *s_gdal_msg (void)
{
    const char *m = CPLGetLastErrorMsg ();
    return m && *m ? m : "no reason given";
}

/* The chip's grey at chip pixel coordinates (x, y), bilinear. */
static double s_grey_at (const uint8_t *grey, int n, double x, double y)
{
    double fx = fmin (fmax (x - 0.5, 0), n - 1), fy = fmin (fmax (y - 0.5, 0), n - 1);
    int x0 = (int)fx, y0 = (int)fy;
    int x1 = x0 + 1 < n ? x0 + 1 : x0, y1 = y0 + 1 < n ? y0 + 1 : y0;
    double tx = fx - x0, ty = fy - y0;
    return (grey[(size_t)y0 * n + x0] * (1 - tx) + grey[(size_t)y0 * n + x1] * tx) * (1 - ty) +
           (grey[(size_t)y1 * n + x0] * (1 - tx) + grey[(size_t)y1 * n + x1] * tx) * ty;
}

typedef struct {
    OGRSpatialReferenceH utm, wgs;
    OGRCoordinateTransformationH to_utm, to_wgs;
    uint8_t *buf;
    double *xs, *ys;
    GDALDatasetH ds;
} s_work_t;

static void s_work_free (s_work_t *w)
{
    if (w->ds)
        GDALClose (w->ds);
    if (w->to_utm)
        OCTDestroyCoordinateTransformation (w->to_utm);
    if (w->to_wgs)
        OCTDestroyCoordinateTransformation (w->to_wgs);
    if (w->utm)
        OSRDestroySpatialReference (w->utm);
    if (w->wgs)
        OSRDestroySpatialReference (w->wgs);
    free (w->buf);
    free (w->xs);
    free (w->ys);
}

/* The UTM zone of (lat, lon) and its spatial reference. */
static int s_srs (s_work_t *w, cgs_geodetic_t at, int *ret_epsg, char *err, size_t errlen)
{
    int zone = (int)floor ((at.lon_deg + 180) / 6) + 1;
    zone = zone < 1 ? 1 : zone > 60 ? 60 : zone;
    bool north = at.lat_deg >= 0;
    int epsg = (north ? 32600 : 32700) + zone;
    w->utm = OSRNewSpatialReference (NULL);
    w->wgs = OSRNewSpatialReference (NULL);
    if (!w->utm || !w->wgs)
        return cgs_errf (err, errlen, "geotiff: out of memory"), -ENOMEM;
    if (OSRImportFromEPSG (w->utm, epsg) != OGRERR_NONE &&
        (OSRSetWellKnownGeogCS (w->utm, "WGS84") != OGRERR_NONE ||
         OSRSetUTM (w->utm, zone, north) != OGRERR_NONE)) {
        cgs_errf (err, errlen, "geotiff: no UTM zone %d%c (%s)", zone, north ? 'N' : 'S',
                  s_gdal_msg ());
        return -EIO;
    }
    if (OSRSetWellKnownGeogCS (w->wgs, "WGS84") != OGRERR_NONE) {
        cgs_errf (err, errlen, "geotiff: no WGS84 (%s)", s_gdal_msg ());
        return -EIO;
    }
    // Longitude then latitude, easting then northing, whatever the authority says.
    OSRSetAxisMappingStrategy (w->utm, OAMS_TRADITIONAL_GIS_ORDER);
    OSRSetAxisMappingStrategy (w->wgs, OAMS_TRADITIONAL_GIS_ORDER);
    w->to_utm = OCTNewCoordinateTransformation (w->wgs, w->utm);
    w->to_wgs = OCTNewCoordinateTransformation (w->utm, w->wgs);
    if (!w->to_utm || !w->to_wgs) {
        cgs_errf (err, errlen, "geotiff: no transformation to UTM (%s)", s_gdal_msg ());
        return -EIO;
    }
    *ret_epsg = epsg;
    return 0;
}

/* The folder of path, writable? 0 or -errno. */
static int s_folder (const char *path, char *err, size_t errlen)
{
    char dir[PATH_MAX];
    snprintf (dir, sizeof dir, "%s", path);
    char *slash = strrchr (dir, '/');
    if (!slash)
        snprintf (dir, sizeof dir, ".");
    else if (slash == dir)
        dir[1] = '\0';
    else
        *slash = '\0';
    if (access (dir, W_OK) == 0)
        return 0;
    int e = errno;
    cgs_errf (err, errlen, "geotiff: cannot write %s: folder %s: %s", path, dir, strerror (e));
    return -e;
}

static int s_write (const char *path, const im_sar_t *sar, const im_sar_chip_t *c,
                    const cgs_geo_t *frame, const cgs_terrain_t *terrain, double time_s,
                    s_work_t *w, char *err, size_t errlen)
{
    cgs_geodetic_t g0;
    if (cgs_geo_enu_to_geodetic (frame, c->center, &g0) < 0)
        return cgs_errf (err, errlen, "geotiff: the chip's centre is not a place"), -EINVAL;
    int epsg, rc = s_srs (w, g0, &epsg, err, errlen);
    if (rc < 0)
        return rc;
    // The footprint: where the chip's edges fall on the ground, in UTM.
    const int n = c->size_px, nb = 4 * S_BORDER;
    double bx[4 * S_BORDER], by[4 * S_BORDER];
    int got = 0;
    for (int k = 0; k < nb; k++) {
        double t = (double)(k % S_BORDER) / S_BORDER * n, x, y;
        switch (k / S_BORDER) {
        case 0:
            x = t, y = 0;
            break;
        case 1:
            x = n, y = t;
            break;
        case 2:
            x = n - t, y = n;
            break;
        default:
            x = 0, y = n - t;
            break;
        }
        cgs_enu_t p;
        cgs_geodetic_t g;
        if (!im_sar_chip_px_to_ground (c, x, y, terrain, &p) ||
            cgs_geo_enu_to_geodetic (frame, p, &g) < 0)
            continue;
        bx[got] = g.lon_deg, by[got] = g.lat_deg, got++;
    }
    if (got < 3 || !OCTTransform (w->to_utm, got, bx, by, NULL))
        return cgs_errf (err, errlen, "geotiff: the chip's footprint is not on the map"), -EINVAL;
    double xmin = INFINITY, xmax = -INFINITY, ymin = INFINITY, ymax = -INFINITY;
    for (int k = 0; k < got; k++) {
        xmin = fmin (xmin, bx[k]), xmax = fmax (xmax, bx[k]);
        ymin = fmin (ymin, by[k]), ymax = fmax (ymax, by[k]);
    }
    // The grid: the chip's spacing, aligned to whole multiples of it.
    const double px = c->pixel_m;
    double x0 = floor (xmin / px) * px, ytop = ceil (ymax / px) * px;
    int wd = (int)ceil ((xmax - x0) / px), ht = (int)ceil ((ytop - ymin) / px);
    if (wd < 1 || ht < 1 || wd > 4 * n || ht > 4 * n)
        return cgs_errf (err, errlen, "geotiff: a footprint of %d x %d pixels", wd, ht), -EINVAL;
    w->buf = calloc ((size_t)wd * ht, 1);
    w->xs = malloc ((size_t)wd * sizeof *w->xs);
    w->ys = malloc ((size_t)wd * sizeof *w->ys);
    if (!w->buf || !w->xs || !w->ys)
        return cgs_errf (err, errlen, "geotiff: out of memory"), -ENOMEM;
    const uint8_t *grey = im_sar_grey (sar);
    cgs_enu_t still = {0, 0, 0};
    for (int j = 0; j < ht; j++) {
        for (int i = 0; i < wd; i++)
            w->xs[i] = x0 + (i + 0.5) * px, w->ys[i] = ytop - (j + 0.5) * px;
        if (!OCTTransform (w->to_wgs, wd, w->xs, w->ys, NULL))
            continue;
        for (int i = 0; i < wd; i++) {
            cgs_geodetic_t g = {w->ys[i], w->xs[i], g0.height_m};
            cgs_enu_t p;
            double cx, cy;
            if (cgs_geo_geodetic_to_enu (frame, g, &p) < 0)
                continue;
            p.u_m = terrain ? cgs_terrain_height_clamped (terrain, p.e_m, p.n_m) : 0.0;
            if (!im_sar_chip_to_px (c, p, still, &cx, &cy))
                continue;
            w->buf[(size_t)j * wd + i] =
                (uint8_t)(1 + lrint (s_grey_at (grey, n, cx, cy) * 254 / 255));
        }
    }
    // The file.
    GDALAllRegister ();
    CPLErrorReset ();
    GDALDriverH drv = GDALGetDriverByName ("GTiff");
    if (!drv)
        return cgs_errf (err, errlen, "geotiff: GDAL has no GTiff driver"), -EIO;
    char tmp[PATH_MAX];
    if (snprintf (tmp, sizeof tmp, "%s.tmp", path) >= (int)sizeof tmp)
        return cgs_errf (err, errlen, "geotiff: path too long"), -EINVAL;
    char *opts[] = {"COMPRESS=DEFLATE", NULL};
    w->ds = GDALCreate (drv, tmp, wd, ht, 1, GDT_Byte, opts);
    if (!w->ds) {
        cgs_errf (err, errlen, "geotiff: cannot create %s (%s)", tmp, s_gdal_msg ());
        return -EIO;
    }
    double gt[6] = {x0, px, 0, ytop, 0, -px};
    char *wkt = NULL;
    OSRExportToWkt (w->utm, &wkt);
    GDALRasterBandH band = GDALGetRasterBand (w->ds, 1);
    bool ok =
        GDALSetGeoTransform (w->ds, gt) == CE_None && wkt &&
        GDALSetProjection (w->ds, wkt) == CE_None &&
        GDALSetRasterNoDataValue (band, 0) == CE_None &&
        GDALRasterIO (band, GF_Write, 0, 0, wd, ht, w->buf, wd, ht, GDT_Byte, 0, 0) == CE_None;
    CPLFree (wkt);
    // Metadata.
    time_t tt = (time_t)floor (time_s);
    struct tm tm;
    char when[32], iso[48], v[64];
    gmtime_r (&tt, &tm);
    strftime (when, sizeof when, "%Y:%m:%d %H:%M:%S", &tm);
    strftime (iso, sizeof iso, "%Y-%m-%dT%H:%M:%S", &tm);
    snprintf (iso + strlen (iso), sizeof iso - strlen (iso), ".%03dZ",
              (int)floor ((time_s - floor (time_s)) * 1000));
    GDALSetMetadataItem (w->ds, "TIFFTAG_DATETIME", when, NULL);
    GDALSetMetadataItem (w->ds, "TIFFTAG_SOFTWARE", "mscgs imagerd", NULL);
    GDALSetMetadataItem (w->ds, "TIFFTAG_IMAGEDESCRIPTION",
                         "SAR chip, ground-projected; grey: dB between the display's black and "
                         "white; 0: no data",
                         NULL);
    GDALSetMetadataItem (w->ds, "SAR_TIME", iso, NULL);
    struct {
        const char *key;
        double v;
    } md[] = {{"SAR_GRAZING_DEG", c->grazing_deg},     {"SAR_SQUINT_DEG", c->squint_deg},
              {"SAR_SLANT_RANGE_M", c->slant_range_m}, {"SAR_RANGE_RES_M", c->range_res_m},
              {"SAR_CROSS_RES_M", c->cross_res_m},     {"SAR_PIXEL_M", c->pixel_m},
              {"SAR_CENTER_LAT_DEG", g0.lat_deg},      {"SAR_CENTER_LON_DEG", g0.lon_deg}};
    for (size_t k = 0; k < sizeof md / sizeof md[0]; k++) {
        snprintf (v, sizeof v, "%.9g", md[k].v);
        GDALSetMetadataItem (w->ds, md[k].key, v, NULL);
    }
    GDALSetMetadataItem (w->ds, "SAR_GEOMETRY", c->geometry == IM_SAR_SLANT ? "slant" : "ground",
                         NULL);
    GDALSetDescription (band, "SAR grey");
    GDALClose (w->ds);
    w->ds = NULL;
    if (!ok || CPLGetLastErrorType () >= CE_Failure) {
        cgs_errf (err, errlen, "geotiff: cannot write %s (%s)", tmp, s_gdal_msg ());
        unlink (tmp);
        return -EIO;
    }
    if (rename (tmp, path) < 0) {
        int e = errno;
        cgs_errf (err, errlen, "geotiff: cannot rename %s to %s: %s", tmp, path, strerror (e));
        unlink (tmp);
        return -e;
    }
    return 0;
}

int im_geotiff_write (const char *path, const im_sar_t *sar, const cgs_geo_t *frame,
                      const cgs_terrain_t *terrain, double time_s, char *err, size_t errlen)
{
    if (!path || !*path || !sar || !frame || !isfinite (time_s)) {
        cgs_errf (err, errlen, "geotiff: no path, chip or frame given");
        return -EINVAL;
    }
    const im_sar_chip_t *c = im_sar_chip (sar);
    if (!c) {
        cgs_errf (err, errlen, "geotiff: %s: no chip made yet", path);
        return -EINVAL;
    }
    int rc = s_folder (path, err, errlen);
    if (rc < 0)
        return rc;
    // GDAL reports through a per-thread handler stack: keep it off stderr.
    CPLPushErrorHandler (CPLQuietErrorHandler);
    s_work_t w = {0};
    rc = s_write (path, sar, c, frame, terrain, time_s, &w, err, errlen);
    s_work_free (&w);
    CPLPopErrorHandler ();
    return rc;
}
