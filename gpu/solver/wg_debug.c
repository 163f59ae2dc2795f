/* Entry points for tests and benchmarks (wg_sim.h): one substep's system, a solve, an SpMV, a
 * reduction and the bandwidth measure, each read back into double arrays. */
#include <string.h>

#include "clock.h"
#include "gpu_error.h"
#include "wg_sim_impl.h"


static void read_vec(wg_sim* g, const wg_tex* t, int count, double* out) {
    wg_array_read(&g->layout, t, count, g->rb);
    for (int i = 0; i < count; ++i)
        for (int c = 0; c < 3; ++c) out[3 * i + c] = g->rb[4 * i + c];
}

static void upload_vec(wg_sim* g, const wg_tex* t, int count, const double* in) {
    for (int i = 0; i < count; ++i)
        for (int c = 0; c < 4; ++c) g->rb[4 * i + c] = c < 3 ? (float)in[3 * i + c] : 0.0f;
    wg_array_upload(&g->layout, t, count, g->rb);
}

/* A symmetric row-major 3x3 block m as the two texels (a00 a01 a02 a11 | a12 a22) the passes
 * read (hi: 2 floats used), and back. */
static void pack_sym(const double* m, float* lo, float* hi) {
    lo[0] = (float)m[0];
    lo[1] = (float)m[1];
    lo[2] = (float)m[2];
    lo[3] = (float)m[4];
    hi[0] = (float)m[5];
    hi[1] = (float)m[8];
}

static void unpack_sym(const float* lo, const float* hi, double* m) {
    m[0] = lo[0]; m[1] = lo[1]; m[2] = lo[2];
    m[3] = lo[1]; m[4] = lo[3]; m[5] = hi[0];
    m[6] = lo[2]; m[7] = hi[0]; m[8] = hi[1];
}

/* Symmetric pairs (lo, hi) of `count` items into row-major 3x3 blocks. */
static int read_sym(wg_sim* g, const wg_tex* lo, const wg_tex* hi, int count, double* out) {
    float* a = wc_calloc(&g->alloc, (size_t)count * 4u, sizeof(float));
    float* b = wc_calloc(&g->alloc, (size_t)count * 4u, sizeof(float));
    if (!a || !b) {
        wc_free(&g->alloc, a);
        wc_free(&g->alloc, b);
        return 0;
    }
    wg_array_read(&g->layout, lo, count, a);
    /* hi is RG32F: read through an RGBA copy */
    wg_tex tmp;
    char err[128];
    if (!wg_array_create(&g->layout, &tmp, GL_RGBA32F, count, NULL, err, sizeof err)) {
        wc_free(&g->alloc, a);
        wc_free(&g->alloc, b);
        return 0;
    }
    wg_copy(&g->run, &tmp, hi);
    wg_array_read(&g->layout, &tmp, count, b);
    wg_tex_destroy(&tmp);
    for (int k = 0; k < count; ++k) unpack_sym(a + 4 * k, b + 4 * k, out + 9 * k);
    wc_free(&g->alloc, a);
    wc_free(&g->alloc, b);
    return 1;
}

wc_status wg_sim_debug_prepare(wg_sim* g, wc_state* s, double h, double alpha1, double* A, double* b, double* S,
                                 double* z, unsigned char* ndof, double* x, wc_diag* diag) {
    wg_step_upload_pins(g, s);
    wg_ring_save(&g->x);
    wc_integ ig;
    wc_integ_coefficients(s, h, 1, &ig);
    wg_step_prepare(g, s, &ig, alpha1, s->def.compression);
    if (A && !read_sym(g, &g->A0, &g->A1, g->nb, A)) return wc_fail(diag, WC_ERROR_OUT_OF_MEMORY, "debug: out of memory");
    if (b) read_vec(g, &g->b, g->n, b);
    if (z) read_vec(g, &g->z, g->n, z);
    if (x) read_vec(g, wg_ring_cur(&g->x), g->n, x);
    if (S || ndof) {
        float* s0 = wc_calloc(&g->alloc, (size_t)g->n * 4u, sizeof(float));
        float* s1 = wc_calloc(&g->alloc, (size_t)g->n * 4u, sizeof(float));
        if (!s0 || !s1) {
            wc_free(&g->alloc, s0);
            wc_free(&g->alloc, s1);
            return wc_fail(diag, WC_ERROR_OUT_OF_MEMORY, "debug: out of memory");
        }
        wg_array_read(&g->layout, &g->S0, g->n, s0);
        wg_array_read(&g->layout, &g->S1, g->n, s1);
        for (int i = 0; i < g->n; ++i) {
            if (S) unpack_sym(s0 + 4 * i, s1 + 4 * i, S + 9 * i);
            if (ndof) ndof[i] = (unsigned char)s1[4 * i + 2];
        }
        wc_free(&g->alloc, s0);
        wc_free(&g->alloc, s1);
    }
    GLenum e = glGetError();
    if (e != GL_NO_ERROR) return wc_fail(diag, WC_ERROR_GPU, "debug prepare: %s", wg_gl_error_name(e));
    return WC_OK;
}

wc_status wg_sim_debug_solve(wg_sim* g, wc_solver_type type, double* dv, wc_solve_result* res, wc_diag* diag) {
    const wc_solver_opts* o = &g->debug_opts;
    const wg_tex* in = wg_ring_cur(&g->dv);
    if (dv) {
        int k = wg_ring_other(&g->dv, 0);
        upload_vec(g, &g->dv.t[k], g->n, dv);
        in = &g->dv.t[k];
    }
    const wg_tex* out = NULL;
    wc_status st = wg_solve(g, o, type, in, &out, res);
    if (dv && out) read_vec(g, out, g->n, dv);
    GLenum e = glGetError();
    if (e != GL_NO_ERROR) return wc_fail(diag, WC_ERROR_GPU, "debug solve: %s", wg_gl_error_name(e));
    return st;
}

wc_status wg_sim_debug_read_system(wg_sim* g, double* A, double* b, wc_diag* diag) {
    if (A && !read_sym(g, &g->A0, &g->A1, g->nb, A)) return wc_fail(diag, WC_ERROR_OUT_OF_MEMORY, "debug: out of memory");
    if (b) read_vec(g, &g->b, g->n, b);
    return WC_OK;
}

wc_status wg_sim_debug_spmv(wg_sim* g, const double* x, double* y, wc_diag* diag) {
    upload_vec(g, &g->t, g->n, x);
    wg_spmv(g, &g->t, 0);
    read_vec(g, &g->q, g->n, y);
    GLenum e = glGetError();
    if (e != GL_NO_ERROR) return wc_fail(diag, WC_ERROR_GPU, "debug spmv: %s", wg_gl_error_name(e));
    return WC_OK;
}

wc_status wg_sim_debug_pcg_dots(wg_sim* g, int rows, const double* c, const double* r, double* q, double* t,
                                double dots[3], wc_diag* diag) {
    if (rows < 1 || rows > g->n) return wc_fail(diag, WC_ERROR_INVALID_ARGUMENT, "debug dots: %d rows of %d", rows, g->n);
    upload_vec(g, &g->c[0], g->n, c);
    upload_vec(g, &g->r[0], g->n, r);
    wg_solve_debug_dots(g, rows, dots);
    read_vec(g, &g->q, rows, q);
    read_vec(g, &g->t, rows, t);
    GLenum e = glGetError();
    if (e != GL_NO_ERROR) return wc_fail(diag, WC_ERROR_GPU, "debug dots: %s", wg_gl_error_name(e));
    return WC_OK;
}

double wg_sim_debug_reduce(wg_sim* g, const double* values, int n, int mode) {
    if (n > g->n) n = g->n;
    for (int i = 0; i < g->n; ++i)
        for (int c = 0; c < 4; ++c) g->rb[4 * i + c] = (c == 0 && i < n) ? (float)values[i] : 0.0f;
    wg_array_upload(&g->layout, &g->part, g->n, g->rb);
    float r[4];
    wg_read1(&g->layout, wg_reduce(&g->run, &g->red_p[1], &g->part, mode, mode, mode, mode), r);
    return r[0];
}

void wg_sim_debug_bandwidth(wg_sim* g, int reps, double* ms_spmv, double* ms_copy, double* bytes_spmv,
                            double* bytes_copy) {
    glFinish();
    double t0 = wc_now_ms();
    for (int k = 0; k < reps; ++k) wg_spmv(g, &g->c[0], 0);
    glFinish();
    double t1 = wc_now_ms();
    for (int k = 0; k < reps; ++k) wg_copy(&g->run, &g->t, &g->c[0]);
    glFinish();
    double t2 = wc_now_ms();
    *ms_spmv = (t1 - t0) / reps;
    *ms_copy = (t2 - t1) / reps;
    /* bytes an SpMV must move at least: per row its range (16), per block its index texel (16),
       the two block texels (16 + 8) and x at the column (16), and y (16) */
    *bytes_spmv = (double)g->n * 32.0 + (double)g->nb * (16.0 + 24.0 + 16.0);
    *bytes_copy = (double)g->n * 32.0;
}

double wg_sim_debug_rho(const wg_sim* g) { return g->rho_valid ? g->rho : 0.0; }

long long wg_sim_debug_passes(const wg_sim* g) { return g->run.passes; }

wc_status wg_sim_debug_set_system(wg_sim* g, const double* A, const double* b, const wc_filter* f, wc_diag* diag) {
    float* lo = wc_calloc(&g->alloc, (size_t)g->nb * 4u, sizeof(float));
    float* hi = wc_calloc(&g->alloc, (size_t)g->nb * 2u, sizeof(float));
    if (!lo || !hi) {
        wc_free(&g->alloc, lo);
        wc_free(&g->alloc, hi);
        return wc_fail(diag, WC_ERROR_OUT_OF_MEMORY, "debug: out of memory");
    }
    for (int k = 0; k < g->nb; ++k) pack_sym(A + 9 * k, lo + 4 * k, hi + 2 * k);
    wg_array_upload(&g->layout, &g->A0, g->nb, lo);
    wg_array_upload(&g->layout, &g->A1, g->nb, hi);
    wc_free(&g->alloc, lo);
    wc_free(&g->alloc, hi);
    upload_vec(g, &g->b, g->n, b);
    if (f) {
        upload_vec(g, &g->z, g->n, f->z);
        float* s0 = wc_calloc(&g->alloc, (size_t)g->n * 4u, sizeof(float));
        float* s1 = wc_calloc(&g->alloc, (size_t)g->n * 4u, sizeof(float));
        if (!s0 || !s1) {
            wc_free(&g->alloc, s0);
            wc_free(&g->alloc, s1);
            return wc_fail(diag, WC_ERROR_OUT_OF_MEMORY, "debug: out of memory");
        }
        for (int i = 0; i < g->n; ++i) {
            pack_sym(f->S + 9 * i, s0 + 4 * i, s1 + 4 * i);
            s1[4 * i + 2] = (float)f->ndof[i];
        }
        wg_array_upload(&g->layout, &g->S0, g->n, s0);
        wg_array_upload(&g->layout, &g->S1, g->n, s1);
        wc_free(&g->alloc, s0);
        wc_free(&g->alloc, s1);
    }
    GLenum e = glGetError();
    if (e != GL_NO_ERROR) return wc_fail(diag, WC_ERROR_GPU, "debug set system: %s", wg_gl_error_name(e));
    return WC_OK;
}

void wg_sim_debug_invalidate_rho(wg_sim* g) { g->rho_valid = 0; }

void wg_sim_debug_set_opts(wg_sim* g, const wc_solver_opts* o) { g->debug_opts = *o; }

void wg_sim_debug_spring_checks(wg_sim* g, const wc_state* s, double* elastic, double* max_strain) {
    wg_checks_springs(g, s, elastic, max_strain);
}

double wg_sim_debug_phi_change(wg_sim* g, const wc_state* s, double h, const double* wa, const double* wb) {
    upload_vec(g, &g->nw_w[0], g->n, wa);
    upload_vec(g, &g->nw_w[1], g->n, wb);
    wc_integ ig;
    wc_integ_coefficients(s, h, 1, &ig);
    return wg_newton_phi_change(g, s, &ig, &g->nw_w[0], &g->nw_w[1]);
}

wc_status wg_sim_debug_newton_system(wg_sim* g, const wc_state* s, double h, const double* w, double* A, double* grad,
                                     double* fa, double* fb, wc_diag* diag) {
    if (!g->newton) return wc_fail(diag, WC_ERROR_INVALID_ARGUMENT, "debug: a cloth without Newton iterations");
    wc_integ ig;
    wc_integ_coefficients(s, h, 1, &ig);
    if (g->nw_friction) wg_newton_friction(g, 1);
    upload_vec(g, &g->nw_w[0], g->n, w);
    wg_newton_system(g, s, &ig, &g->nw_w[0], s->def.compression);
    if (A && !read_sym(g, &g->A0, &g->A1, g->nb, A)) return wc_fail(diag, WC_ERROR_OUT_OF_MEMORY, "debug: out of memory");
    if (grad) read_vec(g, &g->b, g->n, grad);
    if (fa && g->nw_friction && !read_sym(g, &g->nw_fa[0], &g->nw_fa[1], g->n, fa))
        return wc_fail(diag, WC_ERROR_OUT_OF_MEMORY, "debug: out of memory");
    if (fa && !g->nw_friction) memset(fa, 0, (size_t)g->n * 9u * sizeof(double));
    if (fb && g->nw_friction) read_vec(g, &g->nw_fb, g->n, fb);
    if (fb && !g->nw_friction) memset(fb, 0, (size_t)g->n * 3u * sizeof(double));
    GLenum e = glGetError();
    if (e != GL_NO_ERROR) return wc_fail(diag, WC_ERROR_GPU, "debug Newton system: %s", wg_gl_error_name(e));
    return WC_OK;
}
