/* im_params — imagerd's parameter file: an ASCII INI file read at start with
 * documented defaults (deploy/params/imager.ini). Every value is range-checked;
 * every error names the file, the line, the section and key, and what was
 * expected. Pure: no logging, no globals.
 *
 * Sections: [camera], [scene], [overlay], [infrared], [output], [video], [sar]. */
#ifndef IM_PARAMS_H
#define IM_PARAMS_H

#include <stdbool.h>
#include <stddef.h>

// [sar]'s struct only: the rest of im_sar.h needs im_render.h, which needs this header.
#define IM_SAR_PARAMS_ONLY
#include "im_sar.h"
#undef IM_SAR_PARAMS_ONLY

typedef enum { IM_MODE_VISIBLE = 0, IM_MODE_INFRARED = 1, IM_MODE_SAR = 2 } im_mode_t;
typedef enum { IM_WHITE_HOT = 0, IM_BLACK_HOT = 1 } im_polarity_t;

typedef struct {
    // [camera]
    int width_px, height_px;
    double frame_rate_hz; // frames per second of simulation time
    double near_m;        // nearest depth drawn
    double max_range_m;   // farthest depth drawn, and where a footprint ray is cut
    // [scene]
    double sun_azimuth_deg, sun_elevation_deg;
    double visibility_m;   // meteorological range: contrast falls to 2% (haze)
    int chunk_cells;       // terrain chunk side, cells (power of two)
    int lods;              // levels of detail
    double lod_distance_m; // full detail within this; one level coarser per doubling
    // [overlay]
    bool overlay;       // time, altitude, slant range, image centre in MGRS
    bool status_blocks; // a block of marking, force and speed by each ground vehicle in view
    bool frame_code;    // the frame number burnt in along the bottom edge (im_post_frame_code)
    // [infrared]
    im_mode_t mode;
    im_polarity_t polarity;
    double ambient_k;                    // air and shaded ground
    double sun_gain_k;                   // ground facing the sun square-on is this much warmer
    double hull_rise_k;                  // a running vehicle's body above ambient
    double engine_k;                     // a running engine deck or exhaust
    double running_gear_rise_k;          // tracks and wheels of a moving vehicle above ambient
    double glass_k;                      // windows and optics (cold: they reflect the sky)
    double person_k;                     // a person's clothing and skin
    double sky_k;                        // what the atmosphere adds along a long path
    double attenuation_per_km;           // extinction: transmission exp(−a·R)
    double display_min_k, display_max_k; // black and white of white-hot
    double blur_px;                      // Gaussian blur, standard deviation in pixels (0: none)
    double noise_k;                      // temporal noise, standard deviation in kelvin
    // [output]
    double png_rate_hz;    // numbered PNG files per second of simulation time (0: none)
    double latest_rate_hz; // latest.png refreshed per second of simulation time (0: never)
    // [video]: every frame as H.264 with MISB ST 0601 KLV in MPEG-TS
    bool video;                 // encode at all
    int video_bitrate_kbps;     // H.264 target bitrate
    double video_keyframe_s;    // an IDR frame (a place to join) at least this often
    char video_preset[16];      // x264 preset
    bool video_file;            // OUT/INSTANCE.ts
    bool video_map;             // on the bus (`video`), for the map
    char video_udp[64];         // "" none, else HOST:PORT (unicast or multicast)
    int video_ttl;              // multicast TTL (0: this host only)
    char video_local[64];       // multicast: the local address to send from ("" the route's)
    char video_mission_id[128]; // KLV tag 3; "" the exercise's name
    // [sar]: the SAR mode's chip (mode = sar)
    im_sar_params_t sar;
} im_params_t;

/* The defaults (deploy/params/imager.ini documents each). */
void im_params_defaults (im_params_t *p);
/* Read a parameter file over *p; on error *p is unchanged. 0, or a
 * negative errno with err filled ("file:line: [section] key: ..."). */
int im_params_load (const char *path, im_params_t *p, char *err, size_t errlen);
/* The same from text (name stands for the file name in errors). */
int im_params_load_string (const char *name, const char *text, im_params_t *p, char *err,
                           size_t errlen);
/* A [video] udp value, HOST:PORT with HOST a dotted IPv4 address: 0 with
 * the parts (host, port may be NULL), or -EINVAL. */
int im_params_parse_udp (const char *text, char *host, size_t hostlen, int *port);
/* Check a set built in code; 0 or -EINVAL with err filled. */
int im_params_check (const im_params_t *p, char *err, size_t errlen);

#endif
