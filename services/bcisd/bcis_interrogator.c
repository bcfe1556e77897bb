/* bcis_interrogator — the scanning interrogator (see bcis_interrogator.h). */
#include "bcis_interrogator.h"
#include "cgs_util.h"

#include <assert.h>
#include <errno.h>
#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define S_DEG          (M_PI / 180.0)
#define S_CERTAIN_ERRS 1e-12 // expected bit errors below which a message is whole without a draw

struct bcis_interrogator {
    bcis_params_t p;
    const cgs_terrain_t *terrain; // borrowed; NULL: flat open ground at 0
    cgs_scan_t scan;
    gsl_rng *rng;
    bcis_reply_t *replies;
    size_t reply_count, reply_cap;
    bcis_truth_t *truth;
    size_t truth_count, truth_cap;
};

void bcis_interrogator_destroy (bcis_interrogator_t **self_p)
{
    assert (self_p);
    bcis_interrogator_t *self = *self_p;
    if (!self)
        return;
    if (self->rng)
        gsl_rng_free (self->rng);
    free (self->replies);
    free (self->truth);
    free (self);
    *self_p = NULL;
}

bcis_interrogator_t *bcis_interrogator_new (const bcis_params_t *p, const cgs_terrain_t *terrain,
                                            uint64_t seed)
{
    if (bcis_params_check (p, NULL, 0) < 0)
        return NULL;
    bcis_interrogator_t *self = calloc (1, sizeof *self);
    if (!self)
        return NULL;
    self->p = *p;
    self->terrain = terrain;
    cgs_scan_params_t sp = bcis_params_scan (p);
    if (cgs_scan_init (&sp, &self->scan) < 0)
        goto fail;
    if (!(self->rng = gsl_rng_alloc (gsl_rng_mt19937)))
        goto fail;
    gsl_rng_set (self->rng, (unsigned long)(seed ^ (seed >> 32)));
    return self;
fail:
    bcis_interrogator_destroy (&self);
    return NULL;
}

const cgs_scan_t *bcis_interrogator_scan (const bcis_interrogator_t *self)
{
    return &self->scan;
}

bool bcis_interrogator_send (bcis_interrogator_t *self, double ebn0_db, int bits)
{
    double g = pow (10.0, ebn0_db / 10.0);
    if (bits * bcis_ber (self->p.modulation, g) < S_CERTAIN_ERRS)
        return true;
    int errors = 0, allowed = self->p.correctable_bits;
    if (self->p.modulation == BCIS_MOD_BFSK) {
        // Non-coherent: the sent tone's filter holds the signal (energy Eb,
        // random phase) and noise, the other noise only (complex noise of
        // unit power, N0 = 1); the larger energy wins.
        double a = sqrt (g);
        for (int i = 0; i < bits && errors <= allowed; i++) {
            double phase = 2 * M_PI * gsl_rng_uniform (self->rng);
            double r1 = a * cos (phase) + gsl_ran_gaussian_ziggurat (self->rng, M_SQRT1_2),
                   i1 = a * sin (phase) + gsl_ran_gaussian_ziggurat (self->rng, M_SQRT1_2);
            double r2 = gsl_ran_gaussian_ziggurat (self->rng, M_SQRT1_2),
                   i2 = gsl_ran_gaussian_ziggurat (self->rng, M_SQRT1_2);
            errors += r2 * r2 + i2 * i2 > r1 * r1 + i1 * i1;
        }
    } else {
        // Coherent antipodal (BPSK, and each rail of Gray QPSK): the matched
        // filter's output sqrt(Eb) + noise of variance N0/2, scaled to unit
        // noise variance, is sqrt(2 Eb/N0) + n; a negative one is an error.
        double a = sqrt (2.0 * g);
        for (int i = 0; i < bits && errors <= allowed; i++)
            errors += a + gsl_ran_gaussian_ziggurat (self->rng, 1.0) < 0;
    }
    return errors <= allowed;
}

bool bcis_interrogator_geometry (const bcis_interrogator_t *self, cgs_enu_t uav, cgs_enu_t ground,
                                 double beam_az_deg, bcis_geometry_t *ret)
{
    const bcis_params_t *p = &self->p;
    cgs_enu_t tr = {ground.e_m, ground.n_m, ground.u_m + p->antenna_height_m};
    double de = tr.e_m - uav.e_m, dn = tr.n_m - uav.n_m, du = uav.u_m - tr.u_m;
    double hor = hypot (de, dn), range = sqrt (hor * hor + du * du);
    bcis_geometry_t g = {.range_m = range};
    g.elevation_deg = atan2 (du, hor) / S_DEG;
    double az = cgs_wrap360 (atan2 (de, dn) / S_DEG);
    g.az_off_deg = cgs_wrap360 (az - beam_az_deg + 180.0) - 180.0;
    g.el_off_deg = g.elevation_deg - p->beam_depression_deg; // depression below the UAV
    // The part of the path below the rain height.
    double lo = fmin (uav.u_m, tr.u_m), hi = fmax (uav.u_m, tr.u_m), h = p->rain_height_m;
    if (h >= hi)
        g.rain_path_m = range;
    else if (h <= lo)
        g.rain_path_m = 0;
    else
        g.rain_path_m = range * (h - lo) / (hi - lo);
    bool open = !self->terrain || cgs_terrain_los (self->terrain, uav, tr);
    g.foliage_m = open && self->terrain ? cgs_terrain_foliage_m (self->terrain, uav, tr) : 0;
    *ret = g;
    return open;
}

int bcis_interrogator_dwell (bcis_interrogator_t *self, const cgs_dwell_t *d, cgs_enu_t uav,
                             const bcis_entity_t *entities, size_t n, bcis_dwell_out_t *ret)
{
    const bcis_params_t *p = &self->p;
    self->reply_count = self->truth_count = 0;
    size_t in_beam = 0;
    for (size_t i = 0; i < n; i++) {
        const bcis_entity_t *e = &entities[i];
        double de = e->position.e_m - uav.e_m, dn = e->position.n_m - uav.n_m;
        double az = cgs_wrap360 (atan2 (de, dn) / S_DEG);
        if (!cgs_dwell_contains (d, az))
            continue;
        double hor = hypot (de, dn), du = uav.u_m - e->position.u_m;
        double range = hypot (hor, du);
        if (range < p->min_range_m || range > p->max_range_m)
            continue;
        double dep = atan2 (du, hor) / S_DEG;
        if (fabs (dep - p->beam_depression_deg) > p->elevation_beamwidth_deg)
            continue;
        in_beam++;
        if (!e->transponder || e->force != CGS_FORCE_FRIENDLY)
            continue; // only friendly transponders answer
        if (cgs_grow ((void **)&self->truth, &self->truth_cap, self->truth_count + 1,
                      sizeof *self->truth) < 0 ||
            cgs_grow ((void **)&self->replies, &self->reply_cap, self->reply_count + 1,
                      sizeof *self->replies) < 0)
            return -ENOMEM;
        bcis_truth_t *t = &self->truth[self->truth_count++];
        *t = (bcis_truth_t){.entity_id = e->id};
        t->blocked =
            !bcis_interrogator_geometry (self, uav, e->position, d->az_center_deg, &t->geometry);
        if (t->blocked)
            continue;
        bcis_budget (p, &t->geometry, &t->budget);
        t->heard = bcis_interrogator_send (self, t->budget.up_ebn0_db, p->interrogation_bits);
        t->answered =
            t->heard && bcis_interrogator_send (self, t->budget.down_ebn0_db, p->reply_bits);
        if (!t->answered)
            continue;
        bcis_reply_t *r = &self->replies[self->reply_count++];
        *r = (bcis_reply_t){
            .responder_id = e->id,
            .range_m =
                t->geometry.range_m + gsl_ran_gaussian_ziggurat (self->rng, p->range_sigma_m),
            .range_sigma_m = p->range_sigma_m,
            .azimuth_deg = d->az_center_deg,
            .azimuth_sigma_deg = d->width_deg / sqrt (12.0),
            .snr_up_db = t->budget.up_ebn0_db,
            .snr_down_db = t->budget.down_ebn0_db,
        };
        snprintf (r->marking, sizeof r->marking, "%s", e->marking ? e->marking : "");
        if (p->reports_position) {
            double s = p->position_sigma_m;
            r->position_fix = true;
            r->position_sigma_m = s;
            r->position = (cgs_enu_t){e->position.e_m + gsl_ran_gaussian_ziggurat (self->rng, s),
                                      e->position.n_m + gsl_ran_gaussian_ziggurat (self->rng, s),
                                      e->position.u_m + gsl_ran_gaussian_ziggurat (self->rng, s)};
        } else {
            (void)cgs_terrain_at_slant_range (self->terrain, uav, r->azimuth_deg, r->range_m,
                                              &r->position);
        }
    }
    *ret = (bcis_dwell_out_t){
        .replies = self->replies,
        .reply_count = self->reply_count,
        .truth = self->truth,
        .truth_count = self->truth_count,
        .in_beam = in_beam,
    };
    return 0;
}
