/* trackerd's adapter, driven with hand-built decoded messages and a test
 * port (no bus): every message it publishes is encoded and decoded back
 * (so it must be complete, valid protobuf of its topic's type) into a list
 * the tests read; its log lines, bad input and errors are recorded. Scans
 * held until their marker, radars kept apart, scans closed without their
 * marker, stale hits, time going back, malformed input, BCIS identity,
 * batches of 200 tracks, deleted tracks published once, turns. */
#include "cgs_msg.h"
#include "cgs_port.h"
#include "cgs_topics.h"
#include "trk_adapter.h"
#include "trk_params.h"
#include "trk_tracker.h"

#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <syslog.h>

#include <cmocka.h>

#include "port_check.h" // after cmocka.h

#define S_PI     3.14159265358979323846
#define S_MAX    1024 // publications, log lines, bad inputs, errors a test may make
#define S_LINE   1024
#define S_HITS   512 // hits one mti message of these tests holds
#define S_PLAT_U 1500.0

/* One message the adapter published, as decoded back. */
typedef struct {
    char topic[32];
    ProtobufCMessage *msg;
    double t_s; // the simulation time it was published at
} s_pub_t;

typedef struct {
    trk_adapter_t *a;
    s_pub_t pubs[S_MAX];
    size_t npubs;
    int log_priority[S_MAX];
    char log_line[S_MAX][S_LINE];
    size_t nlogs;
    char bad[S_MAX][S_LINE];
    size_t nbad;
    char err[S_MAX][S_LINE];
    size_t nerr;
} s_fix_t;

/* ---- the test port ----------------------------------------------------------------- */

static int s_publish (void *arg, const char *topic, ProtobufCMessage *msg, double sim_time_s)
{
    s_fix_t *f = arg;
    assert_true (f->npubs < S_MAX);
    ProtobufCMessage *back = port_check_roundtrip (topic, msg);
    s_pub_t *p = &f->pubs[f->npubs++];
    snprintf (p->topic, sizeof p->topic, "%s", topic);
    p->msg = back;
    p->t_s = sim_time_s;
    return 0;
}

static void s_log (void *arg, int priority, const char *line)
{
    s_fix_t *f = arg;
    assert_true (f->nlogs < S_MAX);
    f->log_priority[f->nlogs] = priority;
    snprintf (f->log_line[f->nlogs++], S_LINE, "%s", line);
}

static void s_bad_input (void *arg, const char *what)
{
    s_fix_t *f = arg;
    assert_true (f->nbad < S_MAX);
    snprintf (f->bad[f->nbad++], S_LINE, "%s", what);
}

static void s_error (void *arg, const char *why)
{
    s_fix_t *f = arg;
    assert_true (f->nerr < S_MAX);
    snprintf (f->err[f->nerr++], S_LINE, "%s", why);
}

static int s_setup (void **state)
{
    s_fix_t *f = calloc (1, sizeof *f);
    assert_non_null (f);
    trk_params_t p;
    trk_params_defaults (&p);
    cgs_port_t port = {
        .arg = f, .publish = s_publish, .log = s_log, .bad_input = s_bad_input, .error = s_error};
    f->a = trk_adapter_new (&p, &port);
    assert_non_null (f->a);
    *state = f;
    return 0;
}

static int s_teardown (void **state)
{
    s_fix_t *f = *state;
    trk_adapter_destroy (&f->a);
    assert_null (f->a);
    trk_adapter_destroy (&f->a); // idempotent
    for (size_t i = 0; i < f->npubs; i++)
        cgs_msg_free (&f->pubs[i].msg);
    free (f);
    return 0;
}

/* ---- inputs -------------------------------------------------------------------------- */

/* One hit: id, time, measured ground position (at height up_m) and the
 * target's velocity (for the radial velocity the radar would measure). */
typedef struct {
    uint32_t id;
    double t_s;
    double e_m, n_m, up_m;
    double ve_mps, vn_mps;
} s_hit_t;

static void s_send (s_fix_t *f, const char *topic, const ProtobufCMessage *msg, double hdr_t)
{
    Cgs__Header h = CGS__HEADER__INIT;
    h.sim_time_s = hdr_t;
    trk_adapter_on_message (f->a, topic, msg, &h);
}

/* An mti message of radar uav's scan (the radar at (0, 0, 1500)) with
 * these hits, its header at time hdr_t. */
static void s_mti (s_fix_t *f, uint32_t uav, uint32_t scan, double hdr_t, const s_hit_t *hits,
                   size_t n)
{
    assert_true (n <= S_HITS);
    static Cgs__MtiHit h[S_HITS];
    static Cgs__MtiHit *hp[S_HITS];
    static Cgs__Enu pos[S_HITS];
    Cgs__Enu pl = CGS__ENU__INIT;
    pl.up_m = S_PLAT_U;
    for (size_t i = 0; i < n; i++) {
        const s_hit_t *x = &hits[i];
        cgs__mti_hit__init (&h[i]);
        cgs__enu__init (&pos[i]);
        pos[i].east_m = x->e_m;
        pos[i].north_m = x->n_m;
        pos[i].up_m = x->up_m;
        double du = x->up_m - S_PLAT_U, slant = sqrt (x->e_m * x->e_m + x->n_m * x->n_m + du * du);
        h[i].hit_id = x->id;
        h[i].position = &pos[i];
        h[i].range_m = slant;
        h[i].azimuth_deg = fmod (atan2 (x->e_m, x->n_m) * 180 / S_PI + 360, 360);
        h[i].radial_velocity_mps = (x->e_m * x->ve_mps + x->n_m * x->vn_mps) / slant;
        h[i].range_sigma_m = 25;
        h[i].azimuth_sigma_deg = 0.2;
        h[i].sim_time_s = x->t_s;
        hp[i] = &h[i];
    }
    Cgs__Mti m = CGS__MTI__INIT;
    m.uav_id = uav;
    m.scan_number = scan;
    m.platform_position = &pl;
    m.n_hits = n;
    m.hits = n ? hp : NULL;
    s_send (f, "mti", &m.base, hdr_t);
}

/* The mti.scan marker of a full revolution of radar uav from start to end. */
static void s_marker (s_fix_t *f, uint32_t uav, uint32_t scan, double start_s, double end_s)
{
    Cgs__MtiScan m = CGS__MTI_SCAN__INIT;
    m.uav_id = uav;
    m.scan_number = scan;
    m.scan_start_s = start_s;
    m.scan_end_s = end_s;
    m.full_revolution = true;
    s_send (f, "mti.scan", &m.base, end_s);
}

/* A BCIS message of one reply from responder at (e, n) at time t: from an
 * interrogator 8 km south of it and 6 km up, range 10 km (σ 5 m), beam
 * azimuth 0 (σ 1.732°); with fix, a position fix of σ 10 m instead. */
static void s_bcis_reply (s_fix_t *f, uint32_t responder, double t_s, double e_m, double n_m,
                          bool fix, bool interrogator)
{
    Cgs__Enu pos = CGS__ENU__INIT, at = CGS__ENU__INIT;
    pos.east_m = e_m;
    pos.north_m = n_m;
    at.east_m = e_m;
    at.north_m = n_m - 8000;
    at.up_m = 6000;
    Cgs__BcisReply r = CGS__BCIS_REPLY__INIT;
    r.responder_id = responder;
    r.position = &pos;
    r.sim_time_s = t_s;
    r.range_m = 10000;
    r.range_sigma_m = 5;
    r.azimuth_deg = 0;
    r.azimuth_sigma_deg = 1.732;
    r.position_fix = fix;
    r.position_sigma_m = fix ? 10 : 0;
    Cgs__BcisReply *rp = &r;
    Cgs__Bcis m = CGS__BCIS__INIT;
    m.uav_id = 1;
    m.n_replies = 1;
    m.replies = &rp;
    m.interrogator = interrogator ? &at : NULL;
    s_send (f, "bcis", &m.base, t_s);
}

static void s_bcis (s_fix_t *f, uint32_t responder, double t_s, double e_m, double n_m)
{
    s_bcis_reply (f, responder, t_s, e_m, n_m, false, true);
}

/* A target moving at (ve, vn) from (e0, n0) at time 0, hit at time t. */
static s_hit_t s_target (uint32_t id, double t_s, double e0, double n0, double ve, double vn)
{
    return (s_hit_t){id, t_s, e0 + ve * t_s, n0 + vn * t_s, 0, ve, vn};
}

/* ---- outputs ------------------------------------------------------------------------- */

/* Publication i, which must be a `track` batch. */
static const Cgs__TrackBatch *s_batch (const s_fix_t *f, size_t i)
{
    assert_true (i < f->npubs);
    assert_string_equal (f->pubs[i].topic, "track");
    return (const Cgs__TrackBatch *)f->pubs[i].msg;
}

/* The latest publication, a `track` batch. */
static const Cgs__TrackBatch *s_last_batch (const s_fix_t *f)
{
    assert_true (f->npubs > 0);
    return s_batch (f, f->npubs - 1);
}

/* The track in batch b whose latest history point has this hit id, or NULL. */
static const Cgs__Track *s_track_of_hit (const Cgs__TrackBatch *b, uint32_t hit_id)
{
    for (size_t i = 0; i < b->n_tracks; i++) {
        const Cgs__Track *t = b->tracks[i];
        if (t->n_history && t->history[t->n_history - 1]->hit_id == hit_id)
            return t;
    }
    return NULL;
}

/* How many of the recorded log lines have this priority and begin so. */
static size_t s_logged (const s_fix_t *f, int priority, const char *prefix)
{
    size_t n = 0;
    for (size_t i = 0; i < f->nlogs; i++)
        if (f->log_priority[i] == priority &&
            strncmp (f->log_line[i], prefix, strlen (prefix)) == 0)
            n++;
    return n;
}

/* ---- tests --------------------------------------------------------------------------- */

/* Hits are held until their scan's marker; then one batch of that radar's
 * tracks with the scan's number, at the scan's end time. */
static void test_scan_held_until_marker (void **state)
{
    s_fix_t *f = *state;
    s_hit_t d1[2] = {{1, 1, 5000, 0, 0, 0, 0}, {2, 1.5, 0, 5000, 0, 0, 0}};
    s_hit_t d2[1] = {{3, 4, -5000, 0, 0, 0, 0}};
    s_mti (f, 1, 0, 1, d1, 2);
    s_mti (f, 1, 0, 4, d2, 1);
    assert_int_equal (f->npubs, 0);
    assert_false (trk_adapter_take_dirty (f->a));
    assert_int_equal (trk_adapter_stats (f->a)->scans, 0);
    s_marker (f, 1, 0, 0, 10);
    assert_int_equal (f->npubs, 1);
    assert_true (f->pubs[0].t_s == 10);
    const Cgs__TrackBatch *b = s_batch (f, 0);
    assert_int_equal (b->uav_id, 1);
    assert_int_equal (b->scan_number, 0);
    assert_int_equal (b->batch_index, 0);
    assert_int_equal (b->batch_count, 1);
    assert_int_equal (b->n_tracks, 3);
    for (uint32_t id = 1; id <= 3; id++) {
        const Cgs__Track *t = s_track_of_hit (b, id);
        assert_non_null (t);
        assert_int_equal (t->uav_id, 1);
        assert_int_equal (t->status, CGS__TRACK_STATUS__TRACK_STATUS_TENTATIVE);
        assert_int_equal (t->identity, CGS__TRACK_IDENTITY__TRACK_IDENTITY_UNKNOWN);
        assert_int_equal (t->hit_count, 1);
        assert_int_equal (t->n_history, 1);
        assert_int_equal (t->n_covariance, 16);
        assert_non_null (t->position);
        assert_non_null (t->velocity);
    }
    assert_true (s_track_of_hit (b, 3)->position->east_m == -5000);
    const trk_adapter_stats_t *st = trk_adapter_stats (f->a);
    assert_int_equal (st->scans, 1);
    assert_int_equal (st->hits, 3);
    assert_int_equal (st->born, 3);
    assert_true (trk_adapter_take_dirty (f->a));
    assert_false (trk_adapter_take_dirty (f->a));
    // The first scan's line; the next scan's only when verbose.
    assert_int_equal (f->nlogs, 1);
    assert_int_equal (s_logged (f, LOG_INFO, "radar 1 scan 0: 3 hits, 0 updated, 0 missed, 3 new"),
                      1);
    s_marker (f, 1, 1, 10, 20);
    assert_int_equal (f->npubs, 2);
    assert_true (f->pubs[1].t_s == 20);
    assert_int_equal (s_last_batch (f)->scan_number, 1);
    assert_int_equal (s_last_batch (f)->n_tracks, 3);
    assert_int_equal (f->nlogs, 1);
    trk_adapter_set_verbose (f->a, true);
    s_marker (f, 1, 2, 20, 30);
    assert_int_equal (s_logged (f, LOG_INFO, "radar 1 scan 2: 0 hits"), 1);
    assert_int_equal (f->nbad, 0);
    assert_int_equal (f->nerr, 0);
}

/* Scans of two radars in progress at once stay apart: each marker gives a
 * batch of its radar's tracks only. */
static void test_two_radars_apart (void **state)
{
    s_fix_t *f = *state;
    s_hit_t r1a[1] = {{11, 41, 5000, 0, 0, 0, 0}};
    s_hit_t r2[2] = {{21, 91, 0, 5000, 0, 0, 0}, {22, 92, 0, -5000, 0, 0, 0}};
    s_hit_t r1b[1] = {{12, 45, -5000, 0, 0, 0, 0}};
    s_mti (f, 1, 4, 41, r1a, 1);
    s_mti (f, 2, 9, 92, r2, 2);
    s_mti (f, 1, 4, 45, r1b, 1);
    assert_int_equal (f->npubs, 0);
    s_marker (f, 2, 9, 90, 100);
    assert_int_equal (f->npubs, 1);
    const Cgs__TrackBatch *b = s_last_batch (f);
    assert_true (f->pubs[0].t_s == 100);
    assert_int_equal (b->uav_id, 2);
    assert_int_equal (b->scan_number, 9);
    assert_int_equal (b->n_tracks, 2);
    assert_non_null (s_track_of_hit (b, 21));
    assert_non_null (s_track_of_hit (b, 22));
    for (size_t i = 0; i < b->n_tracks; i++)
        assert_int_equal (b->tracks[i]->uav_id, 2);
    s_marker (f, 1, 4, 40, 50);
    assert_int_equal (f->npubs, 2);
    b = s_last_batch (f);
    assert_true (f->pubs[1].t_s == 50);
    assert_int_equal (b->uav_id, 1);
    assert_int_equal (b->scan_number, 4);
    assert_int_equal (b->n_tracks, 2);
    assert_non_null (s_track_of_hit (b, 11));
    assert_non_null (s_track_of_hit (b, 12));
    for (size_t i = 0; i < b->n_tracks; i++)
        assert_int_equal (b->tracks[i]->uav_id, 1);
    const trk_adapter_stats_t *st = trk_adapter_stats (f->a);
    assert_int_equal (st->scans, 2);
    assert_int_equal (st->hits, 4);
    assert_int_equal (st->implicit_scans, 0);
    assert_int_equal (st->stale_scans, 0);
    assert_int_equal (trk_tracker_count (trk_adapter_tracker (f->a)), 4);
}

/* Hits of the next scan without the marker of the open one: it is closed
 * with its hits (ending at its latest hit's time), counted. */
static void test_scan_closed_without_marker (void **state)
{
    s_fix_t *f = *state;
    s_hit_t a[1] = {{1, 1, 5000, 0, 0, 0, 0}}, b[1] = {{2, 3, 0, 5000, 0, 0, 0}};
    s_hit_t c[1] = {{3, 11, -5000, 0, 0, 0, 0}};
    s_mti (f, 1, 0, 1, a, 1);
    s_mti (f, 1, 0, 3, b, 1);
    s_mti (f, 1, 1, 11, c, 1);
    assert_int_equal (f->npubs, 1);
    assert_true (f->pubs[0].t_s == 3);
    const Cgs__TrackBatch *bt = s_last_batch (f);
    assert_int_equal (bt->scan_number, 0);
    assert_int_equal (bt->n_tracks, 2);
    assert_non_null (s_track_of_hit (bt, 1));
    assert_non_null (s_track_of_hit (bt, 2));
    assert_int_equal (trk_adapter_stats (f->a)->implicit_scans, 1);
    assert_int_equal (trk_adapter_stats (f->a)->scans, 1);
    // The hit of scan 1 waits for its own marker.
    s_marker (f, 1, 1, 10, 20);
    assert_int_equal (f->npubs, 2);
    assert_true (f->pubs[1].t_s == 20);
    bt = s_last_batch (f);
    assert_int_equal (bt->scan_number, 1);
    assert_non_null (s_track_of_hit (bt, 3));
    // A marker of scan 3 while scan 2 is open closes scan 2 first.
    s_hit_t d[1] = {{4, 21, 0, -5000, 0, 0, 0}};
    s_mti (f, 1, 2, 21, d, 1);
    s_marker (f, 1, 3, 30, 40);
    assert_int_equal (f->npubs, 4);
    assert_int_equal (s_batch (f, 2)->scan_number, 2);
    assert_true (f->pubs[2].t_s == 21);
    assert_int_equal (s_batch (f, 3)->scan_number, 3);
    const trk_adapter_stats_t *st = trk_adapter_stats (f->a);
    assert_int_equal (st->implicit_scans, 2);
    assert_int_equal (st->scans, 4);
    assert_int_equal (st->hits, 4);
    assert_int_equal (f->nbad, 0);
}

/* Hits or markers of a scan already closed are stale: counted, not used. */
static void test_stale_hits_ignored (void **state)
{
    s_fix_t *f = *state;
    s_hit_t a[1] = {{1, 1, 5000, 0, 0, 0, 0}}, late[1] = {{2, 2, 0, 5000, 0, 0, 0}};
    s_mti (f, 1, 0, 1, a, 1);
    s_marker (f, 1, 0, 0, 10);
    assert_int_equal (f->npubs, 1);
    s_mti (f, 1, 0, 2, late, 1); // scan 0 is over
    assert_int_equal (trk_adapter_stats (f->a)->stale_scans, 1);
    s_marker (f, 1, 0, 0, 10); // its marker again
    assert_int_equal (trk_adapter_stats (f->a)->stale_scans, 2);
    assert_int_equal (f->npubs, 1);
    s_marker (f, 1, 1, 10, 20);
    assert_int_equal (f->npubs, 2);
    const Cgs__TrackBatch *b = s_last_batch (f);
    assert_int_equal (b->n_tracks, 1); // the late hit made no track
    assert_null (s_track_of_hit (b, 2));
    // Scan 3 open: hits of scan 2 are late too.
    s_hit_t c[1] = {{3, 31, 0, 5000, 0, 0, 0}}, d[1] = {{4, 29, 0, -5000, 0, 0, 0}};
    s_mti (f, 1, 3, 31, c, 1);
    s_mti (f, 1, 2, 31, d, 1);
    assert_int_equal (trk_adapter_stats (f->a)->stale_scans, 3);
    s_marker (f, 1, 3, 30, 40);
    assert_int_equal (s_last_batch (f)->scan_number, 3);
    assert_null (s_track_of_hit (s_last_batch (f), 4));
    assert_non_null (s_track_of_hit (s_last_batch (f), 3));
    const trk_adapter_stats_t *st = trk_adapter_stats (f->a);
    assert_int_equal (st->hits, 2);
    assert_int_equal (st->scans, 3);
    assert_int_equal (st->implicit_scans, 0);
}

/* Simulation time going back by more than two scans drops the radar's open
 * scan with a notice; at its next scan the tracks from later times go. */
static void test_time_went_back (void **state)
{
    s_fix_t *f = *state;
    for (uint32_t k = 0; k < 4; k++) {
        s_hit_t h = s_target (k + 1, 10.0 * k + 1, 5000, 0, 10, 0);
        s_mti (f, 1, k, h.t_s, &h, 1);
        s_marker (f, 1, k, 10.0 * k, 10.0 * k + 10);
    }
    const Cgs__Track *before = s_track_of_hit (s_last_batch (f), 4);
    assert_non_null (before);
    assert_int_equal (before->status, CGS__TRACK_STATUS__TRACK_STATUS_CONFIRMED);
    uint32_t old_id = before->track_id;
    s_hit_t open = s_target (5, 41, 5000, 0, 10, 0);
    s_mti (f, 1, 4, 41, &open, 1); // scan 4 in progress
    size_t logs = f->nlogs, pubs = f->npubs;
    uint64_t hits = trk_adapter_stats (f->a)->hits;
    // A new exercise: time 2 s, scan 0.
    s_hit_t fresh = {6, 2, -3000, -3000, 0, 0, 0};
    s_mti (f, 1, 0, 2, &fresh, 1);
    assert_int_equal (f->npubs, pubs); // scan 4 was not run
    assert_int_equal (f->nlogs, logs + 1);
    assert_int_equal (f->log_priority[logs], LOG_NOTICE);
    assert_string_equal (f->log_line[logs],
                         "radar 1: simulation time went back from 41.00 to 2.00 s; its scan in "
                         "progress is dropped and its tracks from later times go at its next scan");
    assert_int_equal (trk_adapter_stats (f->a)->stale_scans, 0);
    s_marker (f, 1, 0, 0, 10);
    assert_int_equal (f->npubs, pubs + 1);
    const trk_adapter_stats_t *st = trk_adapter_stats (f->a);
    assert_int_equal (st->hits, hits + 1); // the new scan's hit only
    assert_int_equal (st->time_resets, 1);
    assert_int_equal (s_logged (f, LOG_NOTICE,
                                "simulation time went back to 10.00 s: 1 tracks of radar 1 from "
                                "later times were deleted"),
                      1);
    const Cgs__TrackBatch *b = s_last_batch (f);
    assert_int_equal (b->scan_number, 0);
    assert_int_equal (b->n_tracks, 2);
    bool deleted = false;
    for (size_t i = 0; i < b->n_tracks; i++)
        if (b->tracks[i]->track_id == old_id) {
            assert_int_equal (b->tracks[i]->status, CGS__TRACK_STATUS__TRACK_STATUS_DELETED);
            deleted = true;
        }
    assert_true (deleted);
    assert_non_null (s_track_of_hit (b, 6));
    assert_null (s_track_of_hit (b, 5));
}

/* What trackerd cannot use goes to bad input and changes nothing. */
static void test_malformed_input (void **state)
{
    s_fix_t *f = *state;
    const char *bad_mti = "an mti message without a radar id or platform position";
    const char *bad_scan = "an mti.scan message without a radar id, times in order or a sector";
    const char *bad_hit = "an MTI hit without a valid position, time, azimuth or radial velocity";
    const char *bad_bcis = "a BCIS reply without a valid position or time";
    // Scan 0 of radar 1 in progress with one hit.
    s_hit_t a = {1, 1, 5000, 0, 0, 0, 0};
    s_mti (f, 1, 0, 1, &a, 1);
    // mti: no platform, no radar id, a platform not finite (all of scan 1:
    // not one of them closes scan 0).
    Cgs__MtiHit h = CGS__MTI_HIT__INIT;
    Cgs__Enu hpos = CGS__ENU__INIT, pl = CGS__ENU__INIT;
    hpos.east_m = -5000;
    h.position = &hpos;
    h.sim_time_s = 11;
    Cgs__MtiHit *hp = &h;
    Cgs__Mti m = CGS__MTI__INIT;
    m.uav_id = 1;
    m.scan_number = 1;
    m.n_hits = 1;
    m.hits = &hp;
    s_send (f, "mti", &m.base, 11);
    assert_int_equal (f->nbad, 1);
    assert_string_equal (f->bad[0], bad_mti);
    m.platform_position = &pl;
    m.uav_id = 0;
    s_send (f, "mti", &m.base, 11);
    m.uav_id = 1;
    pl.north_m = NAN;
    s_send (f, "mti", &m.base, 11);
    pl.north_m = 0;
    pl.up_m = INFINITY;
    s_send (f, "mti", &m.base, 11);
    assert_int_equal (f->nbad, 4);
    for (size_t i = 0; i < 4; i++)
        assert_string_equal (f->bad[i], bad_mti);
    // mti.scan: times not finite or out of order, no radar id, no sector.
    Cgs__MtiScan s = CGS__MTI_SCAN__INIT;
    s.uav_id = 1;
    s.scan_number = 0;
    s.full_revolution = true;
    s.scan_start_s = NAN;
    s.scan_end_s = 10;
    s_send (f, "mti.scan", &s.base, 10);
    s.scan_start_s = 0;
    s.scan_end_s = INFINITY;
    s_send (f, "mti.scan", &s.base, 10);
    s.scan_end_s = -1;
    s_send (f, "mti.scan", &s.base, 10);
    s.scan_end_s = 10;
    s.uav_id = 0;
    s_send (f, "mti.scan", &s.base, 10);
    s.uav_id = 1;
    s.full_revolution = false; // a sector of width 0
    s.sector_center_deg = 90;
    s.sector_width_deg = 0;
    s_send (f, "mti.scan", &s.base, 10);
    s.sector_width_deg = 400;
    s_send (f, "mti.scan", &s.base, 10);
    s.sector_width_deg = 60;
    s.sector_center_deg = NAN;
    s_send (f, "mti.scan", &s.base, 10);
    s.scan_number = 5; // a bad marker of a later scan closes nothing either
    s_send (f, "mti.scan", &s.base, 10);
    assert_int_equal (f->nbad, 12);
    for (size_t i = 4; i < 12; i++)
        assert_string_equal (f->bad[i], bad_scan);
    // bcis: a reply without a position, one with a time not finite.
    Cgs__BcisReply r1 = CGS__BCIS_REPLY__INIT, r2 = CGS__BCIS_REPLY__INIT;
    Cgs__Enu rpos = CGS__ENU__INIT;
    r1.sim_time_s = 5;
    r2.position = &rpos;
    r2.sim_time_s = NAN;
    Cgs__BcisReply *rp[2] = {&r1, &r2};
    Cgs__Bcis bc = CGS__BCIS__INIT;
    bc.n_replies = 2;
    bc.replies = rp;
    s_send (f, "bcis", &bc.base, 5);
    assert_int_equal (f->nbad, 14);
    assert_string_equal (f->bad[12], bad_bcis);
    assert_string_equal (f->bad[13], bad_bcis);
    // Nothing changed: nothing published, nothing counted, tracks untouched.
    assert_int_equal (f->npubs, 0);
    assert_false (trk_adapter_take_dirty (f->a));
    trk_adapter_stats_t zero = {0};
    assert_memory_equal (trk_adapter_stats (f->a), &zero, sizeof zero);
    assert_int_equal (trk_tracker_count (trk_adapter_tracker (f->a)), 0);
    // Scan 0 is still open with its hit: a hit not finite in it is dropped,
    // the good one beside it kept.
    s_hit_t two[2] = {{2, 2, 0, 5000, 0, 0, 0}, {3, NAN, 0, -5000, 0, 0, 0}};
    s_mti (f, 1, 0, 2, two, 2);
    assert_int_equal (f->nbad, 15);
    assert_string_equal (f->bad[14], bad_hit);
    // A hit time outside its scan (by more than 1 s) is counted when it runs.
    s_hit_t outside = {4, 13, -5000, 0, 0, 0, 0};
    s_mti (f, 1, 0, 3, &outside, 1);
    s_marker (f, 1, 0, 0, 10);
    assert_int_equal (f->npubs, 1);
    const Cgs__TrackBatch *b = s_last_batch (f);
    assert_int_equal (b->scan_number, 0);
    assert_int_equal (b->n_tracks, 2);
    assert_non_null (s_track_of_hit (b, 1));
    assert_non_null (s_track_of_hit (b, 2));
    assert_int_equal (trk_adapter_stats (f->a)->hits, 2);
    assert_int_equal (f->nbad, 16);
    assert_string_equal (f->bad[15], "an MTI hit whose time lies outside its scan");
    assert_int_equal (trk_adapter_stats (f->a)->implicit_scans, 0);
    assert_int_equal (f->nerr, 0);
}

/* A BCIS reply near a confirmed track marks it friendly in the next batch;
 * one far from every track marks nothing. */
static void test_bcis_marks_friendly (void **state)
{
    s_fix_t *f = *state;
    for (uint32_t k = 0; k < 5; k++) {
        s_hit_t h[2] = {s_target (10 * k + 1, 10.0 * k + 1, 5000, 2000, 15, 0),
                        s_target (10 * k + 2, 10.0 * k + 1, -4000, -2000, 0, 12)};
        s_mti (f, 1, k, h[0].t_s, h, 2);
        s_marker (f, 1, k, 10.0 * k, 10.0 * k + 10);
    }
    const Cgs__TrackBatch *b = s_last_batch (f);
    const Cgs__Track *t = s_track_of_hit (b, 41), *u = s_track_of_hit (b, 42);
    assert_non_null (t);
    assert_non_null (u);
    assert_int_equal (t->status, CGS__TRACK_STATUS__TRACK_STATUS_CONFIRMED);
    assert_int_equal (t->identity, CGS__TRACK_IDENTITY__TRACK_IDENTITY_UNKNOWN);
    uint32_t friend_id = t->track_id, other_id = u->track_id;
    trk_adapter_take_dirty (f->a);
    s_bcis (f, 77, 46, 5000 + 15 * 46.0, 2000);
    assert_int_equal (trk_adapter_stats (f->a)->bcis_marks, 1);
    assert_true (trk_adapter_take_dirty (f->a));
    s_bcis (f, 78, 46, 20000, 20000); // near nothing
    assert_int_equal (trk_adapter_stats (f->a)->bcis_marks, 1);
    assert_false (trk_adapter_take_dirty (f->a));
    // A position fix marks too; a range and azimuth without the interrogator
    // cannot be placed: refused, counted.
    size_t nbad = f->nbad;
    s_bcis_reply (f, 77, 46, 5000 + 15 * 46.0, 2000, true, false);
    assert_int_equal (trk_adapter_stats (f->a)->bcis_marks, 2);
    s_bcis_reply (f, 77, 46, 5000 + 15 * 46.0, 2000, false, false);
    assert_int_equal (trk_adapter_stats (f->a)->bcis_marks, 2);
    assert_int_equal (f->nbad, nbad + 1);
    assert_string_equal (f->bad[nbad],
                         "a BCIS reply without a valid range, azimuth or interrogator");
    trk_adapter_take_dirty (f->a);
    size_t pubs = f->npubs;
    s_hit_t h[2] = {s_target (51, 51, 5000, 2000, 15, 0), s_target (52, 51, -4000, -2000, 0, 12)};
    s_mti (f, 1, 5, 51, h, 2);
    s_marker (f, 1, 5, 50, 60);
    assert_int_equal (f->npubs, pubs + 1);
    b = s_last_batch (f);
    t = s_track_of_hit (b, 51);
    u = s_track_of_hit (b, 52);
    assert_int_equal (t->track_id, friend_id);
    assert_int_equal (t->identity, CGS__TRACK_IDENTITY__TRACK_IDENTITY_FRIENDLY);
    assert_int_equal (t->friendly_id, 77);
    assert_int_equal (u->track_id, other_id);
    assert_int_equal (u->identity, CGS__TRACK_IDENTITY__TRACK_IDENTITY_UNKNOWN);
    assert_int_equal (u->friendly_id, 0);
    assert_int_equal (f->nbad, 1); // the reply refused above
}

/* More than 200 tracks of a radar go in several batches, numbered; a scan
 * with no tracks still gives one (empty) batch. */
static void test_batches_of_200 (void **state)
{
    s_fix_t *f = *state;
    static s_hit_t hits[450];
    for (uint32_t i = 0; i < 450; i++)
        hits[i] =
            (s_hit_t){i + 1, 5, -29000.0 + 2000 * (i % 30), -15000.0 + 2000 * (i / 30), 0, 0, 0};
    s_mti (f, 3, 7, 5, hits, 450);
    s_marker (f, 3, 7, 0, 10);
    assert_int_equal (f->npubs, 3);
    static bool seen[451];
    size_t sizes[3] = {200, 200, 50}, total = 0;
    for (size_t k = 0; k < 3; k++) {
        const Cgs__TrackBatch *b = s_batch (f, k);
        assert_true (f->pubs[k].t_s == 10);
        assert_int_equal (b->uav_id, 3);
        assert_int_equal (b->scan_number, 7);
        assert_int_equal (b->batch_index, k);
        assert_int_equal (b->batch_count, 3);
        assert_int_equal (b->n_tracks, sizes[k]);
        for (size_t i = 0; i < b->n_tracks; i++) {
            const Cgs__Track *t = b->tracks[i];
            assert_int_equal (t->n_history, 1);
            uint32_t hit = t->history[0]->hit_id;
            assert_true (hit >= 1 && hit <= 450);
            assert_false (seen[hit]);
            seen[hit] = true;
            total++;
        }
    }
    assert_int_equal (total, 450);
    // Radar 4's scan with no hits and no tracks.
    s_marker (f, 4, 0, 0, 10);
    assert_int_equal (f->npubs, 4);
    const Cgs__TrackBatch *b = s_batch (f, 3);
    assert_int_equal (b->uav_id, 4);
    assert_int_equal (b->batch_index, 0);
    assert_int_equal (b->batch_count, 1);
    assert_int_equal (b->n_tracks, 0);
}

/* A track deleted in a scan is published once, with status DELETED, and
 * no more after. */
static void test_deleted_published_once (void **state)
{
    s_fix_t *f = *state;
    s_hit_t h = {1, 1, 5000, 0, 0, 0, 0};
    s_mti (f, 1, 0, 1, &h, 1);
    s_marker (f, 1, 0, 0, 10);
    uint32_t id = s_track_of_hit (s_last_batch (f), 1)->track_id;
    for (uint32_t k = 1; k < 6; k++)
        s_marker (f, 1, k, 10.0 * k, 10.0 * k + 10);
    assert_int_equal (f->npubs, 6);
    size_t deleted = 0, after = 0;
    for (size_t i = 0; i < f->npubs; i++) {
        const Cgs__TrackBatch *b = s_batch (f, i);
        for (size_t j = 0; j < b->n_tracks; j++) {
            if (b->tracks[j]->track_id != id)
                continue;
            if (deleted)
                after++;
            if (b->tracks[j]->status == CGS__TRACK_STATUS__TRACK_STATUS_DELETED) {
                deleted++;
                assert_int_equal (b->tracks[j]->n_history, 1);
            }
        }
    }
    assert_int_equal (deleted, 1);
    assert_int_equal (after, 0);
    assert_int_equal (trk_adapter_stats (f->a)->deleted, 1);
    assert_int_equal (trk_adapter_stats (f->a)->born, 1);
    assert_int_equal (s_last_batch (f)->n_tracks, 0);
    assert_int_equal (trk_tracker_count (trk_adapter_tracker (f->a)), 0);
}

/* A target that turns 90 degrees left (on an arc of 30 s) gives
 * `track.turn`: flagged, then complete with about -90 degrees, at the
 * scan's end time, with the hit's height. */
static void test_turn_published (void **state)
{
    s_fix_t *f = *state;
    // East at 15 m/s from (-6000, 3000) until t = 91, then a left turn on
    // an arc of 30 s (radius 286 m), then north.
    const double r = 15 * 30 / (S_PI / 2), e1 = -6000 + 15 * 91.0;
    for (uint32_t k = 0; k < 16; k++) {
        double t = 10.0 * k + 1, a = fmin ((t - 91) / 30, 1) * S_PI / 2;
        s_hit_t h = k <= 9    ? s_target (k + 1, t, -6000, 3000, 15, 0)
                    : t < 121 ? (s_hit_t){k + 1,
                                          t,
                                          e1 + r * sin (a),
                                          3000 + r * (1 - cos (a)),
                                          0,
                                          15 * cos (a),
                                          15 * sin (a)}
                              : (s_hit_t){k + 1, t, e1 + r, 3000 + r + 15 * (t - 121), 0, 0, 15};
        h.up_m = 120;
        s_mti (f, 1, k, t, &h, 1);
        s_marker (f, 1, k, 10.0 * k, 10.0 * k + 10);
    }
    const Cgs__Track *t = s_track_of_hit (s_last_batch (f), 16);
    assert_non_null (t);
    assert_int_equal (t->status, CGS__TRACK_STATUS__TRACK_STATUS_CONFIRMED);
    // The IMM tracker's word on it: its models, existence and the Pd the
    // radar had of it (clear of the notch, a few km away: near pd), and no
    // continuation.
    assert_int_equal (t->n_mode_probabilities, 3);
    assert_true (fabs (t->mode_probabilities[0] + t->mode_probabilities[1] +
                       t->mode_probabilities[2] - 1) < 1e-9);
    assert_true (t->mode_probabilities[2] < 0.1); // not stopped
    assert_true (t->existence_probability > 0.9 && t->existence_probability <= 1);
    assert_true (t->detection_probability > 0.8 && t->detection_probability < 1);
    assert_int_equal (t->continues, 0);
    size_t turns = 0, flagged = 0, complete = 0;
    for (size_t i = 0; i < f->npubs; i++) {
        if (strcmp (f->pubs[i].topic, "track.turn") != 0)
            continue;
        turns++;
        const Cgs__TrackTurn *m = (const Cgs__TrackTurn *)f->pubs[i].msg;
        assert_int_equal (m->track_id, t->track_id);
        assert_int_equal (m->uav_id, 1);
        assert_true (m->scan_number >= 10 && m->scan_number <= 15);
        // Published after its scan's batch, at the scan's end.
        size_t j = i;
        while (j > 0 && strcmp (f->pubs[j - 1].topic, "track.turn") == 0)
            j--;
        assert_true (j > 0);
        assert_int_equal (s_batch (f, j - 1)->scan_number, m->scan_number);
        assert_true (f->pubs[i].t_s == 10.0 * m->scan_number + 10);
        assert_true (m->sim_time_s == 10.0 * m->scan_number + 1);
        assert_non_null (m->position);
        assert_true (m->position->up_m == 120);
        assert_non_null (m->velocity_before);
        assert_non_null (m->velocity_after);
        assert_true (m->velocity_before->east_mps > 10);
        if (m->complete) {
            complete++;
            print_message ("# turn complete at scan %u: %.1f deg\n", m->scan_number,
                           m->turn_angle_deg);
            assert_true (m->turn_angle_deg < -60 && m->turn_angle_deg > -120);
        } else {
            flagged++;
            assert_true (m->turn_angle_deg < 0);
        }
    }
    assert_true (flagged >= 1);
    assert_true (complete >= 1);
    assert_int_equal (trk_adapter_stats (f->a)->turns, turns);
}

/* Topics it takes; other topics are ignored. */
static void test_topics (void **state)
{
    s_fix_t *f = *state;
    assert_string_equal (trk_adapter_topics[0], "mti");
    assert_string_equal (trk_adapter_topics[1], "mti.scan");
    assert_string_equal (trk_adapter_topics[2], "bcis");
    assert_null (trk_adapter_topics[3]);
    for (size_t i = 0; trk_adapter_topics[i]; i++)
        assert_non_null (cgs_topics_find (trk_adapter_topics[i]));
    Cgs__Uav u = CGS__UAV__INIT;
    trk_adapter_on_message (f->a, "uav", &u.base, NULL);
    assert_int_equal (f->npubs + f->nbad + f->nlogs + f->nerr, 0);
    // A message without a header: no time is noted, the hits are taken.
    s_hit_t h = {1, 1, 5000, 0, 0, 0, 0};
    Cgs__MtiHit mh = CGS__MTI_HIT__INIT;
    Cgs__Enu pos = CGS__ENU__INIT, pl = CGS__ENU__INIT;
    pos.east_m = h.e_m;
    mh.position = &pos;
    mh.sim_time_s = h.t_s;
    Cgs__MtiHit *hp = &mh;
    Cgs__Mti m = CGS__MTI__INIT;
    m.uav_id = 1;
    m.platform_position = &pl;
    m.n_hits = 1;
    m.hits = &hp;
    trk_adapter_on_message (f->a, "mti", &m.base, NULL);
    s_marker (f, 1, 0, 0, 10);
    assert_int_equal (s_last_batch (f)->n_tracks, 1);
}

/* A fixed scan_period_s the radar's revisit disagrees with is refused at
 * the radar's second scan (its first may be partial: a radar that starts
 * mid-revolution), with the file and both periods named, once; one that
 * agrees (10 s against 10 s) is not. */
static void test_fixed_period_refused (void **state)
{
    s_fix_t *f = *state;
    trk_adapter_destroy (&f->a);
    trk_params_t p;
    trk_params_defaults (&p);
    p.filter.mode = TRK_FILTER_PAPER;
    p.filter.dt_auto = false;
    cgs_port_t port = {
        .arg = f, .publish = s_publish, .log = s_log, .bad_input = s_bad_input, .error = s_error};
    f->a = trk_adapter_new (&p, &port);
    assert_non_null (f->a);
    trk_adapter_set_params_path (f->a, "t.ini");
    s_marker (f, 2, 1, 7, 10);  // radar 2 started mid-revolution: a partial scan...
    s_marker (f, 2, 2, 10, 20); // ... then it turns in 10 s: agrees
    assert_int_equal (f->nerr, 0);
    s_marker (f, 1, 1, 0, 5);
    assert_int_equal (f->nerr, 0); // its first scan is not taken
    s_marker (f, 1, 2, 5, 10);     // radar 1 in 5 s: refused
    assert_int_equal (f->nerr, 1);
    assert_string_equal (f->err[0],
                         "t.ini: [filter] scan_period_s = 10 refused: radar 1 revisits a cell "
                         "every 5.00 s (its scan 2, 5.00 to 10.00 s); the paper's gains follow "
                         "each update's own interval (scan_period_s = auto) from now on");
    assert_true (trk_tracker_params (trk_adapter_tracker (f->a))->filter.dt_auto);
    // The nominal gains are the radar's revisit's: r = 4 σ_meas / (σ_mod dt²).
    assert_true (
        fabs (trk_tracker_gains (trk_adapter_tracker (f->a))[0].r - 4 * 25 / (0.2 * 5 * 5)) < 1e-9);
    s_marker (f, 1, 3, 10, 15);
    assert_int_equal (f->nerr, 1);
}

int main (void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup_teardown (test_scan_held_until_marker, s_setup, s_teardown),
        cmocka_unit_test_setup_teardown (test_two_radars_apart, s_setup, s_teardown),
        cmocka_unit_test_setup_teardown (test_scan_closed_without_marker, s_setup, s_teardown),
        cmocka_unit_test_setup_teardown (test_stale_hits_ignored, s_setup, s_teardown),
        cmocka_unit_test_setup_teardown (test_time_went_back, s_setup, s_teardown),
        cmocka_unit_test_setup_teardown (test_malformed_input, s_setup, s_teardown),
        cmocka_unit_test_setup_teardown (test_bcis_marks_friendly, s_setup, s_teardown),
        cmocka_unit_test_setup_teardown (test_batches_of_200, s_setup, s_teardown),
        cmocka_unit_test_setup_teardown (test_deleted_published_once, s_setup, s_teardown),
        cmocka_unit_test_setup_teardown (test_turn_published, s_setup, s_teardown),
        cmocka_unit_test_setup_teardown (test_topics, s_setup, s_teardown),
        cmocka_unit_test_setup_teardown (test_fixed_period_refused, s_setup, s_teardown),
    };
    return cmocka_run_group_tests (tests, NULL, NULL);
}
