/* test_gw_out_in — when our entities go out over DIS and what becomes of
 * theirs, against 1278.1's rules worked by hand: a ground entity on a straight
 * line sends its first PDU and then only heartbeats (5 s of simulation time, or of
 * wall time while paused); a 2°
 * turn is under the 3° threshold and a 4° one is not; 0.5 m off the
 * dead-reckoned line is under 1 m and 1.5 m is not; an accelerating aircraft
 * sends once its acceleration is known and then tracks; deactivation goes out
 * once. External entities are dead-reckoned along their velocity, renamed from
 * first_id up, expired after the timeout or the deactivated bit, and refused
 * past the table's size. Positions are checked in ECEF through cgs_geo. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "cgs_geo.h"
#include "gw_in.h"
#include "gw_out.h"

#include <errno.h>
#include <math.h>
#include <string.h>

#include "test_util.h"

#define DEG (M_PI / 180.0)

static int s_setup (void **state)
{
    *state = cgs_geo_new (35.96, -121.23, 0);
    return *state ? 0 : -1;
}

static int s_teardown (void **state)
{
    cgs_geo_t *geo = *state;
    cgs_geo_destroy (&geo);
    return 0;
}

/* An entity message with its submessages. */
typedef struct {
    Cgs__Entity e;
    Cgs__Enu p;
    Cgs__EnuVelocity v;
    Cgs__EntityType type;
} s_msg_t;

static void s_msg (s_msg_t *m, uint32_t id, Cgs__EntityKind kind, const double p[3],
                   const double v[3], double heading_deg)
{
    cgs__entity__init (&m->e);
    cgs__enu__init (&m->p);
    cgs__enu_velocity__init (&m->v);
    cgs__entity_type__init (&m->type);
    m->type.kind = 1, m->type.domain = 1, m->type.country = 222, m->type.category = 1;
    m->p.east_m = p[0], m->p.north_m = p[1], m->p.up_m = p[2];
    m->v.east_mps = v[0], m->v.north_mps = v[1], m->v.up_mps = v[2];
    m->e.entity_id = id;
    m->e.kind = kind;
    m->e.force = CGS__FORCE__FORCE_HOSTILE;
    m->e.dis_type = &m->type;
    m->e.marking = "T\001NK 01 LONGER"; // a control character, and too long
    m->e.position = &m->p;
    m->e.velocity = &m->v;
    m->e.heading_deg = heading_deg;
    m->e.active = true;
}

static cgs_ecef_t s_ecef (const cgs_geo_t *geo, const double p[3])
{
    cgs_ecef_t x;
    assert_int_equal (cgs_geo_enu_to_ecef (geo, (cgs_enu_t){p[0], p[1], p[2]}, &x), 0);
    return x;
}

static void test_truth (void **state)
{
    const cgs_geo_t *geo = *state;
    const double p[3] = {1200, -800, 15}, v[3] = {3, 4, 0.5};
    s_msg_t m;
    s_msg (&m, 42, CGS__ENTITY_KIND__ENTITY_KIND_TRACKED, p, v, 90);
    gw_truth_t t;
    assert_int_equal (gw_out_truth (geo, &m.e, &t), 0);
    cgs_ecef_t x = s_ecef (geo, p);
    assert_near (t.pos[0], x.x_m, 1e-6);
    assert_near (t.pos[1], x.y_m, 1e-6);
    assert_near (t.pos[2], x.z_m, 1e-6);
    // ENU to ECEF is affine: the velocity is the difference over one second's travel.
    cgs_ecef_t x1 = s_ecef (geo, (double[3]){p[0] + v[0], p[1] + v[1], p[2] + v[2]});
    assert_near (t.vel[0], x1.x_m - x.x_m, 1e-6);
    assert_near (t.vel[1], x1.y_m - x.y_m, 1e-6);
    assert_near (t.vel[2], x1.z_m - x.z_m, 1e-6);
    assert_int_equal (t.entity_id, 42);
    assert_true (t.active);
    assert_false (t.air);
    assert_int_equal (t.force, 2);
    assert_int_equal (t.type.country, 222);
    assert_string_equal (t.marking, "T?NK 01 LON");
    // Heading 90 in the exercise frame: forward is the frame's east axis, which
    // at the origin's latitude and longitude is (-sin lon, cos lon, 0); down is
    // minus the origin's ellipsoid normal; right is the frame's south.
    double la = 35.96 * DEG, lo = -121.23 * DEG;
    const double east[3] = {-sin (lo), cos (lo), 0};
    const double up[3] = {cos (la) * cos (lo), cos (la) * sin (lo), sin (la)};
    const double north[3] = {-sin (la) * cos (lo), -sin (la) * sin (lo), cos (la)};
    for (int i = 0; i < 3; i++) {
        assert_near (t.R[0][i], east[i], 1e-12);
        assert_near (t.R[1][i], -north[i], 1e-12);
        assert_near (t.R[2][i], -up[i], 1e-12);
    }
    // Heading 0, pitch 10° up: forward is cos 10 north + sin 10 up.
    m.e.heading_deg = 0, m.e.pitch_deg = 10;
    m.e.kind = CGS__ENTITY_KIND__ENTITY_KIND_AIR;
    assert_int_equal (gw_out_truth (geo, &m.e, &t), 0);
    assert_true (t.air);
    for (int i = 0; i < 3; i++)
        assert_near (t.R[0][i], cos (10 * DEG) * north[i] + sin (10 * DEG) * up[i], 1e-12);
    // Refused: entity id 0, no position, a velocity or angle that is not finite.
    m.e.entity_id = 0;
    assert_int_equal (gw_out_truth (geo, &m.e, &t), -EINVAL);
    m.e.entity_id = 42, m.e.position = NULL;
    assert_int_equal (gw_out_truth (geo, &m.e, &t), -EINVAL);
    m.e.position = &m.p, m.v.north_mps = NAN;
    assert_int_equal (gw_out_truth (geo, &m.e, &t), -EINVAL);
    m.v.north_mps = 4, m.e.heading_deg = INFINITY;
    assert_int_equal (gw_out_truth (geo, &m.e, &t), -EINVAL);
}

/* Update an entity at ENU position p; the decision. */
static gw_send_t s_update (const cgs_geo_t *geo, gw_out_t *out, s_msg_t *m, const double p[3],
                           double t_s, double now_s, gw_truth_t *ret_truth, gw_dr_t *ret_dr)
{
    m->p.east_m = p[0], m->p.north_m = p[1], m->p.up_m = p[2];
    assert_int_equal (gw_out_truth (geo, &m->e, ret_truth), 0);
    gw_send_t send = (gw_send_t)-1;
    assert_int_equal (gw_out_update (out, ret_truth, t_s, now_s, &send, ret_dr), 0);
    return send;
}

static const double s_p0[3] = {100, 200, 0}, s_v[3] = {5, 3, 0};

static void s_at (double t, double off_m, double p[3])
{
    const double n = sqrt (34); // off_m to the left of (5, 3): along (-3, 5) / sqrt 34
    p[0] = s_p0[0] + s_v[0] * t - 3 / n * off_m;
    p[1] = s_p0[1] + s_v[1] * t + 5 / n * off_m;
    p[2] = s_p0[2];
}

static void test_heartbeat (void **state)
{
    const cgs_geo_t *geo = *state;
    gw_out_params_t par;
    gw_out_params_defaults (&par);
    gw_out_t *out = gw_out_new (&par);
    assert_non_null (out);
    s_msg_t m;
    s_msg (&m, 7, CGS__ENTITY_KIND__ENTITY_KIND_WHEELED, s_p0, s_v, atan2 (5, 3) / DEG);
    gw_truth_t tr;
    gw_dr_t dr;
    double p[3];
    int heartbeats = 0;
    // 10 updates per wall second, the simulation at twice wall time: a
    // heartbeat every 5 simulated seconds (k = 25, 50, 75, 100).
    for (int k = 0; k <= 100; k++) {
        s_at (k / 5.0, 0, p);
        gw_send_t send = s_update (geo, out, &m, p, k / 5.0, 1000 + k / 10.0, &tr, &dr);
        gw_send_t want = k == 0 ? GW_SEND_FIRST : k % 25 == 0 ? GW_SEND_HEARTBEAT : GW_SEND_NONE;
        if (send != want)
            fail_msg ("update %d: sent %d, want %d", k, send, want);
        heartbeats += send == GW_SEND_HEARTBEAT;
        if (k == 0) {
            assert_int_equal (dr.algorithm, GW_DR_FPW); // ground
            for (int i = 0; i < 3; i++) {
                assert_true (dr.pos[i] == tr.pos[i] && dr.vel[i] == tr.vel[i]);
                assert_true (dr.acc[i] == 0 && dr.omega[i] == 0);
            }
        }
    }
    assert_int_equal (heartbeats, 4);
    // Paused (the simulation time stands still): a heartbeat every 5 s of
    // wall time all the same, so receivers keep the entity.
    heartbeats = 0;
    for (int k = 1; k <= 100; k++) {
        gw_send_t send = s_update (geo, out, &m, p, 20.0, 1010 + k / 10.0, &tr, &dr);
        heartbeats += send == GW_SEND_HEARTBEAT;
        if (send != (k % 50 == 0 ? GW_SEND_HEARTBEAT : GW_SEND_NONE))
            fail_msg ("paused, update %d: sent %d", k, send);
    }
    assert_int_equal (heartbeats, 2);
    assert_int_equal (gw_out_count (out), 1);
    gw_out_destroy (&out);
    assert_null (out);
    gw_out_destroy (&out);
}

static void test_thresholds (void **state)
{
    const cgs_geo_t *geo = *state;
    gw_out_params_t par;
    gw_out_params_defaults (&par);
    gw_out_t *out = gw_out_new (&par);
    assert_non_null (out);
    s_msg_t m;
    s_msg (&m, 8, CGS__ENTITY_KIND__ENTITY_KIND_TRACKED, s_p0, s_v, 30);
    gw_truth_t tr;
    gw_dr_t dr;
    double p[3];
    // Heading 30 sent; 32 (2° off) is kept; 34 (4° off) goes out.
    s_at (0, 0, p);
    assert_int_equal (s_update (geo, out, &m, p, 0, 0, &tr, &dr), GW_SEND_FIRST);
    m.e.heading_deg = 32;
    s_at (0.1, 0, p);
    assert_int_equal (s_update (geo, out, &m, p, 0.1, 0.1, &tr, &dr), GW_SEND_NONE);
    m.e.heading_deg = 34;
    s_at (0.2, 0, p);
    assert_int_equal (s_update (geo, out, &m, p, 0.2, 0.2, &tr, &dr), GW_SEND_ORIENTATION);
    assert_near (gw_dr_rot_angle (dr.R, tr.R), 0, 1e-12); // now what receivers hold
    s_at (0.3, 0, p);
    assert_int_equal (s_update (geo, out, &m, p, 0.3, 0.3, &tr, &dr), GW_SEND_NONE);
    // 0.5 m to the side of the dead-reckoned line is kept; 1.5 m goes out.
    s_at (1.0, 0.5, p);
    assert_int_equal (s_update (geo, out, &m, p, 1.0, 1.0, &tr, &dr), GW_SEND_NONE);
    s_at (1.1, 1.5, p);
    assert_int_equal (s_update (geo, out, &m, p, 1.1, 1.1, &tr, &dr), GW_SEND_POSITION);
    for (int i = 0; i < 3; i++)
        assert_true (dr.pos[i] == tr.pos[i]);
    s_at (1.5, 1.5, p); // on the new line
    assert_int_equal (s_update (geo, out, &m, p, 1.5, 1.5, &tr, &dr), GW_SEND_NONE);
    // Deactivation goes out once, standing still with the deactivated bit.
    m.e.active = false;
    s_at (1.6, 1.5, p);
    assert_int_equal (s_update (geo, out, &m, p, 1.6, 1.6, &tr, &dr), GW_SEND_DEACTIVATED);
    assert_int_equal (dr.algorithm, GW_DR_STATIC);
    for (int i = 0; i < 3; i++)
        assert_true (dr.pos[i] == tr.pos[i] && dr.vel[i] == 0);
    gw_espdu_t pdu;
    memset (&pdu, 0, sizeof pdu);
    gw_out_fill (&tr, &dr, (gw_id_t){1, 1, 8}, &pdu);
    assert_true (pdu.appearance & GW_APPEARANCE_DEACTIVATED);
    assert_int_equal (pdu.dr_algorithm, GW_DR_STATIC);
    assert_int_equal (pdu.id.entity, 8);
    assert_int_equal (pdu.force, 2);
    assert_int_equal (pdu.marking_charset, 1);
    assert_string_equal (pdu.marking, "T?NK 01 LON");
    assert_int_equal (s_update (geo, out, &m, p, 1.7, 1.7, &tr, &dr), GW_SEND_NONE);
    assert_int_equal (s_update (geo, out, &m, p, 9.0, 9.0, &tr, &dr), GW_SEND_NONE);
    m.e.active = true; // back again: a first PDU once more
    assert_int_equal (s_update (geo, out, &m, p, 9.1, 9.1, &tr, &dr), GW_SEND_FIRST);
    memset (&pdu, 0, sizeof pdu);
    gw_out_fill (&tr, &dr, (gw_id_t){1, 1, 8}, &pdu);
    assert_int_equal (pdu.appearance, 0);
    // Its orientation: the nose (body x, row 0 of the world-to-body matrix of the
    // PDU's Euler angles) points along the heading in the exercise frame, taken to
    // ECEF axes by the frame's rotation, as the velocity is; the wings (body y)
    // are level: at right angles to the frame's up, written out in closed form.
    double e3[3] = {pdu.orientation[0], pdu.orientation[1], pdu.orientation[2]}, R[3][3];
    gw_dr_rot_from_euler (e3, R);
    double h = m.e.heading_deg * DEG;
    cgs_ecef_t nose;
    cgs_geo_enu_vector_to_ecef (geo, (cgs_enu_t){sin (h), cos (h), 0}, &nose);
    assert_true (R[0][0] * nose.x_m + R[0][1] * nose.y_m + R[0][2] * nose.z_m > cos (1e-6));
    double la = 35.96 * DEG, lo = -121.23 * DEG; // the frame's origin
    double up[3] = {cos (la) * cos (lo), cos (la) * sin (lo), sin (la)};
    assert_near (R[1][0] * up[0] + R[1][1] * up[1] + R[1][2] * up[2], 0, 1e-6);
    gw_out_destroy (&out);
}

// An aircraft accelerating east at 2.5 m/s² from rest: RVW with acceleration zero
// at first, 1.25 t² off by t = 0.9 s (1.01 m), then sent with the acceleration
// from two successive states, after which dead reckoning tracks it exactly.
static void test_air (void **state)
{
    const cgs_geo_t *geo = *state;
    gw_out_params_t par;
    gw_out_params_defaults (&par);
    gw_out_t *out = gw_out_new (&par);
    assert_non_null (out);
    s_msg_t m;
    s_msg (&m, 9, CGS__ENTITY_KIND__ENTITY_KIND_AIR, (double[3]){0, 0, 100}, (double[3]){0, 0, 0},
           90);
    gw_truth_t tr;
    gw_dr_t dr;
    for (int k = 0; k <= 58; k++) {
        double t = k / 10.0;
        m.v.east_mps = 2.5 * t;
        gw_send_t send = s_update (geo, out, &m, (double[3]){1.25 * t * t, 0, 100}, t, t, &tr, &dr);
        gw_send_t want = k == 0 ? GW_SEND_FIRST : k == 9 ? GW_SEND_POSITION : GW_SEND_NONE;
        if (send != want)
            fail_msg ("update %d: sent %d, want %d", k, send, want);
        if (k == 0)
            assert_int_equal (dr.algorithm, GW_DR_RVW);
        if (k == 9) {
            cgs_ecef_t e0 = s_ecef (geo, (double[3]){0, 0, 100});
            cgs_ecef_t e1 = s_ecef (geo, (double[3]){2.5, 0, 100}); // 2.5 m/s² east
            assert_near (dr.acc[0], e1.x_m - e0.x_m, 1e-6);
            assert_near (dr.acc[1], e1.y_m - e0.y_m, 1e-6);
            assert_near (dr.acc[2], e1.z_m - e0.z_m, 1e-6);
            for (int i = 0; i < 3; i++)
                assert_near (dr.omega[i], 0, 1e-6);
        }
    }
    gw_out_destroy (&out);
}

/* ---- external entities ---- */

static void s_pdu (const cgs_geo_t *geo, gw_espdu_t *p, uint16_t entity, const double enu[3])
{
    memset (p, 0, sizeof *p);
    p->hdr.version = 7;
    p->id = (gw_id_t){7, 8, entity};
    p->force = 2;
    p->type = (gw_type_t){1, 1, 225, 1, 1, 0, 0}; // a tank
    cgs_ecef_t x = s_ecef (geo, enu);
    p->location[0] = x.x_m, p->location[1] = x.y_m, p->location[2] = x.z_m;
    p->velocity[0] = 3, p->velocity[1] = -4, p->velocity[2] = 12;            // 13 m/s, ECEF axes
    p->acceleration[0] = 1, p->acceleration[1] = 2, p->acceleration[2] = -2; // FPW ignores it
    // Heading 45 from the exercise frame's north, as the models give headings.
    cgs_dis_euler_t eu;
    cgs_geo_dis_euler_from_local (geo, 45, 0, 0, &eu);
    p->orientation[0] = (float)eu.psi_rad, p->orientation[1] = (float)eu.theta_rad;
    p->orientation[2] = (float)eu.phi_rad;
    p->dr_algorithm = GW_DR_FPW;
    p->marking_charset = 1;
    strcpy (p->marking, "TANK 01");
}

typedef struct {
    int n;
    gw_id_t last;
} s_gone_t;

static void s_gone (void *arg, const gw_in_entity_t *e)
{
    s_gone_t *g = arg;
    g->n++;
    g->last = e->dis_id;
}

static void test_in (void **state)
{
    const cgs_geo_t *geo = *state;
    gw_in_t *in = gw_in_new (100000, 4);
    assert_non_null (in);
    gw_espdu_t p;
    const double enu[3] = {100, 200, 0};
    s_pdu (geo, &p, 9, enu);
    bool fresh = false;
    assert_int_equal (gw_in_take (in, &p, 50.0, &fresh), 0);
    assert_true (fresh);
    const gw_in_entity_t *e = gw_in_find (in, (gw_id_t){7, 8, 9});
    assert_non_null (e);
    assert_int_equal (e->entity_id, 100000);
    // Asked 2 s later: 2 s along the velocity, in ECEF, seen in the local frame.
    gw_in_storage_t st;
    Cgs__Entity msg;
    assert_int_equal (gw_in_entity_msg (geo, e, 52.0, &st, &msg), 0);
    cgs_enu_t want, w0, w1;
    const double x0[3] = {p.location[0], p.location[1], p.location[2]};
    assert_int_equal (
        cgs_geo_ecef_to_enu (geo, (cgs_ecef_t){x0[0] + 6, x0[1] - 8, x0[2] + 24}, &want), 0);
    assert_near (msg.position->east_m, want.e_m, 1e-6);
    assert_near (msg.position->north_m, want.n_m, 1e-6);
    assert_near (msg.position->up_m, want.u_m, 1e-6);
    assert_int_equal (cgs_geo_ecef_to_enu (geo, (cgs_ecef_t){x0[0], x0[1], x0[2]}, &w0), 0);
    assert_int_equal (
        cgs_geo_ecef_to_enu (geo, (cgs_ecef_t){x0[0] + 3, x0[1] - 4, x0[2] + 12}, &w1), 0);
    assert_near (msg.velocity->east_mps, w1.e_m - w0.e_m, 1e-6);
    assert_near (msg.velocity->north_mps, w1.n_m - w0.n_m, 1e-6);
    assert_near (msg.velocity->up_mps, w1.u_m - w0.u_m, 1e-6);
    assert_near (msg.speed_mps, hypot (w1.e_m - w0.e_m, w1.n_m - w0.n_m), 1e-6);
    assert_near (msg.heading_deg, 45, 0.01); // 26 m away: north turns by under 0.001°
    assert_near (msg.pitch_deg, 0, 0.01);
    assert_true (msg.external);
    assert_true (msg.active);
    assert_int_equal (msg.entity_id, 100000);
    assert_string_equal (msg.marking, "TANK 01");
    assert_int_equal (msg.force, CGS__FORCE__FORCE_HOSTILE);
    assert_int_equal (msg.kind, CGS__ENTITY_KIND__ENTITY_KIND_TRACKED);
    assert_int_equal (msg.dis_type->country, 225);
    assert_int_equal (msg.dis_id->site, 7);
    assert_int_equal (msg.dis_id->entity, 9);
    // The same DIS id again is the same entity; another id gets the next internal id.
    assert_int_equal (gw_in_take (in, &p, 53.0, &fresh), 0);
    assert_false (fresh);
    s_pdu (geo, &p, 10, enu);
    assert_int_equal (gw_in_take (in, &p, 60.0, &fresh), 0);
    assert_true (fresh);
    assert_int_equal (gw_in_find (in, p.id)->entity_id, 100001);
    assert_int_equal (gw_in_count (in), 2);
    // Sent with RVW, the acceleration counts: 2 s later p + 2 v + a 2²/2, moving at v + 2 a.
    p.dr_algorithm = GW_DR_RVW;
    assert_int_equal (gw_in_take (in, &p, 60.0, NULL), 0);
    assert_int_equal (gw_in_entity_msg (geo, gw_in_find (in, p.id), 62.0, &st, &msg), 0);
    assert_int_equal (
        cgs_geo_ecef_to_enu (geo, (cgs_ecef_t){x0[0] + 8, x0[1] - 4, x0[2] + 20}, &want), 0);
    assert_near (msg.position->east_m, want.e_m, 1e-6);
    assert_near (msg.position->up_m, want.u_m, 1e-6);
    assert_int_equal (cgs_geo_ecef_to_enu (geo, (cgs_ecef_t){x0[0] + 5, x0[1], x0[2] + 8}, &w1), 0);
    assert_near (msg.velocity->north_mps, w1.n_m - w0.n_m, 1e-6);
    assert_near (msg.velocity->up_mps, w1.u_m - w0.u_m, 1e-6);
    // Silent for exactly the timeout stays; for longer it goes, through the callback.
    s_gone_t gone = {0, {0, 0, 0}};
    assert_int_equal (gw_in_expire (in, 65.0, 12.0, s_gone, &gone), 0);
    assert_int_equal (gw_in_expire (in, 65.5, 12.0, s_gone, &gone), 1);
    assert_int_equal (gone.n, 1);
    assert_true (gw_pdu_id_eq (gone.last, (gw_id_t){7, 8, 9}));
    assert_null (gw_in_find (in, (gw_id_t){7, 8, 9}));
    assert_int_equal (gw_in_find (in, (gw_id_t){7, 8, 10})->entity_id, 100001);
    size_t cursor = 0, n = 0;
    while ((e = gw_in_next (in, &cursor))) {
        assert_int_equal (e->dis_id.entity, 10);
        n++;
    }
    assert_int_equal (n, 1);
    // The deactivated bit: reported inactive, removed at the next expiry.
    p.appearance = GW_APPEARANCE_DEACTIVATED;
    assert_int_equal (gw_in_take (in, &p, 66.0, NULL), 0);
    assert_int_equal (gw_in_entity_msg (geo, gw_in_find (in, p.id), 66.0, &st, &msg), 0);
    assert_false (msg.active);
    assert_int_equal (gw_in_expire (in, 66.0, 12.0, s_gone, &gone), 1);
    assert_int_equal (gone.n, 2);
    assert_int_equal (gw_in_count (in), 0);
    gw_in_destroy (&in);
    assert_null (in);
}

static void test_in_full (void **state)
{
    const cgs_geo_t *geo = *state;
    gw_in_t *in = gw_in_new (5, 2);
    assert_non_null (in);
    gw_espdu_t p;
    for (uint16_t k = 1; k <= 2; k++) {
        s_pdu (geo, &p, k, (double[3]){k, 0, 0});
        assert_int_equal (gw_in_take (in, &p, 0, NULL), 0);
        assert_int_equal (gw_in_find (in, p.id)->entity_id, 4u + k);
    }
    s_pdu (geo, &p, 3, (double[3]){3, 0, 0});
    assert_int_equal (gw_in_take (in, &p, 0, NULL), -ENOSPC);
    assert_null (gw_in_find (in, p.id));
    assert_int_equal (gw_in_count (in), 2);
    s_pdu (geo, &p, 2, (double[3]){2, 0, 0}); // one already known is still taken
    assert_int_equal (gw_in_take (in, &p, 1, NULL), 0);
    gw_in_destroy (&in);
}

int main (void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test (test_truth),      cmocka_unit_test (test_heartbeat),
        cmocka_unit_test (test_thresholds), cmocka_unit_test (test_air),
        cmocka_unit_test (test_in),         cmocka_unit_test (test_in_full),
    };
    return cmocka_run_group_tests (tests, s_setup, s_teardown);
}
