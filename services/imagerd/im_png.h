/* im_png — PNG files of frames, encoded by a writer thread so the renderer
 * never waits on zlib or the disk. Each file is written to NAME.tmp and
 * renamed, so a reader (the map display polling latest.png) never sees half
 * a file. A full queue drops the frame and counts it; closing the writer
 * writes everything queued first. */
#ifndef IM_PNG_H
#define IM_PNG_H

#include <stddef.h>
#include <stdint.h>

/* Write an RGBA frame (top row first) to path now. 0 or -errno with err. */
int im_png_write (const char *path, const uint8_t *rgba, int w, int h, char *err, size_t errlen);
/* Read a PNG into a new RGBA buffer (free it). 0 or -errno with err. */
int im_png_read (const char *path, uint8_t **ret_rgba, int *ret_w, int *ret_h, char *err,
                 size_t errlen);

typedef struct im_png_writer im_png_writer_t;

typedef struct {
    uint64_t queued, written, dropped, failed;
    char last_error[256];
} im_png_stats_t;

/* A writer into folder dir (created if missing), holding at most depth
 * frames. NULL with the reason in err. */
im_png_writer_t *im_png_writer_new (const char *dir, size_t depth, char *err, size_t errlen);
/* Queue a copy of the frame to be written as dir/name. 0, or -EAGAIN when
 * the queue is full (dropped, counted), -ENOMEM. */
int im_png_writer_submit (im_png_writer_t *self, const uint8_t *rgba, int w, int h,
                          const char *name);
void im_png_writer_stats (im_png_writer_t *self, im_png_stats_t *ret);
/* Write what is queued, stop the thread, free; *ret_final (may be NULL)
 * gets the counts once everything is written. */
void im_png_writer_destroy (im_png_writer_t **self_p, im_png_stats_t *ret_final);

#endif
