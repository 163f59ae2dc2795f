/* Real filtered cloth systems for the preconditioner tests (test_amg.c, test_amg_setup.c,
 * test_precond_ic.c, ...): an n x n sheet hanging from two corners (HANG), dropped on a sphere
 * (DRAPE) or held by line pins (LINE), after `frames` direct frames, with the next substep's
 * system prepared in s->A, s->b, s->filter; and a counting allocator. */
#ifndef WEFT_TESTS_AMG_SCENE_H
#define WEFT_TESTS_AMG_SCENE_H
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "bsr_rows.h"
#include "check.h"
#include "solve_kernels.h"
#include "step.h"
#include "test_support.h"

typedef struct scene {
    wc_model m;
    wc_state* s;
} scene;

enum { HANG = 0, DRAPE = 1, LINE = 2 };

/* A sheet of n x n after `frames` frames at one direct step per 1/30 s, then the next substep's
 * system prepared in s->A, s->b, s->filter. */
static inline int make_scene(scene* sc, int n, double k_scale, int kind, int frames) {
    memset(sc, 0, sizeof *sc);
    if (!ts_sheet(&sc->m, n, 1.0, 1.0, 0, k_scale)) return 0;
    wc_sim_def def = wc_default_sim_def();
    def.solver.type = WC_SOLVER_DIRECT;
    def.threads = 1;
    def.sleep_speed = 0;
    wc_diag d = {0};
    if (wc_state_create(&sc->s, &sc->m, &def, NULL, &d) != WC_OK) return 0;
    wc_state* s = sc->s;
    if (kind == DRAPE) {
        wc_collider c = {0};
        c.type = WC_COLLIDER_SPHERE;
        c.radius = 0.3;
        c.center[1] = 0.65;
        c.thickness = 0.005;
        c.friction = 0.3;
        CHECK(wc_state_set_colliders(s, &c, 1, &d) == WC_OK);
    } else {
        wc_pin pins[3] = {{0}};
        pins[0].particle = ts_sheet_particle(&sc->m, n, 0, 0);
        pins[1].particle = ts_sheet_particle(&sc->m, n, n - 1, 0);
        pins[2].particle = ts_sheet_particle(&sc->m, n, n / 2, 0);
        int np = kind == LINE ? 3 : 2;
        for (int k = 0; k < np; ++k) memcpy(pins[k].target, s->x + 3 * pins[k].particle, sizeof pins[k].target);
        if (kind == LINE) { /* the corners slide along X, the middle along Z */
            pins[0].free_axis[0] = pins[1].free_axis[0] = 1.0;
            pins[2].free_axis[2] = 1.0;
        }
        CHECK(wc_state_set_pins(s, pins, np, &d) == WC_OK);
    }
    for (int f = 0; f < frames; ++f) wc_step_frame(s, 1.0 / 30.0, NULL, &d);
    wc_step_stats st = {0};
    wc_substep_prepare(s, 1.0 / 30.0, 1.0, &st);
    return 1;
}

static inline void free_scene(scene* sc) {
    wc_state_destroy(sc->s);
    wc_model_free(&sc->m);
}

/* An allocator over malloc that counts its calls in a counter (wc_allocator a = {count_alloc,
 * count_free, &c}): the tests that solves allocate nothing and destroy frees everything. */
typedef struct counter { long allocs, frees; } counter;
static inline void* count_alloc(size_t n, void* u) { return ++((counter*)u)->allocs, malloc(n); }
static inline void count_free(void* ptr, void* u) { ++((counter*)u)->frees, free(ptr); }

/* A PCG solver with preconditioner pre, relative tolerance tol, at most max_iterations (alloc:
 * NULL for the default allocator). */
static inline wc_solver* pcg_solver(const wc_model* m, wc_precond_type pre, double tol, int max_iterations,
                                    const wc_allocator* alloc) {
    wc_solver_opts o = wc_default_solver_opts();
    o.preconditioner = pre;
    o.tolerance = tol;
    o.max_iterations = max_iterations;
    wc_solver* sv = NULL;
    wc_diag d = {0};
    CHECK(wc_solver_create(&sv, m, &o, 1, alloc, &d) == WC_OK);
    return sv;
}

/* ... with the multigrid preconditioner, at most 500 iterations */
static inline wc_solver* amg_solver(const wc_model* m, double tol, const wc_allocator* alloc) {
    return pcg_solver(m, WC_PRECOND_AMG, tol, 500, alloc);
}

/* Symmetry and positive definiteness of S M^-1 S (what PCG sees) on random vectors, after a setup
 * on s's system (test_amg.c, test_amg_cross.c): the largest relative asymmetry |u.Mv - v.Mu| /
 * (|u.Mv| + |v.Mu|) and the smallest cosine between v and M^-1 v over 6 trials. */
static inline void amg_spd_measure(wc_amg* amg, const wc_state* s, double* worst_sym_out, double* min_ratio_out) {
    int n = s->model->n_particles, n3 = 3 * n;
    wc_par par;
    wc_par_init(&par, 1);
    double *u = calloc(n3, sizeof *u), *v = calloc(n3, sizeof *v), *Mu = calloc(n3, sizeof *Mu),
           *Mv = calloc(n3, sizeof *Mv);
    uint64_t st = 12345;
    double worst_sym = 0, min_ratio = INFINITY;
    for (int trial = 0; trial < 6; ++trial) {
        for (int k = 0; k < n3; ++k) {
            st = st * 6364136223846793005ull + 1442695040888963407ull;
            u[k] = (double)(st >> 11) / 9007199254740992.0 - 0.5;
            st = st * 6364136223846793005ull + 1442695040888963407ull;
            v[k] = (double)(st >> 11) / 9007199254740992.0 - 0.5;
        }
        if (trial % 2) /* smooth vectors too (the coarse levels' business) */
            for (int i = 0; i < n; ++i)
                for (int c = 0; c < 3; ++c) v[3 * i + c] = sin(7.0 * s->model->rest_pos[3 * i] + c) + 0.1 * v[3 * i + c];
        for (int i = 0; i < n; ++i) {
            wc_filter_apply(&s->filter, i, u + 3 * i, u + 3 * i);
            wc_filter_apply(&s->filter, i, v + 3 * i, v + 3 * i);
        }
        wc_amg_apply(amg, u, Mu, &par);
        wc_amg_apply(amg, v, Mv, &par);
        double uMv = 0, vMu = 0, vMv = 0, vv = 0, Mvn = 0;
        for (int i = 0; i < n; ++i) { /* filter the outputs: S M^-1 S */
            wc_filter_apply(&s->filter, i, Mu + 3 * i, Mu + 3 * i);
            wc_filter_apply(&s->filter, i, Mv + 3 * i, Mv + 3 * i);
        }
        for (int k = 0; k < n3; ++k) {
            uMv += u[k] * Mv[k];
            vMu += v[k] * Mu[k];
            vMv += v[k] * Mv[k];
            vv += v[k] * v[k];
            Mvn += Mv[k] * Mv[k];
        }
        double sym = fabs(uMv - vMu) / (fabs(uMv) + fabs(vMu) + 1e-300);
        if (sym > worst_sym) worst_sym = sym;
        double ratio = vMv / sqrt(vv * Mvn); /* cosine between v and M^-1 v: > 0 for SPD */
        if (ratio < min_ratio) min_ratio = ratio;
    }
    *worst_sym_out = worst_sym;
    *min_ratio_out = min_ratio;
    free(u);
    free(v);
    free(Mu);
    free(Mv);
}

/* The V-cycle on its double iterates (opts.single_x off) exactly symmetric (1e-10) and positive;
 * where the float-iterate V-cycle runs (single_x, AVX2: docs/bench/vcycle_float.md) also that
 * one, symmetric to float's rounding amplified by the levels' conditioning (measured up to 2.5e-3
 * on the tests' systems; bound 1e-2) and positive. */
static inline void amg_check_spd(wc_amg* amg, const wc_state* s, const char* what) {
    wc_par par;
    wc_par_init(&par, 1);
    wc_amg_setup(amg, s->A, &s->filter, &par);
    const int fx = amg->opts.single && amg->opts.single_x && wc_bsr_rows_fx_vector() != NULL;
    const int keep = amg->opts.single_x;
    double sym, ratio;
    amg->opts.single_x = 0;
    amg_spd_measure(amg, s, &sym, &ratio);
    amg->opts.single_x = keep;
    printf("  %-34s symmetry %.1e, min cos(v, M^-1 v) %.3f", what, sym, ratio);
    CHECK(sym < 1e-10);
    CHECK(ratio > 0);
    if (fx) {
        amg_spd_measure(amg, s, &sym, &ratio);
        printf("; float iterates %.1e, %.3f", sym, ratio);
        CHECK(sym < 1e-2);
        CHECK(ratio > 0);
    }
    printf("\n");
}

#endif
