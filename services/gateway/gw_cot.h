/* gw_cot — Cursor on Target events on the wire: CoT XML (event version 2.0,
 * MITRE's base schema Event-PUBLIC.xsd, with the detail elements TAK clients
 * write), and the TAK protocol version 1 (protocol buffers, proto/tak.proto)
 * in its mesh framing (0xbf 0x01 0xbf, UDP) out, and in both the mesh and
 * the stream framing (0xbf <varint length>, TCP) in.
 *
 * Detail elements written: <contact callsign>, <track course speed>,
 * <sensor azimuth elevation fov vfov range>, <link point="lat,lon,hae"/> per
 * vertex of a drawing, <strokeColor value>, <marti><dest uid callsign/>,
 * and <remarks>. In protobuf, contact and track are typed fields and the
 * rest is xmlDetail. Read back: the same, and a tasking event's (type t-...)
 * first <link uid> without a point as its addressee when it has no
 * <marti><dest>. Other detail elements are ignored.
 *
 * Decoding validates before it returns anything: the framing, the XML
 * (libxml2, no network, no external entities, no DOCTYPE), the event
 * version, uid, type and how (the schema's patterns), the three times, a
 * point in range and finite numbers, and every detail element it reads.
 * Pure: no sockets, no logging, no globals of its own. */
#ifndef GW_COT_H
#define GW_COT_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#define GW_COT_UNKNOWN_M    9999999.0 // ce or le not known, as CoT writes it
#define GW_COT_MAX_LINKS    64        // vertices of one drawing
#define GW_COT_DECODE_MAX   65536     // longer input is rejected, bytes
#define GW_COT_ENCODED_MAX  16384     // a buffer this long holds any event encoded, XML or proto
#define GW_COT_TAK_VERSION  1         // the TAK protocol version written and read
#define GW_COT_TAK_MAGIC    0xbf      // first byte of both TAK framings
#define GW_COT_MESH_HDR_LEN 3         // 0xbf 0x01 0xbf

typedef struct {
    double lat_deg, lon_deg; // WGS 84
    double hae_m;            // height above the WGS 84 ellipsoid
} gw_cot_point_t;

typedef struct {
    char uid[96];  // required: the event's unique id
    char type[48]; // required: "a-f-A-M-F-Q", "b-m-p-s-p-i", "u-d-f", "t-s", ...
    char how[16];  // required: "m-g", "m-s" (simulated), "h-e", ...
    char opex[48]; // optional: "o", "e" or "s" (simulation), with "-name"
    // UTC, seconds since the Unix epoch; written to the ms.
    double time_s, start_s, stale_s;
    gw_cot_point_t point;
    // Circular and linear error, metres, 1 sigma; GW_COT_UNKNOWN_M when unknown.
    double ce_m, le_m;
    char callsign[64]; // <contact callsign>; "" for none (longer ones read are cut)
    char remarks[256]; // <remarks> text; "" for none (longer ones read are cut)
    // <track course speed>: course in degrees clockwise from true north, ground speed.
    bool has_track;
    double course_deg, speed_mps;
    // <sensor>, a camera's view as ATAK writes it: azimuth (clockwise from
    // true north) and elevation (above the horizontal, negative down) of the
    // centre of the view, the horizontal and vertical fields of view (whole
    // angles), and the range drawn. Missing attributes read as 0.
    bool has_sensor;
    double sensor_azimuth_deg, sensor_elevation_deg, sensor_fov_deg, sensor_vfov_deg;
    double sensor_range_m;
    // A drawing's vertices (a u-d-f line or polygon, a u-d-r rectangle), as
    // <link point="lat,lon,hae"/>. A closed one is written with its first
    // vertex again at the end (a u-d-r: its corners only), as TAK and
    // node-cot read a polygon; read back, a last vertex equal to the first
    // (lat and lon) closes it and is dropped, and a u-d-r is closed.
    size_t n_links;
    gw_cot_point_t links[GW_COT_MAX_LINKS];
    bool closed;
    char stroke_color[16]; // <strokeColor value>: ARGB as a decimal integer, as TAK writes
                           // it ("-16776961" is opaque blue); "" for none
    // A task's addressee, <marti><dest uid callsign/>; "" for none.
    char dest_uid[96];
    char dest_callsign[64];
} gw_cot_event_t;

typedef enum {
    GW_COT_XML,   // CoT XML (TAK protocol version 0)
    GW_COT_PROTO, // TAK protocol version 1, mesh or stream framing
} gw_cot_format_t;

/* An empty event: every field zero or "", ce and le unknown. */
void gw_cot_event_init (gw_cot_event_t *e);

/* One <event> with an XML declaration and a newline before it, NUL-terminated;
 * the length without the NUL, or 0 when it does not fit in cap or a field is
 * not valid (not finite, out of range, not UTF-8, a type or how the schema's
 * patterns refuse). Attribute and text are escaped; lat and lon to 1e-7 deg,
 * metres to the mm. */
size_t gw_cot_encode_xml (const gw_cot_event_t *e, char *buf, size_t cap);

/* TAK protocol version 1 in its mesh framing: 0xbf 0x01 0xbf, then a
 * TakMessage with a TakControl (versions 1 to 1) and the CotEvent: contact
 * and track as typed fields, the rest of the detail as xmlDetail, times in
 * ms. The length, or 0 as gw_cot_encode_xml, and for times before
 * 1970-01-01T00:00:00.0005Z (unsigned ms, 0 meaning missing). */
size_t gw_cot_encode_proto (const gw_cot_event_t *e, uint8_t *buf, size_t cap);

/* Decode one event of len bytes (at most GW_COT_DECODE_MAX): XML when it
 * starts with '<' after an optional UTF-8 byte order mark and white space,
 * TAK mesh with 0xbf 0x01 0xbf, TAK stream with 0xbf and a varint length
 * that equals the bytes after it. 0, or -EINVAL with a reason in why (may
 * be NULL; "line 3: ..." where there is a line), or -ENOMSG for a valid
 * TakMessage that carries no event (a TakControl announcement), or
 * -ENOMEM. *ret and *ret_fmt (may be NULL) are written on success only. */
int gw_cot_decode (const uint8_t *buf, size_t len, gw_cot_event_t *ret, gw_cot_format_t *ret_fmt,
                   char *why, size_t whylen);

/* ISO 8601 as CoT writes it, "2026-11-27T12:34:56.789Z" (fractional
 * seconds optional, any number of digits; Z, or an offset +hh:mm), to
 * seconds since the Unix epoch. 0, or -EINVAL (*ret_s untouched). */
int gw_cot_parse_time (const char *iso, double *ret_s);

/* Seconds since the Unix epoch as "2026-11-27T12:34:56.789Z", to the
 * nearest ms (25 bytes with the NUL); "" when not finite or outside the
 * years 1 to 9999. */
void gw_cot_format_time (double t_s, char *buf, size_t len);

#endif
