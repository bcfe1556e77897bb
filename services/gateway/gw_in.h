/* gw_in — other simulations' entities, heard as Entity State PDUs: each
 * keyed by its DIS id, given an internal entity id of its own, dead-reckoned
 * between PDUs by the algorithm it was sent with, and forgotten after a
 * silence (12 s, 2.4 heartbeats) or a PDU with the deactivated bit. Pure: no
 * sockets, no logging. */
#ifndef GW_IN_H
#define GW_IN_H

#include "cgs_geo.h"
#include "gw_dr.h"
#include "gw_pdu.h"
#include "world.pb-c.h"

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

typedef struct {
    gw_id_t dis_id;
    uint32_t entity_id; // internal id, from the table's first id up
    gw_dr_t dr;         // the last PDU's state
    double heard_s;     // wall-clock time the last PDU arrived
    uint8_t force;
    gw_type_t type;
    char marking[GW_MARKING_LEN + 1];
    bool deactivated; // the last PDU said it left
} gw_in_entity_t;

typedef struct gw_in gw_in_t;

/* A table handing out internal ids first_id, first_id + 1, ... to at most
 * max entities at once; NULL without memory. */
gw_in_t *gw_in_new (uint32_t first_id, size_t max);
/* Free; accepts NULL; nulls the pointer. */
void gw_in_destroy (gw_in_t **self_p);

/* Take a decoded Entity State PDU heard at wall time now_s; *ret_new (may
 * be NULL) tells whether the entity was new. 0, -ENOSPC when the table is
 * full, or -ENOMEM. */
int gw_in_take (gw_in_t *self, const gw_espdu_t *pdu, double now_s, bool *ret_new);
/* Remove the entities silent for more than timeout_s at now_s, and those
 * deactivated; fn (may be NULL) sees each before it goes. The count removed. */
size_t gw_in_expire (gw_in_t *self, double now_s, double timeout_s,
                     void (*fn) (void *arg, const gw_in_entity_t *e), void *arg);
/* Iterate: *cursor = 0 first; NULL at the end. The table must not change meanwhile. */
const gw_in_entity_t *gw_in_next (const gw_in_t *self, size_t *cursor);
/* The entity of a DIS id, or NULL. */
const gw_in_entity_t *gw_in_find (const gw_in_t *self, gw_id_t id);
size_t gw_in_count (const gw_in_t *self);

/* The entity as an `entity` message at wall time now_s: dead-reckoned,
 * in the local frame, marked external. The strings and submessages point
 * into *storage, which must outlive msg. 0 or -EINVAL (not finite, or not
 * convertible). */
typedef struct {
    Cgs__Enu position;
    Cgs__EnuVelocity velocity;
    Cgs__EntityType type;
    Cgs__DisEntityId dis_id;
    char marking[GW_MARKING_LEN + 1];
} gw_in_storage_t;
int gw_in_entity_msg (const cgs_geo_t *geo, const gw_in_entity_t *e, double now_s,
                      gw_in_storage_t *storage, Cgs__Entity *msg);

#endif
