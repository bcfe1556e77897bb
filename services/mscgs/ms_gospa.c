/* ms_gospa — GOSPA with alpha = 2 (see ms_gospa.h).
 *
 * The minimum over assignments is a linear sum assignment: with the smaller
 * set as rows, every row is matched to a distinct column at cost
 * min(d, c)^p. A row matched at cost c^p (distance >= c) stands for a truth
 * and an estimate both left unassigned, which costs (c^p / 2)·2 = c^p in
 * GOSPA too, and every column left over costs c^p / 2 whatever the matching;
 * so the matching of least total cost is the optimal GOSPA assignment. The
 * Hungarian method that finds it is trackerd's (trk_assign: shortest
 * augmenting paths with dual potentials, O(rows² · cols)), the one the
 * tracker's global nearest neighbour association uses. */
#include "ms_gospa.h"

#include "trk_assign.h"

#include <assert.h>
#include <errno.h>
#include <math.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdlib.h>

static bool s_points_finite (const ms_point_t *pt, size_t n)
{
    for (size_t i = 0; i < n; i++)
        if (!isfinite (pt[i].e) || !isfinite (pt[i].n))
            return false;
    return true;
}

int ms_gospa (const ms_point_t *x, size_t nx, const ms_point_t *y, size_t ny, double c, double p,
              ms_gospa_t *ret, long *ret_assign)
{
    assert (ret);
    if ((nx && !x) || (ny && !y))
        return -EINVAL;
    if (!isfinite (c) || c <= 0 || !isfinite (p) || p < 1)
        return -EINVAL;
    const double cp = pow (c, p); // cost of a pair left unassigned, metres^p
    if (!isfinite (cp))
        return -EINVAL;
    if (!s_points_finite (x, nx) || !s_points_finite (y, ny))
        return -EINVAL;

    ms_gospa_t g = {.c = c, .p = p};
    if (nx == 0 || ny == 0) {
        // Nothing to pair: every truth missed, every estimate false.
        g.missed_count = nx;
        g.false_count = ny;
        g.missed = cp / 2 * (double)nx;
        g.false_ = cp / 2 * (double)ny;
        g.distance = pow (g.missed + g.false_, 1 / p);
        if (ret_assign)
            for (size_t j = 0; j < ny; j++)
                ret_assign[j] = -1;
        *ret = g;
        return 0;
    }

    // Rows are the smaller set (the solver wants rows <= cols).
    const bool truth_rows = nx <= ny;
    const size_t rows = truth_rows ? nx : ny, cols = truth_rows ? ny : nx;
    if (rows > SIZE_MAX / sizeof (double) / cols)
        return -ENOMEM;
    double *cost = malloc (rows * cols * sizeof *cost); // min(d, c)^p, metres^p
    size_t *col = malloc (rows * sizeof *col);          // column matched to each row
    trk_assign_t *solver = trk_assign_new ();
    int rc = -ENOMEM;
    if (!cost || !col || !solver)
        goto done;
    for (size_t i = 0; i < rows; i++)
        for (size_t j = 0; j < cols; j++) {
            const ms_point_t *a = truth_rows ? &x[i] : &x[j];
            const ms_point_t *b = truth_rows ? &y[j] : &y[i];
            double d = hypot (a->e - b->e, a->n - b->n);
            cost[i * cols + j] = d < c ? pow (d, p) : cp;
        }
    rc = trk_assign_solve (solver, cost, rows, cols, col, NULL);
    if (rc < 0)
        goto done;

    // Nothing fails from here: the outputs can be written.
    if (ret_assign)
        for (size_t j = 0; j < ny; j++)
            ret_assign[j] = -1;
    for (size_t i = 0; i < rows; i++) {
        double k = cost[i * cols + col[i]];
        if (!(k < cp))
            continue; // at or beyond the cut-off: both stay unassigned
        g.assigned++;
        g.localisation += k;
        if (ret_assign) {
            size_t ti = truth_rows ? i : col[i], ej = truth_rows ? col[i] : i;
            ret_assign[ej] = (long)ti;
        }
    }
    g.missed_count = nx - g.assigned;
    g.false_count = ny - g.assigned;
    g.missed = cp / 2 * (double)g.missed_count;
    g.false_ = cp / 2 * (double)g.false_count;
    g.distance = pow (g.localisation + g.missed + g.false_, 1 / p);
    *ret = g;
    rc = 0;
done:
    trk_assign_destroy (&solver);
    free (col);
    free (cost);
    return rc;
}

int ms_gospa_mean_add (ms_gospa_mean_t *self, const ms_gospa_t *g)
{
    assert (self && g);
    if (self->scans == 0) {
        self->c = g->c;
        self->p = g->p;
    } else if (g->c != self->c || g->p != self->p)
        return -EINVAL;
    self->scans++;
    self->distance += g->distance;
    self->localisation += g->localisation;
    self->missed += g->missed;
    self->false_ += g->false_;
    self->assigned += (double)g->assigned;
    self->missed_count += (double)g->missed_count;
    self->false_count += (double)g->false_count;
    return 0;
}

int ms_gospa_mean_merge (ms_gospa_mean_t *dst, const ms_gospa_mean_t *src)
{
    assert (dst && src);
    if (src->scans == 0)
        return 0;
    if (dst->scans == 0) {
        *dst = *src;
        return 0;
    }
    if (src->c != dst->c || src->p != dst->p)
        return -EINVAL;
    dst->scans += src->scans;
    dst->distance += src->distance;
    dst->localisation += src->localisation;
    dst->missed += src->missed;
    dst->false_ += src->false_;
    dst->assigned += src->assigned;
    dst->missed_count += src->missed_count;
    dst->false_count += src->false_count;
    return 0;
}

void ms_gospa_mean_finish (const ms_gospa_mean_t *self, ms_gospa_avg_t *ret)
{
    assert (self && ret);
    // 0 / 0 would be NaN too, but say so rather than rely on it.
    double k = self->scans ? 1.0 / (double)self->scans : NAN;
    ret->scans = self->scans;
    ret->distance = self->distance * k;
    ret->localisation = self->localisation * k;
    ret->missed = self->missed * k;
    ret->false_ = self->false_ * k;
    ret->assigned = self->assigned * k;
    ret->missed_count = self->missed_count * k;
    ret->false_count = self->false_count * k;
}
