/* The reference's convergence in time, frame by frame (docs/bench/accuracy_methods_sheet32.md
 * section 6): the N x N hanging sheet (1 m, flat at first, two corners of one edge pinned; the
 * same sheet as `weft bench accuracy`'s sheetN, built by tests/test_support.c) stepped by TR-BDF2
 * with direct solves and Newton + line search (tolerance 1e-10) at S, 2S, 4S, ... substeps per
 * frame, 30 fps. Prints, every 5th frame, the RMS particle distance between successive runs /
 * the rest bounding-box diagonal (%): where it halves ~4x per halving the runs converge at second
 * order; where it stops falling the scene amplifies differences.
 *   bench_ref_ladder [N 16] [newton 3] [S 4] [runs 4] [damping_scale 1] [air 1] [frames 60] */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "step.h"
#include "test_support.h"
#include "vec3.h"

int main(int argc, char** argv) {
    const int n = argc > 1 ? atoi(argv[1]) : 16, nw = argc > 2 ? atoi(argv[2]) : 3;
    const int s0 = argc > 3 ? atoi(argv[3]) : 4, runs = argc > 4 ? atoi(argv[4]) : 4;
    const double dscale = argc > 5 ? atof(argv[5]) : 1.0;
    const int air = argc > 6 ? atoi(argv[6]) : 1, frames = argc > 7 ? atoi(argv[7]) : 60;
    if (n < 2 || nw < 1 || s0 < 1 || runs < 2 || runs > 8 || !(dscale >= 0) || frames < 1) {
        fprintf(stderr, "usage: bench_ref_ladder [N] [newton] [S] [runs 2-8] [damping_scale] [air 0/1] [frames]\n");
        return 2;
    }
    wc_model m;
    if (!ts_sheet(&m, n, 1.0, 0.0, 0, 1.0)) return 1;
    for (int t = 0; t < WC_SPRING_TYPE_COUNT; ++t) m.material.d[t] *= dscale;
    const int np = m.n_particles;
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY}, diag = 0.0;
    for (int i = 0; i < np; ++i)
        for (int c = 0; c < 3; ++c) {
            lo[c] = fmin(lo[c], m.rest_pos[3 * i + c]);
            hi[c] = fmax(hi[c], m.rest_pos[3 * i + c]);
        }
    for (int c = 0; c < 3; ++c) diag += (hi[c] - lo[c]) * (hi[c] - lo[c]);
    diag = sqrt(diag);
    double* X[8] = {NULL};
    for (int L = 0; L < runs; ++L) {
        X[L] = malloc(sizeof(double) * 3 * (size_t)np * (size_t)frames);
        if (!X[L]) return 1;
        wc_sim_def d = wc_default_sim_def();
        d.integrator = WC_INTEGRATOR_TRBDF2;
        d.newton_iterations = nw;
        d.line_search = nw > 1;
        d.threads = 1;
        d.solver.type = WC_SOLVER_DIRECT;
        d.solver.tolerance = 1e-10;
        d.substeps = s0 << L;
        d.sleep_speed = 0.0;
        if (!air) d.air.normal_drag = d.air.tangent_drag = 0.0;
        wc_state* s = NULL;
        wc_diag dg = {0};
        if (wc_state_create(&s, &m, &d, NULL, &dg) != WC_OK) {
            fprintf(stderr, "state: %s\n", dg.message);
            return 1;
        }
        wc_pin pins[2];
        memset(pins, 0, sizeof pins);
        pins[0].particle = ts_sheet_particle(&m, n, 0, n - 1);
        pins[1].particle = ts_sheet_particle(&m, n, n - 1, n - 1);
        for (int k = 0; k < 2; ++k) v3_copy(pins[k].target, s->x + 3 * pins[k].particle);
        if (wc_state_set_pins(s, pins, 2, &dg) != WC_OK) return 1;
        int rollbacks = 0;
        for (int f = 0; f < frames; ++f) {
            wc_step_stats st;
            if (wc_step_frame(s, 1.0 / 30, &st, &dg) != WC_OK) {
                fprintf(stderr, "step: %s\n", dg.message);
                return 1;
            }
            rollbacks += st.rollbacks;
            memcpy(X[L] + 3 * (size_t)np * f, s->x, sizeof(double) * 3 * (size_t)np);
        }
        fprintf(stderr, "%d substeps per frame: done, %d rollback(s)\n", d.substeps, rollbacks);
        wc_state_destroy(s);
    }
    printf("sheet%d, TR-BDF2 Newton %d, damping x %g, air %s: RMS difference of successive runs (%% of the "
           "diagonal)\n| frame |", n, nw, dscale, air ? "on" : "off");
    for (int L = 1; L < runs; ++L) printf(" %d-%d |", s0 << (L - 1), s0 << L);
    printf("\n|---|");
    for (int L = 1; L < runs; ++L) printf("---|");
    printf("\n");
    for (int f = 4 < frames - 1 ? 4 : frames - 1; f < frames; f += 5) {
        printf("| %d |", f + 1);
        for (int L = 1; L < runs; ++L) {
            double e = 0.0;
            const double *a = X[L] + 3 * (size_t)np * f, *b = X[L - 1] + 3 * (size_t)np * f;
            for (int k = 0; k < 3 * np; ++k) e += (a[k] - b[k]) * (a[k] - b[k]);
            printf(" %.4f |", 100 * sqrt(e / np) / diag);
        }
        printf("\n");
    }
    for (int L = 0; L < runs; ++L) free(X[L]);
    wc_model_free(&m);
    return 0;
}
