/* cgs_msg — protobuf-c encode/decode, arena, header access, JSON printing. */
#include "cgs_msg.h"

#include <errno.h>
#include <inttypes.h>
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

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
    const ProtobufCFieldDescriptor *f =
        protobuf_c_message_descriptor_get_field (msg->descriptor, 1);
    if (!f || f->type != PROTOBUF_C_TYPE_MESSAGE || f->descriptor != &cgs__header__descriptor ||
        f->label == PROTOBUF_C_LABEL_REPEATED)
        return NULL;
    return (Cgs__Header **)((char *)msg + f->offset);
}

const Cgs__Header *cgs_msg_header (const ProtobufCMessage *msg)
{
    Cgs__Header **slot = cgs_msg_header_slot ((ProtobufCMessage *)msg);
    return slot ? *slot : NULL;
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
