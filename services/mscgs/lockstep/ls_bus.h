/* ls_bus — the lockstep engine's in-process bus: the adapters of every
 * service publish into it through ports (one per instance, as each service
 * binds one publisher), and it delivers each message to the subscribers of
 * its topic in publication order, draining every message published meanwhile
 * before it returns. Messages travel as the bus carries them: checked
 * against the topic catalogue (cgs_topics), stamped with the same header
 * (source, exercise id, epoch, per-topic sequence number, simulation time),
 * encoded and decoded by cgs_msg's stamped codec. The wall time stamped is
 * the simulation time and every epoch is 1, so the same inputs give the
 * same bytes on every run and machine. Single-threaded; no sockets. */
#ifndef LS_BUS_H
#define LS_BUS_H

#include "cgs_bus.h"
#include "cgs_port.h"

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

typedef struct ls_bus ls_bus_t;
typedef struct ls_source ls_source_t;

/* What one publisher's adapter reported besides its messages. */
typedef struct {
    uint64_t published;  // messages it published
    uint64_t bad_inputs; // input its adapter could not use
    uint64_t errors;     // problems it reported (health's last error, live)
    char last_error[256];
} ls_source_stats_t;

/* A bus of exercise exercise_id; NULL without memory. */
ls_bus_t *ls_bus_new (uint32_t exercise_id);
/* Free, with every source; accepts NULL; nulls the pointer. */
void ls_bus_destroy (ls_bus_t **self_p);
/* A publisher named source (an instance name); NULL without memory. Its
 * port (ls_bus_port) stays valid as long as the bus. */
ls_source_t *ls_bus_source (ls_bus_t *self, const char *source);
cgs_port_t ls_bus_port (ls_source_t *src);
const ls_source_stats_t *ls_bus_source_stats (const ls_source_t *src);
/* Where the adapters' log lines go (NULL, the default: dropped), each as
 * "[sim t] source: line". */
void ls_bus_set_log (ls_bus_t *self, FILE *f);
/* Deliver topic's messages to fn, after the subscribers before it; 0 or
 * -ENOMEM, -EINVAL for a topic not in the catalogue. */
int ls_bus_subscribe (ls_bus_t *self, const char *topic, cgs_sub_fn *fn, void *arg);
/* Deliver everything queued, and everything published meanwhile, in
 * publication order; returns how many messages were delivered. */
size_t ls_bus_drain (ls_bus_t *self);
/* The simulation time of the latest message delivered (0 before any). */
double ls_bus_time (const ls_bus_t *self);
/* What every source reported, added up: bad inputs, errors, and the first
 * error as "source: why" into first (may be NULL). */
void ls_bus_report (const ls_bus_t *self, uint64_t *ret_bad_inputs, uint64_t *ret_errors,
                    char *first, size_t firstlen);
/* Messages that could not be queued (out of memory) or decoded: 0 in a sound run. */
uint64_t ls_bus_failures (const ls_bus_t *self);

#endif
