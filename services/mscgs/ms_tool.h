/* ms_tool — what mscgs's commands share: the exercise file (found as the
 * README says) with the tools' CURVE keys, a subscriber to the exercise's
 * bus, one command to one of its services, a position on the command line. */
#ifndef MS_TOOL_H
#define MS_TOOL_H

#include "cgs_bus.h"
#include "cgs_curve.h"
#include "cgs_exercise.h"
#include "ms_opts.h"

#include <stddef.h>

#define MS_MAX_INSTANCES 64 // instances a command keeps track of
#define MS_TOOL_WAIT_S   3  // a command to a service tries this long by default, s

/* The options many commands take: --exercise F, --to INSTANCE, --uav ID
 * (an entity id) and --wait S (ms_tool_read_wait), into ptr. */
#define MS_TOOL_OPT_EXERCISE(ptr)                                                                  \
    {                                                                                              \
        .name = "exercise", .value = "F", .help = "exercise file", .str = (ptr)                    \
    }
#define MS_TOOL_OPT_TO(ptr)                                                                        \
    {                                                                                              \
        .name = "to", .value = "INSTANCE", .help = "the instance to send to", .str = (ptr)         \
    }
#define MS_TOOL_OPT_UAV(ptr)                                                                       \
    {                                                                                              \
        .name = "uav", .value = "ID", .help = "the UAV's entity id (default the only UAV)",        \
        .fn = ms_opts_read_entity_id, .arg = (ptr)                                                 \
    }
#define MS_TOOL_OPT_WAIT(ptr)                                                                      \
    {                                                                                              \
        .name = "wait", .value = "S", .help = "keep trying S seconds (default 3)",                 \
        .fn = ms_tool_read_wait, .arg = (ptr)                                                      \
    }

/* Find the folder of this binary (once, before the rest). */
void ms_tool_init (void);

/* The folder of this binary: the services' programs are beside it. */
const char *ms_tool_exe_dir (void);

/* The exercise path: given, else $MSCGS_EXERCISE, /etc, beside an install
 * or in the source tree (buf may hold it). */
const char *ms_tool_exercise_path (const char *given, char *buf, size_t size);

/* Load the exercise at that path, and the tools' CURVE keys it names; NULL
 * after saying why. */
cgs_exercise_t *ms_tool_load_exercise (const char *given);

/* The tools' CURVE keys of the exercise loaded last; NULL without keys. */
cgs_curve_t *ms_tool_curve (void);

/* A new ZeroMQ context (in *ret_ctx) and a subscriber that takes only this
 * exercise's messages; NULL after saying why. */
cgs_sub_t *ms_tool_open_sub (const cgs_exercise_t *ex, void **ret_ctx);

/* --multicast IFACE: ms_tool_connect_publishers joins the publishers'
 * multicast endpoints on IFACE (the tool's own host's interface) where they
 * have one, as an instance on a host of its own would; NULL or "": their
 * `publish` endpoints (the default). */
void ms_tool_set_multicast (const char *iface);
/* Connect sub to every publisher of topic; returns how many. */
size_t ms_tool_connect_publishers (cgs_sub_t *sub, const cgs_exercise_t *ex, const char *topic);

/* Send cmd to the instance named to, or the first instance of program,
 * trying wait_s seconds (1 s an attempt); print the reply. Exit code: 0
 * ok, 1 refused or no reply, 2 usage. */
int ms_tool_send (const char *tool, cgs_exercise_t *ex, const char *to, const char *program,
                  Cgs__Command *cmd, double wait_s);

/* A position argument, "E,N" or any form of cgs_config_parse_position, in
 * the exercise's frame: 0, or a negative errno after saying why. */
int ms_tool_position (const cgs_exercise_t *ex, const char *text, Cgs__Enu *ret);

/* The option reader of --wait S (1 to 3600 seconds) into a double (arg). */
int ms_tool_read_wait (const ms_opt_t *opt, const char *value);

#endif
