/* im_video — the imaging sensor's frames as STANAG 4609 motion imagery:
 * H.264 (libx264 through libavcodec, zero-latency tuning, no B-frames) and
 * one MISB ST 0601 KLV packet per frame, in an MPEG transport stream
 * (libavformat's muxer). The KLV goes as FFmpeg's default writes it:
 * stream type 0x06 with the "KLVA" registration descriptor, PES stream id
 * 0xFC (metadata stream) with a PTS, that of its video frame, so a reader
 * can pair each packet with its frame. MISB ST 1402's asynchronous form
 * (stream id 0xBD, no PTS) would lose that pairing, and FFmpeg 5.1's
 * synchronous form writes no metadata AU header: neither is used.
 *
 * The frame is converted from RGBA to YUV 4:2:0 (BT.601, limited range) by
 * libswscale. Every keyframe is an IDR with SPS and PPS in band, and the
 * muxer writes PAT and PMT before it, so a receiver can start at any
 * keyframe. The transport stream goes to the caller's sink as it is
 * written, in whole 188-byte packets, at most IM_VIDEO_CHUNK bytes a call
 * (seven packets: one UDP datagram), and every frame's bytes are out when
 * im_video_frame returns. No logging, no sockets, no files: the caller
 * sends the bytes where they go. */
#ifndef IM_VIDEO_H
#define IM_VIDEO_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#define IM_VIDEO_TS_PACKET 188
#define IM_VIDEO_CHUNK     (7 * IM_VIDEO_TS_PACKET)
#define IM_VIDEO_CLOCK_HZ  90000 // MPEG system clock: PTS units per second

typedef struct im_video im_video_t;

typedef struct {
    int width_px, height_px; // both even
    double frame_rate_hz;    // nominal: the encoder's rate control and keyframe count
    int bitrate_kbps;        // target video bitrate
    double keyframe_s;       // an IDR frame at least this often (time of the frames)
    const char *preset;      // x264 preset: ultrafast .. veryslow
    int threads;             // encoder threads; 0: libx264's choice
} im_video_config_t;

/* Where the transport stream goes: len bytes, a whole number of 188-byte
 * packets, at most IM_VIDEO_CHUNK. */
typedef void (im_video_sink_fn) (void *arg, const uint8_t *ts, size_t len);

typedef struct {
    uint64_t frames;      // video frames encoded
    uint64_t keyframes;   // of them IDR frames
    uint64_t klv_packets; // KLV packets muxed
    uint64_t refused;     // frames refused (time not after the last frame's)
    uint64_t bytes;       // transport stream bytes to the sink
    uint64_t video_bytes; // H.264 bytes (before the transport stream)
} im_video_stats_t;

/* Open the encoder and the muxer; the stream's headers go to the sink with
 * the first frame. NULL with the reason in err (no libx264, a bad size ...). */
im_video_t *im_video_new (const im_video_config_t *cfg, im_video_sink_fn *sink, void *arg,
                          char *err, size_t errlen);

/* Encode one frame: rgba (width × height × 4 bytes, top row first) shown at
 * time_s (seconds in [0, 1e9), the PTS: time_s × 90 kHz, modulo 2^33 in the
 * stream) with its KLV packet (klv_len 0: none), and
 * mux both. A frame must come at least one 90 kHz tick after the last:
 * otherwise -EINVAL and nothing is written. *keyframe (may be NULL) says
 * whether it was an IDR frame. 0 or a negative errno with err filled. */
int im_video_frame (im_video_t *self, const uint8_t *rgba, double time_s, const uint8_t *klv,
                    size_t klv_len, bool *keyframe, char *err, size_t errlen);

/* Drain the encoder and end the stream; later frames are refused. 0 or a
 * negative errno with err filled. */
int im_video_finish (im_video_t *self, char *err, size_t errlen);

/* Time went back (a restarted exercise): the next frame, whatever its time,
 * follows the last one in the stream by one nominal frame period, and is a
 * keyframe; later frames keep that offset. */
void im_video_continue (im_video_t *self);

void im_video_stats (const im_video_t *self, im_video_stats_t *ret);

/* Free everything (without finishing the stream); accepts NULL; nulls the pointer. */
void im_video_destroy (im_video_t **self_p);

#endif
