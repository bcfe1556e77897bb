/* ms_cmd_record — `mscgs record`: every topic of an exercise (or a chosen
 * set) into an MCAP file with the protobuf schemas inside. */
#ifndef MS_CMD_RECORD_H
#define MS_CMD_RECORD_H

int ms_record_main (int argc, char **argv);

#endif
