/* cgs_stats — binomial confidence intervals: how sure a count of successes
 * makes a rate (the Monte Carlo's imaged fraction, mtid's detection
 * probability), and which counts a rate makes likely.
 *
 * GSL's own beta inverse (gsl_cdf_beta_Pinv) is not used: it fails to
 * converge for some counts (k = 484 of n = 500, k = 16 of 500, k = 1 of
 * 1e6), and its default error handler then aborts the program. */
#ifndef CGS_STATS_H
#define CGS_STATS_H

/* The two-sided 99% (or any level) Clopper-Pearson interval for k successes
 * in n trials: *ret_lo, *ret_hi. 0, -EINVAL for k > n or a level outside
 * (0, 1), -ERANGE where GSL cannot evaluate the beta distribution (counts with
 * k (n - k) / n beyond about 5e5); outputs are written only on success. */
int cgs_binomial_interval (unsigned long k, unsigned long n, double level, double *ret_lo,
                           double *ret_hi);
/* The interval [lo, hi] of success counts that holds probability >= level
 * for n trials of probability p (equal tails): is a measured count
 * consistent with p? 0, -EINVAL for p outside [0, 1] or a level outside
 * (0, 1), -ERANGE for n beyond UINT_MAX or n p (1 - p) beyond about 5e5. */
int cgs_binomial_count_interval (double p, unsigned long n, double level, unsigned long *ret_lo,
                                 unsigned long *ret_hi);

#endif
