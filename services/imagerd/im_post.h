/* im_post — what is done to a frame after it is read back: the infrared
 * sensor's blur, noise and polarity, and the text overlay (a built-in 5 × 7
 * dot-matrix font). Pure: no GL, no logging; the noise from a seeded
 * generator. Frames are RGBA, 4 bytes a pixel, top row first. */
#ifndef IM_POST_H
#define IM_POST_H

#include "im_params.h"

#include <stddef.h>
#include <stdint.h>

typedef struct {
    int w, h;
    float *a, *b; // scratch, w × h each
    uint64_t rng;
} im_post_t;

/* Scratch for w × h frames and the noise's seed. 0 or -ENOMEM. */
int im_post_init (im_post_t *self, int w, int h, uint64_t seed);
void im_post_fini (im_post_t *self);

/* Infrared: Gaussian blur of blur_px (standard deviation; 0: none), noise of
 * noise_k kelvin (as grey levels on the display's scale), then black-hot
 * inverts. The frame stays grey (R = G = B). */
void im_post_infrared (im_post_t *self, uint8_t *rgba, const im_params_t *p);

/* Text at (x, y) (top-left of the first glyph), each dot scale × scale
 * pixels, in colour rgb; lower case is drawn as upper case, characters the
 * font lacks as a box. Returns the width drawn in pixels. */
int im_post_text (uint8_t *rgba, int w, int h, int x, int y, int scale, const char *text,
                  const uint8_t rgb[3]);
/* The overlay: lines of text at the top-left on a darkened band. */
void im_post_overlay (uint8_t *rgba, int w, int h, const char *const *lines, size_t n);
/* A status block: lines of text on a darkened box whose bottom-left corner
 * is at (x, y), with a leader line from there down-left to the point it
 * belongs to (x - lead, y + lead); clipped to the image. */
void im_post_status_block (uint8_t *rgba, int w, int h, int x, int y, int lead,
                           const char *const *lines, size_t n);

/* The frame code: a frame number burnt into the image, machine-readable, to
 * measure a video's delay to the screen (glass to glass). IM_POST_CODE_BITS
 * cells of IM_POST_CODE_CELL × IM_POST_CODE_CELL pixels in a row along the
 * bottom edge, from (IM_POST_CODE_CELL / 2, h − 1.5 × IM_POST_CODE_CELL),
 * most significant bit first: white for 1, black for 0, the number modulo
 * 2^IM_POST_CODE_BITS. Read a cell's centre pixel: luminance above half is 1.
 * Nothing is drawn when the row does not fit the image. */
#define IM_POST_CODE_BITS 20
#define IM_POST_CODE_CELL 12
void im_post_frame_code (uint8_t *rgba, int w, int h, uint64_t number);
/* The number read back from a frame (a decoded one too): the cells' centres,
 * luminance (R + G + B) / 3 above 127.5 is 1. -1 when the row does not fit. */
long im_post_frame_code_read (const uint8_t *rgba, int w, int h);

#endif
