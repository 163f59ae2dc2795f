/* The coupled system of the multigrid's self-contact tests (test_amg_cross.c, test_amg_merge.c):
 * two n x n layers, the top one falling onto the bottom one, the substep's couplings found by the
 * self-contact pairs, two pins and a row on a plane contact in the bottom layer; its hierarchy;
 * the merged operators' layout check. */
#ifndef WEFT_TESTS_AMG_COUPLED_H
#define WEFT_TESTS_AMG_COUPLED_H
#include <string.h>
#include "amg.h"
#include "check.h"
#include "self_pairs.h"
#include "step.h"
#include "two_layers.h"

static const double AMG_COUPLED_GAP = 0.004, AMG_COUPLED_TH = 0.003;

/* Two pins and a row on a plane y = 0 (normal +y) in the bottom layer of two n x n layers (host
 * vertices 0 .. n^2 - 1). */
static inline void amg_coupled_constrain(const wc_model* m, int n, wc_filter* f) {
    for (int hv = 0; hv < n; ++hv) {
        int p = m->host_to_particle[n * (n / 2) + hv];
        double* S = f->S + 9 * p;
        for (int q = 0; q < 9; ++q) S[q] = q % 4 == 0 ? 1.0 : 0.0;
        S[4] = 0.0;
        f->ndof[p] = 1;
    }
    for (int c = 0; c < 2; ++c) {
        int p = m->host_to_particle[c ? n * n - 1 : 0];
        memset(f->S + 9 * p, 0, 9 * sizeof(double));
        f->ndof[p] = 3;
    }
}

/* The substep's system of the falling layer (two n x n layers of `size` metres), with
 * constraints on the bottom layer. */
static inline wc_state* amg_coupled_layers(wc_model* m, int n, double size) {
    CHECK(two_layers(m, n, size, 0.0, AMG_COUPLED_GAP));
    wc_sim_def def = wc_default_sim_def();
    def.self_collision = 1;
    def.self_thickness = AMG_COUPLED_TH;
    def.self_in_solve = 1;
    def.sleep_speed = 0;
    def.solver.preconditioner = WC_PRECOND_AMG;
    def.solver.tolerance = 1e-8;
    def.solver.max_iterations = 2000;
    wc_state* s = two_layers_approaching(m, n, size, 0.3, &def);
    CHECK(s != NULL);
    if (!s) return NULL;
    wc_step_stats st;
    memset(&st, 0, sizeof st);
    wc_substep_prepare(s, 1.0 / 60, 1.0, &st);
    amg_coupled_constrain(m, n, &s->filter);
    return s;
}

/* A hierarchy of s's model with the couplings, set up on s's system; dense_dofs: the largest
 * level holding them as a dense matrix (0: term lists on every level). */
static inline wc_amg* amg_coupled_hierarchy(wc_state* s, int dense_dofs, wc_par* par) {
    wc_amg_opts o = wc_default_amg_opts();
    o.cross_dense_dofs = dense_dofs;
    wc_amg* a = NULL;
    wc_diag d = {0};
    CHECK(wc_amg_create(&a, s->model, &o, NULL, &d) == WC_OK);
    if (!a) return NULL;
    CHECK(wc_amg_set_coupling(a, &s->self_pairs->coupling, s->self_pairs->list.cap, &d) == WC_OK);
    a->pos = s->x; /* the solver's rotations: about the current positions */
    wc_amg_setup(a, s->A, &s->filter, par);
    return a;
}

/* Level L's merged operator (amg_merge.c) in rows: its columns strictly ascending and exactly the
 * union of B's row and the terms' nodes holding i; returns the mismatches (seen: L->n ints, -1). */
static inline int amg_merged_layout_errors(const wc_amg_level* L, int* seen) {
    const wc_amg_cross* X = L->cross;
    int bad = 0;
    for (int i = 0; i < L->n; ++i) {
        int want = 0;
        for (int k = L->row_start[i]; k < L->row_start[i + 1]; ++k)
            if (seen[L->col[k]] != i) {
                seen[L->col[k]] = i;
                ++want;
            }
        for (int q = 0; q < X->n_terms; ++q) {
            int holds = 0;
            for (int e = X->start[q]; e < X->start[q + 1]; ++e) holds |= X->node[e] == i;
            for (int e = X->start[q]; holds && e < X->start[q + 1]; ++e)
                if (seen[X->node[e]] != i) {
                    seen[X->node[e]] = i;
                    ++want;
                }
        }
        bad += X->m_start[i + 1] - X->m_start[i] != want;
        for (int b = X->m_start[i]; b < X->m_start[i + 1]; ++b) {
            bad += seen[X->m_col[b]] != i;
            bad += b > X->m_start[i] && X->m_col[b - 1] >= X->m_col[b];
        }
    }
    return bad;
}
#endif
