/* st_request — a page's command request (its JSON object, see README.md,
 * "Protocol") checked and turned into the command it asks for, and the
 * service that takes it: guidanced (designate, cancel, footprint_scale,
 * intercept_mode), uavsim (altitude, speed, camera) or the imagerd that
 * serves the UAV (sensor_mode). Malformed input (a field of the wrong type,
 * a number not finite or out of range, an unknown value) is refused with the
 * reason and nothing is made; the services check the rest (the scenario's
 * limits). Pure: no sockets, no logging. */
#ifndef ST_REQUEST_H
#define ST_REQUEST_H

#include "cgs_exercise.h"
#include "cgs_scenario.h"
#include "command.pb-c.h"

#include <json-c/json.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

/* The service a command goes to. */
typedef enum {
    ST_TO_GUIDANCED = 0,
    ST_TO_UAVSIM = 1,
    ST_TO_IMAGERD = 2, // the one that serves the command's UAV (st_request_imagerd)
    ST_TO_REPLAY = 3,  // a replay's timeline (mscgs replay)
} st_to_t;

/* The camera command's `set` bits (SetCamera in command.proto). */
#define ST_CAMERA_SET_DEPRESSION 1u
#define ST_CAMERA_SET_FOV        2u
#define ST_CAMERA_SET_STABILIZED 4u
#define ST_CAMERA_SET_STARE      8u

/* The page's limits on the camera's values (the scenario's are uavsim's to
 * check): depression in [-90, 90] degrees, field of view in (0, 180). */
#define ST_DEPRESSION_MAX_DEG 90.0
#define ST_FOV_MAX_DEG        180.0
#define ST_POINT_MAX_M        1e7 // a point's east and north, either side of the origin

/* A command made from a request: cmd's body points into the struct itself,
 * so it is used where it was filled, never copied. */
typedef struct {
    Cgs__Command cmd;
    st_to_t to;
    uint32_t uav_id; // the request's (0: not given)
    Cgs__Designate designate;
    Cgs__HitRef hit;
    Cgs__Enu point;
    Cgs__Cancel cancel;
    Cgs__SetAltitude altitude;
    Cgs__SetSpeed speed;
    Cgs__SetFootprintScale scale;
    Cgs__SetInterceptMode method;
    Cgs__SetCamera camera;
    Cgs__Enu stare_point;
    Cgs__SetSensorMode sensor_mode;
    Cgs__Pause pause;
    Cgs__Resume resume;
    Cgs__SetTimeScale time_scale;
    Cgs__Seek seek;
} st_command_t;

/* The finite number field key of o: true with it, false when absent or
 * not a finite number. */
bool st_request_number (json_object *o, const char *key, double *ret);

/* Whether op names a command a page may send (designate, cancel, altitude,
 * speed, footprint_scale, intercept_mode, camera, sensor_mode; and a
 * replay's replay_pause, replay_resume, replay_speed {value},
 * replay_seek {t}). */
bool st_request_is_command (const char *op);
/* Whether op is one of a replay's timeline commands (replay_...). */
bool st_request_is_replay (const char *op);

/* The command that req (a JSON object whose "op" is op, a command) asks
 * for: 0 with *ret filled; -EINVAL with the reason in why and nothing to
 * send (a uav_id that is not a whole number >= 0, a missing or malformed
 * field). */
int st_request_command (json_object *req, const char *op, st_command_t *ret, char *why,
                        size_t whylen);

/* The imagerd that serves UAV uav_id: the exercise's imagerd instance
 * whose `uav =` is that UAV's name in the scenario sc and that takes
 * commands (an enabled one first). Without a scenario or a uav_id (0), the
 * exercise's only imagerd that takes commands. 0 with *ret; -ENOENT with
 * the reason in why (no such UAV, no imagerd for it, several and no way to
 * choose). */
int st_request_imagerd (const cgs_exercise_t *ex, const cgs_scenario_t *sc, uint32_t uav_id,
                        const cgs_instance_t **ret, char *why, size_t whylen);

#endif
