/* trk_tracker — tracks from MTI hits (see trk_tracker.h).
 *
 * One scan, in order:
 *  1. the scan's hits get their measurement covariance R;
 *  2. tracks whose time is after the scan (simulation time went back) go;
 *  3. the hits go into a hash grid; each track of the radar looks up the
 *     cells its gate can reach over the scan and keeps the hits inside its
 *     gate as pairs: χ² of the innovation at the hit's own time ≤ G, with S
 *     widened for a confirmed track by the manoeuvre allowance (a_m dt²/2)²
 *     per axis; no track takes a hit beyond its reach at the fastest
 *     target's speed since its estimate;
 *  4. tracks and hits joined by pairs form clusters (union-find); each
 *     cluster is one optimal assignment with cost d² + ln|S| per pair and
 *     G + 1 + ln|S| for leaving a track without a hit (global nearest
 *     neighbour), first over the pairs inside the filter's own gates, then
 *     over what is left with the manoeuvre allowance;
 *  5. assigned tracks are updated, the others count a miss when the scan
 *     covered them; unassigned hits start tentative tracks unless they fell
 *     in a confirmed track's gate;
 *  6. M of N, coasting and deletion; turn detection; identity ageing;
 *     history trimmed to the last scans. */
#include "trk_tracker.h"
#include "cgs_util.h"
#include "trk_assign.h"
#include "trk_kbest.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define S_PI           3.14159265358979323846
#define S_CELL_M       500.0 // hash grid cell
#define S_FORBIDDEN    1e9   // cost of a pair outside the gate in a cluster's matrix
#define S_TIME_SLACK_S 1.0   // a track this far after a scan's end means time went back
#define S_BCIS_RADARS  64    // radars a BCIS reply can mark a track of
#define S_MODEL_MIN_MU 1e-3  // IMM: a model this unlikely opens no gate
#define S_SHARE_MIN    0.01  // IMM: least share of a hit's likelihood a track may take it with
#define S_CLOSE_GATE2  9.2103 // IMM: χ²₂ at 0.99: a hit this close to a confirmed track starts none
#define S_CLOSE_GATE3  11.345 // χ²₃ at 0.99, with the radial velocity
#define S_KBEST_TRACKS 12     // IMM: a cluster of more tracks weighs its best hypothesis alone
#define S_ALT_SCANS    3      // IMM: scans a track keeps its other branch (N-scan pruning)
#define S_ALT_MIN      1e-3   // IMM: least probability a branch is kept with

/* A hit of the scan being processed. */
typedef struct {
    trk_hit_t h;
    double R[4];       // measurement covariance
    bool in_confirmed; // inside a confirmed track's gate
    size_t track;      // assigned track (index), or SIZE_MAX
    double best_cost;  // IMM: the least cost of a pair with it
} s_hit_t;

/* A track-hit pair inside the gate. */
typedef struct {
    size_t track, hit; // indices
    double cost;       // d² + ln|S| (what the pass being solved uses)
    double log_det;
    double gate;                      // the gate it passed (2 or 3 degrees of freedom)
    size_t root;                      // its cluster (union-find root)
    bool plain;                       // inside the filter's own gate (first pass)
    double cost_plain, log_det_plain; // without the manoeuvre allowance
    double cost_wide, log_det_wide;   // with it (second pass)
    double miss;                      // IMM: the cost of leaving the track without a hit (NaN:
                                      // G + 1 + ln|S| of its worst-conditioned pair)
} s_pair_t;

/* One branch's cost of a hit (s_imm_cost). */
typedef struct {
    double cost, miss, log_det, gate;
    bool close;
} s_imm_cost_t;

/* The other branch of a track that took a hit after a coast (a two-branch,
 * track-oriented hypothesis tree, pruned after S_ALT_SCANS scans): the
 * track as it would be had that hit been a false alarm or another
 * vehicle's. Same id; ln_odds is ln P(this branch)/P(the track's). */
typedef struct {
    uint32_t id;
    uint32_t born_scan; // the scan that branched
    bool live;          // s_alt_index's mark: its track still exists
    double ln_odds;
    trk_track_t t;
} s_alt_t;

#define S_GAIN_CACHE 16 // the paper's gains of recent update intervals (dt_auto)

struct trk_tracker {
    trk_params_t p;
    trk_gains_t gains[2]; // at the nominal dt_s
    struct {
        long key; // the interval in tenths of a second (0: empty)
        trk_gains_t g[2];
    } gain_cache[S_GAIN_CACHE];
    double gate;  // G, two degrees of freedom (position)
    double gate3; // three (position and radial velocity)
    double tau;   // cos(turn threshold)
    trk_track_t *tracks;
    size_t count, cap;
    uint32_t next_id;
    trk_assign_t *assign;
    trk_kbest_t *kbest; // IMM: the k best hypotheses of a cluster
    // Scan workspace, reused.
    s_hit_t *hits;
    size_t hit_cap;
    int64_t *cell_keys; // hash grid: cell key per slot
    size_t *cell_head;  // first hit of the slot's cell (SIZE_MAX: empty)
    size_t grid_cap;    // slots, a power of two
    size_t *hit_next;   // next hit in the same cell
    size_t hit_next_cap;
    s_pair_t *pairs;
    size_t pair_count, pair_cap;
    s_pair_t *work; // one pass's pairs
    size_t work_count, work_cap;
    size_t *uf; // union-find parents over tracks then hits
    size_t uf_cap;
    size_t *assigned; // per track: assigned hit, or SIZE_MAX
    size_t assigned_cap;
    double *miss_beta; // IMM, per track: the probability it had no hit this scan
    size_t miss_beta_cap;
    double *beta; // one cluster's association probabilities
    size_t beta_cap;
    size_t *act; // indices of the scanned radar's tracks
    size_t act_cap;
    double *cost; // one cluster's matrix
    size_t cost_cap;
    size_t *col; // its solution
    size_t col_cap;
    size_t *ctracks; // one cluster's tracks
    size_t ctracks_cap;
    size_t *chits; // and hits
    size_t chits_cap;
    trk_turn_t *turns;
    size_t turn_count, turn_cap;
    trk_track_t *dead;
    size_t dead_count, dead_cap;
    // IMM: confirmed tracks deleted lately, which a new track may continue.
    trk_track_t *lost;
    size_t lost_count, lost_cap;
    uint32_t *fresh; // IMM: ids of the tracks confirmed in the scan
    size_t fresh_count, fresh_cap;
    trk_pd_radar_t radar; // the radar during the scan being processed
    // IMM: the other branch of tracks that took a hit after a coast.
    s_alt_t *alts;
    size_t alt_count, alt_cap;
    size_t *alt_of; // per scanned track: its branch in alts, or SIZE_MAX
    size_t alt_of_cap;
    const cgs_terrain_t *terrain; // borrowed: what the radars look over (NULL: none)
    double clutter_ln;            // ln of its false alarm density per m² (IMM costs)
};

/* The paper's gains of both axes at interval dt_s into g; 0, or -EINVAL. */
static int s_paper_gains (const trk_filter_params_t *f, double dt_s, trk_gains_t g[2])
{
    for (int a = 0; a < 2; a++)
        if (trk_gains_paper (f->sigma_meas_m[a], f->sigma_mod_mps2[a], dt_s, &g[a]) < 0)
            return -EINVAL;
    return 0;
}

trk_tracker_t *trk_tracker_new (const trk_params_t *p)
{
    char why[256];
    if (!p || trk_params_check (p, why, sizeof why) < 0)
        return NULL;
    trk_tracker_t *self = calloc (1, sizeof *self);
    if (!self)
        return NULL;
    self->p = *p;
    self->p.imm.sigma_mps2[0] = fmax (p->filter.sigma_mod_mps2[0], p->filter.sigma_mod_mps2[1]);
    self->p.detection.span_mps = p->radial_span_mps;
    self->p.imm.max_speed_mps = 0; // the filter's models unbounded (see s_same_target)
    if (s_paper_gains (&p->filter, p->filter.dt_s, self->gains) < 0)
        goto fail;
    self->gate = trk_params_gate (p);
    self->gate3 = trk_params_gate3 (p);
    self->tau = cos (p->turn_threshold_deg * S_PI / 180);
    self->next_id = 1;
    self->assign = trk_assign_new ();
    self->kbest = trk_kbest_new ();
    if (!self->assign || !self->kbest)
        goto fail;
    return self;
fail:
    trk_tracker_destroy (&self);
    return NULL;
}

void trk_tracker_destroy (trk_tracker_t **self_p)
{
    if (!self_p || !*self_p)
        return;
    trk_tracker_t *self = *self_p;
    trk_assign_destroy (&self->assign);
    trk_kbest_destroy (&self->kbest);
    free (self->miss_beta);
    free (self->beta);
    free (self->tracks);
    free (self->hits);
    free (self->cell_keys);
    free (self->cell_head);
    free (self->hit_next);
    free (self->pairs);
    free (self->work);
    free (self->uf);
    free (self->assigned);
    free (self->act);
    free (self->cost);
    free (self->col);
    free (self->ctracks);
    free (self->chits);
    free (self->turns);
    free (self->dead);
    free (self->lost);
    free (self->fresh);
    free (self->alts);
    free (self->alt_of);
    free (self);
    *self_p = NULL;
}

const trk_params_t *trk_tracker_params (const trk_tracker_t *self)
{
    return &self->p;
}

/* The paper's gains for an update dt_s after the estimate: the nominal
 * ones, or with dt_auto those of dt_s itself, taken to a tenth of a second
 * (a target's revisit wanders by a dwell, 0.08 s, as it moves in azimuth)
 * and kept in a small cache. */
static const trk_gains_t *s_gains (trk_tracker_t *self, double dt_s)
{
    if (!self->p.filter.dt_auto || !(dt_s > 0) || !isfinite (dt_s))
        return self->gains;
    long key = lround (fmin (fmax (dt_s, 0.1), 3600.0) * 10);
    size_t slot = (size_t)key % S_GAIN_CACHE;
    if (self->gain_cache[slot].key != key) {
        trk_gains_t g[2];
        if (s_paper_gains (&self->p.filter, key / 10.0, g) < 0)
            return self->gains; // not for parameters trk_params_check accepts
        memcpy (self->gain_cache[slot].g, g, sizeof g);
        self->gain_cache[slot].key = key;
    }
    return self->gain_cache[slot].g;
}

bool trk_tracker_radar_revisit (trk_tracker_t *self, double revisit_s)
{
    if (!(revisit_s > 0) || !isfinite (revisit_s))
        return true;
    trk_filter_params_t *f = &self->p.filter;
    bool agrees = f->dt_auto || fabs (revisit_s - f->dt_s) <= TRK_REVISIT_TOLERANCE * f->dt_s;
    if (!agrees)
        f->dt_auto = true;
    if (f->dt_auto) { // the nominal interval is the radar's from now on
        f->dt_s = revisit_s;
        trk_gains_t g[2];
        if (s_paper_gains (f, f->dt_s, g) == 0)
            memcpy (self->gains, g, sizeof g);
    }
    return agrees;
}

const trk_gains_t *trk_tracker_gains (const trk_tracker_t *self)
{
    return self->gains;
}

size_t trk_tracker_count (const trk_tracker_t *self)
{
    return self->count;
}

const trk_track_t *trk_tracker_at (const trk_tracker_t *self, size_t i)
{
    return i < self->count ? &self->tracks[i] : NULL;
}

const trk_track_t *trk_tracker_find (const trk_tracker_t *self, uint32_t id)
{
    for (size_t i = 0; i < self->count; i++)
        if (self->tracks[i].id == id)
            return &self->tracks[i];
    return NULL;
}

uint32_t trk_tracker_next_id (const trk_tracker_t *self)
{
    return self->next_id;
}

static bool s_imm (const trk_tracker_t *self, const trk_track_t *t)
{
    return self->p.filter.mode == TRK_FILTER_IMM && t->hits >= 2;
}

/* IMM: the track's models mixed and moved to t_s; ret->mu holds the
 * predicted mode probabilities. */
static void s_imm_predict (const trk_tracker_t *self, const trk_track_t *t, double t_s,
                           trk_imm_t *ret)
{
    trk_imm_t mixed;
    trk_imm_mix (&self->p.imm, &t->imm, t_s - t->est.t_s, &mixed);
    trk_imm_predict (&self->p.imm, &mixed, t_s, ret);
}

void trk_tracker_predict (const trk_tracker_t *self, const trk_track_t *t, double t_s,
                          trk_estimate_t *ret)
{
    if (s_imm (self, t)) {
        trk_imm_t pr;
        s_imm_predict (self, t, t_s, &pr);
        trk_imm_combine (&pr, ret);
        return;
    }
    trk_filter_predict (&t->est, &self->p.filter, t_s, ret);
}

/* ---- measurement covariance ------------------------------------------------------ */

static void s_hit_covariance (const trk_tracker_t *self, const trk_hit_t *h, double R[4])
{
    if (self->p.measurement_noise == TRK_NOISE_HIT && h->range_sigma_m > 0 &&
        h->azimuth_sigma_deg > 0) {
        trk_filter_polar_covariance (h->ground_range_m, h->azimuth_deg, h->range_sigma_m,
                                     h->azimuth_sigma_deg, R);
        return;
    }
    R[0] = self->p.filter.sigma_meas_m[0] * self->p.filter.sigma_meas_m[0];
    R[1] = R[2] = 0;
    R[3] = self->p.filter.sigma_meas_m[1] * self->p.filter.sigma_meas_m[1];
}

/* Largest eigenvalue of a symmetric 2×2 matrix. */
static double s_lambda_max (double a, double b, double d)
{
    double m = (a + d) / 2, h = (a - d) / 2;
    return m + sqrt (h * h + b * b);
}

static bool s_hit_ok (const trk_hit_t *h)
{
    return isfinite (h->t_s) && isfinite (h->z[0]) && isfinite (h->z[1]) && isfinite (h->up_m) &&
           isfinite (h->ground_range_m) && isfinite (h->azimuth_deg) &&
           isfinite (h->range_sigma_m) && isfinite (h->azimuth_sigma_deg) &&
           (!h->has_radial || (isfinite (h->radial_mps) && isfinite (h->los[0]) &&
                               isfinite (h->los[1]) && hypot (h->los[0], h->los[1]) <= 1 + 1e-9)) &&
           fabs (h->z[0]) < 1e8 && fabs (h->z[1]) < 1e8;
}

/* ---- hash grid of the scan's hits ------------------------------------------------- */

static int64_t s_cell_key (int64_t ix, int64_t iy)
{
    return (int64_t)((uint64_t)ix << 32) ^ (int64_t)(uint32_t)iy;
}

static size_t s_slot (const trk_tracker_t *self, int64_t key)
{
    uint64_t h = (uint64_t)key * 0x9E3779B97F4A7C15ull;
    return (size_t)(h >> 20) & (self->grid_cap - 1);
}

static int64_t s_cell_of (double v)
{
    return (int64_t)floor (v / S_CELL_M);
}

static void s_grid_build (trk_tracker_t *self, size_t nh)
{
    for (size_t s = 0; s < self->grid_cap; s++)
        self->cell_head[s] = SIZE_MAX;
    for (size_t i = 0; i < nh; i++) {
        int64_t key =
            s_cell_key (s_cell_of (self->hits[i].h.z[0]), s_cell_of (self->hits[i].h.z[1]));
        size_t s = s_slot (self, key);
        while (self->cell_head[s] != SIZE_MAX && self->cell_keys[s] != key)
            s = (s + 1) & (self->grid_cap - 1);
        self->cell_keys[s] = key;
        self->hit_next[i] = self->cell_head[s];
        self->cell_head[s] = i;
    }
}

static size_t s_grid_first (const trk_tracker_t *self, int64_t ix, int64_t iy)
{
    int64_t key = s_cell_key (ix, iy);
    size_t s = s_slot (self, key);
    while (self->cell_head[s] != SIZE_MAX) {
        if (self->cell_keys[s] == key)
            return self->cell_head[s];
        s = (s + 1) & (self->grid_cap - 1);
    }
    return SIZE_MAX;
}

/* ---- union-find ------------------------------------------------------------------- */

static size_t s_find (size_t *uf, size_t a)
{
    while (uf[a] != a) {
        uf[a] = uf[uf[a]];
        a = uf[a];
    }
    return a;
}

static void s_union (size_t *uf, size_t a, size_t b)
{
    a = s_find (uf, a);
    b = s_find (uf, b);
    if (a != b)
        uf[a > b ? a : b] = a < b ? a : b;
}

trk_hit_t trk_hit_from_mti (uint32_t hit_id, double t_s, cgs_enu_t hit, cgs_enu_t platform,
                            double azimuth_deg, double range_sigma_m, double azimuth_sigma_deg,
                            double radial_mps)
{
    double de = hit.e_m - platform.e_m, dn = hit.n_m - platform.n_m, du = hit.u_m - platform.u_m;
    double slant = sqrt (de * de + dn * dn + du * du), ground = hypot (de, dn);
    return (trk_hit_t){
        .hit_id = hit_id,
        .t_s = t_s,
        .z = {hit.e_m, hit.n_m},
        .up_m = hit.u_m,
        .ground_range_m = ground,
        .azimuth_deg = azimuth_deg,
        .range_sigma_m = ground > 0 ? range_sigma_m * slant / ground : 0,
        .azimuth_sigma_deg = azimuth_sigma_deg,
        .has_radial = slant > 0,
        .radial_mps = radial_mps,
        .los = {slant > 0 ? de / slant : 0, slant > 0 ? dn / slant : 0},
    };
}

/* ---- gating ------------------------------------------------------------------------ */

/* The span over which a false alarm's radial velocity is spread. */
static double s_radial_span (const trk_tracker_t *self)
{
    return self->p.radial_span_mps > 0 ? self->p.radial_span_mps : 2 * self->p.max_speed_mps;
}

/* A hit as the IMM's measurement: its position, and its radial velocity
 * when the radar measured it and radial says to use it. */
static void s_meas (const trk_tracker_t *self, const s_hit_t *h, bool radial, trk_meas_t *m)
{
    memset (m, 0, sizeof *m);
    m->z[0] = h->h.z[0];
    m->z[1] = h->h.z[1];
    memcpy (m->R, h->R, sizeof m->R);
    m->has_radial = radial && h->h.has_radial;
    m->radial_mps = h->h.radial_mps;
    m->los[0] = h->h.los[0];
    m->los[1] = h->h.los[1];
    m->radial_var = self->p.radial_sigma_mps * self->p.radial_sigma_mps;
    m->span_mps = self->p.radial_span_mps;
}

/* The manoeuvre allowance of a gate dt after the track's estimate: the
 * variance, per axis, of a displacement a_m dt² / 2. */
static double s_maneuver_var (const trk_tracker_t *self, double dt)
{
    if (self->p.filter.mode == TRK_FILTER_IMM)
        return 0; // the manoeuvre model's own covariance sizes the gate
    double m = self->p.maneuver_accel_mps2 * dt * dt / 2;
    return m * m;
}

static void s_model_pd (const trk_tracker_t *self, const trk_pd_radar_t *r, const trk_imm_t *s,
                        double up_m, double pd[TRK_IMM_MODELS]);

/* Whether t could be the source of h. The hit must come after the track's
 * estimate, and must not imply a speed above the fastest target's since
 * then (with three standard deviations of both positions to spare). For a
 * track of one hit this is its whole gate; for a coasting one it bounds the
 * manoeuvre allowance, which grows as dt² and would otherwise take in
 * clutter kilometres away. */
static bool s_reachable (const trk_tracker_t *self, const trk_track_t *t, const s_hit_t *h)
{
    double dt = h->h.t_s - t->est.t_s;
    if (!(dt > 0))
        return false; // not after the track's estimate: it cannot be its next hit
    double de = h->h.z[0] - t->est.x[0], dn = h->h.z[1] - t->est.x[1];
    double slack = 3 * sqrt (t->est.P[0] + t->est.P[5] + h->R[0] + h->R[3]);
    return hypot (de, dn) <= self->p.max_speed_mps * dt + slack;
}

/* The IMM cost of hit h for track t (one branch of it): false when the hit
 * lies in none of its likely models' gates. */
static bool s_imm_cost (const trk_tracker_t *self, const trk_track_t *t, const s_hit_t *h,
                        s_imm_cost_t *ret)
{
    if (!s_reachable (self, t, h))
        return false;
    const trk_params_t *p = &self->p;
    trk_meas_t m;
    s_meas (self, h, p->radial_velocity, &m);
    const double *ra = self->radar.position;
    double pd0 = trk_pd_at_range (
        &p->detection, hypot (hypot (h->h.z[0] - ra[0], h->h.z[1] - ra[1]), h->h.up_m - ra[2]));
    double gate = m.has_radial ? self->gate3 : self->gate;
    double d2, ld, cost, miss, r = fmin (fmax (t->existence, 1e-6), 0.999);
    bool close = false;
    trk_estimate_t pr;
    double ln_lambda = self->clutter_ln + (m.has_radial ? -log (s_radial_span (self)) : 0);
    double k_ln_2pi = (m.has_radial ? 3 : 2) * log (2 * S_PI);
    if (!s_imm (self, t)) { // one hit: no models yet
        trk_tracker_predict (self, t, h->h.t_s, &pr);
        d2 = trk_meas_distance (&pr, &m, &ld);
        if (d2 < 0 || d2 > gate)
            return false;
        cost = d2 + ld + k_ln_2pi - 2 * log (r * pd0) + 2 * ln_lambda;
        miss = -2 * log (1 - r * pd0);
    } else {
        trk_imm_t mp;
        s_imm_predict (self, t, h->h.t_s, &mp);
        trk_imm_combine (&mp, &pr);
        d2 = trk_meas_distance (&pr, &m, &ld);
        if (d2 < 0)
            return false;
        double pd[TRK_IMM_MODELS], pd_all = 0, best = INFINITY, lj[TRK_IMM_MODELS];
        double d2v[TRK_IMM_MODELS];
        bool inside = false;
        int likeliest = 0;
        s_model_pd (self, &self->radar, &mp, t->up_m, pd);
        for (int j = 0; j < TRK_IMM_MODELS; j++) {
            double ldj, d2j = d2v[j] = trk_meas_distance (&mp.m[j], &m, &ldj);
            lj[j] = d2j < 0 ? INFINITY : d2j + ldj;
            best = fmin (best, lj[j]);
            pd_all += mp.mu[j] * pd[j];
            inside = inside || (d2j >= 0 && d2j <= gate && mp.mu[j] >= S_MODEL_MIN_MU);
            if (mp.mu[j] > mp.mu[likeliest])
                likeliest = j;
        }
        if (!inside)
            return false;
        // Close to where the likeliest model puts the target: a hit the
        // track leaves is a second look at it or clutter about it, not a
        // new target (a neighbour in a column lies further out).
        close =
            d2v[likeliest] >= 0 && d2v[likeliest] <= (m.has_radial ? S_CLOSE_GATE3 : S_CLOSE_GATE2);
        double sum = 0;
        for (int j = 0; j < TRK_IMM_MODELS; j++)
            if (isfinite (lj[j]))
                sum += mp.mu[j] * pd[j] * exp (-0.5 * (lj[j] - best));
        cost = best + k_ln_2pi - 2 * log (fmax (r * sum, 1e-300)) + 2 * ln_lambda;
        miss = -2 * log (1 - r * pd_all);
    }
    *ret = (s_imm_cost_t){.cost = cost, .miss = miss, .log_det = ld, .gate = gate, .close = close};
    return true;
}

/* ln of the chance that branch t of a track has no hit at time t_s:
 * 1 − r·Pd (−miss/2 of its cost). */
static double s_imm_miss_ln (const trk_tracker_t *self, const trk_track_t *t, double t_s)
{
    double r = fmin (fmax (t->existence, 1e-6), 0.999), pd_all = 0;
    if (!s_imm (self, t)) {
        const double *ra = self->radar.position;
        return log (1 - r * trk_pd_at_range (&self->p.detection, hypot (hypot (t->est.x[0] - ra[0],
                                                                               t->est.x[1] - ra[1]),
                                                                        t->up_m - ra[2])));
    }
    trk_imm_t mp;
    s_imm_predict (self, t, fmax (t_s, t->est.t_s), &mp);
    double pd[TRK_IMM_MODELS];
    s_model_pd (self, &self->radar, &mp, t->up_m, pd);
    for (int j = 0; j < TRK_IMM_MODELS; j++)
        pd_all += mp.mu[j] * pd[j];
    return log (1 - r * pd_all);
}

/* ln(e^a + e^b), either may be -INFINITY. */
static double s_log_add (double a, double b)
{
    double m = fmax (a, b);
    return m == -INFINITY ? -INFINITY : m + log (exp (a - m) + exp (b - m));
}

/* The IMM tracker's pair. The hit must lie in the gate of one of the
 * models the target may be in (not of their moment-matched mixture, which is
 * no Gaussian: a stopped model here, a moving one far on, and the gate of
 * the mixture would take in what lies between); position and radial
 * velocity are gated together, with their covariance, and nothing is added
 * for manoeuvres: the manoeuvre model is there for them. The costs are
 * likelihood ratios against the radar's false alarm density λ (Bar-Shalom's
 * assignment costs, with the track's existence probability r as in JIPDA):
 * −2 ln(r Σ_j c_j pd_j N(ν_j; S_j) / λ) for the pair, −2 ln(1 − r Pd) for
 * leaving the track without a hit, Pd = Σ_j c_j pd_j its detection
 * probability; so a model the radar could not have seen (stopped, in the
 * notch) takes no hit it could not have made, and a track the radar could
 * hardly see is better left without a hit than given a stranger's. A track
 * with two branches (s_alt_t) weighs both: the pair's likelihood ratio and
 * the miss's chance are their mixtures by the branches' probabilities. */
static void s_try_pair_imm (trk_tracker_t *self, size_t ti, size_t hi)
{
    const trk_track_t *t = &self->tracks[self->act[ti]];
    s_hit_t *h = &self->hits[hi];
    s_imm_cost_t c, ca;
    bool in = s_imm_cost (self, t, h, &c);
    const s_alt_t *a = self->alt_of[ti] == SIZE_MAX ? NULL : &self->alts[self->alt_of[ti]];
    if (a) {
        bool in_alt = s_imm_cost (self, &a->t, h, &ca);
        if (!in && !in_alt)
            return;
        // P(alt) = 1/(1 + e^-odds): the ln of each branch's weight.
        double lwa = -log1p (exp (-a->ln_odds)), lwp = -log1p (exp (a->ln_odds));
        double lp = in ? -c.cost / 2 : -INFINITY, la = in_alt ? -ca.cost / 2 : -INFINITY;
        double cost = -2 * s_log_add (lwp + lp, lwa + la);
        double miss = -2 * s_log_add (lwp + s_imm_miss_ln (self, t, h->h.t_s),
                                      lwa + s_imm_miss_ln (self, &a->t, h->h.t_s));
        if (!in)
            c = ca;
        c.cost = cost;
        c.miss = miss;
        c.close = c.close || (in_alt && ca.close);
    } else if (!in) {
        return;
    }
    s_pair_t *pp = &self->pairs[self->pair_count++];
    pp->track = ti;
    pp->hit = hi;
    pp->gate = c.gate;
    pp->plain = true;
    pp->cost_plain = pp->cost_wide = c.cost;
    pp->log_det_plain = pp->log_det_wide = c.log_det;
    pp->miss = c.miss;
    if (t->status != TRK_TENTATIVE && c.close)
        h->in_confirmed = true;
}

/* Try a track-hit pair; adds it when the hit is inside the gate: within G
 * of the prediction with the manoeuvre allowance added to S. The pair keeps
 * two costs: without the allowance (first pass, when it is inside the
 * filter's own gate too) and with it (second pass). */
static void s_try_pair (trk_tracker_t *self, size_t ti, size_t hi)
{
    const trk_track_t *t = &self->tracks[self->act[ti]];
    s_hit_t *h = &self->hits[hi];
    if (self->p.filter.mode == TRK_FILTER_IMM) {
        s_try_pair_imm (self, ti, hi); // each branch checks s_reachable
        return;
    }
    if (!s_reachable (self, t, h))
        return;
    double dt = h->h.t_s - t->est.t_s;
    trk_estimate_t pr;
    trk_filter_predict (&t->est, &self->p.filter, h->h.t_s, &pr);
    // Only a confirmed target is followed through a manoeuvre: tentative
    // tracks keep the filter's own gate, so clutter cannot lead them astray.
    double m2 = t->status == TRK_TENTATIVE ? 0 : s_maneuver_var (self, dt);
    double Rg[4] = {h->R[0] + m2, h->R[1], h->R[2], h->R[3] + m2};
    double ld_gate, d2_gate = trk_filter_distance (&pr, h->h.z, Rg, &ld_gate);
    double log_det, d2 = trk_filter_distance (&pr, h->h.z, h->R, &log_det), gate = self->gate;
    if (d2_gate < 0 || d2 < 0 || d2_gate > self->gate3)
        return;
    if (h->h.has_radial && self->p.radial_velocity) {
        // The hit's radial velocity against the track's along the line of sight.
        const double *u = h->h.los, *P = pr.P;
        double pred = u[0] * pr.x[2] + u[1] * pr.x[3], nu = h->h.radial_mps - pred;
        double span = self->p.radial_span_mps;
        if (span > 0)
            nu -= span * round (nu / span);
        double am = t->status == TRK_TENTATIVE ? 0 : self->p.maneuver_accel_mps2 * dt;
        double sr = u[0] * u[0] * P[10] + 2 * u[0] * u[1] * P[11] + u[1] * u[1] * P[15] +
                    self->p.radial_sigma_mps * self->p.radial_sigma_mps;
        d2 += nu * nu / sr;
        d2_gate += nu * nu / (sr + am * am);
        log_det += log (sr);
        ld_gate += log (sr + am * am);
        gate = self->gate3;
    }
    if (d2_gate > gate)
        return;
    s_pair_t *pp = &self->pairs[self->pair_count++];
    pp->track = ti;
    pp->hit = hi;
    pp->gate = gate;
    pp->plain = d2 <= gate;
    pp->cost_plain = d2 + log_det;
    pp->log_det_plain = log_det;
    pp->cost_wide = d2_gate + ld_gate;
    pp->log_det_wide = ld_gate;
    pp->miss = NAN;
    // A hit inside a confirmed track's gate proper (no manoeuvre allowance)
    // is that target's, or clutter about it: it starts no track.
    if (t->status != TRK_TENTATIVE && pp->plain)
        h->in_confirmed = true;
}

/* Where a track's candidates can lie over the scan: the centre (ce, cn)
 * where it is mid-scan and the half side of the square about it; its
 * largest gate at the latest hit time, plus its motion either way. */
static double s_reach (const trk_tracker_t *self, const trk_track_t *t, double t_lo, double t_hi,
                       double r_max, double *ce, double *cn)
{
    double t_end = fmax (t_hi, t->est.t_s), t_mid = fmax ((t_lo + t_hi) / 2, t->est.t_s);
    trk_estimate_t pe;
    trk_tracker_predict (self, t, t_end, &pe);
    double lam = s_lambda_max (pe.P[0], pe.P[1], pe.P[5]) + r_max +
                 (t->status == TRK_TENTATIVE ? 0 : s_maneuver_var (self, t_end - t->est.t_s));
    double speed = hypot (t->est.x[2], t->est.x[3]);
    double reach = sqrt (self->gate3 * lam) + speed * (t_hi - t_lo) / 2 + 1;
    if (s_imm (self, t)) {
        // Each model's own gate, wherever its prediction lies: a hit in
        // any of them is a candidate (s_try_pair_imm).
        trk_imm_t mp;
        s_imm_predict (self, t, t_end, &mp);
        for (int j = 0; j < TRK_IMM_MODELS; j++) {
            if (mp.mu[j] < S_MODEL_MIN_MU)
                continue;
            const double *P = mp.m[j].P;
            double off = hypot (mp.m[j].x[0] - pe.x[0], mp.m[j].x[1] - pe.x[1]);
            double sp = hypot (mp.m[j].x[2], mp.m[j].x[3]);
            reach =
                fmax (reach, off + sqrt (self->gate3 * (s_lambda_max (P[0], P[1], P[5]) + r_max)) +
                                 fmax (speed, sp) * (t_hi - t_lo) / 2 + 1);
        }
    }
    *ce = t->est.x[0] + t->est.x[2] * (t_mid - t->est.t_s);
    *cn = t->est.x[1] + t->est.x[3] * (t_mid - t->est.t_s);
    return reach;
}

static int s_gate (trk_tracker_t *self, size_t nt, size_t nh, double t_lo, double t_hi,
                   double r_max)
{
    for (size_t ti = 0; ti < nt; ti++) {
        const trk_track_t *t = &self->tracks[self->act[ti]];
        double ce, cn, reach = s_reach (self, t, t_lo, t_hi, r_max, &ce, &cn);
        // The box [x0, x1] × [y0, y1] holds every candidate; a track with two
        // branches looks in the box that holds both.
        double bx0 = ce - reach, bx1 = ce + reach, by0 = cn - reach, by1 = cn + reach;
        if (self->alt_of[ti] != SIZE_MAX) {
            double ae, an,
                ar = s_reach (self, &self->alts[self->alt_of[ti]].t, t_lo, t_hi, r_max, &ae, &an);
            bx0 = fmin (bx0, ae - ar);
            bx1 = fmax (bx1, ae + ar);
            by0 = fmin (by0, an - ar);
            by1 = fmax (by1, an + ar);
        }
        // Pairs: at most one per hit for this track.
        if (cgs_grow ((void **)&self->pairs, &self->pair_cap, self->pair_count + nh,
                      sizeof *self->pairs) < 0)
            return -ENOMEM;
        double span_cells = fmax (bx1 - bx0, by1 - by0) / S_CELL_M + 2;
        if (!isfinite (bx0) || !isfinite (bx1) || !isfinite (by0) || !isfinite (by1) ||
            span_cells * span_cells > (double)nh || fmax (fabs (bx0), fabs (bx1)) > 1e12 ||
            fmax (fabs (by0), fabs (by1)) > 1e12) { // a huge gate: every hit is a candidate
            for (size_t hi = 0; hi < nh; hi++)
                s_try_pair (self, ti, hi);
            continue;
        }
        int64_t x0 = s_cell_of (bx0), x1 = s_cell_of (bx1);
        int64_t y0 = s_cell_of (by0), y1 = s_cell_of (by1);
        for (int64_t ix = x0; ix <= x1; ix++)
            for (int64_t iy = y0; iy <= y1; iy++)
                for (size_t hi = s_grid_first (self, ix, iy); hi != SIZE_MAX;
                     hi = self->hit_next[hi]) {
                    const trk_hit_t *h = &self->hits[hi].h;
                    if (h->z[0] >= bx0 && h->z[0] <= bx1 && h->z[1] >= by0 && h->z[1] <= by1)
                        s_try_pair (self, ti, hi);
                }
    }
    return 0;
}

/* ---- association -------------------------------------------------------------------- */

/* Pairs in cluster order, then as found. */
static int s_cmp_pair (const void *a, const void *b)
{
    const s_pair_t *x = a, *y = b;
    if (x->root != y->root)
        return x->root < y->root ? -1 : 1;
    if (x->track != y->track)
        return x->track < y->track ? -1 : 1;
    return x->hit < y->hit ? -1 : x->hit > y->hit;
}

/* The IMM tracker's cluster (matrix c of its k tracks, m hits and k "no
 * hit" columns): its best hypothesis is the assignment; the k best,
 * weighed, give each track the probability that it had no hit. */
static int s_solve_cluster_imm (trk_tracker_t *self, const double *c, size_t k, size_t m)
{
    size_t cols = m + k;
    size_t want = k <= S_KBEST_TRACKS ? (size_t)self->p.hypotheses : 1;
    int n = trk_kbest_solve (self->kbest, c, k, cols, want, S_FORBIDDEN);
    if (n < 0)
        return n;
    if (n == 0)
        return 0; // cannot happen: every track may go without a hit
    if (cgs_grow ((void **)&self->beta, &self->beta_cap, k * cols, sizeof *self->beta) < 0)
        return -ENOMEM;
    trk_kbest_marginals (self->kbest, (size_t)n, k, cols, self->beta);
    for (size_t r = 0; r < k; r++) {
        self->miss_beta[self->ctracks[r]] = self->beta[r * cols + m + r];
        size_t j = trk_kbest_column (self->kbest, 0, r);
        if (j >= m)
            continue; // left without a hit
        self->assigned[self->ctracks[r]] = self->chits[j];
        self->hits[self->chits[j]].track = self->ctracks[r];
    }
    return 0;
}

static int s_cmp_cost (const void *a, const void *b)
{
    const s_pair_t *x = a, *y = b;
    if (x->cost != y->cost)
        return x->cost < y->cost ? -1 : 1;
    if (x->track != y->track)
        return x->track < y->track ? -1 : 1;
    return x->hit < y->hit ? -1 : x->hit > y->hit;
}

/* A cluster of more than TRK_CLUSTER_MAX tracks (targets so crowded that the
 * gates chain thousands of them together): the optimal assignment's dense
 * matrix would take gigabytes and its solve minutes, so the pairs are taken
 * cheapest first, each track and hit once, a pair only when it costs less
 * than leaving its track without a hit. Each track's chance of no hit is
 * that of this one hypothesis (0 or 1). Counted in out->greedy_clusters. */
static void s_solve_greedy (trk_tracker_t *self, size_t lo, size_t hi, size_t tracks,
                            trk_scan_out_t *out)
{
    s_pair_t *w = self->work + lo;
    size_t np = hi - lo;
    qsort (w, np, sizeof *w, s_cmp_cost);
    for (size_t q = 0; q < np; q++)
        self->miss_beta[w[q].track] = 1;
    if (out->largest_cluster < tracks)
        out->largest_cluster = tracks;
    for (size_t q = 0; q < np; q++) {
        const s_pair_t *pp = &w[q];
        if (self->assigned[pp->track] != SIZE_MAX || self->hits[pp->hit].track != SIZE_MAX)
            continue;
        double miss = isfinite (pp->miss) ? pp->miss : pp->gate + 1 + pp->log_det;
        if (!(pp->cost < miss))
            continue;
        self->assigned[pp->track] = pp->hit;
        self->hits[pp->hit].track = pp->track;
        self->miss_beta[pp->track] = 0;
    }
    out->greedy_clusters++;
}

/* Solve one cluster: work[lo..hi). */
static int s_solve_cluster (trk_tracker_t *self, size_t lo, size_t hi, trk_scan_out_t *out)
{
    size_t np = hi - lo;
    bool imm = self->p.filter.mode == TRK_FILTER_IMM;
    size_t tracks = 0; // pairs come sorted by track
    for (size_t q = lo; q < hi; q++)
        tracks += q == lo || self->work[q].track != self->work[q - 1].track;
    if (tracks > TRK_CLUSTER_MAX) {
        s_solve_greedy (self, lo, hi, tracks, out);
        return 0;
    }
    if (np == 1 && !imm) { // one track, one hit
        const s_pair_t *pp = &self->work[lo];
        if (isfinite (pp->miss) && !(pp->cost < pp->miss))
            return 0; // better left without it
        self->assigned[pp->track] = pp->hit;
        self->hits[pp->hit].track = pp->track;
        if (out->largest_cluster < 1)
            out->largest_cluster = 1;
        return 0;
    }
    // The cluster's tracks (pairs come sorted by track) and hits, numbered locally.
    if (cgs_grow ((void **)&self->ctracks, &self->ctracks_cap, np, sizeof (size_t)) < 0 ||
        cgs_grow ((void **)&self->chits, &self->chits_cap, np, sizeof (size_t)) < 0 ||
        cgs_grow ((void **)&self->col, &self->col_cap, np, sizeof (size_t)) < 0)
        return -ENOMEM;
    size_t k = 0, m = 0;
    for (size_t q = lo; q < hi; q++) {
        const s_pair_t *pp = &self->work[q];
        if (k == 0 || self->ctracks[k - 1] != pp->track)
            self->ctracks[k++] = pp->track;
        bool seen = false;
        for (size_t j = 0; j < m && !seen; j++)
            seen = self->chits[j] == pp->hit;
        if (!seen)
            self->chits[m++] = pp->hit;
    }
    if (out->largest_cluster < k)
        out->largest_cluster = k;
    // k rows; columns: the m hits, then one "no hit" column per track.
    size_t cols = m + k, ncost = k * cols;
    if (cgs_grow ((void **)&self->cost, &self->cost_cap, ncost, sizeof *self->cost) < 0)
        return -ENOMEM;
    double *c = self->cost;
    for (size_t i = 0; i < ncost; i++)
        c[i] = S_FORBIDDEN;
    size_t i = 0;
    for (size_t q = lo; q < hi; q++) {
        const s_pair_t *pp = &self->work[q];
        while (self->ctracks[i] != pp->track)
            i++;
        size_t j = 0;
        while (self->chits[j] != pp->hit)
            j++;
        c[i * cols + j] = pp->cost;
        // Leaving the track without a hit costs G + 1 + ln|S| of its
        // worst-conditioned pair: any pair inside the gate is worth more.
        double miss = isfinite (pp->miss) ? pp->miss : pp->gate + 1 + pp->log_det;
        double *slot = &c[i * cols + m + i];
        if (*slot == S_FORBIDDEN || miss > *slot)
            *slot = miss;
    }
    if (imm)
        return s_solve_cluster_imm (self, c, k, m);
    int rc = trk_assign_solve (self->assign, c, k, cols, self->col, NULL);
    if (rc < 0)
        return rc;
    for (size_t r = 0; r < k; r++) {
        size_t j = self->col[r];
        if (j >= m || c[r * cols + j] >= S_FORBIDDEN)
            continue; // left without a hit
        self->assigned[self->ctracks[r]] = self->chits[j];
        self->hits[self->chits[j]].track = self->ctracks[r];
    }
    return 0;
}

/* One pass of the association over the pairs keep() admits, with the cost
 * it chooses: clusters by union-find, each solved optimally. */
static int s_pass (trk_tracker_t *self, size_t nt, size_t nh, bool wide, trk_scan_out_t *out)
{
    self->work_count = 0;
    if (cgs_grow ((void **)&self->work, &self->work_cap, self->pair_count, sizeof *self->work) < 0)
        return -ENOMEM;
    for (size_t q = 0; q < self->pair_count; q++) {
        s_pair_t pp = self->pairs[q];
        if (!wide && !pp.plain)
            continue;
        if (wide && (self->assigned[pp.track] != SIZE_MAX || self->hits[pp.hit].track != SIZE_MAX))
            continue;
        pp.cost = wide ? pp.cost_wide : pp.cost_plain;
        pp.log_det = wide ? pp.log_det_wide : pp.log_det_plain;
        self->work[self->work_count++] = pp;
    }
    if (self->work_count == 0)
        return 0;
    size_t nodes = nt + nh;
    if (cgs_grow ((void **)&self->uf, &self->uf_cap, nodes, sizeof *self->uf) < 0)
        return -ENOMEM;
    for (size_t i = 0; i < nodes; i++)
        self->uf[i] = i;
    for (size_t q = 0; q < self->work_count; q++)
        s_union (self->uf, self->work[q].track, nt + self->work[q].hit);
    for (size_t q = 0; q < self->work_count; q++)
        self->work[q].root = s_find (self->uf, self->work[q].track);
    qsort (self->work, self->work_count, sizeof *self->work, s_cmp_pair);
    for (size_t lo = 0; lo < self->work_count;) {
        size_t hi = lo + 1;
        while (hi < self->work_count && self->work[hi].root == self->work[lo].root)
            hi++;
        int rc = s_solve_cluster (self, lo, hi, out);
        if (rc < 0)
            return rc;
        out->clusters++;
        lo = hi;
    }
    return 0;
}

/* Global nearest neighbour in two passes: first the pairs inside the
 * filter's own gates (the usual case, small clusters); then, among the
 * tracks and hits left over, the pairs only the manoeuvre allowance admits
 * (a target that turned or braked). */
static int s_associate (trk_tracker_t *self, size_t nt, size_t nh, trk_scan_out_t *out)
{
    if (self->p.filter.mode == TRK_FILTER_IMM) {
        // A hit goes only to a track that could share it (a JPDA-style
        // marginal of at least S_SHARE_MIN among the tracks that want it):
        // a second hit of one target in a scan (at the scan's seam, where a
        // target is looked at twice) must not go to a track whose likelihood
        // of it is a small fraction of its own track's.
        for (size_t hi = 0; hi < nh; hi++)
            self->hits[hi].best_cost = INFINITY;
        for (size_t q = 0; q < self->pair_count; q++) {
            s_hit_t *h = &self->hits[self->pairs[q].hit];
            h->best_cost = fmin (h->best_cost, self->pairs[q].cost_plain);
        }
        double margin = -2 * log (S_SHARE_MIN);
        size_t kept = 0;
        for (size_t q = 0; q < self->pair_count; q++)
            if (self->pairs[q].cost_plain <= self->hits[self->pairs[q].hit].best_cost + margin)
                self->pairs[kept++] = self->pairs[q];
        self->pair_count = kept;
    }
    int rc = s_pass (self, nt, nh, false, out);
    if (rc < 0 || self->p.filter.mode == TRK_FILTER_IMM)
        return rc; // IMM: one pass (its pairs carry no allowance)
    return s_pass (self, nt, nh, true, out);
}

/* ---- track upkeep ----------------------------------------------------------------- */

/* Clockwise angle from unit vector a to unit vector b, degrees in (−180, 180]. */
static double s_signed_angle_deg (const double a[2], const double b[2])
{
    double dot = a[0] * b[0] + a[1] * b[1];
    double cross = a[0] * b[1] - a[1] * b[0]; // positive when b is anticlockwise of a
    double deg = -atan2 (cross, dot) * 180 / S_PI;
    return deg <= -180 ? 180 : deg;
}

static void s_unit (const double v[2], double u[2])
{
    double s = hypot (v[0], v[1]);
    u[0] = v[0] / s;
    u[1] = v[1] / s;
}

/* Equation 8 after an update of a confirmed track. */
static void s_turn (trk_tracker_t *self, trk_track_t *t, uint32_t scan)
{
    double v[2] = {t->est.x[2], t->est.x[3]};
    if (t->updates < (uint32_t)self->p.turn_settle_updates ||
        hypot (v[0], v[1]) < self->p.turn_min_speed_mps || hypot (v[0], v[1]) == 0)
        return;
    if (!t->have_uv) {
        t->have_uv = true;
        t->v_last[0] = v[0];
        t->v_last[1] = v[1];
        return;
    }
    double u[2], up[2];
    s_unit (v, u);
    s_unit (t->v_last, up);
    double dot = u[0] * up[0] + u[1] * up[1];
    trk_turn_t *ev = NULL;
    if (!t->turning && dot < self->tau) {
        t->turning = true;
        t->uv_before[0] = up[0];
        t->uv_before[1] = up[1];
        t->v_before[0] = t->v_last[0];
        t->v_before[1] = t->v_last[1];
        t->turn_scan = scan;
        ev = &self->turns[self->turn_count++];
        ev->complete = false;
    } else if (t->turning && dot >= self->tau) {
        t->turning = false;
        ev = &self->turns[self->turn_count++];
        ev->complete = true;
    }
    if (ev) {
        ev->track_id = t->id;
        ev->scan_number = scan;
        ev->t_s = t->est.t_s;
        ev->dot = dot;
        ev->angle_deg = s_signed_angle_deg (t->uv_before, u);
        ev->position[0] = t->est.x[0];
        ev->position[1] = t->est.x[1];
        ev->v_before[0] = t->v_before[0];
        ev->v_before[1] = t->v_before[1];
        ev->v_after[0] = v[0];
        ev->v_after[1] = v[1];
    }
    t->v_last[0] = v[0];
    t->v_last[1] = v[1];
}

static void s_history_add (const trk_tracker_t *self, trk_track_t *t, const trk_hit_t *h,
                           uint32_t scan)
{
    uint32_t max = (uint32_t)self->p.history_scans;
    if (t->history_count >= max) { // room for one more (a checkpoint may hold more)
        uint32_t drop = t->history_count - max + 1;
        memmove (t->history, t->history + drop, (t->history_count - drop) * sizeof t->history[0]);
        t->history_count -= drop;
    }
    t->history[t->history_count++] = (trk_history_point_t){.e_m = h->z[0],
                                                           .n_m = h->z[1],
                                                           .u_m = h->up_m,
                                                           .t_s = h->t_s,
                                                           .scan_number = scan,
                                                           .hit_id = h->hit_id};
}

static void s_history_trim (const trk_tracker_t *self, trk_track_t *t, uint32_t scan)
{
    uint32_t drop = 0;
    while (drop < t->history_count &&
           scan - t->history[drop].scan_number >= (uint32_t)self->p.history_scans)
        drop++;
    if (drop) {
        memmove (t->history, t->history + drop, (t->history_count - drop) * sizeof t->history[0]);
        t->history_count -= drop;
    }
}

static int s_popcount (uint32_t v)
{
    int n = 0;
    for (; v; v &= v - 1)
        n++;
    return n;
}

/* The radar during a scan, as trk_pd sees it. */
static trk_pd_radar_t s_radar (const trk_scan_t *scan, const cgs_terrain_t *terrain)
{
    return (trk_pd_radar_t){
        .terrain = terrain,
        .position = {scan->platform[0], scan->platform[1], scan->platform_up_m},
        .velocity = {scan->platform_velocity[0], scan->platform_velocity[1]},
        .full_revolution = scan->full_revolution,
        .sector_center_deg = scan->sector_center_deg,
        .sector_width_deg = scan->sector_width_deg,
    };
}

/* Whether a sector scan covered a position. */
static bool s_covered (const trk_scan_t *scan, double e, double n)
{
    trk_pd_radar_t r = s_radar (scan, NULL);
    return trk_pd_covered (&r, e, n);
}

/* A scan's hit h (or none) counted on t: hits, misses, history, the M-of-N
 * window. Returns the hits in the window's last confirm_n scans. */
static int s_count (trk_tracker_t *self, trk_track_t *t, const s_hit_t *h, const trk_scan_t *scan,
                    trk_scan_out_t *out)
{
    const trk_params_t *p = &self->p;
    if (h) {
        t->hits++;
        t->misses = 0;
        t->last_hit_s = h->h.t_s;
        t->last_scan = scan->scan_number;
        t->up_m = h->h.up_m;
        s_history_add (self, t, &h->h, scan->scan_number);
        out->updated++;
    } else {
        t->misses++;
    }
    t->window = (t->window << 1) | (h ? 1u : 0u);
    uint32_t nmask = p->confirm_n >= 32 ? UINT32_MAX : (1u << p->confirm_n) - 1;
    return s_popcount (t->window & nmask);
}

/* ---- the IMM tracker's upkeep ------------------------------------------------------ */

/* The detection probability the radar had of each model's state. */
static void s_model_pd (const trk_tracker_t *self, const trk_pd_radar_t *r, const trk_imm_t *s,
                        double up_m, double pd[TRK_IMM_MODELS])
{
    for (int j = 0; j < TRK_IMM_MODELS; j++) {
        const trk_estimate_t *e = &s->m[j];
        double x[3] = {e->x[0], e->x[1], up_m}, v[2] = {e->x[2], e->x[3]};
        double de = e->x[0] - r->position[0], dn = e->x[1] - r->position[1], g = hypot (de, dn);
        double ue = g > 0 ? de / g : 0, un = g > 0 ? dn / g : 0;
        double var = ue * ue * e->P[10] + 2 * ue * un * e->P[11] + un * un * e->P[15];
        pd[j] = trk_pd_of (&self->p.detection, r, x, v, sqrt (fmax (0.0, var)));
    }
}

/* Largest position standard deviation of an estimate. */
static double s_sigma_max (const trk_estimate_t *e)
{
    return sqrt (s_lambda_max (e->P[0], e->P[1], e->P[5]));
}

/* One scan's outcome for a track of the IMM tracker: hit h (or NULL), the
 * best hypothesis's; miss_beta, the probability over the weighed hypotheses
 * that it had none. Returns false when the track is to be deleted. */
static bool s_upkeep_imm (trk_tracker_t *self, trk_track_t *t, const s_hit_t *h, double miss_beta,
                          const trk_scan_t *scan, trk_scan_out_t *out)
{
    const trk_params_t *p = &self->p;
    trk_pd_radar_t radar = s_radar (scan, self->terrain);
    double mid = (scan->start_s + scan->end_s) / 2;
    if (!h) {
        trk_estimate_t pe;
        trk_tracker_predict (self, t, fmax (mid, t->est.t_s), &pe);
        if (!trk_pd_covered (&radar, pe.x[0], pe.x[1]))
            return true; // not looked at: neither hit nor miss
    }
    t->scans++;
    uint32_t misses_before = t->misses;
    if (t->hits == 1) {
        // One hit: no velocity yet, nothing for the models. A second hit
        // starts them by two-point differencing (a target the radar saw
        // twice moves: never the stopped model).
        if (h) {
            double z1[2] = {t->est.x[0], t->est.x[1]};
            double R1[4] = {t->est.P[0], t->est.P[1], t->est.P[4], t->est.P[5]};
            trk_filter_init_two (&t->est, z1, R1, t->est.t_s, h->h.z, h->R, h->h.t_s);
            const double mu0[TRK_IMM_MODELS] = {0.7, 0.3, 0};
            trk_imm_init (&t->imm, &t->est, mu0);
        } else {
            out->missed++;
        }
    } else {
        double t_at = h ? h->h.t_s : fmax (mid, t->est.t_s);
        trk_imm_t pr;
        s_imm_predict (self, t, t_at, &pr);
        double pd[TRK_IMM_MODELS], pd_all = 0, rate = 0;
        s_model_pd (self, &radar, &pr, t->up_m, pd);
        for (int j = 0; j < TRK_IMM_MODELS; j++) {
            pd_all += pr.mu[j] * pd[j];
            rate += pr.mu[j] / (j == TRK_MODEL_STOPPED ? p->stopped_lifetime_s : p->lifetime_s);
        }
        t->pd = pd_all;
        // Existence: the target may have left the scene since (at a rate
        // that depends on what it was doing), then what the scan showed.
        double e = t->existence * exp (-rate * fmax (0.0, t_at - t->est.t_s));
        if (h) {
            trk_meas_t m;
            s_meas (self, h, p->radial_velocity && p->radial_update, &m);
            if (trk_imm_update (&pr, &m, pd, NULL) < 0) {
                h = NULL; // a covariance gone bad: a miss, not a hit
                miss_beta = 1;
            } else {
                // No ground vehicle is faster than max_speed_mps: a model's
                // velocity beyond it is projected back onto that bound (the
                // estimate projection of a constrained Kalman filter).
                for (int j = 0; j < TRK_IMM_MODELS; j++) {
                    double *x = pr.m[j].x, v = hypot (x[2], x[3]);
                    if (v > p->max_speed_mps) {
                        x[2] *= p->max_speed_mps / v;
                        x[3] *= p->max_speed_mps / v;
                    }
                }
                t->imm = pr;
                trk_imm_combine (&t->imm, &t->est);
                t->updates++;
            }
        }
        if (!h) {
            trk_imm_miss (&pr, pd);
            t->imm = pr;
            trk_imm_combine (&t->imm, &t->est);
            out->missed++;
        }
        // Existence (JIPDA): certain in the hypotheses that give the track a
        // hit; in those that give it none, what a miss leaves of it.
        double beta0 = fmin (fmax (miss_beta, 0.0), 1.0);
        e = (1 - beta0) + beta0 * e * (1 - pd_all) / (1 - e * pd_all);
        t->existence = fmin (0.999, e);
    }
    int got = s_count (self, t, h, scan, out);
    if (t->status == TRK_TENTATIVE) {
        if (got >= p->confirm_m) {
            t->status = TRK_CONFIRMED;
            t->existence = fmax (t->existence, 0.9);
            out->confirmed++;
            self->fresh[self->fresh_count++] = t->id; // s_continue_new after the upkeep
        } else {
            uint32_t n = (uint32_t)p->confirm_n, seen = t->scans < n ? t->scans : n;
            if (got + (int)(n - seen) < p->confirm_m)
                return false; // can no longer be confirmed in its first N scans
        }
    } else if (h) {
        // A hit after a coast of two scans or more moves a velocity the
        // models only predicted: it is confirmed again by the next hit.
        if (misses_before >= 2) {
            t->status = TRK_COASTING;
            t->reconfirm = true;
        } else {
            t->status = TRK_CONFIRMED;
            t->reconfirm = false;
        }
    } else if (t->existence < p->delete_existence || s_sigma_max (&t->est) > p->max_sigma_m) {
        return false; // probably gone, or no longer anywhere in particular
    } else {
        t->status = TRK_COASTING;
        t->reconfirm = false;
    }
    if (h && t->status == TRK_CONFIRMED)
        s_turn (self, t, scan->scan_number);
    return true;
}

/* ---- continuation --------------------------------------------------------------------- */

/* ln of the density of young's estimate under e: position and velocity,
 * each with the sum of the two covariances (the cross-covariance between
 * position and velocity left out); -INFINITY far outside any gate. */
static double s_state_ll (const trk_tracker_t *self, const trk_estimate_t *e,
                          const trk_estimate_t *young)
{
    double ll = 0;
    for (int b = 0; b < 4; b += 2) { // position, then velocity
        double S0 = e->P[b * 5] + young->P[b * 5];
        double S1 = e->P[b * 4 + b + 1] + young->P[b * 4 + b + 1];
        double S3 = e->P[(b + 1) * 5] + young->P[(b + 1) * 5];
        double det = S0 * S3 - S1 * S1;
        if (!(S0 > 0) || !(det > 0) || !isfinite (det))
            return -INFINITY;
        double d0 = young->x[b] - e->x[b], d1 = young->x[b + 1] - e->x[b + 1];
        double d2 = (S3 * d0 * d0 - 2 * S1 * d0 * d1 + S0 * d1 * d1) / det;
        if (d2 > self->gate3 + 10)
            return -INFINITY;
        ll += -0.5 * d2 - 0.5 * log (det) - log (2 * S_PI);
    }
    return ll;
}

/* ln of the likelihood that young, at its estimate's time, is the target of
 * old: old's models predicted there, each weighed by its probability, times
 * the chance that old's vehicle is still in the scene. -INFINITY when the
 * two cannot be one target. */
static double s_same_target (const trk_tracker_t *self, const trk_track_t *old,
                             const trk_track_t *young)
{
    if (old->uav_id != young->uav_id || young->est.t_s <= old->last_hit_s ||
        (old->friendly && young->friendly && old->friendly_id != young->friendly_id))
        return -INFINITY;
    double ll[TRK_IMM_MODELS], best = -INFINITY;
    trk_imm_t pr;
    if (s_imm (self, old)) {
        // Over the gap the moving models spread no further than a ground
        // vehicle can (trk_imm_predict_model's bound at max_speed_mps).
        trk_imm_params_t ip = self->p.imm;
        ip.max_speed_mps = self->p.max_speed_mps;
        trk_imm_t mixed;
        trk_imm_mix (&ip, &old->imm, young->est.t_s - old->est.t_s, &mixed);
        trk_imm_predict (&ip, &mixed, young->est.t_s, &pr);
    } else {
        const double mu0[TRK_IMM_MODELS] = {1, 0, 0};
        trk_imm_init (&pr, &old->est, mu0);
        trk_filter_predict (&old->est, &self->p.filter, young->est.t_s, &pr.m[0]);
    }
    for (int j = 0; j < TRK_IMM_MODELS; j++) {
        ll[j] = pr.mu[j] > 0 ? s_state_ll (self, &pr.m[j], &young->est) : -INFINITY;
        best = fmax (best, ll[j]);
    }
    if (!isfinite (best))
        return -INFINITY;
    double sum = 0;
    for (int j = 0; j < TRK_IMM_MODELS; j++)
        if (isfinite (ll[j]))
            sum += pr.mu[j] * exp (ll[j] - best);
    // Times the prior that old's vehicle is still in the scene (its
    // existence probability, low at its deletion, says rather that the
    // radar lost it).
    return best + log (sum) - fmax (0.0, young->est.t_s - old->est.t_s) / self->p.lifetime_s;
}

/* ln of the density of a new target's position and velocity: birth_density
 * per m², velocities uniform in the disc of max_speed_mps. */
static double s_birth_ll (const trk_tracker_t *self)
{
    double v = self->p.max_speed_mps;
    return log (self->p.birth_density) - log (S_PI * v * v);
}

/* Forget the tracks deleted too long before t_s to be continued (a deleted
 * track's estimate is of the scan that deleted it). */
static void s_lost_expire (trk_tracker_t *self, double t_s)
{
    for (size_t i = 0; i < self->lost_count;) {
        if (!(t_s - self->lost[i].est.t_s <= self->p.continue_window_s))
            self->lost[i] = self->lost[--self->lost_count];
        else
            i++;
    }
}

static void s_kill (trk_tracker_t *self, size_t i, trk_scan_out_t *out);

/* Could live track o have lost young's target since young's first hit?
 * One of young's radar, confirmed once, coasting since before young's first
 * hit (young's history whole, so its first hit is known), near enough for
 * a ground vehicle to have driven there. */
static bool s_reacquire_candidate (const trk_tracker_t *self, const trk_track_t *o,
                                   const trk_track_t *young)
{
    if (o == young || o->uav_id != young->uav_id || o->status != TRK_COASTING || o->misses < 1 ||
        young->history_count == 0 || young->history_count < young->hits ||
        !(young->history[0].t_s > o->last_hit_s))
        return false;
    double reach = self->p.max_speed_mps * fmax (0.0, young->est.t_s - o->last_hit_s) +
                   5 * s_sigma_max (&o->est) + 5 * s_sigma_max (&young->est);
    return hypot (young->est.x[0] - o->est.x[0], young->est.x[1] - o->est.x[1]) <= reach;
}

/* A track just confirmed (tracks[yi]): whose target it probably is. Either
 * a confirmed track deleted lately (the lost list), or one of its radar's
 * tracks still coasting since before its first hit: a target that left its
 * track's gate (a turn sharper than the manoeuvre model expected, a false
 * velocity) and that the radar has seen since as a new track, while the
 * old one coasts on believing it halted. Each candidate's likelihood is
 * s_same_target's, a coasting one's times 1 − r (r its existence: the
 * chance that its target is where it coasts, and so not young's), against
 * a new target's birth density. A coasting track chosen is deleted, and
 * the new one continues it: its target's identity goes on under one link,
 * where guidanced follows it. */
static void s_continue_new (trk_tracker_t *self, size_t yi, trk_scan_out_t *out)
{
    trk_track_t *t = &self->tracks[yi];
    s_lost_expire (self, t->est.t_s);
    double birth = s_birth_ll (self), best = -INFINITY, sum = birth;
    size_t bi = SIZE_MAX;
    bool live = false;
    for (size_t i = 0; i < self->lost_count; i++) {
        double ll = s_same_target (self, &self->lost[i], t);
        sum = s_log_add (sum, ll);
        if (ll > best) {
            best = ll;
            bi = i;
        }
    }
    for (size_t i = 0; i < self->count; i++) {
        const trk_track_t *o = &self->tracks[i];
        if (!s_reacquire_candidate (self, o, t))
            continue;
        double ll = s_same_target (self, o, t) + log1p (-fmin (o->existence, 0.999));
        sum = s_log_add (sum, ll);
        if (ll > best) {
            best = ll;
            bi = i;
            live = true;
        }
    }
    if (bi == SIZE_MAX || !isfinite (best))
        return;
    double pb = exp (best - sum);
    if (pb < self->p.continue_probability)
        return;
    const trk_track_t *old = live ? &self->tracks[bi] : &self->lost[bi];
    t->continues = old->id;
    t->continues_p = pb;
    // BCIS said who it was: the identity passes on only with a link as
    // likely as a reply needs to mark a track.
    if (t->friendly == false && old->friendly && pb >= self->p.identity_min_probability) {
        t->friendly = true;
        t->friendly_id = old->friendly_id;
        t->friendly_s = old->friendly_s;
    }
    out->continued++;
    if (live) {
        s_kill (self, bi, out); // t may have moved: not used after this
        out->reacquired++;
    } else {
        self->lost[bi] = self->lost[--self->lost_count]; // one successor each
    }
}

/* A confirmed track just deleted: a confirmed track born after its last
 * hit that is probably its target continues it; else it waits in the lost
 * list for one. */
static void s_continue_old (trk_tracker_t *self, const trk_track_t *old, trk_scan_out_t *out)
{
    double birth = s_birth_ll (self), best = -INFINITY, sum = 0;
    trk_track_t *bt = NULL;
    for (size_t i = 0; i < self->count; i++) {
        trk_track_t *y = &self->tracks[i];
        if (y->status == TRK_TENTATIVE || y->continues != 0 || y->history_count == 0 ||
            y->history_count < y->hits || !(y->history[0].t_s > old->last_hit_s))
            continue; // only a whole history shows when it began
        double ll = s_same_target (self, old, y);
        if (!isfinite (ll))
            continue;
        if (ll > best) {
            best = ll;
            bt = y;
        }
        sum += exp (ll - birth);
    }
    if (bt) {
        double pb = exp (best - birth) / (sum + 1);
        if (pb >= self->p.continue_probability) {
            bt->continues = old->id;
            bt->continues_p = pb;
            out->continued++;
            return;
        }
    }
    if (cgs_grow ((void **)&self->lost, &self->lost_cap, self->lost_count + 1,
                  sizeof *self->lost) == 0)
        self->lost[self->lost_count++] = *old;
}

/* One scan's outcome for a track: hit h (or NULL); miss_beta, the
 * probability that it had no hit (IMM). Returns false when the track is to
 * be deleted. */
static bool s_upkeep (trk_tracker_t *self, trk_track_t *t, const s_hit_t *h, double miss_beta,
                      const trk_scan_t *scan, trk_scan_out_t *out)
{
    const trk_params_t *p = &self->p;
    if (p->filter.mode == TRK_FILTER_IMM)
        return s_upkeep_imm (self, t, h, miss_beta, scan, out);
    if (!h) {
        double mid = (scan->start_s + scan->end_s) / 2;
        double e = t->est.x[0] + t->est.x[2] * (mid - t->est.t_s);
        double n = t->est.x[1] + t->est.x[3] * (mid - t->est.t_s);
        if (!s_covered (scan, e, n))
            return true; // not looked at: neither hit nor miss
        out->missed++;
    }
    t->scans++;
    if (h) {
        if (t->hits == 1) {
            double z1[2] = {t->est.x[0], t->est.x[1]};
            double R1[4] = {t->est.P[0], t->est.P[1], t->est.P[4], t->est.P[5]};
            trk_filter_init_two (&t->est, z1, R1, t->est.t_s, h->h.z, h->R, h->h.t_s);
        } else {
            trk_estimate_t pr;
            trk_filter_predict (&t->est, &p->filter, h->h.t_s, &pr);
            if (trk_filter_update (&pr, &p->filter, s_gains (self, h->h.t_s - t->est.t_s), h->h.z,
                                   h->R) < 0) {
                h = NULL; // a covariance gone bad: a miss, not a hit
            } else {
                t->est = pr;
                t->updates++;
            }
        }
    }
    int got = s_count (self, t, h, scan, out);
    if (t->status == TRK_TENTATIVE) {
        if (got >= p->confirm_m) {
            t->status = TRK_CONFIRMED;
            out->confirmed++;
        } else {
            uint32_t n = (uint32_t)p->confirm_n, seen = t->scans < n ? t->scans : n;
            if (got + (int)(n - seen) < p->confirm_m)
                return false; // can no longer be confirmed in its first N scans
        }
    } else if (h) {
        t->status = TRK_CONFIRMED;
    } else if (t->misses >= (uint32_t)p->delete_misses) {
        return false;
    } else {
        t->status = TRK_COASTING;
    }
    if (h && t->status == TRK_CONFIRMED)
        s_turn (self, t, scan->scan_number);
    return true;
}

static int s_cmp_alt_id (const void *a, const void *b)
{
    uint32_t x = ((const s_alt_t *)a)->id, y = ((const s_alt_t *)b)->id;
    return x < y ? -1 : x > y;
}

/* The branch of track id in alts (sorted by id), or SIZE_MAX. */
static size_t s_alt_find (const trk_tracker_t *self, uint32_t id)
{
    size_t lo = 0, hi = self->alt_count;
    while (lo < hi) {
        size_t mid = lo + (hi - lo) / 2;
        if (self->alts[mid].id < id)
            lo = mid + 1;
        else
            hi = mid;
    }
    return lo < self->alt_count && self->alts[lo].id == id ? lo : SIZE_MAX;
}

/* The scanned tracks' branches into alt_of; the branches dropped last scan
 * (id 0) and those of tracks gone are dropped. O((tracks + branches)
 * log branches): a scene of thousands of tracks has few branches at once,
 * and no track is looked for once per branch. */
static void s_alt_index (trk_tracker_t *self, size_t nt)
{
    for (size_t ti = 0; ti < nt; ti++)
        self->alt_of[ti] = SIZE_MAX;
    if (self->alt_count == 0)
        return;
    qsort (self->alts, self->alt_count, sizeof *self->alts, s_cmp_alt_id);
    for (size_t a = 0; a < self->alt_count; a++)
        self->alts[a].live = false;
    for (size_t i = 0; i < self->count; i++) {
        size_t a = self->tracks[i].id ? s_alt_find (self, self->tracks[i].id) : SIZE_MAX;
        if (a != SIZE_MAX)
            self->alts[a].live = true;
    }
    size_t kept = 0;
    for (size_t a = 0; a < self->alt_count; a++) {
        if (!self->alts[a].live)
            continue; // dropped (id 0), or its track is gone
        if (kept != a)
            self->alts[kept] = self->alts[a];
        kept++;
    }
    self->alt_count = kept;
    for (size_t ti = 0; ti < nt; ti++)
        self->alt_of[ti] = s_alt_find (self, self->tracks[self->act[ti]].id);
}

/* The IMM tracker's upkeep of track t (scanned as ti) with its branches.
 *
 * A confirmed track that takes a hit after a coast of two scans or more
 * (a vehicle that halted, crossed the notch or was hidden, and whose hit
 * now moves a velocity the models only predicted) may have taken a false
 * alarm or another vehicle's hit: one far from where it stopped, say,
 * which the manoeuvre model's spread after a long coast lets in. Rather
 * than stake the track on it, the tracker keeps the track both ways: as
 * updated with the hit, and as it would be had the hit not been its
 * target's (a miss), each with its probability. Their odds start at the
 * association's own β₀ (the weighed joint hypotheses' chance that the
 * track had no hit), and each later scan multiplies them by each branch's
 * likelihood of what it brought: the hit's likelihood ratio (s_imm_cost)
 * or, for no hit, 1 − r·Pd. The likelier branch is the track (same id);
 * the other is dropped below S_ALT_MIN or after S_ALT_SCANS scans (N-scan
 * pruning), or when either dies. Returns whether the track lives on. */
static bool s_upkeep_branches (trk_tracker_t *self, size_t ti, trk_track_t *t, const s_hit_t *h,
                               double mb, const trk_scan_t *scan, trk_scan_out_t *out)
{
    s_alt_t *a = self->alt_of[ti] == SIZE_MAX ? NULL : &self->alts[self->alt_of[ti]];
    bool branch = false;
    if (!a && h && t->status != TRK_TENTATIVE && t->hits > 1 && t->misses >= 2 && mb >= S_ALT_MIN &&
        mb <= 1 - S_ALT_MIN) {
        a = &self->alts[self->alt_count++]; // room reserved by s_reserve
        *a = (s_alt_t){
            .id = t->id, .born_scan = scan->scan_number, .ln_odds = log (mb / (1 - mb)), .t = *t};
        self->alt_of[ti] = (size_t)(a - self->alts);
        branch = true;
        out->branched++;
    } else if (a) {
        double lp, la;
        if (h) {
            s_imm_cost_t c;
            lp = s_imm_cost (self, t, h, &c) ? -c.cost / 2 : -INFINITY;
            la = s_imm_cost (self, &a->t, h, &c) ? -c.cost / 2 : -INFINITY;
        } else {
            double mid = (scan->start_s + scan->end_s) / 2;
            lp = s_imm_miss_ln (self, t, mid);
            la = s_imm_miss_ln (self, &a->t, mid);
        }
        if (lp > -INFINITY || la > -INFINITY)
            a->ln_odds += la - lp;
    }
    bool alive = s_upkeep (self, t, h, mb, scan, out);
    if (!a)
        return alive;
    // The other branch: had the branching hit not been its target's, this
    // scan was a miss for it; later, the scan's hit (or none) is the same.
    trk_scan_out_t scratch = {0};
    size_t turns = self->turn_count; // its turn events are not the track's
    bool alt_alive = s_upkeep (self, &a->t, branch ? NULL : h, branch ? 1 : mb, scan, &scratch);
    self->turn_count = turns;
    bool keep = alt_alive;
    if (alt_alive && (!alive || a->ln_odds > 0)) {
        trk_track_t other = *t; // the likelier branch becomes the track
        *t = a->t;
        a->t = other;
        a->ln_odds = -a->ln_odds;
        keep = alive;
        alive = true;
        out->alt_swaps++;
    }
    if (!alive || a->ln_odds < log (S_ALT_MIN / (1 - S_ALT_MIN)) ||
        scan->scan_number - a->born_scan >= S_ALT_SCANS)
        keep = false;
    if (!keep) {
        a->id = 0; // dropped by the next s_alt_index
        self->alt_of[ti] = SIZE_MAX;
    }
    return alive;
}

static void s_kill (trk_tracker_t *self, size_t i, trk_scan_out_t *out)
{
    trk_track_t *d = &self->dead[self->dead_count++];
    *d = self->tracks[i];
    d->status = TRK_DELETED;
    self->tracks[i] = self->tracks[--self->count];
    out->deleted++;
}

static void s_new_track (trk_tracker_t *self, const s_hit_t *h, uint32_t uav, uint32_t scan)
{
    trk_track_t *t = &self->tracks[self->count++];
    memset (t, 0, sizeof *t);
    t->id = self->next_id++;
    if (self->next_id == 0)
        self->next_id = 1;
    t->uav_id = uav;
    t->status = TRK_TENTATIVE;
    trk_filter_init_one (&t->est, h->h.z, h->R, h->h.t_s, self->p.max_speed_mps / 2);
    t->up_m = h->h.up_m;
    t->hits = 1;
    t->window = 1;
    t->scans = 1;
    t->last_hit_s = h->h.t_s;
    t->last_scan = scan;
    t->existence = 0.5;
    s_history_add (self, t, &h->h, scan);
}

/* ---- one scan ------------------------------------------------------------------------ */

/* Every buffer a scan of nh hits over the present tracks can need. */
static int s_reserve (trk_tracker_t *self, size_t nh)
{
    size_t nt = self->count;
    size_t grid = 16;
    while (grid < 2 * nh + 2)
        grid *= 2;
    if (grid > self->grid_cap) {
        int64_t *k = realloc (self->cell_keys, grid * sizeof *k);
        if (k)
            self->cell_keys = k;
        size_t *hd = realloc (self->cell_head, grid * sizeof *hd);
        if (hd)
            self->cell_head = hd;
        if (!k || !hd)
            return -ENOMEM;
        self->grid_cap = grid;
    }
    if (cgs_grow ((void **)&self->hits, &self->hit_cap, nh, sizeof *self->hits) < 0 ||
        cgs_grow ((void **)&self->hit_next, &self->hit_next_cap, nh, sizeof *self->hit_next) < 0 ||
        cgs_grow ((void **)&self->act, &self->act_cap, nt + 1, sizeof *self->act) < 0 ||
        cgs_grow ((void **)&self->assigned, &self->assigned_cap, nt + 1, sizeof *self->assigned) <
            0 ||
        cgs_grow ((void **)&self->miss_beta, &self->miss_beta_cap, nt + 1,
                  sizeof *self->miss_beta) < 0 ||
        cgs_grow ((void **)&self->alt_of, &self->alt_of_cap, nt + 1, sizeof *self->alt_of) < 0 ||
        cgs_grow ((void **)&self->alts, &self->alt_cap, self->alt_count + nt + 1,
                  sizeof *self->alts) < 0)
        return -ENOMEM;
    if (cgs_grow ((void **)&self->tracks, &self->cap, nt + nh, sizeof *self->tracks) < 0 ||
        cgs_grow ((void **)&self->turns, &self->turn_cap, nt + 1, sizeof *self->turns) < 0 ||
        cgs_grow ((void **)&self->dead, &self->dead_cap, nt + 1, sizeof *self->dead) < 0 ||
        cgs_grow ((void **)&self->fresh, &self->fresh_cap, nt + 1, sizeof *self->fresh) < 0)
        return -ENOMEM;
    return 0;
}

void trk_tracker_set_terrain (trk_tracker_t *self, const cgs_terrain_t *terrain)
{
    self->terrain = terrain;
}

int trk_tracker_scan (trk_tracker_t *self, const trk_scan_t *scan, const trk_hit_t *hits, size_t n,
                      trk_scan_out_t *ret)
{
    trk_scan_out_t out = {0};
    self->radar = s_radar (scan, self->terrain);
    {
        // The false alarm density: the radar's count over the ground it
        // swept (the range window, the sector).
        const trk_pd_params_t *d = &self->p.detection;
        double frac = scan->full_revolution || !(scan->sector_width_deg < 360)
                          ? 1
                          : fmax (scan->sector_width_deg, 1e-3) / 360;
        double area =
            S_PI * (d->max_range_m * d->max_range_m - d->min_range_m * d->min_range_m) * frac;
        double fa = scan->expected_false_alarms > 0 ? scan->expected_false_alarms
                                                    : self->p.false_alarms_per_scan;
        self->clutter_ln = log (fa / area);
    }
    self->turn_count = 0;
    self->dead_count = 0;
    self->fresh_count = 0;
    self->pair_count = 0;
    int rc = s_reserve (self, n);
    if (rc < 0)
        return rc;
    // 1. The usable hits and their covariance; the span of their times.
    size_t nh = 0;
    double t_lo = INFINITY, t_hi = -INFINITY, r_max = 0;
    for (size_t i = 0; i < n; i++) {
        if (!s_hit_ok (&hits[i]) || hits[i].t_s < scan->start_s - S_TIME_SLACK_S ||
            hits[i].t_s > scan->end_s + S_TIME_SLACK_S)
            continue; // not a hit of this scan
        s_hit_t *h = &self->hits[nh++];
        h->h = hits[i];
        s_hit_covariance (self, &hits[i], h->R);
        h->in_confirmed = false;
        h->track = SIZE_MAX;
        t_lo = fmin (t_lo, hits[i].t_s);
        t_hi = fmax (t_hi, hits[i].t_s);
        r_max = fmax (r_max, s_lambda_max (h->R[0], h->R[1], h->R[3]));
    }
    out.hits = nh;
    if (nh == 0)
        t_lo = t_hi = scan->end_s;
    double scan_end = scan->end_s;
    // 2. Time went back: tracks after the scan cannot continue (they die below).
    // 3. Gating, over the radar's other tracks.
    size_t nt = 0;
    for (size_t i = 0; i < self->count; i++) {
        const trk_track_t *t = &self->tracks[i];
        if (t->uav_id == scan->uav_id && !(t->est.t_s > scan_end + S_TIME_SLACK_S))
            self->act[nt++] = i;
    }
    for (size_t i = 0; i < nt; i++) {
        self->assigned[i] = SIZE_MAX;
        self->miss_beta[i] = 1; // no hit in its gate
    }
    s_alt_index (self, nt);
    s_grid_build (self, nh);
    if ((rc = s_gate (self, nt, nh, t_lo, t_hi, r_max)) < 0)
        goto nomem;
    out.pairs = self->pair_count;
    // 4. Association.
    if ((rc = s_associate (self, nt, nh, &out)) < 0)
        goto nomem;
    // 5, 6. Updates, misses, deaths (nothing fails from here on); then births.
    for (size_t ti = nt; ti-- > 0;) { // backwards: a death moves the last track into its slot
        size_t idx = self->act[ti];
        const s_hit_t *h = self->assigned[ti] == SIZE_MAX ? NULL : &self->hits[self->assigned[ti]];
        bool alive = self->p.filter.mode == TRK_FILTER_IMM
                         ? s_upkeep_branches (self, ti, &self->tracks[idx], h, self->miss_beta[ti],
                                              scan, &out)
                         : s_upkeep (self, &self->tracks[idx], h, self->miss_beta[ti], scan, &out);
        if (!alive) {
            bool was_confirmed = self->tracks[idx].status != TRK_TENTATIVE;
            s_kill (self, idx, &out);
            if (was_confirmed && self->p.filter.mode == TRK_FILTER_IMM)
                s_continue_old (self, &self->dead[self->dead_count - 1], &out);
        }
    }
    // 5b. The tracks just confirmed: whose target each probably is.
    for (size_t f = 0; f < self->fresh_count; f++)
        for (size_t i = 0; i < self->count; i++)
            if (self->tracks[i].id == self->fresh[f]) {
                if (self->tracks[i].continues == 0)
                    s_continue_new (self, i, &out);
                break;
            }
    for (size_t i = 0; i < self->count;) {
        const trk_track_t *t = &self->tracks[i];
        if (t->uav_id == scan->uav_id && t->est.t_s > scan_end + S_TIME_SLACK_S) {
            s_kill (self, i, &out);
            out.time_reset++;
        } else {
            i++;
        }
    }
    for (size_t hi = 0; hi < nh; hi++) {
        const s_hit_t *h = &self->hits[hi];
        if (h->track != SIZE_MAX)
            continue;
        if (h->in_confirmed) {
            out.unused_hits++;
            continue;
        }
        s_new_track (self, h, scan->uav_id, scan->scan_number);
        out.born++;
    }
    for (size_t i = 0; i < self->count; i++)
        if (self->tracks[i].uav_id == scan->uav_id)
            s_history_trim (self, &self->tracks[i], scan->scan_number);
    trk_tracker_age_identity (self, scan_end);
    out.turns = self->turns;
    out.turn_count = self->turn_count;
    out.deleted_tracks = self->dead;
    out.deleted_count = self->dead_count;
    *ret = out;
    return 0;
nomem:
    return rc; // the tracks are as they were
}

/* ---- identity ------------------------------------------------------------------------ */

/* A radar's likeliest track for a BCIS reply, and the sum of its
 * candidates' likelihoods, scaled by exp(cost / 2) of the best. */
typedef struct {
    uint32_t uav_id;
    trk_track_t *best;
    double cost; // d² + ln|S| of the best
    double sum;  // Σ exp(−(cost_i − cost) / 2)
} s_radar_best_t;

int trk_bcis_reply_geometry (double t_s, const double z[2], double range_m, double range_sigma_m,
                             double height_m, double azimuth_deg, double azimuth_sigma_deg,
                             uint32_t responder_id, trk_bcis_reply_t *ret)
{
    double rho2 = range_m * range_m - height_m * height_m;
    if (!isfinite (t_s) || !isfinite (z[0]) || !isfinite (z[1]) || !isfinite (rho2) ||
        !(rho2 > 0) || !(range_sigma_m > 0) || !isfinite (azimuth_deg) ||
        !(azimuth_sigma_deg > 0) || !isfinite (range_sigma_m) || !isfinite (azimuth_sigma_deg))
        return -EINVAL;
    double rho = sqrt (rho2);
    *ret = (trk_bcis_reply_t){.t_s = t_s, .z = {z[0], z[1]}, .responder_id = responder_id};
    trk_filter_polar_covariance (rho, azimuth_deg, range_sigma_m * range_m / rho, azimuth_sigma_deg,
                                 ret->R);
    return 0;
}

size_t trk_tracker_bcis (trk_tracker_t *self, const trk_bcis_reply_t *reply)
{
    double t_s = reply->t_s;
    const double *z = reply->z, *R = reply->R;
    if (!isfinite (t_s) || !isfinite (z[0]) || !isfinite (z[1]))
        return 0;
    // Nothing may reach further than 5 km: no gate of a track this fresh
    // does, and a reply that vague names nobody.
    if (!(R[0] > 0 && R[3] > 0 && R[0] * R[3] - R[1] * R[2] > 0) || R[0] + R[3] > 25e6)
        return 0;
    // A track not updated for longer than this is too vague to take an identity.
    double max_age = (self->p.delete_misses + 1) * self->p.filter.dt_s;
    // The best track of each radar (a target two radars follow has a track of
    // each), in one pass: radars are few, kept in a small table.
    s_radar_best_t radar[S_BCIS_RADARS];
    size_t nr = 0;
    for (size_t i = 0; i < self->count; i++) {
        trk_track_t *c = &self->tracks[i];
        double dt = t_s - c->est.t_s;
        if (c->status == TRK_TENTATIVE || fabs (dt) > max_age)
            continue;
        double e = c->est.x[0] + c->est.x[2] * dt, n = c->est.x[1] + c->est.x[3] * dt;
        double de = z[0] - e, dn = z[1] - n;
        if (de * de + dn * dn > 25e6) // beyond 5 km: no gate reaches
            continue;
        trk_estimate_t pr;
        trk_filter_predict (&c->est, &self->p.filter, t_s, &pr);
        double log_det, d2 = trk_filter_distance (&pr, z, R, &log_det);
        if (d2 < 0 || d2 > self->gate)
            continue;
        size_t k = 0;
        while (k < nr && radar[k].uav_id != c->uav_id)
            k++;
        if (k == nr) {
            if (nr == S_BCIS_RADARS)
                continue; // more radars than the table holds: the rest go without
            radar[nr++] = (s_radar_best_t){c->uav_id, NULL, INFINITY, 0};
        }
        s_radar_best_t *rb = &radar[k];
        double cost = d2 + log_det;
        if (cost < rb->cost) {
            rb->sum = (rb->best ? rb->sum * exp (-(rb->cost - cost) / 2) : 0) + 1;
            rb->cost = cost;
            rb->best = c;
        } else {
            rb->sum += exp (-(cost - rb->cost) / 2);
        }
    }
    size_t marked = 0;
    for (size_t k = 0; k < nr; k++) {
        s_radar_best_t *rb = &radar[k];
        // The best's likelihood N = exp(−cost/2) / 2π (|S| in m²), against
        // the untracked density in the same units (per m²).
        double best = exp (-rb->cost / 2) / (2 * M_PI);
        double untracked = self->p.identity_untracked_per_km2 * 1e-6;
        double p = best / (best * rb->sum + untracked);
        if (p < self->p.identity_min_probability)
            continue;
        trk_track_t *b = rb->best;
        b->friendly = true;
        b->friendly_id = reply->responder_id;
        b->friendly_s = fmax (b->friendly_s, t_s);
        marked++;
    }
    return marked;
}

size_t trk_tracker_age_identity (trk_tracker_t *self, double t_s)
{
    size_t n = 0;
    for (size_t i = 0; i < self->count; i++) {
        trk_track_t *t = &self->tracks[i];
        if (t->friendly && t_s - t->friendly_s > self->p.identity_timeout_s) {
            t->friendly = false;
            t->friendly_id = 0;
            n++;
        }
    }
    return n;
}

/* ---- replacing the tracks (a checkpoint's) ------------------------------------------ */

int trk_tracker_replace (trk_tracker_t *self, const trk_track_t *tracks, size_t count,
                         uint32_t next_id)
{
    if (count > self->cap &&
        cgs_grow ((void **)&self->tracks, &self->cap, count, sizeof *self->tracks) < 0)
        return -ENOMEM;
    if (count)
        memcpy (self->tracks, tracks, count * sizeof *tracks);
    self->count = count;
    self->next_id = next_id;
    self->alt_count = 0; // a checkpoint keeps each track's likelier branch only
    uint32_t max = (uint32_t)self->p.history_scans;
    for (size_t i = 0; i < count; i++) { // keep the newest history_scans points
        trk_track_t *t = &self->tracks[i];
        if (t->history_count > max) {
            uint32_t drop = t->history_count - max;
            memmove (t->history, t->history + drop, max * sizeof t->history[0]);
            t->history_count = max;
        }
    }
    return 0;
}

void trk_tracker_raise_next_id (trk_tracker_t *self, uint32_t id)
{
    if (id > self->next_id)
        self->next_id = id;
}
