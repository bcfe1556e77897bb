/* cgs_ckpt — the one checkpoint format of every service's saved state: a
 * frame around a payload that a service lays out with the writer and reads
 * back with the reader. uavsim, trackerd and guidanced save through it.
 *
 * A frame, little-endian:
 *   magic    4 bytes naming the kind ("TRKS": trackerd's tracks)
 *   version  u32: the payload's layout (each kind numbers its own from 1)
 *   length   u64: bytes of payload
 *   payload  the service's fields (u8, u32, u64, IEEE double, byte strings)
 *   crc      u32: CRC-32 (IEEE 802.3, as zlib computes it) of the payload
 *
 * Errors, the same from cgs_ckpt_open and from every restore built on it,
 * each with the reason in the caller's err buffer:
 *   -EINVAL   malformed: truncated, bytes past its end, or a payload that
 *             does not decode to a valid state
 *   -EPROTO   not a checkpoint of this kind (another magic: another file,
 *             or one written before this format); a restore also gives it
 *             for a checkpoint of another object (another scenario)
 *   -ENOTSUP  this kind in another version of its layout: saved by another
 *             version of mscgs
 *   -EBADMSG  the checksum does not match: damaged
 *   -ENOMEM   out of memory
 *
 * The reader never reads past the payload: a get that would fails, returns
 * 0, and leaves the reader failed (sticky), so a decoder reads every field
 * and checks once. Nothing is asserted on input. Pure: no logging. */
#ifndef CGS_CKPT_H
#define CGS_CKPT_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#define CGS_CKPT_HEAD 16 // magic, version, length: the payload starts here
#define CGS_CKPT_TAIL 4  // the CRC after the payload

/* A frame being written (the caller's, on the stack): cgs_ckpt_writer_init,
 * the puts, then cgs_ckpt_writer_finish; cgs_ckpt_writer_fini to abandon. */
typedef struct {
    uint8_t *buf; // the frame so far
    size_t len, cap;
    bool failed; // out of memory: later puts do nothing, finish fails
} cgs_ckpt_writer_t;

/* Start a frame of kind magic (its first 4 characters) and version. */
void cgs_ckpt_writer_init (cgs_ckpt_writer_t *w, const char *magic, uint32_t version);
void cgs_ckpt_put_u8 (cgs_ckpt_writer_t *w, uint8_t v);
/* A flag as one byte, 0 or 1. */
void cgs_ckpt_put_bool (cgs_ckpt_writer_t *w, bool v);
void cgs_ckpt_put_u32 (cgs_ckpt_writer_t *w, uint32_t v);
void cgs_ckpt_put_u64 (cgs_ckpt_writer_t *w, uint64_t v);
/* A double's IEEE 754 bits, as a u64 (restored exactly, NaN included). */
void cgs_ckpt_put_f64 (cgs_ckpt_writer_t *w, double v);
/* n bytes and their length (u64) before them: a nested frame, a blob. */
void cgs_ckpt_put_bytes (cgs_ckpt_writer_t *w, const void *data, size_t n);
/* A string's bytes and their length (u32) before them, without the NUL. */
void cgs_ckpt_put_str (cgs_ckpt_writer_t *w, const char *s);
/* Close the frame (its length and CRC) and hand its new malloc'd buffer to
 * the caller: 0, or -ENOMEM (nothing handed over). The writer is empty
 * after either. */
int cgs_ckpt_writer_finish (cgs_ckpt_writer_t *w, uint8_t **ret_buf, size_t *ret_len);
/* Free what the writer holds; safe on a zeroed or finished writer. */
void cgs_ckpt_writer_fini (cgs_ckpt_writer_t *w);

/* The payload of an opened frame, read in order (the caller's, on the
 * stack; it points into the caller's buffer and holds no allocation). */
typedef struct {
    const uint8_t *p; // the payload
    size_t len, off;
    bool failed; // a get ran past the end or met a value it refuses
} cgs_ckpt_reader_t;

/* Check that buf holds one whole frame of kind magic and version, its
 * checksum good, and set r to its payload; 0, or -EINVAL, -EPROTO,
 * -ENOTSUP, -EBADMSG with the reason in err naming what (the kind, as in
 * "trackerd checkpoint") and what was found. r is written on success only. */
int cgs_ckpt_open (cgs_ckpt_reader_t *r, const void *buf, size_t len, const char *magic,
                   uint32_t version, const char *what, char *err, size_t errlen);
/* For salvaging a counter from a damaged checkpoint: the header's magic and
 * version checked, but not its length or checksum; r reads what follows
 * the header. 0, or -EINVAL / -EPROTO / -ENOTSUP. */
int cgs_ckpt_open_unchecked (cgs_ckpt_reader_t *r, const void *buf, size_t len, const char *magic,
                             uint32_t version);

uint8_t cgs_ckpt_get_u8 (cgs_ckpt_reader_t *r);
/* A flag: a byte 0 or 1; any other value fails the reader. */
bool cgs_ckpt_get_bool (cgs_ckpt_reader_t *r);
uint32_t cgs_ckpt_get_u32 (cgs_ckpt_reader_t *r);
uint64_t cgs_ckpt_get_u64 (cgs_ckpt_reader_t *r);
/* A double, any value (NaN and infinities too). */
double cgs_ckpt_get_f64 (cgs_ckpt_reader_t *r);
/* A double that must be finite: NaN or an infinity fails the reader. */
double cgs_ckpt_get_finite (cgs_ckpt_reader_t *r);
/* Bytes put with cgs_ckpt_put_bytes: where they are in the payload (no
 * copy) and *ret_len; NULL and 0 when the reader fails. */
const uint8_t *cgs_ckpt_get_bytes (cgs_ckpt_reader_t *r, size_t *ret_len);
/* A string put with cgs_ckpt_put_str, into dst of size bytes with its NUL;
 * one that does not fit or holds a NUL fails the reader (dst is then ""). */
void cgs_ckpt_get_str (cgs_ckpt_reader_t *r, char *dst, size_t size);
/* Fail the reader: a value its decoder refuses. */
void cgs_ckpt_fail (cgs_ckpt_reader_t *r);
/* Whether every get so far succeeded. */
bool cgs_ckpt_ok (const cgs_ckpt_reader_t *r);
/* Payload bytes not read yet (a count the rest cannot hold is refused
 * before anything is allocated for it). */
size_t cgs_ckpt_left (const cgs_ckpt_reader_t *r);
/* The decoder is done: 0 when every get succeeded and the payload is used
 * up, else -EINVAL with the reason in err (naming what). */
int cgs_ckpt_end (const cgs_ckpt_reader_t *r, const char *what, char *err, size_t errlen);

#endif
