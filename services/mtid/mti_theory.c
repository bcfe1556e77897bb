/* mti_theory — the closed forms of detection theory the MTI model is checked
 * against (see mti_theory.h).
 *
 * Arguments outside a function's domain give NAN, as libm does. (The
 * binomial intervals it is checked with are common/cgs_stats.)
 *
 * GSL reports a failure to its error handler before it returns the status,
 * and the default handler aborts. That handler is a process-wide setting, so
 * it is the program's to choose (gsl_set_error_handler_off () in main), not
 * this module's: here every status is checked and a failure gives NAN. The
 * quadratures are set up so that no GSL error arises for sensible arguments;
 * the unit test runs them under a handler that fails the test. */
#include "mti_theory.h"

#include <math.h>
#include <stddef.h>
#include <stdlib.h>

#include <gsl/gsl_cdf.h>
#include <gsl/gsl_errno.h>
#include <gsl/gsl_integration.h>
#include <gsl/gsl_sf_bessel.h>
#include <gsl/gsl_sf_gamma.h>

#define S_QUAD_LIMIT 200   // subintervals per adaptive quadrature
#define S_Q1_EPSREL  1e-12 // relative tolerance of Marcum's Q
#define S_PD_EPSREL  1e-10 // relative tolerance of the CA-CFAR Pd
#define S_RICE_SPAN  15.0  // sqrt of a cell's power lies within sqrt(snr) -+ this
#define S_GAMMA_SPAN 15.0  // Gamma(N, 1) mass lies within N -+ this many sqrt(N)

double mti_theory_cfar_t (double pfa, int n_ref)
{
    if (!(pfa > 0.0 && pfa <= 1.0) || n_ref < 1)
        return NAN;
    return expm1 (-log (pfa) / n_ref);
}

double mti_theory_cfar_pfa (double t, int n_ref)
{
    if (!(t >= 0.0) || n_ref < 1)
        return NAN;
    return exp (-n_ref * log1p (t));
}

double mti_theory_pd_swerling_cacfar (double snr, double t, int n_ref)
{
    if (!(snr >= 0.0) || !(t >= 0.0) || n_ref < 1)
        return NAN;
    return exp (-n_ref * log1p (t / (1.0 + snr)));
}

double mti_theory_pd_swerling_known (double snr, double pfa)
{
    if (!(snr >= 0.0) || !(pfa > 0.0 && pfa <= 1.0))
        return NAN;
    return exp (log (pfa) / (1.0 + snr));
}

/* ---- Marcum's Q ---- */

/* Q1(a, b) is the tail beyond b of the Rice density x exp(-(x^2 + a^2)/2) I0(a x)
 * = x exp(-(x - a)^2 / 2) I0s(a x), I0s the scaled Bessel function. The
 * integrands below are that density at x = b + u (upper) or x = b - u
 * (lower), u >= 0, with the factor exp(-(b - a)^2 / 2) taken out, so that they
 * start near 1 at u = 0 and the quadrature works to a relative tolerance
 * however small the tail. */
typedef struct {
    double a, b;
} s_rice_t;

static double s_rice_upper (double u, void *arg)
{
    const s_rice_t *r = arg;
    double x = r->b + u;
    gsl_sf_result i0s;
    if (gsl_sf_bessel_I0_scaled_e (r->a * x, &i0s) != GSL_SUCCESS)
        return NAN;
    return x * exp (-u * (0.5 * u + (r->b - r->a))) * i0s.val;
}

static double s_rice_lower (double u, void *arg)
{
    const s_rice_t *r = arg;
    double x = r->b - u;
    gsl_sf_result i0s;
    if (gsl_sf_bessel_I0_scaled_e (r->a * x, &i0s) != GSL_SUCCESS)
        return NAN;
    return x * exp (-u * (0.5 * u + (r->a - r->b))) * i0s.val;
}

/* Integrate whichever side of the Rice density is the smaller: the tail
 * beyond b when b > a, else [0, b]. */
double mti_theory_marcum_q1 (double a, double b)
{
    if (isnan (a) || isnan (b) || a < 0.0 || b < 0.0)
        return NAN;
    if (b == 0.0 || isinf (a))
        return 1.0;
    if (isinf (b))
        return 0.0;
    if (a == 0.0)
        return exp (-0.5 * b * b);
    double scale = exp (-0.5 * (b - a) * (b - a));
    if (b > a && scale == 0.0)
        return 0.0; // below the smallest double

    gsl_integration_workspace *ws = gsl_integration_workspace_alloc (S_QUAD_LIMIT);
    if (!ws)
        return NAN;
    s_rice_t r = {a, b};
    double result, abserr;
    int rc;
    if (b > a) {
        gsl_function f = {.function = s_rice_upper, .params = &r};
        rc = gsl_integration_qagiu (&f, 0.0, 0.0, S_Q1_EPSREL, S_QUAD_LIMIT, ws, &result, &abserr);
    } else {
        gsl_function f = {.function = s_rice_lower, .params = &r};
        rc = gsl_integration_qag (&f, 0.0, b, 0.0, S_Q1_EPSREL, S_QUAD_LIMIT, GSL_INTEG_GAUSS21, ws,
                                  &result, &abserr);
    }
    double q = NAN;
    if (rc == GSL_SUCCESS && isfinite (result))
        q = b > a ? scale * result : 1.0 - scale * result;
    gsl_integration_workspace_free (ws);
    return q;
}

double mti_theory_pd_constant_known (double snr, double pfa)
{
    if (!(snr >= 0.0) || !(pfa > 0.0 && pfa <= 1.0))
        return NAN;
    return mti_theory_marcum_q1 (sqrt (2.0 * snr), sqrt (-2.0 * log (pfa)));
}

/* ---- constant target under CA-CFAR ---- */

/* The header's Pd = E_Z[Q1(a, sqrt(2 T Z))] = P(X > T Z), X the cell's power
 * (noise 1): with the order of the averaging swapped it is
 *   Pd = integral_0^inf f_X(x) P(n, x / T) dx,
 *   f_X(x) = e^{-(x + snr)} I0(2 sqrt(snr x)) = e^{-(sqrt x - sqrt snr)^2} I0s(2 sqrt(snr x)),
 * P(n, y) the regularised incomplete gamma function, the distribution function
 * of Z. One quadrature instead of one per point of another: about 35 times
 * faster (some 0.1 ms a call at -O2, which matters to mti_radar, which asks
 * per target and dwell), and within 4e-12 of the nested form over N 1..5000,
 * Pfa 1e-1..1e-14, SNR -20..50 dB; the unit test checks it against the nested
 * form as the header writes it. */
typedef struct {
    double root_snr; // sqrt(snr)
    double t;        // CFAR multiplier
    int n;           // reference cells
} s_cacfar_t;

static double s_cacfar_integrand (double x, void *arg)
{
    const s_cacfar_t *c = arg;
    if (x <= 0.0)
        return 0.0;
    double rx = sqrt (x), d = rx - c->root_snr;
    gsl_sf_result i0s, p;
    if (gsl_sf_bessel_I0_scaled_e (2.0 * c->root_snr * rx, &i0s) != GSL_SUCCESS ||
        gsl_sf_gamma_inc_P_e (c->n, x / c->t, &p) != GSL_SUCCESS)
        return NAN;
    return exp (-d * d) * i0s.val * p.val;
}

static int s_cmp_double (const void *x, const void *y)
{
    double a = *(const double *)x, b = *(const double *)y;
    return (a > b) - (a < b);
}

/* The integrand lives where the density of X does (sqrt x within sqrt(snr) -+
 * a few) and where P(n, x/T) rises from 0 to 1 (x/T within n -+ a few
 * sqrt(n)), two scales that can be far apart (n = 1, T = 1e12). The range is
 * cut at the ends of both, so that no piece hides a narrow peak from the
 * quadrature. */
double mti_theory_pd_constant_cacfar (double snr, double t, int n_ref)
{
    if (!(snr >= 0.0) || !(t >= 0.0) || n_ref < 1)
        return NAN;
    if (t == 0.0 || isinf (snr))
        return 1.0;
    if (isinf (t))
        return 0.0;

    gsl_integration_workspace *ws = gsl_integration_workspace_alloc (S_QUAD_LIMIT);
    if (!ws)
        return NAN;
    s_cacfar_t c = {.root_snr = sqrt (snr), .t = t, .n = n_ref};
    double n = n_ref, sd = sqrt (n);
    double r_lo = fmax (0.0, c.root_snr - S_RICE_SPAN), r_hi = c.root_snr + S_RICE_SPAN;
    double cut[5] = {
        0.0,
        r_lo * r_lo,
        r_hi * r_hi,
        t * fmax (0.0, n - S_GAMMA_SPAN * sd),
        t * (n + S_GAMMA_SPAN * (sd + 1.0)),
    };
    qsort (cut, 5, sizeof cut[0], s_cmp_double);

    // Pd >= Pfa, so pieces far below Pfa need no relative accuracy.
    double epsabs = 1e-3 * S_PD_EPSREL * mti_theory_cfar_pfa (t, n_ref);
    gsl_function f = {.function = s_cacfar_integrand, .params = &c};
    double pd = NAN, sum = 0.0, result, abserr;
    for (int i = 0; i < 4; i++) {
        if (!(cut[i + 1] > cut[i]))
            continue;
        if (gsl_integration_qag (&f, cut[i], cut[i + 1], epsabs, S_PD_EPSREL, S_QUAD_LIMIT,
                                 GSL_INTEG_GAUSS21, ws, &result, &abserr) != GSL_SUCCESS)
            goto done;
        sum += result;
    }
    if (gsl_integration_qagiu (&f, cut[4], epsabs, S_PD_EPSREL, S_QUAD_LIMIT, ws, &result,
                               &abserr) != GSL_SUCCESS)
        goto done;
    sum += result;
    if (isfinite (sum))
        pd = fmin (sum, 1.0);
done:
    gsl_integration_workspace_free (ws);
    return pd;
}

/* ---- clutter cancellers ---- */

/* With e = 1 - rho_1 (computed without cancellation) and rho_2 = rho_1^4,
 * 6 - 8 rho_1 + 2 rho_2 = 2 e^2 (6 - 4 e + e^2), which keeps the three-pulse
 * form exact down to the smallest spreads. */
double mti_theory_canceller_improvement (int pulses, double sigma_hz, double prf_hz)
{
    if (pulses < 1 || pulses > 3 || !(sigma_hz >= 0.0) || !(prf_hz > 0.0) || isinf (prf_hz))
        return NAN;
    if (pulses == 1)
        return 1.0;
    double r = sigma_hz / prf_hz;
    double e = -expm1 (-2.0 * M_PI * M_PI * r * r);
    if (pulses == 2)
        return 1.0 / e;
    return 3.0 / (e * e * (6.0 - 4.0 * e + e * e));
}

double mti_theory_canceller_improvement_approx (int pulses, double sigma_hz, double prf_hz)
{
    if (pulses < 1 || pulses > 3 || !(sigma_hz >= 0.0) || !(prf_hz > 0.0) || isinf (prf_hz))
        return NAN;
    if (pulses == 1)
        return 1.0;
    double x = 2.0 * M_PI * M_PI * (sigma_hz / prf_hz) * (sigma_hz / prf_hz);
    return pulses == 2 ? 1.0 / x : 1.0 / (2.0 * x * x);
}

/* ---- binomial ---- */

/* m of n needs 1 <= m <= n: an m outside that is a misconfiguration, not a
 * question with answer 0 or 1. */
double mti_theory_m_of_n (double p, int m, int n)
{
    if (!(p >= 0.0 && p <= 1.0) || n < 1 || m < 1 || m > n)
        return NAN;
    return gsl_cdf_binomial_Q ((unsigned)(m - 1), p, (unsigned)n);
}

typedef struct {
    double snr, t;
    int n_ref, m, n;
} s_dwell_t;

/* With u = 1 - e^-x (x the Swerling I draw over its mean): the m-of-n Pd
 * of a constant target at x snr, uniform weight in u. */
static double s_dwell_integrand (double u, void *arg)
{
    const s_dwell_t *d = arg;
    double x = -log1p (-u);
    return mti_theory_m_of_n (mti_theory_pd_constant_cacfar (x * d->snr, d->t, d->n_ref), d->m,
                              d->n);
}

double mti_theory_pd_swerling1_m_of_n (double snr, double t, int n_ref, int m, int n)
{
    if (!(snr >= 0.0) || !(t >= 0.0) || n_ref < 1 || n < 1 || m < 1 || m > n)
        return NAN;
    gsl_integration_workspace *ws = gsl_integration_workspace_alloc (S_QUAD_LIMIT);
    if (!ws)
        return NAN;
    s_dwell_t d = {.snr = snr, .t = t, .n_ref = n_ref, .m = m, .n = n};
    gsl_function f = {.function = s_dwell_integrand, .params = &d};
    double result = NAN, abserr;
    if (gsl_integration_qag (&f, 0.0, 1.0, 1e-9, 1e-7, S_QUAD_LIMIT, GSL_INTEG_GAUSS21, ws, &result,
                             &abserr) != GSL_SUCCESS)
        result = NAN;
    gsl_integration_workspace_free (ws);
    return result;
}
