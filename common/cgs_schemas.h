/* cgs_schemas — the message schemas of every topic, for recordings that
 * other tools decode without mscgs: one google.protobuf.FileDescriptorSet
 * of all of proto/ (made at build time by protoc --include_imports), and
 * each topic's message name in it. */
#ifndef CGS_SCHEMAS_H
#define CGS_SCHEMAS_H

#include <stddef.h>
#include <stdint.h>

/* The FileDescriptorSet: its bytes and length. */
const uint8_t *cgs_schemas_fds (size_t *ret_len);

#endif
