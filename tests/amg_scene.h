/* Real filtered cloth systems for the multigrid tests (test_amg.c, test_amg_setup.c): an n x n
 * sheet hanging from two corners (HANG), dropped on a sphere (DRAPE) or held by line pins (LINE),
 * after `frames` direct frames, with the next substep's system prepared in s->A, s->b, s->filter. */
#ifndef WEFT_TESTS_AMG_SCENE_H
#define WEFT_TESTS_AMG_SCENE_H
#include <string.h>
#include "check.h"
#include "solver_impl.h"
#include "step.h"
#include "test_support.h"

typedef struct scene {
    wc_model m;
    wc_state* s;
} scene;

enum { HANG = 0, DRAPE = 1, LINE = 2 };

/* A sheet of n x n after `frames` frames at one direct step per 1/30 s, then the next substep's
 * system prepared in s->A, s->b, s->filter. */
static int make_scene(scene* sc, int n, double k_scale, int kind, int frames) {
    memset(sc, 0, sizeof *sc);
    if (!ts_sheet(&sc->m, n, 1.0, 1.0, 0, k_scale)) return 0;
    wc_sim_def def = wc_default_sim_def();
    def.solver.type = WC_SOLVER_DIRECT;
    def.threads = 1;
    def.sleep_speed = 0;
    wc_diag d = {0};
    if (wc_state_create(&sc->s, &sc->m, &def, NULL, &d) != WEFT_OK) return 0;
    wc_state* s = sc->s;
    if (kind == DRAPE) {
        wc_collider c = {0};
        c.type = WC_COLLIDER_SPHERE;
        c.radius = 0.3;
        c.center[1] = 0.65;
        c.thickness = 0.005;
        c.friction = 0.3;
        CHECK(wc_state_set_colliders(s, &c, 1, &d) == WEFT_OK);
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
        CHECK(wc_state_set_pins(s, pins, np, &d) == WEFT_OK);
    }
    for (int f = 0; f < frames; ++f) wc_step_frame(s, 1.0 / 30.0, NULL, &d);
    wc_step_stats st = {0};
    wc_substep_prepare(s, 1.0 / 30.0, 1.0, &st);
    return 1;
}

static void free_scene(scene* sc) {
    wc_state_destroy(sc->s);
    wc_model_free(&sc->m);
}

/* A PCG solver with the multigrid preconditioner, relative tolerance tol, at most 500 iterations
 * (alloc: NULL for the default allocator). */
static wc_solver* amg_solver(const wc_model* m, double tol, const wc_allocator* alloc) {
    wc_solver_opts o = wc_default_solver_opts();
    o.preconditioner = WC_PRECOND_AMG;
    o.tolerance = tol;
    o.max_iterations = 500;
    wc_solver* sv = NULL;
    wc_diag d = {0};
    CHECK(wc_solver_create(&sv, m, &o, 1, alloc, &d) == WEFT_OK);
    return sv;
}

#endif
