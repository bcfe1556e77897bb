/* uavsim_adapter — uavsim's pure layer between the world and its
 * transport. It steps the world, publishes through its port what is due at
 * each step (`entity`, `uav` and `clock`, each at the scenario's rate), and
 * judges the UAV commands (route task, go to, loiter, altitude, speed,
 * camera): each
 * is applied whole or not at all, and a task's acceptance republishes the
 * UAVs at once. Pacing (the time scale, pause) belongs to the transport: the
 * daemon steps the adapter as wall time passes, the mscgs tool's lockstep
 * engine as fast as it can; the adapter only reports them in `clock`. No
 * sockets, clocks or logging of its own. */
#ifndef UAVSIM_ADAPTER_H
#define UAVSIM_ADAPTER_H

#include "cgs_msg.h"
#include "cgs_port.h"
#include "uavsim_msgs.h"
#include "uavsim_world.h"

#include <stdbool.h>

typedef struct uavsim_adapter uavsim_adapter_t;

/* An adapter over world (the caller's, which must outlive it) in the frame
 * of origin, reporting through port (copied). NULL without memory. */
uavsim_adapter_t *uavsim_adapter_new (uavsim_world_t *world, cgs_geodetic_t origin,
                                      const cgs_port_t *port);
/* Free; accepts NULL; nulls the pointer. */
void uavsim_adapter_destroy (uavsim_adapter_t **self_p);
/* The pacing `clock` reports (default 1, running). */
void uavsim_adapter_set_pacing (uavsim_adapter_t *self, double time_scale, bool paused);
/* One step of the world, then what is due at the new time. */
void uavsim_adapter_step (uavsim_adapter_t *self);
/* Publish what is due at the present time; everything when all. */
void uavsim_adapter_publish_due (uavsim_adapter_t *self, bool all);
/* Publish the clock now (after a pacing change). */
void uavsim_adapter_publish_clock (uavsim_adapter_t *self);
/* A command: 0 when it is one of the UAV commands (reply filled: ok with a
 * detail, or an error; an accepted one is logged through the port with its
 * client and number), 1 when it is not the adapter's (PING, PAUSE, RESUME,
 * SET_TIME_SCALE: the caller's; anything else: unsupported, the reply
 * filled). The reply's texts live in the adapter until the
 * next command. */
int uavsim_adapter_command (uavsim_adapter_t *self, const Cgs__Command *cmd, Cgs__Reply *reply);
/* guidanced's `intercept` of time t_s: the designated target's estimate,
 * where a camera staring at the target looks (another UAV's, or one without
 * a UAV, is ignored). */
void uavsim_adapter_on_intercept (uavsim_adapter_t *self, const Cgs__Intercept *m, double t_s);
/* The world. */
uavsim_world_t *uavsim_adapter_world (uavsim_adapter_t *self);

#endif
