#include "bsr.h"
#include "bsr_rows.h"
#include <string.h>
#include "model.h"
#include "sort.h"
#include "vec3.h"

void wc_bsr_pattern_free(wc_bsr_pattern* p, const wc_allocator* a) {
    if (!p) return;
    wc_free(a, p->row_start);
    wc_free(a, p->col);
    wc_free(a, p->diag);
    wc_free(a, p->transpose);
    wc_free(a, p->row_spring_start);
    wc_free(a, p->row_spring);
    wc_free(a, p->row_spring_block);
    wc_free(a, p->row_spring_sign);
    wc_free(a, p->row_tri_start);
    wc_free(a, p->row_tri);
    memset(p, 0, sizeof *p);
}

int wc_bsr_pattern_build(wc_bsr_pattern* p, const wc_model* m, const wc_allocator* a) {
    memset(p, 0, sizeof *p);
    int n = m->n_particles, ns = m->n_springs, nt = m->n_tris;
    p->n_rows = n;
    p->row_start = WC_NEW(a, int, n + 1);
    p->diag = WC_NEW(a, int, n);
    p->row_spring_start = WC_NEW(a, int, n + 1);
    p->row_tri_start = WC_NEW(a, int, n + 1);
    wc_keyed* keys = WC_NEW(a, wc_keyed, 2 * (size_t)ns + 1);
    int* fill = WC_NEW(a, int, n + 1);
    int* blk = WC_NEW(a, int, 2 * (size_t)ns + 1); /* block of each directed spring end 2s (a,b), 2s+1 (b,a) */
    if (ns > 0) {
        p->row_spring = WC_NEW(a, int, 2 * ns);
        p->row_spring_block = WC_NEW(a, int, 2 * ns);
        p->row_spring_sign = WC_NEW(a, signed char, 2 * ns);
    }
    if (nt > 0) p->row_tri = WC_NEW(a, int, 3 * nt);
    if (!p->row_start || !p->diag || !p->row_spring_start || !p->row_tri_start || !keys || !fill || !blk ||
        (ns > 0 && (!p->row_spring || !p->row_spring_block || !p->row_spring_sign)) || (nt > 0 && !p->row_tri))
        goto oom;

    /* distinct (row, col) pairs: sort the 2 ns directed spring ends by (row, col) */
    int bits = wc_bits_for((unsigned)n);
    for (int s = 0; s < ns; ++s) {
        int i = m->springs[s].a, j = m->springs[s].b;
        keys[2 * s].key = ((uint64_t)i << bits) | (uint64_t)j;
        keys[2 * s].val = 2 * s;
        keys[2 * s + 1].key = ((uint64_t)j << bits) | (uint64_t)i;
        keys[2 * s + 1].val = 2 * s + 1;
    }
    if (!wc_radix_sort(keys, 2 * ns, 2 * bits, a)) goto oom;
    /* count distinct off-diagonal columns per row */
    int nb = n;
    for (int k = 0; k < 2 * ns; ++k) {
        if (k > 0 && keys[k].key == keys[k - 1].key) continue;
        ++p->row_start[(int)(keys[k].key >> bits) + 1];
        ++nb;
    }
    for (int i = 0; i < n; ++i) p->row_start[i + 1] += p->row_start[i] + 1;
    p->n_blocks = nb;
    p->col = WC_NEW(a, int, nb);
    p->transpose = WC_NEW(a, int, nb);
    if (!p->col || !p->transpose) goto oom;
    /* fill columns in ascending order, inserting the diagonal in place; remember each directed
       spring end's block */
    for (int i = 0; i < n; ++i) fill[i] = p->row_start[i];
    int k = 0;
    for (int i = 0; i < n; ++i) {
        int diag_done = 0;
        while (k < 2 * ns && (int)(keys[k].key >> bits) == i) {
            int j = (int)(keys[k].key & (((uint64_t)1 << bits) - 1));
            if (!diag_done && j > i) {
                p->diag[i] = fill[i];
                p->col[fill[i]++] = i;
                diag_done = 1;
            }
            if (!(k > 0 && keys[k].key == keys[k - 1].key)) p->col[fill[i]++] = j;
            blk[keys[k].val] = fill[i] - 1;
            ++k;
        }
        if (!diag_done) {
            p->diag[i] = fill[i];
            p->col[fill[i]++] = i;
        }
    }
    for (int i = 0; i < n; ++i) p->transpose[p->diag[i]] = p->diag[i];
    for (int e = 0; e < 2 * ns; ++e) p->transpose[blk[e]] = blk[e ^ 1];

    /* springs per row, in spring order */
    for (int s = 0; s < ns; ++s) {
        ++p->row_spring_start[m->springs[s].a + 1];
        ++p->row_spring_start[m->springs[s].b + 1];
    }
    for (int i = 0; i < n; ++i) p->row_spring_start[i + 1] += p->row_spring_start[i];
    for (int i = 0; i < n; ++i) fill[i] = p->row_spring_start[i];
    for (int s = 0; s < ns; ++s) {
        int ki = fill[m->springs[s].a]++, kj = fill[m->springs[s].b]++;
        p->row_spring[ki] = s;
        p->row_spring_block[ki] = blk[2 * s];
        p->row_spring_sign[ki] = 1;
        p->row_spring[kj] = s;
        p->row_spring_block[kj] = blk[2 * s + 1];
        p->row_spring_sign[kj] = -1;
    }

    /* triangles per particle, in triangle order */
    for (int t = 0; t < 3 * nt; ++t) ++p->row_tri_start[m->tris[t] + 1];
    for (int i = 0; i < n; ++i) p->row_tri_start[i + 1] += p->row_tri_start[i];
    for (int i = 0; i < n; ++i) fill[i] = p->row_tri_start[i];
    for (int t = 0; t < 3 * nt; ++t) p->row_tri[fill[m->tris[t]]++] = t / 3;

    wc_free(a, keys);
    wc_free(a, fill);
    wc_free(a, blk);
    return 0;
oom:
    wc_free(a, keys);
    wc_free(a, fill);
    wc_free(a, blk);
    wc_bsr_pattern_free(p, a);
    return -1;
}

void wc_bsr_mul(const wc_bsr_pattern* p, const double* val, const double* x, double* y, wc_par* par) {
    WC_PAR_REGION(par)
    {
        int lo, hi;
        wc_par_range(p->n_rows, wc_par_tid(), wc_par_nt(), &lo, &hi);
        wc_bsr_rows(p->row_start, p->col, val, lo, hi, NULL, 1.0, x, y);
    }
}

void wc_bsr_residual(const wc_bsr_pattern* p, const double* val, const double* b, const double* x, double* y,
                     wc_par* par) {
    WC_PAR_REGION(par)
    {
        int lo, hi;
        wc_par_range(p->n_rows, wc_par_tid(), wc_par_nt(), &lo, &hi);
        wc_bsr_rows(p->row_start, p->col, val, lo, hi, b, -1.0, x, y);
    }
}
