/* trk_imm — the interacting multiple model filter (Blom and Bar-Shalom) of
 * the default tracker: three motion models on the state X = (x, y, vx, vy).
 *
 *   CV         near-constant velocity: discrete white-noise acceleration of
 *              σ_cv per axis (the paper's model, trk_filter);
 *   MANEUVER   the same with σ_man, much larger: a vehicle turning, braking,
 *              pulling away;
 *   STOPPED    the vehicle stands: position held, velocity zero with
 *              standard deviation σ_stop. An MTI radar sees nothing of a
 *              stopped vehicle, so under this model a missed scan is what
 *              one expects, and a hit is evidence against it.
 *
 * Model switching is a Markov chain in continuous time: a model is left
 * after a mean sojourn τ_i, p_ii(dt) = exp(−dt/τ_i), and the rest goes to
 * the other models in the fixed proportions `exit`. One cycle: mixing (each
 * model's initial state, a mixture of every model's estimate weighted by the
 * probability that the target was in it given that it is now in this one),
 * prediction by each model's own dynamics, update with the measurement or a
 * miss, mode probabilities μ_j ∝ c_j Λ_j (Λ_j = Pd_j N(ν_j; 0, S_j) for a
 * hit, 1 − Pd_j for a missed scan, Pd_j the detection probability the radar
 * had of the target in model j's state: trk_pd), and the combined estimate
 * by moment matching.
 *
 * The measurement is the hit's position and, when the radar measured it,
 * its radial velocity: a linear measurement of the velocity along the line
 * of sight (h = [0 0 u_e u_n]), its innovation taken modulo the radial
 * velocity's unambiguous span. Pure: no logging, no globals. */
#ifndef TRK_IMM_H
#define TRK_IMM_H

#include "trk_filter.h"

#include <stdbool.h>

#define TRK_IMM_MODELS 3

typedef enum {
    TRK_MODEL_CV = 0,
    TRK_MODEL_MANEUVER = 1,
    TRK_MODEL_STOPPED = 2,
} trk_model_t;

typedef struct {
    double sigma_mps2[2];                        // acceleration σ of CV and MANEUVER, per axis
    double stopped_sigma_mps;                    // velocity σ of a stopped target
    double sojourn_s[TRK_IMM_MODELS];            // mean time in each model
    double exit[TRK_IMM_MODELS][TRK_IMM_MODELS]; // share of each model's exits into each
                                                 // other (rows sum to 1, diagonal 0)
    double max_speed_mps; // fastest target (0: no bound; see trk_imm_predict_model)
} trk_imm_params_t;

/* Every model's estimate (at one time) and the mode probabilities. */
typedef struct {
    trk_estimate_t m[TRK_IMM_MODELS];
    double mu[TRK_IMM_MODELS];
} trk_imm_t;

/* One hit as a measurement: position z with covariance R; radial velocity
 * (positive opening) along the unit ground line of sight los when measured. */
typedef struct {
    double z[2];
    double R[4];
    bool has_radial;
    double radial_mps;
    double los[2];
    double radial_var; // its variance
    double span_mps;   // unambiguous span (0: none)
} trk_meas_t;

/* Every model starting from one estimate, with mode probabilities mu0. */
void trk_imm_init (trk_imm_t *s, const trk_estimate_t *e, const double mu0[TRK_IMM_MODELS]);

/* The transition matrix over dt (row i: from model i), row-major. */
void trk_imm_transition (const trk_imm_params_t *p, double dt_s, double ret_pi[9]);

/* Mixing for an interval dt: each model's initial estimate, and in ret->mu
 * the predicted mode probabilities c_j = Σ_i p_ij μ_i. */
void trk_imm_mix (const trk_imm_params_t *p, const trk_imm_t *s, double dt_s, trk_imm_t *ret);

/* Each model's estimate moved to t_s by its own dynamics (mu kept). */
void trk_imm_predict (const trk_imm_params_t *p, const trk_imm_t *s, double t_s, trk_imm_t *ret);

/* One model's prediction of e to t_s. With max_speed_mps = v > 0, the
 * moving models' uncertainty stays that of a ground vehicle: a velocity
 * variance per axis of at most v²/4 (the spread of velocities of every
 * heading and speed up to v), a position variance grown by at most
 * (v·dt)²/4 over the step (a congruence D P D with D ≤ I, so P stays
 * positive semi-definite). A target unseen for minutes is then somewhere
 * within its reach, not anywhere at any speed. */
void trk_imm_predict_model (const trk_imm_params_t *p, trk_model_t j, const trk_estimate_t *e,
                            double t_s, trk_estimate_t *ret);

/* The combined estimate: x = Σ μ_j x_j, P = Σ μ_j (P_j + (x_j − x)(x_j − x)ᵀ). */
void trk_imm_combine (const trk_imm_t *s, trk_estimate_t *ret);

/* The measurement's innovation against a predicted estimate: the squared
 * Mahalanobis distance (2 or 3 degrees of freedom) and ln det S; negative
 * when S is not positive definite. */
double trk_meas_distance (const trk_estimate_t *pred, const trk_meas_t *m, double *ret_log_det);

/* Kalman update of a predicted estimate (Joseph form); 0, or -EDOM when S
 * is not positive definite (pred unchanged). */
int trk_meas_update (trk_estimate_t *pred, const trk_meas_t *m);

/* Update a predicted state with a hit: each model's Kalman update, and the
 * mode probabilities from pd[j] N(ν_j; S_j). ret_lik (may be NULL) gets the
 * mixture likelihood Σ c_j pd_j N_j. 0, or -EDOM when no model could take
 * it (pred unchanged). */
int trk_imm_update (trk_imm_t *pred, const trk_meas_t *m, const double pd[TRK_IMM_MODELS],
                    double *ret_lik);

/* A scan that saw nothing of the target: mode probabilities by 1 − pd[j]
 * (estimates unchanged). */
void trk_imm_miss (trk_imm_t *pred, const double pd[TRK_IMM_MODELS]);

#endif
