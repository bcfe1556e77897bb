/* trk_filter — the paper's Track & Update filter and the Kalman filter (see
 * trk_filter.h). */
#include "trk_filter.h"

#include <errno.h>
#include <math.h>
#include <string.h>

#define S_PI 3.14159265358979323846

int trk_gains_paper (double sigma_meas_m, double sigma_mod_mps2, double dt_s, trk_gains_t *ret)
{
    if (!(sigma_meas_m > 0) || !(sigma_mod_mps2 > 0) || !(dt_s > 0) || !isfinite (sigma_meas_m) ||
        !isfinite (sigma_mod_mps2) || !isfinite (dt_s))
        return -EINVAL;
    double r = 4 * sigma_meas_m / (sigma_mod_mps2 * dt_s * dt_s);
    double s = sqrt (1 + 2 * r);
    // (s − 1)/r written as 2/(s + 1), which keeps its precision when r is small.
    double u = 2 / (s + 1);
    ret->r = r;
    ret->g = s * u * u;
    ret->gd_hz = 2 / dt_s * u * u;
    return 0;
}

int trk_filter_steady_error (const trk_gains_t *g, double dt_s, double sigma_m, double *ret_pos_var,
                             double *ret_vel_var)
{
    double a = g->g, b = g->gd_hz * dt_s, s2 = sigma_m * sigma_m;
    if (!(a > 0 && a < 1 && b > 0 && b < 4 - 2 * a) || !(dt_s > 0))
        return -EINVAL;
    double den = a * (4 - 2 * a - b);
    *ret_pos_var = s2 * (2 * a * a + b * (2 - 3 * a)) / den;
    *ret_vel_var = s2 * 2 * b * b / (dt_s * dt_s * den);
    return 0;
}

void trk_filter_q_axis (double sigma_mod_mps2, double dt_s, double ret_q[3])
{
    double v = sigma_mod_mps2 * sigma_mod_mps2, dt = fabs (dt_s);
    ret_q[0] = v * dt * dt * dt * dt / 4;
    ret_q[1] = v * dt * dt * dt / 2;
    ret_q[2] = v * dt * dt;
}

void trk_filter_predict (const trk_estimate_t *e, const trk_filter_params_t *p, double t_s,
                         trk_estimate_t *ret)
{
    double dt = t_s - e->t_s;
    const double *P = e->P;
    trk_estimate_t o;
    o.t_s = t_s;
    o.x[0] = e->x[0] + dt * e->x[2];
    o.x[1] = e->x[1] + dt * e->x[3];
    o.x[2] = e->x[2];
    o.x[3] = e->x[3];
    // Φ P Φᵀ with Φ = [I dt·I; 0 I]: A = Φ P, then A Φᵀ.
    double A[16];
    for (int j = 0; j < 4; j++) {
        A[0 * 4 + j] = P[0 * 4 + j] + dt * P[2 * 4 + j];
        A[1 * 4 + j] = P[1 * 4 + j] + dt * P[3 * 4 + j];
        A[2 * 4 + j] = P[2 * 4 + j];
        A[3 * 4 + j] = P[3 * 4 + j];
    }
    for (int i = 0; i < 4; i++) {
        o.P[i * 4 + 0] = A[i * 4 + 0] + dt * A[i * 4 + 2];
        o.P[i * 4 + 1] = A[i * 4 + 1] + dt * A[i * 4 + 3];
        o.P[i * 4 + 2] = A[i * 4 + 2];
        o.P[i * 4 + 3] = A[i * 4 + 3];
    }
    for (int a = 0; a < 2; a++) {
        double q[3];
        trk_filter_q_axis (p->sigma_mod_mps2[a], dt, q);
        o.P[a * 4 + a] += q[0];
        o.P[a * 4 + a + 2] += q[1];
        o.P[(a + 2) * 4 + a] += q[1];
        o.P[(a + 2) * 4 + a + 2] += q[2];
    }
    *ret = o;
}

/* S = H P Hᵀ + R and its inverse; false when S is not positive definite. */
static bool s_innovation_cov (const trk_estimate_t *pred, const double R[4], double S[4],
                              double Si[4], double *ret_det)
{
    S[0] = pred->P[0] + R[0];
    S[1] = pred->P[1] + R[1];
    S[2] = pred->P[4] + R[2];
    S[3] = pred->P[5] + R[3];
    double det = S[0] * S[3] - S[1] * S[2];
    if (!(S[0] > 0) || !(det > 0) || !isfinite (det))
        return false;
    Si[0] = S[3] / det;
    Si[1] = -S[1] / det;
    Si[2] = -S[2] / det;
    Si[3] = S[0] / det;
    *ret_det = det;
    return true;
}

double trk_filter_distance (const trk_estimate_t *pred, const double z[2], const double R[4],
                            double *ret_log_det)
{
    double S[4], Si[4], det;
    if (!s_innovation_cov (pred, R, S, Si, &det))
        return -1;
    double v0 = z[0] - pred->x[0], v1 = z[1] - pred->x[1];
    if (ret_log_det)
        *ret_log_det = log (det);
    return v0 * (Si[0] * v0 + Si[1] * v1) + v1 * (Si[2] * v0 + Si[3] * v1);
}

int trk_filter_kalman_gain (const trk_estimate_t *pred, const double R[4], double ret_K[8])
{
    double S[4], Si[4], det;
    if (!s_innovation_cov (pred, R, S, Si, &det))
        return -EDOM;
    // K = P Hᵀ S⁻¹: P Hᵀ is P's first two columns.
    for (int i = 0; i < 4; i++) {
        double a = pred->P[i * 4 + 0], b = pred->P[i * 4 + 1];
        ret_K[i * 2 + 0] = a * Si[0] + b * Si[2];
        ret_K[i * 2 + 1] = a * Si[1] + b * Si[3];
    }
    return 0;
}

int trk_filter_update (trk_estimate_t *pred, const trk_filter_params_t *p,
                       const trk_gains_t gains[2], const double z[2], const double R[4])
{
    double K[8];
    if (p->mode != TRK_FILTER_PAPER) {
        if (trk_filter_kalman_gain (pred, R, K) < 0)
            return -EDOM;
    } else {
        memset (K, 0, sizeof K);
        K[0 * 2 + 0] = gains[0].g;
        K[1 * 2 + 1] = gains[1].g;
        K[2 * 2 + 0] = gains[0].gd_hz;
        K[3 * 2 + 1] = gains[1].gd_hz;
    }
    double v0 = z[0] - pred->x[0], v1 = z[1] - pred->x[1];
    // Joseph form: P = (I − K H) P (I − K H)ᵀ + K R Kᵀ, right for any gain.
    double IKH[16], A[16], Pn[16];
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 4; j++)
            IKH[i * 4 + j] = (i == j) - (j < 2 ? K[i * 2 + j] : 0);
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 4; j++) {
            double s = 0;
            for (int k = 0; k < 4; k++)
                s += IKH[i * 4 + k] * pred->P[k * 4 + j];
            A[i * 4 + j] = s;
        }
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 4; j++) {
            double s = 0;
            for (int k = 0; k < 4; k++)
                s += A[i * 4 + k] * IKH[j * 4 + k];
            double kr0 = K[i * 2 + 0] * R[0] + K[i * 2 + 1] * R[2];
            double kr1 = K[i * 2 + 0] * R[1] + K[i * 2 + 1] * R[3];
            s += kr0 * K[j * 2 + 0] + kr1 * K[j * 2 + 1];
            Pn[i * 4 + j] = s;
        }
    for (int i = 0; i < 4; i++) {
        pred->x[i] += K[i * 2 + 0] * v0 + K[i * 2 + 1] * v1;
        for (int j = 0; j < 4; j++) // keep P exactly symmetric
            pred->P[i * 4 + j] = i <= j ? (Pn[i * 4 + j] + Pn[j * 4 + i]) / 2 : pred->P[j * 4 + i];
    }
    return 0;
}

void trk_filter_init_one (trk_estimate_t *ret, const double z[2], const double R[4], double t_s,
                          double v0_sigma_mps)
{
    memset (ret, 0, sizeof *ret);
    ret->x[0] = z[0];
    ret->x[1] = z[1];
    ret->t_s = t_s;
    ret->P[0] = R[0];
    ret->P[1] = R[1];
    ret->P[4] = R[2];
    ret->P[5] = R[3];
    ret->P[10] = ret->P[15] = v0_sigma_mps * v0_sigma_mps;
}

int trk_filter_init_two (trk_estimate_t *ret, const double z1[2], const double R1[4], double t1_s,
                         const double z2[2], const double R2[4], double t2_s)
{
    double dt = t2_s - t1_s;
    if (!(dt > 0))
        return -EINVAL;
    memset (ret, 0, sizeof *ret);
    ret->t_s = t2_s;
    for (int a = 0; a < 2; a++) {
        ret->x[a] = z2[a];
        ret->x[a + 2] = (z2[a] - z1[a]) / dt;
    }
    // x = z2, v = (z2 − z1)/dt: cov(x) = R2, cov(x, v) = R2/dt, cov(v) = (R1 + R2)/dt².
    for (int i = 0; i < 2; i++)
        for (int j = 0; j < 2; j++) {
            double r2 = R2[i * 2 + j], r1 = R1[i * 2 + j];
            ret->P[i * 4 + j] = r2;
            ret->P[i * 4 + j + 2] = r2 / dt;
            ret->P[(i + 2) * 4 + j] = r2 / dt;
            ret->P[(i + 2) * 4 + j + 2] = (r1 + r2) / (dt * dt);
        }
    return 0;
}

void trk_filter_polar_covariance (double ground_range_m, double azimuth_deg, double range_sigma_m,
                                  double azimuth_sigma_deg, double ret_R[4])
{
    double az = azimuth_deg * S_PI / 180;
    double ue = sin (az), un = cos (az);  // along the line of sight
    double ce = cos (az), cn = -sin (az); // across it
    double sr = range_sigma_m * range_sigma_m;
    double sc = ground_range_m * azimuth_sigma_deg * S_PI / 180;
    sc *= sc;
    ret_R[0] = sr * ue * ue + sc * ce * ce;
    ret_R[1] = ret_R[2] = sr * ue * un + sc * ce * cn;
    ret_R[3] = sr * un * un + sc * cn * cn;
}
