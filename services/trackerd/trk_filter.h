/* trk_filter — the paper's Track & Update filter (section 4.2, equations 4–7)
 * on the state X = (x, y, vx, vy) in the local frame, and the full covariance
 * Kalman filter offered beside it for scans of varying length.
 *
 * Model: constant velocity with discrete white-noise acceleration per axis
 * (a piecewise-constant acceleration of standard deviation σ_mod over each
 * interval): Φ = [1 dt; 0 1], Q = σ_mod² [dt⁴/4 dt³/2; dt³/2 dt²]. The
 * measurement is the position, with standard deviation σ_meas per axis.
 *
 * The paper's constant gains per axis, computed once from the parameters:
 *   r   = 4 σ_meas / (σ_mod dt²)        (4 / Kalata's tracking index)
 *   g   = √(1+2r) ((√(1+2r) − 1) / r)²  (position)
 *   g_d = (2/dt) ((√(1+2r) − 1) / r)²   (velocity, per second)
 * are the steady-state Kalman gains of that model at the nominal dt.
 *
 * Both modes carry the 4×4 covariance P: the Kalman mode to compute its
 * gains, the paper's mode (propagated with its fixed gains in Joseph form)
 * to size the association gates. Pure: no logging, no globals. */
#ifndef TRK_FILTER_H
#define TRK_FILTER_H

#include <stdbool.h>

typedef enum {
    TRK_FILTER_PAPER = 0,  // the paper's constant gains
    TRK_FILTER_KALMAN = 1, // full covariance Kalman filter, gains from the actual dt
    TRK_FILTER_IMM = 2,    // interacting multiple models with state-dependent Pd (trk_imm)
} trk_filter_mode_t;

/* The filter's parameters. */
typedef struct {
    trk_filter_mode_t mode;
    double sigma_meas_m[2];   // measurement standard deviation per axis (east, north), metres
    double sigma_mod_mps2[2]; // model (acceleration) standard deviation per axis, m/s²
    double dt_s;              // nominal scan interval: the paper's gains are computed for it
    bool dt_auto;             // the paper's gains per update from its own interval (the radar's
                              // revisit of the track's cell, times the scans missed), not from dt_s
} trk_filter_params_t;

/* The paper's gains of one axis. */
typedef struct {
    double r;     // 4 σ_meas / (σ_mod dt²)
    double g;     // position gain (dimensionless)
    double gd_hz; // velocity gain, 1/s
} trk_gains_t;

/* A track's estimate: the state at time t_s and its covariance. */
typedef struct {
    double x[4];  // east_m, north_m, ve_mps, vn_mps
    double P[16]; // covariance, row-major, same order
    double t_s;   // simulation time of the estimate
} trk_estimate_t;

/* The paper's gains for one axis; 0, or -EINVAL unless every input is
 * positive and finite. */
int trk_gains_paper (double sigma_meas_m, double sigma_mod_mps2, double dt_s, trk_gains_t *ret);

/* Steady-state error of the updated estimate of one axis of a constant-gain
 * filter (position gain g, velocity gain gd_hz, interval dt) on a
 * constant-velocity target measured with standard deviation sigma_m
 * (Kalata's closed form, α = g, β = gd·dt):
 *   var(x) = σ² (2α² + β(2 − 3α)) / (α(4 − 2α − β)),
 *   var(v) = σ² 2β² / (dt² α(4 − 2α − β)).
 * -EINVAL unless the gains are stable (0 < α < 1, 0 < β < 4 − 2α). */
int trk_filter_steady_error (const trk_gains_t *g, double dt_s, double sigma_m, double *ret_pos_var,
                             double *ret_vel_var);

/* Process noise Q of one axis over dt: q[0] = dt⁴/4, q[1] = dt³/2, q[2] = dt²
 * times σ_mod². */
void trk_filter_q_axis (double sigma_mod_mps2, double dt_s, double ret_q[3]);

/* The estimate e moved to time t_s: X = Φ X, P = Φ P Φᵀ + Q (dt may be
 * negative for the state; Q uses |dt|). */
void trk_filter_predict (const trk_estimate_t *e, const trk_filter_params_t *p, double t_s,
                         trk_estimate_t *ret);

/* Innovation of a predicted estimate and a measured position z with
 * measurement covariance R (2×2 row-major): ν = z − H X, S = H P Hᵀ + R.
 * Returns the squared Mahalanobis distance νᵀ S⁻¹ ν, and ln det S in
 * *ret_log_det (may be NULL); a negative value when S is not positive
 * definite. */
double trk_filter_distance (const trk_estimate_t *pred, const double z[2], const double R[4],
                            double *ret_log_det);

/* Update a predicted estimate with z (covariance R): with the paper's gains
 * in TRK_FILTER_PAPER mode, with the Kalman gain otherwise. P follows in
 * Joseph form either way. gains[2] are the paper's per axis (unused in
 * Kalman mode, may be NULL then). 0, or -EDOM when S is not positive
 * definite (the estimate is left as it was). */
int trk_filter_update (trk_estimate_t *pred, const trk_filter_params_t *p,
                       const trk_gains_t gains[2], const double z[2], const double R[4]);

/* The Kalman gain K = P Hᵀ S⁻¹ (4×2 row-major) of a predicted estimate with
 * measurement covariance R; 0, or -EDOM when S is not positive definite. */
int trk_filter_kalman_gain (const trk_estimate_t *pred, const double R[4], double ret_K[8]);

/* A track's estimate from one position: velocity zero with standard deviation
 * v0_sigma_mps per axis. */
void trk_filter_init_one (trk_estimate_t *ret, const double z[2], const double R[4], double t_s,
                          double v0_sigma_mps);

/* A track's estimate from two positions (two-point differencing): z1 at t1,
 * z2 at t2 > t1. 0, or -EINVAL when t2 does not follow t1. */
int trk_filter_init_two (trk_estimate_t *ret, const double z1[2], const double R1[4], double t1_s,
                         const double z2[2], const double R2[4], double t2_s);

/* The measurement covariance (2×2, east/north) of a position measured as
 * range (sigma range_sigma_m, along the azimuth) and azimuth (sigma
 * azimuth_sigma_deg) at ground range ground_range_m and azimuth azimuth_deg
 * (clockwise from north). */
void trk_filter_polar_covariance (double ground_range_m, double azimuth_deg, double range_sigma_m,
                                  double azimuth_sigma_deg, double ret_R[4]);

#endif
