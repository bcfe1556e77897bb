/* cgs_entities — the latest state of every entity (see cgs_entities.h):
 * open addressing by id, rebuilt when it grows or when entities are evicted. */
#include "cgs_entities.h"

#include <assert.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#define S_MIN_CAP 1024

typedef struct {
    bool used;
    cgs_entity_state_t s;
} s_slot_t;

struct cgs_entities {
    s_slot_t *slots; // capacity a power of two, at most half full
    size_t cap, count;
    double latest_s;
};

cgs_entities_t *cgs_entities_new (void)
{
    cgs_entities_t *self = calloc (1, sizeof *self);
    if (!self)
        return NULL;
    self->slots = calloc (S_MIN_CAP, sizeof *self->slots);
    if (!self->slots)
        goto fail;
    self->cap = S_MIN_CAP;
    return self;
fail:
    cgs_entities_destroy (&self);
    return NULL;
}

void cgs_entities_destroy (cgs_entities_t **self_p)
{
    assert (self_p);
    cgs_entities_t *self = *self_p;
    if (!self)
        return;
    free (self->slots);
    free (self);
    *self_p = NULL;
}

/* Fibonacci hashing: the high bits of id times 2^32 / phi (the low bits of
 * the product depend only on the id's low bits). cap is a power of two. */
static size_t s_find (const s_slot_t *slots, size_t cap, uint32_t id)
{
    int bits = __builtin_ctzll (cap);
    size_t mask = cap - 1, i = (size_t)((id * 2654435761u) >> (32 - bits)) & mask;
    while (slots[i].used && slots[i].s.id != id)
        i = (i + 1) & mask;
    return i;
}

/* Move the entities that keep (newer than cutoff) into a table of cap slots. */
static int s_rebuild (cgs_entities_t *self, size_t cap, double cutoff)
{
    s_slot_t *fresh = calloc (cap, sizeof *fresh);
    if (!fresh)
        return -ENOMEM;
    size_t kept = 0;
    for (size_t i = 0; i < self->cap; i++)
        if (self->slots[i].used && self->slots[i].s.time_s >= cutoff) {
            fresh[s_find (fresh, cap, self->slots[i].s.id)] = self->slots[i];
            kept++;
        }
    free (self->slots);
    self->slots = fresh;
    self->cap = cap;
    self->count = kept;
    return 0;
}

static bool s_finite (const Cgs__Enu *p)
{
    return p && isfinite (p->east_m) && isfinite (p->north_m) && isfinite (p->up_m);
}

static bool s_finite_v (const Cgs__EnuVelocity *v)
{
    return v && isfinite (v->east_mps) && isfinite (v->north_mps) && isfinite (v->up_mps);
}

int cgs_entities_update (cgs_entities_t *self, const Cgs__EntityBatch *batch, double t_s,
                         size_t *ret_bad)
{
    size_t bad = 0;
    int rc = 0;
    for (size_t i = 0; i < batch->n_entities; i++) {
        const Cgs__Entity *e = batch->entities[i];
        if (!isfinite (t_s) || e->entity_id == 0 || !s_finite (e->position) ||
            !s_finite_v (e->velocity) || !isfinite (e->heading_deg)) {
            bad++;
            continue;
        }
        if ((self->count + 1) * 2 > self->cap &&
            (rc = s_rebuild (self, self->cap * 2, -INFINITY)) < 0)
            break;
        s_slot_t *slot = &self->slots[s_find (self->slots, self->cap, e->entity_id)];
        if (!slot->used) {
            slot->used = true;
            self->count++;
        }
        cgs_entity_state_t *s = &slot->s;
        s->id = e->entity_id;
        s->force = (cgs_force_t)e->force;
        s->kind = (cgs_kind_t)e->kind;
        s->active = e->active;
        s->external = e->external;
        s->bcis_transponder = e->bcis_transponder;
        s->position = (cgs_enu_t){e->position->east_m, e->position->north_m, e->position->up_m};
        s->velocity =
            (cgs_enu_t){e->velocity->east_mps, e->velocity->north_mps, e->velocity->up_mps};
        s->heading_deg = e->heading_deg;
        s->time_s = t_s;
        snprintf (s->rcs_class, sizeof s->rcs_class, "%s", e->rcs_class ? e->rcs_class : "");
        snprintf (s->marking, sizeof s->marking, "%s", e->marking ? e->marking : "");
        if (t_s > self->latest_s)
            self->latest_s = t_s;
    }
    if (rc == 0 && ret_bad)
        *ret_bad = bad;
    return rc;
}

void cgs_entities_evict (cgs_entities_t *self, double t_s, double stale_s)
{
    double cutoff = t_s - stale_s;
    size_t kept = 0;
    for (size_t i = 0; i < self->cap; i++)
        if (self->slots[i].used && self->slots[i].s.time_s >= cutoff)
            kept++;
    if (kept == self->count)
        return;
    size_t cap = S_MIN_CAP;
    while (cap < kept * 2)
        cap *= 2;
    (void)s_rebuild (self, cap, cutoff); // without memory the old table stays; tried next time
}

const cgs_entity_state_t *cgs_entities_find (const cgs_entities_t *self, uint32_t id)
{
    const s_slot_t *slot = &self->slots[s_find (self->slots, self->cap, id)];
    return slot->used ? &slot->s : NULL;
}

const cgs_entity_state_t *cgs_entities_next (const cgs_entities_t *self, size_t *cursor)
{
    while (*cursor < self->cap) {
        const s_slot_t *slot = &self->slots[(*cursor)++];
        if (slot->used)
            return &slot->s;
    }
    return NULL;
}

size_t cgs_entities_count (const cgs_entities_t *self)
{
    return self->count;
}

double cgs_entities_latest_s (const cgs_entities_t *self)
{
    return self->latest_s;
}

bool cgs_entity_at (const cgs_entity_state_t *s, double t_s, double stale_s,
                    const cgs_terrain_t *terrain, cgs_enu_t *ret_pos)
{
    double dt = t_s - s->time_s;
    if (!s->active || dt > stale_s || dt < -stale_s)
        return false;
    cgs_enu_t p = {s->position.e_m + s->velocity.e_m * dt, s->position.n_m + s->velocity.n_m * dt,
                   s->position.u_m + s->velocity.u_m * dt};
    if (s->kind != CGS_KIND_AIR && terrain)
        p.u_m = cgs_terrain_height_clamped (terrain, p.e_m, p.n_m);
    *ret_pos = p;
    return true;
}

void cgs_entities_take (cgs_entities_t *self, const ProtobufCMessage *msg, const Cgs__Header *hdr,
                        const cgs_port_t *port)
{
    size_t bad = 0;
    if (cgs_entities_update (self, (const Cgs__EntityBatch *)msg, hdr->sim_time_s, &bad) < 0)
        cgs_port_error (port, "out of memory for entities");
    for (size_t i = 0; i < bad; i++)
        cgs_port_bad_input (port,
                            "an entity without a valid id, position, velocity, heading or time");
}
