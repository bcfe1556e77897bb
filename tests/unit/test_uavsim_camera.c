/* Unit tests of uavsim's camera settings and the camera command
 * (uavsim_camera, uavsim_adapter): the scenario's start and limits; a
 * command applied whole or refused whole with the reason; the vertical field
 * of view keeping the scenario's aspect; staring at a point (on the terrain)
 * and at guidanced's target estimate moved on to the message's time; the
 * `uav` message carrying the settings, the stare point and the attitude of
 * the very camera cgs_camera builds from that message; the settings kept
 * across a checkpoint. */
#include "cgs_camera.h"
#include "cgs_msg.h"
#include "uavsim_adapter.h"
#include "uavsim_camera.h"
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
                            "size_m = 8000\n"
                            "resolution_m = 50\n"
                            "relief_m = 150\n"
                            "[uav uav1]\n"
                            "position = -2000 -2000\n"
                            "loiter_radius_m = 800\n"
                            "sensor_hfov_deg = 12\n"
                            "sensor_vfov_deg = 9\n"
                            "sensor_depression_min_deg = 20\n"
                            "sensor_depression_max_deg = 80\n"
                            "sensor_hfov_min_deg = 2\n"
                            "sensor_hfov_max_deg = 30\n"
                            "[vehicle a]\n"
                            "force = hostile\n"
                            "point = 0 0\n"
                            "point = 1000 0\n";

static uavsim_world_t *s_world (const char *text)
{
    cgs_scenario_t *sc = NULL;
    char err[512] = "";
    if (cgs_scenario_load_string ("test.ini", text, NULL, 1, &sc, err, sizeof err) < 0)
        fail_msg ("%s", err);
    uavsim_world_t *w = NULL;
    if (uavsim_world_new (sc, NULL, &w, err, sizeof err) < 0)
        fail_msg ("%s", err);
    return w;
}

typedef struct {
    int published;
} s_seen_t;

static int s_publish (void *arg, const char *topic, ProtobufCMessage *msg, double t)
{
    (void)topic, (void)msg, (void)t;
    ((s_seen_t *)arg)->published++;
    return 0;
}

static void s_log (void *arg, int priority, const char *line)
{
    (void)arg, (void)priority, (void)line;
}

static void s_bad (void *arg, const char *what)
{
    (void)arg, (void)what;
}

static void s_error (void *arg, const char *why)
{
    (void)arg, (void)why;
}

/* A camera command through the adapter: the reply's status. */
static int s_command (uavsim_adapter_t *a, Cgs__SetCamera *c, Cgs__Reply *reply)
{
    Cgs__Command cmd = CGS__COMMAND__INIT;
    cmd.client_id = "test";
    cmd.command_number = 1;
    cmd.body_case = CGS__COMMAND__BODY_SET_CAMERA;
    cmd.set_camera = c;
    cgs__reply__init (reply);
    reply->status = CGS__REPLY_STATUS__REPLY_STATUS_OK;
    assert_int_equal (uavsim_adapter_command (a, &cmd, reply), 0);
    return reply->status;
}

static void test_scenario_defaults_and_limits (void **state)
{
    (void)state;
    uavsim_world_t *w = s_world (s_text);
    const cgs_scenario_uav_t *su = &uavsim_world_scenario (w)->uavs[0];
    assert_true (su->sensor_depression_deg == 45 && !su->sensor_stabilized &&
                 !su->sensor_stare_target);
    assert_true (su->gimbal_azimuth_limit_deg == 150 && su->gimbal_elevation_min_deg == -90 &&
                 su->gimbal_elevation_max_deg == 0);
    uavsim_camera_t *c = uavsim_world_camera (w, 0);
    assert_true (c->depression_deg == 45 && c->hfov_deg == 12 && c->vfov_deg == 9);
    assert_int_equal (c->stare, UAVSIM_STARE_OFF);
    assert_null (uavsim_world_camera (w, 1));
    uavsim_world_destroy (&w);
    // A start outside its own limits is refused with file and key.
    cgs_scenario_t *sc = NULL;
    char err[512] = "";
    assert_int_equal (cgs_scenario_load_string ("bad.ini",
                                                "[uav u]\nposition = 0 0\nsensor_depression_deg = "
                                                "30\nsensor_depression_min_deg = 40\n",
                                                NULL, 1, &sc, err, sizeof err),
                      -EINVAL);
    assert_non_null (strstr (err, "bad.ini"));
    assert_non_null (strstr (err, "sensor_depression_deg"));
    assert_int_equal (
        cgs_scenario_load_string ("bad.ini", "[uav u]\nposition = 0 0\nsensor_stare = sometimes\n",
                                  NULL, 1, &sc, err, sizeof err),
        -EINVAL);
    assert_non_null (strstr (err, "sensor_stare"));
}

static void test_set_whole_or_refused (void **state)
{
    (void)state;
    uavsim_world_t *w = s_world (s_text);
    const cgs_scenario_uav_t *su = &uavsim_world_scenario (w)->uavs[0];
    uavsim_camera_t *c = uavsim_world_camera (w, 0);
    char why[256];
    // Zoom in to 6°: the vertical keeps tan(β/2)/tan(γ/2) = tan 4.5° / tan 6°.
    uavsim_camera_cmd_t cmd = {.set = UAVSIM_CAMERA_SET_FOV | UAVSIM_CAMERA_SET_DEPRESSION,
                               .hfov_deg = 6,
                               .depression_deg = 30};
    assert_int_equal (uavsim_camera_set (c, su, uavsim_world_terrain (w), &cmd, why, sizeof why),
                      0);
    double k = tan (4.5 * M_PI / 180) / tan (6 * M_PI / 180);
    assert_true (fabs (tan (c->vfov_deg * M_PI / 360) - k * tan (3 * M_PI / 180)) < 1e-12);
    assert_true (c->depression_deg == 30 && c->hfov_deg == 6);
    // One value outside its limit: nothing changes.
    uavsim_camera_t before = *c;
    cmd = (uavsim_camera_cmd_t){.set = UAVSIM_CAMERA_SET_FOV | UAVSIM_CAMERA_SET_DEPRESSION,
                                .hfov_deg = 10,
                                .depression_deg = 85};
    assert_int_equal (uavsim_camera_set (c, su, uavsim_world_terrain (w), &cmd, why, sizeof why),
                      -EINVAL);
    assert_non_null (strstr (why, "depression 85"));
    assert_memory_equal (c, &before, sizeof before);
    cmd = (uavsim_camera_cmd_t){.set = UAVSIM_CAMERA_SET_FOV, .hfov_deg = 1};
    assert_int_equal (uavsim_camera_set (c, su, NULL, &cmd, why, sizeof why), -EINVAL);
    assert_non_null (strstr (why, "field of view"));
    cmd = (uavsim_camera_cmd_t){.set = 0};
    assert_int_equal (uavsim_camera_set (c, su, NULL, &cmd, why, sizeof why), -EINVAL);
    cmd = (uavsim_camera_cmd_t){.set = 16};
    assert_int_equal (uavsim_camera_set (c, su, NULL, &cmd, why, sizeof why), -EINVAL);
    cmd = (uavsim_camera_cmd_t){.set = UAVSIM_CAMERA_SET_STARE, .stare = 7};
    assert_int_equal (uavsim_camera_set (c, su, NULL, &cmd, why, sizeof why), -EINVAL);
    // A stare point off the terrain, or not a number.
    cmd = (uavsim_camera_cmd_t){
        .set = UAVSIM_CAMERA_SET_STARE, .stare = UAVSIM_STARE_POINT, .stare_point = {9000, 0, 0}};
    assert_int_equal (uavsim_camera_set (c, su, uavsim_world_terrain (w), &cmd, why, sizeof why),
                      -EINVAL);
    assert_non_null (strstr (why, "not on the terrain"));
    cmd.stare_point.e_m = NAN;
    assert_int_equal (uavsim_camera_set (c, su, uavsim_world_terrain (w), &cmd, why, sizeof why),
                      -EINVAL);
    assert_memory_equal (c, &before, sizeof before);
    uavsim_world_destroy (&w);
}

static void test_stare_points (void **state)
{
    (void)state;
    uavsim_world_t *w = s_world (s_text);
    const cgs_scenario_uav_t *su = &uavsim_world_scenario (w)->uavs[0];
    const cgs_terrain_t *t = uavsim_world_terrain (w);
    uavsim_camera_t *c = uavsim_world_camera (w, 0);
    char why[256];
    cgs_enu_t p;
    assert_false (uavsim_camera_stare_at (c, t, 0, &p));
    uavsim_camera_cmd_t cmd = {.set = UAVSIM_CAMERA_SET_STARE,
                               .stare = UAVSIM_STARE_POINT,
                               .stare_point = {300, -200, 999}};
    assert_int_equal (uavsim_camera_set (c, su, t, &cmd, why, sizeof why), 0);
    assert_true (uavsim_camera_stare_at (c, t, 5, &p));
    assert_true (p.e_m == 300 && p.n_m == -200);
    assert_true (p.u_m == cgs_terrain_height_clamped (t, 300, -200)); // on the ground
    // The target: none yet, then guidanced's estimate moved on to the time asked.
    cmd.stare = UAVSIM_STARE_TARGET;
    assert_int_equal (uavsim_camera_set (c, su, t, &cmd, why, sizeof why), 0);
    assert_false (uavsim_camera_stare_at (c, t, 5, &p));
    uavsim_camera_target (c, true, (cgs_enu_t){100, 100, 0}, (cgs_enu_t){10, -5, 0}, 10);
    assert_true (uavsim_camera_stare_at (c, t, 12, &p));
    assert_true (fabs (p.e_m - 120) < 1e-12 && fabs (p.n_m - 90) < 1e-12);
    assert_true (p.u_m == cgs_terrain_height_clamped (t, 120, 90));
    uavsim_camera_target (c, false, (cgs_enu_t){0}, (cgs_enu_t){0}, 12);
    assert_false (uavsim_camera_stare_at (c, t, 12, &p));
    uavsim_camera_target (c, true, (cgs_enu_t){NAN, 0, 0}, (cgs_enu_t){0}, 12);
    assert_false (uavsim_camera_stare_at (c, t, 12, &p));
    uavsim_world_destroy (&w);
}

/* Through the adapter: the command, the intercept intake and the message. */
static void test_command_and_message (void **state)
{
    (void)state;
    uavsim_world_t *w = s_world (s_text);
    s_seen_t seen = {0};
    cgs_port_t port = {&seen, s_publish, s_log, s_bad, s_error};
    uavsim_adapter_t *a = uavsim_adapter_new (w, (cgs_geodetic_t){36, -121, 0}, &port);
    assert_non_null (a);
    for (int i = 0; i < 30; i++)
        uavsim_adapter_step (a);
    Cgs__SetCamera c = CGS__SET_CAMERA__INIT;
    Cgs__Reply reply;
    c.set = 8 | 4;
    c.stabilized = true;
    c.stare = CGS__STARE_MODE__STARE_MODE_TARGET;
    int published = seen.published;
    assert_int_equal (s_command (a, &c, &reply), CGS__REPLY_STATUS__REPLY_STATUS_OK);
    assert_non_null (strstr (reply.detail, "stabilized"));
    assert_true (seen.published > published); // the UAV republished at once
    c.set = 1;
    c.depression_deg = 10;
    assert_int_equal (s_command (a, &c, &reply), CGS__REPLY_STATUS__REPLY_STATUS_ERROR);
    assert_non_null (strstr (reply.error, "depression"));
    c.uav_id = 999;
    assert_int_equal (s_command (a, &c, &reply), CGS__REPLY_STATUS__REPLY_STATUS_ERROR);
    // guidanced's intercept with a target.
    const cgs_scenario_uav_t *su = &uavsim_world_scenario (w)->uavs[0];
    Cgs__Intercept m = CGS__INTERCEPT__INIT;
    Cgs__Enu tp = CGS__ENU__INIT;
    Cgs__EnuVelocity tv = CGS__ENU_VELOCITY__INIT;
    tp.east_m = 500, tp.north_m = 400;
    tv.east_mps = 8;
    m.uav_id = su->id, m.track_id = 3, m.has_target = true, m.target = &tp;
    m.target_velocity = &tv;
    double t0 = uavsim_world_time (w);
    uavsim_adapter_on_intercept (a, &m, t0);
    uavsim_adapter_step (a);
    double t1 = uavsim_world_time (w);
    uavsim_msgs_t *msgs = uavsim_msgs_new (w);
    Cgs__Uav *u = uavsim_msgs_uav (msgs, w, 0);
    assert_true (u->sensor->stabilized && u->sensor->staring);
    assert_int_equal (u->sensor->stare, CGS__STARE_MODE__STARE_MODE_TARGET);
    assert_true (fabs (u->sensor->stare_point->east_m - (500 + 8 * (t1 - t0))) < 1e-9);
    assert_true (u->sensor->gimbal_azimuth_limit_deg == 150);
    // The attitude on the message is that of the camera built from the message.
    cgs_camera_in_t in = {.width_px = 64, .height_px = 48, .near_m = 1, .far_m = 1e4};
    assert_int_equal (cgs_msg_uav_camera (u, &in), 0);
    cgs_camera_t cam;
    assert_int_equal (cgs_camera_make (&in, &cam), 0);
    assert_true (fabs (cam.heading_deg - u->sensor_azimuth_deg) < 1e-9);
    assert_true (fabs (cam.pitch_deg - u->sensor_elevation_deg) < 1e-9);
    assert_true (fabs (cam.roll_deg - u->sensor_roll_deg) < 1e-9);
    assert_int_equal (cam.at_gimbal_limit, u->sensor->at_gimbal_limit);
    if (!cam.at_gimbal_limit) { // looking at the stare point
        double x, y, z;
        cgs_enu_t sp = {u->sensor->stare_point->east_m, u->sensor->stare_point->north_m,
                        u->sensor->stare_point->up_m};
        assert_true (cgs_camera_project (&cam, sp, &x, &y, &z));
        assert_true (fabs (x - 32) < 1e-6 && fabs (y - 24) < 1e-6);
    }
    // Another UAV's intercept (or one without a track) leaves the target / drops it.
    m.track_id = 0;
    uavsim_adapter_on_intercept (a, &m, t1);
    u = uavsim_msgs_uav (msgs, w, 0);
    assert_false (u->sensor->staring);
    assert_null (u->sensor->stare_point);
    uavsim_msgs_destroy (&msgs);
    uavsim_adapter_destroy (&a);
    uavsim_world_destroy (&w);
}

/* The settings survive the world's checkpoint; the target estimate does not
 * need to (the next intercept brings it). */
static void test_checkpoint (void **state)
{
    (void)state;
    uavsim_world_t *w = s_world (s_text), *w2 = s_world (s_text);
    const cgs_scenario_uav_t *su = &uavsim_world_scenario (w)->uavs[0];
    uavsim_camera_t *c = uavsim_world_camera (w, 0);
    char why[256], err[256];
    uavsim_camera_cmd_t cmd = {.set = 15,
                               .depression_deg = 60,
                               .hfov_deg = 3,
                               .stabilized = true,
                               .stare = UAVSIM_STARE_POINT,
                               .stare_point = {-100, 250, 0}};
    assert_int_equal (uavsim_camera_set (c, su, uavsim_world_terrain (w), &cmd, why, sizeof why),
                      0);
    uint8_t *buf = NULL;
    size_t len = 0;
    assert_int_equal (uavsim_world_save (w, &buf, &len), 0);
    assert_int_equal (uavsim_world_restore (w2, buf, len, err, sizeof err), 0);
    uavsim_camera_t *c2 = uavsim_world_camera (w2, 0);
    assert_true (c2->depression_deg == 60 && c2->hfov_deg == 3 && c2->vfov_deg == c->vfov_deg &&
                 c2->stabilized && c2->stare == UAVSIM_STARE_POINT);
    assert_true (c2->stare_point.e_m == -100 && c2->stare_point.n_m == 250 &&
                 c2->stare_point.u_m == c->stare_point.u_m);
    // Damaged settings are refused, and the world is left as it was.
    uint8_t saved[UAVSIM_CAMERA_SAVED];
    uavsim_camera_save (c, saved);
    double bad = 500;
    memcpy (saved, &bad, sizeof bad); // depression 500
    uavsim_camera_t x = *c2;
    assert_int_equal (uavsim_camera_load (&x, su, saved, sizeof saved), -EPROTO);
    assert_int_equal (uavsim_camera_load (&x, su, saved, sizeof saved - 1), -EPROTO);
    assert_memory_equal (&x, c2, sizeof x);
    free (buf);
    uavsim_world_destroy (&w);
    uavsim_world_destroy (&w2);
}

int main (void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test (test_scenario_defaults_and_limits),
        cmocka_unit_test (test_set_whole_or_refused),
        cmocka_unit_test (test_stare_points),
        cmocka_unit_test (test_command_and_message),
        cmocka_unit_test (test_checkpoint),
    };
    return cmocka_run_group_tests (tests, NULL, NULL);
}
