/* mti_mc — Monte Carlo of the detector in one Doppler cell, for checking the
 * chain against the closed forms (mti_theory) and for `mtid --monte-carlo`.
 *
 * Each trial is one coherent interval through the real chain (mti_dsp):
 * receiver noise only (no clutter, no canceller, rectangular window, so the
 * Doppler bins are independent and the detector statistics are exactly
 * those of the theory), with the target on the centre of one Doppler bin.
 * The SNR given is the SNR in that Doppler cell of a target that integrates
 * coherently: per-pulse SNR = cell SNR / fft_size. A constant or Swerling I
 * target (a new amplitude each trial: one look) reaches that cell SNR; a
 * Swerling II target, fluctuating pulse to pulse, spreads over all bins and
 * reaches only the per-pulse SNR: coherent integration gives it nothing.
 * Pd is counted in the target's bin; Pfa in every bin of a second,
 * target-free interval each trial (trials x fft_size cells). Pure: no globals, no logging. */
#ifndef MTI_MC_H
#define MTI_MC_H

#include "mti_params.h"

#include <stdbool.h>
#include <stdint.h>

typedef struct {
    mti_swerling_t swerling;
    double snr_db;        // in the Doppler cell, for a coherently integrating target
    unsigned long trials; // coherent intervals
    int ref_cells;        // CFAR reference cells N
    double pfa;           // design false-alarm probability per cell
    int fft_size;         // pulses coherently integrated
    uint64_t seed;
} mti_mc_config_t;

typedef struct {
    double threshold;         // CA-CFAR multiplier T = Pfa^(-1/N) - 1
    double cell_snr_db;       // the SNR the target actually has in its cell
    unsigned long detections; // in the target's bin
    double pd;                // measured
    double pd_lo, pd_hi;      // its 99% Clopper-Pearson interval ...
    bool pd_interval_ok;      // ... when GSL could compute it
    double pd_theory;         // the closed form at cell_snr
    unsigned long fa_cells;   // target-free cells tested
    unsigned long false_alarms;
    double pfa_measured;
    unsigned long fa_lo, fa_hi; // 99% interval of the count for the design Pfa ...
    bool fa_interval_ok;        // ... when GSL could compute it
} mti_mc_result_t;

/* Defaults: Swerling I, 10 dB, 10000 trials, 16 cells, 1e-4, FFT 64, seed 1. */
void mti_mc_defaults (mti_mc_config_t *c);
/* Run; 0, or -EINVAL (bad configuration, reason in err) / -ENOMEM. */
int mti_mc_run (const mti_mc_config_t *c, mti_mc_result_t *ret, char *err, size_t errlen);

#endif
