/* test_gw_dr — DIS dead reckoning (IEEE 1278.1 annex E) against theory: the
 * Euler-angle matrix against the product of its three elementary rotations,
 * a level body turning at a constant yaw rate against psi + w t, body rates
 * recovered from two orientations, the angle of rotations built here by
 * Rodrigues' formula, and each algorithm's position against its kinematics
 * (p + v t, p + v t + a t²/2, R^T v_b for the body-axis ones). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "gw_dr.h"
#include "gw_pdu.h"

#include <math.h>
#include <string.h>

#include "test_util.h"

#define DEG (M_PI / 180.0)

/* The elementary (passive) rotations: coordinates in axes turned by a about x, y, z. */
static void s_rx (double a, double R[3][3])
{
    double c = cos (a), s = sin (a);
    double M[3][3] = {{1, 0, 0}, {0, c, s}, {0, -s, c}};
    memcpy (R, M, sizeof M);
}
static void s_ry (double a, double R[3][3])
{
    double c = cos (a), s = sin (a);
    double M[3][3] = {{c, 0, -s}, {0, 1, 0}, {s, 0, c}};
    memcpy (R, M, sizeof M);
}
static void s_rz (double a, double R[3][3])
{
    double c = cos (a), s = sin (a);
    double M[3][3] = {{c, s, 0}, {-s, c, 0}, {0, 0, 1}};
    memcpy (R, M, sizeof M);
}
static void s_mul (const double A[3][3], const double B[3][3], double C[3][3])
{
    double T[3][3] = {{0}};
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            for (int k = 0; k < 3; k++)
                T[i][j] += A[i][k] * B[k][j];
    memcpy (C, T, sizeof T);
}
/* Rotation by angle a about unit axis n (Rodrigues, written out here). */
static void s_axis_angle (const double n[3], double a, double R[3][3])
{
    double c = cos (a), s = sin (a), v = 1 - c;
    double M[3][3] = {
        {c + n[0] * n[0] * v, n[0] * n[1] * v - n[2] * s, n[0] * n[2] * v + n[1] * s},
        {n[1] * n[0] * v + n[2] * s, c + n[1] * n[1] * v, n[1] * n[2] * v - n[0] * s},
        {n[2] * n[0] * v - n[1] * s, n[2] * n[1] * v + n[0] * s, c + n[2] * n[2] * v},
    };
    memcpy (R, M, sizeof M);
}
static void s_assert_mat (const double A[3][3], const double B[3][3], double tol)
{
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            if (!(fabs (A[i][j] - B[i][j]) <= tol))
                fail_msg ("[%d][%d]: %.15g, want %.15g", i, j, A[i][j], B[i][j]);
}

static const double s_angles[][3] = {
    {0, 0, 0},
    {30 * DEG, 0, 0},
    {-170 * DEG, 10 * DEG, 5 * DEG},
    {179 * DEG, -45 * DEG, 90 * DEG},
    {1.0, 0.3, -2.5},
    {-0.7, 1.2, 3.0},
    {2.2, -1.5, -0.4},
};
#define S_N_ANGLES (sizeof s_angles / sizeof s_angles[0])

static void test_euler (void **state)
{
    (void)state;
    for (size_t k = 0; k < S_N_ANGLES; k++) {
        const double *e = s_angles[k];
        double R[3][3], X[3][3], Y[3][3], Z[3][3], W[3][3], back[3];
        gw_dr_rot_from_euler (e, R);
        s_rx (e[2], X), s_ry (e[1], Y), s_rz (e[0], Z);
        s_mul (Y, Z, W);
        s_mul (X, W, W); // Rx(phi) Ry(theta) Rz(psi)
        s_assert_mat (R, W, 1e-15);
        gw_dr_euler_from_rot (R, back);
        assert_angle_rad (back[0], e[0], 1e-12);
        assert_near (back[1], e[1], 1e-12);
        assert_angle_rad (back[2], e[2], 1e-12);
    }
    // Worked: heading 90° about z: forward (row 0) is world +y; pitch 30° up tilts
    // forward towards world -z (DIS's z about which psi turns points down here).
    double R[3][3];
    gw_dr_rot_from_euler ((double[3]){90 * DEG, 0, 0}, R);
    assert_near (R[0][0], 0, 1e-15);
    assert_near (R[0][1], 1, 1e-15);
    gw_dr_rot_from_euler ((double[3]){0, 30 * DEG, 0}, R);
    assert_near (R[0][0], cos (30 * DEG), 1e-15);
    assert_near (R[0][2], -0.5, 1e-15);
}

static void test_rotate (void **state)
{
    (void)state;
    // A level body turning at a constant yaw rate w about its z axis: psi + w t.
    const double psi0 = 20 * DEG, w = 0.1;
    const double ts[] = {0.0, 0.5, 3.0, 10.0, 40.0}; // 40 s: 4 rad, past the wrap
    double R0[3][3], R[3][3], e[3];
    gw_dr_rot_from_euler ((double[3]){psi0, 0, 0}, R0);
    for (size_t i = 0; i < sizeof ts / sizeof ts[0]; i++) {
        gw_dr_rotate (R0, (double[3]){0, 0, w}, ts[i], R);
        gw_dr_euler_from_rot (R, e);
        assert_angle_rad (e[0], psi0 + w * ts[i], 1e-12);
        assert_near (e[1], 0, 1e-12);
        assert_angle_rad (e[2], 0, 1e-12);
    }
    // In any attitude, turning about a body axis at rate w for t is the elementary
    // rotation by w t about that axis applied on the body side: Rz(w t) R0, Rx(w t) R0.
    const double t = 2.5;
    double E[3][3], W[3][3];
    for (size_t k = 0; k < S_N_ANGLES; k++) {
        gw_dr_rot_from_euler (s_angles[k], R0);
        gw_dr_rotate (R0, (double[3]){0, 0, w}, t, R);
        s_rz (w * t, E);
        s_mul (E, R0, W);
        s_assert_mat (R, W, 1e-14);
        gw_dr_rotate (R0, (double[3]){-0.3, 0, 0}, t, R);
        s_rx (-0.3 * t, E);
        s_mul (E, R0, W);
        s_assert_mat (R, W, 1e-14);
    }
}

static void test_omega (void **state)
{
    (void)state;
    const double ws[][3] = {{0.05, -0.02, 0.3}, {0, 0, 0}, {1e-7, 0, 0}, {-0.8, 0.5, 0.1}};
    const double dt = 0.5;
    for (size_t k = 0; k < S_N_ANGLES; k++)
        for (size_t j = 0; j < sizeof ws / sizeof ws[0]; j++) {
            double R0[3][3], R1[3][3], w[3];
            gw_dr_rot_from_euler (s_angles[k], R0);
            gw_dr_rotate (R0, ws[j], dt, R1);
            gw_dr_omega (R0, R1, dt, w);
            for (int i = 0; i < 3; i++)
                assert_near (w[i], ws[j][i], 1e-12);
        }
    // Independently: R1 = Ry(0.2) R0 over 0.4 s is 0.5 rad/s about body y.
    double R0[3][3], E[3][3], R1[3][3], w[3];
    gw_dr_rot_from_euler (s_angles[4], R0);
    s_ry (0.2, E);
    s_mul (E, R0, R1);
    gw_dr_omega (R0, R1, 0.4, w);
    assert_near (w[0], 0, 1e-13);
    assert_near (w[1], 0.5, 1e-13);
    assert_near (w[2], 0, 1e-13);
}

static void test_rot_angle (void **state)
{
    (void)state;
    double n[3] = {1, 2, -2}; // |n| = 3
    for (int i = 0; i < 3; i++)
        n[i] /= 3;
    const double as[] = {0, 1e-6, 10 * DEG, 90 * DEG, 170 * DEG, 180 * DEG};
    for (size_t k = 0; k < S_N_ANGLES; k++)
        for (size_t j = 0; j < sizeof as / sizeof as[0]; j++) {
            double A[3][3], E[3][3], B[3][3];
            gw_dr_rot_from_euler (s_angles[k], A);
            s_axis_angle (n, as[j], E);
            s_mul (E, A, B); // on the body side
            assert_near (gw_dr_rot_angle (A, B), as[j], 1e-12);
            s_mul (A, E, B); // on the world side: the same angle
            assert_near (gw_dr_rot_angle (A, B), as[j], 1e-12);
        }
}

static void test_flags (void **state)
{
    (void)state;
    // Annex E names: F/R (fixed or rotating), P/V (position or velocity: the V ones
    // use acceleration), W/B (world or body axes).
    const struct {
        uint8_t a;
        bool rot, acc, body;
    } f[] = {
        {GW_DR_OTHER, 0, 0, 0}, {GW_DR_STATIC, 0, 0, 0}, {GW_DR_FPW, 0, 0, 0}, {GW_DR_RPW, 1, 0, 0},
        {GW_DR_RVW, 1, 1, 0},   {GW_DR_FVW, 0, 1, 0},    {GW_DR_FPB, 0, 0, 1}, {GW_DR_RPB, 1, 0, 1},
        {GW_DR_RVB, 1, 1, 1},   {GW_DR_FVB, 0, 1, 1},    {10, 0, 0, 0},        {255, 0, 0, 0},
    };
    for (size_t i = 0; i < sizeof f / sizeof f[0]; i++) {
        assert_int_equal (gw_dr_rotates (f[i].a), f[i].rot);
        assert_int_equal (gw_dr_accelerates (f[i].a), f[i].acc);
        assert_int_equal (gw_dr_body (f[i].a), f[i].body);
    }
}

static void s_state (gw_dr_t *s, uint8_t algorithm, const double euler[3])
{
    memset (s, 0, sizeof *s);
    s->algorithm = algorithm;
    s->pos[0] = -2700000.0, s->pos[1] = -4300000.0, s->pos[2] = 3700000.0;
    s->vel[0] = 10.0, s->vel[1] = -4.0, s->vel[2] = 2.0;
    s->acc[0] = 0.5, s->acc[1] = 1.0, s->acc[2] = -2.0;
    s->omega[0] = 0.0, s->omega[1] = 0.0, s->omega[2] = 0.2;
    gw_dr_rot_from_euler (euler, s->R);
}

static void test_at (void **state)
{
    (void)state;
    const double t = 3.0, e0[3] = {0.4, 0.1, -0.2};
    gw_dr_t s;
    double pos[3], R[3][3], E[3][3], W[3][3];
    // FPW: p + v t, orientation unchanged.
    s_state (&s, GW_DR_FPW, e0);
    gw_dr_at (&s, t, pos, R);
    for (int i = 0; i < 3; i++)
        assert_near (pos[i], s.pos[i] + s.vel[i] * t, 1e-6);
    s_assert_mat (R, s.R, 0);
    // RVW: p + v t + a t²/2, turned by 0.2 rad/s about body z.
    s_state (&s, GW_DR_RVW, e0);
    gw_dr_at (&s, t, pos, R);
    assert_near (pos[0], -2700000.0 + 30.0 + 2.25, 1e-6);
    assert_near (pos[1], -4300000.0 - 12.0 + 4.5, 1e-6);
    assert_near (pos[2], 3700000.0 + 6.0 - 9.0, 1e-6);
    s_rz (0.2 * t, E);
    s_mul (E, s.R, W);
    s_assert_mat (R, W, 1e-14);
    // FVW accelerates without turning; RPW turns without accelerating.
    s_state (&s, GW_DR_FVW, e0);
    gw_dr_at (&s, t, pos, R);
    assert_near (pos[2], 3700000.0 + 6.0 - 9.0, 1e-6);
    s_assert_mat (R, s.R, 0);
    s_state (&s, GW_DR_RPW, e0);
    gw_dr_at (&s, t, pos, R);
    assert_near (pos[2], 3700000.0 + 6.0, 1e-6);
    s_assert_mat (R, W, 1e-14);
    // Static, Other and an unknown algorithm stand still, whatever the velocity says.
    const uint8_t still[] = {GW_DR_STATIC, GW_DR_OTHER, 42};
    for (size_t k = 0; k < sizeof still; k++) {
        s_state (&s, still[k], e0);
        gw_dr_at (&s, t, pos, R);
        for (int i = 0; i < 3; i++)
            assert_true (pos[i] == s.pos[i]);
        s_assert_mat (R, s.R, 0);
    }
    // FPB: heading 90° (forward is world +y), 10 m/s forward and 1 m/s right
    // (right is world -x): world velocity R^T v_b = (-1, 10, 0).
    s_state (&s, GW_DR_FPB, (double[3]){90 * DEG, 0, 0});
    s.vel[0] = 10, s.vel[1] = 1, s.vel[2] = 0;
    gw_dr_at (&s, t, pos, R);
    assert_near (pos[0], -2700000.0 - 3.0, 1e-6);
    assert_near (pos[1], -4300000.0 + 30.0, 1e-6);
    assert_near (pos[2], 3700000.0, 1e-6);
    // FVB: 2 m/s² forward with pitch 30° up: world acceleration (cos 30, 0, -sin 30) · 2.
    s_state (&s, GW_DR_FVB, (double[3]){0, 30 * DEG, 0});
    s.vel[0] = s.vel[1] = s.vel[2] = 0;
    s.acc[0] = 2, s.acc[1] = s.acc[2] = 0;
    gw_dr_at (&s, t, pos, R);
    assert_near (pos[0], -2700000.0 + 9.0 * cos (30 * DEG), 1e-6);
    assert_near (pos[2], 3700000.0 - 9.0 * 0.5, 1e-6);
    // t = 0 is the state itself for every algorithm.
    for (uint8_t a = 0; a <= 9; a++) {
        s_state (&s, a, e0);
        gw_dr_at (&s, 0, pos, R);
        for (int i = 0; i < 3; i++)
            assert_true (pos[i] == s.pos[i]);
        s_assert_mat (R, s.R, 0);
    }
}

int main (void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test (test_euler), cmocka_unit_test (test_rotate),
        cmocka_unit_test (test_omega), cmocka_unit_test (test_rot_angle),
        cmocka_unit_test (test_flags), cmocka_unit_test (test_at),
    };
    return cmocka_run_group_tests (tests, NULL, NULL);
}
