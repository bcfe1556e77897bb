/* cgs_loop — one event loop per daemon, after Redis's ae: zmq_poll over the
 * registered ZeroMQ sockets and file descriptors, with periodic timers on the
 * monotonic clock (scheduling only; model time comes from the bus). Stops
 * when asked or when cgs_lifecycle reports a stop. */
#ifndef CGS_LOOP_H
#define CGS_LOOP_H

#include <stdint.h>

typedef struct cgs_loop cgs_loop_t;

/* Called when a socket or descriptor is readable, or a timer is due. */
typedef void (cgs_loop_fn) (void *arg);

/* New empty loop; NULL on allocation failure. */
cgs_loop_t *cgs_loop_new (void);
/* Free; accepts NULL; nulls the pointer. Does not close sockets. */
void cgs_loop_destroy (cgs_loop_t **self_p);
/* Watch a ZeroMQ socket for input; 0 or -ENOMEM. */
int cgs_loop_add_socket (cgs_loop_t *self, void *socket, cgs_loop_fn *fn, void *arg);
/* Watch a file descriptor for input; 0 or -ENOMEM. */
int cgs_loop_add_fd (cgs_loop_t *self, int fd, cgs_loop_fn *fn, void *arg);
/* Stop watching a socket or descriptor (socket NULL: match fd). */
void cgs_loop_remove (cgs_loop_t *self, void *socket, int fd);
/* Call fn every interval_s seconds (first call one interval from now);
 * returns a timer id (> 0) or -EINVAL / -ENOMEM. */
int cgs_loop_add_timer (cgs_loop_t *self, double interval_s, cgs_loop_fn *fn, void *arg);
/* Change a timer's interval (next call one new interval from now). */
void cgs_loop_set_interval (cgs_loop_t *self, int timer_id, double interval_s);
/* Run until cgs_loop_stop or a lifecycle stop; 0, or -errno on a poll failure. */
int cgs_loop_run (cgs_loop_t *self);
/* Make cgs_loop_run return after the current callback. */
void cgs_loop_stop (cgs_loop_t *self);
/* Monotonic time, seconds. */
double cgs_loop_now (void);

#endif
