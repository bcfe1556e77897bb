/* ms_cmd_operator — the operator's commands: uavsim's tasks and clock, and
 * guidanced's intercept. Each family parses its options, then one flow
 * loads the exercise, has the family's builder make the command from the
 * operands, and sends it to one instance (ms_tool_send). */
#include "ms_cmd_operator.h"

#include "ms_opts.h"
#include "ms_tool.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* What the options of a command set (each family takes its own). */
typedef struct {
    const char *tool; // the command's name
    const char *exercise, *to;
    uint32_t uav;
    double wait_s;
    const char *at;                         // --at POS (loiter, designate)
    bool here, anticlockwise, no_loiter;    // tasks
    double radius_m, speed_mps, altitude_m; // tasks: 0 leaves the service's own
} s_opts_t;

/* A command and its parts, filled by a builder. */
typedef struct {
    Cgs__Command cmd;
    Cgs__Loiter loiter;
    Cgs__GoTo go_to;
    Cgs__TaskRoute route;
    Cgs__SetAltitude altitude;
    Cgs__SetSpeed speed;
    Cgs__Pause pause;
    Cgs__Resume resume;
    Cgs__SetTimeScale time_scale;
    Cgs__Seek seek;
    Cgs__Designate designate;
    Cgs__Cancel cancel;
    Cgs__SetFootprintScale footprint;
    Cgs__SetInterceptMode mode;
    Cgs__Enu point;
    Cgs__Enu *points; // the route's waypoints (freed after sending)
    Cgs__Enu **ptrs;  // ... and pointers to them
} s_parts_t;

/* Make o->tool's command from its operands in p: 0, or 2 (usage) after
 * saying why. */
typedef int (s_build_fn_t) (const s_opts_t *o, const cgs_exercise_t *ex, int nargs, char **args,
                            s_parts_t *p);

/* Load the exercise, build the command, send it to --to or the first
 * instance of program: the exit code. */
static int s_operate (const s_opts_t *o, const char *program, s_build_fn_t *build, int nargs,
                      char **args)
{
    cgs_exercise_t *ex = ms_tool_load_exercise (o->exercise);
    if (!ex)
        return 1;
    s_parts_t p = {
        .cmd = CGS__COMMAND__INIT,
        .loiter = CGS__LOITER__INIT,
        .go_to = CGS__GO_TO__INIT,
        .route = CGS__TASK_ROUTE__INIT,
        .altitude = CGS__SET_ALTITUDE__INIT,
        .speed = CGS__SET_SPEED__INIT,
        .pause = CGS__PAUSE__INIT,
        .resume = CGS__RESUME__INIT,
        .time_scale = CGS__SET_TIME_SCALE__INIT,
        .seek = CGS__SEEK__INIT,
        .designate = CGS__DESIGNATE__INIT,
        .cancel = CGS__CANCEL__INIT,
        .footprint = CGS__SET_FOOTPRINT_SCALE__INIT,
        .mode = CGS__SET_INTERCEPT_MODE__INIT,
        .point = CGS__ENU__INIT,
    };
    int rc = build (o, ex, nargs, args, &p);
    if (rc == 0)
        rc = ms_tool_send (o->tool, ex, o->to, program, &p.cmd, o->wait_s);
    free (p.points);
    free (p.ptrs);
    cgs_exercise_destroy (&ex);
    return rc;
}

/* ---- uavsim's task and clock commands ------------------------------------------------ */

static const char s_task_usage[] =
    "usage: mscgs loiter (--here | --at POS) [--radius M] [--anticlockwise]\n"
    "       mscgs goto [--radius M] [--anticlockwise] POS   (then loiter there)\n"
    "       mscgs route [--speed MPS] [--altitude M] [--no-loiter] [--radius M]\n"
    "                   [--anticlockwise] POS [POS ...]   (then loiter above the last)\n"
    "       mscgs altitude M          (above ground)\n"
    "       mscgs speed MPS           (airspeed)\n"
    "       mscgs pause | resume | time-scale X\n"
    "       mscgs seek S              (a replay: go to S seconds into the recording)\n";

/* The route through the operands. */
static int s_build_route (const s_opts_t *o, const cgs_exercise_t *ex, int nargs, char **args,
                          s_parts_t *p)
{
    if (nargs < 1) {
        fprintf (stderr, "mscgs route: give one or more positions\n");
        return 2;
    }
    p->points = calloc ((size_t)nargs, sizeof *p->points);
    p->ptrs = calloc ((size_t)nargs, sizeof *p->ptrs);
    if (!p->points || !p->ptrs)
        return 2;
    for (int i = 0; i < nargs; i++) {
        if (ms_tool_position (ex, args[i], &p->points[i]) < 0)
            return 2;
        p->ptrs[i] = &p->points[i];
    }
    p->route.uav_id = o->uav;
    p->route.n_waypoints = (size_t)nargs;
    p->route.waypoints = p->ptrs;
    p->route.airspeed_mps = o->speed_mps;
    p->route.altitude_agl_m = o->altitude_m;
    p->route.loiter_at_end = !o->no_loiter;
    p->route.loiter_radius_m = o->radius_m;
    p->route.loiter_anticlockwise = o->anticlockwise;
    p->cmd.body_case = CGS__COMMAND__BODY_TASK_ROUTE;
    p->cmd.task_route = &p->route;
    return 0;
}

/* altitude M, speed MPS, time-scale X. */
static int s_build_number (const s_opts_t *o, int nargs, char **args, s_parts_t *p)
{
    if (nargs != 1) {
        fprintf (stderr, "mscgs %s: give one number\n", o->tool);
        return 2;
    }
    double v = 0;
    if (ms_opts_number (o->tool, args[0], &v) < 0)
        return 2;
    if (strcmp (o->tool, "seek") == 0) {
        p->seek.t_s = v;
        p->cmd.body_case = CGS__COMMAND__BODY_SEEK;
        p->cmd.seek = &p->seek;
    } else if (o->tool[0] == 'a') {
        p->altitude.uav_id = o->uav;
        p->altitude.altitude_agl_m = v;
        p->cmd.body_case = CGS__COMMAND__BODY_SET_ALTITUDE;
        p->cmd.set_altitude = &p->altitude;
    } else if (o->tool[0] == 's') {
        p->speed.uav_id = o->uav;
        p->speed.airspeed_mps = v;
        p->cmd.body_case = CGS__COMMAND__BODY_SET_SPEED;
        p->cmd.set_speed = &p->speed;
    } else {
        p->time_scale.time_scale = v;
        p->cmd.body_case = CGS__COMMAND__BODY_SET_TIME_SCALE;
        p->cmd.set_time_scale = &p->time_scale;
    }
    return 0;
}

static int s_build_task (const s_opts_t *o, const cgs_exercise_t *ex, int nargs, char **args,
                         s_parts_t *p)
{
    if (strcmp (o->tool, "loiter") == 0) {
        if (nargs != 0 || o->here == (o->at != NULL)) {
            fprintf (stderr, "mscgs loiter: give --here or --at POS\n");
            return 2;
        }
        if (o->at && ms_tool_position (ex, o->at, &p->point) < 0)
            return 2;
        p->loiter.uav_id = o->uav;
        p->loiter.center = o->at ? &p->point : NULL;
        p->loiter.radius_m = o->radius_m;
        p->loiter.clockwise = !o->anticlockwise;
        p->loiter.at_present_position = o->here;
        p->cmd.body_case = CGS__COMMAND__BODY_LOITER;
        p->cmd.loiter = &p->loiter;
    } else if (strcmp (o->tool, "goto") == 0) {
        if (nargs != 1) {
            fprintf (stderr, "mscgs goto: give one position\n");
            return 2;
        }
        if (ms_tool_position (ex, args[0], &p->point) < 0)
            return 2;
        p->go_to.uav_id = o->uav;
        p->go_to.point = &p->point;
        p->go_to.radius_m = o->radius_m;
        p->go_to.anticlockwise = o->anticlockwise;
        p->cmd.body_case = CGS__COMMAND__BODY_GO_TO;
        p->cmd.go_to = &p->go_to;
    } else if (strcmp (o->tool, "route") == 0) {
        return s_build_route (o, ex, nargs, args, p);
    } else if (strcmp (o->tool, "altitude") == 0 || strcmp (o->tool, "speed") == 0 ||
               strcmp (o->tool, "time-scale") == 0 || strcmp (o->tool, "seek") == 0) {
        return s_build_number (o, nargs, args, p);
    } else if (strcmp (o->tool, "pause") == 0) {
        p->cmd.body_case = CGS__COMMAND__BODY_PAUSE;
        p->cmd.pause = &p->pause;
    } else {
        p->cmd.body_case = CGS__COMMAND__BODY_RESUME;
        p->cmd.resume = &p->resume;
    }
    return 0;
}

int ms_task_main (int argc, char **argv)
{
    s_opts_t o = {.tool = argv[0], .wait_s = MS_TOOL_WAIT_S};
    const ms_opt_t opts[] = {
        MS_TOOL_OPT_EXERCISE (&o.exercise),
        MS_TOOL_OPT_TO (&o.to),
        MS_TOOL_OPT_UAV (&o.uav),
        {.name = "here", .help = "loiter about the present position", .flag = &o.here},
        {.name = "at", .value = "POS", .help = "loiter about POS", .str = &o.at},
        {.name = "radius",
         .value = "M",
         .help = "the loiter radius",
         .fn = ms_opts_read_number,
         .arg = &o.radius_m},
        {.name = "anticlockwise", .help = "loiter anticlockwise", .flag = &o.anticlockwise},
        {.name = "speed",
         .value = "MPS",
         .help = "the route's airspeed",
         .fn = ms_opts_read_number,
         .arg = &o.speed_mps},
        {.name = "altitude",
         .value = "M",
         .help = "the route's altitude above ground",
         .fn = ms_opts_read_number,
         .arg = &o.altitude_m},
        {.name = "no-loiter", .help = "no loiter at the route's end", .flag = &o.no_loiter},
        MS_TOOL_OPT_WAIT (&o.wait_s),
        MS_OPTS_HELP,
        MS_OPTS_END,
    };
    const ms_cmd_t spec = {
        .name = o.tool,
        .synopsis = s_task_usage,
        .about = "Common options: --uav ID (entity id; default the only UAV), --to INSTANCE\n"
                 "(default the exercise's uavsim; guidanced also takes altitude and speed),\n"
                 "--wait S (keep trying S seconds, default 3), --exercise F. POS is E,N in "
                 "local metres, or quoted: 'geo LAT LON',\n"
                 "'36.6N 121.2W', 'mgrs GRID'.\n",
        .opts = opts,
    };
    int nargs = ms_opts_parse (&spec, argc, argv);
    if (nargs < 0)
        return ms_opts_exit_code (nargs);
    return s_operate (&o, "uavsim", s_build_task, nargs, argv + 1);
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

/* designate TRACK_ID, or designate --at POS. */
static int s_build_designate (const s_opts_t *o, const cgs_exercise_t *ex, int nargs, char **args,
                              s_parts_t *p)
{
    if ((o->at != NULL) == (nargs == 1) || nargs > 1) {
        fprintf (stderr, "mscgs designate: give a track id, or --at POS\n");
        return 2;
    }
    Cgs__Designate *des = &p->designate;
    if (o->at) {
        if (ms_tool_position (ex, o->at, &p->point) < 0)
            return 2;
        des->target_case = CGS__DESIGNATE__TARGET_POINT;
        des->point = &p->point;
    } else {
        uint32_t id = 0;
        if (ms_opts_u32 ("designate", "a track id (a position needs --at POS)", args[0], &id) < 0)
            return 2;
        if (id == 0) {
            fprintf (stderr, "mscgs designate: track ids start at 1\n");
            return 2;
        }
        des->target_case = CGS__DESIGNATE__TARGET_TRACK_ID;
        des->track_id = id;
    }
    des->uav_id = o->uav;
    p->cmd.body_case = CGS__COMMAND__BODY_DESIGNATE;
    p->cmd.designate = des;
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

static int s_build_guide (const s_opts_t *o, const cgs_exercise_t *ex, int nargs, char **args,
                          s_parts_t *p)
{
    if (strcmp (o->tool, "designate") == 0)
        return s_build_designate (o, ex, nargs, args, p);
    if (strcmp (o->tool, "cancel") == 0) {
        if (nargs != 0) {
            fprintf (stderr, "mscgs cancel: takes no arguments\n");
            return 2;
        }
        p->cancel.uav_id = o->uav;
        p->cmd.body_case = CGS__COMMAND__BODY_CANCEL;
        p->cmd.cancel = &p->cancel;
    } else if (strcmp (o->tool, "footprint-scale") == 0) {
        uint32_t k = 0;
        if (nargs == 1 && ms_opts_u32 ("footprint-scale", "1, 5 or 10", args[0], &k) < 0)
            return 2;
        if (k != 1 && k != 5 && k != 10) {
            fprintf (stderr, "mscgs footprint-scale: give 1, 5 or 10\n");
            return 2;
        }
        p->footprint.uav_id = o->uav;
        p->footprint.scale = k;
        p->cmd.body_case = CGS__COMMAND__BODY_SET_FOOTPRINT_SCALE;
        p->cmd.set_footprint_scale = &p->footprint;
    } else {
        if (nargs != 1 || s_method (args[0], &p->mode.method) < 0) {
            fprintf (stderr, "mscgs intercept-mode: give head-on or mti-hits\n");
            return 2;
        }
        p->mode.uav_id = o->uav;
        p->cmd.body_case = CGS__COMMAND__BODY_SET_INTERCEPT_MODE;
        p->cmd.set_intercept_mode = &p->mode;
    }
    return 0;
}

/* --at POS: designate's; the other commands refuse it. */
static int s_read_at (const ms_opt_t *opt, const char *value)
{
    s_opts_t *o = opt->arg;
    if (strcmp (o->tool, "designate") != 0) {
        fprintf (stderr, "mscgs %s: --at is for designate\n", o->tool);
        return -EINVAL;
    }
    o->at = value;
    return 0;
}

int ms_guide_main (int argc, char **argv)
{
    s_opts_t o = {.tool = argv[0], .wait_s = MS_TOOL_WAIT_S};
    const ms_opt_t opts[] = {
        MS_TOOL_OPT_EXERCISE (&o.exercise),
        MS_TOOL_OPT_TO (&o.to),
        MS_TOOL_OPT_UAV (&o.uav),
        {.name = "at",
         .value = "POS",
         .help = "designate the track whose latest hit is nearest POS",
         .fn = s_read_at,
         .arg = &o},
        MS_TOOL_OPT_WAIT (&o.wait_s),
        MS_OPTS_HELP,
        MS_OPTS_END,
    };
    const ms_cmd_t spec = {.name = o.tool, .synopsis = s_guide_usage, .opts = opts};
    int nargs = ms_opts_parse (&spec, argc, argv);
    if (nargs < 0)
        return ms_opts_exit_code (nargs);
    return s_operate (&o, "guidanced", s_build_guide, nargs, argv + 1);
}
