/* The GPU multigrid's smoothed prolongator (gpu/solver/wg_amg_smooth.c, wg_amg.h "smoothed") on a
 * real EGL context (llvmpipe without a GPU), against core's own smoothed-P hierarchy
 * (core/amg_setup.c: P = (I - w D^-1 A_F) P_tent, T = A P, P^T T) built with the GPU's options
 * (wg_amg_opts_for(1)) on the same float-rounded system (a hanging sheet with two pins, a sheet
 * draped over a sphere with its contacts' filter). Core's lambda_max bounds are set to the GPU's
 * (its bound_reuse, each level's estimate = the GPU's Rayleigh quotient), so that both sides
 * take the same w. Checked per level, to float precision (relative to the level's largest
 * entry): P's blocks, the next level's Galerkin blocks, and one V-cycle on a filtered random
 * vector (the restriction P^T and the prolongation P xc with it) against core's wc_amg_apply.
 * The mutations: P = P_tent on the GPU (WEFT_GPU_AMG_SMOOTH=0's hierarchy) against core's
 * smoothed one is far off on every count; w off by 1 % (core's bounds scaled) is caught too.
 * With the argument "rot" (ctest test_gpu_amg_rot) the same checks with rotations about the rest
 * positions on both sides (wg_amg_opts_form(1, 1): P_tent's blocks from core's QR, two coarse nodes
 * an aggregate, the pair levels' 6x6 block diagonal, the dead unknowns), and two more mutations:
 * the GPU's translations (WEFT_GPU_AMG_ROT=0) against core's rotations, and core's pair levels
 * smoothed with 3x3 blocks (pair_blocks 0) against the GPU's 6x6.
 * With the argument "dead" (ctest test_gpu_amg_dead) the rotations' checks on a sheet beside
 * pieces whose aggregates leave rotations dead (ts_dead_pieces: three dead of an aggregate's six
 * columns as a 1-node aggregate's, one as a 2-node or collinear one's; core's hierarchy is checked
 * to hold them, on every level), then PCG with the multigrid on that system, on the chain and in
 * one work group (WEFT_GPU_SOLVE=group's cloth), against core's PCG with the same multigrid.
 * Mutations it catches (tried by hand in amg_ptap.glsl): the dead unknowns' diagonal left 0 (the
 * coarse blocks 0.53 off, both PCGs unconverged) or set to 1 instead of the block's mean live
 * diagonal (0.52 off).
 * With a second argument "cur" (ctest test_gpu_amg_rot_current, test_gpu_amg_dead_current) the
 * rotations are about the current positions on both sides (wg_amg.current: the GPU's QR per
 * setup, amg_tent_qr.glsl; core's current_positions with wc_amg.pos the positions the GPU holds,
 * read back), every check and mutation above the same; test_gpu_amg_current checks P_tent, R and
 * the dead unknowns themselves. Without it the GPU takes the rest form (WEFT_GPU_AMG_CURRENT=0). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "gpu_group_support.h"
#include "gpu_test_device.h"
#include "solve_kernels.h"
#include "step.h"
#include "test_support.h"
#include "wg_amg.h"
#include "wg_amg_group.h"
#include "wg_sim_impl.h"

static wg_gl_context* gl;
static wg_device* dev;
static int rot;  /* 1: rotations on both sides (arguments "rot", "dead") */
static int dead; /* 1: the system with dead unknowns (argument "dead") */
static int cur;  /* 1: the rotations about the current positions on both sides (second argument "cur") */
static double* cur_pos; /* cur: the positions the GPU holds (core's wc_amg.pos) */

/* cur_pos := the positions g holds */
static void hold_positions(wg_sim* g) {
    const int n = g->n;
    float* xg = calloc(4 * (size_t)n, sizeof(float));
    free(cur_pos);
    cur_pos = calloc(3 * (size_t)n, sizeof(double));
    wg_array_read(&g->layout, wg_ring_cur(&g->x), n, xg);
    for (int i = 0; i < n; ++i)
        for (int c = 0; c < 3; ++c) cur_pos[3 * i + c] = xg[4 * i + c];
    free(xg);
}

#define TOL 2e-4 /* float against double, relative to the level's largest entry */

static void round_to_float(double* a, size_t count) {
    for (size_t k = 0; k < count; ++k) a[k] = (float)a[k];
}

/* max |g - c| / max |c| over count 3x3 blocks: g as RGBA32F block rows (three arrays), c row-major */
static double block_diff(float* const g[3], const double* c, int count) {
    double dm = 0.0, cm = 0.0;
    for (int e = 0; e < count; ++e)
        for (int r = 0; r < 3; ++r)
            for (int q = 0; q < 3; ++q) {
                double cv = c[9 * (size_t)e + 3 * r + q];
                dm = fmax(dm, fabs((double)g[r][4 * (size_t)e + q] - cv));
                cm = fmax(cm, fabs(cv));
            }
    return cm > 0 ? dm / cm : dm;
}

/* Core's hierarchy on A (float-rounded) with the GPU's bounds x scale; NULL on failure. */
static wc_amg* core_hierarchy(const wc_model* m, const wg_amg* a, const double* A, const wc_filter* f, double scale,
                              int pair_blocks, wc_par* par) {
    wc_amg_opts o = wg_amg_opts_form(1, rot);
    o.pair_blocks = pair_blocks;
    o.values = 1;
    o.single = 0;
    o.bound_reuse = 1;
    o.bound_margin = 1.0;
    o.current_positions = cur;
    wc_amg* ca = NULL;
    wc_diag d = {0};
    if (wc_amg_create(&ca, m, &o, NULL, &d) != WC_OK) return NULL;
    if (cur) ca->pos = cur_pos;
    wc_amg_setup(ca, A, f, par); /* a fresh setup, then one with the GPU's estimates */
    for (int l = 0; l < a->n_levels && l < ca->n_levels; ++l) {
        if (l == a->n_levels - 1 && a->dense) break;
        float sums[4];
        wg_read1(a->run->layout, a->lev[l].bound, sums);
        /* the GPU's factor on a coarse level's bound (a pair level's; core applies the finest's) */
        ca->lev[l].estimate = scale * (double)sums[0] / (double)sums[1] * (l > 0 ? wg_amg_bound_scale(a, l) : 1.0);
    }
    ca->hold_bounds = 1;
    wc_amg_setup(ca, A, f, par);
    ca->hold_bounds = 0;
    return ca;
}

/* One V-cycle on r by the GPU's hierarchy of g and by core's ca: max |z_gpu - z_core| / max |z_core|. */
static double vcycle_diff(wg_sim* g, const wc_amg* ca, const double* r, wc_par* par) {
    const int n = g->n;
    double *zc = calloc(3 * (size_t)n, sizeof(double)), *zg = calloc(3 * (size_t)n, sizeof(double));
    wc_amg_apply((wc_amg*)ca, r, zc, par);
    tg_vcycle(g, r, zg);
    double e = ts_max_diff(zg, zc, 3 * n) / ts_max_abs(zc, 3 * n);
    free(zc), free(zg);
    return e;
}

/* The passes the fused V-cycle saves on g's hierarchy (wg_amg.fuse): the first two smoothing steps
 * in one pass on every level (the coarsest's sweeps where it has no factor), and with the smoothed
 * prolongator the residual in the restriction on each level of at most WG_AMG_FOLD_RESIDUAL nodes,
 * and the restriction in the factored coarsest level's solve below one of at most
 * WG_AMG_FOLD_COARSE_ROWS; from the sub-cycle's cut (wg_amg.sub) down, every level's passes in
 * one (2 sweeps + 3 unfused a level: the smoothing steps, the residual, P^T, P; the coarsest
 * level's solve or its sweeps). */
static long long fused_saving(const wg_amg* a) {
    const int L = a->n_levels, cut = a->sub.i.id ? a->sub.first : L;
    long long k = 0;
    if (cut < L) {
        for (int l = cut; l + 1 < L; ++l) k += 2 * a->sweeps + 3;
        k += (a->dense ? 1 : WG_AMG_COARSE_SWEEPS) - 1;
    } else if (!a->dense) {
        k = 1;
    }
    for (int l = 0; l + 1 < L && l < cut; ++l) k += 1 + (a->smoothed && a->lev[l].n <= WG_AMG_FOLD_RESIDUAL);
    if (cut == L && a->smoothed && a->dense && L >= 2 && a->lev[L - 2].n <= WG_AMG_FOLD_COARSE_ROWS) ++k;
    return k;
}

/* Where the sub-cycle runs: the smoothed prolongator, the first level >= 1 of at most
 * WG_AMG_SUB_ROWS nodes with a level below it (every level from it within WG_AMG_SUB_NODES). */
static int sub_expected(const wg_amg* a) {
    if (!a->smoothed) return 0;
    int cut = 1;
    while (cut + 1 < a->n_levels && a->lev[cut].n > WG_AMG_SUB_ROWS) ++cut;
    if (cut + 1 >= a->n_levels) return 0;
    for (int l = cut; l < a->n_levels; ++l)
        if (a->lev[l].n > WG_AMG_SUB_NODES) return 0;
    return cut;
}

/* One V-cycle on r by g's fused passes against the same by one pass a step (wg_amg.fuse 0: the
 * same arithmetic): max |z_fused - z_unfused| / max |z_unfused|, and the passes each queued. */
static double fused_diff(wg_sim* g, const double* r, long long passes[2]) {
    const int n = g->n;
    double* z[2];
    for (int f = 0; f < 2; ++f) {
        z[f] = calloc(3 * (size_t)n, sizeof(double));
        g->amg->fuse = 1 - f;
        const long long p0 = wg_sim_debug_passes(g);
        tg_vcycle(g, r, z[f]);
        passes[f] = wg_sim_debug_passes(g) - p0;
    }
    g->amg->fuse = 1;
    double e = ts_max_diff(z[0], z[1], 3 * n) / ts_max_abs(z[1], 3 * n);
    printf("    fused V-cycle against one pass a step: %.2e apart, %lld passes against %lld\n", e, passes[0], passes[1]);
    free(z[0]), free(z[1]);
    return e;
}

/* The fused V-cycle is the unfused one (to float rounding, FUSE_TOL) in fused_saving's fewer passes. */
#define FUSE_TOL 1e-6
static void check_fused(wg_sim* g, const double* r) {
    long long p[2];
    CHECK(fused_diff(g, r, p) <= FUSE_TOL);
    CHECK(p[1] - p[0] == fused_saving(g->amg));
    const int cut = sub_expected(g->amg);
    CHECK_EQ_INT(g->amg->sub.i.id ? g->amg->sub.first : 0, cut);
    if (cut) printf("    the V-cycle from level %d (%d nodes) in one work group\n", cut, g->amg->lev[cut].n);
}

/* The worst P, coarse-operator and V-cycle differences of the GPU's hierarchy g against core's ca. */
static void compare(wg_sim* g, const wc_amg* ca, const double* r, wc_par* par, double out[3]) {
    wg_amg* a = g->amg;
    out[0] = out[1] = out[2] = 0.0;
    for (int l = 0; l + 1 < a->n_levels; ++l) {
        const wg_amg_level *G = &a->lev[l], *N = &a->lev[l + 1];
        const wc_amg_level *C = &ca->lev[l], *CN = &ca->lev[l + 1];
        int np = C->p_start[C->n], cap = np > CN->n_blocks ? np : CN->n_blocks;
        float* buf[3];
        for (int c = 0; c < 3; ++c) buf[c] = calloc(4 * (size_t)cap, sizeof(float));
        double dp = 1.0, da;
        if (a->smoothed) {
            for (int c = 0; c < 3; ++c) wg_array_read(&g->layout, &G->p[c], np, buf[c]);
            dp = block_diff(buf, C->p_val, np);
        }
        for (int c = 0; c < 3; ++c) wg_array_read(&g->layout, &N->a[c], N->nb, buf[c]);
        da = N->nb == CN->n_blocks ? block_diff(buf, CN->val, N->nb) : 1.0;
        int dead = 0; /* rotations: the next level's dead unknowns (amg_ptap.glsl revives them) */
        for (int k = 0; CN->dead && k < 3 * CN->n; ++k) dead += CN->dead[k];
        printf("    level %d (%d nodes): P %d entries, |dP| %.2e; level %d (%d nodes, %d blocks, %d dead), |dA| %.2e\n",
               l, G->n, np, dp, l + 1, N->n, N->nb, dead, da);
        out[0] = fmax(out[0], dp);
        out[1] = fmax(out[1], da);
        for (int c = 0; c < 3; ++c) free(buf[c]);
    }
    out[2] = vcycle_diff(g, ca, r, par);
    printf("    V-cycle: |z_gpu - z_core| / |z_core| %.2e\n", out[2]);
}

/* The texture of a list of `items` (two a texel, wg_amg_smooth.c upload_keyed) is that size, and
 * its ranges one RG32I texel a group. */
static int list_holds(const wg_layout* L, const wg_tex* range, int groups, const wg_tex* t, long items) {
    int w, h, rw, rh;
    wg_layout_size(L, items > 1 ? (int)((items + 1) / 2) : 1, &w, &h);
    wg_layout_size(L, groups, &rw, &rh);
    return t->w == w && t->h == h && t->internal == GL_RGBA32I && range->w == rw && range->h == rh &&
           range->internal == GL_RG32I;
}

/* The smoothed prolongator's lists of level l hold what core's patterns of P, T = A P and the next
 * level's P^T T call for, two products a texel, and with rotations (two coarse nodes an aggregate,
 * cpa 2) only the products of an even coarse node's entries: one list per pair of entries of P,
 * of T and of the pairs' nodes, one per 2 x 2 group of the next level's blocks (the odd ones
 * read it shifted), their ranges 8 bytes a group. 1 when all four are so. */
static int lists_stored(const wg_sim* g, int l, const wc_amg_level* C, const wc_amg_level* CN) {
    const wg_amg_level *G = &g->amg->lev[l], *N = &g->amg->lev[l + 1];
    const int cpa = C->cpa;
    long n_p = C->n_blocks, n_t = 0, n_gal = 0, n_pt = 0;
    for (int i = 0; i < C->n; ++i)
        for (int k = C->row_start[i]; k < C->row_start[i + 1]; ++k)
            for (int e = C->p_start[C->col[k]]; e < C->p_start[C->col[k] + 1]; ++e) n_t += C->p_col[e] % cpa == 0;
    for (int I = 0; I < CN->n; I += cpa)
        for (int s = C->pt_start[I]; s < C->pt_start[I + 1]; ++s) {
            const int i = C->pt_row[s];
            ++n_pt;
            for (int q = C->t_start[i]; q < C->t_start[i + 1]; ++q) n_gal += C->t_col[q] % cpa == 0;
        }
    printf("    level %d's lists: %ld, %ld, %ld, %ld products (P, T, P^T T, P^T)\n", l, n_p, n_t, n_gal, n_pt);
    const wg_layout* L = &g->layout;
    return list_holds(L, &G->p_range, G->np, &G->p_list, n_p) &&
           list_holds(L, &G->t_range, G->nt, &G->t_list, n_t) &&
           list_holds(L, &N->gal_range, N->nb, &N->gal_list, n_gal) &&
           list_holds(L, &G->pt_range, N->n, &G->pt_list, n_pt);
}

/* One system: the GPU's hierarchy (smoothed, and with P = P_tent as the mutation) against core's. */
static void check_system(const char* name, wc_model* m, wc_state* s) {
    const double h = 1.0 / 30.0;
    const int n = m->n_particles;
    wc_diag d = {0};
    wc_step_stats st;
    memset(&st, 0, sizeof st);
    wg_sim* g = NULL;
    dev->amg_smooth = 1;
    dev->amg_rot = rot;
    dev->amg_current = cur;
    CHECK(wg_sim_create(dev, s, NULL, &g, &d) == WC_OK);
    if (!g) {
        fprintf(stderr, "%s\n", d.message);
        return;
    }
    CHECK(g->amg->smoothed == 1);
    CHECK_EQ_INT(g->amg->rotations, rot);
    CHECK_EQ_INT(g->amg->current, cur);
    hold_positions(g);
    CHECK(wg_sim_debug_prepare(g, s, h, 1.0, NULL, NULL, NULL, NULL, NULL, NULL, &d) == WC_OK);
    wc_substep_prepare(s, h, 1.0, &st);
    const size_t nb9 = 9 * (size_t)m->pattern.n_blocks;
    double* A = malloc(nb9 * sizeof(double));
    memcpy(A, s->A, nb9 * sizeof(double));
    round_to_float(A, nb9);
    CHECK(wg_sim_debug_set_system(g, A, s->b, &s->filter, &d) == WC_OK);
    wg_amg_setup(g->amg);
    /* a filtered random vector */
    double* r = malloc(3 * (size_t)n * sizeof(double));
    unsigned seed = 7u;
    for (int k = 0; k < 3 * n; ++k) {
        seed = seed * 1103515245u + 12345u;
        r[k] = ((seed >> 8) & 0xffff) / 32768.0 - 1.0;
    }
    for (int i = 0; i < n; ++i) wc_filter_apply(&s->filter, i, r + 3 * i, r + 3 * i);
    round_to_float(r, 3 * (size_t)n);
    wc_par par;
    wc_par_init(&par, 1);
    printf("  %s: %d particles, %d levels (coarsest %d nodes)\n", name, n, g->amg->n_levels,
           g->amg->lev[g->amg->n_levels - 1].n);
    wc_amg* ca = core_hierarchy(m, g->amg, A, &s->filter, 1.0, 1, &par);
    CHECK(ca != NULL);
    if (!ca) return;
    CHECK_EQ_INT(ca->n_levels, g->amg->n_levels);
    CHECK(ca->n_levels >= 2);
    double e[3];
    compare(g, ca, r, &par, e);
    for (int l = 0; l + 1 < ca->n_levels; ++l) CHECK(lists_stored(g, l, &ca->lev[l], &ca->lev[l + 1]));
    CHECK(e[0] <= TOL);
    CHECK(e[1] <= TOL);
    CHECK(e[2] <= 10 * TOL);
    check_fused(g, r);
    /* a second setup, on 2 A: the sub-cycle's levels packed again (a stale pack is apart), then
       back to A (cold setups: the first's state again) */
    for (int pass = 0; pass < 2; ++pass) {
        for (size_t k = 0; k < nb9; ++k) A[k] = pass == 0 ? 2.0 * A[k] : 0.5 * A[k];
        CHECK(wg_sim_debug_set_system(g, A, s->b, &s->filter, &d) == WC_OK);
        wg_amg_cold(g->amg);
        wg_amg_setup(g->amg);
        if (pass == 0) check_fused(g, r);
    }
    /* mutation: core's w 1 % off (its bounds scaled) */
    wc_amg* cw = core_hierarchy(m, g->amg, A, &s->filter, 1.01, 1, &par);
    double ew[3];
    printf("  mutation, core's w x 1/1.01:\n");
    compare(g, cw, r, &par, ew);
    CHECK(ew[0] > 10 * TOL && ew[1] > 10 * TOL);
    wc_amg_destroy(cw);
    if (rot && g->amg->n_levels >= 3) {
        /* mutation (a hierarchy with a smoothed pair level): core's pair levels smoothed with two
           3x3 blocks, not the pair's 6x6 */
        wc_amg* c3 = core_hierarchy(m, g->amg, A, &s->filter, 1.0, 0, &par);
        double e3[3];
        printf("  mutation, core's pair levels with 3x3 blocks:\n");
        compare(g, c3, r, &par, e3);
        CHECK(e3[0] > 10 * TOL && e3[2] > 10 * TOL);
        wc_amg_destroy(c3);
    }
    if (rot) {
        /* mutation: the GPU's translations against core's rotations (the V-cycle) */
        wg_sim* gt = NULL;
        dev->amg_rot = 0;
        CHECK(wg_sim_create(dev, s, NULL, &gt, &d) == WC_OK);
        dev->amg_rot = rot;
        if (gt) {
            CHECK(gt->amg->rotations == 0);
            CHECK(wg_sim_debug_prepare(gt, s, h, 1.0, NULL, NULL, NULL, NULL, NULL, NULL, &d) == WC_OK);
            CHECK(wg_sim_debug_set_system(gt, A, s->b, &s->filter, &d) == WC_OK);
            wg_amg_setup(gt->amg);
            double zt = vcycle_diff(gt, ca, r, &par);
            printf("  mutation, the GPU's translations: V-cycle |z_gpu - z_core| / |z_core| %.2e\n", zt);
            CHECK(zt > 100 * e[2] && zt > 10 * TOL);
            wg_sim_destroy(gt);
        }
    }
    /* mutation: the GPU's P = P_tent (its coarse patterns are core's unsmoothed ones: compare
       the V-cycle, and P's blocks as P_tent's identity blocks are not) */
    wg_sim* g0 = NULL;
    dev->amg_smooth = 0;
    CHECK(wg_sim_create(dev, s, NULL, &g0, &d) == WC_OK);
    dev->amg_smooth = 1;
    if (g0) {
        CHECK(g0->amg->smoothed == 0);
        CHECK(wg_sim_debug_prepare(g0, s, h, 1.0, NULL, NULL, NULL, NULL, NULL, NULL, &d) == WC_OK);
        CHECK(wg_sim_debug_set_system(g0, A, s->b, &s->filter, &d) == WC_OK);
        wg_amg_setup(g0->amg);
        double ez = vcycle_diff(g0, ca, r, &par);
        printf("  mutation, the GPU's P = P_tent: V-cycle |z_gpu - z_core| / |z_core| %.2e\n", ez);
        CHECK(ez > 100 * e[2] && ez > 10 * TOL);
        check_fused(g0, r);   /* P = P_tent's fused passes (the first two steps) */
        wg_sim_destroy(g0);
    }
    wc_amg_destroy(ca);
    free(A), free(r);
    wg_sim_destroy(g);
}

static void test_against_core(void) {
    wc_model m;
    wc_state* s = ts_hanging_float(&m, 32, 3, 1.0);
    CHECK(s != NULL);
    if (s) {
        check_system("hanging 32 x 32", &m, s);
        wc_state_destroy(s);
        wc_model_free(&m);
    }
    const wc_sim_def def = ts_amg_def();
    s = ts_draped(&m, 24, &def, 20);
    CHECK(s != NULL);
    if (s) {
        printf("  draped: %d particles in contact\n", s->contacts.active);
        CHECK(s->contacts.active >= 20);
        check_system("draped over a sphere", &m, s);
        wc_state_destroy(s);
        wc_model_free(&m);
    }
}

/* Core's aggregates on each level l of ca by the dead unknowns they leave on level l + 1 (of the
 * six columns of nodes 2a, 2a + 1): counts[l][k] aggregates with k dead (k = 0..6), counts[l][7]
 * those of at most 2 nodes */
static void dead_census(const wc_amg* ca, int counts[][8]) {
    for (int l = 0; l + 1 < ca->n_levels; ++l) {
        const wc_amg_level *L = &ca->lev[l], *N = &ca->lev[l + 1];
        const int n_agg = N->n / 2;
        memset(counts[l], 0, 8 * sizeof(int));
        int small = 0;
        for (int a = 0; a < n_agg; ++a) {
            int k = 0;
            for (int c = 0; c < 6; ++c) k += N->dead[6 * a + c];
            ++counts[l][k];
            small += L->agg_start[a + 1] - L->agg_start[a] <= 2;
        }
        printf("    level %d: %d aggregates (%d of at most 2 nodes), dead columns 0..6: %d %d %d %d %d %d %d\n", l, n_agg,
               small, counts[l][0], counts[l][1], counts[l][2], counts[l][3], counts[l][4], counts[l][5], counts[l][6]);
        counts[l][7] = small;
    }
}

/* PCG with the multigrid on s's system: the chain and the group (a cloth made under
 * WEFT_GPU_SOLVE=group) against core's PCG with the GPU's method (wg_amg_opts()) and CHOLMOD:
 * converged, iterations within test_gpu_amg's margin of core's, the group within 1 of the chain. */
static void dead_solves(wc_model* m, wc_state* s) {
    const int n = m->n_particles;
    wc_diag d = {0};
    dev->solve = WG_SOLVE_GROUP;
    dev->amg_current = cur;
    wg_sim* g = tg_gpu_system(dev, s, 0);
    dev->solve = WG_SOLVE_AUTO;
    CHECK(g != NULL && g->amg != NULL);
    if (!g || !g->amg) return;
    CHECK(g->amg->rotations == 1);
    CHECK(wg_amg_group_fits(g->amg));
    wc_solver_opts o = s->def.solver;
    o.tolerance = 1e-4;
    o.max_iterations = 300;
    wc_solver *direct = NULL, *cpu = NULL;
    o.type = WC_SOLVER_DIRECT;
    CHECK(wc_solver_create(&direct, m, &o, 1, NULL, &d) == WC_OK);
    o.type = WC_SOLVER_PCG;
    CHECK(wc_solver_create(&cpu, m, &o, 0, NULL, &d) == WC_OK);
    if (!direct || !cpu) return;
    wc_amg_destroy(cpu->amg);
    cpu->amg = NULL;
    wc_amg_opts ao = wg_amg_opts();
    ao.values = 1;
    ao.current_positions = cur;
    ao.single_setup = 0;   /* core's reference in double: the bounds below scale by its error */
    CHECK(wc_amg_create(&cpu->amg, m, &ao, &cpu->alloc, &d) == WC_OK);
    CHECK_EQ_INT(g->amg->current, cur);
    if (cur) {
        hold_positions(g);
        cpu->amg->pos = cur_pos;
    }
    wc_solver_set_residual_floor(cpu, wc_state_residual_floor(s, 1.0 / 30.0));
    double *ref = calloc(3 * (size_t)n, sizeof(double)), *dc = calloc(3 * (size_t)n, sizeof(double));
    wc_solve_result rd, rc;
    CHECK(wc_solve(direct, WC_SOLVER_DIRECT, s->A, s->b, &s->filter, ref, &s->par, &rd) == WC_OK);
    wc_solve(cpu, WC_SOLVER_PCG, s->A, s->b, &s->filter, dc, &s->par, &rc);
    tg_solved ch = tg_solve_as(dev, g, &o, NULL, WG_SOLVE_PASSES), gr = tg_solve_as(dev, g, &o, NULL, WG_SOLVE_GROUP);
    const double scale = ts_max_abs(ref, 3 * n), ec = ts_max_diff(dc, ref, 3 * n) / scale;
    const double e_ch = ts_max_diff(ch.dv, ref, 3 * n) / scale, e_gr = ts_max_diff(gr.dv, ref, 3 * n) / scale;
    printf("  PCG (tolerance 1e-4): core %d iterations (error vs CHOLMOD %.2e), GPU chain %d (%.2e, residual %.2e), "
           "group %d (%.2e, residual %.2e)\n",
           rc.iterations, ec, ch.res.iterations, e_ch, ch.res.residual, gr.res.iterations, e_gr, gr.res.residual);
    CHECK(rc.converged);
    CHECK(ch.st == WC_OK && ch.res.converged && ch.res.residual <= 1e-4);
    CHECK(gr.st == WC_OK && gr.res.converged && gr.res.residual <= 1e-4);
    CHECK(ch.res.iterations <= 1.5 * rc.iterations + 3);
    CHECK(abs(gr.res.iterations - ch.res.iterations) <= 1);
    CHECK(e_ch <= 5.0 * (ec / rc.residual) * ch.res.residual + 1e-4);
    CHECK(e_gr <= 5.0 * (ec / rc.residual) * gr.res.residual + 1e-4);
    free(ref), free(dc), free(ch.dv), free(gr.dv);
    wc_solver_destroy(cpu);
    wc_solver_destroy(direct);
    wg_sim_destroy(g);
}

/* A 32 x 32 sheet beside 12 pieces (ts_dead_pieces): core's hierarchy holds aggregates with three
 * and with one dead column on every level; the GPU's P, Galerkin blocks and V-cycle against
 * core's (check_system, its mutations included), then the solves. */
static void test_dead(void) {
    wc_model m;
    wc_state* s = ts_dead_pieces(&m, 32, 12, 3);
    CHECK(s != NULL);
    if (!s) return;
    wc_amg_opts o = wg_amg_opts_form(1, 1);
    wc_amg* ca = NULL;
    wc_diag d = {0};
    CHECK(wc_amg_create(&ca, &m, &o, NULL, &d) == WC_OK);
    if (ca) {
        int counts[WC_AMG_MAX_LEVELS][8];
        CHECK(ca->n_levels >= 3);
        dead_census(ca, counts);
        for (int l = 0; l + 1 < ca->n_levels; ++l) {
            CHECK_EQ_INT(counts[l][3], 6);   /* the tiny squares: as 1-node aggregates */
            CHECK_EQ_INT(counts[l][1], 6);   /* the slivers: as 2-node ones */
            CHECK_EQ_INT(counts[l][2] + counts[l][4] + counts[l][5] + counts[l][6], 0);
            /* below the finest level each piece is one aggregate of one pair (2 nodes); on the
               finest its 4 particles (a mesh has no 1- or 2-particle aggregate) */
            CHECK_EQ_INT(counts[l][7], l > 0 ? 12 : 0);
        }
        wc_amg_destroy(ca);
    }
    check_system("sheet 32 x 32 and 12 pieces with dead rotations", &m, s);
    dead_solves(&m, s);
    wc_state_destroy(s);
    wc_model_free(&m);
}

int main(int argc, char** argv) {
    dead = argc > 1 && strcmp(argv[1], "dead") == 0;
    rot = dead || (argc > 1 && strcmp(argv[1], "rot") == 0);
    cur = rot && argc > 2 && strcmp(argv[2], "cur") == 0;
    printf("  near-null space: %s\n", !rot ? "translations" : cur ? "rotations (current positions)" : "rotations (rest positions)");
    if (!tg_gpu_open(&gl, &dev)) return 1;
    if (dev->compute && dead) RUN_TEST(test_dead);
    else if (dev->compute) RUN_TEST(test_against_core);
    else printf("  skipped: the multigrid needs compute passes\n");
    tg_gpu_close(gl, dev);
    free(cur_pos);
    return TEST_SUMMARY();
}
