/* ms_health — every instance's latest health and the simulation clock, as
 * `mscgs status` prints them and `mscgs run` follows them: a row per
 * instance of the exercise (and per one that reports without being in it). */
#ifndef MS_HEALTH_H
#define MS_HEALTH_H

#include "cgs_exercise.h"
#include "cgs_msg.h"
#include "ms_tool.h"

#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>

typedef struct {
    char instance[CGS_NAME_MAX];
    char program[CGS_NAME_MAX];
    bool enabled;
    bool seen;
    double seen_at; // monotonic
    Cgs__ServiceState state;
    char host[64];    // where the exercise file puts it
    char machine[64]; // the machine its health came from
    uint32_t pid;
    double uptime_s, in_per_s, out_per_s;
    uint64_t gaps, drops, malformed, commands;
    char last_error[256];
    char counters[512]; // the service's own counts, "name=value ..."
    uint64_t http_port; // stationd's map port as it reports it (0: not reported)
    bool sealed;        // its bus payloads are sealed
    uint64_t unauthenticated, replayed;
} ms_health_row_t;

typedef struct {
    ms_health_row_t rows[MS_MAX_INSTANCES];
    size_t nrows;
    double sim_time_s;
    double time_scale;
    bool paused;
    bool have_clock;
    char bus[160]; // the exercise's bus: transport and sealing
    bool sealed;   // the exercise names a group key
} ms_health_t;

/* A row per instance of the exercise, none seen yet, no clock. */
void ms_health_init (ms_health_t *t, const cgs_exercise_t *ex);

/* cgs_sub handlers (arg: the table) of `health` and `clock`. */
void ms_health_on_health (void *arg, const char *topic, const ProtobufCMessage *msg,
                          const Cgs__Header *hdr);
void ms_health_on_clock (void *arg, const char *topic, const ProtobufCMessage *msg,
                         const Cgs__Header *hdr);

/* A row's state at monotonic time now: "down", "silent" (no health for
 * 3 s), "starting", "up", "degraded", "stopping". */
const char *ms_health_state (const ms_health_row_t *r, double now);

/* The table: the bus's line, a line per instance and one of its counters
 * (and its sealing counts, and its sealing when that is not the
 * exercise's) under it. */
void ms_health_print (const ms_health_t *t, FILE *f);

#endif
