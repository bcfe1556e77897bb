/* im_params — imagerd's parameter file (see im_params.h). */
#include "im_params.h"
#include "cgs_config.h"

#include <arpa/inet.h>
#include <errno.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void im_params_defaults (im_params_t *p)
{
    *p = (im_params_t){
        .width_px = 640,
        .height_px = 480,
        .frame_rate_hz = 5,
        .near_m = 5,
        .max_range_m = 20000,
        .sun_azimuth_deg = 135,
        .sun_elevation_deg = 45,
        .visibility_m = 20000,
        .chunk_cells = 32,
        .lods = 5,
        .lod_distance_m = 2000,
        .overlay = true,
        .status_blocks = true,
        .mode = IM_MODE_VISIBLE,
        .polarity = IM_WHITE_HOT,
        .ambient_k = 288,
        .sun_gain_k = 12,
        .hull_rise_k = 8,
        .engine_k = 360,
        .running_gear_rise_k = 25,
        .glass_k = 275,
        .person_k = 305,
        .sky_k = 265,
        .attenuation_per_km = 0.2,
        .display_min_k = 275,
        .display_max_k = 325,
        .blur_px = 0.8,
        .noise_k = 0.3,
        .png_rate_hz = 0,
        .latest_rate_hz = 1,
        .video = true,
        .video_bitrate_kbps = 2000,
        .video_keyframe_s = 1,
        .video_preset = "veryfast",
        .video_file = true,
        .video_map = true,
        .video_ttl = 1,
    };
    im_sar_params_defaults (&p->sar);
}

#define S_R(sec, k, field, lo, hi)                                                                 \
    {                                                                                              \
        sec, k, offsetof (im_params_t, field), lo, hi                                              \
    }
static const cgs_config_real_t s_reals[] = {
    S_R ("camera", "frame_rate_hz", frame_rate_hz, 0.01, 100.0),
    S_R ("camera", "near_m", near_m, 0.1, 1000.0),
    S_R ("camera", "max_range_m", max_range_m, 100.0, 1e6),
    S_R ("scene", "sun_azimuth_deg", sun_azimuth_deg, 0.0, 360.0),
    S_R ("scene", "sun_elevation_deg", sun_elevation_deg, -90.0, 90.0),
    S_R ("scene", "visibility_m", visibility_m, 10.0, 1e7),
    S_R ("scene", "lod_distance_m", lod_distance_m, 10.0, 1e6),
    S_R ("infrared", "ambient_k", ambient_k, 150.0, 400.0),
    S_R ("infrared", "sun_gain_k", sun_gain_k, 0.0, 100.0),
    S_R ("infrared", "hull_rise_k", hull_rise_k, 0.0, 200.0),
    S_R ("infrared", "engine_k", engine_k, 150.0, 1000.0),
    S_R ("infrared", "running_gear_rise_k", running_gear_rise_k, 0.0, 200.0),
    S_R ("infrared", "glass_k", glass_k, 150.0, 400.0),
    S_R ("infrared", "person_k", person_k, 150.0, 400.0),
    S_R ("infrared", "sky_k", sky_k, 100.0, 400.0),
    S_R ("infrared", "attenuation_per_km", attenuation_per_km, 0.0, 10.0),
    S_R ("infrared", "display_min_k", display_min_k, 100.0, 1000.0),
    S_R ("infrared", "display_max_k", display_max_k, 100.0, 1000.0),
    S_R ("infrared", "blur_px", blur_px, 0.0, 10.0),
    S_R ("infrared", "noise_k", noise_k, 0.0, 50.0),
    S_R ("output", "png_rate_hz", png_rate_hz, 0.0, 100.0),
    S_R ("output", "latest_rate_hz", latest_rate_hz, 0.0, 100.0),
    S_R ("video", "keyframe_s", video_keyframe_s, 0.1, 60.0),
};
#undef S_R
#define S_NREALS (sizeof s_reals / sizeof s_reals[0])

#define S_I(sec, k, field, lo, hi)                                                                 \
    {                                                                                              \
        sec, k, offsetof (im_params_t, field), lo, hi                                              \
    }
static const cgs_config_int_t s_ints[] = {
    S_I ("camera", "width_px", width_px, 16, 4096),
    S_I ("camera", "height_px", height_px, 16, 4096),
    S_I ("scene", "chunk_cells", chunk_cells, 2, 1024),
    S_I ("scene", "lods", lods, 1, 6),
    S_I ("video", "bitrate_kbps", video_bitrate_kbps, 50, 100000),
    S_I ("video", "ttl", video_ttl, 0, 255),
};
#undef S_I
#define S_NINTS (sizeof s_ints / sizeof s_ints[0])

/* What the tables cannot say: relations between keys. */
static bool s_relations (const im_params_t *p, const char **sec, const char **key, char *msg,
                         size_t msglen)
{
    if (p->chunk_cells & (p->chunk_cells - 1)) {
        *sec = "scene", *key = "chunk_cells";
        snprintf (msg, msglen, "expected a power of two, got %d", p->chunk_cells);
    } else if (!(p->max_range_m > p->near_m)) {
        *sec = "camera", *key = "max_range_m";
        snprintf (msg, msglen, "expected more than near_m (%g), got %g", p->near_m, p->max_range_m);
    } else if (!(p->display_max_k > p->display_min_k)) {
        *sec = "infrared", *key = "display_max_k";
        snprintf (msg, msglen, "expected more than display_min_k (%g), got %g", p->display_min_k,
                  p->display_max_k);
    } else if ((unsigned)p->mode > IM_MODE_SAR) {
        *sec = "infrared", *key = "mode";
        snprintf (msg, msglen, "expected visible, infrared or sar, got %d", (int)p->mode);
    } else if (p->video && (p->width_px % 2 || p->height_px % 2)) {
        *sec = "camera", *key = p->width_px % 2 ? "width_px" : "height_px";
        snprintf (msg, msglen, "expected an even size for the video (H.264 4:2:0), got %d x %d",
                  p->width_px, p->height_px);
    } else if (p->video_udp[0] && im_params_parse_udp (p->video_udp, NULL, 0, NULL) < 0) {
        *sec = "video", *key = "udp";
        snprintf (msg, msglen, "expected HOST:PORT (an IPv4 address, port 1..65535), got '%s'",
                  p->video_udp);
    } else if ((unsigned)p->polarity > IM_BLACK_HOT) {
        *sec = "infrared", *key = "polarity";
        snprintf (msg, msglen, "expected white-hot or black-hot, got %d", (int)p->polarity);
    } else {
        return false;
    }
    return true;
}

int im_params_check (const im_params_t *p, char *err, size_t errlen)
{
    const char *sec = NULL, *key = NULL;
    char msg[256] = "";
    if (!cgs_config_table_out_of_range (s_reals, S_NREALS, s_ints, S_NINTS, p, &sec, &key, msg,
                                        sizeof msg))
        s_relations (p, &sec, &key, msg, sizeof msg);
    if (key)
        return cgs_config_value_error (NULL, sec, key, msg, err, errlen);
    return im_sar_params_check (&p->sar, err, errlen);
}

static int s_read (cgs_config_t *cfg, void *arg, char *err, size_t errlen)
{
    im_params_t *out = arg, p = *out;
    int rc = cgs_config_check_repeated (cfg, err, errlen);
    if (rc == 0)
        rc = cgs_config_get_table (cfg, s_reals, S_NREALS, s_ints, S_NINTS, &p, err, errlen);
    // The camera's pointing moved to uavsim, so that every service builds the
    // same camera: an older file that still sets it is told where it went.
    static const char *const moved[][2] = {{"stabilized", "sensor_stabilized"},
                                           {"staring", "sensor_stare = target"}};
    for (int k = 0; rc == 0 && k < 2; k++)
        if (cgs_config_has (cfg, "camera", moved[k][0]))
            rc = cgs_config_error (cfg, "camera", moved[k][0], 0, err, errlen,
                                   "no longer imagerd's: the scenario's [uav] %s sets it (and "
                                   "`mscgs camera` or the map at run time), so that the image "
                                   "and the footprint agree",
                                   moved[k][1]);
    if (rc == 0)
        rc = cgs_config_get_bool (cfg, "overlay", "enabled", p.overlay, &p.overlay, err, errlen);
    if (rc == 0)
        rc = cgs_config_get_bool (cfg, "overlay", "status_blocks", p.status_blocks,
                                  &p.status_blocks, err, errlen);
    if (rc == 0)
        rc = cgs_config_get_bool (cfg, "overlay", "frame_code", p.frame_code, &p.frame_code, err,
                                  errlen);
    static const char *const modes[] = {"visible", "infrared", "sar", NULL};
    static const char *const polarities[] = {"white-hot", "black-hot", NULL};
    int mode = (int)p.mode, polarity = (int)p.polarity;
    if (rc == 0)
        rc = cgs_config_get_enum (cfg, "infrared", "mode", modes, mode, &mode, err, errlen);
    if (rc == 0)
        rc = cgs_config_get_enum (cfg, "infrared", "polarity", polarities, polarity, &polarity, err,
                                  errlen);
    p.mode = (im_mode_t)mode;
    p.polarity = (im_polarity_t)polarity;
    if (rc == 0)
        rc = cgs_config_get_bool (cfg, "video", "enabled", p.video, &p.video, err, errlen);
    if (rc == 0)
        rc = cgs_config_get_bool (cfg, "video", "file", p.video_file, &p.video_file, err, errlen);
    if (rc == 0)
        rc = cgs_config_get_bool (cfg, "video", "map", p.video_map, &p.video_map, err, errlen);
    static const char *const presets[] = {"ultrafast", "superfast", "veryfast", "faster",   "fast",
                                          "medium",    "slow",      "slower",   "veryslow", NULL};
    int preset = 0;
    while (presets[preset] && strcmp (presets[preset], p.video_preset) != 0)
        preset++;
    if (!presets[preset])
        preset = 2; // a set built in code with a preset not in the list: veryfast
    if (rc == 0)
        rc = cgs_config_get_enum (cfg, "video", "preset", presets, preset, &preset, err, errlen);
    if (rc == 0)
        snprintf (p.video_preset, sizeof p.video_preset, "%s", presets[preset]);
    struct {
        const char *key;
        char *dst;
        size_t cap;
    } strs[] = {{"udp", p.video_udp, sizeof p.video_udp},
                {"local_address", p.video_local, sizeof p.video_local},
                {"mission_id", p.video_mission_id, sizeof p.video_mission_id}};
    for (size_t i = 0; rc == 0 && i < sizeof strs / sizeof strs[0]; i++) {
        char def[128];
        snprintf (def, sizeof def, "%s", strs[i].dst);
        const char *v = NULL;
        rc = cgs_config_get_string (cfg, "video", strs[i].key, def, &v, err, errlen);
        if (rc == 0 && strlen (v) >= strs[i].cap)
            rc = cgs_config_error (cfg, "video", strs[i].key, 0, err, errlen,
                                   "expected at most %zu bytes, got %zu", strs[i].cap - 1,
                                   strlen (v));
        if (rc == 0)
            snprintf (strs[i].dst, strs[i].cap, "%s", v);
    }
    struct in_addr ia;
    if (rc == 0 && p.video_local[0] && inet_pton (AF_INET, p.video_local, &ia) != 1)
        rc = cgs_config_error (cfg, "video", "local_address", 0, err, errlen,
                               "expected an IPv4 address of this host, got '%s'", p.video_local);
    if (rc == 0)
        rc = im_sar_params_read (cfg, &p.sar, err, errlen);
    if (rc == 0)
        rc = cgs_config_check_unused (cfg, err, errlen);
    if (rc == 0) {
        const char *sec = NULL, *key = NULL;
        char msg[256];
        if (s_relations (&p, &sec, &key, msg, sizeof msg))
            rc = cgs_config_value_error (cfg, sec, key, msg, err, errlen);
    }
    if (rc < 0)
        return rc;
    *out = p;
    return 0;
}

int im_params_parse_udp (const char *text, char *host, size_t hostlen, int *port)
{
    const char *colon = text ? strrchr (text, ':') : NULL;
    if (!colon || colon == text || (size_t)(colon - text) >= 64)
        return -EINVAL;
    char h[64];
    memcpy (h, text, (size_t)(colon - text));
    h[colon - text] = '\0';
    struct in_addr ia;
    char *end;
    long n = strtol (colon + 1, &end, 10);
    if (inet_pton (AF_INET, h, &ia) != 1 || end == colon + 1 || *end || n < 1 || n > 65535)
        return -EINVAL;
    if (host)
        snprintf (host, hostlen, "%s", h);
    if (port)
        *port = (int)n;
    return 0;
}

int im_params_load (const char *path, im_params_t *p, char *err, size_t errlen)
{
    return cgs_config_read (path, NULL, s_read, p, err, errlen);
}

int im_params_load_string (const char *name, const char *text, im_params_t *p, char *err,
                           size_t errlen)
{
    return cgs_config_read (name, text, s_read, p, err, errlen);
}
