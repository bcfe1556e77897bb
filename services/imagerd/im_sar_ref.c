/* im_sar_ref — phase history and backprojection (see im_sar_ref.h). Written
 * apart from im_sar.c on purpose: only the window function is shared. */
#include "im_sar_ref.h"
#include "cgs_util.h"

#include <complex.h>
#include <errno.h>
#include <math.h>
#include <stdlib.h>

#define S_C   299792458.0
#define S_MAX 4096

struct im_sar_ref {
    int np, nf;         // pulses, frequencies
    double f0, df;      // first frequency, spacing
    double fc;          // centre frequency
    double dtheta;      // angle between pulses, radians
    cgs_enu_t *ant;     // antenna per pulse
    double *t;          // time per pulse
    double complex *s;  // phase history, np × nf
    double complex *d;  // weighted by the windows
    double wsum2;       // Σ W²
    cgs_enu_t l0, chat; // line of sight, slant cross-range (right)
};

static cgs_enu_t s_sub (cgs_enu_t a, cgs_enu_t b)
{
    return (cgs_enu_t){a.e_m - b.e_m, a.n_m - b.n_m, a.u_m - b.u_m};
}
static double s_dot (cgs_enu_t a, cgs_enu_t b)
{
    return a.e_m * b.e_m + a.n_m * b.n_m + a.u_m * b.u_m;
}
static double s_len (cgs_enu_t a)
{
    return sqrt (s_dot (a, a));
}

void im_sar_ref_destroy (im_sar_ref_t **self_p)
{
    if (!self_p || !*self_p)
        return;
    im_sar_ref_t *self = *self_p;
    free (self->ant);
    free (self->t);
    free (self->s);
    free (self->d);
    free (self);
    *self_p = NULL;
}

im_sar_ref_t *im_sar_ref_new (const im_sar_params_t *p, const im_sar_geom_t *g,
                              const im_sar_point_t *pts, size_t n, double extent_m, char *err,
                              size_t errlen)
{
    if (im_sar_params_check (p, err, errlen) < 0)
        return NULL;
    cgs_enu_t los = s_sub (g->center, g->radar);
    double r0 = s_len (los), v = s_len (g->radar_vel);
    if (!(r0 > 0 && v > 0 && extent_m > 0 && isfinite (r0 * v * extent_m))) {
        cgs_errf (err, errlen, "sar ref: bad geometry or extent");
        return NULL;
    }
    im_sar_ref_t *self = calloc (1, sizeof *self);
    if (!self) {
        cgs_errf (err, errlen, "sar ref: out of memory");
        return NULL;
    }
    cgs_enu_t l0 = {los.e_m / r0, los.n_m / r0, los.u_m / r0};
    double vl = s_dot (g->radar_vel, l0);
    cgs_enu_t vp = {g->radar_vel.e_m - vl * l0.e_m, g->radar_vel.n_m - vl * l0.n_m,
                    g->radar_vel.u_m - vl * l0.u_m};
    double vperp = s_len (vp);
    // Right of the look, horizontally: ĉ points that way.
    cgs_enu_t gx = {l0.n_m, -l0.e_m, 0};
    double sg = s_dot (vp, gx) >= 0 ? 1 : -1;
    self->l0 = l0;
    self->chat = (cgs_enu_t){sg * vp.e_m / vperp, sg * vp.n_m / vperp, sg * vp.u_m / vperp};
    // Unambiguous over 4 × extent in range and cross-range.
    double span = 4 * extent_m, theta = p->integration_deg * M_PI / 180, lambda = S_C / p->fc_hz;
    self->nf = (int)ceil (2 * p->bandwidth_hz * span / S_C);
    self->np = (int)ceil (2 * theta * span / lambda);
    if (self->nf > S_MAX || self->np > S_MAX || !(vperp > 0)) {
        cgs_errf (err, errlen, "sar ref: %d pulses x %d frequencies: too many (at most %d)",
                  self->np, self->nf, S_MAX);
        im_sar_ref_destroy (&self);
        return NULL;
    }
    self->df = p->bandwidth_hz / self->nf;
    self->f0 = p->fc_hz - p->bandwidth_hz / 2 + self->df / 2;
    self->fc = p->fc_hz;
    self->dtheta = theta / self->np;
    size_t ns = (size_t)self->np * self->nf;
    self->ant = malloc ((size_t)self->np * sizeof *self->ant);
    self->t = malloc ((size_t)self->np * sizeof *self->t);
    self->s = calloc (ns, sizeof *self->s);
    self->d = malloc (ns * sizeof *self->d);
    if (!self->ant || !self->t || !self->s || !self->d) {
        cgs_errf (err, errlen, "sar ref: out of memory");
        im_sar_ref_destroy (&self);
        return NULL;
    }
    double aperture = theta * r0 / vperp;
    for (int i = 0; i < self->np; i++) {
        double t = ((i + 0.5) / self->np - 0.5) * aperture;
        self->t[i] = t;
        self->ant[i] =
            (cgs_enu_t){g->radar.e_m + g->radar_vel.e_m * t, g->radar.n_m + g->radar_vel.n_m * t,
                        g->radar.u_m + g->radar_vel.u_m * t};
    }
    // The phase history.
    for (size_t k = 0; k < n; k++) {
        double a = sqrt (pts[k].rcs_m2);
        for (int i = 0; i < self->np; i++) {
            double t = self->t[i];
            cgs_enu_t pk = {pts[k].position.e_m + pts[k].velocity.e_m * t,
                            pts[k].position.n_m + pts[k].velocity.n_m * t,
                            pts[k].position.u_m + pts[k].velocity.u_m * t};
            double r = s_len (s_sub (pk, self->ant[i]));
            for (int j = 0; j < self->nf; j++) {
                double f = self->f0 + j * self->df;
                self->s[(size_t)i * self->nf + j] += a * cexp (-I * 4 * M_PI * f * r / S_C);
            }
        }
    }
    self->wsum2 = 0;
    for (int i = 0; i < self->np; i++) {
        double wa = im_sar_window (p->window, (i + 0.5) / self->np - 0.5);
        for (int j = 0; j < self->nf; j++) {
            double w = wa * im_sar_window (p->window, (j + 0.5) / self->nf - 0.5);
            self->d[(size_t)i * self->nf + j] = w * self->s[(size_t)i * self->nf + j];
            self->wsum2 += w * w;
        }
    }
    return self;
}

int im_sar_ref_pulses (const im_sar_ref_t *self)
{
    return self->np;
}
int im_sar_ref_freqs (const im_sar_ref_t *self)
{
    return self->nf;
}
double im_sar_ref_time (const im_sar_ref_t *self, int i)
{
    return self->t[i];
}
double im_sar_ref_freq (const im_sar_ref_t *self, int j)
{
    return self->f0 + j * self->df;
}

void im_sar_ref_sample (const im_sar_ref_t *self, int i, int j, double *ret_re, double *ret_im)
{
    double complex v = self->s[(size_t)i * self->nf + j];
    *ret_re = creal (v);
    *ret_im = cimag (v);
}

void im_sar_ref_backproject (const im_sar_ref_t *self, const im_sar_chip_t *plane,
                             const cgs_enu_t *pts, size_t n, double *ret_re_im)
{
    // The area scale: the chip plane's axes against slant range and cross-range.
    double m11 = s_dot (plane->range_dir, self->l0), m12 = s_dot (plane->cross_dir, self->l0);
    double m21 = s_dot (plane->range_dir, self->chat), m22 = s_dot (plane->cross_dir, self->chat);
    double det = fabs (m11 * m22 - m12 * m21);
    double dku = 2 * self->df / S_C, dkv = 2 * self->fc * self->dtheta / S_C;
    double scale = sqrt (dku * dkv * det / self->wsum2);
    for (size_t k = 0; k < n; k++) {
        double complex acc = 0;
        for (int i = 0; i < self->np; i++) {
            double r = s_len (s_sub (pts[k], self->ant[i]));
            double complex z = cexp (I * 4 * M_PI * self->f0 * r / S_C);
            double complex dz = cexp (I * 4 * M_PI * self->df * r / S_C);
            const double complex *d = self->d + (size_t)i * self->nf;
            double complex sum = 0;
            for (int j = 0; j < self->nf; j++) {
                sum += d[j] * z;
                z *= dz;
            }
            acc += sum;
        }
        ret_re_im[2 * k] = scale * creal (acc);
        ret_re_im[2 * k + 1] = scale * cimag (acc);
    }
}
