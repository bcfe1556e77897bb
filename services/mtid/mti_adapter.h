/* mti_adapter — mtid's pure layer between the radar model and its
 * transport. It takes the decoded `entity` and `uav` messages of its UAV,
 * keeps the ground entities (dead-reckoned to each dwell's time, on the
 * terrain), runs every dwell of the scan that has ended by the time of each
 * `uav` message, and publishes through its port each dwell's hits (`mti`),
 * what it saw of each entity (`mti.truth`) and each completed scan
 * (`mti.scan`). No sockets, clocks or logging of its own: the daemon
 * (main.c) and the mscgs tool's lockstep engine drive the same code. */
#ifndef MTI_ADAPTER_H
#define MTI_ADAPTER_H

#include "cgs_msg.h"
#include "cgs_port.h"
#include "cgs_sensor.h"
#include "mti_params.h"
#include "mti_radar.h"

#include <stdint.h>

#define MTI_ADAPTER_STALE_S                                                                        \
    10.0 // an entity not heard of for this long (simulation time) is
         // forgotten

typedef struct mti_adapter mti_adapter_t;

typedef struct {
    uint64_t dwells_run; // dwells modelled and published
    uint64_t skipped;    // dwells skipped because the adapter fell behind (time jumped ahead)
} mti_adapter_stats_t;

/* The topics it takes, NULL-terminated: "entity", "uav". */
extern const char *const mti_adapter_topics[];

/* An adapter of the radar with these parameters on sensor's UAV (the sensor
 * stays the caller's and must outlive the adapter), reporting through port
 * (copied). NULL without memory. */
mti_adapter_t *mti_adapter_new (const mti_params_t *params, cgs_sensor_t *sensor,
                                const cgs_port_t *port);
/* Free; accepts NULL; nulls the pointer. */
void mti_adapter_destroy (mti_adapter_t **self_p);
/* One decoded message of one of its topics, with its header. */
void mti_adapter_on_message (mti_adapter_t *self, const char *topic, const ProtobufCMessage *msg,
                             const Cgs__Header *hdr);
/* The radar model (for the daemon's start-up line). */
const mti_radar_t *mti_adapter_radar (const mti_adapter_t *self);
/* Counters. */
const mti_adapter_stats_t *mti_adapter_stats (const mti_adapter_t *self);

#endif
