/* The float setup's indices built with each level's pattern (core/amg_build.c, amg_setup_f.c) on
 * a real hierarchy (a hanging 48^2 sheet after 10 frames, a drape on a sphere):
 *   - mirror: every block (I, J) of a pair level points to the slot holding (J, I), found here by
 *     a linear scan of row J, and the mirror of the mirror is the block itself;
 *   - tent_f: after each setup (P_tent about the current positions) every entry is the float
 *     rounding of P_tent's double. */
#include "amg.h"
#include "amg_scene.h"

static void check_hierarchy(int kind, const char* what) {
    scene sc;
    if (!make_scene(&sc, 48, 1.0, kind, kind == DRAPE ? 12 : 10)) {
        CHECK(0);
        return;
    }
    wc_state* s = sc.s;
    wc_solver* sv = amg_solver(&sc.m, 1e-4, NULL);
    if (!sv) return;
    wc_solver_set_positions(sv, s->x);
    wc_amg* a = sv->amg;
    wc_amg_setup(a, s->A, &s->filter, &s->par);
    int levels = 0, tent_levels = 0;
    long blocks = 0, wrong = 0, tent_wrong = 0;
    for (int l = 0; l < a->n_levels; ++l) {
        const wc_amg_level* L = &a->lev[l];
        if (L->group == 2 && a->opts.single && a->opts.single_setup) {
            CHECK(L->mirror != NULL);
            if (!L->mirror) continue;
            ++levels;
            for (int I = 0; I < L->n; ++I)
                for (int k = L->row_start[I]; k < L->row_start[I + 1]; ++k) {
                    const int J = L->col[k];
                    int t = -1;
                    for (int u = L->row_start[J]; u < L->row_start[J + 1]; ++u)
                        if (L->col[u] == I) t = u;
                    ++blocks;
                    wrong += t < 0 || L->mirror[k] != t || L->mirror[L->mirror[k]] != k;
                }
        }
        if (L->tent_f) {
            ++tent_levels;
            for (long e = 0; e < 18L * L->n; ++e) tent_wrong += L->tent_f[e] != (float)L->tent[e];
        }
    }
    printf("  %-18s %d pair levels, %ld blocks, %ld wrong mirrors; %d float P_tent levels, %ld wrong entries\n", what,
           levels, blocks, wrong, tent_levels, tent_wrong);
    CHECK(levels >= 1 && blocks > 0 && wrong == 0);
    CHECK(tent_levels >= 1 && tent_wrong == 0);
    wc_solver_destroy(sv);
    free_scene(&sc);
}

static void test_mirror_and_tent(void) {
    check_hierarchy(HANG, "hanging sheet 48^2");
    check_hierarchy(DRAPE, "drape 48^2");
}

int main(void) {
    RUN_TEST(test_mirror_and_tent);
    return TEST_SUMMARY();
}
