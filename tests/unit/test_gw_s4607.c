/* test_gw_s4607 — the STANAG 4607 Edition 3 encoder against the standard's
 * layouts: the packet header and the Platform Location and Mission segments
 * laid out by hand byte by byte, the angle and binary-decimal encodings worked
 * by hand (and against the standard's Annex C examples), the existence mask of a
 * chosen subset of fields worked bit by bit, segment sizes as the sum of the
 * present fields' sizes, the range policy (saturate or reject) field by field,
 * failures that leave the packet untouched, and a file of several packets read
 * back by Wireshark's dissector (tshark, required) whose every raw integer must
 * be the one encoded, with no malformed packet and no expert warning. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "gw_s4607.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

/* A big-endian reader written here, independent of the module's. */
static uint32_t s_be16 (const uint8_t *b)
{
    return (uint32_t)b[0] << 8 | b[1];
}

static uint32_t s_be32 (const uint8_t *b)
{
    return s_be16 (b) << 16 | s_be16 (b + 2);
}

static uint64_t s_be64 (const uint8_t *b)
{
    return (uint64_t)s_be32 (b) << 32 | s_be32 (b + 4);
}

static void s_assert_bytes (const uint8_t *got, const uint8_t *want, size_t n)
{
    for (size_t i = 0; i < n; i++)
        if (got[i] != want[i])
            fail_msg ("byte %zu: 0x%02x, want 0x%02x", i, got[i], want[i]);
}

/* Exactly representable inputs from raw field values: the encoder must give the raw value back. */
static double s_sa32_deg (int32_t raw)
{
    return raw * 90.0 / 2147483648.0;
}

static double s_ba32_deg (uint32_t raw)
{
    return raw * 360.0 / 4294967296.0;
}

static double s_sa16_deg (int16_t raw)
{
    return raw * 90.0 / 32768.0;
}

static double s_ba16_deg (uint16_t raw)
{
    return raw * 360.0 / 65536.0;
}

static gw_s4607_header_t s_header (uint32_t job_id)
{
    gw_s4607_header_t h = {
        .nationality = "XN",
        .classification = GW_S4607_CLASS_UNCLASSIFIED,
        .class_system = "XN",
        .class_code = 0x0102,
        .exercise_indicator = GW_S4607_EXERCISE_SIMULATED,
        .platform_id = "MSCGS UAV1",
        .mission_id = 0x01020304u,
        .job_id = job_id,
    };
    return h;
}

/* ---- 1. hand-worked bytes -------------------------------------------------------------- */

// clang-format off
static const uint8_t s_header_want[32] = {
    /*  0 P1 version "30" */ '3', '0',
    /*  2 P2 packet size */ 0, 0, 0, 32,
    /*  6 P3 nationality */ 'X', 'N',
    /*  8 P4 classification: UNCLASSIFIED */ 5,
    /*  9 P5 classification system */ 'X', 'N',
    /* 11 P6 class code */ 0x01, 0x02,
    /* 13 P7 exercise indicator: exercise, simulated */ 129,
    /* 14 P8 platform id, 10 chars */ 'M', 'S', 'C', 'G', 'S', ' ', 'U', 'A', 'V', '1',
    /* 24 P9 mission id */ 0x01, 0x02, 0x03, 0x04,
    /* 28 P10 job id */ 0x0a, 0x0b, 0x0c, 0x0d,
};
// clang-format on

static void test_header_bytes (void **state)
{
    (void)state;
    uint8_t b[64], before[64];
    gw_s4607_packet_t p, p0;
    gw_s4607_header_t h = s_header (0x0a0b0c0du);
    memset (b, 0xee, sizeof b);
    assert_int_equal (gw_s4607_packet_begin (&p, b, sizeof b, &h), 0);
    assert_int_equal (p.len, 32);
    assert_ptr_equal (p.buf, b);
    assert_int_equal (p.cap, sizeof b);
    assert_int_equal (gw_s4607_packet_end (&p), 32);
    s_assert_bytes (b, s_header_want, 32);
    assert_int_equal (b[32], 0xee); // nothing past the header

    // A short platform id is space padded; so is a one-character classification system.
    strcpy (h.platform_id, "UAV1");
    strcpy (h.class_system, "X");
    assert_int_equal (gw_s4607_packet_begin (&p, b, 32, &h), 0);
    assert_memory_equal (b + 14, "UAV1      ", 10);
    assert_memory_equal (b + 9, "X ", 2);

    // Refusals leave the packet struct and the buffer as they were.
    gw_s4607_header_t bad[9];
    for (int i = 0; i < 9; i++)
        bad[i] = s_header (1);
    bad[0].classification = 0;
    bad[1].classification = 6;
    bad[2].exercise_indicator = 3;
    bad[3].exercise_indicator = 127;
    bad[4].exercise_indicator = 131;
    strcpy (bad[5].nationality, "X");
    bad[6].platform_id[3] = '\n';
    memset (bad[7].platform_id, 'A', sizeof bad[7].platform_id); // 11 chars, no terminator
    bad[8].class_system[0] = (char)0xc3;                         // not ASCII
    memset (b, 0x5a, sizeof b);
    memcpy (before, b, sizeof b);
    p = p0 = (gw_s4607_packet_t){NULL, 7, 9};
    for (int i = 0; i < 9; i++) {
        if (gw_s4607_packet_begin (&p, b, sizeof b, &bad[i]) != -EINVAL)
            fail_msg ("bad header %d accepted", i);
        assert_memory_equal (b, before, sizeof b);
        assert_memory_equal (&p, &p0, sizeof p);
    }
    h = s_header (1);
    assert_int_equal (gw_s4607_packet_begin (&p, b, 31, &h), -ENOSPC);
    assert_memory_equal (b, before, sizeof b);
    assert_memory_equal (&p, &p0, sizeof p);
    // Every exercise indicator the standard defines is taken.
    const uint8_t ok[] = {0, 1, 2, 128, 129, 130};
    for (size_t i = 0; i < sizeof ok; i++) {
        h.exercise_indicator = ok[i];
        assert_int_equal (gw_s4607_packet_begin (&p, b, 32, &h), 0);
        assert_int_equal (b[13], ok[i]);
    }
}

/* The Platform Location segment of the worked example, as the standard lays it out:
 *   L1 time 3723.456 s       -> 3723456 ms                            = 0x0038d0c0
 *   L2 latitude 35.96        -> 35.96 * 2^31 / 90   = 858039022.023   = 0x3324a2ee (SA32)
 *   L3 longitude -121.23     -> 238.77 * 2^32 / 360 = 2848637059.072  = 0xa9cac083 (BA32)
 *   L4 altitude 1234.56 m    -> 123456 cm                             = 0x0001e240
 *   L5 track 125.31          -> 125.31 * 2^16 / 360 = 22811.989       = 0x591c (BA16)
 *   L6 speed 45.678 m/s      -> 45678 mm/s                            = 0x0000b26e
 *   L7 vertical -2.5 m/s     -> -25 dm/s                              = 0xe7 (S8) */
// clang-format off
static const uint8_t s_platform_want[28] = {
    /*  0 S1 type 13, S2 size 28 */ 13, 0, 0, 0, 28,
    /*  5 L1 */ 0x00, 0x38, 0xd0, 0xc0,
    /*  9 L2 */ 0x33, 0x24, 0xa2, 0xee,
    /* 13 L3 */ 0xa9, 0xca, 0xc0, 0x83,
    /* 17 L4 */ 0x00, 0x01, 0xe2, 0x40,
    /* 21 L5 */ 0x59, 0x1c,
    /* 23 L6 */ 0x00, 0x00, 0xb2, 0x6e,
    /* 27 L7 */ 0xe7,
};
// clang-format on

static gw_s4607_platform_t s_platform (void)
{
    gw_s4607_platform_t pl = {
        .time_s = 3723.456,
        .lat_deg = 35.96,
        .lon_deg = -121.23,
        .alt_m = 1234.56,
        .track_deg = 125.31,
        .speed_mps = 45.678,
        .vertical_velocity_mps = -2.5,
    };
    return pl;
}

static void test_platform_bytes (void **state)
{
    (void)state;
    uint8_t b[128];
    gw_s4607_packet_t p;
    gw_s4607_header_t h = s_header (0);
    memset (b, 0xee, sizeof b);
    assert_int_equal (gw_s4607_packet_begin (&p, b, sizeof b, &h), 0);
    gw_s4607_platform_t pl = s_platform ();
    assert_int_equal (gw_s4607_add_platform (&p, &pl), 0);
    assert_int_equal (p.len, 32 + 28);
    assert_int_equal (gw_s4607_packet_end (&p), 60);
    assert_int_equal (s_be32 (b + 2), 60); // P2 counts header and segments
    s_assert_bytes (b + 32, s_platform_want, 28);
    assert_int_equal (b[60], 0xee);
}

/* The Mission segment: M1 "PLAN-A", M2 "FLIGHT 7" (12 chars each, space padded),
 * M3 platform type 16 (UAV-Army), M4 "SIM" (10 chars), M5-M7 2024-02-29. */
// clang-format off
static const uint8_t s_mission_want[44] = {
    /*  0 S1 type 1, S2 size 44 */ 1, 0, 0, 0, 44,
    /*  5 M1 */ 'P', 'L', 'A', 'N', '-', 'A', ' ', ' ', ' ', ' ', ' ', ' ',
    /* 17 M2 */ 'F', 'L', 'I', 'G', 'H', 'T', ' ', '7', ' ', ' ', ' ', ' ',
    /* 29 M3 */ 16,
    /* 30 M4 */ 'S', 'I', 'M', ' ', ' ', ' ', ' ', ' ', ' ', ' ',
    /* 40 M5 year 2024, M6 month, M7 day */ 0x07, 0xe8, 2, 29,
};
// clang-format on

static gw_s4607_mission_t s_mission (void)
{
    gw_s4607_mission_t m = {
        .mission_plan = "PLAN-A",
        .flight_plan = "FLIGHT 7",
        .platform_type = GW_S4607_PLATFORM_UAV_ARMY,
        .platform_config = "SIM",
        .year = 2024,
        .month = 2,
        .day = 29,
    };
    return m;
}

static void test_mission_bytes (void **state)
{
    (void)state;
    uint8_t b[128];
    gw_s4607_packet_t p;
    gw_s4607_header_t h = s_header (0);
    assert_int_equal (gw_s4607_packet_begin (&p, b, sizeof b, &h), 0);
    gw_s4607_mission_t m = s_mission ();
    assert_int_equal (gw_s4607_add_mission (&p, &m), 0);
    assert_int_equal (gw_s4607_packet_end (&p), 32 + 44);
    s_assert_bytes (b + 32, s_mission_want, 44);
    // Dates that are not on the calendar, and a plan of 13 characters.
    const uint16_t ymd[][3] = {{2023, 2, 29}, {2024, 2, 30}, {2024, 13, 1}, {2024, 0, 1},
                               {2024, 4, 31}, {2024, 1, 0},  {0, 1, 1},     {1900, 2, 29}};
    for (size_t i = 0; i < sizeof ymd / sizeof ymd[0]; i++) {
        m.year = ymd[i][0], m.month = (uint8_t)ymd[i][1], m.day = (uint8_t)ymd[i][2];
        if (gw_s4607_add_mission (&p, &m) != -EINVAL)
            fail_msg ("%u-%u-%u accepted", ymd[i][0], ymd[i][1], ymd[i][2]);
    }
    m = s_mission ();
    m.year = 2000; // a century leap year
    assert_int_equal (gw_s4607_add_mission (&p, &m), 0);
    memset (m.mission_plan, 'P', sizeof m.mission_plan);
    assert_int_equal (gw_s4607_add_mission (&p, &m), -EINVAL);
    assert_int_equal (p.len, 32 + 44 + 44);
}

/* The angle, binary-decimal and integer encoders, through the fields that use them. */
static void test_encodings (void **state)
{
    (void)state;
    uint8_t b[128];
    gw_s4607_packet_t p;
    gw_s4607_header_t h = s_header (0);
    gw_s4607_platform_t pl = s_platform ();
    const struct {
        double lat, lon;
        uint32_t want_lat, want_lon;
    } ll[] = {
        // -12.345678 * 2^31 / 90 = -294579351.43 -> -294579351 = 0xee711369 (two's complement);
        // 5.4321 * 2^32 / 360 = 64807477.36 -> 0x03dce235.
        {-12.345678, 5.4321, 0xee711369u, 0x03dce235u},
        {90.0, 180.0, 0x7fffffffu, 0x80000000u}, // +90 takes the top code; 180 is half a turn
        {-90.0, -180.0, 0x80000000u, 0x80000000u},
        {0.0, 360.0, 0, 0},                  // a whole turn wraps to 0
        {0.0, -1e-8, 0, 0},                  // 359.99999999 rounds up to 2^32: 0
        {0.0, 720.0 + 90.0, 0, 0x40000000u}, // two turns and a quarter
        {s_sa32_deg (-1), s_ba32_deg (1), 0xffffffffu, 1},
    };
    for (size_t i = 0; i < sizeof ll / sizeof ll[0]; i++) {
        pl.lat_deg = ll[i].lat, pl.lon_deg = ll[i].lon;
        assert_int_equal (gw_s4607_packet_begin (&p, b, sizeof b, &h), 0);
        assert_int_equal (gw_s4607_add_platform (&p, &pl), 0);
        if (s_be32 (b + 41) != ll[i].want_lat || s_be32 (b + 45) != ll[i].want_lon)
            fail_msg ("%.10g, %.10g: 0x%08x 0x%08x, want 0x%08x 0x%08x", ll[i].lat, ll[i].lon,
                      s_be32 (b + 41), s_be32 (b + 45), ll[i].want_lat, ll[i].want_lon);
    }
    // Latitudes past the poles and non-finite angles are refused.
    const double bad_lat[] = {90.000001, -90.000001, NAN, INFINITY};
    for (size_t i = 0; i < 4; i++) {
        pl = s_platform ();
        pl.lat_deg = bad_lat[i];
        assert_int_equal (gw_s4607_add_platform (&p, &pl), -EINVAL);
        pl = s_platform ();
        pl.lon_deg = i < 2 ? NAN : bad_lat[i];
        assert_int_equal (gw_s4607_add_platform (&p, &pl), -EINVAL);
    }
    // BA16: 125.31 -> 0x591c, the standard's Annex C example (0101100100011100 =
    // 125.31005859375 degrees); -90 -> 270 -> 49152 = 0xc000; 359.999 -> 65535.82 ->
    // 65536, wraps to 0.
    const struct {
        double deg;
        uint16_t want;
    } ba16[] = {{125.31, 0x591c}, {-90.0, 0xc000}, {359.999, 0}, {0.0054931640625, 1}};
    for (size_t i = 0; i < sizeof ba16 / sizeof ba16[0]; i++) {
        pl = s_platform ();
        pl.track_deg = ba16[i].deg;
        assert_int_equal (gw_s4607_packet_begin (&p, b, sizeof b, &h), 0);
        assert_int_equal (gw_s4607_add_platform (&p, &pl), 0);
        assert_int_equal (s_be16 (b + 53), ba16[i].want);
    }
    // L4 altitude: -500 m is the field's floor; L6 speed: 8000 m/s its ceiling; L7
    // vertical velocity saturates at -12.8 and 12.7 m/s; halves round away from zero.
    pl = s_platform ();
    pl.alt_m = -500.0, pl.speed_mps = 8000.0, pl.vertical_velocity_mps = -30.0;
    assert_int_equal (gw_s4607_packet_begin (&p, b, sizeof b, &h), 0);
    assert_int_equal (gw_s4607_add_platform (&p, &pl), 0);
    assert_int_equal (s_be32 (b + 49), (uint32_t)-50000);
    assert_int_equal (s_be32 (b + 55), 8000000);
    assert_int_equal (b[59], 0x80); // -128 dm/s
    pl.vertical_velocity_mps = 99.0, pl.alt_m = 0.125, pl.time_s = 0.0625;
    assert_int_equal (gw_s4607_packet_begin (&p, b, sizeof b, &h), 0);
    assert_int_equal (gw_s4607_add_platform (&p, &pl), 0);
    assert_int_equal (b[59], 0x7f);
    assert_int_equal (s_be32 (b + 49), 13); // 12.5 cm -> 13 cm
    assert_int_equal (s_be32 (b + 37), 63); // 62.5 ms -> 63 ms
    const struct {
        double time, alt, speed;
    } bad[] = {{-0.001, 0, 0},     {4000000.001, 0, 0}, {0, -500.01, 0},
               {0, 2e7 + 0.01, 0}, {0, 0, -0.001},      {0, 0, 8000.001}};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        pl = s_platform ();
        pl.time_s = bad[i].time, pl.alt_m = bad[i].alt, pl.speed_mps = bad[i].speed;
        if (gw_s4607_add_platform (&p, &pl) != -EINVAL)
            fail_msg ("platform location %zu accepted", i);
    }
}

/* A dwell with every field present (all groups, the MDV, every report field). */
static gw_s4607_dwell_t s_dwell_full (void)
{
    gw_s4607_dwell_t d = {
        .revisit_index = 7,
        .dwell_index = 3,
        .last_dwell = true,
        .time_s = 3600.25,
        .sensor_lat_deg = 35.96,
        .sensor_lon_deg = -121.23,
        .sensor_alt_m = 3048.0,
        .along_track_unc_m = 5.0,
        .cross_track_unc_m = 6.0,
        .alt_unc_m = 7.0,
        .track_deg = 90.0,
        .speed_mps = 60.0,
        .vertical_velocity_mps = 1.5,
        .track_unc_deg = 2.0,
        .speed_unc_mps = 0.5,
        .vertical_velocity_unc_mps = 0.25,
        .platform_heading_deg = 91.0,
        .platform_pitch_deg = -34.876,
        .platform_roll_deg = 10.0,
        .area_lat_deg = 36.0,
        .area_lon_deg = -121.0,
        .range_half_extent_m = 12500.0,
        .angle_half_extent_deg = 15.0,
        .sensor_heading_deg = 180.0,
        .sensor_pitch_deg = -20.0,
        .sensor_roll_deg = 0.0,
        .mdv_mps = 1.2,
        .report_fields = GW_S4607_R_ALL,
    };
    return d;
}

/* The same dwell with only the mandatory fields. */
static gw_s4607_dwell_t s_dwell_min (void)
{
    gw_s4607_dwell_t d = s_dwell_full ();
    d.along_track_unc_m = d.cross_track_unc_m = d.alt_unc_m = NAN;
    d.track_deg = d.speed_mps = d.vertical_velocity_mps = NAN;
    d.track_unc_deg = d.speed_unc_mps = d.vertical_velocity_unc_mps = NAN;
    d.platform_heading_deg = d.platform_pitch_deg = d.platform_roll_deg = NAN;
    d.sensor_heading_deg = d.sensor_pitch_deg = d.sensor_roll_deg = NAN;
    d.mdv_mps = NAN;
    d.report_fields = 0;
    return d;
}

static gw_s4607_report_t s_report (int i)
{
    gw_s4607_report_t r = {
        .index = (uint16_t)(100 + i),
        .lat_deg = 35.97 + 0.001 * i,
        .lon_deg = -121.22 - 0.001 * i,
        .height_m = 150.0 + i,
        .los_velocity_mps = -12.34 + i,
        .wrap_velocity_mps = 40.0,
        .snr_db = 17.0 + i,
        .classification = GW_S4607_TARGET_NO_INFO_SIM,
        .class_probability = 0.5,
        .slant_range_unc_m = 7.5,
        .cross_range_unc_m = 20.0,
        .height_unc_m = 15.0,
        .los_velocity_unc_mps = 0.3,
        .truth_application = 2,
        .truth_entity = 0x00010203u + (uint32_t)i,
        .rcs_dbsm = 10.0,
    };
    return r;
}

/* Dwell area fields through the dwell segment: offsets in a mandatory-only dwell. */
enum {
    S_OFF_MASK = 5,      // D1, after the segment header
    S_OFF_AREA = 5 + 31, // D24, after D1-D9 (8 + 23 bytes)
    S_MIN_DWELL = 48,    // 5 + 8 + 23 + 12
};

static void test_dwell_bytes (void **state)
{
    (void)state;
    uint8_t b[512];
    gw_s4607_packet_t p;
    gw_s4607_header_t h = s_header (9);
    gw_s4607_dwell_t d = s_dwell_min ();
    assert_int_equal (gw_s4607_packet_begin (&p, b, sizeof b, &h), 0);
    assert_int_equal (gw_s4607_dwell_size (&d, NULL, 0), S_MIN_DWELL);
    assert_int_equal (gw_s4607_add_dwell (&p, &d, NULL, 0), 0);
    const uint8_t *s = b + 32;
    // Only D2-D9 and D24-D27 and, always, the hi-res location D32.2-3: bytes 7 and 5-3.
    assert_int_equal (s_be64 (s + S_OFF_MASK), 0xff0003c180000000u);
    // D2 7, D3 3, D4 1 (last dwell), D5 0 reports, D6 3600250 ms = 0x0036ef7a,
    // D7 35.96 = 0x3324a2ee, D8 -121.23 = 0xa9cac083, D9 3048 m = 304800 cm = 0x0004a6a0.
    const uint8_t d2_d9[] = {0,    7,    0,    3,    1,    0,    0,    0x00, 0x36, 0xef, 0x7a, 0x33,
                             0x24, 0xa2, 0xee, 0xa9, 0xca, 0xc0, 0x83, 0x00, 0x04, 0xa6, 0xa0};
    s_assert_bytes (s + 13, d2_d9, sizeof d2_d9);
    // D24 36.0 -> 36/90 * 2^31 = 858993459.2 -> 0x33333333; D25 -121 -> 239/360 * 2^32 =
    // 2851381065.96 -> 0xa9f49f4a; D26 12.5 km -> B16 12.5 * 128 = 1600 = 0x0640;
    // D27 15 degrees -> 15/360 * 2^16 = 2730.67 -> 2731 = 0x0aab.
    const uint8_t d24_d27[] = {0x33, 0x33, 0x33, 0x33, 0xa9, 0xf4,
                               0x9f, 0x4a, 0x06, 0x40, 0x0a, 0xab};
    s_assert_bytes (s + S_OFF_AREA, d24_d27, sizeof d24_d27);
    assert_int_equal (s[0], GW_S4607_SEG_DWELL);
    assert_int_equal (s_be32 (s + 1), S_MIN_DWELL);
    assert_int_equal (gw_s4607_packet_end (&p), 32 + S_MIN_DWELL);

    // B16: sign and magnitude, 7 fraction bits: 0.5 km -> 0x0040, 255.9921875 km ->
    // 0x7fff; 256 km, a negative or a NAN half extent, a dwell angle over 180: refused.
    const struct {
        double m;
        uint16_t want;
    } b16[] = {{500.0, 0x0040}, {255992.1875, 0x7fff}, {0.0, 0}, {3.90625, 0x0001}};
    for (size_t i = 0; i < sizeof b16 / sizeof b16[0]; i++) {
        d.range_half_extent_m = b16[i].m;
        assert_int_equal (gw_s4607_packet_begin (&p, b, sizeof b, &h), 0);
        assert_int_equal (gw_s4607_add_dwell (&p, &d, NULL, 0), 0);
        assert_int_equal (s_be16 (s + S_OFF_AREA + 8), b16[i].want);
    }
    const double bad_range[] = {256000.0, -1.0, NAN, INFINITY};
    for (size_t i = 0; i < 4; i++) {
        d = s_dwell_min ();
        d.range_half_extent_m = bad_range[i];
        assert_int_equal (gw_s4607_add_dwell (&p, &d, NULL, 0), -EINVAL);
    }
    d = s_dwell_min ();
    d.angle_half_extent_deg = 180.0; // a full circle: 0x8000
    assert_int_equal (gw_s4607_packet_begin (&p, b, sizeof b, &h), 0);
    assert_int_equal (gw_s4607_add_dwell (&p, &d, NULL, 0), 0);
    assert_int_equal (s_be16 (s + S_OFF_AREA + 10), 0x8000);
    d.angle_half_extent_deg = 180.01;
    assert_int_equal (gw_s4607_add_dwell (&p, &d, NULL, 0), -EINVAL);
    d.angle_half_extent_deg = -1.0;
    assert_int_equal (gw_s4607_add_dwell (&p, &d, NULL, 0), -EINVAL);

    // SA16 through the platform orientation (D21-D23, after D15-D20 are absent):
    // pitch -34.876 -> -34.876 * 2^15 / 90 = -12697.96 -> -12698 = 0xce66, the standard's
    // Annex C example (1100111001100110 = -34.8760986328125 degrees); roll +90 takes
    // the top code 0x7fff; heading 91 -> 16566.04 -> 0x40b6.
    d = s_dwell_min ();
    d.platform_heading_deg = 91.0, d.platform_pitch_deg = -34.876, d.platform_roll_deg = 90.0;
    assert_int_equal (gw_s4607_packet_begin (&p, b, sizeof b, &h), 0);
    assert_int_equal (gw_s4607_add_dwell (&p, &d, NULL, 0), 0);
    assert_int_equal (s_be64 (s + S_OFF_MASK), 0xff001fc180000000u); // + D21, D22, D23
    const uint8_t d21_d23[] = {0x40, 0xb6, 0xce, 0x66, 0x7f, 0xff};
    s_assert_bytes (s + S_OFF_AREA, d21_d23, 6);
    d.platform_roll_deg = -90.0;
    assert_int_equal (gw_s4607_packet_begin (&p, b, sizeof b, &h), 0);
    assert_int_equal (gw_s4607_add_dwell (&p, &d, NULL, 0), 0);
    assert_int_equal (s_be16 (s + S_OFF_AREA + 4), 0x8000);
    d.platform_roll_deg = 90.01;
    assert_int_equal (gw_s4607_add_dwell (&p, &d, NULL, 0), -EINVAL);
}

/* The existence mask of a chosen subset, worked bit by bit (D2 is bit 63):
 *   byte 7 (bits 63-56) D2-D9, mandatory                          1111 1111 = 0xff
 *   byte 6 (55-48) D10 D11 D12 D13 D14 D15 D16 D17: D15-D17      0000 0111 = 0x07
 *   byte 5 (47-40) D18 ... D23 D24 D25: D24, D25                  0000 0011 = 0x03
 *   byte 4 (39-32) D26 D27 D28 D29 D30 D31 D32.1 D32.2:
 *                  D26, D27, D31, D32.1, D32.2                    1100 0111 = 0xc7
 *   byte 3 (31-24) D32.3 .4 .5 .6 .7 .8 .9 .10: .3, .7, .8, .9    1000 1110 = 0x8e
 *   byte 2 (23-16) D32.11 ... D32.18: .18                          0000 0001 = 0x01
 *   bytes 1-0 spare                                                            0x0000
 * Its size: 5 + 8 (mask) + 23 (D2-D9) + 7 (D15 2, D16 4, D17 1) + 12 (D24-D27)
 * + 1 (D31) = 56, and each report 2 (D32.1) + 8 (D32.2-3) + 4 (D32.7-8) + 1 (D32.9)
 * + 1 (D32.18) = 16. */
static void test_mask_and_sizes (void **state)
{
    (void)state;
    uint8_t b[1024];
    gw_s4607_packet_t p;
    gw_s4607_header_t h = s_header (9);
    gw_s4607_dwell_t d = s_dwell_min ();
    d.track_deg = 10.0, d.speed_mps = 20.0, d.vertical_velocity_mps = -1.0, d.mdv_mps = 2.0;
    d.report_fields = GW_S4607_R_INDEX | GW_S4607_R_VELOCITY | GW_S4607_R_SNR | GW_S4607_R_RCS;
    gw_s4607_report_t r[3] = {s_report (0), s_report (1), s_report (2)};
    assert_int_equal (gw_s4607_dwell_size (&d, r, 3), 56 + 3 * 16);
    assert_int_equal (gw_s4607_packet_begin (&p, b, sizeof b, &h), 0);
    assert_int_equal (gw_s4607_add_dwell (&p, &d, r, 3), 0);
    assert_int_equal (p.len, 32 + 56 + 48);
    assert_int_equal (s_be64 (b + 32 + S_OFF_MASK), 0xff0703c78e010000u);
    assert_int_equal (s_be32 (b + 33), 104);      // the segment size field
    assert_int_equal (s_be16 (b + 32 + 18), 3);   // D5, the report count
    assert_int_equal (s_be16 (b + 32 + 56), 100); // report 0: D32.1
    // Report 1 at 56 + 16: D32.1 101, D32.2-3, then D32.7 -11.34 m/s = -1134 cm/s, D32.8
    // 40 m/s = 4000 cm/s, D32.9 18 dB, D32.18 10 dBsm = 20 half-dB.
    const uint8_t *r1 = b + 32 + 56 + 16;
    assert_int_equal (s_be16 (r1), 101);
    assert_int_equal (s_be16 (r1 + 10), (uint16_t)-1134);
    assert_int_equal (s_be16 (r1 + 12), 4000);
    assert_int_equal (r1[14], 18);
    assert_int_equal (r1[15], 20);

    // The whole dwell: 83 bytes and 32 a report; the minimal one 48 and 8 a report.
    gw_s4607_dwell_t full = s_dwell_full ();
    size_t report_full = 2 + 4 + 4 + 2 + 2 + 2 + 1 + 1 + 1 + 2 + 2 + 1 + 2 + 1 + 4 + 1;
    size_t dwell_full = 5 + 8 + (2 + 2 + 1 + 2 + 4 + 4 + 4 + 4) + (4 + 4 + 2) + (2 + 4 + 1) +
                        (1 + 2 + 2) + (2 + 2 + 2) + (4 + 4 + 2 + 2) + (2 + 2 + 2) + 1;
    assert_int_equal (report_full, 32);
    assert_int_equal (dwell_full, 83);
    assert_int_equal (gw_s4607_dwell_size (&full, r, 3), 83 + 3 * 32);
    assert_int_equal (gw_s4607_dwell_size (&full, NULL, 0), 83);
    gw_s4607_dwell_t min = s_dwell_min ();
    assert_int_equal (gw_s4607_dwell_size (&min, r, 3), 48 + 3 * 8);
    assert_int_equal (gw_s4607_packet_begin (&p, b, sizeof b, &h), 0);
    assert_int_equal (gw_s4607_add_dwell (&p, &full, r, 3), 0);
    assert_int_equal (p.len, 32 + 83 + 96);
    // All but D10-D11 and D32.4-5: byte 6 0x3f (as the standard's example "FF3F"), byte 3 0x9f.
    assert_int_equal (s_be64 (b + 32 + S_OFF_MASK), 0xff3fffff9fff0000u);

    // Fixed segments: 44, 73 and 28 bytes, their size fields too.
    gw_s4607_mission_t m = s_mission ();
    gw_s4607_platform_t pl = s_platform ();
    assert_int_equal (gw_s4607_packet_begin (&p, b, sizeof b, &h), 0);
    assert_int_equal (gw_s4607_add_mission (&p, &m), 0);
    assert_int_equal (gw_s4607_add_platform (&p, &pl), 0);
    assert_int_equal (s_be32 (b + 33), 44);
    assert_int_equal (s_be32 (b + 32 + 44 + 1), 28);
    assert_int_equal (gw_s4607_packet_end (&p), 32 + 44 + 28);
}

/* Field by field: which values saturate, which are refused, and the report bytes. */
static void test_report_ranges (void **state)
{
    (void)state;
    uint8_t b[256];
    gw_s4607_packet_t p;
    gw_s4607_header_t h = s_header (9);
    gw_s4607_dwell_t d = s_dwell_min ();
    d.report_fields = GW_S4607_R_ALL;
    // Every report field, at its report offset (D32.1 first, at 0).
    enum {
        O_LAT = 2,
        O_LON = 6,
        O_HEIGHT = 10,
        O_VLOS = 12,
        O_WRAP = 14,
        O_SNR = 16,
        O_CLASS = 17,
        O_PROB = 18,
        O_SLANT = 19,
        O_CROSS = 21,
        O_HUNC = 23,
        O_VUNC = 24,
        O_APP = 26,
        O_ENTITY = 27,
        O_RCS = 31,
    };
    const uint8_t *rb = b + 32 + S_MIN_DWELL;
    gw_s4607_report_t r = s_report (0);
    r.lat_deg = 35.96, r.lon_deg = -121.23;
    r.class_probability = 0.125; // 12.5 % -> 13
    r.rcs_dbsm = 10.25;          // 20.5 half-dB -> 21: halves go away from zero
    r.los_velocity_mps = -0.125; // -12.5 cm/s -> -13
    assert_int_equal (gw_s4607_packet_begin (&p, b, sizeof b, &h), 0);
    assert_int_equal (gw_s4607_add_dwell (&p, &d, &r, 1), 0);
    assert_int_equal (p.len, 32 + S_MIN_DWELL + 32);
    assert_int_equal (s_be16 (rb), 100);
    assert_int_equal (s_be32 (rb + O_LAT), 0x3324a2eeu);
    assert_int_equal (s_be32 (rb + O_LON), 0xa9cac083u);
    assert_int_equal (s_be16 (rb + O_HEIGHT), 150);
    assert_int_equal (s_be16 (rb + O_VLOS), (uint16_t)-13);
    assert_int_equal (s_be16 (rb + O_WRAP), 4000);
    assert_int_equal (rb[O_SNR], 17);
    assert_int_equal (rb[O_CLASS], 128); // No Information, Simulated Target
    assert_int_equal (rb[O_PROB], 13);
    assert_int_equal (s_be16 (rb + O_SLANT), 750); // 7.5 m in cm
    assert_int_equal (s_be16 (rb + O_CROSS), 200); // 20 m in dm
    assert_int_equal (rb[O_HUNC], 15);             // m
    assert_int_equal (s_be16 (rb + O_VUNC), 30);   // 0.3 m/s in cm/s
    assert_int_equal (rb[O_APP], 2);
    assert_int_equal (s_be32 (rb + O_ENTITY), 0x00010203u);
    assert_int_equal (rb[O_RCS], 21);

    // Saturated at the field's limits.
    r.los_velocity_mps = 400.0, r.snr_db = 300.0, r.rcs_dbsm = 100.0, r.wrap_velocity_mps = 1e4;
    r.slant_range_unc_m = 1e6, r.cross_range_unc_m = 1e6, r.height_unc_m = 1e6;
    r.los_velocity_unc_mps = 99.0;
    assert_int_equal (gw_s4607_packet_begin (&p, b, sizeof b, &h), 0);
    assert_int_equal (gw_s4607_add_dwell (&p, &d, &r, 1), 0);
    assert_int_equal (s_be16 (rb + O_VLOS), 32767);
    assert_int_equal (s_be16 (rb + O_WRAP), 65535);
    assert_int_equal (rb[O_SNR], 127);
    assert_int_equal (rb[O_RCS], 127); // 63.5 dBsm
    assert_int_equal (s_be16 (rb + O_SLANT), 65535);
    assert_int_equal (s_be16 (rb + O_CROSS), 65535);
    assert_int_equal (rb[O_HUNC], 255);
    assert_int_equal (s_be16 (rb + O_VUNC), 5000); // the field's 50 m/s
    r.los_velocity_mps = -400.0, r.snr_db = -300.0, r.rcs_dbsm = -100.0;
    assert_int_equal (gw_s4607_packet_begin (&p, b, sizeof b, &h), 0);
    assert_int_equal (gw_s4607_add_dwell (&p, &d, &r, 1), 0);
    assert_int_equal (s_be16 (rb + O_VLOS), 0x8000);
    assert_int_equal (rb[O_SNR], 0x80);
    assert_int_equal (rb[O_RCS], 0x80); // -64 dBsm

    // Refused: a geodetic height out of the field, a probability out of 0..1, a
    // negative uncertainty or wrap velocity, anything non-finite in a present field.
    gw_s4607_report_t bad[10];
    for (int i = 0; i < 10; i++)
        bad[i] = s_report (0);
    bad[0].height_m = -1000.6, bad[1].height_m = 32767.6, bad[2].class_probability = 1.01;
    bad[3].class_probability = -0.01, bad[4].slant_range_unc_m = -0.01;
    bad[5].wrap_velocity_mps = -1.0, bad[6].snr_db = NAN, bad[7].rcs_dbsm = INFINITY;
    bad[8].lat_deg = 91.0, bad[9].lon_deg = NAN;
    for (int i = 0; i < 10; i++)
        if (gw_s4607_add_dwell (&p, &d, &bad[i], 1) != -EINVAL)
            fail_msg ("bad report %d accepted", i);
    // A field the dwell does not carry is not read: NAN there is fine.
    d.report_fields = GW_S4607_R_INDEX;
    assert_int_equal (gw_s4607_add_dwell (&p, &d, &bad[6], 1), 0);
}

/* ---- 2. failures leave the packet as it was ---------------------------------------------- */

typedef struct {
    uint8_t buf[1024];
    gw_s4607_packet_t p;
} s_snap_t;

/* A packet with a header and a platform segment, in a buffer of cap bytes. */
static void s_start (s_snap_t *s, size_t cap, uint32_t job)
{
    gw_s4607_header_t h = s_header (job);
    gw_s4607_platform_t pl = s_platform ();
    memset (s->buf, 0xa5, sizeof s->buf);
    assert_true (cap <= sizeof s->buf);
    assert_int_equal (gw_s4607_packet_begin (&s->p, s->buf, cap, &h), 0);
    assert_int_equal (gw_s4607_add_platform (&s->p, &pl), 0);
}

/* Each kind of segment, added to s: which one is `kind`. */
static int s_add (s_snap_t *s, int kind, const gw_s4607_dwell_t *d, const gw_s4607_report_t *r,
                  size_t n)
{
    gw_s4607_mission_t m = s_mission ();
    gw_s4607_platform_t pl = s_platform ();
    gw_s4607_job_t j;
    switch (kind) {
    case 0:
        return gw_s4607_add_mission (&s->p, &m);
    case 1:
        memset (&j, 0, sizeof j);
        j.job_id = 5, j.priority = 1, j.revisit_interval_s = 10.0;
        j.along_track_unc_m = j.cross_track_unc_m = j.altitude_unc_m = NAN;
        j.track_unc_deg = j.speed_unc_mps = j.slant_range_sd_m = j.cross_range_sd_deg = NAN;
        j.los_velocity_sd_mps = j.mdv_mps = j.detection_probability = NAN;
        j.false_alarm_density_db = NAN;
        return gw_s4607_add_job (&s->p, &j);
    case 2:
        return gw_s4607_add_platform (&s->p, &pl);
    default:
        return gw_s4607_add_dwell (&s->p, d, r, n);
    }
}

static void test_enospc (void **state)
{
    (void)state;
    static s_snap_t a, b;
    gw_s4607_report_t r[3] = {s_report (0), s_report (1), s_report (2)};
    gw_s4607_dwell_t dwells[2] = {s_dwell_full (), s_dwell_min ()};
    const size_t fixed[3] = {GW_S4607_MISSION_LEN, GW_S4607_JOB_LEN, GW_S4607_PLATFORM_LEN};
    for (int kind = 0; kind < 5; kind++) {
        const gw_s4607_dwell_t *d = kind >= 3 ? &dwells[kind - 3] : NULL;
        size_t size = kind < 3 ? fixed[kind] : gw_s4607_dwell_size (d, r, 3);
        assert_true (size > 0);
        // One byte short, then none to spare, then an empty buffer's worth.
        for (size_t short_by = 1; short_by <= size; short_by += size - 1) {
            s_start (&a, 60 + size - short_by, 9);
            b = a;
            b.p.buf = b.buf; // the copy's own buffer, for the comparison
            a.p.buf = a.buf;
            if (s_add (&a, kind, d, r, 3) != -ENOSPC)
                fail_msg ("kind %d with %zu bytes short: not -ENOSPC", kind, short_by);
            assert_memory_equal (a.buf, b.buf, sizeof a.buf);
            assert_true (a.p.cap == b.p.cap && a.p.len == b.p.len && a.p.len == 60);
            if (short_by == size)
                break;
        }
        s_start (&a, 60 + size, 9);
        assert_int_equal (s_add (&a, kind, d, r, 3), 0);
        assert_int_equal (a.p.len, 60 + size);
        assert_int_equal (s_be32 (a.buf + 2), 60 + size);
        assert_int_equal (a.buf[60 + size], 0xa5); // nothing past the segment
        assert_int_equal (s_be32 (a.buf + 61), size);
    }
}

/* Every mandatory dwell field NAN in turn, partial groups, a dwell without a job:
 * -EINVAL and nothing written. */
static void test_einval (void **state)
{
    (void)state;
    static s_snap_t a, b;
    gw_s4607_report_t r[3] = {s_report (0), s_report (1), s_report (2)};
    const size_t mandatory[] = {
        offsetof (gw_s4607_dwell_t, time_s),
        offsetof (gw_s4607_dwell_t, sensor_lat_deg),
        offsetof (gw_s4607_dwell_t, sensor_lon_deg),
        offsetof (gw_s4607_dwell_t, sensor_alt_m),
        offsetof (gw_s4607_dwell_t, area_lat_deg),
        offsetof (gw_s4607_dwell_t, area_lon_deg),
        offsetof (gw_s4607_dwell_t, range_half_extent_m),
        offsetof (gw_s4607_dwell_t, angle_half_extent_deg),
    };
    // One member of each group absent while the others are present.
    const size_t partial[] = {
        offsetof (gw_s4607_dwell_t, alt_unc_m),
        offsetof (gw_s4607_dwell_t, speed_mps),
        offsetof (gw_s4607_dwell_t, track_unc_deg),
        offsetof (gw_s4607_dwell_t, platform_roll_deg),
        offsetof (gw_s4607_dwell_t, sensor_heading_deg),
    };
    s_start (&a, sizeof a.buf, 9);
    b = a;
    for (size_t i = 0; i < sizeof mandatory / sizeof mandatory[0]; i++) {
        const double bad[] = {NAN, INFINITY, -INFINITY};
        for (int k = 0; k < 3; k++) {
            gw_s4607_dwell_t d = s_dwell_full ();
            memcpy ((char *)&d + mandatory[i], &bad[k], sizeof (double));
            if (gw_s4607_add_dwell (&a.p, &d, r, 3) != -EINVAL)
                fail_msg ("dwell field at %zu = %g accepted", mandatory[i], bad[k]);
            a.p.buf = b.p.buf = a.buf; // compare the structs by their contents
            assert_memory_equal (a.buf, b.buf, sizeof a.buf);
            assert_int_equal (a.p.len, b.p.len);
        }
    }
    for (size_t i = 0; i < sizeof partial / sizeof partial[0]; i++) {
        gw_s4607_dwell_t d = s_dwell_full ();
        const double nan = NAN;
        memcpy ((char *)&d + partial[i], &nan, sizeof (double));
        assert_int_equal (gw_s4607_dwell_size (&d, r, 3), 0);
        assert_int_equal (gw_s4607_add_dwell (&a.p, &d, r, 3), -EINVAL);
        // Present with infinity, the group is whole but the value is not finite.
        const double inf = INFINITY;
        memcpy ((char *)&d + partial[i], &inf, sizeof (double));
        assert_true (gw_s4607_dwell_size (&d, r, 3) > 0);
        assert_int_equal (gw_s4607_add_dwell (&a.p, &d, r, 3), -EINVAL);
    }
    gw_s4607_dwell_t d = s_dwell_full ();
    d.report_fields = GW_S4607_R_ALL + 1; // an unknown report field
    assert_int_equal (gw_s4607_dwell_size (&d, r, 3), 0);
    assert_int_equal (gw_s4607_add_dwell (&a.p, &d, r, 3), -EINVAL);
    d = s_dwell_full ();
    assert_int_equal (gw_s4607_dwell_size (&d, r, 65536), 0);
    assert_int_equal (gw_s4607_add_dwell (&a.p, &d, r, 65536), -EINVAL);
    // Optional values refused or saturated.
    d = s_dwell_full ();
    d.speed_mps = -1.0; // a negative speed
    assert_int_equal (gw_s4607_add_dwell (&a.p, &d, r, 3), -EINVAL);
    d = s_dwell_full ();
    d.along_track_unc_m = -0.01;
    assert_int_equal (gw_s4607_add_dwell (&a.p, &d, r, 3), -EINVAL);
    d = s_dwell_full ();
    d.sensor_pitch_deg = -90.01;
    assert_int_equal (gw_s4607_add_dwell (&a.p, &d, r, 3), -EINVAL);
    d = s_dwell_full ();
    d.time_s = 4000000.001; // 4e9 + 1 ms: past the field
    assert_int_equal (gw_s4607_add_dwell (&a.p, &d, r, 3), -EINVAL);
    a.p.buf = b.p.buf = a.buf;
    assert_memory_equal (a.buf, b.buf, sizeof a.buf);
    assert_int_equal (a.p.len, b.p.len);

    // A dwell needs a job: P10 0 is refused; the same dwell goes into a packet with one.
    s_start (&a, sizeof a.buf, 0);
    d = s_dwell_full ();
    assert_int_equal (gw_s4607_add_dwell (&a.p, &d, r, 3), -EINVAL);
    assert_int_equal (a.p.len, 60);
    s_start (&a, sizeof a.buf, 1);
    assert_int_equal (gw_s4607_add_dwell (&a.p, &d, r, 3), 0);

    // The job definition: J1 0, a priority of 0 or 100, spare filter bits, a
    // non-finite corner or revisit interval, a probability above 1, a positive dB.
    gw_s4607_job_t j;
    memset (&j, 0, sizeof j);
    j.job_id = 5, j.priority = 1, j.revisit_interval_s = 10.0;
    j.along_track_unc_m = j.cross_track_unc_m = j.altitude_unc_m = NAN;
    j.track_unc_deg = j.speed_unc_mps = j.slant_range_sd_m = j.cross_range_sd_deg = NAN;
    j.los_velocity_sd_mps = j.mdv_mps = j.detection_probability = NAN;
    j.false_alarm_density_db = NAN;
    s_start (&a, sizeof a.buf, 0);
    b = a;
    for (int i = 0; i < 10; i++) {
        gw_s4607_job_t x = j;
        switch (i) {
        case 0:
            x.job_id = 0;
            break;
        case 1:
            x.priority = 0;
            break;
        case 2:
            x.priority = 100;
            break;
        case 3:
            x.filter_flags = 0x08;
            break;
        case 4:
            x.bounds[2].lat_deg = NAN;
            break;
        case 5:
            x.bounds[3].lon_deg = INFINITY;
            break;
        case 6:
            x.revisit_interval_s = NAN;
            break;
        case 7:
            x.revisit_interval_s = 6553.6;
            break;
        case 8:
            x.detection_probability = 1.5;
            break;
        default:
            x.false_alarm_density_db = 3.0;
            break;
        }
        if (gw_s4607_add_job (&a.p, &x) != -EINVAL)
            fail_msg ("job %d accepted", i);
    }
    a.p.buf = b.p.buf = a.buf;
    assert_memory_equal (a.buf, b.buf, sizeof a.buf);
    j.priority = GW_S4607_PRIORITY_END_OF_JOB;
    assert_int_equal (gw_s4607_add_job (&a.p, &j), 0);
    // The nominal values left out are "no statement": 0xffff and 0xff.
    const uint8_t *js = a.buf + 60 + 5 + 48; // J16 onwards, after J1-J15 (48 bytes)
    const uint8_t ns[] = {0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff,
                          0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff};
    s_assert_bytes (js, ns, sizeof ns);
    assert_int_equal (s_be16 (js - 2), 100); // J15: 10 s = 100 ds
}

/* dwell_size is what add_dwell appends, for every combination of groups and several
 * report field sets and counts. */
static void test_dwell_size (void **state)
{
    (void)state;
    static s_snap_t a;
    gw_s4607_report_t r[5];
    for (int i = 0; i < 5; i++)
        r[i] = s_report (i);
    const uint32_t fields[] = {0, GW_S4607_R_ALL, GW_S4607_R_INDEX | GW_S4607_R_RCS,
                               GW_S4607_R_UNCERTAINTY | GW_S4607_R_HEIGHT,
                               GW_S4607_R_TRUTH_TAG | GW_S4607_R_CLASS | GW_S4607_R_CLASS_PROB};
    const size_t report_size[] = {8, 32, 8 + 2 + 1, 8 + 7 + 2, 8 + 5 + 1 + 1};
    int checked = 0;
    for (int g = 0; g < 64; g++)
        for (size_t f = 0; f < sizeof fields / sizeof fields[0]; f++)
            for (size_t n = 0; n <= 5; n += 2) {
                gw_s4607_dwell_t d = s_dwell_full ();
                size_t want = 83;
                if (!(g & 1)) { // D12-D14: 4 + 4 + 2
                    d.along_track_unc_m = d.cross_track_unc_m = d.alt_unc_m = NAN;
                    want -= 10;
                }
                if (!(g & 2)) { // D15-D17: 2 + 4 + 1
                    d.track_deg = d.speed_mps = d.vertical_velocity_mps = NAN;
                    want -= 7;
                }
                if (!(g & 4)) { // D18-D20: 1 + 2 + 2
                    d.track_unc_deg = d.speed_unc_mps = d.vertical_velocity_unc_mps = NAN;
                    want -= 5;
                }
                if (!(g & 8)) { // D21-D23: 2 + 2 + 2
                    d.platform_heading_deg = d.platform_pitch_deg = d.platform_roll_deg = NAN;
                    want -= 6;
                }
                if (!(g & 16)) { // D28-D30: 2 + 2 + 2
                    d.sensor_heading_deg = d.sensor_pitch_deg = d.sensor_roll_deg = NAN;
                    want -= 6;
                }
                if (!(g & 32)) { // D31: 1
                    d.mdv_mps = NAN;
                    want -= 1;
                }
                d.report_fields = fields[f];
                want += n * report_size[f];
                size_t size = gw_s4607_dwell_size (&d, r, n);
                assert_int_equal (size, want);
                s_start (&a, sizeof a.buf, 9);
                assert_int_equal (gw_s4607_add_dwell (&a.p, &d, r, n), 0);
                assert_int_equal (a.p.len, 60 + size);
                assert_int_equal (s_be32 (a.buf + 61), size);
                assert_int_equal (s_be16 (a.buf + 60 + 18), n); // D5
                checked++;
            }
    print_message ("# %d dwell field sets: dwell_size equals the bytes appended\n", checked);
}

/* ---- 3. tshark reads back every raw integer ---------------------------------------------- */

#define S_NPKT 5

/* The fields tshark is asked for, and the values expected of each in each packet
 * (comma separated, as tshark aggregates several occurrences). */
static const char *const s_names[] = {
    "s4607.version",
    "s4607.size",
    "s4607.nationality",
    "s4607.sec.class",
    "s4607.sec.system",
    "s4607.sec.codes",
    "s4607.exind",
    "s4607.platform",
    "s4607.mission",
    "s4607.job",
    "s4607.seg.type",
    "s4607.seg.size",
    "s4607.mission.plan",
    "s4607.mission.flight",
    "s4607.mission.platform",
    "s4607.mission.config",
    "s4607.mission.year",
    "s4607.mission.month",
    "s4607.mission.day",
    "s4607.job.id",
    "s4607.job.type",
    "s4607.job.model",
    "s4607.job.filter",
    "s4607.job.priority",
    "s4607.job.ba.lat.a",
    "s4607.job.ba.lon.a",
    "s4607.job.ba.lat.b",
    "s4607.job.ba.lon.b",
    "s4607.job.ba.lat.c",
    "s4607.job.ba.lon.c",
    "s4607.job.ba.lat.d",
    "s4607.job.ba.lon.d",
    "s4607.job.mode",
    "s4607.job.revisit",
    "s4607.job.unc.track",
    "s4607.job.unc.cross",
    "s4607.job.unc.alt",
    "s4607.job.unc.heading",
    "s4607.job.unc.speed",
    "s4607.job.sense.slant",
    "s4607.job.sense.cross",
    "s4607.job.sense.vlos",
    "s4607.job.sense.mdv",
    "s4607.job.sense.prob",
    "s4607.job.sense.alarm",
    "s4607.job.terrain",
    "s4607.job.geoid",
    "s4607.ploc.time",
    "s4607.ploc.lat",
    "s4607.ploc.lon",
    "s4607.ploc.alt",
    "s4607.ploc.track",
    "s4607.ploc.speed",
    "s4607.ploc.velocity",
    "s4607.dwell.mask",
    "s4607.dwell.revisit",
    "s4607.dwell.dwell",
    "s4607.dwell.last",
    "s4607.dwell.count",
    "s4607.dwell.time",
    "s4607.dwell.sensor.lat",
    "s4607.dwell.sensor.lon",
    "s4607.dwell.sensor.alt",
    "s4607.dwell.unc.along",
    "s4607.dwell.unc.cross",
    "s4607.dwell.unc.alt",
    "s4607.dwell.track",
    "s4607.dwell.speed",
    "s4607.dwell.vvel",
    "s4607.dwell.track.unc",
    "s4607.dwell.speed.unc",
    "s4607.dwell.vvel.unc",
    "s4607.dwell.plat.heading",
    "s4607.dwell.plat.pitch",
    "s4607.dwell.plat.roll",
    "s4607.dwell.da.lat",
    "s4607.dwell.da.lon",
    "s4607.dwell.da.range",
    "s4607.dwell.da.angle",
    "s4607.dwell.sensor.heading",
    "s4607.dwell.sensor.pitch",
    "s4607.dwell.sensor.roll",
    "s4607.dwell.mdv",
    "s4607.dwell.rpt.idx",
    "s4607.dwell.rpt.lat",
    "s4607.dwell.rpt.lon",
    "s4607.dwell.rpt.height",
    "s4607.dwell.rpt.radial",
    "s4607.dwell.rpt.wrap",
    "s4607.dwell.rpt.snr",
    "s4607.dwell.rpt.class",
    "s4607.dwell.rpt.prob",
    "s4607.dwell.rpt.unc.slant",
    "s4607.dwell.rpt.unc.cross",
    "s4607.dwell.rpt.unc.height",
    "s4607.dwell.rpt.unc.radial",
    "s4607.dwell.rpt.tag.app",
    "s4607.dwell.rpt.tag.entity",
    "s4607.dwell.rpt.section",
};
#define S_NFIELDS (sizeof s_names / sizeof s_names[0])
static char s_wants[S_NFIELDS][S_NPKT][1024];

/* Append one expected value (a string, or an integer) of field `name` in packet pkt. */
static void s_want_str (int pkt, const char *name, const char *value)
{
    for (size_t i = 0; i < S_NFIELDS; i++)
        if (strcmp (s_names[i], name) == 0) {
            char *w = s_wants[i][pkt];
            size_t len = strlen (w);
            snprintf (w + len, sizeof s_wants[i][pkt] - len, "%s%s", len ? "," : "", value);
            return;
        }
    fail_msg ("no field %s in the list", name);
}

static void s_want (int pkt, const char *name, long long value)
{
    char v[32];
    snprintf (v, sizeof v, "%lld", value);
    s_want_str (pkt, name, v);
}

/* A dwell given as raw field values (what tshark must show), and a report likewise. */
typedef struct {
    uint16_t revisit, index;
    bool last;
    uint32_t time_ms;
    int32_t lat;
    uint32_t lon;
    int32_t alt_cm;
    bool unc; // D12-D14
    uint32_t along_cm, cross_cm;
    uint16_t alt_unc_cm;
    bool motion; // D15-D17
    uint16_t track;
    uint32_t speed_mm;
    int8_t vv_dm;
    bool motion_unc; // D18-D20
    uint8_t track_unc;
    uint16_t speed_unc_mm, vv_unc_cm;
    bool platform; // D21-D23
    uint16_t heading;
    int16_t pitch, roll;
    int32_t area_lat;
    uint32_t area_lon;
    uint16_t range, angle;
    bool sensor; // D28-D30
    uint16_t s_heading;
    int16_t s_pitch, s_roll;
    bool has_mdv;
    uint8_t mdv;
    uint32_t fields;
    bool lon_negative; // give the longitudes as negative angles, to be wrapped
} s_raw_dwell_t;

typedef struct {
    uint16_t index;
    int32_t lat;
    uint32_t lon;
    int16_t height;
    int16_t vlos_cm;
    uint16_t wrap_cm;
    int8_t snr;
    uint8_t cls, prob;
    uint16_t slant_cm, cross_dm;
    uint8_t height_unc;
    uint16_t vlos_unc_cm;
    uint8_t app;
    uint32_t entity;
    int8_t rcs_half_db;
} s_raw_report_t;

static double s_lon (uint32_t raw, bool negative)
{
    double deg = s_ba32_deg (raw);
    return negative && raw ? deg - 360.0 : deg;
}

static gw_s4607_dwell_t s_cook_dwell (const s_raw_dwell_t *x)
{
    gw_s4607_dwell_t d = {
        .revisit_index = x->revisit,
        .dwell_index = x->index,
        .last_dwell = x->last,
        .time_s = x->time_ms / 1000.0,
        .sensor_lat_deg = s_sa32_deg (x->lat),
        .sensor_lon_deg = s_lon (x->lon, x->lon_negative),
        .sensor_alt_m = x->alt_cm / 100.0,
        .along_track_unc_m = x->unc ? x->along_cm / 100.0 : NAN,
        .cross_track_unc_m = x->unc ? x->cross_cm / 100.0 : NAN,
        .alt_unc_m = x->unc ? x->alt_unc_cm / 100.0 : NAN,
        .track_deg = x->motion ? s_ba16_deg (x->track) : NAN,
        .speed_mps = x->motion ? x->speed_mm / 1000.0 : NAN,
        .vertical_velocity_mps = x->motion ? x->vv_dm / 10.0 : NAN,
        .track_unc_deg = x->motion_unc ? x->track_unc : NAN,
        .speed_unc_mps = x->motion_unc ? x->speed_unc_mm / 1000.0 : NAN,
        .vertical_velocity_unc_mps = x->motion_unc ? x->vv_unc_cm / 100.0 : NAN,
        .platform_heading_deg = x->platform ? s_ba16_deg (x->heading) : NAN,
        .platform_pitch_deg = x->platform ? s_sa16_deg (x->pitch) : NAN,
        .platform_roll_deg = x->platform ? s_sa16_deg (x->roll) : NAN,
        .area_lat_deg = s_sa32_deg (x->area_lat),
        .area_lon_deg = s_lon (x->area_lon, x->lon_negative),
        .range_half_extent_m = x->range / 128.0 * 1000.0,
        .angle_half_extent_deg = s_ba16_deg (x->angle),
        .sensor_heading_deg = x->sensor ? s_ba16_deg (x->s_heading) : NAN,
        .sensor_pitch_deg = x->sensor ? s_sa16_deg (x->s_pitch) : NAN,
        .sensor_roll_deg = x->sensor ? s_sa16_deg (x->s_roll) : NAN,
        .mdv_mps = x->has_mdv ? x->mdv / 10.0 : NAN,
        .report_fields = x->fields,
    };
    return d;
}

static gw_s4607_report_t s_cook_report (const s_raw_report_t *x, bool lon_negative)
{
    gw_s4607_report_t r = {
        .index = x->index,
        .lat_deg = s_sa32_deg (x->lat),
        .lon_deg = s_lon (x->lon, lon_negative),
        .height_m = x->height,
        .los_velocity_mps = x->vlos_cm / 100.0,
        .wrap_velocity_mps = x->wrap_cm / 100.0,
        .snr_db = x->snr,
        .classification = x->cls,
        .class_probability = x->prob / 100.0,
        .slant_range_unc_m = x->slant_cm / 100.0,
        .cross_range_unc_m = x->cross_dm / 10.0,
        .height_unc_m = x->height_unc,
        .los_velocity_unc_mps = x->vlos_unc_cm / 100.0,
        .truth_application = x->app,
        .truth_entity = x->entity,
        .rcs_dbsm = x->rcs_half_db / 2.0,
    };
    return r;
}

/* The values tshark must show for a dwell and its reports, and its mask worked
 * out here from the raw description (bit 65 - n for Dn, 34 - n for D32.n). */
static void s_expect_dwell (int pkt, const s_raw_dwell_t *x, const s_raw_report_t *r, int n)
{
    uint64_t mask = 0;
    for (int i = 2; i <= 9; i++)
        mask |= UINT64_C (1) << (65 - i);
    for (int i = 24; i <= 27; i++)
        mask |= UINT64_C (1) << (65 - i);
    const struct {
        bool on;
        int first, count;
    } groups[] = {{x->unc, 12, 3},      {x->motion, 15, 3}, {x->motion_unc, 18, 3},
                  {x->platform, 21, 3}, {x->sensor, 28, 3}, {x->has_mdv, 31, 1}};
    for (size_t g = 0; g < sizeof groups / sizeof groups[0]; g++)
        for (int i = 0; groups[g].on && i < groups[g].count; i++)
            mask |= UINT64_C (1) << (65 - groups[g].first - i);
    const struct {
        uint32_t flag;
        int first, count;
    } rf[] = {{GW_S4607_R_INDEX, 1, 1},       {0, 2, 2}, // 0: the location, always
              {GW_S4607_R_HEIGHT, 6, 1},      {GW_S4607_R_VELOCITY, 7, 2},
              {GW_S4607_R_SNR, 9, 1},         {GW_S4607_R_CLASS, 10, 1},
              {GW_S4607_R_CLASS_PROB, 11, 1}, {GW_S4607_R_UNCERTAINTY, 12, 4},
              {GW_S4607_R_TRUTH_TAG, 16, 2},  {GW_S4607_R_RCS, 18, 1}};
    for (size_t g = 0; g < sizeof rf / sizeof rf[0]; g++)
        for (int i = 0; (!rf[g].flag || (x->fields & rf[g].flag)) && i < rf[g].count; i++)
            mask |= UINT64_C (1) << (34 - rf[g].first - i);
    char m[32];
    snprintf (m, sizeof m, "0x%016llx", (unsigned long long)mask);
    s_want_str (pkt, "s4607.dwell.mask", m);
    s_want (pkt, "s4607.dwell.revisit", x->revisit);
    s_want (pkt, "s4607.dwell.dwell", x->index);
    s_want (pkt, "s4607.dwell.last", x->last);
    s_want (pkt, "s4607.dwell.count", n);
    s_want (pkt, "s4607.dwell.time", x->time_ms);
    s_want (pkt, "s4607.dwell.sensor.lat", x->lat);
    s_want (pkt, "s4607.dwell.sensor.lon", x->lon);
    s_want (pkt, "s4607.dwell.sensor.alt", x->alt_cm);
    if (x->unc) {
        s_want (pkt, "s4607.dwell.unc.along", x->along_cm);
        s_want (pkt, "s4607.dwell.unc.cross", x->cross_cm);
        s_want (pkt, "s4607.dwell.unc.alt", x->alt_unc_cm);
    }
    if (x->motion) {
        s_want (pkt, "s4607.dwell.track", x->track);
        s_want (pkt, "s4607.dwell.speed", x->speed_mm);
        s_want (pkt, "s4607.dwell.vvel", x->vv_dm);
    }
    if (x->motion_unc) {
        s_want (pkt, "s4607.dwell.track.unc", x->track_unc);
        s_want (pkt, "s4607.dwell.speed.unc", x->speed_unc_mm);
        s_want (pkt, "s4607.dwell.vvel.unc", x->vv_unc_cm);
    }
    if (x->platform) {
        s_want (pkt, "s4607.dwell.plat.heading", x->heading);
        s_want (pkt, "s4607.dwell.plat.pitch", x->pitch);
        s_want (pkt, "s4607.dwell.plat.roll", x->roll);
    }
    s_want (pkt, "s4607.dwell.da.lat", x->area_lat);
    s_want (pkt, "s4607.dwell.da.lon", x->area_lon);
    s_want (pkt, "s4607.dwell.da.range", x->range);
    s_want (pkt, "s4607.dwell.da.angle", x->angle);
    if (x->sensor) {
        s_want (pkt, "s4607.dwell.sensor.heading", x->s_heading);
        s_want (pkt, "s4607.dwell.sensor.pitch", x->s_pitch);
        s_want (pkt, "s4607.dwell.sensor.roll", x->s_roll);
    }
    if (x->has_mdv)
        s_want (pkt, "s4607.dwell.mdv", x->mdv);
    for (int i = 0; i < n; i++) {
        const s_raw_report_t *t = &r[i];
        uint32_t f = x->fields;
        if (f & GW_S4607_R_INDEX)
            s_want (pkt, "s4607.dwell.rpt.idx", t->index);
        s_want (pkt, "s4607.dwell.rpt.lat", t->lat);
        s_want (pkt, "s4607.dwell.rpt.lon", t->lon);
        if (f & GW_S4607_R_HEIGHT)
            s_want (pkt, "s4607.dwell.rpt.height", t->height);
        if (f & GW_S4607_R_VELOCITY) {
            s_want (pkt, "s4607.dwell.rpt.radial", t->vlos_cm);
            s_want (pkt, "s4607.dwell.rpt.wrap", t->wrap_cm);
        }
        if (f & GW_S4607_R_SNR)
            s_want (pkt, "s4607.dwell.rpt.snr", t->snr);
        if (f & GW_S4607_R_CLASS)
            s_want (pkt, "s4607.dwell.rpt.class", t->cls);
        if (f & GW_S4607_R_CLASS_PROB)
            s_want (pkt, "s4607.dwell.rpt.prob", t->prob);
        if (f & GW_S4607_R_UNCERTAINTY) {
            s_want (pkt, "s4607.dwell.rpt.unc.slant", t->slant_cm);
            s_want (pkt, "s4607.dwell.rpt.unc.cross", t->cross_dm);
            s_want (pkt, "s4607.dwell.rpt.unc.height", t->height_unc);
            s_want (pkt, "s4607.dwell.rpt.unc.radial", t->vlos_unc_cm);
        }
        if (f & GW_S4607_R_TRUTH_TAG) {
            s_want (pkt, "s4607.dwell.rpt.tag.app", t->app);
            s_want (pkt, "s4607.dwell.rpt.tag.entity", t->entity);
        }
        if (f & GW_S4607_R_RCS)
            s_want (pkt, "s4607.dwell.rpt.section", t->rcs_half_db);
    }
}

static void s_expect_header (int pkt, const gw_s4607_header_t *h, size_t size)
{
    s_want_str (pkt, "s4607.version", "30");
    s_want (pkt, "s4607.size", (long long)size);
    s_want_str (pkt, "s4607.nationality", h->nationality);
    s_want (pkt, "s4607.sec.class", h->classification);
    s_want_str (pkt, "s4607.sec.system", h->class_system);
    char code[16];
    snprintf (code, sizeof code, "0x%04x", h->class_code);
    s_want_str (pkt, "s4607.sec.codes", code);
    s_want (pkt, "s4607.exind", h->exercise_indicator);
    char id[16];
    snprintf (id, sizeof id, "%-10s", h->platform_id); // space padded on the wire
    s_want_str (pkt, "s4607.platform", id);
    s_want (pkt, "s4607.mission", h->mission_id);
    s_want (pkt, "s4607.job", h->job_id);
}

static void s_expect_segment (int pkt, int type, size_t size)
{
    s_want (pkt, "s4607.seg.type", type);
    s_want (pkt, "s4607.seg.size", (long long)size);
}

/* Run a command; its standard output (up to cap bytes) and exit status. */
static int s_run (const char *cmd, char *out, size_t cap)
{
    FILE *f = popen (cmd, "r");
    if (!f)
        fail_msg ("popen %s: %s", cmd, strerror (errno));
    size_t n = fread (out, 1, cap - 1, f);
    out[n] = '\0';
    while (fgetc (f) != EOF) // the rest, unread
        ;
    int status = pclose (f);
    return WIFEXITED (status) ? WEXITSTATUS (status) : -1;
}

/* The packets of the file, written into it, with what tshark must show of each. */
static void s_write_file (FILE *f)
{
    static uint8_t b[4096];
    gw_s4607_packet_t p;
    const uint32_t job_id = 4242;

    // 0: mission and job definition (P10 is the job it defines).
    gw_s4607_header_t h = s_header (job_id);
    gw_s4607_mission_t m = s_mission ();
    gw_s4607_job_t j = {
        .job_id = job_id,
        .sensor_type = GW_S4607_SENSOR_OTHER,
        .sensor_model = "MSCGS",
        .filter_flags = GW_S4607_FILTER_AREA,
        .priority = 50,
        .bounds = {{s_sa32_deg (858039022), s_ba32_deg (2848637059u)},
                   {s_sa32_deg (858993459), s_ba32_deg (2851464875u) - 360.0},
                   {s_sa32_deg (857000000), s_ba32_deg (2851000000u)},
                   {s_sa32_deg (-5), s_ba32_deg (7)}},
        .radar_mode = GW_S4607_MODE_MTI,
        .revisit_interval_s = 5.0,  // 50 ds
        .along_track_unc_m = 123.4, // 1234 dm
        .cross_track_unc_m = NAN,   // no statement: 65535
        .altitude_unc_m = 2000.0,   // 20000 dm
        .track_unc_deg = 3.0,       // 3
        .speed_unc_mps = 0.25,      // 250 mm/s
        .slant_range_sd_m = 15.0,   // 1500 cm
        .cross_range_sd_deg = s_ba16_deg (91),
        .los_velocity_sd_mps = 0.3,      // 30 cm/s
        .mdv_mps = 1.5,                  // 15 dm/s
        .detection_probability = 0.85,   // 85 %
        .false_alarm_density_db = -40.0, // 40
        .terrain_model = GW_S4607_TERRAIN_DTED2,
        .geoid_model = GW_S4607_GEOID_EGM96,
    };
    assert_int_equal (gw_s4607_packet_begin (&p, b, sizeof b, &h), 0);
    assert_int_equal (gw_s4607_add_mission (&p, &m), 0);
    assert_int_equal (gw_s4607_add_job (&p, &j), 0);
    size_t len = gw_s4607_packet_end (&p);
    assert_int_equal (fwrite (b, 1, len, f), len);
    s_expect_header (0, &h, len);
    s_expect_segment (0, 1, 44);
    s_expect_segment (0, 5, 73);
    s_want_str (0, "s4607.mission.plan", "PLAN-A      ");
    s_want_str (0, "s4607.mission.flight", "FLIGHT 7    ");
    s_want (0, "s4607.mission.platform", 16);
    s_want_str (0, "s4607.mission.config", "SIM       ");
    s_want (0, "s4607.mission.year", 2024);
    s_want (0, "s4607.mission.month", 2);
    s_want (0, "s4607.mission.day", 29);
    const long long job_want[][2] = {
        {0, job_id},     {1, 1},         {3, 1},          {4, 50},        {5, 858039022},
        {6, 2848637059}, {7, 858993459}, {8, 2851464875}, {9, 857000000}, {10, 2851000000},
        {11, -5},        {12, 7},        {13, 1},         {14, 50},       {15, 1234},
        {16, 65535},     {17, 20000},    {18, 3},         {19, 250},      {20, 1500},
        {21, 91},        {22, 30},       {23, 15},        {24, 85},       {25, 40},
        {26, 3},         {27, 1},
    };
    const char *job_names[] = {
        "s4607.job.id",          "s4607.job.type",        NULL,
        "s4607.job.filter",      "s4607.job.priority",    "s4607.job.ba.lat.a",
        "s4607.job.ba.lon.a",    "s4607.job.ba.lat.b",    "s4607.job.ba.lon.b",
        "s4607.job.ba.lat.c",    "s4607.job.ba.lon.c",    "s4607.job.ba.lat.d",
        "s4607.job.ba.lon.d",    "s4607.job.mode",        "s4607.job.revisit",
        "s4607.job.unc.track",   "s4607.job.unc.cross",   "s4607.job.unc.alt",
        "s4607.job.unc.heading", "s4607.job.unc.speed",   "s4607.job.sense.slant",
        "s4607.job.sense.cross", "s4607.job.sense.vlos",  "s4607.job.sense.mdv",
        "s4607.job.sense.prob",  "s4607.job.sense.alarm", "s4607.job.terrain",
        "s4607.job.geoid",
    };
    for (size_t i = 0; i < sizeof job_want / sizeof job_want[0]; i++)
        s_want (0, job_names[job_want[i][0]], job_want[i][1]);
    s_want_str (0, "s4607.job.model", "MSCGS ");

    // 1: platform location alone (no job: P10 0).
    h = s_header (0);
    strcpy (h.platform_id, "UAV1");
    gw_s4607_platform_t pl = s_platform ();
    assert_int_equal (gw_s4607_packet_begin (&p, b, sizeof b, &h), 0);
    assert_int_equal (gw_s4607_add_platform (&p, &pl), 0);
    len = gw_s4607_packet_end (&p);
    assert_int_equal (fwrite (b, 1, len, f), len);
    s_expect_header (1, &h, len);
    s_expect_segment (1, 13, 28);
    const long long ploc[] = {3723456, 858039022, 2848637059, 123456, 22812, 45678, -25};
    const char *ploc_names[] = {"s4607.ploc.time",    "s4607.ploc.lat",   "s4607.ploc.lon",
                                "s4607.ploc.alt",     "s4607.ploc.track", "s4607.ploc.speed",
                                "s4607.ploc.velocity"};
    for (int i = 0; i < 7; i++)
        s_want (1, ploc_names[i], ploc[i]);

    // 2: a dwell with every field and three reports.
    static const s_raw_dwell_t dw[4] = {
        {.revisit = 1,
         .index = 0,
         .last = false,
         .time_ms = 3600250,
         .lat = 858039022,
         .lon = 2848637059u,
         .alt_cm = 304800,
         .unc = true,
         .along_cm = 500,
         .cross_cm = 600,
         .alt_unc_cm = 700,
         .motion = true,
         .track = 16384,
         .speed_mm = 60000,
         .vv_dm = -15,
         .motion_unc = true,
         .track_unc = 2,
         .speed_unc_mm = 500,
         .vv_unc_cm = 25,
         .platform = true,
         .heading = 16566,
         .pitch = -12698,
         .roll = 3641,
         .area_lat = 858993459,
         .area_lon = 2851464875u,
         .range = 1600,
         .angle = 2731,
         .sensor = true,
         .s_heading = 32768,
         .s_pitch = -7282,
         .s_roll = 1,
         .has_mdv = true,
         .mdv = 12,
         .fields = GW_S4607_R_ALL,
         .lon_negative = true},
        // 3: two dwells in one packet: the mandatory fields only, hi-res location only ...
        {.revisit = 1,
         .index = 1,
         .last = false,
         .time_ms = 3601250,
         .lat = -294579351,
         .lon = 64807477u,
         .alt_cm = -2500,
         .area_lat = -294000000,
         .area_lon = 64000000u,
         .range = 0x7fff,
         .angle = 32768,
         .fields = 0},
        // ... and uncertainty, platform and sensor orientation, some report fields.
        {.revisit = 1,
         .index = 2,
         .last = true,
         .time_ms = 3602250,
         .lat = 858039022,
         .lon = 2848637059u,
         .alt_cm = 2000000000,
         .unc = true,
         .along_cm = 1000000,
         .cross_cm = 0,
         .alt_unc_cm = 65535,
         .platform = true,
         .heading = 65535,
         .pitch = -32768,
         .roll = 32767,
         .area_lat = 858993459,
         .area_lon = 2851464875u,
         .range = 64,
         .angle = 1,
         .sensor = true,
         .s_heading = 0,
         .s_pitch = 16384,
         .s_roll = -16384,
         .fields = GW_S4607_R_HEIGHT | GW_S4607_R_CLASS | GW_S4607_R_CLASS_PROB |
                   GW_S4607_R_UNCERTAINTY | GW_S4607_R_TRUTH_TAG},
        // 4: after a platform location, a dwell with motion and its uncertainty, the MDV.
        {.revisit = 2,
         .index = 0,
         .last = true,
         .time_ms = 4000000000u,
         .lat = -858039022,
         .lon = 4294967295u,
         .alt_cm = -50000,
         .motion = true,
         .track = 0,
         .speed_mm = 8000000,
         .vv_dm = 127,
         .motion_unc = true,
         .track_unc = 45,
         .speed_unc_mm = 65535,
         .vv_unc_cm = 0,
         .area_lat = -858000000,
         .area_lon = 1u,
         .range = 12800,
         .angle = 5461,
         .has_mdv = true,
         .mdv = 255,
         .fields = GW_S4607_R_INDEX | GW_S4607_R_VELOCITY | GW_S4607_R_SNR | GW_S4607_R_RCS,
         .lon_negative = true},
    };
    static const s_raw_report_t rr[4][3] = {
        {{100, 858049022, 2848647059u, 150, -1234, 4000, 17, 128, 50, 750, 200, 15, 30, 2, 66051,
          20},
         {101, 858059022, 2848657059u, -1000, 32767, 65535, -128, 130, 100, 0, 65535, 255, 5000,
          255, 4294967295u, -128},
         {102, 858069022, 2848667059u, 32767, -32768, 0, 127, 255, 0, 65535, 1, 0, 0, 0, 0, 127}},
        {{0, -294579000, 64807000u, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0},
         {0, -294578000, 64806000u, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0},
         {0, -294577000, 64805000u, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0}},
        {{7, 858039000, 2848637000u, 12, 0, 0, 0, 137, 99, 100, 10, 3, 10, 1, 1001, 0},
         {8, 858038000, 2848636000u, -3, 0, 0, 0, 138, 1, 200, 20, 4, 20, 1, 1002, 0},
         {9, 858037000, 2848635000u, 0, 0, 0, 0, 128, 0, 300, 30, 5, 30, 1, 1003, 0}},
        {{65535, -858039000, 4294967000u, 0, 5, 1000, 3, 0, 0, 0, 0, 0, 0, 0, 0, -5},
         {1, -858038000, 4294966000u, 0, -5, 1000, -3, 0, 0, 0, 0, 0, 0, 0, 0, 5},
         {2, -858037000, 0u, 0, 0, 1000, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0}},
    };
    gw_s4607_report_t r[3];
    for (int pkt = 2; pkt < S_NPKT; pkt++) {
        h = s_header (job_id);
        assert_int_equal (gw_s4607_packet_begin (&p, b, sizeof b, &h), 0);
        int first = pkt == 2 ? 0 : pkt == 3 ? 1 : 3, last = pkt == 3 ? 2 : first;
        if (pkt == 4) {
            assert_int_equal (gw_s4607_add_platform (&p, &pl), 0);
            s_expect_segment (pkt, 13, 28);
            for (int i = 0; i < 7; i++)
                s_want (pkt, ploc_names[i], ploc[i]);
        }
        for (int k = first; k <= last; k++) {
            gw_s4607_dwell_t d = s_cook_dwell (&dw[k]);
            for (int i = 0; i < 3; i++)
                r[i] = s_cook_report (&rr[k][i], dw[k].lon_negative);
            size_t size = gw_s4607_dwell_size (&d, r, 3);
            size_t before = p.len;
            int rc = gw_s4607_add_dwell (&p, &d, r, 3);
            if (rc != 0)
                fail_msg ("dwell %d: %d", k, rc);
            assert_int_equal (p.len - before, size);
            s_expect_segment (pkt, 2, size);
            s_expect_dwell (pkt, &dw[k], rr[k], 3);
        }
        len = gw_s4607_packet_end (&p);
        assert_int_equal (fwrite (b, 1, len, f), len);
        s_expect_header (pkt, &h, len);
    }
}

/* Split a line at tabs, in place: up to max fields. */
static size_t s_split (char *line, char **fields, size_t max)
{
    size_t n = 0;
    line[strcspn (line, "\n")] = '\0';
    for (char *s = line; n < max;) {
        fields[n++] = s;
        char *tab = strchr (s, '\t');
        if (!tab)
            break;
        *tab = '\0';
        s = tab + 1;
    }
    return n;
}

static void test_tshark (void **state)
{
    (void)state;
    if (system ("tshark -v >/dev/null 2>&1") != 0)
        fail_msg ("tshark is required for this test (scripts/install-deps installs it): "
                  "it was not found or does not run");
    // The packets in memory first, then in a file that is gone before any check.
    char *bytes = NULL;
    size_t nbytes = 0;
    FILE *mem = open_memstream (&bytes, &nbytes);
    assert_non_null (mem);
    s_write_file (mem);
    assert_int_equal (fclose (mem), 0);
    char path[] = "/tmp/test_gw_s4607_XXXXXX";
    int fd = mkstemp (path);
    assert_true (fd >= 0);
    ssize_t wrote = write (fd, bytes, nbytes);
    close (fd);
    free (bytes);

    static char cmd[8192], fields[1 << 16], detail[1 << 18], expert[1 << 14];
    int at = snprintf (cmd, sizeof cmd, "tshark -r '%s' -T fields", path);
    for (size_t i = 0; i < S_NFIELDS; i++)
        at += snprintf (cmd + at, sizeof cmd - (size_t)at, " -e %s", s_names[i]);
    snprintf (cmd + at, sizeof cmd - (size_t)at, " 2>/dev/null");
    int rc_fields = wrote == (ssize_t)nbytes ? s_run (cmd, fields, sizeof fields) : -1;
    snprintf (cmd, sizeof cmd, "tshark -r '%s' -V 2>&1", path);
    int rc_detail = s_run (cmd, detail, sizeof detail);
    snprintf (cmd, sizeof cmd, "tshark -r '%s' -z expert -q 2>&1", path);
    int rc_expert = s_run (cmd, expert, sizeof expert);
    unlink (path);
    assert_int_equal (wrote, nbytes);
    assert_int_equal (rc_fields, 0);
    assert_int_equal (rc_detail, 0);
    assert_int_equal (rc_expert, 0);

    // Every field of every packet, one line a packet.
    char *save = NULL, *line = strtok_r (fields, "\n", &save);
    int pkt = 0, compared = 0;
    for (; line; line = strtok_r (NULL, "\n", &save), pkt++) {
        if (pkt >= S_NPKT)
            fail_msg ("tshark shows more than %d packets: %s", S_NPKT, line);
        char *got[S_NFIELDS];
        size_t n = s_split (line, got, S_NFIELDS);
        if (n != S_NFIELDS)
            fail_msg ("packet %d: %zu fields, want %zu", pkt, n, S_NFIELDS);
        for (size_t i = 0; i < S_NFIELDS; i++) {
            if (strcmp (got[i], s_wants[i][pkt]) != 0)
                fail_msg ("packet %d, %s: tshark shows '%s', want '%s'", pkt, s_names[i], got[i],
                          s_wants[i][pkt]);
            compared += s_wants[i][pkt][0] != '\0';
        }
    }
    assert_int_equal (pkt, S_NPKT);

    // No malformed packet, no expert information of any severity in the detail view ...
    const char *bad = strstr (detail, "Malformed") ? strstr (detail, "Malformed")
                                                   : strstr (detail, "Expert Info");
    if (bad)
        fail_msg ("tshark -V: %.300s", bad);
    if (!strstr (detail, "Target Report Count: 3") || !strstr (detail, "Platform Location Time") ||
        !strstr (detail, "Mission Reference Time Year: 2024") ||
        !strstr (detail, "Geoid Model Used: EGM96"))
        fail_msg ("tshark -V does not show every segment: %.400s", detail);
    // ... and in its summary: no errors, warnings or notes.
    if (strstr (expert, "Errors") || strstr (expert, "Warns") || strstr (expert, "Warnings") ||
        strstr (expert, "Notes") || strstr (expert, "Malformed"))
        fail_msg ("tshark -z expert: %s", expert);
    print_message ("# tshark read %d packets (%zu bytes); %d fields matched\n", pkt, nbytes,
                   compared);
}

int main (void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test (test_header_bytes),  cmocka_unit_test (test_platform_bytes),
        cmocka_unit_test (test_mission_bytes), cmocka_unit_test (test_encodings),
        cmocka_unit_test (test_dwell_bytes),   cmocka_unit_test (test_mask_and_sizes),
        cmocka_unit_test (test_report_ranges), cmocka_unit_test (test_enospc),
        cmocka_unit_test (test_einval),        cmocka_unit_test (test_dwell_size),
        cmocka_unit_test (test_tshark),
    };
    return cmocka_run_group_tests (tests, NULL, NULL);
}
