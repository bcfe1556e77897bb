/* ms_gospa — the GOSPA metric between a set of truth points and a set of
 * estimate points in the plane, with alpha = 2, and its mean over scans.
 *
 * Rahmathullah, García-Fernández, Svensson, "Generalized optimal sub-pattern
 * assignment metric", FUSION 2017 (arXiv:1601.05585). For truths X, estimates
 * Y, cut-off c > 0 and order p >= 1:
 *
 *   d = ( min over assignments γ of [ Σ_{(i,j)∈γ} d(x_i,y_j)^p
 *                                      + (c^p / 2)·(|X| + |Y| − 2|γ|) ] )^(1/p)
 *
 * With alpha = 2 a pair at distance >= c costs at least as much as leaving
 * both unassigned, so only pairs closer than c are ever assigned; the optimal
 * assignment is a linear sum assignment over the cost matrix min(d, c)^p
 * (trackerd's Hungarian solver, trk_assign), and pairs it makes at distance
 * >= c are undone.
 *
 * The components are reported as Stone Soup's GOSPAMetric reports them
 * (stonesoup/metricgenerator/ospametric.py, compute_gospa_metric: "Note that
 * distance = (localisation + missed + false)^1/p"): as p-th powers, in
 * metres^p, not as distances:
 *   localisation = Σ over assigned pairs of d^p
 *   missed       = (c^p / 2)·(truths unassigned)
 *   false_       = (c^p / 2)·(estimates unassigned)
 *   distance     = (localisation + missed + false_)^(1/p), metres
 * Stone Soup's optional switching term (switching_penalty, default 0) is not
 * computed. Pure: no logging, no globals. */
#ifndef MS_GOSPA_H
#define MS_GOSPA_H

#include <stddef.h>

/* A point in the local plane. */
typedef struct {
    double e, n; // east, north, metres
} ms_point_t;

/* GOSPA at one scan. */
typedef struct {
    double c;            // the cut-off used, metres
    double p;            // the order used
    double distance;     // GOSPA, metres
    double localisation; // Σ d^p over assigned pairs, metres^p
    double missed;       // (c^p / 2) · missed_count, metres^p
    double false_;       // (c^p / 2) · false_count, metres^p
    size_t assigned;     // pairs assigned (each closer than c)
    size_t missed_count; // truths unassigned
    size_t false_count;  // estimates unassigned
} ms_gospa_t;

/* GOSPA between truths x[nx] and estimates y[ny] (either may be NULL when its
 * count is 0) with cut-off c (metres) and order p. ret_assign (may be NULL)
 * gets, for each estimate j < ny, the index of the truth it was assigned to, or
 * -1. 0, -EINVAL (c <= 0, c or p not finite, p < 1, c^p overflows, a point not
 * finite, NULL with a non-zero count), -ENOMEM. *ret and ret_assign are
 * written only on success. */
int ms_gospa (const ms_point_t *x, size_t nx, const ms_point_t *y, size_t ny, double c, double p,
              ms_gospa_t *ret, long *ret_assign);

/* Running mean of GOSPA over scans: a plain struct of sums, empty when
 * zeroed ({0}). Every scan added must share c and p. */
typedef struct {
    size_t scans;                               // scans added
    double c, p;                                // of the first scan added
    double distance;                            // Σ distance, metres
    double localisation, missed, false_;        // Σ of the components, metres^p
    double assigned, missed_count, false_count; // Σ of the counts
} ms_gospa_mean_t;

/* The means per scan: each field the arithmetic mean over the scans (the mean
 * distance is the mean of the per-scan distances, not the p-th root of the
 * mean components). */
typedef struct {
    size_t scans;                               // scans averaged
    double distance;                            // metres
    double localisation, missed, false_;        // metres^p
    double assigned, missed_count, false_count; // per scan
} ms_gospa_avg_t;

/* Add one scan's GOSPA. 0, -EINVAL when its c or p differ from the first scan's. */
int ms_gospa_mean_add (ms_gospa_mean_t *self, const ms_gospa_t *g);
/* Pool src's scans into dst (Monte Carlo runs): the same as adding every scan
 * of src to dst, up to rounding. 0, -EINVAL when both have scans and their c
 * or p differ. dst is unchanged on failure. */
int ms_gospa_mean_merge (ms_gospa_mean_t *dst, const ms_gospa_mean_t *src);
/* The means; every mean is NaN when no scan was added. */
void ms_gospa_mean_finish (const ms_gospa_mean_t *self, ms_gospa_avg_t *ret);

#endif
