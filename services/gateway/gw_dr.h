/* gw_dr — DIS dead reckoning (IEEE 1278.1 annex E) and the rotations it
 * needs. Orientation is a matrix R taking world (ECEF) axes to the entity's
 * body axes (x forward, y right, z down): R = Rx(phi) Ry(theta) Rz(psi) from
 * the DIS Euler angles. A body turning at angular velocity w (body axes)
 * follows dR/dt = -[w]x R, so after t it is exp(-[w]x t) R. Pure. */
#ifndef GW_DR_H
#define GW_DR_H

#include <stdbool.h>
#include <stdint.h>

typedef struct {
    uint8_t algorithm; // GW_DR_*
    double pos[3];     // ECEF, metres
    double vel[3];     // m/s, world axes (body axes for the B algorithms)
    double acc[3];     // m/s², same axes as vel
    double R[3][3];    // world to body
    double omega[3];   // rad/s, body axes
} gw_dr_t;

/* R from DIS Euler angles psi, theta, phi (radians). */
void gw_dr_rot_from_euler (const double e[3], double R[3][3]);
/* DIS Euler angles of R: psi in (-pi, pi], theta in [-pi/2, pi/2], phi in (-pi, pi]. */
void gw_dr_euler_from_rot (const double R[3][3], double e[3]);
/* The angle, radians in [0, pi], of the rotation between A and B. */
double gw_dr_rot_angle (const double A[3][3], const double B[3][3]);
/* The body angular velocity that turns R0 into R1 in dt seconds (> 0). */
void gw_dr_omega (const double R0[3][3], const double R1[3][3], double dt, double ret_omega[3]);
/* R turned by body angular velocity omega for t seconds. */
void gw_dr_rotate (const double R[3][3], const double omega[3], double t, double ret_R[3][3]);
/* Whether the algorithm turns the orientation (R*), uses acceleration (*V*),
 * and keeps velocity in body axes (*B). */
bool gw_dr_rotates (uint8_t algorithm);
bool gw_dr_accelerates (uint8_t algorithm);
bool gw_dr_body (uint8_t algorithm);
/* Where the state's algorithm puts the entity t seconds after it: position
 * and orientation. Static, Other and unknown algorithms stand still. The
 * body-axis algorithms take velocity and acceleration to world axes with
 * the orientation at the start (a first-order form of annex E's). */
void gw_dr_at (const gw_dr_t *s, double t, double ret_pos[3], double ret_R[3][3]);

#endif
