/* gw_out — our entities as DIS sees them: each internal entity's true state
 * against what other simulations dead-reckon from the last Entity State PDU
 * we sent, and the decision to send another, as 1278.1 prescribes: when the
 * extrapolated position is off by more than a threshold (1 m) or the
 * orientation by more than one (3°), at least every heartbeat (5 s), and
 * once more when an entity leaves. In simulation time, as the velocities
 * are: the PDUs carry the state's simulation time as their timestamp, so a
 * receiver that dead-reckons by the timestamps stays within the thresholds
 * at any time scale. The heartbeat also comes every heartbeat of wall time:
 * receivers time entities out on their own clocks, and a paused or slowed
 * exercise must not vanish from them. Ground entities are sent with DR
 * algorithm FPW, air entities with RVW (acceleration and body rates from
 * successive states). Pure: no sockets, no logging. */
#ifndef GW_OUT_H
#define GW_OUT_H

#include "cgs_geo.h"
#include "gw_dr.h"
#include "gw_pdu.h"
#include "world.pb-c.h"

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

typedef struct {
    double position_threshold_m;      // default 1
    double orientation_threshold_deg; // default 3
    double heartbeat_s;               // default 5, of simulation time and of wall time
} gw_out_params_t;

/* An internal entity's true state, in DIS's terms. */
typedef struct {
    uint32_t entity_id;
    bool active;
    bool air;      // sent with RVW, else FPW
    uint8_t force; // DIS force id
    gw_type_t type;
    char marking[GW_MARKING_LEN + 1];
    double pos[3];  // ECEF, metres
    double vel[3];  // ECEF axes, m/s
    double R[3][3]; // world (ECEF) to body
} gw_truth_t;

typedef enum {
    GW_SEND_NONE = 0,
    GW_SEND_FIRST,       // never sent (or active again)
    GW_SEND_POSITION,    // dead-reckoned position off by more than the threshold
    GW_SEND_ORIENTATION, // dead-reckoned orientation off by more than the threshold
    GW_SEND_HEARTBEAT,   // nothing sent for a heartbeat
    GW_SEND_DEACTIVATED, // left the exercise: one last PDU with the deactivated bit
} gw_send_t;

typedef struct gw_out gw_out_t;

/* A new table, or NULL without memory. */
gw_out_t *gw_out_new (const gw_out_params_t *params);
/* Free; accepts NULL; nulls the pointer. */
void gw_out_destroy (gw_out_t **self_p);
/* The defaults. */
void gw_out_params_defaults (gw_out_params_t *p);

/* An entity message in DIS's terms: ECEF position and velocity from the
 * local frame, orientation from heading, pitch and roll in the tangent plane
 * at the entity's position. 0, or -EINVAL for a missing or non-finite value. */
int gw_out_truth (const cgs_geo_t *geo, const Cgs__Entity *e, gw_truth_t *ret);

/* Take a true state at simulation time t_s (for dead reckoning and the
 * heartbeat) and wall time now_s (for the heartbeat too); whether a PDU
 * goes out, and if so the state it carries (*ret_dr, which receivers will
 * extrapolate from). -ENOMEM when a new entity cannot be added. */
int gw_out_update (gw_out_t *self, const gw_truth_t *truth, double t_s, double now_s,
                   gw_send_t *ret_send, gw_dr_t *ret_dr);
/* Entities known. */
size_t gw_out_count (const gw_out_t *self);

/* Fill an Entity State PDU's body (everything but the header) from a state
 * that goes out. */
void gw_out_fill (const gw_truth_t *truth, const gw_dr_t *dr, gw_id_t id, gw_espdu_t *ret);

#endif
