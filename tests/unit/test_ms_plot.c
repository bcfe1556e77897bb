/* test_ms_plot — the report's charts (ms_plot): tick steps of 1, 2 or 5
 * times a power of ten; a chart with every kind of mark is well-formed XML
 * (libxml2 reads it), its title and labels are <text> elements, its data
 * land where the axes say (hand-worked pixels), an equal-aspect chart's
 * ranges grow to keep one unit the same length both ways, text is escaped;
 * librsvg renders it into a PNG of its size, and refuses what is not SVG. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "ms_plot.h"

#include <libxml/parser.h>
#include <libxml/xpath.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static void test_steps (void **state)
{
    (void)state;
    assert_true (ms_plot_step (0, 10, 8) == 1);
    assert_true (fabs (ms_plot_step (0, 1, 6) - 0.2) < 1e-12);
    assert_true (ms_plot_step (0, 1000, 8) == 100);
    assert_true (ms_plot_step (0, 37, 6) == 5);
    assert_true (ms_plot_step (-30, 30, 8) == 10);
    assert_true (ms_plot_step (5, 5, 8) == 1); // no span: a step all the same
}

/* The string value of an XPath expression over doc. */
static char *s_xpath (xmlDocPtr doc, const char *expr)
{
    xmlXPathContextPtr ctx = xmlXPathNewContext (doc);
    xmlXPathObjectPtr o = xmlXPathEvalExpression ((const xmlChar *)expr, ctx);
    xmlChar *s = o ? xmlXPathCastToString (o) : NULL;
    char *out = strdup (s ? (const char *)s : "");
    xmlFree (s);
    xmlXPathFreeObject (o);
    xmlXPathFreeContext (ctx);
    return out;
}

static void s_is (xmlDocPtr doc, const char *expr, const char *want)
{
    char *got = s_xpath (doc, expr);
    if (strcmp (got, want) != 0)
        fail_msg ("%s: got \"%s\", want \"%s\"", expr, got, want);
    free (got);
}

static void test_chart (void **state)
{
    (void)state;
    ms_str_t s = {0};
    ms_plot_t p = {.id = "fig-t",
                   .title = "Speed & range <test>",
                   .xlabel = "time (s)",
                   .ylabel = "speed (m/s)",
                   .x0 = 0,
                   .x1 = 100,
                   .y0 = 0,
                   .y1 = 50,
                   .width = 600,
                   .height = 300};
    ms_plot_begin (&s, &p);
    // The frame: 72 px left, 18 right, 34 top, 48 bottom.
    assert_true (p.px0 == 72 && p.px1 == 582 && p.py1 == 34 && p.py0 == 252);
    assert_true (ms_plot_px (&p, 50) == 327); // 72 + 0.5 · 510
    assert_true (ms_plot_py (&p, 25) == 143); // 252 − 0.5 · 218
    double x[] = {0, 50, NAN, 100}, y[] = {0, 25, 1, 50};
    ms_plot_line (&s, &p, x, y, 4, "#ff0000", 1.5, "4 2");
    ms_plot_points (&s, &p, x, y, 4, "#00ff00", 2, 0.5);
    ms_plot_bar (&s, &p, 10, 20, 40, "#0000ff");
    ms_plot_band (&s, &p, 60, 70, 0, 10, "#cccccc", "a \"band\"");
    ms_plot_vmark (&s, &p, 80, "#000000", "mark");
    ms_plot_text (&s, &p, 5, 45, "start", "a < b");
    const char *names[] = {"one", "two"}, *colors[] = {"#ff0000", "#00ff00"};
    ms_plot_legend (&s, &p, names, colors, 2);
    ms_plot_end (&s, &p);
    assert_false (s.oom);
    xmlDocPtr doc = xmlReadMemory (s.s, (int)s.len, "chart.svg", NULL, XML_PARSE_NONET);
    assert_non_null (doc); // well-formed
    s_is (doc, "string(/*[local-name()='svg']/@id)", "fig-t");
    s_is (doc, "string(//*[@class='title'])", "Speed & range <test>");
    s_is (doc, "string(//*[@class='xlabel'])", "time (s)");
    s_is (doc, "string(//*[@class='ylabel'])", "speed (m/s)");
    // The line breaks at the NaN: two polylines, their points where the axes put them.
    s_is (doc, "count(//*[local-name()='polyline'])", "2");
    s_is (doc, "normalize-space((//*[local-name()='polyline'])[1]/@points)",
          "72.0,252.0 327.0,143.0");
    // The bar from x = 10 to 20 (51 px, less half a pixel between bars), up to y = 40.
    s_is (doc, "string(//*[local-name()='rect'][@fill='#0000ff']/@x)", "123.0");
    s_is (doc, "string(//*[local-name()='rect'][@fill='#0000ff']/@width)", "50.5");
    s_is (doc, "string(//*[local-name()='rect'][@fill='#0000ff']/@y)", "77.6");
    s_is (doc, "string(//*[local-name()='rect']/*[local-name()='title'])", "a \"band\"");
    s_is (doc, "count(//*[local-name()='g'][@class='legend']/*[local-name()='text'])", "2");
    // x ticks every 10 (0..100: 11 labels), y ticks every 10 (0..50: 6).
    s_is (doc, "count(//*[local-name()='g'][@class='ticks']/*[local-name()='text'])", "17");
    xmlFreeDoc (doc);

    // Rendered: a PNG of the chart's size.
    // Under $TMPDIR, as the other tests make their files.
    const char *tmp = getenv ("TMPDIR");
    char path[512], err[256];
    snprintf (path, sizeof path, "%s/test-ms-plot-XXXXXX.png", tmp && *tmp ? tmp : "/tmp");
    int fd = mkstemps (path, 4);
    assert_true (fd >= 0);
    close (fd);
    assert_int_equal (ms_plot_png (s.s, s.len, p.width, p.height, path, err, sizeof err), 0);
    FILE *f = fopen (path, "rb");
    uint8_t h[24];
    assert_int_equal (fread (h, 1, 24, f), 24);
    fclose (f);
    assert_memory_equal (h, "\x89PNG\r\n\x1a\n", 8);
    assert_int_equal ((h[16] << 24) | (h[17] << 16) | (h[18] << 8) | h[19], 600);
    assert_int_equal ((h[20] << 24) | (h[21] << 16) | (h[22] << 8) | h[23], 300);
    // Not SVG: refused, with librsvg's reason.
    assert_int_equal (ms_plot_png ("<svg", 4, 10, 10, path, err, sizeof err), -1);
    assert_non_null (strstr (err, "librsvg"));
    unlink (path);
    ms_str_free (&s);
}

static void test_equal_aspect (void **state)
{
    (void)state;
    ms_str_t s = {0};
    // 10 km by 2 km into a 510 × 218 px frame: the north range grows.
    ms_plot_t p = {.id = "m",
                   .title = "",
                   .xlabel = "east (km)",
                   .ylabel = "north (km)",
                   .x0 = 0,
                   .x1 = 10,
                   .y0 = 0,
                   .y1 = 2,
                   .width = 600,
                   .height = 300,
                   .equal = true};
    ms_plot_begin (&s, &p);
    double sx = (p.x1 - p.x0) / (p.px1 - p.px0), sy = (p.y1 - p.y0) / (p.py0 - p.py1);
    assert_true (fabs (sx - sy) < 1e-12);
    assert_true (p.x0 == 0 && p.x1 == 10);
    assert_true (fabs ((p.y0 + p.y1) / 2 - 1) < 1e-12); // about its middle
    assert_true (p.y1 - p.y0 > 2);
    ms_plot_end (&s, &p);
    ms_str_free (&s);
}

/* A range of no length, or of a few ulps, is drawn as one unit about it
 * (the ticks never loop on a step that does not move); text that is not
 * UTF-8 is replaced, text that is stays. */
static void test_degenerate (void **state)
{
    (void)state;
    ms_str_t s = {0};
    double t = 1795869511.8246522;
    ms_plot_t p = {.id = "d",
                   .title = "caf\xc3\xa9 \xff\xe2\x82",
                   .xlabel = "x (s)",
                   .ylabel = "y (m)",
                   .x0 = t,
                   .x1 = nextafter (t, INFINITY),
                   .y0 = 5,
                   .y1 = 5,
                   .width = 300,
                   .height = 200};
    ms_plot_begin (&s, &p);
    assert_true (fabs (p.x1 - p.x0 - 1) < 1e-6 && p.y0 == 4.5 && p.y1 == 5.5);
    ms_plot_end (&s, &p);
    assert_false (s.oom);
    assert_true (s.len < 10000);
    assert_non_null (strstr (s.s, "caf\xc3\xa9 ??"));
    xmlDocPtr doc = xmlReadMemory (s.s, (int)s.len, "d.svg", NULL, XML_PARSE_NONET);
    assert_non_null (doc);
    xmlFreeDoc (doc);
    ms_str_free (&s);
}

int main (void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test (test_steps),
        cmocka_unit_test (test_chart),
        cmocka_unit_test (test_equal_aspect),
        cmocka_unit_test (test_degenerate),
    };
    return cmocka_run_group_tests (tests, NULL, NULL);
}
