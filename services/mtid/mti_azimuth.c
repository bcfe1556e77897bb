/* mti_azimuth — azimuth measurement (see mti_azimuth.h). */
#include "mti_azimuth.h"

#include <errno.h>
#include <math.h>

double mti_azimuth_look_deg (double width_deg, int n, int c)
{
    return ((double)c + 0.5 - 0.5 * (double)n) * width_deg / (double)n;
}

/* 1 / var(ln y): the fluctuation's share and the noise's, 2 / y, but never
 * more than π²/6, the variance of the log of an exponential power (noise
 * alone, or a Rayleigh target in noise). */
static double s_weight (double y, double fluctuation_var)
{
    return 1.0 / fmin (fluctuation_var + 2.0 / fmax (y, 1.0), MTI_AZIMUTH_LN_EXP_VAR);
}

int mti_azimuth_beam_split (const double *y, const double *x_deg, int n, double beamwidth_deg,
                            double width_deg, double fluctuation_var, double *ret_deg,
                            double *ret_sigma_deg)
{
    if (n < 2 || !(beamwidth_deg > 0) || !(width_deg > 0) || !(fluctuation_var >= 0))
        return -EINVAL;
    double b = 8.0 * M_LN2 / (beamwidth_deg * beamwidth_deg);
    double sw = 0, swx = 0, swz = 0;
    for (int c = 0; c < n; c++) {
        if (!(y[c] > 0) || !isfinite (y[c]) || !isfinite (x_deg[c]))
            return -EINVAL;
        double w = s_weight (y[c], fluctuation_var);
        double z = log (y[c]) + b * x_deg[c] * x_deg[c];
        sw += w;
        swx += w * x_deg[c];
        swz += w * z;
    }
    double xm = swx / sw, zm = swz / sw, sxx = 0, sxz = 0;
    for (int c = 0; c < n; c++) {
        double w = s_weight (y[c], fluctuation_var), z = log (y[c]) + b * x_deg[c] * x_deg[c];
        sxx += w * (x_deg[c] - xm) * (x_deg[c] - xm);
        sxz += w * (x_deg[c] - xm) * (z - zm);
    }
    if (!(sxx > 0))
        return -EINVAL; // every look in one direction
    double u = sxz / sxx / (2.0 * b), lim = 0.5 * (width_deg + beamwidth_deg);
    *ret_deg = fmax (-lim, fmin (lim, u));
    *ret_sigma_deg = 1.0 / (2.0 * b * sqrt (sxx));
    return 0;
}

double mti_azimuth_monopulse_sigma (double beamwidth_deg, double sinr)
{
    double s = beamwidth_deg / (MTI_AZIMUTH_KM * sqrt (2.0 * fmax (sinr, 1e-6)));
    return fmin (s, beamwidth_deg / sqrt (12.0));
}
