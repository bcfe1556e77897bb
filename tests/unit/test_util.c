/* test_util — the small shared helpers: whole-number parsing and the
 * splitmix64 generator. */
#include "cgs_util.h"

#include <errno.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>

#include <cmocka.h>

static void test_parse_u64 (void **state)
{
    (void)state;
    uint64_t v = 42;
    assert_int_equal (cgs_parse_u64 ("0", 10, &v), 0);
    assert_true (v == 0);
    assert_int_equal (cgs_parse_u64 ("17", 17, &v), 0);
    assert_true (v == 17);
    assert_int_equal (cgs_parse_u64 ("18446744073709551615", UINT64_MAX, &v), 0);
    assert_true (v == UINT64_MAX);
    v = 42;
    // Refused, and *ret left as it was.
    const char *bad[] = {
        "", " 7", "+5", "-1", "1e3", "0x10", "7 ", "2.5", "18", "18446744073709551616", NULL};
    for (int i = 0; bad[i]; i++) {
        assert_int_equal (cgs_parse_u64 (bad[i], 17, &v), -EINVAL);
        assert_true (v == 42);
    }
    assert_int_equal (cgs_parse_u64 (NULL, 17, &v), -EINVAL);
}

/* The reference sequence of splitmix64 from state 0 (Vigna's splitmix64.c):
 * 0xe220a8397b1dcdaf, 0x6e789e6aa1b965f4, 0x06c45d188009454f. */
static void test_splitmix64 (void **state)
{
    (void)state;
    uint64_t s = 0;
    assert_true (cgs_splitmix64 (&s) == 0xe220a8397b1dcdafull);
    assert_true (cgs_splitmix64 (&s) == 0x6e789e6aa1b965f4ull);
    assert_true (cgs_splitmix64 (&s) == 0x06c45d188009454full);
    // Uniforms lie strictly inside (0, 1) and average 1/2 (σ of the mean of
    // 100,000 is 0.0009).
    s = 7;
    double sum = 0;
    for (int i = 0; i < 100000; i++) {
        double u = cgs_uniform01 (&s);
        assert_true (u > 0 && u < 1);
        sum += u;
    }
    assert_true (sum / 100000 > 0.5 - 0.004 && sum / 100000 < 0.5 + 0.004);
}

/* cgs_grow: 16 to start, doubled until the need fits, kept when it does;
 * the elements already there survive; a size that would overflow is
 * refused with the array untouched. */
static void test_grow (void **state)
{
    (void)state;
    int *a = NULL;
    size_t cap = 0;
    assert_int_equal (cgs_grow ((void **)&a, &cap, 1, sizeof *a), 0);
    assert_non_null (a);
    assert_int_equal (cap, 16);
    for (int i = 0; i < 16; i++)
        a[i] = i;
    assert_int_equal (cgs_grow ((void **)&a, &cap, 100, sizeof *a), 0);
    assert_int_equal (cap, 128);
    for (int i = 0; i < 16; i++)
        assert_int_equal (a[i], i);
    int *before = a;
    assert_int_equal (cgs_grow ((void **)&a, &cap, 128, sizeof *a), 0);
    assert_ptr_equal (a, before);
    assert_int_equal (cap, 128);
    assert_int_equal (cgs_grow ((void **)&a, &cap, SIZE_MAX / 2, sizeof *a), -ENOMEM);
    assert_int_equal (cgs_grow ((void **)&a, &cap, SIZE_MAX, 1), -ENOMEM);
    assert_ptr_equal (a, before);
    assert_int_equal (cap, 128);
    free (a);
}

int main (void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test (test_parse_u64),
        cmocka_unit_test (test_splitmix64),
        cmocka_unit_test (test_grow),
    };
    return cmocka_run_group_tests (tests, NULL, NULL);
}
