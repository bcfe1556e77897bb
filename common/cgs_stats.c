/* cgs_stats — binomial confidence intervals (see cgs_stats.h).
 *
 * GSL reports a failure to its error handler before it returns the status,
 * and the default handler aborts; every GSL call here is one that returns a
 * value to check (the Brent solver is fed finite values only), so no
 * handler is called for arguments in range. */
#include "cgs_stats.h"

#include <assert.h>
#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdbool.h>

#include <gsl/gsl_cdf.h>
#include <gsl/gsl_errno.h>
#include <gsl/gsl_roots.h>

#define S_ROOT_ITER   200   // Brent iterations for a Clopper-Pearson end
#define S_ROOT_EPSREL 1e-13 // relative tolerance of a Clopper-Pearson end

/* One end of a Clopper-Pearson interval: the root in [lo, hi] of the
 * increasing function beta_P(x; a, b) - tail (upper false) or tail -
 * beta_Q(x; a, b) (upper true), by GSL's Brent solver. GSL's own beta
 * inverse is not used: for counts as small as k = 1 in n = 1e6 it fails to
 * converge, and where beta_P is NAN (large a and b) its bisection never ends. */
typedef struct {
    double a, b, tail;
    bool upper;
    bool bad; // beta_P was not finite somewhere
} s_beta_root_t;

static double s_beta_root_f (double x, void *arg)
{
    s_beta_root_t *r = arg;
    double v = r->upper ? r->tail - gsl_cdf_beta_Q (x, r->a, r->b)
                        : gsl_cdf_beta_P (x, r->a, r->b) - r->tail;
    if (!isfinite (v)) {
        r->bad = true;
        return 1.0; // finite, so that Brent does not call the error handler
    }
    return v;
}

static int s_beta_root (s_beta_root_t *r, double lo, double hi, double *ret_x)
{
    gsl_function f = {.function = s_beta_root_f, .params = r};
    double f_lo = s_beta_root_f (lo, r), f_hi = s_beta_root_f (hi, r);
    if (r->bad)
        return -ERANGE;
    if (f_lo >= 0.0 || f_hi <= 0.0) {
        *ret_x = f_lo >= 0.0 ? lo : hi; // a root at an end of the bracket
        return 0;
    }
    gsl_root_fsolver *s = gsl_root_fsolver_alloc (gsl_root_fsolver_brent);
    if (!s)
        return -ENOMEM;
    int rc = -ERANGE;
    if (gsl_root_fsolver_set (s, &f, lo, hi) != GSL_SUCCESS)
        goto done;
    for (int i = 0; i < S_ROOT_ITER && !r->bad; i++) {
        if (gsl_root_fsolver_iterate (s) != GSL_SUCCESS)
            break;
        double x_lo = gsl_root_fsolver_x_lower (s), x_hi = gsl_root_fsolver_x_upper (s);
        if (gsl_root_test_interval (x_lo, x_hi, 0.0, S_ROOT_EPSREL) == GSL_SUCCESS) {
            if (!r->bad) {
                *ret_x = gsl_root_fsolver_root (s);
                rc = 0;
            }
            break;
        }
    }
done:
    gsl_root_fsolver_free (s);
    return rc;
}

/* Clopper-Pearson: the lower end is the p whose P(X >= k) is (1 - level)/2,
 * the upper the p whose P(X <= k) is; by the beta-binomial identity
 * P(X >= k) = beta_P(p; k, n - k + 1) and P(X <= k) = beta_Q(p; k + 1, n - k).
 * Both ends lie on their side of k/n, where each probability is >= 1/2. */
int cgs_binomial_interval (unsigned long k, unsigned long n, double level, double *ret_lo,
                           double *ret_hi)
{
    assert (ret_lo && ret_hi);
    if (k > n || !(level > 0.0 && level < 1.0))
        return -EINVAL;
    double tail = 0.5 * (1.0 - level);
    double kd = (double)k, nd = (double)n, lo = 0.0, hi = 1.0;
    int rc;
    if (k > 0) {
        s_beta_root_t r = {.a = kd, .b = nd - kd + 1.0, .tail = tail};
        if ((rc = s_beta_root (&r, 0.0, kd / nd, &lo)) < 0)
            return rc;
    }
    if (k < n) {
        s_beta_root_t r = {.a = kd + 1.0, .b = nd - kd, .tail = tail, .upper = true};
        if ((rc = s_beta_root (&r, kd / nd, 1.0, &hi)) < 0)
            return rc;
    }
    *ret_lo = lo;
    *ret_hi = hi;
    return 0;
}

/* Equal tails: lo is the largest count with P(X < lo) <= (1 - level)/2, hi the
 * smallest with P(X > hi) <= (1 - level)/2, each found by bisection on GSL's
 * binomial distribution function (NAN where its continued fraction gives up). */
int cgs_binomial_count_interval (double p, unsigned long n, double level, unsigned long *ret_lo,
                                 unsigned long *ret_hi)
{
    assert (ret_lo && ret_hi);
    if (!(p >= 0.0 && p <= 1.0) || !(level > 0.0 && level < 1.0))
        return -EINVAL;
    if (n > UINT_MAX)
        return -ERANGE;
    double tail = 0.5 * (1.0 - level);
    unsigned nn = (unsigned)n;

    // lo: the smallest k with P(X <= k) > tail (P(X <= n) = 1 > tail).
    unsigned a = 0, b = nn;
    while (a < b) {
        unsigned mid = a + (b - a) / 2;
        double cdf = gsl_cdf_binomial_P (mid, p, nn);
        if (isnan (cdf))
            return -ERANGE;
        if (cdf > tail)
            b = mid;
        else
            a = mid + 1;
    }
    unsigned lo = a;

    // hi: the smallest k with P(X > k) <= tail (P(X > n) = 0); hi >= lo, as
    // the two tails together hold less than 1.
    b = nn;
    while (a < b) {
        unsigned mid = a + (b - a) / 2;
        double sf = gsl_cdf_binomial_Q (mid, p, nn);
        if (isnan (sf))
            return -ERANGE;
        if (sf <= tail)
            b = mid;
        else
            a = mid + 1;
    }
    *ret_lo = lo;
    *ret_hi = a;
    return 0;
}
