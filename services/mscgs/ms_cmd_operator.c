/* ms_cmd_operator — the operator's commands: uavsim's tasks and clock, and
 * guidanced's intercept; each sent to one instance (ms_tool_send), its
 * reply printed. */
#include "ms_cmd_operator.h"

#include "ms_opts.h"
#include "ms_tool.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ---- uavsim's task and clock commands ------------------------------------------------ */

static const char s_task_usage[] =
    "usage: mscgs loiter (--here | --at POS) [--radius M] [--anticlockwise]\n"
    "       mscgs goto [--radius M] [--anticlockwise] POS   (then loiter there)\n"
    "       mscgs route [--speed MPS] [--altitude M] [--no-loiter] [--radius M]\n"
    "                   [--anticlockwise] POS [POS ...]   (then loiter above the last)\n"
    "       mscgs altitude M          (above ground)\n"
    "       mscgs speed MPS           (airspeed)\n"
    "       mscgs pause | resume | time-scale X\n";

int ms_task_main (int argc, char **argv)
{
    const char *tool = argv[0];
    const char *exercise = NULL, *to = NULL, *at = NULL;
    uint32_t uav = 0;
    double radius = 0, speed = 0, altitude = 0, wait_s = MS_TOOL_WAIT_S;
    bool here = false, anticlockwise = false, no_loiter = false;
    const ms_opt_t opts[] = {
        MS_TOOL_OPT_EXERCISE (&exercise),
        MS_TOOL_OPT_TO (&to),
        MS_TOOL_OPT_UAV (&uav),
        {.name = "here", .help = "loiter about the present position", .flag = &here},
        {.name = "at", .value = "POS", .help = "loiter about POS", .str = &at},
        {.name = "radius",
         .value = "M",
         .help = "the loiter radius",
         .fn = ms_opts_read_number,
         .arg = &radius},
        {.name = "anticlockwise", .help = "loiter anticlockwise", .flag = &anticlockwise},
        {.name = "speed",
         .value = "MPS",
         .help = "the route's airspeed",
         .fn = ms_opts_read_number,
         .arg = &speed},
        {.name = "altitude",
         .value = "M",
         .help = "the route's altitude above ground",
         .fn = ms_opts_read_number,
         .arg = &altitude},
        {.name = "no-loiter", .help = "no loiter at the route's end", .flag = &no_loiter},
        MS_TOOL_OPT_WAIT (&wait_s),
        MS_OPTS_HELP,
        MS_OPTS_END,
    };
    const ms_cmd_t spec = {
        .name = tool,
        .synopsis = s_task_usage,
        .about = "Common options: --uav ID (entity id; default the only UAV), --to INSTANCE\n"
                 "(default the exercise's uavsim; guidanced also takes altitude and speed),\n"
                 "--wait S (keep trying S seconds, default 3), --exercise F. POS is E,N in "
                 "local metres, or quoted: 'geo LAT LON',\n"
                 "'36.6N 121.2W', 'mgrs GRID'.\n",
        .opts = opts,
    };
    int nargs = 0;
    int rc = ms_opts_parse (&spec, argc, argv, &nargs);
    if (rc < 0)
        return ms_opts_exit_code (rc);
    char **args = argv + 1;
    cgs_exercise_t *ex = ms_tool_load_exercise (exercise);
    if (!ex)
        return 1;
    Cgs__Command cmd = CGS__COMMAND__INIT;
    Cgs__Loiter loiter = CGS__LOITER__INIT;
    Cgs__GoTo go_to = CGS__GO_TO__INIT;
    Cgs__TaskRoute route = CGS__TASK_ROUTE__INIT;
    Cgs__SetAltitude alt = CGS__SET_ALTITUDE__INIT;
    Cgs__SetSpeed spd = CGS__SET_SPEED__INIT;
    Cgs__Pause pause = CGS__PAUSE__INIT;
    Cgs__Resume resume = CGS__RESUME__INIT;
    Cgs__SetTimeScale scale = CGS__SET_TIME_SCALE__INIT;
    Cgs__Enu centre, *points = NULL;
    Cgs__Enu **ptrs = NULL;
    rc = 2;
    if (strcmp (tool, "loiter") == 0) {
        if (nargs != 0 || here == (at != NULL)) {
            fprintf (stderr, "mscgs loiter: give --here or --at POS\n");
            goto done;
        }
        if (at && ms_tool_position (ex, at, &centre) < 0)
            goto done;
        loiter.uav_id = uav;
        loiter.center = at ? &centre : NULL;
        loiter.radius_m = radius;
        loiter.clockwise = !anticlockwise;
        loiter.at_present_position = here;
        cmd.body_case = CGS__COMMAND__BODY_LOITER;
        cmd.loiter = &loiter;
    } else if (strcmp (tool, "goto") == 0) {
        if (nargs != 1) {
            fprintf (stderr, "mscgs goto: give one position\n");
            goto done;
        }
        if (ms_tool_position (ex, args[0], &centre) < 0)
            goto done;
        go_to.uav_id = uav;
        go_to.point = &centre;
        go_to.radius_m = radius;
        go_to.anticlockwise = anticlockwise;
        cmd.body_case = CGS__COMMAND__BODY_GO_TO;
        cmd.go_to = &go_to;
    } else if (strcmp (tool, "route") == 0) {
        if (nargs < 1) {
            fprintf (stderr, "mscgs route: give one or more positions\n");
            goto done;
        }
        points = calloc ((size_t)nargs, sizeof *points);
        ptrs = calloc ((size_t)nargs, sizeof *ptrs);
        if (!points || !ptrs)
            goto done;
        for (int i = 0; i < nargs; i++) {
            if (ms_tool_position (ex, args[i], &points[i]) < 0)
                goto done;
            ptrs[i] = &points[i];
        }
        route.uav_id = uav;
        route.n_waypoints = (size_t)nargs;
        route.waypoints = ptrs;
        route.airspeed_mps = speed;
        route.altitude_agl_m = altitude;
        route.loiter_at_end = !no_loiter;
        route.loiter_radius_m = radius;
        route.loiter_anticlockwise = anticlockwise;
        cmd.body_case = CGS__COMMAND__BODY_TASK_ROUTE;
        cmd.task_route = &route;
    } else if (strcmp (tool, "altitude") == 0 || strcmp (tool, "speed") == 0 ||
               strcmp (tool, "time-scale") == 0) {
        if (nargs != 1) {
            fprintf (stderr, "mscgs %s: give one number\n", tool);
            goto done;
        }
        double v = 0;
        if (ms_opts_number (tool, args[0], &v) < 0)
            goto done;
        if (tool[0] == 'a') {
            alt.uav_id = uav;
            alt.altitude_agl_m = v;
            cmd.body_case = CGS__COMMAND__BODY_SET_ALTITUDE;
            cmd.set_altitude = &alt;
        } else if (tool[0] == 's') {
            spd.uav_id = uav;
            spd.airspeed_mps = v;
            cmd.body_case = CGS__COMMAND__BODY_SET_SPEED;
            cmd.set_speed = &spd;
        } else {
            scale.time_scale = v;
            cmd.body_case = CGS__COMMAND__BODY_SET_TIME_SCALE;
            cmd.set_time_scale = &scale;
        }
    } else if (strcmp (tool, "pause") == 0) {
        cmd.body_case = CGS__COMMAND__BODY_PAUSE;
        cmd.pause = &pause;
    } else {
        cmd.body_case = CGS__COMMAND__BODY_RESUME;
        cmd.resume = &resume;
    }
    rc = ms_tool_send (tool, ex, to, "uavsim", &cmd, wait_s);
done:
    free (points);
    free (ptrs);
    cgs_exercise_destroy (&ex);
    return rc;
}

/* ---- guidanced's operator commands ----------------------------------------------------- */

static const char s_guide_usage[] =
    "usage: mscgs designate TRACK_ID      designate a track by its id\n"
    "       mscgs designate --at POS      the track whose latest hit is nearest POS\n"
    "       mscgs cancel                  stop the intercept (the UAV loiters)\n"
    "       mscgs footprint-scale 1|5|10  the footprint's display scale\n"
    "       mscgs intercept-mode head-on|mti-hits\n"
    "Common options: --uav ID (entity id; default the only UAV), --to INSTANCE\n"
    "(default the exercise's guidanced), --wait S (keep trying S seconds, default\n"
    "3), --exercise F. POS is E,N in local metres,\n"
    "or quoted: 'geo LAT LON', '36.6N 121.2W', 'mgrs GRID' (or the bare grid,\n"
    "10SFE5964179460).\n";

/* Fill des from a track id argument, or from --at's position (kept in
 * *point); 0, or 2 (usage) after saying why. */
static int s_guide_designate (const cgs_exercise_t *ex, const char *at, int nargs, char **args,
                              Cgs__Designate *des, Cgs__Enu *point)
{
    if ((at != NULL) == (nargs == 1) || nargs > 1) {
        fprintf (stderr, "mscgs designate: give a track id, or --at POS\n");
        return 2;
    }
    if (at) {
        if (ms_tool_position (ex, at, point) < 0)
            return 2;
        des->target_case = CGS__DESIGNATE__TARGET_POINT;
        des->point = point;
        return 0;
    }
    uint32_t id = 0;
    if (ms_opts_u32 ("designate", "a track id (a position needs --at POS)", args[0], &id) < 0)
        return 2;
    if (id == 0) {
        fprintf (stderr, "mscgs designate: track ids start at 1\n");
        return 2;
    }
    des->target_case = CGS__DESIGNATE__TARGET_TRACK_ID;
    des->track_id = id;
    return 0;
}

/* The method named on the command line; 0 or -EINVAL. */
static int s_method (const char *text, Cgs__InterceptMethod *ret)
{
    if (strcmp (text, "head-on") == 0)
        *ret = CGS__INTERCEPT_METHOD__INTERCEPT_METHOD_HEAD_ON;
    else if (strcmp (text, "mti-hits") == 0)
        *ret = CGS__INTERCEPT_METHOD__INTERCEPT_METHOD_MTI_HITS;
    else
        return -EINVAL;
    return 0;
}

/* What --at sets: designate's POS; the other commands refuse it. */
typedef struct {
    const char *tool;
    const char *pos;
} s_at_t;

static int s_read_at (const ms_opt_t *opt, const char *value)
{
    s_at_t *at = opt->arg;
    if (strcmp (at->tool, "designate") != 0) {
        fprintf (stderr, "mscgs %s: --at is for designate\n", at->tool);
        return -EINVAL;
    }
    at->pos = value;
    return 0;
}

int ms_guide_main (int argc, char **argv)
{
    const char *tool = argv[0];
    const char *exercise = NULL, *to = NULL;
    s_at_t at = {.tool = tool};
    uint32_t uav = 0;
    double wait_s = MS_TOOL_WAIT_S;
    const ms_opt_t opts[] = {
        MS_TOOL_OPT_EXERCISE (&exercise),
        MS_TOOL_OPT_TO (&to),
        MS_TOOL_OPT_UAV (&uav),
        {.name = "at",
         .value = "POS",
         .help = "designate the track whose latest hit is nearest POS",
         .fn = s_read_at,
         .arg = &at},
        MS_TOOL_OPT_WAIT (&wait_s),
        MS_OPTS_HELP,
        MS_OPTS_END,
    };
    const ms_cmd_t spec = {.name = tool, .synopsis = s_guide_usage, .opts = opts};
    int nargs = 0;
    int rc = ms_opts_parse (&spec, argc, argv, &nargs);
    if (rc < 0)
        return ms_opts_exit_code (rc);
    char **args = argv + 1;
    cgs_exercise_t *ex = ms_tool_load_exercise (exercise);
    if (!ex)
        return 1;
    Cgs__Command cmd = CGS__COMMAND__INIT;
    Cgs__Designate des = CGS__DESIGNATE__INIT;
    Cgs__Cancel cancel = CGS__CANCEL__INIT;
    Cgs__SetFootprintScale scale = CGS__SET_FOOTPRINT_SCALE__INIT;
    Cgs__SetInterceptMode mode = CGS__SET_INTERCEPT_MODE__INIT;
    Cgs__Enu point = CGS__ENU__INIT;
    rc = 2;
    if (strcmp (tool, "designate") == 0) {
        if (s_guide_designate (ex, at.pos, nargs, args, &des, &point) != 0)
            goto done;
        des.uav_id = uav;
        cmd.body_case = CGS__COMMAND__BODY_DESIGNATE;
        cmd.designate = &des;
    } else if (strcmp (tool, "cancel") == 0) {
        if (nargs != 0) {
            fprintf (stderr, "mscgs cancel: takes no arguments\n");
            goto done;
        }
        cancel.uav_id = uav;
        cmd.body_case = CGS__COMMAND__BODY_CANCEL;
        cmd.cancel = &cancel;
    } else if (strcmp (tool, "footprint-scale") == 0) {
        uint32_t k = 0;
        if (nargs == 1 && ms_opts_u32 ("footprint-scale", "1, 5 or 10", args[0], &k) < 0)
            goto done;
        if (k != 1 && k != 5 && k != 10) {
            fprintf (stderr, "mscgs footprint-scale: give 1, 5 or 10\n");
            goto done;
        }
        scale.uav_id = uav;
        scale.scale = k;
        cmd.body_case = CGS__COMMAND__BODY_SET_FOOTPRINT_SCALE;
        cmd.set_footprint_scale = &scale;
    } else {
        if (nargs != 1 || s_method (args[0], &mode.method) < 0) {
            fprintf (stderr, "mscgs intercept-mode: give head-on or mti-hits\n");
            goto done;
        }
        mode.uav_id = uav;
        cmd.body_case = CGS__COMMAND__BODY_SET_INTERCEPT_MODE;
        cmd.set_intercept_mode = &mode;
    }
    rc = ms_tool_send (tool, ex, to, "guidanced", &cmd, wait_s);
done:
    cgs_exercise_destroy (&ex);
    return rc;
}
