/* ms_cmd_replay — `mscgs replay FILE`: a recording played back onto a bus
 * of its own, with pause, resume, speed and seek by command. */
#ifndef MS_CMD_REPLAY_H
#define MS_CMD_REPLAY_H

int ms_replay_main (int argc, char **argv);

#endif
