/* gw_s4607 — STANAG 4607 (NATO Ground Moving Target Indicator format, Edition 3,
 * version ID "30") packets on the wire: the 32-byte packet header, then Mission
 * (type 1), Dwell (2) with its target reports, Job Definition (5) and Platform
 * Location (13) segments, each behind a 5-byte segment header (type E8, size I32
 * that counts the segment header). Everything is big-endian, written field by
 * field. Callers give SI units and degrees; the encoder quantises to each
 * field's unit with round-to-nearest (halves away from zero) and then checks the
 * field's range.
 *
 * Range policy, per data type:
 * - SA32/SA16 latitudes and attitudes: within [-90, +90] degrees, else -EINVAL;
 *   +90 itself takes the largest code (the field stops one step short of it).
 * - BA32/BA16 longitudes, tracks and headings: any finite angle, wrapped into
 *   [0, 360).
 * - Positions, times and other identifying values: outside the field, -EINVAL.
 * - Measured quantities (velocities, SNR, RCS) and uncertainties: saturated at
 *   the field's limits; a negative uncertainty or speed is -EINVAL.
 * Each field's comment below says which. Non-finite values are -EINVAL except
 * NAN in an optional field, which leaves that field out.
 *
 * Every add either appends a whole segment and returns 0, or returns -EINVAL
 * (checked first) or -ENOSPC and leaves every byte of the buffer and the packet
 * struct as they were. Pure: no logging, no globals, no allocation. */
#ifndef GW_S4607_H
#define GW_S4607_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#define GW_S4607_VERSION      "30"  // P1: Edition 3, version 0
#define GW_S4607_HEADER_LEN   32    // the packet header
#define GW_S4607_SEG_HDR_LEN  5     // segment type E8 + segment size I32
#define GW_S4607_MISSION_LEN  44    // whole Mission segment, its header included
#define GW_S4607_JOB_LEN      73    // whole Job Definition segment
#define GW_S4607_PLATFORM_LEN 28    // whole Platform Location segment
#define GW_S4607_REPORTS_MAX  65535 // target reports in one dwell (D5 is I16)

/* Segment types (S1). */
enum {
    GW_S4607_SEG_MISSION = 1,
    GW_S4607_SEG_DWELL = 2,
    GW_S4607_SEG_JOB = 5,
    GW_S4607_SEG_PLATFORM = 13,
};

/* Packet header P4, security classification. */
enum {
    GW_S4607_CLASS_TOP_SECRET = 1,
    GW_S4607_CLASS_SECRET = 2,
    GW_S4607_CLASS_CONFIDENTIAL = 3,
    GW_S4607_CLASS_RESTRICTED = 4,
    GW_S4607_CLASS_UNCLASSIFIED = 5,
};

/* Packet header P7, exercise indicator. */
enum {
    GW_S4607_OPERATION_REAL = 0,
    GW_S4607_OPERATION_SIMULATED = 1,
    GW_S4607_OPERATION_SYNTHESIZED = 2,
    GW_S4607_EXERCISE_REAL = 128,
    GW_S4607_EXERCISE_SIMULATED = 129,
    GW_S4607_EXERCISE_SYNTHESIZED = 130,
};

/* Mission M3, platform type (a few of the table's values). The table has no
 * generic UAV: it names UAVs by service (16-19). */
enum {
    GW_S4607_PLATFORM_UNIDENTIFIED = 0,
    GW_S4607_PLATFORM_GROUND_BASED = 15,
    GW_S4607_PLATFORM_UAV_ARMY = 16,
    GW_S4607_PLATFORM_UAV_MARINES = 17,
    GW_S4607_PLATFORM_UAV_NAVY = 18,
    GW_S4607_PLATFORM_UAV_AIR_FORCE = 19,
    GW_S4607_PLATFORM_OTHER = 255,
};

/* Job J2 sensor type, J14 radar mode, J27 terrain model, J28 geoid model (a few). */
enum {
    GW_S4607_SENSOR_UNIDENTIFIED = 0,
    GW_S4607_SENSOR_OTHER = 1,
    GW_S4607_SENSOR_NO_STATEMENT = 255,
    GW_S4607_MODE_UNSPECIFIED = 0,
    GW_S4607_MODE_MTI = 1,
    GW_S4607_TERRAIN_NONE = 0,
    GW_S4607_TERRAIN_DTED0 = 1,
    GW_S4607_TERRAIN_DTED1 = 2,
    GW_S4607_TERRAIN_DTED2 = 3,
    GW_S4607_TERRAIN_SRTM1 = 7,
    GW_S4607_TERRAIN_SRTM2 = 8,
    GW_S4607_GEOID_NONE = 0,
    GW_S4607_GEOID_EGM96 = 1,
    GW_S4607_GEOID_GEO96 = 2,
    GW_S4607_GEOID_FLAT_EARTH = 3,
};

/* Job J4, target filtering flag bits (0: no filtering); bits 3-7 are spare. */
enum {
    GW_S4607_FILTER_AREA = 1u << 0,            // intersection of dwell and bounding area
    GW_S4607_FILTER_AREA_BLANKING = 1u << 1,   // area blanking
    GW_S4607_FILTER_SECTOR_BLANKING = 1u << 2, // sector blanking
};

#define GW_S4607_PRIORITY_END_OF_JOB 255 // J5: the job is over

/* Target report D32.10, classification: live targets 0-127, simulated 128-255. */
enum {
    GW_S4607_TARGET_NO_INFO_LIVE = 0,
    GW_S4607_TARGET_WHEELED_LIVE = 2,
    GW_S4607_TARGET_FIXED_WING_LIVE = 4,
    GW_S4607_TARGET_UNKNOWN_LIVE = 127,
    GW_S4607_TARGET_NO_INFO_SIM = 128, // "No Information, Simulated Target"
    GW_S4607_TARGET_TRACKED_SIM = 129,
    GW_S4607_TARGET_WHEELED_SIM = 130,
    GW_S4607_TARGET_ROTARY_WING_SIM = 131,
    GW_S4607_TARGET_FIXED_WING_SIM = 132,
    GW_S4607_TARGET_PERSON_SIM = 137,
    GW_S4607_TARGET_VEHICLE_SIM = 138,
    GW_S4607_TARGET_OTHER_SIM = 254,
    GW_S4607_TARGET_UNKNOWN_SIM = 255,
};

/* Which target-report fields every report of a dwell carries (the existence mask
 * is per dwell). The hi-res latitude and longitude (D32.2, D32.3) are always
 * sent: reduced-resolution locations (D32.4/5 with the D10/11 scale factors)
 * are not written. Fields the standard sends together are one flag. */
enum {
    GW_S4607_R_INDEX = 1u << 0,       // D32.1 MTI report index
    GW_S4607_R_HEIGHT = 1u << 1,      // D32.6 geodetic height
    GW_S4607_R_VELOCITY = 1u << 2,    // D32.7 line-of-sight and D32.8 wrap velocity
    GW_S4607_R_SNR = 1u << 3,         // D32.9
    GW_S4607_R_CLASS = 1u << 4,       // D32.10 classification
    GW_S4607_R_CLASS_PROB = 1u << 5,  // D32.11 classification probability
    GW_S4607_R_UNCERTAINTY = 1u << 6, // D32.12-15 slant, cross, height, radial velocity
    GW_S4607_R_TRUTH_TAG = 1u << 7,   // D32.16 application and D32.17 entity
    GW_S4607_R_RCS = 1u << 8,         // D32.18 radar cross section
    GW_S4607_R_ALL = (1u << 9) - 1,
};

/* A packet being written into a caller's buffer. */
typedef struct {
    uint8_t *buf;
    size_t cap; // bytes of buf
    size_t len; // bytes written: the header and whole segments
} gw_s4607_packet_t;

/* The 32-byte packet header. Alphanumeric fields take printable ASCII
 * (0x20-0x7e) only and are space padded on the wire. */
typedef struct {
    char nationality[3];        // P3: exactly 2 chars, e.g. "XN" (NATO)
    uint8_t classification;     // P4: GW_S4607_CLASS_*, 1..5
    char class_system[3];       // P5: up to 2 chars, e.g. "XN"
    uint16_t class_code;        // P6: bit flags, 0 none
    uint8_t exercise_indicator; // P7: GW_S4607_OPERATION_* or GW_S4607_EXERCISE_*
    char platform_id[11];       // P8: up to 10 chars
    uint32_t mission_id;        // P9
    uint32_t job_id;            // P10: nonzero in a packet with a dwell
} gw_s4607_header_t;

/* Mission segment (M1-M7). */
typedef struct {
    char mission_plan[13];    // M1: up to 12 chars
    char flight_plan[13];     // M2: up to 12 chars
    uint8_t platform_type;    // M3: GW_S4607_PLATFORM_*
    char platform_config[11]; // M4: up to 10 chars
    uint16_t year;            // M5..M7: the reference date (UTC) every segment time counts
    uint8_t month, day;       // from, at its midnight; a real calendar date, else -EINVAL
} gw_s4607_mission_t;

typedef struct {
    double lat_deg; // SA32, -EINVAL outside [-90, 90]
    double lon_deg; // BA32, wrapped
} gw_s4607_point_t;

/* Job Definition segment (J1-J28). The nominal values J16-J26 are NAN for "no
 * statement"; negative is -EINVAL, above the field's maximum saturates. */
typedef struct {
    uint32_t job_id;               // J1: nonzero
    uint8_t sensor_type;           // J2: GW_S4607_SENSOR_* or the table's sensor
    char sensor_model[7];          // J3: up to 6 chars
    uint8_t filter_flags;          // J4: GW_S4607_FILTER_* bits, others -EINVAL
    uint8_t priority;              // J5: 1..99, or 255 end of job
    gw_s4607_point_t bounds[4];    // J6-J13: bounding area corners A..D, clockwise
    uint8_t radar_mode;            // J14: GW_S4607_MODE_*
    double revisit_interval_s;     // J15: I16 decisecond, mandatory, -EINVAL outside 0..6553.5 s
    double along_track_unc_m;      // J16: I16 decimetre, 0..10000 dm
    double cross_track_unc_m;      // J17: I16 decimetre, 0..10000 dm
    double altitude_unc_m;         // J18: I16 decimetre, 0..20000 dm
    double track_unc_deg;          // J19: I8 degree, 0..45
    double speed_unc_mps;          // J20: I16 mm/s, 0..65534
    double slant_range_sd_m;       // J21: I16 cm, 0..65534
    double cross_range_sd_deg;     // J22: BA16 degree, 0..<180
    double los_velocity_sd_mps;    // J23: I16 cm/s, 0..5000
    double mdv_mps;                // J24: I8 dm/s, 0..254
    double detection_probability;  // J25: 0..1, as I8 percent; -EINVAL above 1
    double false_alarm_density_db; // J26: in dB (<= 0); the field holds -dB, 0..254
    uint8_t terrain_model;         // J27: GW_S4607_TERRAIN_*
    uint8_t geoid_model;           // J28: GW_S4607_GEOID_*
} gw_s4607_job_t;

/* Platform Location segment (L1-L7): all mandatory. */
typedef struct {
    double time_s;    // L1: since the reference date's midnight (UTC); I32 ms, 0..4e9 ms
    double lat_deg;   // L2: SA32, WGS 84
    double lon_deg;   // L3: BA32, wrapped
    double alt_m;     // L4: S32 cm above the WGS 84 ellipsoid, -500..2e7 m
    double track_deg; // L5: BA16, wrapped
    double speed_mps; // L6: I32 mm/s, 0..8000 m/s
    double vertical_velocity_mps; // L7: S8 dm/s, saturated at -12.8..12.7 m/s
} gw_s4607_platform_t;

/* Dwell segment (D2-D31). Mandatory fields must be finite; the optional ones
 * are NAN when absent. Fields the standard sends together (D12-14, D15-17,
 * D18-20, D21-23, and D28-30, which Wireshark 4.0 and others read as one
 * group) are all present or all absent, else -EINVAL. */
typedef struct {
    uint16_t revisit_index;           // D2
    uint16_t dwell_index;             // D3
    bool last_dwell;                  // D4: the last dwell of the revisit
    double time_s;                    // D6: since the reference date's midnight; I32 ms, 0..4e9 ms
    double sensor_lat_deg;            // D7: SA32
    double sensor_lon_deg;            // D8: BA32, wrapped
    double sensor_alt_m;              // D9: S32 cm, -500..2e7 m
    double along_track_unc_m;         // D12: I32 cm, saturated at 10 km
    double cross_track_unc_m;         // D13: I32 cm, saturated at 10 km
    double alt_unc_m;                 // D14: I16 cm, saturated at 655.35 m
    double track_deg;                 // D15: BA16, wrapped
    double speed_mps;                 // D16: I32 mm/s, -EINVAL outside 0..8000 m/s
    double vertical_velocity_mps;     // D17: S8 dm/s, saturated at -12.8..12.7 m/s
    double track_unc_deg;             // D18: I8 degree, saturated at 45
    double speed_unc_mps;             // D19: I16 mm/s, saturated at 65.535 m/s
    double vertical_velocity_unc_mps; // D20: I16 cm/s, saturated at 655.35 m/s
    double platform_heading_deg;      // D21: BA16, wrapped
    double platform_pitch_deg;        // D22: SA16
    double platform_roll_deg;         // D23: SA16
    double area_lat_deg;              // D24: dwell area centre, SA32
    double area_lon_deg;              // D25: BA32, wrapped
    double range_half_extent_m;       // D26: B16 km, -EINVAL outside 0..255.9921875 km
    double angle_half_extent_deg;     // D27: BA16, -EINVAL outside 0..180
    double sensor_heading_deg;        // D28: BA16, wrapped
    double sensor_pitch_deg;          // D29: SA16
    double sensor_roll_deg;           // D30: SA16
    double mdv_mps;                   // D31: I8 dm/s, saturated at 25.5 m/s
    uint32_t report_fields;           // GW_S4607_R_* every report carries; others -EINVAL
} gw_s4607_dwell_t;

/* One target report (D32). Only the fields the dwell's report_fields name are
 * read, and those must be finite. */
typedef struct {
    uint16_t index;              // D32.1 MTI report index
    double lat_deg;              // D32.2 hi-res latitude, SA32
    double lon_deg;              // D32.3 hi-res longitude, BA32, wrapped
    double height_m;             // D32.6 geodetic height, S16 m, -EINVAL outside -1000..32767
    double los_velocity_mps;     // D32.7 S16 cm/s, saturated; positive away from the sensor
                                 // (range opening), as our radar's radial velocity
    double wrap_velocity_mps;    // D32.8 I16 cm/s, saturated at 655.35 m/s
    double snr_db;               // D32.9 S8 dB, saturated at -128..127
    uint8_t classification;      // D32.10 GW_S4607_TARGET_*
    double class_probability;    // D32.11 0..1, as I8 percent; -EINVAL outside
    double slant_range_unc_m;    // D32.12 I16 cm, saturated at 655.35 m
    double cross_range_unc_m;    // D32.13 I16 dm, saturated at 6553.5 m
    double height_unc_m;         // D32.14 I8 m, saturated at 255 m
    double los_velocity_unc_mps; // D32.15 I16 cm/s, saturated at 50 m/s
    uint8_t truth_application;   // D32.16 truth tag application
    uint32_t truth_entity;       // D32.17 truth tag entity
    double rcs_dbsm;             // D32.18 S8 half-dB, saturated at -64..63.5 dBsm
} gw_s4607_report_t;

/* Start a packet in buf: writes the header (size 32 until segments follow).
 * 0, -EINVAL (a header field out of range) or -ENOSPC (cap < 32); *p and buf
 * are untouched on failure. */
int gw_s4607_packet_begin (gw_s4607_packet_t *p, uint8_t *buf, size_t cap,
                           const gw_s4607_header_t *h);
/* Append a Mission segment (44 bytes). */
int gw_s4607_add_mission (gw_s4607_packet_t *p, const gw_s4607_mission_t *m);
/* Append a Job Definition segment (73 bytes). */
int gw_s4607_add_job (gw_s4607_packet_t *p, const gw_s4607_job_t *j);
/* Append a Platform Location segment (28 bytes). */
int gw_s4607_add_platform (gw_s4607_packet_t *p, const gw_s4607_platform_t *pl);
/* Bytes the dwell segment of d with n reports takes, its header included; 0
 * when its set of fields is invalid (a partial group, an unknown report
 * field, more than 65535 reports). It depends on which fields are present,
 * not on their values. */
size_t gw_s4607_dwell_size (const gw_s4607_dwell_t *d, const gw_s4607_report_t *r, size_t n);
/* Append a Dwell segment with n target reports r[0..n-1] (the existence mask
 * is computed from the fields present). -EINVAL also when the packet's job
 * id is 0. */
int gw_s4607_add_dwell (gw_s4607_packet_t *p, const gw_s4607_dwell_t *d, const gw_s4607_report_t *r,
                        size_t n);
/* Write the packet size (P2) and return the packet's length in bytes. */
size_t gw_s4607_packet_end (gw_s4607_packet_t *p);

#endif
