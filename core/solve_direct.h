/* The direct solver (CHOLMOD, solve_direct.c): the exact reference, analysed once per model. With
 * active couplings (coupling.h) it runs PCG (solve_pcg.h) preconditioned by its factor. Private to
 * the solvers. */
#ifndef WEFT_CORE_SOLVE_DIRECT_H
#define WEFT_CORE_SOLVE_DIRECT_H
#include "solve_kernels.h"

/* The symbolic analysis and the factor's storage, into s->direct. */
wc_status wcs_direct_create(wc_solver* s, wc_diag* diag);
void wcs_direct_destroy(wc_solver* s);
/* On entry dv is the projected initial guess and s->r holds S (b - A z) (solver.c's start of a
 * solve). */
wc_status wcs_solve_direct(wc_solver* s, const double* A, const double* b, const wc_filter* f, double* dv,
                           wc_par* par, wc_solve_result* res);

#endif
