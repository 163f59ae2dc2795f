/* The GPU multigrid's rotations about the current positions (wg_amg.current, amg_tent_qr.glsl) on
 * a real EGL context (llvmpipe without a GPU), against core's (core/amg_tent.c: wc_amg_rigid_modes
 * and wc_amg_tentative on every level) on the same float positions, those the GPU holds (read
 * back): a 32 x 32 sheet hanging from two corners, bent and twisted, and the sheet beside pieces
 * whose aggregates leave rotations dead (ts_dead_pieces, 4e5 m away). Per level below the
 * coarsest:
 *   - P_tent's blocks (2 a node) against core's tent, relative to the level's largest entry;
 *   - the next level's near-null rows (R) against core's: the GPU takes them about each
 *     aggregate's centre p (nc.xyz), core about the particles' centroid cg, so core's are moved
 *     to p in double (the rotation columns + the translation columns x K(cg - p), K(d) e_k =
 *     d x e_k); the translation and the rotation columns each relative to their largest entry;
 *   - the centres against the aggregates' means (of the positions, then of the finer centres);
 *   - the dead unknowns (nc.w) equal to core's, bit for bit.
 * The mutation: the GPU's rest form (WEFT_GPU_AMG_CURRENT=0, core's P_tent about the rest
 * positions) against core's about the bent sheet's current ones is far off. Caught by hand (in
 * amg_tent_qr.glsl; docs/bench/gpu_amg_current.md): the centre's mean over one node fewer, the dead test
 * about the aggregate's centre, the coarse rows not moved to the centre, the rows about the
 * particles' centroid (float's cancellation). Not caught: one Gram-Schmidt pass (about the
 * aggregate's centre the columns stay well conditioned, even squashed).
 * The levels' P, Galerkin blocks, V-cycle and PCG in this form: test_gpu_amg_smooth "rot cur" and
 * "dead cur". */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "gpu_test_device.h"
#include "step.h"
#include "test_support.h"
#include "wg_amg.h"
#include "wg_sim_impl.h"

static wg_gl_context* gl;
static wg_device* dev;

#define TOL_TENT 2e-6  /* P_tent's blocks: float against double, relative to the largest */
#define TOL_R 2e-6     /* R's columns, relative to their largest entry */
#define TOL_C 1e-6     /* the centres, relative to the largest */

/* Element (r, c), c in 0..5, of node i's 3 x 6 rows (core/amg_tent.c's RB) */
#define RB(arr, i, r, c) (arr)[18 * (size_t)(i) + 9 * ((c) / 3) + 3 * (r) + (c) % 3]

typedef struct diffs {
    double tent, rt, rr, centre;
    int dead_off, dead;
} diffs;

/* The GPU's hierarchy of g after a setup against core's ca after wc_amg_tentative on x. */
static diffs compare(wg_sim* g, const wc_amg* ca, const double* x) {
    const wg_amg* a = g->amg;
    diffs out = {0};
    const int n0 = ca->lev[0].n;
    double cg[3] = {0, 0, 0};
    for (int i = 0; i < n0; ++i)
        for (int q = 0; q < 3; ++q) cg[q] += x[3 * i + q] / n0;
    double* centre = calloc(3 * (size_t)n0, sizeof(double)); /* the expected centres, by node */
    double* next = calloc(3 * (size_t)n0, sizeof(double));
    memcpy(centre, x, 3 * (size_t)n0 * sizeof(double));
    float* buf = calloc(4 * 2 * (size_t)n0 * 7, sizeof(float));
    for (int l = 0; l + 1 < a->n_levels; ++l) {
        const wc_amg_level *F = &ca->lev[l], *C = &ca->lev[l + 1];
        const wg_amg_level *G = &a->lev[l], *N = &a->lev[l + 1];
        /* P_tent: texel 2i + q, row r */
        double dm = 0, cm = 0;
        for (int r = 0; r < 3; ++r) {
            wg_array_read(&g->layout, &G->tent[r], 2 * F->n, buf);
            for (int t = 0; t < 2 * F->n; ++t)
                for (int c = 0; c < 3; ++c) {
                    const double cv = F->tent[9 * (size_t)t + 3 * r + c];
                    dm = fmax(dm, fabs(buf[4 * t + c] - cv));
                    cm = fmax(cm, fabs(cv));
                }
        }
        const double e_tent = dm / cm;
        out.tent = fmax(out.tent, e_tent);
        if (!a->current) { /* the rest form: core's P_tent uploaded, no rows made */
            printf("    level %d -> %d: |dP_tent| %.2e\n", l, l + 1, e_tent);
            continue;
        }
        /* the expected centres of the next level's nodes */
        for (int k = 0; k < C->n / 2; ++k) {
            double p[3] = {0, 0, 0};
            const int m = F->agg_start[k + 1] - F->agg_start[k];
            for (int e = F->agg_start[k]; e < F->agg_start[k + 1]; ++e)
                for (int q = 0; q < 3; ++q) p[q] += centre[3 * F->agg_node[e] + q] / m;
            for (int h = 0; h < 2; ++h) memcpy(next + 3 * (2 * k + h), p, sizeof p);
        }
        memcpy(centre, next, 3 * (size_t)C->n * sizeof(double));
        /* R, the centres, the dead bits */
        float* nn = buf + 4 * (size_t)C->n;
        for (int k = 0; k < 6; ++k) wg_array_read(&g->layout, &N->nn[k], C->n, nn + 4 * (size_t)C->n * k);
        wg_array_read(&g->layout, &N->nc, C->n, buf);
        double dt = 0, mt = 0, dr = 0, mr = 0, dc = 0, mc = 0;
        int dead_off = 0, dead = 0;
        for (int K = 0; K < C->n; ++K) {
            const float* pc = buf + 4 * (size_t)K;
            double d[3];
            for (int q = 0; q < 3; ++q) {
                d[q] = cg[q] - pc[q];
                dc = fmax(dc, fabs(pc[q] - centre[3 * K + q]));
                mc = fmax(mc, fabs(centre[3 * K + q]));
            }
            /* K(d): column k is d x e_k */
            const double Kd[3][3] = {{0, -d[2], d[1]}, {d[2], 0, -d[0]}, {-d[1], d[0], 0}};
            for (int r = 0; r < 3; ++r)
                for (int c = 0; c < 3; ++c) {
                    const double tc = RB(C->nns, K, r, c);
                    double rc = RB(C->nns, K, r, 3 + c);
                    for (int j = 0; j < 3; ++j) rc += RB(C->nns, K, r, j) * Kd[j][c];
                    const float* gt = nn + 4 * (size_t)C->n * (2 * r) + 4 * (size_t)K;
                    const float* gr = nn + 4 * (size_t)C->n * (2 * r + 1) + 4 * (size_t)K;
                    dt = fmax(dt, fabs(gt[c] - tc));
                    mt = fmax(mt, fabs(tc));
                    dr = fmax(dr, fabs(gr[c] - rc));
                    mr = fmax(mr, fabs(rc));
                }
            const int bits = (int)pc[3];
            for (int r = 0; r < 3; ++r) {
                dead_off += ((bits >> r) & 1) != C->dead[3 * K + r];
                dead += C->dead[3 * K + r];
            }
        }
        printf("    level %d -> %d (%d nodes): |dP_tent| %.2e, R |dT| %.2e |dRot| %.2e, centres %.2e, dead %d "
               "(%d differ)\n",
               l, l + 1, C->n, e_tent, dt / mt, dr / mr, dc / mc, dead, dead_off);
        out.rt = fmax(out.rt, dt / mt);
        out.rr = fmax(out.rr, dr / mr);
        out.centre = fmax(out.centre, dc / mc);
        out.dead_off += dead_off;
        out.dead += dead;
    }
    free(centre), free(next), free(buf);
    return out;
}

/* The GPU's setup (current 1, or the rest form) on s's system, and core's QR about the positions
 * the GPU holds. */
static diffs check(const char* name, wc_model* m, wc_state* s, int current) {
    const double h = 1.0 / 30.0;
    const int n = m->n_particles;
    wc_diag d = {0};
    wc_step_stats st;
    memset(&st, 0, sizeof st);
    diffs out = {1, 1, 1, 1, 1, 0};
    wg_sim* g = NULL;
    dev->amg_smooth = 1;
    dev->amg_rot = 1;
    dev->amg_current = current;
    CHECK(wg_sim_create(dev, s, NULL, &g, &d) == WC_OK);
    if (!g) {
        fprintf(stderr, "%s\n", d.message);
        return out;
    }
    CHECK(g->amg->rotations == 1);
    CHECK_EQ_INT(g->amg->current, current);
    CHECK(wg_sim_debug_prepare(g, s, h, 1.0, NULL, NULL, NULL, NULL, NULL, NULL, &d) == WC_OK);
    wc_substep_prepare(s, h, 1.0, &st);
    CHECK(wg_sim_debug_set_system(g, s->A, s->b, &s->filter, &d) == WC_OK);
    wg_amg_setup(g->amg);
    /* the positions the GPU holds */
    float* xg = calloc(4 * (size_t)n, sizeof(float));
    double* x = calloc(3 * (size_t)n, sizeof(double));
    wg_array_read(&g->layout, wg_ring_cur(&g->x), n, xg);
    double moved = 0.0;
    for (int i = 0; i < n; ++i)
        for (int q = 0; q < 3; ++q) {
            x[3 * i + q] = xg[4 * i + q];
            moved = fmax(moved, fabs(x[3 * i + q] - m->rest_pos[3 * i + q]));
        }
    wc_amg_opts o = wg_amg_opts_form(1, 1);
    wc_amg* ca = NULL;
    CHECK(wc_amg_create(&ca, m, &o, NULL, &d) == WC_OK);
    if (ca) {
        CHECK_EQ_INT(ca->n_levels, g->amg->n_levels);
        wc_amg_rigid_modes(&ca->lev[0], x);
        for (int l = 0; l + 1 < ca->n_levels; ++l) wc_amg_tentative(&ca->lev[l], &ca->lev[l + 1], ca->lev[l + 1].n / 2, NULL);
        printf("  %s (%s form on the GPU): %d particles, %d levels, %.3g m from the rest positions at most\n", name,
               current ? "current" : "rest", n, ca->n_levels, moved);
        out = compare(g, ca, x);
        wc_amg_destroy(ca);
    }
    free(xg), free(x);
    wg_sim_destroy(g);
    return out;
}

static void expect_match(diffs e) {
    CHECK(e.tent <= TOL_TENT);
    CHECK(e.rt <= TOL_R);
    CHECK(e.rr <= TOL_R);
    CHECK(e.centre <= TOL_C);
    CHECK_EQ_INT(e.dead_off, 0);
}

/* The 32 x 32 hanging sheet bent about y and twisted about x (positions rounded to float). */
static void test_bent_sheet(void) {
    wc_model m;
    wc_state* s = ts_hanging_float(&m, 32, 3, 1.0);
    CHECK(s != NULL);
    if (!s) return;
    const int n = m.n_particles;
    double* x = malloc(3 * (size_t)n * sizeof(double));
    for (int i = 0; i < n; ++i) {
        const double* p = s->x + 3 * i;
        const double t = 0.8 * p[0], c = cos(t), sn = sin(t);
        x[3 * i] = p[0];
        x[3 * i + 1] = c * p[1] - sn * p[2];
        x[3 * i + 2] = sn * p[1] + c * p[2] + 0.2 * sin(2.5 * p[1]);
        for (int q = 0; q < 3; ++q) x[3 * i + q] = (float)x[3 * i + q];
    }
    wc_diag d = {0};
    CHECK(wc_state_set_positions(s, x, NULL, &d) == WC_OK);
    free(x);
    diffs e = check("bent sheet 32 x 32", &m, s, 1);
    expect_match(e);
    CHECK_EQ_INT(e.dead, 0);
    /* mutation: the rest form's P_tent and R against core's about the current positions */
    diffs r = check("bent sheet 32 x 32", &m, s, 0);
    CHECK(r.tent > 100 * TOL_TENT);
    wc_state_destroy(s);
    wc_model_free(&m);
}

/* The hanging sheet squashed towards its x axis (y and z x 1e-3, rounded to float): every
 * aggregate nearly collinear, its rotation about x some 1e-3 of the others (live: core's test is
 * 1e-6), the QR ill-conditioned, where Gram-Schmidt's second pass counts. */
static void test_squashed_sheet(void) {
    wc_model m;
    wc_state* s = ts_hanging_float(&m, 32, 3, 1.0);
    CHECK(s != NULL);
    if (!s) return;
    const int n = m.n_particles;
    double* x = malloc(3 * (size_t)n * sizeof(double));
    for (int i = 0; i < n; ++i)
        for (int q = 0; q < 3; ++q) x[3 * i + q] = (float)(s->x[3 * i + q] * (q ? 1e-3 : 1.0));
    wc_diag d = {0};
    CHECK(wc_state_set_positions(s, x, NULL, &d) == WC_OK);
    free(x);
    diffs e = check("squashed sheet 32 x 32", &m, s, 1);
    expect_match(e);
    CHECK_EQ_INT(e.dead, 0);
    wc_state_destroy(s);
    wc_model_free(&m);
}

/* The sheet beside 12 pieces 4e5 m away (ts_dead_pieces), stepped 3 frames: core's dead columns
 * (three of a tiny square's six, one of a sliver's) on every level, the GPU's the same. */
static void test_dead_pieces(void) {
    wc_model m;
    wc_state* s = ts_dead_pieces(&m, 32, 12, 3);
    CHECK(s != NULL);
    if (!s) return;
    diffs e = check("sheet 32 x 32 and 12 pieces with dead rotations", &m, s, 1);
    expect_match(e);
    CHECK(e.dead > 0);
    wc_state_destroy(s);
    wc_model_free(&m);
}

int main(void) {
    if (!tg_gpu_open(&gl, &dev)) return 1;
    if (dev->compute) {
        RUN_TEST(test_bent_sheet);
        RUN_TEST(test_squashed_sheet);
        RUN_TEST(test_dead_pieces);
    } else {
        printf("  skipped: the multigrid needs compute passes\n");
    }
    tg_gpu_close(gl, dev);
    return TEST_SUMMARY();
}
