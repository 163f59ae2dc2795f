/* The multigrid's eigenvalue estimates carried from one substep to the next
 * (wc_amg_opts.bound_carry, wc_solver_carry_bounds; amg.h). Checked against the paths that were
 * there before it:
 *   - a carried setup builds, bit for bit, the hierarchy a setup that holds the same estimates
 *     (hold_bounds, the Newton solves' reuse, with bound_margin 1: a carried estimate is taken as
 *     it is) builds, and not a fresh setup's;
 *   - with bound_carry K, the carried setups come K in a row between fresh ones, each fresh one
 *     bit for bit a new hierarchy's estimates; a Newton setup after a carried one holds it; an
 *     invalidation, a level whose couplings came or went, or bound_carry 0 estimates afresh;
 *   - the estimates as state (wc_amg_bounds_get / set): another solver given them builds the same
 *     carried hierarchy; bad values are refused (it estimates);
 *   - carried estimates far below the matrix's: the solve is redone on a fresh setup;
 *   - the step: a hanging sheet's 12 frames on PCG + multigrid carry as the option says, with no
 *     fallback, rollback or unconverged solve, within the solver's tolerance of bound_carry 0's. */
#include "amg_scene.h"

/* Every value a setup leaves in the hierarchy: operators, block inverses, bounds, P_tent, P. */
static size_t level_values(const wc_amg* a, double* out) {
    size_t k = 0;
#define PUT(v) \
    do {                \
        if (out) out[k] = (v); \
        ++k;            \
    } while (0)
    for (int l = 0; l < a->n_levels; ++l) {
        const wc_amg_level* L = &a->lev[l];
        for (int e = 0; e < 9 * L->n_blocks; ++e) PUT(L->val[e]);
        PUT(L->bound);
        if (l + 1 == a->n_levels) break;
        for (int e = 0; e < 9 * L->group * L->n; ++e) PUT(L->Dinv[e]);
        if (L->tent) for (int e = 0; e < 18 * L->n; ++e) PUT(L->tent[e]);
        for (int e = 0; e < 9 * L->p_start[L->n]; ++e) PUT(L->p_val[e]);
    }
#undef PUT
    return k;
}

/* the levels that estimate (not the dense coarsest) */
static int estimating(const wc_amg* a) { return a->coarse_dense ? a->n_levels - 1 : a->n_levels; }

static void setup(wc_amg* a, wc_state* s, int carry, int hold) {
    a->carry_bounds = carry;
    a->hold_bounds = hold;
    wc_amg_setup(a, s->A, &s->filter, &s->par);
    a->carry_bounds = a->hold_bounds = 0;
}

/* the next frame's system (every entry moved) */
static void next_system(wc_state* s) {
    wc_diag d = {0};
    wc_step_frame(s, 1.0 / 30.0, NULL, &d);
    wc_step_stats st = {0};
    wc_substep_prepare(s, 1.0 / 30.0, 1.0, &st);
}

static void test_carried_setups(void) {
    scene sc;
    if (!make_scene(&sc, 24, 1.0, HANG, 8)) {
        CHECK(0);
        return;
    }
    wc_state* s = sc.s;
    wc_solver *sv1 = amg_solver(&sc.m, 1e-8, NULL), *sv2 = amg_solver(&sc.m, 1e-8, NULL),
              *sv3 = amg_solver(&sc.m, 1e-8, NULL);
    if (!sv1 || !sv2 || !sv3) return;
    wc_solver_set_positions(sv1, s->x);
    wc_solver_set_positions(sv2, s->x);
    wc_solver_set_positions(sv3, s->x);
    wc_amg *a1 = sv1->amg, *a2 = sv2->amg, *a3 = sv3->amg;
    CHECK(a1->opts.bound_carry == 7 && a1->n_levels > 2); /* the default */
    size_t nv = level_values(a1, NULL);
    double *v1 = malloc(sizeof(double) * nv), *v2 = malloc(sizeof(double) * nv), *v3 = malloc(sizeof(double) * nv);
    double est[WC_AMG_MAX_LEVELS];

    /* no estimates yet: a carrying setup estimates */
    setup(a1, s, 1, 0);
    setup(a2, s, 0, 0);
    CHECK(!a1->bounds_reused && a1->carried == 0 && a1->est_valid && a1->carry_age == 0);
    for (int l = 0; l < estimating(a1); ++l) {
        est[l] = a1->lev[l].estimate;
        CHECK(est[l] > 0 && memcmp(&est[l], &a2->lev[l].estimate, sizeof est[l]) == 0);
    }

    /* the next system: carried (a1) = held (a2), bit for bit; a fresh setup (a3) differs */
    next_system(s);
    setup(a1, s, 1, 0);
    a2->opts.bound_margin = 1.0;
    setup(a2, s, 0, 1);
    a2->opts.bound_margin = a1->opts.bound_margin;
    setup(a3, s, 1, 0); /* a3 has no estimates: fresh */
    level_values(a1, v1);
    level_values(a2, v2);
    level_values(a3, v3);
    CHECK(a1->bounds_reused && a1->carried == 1 && a1->carry_age == 1 && a2->bounds_reused && !a3->bounds_reused);
    CHECK(memcmp(v1, v2, sizeof(double) * nv) == 0);
    CHECK(memcmp(v1, v3, sizeof(double) * nv) != 0);
    for (int l = 0; l < estimating(a1); ++l) {
        CHECK(a1->lev[l].bound == WC_AMG_SAFETY * est[l]); /* carried as it is */
        CHECK(a1->lev[l].estimate == est[l]); /* a carried setup keeps the fresh estimate */
    }
    a1->carry_bounds = 1;
    amg_check_spd(a1, s, "carried estimates (again)"); /* a second carried setup: SPD */
    a1->carry_bounds = 0;
    CHECK(a1->bounds_reused && a1->carry_age == 2);

    /* a Newton setup after a carried one holds it (not a fresh one) and leaves the age */
    setup(a1, s, 0, 1);
    CHECK(a1->bounds_reused && a1->carry_age == 2 && a1->lev[0].bound == WC_AMG_SAFETY * (a1->opts.bound_margin * est[0]));

    /* the period: bound_carry 2 carries twice, then estimates; a fresh estimate equals a new
       hierarchy's (a3's, fresh on the same system) bit for bit */
    a1->opts.bound_carry = 2;
    setup(a3, s, 0, 0);
    int pattern[6];
    for (int r = 0; r < 6; ++r) {
        setup(a1, s, 1, 0);
        pattern[r] = a1->bounds_reused;
        if (!pattern[r])
            for (int l = 0; l < estimating(a1); ++l)
                CHECK(memcmp(&a1->lev[l].estimate, &a3->lev[l].estimate, sizeof(double)) == 0 &&
                      a1->lev[l].bound == WC_AMG_SAFETY * a1->lev[l].estimate);
    }
    /* the age was 2 (above): estimate, carry, carry, estimate, carry, carry */
    CHECK(!pattern[0] && pattern[1] && pattern[2] && !pattern[3] && pattern[4] && pattern[5]);

    /* invalidated: estimates; bound_carry 0: never carries */
    wc_solver_invalidate_bounds(sv1);
    CHECK(!a1->est_valid);
    setup(a1, s, 1, 0);
    CHECK(!a1->bounds_reused && a1->est_valid);
    a1->opts.bound_carry = 0;
    setup(a1, s, 1, 0);
    CHECK(!a1->bounds_reused);
    a1->opts.bound_carry = 7;

    /* a level whose couplings came or went since its estimate: that level estimates, the others
       carry (the sheet has none: level 1's recorded state flipped) */
    setup(a1, s, 0, 0);
    for (int l = 0; l < estimating(a1); ++l) est[l] = a1->lev[l].estimate;
    CHECK(a1->est_terms == 0);
    a1->est_terms = 2u;
    a1->lev[1].estimate = 0.5 * est[1]; /* so that a fresh estimate shows */
    setup(a1, s, 1, 0);
    CHECK(a1->bounds_reused && a1->est_terms == 0);
    CHECK(a1->lev[0].bound == WC_AMG_SAFETY * est[0]);
    /* level 1 estimated afresh: near the fresh setup's (its operator differs in the last bits:
       level 0's carried bound smooths the prolongator) */
    CHECK(fabs(a1->lev[1].estimate / est[1] - 1.0) < 0.02 && a1->lev[1].bound == WC_AMG_SAFETY * a1->lev[1].estimate);

    /* as state: another solver given the estimates builds the same carried hierarchy */
    wc_amg_bounds b;
    wc_solver_bounds_get(sv1, &b);
    CHECK(b.valid && b.age == a1->carry_age && b.est[0] == a1->lev[0].estimate);
    wc_solver_bounds_set(sv3, &b);
    CHECK(a3->est_valid && a3->carry_age == a1->carry_age);
    next_system(s);
    setup(a1, s, 1, 0);
    setup(a3, s, 1, 0);
    level_values(a1, v1);
    level_values(a3, v3);
    CHECK(a1->bounds_reused && a3->bounds_reused && memcmp(v1, v3, sizeof(double) * nv) == 0);
    b.est[0] = NAN; /* refused: none */
    wc_solver_bounds_set(sv3, &b);
    CHECK(!a3->est_valid);
    b.est[0] = 1.0;
    b.valid = 0;
    wc_solver_bounds_set(sv3, &b);
    CHECK(!a3->est_valid);
    setup(a3, s, 1, 0);
    CHECK(!a3->bounds_reused);
    wc_solver_bounds_get(sv2, &b);
    wc_solver_invalidate_bounds(sv2);
    wc_solver_bounds_get(sv2, &b);
    CHECK(!b.valid && b.est[0] == 0.0);

    /* carried estimates far below the matrix's: the solve is redone on a fresh setup */
    for (int l = 0; l < a1->n_levels; ++l) a1->lev[l].estimate *= 0.05;
    int n3 = 3 * sc.m.n_particles;
    double* dv = calloc((size_t)n3, sizeof *dv);
    sv1->opts.max_iterations = 60;
    wc_solve_result res;
    wc_solver_carry_bounds(sv1, 1);
    long before = a1->bound_fallbacks;
    wc_status st = wc_solve(sv1, WC_SOLVER_PCG, s->A, s->b, &s->filter, dv, &s->par, &res);
    wc_solver_carry_bounds(sv1, 0);
    printf("  carried estimates x 0.05: %s, %ld redone, %d iterations in all\n",
           st == WC_OK && res.converged ? "converged" : "FAILED", a1->bound_fallbacks - before, res.iterations);
    CHECK(st == WC_OK && res.converged && a1->bound_fallbacks == before + 1 && !a1->bounds_reused);
    CHECK(a1->est_valid && a1->carry_age == 0 && a1->lev[0].estimate > 0.5 * est[0]);

    wc_amg_opts o = wc_default_amg_opts();
    o.bound_carry = -1;
    wc_amg* bad = NULL;
    wc_diag d = {0};
    CHECK(wc_amg_create(&bad, &sc.m, &o, NULL, &d) == WC_ERROR_INVALID_ARGUMENT && bad == NULL);
    CHECK(strstr(d.message, "bound_carry") != NULL);
    printf("  %zu values: carried = held bit for bit; period, invalidation, couplings' rule, state round trip\n", nv);
    free(dv);
    free(v1);
    free(v2);
    free(v3);
    wc_solver_destroy(sv1);
    wc_solver_destroy(sv2);
    wc_solver_destroy(sv3);
    free_scene(&sc);
}

/* A hanging 24 x 24 sheet, 12 frames, PCG + multigrid at tolerance tol, Newton 2 (the first
 * solve to `forcing`: core/step.c first_solve), one substep a frame; its final positions in x.
 * Returns the carried setups. */
static long run_sheet(int carry, double tol, double forcing, double* x, int* ok) {
    wc_model m;
    *ok = 0;
    if (!ts_sheet(&m, 24, 1.0, 1.0, 0, 1.0)) return -1;
    wc_sim_def def = wc_default_sim_def();
    def.solver.type = WC_SOLVER_PCG;
    def.solver.preconditioner = WC_PRECOND_AMG;
    def.solver.tolerance = tol;
    def.newton_iterations = 2;
    def.newton_forcing = forcing;
    def.threads = 1;
    def.sleep_speed = 0;
    wc_state* s = NULL;
    wc_diag d = {0};
    if (wc_state_create(&s, &m, &def, NULL, &d) != WC_OK || !s->solver->amg) {
        wc_model_free(&m);
        return -1;
    }
    wc_pin pins[2] = {{0}};
    pins[0].particle = ts_sheet_particle(&m, 24, 0, 0);
    pins[1].particle = ts_sheet_particle(&m, 24, 23, 0);
    for (int k = 0; k < 2; ++k) memcpy(pins[k].target, s->x + 3 * pins[k].particle, sizeof pins[k].target);
    CHECK(wc_state_set_pins(s, pins, 2, &d) == WC_OK);
    s->solver->amg->opts.bound_carry = carry;
    int good = 1;
    for (int f = 0; f < 12; ++f) {
        wc_step_stats st = {0};
        good &= wc_step_frame(s, 1.0 / 30.0, &st, &d) == WC_OK;
        good &= st.rollbacks == 0 && st.not_converged == 0;
    }
    long carried = s->solver->amg->carried;
    good &= s->solver->amg->bound_fallbacks == 0;
    memcpy(x, s->x, sizeof(double) * 3 * (size_t)m.n_particles);
    *ok = good;
    wc_state_destroy(s);
    wc_model_free(&m);
    return carried;
}

static double rms(const double* a, const double* b, int n3) {
    double sum = 0;
    for (int k = 0; k < n3; ++k) sum += (a[k] - b[k]) * (a[k] - b[k]);
    return sqrt(sum / (n3 / 3));
}

/* Carrying changes which iterate the loose first solves stop at (the multigrid's bounds move by
 * the margin), not how close the run is: against the same run solved tightly (tolerance 1e-7,
 * every solve to it), bound_carry 7's and 1's positions are as close as bound_carry 0's. */
static void test_step(void) {
    const int n3 = 3 * 24 * 24;
    double *x0 = malloc(sizeof(double) * n3), *x7 = malloc(sizeof(double) * n3), *x1 = malloc(sizeof(double) * n3),
           *xr = malloc(sizeof(double) * n3);
    int ok0, ok7, ok1, okr;
    const double forcing = wc_default_sim_def().newton_forcing;
    long c0 = run_sheet(0, 1e-4, forcing, x0, &ok0), c7 = run_sheet(7, 1e-4, forcing, x7, &ok7);
    long c1 = run_sheet(1, 1e-4, forcing, x1, &ok1), cr = run_sheet(0, 1e-7, 0.0, xr, &okr);
    double e0 = rms(x0, xr, n3), e7 = rms(x7, xr, n3), e1 = rms(x1, xr, n3), d7 = rms(x7, x0, n3);
    printf("  hanging sheet, 12 frames: carried setups %ld (bound_carry 0), %ld (7), %ld (1); RMS from the tight "
           "run: %.2e m (0), %.2e m (7), %.2e m (1); 7 from 0: %.1e m\n", c0, c7, c1, e0, e7, e1, d7);
    CHECK(ok0 && ok7 && ok1 && okr);
    CHECK(forcing > 1e-4);
    /* one substep a frame: 7 of every 8 first solves carry (frames 2-8, 10-12), every other one with 1 */
    CHECK(c0 == 0 && cr == 0 && c7 == 10 && c1 == 6);
    CHECK(d7 > 0 && e7 <= 1.25 * e0 && e1 <= 1.25 * e0);
    free(x0);
    free(x7);
    free(x1);
    free(xr);
}

int main(void) {
    RUN_TEST(test_carried_setups);
    RUN_TEST(test_step);
    return TEST_SUMMARY();
}
