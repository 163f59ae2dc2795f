/* Helpers of the GPU solve tests (test_gpu_group.c, test_gpu_group_amg.c, test_gpu_amg_smooth.c,
 * test_gpu_amg_cross.c): a hanging sheet's
 * float system set on a GPU cloth, and a solve forced to the one-group form or to the chain. */
#ifndef WEFT_TESTS_GPU_GROUP_SUPPORT_H
#define WEFT_TESTS_GPU_GROUP_SUPPORT_H
#include "state.h"
#include "wg_sim_impl.h"

/* A GPU cloth of dev for state s holding s's next substep's system (prepared on the CPU, set on
 * the GPU rounded to float); with planes, every 7th free particle first held to a plane moving at
 * 0.05 m/s along its normal (a filter with ndof 1 and z != 0). NULL (a message printed) where
 * the cloth fails. */
wg_sim* tg_gpu_system(wg_device* dev, wc_state* s, int planes);
/* A hanging n x n sheet (springs k_scale x the default) pinned at its two top corners, PCG with
 * preconditioner pc, stepped `warm` frames on the CPU, its system with planes on *g
 * (tg_gpu_system). NULL where the state fails; *g NULL where the cloth does. */
wc_state* tg_sheet_system(wg_device* dev, wc_model* m, int n, int warm, double k_scale, wc_precond_type pc,
                          wg_sim** g);

typedef struct tg_solved {
    wc_status st;
    wc_solve_result res;
    double* dv;         /* the caller frees */
    long long passes;
    float grp[4];       /* the group's result texel (pcg_group_solve.glsl image 4) */
} tg_solved;

/* g's system solved from guess (NULL: zeros) with options o, forced to mode (dev->solve, reset
 * to AUTO after) */
tg_solved tg_solve_as(wg_device* dev, wg_sim* g, const wc_solver_opts* o, const double* guess, wg_solve_mode mode);

/* WEFT_GPU_SOLVE=group (dev's choice) on a PCG cloth with preconditioner pc past the group's
 * limit: refused at creation with a message naming the limit, the state untouched; =passes
 * takes it. */
void tg_limit_refused(wg_device* dev, wc_precond_type pc);

/* A test's comparison of the group with the chain on g's system from guess (NULL: zeros): the
 * group's run, which the caller frees */
typedef tg_solved (*tg_compare_fn)(const char* what, wg_sim* g, const wc_solver_opts* o, const double* guess,
                                   double rel_dv, double rel_res);
/* On s's system set on g, options o at tolerance 1e-4: a zero right-hand side (b = 0, z = 0) from
 * a nonzero guess gives dv = z = 0, converged, no iteration (compare runs it); a non-finite b
 * gives diverged in both forms, the same residual and dv = z. g keeps the last system. */
void tg_zero_and_bad_b(wg_device* dev, wc_state* s, wg_sim* g, wc_solver_opts o, tg_compare_fn compare);

/* One V-cycle of g's multigrid, as set up, on r (n x 3, rounded to float on the way up) into z. */
void tg_vcycle(wg_sim* g, const double* r, double* z);

#endif
