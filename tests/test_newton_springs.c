/* The incremental potential's spring terms (core/newton_springs.c, wc_newton_spring_terms): the
 * AVX loop against the scalar loop, bit for bit, and both against sums computed here another way.
 * On a 16 x 16 sheet hanging from two corners, stepped 8 frames, at positions and velocities
 * perturbed at random in 3D (every spring stretched or compressed and moving), with damping
 * blocks -d u u^T at the perturbed directions (out of the sheet's plane, so no entry is 0):
 *  - over the whole range and over ragged sub-ranges (the chunks' boundaries), vec 1 == vec 0 bit
 *    for bit; the padding block after the last spring is NaN (its lane 3 must never be summed);
 *  - with zero damping blocks the terms are wc_spring_energy_at's energy bit for bit (the same
 *    terms minus an exact 0, summed in the same order);
 *  - the damping part (terms minus the energy) is -he/2 sum dv^T D dv summed here entry by entry
 *    in another order, within 1e-12 of the sum of the terms' and the energy's sizes. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "check.h"
#include "forces.h"
#include "newton.h"
#include "step.h"
#include "test_support.h"
#include "vec3.h"

#define N 16

static double urand(unsigned* seed) {
    *seed = *seed * 1103515245u + 12345u;
    return ((*seed >> 8) & 0xFFFF) / 65536.0 - 0.5;
}

static void test_terms(void) {
    wc_model m;
    CHECK(ts_sheet(&m, N, 1.0, 0.0, 1, 1.0));
    wc_sim_def d = wc_default_sim_def();
    d.threads = 1;
    wc_state* s = NULL;
    wc_diag diag = {0};
    CHECK_EQ_INT(wc_state_create(&s, &m, &d, NULL, &diag), WC_OK);
    if (!s) return;
    CHECK_EQ_INT(ts_pin_far_corners(s, N, NULL), WC_OK);
    wc_step_stats st;
    for (int f = 0; f < 8; ++f) CHECK_EQ_INT(wc_step_frame(s, 1.0 / 30.0, &st, &diag), WC_OK);
    int ns = m.n_springs, n3 = 3 * m.n_particles;
    double* kv0 = malloc(sizeof(double) * 9 * ((size_t)ns + 1));
    double* zero = calloc(9 * ((size_t)ns + 1), sizeof(double));
    double* x = malloc(sizeof(double) * (size_t)n3);
    double* v = malloc(sizeof(double) * (size_t)n3);
    CHECK(kv0 && zero && x && v);
    if (!kv0 || !zero || !x || !v) return;
    for (int q = 0; q < 9; ++q) kv0[9 * (size_t)ns + q] = NAN;
    zero[9 * (size_t)ns] = NAN;
    unsigned seed = 7;
    int off = 0, checks = 0, damped = 0;
    double worst_damp = 0.0;
    for (int round = 0; round < 6; ++round) {
        for (int k = 0; k < n3; ++k) {
            x[k] = s->x[k] + 0.02 * urand(&seed);
            v[k] = s->v[k] + 0.5 * urand(&seed);
        }
        double he = round % 2 ? 1.0 / 30.0 : 1.0 / 120.0;
        /* damping blocks -d u u^T at the perturbed directions (out of the sheet's plane: all
           nine entries nonzero), each u_r u_q one product as forces.c builds them */
        for (int k = 0; k < ns; ++k) {
            const wc_spring* sp = &m.springs[k];
            double u[3];
            v3_sub(u, x + 3 * sp->a, x + 3 * sp->b);
            v3_scale(u, u, 1.0 / v3_norm(u));
            double dk = m.material.d[sp->type] > 0.0 ? m.material.d[sp->type] : 1.0;
            for (int r = 0; r < 3; ++r)
                for (int q = 0; q < 3; ++q) kv0[9 * (size_t)k + 3 * r + q] = -dk * (u[r] * u[q]);
        }
        /* whole range and ragged pieces, vec against scalar */
        int cuts[] = {0, 1, 5, 256, 300, ns - 3, ns};
        for (int c = 0; c + 1 < (int)(sizeof cuts / sizeof cuts[0]); ++c) {
            double a = wc_newton_spring_terms(&m, x, v, kv0, he, 0.0, cuts[c], cuts[c + 1], 1);
            double b = wc_newton_spring_terms(&m, x, v, kv0, he, 0.0, cuts[c], cuts[c + 1], 0);
            off += memcmp(&a, &b, sizeof a) != 0;
            ++checks;
        }
        double all = wc_newton_spring_terms(&m, x, v, kv0, he, 0.0, 0, ns, 1);
        off += !isfinite(all);
        /* zero damping: the springs' energy itself */
        double el = wc_newton_spring_terms(&m, x, v, zero, he, 0.0, 0, ns, 1);
        double ref = wc_spring_energy_at(&m, x, 0.0);
        off += memcmp(&el, &ref, sizeof el) != 0;
        ++checks;
        /* the damping part, entry by entry */
        double damp = 0.0, scale = 0.0;
        for (int k = 0; k < ns; ++k) {
            const wc_spring* sp = &m.springs[k];
            double dv[3];
            v3_sub(dv, v + 3 * sp->a, v + 3 * sp->b);
            for (int r = 2; r >= 0; --r)
                for (int q = 2; q >= 0; --q) {
                    double t = -0.5 * he * dv[r] * kv0[9 * (size_t)k + 3 * r + q] * dv[q];
                    damp += t;
                    scale += fabs(t);
                }
        }
        double rel = fabs((all - el) - damp) / fmax(scale + fabs(el), 1e-300);
        if (rel > worst_damp) worst_damp = rel;
        damped += scale > 0.0;
    }
    printf("  %d springs; %d vec/scalar and energy comparisons, %d off; damping part within %.2g (%d rounds damped)\n",
           ns, checks, off, worst_damp, damped);
    CHECK_EQ_INT(off, 0);
    CHECK(damped == 6);
    CHECK(worst_damp < 1e-12);
    free(kv0);
    free(zero);
    free(x);
    free(v);
    wc_state_destroy(s);
    wc_model_free(&m);
}

int main(void) {
    RUN_TEST(test_terms);
    return TEST_SUMMARY();
}
