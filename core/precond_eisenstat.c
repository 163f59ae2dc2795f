/* D-ILU with Eisenstat's trick on the projected matrix (precond_eisenstat.h). */
#include <math.h>
#include <string.h>
#include "precond_eisenstat.h"
#include "solve_kernels.h"
#include "vec3.h"

wc_status wcs_eis_create(wcs_eis** out, const wc_bsr_pattern* p, const wc_allocator* a) {
    *out = NULL;
    wcs_eis* e = WC_NEW(a, wcs_eis, 1);
    if (!e) return WC_ERROR_OUT_OF_MEMORY;
    e->p = p;
    const size_t n = (size_t)p->n_rows;
    e->F = WC_NEW(a, double, 9 * (size_t)p->n_blocks);
    e->Dt = WC_NEW(a, double, 9 * n);
    e->Ci = WC_NEW(a, double, 9 * n);
    e->y = WC_NEW(a, double, 3 * n);
    e->dv0 = WC_NEW(a, double, 3 * n);
    if (!e->F || !e->Dt || !e->Ci || !e->y || !e->dv0) {
        wcs_eis_destroy(e, a);
        return WC_ERROR_OUT_OF_MEMORY;
    }
    *out = e;
    return WC_OK;
}

void wcs_eis_destroy(wcs_eis* e, const wc_allocator* a) {
    if (!e) return;
    wc_free(a, e->F);
    wc_free(a, e->Dt);
    wc_free(a, e->Ci);
    wc_free(a, e->y);
    wc_free(a, e->dv0);
    wc_free(a, e);
}

/* Ci = C^{-1} with D = C C^T (D symmetrised first), lower triangular: 0 when a pivot is not
 * above 1e-12 x ref's diagonal or not finite. */
static int chol_inverse(const double* D, const double* ref, double* Ci) {
    const double tol = 1e-12;
    const double a01 = 0.5 * (D[1] + D[3]), a02 = 0.5 * (D[2] + D[6]), a12 = 0.5 * (D[5] + D[7]);
    const double d0 = D[0];
    if (!(d0 > tol * fabs(ref[0])) || !isfinite(d0)) return 0;
    const double c00 = sqrt(d0), c10 = a01 / c00, c20 = a02 / c00;
    const double d1 = D[4] - c10 * c10;
    if (!(d1 > tol * fabs(ref[4])) || !isfinite(d1)) return 0;
    const double c11 = sqrt(d1), c21 = (a12 - c20 * c10) / c11;
    const double d2 = D[8] - c20 * c20 - c21 * c21;
    if (!(d2 > tol * fabs(ref[8])) || !isfinite(d2)) return 0;
    const double c22 = sqrt(d2);
    /* inverse of the lower triangle [c00 0 0; c10 c11 0; c20 c21 c22] */
    const double i00 = 1.0 / c00, i11 = 1.0 / c11, i22 = 1.0 / c22;
    const double i10 = -c10 * i00 * i11, i21 = -c21 * i11 * i22;
    const double i20 = -(c20 * i00 + c21 * i10) * i22;
    Ci[0] = i00, Ci[1] = 0.0, Ci[2] = 0.0;
    Ci[3] = i10, Ci[4] = i11, Ci[5] = 0.0;
    Ci[6] = i20, Ci[7] = i21, Ci[8] = i22;
    return 1;
}

/* o = a b^T (o may not alias a or b) */
static inline void m3_mul_bt(double* o, const double* a, const double* b) {
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            o[3 * i + j] = a[3 * i] * b[3 * j] + a[3 * i + 1] * b[3 * j + 1] + a[3 * i + 2] * b[3 * j + 2];
}

/* D~ by the mode (F holds P's blocks): 1 when every C_i is found. */
static int diagonal(wcs_eis* e, int mode) {
    const wc_bsr_pattern* p = e->p;
    const int* rs = p->row_start;
    const int* col = p->col;
    for (int i = 0; i < p->n_rows; ++i) {
        const double* Pii = e->F + 9 * (size_t)p->diag[i];
        double* D = e->Dt + 9 * (size_t)i;
        memcpy(D, Pii, 9 * sizeof(double));
        if (mode == 0)
            for (int b = rs[i]; b < p->diag[i]; ++b) { /* D~_i -= P_ik D~_k^{-1} P_ik^T */
                const int k = col[b];
                const double* Pik = e->F + 9 * (size_t)b;
                const double* Ck = e->Ci + 9 * (size_t)k;
                double G[9], H[9];
                m3_mul_bt(G, Pik, Ck); /* P_ik C_k^{-T} */
                m3_mul_bt(H, G, G);    /* P_ik D~_k^{-1} P_ik^T */
                for (int q = 0; q < 9; ++q) D[q] -= H[q];
            }
        if (!chol_inverse(D, Pii, e->Ci + 9 * (size_t)i)) return 0;
    }
    return 1;
}

int wcs_eis_setup(wcs_eis* e, const double* A, const wc_filter* f) {
    const wc_bsr_pattern* p = e->p;
    const int* rs = p->row_start;
    const int* col = p->col;
    ++e->setups;
    e->gs = 0;
    for (int i = 0; i < p->n_rows; ++i)
        for (int b = rs[i]; b < rs[i + 1]; ++b)
            wcs_project_block(f, i, col[b], A + 9 * (size_t)b, e->F + 9 * (size_t)b);
    if (!diagonal(e, e->mode)) {
        if (e->mode != 0 || !diagonal(e, 1)) return 0;
        e->gs = 1;
        ++e->fallbacks;
    }
    /* scale: lower blocks C_i^{-1} P_ik C_k^{-T}, the upper their transposes, the diagonal K~ */
    for (int i = 0; i < p->n_rows; ++i) {
        const double* Ci = e->Ci + 9 * (size_t)i;
        double G[9];
        for (int b = rs[i]; b < p->diag[i]; ++b) {
            double* B = e->F + 9 * (size_t)b;
            m3_mul(G, Ci, B);
            m3_mul_bt(B, G, e->Ci + 9 * (size_t)col[b]);
            double* U = e->F + 9 * (size_t)p->transpose[b];
            for (int r = 0; r < 3; ++r)
                for (int c = 0; c < 3; ++c) U[3 * c + r] = B[3 * r + c];
        }
        double* K = e->F + 9 * (size_t)p->diag[i];
        m3_mul(G, Ci, K);
        m3_mul_bt(K, G, Ci);
        K[0] -= 2.0, K[4] -= 2.0, K[8] -= 2.0;
        K[1] = K[3] = 0.5 * (K[1] + K[3]); /* symmetric to rounding: make it exactly so */
        K[2] = K[6] = 0.5 * (K[2] + K[6]);
        K[5] = K[7] = 0.5 * (K[5] + K[7]);
    }
    return 1;
}

/* o_i = s_i - sum over blocks [k0, k1) of F_k x_col(k) */
static inline void row_sub(const double* F, const int* col, int k0, int k1, const double* x, const double* s,
                           double* o) {
    double a0 = s[0], a1 = s[1], a2 = s[2];
    for (int k = k0; k < k1; ++k) {
        const double* B = F + 9 * (size_t)k;
        const double* v = x + 3 * (size_t)col[k];
        a0 -= B[0] * v[0] + B[1] * v[1] + B[2] * v[2];
        a1 -= B[3] * v[0] + B[4] * v[1] + B[5] * v[2];
        a2 -= B[6] * v[0] + B[7] * v[1] + B[8] * v[2];
    }
    o[0] = a0, o[1] = a1, o[2] = a2;
}

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>
/* The row's sum over blocks [k0, k1) of F_k x_col(k) in lanes 0..2 (lane 3 zero): precond_ic.c's
 * row kernel (a block row per register, FMA per lane, the lanes folded pairwise). */
__attribute__((target("avx2,fma"))) static inline __m256d row_sum(const double* F, const int* col, int k0, int k1,
                                                                   const double* x, __m256i m3) {
    __m256d a0 = _mm256_setzero_pd(), a1 = _mm256_setzero_pd(), a2 = _mm256_setzero_pd();
    for (int k = k0; k < k1; ++k) {
        const double* B = F + 9 * (size_t)k;
        const __m256d v = _mm256_maskload_pd(x + 3 * (size_t)col[k], m3);
        a0 = _mm256_fmadd_pd(_mm256_loadu_pd(B), v, a0);
        a1 = _mm256_fmadd_pd(_mm256_loadu_pd(B + 3), v, a1);
        a2 = _mm256_fmadd_pd(_mm256_maskload_pd(B + 6, m3), v, a2);
    }
    const __m256d h01 = _mm256_hadd_pd(a0, a1);
    const __m256d h2 = _mm256_hadd_pd(a2, _mm256_setzero_pd());
    return _mm256_add_pd(_mm256_permute2f128_pd(h01, h2, 0x20), _mm256_permute2f128_pd(h01, h2, 0x31));
}

/* wcs_eis_product's sweeps with each row in registers. */
__attribute__((target("avx2,fma"))) static double product_avx2(const wcs_eis* e, const double* x, double* t,
                                                                double* o) {
    const wc_bsr_pattern* p = e->p;
    const int* rs = p->row_start;
    const int* col = p->col;
    const int* diag = p->diag;
    const double* F = e->F;
    const int n = p->n_rows;
    const __m256i m3 = _mm256_setr_epi64x(-1, -1, -1, 0);
    for (int i = n - 1; i >= 0; --i) { /* (I + L~^T) t = x */
        const __m256d s = row_sum(F, col, diag[i] + 1, rs[i + 1], t, m3);
        _mm256_maskstore_pd(t + 3 * (size_t)i, m3, _mm256_sub_pd(_mm256_maskload_pd(x + 3 * (size_t)i, m3), s));
    }
    __m256d xo = _mm256_setzero_pd();
    for (int i = 0; i < n; ++i) { /* (I + L~) u = x + K~ t; o = u for now */
        const __m256d xi = _mm256_maskload_pd(x + 3 * (size_t)i, m3);
        const __m256d ti = _mm256_maskload_pd(t + 3 * (size_t)i, m3);
        const __m256d kt = row_sum(F, col, diag[i], diag[i] + 1, t, m3);
        const __m256d u = _mm256_sub_pd(_mm256_add_pd(xi, kt), row_sum(F, col, rs[i], diag[i], o, m3));
        _mm256_maskstore_pd(o + 3 * (size_t)i, m3, u);
        xo = _mm256_fmadd_pd(xi, _mm256_add_pd(u, ti), xo);
    }
    for (int k = 0; k < 3 * n; ++k) o[k] += t[k];
    double l[4];
    _mm256_storeu_pd(l, xo);
    return (l[0] + l[1]) + l[2];
}
static int have_avx2(void) { return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma"); }
#else
static double product_avx2(const wcs_eis* e, const double* x, double* t, double* o) {
    return wcs_eis_product_scalar(e, x, t, o);
}
static int have_avx2(void) { return 0; }
#endif

double wcs_eis_product(const wcs_eis* e, const double* x, double* t, double* o) {
    return have_avx2() ? product_avx2(e, x, t, o) : wcs_eis_product_scalar(e, x, t, o);
}

double wcs_eis_product_scalar(const wcs_eis* e, const double* x, double* t, double* o) {
    const wc_bsr_pattern* p = e->p;
    const int* rs = p->row_start;
    const int* col = p->col;
    const int* diag = p->diag;
    const double* F = e->F;
    const int n = p->n_rows;
    for (int i = n - 1; i >= 0; --i) /* (I + L~^T) t = x */
        row_sub(F, col, diag[i] + 1, rs[i + 1], t, x + 3 * (size_t)i, t + 3 * (size_t)i);
    double xo = 0.0;
    for (int i = 0; i < n; ++i) { /* (I + L~) u = x + K~ t, o = t + u */
        double w[3];
        const double* ti = t + 3 * (size_t)i;
        m3_mulv(w, F + 9 * (size_t)diag[i], ti);
        v3_add(w, w, x + 3 * (size_t)i);
        double* oi = o + 3 * (size_t)i;
        row_sub(F, col, rs[i], diag[i], o, w, oi); /* o_j = u_j for j < i for now */
        xo += v3_dot(x + 3 * (size_t)i, oi) + v3_dot(x + 3 * (size_t)i, ti);
    }
    for (int k = 0; k < 3 * n; ++k) o[k] += t[k];
    return xo;
}

void wcs_eis_apply(const wcs_eis* e, const double* r, double* w, double* o) {
    const wc_bsr_pattern* p = e->p;
    const int* rs = p->row_start;
    const int* col = p->col;
    const int n = p->n_rows;
    for (int i = 0; i < n; ++i) { /* (I + L~) w = C^{-1} r */
        double v[3];
        m3_mulv(v, e->Ci + 9 * (size_t)i, r + 3 * (size_t)i);
        row_sub(e->F, col, rs[i], p->diag[i], w, v, w + 3 * (size_t)i);
    }
    for (int i = n - 1; i >= 0; --i) /* (I + L~^T) w = w, in place */
        row_sub(e->F, col, p->diag[i] + 1, rs[i + 1], w, w + 3 * (size_t)i, w + 3 * (size_t)i);
    for (int i = 0; i < n; ++i) { /* o = C^{-T} w */
        const double* C = e->Ci + 9 * (size_t)i;
        const double* v = w + 3 * (size_t)i;
        double* oi = o + 3 * (size_t)i;
        oi[0] = C[0] * v[0] + C[3] * v[1] + C[6] * v[2];
        oi[1] = C[1] * v[0] + C[4] * v[1] + C[7] * v[2];
        oi[2] = C[2] * v[0] + C[5] * v[1] + C[8] * v[2];
    }
}

/* dv = dv0 + C^{-T} y, projected to z + range(S) */
static void correct(const wcs_eis* e, const wc_filter* f, double* dv, wc_par* par) {
    for (int i = 0; i < e->p->n_rows; ++i) {
        const double* C = e->Ci + 9 * (size_t)i;
        const double* v = e->y + 3 * (size_t)i;
        const double* d0 = e->dv0 + 3 * (size_t)i;
        double* o = dv + 3 * (size_t)i;
        o[0] = d0[0] + (C[0] * v[0] + C[3] * v[1] + C[6] * v[2]);
        o[1] = d0[1] + (C[1] * v[0] + C[4] * v[1] + C[7] * v[2]);
        o[2] = d0[2] + (C[2] * v[0] + C[5] * v[1] + C[8] * v[2]);
    }
    wcs_project(f, dv, par);
}

wc_status wcs_eis_run(wc_solver* s, wcs_eis* e, const double* A, const double* b, const wc_filter* f, double* dv,
                      wc_par* par, wc_solve_result* res) {
    const wc_bsr_pattern* p = e->p;
    const int n = p->n_rows, n3 = 3 * n;
    const wc_solver_opts* o = &s->opts;
    const double goal = o->tolerance * res->scale;
    double* r = s->r; /* r^ */
    double* c = s->c;
    double* t = s->t;
    double* q = s->q;
    double rr0 = wcs_filtered_residual(s, A, b, f, dv, q, par); /* r_0 in q */
    memcpy(e->dv0, dv, sizeof(double) * (size_t)n3);
    memset(e->y, 0, sizeof(double) * (size_t)n3);
    int it = 0, converged = 0;
    wc_status st = WC_OK;
    double rt = rr0; /* the true residual's square at the last check */
    if (sqrt(rr0) <= goal) {
        converged = isfinite(rr0);
    } else {
        for (int i = 0; i < n; ++i) { /* r^ = (I + L~)^{-1} C^{-1} r_0 */
            double v[3];
            m3_mulv(v, e->Ci + 9 * (size_t)i, q + 3 * (size_t)i);
            row_sub(e->F, p->col, p->row_start[i], p->diag[i], r, v, r + 3 * (size_t)i);
        }
        double rr = 0.0;
        for (int k = 0; k < n3; ++k) rr += r[k] * r[k];
        double target = goal * sqrt(rr / rr0);
        const double limit = o->divergence_factor * fmax(res->residual0 * sqrt(rr / rr0), sqrt(rr));
        memcpy(c, r, sizeof(double) * (size_t)n3);
        for (;;) {
            if (!isfinite(rr) || sqrt(rr) > limit) {
                st = WC_ERROR_SOLVER_DIVERGED;
                break;
            }
            if (sqrt(rr) <= target) {
                ++e->checks;
                correct(e, f, dv, par);
                rt = wcs_filtered_residual(s, A, b, f, dv, q, par);
                if (sqrt(rt) <= goal) {
                    converged = 1;
                    break;
                }
                if (!isfinite(rt)) {
                    st = WC_ERROR_SOLVER_DIVERGED;
                    break;
                }
                target = sqrt(rr) * goal / sqrt(rt); /* the two residuals in the ratio they have now */
            }
            if (it >= o->max_iterations) break;
            const double cq = wcs_eis_product(e, c, t, q), alpha = rr / cq;
            if (!(cq > 0.0) || !isfinite(alpha)) {
                st = WC_ERROR_SOLVER_DIVERGED;
                break;
            }
            double rr_new = 0.0;
            for (int k = 0; k < n3; ++k) {
                e->y[k] += alpha * t[k];
                r[k] -= alpha * q[k];
                rr_new += r[k] * r[k];
            }
            const double beta = rr_new / rr;
            for (int k = 0; k < n3; ++k) c[k] = r[k] + beta * c[k];
            rr = rr_new;
            ++it;
        }
        if (st != WC_OK) memcpy(dv, e->dv0, sizeof(double) * (size_t)n3);
        else if (!converged) {
            correct(e, f, dv, par);
            rt = wcs_filtered_residual(s, A, b, f, dv, q, par);
        }
    }
    res->iterations = it;
    if (st != WC_OK) return st;
    res->residual = sqrt(rt) / res->scale;
    res->converged = converged || res->residual <= o->tolerance;
    if (!isfinite(res->residual)) return WC_ERROR_SOLVER_DIVERGED;
    return WC_OK;
}
