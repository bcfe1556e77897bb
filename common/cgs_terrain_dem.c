/* cgs_terrain_dem — a DEM read through GDAL (DTED, GeoTIFF, SRTM HGT, ESRI
 * ASCII grid, anything GDAL reads) and resampled onto the local grid (see
 * cgs_terrain_load in cgs_terrain.h). The only part of cgs_terrain that
 * includes GDAL's headers. Pure: no globals, no logging (GDAL's own messages
 * are silenced while a DEM loads and folded into the caller's error text). */
#include "cgs_terrain.h"
#include "cgs_terrain_impl.h"
#include "cgs_util.h"

#include <errno.h>
#include <math.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include <cpl_conv.h>
#include <cpl_error.h>
#include <cpl_string.h>
#include <cpl_vsi.h>
#include <gdal.h>
#include <ogr_srs_api.h>

#define CGS_TERRAIN_MAX_READ_BYTES ((size_t)1 << 28) // most raster bytes read at once
#define CGS_TERRAIN_EDGE_SAMPLES   256 // points per raster edge when mapping its footprint

/* --- DEM through GDAL ---------------------------------------------------------
 * Raster pixels are samples at their centres; the raster's usable area is the
 * rectangle between the outermost pixel centres, where a bilinear sample has
 * all four neighbours. Its footprint in the local frame (boundary mapped
 * through WGS84) bounds the local grid; the grid is the largest rectangle of
 * lattice nodes (at multiples of the resolution from the origin) that contains
 * the origin and whose nodes all fall in the usable area, so every node is a
 * real sample. Heights are read as heights above the ellipsoid: the geoid
 * separation (tens of metres, nearly constant over an exercise area) is
 * ignored, which shifts the whole surface but not the lines of sight. */

typedef struct {
    const char *path;
    GDALDatasetH ds;
    GDALRasterBandH band;
    OGRSpatialReferenceH wgs84, srs;
    OGRCoordinateTransformationH to_raster; // WGS84 lon/lat -> raster CRS
    OGRCoordinateTransformationH to_wgs84;  // raster CRS -> WGS84 lon/lat
    double gt[6], inv_gt[6];                // geotransform and its inverse
    int width, height;                      // raster size, pixels
    double scale;                           // metres per raster unit (scale * unit)
    double offset_m;                        // added after scaling, metres
    int wx0, wy0, ww, wh;                   // window held in memory, pixels
    float *win;                             // ww * wh heights, metres, no-data filled
} s_dem_t;

/* GDAL's last message, or a fallback. */
static const char *s_gdal_msg (const char *fallback)
{
    const char *m = CPLGetLastErrorMsg ();
    return m && *m ? m : fallback;
}

static void s_dem_close (s_dem_t *d)
{
    free (d->win);
    d->win = NULL;
    if (d->to_raster)
        OCTDestroyCoordinateTransformation (d->to_raster);
    if (d->to_wgs84)
        OCTDestroyCoordinateTransformation (d->to_wgs84);
    if (d->srs)
        OSRRelease (d->srs);
    if (d->wgs84)
        OSRRelease (d->wgs84);
    if (d->ds)
        GDALClose (d->ds);
    d->to_raster = d->to_wgs84 = NULL;
    d->srs = d->wgs84 = NULL;
    d->ds = NULL;
}

/* Metres per unit of the band's height unit; 0 when unknown. */
static double s_unit_m (const char *unit)
{
    if (!unit || !*unit || !strcasecmp (unit, "m") || !strcasecmp (unit, "metre") ||
        !strcasecmp (unit, "meter") || !strcasecmp (unit, "metres") || !strcasecmp (unit, "meters"))
        return 1;
    if (!strcasecmp (unit, "ft") || !strcasecmp (unit, "foot") || !strcasecmp (unit, "feet") ||
        !strcasecmp (unit, "international foot"))
        return 0.3048;
    if (!strcasecmp (unit, "ftUS") || !strcasecmp (unit, "US survey foot"))
        return 1200.0 / 3937.0;
    return 0;
}

/* Open the raster, its band 1, georeferencing and the transformations. */
static int s_dem_open (s_dem_t *d, char *err, size_t errlen)
{
    VSIStatBufL st;
    if (VSIStatL (d->path, &st) != 0) {
        cgs_errf (err, errlen, "%s: no such file", d->path);
        return -ENOENT;
    }
    GDALAllRegister ();
    CPLErrorReset ();
    d->ds = GDALOpenEx (d->path, GDAL_OF_RASTER | GDAL_OF_READONLY | GDAL_OF_VERBOSE_ERROR, NULL,
                        NULL, NULL);
    if (!d->ds) {
        cgs_errf (err, errlen, "%s: not a raster GDAL can read (%s)", d->path,
                  s_gdal_msg ("unknown format"));
        return -EINVAL;
    }
    if (GDALGetRasterCount (d->ds) < 1) {
        cgs_errf (err, errlen, "%s: has no raster band", d->path);
        return -EINVAL;
    }
    d->width = GDALGetRasterXSize (d->ds);
    d->height = GDALGetRasterYSize (d->ds);
    if (d->width < 2 || d->height < 2) {
        cgs_errf (err, errlen, "%s: raster is %d x %d pixels, need at least 2 x 2", d->path,
                  d->width, d->height);
        return -EINVAL;
    }
    if (GDALGetGeoTransform (d->ds, d->gt) != CE_None) {
        cgs_errf (err, errlen, "%s: not georeferenced (no geotransform)", d->path);
        return -EINVAL;
    }
    if (!GDALInvGeoTransform (d->gt, d->inv_gt)) {
        cgs_errf (err, errlen, "%s: degenerate geotransform", d->path);
        return -EINVAL;
    }
    // No guessing: a raster without a CRS may be in degrees or in any metres.
    OGRSpatialReferenceH srs = GDALGetSpatialRef (d->ds);
    if (!srs) {
        cgs_errf (err, errlen,
                  "%s: no coordinate system (give the raster one, e.g. a .prj file or "
                  "gdal_edit.py -a_srs EPSG:4326)",
                  d->path);
        return -EINVAL;
    }
    d->srs = OSRClone (srs);
    d->wgs84 = OSRNewSpatialReference (NULL);
    if (!d->srs || !d->wgs84) {
        cgs_errf (err, errlen, "%s: out of memory", d->path);
        return -ENOMEM;
    }
    if (OSRSetWellKnownGeogCS (d->wgs84, "WGS84") != OGRERR_NONE) {
        cgs_errf (err, errlen, "%s: cannot set up WGS84 (%s)", d->path, s_gdal_msg ("PROJ error"));
        return -EINVAL;
    }
    // x = longitude or easting, y = latitude or northing, whatever the CRS says.
    OSRSetAxisMappingStrategy (d->srs, OAMS_TRADITIONAL_GIS_ORDER);
    OSRSetAxisMappingStrategy (d->wgs84, OAMS_TRADITIONAL_GIS_ORDER);
    d->to_raster = OCTNewCoordinateTransformation (d->wgs84, d->srs);
    d->to_wgs84 = OCTNewCoordinateTransformation (d->srs, d->wgs84);
    if (!d->to_raster || !d->to_wgs84) {
        cgs_errf (err, errlen,
                  "%s: cannot transform between WGS84 and the raster's coordinate "
                  "system (%s)",
                  d->path, s_gdal_msg ("PROJ error"));
        return -EINVAL;
    }
    d->band = GDALGetRasterBand (d->ds, 1);
    double unit = s_unit_m (GDALGetRasterUnitType (d->band));
    if (unit == 0) {
        cgs_errf (err, errlen, "%s: band 1 heights are in an unknown unit '%s'", d->path,
                  GDALGetRasterUnitType (d->band));
        return -EINVAL;
    }
    int has = 0;
    double scale = GDALGetRasterScale (d->band, &has);
    if (!has || !isfinite (scale) || scale == 0)
        scale = 1;
    double offset = GDALGetRasterOffset (d->band, &has);
    if (!has || !isfinite (offset))
        offset = 0;
    d->scale = scale * unit;
    d->offset_m = offset * unit;
    return 0;
}

/* WGS84 lon/lat (degrees) in x, y to pixel/line, in place, for n points;
 * ok[i] is 0 where the transformation fails. */
static void s_dem_to_pixel (const s_dem_t *d, int n, double *x, double *y, int *ok)
{
    for (int i = 0; i < n; i++)
        ok[i] = 0;
    OCTTransformEx (d->to_raster, n, x, y, NULL, ok);
    const double *g = d->inv_gt;
    for (int i = 0; i < n; i++) {
        if (!ok[i] || !isfinite (x[i]) || !isfinite (y[i])) {
            ok[i] = 0;
            continue;
        }
        double X = x[i], Y = y[i];
        x[i] = g[0] + g[1] * X + g[2] * Y;
        y[i] = g[3] + g[4] * X + g[5] * Y;
    }
}

/* Pixel/line to WGS84 lon/lat (degrees), in place, for n points. */
static void s_dem_to_lonlat (const s_dem_t *d, int n, double *x, double *y, int *ok)
{
    const double *g = d->gt;
    for (int i = 0; i < n; i++) {
        double px = x[i], py = y[i];
        x[i] = g[0] + g[1] * px + g[2] * py;
        y[i] = g[3] + g[4] * px + g[5] * py;
        ok[i] = 0;
    }
    OCTTransformEx (d->to_wgs84, n, x, y, NULL, ok);
    for (int i = 0; i < n; i++)
        if (!isfinite (x[i]) || !isfinite (y[i]) || fabs (y[i]) > 90)
            ok[i] = 0;
}

/* True when pixel/line (px, py) lies between the outermost pixel centres. */
static bool s_dem_usable (const s_dem_t *d, double px, double py)
{
    const double eps = 1e-9;
    return px >= 0.5 - eps && px <= d->width - 0.5 + eps && py >= 0.5 - eps &&
           py <= d->height - 0.5 + eps;
}

/* Bilinear sample of the window at pixel/line (px, py); false outside it. */
static bool s_dem_sample (const s_dem_t *d, double px, double py, double *ret_h_m)
{
    const double eps = 1e-6;
    double x = px - 0.5 - d->wx0, y = py - 0.5 - d->wy0;
    if (!(x >= -eps && x <= d->ww - 1 + eps && y >= -eps && y <= d->wh - 1 + eps))
        return false;
    x = cgs_terrain__clamp (x, 0, d->ww - 1);
    y = cgs_terrain__clamp (y, 0, d->wh - 1);
    int i = (int)floor (x), j = (int)floor (y);
    if (i > d->ww - 2)
        i = d->ww - 2;
    if (j > d->wh - 2)
        j = d->wh - 2;
    double u = x - i, v = y - j;
    const float *p = d->win + (size_t)j * d->ww + i;
    *ret_h_m = (p[0] * (1 - u) + p[1] * u) * (1 - v) + (p[d->ww] * (1 - u) + p[d->ww + 1] * u) * v;
    return true;
}

/* Read pixels [x0, x1] x [y0, y1] of band 1 into d->win, in metres, with
 * no-data (GDAL's mask, or not finite) set to the band's lowest valid height. */
static int s_dem_read (s_dem_t *d, int x0, int y0, int x1, int y1, char *err, size_t errlen)
{
    d->wx0 = x0;
    d->wy0 = y0;
    d->ww = x1 - x0 + 1;
    d->wh = y1 - y0 + 1;
    size_t n = (size_t)d->ww * (size_t)d->wh;
    if (n * sizeof (float) > CGS_TERRAIN_MAX_READ_BYTES) {
        cgs_errf (err, errlen,
                  "%s: the area to read is %d x %d pixels (over %zu MiB); give a half extent",
                  d->path, d->ww, d->wh, CGS_TERRAIN_MAX_READ_BYTES >> 20);
        return -EINVAL;
    }
    d->win = malloc (n * sizeof *d->win);
    unsigned char *mask = NULL;
    int flags = GDALGetMaskFlags (d->band);
    if (!(flags & GMF_ALL_VALID))
        mask = malloc (n);
    if (!d->win || (!(flags & GMF_ALL_VALID) && !mask)) {
        free (mask);
        cgs_errf (err, errlen, "%s: out of memory reading %d x %d pixels", d->path, d->ww, d->wh);
        return -ENOMEM;
    }
    CPLErrorReset ();
    if (GDALRasterIO (d->band, GF_Read, x0, y0, d->ww, d->wh, d->win, d->ww, d->wh, GDT_Float32, 0,
                      0) != CE_None ||
        (mask && GDALRasterIO (GDALGetMaskBand (d->band), GF_Read, x0, y0, d->ww, d->wh, mask,
                               d->ww, d->wh, GDT_Byte, 0, 0) != CE_None)) {
        free (mask);
        cgs_errf (err, errlen, "%s: cannot read band 1 (%s)", d->path, s_gdal_msg ("read error"));
        return -EINVAL;
    }
    double lo = INFINITY;
    size_t holes = 0;
    for (size_t i = 0; i < n; i++) {
        double h = d->win[i] * d->scale + d->offset_m;
        bool valid = isfinite (h) && (!mask || mask[i]);
        d->win[i] = valid ? (float)h : NAN;
        holes += !valid;
        if (valid && d->win[i] < lo)
            lo = d->win[i];
    }
    free (mask);
    if (holes == 0)
        return 0;
    // Holes take the band's lowest valid height, not the window's, so the
    // same place gets the same height whatever extent is asked for. This
    // reads the whole band once (GDAL skips its no-data value and NaN).
    double mm[2];
    CPLErrorReset ();
    if (GDALComputeRasterMinMax (d->band, FALSE, mm) == CE_None && isfinite (mm[0]) &&
        isfinite (mm[1])) {
        double a = mm[0] * d->scale + d->offset_m, b = mm[1] * d->scale + d->offset_m;
        lo = fmin (lo, fmin (a, b)); // a negative scale swaps them
    }
    if (!isfinite (lo)) {
        cgs_errf (err, errlen, "%s: band 1 has no valid heights", d->path);
        return -EINVAL;
    }
    for (size_t i = 0; i < n; i++)
        if (isnan (d->win[i]))
            d->win[i] = (float)lo;
    return 0;
}

/* The largest rectangle of set nodes in mask (cols x rows) that contains the
 * set node (c0, r0): for each top row, a histogram of set runs per column,
 * widened from c0 outwards as the height steps down. O(cols * rows). */
static int s_best_rect (const unsigned char *mask, int cols, int rows, int c0, int r0,
                        int ret_lo[2], int ret_hi[2])
{
    int *run = calloc ((size_t)cols, sizeof *run); // set nodes ending at row r, per column
    if (!run)
        return -ENOMEM;
    double best = 0;
    int lo[2] = {c0, r0}, hi[2] = {c0, r0};
    for (int r = 0; r < rows; r++) {
        for (int c = 0; c < cols; c++)
            run[c] = mask[(size_t)r * cols + c] ? run[c] + 1 : 0;
        if (r < r0)
            continue;
        int need = r - r0 + 1; // the rectangle must reach down to row r0
        if (run[c0] < need)
            break; // column c0 is cut between r0 and r: no taller rectangle either
        int left = c0, right = c0, h = run[c0];
        for (;;) {
            while (left > 0 && run[left - 1] >= h)
                left--;
            while (right < cols - 1 && run[right + 1] >= h)
                right++;
            double area = (double)h * (right - left + 1);
            if (area > best) {
                best = area;
                lo[0] = left;
                lo[1] = r - h + 1;
                hi[0] = right;
                hi[1] = r;
            }
            int next = -1;
            if (left > 0)
                next = run[left - 1];
            if (right < cols - 1 && run[right + 1] > next)
                next = run[right + 1];
            if (next < need)
                break;
            h = next;
        }
    }
    free (run);
    ret_lo[0] = lo[0];
    ret_lo[1] = lo[1];
    ret_hi[0] = hi[0];
    ret_hi[1] = hi[1];
    return 0;
}

/* Per-row scratch arrays for the node passes. */
typedef struct {
    double *lat, *lon, *x, *y, *u;
    int *ok;
} s_rowbuf_t;

static void s_rowbuf_free (s_rowbuf_t *b)
{
    free (b->lat);
    free (b->lon);
    free (b->x);
    free (b->y);
    free (b->u);
    free (b->ok);
    memset (b, 0, sizeof *b);
}

static int s_rowbuf_alloc (s_rowbuf_t *b, int n)
{
    size_t m = n > 0 ? (size_t)n : 1;
    b->lat = malloc (m * sizeof (double));
    b->lon = malloc (m * sizeof (double));
    b->x = malloc (m * sizeof (double));
    b->y = malloc (m * sizeof (double));
    b->u = malloc (m * sizeof (double));
    b->ok = malloc (m * sizeof (int));
    if (!b->lat || !b->lon || !b->x || !b->y || !b->u || !b->ok) {
        s_rowbuf_free (b);
        return -ENOMEM;
    }
    return 0;
}

/* Pixel/line of local points (e_m[i] or e0 + i*res, n, u) in b->x, b->y;
 * lat/lon in b->lat, b->lon. */
static void s_local_to_pixel (const s_dem_t *d, const cgs_geo_t *frame, int count, double e0_m,
                              double res_m, double n_m, const double *u_m, s_rowbuf_t *b)
{
    for (int i = 0; i < count; i++) {
        cgs_geodetic_t g = {NAN, NAN, NAN};
        cgs_enu_t p = {e0_m + i * res_m, n_m, u_m ? u_m[i] : 0};
        if (cgs_geo_enu_to_geodetic (frame, p, &g) != 0)
            g.lat_deg = g.lon_deg = NAN;
        b->lat[i] = g.lat_deg;
        b->lon[i] = g.lon_deg;
        b->x[i] = g.lon_deg;
        b->y[i] = g.lat_deg;
    }
    s_dem_to_pixel (d, count, b->x, b->y, b->ok);
}

/* Local-frame bounding box of the raster's usable area. */
static int s_footprint (const s_dem_t *d, const cgs_geo_t *frame, double box[4], char *err,
                        size_t errlen)
{
    enum { N = CGS_TERRAIN_EDGE_SAMPLES };
    double x[4 * N], y[4 * N];
    int ok[4 * N];
    double x0 = 0.5, x1 = d->width - 0.5, y0 = 0.5, y1 = d->height - 0.5;
    for (int i = 0; i < N; i++) {
        double f = (double)i / N;
        x[i] = x0 + f * (x1 - x0), y[i] = y0;                 // top, west to east
        x[N + i] = x1, y[N + i] = y0 + f * (y1 - y0);         // east, top to bottom
        x[2 * N + i] = x1 - f * (x1 - x0), y[2 * N + i] = y1; // bottom, east to west
        x[3 * N + i] = x0, y[3 * N + i] = y1 - f * (y1 - y0); // west, bottom to top
    }
    s_dem_to_lonlat (d, 4 * N, x, y, ok);
    box[0] = box[1] = INFINITY;
    box[2] = box[3] = -INFINITY;
    for (int i = 0; i < 4 * N; i++) {
        cgs_enu_t p;
        if (!ok[i] || cgs_geo_geodetic_to_enu (frame, (cgs_geodetic_t){y[i], x[i], 0}, &p) != 0)
            continue;
        box[0] = fmin (box[0], p.e_m);
        box[1] = fmin (box[1], p.n_m);
        box[2] = fmax (box[2], p.e_m);
        box[3] = fmax (box[3], p.n_m);
    }
    if (!(box[0] <= box[2] && box[1] <= box[3])) {
        cgs_errf (err, errlen, "%s: cannot map the raster's edges to WGS84 (%s)", d->path,
                  s_gdal_msg ("transformation failed"));
        return -EINVAL;
    }
    return 0;
}

/* Metres per pixel at the origin: the smaller of the two pixel sides. */
static int s_pixel_size_m (const s_dem_t *d, const cgs_geo_t *frame, double px, double py,
                           double *ret_res_m, char *err, size_t errlen)
{
    double x[4] = {px - 0.5, px + 0.5, px, px}, y[4] = {py, py, py - 0.5, py + 0.5};
    int ok[4];
    cgs_enu_t p[4];
    s_dem_to_lonlat (d, 4, x, y, ok);
    for (int i = 0; i < 4; i++)
        if (!ok[i] ||
            cgs_geo_geodetic_to_enu (frame, (cgs_geodetic_t){y[i], x[i], 0}, &p[i]) != 0) {
            cgs_errf (err, errlen, "%s: cannot work out the pixel size at the origin", d->path);
            return -EINVAL;
        }
    double dx = hypot (p[1].e_m - p[0].e_m, p[1].n_m - p[0].n_m);
    double dy = hypot (p[3].e_m - p[2].e_m, p[3].n_m - p[2].n_m);
    double res = fmin (dx, dy);
    if (!(res > 0 && isfinite (res))) {
        cgs_errf (err, errlen, "%s: cannot work out the pixel size at the origin", d->path);
        return -EINVAL;
    }
    *ret_res_m = res;
    return 0;
}

/* Build the local grid from an open DEM. */
static int s_dem_build (s_dem_t *d, const cgs_geo_t *frame, double res_m, double half_m,
                        cgs_terrain_t **ret_t, char *err, size_t errlen)
{
    cgs_terrain_t *t = NULL;
    unsigned char *mask = NULL;
    s_rowbuf_t b = {0};
    int rc;

    // The origin must be in the usable area.
    cgs_geodetic_t o = cgs_geo_origin (frame);
    double ox = o.lon_deg, oy = o.lat_deg;
    int ook = 0;
    s_dem_to_pixel (d, 1, &ox, &oy, &ook);
    if (!ook || !s_dem_usable (d, ox, oy)) {
        cgs_errf (err, errlen, "%s: the exercise origin (%.6f, %.6f) is outside the raster",
                  d->path, o.lat_deg, o.lon_deg);
        return -EINVAL;
    }
    if (res_m == 0 && (rc = s_pixel_size_m (d, frame, ox, oy, &res_m, err, errlen)) != 0)
        return rc;
    if (half_m > 0 && half_m < res_m) {
        cgs_errf (err, errlen, "%s: half extent %g m is less than the resolution %g m", d->path,
                  half_m, res_m);
        return -EINVAL;
    }

    // Lattice of nodes at multiples of res_m over the footprint's bounding box.
    double box[4];
    if ((rc = s_footprint (d, frame, box, err, errlen)) != 0)
        return rc;
    if (half_m > 0) {
        box[0] = fmax (box[0], -half_m);
        box[1] = fmax (box[1], -half_m);
        box[2] = fmin (box[2], half_m);
        box[3] = fmin (box[3], half_m);
    }
    double k_lo[2], k_hi[2];
    for (int i = 0; i < 2; i++) {
        k_lo[i] = fmin (ceil (box[i] / res_m - 1e-9), 0);
        k_hi[i] = fmax (floor (box[2 + i] / res_m + 1e-9), 0);
    }
    double cols_d = k_hi[0] - k_lo[0] + 1, rows_d = k_hi[1] - k_lo[1] + 1;
    if (!(cols_d * rows_d <= (double)CGS_TERRAIN_MAX_NODES)) {
        cgs_errf (
            err, errlen,
            "%s: a grid over %.0f x %.0f m at %g m would have over 2^26 nodes; give a coarser "
            "resolution or a half extent",
            d->path, box[2] - box[0], box[3] - box[1], res_m);
        return -EINVAL;
    }
    int cols = (int)cols_d, rows = (int)rows_d;
    int c0 = (int)-k_lo[0], r0 = (int)-k_lo[1];

    // Pass 1: which nodes fall in the usable area, and the pixels they need.
    mask = calloc ((size_t)cols * (size_t)rows, 1);
    if (!mask || s_rowbuf_alloc (&b, cols) != 0) {
        cgs_errf (err, errlen, "%s: out of memory for a %d x %d grid", d->path, cols, rows);
        rc = -ENOMEM;
        goto out;
    }
    double px_lo = INFINITY, py_lo = INFINITY, px_hi = -INFINITY, py_hi = -INFINITY;
    for (int r = 0; r < rows; r++) {
        s_local_to_pixel (d, frame, cols, k_lo[0] * res_m, res_m, (k_lo[1] + r) * res_m, NULL, &b);
        for (int c = 0; c < cols; c++) {
            if (!b.ok[c] || !s_dem_usable (d, b.x[c], b.y[c]))
                continue;
            mask[(size_t)r * cols + c] = 1;
            px_lo = fmin (px_lo, b.x[c]);
            px_hi = fmax (px_hi, b.x[c]);
            py_lo = fmin (py_lo, b.y[c]);
            py_hi = fmax (py_hi, b.y[c]);
        }
    }
    if (!mask[(size_t)r0 * cols + c0]) {
        cgs_errf (err, errlen, "%s: the exercise origin (%.6f, %.6f) is outside the raster",
                  d->path, o.lat_deg, o.lon_deg);
        rc = -EINVAL;
        goto out;
    }
    int lo[2], hi[2];
    if ((rc = s_best_rect (mask, cols, rows, c0, r0, lo, hi)) != 0) {
        cgs_errf (err, errlen, "%s: out of memory", d->path);
        goto out;
    }
    if (hi[0] - lo[0] < 1 || hi[1] - lo[1] < 1) {
        cgs_errf (err, errlen,
                  "%s: the raster covers less than one %g m grid cell about the origin", d->path,
                  res_m);
        rc = -EINVAL;
        goto out;
    }

    // The window of pixels the nodes need, with a margin for the refinement
    // below (it moves a sample by u * distance / R: metres, a few pixels at most).
    const double margin = 8;
    int x0 = (int)fmax (floor (px_lo - 0.5) - margin, 0);
    int y0 = (int)fmax (floor (py_lo - 0.5) - margin, 0);
    int x1 = (int)fmin (ceil (px_hi - 0.5) + margin, d->width - 1);
    int y1 = (int)fmin (ceil (py_hi - 0.5) + margin, d->height - 1);
    if ((rc = s_dem_read (d, x0, y0, x1, y1, err, errlen)) != 0)
        goto out;

    // Pass 2: sample. A node's height is first taken below the point (e, n, 0);
    // the local up axis leans away from the ellipsoid normal by distance/R, so
    // a second sample below (e, n, u) puts the node where the surface really
    // is at (e, n).
    int gc = hi[0] - lo[0] + 1, gr = hi[1] - lo[1] + 1;
    double e0_m = (k_lo[0] + lo[0]) * res_m, n0_m = (k_lo[1] + lo[1]) * res_m;
    t = cgs_terrain__new (gc, gr, e0_m, n0_m, res_m);
    if (!t) {
        cgs_errf (err, errlen, "%s: out of memory for a %d x %d grid", d->path, gc, gr);
        rc = -ENOMEM;
        goto out;
    }
    for (int r = 0; r < gr; r++) {
        double n_m = n0_m + r * res_m;
        for (int pass = 0; pass < 2; pass++) {
            s_local_to_pixel (d, frame, gc, e0_m, res_m, n_m, pass ? b.u : NULL, &b);
            for (int c = 0; c < gc; c++) {
                double h;
                cgs_enu_t p;
                bool ok = b.ok[c] && s_dem_sample (d, b.x[c], b.y[c], &h) &&
                          cgs_geo_geodetic_to_enu (frame, (cgs_geodetic_t){b.lat[c], b.lon[c], h},
                                                   &p) == 0;
                if (ok)
                    b.u[c] = p.u_m;
                else if (pass == 0) {
                    cgs_errf (err, errlen, "%s: cannot sample the raster at local (%g, %g)",
                              d->path, e0_m + c * res_m, n_m);
                    rc = -EINVAL;
                    goto out;
                } // else keep the first sample
            }
        }
        for (int c = 0; c < gc; c++)
            t->h_m[(size_t)r * gc + c] = (float)b.u[c];
    }
    cgs_terrain__finish (t);
    *ret_t = t;
    t = NULL;
    rc = 0;
out:
    cgs_terrain_destroy (&t);
    s_rowbuf_free (&b);
    free (mask);
    return rc;
}

int cgs_terrain_load (const char *path, const cgs_geo_t *frame, double resolution_m,
                      double half_extent_m, cgs_terrain_t **ret_t, char *err, size_t errlen)
{
    if (err && errlen)
        err[0] = '\0';
    if (!path || !frame || !ret_t) {
        cgs_errf (err, errlen, "%s: no file, frame or result given", path ? path : "(null)");
        return -EINVAL;
    }
    if (!isfinite (resolution_m) || resolution_m < 0 || !isfinite (half_extent_m) ||
        half_extent_m < 0) {
        cgs_errf (err, errlen, "%s: resolution and half extent must be finite and >= 0", path);
        return -EINVAL;
    }
    // GDAL reports through a per-thread handler stack: keep it off stderr.
    CPLPushErrorHandler (CPLQuietErrorHandler);
    s_dem_t d = {.path = path};
    cgs_terrain_t *t = NULL;
    int rc = s_dem_open (&d, err, errlen);
    if (rc == 0)
        rc = s_dem_build (&d, frame, resolution_m, half_extent_m, &t, err, errlen);
    s_dem_close (&d);
    CPLPopErrorHandler ();
    if (rc == 0)
        *ret_t = t;
    return rc;
}
