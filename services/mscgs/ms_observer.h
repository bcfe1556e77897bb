/* ms_observer — what the mscgs tool knows of an intercept from ground
 * truth, as `mscgs run` and the lockstep Monte Carlo both judge it: the
 * designation, the true vehicle the designated track followed first (by
 * most of its MTI hits, from `mti.truth`), a hand-over to a track that
 * follows another vehicle, the intercept's state, and the score of the true
 * footprint against that vehicle's true position (cgs_score). Fed with the
 * decoded `intercept`, `track`, `mti.truth` and `entity` messages (their
 * handlers are cgs_sub_fn, for the bus and the lockstep bus alike). Pure:
 * no sockets, no logging; prints only where told. */
#ifndef MS_OBSERVER_H
#define MS_OBSERVER_H

#include "cgs_bus.h"
#include "cgs_footprint.h"
#include "cgs_json.h"
#include "cgs_msg.h"
#include "cgs_score.h"

#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>

#define MS_ICPT_HITS_MAX   4096 // hits remembered per radar (from mti.truth), the newest
#define MS_ICPT_RADARS_MAX 8    // radars whose hits are remembered
#define MS_ICPT_VOTES_MAX  32   // distinct entities counted among a track's hits
#define MS_ICPT_TRAIL      2048 // the designated vehicle's positions remembered...
#define MS_ICPT_TRAIL_DT_S 0.5  // ...at most one in this many seconds

/* The entity that produced each recent hit of one radar: a ring, oldest
 * overwritten first. */
typedef struct {
    uint32_t uav_id; // the radar
    uint64_t epoch;  // its mtid's epoch: hit ids start again at each start
    size_t next;     // slot the next hit goes to
    size_t count;    // slots filled
    uint32_t hit_id[MS_ICPT_HITS_MAX];
    uint32_t entity_id[MS_ICPT_HITS_MAX];
} ms_icpt_hits_t;

/* What `mscgs run` knows of the intercept, from ground truth. */
typedef struct {
    // The latest `intercept` message, whatever its designation (progress line).
    bool seen;
    Cgs__InterceptState state;
    uint32_t track_id;
    double latest_s; // latest simulation time of an intercept or entity message
    // The present designation (at the end of the run, the last one).
    bool designated;
    uint64_t designation_number;
    uint32_t desig_track_id;
    uint32_t first_track_id;         // the track designated (desig_track_id changes on a hand-over)
    Cgs__InterceptState desig_state; // its latest state; kept once final
    uint32_t replans;
    bool final;         // reached DONE, LOST or CANCELLED
    double final_s;     // simulation time it did
    uint32_t entity_id; // the designated target's true entity, 0 until known
    char marking[32];
    uint32_t other_entity_id; // the designated track, or one that took over, follows it instead
    char other_marking[32];
    // How it came to: when (the time of the first of the track's latest hits
    // that are the other vehicle's), how long the track had gone without a
    // hit before it, and how far that hit lay from the designated vehicle's
    // true position at its time (NAN when not known).
    double other_since_s;
    double other_unseen_s;
    double other_gap_m;
    // The designated vehicle's true positions, one every MS_ICPT_TRAIL_DT_S
    // at most, the newest MS_ICPT_TRAIL (a ring).
    double trail_t[MS_ICPT_TRAIL], trail_e[MS_ICPT_TRAIL], trail_n[MS_ICPT_TRAIL];
    size_t trail_next, trail_count;
    cgs_score_t score;
    // Which entity produced each recent hit, per radar.
    ms_icpt_hits_t radars[MS_ICPT_RADARS_MAX];
    size_t nradars;
    uint64_t radars_ignored; // mti.truth of radars beyond MS_ICPT_RADARS_MAX
    uint64_t malformed;      // messages with a non-finite time, position or corner, ignored
} ms_icpt_t;

/* Nothing seen yet. */
void ms_icpt_init (ms_icpt_t *ic);
/* The handlers of `intercept`, `mti.truth`, `track` and `entity` (arg: the ms_icpt_t). */
void ms_icpt_on_intercept (void *arg, const char *topic, const ProtobufCMessage *msg,
                           const Cgs__Header *hdr);
void ms_icpt_on_mti_truth (void *arg, const char *topic, const ProtobufCMessage *msg,
                           const Cgs__Header *hdr);
void ms_icpt_on_track (void *arg, const char *topic, const ProtobufCMessage *msg,
                       const Cgs__Header *hdr);
void ms_icpt_on_entity (void *arg, const char *topic, const ProtobufCMessage *msg,
                        const Cgs__Header *hdr);
/* The entity that produced most of a track's remembered hits (radar: the
 * track's radar), 0 if none is known. */
uint32_t ms_icpt_track_entity (ms_icpt_t *ic, uint32_t radar, const Cgs__Track *tr);
/* An intercept state's name without its prefix ("DONE"). */
const char *ms_icpt_state_name (Cgs__InterceptState state);
/* The intercept section of the summary, for a person. */
void ms_icpt_print (const ms_icpt_t *ic, FILE *f);
/* The intercept summary as a new JSON object (summary.json's members, in
 * the README's order; times to the millisecond, null when they do not
 * exist); NULL without memory. */
json_object *ms_icpt_json (const ms_icpt_t *ic);

#endif
