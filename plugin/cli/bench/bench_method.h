/* The method axes of `weft bench accuracy`, `stability`, `iterations` and `peers`: PCG's
 * preconditioner, the time integrator, Newton iterations per substep, the line search and inexact
 * Newton's forcing term (--preconds, --integrators, --newton, --line-search, --newton-forcing),
 * expanded per solver and applied to a weft_cloth_def. */
#ifndef WEFT_CLI_BENCH_METHOD_H
#define WEFT_CLI_BENCH_METHOD_H
#include <stddef.h>

#include "bench_args.h"

/* How each substep is solved, beside the solver and its tolerance. */
typedef struct bench_method {
    weft_preconditioner precond;   /* PCG's (the other solvers: BLOCK_JACOBI, shown "-") */
    weft_integrator integrator;
    int newton;                 /* Newton iterations per substep (>= 1) */
    int line_search;            /* 0 / 1 */
    double forcing;             /* inexact Newton's forcing term (weft_cloth_def.newton_forcing;
                                   -1: the library's default) */
} bench_method;

/* The method axes of a command line. */
typedef struct bench_methods {
    weft_preconditioner preconds[BENCH_MAX_LIST];
    int n_preconds;
    weft_integrator integrators[BENCH_MAX_LIST];
    int n_integrators;
    int newton[BENCH_MAX_LIST];
    int n_newton;
    int line_search;            /* -1 auto (on when Newton iterations > 1), 0 off, 1 on */
    double forcing[BENCH_MAX_LIST];
    int n_forcing;
} bench_methods;

/* The usage texts' lines on the five options; `preconds` is the command's default list. */
#define BENCH_METHOD_HELP(preconds)                                                                       \
    "  --preconds LIST      PCG's preconditioners: block_jacobi, amg, ic0 or all (default " preconds ");\n" \
    "                       the other solvers have none (shown -)\n"                                     \
    "  --integrators LIST   be (backward Euler), bdf2, trbdf2 or all (default be)\n"                            \
    "  --newton LIST        Newton iterations per substep (default 1: one Baraff-Witkin step)\n"        \
    "  --line-search MODE   auto (on when Newton iterations > 1; default), on or off\n"              \
    "  --newton-forcing LIST  inexact Newton: with more than one Newton iteration, a substep's\n"     \
    "                       first solve stops at this relative residual (default: the library's,\n"  \
    "                       weft_cloth_def.newton_forcing; 0: at the tolerance, like the later ones)\n"

/* Defaults: preconds as given ("block_jacobi", "block_jacobi,amg"), be, 1 Newton iteration, auto,
 * the library's forcing term. */
void bench_methods_default(bench_methods* m, const char* preconds);
/* One of the five options at argv[*i] (bench_option_fn's contract: 1, 0 not one, -1, -2). */
int bench_methods_option(bench_methods* m, int argc, char** argv, int* i, const char** value);
/* The methods a solver runs: every preconditioner (PCG only; one entry for the others) x
 * integrator x Newton count x forcing term, in that order. Returns the count (<= cap). */
int bench_methods_expand(const bench_methods* m, weft_solver solver, bench_method* out, int cap);
/* How many methods any solver can have (the size for bench_methods_expand). */
int bench_methods_max(const bench_methods* m);
/* The method into a cloth def (preconditioner, integrator, newton_iterations, line_search,
 * newton_forcing). */
void bench_method_apply(const bench_method* b, weft_cloth_def* def);
/* 1 when the GPU backend runs the method (block Jacobi, backward Euler, one Newton iteration
 * without line search). */
int bench_method_on_gpu(const bench_method* b);
/* "amg" / "block_jacobi", or "-" when the solver is not PCG. */
const char* bench_precond_label(weft_solver solver, const bench_method* b);
/* The forcing term as written in the tables: "%g", or "default" for the library's. */
const char* bench_forcing_label(double forcing, char* buf, size_t size);
/* "amg bdf2 n3 ls" style short label: the preconditioner (PCG only), then the integrator, Newton
 * count and line search when not be, 1, off, and a forcing term other than the library's
 * ("f0.01") with more than one Newton iteration and an iterative solver; "" for another solver's
 * default method. */
const char* bench_method_short(weft_solver solver, const bench_method* b, char* buf, size_t size);
/* Preconditioner and integrator names ("...,all"). -1 on an unknown name. */
int bench_parse_preconds(const char* text, weft_preconditioner* out);
int bench_parse_integrators(const char* text, weft_integrator* out);

#endif
