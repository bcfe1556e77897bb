/* ms_cmd_status — the commands that look at the bus: `mscgs status`, `echo`,
 * `ping` and `topics`. Each takes the command line from its name on and
 * returns the exit code. */
#ifndef MS_CMD_STATUS_H
#define MS_CMD_STATUS_H

/* mscgs status [--wait S] [--exercise F]: every instance's health. */
int ms_status_main (int argc, char **argv);

/* mscgs echo TOPIC [--json] [--count N] [--timeout S] [--exercise F]. */
int ms_echo_main (int argc, char **argv);

/* mscgs ping INSTANCE [--exercise F]. */
int ms_ping_main (int argc, char **argv);

/* mscgs topics: the topic catalogue (arguments ignored). */
int ms_topics_main (int argc, char **argv);

#endif
