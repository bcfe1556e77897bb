/* mti_dsp — the MTI signal processing chain of one dwell on one target's
 * range cell and its CFAR reference cells, simulated pulse by pulse.
 *
 * Each coherent processing interval (CPI) spans P = fft_size + canceller - 1
 * pulses. For every cell it generates complex baseband samples: receiver
 * noise (complex white Gaussian, power 1, the unit of every power here), ground
 * clutter (complex Gaussian with a Gaussian Doppler spectrum of standard
 * deviation sigma_hz about zero Doppler — the radar keeps its mainbeam
 * clutter centred at zero — and power cnr, the clutter-to-noise ratio), and in
 * the cell under test the target: a point reflector with its Doppler,
 * constant, Swerling I (amplitude drawn once per dwell) or Swerling II
 * (drawn pulse to pulse). The clutter's P x P covariance exp(-2 pi^2
 * sigma^2 (i-j)^2 / prf^2) is decomposed once per spectrum (GSL's symmetric
 * eigensolver) so each cell's clutter is V sqrt(L) w with w white: exact for
 * any spread, however narrow. The radar changes frequency between CPIs, so
 * clutter, noise and the target's phase are independent from one CPI to the
 * next: for noise, clutter, a constant or a Swerling II target m-of-n is a
 * binomial test. A Swerling I target's amplitude is held over the whole
 * dwell (scan to scan, as Swerling defined it), so its CPIs are correlated
 * and its m-of-n Pd is not the binomial sum of one CPI's.
 *
 * Then per cell: the clutter canceller (two- or three-pulse), the window, the
 * Doppler FFT of fft_size points (FFTW) and the square law. Cell-averaging
 * CFAR in each Doppler bin of the cell under test (sum convention: X > T *
 * sum of the N reference cells' powers in that bin, T = Pfa^(-1/N) - 1). A CPI
 * crosses when any bin crosses; the dwell detects when m of its n CPIs cross.
 *
 * Pure: no globals (FFTW's planner aside), no logging; randomness from the
 * GSL generator in the object. Not thread-safe (FFTW planning). */
#ifndef MTI_DSP_H
#define MTI_DSP_H

#include "mti_params.h"

#include <complex.h>
#include <stdbool.h>
#include <stdint.h>

typedef struct mti_dsp mti_dsp_t;

/* A target as one CPI sees it. */
typedef struct {
    double amplitude;    // sqrt of per-pulse SNR (constant, or this dwell's or CPI's draw)
    bool pulse_to_pulse; // Swerling II pulse to pulse: each pulse complex Gaussian of power
                         // amplitude^2
    double doppler_hz;   // relative to the clutter centre
} mti_dsp_target_t;

/* What the dwell sees. */
typedef struct {
    double snr;              // target's mean per-pulse SNR (power ratio); 0: no target
    double doppler_hz;       // target Doppler relative to the clutter centre
    mti_swerling_t swerling; // the target's fluctuation model
    double clutter_sigma_hz; // clutter spectrum standard deviation
    const double *cnr; // per-pulse clutter-to-noise: [0] the target's cell, [1..ref] references
} mti_dsp_input_t;

typedef struct {
    bool detected;     // m of n CPIs crossed
    int crossings;     // CPIs that crossed
    int bin;           // Doppler bin of the strongest crossing, -1 when none
    double ratio;      // X / (sum Z / N) of that crossing: the estimated signal-to-interference
    double doppler_hz; // centre of that bin, in [-prf/2, prf/2)
    double fluctuation[MTI_N_MAX]; // each interval's target power over its mean (1 for a
                                   // constant or pulse-to-pulse target)
} mti_dsp_result_t;

/* Chain for these parameters, generator seeded with seed; NULL on bad
 * parameters or no memory. */
mti_dsp_t *mti_dsp_new (const mti_params_t *p, uint64_t seed);
/* Free; accepts NULL; sets *self_p to NULL. */
void mti_dsp_destroy (mti_dsp_t **self_p);
/* Restart the noise generator from seed, as mti_dsp_new does. */
void mti_dsp_reseed (mti_dsp_t *self, uint64_t seed);

/* The CA-CFAR multiplier T in use. */
double mti_dsp_threshold (const mti_dsp_t *self);
/* Pulses per CPI, and Doppler bins (the FFT size). */
int mti_dsp_cpi_pulses (const mti_dsp_t *self);
int mti_dsp_bins (const mti_dsp_t *self);
/* Centre frequency of bin b, in [-prf/2, prf/2). */
double mti_dsp_bin_hz (const mti_dsp_t *self, int bin);
/* Bin whose centre is nearest to the (aliased) frequency f. */
int mti_dsp_bin_of (const mti_dsp_t *self, double f_hz);

/* Draw a target per its model: constant (amplitude sqrt(snr)), Swerling I
 * and II (|a|^2 exponential of mean snr: drawn once a dwell for I, once
 * a coherent interval for II, mti_dsp_dwell redrawing), Swerling II pulse
 * to pulse (each pulse its own draw). */
mti_dsp_target_t mti_dsp_draw_target (mti_dsp_t *self, mti_swerling_t model, double snr,
                                      double doppler_hz);
/* Use a clutter spectrum of standard deviation sigma_hz from now on (the
 * decomposition is kept while sigma stays the same). 0, or -EINVAL/-ENOMEM. */
int mti_dsp_set_clutter (mti_dsp_t *self, double sigma_hz);
/* One cell's pulses of one CPI: unit noise, clutter of power cnr (the
 * spectrum last set), and tgt when not NULL. x has cpi_pulses entries. */
void mti_dsp_cell (mti_dsp_t *self, double cnr, const mti_dsp_target_t *tgt, double complex *x);
/* Canceller, window, FFT and square law of one cell's pulses: power has
 * fft_size bins, bin 0 at zero Doppler (FFT order). */
void mti_dsp_filter (mti_dsp_t *self, const double complex *x, double *power);
/* One CPI over the cell under test (with tgt, may be NULL) and n_ref
 * reference cells (cnr[0] the cell under test's, cnr[1..n_ref] theirs):
 * x_bins[b] the test cell's power, z_bins[b] the sum of the references'. */
void mti_dsp_cpi (mti_dsp_t *self, const double *cnr, const mti_dsp_target_t *tgt, double *x_bins,
                  double *z_bins);
/* The whole dwell. 0, or -EINVAL (bad clutter spread). */
int mti_dsp_dwell (mti_dsp_t *self, const mti_dsp_input_t *in, mti_dsp_result_t *ret);

/* Full processing of a strip of ncells adjacent range cells for one dwell
 * (clutter-to-noise cnr[i] each, no target): every cell whose whole CFAR
 * window (guard and reference cells, half each side) lies in the strip is
 * tested like the cell under test of a dwell; detected[i] says whether it
 * declared a detection (m of n), false for the cells at the edges. Returns
 * the number of cells tested, or -EINVAL/-ENOMEM. For checking the
 * statistical false-alarm model against the real chain. */
int mti_dsp_strip (mti_dsp_t *self, int ncells, const double *cnr, bool *detected);

/* The probability that a target-free cell in receiver noise has a CFAR
 * crossing in at least one Doppler bin of a CPI. The bins are not
 * independent (the window and canceller correlate neighbours), so this is
 * below 1 - (1 - Pfa)^bins; it is estimated with `samples` draws of the
 * union estimator P(any) = sum_b P(A_b) E[1 / crossings | A_b], P(A_b) =
 * Pfa exactly. Each draw picks b at random and samples the cells given that
 * bin b crosses, by conditioning their Gaussian pulses on their bin-b
 * outputs: each reference cell's is complex Gaussian of power |h_b|^2 / (1 +
 * T) (the crossing tilts the reference sum by exp(-T Z_b / |h_b|^2)), the
 * test cell's has power T Z_b plus an exponential exceedance; then it counts
 * the crossings of all bins. Relative standard error about 0.2 / sqrt(samples).
 * Uses (and advances) the chain's generator. */
double mti_dsp_any_bin_probability (mti_dsp_t *self, int samples);

/* The chain's exact response in Doppler bin `bin` for one cell: the power
 * gain of unit noise, of clutter of unit power (the spectrum last set), and
 * of a unit-power target at f_hz, coherent (constant or Swerling I) or
 * pulse to pulse (Swerling II). The mean power in the bin is noise +
 * cnr * clutter + snr * signal. */
void mti_dsp_bin_response (const mti_dsp_t *self, int bin, double f_hz, bool pulse_to_pulse,
                           double *ret_noise, double *ret_clutter, double *ret_signal);

/* Uniform in [0, 1), Gaussian of unit variance, and a Poisson or binomial
 * count, from the chain's generator (for the radar's statistical draws). */
double mti_dsp_uniform (mti_dsp_t *self);
double mti_dsp_gaussian (mti_dsp_t *self);
unsigned int mti_dsp_binomial (mti_dsp_t *self, double p, unsigned int n);
/* Gamma(k, 1) draw. */
double mti_dsp_gamma (mti_dsp_t *self, double k);

#endif
