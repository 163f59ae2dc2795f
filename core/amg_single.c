/* The single-precision copies the V-cycle reads (amg.h, wc_amg_opts.single): every level's operator
 * and prolongator rounded to float after a setup has computed them in double. Rounded entry by
 * entry, a symmetric operator stays exactly symmetric and the restriction stays the
 * prolongation's transpose, so the V-cycle is still one SPD operator applied symmetrically. The
 * block-diagonal inverses stay double: a few % of the bytes, and the scalar smoother loops that
 * read them cost more instructions in float than they save (docs/bench/cpu_levers_sheet32.md). */
#include "amg.h"

static void round_range(const double* d, float* f, size_t lo, size_t hi) {
    for (size_t k = lo; k < hi; ++k) f[k] = (float)d[k];
}

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>
#define WC_ROUND_AVX 1
/* The same 4 at a time (the same roundings: IEEE round to nearest either way). */
__attribute__((target("avx"))) static void round_range_avx(const double* d, float* f, size_t lo, size_t hi) {
    size_t k = lo;
    for (; k + 4 <= hi; k += 4) _mm_storeu_ps(f + k, _mm256_cvtpd_ps(_mm256_loadu_pd(d + k)));
    round_range(d, f, k, hi);
}
#endif

/* f = d rounded, n values, in blocks of 9 over the threads */
void wc_amg_round(const double* d, float* f, size_t n, wc_par* par) {
    void (*range)(const double*, float*, size_t, size_t) = round_range;
#ifdef WC_ROUND_AVX
    if (__builtin_cpu_supports("avx")) range = round_range_avx;
#endif
    WC_PAR_REGION(par)
    {
        int lo, hi;
        wc_par_range((int)((n + 8) / 9), wc_par_tid(), wc_par_nt(), &lo, &hi);
        size_t e = 9 * (size_t)hi < n ? 9 * (size_t)hi : n;
        if (9 * (size_t)lo < e) range(d, f, 9 * (size_t)lo, e);
    }
}

void wc_amg_single_copies(wc_amg* a, int fine_only, wc_par* par) {
    if (!a->opts.single || !a->opts.values) return;
    for (int l = 0; l < a->n_levels; ++l) {
        wc_amg_level* L = &a->lev[l];
        const int fresh = L->f_fresh; /* made by the float Galerkin products in this setup */
        L->f_fresh = 0;
        if (l == a->n_levels - 1 && a->coarse_dense) break; /* the dense factor is used instead */
        if (!(fresh & 1)) wc_amg_round(L->val, L->val_f, 9 * (size_t)L->n_blocks, par);
        if (fine_only) break;
        if (l + 1 < a->n_levels && !(fresh & 2)) wc_amg_round(L->p_val, L->p_val_f, 9 * (size_t)L->p_start[L->n], par);
    }
}
