/* trk_kbest — the k best assignments of a rectangular cost matrix (Murty's
 * method) and the marginal association probabilities they give.
 *
 * The tracker's clusters are assignment problems: rows are tracks, columns
 * are the cluster's hits and then one "no hit" column per track; a cost is
 * −2 ln of a likelihood ratio, so a whole assignment (a joint association
 * hypothesis) has probability ∝ exp(−total / 2). The best assignment is the
 * global nearest neighbour; the k best, weighed so, give each track the
 * probability of each of its hits and of none (JPDA's β, JIPDA's existence
 * evidence) without enumerating every hypothesis.
 *
 * Murty (1968), as in Cox and Miller (1995): the solution space is split
 * around each solution found, one subproblem per row, forbidding the row's
 * column there and forcing the rows before it; each subproblem is one
 * optimal assignment (trk_assign). Cost: up to k·rows assignment solves of
 * the cluster's size. Pure: no logging, no globals; workspace kept. */
#ifndef TRK_KBEST_H
#define TRK_KBEST_H

#include <stddef.h>

typedef struct trk_kbest trk_kbest_t;

/* A solver with empty workspace; NULL on allocation failure. */
trk_kbest_t *trk_kbest_new (void);
/* Free; accepts NULL, nulls the pointer. */
void trk_kbest_destroy (trk_kbest_t **self_p);

/* The up to k least-cost assignments of rows rows to distinct columns of
 * cost (rows × cols, rows <= cols, every entry finite), in increasing total;
 * an entry at or above forbidden may not be used (an assignment that needs
 * one is no solution). Returns the number found (0 when no assignment avoids
 * the forbidden entries), -EINVAL, -ENOMEM. Solution s is read with
 * trk_kbest_column (self, s, row) and trk_kbest_total (self, s); they stay
 * valid until the next solve. */
int trk_kbest_solve (trk_kbest_t *self, const double *cost, size_t rows, size_t cols, size_t k,
                     double forbidden);
size_t trk_kbest_column (const trk_kbest_t *self, size_t s, size_t row);
double trk_kbest_total (const trk_kbest_t *self, size_t s);

/* Marginals of the last solve's n solutions, each weighed exp(−total / 2)
 * and normalised over them: ret_beta[row * cols + col] is the probability
 * that row takes col (rows × cols, written whole). */
void trk_kbest_marginals (const trk_kbest_t *self, size_t n, size_t rows, size_t cols,
                          double *ret_beta);

#endif
