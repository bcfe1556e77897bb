/* test_sensor_adapters — mtid's and bcisd's adapters driven as the bus and
 * the lockstep engine drive them: decoded `entity` and `uav` messages in,
 * and every message out through a port that encodes and decodes it again
 * (so what goes out is a complete, valid protobuf message of its topic's
 * type). On flat ground, a UAV orbits nothing (it flies east at 38 m/s from
 * the origin) and two ground vehicles drive away from it, radially, at
 * 10 m/s 3 km out: a friendly one with a BCIS transponder, an unknown one
 * without. Over two radar scans (10 s each at 36 deg/s) the radar must
 * publish one `mti` and one `mti.truth` per dwell, in dwell order, and one
 * `mti.scan` per scan with its number, times and hit count; the vehicles must
 * be in some dwell's truth, in the beam and visible, and hits must fall near
 * them (Pd is high at 3 km). The interrogator must get replies from the
 * transponder only, and mark each scan's end. Another UAV's messages are
 * ignored, a malformed one is bad input, time going back is reported. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "bcis_adapter.h"
#include "cgs_msg.h"
#include "cgs_scenario.h"
#include "cgs_topics.h"
#include "mti_adapter.h"
#include "port_check.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <syslog.h>

#define S_MAX_MSGS 4096

/* What the test port saw. */
typedef struct {
    char topic[32][S_MAX_MSGS];
    size_t n;
    char *topics[S_MAX_MSGS];
    ProtobufCMessage *msgs[S_MAX_MSGS];
    double times[S_MAX_MSGS];
    size_t bad, errors, notices;
    char last_bad[256], last_log[512];
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
    if (priority <= LOG_NOTICE)
        s->notices++;
    snprintf (s->last_log, sizeof s->last_log, "%s", line);
}

static void s_bad (void *arg, const char *what)
{
    s_seen_t *s = arg;
    s->bad++;
    snprintf (s->last_bad, sizeof s->last_bad, "%s", what);
}

static void s_error (void *arg, const char *why)
{
    (void)why;
    ((s_seen_t *)arg)->errors++;
}

static void s_clear (s_seen_t *s)
{
    for (size_t i = 0; i < s->n; i++) {
        free (s->topics[i]);
        cgs_msg_free (&s->msgs[i]);
    }
    memset (s, 0, sizeof *s);
}

static size_t s_count (const s_seen_t *s, const char *topic)
{
    size_t n = 0;
    for (size_t i = 0; i < s->n; i++)
        n += strcmp (s->topics[i], topic) == 0;
    return n;
}

/* ---- the scene ---------------------------------------------------------------------- */

static const char *const s_scenario =
    "[terrain]\nsize_m = 12000\nresolution_m = 60\nrelief_m = 0\nbase_height_m = 100\n"
    "[uav uav1]\nposition = 0 0\naltitude_agl_m = 1200\nairspeed_mps = 38\nheading_deg = 90\n"
    "[uav uav2]\nposition = 0 1000\n"
    "[vehicle friend]\nforce = friendly\nkind = wheeled\nbcis_transponder = yes\n"
    "speed_mps = 10\npoint = 0 3000\npoint = 0 5000\n"
    "[vehicle other]\nforce = unknown\nkind = tracked\nspeed_mps = 10\n"
    "point = 0 -3000\npoint = 0 -5000\n";

typedef struct {
    cgs_geo_t *frame;
    cgs_scenario_t *scenario;
    cgs_terrain_t *terrain;
    cgs_sensor_t sensor;
    s_seen_t seen;
    cgs_port_t port;
} s_scene_t;

static void s_scene (s_scene_t *sc, uint64_t salt)
{
    memset (sc, 0, sizeof *sc);
    char err[512] = "";
    sc->frame = cgs_geo_new (35.96, -121.23, 0);
    assert_non_null (sc->frame);
    if (cgs_scenario_load_string ("t.ini", s_scenario, sc->frame, 1, &sc->scenario, err,
                                  sizeof err) < 0 ||
        cgs_scenario_terrain (sc->scenario, sc->frame, &sc->terrain, err, sizeof err) < 0)
        fail_msg ("%s", err);
    if (cgs_sensor_attach (&sc->sensor, "uav1", sc->frame, sc->scenario, sc->terrain, 1, salt, err,
                           sizeof err) < 0)
        fail_msg ("%s", err);
    sc->port = (cgs_port_t){&sc->seen, s_publish, s_log, s_bad, s_error};
}

static void s_scene_free (s_scene_t *sc)
{
    s_clear (&sc->seen);
    cgs_sensor_fini (&sc->sensor); // borrowed: frees nothing
    assert_null (sc->sensor.scenario);
    cgs_terrain_destroy (&sc->terrain);
    cgs_scenario_destroy (&sc->scenario);
    cgs_geo_destroy (&sc->frame);
}

typedef void (s_deliver_fn) (void *adapter, const char *topic, const ProtobufCMessage *msg,
                             const Cgs__Header *hdr);

/* The world at time t: the two vehicles driving away from the origin at
 * 10 m/s, and the UAV flying east from the origin at 38 m/s. */
static void s_tick (s_deliver_fn *fn, void *adapter, double t, const char *uav_name)
{
    Cgs__Header hdr = CGS__HEADER__INIT;
    hdr.sim_time_s = t;
    Cgs__Enu pos[2];
    Cgs__EnuVelocity vel[2];
    Cgs__Entity e[2], *ep[2];
    const char *marks[2] = {"FRIEND", "OTHER"};
    for (int i = 0; i < 2; i++) {
        cgs__enu__init (&pos[i]);
        cgs__enu_velocity__init (&vel[i]);
        cgs__entity__init (&e[i]);
        double sign = i == 0 ? 1 : -1;
        pos[i].north_m = sign * (3000 + 10 * t);
        pos[i].up_m = 100;
        vel[i].north_mps = sign * 10;
        e[i].entity_id = (uint32_t)(3 + i); // after the two UAVs
        e[i].position = &pos[i];
        e[i].velocity = &vel[i];
        e[i].heading_deg = i == 0 ? 0 : 180;
        e[i].force = i == 0 ? CGS__FORCE__FORCE_FRIENDLY : CGS__FORCE__FORCE_UNKNOWN;
        e[i].kind =
            i == 0 ? CGS__ENTITY_KIND__ENTITY_KIND_WHEELED : CGS__ENTITY_KIND__ENTITY_KIND_TRACKED;
        e[i].active = true;
        e[i].bcis_transponder = i == 0;
        e[i].rcs_class = "vehicle";
        e[i].marking = (char *)marks[i];
        ep[i] = &e[i];
    }
    Cgs__EntityBatch b = CGS__ENTITY_BATCH__INIT;
    b.n_entities = 2;
    b.entities = ep;
    b.batch_count = 1;
    fn (adapter, "entity", &b.base, &hdr);
    Cgs__Enu up = CGS__ENU__INIT;
    Cgs__EnuVelocity uv = CGS__ENU_VELOCITY__INIT;
    up.east_m = 38 * t;
    up.up_m = 1300;
    uv.east_mps = 38;
    Cgs__Uav u = CGS__UAV__INIT;
    u.name = (char *)uav_name;
    u.entity_id = strcmp (uav_name, "uav1") == 0 ? 1 : 2;
    u.position = &up;
    u.velocity = &uv;
    u.heading_deg = 90;
    fn (adapter, "uav", &u.base, &hdr);
}

static void s_mti_deliver (void *a, const char *topic, const ProtobufCMessage *m,
                           const Cgs__Header *h)
{
    mti_adapter_on_message (a, topic, m, h);
}

static void s_bcis_deliver (void *a, const char *topic, const ProtobufCMessage *m,
                            const Cgs__Header *h)
{
    bcis_adapter_on_message (a, topic, m, h);
}

/* ---- mtid --------------------------------------------------------------------------- */

static void test_mti_adapter (void **state)
{
    (void)state;
    s_scene_t sc;
    s_scene (&sc, 0xD1B54A32D192ED03ull);
    mti_params_t p;
    mti_params_defaults (&p);
    mti_adapter_t *a = mti_adapter_new (&p, &sc.sensor, &sc.port);
    assert_non_null (a);
    assert_string_equal (mti_adapter_topics[0], "entity");
    assert_string_equal (mti_adapter_topics[1], "uav");
    assert_null (mti_adapter_topics[2]);
    // Another UAV's messages: nothing runs.
    for (int k = 0; k <= 50; k++)
        s_tick (s_mti_deliver, a, k * 0.1, "uav2");
    assert_int_equal (sc.seen.n, 0);
    // Two scans and a little more, at 10 Hz.
    for (int k = 0; k <= 205; k++)
        s_tick (s_mti_deliver, a, k * 0.1, "uav1");
    const mti_adapter_stats_t *st = mti_adapter_stats (a);
    uint32_t per_scan = mti_radar_dwells_per_scan (mti_adapter_radar (a));
    double dwell_s = mti_radar_dwell_s (mti_adapter_radar (a));
    assert_true (fabs (per_scan * dwell_s - 10.0) < 0.5); // 360 deg at 36 deg/s
    assert_int_equal (s_count (&sc.seen, "mti"), st->dwells_run);
    assert_int_equal (s_count (&sc.seen, "mti.truth"), st->dwells_run);
    assert_int_equal (s_count (&sc.seen, "mti.scan"), 2);
    assert_true (st->dwells_run >= 2 * per_scan - 1 && st->dwells_run < 3 * per_scan);
    // Dwells in order (numbered within their scan), each truth right after
    // its hits; scans numbered 1, 2. The dwell under way at the first `uav`
    // message (dwell 0) is not run: the radar starts with the next one.
    uint32_t next_dwell = 1, scans = 0, scan_hits = 0;
    bool friend_seen = false, other_seen = false;
    size_t near_friend = 0, near_other = 0;
    double last_t = -1;
    for (size_t i = 0; i < sc.seen.n; i++) {
        assert_true (sc.seen.times[i] >= last_t);
        last_t = sc.seen.times[i];
        if (strcmp (sc.seen.topics[i], "mti") == 0) {
            const Cgs__Mti *m = (const Cgs__Mti *)sc.seen.msgs[i];
            assert_int_equal (m->uav_id, 1);
            assert_int_equal (m->scan_number, scans + 1);
            assert_int_equal (m->dwell_number, next_dwell);
            assert_non_null (m->platform_position);
            assert_string_equal (sc.seen.topics[i + 1], "mti.truth");
            next_dwell++;
            scan_hits += (uint32_t)m->n_hits;
            for (size_t k = 0; k < m->n_hits; k++) {
                const Cgs__MtiHit *h = m->hits[k];
                double t = h->sim_time_s;
                if (hypot (h->position->east_m, h->position->north_m - (3000 + 10 * t)) < 150)
                    near_friend++;
                if (hypot (h->position->east_m, h->position->north_m + (3000 + 10 * t)) < 150)
                    near_other++;
            }
        } else if (strcmp (sc.seen.topics[i], "mti.truth") == 0) {
            const Cgs__MtiTruth *m = (const Cgs__MtiTruth *)sc.seen.msgs[i];
            for (size_t k = 0; k < m->n_items; k++) {
                assert_true (m->items[k]->in_beam);
                friend_seen |= m->items[k]->entity_id == 3 && m->items[k]->visible;
                other_seen |= m->items[k]->entity_id == 4 && m->items[k]->visible;
            }
        } else {
            assert_string_equal (sc.seen.topics[i], "mti.scan");
            const Cgs__MtiScan *m = (const Cgs__MtiScan *)sc.seen.msgs[i];
            assert_int_equal (m->scan_number, scans + 1);
            assert_int_equal (next_dwell, per_scan); // every dwell of it
            next_dwell = 0;
            assert_true (m->full_revolution);
            assert_true (fabs (m->scan_end_s - m->scan_start_s - 10.0) < 0.5);
            assert_int_equal (m->hit_count, scan_hits);
            assert_true (sc.seen.times[i] == m->scan_end_s);
            scans++;
            scan_hits = 0;
        }
    }
    assert_true (friend_seen && other_seen);
    assert_true (near_friend >= 1 && near_other >= 1);
    // Malformed: bad input, nothing runs.
    size_t before = sc.seen.n;
    Cgs__Header hdr = CGS__HEADER__INIT;
    hdr.sim_time_s = 21;
    Cgs__Uav u = CGS__UAV__INIT;
    u.name = "uav1";
    u.entity_id = 1;
    mti_adapter_on_message (a, "uav", &u.base, &hdr);
    assert_int_equal (sc.seen.bad, 1);
    assert_non_null (strstr (sc.seen.last_bad, "uav message"));
    assert_int_equal (sc.seen.n, before);
    // Time going back (a restarted uavsim): reported, and the scan follows.
    size_t notices = sc.seen.notices;
    s_tick (s_mti_deliver, a, 2.0, "uav1");
    assert_int_equal (sc.seen.notices, notices + 1);
    assert_non_null (strstr (sc.seen.last_log, "went back"));
    mti_adapter_destroy (&a);
    assert_null (a);
    mti_adapter_destroy (&a);
    s_scene_free (&sc);
}

/* ---- bcisd -------------------------------------------------------------------------- */

static void test_bcis_adapter (void **state)
{
    (void)state;
    s_scene_t sc;
    s_scene (&sc, 0xC2B2AE3D27D4EB4Full);
    bcis_params_t p;
    bcis_params_defaults (&p);
    bcis_adapter_t *a = bcis_adapter_new (&p, &sc.sensor, &sc.port);
    assert_non_null (a);
    const cgs_scan_t *scan = bcis_adapter_scan (a);
    double period = scan->dwells * scan->dwell_s; // 6 s at 60 deg/s
    for (int k = 0; k <= (int)(2 * period * 10) + 5; k++)
        s_tick (s_bcis_deliver, a, k * 0.1, "uav1");
    const bcis_adapter_stats_t *st = bcis_adapter_stats (a);
    size_t markers = 0, interrogations = 0, replies = 0;
    for (size_t i = 0; i < sc.seen.n; i++) {
        assert_string_equal (sc.seen.topics[i], "bcis");
        const Cgs__Bcis *m = (const Cgs__Bcis *)sc.seen.msgs[i];
        assert_int_equal (m->uav_id, 1);
        if (m->scan_end) {
            assert_int_equal (m->scan_number, markers + 1);
            assert_int_equal (m->n_replies, 0);
            markers++;
            continue;
        }
        interrogations++;
        for (size_t k = 0; k < m->n_replies; k++) {
            // Only the transponder answers, from about where it is.
            assert_int_equal (m->replies[k]->responder_id, 3);
            assert_string_equal (m->replies[k]->marking, "FRIEND");
            double t = m->replies[k]->sim_time_s;
            assert_true (hypot (m->replies[k]->position->east_m,
                                m->replies[k]->position->north_m - (3000 + 10 * t)) < 200);
            replies++;
        }
    }
    assert_int_equal (markers, 2);
    assert_int_equal (interrogations, st->dwells_run);
    assert_int_equal (replies, st->replies);
    assert_true (replies >= 2); // one pass of the beam a scan at least
    assert_true (st->interrogated >= replies);
    bcis_adapter_destroy (&a);
    assert_null (a);
    s_scene_free (&sc);
}

int main (void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test (test_mti_adapter),
        cmocka_unit_test (test_bcis_adapter),
    };
    return cmocka_run_group_tests (tests, NULL, NULL);
}
