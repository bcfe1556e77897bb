/* Unit tests of mti_params: the defaults, the shipped parameter file (which
 * must give exactly the defaults and document every key), every kind of
 * error with its file, line, section and key, the consistency checks with
 * the numbers they report, classes replaced, added and looked up, and the
 * derived values against hand-worked numbers. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "cgs_config.h"
#include "mti_params.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

// Every key a parameter file takes, by section (the shipped file must give them all).
static const char *const s_keys[][2] = {
    {"radar", "frequency_hz"},
    {"radar", "prf_hz"},
    {"radar", "pulse_width_s"},
    {"radar", "range_resolution_m"},
    {"radar", "azimuth_beamwidth_deg"},
    {"radar", "elevation_beamwidth_deg"},
    {"radar", "beam_depression_deg"},
    {"radar", "sweep_rate_dps"},
    {"radar", "transmit_power_w"},
    {"radar", "antenna_gain_db"},
    {"radar", "noise_figure_db"},
    {"radar", "losses_db"},
    {"radar", "noise_temperature_k"},
    {"radar", "min_range_m"},
    {"radar", "max_range_m"},
    {"scan", "mode"},
    {"scan", "sector_center_deg"},
    {"scan", "sector_width_deg"},
    {"scan", "sector_reference"},
    {"processing", "fft_size"},
    {"processing", "window"},
    {"processing", "canceller"},
    {"processing", "cfar_reference_cells"},
    {"processing", "cfar_guard_cells"},
    {"processing", "pfa"},
    {"processing", "m"},
    {"processing", "n"},
    {"clutter", "gamma_db"},
    {"clutter", "internal_motion_mps"},
};

// Field by field, classes included (exact: values read from text must equal the literals).
static void s_assert_equal (const mti_params_t *a, const mti_params_t *b)
{
#define S_SAME(f)                                                                                  \
    do {                                                                                           \
        if (a->f != b->f)                                                                          \
            fail_msg ("%s: %.17g != %.17g", #f, (double)a->f, (double)b->f);                       \
    } while (0)
    S_SAME (frequency_hz);
    S_SAME (prf_hz);
    S_SAME (pulse_width_s);
    S_SAME (range_resolution_m);
    S_SAME (azimuth_beamwidth_deg);
    S_SAME (elevation_beamwidth_deg);
    S_SAME (beam_depression_deg);
    S_SAME (sweep_rate_dps);
    S_SAME (transmit_power_w);
    S_SAME (antenna_gain_db);
    S_SAME (noise_figure_db);
    S_SAME (losses_db);
    S_SAME (noise_temperature_k);
    S_SAME (min_range_m);
    S_SAME (max_range_m);
    S_SAME (scan_mode);
    S_SAME (sector_center_deg);
    S_SAME (sector_width_deg);
    S_SAME (sector_ref);
    S_SAME (fft_size);
    S_SAME (window);
    S_SAME (canceller);
    S_SAME (ref_cells);
    S_SAME (guard_cells);
    S_SAME (pfa);
    S_SAME (m);
    S_SAME (n);
    S_SAME (clutter_gamma_db);
    S_SAME (clutter_internal_mps);
    S_SAME (class_count);
    for (size_t i = 0; i < a->class_count; i++) {
        assert_string_equal (a->classes[i].name, b->classes[i].name);
        S_SAME (classes[i].rcs_m2);
        S_SAME (classes[i].swerling);
    }
#undef S_SAME
}

// Load text as "r.ini" over defaults; fails the test unless it loads.
static void s_load (const char *text, mti_params_t *p)
{
    char err[512] = "";
    int rc = mti_params_load_string ("r.ini", text, p, err, sizeof err);
    if (rc != 0)
        fail_msg ("load failed: %s", err);
}

// Loading text as "r.ini" fails with -EINVAL and exactly the message expected, and leaves *p alone.
static void s_fails (const char *text, const char *expected)
{
    mti_params_t p, before;
    memset (&p, 0x5a, sizeof p);
    memcpy (&before, &p, sizeof p);
    char err[1024] = "";
    int rc = mti_params_load_string ("r.ini", text, &p, err, sizeof err);
    if (rc != -EINVAL)
        fail_msg ("expected -EINVAL, got %d (%s) for:\n%s", rc, err, text);
    assert_memory_equal (&p, &before, sizeof p);
    assert_string_equal (err, expected);
}

// mti_params_check on p fails with exactly the message expected.
static void s_check_fails (const mti_params_t *p, const char *expected)
{
    char err[1024] = "";
    assert_int_equal (mti_params_check (p, err, sizeof err), -EINVAL);
    assert_string_equal (err, expected);
    assert_int_equal (mti_params_check (p, NULL, 0), -EINVAL); // no buffer: still refused
}

static void s_shipped_path (char *path, size_t len)
{
    const char *root = getenv ("CGS_ROOT");
    snprintf (path, len, "%s/deploy/params/radar.ini", root ? root : ".");
}

static void test_defaults (void **state)
{
    (void)state;
    mti_params_t p;
    memset (&p, 0x5a, sizeof p);
    mti_params_defaults (&p);
    assert_true (p.frequency_hz == 16e9);
    assert_true (p.prf_hz == 5000);
    assert_true (p.pulse_width_s == 200e-9);
    assert_true (p.range_resolution_m == 30);
    assert_true (p.azimuth_beamwidth_deg == 3);
    assert_true (p.elevation_beamwidth_deg == 60);
    assert_true (p.beam_depression_deg == 30);
    assert_true (p.sweep_rate_dps == 36);
    assert_true (p.transmit_power_w == 20000);
    assert_true (p.antenna_gain_db == 24);
    assert_true (p.noise_figure_db == 4);
    assert_true (p.losses_db == 5);
    assert_true (p.noise_temperature_k == 290);
    assert_true (p.min_range_m == 500);
    assert_true (p.max_range_m == 20000);
    assert_int_equal (p.scan_mode, MTI_SCAN_FULL);
    assert_true (p.sector_center_deg == 0);
    assert_true (p.sector_width_deg == 90);
    assert_int_equal (p.sector_ref, MTI_SECTOR_NORTH);
    assert_int_equal (p.fft_size, 64);
    assert_int_equal (p.window, MTI_WINDOW_HAMMING);
    assert_int_equal (p.canceller, MTI_CANCELLER_TWO);
    assert_int_equal (p.ref_cells, 16);
    assert_int_equal (p.guard_cells, 2);
    assert_true (p.pfa == 1e-4);
    assert_int_equal (p.m, 2);
    assert_int_equal (p.n, 4);
    assert_true (p.clutter_gamma_db == -15);
    assert_true (p.clutter_internal_mps == 0.1);
    static const struct {
        const char *name;
        double rcs_m2;
        mti_swerling_t swerling;
    } want[] = {
        {"vehicle", 10, MTI_SWERLING_2}, {"tank", 20, MTI_SWERLING_2},
        {"truck", 15, MTI_SWERLING_2},   {"person", 1, MTI_SWERLING_2},
        {"car", 5, MTI_SWERLING_2},      {"reflector", 10, MTI_SWERLING_0},
    };
    assert_int_equal (p.class_count, 6);
    for (size_t i = 0; i < 6; i++) {
        assert_string_equal (p.classes[i].name, want[i].name);
        assert_true (p.classes[i].rcs_m2 == want[i].rcs_m2);
        assert_int_equal (p.classes[i].swerling, want[i].swerling);
    }
    char err[256] = "";
    assert_int_equal (mti_params_check (&p, err, sizeof err), 0);
}

// The shipped file gives every key, and exactly the defaults; loading it writes over any *p.
static void test_shipped_file (void **state)
{
    (void)state;
    char path[1024], err[512] = "";
    s_shipped_path (path, sizeof path);
    mti_params_t p, def;
    memset (&p, 0x5a, sizeof p);
    if (mti_params_load (path, &p, err, sizeof err) != 0)
        fail_msg ("%s", err);
    mti_params_defaults (&def);
    s_assert_equal (&p, &def);

    cgs_config_t *cfg = NULL;
    if (cgs_config_load (path, &cfg, err, sizeof err) != 0)
        fail_msg ("%s", err);
    for (size_t i = 0; i < sizeof s_keys / sizeof s_keys[0]; i++)
        if (!cgs_config_has (cfg, s_keys[i][0], s_keys[i][1]))
            fail_msg ("%s has no [%s] %s", path, s_keys[i][0], s_keys[i][1]);
    for (size_t i = 0; i < def.class_count; i++) {
        char sec[64];
        snprintf (sec, sizeof sec, "target %s", def.classes[i].name);
        if (!cgs_config_has (cfg, sec, "rcs_m2") || !cgs_config_has (cfg, sec, "swerling"))
            fail_msg ("%s does not give rcs_m2 and swerling of [%s]", path, sec);
    }
    assert_int_equal (cgs_config_section_count (cfg), 4 + def.class_count);
    cgs_config_destroy (&cfg);
}

// Every key read from text lands in its field, enumerations by every accepted name.
static void test_values (void **state)
{
    (void)state;
    mti_params_t p;
    s_load ("[radar]\n"
            "frequency_hz = 9.5e9\n"
            "prf_hz = 2500\n"
            "pulse_width_s = 1e-6\n"
            "range_resolution_m = 15\n"
            "azimuth_beamwidth_deg = 2\n"
            "elevation_beamwidth_deg = 20\n"
            "beam_depression_deg = 10\n"
            "sweep_rate_dps = 10\n"
            "transmit_power_w = 500\n"
            "antenna_gain_db = 30\n"
            "noise_figure_db = 3\n"
            "losses_db = 6\n"
            "noise_temperature_k = 300\n"
            "min_range_m = 1000\n"
            "max_range_m = 50000\n"
            "[scan]\n"
            "mode = Sector\n"
            "sector_center_deg = -45\n"
            "sector_width_deg = 60\n"
            "sector_reference = heading\n"
            "[processing]\n"
            "fft_size = 128\n"
            "window = blackman\n"
            "canceller = three-pulse\n"
            "cfar_reference_cells = 24\n"
            "cfar_guard_cells = 0\n"
            "pfa = 1e-6\n"
            "m = 3\n"
            "n = 3\n"
            "[clutter]\n"
            "gamma_db = -20\n"
            "internal_motion_mps = 0.5\n",
            &p);
    assert_true (p.frequency_hz == 9.5e9);
    assert_true (p.prf_hz == 2500);
    assert_true (p.pulse_width_s == 1e-6);
    assert_true (p.range_resolution_m == 15);
    assert_true (p.azimuth_beamwidth_deg == 2);
    assert_true (p.elevation_beamwidth_deg == 20);
    assert_true (p.beam_depression_deg == 10);
    assert_true (p.sweep_rate_dps == 10);
    assert_true (p.transmit_power_w == 500);
    assert_true (p.antenna_gain_db == 30);
    assert_true (p.noise_figure_db == 3);
    assert_true (p.losses_db == 6);
    assert_true (p.noise_temperature_k == 300);
    assert_true (p.min_range_m == 1000);
    assert_true (p.max_range_m == 50000);
    assert_int_equal (p.scan_mode, MTI_SCAN_SECTOR);
    assert_true (p.sector_center_deg == -45);
    assert_true (p.sector_width_deg == 60);
    assert_int_equal (p.sector_ref, MTI_SECTOR_HEADING);
    assert_int_equal (p.fft_size, 128);
    assert_int_equal (p.window, MTI_WINDOW_BLACKMAN);
    assert_int_equal (p.canceller, MTI_CANCELLER_THREE);
    assert_int_equal (p.ref_cells, 24);
    assert_int_equal (p.guard_cells, 0);
    assert_true (p.pfa == 1e-6);
    assert_int_equal (p.m, 3);
    assert_int_equal (p.n, 3);
    assert_true (p.clutter_gamma_db == -20);
    assert_true (p.clutter_internal_mps == 0.5);
    assert_int_equal (mti_params_cpi_pulses (&p), 130);
    assert_int_equal (p.class_count, 6); // no [target] section: the built-in classes

    const char *windows[] = {"rectangular", "hann", "hamming", "blackman"};
    for (int i = 0; i < 4; i++) {
        char text[128];
        snprintf (text, sizeof text, "[processing]\nwindow = %s\n", windows[i]);
        s_load (text, &p);
        assert_int_equal (p.window, i);
    }
    s_load ("[processing]\ncanceller = none\n", &p);
    assert_int_equal (p.canceller, MTI_CANCELLER_NONE);
    assert_int_equal (mti_params_cpi_pulses (&p), 64);
    s_load ("[scan]\nmode = full\nsector_reference = north\n", &p);
    assert_int_equal (p.scan_mode, MTI_SCAN_FULL);
    assert_int_equal (p.sector_ref, MTI_SECTOR_NORTH);

    const struct {
        const char *text;
        mti_swerling_t want;
    } sw[] = {{"0", MTI_SWERLING_0},        {"constant", MTI_SWERLING_0},
              {"Constant", MTI_SWERLING_0}, {"1", MTI_SWERLING_1},
              {"2", MTI_SWERLING_2},        {"2-pulse", MTI_SWERLING_2_PULSE}};
    for (size_t i = 0; i < sizeof sw / sizeof sw[0]; i++) {
        char text[128];
        snprintf (text, sizeof text, "[target car]\nswerling = %s\n", sw[i].text);
        s_load (text, &p);
        assert_int_equal (p.classes[4].swerling, sw[i].want);
        // The same names outside a file (mtid --monte-carlo --swerling).
        mti_swerling_t m = (mti_swerling_t)-1;
        assert_int_equal (mti_swerling_parse (sw[i].text, &m), 0);
        assert_int_equal (m, sw[i].want);
    }
    mti_swerling_t m = MTI_SWERLING_1;
    assert_int_equal (mti_swerling_parse ("3", &m), -EINVAL);
    assert_int_equal (mti_swerling_parse (NULL, &m), -EINVAL);
    assert_int_equal (m, MTI_SWERLING_1);
    assert_string_equal (mti_swerling_name (MTI_SWERLING_0), "0");
    assert_string_equal (mti_swerling_name (MTI_SWERLING_2), "2");
    assert_string_equal (mti_swerling_name (MTI_SWERLING_2_PULSE), "2-pulse");
    assert_string_equal (mti_swerling_name ((mti_swerling_t)9), "?");

    // Comments, blank lines and an empty file: the defaults.
    mti_params_t def;
    mti_params_defaults (&def);
    memset (&p, 0x5a, sizeof p);
    s_load ("", &p);
    s_assert_equal (&p, &def);
    s_load ("; nothing\n\n[radar]\n# still nothing\n[scan]\n", &p);
    s_assert_equal (&p, &def);
}

static void test_classes (void **state)
{
    (void)state;
    mti_params_t p;
    // Replace: the keys given change, the others stay; order and count stay.
    s_load ("[target tank]\nswerling = 1\n[target person]\nrcs_m2 = 0.5\n", &p);
    assert_int_equal (p.class_count, 6);
    assert_string_equal (p.classes[1].name, "tank");
    assert_true (p.classes[1].rcs_m2 == 20);
    assert_int_equal (p.classes[1].swerling, MTI_SWERLING_1);
    assert_string_equal (p.classes[3].name, "person");
    assert_true (p.classes[3].rcs_m2 == 0.5);
    assert_int_equal (p.classes[3].swerling, MTI_SWERLING_2);

    // Add: appended in file order; swerling 2 unless given; names are case-sensitive.
    s_load ("[target drone]\nrcs_m2 = 0.01\nswerling = constant\n"
            "[target Tank]\nrcs_m2 = 30\n"
            "[target tank]\nrcs_m2 = 25\n",
            &p);
    assert_int_equal (p.class_count, 8);
    assert_string_equal (p.classes[6].name, "drone");
    assert_true (p.classes[6].rcs_m2 == 0.01);
    assert_int_equal (p.classes[6].swerling, MTI_SWERLING_0);
    assert_string_equal (p.classes[7].name, "Tank");
    assert_true (p.classes[7].rcs_m2 == 30);
    assert_int_equal (p.classes[7].swerling, MTI_SWERLING_2);
    assert_true (p.classes[1].rcs_m2 == 25);

    // Lookup: exact match, else the first class (no `default`).
    bool known = false;
    const mti_class_t *k = mti_params_class (&p, "drone", &known);
    assert_true (known);
    assert_ptr_equal (k, &p.classes[6]);
    k = mti_params_class (&p, "DRONE", &known);
    assert_false (known);
    assert_ptr_equal (k, &p.classes[0]);
    assert_string_equal (k->name, "vehicle");
    assert_ptr_equal (mti_params_class (&p, NULL, &known), &p.classes[0]);
    assert_false (known);
    assert_ptr_equal (mti_params_class (&p, "Tank", NULL), &p.classes[7]);

    // ... else `default` when the file has one.
    s_load ("[target default]\nrcs_m2 = 3\nswerling = 2\n", &p);
    assert_int_equal (p.class_count, 7);
    known = true;
    k = mti_params_class (&p, "bicycle", &known);
    assert_false (known);
    assert_string_equal (k->name, "default");
    assert_true (k->rcs_m2 == 3);
    k = mti_params_class (&p, "default", &known);
    assert_true (known);
    k = mti_params_class (&p, "car", &known);
    assert_true (known);
    assert_string_equal (k->name, "car");

    // Without classes there is nothing to return.
    p.class_count = 0;
    assert_null (mti_params_class (&p, "car", &known));
    assert_false (known);

    // Up to MTI_CLASS_MAX classes: the 6 built in and 26 more.
    char text[4096] = "";
    size_t n = 0;
    for (int i = 0; i < MTI_CLASS_MAX - 6; i++)
        n += (size_t)snprintf (text + n, sizeof text - n, "[target c%d]\nrcs_m2 = %d\n", i, i + 1);
    s_load (text, &p);
    assert_int_equal (p.class_count, MTI_CLASS_MAX);
    assert_string_equal (p.classes[MTI_CLASS_MAX - 1].name, "c25");
    // A name of exactly MTI_CLASS_NAME_MAX characters.
    s_load ("[target abcdefghij.abcdefghij-abcdefgh_]\nrcs_m2 = 2\n", &p);
    assert_string_equal (p.classes[6].name, "abcdefghij.abcdefghij-abcdefgh_");
}

static void test_derived (void **state)
{
    (void)state;
    mti_params_t p;
    mti_params_defaults (&p);
    assert_true (fabs (mti_params_wavelength_m (&p) - 0.018737) < 5e-7);
    assert_true (mti_params_wavelength_m (&p) == 299792458.0 / 16e9);
    assert_int_equal (mti_params_cpi_pulses (&p), 65);
    assert_true (fabs (mti_params_dwell_s (&p) - 1.0 / 12) < 1e-15);
    p.canceller = MTI_CANCELLER_THREE;
    assert_int_equal (mti_params_cpi_pulses (&p), 66);
    p.canceller = MTI_CANCELLER_NONE;
    p.fft_size = 256;
    assert_int_equal (mti_params_cpi_pulses (&p), 256);
    p.azimuth_beamwidth_deg = 2;
    p.sweep_rate_dps = 40;
    assert_true (fabs (mti_params_dwell_s (&p) - 0.05) < 1e-15);
}

// Values out of range, malformed, or not one of the names: the line, section, key and range.
static void test_value_errors (void **state)
{
    (void)state;
    s_fails ("[radar]\nprf_hz = 5000\nfrequency_hz = 5e7\n",
             "r.ini:3: [radar] frequency_hz: expected a number in [100000000, 100000000000], got "
             "'5e7'");
    s_fails ("[radar]\nprf_hz = fast\n",
             "r.ini:2: [radar] prf_hz: expected a number in [100, 1000000], got 'fast'");
    s_fails ("\n[radar]\nnoise_temperature_k = 0\n",
             "r.ini:3: [radar] noise_temperature_k: expected a number in [1, 10000], got '0'");
    s_fails ("[scan]\nsector_width_deg = 400\n",
             "r.ini:2: [scan] sector_width_deg: expected a number in [0.1, 360], got '400'");
    s_fails ("[clutter]\ngamma_db = -15 dB\n",
             "r.ini:2: [clutter] gamma_db: expected a number in [-80, 10], got '-15 dB'");
    s_fails ("[processing]\nfft_size = 48\n",
             "r.ini:2: [processing] fft_size: expected a power of two in [4, 1024], got '48'");
    s_fails ("[processing]\nfft_size = +048\n",
             "r.ini:2: [processing] fft_size: expected a power of two in [4, 1024], got '+048'");
    s_fails ("[processing]\nfft_size = 2048\n",
             "r.ini:2: [processing] fft_size: expected an integer in [4, 1024], got '2048'");
    s_fails ("[processing]\nfft_size = 64.0\n",
             "r.ini:2: [processing] fft_size: expected an integer in [4, 1024], got '64.0'");
    s_fails ("[processing]\ncfar_reference_cells = 15\n",
             "r.ini:2: [processing] cfar_reference_cells: expected an even integer in [2, 128], "
             "got '15'");
    s_fails ("[processing]\ncfar_guard_cells = 17\n",
             "r.ini:2: [processing] cfar_guard_cells: expected an integer in [0, 16], got '17'");
    s_fails ("[processing]\nm = 0\n",
             "r.ini:2: [processing] m: expected an integer in [1, 64], got '0'");
    // Open ends: the interval says so, whatever the value.
    s_fails ("[processing]\npfa = 0\n",
             "r.ini:2: [processing] pfa: expected a number in (0, 0.5), got '0'");
    s_fails ("[processing]\npfa = 0.5\n",
             "r.ini:2: [processing] pfa: expected a number in (0, 0.5), got '0.5'");
    s_fails ("[processing]\npfa = 0.7\n",
             "r.ini:2: [processing] pfa: expected a number in (0, 0.5), got '0.7'");
    s_fails ("[processing]\npfa = rare\n",
             "r.ini:2: [processing] pfa: expected a number in (0, 0.5), got 'rare'");
    s_fails ("[target car]\nrcs_m2 = 0\n",
             "r.ini:2: [target car] rcs_m2: expected a number in (0, 1000000], got '0'");
    s_fails ("[target car]\nrcs_m2 = -1\n",
             "r.ini:2: [target car] rcs_m2: expected a number in (0, 1000000], got '-1'");
    // Enumerations.
    s_fails ("[processing]\nwindow = kaiser\n",
             "r.ini:2: [processing] window: expected one of 'rectangular', 'hann', 'hamming', "
             "'blackman', got 'kaiser'");
    s_fails ("[processing]\ncanceller = 2\n",
             "r.ini:2: [processing] canceller: expected one of 'none', 'two-pulse', "
             "'three-pulse', got '2'");
    s_fails ("[scan]\nmode = spotlight\n",
             "r.ini:2: [scan] mode: expected one of 'full', 'sector', got 'spotlight'");
    s_fails ("[scan]\nsector_reference = track\n",
             "r.ini:2: [scan] sector_reference: expected one of 'north', 'heading', got 'track'");
    s_fails (
        "[target car]\nswerling = 3\n",
        "r.ini:2: [target car] swerling: expected one of '0', '1', '2', 'constant', '2-pulse', got "
        "'3'");
    // A key given twice.
    s_fails ("[radar]\nprf_hz = 5000\nprf_hz = 4000\n",
             "r.ini:3: [radar] prf_hz: given twice (first at line 2)");
    // Same for the open-ended keys, whose messages are written here.
    s_fails ("[processing]\npfa = 1e-4\npfa = 0\n",
             "r.ini:3: [processing] pfa: given twice (first at line 2)");
}

// What the file's structure gets wrong: unknown keys and sections, headers given twice, classes.
static void test_structure_errors (void **state)
{
    (void)state;
    s_fails ("[radar]\nprf_hz = 5000\nfrequency = 16e9\n",
             "r.ini:3: [radar] unknown key 'frequency'");
    s_fails ("[clutter]\nclutter_gamma_db = -15\n",
             "r.ini:2: [clutter] unknown key 'clutter_gamma_db'");
    s_fails ("[processing]\nref_cells = 16\n", "r.ini:2: [processing] unknown key 'ref_cells'");
    s_fails ("[radar]\n[antenna]\ngain_db = 3\n", "r.ini:2: unknown section [antenna]");
    s_fails ("[Radar]\nprf_hz = 5000\n", "r.ini:1: unknown section [Radar]");
    s_fails ("[targets car]\nrcs_m2 = 5\n", "r.ini:1: unknown section [targets car]");
    s_fails ("prf_hz = 5000\n[radar]\n", "r.ini:1: unknown key 'prf_hz' (before any section)");
    s_fails ("[target car]\nrcs_m2 = 5\nradius_m = 2\n",
             "r.ini:3: [target car] unknown key 'radius_m'");
    s_fails ("[radar]\nprf_hz = 5000\n[scan]\n[radar]\nlosses_db = 3\n",
             "r.ini:4: [radar] given twice (first at line 1)");
    s_fails ("[target car]\nrcs_m2 = 5\n[target car]\nswerling = 0\n",
             "r.ini:3: [target car] given twice (first at line 1)");
    s_fails ("[radar]\nprf_hz 5000\n",
             "r.ini:2: syntax error (expected `key = value` or `[section]`)");
    s_fails ("[target]\nrcs_m2 = 5\n",
             "r.ini:1: [target] expected [target NAME] with NAME 1 to 31 letters, digits, '_', "
             "'.' or '-', got ''");
    s_fails ("[target big truck]\nrcs_m2 = 5\n",
             "r.ini:1: [target big truck] expected [target NAME] with NAME 1 to 31 letters, "
             "digits, '_', '.' or '-', got 'big truck'");
    s_fails ("[target abcdefghij.abcdefghij-abcdefghij]\nrcs_m2 = 5\n",
             "r.ini:1: [target abcdefghij.abcdefghij-abcdefghij] expected [target NAME] with NAME "
             "1 to 31 letters, digits, '_', '.' or '-', got 'abcdefghij.abcdefghij-abcdefghij'");
    s_fails ("[radar]\n[target drone]\nswerling = 2\n",
             "r.ini:2: [target drone] missing key 'rcs_m2' (a new class needs its mean radar "
             "cross-section, m²)");

    char text[4096] = "";
    size_t n = 0;
    for (int i = 0; i <= MTI_CLASS_MAX - 6; i++)
        n += (size_t)snprintf (text + n, sizeof text - n, "[target c%d]\nrcs_m2 = 1\n", i);
    char want[256];
    snprintf (want, sizeof want,
              "r.ini:%d: [target c%d] too many classes (at most %d, the built-in ones included)",
              2 * (MTI_CLASS_MAX - 6) + 1, MTI_CLASS_MAX - 6, MTI_CLASS_MAX);
    s_fails (text, want);

    // A file that is not there.
    char err[512] = "";
    mti_params_t p, before;
    memset (&p, 0x5a, sizeof p);
    memcpy (&before, &p, sizeof p);
    assert_int_equal (mti_params_load ("/nonexistent/radar.ini", &p, err, sizeof err), -ENOENT);
    assert_string_equal (err, "/nonexistent/radar.ini: No such file or directory");
    assert_memory_equal (&p, &before, sizeof p);
}

// Values each in range that do not hold together, named at the first line involved.
static void test_consistency_errors (void **state)
{
    (void)state;
    // Dwell: the default dwell is 3 deg / 36 deg/s = 1/12 s, 416 pulses at 5 kHz.
    s_fails ("[processing]\nm = 2\nn = 7\n",
             "r.ini:3: [processing] n: n = 7 coherent intervals of 65 pulses (fft_size 64, "
             "canceller two-pulse) need 455 pulses, but a dwell has only 416 "
             "(azimuth_beamwidth_deg 3 / sweep_rate_dps 36 = 0.08333 s at prf_hz 5000)");
    s_fails ("[processing]\nfft_size = 128\n",
             "r.ini:2: [processing] fft_size: n = 4 coherent intervals of 129 pulses (fft_size "
             "128, canceller two-pulse) need 516 pulses, but a dwell has only 416 "
             "(azimuth_beamwidth_deg 3 / sweep_rate_dps 36 = 0.08333 s at prf_hz 5000)");
    s_fails ("[processing]\nwindow = hann\n[radar]\nsweep_rate_dps = 72\n",
             "r.ini:4: [radar] sweep_rate_dps: n = 4 coherent intervals of 65 pulses (fft_size "
             "64, canceller two-pulse) need 260 pulses, but a dwell has only 208 "
             "(azimuth_beamwidth_deg 3 / sweep_rate_dps 72 = 0.04167 s at prf_hz 5000)");
    s_fails ("[radar]\nprf_hz = 3000\n",
             "r.ini:2: [radar] prf_hz: n = 4 coherent intervals of 65 pulses (fft_size 64, "
             "canceller two-pulse) need 260 pulses, but a dwell has only 250 "
             "(azimuth_beamwidth_deg 3 / sweep_rate_dps 36 = 0.08333 s at prf_hz 3000)");
    // Just fits: 6 intervals of 65 = 390 <= 416; a three-pulse canceller at n 6 needs 396.
    mti_params_t p;
    s_load ("[processing]\nn = 6\ncanceller = three-pulse\n", &p);
    assert_int_equal (p.n * mti_params_cpi_pulses (&p), 396);
    // Exactly fits: prf 3120 gives floor(3120 / 12) = 260 = 4 * 65.
    s_load ("[radar]\nprf_hz = 3120\n", &p);

    // Range resolution: c * 200 ns / 2 = 29.98 m; 30 is within the 0.1% slack, finer is fine.
    s_fails ("[radar]\nrange_resolution_m = 60\n",
             "r.ini:2: [radar] range_resolution_m: range_resolution_m 60 is coarser than the "
             "pulse gives, c * pulse_width_s / 2 = 29.98 m with pulse_width_s 2e-07 (finer is "
             "allowed: pulse compression)");
    s_fails ("[radar]\npulse_width_s = 100e-9\n",
             "r.ini:2: [radar] pulse_width_s: range_resolution_m 30 is coarser than the pulse "
             "gives, c * pulse_width_s / 2 = 14.99 m with pulse_width_s 1e-07 (finer is "
             "allowed: pulse compression)");
    s_fails ("[radar]\nrange_resolution_m = 30.05\n",
             "r.ini:2: [radar] range_resolution_m: range_resolution_m 30.05 is coarser than the "
             "pulse gives, c * pulse_width_s / 2 = 29.98 m with pulse_width_s 2e-07 (finer is "
             "allowed: pulse compression)");
    s_load ("[radar]\nrange_resolution_m = 1.5\n", &p);

    // Sector narrower than a beam.
    s_fails ("[scan]\nmode = sector\nsector_width_deg = 2\n",
             "r.ini:3: [scan] sector_width_deg: sector_width_deg 2 is narrower than one beam "
             "(azimuth_beamwidth_deg 3)");
    s_fails ("[radar]\nazimuth_beamwidth_deg = 20\nsweep_rate_dps = 200\n[scan]\n"
             "sector_width_deg = 10\n",
             "r.ini:5: [scan] sector_width_deg: sector_width_deg 10 is narrower than one beam "
             "(azimuth_beamwidth_deg 20)");
    s_load ("[scan]\nmode = sector\nsector_width_deg = 3\n", &p);
    assert_true (p.sector_width_deg == 3);

    // Ranges.
    s_fails ("[radar]\nmax_range_m = 40000\n",
             "r.ini:2: [radar] max_range_m: max_range_m 40000 is beyond the unambiguous range c "
             "/ (2 prf_hz) = 29979 m at prf_hz 5000");
    s_fails ("[radar]\nprf_hz = 10000\n",
             "r.ini:2: [radar] prf_hz: max_range_m 20000 is beyond the unambiguous range c / (2 "
             "prf_hz) = 14990 m at prf_hz 10000");
    s_fails ("[radar]\nmin_range_m = 20000\n",
             "r.ini:2: [radar] min_range_m: min_range_m 20000 must be below max_range_m 20000");

    // m of n.
    s_fails ("[processing]\nm = 5\n",
             "r.ini:2: [processing] m: m 5 is more than n 4 (m crossings of n coherent "
             "intervals)");
}

// mti_params_check on structs built in code: "[section] key: reason", no file.
static void test_check (void **state)
{
    (void)state;
    mti_params_t def, p;
    mti_params_defaults (&def);

    p = def;
    p.n = 7;
    s_check_fails (&p, "[processing] n: n = 7 coherent intervals of 65 pulses (fft_size 64, "
                       "canceller two-pulse) need 455 pulses, but a dwell has only 416 "
                       "(azimuth_beamwidth_deg 3 / sweep_rate_dps 36 = 0.08333 s at prf_hz 5000)");
    p = def;
    p.fft_size = 48;
    s_check_fails (&p, "[processing] fft_size: expected a power of two in [4, 1024], got 48");
    p = def;
    p.ref_cells = 130;
    s_check_fails (&p,
                   "[processing] cfar_reference_cells: expected an even integer in [2, 128], got "
                   "130");
    p = def;
    p.pfa = 0;
    s_check_fails (&p, "[processing] pfa: expected a number in (0, 0.5), got 0");
    p = def;
    p.frequency_hz = NAN;
    s_check_fails (&p,
                   "[radar] frequency_hz: expected a number in [100000000, 100000000000], got nan");
    p = def;
    p.window = (mti_window_t)9;
    s_check_fails (&p, "[processing] window: 9 is not a value of this enumeration");
    p = def;
    p.canceller = (mti_canceller_t)0;
    s_check_fails (&p, "[processing] canceller: 0 is not a value of this enumeration");
    p = def;
    p.range_resolution_m = 45;
    s_check_fails (&p, "[radar] range_resolution_m: range_resolution_m 45 is coarser than the "
                       "pulse gives, c * pulse_width_s / 2 = 29.98 m with pulse_width_s 2e-07 "
                       "(finer is allowed: pulse compression)");
    p = def;
    p.sector_width_deg = 1;
    s_check_fails (&p, "[scan] sector_width_deg: sector_width_deg 1 is narrower than one beam "
                       "(azimuth_beamwidth_deg 3)");
    p = def;
    p.class_count = 0;
    s_check_fails (&p, "[target NAME] expected 1 to 32 radar cross-section classes, got 0");
    p = def;
    p.classes[2].rcs_m2 = 0;
    s_check_fails (&p, "[target truck] rcs_m2: expected a number in (0, 1000000], got 0");
    p = def;
    p.classes[2].swerling = (mti_swerling_t)5;
    s_check_fails (&p, "[target truck] swerling: expected 0, 1, 2 or 2-pulse, got 5");
    p = def;
    strcpy (p.classes[3].name, "tank");
    s_check_fails (&p, "[target tank] class given twice (classes 1 and 3)");
    p = def;
    strcpy (p.classes[0].name, "");
    s_check_fails (&p, "[target ] expected a class name of 1 to 31 letters, digits, '_', '.' or "
                       "'-'");

    // A consistent set built in code passes.
    p = def;
    p.prf_hz = 3120;
    assert_int_equal (mti_params_check (&p, NULL, 0), 0);
}

int main (void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test (test_defaults),
        cmocka_unit_test (test_shipped_file),
        cmocka_unit_test (test_values),
        cmocka_unit_test (test_classes),
        cmocka_unit_test (test_derived),
        cmocka_unit_test (test_value_errors),
        cmocka_unit_test (test_structure_errors),
        cmocka_unit_test (test_consistency_errors),
        cmocka_unit_test (test_check),
    };
    return cmocka_run_group_tests (tests, NULL, NULL);
}
