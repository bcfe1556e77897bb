/* cgs_util — small helpers shared by the common modules. */
#ifndef CGS_UTIL_H
#define CGS_UTIL_H

#include <stddef.h>
#include <stdint.h>

/* Format a reason into a caller's error buffer; err may be NULL or errlen 0. */
void cgs_errf (char *err, size_t errlen, const char *fmt, ...)
    __attribute__ ((format (printf, 3, 4)));

/* CRC-32 (IEEE 802.3, as zlib and PNG compute it) of n bytes. */
uint32_t cgs_crc32 (const void *data, size_t n);

#endif
