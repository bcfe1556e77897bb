/* test_gw_cotout — the exercise as Cursor on Target events, against values
 * worked by hand: a confirmed track of unknown identity is a-u-G, a coasting
 * friendly one a-f-G-E-V, a tentative one is not sent; how m-p; uid
 * mscgs-EX.track.ID; the point cgs_geo's geodetic position of the track;
 * ce the square root of the largest eigenvalue of the position block of the
 * 4x4 covariance (diag 100, 400: 20 m; [[73, 36], [36, 52]]: mean 62.5,
 * sqrt(10.5^2 + 36^2) = 37.5, largest 100: 10 m; [[0, 12], [12, 0]]:
 * sqrt 12); course and speed from the track's heading and speed; a track's
 * event stale stale_s after the batch that last carried it. Each object at
 * rate_hz of wall-clock time: a batch 0.2 s later sends nothing, the tick
 * 1 s after sends again; a deleted track goes out once, stale at once, and
 * is forgotten; a track no batch carries for stale_s is dropped without an
 * event, also among 600 tracks removed while the rest are sent. A UAV's or
 * a drawing's event is stale stale_s after it is sent. A UAV is
 * a-f-A-M-F-Q with its callsign and sensor (range 1200 m / sin 30 degrees =
 * 2400 m to flat ground, or 2000 m to its footprint's centre 1600 m north
 * and 1200 m down). An intercept under way is a u-d-f route (3 links,
 * yellow, ARGB -256) and a closed u-d-f footprint (4 links, cyan,
 * -16711681); when it ends (idle, done, cancelled, lost) both once more,
 * stale at once, and not again. The UAV lookups by name, uid and "". Every
 * event emitted must encode (gw_cot_encode_xml and gw_cot_encode_proto). */
#include "cgs_geo.h"
#include "gw_cot.h"
#include "gw_cotout.h"
#include "gw_params.h"

#include <errno.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "test_util.h"

#define S_EXERCISE 42
#define S_T0       1795773600.0 // 2026-11-27T10:00:00Z, wall clock
#define S_EVENTS   1024

/* ---- what the translator sends ------------------------------------------------------------- */

typedef struct {
    gw_cot_event_t e[S_EVENTS];
    size_t n;
} s_sink_t;

static void s_emit (void *arg, const gw_cot_event_t *e)
{
    s_sink_t *s = arg;
    static char xml[GW_COT_ENCODED_MAX];
    static uint8_t proto[GW_COT_ENCODED_MAX];
    if (gw_cot_encode_xml (e, xml, sizeof xml) == 0)
        fail_msg ("event %s (%s) does not encode as XML", e->uid, e->type);
    if (gw_cot_encode_proto (e, proto, sizeof proto) == 0)
        fail_msg ("event %s (%s) does not encode as TAK protobuf", e->uid, e->type);
    assert_true (s->n < S_EVENTS);
    s->e[s->n++] = *e;
}

typedef struct {
    cgs_geo_t *geo;
    gw_params_t p;
    s_sink_t sink;
} s_fix_t;

static int s_setup (void **state)
{
    s_fix_t *f = calloc (1, sizeof *f);
    if (!f || !(f->geo = cgs_geo_new (35.96, -121.23, 0)))
        return -1;
    gw_params_defaults (&f->p); // stale_s 15, rate_hz 1, uid prefix "mscgs"
    *state = f;
    return 0;
}

static int s_teardown (void **state)
{
    s_fix_t *f = *state;
    cgs_geo_destroy (&f->geo);
    free (f);
    return 0;
}

static gw_cotout_t *s_new (s_fix_t *f)
{
    gw_cotout_t *c = gw_cotout_new (&f->p, f->geo, S_EXERCISE, s_emit, &f->sink);
    assert_non_null (c);
    return c;
}

/* The point an ENU position must be sent at. */
static void s_assert_point (const s_fix_t *f, gw_cot_point_t got, double e, double n, double u)
{
    cgs_geodetic_t g;
    assert_int_equal (cgs_geo_enu_to_geodetic (f->geo, (cgs_enu_t){e, n, u}, &g), 0);
    assert_near (got.lat_deg, g.lat_deg, 1e-12);
    assert_near (got.lon_deg, g.lon_deg, 1e-12);
    assert_near (got.hae_m, g.height_m, 1e-6);
}

/* Times of an event sent at t, stale at stale_at (t itself: it removes its object). */
static void s_assert_times (const gw_cot_event_t *e, double t, double stale_at)
{
    assert_near (e->time_s, t, 1e-6);
    assert_near (e->start_s, t, 1e-6);
    assert_near (e->stale_s, stale_at, 1e-6);
}

/* ---- messages ------------------------------------------------------------------------------ */

typedef struct {
    Cgs__Track t;
    Cgs__Enu p;
    double cov[16];
} s_trk_t;

/* A track with a 4x4 covariance whose position block is [[ee, en], [en, nn]]. */
static void s_trk (s_trk_t *x, uint32_t id, Cgs__TrackStatus status, double e, double n,
                   double heading_deg, double speed_mps, double ee, double en, double nn)
{
    cgs__track__init (&x->t);
    cgs__enu__init (&x->p);
    x->p.east_m = e, x->p.north_m = n, x->p.up_m = 12;
    memset (x->cov, 0, sizeof x->cov);
    x->cov[0] = ee, x->cov[1] = x->cov[4] = en, x->cov[5] = nn;
    x->cov[10] = x->cov[15] = 4; // the velocity block and the position-velocity
    x->cov[2] = x->cov[8] = 3;   // terms: no part of ce
    x->t.track_id = id;
    x->t.status = status;
    x->t.position = &x->p;
    x->t.heading_deg = heading_deg;
    x->t.speed_mps = speed_mps;
    x->t.n_covariance = 16;
    x->t.covariance = x->cov;
}

typedef struct {
    Cgs__TrackBatch b;
    Cgs__Track *tp[8];
} s_batch_t;

static void s_batch (s_batch_t *b, s_trk_t *t, size_t n)
{
    cgs__track_batch__init (&b->b);
    for (size_t i = 0; i < n; i++)
        b->tp[i] = &t[i].t;
    b->b.uav_id = 7;
    b->b.n_tracks = n;
    b->b.tracks = b->tp;
}

typedef struct {
    Cgs__Uav u;
    Cgs__Enu p;
    Cgs__EnuVelocity v;
    Cgs__ImagingSensor s;
} s_uav_t;

static void s_uav (s_uav_t *m, uint32_t id, const char *name)
{
    cgs__uav__init (&m->u);
    cgs__enu__init (&m->p);
    cgs__enu_velocity__init (&m->v);
    cgs__imaging_sensor__init (&m->s);
    m->p.east_m = 2000, m->p.north_m = -1000, m->p.up_m = 1200;
    m->v.north_mps = 25;
    m->s.hfov_deg = 20, m->s.vfov_deg = 15, m->s.depression_deg = 30;
    m->u.entity_id = id;
    m->u.name = (char *)name;
    m->u.position = &m->p;
    m->u.velocity = &m->v;
    m->u.sensor = &m->s;
    m->u.heading_deg = 3; // not the course: the UAV moves
    m->u.sensor_azimuth_deg = -30;
    m->u.sensor_elevation_deg = -30;
}

typedef struct {
    Cgs__Intercept m;
    Cgs__Enu route[3], corner[4], center;
    Cgs__Enu *rp[3], *cp[4];
    Cgs__Footprint fp;
} s_icpt_t;

/* UAV 7's intercept of track 11, under way: a route of three points and a
 * footprint of four corners about (2000, 600, 0). */
static void s_icpt (s_icpt_t *x)
{
    cgs__intercept__init (&x->m);
    cgs__footprint__init (&x->fp);
    const double r[3][3] = {{2500, 0, 1200}, {3500, 500, 1000}, {4500, 1500, 900}};
    const double c[4][3] = {{1900, 500, 0}, {1900, 700, 0}, {2100, 700, 0}, {2100, 500, 0}};
    for (int i = 0; i < 3; i++) {
        cgs__enu__init (&x->route[i]);
        x->route[i].east_m = r[i][0], x->route[i].north_m = r[i][1], x->route[i].up_m = r[i][2];
        x->rp[i] = &x->route[i];
    }
    for (int i = 0; i < 4; i++) {
        cgs__enu__init (&x->corner[i]);
        x->corner[i].east_m = c[i][0], x->corner[i].north_m = c[i][1], x->corner[i].up_m = c[i][2];
        x->cp[i] = &x->corner[i];
    }
    cgs__enu__init (&x->center);
    x->center.east_m = 2000, x->center.north_m = 600, x->center.up_m = 0;
    x->fp.n_corners = 4;
    x->fp.corners = x->cp;
    x->fp.center = &x->center;
    x->m.uav_id = 7;
    x->m.track_id = 11;
    x->m.state = CGS__INTERCEPT_STATE__INTERCEPT_STATE_APPROACH;
    x->m.n_route = 3;
    x->m.route = x->rp;
    x->m.footprint = &x->fp;
}

/* ---- tests --------------------------------------------------------------------------------- */

static void test_tracks (void **state)
{
    s_fix_t *f = *state;
    gw_cotout_t *c = s_new (f);
    s_trk_t t[3];
    s_trk (&t[0], 11, CGS__TRACK_STATUS__TRACK_STATUS_CONFIRMED, 1500, 2500, 30, 8, 100, 0, 400);
    s_trk (&t[1], 12, CGS__TRACK_STATUS__TRACK_STATUS_COASTING, -3000, 500, -90, 5, 73, 36, 52);
    t[1].t.identity = CGS__TRACK_IDENTITY__TRACK_IDENTITY_FRIENDLY;
    t[1].t.friendly_id = 77;
    s_trk (&t[2], 13, CGS__TRACK_STATUS__TRACK_STATUS_TENTATIVE, 0, 0, 0, 0, 1, 0, 1);
    s_batch_t b;
    s_batch (&b, t, 3);
    gw_cotout_on_tracks (c, &b.b, S_T0);
    assert_int_equal (f->sink.n, 2); // not the tentative one

    const gw_cot_event_t *e = &f->sink.e[0];
    assert_string_equal (e->uid, "mscgs-42.track.11");
    assert_string_equal (e->type, "a-u-G");
    assert_string_equal (e->how, "m-p");
    assert_string_equal (e->opex, "s-mscgs");
    assert_string_equal (e->callsign, "T11");
    s_assert_times (e, S_T0, S_T0 + 15);
    s_assert_point (f, e->point, 1500, 2500, 12);
    assert_near (e->ce_m, 20, 1e-9); // sqrt 400
    assert_true (e->has_track);
    assert_near (e->course_deg, 30, 1e-9);
    assert_near (e->speed_mps, 8, 1e-9);

    e = &f->sink.e[1];
    assert_string_equal (e->uid, "mscgs-42.track.12");
    assert_string_equal (e->type, "a-f-G-E-V");
    assert_string_equal (e->how, "m-p");
    s_assert_times (e, S_T0, S_T0 + 15);
    s_assert_point (f, e->point, -3000, 500, 12);
    assert_near (e->ce_m, 10, 1e-9); // [[73, 36], [36, 52]]: largest eigenvalue 100
    assert_near (e->course_deg, 270, 1e-9);
    assert_near (e->speed_mps, 5, 1e-9);
    assert_non_null (strstr (e->remarks, "BCIS responder 77"));
    assert_int_equal (gw_cotout_stats (c)->tracks, 2);

    // 0.2 s later: not due.
    f->sink.n = 0;
    t[0].p.east_m += 2, t[1].p.north_m -= 1;
    gw_cotout_on_tracks (c, &b.b, S_T0 + 0.2);
    assert_int_equal (f->sink.n, 0);
    gw_cotout_tick (c, S_T0 + 0.9);
    assert_int_equal (f->sink.n, 0);
    // A second after they went out: both, where the latest batch put them,
    // stale 15 s after that batch.
    gw_cotout_tick (c, S_T0 + 1.0);
    assert_int_equal (f->sink.n, 2);
    bool seen[2] = {false, false};
    for (size_t i = 0; i < 2; i++) {
        e = &f->sink.e[i];
        s_assert_times (e, S_T0 + 1.0, S_T0 + 0.2 + 15);
        if (strcmp (e->uid, "mscgs-42.track.11") == 0) {
            seen[0] = true;
            s_assert_point (f, e->point, 1502, 2500, 12);
        } else if (strcmp (e->uid, "mscgs-42.track.12") == 0) {
            seen[1] = true;
            s_assert_point (f, e->point, -3000, 499, 12);
        }
    }
    assert_true (seen[0] && seen[1]);

    // Track 11 deleted: once more, stale at once, then forgotten.
    f->sink.n = 0;
    t[0].t.status = CGS__TRACK_STATUS__TRACK_STATUS_DELETED;
    s_batch (&b, t, 2);
    gw_cotout_on_tracks (c, &b.b, S_T0 + 1.5);
    assert_int_equal (f->sink.n, 1); // 12 went out 0.5 s ago
    e = &f->sink.e[0];
    assert_string_equal (e->uid, "mscgs-42.track.11");
    assert_string_equal (e->type, "a-u-G");
    s_assert_times (e, S_T0 + 1.5, S_T0 + 1.5);
    assert_int_equal (gw_cotout_stats (c)->removed, 1);
    f->sink.n = 0;
    gw_cotout_tick (c, S_T0 + 2.0);
    assert_int_equal (f->sink.n, 1);
    assert_string_equal (f->sink.e[0].uid, "mscgs-42.track.12");
    s_assert_times (&f->sink.e[0], S_T0 + 2.0, S_T0 + 1.5 + 15);
    f->sink.n = 0;
    s_batch (&b, t, 1); // 11 deleted again: it is gone already
    gw_cotout_on_tracks (c, &b.b, S_T0 + 2.1);
    assert_int_equal (f->sink.n, 0);

    // Track 12, last carried at +1.5, is sent, stale at +16.5, until 15 s
    // have passed without a batch; then it is dropped without an event.
    gw_cotout_tick (c, S_T0 + 16.0);
    assert_int_equal (f->sink.n, 1);
    assert_string_equal (f->sink.e[0].uid, "mscgs-42.track.12");
    s_assert_times (&f->sink.e[0], S_T0 + 16.0, S_T0 + 16.5);
    f->sink.n = 0;
    gw_cotout_tick (c, S_T0 + 16.5);
    assert_int_equal (f->sink.n, 0);
    gw_cotout_tick (c, S_T0 + 20.0);
    assert_int_equal (f->sink.n, 0);
    t[1].t.status = CGS__TRACK_STATUS__TRACK_STATUS_DELETED; // forgotten: no removal to send
    s_batch (&b, &t[1], 1);
    gw_cotout_on_tracks (c, &b.b, S_T0 + 21.0);
    assert_int_equal (f->sink.n, 0);
    assert_int_equal (gw_cotout_stats (c)->removed, 1);
    gw_cotout_destroy (&c);
    assert_null (c);
    gw_cotout_destroy (&c);
}

/* ce: the 1-sigma radius of the position covariance's major axis. */
static void test_ce (void **state)
{
    s_fix_t *f = *state;
    gw_cotout_t *c = s_new (f);
    s_trk_t t[5];
    const Cgs__TrackStatus ok = CGS__TRACK_STATUS__TRACK_STATUS_CONFIRMED;
    s_trk (&t[0], 1, ok, 0, 0, 0, 0, 400, 0, 100);   // the larger first: 20
    s_trk (&t[1], 2, ok, 0, 0, 0, 0, 100, 0, 400);   // 20
    s_trk (&t[2], 3, ok, 0, 0, 0, 0, 73, 36, 52);    // 10
    s_trk (&t[3], 4, ok, 0, 0, 0, 0, 0, 12, 0);      // eigenvalues +-12: sqrt 12
    s_trk (&t[4], 5, ok, 0, 0, 370, 1, 52, -36, 73); // 10; heading 370: course 10
    t[4].t.n_covariance = 0;                         // no covariance: unknown
    s_batch_t b;
    s_batch (&b, t, 5);
    gw_cotout_on_tracks (c, &b.b, S_T0);
    assert_int_equal (f->sink.n, 5);
    const double want[5] = {20, 20, 10, sqrt (12), GW_COT_UNKNOWN_M};
    for (int i = 0; i < 5; i++)
        assert_near (f->sink.e[i].ce_m, want[i], 1e-9);
    assert_near (f->sink.e[4].course_deg, 10, 1e-9);
    gw_cotout_destroy (&c);
}

static void test_uav (void **state)
{
    s_fix_t *f = *state;
    gw_cotout_t *c = s_new (f);
    s_uav_t u;
    s_uav (&u, 7, "uav1");
    gw_cotout_on_uav (c, &u.u, S_T0);
    assert_int_equal (f->sink.n, 1);
    const gw_cot_event_t *e = &f->sink.e[0];
    assert_string_equal (e->uid, "mscgs-42.uav.uav1");
    assert_string_equal (e->type, "a-f-A-M-F-Q");
    assert_string_equal (e->how, "m-g");
    assert_string_equal (e->opex, "s-mscgs");
    assert_string_equal (e->callsign, "uav1");
    s_assert_times (e, S_T0, S_T0 + 15);
    s_assert_point (f, e->point, 2000, -1000, 1200);
    assert_true (e->has_track);
    assert_near (e->course_deg, 0, 1e-9); // north
    assert_near (e->speed_mps, 25, 1e-9);
    assert_true (e->has_sensor);
    assert_near (e->sensor_azimuth_deg, 330, 1e-9);
    assert_near (e->sensor_elevation_deg, -30, 1e-9);
    assert_near (e->sensor_fov_deg, 20, 1e-9);
    assert_near (e->sensor_vfov_deg, 15, 1e-9);
    assert_near (e->sensor_range_m, 2400, 1e-6); // 1200 m up, 30 degrees down
    // Not due 0.5 s later; a second later it moves south-west.
    f->sink.n = 0;
    gw_cotout_on_uav (c, &u.u, S_T0 + 0.5);
    assert_int_equal (f->sink.n, 0);
    u.v.east_mps = -10, u.v.north_mps = -10;
    gw_cotout_on_uav (c, &u.u, S_T0 + 1.0);
    assert_int_equal (f->sink.n, 1);
    assert_near (f->sink.e[0].course_deg, 225, 1e-9);
    assert_near (f->sink.e[0].speed_mps, sqrt (200), 1e-9);
    // With an intercept's footprint, the range is to its centre: 1600 m
    // north and 1200 m down, 2000 m.
    f->sink.n = 0;
    s_icpt_t x;
    s_icpt (&x);
    gw_cotout_on_intercept (c, &x.m, S_T0 + 1.2);
    assert_int_equal (f->sink.n, 2); // the route and the footprint
    f->sink.n = 0;
    gw_cotout_on_uav (c, &u.u, S_T0 + 2.0);
    assert_int_equal (f->sink.n, 1);
    assert_string_equal (f->sink.e[0].type, "a-f-A-M-F-Q");
    assert_near (f->sink.e[0].sensor_range_m, 2000, 1e-6);
    // A UAV without a name has no uid: not sent.
    f->sink.n = 0;
    s_uav_t v;
    s_uav (&v, 9, "");
    gw_cotout_on_uav (c, &v.u, S_T0 + 3.0);
    assert_int_equal (f->sink.n, 0);
    assert_int_equal (gw_cotout_stats (c)->uavs, 3);
    gw_cotout_destroy (&c);
}

/* Many tracks: deleted ones and silent ones removed while the rest are
 * iterated, each remaining one still found and sent exactly once. */
static void test_many_tracks (void **state)
{
    s_fix_t *f = *state;
    gw_cotout_t *c = s_new (f);
    enum { N = 600, SILENT = 10 };
    s_trk_t *t = calloc (N + SILENT, sizeof *t);
    Cgs__Track **tp = calloc (N + SILENT, sizeof *tp);
    assert_true (t && tp);
    for (size_t i = 0; i < N + SILENT; i++) {
        s_trk (&t[i], 1000 + (uint32_t)i, CGS__TRACK_STATUS__TRACK_STATUS_CONFIRMED,
               10.0 * (double)i, -5.0 * (double)i, 90, 3, 25, 0, 25);
        tp[i] = &t[i].t;
    }
    Cgs__TrackBatch b;
    cgs__track_batch__init (&b);
    b.tracks = tp;
    b.n_tracks = N + SILENT; // ids 1600..1609 are in this batch only
    gw_cotout_on_tracks (c, &b, S_T0);
    assert_int_equal (f->sink.n, N + SILENT);
    // Every third deleted: those go out at once, stale at once.
    f->sink.n = 0;
    for (size_t i = 0; i < N; i += 3)
        t[i].t.status = CGS__TRACK_STATUS__TRACK_STATUS_DELETED;
    b.n_tracks = N;
    gw_cotout_on_tracks (c, &b, S_T0 + 0.5);
    assert_int_equal (f->sink.n, N / 3);
    for (size_t i = 0; i < f->sink.n; i++)
        assert_near (f->sink.e[i].stale_s, S_T0 + 0.5, 1e-6);
    // A second after the first batch: the 400 left and the 10 silent ones.
    f->sink.n = 0;
    gw_cotout_tick (c, S_T0 + 1.0);
    assert_int_equal (f->sink.n, N - N / 3 + SILENT);
    // 15 s after the first batch the silent ones go, without an event, while
    // the rest are sent: each of them once.
    f->sink.n = 0;
    gw_cotout_tick (c, S_T0 + 15.0);
    assert_int_equal (f->sink.n, N - N / 3);
    static bool seen[N + SILENT];
    memset (seen, 0, sizeof seen);
    for (size_t i = 0; i < f->sink.n; i++) {
        unsigned id = 0;
        assert_int_equal (sscanf (f->sink.e[i].uid, "mscgs-42.track.%u", &id), 1);
        assert_true (id >= 1000 && id < 1000 + N);
        assert_false (seen[id - 1000]);
        assert_true ((id - 1000) % 3 != 0);
        seen[id - 1000] = true;
    }
    // The deleted ones again (alone in a batch), and later every one
    // deleted: all forgotten by then.
    f->sink.n = 0;
    Cgs__Track **dp = calloc (N / 3, sizeof *dp);
    assert_non_null (dp);
    for (size_t i = 0; i < N / 3; i++)
        dp[i] = &t[3 * i].t;
    Cgs__TrackBatch db;
    cgs__track_batch__init (&db);
    db.tracks = dp;
    db.n_tracks = N / 3;
    gw_cotout_on_tracks (c, &db, S_T0 + 15.2);
    free (dp);
    assert_int_equal (f->sink.n, 0);
    gw_cotout_tick (c, S_T0 + 15.5); // 15 s after the batch at +0.5
    assert_int_equal (f->sink.n, 0);
    for (size_t i = 0; i < N + SILENT; i++)
        t[i].t.status = CGS__TRACK_STATUS__TRACK_STATUS_DELETED;
    b.n_tracks = N + SILENT;
    gw_cotout_on_tracks (c, &b, S_T0 + 16.0);
    assert_int_equal (f->sink.n, 0);
    free (t);
    free (tp);
    gw_cotout_destroy (&c);
}

/* An intercept's drawings, and their removal when it ends in `end`, in a
 * message that still carries the route and footprint (keep) or not. */
static void s_intercept (void **state, Cgs__InterceptState end, bool keep)
{
    s_fix_t *f = *state;
    gw_cotout_t *c = s_new (f);
    s_icpt_t x;
    s_icpt (&x);
    gw_cotout_on_intercept (c, &x.m, S_T0); // its UAV unknown: nothing to name it by
    assert_int_equal (f->sink.n, 0);
    s_trk_t t;
    s_trk (&t, 11, CGS__TRACK_STATUS__TRACK_STATUS_CONFIRMED, 2000, 600, 0, 0, 1, 0, 1);
    s_batch_t b;
    s_batch (&b, &t, 1);
    gw_cotout_on_tracks (c, &b.b, S_T0);
    s_uav_t u;
    s_uav (&u, 7, "uav1");
    gw_cotout_on_uav (c, &u.u, S_T0);
    assert_int_equal (f->sink.n, 2);
    f->sink.n = 0;

    gw_cotout_on_intercept (c, &x.m, S_T0 + 0.1);
    assert_int_equal (f->sink.n, 2);
    const gw_cot_event_t *r = &f->sink.e[0], *p = &f->sink.e[1];
    if (strcmp (r->uid, "mscgs-42.route.uav1") != 0) {
        const gw_cot_event_t *s = r;
        r = p, p = s;
    }
    assert_string_equal (r->uid, "mscgs-42.route.uav1");
    assert_string_equal (r->type, "u-d-f");
    assert_string_equal (r->how, "h-e");
    assert_string_equal (r->stroke_color, "-256"); // yellow, 0xffffff00
    s_assert_times (r, S_T0 + 0.1, S_T0 + 0.1 + 15);
    assert_int_equal (r->n_links, 3);
    assert_false (r->closed);
    for (int i = 0; i < 3; i++)
        s_assert_point (f, r->links[i], x.route[i].east_m, x.route[i].north_m, x.route[i].up_m);
    assert_string_equal (p->uid, "mscgs-42.footprint.uav1");
    assert_string_equal (p->type, "u-d-f");
    assert_string_equal (p->stroke_color, "-16711681"); // cyan, 0xff00ffff
    s_assert_times (p, S_T0 + 0.1, S_T0 + 0.1 + 15);
    assert_int_equal (p->n_links, 4);
    assert_true (p->closed);
    for (int i = 0; i < 4; i++)
        s_assert_point (f, p->links[i], x.corner[i].east_m, x.corner[i].north_m, 0);

    f->sink.n = 0;
    gw_cotout_on_intercept (c, &x.m, S_T0 + 0.5); // not due
    assert_int_equal (f->sink.n, 0);
    gw_cotout_tick (c, S_T0 + 1.1); // the track, the UAV, the route, the footprint
    assert_int_equal (f->sink.n, 4);
    bool designated = false;
    for (size_t i = 0; i < f->sink.n; i++)
        if (strcmp (f->sink.e[i].uid, "mscgs-42.track.11") == 0)
            designated = strstr (f->sink.e[i].remarks, "designated for uav1") != NULL;
    assert_true (designated);

    // It ends: in a message without route or footprint (as guidanced sends
    // it), or one that still carries them.
    f->sink.n = 0;
    x.m.state = end;
    if (!keep) {
        x.m.n_route = 0;
        x.m.footprint = NULL;
    }
    gw_cotout_on_intercept (c, &x.m, S_T0 + 1.3);
    assert_int_equal (f->sink.n, 2);
    bool route = false, footprint = false;
    for (size_t i = 0; i < 2; i++) {
        const gw_cot_event_t *e = &f->sink.e[i];
        route |= strcmp (e->uid, "mscgs-42.route.uav1") == 0;
        footprint |= strcmp (e->uid, "mscgs-42.footprint.uav1") == 0;
        assert_string_equal (e->type, "u-d-f");
        s_assert_times (e, S_T0 + 1.3, S_T0 + 1.3);
    }
    assert_true (route && footprint);
    f->sink.n = 0;
    gw_cotout_on_intercept (c, &x.m, S_T0 + 1.4);
    assert_int_equal (f->sink.n, 0);
    gw_cotout_tick (c, S_T0 + 2.5); // a second after the removal: the track and the UAV only
    assert_int_equal (f->sink.n, 2);
    for (size_t i = 0; i < f->sink.n; i++) {
        const gw_cot_event_t *e = &f->sink.e[i];
        assert_string_not_equal (e->type, "u-d-f");
        if (strcmp (e->uid, "mscgs-42.track.11") == 0)
            assert_null (strstr (e->remarks, "designated"));
    }
    gw_cotout_destroy (&c);
}

static void test_intercept_idle (void **state)
{
    s_intercept (state, CGS__INTERCEPT_STATE__INTERCEPT_STATE_IDLE, false);
}

static void test_intercept_done (void **state)
{
    s_intercept (state, CGS__INTERCEPT_STATE__INTERCEPT_STATE_DONE, true);
}

static void test_intercept_cancelled (void **state)
{
    s_intercept (state, CGS__INTERCEPT_STATE__INTERCEPT_STATE_CANCELLED, false);
}

static void test_intercept_lost (void **state)
{
    s_intercept (state, CGS__INTERCEPT_STATE__INTERCEPT_STATE_LOST, true);
}

static void test_ids (void **state)
{
    s_fix_t *f = *state;
    gw_cotout_t *c = s_new (f);
    char uid[96];
    assert_int_equal (gw_cotout_uav_id (c, ""), 0); // none heard
    gw_cotout_uav_uid (c, 7, uid, sizeof uid);
    assert_string_equal (uid, "");
    s_uav_t u, v;
    s_uav (&u, 7, "uav1");
    s_uav (&v, 9, "uav2");
    gw_cotout_on_uav (c, &u.u, S_T0);
    gw_cotout_on_uav (c, &v.u, S_T0);
    assert_int_equal (gw_cotout_uav_id (c, "uav2"), 9);
    assert_int_equal (gw_cotout_uav_id (c, "uav1"), 7);
    assert_int_equal (gw_cotout_uav_id (c, "mscgs-42.uav.uav2"), 9);
    assert_int_equal (gw_cotout_uav_id (c, ""), 7); // the first heard
    assert_int_equal (gw_cotout_uav_id (c, "uav3"), 0);
    assert_int_equal (gw_cotout_uav_id (c, "mscgs-43.uav.uav2"), 0); // another exercise's
    assert_int_equal (gw_cotout_uav_id (c, "mscgs-42.track.uav2"), 0);
    gw_cotout_uav_uid (c, 9, uid, sizeof uid);
    assert_string_equal (uid, "mscgs-42.uav.uav2");
    gw_cotout_uav_uid (c, 8, uid, sizeof uid);
    assert_string_equal (uid, "");
    assert_true (gw_cotout_is_ours (c, "mscgs-42.track.11"));
    assert_true (gw_cotout_is_ours (c, "mscgs-42.uav.uav1"));
    assert_false (gw_cotout_is_ours (c, "mscgs-43.track.11"));
    assert_false (gw_cotout_is_ours (c, "mscgs-420.track.11"));
    assert_false (gw_cotout_is_ours (c, "mscgs-42"));
    assert_false (gw_cotout_is_ours (c, "ANDROID-0123456789abcdef"));
    gw_cotout_destroy (&c);
    // Another prefix names every uid and the opex.
    snprintf (f->p.cot_uid_prefix, sizeof f->p.cot_uid_prefix, "lab");
    f->sink.n = 0;
    c = s_new (f);
    gw_cotout_on_uav (c, &u.u, S_T0);
    assert_int_equal (f->sink.n, 1);
    assert_string_equal (f->sink.e[0].uid, "lab-42.uav.uav1");
    assert_string_equal (f->sink.e[0].opex, "s-lab");
    assert_true (gw_cotout_is_ours (c, "lab-42.uav.uav1"));
    assert_false (gw_cotout_is_ours (c, "mscgs-42.uav.uav1"));
    assert_int_equal (gw_cotout_uav_id (c, "lab-42.uav.uav1"), 7);
    gw_cotout_destroy (&c);
}

int main (void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup_teardown (test_tracks, s_setup, s_teardown),
        cmocka_unit_test_setup_teardown (test_ce, s_setup, s_teardown),
        cmocka_unit_test_setup_teardown (test_many_tracks, s_setup, s_teardown),
        cmocka_unit_test_setup_teardown (test_uav, s_setup, s_teardown),
        cmocka_unit_test_setup_teardown (test_intercept_idle, s_setup, s_teardown),
        cmocka_unit_test_setup_teardown (test_intercept_done, s_setup, s_teardown),
        cmocka_unit_test_setup_teardown (test_intercept_cancelled, s_setup, s_teardown),
        cmocka_unit_test_setup_teardown (test_intercept_lost, s_setup, s_teardown),
        cmocka_unit_test_setup_teardown (test_ids, s_setup, s_teardown),
    };
    return cmocka_run_group_tests (tests, NULL, NULL);
}
