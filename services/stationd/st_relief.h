/* st_relief — the map's background: a shaded-relief picture of the terrain,
 * made by GDAL's DEM processing (the hillshade gdaldem computes, Horn's
 * slope) and written as PNG, north up, with the extent it covers in the
 * exercise's local frame. Pure: no sockets, no logging. */
#ifndef ST_RELIEF_H
#define ST_RELIEF_H

#include "cgs_terrain.h"

#include <stddef.h>
#include <stdint.h>

typedef struct {
    double sun_azimuth_deg;   // light from, clockwise from north
    double sun_elevation_deg; // above the horizon
    double z_factor;          // vertical exaggeration
    int max_pixels;           // the picture's longer side at most this
} st_relief_params_t;

typedef struct {
    uint8_t *png; // the PNG file's bytes (malloc'd)
    size_t png_len;
    int width, height; // pixels
    double extent[4];  // min east, min north, max east, max north (metres): the pixels' outer edges
} st_relief_t;

/* Shade terrain into *ret (freed by st_relief_fini). 0, or -errno with the
 * reason in err (GDAL's message when GDAL failed); *ret untouched then. */
int st_relief_make (const cgs_terrain_t *terrain, const st_relief_params_t *p, st_relief_t *ret,
                    char *err, size_t errlen);
/* Free what make gave; accepts a zeroed one. */
void st_relief_fini (st_relief_t *r);

#endif
