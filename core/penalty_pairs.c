/* Penalty pairs in the implicit system (penalty_pairs.h). */
#include "penalty_pairs.h"
#include <string.h>
#include "filter.h"
#include "model.h"
#include "vec3.h"

#define BLK (WC_PENALTY_MAX * WC_PENALTY_MAX)   /* block indices per pair of an in-pattern list */

int wc_penalty_pairs_init(wc_penalty_pairs* pp, int cap, int in_pattern, const wc_allocator* a) {
    memset(pp, 0, sizeof *pp);
    if (cap < 1) cap = 1;
    pp->term = WC_NEW(a, wc_coupling_term, (size_t)cap);
    pp->off = WC_NEW(a, double, (size_t)cap);
    pp->k = WC_NEW(a, double, (size_t)cap);
    pp->active = WC_NEW(a, unsigned char, (size_t)cap);
    if (in_pattern) pp->blk = WC_NEW(a, int, BLK * (size_t)cap);
    if (!pp->term || !pp->off || !pp->k || !pp->active || (in_pattern && !pp->blk)) {
        wc_penalty_pairs_free(pp, a);
        return 0;
    }
    pp->cap = cap;
    return 1;
}

void wc_penalty_pairs_free(wc_penalty_pairs* pp, const wc_allocator* a) {
    wc_free(a, pp->blk);
    wc_free(a, pp->active);
    wc_free(a, pp->k);
    wc_free(a, pp->off);
    wc_free(a, pp->term);
    memset(pp, 0, sizeof *pp);
}

void wc_penalty_pairs_clear(wc_penalty_pairs* pp) {
    pp->n = pp->overflow = pp->skipped = 0;
}

double wc_penalty_inv_mass(const wc_model* m, const wc_filter* f, const unsigned char* stick, int cnt, const int* p,
                           const double* w) {
    double inv = 0.0;
    for (int a = 0; a < cnt; ++a) {
        int i = p[a];
        int pinned = f && f->ndof[i] == 3 && !(stick && stick[i]);
        if (!pinned) inv += w[a] * w[a] * m->inv_mass[i];
    }
    return inv;
}

double wc_penalty_stiffness(double inv_mass, double he) {
    return WC_PENALTY_KAPPA / (inv_mass * he * he);
}

/* index of block (i, j) in the pattern, -1 when it has none */
static int find_block(const wc_bsr_pattern* pt, int i, int j) {
    int lo = pt->row_start[i], hi = pt->row_start[i + 1] - 1;
    while (lo <= hi) {
        int mid = (lo + hi) / 2, c = pt->col[mid];
        if (c == j) return mid;
        if (c < j) lo = mid + 1;
        else hi = mid - 1;
    }
    return -1;
}

void wc_penalty_pairs_set(wc_penalty_pairs* pp, int at, int cnt, const int* p, const double* w, const double* n,
                          double off, double k) {
    wc_coupling_term* t = &pp->term[at];
    t->cnt = cnt;
    for (int a = 0; a < WC_PENALTY_MAX; ++a) {
        t->p[a] = a < cnt ? p[a] : 0;
        t->w[a] = a < cnt ? w[a] : 0.0;
    }
    v3_copy(t->n, n);
    t->c = 0.0;
    pp->off[at] = off;
    pp->k[at] = k;
    pp->active[at] = 0;
}

int wc_penalty_pairs_add(wc_penalty_pairs* pp, const wc_bsr_pattern* pt, int cnt, const int* p, const double* w,
                         const double* n, double off, double k) {
    int blk[BLK];
    for (int q = 0; q < BLK; ++q) blk[q] = -1;
    if (pp->blk)
        for (int a = 0; a < cnt; ++a)
            for (int b = 0; b < cnt; ++b) {
                blk[WC_PENALTY_MAX * a + b] = find_block(pt, p[a], p[b]);
                if (blk[WC_PENALTY_MAX * a + b] < 0) {
                    ++pp->skipped;
                    return 0;
                }
            }
    if (pp->n >= pp->cap) {
        ++pp->overflow;
        return 0;
    }
    int at = pp->n++;
    wc_penalty_pairs_set(pp, at, cnt, p, w, n, off, k);
    if (pp->blk) memcpy(pp->blk + BLK * (size_t)at, blk, sizeof blk);
    return 1;
}

void wc_penalty_pairs_append(wc_penalty_pairs* dst, const wc_penalty_pairs* src) {
    dst->skipped += src->skipped;
    for (int j = 0; j < src->n; ++j) {
        if (dst->n >= dst->cap) {
            ++dst->overflow;
            continue;
        }
        int at = dst->n++;
        dst->term[at] = src->term[j];
        dst->off[at] = src->off[j];
        dst->k[at] = src->k[j];
        dst->active[at] = src->active[j];
        if (dst->blk && src->blk) memcpy(dst->blk + BLK * (size_t)at, src->blk + BLK * (size_t)j, BLK * sizeof(int));
    }
}

int wc_penalty_stages_init(wc_penalty_pairs** stage, int** resume, int threads, int cap, int in_pattern,
                           const wc_allocator* a) {
    *stage = WC_NEW(a, wc_penalty_pairs, (size_t)threads);
    *resume = WC_NEW(a, int, 2 * (size_t)threads);
    if (*stage && *resume) {
        int t = 0;
        while (t < threads && wc_penalty_pairs_init(&(*stage)[t], cap, in_pattern, a)) ++t;
        if (t == threads) return 1;
        wc_penalty_stages_free(stage, resume, t, a);
        return 0;
    }
    wc_penalty_stages_free(stage, resume, 0, a);
    return 0;
}

void wc_penalty_stages_free(wc_penalty_pairs** stage, int** resume, int threads, const wc_allocator* a) {
    if (*stage)
        for (int t = 0; t < threads; ++t) wc_penalty_pairs_free(&(*stage)[t], a);
    wc_free(a, *stage);
    wc_free(a, *resume);
    *stage = NULL;
    *resume = NULL;
}

/* n . sum w_a y_a */
static double along(const wc_coupling_term* t, const double* y) {
    double s = 0.0;
    for (int a = 0; a < t->cnt; ++a) s += t->w[a] * v3_dot(t->n, y + 3 * t->p[a]);
    return s;
}

/* sign x pair j's terms with the (linearised) gap g: b += sign he f_a, A += sign he^2 k w_a w_b
 * n n^T (a coupled list: the diagonal blocks, and the coupling coefficient to match); the pair
 * is active after a positive sign, inactive after a negative one. */
static void add_terms(wc_penalty_pairs* pp, const wc_model* m, int j, double sign, double g, double he, double* A,
                      double* b) {
    wc_coupling_term* t = &pp->term[j];
    const double k = pp->k[j];
    const int* blk = pp->blk ? pp->blk + BLK * (size_t)j : NULL;
    double nn[9];
    m3_outer(nn, t->n, t->n, 1.0);
    for (int a = 0; a < t->cnt; ++a) {
        v3_axpy(b + 3 * t->p[a], -sign * he * k * g * t->w[a], t->n);
        if (blk)
            for (int c = 0; c < t->cnt; ++c)
                m3_axpy(A + 9 * (size_t)blk[WC_PENALTY_MAX * a + c], sign * he * he * k * t->w[a] * t->w[c], nn);
        else
            m3_axpy(A + 9 * (size_t)m->pattern.diag[t->p[a]], sign * he * he * k * t->w[a] * t->w[a], nn);
    }
    t->c = sign > 0.0 ? he * he * k : 0.0;
    pp->active[j] = sign > 0.0;
}

/* the gap linearised for the first system: g(x_n) + he n . sum w v* (the w-dependent part is A's) */
static double gap_rhs(const wc_penalty_pairs* pp, int j, const double* x, const double* vstar, double he) {
    const wc_coupling_term* t = &pp->term[j];
    return along(t, x) - pp->off[j] + he * along(t, vstar);
}

int wc_penalty_pairs_assemble(wc_penalty_pairs* pp, const wc_model* m, const double* x, const double* vstar,
                              const double* f_ext, double he, double* A, double* b, double* f_total) {
    int active = 0;
    for (int j = 0; j < pp->n; ++j) {
        const wc_coupling_term* t = &pp->term[j];
        pp->term[j].c = 0.0;
        pp->active[j] = 0;
        double glin = gap_rhs(pp, j, x, vstar, he), g = glin;
        if (f_ext)
            for (int a = 0; a < t->cnt; ++a) {
                int i = t->p[a];
                g += he * he * t->w[a] * v3_dot(t->n, f_ext + 3 * i) * m->inv_mass[i];
            }
        if (!(g < 0.0)) continue;
        ++active;
        add_terms(pp, m, j, 1.0, glin, he, A, b);
        if (f_total) {
            double g0 = along(t, x) - pp->off[j];
            if (g0 < 0.0)
                for (int a = 0; a < t->cnt; ++a) v3_axpy(f_total + 3 * t->p[a], -pp->k[j] * g0 * t->w[a], t->n);
        }
    }
    return active;
}

int wc_penalty_pairs_recheck(wc_penalty_pairs* pp, const wc_model* m, const double* x, const double* vstar,
                             const double* dv, double he, double* A, double* b) {
    int changed = 0;
    for (int j = 0; j < pp->n; ++j) {
        double glin = gap_rhs(pp, j, x, vstar, he);
        int want = glin + he * along(&pp->term[j], dv) < 0.0;
        if (want == pp->active[j]) continue;
        add_terms(pp, m, j, want ? 1.0 : -1.0, glin, he, A, b);
        ++changed;
    }
    return changed;
}

double wc_penalty_pairs_energy(const wc_penalty_pairs* pp, const double* x) {
    double e = 0.0;
    for (int j = 0; j < pp->n; ++j) {
        double g = along(&pp->term[j], x) - pp->off[j];
        if (g < 0.0) e += 0.5 * pp->k[j] * g * g;
    }
    return e;
}

int wc_penalty_pairs_newton(wc_penalty_pairs* pp, const wc_model* m, const double* x, double he, double* A,
                            double* g_out) {
    int touching = 0;
    for (int j = 0; j < pp->n; ++j) {
        double g = along(&pp->term[j], x) - pp->off[j];
        pp->term[j].c = 0.0;
        pp->active[j] = 0;
        if (!(g < 0.0)) continue;
        ++touching;
        add_terms(pp, m, j, 1.0, g, he, A, g_out);   /* the exact gap at x: force and stiffness */
    }
    return touching;
}

double wc_penalty_pair_eval(const wc_penalty_pairs* pp, int j, const double* x, double* f, double* J) {
    const wc_coupling_term* t = &pp->term[j];
    double g = along(t, x) - pp->off[j], k = pp->k[j];
    int cnt = t->cnt;
    memset(f, 0, 3 * (size_t)cnt * sizeof(double));
    memset(J, 0, 9 * (size_t)cnt * cnt * sizeof(double));
    if (!(g < 0.0)) return 0.0;
    for (int a = 0; a < cnt; ++a) {
        v3_axpy(f + 3 * a, -k * g * t->w[a], t->n);
        for (int c = 0; c < cnt; ++c) m3_outer(J + 9 * (a * cnt + c), t->n, t->n, -k * t->w[a] * t->w[c]);
    }
    return 0.5 * k * g * g;
}
