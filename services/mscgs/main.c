/* mscgs — the command-line tool: run an exercise on this machine, echo a
 * topic, show every service's health, send operator commands. This file
 * is the tool's help and its table of commands; each command lives in its
 * own file (services/mscgs/README.md lists them).
 *
 *   mscgs run [--exercise F] [--scenario F] [--speed X] [--duration S] [--out DIR]
 *             [--resume] [--stop-after-intercept S]
 *   mscgs echo TOPIC [--json] [--count N] [--timeout S] [--exercise F]
 *   mscgs status [--wait S] [--exercise F]
 *   mscgs ping INSTANCE [--exercise F]
 *   mscgs topics
 *   mscgs keygen NAME [--dir DIR] | keygen --group [NAME] [--dir DIR]
 *   mscgs loiter|goto|route|altitude|speed|pause|resume|time-scale ...   (uavsim)
 *   mscgs designate|cancel|footprint-scale|intercept-mode ...            (guidanced)
 *   mscgs camera ..., mscgs sensor MODE      (the imaging sensor: uavsim, imagerd)
 *   mscgs snapshot [N], mscgs fault INSTANCE ..., mscgs montecarlo ...
 */
#include "cgs_service.h"
#include "ms_cmd_admin.h"
#include "ms_cmd_operator.h"
#include "ms_cmd_sensor.h"
#include "ms_cmd_record.h"
#include "ms_cmd_replay.h"
#include "ms_cmd_report.h"
#include "ms_cmd_status.h"
#include "ms_montecarlo.h"
#include "ms_opts.h"
#include "ms_run.h"
#include "ms_tool.h"

#include <gsl/gsl_errno.h>
#include <stdio.h>
#include <string.h>

static void s_usage (FILE *f)
{
    fprintf (f, "usage: mscgs COMMAND [options]\n"
                "The mscgs multisensor Common Ground Station simulation.\n\n"
                "commands:\n"
                "  run      start every built service of the exercise on this machine\n");
    ms_opts_list (ms_run_options (), 11, f);
    fprintf (
        f, "  record   record every topic into an MCAP file: record [--out FILE] [--topics T,..]\n"
           "  replay   play a recording back on a bus of its own: replay FILE [--speed X]\n"
           "           [--from S] [--station PORT]; pause, resume, time-scale, seek S\n"
           "  echo     print the messages of a topic: echo TOPIC [--json] [--count N]\n"
           "           [--timeout S]\n"
           "  status   a table of every service's health [--wait S]\n"
           "  ping     ask a service's command endpoint for a reply: ping INSTANCE\n"
           "  topics   list the bus topics\n"
           "  keygen   make a CURVE key pair: keygen NAME [--dir DIR]; or the bus's\n"
           "           group key: keygen --group [NAME] [--dir DIR]\n"
           "  loiter, goto, route, altitude, speed task a UAV (uavsim); --help for each\n"
           "  pause, resume, time-scale X          the simulation clock (uavsim),\n"
           "  seek S                               or a replay's\n"
           "  designate TRACK_ID | designate --at POS, cancel, footprint-scale 1|5|10,\n"
           "  intercept-mode head-on|mti-hits      the intercept (guidanced); --help\n"
           "  snapshot [N]  write the imaging sensor's next N frames (default 1) as PNG\n"
           "           files in imagerd's output folder [--to INSTANCE] [--uav ID]\n"
           "  camera [--depression DEG] [--fov DEG] [--stabilized on|off]\n"
           "           [--stare off|target|POS]   point the imaging sensor (uavsim)\n"
           "  sensor visible|infrared|sar   the imaging sensor's mode (imagerd)\n"
           "  fault INSTANCE crash | hang [S] | slow MS [S]   the debug-only fault\n"
           "           channel of a test build (FAULT=1); --help\n"
           "  montecarlo  whole scenes in lockstep, many runs, with the imaged rate and\n"
           "           tracking metrics: [--scenario F] [--runs N] [--seed S] [--jobs J];\n"
           "           --help\n"
           "Commands to a service try for --wait S seconds (default 3) before they\n"
           "report no reply; a retry is never applied twice.\n\n"
           "The exercise file is --exercise F, else $MSCGS_EXERCISE, else\n"
           "/etc/mscgs/exercise.ini, else the installed or source tree's default exercise.\n");
}

/* Every command, and the function that takes its command line (from its
 * name on) and returns the exit code. */
static const struct {
    const char *name;
    int (*main) (int argc, char **argv);
} s_commands[] = {
    {"run", ms_run_main},
    {"echo", ms_echo_main},
    {"record", ms_record_main},
    {"replay", ms_replay_main},
    {"report", ms_report_main},
    {"seek", ms_task_main},
    {"status", ms_status_main},
    {"ping", ms_ping_main},
    {"topics", ms_topics_main},
    {"keygen", ms_keygen_main},
    {"snapshot", ms_snapshot_main},
    {"camera", ms_camera_main},
    {"sensor", ms_sensor_main},
    {"fault", ms_fault_main},
    {"montecarlo", ms_montecarlo_main},
    {"loiter", ms_task_main},
    {"goto", ms_task_main},
    {"route", ms_task_main},
    {"altitude", ms_task_main},
    {"speed", ms_task_main},
    {"pause", ms_task_main},
    {"resume", ms_task_main},
    {"time-scale", ms_task_main},
    {"designate", ms_guide_main},
    {"cancel", ms_guide_main},
    {"footprint-scale", ms_guide_main},
    {"intercept-mode", ms_guide_main},
};

int main (int argc, char **argv)
{
    ms_tool_init ();
    // The lockstep engine runs mtid's and trackerd's cores, which check
    // GSL's return codes as their daemons do; GSL's default handler aborts.
    gsl_set_error_handler_off ();
    if (argc < 2) {
        s_usage (stderr);
        return 2;
    }
    const char *cmd = argv[1];
    for (size_t i = 0; i < sizeof s_commands / sizeof s_commands[0]; i++)
        if (strcmp (cmd, s_commands[i].name) == 0)
            return s_commands[i].main (argc - 1, argv + 1);
    if (strcmp (cmd, "help") == 0 || strcmp (cmd, "-h") == 0 || strcmp (cmd, "--help") == 0) {
        s_usage (stdout);
        return 0;
    }
    if (strcmp (cmd, "--version") == 0) {
        printf ("mscgs %s\n", CGS_VERSION);
        return 0;
    }
    fprintf (stderr, "mscgs: unknown command '%s'\n\n", cmd);
    s_usage (stderr);
    return 2;
}
