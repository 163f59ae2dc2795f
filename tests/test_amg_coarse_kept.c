/* The multigrid's kept coarse levels (wc_amg.hold_coarse, wc_solver_hold_coarse): what a
 * substep's friction passes use. A sheet draped on a sphere: system 1 holds every contact stuck
 * (pinned in the filter), system 2 lets them all slide (S = I - n n^T, kinetic damping added to
 * their diagonal blocks): the worst friction pass, where every contact changes. After a full
 * setup on system 1, a setup on system 2 under hold_coarse
 *   - keeps every coarse level's operator, P_tent and prolongator bit for bit;
 *   - gives the finest level's operator and block inverse bit for bit as a fresh hierarchy does,
 *     its bound from the last fresh estimate x bound_margin;
 *   - is a symmetric positive definite V-cycle, and PCG on it reaches CHOLMOD's answer;
 * a kept hierarchy that fails (estimates far too low) is redone fresh; without a full setup
 * before, hold_coarse does a full one. */
#include "amg_scene.h"

/* Every value the coarse levels and the prolongators hold (kept by hold_coarse). */
static size_t coarse_values(const wc_amg* a, double* out) {
    size_t k = 0;
    for (int l = 0; l < a->n_levels; ++l) {
        const wc_amg_level* L = &a->lev[l];
        if (l > 0) {
            for (int e = 0; e < 9 * L->n_blocks; ++e) { if (out) out[k] = L->val[e]; ++k; }
            for (int e = 0; e < 9 * L->group * L->n; ++e) { if (out) out[k] = L->Dinv[e]; ++k; }
            if (out) out[k] = L->bound;
            ++k;
        }
        if (l + 1 == a->n_levels) break;
        if (L->tent) for (int e = 0; e < 18 * L->n; ++e) { if (out) out[k] = L->tent[e]; ++k; }
        for (int e = 0; e < 9 * L->p_start[L->n]; ++e) { if (out) out[k] = L->p_val[e]; ++k; }
    }
    return k;
}

static int solve(wc_solver* sv, wc_state* s, const double* A, const wc_filter* f, wc_solver_type type,
                 double* dv) {
    wc_solve_result res;
    memset(dv, 0, sizeof(double) * 3 * (size_t)s->model->n_particles);
    wc_status st = wc_solve(sv, type, A, s->b, f, dv, &s->par, &res);
    CHECK(st == WC_OK && res.converged);
    return res.iterations;
}

static void test_kept_coarse(void) {
    scene sc;
    if (!make_scene(&sc, 24, 1.0, DRAPE, 12)) {
        CHECK(0);
        return;
    }
    wc_state* s = sc.s;
    const wc_model* m = &sc.m;
    int n = m->n_particles, n3 = 3 * n;
    /* the two systems: contacts stuck (f1, A) and sliding (f2, A2) */
    wc_filter f1 = s->filter, f2 = s->filter;
    f1.S = malloc(sizeof(double) * 9 * (size_t)n);
    f1.ndof = malloc((size_t)n);
    f2.S = malloc(sizeof(double) * 9 * (size_t)n);
    f2.ndof = malloc((size_t)n);
    memcpy(f1.S, s->filter.S, sizeof(double) * 9 * (size_t)n);
    memcpy(f2.S, s->filter.S, sizeof(double) * 9 * (size_t)n);
    memcpy(f1.ndof, s->filter.ndof, (size_t)n);
    memcpy(f2.ndof, s->filter.ndof, (size_t)n);
    size_t nA = 9 * (size_t)m->pattern.n_blocks;
    double* A2 = malloc(sizeof(double) * nA);
    memcpy(A2, s->A, sizeof(double) * nA);
    int contacts = 0;
    for (int i = 0; i < n; ++i) {
        if (s->filter.ndof[i] == 0) continue;
        ++contacts;
        double nrm[3] = {s->x[3 * i], s->x[3 * i + 1] - 0.65, s->x[3 * i + 2]};
        double len = sqrt(nrm[0] * nrm[0] + nrm[1] * nrm[1] + nrm[2] * nrm[2]);
        for (int c = 0; c < 3; ++c) nrm[c] /= len;
        double* S1 = f1.S + 9 * i;
        double* S2 = f2.S + 9 * i;
        double* Aii = A2 + 9 * (size_t)m->pattern.diag[i];
        double damp = 0.3 * (Aii[0] + Aii[4] + Aii[8]) / 3.0;
        for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 3; ++c) {
                S1[3 * r + c] = 0.0;
                S2[3 * r + c] = (r == c ? 1.0 : 0.0) - nrm[r] * nrm[c];
                Aii[3 * r + c] += damp * S2[3 * r + c];
            }
        f1.ndof[i] = 3;
        f2.ndof[i] = 1;
    }
    CHECK(contacts >= 10);

    wc_solver *sv = amg_solver(m, 1e-8, NULL), *fresh = amg_solver(m, 1e-8, NULL);
    if (!sv || !fresh) return;
    wc_solver_set_positions(sv, s->x);
    wc_solver_set_positions(fresh, s->x);
    wc_amg *a = sv->amg, *b = fresh->amg;
    CHECK(a->n_levels > 2);
    double *ref = calloc(n3, sizeof *ref), *dv = calloc(n3, sizeof *dv);
    solve(sv, s, A2, &f2, WC_SOLVER_DIRECT, ref);
    int it_fresh = solve(fresh, s, A2, &f2, WC_SOLVER_PCG, dv); /* system 2, fresh: the yardstick */
    CHECK(ts_rel_diff(dv, ref, n3) < 1e-6);

    wc_solver_hold_coarse(sv, 1); /* no full setup yet: the first is full */
    solve(sv, s, s->A, &f1, WC_SOLVER_PCG, dv);
    CHECK(!a->coarse_kept && a->coarse_keeps == 0);
    size_t nv = coarse_values(a, NULL);
    double *v1 = malloc(sizeof(double) * nv), *v2 = malloc(sizeof(double) * nv);
    coarse_values(a, v1);
    double estimate = a->lev[0].estimate;

    int it_kept = solve(sv, s, A2, &f2, WC_SOLVER_PCG, dv); /* system 2 on system 1's coarse levels */
    CHECK(a->coarse_kept && a->coarse_keeps == 1 && a->bound_fallbacks == 0);
    coarse_values(a, v2);
    CHECK(memcmp(v1, v2, sizeof(double) * nv) == 0);
    const wc_amg_level *L = &a->lev[0], *F = &b->lev[0];
    CHECK(memcmp(L->val, F->val, sizeof(double) * 9 * (size_t)L->n_blocks) == 0);
    CHECK(memcmp(L->Dinv, F->Dinv, sizeof(double) * 9 * (size_t)L->group * L->n) == 0);
    CHECK(L->estimate == estimate);
    CHECK(fabs(L->bound - WC_AMG_SAFETY * a->opts.bound_margin * estimate) <= 1e-12 * L->bound);
    double e_ref = ts_rel_diff(dv, ref, n3);
    printf("  %d contacts stuck -> sliding: iterations to 1e-8 fresh %d, kept coarse levels %d; "
           "vs CHOLMOD %.1e\n", contacts, it_fresh, it_kept, e_ref);
    CHECK(e_ref < 1e-6);
    CHECK(it_kept <= 2 * it_fresh + 2);
    wc_filter own = s->filter;
    s->filter = f2; /* amg_check_spd sets up on s->A and s->filter: still kept */
    memcpy(s->A, A2, sizeof(double) * nA);
    amg_check_spd(a, s, "kept coarse levels");
    CHECK(a->coarse_kept);

    /* estimates far below the matrix's: the kept hierarchy fails, the solve is redone fresh */
    a->lev[0].estimate *= 0.05;
    sv->opts.max_iterations = 60;
    wc_solve_result res;
    memset(dv, 0, sizeof(double) * (size_t)n3);
    wc_status st = wc_solve(sv, WC_SOLVER_PCG, s->A, s->b, &s->filter, dv, &s->par, &res);
    printf("  fine estimate x 0.05: %s, %ld redone, %d iterations in all, vs CHOLMOD %.1e\n",
           st == WC_OK && res.converged ? "converged" : "FAILED", a->bound_fallbacks, res.iterations,
           ts_rel_diff(dv, ref, n3));
    CHECK(st == WC_OK && res.converged && a->bound_fallbacks == 1 && !a->coarse_kept);
    CHECK(ts_rel_diff(dv, ref, n3) < 1e-6);
    CHECK(a->hold_coarse); /* the caller's setting survives the fallback */
    wc_solver_hold_coarse(sv, 0);
    solve(sv, s, s->A, &s->filter, WC_SOLVER_PCG, dv);
    CHECK(!a->coarse_kept);

    s->filter = own;
    free(v1);
    free(v2);
    free(ref);
    free(dv);
    free(A2);
    free(f1.S);
    free(f1.ndof);
    free(f2.S);
    free(f2.ndof);
    wc_solver_destroy(sv);
    wc_solver_destroy(fresh);
    free_scene(&sc);
}

int main(void) {
    RUN_TEST(test_kept_coarse);
    return TEST_SUMMARY();
}
