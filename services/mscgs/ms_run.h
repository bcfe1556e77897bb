/* ms_run — `mscgs run`, the supervisor of an exercise's services on this
 * machine (the README's Commands table says all it does). */
#ifndef MS_RUN_H
#define MS_RUN_H

#include "ms_opts.h"

/* mscgs run [--exercise F] [--scenario F] [--speed X] [--duration S]
 * [--out DIR] [--resume] [--stop-after-intercept S]; the exit code. */
int ms_run_main (int argc, char **argv);

/* run's options, for the tool's help. */
const ms_opt_t *ms_run_options (void);

#endif
