/* Newton's terms with colliders on the GPU (gpu/solver/wg_newton.c, newton_friction.glsl, the
 * friction terms of assemble_a.glsl, newton_gradient.glsl and newton_phi_particles.glsl) against
 * core's (core/newton.c) on the same input, on a real EGL context (llvmpipe without a GPU): a
 * sheet draped over a sphere with friction on the CPU at Newton 2 with the line search, moved 1 mm
 * off the sphere's shell, its velocities then stirred along the sphere by up to 0.3 m/s so that
 * part of the contacts slide (kinetic friction's frozen Fa, Fb non-zero) and part let go, with the sphere's friction raised to 1.5, rounded to float; the next substep prepared on both:
 * friction's frozen terms (Fa on A's diagonal blocks, Fb), Newton's system at an iterate (A with
 * Fa, g = -grad Phi), and the line search's potential change between two iterates with
 * friction's share in it, against wc_newton_potential in double. */
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

/* The draped sheet (25 frames of 1/30 s on the CPU), 1 mm off the shell, its velocities stirred
 * tangentially by up to 0.3 m/s, x, v and dv rounded to float (what the GPU's textures hold). */
static wc_state* draped_state(wc_model* m) {
    wc_sim_def def = wc_default_sim_def();
    def.solver.type = WC_SOLVER_PCG;
    def.solver.preconditioner = WC_PRECOND_BLOCK_JACOBI;
    def.substeps = 1;
    def.newton_iterations = 2;
    def.line_search = 1;
    def.max_colliders = 1;
    def.sleep_speed = 0.0;
    wc_state* s = ts_draped(m, SHEET, &def, 25);
    if (!s) return NULL;
    /* a rough sphere from now on: friction's share of the potential stands out of float's rounding */
    wc_collider c = s->colliders[0];
    c.friction = 1.5;
    wc_diag d = {0};
    CHECK(wc_state_set_colliders(s, &c, 1, &d) == WC_OK);
    srand(3);
    int n = m->n_particles;
    for (int i = 0; i < n; ++i) {
        double* x = s->x + 3 * i;
        double r = sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]), u[3], t[3];
        for (int c = 0; c < 3; ++c) u[c] = (double)rand() / RAND_MAX - 0.5;
        double un = (u[0] * x[0] + u[1] * x[1] + u[2] * x[2]) / (r * r), ut = 0.0;
        for (int c = 0; c < 3; ++c) t[c] = u[c] - un * x[c];   /* along the sphere */
        for (int c = 0; c < 3; ++c) ut += t[c] * t[c];
        double speed = 0.3 * (double)rand() / RAND_MAX / sqrt(ut);
        for (int c = 0; c < 3; ++c) s->v[3 * i + c] += speed * t[c];
        /* 1 mm off the sphere's shell: no particle on the edge of the contacts' tests, where
           float and double may decide apart (wg_contacts.c, SLOP) */
        for (int c = 0; c < 3; ++c) x[c] *= 1.0 + 1e-3 / r;
    }
    for (int k = 0; k < 3 * n; ++k) {
        s->x[k] = (float)s->x[k];
        s->v[k] = (float)s->v[k];
        s->dv[k] = (float)s->dv[k];
    }
    return s;
}

static void test_friction_terms(void) {
    wc_model m;
    wc_state* s = draped_state(&m);
    CHECK(s != NULL);
    if (!s) return;
    CHECK(s->contacts.active > 20);
    wc_diag d = {0};
    wg_sim* g = NULL;
    CHECK(wg_sim_create(dev, s, NULL, &g, &d) == WC_OK);
    if (!g) {
        fprintf(stderr, "wg_sim_create: %s\n", d.message);
        return;
    }
    const int n = m.n_particles, nb = m.pattern.n_blocks;
    const double h = 1.0 / 30.0;
    double* A = calloc((size_t)nb * 9, sizeof(double));
    double* grad = calloc((size_t)n * 3, sizeof(double));
    double* fa = calloc((size_t)n * 9, sizeof(double));
    double* fb = calloc((size_t)n * 3, sizeof(double));
    double* fa_cpu = calloc((size_t)n * 9, sizeof(double));
    double* wa = calloc((size_t)n * 3, sizeof(double));
    double* wb = calloc((size_t)n * 3, sizeof(double));
    /* the iterate: the last substep's dv (the warm start) moved by up to 2.5 cm/s, in float */
    srand(5);
    for (int k = 0; k < 3 * n; ++k) {
        wa[k] = (float)(s->dv[k] + 0.05 * ((double)rand() / RAND_MAX - 0.5));
        wb[k] = (float)(wa[k] + 0.05 * ((double)rand() / RAND_MAX - 0.5));
    }
    CHECK(wg_sim_debug_prepare(g, s, h, 1.0, NULL, NULL, NULL, NULL, NULL, NULL, &d) == WC_OK);
    CHECK(wg_sim_debug_newton_system(g, s, h, wa, A, grad, fa, fb, &d) == WC_OK);
    double gpu_change = wg_sim_debug_phi_change(g, s, h, wa, wb);

    wc_step_stats st;
    memset(&st, 0, sizeof st);
    wc_substep_prepare(s, h, 1.0, &st);   /* contacts, assembly, capture, friction */
    wc_integ ig;
    wc_integ_coefficients(s, h, 1, &ig);
    wc_newton_debug_system(s, &ig, wa, s->def.compression);
    for (int i = 0; i < n; ++i) memcpy(fa_cpu + 9 * i, s->nw_fa + 9 * (size_t)i, 9 * sizeof(double));

    /* friction's terms: which particles slide (Fa != 0) on both, and their values */
    int slide_cpu = 0, slide_gpu = 0, differ = 0, contacts = 0;
    for (int i = 0; i < n; ++i) {
        int a = ts_max_abs(fa_cpu + 9 * i, 9) > 0.0, b = ts_max_abs(fa + 9 * i, 9) > 0.0;
        slide_cpu += a;
        slide_gpu += b;
        differ += a != b;
        contacts += s->contacts.collider[2 * i] >= 0;
    }
    double fa_max = ts_max_abs(fa_cpu, 9 * n), fb_max = ts_max_abs(s->nw_fb, 3 * n);
    double efa = ts_max_diff(fa, fa_cpu, 9 * n), efb = ts_max_diff(fb, s->nw_fb, 3 * n);
    /* the differences are taken in float against A's diagonal blocks (the mass, h^2 k) and b */
    double amax = ts_max_abs(s->A, 9 * nb), bmax = ts_max_abs(s->b, 3 * n);
    printf("  friction's terms: %d sliding particles on the CPU, %d on the GPU (%d differ) of %d in contact; "
           "|Fa| up to %.3g kg, error %.2e (%.2e of A's largest entry); |Fb| up to %.3g N s, error %.2e\n",
           slide_cpu, slide_gpu, differ, contacts, fa_max, efa, efa / amax, fb_max, efb);
    CHECK(slide_cpu >= 10);
    CHECK_EQ_INT(differ, 0);
    CHECK(efa < 1e-6 * amax + 1e-4 * fa_max);
    CHECK(efb < 1e-6 * bmax + 1e-4 * fb_max);

    /* Newton's system at wa: A (+ Fa) and g = -grad Phi(wa) (+ Fb - Fa wa) */
    double kl = 0.0;
    for (int k = 0; k < m.n_springs; ++k) kl = fmax(kl, m.material.k[m.springs[k].type] * m.springs[k].rest);
    double ea = ts_max_diff(A, s->A, 9 * nb) / ts_max_abs(s->A, 9 * nb);
    double eg = ts_max_diff(grad, s->nw_g, 3 * n) / fmax(h * kl, ts_max_abs(s->nw_g, 3 * n));
    /* friction's share of g, to show it is not lost in the error */
    double share = 0.0;
    for (int i = 0; i < n; ++i) {
        const double* F = fa_cpu + 9 * i;
        const double* w = wa + 3 * i;
        for (int r = 0; r < 3; ++r)
            share = fmax(share, fabs(s->nw_fb[3 * i + r] - (F[3 * r] * w[0] + F[3 * r + 1] * w[1] + F[3 * r + 2] * w[2])));
    }
    printf("  Newton's system at an iterate: A relative error %.2e, g %.2e (absolute %.2e; friction's share of g up to "
           "%.3g N s)\n", ea, eg, ts_max_diff(grad, s->nw_g, 3 * n), share);
    CHECK(ea < 1e-5);
    CHECK(eg < 1e-5);
    CHECK(ts_max_diff(grad, s->nw_g, 3 * n) < 0.1 * share);   /* friction's terms are in g */

    /* the potential's change, and friction's share of it */
    double cpu_change = wc_newton_potential(s, &ig, wb) - wc_newton_potential(s, &ig, wa);
    double fric = 0.0;
    for (int i = 0; i < n; ++i) {
        const double* F = fa_cpu + 9 * i;
        for (int r = 0; r < 3; ++r) {
            double Fb = 0.0, Fa = 0.0;
            for (int c = 0; c < 3; ++c) {
                Fb += F[3 * r + c] * wb[3 * i + c];
                Fa += F[3 * r + c] * wa[3 * i + c];
            }
            fric += 0.5 * (wb[3 * i + r] * Fb - wa[3 * i + r] * Fa) - s->nw_fb[3 * i + r] * (wb[3 * i + r] - wa[3 * i + r]);
        }
    }
    printf("  potential change: GPU %.6g J, CPU %.6g J (relative %.2e); friction's share %.3g J\n", gpu_change,
           cpu_change, fabs(gpu_change - cpu_change) / fabs(cpu_change), fric);
    CHECK(fabs(gpu_change - cpu_change) < 1e-3 * fabs(cpu_change));
    CHECK(fabs(gpu_change - cpu_change) < 0.1 * fabs(fric));   /* and in the potential */
    free(A), free(grad), free(fa), free(fb), free(fa_cpu), free(wa), free(wb);
    wg_sim_destroy(g);
    wc_state_destroy(s);
    wc_model_free(&m);
}

int main(void) {
    if (!tg_gpu_open(&gl, &dev)) return 1;
    RUN_TEST(test_friction_terms);
    tg_gpu_close(gl, dev);
    return TEST_SUMMARY();
}
