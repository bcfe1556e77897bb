/* mti_theory — the closed forms of detection theory the MTI model is checked
 * against, and the statistics used to check it. Square-law detection,
 * noise power normalised to 1, SNR as a power ratio (not dB).
 *
 * Cell-averaging CFAR, sum convention: declare X > T * sum(Z_1..Z_N) over N
 * reference cells. In exponential (Gaussian-I/Q) noise
 *   Pfa = (1 + T)^-N,  so  T = Pfa^(-1/N) - 1,
 * and a Swerling I or II target in one look (X exponential with mean 1 + SNR)
 *   Pd = (1 + T / (1 + SNR))^-N.
 * A constant (nonfluctuating) target with known noise and threshold t
 * (Pfa = e^-t): Pd = Q1(sqrt(2 SNR), sqrt(2 t)), Marcum's Q function; under
 * CA-CFAR the same averaged over the sum Z ~ Gamma(N, 1):
 *   Pd = integral Q1(sqrt(2 SNR), sqrt(2 T z)) z^(N-1) e^-z / (N-1)! dz.
 * Clutter cancellers on a Gaussian clutter spectrum of standard deviation
 * sigma_f (Hz) sampled at the PRF f_r: with rho_k = exp(-2 pi^2 sigma_f^2 k^2 / f_r^2)
 *   two-pulse   I = 1 / (1 - rho_1)                      (~ f_r^2 / (2 pi^2 sigma_f^2))
 *   three-pulse I = 6 / (6 - 8 rho_1 + 2 rho_2)          (~ f_r^4 / (8 pi^4 sigma_f^4))
 * (improvement factor: signal gain averaged over all Doppler over clutter gain).
 * m-of-n: P = sum_{k=m..n} C(n,k) p^k (1-p)^(n-k).
 * A dwell of n coherent intervals that detects when m of them cross, each
 * interval with its own reference cells (independent noise):
 *   constant target            P = m-of-n(Pd_constant(SNR))
 *   Swerling II, interval sense P = m-of-n(Pd_Swerling(SNR)) (a new draw
 *                               each interval: the radar hops its frequency)
 *   Swerling I over the dwell  P = integral m-of-n(Pd_constant(x SNR)) e^-x dx
 *                               (one draw for all intervals: they fade together).
 * Pure functions; GSL does the special functions and the quadrature.
 * Arguments outside a function's domain give NAN. */
#ifndef MTI_THEORY_H
#define MTI_THEORY_H

/* CA-CFAR multiplier T for n reference cells (sum convention). */
double mti_theory_cfar_t (double pfa, int n_ref);
/* Pfa of CA-CFAR with multiplier t and n reference cells: (1 + t)^-n. */
double mti_theory_cfar_pfa (double t, int n_ref);
/* Pd of a Swerling I/II target (one look) under CA-CFAR: (1 + T/(1+snr))^-n. */
double mti_theory_pd_swerling_cacfar (double snr, double t, int n_ref);
/* Pd of a Swerling I/II target with known noise and threshold -ln(pfa):
 * pfa^(1/(1+snr)). */
double mti_theory_pd_swerling_known (double snr, double pfa);
/* Marcum's Q function Q1(a, b), a, b >= 0. */
double mti_theory_marcum_q1 (double a, double b);
/* Pd of a constant target with known noise: Q1(sqrt(2 snr), sqrt(-2 ln pfa)). */
double mti_theory_pd_constant_known (double snr, double pfa);
/* Pd of a constant target under CA-CFAR with multiplier t and n reference cells. */
double mti_theory_pd_constant_cacfar (double snr, double t, int n_ref);
/* Improvement factor (power ratio) of a canceller spanning `pulses` pulses
 * (2 or 3; 1 gives 1) on Gaussian clutter of spectral std sigma_hz at prf_hz. */
double mti_theory_canceller_improvement (int pulses, double sigma_hz, double prf_hz);
/* The small-spread approximations f_r^2/(2 pi^2 s^2) and f_r^4/(8 pi^4 s^4). */
double mti_theory_canceller_improvement_approx (int pulses, double sigma_hz, double prf_hz);
/* P(at least m successes in n independent trials of probability p), 1 <= m <= n. */
double mti_theory_m_of_n (double p, int m, int n);
/* Pd of an m-of-n dwell under CA-CFAR (multiplier t, n_ref cells) of a
 * Swerling I target constant over the dwell, mean SNR snr per interval. */
double mti_theory_pd_swerling1_m_of_n (double snr, double t, int n_ref, int m, int n);
#endif
