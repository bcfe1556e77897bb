/* cgs_msg — the only module that touches protobuf-c: encode, decode (with an
 * arena so a busy subscriber does not call malloc per message), find the
 * common header of any topic message, and print any message as JSON through
 * the protobuf-c descriptors. Pure: no logging. */
#ifndef CGS_MSG_H
#define CGS_MSG_H

#include "command.pb-c.h"
#include "header.pb-c.h"
#include "health.pb-c.h"
#include "intercept.pb-c.h"
#include "sensors.pb-c.h"
#include "tracking.pb-c.h"
#include "world.pb-c.h"

#include "cgs_camera.h"

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

/* A bump allocator for decoded messages: reset frees everything at once. */
typedef struct cgs_msg_arena cgs_msg_arena_t;

/* Arena whose first block holds block_size bytes; NULL on allocation failure. */
cgs_msg_arena_t *cgs_msg_arena_new (size_t block_size);
/* Free the arena and everything allocated in it; accepts NULL. */
void cgs_msg_arena_destroy (cgs_msg_arena_t **self_p);
/* Forget every allocation; keeps the first block for reuse. */
void cgs_msg_arena_reset (cgs_msg_arena_t *self);

/* Decode a payload as type desc. With an arena the message lives until the
 * arena is reset (do not free it); without one, free it with cgs_msg_free.
 * 0, or -EPROTO when the bytes are not a valid message of that type. */
int cgs_msg_decode (const ProtobufCMessageDescriptor *desc, const void *data, size_t len,
                    cgs_msg_arena_t *arena, ProtobufCMessage **ret_msg);
/* Free a message decoded without an arena; accepts NULL, nulls the pointer. */
void cgs_msg_free (ProtobufCMessage **msg_p);

/* Encoded size of a message. */
size_t cgs_msg_size (const ProtobufCMessage *msg);
/* Encode into buf (which holds at least cgs_msg_size bytes); returns the length. */
size_t cgs_msg_encode (const ProtobufCMessage *msg, uint8_t *buf);
/* Encode into a new malloc'd buffer; 0 or -ENOMEM. */
int cgs_msg_encode_alloc (const ProtobufCMessage *msg, uint8_t **ret_buf, size_t *ret_len);

/* The address of a message's `Header header = 1` field, or NULL when the type
 * has none (commands, replies). */
Cgs__Header **cgs_msg_header_slot (ProtobufCMessage *msg);
/* The header of a decoded message, or NULL. */
const Cgs__Header *cgs_msg_header (const ProtobufCMessage *msg);

/* The bus's fast path for topic messages. The common header is written and
 * read by hand (byte for byte what protobuf-c would produce: field 1, proto3
 * rules, fields in number order); protobuf-c handles the rest.
 * Encode msg with header h in its field 1 (msg's own header is ignored) into
 * buf of size cap; 0 and *ret_len, or -ENOBUFS with the size needed in
 * *ret_len, or -EINVAL when the type has no header. */
int cgs_msg_encode_stamped (ProtobufCMessage *msg, const Cgs__Header *h, uint8_t *buf, size_t cap,
                            size_t *ret_len);
/* The same into *buf (malloc'd, *cap bytes), grown (doubled) as needed:
 * 0 and *ret_len, -ENOMEM (buf as it was), or -EINVAL. */
int cgs_msg_encode_stamped_grow (ProtobufCMessage *msg, const Cgs__Header *h, uint8_t **buf,
                                 size_t *cap, size_t *ret_len);
/* An upper bound of the stamped encoding's size. */
size_t cgs_msg_stamped_size_max (ProtobufCMessage *msg);
/* Decode a stamped payload of type desc into the arena (required); the
 * message's header field points at *hdr, whose source string is kept in
 * src (src_size bytes). Falls back to protobuf-c for anything unusual.
 * 0, or -EPROTO for bytes that are not such a message. */
int cgs_msg_decode_stamped (const ProtobufCMessageDescriptor *desc, const void *data, size_t len,
                            cgs_msg_arena_t *arena, Cgs__Header *hdr, char *src, size_t src_size,
                            ProtobufCMessage **ret_msg);

/* Print a message as one line of JSON (proto3 JSON mapping: field names as in
 * the .proto, enums by name, 64-bit integers as strings, bytes as base64). */
int cgs_msg_print_json (FILE *f, const ProtobufCMessage *msg);
/* The same into a new malloc'd string; 0 or -ENOMEM. */
int cgs_msg_to_json (const ProtobufCMessage *msg, char **ret_json);
/* An enum value's name without the prefix its enum gives every value
 * (InterceptState's INTERCEPT_STATE_DONE is "DONE"), or fallback when the
 * value is not one of the enum's. */
const char *cgs_msg_enum_short (const ProtobufCEnumDescriptor *desc, int value,
                                const char *fallback);

/* The imaging sensor's camera as a `uav` message gives it, into in: the
 * UAV's position and attitude, the sensor's depression angle and fields of
 * view, stabilization, the stare point it is turned to (when staring) and
 * the gimbal's limits; in's size and depth range are left as they were.
 * -EINVAL (in unchanged) when the position, attitude or sensor is missing
 * or not finite. Every service that needs the camera takes it this way and
 * builds it with cgs_camera_make, so they all have the same one. */
int cgs_msg_uav_camera (const Cgs__Uav *u, cgs_camera_in_t *in);

#endif
