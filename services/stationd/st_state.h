/* st_state — the tactical map's picture: what stationd keeps of every topic
 * (UAVs and how their cameras are set, each UAV's sensor mode as its latest
 * image says, MTI hits by scan, BCIS replies, tracks, intercepts, ground
 * truth, the latest sensor image and its footprint, which UAV's video is
 * relayed)
 * and the JSON it pushes to every browser. Hits of
 * the scan in progress and of the last complete scan are current (yellow);
 * the complete scans before them, up to history_scans, are the grey history.
 * BCIS replies older than bcis_timeout_s of simulation time are dropped, as
 * are tracks and entities no longer heard of. Pure: no sockets, no clock
 * reads, no logging; time is the simulation time the messages carry. */
#ifndef ST_STATE_H
#define ST_STATE_H

#include "intercept.pb-c.h"
#include "replay.pb-c.h"
#include "sensors.pb-c.h"
#include "tracking.pb-c.h"
#include "world.pb-c.h"

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

typedef struct {
    int history_scans;     // complete scans kept grey behind the current ones
    double bcis_timeout_s; // a BCIS reply is shown this long (simulation seconds)
    double track_stale_s;  // a track not updated this long is dropped
    double truth_stale_s;  // an entity not heard of this long is dropped
} st_state_params_t;

typedef struct st_state st_state_t;

/* An empty picture, or NULL without memory. */
st_state_t *st_state_new (const st_state_params_t *p);
/* Free; accepts NULL; nulls the pointer. */
void st_state_destroy (st_state_t **self_p);

/* Take one message of each topic. 0; -EINVAL when it lacks what the map
 * needs (nothing taken; for an entity batch, the entities without a valid id,
 * position or velocity are left out and the others taken); -ENOSPC when the
 * table of UAVs, intercepts or radars (16 each) is full; -ENOMEM (what was
 * taken before stays). hdr may be NULL (no publisher epoch known). */
int st_state_take_uav (st_state_t *self, const Cgs__Uav *m, const Cgs__Header *hdr);
int st_state_take_mti (st_state_t *self, const Cgs__Mti *m, const Cgs__Header *hdr);
int st_state_take_mti_scan (st_state_t *self, const Cgs__MtiScan *m, const Cgs__Header *hdr);
int st_state_take_bcis (st_state_t *self, const Cgs__Bcis *m, const Cgs__Header *hdr);
int st_state_take_tracks (st_state_t *self, const Cgs__TrackBatch *m, const Cgs__Header *hdr);
int st_state_take_intercept (st_state_t *self, const Cgs__Intercept *m, const Cgs__Header *hdr);
int st_state_take_image (st_state_t *self, const Cgs__Image *m, const Cgs__Header *hdr);
int st_state_take_entities (st_state_t *self, const Cgs__EntityBatch *m, const Cgs__Header *hdr);
/* One frame of video: whether to relay its bytes to the pages. The video
 * relayed is that of the UAV whose picture is shown (st_state_image_path's),
 * or, before any picture is, of the first UAV whose video is heard.
 * *ret_relay: it is that UAV's; *ret_restart: it starts another stream than
 * the frames relayed before (another UAV, or its imagerd restarted: a new
 * publisher epoch), so the pages must start over. 0; -EINVAL, with nothing
 * written, when it carries no transport stream: no bytes, not whole
 * 188-byte packets, or a packet without its 0x47 sync byte. */
int st_state_take_video (st_state_t *self, const Cgs__VideoFrame *m, const Cgs__Header *hdr,
                         bool *ret_relay, bool *ret_restart);
/* A replay's position (`replay`), shown on the page's timeline. -EINVAL
 * (nothing kept) when a number is not finite or the span is negative.
 * *ret_new (may be NULL): the replay sought since the last one (its
 * generation changed): the picture before is stale. */
int st_state_take_replay (st_state_t *self, const Cgs__ReplayState *m, bool *ret_new);
/* The simulation time now, from `clock` (its publisher's epoch). Once a
 * clock is heard, only the clock moves time (before, the messages' own times
 * do); it never goes back, unless a new epoch of the clock starts earlier (a
 * restarted exercise): then time is set back, BCIS replies are dropped and
 * what was heard later than the new time counts as heard now. */
void st_state_set_clock (st_state_t *self, double sim_time_s, uint64_t epoch);
/* The clock's time scale (simulation seconds per wall second; not finite or
 * not positive: unknown) and whether it is paused: the page plays the video
 * at that rate. */
void st_state_set_time_scale (st_state_t *self, double time_scale, bool paused);
/* Move time on without a clock (tests, and before any clock is heard). */
void st_state_set_time (st_state_t *self, double sim_time_s);
/* Latest simulation time heard of. */
double st_state_time (const st_state_t *self);
/* Drop what has aged out at the present simulation time: BCIS replies
 * after bcis_timeout_s; tracks, UAVs, intercepts and a radar's hits not heard
 * of for track_stale_s; entities after truth_stale_s. */
void st_state_prune (st_state_t *self);

/* The picture as one JSON "state" message (see README.md, "Protocol"), seq
 * its number: a malloc'd NUL-terminated string and its length in
 * *ret_len, or NULL without memory. */
char *st_state_json (st_state_t *self, uint64_t seq, size_t *ret_len);

/* Counts, for health and tests. */
size_t st_state_hit_count (const st_state_t *self); // every hit kept (current and history)
size_t st_state_track_count (const st_state_t *self);
/* The latest image's file ("" none) and frame number. */
const char *st_state_image_path (const st_state_t *self, uint64_t *ret_frame);
/* The picture shows the image of that frame (its file is there to serve);
 * until this is called it shows none. */
void st_state_image_shown (st_state_t *self, uint64_t frame);

/* The footprint as drawn: each corner moved away from the centre by scale
 * (1, 5 or 10; any other value draws it as it is). */
void st_footprint_scaled (const double corners_en[8], const double center_en[2], unsigned scale,
                          double ret_en[8]);

#endif
