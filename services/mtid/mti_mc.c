/* mti_mc — Monte Carlo of the detector in one Doppler cell (see mti_mc.h). */
#include "mti_mc.h"
#include "cgs_stats.h"
#include "cgs_util.h"
#include "mti_dsp.h"
#include "mti_theory.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>

void mti_mc_defaults (mti_mc_config_t *c)
{
    *c = (mti_mc_config_t){.swerling = MTI_SWERLING_1,
                           .snr_db = 10,
                           .trials = 10000,
                           .ref_cells = 16,
                           .pfa = 1e-4,
                           .fft_size = 64,
                           .seed = 1};
}

int mti_mc_run (const mti_mc_config_t *c, mti_mc_result_t *ret, char *err, size_t errlen)
{
    mti_params_t p;
    mti_params_defaults (&p);
    p.fft_size = c->fft_size;
    p.ref_cells = c->ref_cells;
    p.pfa = c->pfa;
    p.window = MTI_WINDOW_RECT;
    p.canceller = MTI_CANCELLER_NONE;
    p.m = p.n = 1;
    // One CPI per dwell: let the beam dwell long enough for any FFT size.
    p.sweep_rate_dps = p.azimuth_beamwidth_deg * p.prf_hz / (c->fft_size + 8.0);
    if (c->trials < 1 || !isfinite (c->snr_db)) {
        cgs_errf (err, errlen, "trials must be at least 1 and the SNR finite");
        return -EINVAL;
    }
    char why[512];
    if (mti_params_check (&p, why, sizeof why) < 0) {
        cgs_errf (err, errlen, "%s", why);
        return -EINVAL;
    }
    mti_dsp_t *dsp = mti_dsp_new (&p, c->seed);
    double *cnr = calloc ((size_t)c->ref_cells + 1, sizeof (double));
    double *x = malloc (sizeof (double) * c->fft_size);
    double *z = malloc (sizeof (double) * c->fft_size);
    if (!dsp || !cnr || !x || !z) {
        mti_dsp_destroy (&dsp);
        free (cnr);
        free (x);
        free (z);
        return -ENOMEM;
    }
    mti_mc_result_t r = {.threshold = mti_dsp_threshold (dsp)};
    int bin = c->fft_size / 4;
    double f = mti_dsp_bin_hz (dsp, bin);
    double cell_snr = pow (10.0, c->snr_db / 10.0);
    double pulse_snr = cell_snr / c->fft_size;
    for (unsigned long t = 0; t < c->trials; t++) {
        mti_dsp_target_t tgt = mti_dsp_draw_target (dsp, c->swerling, pulse_snr, f);
        mti_dsp_cpi (dsp, cnr, &tgt, x, z);
        r.detections += x[bin] > r.threshold * z[bin];
        // False alarms in a target-free interval (a Swerling II target would
        // leak into every bin of the first).
        mti_dsp_cpi (dsp, cnr, NULL, x, z);
        for (int k = 0; k < c->fft_size; k++)
            r.false_alarms += x[k] > r.threshold * z[k];
    }
    // What the target has in its cell: a target fluctuating pulse to pulse
    // gets no coherent gain (one that changes between intervals does: this
    // is one interval).
    double eff = c->swerling == MTI_SWERLING_2_PULSE ? pulse_snr : cell_snr;
    r.cell_snr_db = 10.0 * log10 (eff);
    r.pd = (double)r.detections / c->trials;
    r.pd_interval_ok =
        cgs_binomial_interval (r.detections, c->trials, 0.99, &r.pd_lo, &r.pd_hi) == 0;
    r.pd_theory = c->swerling == MTI_SWERLING_0
                      ? mti_theory_pd_constant_cacfar (eff, r.threshold, c->ref_cells)
                      : mti_theory_pd_swerling_cacfar (eff, r.threshold, c->ref_cells);
    r.fa_cells = c->trials * (unsigned long)c->fft_size;
    r.pfa_measured = (double)r.false_alarms / r.fa_cells;
    r.fa_interval_ok =
        cgs_binomial_count_interval (c->pfa, r.fa_cells, 0.99, &r.fa_lo, &r.fa_hi) == 0;
    mti_dsp_destroy (&dsp);
    free (cnr);
    free (x);
    free (z);
    *ret = r;
    return 0;
}
