/* cgs_entities — the latest state of every entity heard on `entity`, keyed
 * by entity id, for the services that model sensors over them (mtid, bcisd,
 * imagerd). Each batch's entities are checked (an id, a finite position,
 * velocity and heading) before they replace what was known; entities not
 * heard of for a while are forgotten by cgs_entities_evict. Pure: no
 * logging, no globals; the caller counts and logs what was refused. */
#ifndef CGS_ENTITIES_H
#define CGS_ENTITIES_H

#include "cgs_geo.h"
#include "cgs_port.h"
#include "cgs_scenario.h"
#include "header.pb-c.h"
#include "world.pb-c.h"

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#define CGS_ENTITY_CLASS_MAX 32 // radar cross-section class, with its terminating NUL

/* One entity as last heard of. */
typedef struct {
    uint32_t id;
    cgs_force_t force;
    cgs_kind_t kind;
    bool active;           // false once it has left the exercise
    bool external;         // came in from DIS through the gateway
    bool bcis_transponder; // carries a BCIS transponder
    cgs_enu_t position;    // local frame, metres
    cgs_enu_t velocity;    // metres per second
    double heading_deg;    // clockwise from north
    double time_s;         // simulation time of this state
    char rcs_class[CGS_ENTITY_CLASS_MAX];
    char marking[CGS_MARKING_MAX + 1];
} cgs_entity_state_t;

typedef struct cgs_entities cgs_entities_t;

/* An empty table, or NULL without memory. */
cgs_entities_t *cgs_entities_new (void);
/* Free; accepts NULL; sets *self_p to NULL. */
void cgs_entities_destroy (cgs_entities_t **self_p);

/* Take a batch's states at simulation time t_s. 0, or -ENOMEM (what was
 * taken before stays); on success *ret_bad (may be NULL) counts the entities refused
 * for a missing id, position or velocity or a non-finite value (or all of
 * them for a non-finite time). */
int cgs_entities_update (cgs_entities_t *self, const Cgs__EntityBatch *batch, double t_s,
                         size_t *ret_bad);
/* Take an `entity` batch (msg, with its header) as a service does: each
 * entity refused is the port's bad input, running out of memory its
 * error. */
void cgs_entities_take (cgs_entities_t *self, const ProtobufCMessage *msg, const Cgs__Header *hdr,
                        const cgs_port_t *port);
/* Forget every entity whose state is older than t_s - stale_s. */
void cgs_entities_evict (cgs_entities_t *self, double t_s, double stale_s);
/* The entity of that id, or NULL. */
const cgs_entity_state_t *cgs_entities_find (const cgs_entities_t *self, uint32_t id);
/* Iterate: start with *cursor = 0; the next entity, or NULL at the end.
 * The table must not change during an iteration. */
const cgs_entity_state_t *cgs_entities_next (const cgs_entities_t *self, size_t *cursor);
/* Where entity s is at time t_s, dead-reckoned from its last state along
 * its velocity (the sensors' view between `entity` batches); a ground
 * entity (not CGS_KIND_AIR) is put on the terrain there (NULL: height as
 * reckoned). False, and *ret_pos untouched, when it is inactive or its
 * state is more than stale_s from t_s either way. */
bool cgs_entity_at (const cgs_entity_state_t *s, double t_s, double stale_s,
                    const cgs_terrain_t *terrain, cgs_enu_t *ret_pos);
/* Entities known, and the newest simulation time heard of (0 before any). */
size_t cgs_entities_count (const cgs_entities_t *self);
double cgs_entities_latest_s (const cgs_entities_t *self);

#endif
