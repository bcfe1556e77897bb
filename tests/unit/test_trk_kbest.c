/* Murty's k best assignments (trk_kbest) against exhaustive enumeration,
 * and the association probabilities of a two-track, two-hit crossing
 * against the seven joint hypotheses worked by hand. */
#include "trk_kbest.h"

#include <errno.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "test_util.h"

#define S_FORBID 1e9

static uint64_t s_rng = 99;
static double s_uniform (void)
{
    s_rng = s_rng * 6364136223846793005ull + 1442695040888963407ull;
    return (double)(s_rng >> 11) / 9007199254740992.0;
}

/* Every assignment of rows to distinct columns avoiding forbidden entries:
 * totals[] (unsorted), the count returned. */
static size_t s_enumerate (const double *c, size_t rows, size_t cols, size_t row, bool *used,
                           double sum, double *totals, size_t n)
{
    if (row == rows) {
        totals[n] = sum;
        return n + 1;
    }
    for (size_t j = 0; j < cols; j++) {
        if (used[j] || c[row * cols + j] >= S_FORBID)
            continue;
        used[j] = true;
        n = s_enumerate (c, rows, cols, row + 1, used, sum + c[row * cols + j], totals, n);
        used[j] = false;
    }
    return n;
}

static int s_cmp_double (const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

/* Random matrices up to 5 × 9, a fifth of the entries forbidden: the k
 * best totals are the k least of every assignment, each solution is an
 * assignment of distinct allowed columns with the total it states, and no
 * solution comes twice. */
static void test_kbest_against_enumeration (void **state)
{
    (void)state;
    trk_kbest_t *kb = trk_kbest_new ();
    assert_non_null (kb);
    double c[5 * 9], totals[20000];
    bool used[9];
    size_t checked = 0;
    for (int trial = 0; trial < 300; trial++) {
        size_t rows = 1 + (size_t)(s_uniform () * 5), cols = rows + (size_t)(s_uniform () * 5);
        for (size_t i = 0; i < rows * cols; i++)
            c[i] = s_uniform () < 0.2 ? S_FORBID : floor (s_uniform () * 40) / 4; // ties too
        memset (used, 0, sizeof used);
        size_t all = s_enumerate (c, rows, cols, 0, used, 0, totals, 0);
        qsort (totals, all, sizeof *totals, s_cmp_double);
        size_t k = 1 + (size_t)(s_uniform () * 30);
        int n = trk_kbest_solve (kb, c, rows, cols, k, S_FORBID);
        assert_int_equal (n, all < k ? all : k);
        for (int s = 0; s < n; s++) {
            assert_near (trk_kbest_total (kb, (size_t)s), totals[s], 1e-9);
            double sum = 0;
            bool taken[9] = {false};
            for (size_t r = 0; r < rows; r++) {
                size_t j = trk_kbest_column (kb, (size_t)s, r);
                assert_true (j < cols);
                assert_false (taken[j]);
                taken[j] = true;
                assert_true (c[r * cols + j] < S_FORBID);
                sum += c[r * cols + j];
            }
            assert_near (sum, trk_kbest_total (kb, (size_t)s), 1e-9);
            for (int s2 = 0; s2 < s; s2++) {
                bool same = true;
                for (size_t r = 0; r < rows && same; r++)
                    same =
                        trk_kbest_column (kb, (size_t)s, r) == trk_kbest_column (kb, (size_t)s2, r);
                assert_false (same);
            }
        }
        checked += (size_t)n;
    }
    print_message ("# %zu solutions checked against enumeration\n", checked);
    // Errors: more rows than columns, a cost not finite; nothing feasible.
    double bad[2] = {1, NAN};
    assert_int_equal (trk_kbest_solve (kb, bad, 2, 1, 3, S_FORBID), -EINVAL);
    assert_int_equal (trk_kbest_solve (kb, bad, 1, 2, 3, S_FORBID), -EINVAL);
    double none[2] = {S_FORBID, S_FORBID};
    assert_int_equal (trk_kbest_solve (kb, none, 1, 2, 3, S_FORBID), 0);
    trk_kbest_destroy (&kb);
    assert_null (kb);
    trk_kbest_destroy (&kb);
}

/* Two tracks crossing, two hits between them. Columns: hit 1, hit 2,
 * "no hit" of track 1, "no hit" of track 2 (the other track's forbidden).
 * Costs −2 ln of likelihood ratios: track 1 is nearer hit 1 (1.0) than hit
 * 2 (3.0), track 2 a little nearer hit 2 (1.5) than hit 1 (2.0); leaving a
 * track without a hit costs 4.0. The seven joint hypotheses and their
 * totals, by hand:
 *   {1→h1, 2→h2} 2.5   {1→h2, 2→h1} 5.0   {1→h1, 2→∅} 5.0
 *   {1→∅, 2→h2} 5.5    {1→∅, 2→h1} 6.0    {1→h2, 2→∅} 7.0   {∅, ∅} 8.0
 * each weighed exp(−total/2). */
static void test_crossing_hypotheses (void **state)
{
    (void)state;
    const double F = S_FORBID;
    const double c[2 * 4] = {1.0, 3.0, 4.0, F, 2.0, 1.5, F, 4.0};
    trk_kbest_t *kb = trk_kbest_new ();
    int n = trk_kbest_solve (kb, c, 2, 4, 16, F);
    assert_int_equal (n, 7);
    const double want[7] = {2.5, 5.0, 5.0, 5.5, 6.0, 7.0, 8.0};
    for (int s = 0; s < 7; s++)
        assert_near (trk_kbest_total (kb, (size_t)s), want[s], 1e-12);
    // The best is the global nearest neighbour.
    assert_int_equal (trk_kbest_column (kb, 0, 0), 0);
    assert_int_equal (trk_kbest_column (kb, 0, 1), 1);
    double w[7], sum = 0;
    for (int s = 0; s < 7; s++)
        sum += w[s] = exp (-want[s] / 2);
    double beta[8];
    trk_kbest_marginals (kb, (size_t)n, 2, 4, beta);
    // Track 1: hit 1 in {1→h1,2→h2}, {1→h1,2→∅}; hit 2 in {1→h2,2→h1},
    // {1→h2,2→∅}; none in {1→∅,2→h2}, {1→∅,2→h1}, {∅,∅}.
    assert_near (beta[0], (w[0] + w[2]) / sum, 1e-12);
    assert_near (beta[1], (w[1] + w[5]) / sum, 1e-12);
    assert_near (beta[2], (w[3] + w[4] + w[6]) / sum, 1e-12);
    assert_near (beta[3], 0, 0);
    // Track 2: hit 1 in {1→h2,2→h1}, {1→∅,2→h1}; hit 2 in the best and
    // {1→∅,2→h2}; none in the rest.
    assert_near (beta[4], (w[1] + w[4]) / sum, 1e-12);
    assert_near (beta[5], (w[0] + w[3]) / sum, 1e-12);
    assert_near (beta[7], (w[2] + w[5] + w[6]) / sum, 1e-12);
    for (int r = 0; r < 2; r++)
        assert_near (beta[r * 4] + beta[r * 4 + 1] + beta[r * 4 + 2] + beta[r * 4 + 3], 1, 1e-12);
    // The best three alone: renormalised over them.
    trk_kbest_marginals (kb, 3, 2, 4, beta);
    double s3 = w[0] + w[1] + w[2];
    assert_near (beta[0], (w[0] + w[2]) / s3, 1e-12);
    assert_near (beta[7], w[2] / s3, 1e-12);
    // k = 1: the best alone, certain.
    assert_int_equal (trk_kbest_solve (kb, c, 2, 4, 1, F), 1);
    trk_kbest_marginals (kb, 1, 2, 4, beta);
    assert_near (beta[0], 1, 0);
    assert_near (beta[5], 1, 0);
    assert_near (beta[2], 0, 0);
    trk_kbest_destroy (&kb);
}

int main (void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test (test_kbest_against_enumeration),
        cmocka_unit_test (test_crossing_hypotheses),
    };
    return cmocka_run_group_tests (tests, NULL, NULL);
}
