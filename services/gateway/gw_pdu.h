/* gw_pdu — DIS PDUs on the wire (IEEE 1278.1): the 12-byte header, Entity
 * State, Action Request and Action Response, for protocol versions 3 (DIS
 * 2.0.3, the paper's), 4 (DIS 2.0.4), 5 (1278.1-1995), 6 (1278.1a-1998) and
 * 7 (1278.1-2012); 3 to 6 share one layout, 7 adds the PDU status byte. Every field
 * is written and read one by one in network byte order, never as a struct
 * copy. Decoding validates before it uses: the length field against what
 * arrived, the version, and every count against the length. Pure: no
 * sockets, no logging, no globals. */
#ifndef GW_PDU_H
#define GW_PDU_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#define GW_HEADER_LEN      12
#define GW_ESPDU_LEN       144 // without variable parameter records
#define GW_VARPARAM_LEN    16  // one articulation / variable parameter record
#define GW_ACTION_BASE_LEN 40  // Action Request/Response without datum records
#define GW_MARKING_LEN     11
#define GW_DATUM_MAX       256  // fixed and variable datum records each, in one PDU
#define GW_PDU_MAX         8192 // the largest PDU this gateway writes (it reads up to 65535)

#define GW_VERSION_MIN 3 // DIS 2.0.3 (the third draft, May 1993: the paper's)
#define GW_VERSION_MAX 7 // IEEE 1278.1-2012

enum {
    GW_PDU_ENTITY_STATE = 1,
    GW_PDU_ACTION_REQUEST = 16,
    GW_PDU_ACTION_RESPONSE = 17,
};

enum {
    GW_FAMILY_ENTITY_INFORMATION = 1,
    GW_FAMILY_SIMULATION_MANAGEMENT = 5,
};

/* Dead-reckoning algorithms (1278.1 annex E). */
enum {
    GW_DR_OTHER = 0,
    GW_DR_STATIC = 1,
    GW_DR_FPW = 2,
    GW_DR_RPW = 3,
    GW_DR_RVW = 4,
    GW_DR_FVW = 5,
    GW_DR_FPB = 6,
    GW_DR_RPB = 7,
    GW_DR_RVB = 8,
    GW_DR_FVB = 9,
};

/* Action Response request status (SISO-REF-010). */
enum {
    GW_STATUS_OTHER = 0,
    GW_STATUS_PENDING = 1,
    GW_STATUS_EXECUTING = 2,
    GW_STATUS_COMPLETE = 4,
    GW_STATUS_REJECTED = 5,
    GW_STATUS_RETRANSMIT_LATER = 7,
};

/* The v7 PDU status byte: LVC (bits 1-2) constructive. */
#define GW_STATUS_LVC_CONSTRUCTIVE 0x06
/* Entity appearance bit 23: the entity is deactivated (left the exercise). */
#define GW_APPEARANCE_DEACTIVATED (1u << 23)

typedef struct {
    uint8_t version;    // protocol version
    uint8_t exercise;   // exercise id
    uint8_t type;       // PDU type
    uint8_t family;     // protocol family
    uint32_t timestamp; // DIS units past the hour << 1 | absolute bit
    uint16_t length;    // bytes, header included
    uint8_t status;     // v7 PDU status; 0 (padding) before v7
} gw_header_t;

typedef struct {
    uint16_t site;
    uint16_t application;
    uint16_t entity;
} gw_id_t;

typedef struct {
    uint8_t kind, domain;
    uint16_t country;
    uint8_t category, subcategory, specific, extra;
} gw_type_t;

typedef struct {
    gw_header_t hdr;
    gw_id_t id;
    uint8_t force;
    uint8_t n_params; // variable parameter records that follow (read: skipped, not kept)
    gw_type_t type;
    gw_type_t alt_type;
    float velocity[3];    // m/s, world (ECEF) axes, or body axes for the B algorithms
    double location[3];   // ECEF, metres
    float orientation[3]; // psi, theta, phi, radians
    uint32_t appearance;
    uint8_t dr_algorithm;
    uint8_t dr_other[15];
    float acceleration[3];            // m/s²
    float angular_velocity[3];        // rad/s, body axes
    uint8_t marking_charset;          // 1: ASCII
    char marking[GW_MARKING_LEN + 1]; // NUL-terminated
    uint32_t capabilities;
} gw_espdu_t;

typedef struct {
    uint32_t id;
    uint32_t value;
} gw_fixed_datum_t;

typedef struct {
    uint32_t id;
    uint32_t length_bits;
    const uint8_t *value; // length_bits / 8 rounded up bytes; decode: points into the PDU
} gw_var_datum_t;

/* Action Request (type 16) or Action Response (type 17). */
typedef struct {
    gw_header_t hdr;
    gw_id_t originator;
    gw_id_t receiver;
    uint32_t request_id;
    uint32_t action_or_status; // action id in a request, request status in a response
    uint32_t n_fixed, n_var;
    gw_fixed_datum_t fixed[GW_DATUM_MAX];
    gw_var_datum_t var[GW_DATUM_MAX];
} gw_action_t;

/* A timestamp: seconds past the hour (wrapped into [0, 3600)) in DIS units
 * of 3600/2^31 s, shifted left one, with bit 0 set when absolute. */
uint32_t gw_pdu_timestamp (double seconds_past_hour, bool absolute);
/* Seconds past the hour of a timestamp; *ret_absolute (may be NULL) its bit 0. */
double gw_pdu_timestamp_seconds (uint32_t timestamp, bool *ret_absolute);

/* Encode into buf; the PDU's length, or 0 when cap is too small or the
 * version or a count is out of range. The header's length is computed;
 * its type and family are set here. */
size_t gw_pdu_encode_espdu (const gw_espdu_t *pdu, uint8_t *buf, size_t cap);
size_t gw_pdu_encode_action (const gw_action_t *pdu, uint8_t *buf, size_t cap);

/* Read a header from a PDU of len bytes (one PDU, len its length field);
 * 0 or -EPROTO with *ret_why set to a static reason. */
int gw_pdu_decode_header (const uint8_t *buf, size_t len, gw_header_t *ret, const char **ret_why);
/* Decode a whole PDU of exactly len bytes; 0 or -EPROTO with *ret_why. An
 * action's variable datums point into buf. */
int gw_pdu_decode_espdu (const uint8_t *buf, size_t len, gw_espdu_t *ret, const char **ret_why);
int gw_pdu_decode_action (const uint8_t *buf, size_t len, gw_action_t *ret, const char **ret_why);

/* Walk the PDUs of one datagram by their length fields: fn is called with
 * each PDU (whose length field it equals). Returns the number walked, or
 * -EPROTO with *ret_why at the first PDU that does not fit (the ones before
 * it were walked); trailing bytes that are not a whole PDU are an error. */
typedef void (gw_pdu_fn) (void *arg, const uint8_t *pdu, size_t len);
int gw_pdu_walk (const uint8_t *dgram, size_t len, gw_pdu_fn *fn, void *arg, const char **ret_why);

/* Three float64 in network byte order: 24 bytes, as a variable datum of
 * Geocentric Coordinates (192 bits) carries them. */
void gw_pdu_put_f64x3 (uint8_t out[24], const double v[3]);
void gw_pdu_get_f64x3 (const uint8_t in[24], double ret_v[3]);

/* Whether two ids are equal. */
bool gw_pdu_id_eq (gw_id_t a, gw_id_t b);

#endif
