/* test_im_klv — imagerd's MISB ST 0601 (UAS Datalink Local Set) packets, read
 * back by a decoder written here from the standard's tables, not from
 * im_klv.c: the key, BER lengths (short and long form), each item's BER-OID
 * tag and length, the checksum summed as 16-bit big-endian words (the
 * standard's byte-wise running sum, computed another way), and each item's
 * mapping from its own table below.
 *   - the standard's worked example values (section 8 of ST 0601.11 to .17),
 *     every one reproduced byte for byte, and its checksum example;
 *   - the packet's layout: key, length, tag 2 first, increasing tags, LS
 *     version 17, checksum last; any one flipped bit is detected;
 *   - random frames read back within half a step of each item's mapping;
 *   - corners in offset form (26-33) when they fit ±0.075° of the frame
 *     centre, else in full form (82-89);
 *   - values outside a mapping: the out-of-range value, clamped, wrapped or
 *     left out, as the header says;
 *   - NAN leaves its tag out; a missing or bad time, or too small a buffer,
 *     gives 0 and an untouched buffer;
 *   - short and long BER lengths, the longest packet, mission ids cut at
 *     127 bytes on a character boundary, track ids in decimal.
 * Needs -Iservices/imagerd. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "im_klv.h"

#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ---- a reader of the standard's layout ---------------------------------------------- */

/* ST 0601: the UAS Datalink Local Set's 16-byte key. */
static const uint8_t s_ul[16] = {0x06, 0x0E, 0x2B, 0x34, 0x02, 0x0B, 0x01, 0x01,
                                 0x0E, 0x01, 0x03, 0x01, 0x01, 0x00, 0x00, 0x00};

typedef struct {
    bool present;
    size_t off, len; // the value's offset in the packet, and its length
} s_item_t;

typedef struct {
    s_item_t item[256]; // by tag
    unsigned order[128];
    int count;        // items, in order[]
    int length_bytes; // of the packet's BER length: 1 short form, 2 or 3 long
    size_t value_len; // the packet's length field
    uint16_t stored;  // the checksum item's value
    bool checksum_ok;
} s_pkt_t;

/* The 16-bit sum of n bytes taken as big-endian words, a lone last byte as
 * the high half of a word; wraps. */
static uint16_t s_sum16 (const uint8_t *b, size_t n)
{
    uint32_t sum = 0;
    for (size_t i = 0; i + 1 < n; i += 2)
        sum += (uint32_t)b[i] << 8 | b[i + 1];
    if (n % 2)
        sum += (uint32_t)b[n - 1] << 8;
    return (uint16_t)sum;
}

/* A BER length at b[*i] (short, or long with 1..4 bytes); false when it runs
 * past n. */
static bool s_ber (const uint8_t *b, size_t n, size_t *i, size_t *ret_len, int *ret_bytes)
{
    if (*i >= n)
        return false;
    if (b[*i] < 0x80) {
        *ret_len = b[(*i)++], *ret_bytes = 1;
        return true;
    }
    size_t k = b[*i] & 0x7F, len = 0;
    if (k < 1 || k > 4 || *i + 1 + k > n)
        return false;
    for (size_t j = 0; j < k; j++)
        len = len << 8 | b[*i + 1 + j];
    *i += 1 + k, *ret_len = len, *ret_bytes = (int)(1 + k);
    return true;
}

/* Parse a packet; NULL, or what is wrong with it. */
static const char *s_parse (const uint8_t *b, size_t n, s_pkt_t *p)
{
    memset (p, 0, sizeof *p);
    if (n < 17 || memcmp (b, s_ul, 16) != 0)
        return "not the UAS Datalink LS key";
    size_t i = 16;
    if (!s_ber (b, n, &i, &p->value_len, &p->length_bytes))
        return "bad BER length";
    if (i + p->value_len != n)
        return "length field does not match the packet";
    while (i < n) {
        unsigned tag = 0;
        int k = 0;
        do {
            if (i >= n || k == 3)
                return "bad BER-OID tag";
            tag = tag << 7 | (b[i] & 0x7F), k++;
        } while (b[i++] & 0x80);
        size_t len;
        int lb;
        if (!s_ber (b, n, &i, &len, &lb))
            return "bad item length";
        if (i + len > n)
            return "item runs past the packet";
        if (tag == 0 || tag >= 256 || p->item[tag].present || p->count == 128)
            return "tag zero, unexpected or repeated";
        p->item[tag] = (s_item_t){true, i, len};
        p->order[p->count++] = tag;
        i += len;
    }
    if (p->count == 0 || p->order[p->count - 1] != 1 || p->item[1].len != 2)
        return "checksum is not the last item";
    p->stored = (uint16_t)(b[n - 2] << 8 | b[n - 1]);
    p->checksum_ok = s_sum16 (b, n - 2) == p->stored;
    return NULL;
}

static uint64_t s_raw (const uint8_t *b, const s_pkt_t *p, unsigned tag)
{
    uint64_t v = 0;
    for (size_t i = 0; i < p->item[tag].len; i++)
        v = v << 8 | b[p->item[tag].off + i];
    return v;
}

/* ST 0601 section 8, item by item: unsigned maps 0..2^n-1 onto lo..hi;
 * signed maps ±(2^(n-1)-1) onto ±hi, -2^(n-1) being a special value. */
typedef struct {
    unsigned tag;
    size_t len;
    bool is_signed;
    double lo, hi;
} s_map_t;

static const s_map_t s_maps[] = {
    {5, 2, false, 0, 360},        {6, 2, true, -20, 20},        {7, 2, true, -50, 50},
    {13, 4, true, -90, 90},       {14, 4, true, -180, 180},     {15, 2, false, -900, 19000},
    {16, 2, false, 0, 180},       {17, 2, false, 0, 180},       {18, 4, false, 0, 360},
    {19, 4, true, -180, 180},     {20, 4, false, 0, 360},       {21, 4, false, 0, 5e6},
    {23, 4, true, -90, 90},       {24, 4, true, -180, 180},     {25, 2, false, -900, 19000},
    {26, 2, true, -0.075, 0.075}, {27, 2, true, -0.075, 0.075}, {28, 2, true, -0.075, 0.075},
    {29, 2, true, -0.075, 0.075}, {30, 2, true, -0.075, 0.075}, {31, 2, true, -0.075, 0.075},
    {32, 2, true, -0.075, 0.075}, {33, 2, true, -0.075, 0.075}, {40, 4, true, -90, 90},
    {41, 4, true, -180, 180},     {75, 2, false, -900, 19000},  {82, 4, true, -90, 90},
    {83, 4, true, -180, 180},     {84, 4, true, -90, 90},       {85, 4, true, -180, 180},
    {86, 4, true, -90, 90},       {87, 4, true, -180, 180},     {88, 4, true, -90, 90},
    {89, 4, true, -180, 180},
};

static const s_map_t *s_map (unsigned tag)
{
    for (size_t i = 0; i < sizeof s_maps / sizeof s_maps[0]; i++)
        if (s_maps[i].tag == tag)
            return &s_maps[i];
    fail_msg ("no mapping for tag %u", tag);
    return NULL;
}

/* One step of the item's mapping. */
static double s_lsb (unsigned tag)
{
    const s_map_t *m = s_map (tag);
    double steps = ldexp (1.0, (int)(8 * m->len)) - (m->is_signed ? 2.0 : 1.0);
    return (m->hi - m->lo) / steps;
}

/* The item's value; NAN for the special value -2^(n-1) of a signed item. */
static double s_value (const uint8_t *b, const s_pkt_t *p, unsigned tag)
{
    const s_map_t *m = s_map (tag);
    if (!p->item[tag].present)
        fail_msg ("tag %u is missing", tag);
    assert_int_equal (p->item[tag].len, m->len);
    uint64_t raw = s_raw (b, p, tag);
    int bits = (int)(8 * m->len);
    if (!m->is_signed)
        return m->lo + (double)raw * (m->hi - m->lo) / (ldexp (1.0, bits) - 1.0);
    assert_true (bits <= 32);
    int64_t v = raw >= (1ull << (bits - 1)) ? (int64_t)raw - (int64_t)(1ull << bits) : (int64_t)raw;
    if (v == -(int64_t)(1ull << (bits - 1)))
        return NAN;
    return (double)v * m->hi / (ldexp (1.0, bits - 1) - 1.0);
}

/* The item's bytes against hex digits. */
static void s_expect_hex (const uint8_t *b, const s_pkt_t *p, unsigned tag, const char *hex)
{
    if (!p->item[tag].present)
        fail_msg ("tag %u is missing", tag);
    size_t want = strlen (hex) / 2;
    if (p->item[tag].len != want)
        fail_msg ("tag %u: %zu bytes, want %zu", tag, p->item[tag].len, want);
    for (size_t i = 0; i < want; i++) {
        unsigned byte;
        sscanf (hex + 2 * i, "%2x", &byte);
        if (b[p->item[tag].off + i] != byte)
            fail_msg ("tag %u byte %zu: %02X, want %02X (want %s)", tag, i, b[p->item[tag].off + i],
                      byte, hex);
    }
}

static void s_encode_parse (const im_klv_frame_t *f, uint8_t *b, size_t *ret_n, s_pkt_t *p)
{
    size_t n = im_klv_encode (f, b, IM_KLV_MAX_PACKET);
    assert_true (n > 0 && n <= IM_KLV_MAX_PACKET);
    const char *why = s_parse (b, n, p);
    if (why)
        fail_msg ("packet rejected: %s", why);
    assert_true (p->checksum_ok);
    *ret_n = n;
}

/* ---- the standard's worked examples ------------------------------------------------- */

/* Each item's "example value" from ST 0601 section 8 (0601.11; tag 2 and 3
 * from 0601.9's example). Worked here by the mapping (value × steps / range,
 * rounded to nearest):
 *   5  159.9744 × 65535/360        =  29122.006     → 0x71C2
 *   6  -0.4315251 × 32767/20       =  -706.989      → -707 = 0xFD3D
 *   7  3.405814 × 32767/50         =  2231.966      → 0x08B8
 *  13  60.1768229669783 × (2^31-1)/90  = 1435874925.000 → 0x5595B66D
 *  14  128.426759042045 × (2^31-1)/180 = 1532190916.000 → 0x5B5360C4
 *  15  (14190.72 + 900) × 65535/19900  =  49697.002 → 0xC221 (75 the same)
 *  16  144.5713 × 65535/180        =  52636.001     → 0xCD9C
 *  17  152.6436 × 65535/180        =  55574.991     → 0xD917
 *  18  160.719211474396 × (2^32-1)/360 = 1917454880.446 → 0x724A0A20
 *  19  -168.792324833941 × (2^31-1)/180 = -2013770874.000 → 0x87F84B86
 *  20  176.865437690572 × (2^32-1)/360 = 2110086862.491 → 0x7DC55ECE
 *  21  68590.9833 × (2^32-1)/5e6   = 58919206.0     → 0x03830926; the
 *      document prints the value as 68590.98, which alone gives 0x03830923:
 *      its bytes are those of 68590.9833 (what they decode to)
 *  23  -10.5423886331461 × (2^31-1)/90 = -251551191.000 → 0xF101A229
 *  24  29.157890122923 × (2^31-1)/180  =  347867179.000 → 0x14BC082B
 *  25  (3216.037 + 900) × 65535/19900  =  13554.999 → 0x34F3
 *  26  (-10.579637999887 + 10.5423886331461) × 32767/0.075 = -16274.0 → 0xC06E
 *      and so on for 27-33 from the corners below (0xCBE9 0xD765 0xE2E0
 *      0xEE5B 0xF9D6 0x0552 0x10CD)
 *  40  -79.1638500518929 × (2^31-1)/90 = -1888923038.000 → 0x8F695262
 *  41  166.400812960416 × (2^31-1)/180 =  1985239026.000 → 0x765457F2
 *  82  -10.579637999887 × (2^31-1)/90  = -252439995.510 → 0xF0F41244
 *      and so on for 83-89 (0x14B679B9 0xF0F8F87E 0x14B8ECD6 0xF0FDDE81
 *      0x14BB5FD8 0xF102C4BB 0x14BDD2F5). */
static void s_standard (im_klv_frame_t *f)
{
    im_klv_frame_reset (f);
    f->unix_time_s = 1224807209.913; // 0x000459F4A6AA4AA8 µs, 2008-10-24 00:13:29.913
    strcpy (f->mission_id, "MISSION01");
    f->platform_heading_deg = 159.9744;
    f->platform_pitch_deg = -0.4315251;
    f->platform_roll_deg = 3.405814;
    f->sensor_lat_deg = 60.1768229669783;
    f->sensor_lon_deg = 128.426759042045;
    f->sensor_true_alt_m = 14190.72;
    f->sensor_hae_m = 14190.72;
    f->hfov_deg = 144.5713;
    f->vfov_deg = 152.6436;
    f->sensor_rel_az_deg = 160.719211474396;
    f->sensor_rel_el_deg = -168.792324833941;
    f->sensor_rel_roll_deg = 176.865437690572;
    f->slant_range_m = 68590.9833;
    f->frame_center_lat_deg = -10.5423886331461;
    f->frame_center_lon_deg = 29.157890122923;
    f->frame_center_elev_m = 3216.037;
    const double lat[4] = {-10.579637999887, -10.5661816260963, -10.5527275411938,
                           -10.5392711674031};
    const double lon[4] = {29.1273677986333, 29.140824172424, 29.1542782573265, 29.1677346311172};
    for (int i = 0; i < 4; i++)
        f->corner_lat_deg[i] = lat[i], f->corner_lon_deg[i] = lon[i];
    f->has_target = true;
    f->target_lat_deg = -79.1638500518929;
    f->target_lon_deg = 166.400812960416;
    f->track_id = 42;
}

static void test_standard_examples (void **state)
{
    (void)state;
    im_klv_frame_t f;
    s_standard (&f);
    uint8_t b[IM_KLV_MAX_PACKET];
    size_t n;
    s_pkt_t p;
    s_encode_parse (&f, b, &n, &p);
    static const struct {
        unsigned tag;
        const char *hex;
    } want[] = {
        {2, "000459F4A6AA4AA8"},
        {3, "4D495353494F4E3031"},
        {5, "71C2"},
        {6, "FD3D"},
        {7, "08B8"},
        {13, "5595B66D"},
        {14, "5B5360C4"},
        {15, "C221"},
        {16, "CD9C"},
        {17, "D917"},
        {18, "724A0A20"},
        {19, "87F84B86"},
        {20, "7DC55ECE"},
        {21, "03830926"},
        {23, "F101A229"},
        {24, "14BC082B"},
        {25, "34F3"},
        {26, "C06E"},
        {27, "CBE9"},
        {28, "D765"},
        {29, "E2E0"},
        {30, "EE5B"},
        {31, "F9D6"},
        {32, "0552"},
        {33, "10CD"},
        {40, "8F695262"},
        {41, "765457F2"},
        {65, "11"},
        {75, "C221"},
        {129, "3432"},
    };
    for (size_t i = 0; i < sizeof want / sizeof want[0]; i++)
        s_expect_hex (b, &p, want[i].tag, want[i].hex);
    assert_int_equal (p.count, sizeof want / sizeof want[0] + 1); // and the checksum
    print_message ("# the standard's example frame: %zu bytes, checksum 0x%04X\n", n, p.stored);

    /* Without the frame centre the corners go in full form. */
    f.frame_center_lat_deg = NAN;
    s_encode_parse (&f, b, &n, &p);
    static const struct {
        unsigned tag;
        const char *hex;
    } full[] = {
        {82, "F0F41244"}, {83, "14B679B9"}, {84, "F0F8F87E"}, {85, "14B8ECD6"},
        {86, "F0FDDE81"}, {87, "14BB5FD8"}, {88, "F102C4BB"}, {89, "14BDD2F5"},
    };
    for (size_t i = 0; i < sizeof full / sizeof full[0]; i++)
        s_expect_hex (b, &p, full[i].tag, full[i].hex);
    for (unsigned t = 26; t <= 33; t++)
        assert_false (p.item[t].present);
    assert_false (p.item[23].present);
    s_expect_hex (b, &p, 24, "14BC082B");
}

/* The checksum example of ST 0601's checksum section (060E 2B34 0200 81BB → B4FD)
 * and an odd length, for the reader's own sum; then packets: any flipped
 * bit is caught. */
static void test_checksum (void **state)
{
    (void)state;
    const uint8_t st[] = {0x06, 0x0E, 0x2B, 0x34, 0x02, 0x00, 0x81, 0xBB};
    assert_int_equal (s_sum16 (st, sizeof st), 0xB4FD);
    const uint8_t odd[] = {0xAB, 0xCD, 0xEF}; // 0xABCD + 0xEF00 = 0x19ACD
    assert_int_equal (s_sum16 (odd, sizeof odd), 0x9ACD);

    im_klv_frame_t f;
    s_standard (&f);
    uint8_t b[IM_KLV_MAX_PACKET], c[IM_KLV_MAX_PACKET];
    size_t n;
    s_pkt_t p;
    s_encode_parse (&f, b, &n, &p);
    /* The standard's byte-wise running sum over key to checksum length. */
    uint16_t bcc = 0;
    for (size_t i = 0; i < n - 2; i++)
        bcc = (uint16_t)(bcc + (b[i] << (8 * ((i + 1) % 2))));
    assert_int_equal (bcc, p.stored);
    assert_int_equal (b[n - 4], 0x01);
    assert_int_equal (b[n - 3], 0x02);
    int caught = 0;
    for (size_t i = 0; i < n; i++)
        for (int bit = 0; bit < 8; bit++) {
            memcpy (c, b, n);
            c[i] ^= (uint8_t)(1u << bit);
            s_pkt_t q;
            const char *why = s_parse (c, n, &q);
            if (!why && q.checksum_ok)
                fail_msg ("byte %zu bit %d flipped and not caught", i, bit);
            caught++;
        }
    print_message ("# %d single-bit flips of a %zu-byte packet, every one caught\n", caught, n);
}

/* Key, length, order: tag 2 first, then increasing, LS version 17, checksum
 * last. */
static void test_layout (void **state)
{
    (void)state;
    im_klv_frame_t f;
    s_standard (&f);
    uint8_t b[IM_KLV_MAX_PACKET];
    size_t n;
    s_pkt_t p;
    s_encode_parse (&f, b, &n, &p);
    assert_memory_equal (b, s_ul, 16);
    assert_int_equal (p.order[0], 2);
    for (int i = 1; i < p.count - 1; i++)
        if (p.order[i] <= p.order[i - 1])
            fail_msg ("tag %u after %u", p.order[i], p.order[i - 1]);
    assert_int_equal (p.order[p.count - 1], 1);
    assert_true (p.item[65].present);
    assert_int_equal (s_raw (b, &p, 65), 17);
    assert_int_equal (s_raw (b, &p, 2), 0x000459F4A6AA4AA8ull);
}

/* ---- random frames ------------------------------------------------------------------ */

/* xorshift64*: the same sequence on every machine. */
static uint64_t s_rng = 0x9E3779B97F4A7C15ull;
static uint64_t s_next (void)
{
    s_rng ^= s_rng >> 12;
    s_rng ^= s_rng << 25;
    s_rng ^= s_rng >> 27;
    return s_rng * 0x2545F4914F6CDD1Dull;
}
static double s_uniform (double lo, double hi)
{
    return lo + (hi - lo) * (double)(s_next () >> 11) * 0x1p-53;
}

/* Within half a step (and a hair for the arithmetic). */
static void s_near (unsigned tag, double got, double want, double step, bool circular)
{
    double d = fabs (got - want);
    if (circular)
        d = fmin (d, fabs (360.0 - d));
    if (!(d <= 0.5 * step * (1 + 1e-9) + 1e-12))
        fail_msg ("tag %u: %.12g, want %.12g (%.3g steps off)", tag, got, want, d / step);
}

static void test_round_trip (void **state)
{
    (void)state;
    int offset_frames = 0, full_frames = 0;
    for (int k = 0; k < 5000; k++) {
        im_klv_frame_t f;
        im_klv_frame_reset (&f);
        uint64_t us = 1000000000000000ull + s_next () % 1000000000000000ull;
        f.unix_time_s = (double)us / 1e6;
        size_t ml = s_next () % 128;
        for (size_t i = 0; i < ml; i++)
            f.mission_id[i] = (char)(' ' + s_next () % 95);
        f.platform_heading_deg = s_uniform (0, 360);
        f.platform_pitch_deg = s_uniform (-20, 20);
        f.platform_roll_deg = s_uniform (-50, 50);
        f.sensor_lat_deg = s_uniform (-90, 90);
        f.sensor_lon_deg = s_uniform (-180, 180);
        f.sensor_true_alt_m = s_uniform (-900, 19000);
        f.sensor_hae_m = s_uniform (-900, 19000);
        f.hfov_deg = s_uniform (0, 180);
        f.vfov_deg = s_uniform (0, 180);
        f.sensor_rel_az_deg = s_uniform (0, 360);
        f.sensor_rel_el_deg = s_uniform (-180, 180);
        f.sensor_rel_roll_deg = s_uniform (0, 360);
        f.slant_range_m = s_uniform (0, 5e6);
        f.frame_center_lat_deg = s_uniform (-89, 89);
        f.frame_center_lon_deg = s_uniform (-179.5, 179.5);
        f.frame_center_elev_m = s_uniform (-900, 19000);
        bool small = k % 2 == 0;
        double r = small ? 0.0749 : 1.0;
        for (int i = 0; i < 4; i++) {
            f.corner_lat_deg[i] = f.frame_center_lat_deg + s_uniform (-r, r);
            f.corner_lon_deg[i] = f.frame_center_lon_deg + s_uniform (-r, r);
        }
        if (!small)
            f.corner_lon_deg[2] = f.frame_center_lon_deg + 0.1; // certainly too far
        f.has_target = true;
        f.target_lat_deg = s_uniform (-90, 90);
        f.target_lon_deg = s_uniform (-180, 180);
        f.track_id = (uint32_t)s_next ();

        uint8_t b[IM_KLV_MAX_PACKET];
        size_t n;
        s_pkt_t p;
        s_encode_parse (&f, b, &n, &p);
        assert_int_equal (s_raw (b, &p, 2), us);
        assert_int_equal (p.item[3].present, ml > 0);
        if (ml)
            assert_memory_equal (b + p.item[3].off, f.mission_id, ml),
                assert_int_equal (p.item[3].len, ml);
        char id[16];
        snprintf (id, sizeof id, "%u", f.track_id);
        assert_int_equal (p.item[129].len, strlen (id));
        assert_memory_equal (b + p.item[129].off, id, strlen (id));

        const struct {
            unsigned tag;
            double v;
            bool circular;
        } scalars[] = {
            {5, f.platform_heading_deg, true},
            {6, f.platform_pitch_deg, false},
            {7, f.platform_roll_deg, false},
            {13, f.sensor_lat_deg, false},
            {14, f.sensor_lon_deg, true},
            {15, f.sensor_true_alt_m, false},
            {16, f.hfov_deg, false},
            {17, f.vfov_deg, false},
            {18, f.sensor_rel_az_deg, true},
            {19, f.sensor_rel_el_deg, true},
            {20, f.sensor_rel_roll_deg, true},
            {21, f.slant_range_m, false},
            {23, f.frame_center_lat_deg, false},
            {24, f.frame_center_lon_deg, true},
            {25, f.frame_center_elev_m, false},
            {40, f.target_lat_deg, false},
            {41, f.target_lon_deg, true},
            {75, f.sensor_hae_m, false},
        };
        for (size_t i = 0; i < sizeof scalars / sizeof scalars[0]; i++)
            s_near (scalars[i].tag, s_value (b, &p, scalars[i].tag), scalars[i].v,
                    s_lsb (scalars[i].tag), scalars[i].circular);

        double clat = s_value (b, &p, 23), clon = s_value (b, &p, 24);
        for (unsigned i = 0; i < 4; i++) {
            assert_int_equal (p.item[26 + 2 * i].present, small);
            assert_int_equal (p.item[82 + 2 * i].present, !small);
            if (small) {
                s_near (26 + 2 * i, clat + s_value (b, &p, 26 + 2 * i), f.corner_lat_deg[i],
                        s_lsb (26), false);
                s_near (27 + 2 * i, clon + s_value (b, &p, 27 + 2 * i), f.corner_lon_deg[i],
                        s_lsb (27), false);
            } else {
                s_near (82 + 2 * i, s_value (b, &p, 82 + 2 * i), f.corner_lat_deg[i], s_lsb (82),
                        false);
                s_near (83 + 2 * i, s_value (b, &p, 83 + 2 * i), f.corner_lon_deg[i], s_lsb (83),
                        true);
            }
        }
        small ? offset_frames++ : full_frames++;
    }
    print_message ("# %d frames with offset corners, %d with full corners, all within half a "
                   "step\n",
                   offset_frames, full_frames);
}

/* ---- corners ------------------------------------------------------------------------ */

/* A 200 m footprint around (48.5, 11.25). */
static void s_footprint (im_klv_frame_t *f, double half_deg)
{
    im_klv_frame_reset (f);
    f->unix_time_s = 1.7e9;
    f->frame_center_lat_deg = 48.5, f->frame_center_lon_deg = 11.25;
    const double sl[4] = {1, 1, -1, -1}, so[4] = {-1, 1, 1, -1};
    for (int i = 0; i < 4; i++) {
        f->corner_lat_deg[i] = 48.5 + sl[i] * half_deg;
        f->corner_lon_deg[i] = 11.25 + so[i] * half_deg;
    }
}

static void s_expect_form (const im_klv_frame_t *f, bool offset, bool full)
{
    uint8_t b[IM_KLV_MAX_PACKET];
    size_t n;
    s_pkt_t p;
    s_encode_parse (f, b, &n, &p);
    for (unsigned t = 26; t <= 33; t++)
        assert_int_equal (p.item[t].present, offset);
    for (unsigned t = 82; t <= 89; t++)
        assert_int_equal (p.item[t].present, full);
}

static void test_corner_forms (void **state)
{
    (void)state;
    im_klv_frame_t f;
    s_footprint (&f, 0.001);
    s_expect_form (&f, true, false);
    s_footprint (&f, 0.0749);
    s_expect_form (&f, true, false);
    s_footprint (&f, 0.0751);
    s_expect_form (&f, false, true);
    s_footprint (&f, 0.001);
    f.corner_lat_deg[3] = 48.6; // one corner 0.1° away
    s_expect_form (&f, false, true);
    s_footprint (&f, 0.001);
    f.corner_lon_deg[1] = 11.15;
    s_expect_form (&f, false, true);
    s_footprint (&f, 0.001);
    f.frame_center_lon_deg = NAN; // nothing to offset from
    s_expect_form (&f, false, true);
    s_footprint (&f, 0.001);
    f.frame_center_lat_deg = 91; // the centre is left out, so
    s_expect_form (&f, false, true);
    s_footprint (&f, 0.001);
    f.corner_lon_deg[2] = NAN; // corners go together or not at all
    s_expect_form (&f, false, false);
    s_footprint (&f, 0.5);
    f.corner_lat_deg[0] = 90.5;
    s_expect_form (&f, false, false);

    /* Astride the antimeridian: full form, longitudes wrapped. */
    s_footprint (&f, 0.01);
    f.frame_center_lon_deg = 179.995;
    for (int i = 0; i < 4; i++)
        f.corner_lon_deg[i] = 179.995 + (i == 1 || i == 2 ? 0.01 : -0.01);
    uint8_t b[IM_KLV_MAX_PACKET];
    size_t n;
    s_pkt_t p;
    s_encode_parse (&f, b, &n, &p);
    assert_true (p.item[85].present);
    s_near (85, s_value (b, &p, 85), 180.005 - 360.0, s_lsb (85), false);
}

/* ---- out of range, left out, refused ------------------------------------------------ */

typedef struct {
    size_t off; // offsetof a double in im_klv_frame_t
    unsigned tag;
} s_field_t;

/* The raw value of one tag (and whether it is there) for the standard's
 * example frame with one double changed. */
static uint64_t s_raw_of (size_t off, double v, unsigned tag, bool *ret_present)
{
    im_klv_frame_t f;
    s_standard (&f);
    *(double *)((char *)&f + off) = v;
    uint8_t b[IM_KLV_MAX_PACKET];
    size_t n;
    s_pkt_t p;
    s_encode_parse (&f, b, &n, &p);
    *ret_present = p.item[tag].present;
    return p.item[tag].present ? s_raw (b, &p, tag) : 0;
}

/* Same bytes for two values of one field. */
static void s_same (size_t off, unsigned tag, double a, double b)
{
    bool pa, pb;
    uint64_t ra = s_raw_of (off, a, tag, &pa), rb = s_raw_of (off, b, tag, &pb);
    assert_true (pa && pb);
    if (ra != rb)
        fail_msg ("tag %u: %.9g gives 0x%llX, %.9g gives 0x%llX", tag, a, (unsigned long long)ra, b,
                  (unsigned long long)rb);
}

static void s_raw_is (size_t off, unsigned tag, double v, uint64_t want)
{
    bool present;
    uint64_t raw = s_raw_of (off, v, tag, &present);
    if (!present)
        fail_msg ("tag %u left out for %.9g", tag, v);
    if (raw != want)
        fail_msg ("tag %u: %.9g gives 0x%llX, want 0x%llX", tag, v, (unsigned long long)raw,
                  (unsigned long long)want);
}

static void s_absent (size_t off, unsigned tag, double v)
{
    bool present;
    s_raw_of (off, v, tag, &present);
    if (present)
        fail_msg ("tag %u present for %.9g", tag, v);
}

#define F(field) offsetof (im_klv_frame_t, field)

static void test_out_of_range (void **state)
{
    (void)state;
    /* Out-of-range indicator (pitch ±20, roll ±50). */
    s_raw_is (F (platform_pitch_deg), 6, 25, 0x8000);
    s_raw_is (F (platform_pitch_deg), 6, -20.001, 0x8000);
    s_raw_is (F (platform_pitch_deg), 6, 20, 0x7FFF);
    s_raw_is (F (platform_pitch_deg), 6, -20, 0x8001);
    s_raw_is (F (platform_pitch_deg), 6, 0, 0x0000);
    s_raw_is (F (platform_roll_deg), 7, 50.001, 0x8000);
    s_raw_is (F (platform_roll_deg), 7, -50, 0x8001);
    /* Clamped. */
    s_raw_is (F (sensor_true_alt_m), 15, 19000.5, 0xFFFF);
    s_raw_is (F (sensor_true_alt_m), 15, -901, 0x0000);
    s_raw_is (F (sensor_true_alt_m), 15, -900, 0x0000);
    s_raw_is (F (sensor_true_alt_m), 15, 0, 2964); // 900 × 65535/19900 = 2963.8
    s_raw_is (F (sensor_hae_m), 75, 25000, 0xFFFF);
    s_raw_is (F (frame_center_elev_m), 25, -5000, 0x0000);
    s_raw_is (F (hfov_deg), 16, 181, 0xFFFF);
    s_raw_is (F (vfov_deg), 17, -1, 0x0000);
    s_raw_is (F (vfov_deg), 17, 90, 32768); // 32767.5 rounds up
    s_raw_is (F (slant_range_m), 21, -1, 0);
    s_raw_is (F (slant_range_m), 21, 6e6, 0xFFFFFFFF);
    s_raw_is (F (slant_range_m), 21, 1000, 858993); // 1000 × (2^32-1)/5e6 = 858993.459
    /* Wrapped: angles. */
    s_same (F (platform_heading_deg), 5, -90, 270);
    s_same (F (platform_heading_deg), 5, 720.5, 0.5);
    s_same (F (platform_heading_deg), 5, 360, 0);
    s_raw_is (F (platform_heading_deg), 5, 90, 16384); // 16383.75
    s_same (F (sensor_rel_az_deg), 18, -10, 350);
    s_same (F (sensor_rel_roll_deg), 20, 370, 10);
    s_same (F (sensor_rel_el_deg), 19, 190, -170);
    s_same (F (sensor_rel_el_deg), 19, -181, 179);
    s_raw_is (F (sensor_rel_el_deg), 19, -180, 0x80000001);
    s_same (F (sensor_lon_deg), 14, 190, -170);
    s_same (F (frame_center_lon_deg), 24, -200, 160);
    s_same (F (target_lon_deg), 41, 540, -180); // the same meridian as 180
    s_raw_is (F (sensor_lon_deg), 14, -180, 0x80000001);
    s_raw_is (F (sensor_lat_deg), 13, 90, 0x7FFFFFFF);
    /* Left out: a latitude outside ±90 (0x80000000 is reserved), and any
     * optional value that is not finite. */
    s_absent (F (sensor_lat_deg), 13, 90.0001);
    s_absent (F (frame_center_lat_deg), 23, -91);
    s_absent (F (target_lat_deg), 40, 95);
    s_absent (F (platform_pitch_deg), 6, INFINITY);
    s_absent (F (slant_range_m), 21, -INFINITY);
    s_absent (F (platform_heading_deg), 5, INFINITY);
}

/* NAN leaves exactly its own tag out. */
static void test_left_out (void **state)
{
    (void)state;
    static const s_field_t fields[] = {
        {F (platform_heading_deg), 5},
        {F (platform_pitch_deg), 6},
        {F (platform_roll_deg), 7},
        {F (sensor_lat_deg), 13},
        {F (sensor_lon_deg), 14},
        {F (sensor_true_alt_m), 15},
        {F (hfov_deg), 16},
        {F (vfov_deg), 17},
        {F (sensor_rel_az_deg), 18},
        {F (sensor_rel_el_deg), 19},
        {F (sensor_rel_roll_deg), 20},
        {F (slant_range_m), 21},
        {F (frame_center_elev_m), 25},
        {F (target_lat_deg), 40},
        {F (target_lon_deg), 41},
        {F (sensor_hae_m), 75},
    };
    im_klv_frame_t f;
    s_standard (&f);
    uint8_t base[IM_KLV_MAX_PACKET], b[IM_KLV_MAX_PACKET];
    size_t bn, n;
    s_pkt_t bp, p;
    s_encode_parse (&f, base, &bn, &bp);
    for (size_t k = 0; k < sizeof fields / sizeof fields[0]; k++) {
        s_standard (&f);
        *(double *)((char *)&f + fields[k].off) = NAN;
        s_encode_parse (&f, b, &n, &p);
        assert_int_equal (p.count, bp.count - 1);
        for (int i = 0, j = 0; i < bp.count; i++) {
            unsigned t = bp.order[i];
            if (t == fields[k].tag)
                continue;
            assert_int_equal (p.order[j], t);
            if (t != 1) { // the checksum differs, of course
                assert_int_equal (p.item[t].len, bp.item[t].len);
                assert_memory_equal (b + p.item[t].off, base + bp.item[t].off, p.item[t].len);
            }
            j++;
        }
    }

    /* Nothing but the time: tags 2, 65 and 1; with a mission id, 3 too. */
    im_klv_frame_reset (&f);
    f.unix_time_s = 0;
    s_encode_parse (&f, b, &n, &p);
    assert_int_equal (p.count, 3);
    assert_int_equal (p.order[0], 2), assert_int_equal (p.order[1], 65);
    assert_int_equal (s_raw (b, &p, 2), 0);
    strcpy (f.mission_id, "M");
    s_encode_parse (&f, b, &n, &p);
    assert_int_equal (p.count, 4);
    assert_int_equal (p.order[1], 3);

    /* No target: no 40, 41, 129, whatever the values say. */
    s_standard (&f);
    f.has_target = false;
    s_encode_parse (&f, b, &n, &p);
    assert_false (p.item[40].present || p.item[41].present || p.item[129].present);
    assert_int_equal (p.count, bp.count - 3);
    /* A target without a position still names its track. */
    s_standard (&f);
    f.target_lat_deg = f.target_lon_deg = NAN;
    f.track_id = 0;
    s_encode_parse (&f, b, &n, &p);
    assert_false (p.item[40].present || p.item[41].present);
    s_expect_hex (b, &p, 129, "30");
}

static void test_refused (void **state)
{
    (void)state;
    im_klv_frame_t f;
    s_standard (&f);
    uint8_t b[IM_KLV_MAX_PACKET + 8];
    const double bad[] = {NAN, INFINITY, -INFINITY, -1e-3, 1e14};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        f.unix_time_s = bad[i];
        memset (b, 0xA5, sizeof b);
        assert_int_equal (im_klv_encode (&f, b, sizeof b), 0);
        for (size_t j = 0; j < sizeof b; j++)
            assert_int_equal (b[j], 0xA5);
    }
    s_standard (&f);
    uint8_t good[IM_KLV_MAX_PACKET];
    size_t n = im_klv_encode (&f, good, sizeof good);
    assert_true (n > 0);
    for (size_t cap = 0; cap < n; cap++) {
        memset (b, 0xA5, sizeof b);
        assert_int_equal (im_klv_encode (&f, b, cap), 0);
        for (size_t j = 0; j < sizeof b; j++)
            assert_int_equal (b[j], 0xA5);
    }
    assert_int_equal (im_klv_encode (&f, NULL, 0), 0);
    memset (b, 0xA5, sizeof b);
    assert_int_equal (im_klv_encode (&f, b, n), n);
    assert_memory_equal (b, good, n);
    assert_int_equal (b[n], 0xA5);
}

/* ---- lengths, strings --------------------------------------------------------------- */

static void test_lengths (void **state)
{
    (void)state;
    im_klv_frame_t f;
    uint8_t b[IM_KLV_MAX_PACKET];
    size_t n;
    s_pkt_t p;

    /* Short form: time, version, checksum = 10 + 3 + 4 bytes. */
    im_klv_frame_reset (&f);
    f.unix_time_s = 1.7e9;
    s_encode_parse (&f, b, &n, &p);
    assert_int_equal (p.length_bytes, 1);
    assert_int_equal (b[16], 17);
    assert_int_equal (n, 16 + 1 + 17);

    /* 0x81: a 127-byte mission id makes 146 bytes of items. */
    memset (f.mission_id, 'Q', 127);
    f.mission_id[127] = '\0';
    s_encode_parse (&f, b, &n, &p);
    assert_int_equal (p.length_bytes, 2);
    assert_int_equal (b[16], 0x81);
    assert_int_equal (b[17], 146);
    assert_int_equal (p.item[3].len, 127);
    assert_int_equal (n, 16 + 2 + 146);

    /* 0x82: everything, full corners, the longest mission and track id: the
     * longest packet there is. */
    s_standard (&f);
    memset (f.mission_id, 'Q', 127);
    f.mission_id[127] = '\0';
    f.frame_center_lat_deg += 1; // corners > 0.075° away
    f.track_id = UINT32_MAX;
    s_encode_parse (&f, b, &n, &p);
    assert_int_equal (p.length_bytes, 3);
    assert_int_equal (b[16], 0x82);
    assert_int_equal (p.value_len, (size_t)b[17] << 8 | b[18]);
    assert_int_equal (n, IM_KLV_MAX_PACKET);
    assert_true (p.item[89].present);
    s_expect_hex (b, &p, 129, "34323934393637323935"); // "4294967295"
    /* Tag 129's BER-OID is two bytes: 0x81 0x01. */
    assert_int_equal (b[p.item[129].off - 3], 0x81);
    assert_int_equal (b[p.item[129].off - 2], 0x01);
    assert_int_equal (b[p.item[129].off - 1], 10);
    print_message ("# the longest packet: %zu bytes, length 82 %02X %02X\n", n, b[17], b[18]);

    /* A mission id filling all 128 bytes, no terminator: cut at 127. */
    im_klv_frame_reset (&f);
    f.unix_time_s = 1.7e9;
    memset (f.mission_id, 'x', sizeof f.mission_id);
    s_encode_parse (&f, b, &n, &p);
    assert_int_equal (p.item[3].len, 127);
    /* ... and not through a character: 126 'a' then é (C3 A9) is cut to 126. */
    memset (f.mission_id, 'a', 126);
    f.mission_id[126] = (char)0xC3, f.mission_id[127] = (char)0xA9;
    s_encode_parse (&f, b, &n, &p);
    assert_int_equal (p.item[3].len, 126);
    /* 125 'a' then é fits whole. */
    f.mission_id[125] = (char)0xC3, f.mission_id[126] = (char)0xA9, f.mission_id[127] = '\0';
    s_encode_parse (&f, b, &n, &p);
    assert_int_equal (p.item[3].len, 127);
    assert_int_equal (b[p.item[3].off + 126], 0xA9);
}

int main (void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test (test_standard_examples),
        cmocka_unit_test (test_checksum),
        cmocka_unit_test (test_layout),
        cmocka_unit_test (test_round_trip),
        cmocka_unit_test (test_corner_forms),
        cmocka_unit_test (test_out_of_range),
        cmocka_unit_test (test_left_out),
        cmocka_unit_test (test_refused),
        cmocka_unit_test (test_lengths),
    };
    return cmocka_run_group_tests (tests, NULL, NULL);
}
