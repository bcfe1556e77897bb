/* gd_adapter — guidanced's pure layer between the intercept cores and the
 * transport. It keeps the latest tracks (the track table), runs one
 * intercept per UAV of the scenario (gd_intercept), takes the decoded
 * `uav`, `track` and `track.turn` messages, judges the operator's commands
 * (designate, cancel, footprint scale, intercept method), runs the
 * scenario's operator script when no operator has designated, publishes
 * `intercept` through its port, and keeps the bookkeeping of the tasks that
 * must reach uavsim: each task gets a command number once, before it is
 * first sent, so a resend after a timeout or a restart is a duplicate to
 * uavsim, never a second task. It also writes and reads its whole state
 * (the service's state file's contents). No sockets, clocks, files or
 * logging of its own: the daemon (main.c) sends the tasks over the command
 * channel and saves the state; the mscgs tool's lockstep engine hands the
 * tasks to uavsim's adapter in-process. */
#ifndef GD_ADAPTER_H
#define GD_ADAPTER_H

#include "cgs_msg.h"
#include "cgs_port.h"
#include "cgs_scenario.h"
#include "gd_intercept.h"
#include "gd_params.h"

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#define GD_ADAPTER_UAVS_MAX 16

typedef struct gd_adapter gd_adapter_t;

/* The topics it takes, NULL-terminated: "uav", "track", "track.turn". */
extern const char *const gd_adapter_topics[];

/* An adapter for the UAVs of scenario (kept by the caller, as is terrain,
 * which may be NULL: flat ground), with these parameters, reporting
 * through port (copied). NULL without memory, or with more than
 * GD_ADAPTER_UAVS_MAX UAVs (*ret_too_many set when not NULL). */
gd_adapter_t *gd_adapter_new (const gd_params_t *params, const cgs_scenario_t *scenario,
                              const cgs_terrain_t *terrain, const cgs_port_t *port,
                              bool *ret_too_many);
/* Free; accepts NULL; nulls the pointer. */
void gd_adapter_destroy (gd_adapter_t **self_p);

/* One decoded message of one of its topics, with its header. After a
 * `track` batch it runs the operator script; after each message it
 * publishes `intercept` for the UAVs concerned. */
void gd_adapter_on_message (gd_adapter_t *self, const char *topic, const ProtobufCMessage *msg,
                            const Cgs__Header *hdr);

/* An operator command. Returns 0 when it was judged here (reply filled: ok
 * with a detail, or an error), or 1 for SET_ALTITUDE and SET_SPEED, which
 * go to uavsim as they are (the caller forwards them). */
int gd_adapter_command (gd_adapter_t *self, const Cgs__Command *cmd, Cgs__Reply *reply);

/* The periodic tick (the daemon's delivery timer): each intercept's own
 * time-outs at the latest simulation time heard. */
void gd_adapter_tick (gd_adapter_t *self);

/* ---- tasks for uavsim ---------------------------------------------------------------- */

/* A task command to send to uavsim: a TASK_ROUTE or LOITER command built in
 * the adapter (valid until the next call into it), its command number and
 * the task number it carries. */
typedef struct {
    const Cgs__Command *command;
    uint64_t command_number; // give it to the command client (cgs_cmd_client_set_next_number)
    uint64_t task_number;
    size_t uav;      // index of the UAV it is for
    bool new_number; // the number was given now: save the state before sending
} gd_adapter_task_t;

/* The next task not yet delivered, looking from UAV index *cursor on
 * (start with 0; advanced past the one returned). True and *ret, or false
 * when none is due. */
bool gd_adapter_next_task (gd_adapter_t *self, size_t *cursor, gd_adapter_task_t *ret);
/* uavsim's answer to a task sent: OK, NOT_SAVED, a duplicate or a refusal
 * marks it delivered (a refusal is reported through the port); a
 * BAD_REQUEST that is not a duplicate (the number was taken) makes it go
 * again under a new number. NULL reply: no answer (tried again later). */
void gd_adapter_task_answered (gd_adapter_t *self, const gd_adapter_task_t *task,
                               const Cgs__Reply *reply);
/* A command number for a forwarded command (altitude, speed): the next one
 * of the same client's sequence. */
uint64_t gd_adapter_take_number (gd_adapter_t *self);

/* ---- state ----------------------------------------------------------------------------- */

/* The client id the task numbers go under; set at a fresh start (the
 * daemon makes one that differs from any earlier run's), kept in the state. */
void gd_adapter_set_client_id (gd_adapter_t *self, const char *client_id);
const char *gd_adapter_client_id (const gd_adapter_t *self);
/* The last command number used (the command client goes on from the next). */
uint64_t gd_adapter_last_number (const gd_adapter_t *self);
/* Whether the state changed in a way that must be saved now (a script line
 * done, a designation); cleared by the call. */
bool gd_adapter_take_dirty (gd_adapter_t *self);
/* The whole state, as the state file holds it (a cgs_ckpt frame, "GDST");
 * 0 or -ENOMEM. */
int gd_adapter_save (const gd_adapter_t *self, uint8_t **ret_buf, size_t *ret_len);
/* Restore it; 0, or one of cgs_ckpt's errors with the reason in err (the
 * adapter is then as after gd_adapter_reset). A saved UAV not in the
 * scenario is reported through the port and skipped. */
int gd_adapter_restore (gd_adapter_t *self, const uint8_t *buf, size_t len, char *err,
                        size_t errlen);
/* Back to idle: every intercept new, no task bookkeeping, the script from
 * its start. */
void gd_adapter_reset (gd_adapter_t *self);

/* ---- what it knows ---------------------------------------------------------------------- */

size_t gd_adapter_uav_count (const gd_adapter_t *self);
/* UAV i's intercept (status, task) and its name and entity id. */
const gd_intercept_t *gd_adapter_intercept (const gd_adapter_t *self, size_t i);
const char *gd_adapter_uav_name (const gd_adapter_t *self, size_t i);
uint32_t gd_adapter_uav_id (const gd_adapter_t *self, size_t i);
/* Tracks known (confirmed, coasting and tentative ones not deleted). */
size_t gd_adapter_track_count (const gd_adapter_t *self);
/* Whether a track batch has been heard (the daemon holds commands until then). */
bool gd_adapter_heard_tracks (const gd_adapter_t *self);
/* The latest simulation time heard. */
double gd_adapter_time (const gd_adapter_t *self);

#endif
