/* What a frame reports (wc_step_stats): the substeps, solves and iterations it took, its retries,
 * contacts and self-collision work, its end state and its wall time per stage. Filled by the frame
 * driver (step_driver.h) and the parts it calls (the CPU substep, step.c; Newton, newton.h; the GPU
 * backend's substeps); every count is summed over the frame. */
#ifndef WEFT_CORE_STEP_STATS_H
#define WEFT_CORE_STEP_STATS_H
#include "solve.h"

typedef struct wc_step_stats {
    int substeps;               /* substeps completed (halved retries count each piece) */
    int solves;                 /* linear solves (Newton iterations and friction passes included) */
    int iterations;             /* solver iterations, summed over substeps */
    int max_iterations;         /* largest in one solve */
    double residual;            /* largest final relative residual of an accepted solve held to
                                   the tolerance (inexact Newton's first solve, held to its forcing
                                   term, newton.h, is in not_converged when it misses that) */
    int not_converged;          /* solves that stopped at the iteration cap above tolerance */
    int friction_passes;        /* extra solves because sticking contacts had to slide */
    wc_solver_type solver;      /* last solver used */
    int rollbacks;              /* failed substeps restored */
    int halvings;               /* retries with a halved step */
    int direct_fallbacks;       /* retries with the direct solver */
    int failures;               /* substeps that failed every retry (state restored) */
    int contacts;               /* particles in contact at the end of the frame */
    double max_strain;          /* largest stretch-spring strain at the end of the frame */
    double kinetic_energy;      /* J, end of frame */
    int asleep;                 /* 1: the cloth slept through this frame (nothing simulated) */
    int fell_asleep;            /* 1: it came to rest in this frame and sleeps from the next one */
    int woke;                   /* 1: it was asleep and an input change woke it; this frame was simulated */
    double precond_ms;          /* wall time building preconditioners (inside ms.solve) */
    int newton_iterations;      /* Newton steps taken after each substep's first solve (newton.h), summed */
    int backtracks;             /* line-search halvings, summed */
    int bdf2_substeps;          /* substeps taken as BDF2 (the others: backward Euler; bdf2.h) */
    int self_proximity;         /* self-collision (self_collide.h), summed over substeps: proximity impulses */
    int self_impacts;           /* ... CCD collisions found by the impulse passes */
    int self_zones;             /* ... impact zones formed */
    int self_unresolved;        /* ... pairs left colliding when the zone loop gave up (0 normally) */
    int self_zone_relaxed;      /* ... stretch-spring corrections around the zones (self_collide.h, stage 4) */
    struct { double forces, assemble, solve, collide, integrate, total, self_collide; } ms; /* wall time per stage */
    int energy_iterations;      /* Newton steps past newton_iterations by the energy guard (newton.h), summed */
    int stage1_iterations;      /* Newton steps past newton_iterations converging TR-BDF2's stage 1 (newton.h) */
    int stage1_unconverged;     /* TR-BDF2 stage 1s under that rule that ended above its tolerance */
    /* the mesh colliders' feature contacts in the solve (mesh_pairs.h), summed over substeps */
    int mesh_pairs;             /* pairs found (edge-edge and body-vertex/cloth-triangle) */
    int mesh_pairs_active;      /* pairs active in the first system */
    int mesh_pair_passes;       /* extra solves because the pairs' active set changed */
    int mesh_pair_overflow;     /* pairs past the list's capacity (dropped; logged as a warning) */
    int mesh_pair_skipped;      /* pairs whose particles lack a pattern block (dropped) */
    /* the self-contacts in the solve (self_pairs.h), summed over substeps */
    int self_pairs;             /* pairs found (vertex-triangle and edge-edge) */
    int self_pairs_active;      /* pairs active in the first system */
    int self_pair_passes;       /* extra solves because their active set changed (no Newton) */
    int self_pair_overflow;     /* pairs past the list's capacity (dropped; logged as a warning) */
    double judged_energy_end;   /* J: the total energy the energy judge took for the last substep's
                                   end state (before the collision responses' gains come off; NaN
                                   when it judged none): tests compare it with a fresh measure */
    double judged_total;        /* J: the end's total the judge compared, those gains off (NaN ...) */
    double judged_cap;          /* J: that substep's bound for Newton's energy guard (NaN ...) */
} wc_step_stats;

/* A solve's result into the frame's stats: solves, solver, iterations (summed and largest),
 * largest residual, not converged, preconditioner time. */
void wc_step_stats_add_solve(wc_step_stats* st, wc_solver_type solver, const wc_solve_result* res);

#endif
