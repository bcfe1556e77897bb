/* trk_assign — the Hungarian method with potentials (see trk_assign.h).
 *
 * Rows are added one at a time; each addition finds the shortest augmenting
 * path from the new row to a free column in the reduced costs
 * c(i, j) − u(i) − v(j) (Dijkstra over columns), then updates the potentials
 * so every reduced cost stays non-negative and those on the matching are 0. */
#include "trk_assign.h"

#include <errno.h>
#include <math.h>
#include <stdbool.h>
#include <stdlib.h>

struct trk_assign {
    size_t cap_rows, cap_cols;
    double *u, *v; // row and column potentials (index 0 is the virtual row/column)
    double *minv;  // shortest reduced distance to each column found so far
    size_t *p;     // p[j]: row matched to column j (0: none), 1-based
    size_t *way;   // way[j]: the previous column on the path to j
    bool *used;    // columns already settled in this search
};

trk_assign_t *trk_assign_new (void)
{
    return calloc (1, sizeof (trk_assign_t));
}

void trk_assign_destroy (trk_assign_t **self_p)
{
    if (!self_p || !*self_p)
        return;
    trk_assign_t *self = *self_p;
    free (self->u);
    free (self->v);
    free (self->minv);
    free (self->p);
    free (self->way);
    free (self->used);
    free (self);
    *self_p = NULL;
}

static int s_reserve (trk_assign_t *self, size_t rows, size_t cols)
{
    if (rows > self->cap_rows) {
        double *u = realloc (self->u, (rows + 1) * sizeof *u);
        if (!u)
            return -ENOMEM;
        self->u = u;
        self->cap_rows = rows;
    }
    if (cols > self->cap_cols) {
        size_t n = cols + 1;
        double *v = realloc (self->v, n * sizeof *v);
        if (v)
            self->v = v;
        double *minv = realloc (self->minv, n * sizeof *minv);
        if (minv)
            self->minv = minv;
        size_t *p = realloc (self->p, n * sizeof *p);
        if (p)
            self->p = p;
        size_t *way = realloc (self->way, n * sizeof *way);
        if (way)
            self->way = way;
        bool *used = realloc (self->used, n * sizeof *used);
        if (used)
            self->used = used;
        if (!v || !minv || !p || !way || !used)
            return -ENOMEM;
        self->cap_cols = cols;
    }
    return 0;
}

int trk_assign_solve (trk_assign_t *self, const double *cost, size_t rows, size_t cols,
                      size_t *ret_col, double *ret_total)
{
    if (rows > cols)
        return -EINVAL;
    if (rows == 0) {
        if (ret_total)
            *ret_total = 0;
        return 0;
    }
    for (size_t k = 0; k < rows * cols; k++)
        if (!isfinite (cost[k]))
            return -EINVAL;
    if (s_reserve (self, rows, cols) < 0)
        return -ENOMEM;
    double *u = self->u, *v = self->v, *minv = self->minv;
    size_t *p = self->p, *way = self->way;
    bool *used = self->used;
    for (size_t i = 0; i <= rows; i++)
        u[i] = 0;
    for (size_t j = 0; j <= cols; j++) {
        v[j] = 0;
        p[j] = 0;
        way[j] = 0;
    }
    for (size_t i = 1; i <= rows; i++) {
        p[0] = i;
        size_t j0 = 0;
        for (size_t j = 0; j <= cols; j++) {
            minv[j] = INFINITY;
            used[j] = false;
        }
        do {
            used[j0] = true;
            size_t i0 = p[j0], j1 = 0;
            double delta = INFINITY;
            const double *row = cost + (i0 - 1) * cols;
            for (size_t j = 1; j <= cols; j++) {
                if (used[j])
                    continue;
                double cur = row[j - 1] - u[i0] - v[j];
                if (cur < minv[j]) {
                    minv[j] = cur;
                    way[j] = j0;
                }
                if (minv[j] < delta) {
                    delta = minv[j];
                    j1 = j;
                }
            }
            for (size_t j = 0; j <= cols; j++) {
                if (used[j]) {
                    u[p[j]] += delta;
                    v[j] -= delta;
                } else {
                    minv[j] -= delta;
                }
            }
            j0 = j1;
        } while (p[j0] != 0);
        do { // flip the augmenting path
            size_t j1 = way[j0];
            p[j0] = p[j1];
            j0 = j1;
        } while (j0);
    }
    double total = 0;
    for (size_t j = 1; j <= cols; j++)
        if (p[j]) {
            ret_col[p[j] - 1] = j - 1;
            total += cost[(p[j] - 1) * cols + (j - 1)];
        }
    if (ret_total)
        *ret_total = total;
    return 0;
}
