/* The linear solvers on the GPU, the same methods as core/solve_*.c on the filtered system
 * A dv = b, (S, z): filtered PCG with the block-diagonal preconditioner, block Jacobi and
 * Chebyshev-accelerated block Jacobi. No read-back per iteration: PCG's scalars (delta, alpha,
 * beta, |r|^2, done / diverged / converged flags, iteration count) live in a 1 x 1 texture that
 * reduction passes feed and later passes read; once the GPU marks the solve done, the remaining
 * queued passes change nothing. The host reads the flags back every check_every iterations to
 * stop queueing (and to confirm convergence with the true residual, restarting from it on drift
 * as core's PCG does), and the result once at the end. Jacobi and Chebyshev measure the residual
 * every check_every iterations (a reduction and one texel read back), as on the CPU. A small
 * cloth's PCG runs instead as one dispatch of one work group that does all of the above, host
 * loop included, with block Jacobi (pcg_group.glsl) or the multigrid's V-cycle after its setup
 * passes (pcg_group_amg.glsl); wg_device.h wg_solve_mode says where. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "wg_amg_group.h"
#include "wg_sim_impl.h"

/* A sum that the scalars pass finishes: the first `count` texels of tex (layout order) add up to
 * it. Compute passes leave per-work-group partials (the fused passes' or a reduction's first
 * level, wg_reduce_sums); fragment passes a whole reduction (count 1). */
typedef struct wg_sums {
    const wg_tex* tex;
    int count;
} wg_sums;

static const wg_sums kNoSums = {NULL, 0};

static wg_sums sums_of(wg_sim* g, wg_chain* ch, const wg_tex* src) {
    wg_sums s;
    s.tex = wg_reduce_sums(&g->run, ch, src, &s.count);
    return s;
}

/* Work groups of a 256-invocation dispatch over every texel of a particle array */
static int groups_of(const wg_sim* g, int per_texel) {
    long long texels = (long long)g->q.w * g->q.h;
    return (int)((per_texel * texels + 255) / 256);
}

/* The most partials a pass finishes in every work group (a scalars step folded into the pass
 * after it: each group reads them all, a few texels an invocation). */
#define FOLD_MAX 1024

/* pcg_scalars_rules.glsl's uniforms, on the program in use */
static void rules_uniforms(wg_sim* g, const wc_solver_opts* o, int mode, int max_it) {
    wg_runner* run = &g->run;
    wg_u1i(run, "u_mode", mode);
    wg_u1f(run, "u_tolerance", o->tolerance);
    wg_u1f(run, "u_divergence", o->divergence_factor);
    wg_u1f(run, "u_max_iterations", (double)max_it);
    wg_u1f(run, "u_floor", g->residual_floor);
}

/* sc[cur] -> sc[other] (pcg_scalars_rules.glsl's mode; sum and dots: kNoSums where the mode reads
 * none). Compute passes: one work group that finishes both sums first (pcg_scalars_groups.glsl). */
static void scalars(wg_sim* g, const wc_solver_opts* o, int mode, wg_sums sum, wg_sums dots, int max_it) {
    wg_runner* run = &g->run;
    int a = g->sc_cur, b = 1 - a;
    const int groups = g->dev->compute;
    WG_USE(run, groups ? WGP_PCG_SCALARS_GROUPS : WGP_PCG_SCALARS, &(wg_pcg_scalars_in){.scalars0 = &g->sc[a][0],
        .scalars1 = &g->sc[a][1], .sum = sum.tex ? sum.tex : &g->sc[a][0], .dots = dots.tex ? dots.tex : &g->sc[a][0],
        .scalars2 = &g->sc[a][2]});
    rules_uniforms(g, o, mode, max_it);
    if (groups) {
        wg_u1i(run, "u_sum_n", sum.count);
        wg_u1i(run, "u_dots_n", dots.count);
        WG_RUN_GROUPS(run, 1, 1, &g->sc[b][0], &g->sc[b][1], &g->sc[b][2]);
    } else {
        WG_RUN(run, 1, &g->sc[b][0], &g->sc[b][1], &g->sc[b][2]);
    }
    g->sc_cur = b;
}

/* out = S (b - A x); with size, also |A| |x| per particle (residual.glsl) */
static void residual2(wg_sim* g, const wg_tex* x, const wg_tex* out, const wg_tex* size) {
    wg_runner* run = &g->run;
    WG_USE(run, WGP_RESIDUAL, &(wg_residual_in){.pblocks = &g->pblocks, .block = &g->block, .a_lo = &g->A0,
        .a_hi = &g->A1, .x = x, .b = &g->b, .S0 = &g->S0, .S1 = &g->S1, .pairs = wg_sim_pair_in(g)});
    wg_sim_pair_uniform(g);
    if (size) WG_RUN(run, g->n, out, size);
    else WG_RUN(run, g->n, out);
}

static void residual(wg_sim* g, const wg_tex* x, const wg_tex* out) { residual2(g, x, out, NULL); }

static void project(wg_sim* g, const wg_tex* in, const wg_tex* out, int to_z) {
    wg_runner* run = &g->run;
    WG_USE(run, WGP_PROJECT, &(wg_project_in){.dv = in, .S0 = &g->S0, .S1 = &g->S1, .z = &g->z});
    wg_u1i(run, "u_to_z", to_z);
    WG_RUN(run, g->n, out);
}

/* q = A x over rows [0, rows) (g->n but in a test); with filter, q = S (A x) and its w = x.q. With
 * partials (compute passes only): also the sums of w per work group into gpart[0]. Returns the
 * work groups run (0 for a fragment pass). */
static int spmv_rows(wg_sim* g, const wg_tex* x, int filter, int rows, int partials) {
    wg_runner* run = &g->run;
    WG_USE(run, g->dev->compute ? WGP_SPMV_GROUPS : WGP_SPMV, &(wg_spmv_in){.pblocks = &g->pblocks, .block = &g->block,
        .a_lo = &g->A0, .a_hi = &g->A1, .x = x, .S0 = &g->S0, .S1 = &g->S1, .pairs = wg_sim_pair_in(g)});
    wg_u1i(run, "u_filter", filter);
    wg_sim_pair_uniform(g);
    if (!g->dev->compute) {
        WG_RUN(run, rows, &g->q);
        return 0;
    }
    /* spmv_groups.glsl: 4 invocations a row, 256 a group */
    const int groups = groups_of(g, 4);
    wg_u1i(run, "u_texels", g->q.w * g->q.h);
    wg_u1i(run, "u_partials", partials);
    if (partials) WG_RUN_GROUPS(run, rows, groups, &g->q, &g->gpart[0]);
    else WG_RUN_GROUPS(run, rows, groups, &g->q);
    return groups;
}

void wg_spmv(wg_sim* g, const wg_tex* x, int filter) { spmv_rows(g, x, filter, g->n, 0); }

/* PCG's q = S (A c) and the sum c.q for scalars(): compute passes fold the sum's first level into
 * the SpMV (a partial a work group); fragment passes reduce q's w. */
static wg_sums spmv_dot(wg_sim* g, const wg_tex* c, int rows) {
    if (!g->dev->compute) {
        spmv_rows(g, c, 1, rows, 0);
        return sums_of(g, &g->red_p[0], &g->q);
    }
    return (wg_sums){&g->gpart[0], spmv_rows(g, c, 1, rows, 1)};
}

typedef struct pcg_vecs {
    int dv, r, c;   /* indices into g->sv (0/1), g->r, g->c */
} pcg_vecs;

/* Block Jacobi's update on compute passes (pcg_update_groups.glsl): dv, r, t and the partials of
 * (r.t, r.r) in one pass; with alpha (o, max_it), also alpha's scalars step (mode 1, from the
 * SpMV's partials cq) before the update, in every work group. */
static wg_sums update_groups(wg_sim* g, pcg_vecs* v, int first, int rows, const wc_solver_opts* alpha, wg_sums cq,
                             int max_it) {
    wg_runner* run = &g->run;
    const int a = g->sc_cur, b = 1 - a;
    WG_USE(run, WGP_PCG_UPDATE_GROUPS, &(wg_pcg_update_groups_in){.dv = &g->sv[v->dv], .r = &g->r[v->r],
        .c = &g->c[v->c], .q = &g->q, .dinv_lo = &g->D0, .dinv_hi = &g->D1, .scalars0 = &g->sc[a][0],
        .scalars1 = &g->sc[a][1], .scalars2 = &g->sc[a][2], .sum = alpha ? cq.tex : &g->sc[a][0]});
    wg_u1i(run, "u_first", first);
    wg_u1i(run, "u_jacobi", !g->amg_on);   /* the multigrid: t = 0, its partials unread */
    wg_u1i(run, "u_fold", alpha != NULL);
    wg_u1i(run, "u_sum_n", alpha ? cq.count : 0);
    wg_u1i(run, "u_texels", g->q.w * g->q.h);
    if (alpha) rules_uniforms(g, alpha, 1, max_it);
    const wg_tex *dv = &g->sv[1 - v->dv], *r = &g->r[1 - v->r];
    v->dv = 1 - v->dv;
    v->r = 1 - v->r;
    const int k = groups_of(g, 1);
    if (alpha) {
        WG_RUN_GROUPS(run, rows, k, dv, r, &g->t, &g->gpart[1], &g->sc[b][0], &g->sc[b][1], &g->sc[b][2]);
        g->sc_cur = b;
    } else {
        WG_RUN_GROUPS(run, rows, k, dv, r, &g->t, &g->gpart[1]);
    }
    return (wg_sums){&g->gpart[1], k};
}

/* dv += alpha c, r -= alpha q, z = M^-1 r over rows [0, rows), and the sums (r.z, r.r) for
 * scalars(). Block Jacobi on compute passes: one pass with the sums' first level folded in
 * (update_groups); fragment passes reduce the update's partial products; the multigrid gives z
 * and the products itself. */
static wg_sums update(wg_sim* g, pcg_vecs* v, int first, int rows) {
    wg_runner* run = &g->run;
    if (g->dev->compute && !g->amg_on) return update_groups(g, v, first, rows, NULL, kNoSums, 0);
    WG_USE(run, WGP_PCG_UPDATE, &(wg_pcg_update_in){.dv = &g->sv[v->dv], .r = &g->r[v->r], .c = &g->c[v->c],
        .q = &g->q, .dinv_lo = &g->D0, .dinv_hi = &g->D1, .scalars0 = &g->sc[g->sc_cur][0],
        .scalars1 = &g->sc[g->sc_cur][1]});
    wg_u1i(run, "u_first", first);
    wg_u1i(run, "u_jacobi", !g->amg_on);
    const wg_tex *dv = &g->sv[1 - v->dv], *r = &g->r[1 - v->r];
    v->dv = 1 - v->dv;
    v->r = 1 - v->r;
    if (!g->amg_on) {
        WG_RUN(run, rows, dv, r, &g->t, &g->part);
        return sums_of(g, &g->red_p[1], &g->part);
    }
    /* the multigrid's z = M^-1 r replaces the block-Jacobi t, and its (r.z, r.r) the update's */
    WG_RUN(run, rows, dv, r);
    wg_amg_apply(g->amg, r, &g->part);
    return sums_of(g, &g->red_p[1], &g->part);
}

static void direction(wg_sim* g, pcg_vecs* v, int first) {
    wg_runner* run = &g->run;
    WG_USE(run, WGP_PCG_DIRECTION, &(wg_pcg_direction_in){.t = g->amg_on ? g->amg->z : &g->t, .c = &g->c[v->c],
        .S0 = &g->S0, .S1 = &g->S1, .scalars0 = &g->sc[g->sc_cur][0], .scalars1 = &g->sc[g->sc_cur][1]});
    wg_u1i(run, "u_first", first);
    WG_RUN(run, g->n, &g->c[1 - v->c]);
    v->c = 1 - v->c;
}

/* The next direction with beta's scalars step (mode 2, from the update's partials) folded in
 * (pcg_direction_groups.glsl). */
static void direction_groups(wg_sim* g, const wc_solver_opts* o, pcg_vecs* v, wg_sums dots, int max_it) {
    wg_runner* run = &g->run;
    const int a = g->sc_cur, b = 1 - a;
    WG_USE(run, WGP_PCG_DIRECTION_GROUPS, &(wg_pcg_direction_groups_in){.t = g->amg_on ? g->amg->z : &g->t,
        .c = &g->c[v->c], .S0 = &g->S0, .S1 = &g->S1, .scalars0 = &g->sc[a][0], .scalars1 = &g->sc[a][1],
        .scalars2 = &g->sc[a][2], .dots = dots.tex});
    rules_uniforms(g, o, 2, max_it);
    wg_u1i(run, "u_dots_n", dots.count);
    wg_u1i(run, "u_texels", g->q.w * g->q.h);
    WG_RUN_GROUPS(run, g->n, groups_of(g, 1), &g->c[1 - v->c], &g->sc[b][0], &g->sc[b][1], &g->sc[b][2]);
    g->sc_cur = b;
    v->c = 1 - v->c;
}

/* One PCG iteration, queued. Compute passes fold each sum's first level into the pass that makes
 * its input, and each scalars step into the pass after it where that pass can finish the sum in
 * every work group (at most FOLD_MAX partials): block Jacobi then takes 3 passes (SpMV, update,
 * direction) up to 65,536 particles, 4 up to 262,144 and 5 beyond; fragment passes 7 or more. */
static void pcg_iteration(wg_sim* g, const wc_solver_opts* o, pcg_vecs* v, int max_it) {
    const wg_sums cq = spmv_dot(g, &g->c[v->c], g->n);
    const int fold = g->dev->compute;
    wg_sums dots;
    if (fold && cq.count <= FOLD_MAX) {
        dots = update_groups(g, v, 0, g->n, o, cq, max_it);
        if (g->amg_on) { /* the update's dv and r, then the V-cycle's z and (r.z, r.r) */
            wg_amg_apply(g->amg, &g->r[v->r], &g->part);
            dots = sums_of(g, &g->red_p[1], &g->part);
        }
    } else {
        scalars(g, o, 1, cq, kNoSums, max_it);
        dots = update(g, v, 0, g->n);
    }
    if (fold && dots.count <= FOLD_MAX) {
        direction_groups(g, o, v, dots, max_it);
    } else {
        scalars(g, o, 2, kNoSums, dots, max_it);
        direction(g, v, 0);
    }
}

static void read_scalars(wg_sim* g, float s0[4], float s1[4], float s2[4]) {
    wg_read1(&g->layout, &g->sc[g->sc_cur][0], s0);
    wg_read1(&g->layout, &g->sc[g->sc_cur][1], s1);
    wg_read1(&g->layout, &g->sc[g->sc_cur][2], s2);
}

/* |S (b - A x)|^2 of x (into r[spare]); one texel read back. With floor: also the residual's
 * float floor, 2^-24 |(|A| |x|)| (residual.glsl; the unit roundoff of the sums the product
 * makes), into *floor (g->t is its scratch: update() rewrites it before direction() reads it). */
static double true_residual2(wg_sim* g, const wg_tex* x, const wg_tex* out, double* floor) {
    wg_runner* run = &g->run;
    residual2(g, x, out, floor ? &g->t : NULL);
    float v[4];
    wg_read1(&g->layout, wg_reduce(run, &g->red_p[0], out, 0, 0, 0, 0), v);
    if (floor) {
        float a[4];
        wg_read1(&g->layout, wg_reduce(run, &g->red_p[0], &g->t, 0, 0, 0, 0), a);
        *floor = ldexp(sqrt((double)a[3]), -24);
    }
    return (double)v[3];
}

static wc_status solve_pcg(wg_sim* g, const wc_solver_opts* o, const wg_tex** out, wc_solve_result* res) {
    pcg_vecs v = {0, 0, 0};
    const int K = o->check_every > 0 ? o->check_every : 10, max_it = o->max_iterations;
    /* residual0 from z, then the initial guess (sv[0], projected) */
    residual(g, &g->z, &g->rz);
    const wg_sums r0 = sums_of(g, &g->red_p[0], &g->rz);
    residual(g, &g->sv[0], &g->r[0]);
    const wg_sums dots = update(g, &v, 1, g->n);
    /* keep residual0's reduction: red_p[0] is reused by the next reductions, so scalars read it now */
    scalars(g, o, 0, r0, dots, max_it);
    direction(g, &v, 1);
    float s0[4], s1[4], s2[4];
    wc_status st = WC_OK;
    int converged = 0, queued = 0;
    double rt = -1.0;
    for (;;) {
        read_scalars(g, s0, s1, s2);
        if (s1[0] != 0.0f) {
            if (s1[1] != 0.0f) {
                st = WC_ERROR_SOLVER_DIVERGED;
                break;
            }
            if (s1[3] == 0.0f) break;   /* the iteration cap */
            if (s2[0] == 0.0f) {        /* zero right-hand side: dv = z */
                project(g, &g->sv[v.dv], &g->sv[1 - v.dv], 1);
                v.dv = 1 - v.dv;
                *out = &g->sv[v.dv];
                res->residual0 = 0.0;
                res->iterations = 0;
                res->converged = 1;
                res->residual = 0.0;
                return WC_OK;
            }
            /* confirm with the true residual; on drift restart from it. Float cannot compute a
               residual below ~2^-24 |(|A| |dv|)|: a solve whose goal lies under that floor (a
               stiff cloth at rest: the sums cancel a smooth dv's large terms) stops there, as
               converged as float allows, where it would restart until its cap (the flag's first
               solve: 300 iterations at ~4e-4). The floor counts up to 100x the goal: a floor
               beyond that (an iterate far too large) is no reason to stop */
            project(g, &g->sv[v.dv], &g->sv[1 - v.dv], 0);
            v.dv = 1 - v.dv;
            double fl = 0.0;
            rt = true_residual2(g, &g->sv[v.dv], &g->r[1 - v.r], &fl);
            if (sqrt(rt) <= fmax((double)s2[1], fmin(fl, 100.0 * (double)s2[1]))) {
                converged = 1;
                break;
            }
            if (s1[2] >= (float)max_it) break;
            v.r = 1 - v.r;   /* r = the true residual */
            const wg_sums d = update(g, &v, 1, g->n);
            scalars(g, o, 3, kNoSums, d, max_it);
            direction(g, &v, 1);
            rt = -1.0;
            continue;
        }
        /* queue K more iterations (never beyond what the cap can still use) */
        int left = max_it - (int)s1[2];
        int batch = K < left ? K : left;
        if (batch < 1) batch = 1;
        for (int k = 0; k < batch; ++k) pcg_iteration(g, o, &v, max_it);
        queued += batch;
        if (queued > 4 * (max_it + 1) + 100) break;   /* a GPU that never sets done: stop anyway */
    }
    if (!converged) {
        project(g, &g->sv[v.dv], &g->sv[1 - v.dv], 0);
        v.dv = 1 - v.dv;
        rt = true_residual2(g, &g->sv[v.dv], &g->r[1 - v.r], NULL);
    }
    read_scalars(g, s0, s1, s2);
    res->residual0 = (double)s2[0];
    res->scale = fmax(res->residual0, g->residual_floor);
    res->iterations = (int)s1[2];
    res->residual = sqrt(rt) / res->scale;
    res->converged = converged || res->residual <= o->tolerance;
    if (!isfinite(res->residual0)) {
        project(g, &g->sv[v.dv], &g->sv[1 - v.dv], 1);
        v.dv = 1 - v.dv;
        res->residual = 1.0;
        res->converged = 0;
        st = WC_ERROR_SOLVER_DIVERGED;
    }
    if (st == WC_OK && !isfinite(res->residual)) st = WC_ERROR_SOLVER_DIVERGED;
    *out = &g->sv[v.dv];
    return st;
}

/* PCG in one work group, with block Jacobi (pcg_group.glsl) or, with amg, the multigrid after
 * its setup passes (pcg_group_amg.glsl): one dispatch from the guess dv_in to the result in
 * sv[0], the scalars left as the chain leaves them, then one read-back of them and of the
 * group's result texel; res filled by solve_pcg's rules. */
static wc_status solve_group(wg_sim* g, const wc_solver_opts* o, const wg_tex* dv_in, int amg, const wg_tex** out,
                             wc_solve_result* res) {
    wg_runner* run = &g->run;
    const int max_it = o->max_iterations, b = 1 - g->sc_cur;
    const wg_pcg_group_in in = {.pblocks = &g->pblocks, .block = &g->block, .a_lo = &g->A0, .a_hi = &g->A1,
                                .b = &g->b, .S0 = &g->S0, .S1 = &g->S1, .z = &g->z, .dv = dv_in};
    if (amg) {
        wg_amg_setup(g->amg);
        wg_amg_group_pack(g->amg);
        wg_amg_group_use(g->amg, &in);
    } else {
        WG_USE(run, WGP_PCG_GROUP, &in);
    }
    rules_uniforms(g, o, 0, max_it);
    wg_u1i(run, "u_texels", g->q.w * g->q.h);
    wg_u1i(run, "u_guard", 4 * (max_it + 1) + 100);
    const wg_tex* const outs[] = {&g->sv[0], &g->sc[b][0], &g->sc[b][1], &g->sc[b][2], &g->grp};
    if (amg) wg_run_groups_scratch(run, g->n, 1, outs, 5, &g->amg->group.v);
    else wg_run_groups_into(run, g->n, 1, outs, 5);
    g->sc_cur = b;
    *out = &g->sv[0];
    float s0[4], s1[4], s2[4], rg[4];
    read_scalars(g, s0, s1, s2);
    wg_read1(&g->layout, &g->grp, rg);
    if (rg[2] < 0.0f) {   /* the shader's limit below the host's: a bug */
        if (!run->fault[0]) snprintf(run->fault, sizeof run->fault, "pcg_group: %d particles past its limit", g->n);
        res->residual = 1.0;
        return WC_ERROR_GPU;
    }
    if (rg[2] > 0.0f) {   /* zero right-hand side: dv = z */
        res->converged = 1;
        return WC_OK;
    }
    res->residual0 = (double)s2[0];
    res->scale = fmax(res->residual0, g->residual_floor);
    res->iterations = (int)s1[2];
    res->residual = sqrt((double)rg[0]) / res->scale;
    res->converged = rg[1] != 0.0f || res->residual <= o->tolerance;
    wc_status st = s1[1] != 0.0f ? WC_ERROR_SOLVER_DIVERGED : WC_OK;
    if (!isfinite(res->residual0)) {   /* the shader left dv = z */
        res->residual = 1.0;
        res->converged = 0;
        st = WC_ERROR_SOLVER_DIVERGED;
    }
    if (st == WC_OK && !isfinite(res->residual)) st = WC_ERROR_SOLVER_DIVERGED;
    return st;
}

/* PCG in one work group: compute passes, a cloth within the group's limit (with the multigrid:
 * its packed patterns made) and no penalty pairs in its system (the group solves have no
 * pairs_row.glsl: the chain solves those). Block Jacobi on a hardware device (a software
 * rasteriser runs one work group on one thread, where it runs a pass over all its cores: the
 * chain is faster there) or where WEFT_GPU_SOLVE=group forces it; the multigrid only where it is
 * forced, until it has run on a GPU (docs/design/gpu_passes.md) */
static int group_wanted(const wg_sim* g, int amg) {
    const wg_device* d = g->dev;
    if (!d->compute || d->solve == WG_SOLVE_PASSES || g->n > WG_GROUP_MAX_PARTICLES || wg_pairs_on(g->pairs)) return 0;
    if (amg) return d->solve == WG_SOLVE_GROUP && wg_amg_group_fits(g->amg);
    return d->solve == WG_SOLVE_GROUP || !d->software;
}

/* Chebyshev's rho: 20 CG steps of the PCG passes on P y = S g (core/solve_rho.c), their alpha and
 * beta recorded per step into g->lanczos on the GPU and read back once. */
static double estimate_rho(wg_sim* g, const wc_solver_opts* o) {
    wg_runner* run = &g->run;
    wc_solver_opts lo = *o;
    lo.tolerance = 0.0;
    lo.divergence_factor = 1e30;
    pcg_vecs v = {0, 0, 0};
    WG_USE(run, WGP_LANCZOS_START, &(wg_lanczos_start_in){.S0 = &g->S0, .S1 = &g->S1});
    WG_RUN(run, g->n, &g->r[0]);
    const wg_sums rn = sums_of(g, &g->red_p[0], &g->r[0]);   /* w: |g|^2 */
    const wg_sums dots = update(g, &v, 1, g->n);
    /* residual0 = |g|, tolerance 0: the GPU marks the steps done only when r vanishes */
    scalars(g, &lo, 0, rn, dots, 1 << 20);
    direction(g, &v, 1);
    float first[4];
    wg_read1(&g->layout, &g->sc[g->sc_cur][0], first);
    if (first[3] == 0.0f) return 0.0;   /* no free direction anywhere */
    if (!(first[0] > 0.0f) || !isfinite(first[0])) return 0.9995;
    for (int k = 0; k < 20; ++k) {
        pcg_iteration(g, &lo, &v, 1 << 20);
        WG_USE(run, WGP_COPY_TEXEL, &(wg_src_in){.src = &g->sc[g->sc_cur][0]});
        wg_run_texel(run, &g->lanczos, k);
    }
    float rec[32 * 4];
    wg_read_texels(&g->layout, &g->lanczos, 0, 20, rec);
    double alpha[20], beta[20], delta0 = first[0];
    int k = 0;
    for (; k < 20; ++k) {
        double a = rec[4 * k + 1], b = rec[4 * k + 2], d = rec[4 * k];
        if (k > 0 && memcmp(rec + 4 * k, rec + 4 * (k - 1), 4 * sizeof(float)) == 0) break;   /* not applied */
        if (!(a > 0.0) || !isfinite(a)) {
            if (k == 0) return 0.9995;
            break;
        }
        alpha[k] = a;
        beta[k] = b;
        if (!(d > 1e-28 * delta0) || !isfinite(d)) {
            ++k;
            break;
        }
    }
    return wc_rho_from_lanczos(alpha, beta, k, o->chebyshev_gamma);
}

static wc_status solve_jacobi(wg_sim* g, const wc_solver_opts* o, int chebyshev, const wg_tex** out,
                                wc_solve_result* res) {
    wg_runner* run = &g->run;
    const double gamma = chebyshev ? o->chebyshev_gamma : 1.0;
    const int delay = o->chebyshev_delay > 1 ? o->chebyshev_delay : 1;
    const int check_every = o->check_every > 0 ? o->check_every : 10;
    residual(g, &g->z, &g->rz);
    float r0[4];
    wg_read1(&g->layout, wg_reduce(run, &g->red_p[0], &g->rz, 0, 0, 0, 0), r0);
    const double res0 = sqrt((double)r0[3]);
    res->residual0 = res0;
    if (!isfinite(res0) || res0 == 0.0) {
        project(g, &g->sv[0], &g->sv[1], 1);
        *out = &g->sv[1];
        res->iterations = 0;
        res->converged = res0 == 0.0;
        res->residual = res0 == 0.0 ? 0.0 : 1.0;
        return res0 == 0.0 ? WC_OK : WC_ERROR_SOLVER_DIVERGED;
    }
    double rho = chebyshev ? (o->chebyshev_rho > 0.0 ? o->chebyshev_rho : g->rho) : 0.0;
    res->scale = fmax(res0, g->residual_floor);
    const double goal = o->tolerance * res->scale;
    double limit = o->divergence_factor * res0, rn = res0, omega = 1.0;
    int x = 0, prev = 1, nxt = 2, k = 0, converged = 0;
    wc_status st = WC_OK;
    for (;; ++k) {
        int check = (k % check_every == 0) || k >= o->max_iterations;
        if (chebyshev) omega = wc_chebyshev_omega(k, delay, rho, omega);
        WG_USE(run, WGP_JACOBI_SWEEP, &(wg_jacobi_sweep_in){.pblocks = &g->pblocks, .block = &g->block, .a_lo = &g->A0,
            .a_hi = &g->A1, .x = &g->sv[x], .b = &g->b, .S0 = &g->S0, .S1 = &g->S1, .dinv_lo = &g->D0,
            .dinv_hi = &g->D1, .x_prev = &g->sv[prev], .pairs = wg_sim_pair_in(g)});
        wg_sim_pair_uniform(g);
        wg_u1f(run, "u_gamma", gamma);
        wg_u1f(run, "u_omega", omega);
        WG_RUN(run, g->n, &g->sv[nxt]);
        if (check) {
            float v[4];
            wg_read1(&g->layout, wg_reduce(run, &g->red_p[0], &g->sv[nxt], 0, 0, 0, 0), v);
            rn = sqrt((double)v[3]);
            if (k == 0) limit = o->divergence_factor * fmax(res0, rn);
            if (!isfinite(rn) || rn > limit) {
                st = WC_ERROR_SOLVER_DIVERGED;
                break;
            }
            if (rn <= goal) {
                converged = 1;
                break;
            }
            if (k >= o->max_iterations) break;
        }
        int old_prev = prev;
        prev = x;
        x = nxt;
        nxt = old_prev;
    }
    /* sv[x] = dv_k, the iterate whose residual rn was measured */
    res->iterations = k;
    res->converged = converged;
    if (!isfinite(rn)) {
        project(g, &g->sv[x], &g->sv[nxt], 1);   /* no finite iterate kept: dv = z */
        *out = &g->sv[nxt];
        res->residual = 1.0;
        return st;
    }
    project(g, &g->sv[x], &g->sv[nxt], 0);
    *out = &g->sv[nxt];
    res->residual = rn / res->scale;
    return st;
}

void wg_solve_debug_dots(wg_sim* g, int rows, double out[3]) {
    wg_runner* run = &g->run;
    WG_USE(run, WGP_DINV, &(wg_dinv_in){.pblocks = &g->pblocks, .a_lo = &g->A0, .a_hi = &g->A1, .S0 = &g->S0,
        .S1 = &g->S1});
    WG_RUN(run, g->n, &g->D0, &g->D1);
    wc_solver_opts o;
    memset(&o, 0, sizeof o);
    o.divergence_factor = 1e30;
    const int amg = g->amg_on;
    g->amg_on = 0;
    float s0[4], s1[4], s2[4];
    /* mode 0 reads residual0 = sqrt(sum) and (delta, rr) = dots: c.q first (compute passes keep
       one set of partials at a time), then the update's pair */
    scalars(g, &o, 0, spmv_dot(g, &g->c[0], rows), kNoSums, 1);
    read_scalars(g, s0, s1, s2);
    out[0] = (double)s2[0] * (double)s2[0];
    pcg_vecs v = {0, 0, 0};
    scalars(g, &o, 0, kNoSums, update(g, &v, 1, rows), 1);
    read_scalars(g, s0, s1, s2);
    out[1] = s0[0];
    out[2] = s0[3];
    g->amg_on = amg;
}

wc_status wg_solve(wg_sim* g, const wc_solver_opts* o, wc_solver_type type, const wg_tex* dv_in,
                     const wg_tex** out, wc_solve_result* res) {
    wg_runner* run = &g->run;
    memset(res, 0, sizeof *res);
    res->solver = type;
    /* the preconditioner (block Jacobi's unless PCG has the multigrid), and the initial guess
       projected into sv[0] */
    const int amg = type == WC_SOLVER_PCG && g->amg;
    if (type == WC_SOLVER_PCG && group_wanted(g, amg)) {
        wc_status st = solve_group(g, o, dv_in, amg, out, res);
        if (amg && (st != WC_OK || !res->converged)) wg_amg_cold(g->amg);
        res->status = st;
        return st;
    }
    if (!amg) {
        WG_USE(run, WGP_DINV, &(wg_dinv_in){.pblocks = &g->pblocks, .a_lo = &g->A0, .a_hi = &g->A1, .S0 = &g->S0,
            .S1 = &g->S1});
        WG_RUN(run, g->n, &g->D0, &g->D1);
    }
    /* Chebyshev's rho first: its CG steps use every solver iterate (sv included) as scratch */
    if (type == WC_SOLVER_CHEBYSHEV && !(o->chebyshev_rho > 0.0) && !g->rho_valid) {
        g->rho = estimate_rho(g, o);
        g->rho_valid = 1;
    }
    project(g, dv_in, &g->sv[0], 0);
    wc_status st;
    if (amg) {
        wg_amg_setup(g->amg);
        g->amg_on = 1;
        st = solve_pcg(g, o, out, res);
        g->amg_on = 0;
        if (st != WC_OK || !res->converged) wg_amg_cold(g->amg);   /* the next bounds afresh */
    } else if (type == WC_SOLVER_PCG) st = solve_pcg(g, o, out, res);
    else if (type == WC_SOLVER_JACOBI || type == WC_SOLVER_CHEBYSHEV)
        st = solve_jacobi(g, o, type == WC_SOLVER_CHEBYSHEV, out, res);
    else {
        *out = &g->sv[0];
        st = WC_ERROR_UNSUPPORTED;
    }
    res->status = st;
    return st;
}
