/* cgs_score — how well an intercept imaged its target, judged from ground
 * truth: each target position against the latest true footprint. */
#include "cgs_score.h"

#include <math.h>
#include <string.h>

#define CGS_SCORE_MAX_AGE_S 0.5 // default: a footprint older than this judges nothing

void cgs_score_init (cgs_score_t *self)
{
    memset (self, 0, sizeof *self);
    self->max_age_s = CGS_SCORE_MAX_AGE_S;
    self->designation_s = NAN;
    self->first_inside_s = NAN;
    self->closest_m = INFINITY;
    self->closest_s = NAN;
    self->closest_edge_m = INFINITY;
}

void cgs_score_designated (cgs_score_t *self, double t_s)
{
    if (self->designated)
        return;
    self->designated = true;
    self->designation_s = t_s;
}

void cgs_score_footprint (cgs_score_t *self, double t_s, const cgs_footprint_t *fp)
{
    self->have_fp = fp != NULL;
    if (!fp)
        return;
    self->fp = *fp;
    self->fp_t_s = t_s;
}

/* True when the latest footprint may judge a target seen at t_s: one is
 * shown and its time is within max_age_s of t_s (either way: footprints and
 * target positions come from different publishers, so a footprint a little
 * newer than the target position is as good as one a little older). */
static bool s_footprint_fresh (const cgs_score_t *self, double t_s)
{
    return self->have_fp && fabs (t_s - self->fp_t_s) <= self->max_age_s;
}

/* Judge p at t_s against the footprint; returns whether it is inside. */
static bool s_judge (cgs_score_t *self, double t_s, cgs_v2_t p)
{
    self->judged++;
    bool inside = cgs_footprint_contains (&self->fp, p);
    double centre_m = hypot (p.e - self->fp.center.e, p.n - self->fp.center.n);
    if (centre_m < self->closest_m) {
        self->closest_m = centre_m;
        self->closest_s = t_s;
    }
    double edge_m = inside ? 0.0 : cgs_footprint_distance (&self->fp, p);
    if (edge_m < self->closest_edge_m)
        self->closest_edge_m = edge_m;
    if (inside && !self->imaged) {
        self->imaged = true;
        self->first_inside_s = t_s;
    }
    return inside;
}

void cgs_score_target (cgs_score_t *self, double t_s, cgs_v2_t p)
{
    self->samples++;
    bool inside = s_footprint_fresh (self, t_s) && s_judge (self, t_s, p);
    // An interval counts when both of its ends were inside.
    if (inside && self->have_target && self->last_inside && t_s > self->last_t_s)
        self->inside_s += t_s - self->last_t_s;
    self->have_target = true;
    self->last_inside = inside;
    self->last_t_s = t_s;
}

double cgs_score_time_to_image (const cgs_score_t *self)
{
    if (!self->designated || !self->imaged)
        return NAN;
    return self->first_inside_s - self->designation_s;
}
