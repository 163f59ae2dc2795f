/* The Chebyshev smoother's AVX2 node updates (core/amg_smooth.c) against the scalar loops' rule,
 * bit for bit:
 * - the kernel on planted levels (3x3 blocks, and pair levels' two blocks a node), every mode
 *   (x = d, x += d, d = c1 d + c2 D^-1 t), against this file's own m3_mulv-order arithmetic; the
 *   float shadow's 4th float 0; nothing written outside the nodes' range;
 * - a draped sheet on PCG + multigrid (ts_amg_def) stepped with the kernel and with the scalar
 *   loops (wc_amg_opts.smooth_vector 0): the same positions and velocities, frame by frame.
 * Skipped (said so) where the CPU has no AVX2. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "amg.h"
#include "check.h"
#include "solve_kernels.h"
#include "step.h"
#include "test_support.h"

#define NODES 37

/* full 53-bit mantissas (values of few bits would sum exactly in any order) */
static double rnd(unsigned* s) {
    *s = *s * 1103515245u + 12345u;
    unsigned a = *s >> 5;
    *s = *s * 1103515245u + 12345u;
    unsigned b = *s >> 6;
    return ((a * 67108864.0 + b) / 9007199254740992.0 - 0.5) * (1.0 + (double)(*s & 7));
}

/* The scalar rule: e = (D^-1 t)_i in m3_mulv's order (group 2: the second block's product added). */
static void dinv_ref(const double* Dinv, int g, int i, const double* t, double* e) {
    const int b = g == 1 ? i : i & ~1;
    for (int r = 0; r < 3; ++r) {
        const double* m = Dinv + 9 * ((size_t)g * i) + 3 * r;
        e[r] = m[0] * t[3 * b] + m[1] * t[3 * b + 1] + m[2] * t[3 * b + 2];
    }
    if (g == 2)
        for (int r = 0; r < 3; ++r) {
            const double* m = Dinv + 9 * ((size_t)g * i + 1) + 3 * r;
            e[r] += m[0] * t[3 * b + 3] + m[1] * t[3 * b + 4] + m[2] * t[3 * b + 5];
        }
}

static void test_kernel_planted(void) {
    wc_amg_cheb_nodes_fn k = wc_amg_cheb_nodes_kernel();
    if (!k) {
        printf("  no AVX2 on this CPU: the scalar loops run, nothing to compare\n");
        return;
    }
    unsigned seed = 7;
    int compared = 0, off = 0, shadow = 0, outside = 0;
    for (int g = 1; g <= 2; ++g)
        for (int mode = 0; mode < 3; ++mode) {
            const int n = NODES + (g == 2); /* pairs: an even count */
            wc_amg_level L;
            memset(&L, 0, sizeof L);
            L.group = g;
            L.n = n;
            L.Dinv = malloc(sizeof(double) * 9 * g * n);
            L.DinvT = malloc(sizeof(double) * 12 * g * n);
            double *t = malloc(sizeof(double) * 3 * n), *d = malloc(sizeof(double) * 3 * n),
                   *x = malloc(sizeof(double) * 3 * n), *d0 = malloc(sizeof(double) * 3 * n),
                   *x0 = malloc(sizeof(double) * 3 * n);
            float* xf = malloc(sizeof(float) * 4 * n);
            for (int q = 0; q < 9 * g * n; ++q) L.Dinv[q] = rnd(&seed);
            for (int q = 0; q < 3 * n; ++q) {
                t[q] = rnd(&seed);
                d0[q] = d[q] = rnd(&seed);
                x0[q] = x[q] = rnd(&seed);
            }
            for (int q = 0; q < 4 * n; ++q) xf[q] = 9.0f; /* sentinels */
            wc_amg_dinv_columns(&L, 0, n);
            const int lo = 3, hi = n - 4;
            const double c1 = 0.3 + rnd(&seed) * 0.01, c2 = 0.7 + rnd(&seed) * 0.01;
            k(&L, t, d, x, xf, lo, hi, c1, c2, mode);
            for (int i = 0; i < n; ++i) {
                double ed[3], ex[3];
                if (i >= lo && i < hi) {
                    double e[3];
                    dinv_ref(L.Dinv, g, i, t, e);
                    for (int c = 0; c < 3; ++c) {
                        ed[c] = mode == 2 ? c1 * d0[3 * i + c] + c2 * e[c] : e[c] * c2;
                        ex[c] = mode == 0 ? ed[c] : x0[3 * i + c] + ed[c];
                    }
                    for (int c = 0; c < 3; ++c) shadow += xf[4 * i + c] != (float)ex[c];
                    shadow += memcmp(&xf[4 * i + 3], &(float){0.0f}, sizeof(float)) != 0;
                    ++compared;
                } else {
                    memcpy(ed, d0 + 3 * i, sizeof ed);
                    memcpy(ex, x0 + 3 * i, sizeof ex);
                    for (int c = 0; c < 4; ++c) outside += xf[4 * i + c] != 9.0f;
                }
                int bad = memcmp(ed, d + 3 * i, sizeof ed) != 0 || memcmp(ex, x + 3 * i, sizeof ex) != 0;
                if (i >= lo && i < hi) off += bad;
                else outside += bad;
            }
            free(L.Dinv);
            free(L.DinvT);
            free(t);
            free(d);
            free(x);
            free(d0);
            free(x0);
            free(xf);
        }
    printf("  %d node updates compared: %d off the scalar rule, %d shadows off, %d writes outside the range\n",
           compared, off, shadow, outside);
    CHECK(compared > 6 * 30);
    CHECK_EQ_INT(off, 0);
    CHECK_EQ_INT(shadow, 0);
    CHECK_EQ_INT(outside, 0);
}

#define FRAMES 8

static void run(int scalar, double* out, int* iterations) {
    wc_model m;
    wc_sim_def def = ts_amg_def();
    def.threads = 1;
    wc_state* s = ts_draped(&m, 20, &def, 0);
    CHECK(s != NULL);
    if (!s) return;
    CHECK(s->solver->amg != NULL && s->solver->amg->opts.smooth_vector == 1);
    if (s->solver->amg) s->solver->amg->opts.smooth_vector = !scalar;
    size_t n3 = 3 * (size_t)m.n_particles;
    wc_diag d = {0};
    *iterations = 0;
    for (int f = 0; f < FRAMES; ++f) {
        wc_step_stats st;
        CHECK_EQ_INT(wc_step_frame(s, 1.0 / 30.0, &st, &d), WC_OK);
        *iterations += st.iterations;
        memcpy(out + 2 * n3 * f, s->x, n3 * sizeof(double));
        memcpy(out + 2 * n3 * f + n3, s->v, n3 * sizeof(double));
    }
    wc_state_destroy(s);
    wc_model_free(&m);
}

static void test_draped_same_bits(void) {
    const size_t len = 2 * 3 * 20 * 20 * (size_t)FRAMES;
    double *a = calloc(len, sizeof(double)), *b = calloc(len, sizeof(double));
    int ia = 0, ib = 0;
    run(0, a, &ia);
    run(1, b, &ib);
    printf("  draped 20 x 20, %d frames: %d PCG iterations with the kernel, %d with the scalar loops%s\n", FRAMES, ia,
           ib, wc_amg_cheb_nodes_kernel() ? "" : " (no AVX2: both scalar)");
    CHECK(ia > 0);
    CHECK_EQ_INT(ia, ib);
    CHECK(memcmp(a, b, len * sizeof(double)) == 0);
    free(a);
    free(b);
}

int main(void) {
    RUN_TEST(test_kernel_planted);
    RUN_TEST(test_draped_same_bits);
    return TEST_SUMMARY();
}
