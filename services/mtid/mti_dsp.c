/* mti_dsp — the MTI signal processing chain of one dwell (see mti_dsp.h). */
#include "mti_dsp.h"
#include "mti_theory.h"

#include <assert.h>
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <fftw3.h>
#include <gsl/gsl_eigen.h>
#include <gsl/gsl_matrix.h>
#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>
#include <gsl/gsl_vector.h>

struct mti_dsp {
    int fft_size;  // Doppler bins
    int pulses;    // pulses per CPI
    int canceller; // pulses the canceller spans (1, 2, 3)
    int n_ref;     // CFAR reference cells
    int n_guard;   // CFAR guard cells each side
    int n_cpi, m;  // m of n
    double t_cfar; // CA-CFAR multiplier (sum convention)
    double prf_hz;
    double *window;    // fft_size coefficients
    fftw_complex *buf; // FFT in place, fft_size
    fftw_plan plan;
    gsl_rng *rng;
    /* Clutter: x = A w, A = V sqrt(L) restricted to the significant eigenvalues. */
    double clutter_sigma_hz; // spectrum A was built for (NAN: none yet)
    double *clutter_a;       // pulses x rank, row-major
    double *rho;             // clutter correlation at lags 0..pulses-1
    int clutter_rank;
    gsl_eigen_symmv_workspace *eig_ws;
    gsl_matrix *cov, *evec;
    gsl_vector *eval;
    /* Scratch for one CPI. */
    double complex *x;               // pulses
    double complex *w;               // rank
    double *power, *x_bins, *z_bins; // fft_size each
};

void mti_dsp_destroy (mti_dsp_t **self_p)
{
    assert (self_p);
    mti_dsp_t *self = *self_p;
    if (!self)
        return;
    if (self->plan)
        fftw_destroy_plan (self->plan);
    if (self->buf)
        fftw_free (self->buf);
    if (self->rng)
        gsl_rng_free (self->rng);
    if (self->eig_ws)
        gsl_eigen_symmv_free (self->eig_ws);
    if (self->cov)
        gsl_matrix_free (self->cov);
    if (self->evec)
        gsl_matrix_free (self->evec);
    if (self->eval)
        gsl_vector_free (self->eval);
    free (self->window);
    free (self->clutter_a);
    free (self->rho);
    free (self->x);
    free (self->w);
    free (self->power);
    free (self->x_bins);
    free (self->z_bins);
    free (self);
    *self_p = NULL;
}

static void s_window (mti_window_t kind, int n, double *w)
{
    for (int k = 0; k < n; k++) {
        double a = n > 1 ? 2.0 * M_PI * k / (n - 1) : 0;
        switch (kind) {
        case MTI_WINDOW_HANN:
            w[k] = 0.5 - 0.5 * cos (a);
            break;
        case MTI_WINDOW_HAMMING:
            w[k] = 0.54 - 0.46 * cos (a);
            break;
        case MTI_WINDOW_BLACKMAN:
            w[k] = 0.42 - 0.5 * cos (a) + 0.08 * cos (2 * a);
            break;
        default:
            w[k] = 1.0;
            break;
        }
    }
}

void mti_dsp_reseed (mti_dsp_t *self, uint64_t seed)
{
    gsl_rng_set (self->rng, (unsigned long)(seed ^ (seed >> 32)));
}

mti_dsp_t *mti_dsp_new (const mti_params_t *p, uint64_t seed)
{
    if (mti_params_check (p, NULL, 0) < 0)
        return NULL;
    mti_dsp_t *self = calloc (1, sizeof *self);
    if (!self)
        return NULL;
    self->fft_size = p->fft_size;
    self->canceller = (int)p->canceller;
    self->pulses = mti_params_cpi_pulses (p);
    self->n_ref = p->ref_cells;
    self->n_guard = p->guard_cells;
    self->n_cpi = p->n;
    self->m = p->m;
    self->prf_hz = p->prf_hz;
    self->t_cfar = mti_theory_cfar_t (p->pfa, p->ref_cells);
    self->clutter_sigma_hz = NAN;
    int n = self->fft_size, np = self->pulses;
    self->window = malloc (sizeof (double) * n);
    self->buf = fftw_malloc (sizeof (fftw_complex) * n);
    self->rng = gsl_rng_alloc (gsl_rng_mt19937);
    self->eig_ws = gsl_eigen_symmv_alloc (np);
    self->cov = gsl_matrix_alloc (np, np);
    self->evec = gsl_matrix_alloc (np, np);
    self->eval = gsl_vector_alloc (np);
    self->clutter_a = malloc (sizeof (double) * np * np);
    self->rho = malloc (sizeof (double) * np);
    self->x = malloc (sizeof (double complex) * np);
    self->w = malloc (sizeof (double complex) * np);
    self->power = malloc (sizeof (double) * n);
    self->x_bins = malloc (sizeof (double) * n);
    self->z_bins = malloc (sizeof (double) * n);
    if (!self->window || !self->buf || !self->rng || !self->eig_ws || !self->cov || !self->evec ||
        !self->eval || !self->clutter_a || !self->rho || !self->x || !self->w || !self->power ||
        !self->x_bins || !self->z_bins)
        goto fail;
    self->plan = fftw_plan_dft_1d (n, self->buf, self->buf, FFTW_FORWARD, FFTW_ESTIMATE);
    if (!self->plan)
        goto fail;
    s_window (p->window, n, self->window);
    mti_dsp_reseed (self, seed);
    return self;
fail:
    mti_dsp_destroy (&self);
    return NULL;
}

double mti_dsp_threshold (const mti_dsp_t *self)
{
    return self->t_cfar;
}

int mti_dsp_cpi_pulses (const mti_dsp_t *self)
{
    return self->pulses;
}

int mti_dsp_bins (const mti_dsp_t *self)
{
    return self->fft_size;
}

double mti_dsp_bin_hz (const mti_dsp_t *self, int bin)
{
    int n = self->fft_size;
    int k = bin >= n / 2 ? bin - n : bin;
    return self->prf_hz * k / n;
}

int mti_dsp_bin_of (const mti_dsp_t *self, double f_hz)
{
    int n = self->fft_size;
    double k = round (f_hz / self->prf_hz * n);
    long b = (long)fmod (k, n);
    if (b < 0)
        b += n;
    return (int)b;
}

/* Complex Gaussian of unit power. */
static inline double complex s_cgauss (gsl_rng *r)
{
    return M_SQRT1_2 * gsl_ran_gaussian_ziggurat (r, 1.0) +
           I * (M_SQRT1_2 * gsl_ran_gaussian_ziggurat (r, 1.0));
}

mti_dsp_target_t mti_dsp_draw_target (mti_dsp_t *self, mti_swerling_t model, double snr,
                                      double doppler_hz)
{
    mti_dsp_target_t t = {.amplitude = sqrt (snr > 0 ? snr : 0), .doppler_hz = doppler_hz};
    if (model == MTI_SWERLING_1 || model == MTI_SWERLING_2)
        t.amplitude = sqrt (gsl_ran_exponential (self->rng, snr > 0 ? snr : 0));
    else if (model == MTI_SWERLING_2_PULSE)
        t.pulse_to_pulse = true;
    return t;
}

int mti_dsp_set_clutter (mti_dsp_t *self, double sigma_hz)
{
    if (!(sigma_hz >= 0) || !isfinite (sigma_hz))
        return -EINVAL;
    if (sigma_hz == self->clutter_sigma_hz)
        return 0;
    int np = self->pulses;
    double s = 2.0 * M_PI * M_PI * sigma_hz * sigma_hz / (self->prf_hz * self->prf_hz);
    for (int d = 0; d < np; d++)
        self->rho[d] = exp (-s * (double)d * d);
    for (int i = 0; i < np; i++)
        for (int j = 0; j < np; j++)
            gsl_matrix_set (self->cov, i, j, self->rho[abs (i - j)]);
    if (gsl_eigen_symmv (self->cov, self->eval, self->evec, self->eig_ws) != 0)
        return -EINVAL;
    // Keep the components that carry power; the rest are rounding noise.
    double trace = np, keep = 1e-12 * trace;
    int rank = 0;
    for (int k = 0; k < np; k++) {
        double l = gsl_vector_get (self->eval, k);
        if (l <= keep)
            continue;
        double sl = sqrt (l);
        for (int i = 0; i < np; i++)
            self->clutter_a[i * np + rank] = gsl_matrix_get (self->evec, i, k) * sl;
        rank++;
    }
    self->clutter_rank = rank;
    self->clutter_sigma_hz = sigma_hz;
    return 0;
}

void mti_dsp_cell (mti_dsp_t *self, double cnr, const mti_dsp_target_t *tgt, double complex *x)
{
    int np = self->pulses;
    gsl_rng *r = self->rng;
    for (int k = 0; k < np; k++)
        x[k] = s_cgauss (r);
    if (cnr > 0 && self->clutter_rank > 0) {
        assert (!isnan (self->clutter_sigma_hz));
        int rank = self->clutter_rank;
        double g = sqrt (cnr);
        for (int j = 0; j < rank; j++)
            self->w[j] = g * s_cgauss (r);
        for (int i = 0; i < np; i++) {
            const double *a = &self->clutter_a[i * np];
            double re = 0, im = 0;
            for (int j = 0; j < rank; j++) {
                re += a[j] * creal (self->w[j]);
                im += a[j] * cimag (self->w[j]);
            }
            x[i] += re + I * im;
        }
    }
    if (tgt && tgt->amplitude > 0) {
        double phase0 = 2.0 * M_PI * gsl_rng_uniform (r);
        double dphi = 2.0 * M_PI * tgt->doppler_hz / self->prf_hz;
        for (int k = 0; k < np; k++) {
            double complex s = cexp (I * (phase0 + dphi * k));
            x[k] += tgt->pulse_to_pulse ? tgt->amplitude * s_cgauss (r) * s : tgt->amplitude * s;
        }
    }
}

void mti_dsp_filter (mti_dsp_t *self, const double complex *x, double *power)
{
    int n = self->fft_size;
    double complex *b = (double complex *)self->buf;
    for (int k = 0; k < n; k++) {
        const double complex *p = &x[k];
        double complex y;
        switch (self->canceller) {
        case 2:
            y = p[1] - p[0];
            break;
        case 3:
            y = p[2] - 2.0 * p[1] + p[0];
            break;
        default:
            y = p[0];
            break;
        }
        b[k] = self->window[k] * y;
    }
    fftw_execute (self->plan);
    for (int k = 0; k < n; k++)
        power[k] = creal (b[k]) * creal (b[k]) + cimag (b[k]) * cimag (b[k]);
}

void mti_dsp_cpi (mti_dsp_t *self, const double *cnr, const mti_dsp_target_t *tgt, double *x_bins,
                  double *z_bins)
{
    int n = self->fft_size;
    mti_dsp_cell (self, cnr[0], tgt, self->x);
    mti_dsp_filter (self, self->x, x_bins);
    memset (z_bins, 0, sizeof (double) * n);
    for (int c = 1; c <= self->n_ref; c++) {
        mti_dsp_cell (self, cnr[c], NULL, self->x);
        mti_dsp_filter (self, self->x, self->power);
        for (int k = 0; k < n; k++)
            z_bins[k] += self->power[k];
    }
}

int mti_dsp_dwell (mti_dsp_t *self, const mti_dsp_input_t *in, mti_dsp_result_t *ret)
{
    int rc = mti_dsp_set_clutter (self, in->clutter_sigma_hz);
    if (rc < 0)
        return rc;
    mti_dsp_result_t res = {.bin = -1};
    mti_dsp_target_t tgt = {0};
    bool have_tgt = in->snr > 0;
    if (have_tgt)
        tgt = mti_dsp_draw_target (self, in->swerling, in->snr, in->doppler_hz);
    int n = self->fft_size;
    for (int c = 0; c < self->n_cpi; c++) {
        // Swerling II in the interval sense: the frequency hop between
        // coherent intervals gives each its own draw.
        if (have_tgt && c > 0 && in->swerling == MTI_SWERLING_2)
            tgt = mti_dsp_draw_target (self, in->swerling, in->snr, in->doppler_hz);
        if (have_tgt && !tgt.pulse_to_pulse)
            res.fluctuation[c] = tgt.amplitude * tgt.amplitude / in->snr;
        else
            res.fluctuation[c] = 1.0;
        mti_dsp_cpi (self, in->cnr, have_tgt ? &tgt : NULL, self->x_bins, self->z_bins);
        bool crossed = false;
        for (int k = 0; k < n; k++) {
            double x = self->x_bins[k], z = self->z_bins[k];
            if (!(x > self->t_cfar * z))
                continue;
            crossed = true;
            double ratio = z > 0 ? x / (z / self->n_ref) : INFINITY;
            if (res.bin < 0 || ratio > res.ratio) {
                res.bin = k;
                res.ratio = ratio;
            }
        }
        res.crossings += crossed;
    }
    res.detected = res.crossings >= self->m;
    res.doppler_hz = res.bin >= 0 ? mti_dsp_bin_hz (self, res.bin) : 0;
    *ret = res;
    return 0;
}

int mti_dsp_strip (mti_dsp_t *self, int ncells, const double *cnr, bool *detected)
{
    int n = self->fft_size, half = self->n_ref / 2, reach = self->n_guard + half;
    if (ncells < 2 * reach + 1)
        return -EINVAL;
    double *pw = malloc (sizeof (double) * (size_t)ncells * n);
    int *cross = calloc ((size_t)ncells, sizeof (int));
    if (!pw || !cross) {
        free (pw);
        free (cross);
        return -ENOMEM;
    }
    for (int c = 0; c < self->n_cpi; c++) {
        for (int i = 0; i < ncells; i++) {
            mti_dsp_cell (self, cnr[i], NULL, self->x);
            mti_dsp_filter (self, self->x, &pw[(size_t)i * n]);
        }
        for (int i = reach; i < ncells - reach; i++) {
            bool crossed = false;
            for (int k = 0; k < n && !crossed; k++) {
                double z = 0;
                for (int j = self->n_guard + 1; j <= reach; j++)
                    z += pw[(size_t)(i - j) * n + k] + pw[(size_t)(i + j) * n + k];
                crossed = pw[(size_t)i * n + k] > self->t_cfar * z;
            }
            cross[i] += crossed;
        }
    }
    for (int i = 0; i < ncells; i++)
        detected[i] = i >= reach && i < ncells - reach && cross[i] >= self->m;
    free (pw);
    free (cross);
    return ncells - 2 * reach;
}

/* The chain's output in Doppler bin `bin` as sum_j h[j] x[j] over the
 * CPI's pulses: canceller, then window, then the DFT row of the bin. */
static void s_bin_filter (const mti_dsp_t *self, int bin, double complex *h)
{
    int n = self->fft_size;
    static const double c2[] = {-1, 1}, c3[] = {1, -2, 1}, c1[] = {1};
    const double *coef = self->canceller == 3 ? c3 : self->canceller == 2 ? c2 : c1;
    for (int j = 0; j < self->pulses; j++)
        h[j] = 0;
    for (int k = 0; k < n; k++) {
        double complex d = self->window[k] * cexp (-2.0 * M_PI * I * bin * k / n);
        for (int i = 0; i < self->canceller; i++)
            h[k + i] += d * coef[i];
    }
}

/* Replace the bin output y = h.x of white pulses x by y_new: x += h^H (y_new - y) / |h|^2
 * (the Gaussian x conditioned on its bin output). */
static void s_condition (double complex *x, const double complex *h, int np, double hh,
                         double complex y, double complex y_new)
{
    for (int j = 0; j < np; j++)
        x[j] += conj (h[j]) * (y_new - y) / hh;
}

static double complex s_dot (const double complex *h, const double complex *x, int np)
{
    double complex y = 0;
    for (int j = 0; j < np; j++)
        y += h[j] * x[j];
    return y;
}

double mti_dsp_any_bin_probability (mti_dsp_t *self, int samples)
{
    int n = self->fft_size, np = self->pulses;
    double complex h[MTI_FFT_MAX + 2];
    double t = self->t_cfar, shrink = 1.0 / sqrt (1.0 + t), sum = 0;
    for (int s = 0; s < samples; s++) {
        int b = (int)(gsl_rng_uniform (self->rng) * n);
        s_bin_filter (self, b, h);
        double hh = 0;
        for (int j = 0; j < np; j++)
            hh += creal (h[j] * conj (h[j]));
        if (!(hh > 0)) {
            sum += 1.0; // a bin the chain zeroes: count it as independent
            continue;
        }
        // Given that bin b crosses (X_b > T Z_b, X_b exponential of mean hh),
        // the reference sum is tilted by exp(-T Z_b / hh): each reference
        // cell's bin-b output is complex Gaussian of power hh / (1 + T).
        memset (self->z_bins, 0, sizeof (double) * n);
        for (int c = 0; c < self->n_ref; c++) {
            for (int j = 0; j < np; j++)
                self->x[j] = s_cgauss (self->rng);
            double complex y = s_dot (h, self->x, np);
            s_condition (self->x, h, np, hh, y, y * shrink);
            mti_dsp_filter (self, self->x, self->power);
            for (int k = 0; k < n; k++)
                self->z_bins[k] += self->power[k];
        }
        // The cell under test: X_b = T Z_b + an exponential exceedance
        // (memoryless), at a uniform phase.
        for (int j = 0; j < np; j++)
            self->x[j] = s_cgauss (self->rng);
        double complex y = s_dot (h, self->x, np);
        double mag2 = t * self->z_bins[b] + gsl_ran_exponential (self->rng, hh);
        s_condition (self->x, h, np, hh, y,
                     sqrt (mag2) * cexp (2.0 * M_PI * I * gsl_rng_uniform (self->rng)));
        mti_dsp_filter (self, self->x, self->x_bins);
        int crossings = 0;
        for (int k = 0; k < n; k++)
            crossings += self->x_bins[k] > t * self->z_bins[k];
        // Bin b crosses by construction (up to rounding at the threshold).
        sum += 1.0 / (crossings > 0 ? crossings : 1);
    }
    double pfa = pow (1.0 + t, -self->n_ref);
    return pfa * n * (sum / samples);
}

void mti_dsp_bin_response (const mti_dsp_t *self, int bin, double f_hz, bool pulse_to_pulse,
                           double *ret_noise, double *ret_clutter, double *ret_signal)
{
    int np = self->pulses;
    double complex h[MTI_FFT_MAX + 2];
    s_bin_filter (self, bin, h);
    double noise = 0, clutter = 0;
    double complex sig = 0;
    bool have_clutter = !isnan (self->clutter_sigma_hz);
    for (int j = 0; j < np; j++) {
        noise += creal (h[j] * conj (h[j]));
        sig += h[j] * cexp (2.0 * M_PI * I * f_hz * j / self->prf_hz);
        if (have_clutter)
            for (int l = 0; l < np; l++)
                clutter += creal (h[j] * conj (h[l])) * self->rho[abs (j - l)];
    }
    *ret_noise = noise;
    *ret_clutter = clutter;
    *ret_signal = pulse_to_pulse ? noise : creal (sig * conj (sig));
}

double mti_dsp_uniform (mti_dsp_t *self)
{
    return gsl_rng_uniform (self->rng);
}

double mti_dsp_gaussian (mti_dsp_t *self)
{
    return gsl_ran_gaussian_ziggurat (self->rng, 1.0);
}

unsigned int mti_dsp_binomial (mti_dsp_t *self, double p, unsigned int n)
{
    return gsl_ran_binomial (self->rng, p, n);
}

double mti_dsp_gamma (mti_dsp_t *self, double k)
{
    return gsl_ran_gamma (self->rng, k, 1.0);
}
