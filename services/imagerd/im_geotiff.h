/* im_geotiff — a SAR chip as a GeoTIFF a GIS opens: the chip resampled
 * onto a north-up grid in the UTM zone of its centre (WGS84, the EPSG code
 * set), one Byte band of the chip's display grey (1..255; 0 is nodata,
 * outside the chip), at the chip's pixel spacing. Each map pixel is a
 * ground point (on the terrain, so the map is orthorectified; without
 * terrain, flat ground at height 0), coloured by where that point's return
 * falls in the chip (layover and shadow are where the radar put them).
 * Metadata: the time (TIFFTAG_DATETIME and SAR_TIME, UTC), grazing and
 * squint angles, slant range, resolutions, geometry. Written to PATH.tmp
 * and renamed over PATH, so a reader never sees half a file. GDAL's
 * messages come back in err, never on stderr. Pure otherwise. */
#ifndef IM_GEOTIFF_H
#define IM_GEOTIFF_H

#include "cgs_geo.h"
#include "cgs_terrain.h"
#include "im_sar.h"

#include <stddef.h>

/* Write sar's last chip to path. frame: the exercise's local frame (its
 * ENU is the chip's); terrain: the ground the chip was made over (NULL:
 * flat at height 0); time_s: the chip's time, seconds since 1970 UTC.
 * 0; -EINVAL (no chip yet, bad arguments), -EACCES/-ENOENT (the folder),
 * -EIO (GDAL could not write), -ENOMEM; the reason in err. */
int im_geotiff_write (const char *path, const im_sar_t *sar, const cgs_geo_t *frame,
                      const cgs_terrain_t *terrain, double time_s, char *err, size_t errlen);

#endif
