/* cgs_health — the `health` message every service publishes at 1 Hz: state,
 * uptime, message counts and rates per topic, gaps, drops, malformed inputs,
 * commands, and the last error. Reads the counters of the publisher,
 * subscribers and command server it is told to watch. Pure of logging. */
#ifndef CGS_HEALTH_H
#define CGS_HEALTH_H

#include "cgs_bus.h"
#include "cgs_cmd.h"

typedef struct cgs_health cgs_health_t;

/* Health of one service instance, which the exercise file places on host
 * (NULL or "": none given); NULL on allocation failure. */
cgs_health_t *cgs_health_new (const char *program, const char *instance, const char *version,
                              const char *host);
/* Free; accepts NULL; nulls the pointer. */
void cgs_health_destroy (cgs_health_t **self_p);
/* Count this publisher's traffic (outbound). */
void cgs_health_watch_pub (cgs_health_t *self, const cgs_pub_t *pub);
/* Count this subscriber's traffic (inbound); up to 8 subscribers. */
int cgs_health_watch_sub (cgs_health_t *self, const cgs_sub_t *sub);
/* Count this command server's commands. */
void cgs_health_watch_cmd (cgs_health_t *self, const cgs_cmd_server_t *cmd);
/* Set the state (CGS__SERVICE_STATE__SERVICE_STATE_RUNNING, ...). */
void cgs_health_set_state (cgs_health_t *self, Cgs__ServiceState state);
/* Whether the service's bus payloads are sealed (reported as `sealed`). */
void cgs_health_set_sealed (cgs_health_t *self, bool sealed);
/* Record the last error (copied), with the wall time. */
void cgs_health_set_error (cgs_health_t *self, const char *error);
/* Count malformed inputs the service found itself (beyond the bus's own). */
void cgs_health_add_malformed (cgs_health_t *self, uint64_t n);
/* Set a named count of the service's own (up to 16 names; the name is
 * copied, at most 31 characters); reported in every health message after. */
void cgs_health_set_counter (cgs_health_t *self, const char *name, uint64_t value);
/* Build the message and publish it on `health`; rates are over the time
 * since the previous call. 0 or the publisher's error. */
int cgs_health_publish (cgs_health_t *self, cgs_pub_t *pub, double sim_time_s);

#endif
