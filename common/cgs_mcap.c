/* cgs_mcap — see cgs_mcap.h. The layout follows the MCAP specification
 * (mcap.dev/spec): little-endian integers, strings with a u32 length, maps
 * and arrays with a u32 byte length, each record an opcode, a u64 length and
 * its content. */
#include "cgs_mcap.h"

#include <errno.h>
#include <fcntl.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zlib.h>
#include <zstd.h>

#include "cgs_util.h"

#define S_MAGIC        "\x89MCAP0\r\n"
#define S_MAGIC_LEN    8
#define S_OP_HEADER    0x01
#define S_OP_FOOTER    0x02
#define S_OP_SCHEMA    0x03
#define S_OP_CHANNEL   0x04
#define S_OP_MESSAGE   0x05
#define S_OP_CHUNK     0x06
#define S_OP_MSG_INDEX 0x07
#define S_OP_CHUNK_IDX 0x08
#define S_OP_STATS     0x0B
#define S_OP_SUM_OFF   0x0E
#define S_OP_DATA_END  0x0F
#define S_MAX_IDS      65535
#define S_MAX_CHUNK    ((uint64_t)1 << 28) // a chunk the reader takes (the writer's are 1 MiB)

/* ---- a growable byte buffer ---------------------------------------------------------------- */

typedef struct {
    uint8_t *p;
    size_t len, cap;
    bool oom;
} s_buf_t;

static void s_put (s_buf_t *b, const void *data, size_t n)
{
    if (b->oom || cgs_grow ((void **)&b->p, &b->cap, b->len + n, 1) < 0) {
        b->oom = true;
        return;
    }
    if (n)
        memcpy (b->p + b->len, data, n);
    b->len += n;
}

static void s_u8 (s_buf_t *b, uint8_t v)
{
    s_put (b, &v, 1);
}

static void s_le (s_buf_t *b, uint64_t v, int n)
{
    uint8_t x[8];
    for (int i = 0; i < n; i++)
        x[i] = (uint8_t)(v >> (8 * i));
    s_put (b, x, (size_t)n);
}

static void s_u16 (s_buf_t *b, uint16_t v)
{
    s_le (b, v, 2);
}
static void s_u32 (s_buf_t *b, uint32_t v)
{
    s_le (b, v, 4);
}
static void s_u64 (s_buf_t *b, uint64_t v)
{
    s_le (b, v, 8);
}

static void s_str (s_buf_t *b, const char *s)
{
    size_t n = strlen (s);
    s_u32 (b, (uint32_t)n);
    s_put (b, s, n);
}

/* Start a record: its opcode and a length patched by s_end. */
static size_t s_begin (s_buf_t *b, uint8_t op)
{
    s_u8 (b, op);
    size_t at = b->len;
    s_u64 (b, 0);
    return at;
}

static void s_end (s_buf_t *b, size_t at)
{
    if (b->oom)
        return;
    uint64_t n = b->len - at - 8;
    for (int i = 0; i < 8; i++)
        b->p[at + i] = (uint8_t)(n >> (8 * i));
}

static uint64_t s_get (const uint8_t *p, int n)
{
    uint64_t v = 0;
    for (int i = 0; i < n; i++)
        v |= (uint64_t)p[i] << (8 * i);
    return v;
}

/* ---- writer ------------------------------------------------------------------------------ */

typedef struct {
    s_buf_t rec;  // its record, as written (for the summary)
    bool in_data; // written in the data section already
} s_def_t;

typedef struct {
    s_buf_t rec;
    uint16_t schema_id;
    bool in_data;
    uint64_t count; // messages in the file
    s_buf_t index;  // this chunk's (log time, offset) pairs, 16 bytes each
} s_chan_t;

struct cgs_mcap_writer {
    int fd;
    char path[4096];
    char error[256];
    cgs_mcap_options_t o;
    uint64_t offset; // bytes in the file
    uLong data_crc;  // of the data section so far
    s_def_t *schemas;
    size_t n_schemas, cap_schemas;
    s_chan_t *chans;
    size_t n_chans, cap_chans;
    s_buf_t chunk; // the open chunk's records, uncompressed
    uint64_t chunk_start, chunk_end;
    uint64_t chunk_messages;
    s_buf_t chunk_indexes; // ChunkIndex records for the summary
    s_buf_t out;           // scratch
    s_buf_t zbuf;
    ZSTD_CCtx *zctx;
    uint64_t messages, start_ns, end_ns;
    uint32_t chunks;
};

static int s_fail (cgs_mcap_writer_t *self, const char *what, int e)
{
    if (!self->error[0])
        snprintf (self->error, sizeof self->error, "%s: %s: %s", self->path, what, strerror (e));
    return -EIO;
}

/* Write b out and add it to the data CRC (when data is true). */
static int s_write (cgs_mcap_writer_t *self, const uint8_t *p, size_t n, bool data)
{
    if (self->error[0])
        return -EIO;
    if (data)
        self->data_crc = crc32_z (self->data_crc, p, n);
    size_t done = 0;
    while (done < n) {
        ssize_t w = write (self->fd, p + done, n - done);
        if (w < 0 && errno == EINTR)
            continue;
        if (w <= 0)
            return s_fail (self, "cannot write", w < 0 ? errno : EIO);
        done += (size_t)w;
    }
    self->offset += n;
    return 0;
}

cgs_mcap_writer_t *cgs_mcap_writer_open (const char *path, const cgs_mcap_options_t *o, char *err,
                                         size_t errlen)
{
    cgs_mcap_writer_t *self = calloc (1, sizeof *self);
    if (!self) {
        cgs_errf (err, errlen, "%s: out of memory", path);
        return NULL;
    }
    if (o)
        self->o = *o;
    if (!self->o.chunk_bytes)
        self->o.chunk_bytes = 1u << 20;
    snprintf (self->path, sizeof self->path, "%s", path);
    self->fd = open (path, O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (self->fd < 0) {
        cgs_errf (err, errlen, "%s: cannot create: %s", path, strerror (errno));
        free (self);
        return NULL;
    }
    self->data_crc = crc32 (0L, Z_NULL, 0);
    if (self->o.compress && !(self->zctx = ZSTD_createCCtx ())) {
        cgs_errf (err, errlen, "%s: out of memory for zstd", path);
        close (self->fd);
        free (self);
        return NULL;
    }
    s_buf_t b = {0};
    s_put (&b, S_MAGIC, S_MAGIC_LEN);
    size_t at = s_begin (&b, S_OP_HEADER);
    s_str (&b, "");
    s_str (&b, self->o.library ? self->o.library : "mscgs");
    s_end (&b, at);
    int rc = b.oom ? -ENOMEM : s_write (self, b.p, b.len, true);
    free (b.p);
    if (rc < 0) {
        cgs_errf (err, errlen, "%s", self->error[0] ? self->error : "out of memory");
        close (self->fd);
        self->fd = -1;
        cgs_mcap_writer_close (&self, NULL, 0);
        return NULL;
    }
    return self;
}

int cgs_mcap_writer_schema (cgs_mcap_writer_t *self, const char *name, const char *encoding,
                            const uint8_t *data, size_t len)
{
    if (self->n_schemas >= S_MAX_IDS)
        return -ENOSPC;
    if (cgs_grow ((void **)&self->schemas, &self->cap_schemas, self->n_schemas + 1,
                  sizeof *self->schemas) < 0)
        return -ENOMEM;
    s_def_t *d = &self->schemas[self->n_schemas];
    *d = (s_def_t){0};
    uint16_t id = (uint16_t)(self->n_schemas + 1);
    size_t at = s_begin (&d->rec, S_OP_SCHEMA);
    s_u16 (&d->rec, id);
    s_str (&d->rec, name);
    s_str (&d->rec, encoding);
    s_u32 (&d->rec, (uint32_t)len);
    s_put (&d->rec, data, len);
    s_end (&d->rec, at);
    if (d->rec.oom) {
        free (d->rec.p);
        return -ENOMEM;
    }
    self->n_schemas++;
    return id;
}

int cgs_mcap_writer_channel (cgs_mcap_writer_t *self, uint16_t schema_id, const char *topic,
                             const char *message_encoding, const char *const *meta_keys,
                             const char *const *meta_values, size_t n_meta)
{
    if (self->n_chans >= S_MAX_IDS)
        return -ENOSPC;
    if (schema_id > self->n_schemas)
        return -EINVAL;
    if (cgs_grow ((void **)&self->chans, &self->cap_chans, self->n_chans + 1, sizeof *self->chans) <
        0)
        return -ENOMEM;
    s_chan_t *c = &self->chans[self->n_chans];
    *c = (s_chan_t){.schema_id = schema_id};
    uint16_t id = (uint16_t)(self->n_chans + 1);
    size_t at = s_begin (&c->rec, S_OP_CHANNEL);
    s_u16 (&c->rec, id);
    s_u16 (&c->rec, schema_id);
    s_str (&c->rec, topic);
    s_str (&c->rec, message_encoding);
    // Map<string, string>: its byte length, then the pairs.
    size_t map_at = c->rec.len;
    s_u32 (&c->rec, 0);
    for (size_t i = 0; i < n_meta; i++) {
        s_str (&c->rec, meta_keys[i]);
        s_str (&c->rec, meta_values[i]);
    }
    if (!c->rec.oom) {
        uint32_t n = (uint32_t)(c->rec.len - map_at - 4);
        for (int i = 0; i < 4; i++)
            c->rec.p[map_at + i] = (uint8_t)(n >> (8 * i));
    }
    s_end (&c->rec, at);
    if (c->rec.oom) {
        free (c->rec.p);
        return -ENOMEM;
    }
    self->n_chans++;
    return id;
}

int cgs_mcap_writer_message (cgs_mcap_writer_t *self, uint16_t channel, uint32_t sequence,
                             uint64_t log_time_ns, uint64_t publish_time_ns, const uint8_t *data,
                             size_t len)
{
    if (self->error[0])
        return -EIO;
    if (channel == 0 || channel > self->n_chans)
        return -EINVAL;
    s_chan_t *c = &self->chans[channel - 1];
    s_buf_t *b = &self->chunk;
    // Its schema and channel in the data section before its first message.
    if (c->schema_id && !self->schemas[c->schema_id - 1].in_data) {
        s_def_t *d = &self->schemas[c->schema_id - 1];
        s_put (b, d->rec.p, d->rec.len);
        d->in_data = true;
    }
    if (!c->in_data) {
        s_put (b, c->rec.p, c->rec.len);
        c->in_data = true;
    }
    uint64_t at_chunk = b->len;
    size_t at = s_begin (b, S_OP_MESSAGE);
    s_u16 (b, channel);
    s_u32 (b, sequence);
    s_u64 (b, log_time_ns);
    s_u64 (b, publish_time_ns);
    s_put (b, data, len);
    s_end (b, at);
    s_u64 (&c->index, log_time_ns);
    s_u64 (&c->index, at_chunk);
    if (b->oom || c->index.oom)
        return s_fail (self, "out of memory for a chunk", ENOMEM);
    if (self->chunk_messages == 0 || log_time_ns < self->chunk_start)
        self->chunk_start = log_time_ns;
    if (self->chunk_messages == 0 || log_time_ns > self->chunk_end)
        self->chunk_end = log_time_ns;
    if (self->messages == 0 || log_time_ns < self->start_ns)
        self->start_ns = log_time_ns;
    if (self->messages == 0 || log_time_ns > self->end_ns)
        self->end_ns = log_time_ns;
    self->chunk_messages++;
    self->messages++;
    c->count++;
    if (b->len >= self->o.chunk_bytes)
        return cgs_mcap_writer_flush (self);
    return 0;
}

int cgs_mcap_writer_flush (cgs_mcap_writer_t *self)
{
    if (self->error[0])
        return -EIO;
    s_buf_t *ch = &self->chunk;
    if (ch->len == 0 || self->chunk_messages == 0)
        return 0;
    uLong crc = crc32_z (crc32_z (0L, Z_NULL, 0), ch->p, ch->len);
    const uint8_t *records = ch->p;
    size_t rlen = ch->len;
    const char *compression = "";
    if (self->zctx && ch->len >= 1024) {
        size_t bound = ZSTD_compressBound (ch->len);
        self->zbuf.len = 0;
        if (cgs_grow ((void **)&self->zbuf.p, &self->zbuf.cap, bound, 1) < 0)
            return s_fail (self, "out of memory for zstd", ENOMEM);
        size_t z = ZSTD_compressCCtx (self->zctx, self->zbuf.p, bound, ch->p, ch->len, 1);
        if (!ZSTD_isError (z) && (double)z * 1.02 < (double)ch->len) {
            records = self->zbuf.p, rlen = z, compression = "zstd";
        }
    }
    s_buf_t *o = &self->out;
    o->len = 0;
    uint64_t chunk_at = self->offset;
    size_t at = s_begin (o, S_OP_CHUNK);
    s_u64 (o, self->chunk_start);
    s_u64 (o, self->chunk_end);
    s_u64 (o, ch->len);
    s_u32 (o, (uint32_t)crc);
    s_str (o, compression);
    s_u64 (o, rlen);
    s_put (o, records, rlen);
    s_end (o, at);
    uint64_t chunk_len = o->len;
    // The message indexes, one per channel with messages in the chunk.
    s_buf_t offs = {0}; // Map<u16, u64> of their file offsets
    for (size_t i = 0; i < self->n_chans; i++) {
        s_chan_t *c = &self->chans[i];
        if (c->index.len == 0)
            continue;
        s_u16 (&offs, (uint16_t)(i + 1));
        s_u64 (&offs, chunk_at + o->len);
        size_t mi = s_begin (o, S_OP_MSG_INDEX);
        s_u16 (o, (uint16_t)(i + 1));
        s_u32 (o, (uint32_t)c->index.len);
        s_put (o, c->index.p, c->index.len);
        s_end (o, mi);
        c->index.len = 0;
    }
    uint64_t index_len = o->len - chunk_len;
    if (o->oom || offs.oom) {
        free (offs.p);
        return s_fail (self, "out of memory for a chunk", ENOMEM);
    }
    int rc = s_write (self, o->p, o->len, true);
    // Its index for the summary.
    s_buf_t *ci = &self->chunk_indexes;
    size_t cat = s_begin (ci, S_OP_CHUNK_IDX);
    s_u64 (ci, self->chunk_start);
    s_u64 (ci, self->chunk_end);
    s_u64 (ci, chunk_at);
    s_u64 (ci, chunk_len);
    s_u32 (ci, (uint32_t)offs.len);
    s_put (ci, offs.p, offs.len);
    s_u64 (ci, index_len);
    s_str (ci, compression);
    s_u64 (ci, rlen);
    s_u64 (ci, ch->len);
    s_end (ci, cat);
    free (offs.p);
    ch->len = 0;
    self->chunk_messages = 0;
    self->chunks++;
    if (ci->oom)
        return s_fail (self, "out of memory for the chunk index", ENOMEM);
    return rc;
}

uint64_t cgs_mcap_writer_messages (const cgs_mcap_writer_t *self)
{
    return self->messages;
}
uint32_t cgs_mcap_writer_chunks (const cgs_mcap_writer_t *self)
{
    return self->chunks;
}
uint64_t cgs_mcap_writer_bytes (const cgs_mcap_writer_t *self)
{
    return self->offset;
}
const char *cgs_mcap_writer_error (const cgs_mcap_writer_t *self)
{
    return self->error;
}

/* Append group to b with a SummaryOffset for it in offs (none when empty). */
static void s_group (s_buf_t *b, s_buf_t *offs, uint64_t base, uint8_t op, const uint8_t *p,
                     size_t n)
{
    if (n == 0)
        return;
    size_t at = s_begin (offs, S_OP_SUM_OFF);
    s_u8 (offs, op);
    s_u64 (offs, base + b->len);
    s_u64 (offs, n);
    s_end (offs, at);
    s_put (b, p, n);
}

/* The summary, summary offsets, footer and magic. */
static int s_finish (cgs_mcap_writer_t *self)
{
    int rc = cgs_mcap_writer_flush (self);
    if (rc < 0)
        return rc;
    s_buf_t end = {0};
    size_t at = s_begin (&end, S_OP_DATA_END);
    s_u32 (&end, (uint32_t)self->data_crc); // everything before DataEnd
    s_end (&end, at);
    rc = end.oom ? -ENOMEM : s_write (self, end.p, end.len, false);
    free (end.p);
    if (rc < 0)
        return rc;
    uint64_t summary_start = self->offset;
    s_buf_t sum = {0}, offs = {0}, grp = {0};
    for (size_t i = 0; i < self->n_schemas; i++)
        s_put (&grp, self->schemas[i].rec.p, self->schemas[i].rec.len);
    s_group (&sum, &offs, summary_start, S_OP_SCHEMA, grp.p, grp.len);
    grp.len = 0;
    for (size_t i = 0; i < self->n_chans; i++)
        s_put (&grp, self->chans[i].rec.p, self->chans[i].rec.len);
    s_group (&sum, &offs, summary_start, S_OP_CHANNEL, grp.p, grp.len);
    grp.len = 0;
    size_t sat = s_begin (&grp, S_OP_STATS);
    s_u64 (&grp, self->messages);
    s_u16 (&grp, (uint16_t)self->n_schemas);
    s_u32 (&grp, (uint32_t)self->n_chans);
    s_u32 (&grp, 0); // attachments
    s_u32 (&grp, 0); // metadata
    s_u32 (&grp, self->chunks);
    s_u64 (&grp, self->messages ? self->start_ns : 0);
    s_u64 (&grp, self->messages ? self->end_ns : 0);
    size_t n_counted = 0;
    for (size_t i = 0; i < self->n_chans; i++)
        n_counted += self->chans[i].count > 0;
    s_u32 (&grp, (uint32_t)(n_counted * 10));
    for (size_t i = 0; i < self->n_chans; i++)
        if (self->chans[i].count > 0) {
            s_u16 (&grp, (uint16_t)(i + 1));
            s_u64 (&grp, self->chans[i].count);
        }
    s_end (&grp, sat);
    s_group (&sum, &offs, summary_start, S_OP_STATS, grp.p, grp.len);
    s_group (&sum, &offs, summary_start, S_OP_CHUNK_IDX, self->chunk_indexes.p,
             self->chunk_indexes.len);
    free (grp.p);
    uint64_t offsets_start = summary_start + sum.len;
    s_put (&sum, offs.p, offs.len);
    free (offs.p);
    s_u8 (&sum, S_OP_FOOTER); // its length first: the CRC covers it
    s_u64 (&sum, 20);
    s_u64 (&sum, summary_start);
    s_u64 (&sum, offs.len ? offsets_start : 0);
    uint32_t scrc = sum.oom ? 0 : (uint32_t)crc32_z (crc32_z (0L, Z_NULL, 0), sum.p, sum.len);
    s_u32 (&sum, scrc);
    s_put (&sum, S_MAGIC, S_MAGIC_LEN);
    rc = sum.oom ? s_fail (self, "out of memory for the summary", ENOMEM)
                 : s_write (self, sum.p, sum.len, false);
    free (sum.p);
    return rc;
}

int cgs_mcap_writer_close (cgs_mcap_writer_t **self_p, char *err, size_t errlen)
{
    cgs_mcap_writer_t *self = self_p ? *self_p : NULL;
    if (!self)
        return 0;
    int rc = 0;
    if (self->fd >= 0) {
        rc = s_finish (self);
        if (close (self->fd) < 0 && rc == 0)
            rc = s_fail (self, "cannot close", errno);
    }
    if (rc < 0)
        cgs_errf (err, errlen, "%s", self->error[0] ? self->error : "cannot write the summary");
    for (size_t i = 0; i < self->n_schemas; i++)
        free (self->schemas[i].rec.p);
    for (size_t i = 0; i < self->n_chans; i++)
        free (self->chans[i].rec.p), free (self->chans[i].index.p);
    free (self->schemas);
    free (self->chans);
    free (self->chunk.p);
    free (self->chunk_indexes.p);
    free (self->out.p);
    free (self->zbuf.p);
    ZSTD_freeCCtx (self->zctx);
    free (self);
    *self_p = NULL;
    return rc;
}

/* ---- reader ------------------------------------------------------------------------------ */

struct cgs_mcap_reader {
    const uint8_t *file; // mapped (NULL for an empty file)
    size_t size, pos;    // in the file
    uint8_t *chunk;      // the open chunk's records (decompressed), or NULL
    size_t chunk_len, chunk_pos;
    bool complete;
    bool summary;    // past DataEnd: the summary repeats the data section's schemas and channels
    size_t chunk_at; // the open chunk's file offset
    char name[1024], encoding[256];
};

cgs_mcap_reader_t *cgs_mcap_reader_open (const char *path, char *err, size_t errlen)
{
    int fd = open (path, O_RDONLY | O_CLOEXEC);
    if (fd < 0) {
        cgs_errf (err, errlen, "%s: cannot open: %s", path, strerror (errno));
        return NULL;
    }
    cgs_mcap_reader_t *self = calloc (1, sizeof *self);
    struct stat st;
    if (!self || fstat (fd, &st) < 0) {
        cgs_errf (err, errlen, "%s: cannot read it: %s", path, strerror (errno));
        close (fd);
        free (self);
        return NULL;
    }
    // Mapped, not read: a recording of hours is read a chunk at a time.
    self->size = (size_t)st.st_size;
    if (self->size >= S_MAGIC_LEN) {
        void *m = mmap (NULL, self->size, PROT_READ, MAP_PRIVATE, fd, 0);
        if (m == MAP_FAILED) {
            cgs_errf (err, errlen, "%s: cannot map it: %s", path, strerror (errno));
            close (fd);
            free (self);
            return NULL;
        }
        madvise (m, self->size, MADV_SEQUENTIAL);
        self->file = m;
    }
    close (fd);
    if (self->size < S_MAGIC_LEN || memcmp (self->file, S_MAGIC, S_MAGIC_LEN) != 0) {
        cgs_errf (err, errlen, "%s: not an MCAP file (no magic at its start)", path);
        cgs_mcap_reader_destroy (&self);
        return NULL;
    }
    self->pos = S_MAGIC_LEN;
    return self;
}

void cgs_mcap_reader_rewind (cgs_mcap_reader_t *self)
{
    self->pos = S_MAGIC_LEN;
    free (self->chunk);
    self->chunk = NULL;
    self->chunk_len = self->chunk_pos = 0;
    self->complete = false;
    self->summary = false;
}

/* Does the file end with a footer and the magic (it was closed)? */
static bool s_has_footer (const cgs_mcap_reader_t *self)
{
    size_t n = self->size;
    return n >= 2 * S_MAGIC_LEN + 29 &&
           memcmp (self->file + n - S_MAGIC_LEN, S_MAGIC, S_MAGIC_LEN) == 0 &&
           self->file[n - S_MAGIC_LEN - 29] == S_OP_FOOTER &&
           s_get (self->file + n - S_MAGIC_LEN - 28, 8) == 20;
}

static int s_bad (char *err, size_t errlen, size_t at, const char *fmt, ...)
    __attribute__ ((format (printf, 4, 5)));
static int s_bad (char *err, size_t errlen, size_t at, const char *fmt, ...)
{
    char what[200];
    va_list ap;
    va_start (ap, fmt);
    vsnprintf (what, sizeof what, fmt, ap);
    va_end (ap);
    cgs_errf (err, errlen, "damaged MCAP at byte %zu: %s", at, what);
    return -EINVAL;
}

/* A string at *p within end into buf: false when it overruns. */
static bool s_rstr (const uint8_t **p, const uint8_t *end, char *buf, size_t cap)
{
    if (end - *p < 4)
        return false;
    uint32_t n = (uint32_t)s_get (*p, 4);
    if ((size_t)(end - *p - 4) < n)
        return false;
    size_t k = n < cap - 1 ? n : cap - 1;
    memcpy (buf, *p + 4, k);
    buf[k] = '\0';
    *p += 4 + (size_t)n;
    return true;
}

/* One record of the data (p, n: content) into ret: 1 when it is a schema,
 * channel or message, 0 to skip it, -EINVAL when damaged. */
static int s_parse (cgs_mcap_reader_t *self, uint8_t op, const uint8_t *p, size_t n,
                    cgs_mcap_record_t *ret, size_t at, char *err, size_t errlen)
{
    const uint8_t *end = p + n;
    memset (ret, 0, sizeof *ret);
    switch (op) {
    case S_OP_SCHEMA:
        if (n < 2)
            return s_bad (err, errlen, at, "a schema record too short");
        ret->kind = CGS_MCAP_SCHEMA;
        ret->id = (uint16_t)s_get (p, 2);
        p += 2;
        if (!s_rstr (&p, end, self->name, sizeof self->name) ||
            !s_rstr (&p, end, self->encoding, sizeof self->encoding) || end - p < 4 ||
            (size_t)(end - p - 4) < s_get (p, 4))
            return s_bad (err, errlen, at, "a schema record overruns itself");
        ret->len = (size_t)s_get (p, 4);
        ret->data = p + 4;
        break;
    case S_OP_CHANNEL:
        if (n < 4)
            return s_bad (err, errlen, at, "a channel record too short");
        ret->kind = CGS_MCAP_CHANNEL;
        ret->id = (uint16_t)s_get (p, 2);
        ret->schema_id = (uint16_t)s_get (p + 2, 2);
        p += 4;
        if (!s_rstr (&p, end, self->name, sizeof self->name) ||
            !s_rstr (&p, end, self->encoding, sizeof self->encoding))
            return s_bad (err, errlen, at, "a channel record overruns itself");
        break;
    case S_OP_MESSAGE:
        if (n < 22)
            return s_bad (err, errlen, at, "a message record too short");
        ret->kind = CGS_MCAP_MESSAGE;
        ret->id = (uint16_t)s_get (p, 2);
        ret->sequence = (uint32_t)s_get (p + 2, 4);
        ret->log_time_ns = s_get (p + 6, 8);
        ret->publish_time_ns = s_get (p + 14, 8);
        ret->data = p + 22;
        ret->len = n - 22;
        return 1;
    default:
        return 0;
    }
    ret->name = self->name;
    ret->encoding = self->encoding;
    return 1;
}

/* Open the chunk record (p, n: content) at file offset at. */
static int s_open_chunk (cgs_mcap_reader_t *self, const uint8_t *p, size_t n, size_t at, char *err,
                         size_t errlen)
{
    const uint8_t *end = p + n;
    if (n < 28)
        return s_bad (err, errlen, at, "a chunk record too short");
    uint64_t usize = s_get (p + 16, 8);
    uint32_t crc = (uint32_t)s_get (p + 24, 4);
    p += 28;
    char comp[32];
    if (!s_rstr (&p, end, comp, sizeof comp) || end - p < 8 ||
        (uint64_t)(end - p - 8) < s_get (p, 8))
        return s_bad (err, errlen, at, "a chunk record overruns itself");
    size_t clen = (size_t)s_get (p, 8);
    p += 8;
    free (self->chunk);
    self->chunk = NULL;
    self->chunk_at = at;
    // The size it claims, checked before any memory is given to it.
    if (usize > S_MAX_CHUNK)
        return s_bad (err, errlen, at, "a chunk of %llu bytes (at most %llu)",
                      (unsigned long long)usize, (unsigned long long)S_MAX_CHUNK);
    if (comp[0] == '\0' && clen != usize)
        return s_bad (err, errlen, at, "an uncompressed chunk of %zu bytes says %llu", clen,
                      (unsigned long long)usize);
    if (comp[0] != '\0' && strcmp (comp, "zstd") != 0)
        return s_bad (err, errlen, at, "a chunk compressed with '%s' (only zstd or none)", comp);
    if (comp[0] != '\0' && ZSTD_getFrameContentSize (p, clen) != usize)
        return s_bad (err, errlen, at, "a zstd chunk whose frame does not say its %llu bytes",
                      (unsigned long long)usize);
    uint8_t *buf = malloc (usize ? (size_t)usize : 1);
    if (!buf)
        return s_bad (err, errlen, at, "no memory for a chunk of %llu bytes",
                      (unsigned long long)usize);
    if (comp[0] == '\0') {
        memcpy (buf, p, clen);
    } else {
        size_t got = ZSTD_decompress (buf, (size_t)usize, p, clen);
        if (ZSTD_isError (got) || got != usize) {
            free (buf);
            return s_bad (err, errlen, at, "a zstd chunk does not decompress to its %llu bytes",
                          (unsigned long long)usize);
        }
    }
    if (crc != 0 && (uint32_t)crc32_z (crc32_z (0L, Z_NULL, 0), buf, (size_t)usize) != crc) {
        free (buf);
        return s_bad (err, errlen, at, "a chunk's CRC does not match its records");
    }
    self->chunk = buf;
    self->chunk_len = (size_t)usize, self->chunk_pos = 0;
    return 0;
}

/* An error inside the open chunk: it is dropped (its records are not to be
 * trusted), and the error names the chunk's file offset. */
static int s_bad_in_chunk (cgs_mcap_reader_t *self, char *err, size_t errlen, const char *what)
{
    size_t at = self->chunk_at, pos = self->chunk_pos;
    free (self->chunk);
    self->chunk = NULL;
    return s_bad (err, errlen, at, "%s (byte %zu of the chunk's records)", what, pos);
}

int cgs_mcap_reader_next (cgs_mcap_reader_t *self, cgs_mcap_record_t *ret, char *err, size_t errlen)
{
    for (;;) {
        if (self->chunk) {
            if (self->chunk_pos < self->chunk_len) {
                size_t at = self->chunk_pos;
                if (self->chunk_len - at < 9 ||
                    self->chunk_len - at - 9 < s_get (self->chunk + at + 1, 8))
                    return s_bad_in_chunk (self, err, errlen, "a record overruns its chunk");
                size_t n = (size_t)s_get (self->chunk + at + 1, 8);
                int rc = s_parse (self, self->chunk[at], self->chunk + at + 9, n, ret,
                                  self->chunk_at, err, errlen);
                if (rc < 0)
                    return s_bad_in_chunk (self, err, errlen, "a record is damaged");
                self->chunk_pos = at + 9 + n;
                if (rc != 0)
                    return rc;
                continue;
            }
            free (self->chunk);
            self->chunk = NULL;
        }
        size_t at = self->pos;
        if (self->size - at < 9 || self->size - at - 9 < s_get (self->file + at + 1, 8)) {
            // The end, or a record cut short: a recorder killed. A file that
            // ends with its footer and magic was not cut: it is damaged.
            if (at < self->size && s_has_footer (self))
                return s_bad (err, errlen, at, "a record overruns the file, which has its footer");
            return 0;
        }
        uint8_t op = self->file[at];
        size_t n = (size_t)s_get (self->file + at + 1, 8);
        const uint8_t *p = self->file + at + 9;
        self->pos = at + 9 + n;
        if (op == S_OP_FOOTER) {
            self->complete = self->size - self->pos == S_MAGIC_LEN &&
                             memcmp (self->file + self->pos, S_MAGIC, S_MAGIC_LEN) == 0;
            if (self->complete)
                self->pos = self->size;
            return 0;
        }
        if (op == S_OP_DATA_END)
            self->summary = true;
        if (self->summary)
            continue;
        if (op == S_OP_CHUNK) {
            int rc = s_open_chunk (self, p, n, at, err, errlen);
            if (rc < 0)
                return rc;
            continue;
        }
        // Schemas, channels and messages outside chunks (a writer that does
        // not chunk); indexes are skipped.
        int rc = s_parse (self, op, p, n, ret, at, err, errlen);
        if (rc != 0)
            return rc;
    }
}

bool cgs_mcap_reader_complete (const cgs_mcap_reader_t *self)
{
    return self->complete;
}

size_t cgs_mcap_reader_unread (const cgs_mcap_reader_t *self)
{
    return self->size - self->pos;
}

void cgs_mcap_reader_destroy (cgs_mcap_reader_t **self_p)
{
    if (!self_p || !*self_p)
        return;
    if ((*self_p)->file)
        munmap ((void *)(*self_p)->file, (*self_p)->size);
    free ((*self_p)->chunk);
    free (*self_p);
    *self_p = NULL;
}
