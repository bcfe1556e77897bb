/* cgs_ckpt — the common checkpoint frame, its writer and its reader (see cgs_ckpt.h). */
#include "cgs_ckpt.h"
#include "cgs_util.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ---- little-endian bytes ------------------------------------------------------------- */

static void s_le (uint8_t *p, uint64_t v, int bytes)
{
    for (int i = 0; i < bytes; i++)
        p[i] = (uint8_t)(v >> (8 * i));
}

static uint64_t s_from_le (const uint8_t *p, int bytes)
{
    uint64_t v = 0;
    for (int i = 0; i < bytes; i++)
        v |= (uint64_t)p[i] << (8 * i);
    return v;
}

/* ---- writer -------------------------------------------------------------------------- */

/* Room for n more bytes; false (and failed) when there is none. */
static bool s_room (cgs_ckpt_writer_t *w, size_t n)
{
    if (w->failed)
        return false;
    if (n > SIZE_MAX - w->len || cgs_grow ((void **)&w->buf, &w->cap, w->len + n, 1) < 0) {
        w->failed = true;
        return false;
    }
    return true;
}

static void s_put (cgs_ckpt_writer_t *w, const void *data, size_t n)
{
    if (n == 0 || !s_room (w, n))
        return;
    memcpy (w->buf + w->len, data, n);
    w->len += n;
}

static void s_put_le (cgs_ckpt_writer_t *w, uint64_t v, int bytes)
{
    if (!s_room (w, (size_t)bytes))
        return;
    s_le (w->buf + w->len, v, bytes);
    w->len += (size_t)bytes;
}

void cgs_ckpt_writer_init (cgs_ckpt_writer_t *w, const char *magic, uint32_t version)
{
    *w = (cgs_ckpt_writer_t){0};
    s_put (w, magic, 4);
    s_put_le (w, version, 4);
    s_put_le (w, 0, 8); // the length, filled in by finish
}

void cgs_ckpt_put_u8 (cgs_ckpt_writer_t *w, uint8_t v)
{
    s_put_le (w, v, 1);
}

void cgs_ckpt_put_bool (cgs_ckpt_writer_t *w, bool v)
{
    s_put_le (w, v ? 1 : 0, 1);
}

void cgs_ckpt_put_u32 (cgs_ckpt_writer_t *w, uint32_t v)
{
    s_put_le (w, v, 4);
}

void cgs_ckpt_put_u64 (cgs_ckpt_writer_t *w, uint64_t v)
{
    s_put_le (w, v, 8);
}

void cgs_ckpt_put_f64 (cgs_ckpt_writer_t *w, double v)
{
    uint64_t u;
    memcpy (&u, &v, sizeof u);
    s_put_le (w, u, 8);
}

void cgs_ckpt_put_bytes (cgs_ckpt_writer_t *w, const void *data, size_t n)
{
    s_put_le (w, n, 8);
    s_put (w, data, n);
}

void cgs_ckpt_put_str (cgs_ckpt_writer_t *w, const char *s)
{
    size_t n = strlen (s);
    if (n > UINT32_MAX) {
        w->failed = true;
        return;
    }
    s_put_le (w, n, 4);
    s_put (w, s, n);
}

int cgs_ckpt_writer_finish (cgs_ckpt_writer_t *w, uint8_t **ret_buf, size_t *ret_len)
{
    if (!w->failed && w->len >= CGS_CKPT_HEAD) {
        size_t payload = w->len - CGS_CKPT_HEAD;
        uint32_t crc = cgs_crc32 (w->buf + CGS_CKPT_HEAD, payload);
        if (s_room (w, CGS_CKPT_TAIL)) {
            s_le (w->buf + 8, payload, 8);
            s_le (w->buf + w->len, crc, 4);
            *ret_buf = w->buf;
            *ret_len = w->len + CGS_CKPT_TAIL;
            *w = (cgs_ckpt_writer_t){0};
            return 0;
        }
    }
    cgs_ckpt_writer_fini (w);
    return -ENOMEM;
}

void cgs_ckpt_writer_fini (cgs_ckpt_writer_t *w)
{
    if (!w)
        return;
    free (w->buf);
    *w = (cgs_ckpt_writer_t){0};
}

/* ---- frame --------------------------------------------------------------------------- */

/* The 4 bytes at p as text when they are printable, else in hex. */
static void s_show (const uint8_t *p, size_t n, char *out, size_t size)
{
    bool text = n > 0;
    for (size_t i = 0; i < n; i++)
        text = text && p[i] >= 0x20 && p[i] < 0x7f && p[i] != '"';
    if (text) {
        snprintf (out, size, "\"%.*s\"", (int)n, (const char *)p);
        return;
    }
    size_t at = (size_t)snprintf (out, size, "0x");
    for (size_t i = 0; i < n && at < size; i++)
        at += (size_t)snprintf (out + at, size - at, "%02x", p[i]);
}

/* The header's checks shared by both opens: magic and version. */
static int s_head (const uint8_t *b, size_t len, const char *magic, uint32_t version,
                   const char *what, char *err, size_t errlen)
{
    size_t m = len < 4 ? len : 4;
    if (memcmp (b, magic, m) != 0) {
        char found[16];
        s_show (b, m, found, sizeof found);
        cgs_errf (err, errlen,
                  "not a %s: it begins %s, not \"%.4s\" (another kind of file, or one saved "
                  "before mscgs's common checkpoint format)",
                  what, found, magic);
        return -EPROTO;
    }
    if (len < 8) {
        cgs_errf (err, errlen, "a %s truncated to %zu bytes", what, len);
        return -EINVAL;
    }
    uint32_t v = (uint32_t)s_from_le (b + 4, 4);
    if (v != version) {
        cgs_errf (err, errlen,
                  "a %s saved by another version of mscgs (format %u; this one reads format %u)",
                  what, v, version);
        return -ENOTSUP;
    }
    return 0;
}

int cgs_ckpt_open (cgs_ckpt_reader_t *r, const void *buf, size_t len, const char *magic,
                   uint32_t version, const char *what, char *err, size_t errlen)
{
    const uint8_t *b = buf;
    if (!b || len == 0) {
        cgs_errf (err, errlen, "a %s of no bytes", what);
        return -EINVAL;
    }
    int rc = s_head (b, len, magic, version, what, err, errlen);
    if (rc < 0)
        return rc;
    if (len < CGS_CKPT_HEAD + CGS_CKPT_TAIL) {
        cgs_errf (err, errlen, "a %s truncated to %zu bytes", what, len);
        return -EINVAL;
    }
    uint64_t n = s_from_le (b + 8, 8);
    size_t have = len - CGS_CKPT_HEAD - CGS_CKPT_TAIL;
    if (n > have) {
        cgs_errf (err, errlen, "a %s truncated: %zu bytes of its %llu", what, len,
                  (unsigned long long)n + CGS_CKPT_HEAD + CGS_CKPT_TAIL);
        return -EINVAL;
    }
    if (n < have) {
        cgs_errf (err, errlen, "a %s with %zu bytes past its end", what, (size_t)(have - n));
        return -EINVAL;
    }
    uint32_t crc = (uint32_t)s_from_le (b + len - CGS_CKPT_TAIL, 4);
    if (crc != cgs_crc32 (b + CGS_CKPT_HEAD, have)) {
        cgs_errf (err, errlen, "a %s whose checksum does not match: damaged", what);
        return -EBADMSG;
    }
    *r = (cgs_ckpt_reader_t){.p = b + CGS_CKPT_HEAD, .len = have};
    return 0;
}

int cgs_ckpt_open_unchecked (cgs_ckpt_reader_t *r, const void *buf, size_t len, const char *magic,
                             uint32_t version)
{
    const uint8_t *b = buf;
    if (!b || len == 0)
        return -EINVAL;
    int rc = s_head (b, len, magic, version, "", NULL, 0);
    if (rc < 0)
        return rc;
    if (len < CGS_CKPT_HEAD)
        return -EINVAL;
    *r = (cgs_ckpt_reader_t){.p = b + CGS_CKPT_HEAD, .len = len - CGS_CKPT_HEAD};
    return 0;
}

/* ---- reader -------------------------------------------------------------------------- */

/* The next n bytes, or NULL (and failed) when fewer are left. */
static const uint8_t *s_take (cgs_ckpt_reader_t *r, size_t n)
{
    if (r->failed || n > r->len - r->off) {
        r->failed = true;
        return NULL;
    }
    const uint8_t *p = r->p + r->off;
    r->off += n;
    return p;
}

static uint64_t s_get_le (cgs_ckpt_reader_t *r, int bytes)
{
    const uint8_t *p = s_take (r, (size_t)bytes);
    return p ? s_from_le (p, bytes) : 0;
}

uint8_t cgs_ckpt_get_u8 (cgs_ckpt_reader_t *r)
{
    return (uint8_t)s_get_le (r, 1);
}

bool cgs_ckpt_get_bool (cgs_ckpt_reader_t *r)
{
    uint8_t v = cgs_ckpt_get_u8 (r);
    if (v > 1)
        r->failed = true;
    return v == 1;
}

uint32_t cgs_ckpt_get_u32 (cgs_ckpt_reader_t *r)
{
    return (uint32_t)s_get_le (r, 4);
}

uint64_t cgs_ckpt_get_u64 (cgs_ckpt_reader_t *r)
{
    return s_get_le (r, 8);
}

double cgs_ckpt_get_f64 (cgs_ckpt_reader_t *r)
{
    uint64_t u = s_get_le (r, 8);
    double v;
    memcpy (&v, &u, sizeof v);
    return v;
}

double cgs_ckpt_get_finite (cgs_ckpt_reader_t *r)
{
    double v = cgs_ckpt_get_f64 (r);
    if (!isfinite (v)) {
        r->failed = true;
        return 0;
    }
    return v;
}

const uint8_t *cgs_ckpt_get_bytes (cgs_ckpt_reader_t *r, size_t *ret_len)
{
    uint64_t n = s_get_le (r, 8);
    const uint8_t *p = n <= r->len - r->off ? s_take (r, (size_t)n) : NULL;
    if (!p)
        r->failed = true;
    *ret_len = p ? (size_t)n : 0;
    return p;
}

void cgs_ckpt_get_str (cgs_ckpt_reader_t *r, char *dst, size_t size)
{
    uint32_t n = cgs_ckpt_get_u32 (r);
    const uint8_t *p = n < size ? s_take (r, n) : NULL;
    if (!p || memchr (p, '\0', n)) {
        r->failed = true;
        if (size)
            dst[0] = '\0';
        return;
    }
    memcpy (dst, p, n);
    dst[n] = '\0';
}

void cgs_ckpt_fail (cgs_ckpt_reader_t *r)
{
    r->failed = true;
}

bool cgs_ckpt_ok (const cgs_ckpt_reader_t *r)
{
    return !r->failed;
}

size_t cgs_ckpt_left (const cgs_ckpt_reader_t *r)
{
    return r->len - r->off;
}

int cgs_ckpt_end (const cgs_ckpt_reader_t *r, const char *what, char *err, size_t errlen)
{
    if (r->failed) {
        cgs_errf (err, errlen, "a %s that does not decode (a field past its end or out of range)",
                  what);
        return -EINVAL;
    }
    if (r->off != r->len) {
        cgs_errf (err, errlen, "a %s with %zu bytes past its fields", what, r->len - r->off);
        return -EINVAL;
    }
    return 0;
}
