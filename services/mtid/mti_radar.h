/* mti_radar — the MTI radar on one UAV: the scan schedule, the geometry and
 * radar equation of each target and its clutter, the signal processing chain
 * (mti_dsp) per target in the beam, hits with measurement noise, and false
 * alarms over the rest of the swept area.
 *
 * Scan: the antenna is stabilised in azimuth and sweeps at sweep_rate_dps,
 * full revolutions clockwise, or back and forth across a sector (each pass a
 * scan). The swept span is cut into D = floor(span / beamwidth) dwells of
 * equal width (at least one beamwidth), each lasting width / sweep rate.
 * Dwell k of the exercise starts at k * dwell time: the schedule is a pure
 * function of simulation time, so a restarted mtid scans on where it was.
 *
 * Each target whose azimuth falls in a dwell's sector, within the range
 * limits and inside the elevation beam is "in the beam" for that dwell; the
 * beam sweeps across it, so the dwell sees it for its whole time on target
 * with the two-way beam-shape loss counted in losses_db.
 *
 * Per target in the beam:
 *   - hidden when the terrain cuts the line from the antenna to 2 m above
 *     the target (no return at all);
 *   - SNR per pulse = Pt tau G^2 lambda^2 sigma g_el / ((4 pi)^3 R^4 k T0 F L),
 *     g_el the two-way Gaussian elevation pattern exp(-8 ln2 (d/theta_el)^2)
 *     at depression offset d from the beam centre (energy form: pulse
 *     compression is allowed);
 *   - clutter in the target's cell and its CFAR reference cells (guard
 *     cells skipped, half each side along the same azimuth): constant-gamma
 *     sigma0 = gamma sin(psi), psi the grazing angle between the line of sight
 *     and the terrain surface (terrain normal) at the cell; patch area R
 *     theta_az dR / cos(psi); none where psi <= 0 or the terrain hides the
 *     cell (radar shadow);
 *   - clutter spectrum std sigma_f^2 = (2 sigma_v / lambda)^2 (internal
 *     motion) + (0.3 theta_az (2 V / lambda) |sin alpha|)^2 (platform motion
 *     across the beam, alpha between the beam and the ground velocity) +
 *     (0.265 omega / theta_az)^2 (scan modulation), about zero Doppler (the
 *     radar centres mainbeam clutter);
 *   - target Doppler -2 v_r / lambda, v_r its radial velocity over the ground
 *     (positive opening), aliased at the PRF like a real pulse Doppler radar.
 * A detection becomes a hit: range at the centre of its range gate (sigma
 * dR / sqrt 12); azimuth with Gaussian noise of sigma theta / (1.6 sqrt(2
 * SINR)), no more than theta / sqrt 12; radial velocity from the Doppler
 * bin; position on the ground by intersecting the measured range and
 * azimuth with the terrain.
 *
 * False alarms (drawn, not processed cell by cell): each range gate of the
 * dwell declares one with P = m_of_n(p_cpi), p_cpi the chance of a crossing
 * in any Doppler bin of a CPI (CA-CFAR holds Pfa in every bin of homogeneous
 * Gaussian clutter and noise; the bins are correlated by the window, so
 * p_cpi < 1 - (1 - Pfa)^bins: it is estimated once, at creation, by the
 * real chain with mti_dsp_any_bin_probability);
 * the count is binomial, each placed in a random gate, azimuth in the
 * dwell, Doppler bin, with the CFAR ratio of an exceedance. Pure: no
 * sockets, clocks, globals or logging. */
#ifndef MTI_RADAR_H
#define MTI_RADAR_H

#include "cgs_geo.h"
#include "cgs_scan.h"
#include "cgs_terrain.h"
#include "mti_params.h"

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

typedef struct mti_radar mti_radar_t;

/* One dwell of the schedule (cgs_scan). */
typedef cgs_dwell_t mti_dwell_t;

/* The UAV as the radar sees it at the dwell's centre time. */
typedef struct {
    cgs_enu_t position; // antenna, local frame
    cgs_enu_t velocity; // m/s
    double heading_deg; // for a heading-referenced sector
} mti_platform_t;

/* A ground entity at the dwell's centre time. */
typedef struct {
    uint32_t id;
    cgs_enu_t position; // on the ground
    cgs_enu_t velocity;
    const char *rcs_class; // NULL: the default class
} mti_target_t;

typedef struct {
    uint32_t hit_id;            // unique in this radar's life, from 1
    uint32_t entity_id;         // source (0: false alarm); for scoring only
    cgs_enu_t position;         // measured, on the ground
    double range_m;             // measured slant range
    double azimuth_deg;         // measured, clockwise from north
    double radial_velocity_mps; // measured, positive opening
    double snr_db;              // CFAR ratio of the detection
    double range_sigma_m;
    double azimuth_sigma_deg;
} mti_hit_t;

/* What the radar saw of one target in the beam. */
typedef struct {
    uint32_t entity_id;
    bool visible;  // not hidden by terrain
    double snr_db; // expected SINR in its Doppler bin (one CPI); -inf when hidden
    double pd;     // the dwell's detection probability (m of n intervals), from theory
    bool detected;
    uint32_t hit_id;            // 0 when not detected
    uint32_t merged_with;       // not resolved: its echo shares this target's range-Doppler
    uint32_t merged_into;       // cell, whose hit (this id) stands for both (detected false)
    double radial_velocity_mps; // true, positive opening
    double range_m;             // true slant range
} mti_truth_t;

/* A dwell's outcome; arrays owned by the radar, valid until the next dwell. */
typedef struct {
    const mti_hit_t *hits;
    size_t hit_count;
    const mti_truth_t *truth; // targets in the beam
    size_t truth_count;
    uint32_t false_alarms;
} mti_dwell_out_t;

/* A radar with these parameters over this terrain (borrowed, may be NULL:
 * flat ground at height 0), seeded; NULL on bad parameters or no memory. */
mti_radar_t *mti_radar_new (const mti_params_t *p, const cgs_terrain_t *terrain, uint64_t seed);
/* Free; accepts NULL; sets *self_p to NULL. */
void mti_radar_destroy (mti_radar_t **self_p);
/* Restart the radar's noise from seed and its hit ids from 1, as a new
 * radar would (the calibration, which is costly, is kept). */
void mti_radar_reseed (mti_radar_t *self, uint64_t seed);

/* Seconds per dwell, and dwells per scan. */
double mti_radar_dwell_s (const mti_radar_t *self);
uint32_t mti_radar_dwells_per_scan (const mti_radar_t *self);
/* The scan schedule. */
const cgs_scan_t *mti_radar_scan (const mti_radar_t *self);
/* Dwell number k of the schedule; heading_deg orients a heading-referenced sector. */
void mti_radar_schedule (const mti_radar_t *self, uint64_t k, double heading_deg, mti_dwell_t *ret);
/* Number of the dwell in progress at simulation time t (t >= 0). */
uint64_t mti_radar_dwell_at (const mti_radar_t *self, double t_s);

/* Process one dwell: the targets (any number; those not in the beam are
 * skipped) as they are at the dwell's centre. 0, or -ENOMEM. */
int mti_radar_dwell (mti_radar_t *self, const mti_dwell_t *d, const mti_platform_t *plat,
                     const mti_target_t *targets, size_t n, mti_dwell_out_t *ret);

/* Geometry and models, for tests and the truth. */
/* Per-pulse SNR of a target of rcs_m2 at slant range r_m and depression offset d_deg. */
double mti_radar_snr (const mti_radar_t *self, double rcs_m2, double r_m,
                      double depression_off_deg);
/* Clutter spectrum std (Hz) for a platform ground speed v_mps whose
 * velocity makes angle alpha_deg with the beam. */
double mti_radar_clutter_sigma_hz (const mti_radar_t *self, double v_mps, double alpha_deg);
/* Per-pulse clutter-to-noise of the ground cell at slant range r_m with
 * grazing angle psi_deg, depression offset d_deg. */
double mti_radar_cnr (const mti_radar_t *self, double r_m, double psi_deg,
                      double depression_off_deg);
/* The probability that a target-free range gate declares a false alarm in
 * one dwell: m_of_n(cpi_pfa). */
double mti_radar_gate_pfa (const mti_radar_t *self);
/* The probability that a target-free gate has a crossing in any Doppler bin
 * of one CPI, estimated at creation (mti_dsp_any_bin_probability). */
double mti_radar_cpi_pfa (const mti_radar_t *self);
/* Range gates in a dwell, between the range limits. */
uint32_t mti_radar_gates (const mti_radar_t *self);
/* The chain the radar uses (its generator, FFT and CFAR). */
struct mti_dsp *mti_radar_dsp (mti_radar_t *self);

#endif
