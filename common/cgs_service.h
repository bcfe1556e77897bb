/* cgs_service — the thin shell every service's main.c shares: standard
 * options, the exercise file, the instance's publisher, subscriptions to every
 * publisher of a topic, the command server, the 1 Hz health message, signals,
 * systemd notification and the watchdog, all around one cgs_loop. Unlike the
 * rest of common/, this is main-program code: it logs (through cgs_log) and
 * prints usage.
 *
 * Standard options: --exercise FILE (default $MSCGS_EXERCISE, else
 * /etc/mscgs/exercise.ini), --instance NAME (default: the program's name),
 * --scenario FILE, --params FILE, --state-dir DIR, --time-scale X (the
 * exercise's time scale, for the service that owns time), --check (validate the
 * configuration and exit), -v/--verbose, -h/--help, --version.
 *
 * Built with CGS_FAULT (make FAULT=1; the test build is), it also serves the
 * debug-only fault channel of cgs_fault.h on ipc://STATE_DIR/INSTANCE.fault. */
#ifndef CGS_SERVICE_H
#define CGS_SERVICE_H

#include "cgs_bus.h"
#include "cgs_cmd.h"
#include "cgs_curve.h"
#include "cgs_exercise.h"
#include "cgs_fault.h"
#include "cgs_health.h"
#include "cgs_loop.h"
#include "cgs_port.h"
#include "cgs_scenario.h"

#include <stdbool.h>

#define CGS_VERSION "0.1.0"

/* One service-specific long option. */
typedef struct {
    const char *name; // without the dashes
    bool has_arg;
    const char *arg_name; // for help, e.g. "N"
    const char *help;
} cgs_service_option_t;

/* What a service tells the shell about itself. */
typedef struct {
    const char *program;                 // e.g. "uavsim"
    const char *summary;                 // one line for --help
    const cgs_service_option_t *options; // extra options, ended by {NULL}; may be NULL
    /* Called for each extra option given; return 0, or -EINVAL after filling why. */
    int (*on_option) (void *arg, const char *name, const char *value, char *why, size_t whylen);
    void *option_arg;
} cgs_service_info_t;

/* One running service: its options, exercise, instance, loop, sockets and
 * health. Opaque; read it through the accessors below. */
typedef struct cgs_service cgs_service_t;

/* Parse options, read the exercise, find the instance, create the state
 * folder, the loop and the publisher (bound). Returns 0 with *ret_svc set to
 * go on (with --check, only the options, exercise and instance are set up), 1
 * when --help or --version was printed (exit 0), or a negative errno after
 * logging why (exit non-zero); *ret_svc is written only when 0 is returned. */
int cgs_service_new (const cgs_service_info_t *info, int argc, char **argv,
                     cgs_service_t **ret_svc);
/* Free everything and set *self_p to NULL; accepts NULL. */
void cgs_service_destroy (cgs_service_t **self_p);

/* The instance's name (--instance, default the program's name). */
const char *cgs_service_instance_name (const cgs_service_t *svc);
/* The exercise file read (--exercise, $MSCGS_EXERCISE, or the default). */
const char *cgs_service_exercise_path (const cgs_service_t *svc);
/* The scenario file (--scenario, else the exercise's); "" when none. */
const char *cgs_service_scenario_path (const cgs_service_t *svc);
/* The model parameter file (--params, else the instance's); "" when none. */
const char *cgs_service_params_path (const cgs_service_t *svc);
/* The state folder (--state-dir, else the exercise's); absolute unless --check. */
const char *cgs_service_state_dir (const cgs_service_t *svc);
/* Simulation seconds per wall second: --time-scale, else the exercise's. */
double cgs_service_time_scale (const cgs_service_t *svc);
/* Whether --time-scale was on the command line. */
bool cgs_service_time_scale_given (const cgs_service_t *svc);
/* Whether --check was given: validate the configuration and exit. */
bool cgs_service_check_only (const cgs_service_t *svc);
/* How many times -v/--verbose was given. */
int cgs_service_verbose (const cgs_service_t *svc);
/* The exercise read; valid while the service lives. */
const cgs_exercise_t *cgs_service_exercise (const cgs_service_t *svc);
/* This instance's section of the exercise; valid while the service lives. */
const cgs_instance_t *cgs_service_instance (const cgs_service_t *svc);
/* The ZeroMQ context, for the service's own sockets; NULL with --check. */
void *cgs_service_ctx (cgs_service_t *svc);
/* The event loop, for the service's own timers and fds; NULL with --check. */
cgs_loop_t *cgs_service_loop (cgs_service_t *svc);
/* The health message's counters and last error; NULL with --check. */
cgs_health_t *cgs_service_health (cgs_service_t *svc);
/* The CURVE keys, to protect the service's own clients; NULL when none. */
cgs_curve_t *cgs_service_curve (cgs_service_t *svc);
/* The publisher; NULL when the instance publishes nothing (or --check). */
cgs_pub_t *cgs_service_pub (cgs_service_t *svc);
/* The subscriber; NULL before the first cgs_service_subscribe. */
cgs_sub_t *cgs_service_sub (cgs_service_t *svc);
/* The command server; NULL before cgs_service_serve_commands. */
cgs_cmd_server_t *cgs_service_cmd_server (cgs_service_t *svc);
/* Whether the commands are held (cgs_service_hold_commands). */
bool cgs_service_commands_held (const cgs_service_t *svc);
/* Set the simulation time that publish and health stamp on messages. */
void cgs_service_set_sim_time (cgs_service_t *svc, double sim_time_s);

/* Subscribe to topic with fn, connecting to every publisher of it named in
 * the exercise; 0 or -errno (logged). */
int cgs_service_subscribe (cgs_service_t *svc, const char *topic, cgs_sub_fn *fn, void *arg);
/* Serve commands on the instance's command endpoint. After each command the
 * stored replies and the service's state (from save, which may be NULL) are
 * written to STATE_DIR/INSTANCE.state in one atomic write before the reply
 * goes out; 0 or -errno (logged). */
int cgs_service_serve_commands (cgs_service_t *svc, cgs_cmd_handler_fn *handler,
                                cgs_cmd_save_fn *save, void *arg);
/* Hold the commands (true): they wait in the socket, unanswered, while a
 * client's retries cover the wait; or take them again (false), the waiting
 * ones first. For a restarted service that must hear the bus before it can
 * judge commands. */
void cgs_service_hold_commands (cgs_service_t *svc, bool hold);
/* Input the service cannot use (what: "a uav message without ..."): counted
 * in health as malformed, logged the first time, only counted after. */
void cgs_service_bad_input (cgs_service_t *svc, const char *what);
/* Take an `entity` batch (msg, with its header) into ents: the entities
 * without a valid id, position, velocity, heading or time are bad input;
 * running out of memory is health's last error. */
struct cgs_entities;
void cgs_service_take_entities (cgs_service_t *svc, struct cgs_entities *ents,
                                const ProtobufCMessage *msg, const Cgs__Header *hdr);
/* Write the state file now (a periodic checkpoint); 0 or -errno (counted in
 * health as the last error). */
int cgs_service_save_state (cgs_service_t *svc);
/* The service state saved by the previous run (after serve_commands); *ret_len
 * 0 when there was none. */
void cgs_service_saved_state (const cgs_service_t *svc, const uint8_t **ret_buf, size_t *ret_len);
/* Publish msg on topic stamped with the simulation time
 * (cgs_service_set_sim_time); a failure is counted and becomes the health's
 * last error. */
int cgs_service_publish (cgs_service_t *svc, const char *topic, ProtobufCMessage *msg);
/* The port an adapter of this service works through: publish stamps the
 * message with the time given (and makes it the health's time), log goes
 * to cgs_log, bad_input to cgs_service_bad_input, error to the health's
 * last error. Valid while svc lives. */
cgs_port_t cgs_service_port (cgs_service_t *svc);
/* The exercise's scene: the local frame about its origin, the scenario it
 * names (cgs_service_scenario_path, seeded by the exercise) and that scenario's
 * terrain. 0 with all three set (the caller destroys them:
 * cgs_terrain_destroy, cgs_scenario_destroy, cgs_geo_destroy); -EINVAL when
 * no scenario is named or the origin is unusable, or the scenario's own
 * error, with err filled. */
int cgs_service_load_scene (const cgs_service_t *svc, cgs_geo_t **ret_frame,
                            cgs_scenario_t **ret_scenario, cgs_terrain_t **ret_terrain, char *err,
                            size_t errlen);
/* Run the loop until stopped: READY to systemd, health at 1 Hz, the watchdog
 * from the loop. Returns the process exit code. */
int cgs_service_run (cgs_service_t *svc);

#endif
