/* ms_plot — charts as SVG text, and SVG to PNG through librsvg. */
#include "ms_plot.h"

#include <cairo.h>
#include <librsvg/rsvg.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define S_MARGIN_L 72.0 // pixels left of the frame (the y ticks and label)
#define S_MARGIN_R 18.0
#define S_MARGIN_T 34.0 // the title
#define S_MARGIN_B 48.0 // the x ticks and label
#define S_FONT     "DejaVu Sans, Verdana, sans-serif"

/* ---- strings ----------------------------------------------------------------------- */

static bool s_reserve (ms_str_t *self, size_t more)
{
    if (self->oom)
        return false;
    if (self->len + more + 1 <= self->cap)
        return true;
    size_t cap = self->cap ? self->cap : 4096;
    while (cap < self->len + more + 1)
        cap *= 2;
    char *s = realloc (self->s, cap);
    if (!s) {
        self->oom = true;
        return false;
    }
    self->s = s;
    self->cap = cap;
    return true;
}

void ms_str_printf (ms_str_t *self, const char *fmt, ...)
{
    va_list ap;
    va_start (ap, fmt);
    int n = vsnprintf (NULL, 0, fmt, ap);
    va_end (ap);
    if (n < 0 || !s_reserve (self, (size_t)n))
        return;
    va_start (ap, fmt);
    vsnprintf (self->s + self->len, (size_t)n + 1, fmt, ap);
    va_end (ap);
    self->len += (size_t)n;
}

/* The length of the valid UTF-8 sequence at p (1..4), or 0. */
static int s_utf8_len (const unsigned char *p)
{
    int n = p[0] < 0x80             ? 1
            : (p[0] & 0xe0) == 0xc0 ? 2
            : (p[0] & 0xf0) == 0xe0 ? 3
            : (p[0] & 0xf8) == 0xf0 ? 4
                                    : 0;
    if (n == 2 && p[0] < 0xc2)
        return 0; // overlong
    for (int i = 1; i < n; i++)
        if ((p[i] & 0xc0) != 0x80)
            return 0;
    return n;
}

void ms_str_escaped (ms_str_t *self, const char *text)
{
    for (const char *c = text ? text : ""; *c; c++) {
        int n = s_utf8_len ((const unsigned char *)c);
        if (n == 0) { // not UTF-8 (or a character cut short): not in an XML page
            ms_str_printf (self, "?");
            continue;
        }
        if (n > 1) {
            ms_str_printf (self, "%.*s", n, c);
            c += n - 1;
            continue;
        }
        switch (*c) {
        case '&':
            ms_str_printf (self, "&amp;");
            break;
        case '<':
            ms_str_printf (self, "&lt;");
            break;
        case '>':
            ms_str_printf (self, "&gt;");
            break;
        case '"':
            ms_str_printf (self, "&quot;");
            break;
        default:
            if ((unsigned char)*c >= 0x20 || *c == '\n')
                ms_str_printf (self, "%c", *c);
        }
    }
}

void ms_str_free (ms_str_t *self)
{
    free (self->s);
    memset (self, 0, sizeof *self);
}

/* ---- the frame ----------------------------------------------------------------------- */

double ms_plot_step (double lo, double hi, int n)
{
    double span = hi - lo;
    if (!(span > 0) || !isfinite (span) || n < 1)
        return 1;
    double raw = span / n, mag = pow (10, floor (log10 (raw))), f = raw / mag;
    return (f < 1.5 ? 1 : f < 3.5 ? 2 : f < 7.5 ? 5 : 10) * mag;
}

double ms_plot_px (const ms_plot_t *p, double x)
{
    return p->px0 + (x - p->x0) / (p->x1 - p->x0) * (p->px1 - p->px0);
}

double ms_plot_py (const ms_plot_t *p, double y)
{
    return p->py0 - (y - p->y0) / (p->y1 - p->y0) * (p->py0 - p->py1);
}

/* A tick's label: no trailing zeros, no "-0". */
static void s_tick_label (char *buf, size_t n, double v, double step)
{
    if (fabs (v) < step * 1e-9)
        v = 0;
    int decimals = step >= 1 ? 0 : (int)ceil (-log10 (step) - 1e-9);
    snprintf (buf, n, "%.*f", decimals, v);
}

/* A range too short to draw (or not finite) becomes one unit about its middle. */
static void s_fix_range (double *lo, double *hi)
{
    if (!isfinite (*lo) || !isfinite (*hi)) {
        *lo = 0, *hi = 1;
        return;
    }
    if (*hi - *lo > 1e-9 * fmax (1, fmax (fabs (*lo), fabs (*hi))))
        return;
    double mid = (*lo + *hi) / 2;
    *lo = mid - 0.5, *hi = mid + 0.5;
}

void ms_plot_begin (ms_str_t *s, ms_plot_t *p)
{
    s_fix_range (&p->x0, &p->x1);
    s_fix_range (&p->y0, &p->y1);
    p->px0 = S_MARGIN_L;
    p->px1 = p->width - S_MARGIN_R;
    p->py1 = S_MARGIN_T;
    p->py0 = p->height - S_MARGIN_B;
    if (p->equal) { // the range that is short for its side grows about its middle
        double sx = (p->x1 - p->x0) / (p->px1 - p->px0), sy = (p->y1 - p->y0) / (p->py0 - p->py1);
        if (sx > sy) {
            double mid = (p->y0 + p->y1) / 2, half = sx * (p->py0 - p->py1) / 2;
            p->y0 = mid - half, p->y1 = mid + half;
        } else {
            double mid = (p->x0 + p->x1) / 2, half = sy * (p->px1 - p->px0) / 2;
            p->x0 = mid - half, p->x1 = mid + half;
        }
    }
    ms_str_printf (s,
                   "<svg xmlns=\"http://www.w3.org/2000/svg\" id=\"%s\" width=\"%d\" "
                   "height=\"%d\" viewBox=\"0 0 %d %d\" font-family=\"%s\" font-size=\"12\" "
                   "role=\"img\" aria-labelledby=\"%s-title\">\n",
                   p->id, p->width, p->height, p->width, p->height, S_FONT, p->id);
    ms_str_printf (s, "<rect width=\"%d\" height=\"%d\" fill=\"#ffffff\"/>\n", p->width, p->height);
    ms_str_printf (s,
                   "<text id=\"%s-title\" class=\"title\" x=\"%.1f\" y=\"20\" "
                   "font-size=\"14\" font-weight=\"bold\">",
                   p->id, p->px0);
    ms_str_escaped (s, p->title);
    ms_str_printf (s, "</text>\n");
    // Grid and ticks.
    ms_str_printf (s, "<g class=\"axes\" stroke=\"#dddddd\" stroke-width=\"1\">\n");
    double xs = ms_plot_step (p->x0, p->x1, 8), ys = ms_plot_step (p->y0, p->y1, 6);
    for (double v = ceil (p->x0 / xs) * xs; v <= p->x1 + xs * 1e-9; v += xs)
        ms_str_printf (s, "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\"/>\n",
                       ms_plot_px (p, v), p->py0, ms_plot_px (p, v), p->py1);
    if (!p->no_yticks)
        for (double v = ceil (p->y0 / ys) * ys; v <= p->y1 + ys * 1e-9; v += ys)
            ms_str_printf (s, "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\"/>\n", p->px0,
                           ms_plot_py (p, v), p->px1, ms_plot_py (p, v));
    ms_str_printf (s, "</g>\n<g class=\"ticks\" fill=\"#333333\">\n");
    char label[64];
    for (double v = ceil (p->x0 / xs) * xs; v <= p->x1 + xs * 1e-9; v += xs) {
        s_tick_label (label, sizeof label, v, xs);
        ms_str_printf (s, "<text x=\"%.1f\" y=\"%.1f\" text-anchor=\"middle\">%s</text>\n",
                       ms_plot_px (p, v), p->py0 + 16, label);
    }
    if (!p->no_yticks)
        for (double v = ceil (p->y0 / ys) * ys; v <= p->y1 + ys * 1e-9; v += ys) {
            s_tick_label (label, sizeof label, v, ys);
            ms_str_printf (s, "<text x=\"%.1f\" y=\"%.1f\" text-anchor=\"end\">%s</text>\n",
                           p->px0 - 6, ms_plot_py (p, v) + 4, label);
        }
    ms_str_printf (s, "</g>\n");
    ms_str_printf (s,
                   "<rect x=\"%.1f\" y=\"%.1f\" width=\"%.1f\" height=\"%.1f\" fill=\"none\" "
                   "stroke=\"#333333\"/>\n",
                   p->px0, p->py1, p->px1 - p->px0, p->py0 - p->py1);
    ms_str_printf (s, "<text class=\"xlabel\" x=\"%.1f\" y=\"%.1f\" text-anchor=\"middle\">",
                   (p->px0 + p->px1) / 2, (double)p->height - 10);
    ms_str_escaped (s, p->xlabel);
    ms_str_printf (s, "</text>\n");
    double yc = (p->py0 + p->py1) / 2;
    ms_str_printf (s,
                   "<text class=\"ylabel\" x=\"16\" y=\"%.1f\" text-anchor=\"middle\" "
                   "transform=\"rotate(-90 16 %.1f)\">",
                   yc, yc);
    ms_str_escaped (s, p->ylabel);
    ms_str_printf (s, "</text>\n");
    // What is drawn stays in the frame.
    ms_str_printf (s,
                   "<clipPath id=\"%s-clip\"><rect x=\"%.1f\" y=\"%.1f\" width=\"%.1f\" "
                   "height=\"%.1f\"/></clipPath>\n<g clip-path=\"url(#%s-clip)\">\n",
                   p->id, p->px0, p->py1, p->px1 - p->px0, p->py0 - p->py1, p->id);
}

void ms_plot_line (ms_str_t *s, const ms_plot_t *p, const double *x, const double *y, size_t n,
                   const char *color, double width, const char *dash)
{
    bool open = false;
    for (size_t i = 0; i < n; i++) {
        if (!isfinite (x[i]) || !isfinite (y[i])) {
            if (open)
                ms_str_printf (s, "\"/>\n");
            open = false;
            continue;
        }
        if (!open) {
            ms_str_printf (s,
                           "<polyline fill=\"none\" stroke=\"%s\" stroke-width=\"%.1f\"%s%s%s "
                           "points=\"",
                           color, width, dash ? " stroke-dasharray=\"" : "", dash ? dash : "",
                           dash ? "\"" : "");
            open = true;
        }
        ms_str_printf (s, "%.1f,%.1f ", ms_plot_px (p, x[i]), ms_plot_py (p, y[i]));
    }
    if (open)
        ms_str_printf (s, "\"/>\n");
}

void ms_plot_points (ms_str_t *s, const ms_plot_t *p, const double *x, const double *y, size_t n,
                     const char *color, double r, double opacity)
{
    // One path of tiny squares: far smaller than a <circle> per point.
    ms_str_printf (s, "<path fill=\"%s\" fill-opacity=\"%.2f\" d=\"", color, opacity);
    for (size_t i = 0; i < n; i++)
        if (isfinite (x[i]) && isfinite (y[i]))
            ms_str_printf (s, "M%.1f %.1fh%.1fv%.1fh-%.1fz", ms_plot_px (p, x[i]) - r,
                           ms_plot_py (p, y[i]) - r, 2 * r, 2 * r, 2 * r);
    ms_str_printf (s, "\"/>\n");
}

void ms_plot_bar (ms_str_t *s, const ms_plot_t *p, double x_lo, double x_hi, double y,
                  const char *color)
{
    if (!isfinite (y) || y <= 0)
        return;
    double a = ms_plot_px (p, x_lo), b = ms_plot_px (p, x_hi), top = ms_plot_py (p, y);
    ms_str_printf (s, "<rect x=\"%.1f\" y=\"%.1f\" width=\"%.1f\" height=\"%.1f\" fill=\"%s\"/>\n",
                   a, top, b - a > 0.5 ? b - a - 0.5 : 0.5, p->py0 - top, color);
}

void ms_plot_band (ms_str_t *s, const ms_plot_t *p, double x0, double x1, double y0, double y1,
                   const char *color, const char *title)
{
    double a = ms_plot_px (p, x0), b = ms_plot_px (p, x1);
    double top = ms_plot_py (p, y1), bottom = ms_plot_py (p, y0);
    ms_str_printf (s, "<rect x=\"%.1f\" y=\"%.1f\" width=\"%.1f\" height=\"%.1f\" fill=\"%s\">", a,
                   top, b - a > 0.5 ? b - a : 0.5, bottom - top, color);
    if (title) {
        ms_str_printf (s, "<title>");
        ms_str_escaped (s, title);
        ms_str_printf (s, "</title>");
    }
    ms_str_printf (s, "</rect>\n");
}

void ms_plot_vmark (ms_str_t *s, const ms_plot_t *p, double x, const char *color, const char *label)
{
    double px = ms_plot_px (p, x);
    ms_str_printf (s,
                   "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"%s\" "
                   "stroke-width=\"1.5\"/>\n",
                   px, p->py0, px, p->py1, color);
    if (label) {
        ms_str_printf (s,
                       "<text x=\"%.1f\" y=\"%.1f\" font-size=\"10\" fill=\"%s\" "
                       "transform=\"rotate(-90 %.1f %.1f)\" text-anchor=\"end\">",
                       px - 2, p->py1 + 4, color, px - 2, p->py1 + 4);
        ms_str_escaped (s, label);
        ms_str_printf (s, "</text>\n");
    }
}

void ms_plot_text (ms_str_t *s, const ms_plot_t *p, double x, double y, const char *anchor,
                   const char *text)
{
    ms_str_printf (s, "<text x=\"%.1f\" y=\"%.1f\" text-anchor=\"%s\" font-size=\"11\">",
                   ms_plot_px (p, x), ms_plot_py (p, y), anchor);
    ms_str_escaped (s, text);
    ms_str_printf (s, "</text>\n");
}

void ms_plot_legend (ms_str_t *s, const ms_plot_t *p, const char *const *names,
                     const char *const *colors, size_t n)
{
    ms_str_printf (s, "</g>\n<g class=\"legend\">\n"); // out of the clip
    double w = 0;
    for (size_t i = 0; i < n; i++)
        w = fmax (w, 7.5 * (double)strlen (names[i]));
    double x = p->px1 - w - 30, y = p->py1 + 8;
    ms_str_printf (s,
                   "<rect x=\"%.1f\" y=\"%.1f\" width=\"%.1f\" height=\"%.1f\" fill=\"#ffffff\" "
                   "fill-opacity=\"0.85\" stroke=\"#999999\"/>\n",
                   x - 6, y - 4, w + 34, 16.0 * (double)n + 6);
    for (size_t i = 0; i < n; i++) {
        ms_str_printf (s, "<rect x=\"%.1f\" y=\"%.1f\" width=\"14\" height=\"8\" fill=\"%s\"/>", x,
                       y + 16.0 * (double)i + 2, colors[i]);
        ms_str_printf (s, "<text x=\"%.1f\" y=\"%.1f\" font-size=\"11\">", x + 20,
                       y + 16.0 * (double)i + 10);
        ms_str_escaped (s, names[i]);
        ms_str_printf (s, "</text>\n");
    }
    ms_str_printf (s, "</g>\n<g>\n"); // the new one balanced by ms_plot_end's </g>
}

void ms_plot_end (ms_str_t *s, const ms_plot_t *p)
{
    (void)p;
    ms_str_printf (s, "</g>\n</svg>\n");
}

/* ---- PNG ------------------------------------------------------------------------------- */

int ms_plot_png (const char *svg, size_t len, int width, int height, const char *path, char *err,
                 size_t errlen)
{
    GError *gerr = NULL;
    RsvgHandle *h = rsvg_handle_new_from_data ((const guint8 *)svg, len, &gerr);
    if (!h) {
        snprintf (err, errlen, "librsvg cannot read the chart: %s",
                  gerr ? gerr->message : "unknown error");
        g_clear_error (&gerr);
        return -1;
    }
    cairo_surface_t *surf = cairo_image_surface_create (CAIRO_FORMAT_ARGB32, width, height);
    cairo_t *cr = cairo_create (surf);
    RsvgRectangle vp = {0, 0, width, height};
    int rc = 0;
    if (!rsvg_handle_render_document (h, cr, &vp, &gerr)) {
        snprintf (err, errlen, "librsvg cannot draw the chart: %s",
                  gerr ? gerr->message : "unknown error");
        g_clear_error (&gerr);
        rc = -1;
    } else if (cairo_surface_write_to_png (surf, path) != CAIRO_STATUS_SUCCESS) {
        snprintf (err, errlen, "%s: cannot write the PNG", path);
        rc = -1;
    }
    cairo_destroy (cr);
    cairo_surface_destroy (surf);
    g_object_unref (h);
    return rc;
}
