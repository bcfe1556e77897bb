/* cgs_score — how well an intercept imaged its target, judged from ground
 * truth (which guidanced itself never sees): the true footprint over time
 * against the designated target's true position over time. Used by the
 * mscgs tool: `mscgs run`'s summary and the lockstep Monte Carlo. Pure: no
 * logging.
 *
 * Feed footprints and target positions in time order, as they come; each
 * target position is judged against the latest footprint, if it is no
 * older than max_age_s. Time inside is the sum of the intervals between
 * consecutive target positions that were both inside. */
#ifndef CGS_SCORE_H
#define CGS_SCORE_H

#include "cgs_footprint.h"

#include <stdbool.h>
#include <stddef.h>

typedef struct {
    double max_age_s; // a footprint older than this judges nothing (default 0.5 s)
    // Latest footprint.
    bool have_fp;
    cgs_footprint_t fp;
    double fp_t_s;
    // Latest target sample.
    bool have_target;
    bool last_inside;
    double last_t_s;
    // Results.
    bool designated;
    double designation_s; // simulation time of the designation
    bool imaged;          // the target was inside the true footprint at least once
    double first_inside_s;
    double inside_s;        // time inside the true footprint, seconds
    double closest_m;       // closest distance of the target to the footprint centre
    double closest_s;       // when
    double closest_edge_m;  // closest distance to the footprint (0 once inside)
    size_t samples, judged; // target positions fed, and judged against a footprint
} cgs_score_t;

/* A score with nothing seen yet (closest_m and closest_edge_m +inf). */
void cgs_score_init (cgs_score_t *self);
/* The designation happened at t_s (the first call counts). */
void cgs_score_designated (cgs_score_t *self, double t_s);
/* The true footprint at t_s, or NULL when none is shown (no intercept). */
void cgs_score_footprint (cgs_score_t *self, double t_s, const cgs_footprint_t *fp);
/* The target's true ground position at t_s. */
void cgs_score_target (cgs_score_t *self, double t_s, cgs_v2_t p);
/* Designation to the first moment inside, seconds; NaN when not imaged or
 * not designated. */
double cgs_score_time_to_image (const cgs_score_t *self);

#endif
