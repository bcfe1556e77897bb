/* im_klv — a frame's metadata as a MISB ST 0601 UAS Datalink Local Set
 * packet. The items are built into a local buffer first (the packet's length
 * comes before them), then key, length, items and checksum are copied out
 * when they fit. See im_klv.h for every item's mapping. */
#include "im_klv.h"

#include <assert.h>
#include <math.h>
#include <string.h>

/* The UAS Datalink Local Set's 16-byte Universal Label (ST 0601). */
static const uint8_t s_key[16] = {0x06, 0x0E, 0x2B, 0x34, 0x02, 0x0B, 0x01, 0x01,
                                  0x0E, 0x01, 0x03, 0x01, 0x01, 0x00, 0x00, 0x00};

#define S_KEY_LEN     16
#define S_MAX_BER     3                                           // 0x82 and two bytes
#define S_MAX_ITEMS   (IM_KLV_MAX_PACKET - S_KEY_LEN - S_MAX_BER) // every item, checksum too
#define S_OFFSET_MAX  0.075                                       // tags 26-33, degrees
#define S_MISSION_MAX 127                                         // tag 3's longest, bytes

/* Items being built: p[0..n). */
typedef struct {
    uint8_t p[S_MAX_ITEMS];
    size_t n;
} s_items_t;

void im_klv_frame_reset (im_klv_frame_t *f)
{
    assert (f);
    memset (f, 0, sizeof *f);
    double *all[] = {&f->unix_time_s,
                     &f->platform_heading_deg,
                     &f->platform_pitch_deg,
                     &f->platform_roll_deg,
                     &f->sensor_lat_deg,
                     &f->sensor_lon_deg,
                     &f->sensor_true_alt_m,
                     &f->sensor_hae_m,
                     &f->hfov_deg,
                     &f->vfov_deg,
                     &f->sensor_rel_az_deg,
                     &f->sensor_rel_el_deg,
                     &f->sensor_rel_roll_deg,
                     &f->slant_range_m,
                     &f->frame_center_lat_deg,
                     &f->frame_center_lon_deg,
                     &f->frame_center_elev_m,
                     &f->target_lat_deg,
                     &f->target_lon_deg};
    for (size_t i = 0; i < sizeof all / sizeof all[0]; i++)
        *all[i] = NAN;
    for (int i = 0; i < 4; i++)
        f->corner_lat_deg[i] = NAN, f->corner_lon_deg[i] = NAN;
}

/* ---- items -------------------------------------------------------------------------- */

/* One item: the tag as a BER-OID (7 bits a byte, high bit set on all but the
 * last), a one-byte length (every value here is under 128 bytes), the value. */
static void s_item (s_items_t *it, unsigned tag, const uint8_t *value, size_t len)
{
    assert (tag > 0 && tag < 16384 && len < 128);
    assert (it->n + 3 + len <= sizeof it->p);
    if (tag >= 128)
        it->p[it->n++] = (uint8_t)(0x80 | tag >> 7);
    it->p[it->n++] = (uint8_t)(tag & 0x7F);
    it->p[it->n++] = (uint8_t)len;
    memcpy (it->p + it->n, value, len);
    it->n += len;
}

/* An item holding the low `bytes` bytes of v, big-endian (two's complement
 * for a signed value converted to uint64_t). */
static void s_item_int (s_items_t *it, unsigned tag, uint64_t v, size_t bytes)
{
    uint8_t b[8];
    for (size_t i = 0; i < bytes; i++)
        b[i] = (uint8_t)(v >> (8 * (bytes - 1 - i)));
    s_item (it, tag, b, bytes);
}

/* ---- mappings ----------------------------------------------------------------------- */

/* An angle in [0, 360). */
static double s_wrap360 (double deg)
{
    double w = fmod (deg, 360.0);
    if (w < 0)
        w += 360.0;
    return w >= 360.0 ? 0.0 : w; // -1e-17 + 360 rounds to 360
}

/* An angle in [-180, 180]; one inside is kept as it is. */
static double s_wrap180 (double deg)
{
    if (deg >= -180.0 && deg <= 180.0)
        return deg;
    return s_wrap360 (deg + 180.0) - 180.0;
}

/* Unsigned: lo..hi onto 0..2^bits - 1, v clamped into lo..hi first. */
static uint64_t s_unsigned (double v, double lo, double hi, int bits)
{
    double top = ldexp (1.0, bits) - 1.0;
    v = v < lo ? lo : v > hi ? hi : v;
    return (uint64_t)llround ((v - lo) * (top / (hi - lo)));
}

/* Signed: ±range onto ±(2^(bits-1) - 1); |v| <= range. */
static int64_t s_signed (double v, double range, int bits)
{
    double top = ldexp (1.0, bits - 1) - 1.0;
    return llround (v * (top / range));
}

/* A signed value's two's complement; s_item_int keeps its low bytes. */
static uint64_t s_twos (int64_t v)
{
    return (uint64_t)v;
}

/* What a reader decodes from a latitude or longitude item: the value the
 * offset corners are measured from. */
static double s_decoded (double v, double range)
{
    double top = ldexp (1.0, 31) - 1.0;
    return (double)s_signed (v, range, 32) * (range / top);
}

/* A latitude item (13, 23, 40, 82, ...): left out outside ±90. */
static void s_lat (s_items_t *it, unsigned tag, double deg)
{
    if (isfinite (deg) && fabs (deg) <= 90.0)
        s_item_int (it, tag, s_twos (s_signed (deg, 90.0, 32)), 4);
}

/* A longitude item (14, 24, 41, 83, ...): wrapped into ±180. */
static void s_lon (s_items_t *it, unsigned tag, double deg)
{
    if (isfinite (deg))
        s_item_int (it, tag, s_twos (s_signed (s_wrap180 (deg), 180.0, 32)), 4);
}

/* A heading-like u16 or u32 angle (5, 18, 20): wrapped into [0, 360). */
static void s_angle360 (s_items_t *it, unsigned tag, double deg, int bits)
{
    if (isfinite (deg))
        s_item_int (it, tag, s_unsigned (s_wrap360 (deg), 0.0, 360.0, bits), (size_t)bits / 8);
}

/* A clamped unsigned quantity (15, 16, 17, 21, 25, 75). */
static void s_clamped (s_items_t *it, unsigned tag, double v, double lo, double hi, int bits)
{
    if (isfinite (v))
        s_item_int (it, tag, s_unsigned (v, lo, hi, bits), (size_t)bits / 8);
}

/* An s16 attitude angle (6, 7): 0x8000 ("out of range") outside ±range. */
static void s_attitude (s_items_t *it, unsigned tag, double deg, double range)
{
    if (!isfinite (deg))
        return;
    uint64_t v = fabs (deg) <= range ? s_twos (s_signed (deg, range, 16)) : 0x8000u;
    s_item_int (it, tag, v, 2);
}

/* Tag 3: at most 127 bytes, cut before a character that would not fit whole
 * (a UTF-8 continuation byte is 10xxxxxx). */
static void s_mission (s_items_t *it, const char *id, size_t size)
{
    size_t n = strnlen (id, size);
    if (n > S_MISSION_MAX) {
        n = S_MISSION_MAX;
        while (n > 0 && ((uint8_t)id[n] & 0xC0) == 0x80)
            n--;
    }
    if (n > 0)
        s_item (it, 3, (const uint8_t *)id, n);
}

/* Tag 129: the track id in decimal. */
static void s_track_id (s_items_t *it, uint32_t id)
{
    uint8_t rev[10], txt[10];
    size_t n = 0;
    do {
        rev[n++] = (uint8_t)('0' + id % 10);
        id /= 10;
    } while (id);
    for (size_t i = 0; i < n; i++)
        txt[i] = rev[n - 1 - i];
    s_item (it, 129, txt, n);
}

/* ---- corners ------------------------------------------------------------------------ */

typedef enum { S_CORNERS_NONE, S_CORNERS_OFFSET, S_CORNERS_FULL } s_corners_t;

/* Which form the corners take; off_lat/off_lon get the offsets when it is
 * S_CORNERS_OFFSET. */
static s_corners_t s_corner_form (const im_klv_frame_t *f, double off_lat[4], double off_lon[4])
{
    for (int i = 0; i < 4; i++)
        if (!isfinite (f->corner_lat_deg[i]) || !isfinite (f->corner_lon_deg[i]) ||
            fabs (f->corner_lat_deg[i]) > 90.0)
            return S_CORNERS_NONE;
    double clat = f->frame_center_lat_deg, clon = f->frame_center_lon_deg;
    if (!isfinite (clat) || fabs (clat) > 90.0 || !isfinite (clon))
        return S_CORNERS_FULL; // no centre goes out to be offset from
    clat = s_decoded (clat, 90.0);
    clon = s_decoded (s_wrap180 (clon), 180.0);
    for (int i = 0; i < 4; i++) {
        off_lat[i] = f->corner_lat_deg[i] - clat;
        off_lon[i] = s_wrap180 (f->corner_lon_deg[i]) - clon;
        if (!(fabs (off_lat[i]) <= S_OFFSET_MAX && fabs (off_lon[i]) <= S_OFFSET_MAX))
            return S_CORNERS_FULL;
    }
    return S_CORNERS_OFFSET;
}

/* ---- the packet --------------------------------------------------------------------- */

/* The standard's checksum (ST 0601, "Checksum"): a 16-bit running sum, each
 * byte at an even index the high half of a 16-bit word. */
static uint16_t s_checksum (const uint8_t *b, size_t n)
{
    uint16_t bcc = 0;
    for (size_t i = 0; i < n; i++)
        bcc = (uint16_t)(bcc + ((unsigned)b[i] << (8 * ((i + 1) % 2))));
    return bcc;
}

/* The BER length of n into ber; returns its size. */
static size_t s_ber_length (size_t n, uint8_t ber[S_MAX_BER])
{
    assert (n <= 0xFFFF);
    if (n < 128) {
        ber[0] = (uint8_t)n;
        return 1;
    }
    if (n <= 0xFF) {
        ber[0] = 0x81, ber[1] = (uint8_t)n;
        return 2;
    }
    ber[0] = 0x82, ber[1] = (uint8_t)(n >> 8), ber[2] = (uint8_t)n;
    return 3;
}

size_t im_klv_encode (const im_klv_frame_t *f, uint8_t *buf, size_t cap)
{
    assert (f && (buf || cap == 0));
    double us = floor (f->unix_time_s * 1e6 + 0.5);
    if (!(us >= 0.0 && us < 0x1p63)) // NAN fails too
        return 0;

    s_items_t it = {.n = 0};
    s_item_int (&it, 2, (uint64_t)us, 8);
    s_mission (&it, f->mission_id, sizeof f->mission_id);
    s_angle360 (&it, 5, f->platform_heading_deg, 16);
    s_attitude (&it, 6, f->platform_pitch_deg, 20.0);
    s_attitude (&it, 7, f->platform_roll_deg, 50.0);
    s_lat (&it, 13, f->sensor_lat_deg);
    s_lon (&it, 14, f->sensor_lon_deg);
    s_clamped (&it, 15, f->sensor_true_alt_m, -900.0, 19000.0, 16);
    s_clamped (&it, 16, f->hfov_deg, 0.0, 180.0, 16);
    s_clamped (&it, 17, f->vfov_deg, 0.0, 180.0, 16);
    s_angle360 (&it, 18, f->sensor_rel_az_deg, 32);
    if (isfinite (f->sensor_rel_el_deg))
        s_item_int (&it, 19, s_twos (s_signed (s_wrap180 (f->sensor_rel_el_deg), 180.0, 32)), 4);
    s_angle360 (&it, 20, f->sensor_rel_roll_deg, 32);
    s_clamped (&it, 21, f->slant_range_m, 0.0, 5e6, 32);
    s_lat (&it, 23, f->frame_center_lat_deg);
    s_lon (&it, 24, f->frame_center_lon_deg);
    s_clamped (&it, 25, f->frame_center_elev_m, -900.0, 19000.0, 16);

    double off_lat[4], off_lon[4];
    s_corners_t form = s_corner_form (f, off_lat, off_lon);
    if (form == S_CORNERS_OFFSET)
        for (unsigned i = 0; i < 4; i++) {
            s_item_int (&it, 26 + 2 * i, s_twos (s_signed (off_lat[i], S_OFFSET_MAX, 16)), 2);
            s_item_int (&it, 27 + 2 * i, s_twos (s_signed (off_lon[i], S_OFFSET_MAX, 16)), 2);
        }
    if (f->has_target) {
        s_lat (&it, 40, f->target_lat_deg);
        s_lon (&it, 41, f->target_lon_deg);
    }
    uint8_t version = IM_KLV_LS_VERSION;
    s_item (&it, 65, &version, 1);
    s_clamped (&it, 75, f->sensor_hae_m, -900.0, 19000.0, 16);
    if (form == S_CORNERS_FULL)
        for (unsigned i = 0; i < 4; i++) {
            s_lat (&it, 82 + 2 * i, f->corner_lat_deg[i]);
            s_lon (&it, 83 + 2 * i, f->corner_lon_deg[i]);
        }
    if (f->has_target)
        s_track_id (&it, f->track_id);

    uint8_t ber[S_MAX_BER];
    size_t ber_n = s_ber_length (it.n + 4, ber); // + the checksum item
    size_t total = S_KEY_LEN + ber_n + it.n + 4;
    assert (total <= IM_KLV_MAX_PACKET);
    if (total > cap)
        return 0;
    uint8_t *p = buf;
    memcpy (p, s_key, S_KEY_LEN), p += S_KEY_LEN;
    memcpy (p, ber, ber_n), p += ber_n;
    memcpy (p, it.p, it.n), p += it.n;
    *p++ = 1, *p++ = 2;
    uint16_t bcc = s_checksum (buf, (size_t)(p - buf));
    *p++ = (uint8_t)(bcc >> 8), *p++ = (uint8_t)bcc;
    return total;
}
