/* cgs_exercise — the exercise file every host shares: exercise id, origin,
 * time scale, seed, state directory, default scenario, and for every service
 * instance its publish and command endpoints (and, optionally, CURVE keys).
 *
 *   [exercise]
 *   id = 1                       ; DIS exercise id too, 1..255
 *   name = default
 *   origin = geo 36.5950 -121.8740 0
 *   time_scale = 1
 *   seed = 1
 *   state_dir = /var/lib/mscgs   ; relative: from the working directory, not the file
 *   scenario = ../scenarios/default.ini
 *
 *   [service uavsim]             ; instance name; program is the part before '.'
 *   publish = ipc:///tmp/mscgs/uavsim.pub
 *   command = ipc:///tmp/mscgs/uavsim.cmd
 *   host = localhost             ; where it runs (used by deploy tooling)
 *   hwm = 100000                 ; messages queued per subscriber before loss
 *   multicast = epgm://10.0.0.2;239.192.77.1:7400 ; optional: also publish on UDP multicast
 *   interface = eth0             ; its multicast interface (else [bus] interface)
 *
 *   [bus]                        ; optional: the bus over UDP multicast, and sealing
 *   transport = epgm             ; epgm | norm: every publisher gets a multicast endpoint
 *                                ; (group + k, port + k for the k-th); tcp | ipc: none
 *   group = 239.192.77.1         ; the first publisher's group
 *   port = 7400                  ; the first publisher's port
 *   interface = eth0             ; the multicast interface of every instance without one
 *   key_file = group.key         ; seal every payload (mscgs keygen --group); none: clear
 *   replay_window_s = 30         ; refuse sealed messages sent longer ago (0: no limit)
 *   rate_kbps = 100000           ; epgm: the sender's rate limit
 *   recovery_ms = 5000           ; epgm: how long a sender keeps data for repairs
 *   hops = 1                     ; epgm: multicast TTL
 *
 * A subscriber takes a publisher's multicast endpoint (on its own interface)
 * when the publisher runs on another host, and its `publish` endpoint when
 * both run on the same host (PGM never loops back to its own host); the
 * tools (mscgs) always take `publish`.
 *
 * Pure: no logging. */
#ifndef CGS_EXERCISE_H
#define CGS_EXERCISE_H

#include "cgs_config.h"
#include "cgs_geo.h"
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#define CGS_NAME_MAX             64
#define CGS_ENDPOINT_MAX         256
#define CGS_KEY_MAX              41     // Z85 CURVE key, 40 characters and a NUL
#define CGS_EXERCISE_DEFAULT_HWM 100000 // messages a publisher queues per subscriber

typedef struct {
    char name[CGS_NAME_MAX];        // instance, e.g. "mtid.uav1"
    char program[CGS_NAME_MAX];     // executable, e.g. "mtid" (or `program =`)
    char publish[CGS_ENDPOINT_MAX]; // PUB endpoint it binds, "" if none
    char command[CGS_ENDPOINT_MAX]; // ROUTER endpoint it binds, "" if none
    char host[CGS_NAME_MAX];        // host it runs on (default "localhost")
    char uav[CGS_NAME_MAX];         // UAV it serves, for per-UAV services ("" if none)
    char params[4096];              // model parameter file, absolute ("" if none)
    char public_key[CGS_KEY_MAX];   // CURVE server public key ("" without CURVE)
    char secret_key_file[4096];     // file holding its secret key ("" without CURVE)
    int hwm;                        // high-water mark of its PUB and SUB sockets, messages
    bool enabled;                   // `enabled = no` leaves it out of `mscgs run`
    char mcast_scheme[8];           // "norm" or "epgm": it also publishes on multicast; "" not
    char mcast_group[64];           // its multicast GROUP:PORT ("" without multicast)
    char interface[CGS_NAME_MAX];   // its multicast interface ("" when none is given)
} cgs_instance_t;

/* [bus]: the multicast transport's parameters and the sealing key. */
typedef struct {
    char transport[8];      // "norm", "epgm", "tcp" or "ipc" (the default: tcp)
    char key_file[4096];    // absolute; "" runs in the clear
    double replay_window_s; // sealed: refuse messages sent longer ago than this; 0: no limit
    int rate_kbps;          // epgm: ZMQ_RATE
    int recovery_ms;        // epgm: ZMQ_RECOVERY_IVL
    int hops;               // epgm: ZMQ_MULTICAST_HOPS
} cgs_bus_params_t;

#define CGS_BUS_DEFAULT_GROUP     "239.192.77.1"
#define CGS_BUS_DEFAULT_PORT      7400
#define CGS_BUS_DEFAULT_WINDOW_S  30
#define CGS_BUS_DEFAULT_RATE_KBPS 100000
#define CGS_BUS_DEFAULT_RECOVERY  5000
#define CGS_BUS_DEFAULT_HOPS      1

typedef struct cgs_exercise cgs_exercise_t;

/* Read and validate an exercise file; 0, or negative errno with
 * "file:line: reason" in err. Endpoints must be tcp://, ipc:// or inproc://
 * and unique; instance names unique. */
int cgs_exercise_load (const char *path, cgs_exercise_t **ret_ex, char *err, size_t errlen);
/* Free; accepts NULL; sets *self_p to NULL. */
void cgs_exercise_destroy (cgs_exercise_t **self_p);

const char *cgs_exercise_path (const cgs_exercise_t *self);
const char *cgs_exercise_name (const cgs_exercise_t *self);
uint32_t cgs_exercise_id (const cgs_exercise_t *self);
cgs_geodetic_t cgs_exercise_origin (const cgs_exercise_t *self);
double cgs_exercise_time_scale (const cgs_exercise_t *self);
uint64_t cgs_exercise_seed (const cgs_exercise_t *self);
/* State directory, absolute. */
const char *cgs_exercise_state_dir (const cgs_exercise_t *self);
/* Default scenario file, absolute, "" when none. */
const char *cgs_exercise_scenario (const cgs_exercise_t *self);
/* The parsed file. */
cgs_config_t *cgs_exercise_config (cgs_exercise_t *self);
/* Whether the exercise uses CURVE: some instance has a public_key, or there is
 * a [curve] section. Then every instance has a public_key and a
 * secret_key_file (checked at load). */
bool cgs_exercise_uses_curve (const cgs_exercise_t *self);
/* [curve]: the tools' pair ("" when not given; the secret key's file
 * absolute), and the other client keys admitted (`allow =` lines). */
const char *cgs_exercise_client_public_key (const cgs_exercise_t *self);
const char *cgs_exercise_client_secret_key_file (const cgs_exercise_t *self);
size_t cgs_exercise_allowed_count (const cgs_exercise_t *self);
const char *cgs_exercise_allowed (const cgs_exercise_t *self, size_t i);
/* The [bus] section (defaults when absent). */
const cgs_bus_params_t *cgs_exercise_bus (const cgs_exercise_t *self);
/* Whether the linked libzmq carries the bus over NORM (newer than 4.3.4,
 * whose NORM engine stops on a message over 2038 bytes); its version in
 * the three. A norm transport is refused at load when it does not. */
bool cgs_exercise_norm_usable (int *major, int *minor, int *patch);
/* Whether any instance publishes on multicast. */
bool cgs_exercise_uses_multicast (const cgs_exercise_t *self);
/* The endpoint through which `local` (an instance of the exercise, or NULL
 * for a tool) reaches publisher pub: its multicast endpoint on local's
 * interface ("norm://IFACE;GROUP:PORT") when pub has one and runs on
 * another host than local, else pub's `publish`. Pass pub as local for the
 * endpoint pub binds on multicast (use_multicast forced). buf holds
 * CGS_ENDPOINT_MAX bytes. Returns whether the endpoint is multicast. */
bool cgs_exercise_endpoint_for (const cgs_instance_t *pub, const cgs_instance_t *local, char *buf,
                                size_t len);

/* The first instance of program (in the file's order), or NULL. */
const cgs_instance_t *cgs_exercise_first_of (const cgs_exercise_t *self, const char *program);

size_t cgs_exercise_instance_count (const cgs_exercise_t *self);
const cgs_instance_t *cgs_exercise_instance (const cgs_exercise_t *self, size_t i);
/* The instance of that name, or NULL. */
const cgs_instance_t *cgs_exercise_find (const cgs_exercise_t *self, const char *name);
/* Instances that publish topic (per cgs_topics), up to max into ret; returns the
 * number found (may exceed max). */
size_t cgs_exercise_publishers_of (const cgs_exercise_t *self, const char *topic,
                                   const cgs_instance_t **ret, size_t max);

#endif
