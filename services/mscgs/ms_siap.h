/* ms_siap — SIAP-style track-quality figures over a run, fed once per radar
 * scan with the truths trackable at that scan and the tracks (confirmed or
 * coasting: the caller filters) with the truth each track is associated to.
 *
 * The association is given: the caller decides, scan by scan, which truth
 * each track stands for (0: none), and nothing here second-guesses it. A
 * track naming a truth that is not among the scan's truths counts as
 * unassociated (and in unknown_truth_scans). The figures say how well the
 * tracks cover the truths under that association.
 *
 * Definitions follow Stone Soup's SIAPMetrics
 * (stonesoup/metricgenerator/tracktotruthmetrics.py, compute_metric), summed
 * over the scans k of every run, with J(k) the truths present, JT(k) those
 * with at least one associated track, N(k) the tracks and NA(k) the tracks
 * associated to a truth present at k:
 *   completeness  C  = Σ JT(k) / Σ J(k)            ("JT_sum / J_sum")
 *   ambiguity     A  = Σ NA(k) / Σ JT(k)           ("NA_sum / JT_sum")
 *   spuriousness  S  = Σ [N(k) − NA(k)] / Σ N(k)   ("(N_sum - NA_sum) / N_sum")
 *                 and, ours, the part of it made of tracks the caller flags
 *                 truth_unseen (a vehicle present but not among the scan's
 *                 truths, within the gate: a track holding a vehicle the
 *                 radar could not see): Σ unseen(k) / Σ N(k)
 *   position accuracy PA = Σ_k Σ_associated |track − truth| / Σ NA(k):
 *                 the MEAN distance (not RMS), as Stone Soup's
 *                 accuracy_at_time ("error_sum += measure(track[timestamp],
 *                 truth[timestamp])") over "PA_sum / NA_sum"; metres, in
 *                 the plane (east, north)
 * Where a denominator is 0 the figure is NaN; Stone Soup gives 0 (C, S, PA)
 * or 1 (A) there instead.
 *
 * Continuity figures (ours: Stone Soup's rate of track number changes R,
 * Σ (NU_j − 1) / Σ TT_j, counts the fewest tracks needed to cover a truth per
 * second tracked; these count events per hour the truths were present):
 *   - primary track of a truth at a scan: among the tracks associated to it,
 *     its last primary (from any earlier scan of the run, across scans where
 *     it had none) if that one is associated again, else the lowest id;
 *   - swap: the primary changes from one track id to another (a truth's first
 *     primary is not a swap);
 *   - break: a truth that had an associated track at the last scan it was
 *     present at (in this run) is present with none;
 *   - truth time: scan k covers dt_k = t_k − t_(k−1), the interval since the
 *     previous scan of the same run (0 for a run's first scan), credited to
 *     each truth present at k: Σ_k dt_k · J(k);
 *   - swaps and breaks per truth-hour = count / (truth time / 3600 s);
 *   - false track: a track id seen in a run and never associated to a truth
 *     present at a scan during that run; false tracks per hour = count /
 *     (run time / 3600 s), run time = Σ_k dt_k = Σ over runs of (last scan
 *     time − first scan time).
 *
 * Identification figures, after Stone Soup's IDSIAPMetrics ("SIAP ID
 * Completeness", "SIAP ID Correctness") but counted over associated tracks
 * where it counts truths (of JT(k), those whose associated tracks all carry
 * no id, JU, all the truth's id, JC, all another, JI, or a mix, JA; its
 * figures are (JT − JU) / JT, JC / JT and JA / JT, 0 on an empty sum). A
 * truth's identity is the id it can be identified by (the caller's choice:
 * its entity id when friendly with a BCIS transponder), 0 for none; a
 * track's claimed identity is the id it gives its target (its BCIS
 * responder id when marked friendly), 0 for none. Summed over the NA(k)
 * associated tracks of every scan k of every run (ms_siap_result_t's id
 * member, id.marked for id_marked and so on):
 *   id_identifiable          tracks whose truth has an identity
 *   id_identifiable_marked   of those, tracks claiming some identity
 *   id_marked                tracks claiming an identity
 *   id_correct               tracks claiming their truth's identity
 *   id_wrong                 tracks claiming an identity other than their
 *                            truth's (a truth without identity included)
 *   id_hostile_marked        tracks of a hostile truth claiming an identity
 *                            (the dangerous error: a hostile vehicle taken
 *                            for a friend; within id_wrong, as a hostile
 *                            truth has no identity)
 *   ID completeness  = id_identifiable_marked / id_identifiable
 *   ID correctness   = id_correct / id_marked
 *   ID wrong         = id_wrong / id_marked  (= 1 − ID correctness)
 * Where a denominator is 0 the figure is NaN. Unassociated tracks and tracks
 * naming an absent truth count in none of these.
 *
 * Pooling: ms_siap_end_run closes a run (per-truth and per-track memory is
 * forgotten, so ids may be reused and time may restart); ms_siap_merge adds
 * another accumulator's runs as closed runs. Merging accumulators that each
 * saw whole runs gives the same counts and figures (up to rounding of the
 * sums) as one accumulator fed every run with ms_siap_end_run between them.
 * One run split across accumulators does not pool: swaps and breaks at the
 * first scan after the split, the interval across it, and the lifetime of
 * each track (a track seen in both parts counts twice) are lost.
 * Pure: no logging, no globals. */
#ifndef MS_SIAP_H
#define MS_SIAP_H

#include "ms_gospa.h"

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

typedef struct ms_siap ms_siap_t;

/* A truth trackable at the scan. */
typedef struct {
    uint32_t id;       // non-zero, unique within a scan
    ms_point_t pos;    // metres
    uint32_t identity; // the id it can be identified by, 0: none
    bool hostile;      // hostile force: a claimed identity on its tracks is counted apart
} ms_siap_truth_t;

/* A confirmed or coasting track at the scan. */
typedef struct {
    uint32_t id;         // non-zero, unique within a scan
    uint32_t truth_id;   // the truth the caller associated it with, 0: none
    ms_point_t pos;      // metres
    uint32_t claimed_id; // the identity it claims for its target, 0: none
    bool truth_unseen;   // the caller's: it follows a vehicle present but not among the
                         // scan's truths (the radar could not see it), within the gate
} ms_siap_track_t;

/* The identification counts, over associated track-scans (see above). */
typedef struct {
    size_t identifiable;        // id_identifiable: the truth has an identity
    size_t identifiable_marked; // id_identifiable_marked: of those, the track claims one
    size_t marked;              // id_marked: the track claims an identity
    size_t correct;             // id_correct: of those, its truth's
    size_t wrong;               // id_wrong: of those, another (or the truth has none)
    size_t hostile_marked;      // id_hostile_marked: of id_wrong, the truth is hostile
} ms_siap_id_t;

typedef struct {
    /* Raw counts, summed over scans and runs: what ms_siap_merge pools. */
    size_t runs;                   // runs with at least one scan
    size_t scans;                  // scans fed
    size_t truth_scans;            // Σ J(k)
    size_t tracked_truth_scans;    // Σ JT(k)
    size_t track_scans;            // Σ N(k)
    size_t associated_track_scans; // Σ NA(k)
    size_t unknown_truth_scans;    // track-scans naming a truth absent at k (unassociated)
    size_t unseen_track_scans;     // unassociated track-scans flagged truth_unseen
    double position_error_m;       // Σ distance over associated track-scans, metres
    double truth_time_s;           // Σ dt_k · J(k), seconds
    double run_time_s;             // Σ dt_k, seconds
    size_t swaps;                  // primary track changes
    size_t breaks;                 // truths losing their last associated track
    size_t tracks;                 // distinct track ids seen, counted per run
    size_t false_tracks;           // of those, never associated in their run
    ms_siap_id_t id;               // identification counts
    /* Figures; NaN when the denominator is 0. */
    double completeness;          // Σ JT / Σ J, 0..1
    double ambiguity;             // Σ NA / Σ JT, >= 1
    double spuriousness;          // Σ (N − NA) / Σ N, 0..1
    double spuriousness_unseen;   // Σ unseen / Σ N: the part of it holding unseen vehicles
    double position_accuracy_m;   // mean distance track to truth, metres
    double swaps_per_truth_hour;  // swaps / truth hours
    double breaks_per_truth_hour; // breaks / truth hours
    double false_tracks_per_hour; // false tracks / run hours
    double id_completeness;       // id_identifiable_marked / id_identifiable, 0..1
    double id_correctness;        // id_correct / id_marked, 0..1
    double id_wrong_fraction;     // id_wrong / id_marked, 0..1
} ms_siap_result_t;

/* An empty accumulator; NULL on allocation failure. */
ms_siap_t *ms_siap_new (void);
/* Free; accepts NULL, nulls the pointer. */
void ms_siap_destroy (ms_siap_t **self_p);

/* Feed one scan at t_s (seconds of simulation time, later than the run's
 * previous scan): truths[n_truths] and tracks[n_tracks] (either may be NULL
 * when its count is 0). 0, -EINVAL (t_s not finite or not later, an id 0 or
 * repeated within the scan, a position not finite, NULL with a non-zero
 * count), -ENOMEM. On failure the accumulator is as it was. */
int ms_siap_add (ms_siap_t *self, double t_s, const ms_siap_truth_t *truths, size_t n_truths,
                 const ms_siap_track_t *tracks, size_t n_tracks);
/* Close the run under way (if any): the next scan starts a new run. */
void ms_siap_end_run (ms_siap_t *self);
/* Add src's runs (its run under way included) to dst as closed runs; dst's
 * own run under way goes on. 0, -EINVAL when dst is src. */
int ms_siap_merge (ms_siap_t *dst, const ms_siap_t *src);
/* Counts and figures so far, the run under way included. */
void ms_siap_result (const ms_siap_t *self, ms_siap_result_t *ret);
/* Add src's raw counts to dst's and work dst's figures out again: results
 * of whole runs (as Monte Carlo processes send them back) pool as
 * ms_siap_merge pools their accumulators. A zeroed dst is empty. */
void ms_siap_result_pool (ms_siap_result_t *dst, const ms_siap_result_t *src);

#endif
