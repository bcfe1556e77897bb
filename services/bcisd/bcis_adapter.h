/* bcis_adapter — bcisd's pure layer between the interrogator model and its
 * transport. It takes the decoded `entity` and `uav` messages of its UAV,
 * keeps the ground entities (dead-reckoned to each dwell's time, on the
 * terrain), interrogates once a dwell for every dwell that has ended by the
 * time of each `uav` message, and publishes through its port each
 * interrogation's replies and the end of each scan on `bcis`. No sockets,
 * clocks or logging of its own: the daemon (main.c) and the mscgs tool's
 * lockstep engine drive the same code. */
#ifndef BCIS_ADAPTER_H
#define BCIS_ADAPTER_H

#include "bcis_interrogator.h"
#include "bcis_params.h"
#include "cgs_msg.h"
#include "cgs_port.h"
#include "cgs_sensor.h"

#include <stdint.h>

#define BCIS_ADAPTER_STALE_S                                                                       \
    10.0 // an entity not heard of for this long (simulation time) is
         // forgotten

typedef struct bcis_adapter bcis_adapter_t;

typedef struct {
    uint64_t dwells_run;   // interrogations modelled (one a dwell)
    uint64_t skipped;      // dwells skipped because the adapter fell behind
    uint64_t interrogated; // transponders in the beam
    uint64_t blocked;      // of them, behind terrain
    uint64_t replies;      // replies published
} bcis_adapter_stats_t;

/* The topics it takes, NULL-terminated: "entity", "uav". */
extern const char *const bcis_adapter_topics[];

/* An adapter of the interrogator with these parameters on sensor's UAV (the
 * sensor stays the caller's and must outlive the adapter), reporting
 * through port (copied). NULL without memory. */
bcis_adapter_t *bcis_adapter_new (const bcis_params_t *params, cgs_sensor_t *sensor,
                                  const cgs_port_t *port);
/* Free; accepts NULL; nulls the pointer. */
void bcis_adapter_destroy (bcis_adapter_t **self_p);
/* One decoded message of one of its topics, with its header. */
void bcis_adapter_on_message (bcis_adapter_t *self, const char *topic, const ProtobufCMessage *msg,
                              const Cgs__Header *hdr);
/* The scan it follows (for the daemon's start-up line). */
const cgs_scan_t *bcis_adapter_scan (const bcis_adapter_t *self);
/* Counters. */
const bcis_adapter_stats_t *bcis_adapter_stats (const bcis_adapter_t *self);

#endif
