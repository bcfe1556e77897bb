/* test_im_video — imagerd's video: im_video's MPEG transport stream read back
 * by libavformat's demuxer and libavcodec's H.264 decoder (the reading side
 * of the libraries, not the writing side the module uses), im_vout's file,
 * and im_frame_klv's metadata from a camera and its footprint.
 *   - the sink gets whole 188-byte packets (sync byte 0x47), at most seven
 *     a call; a keyframe's bytes begin with PAT (PID 0) and PMT;
 *   - the demuxer finds an H.264 stream and a SMPTE KLV stream (stream type
 *     0x06 with the KLVA registration: asynchronous carriage), one KLV
 *     packet per frame with the very bytes given and its frame's PTS
 *     (time × 90 kHz);
 *   - an IDR frame at least every keyframe_s of frame time, also when frames
 *     come irregularly; none in between;
 *   - decoded frames match the source within the codec's loss (PSNR);
 *   - a frame not after the last is refused and writes nothing; bad sizes,
 *     presets and times are refused with the reason;
 *   - the video file: a partial packet at its end is cut at open, writes
 *     append;
 *   - KLV from a camera: a fixed camera is at azimuth 0, elevation −ε, roll 0
 *     relative to the platform, for any attitude; stabilized and staring
 *     cameras' relative angles rebuild their boresight and right axis from
 *     the platform's body axes; corners go upper left, upper right, lower
 *     right, lower left (the footprint's far-left, far-right, near-right,
 *     near-left); heights are one value for MSL and the ellipsoid.
 * Needs -Iservices/imagerd. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "im_frame.h"
#include "im_post.h"
#include "im_video.h"
#include "im_vout.h"

#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libswscale/swscale.h>

#include <fcntl.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#define S_W 320
#define S_H 240

/* ---- what the sink got ------------------------------------------------------------- */

typedef struct {
    uint8_t *buf;
    size_t len, cap;
    size_t calls, bad_calls; // calls not whole packets, or too long
} s_ts_t;

static void s_sink (void *arg, const uint8_t *ts, size_t len)
{
    s_ts_t *t = arg;
    t->calls++;
    if (len == 0 || len % IM_VIDEO_TS_PACKET || len > IM_VIDEO_CHUNK)
        t->bad_calls++;
    for (size_t i = 0; i < len; i += IM_VIDEO_TS_PACKET)
        if (ts[i] != 0x47)
            t->bad_calls++;
    if (t->len + len > t->cap) {
        t->cap = (t->len + len) * 2;
        t->buf = realloc (t->buf, t->cap);
        assert_non_null (t->buf);
    }
    memcpy (t->buf + t->len, ts, len);
    t->len += len;
}

static unsigned s_pid (const uint8_t *p)
{
    return (unsigned)(p[1] & 0x1F) << 8 | p[2];
}

/* ---- a source picture: smooth gradients and a moving block --------------------------- */

static void s_picture (uint8_t *rgba, int k)
{
    for (int y = 0; y < S_H; y++)
        for (int x = 0; x < S_W; x++) {
            uint8_t *p = rgba + 4 * ((size_t)y * S_W + (size_t)x);
            p[0] = (uint8_t)(x * 255 / S_W);
            p[1] = (uint8_t)(y * 255 / S_H);
            p[2] = (uint8_t)(128 + 100 * sin ((x + y + 4 * k) / 40.0));
            p[3] = 255;
            int bx = 20 + 6 * k, by = 60;
            if (x >= bx && x < bx + 40 && y >= by && y < by + 30)
                p[0] = p[1] = p[2] = 240;
        }
}

/* ---- reading the stream back with libavformat and libavcodec -------------------------- */

typedef struct {
    const uint8_t *buf;
    size_t len, pos;
} s_reader_t;

static int s_read (void *opaque, uint8_t *buf, int n)
{
    s_reader_t *r = opaque;
    size_t left = r->len - r->pos;
    if (left == 0)
        return AVERROR_EOF;
    size_t k = (size_t)n < left ? (size_t)n : left;
    memcpy (buf, r->buf + r->pos, k);
    r->pos += k;
    return (int)k;
}

#define S_MAX_FRAMES 64

typedef struct {
    int nvideo, nklv, nkey;
    int64_t video_pts[S_MAX_FRAMES], klv_pts[S_MAX_FRAMES];
    bool key[S_MAX_FRAMES];
    uint8_t *klv[S_MAX_FRAMES];
    size_t klv_len[S_MAX_FRAMES];
    int decoded;
    double psnr_min;         // over the decoded frames, against the sources
    long code[S_MAX_FRAMES]; // the frame code read back from each decoded frame
    enum AVCodecID video_id, data_id;
    uint32_t data_tag;
} s_back_t;

static uint8_t s_decoded[S_W * S_H * 4]; // the last decoded frame, as RGBA

/* PSNR of decoded YUV (converted to RGB) against the source RGBA. */
static double s_psnr (struct SwsContext *sws, const AVFrame *f, const uint8_t *src)
{
    uint8_t *rgba = s_decoded;
    uint8_t *dst[1] = {rgba};
    int stride[1] = {S_W * 4};
    sws_scale (sws, (const uint8_t *const *)f->data, f->linesize, 0, S_H, dst, stride);
    double se = 0;
    for (size_t i = 0; i < (size_t)S_W * S_H * 4; i++) {
        if (i % 4 == 3)
            continue;
        double d = (double)rgba[i] - src[i];
        se += d * d;
    }
    double mse = se / ((double)S_W * S_H * 3);
    return mse > 0 ? 10 * log10 (255.0 * 255.0 / mse) : 99;
}

static void s_read_back (const s_ts_t *ts, uint8_t *const *sources, s_back_t *ret)
{
    memset (ret, 0, sizeof *ret);
    ret->psnr_min = 1e9;
    s_reader_t r = {ts->buf, ts->len, 0};
    uint8_t *iobuf = av_malloc (4096);
    AVIOContext *pb = avio_alloc_context (iobuf, 4096, 0, &r, s_read, NULL, NULL);
    AVFormatContext *fc = avformat_alloc_context ();
    fc->pb = pb;
    assert_int_equal (avformat_open_input (&fc, NULL, av_find_input_format ("mpegts"), NULL), 0);
    assert_true (avformat_find_stream_info (fc, NULL) >= 0);
    int vi = -1, di = -1;
    for (unsigned i = 0; i < fc->nb_streams; i++) {
        AVCodecParameters *cp = fc->streams[i]->codecpar;
        if (cp->codec_type == AVMEDIA_TYPE_VIDEO)
            vi = (int)i, ret->video_id = cp->codec_id;
        if (cp->codec_type == AVMEDIA_TYPE_DATA)
            di = (int)i, ret->data_id = cp->codec_id, ret->data_tag = cp->codec_tag;
    }
    assert_true (vi >= 0 && di >= 0);
    const AVCodec *dec = avcodec_find_decoder (AV_CODEC_ID_H264);
    AVCodecContext *dc = avcodec_alloc_context3 (dec);
    avcodec_parameters_to_context (dc, fc->streams[vi]->codecpar);
    assert_int_equal (avcodec_open2 (dc, dec, NULL), 0);
    struct SwsContext *sws = sws_getContext (S_W, S_H, AV_PIX_FMT_YUV420P, S_W, S_H,
                                             AV_PIX_FMT_RGBA, SWS_BILINEAR, NULL, NULL, NULL);
    AVPacket *pkt = av_packet_alloc ();
    AVFrame *fr = av_frame_alloc ();
    for (;;) {
        bool end = av_read_frame (fc, pkt) < 0;
        if (!end && pkt->stream_index == di && ret->nklv < S_MAX_FRAMES) {
            ret->klv_pts[ret->nklv] = pkt->pts;
            ret->klv[ret->nklv] = malloc ((size_t)pkt->size);
            memcpy (ret->klv[ret->nklv], pkt->data, (size_t)pkt->size);
            ret->klv_len[ret->nklv++] = (size_t)pkt->size;
        }
        if (!end && pkt->stream_index == vi && ret->nvideo < S_MAX_FRAMES) {
            ret->video_pts[ret->nvideo] = pkt->pts;
            ret->key[ret->nvideo++] = pkt->flags & AV_PKT_FLAG_KEY;
            ret->nkey += (pkt->flags & AV_PKT_FLAG_KEY) != 0;
        }
        if (end || pkt->stream_index == vi) {
            avcodec_send_packet (dc, end ? NULL : pkt);
            while (avcodec_receive_frame (dc, fr) == 0) {
                if (sources && sources[ret->decoded])
                    ret->psnr_min = fmin (ret->psnr_min, s_psnr (sws, fr, sources[ret->decoded]));
                if (sources && ret->decoded < S_MAX_FRAMES)
                    ret->code[ret->decoded] = im_post_frame_code_read (s_decoded, S_W, S_H);
                ret->decoded++;
            }
        }
        if (end)
            break;
        av_packet_unref (pkt);
    }
    av_frame_free (&fr);
    av_packet_free (&pkt);
    sws_freeContext (sws);
    avcodec_free_context (&dc);
    avformat_close_input (&fc);
    av_freep (&pb->buffer);
    avio_context_free (&pb);
}

static void s_back_free (s_back_t *b)
{
    for (int i = 0; i < b->nklv; i++)
        free (b->klv[i]);
}

static im_video_config_t s_cfg (void)
{
    return (im_video_config_t){.width_px = S_W,
                               .height_px = S_H,
                               .frame_rate_hz = 10,
                               .bitrate_kbps = 2000,
                               .keyframe_s = 1,
                               .preset = "veryfast",
                               .threads = 1};
}

/* A fake KLV packet for frame k: its bytes must come back unchanged. */
static size_t s_fake_klv (uint8_t *b, int k)
{
    static const uint8_t key[16] = {0x06, 0x0E, 0x2B, 0x34, 0x02, 0x0B, 0x01, 0x01,
                                    0x0E, 0x01, 0x03, 0x01, 0x01, 0x00, 0x00, 0x00};
    memcpy (b, key, 16);
    size_t n = 10 + (size_t)k % 7;
    b[16] = (uint8_t)n;
    for (size_t i = 0; i < n; i++)
        b[17 + i] = (uint8_t)(k * 31 + (int)i);
    return 17 + n;
}

/* ---- the stream --------------------------------------------------------------------- */

static void test_stream (void **state)
{
    (void)state;
    enum { N = 35 };
    s_ts_t ts = {0};
    char err[256] = "";
    im_video_config_t cfg = s_cfg ();
    im_video_t *v = im_video_new (&cfg, s_sink, &ts, err, sizeof err);
    assert_non_null (v);
    static uint8_t pics[N][S_W * S_H * 4];
    uint8_t *sources[N + 1] = {0};
    size_t starts[N];
    bool keys[N];
    uint8_t klv[N][64];
    size_t klv_len[N];
    double t0 = 100.0; // simulation time: PTS are time × 90 kHz
    for (int k = 0; k < N; k++) {
        s_picture (pics[k], k);
        im_post_frame_code (pics[k], S_W, S_H, 1000 + (uint64_t)k); // survives the codec
        assert_int_equal (im_post_frame_code_read (pics[k], S_W, S_H), 1000 + k);
        sources[k] = pics[k];
        klv_len[k] = s_fake_klv (klv[k], k);
        starts[k] = ts.len;
        assert_int_equal (im_video_frame (v, pics[k], t0 + 0.1 * k, klv[k], klv_len[k], &keys[k],
                                          err, sizeof err),
                          0);
        assert_true (ts.len > starts[k]); // every frame's bytes are out when it returns
    }
    assert_int_equal (im_video_finish (v, err, sizeof err), 0);
    im_video_stats_t st;
    im_video_stats (v, &st);
    im_video_destroy (&v);
    assert_null (v);
    assert_int_equal (ts.bad_calls, 0);
    assert_int_equal (ts.len % IM_VIDEO_TS_PACKET, 0);
    assert_int_equal (st.frames, N);
    assert_int_equal (st.klv_packets, N);
    assert_int_equal (st.bytes, ts.len);
    // IDR frames at 0, 1, 2, 3 s of frame time: frames 0, 10, 20, 30.
    for (int k = 0; k < N; k++) {
        assert_int_equal (keys[k], k % 10 == 0);
        if (keys[k]) { // PAT and PMT before the frame's first video packet
            unsigned pmt = s_pid (ts.buf + IM_VIDEO_TS_PACKET); // the stream's second packet
            bool pat = false, have_pmt = false;
            size_t i = starts[k];
            for (; i < ts.len && s_pid (ts.buf + i) != 0x100; i += IM_VIDEO_TS_PACKET) {
                pat = pat || s_pid (ts.buf + i) == 0;
                have_pmt = have_pmt || (pat && s_pid (ts.buf + i) == pmt);
            }
            assert_true (pat && have_pmt);
            assert_true (ts.buf[i + 1] & 0x40); // the video PES starts there
        }
    }
    assert_int_equal (st.keyframes, 4);
    s_back_t b;
    s_read_back (&ts, sources, &b);
    assert_int_equal (b.video_id, AV_CODEC_ID_H264);
    assert_int_equal (b.data_id, AV_CODEC_ID_SMPTE_KLV);
    assert_int_equal (b.data_tag, MKTAG ('K', 'L', 'V', 'A'));
    assert_int_equal (b.nvideo, N);
    assert_int_equal (b.nklv, N);
    assert_int_equal (b.nkey, 4);
    for (int k = 0; k < N; k++) {
        int64_t want = llround ((t0 + 0.1 * k) * IM_VIDEO_CLOCK_HZ);
        assert_int_equal (b.video_pts[k], want);
        assert_int_equal (b.klv_pts[k], want);
        assert_int_equal (b.key[k], k % 10 == 0);
        assert_int_equal (b.klv_len[k], klv_len[k]);
        assert_memory_equal (b.klv[k], klv[k], klv_len[k]);
    }
    assert_int_equal (b.decoded, N);
    for (int k = 0; k < N; k++)
        assert_int_equal (b.code[k], 1000 + k);
    printf ("# %d frames %d x %d: %zu bytes of transport stream, PSNR %.1f dB at least\n", N, S_W,
            S_H, ts.len, b.psnr_min);
    assert_true (b.psnr_min > 35.0);
    s_back_free (&b);
    free (ts.buf);
}

/* Frames that come irregularly (skipped frames, a paused exercise): an IDR
 * when the last is keyframe_s old, by the frames' own times. */
static void test_irregular (void **state)
{
    (void)state;
    static const double times[] = {0, 0.1, 0.5, 0.9, 1.05, 1.1, 3.0, 3.2, 3.9, 4.0, 4.01};
    static const bool key[] = {1, 0, 0, 0, 1, 0, 1, 0, 0, 1, 0};
    enum { N = sizeof times / sizeof times[0] };
    s_ts_t ts = {0};
    char err[256];
    im_video_config_t cfg = s_cfg ();
    im_video_t *v = im_video_new (&cfg, s_sink, &ts, err, sizeof err);
    static uint8_t pic[S_W * S_H * 4];
    for (int k = 0; k < N; k++) {
        s_picture (pic, k);
        bool kf;
        assert_int_equal (im_video_frame (v, pic, times[k], NULL, 0, &kf, err, sizeof err), 0);
        assert_int_equal (kf, key[k]);
    }
    im_video_finish (v, err, sizeof err);
    im_video_destroy (&v);
    s_back_t b;
    s_read_back (&ts, NULL, &b);
    assert_int_equal (b.nvideo, N);
    assert_int_equal (b.nklv, 0); // no KLV given, none muxed
    for (int k = 0; k < N; k++)
        assert_int_equal (b.video_pts[k], llround (times[k] * IM_VIDEO_CLOCK_HZ));
    s_back_free (&b);
    free (ts.buf);
}

static void test_refused (void **state)
{
    (void)state;
    s_ts_t ts = {0};
    char err[256] = "";
    im_video_config_t cfg = s_cfg ();
    cfg.width_px = 321;
    assert_null (im_video_new (&cfg, s_sink, &ts, err, sizeof err));
    assert_non_null (strstr (err, "even"));
    cfg = s_cfg ();
    cfg.preset = "warp";
    assert_null (im_video_new (&cfg, s_sink, &ts, err, sizeof err));
    assert_non_null (strstr (err, "warp"));
    cfg = s_cfg ();
    im_video_t *v = im_video_new (&cfg, s_sink, &ts, err, sizeof err);
    static uint8_t pic[S_W * S_H * 4];
    s_picture (pic, 0);
    assert_int_equal (im_video_frame (v, pic, 5.0, NULL, 0, NULL, err, sizeof err), 0);
    size_t len = ts.len;
    // The same time, an earlier one, less than a 90 kHz tick later: refused, nothing written.
    assert_int_equal (im_video_frame (v, pic, 5.0, NULL, 0, NULL, err, sizeof err), -EINVAL);
    assert_non_null (strstr (err, "not after"));
    assert_int_equal (im_video_frame (v, pic, 4.0, NULL, 0, NULL, err, sizeof err), -EINVAL);
    assert_int_equal (
        im_video_frame (v, pic, 5.0 + 0.4 / IM_VIDEO_CLOCK_HZ, NULL, 0, NULL, err, sizeof err),
        -EINVAL);
    assert_int_equal (im_video_frame (v, pic, NAN, NULL, 0, NULL, err, sizeof err), -EINVAL);
    assert_int_equal (im_video_frame (v, pic, -1.0, NULL, 0, NULL, err, sizeof err), -EINVAL);
    assert_int_equal (im_video_frame (v, NULL, 6.0, NULL, 0, NULL, err, sizeof err), -EINVAL);
    assert_int_equal (im_video_frame (v, pic, 6.0, NULL, 5, NULL, err, sizeof err), -EINVAL);
    assert_int_equal (ts.len, len);
    im_video_stats_t st;
    im_video_stats (v, &st);
    assert_int_equal (st.refused, 3);
    assert_int_equal (im_video_frame (v, pic, 5.1, NULL, 0, NULL, err, sizeof err), 0);
    // Time went back (a restarted exercise): after im_video_continue the next
    // frame follows the last by one frame period (10 Hz), a keyframe, and the
    // ones after keep that offset.
    im_video_continue (v);
    bool kf = false;
    assert_int_equal (im_video_frame (v, pic, 0.5, NULL, 0, &kf, err, sizeof err), 0);
    assert_true (kf);
    assert_int_equal (im_video_frame (v, pic, 0.6, NULL, 0, &kf, err, sizeof err), 0);
    assert_false (kf);
    assert_int_equal (im_video_frame (v, pic, 0.6, NULL, 0, NULL, err, sizeof err), -EINVAL);
    assert_int_equal (im_video_finish (v, err, sizeof err), 0);
    s_back_t b;
    s_read_back (&ts, NULL, &b);
    static const double want[] = {5.0, 5.1, 5.2, 5.3};
    assert_int_equal (b.nvideo, 4);
    for (int k = 0; k < 4; k++)
        assert_int_equal (b.video_pts[k], llround (want[k] * IM_VIDEO_CLOCK_HZ));
    s_back_free (&b);
    assert_int_equal (im_video_frame (v, pic, 6.0, NULL, 0, NULL, err, sizeof err), -EINVAL);
    assert_non_null (strstr (err, "ended"));
    im_video_destroy (&v);
    // A stream never started ends with nothing written.
    s_ts_t none = {0};
    v = im_video_new (&cfg, s_sink, &none, err, sizeof err);
    assert_int_equal (im_video_finish (v, err, sizeof err), 0);
    assert_int_equal (none.len, 0);
    im_video_destroy (&v);
    im_video_destroy (NULL);
    free (ts.buf);
}

/* The frame code: round trip, modulo 2^20, and nothing drawn where it does not fit. */
static void test_frame_code (void **state)
{
    (void)state;
    static uint8_t pic[S_W * S_H * 4];
    static const uint64_t nums[] = {0, 1, 0xAAAAA, 0xFFFFF, 123456, (1u << 20) + 5};
    for (size_t i = 0; i < sizeof nums / sizeof nums[0]; i++) {
        s_picture (pic, (int)i);
        im_post_frame_code (pic, S_W, S_H, nums[i]);
        assert_int_equal (im_post_frame_code_read (pic, S_W, S_H), (long)(nums[i] & 0xFFFFF));
    }
    uint8_t small[100 * 20 * 4], copy[sizeof small];
    memset (small, 77, sizeof small);
    memcpy (copy, small, sizeof small);
    im_post_frame_code (small, 100, 20, 5);
    assert_memory_equal (small, copy, sizeof small);
    assert_int_equal (im_post_frame_code_read (small, 100, 20), -1);
}

/* ---- the file ------------------------------------------------------------------------- */

static void test_file (void **state)
{
    (void)state;
    char path[4096];
    const char *dir = getenv ("TMPDIR");
    snprintf (path, sizeof path, "%s/test_im_video_%s", dir && *dir ? dir : "/tmp",
              "XXXXXX"); // mkstemp's template: it fills in the six characters
    int fd = mkstemp (path);
    assert_true (fd >= 0);
    uint8_t junk[3 * IM_VIDEO_TS_PACKET + 50];
    memset (junk, 0x47, sizeof junk);
    assert_int_equal (write (fd, junk, sizeof junk), (ssize_t)sizeof junk);
    close (fd);
    char err[256];
    im_vout_config_t oc = {.file = path, .keep_frame = true};
    im_vout_t *o = im_vout_new (&oc, err, sizeof err);
    assert_non_null (o);
    im_vout_stats_t st;
    im_vout_stats (o, &st);
    assert_int_equal (st.cut_bytes, 50); // the partial packet a crash left
    uint8_t pkt[2 * IM_VIDEO_TS_PACKET];
    memset (pkt, 0x47, sizeof pkt);
    im_vout_write (o, pkt, sizeof pkt);
    size_t n;
    const uint8_t *f = im_vout_frame (o, &n);
    assert_non_null (f);
    assert_int_equal (n, sizeof pkt);
    im_vout_frame_reset (o);
    im_vout_frame (o, &n);
    assert_int_equal (n, 0);
    im_vout_stats (o, &st);
    assert_int_equal (st.file_bytes, sizeof pkt);
    im_vout_destroy (&o);
    assert_null (o);
    struct stat sb;
    assert_int_equal (stat (path, &sb), 0);
    assert_int_equal (sb.st_size, 5 * IM_VIDEO_TS_PACKET);
    unlink (path);
    // A folder that is not there: the reason, not a crash.
    oc.file = "/nonexistent-folder/x.ts";
    assert_null (im_vout_new (&oc, err, sizeof err));
    assert_non_null (strstr (err, "/nonexistent-folder/x.ts"));
    // A UDP destination libavformat refuses.
    oc = (im_vout_config_t){
        .udp_host = "127.0.0.1", .udp_port = 5600, .local_addr = "203.0.113.77"}; // not this host's
    assert_null (im_vout_new (&oc, err, sizeof err));
    assert_non_null (strstr (err, "localaddr=203.0.113.77"));
}

/* ---- KLV from the camera -------------------------------------------------------------- */

static double s_dot (cgs_enu_t a, cgs_enu_t b)
{
    return a.e_m * b.e_m + a.n_m * b.n_m + a.u_m * b.u_m;
}

/* The camera's boresight and right axis rebuilt from the relative angles and
 * the platform's body axes (azimuth about the body's up, clockwise seen from
 * above; elevation up; roll right side down). */
static void s_rebuild (const cgs_camera_t *body, const im_klv_frame_t *k, cgs_enu_t *f,
                       cgs_enu_t *r)
{
    double az = k->sensor_rel_az_deg * M_PI / 180, el = k->sensor_rel_el_deg * M_PI / 180;
    double ro = k->sensor_rel_roll_deg * M_PI / 180;
    double b[3][3] = {{body->forward.e_m, body->forward.n_m, body->forward.u_m},
                      {body->right.e_m, body->right.n_m, body->right.u_m},
                      {body->up.e_m, body->up.n_m, body->up.u_m}};
    // In body coordinates (forward, right, up).
    double fb[3] = {cos (el) * cos (az), cos (el) * sin (az), sin (el)};
    double rg[3] = {-sin (az), cos (az), 0};
    double ug[3] = {-sin (el) * cos (az), -sin (el) * sin (az), cos (el)}; // rg × fb
    double rb[3];
    for (int i = 0; i < 3; i++)
        rb[i] = cos (ro) * rg[i] - sin (ro) * ug[i];
    double out_f[3] = {0}, out_r[3] = {0};
    for (int j = 0; j < 3; j++)
        for (int i = 0; i < 3; i++) {
            out_f[j] += fb[i] * b[i][j];
            out_r[j] += rb[i] * b[i][j];
        }
    *f = (cgs_enu_t){out_f[0], out_f[1], out_f[2]};
    *r = (cgs_enu_t){out_r[0], out_r[1], out_r[2]};
}

static void test_klv_angles (void **state)
{
    (void)state;
    cgs_geo_t *geo = cgs_geo_new (36.0, -117.0, 500.0);
    assert_non_null (geo);
    im_params_t p;
    im_params_defaults (&p);
    static const double att[][3] = {{0, 0, 0}, {70, 5, 30}, {200, -8, -45}, {359, 12, 10}};
    for (int mode = 0; mode < 3; mode++)
        for (size_t a = 0; a < sizeof att / sizeof att[0]; a++) {
            im_uav_t u = {.valid = true,
                          .position = {100, -200, 1500},
                          .heading_deg = att[a][0],
                          .pitch_deg = att[a][1],
                          .roll_deg = att[a][2],
                          .depression_deg = 40,
                          .hfov_deg = 10,
                          .vfov_deg = 7.5,
                          .time_s = 50};
            u.point.stabilized = mode == 1;
            u.point.staring = mode == 2;
            u.point.stare_at = (cgs_enu_t){800, 900, 0};
            cgs_camera_t cam, body;
            assert_int_equal (im_frame_camera (&p, &u, 50, &cam), 0);
            im_uav_t level = u;
            level.depression_deg = 0;
            level.point.stabilized = level.point.staring = false;
            assert_int_equal (im_frame_camera (&p, &level, 50, &body), 0);
            cgs_footprint_t fp;
            cgs_camera_footprint (&cam, NULL, 20000, &fp);
            im_klv_frame_t k;
            assert_int_equal (
                im_frame_klv (&cam, &fp, &u, geo, 1.7e9 + 50, "m", true, u.point.stare_at, 42, &k),
                0);
            if (mode == 0) { // fixed: the mounting itself
                assert_true (fabs (k.sensor_rel_az_deg) < 1e-9 ||
                             fabs (k.sensor_rel_az_deg - 360) < 1e-9);
                assert_true (fabs (k.sensor_rel_el_deg + 40) < 1e-9);
                assert_true (fabs (k.sensor_rel_roll_deg) < 1e-9 ||
                             fabs (k.sensor_rel_roll_deg - 360) < 1e-9);
            }
            cgs_enu_t f, r;
            s_rebuild (&body, &k, &f, &r);
            assert_true (s_dot (f, cam.forward) > 1 - 1e-12);
            assert_true (s_dot (r, cam.right) > 1 - 1e-12);
            assert_true (k.platform_heading_deg == u.heading_deg);
            assert_true (k.platform_pitch_deg == u.pitch_deg);
            assert_true (k.platform_roll_deg == u.roll_deg);
        }
    cgs_geo_destroy (&geo);
}

static void test_klv_places (void **state)
{
    (void)state;
    cgs_geo_t *geo = cgs_geo_new (36.0, -117.0, 500.0);
    im_params_t p;
    im_params_defaults (&p);
    im_uav_t u = {.valid = true,
                  .position = {0, 0, 1000},
                  .heading_deg = 90,
                  .depression_deg = 45,
                  .hfov_deg = 10,
                  .vfov_deg = 8,
                  .time_s = 0};
    cgs_camera_t cam;
    assert_int_equal (im_frame_camera (&p, &u, 0, &cam), 0);
    cgs_footprint_t fp;
    cgs_camera_footprint (&cam, NULL, 20000, &fp);
    im_klv_frame_t k;
    assert_int_equal (
        im_frame_klv (&cam, &fp, &u, geo, 1234.5, "exercise", false, (cgs_enu_t){0}, 0, &k), 0);
    assert_true (k.unix_time_s == 1234.5);
    assert_string_equal (k.mission_id, "exercise");
    cgs_geodetic_t g;
    cgs_geo_enu_to_geodetic (geo, cam.eye, &g);
    assert_true (k.sensor_lat_deg == g.lat_deg && k.sensor_lon_deg == g.lon_deg);
    assert_true (k.sensor_true_alt_m == g.height_m && k.sensor_hae_m == g.height_m);
    // Looking east, 45° down from 1000 m over flat ground at 0: the centre 1000 m east.
    assert_true (fabs (k.slant_range_m - 1000 * sqrt (2)) < 1e-6);
    cgs_geo_enu_to_geodetic (geo, (cgs_enu_t){1000, 0, 0}, &g);
    assert_true (fabs (k.frame_center_lat_deg - g.lat_deg) < 1e-9);
    assert_true (fabs (k.frame_center_lon_deg - g.lon_deg) < 1e-9);
    assert_true (fabs (k.frame_center_elev_m - g.height_m) < 1e-6);
    // Upper left is far-left: looking east, the far corner to the north (left).
    static const int order[4] = {1, 2, 3, 0};
    for (int i = 0; i < 4; i++) {
        cgs_geo_enu_to_geodetic (geo, cgs_footprint_corner_enu (&fp, order[i]), &g);
        assert_true (k.corner_lat_deg[i] == g.lat_deg && k.corner_lon_deg[i] == g.lon_deg);
    }
    assert_true (k.corner_lat_deg[0] > k.frame_center_lat_deg); // upper left: north
    assert_true (k.corner_lon_deg[0] > k.frame_center_lon_deg); // and farther east
    assert_true (k.corner_lat_deg[2] < k.frame_center_lat_deg); // lower right: south, nearer
    assert_true (k.corner_lon_deg[2] < k.frame_center_lon_deg);
    assert_false (k.has_target);
    assert_true (isnan (k.target_lat_deg));
    // A ray that met no ground: no slant range, frame centre or corners.
    cgs_footprint_t clipped = fp;
    clipped.clipped = true;
    im_klv_frame_t kc;
    assert_int_equal (
        im_frame_klv (&cam, &clipped, &u, geo, 1234.5, "", true, (cgs_enu_t){0}, 3, &kc), 0);
    assert_true (isnan (kc.slant_range_m) && isnan (kc.frame_center_lat_deg) &&
                 isnan (kc.corner_lat_deg[0]) && isnan (kc.corner_lon_deg[3]));
    assert_true (kc.sensor_lat_deg == k.sensor_lat_deg && kc.has_target && kc.track_id == 3);
    assert_true (k.hfov_deg == 10 && k.vfov_deg == 8);
    // And it encodes.
    uint8_t buf[IM_KLV_MAX_PACKET];
    assert_true (im_klv_encode (&k, buf, sizeof buf) > 0);
    assert_int_equal (im_frame_klv (&cam, &fp, &u, NULL, 0, "", false, (cgs_enu_t){0}, 0, &k),
                      -EINVAL);
    cgs_geo_destroy (&geo);
}

int main (void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test (test_stream),     cmocka_unit_test (test_irregular),
        cmocka_unit_test (test_refused),    cmocka_unit_test (test_file),
        cmocka_unit_test (test_klv_angles), cmocka_unit_test (test_klv_places),
        cmocka_unit_test (test_frame_code),
    };
    return cmocka_run_group_tests (tests, NULL, NULL);
}
