/* im_vout — the video's outputs (see im_vout.h). */
#include "im_vout.h"

#include "cgs_util.h"
#include "im_video.h"

#include <libavformat/avformat.h>

#include <errno.h>
#include <fcntl.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

struct im_vout {
    int fd;
    off_t file_size; // whole packets written
    AVIOContext *udp;
    bool keep, broken; // broken: a frame's bytes could not all be kept
    uint8_t *frame;
    size_t frame_len, frame_cap;
    im_vout_stats_t stats;
};

static void s_fail (im_vout_t *self, const char *fmt, ...) __attribute__ ((format (printf, 2, 3)));
static void s_fail (im_vout_t *self, const char *fmt, ...)
{
    va_list ap;
    va_start (ap, fmt);
    vsnprintf (self->stats.last_error, sizeof self->stats.last_error, fmt, ap);
    va_end (ap);
}

static int s_open_file (im_vout_t *self, const char *path, char *err, size_t errlen)
{
    self->fd = open (path, O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0644);
    struct stat st;
    if (self->fd < 0 || fstat (self->fd, &st) < 0) {
        snprintf (err, errlen, "cannot open the video file %s: %s", path, strerror (errno));
        return -errno;
    }
    off_t whole = st.st_size - st.st_size % IM_VIDEO_TS_PACKET;
    if (whole != st.st_size) { // a crash mid-packet: cut back to the last whole one
        if (ftruncate (self->fd, whole) < 0) {
            snprintf (err, errlen, "cannot cut the partial packet off %s: %s", path,
                      strerror (errno));
            return -errno;
        }
        self->stats.cut_bytes = (uint64_t)(st.st_size - whole);
    }
    self->file_size = whole;
    return 0;
}

static int s_open_udp (im_vout_t *self, const im_vout_config_t *cfg, char *err, size_t errlen)
{
    char url[256];
    int n = snprintf (url, sizeof url, "udp://%s:%d?pkt_size=%d&ttl=%d", cfg->udp_host,
                      cfg->udp_port, IM_VIDEO_CHUNK, cfg->ttl);
    if (cfg->local_addr && *cfg->local_addr)
        snprintf (url + n, sizeof url - (size_t)n, "&localaddr=%s", cfg->local_addr);
    avformat_network_init ();
    int rc = avio_open2 (&self->udp, url, AVIO_FLAG_WRITE, NULL, NULL);
    if (rc < 0) {
        char why[AV_ERROR_MAX_STRING_SIZE] = "";
        av_strerror (rc, why, sizeof why);
        snprintf (err, errlen, "cannot send video to %s: %s", url, why);
        return -EIO;
    }
    return 0;
}

im_vout_t *im_vout_new (const im_vout_config_t *cfg, char *err, size_t errlen)
{
    im_vout_t *self = calloc (1, sizeof *self);
    if (!self) {
        snprintf (err, errlen, "out of memory");
        return NULL;
    }
    self->fd = -1;
    self->keep = cfg->keep_frame;
    if ((cfg->file && *cfg->file && s_open_file (self, cfg->file, err, errlen) < 0) ||
        (cfg->udp_host && *cfg->udp_host && s_open_udp (self, cfg, err, errlen) < 0)) {
        im_vout_destroy (&self);
        return NULL;
    }
    return self;
}

void im_vout_write (void *arg, const uint8_t *ts, size_t len)
{
    im_vout_t *self = arg;
    if (self->fd >= 0) {
        int rc = cgs_write_all (self->fd, ts, len);
        if (rc < 0) {
            self->stats.file_errors++;
            s_fail (self, "writing the video file: %s", strerror (-rc));
            // Back to the last whole packet, so later writes stay on the grid.
            if (ftruncate (self->fd, self->file_size) < 0)
                s_fail (self, "writing the video file: %s; and cannot cut it back: %s",
                        strerror (-rc), strerror (errno));
        } else {
            self->stats.file_bytes += len;
            self->file_size += (off_t)len;
        }
    }
    if (self->udp) {
        avio_write (self->udp, ts, (int)len);
        avio_flush (self->udp); // one datagram
        if (self->udp->error) {
            self->stats.udp_errors++;
            char why[AV_ERROR_MAX_STRING_SIZE] = "";
            av_strerror (self->udp->error, why, sizeof why);
            s_fail (self, "sending video: %s", why);
            self->udp->error = 0;
        } else {
            self->stats.datagrams++;
        }
    }
    if (self->keep) {
        if (self->frame_len + len > self->frame_cap) {
            size_t cap = self->frame_cap ? self->frame_cap : 65536;
            while (cap < self->frame_len + len)
                cap *= 2;
            uint8_t *f = realloc (self->frame, cap);
            if (!f) {
                s_fail (self, "out of memory for a video frame's bytes");
                if (!self->broken)
                    self->stats.frames_lost++;
                self->broken = true;
                return;
            }
            self->frame = f;
            self->frame_cap = cap;
        }
        memcpy (self->frame + self->frame_len, ts, len);
        self->frame_len += len;
    }
}

const uint8_t *im_vout_frame (const im_vout_t *self, size_t *len)
{
    *len = self->broken ? 0 : self->frame_len;
    return self->broken ? NULL : self->frame;
}

void im_vout_frame_reset (im_vout_t *self)
{
    self->frame_len = 0;
    self->broken = false;
}

void im_vout_stats (const im_vout_t *self, im_vout_stats_t *ret)
{
    *ret = self->stats;
}

void im_vout_destroy (im_vout_t **self_p)
{
    im_vout_t *self = self_p ? *self_p : NULL;
    if (!self)
        return;
    if (self->fd >= 0)
        close (self->fd);
    avio_closep (&self->udp);
    free (self->frame);
    free (self);
    *self_p = NULL;
}
