/*
 * timing.c - the benchmarks' clocks, their summaries and the plain-read baseline (bench.h). Thread
 * CPU time for ratios (a shared machine's other jobs do not enter it), the monotonic clock for wall
 * time.
 */
#include <stdlib.h>
#include <string.h>
#include <time.h>
#ifdef __GLIBC__
#include <malloc.h> /* mallopt */
#endif

#include "bench/bench.h"
#include "demo/demo.h"

/* the wall clock and the median are the demo library's (libqibl-tools, below this one) */
double qtool_bench_now(void)
{
    return qtool_demo_now();
}

void qtool_bench_fresh_arrays(void)
{
#if defined(__GLIBC__) && defined(M_MMAP_THRESHOLD)
    (void)mallopt(M_MMAP_THRESHOLD, 128 * 1024); /* glibc's default, no longer raised by a free */
#endif
}

double qtool_bench_cpu_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

double qtool_bench_median(double *v, int n)
{
    return qtool_demo_median(v, n);
}

double qtool_bench_paired_ratio(const double *num, const double *den, int n)
{
    double r[64];
    n = n > 64 ? 64 : n;
    for (int i = 0; i < n; ++i)
        r[i] = num[i] / den[i];
    return n > 0 ? qtool_bench_median(r, n) : 0.0;
}

uint64_t qtool_bench_read_u64(const uint8_t *p, size_t n)
{
    uint64_t acc = 0;
    for (size_t i = 0; i + 8 <= n; i += 8) {
        uint64_t w;
        memcpy(&w, p + i, 8);
        acc += w;
    }
    return acc;
}

double qtool_bench_min(const double *v, int n)
{
    double m = v[0];
    for (int i = 1; i < n; ++i)
        m = v[i] < m ? v[i] : m;
    return m;
}

int qtool_bench_failed;
