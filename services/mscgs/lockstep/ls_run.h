/* ls_run — one whole exercise in lockstep, in one process: the adapters of
 * uavsim, every mtid and bcisd, trackerd and guidanced (the services' own
 * code, as their daemons run it) over an in-process bus (ls_bus), the world
 * stepped as fast as it goes, every message delivered before the next step,
 * guidanced's tasks handed to uavsim at once, and the intercept judged from
 * ground truth as `mscgs run` judges it (ms_observer). imagerd, gateway and
 * stationd do not take part: they change nothing the others see. The same
 * exercise, scenario and variation give the same run, byte for byte.
 *
 * Per-run variation, for Monte Carlo runs of one scene: the exercise seed
 * (radar noise, BCIS, vehicle wander), a shift of every operator
 * designation's time, and the UAVs' start point on their loiter orbits. */
#ifndef LS_RUN_H
#define LS_RUN_H

#include "ms_observer.h"

#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>

typedef struct {
    const char *exercise_path; // required: origin, id, instances and their parameter files
    const char *scenario_path; // NULL: the exercise's scenario
    bool seed_given;           // else the exercise's seed
    uint64_t seed;
    double designation_shift_s; // added to every [operator] line's time (0)
    bool uav_phase_given;       // else the UAVs start where the scenario puts them
    double uav_phase_deg;       // start on the loiter orbit at this bearing from its centre
    double limit_s;             // stop at this simulation time (<= 0: 1500 s after the last
                                // operator line, or 1800 s without one)
    double after_s;             // go on this long after the intercept ends (0)
    FILE *log;                  // the adapters' log lines, "[t] instance: line" (NULL: none)
    /* Called with each message delivered, after the observers (NULL: none). */
    void (*watch) (void *arg, const char *topic, const ProtobufCMessage *msg,
                   const Cgs__Header *hdr);
    void *watch_arg;
} ls_run_config_t;

typedef struct {
    ms_icpt_t icpt;        // the intercept as judged from ground truth
    double end_s;          // simulation time the run ended at
    uint64_t steps;        // world steps
    uint64_t messages;     // messages delivered
    uint64_t tasks;        // tasks guidanced handed to uavsim
    uint64_t bad_inputs;   // messages some adapter could not use: 0 in a sound run
    uint64_t errors;       // problems adapters reported
    uint64_t failures;     // messages the bus could not carry
    char first_error[256]; // the first problem reported, "instance: why"
} ls_run_result_t;

/* Run it. 0 (*ret filled), or a negative errno with the reason in err (a
 * file that does not load, an instance that cannot be built). */
int ls_run (const ls_run_config_t *c, ls_run_result_t *ret, char *err, size_t errlen);

#endif
