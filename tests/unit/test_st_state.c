/* test_st_state — the tactical map's picture, read back from the JSON it
 * pushes: the hits of the last complete scan are current (yellow, the
 * paper's current scan: one hit a vehicle), exactly history_scans complete
 * scans before it are grey, older ones go, a scan in progress is drawn when
 * it ends (or when a later scan begins: its end marker was lost), late hits of a dropped scan are
 * ignored and a restarted radar starts afresh; BCIS replies live bcis_timeout_s of simulation time,
 * to the boundary; tracks are updated in place, removed when deleted, stale or superseded by a
 * restarted tracker, and carry their newest hit; the footprint is drawn scaled about its centre
 * (area k² times the true one) and the range is the ground distance UAV to track; ground truth
 * leaves out the UAVs; bad messages are refused whole; each UAV carries how
 * its camera is set (uav.sensor) and its sensor's live mode (its latest
 * image's, SAR too).
 *
 * Also st_request, the page's commands: each op's input is checked (types,
 * finite numbers, ranges, known values) and refused with the reason, and
 * made into the command with exactly the fields given (the camera's `set`
 * bits and values, the sensor mode), for the right service; the imagerd of
 * a UAV is the exercise's imagerd whose `uav =` names it. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "st_request.h"
#include "st_state.h"

#include <errno.h>
#include <json-c/json.h>
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static const st_state_params_t s_params = {20, 5.0, 60.0, 30.0};

static json_object *s_picture (st_state_t *st)
{
    size_t len = 0;
    char *text = st_state_json (st, 7, &len);
    assert_non_null (text);
    assert_int_equal (strlen (text), len);
    json_object *o = json_tokener_parse (text);
    free (text);
    assert_non_null (o);
    return o;
}

static json_object *s_get (json_object *o, const char *key)
{
    json_object *v = NULL;
    if (!json_object_object_get_ex (o, key, &v))
        fail_msg ("no key %s", key);
    return v;
}

static double s_num (json_object *o, const char *key)
{
    return json_object_get_double (s_get (o, key));
}

/* One mti message of n hits at (scan*100 + i, -scan) for radar 1. */
static int s_hits (st_state_t *st, uint32_t scan, int n, uint64_t epoch)
{
    Cgs__Header h = CGS__HEADER__INIT;
    h.epoch = epoch;
    h.sim_time_s = scan;
    Cgs__Mti m = CGS__MTI__INIT;
    m.uav_id = 1;
    m.scan_number = scan;
    Cgs__MtiHit hits[16], *ptrs[16];
    Cgs__Enu pos[16];
    assert_true (n <= 16);
    for (int i = 0; i < n; i++) {
        cgs__mti_hit__init (&hits[i]);
        cgs__enu__init (&pos[i]);
        pos[i].east_m = scan * 100.0 + i;
        pos[i].north_m = -(double)scan;
        hits[i].position = &pos[i];
        hits[i].hit_id = scan * 100 + (uint32_t)i + 1;
        ptrs[i] = &hits[i];
    }
    m.n_hits = (size_t)n;
    m.hits = ptrs;
    return st_state_take_mti (st, &m, &h);
}

static void s_scan_end (st_state_t *st, uint32_t scan, uint64_t epoch)
{
    Cgs__Header h = CGS__HEADER__INIT;
    h.epoch = epoch;
    Cgs__MtiScan m = CGS__MTI_SCAN__INIT;
    m.uav_id = 1;
    m.scan_number = scan;
    assert_int_equal (st_state_take_mti_scan (st, &m, &h), 0);
}

/* Counts of current and grey scans (and hits) in the picture; the current
 * scans' numbers into cur (up to 4). */
static void s_scans (st_state_t *st, int *ret_cur, int *ret_grey, int *ret_hits, uint32_t cur[4],
                     uint32_t *ret_oldest)
{
    json_object *o = s_picture (st), *hits = s_get (o, "hits");
    int c = 0, g = 0, n = 0;
    uint32_t oldest = UINT32_MAX;
    for (size_t i = 0; i < json_object_array_length (hits); i++) {
        json_object *s = json_object_array_get_idx (hits, i);
        uint32_t number = (uint32_t)s_num (s, "scan");
        json_object *xy = s_get (s, "xy"), *ids = s_get (s, "ids");
        int k = (int)json_object_array_length (xy);
        assert_int_equal (k % 2, 0);
        // Each hit's id beside its position, as the page sends it back.
        assert_int_equal ((int)json_object_array_length (ids), k / 2);
        for (int j = 0; j < k / 2; j++) {
            double e = json_object_get_double (json_object_array_get_idx (xy, 2 * j));
            uint32_t id = (uint32_t)json_object_get_int64 (json_object_array_get_idx (ids, j));
            assert_int_equal (id, number * 100 + (uint32_t)lround (e - number * 100.0) + 1);
        }
        n += k / 2;
        if (number < oldest)
            oldest = number;
        if (json_object_get_boolean (s_get (s, "current"))) {
            if (c < 4)
                cur[c] = number;
            c++;
        } else {
            g++;
        }
    }
    json_object_put (o);
    *ret_cur = c;
    *ret_grey = g;
    *ret_hits = n;
    *ret_oldest = oldest;
}

static void test_history_of_scans (void **state)
{
    (void)state;
    st_state_t *st = st_state_new (&s_params);
    assert_non_null (st);
    int cur, grey, hits;
    uint32_t c[4], oldest;
    // Three hits in each of scans 1..30, every one complete.
    for (uint32_t s = 1; s <= 30; s++) {
        assert_int_equal (s_hits (st, s, 3, 9), 0);
        s_scan_end (st, s, 9);
    }
    s_scans (st, &cur, &grey, &hits, c, &oldest);
    assert_int_equal (cur, 1); // the last complete scan
    assert_int_equal (c[0], 30);
    assert_int_equal (grey, 20); // scans 10..29
    assert_int_equal (oldest, 10);
    assert_int_equal (hits, 21 * 3);
    assert_int_equal (st_state_hit_count (st), 21 * 3);
    // Scan 31 in progress: not drawn yet; 30 is current, 10..29 grey.
    assert_int_equal (s_hits (st, 31, 2, 9), 0);
    s_scans (st, &cur, &grey, &hits, c, &oldest);
    assert_int_equal (cur, 1);
    assert_int_equal (c[0], 30);
    assert_int_equal (grey, 20);
    assert_int_equal (oldest, 10);
    assert_int_equal (hits, 21 * 3);
    // Scan 31 ends: 31 current; 11..30 grey; scan 10 is gone.
    s_scan_end (st, 31, 9);
    s_scans (st, &cur, &grey, &hits, c, &oldest);
    assert_int_equal (cur, 1);
    assert_int_equal (c[0], 31);
    assert_int_equal (grey, 20);
    assert_int_equal (oldest, 11);
    assert_int_equal (hits, 20 * 3 + 2);
    // Late hits of the dropped scan 10 are ignored, not made a new scan.
    assert_int_equal (s_hits (st, 10, 3, 9), 0);
    assert_int_equal (st_state_hit_count (st), 20 * 3 + 2);
    // More hits of scan 31 join it.
    assert_int_equal (s_hits (st, 31, 4, 9), 0);
    assert_int_equal (st_state_hit_count (st), 20 * 3 + 6);
    // The radar restarts (new epoch): its old scans are forgotten, and its
    // first scan is drawn when it ends.
    assert_int_equal (s_hits (st, 1, 5, 10), 0);
    s_scans (st, &cur, &grey, &hits, c, &oldest);
    assert_int_equal (cur, 0);
    assert_int_equal (grey, 0);
    assert_int_equal (hits, 0);
    // Its end marker is lost: the next scan's first hits draw it.
    assert_int_equal (s_hits (st, 2, 4, 10), 0);
    s_scans (st, &cur, &grey, &hits, c, &oldest);
    assert_int_equal (cur, 1);
    assert_int_equal (c[0], 1);
    assert_int_equal (grey, 0);
    assert_int_equal (hits, 5);
    st_state_destroy (&st);
    assert_null (st);
    st_state_destroy (&st); // accepts NULL
}

static void test_history_length_is_a_parameter (void **state)
{
    (void)state;
    st_state_params_t p = s_params;
    p.history_scans = 0;
    st_state_t *st = st_state_new (&p);
    for (uint32_t s = 1; s <= 5; s++) {
        assert_int_equal (s_hits (st, s, 1, 1), 0);
        s_scan_end (st, s, 1);
    }
    int cur, grey, hits;
    uint32_t c[4], oldest;
    s_scans (st, &cur, &grey, &hits, c, &oldest);
    assert_int_equal (cur, 1);
    assert_int_equal (grey, 0);
    assert_int_equal (c[0], 5);
    st_state_destroy (&st);
}

static void test_bad_hits_are_refused_whole (void **state)
{
    (void)state;
    st_state_t *st = st_state_new (&s_params);
    Cgs__Mti m = CGS__MTI__INIT;
    m.uav_id = 1;
    Cgs__MtiHit good = CGS__MTI_HIT__INIT, bad = CGS__MTI_HIT__INIT;
    Cgs__Enu p = CGS__ENU__INIT, nan_p = CGS__ENU__INIT;
    good.position = &p;
    nan_p.east_m = NAN;
    bad.position = &nan_p;
    Cgs__MtiHit *ptrs[2] = {&good, &bad};
    m.n_hits = 2;
    m.hits = ptrs;
    assert_int_equal (st_state_take_mti (st, &m, NULL), -EINVAL);
    bad.position = NULL;
    assert_int_equal (st_state_take_mti (st, &m, NULL), -EINVAL);
    assert_int_equal (st_state_hit_count (st), 0);
    m.uav_id = 0;
    m.n_hits = 1;
    assert_int_equal (st_state_take_mti (st, &m, NULL), -EINVAL);
    st_state_destroy (&st);
}

static size_t s_bcis_count (st_state_t *st, double *ret_age)
{
    st_state_prune (st);
    json_object *o = s_picture (st), *b = s_get (o, "bcis");
    size_t n = json_object_array_length (b);
    if (n && ret_age)
        *ret_age = s_num (json_object_array_get_idx (b, 0), "age_s");
    json_object_put (o);
    return n;
}

static void test_bcis_replies_time_out (void **state)
{
    (void)state;
    st_state_t *st = st_state_new (&s_params);
    Cgs__Bcis m = CGS__BCIS__INIT;
    m.uav_id = 1;
    Cgs__BcisReply r = CGS__BCIS_REPLY__INIT;
    Cgs__Enu p = CGS__ENU__INIT;
    p.east_m = 300;
    p.north_m = 400;
    r.position = &p;
    r.responder_id = 17;
    r.marking = "BLUE 1";
    r.sim_time_s = 10;
    Cgs__BcisReply *ptrs[1] = {&r};
    m.n_replies = 1;
    m.replies = ptrs;
    assert_int_equal (st_state_take_bcis (st, &m, NULL), 0);
    double age = -1;
    st_state_set_time (st, 14.9);
    assert_int_equal (s_bcis_count (st, &age), 1);
    assert_true (fabs (age - 4.9) < 0.006);
    st_state_set_time (st, 15.0); // exactly the timeout: still shown
    assert_int_equal (s_bcis_count (st, NULL), 1);
    st_state_set_time (st, 15.01);
    assert_int_equal (s_bcis_count (st, NULL), 0);
    // Time never goes back: an older clock does not revive anything.
    st_state_set_time (st, 11);
    assert_true (st_state_time (st) > 15);
    // A reply without a time is refused.
    r.sim_time_s = NAN;
    assert_int_equal (st_state_take_bcis (st, &m, NULL), -EINVAL);
    st_state_destroy (&st);
}

typedef struct {
    Cgs__Track t;
    Cgs__Enu pos;
    Cgs__TrackHistoryPoint h[2], *hp[2];
    Cgs__Enu hpos[2];
} s_track_msg_t;

static void s_track (s_track_msg_t *m, uint32_t id, int status, double e, double n)
{
    cgs__track__init (&m->t);
    cgs__enu__init (&m->pos);
    m->t.track_id = id;
    m->t.status = status;
    m->pos.east_m = e;
    m->pos.north_m = n;
    m->t.position = &m->pos;
    m->t.heading_deg = 90;
    m->t.speed_mps = 8;
    for (int i = 0; i < 2; i++) {
        cgs__track_history_point__init (&m->h[i]);
        cgs__enu__init (&m->hpos[i]);
        m->hpos[i].east_m = e - 10 * (2 - i); // oldest first; the newest is e - 10
        m->hpos[i].north_m = n;
        m->h[i].position = &m->hpos[i];
        m->hp[i] = &m->h[i];
    }
    m->t.n_history = 2;
    m->t.history = m->hp;
}

static int s_batch (st_state_t *st, s_track_msg_t *tracks, size_t n, double t, uint64_t epoch)
{
    Cgs__Track *ptrs[8];
    for (size_t i = 0; i < n; i++)
        ptrs[i] = &tracks[i].t;
    Cgs__TrackBatch b = CGS__TRACK_BATCH__INIT;
    b.uav_id = 1;
    b.n_tracks = n;
    b.tracks = ptrs;
    Cgs__Header h = CGS__HEADER__INIT;
    h.sim_time_s = t;
    h.epoch = epoch;
    return st_state_take_tracks (st, &b, &h);
}

/* The track of that id in the picture (a new reference), or NULL. */
static json_object *s_find_track (st_state_t *st, uint32_t id)
{
    json_object *o = s_picture (st), *tr = s_get (o, "tracks"), *found = NULL;
    for (size_t i = 0; i < json_object_array_length (tr); i++) {
        json_object *t = json_object_array_get_idx (tr, i);
        if ((uint32_t)s_num (t, "id") == id)
            found = json_object_get (t);
    }
    json_object_put (o);
    return found;
}

static void test_tracks (void **state)
{
    (void)state;
    st_state_t *st = st_state_new (&s_params);
    s_track_msg_t m[3];
    s_track (&m[0], 5, CGS__TRACK_STATUS__TRACK_STATUS_CONFIRMED, 1000, 2000);
    s_track (&m[1], 6, CGS__TRACK_STATUS__TRACK_STATUS_TENTATIVE, -500, 0);
    m[1].t.identity = CGS__TRACK_IDENTITY__TRACK_IDENTITY_FRIENDLY;
    assert_int_equal (s_batch (st, m, 2, 100, 1), 0);
    assert_int_equal (st_state_track_count (st), 2);
    json_object *t = s_find_track (st, 5);
    assert_non_null (t);
    assert_string_equal (json_object_get_string (s_get (t, "status")), "confirmed");
    assert_string_equal (json_object_get_string (s_get (t, "identity")), "unknown");
    json_object *lh = s_get (t, "last_hit");
    assert_true (fabs (json_object_get_double (json_object_array_get_idx (lh, 0)) - 990) < 1e-9);
    json_object_put (t);
    t = s_find_track (st, 6);
    assert_string_equal (json_object_get_string (s_get (t, "identity")), "friendly");
    assert_string_equal (json_object_get_string (s_get (t, "status")), "tentative");
    json_object_put (t);
    // Updated in place: one track 5, at its new position.
    s_track (&m[0], 5, CGS__TRACK_STATUS__TRACK_STATUS_COASTING, 1100, 2000);
    assert_int_equal (s_batch (st, m, 1, 110, 1), 0);
    assert_int_equal (st_state_track_count (st), 2);
    t = s_find_track (st, 5);
    assert_true (fabs (s_num (t, "e") - 1100) < 1e-9);
    assert_string_equal (json_object_get_string (s_get (t, "status")), "coasting");
    json_object_put (t);
    // Deleted: gone at once.
    s_track (&m[1], 6, CGS__TRACK_STATUS__TRACK_STATUS_DELETED, -500, 0);
    assert_int_equal (s_batch (st, &m[1], 1, 111, 1), 0);
    assert_null (s_find_track (st, 6));
    // Stale: track 5 last updated at 110 goes once 60 s have passed without it.
    st_state_set_time (st, 170);
    st_state_prune (st);
    assert_int_equal (st_state_track_count (st), 1);
    st_state_set_time (st, 170.5);
    st_state_prune (st);
    assert_int_equal (st_state_track_count (st), 0);
    // A restarted tracker (new epoch) replaces the old one's tracks.
    s_track (&m[0], 1, CGS__TRACK_STATUS__TRACK_STATUS_CONFIRMED, 0, 0);
    s_track (&m[1], 2, CGS__TRACK_STATUS__TRACK_STATUS_CONFIRMED, 0, 0);
    assert_int_equal (s_batch (st, m, 2, 200, 1), 0);
    s_track (&m[2], 3, CGS__TRACK_STATUS__TRACK_STATUS_CONFIRMED, 0, 0);
    assert_int_equal (s_batch (st, &m[2], 1, 201, 2), 0);
    assert_int_equal (st_state_track_count (st), 1);
    assert_non_null ((t = s_find_track (st, 3)));
    json_object_put (t);
    // A track without a position is refused, and nothing of its batch taken.
    m[1].t.position = NULL;
    s_track (&m[0], 9, CGS__TRACK_STATUS__TRACK_STATUS_CONFIRMED, 0, 0);
    assert_int_equal (s_batch (st, m, 2, 202, 2), -EINVAL);
    assert_null (s_find_track (st, 9));
    st_state_destroy (&st);
}

/* Shoelace area of a polygon given as e,n pairs. */
static double s_area (json_object *xy)
{
    size_t n = json_object_array_length (xy) / 2;
    double a = 0;
    for (size_t i = 0; i < n; i++) {
        size_t j = (i + 1) % n;
        double xi = json_object_get_double (json_object_array_get_idx (xy, 2 * i));
        double yi = json_object_get_double (json_object_array_get_idx (xy, 2 * i + 1));
        double xj = json_object_get_double (json_object_array_get_idx (xy, 2 * j));
        double yj = json_object_get_double (json_object_array_get_idx (xy, 2 * j + 1));
        a += xi * yj - xj * yi;
    }
    return fabs (a) / 2;
}

static void test_footprint_scale_and_range (void **state)
{
    (void)state;
    // A trapezoid: near edge 200 m, far edge 400 m, 300 m deep, centre at its middle.
    const double corners[8] = {900, 1000, 800, 1300, 1200, 1300, 1100, 1000};
    const double centre[2] = {1000, 1150};
    double shown[8];
    st_footprint_scaled (corners, centre, 5, shown);
    for (int i = 0; i < 8; i++)
        assert_true (fabs (shown[i] - (centre[i % 2] + 5 * (corners[i] - centre[i % 2]))) < 1e-9);
    st_footprint_scaled (corners, centre, 3, shown); // not a display scale: as it is
    assert_memory_equal (shown, corners, sizeof corners);

    st_state_t *st = st_state_new (&s_params);
    Cgs__Uav u = CGS__UAV__INIT;
    Cgs__Enu up = CGS__ENU__INIT;
    up.east_m = -2000;
    up.north_m = 1000;
    u.entity_id = 1;
    u.name = "uav1";
    u.position = &up;
    assert_int_equal (st_state_take_uav (st, &u, NULL), 0);
    s_track_msg_t tm;
    s_track (&tm, 12, CGS__TRACK_STATUS__TRACK_STATUS_CONFIRMED, 1000, 5000);
    assert_int_equal (s_batch (st, &tm, 1, 1, 0), 0);
    Cgs__Intercept x = CGS__INTERCEPT__INIT;
    Cgs__Footprint f = CGS__FOOTPRINT__INIT;
    Cgs__Enu c[4], *cp[4], ce = CGS__ENU__INIT, r[3], *rp[3];
    for (int i = 0; i < 4; i++) {
        cgs__enu__init (&c[i]);
        c[i].east_m = corners[2 * i];
        c[i].north_m = corners[2 * i + 1];
        cp[i] = &c[i];
    }
    for (int i = 0; i < 3; i++) {
        cgs__enu__init (&r[i]);
        r[i].east_m = 100.0 * i;
        rp[i] = &r[i];
    }
    ce.east_m = centre[0];
    ce.north_m = centre[1];
    f.n_corners = 4;
    f.corners = cp;
    f.center = &ce;
    x.uav_id = 1;
    x.track_id = 12;
    x.state = CGS__INTERCEPT_STATE__INTERCEPT_STATE_APPROACH;
    x.footprint = &f;
    x.n_route = 3;
    x.route = rp;
    const unsigned scales[3] = {1, 5, 10};
    for (int k = 0; k < 3; k++) {
        f.display_scale = scales[k];
        assert_int_equal (st_state_take_intercept (st, &x, NULL), 0);
        json_object *o = s_picture (st);
        json_object *i0 = json_object_array_get_idx (s_get (o, "intercepts"), 0);
        assert_non_null (i0);
        double a_true = s_area (s_get (i0, "footprint"));
        double a_shown = s_area (s_get (i0, "footprint_display"));
        assert_true (fabs (a_true - 90000) < 1e-6); // (200 + 400) / 2 * 300
        assert_true (fabs (a_shown / a_true - scales[k] * scales[k]) < 1e-9);
        assert_int_equal ((int)s_num (i0, "scale"), (int)scales[k]);
        assert_string_equal (json_object_get_string (s_get (i0, "state")), "APPROACH");
        assert_int_equal (json_object_array_length (s_get (i0, "route")), 6);
        // Ground range UAV (-2000, 1000) to track (1000, 5000): 5000 m.
        assert_true (fabs (s_num (i0, "range_m") - 5000) < 0.05);
        json_object_put (o);
    }
    // A route point without a position refuses the message.
    rp[1] = NULL;
    assert_int_equal (st_state_take_intercept (st, &x, NULL), -EINVAL);
    st_state_destroy (&st);
}

static void test_truth_and_image (void **state)
{
    (void)state;
    st_state_t *st = st_state_new (&s_params);
    Cgs__Entity e[2];
    Cgs__Enu p[2];
    Cgs__EnuVelocity v[2];
    Cgs__Entity *ptrs[2];
    for (int i = 0; i < 2; i++) {
        cgs__entity__init (&e[i]);
        cgs__enu__init (&p[i]);
        cgs__enu_velocity__init (&v[i]);
        v[i].east_mps = 3;
        v[i].north_mps = 4;
        e[i].position = &p[i];
        e[i].velocity = &v[i];
        e[i].active = true;
        ptrs[i] = &e[i];
    }
    e[0].entity_id = 1; // the UAV
    e[0].kind = CGS__ENTITY_KIND__ENTITY_KIND_AIR;
    e[1].entity_id = 4;
    e[1].marking = "RED 1";
    e[1].force = CGS__FORCE__FORCE_HOSTILE;
    e[1].kind = CGS__ENTITY_KIND__ENTITY_KIND_TRACKED;
    Cgs__EntityBatch b = CGS__ENTITY_BATCH__INIT;
    b.n_entities = 2;
    b.entities = ptrs;
    Cgs__Header h = CGS__HEADER__INIT;
    h.sim_time_s = 3;
    assert_int_equal (st_state_take_entities (st, &b, &h), 0);
    Cgs__Uav u = CGS__UAV__INIT;
    Cgs__Enu up = CGS__ENU__INIT;
    u.entity_id = 1;
    u.position = &up;
    assert_int_equal (st_state_take_uav (st, &u, NULL), 0);
    Cgs__Image im = CGS__IMAGE__INIT;
    im.uav_id = 1;
    im.frame_number = 42;
    im.latest_path = "images/latest.png"; // relative: refused
    assert_int_equal (st_state_take_image (st, &im, NULL), -EINVAL);
    im.latest_path = "";
    assert_int_equal (st_state_take_image (st, &im, NULL), 0); // a frame without a file
    assert_string_equal (st_state_image_path (st, NULL), "");
    im.latest_path = "/srv/images/latest.png";
    im.mode = CGS__IMAGE_MODE__IMAGE_MODE_INFRARED;
    assert_int_equal (st_state_take_image (st, &im, NULL), 0);
    uint64_t frame = 0;
    assert_string_equal (st_state_image_path (st, &frame), "/srv/images/latest.png");
    assert_int_equal (frame, 42);
    json_object *o = s_picture (st); // not shown until its file is there
    assert_true (json_object_get_type (s_get (o, "image")) == json_type_null);
    json_object_put (o);
    st_state_image_shown (st, 42);
    o = s_picture (st);
    json_object *truth = s_get (o, "truth");
    assert_int_equal (json_object_array_length (truth), 1); // not the UAV
    json_object *t = json_object_array_get_idx (truth, 0);
    assert_string_equal (json_object_get_string (s_get (t, "force")), "opposing");
    assert_string_equal (json_object_get_string (s_get (t, "kind")), "tracked");
    assert_string_equal (json_object_get_string (s_get (t, "marking")), "RED 1");
    assert_true (fabs (s_num (t, "speed_mps") - 5) < 1e-9);
    json_object *img = s_get (o, "image");
    assert_string_equal (json_object_get_string (s_get (img, "url")), "/image/latest.png?frame=42");
    assert_string_equal (json_object_get_string (s_get (img, "mode")), "infrared");
    assert_string_equal (json_object_get_string (s_get (o, "type")), "state");
    assert_int_equal ((int)s_num (o, "seq"), 7);
    json_object_put (o);
    // An entity without a velocity is bad input.
    e[1].velocity = NULL;
    assert_int_equal (st_state_take_entities (st, &b, &h), -EINVAL);
    // Not heard of for truth_stale_s: gone.
    st_state_set_time (st, 3 + 30.5);
    st_state_prune (st);
    o = s_picture (st);
    assert_int_equal (json_object_array_length (s_get (o, "truth")), 0);
    json_object_put (o);
    st_state_destroy (&st);
}

static void test_clock_and_staleness (void **state)
{
    (void)state;
    st_state_t *st = st_state_new (&s_params);
    // Without a clock, messages move time; once a clock is heard only it does.
    assert_int_equal (s_hits (st, 1, 2, 1), 0); // header time 1
    assert_true (st_state_time (st) == 1);
    st_state_set_clock (st, 10, 77);
    assert_true (st_state_time (st) == 10);
    assert_int_equal (s_hits (st, 500, 2, 1), 0); // header time 500: does not move it
    assert_true (st_state_time (st) == 10);
    st_state_set_clock (st, 9, 77); // the same clock never goes back
    assert_true (st_state_time (st) == 10);
    Cgs__Uav u = CGS__UAV__INIT;
    Cgs__Enu up = CGS__ENU__INIT;
    u.entity_id = 1;
    u.position = &up;
    assert_int_equal (st_state_take_uav (st, &u, NULL), 0);
    // A radar and a UAV not heard of for track_stale_s (60 s) leave the map.
    st_state_set_clock (st, 70, 77);
    st_state_prune (st);
    json_object *o = s_picture (st);
    assert_int_equal (json_object_array_length (s_get (o, "uavs")), 1);
    json_object_put (o);
    assert_int_equal (st_state_hit_count (st), 4);
    st_state_set_clock (st, 70.5, 77);
    st_state_prune (st);
    o = s_picture (st);
    assert_int_equal (json_object_array_length (s_get (o, "uavs")), 0);
    assert_int_equal (json_object_array_length (s_get (o, "hits")), 0);
    json_object_put (o);
    assert_int_equal (st_state_hit_count (st), 0);
    // A restarted exercise (new clock epoch, earlier time): time goes back and
    // a track heard "later" is not kept forever.
    s_track_msg_t tm;
    s_track (&tm, 4, CGS__TRACK_STATUS__TRACK_STATUS_CONFIRMED, 0, 0);
    assert_int_equal (s_batch (st, &tm, 1, 70.5, 1), 0);
    st_state_set_clock (st, 2, 78);
    assert_true (st_state_time (st) == 2);
    st_state_set_clock (st, 62.5, 78);
    st_state_prune (st);
    assert_int_equal (st_state_track_count (st), 0);
    st_state_destroy (&st);
}

/* Video: malformed frames refused with nothing written; the UAV whose video
 * is relayed (the first heard, then the picture's); a new stream (another
 * UAV, a restarted imagerd's new epoch, or video that went stale and came
 * back) restarts the pages. */
static int s_video (st_state_t *st, uint32_t uav, const uint8_t *ts, size_t len, uint64_t epoch,
                    double t, bool *relay, bool *restart)
{
    Cgs__VideoFrame m = CGS__VIDEO_FRAME__INIT;
    Cgs__Header h = CGS__HEADER__INIT;
    m.uav_id = uav;
    m.ts.data = (uint8_t *)ts;
    m.ts.len = len;
    h.epoch = epoch;
    h.sim_time_s = t;
    return st_state_take_video (st, &m, &h, relay, restart);
}

static void test_video (void **state)
{
    (void)state;
    st_state_t *st = st_state_new (&s_params);
    static uint8_t ts[3 * 188];
    memset (ts, 0, sizeof ts);
    for (size_t i = 0; i < sizeof ts; i += 188)
        ts[i] = 0x47;
    bool relay = true, restart = true;
    // Refused, and nothing written.
    assert_int_equal (s_video (st, 5, NULL, 0, 100, 1, &relay, &restart), -EINVAL);
    assert_int_equal (s_video (st, 5, ts, 0, 100, 1, &relay, &restart), -EINVAL);
    assert_int_equal (s_video (st, 5, ts, 187, 100, 1, &relay, &restart), -EINVAL);
    ts[188] = 0x48;
    assert_int_equal (s_video (st, 5, ts, sizeof ts, 100, 1, &relay, &restart), -EINVAL);
    assert_true (relay && restart);
    ts[188] = 0x47;
    // The first UAV heard is relayed; another's is not.
    assert_int_equal (s_video (st, 5, ts, sizeof ts, 100, 1, &relay, &restart), 0);
    assert_true (relay && !restart);
    assert_int_equal (s_video (st, 6, ts, sizeof ts, 200, 1.1, &relay, &restart), 0);
    assert_false (relay || restart);
    assert_int_equal (s_video (st, 5, ts, 188, 100, 1.2, &relay, &restart), 0);
    assert_true (relay && !restart);
    // Its imagerd restarted: a new epoch starts the pages over.
    assert_int_equal (s_video (st, 5, ts, sizeof ts, 101, 1.3, &relay, &restart), 0);
    assert_true (relay && restart);
    assert_int_equal (s_video (st, 5, ts, sizeof ts, 101, 1.4, &relay, &restart), 0);
    assert_true (relay && !restart);
    // The picture shown is UAV 6's: its video now, from the start.
    Cgs__Image im = CGS__IMAGE__INIT;
    im.uav_id = 6;
    im.latest_path = "/tmp/images/latest.png";
    assert_int_equal (st_state_take_image (st, &im, NULL), 0);
    assert_int_equal (s_video (st, 5, ts, sizeof ts, 101, 1.5, &relay, &restart), 0);
    assert_false (relay);
    assert_int_equal (s_video (st, 6, ts, sizeof ts, 200, 1.6, &relay, &restart), 0);
    assert_true (relay && restart);
    assert_int_equal (s_video (st, 6, ts, sizeof ts, 200, 1.7, &relay, &restart), 0);
    assert_true (relay && !restart);
    // Not heard of for track_stale_s (60 s): the next frame starts over.
    st_state_set_time (st, 70);
    st_state_prune (st);
    assert_int_equal (s_video (st, 6, ts, sizeof ts, 200, 70, &relay, &restart), 0);
    assert_true (relay && restart);
    st_state_destroy (&st);
}

static void test_full_tables (void **state)
{
    (void)state;
    st_state_t *st = st_state_new (&s_params);
    Cgs__Uav u = CGS__UAV__INIT;
    Cgs__Enu up = CGS__ENU__INIT;
    u.position = &up;
    for (uint32_t id = 1; id <= 16; id++) {
        u.entity_id = id;
        assert_int_equal (st_state_take_uav (st, &u, NULL), 0);
    }
    u.entity_id = 17;
    assert_int_equal (st_state_take_uav (st, &u, NULL), -ENOSPC);
    u.entity_id = 5; // a known one is still updated
    assert_int_equal (st_state_take_uav (st, &u, NULL), 0);
    st_state_destroy (&st);
}

/* ---- the camera and the sensor mode on the picture -------------------------------- */

static json_object *s_uav0 (json_object *picture)
{
    json_object *uavs = s_get (picture, "uavs");
    assert_int_equal (json_object_array_length (uavs), 1);
    return json_object_array_get_idx (uavs, 0);
}

static void test_camera_and_sensor_mode (void **state)
{
    (void)state;
    st_state_t *st = st_state_new (&s_params);
    Cgs__Uav u = CGS__UAV__INIT;
    Cgs__Enu up = CGS__ENU__INIT;
    u.entity_id = 3;
    u.position = &up;
    // Without the sensor: no camera, and no mode before an image.
    assert_int_equal (st_state_take_uav (st, &u, NULL), 0);
    json_object *o = s_picture (st);
    json_object *j = s_uav0 (o);
    assert_true (json_object_get_type (s_get (j, "camera")) == json_type_null);
    assert_true (json_object_get_type (s_get (j, "sensor_mode")) == json_type_null);
    json_object_put (o);
    // Set, staring at a point and held at the gimbal's limit.
    Cgs__ImagingSensor c = CGS__IMAGING_SENSOR__INIT;
    Cgs__Enu sp = CGS__ENU__INIT;
    sp.east_m = 1234.56;
    sp.north_m = -789.04;
    c.depression_deg = 32.5;
    c.hfov_deg = 6;
    c.vfov_deg = 4.5;
    c.stabilized = true;
    c.stare = CGS__STARE_MODE__STARE_MODE_POINT;
    c.stare_point = &sp;
    c.staring = true;
    c.at_gimbal_limit = true;
    c.gimbal_azimuth_limit_deg = 150;
    c.gimbal_elevation_min_deg = -90;
    u.sensor = &c;
    assert_int_equal (st_state_take_uav (st, &u, NULL), 0);
    o = s_picture (st);
    json_object *cam = s_get (s_uav0 (o), "camera");
    assert_true (fabs (s_num (cam, "depression_deg") - 32.5) < 1e-9);
    assert_true (fabs (s_num (cam, "hfov_deg") - 6) < 1e-9);
    assert_true (fabs (s_num (cam, "vfov_deg") - 4.5) < 1e-9);
    assert_true (json_object_get_boolean (s_get (cam, "stabilized")));
    assert_string_equal (json_object_get_string (s_get (cam, "stare")), "point");
    json_object *pt = s_get (cam, "stare_point");
    assert_true (fabs (json_object_get_double (json_object_array_get_idx (pt, 0)) - 1234.6) < 1e-9);
    assert_true (fabs (json_object_get_double (json_object_array_get_idx (pt, 1)) + 789.0) < 1e-9);
    assert_true (json_object_get_boolean (s_get (cam, "staring")));
    assert_true (json_object_get_boolean (s_get (cam, "at_gimbal_limit")));
    json_object *g = s_get (cam, "gimbal");
    assert_true (fabs (s_num (g, "azimuth_limit_deg") - 150) < 1e-9);
    assert_true (fabs (s_num (g, "elevation_min_deg") + 90) < 1e-9);
    assert_true (fabs (s_num (g, "elevation_max_deg")) < 1e-9);
    json_object_put (o);
    // Off, without a point; a value that is not finite is unknown (null).
    c.stare = CGS__STARE_MODE__STARE_MODE_OFF;
    c.stare_point = NULL;
    c.staring = false;
    c.at_gimbal_limit = false;
    c.stabilized = false;
    c.hfov_deg = NAN;
    assert_int_equal (st_state_take_uav (st, &u, NULL), 0);
    o = s_picture (st);
    cam = s_get (s_uav0 (o), "camera");
    assert_string_equal (json_object_get_string (s_get (cam, "stare")), "off");
    assert_true (json_object_get_type (s_get (cam, "stare_point")) == json_type_null);
    assert_true (json_object_get_type (s_get (cam, "hfov_deg")) == json_type_null);
    assert_false (json_object_get_boolean (s_get (cam, "staring")));
    assert_false (json_object_get_boolean (s_get (cam, "stabilized")));
    json_object_put (o);
    c.stare = CGS__STARE_MODE__STARE_MODE_TARGET;
    assert_int_equal (st_state_take_uav (st, &u, NULL), 0);
    o = s_picture (st);
    assert_string_equal (json_object_get_string (s_get (s_get (s_uav0 (o), "camera"), "stare")),
                         "target");
    json_object_put (o);

    // The live mode: every image message of the UAV says it (those that did
    // not refresh latest.png too); another UAV's does not.
    static const struct {
        Cgs__ImageMode mode;
        const char *path, *name;
    } seq[] = {{CGS__IMAGE_MODE__IMAGE_MODE_VISIBLE, "/i/latest.png", "visible"},
               {CGS__IMAGE_MODE__IMAGE_MODE_INFRARED, "", "infrared"},
               {CGS__IMAGE_MODE__IMAGE_MODE_SAR, "/i/latest.png", "sar"}};
    Cgs__Image im = CGS__IMAGE__INIT;
    for (size_t i = 0; i < 3; i++) {
        im.uav_id = 3;
        im.frame_number = i + 1;
        im.mode = seq[i].mode;
        im.latest_path = (char *)seq[i].path;
        assert_int_equal (st_state_take_image (st, &im, NULL), 0);
        st_state_image_shown (st, i + 1);
        o = s_picture (st);
        assert_string_equal (json_object_get_string (s_get (s_uav0 (o), "sensor_mode")),
                             seq[i].name);
        json_object_put (o);
    }
    im.uav_id = 9;
    im.mode = CGS__IMAGE_MODE__IMAGE_MODE_VISIBLE;
    im.latest_path = "";
    assert_int_equal (st_state_take_image (st, &im, NULL), 0);
    o = s_picture (st);
    assert_string_equal (json_object_get_string (s_get (s_uav0 (o), "sensor_mode")), "sar");
    // The picture's image says SAR too.
    assert_string_equal (json_object_get_string (s_get (s_get (o, "image"), "mode")), "sar");
    json_object_put (o);
    // Its imagerd not heard of for track_stale_s: the mode is no longer known.
    st_state_set_time (st, 61);
    assert_int_equal (st_state_take_uav (st, &u, NULL), 0);
    st_state_prune (st);
    o = s_picture (st);
    assert_true (json_object_get_type (s_get (s_uav0 (o), "sensor_mode")) == json_type_null);
    json_object_put (o);
    st_state_destroy (&st);
}

/* ---- st_request: the page's commands ---------------------------------------------- */

/* The command made of a page's message text: st_request_command's result,
 * the reason in why. */
static int s_request (const char *text, st_command_t *c, char *why, size_t whylen)
{
    json_object *req = json_tokener_parse (text);
    assert_non_null (req);
    json_object *op;
    assert_true (json_object_object_get_ex (req, "op", &op));
    assert_true (st_request_is_command (json_object_get_string (op)));
    *why = '\0';
    int rc = st_request_command (req, json_object_get_string (op), c, why, whylen);
    json_object_put (req);
    return rc;
}

/* text is refused, the reason starting with want. */
static void s_refused (const char *text, const char *want)
{
    st_command_t c;
    char why[512];
    if (s_request (text, &c, why, sizeof why) != -EINVAL)
        fail_msg ("%s was not refused", text);
    if (strncmp (why, want, strlen (want)) != 0)
        fail_msg ("%s: refused with \"%s\", not \"%s...\"", text, why, want);
}

static void test_request_ops (void **state)
{
    (void)state;
    assert_false (st_request_is_command ("mgrs"));
    assert_false (st_request_is_command ("fly-away"));
    assert_false (st_request_is_command (NULL));
    st_command_t c;
    char why[512];
    // designate: a hit by its id, or a point.
    assert_int_equal (s_request ("{\"op\":\"designate\",\"uav_id\":2,\"hit\":17,\"radar\":2}", &c,
                                 why, sizeof why),
                      0);
    assert_int_equal (c.to, ST_TO_GUIDANCED);
    assert_int_equal (c.cmd.body_case, CGS__COMMAND__BODY_DESIGNATE);
    assert_int_equal (c.cmd.designate->uav_id, 2);
    assert_int_equal (c.cmd.designate->target_case, CGS__DESIGNATE__TARGET_HIT);
    assert_int_equal (c.cmd.designate->hit->hit_id, 17);
    assert_int_equal (c.cmd.designate->hit->radar_uav_id, 2);
    assert_int_equal (s_request ("{\"op\":\"designate\",\"e\":10.5,\"n\":-3}", &c, why, sizeof why),
                      0);
    assert_int_equal (c.cmd.designate->target_case, CGS__DESIGNATE__TARGET_POINT);
    assert_true (c.cmd.designate->point->east_m == 10.5 && c.cmd.designate->point->north_m == -3);
    assert_int_equal (c.uav_id, 0);
    s_refused ("{\"op\":\"designate\",\"hit\":2.5,\"radar\":1}", "designate: hit and radar");
    s_refused ("{\"op\":\"designate\",\"hit\":5,\"radar\":\"uav1\"}", "designate: hit and radar");
    s_refused ("{\"op\":\"designate\",\"e\":\"x\",\"n\":1}", "designate needs the clicked hit");
    // The UAV id, when given, is a whole number >= 0, for every op.
    s_refused ("{\"op\":\"cancel\",\"uav_id\":-1}", "uav_id must be a whole number >= 0");
    s_refused ("{\"op\":\"camera\",\"uav_id\":\"1\",\"depression\":30}", "uav_id must be");
    s_refused ("{\"op\":\"sensor_mode\",\"uav_id\":1.5,\"mode\":\"sar\"}", "uav_id must be");
    assert_int_equal (s_request ("{\"op\":\"cancel\",\"uav_id\":4}", &c, why, sizeof why), 0);
    assert_int_equal (c.cmd.body_case, CGS__COMMAND__BODY_CANCEL);
    assert_int_equal (c.cmd.cancel->uav_id, 4);
    // uavsim's, and guidanced's settings.
    assert_int_equal (s_request ("{\"op\":\"altitude\",\"value\":1300}", &c, why, sizeof why), 0);
    assert_int_equal (c.to, ST_TO_UAVSIM);
    assert_true (c.cmd.set_altitude->altitude_agl_m == 1300);
    assert_int_equal (s_request ("{\"op\":\"speed\",\"value\":41}", &c, why, sizeof why), 0);
    assert_int_equal (c.cmd.body_case, CGS__COMMAND__BODY_SET_SPEED);
    s_refused ("{\"op\":\"speed\",\"value\":\"fast\"}", "needs a number value");
    assert_int_equal (s_request ("{\"op\":\"footprint_scale\",\"value\":5}", &c, why, sizeof why),
                      0);
    assert_int_equal (c.cmd.set_footprint_scale->scale, 5);
    s_refused ("{\"op\":\"footprint_scale\",\"value\":2.5}", "footprint_scale needs");
    assert_int_equal (
        s_request ("{\"op\":\"intercept_mode\",\"value\":\"mti-hits\"}", &c, why, sizeof why), 0);
    assert_int_equal (c.cmd.set_intercept_mode->method,
                      CGS__INTERCEPT_METHOD__INTERCEPT_METHOD_MTI_HITS);
    s_refused ("{\"op\":\"intercept_mode\",\"value\":\"sideways\"}", "intercept_mode needs");
}

/* A replay's timeline: its four commands, to the replay; bad values refused. */
static void test_request_replay (void **state)
{
    (void)state;
    st_command_t c;
    char why[512];
    assert_true (st_request_is_replay ("replay_seek"));
    assert_false (st_request_is_replay ("designate"));
    assert_false (st_request_is_replay ("replay_rewind")); // not one of them
    assert_false (st_request_is_command ("replay_rewind"));
    assert_int_equal (s_request ("{\"op\":\"replay_pause\"}", &c, why, sizeof why), 0);
    assert_int_equal (c.to, ST_TO_REPLAY);
    assert_int_equal (c.cmd.body_case, CGS__COMMAND__BODY_PAUSE);
    assert_int_equal (s_request ("{\"op\":\"replay_resume\"}", &c, why, sizeof why), 0);
    assert_int_equal (c.cmd.body_case, CGS__COMMAND__BODY_RESUME);
    assert_int_equal (s_request ("{\"op\":\"replay_speed\",\"value\":2.5}", &c, why, sizeof why),
                      0);
    assert_int_equal (c.cmd.body_case, CGS__COMMAND__BODY_SET_TIME_SCALE);
    assert_true (c.cmd.set_time_scale->time_scale == 2.5);
    assert_int_equal (s_request ("{\"op\":\"replay_seek\",\"t\":12.5}", &c, why, sizeof why), 0);
    assert_int_equal (c.to, ST_TO_REPLAY);
    assert_int_equal (c.cmd.body_case, CGS__COMMAND__BODY_SEEK);
    assert_true (c.cmd.seek->t_s == 12.5);
    s_refused ("{\"op\":\"replay_speed\",\"value\":0}", "replay_speed needs a value in (0, 1000]");
    s_refused ("{\"op\":\"replay_speed\",\"value\":2000}", "replay_speed needs");
    s_refused ("{\"op\":\"replay_seek\",\"t\":-1}", "replay_seek needs a time t >= 0");
    s_refused ("{\"op\":\"replay_seek\",\"t\":\"end\"}", "replay_seek needs");
}

/* A replay's position goes to the page as it came; a seek (a new
 * generation) says the picture before is stale; bad numbers are refused. */
static void test_replay_state (void **state)
{
    (void)state;
    st_state_t *st = st_state_new (&s_params);
    Cgs__ReplayState m = CGS__REPLAY_STATE__INIT;
    Cgs__ReplayMark k = CGS__REPLAY_MARK__INIT, *pk = &k;
    k.t_s = 12.25;
    k.kind = "designate";
    k.text = "designate track 49";
    m.file = "run.mcap";
    m.t_s = 3.5;
    m.span_s = 60;
    m.speed = 2;
    m.paused = true;
    m.generation = 0;
    m.n_marks = 1;
    m.marks = &pk;
    bool fresh = true;
    assert_int_equal (st_state_take_replay (st, &m, &fresh), 0);
    assert_false (fresh); // the first heard is not a seek
    size_t len;
    char *json = st_state_json (st, 1, &len);
    assert_non_null (strstr (json,
                             "\"replay\":{\"file\":\"run.mcap\",\"t_s\":3.50,\"span_s\":60.00,"
                             "\"speed\":2.000,\"paused\":true,\"ended\":false,\"generation\":0"));
    assert_non_null (strstr (json, "\"marks\":[{\"t_s\":12.25,\"kind\":\"designate\",\"text\":"
                                   "\"designate track 49\"}]"));
    free (json);
    m.t_s = 4;
    assert_int_equal (st_state_take_replay (st, &m, &fresh), 0);
    assert_false (fresh); // the same generation
    m.generation = 1;
    assert_int_equal (st_state_take_replay (st, &m, &fresh), 0);
    assert_true (fresh);
    m.t_s = NAN;
    assert_int_equal (st_state_take_replay (st, &m, &fresh), -EINVAL);
    assert_false (fresh);
    m.t_s = 1;
    m.span_s = -1;
    assert_int_equal (st_state_take_replay (st, &m, NULL), -EINVAL);
    st_state_destroy (&st);
    // A live exercise: "replay": null.
    st = st_state_new (&s_params);
    json = st_state_json (st, 1, &len);
    assert_non_null (strstr (json, "\"replay\":null"));
    free (json);
    st_state_destroy (&st);
}

static void test_request_camera (void **state)
{
    (void)state;
    st_command_t c;
    char why[512];
    // Only what is given is set: its bit and its value, the others zero.
    assert_int_equal (
        s_request ("{\"op\":\"camera\",\"uav_id\":1,\"depression\":30}", &c, why, sizeof why), 0);
    assert_int_equal (c.to, ST_TO_UAVSIM);
    assert_int_equal (c.cmd.body_case, CGS__COMMAND__BODY_SET_CAMERA);
    const Cgs__SetCamera *k = c.cmd.set_camera;
    assert_int_equal (k->uav_id, 1);
    assert_int_equal (k->set, ST_CAMERA_SET_DEPRESSION);
    assert_int_equal (k->set, 1);
    assert_true (k->depression_deg == 30 && k->hfov_deg == 0 && !k->stabilized);
    assert_null (k->stare_point);
    assert_int_equal (s_request ("{\"op\":\"camera\",\"fov\":6.5}", &c, why, sizeof why), 0);
    assert_int_equal (c.cmd.set_camera->set, 2);
    assert_true (c.cmd.set_camera->hfov_deg == 6.5 && c.cmd.set_camera->depression_deg == 0);
    assert_int_equal (s_request ("{\"op\":\"camera\",\"stabilized\":false}", &c, why, sizeof why),
                      0);
    assert_int_equal (c.cmd.set_camera->set, 4);
    assert_false (c.cmd.set_camera->stabilized);
    assert_int_equal (s_request ("{\"op\":\"camera\",\"stabilized\":true}", &c, why, sizeof why),
                      0);
    assert_true (c.cmd.set_camera->stabilized);
    // Stare: off, at the target, at a point.
    assert_int_equal (s_request ("{\"op\":\"camera\",\"stare\":\"off\"}", &c, why, sizeof why), 0);
    assert_int_equal (c.cmd.set_camera->set, 8);
    assert_int_equal (c.cmd.set_camera->stare, CGS__STARE_MODE__STARE_MODE_OFF);
    assert_null (c.cmd.set_camera->stare_point);
    assert_int_equal (s_request ("{\"op\":\"camera\",\"stare\":\"target\"}", &c, why, sizeof why),
                      0);
    assert_int_equal (c.cmd.set_camera->set, 8);
    assert_int_equal (c.cmd.set_camera->stare, CGS__STARE_MODE__STARE_MODE_TARGET);
    assert_int_equal (s_request ("{\"op\":\"camera\",\"uav_id\":2,\"stare\":{\"e\":-1500.25,"
                                 "\"n\":820}}",
                                 &c, why, sizeof why),
                      0);
    k = c.cmd.set_camera;
    assert_int_equal (k->set, 8);
    assert_int_equal (k->uav_id, 2);
    assert_int_equal (k->stare, CGS__STARE_MODE__STARE_MODE_POINT);
    assert_non_null (k->stare_point);
    assert_true (k->stare_point->east_m == -1500.25 && k->stare_point->north_m == 820);
    assert_true (k->stare_point->up_m == 0);
    // All four at once: every bit.
    assert_int_equal (s_request ("{\"op\":\"camera\",\"depression\":-10,\"fov\":40,"
                                 "\"stabilized\":true,\"stare\":\"target\"}",
                                 &c, why, sizeof why),
                      0);
    k = c.cmd.set_camera;
    assert_int_equal (k->set, 15);
    assert_true (k->depression_deg == -10 && k->hfov_deg == 40 && k->stabilized);
    assert_int_equal (k->stare, CGS__STARE_MODE__STARE_MODE_TARGET);
    // The command packs and unpacks as it was made (its body points into c).
    size_t len = cgs__command__get_packed_size (&c.cmd);
    uint8_t buf[256];
    assert_true (len <= sizeof buf);
    cgs__command__pack (&c.cmd, buf);
    Cgs__Command *back = cgs__command__unpack (NULL, len, buf);
    assert_non_null (back);
    assert_int_equal (back->body_case, CGS__COMMAND__BODY_SET_CAMERA);
    assert_int_equal (back->set_camera->set, 15);
    assert_true (back->set_camera->hfov_deg == 40);
    cgs__command__free_unpacked (back, NULL);
    // Refused: wrong types, numbers out of range, unknown stare values, nothing to set.
    s_refused ("{\"op\":\"camera\"}", "camera needs at least one of");
    s_refused ("{\"op\":\"camera\",\"uav_id\":1,\"zoom\":3}", "camera needs at least one of");
    s_refused ("{\"op\":\"camera\",\"depression\":\"30\"}", "camera: depression must be");
    s_refused ("{\"op\":\"camera\",\"depression\":null}", "camera: depression must be");
    s_refused ("{\"op\":\"camera\",\"depression\":90.5}", "camera: depression must be");
    s_refused ("{\"op\":\"camera\",\"depression\":-91}", "camera: depression must be");
    s_refused ("{\"op\":\"camera\",\"depression\":1e400}", "camera: depression must be");
    s_refused ("{\"op\":\"camera\",\"fov\":0}", "camera: fov");
    s_refused ("{\"op\":\"camera\",\"fov\":-5}", "camera: fov");
    s_refused ("{\"op\":\"camera\",\"fov\":180}", "camera: fov");
    s_refused ("{\"op\":\"camera\",\"fov\":true}", "camera: fov");
    s_refused ("{\"op\":\"camera\",\"stabilized\":1}", "camera: stabilized must be true or false");
    s_refused ("{\"op\":\"camera\",\"stabilized\":\"on\"}", "camera: stabilized must be");
    s_refused ("{\"op\":\"camera\",\"stare\":\"on\"}", "camera: stare must be");
    s_refused ("{\"op\":\"camera\",\"stare\":true}", "camera: stare must be");
    s_refused ("{\"op\":\"camera\",\"stare\":[1,2]}", "camera: stare must be");
    s_refused ("{\"op\":\"camera\",\"stare\":{\"e\":1}}", "camera: stare must be");
    s_refused ("{\"op\":\"camera\",\"stare\":{\"e\":\"1\",\"n\":2}}", "camera: stare must be");
    s_refused ("{\"op\":\"camera\",\"stare\":{\"e\":2e7,\"n\":0}}", "camera: stare must be");
    s_refused ("{\"op\":\"camera\",\"stare\":{\"e\":0,\"n\":-1e400}}", "camera: stare must be");
    // One bad field refuses the whole command.
    s_refused ("{\"op\":\"camera\",\"depression\":30,\"fov\":\"wide\"}", "camera: fov");
}

static void test_request_sensor_mode (void **state)
{
    (void)state;
    static const struct {
        const char *name;
        Cgs__ImageMode mode;
    } modes[] = {{"visible", CGS__IMAGE_MODE__IMAGE_MODE_VISIBLE},
                 {"infrared", CGS__IMAGE_MODE__IMAGE_MODE_INFRARED},
                 {"sar", CGS__IMAGE_MODE__IMAGE_MODE_SAR}};
    st_command_t c;
    char why[512], text[128];
    for (size_t i = 0; i < 3; i++) {
        snprintf (text, sizeof text, "{\"op\":\"sensor_mode\",\"uav_id\":3,\"mode\":\"%s\"}",
                  modes[i].name);
        assert_int_equal (s_request (text, &c, why, sizeof why), 0);
        assert_int_equal (c.to, ST_TO_IMAGERD);
        assert_int_equal (c.uav_id, 3);
        assert_int_equal (c.cmd.body_case, CGS__COMMAND__BODY_SET_SENSOR_MODE);
        assert_int_equal (c.cmd.set_sensor_mode->uav_id, 3);
        assert_int_equal (c.cmd.set_sensor_mode->mode, modes[i].mode);
    }
    s_refused ("{\"op\":\"sensor_mode\"}", "sensor_mode needs the mode");
    s_refused ("{\"op\":\"sensor_mode\",\"mode\":\"flir\"}", "sensor_mode needs the mode");
    s_refused ("{\"op\":\"sensor_mode\",\"mode\":\"SAR\"}", "sensor_mode needs the mode");
    s_refused ("{\"op\":\"sensor_mode\",\"mode\":2}", "sensor_mode needs the mode");
    s_refused ("{\"op\":\"sensor_mode\",\"value\":\"sar\"}", "sensor_mode needs the mode");
}

/* An exercise file of that text in a fresh folder, loaded. */
static cgs_exercise_t *s_exercise (const char *text)
{
    char dir[] = "/tmp/test_st_request.XXXXXX", path[64], err[512] = "";
    assert_non_null (mkdtemp (dir));
    snprintf (path, sizeof path, "%s/ex.ini", dir);
    FILE *f = fopen (path, "w");
    assert_non_null (f);
    fputs (text, f);
    fclose (f);
    cgs_exercise_t *ex = NULL;
    if (cgs_exercise_load (path, &ex, err, sizeof err) < 0)
        fail_msg ("%s", err);
    unlink (path);
    rmdir (dir);
    return ex;
}

#define S_EX_HEAD "[exercise]\norigin = geo 35.96 -121.23 0\n"

static void test_request_imagerd (void **state)
{
    (void)state;
    char err[512] = "", why[512];
    cgs_scenario_t *sc = NULL;
    if (cgs_scenario_load_string ("s.ini",
                                  "[uav alpha]\nid = 7\nposition = 0 0\n"
                                  "[uav bravo]\nid = 8\nposition = 5000 0\n"
                                  "[uav charlie]\nid = 9\nposition = 9000 0\n",
                                  NULL, 1, &sc, err, sizeof err) < 0)
        fail_msg ("%s", err);
    cgs_exercise_t *ex = s_exercise (
        S_EX_HEAD
        "[service uavsim]\npublish = ipc:///tmp/t-uavsim.pub\ncommand = ipc:///tmp/t-u.cmd\n"
        "[service imagerd.alpha]\npublish = ipc:///tmp/t-imagerd.alpha.pub\nuav = alpha\n"
        "command = ipc:///tmp/t-ia.cmd\n"
        "[service imagerd.bravo0]\npublish = ipc:///tmp/t-imagerd.bravo0.pub\nuav = bravo\n"
        "command = ipc:///tmp/t-ib0.cmd\nenabled = no\n"
        "[service imagerd.bravo]\npublish = ipc:///tmp/t-imagerd.bravo.pub\nuav = bravo\n"
        "command = ipc:///tmp/t-ib.cmd\n"
        "[service imagerd.charlie]\npublish = ipc:///tmp/t-imagerd.charlie.pub\nuav = charlie\n");
    const cgs_instance_t *in = NULL;
    // The imagerd whose uav names the UAV of that entity id.
    assert_int_equal (st_request_imagerd (ex, sc, 7, &in, why, sizeof why), 0);
    assert_string_equal (in->name, "imagerd.alpha");
    assert_string_equal (in->command, "ipc:///tmp/t-ia.cmd");
    // An enabled one before one the exercise leaves out.
    assert_int_equal (st_request_imagerd (ex, sc, 8, &in, why, sizeof why), 0);
    assert_string_equal (in->name, "imagerd.bravo");
    // One without a command endpoint cannot take it: refused, saying why.
    in = NULL;
    assert_int_equal (st_request_imagerd (ex, sc, 9, &in, why, sizeof why), -ENOENT);
    assert_null (in);
    assert_non_null (strstr (why, "no imagerd for charlie that takes commands"));
    assert_int_equal (st_request_imagerd (ex, sc, 5, &in, why, sizeof why), -ENOENT);
    assert_string_equal (why, "the scenario has no UAV of entity id 5");
    // Several imagerd and no UAV named: no way to choose.
    assert_int_equal (st_request_imagerd (ex, sc, 0, &in, why, sizeof why), -ENOENT);
    assert_non_null (strstr (why, "say which UAV"));
    assert_int_equal (st_request_imagerd (ex, NULL, 7, &in, why, sizeof why), -ENOENT);
    assert_non_null (strstr (why, "without a scenario"));
    cgs_exercise_destroy (&ex);
    // The only one, without a scenario (it checks the UAV id itself).
    ex = s_exercise (
        S_EX_HEAD "[service imagerd.alpha]\npublish = ipc:///tmp/t-imagerd.alpha.pub\nuav = alpha\n"
                  "command = ipc:///tmp/t-ia.cmd\n");
    assert_int_equal (st_request_imagerd (ex, NULL, 7, &in, why, sizeof why), 0);
    assert_string_equal (in->name, "imagerd.alpha");
    assert_int_equal (st_request_imagerd (ex, sc, 0, &in, why, sizeof why), 0);
    assert_string_equal (in->name, "imagerd.alpha");
    cgs_exercise_destroy (&ex);
    // None at all.
    ex = s_exercise (
        S_EX_HEAD
        "[service uavsim]\npublish = ipc:///tmp/t-uavsim.pub\ncommand = ipc:///tmp/t-u.cmd\n");
    assert_int_equal (st_request_imagerd (ex, sc, 7, &in, why, sizeof why), -ENOENT);
    assert_non_null (strstr (why, "no imagerd for alpha"));
    assert_int_equal (st_request_imagerd (ex, NULL, 0, &in, why, sizeof why), -ENOENT);
    assert_non_null (strstr (why, "no imagerd that takes commands"));
    cgs_exercise_destroy (&ex);
    cgs_scenario_destroy (&sc);
}

int main (void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test (test_history_of_scans),
        cmocka_unit_test (test_history_length_is_a_parameter),
        cmocka_unit_test (test_bad_hits_are_refused_whole),
        cmocka_unit_test (test_bcis_replies_time_out),
        cmocka_unit_test (test_tracks),
        cmocka_unit_test (test_footprint_scale_and_range),
        cmocka_unit_test (test_truth_and_image),
        cmocka_unit_test (test_clock_and_staleness),
        cmocka_unit_test (test_full_tables),
        cmocka_unit_test (test_video),
        cmocka_unit_test (test_camera_and_sensor_mode),
        cmocka_unit_test (test_request_ops),
        cmocka_unit_test (test_request_replay),
        cmocka_unit_test (test_replay_state),
        cmocka_unit_test (test_request_camera),
        cmocka_unit_test (test_request_sensor_mode),
        cmocka_unit_test (test_request_imagerd),
    };
    return cmocka_run_group_tests (tests, NULL, NULL);
}
