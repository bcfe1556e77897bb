/* ms_cmd_sensor — the imaging sensor's commands (see ms_cmd_sensor.h). */
#include "ms_cmd_sensor.h"

#include "cgs_msg.h"
#include "ms_opts.h"
#include "ms_tool.h"

#include <math.h>
#include <stdio.h>
#include <string.h>
#include <strings.h>

/* ---- camera ------------------------------------------------------------------------------ */

int ms_camera_main (int argc, char **argv)
{
    const char *exercise = NULL, *to = NULL, *stabilized = NULL, *stare = NULL;
    double depression = NAN, fov = NAN, wait_s = MS_TOOL_WAIT_S;
    uint32_t uav = 0;
    const ms_opt_t opts[] = {
        {.name = "depression",
         .value = "DEG",
         .help = "the boresight's depression below the body's forward axis",
         .fn = ms_opts_read_number,
         .arg = &depression},
        {.name = "fov",
         .value = "DEG",
         .help = "the horizontal field of view (zoom; the vertical keeps the aspect)",
         .fn = ms_opts_read_number,
         .arg = &fov},
        {.name = "stabilized",
         .value = "on|off",
         .help = "level the camera against the bank",
         .str = &stabilized},
        {.name = "stare",
         .value = "off|target|POS",
         .help = "keep the camera on the designated target or a ground point",
         .str = &stare},
        MS_TOOL_OPT_UAV (&uav),
        MS_TOOL_OPT_TO (&to),
        MS_TOOL_OPT_WAIT (&wait_s),
        MS_TOOL_OPT_EXERCISE (&exercise),
        MS_OPTS_HELP,
        MS_OPTS_END,
    };
    const ms_cmd_t spec = {
        .name = "camera",
        .about = "uavsim points the UAV's imaging sensor; only what is given changes, each\n"
                 "within the scenario's limits (sensor_depression_min_deg ..., the gimbal's\n"
                 "for staring). POS is E,N in local metres, or quoted: 'geo LAT LON',\n"
                 "'36.6N 121.2W', 'mgrs GRID'. The camera is on `uav` (mscgs echo uav).\n",
        .opts = opts,
    };
    int nargs = ms_opts_parse (&spec, argc, argv);
    if (nargs < 0)
        return ms_opts_exit_code (nargs);
    if (nargs > 0) {
        fprintf (stderr, "mscgs camera: takes options only (see --help)\n");
        return 2;
    }
    Cgs__SetCamera c = CGS__SET_CAMERA__INIT;
    Cgs__Enu point = CGS__ENU__INIT;
    c.uav_id = uav;
    if (!isnan (depression)) {
        c.set |= 1;
        c.depression_deg = depression;
    }
    if (!isnan (fov)) {
        c.set |= 2;
        c.hfov_deg = fov;
    }
    if (stabilized) {
        if (strcasecmp (stabilized, "on") != 0 && strcasecmp (stabilized, "off") != 0) {
            fprintf (stderr, "mscgs camera: --stabilized takes on or off, not '%s'\n", stabilized);
            return 2;
        }
        c.set |= 4;
        c.stabilized = strcasecmp (stabilized, "on") == 0;
    }
    cgs_exercise_t *ex = ms_tool_load_exercise (exercise);
    if (!ex)
        return 1;
    if (stare) {
        c.set |= 8;
        if (strcasecmp (stare, "off") == 0) {
            c.stare = CGS__STARE_MODE__STARE_MODE_OFF;
        } else if (strcasecmp (stare, "target") == 0) {
            c.stare = CGS__STARE_MODE__STARE_MODE_TARGET;
        } else if (ms_tool_position (ex, stare, &point) == 0) {
            c.stare = CGS__STARE_MODE__STARE_MODE_POINT;
            c.stare_point = &point;
        } else {
            cgs_exercise_destroy (&ex);
            return 2;
        }
    }
    if (!c.set) {
        fprintf (stderr, "mscgs camera: give at least one of --depression, --fov, --stabilized, "
                         "--stare\n");
        cgs_exercise_destroy (&ex);
        return 2;
    }
    Cgs__Command cmd = CGS__COMMAND__INIT;
    cmd.body_case = CGS__COMMAND__BODY_SET_CAMERA;
    cmd.set_camera = &c;
    int rc = ms_tool_send ("camera", ex, to, "uavsim", &cmd, wait_s);
    cgs_exercise_destroy (&ex);
    return rc;
}

/* ---- sensor mode ------------------------------------------------------------------------ */

int ms_sensor_main (int argc, char **argv)
{
    const char *exercise = NULL, *to = NULL;
    Cgs__SetSensorMode m = CGS__SET_SENSOR_MODE__INIT;
    double wait_s = MS_TOOL_WAIT_S;
    const ms_opt_t opts[] = {
        MS_TOOL_OPT_UAV (&m.uav_id),      MS_TOOL_OPT_TO (&to), MS_TOOL_OPT_WAIT (&wait_s),
        MS_TOOL_OPT_EXERCISE (&exercise), MS_OPTS_HELP,         MS_OPTS_END,
    };
    const ms_cmd_t spec = {
        .name = "sensor",
        .operands = "visible|infrared|flir|sar",
        .about = "imagerd's imaging sensor mode: the visible camera, the infrared (FLIR)\n"
                 "view or a SAR spotlight image; the `image` messages say which is live.\n",
        .missing = "give a mode: visible, infrared (flir) or sar",
        .opts = opts,
    };
    int nargs = ms_opts_parse (&spec, argc, argv);
    if (nargs < 0)
        return ms_opts_exit_code (nargs);
    if (nargs != 1) {
        fprintf (stderr, "mscgs sensor: give one mode: visible, infrared (flir) or sar\n");
        return 2;
    }
    const char *mode = argv[1];
    if (strcasecmp (mode, "visible") == 0 || strcasecmp (mode, "eo") == 0)
        m.mode = CGS__IMAGE_MODE__IMAGE_MODE_VISIBLE;
    else if (strcasecmp (mode, "infrared") == 0 || strcasecmp (mode, "flir") == 0 ||
             strcasecmp (mode, "ir") == 0)
        m.mode = CGS__IMAGE_MODE__IMAGE_MODE_INFRARED;
    else if (strcasecmp (mode, "sar") == 0)
        m.mode = CGS__IMAGE_MODE__IMAGE_MODE_SAR;
    else {
        fprintf (stderr, "mscgs sensor: '%s' is not a mode: visible, infrared (flir) or sar\n",
                 mode);
        return 2;
    }
    cgs_exercise_t *ex = ms_tool_load_exercise (exercise);
    if (!ex)
        return 1;
    Cgs__Command cmd = CGS__COMMAND__INIT;
    cmd.body_case = CGS__COMMAND__BODY_SET_SENSOR_MODE;
    cmd.set_sensor_mode = &m;
    int rc = ms_tool_send ("sensor", ex, to, "imagerd", &cmd, wait_s);
    cgs_exercise_destroy (&ex);
    return rc;
}
