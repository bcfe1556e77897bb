/* trk_assign — optimal (minimum total cost) assignment of the rows of a
 * rectangular cost matrix to distinct columns: the Hungarian method in its
 * shortest-augmenting-path form with dual potentials, O(rows² · cols). The
 * tracker calls it once per cluster of tracks and hits that share gates, so
 * the association is the global nearest neighbour, not greedy. Workspace is
 * kept between calls. Pure: no logging, no globals. */
#ifndef TRK_ASSIGN_H
#define TRK_ASSIGN_H

#include <stddef.h>

typedef struct trk_assign trk_assign_t;

/* A solver with empty workspace; NULL on allocation failure. */
trk_assign_t *trk_assign_new (void);
/* Free; accepts NULL, nulls the pointer. */
void trk_assign_destroy (trk_assign_t **self_p);

/* Assign each of rows rows to a distinct one of cols columns (rows <= cols)
 * so that the sum of cost[row * cols + col] is least; every cost must be
 * finite (use a large value for a forbidden pair and check the result).
 * ret_col[row] is the chosen column; *ret_total (may be NULL) the sum.
 * 0, -EINVAL when rows > cols or a cost is not finite, -ENOMEM. */
int trk_assign_solve (trk_assign_t *self, const double *cost, size_t rows, size_t cols,
                      size_t *ret_col, double *ret_total);

#endif
