/* cgs_curve — CURVE security for every socket of an exercise, when its file
 * names keys: each instance has a key pair (`public_key`, `secret_key_file`
 * in its section); servers (PUB, ROUTER) run as CURVE servers with their own
 * secret key, clients (SUB, DEALER) authenticate with their own pair to the
 * server's public key; tools such as mscgs use the pair of the exercise's
 * [curve] section (`client_public_key`, `client_secret_key_file`). A ZAP
 * handler in each server process admits only the listed keys: every
 * instance's, the tools', and any `allow = KEY` of [curve] (libzmq admits
 * anyone who knows the server key when no handler runs, so the handler is
 * bound before any server socket). The exercise loader reads [curve] and
 * checks every key and that every instance has its pair; here the secret
 * keys are read and matched to their public keys. Without keys in the
 * exercise everything here does nothing. Pure of logging; errors name the
 * file and key. */
#ifndef CGS_CURVE_H
#define CGS_CURVE_H

#include "cgs_cmd.h"
#include "cgs_exercise.h"

#include <stdbool.h>
#include <stdint.h>

typedef struct cgs_curve cgs_curve_t;

/* The exercise's CURVE set-up for the instance named (NULL: a tool, with the
 * [curve] client pair). *ret_curve is NULL when the exercise names no keys.
 * 0, or -errno with the reason in err (a key missing or unreadable, an
 * instance without keys in an exercise that has them). */
int cgs_curve_load (cgs_exercise_t *ex, const char *instance, cgs_curve_t **ret_curve, char *err,
                    size_t errlen);
/* Free; accepts NULL; nulls the pointer. */
void cgs_curve_destroy (cgs_curve_t **self_p);
/* Make socket a CURVE server with this instance's secret key (before bind);
 * 0 (also when self is NULL) or -errno. */
int cgs_curve_server (const cgs_curve_t *self, void *socket);
/* Make socket's next connection a CURVE client of the server whose public key
 * is server_key (before connect); 0 (also when self is NULL) or -errno;
 * -EINVAL when the server has no key. */
int cgs_curve_client (const cgs_curve_t *self, void *socket, const char *server_key);
/* Give a command client's every socket (it makes a new one per try) the
 * client side towards server_key; 0 (also when self is NULL) or -errno.
 * Thread-safe. */
int cgs_curve_protect_client (cgs_curve_t *self, cgs_cmd_client_t *client, const char *server_key);
/* Bind the ZAP handler in ctx (one per process, before any server socket
 * binds); 0 or -errno. Then poll cgs_curve_zap_socket and call
 * cgs_curve_zap_handle when it is readable. */
int cgs_curve_zap_bind (cgs_curve_t *self, void *ctx);
void *cgs_curve_zap_socket (cgs_curve_t *self);
/* Answer the ZAP requests waiting; returns how many, or -errno. */
int cgs_curve_zap_handle (cgs_curve_t *self);
/* Connections admitted and refused by the ZAP handler. */
uint64_t cgs_curve_admitted (const cgs_curve_t *self);
uint64_t cgs_curve_refused (const cgs_curve_t *self);
/* The public key of the pair this side authenticates with. */
const char *cgs_curve_public_key (const cgs_curve_t *self);

#endif
