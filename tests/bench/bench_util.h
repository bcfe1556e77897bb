/* bench_util — the timing helpers every benchmark uses: CPU and wall-clock
 * time in seconds, the median of a sample, and option numbers. Header-only (benchmarks are
 * single files). */
#ifndef BENCH_UTIL_H
#define BENCH_UTIL_H

#include <stdlib.h>
#include <errno.h>
#include <stdbool.h>
#include <time.h>

/* CPU time of this process, seconds. */
/* A whole number in [min, max] from an option's text; false (nothing
 * written) when it is not one. */
static inline bool bench_parse_long (const char *s, long min, long max, long *ret)
{
    char *end = NULL;
    errno = 0;
    long v = s ? strtol (s, &end, 10) : 0;
    if (!s || errno || end == s || *end || v < min || v > max)
        return false;
    *ret = v;
    return true;
}

static inline double bench_cpu_s (void)
{
    struct timespec ts;
    clock_gettime (CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + ts.tv_nsec * 1e-9;
}

/* Monotonic wall-clock time, seconds. */
static inline double bench_wall_s (void)
{
    struct timespec ts;
    clock_gettime (CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + ts.tv_nsec * 1e-9;
}

static inline int bench_cmp_double (const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

/* The median of v[0..n) (n > 0); sorts v. */
static inline double bench_median (double *v, int n)
{
    qsort (v, (size_t)n, sizeof *v, bench_cmp_double);
    return n % 2 ? v[n / 2] : (v[n / 2 - 1] + v[n / 2]) / 2;
}

#endif
