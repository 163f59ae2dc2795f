#include "par.h"

void wc_par_init(wc_par* p, int threads) {
#ifdef _OPENMP
    if (threads <= 0) threads = omp_get_max_threads();
#else
    threads = 1;
#endif
    if (threads < 1) threads = 1;
    if (threads > WC_PAR_MAX_THREADS) threads = WC_PAR_MAX_THREADS;
    p->threads = threads;
    for (int i = 0; i < WC_PAR_MAX_THREADS * 8; ++i) p->partial[i] = 0.0;
}

double wc_par_dot(wc_par* p, const double* a, const double* b, int n) {
    int used = p->threads;
    WC_PAR_REGION(p)
    {
        int t = wc_par_tid(), nt = wc_par_nt(), lo, hi;
        if (t == 0) used = nt;
        wc_par_range(n, t, nt, &lo, &hi);
        double s = 0.0;
        for (int i = lo; i < hi; ++i) s += a[i] * b[i];
        p->partial[8 * t] = s;
    }
    double s = 0.0;
    for (int t = 0; t < used; ++t) s += p->partial[8 * t];
    return s;
}
