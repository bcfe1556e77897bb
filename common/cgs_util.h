/* cgs_util — small helpers shared by the common modules. */
#ifndef CGS_UTIL_H
#define CGS_UTIL_H

#include <stddef.h>
#include <stdint.h>

/* Format a reason into a caller's error buffer; err may be NULL or errlen 0. */
void cgs_errf (char *err, size_t errlen, const char *fmt, ...)
    __attribute__ ((format (printf, 3, 4)));

/* A whole number written in decimal digits only (no sign, space or
 * exponent), at most max: 0 and *ret, or -EINVAL (*ret untouched). */
int cgs_parse_u64 (const char *text, uint64_t max, uint64_t *ret);
/* splitmix64 (Steele, Lea and Flood 2014): the next number of the sequence
 * whose state is *state (advanced). Seeded generators of models and Monte
 * Carlo drivers draw from it. */
uint64_t cgs_splitmix64 (uint64_t *state);
/* A uniform number in the open interval (0, 1) from splitmix64. */
double cgs_uniform01 (uint64_t *state);
/* Make the array *p (*cap elements of size bytes) hold at least need: its
 * capacity doubles from 16 until it does. 0, or -ENOMEM with *p and *cap
 * untouched (also when the size overflows). */
int cgs_grow (void **p, size_t *cap, size_t need, size_t size);
/* Write all of buf to fd, again after EINTR and short writes; 0 or -errno
 * (-EIO when write wrote nothing). */
int cgs_write_all (int fd, const void *buf, size_t len);
/* CRC-32 (IEEE 802.3, as zlib and PNG compute it) of n bytes. */
uint32_t cgs_crc32 (const void *data, size_t n);

#endif
