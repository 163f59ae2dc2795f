/* Deterministic data-parallel helpers (OpenMP when built with it). Work is split into fixed
 * contiguous ranges by thread number, and reductions add the per-thread partial sums in thread
 * order, so the same inputs and thread count give bit-identical results. */
#ifndef WEFT_CORE_PAR_H
#define WEFT_CORE_PAR_H

#define WC_PAR_MAX_THREADS 64

typedef struct wc_par {
    int threads;                                /* >= 1 */
    double partial[WC_PAR_MAX_THREADS * 8];     /* per-thread partial sums, 64 bytes apart */
} wc_par;

/* threads <= 0: OpenMP's default (1 without OpenMP); clamped to [1, WC_PAR_MAX_THREADS]. */
void wc_par_init(wc_par* p, int threads);
/* The contiguous range [*lo, *hi) of n items that thread t of nt owns. */
static inline void wc_par_range(int n, int t, int nt, int* lo, int* hi) {
    long long a = (long long)n * t / nt, b = (long long)n * (t + 1) / nt;
    *lo = (int)a;
    *hi = (int)b;
}
/* sum_i a[i] * b[i], i < n. */
double wc_par_dot(wc_par* p, const double* a, const double* b, int n);

#ifdef _OPENMP
#include <omp.h>
/* Open a parallel region over p's threads (put a block after it); inside, wc_par_tid() and
 * wc_par_nt() give the thread and the team size. */
#define WC_PAR_PRAGMA_(x) _Pragma(#x)
#define WC_PAR_REGION(p) WC_PAR_PRAGMA_(omp parallel num_threads((p)->threads))
/* Inside a region (or a function it calls): wait until every thread of the team got here. Half a
 * region's fork and join: a kernel sequence that runs in one region with barriers between its
 * phases pays less than one region per phase. */
#define WC_PAR_BARRIER() WC_PAR_PRAGMA_(omp barrier)
/* Inside a region: the next for loop's iterations shared among the team in chunks of c, each
 * chunk to the next free thread (then a barrier). Only for loops whose iterations each write
 * their own results: who runs an iteration then changes no bit (load balance for uneven work). */
#define WC_PAR_FOR_DYNAMIC(c) WC_PAR_PRAGMA_(omp for schedule(dynamic, c))
static inline int wc_par_tid(void) { return omp_get_thread_num(); }
static inline int wc_par_nt(void) { return omp_get_num_threads(); }
#else
#define WC_PAR_FOR_DYNAMIC(c)
#define WC_PAR_REGION(p) (void)(p);
#define WC_PAR_BARRIER() ((void)0)
static inline int wc_par_tid(void) { return 0; }
static inline int wc_par_nt(void) { return 1; }
#endif

#endif
