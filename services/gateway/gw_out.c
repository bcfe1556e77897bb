/* gw_out — when our entities go out as Entity State PDUs. */
#include "gw_out.h"

#include "gw_index.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <stdio.h>
#include <string.h>

#define S_DEG (M_PI / 180.0)

typedef struct {
    uint32_t id;
    bool sent;       // a PDU has gone out since it was last active
    bool have_prev;  // prev_* hold the state before this one
    double sent_t_s; // simulation time of the state sent
    double sent_wall_s;
    gw_dr_t dr; // what receivers extrapolate from
    double prev_t_s;
    double prev_vel[3];
    double prev_R[3][3];
} s_ent_t;

struct gw_out {
    gw_out_params_t p;
    s_ent_t *ents;
    size_t count, cap;
    gw_index_t *index;
};

void gw_out_params_defaults (gw_out_params_t *p)
{
    p->position_threshold_m = 1.0;
    p->orientation_threshold_deg = 3.0;
    p->heartbeat_s = 5.0;
}

gw_out_t *gw_out_new (const gw_out_params_t *params)
{
    gw_out_t *self = calloc (1, sizeof *self);
    if (!self)
        return NULL;
    self->p = *params;
    if (!(self->index = gw_index_new ()))
        gw_out_destroy (&self);
    return self;
}

void gw_out_destroy (gw_out_t **self_p)
{
    if (!self_p || !*self_p)
        return;
    gw_index_destroy (&(*self_p)->index);
    free ((*self_p)->ents);
    free (*self_p);
    *self_p = NULL;
}

size_t gw_out_count (const gw_out_t *self)
{
    return self->count;
}

static bool s_finite3 (const double v[3])
{
    return isfinite (v[0]) && isfinite (v[1]) && isfinite (v[2]);
}

int gw_out_truth (const cgs_geo_t *geo, const Cgs__Entity *e, gw_truth_t *ret)
{
    if (!e->position || !e->velocity || e->entity_id == 0)
        return -EINVAL;
    cgs_enu_t p = {e->position->east_m, e->position->north_m, e->position->up_m};
    cgs_enu_t v = {e->velocity->east_mps, e->velocity->north_mps, e->velocity->up_mps};
    gw_truth_t t;
    memset (&t, 0, sizeof t);
    cgs_ecef_t x, xv;
    cgs_dis_euler_t eu;
    if (cgs_geo_enu_to_ecef (geo, p, &x) < 0 || !isfinite (v.e_m) || !isfinite (v.n_m) ||
        !isfinite (v.u_m) || !isfinite (e->heading_deg) || !isfinite (e->pitch_deg) ||
        !isfinite (e->roll_deg))
        return -EINVAL;
    // Headings are from the exercise frame's north, as every model gives them, so the
    // attitude goes to ECEF by the same fixed rotation as the velocity and stays
    // aligned with it at any distance from the origin.
    cgs_geo_dis_euler_from_local (geo, e->heading_deg, e->pitch_deg, e->roll_deg, &eu);
    cgs_geo_enu_vector_to_ecef (geo, v, &xv);
    t.entity_id = e->entity_id;
    t.active = e->active;
    t.air = e->kind == CGS__ENTITY_KIND__ENTITY_KIND_AIR;
    t.force = (uint8_t)e->force;
    if (e->dis_type)
        t.type = (gw_type_t){(uint8_t)e->dis_type->kind,        (uint8_t)e->dis_type->domain,
                             (uint16_t)e->dis_type->country,    (uint8_t)e->dis_type->category,
                             (uint8_t)e->dis_type->subcategory, (uint8_t)e->dis_type->specific,
                             (uint8_t)e->dis_type->extra};
    snprintf (t.marking, sizeof t.marking, "%s", e->marking ? e->marking : "");
    for (char *c = t.marking; *c; c++)
        if ((unsigned char)*c < 0x20 || (unsigned char)*c > 0x7e)
            *c = '?'; // DIS markings are printable ASCII
    t.pos[0] = x.x_m, t.pos[1] = x.y_m, t.pos[2] = x.z_m;
    t.vel[0] = xv.x_m, t.vel[1] = xv.y_m, t.vel[2] = xv.z_m;
    double angles[3] = {eu.psi_rad, eu.theta_rad, eu.phi_rad};
    gw_dr_rot_from_euler (angles, t.R);
    if (!s_finite3 (t.pos) || !s_finite3 (t.vel) || !s_finite3 (angles))
        return -EINVAL;
    *ret = t;
    return 0;
}

static s_ent_t *s_entity (gw_out_t *self, uint32_t id)
{
    size_t at;
    if (gw_index_get (self->index, id, &at))
        return &self->ents[at];
    if (self->count == self->cap) {
        size_t cap = self->cap ? self->cap * 2 : 256;
        s_ent_t *ents = realloc (self->ents, cap * sizeof *ents);
        if (!ents)
            return NULL;
        self->ents = ents;
        self->cap = cap;
    }
    if (gw_index_put (self->index, id, self->count) < 0)
        return NULL;
    s_ent_t *e = &self->ents[self->count++];
    memset (e, 0, sizeof *e);
    e->id = id;
    return e;
}

/* The state a PDU sent now carries. */
static void s_dr_now (const s_ent_t *e, const gw_truth_t *t, double t_s, gw_dr_t *dr)
{
    memset (dr, 0, sizeof *dr);
    dr->algorithm = t->air ? GW_DR_RVW : GW_DR_FPW;
    memcpy (dr->pos, t->pos, sizeof dr->pos);
    memcpy (dr->vel, t->vel, sizeof dr->vel);
    memcpy (dr->R, t->R, sizeof dr->R);
    double dt = t_s - e->prev_t_s;
    if (t->air && e->have_prev && dt > 1e-6 && dt < 2.0) {
        for (int i = 0; i < 3; i++)
            dr->acc[i] = (t->vel[i] - e->prev_vel[i]) / dt;
        gw_dr_omega (e->prev_R, t->R, dt, dr->omega);
    }
}

int gw_out_update (gw_out_t *self, const gw_truth_t *truth, double t_s, double now_s,
                   gw_send_t *ret_send, gw_dr_t *ret_dr)
{
    s_ent_t *e = s_entity (self, truth->entity_id);
    if (!e)
        return -ENOMEM;
    gw_send_t send = GW_SEND_NONE;
    if (!truth->active) {
        if (e->sent) {
            send = GW_SEND_DEACTIVATED;
            e->sent = false;
            memcpy (ret_dr, &e->dr, sizeof *ret_dr);
            memcpy (ret_dr->pos, truth->pos, sizeof ret_dr->pos);
            memset (ret_dr->vel, 0, sizeof ret_dr->vel);
            memset (ret_dr->acc, 0, sizeof ret_dr->acc);
            memset (ret_dr->omega, 0, sizeof ret_dr->omega);
            ret_dr->algorithm = GW_DR_STATIC;
        }
        e->have_prev = false;
        *ret_send = send;
        return 0;
    }
    if (!e->sent) {
        send = GW_SEND_FIRST;
    } else {
        double pos[3], R[3][3];
        gw_dr_at (&e->dr, t_s - e->sent_t_s, pos, R);
        double dx = pos[0] - truth->pos[0], dy = pos[1] - truth->pos[1],
               dz = pos[2] - truth->pos[2];
        if (sqrt (dx * dx + dy * dy + dz * dz) > self->p.position_threshold_m)
            send = GW_SEND_POSITION;
        else if (gw_dr_rot_angle (R, truth->R) > self->p.orientation_threshold_deg * S_DEG)
            send = GW_SEND_ORIENTATION;
        else if (t_s - e->sent_t_s >= self->p.heartbeat_s ||
                 now_s - e->sent_wall_s >= self->p.heartbeat_s)
            send = GW_SEND_HEARTBEAT;
    }
    if (send != GW_SEND_NONE) {
        s_dr_now (e, truth, t_s, &e->dr);
        e->sent = true;
        e->sent_t_s = t_s;
        e->sent_wall_s = now_s;
        *ret_dr = e->dr;
    }
    e->have_prev = true;
    e->prev_t_s = t_s;
    memcpy (e->prev_vel, truth->vel, sizeof e->prev_vel);
    memcpy (e->prev_R, truth->R, sizeof e->prev_R);
    *ret_send = send;
    return 0;
}

void gw_out_fill (const gw_truth_t *truth, const gw_dr_t *dr, gw_id_t id, gw_espdu_t *ret)
{
    gw_header_t hdr = ret->hdr;
    memset (ret, 0, sizeof *ret);
    ret->hdr = hdr;
    ret->id = id;
    ret->force = truth->force;
    ret->type = truth->type;
    ret->alt_type = truth->type;
    double e[3];
    gw_dr_euler_from_rot (dr->R, e);
    for (int i = 0; i < 3; i++) {
        ret->velocity[i] = (float)dr->vel[i];
        ret->location[i] = dr->pos[i];
        ret->orientation[i] = (float)e[i];
        ret->acceleration[i] = (float)dr->acc[i];
        ret->angular_velocity[i] = (float)dr->omega[i];
    }
    ret->appearance = truth->active ? 0 : GW_APPEARANCE_DEACTIVATED;
    ret->dr_algorithm = dr->algorithm;
    ret->marking_charset = 1; // ASCII
    memcpy (ret->marking, truth->marking, sizeof ret->marking);
    ret->capabilities = 0;
}
