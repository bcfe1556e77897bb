/* gw_dr — DIS dead reckoning and rotations. */
#include "gw_dr.h"

#include "gw_pdu.h"

#include <math.h>
#include <string.h>

static void s_mul (const double A[3][3], const double B[3][3], double C[3][3])
{
    double T[3][3];
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            T[i][j] = A[i][0] * B[0][j] + A[i][1] * B[1][j] + A[i][2] * B[2][j];
    memcpy (C, T, sizeof T);
}

/* A times B transposed. */
static void s_mul_t (const double A[3][3], const double B[3][3], double C[3][3])
{
    double T[3][3];
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            T[i][j] = A[i][0] * B[j][0] + A[i][1] * B[j][1] + A[i][2] * B[j][2];
    memcpy (C, T, sizeof T);
}

void gw_dr_rot_from_euler (const double e[3], double R[3][3])
{
    double cp = cos (e[0]), sp = sin (e[0]);
    double ct = cos (e[1]), st = sin (e[1]);
    double cf = cos (e[2]), sf = sin (e[2]);
    R[0][0] = ct * cp;
    R[0][1] = ct * sp;
    R[0][2] = -st;
    R[1][0] = sf * st * cp - cf * sp;
    R[1][1] = sf * st * sp + cf * cp;
    R[1][2] = sf * ct;
    R[2][0] = cf * st * cp + sf * sp;
    R[2][1] = cf * st * sp - sf * cp;
    R[2][2] = cf * ct;
}

void gw_dr_euler_from_rot (const double R[3][3], double e[3])
{
    double s = -R[0][2];
    s = s > 1 ? 1 : s < -1 ? -1 : s;
    e[0] = atan2 (R[0][1], R[0][0]);
    e[1] = asin (s);
    e[2] = atan2 (R[1][2], R[2][2]);
}

double gw_dr_rot_angle (const double A[3][3], const double B[3][3])
{
    double M[3][3];
    s_mul_t (A, B, M);
    // The axis part (M - Mt)/2 = sin(a)·n and the trace part (tr M - 1)/2 = cos(a)
    // together give the angle well conditioned at every size.
    double x = M[2][1] - M[1][2], y = M[0][2] - M[2][0], z = M[1][0] - M[0][1];
    double s = 0.5 * sqrt (x * x + y * y + z * z);
    double c = 0.5 * (M[0][0] + M[1][1] + M[2][2] - 1);
    return atan2 (s, c);
}

void gw_dr_omega (const double R0[3][3], const double R1[3][3], double dt, double ret_omega[3])
{
    // exp(-[w]x dt) = R1 R0t = M; M = exp([a]x) with a the rotation vector.
    double M[3][3];
    s_mul_t (R1, R0, M);
    double x = 0.5 * (M[2][1] - M[1][2]), y = 0.5 * (M[0][2] - M[2][0]),
           z = 0.5 * (M[1][0] - M[0][1]);
    double s = sqrt (x * x + y * y + z * z);
    double c = 0.5 * (M[0][0] + M[1][1] + M[2][2] - 1);
    double angle = atan2 (s, c);
    double k = s > 1e-12 ? angle / s : 1.0; // angle/sin(angle) -> 1 as the angle -> 0
    ret_omega[0] = -k * x / dt;
    ret_omega[1] = -k * y / dt;
    ret_omega[2] = -k * z / dt;
}

void gw_dr_rotate (const double R[3][3], const double omega[3], double t, double ret_R[3][3])
{
    // Rodrigues: exp([a]x) with a = -omega t.
    double a[3] = {-omega[0] * t, -omega[1] * t, -omega[2] * t};
    double th = sqrt (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
    if (th < 1e-15) {
        memcpy (ret_R, R, sizeof (double[3][3]));
        return;
    }
    double n[3] = {a[0] / th, a[1] / th, a[2] / th};
    double c = cos (th), s = sin (th), v = 1 - c;
    double E[3][3] = {
        {c + n[0] * n[0] * v, n[0] * n[1] * v - n[2] * s, n[0] * n[2] * v + n[1] * s},
        {n[1] * n[0] * v + n[2] * s, c + n[1] * n[1] * v, n[1] * n[2] * v - n[0] * s},
        {n[2] * n[0] * v - n[1] * s, n[2] * n[1] * v + n[0] * s, c + n[2] * n[2] * v},
    };
    s_mul (E, R, ret_R);
}

bool gw_dr_rotates (uint8_t a)
{
    return a == GW_DR_RPW || a == GW_DR_RVW || a == GW_DR_RPB || a == GW_DR_RVB;
}

bool gw_dr_accelerates (uint8_t a)
{
    return a == GW_DR_RVW || a == GW_DR_FVW || a == GW_DR_RVB || a == GW_DR_FVB;
}

bool gw_dr_body (uint8_t a)
{
    return a >= GW_DR_FPB && a <= GW_DR_FVB;
}

void gw_dr_at (const gw_dr_t *s, double t, double ret_pos[3], double ret_R[3][3])
{
    uint8_t a = s->algorithm;
    bool moves = a >= GW_DR_FPW && a <= GW_DR_FVB;
    double v[3], acc[3];
    for (int i = 0; i < 3; i++) {
        v[i] = moves ? s->vel[i] : 0;
        acc[i] = moves && gw_dr_accelerates (a) ? s->acc[i] : 0;
    }
    if (moves && gw_dr_body (a)) {
        // World = Rt body.
        double vw[3], aw[3];
        for (int i = 0; i < 3; i++) {
            vw[i] = s->R[0][i] * v[0] + s->R[1][i] * v[1] + s->R[2][i] * v[2];
            aw[i] = s->R[0][i] * acc[0] + s->R[1][i] * acc[1] + s->R[2][i] * acc[2];
        }
        memcpy (v, vw, sizeof v);
        memcpy (acc, aw, sizeof acc);
    }
    for (int i = 0; i < 3; i++)
        ret_pos[i] = s->pos[i] + v[i] * t + 0.5 * acc[i] * t * t;
    if (moves && gw_dr_rotates (a))
        gw_dr_rotate (s->R, s->omega, t, ret_R);
    else
        memcpy (ret_R, s->R, sizeof (double[3][3]));
}
