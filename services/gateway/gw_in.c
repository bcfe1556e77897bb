/* gw_in — external entities heard over DIS. */
#include "gw_in.h"

#include "gw_index.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

struct gw_in {
    gw_in_entity_t *ents; // dense
    size_t count, cap, max;
    gw_index_t *index; // DIS id -> position in ents
    uint32_t next_id;
    uint32_t first_id;
};

static uint64_t s_key (gw_id_t id)
{
    return (uint64_t)id.site << 32 | (uint64_t)id.application << 16 | id.entity;
}

gw_in_t *gw_in_new (uint32_t first_id, size_t max)
{
    gw_in_t *self = calloc (1, sizeof *self);
    if (!self)
        return NULL;
    self->max = max;
    self->first_id = self->next_id = first_id;
    if (!(self->index = gw_index_new ()))
        gw_in_destroy (&self);
    return self;
}

void gw_in_destroy (gw_in_t **self_p)
{
    if (!self_p || !*self_p)
        return;
    gw_index_destroy (&(*self_p)->index);
    free ((*self_p)->ents);
    free (*self_p);
    *self_p = NULL;
}

size_t gw_in_count (const gw_in_t *self)
{
    return self->count;
}

const gw_in_entity_t *gw_in_find (const gw_in_t *self, gw_id_t id)
{
    size_t at;
    return gw_index_get (self->index, s_key (id), &at) ? &self->ents[at] : NULL;
}

const gw_in_entity_t *gw_in_next (const gw_in_t *self, size_t *cursor)
{
    return *cursor < self->count ? &self->ents[(*cursor)++] : NULL;
}

/* An internal id no present entity has (ids wrap within 2^31 past the first). */
static uint32_t s_new_id (gw_in_t *self)
{
    for (;;) {
        uint32_t id = self->next_id++;
        if (self->next_id - self->first_id >= 0x80000000u)
            self->next_id = self->first_id;
        bool taken = false;
        for (size_t i = 0; i < self->count && !taken; i++)
            taken = self->ents[i].entity_id == id;
        if (!taken)
            return id;
    }
}

int gw_in_take (gw_in_t *self, const gw_espdu_t *pdu, double now_s, bool *ret_new)
{
    size_t at;
    bool fresh = !gw_index_get (self->index, s_key (pdu->id), &at);
    if (fresh) {
        if (self->count >= self->max)
            return -ENOSPC;
        if (self->count == self->cap) {
            size_t cap = self->cap ? self->cap * 2 : 64;
            gw_in_entity_t *ents = realloc (self->ents, cap * sizeof *ents);
            if (!ents)
                return -ENOMEM;
            self->ents = ents;
            self->cap = cap;
        }
        at = self->count;
        if (gw_index_put (self->index, s_key (pdu->id), at) < 0)
            return -ENOMEM;
        memset (&self->ents[at], 0, sizeof self->ents[at]);
        self->ents[at].dis_id = pdu->id;
        self->ents[at].entity_id = s_new_id (self);
        self->count++;
    }
    gw_in_entity_t *e = &self->ents[at];
    e->heard_s = now_s;
    e->force = pdu->force;
    e->type = pdu->type;
    memcpy (e->marking, pdu->marking, sizeof e->marking);
    e->deactivated = pdu->appearance & GW_APPEARANCE_DEACTIVATED;
    e->dr.algorithm = pdu->dr_algorithm;
    double angles[3];
    for (int i = 0; i < 3; i++) {
        e->dr.pos[i] = pdu->location[i];
        e->dr.vel[i] = pdu->velocity[i];
        e->dr.acc[i] = pdu->acceleration[i];
        e->dr.omega[i] = pdu->angular_velocity[i];
        angles[i] = pdu->orientation[i];
    }
    gw_dr_rot_from_euler (angles, e->dr.R);
    if (ret_new)
        *ret_new = fresh;
    return 0;
}

size_t gw_in_expire (gw_in_t *self, double now_s, double timeout_s,
                     void (*fn) (void *arg, const gw_in_entity_t *e), void *arg)
{
    size_t kept = 0, removed = 0;
    for (size_t i = 0; i < self->count; i++) {
        gw_in_entity_t *e = &self->ents[i];
        if (e->deactivated || now_s - e->heard_s > timeout_s) {
            if (fn)
                fn (arg, e);
            removed++;
            continue;
        }
        if (kept != i)
            self->ents[kept] = *e;
        kept++;
    }
    if (removed) {
        self->count = kept;
        gw_index_clear (self->index);
        for (size_t i = 0; i < kept; i++)
            gw_index_put (self->index, s_key (self->ents[i].dis_id), i); // never grows: fewer keys
    }
    return removed;
}

/* The kind of entity the models know, from a DIS entity type (SISO-REF-010). */
static Cgs__EntityKind s_kind (gw_type_t t)
{
    if (t.kind == 3)
        return CGS__ENTITY_KIND__ENTITY_KIND_PERSON; // life form
    if (t.kind != 1)
        return CGS__ENTITY_KIND__ENTITY_KIND_OTHER;
    if (t.domain == 2)
        return CGS__ENTITY_KIND__ENTITY_KIND_AIR;
    if (t.domain != 1)
        return CGS__ENTITY_KIND__ENTITY_KIND_OTHER;
    // Land platforms: small and large wheeled utility vehicles (6, 7) are wheeled;
    // tanks, fighting and utility armour, artillery and tracked utility vehicles tracked.
    if (t.category == 6 || t.category == 7)
        return CGS__ENTITY_KIND__ENTITY_KIND_WHEELED;
    if ((t.category >= 1 && t.category <= 5) || t.category == 8 || t.category == 9)
        return CGS__ENTITY_KIND__ENTITY_KIND_TRACKED;
    return CGS__ENTITY_KIND__ENTITY_KIND_OTHER;
}

int gw_in_entity_msg (const cgs_geo_t *geo, const gw_in_entity_t *e, double now_s,
                      gw_in_storage_t *st, Cgs__Entity *msg)
{
    double t = now_s - e->heard_s, pos[3], R[3][3];
    gw_dr_at (&e->dr, t, pos, R);
    // Velocity now, in world axes.
    double v[3] = {0, 0, 0};
    uint8_t a = e->dr.algorithm;
    if (a >= GW_DR_FPW && a <= GW_DR_FVB) {
        double acc = gw_dr_accelerates (a) ? t : 0;
        for (int i = 0; i < 3; i++)
            v[i] = e->dr.vel[i] + e->dr.acc[i] * acc;
        if (gw_dr_body (a)) {
            double w[3];
            for (int i = 0; i < 3; i++)
                w[i] = e->dr.R[0][i] * v[0] + e->dr.R[1][i] * v[1] + e->dr.R[2][i] * v[2];
            memcpy (v, w, sizeof v);
        }
    }
    cgs_enu_t p, vel;
    if (cgs_geo_ecef_to_enu (geo, (cgs_ecef_t){pos[0], pos[1], pos[2]}, &p) < 0)
        return -EINVAL;
    cgs_geo_ecef_vector_to_enu (geo, (cgs_ecef_t){v[0], v[1], v[2]}, &vel);
    double angles[3], heading, pitch, roll;
    gw_dr_euler_from_rot (R, angles);
    // In the exercise frame's terms, as the models take them (see gw_out_truth).
    cgs_geo_local_from_dis_euler (geo, (cgs_dis_euler_t){angles[0], angles[1], angles[2]}, &heading,
                                  &pitch, &roll);
    if (!isfinite (p.e_m) || !isfinite (p.n_m) || !isfinite (p.u_m) || !isfinite (vel.e_m) ||
        !isfinite (vel.n_m) || !isfinite (vel.u_m) || !isfinite (heading))
        return -EINVAL;
    cgs__enu__init (&st->position);
    st->position.east_m = p.e_m, st->position.north_m = p.n_m, st->position.up_m = p.u_m;
    cgs__enu_velocity__init (&st->velocity);
    st->velocity.east_mps = vel.e_m, st->velocity.north_mps = vel.n_m;
    st->velocity.up_mps = vel.u_m;
    cgs__entity_type__init (&st->type);
    st->type.kind = e->type.kind, st->type.domain = e->type.domain;
    st->type.country = e->type.country, st->type.category = e->type.category;
    st->type.subcategory = e->type.subcategory, st->type.specific = e->type.specific;
    st->type.extra = e->type.extra;
    cgs__dis_entity_id__init (&st->dis_id);
    st->dis_id.site = e->dis_id.site, st->dis_id.application = e->dis_id.application;
    st->dis_id.entity = e->dis_id.entity;
    // Printable ASCII only: the marking came off the network.
    size_t n = 0;
    for (size_t i = 0; i < GW_MARKING_LEN && e->marking[i]; i++) {
        unsigned char c = (unsigned char)e->marking[i];
        st->marking[n++] = c >= 0x20 && c <= 0x7e ? (char)c : '?';
    }
    st->marking[n] = '\0';
    cgs__entity__init (msg);
    msg->entity_id = e->entity_id;
    msg->marking = st->marking;
    msg->force = e->force <= 3 ? (Cgs__Force)e->force : CGS__FORCE__FORCE_UNKNOWN;
    msg->dis_type = &st->type;
    msg->kind = s_kind (e->type);
    msg->position = &st->position;
    msg->velocity = &st->velocity;
    msg->heading_deg = heading;
    msg->pitch_deg = pitch;
    msg->roll_deg = roll;
    msg->bcis_transponder = e->force == 1; // friendly forces carry BCIS transponders
    msg->rcs_class = msg->kind == CGS__ENTITY_KIND__ENTITY_KIND_PERSON ? "person" : "vehicle";
    msg->active = !e->deactivated;
    msg->external = true;
    msg->dis_id = &st->dis_id;
    msg->speed_mps = hypot (vel.e_m, vel.n_m);
    return 0;
}
