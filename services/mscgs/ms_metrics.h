/* ms_metrics — tracking quality measured against ground truth, from the
 * messages of an exercise (live in `mscgs run`, or in lockstep): after each
 * radar scan's complete `track` batch, the scan's truths and tracks feed
 * GOSPA (p = 2, alpha = 2, cut-off 500 m: ms_gospa) and the SIAP-style
 * figures (ms_siap).
 *
 * Truths of a scan: the ground vehicles that radar has detected at least
 * once so far (a hit attributed to them in `mti.truth`) and that were in
 * its beam and visible (in range and line of sight) during the scan, at
 * their true position (`entity`) moved on to the scan's end.
 *
 * Tracks of a scan: the radar's confirmed and coasting tracks of that scan.
 *
 * Truth-to-track assignment (SIAP): a track stands for the vehicle that
 * produced most of the MTI hits in its history (attributed by `mti.truth`,
 * ms_icpt_track_entity), when that vehicle is one of the scan's truths and
 * within the cut-off (500 m) of the track; otherwise it stands for none.
 * GOSPA makes its own optimal assignment of positions.
 *
 * Identification (ms_siap's ID figures): a truth's identity is its entity
 * id when `entity` says it is friendly with a BCIS transponder (0
 * otherwise), and it is hostile when its force is; a track claims its
 * `friendly_id` (0: none). */
#ifndef MS_METRICS_H
#define MS_METRICS_H

#include "cgs_json.h"
#include "ms_gospa.h"
#include "ms_observer.h"
#include "ms_siap.h"

#include <stdio.h>

#define MS_METRICS_C_M 500.0 // GOSPA cut-off and association gate, metres
#define MS_METRICS_P   2.0   // GOSPA order

typedef struct ms_metrics ms_metrics_t;

/* Metrics over the messages seen, using ic's hit attribution (ic must be
 * fed `mti.truth` too, and outlive this). NULL without memory. */
ms_metrics_t *ms_metrics_new (ms_icpt_t *ic);
/* Free; accepts NULL; nulls the pointer. */
void ms_metrics_destroy (ms_metrics_t **self_p);
/* The handlers of `entity`, `mti.truth` and `track` (arg: the ms_metrics_t). */
void ms_metrics_on_entity (void *arg, const char *topic, const ProtobufCMessage *msg,
                           const Cgs__Header *hdr);
void ms_metrics_on_mti_truth (void *arg, const char *topic, const ProtobufCMessage *msg,
                              const Cgs__Header *hdr);
void ms_metrics_on_track (void *arg, const char *topic, const ProtobufCMessage *msg,
                          const Cgs__Header *hdr);
/* One radar scan's figures, as they are computed. */
typedef struct {
    uint32_t uav_id;       // the radar's UAV
    double t_s;            // simulation time of the scan's end
    ms_gospa_t gospa;      // GOSPA of the scan
    size_t truths;         // the scan's truths
    size_t tracks;         // its confirmed and coasting tracks
    size_t tracked_truths; // truths with a track associated
    size_t unassociated;   // tracks associated with no truth of the scan
} ms_metrics_scan_t;
typedef void (ms_metrics_scan_fn) (void *arg, const ms_metrics_scan_t *scan);
/* Call fn after every scan (NULL: none). */
void ms_metrics_on_scan (ms_metrics_t *self, ms_metrics_scan_fn *fn, void *arg);
/* The accumulated figures (a run ends: ms_siap_end_run is the caller's). */
ms_siap_t *ms_metrics_siap (ms_metrics_t *self);
const ms_gospa_mean_t *ms_metrics_gospa (const ms_metrics_t *self);
/* The Tracking section of a summary, for a person. */
void ms_metrics_print (ms_metrics_t *self, FILE *f);
/* The same figures as a new JSON object (summary.json's "tracking": scans,
 * then the figures to 4 decimals, null when undefined); NULL without
 * memory. */
json_object *ms_metrics_json (ms_metrics_t *self);
/* Scans whose metrics could not be computed (out of memory): 0 in a sound run. */
uint64_t ms_metrics_failures (const ms_metrics_t *self);

#endif
