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
#include "trk_assign.h"

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

/* A hit of the scan being processed. */
typedef struct {
    trk_hit_t h;
    double R[4];       // measurement covariance
    bool in_confirmed; // inside a confirmed track's gate
    size_t track;      // assigned track (index), or SIZE_MAX
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
} s_pair_t;

struct trk_tracker {
    trk_params_t p;
    trk_gains_t gains[2];
    double gate;  // G, two degrees of freedom (position)
    double gate3; // three (position and radial velocity)
    double tau;   // cos(turn threshold)
    trk_track_t *tracks;
    size_t count, cap;
    uint32_t next_id;
    trk_assign_t *assign;
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
};

static int s_grow (void **p, size_t *cap, size_t need, size_t size)
{
    if (need <= *cap)
        return 0;
    size_t n = *cap ? *cap : 16;
    while (n < need)
        n *= 2;
    void *q = realloc (*p, n * size);
    if (!q)
        return -ENOMEM;
    *p = q;
    *cap = n;
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
    for (int a = 0; a < 2; a++)
        if (trk_gains_paper (p->filter.sigma_meas_m[a], p->filter.sigma_mod_mps2[a], p->filter.dt_s,
                             &self->gains[a]) < 0)
            goto fail;
    self->gate = trk_params_gate (p);
    self->gate3 = trk_params_gate3 (p);
    self->tau = cos (p->turn_threshold_deg * S_PI / 180);
    self->next_id = 1;
    self->assign = trk_assign_new ();
    if (!self->assign)
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
    free (self);
    *self_p = NULL;
}

const trk_params_t *trk_tracker_params (const trk_tracker_t *self)
{
    return &self->p;
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

void trk_tracker_predict (const trk_tracker_t *self, const trk_track_t *t, double t_s,
                          trk_estimate_t *ret)
{
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

/* The manoeuvre allowance of a gate dt after the track's estimate: the
 * variance, per axis, of a displacement a_m dt² / 2. */
static double s_maneuver_var (const trk_tracker_t *self, double dt)
{
    double m = self->p.maneuver_accel_mps2 * dt * dt / 2;
    return m * m;
}

/* Try a track-hit pair; adds it when the hit is inside the gate: within G
 * of the prediction with the manoeuvre allowance added to S. The pair keeps
 * two costs: without the allowance (first pass, when it is inside the
 * filter's own gate too) and with it (second pass). */
static void s_try_pair (trk_tracker_t *self, size_t ti, size_t hi)
{
    const trk_track_t *t = &self->tracks[self->act[ti]];
    s_hit_t *h = &self->hits[hi];
    double dt = h->h.t_s - t->est.t_s;
    if (!(dt > 0))
        return; // not after the track's estimate: it cannot be its next hit
    {
        // The hit must not imply a speed above the fastest target's since the
        // track's estimate (with three standard deviations of both positions
        // to spare). For a track of one hit this is its whole gate; for a
        // coasting one it bounds the manoeuvre allowance, which grows as dt²
        // and would otherwise take in clutter kilometres away.
        double de = h->h.z[0] - t->est.x[0], dn = h->h.z[1] - t->est.x[1];
        double slack = 3 * sqrt (t->est.P[0] + t->est.P[5] + h->R[0] + h->R[3]);
        if (hypot (de, dn) > self->p.max_speed_mps * dt + slack)
            return;
    }
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
    // A hit inside a confirmed track's gate proper (no manoeuvre allowance)
    // is that target's, or clutter about it: it starts no track.
    if (t->status != TRK_TENTATIVE && pp->plain)
        h->in_confirmed = true;
}

static int s_gate (trk_tracker_t *self, size_t nt, size_t nh, double t_lo, double t_hi,
                   double r_max)
{
    for (size_t ti = 0; ti < nt; ti++) {
        const trk_track_t *t = &self->tracks[self->act[ti]];
        // The gate's reach over the scan: its largest extent at the latest hit
        // time, centred where the track is mid-scan, plus its motion either way.
        double t_end = fmax (t_hi, t->est.t_s), t_mid = fmax ((t_lo + t_hi) / 2, t->est.t_s);
        trk_estimate_t pe;
        trk_filter_predict (&t->est, &self->p.filter, t_end, &pe);
        double lam = s_lambda_max (pe.P[0], pe.P[1], pe.P[5]) + r_max +
                     (t->status == TRK_TENTATIVE ? 0 : s_maneuver_var (self, t_end - t->est.t_s));
        double speed = hypot (t->est.x[2], t->est.x[3]);
        double reach = sqrt (self->gate3 * lam) + speed * (t_hi - t_lo) / 2 + 1;
        double ce = t->est.x[0] + t->est.x[2] * (t_mid - t->est.t_s);
        double cn = t->est.x[1] + t->est.x[3] * (t_mid - t->est.t_s);
        // Pairs: at most one per hit for this track.
        if (s_grow ((void **)&self->pairs, &self->pair_cap, self->pair_count + nh,
                    sizeof *self->pairs) < 0)
            return -ENOMEM;
        double span_cells = 2 * reach / S_CELL_M + 2;
        if (!isfinite (reach) || !isfinite (ce) || !isfinite (cn) ||
            span_cells * span_cells > (double)nh || fabs (ce) + reach > 1e12 ||
            fabs (cn) + reach > 1e12) { // a huge gate: every hit is a candidate
            for (size_t hi = 0; hi < nh; hi++)
                s_try_pair (self, ti, hi);
            continue;
        }
        int64_t x0 = s_cell_of (ce - reach), x1 = s_cell_of (ce + reach);
        int64_t y0 = s_cell_of (cn - reach), y1 = s_cell_of (cn + reach);
        for (int64_t ix = x0; ix <= x1; ix++)
            for (int64_t iy = y0; iy <= y1; iy++)
                for (size_t hi = s_grid_first (self, ix, iy); hi != SIZE_MAX;
                     hi = self->hit_next[hi]) {
                    const trk_hit_t *h = &self->hits[hi].h;
                    if (fabs (h->z[0] - ce) <= reach && fabs (h->z[1] - cn) <= reach)
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

/* Solve one cluster: work[lo..hi). */
static int s_solve_cluster (trk_tracker_t *self, size_t lo, size_t hi, trk_scan_out_t *out)
{
    size_t np = hi - lo;
    if (np == 1) { // one track, one hit
        const s_pair_t *pp = &self->work[lo];
        self->assigned[pp->track] = pp->hit;
        self->hits[pp->hit].track = pp->track;
        if (out->largest_cluster < 1)
            out->largest_cluster = 1;
        return 0;
    }
    // The cluster's tracks (pairs come sorted by track) and hits, numbered locally.
    if (s_grow ((void **)&self->ctracks, &self->ctracks_cap, np, sizeof (size_t)) < 0 ||
        s_grow ((void **)&self->chits, &self->chits_cap, np, sizeof (size_t)) < 0 ||
        s_grow ((void **)&self->col, &self->col_cap, np, sizeof (size_t)) < 0)
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
    if (s_grow ((void **)&self->cost, &self->cost_cap, ncost, sizeof *self->cost) < 0)
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
        double miss = pp->gate + 1 + pp->log_det, *slot = &c[i * cols + m + i];
        if (*slot == S_FORBIDDEN || miss > *slot)
            *slot = miss;
    }
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
    if (s_grow ((void **)&self->work, &self->work_cap, self->pair_count, sizeof *self->work) < 0)
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
    if (s_grow ((void **)&self->uf, &self->uf_cap, nodes, sizeof *self->uf) < 0)
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
    int rc = s_pass (self, nt, nh, false, out);
    return rc < 0 ? rc : s_pass (self, nt, nh, true, out);
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

/* Whether a sector scan covered a position. */
static bool s_covered (const trk_scan_t *scan, double e, double n)
{
    if (scan->full_revolution || !(scan->sector_width_deg < 360))
        return true;
    double az = atan2 (e - scan->platform[0], n - scan->platform[1]) * 180 / S_PI;
    double off = fmod (az - scan->sector_center_deg, 360.0);
    if (off > 180)
        off -= 360;
    if (off < -180)
        off += 360;
    return fabs (off) <= scan->sector_width_deg / 2;
}

/* One scan's outcome for a track: hit h (or NULL). Returns false when the
 * track is to be deleted. */
static bool s_upkeep (trk_tracker_t *self, trk_track_t *t, const s_hit_t *h, const trk_scan_t *scan,
                      trk_scan_out_t *out)
{
    const trk_params_t *p = &self->p;
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
            if (trk_filter_update (&pr, &p->filter, self->gains, h->h.z, h->R) < 0) {
                h = NULL; // a covariance gone bad: a miss, not a hit
            } else {
                t->est = pr;
                t->updates++;
            }
        }
    }
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
    int got = s_popcount (t->window & nmask);
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
    if (s_grow ((void **)&self->hits, &self->hit_cap, nh, sizeof *self->hits) < 0 ||
        s_grow ((void **)&self->hit_next, &self->hit_next_cap, nh, sizeof *self->hit_next) < 0 ||
        s_grow ((void **)&self->act, &self->act_cap, nt + 1, sizeof *self->act) < 0 ||
        s_grow ((void **)&self->assigned, &self->assigned_cap, nt + 1, sizeof *self->assigned) < 0)
        return -ENOMEM;
    if (s_grow ((void **)&self->tracks, &self->cap, nt + nh, sizeof *self->tracks) < 0 ||
        s_grow ((void **)&self->turns, &self->turn_cap, nt + 1, sizeof *self->turns) < 0 ||
        s_grow ((void **)&self->dead, &self->dead_cap, nt + 1, sizeof *self->dead) < 0)
        return -ENOMEM;
    return 0;
}

int trk_tracker_scan (trk_tracker_t *self, const trk_scan_t *scan, const trk_hit_t *hits, size_t n,
                      trk_scan_out_t *ret)
{
    trk_scan_out_t out = {0};
    self->turn_count = 0;
    self->dead_count = 0;
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
    for (size_t i = 0; i < nt; i++)
        self->assigned[i] = SIZE_MAX;
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
        if (!s_upkeep (self, &self->tracks[idx], h, scan, &out))
            s_kill (self, idx, &out);
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

/* A radar's likeliest track for a BCIS reply. */
typedef struct {
    uint32_t uav_id;
    trk_track_t *best;
    double cost; // d² + ln|S|
} s_radar_best_t;

size_t trk_tracker_bcis (trk_tracker_t *self, double t_s, const double z[2], uint32_t responder_id)
{
    if (!isfinite (t_s) || !isfinite (z[0]) || !isfinite (z[1]))
        return 0;
    double s2 = self->p.bcis_sigma_m * self->p.bcis_sigma_m;
    double R[4] = {s2, 0, 0, s2};
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
        if (de * de + dn * dn > 25e6) // beyond 5 km: no gate of a track this fresh reaches
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
            radar[nr++] = (s_radar_best_t){c->uav_id, NULL, INFINITY};
        }
        if (d2 + log_det < radar[k].cost) {
            radar[k].cost = d2 + log_det;
            radar[k].best = c;
        }
    }
    for (size_t k = 0; k < nr; k++) {
        trk_track_t *b = radar[k].best;
        b->friendly = true;
        b->friendly_id = responder_id;
        b->friendly_s = fmax (b->friendly_s, t_s);
    }
    return nr;
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

/* ---- checkpoint ---------------------------------------------------------------------- */

#define S_MAGIC   "MSCGSTRK"
#define S_VERSION 1u

typedef struct {
    uint8_t *buf;
    size_t len, cap;
    bool fail;
} s_writer_t;

static void s_put (s_writer_t *w, const void *src, size_t n)
{
    if (w->fail)
        return;
    if (w->len + n > w->cap) {
        size_t cap = w->cap ? w->cap * 2 : 4096;
        while (cap < w->len + n)
            cap *= 2;
        uint8_t *b = realloc (w->buf, cap);
        if (!b) {
            w->fail = true;
            return;
        }
        w->buf = b;
        w->cap = cap;
    }
    memcpy (w->buf + w->len, src, n);
    w->len += n;
}

static void s_put_u32 (s_writer_t *w, uint32_t v)
{
    uint8_t b[4] = {(uint8_t)v, (uint8_t)(v >> 8), (uint8_t)(v >> 16), (uint8_t)(v >> 24)};
    s_put (w, b, 4);
}

static void s_put_f64 (s_writer_t *w, double d)
{
    uint64_t v;
    memcpy (&v, &d, 8);
    s_put_u32 (w, (uint32_t)v);
    s_put_u32 (w, (uint32_t)(v >> 32));
}

typedef struct {
    const uint8_t *buf;
    size_t len, off;
    bool fail;
} s_reader_t;

static uint32_t s_get_u32 (s_reader_t *r)
{
    if (r->fail || r->len - r->off < 4) {
        r->fail = true;
        return 0;
    }
    const uint8_t *b = r->buf + r->off;
    r->off += 4;
    return (uint32_t)b[0] | (uint32_t)b[1] << 8 | (uint32_t)b[2] << 16 | (uint32_t)b[3] << 24;
}

static double s_get_f64 (s_reader_t *r)
{
    uint64_t lo = s_get_u32 (r), hi = s_get_u32 (r);
    uint64_t v = lo | hi << 32;
    double d;
    memcpy (&d, &v, 8);
    if (!isfinite (d))
        r->fail = true;
    return d;
}

static void s_put_track (s_writer_t *w, const trk_track_t *t)
{
    s_put_u32 (w, t->id);
    s_put_u32 (w, t->uav_id);
    s_put_u32 (w, (uint32_t)t->status);
    for (int i = 0; i < 4; i++)
        s_put_f64 (w, t->est.x[i]);
    for (int i = 0; i < 16; i++)
        s_put_f64 (w, t->est.P[i]);
    s_put_f64 (w, t->est.t_s);
    s_put_f64 (w, t->up_m);
    s_put_u32 (w, t->hits);
    s_put_u32 (w, t->updates);
    s_put_u32 (w, t->misses);
    s_put_u32 (w, t->window);
    s_put_u32 (w, t->scans);
    s_put_f64 (w, t->last_hit_s);
    s_put_u32 (w, t->last_scan);
    s_put_u32 (w, t->friendly);
    s_put_u32 (w, t->friendly_id);
    s_put_f64 (w, t->friendly_s);
    s_put_u32 (w, t->have_uv);
    s_put_f64 (w, t->v_last[0]);
    s_put_f64 (w, t->v_last[1]);
    s_put_u32 (w, t->turning);
    for (int i = 0; i < 2; i++) {
        s_put_f64 (w, t->uv_before[i]);
        s_put_f64 (w, t->v_before[i]);
    }
    s_put_u32 (w, t->turn_scan);
    s_put_u32 (w, t->history_count);
    for (uint32_t k = 0; k < t->history_count; k++) {
        const trk_history_point_t *h = &t->history[k];
        s_put_f64 (w, h->e_m);
        s_put_f64 (w, h->n_m);
        s_put_f64 (w, h->u_m);
        s_put_f64 (w, h->t_s);
        s_put_u32 (w, h->scan_number);
        s_put_u32 (w, h->hit_id);
    }
}

static bool s_get_track (s_reader_t *r, trk_track_t *t)
{
    memset (t, 0, sizeof *t);
    t->id = s_get_u32 (r);
    t->uav_id = s_get_u32 (r);
    uint32_t status = s_get_u32 (r);
    for (int i = 0; i < 4; i++)
        t->est.x[i] = s_get_f64 (r);
    for (int i = 0; i < 16; i++)
        t->est.P[i] = s_get_f64 (r);
    t->est.t_s = s_get_f64 (r);
    t->up_m = s_get_f64 (r);
    t->hits = s_get_u32 (r);
    t->updates = s_get_u32 (r);
    t->misses = s_get_u32 (r);
    t->window = s_get_u32 (r);
    t->scans = s_get_u32 (r);
    t->last_hit_s = s_get_f64 (r);
    t->last_scan = s_get_u32 (r);
    uint32_t friendly = s_get_u32 (r);
    t->friendly_id = s_get_u32 (r);
    t->friendly_s = s_get_f64 (r);
    uint32_t have_uv = s_get_u32 (r);
    t->v_last[0] = s_get_f64 (r);
    t->v_last[1] = s_get_f64 (r);
    uint32_t turning = s_get_u32 (r);
    for (int i = 0; i < 2; i++) {
        t->uv_before[i] = s_get_f64 (r);
        t->v_before[i] = s_get_f64 (r);
    }
    t->turn_scan = s_get_u32 (r);
    t->history_count = s_get_u32 (r);
    if (r->fail || status > TRK_COASTING || friendly > 1 || have_uv > 1 || turning > 1 ||
        t->id == 0 || t->hits == 0 || t->history_count > TRK_HISTORY_MAX)
        return false;
    for (int i = 0; i < 4; i++)
        if (!(t->est.P[i * 5] >= 0))
            return false;
    t->status = (trk_status_t)status;
    t->friendly = friendly;
    t->have_uv = have_uv;
    t->turning = turning;
    for (uint32_t k = 0; k < t->history_count; k++) {
        trk_history_point_t *h = &t->history[k];
        h->e_m = s_get_f64 (r);
        h->n_m = s_get_f64 (r);
        h->u_m = s_get_f64 (r);
        h->t_s = s_get_f64 (r);
        h->scan_number = s_get_u32 (r);
        h->hit_id = s_get_u32 (r);
    }
    return !r->fail;
}

int trk_tracker_save (const trk_tracker_t *self, uint8_t **ret_buf, size_t *ret_len)
{
    s_writer_t w = {0};
    s_put (&w, S_MAGIC, 8);
    s_put_u32 (&w, S_VERSION);
    s_put_u32 (&w, self->next_id);
    s_put_u32 (&w, (uint32_t)self->count);
    for (size_t i = 0; i < self->count; i++)
        s_put_track (&w, &self->tracks[i]);
    if (w.fail) {
        free (w.buf);
        return -ENOMEM;
    }
    *ret_buf = w.buf;
    *ret_len = w.len;
    return 0;
}

static int s_cmp_u32 (const void *a, const void *b)
{
    uint32_t x = *(const uint32_t *)a, y = *(const uint32_t *)b;
    return x < y ? -1 : x > y;
}

int trk_tracker_restore (trk_tracker_t *self, const uint8_t *buf, size_t len, char *err,
                         size_t errlen)
{
    s_reader_t r = {.buf = buf, .len = len};
    if (len < 20 || memcmp (buf, S_MAGIC, 8) != 0) {
        snprintf (err, errlen, "not a trackerd checkpoint");
        return -EPROTO;
    }
    r.off = 8;
    uint32_t version = s_get_u32 (&r), next_id = s_get_u32 (&r), count = s_get_u32 (&r);
    if (version != S_VERSION) {
        snprintf (err, errlen, "a trackerd checkpoint of version %u (this is %u)", version,
                  S_VERSION);
        return -EPROTO;
    }
    // Each track takes at least 300 bytes: a count the buffer cannot hold is damage.
    if (count > len / 300) {
        snprintf (err, errlen, "the checkpoint claims %u tracks in %zu bytes", count, len);
        return -EPROTO;
    }
    trk_track_t *tracks = count ? malloc (count * sizeof *tracks) : NULL;
    uint32_t *ids = count ? malloc (count * sizeof *ids) : NULL;
    if (count && (!tracks || !ids)) {
        free (tracks);
        free (ids);
        snprintf (err, errlen, "out of memory for %u tracks", count);
        return -ENOMEM;
    }
    int rc = 0;
    for (uint32_t i = 0; i < count && rc == 0; i++) {
        if (!s_get_track (&r, &tracks[i])) {
            snprintf (err, errlen, "track %u of %u in the checkpoint is damaged", i + 1, count);
            rc = -EPROTO;
        } else {
            ids[i] = tracks[i].id;
        }
    }
    if (rc == 0 && r.off != len) {
        snprintf (err, errlen, "the checkpoint has %zu bytes too many", len - r.off);
        rc = -EPROTO;
    }
    if (rc == 0 && count) {
        qsort (ids, count, sizeof *ids, s_cmp_u32);
        for (uint32_t i = 0; i < count && rc == 0; i++)
            if ((i > 0 && ids[i] == ids[i - 1]) || ids[i] >= next_id) {
                snprintf (err, errlen,
                          "the checkpoint's track ids are inconsistent (id %u, next id %u)", ids[i],
                          next_id);
                rc = -EPROTO;
            }
    }
    if (rc == 0 && next_id == 0) {
        snprintf (err, errlen, "the checkpoint's next track id is 0");
        rc = -EPROTO;
    }
    for (uint32_t i = 0; i < count && rc == 0; i++) { // keep the newest history_scans points
        trk_track_t *t = &tracks[i];
        uint32_t max = (uint32_t)self->p.history_scans;
        if (t->history_count > max) {
            uint32_t drop = t->history_count - max;
            memmove (t->history, t->history + drop, max * sizeof t->history[0]);
            t->history_count = max;
        }
    }
    if (rc == 0 && count > self->cap &&
        s_grow ((void **)&self->tracks, &self->cap, count, sizeof *self->tracks) < 0) {
        snprintf (err, errlen, "out of memory for %u tracks", count);
        rc = -ENOMEM;
    }
    if (rc == 0) {
        if (count)
            memcpy (self->tracks, tracks, count * sizeof *tracks);
        self->count = count;
        self->next_id = next_id;
    }
    free (tracks);
    free (ids);
    return rc;
}

int trk_tracker_checkpoint_next_id (const uint8_t *buf, size_t len, uint32_t *ret_id)
{
    if (len < 20 || memcmp (buf, S_MAGIC, 8) != 0)
        return -EPROTO;
    s_reader_t r = {.buf = buf, .len = len, .off = 8};
    uint32_t version = s_get_u32 (&r), next_id = s_get_u32 (&r);
    if (version != S_VERSION || next_id == 0)
        return -EPROTO;
    *ret_id = next_id;
    return 0;
}

void trk_tracker_raise_next_id (trk_tracker_t *self, uint32_t id)
{
    if (id > self->next_id)
        self->next_id = id;
}
