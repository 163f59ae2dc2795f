/* Sewing (core/sew.h): seams found by distance on a tube sewn from two panels whose seam vertices
 * pair vertex to edge, the seam springs' energy against the three-point formula (independent of
 * the pair-spring decomposition), their forces and Jacobian by finite differences, the tube
 * hanging by one panel, host seam pairs pulled shut from 0.3 m along their ramp, AMG iterations
 * with and without seams, and bad inputs refused by the model build. The public API, scenes and
 * `weft inspect --sew-distance` are in test_sew_api.c. */
#include <stdlib.h>
#include "check.h"
#include "forces.h"
#include "model.h"
#include "sew.h"
#include "step.h"
#include "test_support.h"
#include "sew_sheets.h"
#include "sew_tube.h"
#include "vec3.h"

static wc_model_def sew_def(double sew) {
    wc_model_def def = wc_default_model_def();
    def.sew_distance = sew;
    return def;
}

static double max_gap(const wc_model* m, const double* x) {
    double g = 0.0;
    for (int s = 0; s < m->n_seams; ++s) {
        double d = wc_seam_gap(&m->seams[s], x);
        if (d > g) g = d;
    }
    return g;
}

/* ---- seams found ----------------------------------------------------------------------------- */

static void test_tube_seams_found(void) {
    wc_model m;
    wc_diag d = {0};
    wc_model_def def = sew_def(0.0);
    CHECK_EQ_INT(tube_model(&m, &def, &d), WC_OK);
    CHECK_EQ_INT(m.report.components, 2);
    CHECK_EQ_INT(m.report.seams, 0);
    CHECK_EQ_INT(m.report.panels, 2);
    CHECK_EQ_INT(m.report.springs[WC_SPRING_SEAM], 0);
    wc_model_free(&m);

    def = sew_def(SEW);
    CHECK_EQ_INT(tube_model(&m, &def, &d), WC_OK);
    printf("tube: %d seams (expected %d), panels %d -> %d, %d seam springs\n", m.report.seams, TUBE_SEAMS,
           m.report.components, m.report.panels, m.report.springs[WC_SPRING_SEAM]);
    CHECK_EQ_INT(m.report.seams, TUBE_SEAMS);
    CHECK_EQ_INT(m.n_seams, TUBE_SEAMS);
    CHECK_EQ_INT(m.report.components, 2);
    CHECK_EQ_INT(m.report.panels, 1);
    CHECK_EQ_INT(m.n_panels, 1);
    /* every seam is vertex to edge (t = 1/2), joins the two panels, and starts GAP apart */
    for (int s = 0; s < m.n_seams; ++s) {
        const wc_seam* sm = &m.seams[s];
        CHECK_NEAR(sm->t, 0.5, 1e-9);
        CHECK(sm->q0 != sm->q1);
        CHECK(m.particle_component[sm->p] != m.particle_component[sm->q0]);
        CHECK_NEAR(wc_seam_gap(sm, m.rest_pos), GAP, 1e-9);
    }
    /* seam springs: zero rest, weights of one seam sum to... their energy is the seams' (below) */
    for (int s = m.spring_type_start[WC_SPRING_SEAM]; s < m.spring_type_start[WC_SPRING_SEAM + 1]; ++s) {
        CHECK(m.springs[s].rest == 0.0);
        CHECK(m.springs[s].a < m.springs[s].b);
        CHECK(m.springs[s].w != 0.0);
    }
    wc_model_free(&m);

    /* a smaller distance than the gap sews nothing */
    def = sew_def(0.5 * GAP);
    CHECK_EQ_INT(tube_model(&m, &def, &d), WC_OK);
    CHECK_EQ_INT(m.report.seams, 0);
    CHECK_EQ_INT(m.report.panels, 2);
    wc_model_free(&m);
}

/* Vertex-to-vertex seams are kept once, not once from each side. */
static void test_vertex_pairs_once(void) {
    /* two 3x3 sheets side by side, their facing edges 1 mm apart, vertices facing vertices */
    double pos[2 * 9 * 3];
    int sizes[8], idx[32];
    for (int panel = 0; panel < 2; ++panel)
        for (int j = 0; j < 3; ++j)
            for (int i = 0; i < 3; ++i) {
                double* p = pos + 3 * (9 * panel + 3 * j + i);
                p[0] = 0.1 * i + panel * (0.2 + 0.001);
                p[1] = 0.1 * j;
                p[2] = 0.0;
            }
    int f = 0;
    for (int panel = 0; panel < 2; ++panel)
        for (int j = 0; j < 2; ++j)
            for (int i = 0; i < 2; ++i, ++f) {
                int a = 9 * panel + 3 * j + i;
                sizes[f] = 4;
                idx[4 * f] = a;
                idx[4 * f + 1] = a + 1;
                idx[4 * f + 2] = a + 4;
                idx[4 * f + 3] = a + 3;
            }
    wc_source_mesh src;
    wc_diag d = {0};
    CHECK_EQ_INT(wc_source_mesh_from_arrays(&src, NULL, pos, 18, sizes, 8, idx, 1.0, &d), WC_OK);
    wc_model_def def = sew_def(0.002);
    wc_model m;
    CHECK_EQ_INT(wc_model_build(&m, &src, &def, NULL, &d), WC_OK);
    CHECK_EQ_INT(m.report.seams, 3);
    CHECK_EQ_INT(m.report.panels, 1);
    CHECK_EQ_INT(m.report.springs[WC_SPRING_SEAM], 3);
    for (int s = 0; s < m.n_seams; ++s) CHECK(m.seams[s].q0 == m.seams[s].q1 && m.seams[s].t == 0.0);
    wc_model_free(&m);
    wc_source_mesh_free(&src);
}

/* ---- forces ---------------------------------------------------------------------------------- */

static unsigned long long rng_ = 0x2545F4914F6CDD1Dull;
static double rnd(void) { /* [-1, 1) */
    rng_ ^= rng_ >> 12;
    rng_ ^= rng_ << 25;
    rng_ ^= rng_ >> 27;
    return (double)((rng_ * 2685821657736338717ull) >> 11) * (2.0 / 9007199254740992.0) - 1.0;
}

/* Seam springs only: energy, force and Jacobian. */
static double seam_energy(const wc_model* m, const double* x, double scale) {
    double e = 0.0, k = m->material.k[WC_SPRING_SEAM];
    for (int s = m->spring_type_start[WC_SPRING_SEAM]; s < m->spring_type_start[WC_SPRING_SEAM + 1]; ++s) {
        double L[3];
        v3_sub(L, x + 3 * m->springs[s].a, x + 3 * m->springs[s].b);
        double ext = wc_spring_extension(&m->springs[s], v3_norm(L), scale);
        e += 0.5 * k * m->springs[s].w * ext * ext;
    }
    return e;
}

static void seam_forces(const wc_model* m, const wc_spring_eval* se, double* F) {
    for (int i = 0; i < 3 * m->n_particles; ++i) F[i] = 0.0;
    for (int s = m->spring_type_start[WC_SPRING_SEAM]; s < m->spring_type_start[WC_SPRING_SEAM + 1]; ++s)
        for (int q = 0; q < 3; ++q) {
            F[3 * m->springs[s].a + q] += se[s].f[q];
            F[3 * m->springs[s].b + q] -= se[s].f[q];
        }
}

/* Seam springs of m at x = rest + amp noise: force = -grad E and Jacobian by finite differences,
 * damping exact; seam_scale as the step passes it. */
static void fd_check(const wc_model* m, double amp, double scale) {
    int n = m->n_particles;
    double kd = m->material.d[WC_SPRING_SEAM];
    double *x = malloc(sizeof(double) * 3 * n), *v = malloc(sizeof(double) * 3 * n),
           *zero = calloc(3 * (size_t)n, sizeof(double)), *F = malloc(sizeof(double) * 3 * n),
           *Fp = malloc(sizeof(double) * 3 * n), *Fm = malloc(sizeof(double) * 3 * n),
           *dx = malloc(sizeof(double) * 3 * n), *Kdx = calloc(3 * (size_t)n, sizeof(double));
    wc_spring_eval* se = calloc((size_t)m->n_springs, sizeof *se);
    wc_spring_eval* sv = calloc((size_t)m->n_springs, sizeof *sv);
    wc_par par;
    wc_par_init(&par, 1);
    for (int i = 0; i < 3 * n; ++i) {
        x[i] = m->rest_pos[i] + amp * rnd();
        v[i] = rnd();
        dx[i] = rnd();
    }
    /* force = -grad E (velocity zero), central differences */
    wc_eval_springs_at(m, x, zero, WC_COMPRESSION_FULL, scale, &par, se);
    seam_forces(m, se, F);
    double worst = 0.0, fmax = 0.0;
    const double h = 1e-6;
    for (int i = 0; i < 3 * n; ++i) {
        double keep = x[i];
        x[i] = keep + h;
        double ep = seam_energy(m, x, scale);
        x[i] = keep - h;
        double em = seam_energy(m, x, scale);
        x[i] = keep;
        double fd = -(ep - em) / (2 * h);
        if (fabs(fd - F[i]) > worst) worst = fabs(fd - F[i]);
        if (fabs(F[i]) > fmax) fmax = fabs(F[i]);
    }
    printf("seam force vs -dE/dx (scale %g): max error %.3g (max force %.3g N)\n", scale, worst, fmax);
    CHECK(fmax > 0.0);
    CHECK(worst <= 1e-6 * fmax + 1e-9);
    /* Jacobian: K dx from the blocks vs (F(x + eps dx) - F(x - eps dx)) / 2 eps */
    for (int s = m->spring_type_start[WC_SPRING_SEAM]; s < m->spring_type_start[WC_SPRING_SEAM + 1]; ++s) {
        double r[3], kr[3];
        v3_sub(r, dx + 3 * m->springs[s].a, dx + 3 * m->springs[s].b);
        m3_mulv(kr, se[s].kx, r);
        v3_add(Kdx + 3 * m->springs[s].a, Kdx + 3 * m->springs[s].a, kr);
        v3_sub(Kdx + 3 * m->springs[s].b, Kdx + 3 * m->springs[s].b, kr);
    }
    const double eps = 1e-6;
    for (int i = 0; i < 3 * n; ++i) x[i] += eps * dx[i];
    wc_eval_springs_at(m, x, zero, WC_COMPRESSION_FULL, scale, &par, sv);
    seam_forces(m, sv, Fp);
    for (int i = 0; i < 3 * n; ++i) x[i] -= 2 * eps * dx[i];
    wc_eval_springs_at(m, x, zero, WC_COMPRESSION_FULL, scale, &par, sv);
    seam_forces(m, sv, Fm);
    for (int i = 0; i < 3 * n; ++i) x[i] += eps * dx[i];
    double kmax = 0.0;
    worst = 0.0;
    for (int i = 0; i < 3 * n; ++i) {
        double fd = (Fp[i] - Fm[i]) / (2 * eps);
        if (fabs(fd - Kdx[i]) > worst) worst = fabs(fd - Kdx[i]);
        if (fabs(Kdx[i]) > kmax) kmax = fabs(Kdx[i]);
    }
    printf("seam Jacobian vs finite differences (scale %g): max error %.3g (max |K dx| %.3g)\n", scale, worst, kmax);
    CHECK(kmax > 0.0);
    CHECK(worst <= 1e-6 * kmax);
    /* damping: f(v) - f(0) = kv (v_a - v_b) = -d w (v_a - v_b) per spring */
    wc_eval_springs_at(m, x, v, WC_COMPRESSION_FULL, scale, &par, sv);
    worst = 0.0;
    for (int s = m->spring_type_start[WC_SPRING_SEAM]; s < m->spring_type_start[WC_SPRING_SEAM + 1]; ++s) {
        double dv[3], kdv[3];
        v3_sub(dv, v + 3 * m->springs[s].a, v + 3 * m->springs[s].b);
        m3_mulv(kdv, sv[s].kv, dv);
        for (int q = 0; q < 3; ++q) {
            double want = -kd * m->springs[s].w * dv[q];
            if (fabs(sv[s].f[q] - se[s].f[q] - want) > worst) worst = fabs(sv[s].f[q] - se[s].f[q] - want);
            if (fabs(kdv[q] - want) > worst) worst = fabs(kdv[q] - want);
        }
    }
    CHECK(worst < 1e-9);
    free(x), free(v), free(zero), free(F), free(Fp), free(Fm), free(dx), free(Kdx), free(se), free(sv);
}

static void test_seam_forces_fd(void) {
    wc_model m;
    wc_diag d = {0};
    wc_model_def def = sew_def(SEW);
    def.material.k[WC_SPRING_SEAM] = 3000.0; /* distinct from stretch, so a wrong type lookup shows */
    def.material.d[WC_SPRING_SEAM] = 1.5;
    CHECK_EQ_INT(tube_model(&m, &def, &d), WC_OK);
    /* energy of the pair springs == sum over seams of k/2 |p - (1-t) q0 - t q1|^2 */
    int n = m.n_particles;
    double* x = malloc(sizeof(double) * 3 * n);
    for (int i = 0; i < 3 * n; ++i) x[i] = m.rest_pos[i] + 0.01 * rnd();
    double e3 = 0.0;
    for (int s = 0; s < m.n_seams; ++s) {
        double g = wc_seam_gap(&m.seams[s], x);
        e3 += 0.5 * 3000.0 * g * g;
    }
    CHECK_NEAR(seam_energy(&m, x, 0.0), e3, 1e-9 * e3);
    CHECK_NEAR(seam_energy(&m, x, 0.7), e3, 1e-9 * e3); /* distance seams have no ramp */
    /* wc_spring_energy includes the seams */
    CHECK(wc_spring_energy(&m, x) - seam_energy(&m, x, 0.0) >= 0.0);
    free(x);
    fd_check(&m, 0.01, 0.0);
    wc_model_free(&m);
}

/* ---- simulation -------------------------------------------------------------------------------- */

typedef struct run_result {
    int rollbacks, failures, iterations, frames_ok;
    double max_strain, gap;
} run_result;

static void debug_log(wc_log_level level, const char* message, void* user) {
    (void)level, (void)user;
    if (getenv("SEW_DEBUG")) fprintf(stderr, "log: %s\n", message);
}

/* Pin the given particles at rest, step frames at 60 fps; returns totals. */
static run_result hang(const wc_model* m, const int* pinned, int n_pins, int frames, int amg,
                       double (*measure)(const wc_model*, const double*)) {
    run_result r = {0, 0, 0, 0, 0.0, 0.0};
    wc_sim_def sd = wc_default_sim_def();
    sd.threads = 1;
    sd.sleep_speed = 0.0;
    sd.solver.preconditioner = amg ? WC_PRECOND_AMG : WC_PRECOND_BLOCK_JACOBI;
    wc_state* s = NULL;
    wc_diag d = {0};
    d.log = debug_log;
    if (wc_state_create(&s, m, &sd, NULL, &d) != WC_OK) {
        fprintf(stderr, "state: %s\n", d.message);
        CHECK(0);
        return r;
    }
    wc_pin* pins = calloc((size_t)n_pins + 1, sizeof *pins);
    for (int k = 0; k < n_pins; ++k) {
        pins[k].particle = pinned[k];
        v3_copy(pins[k].target, m->rest_pos + 3 * pinned[k]);
    }
    CHECK_EQ_INT(wc_state_set_pins(s, pins, n_pins, &d), WC_OK);
    for (int f = 0; f < frames; ++f) {
        wc_step_stats st;
        wc_status ok = wc_step_frame(s, 1.0 / 60.0, &st, &d);
        if (ok != WC_OK) {
            fprintf(stderr, "frame %d: %s\n", f, d.message);
            break;
        }
        ++r.frames_ok;
        r.rollbacks += st.rollbacks;
        if (getenv("SEW_DEBUG") && st.rollbacks)
            fprintf(stderr, "amg %d frame %d: %d rollbacks, strain %g, gap %g\n", amg, f, st.rollbacks,
                    st.max_strain, measure(m, s->x));
        r.failures += st.failures;
        r.iterations += st.iterations;
        if (st.max_strain > r.max_strain) r.max_strain = st.max_strain;
    }
    r.gap = measure(m, s->x);
    free(pins);
    wc_state_destroy(s);
    return r;
}

/* Panel B's lowest point below its rest height (m): how far it fell. */
static double b_drop(const wc_model* m, const double* x) {
    double drop = 0.0;
    for (int p = 0; p < m->n_particles; ++p) {
        if (m->particle_component[p] == m->particle_component[m->host_to_particle[0]]) continue;
        double dd = m->rest_pos[3 * p + 1] - x[3 * p + 1];
        if (dd > drop) drop = dd;
    }
    return drop;
}

static int top_row(const wc_model* m, int panel, int* out) {
    for (int j = 0; j <= NW; ++j) out[j] = m->host_to_particle[tube_vertex(panel, 0, j)];
    return NW + 1;
}

static void test_tube_hangs_sewn(void) {
    wc_model m;
    wc_diag d = {0};
    wc_model_def def = sew_def(SEW);
    CHECK_EQ_INT(tube_model(&m, &def, &d), WC_OK);
    int pins[NW + 1];
    int np = top_row(&m, 0, pins); /* only panel A is held: B hangs from the seams */
    run_result r = hang(&m, pins, np, 120, 0, max_gap);
    run_result drop = hang(&m, pins, np, 120, 0, b_drop);
    printf("sewn tube after 2 s: max seam gap %.3g m (started %.3g), max strain %.4f, B dropped %.3g m, "
           "%d rollbacks\n", r.gap, GAP, r.max_strain, drop.gap, r.rollbacks);
    CHECK_EQ_INT(r.frames_ok, 120);
    CHECK_EQ_INT(r.failures, 0);
    CHECK_EQ_INT(r.rollbacks, 0);
    CHECK(r.gap < 1e-4);
    CHECK(r.max_strain < 0.05);
    CHECK(drop.gap < 0.03); /* the sag of the whole tube; unsewn, B falls metres (below) */
    wc_model_free(&m);

    /* the same mesh unsewn: panel B falls off */
    def = sew_def(0.0);
    CHECK_EQ_INT(tube_model(&m, &def, &d), WC_OK);
    np = top_row(&m, 0, pins);
    drop = hang(&m, pins, np, 120, 0, b_drop);
    printf("unsewn tube after 2 s: B dropped %.3g m\n", drop.gap);
    CHECK(drop.gap > 5.0);
    wc_model_free(&m);
}

/* AMG with seams: iterations comparable to the same tube held by both panels' top rows unsewn. */
static void test_amg_with_seams(void) {
    wc_model sewn, apart;
    wc_diag d = {0};
    wc_model_def def = sew_def(SEW);
    CHECK_EQ_INT(tube_model(&sewn, &def, &d), WC_OK);
    def = sew_def(0.0);
    CHECK_EQ_INT(tube_model(&apart, &def, &d), WC_OK);
    int pins[2 * (NW + 1)];
    int np = top_row(&sewn, 0, pins);
    run_result rs = hang(&sewn, pins, np, 30, 1, max_gap);
    np = top_row(&apart, 0, pins);
    np += top_row(&apart, 1, pins + np);
    run_result ra = hang(&apart, pins, np, 30, 1, max_gap);
    printf("AMG PCG iterations over 30 frames: sewn %d, unsewn (both panels held) %d\n", rs.iterations,
           ra.iterations);
    CHECK_EQ_INT(rs.frames_ok, 30);
    CHECK_EQ_INT(rs.rollbacks, 0); /* the V-cycle stays positive definite with seams (amg.h) */
    CHECK_EQ_INT(ra.rollbacks, 0);
    CHECK(rs.iterations > 0);
    CHECK(rs.iterations <= 3 * ra.iterations + 60);
    wc_model_free(&sewn);
    wc_model_free(&apart);
}

/* Host seam pairs: two sheets 0.3 m apart, B's top row sewn to A's, pulled shut (sew_sheets.h). */
static void test_host_pairs_close(void) {
    enum { NV = 2 * SHEET_N * SHEET_N, NF = 2 * (SHEET_N - 1) * (SHEET_N - 1) };
    double pos[3 * NV];
    int sizes[NF], idx[4 * NF], sa[SHEET_N], sb[SHEET_N];
    two_sheets(pos, sizes, idx, 0.3);
    for (int i = 0; i < SHEET_N; ++i) {
        sa[i] = i;                        /* A's top row */
        sb[i] = SHEET_N * SHEET_N + i;    /* B's top row */
    }
    wc_source_mesh src;
    wc_diag d = {0};
    CHECK_EQ_INT(wc_source_mesh_from_arrays(&src, NULL, pos, NV, sizes, NF, idx, 1.0, &d), WC_OK);
    wc_model_def def = sew_def(0.0);
    def.n_seam_pairs = SHEET_N;
    def.seam_a = sa;
    def.seam_b = sb;
    wc_model m;
    CHECK_EQ_INT(wc_model_build(&m, &src, &def, NULL, &d), WC_OK);
    CHECK_EQ_INT(m.report.seams, SHEET_N);
    CHECK_EQ_INT(m.report.panels, 1);
    CHECK_NEAR(max_gap(&m, m.rest_pos), 0.3, 1e-12);
    /* the ramp's one-sided spring stretched beyond rest x 0.5 (l ~ 0.3 > 0.15) */
    fd_check(&m, 0.01, 0.5);
    /* ... and slack at its full start length (l = rest x 1): no force, no stiffness */
    {
        wc_spring_eval* se = calloc((size_t)m.n_springs, sizeof *se);
        double* zero = calloc(3 * (size_t)m.n_particles, sizeof(double));
        wc_par par;
        wc_par_init(&par, 1);
        wc_eval_springs_at(&m, m.rest_pos, zero, WC_COMPRESSION_FULL, 1.0, &par, se);
        double most = 0.0;
        for (int s = m.spring_type_start[WC_SPRING_SEAM]; s < m.spring_type_start[WC_SPRING_SEAM + 1]; ++s) {
            CHECK_NEAR(m.springs[s].rest, 0.3, 1e-12);
            for (int q = 0; q < 9; ++q) most = fmax(most, fabs(se[s].kx[q]) + (q < 3 ? fabs(se[s].f[q]) : 0.0));
        }
        CHECK(most == 0.0);
        CHECK_NEAR(seam_energy(&m, m.rest_pos, 1.0), 0.0, 0.0);
        CHECK_NEAR(seam_energy(&m, m.rest_pos, 0.0), 0.5 * SHEET_N * 5000.0 * 0.09, 1e-9);
        free(se);
        free(zero);
    }
    int pins[SHEET_N];
    for (int i = 0; i < SHEET_N; ++i) pins[i] = m.host_to_particle[i];
    /* the rest length shrinks linearly over seam_close_time (0.5 s): the gap follows it */
    CHECK_NEAR(m.seam_close_time, 0.5, 0);
    static const int frame_counts[] = {1, 15, 60};
    for (int c = 0; c < 3; ++c) {
        int frames = frame_counts[c];
        run_result r = hang(&m, pins, SHEET_N, frames, 0, max_gap);
        printf("host pairs 0.3 m apart after %d frames: gap %.3g m, %d rollbacks, %d failures, max strain %.3f\n",
               frames, r.gap, r.rollbacks, r.failures, r.max_strain);
        CHECK_EQ_INT(r.frames_ok, frames);
        CHECK_EQ_INT(r.rollbacks, 0);
        CHECK_EQ_INT(r.failures, 0);
        double ramp = 0.3 * (1.0 - frames / 30.0); /* the rest length at the end */
        if (ramp > 0) CHECK(r.gap >= ramp - 1e-9 && r.gap < ramp + 0.03);
        if (frames == 60) CHECK(r.gap < 1e-4);
        CHECK(r.max_strain < 0.1);
    }
    wc_model_free(&m);
    wc_source_mesh_free(&src);
}

/* ---- bad inputs -------------------------------------------------------------------------------- */

static void expect_refused(const wc_source_mesh* src, const wc_model_def* def, wc_status want, const char* word) {
    wc_model m;
    memset(&m, 0x5a, sizeof m);
    wc_diag d = {0};
    wc_status st = wc_model_build(&m, src, def, NULL, &d);
    CHECK_EQ_INT(st, want);
    CHECK(strstr(d.message, word) != NULL);
    CHECK(m.n_particles == 0 && m.springs == NULL && m.seams == NULL && m.n_seams == 0);
    printf("  refused: %s\n", d.message);
}

static void test_core_bad_inputs(void) {
    wc_source_mesh src;
    ts_quad_grid(&src, 4, 4, 1.0, 1.0, 0);
    int a[2] = {0, 3}, b[2] = {15, 3}, far[1] = {16}, neg[1] = {-1};
    wc_model_def def = sew_def(NAN);
    expect_refused(&src, &def, WC_ERROR_INVALID_ARGUMENT, "sew_distance");
    def = sew_def(-0.001);
    expect_refused(&src, &def, WC_ERROR_INVALID_ARGUMENT, "sew_distance");
    def = sew_def(INFINITY);
    expect_refused(&src, &def, WC_ERROR_INVALID_ARGUMENT, "sew_distance");
    def = sew_def(0.0);
    def.seam_close_time = -1.0;
    expect_refused(&src, &def, WC_ERROR_INVALID_ARGUMENT, "seam_close_time");
    def.seam_close_time = NAN;
    expect_refused(&src, &def, WC_ERROR_INVALID_ARGUMENT, "seam_close_time");
    def = sew_def(0.0);
    def.n_seam_pairs = -1;
    expect_refused(&src, &def, WC_ERROR_INVALID_ARGUMENT, "count");
    def.n_seam_pairs = 1;
    def.seam_a = a;
    expect_refused(&src, &def, WC_ERROR_INVALID_ARGUMENT, "NULL");
    def.seam_b = far;
    expect_refused(&src, &def, WC_ERROR_OUT_OF_RANGE, "outside");
    def.seam_b = neg;
    expect_refused(&src, &def, WC_ERROR_OUT_OF_RANGE, "outside");
    def.n_seam_pairs = 2;
    def.seam_b = b;
    expect_refused(&src, &def, WC_ERROR_INVALID_ARGUMENT, "itself");
    /* the good pair alone builds */
    def.n_seam_pairs = 1;
    wc_model m;
    wc_diag d = {0};
    CHECK_EQ_INT(wc_model_build(&m, &src, &def, NULL, &d), WC_OK);
    CHECK_EQ_INT(m.report.seams, 1);
    CHECK_EQ_INT(m.report.panels, 1);
    wc_model_free(&m);
    wc_source_mesh_free(&src);
    /* two host vertices welded into one particle cannot be sewn together */
    ts_quad_grid(&src, 3, 3, 1.0, 1.0, 1); /* split: 4 vertices per quad, welded */
    int wa[1] = {1}, wb[1] = {4};           /* quad 0's (1, 0) and quad 1's (1, 0): one particle */
    def = sew_def(0.0);
    def.n_seam_pairs = 1;
    def.seam_a = wa;
    def.seam_b = wb;
    expect_refused(&src, &def, WC_ERROR_INVALID_ARGUMENT, "welded");
    wc_source_mesh_free(&src);
}
int main(void) {
    RUN_TEST(test_tube_seams_found);
    RUN_TEST(test_vertex_pairs_once);
    RUN_TEST(test_seam_forces_fd);
    RUN_TEST(test_tube_hangs_sewn);
    RUN_TEST(test_amg_with_seams);
    RUN_TEST(test_host_pairs_close);
    RUN_TEST(test_core_bad_inputs);
    return TEST_SUMMARY();
}
