/* libFuzzer target: any bytes as one Cursor on Target datagram (or TCP
 * frame) arriving at the gateway. gw_cot_decode must either refuse them
 * with a reason (-EINVAL, or -ENOMSG for a TakControl without an event) or
 * return an event that keeps the codec's own rules: every text field
 * terminated, uid, type and how present, a point in range, at most
 * GW_COT_MAX_LINKS links and a closed drawing of 3 or more. A decoded event
 * is encoded again as CoT XML, as TAK protobuf in the mesh framing and
 * (that message again) in the stream framing, and each encoding must decode
 * to the same uid, type, how, times and point: exactly through protobuf,
 * within the XML's precision (lat and lon written to 1e-7 degree, hae to
 * the mm, times to the ms). abort() when not: a real finding. The encoder
 * has no protobuf form for a time before 1970-01-01T00:00:00.0005Z
 * (unsigned ms, 0 meaning missing): it must refuse those events. The bytes, as
 * a string, also go through gw_cot_parse_time, and a time it reads through
 * gw_cot_format_time and back. Must never crash, leak or hit undefined
 * behaviour. */
#include "gw_cot.h"

#include <errno.h>
#include <math.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

int LLVMFuzzerTestOneInput (const uint8_t *data, size_t size);

static char s_xml[GW_COT_ENCODED_MAX];
static uint8_t s_proto[GW_COT_ENCODED_MAX];
static uint8_t s_stream[GW_COT_ENCODED_MAX + 16];

#define S_DEG_XML 0.5e-7 // lat and lon are written to 1e-7 degree
#define S_M_XML   0.5e-3 // metres to the mm
#define S_S_TIME  0.5e-3 // times to the ms

static bool s_terminated (const char *s, size_t cap)
{
    return memchr (s, '\0', cap) != NULL;
}

/* What every decoded event must be. */
static void s_check_event (const gw_cot_event_t *e)
{
    if (!s_terminated (e->uid, sizeof e->uid) || !s_terminated (e->type, sizeof e->type) ||
        !s_terminated (e->how, sizeof e->how) || !s_terminated (e->opex, sizeof e->opex) ||
        !s_terminated (e->callsign, sizeof e->callsign) ||
        !s_terminated (e->remarks, sizeof e->remarks) ||
        !s_terminated (e->stroke_color, sizeof e->stroke_color) ||
        !s_terminated (e->dest_uid, sizeof e->dest_uid) ||
        !s_terminated (e->dest_callsign, sizeof e->dest_callsign))
        abort ();
    if (!e->uid[0] || !e->type[0] || !e->how[0])
        abort ();
    if (!(fabs (e->point.lat_deg) <= 90) || !(fabs (e->point.lon_deg) <= 180) ||
        !isfinite (e->point.hae_m) || !isfinite (e->ce_m) || !isfinite (e->le_m) ||
        !isfinite (e->time_s) || !isfinite (e->start_s) || !isfinite (e->stale_s))
        abort ();
    if (e->n_links > GW_COT_MAX_LINKS || (e->closed && e->n_links < 3))
        abort ();
    for (size_t i = 0; i < e->n_links; i++)
        if (!(fabs (e->links[i].lat_deg) <= 90) || !(fabs (e->links[i].lon_deg) <= 180) ||
            !isfinite (e->links[i].hae_m))
            abort ();
}

/* |a - b| within tol, and within the double's own resolution at a's size. */
static bool s_near (double a, double b, double tol)
{
    return fabs (a - b) <= tol + 4e-16 * fabs (a);
}

/* b, the decoding of a's encoding, names the same object at the same place and time. */
static void s_same (const gw_cot_event_t *a, const gw_cot_event_t *b, bool exact)
{
    if (strcmp (a->uid, b->uid) != 0 || strcmp (a->type, b->type) != 0 ||
        strcmp (a->how, b->how) != 0)
        abort ();
    double deg = exact ? 0 : S_DEG_XML, m = exact ? 0 : S_M_XML;
    if (!s_near (a->point.lat_deg, b->point.lat_deg, deg) ||
        !s_near (a->point.lon_deg, b->point.lon_deg, deg) ||
        !s_near (a->point.hae_m, b->point.hae_m, m))
        abort ();
    // Times go to the ms in both encodings.
    if (!s_near (a->time_s, b->time_s, S_S_TIME) || !s_near (a->start_s, b->start_s, S_S_TIME) ||
        !s_near (a->stale_s, b->stale_s, S_S_TIME))
        abort ();
}

/* Whether a time has a protobuf form the decoder reads back: at least 1 ms. */
static bool s_proto_time (double t_s)
{
    return llround (t_s * 1000.0) >= 1;
}

static void s_round_trip (const gw_cot_event_t *e)
{
    gw_cot_event_t x;
    gw_cot_format_t fmt;
    char why[256];
    size_t n = gw_cot_encode_xml (e, s_xml, sizeof s_xml);
    if (n == 0 || strlen (s_xml) != n)
        abort (); // a decoded event the encoder refuses, or a wrong length
    if (gw_cot_decode ((const uint8_t *)s_xml, n, &x, &fmt, why, sizeof why) < 0 ||
        fmt != GW_COT_XML)
        abort (); // our own XML does not decode
    s_check_event (&x);
    s_same (e, &x, false);

    n = gw_cot_encode_proto (e, s_proto, sizeof s_proto);
    if (!s_proto_time (e->time_s) || !s_proto_time (e->start_s) || !s_proto_time (e->stale_s)) {
        if (n != 0)
            abort (); // a time with no protobuf form (above) was encoded
        return;
    }
    if (n <= GW_COT_MESH_HDR_LEN || s_proto[0] != GW_COT_TAK_MAGIC ||
        s_proto[1] != GW_COT_TAK_VERSION || s_proto[2] != GW_COT_TAK_MAGIC)
        abort ();
    if (gw_cot_decode (s_proto, n, &x, &fmt, why, sizeof why) < 0 || fmt != GW_COT_PROTO)
        abort ();
    s_check_event (&x);
    s_same (e, &x, true);
    // The same TakMessage in the stream framing: 0xbf, its length as a varint.
    size_t len = n - GW_COT_MESH_HDR_LEN, at = 0;
    s_stream[at++] = GW_COT_TAK_MAGIC;
    for (size_t v = len;;) {
        uint8_t b = v & 0x7f;
        v >>= 7;
        s_stream[at++] = (uint8_t)(b | (v ? 0x80 : 0));
        if (!v)
            break;
    }
    memcpy (s_stream + at, s_proto + GW_COT_MESH_HDR_LEN, len);
    if (gw_cot_decode (s_stream, at + len, &x, &fmt, why, sizeof why) < 0 || fmt != GW_COT_PROTO)
        abort ();
    s_same (e, &x, true);
}

/* The bytes as an ISO 8601 time; one read is written and read again. */
static void s_time (const uint8_t *data, size_t size)
{
    char iso[64], out[40];
    if (size >= sizeof iso)
        return;
    memcpy (iso, data, size);
    iso[size] = '\0';
    double t = NAN, u = NAN;
    if (gw_cot_parse_time (iso, &t) < 0)
        return;
    if (!isfinite (t))
        abort ();
    gw_cot_format_time (t, out, sizeof out);
    if (!out[0])
        return; // outside the years 1 to 9999
    if (gw_cot_parse_time (out, &u) < 0 || !s_near (t, u, S_S_TIME))
        abort ();
}

int LLVMFuzzerTestOneInput (const uint8_t *data, size_t size)
{
    gw_cot_event_t e, e2;
    gw_cot_format_t fmt;
    char why[256];
    why[0] = '\0';
    int rc = gw_cot_decode (data, size, &e, &fmt, why, sizeof why);
    // The same without the optional outputs: the same verdict.
    int rc2 = gw_cot_decode (data, size, &e2, NULL, NULL, 0);
    if (rc != rc2)
        abort ();
    s_time (data, size);
    if (rc < 0) {
        if (rc != -EINVAL && rc != -ENOMSG && rc != -ENOMEM)
            abort ();
        if (!why[0] || !s_terminated (why, sizeof why))
            abort (); // refused without a reason
        return 0;
    }
    if (fmt != GW_COT_XML && fmt != GW_COT_PROTO)
        abort ();
    s_check_event (&e);
    s_round_trip (&e);
    return 0;
}
