/* test_im_sar — the SAR mode (im_sar, the fast path) against theory and
 * against the reference (im_sar_ref: phase history and backprojection):
 *   - the windows: 3 dB widths and peak sidelobe ratios computed here from
 *     each window's own spectrum (rect 0.886 and −13.26 dB, Hamming 1.30 and
 *     −42.7 dB, Taylor n̄ 4 −35 dB 1.18 and about −35 dB);
 *   - the impulse response in range and cross-range, for rect, Hamming and
 *     Taylor, in the reference and the fast path: 3 dB widths against
 *     k·c/(2B) and k·λ/(2Δθ) (k the window's width: 0.886 for rect), the
 *     peak sidelobe ratio against the window's, measured on cuts through
 *     the peak interpolated 16× by zero-padded FFT;
 *   - layover: a point h above flat ground appears h·sin ψ nearer in slant
 *     range, h·tan ψ nearer in ground range; shadow: a box h high leaves
 *     h·cot ψ of ground behind it dark, and its top's far edge lays over
 *     h·tan ψ toward the radar (the "h·cot(grazing)" is the shadow's
 *     length; h·cot of the incidence angle, h·tan ψ, is the layover);
 *   - a moving target's cross-range shift R·v_r/V, in the direction of the
 *     platform's motion when it approaches, from the reference's phase
 *     history and in the fast path;
 *   - fast against reference: peak positions within 0.05 pixel, widths
 *     within 2%, peak intensities within 3%, for points on the ground, an
 *     elevated one, broadside and squinted, ground and slant geometry;
 *   - speckle: flat clutter's single-look intensity has contrast (std/mean)
 *     1, L looks 1/√L; its mean is σ0 = γ·sin ψ (the calibration); speckle
 *     off is smooth; each chip draws new speckle, the same seed the same;
 *   - vehicles: bright at their place, a moving one where its Doppler puts it;
 *   - the chip's geometry: corners, up is far, the frame's letterbox, pixel
 *     to ground and back on terrain;
 *   - bad parameters and geometries refused with a reason;
 *   - a widened chip is the chip of the scaled parameters (to the bit), its
 *     point response w times wider. */
#include "im_sar.h"
#include "im_sar_ref.h"
#include "test_util.h"

#include <complex.h>
#include <errno.h>
#include <fftw3.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define S_C   299792458.0
#define S_DEG (M_PI / 180)
#define S_N   128 // test chips: 64 m in 128 pixels
#define S_F   16  // cut interpolation

/* ---- helpers ----------------------------------------------------------------------- */

/* The window's response at y (cycles across its support), midpoint rule. */
static double s_resp (im_sar_window_t w, double y)
{
    enum { N = 1000 };
    double s = 0;
    for (int i = 0; i < N; i++) {
        double x = (i + 0.5) / N - 0.5;
        s += im_sar_window (w, x) * cos (2 * M_PI * x * y);
    }
    return s / N;
}

/* The window's 3 dB width (units of 1/support) and peak sidelobe ratio (dB),
 * from its spectrum. */
static void s_window_theory (im_sar_window_t w, double *ret_width, double *ret_pslr)
{
    double r0 = s_resp (w, 0);
    double lo = 0, hi = 1.5;
    for (int i = 0; i < 50; i++) {
        double m = (lo + hi) / 2, r = s_resp (w, m) / r0;
        if (r * r > 0.5)
            lo = m;
        else
            hi = m;
    }
    *ret_width = lo + hi;
    double prev = 1, y = 0, side = 0;
    bool past_null = false;
    for (y = 0.005; y < 12; y += 0.005) {
        double r = s_resp (w, y) / r0, pw = r * r;
        if (!past_null && pw > prev)
            past_null = true;
        if (past_null && pw > side)
            side = pw;
        prev = pw;
    }
    *ret_pslr = 10 * log10 (side);
}

/* |.|² of n complex samples interpolated f times by zero-padded FFT. */
static double *s_interp (const double *re_im, int n, int f)
{
    int m = n * f;
    fftw_complex *a = fftw_malloc (sizeof *a * n), *b = fftw_malloc (sizeof *b * m);
    assert_non_null (a);
    assert_non_null (b);
    for (int i = 0; i < n; i++)
        a[i] = re_im[2 * i] + I * re_im[2 * i + 1];
    fftw_plan p = fftw_plan_dft_1d (n, a, a, FFTW_FORWARD, FFTW_ESTIMATE);
    fftw_execute (p);
    fftw_destroy_plan (p);
    memset (b, 0, sizeof *b * m);
    for (int k = 0; k < n; k++) {
        if (k == n / 2) { // the Nyquist bin, split
            b[n / 2] = a[k] / 2;
            b[m - n / 2] = a[k] / 2;
        } else {
            b[k < n / 2 ? k : k - n + m] = a[k];
        }
    }
    p = fftw_plan_dft_1d (m, b, b, FFTW_BACKWARD, FFTW_ESTIMATE);
    fftw_execute (p);
    fftw_destroy_plan (p);
    double *out = malloc (sizeof *out * m);
    assert_non_null (out);
    for (int i = 0; i < m; i++)
        out[i] = pow (cabs (b[i]) / n, 2);
    fftw_free (a);
    fftw_free (b);
    return out;
}

/* A cut's peak: position (samples, from the first), 3 dB width (samples),
 * PSLR (dB: the highest sidelobe beyond the first nulls), peak power. */
typedef struct {
    double pos, width, pslr, peak;
} s_cut_t;

static s_cut_t s_measure (const double *re_im, int n)
{
    double *pw = s_interp (re_im, n, S_F);
    int m = n * S_F, ip = 0;
    for (int i = 1; i < m; i++)
        if (pw[i] > pw[ip])
            ip = i;
    assert_true (ip > 0 && ip < m - 1);
    double pk = pw[ip], h = pk / 2;
    int l = ip, r = ip;
    while (l > 0 && pw[l] > h)
        l--;
    while (r < m - 1 && pw[r] > h)
        r++;
    double xl = l + (h - pw[l]) / (pw[l + 1] - pw[l]);
    double xr = r - 1 + (pw[r - 1] - h) / (pw[r - 1] - pw[r]);
    double y0 = pw[ip - 1], y1 = pw[ip], y2 = pw[ip + 1];
    s_cut_t c = {.pos = (ip + 0.5 * (y0 - y2) / (y0 - 2 * y1 + y2)) / S_F,
                 .width = (xr - xl) / S_F,
                 .peak = pk};
    int a = ip, b = ip;
    while (a > 0 && pw[a - 1] < pw[a])
        a--;
    while (b < m - 1 && pw[b + 1] < pw[b])
        b++;
    double side = 0;
    for (int i = 0; i < m; i++)
        if ((i < a || i > b) && pw[i] > side)
            side = pw[i];
    c.pslr = 10 * log10 (side / pk);
    free (pw);
    return c;
}

/* A point's response in a chip: its peak (chip pixels, found in 2-D), the
 * peak's intensity, and the 3 dB widths (metres along x and y) and PSLRs
 * of cuts along the rows and columns through the brightest pixel. */
typedef struct {
    double x, y, peak, wx, wy, px, py;
} s_pt_resp_t;

typedef double s_power_fn (const void *arg, double x, double y);

/* The maximum of f near (x, y): a pattern search down to 0.001 pixel. */
static void s_peak2d (s_power_fn *f, const void *arg, double x, double y, s_pt_resp_t *r)
{
    double best = f (arg, x, y);
    for (double step = 0.25; step > 0.001;) {
        double bx = x, by = y;
        for (int dy = -1; dy <= 1; dy++)
            for (int dx = -1; dx <= 1; dx++) {
                double v = (dx || dy) ? f (arg, x + dx * step, y + dy * step) : best;
                if (v > best)
                    best = v, bx = x + dx * step, by = y + dy * step;
            }
        if (bx == x && by == y)
            step /= 2;
        x = bx, y = by;
    }
    r->x = x, r->y = y, r->peak = best;
}

static void s_cuts (const double *row, const double *col, const im_sar_chip_t *c, s_pt_resp_t *r)
{
    s_cut_t cx = s_measure (row, c->size_px), cy = s_measure (col, c->size_px);
    r->wx = cx.width * c->pixel_m, r->wy = cy.width * c->pixel_m;
    r->px = cx.pslr, r->py = cy.pslr;
}

/* The fast path's complex chip as a band-limited function: its spectrum. */
typedef struct {
    int n;
    fftw_complex *f;
} s_spec_t;

static double s_spec_power (const void *arg, double x, double y)
{
    const s_spec_t *s = arg;
    const int n = s->n;
    double complex ex[S_N], acc = 0;
    for (int k = 0; k < n; k++) {
        int kk = k < n / 2 ? k : k - n;
        ex[k] = cexp (I * 2 * M_PI * kk * (x - 0.5) / n);
    }
    for (int ky = 0; ky < n; ky++) {
        int kk = ky < n / 2 ? ky : ky - n;
        double complex row = 0;
        for (int kx = 0; kx < n; kx++)
            row += s->f[ky * n + kx] * ex[kx];
        acc += row * cexp (I * 2 * M_PI * kk * (y - 0.5) / n);
    }
    return pow (cabs (acc) / ((double)n * n), 2);
}

/* The fast path's response to the brightest point within 4 pixels of (gx, gy). */
static s_pt_resp_t s_fast (const im_sar_t *sar, const im_sar_chip_t *c, double gx, double gy)
{
    const int n = c->size_px;
    const double *in = im_sar_intensity (sar), *slc = im_sar_slc (sar);
    assert_non_null (slc);
    int bx = -1, by = -1;
    for (int y = (int)gy - 4; y <= (int)gy + 4; y++)
        for (int x = (int)gx - 4; x <= (int)gx + 4; x++)
            if (x >= 0 && y >= 0 && x < n && y < n && (bx < 0 || in[y * n + x] > in[by * n + bx]))
                bx = x, by = y;
    double row[2 * S_N], col[2 * S_N];
    for (int i = 0; i < n; i++) {
        row[2 * i] = slc[2 * (by * n + i)], row[2 * i + 1] = slc[2 * (by * n + i) + 1];
        col[2 * i] = slc[2 * (i * n + bx)], col[2 * i + 1] = slc[2 * (i * n + bx) + 1];
    }
    s_pt_resp_t r;
    s_cuts (row, col, c, &r);
    s_spec_t sp = {n, fftw_malloc (sizeof (fftw_complex) * n * n)};
    assert_non_null (sp.f);
    for (int i = 0; i < n * n; i++)
        sp.f[i] = slc[2 * i] + I * slc[2 * i + 1];
    fftw_plan p = fftw_plan_dft_2d (n, n, sp.f, sp.f, FFTW_FORWARD, FFTW_ESTIMATE);
    fftw_execute (p);
    fftw_destroy_plan (p);
    s_peak2d (s_spec_power, &sp, bx + 0.5, by + 0.5, &r);
    fftw_free (sp.f);
    return r;
}

typedef struct {
    const im_sar_ref_t *ref;
    const im_sar_chip_t *c;
} s_refarg_t;

static double s_ref_power (const void *arg, double x, double y)
{
    const s_refarg_t *a = arg;
    cgs_enu_t p;
    double v[2];
    im_sar_chip_px_to_plane (a->c, x, y, &p);
    im_sar_ref_backproject (a->ref, a->c, &p, 1, v);
    return v[0] * v[0] + v[1] * v[1];
}

/* The reference's response near (gx, gy), on the chip's pixel grid. */
static s_pt_resp_t s_ref (const im_sar_ref_t *r, const im_sar_chip_t *c, double gx, double gy)
{
    const int n = c->size_px;
    cgs_enu_t pts[S_N];
    double v[2 * S_N];
    int bx = -1, by = -1;
    double best = -1;
    for (int y = (int)gy - 3; y <= (int)gy + 3; y++) {
        int k = 0;
        for (int x = (int)gx - 3; x <= (int)gx + 3; x++)
            im_sar_chip_px_to_plane (c, x + 0.5, y + 0.5, &pts[k++]);
        im_sar_ref_backproject (r, c, pts, (size_t)k, v);
        for (int i = 0; i < k; i++)
            if (v[2 * i] * v[2 * i] + v[2 * i + 1] * v[2 * i + 1] > best)
                best = v[2 * i] * v[2 * i] + v[2 * i + 1] * v[2 * i + 1], bx = (int)gx - 3 + i,
                by = y;
    }
    double row[2 * S_N], col[2 * S_N];
    for (int i = 0; i < n; i++)
        im_sar_chip_px_to_plane (c, i + 0.5, by + 0.5, &pts[i]);
    im_sar_ref_backproject (r, c, pts, (size_t)n, row);
    for (int i = 0; i < n; i++)
        im_sar_chip_px_to_plane (c, bx + 0.5, i + 0.5, &pts[i]);
    im_sar_ref_backproject (r, c, pts, (size_t)n, col);
    s_pt_resp_t out;
    s_cuts (row, col, c, &out);
    s_refarg_t arg = {r, c};
    s_peak2d (s_ref_power, &arg, bx + 0.5, by + 0.5, &out);
    return out;
}

/* The test's parameters: 64 m in 128 pixels, no speckle. */
static im_sar_params_t s_params (im_sar_window_t w, im_sar_geometry_t geo)
{
    im_sar_params_t p;
    im_sar_params_defaults (&p);
    p.window = w;
    p.geometry = geo;
    p.scene_m = 64;
    p.size_px = S_N;
    p.speckle = false;
    return p;
}

#define S_R   5000.0 // slant range
#define S_V   100.0  // platform speed
#define S_PSI 30.0   // grazing angle

/* The radar south of the origin, at S_R and S_PSI, flying at S_V (east,
 * turned squint_deg toward north). */
static im_sar_geom_t s_geom (double squint_deg)
{
    double psi = S_PSI * S_DEG, sq = squint_deg * S_DEG;
    return (im_sar_geom_t){.radar = {0, -S_R * cos (psi), S_R * sin (psi)},
                           .radar_vel = {S_V * cos (sq), S_V * sin (sq), 0},
                           .center = {0, 0, 0}};
}

/* Ground point p's pixel in a ground chip, from the geometry alone. */
static void s_ground_px (const im_sar_chip_t *c, cgs_enu_t p, double *x, double *y)
{
    cgs_enu_t d = {p.e_m - c->center.e_m, p.n_m - c->center.n_m, p.u_m - c->center.u_m};
    double a = d.e_m * c->range_dir.e_m + d.n_m * c->range_dir.n_m;
    double b = d.e_m * c->cross_dir.e_m + d.n_m * c->cross_dir.n_m;
    *x = c->size_px / 2.0 + b / c->pixel_m;
    *y = c->size_px / 2.0 - a / c->pixel_m;
}

static im_sar_t *s_image (const im_sar_params_t *p, const im_sar_geom_t *g,
                          const im_sar_scene_t *sc, im_sar_chip_t *ret)
{
    char err[256] = "";
    im_sar_t *sar = im_sar_new (p, 1, err, sizeof err);
    if (!sar)
        fail_msg ("im_sar_new: %s", err);
    assert_int_equal (im_sar_image (sar, g, sc, ret), 0);
    return sar;
}

/* ---- the windows ------------------------------------------------------------------- */

static void test_windows (void **state)
{
    (void)state;
    double w, pslr;
    s_window_theory (IM_SAR_WINDOW_RECT, &w, &pslr);
    assert_near (w, 0.8859, 0.0005);
    assert_near (pslr, -13.26, 0.02);
    s_window_theory (IM_SAR_WINDOW_HAMMING, &w, &pslr);
    assert_near (w, 1.30, 0.01);
    assert_near (pslr, -42.7, 0.2);
    s_window_theory (IM_SAR_WINDOW_TAYLOR, &w, &pslr);
    assert_near (w, 1.18, 0.015);
    assert_near (pslr, -35.0, 0.5); // n̄ = 4 is a little short of −35 dB's ideal n̄
    // The library's own width agrees.
    for (int k = 0; k < 3; k++) {
        s_window_theory ((im_sar_window_t)k, &w, &pslr);
        assert_near (im_sar_window_width ((im_sar_window_t)k), w, 1e-3);
    }
    assert_true (im_sar_window (IM_SAR_WINDOW_TAYLOR, 0.6) == 0);
}

/* ---- the impulse response ---------------------------------------------------------- */

/* Widths and PSLR in slant geometry (broadside), both paths, one window. */
static void s_impulse (im_sar_window_t win)
{
    im_sar_params_t p = s_params (win, IM_SAR_SLANT);
    im_sar_geom_t g = s_geom (0);
    im_sar_point_t pt = {.position = {3.3, 7.7, 0}, .rcs_m2 = 100};
    im_sar_scene_t sc = {.points = &pt, .npoints = 1, .no_clutter = true};
    im_sar_chip_t c;
    im_sar_t *sar = s_image (&p, &g, &sc, &c);
    double k, pslr;
    s_window_theory (win, &k, &pslr);
    double lambda = S_C / p.fc_hz;
    double wr = k * S_C / (2 * p.bandwidth_hz), wx = k * lambda / (2 * p.integration_deg * S_DEG);
    double gx, gy;
    assert_true (im_sar_chip_to_px (&c, pt.position, (cgs_enu_t){0, 0, 0}, &gx, &gy));
    s_pt_resp_t f = s_fast (sar, &c, gx, gy);
    char err[256] = "";
    im_sar_ref_t *ref = im_sar_ref_new (&p, &g, &pt, 1, 40, err, sizeof err);
    if (!ref)
        fail_msg ("%s", err);
    s_pt_resp_t r = s_ref (ref, &c, gx, gy);
    // Range is down the chip (y), cross-range across (x).
    assert_rel (f.wy, wr, 0.01);
    assert_rel (f.wx, wx, 0.01);
    assert_rel (r.wy, wr, 0.01);
    assert_rel (r.wx, wx, 0.01);
    double tol = win == IM_SAR_WINDOW_RECT ? 0.3 : 0.5;
    assert_near (f.py, pslr, tol);
    assert_near (f.px, pslr, tol);
    assert_near (r.py, pslr, tol);
    assert_near (r.px, pslr, tol);
    if (win == IM_SAR_WINDOW_RECT) {
        assert_near (f.px, -13.26, 0.3);
        assert_near (r.py, -13.26, 0.3);
    }
    // The chip reports the same widths.
    assert_rel (c.range_res_m, wr, 0.002);
    assert_rel (c.cross_res_m, wx, 0.002);
    printf ("# %s: range %.4f m (fast) %.4f (ref) %.4f (theory), cross %.4f %.4f %.4f, "
            "PSLR range %.2f %.2f cross %.2f %.2f (window %.2f dB)\n",
            win == IM_SAR_WINDOW_RECT      ? "rect"
            : win == IM_SAR_WINDOW_HAMMING ? "hamming"
                                           : "taylor",
            f.wy, r.wy, wr, f.wx, r.wx, wx, f.py, r.py, f.px, r.px, pslr);
    im_sar_ref_destroy (&ref);
    im_sar_destroy (&sar);
}

static void test_impulse_rect (void **state)
{
    (void)state;
    s_impulse (IM_SAR_WINDOW_RECT);
}
static void test_impulse_taylor (void **state)
{
    (void)state;
    s_impulse (IM_SAR_WINDOW_TAYLOR);
}
static void test_impulse_hamming (void **state)
{
    (void)state;
    s_impulse (IM_SAR_WINDOW_HAMMING);
}

/* Ground geometry: range widths grow by 1/cos ψ. */
static void test_ground_widths (void **state)
{
    (void)state;
    im_sar_params_t p = s_params (IM_SAR_WINDOW_RECT, IM_SAR_GROUND);
    im_sar_geom_t g = s_geom (0);
    im_sar_point_t pt = {.position = {-4, 6, 0}, .rcs_m2 = 10};
    im_sar_scene_t sc = {.points = &pt, .npoints = 1, .no_clutter = true};
    im_sar_chip_t c;
    im_sar_t *sar = s_image (&p, &g, &sc, &c);
    double gx, gy;
    s_ground_px (&c, pt.position, &gx, &gy);
    s_pt_resp_t f = s_fast (sar, &c, gx, gy);
    assert_near (c.grazing_deg, S_PSI, 1e-9);
    assert_rel (f.wy, 0.8859 * S_C / (2 * p.bandwidth_hz) / cos (S_PSI * S_DEG), 0.01);
    assert_near (f.x, gx, 0.02);
    assert_near (f.y, gy, 0.02);
    // Calibration: with ∫|h|² dA = 1, a point of σ (rect window) peaks at
    // σ times the spectral support's area on the ground, σ/(ρ_r·ρ_x)·0.886²
    // (within 2%: the support's edge bins, counted by their share inside,
    // are about 1% of its bins).
    double area = 2 * p.bandwidth_hz / S_C * cos (S_PSI * S_DEG) * 2 * p.integration_deg * S_DEG *
                  p.fc_hz / S_C;
    assert_rel (f.peak, pt.rcs_m2 * area, 0.02);
    im_sar_destroy (&sar);
}

/* ---- layover and shadow ------------------------------------------------------------ */

static void test_layover (void **state)
{
    (void)state;
    const double h = 20;
    double psi = S_PSI * S_DEG;
    im_sar_geom_t g = s_geom (0);
    im_sar_point_t pts[2] = {{.position = {4, 3, 0}, .rcs_m2 = 10},
                             {.position = {-6, -2, h}, .rcs_m2 = 10}};
    im_sar_scene_t sc = {.points = pts, .npoints = 2, .no_clutter = true};
    char err[256];
    im_sar_ref_t *ref = NULL;
    for (int geo = 0; geo < 2; geo++) {
        im_sar_params_t p = s_params (IM_SAR_WINDOW_TAYLOR, (im_sar_geometry_t)geo);
        im_sar_chip_t c;
        im_sar_t *sar = s_image (&p, &g, &sc, &c);
        if (!ref && !(ref = im_sar_ref_new (&p, &g, pts, 2, 40, err, sizeof err)))
            fail_msg ("%s", err);
        // Where each would be on the ground; the elevated one's foot.
        cgs_enu_t foot = {-6, -2, 0};
        double x0, y0, x1, y1;
        assert_true (im_sar_chip_to_px (&c, pts[0].position, (cgs_enu_t){0, 0, 0}, &x0, &y0));
        assert_true (im_sar_chip_to_px (&c, foot, (cgs_enu_t){0, 0, 0}, &x1, &y1));
        if (geo == IM_SAR_GROUND) { // the mapping of ground points is the plane's
            double ex, ey;
            s_ground_px (&c, foot, &ex, &ey);
            assert_near (x1, ex, 1e-6);
            assert_near (y1, ey, 1e-6);
        }
        s_pt_resp_t f0 = s_fast (sar, &c, x0, y0), r0 = s_ref (ref, &c, x0, y0);
        // Nearer is down the chip: +y. Layover h·tan ψ on the ground, h·sin ψ in slant range.
        double shift = (geo == IM_SAR_GROUND ? h * tan (psi) : h * sin (psi)) / c.pixel_m;
        s_pt_resp_t f1 = s_fast (sar, &c, x1, y1 + shift), r1 = s_ref (ref, &c, x1, y1 + shift);
        // The first-order relations hold to their second-order term,
        // h²·(1 + tan²ψ)/(2ρ) (0.06 m here, ρ the ground range); the exact
        // one (spherical wavefronts) keeps the range: on the ground plane
        // ρ' = √(ρ² − 2Hh + h²), H the radar's height.
        double rho = -g.radar.n_m + pts[1].position.n_m, hh = g.radar.u_m;
        double exact = geo == IM_SAR_GROUND
                           ? (rho - sqrt (rho * rho - 2 * hh * h + h * h)) / c.pixel_m
                           : shift;
        assert_near (f0.y, y0, 0.03);
        assert_near (f1.y - y1, shift, 0.15);
        assert_near (r1.y - y1, shift, 0.15);
        if (geo == IM_SAR_GROUND) {
            assert_near (f1.y - y1, exact, 0.03);
            assert_near (r1.y - y1, exact, 0.03);
        }
        assert_near (f1.x, x1, 0.03);
        assert_near (f1.y, r1.y, 0.03);
        assert_near (f0.y, r0.y, 0.03);
        // The mapping predicts it too.
        double mx, my;
        assert_true (im_sar_chip_to_px (&c, pts[1].position, (cgs_enu_t){0, 0, 0}, &mx, &my));
        assert_near (my - y1, exact, geo == IM_SAR_GROUND ? 1e-6 : 0.15);
        printf ("# layover of %g m (%s): %.3f m measured (fast), %.3f (reference), %.3f theory\n",
                h, geo == IM_SAR_GROUND ? "ground range, h tan psi" : "slant range, h sin psi",
                (f1.y - y1) * c.pixel_m, (r1.y - y1) * c.pixel_m, shift * c.pixel_m);
        im_sar_destroy (&sar);
    }
    im_sar_ref_destroy (&ref);
}

/* A 10 m box on flat ground: behind it h·cot ψ of ground is dark; its top's
 * far edge lays over h·tan ψ toward the radar. */
static void test_shadow (void **state)
{
    (void)state;
    const double h = 10, res = 0.5, half = 100;
    const int nn = (int)(2 * half / res) + 1;
    float *z = calloc ((size_t)nn * nn, sizeof *z);
    assert_non_null (z);
    for (int r = 0; r < nn; r++)
        for (int c = 0; c < nn; c++) {
            double e = -half + c * res, n = -half + r * res;
            if (fabs (e) <= 8 && fabs (n) <= 5)
                z[(size_t)r * nn + c] = (float)h;
        }
    cgs_terrain_t *t = cgs_terrain_new_grid (nn, nn, -half, -half, res, z);
    free (z);
    assert_non_null (t);
    im_sar_params_t p = s_params (IM_SAR_WINDOW_TAYLOR, IM_SAR_GROUND);
    p.nesz_db = -60;
    im_sar_geom_t g = s_geom (0);
    im_sar_scene_t sc = {.terrain = t};
    im_sar_chip_t c;
    im_sar_t *sar = s_image (&p, &g, &sc, &c);
    const double *in = im_sar_intensity (sar);
    // Amplitude down the chip's middle columns (the box spans e in ±8).
    double amp[S_N] = {0}, ground = 0;
    double fx, fy;
    s_ground_px (&c, (cgs_enu_t){0, 0, 0}, &fx, &fy);
    int x0 = (int)fx;
    for (int y = 0; y < S_N; y++)
        for (int x = x0 - 6; x < x0 + 6; x++)
            amp[y] += sqrt (in[y * S_N + x]) / 12;
    for (int y = 0; y < 12; y++) // far ground, clear of the shadow
        ground += amp[y] / 12;
    // The box's far top edge is at n = 5: at the centre's grazing angle its
    // shadow ends at 5 + h cot ψ, its layover starts at 5 − h tan ψ (north
    // is up the chip).
    double dist = S_R * cos (S_PSI * S_DEG) + 5, hr = S_R * sin (S_PSI * S_DEG);
    double cot = dist / (hr - h), tn = hr / dist; // the ray over the edge; the edge's layover
    double end_n = 5 + h * cot, start_n = 5 - h * tn;
    // Find the dark run: amplitude under half the ground's, walking down from far.
    int y = 0;
    while (y < S_N && amp[y] > ground / 2)
        y++;
    assert_true (y > 0 && y < S_N);
    double y_end = y - 1 + (amp[y - 1] - ground / 2) / (amp[y - 1] - amp[y]) + 0.5;
    while (y < S_N && amp[y] <= ground / 2)
        y++;
    double y_start = y - 1 + (ground / 2 - amp[y - 1]) / (amp[y] - amp[y - 1]) + 0.5;
    // Chip row y is (size/2 − y)·pixel north of the centre (the origin).
    double n_end = (c.size_px / 2.0 - y_end) * c.pixel_m;
    double n_start = (c.size_px / 2.0 - y_start) * c.pixel_m;
    printf ("# shadow of a %g m box: ground from %.2f to %.2f m dark (theory %.2f to %.2f: "
            "layover h tan psi %.2f, shadow h cot psi %.2f)\n",
            h, n_start, n_end, start_n, end_n, h * tn, h * cot);
    assert_near (n_end, end_n, 0.5);
    assert_near (n_start, start_n, 0.5);
    // Inside the shadow it is dark: 20 dB under the ground at least.
    double dark = 0;
    int cnt = 0;
    for (int yy = 0; yy < S_N; yy++) {
        double n = (c.size_px / 2.0 - yy - 0.5) * c.pixel_m;
        if (n > start_n + 2 && n < end_n - 2)
            for (int x = x0 - 6; x < x0 + 6; x++)
                dark += in[yy * S_N + x], cnt++;
    }
    assert_true (cnt > 100);
    assert_true (dark / cnt < 0.01 * ground * ground);
    im_sar_destroy (&sar);
    cgs_terrain_destroy (&t);
}

/* ---- a moving target --------------------------------------------------------------- */

static void test_moving_target (void **state)
{
    (void)state;
    im_sar_params_t p = s_params (IM_SAR_WINDOW_TAYLOR, IM_SAR_GROUND);
    im_sar_geom_t g = s_geom (0);
    // Two targets side by side, one driving toward the radar (south), one away.
    const double sp = 0.4;
    im_sar_point_t pts[2] = {
        {.position = {0, 8, 0}, .velocity = {0, -sp, 0}, .rcs_m2 = 10},
        {.position = {0, -8, 0}, .velocity = {0, sp, 0}, .rcs_m2 = 10},
    };
    im_sar_scene_t sc = {.points = pts, .npoints = 2, .no_clutter = true};
    im_sar_chip_t c;
    im_sar_t *sar = s_image (&p, &g, &sc, &c);
    char err[256];
    im_sar_ref_t *ref = im_sar_ref_new (&p, &g, pts, 2, 40, err, sizeof err);
    if (!ref)
        fail_msg ("%s", err);
    for (int k = 0; k < 2; k++) {
        cgs_enu_t q = {pts[k].position.e_m - g.radar.e_m, pts[k].position.n_m - g.radar.n_m,
                       pts[k].position.u_m - g.radar.u_m};
        double r = sqrt (q.e_m * q.e_m + q.n_m * q.n_m + q.u_m * q.u_m);
        double vr = (k == 0 ? 1 : -1) * sp * (q.n_m / r); // speed toward the radar
        double shift = r * vr / S_V; // along the platform's motion: east, right
        double x0, y0;
        s_ground_px (&c, pts[k].position, &x0, &y0);
        s_pt_resp_t f = s_fast (sar, &c, x0 + shift / c.pixel_m, y0);
        s_pt_resp_t rr = s_ref (ref, &c, x0 + shift / c.pixel_m, y0);
        printf ("# moving target (v_r %+.3f m/s toward the radar): shift %.3f m (fast), %.3f "
                "(reference), R v_r / V = %.3f\n",
                vr, (f.x - x0) * c.pixel_m, (rr.x - x0) * c.pixel_m, shift);
        assert_near ((rr.x - x0) * c.pixel_m, shift, 0.1);
        assert_near ((f.x - x0) * c.pixel_m, shift, 0.05);
        assert_near (f.x, rr.x, 0.05);
        assert_near (f.y, rr.y, 0.05);
        double mx, my;
        assert_true (im_sar_chip_to_px (&c, pts[k].position, pts[k].velocity, &mx, &my));
        assert_near (mx, f.x, 0.05);
        // Its apparent place on the ground: shifted east by R v_r / V; a static
        // point's is itself.
        cgs_enu_t a;
        assert_true (im_sar_apparent (&c, pts[k].position, pts[k].velocity, NULL, &a));
        assert_near (a.e_m - pts[k].position.e_m, shift, 0.05);
        assert_near (a.n_m, pts[k].position.n_m, 0.05);
        assert_true (im_sar_apparent (&c, pts[k].position, (cgs_enu_t){0, 0, 0}, NULL, &a));
        assert_near (a.e_m, pts[k].position.e_m, 0.01);
        assert_near (a.n_m, pts[k].position.n_m, 0.01);
        // A fast mover's return lands far outside the chip: still placed.
        cgs_enu_t fast = {0, (k == 0 ? -1 : 1) * 8.0, 0};
        double big = r * (k == 0 ? 1 : -1) * 8.0 * (q.n_m / r) / S_V;
        assert_false (im_sar_chip_to_px (&c, pts[k].position, fast, &mx, &my));
        assert_true (im_sar_apparent (&c, pts[k].position, fast, NULL, &a));
        printf ("# an 8 m/s mover: apparent shift %.1f m, R v_r / V = %.1f m\n",
                a.e_m - pts[k].position.e_m, big);
        assert_rel (a.e_m - pts[k].position.e_m, big, 0.02);
    }
    assert_true (pts[0].velocity.n_m < 0); // the first approaches: shifted east (right)
    im_sar_ref_destroy (&ref);
    im_sar_destroy (&sar);
}

/* ---- fast against reference -------------------------------------------------------- */

static void s_compare (im_sar_geometry_t geo, double squint)
{
    im_sar_params_t p = s_params (IM_SAR_WINDOW_TAYLOR, geo);
    im_sar_geom_t g = s_geom (squint);
    im_sar_point_t pts[3] = {{.position = {-12, 10, 0}, .rcs_m2 = 5},
                             {.position = {9, -14, 0}, .rcs_m2 = 50},
                             {.position = {14, 12, 15}, .rcs_m2 = 20}};
    im_sar_scene_t sc = {.points = pts, .npoints = 3, .no_clutter = true};
    im_sar_chip_t c;
    im_sar_t *sar = s_image (&p, &g, &sc, &c);
    char err[256];
    im_sar_ref_t *ref = im_sar_ref_new (&p, &g, pts, 3, 40, err, sizeof err);
    if (!ref)
        fail_msg ("%s", err);
    for (int k = 0; k < 3; k++) {
        double x, y;
        assert_true (im_sar_chip_to_px (&c, pts[k].position, (cgs_enu_t){0, 0, 0}, &x, &y));
        s_pt_resp_t f = s_fast (sar, &c, x, y), r = s_ref (ref, &c, x, y);
        assert_near (f.x, r.x, 0.05);
        assert_near (f.y, r.y, 0.05);
        assert_rel (f.wx, r.wx, 0.02);
        assert_rel (f.wy, r.wy, 0.02);
        assert_rel (f.peak, r.peak, 0.03);
        assert_near (f.x, x, 0.05); // where the mapping puts it
        assert_near (f.y, y, 0.05);
    }
    im_sar_ref_destroy (&ref);
    im_sar_destroy (&sar);
}

static void test_fast_vs_ref (void **state)
{
    (void)state;
    s_compare (IM_SAR_GROUND, 0);
    s_compare (IM_SAR_SLANT, 0);
    s_compare (IM_SAR_GROUND, 35);
    s_compare (IM_SAR_SLANT, -30);
}

/* ---- speckle ----------------------------------------------------------------------- */

static void s_stats (const double *in, int n, double *ret_mean, double *ret_contrast)
{
    double m = 0, m2 = 0;
    int cnt = 0;
    for (int y = n / 8; y < n - n / 8; y++)
        for (int x = n / 8; x < n - n / 8; x++) {
            m += in[y * n + x], m2 += in[y * n + x] * in[y * n + x];
            cnt++;
        }
    m /= cnt, m2 /= cnt;
    *ret_mean = m;
    *ret_contrast = sqrt (m2 - m * m) / m;
}

static void test_speckle (void **state)
{
    (void)state;
    im_sar_geom_t g = s_geom (0);
    im_sar_scene_t sc = {0}; // flat open ground
    double sigma0 = pow (10, -12 / 10.0) * sin (S_PSI * S_DEG);
    const int looks[] = {1, 4};
    for (int k = 0; k < 2; k++) {
        im_sar_params_t p = s_params (IM_SAR_WINDOW_TAYLOR, IM_SAR_GROUND);
        p.speckle = true;
        p.looks = looks[k];
        p.nesz_db = -100;
        p.ground_gamma_db = -12;
        im_sar_chip_t c;
        im_sar_t *sar = s_image (&p, &g, &sc, &c);
        double m, con;
        s_stats (im_sar_intensity (sar), S_N, &m, &con);
        printf ("# speckle, %d look(s): contrast %.3f (1/sqrt L = %.3f), mean %.4g (sigma0 %.4g)\n",
                looks[k], con, 1 / sqrt (looks[k]), m, sigma0);
        assert_near (con, 1 / sqrt (looks[k]), 0.08 / sqrt (looks[k]));
        assert_rel (m, sigma0, 0.06);
        im_sar_destroy (&sar);
    }
    // Speckle off: smooth, the same mean.
    im_sar_params_t p = s_params (IM_SAR_WINDOW_TAYLOR, IM_SAR_GROUND);
    p.nesz_db = -100;
    im_sar_chip_t c;
    im_sar_t *sar = s_image (&p, &g, &sc, &c);
    double m, con;
    s_stats (im_sar_intensity (sar), S_N, &m, &con);
    assert_true (con < 0.05);
    assert_rel (m, sigma0, 0.03);
    im_sar_destroy (&sar);
    // Slant geometry: flat ground averages σ0 / cos ψ.
    p = s_params (IM_SAR_WINDOW_TAYLOR, IM_SAR_SLANT);
    p.nesz_db = -100, p.speckle = true, p.looks = 4;
    sar = s_image (&p, &g, &sc, &c);
    s_stats (im_sar_intensity (sar), S_N, &m, &con);
    assert_rel (m, sigma0 / cos (S_PSI * S_DEG), 0.06);
    im_sar_destroy (&sar);
    // A new draw each chip; the same seed, the same chips.
    p = s_params (IM_SAR_WINDOW_TAYLOR, IM_SAR_GROUND);
    p.speckle = true;
    char err[256];
    im_sar_t *a = im_sar_new (&p, 42, err, sizeof err), *b = im_sar_new (&p, 42, err, sizeof err);
    assert_non_null (a);
    assert_non_null (b);
    assert_int_equal (im_sar_image (a, &g, &sc, NULL), 0);
    assert_int_equal (im_sar_image (b, &g, &sc, NULL), 0);
    size_t px = (size_t)S_N * S_N;
    double *first = malloc (px * sizeof *first);
    assert_non_null (first);
    memcpy (first, im_sar_intensity (a), px * sizeof *first);
    assert_memory_equal (first, im_sar_intensity (b), px * sizeof *first);
    assert_int_equal (im_sar_image (a, &g, &sc, NULL), 0);
    const double *second = im_sar_intensity (a);
    double sa = 0, sb = 0, sab = 0, saa = 0, sbb = 0;
    for (size_t i = 0; i < px; i++) {
        sa += first[i], sb += second[i];
        sab += first[i] * second[i], saa += first[i] * first[i], sbb += second[i] * second[i];
    }
    double cov = sab / px - sa * sb / px / px;
    double corr = cov / sqrt ((saa / px - sa * sa / px / px) * (sbb / px - sb * sb / px / px));
    assert_true (fabs (corr) < 0.1);
    free (first);
    im_sar_destroy (&a);
    im_sar_destroy (&b);
}

/* ---- vehicles ---------------------------------------------------------------------- */

static void test_vehicles (void **state)
{
    (void)state;
    im_sar_params_t p = s_params (IM_SAR_WINDOW_TAYLOR, IM_SAR_GROUND);
    p.speckle = true;
    im_sar_geom_t g = s_geom (0);
    im_entity_t ents[3] = {
        {.id = 1, .kind = CGS_KIND_TRACKED, .position = {-10, 10, 0}, .heading_deg = 90},
        {.id = 2,
         .kind = CGS_KIND_WHEELED,
         .position = {10, -10, 0},
         .heading_deg = 180,
         .speed_mps = 0.5}, // toward the radar
        {.id = 3, .kind = CGS_KIND_AIR, .position = {10, 10, 0}},
    };
    im_sar_scene_t sc = {.ents = ents, .nents = 3};
    im_sar_chip_t c;
    im_sar_t *sar = s_image (&p, &g, &sc, &c);
    const double *in = im_sar_intensity (sar);
    double clutter = pow (10, p.ground_gamma_db / 10) * sin (S_PSI * S_DEG);
    for (int k = 0; k < 3; k++) {
        double x, y, best = 0;
        cgs_enu_t vel = {ents[k].speed_mps * sin (ents[k].heading_deg * S_DEG),
                         ents[k].speed_mps * cos (ents[k].heading_deg * S_DEG), 0};
        assert_true (im_sar_ground_to_px (&c, S_N, S_N, ents[k].position, vel, &x, &y));
        for (int yy = (int)y - 6; yy <= (int)y + 6; yy++)
            for (int xx = (int)x - 6; xx <= (int)x + 6; xx++)
                best = fmax (best, in[yy * S_N + xx]);
        if (ents[k].kind == CGS_KIND_AIR)
            assert_true (best < 30 * clutter); // not imaged
        else
            assert_true (best > 100 * clutter); // 20 dB over the ground
    }
    // The moving one is not at its place: only its shadow is.
    double x, y, best = 0;
    s_ground_px (&c, ents[1].position, &x, &y);
    for (int yy = (int)y - 3; yy <= (int)y + 3; yy++)
        for (int xx = (int)x - 3; xx <= (int)x + 3; xx++)
            best = fmax (best, in[yy * S_N + xx]);
    assert_true (best < 30 * clutter);
    im_sar_destroy (&sar);
}

/* ---- the chip's geometry ----------------------------------------------------------- */

static double s_dist (cgs_enu_t a, cgs_enu_t b)
{
    return sqrt (pow (a.e_m - b.e_m, 2) + pow (a.n_m - b.n_m, 2) + pow (a.u_m - b.u_m, 2));
}

static void test_geometry (void **state)
{
    (void)state;
    im_sar_params_t p = s_params (IM_SAR_WINDOW_TAYLOR, IM_SAR_GROUND);
    // Radar to the east looking west, flying north (right-looking... left of the look: south).
    double psi = 40 * S_DEG;
    im_sar_geom_t g = {.radar = {4000 * cos (psi), 0, 4000 * sin (psi)},
                       .radar_vel = {0, 80, 0},
                       .center = {0, 0, 0}};
    im_sar_scene_t sc = {.no_clutter = true};
    im_sar_chip_t c;
    im_sar_t *sar = s_image (&p, &g, &sc, &c);
    assert_near (c.grazing_deg, 40, 1e-9);
    assert_near (c.slant_range_m, 4000, 1e-6);
    assert_near (c.squint_deg, 0, 1e-9);
    assert_rel (c.aperture_s, p.integration_deg * S_DEG * 4000 / 80, 1e-9);
    // Up is far (west), right is north of the look.
    assert_near (c.range_dir.e_m, -1, 1e-12);
    assert_near (c.cross_dir.n_m, 1, 1e-12);
    // Corners: near-left, far-left, far-right, near-right.
    assert_true (s_dist (c.corners[0], g.radar) < s_dist (c.corners[1], g.radar));
    assert_true (s_dist (c.corners[3], g.radar) < s_dist (c.corners[2], g.radar));
    assert_near (c.corners[0].n_m, -32, 1e-9);
    assert_near (c.corners[0].e_m, 32, 1e-9);
    assert_near (c.corners[2].n_m, 32, 1e-9);
    assert_near (c.corners[2].e_m, -32, 1e-9);
    double x, y;
    assert_true (im_sar_chip_to_px (&c, (cgs_enu_t){-10, 5, 0}, (cgs_enu_t){0, 0, 0}, &x, &y));
    assert_near (x, 64 + 5 / c.pixel_m, 1e-9);
    assert_near (y, 64 - 10 / c.pixel_m, 1e-9);
    assert_false (im_sar_chip_to_px (&c, (cgs_enu_t){-40, 0, 0}, (cgs_enu_t){0, 0, 0}, &x, &y));
    // In a 640 × 480 frame: 480 × 480 in the middle, black bars.
    assert_true (
        im_sar_ground_to_px (&c, 640, 480, (cgs_enu_t){-10, 5, 0}, (cgs_enu_t){0, 0, 0}, &x, &y));
    assert_near (x, 80 + (64 + 5 / c.pixel_m) * 480.0 / S_N, 1e-9);
    assert_near (y, (64 - 10 / c.pixel_m) * 480.0 / S_N, 1e-9);
    uint8_t *rgba = malloc (640 * 480 * 4);
    assert_non_null (rgba);
    im_sar_to_rgba (sar, rgba, 640, 480);
    for (int yy = 0; yy < 480; yy += 7) {
        assert_int_equal (rgba[4 * (yy * 640 + 10)], 0);
        assert_int_equal (rgba[4 * (yy * 640 + 630) + 3], 255);
    }
    free (rgba);
    im_sar_destroy (&sar);
    // Pixel to ground and back over hills, in both geometries.
    cgs_terrain_fbm_t fb;
    cgs_terrain_fbm_defaults (&fb);
    fb.seed = 9, fb.size_m = 2000, fb.resolution_m = 10, fb.relief_m = 80, fb.feature_m = 400;
    cgs_terrain_t *t = cgs_terrain_new_fbm (&fb);
    assert_non_null (t);
    for (int geo = 0; geo < 2; geo++) {
        p = s_params (IM_SAR_WINDOW_TAYLOR, (im_sar_geometry_t)geo);
        double hc = cgs_terrain_height_clamped (t, 0, 0);
        im_sar_geom_t gt = s_geom (20);
        gt.center.u_m = hc, gt.radar.u_m += hc;
        im_sar_scene_t st = {.terrain = t, .no_clutter = true};
        sar = s_image (&p, &gt, &st, &c);
        for (int k = 0; k < 20; k++) {
            double px = 5 + 6 * k, py = 120 - 5.5 * k, qx, qy;
            cgs_enu_t gp;
            assert_true (im_sar_chip_px_to_ground (&c, px, py, t, &gp));
            assert_near (gp.u_m, cgs_terrain_height_clamped (t, gp.e_m, gp.n_m), 0.01);
            assert_true (im_sar_chip_to_px (&c, gp, (cgs_enu_t){0, 0, 0}, &qx, &qy));
            assert_near (qx, px, 1e-3);
            assert_near (qy, py, 1e-3);
        }
        im_sar_destroy (&sar);
    }
    cgs_terrain_destroy (&t);
}

/* ---- refusals ---------------------------------------------------------------------- */

static void s_refused (im_sar_params_t p, const char *want)
{
    char err[256] = "";
    assert_int_equal (im_sar_params_check (&p, err, sizeof err), -EINVAL);
    if (!strstr (err, want))
        fail_msg ("'%s' does not say '%s'", err, want);
    err[0] = '\0';
    assert_null (im_sar_new (&p, 1, err, sizeof err));
    assert_non_null (strstr (err, want));
}

static void test_refusals (void **state)
{
    (void)state;
    im_sar_params_t p;
    im_sar_params_defaults (&p);
    char err[256];
    assert_int_equal (im_sar_params_check (&p, err, sizeof err), 0);
    p.looks = 0;
    s_refused (p, "[sar] looks: expected an integer in [1, 16], got 0");
    im_sar_params_defaults (&p);
    p.size_px = 32;
    s_refused (p, "[sar] size_px: expected an integer in [64, 2048], got 32");
    im_sar_params_defaults (&p);
    p.bandwidth_hz = 3e9;
    s_refused (p, "[sar] bandwidth_hz: expected at most a quarter of fc_hz (2.4e+09), got 3e+09");
    im_sar_params_defaults (&p);
    p.fc_hz = NAN;
    s_refused (p, "[sar] fc_hz: expected a number in [1e+09, 1e+11]");
    im_sar_params_defaults (&p);
    p.window = (im_sar_window_t)5;
    s_refused (p, "[sar] window: expected rect, hamming or taylor, got 5");
    im_sar_params_defaults (&p);
    p.geometry = (im_sar_geometry_t)-1;
    s_refused (p, "[sar] geometry: expected ground or slant, got -1");
    im_sar_params_defaults (&p);
    p.scene_m = 4000;
    p.size_px = 2048;
    s_refused (p, "[sar] scene_m: expected a smaller chip for the resolution");
    // Geometries.
    im_sar_params_defaults (&p);
    p.size_px = 64, p.scene_m = 64;
    im_sar_t *sar = im_sar_new (&p, 1, err, sizeof err);
    assert_non_null (sar);
    im_sar_scene_t sc = {.no_clutter = true};
    im_sar_geom_t g = s_geom (0);
    assert_null (im_sar_chip (sar));
    assert_int_equal (im_sar_image (sar, &g, &sc, NULL), 0);
    const im_sar_chip_t *before = im_sar_chip (sar);
    assert_non_null (before);
    im_sar_chip_t copy = *before, out;
    memset (&out, 0x5a, sizeof out);
    im_sar_chip_t poison = out;
    im_sar_geom_t bad = g;
    bad.radar_vel = (cgs_enu_t){0, 0, 0};
    assert_int_equal (im_sar_image (sar, &bad, &sc, &out), -EINVAL);
    bad = g, bad.radar.e_m = NAN;
    assert_int_equal (im_sar_image (sar, &bad, &sc, &out), -EINVAL);
    bad = g, bad.radar.u_m = 10; // grazing under 1°
    assert_int_equal (im_sar_image (sar, &bad, &sc, &out), -EDOM);
    bad = g, bad.radar_vel = (cgs_enu_t){0, 100, 0}; // flying straight at the scene
    assert_int_equal (im_sar_image (sar, &bad, &sc, &out), -EDOM);
    bad = g, bad.radar = (cgs_enu_t){0, -40, 50}; // 64 m away
    assert_int_equal (im_sar_image (sar, &bad, &sc, &out), -EDOM);
    bad = s_geom (88); // squinted so far cross-range is nearly vertical
    assert_int_equal (im_sar_image (sar, &bad, &sc, &out), -EDOM);
    assert_memory_equal (&out, &poison, sizeof out); // nothing written
    assert_memory_equal (im_sar_chip (sar), &copy, sizeof copy);
    im_sar_destroy (&sar);
    assert_null (sar);
    im_sar_destroy (&sar);
    im_sar_destroy (NULL);
}

/* A widened chip (im_sar_geom_t.widen) is the chip the scaled parameters
 * make: scene and resolutions w times, integration angle and aperture time
 * w times smaller; its point response is w times wider. */
static void test_widened (void **state)
{
    (void)state;
    const double w = 4;
    im_sar_params_t p = s_params (IM_SAR_WINDOW_RECT, IM_SAR_SLANT);
    im_sar_geom_t g = s_geom (10), gw = g;
    gw.widen = w;
    im_sar_point_t pt = {.position = {21, -37, 0}, .rcs_m2 = 100};
    im_sar_scene_t sc = {.points = &pt, .npoints = 1, .no_clutter = true};
    im_sar_chip_t c, cw, cs;
    im_sar_t *sar = s_image (&p, &g, &sc, &c), *sarw = s_image (&p, &gw, &sc, &cw);
    assert_near (c.widen, 1, 0);
    assert_near (cw.widen, w, 0);
    assert_rel (cw.pixel_m, w * c.pixel_m, 1e-12);
    assert_rel (cw.range_res_m, w * c.range_res_m, 1e-12);
    assert_rel (cw.cross_res_m, w * c.cross_res_m, 1e-12);
    assert_rel (cw.aperture_s, c.aperture_s / w, 1e-12);
    // im_sar_plan says the same before the chip is made.
    im_sar_chip_t pw;
    assert_int_equal (im_sar_plan (sar, &gw, &pw), 0);
    assert_rel (pw.pixel_m, cw.pixel_m, 1e-12);
    assert_rel (s_dist (pw.corners[0], pw.corners[2]), s_dist (cw.corners[0], cw.corners[2]),
                1e-12);
    // The measured response: w times the theory's widths, where the geometry puts it.
    double lambda = S_C / p.fc_hz;
    double wr = 0.8859 * S_C / (2 * p.bandwidth_hz),
           wx = 0.8859 * lambda / (2 * p.integration_deg * S_DEG);
    double gx, gy;
    assert_true (im_sar_chip_to_px (&cw, pt.position, (cgs_enu_t){0, 0, 0}, &gx, &gy));
    s_pt_resp_t f = s_fast (sarw, &cw, gx, gy);
    assert_rel (f.wy, w * wr, 0.01);
    assert_rel (f.wx, w * wx, 0.01);
    assert_near (f.x, gx, 0.05);
    assert_near (f.y, gy, 0.05);
    // And the whole chip (over terrain, with its clutter) is the one the
    // scaled parameters make.
    cgs_terrain_fbm_t fb;
    cgs_terrain_fbm_defaults (&fb);
    fb.seed = 9, fb.size_m = 2000, fb.resolution_m = 10, fb.relief_m = 80, fb.feature_m = 400;
    cgs_terrain_t *hills = cgs_terrain_new_fbm (&fb);
    assert_non_null (hills);
    im_sar_scene_t sct = {.terrain = hills, .points = &pt, .npoints = 1};
    im_sar_params_t ps = p;
    ps.bandwidth_hz /= w, ps.integration_deg /= w, ps.scene_m *= w;
    im_sar_t *a = s_image (&p, &gw, &sct, &cw), *b = s_image (&ps, &g, &sct, &cs);
    assert_rel (cs.pixel_m, cw.pixel_m, 1e-12);
    const double *ia = im_sar_intensity (a), *ib = im_sar_intensity (b);
    double worst = 0, top = 0;
    for (int i = 0; i < p.size_px * p.size_px; i++)
        worst = fmax (worst, fabs (ia[i] - ib[i])), top = fmax (top, ib[i]);
    assert_true (top > 0);
    assert_true (worst <= 1e-9 * top);
    printf ("# widened x%.0f: range %.3f m (theory %.3f), cross %.3f (theory %.3f); "
            "the scaled parameters' chip within %.1e of its peak\n",
            w, f.wy, w * wr, f.wx, w * wx, worst / top);
    cgs_terrain_destroy (&hills);
    im_sar_destroy (&a);
    im_sar_destroy (&b);
    im_sar_destroy (&sar);
    im_sar_destroy (&sarw);
}

int main (void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test (test_windows),        cmocka_unit_test (test_impulse_rect),
        cmocka_unit_test (test_impulse_taylor), cmocka_unit_test (test_impulse_hamming),
        cmocka_unit_test (test_ground_widths),  cmocka_unit_test (test_layover),
        cmocka_unit_test (test_shadow),         cmocka_unit_test (test_moving_target),
        cmocka_unit_test (test_fast_vs_ref),    cmocka_unit_test (test_speckle),
        cmocka_unit_test (test_vehicles),       cmocka_unit_test (test_geometry),
        cmocka_unit_test (test_refusals),       cmocka_unit_test (test_widened),
    };
    return cmocka_run_group_tests (tests, NULL, NULL);
}
