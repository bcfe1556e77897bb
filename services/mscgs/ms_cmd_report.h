/* ms_cmd_report — `mscgs report FILE [--out DIR]`: the after-action review
 * of a recording, as one HTML file with its charts inline, PNG figures and
 * the run summary's figures computed again from the recording. */
#ifndef MS_CMD_REPORT_H
#define MS_CMD_REPORT_H

int ms_report_main (int argc, char **argv);

#endif
