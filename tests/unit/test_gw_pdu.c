/* test_gw_pdu — DIS PDUs against IEEE 1278.1's layouts: an Entity State PDU
 * built by hand and checked byte by byte at the standard's offsets, round
 * trips in versions 3 to 7, an Action Request whose variable datums are
 * padded to 64 bits, timestamps worked by hand, every rejection with its
 * reason, datagram walking, and malformed input (the fuzz corpus when it is
 * there, and mutations of good PDUs always) under the sanitizers. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "gw_pdu.h"

#include <dirent.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* A big-endian reader written here, independent of the module's. */
static uint32_t s_be16 (const uint8_t *b)
{
    return (uint32_t)b[0] << 8 | b[1];
}

/* The worked example: every field a distinct, exactly representable value. */
static void s_example (gw_espdu_t *p, uint8_t version)
{
    memset (p, 0, sizeof *p);
    p->hdr.version = version, p->hdr.exercise = 3, p->hdr.timestamp = 0x12345679u;
    p->hdr.status = GW_STATUS_LVC_CONSTRUCTIVE;
    p->id = (gw_id_t){1, 2, 3};
    p->force = 2;
    p->type = (gw_type_t){1, 2, 225, 1, 2, 3, 4};
    p->alt_type = (gw_type_t){1, 1, 222, 2, 1, 5, 6};
    p->velocity[0] = 1.5f, p->velocity[1] = -2.0f, p->velocity[2] = 0.25f;
    p->location[0] = 6378137.0, p->location[1] = -4500000.25, p->location[2] = 3700000.125;
    p->orientation[0] = 0.5f, p->orientation[1] = -0.25f, p->orientation[2] = 1.0f;
    p->appearance = 0x00800001u;
    p->dr_algorithm = GW_DR_RVW;
    for (int i = 0; i < 15; i++)
        p->dr_other[i] = (uint8_t)(0x10 + i);
    p->acceleration[0] = 0.125f, p->acceleration[1] = 0.0f, p->acceleration[2] = -9.75f;
    p->angular_velocity[0] = 0.5f, p->angular_velocity[1] = 0.0f, p->angular_velocity[2] = -1.5f;
    p->marking_charset = 1;
    strcpy (p->marking, "ABCDEFGHIJK");
    p->capabilities = 0xdeadbeefu;
}

/* The worked example as 1278.1 lays it out, by offset (version 7). */
// clang-format off
static const uint8_t s_want[144] = {
    /*   0 header */ 7, 3, 1, 1, 0x12, 0x34, 0x56, 0x79, 0, 144, 0x06, 0,
    /*  12 id */ 0, 1, 0, 2, 0, 3,
    /*  18 force, variable parameter count */ 2, 0,
    /*  20 entity type, alternative type */ 1, 2, 0, 225, 1, 2, 3, 4,  1, 1, 0, 222, 2, 1, 5, 6,
    /*  36 velocity: 1.5f, -2.0f, 0.25f */
    0x3f, 0xc0, 0, 0,  0xc0, 0, 0, 0,  0x3e, 0x80, 0, 0,
    /*  48 location: 6378137.0, -4500000.25, 3700000.125 */
    0x41, 0x58, 0x54, 0xa6, 0x40, 0, 0, 0,
    0xc1, 0x51, 0x2a, 0x88, 0x10, 0, 0, 0,
    0x41, 0x4c, 0x3a, 0x90, 0x10, 0, 0, 0,
    /*  72 orientation: 0.5f, -0.25f, 1.0f */
    0x3f, 0, 0, 0,  0xbe, 0x80, 0, 0,  0x3f, 0x80, 0, 0,
    /*  84 appearance */ 0x00, 0x80, 0x00, 0x01,
    /*  88 dead reckoning algorithm, other parameters */
    4, 0x10, 0x11, 0x12, 0x13, 0x14, 0x15, 0x16, 0x17, 0x18, 0x19, 0x1a, 0x1b, 0x1c, 0x1d, 0x1e,
    /* 104 acceleration: 0.125f, 0, -9.75f */
    0x3e, 0, 0, 0,  0, 0, 0, 0,  0xc1, 0x1c, 0, 0,
    /* 116 angular velocity: 0.5f, 0, -1.5f */
    0x3f, 0, 0, 0,  0, 0, 0, 0,  0xbf, 0xc0, 0, 0,
    /* 128 marking character set, marking */
    1, 'A', 'B', 'C', 'D', 'E', 'F', 'G', 'H', 'I', 'J', 'K',
    /* 140 capabilities */ 0xde, 0xad, 0xbe, 0xef,
};
// clang-format on

static void s_assert_bytes (const uint8_t *got, const uint8_t *want, size_t n)
{
    for (size_t i = 0; i < n; i++)
        if (got[i] != want[i])
            fail_msg ("byte %zu: 0x%02x, want 0x%02x", i, got[i], want[i]);
}

static void test_espdu_bytes (void **state)
{
    (void)state;
    gw_espdu_t p;
    uint8_t b[256], want[144];
    for (uint8_t v = 4; v <= 7; v++) {
        s_example (&p, v);
        memset (b, 0xee, sizeof b);
        assert_int_equal (gw_pdu_encode_espdu (&p, b, sizeof b), 144);
        assert_int_equal (b[144], 0xee); // nothing past the PDU
        memcpy (want, s_want, sizeof want);
        want[0] = v;
        want[10] = v == 7 ? 0x06 : 0; // the PDU status byte only from 1278.1-2012
        s_assert_bytes (b, want, 144);
    }
    // A short marking is NUL-padded to eleven bytes.
    s_example (&p, 7);
    strcpy (p.marking, "T1");
    assert_int_equal (gw_pdu_encode_espdu (&p, b, sizeof b), 144);
    const uint8_t mark[11] = {'T', '1'};
    assert_memory_equal (b + 129, mark, 11);
    // Refusals: room for 143 bytes, version 2 or 8, variable parameters asked for.
    s_example (&p, 7);
    assert_int_equal (gw_pdu_encode_espdu (&p, b, 143), 0);
    p.hdr.version = 2;
    assert_int_equal (gw_pdu_encode_espdu (&p, b, sizeof b), 0);
    p.hdr.version = 8;
    assert_int_equal (gw_pdu_encode_espdu (&p, b, sizeof b), 0);
    s_example (&p, 7);
    p.n_params = 1;
    assert_int_equal (gw_pdu_encode_espdu (&p, b, sizeof b), 0);
}

// Decoding the hand-laid bytes gives the example's fields: checked directly for the
// header, and for the rest by encoding them again (the encoder writes every field,
// and test_espdu_bytes showed it writes the example as laid out).
static void test_espdu_round_trip (void **state)
{
    (void)state;
    for (uint8_t v = 3; v <= 7; v++) {
        uint8_t want[144], again[144];
        memcpy (want, s_want, sizeof want);
        want[0] = v;
        want[10] = v == 7 ? 0x06 : 0;
        gw_espdu_t q;
        const char *why = NULL;
        memset (&q, 0x5a, sizeof q);
        if (gw_pdu_decode_espdu (want, 144, &q, &why) != 0)
            fail_msg ("version %d: %s", v, why);
        assert_true (q.hdr.version == v && q.hdr.exercise == 3 && q.hdr.length == 144);
        assert_true (q.hdr.type == GW_PDU_ENTITY_STATE && q.hdr.timestamp == 0x12345679u);
        assert_true (q.hdr.family == GW_FAMILY_ENTITY_INFORMATION && q.n_params == 0);
        assert_int_equal (q.hdr.status, v == 7 ? GW_STATUS_LVC_CONSTRUCTIVE : 0);
        assert_true (q.location[0] == 6378137.0 && q.velocity[1] == -2.0f);
        assert_true (q.orientation[1] == -0.25f && q.acceleration[2] == -9.75f);
        assert_string_equal (q.marking, "ABCDEFGHIJK");
        assert_int_equal (gw_pdu_encode_espdu (&q, again, sizeof again), 144);
        s_assert_bytes (again, want, 144);
    }
}

/* Expect a rejection whose reason mentions `word`. */
#define assert_rejected(call, word)                                                                \
    do {                                                                                           \
        const char *why_ = NULL;                                                                   \
        int rc_ = (call);                                                                          \
        if (rc_ != -EPROTO || !why_ || !strstr (why_, (word)))                                     \
            fail_msg ("%s: rc %d, why '%s', want '%s'", #call, rc_, why_ ? why_ : "(null)", word); \
    } while (0)

/* One byte of a good PDU changed, and the reason it is then refused for. */
typedef struct {
    size_t at;
    uint8_t value;
    size_t len; // bytes handed to the decoder
    const char *why;
} s_cut_t;

static void test_espdu_rejects (void **state)
{
    (void)state;
    static const s_cut_t cuts[] = {
        {0, 2, 144, "version"},             // 1278-1993 (before DIS 2.0.3) is not known
        {0, 8, 144, "version"},             // nor anything after 1278.1-2012
        {9, 143, 144, "length"},            // length field 143 on 144 bytes
        {9, 143, 143, "144"},               // consistent, but shorter than an ESPDU
        {19, 1, 144, "variable parameter"}, // one record announced, none there
        {2, 16, 144, "Entity State"},       // an Action Request's type
        {48, 0xff, 144, "finite"},          // location x: 0xff... is a NaN
    };
    uint8_t b[160];
    gw_espdu_t q;
    gw_header_t h;
    for (size_t i = 0; i < sizeof cuts / sizeof cuts[0]; i++) {
        memcpy (b, s_want, 144);
        b[cuts[i].at] = cuts[i].value;
        if (cuts[i].at == 48)
            memset (b + 48, 0xff, 8);
        assert_rejected (gw_pdu_decode_espdu (b, cuts[i].len, &q, &why_), cuts[i].why);
    }
    assert_rejected (gw_pdu_decode_header (s_want, 11, &h, &why_), "12 bytes");
    // With 16 more bytes and a length field of 160 a variable parameter record fits.
    memcpy (b, s_want, 144);
    memset (b + 144, 0x77, 16);
    b[9] = 160, b[19] = 1;
    const char *why = NULL;
    if (gw_pdu_decode_espdu (b, 160, &q, &why) != 0)
        fail_msg ("%s", why);
    assert_int_equal (q.n_params, 1);
    assert_string_equal (q.marking, "ABCDEFGHIJK");
}

#define S_ACTION_LEN 128

/* An Action Request with two fixed datums and variable datums of 192, 12 and 65
 * bits, as 1278.1 lays it out: 40 + 2 * 8 + (8 + 24) + (8 + 8) + (8 + 16) bytes. */
// clang-format off
static const uint8_t s_action_want[S_ACTION_LEN] = {
    /*   0 header */ 7, 9, 16, 5, 0x80, 0, 0, 1, 0, 128, 0, 0,
    /*  12 originator, receiver */ 0, 10, 0, 20, 0, 0,  0, 1, 0, 1, 0, 5,
    /*  24 request id, action id */ 0, 0, 0, 77,  0, 0, 0, 40,
    /*  32 fixed and variable datum counts */ 0, 0, 0, 2,  0, 0, 0, 3,
    /*  40 fixed: 36400 = 20.0f, 1 = 2 */ 0, 0, 0x8e, 0x30, 0x41, 0xa0, 0, 0,  0, 0, 0, 1, 0, 0, 0, 2,
    /*  56 variable: 31200, 192 bits */ 0, 0, 0x79, 0xe0, 0, 0, 0, 192,
    1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16, 17, 18, 19, 20, 21, 22, 23, 24,
    /*  88 variable: 500, 12 bits padded to 64 */ 0, 0, 0x01, 0xf4, 0, 0, 0, 12,
    0xab, 0xc0, 0, 0, 0, 0, 0, 0,
    /* 104 variable: 501, 65 bits padded to 128 */ 0, 0, 0x01, 0xf5, 0, 0, 0, 65,
    0xf1, 0xf2, 0xf3, 0xf4, 0xf5, 0xf6, 0xf7, 0xf8, 0x80, 0, 0, 0, 0, 0, 0, 0,
};
// clang-format on

static void s_action (gw_action_t *a)
{
    memset (a, 0, sizeof *a);
    a->hdr = (gw_header_t){
        .version = 7, .exercise = 9, .type = GW_PDU_ACTION_REQUEST, .timestamp = 0x80000001u};
    a->originator = (gw_id_t){10, 20, 0};
    a->receiver = (gw_id_t){1, 1, 5};
    a->request_id = 77;
    a->action_or_status = 40;
    a->n_fixed = 2;
    a->fixed[0] = (gw_fixed_datum_t){36400, 0x41a00000u}; // 20.0f
    a->fixed[1] = (gw_fixed_datum_t){1, 2};
    a->n_var = 3;
    a->var[0] = (gw_var_datum_t){31200, 192, s_action_want + 64};
    a->var[1] = (gw_var_datum_t){500, 12, s_action_want + 96};
    a->var[2] = (gw_var_datum_t){501, 65, s_action_want + 112};
}

static void test_action (void **state)
{
    (void)state;
    gw_action_t *a = malloc (sizeof *a), *q = malloc (sizeof *q);
    assert_non_null (a);
    assert_non_null (q);
    s_action (a);
    uint8_t b[S_ACTION_LEN + 8];
    memset (b, 0xee, sizeof b);
    assert_int_equal (gw_pdu_encode_action (a, b, sizeof b), S_ACTION_LEN);
    s_assert_bytes (b, s_action_want, S_ACTION_LEN);
    assert_int_equal (b[S_ACTION_LEN], 0xee);
    assert_int_equal (gw_pdu_encode_action (a, b, S_ACTION_LEN - 1), 0);

    const char *why = NULL;
    if (gw_pdu_decode_action (b, S_ACTION_LEN, q, &why) != 0)
        fail_msg ("%s", why);
    assert_int_equal (q->hdr.type, GW_PDU_ACTION_REQUEST);
    assert_true (gw_pdu_id_eq (q->originator, a->originator));
    assert_true (gw_pdu_id_eq (q->receiver, a->receiver));
    assert_true (q->request_id == 77 && q->action_or_status == 40);
    assert_true (q->n_fixed == 2 && q->fixed[0].id == 36400 && q->fixed[1].value == 2);
    assert_true (q->n_var == 3 && q->var[1].id == 500 && q->var[1].length_bits == 12);
    assert_ptr_equal (q->var[0].value, b + 64); // points into the PDU
    assert_ptr_equal (q->var[2].value, b + 112);

    // An Action Response with no datums is the 40-byte base.
    a->hdr.type = GW_PDU_ACTION_RESPONSE;
    a->hdr.version = 5;
    a->action_or_status = GW_STATUS_COMPLETE;
    a->n_fixed = a->n_var = 0;
    uint8_t r[40];
    assert_int_equal (gw_pdu_encode_action (a, r, sizeof r), 40);
    assert_int_equal (s_be16 (r + 8), 40);
    assert_int_equal (gw_pdu_decode_action (r, 40, q, &why), 0);
    assert_int_equal (q->hdr.type, GW_PDU_ACTION_RESPONSE);
    assert_int_equal (q->action_or_status, GW_STATUS_COMPLETE);
    a->hdr.type = GW_PDU_ENTITY_STATE; // not an action
    assert_int_equal (gw_pdu_encode_action (a, r, sizeof r), 0);
    free (a);
    free (q);
}

static void test_action_rejects (void **state)
{
    (void)state;
    static const s_cut_t cuts[] = {
        {35, 12, S_ACTION_LEN, "fixed datum count"},   // 12 fixed: 96 bytes where 88 follow
        {39, 4, S_ACTION_LEN, "variable datum count"}, // a fourth variable datum announced
        {111, 129, S_ACTION_LEN, "runs past"},         // 129 bits: 24 bytes where 16 remain
        {39, 2, S_ACTION_LEN, "left over"},            // two read, 24 bytes left over
        {9, 39, 39, "shorter than 40"},                // consistent, but no room for the base
    };
    gw_action_t *a = malloc (sizeof *a);
    assert_non_null (a);
    uint8_t m[S_ACTION_LEN];
    for (size_t i = 0; i < sizeof cuts / sizeof cuts[0]; i++) {
        memcpy (m, s_action_want, sizeof m);
        m[cuts[i].at] = cuts[i].value;
        assert_rejected (gw_pdu_decode_action (m, cuts[i].len, a, &why_), cuts[i].why);
    }
    assert_rejected (gw_pdu_decode_action (s_action_want, 39, a, &why_), "length"); // says 128
    free (a);
}

static void test_timestamp (void **state)
{
    (void)state;
    // 1800 s is half an hour: 2^30 units, shifted left one: 2^31, bit 0 absolute.
    assert_int_equal (gw_pdu_timestamp (1800.0, true), 0x80000001u);
    assert_int_equal (gw_pdu_timestamp (1800.0, false), 0x80000000u);
    assert_int_equal (gw_pdu_timestamp (0.0, true), 1u);
    assert_int_equal (gw_pdu_timestamp (3600.0, false), 0u);                   // wraps to 0
    assert_int_equal (gw_pdu_timestamp (5400.0, false), 0x80000000u);          // 1.5 h: 1800 s past
    assert_int_equal (gw_pdu_timestamp (-1800.0, false), 0x80000000u);         // wraps from below
    assert_int_equal (gw_pdu_timestamp (3599.9999999999, false), 0xfffffffeu); // last unit
    bool absolute = false;
    assert_true (gw_pdu_timestamp_seconds (0x80000001u, &absolute) == 1800.0);
    assert_true (absolute);
    assert_true (gw_pdu_timestamp_seconds (0x80000000u, &absolute) == 1800.0);
    assert_false (absolute);
    const double unit = 3600.0 / 2147483648.0;
    const double s[] = {0.0, 0.001, 1.0, 59.99, 1234.5678, 1800.0, 3599.0, 3599.9999};
    for (size_t i = 0; i < sizeof s / sizeof s[0]; i++) {
        double back = gw_pdu_timestamp_seconds (gw_pdu_timestamp (s[i], true), NULL);
        if (!(back <= s[i] + 1e-9 && s[i] - back < unit + 1e-9))
            fail_msg ("%.9f s came back as %.9f s", s[i], back);
    }
}

/* The PDUs a walk visits: each must start where the one before it ended. */
typedef struct {
    const uint8_t *next;
    int n;
} s_seen_t;

static void s_see (void *arg, const uint8_t *pdu, size_t len)
{
    s_seen_t *s = arg;
    assert_ptr_equal (pdu, s->next);
    assert_int_equal (s_be16 (pdu + 8), len);
    s->next = pdu + len;
    s->n++;
}

/* A Geocentric Coordinates datum's 24 bytes: IEEE 754 doubles, big-endian. */
static void test_f64x3 (void **state)
{
    (void)state;
    uint8_t b[24];
    gw_pdu_put_f64x3 (b, (double[3]){1.0, -2.0, 0.5});
    // 1.0 = 3ff0 0000 0000 0000, -2.0 = c000 ..., 0.5 = 3fe0 ...
    const uint8_t want[24] = {0x3f, 0xf0, 0, 0, 0,    0,    0, 0, 0xc0, 0x00, 0, 0,
                              0,    0,    0, 0, 0x3f, 0xe0, 0, 0, 0,    0,    0, 0};
    assert_memory_equal (b, want, 24);
    double v[3];
    gw_pdu_get_f64x3 (want, v);
    assert_true (v[0] == 1.0 && v[1] == -2.0 && v[2] == 0.5);
    const double x[3] = {-2680382.64853988, -4422398.8131746985, 3722968.213462259};
    gw_pdu_put_f64x3 (b, x);
    gw_pdu_get_f64x3 (b, v);
    assert_memory_equal (v, x, sizeof x);
}

static void test_walk (void **state)
{
    (void)state;
    gw_espdu_t p;
    gw_action_t *a = malloc (sizeof *a);
    assert_non_null (a);
    s_action (a);
    uint8_t d[144 + S_ACTION_LEN + 144 + 5];
    s_example (&p, 7);
    assert_int_equal (gw_pdu_encode_espdu (&p, d, 144), 144);
    assert_int_equal (gw_pdu_encode_action (a, d + 144, S_ACTION_LEN), S_ACTION_LEN);
    s_example (&p, 5);
    assert_int_equal (gw_pdu_encode_espdu (&p, d + 144 + S_ACTION_LEN, 144), 144);
    const size_t whole = 144 + S_ACTION_LEN + 144;
    s_seen_t seen = {d, 0};
    const char *why = NULL;
    assert_int_equal (gw_pdu_walk (d, whole, s_see, &seen, &why), 3);
    assert_true (seen.n == 3 && seen.next == d + whole);
    // Five bytes of garbage after the third: an error, the three still walked.
    memset (d + whole, 0x42, 5);
    seen = (s_seen_t){d, 0};
    assert_rejected (gw_pdu_walk (d, whole + 5, s_see, &seen, &why_), "after the last PDU");
    assert_int_equal (seen.n, 3);
    // The second PDU claims more than arrived: only the first is walked.
    seen = (s_seen_t){d, 0};
    assert_rejected (gw_pdu_walk (d, 144 + 100, s_see, &seen, &why_), "longer");
    assert_int_equal (seen.n, 1);
    // A length field of 0 cannot stall the walk.
    d[144 + 8] = 0, d[144 + 9] = 0;
    seen = (s_seen_t){d, 0};
    assert_rejected (gw_pdu_walk (d, whole, s_see, &seen, &why_), "shorter than a PDU header");
    assert_int_equal (seen.n, 1);
    assert_int_equal (gw_pdu_walk (d, 0, s_see, &seen, &why), 0); // an empty datagram
    free (a);
}

/* Every PDU of a datagram through the header, ESPDU and action decoders. */
static void s_decode_all (void *arg, const uint8_t *pdu, size_t len)
{
    gw_action_t *a = arg;
    gw_header_t h;
    gw_espdu_t e;
    const char *why = NULL;
    if (gw_pdu_decode_header (pdu, len, &h, &why) < 0)
        assert_non_null (why);
    if (gw_pdu_decode_espdu (pdu, len, &e, &why) == 0)
        assert_true (isfinite (e.location[0]) && e.marking[GW_MARKING_LEN] == '\0');
    if (gw_pdu_decode_action (pdu, len, a, &why) == 0)
        for (uint32_t i = 0; i < a->n_var; i++) // each value lies inside the PDU
            assert_true (a->var[i].value >= pdu && a->var[i].value <= pdu + len);
}

static void s_feed (gw_action_t *a, const uint8_t *d, size_t len)
{
    uint8_t *copy = malloc (len ? len : 1); // exact size: ASan sees any overread
    assert_non_null (copy);
    memcpy (copy, d, len);
    const char *why = NULL;
    (void)gw_pdu_walk (copy, len, s_decode_all, a, &why);
    s_decode_all (a, copy, len); // and the whole datagram as one PDU
    free (copy);
}

static void test_malformed (void **state)
{
    (void)state;
    gw_action_t *a = malloc (sizeof *a);
    assert_non_null (a);
    // Every single-byte change and every truncation of two good PDUs.
    uint8_t good[144 + S_ACTION_LEN], m[sizeof good];
    gw_espdu_t p;
    s_example (&p, 7);
    assert_int_equal (gw_pdu_encode_espdu (&p, good, 144), 144);
    s_action (a);
    assert_int_equal (gw_pdu_encode_action (a, good + 144, S_ACTION_LEN), S_ACTION_LEN);
    const uint8_t vals[] = {0x00, 0x01, 0x07, 0x10, 0x7f, 0x80, 0xff};
    for (size_t i = 0; i < sizeof good; i++)
        for (size_t k = 0; k < sizeof vals; k++) {
            memcpy (m, good, sizeof m);
            m[i] = vals[k];
            s_feed (a, m, sizeof m);
        }
    for (size_t n = 0; n <= sizeof good; n++)
        s_feed (a, good, n);
    // The fuzz corpus, when it has been made (tests/fuzz/corpus/fuzz_dis).
    const char *root = getenv ("CGS_ROOT");
    char dir[1024];
    snprintf (dir, sizeof dir, "%s/tests/fuzz/corpus/fuzz_dis", root ? root : ".");
    DIR *dp = opendir (dir);
    int files = 0;
    for (struct dirent *de; dp && (de = readdir (dp));) {
        char path[2048];
        snprintf (path, sizeof path, "%s/%s", dir, de->d_name);
        FILE *f = de->d_name[0] == '.' ? NULL : fopen (path, "rb");
        if (!f)
            continue;
        static uint8_t buf[65536];
        size_t n = fread (buf, 1, sizeof buf, f);
        fclose (f);
        s_feed (a, buf, n);
        files++;
    }
    if (dp)
        closedir (dp);
    print_message ("# %d fuzz corpus files from %s%s\n", files, dir, dp ? "" : " (absent)");
    free (a);
}

int main (void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test (test_espdu_bytes),    cmocka_unit_test (test_espdu_round_trip),
        cmocka_unit_test (test_espdu_rejects),  cmocka_unit_test (test_action),
        cmocka_unit_test (test_action_rejects), cmocka_unit_test (test_timestamp),
        cmocka_unit_test (test_walk),           cmocka_unit_test (test_malformed),
        cmocka_unit_test (test_f64x3),
    };
    return cmocka_run_group_tests (tests, NULL, NULL);
}
