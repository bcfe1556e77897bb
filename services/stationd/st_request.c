/* st_request — a page's command request checked and made into the command
 * (see st_request.h). */
#include "st_request.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

static const char *const s_commands[] = {
    "designate",      "cancel",      "altitude",    "speed",        "footprint_scale",
    "intercept_mode", "camera",      "sensor_mode", "replay_pause", "replay_resume",
    "replay_speed",   "replay_seek", NULL};

bool st_request_is_command (const char *op)
{
    for (int i = 0; op && s_commands[i]; i++)
        if (strcmp (op, s_commands[i]) == 0)
            return true;
    return false;
}

bool st_request_is_replay (const char *op)
{
    return op && strncmp (op, "replay_", 7) == 0 && st_request_is_command (op);
}

/* A finite number; false when v is not a number or not finite. */
static bool s_finite (json_object *v, double *ret)
{
    json_type t = json_object_get_type (v);
    if (t != json_type_double && t != json_type_int)
        return false;
    double d = json_object_get_double (v);
    if (!isfinite (d))
        return false;
    *ret = d;
    return true;
}

bool st_request_number (json_object *o, const char *key, double *ret)
{
    json_object *v;
    return json_object_object_get_ex (o, key, &v) && s_finite (v, ret);
}

static bool s_whole (double v, double max)
{
    return v >= 0 && v <= max && v == floor (v);
}

/* The string field key ("" when absent or not a string). */
static const char *s_string (json_object *o, const char *key)
{
    json_object *v;
    return json_object_object_get_ex (o, key, &v) && json_object_is_type (v, json_type_string)
               ? json_object_get_string (v)
               : "";
}

static int s_refuse (char *why, size_t whylen, const char *reason)
{
    snprintf (why, whylen, "%s", reason);
    return -EINVAL;
}

/* A point {e, n} on the ground, in metres within ST_POINT_MAX_M. */
static bool s_point (json_object *v, Cgs__Enu *ret)
{
    double e, n;
    if (!json_object_is_type (v, json_type_object) || !st_request_number (v, "e", &e) ||
        !st_request_number (v, "n", &n) || fabs (e) > ST_POINT_MAX_M || fabs (n) > ST_POINT_MAX_M)
        return false;
    ret->east_m = e;
    ret->north_m = n;
    ret->up_m = 0;
    return true;
}

static int s_designate (json_object *req, st_command_t *c, char *why, size_t whylen)
{
    double hit_id = 0, radar = 0, e, n;
    if (st_request_number (req, "hit", &hit_id)) {
        // The clicked hit: guidanced designates the track that took it.
        // A radar given must be a whole number (absent: any radar).
        bool radar_given = json_object_object_get_ex (req, "radar", NULL);
        if (!(hit_id >= 1 && s_whole (hit_id, UINT32_MAX)) ||
            (radar_given &&
             !(st_request_number (req, "radar", &radar) && s_whole (radar, UINT32_MAX))))
            return s_refuse (why, whylen,
                             "designate: hit and radar must be whole numbers (a hit id >= 1)");
        c->hit.hit_id = (uint32_t)hit_id;
        c->hit.radar_uav_id = (uint32_t)radar;
        c->designate.target_case = CGS__DESIGNATE__TARGET_HIT;
        c->designate.hit = &c->hit;
    } else if (!st_request_number (req, "e", &e) || !st_request_number (req, "n", &n)) {
        return s_refuse (why, whylen,
                         "designate needs the clicked hit (hit, radar) or a point (e, n)");
    } else {
        c->point.east_m = e;
        c->point.north_m = n;
        c->designate.target_case = CGS__DESIGNATE__TARGET_POINT;
        c->designate.point = &c->point;
    }
    c->designate.uav_id = c->uav_id;
    c->cmd.body_case = CGS__COMMAND__BODY_DESIGNATE;
    c->cmd.designate = &c->designate;
    return 0;
}

/* The camera: only the fields given are set (their bits), each checked. */
static int s_camera (json_object *req, st_command_t *c, char *why, size_t whylen)
{
    Cgs__SetCamera *k = &c->camera;
    json_object *v;
    double d;
    k->uav_id = c->uav_id;
    if (json_object_object_get_ex (req, "depression", &v)) {
        if (!s_finite (v, &d) || fabs (d) > ST_DEPRESSION_MAX_DEG)
            return s_refuse (why, whylen,
                             "camera: depression must be a number of degrees in [-90, 90]");
        k->set |= ST_CAMERA_SET_DEPRESSION;
        k->depression_deg = d;
    }
    if (json_object_object_get_ex (req, "fov", &v)) {
        if (!s_finite (v, &d) || !(d > 0 && d < ST_FOV_MAX_DEG))
            return s_refuse (why, whylen,
                             "camera: fov (the horizontal field of view) must be a number of "
                             "degrees in (0, 180)");
        k->set |= ST_CAMERA_SET_FOV;
        k->hfov_deg = d;
    }
    if (json_object_object_get_ex (req, "stabilized", &v)) {
        if (!json_object_is_type (v, json_type_boolean))
            return s_refuse (why, whylen, "camera: stabilized must be true or false");
        k->set |= ST_CAMERA_SET_STABILIZED;
        k->stabilized = json_object_get_boolean (v);
    }
    if (json_object_object_get_ex (req, "stare", &v)) {
        const char *s = json_object_is_type (v, json_type_string) ? json_object_get_string (v) : "";
        if (strcmp (s, "off") == 0) {
            k->stare = CGS__STARE_MODE__STARE_MODE_OFF;
        } else if (strcmp (s, "target") == 0) {
            k->stare = CGS__STARE_MODE__STARE_MODE_TARGET;
        } else if (s_point (v, &c->stare_point)) {
            k->stare = CGS__STARE_MODE__STARE_MODE_POINT;
            k->stare_point = &c->stare_point;
        } else {
            return s_refuse (why, whylen,
                             "camera: stare must be \"off\", \"target\" or a point {e, n} "
                             "(metres, finite)");
        }
        k->set |= ST_CAMERA_SET_STARE;
    }
    if (!k->set)
        return s_refuse (why, whylen,
                         "camera needs at least one of depression, fov, stabilized, stare");
    c->cmd.body_case = CGS__COMMAND__BODY_SET_CAMERA;
    c->cmd.set_camera = k;
    return 0;
}

static int s_sensor_mode (json_object *req, st_command_t *c, char *why, size_t whylen)
{
    static const struct {
        const char *name;
        Cgs__ImageMode mode;
    } modes[] = {{"visible", CGS__IMAGE_MODE__IMAGE_MODE_VISIBLE},
                 {"infrared", CGS__IMAGE_MODE__IMAGE_MODE_INFRARED},
                 {"sar", CGS__IMAGE_MODE__IMAGE_MODE_SAR}};
    const char *m = s_string (req, "mode");
    for (size_t i = 0; i < sizeof modes / sizeof modes[0]; i++) {
        if (strcmp (m, modes[i].name) == 0) {
            c->sensor_mode.uav_id = c->uav_id;
            c->sensor_mode.mode = modes[i].mode;
            c->cmd.body_case = CGS__COMMAND__BODY_SET_SENSOR_MODE;
            c->cmd.set_sensor_mode = &c->sensor_mode;
            return 0;
        }
    }
    return s_refuse (why, whylen,
                     "sensor_mode needs the mode \"visible\", \"infrared\" or \"sar\"");
}

int st_request_command (json_object *req, const char *op, st_command_t *ret, char *why,
                        size_t whylen)
{
    st_command_t *c = ret;
    *c = (st_command_t){.cmd = CGS__COMMAND__INIT,
                        .to = ST_TO_GUIDANCED,
                        .designate = CGS__DESIGNATE__INIT,
                        .hit = CGS__HIT_REF__INIT,
                        .point = CGS__ENU__INIT,
                        .cancel = CGS__CANCEL__INIT,
                        .altitude = CGS__SET_ALTITUDE__INIT,
                        .speed = CGS__SET_SPEED__INIT,
                        .scale = CGS__SET_FOOTPRINT_SCALE__INIT,
                        .method = CGS__SET_INTERCEPT_MODE__INIT,
                        .camera = CGS__SET_CAMERA__INIT,
                        .stare_point = CGS__ENU__INIT,
                        .sensor_mode = CGS__SET_SENSOR_MODE__INIT,
                        .pause = CGS__PAUSE__INIT,
                        .resume = CGS__RESUME__INIT,
                        .time_scale = CGS__SET_TIME_SCALE__INIT,
                        .seek = CGS__SEEK__INIT};
    double uav = 0, value = 0;
    // Given, but not a UAV id: refused, never taken as "the only UAV".
    if (json_object_object_get_ex (req, "uav_id", NULL) &&
        !(st_request_number (req, "uav_id", &uav) && s_whole (uav, UINT32_MAX)))
        return s_refuse (why, whylen, "uav_id must be a whole number >= 0");
    c->uav_id = (uint32_t)uav;
    if (strcmp (op, "designate") == 0)
        return s_designate (req, c, why, whylen);
    if (strcmp (op, "cancel") == 0) {
        c->cancel.uav_id = c->uav_id;
        c->cmd.body_case = CGS__COMMAND__BODY_CANCEL;
        c->cmd.cancel = &c->cancel;
        return 0;
    }
    if (strcmp (op, "altitude") == 0 || strcmp (op, "speed") == 0) {
        c->to = ST_TO_UAVSIM;
        if (!st_request_number (req, "value", &value))
            return s_refuse (why, whylen, "needs a number value");
        if (op[0] == 'a') {
            c->altitude.uav_id = c->uav_id;
            c->altitude.altitude_agl_m = value;
            c->cmd.body_case = CGS__COMMAND__BODY_SET_ALTITUDE;
            c->cmd.set_altitude = &c->altitude;
        } else {
            c->speed.uav_id = c->uav_id;
            c->speed.airspeed_mps = value;
            c->cmd.body_case = CGS__COMMAND__BODY_SET_SPEED;
            c->cmd.set_speed = &c->speed;
        }
        return 0;
    }
    if (strcmp (op, "footprint_scale") == 0) {
        if (!st_request_number (req, "value", &value) || !s_whole (value, 1000))
            return s_refuse (why, whylen, "footprint_scale needs a value 1, 5 or 10");
        c->scale.uav_id = c->uav_id;
        c->scale.scale = (uint32_t)value; // guidanced says why anything but 1, 5, 10 is refused
        c->cmd.body_case = CGS__COMMAND__BODY_SET_FOOTPRINT_SCALE;
        c->cmd.set_footprint_scale = &c->scale;
        return 0;
    }
    if (strcmp (op, "intercept_mode") == 0) {
        const char *m = s_string (req, "value");
        if (strcmp (m, "head-on") != 0 && strcmp (m, "mti-hits") != 0)
            return s_refuse (why, whylen,
                             "intercept_mode needs the value \"head-on\" or \"mti-hits\"");
        c->method.uav_id = c->uav_id;
        c->method.method = m[0] == 'h' ? CGS__INTERCEPT_METHOD__INTERCEPT_METHOD_HEAD_ON
                                       : CGS__INTERCEPT_METHOD__INTERCEPT_METHOD_MTI_HITS;
        c->cmd.body_case = CGS__COMMAND__BODY_SET_INTERCEPT_MODE;
        c->cmd.set_intercept_mode = &c->method;
        return 0;
    }
    if (strcmp (op, "camera") == 0) {
        c->to = ST_TO_UAVSIM;
        return s_camera (req, c, why, whylen);
    }
    if (strcmp (op, "sensor_mode") == 0) {
        c->to = ST_TO_IMAGERD;
        return s_sensor_mode (req, c, why, whylen);
    }
    if (st_request_is_replay (op)) {
        c->to = ST_TO_REPLAY;
        if (strcmp (op, "replay_pause") == 0) {
            c->cmd.body_case = CGS__COMMAND__BODY_PAUSE;
            c->cmd.pause = &c->pause;
        } else if (strcmp (op, "replay_resume") == 0) {
            c->cmd.body_case = CGS__COMMAND__BODY_RESUME;
            c->cmd.resume = &c->resume;
        } else if (strcmp (op, "replay_speed") == 0) {
            if (!st_request_number (req, "value", &value) || !(value > 0 && value <= 1000))
                return s_refuse (why, whylen, "replay_speed needs a value in (0, 1000]");
            c->time_scale.time_scale = value;
            c->cmd.body_case = CGS__COMMAND__BODY_SET_TIME_SCALE;
            c->cmd.set_time_scale = &c->time_scale;
        } else {
            if (!st_request_number (req, "t", &value) || value < 0)
                return s_refuse (why, whylen, "replay_seek needs a time t >= 0 (seconds)");
            c->seek.t_s = value;
            c->cmd.body_case = CGS__COMMAND__BODY_SEEK;
            c->cmd.seek = &c->seek;
        }
        return 0;
    }
    snprintf (why, whylen, "unknown op \"%.40s\"", op);
    return -EINVAL;
}

int st_request_imagerd (const cgs_exercise_t *ex, const cgs_scenario_t *sc, uint32_t uav_id,
                        const cgs_instance_t **ret, char *why, size_t whylen)
{
    const char *name = NULL;
    if (sc && uav_id) {
        for (size_t i = 0; i < sc->uav_count && !name; i++)
            if (sc->uavs[i].id == uav_id)
                name = sc->uavs[i].name;
        if (!name) {
            snprintf (why, whylen, "the scenario has no UAV of entity id %u", uav_id);
            return -ENOENT;
        }
    }
    const cgs_instance_t *first = NULL, *enabled = NULL;
    size_t count = 0;
    for (size_t i = 0; i < cgs_exercise_instance_count (ex); i++) {
        const cgs_instance_t *in = cgs_exercise_instance (ex, i);
        if (strcmp (in->program, "imagerd") != 0 || !*in->command ||
            (name && strcmp (in->uav, name) != 0))
            continue;
        count++;
        if (!first)
            first = in;
        if (!enabled && in->enabled)
            enabled = in;
    }
    if (!first) {
        if (name)
            snprintf (why, whylen,
                      "the exercise has no imagerd for %s that takes commands (an imagerd with "
                      "`uav = %s` and a `command =` endpoint)",
                      name, name);
        else
            snprintf (why, whylen,
                      "the exercise has no imagerd that takes commands (one with a `command =` "
                      "endpoint)");
        return -ENOENT;
    }
    if (!name && count > 1) {
        if (uav_id)
            snprintf (why, whylen,
                      "without a scenario stationd cannot tell which of the exercise's %zu "
                      "imagerd serves UAV %u",
                      count, uav_id);
        else
            snprintf (why, whylen,
                      "the exercise has %zu imagerd that take commands: say which UAV (uav_id)",
                      count);
        return -ENOENT;
    }
    *ret = enabled ? enabled : first;
    return 0;
}
