/* im_post — infrared post-processing and the text overlay (see im_post.h). */
#include "im_post.h"
#include "cgs_util.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

int im_post_init (im_post_t *self, int w, int h, uint64_t seed)
{
    memset (self, 0, sizeof *self);
    if (w < 1 || h < 1)
        return -EINVAL;
    self->w = w;
    self->h = h;
    self->a = malloc ((size_t)w * (size_t)h * sizeof *self->a);
    self->b = malloc ((size_t)w * (size_t)h * sizeof *self->b);
    self->rng = seed;
    if (!self->a || !self->b) {
        im_post_fini (self);
        return -ENOMEM;
    }
    return 0;
}

void im_post_fini (im_post_t *self)
{
    free (self->a);
    free (self->b);
    self->a = self->b = NULL;
}

/* One pass of a normalised kernel of radius r along rows (dx 1) or columns. */
static void s_convolve (const float *in, float *out, int w, int h, const float *k, int r, bool rows)
{
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            double s = 0;
            for (int i = -r; i <= r; i++) {
                int xx = rows ? x + i : x, yy = rows ? y : y + i;
                xx = xx < 0 ? 0 : xx >= w ? w - 1 : xx; // edges repeat
                yy = yy < 0 ? 0 : yy >= h ? h - 1 : yy;
                s += k[i + r] * in[(size_t)yy * (size_t)w + (size_t)xx];
            }
            out[(size_t)y * (size_t)w + (size_t)x] = (float)s;
        }
}

static double s_gauss (uint64_t *rng)
{
    double u1 = cgs_uniform01 (rng), u2 = cgs_uniform01 (rng);
    return sqrt (-2.0 * log (u1 > 0 ? u1 : 1e-300)) * cos (2.0 * M_PI * u2);
}

void im_post_infrared (im_post_t *self, uint8_t *rgba, const im_params_t *p)
{
    const int w = self->w, h = self->h;
    const size_t n = (size_t)w * (size_t)h;
    for (size_t i = 0; i < n; i++)
        self->a[i] = rgba[4 * i];
    if (p->blur_px > 0) {
        enum { RMAX = 30 };
        int r = (int)ceil (3.0 * p->blur_px);
        r = r > RMAX ? RMAX : r;
        float k[2 * RMAX + 1];
        double sum = 0;
        for (int i = -r; i <= r; i++)
            sum += k[i + r] = (float)exp (-0.5 * i * i / (p->blur_px * p->blur_px));
        for (int i = 0; i <= 2 * r; i++)
            k[i] = (float)(k[i] / sum);
        s_convolve (self->a, self->b, w, h, k, r, true);
        s_convolve (self->b, self->a, w, h, k, r, false);
    }
    double sd = p->noise_k / (p->display_max_k - p->display_min_k) * 255.0;
    for (size_t i = 0; i < n; i++) {
        double g = self->a[i] + (sd > 0 ? sd * s_gauss (&self->rng) : 0.0);
        g = g < 0 ? 0 : g > 255 ? 255 : g;
        uint8_t v = (uint8_t)lrint (p->polarity == IM_BLACK_HOT ? 255.0 - g : g);
        rgba[4 * i] = rgba[4 * i + 1] = rgba[4 * i + 2] = v;
        rgba[4 * i + 3] = 255;
    }
}

/* ---- the font: 5 × 7 dots, a byte a row, the leftmost dot the 0x10 bit ------ */

static const char s_chars[] = " 0123456789ABCDEFGHIJKLMNOPQRSTUVWXYZ.:-+/%()=,";
static const uint8_t s_glyphs[][7] = {
    {0, 0, 0, 0, 0, 0, 0},                      // space
    {0x0E, 0x11, 0x13, 0x15, 0x19, 0x11, 0x0E}, // 0
    {0x04, 0x0C, 0x04, 0x04, 0x04, 0x04, 0x0E}, // 1
    {0x0E, 0x11, 0x01, 0x02, 0x04, 0x08, 0x1F}, // 2
    {0x1F, 0x02, 0x04, 0x02, 0x01, 0x11, 0x0E}, // 3
    {0x02, 0x06, 0x0A, 0x12, 0x1F, 0x02, 0x02}, // 4
    {0x1F, 0x10, 0x1E, 0x01, 0x01, 0x11, 0x0E}, // 5
    {0x06, 0x08, 0x10, 0x1E, 0x11, 0x11, 0x0E}, // 6
    {0x1F, 0x01, 0x02, 0x04, 0x08, 0x08, 0x08}, // 7
    {0x0E, 0x11, 0x11, 0x0E, 0x11, 0x11, 0x0E}, // 8
    {0x0E, 0x11, 0x11, 0x0F, 0x01, 0x02, 0x0C}, // 9
    {0x0E, 0x11, 0x11, 0x1F, 0x11, 0x11, 0x11}, // A
    {0x1E, 0x11, 0x11, 0x1E, 0x11, 0x11, 0x1E}, // B
    {0x0E, 0x11, 0x10, 0x10, 0x10, 0x11, 0x0E}, // C
    {0x1C, 0x12, 0x11, 0x11, 0x11, 0x12, 0x1C}, // D
    {0x1F, 0x10, 0x10, 0x1E, 0x10, 0x10, 0x1F}, // E
    {0x1F, 0x10, 0x10, 0x1E, 0x10, 0x10, 0x10}, // F
    {0x0E, 0x11, 0x10, 0x17, 0x11, 0x11, 0x0F}, // G
    {0x11, 0x11, 0x11, 0x1F, 0x11, 0x11, 0x11}, // H
    {0x0E, 0x04, 0x04, 0x04, 0x04, 0x04, 0x0E}, // I
    {0x07, 0x02, 0x02, 0x02, 0x02, 0x12, 0x0C}, // J
    {0x11, 0x12, 0x14, 0x18, 0x14, 0x12, 0x11}, // K
    {0x10, 0x10, 0x10, 0x10, 0x10, 0x10, 0x1F}, // L
    {0x11, 0x1B, 0x15, 0x15, 0x11, 0x11, 0x11}, // M
    {0x11, 0x11, 0x19, 0x15, 0x13, 0x11, 0x11}, // N
    {0x0E, 0x11, 0x11, 0x11, 0x11, 0x11, 0x0E}, // O
    {0x1E, 0x11, 0x11, 0x1E, 0x10, 0x10, 0x10}, // P
    {0x0E, 0x11, 0x11, 0x11, 0x15, 0x12, 0x0D}, // Q
    {0x1E, 0x11, 0x11, 0x1E, 0x14, 0x12, 0x11}, // R
    {0x0F, 0x10, 0x10, 0x0E, 0x01, 0x01, 0x1E}, // S
    {0x1F, 0x04, 0x04, 0x04, 0x04, 0x04, 0x04}, // T
    {0x11, 0x11, 0x11, 0x11, 0x11, 0x11, 0x0E}, // U
    {0x11, 0x11, 0x11, 0x11, 0x11, 0x0A, 0x04}, // V
    {0x11, 0x11, 0x11, 0x15, 0x15, 0x15, 0x0A}, // W
    {0x11, 0x11, 0x0A, 0x04, 0x0A, 0x11, 0x11}, // X
    {0x11, 0x11, 0x11, 0x0A, 0x04, 0x04, 0x04}, // Y
    {0x1F, 0x01, 0x02, 0x04, 0x08, 0x10, 0x1F}, // Z
    {0x00, 0x00, 0x00, 0x00, 0x00, 0x0C, 0x0C}, // .
    {0x00, 0x0C, 0x0C, 0x00, 0x0C, 0x0C, 0x00}, // :
    {0x00, 0x00, 0x00, 0x1F, 0x00, 0x00, 0x00}, // -
    {0x00, 0x04, 0x04, 0x1F, 0x04, 0x04, 0x00}, // +
    {0x00, 0x01, 0x02, 0x04, 0x08, 0x10, 0x00}, // /
    {0x18, 0x19, 0x02, 0x04, 0x08, 0x13, 0x03}, // %
    {0x02, 0x04, 0x08, 0x08, 0x08, 0x04, 0x02}, // (
    {0x08, 0x04, 0x02, 0x02, 0x02, 0x04, 0x08}, // )
    {0x00, 0x00, 0x1F, 0x00, 0x1F, 0x00, 0x00}, // =
    {0x00, 0x00, 0x00, 0x00, 0x0C, 0x04, 0x08}, // ,
};
static const uint8_t s_box[7] = {0x1F, 0x11, 0x11, 0x11, 0x11, 0x11, 0x1F};

int im_post_text (uint8_t *rgba, int w, int h, int x, int y, int scale, const char *text,
                  const uint8_t rgb[3])
{
    int x0 = x;
    for (const char *c = text; *c; c++, x += 6 * scale) {
        const char *at = strchr (s_chars, toupper ((unsigned char)*c));
        const uint8_t *g = at && *c ? s_glyphs[at - s_chars] : s_box;
        for (int row = 0; row < 7; row++)
            for (int col = 0; col < 5; col++) {
                if (!(g[row] & (0x10 >> col)))
                    continue;
                for (int dy = 0; dy < scale; dy++)
                    for (int dx = 0; dx < scale; dx++) {
                        int px = x + col * scale + dx, py = y + row * scale + dy;
                        if (px < 0 || py < 0 || px >= w || py >= h)
                            continue;
                        uint8_t *p = rgba + 4 * ((size_t)py * (size_t)w + (size_t)px);
                        p[0] = rgb[0], p[1] = rgb[1], p[2] = rgb[2], p[3] = 255;
                    }
            }
    }
    return x - x0;
}

/* A third of every pixel's colour in [x0, x1) × [y0, y1), clipped to the image. */
static void s_darken (uint8_t *rgba, int w, int h, int x0, int y0, int x1, int y1)
{
    for (int y = y0 < 0 ? 0 : y0; y < y1 && y < h; y++)
        for (int x = x0 < 0 ? 0 : x0; x < x1 && x < w; x++) {
            uint8_t *p = rgba + 4 * ((size_t)y * (size_t)w + (size_t)x);
            p[0] = (uint8_t)(p[0] / 3), p[1] = (uint8_t)(p[1] / 3), p[2] = (uint8_t)(p[2] / 3);
        }
}

void im_post_status_block (uint8_t *rgba, int w, int h, int x, int y, int lead,
                           const char *const *lines, size_t n)
{
    int scale = w >= 960 ? 2 : 1, line_h = 9 * scale, width = 0;
    for (size_t i = 0; i < n; i++)
        width = width > (int)strlen (lines[i]) ? width : (int)strlen (lines[i]);
    int bw = width * 6 * scale + 4 * scale, bh = (int)n * line_h + 2 * scale, top = y - bh;
    s_darken (rgba, w, h, x, top, x + bw, y);
    static const uint8_t yellow[3] = {255, 230, 64};
    for (int k = 0; k <= lead; k++) { // the leader, one pixel wide
        int xx = x - k, yy = y + k;
        if (xx >= 0 && yy >= 0 && xx < w && yy < h)
            memcpy (rgba + 4 * ((size_t)yy * (size_t)w + (size_t)xx), yellow, 3);
    }
    for (size_t i = 0; i < n; i++)
        im_post_text (rgba, w, h, x + 2 * scale, top + 2 * scale + (int)i * line_h, scale, lines[i],
                      yellow);
}

void im_post_overlay (uint8_t *rgba, int w, int h, const char *const *lines, size_t n)
{
    int scale = w >= 960 ? 2 : 1, line_h = 9 * scale;
    int band = (int)n * line_h + 4 * scale;
    s_darken (rgba, w, h, 0, 0, w, band);
    static const uint8_t white[3] = {255, 255, 255};
    for (size_t i = 0; i < n; i++)
        im_post_text (rgba, w, h, 3 * scale, 3 * scale + (int)i * line_h, scale, lines[i], white);
}

static bool s_code_fits (int w, int h)
{
    return w >= (IM_POST_CODE_BITS + 1) * IM_POST_CODE_CELL && h >= 2 * IM_POST_CODE_CELL;
}

void im_post_frame_code (uint8_t *rgba, int w, int h, uint64_t number)
{
    if (!s_code_fits (w, h))
        return;
    int x0 = IM_POST_CODE_CELL / 2, y0 = h - 3 * IM_POST_CODE_CELL / 2;
    for (int b = 0; b < IM_POST_CODE_BITS; b++) {
        uint8_t v = (number >> (IM_POST_CODE_BITS - 1 - b)) & 1 ? 255 : 0;
        for (int y = y0; y < y0 + IM_POST_CODE_CELL; y++)
            for (int x = x0 + b * IM_POST_CODE_CELL; x < x0 + (b + 1) * IM_POST_CODE_CELL; x++) {
                uint8_t *p = rgba + 4 * ((size_t)y * (size_t)w + (size_t)x);
                p[0] = p[1] = p[2] = v;
                p[3] = 255;
            }
    }
}

long im_post_frame_code_read (const uint8_t *rgba, int w, int h)
{
    if (!s_code_fits (w, h))
        return -1;
    int x0 = IM_POST_CODE_CELL / 2, y = h - IM_POST_CODE_CELL;
    long n = 0;
    for (int b = 0; b < IM_POST_CODE_BITS; b++) {
        int x = x0 + b * IM_POST_CODE_CELL + IM_POST_CODE_CELL / 2;
        const uint8_t *p = rgba + 4 * ((size_t)y * (size_t)w + (size_t)x);
        n = n << 1 | ((p[0] + p[1] + p[2]) / 3.0 > 127.5);
    }
    return n;
}
