/* im_vout — where the video's transport stream goes (im_video's sink): a
 * file, a UDP destination and the current frame's bytes for the bus.
 *   - The file is appended to in whole 188-byte packets; at open, a partial
 *     packet left at its end by a crash is cut off first, so a restarted
 *     imagerd continues a file every player can read.
 *   - UDP goes through libavformat's udp protocol, one datagram per chunk
 *     (at most seven packets, 1316 bytes); a multicast group gets the TTL
 *     and is sent from the local address given (127.0.0.1: over loopback).
 *   - The frame's bytes are kept until im_vout_frame_reset, for one `video`
 *     message per frame.
 * A failed write is counted and kept as the last error; it never stops the
 * others. No logging. */
#ifndef IM_VOUT_H
#define IM_VOUT_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

typedef struct im_vout im_vout_t;

typedef struct {
    const char *file;     // path, NULL or "" for none
    const char *udp_host; // dotted IPv4, NULL or "" for none
    int udp_port;
    int ttl;                // multicast TTL
    const char *local_addr; // multicast: send from this address ("" or NULL: the route's)
    bool keep_frame;        // collect each frame's bytes (for the bus)
} im_vout_config_t;

typedef struct {
    uint64_t file_bytes, file_errors;
    uint64_t datagrams, udp_errors;
    uint64_t cut_bytes;   // a partial packet cut off the file's end at open
    uint64_t frames_lost; // frames whose bytes could not be kept for the bus
    char last_error[160];
} im_vout_stats_t;

/* Open the outputs; NULL with the reason in err. */
im_vout_t *im_vout_new (const im_vout_config_t *cfg, char *err, size_t errlen);
/* The sink: len bytes of transport stream (im_video_sink_fn's contract). */
void im_vout_write (void *self, const uint8_t *ts, size_t len);
/* This frame's bytes so far (valid until the next write or reset); NULL
 * when some could not be kept (out of memory). */
const uint8_t *im_vout_frame (const im_vout_t *self, size_t *len);
void im_vout_frame_reset (im_vout_t *self);
void im_vout_stats (const im_vout_t *self, im_vout_stats_t *ret);
/* Close everything; accepts NULL; nulls the pointer. */
void im_vout_destroy (im_vout_t **self_p);

#endif
