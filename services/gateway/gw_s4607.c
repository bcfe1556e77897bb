/* gw_s4607 — STANAG 4607 Edition 3 packets, quantised and written field by field. */
#include "gw_s4607.h"

#include <assert.h>
#include <errno.h>
#include <math.h>
#include <string.h>

#define S_TWO_31 2147483648.0 // 2^31
#define S_TWO_32 4294967296.0 // 2^32

/* ---- quantisers: SI value to the field's integer, or -EINVAL ---------------------------- */

enum {
    S_CLAMP_LO = 1, // below the field's minimum: saturate (else -EINVAL)
    S_CLAMP_HI = 2, // above its maximum: saturate (else -EINVAL)
};

/* v * scale rounded to the nearest integer (halves away from zero), then held to
 * [lo, hi] by the clamp flags. */
static int s_quant (double v, double scale, int64_t lo, int64_t hi, int clamp, int64_t *ret)
{
    if (!isfinite (v))
        return -EINVAL;
    double q = round (v * scale);
    if (q < (double)lo) {
        if (!(clamp & S_CLAMP_LO))
            return -EINVAL;
        q = (double)lo;
    }
    if (q > (double)hi) {
        if (!(clamp & S_CLAMP_HI))
            return -EINVAL;
        q = (double)hi;
    }
    *ret = (int64_t)q;
    return 0;
}

/* An uncertainty or other magnitude: negative is -EINVAL, too large saturates. */
static int s_mag (double v, double scale, int64_t hi, int64_t *ret)
{
    return s_quant (v, scale, 0, hi, S_CLAMP_HI, ret);
}

/* A measured signed quantity: saturates at both ends. */
static int s_sat (double v, double scale, int64_t lo, int64_t hi, int64_t *ret)
{
    return s_quant (v, scale, lo, hi, S_CLAMP_LO | S_CLAMP_HI, ret);
}

/* An exact value: outside [lo, hi] is -EINVAL. */
static int s_exact (double v, double scale, int64_t lo, int64_t hi, int64_t *ret)
{
    return s_quant (v, scale, lo, hi, 0, ret);
}

/* SA32: signed binary angle, 180/2^32 degree a step, [-90, 90); +90 takes the top code. */
static int s_sa32 (double deg, int32_t *ret)
{
    if (!isfinite (deg) || deg < -90.0 || deg > 90.0)
        return -EINVAL;
    double q = round (deg * (S_TWO_31 / 90.0));
    *ret = q >= S_TWO_31 ? INT32_MAX : (int32_t)q;
    return 0;
}

/* SA16: signed binary angle, 180/2^16 degree a step, [-90, 90); +90 takes the top code. */
static int s_sa16 (double deg, int16_t *ret)
{
    if (!isfinite (deg) || deg < -90.0 || deg > 90.0)
        return -EINVAL;
    double q = round (deg * (32768.0 / 90.0));
    *ret = q >= 32768.0 ? INT16_MAX : (int16_t)q;
    return 0;
}

/* The angle wrapped into [0, 360) and scaled to `steps` codes a turn, modulo steps. */
static int s_binary_angle (double deg, double steps, double *ret)
{
    if (!isfinite (deg))
        return -EINVAL;
    double a = fmod (deg, 360.0);
    if (a < 0)
        a += 360.0;
    double q = round (a * (steps / 360.0));
    *ret = q >= steps ? q - steps : q;
    return 0;
}

/* BA32: unsigned binary angle, 360/2^32 degree a step. */
static int s_ba32 (double deg, uint32_t *ret)
{
    double q = 0;
    int rc = s_binary_angle (deg, S_TWO_32, &q);
    if (rc == 0)
        *ret = (uint32_t)q;
    return rc;
}

/* BA16: unsigned binary angle, 360/2^16 degree a step. */
static int s_ba16 (double deg, uint16_t *ret)
{
    double q = 0;
    int rc = s_binary_angle (deg, 65536.0, &q);
    if (rc == 0)
        *ret = (uint16_t)q;
    return rc;
}

/* B16: binary decimal, sign and magnitude: a sign bit, 8 integer bits, 7 fraction
 * bits (1/128 a step), so |x| <= 255.9921875. */
static int s_b16 (double x, uint16_t *ret)
{
    int64_t m = 0;
    int rc = s_exact (fabs (x), 128.0, 0, 0x7fff, &m);
    if (rc == 0)
        *ret = (uint16_t)((x < 0 && m ? 0x8000u : 0u) | (uint32_t)m);
    return rc;
}

/* An optional value's presence. */
static bool s_has (double v)
{
    return !isnan (v);
}

/* ---- writer ----------------------------------------------------------------------------- */

/* The caller has checked the room: these write at w->at and advance it. */
typedef struct {
    uint8_t *at;
} s_w_t;

static void s_i8 (s_w_t *w, uint8_t v)
{
    *w->at++ = v;
}

static void s_i16 (s_w_t *w, uint16_t v)
{
    s_i8 (w, (uint8_t)(v >> 8));
    s_i8 (w, (uint8_t)v);
}

static void s_i32 (s_w_t *w, uint32_t v)
{
    s_i16 (w, (uint16_t)(v >> 16));
    s_i16 (w, (uint16_t)v);
}

static void s_i64 (s_w_t *w, uint64_t v)
{
    s_i32 (w, (uint32_t)(v >> 32));
    s_i32 (w, (uint32_t)v);
}

/* S8/S16/S32: two's complement, big-endian. */
static void s_s8 (s_w_t *w, int8_t v)
{
    s_i8 (w, (uint8_t)v);
}

static void s_s16 (s_w_t *w, int16_t v)
{
    s_i16 (w, (uint16_t)v);
}

static void s_s32 (s_w_t *w, int32_t v)
{
    s_i32 (w, (uint32_t)v);
}

/* An alphanumeric field of n bytes: the string, space padded. */
static void s_chars (s_w_t *w, const char *s, size_t n)
{
    size_t k = strnlen (s, n);
    memcpy (w->at, s, k);
    memset (w->at + k, ' ', n - k);
    w->at += n;
}

/* A string that fits an n-character field (its array is n + 1 bytes) in
 * printable ASCII. */
static bool s_chars_ok (const char *s, size_t n)
{
    size_t k = strnlen (s, n + 1);
    if (k > n)
        return false;
    for (size_t i = 0; i < k; i++)
        if ((unsigned char)s[i] < 0x20 || (unsigned char)s[i] > 0x7e)
            return false;
    return true;
}

/* Room for n more bytes: a pointer to them, or NULL. */
static uint8_t *s_room (const gw_s4607_packet_t *p, size_t n)
{
    assert (p->buf && p->len >= GW_S4607_HEADER_LEN && p->len <= p->cap);
    return p->cap - p->len < n ? NULL : p->buf + p->len;
}

static void s_put_size (gw_s4607_packet_t *p)
{
    s_w_t w = {p->buf + 2};
    s_i32 (&w, (uint32_t)p->len);
}

/* Commit n bytes just written at the end of the packet. */
static void s_commit (gw_s4607_packet_t *p, size_t n)
{
    p->len += n;
    s_put_size (p);
}

static void s_seg_header (s_w_t *w, uint8_t type, size_t size)
{
    s_i8 (w, type);
    s_i32 (w, (uint32_t)size);
}

/* ---- packet header ---------------------------------------------------------------------- */

int gw_s4607_packet_begin (gw_s4607_packet_t *p, uint8_t *buf, size_t cap,
                           const gw_s4607_header_t *h)
{
    uint8_t x = h->exercise_indicator;
    if (strnlen (h->nationality, sizeof h->nationality) != 2 || !s_chars_ok (h->nationality, 2) ||
        !s_chars_ok (h->class_system, 2) || !s_chars_ok (h->platform_id, 10) ||
        h->classification < GW_S4607_CLASS_TOP_SECRET ||
        h->classification > GW_S4607_CLASS_UNCLASSIFIED || !(x <= 2 || (x >= 128 && x <= 130)))
        return -EINVAL;
    if (!buf || cap < GW_S4607_HEADER_LEN)
        return -ENOSPC;
    s_w_t w = {buf};
    s_chars (&w, GW_S4607_VERSION, 2); // P1 version ID
    s_i32 (&w, GW_S4607_HEADER_LEN);   // P2 packet size, rewritten as segments come
    s_chars (&w, h->nationality, 2);   // P3
    s_i8 (&w, h->classification);      // P4
    s_chars (&w, h->class_system, 2);  // P5
    s_i16 (&w, h->class_code);         // P6
    s_i8 (&w, h->exercise_indicator);  // P7
    s_chars (&w, h->platform_id, 10);  // P8
    s_i32 (&w, h->mission_id);         // P9
    s_i32 (&w, h->job_id);             // P10
    assert (w.at == buf + GW_S4607_HEADER_LEN);
    *p = (gw_s4607_packet_t){buf, cap, GW_S4607_HEADER_LEN};
    return 0;
}

size_t gw_s4607_packet_end (gw_s4607_packet_t *p)
{
    assert (p->buf && p->len >= GW_S4607_HEADER_LEN && p->len <= p->cap);
    s_put_size (p);
    return p->len;
}

/* ---- mission ---------------------------------------------------------------------------- */

static bool s_date_ok (unsigned y, unsigned m, unsigned d)
{
    static const uint8_t days[12] = {31, 28, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31};
    if (y < 1 || m < 1 || m > 12 || d < 1)
        return false;
    bool leap = (y % 4 == 0 && y % 100 != 0) || y % 400 == 0;
    return d <= days[m - 1] + (m == 2 && leap ? 1u : 0u);
}

int gw_s4607_add_mission (gw_s4607_packet_t *p, const gw_s4607_mission_t *m)
{
    if (!s_chars_ok (m->mission_plan, 12) || !s_chars_ok (m->flight_plan, 12) ||
        !s_chars_ok (m->platform_config, 10) || !s_date_ok (m->year, m->month, m->day))
        return -EINVAL;
    uint8_t *at = s_room (p, GW_S4607_MISSION_LEN);
    if (!at)
        return -ENOSPC;
    s_w_t w = {at};
    s_seg_header (&w, GW_S4607_SEG_MISSION, GW_S4607_MISSION_LEN);
    s_chars (&w, m->mission_plan, 12);    // M1
    s_chars (&w, m->flight_plan, 12);     // M2
    s_i8 (&w, m->platform_type);          // M3
    s_chars (&w, m->platform_config, 10); // M4
    s_i16 (&w, m->year);                  // M5
    s_i8 (&w, m->month);                  // M6
    s_i8 (&w, m->day);                    // M7
    assert (w.at == at + GW_S4607_MISSION_LEN);
    s_commit (p, GW_S4607_MISSION_LEN);
    return 0;
}

/* ---- job definition --------------------------------------------------------------------- */

/* A nominal value: NAN is "no statement" (ns), else a magnitude saturated at hi. */
static int s_nominal (double v, double scale, int64_t hi, int64_t ns, int64_t *ret)
{
    if (isnan (v)) {
        *ret = ns;
        return 0;
    }
    return s_mag (v, scale, hi, ret);
}

/* The quantised job definition. */
typedef struct {
    int32_t lat[4];
    uint32_t lon[4];
    int64_t revisit, along, cross, alt, track, speed, slant, vlos, mdv, pd, fad;
    uint16_t cross_sd;
} s_job_q_t;

static int s_job_quantise (const gw_s4607_job_t *j, s_job_q_t *q)
{
    int rc = 0;
    if (j->job_id == 0 || !s_chars_ok (j->sensor_model, 6) || (j->filter_flags & ~0x07u) ||
        !((j->priority >= 1 && j->priority <= 99) || j->priority == GW_S4607_PRIORITY_END_OF_JOB))
        return -EINVAL;
    for (int i = 0; i < 4; i++) {
        rc |= s_sa32 (j->bounds[i].lat_deg, &q->lat[i]);
        rc |= s_ba32 (j->bounds[i].lon_deg, &q->lon[i]);
    }
    rc |= s_exact (j->revisit_interval_s, 10.0, 0, 65535, &q->revisit);
    rc |= s_nominal (j->along_track_unc_m, 10.0, 10000, 0xffff, &q->along);
    rc |= s_nominal (j->cross_track_unc_m, 10.0, 10000, 0xffff, &q->cross);
    rc |= s_nominal (j->altitude_unc_m, 10.0, 20000, 0xffff, &q->alt);
    rc |= s_nominal (j->track_unc_deg, 1.0, 45, 0xff, &q->track);
    rc |= s_nominal (j->speed_unc_mps, 1000.0, 65534, 0xffff, &q->speed);
    rc |= s_nominal (j->slant_range_sd_m, 100.0, 65534, 0xffff, &q->slant);
    rc |= s_nominal (j->los_velocity_sd_mps, 100.0, 5000, 0xffff, &q->vlos);
    rc |= s_nominal (j->mdv_mps, 10.0, 254, 0xff, &q->mdv);
    // J25: a probability above 1 is an error, not a saturation.
    if (!isnan (j->detection_probability) && j->detection_probability > 1.0)
        return -EINVAL;
    rc |= s_nominal (j->detection_probability, 100.0, 100, 0xff, &q->pd);
    // J26 holds the density's dB negated: -40 dB is 40; a positive dB is an error.
    rc |= s_nominal (-j->false_alarm_density_db, 1.0, 254, 0xff, &q->fad);
    // J22: BA16 below 180 degrees; no statement is 0xffff (any code from 180 up).
    if (isnan (j->cross_range_sd_deg)) {
        q->cross_sd = 0xffff;
    } else {
        int64_t c = 0;
        rc |= s_mag (j->cross_range_sd_deg, 65536.0 / 360.0, 0x7fff, &c);
        q->cross_sd = (uint16_t)c;
    }
    return rc ? -EINVAL : 0;
}

int gw_s4607_add_job (gw_s4607_packet_t *p, const gw_s4607_job_t *j)
{
    s_job_q_t q = {0};
    if (s_job_quantise (j, &q) < 0)
        return -EINVAL;
    uint8_t *at = s_room (p, GW_S4607_JOB_LEN);
    if (!at)
        return -ENOSPC;
    s_w_t w = {at};
    s_seg_header (&w, GW_S4607_SEG_JOB, GW_S4607_JOB_LEN);
    s_i32 (&w, j->job_id);            // J1
    s_i8 (&w, j->sensor_type);        // J2
    s_chars (&w, j->sensor_model, 6); // J3
    s_i8 (&w, j->filter_flags);       // J4
    s_i8 (&w, j->priority);           // J5
    for (int i = 0; i < 4; i++) {     // J6-J13
        s_s32 (&w, q.lat[i]);
        s_i32 (&w, q.lon[i]);
    }
    s_i8 (&w, j->radar_mode);        // J14
    s_i16 (&w, (uint16_t)q.revisit); // J15
    s_i16 (&w, (uint16_t)q.along);   // J16
    s_i16 (&w, (uint16_t)q.cross);   // J17
    s_i16 (&w, (uint16_t)q.alt);     // J18
    s_i8 (&w, (uint8_t)q.track);     // J19
    s_i16 (&w, (uint16_t)q.speed);   // J20
    s_i16 (&w, (uint16_t)q.slant);   // J21
    s_i16 (&w, q.cross_sd);          // J22
    s_i16 (&w, (uint16_t)q.vlos);    // J23
    s_i8 (&w, (uint8_t)q.mdv);       // J24
    s_i8 (&w, (uint8_t)q.pd);        // J25
    s_i8 (&w, (uint8_t)q.fad);       // J26
    s_i8 (&w, j->terrain_model);     // J27
    s_i8 (&w, j->geoid_model);       // J28
    assert (w.at == at + GW_S4607_JOB_LEN);
    s_commit (p, GW_S4607_JOB_LEN);
    return 0;
}

/* ---- platform location ------------------------------------------------------------------ */

int gw_s4607_add_platform (gw_s4607_packet_t *p, const gw_s4607_platform_t *pl)
{
    int32_t lat = 0;
    uint32_t lon = 0;
    uint16_t track = 0;
    int64_t time = 0, alt = 0, speed = 0, vv = 0;
    int rc = s_exact (pl->time_s, 1000.0, 0, 4000000000, &time);
    rc |= s_sa32 (pl->lat_deg, &lat);
    rc |= s_ba32 (pl->lon_deg, &lon);
    rc |= s_exact (pl->alt_m, 100.0, -50000, 2000000000, &alt);
    rc |= s_ba16 (pl->track_deg, &track);
    rc |= s_exact (pl->speed_mps, 1000.0, 0, 8000000, &speed);
    rc |= s_sat (pl->vertical_velocity_mps, 10.0, INT8_MIN, INT8_MAX, &vv);
    if (rc)
        return -EINVAL;
    uint8_t *at = s_room (p, GW_S4607_PLATFORM_LEN);
    if (!at)
        return -ENOSPC;
    s_w_t w = {at};
    s_seg_header (&w, GW_S4607_SEG_PLATFORM, GW_S4607_PLATFORM_LEN);
    s_i32 (&w, (uint32_t)time);  // L1
    s_s32 (&w, lat);             // L2
    s_i32 (&w, lon);             // L3
    s_s32 (&w, (int32_t)alt);    // L4
    s_i16 (&w, track);           // L5
    s_i32 (&w, (uint32_t)speed); // L6
    s_s8 (&w, (int8_t)vv);       // L7
    assert (w.at == at + GW_S4607_PLATFORM_LEN);
    s_commit (p, GW_S4607_PLATFORM_LEN);
    return 0;
}

/* ---- dwell ------------------------------------------------------------------------------ */

/* Existence mask bits (D1): D2 is bit 63 down to D31 at bit 34; D32.1 is bit 33
 * down to D32.18 at bit 16; bits 15-0 are spare. */
#define S_D(n)   (UINT64_C (1) << (65 - (n)))
#define S_D32(n) (UINT64_C (1) << (34 - (n)))

/* The mask bits of fields Da..Db. */
static uint64_t s_range (int a, int b)
{
    uint64_t m = 0;
    for (int i = a; i <= b; i++)
        m |= S_D (i);
    return m;
}

/* Which of a group of three optional values are present: 0 none, 1 all, -1 some. */
static int s_group (double a, double b, double c)
{
    int k = s_has (a) + s_has (b) + s_has (c);
    return k == 0 ? 0 : k == 3 ? 1 : -1;
}

/* The existence mask of a dwell, or 0 when its field set is invalid. */
static uint64_t s_mask (const gw_s4607_dwell_t *d)
{
    const int g[5] = {
        s_group (d->along_track_unc_m, d->cross_track_unc_m, d->alt_unc_m),
        s_group (d->track_deg, d->speed_mps, d->vertical_velocity_mps),
        s_group (d->track_unc_deg, d->speed_unc_mps, d->vertical_velocity_unc_mps),
        s_group (d->platform_heading_deg, d->platform_pitch_deg, d->platform_roll_deg),
        s_group (d->sensor_heading_deg, d->sensor_pitch_deg, d->sensor_roll_deg),
    };
    const int first[5] = {12, 15, 18, 21, 28};
    uint64_t mask = s_range (2, 9) | s_range (24, 27); // the mandatory fields
    for (int i = 0; i < 5; i++) {
        if (g[i] < 0)
            return 0;
        if (g[i])
            mask |= s_range (first[i], first[i] + 2);
    }
    if (s_has (d->mdv_mps))
        mask |= S_D (31);
    uint32_t f = d->report_fields;
    if (f & ~(uint32_t)GW_S4607_R_ALL)
        return 0;
    mask |= S_D32 (2) | S_D32 (3); // hi-res location, always
    if (f & GW_S4607_R_INDEX)
        mask |= S_D32 (1);
    if (f & GW_S4607_R_HEIGHT)
        mask |= S_D32 (6);
    if (f & GW_S4607_R_VELOCITY)
        mask |= S_D32 (7) | S_D32 (8);
    if (f & GW_S4607_R_SNR)
        mask |= S_D32 (9);
    if (f & GW_S4607_R_CLASS)
        mask |= S_D32 (10);
    if (f & GW_S4607_R_CLASS_PROB)
        mask |= S_D32 (11);
    if (f & GW_S4607_R_UNCERTAINTY)
        mask |= S_D32 (12) | S_D32 (13) | S_D32 (14) | S_D32 (15);
    if (f & GW_S4607_R_TRUTH_TAG)
        mask |= S_D32 (16) | S_D32 (17);
    if (f & GW_S4607_R_RCS)
        mask |= S_D32 (18);
    return mask;
}

/* Bytes of each field D2..D31 (index n) and D32.1..D32.18 (index n). */
static const uint8_t s_dwell_width[32] = {
    [2] = 2,  [3] = 2,  [4] = 1,  [5] = 2,  [6] = 4,  [7] = 4,  [8] = 4,  [9] = 4,
    [10] = 4, [11] = 4, [12] = 4, [13] = 4, [14] = 2, [15] = 2, [16] = 4, [17] = 1,
    [18] = 1, [19] = 2, [20] = 2, [21] = 2, [22] = 2, [23] = 2, [24] = 4, [25] = 4,
    [26] = 2, [27] = 2, [28] = 2, [29] = 2, [30] = 2, [31] = 1,
};
static const uint8_t s_report_width[19] = {
    [1] = 2,  [2] = 4,  [3] = 4,  [4] = 2,  [5] = 2,  [6] = 2,  [7] = 2,  [8] = 2,  [9] = 1,
    [10] = 1, [11] = 1, [12] = 2, [13] = 2, [14] = 1, [15] = 2, [16] = 1, [17] = 4, [18] = 1,
};

static size_t s_report_size (uint64_t mask)
{
    size_t n = 0;
    for (int i = 1; i <= 18; i++)
        if (mask & S_D32 (i))
            n += s_report_width[i];
    return n;
}

static size_t s_dwell_size (uint64_t mask, size_t n)
{
    size_t size = GW_S4607_SEG_HDR_LEN + 8; // segment header, existence mask
    for (int i = 2; i <= 31; i++)
        if (mask & S_D (i))
            size += s_dwell_width[i];
    return size + n * s_report_size (mask);
}

size_t gw_s4607_dwell_size (const gw_s4607_dwell_t *d, const gw_s4607_report_t *r, size_t n)
{
    (void)r; // the size depends on which fields are present, not on the reports' values
    uint64_t mask = s_mask (d);
    return mask && n <= GW_S4607_REPORTS_MAX ? s_dwell_size (mask, n) : 0;
}

/* The dwell's fields quantised; optional ones are read only when the mask has them. */
typedef struct {
    int64_t time, alt, along, cross, alt_unc, speed, vv, track_unc, speed_unc, vv_unc, mdv;
    int32_t lat, area_lat;
    uint32_t lon, area_lon;
    uint16_t track, plat_heading, range, angle, sensor_heading;
    int16_t plat_pitch, plat_roll, sensor_pitch, sensor_roll;
} s_dwell_q_t;

static int s_dwell_quantise (const gw_s4607_dwell_t *d, uint64_t mask, s_dwell_q_t *q)
{
    int rc = s_exact (d->time_s, 1000.0, 0, 4000000000, &q->time);
    rc |= s_sa32 (d->sensor_lat_deg, &q->lat);
    rc |= s_ba32 (d->sensor_lon_deg, &q->lon);
    rc |= s_exact (d->sensor_alt_m, 100.0, -50000, 2000000000, &q->alt);
    if (mask & S_D (12)) {
        rc |= s_mag (d->along_track_unc_m, 100.0, 1000000, &q->along);
        rc |= s_mag (d->cross_track_unc_m, 100.0, 1000000, &q->cross);
        rc |= s_mag (d->alt_unc_m, 100.0, 65535, &q->alt_unc);
    }
    if (mask & S_D (15)) {
        rc |= s_ba16 (d->track_deg, &q->track);
        rc |= s_exact (d->speed_mps, 1000.0, 0, 8000000, &q->speed);
        rc |= s_sat (d->vertical_velocity_mps, 10.0, INT8_MIN, INT8_MAX, &q->vv);
    }
    if (mask & S_D (18)) {
        rc |= s_mag (d->track_unc_deg, 1.0, 45, &q->track_unc);
        rc |= s_mag (d->speed_unc_mps, 1000.0, 65535, &q->speed_unc);
        rc |= s_mag (d->vertical_velocity_unc_mps, 100.0, 65535, &q->vv_unc);
    }
    if (mask & S_D (21)) {
        rc |= s_ba16 (d->platform_heading_deg, &q->plat_heading);
        rc |= s_sa16 (d->platform_pitch_deg, &q->plat_pitch);
        rc |= s_sa16 (d->platform_roll_deg, &q->plat_roll);
    }
    rc |= s_sa32 (d->area_lat_deg, &q->area_lat);
    rc |= s_ba32 (d->area_lon_deg, &q->area_lon);
    rc |= s_b16 (d->range_half_extent_m / 1000.0, &q->range);
    if (!(d->range_half_extent_m >= 0))
        rc = -EINVAL; // a negative half extent would take the sign bit
    if (!(d->angle_half_extent_deg >= 0.0 && d->angle_half_extent_deg <= 180.0))
        rc = -EINVAL;
    rc |= s_ba16 (d->angle_half_extent_deg, &q->angle);
    if (mask & S_D (28)) {
        rc |= s_ba16 (d->sensor_heading_deg, &q->sensor_heading);
        rc |= s_sa16 (d->sensor_pitch_deg, &q->sensor_pitch);
        rc |= s_sa16 (d->sensor_roll_deg, &q->sensor_roll);
    }
    if (mask & S_D (31))
        rc |= s_mag (d->mdv_mps, 10.0, UINT8_MAX, &q->mdv);
    return rc ? -EINVAL : 0;
}

/* A target report quantised; fields the mask lacks are not read. */
typedef struct {
    int32_t lat;
    uint32_t lon;
    int64_t height, vlos, wrap, snr, prob, slant, cross, hunc, vunc, rcs;
} s_report_q_t;

static int s_report_quantise (const gw_s4607_report_t *r, uint64_t mask, s_report_q_t *q)
{
    int rc = s_sa32 (r->lat_deg, &q->lat);
    rc |= s_ba32 (r->lon_deg, &q->lon);
    if (mask & S_D32 (6))
        rc |= s_exact (r->height_m, 1.0, -1000, INT16_MAX, &q->height);
    if (mask & S_D32 (7)) {
        rc |= s_sat (r->los_velocity_mps, 100.0, INT16_MIN, INT16_MAX, &q->vlos);
        rc |= s_mag (r->wrap_velocity_mps, 100.0, UINT16_MAX, &q->wrap);
    }
    if (mask & S_D32 (9))
        rc |= s_sat (r->snr_db, 1.0, INT8_MIN, INT8_MAX, &q->snr);
    if (mask & S_D32 (11))
        rc |= s_exact (r->class_probability, 100.0, 0, 100, &q->prob);
    if (mask & S_D32 (12)) {
        rc |= s_mag (r->slant_range_unc_m, 100.0, UINT16_MAX, &q->slant);
        rc |= s_mag (r->cross_range_unc_m, 10.0, UINT16_MAX, &q->cross);
        rc |= s_mag (r->height_unc_m, 1.0, UINT8_MAX, &q->hunc);
        rc |= s_mag (r->los_velocity_unc_mps, 100.0, 5000, &q->vunc);
    }
    if (mask & S_D32 (18))
        rc |= s_sat (r->rcs_dbsm, 2.0, INT8_MIN, INT8_MAX, &q->rcs);
    return rc ? -EINVAL : 0;
}

static void s_put_report (s_w_t *w, const gw_s4607_report_t *r, uint64_t mask,
                          const s_report_q_t *q)
{
    if (mask & S_D32 (1))
        s_i16 (w, r->index);
    s_s32 (w, q->lat); // D32.2
    s_i32 (w, q->lon); // D32.3
    if (mask & S_D32 (6))
        s_s16 (w, (int16_t)q->height);
    if (mask & S_D32 (7)) {
        s_s16 (w, (int16_t)q->vlos);
        s_i16 (w, (uint16_t)q->wrap); // D32.8
    }
    if (mask & S_D32 (9))
        s_s8 (w, (int8_t)q->snr);
    if (mask & S_D32 (10))
        s_i8 (w, r->classification);
    if (mask & S_D32 (11))
        s_i8 (w, (uint8_t)q->prob);
    if (mask & S_D32 (12)) {
        s_i16 (w, (uint16_t)q->slant);
        s_i16 (w, (uint16_t)q->cross); // D32.13
        s_i8 (w, (uint8_t)q->hunc);    // D32.14
        s_i16 (w, (uint16_t)q->vunc);  // D32.15
    }
    if (mask & S_D32 (16)) {
        s_i8 (w, r->truth_application);
        s_i32 (w, r->truth_entity); // D32.17
    }
    if (mask & S_D32 (18))
        s_s8 (w, (int8_t)q->rcs);
}

int gw_s4607_add_dwell (gw_s4607_packet_t *p, const gw_s4607_dwell_t *d, const gw_s4607_report_t *r,
                        size_t n)
{
    assert (p->buf && p->len >= GW_S4607_HEADER_LEN);
    assert (n == 0 || r);
    uint64_t mask = s_mask (d);
    const uint8_t *job = p->buf + 28; // P10: a dwell belongs to a job
    if (!mask || n > GW_S4607_REPORTS_MAX || !(job[0] | job[1] | job[2] | job[3]))
        return -EINVAL;
    s_dwell_q_t q = {0}; // zeroed: each quantiser writes only on success
    s_report_q_t rq = {0};
    if (s_dwell_quantise (d, mask, &q) < 0)
        return -EINVAL;
    for (size_t i = 0; i < n; i++)
        if (s_report_quantise (&r[i], mask, &rq) < 0)
            return -EINVAL;
    size_t size = s_dwell_size (mask, n);
    uint8_t *at = s_room (p, size);
    if (!at)
        return -ENOSPC;
    s_w_t w = {at};
    s_seg_header (&w, GW_S4607_SEG_DWELL, size);
    s_i64 (&w, mask);                 // D1
    s_i16 (&w, d->revisit_index);     // D2
    s_i16 (&w, d->dwell_index);       // D3
    s_i8 (&w, d->last_dwell ? 1 : 0); // D4
    s_i16 (&w, (uint16_t)n);          // D5
    s_i32 (&w, (uint32_t)q.time);     // D6
    s_s32 (&w, q.lat);                // D7
    s_i32 (&w, q.lon);                // D8
    s_s32 (&w, (int32_t)q.alt);       // D9
    if (mask & S_D (12)) {
        s_i32 (&w, (uint32_t)q.along);   // D12
        s_i32 (&w, (uint32_t)q.cross);   // D13
        s_i16 (&w, (uint16_t)q.alt_unc); // D14
    }
    if (mask & S_D (15)) {
        s_i16 (&w, q.track);           // D15
        s_i32 (&w, (uint32_t)q.speed); // D16
        s_s8 (&w, (int8_t)q.vv);       // D17
    }
    if (mask & S_D (18)) {
        s_i8 (&w, (uint8_t)q.track_unc);   // D18
        s_i16 (&w, (uint16_t)q.speed_unc); // D19
        s_i16 (&w, (uint16_t)q.vv_unc);    // D20
    }
    if (mask & S_D (21)) {
        s_i16 (&w, q.plat_heading); // D21
        s_s16 (&w, q.plat_pitch);   // D22
        s_s16 (&w, q.plat_roll);    // D23
    }
    s_s32 (&w, q.area_lat); // D24
    s_i32 (&w, q.area_lon); // D25
    s_i16 (&w, q.range);    // D26
    s_i16 (&w, q.angle);    // D27
    if (mask & S_D (28)) {
        s_i16 (&w, q.sensor_heading); // D28
        s_s16 (&w, q.sensor_pitch);   // D29
        s_s16 (&w, q.sensor_roll);    // D30
    }
    if (mask & S_D (31))
        s_i8 (&w, (uint8_t)q.mdv); // D31
    for (size_t i = 0; i < n; i++) {
        s_report_quantise (&r[i], mask, &rq);
        s_put_report (&w, &r[i], mask, &rq);
    }
    assert (w.at == at + size);
    s_commit (p, size);
    return 0;
}
