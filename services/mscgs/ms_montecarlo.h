/* ms_montecarlo — the `mscgs montecarlo` command (see ms_montecarlo.c). */
#ifndef MS_MONTECARLO_H
#define MS_MONTECARLO_H

/* Parse the options after "montecarlo" (argv[0]) and run; the exit code. */
int ms_montecarlo_main (int argc, char **argv);

#endif
