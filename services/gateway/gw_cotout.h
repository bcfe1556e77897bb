/* gw_cotout — the exercise as Cursor on Target events (the codec is gw_cot):
 *  - every confirmed or coasting track of `track`: type from its identity
 *    (a-f-G-E-V friendly, a BCIS responder's vehicle; a-u-G unknown: the
 *    tracker knows no other identities), how m-p (machine-generated, passed
 *    on from another system: the tracker), ce
 *    the 1-sigma radius of its position covariance's major axis, course and
 *    speed; a deleted track once more, stale at once, so clients drop it;
 *  - every UAV of `uav`: a-f-A-M-F-Q with its callsign, course and speed and
 *    the imaging sensor (azimuth, elevation, fields of view, range to the
 *    footprint's centre when there is one);
 *  - each UAV's intercept (`intercept`) route as a u-d-f line and its
 *    sensor footprint as a closed u-d-f polygon; once the intercept ends,
 *    both once more, stale at once.
 * Each object is sent at rate_hz of wall-clock time. A UAV's event is stale
 * stale_s after it is sent (uavsim reports UAVs while paused too); a
 * track's is stale stale_s after the batch that last carried it, so a
 * track the tracker no longer reports (or a paused exercise's) drops from
 * the clients then, and is no longer sent.
 * Times are wall-clock UTC. Every event is marked as simulation (opex
 * "s-PREFIX"). uids: PREFIX-EX.track.ID, PREFIX-EX.uav.NAME,
 * PREFIX-EX.route.NAME, PREFIX-EX.footprint.NAME (EX the exercise id).
 *
 * Pure: no logging, no sockets; events go to the emit callback. */
#ifndef GW_COTOUT_H
#define GW_COTOUT_H

#include "cgs_geo.h"
#include "gw_cot.h"
#include "gw_params.h"
#include "intercept.pb-c.h"
#include "tracking.pb-c.h"
#include "world.pb-c.h"

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

typedef struct gw_cotout gw_cotout_t;
/* An event to send (valid during the call). */
typedef void gw_cotout_emit_fn (void *arg, const gw_cot_event_t *e);

typedef struct {
    uint64_t events, tracks, uavs, drawings, removed;
    uint64_t unplaceable; // positions that could not be placed on the Earth
} gw_cotout_stats_t;

/* With the [cot] parameters of p (copied), the frame (borrowed) and the
 * exercise id. NULL: out of memory. */
gw_cotout_t *gw_cotout_new (const gw_params_t *p, const cgs_geo_t *geo, uint32_t exercise_id,
                            gw_cotout_emit_fn *emit, void *arg);
void gw_cotout_destroy (gw_cotout_t **self_p);
/* The bus's messages, taken at wall-clock UTC now_s. Tracks of a batch are
 * sent when due; a deleted one at once. */
void gw_cotout_on_tracks (gw_cotout_t *self, const Cgs__TrackBatch *b, double now_s);
void gw_cotout_on_uav (gw_cotout_t *self, const Cgs__Uav *u, double now_s);
void gw_cotout_on_intercept (gw_cotout_t *self, const Cgs__Intercept *m, double now_s);
/* Send what is due at now_s, and forget what has gone stale. */
void gw_cotout_tick (gw_cotout_t *self, double now_s);
/* The UAV whose name or uid (PREFIX-EX.uav.NAME) is given, or with "" the
 * first heard: its entity id, 0 when none. */
uint32_t gw_cotout_uav_id (const gw_cotout_t *self, const char *name_or_uid);
/* The uid of the UAV of that entity id into buf ("" when unknown). */
void gw_cotout_uav_uid (const gw_cotout_t *self, uint32_t uav_id, char *buf, size_t len);
/* Whether a uid is one of ours (PREFIX-EX.). */
bool gw_cotout_is_ours (const gw_cotout_t *self, const char *uid);
const gw_cotout_stats_t *gw_cotout_stats (const gw_cotout_t *self);

#endif
