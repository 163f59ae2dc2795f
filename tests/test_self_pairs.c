/* Self-contacts inside the implicit solve (core/self_pairs.h, core/penalty_pairs.h,
 * core/coupling.h):
 *   - each pair's force and stiffness against finite differences of its energy (a
 *     vertex-triangle and an edge-edge pair);
 *   - the substep's system with the off-pattern couplings solved by PCG (block-Jacobi and
 *     multigrid) and by the direct solver (its factor preconditioning PCG) against a dense
 *     Gaussian elimination of the same system written out here, and shown to differ from the
 *     system without the couplings (so the check can fail);
 *   - a sheet falling onto a pinned one: no crossing, fewer corrections left to the stage after
 *     the solve than with the stage alone, no allocation in a step, the same result on 1 and 2
 *     threads. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "check.h"
#include "test_support.h"
#include "self_collide.h"
#include "self_pairs.h"
#include "solve.h"
#include "step.h"
#include "two_layers.h"

enum { N = 7 };            /* vertices per side of each layer */
static const double SIZE = 0.3, GAP = 0.004, TH = 0.003;

/* The two layers, the top one shifted by a third of a cell so that its vertices sit over the
 * bottom one's triangles, GAP above it. */
static void layers(wc_model* m) {
    CHECK(two_layers(m, N, SIZE, 0.0, GAP));
}

static wc_sim_def def_self(int in_solve) {
    wc_sim_def d = wc_default_sim_def();
    d.self_collision = 1;
    d.self_thickness = TH;
    d.self_in_solve = in_solve;
    d.sleep_speed = 0;
    return d;
}

/* A state whose top layer moves down at 0.3 m/s over the bottom one. */
static wc_state* approaching(const wc_model* m, const wc_sim_def* def) {
    wc_state* s = two_layers_approaching(m, N, SIZE, 0.3, def);
    CHECK(s != NULL);
    return s;
}

/* Energy of pair k at x (penalty_pairs.h's formula, written out) */
static double pair_energy(const wc_penalty_pairs* sp, int k, const double* x) {
    const wc_coupling_term* t = &sp->term[k];
    double g = -sp->off[k];
    for (int a = 0; a < 4; ++a) g += t->w[a] * v3_dot(t->n, x + 3 * t->p[a]);
    return g < 0.0 ? 0.5 * sp->k[k] * g * g : 0.0;
}

static void check_pair_fd(const wc_penalty_pairs* sp, int k, const double* x0, int n) {
    double* x = malloc(3 * (size_t)n * sizeof(double));
    memcpy(x, x0, 3 * (size_t)n * sizeof(double));
    const wc_coupling_term* t = &sp->term[k];
    /* push the pair into contact: its first particle moves 2 thicknesses against n */
    v3_axpy(x + 3 * t->p[0], -2.0 * TH / t->w[0], t->n);
    double f[12], J[144], fp[12], Jp[144], fm[12], Jm[144];
    double e = wc_penalty_pair_eval(sp, k, x, f, J);
    CHECK(e > 0.0);
    const double eps = 1e-7;
    double worst_f = 0.0, worst_j = 0.0, fscale = 0.0, jscale = 0.0;
    for (int q = 0; q < 12; ++q) fscale = fmax(fscale, fabs(f[q]));
    for (int q = 0; q < 144; ++q) jscale = fmax(jscale, fabs(J[q]));
    for (int b = 0; b < 4; ++b)
        for (int c = 0; c < 3; ++c) {
            double* xi = x + 3 * t->p[b] + c;
            double keep = *xi;
            *xi = keep + eps;
            double ep = pair_energy(sp, k, x);
            wc_penalty_pair_eval(sp, k, x, fp, Jp);
            *xi = keep - eps;
            double em = pair_energy(sp, k, x);
            wc_penalty_pair_eval(sp, k, x, fm, Jm);
            *xi = keep;
            worst_f = fmax(worst_f, fabs(-(ep - em) / (2 * eps) - f[3 * b + c]));
            for (int a = 0; a < 4; ++a)
                for (int r = 0; r < 3; ++r) {
                    double jd = (fp[3 * a + r] - fm[3 * a + r]) / (2 * eps);
                    worst_j = fmax(worst_j, fabs(jd - J[9 * (a * 4 + b) + 3 * r + c]));
                }
        }
    printf("  pair %d (%s): E %.3g J, force error %.2g of %.3g N, stiffness error %.2g of %.3g N/m\n", k,
           t->w[1] > 0 ? "edge-edge" : "vertex-triangle", e, worst_f, fscale, worst_j, jscale);
    CHECK(worst_f <= 1e-6 * fscale);
    CHECK(worst_j <= 1e-6 * jscale);
    free(x);
}

static void test_pair_derivatives(void) {
    wc_model m;
    layers(&m);
    wc_sim_def def = def_self(1);
    wc_state* s = approaching(&m, &def);
    wc_step_stats st;
    memset(&st, 0, sizeof st);
    wc_substep_prepare(s, 1.0 / 60, 1.0, &st);
    wc_penalty_pairs* sp = s->self_pairs ? &s->self_pairs->list : NULL;
    CHECK(sp && sp->n > 0);
    int vt = -1, ee = -1;
    for (int k = 0; k < sp->n; ++k) {
        if (sp->term[k].w[0] == 1.0 && vt < 0) vt = k;
        if (sp->term[k].w[1] > 0.0 && ee < 0) ee = k;
    }
    printf("  %d pairs found, %d active\n", sp->n, st.self_pairs_active);
    CHECK(vt >= 0);
    CHECK(ee >= 0);
    if (vt >= 0) check_pair_fd(sp, vt, s->x, m.n_particles);
    if (ee >= 0) check_pair_fd(sp, ee, s->x, m.n_particles);
    wc_state_destroy(s);
    wc_model_free(&m);
}

/* 1 when lists a and b hold the same pairs bit for bit, with the same counts */
static int same_list(const wc_penalty_pairs* a, const wc_penalty_pairs* b) {
    if (a->n != b->n || a->overflow != b->overflow || a->skipped != b->skipped) return 0;
    for (int j = 0; j < a->n; ++j)
        if (memcmp(&a->term[j], &b->term[j], sizeof a->term[j]) || a->off[j] != b->off[j] || a->k[j] != b->k[j] ||
            a->active[j] != b->active[j])
            return 0;
    return 1;
}

/* The detection on 2 and 3 threads (each thread's range of queries staged, then appended in order)
 * gives the serial list, with stages that fill up (the rest of a range found serially) and a list
 * that overflows. */
static void test_pairs_threads(void) {
    wc_model m;
    layers(&m);
    wc_sim_def def = def_self(1);
    wc_state* s = approaching(&m, &def);
    const double h = 1.0 / 60;
    int n = m.n_particles, ne = s->self->n_edges, found = 0;
    const int caps[2] = {n + ne + 64, 7};
    for (int ci = 0; ci < 2; ++ci) {
        wc_self_pairs* serial = wc_self_pairs_create(caps[ci], n, ne, 1, 0, NULL);
        CHECK(serial != NULL);
        wc_self_pairs_find(serial, s->self, &m, &s->filter, s->x, s->v, h, h);
        if (ci == 0) found = serial->list.n;
        else CHECK(serial->list.overflow > 0);
        const int threads[3] = {2, 3, 2}, stage_caps[3] = {0, 1, 5};
        for (int r = 0; r < 3; ++r) {
            wc_self_pairs* par = wc_self_pairs_create(caps[ci], n, ne, threads[r], stage_caps[r], NULL);
            CHECK(par != NULL);
            wc_self_pairs_find(par, s->self, &m, &s->filter, s->x, s->v, h, h);
            CHECK(same_list(&serial->list, &par->list));
            CHECK_EQ_INT(par->coupling.n, serial->coupling.n);
            wc_self_pairs_destroy(par, NULL);
        }
        wc_self_pairs_destroy(serial, NULL);
    }
    printf("  %d pairs found alike on 1, 2 and 3 threads, with stages of room 1, 5 and the default, and with a "
           "list of room 7\n", found);
    CHECK(found > 20);
    wc_state_destroy(s);
    wc_model_free(&m);
}

/* wc_self_pairs_from (the GPU's finder's host part, gpu/solver/wg_self_pairs.h) on every pair of
 * queries and elements (each vertex against every triangle, each edge against every edge above
 * it), sorted by query and leaf: wc_self_pairs_find's list bit for bit, with room for all and for
 * 7 (the overflow), the upper layer approaching and at rest. At rest its leaf test decides: the
 * layers 4 mm apart are within the rules' reach (th + thickness = 6 mm) but not the trees' (the
 * triangles' boxes grown by 3 mm), so core's walk never visits them. */
typedef struct cand3 {
    int q, key, e;
} cand3;
static int by_leaf(const void* pa, const void* pb) {
    const cand3 *a = pa, *b = pb;
    if (a->q != b->q) return a->q < b->q ? -1 : 1;
    return a->key < b->key ? -1 : a->key > b->key;
}

static void test_pairs_from_candidates(void) {
    wc_model m;
    layers(&m);
    wc_sim_def def = def_self(1);
    wc_state* s = approaching(&m, &def);
    const double h = 1.0 / 60;
    const wc_self* sc = s->self;
    const int n = m.n_particles, ne = sc->n_edges, nt = m.n_tris;
    const size_t all = (size_t)n * nt + (size_t)ne * ne;
    cand3* c = malloc(all * sizeof *c);
    int* list = malloc(2 * all * sizeof(int));
    int nc = 0;
    for (int i = 0; i < n; ++i)
        for (int t = 0; t < nt; ++t) c[nc++] = (cand3){i, sc->tri_bvh.leaf_of[t], t};
    for (int e = 0; e < ne; ++e)
        for (int f = e + 1; f < ne; ++f) c[nc++] = (cand3){n + e, sc->edge_bvh.leaf_of[f], f};
    qsort(c, (size_t)nc, sizeof *c, by_leaf);
    for (int k = 0; k < nc; ++k) {
        list[2 * k] = c[k].q;
        list[2 * k + 1] = c[k].e;
    }
    const int caps[3] = {n + ne + 64, 7, n + ne + 64};
    int found[3] = {0, 0, 0};
    for (int ci = 0; ci < 3; ++ci) {
        if (ci == 2) memset(s->v, 0, 3 * (size_t)n * sizeof(double));   /* at rest */
        wc_self_pairs* a = wc_self_pairs_create(caps[ci], n, ne, 1, 0, NULL);
        wc_self_pairs* b = wc_self_pairs_create(caps[ci], n, ne, 1, 0, NULL);
        CHECK(a && b);
        wc_self_pairs_find(a, s->self, &m, &s->filter, s->x, s->v, h, h);
        CHECK_EQ_INT(wc_self_pairs_from(b, s->self, &m, &s->filter, s->x, s->v, h, h, list, nc), a->list.n);
        CHECK(same_list(&a->list, &b->list));
        CHECK_EQ_INT(b->coupling.n, a->coupling.n);
        found[ci] = a->list.n;
        if (ci == 1) CHECK(a->list.overflow > 0);
        wc_self_pairs_destroy(a, NULL);
        wc_self_pairs_destroy(b, NULL);
    }
    printf("  %d pairs from %d candidates (every pair), as wc_self_pairs_find's, also with a list of room 7; at "
           "rest %d\n", found[0], nc, found[2]);
    CHECK(found[0] > 20);
    CHECK(found[2] < found[0]);
    free(c);
    free(list);
    wc_state_destroy(s);
    wc_model_free(&m);
}

/* Dense Gaussian elimination with partial pivoting: solves K y = r (K overwritten). */
static void dense_solve(double* K, double* r, int N3) {
    for (int c = 0; c < N3; ++c) {
        int piv = c;
        for (int i = c + 1; i < N3; ++i)
            if (fabs(K[(size_t)i * N3 + c]) > fabs(K[(size_t)piv * N3 + c])) piv = i;
        if (piv != c) {
            for (int j = 0; j < N3; ++j) {
                double t = K[(size_t)c * N3 + j];
                K[(size_t)c * N3 + j] = K[(size_t)piv * N3 + j];
                K[(size_t)piv * N3 + j] = t;
            }
            double t = r[c];
            r[c] = r[piv];
            r[piv] = t;
        }
        for (int i = c + 1; i < N3; ++i) {
            double f = K[(size_t)i * N3 + c] / K[(size_t)c * N3 + c];
            for (int j = c; j < N3; ++j) K[(size_t)i * N3 + j] -= f * K[(size_t)c * N3 + j];
            r[i] -= f * r[c];
        }
    }
    for (int i = N3 - 1; i >= 0; --i) {
        double acc = r[i];
        for (int j = i + 1; j < N3; ++j) acc -= K[(size_t)i * N3 + j] * r[j];
        r[i] = acc / K[(size_t)i * N3 + i];
    }
}

/* The dense system of the substep: A's blocks, plus the couplings' off-diagonal blocks when
 * with_coupling. No constraint (nothing pinned, no collider): the filter is the identity. */
static void dense_system(const wc_state* s, int with_coupling, double* K) {
    const wc_model* m = s->model;
    const wc_bsr_pattern* p = &m->pattern;
    int N3 = 3 * m->n_particles;
    memset(K, 0, (size_t)N3 * N3 * sizeof(double));
    for (int i = 0; i < m->n_particles; ++i)
        for (int k = p->row_start[i]; k < p->row_start[i + 1]; ++k)
            for (int r = 0; r < 3; ++r)
                for (int c = 0; c < 3; ++c)
                    K[(size_t)(3 * i + r) * N3 + 3 * p->col[k] + c] = s->A[9 * (size_t)k + 3 * r + c];
    if (!with_coupling) return;
    const wc_penalty_pairs* sp = &s->self_pairs->list;
    for (int q = 0; q < sp->n; ++q) {
        const wc_coupling_term* t = &sp->term[q];
        if (!(t->c > 0)) continue;
        for (int a = 0; a < 4; ++a)
            for (int b = 0; b < 4; ++b) {
                if (a == b) continue;
                for (int r = 0; r < 3; ++r)
                    for (int c = 0; c < 3; ++c)
                        K[(size_t)(3 * t->p[a] + r) * N3 + 3 * t->p[b] + c] += t->c * t->w[a] * t->w[b] * t->n[r] * t->n[c];
            }
    }
}

static void test_solve_against_dense(void) {
    wc_model m;
    layers(&m);
    int N3 = 3 * m.n_particles;
    double* K = malloc((size_t)N3 * N3 * sizeof(double));
    double* ref = malloc((size_t)N3 * sizeof(double));
    double* ref0 = malloc((size_t)N3 * sizeof(double));
    double* dv = malloc((size_t)N3 * sizeof(double));
    const char* names[3] = {"pcg block_jacobi", "pcg amg", "direct"};
    for (int variant = 0; variant < 3; ++variant) {
        wc_sim_def def = def_self(1);
        def.solver.tolerance = 1e-10;
        def.solver.max_iterations = 2000;
        def.solver.preconditioner = variant == 1 ? WC_PRECOND_AMG : WC_PRECOND_BLOCK_JACOBI;
        def.direct_fallback = 1;
        wc_state* s = approaching(&m, &def);
        wc_step_stats st;
        memset(&st, 0, sizeof st);
        wc_substep_prepare(s, 1.0 / 60, 1.0, &st);
        int active = wc_coupling_active(&s->self_pairs->coupling);
        CHECK(active > 0);
        dense_system(s, 1, K);
        memcpy(ref, s->b, (size_t)N3 * sizeof(double));
        dense_solve(K, ref, N3);
        dense_system(s, 0, K);
        memcpy(ref0, s->b, (size_t)N3 * sizeof(double));
        dense_solve(K, ref0, N3);
        memset(dv, 0, (size_t)N3 * sizeof(double));
        wc_solve_result res;
        wc_solver_type type = variant == 2 ? WC_SOLVER_DIRECT : WC_SOLVER_PCG;
        CHECK_EQ_INT(wc_solve(s->solver, type, s->A, s->b, &s->filter, dv, &s->par, &res), WC_OK);
        double err = ts_rel_diff(dv, ref, N3), without = ts_rel_diff(ref0, ref, N3);
        printf("  %s: %d active couplings, %d iterations, residual %.2g; off the dense solve by %.2g (the "
               "system without the couplings: %.2g off)\n",
               names[variant], active, res.iterations, res.residual, err, without);
        CHECK(res.converged);
        CHECK(err < 1e-7);
        CHECK(without > 1e-3);
        wc_state_destroy(s);
    }
    free(K);
    free(ref);
    free(ref0);
    free(dv);
    wc_model_free(&m);
}

/* ---- a counting allocator ---- */
typedef struct counter {
    long allocs, frees;
} counter;
static void* count_alloc(size_t n, void* u) {
    ++((counter*)u)->allocs;
    return malloc(n);
}
static void count_free(void* p, void* u) {
    if (p) ++((counter*)u)->frees;
    free(p);
}

typedef struct drop_result {
    int crossings_frames, impacts, proximity, zones, pairs, rollbacks;
    long allocs_in_steps;
    double* x;   /* final positions (malloc'ed) */
} drop_result;

static drop_result drop(const wc_model* m, int in_solve, int threads) {
    drop_result r = {0};
    counter cnt = {0, 0};
    wc_allocator al = {count_alloc, count_free, &cnt};
    wc_sim_def def = def_self(in_solve);
    def.threads = threads;
    wc_state* s = NULL;
    wc_diag d = {0};
    CHECK(wc_state_create(&s, m, &def, &al, &d) == WC_OK);
    int n = m->n_particles;
    double* x = malloc(3 * (size_t)n * sizeof(double));
    two_layers_shifted(m, N, SIZE, x);
    for (int hv = N * N; hv < 2 * N * N; ++hv) x[3 * m->host_to_particle[hv] + 1] += 0.02;   /* 2 cm up */
    CHECK(wc_state_set_positions(s, x, NULL, &d) == WC_OK);
    /* the bottom layer pinned at its rim, where it is */
    wc_pin* pins = calloc((size_t)N * N, sizeof *pins);
    int np = 0;
    for (int hv = 0; hv < N * N; ++hv) {
        int i = hv % N, j = hv / N;
        if (i != 0 && j != 0 && i != N - 1 && j != N - 1) continue;
        pins[np].particle = m->host_to_particle[hv];
        v3_copy(pins[np].target, x + 3 * pins[np].particle);
        ++np;
    }
    CHECK(wc_state_set_pins(s, pins, np, &d) == WC_OK);
    long before = cnt.allocs;
    for (int f = 0; f < 30; ++f) {
        wc_step_stats st;
        CHECK(wc_step_frame(s, 1.0 / 30, &st, &d) == WC_OK);
        r.impacts += st.self_impacts;
        r.proximity += st.self_proximity;
        r.zones += st.self_zones;
        r.pairs += st.self_pairs_active;
        r.rollbacks += st.rollbacks;
        int c = -1;
        CHECK(wc_self_intersections(m, s->x, NULL, &c, &d) == WC_OK);
        r.crossings_frames += c != 0;
    }
    r.allocs_in_steps = cnt.allocs - before;
    r.x = malloc(3 * (size_t)n * sizeof(double));
    memcpy(r.x, s->x, 3 * (size_t)n * sizeof(double));
    wc_state_destroy(s);
    CHECK(cnt.allocs == cnt.frees);
    free(pins);
    free(x);
    return r;
}

static void test_drop_on_layer(void) {
    wc_model m;
    layers(&m);
    drop_result on = drop(&m, 1, 1), stage = drop(&m, 0, 1), two = drop(&m, 1, 2);
    printf("  sheet onto a pinned sheet, 30 frames: in the solve: %d active pairs, stage impacts %d, proximity "
           "impulses %d, zones %d, rollbacks %d, frames crossing %d, %ld allocations in the steps; stage alone: "
           "impacts %d, proximity impulses %d, zones %d, rollbacks %d, frames crossing %d\n",
           on.pairs, on.impacts, on.proximity, on.zones, on.rollbacks, on.crossings_frames, on.allocs_in_steps,
           stage.impacts, stage.proximity, stage.zones, stage.rollbacks, stage.crossings_frames);
    CHECK(on.pairs > 0);
    CHECK_EQ_INT(on.crossings_frames, 0);
    CHECK_EQ_INT(stage.crossings_frames, 0);
    CHECK(on.impacts < stage.impacts);
    CHECK_EQ_INT(on.allocs_in_steps, 0);
    CHECK(memcmp(on.x, two.x, 3 * (size_t)m.n_particles * sizeof(double)) == 0);   /* thread count */
    free(on.x);
    free(stage.x);
    free(two.x);
    wc_model_free(&m);
}

int main(void) {
    RUN_TEST(test_pair_derivatives);
    RUN_TEST(test_pairs_threads);
    RUN_TEST(test_pairs_from_candidates);
    RUN_TEST(test_solve_against_dense);
    RUN_TEST(test_drop_on_layer);
    return TEST_SUMMARY();
}
