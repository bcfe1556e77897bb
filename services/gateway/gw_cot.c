/* gw_cot — Cursor on Target events as XML and as TAK protocol version 1.
 * Numbers are written and read in the C locale (no program here calls
 * setlocale). libxml2 parses; protobuf-c packs and unpacks (tak.pb-c.h,
 * generated from proto/tak.proto), and stays inside this file. */
#include "gw_cot.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <libxml/parser.h>
#include <libxml/tree.h>

#include "tak.pb-c.h"

#define S_METRES_MAX 1e12               // larger metres or m/s are refused
#define S_TIME_MIN   (-62135596800.0)   // 0001-01-01T00:00:00Z
#define S_TIME_MAX   (253402300800.0)   // 10000-01-01T00:00:00Z, excluded
#define S_MS_MAX     253402300799999ull // 9999-12-31T23:59:59.999Z in ms
#define S_ATTR_MAX   128                // a number or time attribute, bytes

/* ---- reasons ------------------------------------------------------------------------------- */

static int s_fail (char *why, size_t whylen, const char *fmt, ...)
    __attribute__ ((format (printf, 3, 4)));

static int s_fail (char *why, size_t whylen, const char *fmt, ...)
{
    if (why && whylen) {
        va_list ap;
        va_start (ap, fmt);
        vsnprintf (why, whylen, fmt, ap);
        va_end (ap);
    }
    return -EINVAL;
}

/* ---- text ---------------------------------------------------------------------------------- */

/* Whether s is UTF-8 that XML 1.0 can carry: no overlong forms, no
 * surrogates, nothing past U+10FFFF, no U+FFFE or U+FFFF, and no control
 * characters (tab, line feed and carriage return only where ctl allows). */
static bool s_text_ok (const char *s, bool ctl)
{
    const unsigned char *p = (const unsigned char *)s;
    while (*p) {
        unsigned c = *p;
        if (c < 0x80) {
            if (c < 0x20 && !(ctl && (c == '\t' || c == '\n' || c == '\r')))
                return false;
            p++;
            continue;
        }
        int n;
        unsigned cp;
        if (c >= 0xc2 && c <= 0xdf)
            n = 1, cp = c & 0x1f;
        else if (c >= 0xe0 && c <= 0xef)
            n = 2, cp = c & 0x0f;
        else if (c >= 0xf0 && c <= 0xf4)
            n = 3, cp = c & 0x07;
        else
            return false;
        for (int i = 1; i <= n; i++) {
            if ((p[i] & 0xc0) != 0x80)
                return false;
            cp = cp << 6 | (p[i] & 0x3f);
        }
        if ((n == 2 && cp < 0x800) || (n == 3 && (cp < 0x10000 || cp > 0x10ffff)) ||
            (cp >= 0xd800 && cp <= 0xdfff) || cp == 0xfffe || cp == 0xffff)
            return false;
        p += n + 1;
    }
    return true;
}

/* NUL-terminated within its array. */
static bool s_terminated (const char *s, size_t cap)
{
    return memchr (s, '\0', cap) != NULL;
}

/* A word character of the schema's patterns (XML Schema's \w, ASCII only):
 * letters, digits and the symbols; not '_' or '-', which are punctuation. */
static bool s_word (char c)
{
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
           (c && strchr ("$+<=>^`|~", c));
}

/* type: \w+(-\w+)*(;[^;]*)? */
static bool s_type_ok (const char *s)
{
    const char *p = s;
    for (;;) {
        if (!s_word (*p))
            return false;
        while (s_word (*p))
            p++;
        if (*p != '-')
            break;
        p++;
    }
    if (*p == ';')
        return strchr (p + 1, ';') == NULL && s_text_ok (p + 1, false);
    return *p == '\0';
}

/* how: \w(-\w+)* */
static bool s_how_ok (const char *s)
{
    const char *p = s;
    if (!s_word (*p++))
        return false;
    while (*p == '-') {
        p++;
        if (!s_word (*p))
            return false;
        while (s_word (*p))
            p++;
    }
    return *p == '\0';
}

/* Copy src into dst of cap bytes, cut at a character boundary when longer. */
static void s_copy_cut (char *dst, size_t cap, const char *src)
{
    size_t n = strlen (src);
    if (n >= cap) {
        n = cap - 1;
        while (n > 0 && ((unsigned char)src[n] & 0xc0) == 0x80)
            n--; // src[n] is a continuation byte: the character starts before it
    }
    memcpy (dst, src, n);
    dst[n] = '\0';
}

/* Copy src into dst of cap bytes; false when it does not fit. */
static bool s_copy (char *dst, size_t cap, const char *src)
{
    size_t n = strlen (src);
    if (n >= cap)
        return false;
    memcpy (dst, src, n + 1);
    return true;
}

static bool s_space (char c)
{
    return c == ' ' || c == '\t' || c == '\n' || c == '\r';
}

/* A decimal number, XML white space around it allowed: [+-]digits[.digits]
 * with an optional exponent. No hexadecimal, no inf or nan. */
static bool s_number (const char *s, double *ret)
{
    const char *p = s;
    while (s_space (*p))
        p++;
    const char *start = p;
    if (*p == '+' || *p == '-')
        p++;
    size_t digits = 0;
    while (*p >= '0' && *p <= '9')
        p++, digits++;
    if (*p == '.') {
        p++;
        while (*p >= '0' && *p <= '9')
            p++, digits++;
    }
    if (!digits)
        return false;
    if (*p == 'e' || *p == 'E') {
        p++;
        if (*p == '+' || *p == '-')
            p++;
        if (!(*p >= '0' && *p <= '9'))
            return false;
        while (*p >= '0' && *p <= '9')
            p++;
    }
    const char *end = p;
    while (s_space (*p))
        p++;
    if (*p)
        return false;
    char tmp[S_ATTR_MAX];
    size_t n = (size_t)(end - start);
    if (n >= sizeof tmp)
        return false;
    memcpy (tmp, start, n);
    tmp[n] = '\0';
    double v = strtod (tmp, NULL);
    if (!isfinite (v))
        return false;
    *ret = v;
    return true;
}

/* A decimal integer an ARGB colour can be: -2^31 to 2^32 - 1. */
static bool s_color_ok (const char *s)
{
    const char *p = s[0] == '-' ? s + 1 : s;
    size_t n = strlen (p);
    if (n == 0 || n > 10 || strspn (p, "0123456789") != n)
        return false;
    long long v = strtoll (s, NULL, 10);
    return v >= -2147483648ll && v <= 4294967295ll;
}

/* ---- time ---------------------------------------------------------------------------------- */

/* Days from 1970-01-01 to y-m-d of the proleptic Gregorian calendar
 * (H. Hinnant's days_from_civil). */
static long long s_days_from_civil (long long y, unsigned m, unsigned d)
{
    y -= m <= 2;
    long long era = (y >= 0 ? y : y - 399) / 400;
    unsigned yoe = (unsigned)(y - era * 400);
    unsigned doy = (153 * (m > 2 ? m - 3 : m + 9) + 2) / 5 + d - 1;
    unsigned doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
    return era * 146097 + (long long)doe - 719468;
}

/* The inverse: y-m-d of a day count from 1970-01-01. */
static void s_civil_from_days (long long z, long long *y, unsigned *m, unsigned *d)
{
    z += 719468;
    long long era = (z >= 0 ? z : z - 146096) / 146097;
    unsigned doe = (unsigned)(z - era * 146097);
    unsigned yoe = (doe - doe / 1460 + doe / 36524 - doe / 146096) / 365;
    unsigned doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    unsigned mp = (5 * doy + 2) / 153;
    *d = doy - (153 * mp + 2) / 5 + 1;
    *m = mp < 10 ? mp + 3 : mp - 9;
    *y = (long long)yoe + era * 400 + (*m <= 2);
}

static bool s_time_ok (double t)
{
    return isfinite (t) && t >= S_TIME_MIN && t < S_TIME_MAX - 0.0005;
}

/* Reads n digits at *p into *ret and steps past them; false (and *p left
 * where the first non-digit is, never past the NUL) when there are fewer. */
static bool s_digits (const char **p, int n, int *ret)
{
    int v = 0;
    for (int i = 0; i < n; i++) {
        char c = (*p)[0];
        if (c < '0' || c > '9')
            return false;
        v = v * 10 + (c - '0');
        (*p)++;
    }
    *ret = v;
    return true;
}

/* Steps past the character c at *p; false when another is there. */
static bool s_char (const char **p, char c)
{
    if (**p != c)
        return false;
    (*p)++;
    return true;
}

int gw_cot_parse_time (const char *iso, double *ret_s)
{
    if (!iso)
        return -EINVAL;
    const char *p = iso;
    int y, mo, d, h, mi, s;
    if (!s_digits (&p, 4, &y) || !s_char (&p, '-') || !s_digits (&p, 2, &mo) || !s_char (&p, '-') ||
        !s_digits (&p, 2, &d) || !s_char (&p, 'T') || !s_digits (&p, 2, &h) || !s_char (&p, ':') ||
        !s_digits (&p, 2, &mi) || !s_char (&p, ':') || !s_digits (&p, 2, &s))
        return -EINVAL;
    static const int mdays[12] = {31, 28, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31};
    bool leap = (y % 4 == 0 && y % 100 != 0) || y % 400 == 0;
    if (y < 1 || mo < 1 || mo > 12 || d < 1 || d > mdays[mo - 1] + (mo == 2 && leap) || h > 23 ||
        mi > 59 || s > 59)
        return -EINVAL;
    double frac = 0, scale = 0.1;
    if (s_char (&p, '.')) {
        if (!(*p >= '0' && *p <= '9'))
            return -EINVAL;
        for (; *p >= '0' && *p <= '9'; p++, scale /= 10)
            frac += (*p - '0') * scale;
    }
    int offset_s = 0;
    if (*p == '+' || *p == '-') {
        int sign = *p++ == '-' ? -1 : 1, oh, om;
        if (!s_digits (&p, 2, &oh) || !s_char (&p, ':') || !s_digits (&p, 2, &om) || oh > 14 ||
            om > 59)
            return -EINVAL;
        offset_s = sign * (oh * 3600 + om * 60);
    } else if (!s_char (&p, 'Z')) {
        return -EINVAL; // no time zone: CoT times are UTC, with Z
    }
    if (*p)
        return -EINVAL;
    long long days = s_days_from_civil (y, (unsigned)mo, (unsigned)d);
    long long whole = days * 86400 + h * 3600 + mi * 60 + s - offset_s;
    *ret_s = (double)whole + frac;
    return 0;
}

void gw_cot_format_time (double t_s, char *buf, size_t len)
{
    if (!buf || !len)
        return;
    buf[0] = '\0';
    if (!s_time_ok (t_s))
        return;
    long long ms = llround (t_s * 1000.0);
    long long days = ms >= 0 ? ms / 86400000 : -((-ms + 86399999) / 86400000);
    long long in_day = ms - days * 86400000;
    long long y;
    unsigned m, d;
    s_civil_from_days (days, &y, &m, &d);
    snprintf (buf, len, "%04lld-%02u-%02uT%02lld:%02lld:%02lld.%03lldZ", y, m, d, in_day / 3600000,
              in_day / 60000 % 60, in_day / 1000 % 60, in_day % 1000);
}

/* ---- the event's rules --------------------------------------------------------------------- */

static bool s_metres_ok (double v)
{
    return isfinite (v) && fabs (v) <= S_METRES_MAX;
}

static bool s_point_ok (const gw_cot_point_t *p)
{
    return isfinite (p->lat_deg) && isfinite (p->lon_deg) && fabs (p->lat_deg) <= 90 &&
           fabs (p->lon_deg) <= 180 && s_metres_ok (p->hae_m);
}

/* Whether e is an event CoT allows, with a reason when not. */
static int s_check (const gw_cot_event_t *e, char *why, size_t whylen)
{
    if (!s_terminated (e->uid, sizeof e->uid) || !s_terminated (e->type, sizeof e->type) ||
        !s_terminated (e->how, sizeof e->how) || !s_terminated (e->opex, sizeof e->opex) ||
        !s_terminated (e->callsign, sizeof e->callsign) ||
        !s_terminated (e->remarks, sizeof e->remarks) ||
        !s_terminated (e->stroke_color, sizeof e->stroke_color) ||
        !s_terminated (e->dest_uid, sizeof e->dest_uid) ||
        !s_terminated (e->dest_callsign, sizeof e->dest_callsign))
        return s_fail (why, whylen, "a text field is not NUL-terminated");
    if (!e->uid[0] || !s_text_ok (e->uid, false))
        return s_fail (why, whylen, "uid is empty, not UTF-8, or has a control character");
    if (!s_type_ok (e->type))
        return s_fail (why, whylen, "type '%s' is not of the form a-f-G[;text] (\\w+(-\\w+)*)",
                       e->type);
    if (!s_how_ok (e->how))
        return s_fail (why, whylen, "how '%s' is not of the form m-g (\\w(-\\w+)*)", e->how);
    if (!s_text_ok (e->opex, false))
        return s_fail (why, whylen, "opex is not UTF-8 or has a control character");
    if (!s_time_ok (e->time_s) || !s_time_ok (e->start_s) || !s_time_ok (e->stale_s))
        return s_fail (why, whylen, "time, start or stale is not finite or outside years 1-9999");
    if (!isfinite (e->point.lat_deg) || fabs (e->point.lat_deg) > 90)
        return s_fail (why, whylen, "point lat %g is outside [-90, 90]", e->point.lat_deg);
    if (!isfinite (e->point.lon_deg) || fabs (e->point.lon_deg) > 180)
        return s_fail (why, whylen, "point lon %g is outside [-180, 180]", e->point.lon_deg);
    if (!s_metres_ok (e->point.hae_m) || !s_metres_ok (e->ce_m) || !s_metres_ok (e->le_m))
        return s_fail (why, whylen, "point hae, ce or le is not finite or beyond 1e12 m");
    if (e->ce_m < 0 || e->le_m < 0)
        return s_fail (why, whylen, "point ce %g or le %g is negative", e->ce_m, e->le_m);
    if (!s_text_ok (e->callsign, true) || !s_text_ok (e->remarks, true))
        return s_fail (why, whylen, "callsign or remarks is not UTF-8 or has a control character");
    if (e->has_track && (!s_metres_ok (e->course_deg) || !s_metres_ok (e->speed_mps)))
        return s_fail (why, whylen, "track course or speed is not finite");
    if (e->has_sensor &&
        (!s_metres_ok (e->sensor_azimuth_deg) || !s_metres_ok (e->sensor_elevation_deg) ||
         !s_metres_ok (e->sensor_fov_deg) || !s_metres_ok (e->sensor_vfov_deg) ||
         !s_metres_ok (e->sensor_range_m)))
        return s_fail (why, whylen, "a sensor value is not finite");
    if (e->n_links > GW_COT_MAX_LINKS)
        return s_fail (why, whylen, "%zu link points (at most %d)", e->n_links, GW_COT_MAX_LINKS);
    for (size_t i = 0; i < e->n_links; i++)
        if (!s_point_ok (&e->links[i]))
            return s_fail (why, whylen, "link point %zu is out of range or not finite", i + 1);
    if (e->closed && e->n_links < 3)
        return s_fail (why, whylen, "a closed drawing needs 3 link points or more");
    if (e->stroke_color[0] && !s_color_ok (e->stroke_color))
        return s_fail (why, whylen, "strokeColor '%s' is not a decimal ARGB integer",
                       e->stroke_color);
    if (!s_text_ok (e->dest_uid, false) || !s_text_ok (e->dest_callsign, true))
        return s_fail (why, whylen, "dest uid or callsign is not UTF-8 or has a control character");
    return 0;
}

void gw_cot_event_init (gw_cot_event_t *e)
{
    memset (e, 0, sizeof *e);
    e->ce_m = GW_COT_UNKNOWN_M;
    e->le_m = GW_COT_UNKNOWN_M;
}

/* ---- XML writer ---------------------------------------------------------------------------- */

typedef struct {
    char *p;
    size_t len, cap; // cap counts the NUL
    bool overflow;
} s_out_t;

static void s_put (s_out_t *o, const char *s, size_t n)
{
    if (o->overflow || o->cap - o->len <= n) {
        o->overflow = true;
        return;
    }
    memcpy (o->p + o->len, s, n);
    o->len += n;
    o->p[o->len] = '\0';
}

static void s_puts (s_out_t *o, const char *s)
{
    s_put (o, s, strlen (s));
}

/* Text escaped for an attribute value or element content: the five XML
 * specials, and tab, line feed and carriage return as character references
 * (a parser would turn them into spaces in an attribute). */
static void s_esc (s_out_t *o, const char *s)
{
    for (const char *p = s; *p; p++) {
        switch (*p) {
        case '&':
            s_puts (o, "&amp;");
            break;
        case '<':
            s_puts (o, "&lt;");
            break;
        case '>':
            s_puts (o, "&gt;");
            break;
        case '"':
            s_puts (o, "&quot;");
            break;
        case '\'':
            s_puts (o, "&apos;");
            break;
        case '\t':
            s_puts (o, "&#9;");
            break;
        case '\n':
            s_puts (o, "&#10;");
            break;
        case '\r':
            s_puts (o, "&#13;");
            break;
        default:
            s_put (o, p, 1);
        }
    }
}

/* v with `decimals` digits after the point, trailing zeros dropped but one
 * (9999999.0), and never "-0". An xs:decimal: no exponent. */
static void s_num (s_out_t *o, double v, int decimals, bool strip)
{
    char b[64];
    int n = snprintf (b, sizeof b, "%.*f", decimals, v);
    if (n < 0 || (size_t)n >= sizeof b) {
        o->overflow = true; // not reached: the values are bounded before
        return;
    }
    if (strip) {
        while (n > 2 && b[n - 1] == '0' && b[n - 2] != '.')
            b[--n] = '\0';
    }
    const char *s = b;
    if (b[0] == '-' && strspn (b + 1, "0.") == (size_t)n - 1)
        s = b + 1; // "-0.000" rounds a tiny negative: write it unsigned
    s_puts (o, s);
}

static void s_attr_text (s_out_t *o, const char *name, const char *v)
{
    s_puts (o, " ");
    s_puts (o, name);
    s_puts (o, "=\"");
    s_esc (o, v);
    s_puts (o, "\"");
}

static void s_attr_num (s_out_t *o, const char *name, double v, int decimals, bool strip)
{
    s_puts (o, " ");
    s_puts (o, name);
    s_puts (o, "=\"");
    s_num (o, v, decimals, strip);
    s_puts (o, "\"");
}

static void s_attr_time (s_out_t *o, const char *name, double t)
{
    char b[40];
    gw_cot_format_time (t, b, sizeof b);
    s_attr_text (o, name, b);
}

static void s_put_link (s_out_t *o, const gw_cot_point_t *p)
{
    s_puts (o, "<link point=\"");
    s_num (o, p->lat_deg, 7, false);
    s_puts (o, ",");
    s_num (o, p->lon_deg, 7, false);
    s_puts (o, ",");
    s_num (o, p->hae_m, 3, true);
    s_puts (o, "\"/>");
}

/* The detail's children; contact and track only when not typed (proto). */
static void s_put_detail (s_out_t *o, const gw_cot_event_t *e, bool typed)
{
    if (!typed && e->callsign[0]) {
        s_puts (o, "<contact");
        s_attr_text (o, "callsign", e->callsign);
        s_puts (o, "/>");
    }
    if (!typed && e->has_track) {
        s_puts (o, "<track");
        s_attr_num (o, "course", e->course_deg, 3, true);
        s_attr_num (o, "speed", e->speed_mps, 3, true);
        s_puts (o, "/>");
    }
    if (e->has_sensor) {
        s_puts (o, "<sensor");
        s_attr_num (o, "azimuth", e->sensor_azimuth_deg, 3, true);
        s_attr_num (o, "elevation", e->sensor_elevation_deg, 3, true);
        s_attr_num (o, "fov", e->sensor_fov_deg, 3, true);
        s_attr_num (o, "vfov", e->sensor_vfov_deg, 3, true);
        s_attr_num (o, "range", e->sensor_range_m, 3, true);
        s_puts (o, "/>");
    }
    for (size_t i = 0; i < e->n_links; i++)
        s_put_link (o, &e->links[i]);
    // A closed shape repeats its first vertex (TAK and node-cot read a
    // polygon so); a u-d-r rectangle is its four corners.
    if (e->closed && e->n_links && strcmp (e->type, "u-d-r") != 0)
        s_put_link (o, &e->links[0]);
    if (e->stroke_color[0]) {
        s_puts (o, "<strokeColor");
        s_attr_text (o, "value", e->stroke_color);
        s_puts (o, "/>");
    }
    if (e->dest_uid[0] || e->dest_callsign[0]) {
        s_puts (o, "<marti><dest");
        if (e->dest_uid[0])
            s_attr_text (o, "uid", e->dest_uid);
        if (e->dest_callsign[0])
            s_attr_text (o, "callsign", e->dest_callsign);
        s_puts (o, "/></marti>");
    }
    if (e->remarks[0]) {
        s_puts (o, "<remarks>");
        s_esc (o, e->remarks);
        s_puts (o, "</remarks>");
    }
}

/* Whether the detail has anything to say (with contact and track unless typed). */
static bool s_has_detail (const gw_cot_event_t *e, bool typed)
{
    return (!typed && (e->callsign[0] || e->has_track)) || e->has_sensor || e->n_links ||
           e->stroke_color[0] || e->dest_uid[0] || e->dest_callsign[0] || e->remarks[0];
}

size_t gw_cot_encode_xml (const gw_cot_event_t *e, char *buf, size_t cap)
{
    if (!e || !buf || cap == 0 || s_check (e, NULL, 0) < 0)
        return 0;
    s_out_t o = {buf, 0, cap, false};
    buf[0] = '\0';
    // The declaration, then a newline, as TAK's stream of XML events has it.
    s_puts (&o, "<?xml version=\"1.0\" encoding=\"UTF-8\" standalone=\"yes\"?>\n");
    s_puts (&o, "<event version=\"2.0\"");
    s_attr_text (&o, "uid", e->uid);
    s_attr_text (&o, "type", e->type);
    s_attr_text (&o, "how", e->how);
    s_attr_time (&o, "time", e->time_s);
    s_attr_time (&o, "start", e->start_s);
    s_attr_time (&o, "stale", e->stale_s);
    if (e->opex[0])
        s_attr_text (&o, "opex", e->opex);
    s_puts (&o, "><point");
    s_attr_num (&o, "lat", e->point.lat_deg, 7, false);
    s_attr_num (&o, "lon", e->point.lon_deg, 7, false);
    s_attr_num (&o, "hae", e->point.hae_m, 3, true);
    s_attr_num (&o, "ce", e->ce_m, 3, true);
    s_attr_num (&o, "le", e->le_m, 3, true);
    s_puts (&o, "/>");
    if (s_has_detail (e, false)) {
        s_puts (&o, "<detail>");
        s_put_detail (&o, e, false);
        s_puts (&o, "</detail>");
    }
    s_puts (&o, "</event>");
    if (o.overflow) {
        buf[0] = '\0';
        return 0;
    }
    return o.len;
}

/* ---- TAK protocol out ---------------------------------------------------------------------- */

size_t gw_cot_encode_proto (const gw_cot_event_t *e, uint8_t *buf, size_t cap)
{
    if (!e || !buf || s_check (e, NULL, 0) < 0)
        return 0;
    // Times are unsigned ms, and 0 is "missing": an event before
    // 1970-01-01T00:00:00.0005Z has no protobuf form.
    if (llround (e->time_s * 1000.0) < 1 || llround (e->start_s * 1000.0) < 1 ||
        llround (e->stale_s * 1000.0) < 1)
        return 0;
    char xml[GW_COT_ENCODED_MAX];
    s_out_t o = {xml, 0, sizeof xml, false};
    xml[0] = '\0';
    s_put_detail (&o, e, true);
    if (o.overflow)
        return 0;

    Tak__TakControl control = TAK__TAK_CONTROL__INIT;
    control.minprotoversion = GW_COT_TAK_VERSION;
    control.maxprotoversion = GW_COT_TAK_VERSION;
    Tak__Contact contact = TAK__CONTACT__INIT;
    contact.callsign = (char *)e->callsign;
    Tak__Track track = TAK__TRACK__INIT;
    track.course = e->course_deg;
    track.speed = e->speed_mps;
    Tak__Detail detail = TAK__DETAIL__INIT;
    detail.xmldetail = xml;
    detail.contact = e->callsign[0] ? &contact : NULL;
    detail.track = e->has_track ? &track : NULL;
    Tak__CotEvent ev = TAK__COT_EVENT__INIT;
    ev.type = (char *)e->type;
    ev.opex = (char *)e->opex;
    ev.uid = (char *)e->uid;
    ev.how = (char *)e->how;
    ev.sendtime = (uint64_t)llround (e->time_s * 1000.0);
    ev.starttime = (uint64_t)llround (e->start_s * 1000.0);
    ev.staletime = (uint64_t)llround (e->stale_s * 1000.0);
    ev.lat = e->point.lat_deg;
    ev.lon = e->point.lon_deg;
    ev.hae = e->point.hae_m;
    ev.ce = e->ce_m;
    ev.le = e->le_m;
    ev.detail = s_has_detail (e, false) ? &detail : NULL;
    Tak__TakMessage msg = TAK__TAK_MESSAGE__INIT;
    msg.takcontrol = &control;
    msg.cotevent = &ev;

    size_t n = tak__tak_message__get_packed_size (&msg);
    if (cap < GW_COT_MESH_HDR_LEN || cap - GW_COT_MESH_HDR_LEN < n)
        return 0;
    buf[0] = GW_COT_TAK_MAGIC;
    buf[1] = GW_COT_TAK_VERSION;
    buf[2] = GW_COT_TAK_MAGIC;
    size_t packed = tak__tak_message__pack (&msg, buf + GW_COT_MESH_HDR_LEN);
    return packed == n ? GW_COT_MESH_HDR_LEN + n : 0;
}

/* ---- XML reader ---------------------------------------------------------------------------- */

typedef struct {
    const char *where; // "" for an event, "xmlDetail " for a TAK message's detail
    long line_off;     // lines skipped before the text libxml2 saw
    char *why;
    size_t whylen;
} s_ctx_t;

static long s_line (const s_ctx_t *c, const xmlNode *n)
{
    return xmlGetLineNo (n) + c->line_off;
}

static bool s_is (const xmlNode *n, const char *name)
{
    return n->type == XML_ELEMENT_NODE && strcmp ((const char *)n->name, name) == 0;
}

/* An attribute's value into dst of cap bytes: 1, 0 when absent, -1 when
 * longer than cap - 1. */
static int s_attr (const xmlNode *n, const char *name, char *dst, size_t cap)
{
    xmlChar *v = xmlGetNoNsProp (n, (const xmlChar *)name);
    if (!v)
        return 0;
    bool fits = s_copy (dst, cap, (const char *)v);
    xmlFree (v);
    return fits ? 1 : -1;
}

/* A required identifier attribute of <event>. */
static int s_event_id (const s_ctx_t *c, const xmlNode *n, const char *name, char *dst, size_t cap)
{
    int rc = s_attr (n, name, dst, cap);
    if (rc == 0)
        return s_fail (c->why, c->whylen, "line %ld: <event> has no %s", s_line (c, n), name);
    if (rc < 0)
        return s_fail (c->why, c->whylen, "line %ld: <event> %s longer than %zu bytes",
                       s_line (c, n), name, cap - 1);
    return 0;
}

/* A number attribute: required (absent is an error) or optional (absent leaves *ret). */
static int s_attr_number (const s_ctx_t *c, const xmlNode *n, const char *name, bool required,
                          double *ret)
{
    char b[S_ATTR_MAX];
    int rc = s_attr (n, name, b, sizeof b);
    if (rc == 0 && !required)
        return 0;
    if (rc == 0)
        return s_fail (c->why, c->whylen, "%sline %ld: <%s> has no %s", c->where, s_line (c, n),
                       (const char *)n->name, name);
    if (rc < 0 || !s_number (b, ret))
        return s_fail (c->why, c->whylen, "%sline %ld: <%s> %s '%.40s' is not a finite number",
                       c->where, s_line (c, n), (const char *)n->name, name, rc < 0 ? "" : b);
    return 0;
}

static int s_attr_time_in (const s_ctx_t *c, const xmlNode *n, const char *name, double *ret)
{
    char b[S_ATTR_MAX];
    int rc = s_attr (n, name, b, sizeof b);
    if (rc == 0)
        return s_fail (c->why, c->whylen, "line %ld: <event> has no %s", s_line (c, n), name);
    if (rc < 0 || gw_cot_parse_time (b, ret) < 0 || !s_time_ok (*ret))
        return s_fail (c->why, c->whylen,
                       "line %ld: <event> %s '%.40s' is not a time like 2026-11-27T12:34:56.789Z",
                       s_line (c, n), name, rc < 0 ? "" : b);
    return 0;
}

/* "lat,lon[,hae]" */
static bool s_link_point (const char *s, gw_cot_point_t *ret)
{
    char b[S_ATTR_MAX];
    if (!s_copy (b, sizeof b, s))
        return false;
    double v[3] = {0, 0, 0};
    int k = 0;
    for (char *tok = b, *comma; k < 3; tok = comma + 1) {
        comma = strchr (tok, ',');
        if (comma)
            *comma = '\0';
        if (!s_number (tok, &v[k++]))
            return false;
        if (!comma)
            break;
        if (k == 3)
            return false; // a fourth component
    }
    if (k < 2)
        return false;
    gw_cot_point_t p = {v[0], v[1], v[2]};
    if (!s_point_ok (&p))
        return false;
    *ret = p;
    return true;
}

/* The <link> elements of a detail: vertices (one more than a drawing has,
 * for a closed one's repeated first), and the first uid of a link without a
 * point. */
#define S_LINKS_READ (GW_COT_MAX_LINKS + 1)
typedef struct {
    gw_cot_point_t pts[S_LINKS_READ];
    size_t n;
    char uid[96];
} s_links_t;

/* What one <detail> says, into e and l; *ret_contact and *ret_track say whether it
 * had those elements (a TAK message's typed fields yield to them). */
/* Whether a <link> names the event's parent (relation "p-p", "p-..."). */
static bool s_parent_link (const xmlNode *n)
{
    char rel[16];
    return s_attr (n, "relation", rel, sizeof rel) > 0 && rel[0] == 'p' &&
           (rel[1] == '-' || rel[1] == '\0');
}

static int s_read_detail (const s_ctx_t *c, const xmlNode *detail, gw_cot_event_t *e, s_links_t *l,
                          bool *ret_contact, bool *ret_track)
{
    bool contact = false, remarks = false, dest = false, color = false;
    for (const xmlNode *n = detail->children; n; n = n->next) {
        if (n->type != XML_ELEMENT_NODE)
            continue;
        long line = s_line (c, n);
        if (s_is (n, "contact") && !contact) {
            contact = true;
            xmlChar *v = xmlGetNoNsProp (n, (const xmlChar *)"callsign");
            if (v)
                s_copy_cut (e->callsign, sizeof e->callsign, (const char *)v);
            xmlFree (v);
        } else if (s_is (n, "remarks") && !remarks) {
            remarks = true;
            xmlChar *v = xmlNodeGetContent (n);
            if (v)
                s_copy_cut (e->remarks, sizeof e->remarks, (const char *)v);
            xmlFree (v);
        } else if (s_is (n, "track") && !e->has_track) {
            e->has_track = true;
            if (s_attr_number (c, n, "course", false, &e->course_deg) < 0 ||
                s_attr_number (c, n, "speed", false, &e->speed_mps) < 0)
                return -EINVAL;
        } else if (s_is (n, "sensor") && !e->has_sensor) {
            e->has_sensor = true;
            if (s_attr_number (c, n, "azimuth", false, &e->sensor_azimuth_deg) < 0 ||
                s_attr_number (c, n, "elevation", false, &e->sensor_elevation_deg) < 0 ||
                s_attr_number (c, n, "fov", false, &e->sensor_fov_deg) < 0 ||
                s_attr_number (c, n, "vfov", false, &e->sensor_vfov_deg) < 0 ||
                s_attr_number (c, n, "range", false, &e->sensor_range_m) < 0)
                return -EINVAL;
        } else if (s_is (n, "link")) {
            char b[S_ATTR_MAX];
            int rc = s_attr (n, "point", b, sizeof b);
            if (rc != 0) {
                if (l->n == S_LINKS_READ)
                    return s_fail (c->why, c->whylen, "%sline %ld: more than %d link points",
                                   c->where, line, GW_COT_MAX_LINKS);
                if (rc < 0 || !s_link_point (b, &l->pts[l->n]))
                    return s_fail (c->why, c->whylen,
                                   "%sline %ld: <link> point '%.60s' is not lat,lon[,hae] in range",
                                   c->where, line, rc < 0 ? "" : b);
                l->n++;
            } else if (!l->uid[0] && !s_parent_link (n)) {
                // A task's addressee, when it has no <marti><dest>: the first
                // link to another object that is not the sender's own parent
                // (ATAK links every event to its sender, relation p-p).
                if (s_attr (n, "uid", l->uid, sizeof l->uid) < 0)
                    return s_fail (c->why, c->whylen,
                                   "%sline %ld: <link> uid longer than %zu bytes", c->where, line,
                                   sizeof l->uid - 1);
            }
        } else if (s_is (n, "strokeColor") && !color) {
            color = true;
            int rc = s_attr (n, "value", e->stroke_color, sizeof e->stroke_color);
            if (rc < 0 || (rc > 0 && !s_color_ok (e->stroke_color)))
                return s_fail (c->why, c->whylen,
                               "%sline %ld: <strokeColor> value is not a decimal ARGB integer",
                               c->where, line);
        } else if (s_is (n, "marti") && !dest) {
            for (const xmlNode *d = n->children; d && !dest; d = d->next) {
                if (!s_is (d, "dest"))
                    continue;
                int ru = s_attr (d, "uid", e->dest_uid, sizeof e->dest_uid);
                int rc = s_attr (d, "callsign", e->dest_callsign, sizeof e->dest_callsign);
                if (ru < 0 || rc < 0)
                    return s_fail (c->why, c->whylen,
                                   "%sline %ld: <dest> uid or callsign longer than %zu bytes",
                                   c->where, s_line (c, d), sizeof e->dest_callsign - 1);
                dest = ru > 0 || rc > 0;
            }
        }
    }
    if (ret_contact)
        *ret_contact = contact;
    if (ret_track)
        *ret_track = e->has_track;
    return 0;
}

/* After the detail: the vertices, closed when the first comes again at the
 * end (dropped) or for a u-d-r rectangle; a task's addressee from a link
 * when it has no dest. */
static int s_finish (gw_cot_event_t *e, const s_links_t *l, char *why, size_t whylen)
{
    size_t n = l->n;
    bool closed = false;
    if (strcmp (e->type, "u-d-r") == 0 && n >= 3) {
        closed = true;
    } else if (n >= 4 && l->pts[0].lat_deg == l->pts[n - 1].lat_deg &&
               l->pts[0].lon_deg == l->pts[n - 1].lon_deg) {
        closed = true;
        n--;
    }
    if (n > GW_COT_MAX_LINKS)
        return s_fail (why, whylen, "more than %d link points", GW_COT_MAX_LINKS);
    memcpy (e->links, l->pts, n * sizeof *l->pts);
    e->n_links = n;
    e->closed = closed;
    if (!e->dest_uid[0] && !e->dest_callsign[0] && l->uid[0] && strncmp (e->type, "t-", 2) == 0)
        s_copy_cut (e->dest_uid, sizeof e->dest_uid, l->uid);
    return 0;
}

/* Parse len bytes with libxml2: no network, no entity substitution, no
 * DTD loading, no messages on stderr; a DOCTYPE is refused. */
static xmlDoc *s_parse (const s_ctx_t *c, const char *text, size_t len, int *ret_rc)
{
    xmlInitParser ();
    xmlParserCtxt *ctxt = xmlNewParserCtxt ();
    if (!ctxt) {
        *ret_rc = -ENOMEM;
        s_fail (c->why, c->whylen, "out of memory for the XML parser");
        return NULL;
    }
    xmlDoc *doc = xmlCtxtReadMemory (ctxt, text, (int)len, NULL, NULL,
                                     XML_PARSE_NONET | XML_PARSE_NOERROR | XML_PARSE_NOWARNING);
    if (!doc || !ctxt->wellFormed) {
        xmlError *err = xmlCtxtGetLastError (ctxt);
        char msg[160] = "not well-formed XML";
        if (err && err->message) {
            snprintf (msg, sizeof msg, "%s", err->message);
            size_t n = strlen (msg);
            while (n && (msg[n - 1] == '\n' || msg[n - 1] == ' '))
                msg[--n] = '\0';
        }
        s_fail (c->why, c->whylen, "%sline %ld: %s", c->where,
                (err ? (long)err->line : 0) + c->line_off, msg);
        xmlFreeDoc (doc);
        xmlFreeParserCtxt (ctxt);
        *ret_rc = -EINVAL;
        return NULL;
    }
    xmlFreeParserCtxt (ctxt);
    if (doc->intSubset || doc->extSubset) {
        s_fail (c->why, c->whylen, "%sa DOCTYPE is not allowed in CoT", c->where);
        xmlFreeDoc (doc);
        *ret_rc = -EINVAL;
        return NULL;
    }
    return doc;
}

static int s_decode_xml (const char *text, size_t len, long line_off, gw_cot_event_t *ret,
                         char *why, size_t whylen)
{
    s_ctx_t c = {"", line_off, why, whylen};
    int rc = 0;
    xmlDoc *doc = s_parse (&c, text, len, &rc);
    if (!doc)
        return rc;
    gw_cot_event_t e;
    gw_cot_event_init (&e);
    s_links_t links = {.n = 0};
    links.uid[0] = '\0';
    const xmlNode *ev = xmlDocGetRootElement (doc);
    const xmlNode *point = NULL, *detail = NULL;
    char b[S_ATTR_MAX];
    double version = 0;
    if (!ev || !s_is (ev, "event")) {
        rc = s_fail (why, whylen, "line %ld: the root element is <%s>, not <event>",
                     ev ? s_line (&c, ev) : 1, ev ? (const char *)ev->name : "");
        goto done;
    }
    if ((rc = s_attr (ev, "version", b, sizeof b)) <= 0 || !s_number (b, &version) || version < 2) {
        rc = s_fail (why, whylen, "line %ld: <event> version %s'%.20s' (2.0 or later expected)",
                     s_line (&c, ev), rc == 0 ? "missing " : "", rc > 0 ? b : "");
        goto done;
    }
    if ((rc = s_event_id (&c, ev, "uid", e.uid, sizeof e.uid)) < 0 ||
        (rc = s_event_id (&c, ev, "type", e.type, sizeof e.type)) < 0 ||
        (rc = s_event_id (&c, ev, "how", e.how, sizeof e.how)) < 0 ||
        (rc = s_attr_time_in (&c, ev, "time", &e.time_s)) < 0 ||
        (rc = s_attr_time_in (&c, ev, "start", &e.start_s)) < 0 ||
        (rc = s_attr_time_in (&c, ev, "stale", &e.stale_s)) < 0)
        goto done;
    if (s_attr (ev, "opex", e.opex, sizeof e.opex) < 0) {
        rc = s_fail (why, whylen, "line %ld: <event> opex longer than %zu bytes", s_line (&c, ev),
                     sizeof e.opex - 1);
        goto done;
    }
    for (const xmlNode *n = ev->children; n; n = n->next) {
        const xmlNode **slot = s_is (n, "point") ? &point : s_is (n, "detail") ? &detail : NULL;
        if (slot && *slot) {
            rc = s_fail (why, whylen, "line %ld: a second <%s>", s_line (&c, n),
                         (const char *)n->name);
            goto done;
        }
        if (slot)
            *slot = n;
    }
    if (!point) {
        rc = s_fail (why, whylen, "line %ld: <event> has no <point>", s_line (&c, ev));
        goto done;
    }
    if ((rc = s_attr_number (&c, point, "lat", true, &e.point.lat_deg)) < 0 ||
        (rc = s_attr_number (&c, point, "lon", true, &e.point.lon_deg)) < 0 ||
        (rc = s_attr_number (&c, point, "hae", true, &e.point.hae_m)) < 0 ||
        (rc = s_attr_number (&c, point, "ce", true, &e.ce_m)) < 0 ||
        (rc = s_attr_number (&c, point, "le", true, &e.le_m)) < 0)
        goto done;
    if (fabs (e.point.lat_deg) > 90 || fabs (e.point.lon_deg) > 180) {
        rc = s_fail (why, whylen, "line %ld: <point> lat %g lon %g out of range",
                     s_line (&c, point), e.point.lat_deg, e.point.lon_deg);
        goto done;
    }
    if (detail && (rc = s_read_detail (&c, detail, &e, &links, NULL, NULL)) < 0)
        goto done;
    if ((rc = s_finish (&e, &links, why, whylen)) < 0 || (rc = s_check (&e, why, whylen)) < 0)
        goto done;
    *ret = e;
done:
    xmlFreeDoc (doc);
    return rc;
}

/* ---- TAK protocol in ----------------------------------------------------------------------- */

/* An unsigned varint at buf[*at]; false when it runs past len or 10 bytes. */
static bool s_varint (const uint8_t *buf, size_t len, size_t *at, uint64_t *ret)
{
    uint64_t v = 0;
    for (int shift = 0; shift < 70 && *at < len; shift += 7) {
        uint8_t b = buf[(*at)++];
        v |= (uint64_t)(b & 0x7f) << shift;
        if (!(b & 0x80)) {
            *ret = v;
            return true;
        }
    }
    return false;
}

static int s_proto_id (const char *src, char *dst, size_t cap, const char *name, char *why,
                       size_t whylen)
{
    if (!s_copy (dst, cap, src ? src : ""))
        return s_fail (why, whylen, "cotEvent %s longer than %zu bytes", name, cap - 1);
    return 0;
}

static int s_proto_time (uint64_t ms, double *ret, const char *name, char *why, size_t whylen)
{
    if (ms == 0 || ms > S_MS_MAX)
        return s_fail (why, whylen, "cotEvent %s %llu ms is missing or after the year 9999", name,
                       (unsigned long long)ms);
    *ret = (double)ms / 1000.0;
    return 0;
}

static int s_decode_message (const uint8_t *p, size_t n, gw_cot_event_t *ret, char *why,
                             size_t whylen)
{
    Tak__TakMessage *m = tak__tak_message__unpack (NULL, n, p);
    if (!m)
        return s_fail (why, whylen, "not a TakMessage: the protobuf is truncated or malformed");
    int rc = 0;
    char *wrapped = NULL;
    xmlDoc *doc = NULL;
    gw_cot_event_t e;
    gw_cot_event_init (&e);
    s_links_t links = {.n = 0};
    links.uid[0] = '\0';
    const Tak__CotEvent *ev = m->cotevent;
    if (!ev) {
        s_fail (why, whylen, "a TakMessage without a cotEvent (a TakControl announcement)");
        rc = -ENOMSG;
        goto done;
    }
    if ((rc = s_proto_id (ev->uid, e.uid, sizeof e.uid, "uid", why, whylen)) < 0 ||
        (rc = s_proto_id (ev->type, e.type, sizeof e.type, "type", why, whylen)) < 0 ||
        (rc = s_proto_id (ev->how, e.how, sizeof e.how, "how", why, whylen)) < 0 ||
        (rc = s_proto_id (ev->opex, e.opex, sizeof e.opex, "opex", why, whylen)) < 0 ||
        (rc = s_proto_time (ev->sendtime, &e.time_s, "sendTime", why, whylen)) < 0 ||
        (rc = s_proto_time (ev->starttime, &e.start_s, "startTime", why, whylen)) < 0 ||
        (rc = s_proto_time (ev->staletime, &e.stale_s, "staleTime", why, whylen)) < 0)
        goto done;
    e.point = (gw_cot_point_t){ev->lat, ev->lon, ev->hae};
    e.ce_m = ev->ce;
    e.le_m = ev->le;
    const Tak__Detail *d = ev->detail;
    bool xml_contact = false, xml_track = false;
    if (d && d->xmldetail && d->xmldetail[0]) {
        // The receiver's rule: wrap it in <detail>, read it, then merge the typed fields.
        static const char open[] = "<detail>", close[] = "</detail>";
        size_t xl = strlen (d->xmldetail);
        wrapped = malloc (sizeof open - 1 + xl + sizeof close);
        if (!wrapped) {
            s_fail (why, whylen, "out of memory for xmlDetail");
            rc = -ENOMEM;
            goto done;
        }
        memcpy (wrapped, open, sizeof open - 1);
        memcpy (wrapped + sizeof open - 1, d->xmldetail, xl);
        memcpy (wrapped + sizeof open - 1 + xl, close, sizeof close);
        s_ctx_t c = {"xmlDetail ", 0, why, whylen};
        doc = s_parse (&c, wrapped, strlen (wrapped), &rc);
        if (!doc)
            goto done;
        const xmlNode *root = xmlDocGetRootElement (doc);
        if ((rc = s_read_detail (&c, root, &e, &links, &xml_contact, &xml_track)) < 0)
            goto done;
    }
    // Data for an element in both places: the XML's stands, the typed field is ignored.
    if (d && d->contact && !xml_contact && d->contact->callsign)
        s_copy_cut (e.callsign, sizeof e.callsign, d->contact->callsign);
    if (d && d->track && !xml_track) {
        e.has_track = true;
        e.course_deg = d->track->course;
        e.speed_mps = d->track->speed;
    }
    if ((rc = s_finish (&e, &links, why, whylen)) < 0 || (rc = s_check (&e, why, whylen)) < 0)
        goto done;
    *ret = e;
done:
    xmlFreeDoc (doc);
    free (wrapped);
    tak__tak_message__free_unpacked (m, NULL);
    return rc;
}

static int s_decode_tak (const uint8_t *buf, size_t len, gw_cot_event_t *ret, char *why,
                         size_t whylen)
{
    size_t at = 1;
    uint64_t v;
    if (!s_varint (buf, len, &at, &v))
        return s_fail (why, whylen, "TAK header truncated after 0xbf");
    if (at < len && buf[at] == GW_COT_TAK_MAGIC) {
        // Mesh: 0xbf <version> 0xbf <TakMessage>.
        if (v != GW_COT_TAK_VERSION)
            return s_fail (why, whylen, "TAK protocol version %llu (only %d is read)",
                           (unsigned long long)v, GW_COT_TAK_VERSION);
        at++;
        return s_decode_message (buf + at, len - at, ret, why, whylen);
    }
    // Stream: 0xbf <length> <TakMessage of that length>.
    if (v != len - at)
        return s_fail (why, whylen,
                       "TAK header: neither mesh (0xbf 0x01 0xbf) nor a stream length that "
                       "matches (%llu, %zu bytes follow)",
                       (unsigned long long)v, len - at);
    return s_decode_message (buf + at, len - at, ret, why, whylen);
}

int gw_cot_decode (const uint8_t *buf, size_t len, gw_cot_event_t *ret, gw_cot_format_t *ret_fmt,
                   char *why, size_t whylen)
{
    if (!buf || len == 0)
        return s_fail (why, whylen, "empty");
    if (len > GW_COT_DECODE_MAX)
        return s_fail (why, whylen, "%zu bytes: longer than %d", len, GW_COT_DECODE_MAX);
    size_t at = 0;
    long lines = 0;
    if (len >= 3 && buf[0] == 0xef && buf[1] == 0xbb && buf[2] == 0xbf)
        at = 3; // UTF-8 byte order mark
    while (at < len && s_space ((char)buf[at]))
        lines += buf[at++] == '\n';
    gw_cot_event_t e;
    int rc;
    gw_cot_format_t fmt;
    if (at < len && buf[at] == '<') {
        fmt = GW_COT_XML;
        rc = s_decode_xml ((const char *)buf + at, len - at, lines, &e, why, whylen);
    } else if (buf[0] == GW_COT_TAK_MAGIC) {
        fmt = GW_COT_PROTO;
        rc = s_decode_tak (buf, len, &e, why, whylen);
    } else {
        return s_fail (why, whylen,
                       "neither XML ('<') nor TAK protocol (0xbf): starts with byte 0x%02x",
                       at < len ? buf[at] : buf[0]);
    }
    if (rc < 0)
        return rc;
    *ret = e;
    if (ret_fmt)
        *ret_fmt = fmt;
    return 0;
}
