/* Unit tests of uavsim_world and uavsim_msgs: the same seed gives the same
 * world; a checkpoint restored into a fresh world continues bit for bit; a
 * damaged checkpoint or one of another scenario is refused and changes
 * nothing; the messages carry what the models say (heights on the terrain,
 * inactive before the start time, batches of UAVSIM_MSGS_BATCH). */
#include "cgs_ckpt.h"
#include "cgs_util.h"
#include "uavsim_msgs.h"
#include "uavsim_world.h"

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char *s_text = "[terrain]\n"
                            "seed = 7\n"
                            "size_m = 6000\n"
                            "resolution_m = 50\n"
                            "relief_m = 150\n"
                            "[uav uav1]\n"
                            "position = -2000 -2000\n"
                            "loiter_radius_m = 800\n"
                            "[vehicle a]\n"
                            "force = friendly\n"
                            "point = 0 0\n"
                            "point = 1000 0\n"
                            "point = 1000 1000\n"
                            "end = loop\n"
                            "deviation_m = 20\n"
                            "[vehicle b]\n"
                            "force = unknown\n"
                            "kind = wheeled\n"
                            "start_time_s = 20\n"
                            "point = -500 500\n"
                            "point = 500 -500 @ 6\n"
                            "point = 1500 -400\n"
                            "end = reverse\n";

static uavsim_world_t *s_world (const char *text, uint64_t seed)
{
    cgs_scenario_t *sc = NULL;
    char err[512] = "";
    if (cgs_scenario_load_string ("test.ini", text, NULL, seed, &sc, err, sizeof err) < 0)
        fail_msg ("%s", err);
    uavsim_world_t *w = NULL;
    if (uavsim_world_new (sc, NULL, &w, err, sizeof err) < 0)
        fail_msg ("%s", err);
    return w;
}

static void s_steps (uavsim_world_t *w, int n)
{
    for (int i = 0; i < n; i++)
        uavsim_world_step (w);
}

/* Seal a forged frame again: its payload's CRC-32 in the last 4 bytes. */
static void s_reseal (uint8_t *b, size_t len)
{
    uint32_t c = cgs_crc32 (b + CGS_CKPT_HEAD, len - CGS_CKPT_HEAD - CGS_CKPT_TAIL);
    for (int i = 0; i < 4; i++)
        b[len - 4 + i] = (uint8_t)(c >> (8 * i));
}

/* The world's checkpoint bytes: equal bytes, equal worlds. */
static uint8_t *s_save (uavsim_world_t *w, size_t *len)
{
    uint8_t *buf = NULL;
    assert_int_equal (uavsim_world_save (w, &buf, len), 0);
    return buf;
}

static void test_same_seed_same_world (void **state)
{
    (void)state;
    uavsim_world_t *a = s_world (s_text, 1), *b = s_world (s_text, 1), *c = s_world (s_text, 2);
    s_steps (a, 1200);
    s_steps (b, 1200);
    s_steps (c, 1200);
    assert_true (fabs (uavsim_world_time (a) - 60.0) < 1e-9);
    size_t la, lb, lc;
    uint8_t *sa = s_save (a, &la), *sb = s_save (b, &lb), *sc = s_save (c, &lc);
    assert_int_equal (la, lb);
    assert_memory_equal (sa, sb, la);
    // Another exercise seed: other hills are not drawn (the terrain seed is
    // given) but the deviation of vehicle a is, so its track differs.
    assert_int_equal (la, lc);
    assert_memory_not_equal (sa, sc, la);
    free (sa);
    free (sb);
    free (sc);
    uavsim_world_destroy (&a);
    uavsim_world_destroy (&b);
    uavsim_world_destroy (&c);
    assert_null (a);
    uavsim_world_destroy (&a);
}

static void test_checkpoint_continues_bit_for_bit (void **state)
{
    (void)state;
    uavsim_world_t *a = s_world (s_text, 1);
    s_steps (a, 437);
    // Task the UAV mid-run, so the task is in the checkpoint too.
    cgs_enu_t pts[2] = {{0, 0, 0}, {1500, 500, 0}};
    assert_int_equal (uavsim_uav_route (uavsim_world_uav (a, 0), pts, 2, true, 0, true), 0);
    s_steps (a, 100);
    size_t len;
    uint8_t *ck = s_save (a, &len);
    uavsim_world_t *b = s_world (s_text, 1);
    char err[256];
    assert_int_equal (uavsim_world_restore (b, ck, len, err, sizeof err), 0);
    assert_int_equal (uavsim_world_tick (b), 537);
    assert_true (uavsim_world_time (b) == uavsim_world_time (a));
    uavsim_uav_state_t ua, ub;
    uavsim_uav_state (uavsim_world_uav (b, 0), &ub);
    assert_int_equal (ub.mode, UAVSIM_UAV_MODE_ROUTE);
    s_steps (a, 3000);
    s_steps (b, 3000);
    size_t la, lb;
    uint8_t *sa = s_save (a, &la), *sb = s_save (b, &lb);
    assert_int_equal (la, lb);
    assert_memory_equal (sa, sb, la);
    uavsim_uav_state (uavsim_world_uav (a, 0), &ua);
    uavsim_uav_state (uavsim_world_uav (b, 0), &ub);
    assert_true (ua.position.e_m == ub.position.e_m && ua.task_number == ub.task_number);
    free (ck);
    free (sa);
    free (sb);
    uavsim_world_destroy (&a);
    uavsim_world_destroy (&b);
}

static void test_bad_checkpoints_change_nothing (void **state)
{
    (void)state;
    uavsim_world_t *a = s_world (s_text, 1);
    s_steps (a, 300);
    size_t len;
    uint8_t *ck = s_save (a, &len);
    uavsim_world_t *b = s_world (s_text, 1);
    s_steps (b, 10);
    size_t lb0;
    uint8_t *before = s_save (b, &lb0);
    char err[256];
    // A flipped byte in each part: the magic, the header, the UAV, a
    // vehicle, the CRC.
    size_t spots[] = {3, 20, 60, len / 2, len - 1};
    int want[] = {-EPROTO, -EBADMSG, -EBADMSG, -EBADMSG, -EBADMSG};
    for (size_t i = 0; i < 5; i++) {
        ck[spots[i]] ^= 0x20;
        assert_int_equal (uavsim_world_restore (b, ck, len, err, sizeof err), want[i]);
        ck[spots[i]] ^= 0x20;
        size_t l;
        uint8_t *now = s_save (b, &l);
        assert_int_equal (l, lb0);
        assert_memory_equal (now, before, l);
        free (now);
    }
    assert_int_equal (uavsim_world_restore (b, ck, len - 5, err, sizeof err), -EINVAL);
    assert_non_null (strstr (err, "truncated"));
    // Sealed, but an entity's own frame damaged: refused naming the entity,
    // and a restore that fails part way leaves the world as it was.
    uint8_t *forged = malloc (len);
    memcpy (forged, ck, len);
    // Inside the last vehicle's frame, before the one UAV's camera settings
    // (their 8-byte length and UAVSIM_CAMERA_SAVED bytes).
    forged[len - CGS_CKPT_TAIL - 10 - 8 - UAVSIM_CAMERA_SAVED] ^= 0x01;
    s_reseal (forged, len);
    assert_int_equal (uavsim_world_restore (b, forged, len, err, sizeof err), -EBADMSG);
    assert_non_null (strstr (err, "vehicle b: "));
    size_t lf;
    uint8_t *now = s_save (b, &lf);
    assert_int_equal (lf, lb0);
    assert_memory_equal (now, before, lf);
    free (now);
    // Sealed, the camera settings damaged: refused naming the UAV.
    memcpy (forged, ck, len);
    double bad = 500; // a depression of 500 degrees
    memcpy (forged + len - CGS_CKPT_TAIL - UAVSIM_CAMERA_SAVED, &bad, sizeof bad);
    s_reseal (forged, len);
    assert_int_equal (uavsim_world_restore (b, forged, len, err, sizeof err), -EPROTO);
    assert_non_null (strstr (err, "uav uav1: its camera settings"));
    now = s_save (b, &lf);
    assert_memory_equal (now, before, lf);
    free (now);
    free (forged);
    // The world's frame as an older uavsim wrote it ("UAVSIMW1"): refused.
    uint8_t old[48] = "UAVSIMW1\x01\x00\x00\x00";
    assert_int_equal (uavsim_world_restore (b, old, sizeof old, err, sizeof err), -EPROTO);
    assert_non_null (strstr (err, "it begins \"UAVS\""));
    // A checkpoint of another scenario (one vehicle fewer).
    const char *cut = strstr (s_text, "[vehicle b]");
    char other[2048];
    snprintf (other, sizeof other, "%.*s", (int)(cut - s_text), s_text);
    uavsim_world_t *c = s_world (other, 1);
    assert_int_equal (uavsim_world_restore (c, ck, len, err, sizeof err), -EPROTO);
    assert_non_null (strstr (err, "another scenario"));
    // The same entities with another step: simulation time would be wrong.
    char stepped[2048];
    snprintf (stepped, sizeof stepped, "%s[uavsim]\nstep_s = 0.1\n", s_text);
    uavsim_world_t *d = s_world (stepped, 1);
    assert_int_equal (uavsim_world_restore (d, ck, len, err, sizeof err), -EPROTO);
    assert_non_null (strstr (err, "another scenario"));
    uavsim_world_destroy (&d);
    assert_int_equal (uavsim_world_restore (b, ck, len, err, sizeof err), 0);
    free (ck);
    free (before);
    uavsim_world_destroy (&a);
    uavsim_world_destroy (&b);
    uavsim_world_destroy (&c);
}

static void test_messages_follow_the_models (void **state)
{
    (void)state;
    uavsim_world_t *w = s_world (s_text, 1);
    uavsim_msgs_t *m = uavsim_msgs_new (w);
    assert_non_null (m);
    s_steps (w, 200); // 10 s: vehicle b has not started
    assert_int_equal (uavsim_msgs_entities (m, w), 1);
    Cgs__EntityBatch *b = uavsim_msgs_batch (m, 0);
    assert_int_equal (b->n_entities, 3);
    assert_int_equal (b->batch_count, 1);
    const cgs_terrain_t *t = uavsim_world_terrain (w);
    const Cgs__Entity *uav = b->entities[0], *va = b->entities[1], *vb = b->entities[2];
    assert_int_equal (uav->kind, CGS__ENTITY_KIND__ENTITY_KIND_AIR);
    assert_true (va->active);
    assert_false (vb->active); // before its start time
    assert_int_equal (vb->force, CGS__FORCE__FORCE_UNKNOWN);
    assert_int_equal (vb->kind, CGS__ENTITY_KIND__ENTITY_KIND_WHEELED);
    assert_true (va->bcis_transponder);
    assert_false (vb->bcis_transponder);
    // Vehicles sit on the terrain; the UAV is its commanded height above it.
    double h = cgs_terrain_height_clamped (t, va->position->east_m, va->position->north_m);
    assert_true (fabs (va->position->up_m - h) < 1e-6);
    Cgs__Uav *u = uavsim_msgs_uav (m, w, 0);
    assert_int_equal (u->entity_id, uav->entity_id);
    assert_true (fabs (u->altitude_agl_m - 1200) < 50); // default AGL, still settling
    assert_true (u->sensor->depression_deg == 45);
    s_steps (w, 400); // 30 s
    uavsim_msgs_entities (m, w);
    assert_true (vb->active);
    assert_true (vb->speed_mps > 0);
    Cgs__Clock *c = uavsim_msgs_clock (m, w, 4, true, (cgs_geodetic_t){35.96, -121.23, 0});
    assert_true (fabs (c->sim_time_s - 30.0) < 1e-9);
    assert_true (c->paused && c->time_scale == 4 && c->tick == 600);
    uavsim_msgs_destroy (&m);
    uavsim_world_destroy (&w);
}

/* More entities than one batch holds: several batches, every entity once. */
static void test_batches (void **state)
{
    (void)state;
    char *text = malloc (200000);
    size_t n = (size_t)snprintf (text, 200000, "[uav u]\nposition = 0 0\n");
    for (int i = 0; i < 450; i++)
        n += (size_t)snprintf (text + n, 200000 - n,
                               "[vehicle v%d]\nforce = hostile\npoint = %d 0\npoint = %d 100\n", i,
                               i * 10 - 2000, i * 10 - 2000);
    uavsim_world_t *w = s_world (text, 1);
    free (text);
    uavsim_msgs_t *m = uavsim_msgs_new (w);
    size_t nb = uavsim_msgs_entities (m, w);
    assert_int_equal (nb, (451 + UAVSIM_MSGS_BATCH - 1) / UAVSIM_MSGS_BATCH);
    size_t total = 0;
    uint32_t last_id = 0;
    for (size_t k = 0; k < nb; k++) {
        Cgs__EntityBatch *b = uavsim_msgs_batch (m, k);
        assert_int_equal (b->batch_index, k);
        assert_int_equal (b->batch_count, nb);
        for (size_t i = 0; i < b->n_entities; i++) {
            assert_true (b->entities[i]->entity_id > last_id);
            last_id = b->entities[i]->entity_id;
        }
        total += b->n_entities;
    }
    assert_int_equal (total, 451);
    assert_null (uavsim_msgs_batch (m, nb));
    uavsim_msgs_destroy (&m);
    uavsim_world_destroy (&w);
}

/* Worked examples of the sensor's boresight. Level flight heading 90°, 45°
 * depression: azimuth 90, elevation -45. Nose up 10° in level flight: the
 * boresight rises by 10° (elevation -35). Banked 90° right (roll 90) at
 * heading 0 with 30° depression: the body's down axis points west, so the
 * boresight (cos 30 forward, sin 30 down) points north and west: azimuth
 * 360 - atan(sin30/cos30) = 330, elevation 0. */
/* A halt in the scenario reaches the vehicle model through the world: the
 * vehicle drives 500 m at 10 m/s, stands 30 s at its halt point (speed 0,
 * the same position), and goes on. */
static void test_halt_in_the_world (void **state)
{
    (void)state;
    uavsim_world_t *w = s_world ("[terrain]\nsize_m = 6000\nresolution_m = 50\nrelief_m = 0\n"
                                 "[uav uav1]\nposition = -2000 -2000\n"
                                 "[vehicle h]\nforce = unknown\nspeed_mps = 10\npoint = 0 0\n"
                                 "point = 500 0 halt 30\npoint = 1500 0\n",
                                 1);
    // At 70 s it has arrived (50 s of driving, braking included) and stands.
    while (uavsim_world_time (w) < 70)
        uavsim_world_step (w);
    uavsim_vehicle_state_t a, b;
    uavsim_vehicle_state (uavsim_world_vehicle (w, 0), &a);
    assert_true (fabs (a.e_m - 500) < 1e-6 && fabs (a.n_m) < 1e-6);
    assert_true (a.halted);
    assert_true (hypot (a.ve_mps, a.vn_mps) == 0);
    while (uavsim_world_time (w) < 75)
        uavsim_world_step (w);
    uavsim_vehicle_state (uavsim_world_vehicle (w, 0), &b);
    assert_true (b.e_m == a.e_m && b.n_m == a.n_m);
    // 30 s after it stopped it goes on.
    while (uavsim_world_time (w) < 110)
        uavsim_world_step (w);
    uavsim_vehicle_state (uavsim_world_vehicle (w, 0), &b);
    assert_false (b.halted);
    assert_true (b.e_m > 520);
    uavsim_world_destroy (&w);
}

static void test_boresight (void **state)
{
    (void)state;
    double az, el;
    uavsim_msgs_boresight (90, 0, 0, 45, &az, &el);
    assert_true (fabs (az - 90) < 1e-9 && fabs (el + 45) < 1e-9);
    uavsim_msgs_boresight (90, 10, 0, 45, &az, &el);
    assert_true (fabs (az - 90) < 1e-9 && fabs (el + 35) < 1e-9);
    uavsim_msgs_boresight (0, 0, 90, 30, &az, &el);
    assert_true (fabs (az - 330) < 1e-9 && fabs (el) < 1e-9);
    uavsim_msgs_boresight (0, 0, 0, 90, &az, &el); // straight down
    assert_true (fabs (el + 90) < 1e-9);
}

int main (void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test (test_same_seed_same_world),
        cmocka_unit_test (test_checkpoint_continues_bit_for_bit),
        cmocka_unit_test (test_bad_checkpoints_change_nothing),
        cmocka_unit_test (test_messages_follow_the_models),
        cmocka_unit_test (test_batches),
        cmocka_unit_test (test_halt_in_the_world),
        cmocka_unit_test (test_boresight),
    };
    return cmocka_run_group_tests (tests, NULL, NULL);
}
