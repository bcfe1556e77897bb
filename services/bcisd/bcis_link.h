/* bcis_link — the BCIS link in both directions, term by term: free-space
 * loss, gases, rain (ITU-R P.838-3), foliage (Weissberger), the
 * interrogator's beam pattern, transmitters and receivers; then the bit-error
 * rate of the modulation and the probability that a message arrives whole.
 * Pure functions of the parameters and the geometry.
 *
 *   free space      L = 20 log10(4 pi d f / c)
 *   gases           a = atmospheric_db_per_km * d_km (the whole path)
 *   rain            gamma = k R^alpha dB/km over the path below rain_height_m,
 *                   k and alpha from P.838-3's regression for H and V and
 *                   combined for the path elevation theta and polarisation tilt
 *                   tau: k = (kH + kV + (kH - kV) cos^2 theta cos 2 tau) / 2,
 *                   alpha = (kH aH + kV aV + (kH aH - kV aV) cos^2 theta cos 2 tau) / (2 k)
 *   foliage         Weissberger's modified exponential decay, f in GHz, depth d
 *                   in metres: 0.45 f^0.284 d (d <= 14 m), 1.33 f^0.284 d^0.588
 *                   (14 < d <= 400 m, the model's stated range; deeper woods,
 *                   which no link here survives, take the same formula)
 *   beam pattern    one-way Gaussian, 12 (off / beamwidth)^2 dB (3 dB at half
 *                   the beamwidth), in azimuth and in elevation
 *   received power  Pt + Gt - Lt - patterns - path losses + Gr - Lr (dBW)
 *   noise           k T0 F Rb (the noise in the bit rate's bandwidth), so the
 *                   SNR is Eb/N0
 *   bit errors      BPSK and Gray QPSK: Q(sqrt(2 Eb/N0)); non-coherent BFSK:
 *                   exp(-Eb / 2 N0) / 2
 *   message         P(at most t of L bits wrong) = sum_{i<=t} C(L,i) p^i (1-p)^(L-i):
 *                   the frequency hopping spreads a message over many hops,
 *                   so bit errors are taken as independent
 *   reply           P = P_message(up) * P_message(down) */
#ifndef BCIS_LINK_H
#define BCIS_LINK_H

#include "bcis_params.h"

#include <stdbool.h>

/* Geometry of one interrogator-transponder path. */
typedef struct {
    double range_m;       // slant range, antenna to antenna
    double elevation_deg; // of the path above the horizontal at the transponder
    double rain_path_m;   // part of the path below the rain height
    double foliage_m;     // part of the path inside woods
    double az_off_deg;    // transponder's azimuth off the interrogator's beam centre
    double el_off_deg;    // and its depression off the elevation beam centre
} bcis_geometry_t;

/* Every term of the budget, both ways. Losses positive, in dB. */
typedef struct {
    double fspl_db, atmospheric_db, rain_db_per_km, rain_db, foliage_db;
    double pattern_db;   // the interrogator's beam, azimuth and elevation, one way
    double path_loss_db; // fspl + gases + rain + foliage
    double up_eirp_dbw;  // interrogator: Pt + G - losses - pattern
    double up_rx_dbw;    // power at the transponder's receiver
    double up_noise_dbw; // k T0 F Rb at the transponder
    double up_ebn0_db;
    double down_eirp_dbw; // transponder: Pt + G - losses
    double down_rx_dbw;   // at the interrogator's receiver, after its gain, pattern, losses
    double down_noise_dbw;
    double down_ebn0_db;
    double up_ber, down_ber;
    double p_up;    // the interrogation decoded whole
    double p_down;  // the reply decoded whole
    double p_reply; // both
} bcis_budget_t;

/* Free-space path loss, dB, at f_hz over d_m. */
double bcis_fspl_db (double f_hz, double d_m);
/* P.838-3 coefficients at f_ghz (1..1000): horizontal and vertical k, alpha. */
void bcis_p838 (double f_ghz, double *ret_kh, double *ret_ah, double *ret_kv, double *ret_av);
/* Specific rain attenuation, dB/km, at f_ghz for rate_mmph, a path of
 * elevation_deg and polarisation tilt tau_deg (0 horizontal, 90 vertical, 45 circular). */
double bcis_rain_db_per_km (double f_ghz, double rate_mmph, double elevation_deg, double tau_deg);
/* Weissberger's foliage loss, dB, at f_ghz through depth_m of woods. */
double bcis_foliage_db (double f_ghz, double depth_m);
/* One-way loss of a Gaussian beam off_deg off its axis, dB. */
double bcis_pattern_db (double off_deg, double beamwidth_deg);
/* Bit-error probability of the modulation at Eb/N0 (linear). */
double bcis_ber (bcis_modulation_t m, double ebn0);
/* Probability that a message of bits bits arrives with at most correctable errors. */
double bcis_message_p (double ber, int bits, int correctable);
/* The polarisation's tilt angle, degrees. */
double bcis_tilt_deg (bcis_polarization_t pol);
/* The whole budget of one path. */
void bcis_budget (const bcis_params_t *p, const bcis_geometry_t *g, bcis_budget_t *ret);

#endif
