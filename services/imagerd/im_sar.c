/* im_sar — a spotlight SAR chip by image-domain synthesis (see im_sar.h).
 *
 * The pipeline, per chip:
 *   1. Frame: the line of sight l̂ (radar to centre), the grazing angle ψ,
 *      the slant-plane cross-range direction ĉ (the part of the velocity
 *      across l̂), and the chip's plane axes (ground range and the horizontal
 *      across it, or l̂ and ĉ). (u, v) = M·(a, b) takes plane coordinates to
 *      slant range and slant cross-range: the point-spread function is
 *      separable in (u, v), so on the ground plane it is sheared when the
 *      chip is squinted.
 *   2. Scatterers: terrain facets on a ground lattice finer than the pixels
 *      (half the internal sample spacing), over the grid plus a margin for
 *      layover; σ0 = γ·cos(incidence) for open ground, volume scatterers at
 *      canopy height for woods, vehicles as a few bright points. Shadow: a
 *      sweep from near to far along each lattice column keeps the lowest
 *      tan(depression) of anything nearer (terrain, canopy, vehicle boxes;
 *      terrain nearer than the lattice by a march toward the radar); a point
 *      seen at a steeper depression than that is hidden. Each scatterer is
 *      placed by its range history: a straight, steady aperture gives every
 *      point with the same range R and the same along-velocity offset D =
 *      (v − v_target)·(s − radar)/V at the aperture's centre the same phase
 *      history, so it goes to the point of the chip's plane with that R and
 *      D — layover, foreshortening and the moving-target shift R·v_r/V.
 *   3. Per look: each scatterer (random phase) is spread with an
 *      "exponential of semicircle" kernel onto a grid oversampled about 2×
 *      over the band, FFT; each bin inside the support is divided by the
 *      kernel's transform, weighted by the window in u and v, and folded onto
 *      the internal output grid (folding is sampling, so squinted supports
 *      wider than that grid's band are still sampled exactly); noise is added
 *      there; inverse FFT; |.|². Looks are averaged, blocks of q × q internal
 *      samples averaged into a pixel when pixels are coarser than the band's
 *      Nyquist spacing.
 * Calibration: the response h is scaled so that ∫|h|² dA = 1 on the chip's
 * plane, so a field of σ0 per unit area averages σ0. */
#include "im_sar.h"
#include "cgs_util.h"

#include <complex.h>
#include <fftw3.h>

#include <assert.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define S_C         299792458.0
#define S_KW        6             // spreading kernel width, grid cells
#define S_BETA      (2.30 * S_KW) // its shape, for a grid oversampled 2×
#define S_SIGMA     2.0           // spreading grid samples the band this many times over
#define S_SIGMA_MIN 1.3           // a squinted support may use up the grid to here
#define S_KTAB      1000          // kernel table samples per cell
#define S_WTAB      4096          // window table intervals across the support
#define S_NPHASE    4096          // random phases drawn from this many
#define S_MAX_GRID  4096          // largest grid side (16·N² bytes each)
#define S_DEG       (M_PI / 180.0)

/* ---- parameters ------------------------------------------------------------------ */

void im_sar_params_defaults (im_sar_params_t *p)
{
    *p = (im_sar_params_t){
        .fc_hz = 9.6e9,
        .bandwidth_hz = 133e6,
        .integration_deg = 0.79,
        .window = IM_SAR_WINDOW_TAYLOR,
        .looks = 1,
        .scene_m = 256,
        .size_px = 256,
        .max_widen = 16,
        .gmti = true,
        .gmti_sigma_mps = 0.25,
        .geometry = IM_SAR_GROUND,
        .speckle = true,
        .ground_gamma_db = -12,
        .woods_gamma_db = -7,
        .vehicle_rcs_m2 = 100,
        .nesz_db = -30,
        .display_max_db = 5,
        .dynamic_range_db = 40,
    };
}

#define S_R(k, field, lo, hi)                                                                      \
    {                                                                                              \
        "sar", k, offsetof (im_sar_params_t, field), lo, hi                                        \
    }
static const cgs_config_real_t s_reals[] = {
    S_R ("fc_hz", fc_hz, 1e9, 1e11),
    S_R ("bandwidth_hz", bandwidth_hz, 1e6, 3e9),
    S_R ("integration_deg", integration_deg, 0.05, 20.0),
    S_R ("scene_m", scene_m, 16.0, 10000.0),
    S_R ("max_widen", max_widen, 1.0, IM_SAR_WIDEN_MAX),
    S_R ("gmti_sigma_mps", gmti_sigma_mps, 0.0, 10.0),
    S_R ("ground_gamma_db", ground_gamma_db, -100.0, 10.0),
    S_R ("woods_gamma_db", woods_gamma_db, -100.0, 10.0),
    S_R ("vehicle_rcs_m2", vehicle_rcs_m2, 0.0, 10000.0),
    S_R ("nesz_db", nesz_db, -100.0, 0.0),
    S_R ("display_max_db", display_max_db, -60.0, 60.0),
    S_R ("dynamic_range_db", dynamic_range_db, 1.0, 120.0),
};
#undef S_R
#define S_NREALS (sizeof s_reals / sizeof s_reals[0])
#define S_I(k, field, lo, hi)                                                                      \
    {                                                                                              \
        "sar", k, offsetof (im_sar_params_t, field), lo, hi                                        \
    }
static const cgs_config_int_t s_ints[] = {
    S_I ("looks", looks, 1, 16),
    S_I ("size_px", size_px, 64, 2048),
};
#undef S_I
#define S_NINTS (sizeof s_ints / sizeof s_ints[0])

static const char *const s_windows[] = {"rect", "hamming", "taylor", NULL};
static const char *const s_geometries[] = {"ground", "slant", NULL};

/* The grid sizes the parameters ask for. */
typedef struct {
    int q;      // internal output samples per pixel, each way
    int margin; // internal output samples beyond the chip, each side
    int n_out;  // internal output grid side
    int n_g;    // spreading grid side
    double k_u; // half the spectral support in slant range, cycles/m
    double k_v; // half the spectral support in cross-range, cycles/m
    double d;   // pixel spacing
    double d_o; // internal output spacing
    double d_g; // spreading grid spacing
    double len; // grid side, metres
} s_plan_t;

static bool s_nice (int n)
{
    static const int f[] = {2, 3, 5, 7};
    for (int i = 0; i < 4; i++)
        while (n % f[i] == 0)
            n /= f[i];
    return n == 1;
}

static int s_nice_up (int n)
{
    while (!s_nice (n))
        n++;
    return n;
}

static void s_plan (const im_sar_params_t *p, s_plan_t *ret)
{
    s_plan_t pl = {0};
    pl.k_u = p->bandwidth_hz / S_C;
    pl.k_v = p->integration_deg * S_DEG * p->fc_hz / S_C;
    double k = fmax (pl.k_u, pl.k_v);
    pl.d = p->scene_m / p->size_px;
    pl.q = (int)ceil (pl.d * 2.0 * k * 1.02 - 1e-9);
    if (pl.q < 1)
        pl.q = 1;
    pl.d_o = pl.d / pl.q;
    int inner = pl.q * p->size_px;
    pl.margin = inner / 16 > 16 ? inner / 16 : 16;
    while (!s_nice (inner + 2 * pl.margin))
        pl.margin++;
    pl.n_out = inner + 2 * pl.margin;
    pl.len = pl.n_out * pl.d_o;
    double need = ceil (S_SIGMA * 2.0 * k * pl.len);
    pl.n_g = s_nice_up (need > pl.n_out ? (int)fmin (need, 1e6) : pl.n_out);
    pl.d_g = pl.len / pl.n_g;
    *ret = pl;
}

/* The first bad key of p: true with its name and "expected ..., got ...". */
static bool s_invalid (const im_sar_params_t *p, const char **ret_key, char *msg, size_t msglen)
{
    const char *sec = NULL;
    if (cgs_config_table_out_of_range (s_reals, S_NREALS, s_ints, S_NINTS, p, &sec, ret_key, msg,
                                       msglen))
        return true;
    if ((unsigned)p->window > IM_SAR_WINDOW_TAYLOR) {
        *ret_key = "window";
        snprintf (msg, msglen, "expected rect, hamming or taylor, got %d", (int)p->window);
    } else if ((unsigned)p->geometry > IM_SAR_SLANT) {
        *ret_key = "geometry";
        snprintf (msg, msglen, "expected ground or slant, got %d", (int)p->geometry);
    } else if (p->bandwidth_hz > p->fc_hz / 4) {
        *ret_key = "bandwidth_hz";
        snprintf (msg, msglen, "expected at most a quarter of fc_hz (%g), got %g", p->fc_hz / 4,
                  p->bandwidth_hz);
    } else {
        s_plan_t pl;
        s_plan (p, &pl);
        if (pl.n_g <= S_MAX_GRID)
            return false;
        *ret_key = "scene_m";
        snprintf (msg, msglen,
                  "expected a smaller chip for the resolution (its grid would be %d cells a side, "
                  "at most %d), got %g",
                  pl.n_g, S_MAX_GRID, p->scene_m);
    }
    return true;
}

int im_sar_params_check (const im_sar_params_t *p, char *err, size_t errlen)
{
    const char *key = NULL;
    char msg[256] = "";
    if (!s_invalid (p, &key, msg, sizeof msg))
        return 0;
    return cgs_config_value_error (NULL, "sar", key, msg, err, errlen);
}

int im_sar_params_read (cgs_config_t *cfg, im_sar_params_t *p, char *err, size_t errlen)
{
    im_sar_params_t q = *p;
    int rc = cgs_config_get_table (cfg, s_reals, S_NREALS, s_ints, S_NINTS, &q, err, errlen);
    int window = (int)q.window, geometry = (int)q.geometry;
    if (rc == 0)
        rc = cgs_config_get_enum (cfg, "sar", "window", s_windows, window, &window, err, errlen);
    if (rc == 0)
        rc = cgs_config_get_enum (cfg, "sar", "geometry", s_geometries, geometry, &geometry, err,
                                  errlen);
    if (rc == 0)
        rc = cgs_config_get_bool (cfg, "sar", "speckle", q.speckle, &q.speckle, err, errlen);
    if (rc == 0)
        rc = cgs_config_get_bool (cfg, "sar", "gmti", q.gmti, &q.gmti, err, errlen);
    q.window = (im_sar_window_t)window;
    q.geometry = (im_sar_geometry_t)geometry;
    if (rc == 0) {
        const char *key = NULL;
        char msg[256];
        if (s_invalid (&q, &key, msg, sizeof msg))
            rc = cgs_config_value_error (cfg, "sar", key, msg, err, errlen);
    }
    if (rc < 0)
        return rc;
    *p = q;
    return 0;
}

/* ---- windows --------------------------------------------------------------------- */

/* Taylor coefficients F_1..F_{nbar-1} for n̄ = 4, −35 dB (Carrara, Goodman
 * and Majewski, "Spotlight SAR", appendix D). */
#define S_NBAR    4
#define S_TAY_SLL 35.0
static void s_taylor (double f[S_NBAR])
{
    double a = acosh (pow (10.0, S_TAY_SLL / 20.0)) / M_PI;
    double s2 = (double)(S_NBAR * S_NBAR) / (a * a + (S_NBAR - 0.5) * (S_NBAR - 0.5));
    f[0] = 0;
    for (int m = 1; m < S_NBAR; m++) {
        double num = 1, den = 1;
        for (int n = 1; n < S_NBAR; n++) {
            num *= 1.0 - (double)(m * m) / (s2 * (a * a + (n - 0.5) * (n - 0.5)));
            if (n != m)
                den *= 1.0 - (double)(m * m) / (double)(n * n);
        }
        f[m] = ((m % 2) ? 0.5 : -0.5) * num / den;
    }
}

double im_sar_window (im_sar_window_t w, double x)
{
    if (!(fabs (x) <= 0.5))
        return 0;
    switch (w) {
    case IM_SAR_WINDOW_HAMMING:
        return 0.54 + 0.46 * cos (2 * M_PI * x);
    case IM_SAR_WINDOW_TAYLOR: {
        double f[S_NBAR], v = 1;
        s_taylor (f);
        for (int m = 1; m < S_NBAR; m++)
            v += 2 * f[m] * cos (2 * M_PI * m * x);
        return v;
    }
    default:
        return 1;
    }
}

/* The window's response at y (cycles across the support), midpoint rule. */
static double s_response (const double *wv, int n, double y)
{
    double s = 0;
    for (int i = 0; i < n; i++)
        s += wv[i] * cos (2 * M_PI * ((i + 0.5) / n - 0.5) * y);
    return s / n;
}

double im_sar_window_width (im_sar_window_t w)
{
    enum { N = 2000 };
    double wv[N];
    for (int i = 0; i < N; i++)
        wv[i] = im_sar_window (w, (i + 0.5) / N - 0.5);
    double r0 = s_response (wv, N, 0), lo = 0, hi = 1.5;
    for (int it = 0; it < 60; it++) {
        double mid = (lo + hi) / 2, r = s_response (wv, N, mid) / r0;
        if (r * r > 0.5)
            lo = mid;
        else
            hi = mid;
    }
    return lo + hi; // twice the half width
}

/* ---- vectors and the collection's frame ------------------------------------------ */

static cgs_enu_t s_v (double e, double n, double u)
{
    return (cgs_enu_t){e, n, u};
}
static cgs_enu_t s_add (cgs_enu_t a, cgs_enu_t b)
{
    return s_v (a.e_m + b.e_m, a.n_m + b.n_m, a.u_m + b.u_m);
}
static cgs_enu_t s_sub (cgs_enu_t a, cgs_enu_t b)
{
    return s_v (a.e_m - b.e_m, a.n_m - b.n_m, a.u_m - b.u_m);
}
static cgs_enu_t s_mul (cgs_enu_t a, double k)
{
    return s_v (a.e_m * k, a.n_m * k, a.u_m * k);
}
static double s_dot (cgs_enu_t a, cgs_enu_t b)
{
    return a.e_m * b.e_m + a.n_m * b.n_m + a.u_m * b.u_m;
}
static double s_len (cgs_enu_t a)
{
    return sqrt (s_dot (a, a));
}
static cgs_enu_t s_unit (cgs_enu_t a)
{
    return s_mul (a, 1.0 / s_len (a));
}
static bool s_finite (cgs_enu_t a)
{
    return isfinite (a.e_m) && isfinite (a.n_m) && isfinite (a.u_m);
}

typedef struct {
    im_sar_geometry_t geometry;
    cgs_enu_t r0, v, c; // radar, velocity, centre
    double speed;       // |v|
    cgs_enu_t vhat;
    cgs_enu_t l0;              // unit line of sight
    double r_0;                // slant range to the centre
    double psi;                // grazing angle, radians
    cgs_enu_t gr, gx;          // ground range, ground cross (right), horizontal units
    cgs_enu_t chat;            // slant cross-range (right)
    cgs_enu_t ns;              // in the slant plane, across the velocity, toward the scene
    double side;               // the scene's side of the ground track: +1 left of it, −1 right
    cgs_enu_t er, ex;          // the chip plane's axes: far and right
    double m11, m12, m21, m22; // (u, v) = M (a, b)
    double vperp;              // speed across the line of sight
    double wn, ue, un;         // the velocity's horizontal part: length (of v̂'s) and unit
} s_frame_t;

/* |(x, y)|: the arguments are metres, far from overflow (glibc's hypot is slow). */
static double s_hyp (double x, double y)
{
    return sqrt (x * x + y * y);
}

/* The frame of a collection: 0, -EINVAL or -EDOM (see im_sar_image). */
static int s_frame (cgs_enu_t r0, cgs_enu_t v, cgs_enu_t c, im_sar_geometry_t geometry,
                    s_frame_t *ret)
{
    if (!s_finite (r0) || !s_finite (v) || !s_finite (c))
        return -EINVAL;
    s_frame_t f = {.geometry = geometry, .r0 = r0, .v = v, .c = c};
    f.speed = s_len (v);
    if (!(f.speed >= 0.1))
        return -EINVAL;
    f.vhat = s_mul (v, 1.0 / f.speed);
    cgs_enu_t los = s_sub (c, r0);
    f.r_0 = s_len (los);
    if (!(f.r_0 >= 100))
        return -EDOM;
    f.l0 = s_mul (los, 1.0 / f.r_0);
    f.psi = asin (-f.l0.u_m);
    if (!(f.psi >= 1 * S_DEG && f.psi <= 85 * S_DEG))
        return -EDOM;
    double wn = s_hyp (f.vhat.e_m, f.vhat.n_m);
    if (wn < 1e-3)
        return -EDOM; // climbing or diving straight: no ground track
    f.wn = wn, f.ue = f.vhat.e_m / wn, f.un = f.vhat.n_m / wn;
    cgs_enu_t vperp = s_sub (f.v, s_mul (f.l0, s_dot (f.v, f.l0)));
    f.vperp = s_len (vperp);
    if (f.vperp < 0.2 * f.speed)
        return -EDOM; // looking within 11.5° of the track: no cross-range resolution
    f.gr = s_unit (s_v (f.l0.e_m, f.l0.n_m, 0));
    f.gx = s_v (f.gr.n_m, -f.gr.e_m, 0);
    f.chat = s_mul (vperp, 1.0 / f.vperp);
    if (s_dot (f.chat, f.gx) < 0)
        f.chat = s_mul (f.chat, -1);
    if (fabs (s_dot (f.chat, f.gx)) < 0.25)
        return -EDOM; // the slant plane near vertical: cross-range has no ground across the look
    f.ns = s_unit (s_sub (f.l0, s_mul (f.vhat, s_dot (f.l0, f.vhat))));
    cgs_enu_t perp = s_v (-f.vhat.n_m / wn, f.vhat.e_m / wn, 0); // left of the track
    f.side = s_dot (los, perp) >= 0 ? 1 : -1;
    if (geometry == IM_SAR_SLANT) {
        f.er = f.l0, f.ex = f.chat;
        f.m11 = 1, f.m12 = 0, f.m21 = 0, f.m22 = 1;
    } else {
        f.er = f.gr, f.ex = f.gx;
        f.m11 = s_dot (f.gr, f.l0), f.m12 = s_dot (f.gx, f.l0);
        f.m21 = s_dot (f.gr, f.chat), f.m22 = s_dot (f.gx, f.chat);
    }
    *ret = f;
    return 0;
}

/* The point at height z with range R and along-velocity offset D from the radar. */
static bool s_rd_at_height (const s_frame_t *f, double r, double d, double z, cgs_enu_t *ret)
{
    double qz = z - f->r0.u_m;
    double wn = f->wn, ue = f->ue, un = f->un;
    double alpha = (d - qz * f->vhat.u_m) / wn;
    double beta2 = r * r - qz * qz - alpha * alpha;
    if (!(beta2 >= 0))
        return false;
    double beta = f->side * sqrt (beta2);
    *ret = s_v (f->r0.e_m + alpha * ue - beta * un, f->r0.n_m + alpha * un + beta * ue, z);
    return true;
}

/* The point of the chip's plane with range R and offset D. */
static bool s_rd_to_plane (const s_frame_t *f, double r, double d, cgs_enu_t *ret)
{
    if (f->geometry == IM_SAR_GROUND)
        return s_rd_at_height (f, r, d, f->c.u_m, ret);
    double y2 = r * r - d * d;
    if (!(y2 >= 0))
        return false;
    *ret = s_add (f->r0, s_add (s_mul (f->vhat, d), s_mul (f->ns, sqrt (y2))));
    return true;
}

/* Where a scatterer at s moving at vel images: plane coordinates (a far, b right). */
static bool s_place (const s_frame_t *f, cgs_enu_t s, cgs_enu_t vel, double *ret_a, double *ret_b)
{
    cgs_enu_t q = s_sub (s, f->r0);
    double r = s_len (q), d = s_dot (s_sub (f->v, vel), q) / f->speed;
    cgs_enu_t p;
    if (!s_rd_to_plane (f, r, d, &p))
        return false;
    cgs_enu_t dp = s_sub (p, f->c);
    *ret_a = s_dot (dp, f->er);
    *ret_b = s_dot (dp, f->ex);
    return true;
}

static int s_frame_of_chip (const im_sar_chip_t *c, s_frame_t *ret)
{
    return s_frame (c->radar, c->radar_vel, c->center, c->geometry, ret);
}

/* Chip pixel coordinates to plane coordinates and back. */
static void s_px_to_ab (const im_sar_chip_t *c, double x, double y, double *a, double *b)
{
    *b = (x - c->size_px / 2.0) * c->pixel_m;
    *a = (c->size_px / 2.0 - y) * c->pixel_m;
}

/* ---- the object ------------------------------------------------------------------ */

typedef struct {
    float x, y; // spreading grid coordinates (columns right, rows toward near)
    float amp;  // √σ, or the speckle-free amplitude
} s_scat_t;

struct im_sar {
    im_sar_params_t p;
    s_plan_t pl0; // as configured
    s_plan_t pl;  // the chip being made: pl0 widened (im_sar_geom_t.widen)
    uint64_t rng;
    fftw_complex *g, *o; // spreading grid, internal output grid
    fftw_plan fwd, inv;
    float *ktab;             // kernel, S_KTAB samples per cell
    double *deconv;          // 1/φ̂ per spreading bin (index 0..n_g-1)
    double wtab[S_WTAB + 2]; // window across its support
    double complex phase[S_NPHASE];
    // the chip
    double *inten;
    double *slc;
    uint8_t *grey;
    im_sar_chip_t chip;
    bool have_chip;
    // per chip, reused
    s_scat_t *sc;
    size_t nsc, capsc;
    float *fz, *fcan, *fveh, *fhz; // lattice: ground height, canopy, vehicle box, horizon
    size_t capf;
    double *acc; // intensity accumulator over the chip
};

static double s_gauss (uint64_t *rng)
{
    double u1 = cgs_uniform01 (rng), u2 = cgs_uniform01 (rng);
    return sqrt (-2 * log (u1)) * cos (2 * M_PI * u2);
}

static double s_kernel (double x) // x in cells, |x| <= S_KW/2
{
    double z = 2 * x / S_KW;
    return fabs (z) >= 1 ? 0 : exp (S_BETA * (sqrt (1 - z * z) - 1));
}

void im_sar_destroy (im_sar_t **self_p)
{
    if (!self_p || !*self_p)
        return;
    im_sar_t *self = *self_p;
    if (self->fwd)
        fftw_destroy_plan (self->fwd);
    if (self->inv)
        fftw_destroy_plan (self->inv);
    fftw_free (self->g);
    fftw_free (self->o);
    free (self->ktab);
    free (self->deconv);
    free (self->inten);
    free (self->slc);
    free (self->grey);
    free (self->sc);
    free (self->fz);
    free (self->fcan);
    free (self->fveh);
    free (self->fhz);
    free (self->acc);
    free (self);
    *self_p = NULL;
}

im_sar_t *im_sar_new (const im_sar_params_t *p, uint64_t seed, char *err, size_t errlen)
{
    if (im_sar_params_check (p, err, errlen) < 0)
        return NULL;
    im_sar_t *self = calloc (1, sizeof *self);
    if (!self)
        goto nomem;
    self->p = *p;
    self->rng = seed ^ 0x5a52u;
    s_plan (p, &self->pl0);
    self->pl = self->pl0;
    const s_plan_t *pl = &self->pl;
    size_t ng2 = (size_t)pl->n_g * pl->n_g, no2 = (size_t)pl->n_out * pl->n_out;
    size_t px = (size_t)p->size_px * p->size_px;
    self->g = fftw_malloc (ng2 * sizeof *self->g);
    self->o = fftw_malloc (no2 * sizeof *self->o);
    self->ktab = malloc (((size_t)S_KW * S_KTAB + 2) * sizeof *self->ktab);
    self->deconv = malloc ((size_t)pl->n_g * sizeof *self->deconv);
    self->inten = calloc (px, sizeof *self->inten);
    self->acc = calloc (px, sizeof *self->acc);
    self->grey = calloc (px, 1);
    if (pl->q == 1)
        self->slc = calloc (2 * px, sizeof *self->slc);
    if (!self->g || !self->o || !self->ktab || !self->deconv || !self->inten || !self->acc ||
        !self->grey || (pl->q == 1 && !self->slc))
        goto nomem;
    self->fwd = fftw_plan_dft_2d (pl->n_g, pl->n_g, self->g, self->g, FFTW_FORWARD, FFTW_ESTIMATE);
    self->inv =
        fftw_plan_dft_2d (pl->n_out, pl->n_out, self->o, self->o, FFTW_BACKWARD, FFTW_ESTIMATE);
    if (!self->fwd || !self->inv) {
        cgs_errf (err, errlen, "sar: FFTW could not plan a %d x %d transform", pl->n_g, pl->n_g);
        im_sar_destroy (&self);
        return NULL;
    }
    for (int i = 0; i <= S_KW * S_KTAB + 1; i++)
        self->ktab[i] = (float)s_kernel ((double)i / S_KTAB - S_KW / 2.0);
    // The kernel's transform at each bin, by the midpoint rule (200 points a cell).
    enum { Q = 200 };
    for (int k = 0; k < pl->n_g; k++) {
        int kk = k < (pl->n_g + 1) / 2 ? k : pl->n_g - k;
        double s = 0;
        for (int i = 0; i < S_KW * Q; i++) {
            double x = (i + 0.5) / Q - S_KW / 2.0;
            s += s_kernel (x) * cos (2 * M_PI * kk * x / pl->n_g);
        }
        self->deconv[k] = (double)Q / s;
    }
    for (int i = 0; i <= S_WTAB + 1; i++)
        self->wtab[i] = im_sar_window (p->window, fmin ((double)i / S_WTAB, 1.0) - 0.5);
    for (int i = 0; i < S_NPHASE; i++)
        self->phase[i] = cexp (I * 2 * M_PI * i / S_NPHASE);
    return self;
nomem:
    cgs_errf (err, errlen, "sar: out of memory for a %d-pixel chip", p->size_px);
    im_sar_destroy (&self);
    return NULL;
}

/* The window at x in [−0.5, 0.5] from the table. */
static double s_wt (const im_sar_t *self, double x)
{
    double f = (x + 0.5) * S_WTAB;
    int i = (int)f;
    if (i < 0 || i >= S_WTAB)
        return i == S_WTAB ? self->wtab[S_WTAB] : 0;
    double t = f - i;
    return self->wtab[i] * (1 - t) + self->wtab[i + 1] * t;
}

static int s_push (im_sar_t *self, double x, double y, double amp)
{
    const s_plan_t *pl = &self->pl;
    double lo = -0.5 * pl->d_o / pl->d_g;
    if (!(x >= lo && x < pl->n_g + lo && y >= lo && y < pl->n_g + lo) || !(amp > 0))
        return 0;
    if (self->nsc == self->capsc &&
        cgs_grow ((void **)&self->sc, &self->capsc, self->nsc + 1, sizeof *self->sc) < 0)
        return -ENOMEM;
    self->sc[self->nsc++] = (s_scat_t){(float)x, (float)y, (float)amp};
    return 0;
}

/* The filter's frame-dependent numbers. */
typedef struct {
    double ka_max, kb_max; // half-extents of the support on the chip's plane, cycles/m
    double sn;             // scale: ∫|h|² dA = 1
    double coh;            // speckle-free facet amplitude per √(σ)·spacing
} s_filter_t;

/* The share of a bin at x (bins dx wide) inside [−0.5, 0.5]. */
static double s_inside (double x, double dx)
{
    double f = (0.5 - fabs (x)) / dx + 0.5;
    return f <= 0 ? 0 : f >= 1 ? 1 : f;
}

/* The window at spreading bin (ky, kx) (signed), 0 outside the support. A
 * bin the support's edge cuts counts by its share inside, so the sampled
 * window keeps the continuous one's extent. */
static double s_weight (const im_sar_t *self, const s_frame_t *f, int ky, int kx)
{
    const s_plan_t *pl = &self->pl;
    double ka = -ky / pl->len, kb = kx / pl->len; // rows run toward near: a = −y
    double kv, ku;
    if (f->geometry == IM_SAR_SLANT) {
        ku = ka, kv = kb;
    } else {
        kv = kb / f->m22;
        ku = (ka - f->m21 * kv) / f->m11;
    }
    double xu = ku / (2 * pl->k_u), xv = kv / (2 * pl->k_v);
    double dxu = 1 / (2 * pl->k_u * pl->len * fabs (f->m11));
    double dxv = 1 / (2 * pl->k_v * pl->len * fabs (f->m22));
    double fu = s_inside (xu, dxu), fv = s_inside (xv, dxv);
    if (fu == 0 || fv == 0)
        return 0;
    return fu * fv * s_wt (self, fmax (-0.5, fmin (0.5, xu))) *
           s_wt (self, fmax (-0.5, fmin (0.5, xv)));
}

static void s_filter (const im_sar_t *self, const s_frame_t *f, s_filter_t *ret)
{
    const s_plan_t *pl = &self->pl;
    s_filter_t fl;
    fl.ka_max = fabs (f->m11) * pl->k_u + fabs (f->m21) * pl->k_v;
    fl.kb_max = fabs (f->m12) * pl->k_u + fabs (f->m22) * pl->k_v;
    int ny = (int)ceil (fl.ka_max * pl->len) + 1, nx = (int)ceil (fl.kb_max * pl->len) + 1;
    double s2 = 0;
    for (int ky = -ny; ky <= ny; ky++)
        for (int kx = -nx; kx <= nx; kx++) {
            double w = s_weight (self, f, ky, kx);
            s2 += w * w;
        }
    fl.sn = 1.0 / (pl->len * sqrt (s2));
    double h0 = s_wt (self, 0) * s_wt (self, 0);
    fl.coh = 1.0 / (fl.sn * h0 * pl->len * pl->len);
    *ret = fl;
}

/* ---- the scene's scatterers ------------------------------------------------------ */

typedef struct {
    double x, y, z, w; // body frame (forward, right, up) metres; share of the RCS
} s_bodypt_t;

static const s_bodypt_t s_tracked[] = {
    {3.4, -1.7, 1.8, 8}, {3.4, 1.7, 1.8, 8},   {-3.4, -1.7, 1.8, 8}, {-3.4, 1.7, 1.8, 8},
    {0.0, 0.0, 2.4, 15}, {0.0, -1.8, 0.4, 20}, {0.0, 1.8, 0.4, 20},  {5.5, 0.0, 2.1, 5},
    {3.5, 0.0, 0.8, 6},  {-3.5, 0.0, 0.8, 6},
};
static const s_bodypt_t s_wheeled[] = {
    {2.9, -1.2, 2.3, 10}, {2.9, 1.2, 2.3, 10},   {-2.9, -1.2, 2.3, 10}, {-2.9, 1.2, 2.3, 10},
    {2.8, 0.0, 1.5, 15},  {0.0, -1.25, 0.5, 20}, {0.0, 1.25, 0.5, 20},  {-3.0, 0.0, 1.2, 10},
};
static const s_bodypt_t s_person[] = {{0, 0, 1.0, 1}};

typedef struct {
    const s_bodypt_t *pts;
    size_t n;
    double rcs_share;          // of vehicle_rcs_m2
    double len, width, height; // box, metres
} s_body_t;

static bool s_body (cgs_kind_t kind, s_body_t *ret)
{
    switch (kind) {
    case CGS_KIND_TRACKED:
        *ret = (s_body_t){s_tracked, sizeof s_tracked / sizeof *s_tracked, 1.0, 7.0, 3.6, 2.4};
        return true;
    case CGS_KIND_PERSON:
        *ret = (s_body_t){s_person, 1, 0.01, 0.6, 0.6, 1.8};
        return true;
    case CGS_KIND_AIR:
        return false;
    default:
        *ret = (s_body_t){s_wheeled, sizeof s_wheeled / sizeof *s_wheeled, 0.6, 6.0, 2.5, 2.5};
        return true;
    }
}

/* The ground lattice: facets at (a0 + (i+½)s, b0 + (j+½)s), i toward far. */
typedef struct {
    double a0, b0, s;
    int na, nb;
} s_lattice_t;

static double s_height (const cgs_terrain_t *t, double e, double n)
{
    return t ? cgs_terrain_height_clamped (t, e, n) : 0.0;
}

/* Ground (a, b) to ENU at height z. */
static cgs_enu_t s_ground (const s_frame_t *f, double a, double b, double z)
{
    return s_v (f->c.e_m + a * f->gr.e_m + b * f->gx.e_m, f->c.n_m + a * f->gr.n_m + b * f->gx.n_m,
                z);
}

/* The lowest tan(depression) from the radar over terrain (and canopy) between
 * the radar and p, outside the lattice: a march toward the radar. */
static double s_outer_horizon (const cgs_terrain_t *t, const s_frame_t *f, cgs_enu_t p, double step)
{
    double best = INFINITY;
    if (!t)
        return best;
    double e0, n0, e1, n1;
    cgs_terrain_bounds (t, &e0, &n0, &e1, &n1);
    double de = f->r0.e_m - p.e_m, dn = f->r0.n_m - p.n_m, dist = s_hyp (de, dn);
    if (dist <= step)
        return best;
    de /= dist, dn /= dist;
    // Clip the segment to the grid (slabs).
    double lo = step, hi = dist - step;
    const double pe[2] = {p.e_m, p.n_m}, dd[2] = {de, dn}, mn[2] = {e0, n0}, mx[2] = {e1, n1};
    for (int k = 0; k < 2; k++) {
        if (fabs (dd[k]) < 1e-12) {
            if (pe[k] < mn[k] || pe[k] > mx[k])
                return best;
            continue;
        }
        double t0 = (mn[k] - pe[k]) / dd[k], t1 = (mx[k] - pe[k]) / dd[k];
        if (t0 > t1) {
            double x = t0;
            t0 = t1, t1 = x;
        }
        lo = fmax (lo, t0), hi = fmin (hi, t1);
    }
    for (double s = lo; s <= hi; s += step) {
        double e = p.e_m + s * de, n = p.n_m + s * dn;
        double z = cgs_terrain_height_clamped (t, e, n) + cgs_terrain_canopy (t, e, n);
        double tn = (f->r0.u_m - z) / (dist - s);
        if (tn < best)
            best = tn;
    }
    return best;
}

/* Is a point at p (height z) seen past the horizon hz of its lattice cell? */
static bool s_seen (const s_frame_t *f, cgs_enu_t p, double hz)
{
    double dist = s_hyp (p.e_m - f->r0.e_m, p.n_m - f->r0.n_m);
    return (f->r0.u_m - p.u_m) / dist <= hz + 0.05 / dist;
}

static int s_lattice_cell (const s_lattice_t *lt, const s_frame_t *f, cgs_enu_t p, int *ret_i,
                           int *ret_j)
{
    cgs_enu_t d = s_sub (p, f->c);
    double fi = (s_dot (d, f->gr) - lt->a0) / lt->s, fj = (s_dot (d, f->gx) - lt->b0) / lt->s;
    if (!(fi >= 0 && fj >= 0 && fi < lt->na && fj < lt->nb))
        return -1;
    int i = (int)fi, j = (int)fj;
    *ret_i = i, *ret_j = j;
    return 0;
}

/* Place a point scatterer (σ m²) if the radar sees it. */
static int s_point (im_sar_t *self, const s_frame_t *f, const s_lattice_t *lt,
                    const cgs_terrain_t *t, cgs_enu_t p, cgs_enu_t vel, double sigma)
{
    int i, j;
    if (s_lattice_cell (lt, f, p, &i, &j) == 0) {
        if (!s_seen (f, p, self->fhz[(size_t)j * lt->na + i]))
            return 0;
    } else if (t && !cgs_terrain_los (t, f->r0, s_add (p, s_v (0, 0, 0.05)))) {
        return 0;
    }
    double a, b;
    if (!s_place (f, p, vel, &a, &b))
        return 0;
    const s_plan_t *pl = &self->pl;
    double x = (b + pl->len / 2 - pl->d_o / 2) / pl->d_g;
    double y = (pl->len / 2 - pl->d_o / 2 - a) / pl->d_g;
    return s_push (self, x, y, sqrt (sigma));
}

static int s_grow_lattice (im_sar_t *self, size_t n)
{
    if (n <= self->capf)
        return 0;
    float **arr[4] = {&self->fz, &self->fcan, &self->fveh, &self->fhz};
    for (int k = 0; k < 4; k++) {
        float *q = realloc (*arr[k], n * sizeof *q);
        if (!q)
            return -ENOMEM;
        *arr[k] = q;
    }
    self->capf = n;
    return 0;
}

/* The lattice over the grid's ground footprint plus the layover margins. */
static void s_lattice (const im_sar_t *self, const s_frame_t *f, const cgs_terrain_t *t,
                       s_lattice_t *ret)
{
    const s_plan_t *pl = &self->pl;
    double h = pl->len / 2;
    double amin = INFINITY, amax = -INFINITY, bmin = INFINITY, bmax = -INFINITY;
    for (int k = 0; k < 4; k++) {
        double a = (k & 1) ? h : -h, b = (k & 2) ? h : -h;
        cgs_enu_t p = s_add (f->c, s_add (s_mul (f->er, a), s_mul (f->ex, b))), g;
        cgs_enu_t q = s_sub (p, f->r0);
        if (f->geometry == IM_SAR_GROUND)
            g = p;
        else if (!s_rd_at_height (f, s_len (q), s_dot (q, f->vhat), f->c.u_m, &g))
            g = p;
        cgs_enu_t d = s_sub (g, f->c);
        double ga = s_dot (d, f->gr), gb = s_dot (d, f->gx);
        amin = fmin (amin, ga), amax = fmax (amax, ga);
        bmin = fmin (bmin, gb), bmax = fmax (bmax, gb);
    }
    // Heights about: a coarse look for the layover margins.
    double zlo = 0, zhi = 0;
    if (t) {
        zlo = INFINITY, zhi = -INFINITY;
        double ea = (amax - amin) * 0.2, eb = (bmax - bmin) * 0.2;
        for (int u = 0; u <= 24; u++)
            for (int w = 0; w <= 24; w++) {
                cgs_enu_t g = s_ground (f, amin - ea + (amax - amin + 2 * ea) * u / 24.0,
                                        bmin - eb + (bmax - bmin + 2 * eb) * w / 24.0, 0);
                double z = cgs_terrain_height_clamped (t, g.e_m, g.n_m);
                zlo = fmin (zlo, z);
                zhi = fmax (zhi, z + cgs_terrain_canopy (t, g.e_m, g.n_m));
            }
    }
    double tp = tan (f->psi), cap = pl->len;
    amax += fmin (fmax (zhi + 3 - f->c.u_m, 0) * tp, cap) + 2 * pl->d_o;
    amin -= fmin (fmax (f->c.u_m - zlo, 0) * tp, cap) + 2 * pl->d_o;
    bmin -= 2 * pl->d_o, bmax += 2 * pl->d_o;
    s_lattice_t lt = {.s = pl->d_o / 2};
    lt.na = (int)ceil ((amax - amin) / lt.s), lt.nb = (int)ceil ((bmax - bmin) / lt.s);
    lt.a0 = amin, lt.b0 = bmin;
    *ret = lt;
}

/* Woods: the crown's top S_CROWN_M metres scatter and let the radar in;
 * below that the canopy is opaque (it hides the ground and casts shadow). */
#define S_CROWN_M 3.0
static double s_opaque (double canopy)
{
    return canopy > S_CROWN_M ? canopy - S_CROWN_M : 0;
}

/* Heights, canopy, vehicle boxes and the horizon sweep over the lattice. */
static int s_terrain_pass (im_sar_t *self, const s_frame_t *f, const s_lattice_t *lt,
                           const im_sar_scene_t *sc)
{
    const cgs_terrain_t *t = sc->terrain;
    size_t n = (size_t)lt->na * lt->nb;
    if (s_grow_lattice (self, n) < 0)
        return -ENOMEM;
    bool woods = t && cgs_terrain_vegetated_fraction (t) > 0;
    for (int j = 0; j < lt->nb; j++)
        for (int i = 0; i < lt->na; i++) {
            cgs_enu_t g = s_ground (f, lt->a0 + (i + 0.5) * lt->s, lt->b0 + (j + 0.5) * lt->s, 0);
            size_t k = (size_t)j * lt->na + i;
            self->fz[k] = (float)s_height (t, g.e_m, g.n_m);
            self->fcan[k] = woods ? (float)cgs_terrain_canopy (t, g.e_m, g.n_m) : 0.0f;
            self->fveh[k] = 0;
        }
    // Vehicle boxes.
    for (size_t e = 0; e < sc->nents; e++) {
        s_body_t bd;
        const im_entity_t *en = &sc->ents[e];
        if (!s_body (en->kind, &bd) || !s_finite (en->position))
            continue;
        double hd = en->heading_deg * S_DEG;
        cgs_enu_t fw = s_v (sin (hd), cos (hd), 0), rt = s_v (cos (hd), -sin (hd), 0);
        cgs_enu_t d = s_sub (en->position, f->c);
        double ac = s_dot (d, f->gr), bc = s_dot (d, f->gx), rad = s_hyp (bd.len, bd.width) / 2;
        if (!(fabs (ac) < 1e6 && fabs (bc) < 1e6))
            continue; // far off the chip (and clear of int overflow)
        int i0 = (int)floor ((ac - rad - lt->a0) / lt->s),
            i1 = (int)ceil ((ac + rad - lt->a0) / lt->s);
        int j0 = (int)floor ((bc - rad - lt->b0) / lt->s),
            j1 = (int)ceil ((bc + rad - lt->b0) / lt->s);
        for (int j = j0 < 0 ? 0 : j0; j <= j1 && j < lt->nb; j++)
            for (int i = i0 < 0 ? 0 : i0; i <= i1 && i < lt->na; i++) {
                double da = lt->a0 + (i + 0.5) * lt->s - ac, db = lt->b0 + (j + 0.5) * lt->s - bc;
                cgs_enu_t off = s_add (s_mul (f->gr, da), s_mul (f->gx, db));
                if (fabs (s_dot (off, fw)) <= bd.len / 2 &&
                    fabs (s_dot (off, rt)) <= bd.width / 2) {
                    size_t k = (size_t)j * lt->na + i;
                    self->fveh[k] = fmaxf (self->fveh[k], (float)bd.height);
                }
            }
    }
    // The sweep: fhz holds the lowest tan(depression) of anything nearer.
    double step = t ? fmax (cgs_terrain_resolution (t) / 2, lt->s) : 0;
    for (int j = 0; j < lt->nb; j++) {
        cgs_enu_t g0 = s_ground (f, lt->a0, lt->b0 + (j + 0.5) * lt->s, 0);
        double hz = s_outer_horizon (t, f, g0, step);
        for (int i = 0; i < lt->na; i++) {
            size_t k = (size_t)j * lt->na + i;
            self->fhz[k] = (float)fmin (hz, 1e30);
            cgs_enu_t g = s_ground (f, lt->a0 + (i + 0.5) * lt->s, lt->b0 + (j + 0.5) * lt->s, 0);
            double dist = s_hyp (g.e_m - f->r0.e_m, g.n_m - f->r0.n_m);
            double top = self->fz[k] + fmax (s_opaque (self->fcan[k]), self->fveh[k]);
            double tn = (f->r0.u_m - top) / dist;
            if (tn < hz)
                hz = tn;
        }
    }
    return 0;
}

/* Ground and woods scatterers. */
static int s_clutter (im_sar_t *self, const s_frame_t *f, const s_lattice_t *lt,
                      const s_filter_t *fl)
{
    const s_plan_t *pl = &self->pl;
    const im_sar_params_t *p = &self->p;
    double gg = pow (10, p->ground_gamma_db / 10), gw = pow (10, p->woods_gamma_db / 10);
    double s = lt->s, area = s * s;
    bool speckle = p->speckle;
    double geo = f->geometry == IM_SAR_SLANT ? sqrt (cos (f->psi)) : 1.0;
    cgs_enu_t still = {0, 0, 0};
    for (int j = 0; j < lt->nb; j++)
        for (int i = 0; i < lt->na; i++) {
            size_t k = (size_t)j * lt->na + i;
            if (self->fveh[k] > 0)
                continue; // under a vehicle
            // The local slope, by differences across the neighbours.
            int i0 = i > 0 ? i - 1 : i, i1 = i + 1 < lt->na ? i + 1 : i;
            int j0 = j > 0 ? j - 1 : j, j1 = j + 1 < lt->nb ? j + 1 : j;
            const float *z_ = self->fz;
            double za = i1 > i0 ? (z_[(size_t)j * lt->na + i1] - z_[(size_t)j * lt->na + i0]) /
                                      ((i1 - i0) * s)
                                : 0;
            double zb = j1 > j0 ? (z_[(size_t)j1 * lt->na + i] - z_[(size_t)j0 * lt->na + i]) /
                                      ((j1 - j0) * s)
                                : 0;
            double da = 0, db = 0; // jitter within the facet
            if (speckle) {
                da = (cgs_uniform01 (&self->rng) - 0.5) * s;
                db = (cgs_uniform01 (&self->rng) - 0.5) * s;
            }
            double a = lt->a0 + (i + 0.5) * s + da, b = lt->b0 + (j + 0.5) * s + db;
            double z = self->fz[k] + za * da + zb * db;
            double can = self->fcan[k];
            int parts = can > 0 ? 2 : 1;
            for (int m = 0; m < parts; m++) {
                double zz = z, sigma;
                if (can > 0) // in the crown
                    zz += can - fmin (can, S_CROWN_M) *
                                    (speckle ? cgs_uniform01 (&self->rng) : 0.25 + 0.5 * m);
                cgs_enu_t pt = s_ground (f, a, b, zz);
                if (!s_seen (f, pt, self->fhz[k]))
                    continue;
                cgs_enu_t to = s_unit (s_sub (f->r0, pt));
                double nz = 1;
                if (can > 0) {
                    sigma = gw * fmax (to.u_m, 0) * area / 2;
                } else {
                    cgs_enu_t nrm =
                        s_v (-za * f->gr.e_m - zb * f->gx.e_m, -za * f->gr.n_m - zb * f->gx.n_m, 1);
                    double nl = s_len (nrm);
                    nz = 1 / nl;
                    sigma = gg * fmax (s_dot (nrm, to) / nl, 0) * area / nz;
                }
                double pa, pb;
                if (!(sigma > 0) || !s_place (f, pt, still, &pa, &pb))
                    continue;
                double x = (pb + pl->len / 2 - pl->d_o / 2) / pl->d_g;
                double y = (pl->len / 2 - pl->d_o / 2 - pa) / pl->d_g;
                double amp = speckle ? sqrt (sigma) : sqrt (sigma * nz) * s * fl->coh * geo;
                if (s_push (self, x, y, amp) < 0)
                    return -ENOMEM;
            }
        }
    return 0;
}

/* Vehicles and the scene's extra points. */
static int s_targets (im_sar_t *self, const s_frame_t *f, const s_lattice_t *lt,
                      const im_sar_scene_t *sc)
{
    for (size_t e = 0; e < sc->nents; e++) {
        s_body_t bd;
        const im_entity_t *en = &sc->ents[e];
        if (!s_body (en->kind, &bd) || !s_finite (en->position))
            continue;
        double hd = en->heading_deg * S_DEG, wsum = 0;
        cgs_enu_t fw = s_v (sin (hd), cos (hd), 0), rt = s_v (cos (hd), -sin (hd), 0);
        cgs_enu_t vel = s_mul (fw, isfinite (en->speed_mps) ? en->speed_mps : 0);
        for (size_t k = 0; k < bd.n; k++)
            wsum += bd.pts[k].w;
        for (size_t k = 0; k < bd.n; k++) {
            const s_bodypt_t *b = &bd.pts[k];
            cgs_enu_t pt = s_add (
                en->position, s_add (s_add (s_mul (fw, b->x), s_mul (rt, b->y)), s_v (0, 0, b->z)));
            double sigma = self->p.vehicle_rcs_m2 * bd.rcs_share * b->w / wsum;
            if (s_point (self, f, lt, sc->terrain, pt, vel, sigma) < 0)
                return -ENOMEM;
        }
    }
    for (size_t k = 0; k < sc->npoints; k++) {
        const im_sar_point_t *q = &sc->points[k];
        if (!s_finite (q->position) || !s_finite (q->velocity) || !(q->rcs_m2 > 0))
            continue;
        if (s_point (self, f, lt, sc->terrain, q->position, q->velocity, q->rcs_m2) < 0)
            return -ENOMEM;
    }
    return 0;
}

/* ---- one look -------------------------------------------------------------------- */

static void s_spread (im_sar_t *self)
{
    const int n = self->pl.n_g;
    fftw_complex *g = self->g;
    memset (g, 0, (size_t)n * n * sizeof *g);
    bool speckle = self->p.speckle;
    uint64_t bits = 0;
    int left = 0;
    for (size_t s = 0; s < self->nsc; s++) {
        const s_scat_t *q = &self->sc[s];
        double complex a = q->amp;
        if (speckle) {
            if (left == 0)
                bits = cgs_splitmix64 (&self->rng), left = 5;
            a *= self->phase[bits & (S_NPHASE - 1)];
            bits >>= 12, left--;
        }
        int ix[S_KW], iy[S_KW];
        float wx[S_KW], wy[S_KW];
        int x0 = (int)ceil (q->x - S_KW / 2.0), y0 = (int)ceil (q->y - S_KW / 2.0);
        for (int k = 0; k < S_KW; k++) {
            double fx = (x0 + k - q->x + S_KW / 2.0) * S_KTAB,
                   fy = (y0 + k - q->y + S_KW / 2.0) * S_KTAB;
            int kx = (int)fx, ky = (int)fy;
            double tx = fx - kx, ty = fy - ky;
            wx[k] = (float)(self->ktab[kx] * (1 - tx) + self->ktab[kx + 1] * tx);
            wy[k] = (float)(self->ktab[ky] * (1 - ty) + self->ktab[ky + 1] * ty);
            ix[k] = ((x0 + k) % n + n) % n;
            iy[k] = ((y0 + k) % n + n) % n;
        }
        for (int ky = 0; ky < S_KW; ky++) {
            fftw_complex *row = g + (size_t)iy[ky] * n;
            double complex ay = a * wy[ky];
            for (int kx = 0; kx < S_KW; kx++)
                row[ix[kx]] += ay * wx[kx];
        }
    }
}

/* Filter the spread grid's spectrum and fold it onto the output grid, with noise. */
static void s_fold (im_sar_t *self, const s_frame_t *f, const s_filter_t *fl, double noise)
{
    const s_plan_t *pl = &self->pl;
    const int ng = pl->n_g, no = pl->n_out;
    memset (self->o, 0, (size_t)no * no * sizeof *self->o);
    int ny = (int)ceil (fl->ka_max * pl->len) + 1, nx = (int)ceil (fl->kb_max * pl->len) + 1;
    double nsd = sqrt (noise * pl->len * pl->len / 2);
    for (int ky = -ny; ky <= ny; ky++) {
        int gy = (ky % ng + ng) % ng, oy = (ky % no + no) % no;
        for (int kx = -nx; kx <= nx; kx++) {
            double w = s_weight (self, f, ky, kx);
            if (w == 0)
                continue;
            int gx = (kx % ng + ng) % ng, ox = (kx % no + no) % no;
            double complex v = self->g[(size_t)gy * ng + gx] * self->deconv[gx] * self->deconv[gy];
            if (nsd > 0)
                v += nsd * (s_gauss (&self->rng) + I * s_gauss (&self->rng));
            self->o[(size_t)oy * no + ox] += fl->sn * w * v;
        }
    }
}

/* ---- the chip -------------------------------------------------------------------- */

/* The configured plan widened w times: the same grids (so the same FFTW
 * plans and cost), every length w times longer, the spectral support w times
 * narrower (the resolutions w times coarser). */
static void s_plan_widened (const im_sar_t *self, double w, s_plan_t *ret)
{
    s_plan_t pl = self->pl0;
    pl.k_u /= w, pl.k_v /= w;
    pl.d *= w, pl.d_o *= w, pl.d_g *= w, pl.len *= w;
    *ret = pl;
}

static double s_widen_of (const im_sar_geom_t *g)
{
    return isfinite (g->widen) && g->widen > 1 ? fmin (g->widen, IM_SAR_WIDEN_MAX) : 1.0;
}

/* The geometry of a chip collected over frame f with plan pl (widened w). */
static void s_chip_of (const im_sar_t *self, const s_plan_t *pl, double w, const s_frame_t *pf,
                       im_sar_chip_t *ret)
{
    const im_sar_params_t *p = &self->p;
    const s_frame_t f = *pf;
    const int size = p->size_px;
    // The chip's geometry.
    im_sar_chip_t c = {
        .geometry = p->geometry,
        .size_px = size,
        .pixel_m = pl->d,
        .radar = f.r0,
        .radar_vel = f.v,
        .center = f.c,
        .los = f.l0,
        .range_dir = f.er,
        .cross_dir = f.ex,
        .slant_range_m = f.r_0,
        .grazing_deg = f.psi / S_DEG,
        .aperture_s = p->integration_deg / w * S_DEG * f.r_0 / f.vperp,
        .widen = w,
    };
    double vs = s_dot (f.vhat, f.l0);
    c.squint_deg = asin (fmax (-1, fmin (1, vs))) / S_DEG;
    double wrel = im_sar_window_width (p->window);
    double rr = wrel / (2 * pl->k_u), rx = wrel / (2 * pl->k_v);
    c.range_res_m = rr / fabs (f.m11);
    c.cross_res_m = rx / fabs (f.m22);
    static const double cx[4] = {0, 0, 1, 1}, cy[4] = {1, 0, 0, 1};
    for (int k = 0; k < 4; k++) {
        double a, b;
        s_px_to_ab (&c, cx[k] * size, cy[k] * size, &a, &b);
        cgs_enu_t pp = s_add (f.c, s_add (s_mul (f.er, a), s_mul (f.ex, b))), gnd = pp;
        cgs_enu_t qq = s_sub (pp, f.r0);
        if (f.geometry == IM_SAR_SLANT)
            s_rd_at_height (&f, s_len (qq), s_dot (qq, f.vhat), f.c.u_m, &gnd);
        c.corners[k] = gnd;
    }
    *ret = c;
}

const im_sar_params_t *im_sar_params (const im_sar_t *self)
{
    return &self->p;
}

int im_sar_plan (const im_sar_t *self, const im_sar_geom_t *g, im_sar_chip_t *ret_chip)
{
    s_frame_t f;
    int rc = s_frame (g->radar, g->radar_vel, g->center, self->p.geometry, &f);
    if (rc < 0)
        return rc;
    double w = s_widen_of (g);
    s_plan_t pl;
    s_plan_widened (self, w, &pl);
    s_chip_of (self, &pl, w, &f, ret_chip);
    return 0;
}

int im_sar_image (im_sar_t *self, const im_sar_geom_t *g, const im_sar_scene_t *scene,
                  im_sar_chip_t *ret_chip)
{
    assert (self && g && scene);
    if ((scene->nents && !scene->ents) || (scene->npoints && !scene->points))
        return -EINVAL;
    const im_sar_params_t *p = &self->p;
    double w = s_widen_of (g);
    s_plan_widened (self, w, &self->pl);
    const s_plan_t *pl = &self->pl;
    s_frame_t f;
    int rc = s_frame (g->radar, g->radar_vel, g->center, p->geometry, &f);
    if (rc < 0)
        return rc;
    s_filter_t fl;
    s_filter (self, &f, &fl);
    double cap = 1.0 / (2 * pl->d_g);
    if (fl.ka_max * S_SIGMA_MIN > cap || fl.kb_max * S_SIGMA_MIN > cap)
        return -EDOM; // the squinted support does not fit the spreading grid
    s_lattice_t lt;
    s_lattice (self, &f, scene->terrain, &lt);
    self->nsc = 0;
    if ((rc = s_terrain_pass (self, &f, &lt, scene)) < 0)
        return rc;
    if (!scene->no_clutter && (rc = s_clutter (self, &f, &lt, &fl)) < 0)
        return rc;
    if ((rc = s_targets (self, &f, &lt, scene)) < 0)
        return rc;
    // The looks.
    const int size = p->size_px, q = pl->q, no = pl->n_out;
    size_t px = (size_t)size * size;
    memset (self->acc, 0, px * sizeof *self->acc);
    double noise = scene->no_clutter ? 0 : pow (10, p->nesz_db / 10);
    for (int look = 0; look < p->looks; look++) {
        s_spread (self);
        fftw_execute (self->fwd);
        s_fold (self, &f, &fl, noise);
        fftw_execute (self->inv);
        for (int y = 0; y < size * q; y++) {
            const fftw_complex *row = self->o + (size_t)(y + pl->margin) * no + pl->margin;
            double *acc = self->acc + (size_t)(y / q) * size;
            for (int x = 0; x < size * q; x++) {
                double re = creal (row[x]), im = cimag (row[x]);
                acc[x / q] += re * re + im * im;
                if (q == 1 && look == p->looks - 1) {
                    self->slc[2 * ((size_t)y * size + x)] = re;
                    self->slc[2 * ((size_t)y * size + x) + 1] = im;
                }
            }
        }
    }
    double norm = 1.0 / ((double)p->looks * q * q);
    double lo = p->display_max_db - p->dynamic_range_db;
    for (size_t k = 0; k < px; k++) {
        double v = self->acc[k] * norm;
        self->inten[k] = v;
        double db = v > 0 ? 10 * log10 (v) : -1e9;
        double gl = 255 * (db - lo) / p->dynamic_range_db;
        self->grey[k] = (uint8_t)(gl <= 0 ? 0 : gl >= 255 ? 255 : lrint (gl));
    }
    im_sar_chip_t c;
    s_chip_of (self, pl, w, &f, &c);
    c.scatterers = self->nsc;
    self->chip = c;
    self->have_chip = true;
    if (ret_chip)
        *ret_chip = c;
    return 0;
}

const im_sar_chip_t *im_sar_chip (const im_sar_t *self)
{
    return self->have_chip ? &self->chip : NULL;
}
int im_sar_size (const im_sar_t *self)
{
    return self->p.size_px;
}
const double *im_sar_intensity (const im_sar_t *self)
{
    return self->inten;
}
const uint8_t *im_sar_grey (const im_sar_t *self)
{
    return self->grey;
}
const double *im_sar_slc (const im_sar_t *self)
{
    return self->slc;
}

/* The chip's square in a width × height frame: scale and offset. */
static void s_layout (int size, int width, int height, double *ret_scale, double *ret_ox,
                      double *ret_oy)
{
    double sc = fmin ((double)width, (double)height) / size;
    *ret_scale = sc;
    *ret_ox = (width - size * sc) / 2;
    *ret_oy = (height - size * sc) / 2;
}

void im_sar_to_rgba (const im_sar_t *self, uint8_t *rgba, int width, int height)
{
    const int n = self->p.size_px;
    double sc, ox, oy;
    s_layout (n, width, height, &sc, &ox, &oy);
    for (int y = 0; y < height; y++)
        for (int x = 0; x < width; x++) {
            uint8_t *o = rgba + 4 * ((size_t)y * width + x);
            double cx = (x + 0.5 - ox) / sc, cy = (y + 0.5 - oy) / sc;
            uint8_t v = 0;
            if (cx >= 0 && cx < n && cy >= 0 && cy < n) {
                double fx = fmin (fmax (cx - 0.5, 0), n - 1), fy = fmin (fmax (cy - 0.5, 0), n - 1);
                int x0 = (int)fx, y0 = (int)fy;
                int x1 = x0 + 1 < n ? x0 + 1 : x0, y1 = y0 + 1 < n ? y0 + 1 : y0;
                double tx = fx - x0, ty = fy - y0;
                const uint8_t *gr = self->grey;
                double t =
                    (gr[(size_t)y0 * n + x0] * (1 - tx) + gr[(size_t)y0 * n + x1] * tx) * (1 - ty) +
                    (gr[(size_t)y1 * n + x0] * (1 - tx) + gr[(size_t)y1 * n + x1] * tx) * ty;
                v = (uint8_t)lrint (t);
            }
            o[0] = o[1] = o[2] = v;
            o[3] = 255;
        }
}

bool im_sar_chip_to_px (const im_sar_chip_t *c, cgs_enu_t p, cgs_enu_t vel, double *ret_x,
                        double *ret_y)
{
    s_frame_t f;
    double a, b;
    if (s_frame_of_chip (c, &f) < 0 || !s_finite (p) || !s_finite (vel) ||
        !s_place (&f, p, vel, &a, &b))
        return false;
    double x = c->size_px / 2.0 + b / c->pixel_m, y = c->size_px / 2.0 - a / c->pixel_m;
    if (!(x >= 0 && x < c->size_px && y >= 0 && y < c->size_px))
        return false;
    *ret_x = x, *ret_y = y;
    return true;
}

bool im_sar_apparent (const im_sar_chip_t *c, cgs_enu_t p, cgs_enu_t vel,
                      const cgs_terrain_t *terrain, cgs_enu_t *ret)
{
    s_frame_t f;
    double a, b;
    if (s_frame_of_chip (c, &f) < 0 || !s_finite (p) || !s_finite (vel) ||
        !s_place (&f, p, vel, &a, &b))
        return false;
    double x = c->size_px / 2.0 + b / c->pixel_m, y = c->size_px / 2.0 - a / c->pixel_m;
    return im_sar_chip_px_to_ground (c, x, y, terrain, ret);
}

bool im_sar_ground_to_px (const im_sar_chip_t *c, int width, int height, cgs_enu_t p, cgs_enu_t vel,
                          double *ret_x, double *ret_y)
{
    double x, y, sc, ox, oy;
    if (width < 1 || height < 1 || !im_sar_chip_to_px (c, p, vel, &x, &y))
        return false;
    s_layout (c->size_px, width, height, &sc, &ox, &oy);
    *ret_x = ox + x * sc;
    *ret_y = oy + y * sc;
    return true;
}

void im_sar_chip_px_to_plane (const im_sar_chip_t *c, double x, double y, cgs_enu_t *ret)
{
    double a, b;
    s_px_to_ab (c, x, y, &a, &b);
    *ret = s_add (c->center, s_add (s_mul (c->range_dir, a), s_mul (c->cross_dir, b)));
}

bool im_sar_chip_px_to_ground (const im_sar_chip_t *c, double x, double y,
                               const cgs_terrain_t *terrain, cgs_enu_t *ret)
{
    s_frame_t f;
    if (s_frame_of_chip (c, &f) < 0 || !isfinite (x) || !isfinite (y))
        return false;
    cgs_enu_t p;
    im_sar_chip_px_to_plane (c, x, y, &p);
    cgs_enu_t q = s_sub (p, f.r0);
    double r = s_len (q), d = s_dot (q, f.vhat), z = terrain ? f.c.u_m : 0;
    cgs_enu_t g;
    for (int it = 0; it < (terrain ? 12 : 1); it++) {
        if (!s_rd_at_height (&f, r, d, z, &g))
            return false;
        if (terrain)
            z = cgs_terrain_height_clamped (terrain, g.e_m, g.n_m);
    }
    if (terrain && !s_rd_at_height (&f, r, d, z, &g))
        return false;
    *ret = g;
    return true;
}
