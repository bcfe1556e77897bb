/* trk_pd — what the radar could have seen: the detection probability the
 * tracker expects of a target in a given state, one scan of one radar.
 *
 * An MTI radar sees nothing of a target whose radial velocity over the
 * ground lies in its clutter notch: below the minimum detectable velocity
 * (MDV) about zero, and about each blind speed (multiples of the radial
 * velocity's unambiguous span λ·PRF/2, where the target's Doppler aliases
 * onto the clutter). The notch is widest across the platform's motion,
 * where the platform spreads the mainbeam clutter's Doppler most, and
 * narrowest along it, where the canceller alone makes it:
 *   MDV(α) = √(mdv_along² + (mdv_across² − mdv_along²) sin² α),
 * α the angle between the platform's ground velocity and the line of sight.
 * Outside the notch the radar detects with pd(R), falling with the slant
 * range R as the signal does (R⁻⁴ in the radar equation):
 *   pd(R) = pd / (1 + (R / half_range)^range_exponent),
 * half of pd at half_range; across the notch's edge Pd rises as
 *   Pd = pd(R) · Φ((|v_r| − MDV(α)) / √(w² + σ_vr²)),
 * w the edge's width and σ_vr the standard deviation of the state's radial
 * velocity, so an uncertain state near the edge is neither seen nor unseen
 * for sure. Outside the radar's range window, or outside the sector a scan
 * swept, Pd is zero. The defaults are measured on mtid's chain at its
 * default parameters (a 10 m² vehicle, Swerling II from one coherent
 * interval to the next, the UAV 1200 m up): 50% points of the notch
 * 0.58 m/s along and 1.8 m/s across at 8 km, an edge of about 0.2 m/s;
 * clear of the notch, 1.00 at 4 km, 0.98 at 8, 0.83 at 10, 0.44 at 12,
 * 0.14 at 14 and 0.03 at 16 km along the ground, which pd 0.995,
 * half_range 11 800 m and exponent 10.8 follow within 0.04 (test_trk_imm,
 * 400 dwells a point). Where the radar's terrain is known, a target the
 * terrain hides (the line from the antenna to 2 m above the ground at the
 * target cut, as mtid models it) has Pd zero; foliage is not modelled (it
 * does not hide targets from mtid either). Pure: no logging, no globals. */
#ifndef TRK_PD_H
#define TRK_PD_H

#include "cgs_terrain.h"

#include <stdbool.h>

typedef struct {
    double pd;             // detection probability clear of the notch, near
    double half_range_m;   // slant range at which it has fallen to half
    double range_exponent; // and how steeply: pd / (1 + (R / half_range)^exponent)
    double mdv_along_mps;  // MDV along the platform's ground velocity
    double mdv_across_mps; // MDV across it
    double width_mps;      // width of the notch's edge
    double span_mps;       // blind speeds: multiples of this (0: none)
    double min_range_m;    // the radar's range window, along the ground
    double max_range_m;
} trk_pd_params_t;

/* The radar during one scan. */
typedef struct {
    double position[3]; // antenna: east, north, up
    double velocity[2]; // ground velocity, east and north
    bool full_revolution;
    double sector_center_deg; // clockwise from north (sector scans)
    double sector_width_deg;
    const cgs_terrain_t *terrain; // the ground the radar looks over (borrowed; NULL: none)
} trk_pd_radar_t;

/* The MDV at angle alpha_rad between the platform's velocity and the line
 * of sight. */
double trk_pd_mdv (const trk_pd_params_t *p, double alpha_rad);

/* Clear of the notch, at slant range r_m: pd / (1 + (r / half_range)^k). */
double trk_pd_at_range (const trk_pd_params_t *p, double r_m);

/* The detection probability of a target at x (east, north, up) moving at
 * v (east, north) with radial-velocity standard deviation sigma_vr. */
double trk_pd_of (const trk_pd_params_t *p, const trk_pd_radar_t *r, const double x[3],
                  const double v[2], double sigma_vr);

/* Whether the scan swept the direction of (e, n) from the radar. */
bool trk_pd_covered (const trk_pd_radar_t *r, double e, double n);

#endif
