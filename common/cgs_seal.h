/* cgs_seal — authenticated encryption of bus payloads under an exercise's
 * group key (libsodium's XChaCha20-Poly1305, IETF construction): what keeps
 * a multicast bus, which has no handshake and so no CURVE, private and
 * unforgeable.
 *
 * A sealed payload (every integer big-endian):
 *
 *   0      1 byte   0x00 (never the first byte of a protobuf message: field 0)
 *   1      3 bytes  "CGS"
 *   4      1 byte   version, 1
 *   5      4 bytes  exercise id
 *   9      8 bytes  publisher epoch
 *   17     8 bytes  sequence number
 *   25     8 bytes  wall time of sending, IEEE 754 double, Unix seconds
 *   33     1 byte   source length L (at most CGS_SEAL_SOURCE_MAX)
 *   34     L bytes  source instance name
 *   34+L   24 bytes nonce (random)
 *   58+L   n+16     ciphertext of the n-byte protobuf payload, and its tag
 *
 * The associated data is the topic (its length in one byte, then its bytes)
 * followed by bytes 0 to 33+L: the header travels in the clear, so that a
 * subscriber can count and drop without decrypting, and any change to it,
 * to the topic or to the ciphertext fails authentication. Random 24-byte
 * nonces never repeat in practice (2^-96 after 2^48 messages under a key).
 *
 * Pure: no logging, no global state beyond libsodium's one-time init. */
#ifndef CGS_SEAL_H
#define CGS_SEAL_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#define CGS_SEAL_KEY_BYTES  32
#define CGS_SEAL_SOURCE_MAX 63
#define CGS_SEAL_FIXED      74 // header, nonce and tag without the source: overhead = 74 + L
#define CGS_SEAL_TOPIC_MAX  255

typedef struct {
    uint8_t k[CGS_SEAL_KEY_BYTES];
} cgs_seal_key_t;

/* The clear header of a sealed payload. */
typedef struct {
    uint32_t exercise_id;
    uint64_t epoch;
    uint64_t seq;
    double wall_time_s;
    char source[CGS_SEAL_SOURCE_MAX + 1];
} cgs_seal_header_t;

/* libsodium's init; 0 or -EIO. Called by the functions below; thread-safe. */
int cgs_seal_init (void);

/* A new random key. 0 or -EIO. */
int cgs_seal_key_new (cgs_seal_key_t *key);

/* The key file's text: a comment line and the key as 64 hexadecimal digits.
 * buf must hold CGS_SEAL_KEY_TEXT_MAX bytes. */
#define CGS_SEAL_KEY_TEXT_MAX 160
void cgs_seal_key_format (const cgs_seal_key_t *key, char *buf, size_t len);

/* Read a key file (lines starting with '#' and blank lines are skipped; one
 * line of 64 hexadecimal digits). 0, or -errno with "path:line: reason" (or
 * "path: reason") in err. */
int cgs_seal_key_load (const char *path, cgs_seal_key_t *key, char *err, size_t errlen);

/* Whether payload looks sealed (its first four bytes), whatever the key. */
bool cgs_seal_is_sealed (const void *payload, size_t len);

/* The sealed size of an n-byte payload from source. */
size_t cgs_seal_size (size_t n, const char *source);

/* Seal plain[n] for topic under key with header h into out (cap bytes, at
 * least cgs_seal_size). *out_len is the sealed size. 0, -EINVAL (topic or
 * source too long), -ENOBUFS (cap too small). */
int cgs_seal (const cgs_seal_key_t *key, const char *topic, const cgs_seal_header_t *h,
              const void *plain, size_t n, void *out, size_t cap, size_t *out_len);

/* Open sealed[len] received on topic: its header into *h, the payload into
 * out (cap bytes, at least len - overhead) and its size into *out_len.
 * 0; -EPROTO (not a sealed payload of this version, or truncated);
 * -EBADMSG (fails authentication: wrong key, or a byte changed); -ENOBUFS. */
int cgs_seal_open (const cgs_seal_key_t *key, const char *topic, const void *sealed, size_t len,
                   cgs_seal_header_t *h, void *out, size_t cap, size_t *out_len);

#endif
