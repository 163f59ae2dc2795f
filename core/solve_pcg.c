/* Modified preconditioned conjugate gradient of Baraff & Witkin (1998) section 5.3: CG on the
 * projected system with every search direction filtered (c = S (P^{-1} r + beta c)), so the
 * iterate stays in z + range(S). Preconditioner: the filtered block-diagonal
 * D~_i^{-1} = (S_i A_ii S_i + I - S_i)^{-1} in place of B&W's diagonal one, or the multigrid
 * V-cycle (amg.h), or the block IC(0) factor (precond_ic.h); the direct solver runs the same iterations with its factor (wcs_pcg_run).
 *
 * Stopping: ||r||_2 <= tolerance max(||S (b - A z)||_2, floor) (solve.h) with r the recursively
 * updated residual. When that test passes, the true residual S (b - A dv) is computed; if it is
 * above the tolerance (the recursion drifted) r is replaced by it and CG restarts from dv, until
 * the cap. The reported residual is always the true one of the returned dv.
 *
 * Divergence: a non-finite value, a residual above divergence_factor x max(initial residual of
 * z, of the initial guess), or c^T S A c <= 0 (P not positive definite along c) stop the
 * iteration with SOLVER_DIVERGED; dv keeps the last iterate (finite: alpha is checked before it
 * is applied).
 *
 * Threads: an iteration's steps from the last preconditioned residual's r . t to the next update
 * (r . t, the direction, the checks, the product, the filtered dot, the update) run in one parallel
 * region with barriers between them; only a preconditioner other than the block diagonal (the
 * V-cycle, the IC(0) sweeps, the direct factor) runs between the regions. Every sum is per chunk of WCS_CHUNK rows,
 * the chunks added in chunk order by every thread itself, so all threads take the same branches
 * and the bits do not depend on the thread count (docs/bench/threads.md). The couplings' product
 * runs on all threads through their row index (coupling.h: the terms' factors beside the pattern's
 * rows, then each thread adds its own chunks' rows), with the serial product's bits. */
#include <math.h>
#include "bsr_rows.h"
#include "clock.h"
#include "precond_ic.h"
#include "solve_pcg.h"
#include "vec3.h"

/* The multigrid preconditioner: t = V-cycle(r); PCG sums r . r and r . t. */
static int precond_amg(wc_solver* s, double* rr, double* delta, wc_par* par) {
    (void)rr;
    (void)delta;
    wc_amg_apply(s->amg, s->r, s->t, par);
    return 0;
}

/* The IC(0) preconditioner: t = M^{-1} r, two triangular sweeps on one thread; PCG sums r . t. */
static int precond_ic(wc_solver* s, double* rr, double* delta, wc_par* par) {
    (void)rr;
    (void)delta;
    (void)par;
    wcs_ic_apply(s->ic, s->r, s->t);
    return 0;
}

wc_status wcs_solve_pcg(wc_solver* s, const double* A, const double* b, const wc_filter* f, double* dv,
                        wc_par* par, wc_solve_result* res) {
    const int amg = s->amg && s->opts.preconditioner == WC_PRECOND_AMG;
    double t_setup = wc_now_ms();
    const int ic = s->ic && s->opts.preconditioner == WC_PRECOND_IC0;
    if (amg) wc_amg_setup(s->amg, A, f, par);
    else if (ic) wcs_ic_setup(s->ic, A, f);
    else wcs_build_precond(s, A, f, par);
    res->setup_ms += wc_now_ms() - t_setup;
    wc_status st = wcs_pcg_run(s, A, b, f, dv, par, res, amg ? precond_amg : ic ? precond_ic : NULL);
    if (amg && s->amg->bounds_reused && (st != WC_OK || !res->converged)) {
        /* the reused eigenvalue bounds may have fallen short of this matrix's (the smoother then
           amplifies the modes above them and the V-cycle can turn indefinite), or the kept coarse
           levels (hold_coarse) may serve this system poorly: a fresh setup, and
           PCG again, from the last iterate when it merely ran out of iterations, from z (the
           constraints' values, as a solve without a guess starts) when it diverged */
        int it = res->iterations, hold = s->amg->hold_bounds, hold_coarse = s->amg->hold_coarse;
        int carry = s->amg->carry_bounds;
        if (st != WC_OK) wcs_fallback(f, dv, s->n);
        ++s->amg->bound_fallbacks;
        t_setup = wc_now_ms();
        s->amg->hold_bounds = 0;
        s->amg->hold_coarse = 0;
        s->amg->carry_bounds = 0;
        wc_amg_setup(s->amg, A, f, par);
        s->amg->hold_bounds = hold;
        s->amg->hold_coarse = hold_coarse;
        s->amg->carry_bounds = carry;
        res->setup_ms += wc_now_ms() - t_setup;
        st = wcs_pcg_run(s, A, b, f, dv, par, res, precond_amg);
        res->iterations += it;
    }
    return st;
}

/* Partial-sum slots (s->partial, n_chunks each): r . r, c . S A c and r . t. A slot is written
 * again only after a barrier that every thread passes after adding it up. */
enum { SLOT_RR = 0, SLOT_CQ = 1, SLOT_DELTA = 2 };

/* What one region's threads share: the inputs (set by the master before the region) and the
 * results thread 0 hands back (every thread computes the same ones). */
typedef struct pcg_region {
    wc_solver* s;
    const double* A;
    const wc_filter* f;
    double* dv;
    int jacobi;         /* t = D~^{-1} r in the update's pass, and r . t with it */
    int need_delta;     /* t came from the preconditioner: r . t is summed first */
    int first;          /* the direction is t alone (beta 0): after a (re)start */
    double rr, delta, delta_old, limit, goal;
    int it, max_iterations;
    double delta_out;   /* r . t (delta, or the sum made here) */
    int stop;           /* a check stopped the iteration before the product (the master redoes it) */
    int bad_alpha;      /* c . S A c <= 0 or alpha not finite: no update */
} pcg_region;

/* The checks at the top of an iteration: 1 when it goes on to the product. */
static int pcg_goes_on(const pcg_region* p, double delta) {
    double rr = p->rr;
    if (!isfinite(rr) || !(delta >= 0.0) || !isfinite(delta) || sqrt(rr) > p->limit) return 0;
    if (sqrt(rr) <= p->goal) return 0;
    return p->it < p->max_iterations;
}

/* One thread's share of an iteration (inside the region): r . t when pending, c = S (t + beta c),
 * the checks, q = S A c (the couplings' terms in two passes, coupling.h), alpha = delta / (c . q),
 * the update. */
static void iteration_part(pcg_region* p) {
    wc_solver* s = p->s;
    const wc_filter* f = p->f;
    const wc_bsr_pattern* pat = &s->m->pattern;
    const int tid = wc_par_tid(), nt = wc_par_nt();
    int c0, c1, lo, hi;
    wc_par_range(s->n_chunks, tid, nt, &c0, &c1);
    double delta = p->delta;
    if (p->need_delta) {
        for (int k = c0; k < c1; ++k) {
            int a, e;
            wcs_chunk_rows(s, k, &a, &e);
            double acc = 0.0;
            for (int i = a; i < e; ++i) acc += v3_dot(s->r + 3 * i, s->t + 3 * i);
            s->partial[SLOT_DELTA * s->n_chunks + k] = acc;
        }
        WC_PAR_BARRIER();
        delta = wcs_sum(s, SLOT_DELTA);
    }
    const double beta = p->first ? 0.0 : delta / p->delta_old;
    const double* c = s->c;
    wc_par_range(s->n, tid, nt, &lo, &hi);
    wcs_pcg_direction_rows(s, f, beta, lo, hi);
    const int go = pcg_goes_on(p, delta);
    if (tid == 0) {
        p->delta_out = delta;
        p->stop = !go;
    }
    if (!go) return;
    WC_PAR_BARRIER(); /* c complete */
    wc_par_range(pat->n_rows, tid, nt, &lo, &hi);
    wc_bsr_rows(pat->row_start, pat->col, p->A, lo, hi, NULL, 1.0, c, s->q);
    const wc_coupling* cpl = s->coupling;
    const int cpl_rows = s->coupling_rows_ok, cpl_serial = !cpl_rows && cpl && cpl->n > 0;
    if (cpl_rows) { /* the couplings' pass 1: their terms' factors (coupling.h) */
        int k0, k1;
        wc_par_range(cpl->n, tid, nt, &k0, &k1);
        wc_coupling_scale_terms(cpl, s->coupling_rows, 1.0, c, k0, k1);
    }
    WC_PAR_BARRIER(); /* q's rows (and the factors) complete */
    if (cpl_serial) {
        if (tid == 0) wc_coupling_mul_offdiag_add(cpl, 1.0, c, s->q);
        WC_PAR_BARRIER();
    }
    if (cpl_rows) { /* pass 2 on this thread's chunks' rows (empty range when it has none), which
                       it filters next: no barrier between */
        const int end = c1 * WCS_CHUNK < s->n ? c1 * WCS_CHUNK : s->n;
        wc_coupling_rows_add(cpl, s->coupling_rows, s->q, c0 * WCS_CHUNK, end);
    }
    wcs_pcg_filter_dot_chunks(s, f, c, s->q, c0, c1, SLOT_CQ); /* q = S q, c . q */
    WC_PAR_BARRIER();
    const double cq = wcs_sum(s, SLOT_CQ), alpha = delta / cq;
    const int bad = !(cq > 0.0) || !isfinite(alpha);
    if (tid == 0) p->bad_alpha = bad;
    if (bad) return;
    wcs_pcg_update_chunks(s, alpha, p->dv, p->jacobi, c0, c1, SLOT_RR, SLOT_DELTA);
}

/* After an update's region: rr from its chunks, then the preconditioner (when not the block
 * diagonal's, done in the region) and delta, or delta left to the next region. */
static void after_update(pcg_region* p, wcs_pcg_precond_fn precond, wc_par* par) {
    wc_solver* s = p->s;
    p->rr = wcs_sum(s, SLOT_RR);
    p->need_delta = 0;
    if (p->jacobi) p->delta = wcs_sum(s, SLOT_DELTA);
    else if (!precond(s, &p->rr, &p->delta, par)) p->need_delta = 1;
}

/* A (re)start from the residual in s->r: t, rr, delta and a direction from t alone next. */
static void pcg_start(pcg_region* p, wcs_pcg_precond_fn precond, wc_par* par) {
    WC_PAR_REGION(par)
    {
        int c0, c1;
        wc_par_range(p->s->n_chunks, wc_par_tid(), wc_par_nt(), &c0, &c1);
        wcs_pcg_update_chunks(p->s, 0.0, p->dv, p->jacobi, c0, c1, SLOT_RR, SLOT_DELTA);
    }
    after_update(p, precond, par);
    p->first = 1;
}

wc_status wcs_pcg_run(wc_solver* s, const double* A, const double* b, const wc_filter* f, double* dv, wc_par* par,
                      wc_solve_result* res, wcs_pcg_precond_fn precond) {
    const wc_solver_opts* o = &s->opts;
    const double res0 = res->residual0, goal = o->tolerance * res->scale;
    wc_status st = WC_OK;
    int converged = 0;
    double rr_final = -1.0;
    pcg_region p = {.s = s, .A = A, .f = f, .dv = dv, .jacobi = precond == NULL, .goal = goal,
                    .max_iterations = o->max_iterations};

    p.rr = wcs_filtered_residual(s, A, b, f, dv, s->r, par);
    p.limit = o->divergence_factor * fmax(res0, sqrt(p.rr));
    pcg_start(&p, precond, par);
    for (;;) {
        WC_PAR_REGION(par) iteration_part(&p);
        double delta = p.delta_out;
        if (p.stop) { /* the checks again, on the master, to see which one */
            const double rr = p.rr;
            if (!isfinite(rr) || !(delta >= 0.0) || !isfinite(delta) || sqrt(rr) > p.limit) {
                st = WC_ERROR_SOLVER_DIVERGED;
                break;
            }
            if (sqrt(rr) <= goal) {
                /* confirm with the true residual; on drift restart from it */
                wcs_project(f, dv, par);
                double rt = wcs_filtered_residual(s, A, b, f, dv, s->q, par);
                if (sqrt(rt) <= goal) {
                    converged = 1;
                    rr_final = rt;
                    break;
                }
                if (p.it >= o->max_iterations) break;
                for (int k = 0; k < 3 * s->n; ++k) s->r[k] = s->q[k];
                pcg_start(&p, precond, par);
                continue;
            }
            break; /* the iteration cap */
        }
        if (p.bad_alpha) {
            st = WC_ERROR_SOLVER_DIVERGED;
            break;
        }
        p.delta_old = delta;
        p.delta = delta;
        after_update(&p, precond, par);
        ++p.it;
        p.first = 0;
    }
    if (!converged) {
        wcs_project(f, dv, par);
        rr_final = wcs_filtered_residual(s, A, b, f, dv, s->q, par);
    }
    res->iterations = p.it;
    res->residual = sqrt(rr_final) / res->scale;
    res->converged = converged || res->residual <= o->tolerance;
    if (st == WC_OK && !isfinite(res->residual)) st = WC_ERROR_SOLVER_DIVERGED;
    return st;
}
