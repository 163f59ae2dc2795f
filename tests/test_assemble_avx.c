/* The system's assembly with AVX (core/assemble.c, wc_assemble where the CPU has AVX) against the
 * scalar loops (wc_assemble_scalar, the code before it): A's blocks, b and f0 bit for bit, on a
 * hanging sheet and a drape with contacts after some frames (springs stretched and bent), at
 * random velocities and external forces and several step lengths, on 1 and 2 threads. Independently of the scalar
 * code: b_i is h (f_i + h sum_s kx_s (v_i - v_j)) summed here spring by spring, within
 * rounding, and each row's blocks sum to M_i (a spring adds J to A_ij and takes it from A_ii, so the
 * row's sum telescopes), within rounding. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include "assemble.h"
#include "forces.h"
#include "check.h"
#include "step.h"
#include "test_support.h"
#include "amg_scene.h"

static void check_scene(int n, int kind, int frames, const char* what) {
    scene sc;
    if (!make_scene(&sc, n, 1.0, kind, frames)) return;
    const wc_model* m = &sc.m;
    const wc_state* s = sc.s;
    const int n3 = 3 * m->n_particles;
    /* the scene's frames ran the kernel under test: a wrong one blows the sheet up, and forces of
       1e31 would swallow the kx (v_i - v_j) terms below */
    const double strain = wc_max_stretch_strain(m, s->x);
    printf("  %-26s largest stretch strain %.3f\n", what, strain);
    CHECK(strain < 0.5);
    const size_t nb = 9 * (size_t)m->pattern.n_blocks;
    double *Av = malloc(sizeof(double) * nb), *As = malloc(sizeof(double) * nb);
    double *bv = malloc(sizeof(double) * n3), *bs = malloc(sizeof(double) * n3);
    double *fv = malloc(sizeof(double) * n3), *fs = malloc(sizeof(double) * n3);
    double *v = malloc(sizeof(double) * n3), *fe = malloc(sizeof(double) * n3);
    wc_spring_eval* se = malloc(sizeof(wc_spring_eval) * ((size_t)m->n_springs + 1));
    uint64_t st = 3 + (uint64_t)n;
    int same = 1, rows_ok = 1;
    double worst_row = 0.0, worst_b = 0.0;
    int b_ok = 1;
    for (int threads = 1; threads <= 2; ++threads) {
        wc_par par;
        wc_par_init(&par, threads);
        const double hs[3] = {1.0 / 30, 1.0 / 240, 0.1};
        for (int trial = 0; trial < 3; ++trial) {
            for (int k = 0; k < n3; ++k) {
                st = st * 6364136223846793005ull + 1442695040888963407ull;
                v[k] = (double)(st >> 11) / 9007199254740992.0 - 0.5;
                fe[k] = 0.01 * v[k] - 0.001; /* an external force of the springs' size or below, so
                                                that b shows the kx (v_i - v_j) terms */
            }
            /* the springs at the scene's positions and these velocities */
            wc_eval_springs_at(m, s->x, v, trial % 2 ? WC_COMPRESSION_FULL : WC_COMPRESSION_DROP, 0.0, &par, se);
            memset(Av, 0xff, sizeof(double) * nb); /* NaN: every block must be written */
            memset(As, 0xff, sizeof(double) * nb);
            wc_assemble(m, se, fe, v, hs[trial], &par, Av, bv, fv);
            wc_assemble_scalar(m, se, fe, v, hs[trial], &par, As, bs, fs);
            same &= memcmp(Av, As, sizeof(double) * nb) == 0 && memcmp(bv, bs, sizeof(double) * n3) == 0 &&
                    memcmp(fv, fs, sizeof(double) * n3) == 0;
            wc_assemble(m, se, fe, v, hs[trial], &par, Av, bv, NULL); /* f_total optional */
            same &= memcmp(Av, As, sizeof(double) * nb) == 0 && memcmp(bv, bs, sizeof(double) * n3) == 0;
            for (int i = 0; i < m->n_particles; ++i) { /* b_i = h (f_i + h sum kx (v_i - v_j)), by springs */
                double f[3] = {fe[3 * i], fe[3 * i + 1], fe[3 * i + 2]}, kv[3] = {0, 0, 0}, mag = 1e-300;
                for (int s2 = 0; s2 < m->n_springs; ++s2) {
                    const wc_spring* sp = m->springs + s2;
                    if (sp->a != i && sp->b != i) continue;
                    const int j = sp->a == i ? sp->b : sp->a;
                    const double sign = sp->a == i ? 1.0 : -1.0;
                    for (int r = 0; r < 3; ++r) {
                        f[r] += sign * se[s2].f[r];
                        for (int q = 0; q < 3; ++q) kv[r] += se[s2].kx[3 * r + q] * (v[3 * i + q] - v[3 * j + q]);
                        mag = fmax(mag, fabs(se[s2].f[r]) + hs[trial] * fabs(se[s2].kx[3 * r + r]));
                    }
                }
                for (int r = 0; r < 3; ++r) {
                    const double err = fabs(bv[3 * i + r] - hs[trial] * (f[r] + hs[trial] * kv[r])) / (hs[trial] * mag);
                    worst_b = fmax(worst_b, err);
                    b_ok &= err < 1e-12;
                }
            }
            for (int i = 0; i < m->n_particles; ++i) { /* sum_j A_ij = M_i I */
                double sum[9] = {0}, mag = 0.0;
                for (int k = m->pattern.row_start[i]; k < m->pattern.row_start[i + 1]; ++k)
                    for (int q = 0; q < 9; ++q) {
                        sum[q] += Av[9 * (size_t)k + q];
                        mag = fmax(mag, fabs(Av[9 * (size_t)k + q]));
                    }
                for (int q = 0; q < 9; ++q) {
                    const double want = q % 4 == 0 ? m->mass[i] : 0.0;
                    const double err = fabs(sum[q] - want) / (mag + m->mass[i]);
                    worst_row = fmax(worst_row, err);
                    rows_ok &= isfinite(sum[q]) && err < 1e-12;
                }
            }
        }
    }
    printf("  %-26s AVX = scalar: %s; rows' sums = M_i within %.1e; b by springs within %.1e\n", what,
           same ? "same bits" : "DIFFERENT", worst_row, worst_b);
    CHECK(same);
    CHECK(rows_ok);
    CHECK(b_ok);
    free(Av), free(As), free(bv), free(bs), free(fv), free(fs), free(v), free(fe), free(se);
    free_scene(&sc);
}

static void test_bits(void) {
    if (!__builtin_cpu_supports("avx")) printf("  no AVX: both are the scalar loops\n");
    check_scene(16, HANG, 6, "16^2 hanging sheet");
    check_scene(32, DRAPE, 12, "32^2 drape with contacts");
}

int main(void) {
    RUN_TEST(test_bits);
    return TEST_SUMMARY();
}
