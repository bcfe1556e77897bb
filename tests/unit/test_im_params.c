/* Unit tests of im_params: the defaults, the shipped parameter file (which
 * must give exactly the defaults and document every key), every key read
 * from text, and every kind of error with its file, line, section and key
 * (ranges, the relations between keys: a power-of-two chunk, max_range_m
 * beyond near_m, display_max_k above display_min_k; the mode and polarity
 * names); a refused file leaves the parameters as they were; a set built
 * in code is checked too. The [sar] section (the SAR mode's chip): every
 * key, its errors on its line, and its relations (bandwidth under a quarter
 * of the centre frequency, a chip whose grid fits). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "cgs_config.h"
#include "im_params.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

// Every key the file takes, by section (the shipped file must give them all).
static const char *const s_keys[][2] = {
    {"camera", "width_px"},
    {"camera", "height_px"},
    {"camera", "frame_rate_hz"},
    {"camera", "near_m"},
    {"camera", "max_range_m"},
    {"scene", "sun_azimuth_deg"},
    {"scene", "sun_elevation_deg"},
    {"scene", "visibility_m"},
    {"scene", "chunk_cells"},
    {"scene", "lods"},
    {"scene", "lod_distance_m"},
    {"overlay", "enabled"},
    {"overlay", "status_blocks"},
    {"infrared", "mode"},
    {"infrared", "polarity"},
    {"infrared", "ambient_k"},
    {"infrared", "sun_gain_k"},
    {"infrared", "hull_rise_k"},
    {"infrared", "engine_k"},
    {"infrared", "running_gear_rise_k"},
    {"infrared", "glass_k"},
    {"infrared", "person_k"},
    {"infrared", "sky_k"},
    {"infrared", "attenuation_per_km"},
    {"infrared", "display_min_k"},
    {"infrared", "display_max_k"},
    {"infrared", "blur_px"},
    {"infrared", "noise_k"},
    {"output", "png_rate_hz"},
    {"output", "latest_rate_hz"},
    {"video", "enabled"},
    {"video", "bitrate_kbps"},
    {"video", "keyframe_s"},
    {"video", "preset"},
    {"video", "file"},
    {"video", "map"},
    {"video", "udp"},
    {"video", "ttl"},
    {"video", "local_address"},
    {"video", "mission_id"},
    {"sar", "fc_hz"},
    {"sar", "bandwidth_hz"},
    {"sar", "integration_deg"},
    {"sar", "window"},
    {"sar", "looks"},
    {"sar", "scene_m"},
    {"sar", "size_px"},
    {"sar", "max_widen"},
    {"sar", "gmti"},
    {"sar", "gmti_sigma_mps"},
    {"sar", "geometry"},
    {"sar", "speckle"},
    {"sar", "ground_gamma_db"},
    {"sar", "woods_gamma_db"},
    {"sar", "vehicle_rcs_m2"},
    {"sar", "nesz_db"},
    {"sar", "display_max_db"},
    {"sar", "dynamic_range_db"},
};

static void s_assert_equal (const im_params_t *a, const im_params_t *b)
{
#define S_SAME(f)                                                                                  \
    do {                                                                                           \
        if (a->f != b->f)                                                                          \
            fail_msg ("%s: %.17g != %.17g", #f, (double)a->f, (double)b->f);                       \
    } while (0)
    S_SAME (width_px);
    S_SAME (height_px);
    S_SAME (frame_rate_hz);
    S_SAME (near_m);
    S_SAME (max_range_m);
    S_SAME (sun_azimuth_deg);
    S_SAME (sun_elevation_deg);
    S_SAME (visibility_m);
    S_SAME (chunk_cells);
    S_SAME (lods);
    S_SAME (lod_distance_m);
    S_SAME (overlay);
    S_SAME (status_blocks);
    S_SAME (frame_code);
    S_SAME (mode);
    S_SAME (polarity);
    S_SAME (ambient_k);
    S_SAME (sun_gain_k);
    S_SAME (hull_rise_k);
    S_SAME (engine_k);
    S_SAME (running_gear_rise_k);
    S_SAME (glass_k);
    S_SAME (person_k);
    S_SAME (sky_k);
    S_SAME (attenuation_per_km);
    S_SAME (display_min_k);
    S_SAME (display_max_k);
    S_SAME (blur_px);
    S_SAME (noise_k);
    S_SAME (png_rate_hz);
    S_SAME (latest_rate_hz);
    S_SAME (video);
    S_SAME (video_bitrate_kbps);
    S_SAME (video_keyframe_s);
    S_SAME (video_file);
    S_SAME (video_map);
    S_SAME (video_ttl);
    S_SAME (sar.fc_hz);
    S_SAME (sar.bandwidth_hz);
    S_SAME (sar.integration_deg);
    S_SAME (sar.window);
    S_SAME (sar.looks);
    S_SAME (sar.scene_m);
    S_SAME (sar.size_px);
    S_SAME (sar.max_widen);
    S_SAME (sar.gmti);
    S_SAME (sar.gmti_sigma_mps);
    S_SAME (sar.geometry);
    S_SAME (sar.speckle);
    S_SAME (sar.ground_gamma_db);
    S_SAME (sar.woods_gamma_db);
    S_SAME (sar.vehicle_rcs_m2);
    S_SAME (sar.nesz_db);
    S_SAME (sar.display_max_db);
    S_SAME (sar.dynamic_range_db);
#undef S_SAME
#define S_SAME_STR(f)                                                                              \
    do {                                                                                           \
        if (strcmp (a->f, b->f) != 0)                                                              \
            fail_msg ("%s: '%s' != '%s'", #f, a->f, b->f);                                         \
    } while (0)
    S_SAME_STR (video_preset);
    S_SAME_STR (video_udp);
    S_SAME_STR (video_local);
    S_SAME_STR (video_mission_id);
#undef S_SAME_STR
}

/* A set in which every field differs from its default (and is valid). */
static im_params_t s_not_defaults (void)
{
    return (im_params_t){
        .width_px = 1280,
        .height_px = 720,
        .frame_rate_hz = 10,
        .near_m = 2,
        .max_range_m = 30000,
        .sun_azimuth_deg = 200,
        .sun_elevation_deg = 20,
        .visibility_m = 8000,
        .chunk_cells = 64,
        .lods = 3,
        .lod_distance_m = 1500,
        .overlay = false,
        .status_blocks = false,
        .frame_code = true,
        .mode = IM_MODE_INFRARED,
        .polarity = IM_BLACK_HOT,
        .ambient_k = 290,
        .sun_gain_k = 10,
        .hull_rise_k = 9,
        .engine_k = 350,
        .running_gear_rise_k = 20,
        .glass_k = 270,
        .person_k = 306,
        .sky_k = 260,
        .attenuation_per_km = 0.3,
        .display_min_k = 270,
        .display_max_k = 330,
        .blur_px = 1.5,
        .noise_k = 0.2,
        .png_rate_hz = 2,
        .latest_rate_hz = 0.5,
        .video = false,
        .video_bitrate_kbps = 500,
        .video_keyframe_s = 2,
        .video_preset = "ultrafast",
        .video_file = false,
        .video_map = false,
        .video_udp = "239.1.2.5:5600",
        .video_ttl = 0,
        .video_local = "127.0.0.1",
        .video_mission_id = "training-7",
        .sar = {.fc_hz = 10e9,
                .bandwidth_hz = 300e6,
                .integration_deg = 1.5,
                .window = IM_SAR_WINDOW_HAMMING,
                .looks = 4,
                .scene_m = 512,
                .max_widen = 4,
                .gmti = false,
                .gmti_sigma_mps = 0.5,
                .size_px = 512,
                .geometry = IM_SAR_SLANT,
                .speckle = false,
                .ground_gamma_db = -15,
                .woods_gamma_db = -9,
                .vehicle_rcs_m2 = 50,
                .nesz_db = -25,
                .display_max_db = 0,
                .dynamic_range_db = 30},
    };
}

static void s_load (const char *text, im_params_t *p)
{
    char err[512] = "";
    if (im_params_load_string ("i.ini", text, p, err, sizeof err) != 0)
        fail_msg ("load failed: %s", err);
}

// Loading text as "i.ini" fails with -EINVAL, exactly the message expected,
// and leaves *p alone.
static void s_fails (const char *text, const char *expected)
{
    im_params_t p, before;
    im_params_defaults (&p);
    p.lod_distance_m = 1234; // not a default: a partial write would show
    before = p;
    char err[512] = "";
    int rc = im_params_load_string ("i.ini", text, &p, err, sizeof err);
    if (rc != -EINVAL)
        fail_msg ("expected -EINVAL, got %d (%s) for:\n%s", rc, err, text);
    s_assert_equal (&p, &before);
    assert_string_equal (err, expected);
}

static void test_defaults (void **state)
{
    (void)state;
    im_params_t p;
    memset (&p, 0x5a, sizeof p);
    im_params_defaults (&p);
    assert_int_equal (p.width_px, 640);
    assert_int_equal (p.height_px, 480);
    assert_true (p.frame_rate_hz == 5);
    assert_true (p.near_m == 5);
    assert_true (p.max_range_m == 20000);
    assert_true (p.sun_azimuth_deg == 135);
    assert_true (p.sun_elevation_deg == 45);
    assert_true (p.visibility_m == 20000);
    assert_int_equal (p.chunk_cells, 32);
    assert_int_equal (p.lods, 5);
    assert_true (p.lod_distance_m == 2000);
    assert_true (p.overlay);
    assert_false (p.frame_code);
    assert_int_equal (p.mode, IM_MODE_VISIBLE);
    assert_int_equal (p.polarity, IM_WHITE_HOT);
    assert_true (p.ambient_k == 288);
    assert_true (p.sun_gain_k == 12);
    assert_true (p.hull_rise_k == 8);
    assert_true (p.engine_k == 360);
    assert_true (p.running_gear_rise_k == 25);
    assert_true (p.glass_k == 275);
    assert_true (p.person_k == 305);
    assert_true (p.sky_k == 265);
    assert_true (p.attenuation_per_km == 0.2);
    assert_true (p.display_min_k == 275);
    assert_true (p.display_max_k == 325);
    assert_true (p.blur_px == 0.8);
    assert_true (p.noise_k == 0.3);
    assert_true (p.png_rate_hz == 0);
    assert_true (p.latest_rate_hz == 1);
    assert_true (p.video && p.video_file && p.video_map);
    assert_int_equal (p.video_bitrate_kbps, 2000);
    assert_true (p.video_keyframe_s == 1);
    assert_string_equal (p.video_preset, "veryfast");
    assert_string_equal (p.video_udp, "");
    assert_int_equal (p.video_ttl, 1);
    assert_string_equal (p.video_local, "");
    assert_string_equal (p.video_mission_id, "");
    assert_true (p.sar.fc_hz == 9.6e9);
    assert_true (p.sar.bandwidth_hz == 133e6);
    assert_true (p.sar.integration_deg == 0.79);
    assert_int_equal (p.sar.window, IM_SAR_WINDOW_TAYLOR);
    assert_int_equal (p.sar.looks, 1);
    assert_true (p.sar.scene_m == 256);
    assert_true (p.sar.max_widen == 16);
    assert_true (p.sar.gmti);
    assert_true (p.sar.gmti_sigma_mps == 0.25);
    assert_int_equal (p.sar.size_px, 256);
    assert_int_equal (p.sar.geometry, IM_SAR_GROUND);
    assert_true (p.sar.speckle);
    assert_true (p.sar.ground_gamma_db == -12);
    assert_true (p.sar.woods_gamma_db == -7);
    assert_true (p.sar.vehicle_rcs_m2 == 100);
    assert_true (p.sar.nesz_db == -30);
    assert_true (p.sar.display_max_db == 5);
    assert_true (p.sar.dynamic_range_db == 40);
    char err[256] = "";
    assert_int_equal (im_params_check (&p, err, sizeof err), 0);
    im_params_t q = s_not_defaults ();
    assert_int_equal (im_params_check (&q, err, sizeof err), 0);
}

// The shipped file gives every key, and exactly the defaults.
static void test_shipped_file (void **state)
{
    (void)state;
    const char *root = getenv ("CGS_ROOT");
    char path[1024], err[512] = "";
    snprintf (path, sizeof path, "%s/deploy/params/imager.ini", root ? root : ".");
    im_params_t p, def;
    im_params_defaults (&def);
    memset (&p, 0, sizeof p);
    p.mode = IM_MODE_INFRARED; // loading over a non-default set writes every field back
    p.width_px = 100;
    if (im_params_load (path, &p, err, sizeof err) != 0)
        fail_msg ("%s", err);
    s_assert_equal (&p, &def);
    im_params_t over = s_not_defaults ();
    if (im_params_load (path, &over, err, sizeof err) != 0)
        fail_msg ("%s", err);
    s_assert_equal (&over, &def);
    cgs_config_t *cfg = NULL;
    if (cgs_config_load (path, &cfg, err, sizeof err) != 0)
        fail_msg ("%s", err);
    for (size_t i = 0; i < sizeof s_keys / sizeof s_keys[0]; i++)
        if (!cgs_config_has (cfg, s_keys[i][0], s_keys[i][1]))
            fail_msg ("%s has no [%s] %s", path, s_keys[i][0], s_keys[i][1]);
    assert_int_equal (cgs_config_section_count (cfg), 7);
    cgs_config_destroy (&cfg);
}

// Every key read from text lands in its field; a key left out keeps its value.
static void test_values (void **state)
{
    (void)state;
    im_params_t p;
    im_params_defaults (&p);
    s_load ("[camera]\n"
            "width_px = 1280\n"
            "height_px = 720\n"
            "frame_rate_hz = 10\n"
            "near_m = 2\n"
            "max_range_m = 30000\n"
            "[scene]\n"
            "sun_azimuth_deg = 200\n"
            "sun_elevation_deg = 20\n"
            "visibility_m = 8000\n"
            "chunk_cells = 64\n"
            "lods = 3\n"
            "lod_distance_m = 1500\n"
            "[overlay]\n"
            "enabled = false\n"
            "status_blocks = no\n"
            "frame_code = yes\n"
            "[infrared]\n"
            "mode = infrared\n"
            "polarity = black-hot\n"
            "ambient_k = 290\n"
            "sun_gain_k = 10\n"
            "hull_rise_k = 9\n"
            "engine_k = 350\n"
            "running_gear_rise_k = 20\n"
            "glass_k = 270\n"
            "person_k = 306\n"
            "sky_k = 260\n"
            "attenuation_per_km = 0.3\n"
            "display_min_k = 270\n"
            "display_max_k = 330\n"
            "blur_px = 1.5\n"
            "noise_k = 0.2\n"
            "[output]\n"
            "png_rate_hz = 2\n"
            "latest_rate_hz = 0.5\n"
            "[video]\n"
            "enabled = false\n"
            "bitrate_kbps = 500\n"
            "keyframe_s = 2\n"
            "preset = ultrafast\n"
            "file = false\n"
            "map = false\n"
            "udp = 239.1.2.5:5600\n"
            "ttl = 0\n"
            "local_address = 127.0.0.1\n"
            "mission_id = training-7\n"
            "[sar]\n"
            "fc_hz = 10e9\n"
            "bandwidth_hz = 300e6\n"
            "integration_deg = 1.5\n"
            "window = hamming\n"
            "looks = 4\n"
            "scene_m = 512\n"
            "max_widen = 4\n"
            "gmti = false\n"
            "gmti_sigma_mps = 0.5\n"
            "size_px = 512\n"
            "geometry = slant\n"
            "speckle = false\n"
            "ground_gamma_db = -15\n"
            "woods_gamma_db = -9\n"
            "vehicle_rcs_m2 = 50\n"
            "nesz_db = -25\n"
            "display_max_db = 0\n"
            "dynamic_range_db = 30\n",
            &p);
    im_params_t want = s_not_defaults ();
    s_assert_equal (&p, &want);
    // Names are case-insensitive; a key left out keeps its value.
    s_load ("[infrared]\nmode = VISIBLE\npolarity = White-Hot\n", &p);
    want.mode = IM_MODE_VISIBLE;
    want.polarity = IM_WHITE_HOT;
    s_assert_equal (&p, &want);
    s_load ("[camera]\nnear_m = 1\n[overlay]\nenabled = 1\n", &p);
    want.near_m = 1;
    want.overlay = true;
    s_assert_equal (&p, &want);
    // An empty file changes nothing.
    s_load ("", &p);
    s_assert_equal (&p, &want);
    // The edges of the ranges are taken.
    im_params_defaults (&p);
    s_load ("[camera]\nwidth_px = 16\nheight_px = 4096\nnear_m = 0.1\nmax_range_m = 100\n"
            "[scene]\nchunk_cells = 2\nlods = 6\n[infrared]\nnoise_k = 0\nblur_px = 10\n",
            &p);
    assert_int_equal (p.width_px, 16);
    assert_int_equal (p.height_px, 4096);
    assert_int_equal (p.chunk_cells, 2);
    assert_int_equal (p.lods, 6);
    s_load ("[scene]\nchunk_cells = 1024\n", &p);
    assert_int_equal (p.chunk_cells, 1024);
}

static void test_range_errors (void **state)
{
    (void)state;
    s_fails ("[camera]\nwidth_px = 8\n",
             "i.ini:2: [camera] width_px: expected an integer in [16, 4096], got '8'");
    s_fails ("[camera]\n\nheight_px = 5000\n",
             "i.ini:3: [camera] height_px: expected an integer in [16, 4096], got '5000'");
    s_fails ("[camera]\nwidth_px = 640.5\n",
             "i.ini:2: [camera] width_px: expected an integer in [16, 4096], got '640.5'");
    s_fails ("[camera]\nframe_rate_hz = 0\n",
             "i.ini:2: [camera] frame_rate_hz: expected a number in [0.01, 100], got '0'");
    s_fails ("[camera]\nnear_m = abc\n",
             "i.ini:2: [camera] near_m: expected a number in [0.1, 1000], got 'abc'");
    s_fails ("[camera]\nmax_range_m = 50\n",
             "i.ini:2: [camera] max_range_m: expected a number in [100, 1000000], got '50'");
    s_fails ("[scene]\nsun_elevation_deg = 91\n",
             "i.ini:2: [scene] sun_elevation_deg: expected a number in [-90, 90], got '91'");
    s_fails ("[scene]\nchunk_cells = 2048\n",
             "i.ini:2: [scene] chunk_cells: expected an integer in [2, 1024], got '2048'");
    s_fails ("[scene]\nlods = 0\n",
             "i.ini:2: [scene] lods: expected an integer in [1, 6], got '0'");
    s_fails ("[scene]\nlods = 7\n",
             "i.ini:2: [scene] lods: expected an integer in [1, 6], got '7'");
    s_fails ("[infrared]\nblur_px = -1\n",
             "i.ini:2: [infrared] blur_px: expected a number in [0, 10], got '-1'");
    s_fails ("[infrared]\nnoise_k = nan\n",
             "i.ini:2: [infrared] noise_k: expected a number in [0, 50], got 'nan'");
    s_fails ("[output]\npng_rate_hz = 101\n",
             "i.ini:2: [output] png_rate_hz: expected a number in [0, 100], got '101'");
    // The camera's pointing is uavsim's now: an older file is told where it went.
    s_fails ("[camera]\nstabilized = yes\n",
             "i.ini:2: [camera] stabilized: no longer imagerd's: the scenario's [uav] "
             "sensor_stabilized sets it (and `mscgs camera` or the map at run time), so that "
             "the image and the footprint agree");
    s_fails ("[camera]\nwidth_px = 320\nstaring = on\n",
             "i.ini:3: [camera] staring: no longer imagerd's: the scenario's [uav] sensor_stare "
             "= target sets it (and `mscgs camera` or the map at run time), so that the image "
             "and the footprint agree");
    s_fails ("[overlay]\nenabled = 2\n",
             "i.ini:2: [overlay] enabled: expected true/false, yes/no, on/off or 1/0, got '2'");
}

// Relations between keys, each reported on the line of the key named.
static void test_relation_errors (void **state)
{
    (void)state;
    s_fails ("[scene]\nchunk_cells = 48\n",
             "i.ini:2: [scene] chunk_cells: expected a power of two, got 48");
    s_fails ("[scene]\nlods = 2\nchunk_cells = 3\n",
             "i.ini:3: [scene] chunk_cells: expected a power of two, got 3");
    s_fails ("[scene]\nchunk_cells = 1000\n",
             "i.ini:2: [scene] chunk_cells: expected a power of two, got 1000");
    s_fails ("[camera]\nnear_m = 500\nmax_range_m = 400\n",
             "i.ini:3: [camera] max_range_m: expected more than near_m (500), got 400");
    s_fails ("[camera]\nmax_range_m = 500\nnear_m = 500\n",
             "i.ini:2: [camera] max_range_m: expected more than near_m (500), got 500");
    s_fails ("[infrared]\ndisplay_min_k = 300\ndisplay_max_k = 290\n",
             "i.ini:3: [infrared] display_max_k: expected more than display_min_k (300), got 290");
    s_fails ("[infrared]\ndisplay_max_k = 300\ndisplay_min_k = 300\n",
             "i.ini:2: [infrared] display_max_k: expected more than display_min_k (300), got 300");
    // The key named is not in the file: no line, the file's name.
    s_fails ("[infrared]\ndisplay_min_k = 325\n",
             "i.ini: [infrared] display_max_k: expected more than display_min_k (325), got 325");
}

// The [video] section: every key, and its errors.
static void test_video (void **state)
{
    (void)state;
    im_params_t p;
    im_params_defaults (&p);
    s_load ("[video]\nenabled = no\nbitrate_kbps = 800\nkeyframe_s = 0.5\npreset = ultrafast\n"
            "file = off\nmap = 0\nudp = 239.1.2.5:5600\nttl = 0\nlocal_address = 127.0.0.1\n"
            "mission_id = night exercise\n",
            &p);
    assert_false (p.video || p.video_file || p.video_map);
    assert_int_equal (p.video_bitrate_kbps, 800);
    assert_true (p.video_keyframe_s == 0.5);
    assert_string_equal (p.video_preset, "ultrafast");
    assert_string_equal (p.video_udp, "239.1.2.5:5600");
    assert_int_equal (p.video_ttl, 0);
    assert_string_equal (p.video_local, "127.0.0.1");
    assert_string_equal (p.video_mission_id, "night exercise");
    char host[64];
    int port;
    assert_int_equal (im_params_parse_udp ("127.0.0.1:15004", host, sizeof host, &port), 0);
    assert_string_equal (host, "127.0.0.1");
    assert_int_equal (port, 15004);
    s_fails ("[video]\nudp = 127.0.0.1\n",
             "i.ini:2: [video] udp: expected HOST:PORT (an IPv4 address, port 1..65535), got "
             "'127.0.0.1'");
    s_fails ("[video]\nudp = localhost:5600\n",
             "i.ini:2: [video] udp: expected HOST:PORT (an IPv4 address, port 1..65535), got "
             "'localhost:5600'");
    s_fails ("[video]\nudp = 127.0.0.1:70000\n",
             "i.ini:2: [video] udp: expected HOST:PORT (an IPv4 address, port 1..65535), got "
             "'127.0.0.1:70000'");
    s_fails ("[video]\nudp = 127.0.0.1:\n",
             "i.ini:2: [video] udp: expected HOST:PORT (an IPv4 address, port 1..65535), got "
             "'127.0.0.1:'");
    s_fails ("[video]\nlocal_address = eth0\n",
             "i.ini:2: [video] local_address: expected an IPv4 address of this host, got 'eth0'");
    s_fails ("[video]\npreset = turbo\n",
             "i.ini:2: [video] preset: expected one of 'ultrafast', 'superfast', 'veryfast', "
             "'faster', 'fast', 'medium', 'slow', 'slower', 'veryslow', got 'turbo'");
    s_fails ("[video]\nbitrate_kbps = 10\n",
             "i.ini:2: [video] bitrate_kbps: expected an integer in [50, 100000], got '10'");
    s_fails ("[camera]\nwidth_px = 641\n",
             "i.ini:2: [camera] width_px: expected an even size for the video (H.264 4:2:0), got "
             "641 x 480");
    s_load ("[camera]\nwidth_px = 641\n[video]\nenabled = false\n", &p); // no video: any size
    assert_int_equal (p.width_px, 641);
}

static void test_enum_and_file_errors (void **state)
{
    (void)state;
    s_fails ("[infrared]\nmode = thermal\n",
             "i.ini:2: [infrared] mode: expected one of 'visible', 'infrared', 'sar', got "
             "'thermal'");
    s_fails ("[infrared]\npolarity = green-hot\n",
             "i.ini:2: [infrared] polarity: expected one of 'white-hot', 'black-hot', got "
             "'green-hot'");
    s_fails ("[infrared]\npolarity = 1\n",
             "i.ini:2: [infrared] polarity: expected one of 'white-hot', 'black-hot', got '1'");
    s_fails ("[camera]\nzoom = 2\n", "i.ini:2: [camera] unknown key 'zoom'");
    s_fails ("[infrared]\nmode = infrared\nfov_deg = 3\n",
             "i.ini:3: [infrared] unknown key 'fov_deg'");
    s_fails ("[lens]\nx = 1\n", "i.ini:1: unknown section [lens]");
    s_fails ("[camera]\nwidth_px = 800\nwidth_px = 1024\n",
             "i.ini:3: [camera] width_px: given twice (first at line 2)");
    // The file is missing.
    im_params_t p;
    im_params_defaults (&p);
    char err[512] = "";
    assert_true (im_params_load ("/nonexistent/imager.ini", &p, err, sizeof err) < 0);
    assert_non_null (strstr (err, "/nonexistent/imager.ini"));
}

// A set built in code is checked too: ranges, then relations, then enums.
static void test_check (void **state)
{
    (void)state;
    im_params_t p;
    char err[256] = "";
    im_params_defaults (&p);
    p.chunk_cells = 48;
    assert_int_equal (im_params_check (&p, err, sizeof err), -EINVAL);
    assert_string_equal (err, "[scene] chunk_cells: expected a power of two, got 48");
    im_params_defaults (&p);
    p.near_m = 100;
    p.max_range_m = 100;
    assert_int_equal (im_params_check (&p, err, sizeof err), -EINVAL);
    assert_string_equal (err, "[camera] max_range_m: expected more than near_m (100), got 100");
    im_params_defaults (&p);
    p.display_max_k = p.display_min_k - 1;
    assert_int_equal (im_params_check (&p, err, sizeof err), -EINVAL);
    assert_string_equal (
        err, "[infrared] display_max_k: expected more than display_min_k (275), got 274");
    im_params_defaults (&p);
    p.mode = (im_mode_t)7;
    assert_int_equal (im_params_check (&p, err, sizeof err), -EINVAL);
    assert_string_equal (err, "[infrared] mode: expected visible, infrared or sar, got 7");
    im_params_defaults (&p);
    p.polarity = (im_polarity_t)-1;
    assert_int_equal (im_params_check (&p, err, sizeof err), -EINVAL);
    assert_string_equal (err, "[infrared] polarity: expected white-hot or black-hot, got -1");
    im_params_defaults (&p);
    p.width_px = 8;
    assert_int_equal (im_params_check (&p, err, sizeof err), -EINVAL);
    assert_string_equal (err, "[camera] width_px: expected an integer in [16, 4096], got 8");
    im_params_defaults (&p);
    p.noise_k = NAN;
    assert_int_equal (im_params_check (&p, err, sizeof err), -EINVAL);
    assert_non_null (strstr (err, "[infrared] noise_k: expected a number in [0, 50]"));
    im_params_defaults (&p);
    p.attenuation_per_km = 11;
    assert_int_equal (im_params_check (&p, err, sizeof err), -EINVAL);
    assert_string_equal (err,
                         "[infrared] attenuation_per_km: expected a number in [0, 10], got 11");
}

// The [sar] section: the mode, every key's errors on its line, relations.
static void test_sar (void **state)
{
    (void)state;
    im_params_t p;
    im_params_defaults (&p);
    s_load ("[infrared]\nmode = sar\n[sar]\nwindow = RECT\ngeometry = Slant\n", &p);
    assert_int_equal (p.mode, IM_MODE_SAR);
    assert_int_equal (p.sar.window, IM_SAR_WINDOW_RECT);
    assert_int_equal (p.sar.geometry, IM_SAR_SLANT);
    s_fails ("[sar]\nfc_hz = 5e8\n",
             "i.ini:2: [sar] fc_hz: expected a number in [1000000000, 100000000000], got "
             "'5e8'");
    s_fails ("[sar]\nlooks = 17\n",
             "i.ini:2: [sar] looks: expected an integer in [1, 16], got '17'");
    s_fails ("[sar]\n\nsize_px = 32\n",
             "i.ini:3: [sar] size_px: expected an integer in [64, 2048], got '32'");
    s_fails ("[sar]\nintegration_deg = 0\n",
             "i.ini:2: [sar] integration_deg: expected a number in [0.05, 20], got '0'");
    s_fails ("[sar]\nnesz_db = 3\n",
             "i.ini:2: [sar] nesz_db: expected a number in [-100, 0], got '3'");
    s_fails ("[sar]\ndynamic_range_db = 0\n",
             "i.ini:2: [sar] dynamic_range_db: expected a number in [1, 120], got '0'");
    s_fails ("[sar]\nwindow = kaiser\n",
             "i.ini:2: [sar] window: expected one of 'rect', 'hamming', 'taylor', got 'kaiser'");
    s_fails ("[sar]\ngeometry = oblique\n",
             "i.ini:2: [sar] geometry: expected one of 'ground', 'slant', got 'oblique'");
    s_fails ("[sar]\nspeckle = some\n",
             "i.ini:2: [sar] speckle: expected true/false, yes/no, on/off or 1/0, got 'some'");
    s_fails ("[sar]\nfc_hz = 2e9\nbandwidth_hz = 600e6\n",
             "i.ini:3: [sar] bandwidth_hz: expected at most a quarter of fc_hz (5e+08), got 6e+08");
    s_fails ("[sar]\nsize_px = 2048\nscene_m = 4000\n",
             "i.ini:3: [sar] scene_m: expected a smaller chip for the resolution (its grid would "
             "be 8000 cells a side, at most 4096), got 4000");
    s_fails ("[sar]\nspeckle = no\nblur = 1\n", "i.ini:3: [sar] unknown key 'blur'");
    // A set built in code.
    char err[256] = "";
    im_params_defaults (&p);
    p.sar.looks = 0;
    assert_int_equal (im_params_check (&p, err, sizeof err), -EINVAL);
    assert_string_equal (err, "[sar] looks: expected an integer in [1, 16], got 0");
    im_params_defaults (&p);
    p.mode = IM_MODE_SAR;
    assert_int_equal (im_params_check (&p, err, sizeof err), 0);
}

int main (void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test (test_defaults),
        cmocka_unit_test (test_shipped_file),
        cmocka_unit_test (test_values),
        cmocka_unit_test (test_range_errors),
        cmocka_unit_test (test_relation_errors),
        cmocka_unit_test (test_enum_and_file_errors),
        cmocka_unit_test (test_check),
        cmocka_unit_test (test_video),
        cmocka_unit_test (test_sar),
    };
    return cmocka_run_group_tests (tests, NULL, NULL);
}
