/* The GPU's BDF2 and TR-BDF2 coefficients (gpu/solver integ_prepare.glsl, the he, v* and mom
 * terms of springs.glsl and assemble_b.glsl, TR-BDF2's implicit air in air_lump.glsl and
 * assemble_a.glsl) against core's (core/bdf2.c, core/step.c's prepare) on the same input, on a
 * real EGL context (llvmpipe without a GPU): the assembled A and b of a BDF2 substep with a
 * valid, perturbed history (x_{n-1}, v_{n-1}: the xb, v* and mom terms all non-zero) and of
 * TR-BDF2's stage 1 with air drag (mom = he f0 / m; A += he L), for a hanging sheet stepped a few
 * frames on the CPU, and the line search's potential change of that stage against core's
 * wc_newton_potential. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "gpu_test_device.h"
#include "newton.h"
#include "step.h"
#include "test_support.h"
#include "wg_sim.h"

#define SHEET 13

static wg_gl_context* gl;
static wg_device* dev;

/* A hanging sheet pinned at its two top corners with the given integrator, one substep a frame,
 * stepped 4 frames of 1/30 s on the CPU; its state and history then perturbed by up to 1 cm and
 * 1 cm/s (v_{n-1} by up to 1 m/s, so that BDF2's M mom stands out of b's rounding) and rounded
 * to float (what the GPU's textures hold). */
static wc_state* sheet_state(wc_model* m, wc_integrator integ, int newton) {
    if (!ts_sheet(m, SHEET, 1.0, 1.0, 1, 1.0)) return NULL;
    wc_sim_def def = wc_default_sim_def();
    def.solver.type = WC_SOLVER_PCG;
    def.solver.preconditioner = WC_PRECOND_BLOCK_JACOBI;
    def.integrator = integ;
    def.substeps = 1;
    def.newton_iterations = newton;
    def.line_search = newton > 1;
    def.max_colliders = 0;
    def.sleep_speed = 0.0;
    wc_state* s = NULL;
    wc_diag d = {0};
    if (wc_state_create(&s, m, &def, NULL, &d) != WC_OK) {
        fprintf(stderr, "state: %s\n", d.message);
        return NULL;
    }
    wc_pin pins[2] = {{ts_sheet_particle(m, SHEET, 0, SHEET - 1), {0, 0, 0}, {0, 0, 0}},
                      {ts_sheet_particle(m, SHEET, SHEET - 1, SHEET - 1), {0, 0, 0}, {0, 0, 0}}};
    for (int k = 0; k < 2; ++k) memcpy(pins[k].target, s->x + 3 * pins[k].particle, sizeof pins[k].target);
    wc_state_set_pins(s, pins, 2, &d);
    for (int f = 0; f < 4; ++f) CHECK(wc_step_frame(s, 1.0 / 30.0, NULL, &d) == WC_OK);
    srand(11);
    double* arrays[] = {s->x, s->v, s->x_prev, s->v_prev};
    for (int a = 0; a < 4; ++a)
        for (int k = 0; k < 3 * m->n_particles; ++k)
            arrays[a][k] = (float)(arrays[a][k] + 0.01 * ((double)rand() / RAND_MAX - 0.5));
    for (int k = 0; k < 3 * m->n_particles; ++k) {
        s->v_prev[k] = (float)(s->v_prev[k] + 2.0 * ((double)rand() / RAND_MAX - 0.5));   /* BDF2's mom, ~0.3 m/s */
        s->dv[k] = (float)s->dv[k];
    }
    for (int k = 0; k < s->n_pins; ++k)
        for (int c = 0; c < 3; ++c) s->pins[k].target[c] = s->pin_from[3 * k + c] = (float)s->x[3 * pins[k].particle + c];
    return s;
}

/* A and b of the next substep on the GPU against core's. */
static void compare_system(const char* what, const wc_model* m, wc_state* s) {
    wc_diag d = {0};
    wg_sim* g = NULL;
    CHECK(wg_sim_create(dev, s, NULL, &g, &d) == WC_OK);
    if (!g) {
        fprintf(stderr, "%s: %s\n", what, d.message);
        return;
    }
    int n = m->n_particles, nb = m->pattern.n_blocks;
    const double h = 1.0 / 30.0;
    double* A = calloc((size_t)nb * 9, sizeof(double));
    double* b = calloc((size_t)n * 3, sizeof(double));
    wc_integ ig;
    wc_integ_coefficients(s, h, 1, &ig);
    CHECK(wg_sim_debug_prepare(g, s, h, 1.0, A, b, NULL, NULL, NULL, NULL, &d) == WC_OK);
    wc_step_stats st;
    memset(&st, 0, sizeof st);
    wc_substep_prepare(s, h, 1.0, &st);
    /* float rounds each spring's term k (l - r) at ~6e-8 k l: b's error relative to he k l or to
       b's largest entry (the momentum terms), A's to its largest entry (test_gpu_solver.c) */
    double kl = 0.0, mom = 0.0, mmom = 0.0;
    for (int k = 0; k < m->n_springs; ++k) {
        const wc_spring* sp = &m->springs[k];
        kl = fmax(kl, m->material.k[sp->type] * sp->rest);
    }
    for (int k = 0; k < 3 * n; ++k) {
        mom = fmax(mom, fabs(s->mom[k]));
        mmom = fmax(mmom, m->mass[k / 3] * fabs(s->mom[k]));
    }
    double ea = ts_max_diff(A, s->A, 9 * nb) / ts_max_abs(s->A, 9 * nb);
    double eb = ts_max_diff(b, s->b, 3 * n) / fmax(ig.he * kl, ts_max_abs(s->b, 3 * n));
    double eb_abs = ts_max_diff(b, s->b, 3 * n);
    printf("  %s (h %.4g s, he %.4g s, largest |mom| %.3g m/s, |M mom| %.3g N s): A relative error %.2e, b %.2e "
           "(%.3g N s, %.2e of |M mom|)\n", what, ig.h, ig.he, mom, mmom, ea, eb, eb_abs, eb_abs / mmom);
    CHECK(ig.bdf2 || ig.stage == 1);
    CHECK(mom > 1e-4);   /* the momentum term is in b */
    CHECK(ea < 1e-5);
    CHECK(eb < 1e-5);
    CHECK(eb_abs < 1e-2 * mmom);   /* the momentum term itself, not hidden in the springs' rounding */
    if (ig.stage == 1 && s->def.newton_iterations > 1) {
        /* the potential's change between two iterates 0.05 m/s apart (the sew test's measure) */
        double* wa = calloc((size_t)n * 3, sizeof(double));
        double* wb = calloc((size_t)n * 3, sizeof(double));
        srand(5);
        for (int k = 0; k < 3 * n; ++k) {
            wa[k] = s->dv[k] + 0.05 * ((double)rand() / RAND_MAX - 0.5);
            wb[k] = (float)(wa[k] + 0.05 * ((double)rand() / RAND_MAX - 0.5));
            wa[k] = (float)wa[k];
        }
        wc_newton_capture(s);
        double cpu = wc_newton_potential(s, &ig, wb) - wc_newton_potential(s, &ig, wa);
        double gpu = wg_sim_debug_phi_change(g, s, h, wa, wb);
        printf("  %s: potential change GPU %.6g J, CPU %.6g J (relative %.2e)\n", what, gpu, cpu,
               fabs(gpu - cpu) / fabs(cpu));
        CHECK(fabs(gpu - cpu) < 1e-3 * fabs(cpu));
        free(wa), free(wb);
    }
    free(A), free(b);
    wg_sim_destroy(g);
}

static void test_bdf2_system(void) {
    wc_model m;
    wc_state* s = sheet_state(&m, WC_INTEGRATOR_BDF2, 1);
    CHECK(s != NULL);
    if (!s) return;
    CHECK(s->hist_valid && s->hist_h == 1.0 / 30.0);
    compare_system("BDF2 substep", &m, s);
    wc_state_destroy(s);
    wc_model_free(&m);
}

static void test_trbdf2_stage1_system(void) {
    wc_model m;
    wc_state* s = sheet_state(&m, WC_INTEGRATOR_TRBDF2, 2);
    CHECK(s != NULL);
    if (!s) return;
    CHECK(s->def.air.normal_drag > 0.0);   /* the implicit air's A += he L is compared too */
    compare_system("TR-BDF2 stage 1 with air", &m, s);
    wc_state_destroy(s);
    wc_model_free(&m);
}

int main(void) {
    if (!tg_gpu_open(&gl, &dev)) return 1;
    RUN_TEST(test_bdf2_system);
    RUN_TEST(test_trbdf2_stage1_system);
    tg_gpu_close(gl, dev);
    return TEST_SUMMARY();
}
