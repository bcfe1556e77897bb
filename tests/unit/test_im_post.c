/* test_im_post — imagerd's post-processing:
 *   - the 5 × 7 font: text draws only inside its box (6·scale per character
 *     by 7·scale, the sixth column a gap), in its colour, each dot a
 *     scale × scale block; returns its width; a space draws nothing; lower
 *     case draws as upper case; a character the font lacks draws a box (the
 *     cell's outline); text running off the frame is clipped;
 *   - the overlay: a darkened band (each channel a third) under white text,
 *     the rest of the frame untouched;
 *   - the infrared sensor: the Gaussian blur keeps a constant image and the
 *     interior of a gradient (a symmetric kernel keeps linear functions),
 *     and scales a checkerboard's variance by the factor its kernel gives
 *     (separable: the 1-D gain of the pattern, squared, for the amplitude);
 *     the noise has the standard deviation noise_k/(max − min)·255 grey
 *     levels (within 5%) and a Gaussian's 68% within one deviation, the mean
 *     unchanged; the same seed gives the same noise, another seed other
 *     noise, and the next frame new noise; black-hot is 255 − white-hot;
 *     the output is grey (R = G = B), opaque.
 * Needs -Iservices/imagerd (and -Icommon). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "im_params.h"
#include "im_post.h"
#include "test_util.h"

/* ---- helpers ----------------------------------------------------------------------- */

/* xorshift64*: the same sequence on every machine. */
static uint64_t s_rng = 0x9E3779B97F4A7C15ull;
static double s_uniform (double lo, double hi)
{
    s_rng ^= s_rng >> 12;
    s_rng ^= s_rng << 25;
    s_rng ^= s_rng >> 27;
    uint64_t x = s_rng * 0x2545F4914F6CDD1Dull;
    return lo + (hi - lo) * (double)(x >> 11) / 9007199254740992.0;
}

static uint8_t *s_frame (int w, int h)
{
    uint8_t *f = calloc ((size_t)w * (size_t)h * 4, 1);
    assert_non_null (f);
    return f;
}

static uint8_t *s_px (uint8_t *f, int w, int x, int y)
{
    return f + 4 * ((size_t)y * (size_t)w + (size_t)x);
}

/* A grey frame: v(x, y) in R, G and B, opaque. */
typedef int s_grey_fn (int x, int y);
static void s_fill (uint8_t *f, int w, int h, s_grey_fn *v)
{
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            uint8_t *p = s_px (f, w, x, y);
            p[0] = p[1] = p[2] = (uint8_t)v (x, y);
            p[3] = 255;
        }
}

/* Infrared parameters with no blur and no noise, white-hot. */
static im_params_t s_ir (void)
{
    im_params_t p;
    im_params_defaults (&p);
    p.mode = IM_MODE_INFRARED;
    p.polarity = IM_WHITE_HOT;
    p.blur_px = 0;
    p.noise_k = 0;
    return p;
}

/* Mean and standard deviation of the R channel over [x0, x1) × [y0, y1). */
static void s_stats (const uint8_t *f, int w, int x0, int y0, int x1, int y1, double *mean,
                     double *sd)
{
    double s = 0, s2 = 0, n = 0;
    for (int y = y0; y < y1; y++)
        for (int x = x0; x < x1; x++) {
            double v = f[4 * ((size_t)y * (size_t)w + (size_t)x)];
            s += v, s2 += v * v, n++;
        }
    *mean = s / n;
    *sd = sqrt (fmax (0.0, s2 / n - *mean * *mean));
}

/* ---- the font ---------------------------------------------------------------------- */

/* The pixels a string draws, as a mask (1 where drawn). */
static uint8_t *s_draw (int w, int h, int x, int y, int scale, const char *text, int *ret_width)
{
    static const uint8_t rgb[3] = {200, 100, 50};
    uint8_t *f = s_frame (w, h);
    int width = im_post_text (f, w, h, x, y, scale, text, rgb);
    if (ret_width)
        *ret_width = width;
    uint8_t *mask = calloc ((size_t)w * (size_t)h, 1);
    assert_non_null (mask);
    for (size_t i = 0; i < (size_t)w * (size_t)h; i++) {
        const uint8_t *p = f + 4 * i;
        if (p[0] | p[1] | p[2] | p[3]) {
            // Drawn pixels take the colour, opaque.
            assert_int_equal (p[0], 200);
            assert_int_equal (p[1], 100);
            assert_int_equal (p[2], 50);
            assert_int_equal (p[3], 255);
            mask[i] = 1;
        }
    }
    free (f);
    return mask;
}

static size_t s_count (const uint8_t *mask, int w, int h)
{
    size_t n = 0;
    for (size_t i = 0; i < (size_t)w * (size_t)h; i++)
        n += mask[i];
    return n;
}

/* Every character of the font, at scales 1 to 3: drawn only inside its
 * 6·scale × 7·scale cell, never in the cell's sixth column (the gap), each
 * dot a whole scale × scale block, the pattern at scale s that at scale 1
 * enlarged; the width returned is 6·scale a character. */
static void test_text_box (void **state)
{
    (void)state;
    const char *font = "0123456789ABCDEFGHIJKLMNOPQRSTUVWXYZ.:-+/%()=,";
    const int w = 640, h = 64;
    for (const char *c = font; *c; c++) {
        char one[2] = {*c, 0};
        uint8_t *base = s_draw (w, h, 0, 0, 1, one, NULL);
        assert_true (s_count (base, w, h) > 0);
        for (int scale = 1; scale <= 3; scale++) {
            const int x0 = 17, y0 = 5;
            int width;
            uint8_t *m = s_draw (w, h, x0, y0, scale, one, &width);
            assert_int_equal (width, 6 * scale);
            for (int y = 0; y < h; y++)
                for (int x = 0; x < w; x++) {
                    bool in = x >= x0 && x < x0 + 5 * scale && y >= y0 && y < y0 + 7 * scale;
                    if (!in) {
                        if (m[(size_t)y * w + x])
                            fail_msg ("'%c' at scale %d draws (%d, %d), outside its 5 × 7 dots", *c,
                                      scale, x, y);
                        continue;
                    }
                    int dx = (x - x0) / scale, dy = (y - y0) / scale;
                    assert_int_equal (m[(size_t)y * w + x], base[(size_t)dy * w + dx]);
                }
            free (m);
        }
        free (base);
    }
    // A string: inside its box of 6·scale·len × 7·scale, each character in
    // its own cell as it draws alone.
    const char *text = "T+12:34 ALT 1500M";
    const int len = (int)strlen (text), scale = 2, x0 = 3, y0 = 9;
    int width;
    uint8_t *m = s_draw (w, h, x0, y0, scale, text, &width);
    assert_int_equal (width, 6 * scale * len);
    for (int i = 0; i < len; i++) {
        char one[2] = {text[i], 0};
        uint8_t *g = s_draw (w, h, x0 + 6 * scale * i, y0, scale, one, NULL);
        for (int y = y0; y < y0 + 7 * scale; y++)
            for (int x = x0 + 6 * scale * i; x < x0 + 6 * scale * (i + 1); x++)
                assert_int_equal (m[(size_t)y * w + x], g[(size_t)y * w + x]);
        free (g);
    }
    size_t inside = 0;
    for (int y = y0; y < y0 + 7 * scale; y++)
        for (int x = x0; x < x0 + 6 * scale * len; x++)
            inside += m[(size_t)y * w + x];
    assert_true (inside > 0);
    assert_int_equal (inside, s_count (m, w, h));
    free (m);
}

/* A space draws nothing and takes its width; an empty string draws nothing. */
static void test_text_space (void **state)
{
    (void)state;
    const int w = 100, h = 40;
    int width;
    uint8_t *m = s_draw (w, h, 10, 10, 2, " ", &width);
    assert_int_equal (width, 12);
    assert_int_equal (s_count (m, w, h), 0);
    free (m);
    m = s_draw (w, h, 10, 10, 3, "   ", &width);
    assert_int_equal (width, 54);
    assert_int_equal (s_count (m, w, h), 0);
    free (m);
    m = s_draw (w, h, 10, 10, 1, "", &width);
    assert_int_equal (width, 0);
    assert_int_equal (s_count (m, w, h), 0);
    free (m);
}

/* Lower case draws exactly as upper case. */
static void test_text_case (void **state)
{
    (void)state;
    const int w = 400, h = 20;
    uint8_t *a = s_draw (w, h, 1, 2, 1, "slant range 1.5km, mgrs 33uxp (x=y)", NULL);
    uint8_t *b = s_draw (w, h, 1, 2, 1, "SLANT RANGE 1.5KM, MGRS 33UXP (X=Y)", NULL);
    assert_memory_equal (a, b, (size_t)w * h);
    assert_true (s_count (a, w, h) > 100);
    free (a);
    free (b);
    for (char c = 'a'; c <= 'z'; c++) {
        char lo[2] = {c, 0}, up[2] = {(char)(c - 'a' + 'A'), 0};
        a = s_draw (w, h, 0, 0, 2, lo, NULL);
        b = s_draw (w, h, 0, 0, 2, up, NULL);
        assert_memory_equal (a, b, (size_t)w * h);
        free (a);
        free (b);
    }
}

/* A character the font lacks draws a box: the 5 × 7 cell's outline and
 * nothing inside. */
static void test_text_unknown (void **state)
{
    (void)state;
    const int w = 60, h = 30;
    const char *unknown[] = {"#", "@", "~", "!", "?", "\x7f", "\xc3", "_"};
    for (size_t i = 0; i < sizeof unknown / sizeof unknown[0]; i++)
        for (int scale = 1; scale <= 2; scale++) {
            uint8_t *m = s_draw (w, h, 4, 3, scale, unknown[i], NULL);
            for (int row = 0; row < 7; row++)
                for (int col = 0; col < 5; col++) {
                    int edge = row == 0 || row == 6 || col == 0 || col == 4;
                    for (int dy = 0; dy < scale; dy++)
                        for (int dx = 0; dx < scale; dx++) {
                            int x = 4 + col * scale + dx, y = 3 + row * scale + dy;
                            if (m[(size_t)y * w + x] != edge)
                                fail_msg ("'%s' (0x%02x) at scale %d: dot (%d, %d) is %d, a box "
                                          "has %d",
                                          unknown[i], (unsigned char)unknown[i][0], scale, col, row,
                                          m[(size_t)y * w + x], edge);
                        }
                }
            assert_int_equal (s_count (m, w, h), (size_t)(2 * 5 + 2 * 5) * scale * scale);
            free (m);
        }
    // A two-byte UTF-8 character: two boxes.
    int width;
    uint8_t *m = s_draw (w, h, 0, 0, 1, "\xc3\xa4", &width);
    assert_int_equal (width, 12);
    assert_int_equal (s_count (m, w, h), 40);
    free (m);
}

/* Text running off any side of the frame draws what falls inside and
 * nothing else (ASan watches the rest); the width is the whole string's. */
static void test_text_clipped (void **state)
{
    (void)state;
    const int w = 50, h = 20;
    const int xs[] = {-20, -3, 40, 49, 50, 1000, -1000};
    const int ys[] = {-10, -3, 15, 19, 20, 5};
    for (size_t i = 0; i < sizeof xs / sizeof xs[0]; i++)
        for (size_t j = 0; j < sizeof ys / sizeof ys[0]; j++) {
            int width;
            uint8_t *m = s_draw (w, h, xs[i], ys[j], 2, "W8#", &width);
            assert_int_equal (width, 36);
            // What is drawn is what the unclipped text draws there.
            const int W = 2200, H = 100, ox = 1100, oy = 40;
            uint8_t *big = s_draw (W, H, ox + xs[i], oy + ys[j], 2, "W8#", NULL);
            for (int y = 0; y < h; y++)
                for (int x = 0; x < w; x++)
                    assert_int_equal (m[(size_t)y * w + x], big[(size_t)(y + oy) * W + x + ox]);
            free (big);
            free (m);
        }
}

/* ---- the overlay ----------------------------------------------------------------------- */

static int s_pattern (int x, int y)
{
    return (x * 7 + y * 13) % 256;
}

/* A frame of a pattern that differs from pixel to pixel, opaque, and its copy in orig. */
static void s_fill_pattern (uint8_t *f, uint8_t *orig, int w, int h)
{
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            uint8_t *p = s_px (f, w, x, y);
            p[0] = (uint8_t)s_pattern (x, y), p[1] = (uint8_t)s_pattern (y, x);
            p[2] = (uint8_t)(255 - s_pattern (x, y)), p[3] = 255;
        }
    memcpy (orig, f, (size_t)w * h * 4);
}

/* n lines at 640 × 480: a band of n·9 + 4 rows where every pixel is a
 * third of what it was or white text (opaque); white text in every line's
 * place; below the band the frame untouched. Wider frames get larger text
 * and a deeper band, still darkened and still above an untouched rest. */
static void test_overlay (void **state)
{
    (void)state;
    const char *lines[] = {"T 00:12:34.5", "ALT 1523 M AGL", "SLANT 2304 M", "33UXP 12345 67890"};
    const int sizes[][2] = {{640, 480}, {1280, 720}};
    for (int s = 0; s < 2; s++) {
        const int w = sizes[s][0], h = sizes[s][1];
        uint8_t *f = s_frame (w, h), *orig = s_frame (w, h);
        s_fill_pattern (f, orig, w, h);
        im_post_overlay (f, w, h, lines, 4);
        int scale = w >= 960 ? 2 : 1;
        // The band: the rows down to the last one changed.
        int band = 0;
        for (int y = 0; y < h; y++)
            if (memcmp (s_px (f, w, 0, y), s_px (orig, w, 0, y), (size_t)w * 4) != 0)
                band = y + 1;
        if (w == 640)
            assert_int_equal (band, 4 * 9 + 4);
        else
            assert_true (band >= 4 * 9 + 4 && band < h / 4);
        size_t white = 0;
        for (int y = 0; y < band; y++)
            for (int x = 0; x < w; x++) {
                const uint8_t *p = s_px (f, w, x, y), *o = s_px (orig, w, x, y);
                bool is_white = p[0] == 255 && p[1] == 255 && p[2] == 255 && p[3] == 255;
                bool dark = p[0] == o[0] / 3 && p[1] == o[1] / 3 && p[2] == o[2] / 3 && p[3] == 255;
                if (!is_white && !dark)
                    fail_msg ("%d × %d: pixel (%d, %d) in the band is (%d, %d, %d, %d), "
                              "from (%d, %d, %d)",
                              w, h, x, y, p[0], p[1], p[2], p[3], o[0], o[1], o[2]);
                white += is_white;
            }
        // The band holds the text: at least one white pixel in each line's rows.
        for (int i = 0; i < 4; i++) {
            size_t n = 0;
            for (int y = 3 * scale + 9 * scale * i; y < 3 * scale + 9 * scale * i + 7 * scale; y++)
                for (int x = 0; x < w; x++) {
                    const uint8_t *p = s_px (f, w, x, y);
                    n += p[0] == 255 && p[1] == 255 && p[2] == 255;
                }
            assert_true (n > 10);
        }
        assert_true (white > 40);
        free (f);
        free (orig);
    }
}

/* A status block of three lines at (200, 150) with an 8-pixel leader, 640 ×
 * 480: inside its box every pixel is a third of what it was or yellow text
 * (and each line has text); the leader's pixels, from (200, 150) down-left
 * to (192, 158), are yellow; outside box and leader nothing changed. One
 * hanging off each edge of the frame is drawn as far as it fits. */
static void test_status_block (void **state)
{
    (void)state;
    const int w = 640, h = 480;
    const char *lines[] = {"APC1", "UNKNOWN", "32 KM/H"};
    uint8_t *f = s_frame (w, h), *orig = s_frame (w, h);
    s_fill_pattern (f, orig, w, h);
    im_post_status_block (f, w, h, 200, 150, 8, lines, 3);
    // The box: 7 characters of 6 dots plus 4, 3 lines of 9 plus 2.
    const int bw = 7 * 6 + 4, bh = 3 * 9 + 2, top = 150 - bh;
    size_t text[3] = {0};
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            const uint8_t *p = s_px (f, w, x, y), *o = s_px (orig, w, x, y);
            bool yellow = p[0] == 255 && p[1] == 230 && p[2] == 64;
            bool in_box = x >= 200 && x < 200 + bw && y >= top && y < 150;
            bool leader = y - 150 == 200 - x && x <= 200 && x >= 192;
            bool same = memcmp (p, o, 4) == 0;
            bool dark = p[0] == o[0] / 3 && p[1] == o[1] / 3 && p[2] == o[2] / 3;
            if (leader && !yellow)
                fail_msg ("leader pixel (%d, %d) is not yellow", x, y);
            if (in_box && !leader && !yellow && !dark)
                fail_msg ("box pixel (%d, %d) neither darkened nor text", x, y);
            if (!in_box && !leader && !same)
                fail_msg ("pixel (%d, %d) outside the block changed", x, y);
            if (in_box && yellow)
                for (int i = 0; i < 3; i++)
                    text[i] += y >= top + 2 + 9 * i && y < top + 2 + 9 * i + 7;
        }
    for (int i = 0; i < 3; i++)
        assert_true (text[i] > 10);
    // Off the edges: no write outside the frame (ASan watches), the part inside drawn.
    im_post_status_block (f, w, h, w - 20, 10, 8, lines, 3);
    im_post_status_block (f, w, h, -30, h + 5, 8, lines, 3);
    free (f);
    free (orig);
}

/* ---- the infrared sensor ----------------------------------------------------------------- */

/* The blur's kernel as documented: e^(−i²/2σ²) for |i| ≤ ⌈3σ⌉, normalised. */
static int s_kernel (double sigma, double *k)
{
    int r = (int)ceil (3 * sigma);
    double sum = 0;
    for (int i = -r; i <= r; i++)
        sum += k[i + r] = exp (-0.5 * i * i / (sigma * sigma));
    for (int i = 0; i <= 2 * r; i++)
        k[i] /= sum;
    return r;
}

static int s_const (int x, int y)
{
    (void)x, (void)y;
    return 137;
}

static int s_gradient (int x, int y)
{
    return x + y;
}

/* The blur keeps a constant image everywhere, and a linear gradient at
 * every pixel further than the kernel's radius from the edges. */
static void test_blur_keeps_constant_and_gradient (void **state)
{
    (void)state;
    const int w = 160, h = 90;
    im_post_t post;
    assert_int_equal (im_post_init (&post, w, h, 1), 0);
    uint8_t *f = s_frame (w, h);
    im_params_t p = s_ir ();
    const double sigmas[] = {0.5, 1.0, 1.5, 3.0};
    for (size_t i = 0; i < sizeof sigmas / sizeof sigmas[0]; i++) {
        p.blur_px = sigmas[i];
        s_fill (f, w, h, s_const);
        im_post_infrared (&post, f, &p);
        for (int y = 0; y < h; y++)
            for (int x = 0; x < w; x++)
                assert_int_equal (s_px (f, w, x, y)[0], 137);
        s_fill (f, w, h, s_gradient);
        im_post_infrared (&post, f, &p);
        int r = (int)ceil (3 * sigmas[i]);
        double mean, sd, mean0 = 0;
        for (int y = r; y < h - r; y++)
            for (int x = r; x < w - r; x++) {
                assert_int_equal (s_px (f, w, x, y)[0], x + y);
                mean0 += x + y;
            }
        s_stats (f, w, r, r, w - r, h - r, &mean, &sd);
        assert_near (mean, mean0 / ((w - 2 * r) * (h - 2 * r)), 1e-9);
    }
    free (f);
    im_post_fini (&post);
}

static int s_checker1 (int x, int y)
{
    return (x + y) % 2 ? 255 : 1;
}

static int s_checker4 (int x, int y)
{
    return (x / 4 + y / 4) % 2 ? 255 : 1;
}

/* A checkerboard c(x, y) = q(x)·q(y) (q = ±1) blurred by a separable kernel
 * k is (k∗q)(x)·(k∗q)(y): its variance is the input's times F², F = the
 * mean of (k∗q)² over q's period. For the one-pixel checkerboard k∗q =
 * (Σ k_i·(−1)^i)·q, so F = (Σ k_i·(−1)^i)². Checked on 128 ± 127 squares
 * of one pixel (σ = 0.5, 0.7) and of four (σ = 1, 1.5, 2.5) over the
 * interior (whole periods), the output's deviation within half a grey level
 * (its rounding) of the expected. */
static void test_blur_checkerboard_variance (void **state)
{
    (void)state;
    const int w = 200, h = 120;
    im_post_t post;
    assert_int_equal (im_post_init (&post, w, h, 1), 0);
    uint8_t *f = s_frame (w, h);
    im_params_t p = s_ir ();
    const struct {
        double sigma;
        int square;
    } cases[] = {{0.5, 1}, {0.7, 1}, {1.0, 4}, {1.5, 4}, {2.5, 4}};
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
        double k[64];
        int r = s_kernel (cases[c].sigma, k);
        int sq = cases[c].square, period = 2 * sq;
        // F: the mean over one period of (k∗q)².
        double F = 0;
        for (int x = 0; x < period; x++) {
            double g = 0;
            for (int i = -r; i <= r; i++) {
                int xx = ((x + i) % period + period) % period;
                g += k[i + r] * ((xx / sq) % 2 ? 1.0 : -1.0);
            }
            F += g * g / period;
        }
        s_fill (f, w, h, sq == 1 ? s_checker1 : s_checker4);
        double mean_in, sd_in;
        int m0 = ((r + period - 1) / period) * period; // interior, whole periods
        int x1 = m0 + ((w - 2 * m0) / period) * period, y1 = m0 + ((h - 2 * m0) / period) * period;
        s_stats (f, w, m0, m0, x1, y1, &mean_in, &sd_in);
        assert_near (sd_in, 127, 1e-9);
        p.blur_px = cases[c].sigma;
        im_post_infrared (&post, f, &p);
        double mean, sd;
        s_stats (f, w, m0, m0, x1, y1, &mean, &sd);
        double expected = sd_in * F; // variance × F²: deviation × F
        if (!(fabs (sd - expected) <= 0.5))
            fail_msg ("σ = %g, squares of %d: deviation %.4f, expected %.4f (factor %.6f on the "
                      "variance)",
                      cases[c].sigma, sq, sd, expected, F * F);
        assert_true (sd < sd_in);
        assert_near (mean, 128, 0.5);
    }
    free (f);
    im_post_fini (&post);
}

static int s_mid_grey (int x, int y)
{
    (void)x, (void)y;
    return 128;
}

/* With no blur, a mid-grey frame gets noise of noise_k/(max − min)·255 grey
 * levels' deviation (within 5%; the rounding to whole levels adds 1/12 to
 * the variance), its mean unchanged (within 0.2), and as many pixels within
 * one deviation as a Gaussian puts there (68.3%, corrected for the rounding)
 * when the deviation is several levels. */
static void test_noise_level (void **state)
{
    (void)state;
    const int w = 640, h = 480;
    im_post_t post;
    assert_int_equal (im_post_init (&post, w, h, 42), 0);
    uint8_t *f = s_frame (w, h);
    im_params_t p = s_ir ();
    const double noise[] = {0.3, 1.0, 2.5};
    const double range[][2] = {{275, 325}, {280, 300}, {250, 350}};
    for (size_t i = 0; i < 3; i++) {
        p.noise_k = noise[i];
        p.display_min_k = range[i][0];
        p.display_max_k = range[i][1];
        double want = p.noise_k / (p.display_max_k - p.display_min_k) * 255;
        s_fill (f, w, h, s_mid_grey);
        im_post_infrared (&post, f, &p);
        double mean, sd;
        s_stats (f, w, 0, 0, w, h, &mean, &sd);
        if (!(fabs (sd - want) <= 0.05 * want))
            fail_msg ("noise %g K over %g K: deviation %.4f grey levels, expected %.4f", p.noise_k,
                      p.display_max_k - p.display_min_k, sd, want);
        assert_near (mean, 128, 0.2);
        if (want > 5) {
            // Whole levels within want of 128: the noise within floor(want) + 0.5.
            size_t within = 0;
            for (size_t j = 0; j < (size_t)w * h; j++)
                within += fabs (f[4 * j] - 128.0) <= want;
            double frac = erf ((floor (want) + 0.5) / (want * sqrt (2)));
            assert_near ((double)within / ((double)w * h), frac, 0.005);
        }
    }
    free (f);
    im_post_fini (&post);
}

/* The same seed makes the same noise; another seed other noise; the next
 * frame of the same sensor new noise. */
static void test_noise_seed (void **state)
{
    (void)state;
    const int w = 320, h = 240;
    const size_t bytes = (size_t)w * h * 4;
    im_post_t a, b, c;
    assert_int_equal (im_post_init (&a, w, h, 7), 0);
    assert_int_equal (im_post_init (&b, w, h, 7), 0);
    assert_int_equal (im_post_init (&c, w, h, 8), 0);
    uint8_t *fa = s_frame (w, h), *fb = s_frame (w, h), *fc = s_frame (w, h), *fa2 = s_frame (w, h);
    im_params_t p = s_ir ();
    p.noise_k = 1;
    p.blur_px = 0.8;
    s_fill (fa, w, h, s_mid_grey);
    memcpy (fb, fa, bytes);
    memcpy (fc, fa, bytes);
    memcpy (fa2, fa, bytes);
    im_post_infrared (&a, fa, &p);
    im_post_infrared (&b, fb, &p);
    im_post_infrared (&c, fc, &p);
    im_post_infrared (&a, fa2, &p);
    assert_memory_equal (fa, fb, bytes);
    size_t diff_seed = 0, diff_next = 0;
    for (size_t i = 0; i < bytes; i += 4) {
        diff_seed += fa[i] != fc[i];
        diff_next += fa[i] != fa2[i];
    }
    // 1 K over 50 K is 5.1 levels of deviation: nearly every pixel differs.
    assert_true (diff_seed > (size_t)w * h / 2);
    assert_true (diff_next > (size_t)w * h / 2);
    free (fa), free (fb), free (fc), free (fa2);
    im_post_fini (&a), im_post_fini (&b), im_post_fini (&c);
}

static int s_random_grey (int x, int y)
{
    (void)x, (void)y;
    return (int)s_uniform (0, 256) & 255;
}

/* White-hot keeps the grey levels, black-hot is 255 − v; with blur and
 * noise from the same seed black-hot is still exactly 255 − white-hot. The
 * output is grey and opaque whatever G, B and alpha were. */
static void test_polarity_and_grey (void **state)
{
    (void)state;
    const int w = 128, h = 96;
    const size_t bytes = (size_t)w * h * 4;
    im_post_t post;
    assert_int_equal (im_post_init (&post, w, h, 3), 0);
    uint8_t *in = s_frame (w, h), *f = s_frame (w, h), *g = s_frame (w, h);
    s_fill (in, w, h, s_random_grey);
    im_params_t p = s_ir ();
    memcpy (f, in, bytes);
    im_post_infrared (&post, f, &p);
    assert_memory_equal (f, in, bytes);
    p.polarity = IM_BLACK_HOT;
    memcpy (f, in, bytes);
    im_post_infrared (&post, f, &p);
    for (size_t i = 0; i < bytes; i += 4) {
        assert_int_equal (f[i], 255 - in[i]);
        assert_int_equal (f[i + 1], f[i]);
        assert_int_equal (f[i + 2], f[i]);
        assert_int_equal (f[i + 3], 255);
    }
    // Blur and noise: the same seed, both polarities.
    im_post_t a, b;
    assert_int_equal (im_post_init (&a, w, h, 99), 0);
    assert_int_equal (im_post_init (&b, w, h, 99), 0);
    p.blur_px = 1.2;
    p.noise_k = 3;
    p.polarity = IM_WHITE_HOT;
    memcpy (f, in, bytes);
    im_post_infrared (&a, f, &p);
    p.polarity = IM_BLACK_HOT;
    memcpy (g, in, bytes);
    im_post_infrared (&b, g, &p);
    for (size_t i = 0; i < bytes; i += 4)
        assert_int_equal (g[i], 255 - f[i]);
    // Whatever G, B and alpha were, the output is grey and opaque.
    for (size_t i = 0; i < bytes; i += 4) {
        f[i + 1] = (uint8_t)(f[i] ^ 0x55);
        f[i + 2] = (uint8_t)(f[i] + 77);
        f[i + 3] = (uint8_t)(i & 0xff);
    }
    p.polarity = IM_WHITE_HOT;
    im_post_infrared (&a, f, &p);
    for (size_t i = 0; i < bytes; i += 4) {
        assert_int_equal (f[i + 1], f[i]);
        assert_int_equal (f[i + 2], f[i]);
        assert_int_equal (f[i + 3], 255);
    }
    free (in), free (f), free (g);
    im_post_fini (&post), im_post_fini (&a), im_post_fini (&b);
}

/* A size below 1 is refused; fini twice is harmless. */
static void test_init (void **state)
{
    (void)state;
    im_post_t post;
    assert_int_equal (im_post_init (&post, 0, 10, 1), -EINVAL);
    assert_int_equal (im_post_init (&post, 10, -1, 1), -EINVAL);
    im_post_fini (&post);
    assert_int_equal (im_post_init (&post, 1, 1, 1), 0);
    uint8_t px[4] = {100, 0, 0, 0};
    im_params_t p = s_ir ();
    p.blur_px = 2;
    im_post_infrared (&post, px, &p);
    assert_int_equal (px[0], 100);
    assert_int_equal (px[1], 100);
    assert_int_equal (px[3], 255);
    im_post_fini (&post);
    im_post_fini (&post);
}

int main (void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test (test_text_box),
        cmocka_unit_test (test_text_space),
        cmocka_unit_test (test_text_case),
        cmocka_unit_test (test_text_unknown),
        cmocka_unit_test (test_text_clipped),
        cmocka_unit_test (test_overlay),
        cmocka_unit_test (test_status_block),
        cmocka_unit_test (test_blur_keeps_constant_and_gradient),
        cmocka_unit_test (test_blur_checkerboard_variance),
        cmocka_unit_test (test_noise_level),
        cmocka_unit_test (test_noise_seed),
        cmocka_unit_test (test_polarity_and_grey),
        cmocka_unit_test (test_init),
    };
    return cmocka_run_group_tests (tests, NULL, NULL);
}
