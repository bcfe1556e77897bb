/* im_klv — one frame's metadata as a MISB ST 0601 UAS Datalink Local Set
 * packet (KLV), the metadata of STANAG 4609 motion imagery. Pure: no
 * logging, no allocation, no globals.
 *
 * The packet: the 16-byte Universal Label 06 0E 2B 34 02 0B 01 01 0E 01 03 01
 * 01 00 00 00, a BER length (short form below 128, else long form 0x81 or
 * 0x82), then the items in increasing tag order with tag 2 first, tag 65
 * (LS version, IM_KLV_LS_VERSION) and tag 1 (checksum) last. Each item's tag
 * is a BER-OID (tag 129 is 0x81 0x01) and its length one byte. The checksum
 * is the standard's 16-bit running sum, bcc += byte << (8 * ((i + 1) % 2)),
 * over every byte from the key's first through the checksum item's length.
 *
 * Mappings (ST 0601.17 section 8; the same since 0601.16 for these items).
 * u16 ⟨lo..hi⟩ is round((v - lo) × (2^16 - 1) / (hi - lo)); s32 ±R is
 * round(v × (2^31 - 1) / R), and so on; every value is rounded to nearest
 * (which reproduces each of the standard's worked examples):
 *
 *  tag  item                          type  mapping         outside it
 *    2  precision time stamp          u64   µs since 1970   required: 0 returned
 *    3  mission id                    UTF-8 1..127 bytes    cut at 127 (whole characters)
 *    5  platform heading              u16   0..360          wrapped (an angle)
 *    6  platform pitch                s16   ±20             0x8000, "out of range"
 *    7  platform roll                 s16   ±50             0x8000, "out of range"
 *   13  sensor latitude               s32   ±90             left out (0x80000000 is reserved)
 *   14  sensor longitude              s32   ±180            wrapped
 *   15  sensor true altitude (MSL)    u16   -900..19000 m   clamped
 *   16  sensor horizontal FOV         u16   0..180          clamped
 *   17  sensor vertical FOV           u16   0..180          clamped
 *   18  sensor relative azimuth       u32   0..360          wrapped
 *   19  sensor relative elevation     s32   ±180            wrapped (0x80000000 never sent)
 *   20  sensor relative roll          u32   0..360          wrapped
 *   21  slant range                   u32   0..5e6 m        clamped
 *   23  frame centre latitude         s32   ±90             left out
 *   24  frame centre longitude        s32   ±180            wrapped
 *   25  frame centre elevation (MSL)  u16   -900..19000 m   clamped
 * 26-33 offset corners 1-4, lat/lon   s16   ±0.075 of the frame centre (see below)
 *   40  target location latitude      s32   ±90             left out
 *   41  target location longitude     s32   ±180            wrapped
 *   65  LS version number             u8    IM_KLV_LS_VERSION
 *   75  sensor ellipsoid height       u16   -900..19000 m   clamped
 * 82-89 full corners 1-4, lat/lon     s32   ±90 / ±180      as 23 / 24
 *  129  target id                     UTF-8 track id in decimal ("42")
 *    1  checksum                      u16
 *
 * Corners go together or not at all (any of the eight values non-finite, or
 * a latitude outside ±90: none). They are in offset form (26-33, each the
 * corner minus the frame centre as a reader decodes the centre) when the
 * frame centre (23, 24) is sent and all eight offsets are within ±0.075
 * degrees, else in full form (82-89). A longitude offset is not taken across
 * the antimeridian: a footprint astride it goes in full form. The special
 * values ("N/A (Off-Earth)", "reserved") are never sent, except the
 * out-of-range indicator of tags 6 and 7.
 *
 * Target: when has_target, tags 40 and 41 (each if finite) and tag 129, the
 * standard's "Target ID" (alpha-numeric, up to 32 characters), carrying the
 * designated track's id in decimal. ST 0601 has no numeric track-id item;
 * VMTI (tag 74, ST 0903) would be the other home, at far more cost. */
#ifndef IM_KLV_H
#define IM_KLV_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#define IM_KLV_LS_VERSION 17  // ST 0601.17, written in tag 65
#define IM_KLV_MAX_PACKET 318 // the longest packet im_klv_encode writes, bytes

/* One frame's metadata. A double that is not finite (NAN) leaves its tag
 * out; im_klv_frame_reset makes every one NAN. */
typedef struct {
    double unix_time_s;                                // tag 2; required, >= 0
    char mission_id[128];                              // tag 3; "" leaves it out
    double platform_heading_deg;                       // tag 5, true north, clockwise
    double platform_pitch_deg, platform_roll_deg;      // tags 6, 7; up, right wing down
    double sensor_lat_deg, sensor_lon_deg;             // tags 13, 14, WGS 84
    double sensor_true_alt_m;                          // tag 15, above mean sea level
    double sensor_hae_m;                               // tag 75, above the WGS 84 ellipsoid
    double hfov_deg, vfov_deg;                         // tags 16, 17
    double sensor_rel_az_deg;                          // tag 18, from the nose, clockwise
    double sensor_rel_el_deg;                          // tag 19, negative down
    double sensor_rel_roll_deg;                        // tag 20
    double slant_range_m;                              // tag 21, to the frame centre
    double frame_center_lat_deg, frame_center_lon_deg; // tags 23, 24
    double frame_center_elev_m;                        // tag 25, above mean sea level
    double corner_lat_deg[4], corner_lon_deg[4];       // upper left, upper right,
                                                       // lower right, lower left
    bool has_target;                                   // an intercept is designated
    double target_lat_deg, target_lon_deg;             // tags 40, 41
    uint32_t track_id;                                 // tag 129, in decimal
} im_klv_frame_t;

/* Every double NAN, the mission id empty, no target. */
void im_klv_frame_reset (im_klv_frame_t *f);

/* Write the frame's packet into buf (at most cap bytes) and return its
 * length; 0, with buf untouched, when the time is not finite or negative or
 * the packet does not fit. IM_KLV_MAX_PACKET bytes always suffice. */
size_t im_klv_encode (const im_klv_frame_t *f, uint8_t *buf, size_t cap);

#endif
