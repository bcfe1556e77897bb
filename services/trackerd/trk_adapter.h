/* trk_adapter — trackerd's pure layer between the tracker (trk_tracker) and
 * its transport. It takes the decoded `mti`, `mti.scan` and `bcis` messages,
 * validates them, assembles each radar's scan from its hits (held until the
 * scan's `mti.scan` marker, or closed without it when hits of the next scan
 * come), runs the tracker on each scan, and publishes through its port every
 * track of that radar after the scan (`track`, in batches of
 * TRK_ADAPTER_BATCH_TRACKS) and each turn the filter saw (`track.turn`).
 * BCIS replies mark tracks friendly. No sockets, clocks or logging of its
 * own: the daemon (main.c) and the mscgs tool's lockstep engine drive the
 * same code. */
#ifndef TRK_ADAPTER_H
#define TRK_ADAPTER_H

#include "cgs_msg.h"
#include "cgs_port.h"
#include "trk_params.h"
#include "trk_tracker.h"

#include <stdbool.h>
#include <stdint.h>

#define TRK_ADAPTER_BATCH_TRACKS 200 // tracks per `track` message
#define TRK_ADAPTER_RADARS_MAX   64  // radars whose open scans are kept

typedef struct trk_adapter trk_adapter_t;

typedef struct {
    uint64_t scans;          // scans run through the tracker
    uint64_t implicit_scans; // scans closed without their end marker
    uint64_t stale_scans;    // hits or markers of a scan already closed, ignored
    uint64_t hits;           // hits the tracker took
    uint64_t turns;          // turns published
    uint64_t bcis_marks;     // tracks BCIS replies marked friendly
    uint64_t born, deleted;  // tracks started, deleted
    uint64_t time_resets;    // tracks deleted because their radar's time went back
} trk_adapter_stats_t;

/* The topics it takes, NULL-terminated: "mti", "mti.scan", "bcis". */
extern const char *const trk_adapter_topics[];

/* An adapter over a new tracker with these parameters, reporting through
 * port (copied). NULL when the parameters are inconsistent or memory is
 * short. */
trk_adapter_t *trk_adapter_new (const trk_params_t *params, const cgs_port_t *port);
/* Free; accepts NULL; nulls the pointer. */
void trk_adapter_destroy (trk_adapter_t **self_p);
/* One decoded message of one of its topics, with its header (which may be
 * NULL: no simulation time); other topics are ignored. */
void trk_adapter_on_message (trk_adapter_t *self, const char *topic, const ProtobufCMessage *msg,
                             const Cgs__Header *hdr);
/* Log a line per scan (LOG_INFO) when true; when false, only for the first. */
void trk_adapter_set_verbose (trk_adapter_t *self, bool verbose);
/* The parameter file the tracker's parameters came from, for the errors
 * that name one of its keys (copied; NULL or "": the built-in defaults). */
void trk_adapter_set_params_path (trk_adapter_t *self, const char *path);
/* The tracker (for checkpoints and the daemon's log lines). */
trk_tracker_t *trk_adapter_tracker (trk_adapter_t *self);
/* Counters. */
const trk_adapter_stats_t *trk_adapter_stats (const trk_adapter_t *self);
/* Whether the tracks changed since the last call (a scan ran, or a BCIS
 * reply marked a track); clears the flag. */
bool trk_adapter_take_dirty (trk_adapter_t *self);

#endif
