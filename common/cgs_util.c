/* cgs_util — small helpers shared by the common modules. */
#include "cgs_util.h"

#include <stdarg.h>
#include <stdio.h>
#include <zlib.h>

void cgs_errf (char *err, size_t errlen, const char *fmt, ...)
{
    if (!err || errlen == 0)
        return;
    va_list ap;
    va_start (ap, fmt);
    vsnprintf (err, errlen, fmt, ap);
    va_end (ap);
}

uint32_t cgs_crc32 (const void *data, size_t n)
{
    // zlib takes lengths as uInt: feed it in pieces.
    uLong crc = crc32 (0L, Z_NULL, 0);
    const Bytef *p = data;
    while (n > 0) {
        uInt chunk = n > 0x40000000u ? 0x40000000u : (uInt)n;
        crc = crc32 (crc, p, chunk);
        p += chunk;
        n -= chunk;
    }
    return (uint32_t)crc;
}
