/* ms_plot — charts as SVG text, for the after-action report: a frame with
 * its title, axes with ticks at 1-2-5 steps, labels (units in them), and
 * lines, points, bars, bands and marks drawn in data coordinates; and an
 * SVG made into a PNG file (librsvg renders it onto a cairo surface).
 * The SVG is plain text: every label is a <text> element a reader (or
 * xmllint) can find. Pure but for ms_plot_png's file. */
#ifndef MS_PLOT_H
#define MS_PLOT_H

#include <stdbool.h>
#include <stddef.h>

/* A growing string. */
typedef struct {
    char *s;
    size_t len, cap;
    bool oom; // an append failed: the text is incomplete
} ms_str_t;

void ms_str_printf (ms_str_t *self, const char *fmt, ...) __attribute__ ((format (printf, 2, 3)));
/* Text with &, <, > and " escaped. */
void ms_str_escaped (ms_str_t *self, const char *text);
void ms_str_free (ms_str_t *self);

/* One chart. The caller sets the first members; ms_plot_begin the rest. */
typedef struct {
    const char *id;     // the svg element's id ("fig-map")
    const char *title;  // above the frame
    const char *xlabel; // under the x axis, with its unit: "simulation time (s)"
    const char *ylabel; // beside the y axis, with its unit
    double x0, x1;      // the x range (x0 == x1: give up: an empty chart)
    double y0, y1;
    int width, height; // pixels of the whole SVG
    bool equal;        // one unit the same length on both axes (a map); the ranges grow
    bool no_yticks;    // a timeline's lanes: the caller labels them
    // Set by ms_plot_begin: the frame in pixels.
    double px0, px1, py0, py1;
} ms_plot_t;

/* Start the chart: <svg>, the frame, the ticks, the title and labels. */
void ms_plot_begin (ms_str_t *s, ms_plot_t *p);
/* The pixel of a data point. */
double ms_plot_px (const ms_plot_t *p, double x);
double ms_plot_py (const ms_plot_t *p, double y);
/* A polyline through the finite points (a non-finite one breaks it). */
void ms_plot_line (ms_str_t *s, const ms_plot_t *p, const double *x, const double *y, size_t n,
                   const char *color, double width, const char *dash);
/* Dots of radius r. */
void ms_plot_points (ms_str_t *s, const ms_plot_t *p, const double *x, const double *y, size_t n,
                     const char *color, double r, double opacity);
/* A bar from (x_lo, 0) to (x_hi, y). */
void ms_plot_bar (ms_str_t *s, const ms_plot_t *p, double x_lo, double x_hi, double y,
                  const char *color);
/* A filled rectangle in data coordinates, with a title (a tooltip; may be NULL). */
void ms_plot_band (ms_str_t *s, const ms_plot_t *p, double x0, double x1, double y0, double y1,
                   const char *color, const char *title);
/* A vertical mark at x over the frame, its label (may be NULL) at its top. */
void ms_plot_vmark (ms_str_t *s, const ms_plot_t *p, double x, const char *color,
                    const char *label);
/* A text at a data point (anchor "start", "middle" or "end"). */
void ms_plot_text (ms_str_t *s, const ms_plot_t *p, double x, double y, const char *anchor,
                   const char *text);
/* The legend: n names with their colours, in the frame's top right. */
void ms_plot_legend (ms_str_t *s, const ms_plot_t *p, const char *const *names,
                     const char *const *colors, size_t n);
/* </svg>. */
void ms_plot_end (ms_str_t *s, const ms_plot_t *p);

/* The step of about n ticks over [lo, hi]: 1, 2 or 5 times a power of 10. */
double ms_plot_step (double lo, double hi, int n);

/* Render svg (len bytes, width × height pixels) into a PNG file: 0, or -1
 * with the reason in err. */
int ms_plot_png (const char *svg, size_t len, int width, int height, const char *path, char *err,
                 size_t errlen);

#endif
