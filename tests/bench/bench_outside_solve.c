/* Same-process wall A/B of the kernels outside the sheet's solves: the system's assembly
 * (wc_assemble: AVX rows, against wc_assemble_scalar) and the springs' forces and blocks
 * (wc_eval_springs_at: AVX blocks, against wc_eval_springs_scalar), on an n x n hanging sheet after
 * some frames, 1 thread. Rounds alternate the two kernels (A B B A ...) so that load on a shared
 * machine falls on both; prints each kernel's median and minimum microseconds a call, and the
 * median of the per-round ratios. A table, no limits asserted.
 *     bench_outside_solve [--n 32] [--rounds 41] [--calls 200] */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "assemble.h"
#include "clock.h"
#include "forces.h"
#include "step.h"
#include "test_support.h"
#include "amg_scene.h"

static int cmp_double(const void* a, const void* b) {
    double x = *(const double*)a, y = *(const double*)b;
    return (x > y) - (x < y);
}

typedef struct ctx {
    const wc_model* m;
    const wc_state* s;
    wc_par* par;
    double *A, *b, *f, *v;
    wc_spring_eval* se;
} ctx;

static void run(const ctx* c, int which, int calls) {
    for (int k = 0; k < calls; ++k) switch (which) {
        case 0: wc_assemble(c->m, c->se, c->s->f_ext, c->v, 1.0 / 30, c->par, c->A, c->b, c->f); break;
        case 1: wc_assemble_scalar(c->m, c->se, c->s->f_ext, c->v, 1.0 / 30, c->par, c->A, c->b, c->f); break;
        case 2: wc_eval_springs_at(c->m, c->s->x, c->v, WC_COMPRESSION_DROP, 0.0, c->par, c->se); break;
        default: wc_eval_springs_scalar(c->m, c->s->x, c->v, WC_COMPRESSION_DROP, 0.0, c->par, c->se); break;
        }
}

int main(int argc, char** argv) {
    int n = 32, rounds = 41, calls = 200;
    for (int i = 1; i + 1 < argc; i += 2) {
        if (!strcmp(argv[i], "--n")) n = atoi(argv[i + 1]);
        else if (!strcmp(argv[i], "--rounds")) rounds = atoi(argv[i + 1]);
        else if (!strcmp(argv[i], "--calls")) calls = atoi(argv[i + 1]);
    }
    if (n < 2 || rounds < 1 || calls < 1) return 2;
    scene sc;
    if (!make_scene(&sc, n, 1.0, HANG, 10)) return 1;
    wc_par par;
    wc_par_init(&par, 1);
    const wc_model* m = &sc.m;
    ctx c = {m, sc.s, &par, malloc(sizeof(double) * 9 * (size_t)m->pattern.n_blocks),
             malloc(sizeof(double) * 3 * m->n_particles), malloc(sizeof(double) * 3 * m->n_particles),
             calloc(3 * (size_t)m->n_particles, sizeof(double)), malloc(sizeof(wc_spring_eval) * ((size_t)m->n_springs + 1))};
    memcpy(c.v, sc.s->v, sizeof(double) * 3 * m->n_particles);
    run(&c, 2, 1);
    double* t = malloc(sizeof(double) * 4 * rounds);
    double* ratio = malloc(sizeof(double) * 2 * rounds);
    for (int r = 0; r < rounds; ++r)
        for (int q = 0; q < 4; ++q) {
            const int which = r % 2 ? (q ^ 1) : q; /* A B, then B A */
            const double t0 = wc_now_ms();
            run(&c, which, calls);
            t[which * rounds + r] = 1e3 * (wc_now_ms() - t0) / calls;
        }
    for (int r = 0; r < rounds; ++r) {
        ratio[r] = t[0 * rounds + r] / t[1 * rounds + r];
        ratio[rounds + r] = t[2 * rounds + r] / t[3 * rounds + r];
    }
    const char* names[4] = {"wc_assemble (AVX rows)", "wc_assemble_scalar", "wc_eval_springs_at (AVX)", "wc_eval_springs_scalar"};
    printf("%d x %d sheet, %d springs, 1 thread, %d rounds of %d calls\n", n, n, m->n_springs, rounds, calls);
    printf("| kernel | median us | min us |\n|---|---|---|\n");
    for (int w = 0; w < 4; ++w) {
        qsort(t + w * rounds, rounds, sizeof(double), cmp_double);
        printf("| %s | %.1f | %.1f |\n", names[w], t[w * rounds + rounds / 2], t[w * rounds]);
    }
    qsort(ratio, rounds, sizeof(double), cmp_double);
    qsort(ratio + rounds, rounds, sizeof(double), cmp_double);
    printf("median ratio AVX / scalar: assembly %.3f, springs %.3f\n", ratio[rounds / 2], ratio[rounds + rounds / 2]);
    free(t), free(ratio), free(c.A), free(c.b), free(c.f), free(c.v), free(c.se);
    free_scene(&sc);
    return 0;
}
