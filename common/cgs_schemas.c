/* cgs_schemas — see cgs_schemas.h. The bytes are $(O)/gen/cgs_fds.c (xxd). */
#include "cgs_schemas.h"

extern unsigned char cgs_fds_bin[];
extern unsigned int cgs_fds_bin_len;

const uint8_t *cgs_schemas_fds (size_t *ret_len)
{
    *ret_len = cgs_fds_bin_len;
    return cgs_fds_bin;
}
