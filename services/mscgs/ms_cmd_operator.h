/* ms_cmd_operator — the operator's commands: uavsim's tasks and clock
 * (`mscgs loiter`, `goto`, `route`, `altitude`, `speed`, `pause`, `resume`,
 * `time-scale`) and guidanced's intercept (`designate`, `cancel`,
 * `footprint-scale`, `intercept-mode`). Each takes the command line from
 * its name (argv[0]) on and returns the exit code. */
#ifndef MS_CMD_OPERATOR_H
#define MS_CMD_OPERATOR_H

/* mscgs loiter|goto|route|altitude|speed|pause|resume|time-scale ... */
int ms_task_main (int argc, char **argv);

/* mscgs designate|cancel|footprint-scale|intercept-mode ... */
int ms_guide_main (int argc, char **argv);

#endif
