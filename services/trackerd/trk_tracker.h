/* trk_tracker — tracks from MTI hits, one radar scan at a time: gating
 * against each track's prediction, global-nearest-neighbour association (an
 * optimal assignment per cluster of tracks and hits that share gates),
 * initiation from unassociated hits, confirmation M of N, coasting through
 * missed scans and deletion after too many; the paper's Track & Update filter
 * (trk_filter); turn detection (paper, equation 8); identity from BCIS
 * replies, which ages out; the last scans of each track's hits. Its
 * checkpoint (every track and the id counter) is trk_checkpoint's.
 *
 * Association uses each hit's radial velocity when the radar measured it
 * (a third dimension of the gate, against the track's velocity along the
 * line of sight); the filter uses positions only, as the paper's does.
 *
 * Tracks belong to the radar (UAV) whose hits made them; a scan of one radar
 * touches only its tracks. BCIS replies mark tracks of any radar.
 * Pure: no logging, no sockets, no clock. */
#ifndef TRK_TRACKER_H
#define TRK_TRACKER_H

#include "cgs_geo.h"
#include "cgs_terrain.h"
#include "trk_filter.h"
#include "trk_imm.h"
#include "trk_params.h"

#include "cgs_track_status.h"

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

/* A track's status: the message's (cgs_track_status.h). */
typedef enum {
    TRK_TENTATIVE = CGS_TRACK_TENTATIVE, // not yet M hits in N scans
    TRK_CONFIRMED = CGS_TRACK_CONFIRMED, // hit in its latest scan
    TRK_COASTING = CGS_TRACK_COASTING,   // confirmed, missed its latest scan(s)
    TRK_DELETED = CGS_TRACK_DELETED,     // reported once, then forgotten
} trk_status_t;

/* One MTI hit as the tracker takes it. */
typedef struct {
    uint32_t hit_id;
    double t_s;            // simulation time of the dwell
    double z[2];           // measured position, east and north, metres
    double up_m;           // its height (kept for the history)
    double ground_range_m; // from the radar, along the ground
    double azimuth_deg;    // from the radar, clockwise from north
    double range_sigma_m;  // standard deviations the radar reports (0: unknown)
    double azimuth_sigma_deg;
    bool has_radial;   // the radar measured the radial velocity:
    double radial_mps; // positive opening
    double los[2];     // east, north parts of the unit line of sight from the
                       // radar to the hit: radial velocity = los · v
} trk_hit_t;

/* A hit from an MTI detection at hit (on the ground) seen from the radar at
 * platform, at time t_s: the slant range's standard deviation becomes one
 * along the ground (slant / ground times longer), the line of sight is the
 * ground-plane part of the unit vector from the radar to the hit, and the
 * radial velocity counts as measured when the two are apart. */
trk_hit_t trk_hit_from_mti (uint32_t hit_id, double t_s, cgs_enu_t hit, cgs_enu_t platform,
                            double azimuth_deg, double range_sigma_m, double azimuth_sigma_deg,
                            double radial_mps);

/* One radar scan: what it covered. */
typedef struct {
    uint32_t uav_id;
    uint32_t scan_number;
    double start_s, end_s;
    bool full_revolution;     // else a sector:
    double sector_center_deg; // clockwise from north
    double sector_width_deg;
    double platform[2];           // the radar's ground position (east, north) during the scan
    double platform_up_m;         // its height (0 when unknown)
    double platform_velocity[2];  // its ground velocity over the scan (east, north)
    double expected_false_alarms; // the radar's design count of false alarms over the scan (0:
                                  // unknown: the [detection] parameter)
} trk_scan_t;

/* One past hit of a track. */
typedef struct {
    double e_m, n_m, u_m;
    double t_s;
    uint32_t scan_number;
    uint32_t hit_id;
} trk_history_point_t;

/* A track. */
typedef struct {
    uint32_t id;     // stable for the track's life, never reused
    uint32_t uav_id; // radar whose hits it follows
    trk_status_t status;
    trk_estimate_t est; // the filter's estimate at its last update
    double up_m;        // height of its latest hit
    uint32_t hits;      // hits associated in all
    uint32_t updates;   // filter updates since two-point initiation
    uint32_t misses;    // consecutive scans without a hit
    uint32_t window;    // bit k: a hit k scans ago (M of N)
    uint32_t scans;     // scans it has been through since its first hit
    double last_hit_s;
    uint32_t last_scan;
    trk_history_point_t history[TRK_HISTORY_MAX]; // oldest first
    uint32_t history_count;
    // Identity from BCIS.
    bool friendly;
    uint32_t friendly_id; // responder id of the latest reply in its gate
    double friendly_s;    // time of that reply
    // Turn detection (equation 8).
    bool have_uv;
    double v_last[2];    // predicted velocity after the latest update (UV is its unit vector)
    bool turning;        // dot fell below τ and has not come back
    double uv_before[2]; // unit velocity before the turn began
    double v_before[2];  // velocity before the turn began, m/s
    uint32_t turn_scan;  // scan the turn was flagged in
    // The IMM tracker (mode = imm); est is then the models' combination.
    trk_imm_t imm;      // every model's estimate at est.t_s, and the mode probabilities
    double existence;   // probability that the target exists
    double pd;          // detection probability the radar had of it in the latest scan
    bool reconfirm;     // its first hit after a coast: confirmed at the next
    uint32_t continues; // the deleted track whose target this one probably is (0: none)
    double continues_p; // that probability
} trk_track_t;

/* A turn (paper, equation 8): flagged when dot falls below τ, complete when
 * it is above τ again. */
typedef struct {
    uint32_t track_id;
    uint32_t scan_number;
    double t_s;
    bool complete;      // false: flagged (angle so far); true: the whole change
    double dot;         // the dot product that triggered the event
    double angle_deg;   // change of direction, clockwise positive, (−180, 180]
    double position[2]; // the track's position then
    double v_before[2]; // velocity before the turn
    double v_after[2];  // velocity now
} trk_turn_t;

/* A cluster of more tracks than this (targets so crowded that the gates
 * chain them together) is assigned greedily, not optimally. */
#define TRK_CLUSTER_MAX 400

/* What one scan did. Pointers stay valid until the next call on the tracker. */
typedef struct {
    size_t hits;            // hits of the scan
    size_t pairs;           // track-hit pairs inside a gate
    size_t clusters;        // groups solved as one assignment
    size_t largest_cluster; // tracks in the largest
    size_t greedy_clusters; // of more than TRK_CLUSTER_MAX tracks, assigned greedily
    size_t branched;        // IMM: tracks that took a hit after a coast and kept both branches
    size_t alt_swaps;       // IMM: tracks whose other branch became the likelier
    size_t updated, missed, born, confirmed, deleted;
    size_t unused_hits; // in a confirmed track's gate but not assigned: start nothing
    size_t time_reset;  // tracks deleted because the scan came before their time
    size_t continued;   // tracks found to continue a deleted one
    size_t reacquired;  // of those, continuing one that was coasting (deleted for it)
    const trk_turn_t *turns;
    size_t turn_count;
    const trk_track_t *deleted_tracks; // copies, status TRK_DELETED
    size_t deleted_count;
} trk_scan_out_t;

typedef struct trk_tracker trk_tracker_t;

/* A tracker with no tracks; NULL when p is inconsistent or memory is short. */
trk_tracker_t *trk_tracker_new (const trk_params_t *p);
/* Free; accepts NULL, nulls the pointer. */
void trk_tracker_destroy (trk_tracker_t **self_p);
/* Its parameters. */
const trk_params_t *trk_tracker_params (const trk_tracker_t *self);
/* The paper's gains per axis at the nominal dt_s, computed once from the parameters. */
const trk_gains_t *trk_tracker_gains (const trk_tracker_t *self);
/* A radar's revisit of a cell (its scan's length, from mti.scan). With
 * dt_auto it becomes the nominal interval (dt_s: the BCIS age limit, the
 * time-went-back test). A fixed dt_s that disagrees with it by more than
 * TRK_REVISIT_TOLERANCE (10%) is refused: the tracker takes dt_auto and
 * the radar's revisit, and returns false (once: it then agrees). */
#define TRK_REVISIT_TOLERANCE 0.1
bool trk_tracker_radar_revisit (trk_tracker_t *self, double revisit_s);

/* The ground the radars look over (borrowed, may be NULL: none), for the
 * IMM tracker's expected detection probability: a target the terrain hides
 * from the radar is not expected to be seen. */
void trk_tracker_set_terrain (trk_tracker_t *self, const cgs_terrain_t *terrain);

/* Process one scan of one radar and its hits (a hit with a non-finite field
 * is skipped and counted as not a hit). 0, or -ENOMEM (the tracks are as
 * they were before the call). */
int trk_tracker_scan (trk_tracker_t *self, const trk_scan_t *scan, const trk_hit_t *hits, size_t n,
                      trk_scan_out_t *ret);

/* A BCIS reply: where it puts the responder on the ground and how well. */
typedef struct {
    double t_s;
    double z[2]; // east, north
    double R[4]; // its covariance, row-major
    uint32_t responder_id;
} trk_bcis_reply_t;

/* A reply that measured slant range range_m (σ range_sigma_m) from an
 * interrogator at height height_m above the responder, toward beam azimuth
 * azimuth_deg (σ azimuth_sigma_deg), putting it at z on the ground: the
 * range and azimuth converted about the ground range ρ = √(r² − h²), whose
 * σ is range_sigma_m · r / ρ (trk_filter_polar_covariance). -EINVAL when
 * the range does not reach the ground or a value is not finite. */
int trk_bcis_reply_geometry (double t_s, const double z[2], double range_m, double range_sigma_m,
                             double height_m, double azimuth_deg, double azimuth_sigma_deg,
                             uint32_t responder_id, trk_bcis_reply_t *ret);

/* A BCIS reply: of each radar's confirmed (or coasting) tracks updated
 * within (delete_misses + 1) scan periods, those whose gate holds the reply
 * (χ² at most the gate with S = P + R) are the candidates, each with the
 * likelihood N(z; ẑ, S); beside them the responder may be a vehicle the
 * radar does not track (halted, masked), of density identity_untracked_per_km2.
 * The likeliest candidate becomes friendly when its probability, its
 * likelihood over the sum of all and the untracked density, is at least
 * identity_min_probability. Returns how many tracks it marked (one a radar
 * at most). */
size_t trk_tracker_bcis (trk_tracker_t *self, const trk_bcis_reply_t *reply);
/* Friendly tracks whose last reply is older than the identity timeout at
 * time t_s become unknown again; returns how many. */
size_t trk_tracker_age_identity (trk_tracker_t *self, double t_s);

/* Number of live tracks, and the i-th (order changes when tracks die). */
size_t trk_tracker_count (const trk_tracker_t *self);
const trk_track_t *trk_tracker_at (const trk_tracker_t *self, size_t i);
/* The live track with this id, or NULL. */
const trk_track_t *trk_tracker_find (const trk_tracker_t *self, uint32_t id);
/* A track's estimate moved to time t_s (prediction, covariance grown). */
void trk_tracker_predict (const trk_tracker_t *self, const trk_track_t *t, double t_s,
                          trk_estimate_t *ret);
/* The id the next new track will get. */
uint32_t trk_tracker_next_id (const trk_tracker_t *self);

/* Replace the tracks with count tracks (copied; history beyond
 * history_scans trimmed to the newest) and the id counter with next_id, as
 * trk_checkpoint_restore does once it has checked them: their ids distinct
 * and below next_id. 0, or -ENOMEM (the tracker unchanged). */
int trk_tracker_replace (trk_tracker_t *self, const trk_track_t *tracks, size_t count,
                         uint32_t next_id);
/* Never give ids below id (those of a checkpoint set aside). */
void trk_tracker_raise_next_id (trk_tracker_t *self, uint32_t id);

#endif
