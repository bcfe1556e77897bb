/* trk_kbest — Murty's k best assignments (see trk_kbest.h).
 *
 * Every node of the search is a cost matrix with some entries forbidden
 * (set to the forbidden value) and some rows forced (every other entry of
 * the row and of the forced column forbidden), with its optimal assignment.
 * The node of least total is taken as the next solution and split: for the
 * i-th row not yet forced, a child forbids that row's column and forces the
 * rows split before it to their columns. Nodes live in flat arrays reused
 * from one solve to the next (grown, never shrunk, whatever the shape). */
#include "trk_kbest.h"
#include "cgs_util.h"
#include "trk_assign.h"

#include <errno.h>
#include <math.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

struct trk_kbest {
    trk_assign_t *assign;
    size_t rows, cols;
    // the search's nodes: matrix (rows × cols), solution (rows), forced rows
    double *mat;
    size_t *sol;
    bool *forced;
    double *total;
    bool *open;        // still to be taken
    size_t nodes, cap; // nodes in use; nodes the arrays hold at this shape
    size_t mat_cap, sol_cap, forced_cap, total_cap, open_cap; // elements each array holds
    // the solutions, in order
    size_t *found_sol;
    double *found_total;
    size_t found, found_total_cap, found_sol_cap;
    size_t *col; // one solve's columns
    size_t col_cap;
};

trk_kbest_t *trk_kbest_new (void)
{
    trk_kbest_t *self = calloc (1, sizeof *self);
    if (!self)
        return NULL;
    self->assign = trk_assign_new ();
    if (!self->assign) {
        free (self);
        return NULL;
    }
    return self;
}

void trk_kbest_destroy (trk_kbest_t **self_p)
{
    if (!self_p || !*self_p)
        return;
    trk_kbest_t *self = *self_p;
    trk_assign_destroy (&self->assign);
    free (self->mat);
    free (self->sol);
    free (self->forced);
    free (self->total);
    free (self->open);
    free (self->found_sol);
    free (self->found_total);
    free (self->col);
    free (self);
    *self_p = NULL;
}

/* Room for node index n at the present shape. */
static int s_node_reserve (trk_kbest_t *self, size_t n)
{
    if (n < self->cap)
        return 0;
    size_t cap = self->cap ? self->cap * 2 : 16;
    while (cap <= n)
        cap *= 2;
    size_t rc = self->rows * self->cols, r = self->rows;
    if (cgs_grow ((void **)&self->mat, &self->mat_cap, cap * rc, sizeof (double)) < 0 ||
        cgs_grow ((void **)&self->sol, &self->sol_cap, cap * r, sizeof (size_t)) < 0 ||
        cgs_grow ((void **)&self->forced, &self->forced_cap, cap * r, sizeof (bool)) < 0 ||
        cgs_grow ((void **)&self->total, &self->total_cap, cap, sizeof (double)) < 0 ||
        cgs_grow ((void **)&self->open, &self->open_cap, cap, sizeof (bool)) < 0)
        return -ENOMEM;
    self->cap = cap;
    return 0;
}

/* Solve node n's matrix; it stays open only when a solution avoids every
 * forbidden entry. */
static int s_node_solve (trk_kbest_t *self, size_t n, double forbidden)
{
    size_t r = self->rows, c = self->cols;
    const double *m = self->mat + n * r * c;
    double total;
    int rc = trk_assign_solve (self->assign, m, r, c, self->col, &total);
    if (rc < 0)
        return rc;
    bool ok = true;
    for (size_t i = 0; i < r && ok; i++)
        ok = m[i * c + self->col[i]] < forbidden;
    memcpy (self->sol + n * r, self->col, r * sizeof (size_t));
    self->total[n] = total;
    self->open[n] = ok;
    return 0;
}

int trk_kbest_solve (trk_kbest_t *self, const double *cost, size_t rows, size_t cols, size_t k,
                     double forbidden)
{
    self->found = 0;
    self->nodes = 0;
    if (rows > cols || !isfinite (forbidden))
        return -EINVAL;
    for (size_t i = 0; i < rows * cols; i++)
        if (!isfinite (cost[i]))
            return -EINVAL;
    if (k == 0)
        return 0;
    // A change of shape changes the node arrays' strides: their count of
    // nodes starts again (the memory stays).
    if (rows != self->rows || cols != self->cols) {
        self->rows = rows;
        self->cols = cols;
        self->cap = 0;
    }
    if (cgs_grow ((void **)&self->col, &self->col_cap, rows + 1, sizeof (size_t)) < 0 ||
        cgs_grow ((void **)&self->found_total, &self->found_total_cap, k, sizeof (double)) < 0 ||
        cgs_grow ((void **)&self->found_sol, &self->found_sol_cap, k * (rows + 1),
                  sizeof (size_t)) < 0)
        return -ENOMEM;
    size_t rc = rows * cols;
    int e = s_node_reserve (self, 0);
    if (e < 0)
        return e;
    memcpy (self->mat, cost, rc * sizeof (double));
    memset (self->forced, 0, rows * sizeof (bool));
    self->nodes = 1;
    if ((e = s_node_solve (self, 0, forbidden)) < 0)
        return e;
    while (self->found < k) {
        // The open node of least total is the next solution.
        size_t best = SIZE_MAX;
        for (size_t n = 0; n < self->nodes; n++)
            if (self->open[n] && (best == SIZE_MAX || self->total[n] < self->total[best]))
                best = n;
        if (best == SIZE_MAX)
            break;
        self->open[best] = false;
        memcpy (self->found_sol + self->found * rows, self->sol + best * rows,
                rows * sizeof (size_t));
        self->found_total[self->found++] = self->total[best];
        if (self->found == k)
            break;
        // Split it: child i forbids row i's column, with the rows split
        // before it forced to theirs.
        if ((e = s_node_reserve (self, self->nodes + rows)) < 0)
            return e;
        const size_t *bsol = self->sol + best * rows;
        for (size_t i = 0; i < rows; i++) {
            if (self->forced[best * rows + i])
                continue;
            size_t n = self->nodes;
            double *m = self->mat + n * rc;
            bool *fo = self->forced + n * rows;
            memcpy (m, self->mat + best * rc, rc * sizeof (double));
            memcpy (fo, self->forced + best * rows, rows * sizeof (bool));
            m[i * cols + bsol[i]] = forbidden;
            // Force the rows split before i (those not forced already).
            for (size_t j = 0; j < i; j++) {
                if (fo[j])
                    continue;
                fo[j] = true;
                for (size_t cc = 0; cc < cols; cc++)
                    if (cc != bsol[j])
                        m[j * cols + cc] = forbidden;
                for (size_t rr = 0; rr < rows; rr++)
                    if (rr != j)
                        m[rr * cols + bsol[j]] = forbidden;
            }
            if ((e = s_node_solve (self, n, forbidden)) < 0)
                return e;
            if (self->open[n])
                self->nodes++;
        }
    }
    return (int)self->found;
}

size_t trk_kbest_column (const trk_kbest_t *self, size_t s, size_t row)
{
    return self->found_sol[s * self->rows + row];
}

double trk_kbest_total (const trk_kbest_t *self, size_t s)
{
    return self->found_total[s];
}

void trk_kbest_marginals (const trk_kbest_t *self, size_t n, size_t rows, size_t cols,
                          double *ret_beta)
{
    for (size_t i = 0; i < rows * cols; i++)
        ret_beta[i] = 0;
    if (n == 0 || n > self->found)
        n = self->found;
    if (n == 0)
        return;
    double sum = 0, t0 = self->found_total[0];
    for (size_t s = 0; s < n; s++) {
        double w = exp (-0.5 * (self->found_total[s] - t0));
        sum += w;
        for (size_t r = 0; r < rows; r++)
            ret_beta[r * cols + self->found_sol[s * self->rows + r]] += w;
    }
    for (size_t i = 0; i < rows * cols; i++)
        ret_beta[i] /= sum;
}
