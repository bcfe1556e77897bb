/* st_relief — shaded relief of the terrain with GDAL (see st_relief.h). */
#include "st_relief.h"

#include <cpl_conv.h>
#include <cpl_error.h>
#include <cpl_vsi.h>
#include <errno.h>
#include <gdal.h>
#include <gdal_utils.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* A unique /vsimem/ name, so concurrent callers never share a file. */
static void s_name (char *buf, size_t size, const char *what, const void *key)
{
    snprintf (buf, size, "/vsimem/st_relief_%p_%s", key, what);
}

static int s_fail (char *err, size_t errlen, const char *what)
{
    const char *msg = CPLGetLastErrorMsg ();
    snprintf (err, errlen, "%s%s%s", what, msg && *msg ? ": " : "", msg ? msg : "");
    return -EIO;
}

int st_relief_make (const cgs_terrain_t *terrain, const st_relief_params_t *p, st_relief_t *ret,
                    char *err, size_t errlen)
{
    GDALAllRegister ();
    CPLErrorReset ();
    int cols = cgs_terrain_cols (terrain), rows = cgs_terrain_rows (terrain);
    double res = cgs_terrain_resolution (terrain), e0, n0, e1, n1;
    cgs_terrain_bounds (terrain, &e0, &n0, &e1, &n1);
    if (cols < 2 || rows < 2 || !(res > 0)) {
        snprintf (err, errlen, "terrain grid %d x %d at %g m cannot be shaded", cols, rows, res);
        return -EINVAL;
    }
    char dem_name[96], shade_name[96], small_name[96], png_name[96];
    s_name (dem_name, sizeof dem_name, "dem.tif", ret);
    s_name (shade_name, sizeof shade_name, "shade.tif", ret);
    s_name (small_name, sizeof small_name, "small.tif", ret);
    s_name (png_name, sizeof png_name, "relief.png", ret);
    int rc = -EIO;
    GDALDatasetH dem = NULL, shade = NULL, small = NULL, png = NULL;
    float *line = NULL;
    GDALDEMProcessingOptions *dem_opts = NULL;
    GDALTranslateOptions *tr_opts = NULL;

    // The heights as a GDAL raster: nodes are pixel centres, row 0 is the north row.
    GDALDriverH tif = GDALGetDriverByName ("GTiff");
    if (!tif || !(dem = GDALCreate (tif, dem_name, cols, rows, 1, GDT_Float32, NULL))) {
        rc = s_fail (err, errlen, "cannot make the height raster");
        goto done;
    }
    double gt[6] = {e0 - res / 2, res, 0, n1 + res / 2, 0, -res};
    GDALSetGeoTransform (dem, gt);
    if (!(line = malloc ((size_t)cols * sizeof *line))) {
        rc = -ENOMEM;
        snprintf (err, errlen, "out of memory");
        goto done;
    }
    GDALRasterBandH band = GDALGetRasterBand (dem, 1);
    for (int r = 0; r < rows; r++) {
        int node_row = rows - 1 - r; // terrain row 0 is the southernmost
        for (int c = 0; c < cols; c++)
            line[c] = cgs_terrain_node (terrain, c, node_row);
        if (GDALRasterIO (band, GF_Write, 0, r, cols, 1, line, cols, 1, GDT_Float32, 0, 0) !=
            CE_None) {
            rc = s_fail (err, errlen, "cannot write the height raster");
            goto done;
        }
    }
    char az[32], alt[32], z[32];
    snprintf (az, sizeof az, "%.6f", p->sun_azimuth_deg);
    snprintf (alt, sizeof alt, "%.6f", p->sun_elevation_deg);
    snprintf (z, sizeof z, "%.6f", p->z_factor);
    char *dem_argv[] = {"-az", az, "-alt", alt, "-z", z, "-compute_edges", "-of", "GTiff", NULL};
    if (!(dem_opts = GDALDEMProcessingOptionsNew (dem_argv, NULL))) {
        rc = s_fail (err, errlen, "bad hillshade options");
        goto done;
    }
    int usage = 0;
    if (!(shade = GDALDEMProcessing (shade_name, dem, "hillshade", NULL, dem_opts, &usage))) {
        rc = s_fail (err, errlen, "hillshade failed");
        goto done;
    }
    // At most max_pixels on the longer side, keeping the aspect.
    int w = cols, h = rows;
    if (w > p->max_pixels || h > p->max_pixels) {
        double k = (double)p->max_pixels / (w > h ? w : h);
        w = (int)fmax (1, round (w * k));
        h = (int)fmax (1, round (h * k));
        char ws[16], hs[16];
        snprintf (ws, sizeof ws, "%d", w);
        snprintf (hs, sizeof hs, "%d", h);
        char *tr_argv[] = {"-outsize", ws, hs, "-r", "average", "-of", "GTiff", NULL};
        if (!(tr_opts = GDALTranslateOptionsNew (tr_argv, NULL)) ||
            !(small = GDALTranslate (small_name, shade, tr_opts, &usage))) {
            rc = s_fail (err, errlen, "cannot scale the relief down");
            goto done;
        }
    }
    GDALDriverH png_drv = GDALGetDriverByName ("PNG");
    if (!png_drv || !(png = GDALCreateCopy (png_drv, png_name, small ? small : shade, FALSE, NULL,
                                            NULL, NULL))) {
        rc = s_fail (err, errlen, "cannot write the relief as PNG");
        goto done;
    }
    GDALClose (png);
    png = NULL;
    vsi_l_offset len = 0;
    GByte *bytes = VSIGetMemFileBuffer (png_name, &len, FALSE);
    uint8_t *copy = bytes && len ? malloc ((size_t)len) : NULL;
    if (!copy) {
        rc = bytes ? -ENOMEM : s_fail (err, errlen, "the PNG is empty");
        if (bytes)
            snprintf (err, errlen, "out of memory");
        goto done;
    }
    memcpy (copy, bytes, (size_t)len);
    *ret = (st_relief_t){.png = copy,
                         .png_len = (size_t)len,
                         .width = w,
                         .height = h,
                         .extent = {gt[0], n0 - res / 2, e1 + res / 2, gt[3]}};
    rc = 0;
done:
    free (line);
    if (dem_opts)
        GDALDEMProcessingOptionsFree (dem_opts);
    if (tr_opts)
        GDALTranslateOptionsFree (tr_opts);
    if (png)
        GDALClose (png);
    if (small)
        GDALClose (small);
    if (shade)
        GDALClose (shade);
    if (dem)
        GDALClose (dem);
    VSIUnlink (dem_name);
    VSIUnlink (shade_name);
    VSIUnlink (small_name);
    VSIUnlink (png_name);
    char aux[128];
    snprintf (aux, sizeof aux, "%s.aux.xml", png_name);
    VSIUnlink (aux);
    return rc;
}

void st_relief_fini (st_relief_t *r)
{
    if (!r)
        return;
    free (r->png);
    memset (r, 0, sizeof *r);
}
