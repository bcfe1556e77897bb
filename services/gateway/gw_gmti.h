/* gw_gmti — the radars' bus messages as STANAG 4607 packets (the codec is
 * gw_s4607). Per radar (a UAV that carries one, keyed by its entity id):
 * the first packet holds a mission segment (platform type UAV, the
 * exercise indicator "exercise, simulated data") and a job definition;
 * then platform location segments at the parameters' rate, from `uav`,
 * with the mission and job again every 60 s of simulation time (for a
 * receiver that joins late);
 * and one dwell segment per `mti` message (one MTI dwell), a target report
 * per hit. With truth tags on, a dwell waits for its `mti.truth` (mtid
 * publishes it right after the dwell's `mti`), whose items name the entity
 * of each hit; the next `mti` of that radar, gw_gmti_tick or gw_gmti_flush
 * sends a dwell whose truth did not come without truth tag fields (a tag of
 * 0 would say "a false alarm"). A dwell too large for one
 * packet is split over packets of consecutive dwell segments that share
 * the dwell index, only the last marked last of the revisit.
 *
 * Times in the segments are the exercise clock (set by gw_gmti_set_clock:
 * UTC at a simulation time, the simulation time running from there, as
 * the DIS timestamps), in milliseconds since midnight UTC of the reference
 * date of the mission segment, the date of the first packet.
 *
 * Pure: no logging, no sockets; packets go to the emit callback. */
#ifndef GW_GMTI_H
#define GW_GMTI_H

#include "cgs_geo.h"
#include "gw_params.h"
#include "sensors.pb-c.h"
#include "world.pb-c.h"

#include <stddef.h>
#include <stdint.h>

#define GW_GMTI_PACKET_MAX 65000 // one UDP datagram

typedef struct gw_gmti gw_gmti_t;
/* A finished packet (valid during the call). */
typedef void gw_gmti_emit_fn (void *arg, const uint8_t *packet, size_t len);

typedef struct {
    uint64_t packets, dwells, reports, platforms, missions;
    uint64_t tagged;      // target reports with a truth tag
    uint64_t untagged;    // dwells sent without their truth (it did not come in time)
    uint64_t unplaceable; // hits or platform states that could not be placed on the Earth, and
                          // segments the encoder refused (counted in health)
    uint64_t no_uav;      // dwells of a radar whose UAV was not heard yet: sent with what is known
} gw_gmti_stats_t;

/* For the exercise id (the packets' mission id), the DIS site and
 * application and entity-id base (truth tags), the [stanag4607] parameters
 * of p (copied) and the frame (borrowed). NULL: out of memory. */
gw_gmti_t *gw_gmti_new (const gw_params_t *p, const cgs_geo_t *geo, uint32_t exercise_id,
                        gw_gmti_emit_fn *emit, void *arg);
void gw_gmti_destroy (gw_gmti_t **self_p);
/* The exercise clock: UTC utc_s (seconds since the Unix epoch) at simulation
 * time sim_s. Until set, UTC is taken to be the simulation time past
 * 2000-01-01. */
void gw_gmti_set_clock (gw_gmti_t *self, double utc_s, double sim_s);
/* A UAV's state at simulation time t_s: remembered for its dwells, and a
 * platform location segment when one is due. */
void gw_gmti_on_uav (gw_gmti_t *self, const Cgs__Uav *u, double t_s);
/* One dwell's hits. -EINVAL when the message lacks what a dwell segment
 * must say (a radar: a uav id, at most 64 radars; a platform position on
 * the Earth; finite times), -ENOMEM without memory: nothing sent. A hit
 * without a position is left out and counted (unplaceable). */
int gw_gmti_on_mti (gw_gmti_t *self, const Cgs__Mti *m);
/* The truth of a dwell: tags the pending dwell it belongs to and sends it. */
void gw_gmti_on_truth (gw_gmti_t *self, const Cgs__MtiTruth *t);
/* Called periodically: send, untagged, the dwells that were already
 * pending at the previous call (their truth had a whole period to come). */
void gw_gmti_tick (gw_gmti_t *self);
/* Send every pending dwell as it is (at exit). */
void gw_gmti_flush (gw_gmti_t *self);
const gw_gmti_stats_t *gw_gmti_stats (const gw_gmti_t *self);

#endif
