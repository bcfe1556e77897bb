/* im_png — PNG files of frames, off the rendering path (see im_png.h). */
#include "im_png.h"
#include "cgs_state.h"
#include "cgs_util.h"

#include <errno.h>
#include <png.h>
#include <pthread.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int im_png_write (const char *path, const uint8_t *rgba, int w, int h, char *err, size_t errlen)
{
    char tmp[4200];
    snprintf (tmp, sizeof tmp, "%s.tmp", path);
    png_image img;
    memset (&img, 0, sizeof img);
    img.version = PNG_IMAGE_VERSION;
    img.width = (png_uint_32)w;
    img.height = (png_uint_32)h;
    img.format = PNG_FORMAT_RGBA;
    FILE *f = fopen (tmp, "wb");
    if (!f) {
        int e = errno;
        cgs_errf (err, errlen, "%s: %s", tmp, strerror (e));
        return -e;
    }
    int ok = png_image_write_to_stdio (&img, f, 0, rgba, 0, NULL);
    int e = ok ? 0 : EIO;
    if (fclose (f) != 0 && ok)
        e = errno;
    if (e) {
        cgs_errf (err, errlen, "%s: %s", tmp, ok ? strerror (e) : img.message);
        remove (tmp);
        return -e;
    }
    if (rename (tmp, path) != 0) {
        e = errno;
        cgs_errf (err, errlen, "%s: %s", path, strerror (e));
        remove (tmp);
        return -e;
    }
    return 0;
}

int im_png_read (const char *path, uint8_t **ret_rgba, int *ret_w, int *ret_h, char *err,
                 size_t errlen)
{
    png_image img;
    memset (&img, 0, sizeof img);
    img.version = PNG_IMAGE_VERSION;
    if (!png_image_begin_read_from_file (&img, path)) {
        cgs_errf (err, errlen, "%s: %s", path, img.message);
        return -EIO;
    }
    img.format = PNG_FORMAT_RGBA;
    uint8_t *buf = malloc (PNG_IMAGE_SIZE (img));
    if (!buf) {
        png_image_free (&img);
        cgs_errf (err, errlen, "%s: out of memory", path);
        return -ENOMEM;
    }
    if (!png_image_finish_read (&img, NULL, buf, 0, NULL)) {
        cgs_errf (err, errlen, "%s: %s", path, img.message);
        free (buf);
        return -EIO;
    }
    *ret_rgba = buf;
    *ret_w = (int)img.width;
    *ret_h = (int)img.height;
    return 0;
}

typedef struct {
    uint8_t *rgba;
    int w, h;
    char name[256];
} s_job_t;

struct im_png_writer {
    char dir[4096];
    pthread_t thread;
    pthread_mutex_t lock;
    pthread_cond_t cond;
    s_job_t *jobs; // ring
    size_t depth, head, count;
    bool stop;
    im_png_stats_t stats;
};

static void *s_run (void *arg)
{
    im_png_writer_t *self = arg;
    pthread_mutex_lock (&self->lock);
    for (;;) {
        while (self->count == 0 && !self->stop)
            pthread_cond_wait (&self->cond, &self->lock);
        if (self->count == 0)
            break; // stopping, and everything is written
        s_job_t job = self->jobs[self->head];
        self->head = (self->head + 1) % self->depth;
        self->count--;
        pthread_mutex_unlock (&self->lock);
        char path[4400], err[256] = "";
        snprintf (path, sizeof path, "%s/%s", self->dir, job.name);
        int rc = im_png_write (path, job.rgba, job.w, job.h, err, sizeof err);
        free (job.rgba);
        pthread_mutex_lock (&self->lock);
        if (rc < 0) {
            self->stats.failed++;
            snprintf (self->stats.last_error, sizeof self->stats.last_error, "%s", err);
        } else {
            self->stats.written++;
        }
    }
    pthread_mutex_unlock (&self->lock);
    return NULL;
}

im_png_writer_t *im_png_writer_new (const char *dir, size_t depth, char *err, size_t errlen)
{
    if (depth < 1 || strlen (dir) >= 4096) {
        cgs_errf (err, errlen, "a PNG writer needs a queue and a folder name under 4096 bytes");
        return NULL;
    }
    if (cgs_state_mkdir (dir) < 0) {
        cgs_errf (err, errlen, "cannot create the image folder %s: %s", dir, strerror (errno));
        return NULL;
    }
    im_png_writer_t *self = calloc (1, sizeof *self);
    if (!self || !(self->jobs = calloc (depth, sizeof *self->jobs))) {
        free (self);
        cgs_errf (err, errlen, "out of memory for the PNG writer");
        return NULL;
    }
    snprintf (self->dir, sizeof self->dir, "%s", dir);
    self->depth = depth;
    pthread_mutex_init (&self->lock, NULL);
    pthread_cond_init (&self->cond, NULL);
    if (pthread_create (&self->thread, NULL, s_run, self) != 0) {
        cgs_errf (err, errlen, "cannot start the PNG writer thread");
        pthread_mutex_destroy (&self->lock);
        pthread_cond_destroy (&self->cond);
        free (self->jobs);
        free (self);
        return NULL;
    }
    return self;
}

int im_png_writer_submit (im_png_writer_t *self, const uint8_t *rgba, int w, int h,
                          const char *name)
{
    size_t bytes = (size_t)w * (size_t)h * 4;
    pthread_mutex_lock (&self->lock);
    bool full = self->count == self->depth;
    if (full)
        self->stats.dropped++;
    pthread_mutex_unlock (&self->lock);
    if (full)
        return -EAGAIN;
    uint8_t *copy = malloc (bytes);
    if (!copy)
        return -ENOMEM;
    memcpy (copy, rgba, bytes);
    s_job_t job = {.rgba = copy, .w = w, .h = h};
    snprintf (job.name, sizeof job.name, "%s", name);
    pthread_mutex_lock (&self->lock);
    self->jobs[(self->head + self->count) % self->depth] = job; // only this thread adds
    self->count++;
    self->stats.queued++;
    pthread_cond_signal (&self->cond);
    pthread_mutex_unlock (&self->lock);
    return 0;
}

void im_png_writer_stats (im_png_writer_t *self, im_png_stats_t *ret)
{
    pthread_mutex_lock (&self->lock);
    *ret = self->stats;
    pthread_mutex_unlock (&self->lock);
}

void im_png_writer_destroy (im_png_writer_t **self_p, im_png_stats_t *ret_final)
{
    if (!self_p || !*self_p)
        return;
    im_png_writer_t *self = *self_p;
    pthread_mutex_lock (&self->lock);
    self->stop = true;
    pthread_cond_signal (&self->cond);
    pthread_mutex_unlock (&self->lock);
    pthread_join (self->thread, NULL);
    if (ret_final)
        *ret_final = self->stats;
    pthread_mutex_destroy (&self->lock);
    pthread_cond_destroy (&self->cond);
    free (self->jobs);
    free (self);
    *self_p = NULL;
}
