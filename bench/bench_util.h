/* Helpers shared by the benchmark programs. */
#ifndef BENCH_UTIL_H
#define BENCH_UTIL_H

#include <stdio.h>
#include <stdlib.h>

#include "sam/sam_common.h"

/* Prints "<program>: <what>: <message>" and exits with status 1. */
static inline void bench_die(const char *program, const char *what, const sam_error *err)
{
    fprintf(stderr, "%s: %s: %s\n", program, what, err ? err->message : "failed");
    exit(1);
}

/* qsort comparator for doubles, ascending. */
static inline int bench_cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

#endif
