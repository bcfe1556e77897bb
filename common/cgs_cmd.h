/* cgs_cmd — the command channel: DEALER (client) to ROUTER (server), never
 * PUB/SUB. Every command carries the client's id and a command number; the
 * client waits for an explicit reply, retries on timeout over a fresh socket
 * (lazy pirate), and gives a clear error when the server stays silent.
 *
 * The server hands each new command to the service's handler, which applies
 * it in memory. Then, before the reply is sent, the server writes one state
 * file, atomically: the stored replies together with the service's state (as
 * the service's save function serialises it). So a command is either applied
 * and acknowledged in the file, or neither: a retry — within one server life
 * or after a crash and restart anywhere in between — is answered from the
 * stored reply or applied afresh to the state as it was, never applied twice
 * to the saved state. A restarted service reloads its state from
 * cgs_cmd_server_saved_state. Side effects outside that state (messages it
 * published, files it wrote itself) may repeat after a crash. Pure of logging
 * and global state. */
#ifndef CGS_CMD_H
#define CGS_CMD_H

#include "cgs_msg.h"
#include <stddef.h>
#include <stdint.h>

#define CGS_CMD_DEFAULT_TIMEOUT_MS 1000
#define CGS_CMD_DEFAULT_ATTEMPTS   5

/* ---- client --------------------------------------------------------------------- */

typedef struct cgs_cmd_client cgs_cmd_client_t;

/* Client of the server at endpoint, with an id unique to this process:
 * LABEL@host:pid:random (label NULL: "client"); NULL with errno on failure. */
cgs_cmd_client_t *cgs_cmd_client_new (void *ctx, const char *endpoint, const char *label);
/* A client with exactly this id whose commands are numbered from
 * first_number: for a tool that keeps its own id and numbering across runs
 * (and for tests of retries). Reusing a number for another command is refused
 * by the server. NULL with errno on failure. */
cgs_cmd_client_t *cgs_cmd_client_new_exact (void *ctx, const char *endpoint, const char *client_id,
                                            uint64_t first_number);
/* Number the next command n (> 0): a sender that keeps its own numbering
 * (and resends a command under the number it first had) sets it before
 * each call. */
void cgs_cmd_client_set_next_number (cgs_cmd_client_t *self, uint64_t n);
/* Close and free; accepts NULL; nulls the pointer. */
void cgs_cmd_client_destroy (cgs_cmd_client_t **self_p);
/* The client's id. */
const char *cgs_cmd_client_id (const cgs_cmd_client_t *self);
/* Hook to configure each new socket (e.g. CURVE keys) before it connects. */
void cgs_cmd_client_set_socket_hook (cgs_cmd_client_t *self, int (*hook) (void *socket, void *arg),
                                     void *arg);
/* Send cmd (its body set by the caller; id and number are filled here) and
 * wait up to timeout_ms per attempt, for up to attempts attempts. On a reply
 * (whatever its status) 0 and *ret_reply, freed by cgs_cmd_reply_free. On
 * silence -ETIMEDOUT with a message in err naming the endpoint; -EPROTO when
 * the reply is malformed; -EINTR when a signal interrupted the wait. */
int cgs_cmd_client_call (cgs_cmd_client_t *self, Cgs__Command *cmd, int timeout_ms, int attempts,
                         Cgs__Reply **ret_reply, char *err, size_t errlen);
/* Free a reply; accepts NULL; nulls the pointer. */
void cgs_cmd_reply_free (Cgs__Reply **reply_p);
/* Name of a command's body ("designate", "ping", ...), "none" when unset. */
const char *cgs_cmd_name (const Cgs__Command *cmd);

/* ---- server --------------------------------------------------------------------- */

typedef struct cgs_cmd_server cgs_cmd_server_t;

/* Apply a new command: fill reply->status (OK by default), ->detail or
 * ->error (strings the handler owns, valid until it is next called). */
typedef void (cgs_cmd_handler_fn) (void *arg, const Cgs__Command *cmd, Cgs__Reply *reply);
/* Serialise the service's state into a new malloc'd buffer; 0 or -errno. */
typedef int (cgs_cmd_save_fn) (void *arg, uint8_t **ret_buf, size_t *ret_len);

/* Server named name (put in every reply). cache_path: file in the state
 * directory for the stored replies, or NULL to keep them in memory only; an
 * existing file is loaded (a damaged one is set aside as cache_path.bad and
 * reported by cgs_cmd_server_load_error); one that cannot be read is an error.
 * NULL with errno on failure. */
cgs_cmd_server_t *cgs_cmd_server_new (void *ctx, const char *name, const char *cache_path,
                                      cgs_cmd_handler_fn *handler, void *arg);
/* Close and free; accepts NULL; nulls the pointer. */
void cgs_cmd_server_destroy (cgs_cmd_server_t **self_p);
/* Save the service's state with every stored reply (called with the handler's arg). */
void cgs_cmd_server_set_save (cgs_cmd_server_t *self, cgs_cmd_save_fn *save);
/* Write the state file now (stored replies and the service's state), e.g. for
 * a periodic checkpoint; 0 or -errno. */
int cgs_cmd_server_save_now (cgs_cmd_server_t *self);
/* The service state found in the state file at start; *ret_len 0 when none. */
void cgs_cmd_server_saved_state (const cgs_cmd_server_t *self, const uint8_t **ret_buf,
                                 size_t *ret_len);
/* Bind the ROUTER socket (creates the folder of an ipc:// path); 0 or -errno. */
int cgs_cmd_server_bind (cgs_cmd_server_t *self, const char *endpoint);
/* Handle up to max waiting commands without blocking; returns how many, or -errno. */
int cgs_cmd_server_dispatch (cgs_cmd_server_t *self, int max);
/* The underlying socket, for zmq_poll and options such as CURVE. */
void *cgs_cmd_server_socket (cgs_cmd_server_t *self);
/* "" or why the stored replies could not be loaded at start. */
const char *cgs_cmd_server_load_error (const cgs_cmd_server_t *self);
/* Counters: commands applied, duplicates answered, malformed refused (and
 * reused command numbers), state file write failures (such a command is
 * answered NOT_SAVED, with the reason, and not stored: a retry applies it
 * again and tries to save again). */
uint64_t cgs_cmd_server_applied (const cgs_cmd_server_t *self);
uint64_t cgs_cmd_server_duplicates (const cgs_cmd_server_t *self);
uint64_t cgs_cmd_server_malformed (const cgs_cmd_server_t *self);
uint64_t cgs_cmd_server_write_errors (const cgs_cmd_server_t *self);
/* "" or the latest failure to write the state file. */
const char *cgs_cmd_server_last_error (const cgs_cmd_server_t *self);

#endif
