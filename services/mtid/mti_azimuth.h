/* mti_azimuth — how the MTI radar measures a hit's azimuth.
 *
 * Beam splitting (the default). The radar has one receive channel (no
 * monopulse difference channel); its beam sweeps the dwell's width while the
 * dwell's n coherent intervals are taken, evenly spread: interval c looks at
 * x_c = (c + 1/2 − n/2) w / n from the dwell's centre (w the dwell's width).
 * Each interval measures the echo's power y_c in the detection's Doppler bin
 * (in noise units). With the two-way Gaussian power pattern
 * G(u − x) = exp(−b (u − x)²), b = 8 ln 2 / θ² (θ the one-way 3 dB
 * beamwidth; 3 dB one way at θ/2), the target at u gives
 *   ln y_c ≈ ln(S α_c) − b (u − x_c)²  (+ noise),
 * so z_c = ln y_c + b x_c² is a straight line in x_c of slope 2 b u. The
 * estimate is the weighted least-squares slope:
 *   û = β̂ / (2 b),  β̂ = Σ w_c (x_c − x̄)(z_c − z̄) / Σ w_c (x_c − x̄)²,
 *   σ_u = 1 / (2 b √(Σ w_c (x_c − x̄)²)),  x̄, z̄ the w-weighted means.
 * The weights are 1 / var(ln y_c): receiver noise gives about 2 / y_c (the
 * log of signal plus complex noise of unit power, linearised), at most
 * π²/6 (the variance of the log of an exponential power, noise alone); a
 * target whose amplitude decorrelates between intervals (the radar hops its
 * frequency between them: Swerling II in the interval sense) is complex
 * Gaussian, and so is its sum with the noise: its power is exponential and
 * the log's variance π²/6 whatever the SNR.
 * That term is the floor of beam splitting under frequency agility: for the
 * default radar (θ = w = 3°, n = 4) σ_u ≥ 0.62°. A target that keeps its
 * amplitude over the dwell (constant, or Swerling I) has that term cancel
 * in the intercept; the radar cannot tell which target it sees, so it
 * always allows for it (`fluctuation_var`), and its σ is then on the
 * cautious side for those. The estimate is held to the dwell's width plus
 * half a beamwidth each side.
 *
 * Monopulse (`azimuth = monopulse`): a radar with sum and difference
 * channels measures the angle within each interval, and the thermal-noise
 * error of the dwell's estimate is σ = θ / (k_m √(2 SINR)) with the
 * normalised monopulse slope k_m = 1.6 (Barton's form for the
 * thermal-noise error of a monopulse measurement), held to at most θ/√12.
 *
 * Pure functions, no state. */
#ifndef MTI_AZIMUTH_H
#define MTI_AZIMUTH_H

#include <math.h>

#define MTI_AZIMUTH_KM 1.6 // normalised monopulse slope

typedef enum {
    MTI_AZIMUTH_BEAM_SPLIT = 0, // amplitude comparison across the dwell's intervals
    MTI_AZIMUTH_MONOPULSE = 1,  // sum and difference channels
} mti_azimuth_t;

/* The variance of ln of an exponential variable: π²/6. */
#define MTI_AZIMUTH_LN_EXP_VAR (M_PI * M_PI / 6.0)

/* Interval c's look direction, degrees from the dwell's centre, for a dwell
 * of width width_deg cut into n intervals. */
double mti_azimuth_look_deg (double width_deg, int n, int c);

/* The beam-splitting estimate from the n intervals' powers y (noise units,
 * > 0), looking at x_deg (from the dwell's centre), with a one-way 3 dB
 * beamwidth beamwidth_deg, allowing fluctuation_var for the target's
 * interval-to-interval fluctuation of ln power. Writes the estimate
 * (degrees from the dwell's centre, held to ±(width_deg + beamwidth_deg)/2)
 * and its standard deviation. 0, or -EINVAL (n < 2, a bad argument). */
int mti_azimuth_beam_split (const double *y, const double *x_deg, int n, double beamwidth_deg,
                            double width_deg, double fluctuation_var, double *ret_deg,
                            double *ret_sigma_deg);

/* The monopulse thermal-noise error at the dwell's SINR: θ / (k_m √(2 SINR)),
 * at most θ/√12. */
double mti_azimuth_monopulse_sigma (double beamwidth_deg, double sinr);

#endif
