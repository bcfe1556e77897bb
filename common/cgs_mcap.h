/* cgs_mcap — MCAP files (https://mcap.dev): a chunked, indexed writer and a
 * streaming reader, for recordings of the bus that standard tools open
 * (Foxglove, @mcap/core, the mcap CLI) with the message schemas inside.
 *
 * The writer puts each Schema and Channel record in the data section before
 * the channel's first message, gathers messages in chunks (zstd-compressed
 * when that pays, else uncompressed), and writes a chunk out with write(2)
 * when it reaches its size or when the caller flushes (a recorder flushes at
 * least once a second, so a kill -9 loses at most that second: the stream
 * reader, ours or @mcap/core's, reads every whole chunk of a file cut short).
 * Each chunk is followed by its message indexes; closing writes DataEnd (with
 * the data section's CRC), the summary (schemas, channels, statistics, chunk
 * indexes), the summary offsets and the footer (with the summary's CRC).
 *
 * The reader walks a file's records in order, opening chunks: schemas,
 * channels and messages, as they were written; a file without its footer
 * (a recorder killed) reads up to its last whole chunk and says so.
 *
 * No globals; an object is used from one thread at a time. */
#ifndef CGS_MCAP_H
#define CGS_MCAP_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

/* ---- writer ------------------------------------------------------------------------------ */

typedef struct cgs_mcap_writer cgs_mcap_writer_t;

typedef struct {
    const char *library; // Header.library ("mscgs" when NULL)
    bool compress;       // zstd chunks (when that saves 2% or more)
    size_t chunk_bytes;  // a chunk is written out at this many uncompressed bytes (0: 1 MiB)
} cgs_mcap_options_t;

/* Create (or truncate) path and write the magic and header. NULL with the
 * reason in err. */
cgs_mcap_writer_t *cgs_mcap_writer_open (const char *path, const cgs_mcap_options_t *o, char *err,
                                         size_t errlen);
/* A schema: its id (1..65535), or -ENOSPC, -ENOMEM. encoding "protobuf"
 * with data a serialized FileDescriptorSet and name the message's full name. */
int cgs_mcap_writer_schema (cgs_mcap_writer_t *self, const char *name, const char *encoding,
                            const uint8_t *data, size_t len);
/* A channel on topic, of schema schema_id (0: none), its messages in
 * message_encoding; metadata: n_meta key/value pairs (may be NULL). Its id
 * (1..65535), or a negative errno. */
int cgs_mcap_writer_channel (cgs_mcap_writer_t *self, uint16_t schema_id, const char *topic,
                             const char *message_encoding, const char *const *meta_keys,
                             const char *const *meta_values, size_t n_meta);
/* A message on channel: log_time (when it was received) and publish_time,
 * nanoseconds; 0, or a negative errno (-EIO with the reason in
 * cgs_mcap_writer_error once the file cannot be written). */
int cgs_mcap_writer_message (cgs_mcap_writer_t *self, uint16_t channel, uint32_t sequence,
                             uint64_t log_time_ns, uint64_t publish_time_ns, const uint8_t *data,
                             size_t len);
/* Write the open chunk out now (nothing when it is empty): 0 or -EIO. */
int cgs_mcap_writer_flush (cgs_mcap_writer_t *self);
/* Messages written so far (in chunks written out or not), chunks written out,
 * bytes in the file. */
uint64_t cgs_mcap_writer_messages (const cgs_mcap_writer_t *self);
uint32_t cgs_mcap_writer_chunks (const cgs_mcap_writer_t *self);
uint64_t cgs_mcap_writer_bytes (const cgs_mcap_writer_t *self);
/* The first write error ("" when none). */
const char *cgs_mcap_writer_error (const cgs_mcap_writer_t *self);
/* Flush, write the summary and footer, close the file, free: 0 or -EIO
 * with the reason in err. Accepts NULL. */
int cgs_mcap_writer_close (cgs_mcap_writer_t **self_p, char *err, size_t errlen);

/* ---- reader ------------------------------------------------------------------------------ */

typedef enum {
    CGS_MCAP_SCHEMA = 1,
    CGS_MCAP_CHANNEL,
    CGS_MCAP_MESSAGE,
} cgs_mcap_kind_t;

/* One record. Pointers into the reader's buffers: valid until the next call. */
typedef struct {
    cgs_mcap_kind_t kind;
    uint16_t id;          // schema or channel id; a message's channel
    uint16_t schema_id;   // a channel's
    const char *name;     // a schema's name, a channel's topic (NUL-terminated copies)
    const char *encoding; // a schema's encoding, a channel's message encoding
    uint32_t sequence;
    uint64_t log_time_ns, publish_time_ns;
    const uint8_t *data; // a schema's data, a message's payload
    size_t len;
} cgs_mcap_record_t;

typedef struct cgs_mcap_reader cgs_mcap_reader_t;

/* Open path (mapped, read a chunk at a time). NULL with the reason in err. */
cgs_mcap_reader_t *cgs_mcap_reader_open (const char *path, char *err, size_t errlen);
/* The next schema, channel or message: 1, 0 at the end, or -EINVAL with
 * the reason (file offset) in err for a damaged file (a bad CRC, a record
 * that overruns its chunk, an unknown compression). */
int cgs_mcap_reader_next (cgs_mcap_reader_t *self, cgs_mcap_record_t *ret, char *err,
                          size_t errlen);
/* After the end: true when the file ended with its footer and magic (else it
 * was cut short: its whole chunks were read), and the bytes left unread. */
bool cgs_mcap_reader_complete (const cgs_mcap_reader_t *self);
size_t cgs_mcap_reader_unread (const cgs_mcap_reader_t *self);
/* Read again from the first record (a replay that seeks back). */
void cgs_mcap_reader_rewind (cgs_mcap_reader_t *self);
void cgs_mcap_reader_destroy (cgs_mcap_reader_t **self_p);

#endif
