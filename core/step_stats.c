/* A frame's statistics (step_stats.h). */
#include "step_stats.h"

void wc_step_stats_add_solve(wc_step_stats* st, wc_solver_type solver, const wc_solve_result* res) {
    st->solver = solver;
    ++st->solves;
    st->precond_ms += res->setup_ms;
    st->iterations += res->iterations;
    if (res->iterations > st->max_iterations) st->max_iterations = res->iterations;
    if (res->residual > st->residual) st->residual = res->residual;
    if (!res->converged) ++st->not_converged;
}
