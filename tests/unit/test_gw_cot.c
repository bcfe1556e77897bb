/* test_gw_cot — Cursor on Target in and out: times worked by hand, round
 * trips of every field through XML and through the TAK protocol (mesh and
 * stream framing), escaping, the drawings' closed shapes, every rejection
 * with its reason, mutated input under the sanitizers, and the outside
 * checks: xmllint validates encoded events against MITRE's
 * Event-PUBLIC.xsd (tests/data/cot), and protoc decodes our TAK payloads
 * with proto/tak.proto and with TAK's own .proto files (as node-cot ships
 * them in tests/interop/node_modules). xmllint and protoc are required.
 *
 * The events it writes go to $CGS_COT_OUT when set (kept, for
 * tests/interop/cot.mjs), else to a temporary folder removed at the end. */
#include "gw_cot.h"

#include "test_util.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#define T_EXAMPLE_S 1795782896.789 // 2026-11-27T12:34:56.789Z, worked in test_time

static const char *s_root (void)
{
    const char *root = getenv ("CGS_ROOT");
    return root && *root ? root : ".";
}

/* ---- events -------------------------------------------------------------------------------- */

static void s_times (gw_cot_event_t *e)
{
    e->time_s = T_EXAMPLE_S;
    e->start_s = T_EXAMPLE_S;
    e->stale_s = T_EXAMPLE_S + 30;
}

/* A radar track, as the gateway sends one. */
static void s_track (gw_cot_event_t *e)
{
    gw_cot_event_init (e);
    strcpy (e->uid, "mscgs.track.16");
    strcpy (e->type, "a-h-G-E-V");
    strcpy (e->how, "m-s");
    strcpy (e->opex, "s-mscgs");
    s_times (e);
    e->point = (gw_cot_point_t){38.8894839, -77.0352375, 12.5};
    e->ce_m = 25;
    strcpy (e->callsign, "Track 16");
    e->has_track = true, e->course_deg = 271.25, e->speed_mps = 13.5;
    strcpy (e->remarks, "radar track 16, quality 0.93");
}

/* A UAV with its camera's view. */
static void s_uav (gw_cot_event_t *e)
{
    gw_cot_event_init (e);
    strcpy (e->uid, "mscgs.uav1");
    strcpy (e->type, "a-f-A-M-F-Q");
    strcpy (e->how, "m-s");
    strcpy (e->opex, "s-mscgs");
    s_times (e);
    e->point = (gw_cot_point_t){38.9012345, -77.0123456, 1500.25};
    e->ce_m = 5, e->le_m = 10;
    strcpy (e->callsign, "uav1");
    e->has_track = true, e->course_deg = 90, e->speed_mps = 30.5;
    e->has_sensor = true, e->sensor_azimuth_deg = 45, e->sensor_elevation_deg = -30;
    e->sensor_fov_deg = 12.5, e->sensor_vfov_deg = 9.375, e->sensor_range_m = 2500;
}

/* A closed drawing of five vertices. */
static void s_drawing (gw_cot_event_t *e)
{
    gw_cot_event_init (e);
    strcpy (e->uid, "mscgs.area.1");
    strcpy (e->type, "u-d-f");
    strcpy (e->how, "h-e");
    s_times (e);
    e->point = (gw_cot_point_t){38.88, -77.03, 0};
    strcpy (e->callsign, "Area 1");
    const double v[5][2] = {
        {38.87, -77.04}, {38.87, -77.02}, {38.89, -77.01}, {38.90, -77.03}, {38.88, -77.05}};
    for (int i = 0; i < 5; i++)
        e->links[i] = (gw_cot_point_t){v[i][0], v[i][1], 10.0 * i};
    e->n_links = 5;
    e->closed = true;
    strcpy (e->stroke_color, "-16776961");
}

/* A task for uav1 at a point. */
static void s_task (gw_cot_event_t *e)
{
    gw_cot_event_init (e);
    strcpy (e->uid, "mscgs.task.7");
    strcpy (e->type, "t-s");
    strcpy (e->how, "h-e");
    s_times (e);
    e->point = (gw_cot_point_t){38.95, -77.1, 50};
    strcpy (e->dest_uid, "mscgs.uav1");
    strcpy (e->dest_callsign, "uav1");
    strcpy (e->remarks, "look at this");
}

/* Every field set at once. */
static void s_full (gw_cot_event_t *e)
{
    s_uav (e);
    strcpy (e->type, "u-d-f");
    strcpy (e->remarks, "all fields: \xc3\xa9t\xc3\xa9, line\nbreak");
    for (int i = 0; i < 4; i++)
        e->links[i] = (gw_cot_point_t){-45.5 + i * 0.1234567, 179.9999999 - i, -12.25 + i};
    e->n_links = 4;
    e->closed = true;
    strcpy (e->stroke_color, "4278190335");
    strcpy (e->dest_uid, "ANDROID-deadbeef");
    strcpy (e->dest_callsign, "Eagle Eye");
    e->start_s = T_EXAMPLE_S + 1.5;
    e->stale_s = T_EXAMPLE_S + 3600.001;
}

/* a equals b field by field, to the precision written (lat and lon 1e-7
 * deg, metres and degrees 1e-3, times to the ms). */
static void s_same (const gw_cot_event_t *a, const gw_cot_event_t *b)
{
    assert_string_equal (a->uid, b->uid);
    assert_string_equal (a->type, b->type);
    assert_string_equal (a->how, b->how);
    assert_string_equal (a->opex, b->opex);
    assert_near (a->time_s, b->time_s, 1e-6);
    assert_near (a->start_s, b->start_s, 1e-6);
    assert_near (a->stale_s, b->stale_s, 1e-6);
    assert_near (a->point.lat_deg, b->point.lat_deg, 5.01e-8);
    assert_near (a->point.lon_deg, b->point.lon_deg, 5.01e-8);
    assert_near (a->point.hae_m, b->point.hae_m, 5.01e-4);
    assert_near (a->ce_m, b->ce_m, 5.01e-4);
    assert_near (a->le_m, b->le_m, 5.01e-4);
    assert_string_equal (a->callsign, b->callsign);
    assert_string_equal (a->remarks, b->remarks);
    assert_int_equal (a->has_track, b->has_track);
    assert_near (a->course_deg, b->course_deg, 5.01e-4);
    assert_near (a->speed_mps, b->speed_mps, 5.01e-4);
    assert_int_equal (a->has_sensor, b->has_sensor);
    assert_near (a->sensor_azimuth_deg, b->sensor_azimuth_deg, 5.01e-4);
    assert_near (a->sensor_elevation_deg, b->sensor_elevation_deg, 5.01e-4);
    assert_near (a->sensor_fov_deg, b->sensor_fov_deg, 5.01e-4);
    assert_near (a->sensor_vfov_deg, b->sensor_vfov_deg, 5.01e-4);
    assert_near (a->sensor_range_m, b->sensor_range_m, 5.01e-4);
    assert_int_equal (a->n_links, b->n_links);
    for (size_t i = 0; i < a->n_links; i++) {
        assert_near (a->links[i].lat_deg, b->links[i].lat_deg, 5.01e-8);
        assert_near (a->links[i].lon_deg, b->links[i].lon_deg, 5.01e-8);
        assert_near (a->links[i].hae_m, b->links[i].hae_m, 5.01e-4);
    }
    assert_int_equal (a->closed, b->closed);
    assert_string_equal (a->stroke_color, b->stroke_color);
    assert_string_equal (a->dest_uid, b->dest_uid);
    assert_string_equal (a->dest_callsign, b->dest_callsign);
}

/* Decode text (XML) and expect a rejection whose reason contains want. */
static void s_reject (const char *text, size_t len, const char *want)
{
    gw_cot_event_t e;
    gw_cot_format_t fmt = (gw_cot_format_t)77;
    char why[256] = "";
    strcpy (e.uid, "untouched");
    int rc = gw_cot_decode ((const uint8_t *)text, len, &e, &fmt, why, sizeof why);
    if (rc != -EINVAL || !strstr (why, want))
        fail_msg ("rc %d, reason '%s': want -EINVAL and a reason with '%s'", rc, why, want);
    assert_string_equal (e.uid, "untouched"); // outputs written on success only
    assert_int_equal (fmt, 77);
}

static void s_reject_s (const char *text, const char *want)
{
    s_reject (text, strlen (text), want);
}

/* ---- times --------------------------------------------------------------------------------- */

static void test_time (void **state)
{
    (void)state;
    // 2026-11-27: 56 years after 1970 with 14 leap days (1972 to 2024), so
    // 56 * 365 + 14 = 20454 days to 2026-01-01, and 304 days of January to
    // October and 26 more: 20784 days, 1795737600 s. 12:34:56 is 45296 s:
    // 1795782896 s (as `date -u -d 2026-11-27T12:34:56Z +%s` says).
    assert_int_equal ((20454 + 304 + 26) * 86400LL + 12 * 3600 + 34 * 60 + 56, 1795782896LL);
    double t = 0;
    assert_int_equal (gw_cot_parse_time ("2026-11-27T12:34:56.789Z", &t), 0);
    assert_near (t, 1795782896.789, 1e-6);
    char b[32];
    gw_cot_format_time (1795782896.789, b, sizeof b);
    assert_string_equal (b, "2026-11-27T12:34:56.789Z");
    assert_int_equal (strlen (b) + 1, 25);
    // The same instant with an offset, and with other numbers of digits.
    assert_int_equal (gw_cot_parse_time ("2026-11-27T13:34:56.789+01:00", &t), 0);
    assert_near (t, 1795782896.789, 1e-6);
    assert_int_equal (gw_cot_parse_time ("2026-11-27T07:04:56.789-05:30", &t), 0);
    assert_near (t, 1795782896.789, 1e-6);
    assert_int_equal (gw_cot_parse_time ("2026-11-27T12:34:56Z", &t), 0);
    assert_near (t, 1795782896.0, 1e-9);
    assert_int_equal (gw_cot_parse_time ("2026-11-27T12:34:56.7891234Z", &t), 0);
    assert_near (t, 1795782896.7891234, 1e-6);
    // Epoch, a leap day (10957 + 59 days), the schema's own example.
    assert_int_equal (gw_cot_parse_time ("1970-01-01T00:00:00Z", &t), 0);
    assert_near (t, 0, 0);
    assert_int_equal (gw_cot_parse_time ("2000-02-29T00:00:00.00Z", &t), 0);
    assert_near (t, (10957 + 59) * 86400.0, 0);
    assert_near (t, 951782400, 0);
    assert_int_equal (gw_cot_parse_time ("2002-10-05T17:01:14.00Z", &t), 0);
    gw_cot_format_time (t, b, sizeof b);
    assert_string_equal (b, "2002-10-05T17:01:14.000Z");
    // Rounding to the ms, and before 1970.
    gw_cot_format_time (0.0004, b, sizeof b);
    assert_string_equal (b, "1970-01-01T00:00:00.000Z");
    gw_cot_format_time (59.9996, b, sizeof b);
    assert_string_equal (b, "1970-01-01T00:01:00.000Z");
    gw_cot_format_time (-0.5, b, sizeof b);
    assert_string_equal (b, "1969-12-31T23:59:59.500Z");
    gw_cot_format_time (951782399.999, b, sizeof b);
    assert_string_equal (b, "2000-02-28T23:59:59.999Z");
    gw_cot_format_time (NAN, b, sizeof b);
    assert_string_equal (b, "");
    gw_cot_format_time (1e12, b, sizeof b);
    assert_string_equal (b, "");
    // Every format a parse then format keeps, over a few centuries.
    for (double s = -2e9; s < 8e9; s += 123456789.125) {
        gw_cot_format_time (s, b, sizeof b);
        assert_int_equal (gw_cot_parse_time (b, &t), 0);
        assert_near (t, s, 1e-6);
    }
    // Refused: not a leap year, hour 24, second 60, no zone, a space, month
    // 13, a dot without digits, cut short, trailing text, day 31 of April.
    const char *bad[] = {"2026-02-29T00:00:00Z",
                         "2026-11-27T24:00:00Z",
                         "2026-11-27T12:34:60Z",
                         "2026-11-27T12:34:56",
                         "2026-11-27 12:34:56Z",
                         "2026-13-01T00:00:00Z",
                         "2026-11-27T12:34:56.Z",
                         "2026-1",
                         "",
                         "2026-11-27T12:34:56Zx",
                         "2026-04-31T00:00:00Z",
                         "0000-01-01T00:00:00Z",
                         "2026-11-27T12:34:56+1",
                         "2026-11-27T12:34:56.789+01"};
    for (size_t i = 0; i < sizeof bad / sizeof *bad; i++) {
        t = 42;
        if (gw_cot_parse_time (bad[i], &t) != -EINVAL)
            fail_msg ("'%s' was taken", bad[i]);
        assert_near (t, 42, 0);
    }
}

/* ---- round trips --------------------------------------------------------------------------- */

static void s_round_trip (void (*make) (gw_cot_event_t *))
{
    gw_cot_event_t e, d;
    make (&e);
    char xml[GW_COT_ENCODED_MAX];
    size_t n = gw_cot_encode_xml (&e, xml, sizeof xml);
    assert_true (n > 0);
    assert_int_equal (strlen (xml), n);
    gw_cot_format_t fmt = GW_COT_PROTO;
    char why[256] = "";
    if (gw_cot_decode ((const uint8_t *)xml, n, &d, &fmt, why, sizeof why) != 0)
        fail_msg ("%s\n%s", why, xml);
    assert_int_equal (fmt, GW_COT_XML);
    s_same (&e, &d);

    uint8_t pb[GW_COT_ENCODED_MAX];
    size_t m = gw_cot_encode_proto (&e, pb, sizeof pb);
    assert_true (m > 3);
    assert_int_equal (pb[0], 0xbf);
    assert_int_equal (pb[1], 0x01);
    assert_int_equal (pb[2], 0xbf);
    fmt = GW_COT_XML;
    if (gw_cot_decode (pb, m, &d, &fmt, why, sizeof why) != 0)
        fail_msg ("%s", why);
    assert_int_equal (fmt, GW_COT_PROTO);
    s_same (&e, &d);

    // The stream framing: 0xbf, the payload's length as a varint, the payload.
    uint8_t st[GW_COT_ENCODED_MAX + 8];
    size_t len = m - 3, k = 0, v = len;
    st[k++] = 0xbf;
    for (; v >= 0x80; v >>= 7)
        st[k++] = (uint8_t)(v | 0x80);
    st[k++] = (uint8_t)v;
    memcpy (st + k, pb + 3, len);
    if (gw_cot_decode (st, k + len, &d, &fmt, why, sizeof why) != 0)
        fail_msg ("stream framing: %s", why);
    assert_int_equal (fmt, GW_COT_PROTO);
    s_same (&e, &d);

    // XML after a byte order mark and white space is still XML.
    char padded[GW_COT_ENCODED_MAX + 16] = "\xef\xbb\xbf \r\n\t";
    size_t pad = strlen (padded);
    memcpy (padded + pad, xml, n);
    assert_int_equal (gw_cot_decode ((const uint8_t *)padded, pad + n, &d, &fmt, why, sizeof why),
                      0);
    s_same (&e, &d);

    // Any buffer too short fails whole, the exact one (XML: with its NUL) works.
    for (size_t cap = 0; cap <= n; cap++)
        assert_int_equal (gw_cot_encode_xml (&e, xml, cap), 0);
    assert_int_equal (gw_cot_encode_xml (&e, xml, n + 1), n);
    for (size_t cap = 0; cap < m; cap++)
        assert_int_equal (gw_cot_encode_proto (&e, pb, cap), 0);
    assert_int_equal (gw_cot_encode_proto (&e, pb, m), m);
}

static void test_round_trip (void **state)
{
    (void)state;
    s_round_trip (s_full);
    s_round_trip (s_track);
    s_round_trip (s_uav);
    s_round_trip (s_drawing);
    s_round_trip (s_task);
}

/* What the encoder writes, looked at as text. */
static void test_xml_text (void **state)
{
    (void)state;
    gw_cot_event_t e;
    s_track (&e);
    char xml[GW_COT_ENCODED_MAX];
    assert_true (gw_cot_encode_xml (&e, xml, sizeof xml) > 0);
    const char *want_start =
        "<?xml version=\"1.0\" encoding=\"UTF-8\" standalone=\"yes\"?>\n<event "
        "version=\"2.0\" uid=\"mscgs.track.16\" type=\"a-h-G-E-V\" how=\"m-s\" "
        "time=\"2026-11-27T12:34:56.789Z\" start=\"2026-11-27T12:34:56.789Z\" "
        "stale=\"2026-11-27T12:35:26.789Z\" opex=\"s-mscgs\"><point "
        "lat=\"38.8894839\" lon=\"-77.0352375\" hae=\"12.5\" ce=\"25.0\" "
        "le=\"9999999.0\"/><detail>";
    assert_memory_equal (xml, want_start, strlen (want_start));
    assert_non_null (strstr (xml, "<contact callsign=\"Track 16\"/>"));
    assert_non_null (strstr (xml, "<track course=\"271.25\" speed=\"13.5\"/>"));
    assert_non_null (strstr (xml, "<remarks>radar track 16, quality 0.93</remarks>"));
    assert_non_null (strstr (xml, "</detail></event>"));
    // The point comes before the detail (the schema's order).
    assert_true (strstr (xml, "<point") < strstr (xml, "<detail>"));

    s_uav (&e);
    assert_true (gw_cot_encode_xml (&e, xml, sizeof xml) > 0);
    assert_non_null (strstr (xml, "<sensor azimuth=\"45.0\" elevation=\"-30.0\" fov=\"12.5\" "
                                  "vfov=\"9.375\" range=\"2500.0\"/>"));
    assert_non_null (strstr (xml, "lat=\"38.9012345\" lon=\"-77.0123456\" hae=\"1500.25\" "
                                  "ce=\"5.0\" le=\"10.0\""));

    // A closed drawing repeats its first vertex; a u-d-r is its four corners.
    s_drawing (&e);
    assert_true (gw_cot_encode_xml (&e, xml, sizeof xml) > 0);
    assert_non_null (strstr (xml, "<link point=\"38.8700000,-77.0400000,0.0\"/><link "
                                  "point=\"38.8700000,-77.0200000,10.0\"/>"));
    assert_non_null (strstr (xml, "<link point=\"38.8800000,-77.0500000,40.0\"/><link "
                                  "point=\"38.8700000,-77.0400000,0.0\"/><strokeColor "
                                  "value=\"-16776961\"/>"));
    size_t links = 0;
    for (const char *p = xml; (p = strstr (p, "<link ")); p++)
        links++;
    assert_int_equal (links, 6);
    strcpy (e.type, "u-d-r");
    e.n_links = 4;
    assert_true (gw_cot_encode_xml (&e, xml, sizeof xml) > 0);
    links = 0;
    for (const char *p = xml; (p = strstr (p, "<link ")); p++)
        links++;
    assert_int_equal (links, 4);
    gw_cot_event_t d;
    char why[256];
    assert_int_equal (gw_cot_decode ((const uint8_t *)xml, strlen (xml), &d, NULL, why, sizeof why),
                      0);
    assert_true (d.closed);
    assert_int_equal (d.n_links, 4);
    // An open line stays open.
    s_drawing (&e);
    e.closed = false;
    assert_true (gw_cot_encode_xml (&e, xml, sizeof xml) > 0);
    assert_int_equal (gw_cot_decode ((const uint8_t *)xml, strlen (xml), &d, NULL, why, sizeof why),
                      0);
    assert_false (d.closed);
    assert_int_equal (d.n_links, 5);

    s_task (&e);
    assert_true (gw_cot_encode_xml (&e, xml, sizeof xml) > 0);
    assert_non_null (strstr (xml, "<marti><dest uid=\"mscgs.uav1\" callsign=\"uav1\"/></marti>"));

    // An event with nothing in its detail has no <detail>; tiny negatives print unsigned.
    gw_cot_event_init (&e);
    strcpy (e.uid, "x"), strcpy (e.type, "a-u-G"), strcpy (e.how, "m-g");
    e.point = (gw_cot_point_t){-0.00000001, 0, -0.0001};
    assert_true (gw_cot_encode_xml (&e, xml, sizeof xml) > 0);
    assert_non_null (strstr (xml, "time=\"1970-01-01T00:00:00.000Z\""));
    assert_non_null (strstr (xml, "<point lat=\"0.0000000\" lon=\"0.0000000\" hae=\"0.0\""));
    assert_null (strstr (xml, "<detail"));
}

static void test_escaping (void **state)
{
    (void)state;
    gw_cot_event_t e, d;
    s_track (&e);
    strcpy (e.uid, "a&b<c>\"d'e");
    strcpy (e.callsign, "tab\there\nline");
    strcpy (e.remarks, "</remarks><x>&amp; \r\n end \xe2\x82\xac");
    strcpy (e.dest_callsign, "O'Neil & \"Co\"");
    char xml[GW_COT_ENCODED_MAX];
    size_t n = gw_cot_encode_xml (&e, xml, sizeof xml);
    assert_true (n > 0);
    assert_non_null (strstr (xml, "uid=\"a&amp;b&lt;c&gt;&quot;d&apos;e\""));
    assert_non_null (strstr (xml, "callsign=\"tab&#9;here&#10;line\""));
    assert_non_null (
        strstr (xml, "<remarks>&lt;/remarks&gt;&lt;x&gt;&amp;amp; &#13;&#10; end \xe2\x82\xac"));
    assert_non_null (strstr (xml, "callsign=\"O&apos;Neil &amp; &quot;Co&quot;\""));
    assert_null (strstr (xml, "<x>"));
    char why[256];
    assert_int_equal (gw_cot_decode ((const uint8_t *)xml, n, &d, NULL, why, sizeof why), 0);
    s_same (&e, &d);
    uint8_t pb[GW_COT_ENCODED_MAX];
    size_t m = gw_cot_encode_proto (&e, pb, sizeof pb);
    assert_true (m > 0);
    assert_int_equal (gw_cot_decode (pb, m, &d, NULL, why, sizeof why), 0);
    s_same (&e, &d);

    // What XML cannot carry is refused, not written: other control
    // characters, malformed UTF-8, surrogates, U+FFFF.
    const char *bad[] = {"a\x01"
                         "b",
                         "\xc3",
                         "\xc0\xaf",
                         "\xed\xa0\x80",
                         "\xef\xbf\xbf",
                         "\xf5\x80\x80\x80"};
    for (size_t i = 0; i < sizeof bad / sizeof *bad; i++) {
        s_track (&e);
        strcpy (e.callsign, bad[i]);
        assert_int_equal (gw_cot_encode_xml (&e, xml, sizeof xml), 0);
        assert_int_equal (gw_cot_encode_proto (&e, pb, sizeof pb), 0);
    }
    // Longer remarks and callsigns are cut at a character boundary.
    char big[1024] = "<?xml version=\"1.0\"?><event version=\"2.0\" uid=\"u\" type=\"a-f-G\" "
                     "how=\"m-g\" time=\"2026-11-27T12:34:56Z\" start=\"2026-11-27T12:34:56Z\" "
                     "stale=\"2026-11-27T12:34:56Z\"><point lat=\"1\" lon=\"2\" hae=\"3\" "
                     "ce=\"4\" le=\"5\"/><detail><remarks>";
    for (int i = 0; i < 150; i++)
        strcat (big, "\xc3\xa9"); // é, two bytes each: 300 bytes
    strcat (big, "</remarks></detail></event>");
    assert_int_equal (gw_cot_decode ((const uint8_t *)big, strlen (big), &d, NULL, why, sizeof why),
                      0);
    assert_int_equal (strlen (d.remarks), 254);
    assert_int_equal ((unsigned char)d.remarks[252], 0xc3);
}

/* The largest event fits GW_COT_ENCODED_MAX, in both encodings. */
static void test_largest (void **state)
{
    (void)state;
    gw_cot_event_t e, d;
    s_full (&e);
    memset (e.uid, '&', sizeof e.uid - 1), e.uid[sizeof e.uid - 1] = '\0';
    memset (e.type, 'A', sizeof e.type - 1), e.type[sizeof e.type - 1] = '\0';
    memset (e.how, 'h', 1), e.how[1] = '\0';
    for (size_t i = 1; i + 2 < sizeof e.how; i += 2)
        e.how[i] = '-', e.how[i + 1] = 'x', e.how[i + 2] = '\0';
    memset (e.opex, '"', sizeof e.opex - 1), e.opex[sizeof e.opex - 1] = '\0';
    memset (e.callsign, '"', sizeof e.callsign - 1), e.callsign[sizeof e.callsign - 1] = '\0';
    memset (e.remarks, '\'', sizeof e.remarks - 1), e.remarks[sizeof e.remarks - 1] = '\0';
    memset (e.dest_uid, '"', sizeof e.dest_uid - 1), e.dest_uid[sizeof e.dest_uid - 1] = '\0';
    memset (e.dest_callsign, '"', sizeof e.dest_callsign - 1);
    e.dest_callsign[sizeof e.dest_callsign - 1] = '\0';
    strcpy (e.stroke_color, "-2147483648");
    e.point.hae_m = -1e12, e.ce_m = 1e12, e.le_m = 1e12;
    e.course_deg = -1e12, e.speed_mps = -1e12;
    e.sensor_azimuth_deg = e.sensor_elevation_deg = e.sensor_fov_deg = -1e12;
    e.sensor_vfov_deg = e.sensor_range_m = -1e12;
    e.n_links = GW_COT_MAX_LINKS;
    for (size_t i = 0; i < e.n_links; i++)
        e.links[i] = (gw_cot_point_t){-89.1234567, -179.1234567 + i * 1e-3, -1e12};
    static char xml[GW_COT_ENCODED_MAX];
    size_t n = gw_cot_encode_xml (&e, xml, sizeof xml);
    assert_true (n > 0);
    print_message ("# largest event: %zu bytes of XML\n", n);
    char why[256];
    if (gw_cot_decode ((const uint8_t *)xml, n, &d, NULL, why, sizeof why) != 0)
        fail_msg ("%s", why);
    s_same (&e, &d);
    static uint8_t pb[GW_COT_ENCODED_MAX];
    size_t m = gw_cot_encode_proto (&e, pb, sizeof pb);
    assert_true (m > 0);
    print_message ("# largest event: %zu bytes of TAK protocol\n", m);
    assert_int_equal (gw_cot_decode (pb, m, &d, NULL, why, sizeof why), 0);
    s_same (&e, &d);
    // One link more, one more in a value's range: refused.
    e.n_links = GW_COT_MAX_LINKS + 1;
    assert_int_equal (gw_cot_encode_xml (&e, xml, sizeof xml), 0);
    e.n_links = GW_COT_MAX_LINKS;
    e.point.hae_m = -1.001e12;
    assert_int_equal (gw_cot_encode_xml (&e, xml, sizeof xml), 0);
}

/* ---- rejections ---------------------------------------------------------------------------- */

/* A good event with one piece of text replaced. */
static void s_event_with (char *out, size_t cap, const char *from, const char *to)
{
    gw_cot_event_t e;
    s_uav (&e);
    char xml[GW_COT_ENCODED_MAX];
    assert_true (gw_cot_encode_xml (&e, xml, sizeof xml) > 0);
    char *at = strstr (xml, from);
    if (!at)
        fail_msg ("'%s' is not in %s", from, xml);
    snprintf (out, cap, "%.*s%s%s", (int)(at - xml), xml, to, at + strlen (from));
}

static void test_rejects_xml (void **state)
{
    (void)state;
    char t[GW_COT_ENCODED_MAX + 64];
    const struct {
        const char *from, *to, *why;
    } cases[] = {
        {"lat=\"38.9012345\"", "lat=\"91\"", "lat 91 lon -77.0123 out of range"},
        {"lat=\"38.9012345\"", "lat=\"-90.0000001\"", "out of range"},
        {"lon=\"-77.0123456\"", "lon=\"180.5\"", "out of range"},
        {"hae=\"1500.25\"", "hae=\"NaN\"", "line 2: <point> hae 'NaN' is not a finite number"},
        {"ce=\"5.0\"", "ce=\"INF\"", "<point> ce 'INF' is not a finite number"},
        {"ce=\"5.0\"", "ce=\"-5\"", "point ce -5 or le 10 is negative"},
        {"le=\"10.0\"", "le=\"1e999\"", "<point> le '1e999' is not a finite number"},
        {"le=\"10.0\"", "le=\"0x10\"", "not a finite number"},
        {" le=\"10.0\"", "", "<point> has no le"},
        {"time=\"2026-11-27T12:34:56.789Z\"", "time=\"2026-11-27T25:00:00Z\"",
         "<event> time '2026-11-27T25:00:00Z' is not a time"},
        {"stale=\"2026-11-27T12:35:26.789Z\"", "stale=\"yesterday\"", "stale 'yesterday'"},
        {" start=\"2026-11-27T12:34:56.789Z\"", "", "<event> has no start"},
        {" how=\"m-s\"", "", "<event> has no how"},
        {"how=\"m-s\"", "how=\"ms-\"", "how 'ms-' is not of the form"},
        {"type=\"a-f-A-M-F-Q\"", "type=\"a_f\"", "type 'a_f' is not of the form"},
        {"type=\"a-f-A-M-F-Q\"", "type=\"\"", "type '' is not of the form"},
        {" uid=\"mscgs.uav1\"", "", "<event> has no uid"},
        {"uid=\"mscgs.uav1\"", "uid=\"\"", "uid is empty"},
        {"version=\"2.0\"", "version=\"1.1\"", "version '1.1' (2.0 or later expected)"},
        {" version=\"2.0\"", "", "version missing"},
        {"<point", "<pointe", "<event> has no <point>"},
        {"<detail>", "<point lat=\"1\" lon=\"1\" hae=\"1\" ce=\"1\" le=\"1\"/><detail>",
         "a second <point>"},
        {"<event", "<events", "line 2: "},
        {"<sensor azimuth=\"45.0\"", "<sensor azimuth=\"east\"", "<sensor> azimuth 'east'"},
        {"<track course=\"90.0\"", "<track course=\"\"", "<track> course ''"},
        {"<contact", "<link point=\"91,1\"/><contact", "<link> point '91,1' is not lat,lon"},
        {"<contact", "<link point=\"1,2,3,4\"/><contact", "is not lat,lon[,hae]"},
        {"<contact", "<link point=\"1\"/><contact", "is not lat,lon[,hae]"},
        {"<contact", "<strokeColor value=\"blue\"/><contact", "<strokeColor> value"},
        {"<?xml version=\"1.0\" encoding=\"UTF-8\" standalone=\"yes\"?>",
         "<?xml version=\"1.0\"?><!DOCTYPE event [<!ENTITY a \"b\">]>", "DOCTYPE"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof *cases; i++) {
        s_event_with (t, sizeof t, cases[i].from, cases[i].to);
        s_reject_s (t, cases[i].why);
    }
    // Truncated: libxml2's reason with its line.
    s_event_with (t, sizeof t, "x", "x");
    s_reject (t, strlen (t) / 2, "line 2: ");
    s_reject (t, strlen (t) - 3, "line 2: ");
    // Not XML at all, empty, a bad first byte, too long.
    s_reject_s ("hello", "neither XML ('<') nor TAK protocol (0xbf): starts with byte 0x68");
    s_reject ("\x01\xbf", 2, "starts with byte 0x01");
    s_reject ("", 0, "empty");
    s_reject_s ("   \n  ", "starts with byte 0x20");
    static char huge[GW_COT_DECODE_MAX + 2];
    memset (huge, ' ', sizeof huge - 1);
    huge[0] = '<';
    s_reject (huge, sizeof huge - 1, "65537 bytes: longer than 65536");
    // The line counts the white space skipped before the XML.
    s_event_with (t, sizeof t, "lat=\"38.9012345\"", "lat=\"x\"");
    char shifted[sizeof t + 8] = "\n\n\n";
    strcat (shifted, t);
    s_reject_s (shifted, "line 5: <point> lat 'x'");
    // 66 link points; 65 that do not close a shape.
    char links[66 * 40 + 16] = "";
    for (int i = 0; i < 66; i++)
        strcat (links, "<link point=\"1.5,2.5,3\"/>");
    strcat (links, "<contact");
    s_event_with (t, sizeof t, "<contact", links);
    s_reject_s (t, "line 2: more than 64 link points");
    links[0] = '\0';
    for (int i = 0; i < 65; i++)
        sprintf (links + strlen (links), "<link point=\"1.5,%d,3\"/>", i);
    strcat (links, "<contact");
    s_event_with (t, sizeof t, "<contact", links);
    s_reject_s (t, "more than 64 link points");
}

/* What the decoder takes that the encoder never writes. */
static void test_accepts (void **state)
{
    (void)state;
    gw_cot_event_t d;
    char why[256] = "";
    // ATAK's habits: single quotes, detail before point, other details,
    // a task's addressee as a link, ce and le as integers.
    const char *x = "<?xml version='1.0' encoding='UTF-8' standalone='yes'?>\n"
                    "<event version='2.0' uid='T-1' type='t-s' how='h-g-i-g-o' "
                    "time='2026-11-27T12:34:56.7Z' start='2026-11-27T12:34:56Z' "
                    "stale='2026-11-27T13:34:56.123456Z' access='Undefined'>\n"
                    "  <detail>\n"
                    "    <__group name='Cyan' role='Team Member'/>\n"
                    "    <link uid='ANDROID-1' type='a-f-G-U-C' relation='p-p'/>\n"
                    "    <link uid='mscgs.uav2' relation='t-t'/>\n"
                    "    <remarks source='x'>look <b>here</b></remarks>\n"
                    "    <track speed='3'/>\n"
                    "  </detail>\n"
                    "  <point lat='-33.35' lon='44.383333' hae='9999999.0' ce='9999999' "
                    "le=' 12 '/>\n"
                    "</event>";
    if (gw_cot_decode ((const uint8_t *)x, strlen (x), &d, NULL, why, sizeof why) != 0)
        fail_msg ("%s", why);
    assert_string_equal (d.uid, "T-1");
    assert_string_equal (d.how, "h-g-i-g-o");
    assert_near (d.time_s, 1795782896.7, 1e-6);
    assert_near (d.stale_s, 1795782896 + 3600.123456, 1e-6);
    assert_near (d.point.lat_deg, -33.35, 0);
    assert_near (d.le_m, 12, 0);
    assert_string_equal (d.dest_uid,
                         "mscgs.uav2"); // the first link to another object: not the parent (p-p)
    assert_string_equal (d.remarks, "look here");
    assert_true (d.has_track);
    assert_near (d.speed_mps, 3, 0);
    assert_near (d.course_deg, 0, 0);
    assert_string_equal (d.callsign, "");
    // <marti><dest> wins over a link; only a task takes a link's uid.
    const char *y = "<event version='2.0' uid='T-2' type='t-s' how='h-e' "
                    "time='2026-11-27T12:34:56Z' start='2026-11-27T12:34:56Z' "
                    "stale='2026-11-27T12:34:56Z'><point lat='0' lon='0' hae='0' ce='0' le='0'/>"
                    "<detail><link uid='L'/><marti><dest callsign='Viper'/>"
                    "<dest uid='second'/></marti></detail></event>";
    assert_int_equal (gw_cot_decode ((const uint8_t *)y, strlen (y), &d, NULL, why, sizeof why), 0);
    assert_string_equal (d.dest_callsign, "Viper");
    assert_string_equal (d.dest_uid, "");
    char z[1024];
    snprintf (z, sizeof z, "%s", y);
    memcpy (strstr (z, "t-s"), "a-f", 3);
    memcpy (strstr (z, "<marti>"), "<xarti>", 7);
    memcpy (strstr (z, "</marti>"), "</xarti>", 8);
    assert_int_equal (gw_cot_decode ((const uint8_t *)z, strlen (z), &d, NULL, why, sizeof why), 0);
    assert_string_equal (d.dest_uid, "");
    assert_string_equal (d.dest_callsign, "");
}

/* ---- TAK protocol -------------------------------------------------------------------------- */

/* A protobuf field written by hand: key, then a varint or the bytes. */
static size_t s_pb_varint (uint8_t *p, uint64_t v)
{
    size_t n = 0;
    for (; v >= 0x80; v >>= 7)
        p[n++] = (uint8_t)(v | 0x80);
    p[n++] = (uint8_t)v;
    return n;
}

static size_t s_pb_bytes (uint8_t *p, unsigned field, const void *b, size_t len)
{
    size_t n = s_pb_varint (p, field << 3 | 2);
    n += s_pb_varint (p + n, len);
    memcpy (p + n, b, len);
    return n + len;
}

static size_t s_pb_u64 (uint8_t *p, unsigned field, uint64_t v)
{
    size_t n = s_pb_varint (p, field << 3 | 0);
    return n + s_pb_varint (p + n, v);
}

static size_t s_pb_f64 (uint8_t *p, unsigned field, double v)
{
    size_t n = s_pb_varint (p, field << 3 | 1);
    memcpy (p + n, &v, 8); // little-endian host, as protobuf's fixed64
    return n + 8;
}

/* A mesh message of a CotEvent written by hand (lat as given). */
static size_t s_hand_event (uint8_t *out, double lat, uint64_t send_ms, const char *xml_detail)
{
    uint8_t ev[1024], det[512];
    size_t n = 0;
    n += s_pb_bytes (ev + n, 1, "a-f-G", 5);
    n += s_pb_bytes (ev + n, 5, "hand", 4);
    n += s_pb_u64 (ev + n, 6, send_ms);
    n += s_pb_u64 (ev + n, 7, 1795782896789ull);
    n += s_pb_u64 (ev + n, 8, 1795782926789ull);
    n += s_pb_bytes (ev + n, 9, "m-g", 3);
    n += s_pb_f64 (ev + n, 10, lat);
    n += s_pb_f64 (ev + n, 11, 2.5);
    if (xml_detail) {
        size_t dn = s_pb_bytes (det, 1, xml_detail, strlen (xml_detail));
        n += s_pb_bytes (ev + n, 15, det, dn);
    }
    out[0] = 0xbf, out[1] = 0x01, out[2] = 0xbf;
    return 3 + s_pb_bytes (out + 3, 2, ev, n);
}

static void s_reject_pb (const uint8_t *p, size_t n, int want_rc, const char *want)
{
    gw_cot_event_t e;
    char why[256] = "";
    strcpy (e.uid, "untouched");
    int rc = gw_cot_decode (p, n, &e, NULL, why, sizeof why);
    if (rc != want_rc || !strstr (why, want))
        fail_msg ("rc %d, reason '%s': want %d and a reason with '%s'", rc, why, want_rc, want);
    assert_string_equal (e.uid, "untouched");
}

static void test_proto (void **state)
{
    (void)state;
    uint8_t p[2048];
    gw_cot_event_t d;
    char why[256] = "";
    // A hand-made message decodes: the field numbers are TAK's.
    size_t n = s_hand_event (p, 1.25, 1795782896789ull, "<contact callsign='hand'/>");
    if (gw_cot_decode (p, n, &d, NULL, why, sizeof why) != 0)
        fail_msg ("%s", why);
    assert_string_equal (d.uid, "hand");
    assert_string_equal (d.type, "a-f-G");
    assert_string_equal (d.how, "m-g");
    assert_near (d.point.lat_deg, 1.25, 0);
    assert_near (d.point.lon_deg, 2.5, 0);
    assert_near (d.time_s, T_EXAMPLE_S, 1e-6);
    assert_near (d.stale_s, T_EXAMPLE_S + 30, 1e-6);
    assert_near (d.ce_m, 0, 0); // proto3: absent is zero
    assert_string_equal (d.callsign, "hand");

    // Rejected with a reason: lat 91, NaN, no send time, malformed xmlDetail.
    n = s_hand_event (p, 91, 1795782896789ull, NULL);
    s_reject_pb (p, n, -EINVAL, "point lat 91 is outside [-90, 90]");
    n = s_hand_event (p, NAN, 1795782896789ull, NULL);
    s_reject_pb (p, n, -EINVAL, "point lat nan");
    n = s_hand_event (p, 1, 0, NULL);
    s_reject_pb (p, n, -EINVAL, "sendTime 0 ms is missing");
    n = s_hand_event (p, 1, 253402300800000ull, NULL);
    s_reject_pb (p, n, -EINVAL, "after the year 9999");
    n = s_hand_event (p, 1, 1795782896789ull, "<track course='x'/>");
    s_reject_pb (p, n, -EINVAL, "xmlDetail line 1: <track> course 'x'");
    n = s_hand_event (p, 1, 1795782896789ull, "<remarks>open");
    s_reject_pb (p, n, -EINVAL, "xmlDetail line 1: ");

    // Truncated anywhere: never an event (a cut before the cotEvent is a
    // TakMessage without one).
    gw_cot_event_t e;
    s_full (&e);
    uint8_t pb[GW_COT_ENCODED_MAX];
    size_t m = gw_cot_encode_proto (&e, pb, sizeof pb);
    assert_true (m > 0);
    for (size_t cut = 1; cut < m; cut++) {
        int rc = gw_cot_decode (pb, cut, &d, NULL, why, sizeof why);
        assert_true (rc == -EINVAL || rc == -ENOMSG);
    }
    s_reject_pb (pb, m - 1, -EINVAL, "not a TakMessage: the protobuf is truncated or malformed");
    s_reject_pb (pb, 1, -EINVAL, "TAK header truncated after 0xbf");
    // Framing: another version, a stream length that does not match.
    uint8_t v2[GW_COT_ENCODED_MAX];
    memcpy (v2, pb, m);
    v2[1] = 0x02;
    s_reject_pb (v2, m, -EINVAL, "TAK protocol version 2 (only 1 is read)");
    v2[1] = 0x7f, v2[2] = 0x0a;
    s_reject_pb (v2, m, -EINVAL, "stream length that matches (127, ");
    // Garbage after a good mesh header.
    const uint8_t junk[] = {0xbf, 0x01, 0xbf, 0xff, 0xff, 0xff};
    s_reject_pb (junk, sizeof junk, -EINVAL, "truncated or malformed");
    // A TakControl alone: a valid message, no event.
    const uint8_t control[] = {0xbf, 0x01, 0xbf, 0x0a, 0x04, 0x08, 0x01, 0x10, 0x01};
    s_reject_pb (control, sizeof control, -ENOMSG, "without a cotEvent");
    const uint8_t control_stream[] = {0xbf, 0x06, 0x0a, 0x04, 0x08, 0x01, 0x10, 0x01};
    s_reject_pb (control_stream, sizeof control_stream, -ENOMSG, "without a cotEvent");

    // The typed contact and track yield to the same elements in xmlDetail.
    n = s_hand_event (p, 1, 1795782896789ull, "<contact callsign='xml'/><track course='7'/>");
    // (append a Detail with typed fields: a second field 15 merges into the first)
    uint8_t det[64], contact[32], track[32];
    size_t cn = s_pb_bytes (contact, 2, "typed", 5);
    size_t tn = s_pb_f64 (track, 2, 99);
    size_t dn = s_pb_bytes (det, 2, contact, cn);
    dn += s_pb_bytes (det + dn, 7, track, tn);
    uint8_t q[2048];
    size_t ev_len = n - 3 - 2; // the cotEvent field: key 0x12, one length byte (< 128)
    assert_true (ev_len < 128);
    uint8_t ev[1024];
    memcpy (ev, p + 5, ev_len);
    ev_len += s_pb_bytes (ev + ev_len, 15, det, dn);
    q[0] = 0xbf, q[1] = 0x01, q[2] = 0xbf;
    size_t qn = 3 + s_pb_bytes (q + 3, 2, ev, ev_len);
    assert_int_equal (gw_cot_decode (q, qn, &d, NULL, why, sizeof why), 0);
    assert_string_equal (d.callsign, "xml");
    assert_near (d.course_deg, 7, 0);
    // Without the XML ones, the typed fields are read.
    n = s_hand_event (p, 1, 1795782896789ull, "<remarks>r</remarks>");
    ev_len = n - 5;
    memcpy (ev, p + 5, ev_len);
    ev_len += s_pb_bytes (ev + ev_len, 15, det, dn);
    qn = 3 + s_pb_bytes (q + 3, 2, ev, ev_len);
    assert_int_equal (gw_cot_decode (q, qn, &d, NULL, why, sizeof why), 0);
    assert_string_equal (d.callsign, "typed");
    assert_true (d.has_track);
    assert_near (d.course_deg, 99, 0);
    assert_string_equal (d.remarks, "r");

    // Before 1970 an event has no protobuf form (times are unsigned ms).
    s_track (&e);
    e.time_s = -1;
    assert_int_equal (gw_cot_encode_proto (&e, pb, sizeof pb), 0);
    char xml[GW_COT_ENCODED_MAX];
    assert_true (gw_cot_encode_xml (&e, xml, sizeof xml) > 0);
}

/* ---- encoder refusals ---------------------------------------------------------------------- */

static void test_encode_rejects (void **state)
{
    (void)state;
    char xml[GW_COT_ENCODED_MAX];
    uint8_t pb[GW_COT_ENCODED_MAX];
    gw_cot_event_t e;
    for (int k = 0; k < 16; k++) {
        s_uav (&e);
        switch (k) {
        case 0:
            e.point.lat_deg = NAN;
            break;
        case 1:
            e.point.lat_deg = 91;
            break;
        case 2:
            e.point.lon_deg = -180.0001;
            break;
        case 3:
            e.point.hae_m = INFINITY;
            break;
        case 4:
            e.ce_m = NAN;
            break;
        case 5:
            e.time_s = NAN;
            break;
        case 6:
            e.stale_s = 1e12;
            break;
        case 7:
            strcpy (e.type, "a_f");
            break;
        case 8:
            strcpy (e.how, "m-");
            break;
        case 9:
            e.uid[0] = '\0';
            break;
        case 10:
            e.speed_mps = NAN;
            break;
        case 11:
            e.sensor_fov_deg = -INFINITY;
            break;
        case 12:
            strcpy (e.stroke_color, "4294967296");
            break;
        case 13:
            e.n_links = 2, e.closed = true;
            e.links[0] = e.links[1] = e.point;
            break;
        case 14:
            memset (e.callsign, 'x', sizeof e.callsign);
            break; // no NUL
        case 15:
            strcpy (e.uid, "tab\there");
            break;
        }
        if (gw_cot_encode_xml (&e, xml, sizeof xml) != 0 ||
            gw_cot_encode_proto (&e, pb, sizeof pb) != 0)
            fail_msg ("case %d was encoded", k);
    }
}

/* ---- mutations ----------------------------------------------------------------------------- */

/* Whatever decodes is an event the encoder takes. */
static void s_mutate (const uint8_t *good, size_t len)
{
    static uint8_t m[GW_COT_ENCODED_MAX];
    const uint8_t vals[] = {0x00, 0xff, 0xbf, '<', '>', '"', '&', '9', '-', ',', 0x80, 0x7f};
    gw_cot_event_t d;
    char why[256];
    static char xml[GW_COT_ENCODED_MAX];
    for (size_t i = 0; i < len; i++)
        for (size_t k = 0; k < sizeof vals; k++) {
            memcpy (m, good, len);
            m[i] = vals[k];
            if (gw_cot_decode (m, len, &d, NULL, why, sizeof why) == 0 &&
                gw_cot_encode_xml (&d, xml, sizeof xml) == 0)
                fail_msg ("byte %zu = 0x%02x decodes to an event that does not encode", i, vals[k]);
        }
}

static void test_mutations (void **state)
{
    (void)state;
    gw_cot_event_t e;
    s_full (&e);
    static char xml[GW_COT_ENCODED_MAX];
    static uint8_t pb[GW_COT_ENCODED_MAX];
    size_t n = gw_cot_encode_xml (&e, xml, sizeof xml);
    size_t m = gw_cot_encode_proto (&e, pb, sizeof pb);
    assert_true (n > 0 && m > 0);
    s_mutate ((const uint8_t *)xml, n);
    s_mutate (pb, m);
}

/* ---- outside checks: xmllint and protoc ---------------------------------------------------- */

static char s_dir[1024];
static bool s_keep;

static int s_setup_dir (void **state)
{
    (void)state;
    const char *out = getenv ("CGS_COT_OUT");
    if (out && *out) {
        snprintf (s_dir, sizeof s_dir, "%s", out);
        mkdir (s_dir, 0755);
        s_keep = true;
    } else {
        snprintf (s_dir, sizeof s_dir, "/tmp/test_gw_cot.XXXXXX");
        if (!mkdtemp (s_dir))
            return -1;
    }
    return 0;
}

static int s_teardown_dir (void **state)
{
    (void)state;
    if (!s_keep) {
        char cmd[1200];
        snprintf (cmd, sizeof cmd, "rm -rf '%s'", s_dir);
        if (system (cmd) != 0)
            return -1;
    } else {
        print_message ("# events kept in %s\n", s_dir);
    }
    return 0;
}

static void s_need (const char *tool, const char *package)
{
    char cmd[256];
    snprintf (cmd, sizeof cmd, "command -v %s >/dev/null 2>&1", tool);
    if (system (cmd) != 0)
        fail_msg ("%s is required for this test and is not installed (Debian: apt-get install "
                  "%s; scripts/install-deps installs it)",
                  tool, package);
}

static void s_write (const char *name, const void *p, size_t n, char *path, size_t cap)
{
    snprintf (path, cap, "%s/%s", s_dir, name);
    FILE *f = fopen (path, "wb");
    assert_non_null (f);
    assert_int_equal (fwrite (p, 1, n, f), n);
    assert_int_equal (fclose (f), 0);
}

/* Run cmd; its exit status, with its output in out. */
static int s_run (const char *cmd, char *out, size_t cap)
{
    FILE *p = popen (cmd, "r");
    assert_non_null (p);
    size_t n = fread (out, 1, cap - 1, p);
    out[n] = '\0';
    return pclose (p);
}

static void test_schema (void **state)
{
    (void)state;
    s_need ("xmllint", "libxml2-utils");
    char xsd[1200];
    snprintf (xsd, sizeof xsd, "%s/tests/data/cot/Event-PUBLIC.xsd", s_root ());
    if (access (xsd, R_OK) != 0)
        fail_msg ("no schema at %s", xsd);
    const struct {
        const char *name;
        void (*make) (gw_cot_event_t *);
    } events[] = {{"track", s_track}, {"uav", s_uav},   {"drawing", s_drawing},
                  {"task", s_task},   {"full", s_full}, {"escaped", NULL}};
    char xml[GW_COT_ENCODED_MAX], path[1200], cmd[4096], out[4096];
    uint8_t pb[GW_COT_ENCODED_MAX];
    for (size_t i = 0; i < sizeof events / sizeof *events; i++) {
        gw_cot_event_t e;
        if (events[i].make) {
            events[i].make (&e);
        } else {
            s_track (&e);
            strcpy (e.uid, "a&b<c>\"d'e");
            strcpy (e.callsign, "tab\there\nline");
            strcpy (e.remarks, "</remarks><x>&amp; \r\n end");
        }
        size_t n = gw_cot_encode_xml (&e, xml, sizeof xml);
        assert_true (n > 0);
        char name[64];
        snprintf (name, sizeof name, "%s.xml", events[i].name);
        s_write (name, xml, n, path, sizeof path);
        snprintf (cmd, sizeof cmd, "xmllint --noout --schema '%s' '%s' 2>&1", xsd, path);
        if (s_run (cmd, out, sizeof out) != 0)
            fail_msg ("%s does not validate:\n%s\n%s", name, out, xml);
        size_t m = gw_cot_encode_proto (&e, pb, sizeof pb);
        assert_true (m > 0);
        snprintf (name, sizeof name, "%s.takp", events[i].name);
        s_write (name, pb, m, path, sizeof path);
    }
    // The check can fail: xmllint refuses what the schema does.
    const char *bad[] = {
        "<event version='2.0' uid='u' type='a-f-G' how='m-g' time='2026-11-27T12:34:56Z' "
        "start='2026-11-27T12:34:56Z' stale='2026-11-27T12:34:56Z'><point lat='91' lon='0' "
        "hae='0' ce='0' le='0'/></event>",
        "<event version='2.0' uid='u' type='a_f' how='m-g' time='2026-11-27T12:34:56Z' "
        "start='2026-11-27T12:34:56Z' stale='2026-11-27T12:34:56Z'><point lat='0' lon='0' "
        "hae='0' ce='0' le='0'/></event>",
        "<event version='2.0' uid='u' type='a-f-G' how='m-g' time='2026-11-27T12:34:56Z' "
        "start='2026-11-27T12:34:56Z' stale='2026-11-27T12:34:56Z'><point lat='0' lon='0' "
        "hae='1e3' ce='0' le='0'/></event>",
    };
    for (size_t i = 0; i < sizeof bad / sizeof *bad; i++) {
        s_write ("refused.xml", bad[i], strlen (bad[i]), path, sizeof path);
        snprintf (cmd, sizeof cmd, "xmllint --noout --schema '%s' '%s' 2>&1", xsd, path);
        if (s_run (cmd, out, sizeof out) == 0)
            fail_msg ("xmllint took %s", bad[i]);
    }
    unlink (path);
}

/* The value protoc's text format gives key at the indentation given. */
static bool s_text_field (const char *out, const char *key, char *val, size_t cap)
{
    char pat[64];
    snprintf (pat, sizeof pat, "\n  %s: ", key);
    const char *at = strstr (out, pat);
    if (!at)
        return false;
    at += strlen (pat);
    size_t n = strcspn (at, "\n");
    snprintf (val, cap, "%.*s", (int)n, at);
    return true;
}

static void s_protoc (const char *proto_path, const char *proto, const char *message,
                      const char *payload, char *out, size_t cap)
{
    char cmd[4096];
    snprintf (cmd, sizeof cmd, "protoc --decode=%s --proto_path='%s' '%s/%s' < '%s' 2>&1", message,
              proto_path, proto_path, proto, payload);
    if (s_run (cmd, out, cap) != 0)
        fail_msg ("%s:\n%s", cmd, out);
}

static void s_expect (const char *out, const char *key, const char *want)
{
    char v[512];
    if (!s_text_field (out, key, v, sizeof v))
        fail_msg ("no %s in protoc's output:\n%s", key, out);
    assert_string_equal (v, want);
}

static void s_expect_num (const char *out, const char *key, double want, double tol)
{
    char v[512];
    if (!s_text_field (out, key, v, sizeof v))
        fail_msg ("no %s in protoc's output:\n%s", key, out);
    assert_near (strtod (v, NULL), want, tol);
}

static void test_protoc (void **state)
{
    (void)state;
    s_need ("protoc", "protobuf-compiler");
    char protos[1200], tak[1200];
    snprintf (protos, sizeof protos, "%s/proto", s_root ());
    snprintf (tak, sizeof tak, "%s/tests/interop/node_modules/@tak-ps/node-cot/lib/proto",
              s_root ());
    gw_cot_event_t e;
    s_uav (&e);
    uint8_t pb[GW_COT_ENCODED_MAX];
    size_t m = gw_cot_encode_proto (&e, pb, sizeof pb);
    assert_true (m > 3);
    char path[1200];
    s_write ("uav.pb", pb + 3, m - 3, path, sizeof path); // the payload after the mesh header
    static char out[65536];

    // Ours.
    s_protoc (protos, "tak.proto", "tak.TakMessage", path, out, sizeof out);
    assert_non_null (strstr (out, "takControl {\n  minProtoVersion: 1\n  maxProtoVersion: 1\n}"));
    const char *ev = strstr (out, "cotEvent {\n");
    assert_non_null (ev);
    s_expect (ev, "uid", "\"mscgs.uav1\"");
    s_expect (ev, "type", "\"a-f-A-M-F-Q\"");
    s_expect (ev, "how", "\"m-s\"");
    s_expect (ev, "opex", "\"s-mscgs\"");
    s_expect_num (ev, "lat", e.point.lat_deg, 0);
    s_expect_num (ev, "lon", e.point.lon_deg, 0);
    s_expect_num (ev, "hae", e.point.hae_m, 0);
    s_expect (ev, "sendTime", "1795782896789");
    s_expect (ev, "staleTime", "1795782926789");

    // TAK's own definitions (package atakmap.commoncommo.protobuf.v1), as
    // node-cot ships them: the same bytes read as the same fields.
    char takmsg[1300];
    snprintf (takmsg, sizeof takmsg, "%s/takmessage.proto", tak);
    if (access (takmsg, R_OK) != 0)
        fail_msg ("no %s: run scripts/install-deps (npm ci in tests/interop)", takmsg);
    s_protoc (tak, "takmessage.proto", "atakmap.commoncommo.protobuf.v1.TakMessage", path, out,
              sizeof out);
    ev = strstr (out, "cotEvent {\n");
    assert_non_null (ev);
    s_expect (ev, "uid", "\"mscgs.uav1\"");
    s_expect (ev, "type", "\"a-f-A-M-F-Q\"");
    s_expect_num (ev, "lat", e.point.lat_deg, 0);
    s_expect_num (ev, "lon", e.point.lon_deg, 0);
    s_expect_num (ev, "ce", 5, 0);
    s_expect_num (ev, "le", 10, 0);
    assert_non_null (strstr (ev, "    contact {\n      callsign: \"uav1\"\n    }"));
    assert_non_null (strstr (ev, "    track {\n      speed: 30.5\n      course: 90\n    }"));
    assert_non_null (strstr (ev, "    xmlDetail: \"<sensor azimuth=\\\"45.0\\\""));
    unlink (path);
}

int main (void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test (test_time),           cmocka_unit_test (test_round_trip),
        cmocka_unit_test (test_xml_text),       cmocka_unit_test (test_escaping),
        cmocka_unit_test (test_largest),        cmocka_unit_test (test_rejects_xml),
        cmocka_unit_test (test_accepts),        cmocka_unit_test (test_proto),
        cmocka_unit_test (test_encode_rejects), cmocka_unit_test (test_mutations),
        cmocka_unit_test (test_schema),         cmocka_unit_test (test_protoc),
    };
    return cmocka_run_group_tests (tests, s_setup_dir, s_teardown_dir);
}
