/* test_util.h — the unit tests' shared floating-point checks (header only).
 * cmocka 1.1 compares integers only, so doubles need these. Each check fails
 * the test at the caller's file and line, printing the expression's text and
 * both values with %.17g. A NaN on either side fails every check.
 *
 * cmocka.h needs <stdarg.h>, <stddef.h>, <stdint.h> and <setjmp.h> included
 * before it; this header includes them, cmocka.h and <math.h> itself, so a
 * test may include just it, after its own headers. (Not to be confused with
 * test_util.c, the tests of common/cgs_util.) */
#ifndef TEST_UTIL_H
#define TEST_UTIL_H

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <math.h>

/* Absolute: fails unless |got - want| <= tol. */
#define assert_near(got, want, tol) test_util_near ((got), (want), (tol), #got, __FILE__, __LINE__)

/* Relative: fails unless |got - want| <= rel |want| (so want = 0 asks for got = 0). */
#define assert_rel(got, want, rel) test_util_rel ((got), (want), (rel), #got, __FILE__, __LINE__)

/* Angles in radians: fails unless got - want, wrapped to [-pi, pi], is within tol. */
#define assert_angle_rad(got, want, tol)                                                           \
    test_util_angle ((got), (want), 2.0 * M_PI, (tol), #got, __FILE__, __LINE__)

/* Angles in degrees: fails unless got - want, wrapped to [-180, 180], is within tol. */
#define assert_angle_deg(got, want, tol)                                                           \
    test_util_angle ((got), (want), 360.0, (tol), #got, __FILE__, __LINE__)

/* The check behind assert_near; expr is got's text, file and line the caller's. */
static inline void test_util_near (double got, double want, double tol, const char *expr,
                                   const char *file, int line)
{
    if (!(fabs (got - want) <= tol)) {
        print_error ("ERROR: %s = %.17g, want %.17g +- %g\n", expr, got, want, tol);
        _fail (file, line);
    }
}

/* The check behind assert_rel. */
static inline void test_util_rel (double got, double want, double rel, const char *expr,
                                  const char *file, int line)
{
    if (!(fabs (got - want) <= rel * fabs (want))) {
        print_error ("ERROR: %s = %.17g, want %.17g (relative error %.3g > %g)\n", expr, got, want,
                     fabs (got - want) / fabs (want), rel);
        _fail (file, line);
    }
}

/* The check behind the angle asserts: got - want wrapped to [-period/2, period/2]. */
static inline void test_util_angle (double got, double want, double period, double tol,
                                    const char *expr, const char *file, int line)
{
    double off = remainder (got - want, period);
    if (!(fabs (off) <= tol)) {
        print_error ("ERROR: %s = %.17g, want %.17g modulo %g (off by %.17g, +- %g)\n", expr, got,
                     want, period, off, tol);
        _fail (file, line);
    }
}

/* Componentwise absolute: fails unless |got[i] - want[i]| <= tol for each of
 * the n components. For a test's own vector types, wrapped in a macro that
 * copies the fields out once (see assert_v2_near in test_gd_geom.c). */
static inline void test_util_near_v (const double *got, const double *want, size_t n, double tol,
                                     const char *expr, const char *file, int line)
{
    size_t i = 0;
    while (i < n && fabs (got[i] - want[i]) <= tol)
        i++;
    if (i == n)
        return;
    print_error ("ERROR: %s = (", expr);
    for (i = 0; i < n; i++)
        print_error ("%s%.17g", i ? ", " : "", got[i]);
    print_error ("), want (");
    for (i = 0; i < n; i++)
        print_error ("%s%.17g", i ? ", " : "", want[i]);
    print_error (") +- %g\n", tol);
    _fail (file, line);
}

#endif
