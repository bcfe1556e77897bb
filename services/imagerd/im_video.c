/* im_video — H.264 and KLV in an MPEG transport stream (see im_video.h). */
#include "im_video.h"

#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libavutil/imgutils.h>
#include <libavutil/opt.h>
#include <libswscale/swscale.h>

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

struct im_video {
    im_video_config_t cfg;
    im_video_sink_fn *sink;
    void *arg;
    AVCodecContext *enc;
    AVFormatContext *mux;
    AVStream *video, *klv;
    struct SwsContext *sws;
    AVFrame *frame;
    AVPacket *pkt;
    bool header_written, finished, started;
    bool rebase; // the next frame follows the last, whatever its time
    int64_t last_pts, last_key_pts;
    int64_t offset; // added to every frame's PTS (rebased after time went back)
    im_video_stats_t stats;
};

static void s_averror (int rc, const char *what, char *err, size_t errlen)
{
    char why[AV_ERROR_MAX_STRING_SIZE] = "";
    av_strerror (rc, why, sizeof why);
    snprintf (err, errlen, "%s: %s", what, why);
}

/* libavformat's output: every buffer it flushes goes to the sink. */
static int s_write (void *opaque, uint8_t *buf, int len)
{
    im_video_t *self = opaque;
    if (len > 0) {
        self->sink (self->arg, buf, (size_t)len);
        self->stats.bytes += (uint64_t)len;
    }
    return len;
}

/* Free everything, the custom output's buffer included. */
static void s_free (im_video_t *self)
{
    if (self->mux) {
        if (self->mux->pb) {
            av_freep (&self->mux->pb->buffer);
            avio_context_free (&self->mux->pb);
        }
        avformat_free_context (self->mux);
    }
    avcodec_free_context (&self->enc);
    sws_freeContext (self->sws);
    av_frame_free (&self->frame);
    av_packet_free (&self->pkt);
    av_free (self);
}

static int s_open_encoder (im_video_t *self, char *err, size_t errlen)
{
    const im_video_config_t *c = &self->cfg;
    const AVCodec *codec = avcodec_find_encoder_by_name ("libx264");
    if (!codec) {
        snprintf (err, errlen,
                  "libavcodec has no libx264 encoder (install libx264 and an "
                  "FFmpeg built with it)");
        return -ENOSYS;
    }
    if (!(self->enc = avcodec_alloc_context3 (codec)))
        return -ENOMEM;
    AVCodecContext *e = self->enc;
    e->width = c->width_px;
    e->height = c->height_px;
    e->pix_fmt = AV_PIX_FMT_YUV420P;
    e->time_base = (AVRational){1, IM_VIDEO_CLOCK_HZ};
    e->framerate = av_d2q (c->frame_rate_hz, 100000);
    e->bit_rate = (int64_t)c->bitrate_kbps * 1000;
    e->rc_max_rate = e->bit_rate;
    e->rc_buffer_size = (int)(e->bit_rate / 2); // half a second of video: low latency
    e->max_b_frames = 0;
    e->thread_count = c->threads;
    e->color_range = AVCOL_RANGE_MPEG;
    e->colorspace = AVCOL_SPC_SMPTE170M;
    e->color_primaries = AVCOL_PRI_SMPTE170M;
    e->color_trc = AVCOL_TRC_SMPTE170M;
    int rc;
    if ((rc = av_opt_set (e->priv_data, "preset", c->preset, 0)) < 0) {
        snprintf (err, errlen, "libx264 has no preset '%s'", c->preset);
        return -EINVAL;
    }
    av_opt_set (e->priv_data, "tune", "zerolatency", 0);
    av_opt_set (e->priv_data, "forced-idr", "1", 0); // a keyframe asked for is an IDR
    // Keyframes by the frames' time alone (im_video_frame asks for them):
    // none of x264's own, by frame count or scene cut.
    av_opt_set (e->priv_data, "x264-params", "keyint=infinite:scenecut=0", 0);
    if ((rc = avcodec_open2 (e, codec, NULL)) < 0) {
        char what[96];
        snprintf (what, sizeof what, "cannot open the H.264 encoder (x264 preset '%s')", c->preset);
        s_averror (rc, what, err, errlen);
        return -EINVAL;
    }
    if (!(self->frame = av_frame_alloc ()) || !(self->pkt = av_packet_alloc ()))
        return -ENOMEM;
    self->frame->format = e->pix_fmt;
    self->frame->width = e->width;
    self->frame->height = e->height;
    if ((rc = av_frame_get_buffer (self->frame, 0)) < 0)
        return -ENOMEM;
    self->sws = sws_getContext (c->width_px, c->height_px, AV_PIX_FMT_RGBA, c->width_px,
                                c->height_px, AV_PIX_FMT_YUV420P, SWS_BILINEAR, NULL, NULL, NULL);
    if (!self->sws) {
        snprintf (err, errlen, "libswscale cannot convert RGBA to YUV 4:2:0 at %d x %d",
                  c->width_px, c->height_px);
        return -EINVAL;
    }
    return 0;
}

static int s_open_muxer (im_video_t *self, char *err, size_t errlen)
{
    int rc = avformat_alloc_output_context2 (&self->mux, NULL, "mpegts", NULL);
    if (rc < 0 || !self->mux) {
        s_averror (rc, "libavformat has no MPEG-TS muxer", err, errlen);
        return -ENOSYS;
    }
    uint8_t *buf = av_malloc (IM_VIDEO_CHUNK);
    if (!buf)
        return -ENOMEM;
    self->mux->pb = avio_alloc_context (buf, IM_VIDEO_CHUNK, 1, self, NULL, s_write, NULL);
    if (!self->mux->pb) {
        av_free (buf);
        return -ENOMEM;
    }
    self->mux->flags |= AVFMT_FLAG_CUSTOM_IO | AVFMT_FLAG_FLUSH_PACKETS;
    if (!(self->video = avformat_new_stream (self->mux, NULL)) ||
        !(self->klv = avformat_new_stream (self->mux, NULL)))
        return -ENOMEM;
    if ((rc = avcodec_parameters_from_context (self->video->codecpar, self->enc)) < 0) {
        s_averror (rc, "cannot describe the video stream", err, errlen);
        return -EINVAL;
    }
    self->video->time_base = self->enc->time_base;
    self->video->avg_frame_rate = self->enc->framerate;
    self->klv->codecpar->codec_type = AVMEDIA_TYPE_DATA;
    self->klv->codecpar->codec_id =
        AV_CODEC_ID_SMPTE_KLV; // profile unset: FFmpeg's default (KLVA, stream id 0xFC)
    self->klv->time_base = self->enc->time_base;
    return 0;
}

im_video_t *im_video_new (const im_video_config_t *cfg, im_video_sink_fn *sink, void *arg,
                          char *err, size_t errlen)
{
    if (!cfg || !sink || cfg->width_px < 16 || cfg->height_px < 16 || cfg->width_px % 2 ||
        cfg->height_px % 2 || !(cfg->frame_rate_hz > 0) || cfg->bitrate_kbps <= 0 ||
        !(cfg->keyframe_s > 0) || !cfg->preset || cfg->threads < 0) {
        snprintf (err, errlen,
                  "video: the size must be even and at least 16 x 16, the frame "
                  "rate, bitrate and keyframe interval positive, a preset named");
        return NULL;
    }
    im_video_t *self = av_mallocz (sizeof *self);
    if (!self) {
        snprintf (err, errlen, "out of memory");
        return NULL;
    }
    self->cfg = *cfg;
    self->sink = sink;
    self->arg = arg;
    av_log_set_level (AV_LOG_QUIET); // errors come back in err
    int rc = s_open_encoder (self, err, errlen);
    if (rc == 0)
        rc = s_open_muxer (self, err, errlen);
    if (rc < 0) {
        if (rc == -ENOMEM)
            snprintf (err, errlen, "out of memory for the video encoder");
        s_free (self);
        return NULL;
    }
    return self;
}

/* Every packet the encoder has ready, to the muxer; then the frame's KLV. */
static int s_drain (im_video_t *self, bool *keyframe, char *err, size_t errlen)
{
    for (;;) {
        int rc = avcodec_receive_packet (self->enc, self->pkt);
        if (rc == AVERROR (EAGAIN) || rc == AVERROR_EOF)
            return 0;
        if (rc < 0) {
            s_averror (rc, "H.264 encoding failed", err, errlen);
            return -EIO;
        }
        bool key = self->pkt->flags & AV_PKT_FLAG_KEY;
        if (keyframe)
            *keyframe = *keyframe || key;
        self->stats.keyframes += key;
        self->stats.video_bytes += (uint64_t)self->pkt->size;
        self->pkt->stream_index = self->video->index;
        av_packet_rescale_ts (self->pkt, self->enc->time_base, self->video->time_base);
        rc = av_write_frame (self->mux, self->pkt);
        av_packet_unref (self->pkt);
        if (rc < 0) {
            s_averror (rc, "cannot mux a video frame", err, errlen);
            return -EIO;
        }
    }
}

int im_video_frame (im_video_t *self, const uint8_t *rgba, double time_s, const uint8_t *klv,
                    size_t klv_len, bool *keyframe, char *err, size_t errlen)
{
    if (keyframe)
        *keyframe = false;
    if (self->finished) {
        snprintf (err, errlen, "the video stream has ended");
        return -EINVAL;
    }
    if (!rgba || !(time_s >= 0 && time_s < 1e9) || (klv_len && !klv) || klv_len > INT32_MAX) {
        snprintf (err, errlen,
                  "a video frame without pixels, a time in [0, 1e9) s or its KLV "
                  "bytes");
        return -EINVAL;
    }
    if (!self->started) {
        self->last_pts = -1;
        self->last_key_pts = INT64_MIN / 2;
    }
    // The time itself (simulation time): a restarted imagerd continues its file
    // forward. After im_video_continue, the offset makes this frame follow the last.
    int64_t tick = llround (time_s * IM_VIDEO_CLOCK_HZ);
    if (self->rebase && self->started) {
        int64_t step = llround (IM_VIDEO_CLOCK_HZ / self->cfg.frame_rate_hz);
        self->offset = self->last_pts + (step > 0 ? step : 1) - tick;
        self->last_key_pts = INT64_MIN / 2; // and it is a keyframe
    }
    self->rebase = false;
    int64_t pts = tick + self->offset;
    if (pts <= self->last_pts) {
        self->stats.refused++;
        snprintf (err, errlen, "a video frame at %.6f s is not after the last one", time_s);
        return -EINVAL;
    }
    int rc;
    if (!self->header_written) {
        // Each stream's first packet says "discontinuity": a receiver (or a file a
        // restarted imagerd appends to) resets its continuity counters there.
        AVDictionary *opts = NULL;
        av_dict_set (&opts, "mpegts_flags", "initial_discontinuity", 0);
        // The video PES packets carry their length (when under 64 KiB), so a
        // receiver can hand a frame on when its last byte comes, not when the
        // next frame starts.
        av_dict_set (&opts, "omit_video_pes_length", "0", 0);
        rc = avformat_write_header (self->mux, &opts);
        av_dict_free (&opts);
        if (rc < 0) {
            self->finished = true; // the muxer cannot be used again
            s_averror (rc, "cannot start the transport stream", err, errlen);
            return -EIO;
        }
        self->header_written = true;
    }
    self->started = true;
    self->last_pts = pts;
    if ((rc = av_frame_make_writable (self->frame)) < 0) {
        s_averror (rc, "video frame buffer", err, errlen);
        return -ENOMEM;
    }
    const uint8_t *src[1] = {rgba};
    const int stride[1] = {self->cfg.width_px * 4};
    sws_scale (self->sws, src, stride, 0, self->cfg.height_px, self->frame->data,
               self->frame->linesize);
    self->frame->pts = pts;
    // An IDR when the last one is keyframe_s old (frames may come irregularly).
    bool want_key = pts - self->last_key_pts >= llround (self->cfg.keyframe_s * IM_VIDEO_CLOCK_HZ);
    self->frame->pict_type = want_key ? AV_PICTURE_TYPE_I : AV_PICTURE_TYPE_NONE;
    if (want_key)
        self->last_key_pts = pts;
    if ((rc = avcodec_send_frame (self->enc, self->frame)) < 0) {
        s_averror (rc, "H.264 encoding failed", err, errlen);
        return -EIO;
    }
    self->stats.frames++;
    if ((rc = s_drain (self, keyframe, err, errlen)) < 0)
        return rc;
    if (klv_len > 0) {
        AVPacket *p = self->pkt;
        if ((rc = av_new_packet (p, (int)klv_len)) < 0)
            return -ENOMEM;
        memcpy (p->data, klv, klv_len);
        p->pts = p->dts = av_rescale_q (pts, self->enc->time_base, self->klv->time_base);
        p->stream_index = self->klv->index;
        p->flags |= AV_PKT_FLAG_KEY;
        rc = av_write_frame (self->mux, p);
        av_packet_unref (p);
        if (rc < 0) {
            s_averror (rc, "cannot mux a KLV packet", err, errlen);
            return -EIO;
        }
        self->stats.klv_packets++;
    }
    avio_flush (self->mux->pb);
    return 0;
}

int im_video_finish (im_video_t *self, char *err, size_t errlen)
{
    if (self->finished)
        return 0;
    self->finished = true;
    if (!self->header_written)
        return 0; // no frame: no stream
    int rc = avcodec_send_frame (self->enc, NULL);
    if (rc < 0 && rc != AVERROR_EOF) {
        s_averror (rc, "cannot drain the H.264 encoder", err, errlen);
        return -EIO;
    }
    if ((rc = s_drain (self, NULL, err, errlen)) < 0)
        return rc;
    if ((rc = av_write_trailer (self->mux)) < 0) {
        s_averror (rc, "cannot end the transport stream", err, errlen);
        return -EIO;
    }
    avio_flush (self->mux->pb);
    return 0;
}

void im_video_continue (im_video_t *self)
{
    self->rebase = true;
}

void im_video_stats (const im_video_t *self, im_video_stats_t *ret)
{
    *ret = self->stats;
}

void im_video_destroy (im_video_t **self_p)
{
    im_video_t *self = self_p ? *self_p : NULL;
    if (!self)
        return;
    s_free (self);
    *self_p = NULL;
}
