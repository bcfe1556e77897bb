/* test_gd_adapter — guidanced's adapter (gd_adapter) driven as the daemon
 * and the lockstep engine drive it: hand-built decoded `uav`, `track` and
 * `track.turn` messages and operator commands in; every `intercept` out
 * through a port that encodes and decodes it again (so what goes out is a
 * complete, valid message of its topic's type), and the port's log lines,
 * bad input and errors recorded.
 *
 * The scene: flat ground 100 m above the datum; uav1 (entity 1) at the
 * origin flying east at 38 m/s, 1200 m above the ground, sensor depressed
 * 45° with a 10° × 7.5° field of view; track 7, an unknown vehicle 6 km
 * east driving west at 10 m/s; track 8, an unknown one at (−5000, 4000);
 * track 9, a friendly one at (6000, 400). A second scenario has two UAVs,
 * a third an operator script line `designate = unknown nearest 6000 500 at
 * 50`.
 *
 * Cases:
 *   - designate by track id, by point (the nearest within the pick radius;
 *     refused beyond it, with the text), with neither; unknown tracks and
 *     UAVs, and a UAV id 0 with several UAVs;
 *   - cancel, footprint scale, intercept method and their refusals; ping,
 *     unsupported commands; SET_ALTITUDE and SET_SPEED are the caller's (1);
 *   - tasks: a designation gives a TASK_ROUTE for the right UAV under a new
 *     number, stable across calls until answered; OK marks it delivered;
 *     a BAD_REQUEST not a duplicate sends it again under a new number; a
 *     refusal is reported and marked delivered; a cancel gives a LOITER;
 *     forwarded commands take numbers of the same sequence; two UAVs;
 *   - the track table: deleted tracks leave it, unusable tracks, batches and
 *     turn events are bad input;
 *   - the operator script: waits (logged once) for a qualifying track,
 *     designates the nearest unknown one at its time and makes the state
 *     dirty; skipped, with a notice, after an operator's designation;
 *   - state: save → restore into a new adapter gives the same bytes and the
 *     same pending numbers; a UAV not in the scenario is reported and
 *     skipped; damaged states, another version's and the text format of
 *     before cgs_ckpt are refused with cgs_ckpt's errors and leave the
 *     adapter idle;
 *   - `intercept` messages: one per UAV after each uav message and track
 *     batch, the footprint once the UAV is heard with a valid sensor during
 *     an intercept, route points at the terrain's height, the phase's
 *     notices. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "cgs_ckpt.h"
#include "cgs_msg.h"
#include "cgs_scenario.h"
#include "cgs_topics.h"
#include "gd_adapter.h"
#include "gd_checkpoint.h"
#include "port_check.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <syslog.h>

#include "test_util.h"

#define S_MAX_MSGS 512
#define S_MAX_LOGS 256

#define assert_has(str, sub)                                                                       \
    do {                                                                                           \
        const char *s_ = (str);                                                                    \
        if (!s_ || !strstr (s_, (sub)))                                                            \
            fail_msg ("%s = \"%s\" does not contain \"%s\"", #str, s_ ? s_ : "(null)", (sub));     \
    } while (0)

/* ---- the test port ------------------------------------------------------------------------ */

typedef struct {
    size_t n;
    char *topics[S_MAX_MSGS];
    ProtobufCMessage *msgs[S_MAX_MSGS];
    double times[S_MAX_MSGS];
    size_t nlogs;
    int priorities[S_MAX_LOGS];
    char logs[S_MAX_LOGS][512];
    size_t bad, errors;
    char last_bad[256], last_error[512];
} s_seen_t;

static int s_publish (void *arg, const char *topic, ProtobufCMessage *msg, double t)
{
    s_seen_t *s = arg;
    ProtobufCMessage *back = port_check_roundtrip (topic, msg);
    assert_true (s->n < S_MAX_MSGS);
    s->topics[s->n] = strdup (topic);
    s->msgs[s->n] = back;
    s->times[s->n] = t;
    s->n++;
    return 0;
}

static void s_log (void *arg, int priority, const char *line)
{
    s_seen_t *s = arg;
    assert_true (s->nlogs < S_MAX_LOGS);
    s->priorities[s->nlogs] = priority;
    snprintf (s->logs[s->nlogs], sizeof s->logs[0], "%s", line);
    s->nlogs++;
}

static void s_bad (void *arg, const char *what)
{
    s_seen_t *s = arg;
    s->bad++;
    snprintf (s->last_bad, sizeof s->last_bad, "%s", what);
}

static void s_error (void *arg, const char *why)
{
    s_seen_t *s = arg;
    s->errors++;
    snprintf (s->last_error, sizeof s->last_error, "%s", why);
}

static void s_clear (s_seen_t *s)
{
    for (size_t i = 0; i < s->n; i++) {
        free (s->topics[i]);
        cgs_msg_free (&s->msgs[i]);
    }
    memset (s, 0, sizeof *s);
}

/* How many log lines at priority containing text. */
static size_t s_logged (const s_seen_t *s, int priority, const char *text)
{
    size_t n = 0;
    for (size_t i = 0; i < s->nlogs; i++)
        n += s->priorities[i] == priority && strstr (s->logs[i], text) != NULL;
    return n;
}

#define assert_logged(seen, priority, text)                                                        \
    do {                                                                                           \
        if (s_logged ((seen), (priority), (text)) == 0)                                            \
            fail_msg ("no log line at priority %d containing \"%s\"", (priority), (text));         \
    } while (0)

/* The latest `intercept` published for UAV uav_id, or NULL. */
static const Cgs__Intercept *s_last_intercept (const s_seen_t *s, uint32_t uav_id)
{
    for (size_t i = s->n; i-- > 0;) {
        if (strcmp (s->topics[i], "intercept") != 0)
            continue;
        const Cgs__Intercept *m = (const Cgs__Intercept *)s->msgs[i];
        if (m->uav_id == uav_id)
            return m;
    }
    return NULL;
}

static size_t s_count (const s_seen_t *s, const char *topic)
{
    size_t n = 0;
    for (size_t i = 0; i < s->n; i++)
        n += strcmp (s->topics[i], topic) == 0;
    return n;
}

/* ---- the scene ---------------------------------------------------------------------------- */

#define S_TERRAIN                                                                                  \
    "[terrain]\nsize_m = 20000\nresolution_m = 100\nrelief_m = 0\nbase_height_m = 100\n"
#define S_UAV1                                                                                     \
    "[uav uav1]\nposition = 0 0\naltitude_agl_m = 1200\nairspeed_mps = 38\nheading_deg = 90\n"
#define S_UAV2 "[uav uav2]\nposition = 0 3000\n"

static const char *const s_one = S_TERRAIN S_UAV1;
static const char *const s_two = S_TERRAIN S_UAV1 S_UAV2;
static const char *const s_script =
    S_TERRAIN S_UAV1 "[operator]\ndesignate = unknown nearest 6000 500 at 50\n";

typedef struct {
    cgs_geo_t *frame;
    cgs_scenario_t *scenario;
    cgs_terrain_t *terrain;
    gd_params_t params;
    s_seen_t seen;
    cgs_port_t port;
    gd_adapter_t *gd;
} s_fx_t;

static s_fx_t *s_fx_new (const char *text)
{
    s_fx_t *fx = calloc (1, sizeof *fx);
    assert_non_null (fx);
    char err[512] = "";
    fx->frame = cgs_geo_new (35.96, -121.23, 0);
    assert_non_null (fx->frame);
    if (cgs_scenario_load_string ("t.ini", text, fx->frame, 1, &fx->scenario, err, sizeof err) <
            0 ||
        cgs_scenario_terrain (fx->scenario, fx->frame, &fx->terrain, err, sizeof err) < 0)
        fail_msg ("%s", err);
    gd_params_defaults (&fx->params);
    fx->port = (cgs_port_t){&fx->seen, s_publish, s_log, s_bad, s_error};
    bool too_many = true;
    fx->gd = gd_adapter_new (&fx->params, fx->scenario, fx->terrain, &fx->port, &too_many);
    assert_non_null (fx->gd);
    assert_false (too_many);
    gd_adapter_set_client_id (fx->gd, "guidanced@1.000001");
    return fx;
}

static void s_fx_free (s_fx_t **fx_p)
{
    s_fx_t *fx = *fx_p;
    gd_adapter_destroy (&fx->gd);
    assert_null (fx->gd);
    gd_adapter_destroy (&fx->gd); // again: accepts NULL
    s_clear (&fx->seen);
    cgs_terrain_destroy (&fx->terrain);
    cgs_scenario_destroy (&fx->scenario);
    cgs_geo_destroy (&fx->frame);
    free (fx);
    *fx_p = NULL;
}

static double s_ground (const s_fx_t *fx, double e, double n)
{
    return cgs_terrain_height_clamped (fx->terrain, e, n);
}

/* UAV entity id heard at time t at (e, n), flying east, with its sensor's
 * depression (45 for a valid one). */
static void s_uav_msg (s_fx_t *fx, uint32_t id, double t, double e, double n, double depression)
{
    Cgs__Header hdr = CGS__HEADER__INIT;
    hdr.sim_time_s = t;
    Cgs__Enu p = CGS__ENU__INIT;
    p.east_m = e;
    p.north_m = n;
    p.up_m = s_ground (fx, e, n) + 1200;
    Cgs__ImagingSensor sn = CGS__IMAGING_SENSOR__INIT;
    sn.depression_deg = depression;
    sn.hfov_deg = 10;
    sn.vfov_deg = 7.5;
    Cgs__Uav m = CGS__UAV__INIT;
    m.entity_id = id;
    m.position = &p;
    m.heading_deg = 90;
    m.ground_speed_mps = 38;
    m.airspeed_mps = 38;
    m.commanded_airspeed_mps = 38;
    m.altitude_agl_m = 1200;
    m.bank_limit_deg = 30;
    m.sensor = &sn;
    gd_adapter_on_message (fx->gd, "uav", &m.base, &hdr);
}

typedef struct {
    uint32_t id;
    Cgs__TrackStatus status;
    bool friendly;
    double e, n, ve, vn;
} s_trk_t;

/* A `track` batch at time t (t NaN: a header without a time), of radar 1.
 * With hid, each track i has a history of two hits: ids hid[i] (scan
 * last − 3, 30 s before) and hid[i] + 1000 (scan last, its newest). */
static void s_tracks_hits (s_fx_t *fx, double t, const s_trk_t *tr, size_t count,
                           const uint32_t *hid, uint32_t last)
{
    Cgs__Header hdr = CGS__HEADER__INIT;
    hdr.sim_time_s = t;
    Cgs__Track m[8], *mp[8];
    Cgs__Enu pos[8], hp[8][2];
    Cgs__EnuVelocity vel[8];
    Cgs__TrackHistoryPoint h[8][2], *hpp[8][2];
    assert_true (count <= 8);
    for (size_t i = 0; i < count; i++) {
        cgs__track__init (&m[i]);
        cgs__enu__init (&pos[i]);
        cgs__enu_velocity__init (&vel[i]);
        pos[i].east_m = tr[i].e;
        pos[i].north_m = tr[i].n;
        pos[i].up_m = 100;
        vel[i].east_mps = tr[i].ve;
        vel[i].north_mps = tr[i].vn;
        m[i].track_id = tr[i].id;
        m[i].uav_id = 1;
        m[i].status = tr[i].status;
        m[i].identity = tr[i].friendly ? CGS__TRACK_IDENTITY__TRACK_IDENTITY_FRIENDLY
                                       : CGS__TRACK_IDENTITY__TRACK_IDENTITY_UNKNOWN;
        m[i].position = &pos[i];
        m[i].velocity = &vel[i];
        m[i].hit_count = 10;
        m[i].last_hit_time_s = t;
        mp[i] = &m[i];
        if (!hid)
            continue;
        m[i].last_scan_number = last;
        for (int k = 0; k < 2; k++) {
            cgs__track_history_point__init (&h[i][k]);
            cgs__enu__init (&hp[i][k]);
            hp[i][k].east_m = tr[i].e - (k ? 0 : 30 * tr[i].ve);
            hp[i][k].north_m = tr[i].n - (k ? 0 : 30 * tr[i].vn);
            h[i][k].position = &hp[i][k];
            h[i][k].sim_time_s = t - (k ? 0 : 30);
            h[i][k].scan_number = k ? last : last - 3;
            h[i][k].hit_id = k ? hid[i] + 1000 : hid[i];
            hpp[i][k] = &h[i][k];
        }
        m[i].n_history = 2;
        m[i].history = hpp[i];
    }
    Cgs__TrackBatch b = CGS__TRACK_BATCH__INIT;
    b.uav_id = 1;
    b.n_tracks = count;
    b.tracks = mp;
    b.batch_count = 1;
    gd_adapter_on_message (fx->gd, "track", &b.base, &hdr);
}

static void s_tracks (s_fx_t *fx, double t, const s_trk_t *tr, size_t count)
{
    s_tracks_hits (fx, t, tr, count, NULL, 0);
}

#define S_CONFIRMED CGS__TRACK_STATUS__TRACK_STATUS_CONFIRMED
#define S_DELETED   CGS__TRACK_STATUS__TRACK_STATUS_DELETED

static const s_trk_t s_t7 = {7, S_CONFIRMED, false, 6000, 0, -10, 0};
static const s_trk_t s_t8 = {8, S_CONFIRMED, false, -5000, 4000, 0, 5};
static const s_trk_t s_t9 = {9, S_CONFIRMED, true, 6000, 400, -10, 0};

/* The scene at time t: the UAV(s) heard, then tracks 7 and 8. */
static void s_scene (s_fx_t *fx, double t)
{
    for (size_t i = 0; i < gd_adapter_uav_count (fx->gd); i++)
        s_uav_msg (fx, gd_adapter_uav_id (fx->gd, i), t, 0, 3000.0 * (double)i, 45);
    const s_trk_t tr[2] = {s_t7, s_t8};
    s_tracks (fx, t, tr, 2);
}

/* A command as the command server hands it over (reply OK until judged). */
static int s_command (s_fx_t *fx, Cgs__Command *cmd, Cgs__Reply *reply)
{
    static uint64_t number;
    cmd->client_id = "mscgs@test";
    cmd->command_number = ++number;
    cgs__reply__init (reply);
    reply->status = CGS__REPLY_STATUS__REPLY_STATUS_OK;
    return gd_adapter_command (fx->gd, cmd, reply);
}

static int s_designate_track (s_fx_t *fx, uint32_t uav_id, uint32_t track_id, Cgs__Reply *reply)
{
    Cgs__Designate d = CGS__DESIGNATE__INIT;
    d.uav_id = uav_id;
    d.target_case = CGS__DESIGNATE__TARGET_TRACK_ID;
    d.track_id = track_id;
    Cgs__Command cmd = CGS__COMMAND__INIT;
    cmd.body_case = CGS__COMMAND__BODY_DESIGNATE;
    cmd.designate = &d;
    return s_command (fx, &cmd, reply);
}

static int s_designate_point (s_fx_t *fx, uint32_t uav_id, double e, double n, Cgs__Reply *reply)
{
    Cgs__Enu p = CGS__ENU__INIT;
    p.east_m = e;
    p.north_m = n;
    Cgs__Designate d = CGS__DESIGNATE__INIT;
    d.uav_id = uav_id;
    d.target_case = CGS__DESIGNATE__TARGET_POINT;
    d.point = &p;
    Cgs__Command cmd = CGS__COMMAND__INIT;
    cmd.body_case = CGS__COMMAND__BODY_DESIGNATE;
    cmd.designate = &d;
    return s_command (fx, &cmd, reply);
}

static int s_cancel (s_fx_t *fx, uint32_t uav_id, Cgs__Reply *reply)
{
    Cgs__Cancel c = CGS__CANCEL__INIT;
    c.uav_id = uav_id;
    Cgs__Command cmd = CGS__COMMAND__INIT;
    cmd.body_case = CGS__COMMAND__BODY_CANCEL;
    cmd.cancel = &c;
    return s_command (fx, &cmd, reply);
}

static void s_assert_ok (const Cgs__Reply *reply, const char *detail)
{
    assert_int_equal (reply->status, CGS__REPLY_STATUS__REPLY_STATUS_OK);
    assert_has (reply->detail, detail);
}

static void s_assert_refused (const Cgs__Reply *reply, const char *error)
{
    assert_int_equal (reply->status, CGS__REPLY_STATUS__REPLY_STATUS_ERROR);
    if (strcmp (reply->error, error) != 0)
        fail_msg ("error \"%s\", expected \"%s\"", reply->error, error);
}

static gd_status_t s_status (const s_fx_t *fx, size_t i)
{
    gd_status_t st;
    gd_intercept_status (gd_adapter_intercept (fx->gd, i), &st);
    return st;
}

/* The next task due, from UAV 0 on; fails when there is none. */
static gd_adapter_task_t s_next (s_fx_t *fx)
{
    size_t cursor = 0;
    gd_adapter_task_t task;
    if (!gd_adapter_next_task (fx->gd, &cursor, &task))
        fail_msg ("no task due");
    assert_int_equal (cursor, task.uav + 1);
    return task;
}

static bool s_none_due (s_fx_t *fx)
{
    size_t cursor = 0;
    gd_adapter_task_t task;
    return !gd_adapter_next_task (fx->gd, &cursor, &task);
}

static void s_answer (s_fx_t *fx, const gd_adapter_task_t *task, Cgs__ReplyStatus status,
                      bool duplicate, const char *error)
{
    Cgs__Reply r = CGS__REPLY__INIT;
    r.status = status;
    r.duplicate = duplicate;
    if (error)
        r.error = (char *)error;
    gd_adapter_task_answered (fx->gd, task, &r);
}

/* ---- commands ----------------------------------------------------------------------------- */

static void test_designate (void **state)
{
    (void)state;
    s_fx_t *fx = s_fx_new (s_one);
    assert_false (gd_adapter_heard_tracks (fx->gd));
    s_scene (fx, 10);
    assert_true (gd_adapter_heard_tracks (fx->gd));
    assert_int_equal (gd_adapter_track_count (fx->gd), 2);
    Cgs__Reply r;

    // By track id: planned at once (the UAV is heard).
    assert_int_equal (s_designate_track (fx, 1, 7, &r), 0);
    s_assert_ok (&r, "uav1: designated track 7; TO_");
    assert_has (r.detail, "waypoint (");
    assert_has (r.detail, "t_pred ");
    assert_int_equal (s_status (fx, 0).track_id, 7);
    assert_logged (&fx->seen, LOG_INFO, "uav1: designated track 7; ");
    assert_logged (&fx->seen, LOG_INFO, "(from mscgs@test #");
    assert_true (gd_adapter_take_dirty (fx->gd));
    assert_false (gd_adapter_take_dirty (fx->gd));

    // By id 0: the only UAV.
    assert_int_equal (s_designate_track (fx, 0, 8, &r), 0);
    s_assert_ok (&r, "uav1: designated track 8 (pre-empts track 7)");

    // By point: the nearest track within the pick radius.
    assert_int_equal (s_designate_point (fx, 1, 5900, 100, &r), 0);
    s_assert_ok (&r, "uav1: designated track 7 (pre-empts track 8)");
    assert_int_equal (s_status (fx, 0).track_id, 7);
    assert_true (gd_adapter_take_dirty (fx->gd));

    // Refusals, with their texts; the intercept stays as it was.
    assert_int_equal (s_designate_point (fx, 1, 0, -9000, &r), 0);
    char want[256];
    snprintf (want, sizeof want,
              "no track's newest hit within 2000 m of (0, -9000): the nearest is track 7, %.0f m "
              "away",
              hypot (6000, 9000));
    s_assert_refused (&r, want);
    assert_int_equal (s_designate_track (fx, 1, 99, &r), 0);
    s_assert_refused (&r, "no track 99 (2 live tracks known)");
    assert_int_equal (s_designate_track (fx, 42, 7, &r), 0);
    s_assert_refused (&r, "no UAV with entity id 42");
    Cgs__Designate d = CGS__DESIGNATE__INIT;
    d.uav_id = 1;
    Cgs__Command cmd = CGS__COMMAND__INIT;
    cmd.body_case = CGS__COMMAND__BODY_DESIGNATE;
    cmd.designate = &d;
    assert_int_equal (s_command (fx, &cmd, &r), 0);
    s_assert_refused (&r, "designate needs a track id, a point or a hit");
    Cgs__Enu far = CGS__ENU__INIT;
    far.east_m = NAN;
    d.target_case = CGS__DESIGNATE__TARGET_POINT;
    d.point = &far;
    assert_int_equal (s_command (fx, &cmd, &r), 0);
    s_assert_refused (&r, "designate needs a track id, a point or a hit");
    assert_int_equal (s_status (fx, 0).track_id, 7);
    assert_int_equal (s_status (fx, 0).designation_number, 3);
    assert_false (gd_adapter_take_dirty (fx->gd)); // refusals changed nothing
    s_fx_free (&fx);
}

static int s_designate_hit (s_fx_t *fx, uint32_t radar, uint32_t hit, Cgs__Reply *reply)
{
    Cgs__HitRef h = CGS__HIT_REF__INIT;
    h.radar_uav_id = radar;
    h.hit_id = hit;
    Cgs__Designate d = CGS__DESIGNATE__INIT;
    d.uav_id = 1;
    d.target_case = CGS__DESIGNATE__TARGET_HIT;
    d.hit = &h;
    Cgs__Command cmd = CGS__COMMAND__INIT;
    cmd.body_case = CGS__COMMAND__BODY_DESIGNATE;
    cmd.designate = &d;
    return s_command (fx, &cmd, reply);
}

/* The map's click: the track that took the clicked hit, exactly, even with
 * another track's newest hit nearer the click (tracks 7 and 9 are 400 m
 * apart, as in a column); refused, with the reason, for a hit no track took
 * (a false alarm), a friendly track's, a tentative track's, a stale hit (3
 * scans before the track's newest) and another radar's. */
static void test_designate_by_hit (void **state)
{
    (void)state;
    s_fx_t *fx = s_fx_new (s_one);
    s_uav_msg (fx, 1, 10, 0, 0, 45);
    const s_trk_t tent = {11, CGS__TRACK_STATUS__TRACK_STATUS_TENTATIVE, false, 0, 6000, 5, 0};
    const s_trk_t tr[4] = {s_t7, s_t8, s_t9, tent};
    const uint32_t hid[4] = {70, 80, 90, 110};
    s_tracks_hits (fx, 10, tr, 4, hid, 20);
    Cgs__Reply r;
    assert_int_equal (s_designate_hit (fx, 1, 1070, &r), 0);
    s_assert_ok (&r, "uav1: designated track 7; TO_");
    assert_int_equal (s_status (fx, 0).track_id, 7);
    assert_int_equal (s_designate_hit (fx, 0, 1080, &r), 0); // any radar
    s_assert_ok (&r, "uav1: designated track 8 (pre-empts track 7)");
    assert_int_equal (s_designate_hit (fx, 1, 4242, &r), 0);
    s_assert_refused (&r, "hit 4242 is in no track: a false alarm, or a hit no track has taken");
    assert_int_equal (s_designate_hit (fx, 1, 1090, &r), 0);
    s_assert_refused (&r, "hit 1090 is track 9's, which BCIS says is friendly");
    assert_int_equal (s_designate_hit (fx, 1, 1110, &r), 0);
    s_assert_refused (&r, "hit 1110 is track 11's, which is tentative (not yet confirmed)");
    assert_int_equal (s_designate_hit (fx, 1, 70, &r), 0);
    s_assert_refused (&r, "hit 70 is track 7's of scan 17, 3 scans before its newest: click its "
                          "current (yellow) hit");
    assert_int_equal (s_designate_hit (fx, 2, 1070, &r), 0);
    s_assert_refused (&r, "hit 1070 is in no track: a false alarm, or a hit no track has taken");
    assert_int_equal (s_status (fx, 0).track_id, 8); // the refusals changed nothing
    s_fx_free (&fx);
}

/* uavsim resumes from its saved state: a UAV update more than a second
 * older than the latest heard is time going back, said once, and the
 * intercepts take back what they heard since (gd_intercept_time_back:
 * test_gd_intercept); the ordinary jitter of a few tenths is not. */
static void test_time_back (void **state)
{
    (void)state;
    s_fx_t *fx = s_fx_new (s_one);
    s_scene (fx, 100);
    Cgs__Reply r;
    assert_int_equal (s_designate_track (fx, 1, 7, &r), 0);
    s_uav_msg (fx, 1, 99.5, 0, 0, 45);
    assert_int_equal (s_logged (&fx->seen, LOG_NOTICE, "went back"), 0);
    s_uav_msg (fx, 1, 60, 0, 0, 45);
    assert_logged (&fx->seen, LOG_NOTICE,
                   "simulation time went back from 100.00 to 60.00 s: the intercepts take back "
                   "what they heard since");
    assert_true (s_status (fx, 0).has_plan); // made again for the UAV where it is now
    s_uav_msg (fx, 1, 60.5, 0, 0, 45);
    assert_int_equal (s_logged (&fx->seen, LOG_NOTICE, "went back"), 1); // once
    s_fx_free (&fx);
}

static void test_designate_no_tracks (void **state)
{
    (void)state;
    s_fx_t *fx = s_fx_new (s_one);
    Cgs__Reply r;
    assert_int_equal (s_designate_point (fx, 1, 0, 0, &r), 0);
    s_assert_refused (&r, "no confirmed track to designate");
    // Not yet heard: planned when it is.
    s_tracks (fx, 5, &s_t7, 1);
    assert_int_equal (s_designate_track (fx, 1, 7, &r), 0);
    s_assert_ok (&r, "uav1: designated track 7; planned when the UAV is heard");
    assert_true (s_none_due (fx));
    s_uav_msg (fx, 1, 6, 0, 0, 45);
    gd_adapter_task_t task = s_next (fx);
    assert_int_equal (task.command->body_case, CGS__COMMAND__BODY_TASK_ROUTE);
    s_fx_free (&fx);
}

static void test_settings (void **state)
{
    (void)state;
    s_fx_t *fx = s_fx_new (s_two);
    s_scene (fx, 10);
    Cgs__Reply r;
    Cgs__Command cmd;

    // Cancel: nothing to cancel, then an intercept cancelled.
    assert_int_equal (s_cancel (fx, 1, &r), 0);
    s_assert_refused (&r, "uav1: no intercept to cancel");
    assert_int_equal (s_cancel (fx, 0, &r), 0);
    s_assert_refused (&r, "no UAV with entity id 0 (give one: the scenario has several)");
    assert_int_equal (s_designate_track (fx, 0, 7, &r), 0);
    s_assert_refused (&r, "no UAV with entity id 0 (give one: the scenario has several)");
    assert_int_equal (s_designate_track (fx, 2, 7, &r), 0);
    s_assert_ok (&r, "uav2: designated track 7");
    assert_int_equal (s_cancel (fx, 2, &r), 0);
    s_assert_ok (&r, "uav2: intercept cancelled; loitering here");
    assert_int_equal (s_status (fx, 1).phase, GD_CANCELLED);
    assert_int_equal (s_status (fx, 0).phase, GD_IDLE);
    assert_logged (&fx->seen, LOG_INFO, "uav2: intercept cancelled; loitering here (from ");

    // Footprint scale.
    Cgs__SetFootprintScale fs = CGS__SET_FOOTPRINT_SCALE__INIT;
    fs.uav_id = 1;
    fs.scale = 5;
    cmd = (Cgs__Command)CGS__COMMAND__INIT;
    cmd.body_case = CGS__COMMAND__BODY_SET_FOOTPRINT_SCALE;
    cmd.set_footprint_scale = &fs;
    assert_int_equal (s_command (fx, &cmd, &r), 0);
    s_assert_ok (&r, "uav1: footprint shown 5 times");
    assert_int_equal (s_status (fx, 0).display_scale, 5);
    fs.scale = 3;
    assert_int_equal (s_command (fx, &cmd, &r), 0);
    s_assert_refused (&r, "footprint scale must be 1, 5 or 10, got 3");
    assert_int_equal (s_status (fx, 0).display_scale, 5);
    fs.uav_id = 9;
    assert_int_equal (s_command (fx, &cmd, &r), 0);
    s_assert_refused (&r, "no UAV with entity id 9");
    assert_int_equal (s_last_intercept (&fx->seen, 1)->footprint ? 1 : 0, 0); // idle: none

    // Intercept method.
    Cgs__SetInterceptMode im = CGS__SET_INTERCEPT_MODE__INIT;
    im.uav_id = 2;
    im.method = CGS__INTERCEPT_METHOD__INTERCEPT_METHOD_MTI_HITS;
    cmd = (Cgs__Command)CGS__COMMAND__INIT;
    cmd.body_case = CGS__COMMAND__BODY_SET_INTERCEPT_MODE;
    cmd.set_intercept_mode = &im;
    assert_int_equal (s_command (fx, &cmd, &r), 0);
    s_assert_ok (&r, "uav2: intercept method Intercept by MTI TGT Hits");
    assert_int_equal (s_status (fx, 1).method, GD_MTI_HITS);
    assert_int_equal (s_last_intercept (&fx->seen, 2)->method,
                      CGS__INTERCEPT_METHOD__INTERCEPT_METHOD_MTI_HITS);
    im.method = CGS__INTERCEPT_METHOD__INTERCEPT_METHOD_HEAD_ON;
    assert_int_equal (s_command (fx, &cmd, &r), 0);
    s_assert_ok (&r, "uav2: intercept method head-on waypoint");
    im.method = (Cgs__InterceptMethod)7;
    assert_int_equal (s_command (fx, &cmd, &r), 0);
    s_assert_refused (&r, "unknown intercept method 7");

    // Altitude and speed are uavsim's: the caller forwards them, untouched.
    Cgs__SetAltitude alt = CGS__SET_ALTITUDE__INIT;
    cmd = (Cgs__Command)CGS__COMMAND__INIT;
    cmd.body_case = CGS__COMMAND__BODY_SET_ALTITUDE;
    cmd.set_altitude = &alt;
    assert_int_equal (s_command (fx, &cmd, &r), 1);
    assert_int_equal (r.status, CGS__REPLY_STATUS__REPLY_STATUS_OK);
    Cgs__SetSpeed spd = CGS__SET_SPEED__INIT;
    cmd = (Cgs__Command)CGS__COMMAND__INIT;
    cmd.body_case = CGS__COMMAND__BODY_SET_SPEED;
    cmd.set_speed = &spd;
    assert_int_equal (s_command (fx, &cmd, &r), 1);

    // Ping: OK as it is; what guidanced does not serve: UNSUPPORTED.
    Cgs__Ping ping = CGS__PING__INIT;
    cmd = (Cgs__Command)CGS__COMMAND__INIT;
    cmd.body_case = CGS__COMMAND__BODY_PING;
    cmd.ping = &ping;
    assert_int_equal (s_command (fx, &cmd, &r), 0);
    assert_int_equal (r.status, CGS__REPLY_STATUS__REPLY_STATUS_OK);
    Cgs__Loiter lo = CGS__LOITER__INIT;
    cmd = (Cgs__Command)CGS__COMMAND__INIT;
    cmd.body_case = CGS__COMMAND__BODY_LOITER;
    cmd.loiter = &lo;
    assert_int_equal (s_command (fx, &cmd, &r), 0);
    assert_int_equal (r.status, CGS__REPLY_STATUS__REPLY_STATUS_UNSUPPORTED);
    assert_has (r.error, "guidanced does not handle loiter");
    s_fx_free (&fx);
}

/* ---- tasks -------------------------------------------------------------------------------- */

static void test_tasks (void **state)
{
    (void)state;
    s_fx_t *fx = s_fx_new (s_one);
    s_scene (fx, 10);
    assert_true (s_none_due (fx)); // idle: no task
    Cgs__Reply r;
    assert_int_equal (s_designate_track (fx, 1, 7, &r), 0);

    // The route, numbered once.
    gd_adapter_task_t task = s_next (fx);
    assert_int_equal (task.uav, 0);
    assert_true (task.new_number);
    assert_int_equal (task.command_number, 1);
    const gd_task_t *want = gd_intercept_task (gd_adapter_intercept (fx->gd, 0));
    assert_int_equal (task.task_number, want->number);
    assert_int_equal (want->kind, GD_TASK_ROUTE);
    const Cgs__Command *c = task.command;
    assert_int_equal (c->body_case, CGS__COMMAND__BODY_TASK_ROUTE);
    assert_int_equal (c->task_route->uav_id, 1);
    assert_true (c->task_route->loiter_at_end);
    assert_int_equal (c->task_route->n_waypoints, want->count);
    assert_true (want->count > 1);
    for (size_t k = 0; k < want->count; k++) {
        const Cgs__Enu *p = c->task_route->waypoints[k];
        assert_near (p->east_m, want->points[k].e, 1e-9);
        assert_near (p->north_m, want->points[k].n, 1e-9);
        assert_near (p->up_m, s_ground (fx, p->east_m, p->north_m), 1e-9);
        assert_near (p->up_m, 100, 1e-6);
    }
    uint64_t route_task = task.task_number;
    // Stable until answered: no answer (a timeout) leaves it as it was.
    task = s_next (fx);
    assert_false (task.new_number);
    assert_int_equal (task.command_number, 1);
    gd_adapter_task_answered (fx->gd, &task, NULL);
    task = s_next (fx);
    assert_false (task.new_number);
    assert_int_equal (task.command_number, 1);
    assert_int_equal (gd_adapter_last_number (fx->gd), 1);
    // OK: delivered.
    s_answer (fx, &task, CGS__REPLY_STATUS__REPLY_STATUS_OK, false, NULL);
    assert_true (s_none_due (fx));
    char line[160];
    snprintf (line, sizeof line, "uav1: task %llu (route, %zu points) delivered",
              (unsigned long long)route_task, want->count);
    assert_logged (&fx->seen, LOG_INFO, line);

    // A forwarded command takes the next number of the same sequence.
    assert_int_equal (gd_adapter_take_number (fx->gd), 2);

    // Cancel: a loiter, under a new number.
    assert_int_equal (s_cancel (fx, 1, &r), 0);
    task = s_next (fx);
    assert_true (task.new_number);
    assert_int_equal (task.command_number, 3);
    assert_int_equal (task.command->body_case, CGS__COMMAND__BODY_LOITER);
    assert_int_equal (task.command->loiter->uav_id, 1);
    assert_true (task.command->loiter->at_present_position);
    assert_true (task.command->loiter->clockwise);
    // BAD_REQUEST, not a duplicate (the number was taken): again, under a new one.
    s_answer (fx, &task, CGS__REPLY_STATUS__REPLY_STATUS_BAD_REQUEST, false,
              "command number 3 was used for another command");
    snprintf (line, sizeof line,
              "uav1: task %llu: uavsim: command number 3 was used for another command; sending "
              "it under a new number",
              (unsigned long long)task.task_number);
    assert_logged (&fx->seen, LOG_NOTICE, line);
    gd_adapter_task_t again = s_next (fx);
    assert_true (again.new_number);
    assert_int_equal (again.command_number, 4);
    assert_int_equal (again.task_number, task.task_number);
    // NOT_SAVED (applied, not written): delivered.
    s_answer (fx, &again, CGS__REPLY_STATUS__REPLY_STATUS_NOT_SAVED, false, NULL);
    assert_true (s_none_due (fx));
    snprintf (line, sizeof line, "uav1: task %llu (loiter here, 0 points) delivered",
              (unsigned long long)task.task_number);
    assert_logged (&fx->seen, LOG_INFO, line);

    // A refusal: reported, and marked delivered (not sent for ever).
    assert_int_equal (s_designate_track (fx, 1, 8, &r), 0);
    task = s_next (fx);
    assert_int_equal (task.command_number, 5);
    assert_int_equal (fx->seen.errors, 0);
    s_answer (fx, &task, CGS__REPLY_STATUS__REPLY_STATUS_ERROR, false, "no such route");
    snprintf (line, sizeof line, "uavsim refused uav1 task %llu: no such route",
              (unsigned long long)task.task_number);
    assert_int_equal (fx->seen.errors, 1);
    assert_string_equal (fx->seen.last_error, line);
    assert_logged (&fx->seen, LOG_WARNING, line);
    assert_true (s_none_due (fx));

    // A duplicate's BAD_REQUEST is an answer too (not sent again).
    assert_int_equal (s_designate_track (fx, 1, 7, &r), 0);
    task = s_next (fx);
    assert_int_equal (task.command_number, 6);
    s_answer (fx, &task, CGS__REPLY_STATUS__REPLY_STATUS_BAD_REQUEST, true, "reused");
    assert_true (s_none_due (fx));
    assert_int_equal (gd_adapter_last_number (fx->gd), 6);
    s_fx_free (&fx);
}

static void test_tasks_two_uavs (void **state)
{
    (void)state;
    s_fx_t *fx = s_fx_new (s_two);
    s_scene (fx, 10);
    Cgs__Reply r;
    assert_int_equal (s_designate_track (fx, 2, 8, &r), 0);
    assert_int_equal (s_designate_track (fx, 1, 7, &r), 0);
    size_t cursor = 0;
    gd_adapter_task_t a, b, c;
    assert_true (gd_adapter_next_task (fx->gd, &cursor, &a));
    assert_int_equal (a.uav, 0);
    assert_int_equal (a.command->task_route->uav_id, 1);
    assert_int_equal (a.command_number, 1);
    assert_true (gd_adapter_next_task (fx->gd, &cursor, &b));
    assert_int_equal (b.uav, 1);
    assert_int_equal (b.command->task_route->uav_id, 2);
    assert_int_equal (b.command_number, 2);
    assert_false (gd_adapter_next_task (fx->gd, &cursor, &c));
    // uav2's answered; uav1's is still due under its number.
    s_answer (fx, &b, CGS__REPLY_STATUS__REPLY_STATUS_OK, false, NULL);
    c = s_next (fx);
    assert_int_equal (c.uav, 0);
    assert_int_equal (c.command_number, 1);
    assert_false (c.new_number);
    s_fx_free (&fx);
}

/* ---- inputs ------------------------------------------------------------------------------- */

static void test_track_table (void **state)
{
    (void)state;
    s_fx_t *fx = s_fx_new (s_one);
    const s_trk_t three[3] = {s_t7, s_t8, s_t9};
    s_tracks (fx, 10, three, 3);
    assert_int_equal (gd_adapter_track_count (fx->gd), 3);
    assert_near (gd_adapter_time (fx->gd), 10, 0);
    // Updates replace, deleted tracks leave.
    s_trk_t upd[2] = {s_t7, s_t8};
    upd[0].e = 5900;
    upd[1].status = S_DELETED;
    s_tracks (fx, 11, upd, 2);
    assert_int_equal (gd_adapter_track_count (fx->gd), 2);
    Cgs__Reply r;
    assert_int_equal (s_designate_track (fx, 1, 8, &r), 0);
    s_assert_refused (&r, "no track 8 (2 live tracks known)");
    assert_int_equal (fx->seen.bad, 0);

    // A track with a non-finite position is bad input; the others are kept.
    s_trk_t bad[2] = {s_t8, s_t9};
    bad[0].n = NAN;
    s_tracks (fx, 12, bad, 2);
    assert_int_equal (fx->seen.bad, 1);
    assert_string_equal (fx->seen.last_bad, "a track without an id, a valid position or velocity");
    assert_int_equal (gd_adapter_track_count (fx->gd), 2);
    bad[0] = s_t8;
    bad[0].id = 0; // no id
    s_tracks (fx, 12, bad, 1);
    assert_int_equal (fx->seen.bad, 2);
    // A batch without a time: bad input, nothing taken, time unchanged.
    s_tracks (fx, NAN, &s_t8, 1);
    assert_int_equal (fx->seen.bad, 3);
    assert_string_equal (fx->seen.last_bad, "a track batch without a simulation time");
    assert_int_equal (gd_adapter_track_count (fx->gd), 2);
    assert_near (gd_adapter_time (fx->gd), 12, 0);

    // Turn events: taken, or bad input without a velocity.
    Cgs__TrackTurn turn = CGS__TRACK_TURN__INIT;
    turn.track_id = 7;
    turn.sim_time_s = 12;
    gd_adapter_on_message (fx->gd, "track.turn", &turn.base, NULL);
    assert_int_equal (fx->seen.bad, 4);
    assert_string_equal (fx->seen.last_bad, "a turn event without a track, time or velocity");
    Cgs__EnuVelocity v = CGS__ENU_VELOCITY__INIT;
    v.north_mps = 10;
    turn.velocity_after = &v;
    turn.turn_angle_deg = 90;
    size_t published = fx->seen.n;
    gd_adapter_on_message (fx->gd, "track.turn", &turn.base, NULL);
    assert_int_equal (fx->seen.bad, 4);
    assert_int_equal (fx->seen.n, published); // a turn publishes nothing by itself
    // Other topics are not its own: ignored.
    gd_adapter_on_message (fx->gd, "entity", &turn.base, NULL);
    assert_int_equal (fx->seen.bad, 4);
    s_fx_free (&fx);
}

static void test_intercept_messages (void **state)
{
    (void)state;
    s_fx_t *fx = s_fx_new (s_one);
    // Tracks before the UAV: an idle intercept, no footprint.
    s_tracks (fx, 10, &s_t7, 1);
    assert_int_equal (s_count (&fx->seen, "intercept"), 1);
    const Cgs__Intercept *m = s_last_intercept (&fx->seen, 1);
    assert_non_null (m);
    assert_int_equal (m->state, CGS__INTERCEPT_STATE__INTERCEPT_STATE_IDLE);
    assert_null (m->footprint);
    assert_null (m->waypoint);
    assert_near (m->time_to_go_s, -1, 0);
    // A UAV without a valid sensor: bad input, nothing published.
    s_uav_msg (fx, 1, 10, 0, 0, 95);
    assert_int_equal (fx->seen.bad, 1);
    assert_has (fx->seen.last_bad, "imaging sensor");
    assert_int_equal (s_count (&fx->seen, "intercept"), 1);
    // A UAV of another scenario: not ours, not bad.
    s_uav_msg (fx, 42, 10, 0, 0, 45);
    assert_int_equal (fx->seen.bad, 1);
    assert_int_equal (s_count (&fx->seen, "intercept"), 1);
    // Heard: still idle, so no footprint shown.
    s_uav_msg (fx, 1, 11, 0, 0, 45);
    assert_int_equal (s_count (&fx->seen, "intercept"), 2);
    assert_null (s_last_intercept (&fx->seen, 1)->footprint);
    assert_near (fx->seen.times[fx->seen.n - 1], 11, 0);

    // Designated: the plan, the route at the terrain's height, the footprint.
    Cgs__Reply r;
    assert_int_equal (s_designate_track (fx, 1, 7, &r), 0);
    assert_int_equal (s_count (&fx->seen, "intercept"), 3);
    m = s_last_intercept (&fx->seen, 1);
    assert_int_equal (m->track_id, 7);
    assert_int_equal (m->state, CGS__INTERCEPT_STATE__INTERCEPT_STATE_TO_WAYPOINT);
    assert_int_equal (m->designation_number, 1);
    assert_non_null (m->waypoint);
    assert_near (m->waypoint->up_m, 100, 1e-6);
    assert_true (m->n_route > 1);
    for (size_t k = 0; k < m->n_route; k++)
        assert_near (m->route[k]->up_m, s_ground (fx, m->route[k]->east_m, m->route[k]->north_m),
                     1e-9);
    assert_has (m->reason, "designated track 7");
    assert_logged (&fx->seen, LOG_NOTICE,
                   "uav1: TO_WAYPOINT, track 7, t=11.0 s: designated track 7");
    s_uav_msg (fx, 1, 12, 38, 0, 45);
    m = s_last_intercept (&fx->seen, 1);
    assert_non_null (m->footprint);
    assert_int_equal (m->footprint->n_corners, 4);
    assert_non_null (m->footprint->center);
    assert_int_equal (m->footprint->display_scale, 1);
    // The footprint lies ahead of the UAV (east), about the look-ahead away, on the ground.
    assert_near (m->footprint->center->east_m, 38 + 1200, 50);
    assert_near (m->footprint->center->north_m, 0, 50);
    assert_near (m->footprint->center->up_m, 100, 1);
    // A notice only when something changed.
    size_t notices = s_logged (&fx->seen, LOG_NOTICE, "uav1: ");
    s_uav_msg (fx, 1, 13, 76, 0, 45);
    assert_int_equal (s_logged (&fx->seen, LOG_NOTICE, "uav1: "), notices);
    assert_int_equal (fx->seen.bad, 1);
    s_fx_free (&fx);
}

/* ---- the operator's script --------------------------------------------------------------- */

static void test_script (void **state)
{
    (void)state;
    s_fx_t *fx = s_fx_new (s_script);
    assert_int_equal (fx->scenario->designation_count, 1);
    int line = fx->scenario->designations[0].line;
    s_uav_msg (fx, 1, 10, 0, 0, 45);
    // Before its time: nothing.
    const s_trk_t early[2] = {s_t8, s_t9};
    s_tracks (fx, 40, early, 2);
    assert_int_equal (s_status (fx, 0).phase, GD_IDLE);
    assert_false (gd_adapter_take_dirty (fx->gd));
    assert_int_equal (s_logged (&fx->seen, LOG_INFO, "operator script"), 0);
    // At its time, no unknown track near (track 9 is friendly): it waits, said once.
    s_trk_t away[2] = {s_t8, s_t9};
    s_tracks (fx, 50, away, 2);
    s_tracks (fx, 51, away, 2);
    char want[256];
    snprintf (want, sizeof want,
              "operator script line %d: no track qualifies within 2000 m of (6000, 500) yet; "
              "waiting",
              line);
    assert_int_equal (s_logged (&fx->seen, LOG_INFO, want), 1);
    assert_int_equal (s_status (fx, 0).phase, GD_IDLE);
    assert_false (gd_adapter_take_dirty (fx->gd));
    // The unknown track 7 comes: designated, though friendly 9 is nearer.
    size_t before = s_count (&fx->seen, "intercept");
    const s_trk_t all[3] = {s_t7, s_t8, s_t9};
    s_tracks (fx, 52, all, 3);
    snprintf (want, sizeof want,
              "operator script line %d: uav1 designates track 7, 500 m from (6000, 500), at "
              "t=52.0 s",
              line);
    assert_logged (&fx->seen, LOG_NOTICE, want);
    assert_int_equal (s_status (fx, 0).track_id, 7);
    assert_int_equal (s_status (fx, 0).phase, GD_TO_WAYPOINT);
    assert_true (gd_adapter_take_dirty (fx->gd));
    assert_false (gd_adapter_take_dirty (fx->gd));
    // Its intercept right away, and with the others after the batch.
    assert_int_equal (s_count (&fx->seen, "intercept"), before + 2);
    gd_adapter_task_t task = s_next (fx);
    assert_int_equal (task.command->body_case, CGS__COMMAND__BODY_TASK_ROUTE);
    // Done: not run again.
    s_tracks (fx, 60, all, 3);
    assert_false (gd_adapter_take_dirty (fx->gd));
    assert_int_equal (s_status (fx, 0).designation_number, 1);
    s_fx_free (&fx);
}

static void test_script_skipped (void **state)
{
    (void)state;
    s_fx_t *fx = s_fx_new (s_script);
    int line = fx->scenario->designations[0].line;
    s_scene (fx, 20);
    Cgs__Reply r;
    assert_int_equal (s_designate_track (fx, 1, 8, &r), 0);
    s_assert_ok (&r, "uav1: designated track 8");
    assert_true (gd_adapter_take_dirty (fx->gd));
    const s_trk_t all[3] = {s_t7, s_t8, s_t9};
    s_tracks (fx, 55, all, 3);
    char want[160];
    snprintf (want, sizeof want, "operator script line %d skipped: an operator designated already",
              line);
    assert_logged (&fx->seen, LOG_NOTICE, want);
    assert_true (gd_adapter_take_dirty (fx->gd));
    assert_int_equal (s_status (fx, 0).track_id, 8); // the operator's stands
    assert_int_equal (s_status (fx, 0).designation_number, 1);
    s_fx_free (&fx);
}

/* ---- state -------------------------------------------------------------------------------- */

static void s_save (const s_fx_t *fx, uint8_t **buf, size_t *len)
{
    assert_int_equal (gd_adapter_save (fx->gd, buf, len), 0);
    assert_non_null (*buf);
}

static void test_save_restore (void **state)
{
    (void)state;
    s_fx_t *a = s_fx_new (s_two);
    s_scene (a, 10);
    Cgs__Reply r;
    assert_int_equal (s_designate_track (a, 1, 7, &r), 0);
    assert_int_equal (s_designate_track (a, 2, 8, &r), 0);
    gd_adapter_task_t t1 = s_next (a); // uav1's numbered, not answered
    size_t cursor = 1;
    gd_adapter_task_t t2;
    assert_true (gd_adapter_next_task (a->gd, &cursor, &t2));           // uav2's numbered...
    s_answer (a, &t2, CGS__REPLY_STATUS__REPLY_STATUS_OK, false, NULL); // ...and delivered
    assert_int_equal (gd_adapter_take_number (a->gd), 3);
    uint8_t *buf = NULL, *buf2 = NULL;
    size_t len = 0, len2 = 0;
    s_save (a, &buf, &len);
    // The frame's counters and first UAV record.
    cgs_ckpt_reader_t rd;
    char err[256] = "", id[128];
    assert_int_equal (cgs_ckpt_open (&rd, buf, len, "GDST", 1, "x", err, sizeof err), 0);
    cgs_ckpt_get_str (&rd, id, sizeof id);
    assert_string_equal (id, "guidanced@1.000001");
    assert_int_equal (cgs_ckpt_get_u64 (&rd), 3); // the last command number
    assert_int_equal (cgs_ckpt_get_u64 (&rd), 0); // script lines done
    assert_true (cgs_ckpt_get_bool (&rd));        // an operator acted
    assert_int_equal (cgs_ckpt_get_u32 (&rd), 2); // UAVs
    assert_int_equal (cgs_ckpt_get_u32 (&rd), 1); // the first, entity 1,
    assert_int_equal (cgs_ckpt_get_u64 (&rd), 0); // nothing delivered
    assert_true (cgs_ckpt_ok (&rd));

    s_fx_t *b = s_fx_new (s_two);
    gd_adapter_set_client_id (b->gd, "guidanced@2.000002"); // a new start's, replaced by the saved
    assert_int_equal (gd_adapter_restore (b->gd, buf, len, err, sizeof err), 0);
    s_save (b, &buf2, &len2);
    assert_int_equal (len2, len);
    assert_memory_equal (buf2, buf, len);
    assert_string_equal (gd_adapter_client_id (b->gd), "guidanced@1.000001");
    assert_int_equal (gd_adapter_last_number (b->gd), 3);
    for (size_t i = 0; i < 2; i++) {
        gd_status_t sa = s_status (a, i), sb = s_status (b, i);
        assert_int_equal (sb.phase, sa.phase);
        assert_int_equal (sb.track_id, sa.track_id);
        assert_int_equal (sb.designation_number, sa.designation_number);
    }
    // The pending task goes under the number it had; the delivered one is done.
    gd_adapter_task_t rt = s_next (b);
    assert_int_equal (rt.uav, 0);
    assert_false (rt.new_number);
    assert_int_equal (rt.command_number, t1.command_number);
    assert_int_equal (rt.task_number, t1.task_number);
    cursor = 1;
    assert_false (gd_adapter_next_task (b->gd, &cursor, &rt));
    // The next number goes on from the saved one.
    assert_int_equal (gd_adapter_take_number (b->gd), 4);
    free (buf);
    free (buf2);
    s_fx_free (&a);
    s_fx_free (&b);
}

/* The tracker says once that the designated track was deleted, and once
 * which new track continues it: each change is saved, so a guidanced that
 * restarts in between still waits for the successor, and takes it. */
static void test_deletion_saved (void **state)
{
    (void)state;
    s_fx_t *a = s_fx_new (s_one);
    s_scene (a, 10);
    Cgs__Reply r;
    assert_int_equal (s_designate_track (a, 1, 7, &r), 0);
    s_assert_ok (&r, "uav1: designated track 7");
    assert_true (gd_adapter_take_dirty (a->gd));
    const uint32_t hid[2] = {100, 200};
    s_trk_t t7 = s_t7;
    t7.e = 5900;
    s_tracks_hits (a, 20, &t7, 1, hid, 4);
    (void)gd_adapter_take_dirty (a->gd);
    uint64_t before = gd_intercept_changes (gd_adapter_intercept (a->gd, 0));
    t7.status = S_DELETED;
    s_tracks_hits (a, 30, &t7, 1, hid, 5);
    assert_true (gd_intercept_changes (gd_adapter_intercept (a->gd, 0)) > before);
    assert_string_equal (s_status (a, 0).reason, "track 7 was deleted: flying on its prediction");
    assert_true (gd_adapter_take_dirty (a->gd)); // saved: the tracker will not say it again
    uint8_t *buf = NULL;
    size_t len = 0;
    s_save (a, &buf, &len);
    // Restarted: the successor, where track 7's target is by then, takes over.
    s_fx_t *b = s_fx_new (s_one);
    char err[256] = "";
    assert_int_equal (gd_adapter_restore (b->gd, buf, len, err, sizeof err), 0);
    s_uav_msg (b, 1, 60, 0, 0, 45);
    s_trk_t t17 = {17, S_CONFIRMED, false, 5900 - 10 * 50, 0, -10, 0};
    const uint32_t hid17[1] = {300};
    s_tracks_hits (b, 70, &t17, 1, hid17, 9);
    assert_int_equal (s_status (b, 0).track_id, 17);
    assert_string_equal (s_status (b, 0).reason,
                         "track 7 was deleted; its target goes on as track 17");
    assert_true (gd_adapter_take_dirty (b->gd)); // the hand-over is saved too
    free (buf);
    s_fx_free (&a);
    s_fx_free (&b);
}

/* A state as s_state_frame writes it: the counters, then a record per UAV
 * (entity ids[i], delivered, pending and its command number 3, 4, 7 for
 * the first, 0 for the others) each with the intercept checkpoint core. */
static uint8_t *s_state_frame (const uint32_t *ids, size_t n, const uint8_t *core, size_t clen,
                               size_t *ret_len)
{
    cgs_ckpt_writer_t w;
    cgs_ckpt_writer_init (&w, "GDST", 1);
    cgs_ckpt_put_str (&w, "guidanced@1700000000.000001");
    cgs_ckpt_put_u64 (&w, 7);
    cgs_ckpt_put_u64 (&w, 1);
    cgs_ckpt_put_bool (&w, true);
    cgs_ckpt_put_u32 (&w, (uint32_t)n);
    for (size_t i = 0; i < n; i++) {
        cgs_ckpt_put_u32 (&w, ids[i]);
        cgs_ckpt_put_u64 (&w, i == 0 ? 3 : 0);
        cgs_ckpt_put_u64 (&w, i == 0 ? 4 : 0);
        cgs_ckpt_put_u64 (&w, i == 0 ? 7 : 0);
        cgs_ckpt_put_bytes (&w, core, clen);
    }
    uint8_t *buf = NULL;
    assert_int_equal (cgs_ckpt_writer_finish (&w, &buf, ret_len), 0);
    return buf;
}

/* A saved UAV that is not in the scenario is skipped with a warning; the
 * rest restores, and is written back the same, less that UAV. */
static void test_restore_unknown_uav (void **state)
{
    (void)state;
    s_fx_t *fx = s_fx_new (s_one);
    // An idle intercept's own checkpoint, as each record's.
    gd_params_t p;
    gd_params_defaults (&p);
    gd_intercept_t *ic = gd_intercept_new (&p, NULL);
    assert_non_null (ic);
    uint8_t *core = NULL;
    size_t clen = 0;
    assert_int_equal (gd_checkpoint_save (ic, &core, &clen), 0);
    gd_intercept_destroy (&ic);
    size_t len = 0, first_len = 0;
    uint8_t *state_buf = s_state_frame ((const uint32_t[]){1, 99}, 2, core, clen, &len);
    uint8_t *first = s_state_frame ((const uint32_t[]){1}, 1, core, clen, &first_len);
    char err[256] = "";
    assert_int_equal (gd_adapter_restore (fx->gd, state_buf, len, err, sizeof err), 0);
    assert_logged (&fx->seen, LOG_WARNING,
                   "saved intercept of UAV 99 ignored: not in the scenario");
    assert_string_equal (gd_adapter_client_id (fx->gd), "guidanced@1700000000.000001");
    assert_int_equal (gd_adapter_last_number (fx->gd), 7);
    // Written back the same, less the UAV that is not in the scenario.
    uint8_t *buf = NULL;
    size_t blen = 0;
    s_save (fx, &buf, &blen);
    assert_int_equal (blen, first_len);
    assert_memory_equal (buf, first, first_len);
    free (buf);
    free (first);
    free (state_buf);
    free (core);
    s_fx_free (&fx);
}

static void test_restore_damaged (void **state)
{
    (void)state;
    // Frames: counters cut short; a UAV record claiming more bytes than
    // there are; a count of 1 with no record; a record whose intercept
    // checkpoint is not one.
    cgs_ckpt_writer_t w;
    uint8_t *frames[4] = {NULL};
    size_t flen[4] = {0};
    for (int k = 0; k < 4; k++) {
        cgs_ckpt_writer_init (&w, "GDST", 1);
        cgs_ckpt_put_str (&w, "guidanced@9.000009");
        if (k > 0) {
            cgs_ckpt_put_u64 (&w, 5);
            cgs_ckpt_put_u64 (&w, 0);
            cgs_ckpt_put_bool (&w, true);
            cgs_ckpt_put_u32 (&w, 1);
        }
        if (k == 1 || k == 3) {
            cgs_ckpt_put_u32 (&w, 1);
            for (int i = 0; i < 3; i++)
                cgs_ckpt_put_u64 (&w, 0);
        }
        if (k == 1) {
            cgs_ckpt_put_u64 (&w, 999);
            cgs_ckpt_put_u8 (&w, 'a');
        }
        if (k == 3)
            cgs_ckpt_put_bytes (&w, "hello", 5);
        assert_int_equal (cgs_ckpt_writer_finish (&w, &frames[k], &flen[k]), 0);
    }
    const char *old = "guidanced 1\nclient guidanced@9.000009 5 0 1\nuav 1 0 0 0 5\nhello";
    struct {
        const void *buf;
        size_t len;
        int rc;
        const char *reason;
    } cases[] = {
        {"not a state\n", 12, -EPROTO,
         "not a guidanced state: it begins \"not \", not \"GDST\" (another kind of file, or one "
         "saved before mscgs's common checkpoint format)"},
        {old, strlen (old), -EPROTO, NULL}, // the text format before cgs_ckpt
        {"GDST\x01\x00", 6, -EINVAL, "a guidanced state truncated to 6 bytes"},
        {"GDST\x07\x00\x00\x00", 8, -ENOTSUP,
         "a guidanced state saved by another version of mscgs (format 7; this one reads "
         "format 1)"},
        {frames[0], flen[0], -EINVAL, "a guidanced state with damaged counters"},
        {frames[1], flen[1], -EINVAL, "a guidanced state whose UAV record 1 of 1 is damaged"},
        {frames[2], flen[2], -EINVAL, "a guidanced state whose UAV record 1 of 1 is damaged"},
        {frames[3], flen[3], -EPROTO, NULL}, // the intercept's own reason
        {frames[3], flen[3] - 1, -EINVAL, NULL},
    };
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        s_fx_t *fx = s_fx_new (s_one);
        // Busy first: an intercept, a numbered task, a script state.
        s_scene (fx, 10);
        Cgs__Reply r;
        assert_int_equal (s_designate_track (fx, 1, 7, &r), 0);
        (void)s_next (fx);
        assert_int_equal (gd_adapter_last_number (fx->gd), 1);
        char err[256] = "";
        int rc = gd_adapter_restore (fx->gd, cases[k].buf, cases[k].len, err, sizeof err);
        if (rc != cases[k].rc)
            fail_msg ("case %zu: %d, expected %d (%s)", k, rc, cases[k].rc, err);
        if (cases[k].reason)
            assert_string_equal (err, cases[k].reason);
        else
            assert_true (strlen (err) > 0);
        if (k == 1)
            assert_non_null (strstr (err, "it begins \"guid\""));
        if (k == 7)
            assert_non_null (strstr (err, "UAV 1: "));
        // Idle, as after gd_adapter_reset; its client id and numbering kept.
        assert_int_equal (s_status (fx, 0).phase, GD_IDLE);
        assert_int_equal (s_status (fx, 0).track_id, 0);
        assert_true (s_none_due (fx));
        assert_int_equal (gd_adapter_last_number (fx->gd), 1);
        assert_string_equal (gd_adapter_client_id (fx->gd), "guidanced@1.000001");
        assert_int_equal (gd_adapter_track_count (fx->gd), 2); // the picture heard stays
        // Its state is a fresh adapter's that used one number.
        s_fx_t *fresh = s_fx_new (s_one);
        assert_int_equal (gd_adapter_take_number (fresh->gd), 1);
        uint8_t *a = NULL, *b = NULL;
        size_t alen = 0, blen = 0;
        s_save (fx, &a, &alen);
        s_save (fresh, &b, &blen);
        assert_int_equal (alen, blen);
        assert_memory_equal (a, b, alen);
        free (a);
        free (b);
        s_fx_free (&fresh);
        s_fx_free (&fx);
    }
    for (int k = 0; k < 4; k++)
        free (frames[k]);
}

static void test_reset_and_names (void **state)
{
    (void)state;
    s_fx_t *fx = s_fx_new (s_two);
    assert_int_equal (gd_adapter_uav_count (fx->gd), 2);
    assert_string_equal (gd_adapter_uav_name (fx->gd, 0), "uav1");
    assert_string_equal (gd_adapter_uav_name (fx->gd, 1), "uav2");
    assert_int_equal (gd_adapter_uav_id (fx->gd, 0), 1);
    assert_int_equal (gd_adapter_uav_id (fx->gd, 1), 2);
    assert_string_equal (gd_adapter_topics[0], "uav");
    assert_string_equal (gd_adapter_topics[1], "track");
    assert_string_equal (gd_adapter_topics[2], "track.turn");
    assert_null (gd_adapter_topics[3]);
    s_scene (fx, 10);
    Cgs__Reply r;
    assert_int_equal (s_designate_track (fx, 1, 7, &r), 0);
    (void)s_next (fx);
    gd_adapter_reset (fx->gd);
    assert_int_equal (s_status (fx, 0).phase, GD_IDLE);
    assert_int_equal (s_status (fx, 0).designation_number, 0);
    assert_true (s_none_due (fx));
    assert_false (gd_adapter_take_dirty (fx->gd));
    // The numbering goes on under the same id; a new client id numbers from 1.
    assert_int_equal (gd_adapter_last_number (fx->gd), 1);
    assert_int_equal (gd_adapter_take_number (fx->gd), 2);
    assert_int_equal (s_designate_track (fx, 1, 7, &r), 0);
    s_uav_msg (fx, 1, 11, 0, 0, 45); // the new intercept plans when it hears the UAV
    gd_adapter_task_t task = s_next (fx);
    assert_true (task.new_number);
    assert_int_equal (task.command_number, 3);
    gd_adapter_set_client_id (fx->gd, "guidanced@3.000003");
    assert_string_equal (gd_adapter_client_id (fx->gd), "guidanced@3.000003");
    assert_int_equal (gd_adapter_take_number (fx->gd), 1);

    // Too many UAVs for one guidanced.
    char text[8192];
    size_t len = (size_t)snprintf (text, sizeof text, "%s", S_TERRAIN);
    for (int i = 0; i <= GD_ADAPTER_UAVS_MAX; i++)
        len += (size_t)snprintf (text + len, sizeof text - len, "[uav u%d]\nposition = %d 0\n", i,
                                 i * 100);
    cgs_scenario_t *sc = NULL;
    char err[512] = "";
    if (cgs_scenario_load_string ("many.ini", text, fx->frame, 1, &sc, err, sizeof err) < 0)
        fail_msg ("%s", err);
    bool too_many = false;
    gd_adapter_t *gd = gd_adapter_new (&fx->params, sc, NULL, &fx->port, &too_many);
    assert_null (gd);
    assert_true (too_many);
    cgs_scenario_destroy (&sc);
    s_fx_free (&fx);
}

int main (void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test (test_designate),          cmocka_unit_test (test_designate_by_hit),
        cmocka_unit_test (test_time_back),          cmocka_unit_test (test_designate_no_tracks),
        cmocka_unit_test (test_settings),           cmocka_unit_test (test_tasks),
        cmocka_unit_test (test_tasks_two_uavs),     cmocka_unit_test (test_track_table),
        cmocka_unit_test (test_intercept_messages), cmocka_unit_test (test_script),
        cmocka_unit_test (test_script_skipped),     cmocka_unit_test (test_save_restore),
        cmocka_unit_test (test_deletion_saved),     cmocka_unit_test (test_restore_unknown_uav),
        cmocka_unit_test (test_restore_damaged),    cmocka_unit_test (test_reset_and_names),
    };
    return cmocka_run_group_tests (tests, NULL, NULL);
}
