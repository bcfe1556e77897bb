/* trk_imm — the interacting multiple model filter (see trk_imm.h). */
#include "trk_imm.h"

#include <errno.h>
#include <math.h>
#include <string.h>

#define S_LOG_2PI 1.8378770664093454836

void trk_imm_init (trk_imm_t *s, const trk_estimate_t *e, const double mu0[TRK_IMM_MODELS])
{
    for (int j = 0; j < TRK_IMM_MODELS; j++) {
        s->m[j] = *e;
        s->mu[j] = mu0[j];
    }
}

void trk_imm_transition (const trk_imm_params_t *p, double dt_s, double ret_pi[9])
{
    double dt = fabs (dt_s);
    for (int i = 0; i < TRK_IMM_MODELS; i++) {
        double stay = exp (-dt / p->sojourn_s[i]);
        for (int j = 0; j < TRK_IMM_MODELS; j++)
            ret_pi[i * 3 + j] = i == j ? stay : (1 - stay) * p->exit[i][j];
    }
}

/* e's mean and covariance moment-matched over weights w (summing to 1). */
static void s_moments (const trk_estimate_t *e, const double *w, trk_estimate_t *ret)
{
    trk_estimate_t o;
    memset (&o, 0, sizeof o);
    o.t_s = e[0].t_s;
    for (int j = 0; j < TRK_IMM_MODELS; j++)
        for (int a = 0; a < 4; a++)
            o.x[a] += w[j] * e[j].x[a];
    for (int j = 0; j < TRK_IMM_MODELS; j++) {
        double d[4];
        for (int a = 0; a < 4; a++)
            d[a] = e[j].x[a] - o.x[a];
        for (int a = 0; a < 4; a++)
            for (int b = 0; b < 4; b++)
                o.P[a * 4 + b] += w[j] * (e[j].P[a * 4 + b] + d[a] * d[b]);
    }
    *ret = o;
}

void trk_imm_mix (const trk_imm_params_t *p, const trk_imm_t *s, double dt_s, trk_imm_t *ret)
{
    double pi[9];
    trk_imm_transition (p, dt_s, pi);
    trk_imm_t o;
    for (int j = 0; j < TRK_IMM_MODELS; j++) {
        double c = 0, w[TRK_IMM_MODELS];
        for (int i = 0; i < TRK_IMM_MODELS; i++)
            c += pi[i * 3 + j] * s->mu[i];
        for (int i = 0; i < TRK_IMM_MODELS; i++)
            w[i] = c > 0 ? pi[i * 3 + j] * s->mu[i] / c : (i == j);
        s_moments (s->m, w, &o.m[j]);
        o.mu[j] = c;
    }
    *ret = o;
}

void trk_imm_predict_model (const trk_imm_params_t *p, trk_model_t j, const trk_estimate_t *e,
                            double t_s, trk_estimate_t *ret)
{
    if (j == TRK_MODEL_STOPPED) {
        // Φ = diag(1, 1, 0, 0): the position held, the velocity zero.
        trk_estimate_t o;
        memset (&o, 0, sizeof o);
        o.t_s = t_s;
        o.x[0] = e->x[0];
        o.x[1] = e->x[1];
        o.P[0] = e->P[0];
        o.P[1] = e->P[1];
        o.P[4] = e->P[4];
        o.P[5] = e->P[5];
        o.P[10] = o.P[15] = p->stopped_sigma_mps * p->stopped_sigma_mps;
        *ret = o;
        return;
    }
    trk_filter_params_t fp = {.mode = TRK_FILTER_KALMAN, .dt_s = 1};
    fp.sigma_mod_mps2[0] = fp.sigma_mod_mps2[1] = p->sigma_mps2[j];
    trk_estimate_t o;
    trk_filter_predict (e, &fp, t_s, &o);
    if (p->max_speed_mps > 0) {
        double v2 = p->max_speed_mps * p->max_speed_mps / 4, dt = fabs (t_s - e->t_s), d[4];
        for (int a = 0; a < 2; a++) {
            double pos = e->P[a * 5] + v2 * dt * dt;
            d[a] = o.P[a * 5] > pos ? sqrt (pos / o.P[a * 5]) : 1;
            d[a + 2] = o.P[(a + 2) * 5] > v2 ? sqrt (v2 / o.P[(a + 2) * 5]) : 1;
        }
        for (int a = 0; a < 4; a++)
            for (int b = 0; b < 4; b++)
                o.P[a * 4 + b] *= d[a] * d[b];
    }
    *ret = o;
}

void trk_imm_predict (const trk_imm_params_t *p, const trk_imm_t *s, double t_s, trk_imm_t *ret)
{
    trk_imm_t o;
    for (int j = 0; j < TRK_IMM_MODELS; j++) {
        trk_imm_predict_model (p, (trk_model_t)j, &s->m[j], t_s, &o.m[j]);
        o.mu[j] = s->mu[j];
    }
    *ret = o;
}

void trk_imm_combine (const trk_imm_t *s, trk_estimate_t *ret)
{
    s_moments (s->m, s->mu, ret);
}

/* ---- the measurement ------------------------------------------------------------ */

/* H (rows: east, north, radial) and the innovation of m against pred;
 * returns the dimension. */
static int s_model (const trk_estimate_t *pred, const trk_meas_t *m, double H[3][4], double nu[3],
                    double R[9])
{
    int k = m->has_radial ? 3 : 2;
    memset (H, 0, sizeof (double[3][4]));
    memset (R, 0, 9 * sizeof *R);
    H[0][0] = H[1][1] = 1;
    nu[0] = m->z[0] - pred->x[0];
    nu[1] = m->z[1] - pred->x[1];
    R[0] = m->R[0];
    R[1] = m->R[1];
    R[k] = m->R[2];
    R[k + 1] = m->R[3];
    if (k == 3) {
        H[2][2] = m->los[0];
        H[2][3] = m->los[1];
        double v = m->radial_mps - (m->los[0] * pred->x[2] + m->los[1] * pred->x[3]);
        if (m->span_mps > 0)
            v -= m->span_mps * round (v / m->span_mps);
        nu[2] = v;
        R[8] = m->radial_var;
    }
    return k;
}

/* S = H P Hᵀ + R (k×k) and its inverse; false unless positive definite. */
static bool s_innovation (const trk_estimate_t *pred, double H[3][4], const double R[9], int k,
                          double PHt[4][3], double S[9], double Si[9], double *ret_det)
{
    for (int a = 0; a < 4; a++)
        for (int r = 0; r < k; r++) {
            double s = 0;
            for (int b = 0; b < 4; b++)
                s += pred->P[a * 4 + b] * H[r][b];
            PHt[a][r] = s;
        }
    for (int r = 0; r < k; r++)
        for (int c = 0; c < k; c++) {
            double s = R[r * k + c];
            for (int a = 0; a < 4; a++)
                s += H[r][a] * PHt[a][c];
            S[r * k + c] = s;
        }
    double det;
    if (k == 2) {
        det = S[0] * S[3] - S[1] * S[2];
        if (!(S[0] > 0) || !(det > 0) || !isfinite (det))
            return false;
        Si[0] = S[3] / det;
        Si[1] = -S[1] / det;
        Si[2] = -S[2] / det;
        Si[3] = S[0] / det;
    } else {
        double a = S[0], b = S[1], c = S[2], d = S[3], e = S[4], f = S[5], g = S[6], h = S[7],
               i = S[8];
        double A = e * i - f * h, B = -(d * i - f * g), C = d * h - e * g;
        det = a * A + b * B + c * C;
        if (!(a > 0) || !(a * e - b * d > 0) || !(det > 0) || !isfinite (det))
            return false;
        Si[0] = A / det;
        Si[1] = -(b * i - c * h) / det;
        Si[2] = (b * f - c * e) / det;
        Si[3] = B / det;
        Si[4] = (a * i - c * g) / det;
        Si[5] = -(a * f - c * d) / det;
        Si[6] = C / det;
        Si[7] = -(a * h - b * g) / det;
        Si[8] = (a * e - b * d) / det;
    }
    *ret_det = det;
    return true;
}

static double s_quad (const double Si[9], const double nu[3], int k)
{
    double d2 = 0;
    for (int r = 0; r < k; r++)
        for (int c = 0; c < k; c++)
            d2 += nu[r] * Si[r * k + c] * nu[c];
    return d2;
}

double trk_meas_distance (const trk_estimate_t *pred, const trk_meas_t *m, double *ret_log_det)
{
    double H[3][4], nu[3], R[9], PHt[4][3], S[9], Si[9], det;
    int k = s_model (pred, m, H, nu, R);
    if (!s_innovation (pred, H, R, k, PHt, S, Si, &det))
        return -1;
    if (ret_log_det)
        *ret_log_det = log (det);
    return s_quad (Si, nu, k);
}

/* The update proper; the distance and ln det S of the innovation. */
static int s_update (trk_estimate_t *pred, const trk_meas_t *m, double *ret_d2, double *ret_ld)
{
    double H[3][4], nu[3], R[9], PHt[4][3], S[9], Si[9], det;
    int k = s_model (pred, m, H, nu, R);
    if (!s_innovation (pred, H, R, k, PHt, S, Si, &det))
        return -EDOM;
    double K[4][3];
    for (int a = 0; a < 4; a++)
        for (int c = 0; c < k; c++) {
            double s = 0;
            for (int r = 0; r < k; r++)
                s += PHt[a][r] * Si[r * k + c];
            K[a][c] = s;
        }
    // Joseph form: P = (I − K H) P (I − K H)ᵀ + K R Kᵀ.
    double IKH[16], A[16], Pn[16];
    for (int a = 0; a < 4; a++)
        for (int b = 0; b < 4; b++) {
            double s = a == b;
            for (int r = 0; r < k; r++)
                s -= K[a][r] * H[r][b];
            IKH[a * 4 + b] = s;
        }
    for (int a = 0; a < 4; a++)
        for (int b = 0; b < 4; b++) {
            double s = 0;
            for (int c = 0; c < 4; c++)
                s += IKH[a * 4 + c] * pred->P[c * 4 + b];
            A[a * 4 + b] = s;
        }
    for (int a = 0; a < 4; a++)
        for (int b = 0; b < 4; b++) {
            double s = 0;
            for (int c = 0; c < 4; c++)
                s += A[a * 4 + c] * IKH[b * 4 + c];
            for (int r = 0; r < k; r++)
                for (int c = 0; c < k; c++)
                    s += K[a][r] * R[r * k + c] * K[b][c];
            Pn[a * 4 + b] = s;
        }
    for (int a = 0; a < 4; a++)
        for (int r = 0; r < k; r++)
            pred->x[a] += K[a][r] * nu[r];
    for (int a = 0; a < 4; a++)
        for (int b = 0; b < 4; b++)
            pred->P[a * 4 + b] = (Pn[a * 4 + b] + Pn[b * 4 + a]) / 2;
    if (ret_d2)
        *ret_d2 = s_quad (Si, nu, k);
    if (ret_ld)
        *ret_ld = log (det) + k * S_LOG_2PI;
    return 0;
}

int trk_meas_update (trk_estimate_t *pred, const trk_meas_t *m)
{
    return s_update (pred, m, NULL, NULL);
}

int trk_imm_update (trk_imm_t *pred, const trk_meas_t *m, const double pd[TRK_IMM_MODELS],
                    double *ret_lik)
{
    trk_imm_t o = *pred;
    double ll[TRK_IMM_MODELS], best = -INFINITY;
    bool any = false;
    for (int j = 0; j < TRK_IMM_MODELS; j++) {
        double d2, ld;
        if (s_update (&o.m[j], m, &d2, &ld) < 0) {
            ll[j] = -INFINITY;
            continue;
        }
        any = true;
        ll[j] = -0.5 * (d2 + ld); // ln N(ν; 0, S)
        best = fmax (best, ll[j]);
    }
    if (!any)
        return -EDOM;
    // μ_j ∝ c_j pd_j N_j, scaled by the best N to keep it in range; when the
    // radar could have seen the target in no model (pd all zero), by N alone.
    double w[TRK_IMM_MODELS], sum = 0, sum_n = 0;
    for (int j = 0; j < TRK_IMM_MODELS; j++) {
        double n = isfinite (ll[j]) ? exp (ll[j] - best) : 0;
        w[j] = pred->mu[j] * pd[j] * n;
        sum += w[j];
        sum_n += pred->mu[j] * n;
    }
    for (int j = 0; j < TRK_IMM_MODELS; j++) {
        double n = isfinite (ll[j]) ? exp (ll[j] - best) : 0;
        o.mu[j] = sum > 1e-300 ? w[j] / sum : pred->mu[j] * n / sum_n;
    }
    if (ret_lik)
        *ret_lik = exp (best) * (sum > 1e-300 ? sum : 0);
    *pred = o;
    return 0;
}

void trk_imm_miss (trk_imm_t *pred, const double pd[TRK_IMM_MODELS])
{
    double sum = 0, w[TRK_IMM_MODELS];
    for (int j = 0; j < TRK_IMM_MODELS; j++)
        sum += w[j] = pred->mu[j] * (1 - pd[j]);
    if (!(sum > 1e-300))
        return; // every model was sure to be seen: nothing to learn from the odds
    for (int j = 0; j < TRK_IMM_MODELS; j++)
        pred->mu[j] = w[j] / sum;
}
