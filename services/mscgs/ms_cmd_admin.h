/* ms_cmd_admin — the commands around an exercise: `mscgs snapshot`
 * (imagerd's frames as PNG files), `fault` (a test build's fault channel)
 * and `keygen` (a CURVE key pair). Each takes the command line from its
 * name on and returns the exit code. */
#ifndef MS_CMD_ADMIN_H
#define MS_CMD_ADMIN_H

/* mscgs snapshot [N] [--to INSTANCE] [--uav ID] [--exercise F]. */
int ms_snapshot_main (int argc, char **argv);

/* mscgs fault INSTANCE crash | hang [S] | slow MS [S] [--state-dir DIR]. */
int ms_fault_main (int argc, char **argv);

/* mscgs keygen NAME [--dir DIR]. */
int ms_keygen_main (int argc, char **argv);

#endif
