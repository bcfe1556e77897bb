/* libFuzzer target: any bytes as one DIS datagram arriving at the gateway.
 * The datagram is walked PDU by PDU (gw_pdu_walk) and each PDU, and the
 * whole datagram as if it were one PDU, goes through gw_pdu_decode_header,
 * gw_pdu_decode_espdu and gw_pdu_decode_action. A decoded PDU is encoded
 * again and the encoding must decode to the same fields (abort() if not: a
 * real finding). A decoded Entity State PDU also goes down the inbound
 * path: gw_in_take into a table of external entities at the time its
 * timestamp says, gw_in_entity_msg of it, gw_in_expire (timeout 12 s, as
 * the gateway's default), and the table's index must still find every
 * entity it holds. Must never crash, leak or hit undefined behaviour.
 * The exercise frame is made once and kept; the entity table is made and
 * freed per input, so each input runs the same way every time. */
#include "cgs_geo.h"
#include "gw_in.h"
#include "gw_pdu.h"

#include <math.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#define S_TIMEOUT_S 12.0 // the gateway's default [dead_reckoning] timeout
#define S_TABLE_MAX 32   // small, so that a datagram can fill it

int LLVMFuzzerTestOneInput (const uint8_t *data, size_t size);

typedef struct {
    const cgs_geo_t *geo;
    gw_in_t *in;
    double last_s; // the latest time an Entity State PDU said
} s_ctx_t;

static gw_action_t s_action, s_action2; // 6 KB each: kept out of the stack
static uint8_t s_enc[65536];

static bool s_same_f32 (const float *a, const float *b, size_t n)
{
    return memcmp (a, b, n * sizeof *a) == 0;
}

static bool s_same_header (const gw_header_t *a, const gw_header_t *b)
{
    return a->version == b->version && a->exercise == b->exercise && a->type == b->type &&
           a->timestamp == b->timestamp && a->status == b->status;
}

/* Encode an Entity State PDU again and decode that: the fields must survive.
 * Variable parameter records are not kept by the decoder nor written by the
 * encoder, so the count goes to 0 (the length to 144). */
static void s_check_espdu (const gw_espdu_t *e)
{
    gw_espdu_t a = *e, b;
    a.n_params = 0;
    size_t n = gw_pdu_encode_espdu (&a, s_enc, sizeof s_enc);
    if (n != GW_ESPDU_LEN)
        abort (); // a decoded PDU that does not encode
    const char *why = NULL;
    if (gw_pdu_decode_espdu (s_enc, n, &b, &why) < 0)
        abort (); // its encoding does not decode
    if (!s_same_header (&a.hdr, &b.hdr) || b.hdr.length != GW_ESPDU_LEN ||
        b.hdr.family != GW_FAMILY_ENTITY_INFORMATION || !gw_pdu_id_eq (a.id, b.id) ||
        a.force != b.force || b.n_params != 0 || memcmp (&a.type, &b.type, sizeof a.type) ||
        memcmp (&a.alt_type, &b.alt_type, sizeof a.alt_type) ||
        !s_same_f32 (a.velocity, b.velocity, 3) ||
        memcmp (a.location, b.location, sizeof a.location) ||
        !s_same_f32 (a.orientation, b.orientation, 3) || a.appearance != b.appearance ||
        a.dr_algorithm != b.dr_algorithm || memcmp (a.dr_other, b.dr_other, sizeof a.dr_other) ||
        !s_same_f32 (a.acceleration, b.acceleration, 3) ||
        !s_same_f32 (a.angular_velocity, b.angular_velocity, 3) ||
        a.marking_charset != b.marking_charset || strcmp (a.marking, b.marking) ||
        a.capabilities != b.capabilities)
        abort (); // a field changed on the way
}

/* The same for an Action Request or Response. The decoder takes PDUs up to
 * 65535 bytes, the encoder writes at most GW_PDU_MAX: longer ones are not
 * encoded again. */
static void s_check_action (const gw_action_t *a, size_t len)
{
    size_t n = gw_pdu_encode_action (a, s_enc, sizeof s_enc);
    if (len > GW_PDU_MAX) {
        if (n != 0)
            abort (); // the encoder wrote more than it says it ever writes
        return;
    }
    if (n != len)
        abort (); // a decoded PDU that does not encode to its own length
    const char *why = NULL;
    gw_action_t *b = &s_action2;
    if (gw_pdu_decode_action (s_enc, n, b, &why) < 0)
        abort ();
    if (!s_same_header (&a->hdr, &b->hdr) || b->hdr.length != len ||
        b->hdr.family != GW_FAMILY_SIMULATION_MANAGEMENT ||
        !gw_pdu_id_eq (a->originator, b->originator) || !gw_pdu_id_eq (a->receiver, b->receiver) ||
        a->request_id != b->request_id || a->action_or_status != b->action_or_status ||
        a->n_fixed != b->n_fixed || a->n_var != b->n_var ||
        memcmp (a->fixed, b->fixed, a->n_fixed * sizeof *a->fixed))
        abort ();
    for (uint32_t i = 0; i < a->n_var; i++) {
        const gw_var_datum_t *x = &a->var[i], *y = &b->var[i];
        size_t used = ((size_t)x->length_bits + 7) / 8;
        if (x->id != y->id || x->length_bits != y->length_bits ||
            (used && memcmp (x->value, y->value, used)))
            abort ();
    }
}

/* The entity as the gateway publishes it: when the conversion succeeds,
 * every number in it is finite. */
static void s_publish (const s_ctx_t *c, const gw_in_entity_t *e, double now_s)
{
    gw_in_storage_t st;
    Cgs__Entity m;
    if (gw_in_entity_msg (c->geo, e, now_s, &st, &m) < 0)
        return;
    if (!isfinite (m.heading_deg) || !isfinite (m.pitch_deg) || !isfinite (m.roll_deg) ||
        !isfinite (m.speed_mps) || !isfinite (m.position->east_m) ||
        !isfinite (m.velocity->up_mps) || strlen (m.marking) > GW_MARKING_LEN)
        abort ();
}

static void s_on_expired (void *arg, const gw_in_entity_t *e)
{
    const s_ctx_t *c = arg;
    s_publish (c, e, c->last_s);
}

/* Every entity in the table is found again by its DIS id. */
static void s_check_table (const gw_in_t *in)
{
    size_t cursor = 0, n = 0;
    const gw_in_entity_t *e;
    while ((e = gw_in_next (in, &cursor))) {
        if (gw_in_find (in, e->dis_id) != e)
            abort ();
        n++;
    }
    if (n != gw_in_count (in) || n > S_TABLE_MAX)
        abort ();
}

static void s_inbound (s_ctx_t *c, const gw_espdu_t *e)
{
    double t = gw_pdu_timestamp_seconds (e->hdr.timestamp, NULL);
    if (t > c->last_s)
        c->last_s = t;
    bool fresh = false;
    if (gw_in_take (c->in, e, t, &fresh) == 0) {
        const gw_in_entity_t *x = gw_in_find (c->in, e->id);
        if (!x)
            abort (); // taken but not found
        // As published now, and as dead-reckoned a little and a long while later.
        s_publish (c, x, t);
        s_publish (c, x, t + 0.25);
        s_publish (c, x, t + 11.0);
    }
    gw_in_expire (c->in, c->last_s, S_TIMEOUT_S, s_on_expired, c);
    s_check_table (c->in);
}

/* One PDU (or a whole datagram taken as one) through every decoder. */
static void s_on_pdu (void *arg, const uint8_t *pdu, size_t len)
{
    s_ctx_t *c = arg;
    const char *why = NULL;
    gw_header_t h;
    int hrc = gw_pdu_decode_header (pdu, len, &h, &why);
    if (hrc < 0 && !why)
        abort (); // rejected without a reason
    gw_espdu_t e;
    why = NULL;
    if (gw_pdu_decode_espdu (pdu, len, &e, &why) == 0) {
        if (hrc < 0)
            abort (); // a whole PDU whose header alone does not decode
        s_check_espdu (&e);
        s_inbound (c, &e);
    } else if (!why)
        abort ();
    why = NULL;
    if (gw_pdu_decode_action (pdu, len, &s_action, &why) == 0) {
        if (hrc < 0)
            abort ();
        s_check_action (&s_action, len);
    } else if (!why)
        abort ();
}

int LLVMFuzzerTestOneInput (const uint8_t *data, size_t size)
{
    static cgs_geo_t *geo;
    if (!geo && !(geo = cgs_geo_new (35.96, -121.23, 0)))
        abort ();
    s_ctx_t c = {geo, gw_in_new (100000, S_TABLE_MAX), 0};
    if (!c.in)
        return 0;
    const char *why = NULL;
    int n = gw_pdu_walk (data, size, s_on_pdu, &c, &why);
    if (n < 0 && !why)
        abort ();
    s_on_pdu (&c, data, size); // the datagram as one PDU: the length field checked against it
    // Everything goes: the deactivated and the silent, each published once more.
    c.last_s += 2 * S_TIMEOUT_S;
    gw_in_expire (c.in, c.last_s, S_TIMEOUT_S, s_on_expired, &c);
    if (gw_in_count (c.in) != 0)
        abort ();
    gw_in_destroy (&c.in);
    return 0;
}
