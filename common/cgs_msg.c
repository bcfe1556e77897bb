/* cgs_msg — protobuf-c encode/decode, arena, header access, JSON printing. */
#include "cgs_msg.h"
#include "cgs_track_status.h"

#include <ctype.h>
#include <errno.h>
#include <inttypes.h>
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

/* The cores' track status is the message's. */
_Static_assert((int)CGS_TRACK_TENTATIVE == (int)CGS__TRACK_STATUS__TRACK_STATUS_TENTATIVE &&
                   (int)CGS_TRACK_CONFIRMED == (int)CGS__TRACK_STATUS__TRACK_STATUS_CONFIRMED &&
                   (int)CGS_TRACK_COASTING == (int)CGS__TRACK_STATUS__TRACK_STATUS_COASTING &&
                   (int)CGS_TRACK_DELETED == (int)CGS__TRACK_STATUS__TRACK_STATUS_DELETED,
               "cgs_track_status_t and cgs.TrackStatus differ");

/* ---- arena ------------------------------------------------------------------ */

typedef struct s_block {
    struct s_block *next;
    size_t size; // usable bytes after the header
    size_t used;
    max_align_t data[];
} s_block_t;

struct cgs_msg_arena {
    s_block_t *first; // kept across resets
    s_block_t *extra; // overflow blocks, freed at reset
    ProtobufCAllocator allocator;
};

static s_block_t *s_block_new (size_t size)
{
    s_block_t *b = malloc (sizeof *b + size);
    if (b) {
        b->next = NULL;
        b->size = size;
        b->used = 0;
    }
    return b;
}

static void *s_arena_alloc (void *data, size_t size)
{
    cgs_msg_arena_t *self = data;
    size = (size + sizeof (max_align_t) - 1) & ~(sizeof (max_align_t) - 1);
    s_block_t *b = self->extra ? self->extra : self->first;
    if (b->size - b->used < size) {
        size_t want = size > self->first->size ? size : self->first->size;
        b = s_block_new (want);
        if (!b)
            return NULL;
        b->next = self->extra;
        self->extra = b;
    }
    void *p = (char *)b->data + b->used;
    b->used += size;
    return p;
}

static void s_arena_free (void *data, void *ptr)
{
    (void)data;
    (void)ptr; // freed all at once by cgs_msg_arena_reset
}

cgs_msg_arena_t *cgs_msg_arena_new (size_t block_size)
{
    cgs_msg_arena_t *self = calloc (1, sizeof *self);
    if (!self)
        return NULL;
    self->first = s_block_new (block_size ? block_size : 65536);
    if (!self->first) {
        free (self);
        return NULL;
    }
    self->allocator.alloc = s_arena_alloc;
    self->allocator.free = s_arena_free;
    self->allocator.allocator_data = self;
    return self;
}

void cgs_msg_arena_reset (cgs_msg_arena_t *self)
{
    if (!self)
        return;
    while (self->extra) {
        s_block_t *next = self->extra->next;
        free (self->extra);
        self->extra = next;
    }
    self->first->used = 0;
}

void cgs_msg_arena_destroy (cgs_msg_arena_t **self_p)
{
    if (!self_p || !*self_p)
        return;
    cgs_msg_arena_t *self = *self_p;
    cgs_msg_arena_reset (self);
    free (self->first);
    free (self);
    *self_p = NULL;
}

/* ---- encode / decode ---------------------------------------------------------- */

int cgs_msg_decode (const ProtobufCMessageDescriptor *desc, const void *data, size_t len,
                    cgs_msg_arena_t *arena, ProtobufCMessage **ret_msg)
{
    ProtobufCMessage *m =
        protobuf_c_message_unpack (desc, arena ? &arena->allocator : NULL, len, data);
    if (!m)
        return -EPROTO;
    *ret_msg = m;
    return 0;
}

void cgs_msg_free (ProtobufCMessage **msg_p)
{
    if (!msg_p || !*msg_p)
        return;
    protobuf_c_message_free_unpacked (*msg_p, NULL);
    *msg_p = NULL;
}

size_t cgs_msg_size (const ProtobufCMessage *msg)
{
    return protobuf_c_message_get_packed_size (msg);
}

size_t cgs_msg_encode (const ProtobufCMessage *msg, uint8_t *buf)
{
    return protobuf_c_message_pack (msg, buf);
}

int cgs_msg_encode_alloc (const ProtobufCMessage *msg, uint8_t **ret_buf, size_t *ret_len)
{
    size_t n = cgs_msg_size (msg);
    uint8_t *buf = malloc (n ? n : 1);
    if (!buf)
        return -ENOMEM;
    *ret_len = cgs_msg_encode (msg, buf);
    *ret_buf = buf;
    return 0;
}

/* ---- header ------------------------------------------------------------------- */

Cgs__Header **cgs_msg_header_slot (ProtobufCMessage *msg)
{
    if (!msg)
        return NULL;
    // protobuf-c keeps fields sorted by number, so field 1 comes first when present.
    const ProtobufCMessageDescriptor *d = msg->descriptor;
    const ProtobufCFieldDescriptor *f = d->n_fields > 0 ? &d->fields[0] : NULL;
    if (!f || f->id != 1 || f->type != PROTOBUF_C_TYPE_MESSAGE ||
        f->descriptor != &cgs__header__descriptor || f->label == PROTOBUF_C_LABEL_REPEATED)
        return NULL;
    return (Cgs__Header **)((char *)msg + f->offset);
}

const Cgs__Header *cgs_msg_header (const ProtobufCMessage *msg)
{
    Cgs__Header **slot = cgs_msg_header_slot ((ProtobufCMessage *)msg);
    return slot ? *slot : NULL;
}

/* ---- stamped messages: the header by hand --------------------------------------- */

#define S_HDR_FIXED 48 // field tags, lengths and the fixed-size fields of a Header

static size_t s_put_varint (uint8_t *p, uint64_t v)
{
    size_t n = 0;
    while (v >= 0x80) {
        p[n++] = (uint8_t)(v | 0x80);
        v >>= 7;
    }
    p[n++] = (uint8_t)v;
    return n;
}

/* A double as its 8 little-endian bytes (the wire's byte order on any host). */
static void s_put_double (uint8_t *p, double d)
{
#if __BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__
    memcpy (p, &d, 8);
#else
    uint64_t bits;
    memcpy (&bits, &d, 8);
    for (int i = 0; i < 8; i++)
        p[i] = (uint8_t)(bits >> (8 * i));
#endif
}

static double s_get_double (const uint8_t *p)
{
    double d;
#if __BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__
    memcpy (&d, p, 8);
#else
    uint64_t bits = 0;
    for (int i = 0; i < 8; i++)
        bits |= (uint64_t)p[i] << (8 * i);
    memcpy (&d, &bits, 8);
#endif
    return d;
}

/* Read a varint at *i (before end); 0, or -1 when it is cut short or too long. */
static int s_get_varint (const uint8_t *p, size_t end, size_t *i, uint64_t *v)
{
    size_t k = *i;
    if (k < end && p[k] < 0x80) { // the common one-byte case
        *v = p[k];
        *i = k + 1;
        return 0;
    }
    uint64_t r = 0;
    for (unsigned shift = 0; shift < 64 && k < end; shift += 7) {
        uint8_t b = p[k++];
        r |= (uint64_t)(b & 0x7f) << shift;
        if (!(b & 0x80)) {
            *v = r;
            *i = k;
            return 0;
        }
    }
    return -1;
}

size_t cgs_msg_stamped_size_max (ProtobufCMessage *msg)
{
    Cgs__Header **slot = cgs_msg_header_slot (msg);
    Cgs__Header *saved = slot ? *slot : NULL;
    if (slot)
        *slot = NULL;
    size_t n = cgs_msg_size (msg);
    if (slot)
        *slot = saved;
    return n + S_HDR_FIXED + 2 * 10 + 256; // varints of 10 bytes, a source of up to 255
}

int cgs_msg_encode_stamped_grow (ProtobufCMessage *msg, const Cgs__Header *h, uint8_t **buf,
                                 size_t *cap, size_t *ret_len)
{
    size_t len = 0;
    int rc = cgs_msg_encode_stamped (msg, h, *buf, *cap, &len);
    if (rc == -ENOBUFS) {
        size_t n = *cap ? *cap : 256;
        while (n < len)
            n *= 2;
        uint8_t *nb = realloc (*buf, n);
        if (!nb)
            return -ENOMEM;
        *buf = nb;
        *cap = n;
        rc = cgs_msg_encode_stamped (msg, h, *buf, *cap, &len);
    }
    if (rc == 0)
        *ret_len = len;
    return rc;
}

int cgs_msg_encode_stamped (ProtobufCMessage *msg, const Cgs__Header *h, uint8_t *buf, size_t cap,
                            size_t *ret_len)
{
    Cgs__Header **slot = cgs_msg_header_slot (msg);
    if (!slot)
        return -EINVAL;
    const char *src = h->source ? h->source : "";
    size_t sl = strlen (src);
    if (sl > 255)
        return -EINVAL;
    uint8_t hdr[S_HDR_FIXED + 2 * 10 + 256];
    size_t n = 0;
    if (sl) {
        hdr[n++] = 0x0a; // 1: source
        n += s_put_varint (hdr + n, sl);
        memcpy (hdr + n, src, sl);
        n += sl;
    }
    if (h->exercise_id) {
        hdr[n++] = 0x10; // 2: exercise_id
        n += s_put_varint (hdr + n, h->exercise_id);
    }
    if (h->epoch) {
        hdr[n++] = 0x18; // 3: epoch
        n += s_put_varint (hdr + n, h->epoch);
    }
    if (h->seq) {
        hdr[n++] = 0x20; // 4: seq
        n += s_put_varint (hdr + n, h->seq);
    }
    if (h->sim_time_s != 0) {
        hdr[n++] = 0x29; // 5: sim_time_s, 64-bit
        s_put_double (hdr + n, h->sim_time_s);
        n += 8;
    }
    if (h->wall_time_s != 0) {
        hdr[n++] = 0x31; // 6: wall_time_s, 64-bit
        s_put_double (hdr + n, h->wall_time_s);
        n += 8;
    }
    Cgs__Header *saved = *slot;
    *slot = NULL;
    size_t rest = cgs_msg_size (msg);
    size_t total = 1 + 10 + n + rest;
    if (total > cap) {
        *slot = saved;
        *ret_len = total;
        return -ENOBUFS;
    }
    size_t m = 0;
    buf[m++] = 0x0a; // field 1 of the message, length-delimited
    m += s_put_varint (buf + m, n);
    memcpy (buf + m, hdr, n);
    m += n;
    m += cgs_msg_encode (msg, buf + m);
    *slot = saved;
    *ret_len = m;
    return 0;
}

/* Parse a leading `1: Header`; 0 and the offset past it, or -1 to fall back. */
static int s_get_header (const uint8_t *p, size_t len, Cgs__Header *h, char *src, size_t src_size,
                         size_t *ret_end)
{
    size_t i = 1;
    uint64_t v;
    if (len < 2 || p[0] != 0x0a || s_get_varint (p, len, &i, &v) || v > len - i)
        return -1;
    size_t end = i + (size_t)v;
    cgs__header__init (h);
    src[0] = '\0';
    h->source = src;
    while (i < end) {
        uint8_t tag = p[i++];
        switch (tag) {
        case 0x0a:
            if (s_get_varint (p, end, &i, &v) || v > end - i || v >= src_size ||
                memchr (p + i, 0, (size_t)v))
                return -1;
            memcpy (src, p + i, (size_t)v);
            src[v] = '\0';
            i += (size_t)v;
            break;
        case 0x10:
            if (s_get_varint (p, end, &i, &v))
                return -1;
            h->exercise_id = (uint32_t)v;
            break;
        case 0x18:
            if (s_get_varint (p, end, &i, &h->epoch))
                return -1;
            break;
        case 0x20:
            if (s_get_varint (p, end, &i, &h->seq))
                return -1;
            break;
        case 0x29:
        case 0x31:
            if (end - i < 8)
                return -1;
            *(tag == 0x29 ? &h->sim_time_s : &h->wall_time_s) = s_get_double (p + i);
            i += 8;
            break;
        default:
            return -1; // anything unusual: protobuf-c judges it
        }
    }
    *ret_end = end;
    return 0;
}

int cgs_msg_decode_stamped (const ProtobufCMessageDescriptor *desc, const void *data, size_t len,
                            cgs_msg_arena_t *arena, Cgs__Header *hdr, char *src, size_t src_size,
                            ProtobufCMessage **ret_msg)
{
    const uint8_t *p = data;
    size_t end = 0;
    ProtobufCMessage *m = NULL;
    if (arena && src_size > 0 && s_get_header (p, len, hdr, src, src_size, &end) == 0 &&
        cgs_msg_decode (desc, p + end, len - end, arena, &m) == 0) {
        Cgs__Header **slot = cgs_msg_header_slot (m);
        if (slot && !*slot) {
            *slot = hdr;
            *ret_msg = m;
            return 0;
        }
        // The rest carried a header of its own (or the type has none): decode
        // the whole payload the ordinary way, so protobuf's merge rules apply.
    }
    return cgs_msg_decode (desc, data, len, arena, ret_msg);
}

/* ---- JSON --------------------------------------------------------------------- */

typedef struct {
    char *buf;
    size_t len, cap;
    bool failed;
} s_out_t;

static void s_put (s_out_t *o, const char *s, size_t n)
{
    if (o->failed)
        return;
    if (o->len + n + 1 > o->cap) {
        size_t cap = o->cap ? o->cap * 2 : 256;
        while (cap < o->len + n + 1)
            cap *= 2;
        char *nb = realloc (o->buf, cap);
        if (!nb) {
            o->failed = true;
            return;
        }
        o->buf = nb;
        o->cap = cap;
    }
    memcpy (o->buf + o->len, s, n);
    o->len += n;
    o->buf[o->len] = '\0';
}

static void s_puts (s_out_t *o, const char *s)
{
    s_put (o, s, strlen (s));
}

static void s_printf (s_out_t *o, const char *fmt, ...) __attribute__ ((format (printf, 2, 3)));
static void s_printf (s_out_t *o, const char *fmt, ...)
{
    char tmp[64];
    va_list ap;
    va_start (ap, fmt);
    int n = vsnprintf (tmp, sizeof tmp, fmt, ap);
    va_end (ap);
    if (n > 0)
        s_put (o, tmp, (size_t)n < sizeof tmp ? (size_t)n : sizeof tmp - 1);
}

static void s_json_string (s_out_t *o, const char *s, size_t n)
{
    s_puts (o, "\"");
    for (size_t i = 0; i < n; i++) {
        unsigned char c = (unsigned char)s[i];
        switch (c) {
        case '"':
            s_puts (o, "\\\"");
            break;
        case '\\':
            s_puts (o, "\\\\");
            break;
        case '\n':
            s_puts (o, "\\n");
            break;
        case '\r':
            s_puts (o, "\\r");
            break;
        case '\t':
            s_puts (o, "\\t");
            break;
        default:
            if (c < 0x20)
                s_printf (o, "\\u%04x", c);
            else
                s_put (o, (const char *)&s[i], 1);
        }
    }
    s_puts (o, "\"");
}

static void s_json_base64 (s_out_t *o, const uint8_t *d, size_t n)
{
    static const char tbl[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    s_puts (o, "\"");
    for (size_t i = 0; i < n; i += 3) {
        uint32_t v = (uint32_t)d[i] << 16;
        if (i + 1 < n)
            v |= (uint32_t)d[i + 1] << 8;
        if (i + 2 < n)
            v |= d[i + 2];
        char q[4] = {tbl[(v >> 18) & 63], tbl[(v >> 12) & 63], i + 1 < n ? tbl[(v >> 6) & 63] : '=',
                     i + 2 < n ? tbl[v & 63] : '='};
        s_put (o, q, 4);
    }
    s_puts (o, "\"");
}

static void s_json_double (s_out_t *o, double v)
{
    if (isnan (v))
        s_puts (o, "\"NaN\"");
    else if (isinf (v))
        s_puts (o, v > 0 ? "\"Infinity\"" : "\"-Infinity\"");
    else
        s_printf (o, "%.17g", v);
}

static void s_json_message (s_out_t *o, const ProtobufCMessage *m);

/* One value of a field at address p. */
static void s_json_value (s_out_t *o, const ProtobufCFieldDescriptor *f, const void *p)
{
    switch (f->type) {
    case PROTOBUF_C_TYPE_INT32:
    case PROTOBUF_C_TYPE_SINT32:
    case PROTOBUF_C_TYPE_SFIXED32:
        s_printf (o, "%" PRId32, *(const int32_t *)p);
        break;
    case PROTOBUF_C_TYPE_UINT32:
    case PROTOBUF_C_TYPE_FIXED32:
        s_printf (o, "%" PRIu32, *(const uint32_t *)p);
        break;
    case PROTOBUF_C_TYPE_INT64:
    case PROTOBUF_C_TYPE_SINT64:
    case PROTOBUF_C_TYPE_SFIXED64:
        s_printf (o, "\"%" PRId64 "\"", *(const int64_t *)p);
        break;
    case PROTOBUF_C_TYPE_UINT64:
    case PROTOBUF_C_TYPE_FIXED64:
        s_printf (o, "\"%" PRIu64 "\"", *(const uint64_t *)p);
        break;
    case PROTOBUF_C_TYPE_FLOAT:
        s_json_double (o, *(const float *)p);
        break;
    case PROTOBUF_C_TYPE_DOUBLE:
        s_json_double (o, *(const double *)p);
        break;
    case PROTOBUF_C_TYPE_BOOL:
        s_puts (o, *(const protobuf_c_boolean *)p ? "true" : "false");
        break;
    case PROTOBUF_C_TYPE_ENUM: {
        int v = *(const int *)p;
        const ProtobufCEnumValue *ev = protobuf_c_enum_descriptor_get_value (
            (const ProtobufCEnumDescriptor *)f->descriptor, v);
        if (ev)
            s_json_string (o, ev->name, strlen (ev->name));
        else
            s_printf (o, "%d", v);
        break;
    }
    case PROTOBUF_C_TYPE_STRING: {
        const char *s = *(char *const *)p;
        s = s ? s : "";
        s_json_string (o, s, strlen (s));
        break;
    }
    case PROTOBUF_C_TYPE_BYTES: {
        const ProtobufCBinaryData *b = p;
        s_json_base64 (o, b->data, b->len);
        break;
    }
    case PROTOBUF_C_TYPE_MESSAGE: {
        const ProtobufCMessage *sub = *(ProtobufCMessage *const *)p;
        if (sub)
            s_json_message (o, sub);
        else
            s_puts (o, "null");
        break;
    }
    }
}

static size_t s_type_size (ProtobufCType t)
{
    switch (t) {
    case PROTOBUF_C_TYPE_INT64:
    case PROTOBUF_C_TYPE_SINT64:
    case PROTOBUF_C_TYPE_SFIXED64:
    case PROTOBUF_C_TYPE_UINT64:
    case PROTOBUF_C_TYPE_FIXED64:
    case PROTOBUF_C_TYPE_DOUBLE:
        return 8;
    case PROTOBUF_C_TYPE_BOOL:
        return sizeof (protobuf_c_boolean);
    case PROTOBUF_C_TYPE_ENUM:
        return sizeof (int);
    case PROTOBUF_C_TYPE_STRING:
        return sizeof (char *);
    case PROTOBUF_C_TYPE_BYTES:
        return sizeof (ProtobufCBinaryData);
    case PROTOBUF_C_TYPE_MESSAGE:
        return sizeof (ProtobufCMessage *);
    default:
        return 4;
    }
}

/* True when a proto3 scalar holds its default and so is left out, as proto3 JSON does. */
static bool s_is_default (const ProtobufCFieldDescriptor *f, const void *p)
{
    switch (f->type) {
    case PROTOBUF_C_TYPE_STRING: {
        const char *s = *(char *const *)p;
        return !s || !*s;
    }
    case PROTOBUF_C_TYPE_BYTES:
        return ((const ProtobufCBinaryData *)p)->len == 0;
    case PROTOBUF_C_TYPE_MESSAGE:
        return *(ProtobufCMessage *const *)p == NULL;
    case PROTOBUF_C_TYPE_DOUBLE:
        return *(const double *)p == 0.0 && !signbit (*(const double *)p);
    case PROTOBUF_C_TYPE_FLOAT:
        return *(const float *)p == 0.0f && !signbit (*(const float *)p);
    default: {
        uint8_t zero[8] = {0};
        return memcmp (p, zero, s_type_size (f->type)) == 0;
    }
    }
}

static void s_json_message (s_out_t *o, const ProtobufCMessage *m)
{
    const ProtobufCMessageDescriptor *d = m->descriptor;
    const char *base = (const char *)m;
    bool first = true;
    s_puts (o, "{");
    for (unsigned i = 0; i < d->n_fields; i++) {
        const ProtobufCFieldDescriptor *f = &d->fields[i];
        const void *p = base + f->offset;
        if (f->label == PROTOBUF_C_LABEL_REPEATED) {
            size_t n = *(const size_t *)(base + f->quantifier_offset);
            if (n == 0)
                continue;
            s_puts (o, first ? "\"" : ",\"");
            s_puts (o, f->name);
            s_puts (o, "\":[");
            const char *arr = *(char *const *)p;
            for (size_t k = 0; k < n; k++) {
                if (k)
                    s_puts (o, ",");
                s_json_value (o, f, arr + k * s_type_size (f->type));
            }
            s_puts (o, "]");
            first = false;
            continue;
        }
        if (f->flags & PROTOBUF_C_FIELD_FLAG_ONEOF) {
            uint32_t which = *(const uint32_t *)(base + f->quantifier_offset);
            if (which != f->id)
                continue;
        } else if (f->label == PROTOBUF_C_LABEL_OPTIONAL && f->quantifier_offset &&
                   f->type != PROTOBUF_C_TYPE_MESSAGE && f->type != PROTOBUF_C_TYPE_STRING) {
            if (!*(const protobuf_c_boolean *)(base + f->quantifier_offset))
                continue;
        } else if (s_is_default (f, p)) {
            continue;
        }
        s_puts (o, first ? "\"" : ",\"");
        s_puts (o, f->name);
        s_puts (o, "\":");
        s_json_value (o, f, p);
        first = false;
    }
    s_puts (o, "}");
}

int cgs_msg_to_json (const ProtobufCMessage *msg, char **ret_json)
{
    s_out_t o = {0};
    s_json_message (&o, msg);
    if (o.failed || !o.buf) {
        free (o.buf);
        return -ENOMEM;
    }
    *ret_json = o.buf;
    return 0;
}

int cgs_msg_print_json (FILE *f, const ProtobufCMessage *msg)
{
    char *json = NULL;
    int rc = cgs_msg_to_json (msg, &json);
    if (rc < 0)
        return rc;
    int n = fprintf (f, "%s\n", json);
    free (json);
    return n < 0 ? -EIO : 0;
}

const char *cgs_msg_enum_short (const ProtobufCEnumDescriptor *desc, int value,
                                const char *fallback)
{
    const ProtobufCEnumValue *ev = protobuf_c_enum_descriptor_get_value (desc, value);
    if (!ev)
        return fallback;
    // The prefix is the enum's CamelCase name in UPPER_SNAKE, and a '_'.
    const char *n = ev->name, *c = desc->short_name;
    for (; *c; c++, n++) {
        if (c != desc->short_name && isupper ((unsigned char)*c) && *n++ != '_')
            return ev->name;
        if (toupper ((unsigned char)*c) != *n)
            return ev->name;
    }
    return *n == '_' && n[1] ? n + 1 : ev->name;
}

int cgs_msg_uav_camera (const Cgs__Uav *u, cgs_camera_in_t *in)
{
    if (!u || !in || !u->position || !u->sensor || !isfinite (u->position->east_m) ||
        !isfinite (u->position->north_m) || !isfinite (u->position->up_m) ||
        !isfinite (u->heading_deg) || !isfinite (u->pitch_deg) || !isfinite (u->roll_deg) ||
        !isfinite (u->sensor->depression_deg) || !isfinite (u->sensor->hfov_deg) ||
        !isfinite (u->sensor->vfov_deg))
        return -EINVAL;
    const Cgs__ImagingSensor *s = u->sensor;
    bool staring = s->staring && s->stare_point && isfinite (s->stare_point->east_m) &&
                   isfinite (s->stare_point->north_m) && isfinite (s->stare_point->up_m);
    in->position = (cgs_enu_t){u->position->east_m, u->position->north_m, u->position->up_m};
    in->heading_deg = u->heading_deg;
    in->pitch_deg = u->pitch_deg;
    in->roll_deg = u->roll_deg;
    in->depression_deg = s->depression_deg;
    in->hfov_deg = s->hfov_deg;
    in->vfov_deg = s->vfov_deg;
    in->point.stabilized = s->stabilized;
    in->point.staring = staring;
    in->point.stare_at =
        staring ? (cgs_enu_t){s->stare_point->east_m, s->stare_point->north_m, s->stare_point->up_m}
                : (cgs_enu_t){0, 0, 0};
    in->point.gimbal_limited = s->gimbal_azimuth_limit_deg > 0;
    in->point.gimbal_azimuth_deg = s->gimbal_azimuth_limit_deg;
    in->point.gimbal_elevation_min_deg = s->gimbal_elevation_min_deg;
    in->point.gimbal_elevation_max_deg = s->gimbal_elevation_max_deg;
    return 0;
}
