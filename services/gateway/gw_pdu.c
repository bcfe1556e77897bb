/* gw_pdu — DIS PDUs on the wire, field by field in network byte order. */
#include "gw_pdu.h"

#include <errno.h>
#include <math.h>
#include <string.h>

#define S_UNITS_PER_HOUR 2147483648.0 // 2^31 timestamp units in one hour

/* ---- writer -------------------------------------------------------------------------------- */

typedef struct {
    uint8_t *p;
    size_t len, cap;
    bool overflow;
} s_w_t;

static uint8_t *s_room (s_w_t *w, size_t n)
{
    if (w->overflow || w->cap - w->len < n) {
        w->overflow = true;
        return NULL;
    }
    uint8_t *at = w->p + w->len;
    w->len += n;
    return at;
}

static void s_u8 (s_w_t *w, uint8_t v)
{
    uint8_t *b = s_room (w, 1);
    if (b)
        b[0] = v;
}

static void s_u16 (s_w_t *w, uint16_t v)
{
    uint8_t *b = s_room (w, 2);
    if (b) {
        b[0] = (uint8_t)(v >> 8);
        b[1] = (uint8_t)v;
    }
}

static void s_u32 (s_w_t *w, uint32_t v)
{
    uint8_t *b = s_room (w, 4);
    if (b) {
        b[0] = (uint8_t)(v >> 24);
        b[1] = (uint8_t)(v >> 16);
        b[2] = (uint8_t)(v >> 8);
        b[3] = (uint8_t)v;
    }
}

static void s_u64 (s_w_t *w, uint64_t v)
{
    s_u32 (w, (uint32_t)(v >> 32));
    s_u32 (w, (uint32_t)v);
}

static void s_f32 (s_w_t *w, float v)
{
    uint32_t u;
    memcpy (&u, &v, sizeof u);
    s_u32 (w, u);
}

static void s_f64 (s_w_t *w, double v)
{
    uint64_t u;
    memcpy (&u, &v, sizeof u);
    s_u64 (w, u);
}

static void s_bytes (s_w_t *w, const void *src, size_t n)
{
    uint8_t *b = s_room (w, n);
    if (b && n)
        memcpy (b, src, n);
}

static void s_zeros (s_w_t *w, size_t n)
{
    uint8_t *b = s_room (w, n);
    if (b && n)
        memset (b, 0, n);
}

/* ---- reader -------------------------------------------------------------------------------- */

typedef struct {
    const uint8_t *p;
    size_t len, at;
} s_r_t;

/* The caller has checked that the fields it reads fit; these never read past len. */
static const uint8_t *s_take (s_r_t *r, size_t n)
{
    if (r->len - r->at < n)
        return NULL;
    const uint8_t *b = r->p + r->at;
    r->at += n;
    return b;
}

static uint8_t s_g8 (s_r_t *r)
{
    const uint8_t *b = s_take (r, 1);
    return b ? b[0] : 0;
}

static uint16_t s_g16 (s_r_t *r)
{
    const uint8_t *b = s_take (r, 2);
    return b ? (uint16_t)(b[0] << 8 | b[1]) : 0;
}

static uint32_t s_g32 (s_r_t *r)
{
    const uint8_t *b = s_take (r, 4);
    return b ? (uint32_t)b[0] << 24 | (uint32_t)b[1] << 16 | (uint32_t)b[2] << 8 | b[3] : 0;
}

static uint64_t s_g64 (s_r_t *r)
{
    uint64_t hi = s_g32 (r);
    return hi << 32 | s_g32 (r);
}

static float s_gf32 (s_r_t *r)
{
    uint32_t u = s_g32 (r);
    float v;
    memcpy (&v, &u, sizeof v);
    return v;
}

static double s_gf64 (s_r_t *r)
{
    uint64_t u = s_g64 (r);
    double v;
    memcpy (&v, &u, sizeof v);
    return v;
}

/* ---- timestamps ---------------------------------------------------------------------------- */

uint32_t gw_pdu_timestamp (double seconds_past_hour, bool absolute)
{
    double s = isfinite (seconds_past_hour) ? fmod (seconds_past_hour, 3600.0) : 0;
    if (s < 0)
        s += 3600.0;
    double units = floor (s / 3600.0 * S_UNITS_PER_HOUR);
    if (units >= S_UNITS_PER_HOUR)
        units = S_UNITS_PER_HOUR - 1;
    return (uint32_t)units << 1 | (absolute ? 1u : 0u);
}

double gw_pdu_timestamp_seconds (uint32_t timestamp, bool *ret_absolute)
{
    if (ret_absolute)
        *ret_absolute = timestamp & 1u;
    return (double)(timestamp >> 1) * 3600.0 / S_UNITS_PER_HOUR;
}

/* ---- records ------------------------------------------------------------------------------- */

static void s_put_header (s_w_t *w, const gw_header_t *h, uint8_t type, uint8_t family,
                          size_t length)
{
    s_u8 (w, h->version);
    s_u8 (w, h->exercise);
    s_u8 (w, type);
    s_u8 (w, family);
    s_u32 (w, h->timestamp);
    s_u16 (w, (uint16_t)length);
    // Before version 7 these two bytes are padding; from 7 the first is the PDU status.
    s_u8 (w, h->version >= 7 ? h->status : 0);
    s_u8 (w, 0);
}

static void s_put_id (s_w_t *w, gw_id_t id)
{
    s_u16 (w, id.site);
    s_u16 (w, id.application);
    s_u16 (w, id.entity);
}

static gw_id_t s_get_id (s_r_t *r)
{
    gw_id_t id;
    id.site = s_g16 (r);
    id.application = s_g16 (r);
    id.entity = s_g16 (r);
    return id;
}

static void s_put_type (s_w_t *w, const gw_type_t *t)
{
    s_u8 (w, t->kind);
    s_u8 (w, t->domain);
    s_u16 (w, t->country);
    s_u8 (w, t->category);
    s_u8 (w, t->subcategory);
    s_u8 (w, t->specific);
    s_u8 (w, t->extra);
}

static gw_type_t s_get_type (s_r_t *r)
{
    gw_type_t t;
    t.kind = s_g8 (r);
    t.domain = s_g8 (r);
    t.country = s_g16 (r);
    t.category = s_g8 (r);
    t.subcategory = s_g8 (r);
    t.specific = s_g8 (r);
    t.extra = s_g8 (r);
    return t;
}

static bool s_version_ok (uint8_t v)
{
    return v >= GW_VERSION_MIN && v <= GW_VERSION_MAX;
}

/* ---- encode -------------------------------------------------------------------------------- */

size_t gw_pdu_encode_espdu (const gw_espdu_t *pdu, uint8_t *buf, size_t cap)
{
    if (!s_version_ok (pdu->hdr.version) || pdu->n_params != 0)
        return 0;
    s_w_t w = {buf, 0, cap, false};
    s_put_header (&w, &pdu->hdr, GW_PDU_ENTITY_STATE, GW_FAMILY_ENTITY_INFORMATION, GW_ESPDU_LEN);
    s_put_id (&w, pdu->id);
    s_u8 (&w, pdu->force);
    s_u8 (&w, 0); // no variable parameter records
    s_put_type (&w, &pdu->type);
    s_put_type (&w, &pdu->alt_type);
    for (int i = 0; i < 3; i++)
        s_f32 (&w, pdu->velocity[i]);
    for (int i = 0; i < 3; i++)
        s_f64 (&w, pdu->location[i]);
    for (int i = 0; i < 3; i++)
        s_f32 (&w, pdu->orientation[i]);
    s_u32 (&w, pdu->appearance);
    s_u8 (&w, pdu->dr_algorithm);
    s_bytes (&w, pdu->dr_other, sizeof pdu->dr_other);
    for (int i = 0; i < 3; i++)
        s_f32 (&w, pdu->acceleration[i]);
    for (int i = 0; i < 3; i++)
        s_f32 (&w, pdu->angular_velocity[i]);
    s_u8 (&w, pdu->marking_charset);
    // Eleven characters, NUL-padded, never a terminator of our own beyond them.
    size_t n = strnlen (pdu->marking, GW_MARKING_LEN);
    s_bytes (&w, pdu->marking, n);
    s_zeros (&w, GW_MARKING_LEN - n);
    s_u32 (&w, pdu->capabilities);
    return w.overflow || w.len != GW_ESPDU_LEN ? 0 : w.len;
}

/* Bytes a variable datum's value takes on the wire: its bits padded to 64. */
static size_t s_var_bytes (uint32_t length_bits)
{
    return ((size_t)length_bits + 63) / 64 * 8;
}

size_t gw_pdu_encode_action (const gw_action_t *pdu, uint8_t *buf, size_t cap)
{
    if (!s_version_ok (pdu->hdr.version) || pdu->n_fixed > GW_DATUM_MAX ||
        pdu->n_var > GW_DATUM_MAX ||
        (pdu->hdr.type != GW_PDU_ACTION_REQUEST && pdu->hdr.type != GW_PDU_ACTION_RESPONSE))
        return 0;
    size_t length = GW_ACTION_BASE_LEN + 8 * (size_t)pdu->n_fixed;
    for (uint32_t i = 0; i < pdu->n_var; i++)
        length += 8 + s_var_bytes (pdu->var[i].length_bits);
    if (length > GW_PDU_MAX || length > cap)
        return 0;
    s_w_t w = {buf, 0, cap, false};
    s_put_header (&w, &pdu->hdr, pdu->hdr.type, GW_FAMILY_SIMULATION_MANAGEMENT, length);
    s_put_id (&w, pdu->originator);
    s_put_id (&w, pdu->receiver);
    s_u32 (&w, pdu->request_id);
    s_u32 (&w, pdu->action_or_status);
    s_u32 (&w, pdu->n_fixed);
    s_u32 (&w, pdu->n_var);
    for (uint32_t i = 0; i < pdu->n_fixed; i++) {
        s_u32 (&w, pdu->fixed[i].id);
        s_u32 (&w, pdu->fixed[i].value);
    }
    for (uint32_t i = 0; i < pdu->n_var; i++) {
        const gw_var_datum_t *d = &pdu->var[i];
        size_t used = ((size_t)d->length_bits + 7) / 8;
        s_u32 (&w, d->id);
        s_u32 (&w, d->length_bits);
        s_bytes (&w, d->value, used);
        s_zeros (&w, s_var_bytes (d->length_bits) - used);
    }
    return w.overflow || w.len != length ? 0 : w.len;
}

/* ---- decode -------------------------------------------------------------------------------- */

static int s_fail (const char **ret_why, const char *why)
{
    if (ret_why)
        *ret_why = why;
    return -EPROTO;
}

int gw_pdu_decode_header (const uint8_t *buf, size_t len, gw_header_t *ret, const char **ret_why)
{
    if (len < GW_HEADER_LEN)
        return s_fail (ret_why, "shorter than a PDU header (12 bytes)");
    s_r_t r = {buf, len, 0};
    gw_header_t h;
    h.version = s_g8 (&r);
    h.exercise = s_g8 (&r);
    h.type = s_g8 (&r);
    h.family = s_g8 (&r);
    h.timestamp = s_g32 (&r);
    h.length = s_g16 (&r);
    uint8_t status = s_g8 (&r);
    if (!s_version_ok (h.version))
        return s_fail (ret_why, "unknown protocol version (known: 3 to 7)");
    if (h.length != len)
        return s_fail (ret_why, "length field does not match the bytes that arrived");
    h.status = h.version >= 7 ? status : 0;
    *ret = h;
    return 0;
}

int gw_pdu_decode_espdu (const uint8_t *buf, size_t len, gw_espdu_t *ret, const char **ret_why)
{
    gw_header_t h;
    int rc = gw_pdu_decode_header (buf, len, &h, ret_why);
    if (rc < 0)
        return rc;
    if (h.type != GW_PDU_ENTITY_STATE)
        return s_fail (ret_why, "not an Entity State PDU");
    if (len < GW_ESPDU_LEN)
        return s_fail (ret_why, "Entity State PDU shorter than 144 bytes");
    s_r_t r = {buf, len, GW_HEADER_LEN};
    gw_espdu_t p;
    memset (&p, 0, sizeof p);
    p.hdr = h;
    p.id = s_get_id (&r);
    p.force = s_g8 (&r);
    p.n_params = s_g8 (&r);
    if ((size_t)GW_ESPDU_LEN + (size_t)p.n_params * GW_VARPARAM_LEN != len)
        return s_fail (ret_why, "variable parameter count does not fit the length");
    p.type = s_get_type (&r);
    p.alt_type = s_get_type (&r);
    for (int i = 0; i < 3; i++)
        p.velocity[i] = s_gf32 (&r);
    for (int i = 0; i < 3; i++)
        p.location[i] = s_gf64 (&r);
    for (int i = 0; i < 3; i++)
        p.orientation[i] = s_gf32 (&r);
    p.appearance = s_g32 (&r);
    p.dr_algorithm = s_g8 (&r);
    memcpy (p.dr_other, s_take (&r, sizeof p.dr_other), sizeof p.dr_other);
    for (int i = 0; i < 3; i++)
        p.acceleration[i] = s_gf32 (&r);
    for (int i = 0; i < 3; i++)
        p.angular_velocity[i] = s_gf32 (&r);
    p.marking_charset = s_g8 (&r);
    memcpy (p.marking, s_take (&r, GW_MARKING_LEN), GW_MARKING_LEN);
    p.marking[GW_MARKING_LEN] = '\0';
    p.capabilities = s_g32 (&r);
    for (int i = 0; i < 3; i++)
        if (!isfinite (p.location[i]) || !isfinite (p.velocity[i]) ||
            !isfinite (p.orientation[i]) || !isfinite (p.acceleration[i]) ||
            !isfinite (p.angular_velocity[i]))
            return s_fail (ret_why, "a location, velocity or angle that is not a finite number");
    *ret = p;
    return 0;
}

int gw_pdu_decode_action (const uint8_t *buf, size_t len, gw_action_t *ret, const char **ret_why)
{
    gw_header_t h;
    int rc = gw_pdu_decode_header (buf, len, &h, ret_why);
    if (rc < 0)
        return rc;
    if (h.type != GW_PDU_ACTION_REQUEST && h.type != GW_PDU_ACTION_RESPONSE)
        return s_fail (ret_why, "not an Action Request or Action Response PDU");
    if (len < GW_ACTION_BASE_LEN)
        return s_fail (ret_why, "Action PDU shorter than 40 bytes");
    s_r_t r = {buf, len, GW_HEADER_LEN};
    gw_id_t orig = s_get_id (&r), recv = s_get_id (&r);
    uint32_t request_id = s_g32 (&r), what = s_g32 (&r);
    uint32_t n_fixed = s_g32 (&r), n_var = s_g32 (&r);
    // Counts and lengths against the PDU's length first; *ret is written after.
    if (n_fixed > (len - GW_ACTION_BASE_LEN) / 8)
        return s_fail (ret_why, "fixed datum count does not fit the length");
    if (n_fixed > GW_DATUM_MAX || n_var > GW_DATUM_MAX)
        return s_fail (ret_why, "more than 256 datum records");
    size_t records = r.at;
    r.at += 8 * (size_t)n_fixed;
    for (uint32_t i = 0; i < n_var; i++) {
        if (r.len - r.at < 8)
            return s_fail (ret_why, "variable datum count does not fit the length");
        (void)s_g32 (&r);
        size_t bytes = s_var_bytes (s_g32 (&r));
        if (r.len - r.at < bytes)
            return s_fail (ret_why, "a variable datum's length runs past the PDU");
        r.at += bytes;
    }
    if (r.at != len)
        return s_fail (ret_why, "bytes left over after the datum records");
    r.at = records;
    for (uint32_t i = 0; i < n_fixed; i++) {
        ret->fixed[i].id = s_g32 (&r);
        ret->fixed[i].value = s_g32 (&r);
    }
    for (uint32_t i = 0; i < n_var; i++) {
        ret->var[i].id = s_g32 (&r);
        ret->var[i].length_bits = s_g32 (&r);
        ret->var[i].value = s_take (&r, s_var_bytes (ret->var[i].length_bits));
    }
    ret->hdr = h;
    ret->originator = orig;
    ret->receiver = recv;
    ret->request_id = request_id;
    ret->action_or_status = what;
    ret->n_fixed = n_fixed;
    ret->n_var = n_var;
    return 0;
}

int gw_pdu_walk (const uint8_t *dgram, size_t len, gw_pdu_fn *fn, void *arg, const char **ret_why)
{
    size_t at = 0;
    int count = 0;
    while (at < len) {
        if (len - at < GW_HEADER_LEN)
            return s_fail (ret_why, "bytes after the last PDU that are not a PDU header");
        uint16_t plen = (uint16_t)(dgram[at + 8] << 8 | dgram[at + 9]);
        if (plen < GW_HEADER_LEN)
            return s_fail (ret_why, "length field shorter than a PDU header");
        if (plen > len - at)
            return s_fail (ret_why, "length field longer than the bytes that arrived");
        fn (arg, dgram + at, plen);
        at += plen;
        count++;
    }
    return count;
}

void gw_pdu_put_f64x3 (uint8_t out[24], const double v[3])
{
    s_w_t w = {out, 0, 24, false};
    for (int i = 0; i < 3; i++)
        s_f64 (&w, v[i]);
}

void gw_pdu_get_f64x3 (const uint8_t in[24], double ret_v[3])
{
    s_r_t r = {in, 24, 0};
    for (int i = 0; i < 3; i++)
        ret_v[i] = s_gf64 (&r);
}

bool gw_pdu_id_eq (gw_id_t a, gw_id_t b)
{
    return a.site == b.site && a.application == b.application && a.entity == b.entity;
}
