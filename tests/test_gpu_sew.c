/* The GPU's seam springs (gpu/solver springs.glsl, check_springs.glsl) against core's
 * (core/forces.c seam_blocks, wc_spring_energy_at) on the same input, on a real EGL context
 * (llvmpipe without a GPU): the assembled A and b of a substep and the springs' checks (elastic
 * energy, strain) for the sewn tube (seams by distance, vertex to edge: weights 1-t, t and the
 * negative -t(1-t)) and for the host-pair sheets at points of their rest-length ramp (pulling,
 * slack, closed), each at a perturbed state so that every seam is stretched its own way; and the
 * line search's measure of the incremental potential's change between two iterates
 * (wg_newton.c) against core's wc_newton_potential, seams included. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "gpu_test_device.h"
#include "forces.h"
#include "newton.h"
#include "sew_sheets.h"
#include "sew_tube.h"
#include "step.h"
#include "test_support.h"
#include "wg_sim.h"

static wg_gl_context* gl;
static wg_device* dev;

/* A state of m with the given pins (particles, held where they are), stepped `warm` frames on the
 * CPU, then moved by up to `noise` metres and m/s per coordinate and rounded to float (what the
 * GPU's textures hold), so both backends see the same input. */
static wc_state* perturbed_state(wc_model* m, const int* pinned, int n_pins, int warm, double noise, int newton) {
    wc_sim_def def = wc_default_sim_def();
    def.solver.type = WC_SOLVER_PCG;
    def.solver.preconditioner = WC_PRECOND_BLOCK_JACOBI;
    def.newton_iterations = newton;
    def.line_search = newton > 1;
    def.max_colliders = 0;   /* no colliders: the sewn system alone */
    def.sleep_speed = 0.0;
    wc_state* s = NULL;
    wc_diag d = {0};
    if (wc_state_create(&s, m, &def, NULL, &d) != WC_OK) {
        fprintf(stderr, "state: %s\n", d.message);
        return NULL;
    }
    wc_pin pins[SHEET_N];
    for (int k = 0; k < n_pins; ++k) {
        memset(&pins[k], 0, sizeof pins[k]);
        pins[k].particle = pinned[k];
        memcpy(pins[k].target, s->x + 3 * pinned[k], sizeof pins[k].target);
    }
    if (n_pins > 0) wc_state_set_pins(s, pins, n_pins, &d);
    for (int f = 0; f < warm; ++f) CHECK(wc_step_frame(s, 1.0 / 30.0, NULL, &d) == WC_OK);
    srand(7);
    for (int k = 0; k < 3 * m->n_particles; ++k) {
        s->x[k] = (float)(s->x[k] + noise * ((double)rand() / RAND_MAX - 0.5));
        s->v[k] = (float)(s->v[k] + noise * ((double)rand() / RAND_MAX - 0.5));
        s->dv[k] = (float)s->dv[k];
    }
    for (int k = 0; k < s->n_pins; ++k)
        for (int c = 0; c < 3; ++c) s->pins[k].target[c] = s->pin_from[3 * k + c] = (float)s->x[3 * pinned[k] + c];
    return s;
}

/* A, b and the springs' checks of one substep on the GPU against core's at s->seam_scale. */
static void compare_system(const char* what, const wc_model* m, wc_state* s) {
    wc_diag d = {0};
    wg_sim* g = NULL;
    CHECK(wg_sim_create(dev, s, NULL, &g, &d) == WC_OK);
    if (!g) {
        fprintf(stderr, "%s: %s\n", what, d.message);
        return;
    }
    int n = m->n_particles, nb = m->pattern.n_blocks;
    double h = 1.0 / 30.0;
    double* A = calloc((size_t)nb * 9, sizeof(double));
    double* b = calloc((size_t)n * 3, sizeof(double));
    double e_gpu = 0.0, strain_gpu = 0.0;
    wg_sim_debug_spring_checks(g, s, &e_gpu, &strain_gpu);
    CHECK(wg_sim_debug_prepare(g, s, h, 1.0, A, b, NULL, NULL, NULL, NULL, &d) == WC_OK);
    wc_step_stats st;
    memset(&st, 0, sizeof st);
    wc_substep_prepare(s, h, 1.0, &st);
    /* float rounds each spring's term k w (l - r) at ~6e-8 of k |w| l: b's error is relative to
       h k |w| l (test_gpu_solver.c), A's to its largest entry, the energy's to the sum of the
       springs' |w| k e^2 / 2 */
    double kl = 0.0, e_abs = 0.0;
    int slack = 0, pulling = 0;
    for (int k = 0; k < m->n_springs; ++k) {
        const wc_spring* sp = &m->springs[k];
        double L[3];
        for (int c = 0; c < 3; ++c) L[c] = s->x[3 * sp->a + c] - s->x[3 * sp->b + c];
        double l = sqrt(L[0] * L[0] + L[1] * L[1] + L[2] * L[2]);
        double kw = m->material.k[sp->type] * fabs(sp->w), e = wc_spring_extension(sp, l, s->seam_scale);
        kl = fmax(kl, kw * fmax(sp->rest, l));
        e_abs += 0.5 * kw * e * e;
        if (sp->type == WC_SPRING_SEAM) {
            slack += e == 0.0;
            pulling += e > 0.0;
        }
    }
    double e_cpu = wc_spring_energy_at(m, s->x, s->seam_scale), strain_cpu = wc_max_stretch_strain(m, s->x);
    double ea = ts_max_diff(A, s->A, 9 * nb) / ts_max_abs(s->A, 9 * nb), eb = ts_max_diff(b, s->b, 3 * n) / (h * kl);
    double ee = fabs(e_gpu - e_cpu) / e_abs;
    printf("  %s (seam scale %.2f, %d seam springs pulling, %d slack): A relative error %.2e, b %.2e (of h k l), "
           "energy %.6g J vs %.6g J (%.2e of the terms), strain %.3g vs %.3g\n",
           what, s->seam_scale, pulling, slack, ea, eb, e_gpu, e_cpu, ee, strain_gpu, strain_cpu);
    CHECK(pulling > 0);
    CHECK(ea < 1e-5);
    CHECK(eb < 1e-5);
    CHECK(ee < 1e-5);
    CHECK(fabs(strain_gpu - strain_cpu) < 1e-5);
    free(A), free(b);
    wg_sim_destroy(g);
}

/* The tube, sewn by distance: 3 pair springs a seam, some of negative weight. */
static void test_tube(void) {
    wc_model m;
    wc_diag d = {0};
    wc_model_def def = wc_default_model_def();
    def.sew_distance = SEW;
    CHECK_EQ_INT(tube_model(&m, &def, &d), WC_OK);
    CHECK_EQ_INT(m.n_seams, TUBE_SEAMS);
    int negative = 0;
    for (int k = m.spring_type_start[WC_SPRING_SEAM]; k < m.spring_type_start[WC_SPRING_SEAM + 1]; ++k)
        negative += m.springs[k].w < 0.0;
    CHECK(negative > 0);
    int top[2] = {m.host_to_particle[tube_vertex(0, 0, 0)], m.host_to_particle[tube_vertex(0, 0, NW)]};
    wc_state* s = perturbed_state(&m, top, 2, 3, 0.01, 1);
    CHECK(s != NULL);
    if (s) compare_system("sewn tube", &m, s);
    wc_state_destroy(s);
    wc_model_free(&m);
}

/* The host-pair sheets 0.1 m apart: the ramp's start (slack at rest length), its middle and its
 * end (closed: linear springs). */
static void test_host_pairs(void) {
    enum { NV = 2 * SHEET_N * SHEET_N, NF = 2 * (SHEET_N - 1) * (SHEET_N - 1) };
    double pos[3 * NV];
    int sizes[NF], idx[4 * NF], sa[SHEET_N], sb[SHEET_N];
    two_sheets(pos, sizes, idx, 0.1);
    for (int i = 0; i < SHEET_N; ++i) {
        sa[i] = i;
        sb[i] = SHEET_N * SHEET_N + i;
    }
    wc_source_mesh src;
    wc_diag d = {0};
    CHECK_EQ_INT(wc_source_mesh_from_arrays(&src, NULL, pos, NV, sizes, NF, idx, 1.0, &d), WC_OK);
    wc_model_def def = wc_default_model_def();
    def.n_seam_pairs = SHEET_N;
    def.seam_a = sa;
    def.seam_b = sb;
    wc_model m;
    CHECK_EQ_INT(wc_model_build(&m, &src, &def, NULL, &d), WC_OK);
    CHECK_EQ_INT(m.n_host_seams, SHEET_N);
    int top[SHEET_N];
    for (int i = 0; i < SHEET_N; ++i) top[i] = m.host_to_particle[i];
    static const double scales[] = {1.0, 0.5, 0.0};
    static const char* names[] = {"host pairs, ramp start", "host pairs, mid-ramp", "host pairs, closed"};
    for (int c = 0; c < 3; ++c) {
        wc_state* s = perturbed_state(&m, top, SHEET_N, 0, 0.04, 1);
        CHECK(s != NULL);
        if (!s) continue;
        s->seam_scale = scales[c];
        compare_system(names[c], &m, s);
        wc_state_destroy(s);
    }
    wc_model_free(&m);
    wc_source_mesh_free(&src);
}

/* Phi(wb) - Phi(wa) on the GPU (the line search's measure) against core's potential in double, for
 * iterates a Newton step apart (wa random, wb = wa + a smaller random step), and for a step of
 * one hundredth of that. */
static void test_potential_change(void) {
    wc_model m;
    wc_diag d = {0};
    wc_model_def def = wc_default_model_def();
    def.sew_distance = SEW;
    CHECK_EQ_INT(tube_model(&m, &def, &d), WC_OK);
    int top[2] = {m.host_to_particle[tube_vertex(0, 0, 0)], m.host_to_particle[tube_vertex(0, 0, NW)]};
    wc_state* s = perturbed_state(&m, top, 2, 3, 0.01, 2);
    CHECK(s != NULL);
    wg_sim* g = NULL;
    if (s) CHECK(wg_sim_create(dev, s, NULL, &g, &d) == WC_OK);
    if (!g) {
        fprintf(stderr, "%s\n", d.message);
        wc_state_destroy(s);
        wc_model_free(&m);
        return;
    }
    int n3 = 3 * m.n_particles;
    double h = 1.0 / 30.0;
    double* wa = calloc((size_t)n3, sizeof(double));
    double* wb = calloc((size_t)n3, sizeof(double));
    CHECK(wg_sim_debug_prepare(g, s, h, 1.0, NULL, NULL, NULL, NULL, NULL, NULL, &d) == WC_OK);
    wc_step_stats st;
    memset(&st, 0, sizeof st);
    wc_substep_prepare(s, h, 1.0, &st);   /* captures the frozen damping and f_ext (newton.h) */
    wc_integ ig;
    wc_integ_begin(s, h, &ig);
    srand(11);
    static const double steps[] = {0.05, 5e-4};
    for (int c = 0; c < 2; ++c) {
        for (int k = 0; k < n3; ++k) {
            wa[k] = (float)(0.1 * ((double)rand() / RAND_MAX - 0.5));
            wb[k] = (float)(wa[k] + steps[c] * ((double)rand() / RAND_MAX - 0.5));
        }
        double cpu = wc_newton_potential(s, &ig, wb) - wc_newton_potential(s, &ig, wa);
        double gpu = wg_sim_debug_phi_change(g, s, h, wa, wb);
        double rel = fabs(gpu - cpu) / fabs(cpu);
        printf("  sewn tube, iterates %.0e m/s apart: Phi change %.6g J on the GPU, %.6g J in double (%.2e of it)\n",
               steps[c], gpu, cpu, rel);
        CHECK(cpu != 0.0);
        CHECK(rel < 1e-3);
    }
    free(wa), free(wb);
    wg_sim_destroy(g);
    wc_state_destroy(s);
    wc_model_free(&m);
}

int main(void) {
    if (!tg_gpu_open(&gl, &dev)) return 1;
    RUN_TEST(test_tube);
    RUN_TEST(test_host_pairs);
    RUN_TEST(test_potential_change);
    tg_gpu_close(gl, dev);
    return TEST_SUMMARY();
}
