/* uavsim_msgs — uavsim's world as bus messages: entity batches (every UAV and
 * vehicle), one `uav` message per UAV, and the clock. The storage is reused
 * from one publication to the next, so publishing allocates nothing. Pure:
 * builds messages, sends none. */
#ifndef UAVSIM_MSGS_H
#define UAVSIM_MSGS_H

#include "cgs_msg.h"
#include "uavsim_world.h"

#include <stdbool.h>
#include <stddef.h>

#define UAVSIM_MSGS_BATCH 200 // entities per `entity` message

typedef struct uavsim_msgs uavsim_msgs_t;

/* Storage for the world's entities; NULL on allocation failure. */
uavsim_msgs_t *uavsim_msgs_new (const uavsim_world_t *world);
/* Free; accepts NULL; nulls the pointer. */
void uavsim_msgs_destroy (uavsim_msgs_t **self_p);
/* Refresh every entity from the world; returns the number of batches. */
size_t uavsim_msgs_entities (uavsim_msgs_t *self, uavsim_world_t *world);
/* Batch k of the last refresh (valid until the next). */
Cgs__EntityBatch *uavsim_msgs_batch (uavsim_msgs_t *self, size_t k);
/* The `uav` message of UAV i (valid until the next call). */
Cgs__Uav *uavsim_msgs_uav (uavsim_msgs_t *self, uavsim_world_t *world, size_t i);
/* The direction of a body-fixed sensor depressed by depression_deg on a UAV
 * at that heading, pitch and roll: azimuth clockwise from north [0, 360) and
 * elevation above the horizon (negative below). */
void uavsim_msgs_boresight (double heading_deg, double pitch_deg, double roll_deg,
                            double depression_deg, double *ret_azimuth_deg,
                            double *ret_elevation_deg);
/* The clock message. */
Cgs__Clock *uavsim_msgs_clock (uavsim_msgs_t *self, const uavsim_world_t *world, double time_scale,
                               bool paused, cgs_geodetic_t origin);

#endif
