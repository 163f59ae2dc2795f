/* The springs' forces and blocks with AVX (core/forces.c, wc_eval_springs_at where the CPU has
 * AVX) against the scalar loops (wc_eval_springs_scalar, the code before it): every record bit for
 * bit, on a hanging sheet and a drape with contacts after some frames (springs stretched,
 * compressed and bent), at random velocities, both compression modes, 1 and 2 threads; nothing
 * written past the last record. Independently of the scalar code: each kx and kv is exactly
 * symmetric (the assembly's AVX rows read kx's rows as its columns, assemble.c), and f is
 * -(k (l - rest) + d (v_a - v_b).u) u with u the spring's direction, within rounding. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include "check.h"
#include "forces.h"
#include "step.h"
#include "test_support.h"
#include "amg_scene.h"

static void check_scene(int n, int kind, int frames, const char* what) {
    scene sc;
    if (!make_scene(&sc, n, 1.0, kind, frames)) return;
    const wc_model* m = &sc.m;
    const wc_state* s = sc.s;
    const int ns = m->n_springs, n3 = 3 * m->n_particles;
    wc_spring_eval *ev = malloc(sizeof(wc_spring_eval) * (ns + 1)), *es = malloc(sizeof(wc_spring_eval) * (ns + 1));
    double* v = malloc(sizeof(double) * n3);
    uint64_t st = 7 + (uint64_t)n;
    int same = 1, symmetric = 1, pad = 1, f_ok = 1;
    double worst_f = 0.0;
    for (int threads = 1; threads <= 2; ++threads) {
        wc_par par;
        wc_par_init(&par, threads);
        for (int trial = 0; trial < 4; ++trial) {
            for (int k = 0; k < n3; ++k) {
                st = st * 6364136223846793005ull + 1442695040888963407ull;
                v[k] = (double)(st >> 11) / 9007199254740992.0 - 0.5;
            }
            const wc_compression comp = trial % 2 ? WC_COMPRESSION_FULL : WC_COMPRESSION_DROP;
            memset(ev, 0xa5, sizeof(wc_spring_eval) * (ns + 1)); /* every entry must be written */
            memset(es, 0xa5, sizeof(wc_spring_eval) * (ns + 1));
            wc_eval_springs_at(m, s->x, v, comp, 0.0, &par, ev);
            wc_eval_springs_scalar(m, s->x, v, comp, 0.0, &par, es);
            if (same && memcmp(ev, es, sizeof(wc_spring_eval) * ns) != 0) { /* say where, once */
                same = 0;
                for (int k = 0, shown = 0; k < ns && !shown; ++k)
                    for (int q = 0; q < 21 && !shown; ++q) {
                        const double *a = (const double*)(ev + k) + q, *b = (const double*)(es + k) + q;
                        if (memcmp(a, b, sizeof(double))) printf("  spring %d double %d: %.17g vs %.17g\n", k, q, *a, *b), shown = 1;
                    }
            }
            const unsigned char* p = (const unsigned char*)(ev + ns);
            for (size_t b = 0; b < sizeof(wc_spring_eval); ++b) pad &= p[b] == 0xa5;
            for (int k = 0; k < ns; ++k) {
                const wc_spring_eval* e = ev + k;
                for (int r = 0; r < 3; ++r)
                    for (int q = 0; q < 3; ++q)
                        symmetric &= memcmp(&e->kx[3 * r + q], &e->kx[3 * q + r], sizeof(double)) == 0 &&
                                     memcmp(&e->kv[3 * r + q], &e->kv[3 * q + r], sizeof(double)) == 0;
                const wc_spring* sp = m->springs + k;
                double L[3], dv[3], l;
                for (int q = 0; q < 3; ++q) {
                    L[q] = s->x[3 * sp->a + q] - s->x[3 * sp->b + q];
                    dv[q] = v[3 * sp->a + q] - v[3 * sp->b + q];
                }
                l = sqrt(L[0] * L[0] + L[1] * L[1] + L[2] * L[2]);
                if (sp->type == WC_SPRING_SEAM || !(l > 1e-9)) continue;
                const double kk = m->material.k[sp->type], dd = m->material.d[sp->type];
                const double fs = kk * (l - sp->rest) + dd * (dv[0] * L[0] + dv[1] * L[1] + dv[2] * L[2]) / l;
                /* relative to the terms' sizes: k (l - rest) and the damping cancel in places */
                const double scale = kk * l + dd * sqrt(dv[0] * dv[0] + dv[1] * dv[1] + dv[2] * dv[2]);
                for (int q = 0; q < 3; ++q) {
                    const double err = fabs(e->f[q] + fs * L[q] / l) / scale;
                    worst_f = fmax(worst_f, err);
                    f_ok &= isfinite(e->f[q]) && err < 1e-14;
                }
            }
        }
    }
    printf("  %-26s AVX = scalar: %s; blocks symmetric: %s; pad untouched: %s; f within %.1e of (k l + d |dv|)\n", what,
           same ? "same bits" : "DIFFERENT", symmetric ? "yes" : "NO", pad ? "yes" : "NO", worst_f);
    CHECK(same);
    CHECK(symmetric);
    CHECK(pad);
    CHECK(f_ok);
    free(ev), free(es), free(v);
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
