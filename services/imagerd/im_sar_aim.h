/* im_sar_aim — where a SAR chip looks when a target is designated, and how
 * wide it must be to hold the target's return.
 *
 * A moving target's return falls R·v_r/V⊥ along cross range from it:
 * hundreds of metres per m/s of radial velocity at 10 km, more near the
 * flight path. A tracker's radial velocity (from MTI hits seconds old, and
 * an estimate that doubts whether the vehicle has stopped) is good to a few
 * m/s, so a 256 m chip centred by it misses the return most of the time.
 * Two things put it in the chip:
 *
 *  - Widening (im_sar_geom_t.widen): the chip grows, with its resolutions,
 *    until it holds the return within IM_SAR_AIM_SIGMAS standard deviations
 *    of where it is expected (the track's position covariance across and
 *    along the chip, and its radial velocity's times the metres per m/s the
 *    geometry gives).
 *  - The SAR's moving-target channel (SAR-GMTI: the along-track
 *    interferometric phase of a mover's return gives its radial velocity):
 *    once a chip holds the target's return, that chip measures its radial
 *    velocity (σ [sar] gmti_sigma_mps) and so its true place. The next chip
 *    is aimed by that measurement, carried on with the track's velocity
 *    across the line of sight, its radial velocity allowed to drift by
 *    IM_SAR_AIM_VR_DRIFT m/s a second; it needs far less widening. A chip
 *    that misses the return falls back to the track.
 *
 * Pure: no logging, no globals. */
#ifndef IM_SAR_AIM_H
#define IM_SAR_AIM_H

#include "im_sar.h"

#define IM_SAR_AIM_SIGMAS   2.5  // a chip holds the expected return within this many σ
#define IM_SAR_AIM_MARGIN_M 10.0 // and the vehicle's own size about it
#define IM_SAR_AIM_VR_DRIFT 0.2  // m/s a second a measured radial velocity may drift
#define IM_SAR_AIM_MAX_AGE  30.0 // s: a measurement older than this is not used

/* The designated track, as the tracker last said. */
typedef struct {
    cgs_enu_t pos, vel; // east, north (up ignored) at t_s; m, m/s
    double t_s;
    bool has_cov;
    double cov[16]; // 4 × 4 row-major (east, north, ve, vn)
} im_sar_track_t;

/* The SAR's own measurement of the designated target's radial velocity. */
typedef struct {
    bool have;
    double t_s;    // of the chip that measured it
    cgs_enu_t pos; // the target's place it gives (ground, at t_s)
    cgs_enu_t los; // horizontal unit line of sight it was measured along
    double vr_mps; // radial velocity, positive opening
    double sigma_mps;
} im_sar_gmti_t;

/* Where to look. */
typedef struct {
    cgs_enu_t center; // the chip's centre: where the target's return is expected
    cgs_enu_t target; // the target's expected place (ground) and velocity
    cgs_enu_t vel;
    double widen;   // im_sar_geom_t.widen (1: as configured)
    double sigma_m; // standard deviation of the return's place, metres
    bool by_gmti;   // aimed by the SAR's own measurement
} im_sar_aim_t;

/* The chip to make at time t from radar (antenna, velocity) for a
 * designated target: trk, and gm when it is fresh (NULL: none). terrain may
 * be NULL (flat at 0). Widening at most max_widen. 0, or a negative errno
 * when no chip can be aimed there (ret then holds the target, unwidened). */
int im_sar_aim (const im_sar_t *sar, cgs_enu_t radar, cgs_enu_t radar_vel,
                const cgs_terrain_t *terrain, const im_sar_track_t *trk, const im_sar_gmti_t *gm,
                double t, double max_widen, im_sar_aim_t *ret);

/* The moving-target channel of chip c (made at t_s) on a target truly at p
 * moving at vel: true, with its radial velocity along the chip's line of
 * sight measured with noise of σ sigma_mps from *rng and the place that
 * gives, when the target's return falls in the chip and the radar sees it
 * (terrain; NULL: flat); false otherwise. */
bool im_sar_gmti_measure (const im_sar_chip_t *c, const cgs_terrain_t *terrain, cgs_enu_t p,
                          cgs_enu_t vel, double t_s, double sigma_mps, uint64_t *rng,
                          im_sar_gmti_t *ret);

#endif
