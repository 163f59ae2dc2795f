/* Mutable simulation state of one model: positions, velocities, the settings that may change
 * between frames (gravity, air, pins, colliders), and every scratch array a step needs, all
 * allocated at creation (a step allocates nothing). The model is borrowed and must outlive the
 * state.
 *
 * Sleeping. A cloth whose fastest particle stays slower than def.sleep_speed for def.sleep_time
 * seconds of simulated time (the rest timer, counted at the end of each frame) falls asleep: its
 * velocities are set to zero and, while it sleeps, wc_step_frame only advances time and frame
 * (positions stay bit-identical, nothing is solved; step.h). It wakes, and that same frame is
 * simulated normally, when an input changes:
 *   - wc_state_set_pins with another count, particle, target or axis;
 *   - wc_state_set_colliders with another count or any other field (velocity included);
 *   - def.gravity or def.air (wind, drags) different from the previous frame's (wc_step_frame
 *     compares them, so a caller may write them directly);
 *   - wc_state_set_positions, wc_state_set_sleep(s, 0, ...), or wc_state_wake (a caller that
 *     changes anything else the cloth must feel: x or v written directly, other def fields).
 * Every wake also restarts the rest timer, asleep or not. sleep_speed 0 disables sleeping.
 *
 * BDF2's history (x_prev, v_prev; bdf2.h) is moved on by every substep of a BDF2 cloth and
 * invalidated by wc_state_set_positions and by falling asleep; a caller that writes x or v
 * directly (teleport, reset) sets hist_valid = 0 or transforms the history the same way. */
#ifndef WEFT_CORE_STATE_H
#define WEFT_CORE_STATE_H
#include "collide.h"
#include "energy_memo.h"
#include "forces.h"
#include "mesh_collider.h"
#include "solve.h"

/* Time integrator of a substep. */
typedef enum wc_integrator {
    WC_INTEGRATOR_BE = 0,       /* backward Euler (Baraff & Witkin 1998) */
    WC_INTEGRATOR_BDF2 = 1,     /* second-order backward differentiation (Choi & Ko 2002) */
    WC_INTEGRATOR_TRBDF2 = 2,   /* TR-BDF2 (Bank et al. 1985): a trapezoidal stage, then BDF2 (bdf2.h) */
    WC_INTEGRATOR_COUNT = 3
} wc_integrator;

const char* wc_integrator_name(wc_integrator t);       /* "be", "bdf2", "trbdf2" */
int wc_integrator_from_name(const char* name);         /* -1 when unknown */

typedef struct wc_sim_def {
    double gravity[3];          /* m/s^2 (0, -9.81, 0): Y is up */
    wc_air air;                 /* wind 0, normal_drag 0.5, tangent_drag 0.02 */
    wc_solver_opts solver;
    wc_integrator integrator;   /* BE */
    int newton_iterations;      /* linearised solves per substep (1: one Baraff-Witkin step) */
    int line_search;            /* 1: backtracking line search on the incremental potential */
    double newton_forcing;      /* inexact Newton (newton.h "Inexact"), in [0, 1): with more than
                                   one Newton iteration, the substep's first system is solved to
                                   this relative residual (when above the solver's tolerance; never
                                   past tolerance x the floor); 0: to the tolerance. Default
                                   1e-2 */
    double newton_tolerance;    /* Newton's stop (newton.c "Stops early"), in [0, 1): a substep
                                   stops iterating once |S grad Phi| is at most this x the first
                                   system's residual; 0 (default): at the solver's tolerance. The
                                   energy guard's extra iterations keep the solver's tolerance */
    double stage1_tolerance;    /* TR-BDF2's stage 1 (newton.c "Stage 1"), in [0, 1): with more than one
                                   Newton iteration and no contact, it iterates on past
                                   newton_iterations until |S grad Phi| is at most this x the first
                                   system's residual; 0: off. Internal (no ABI field). Default 2e-2 */
    int substeps;               /* substeps per frame when substep_dt is 0 (1) */
    double substep_dt;          /* s; > 0: fixed substep length with an accumulator instead */
    wc_compression compression; /* DROP */
    double strain_limit;        /* 0 off; 0.1 caps stretch springs at 110% of rest length */
    int strain_passes;          /* 4 */
    int max_pins;               /* capacity for pins, fixed at creation (0: as many as particles) */
    int max_colliders;          /* capacity for colliders (16) */
    int max_halvings;           /* a failed substep is retried with h/2 up to this many times (3) */
    int direct_fallback;        /* then with the direct solver (1; analysed at creation) */
    double fail_strain;         /* a substep that stretches a spring beyond this fails (1.0) */
    double fail_energy_growth;  /* ... or multiplies kinetic energy by more than this (1e3) */
    double fail_energy_gain;    /* ... or, in a substep with no energy source (pins and colliders
                                   still, no wind), raises the total energy (kinetic + springs +
                                   gravity) by more than this x (M |g| D + its kinetic and spring
                                   energy at the start), M the mass, D the bounding-box diagonal:
                                   backward Euler only dissipates, a gain is the linearisation
                                   failing (0.01; 0: not judged). Not charged: what the
                                   colliders' position corrections and the self-collision stage
                                   put in (collision responses: work done on the cloth, step.c) */
    int threads;                /* OpenMP threads, 0 = OpenMP's default */
    double sleep_speed;         /* m/s (1e-3): the cloth falls asleep when its fastest particle stays
                                   slower than this for sleep_time; 0 never sleeps */
    double sleep_time;          /* s of simulated time (0.5) */
    /* self-collision (self_collide.h) */
    int self_collision;         /* 1: on; 0: off (the core's default; the plugin resolves its own) */
    double self_thickness;      /* m, finite and > 0 (0.003) */
    int self_in_solve;          /* 1 (default): with self-collision on, its close pairs are also
                                   penalty terms of the implicit solve (self_pairs.h); 0: only the
                                   stage after the solve */
} wc_sim_def;

wc_sim_def wc_default_sim_def(void);

/* A pinned particle (3 DOF), or with a unit free_axis a particle that may slide along that line
 * through its target (2 DOF). Targets move: the step interpolates from the previous frame's
 * target to this frame's. */
typedef struct wc_pin {
    int particle;
    double target[3];           /* m, world, at the end of the next frame */
    double free_axis[3];        /* zero: fully pinned; unit vector: line constraint */
} wc_pin;

typedef struct wc_state {
    const wc_model* model;
    wc_sim_def def;
    wc_allocator alloc;
    wc_par par;
    double time;                /* s, simulated */
    double seam_scale;          /* host seam pairs' rest-length ramp over the current frame (sew.h),
                                   derived from time: wc_seam_scale(model, time at the frame's end) */
    int seam_ramping;           /* 1 while that ramp shortens host seams in this frame (an energy
                                   source: the energy gain is not judged), derived from time */
    double accumulator;         /* s, fixed-substep mode: time not yet simulated */
    long long frame;            /* frames stepped */

    double total_mass;          /* kg, sum of the model's particle masses */
    double* x;                  /* (n x 3) positions (m) */
    double* v;                  /* (n x 3) velocities (m/s) */

    /* sleeping (see the top of the file) */
    int asleep;                 /* 1: wc_step_frame skips the simulation */
    int woke;                   /* 1: woken since the last frame (reported by the next step) */
    double rest_time;           /* s: simulated time the fastest particle has been below sleep_speed */
    double sleep_strain;        /* max stretch strain of the sleeping positions (stats) */
    double input_gravity[3];    /* def.gravity and def.air of the last frame: a change wakes */
    wc_air input_air;

    int judge_fresh;            /* tests: 1 = the energy judge measures every state afresh instead
                                   of taking an earlier measure of the same state (step.c,
                                   energy_memo.h), and the line search's first potential sums its
                                   springs afresh instead of taking prepare's energies (newton.c) */

    int n_pins;
    wc_pin* pins;               /* (max_pins) */
    double* pin_from;           /* (max_pins x 3) target at the start of the frame */
    int* pin_scratch;           /* (n) -1 between calls: set_pins' per-particle lookup */
    int n_colliders;
    wc_collider* colliders;     /* (max_colliders) */
    wc_contacts contacts;
    wc_contacts contacts_save;  /* contacts at the start of the substep (rollback) */

    /* scratch, all (n x 3) unless noted */
    double *x0, *v0, *dv0;      /* start of the substep (rollback) */
    double *f_ext, *f, *b, *r;
    double* dv;                 /* last velocity change: the next solve's initial guess */
    double* tri_scratch;        /* (n_tris x 3) */
    double* spring_scratch;     /* (n_springs x 3) */
    double* A;                  /* (pattern.n_blocks x 9) */
    wc_spring_eval* se;         /* (n_springs) */
    wc_filter filter;
    wc_solver* solver;

    /* BDF2 history (bdf2.h): the previous substep's start x_{n-1} (after its contact correction)
       and v_{n-1}; valid for a next substep of the same length hist_h. A TR-BDF2 cloth keeps its
       substep's start x_n, v_n here between its two stages (scratch: hist_valid stays 0) */
    int hist_valid;
    double hist_h;              /* s */
    double *x_prev, *v_prev;    /* (n x 3) */
    int hist_valid0;            /* the history at the start of the substep (rollback) */
    double hist_h0;
    double *x_prev0, *v_prev0;  /* (n x 3) */
    /* integrator scratch of a substep (bdf2.h), (n x 3) each */
    double *xb, *xs, *vstar, *mom;
    double* stage1_impulse;     /* TR-BDF2: stage 1's contact impulses, added to stage 2's in the
                                   release test (wc_integ_contact_impulses) */
    /* Newton scratch (newton.h), (n x 3) each unless noted */
    double *nw_w, *nw_d, *nw_x, *nw_v, *nw_zero, *nw_g, *nw_fb;
    double* nw_wh;              /* TR-BDF2's stage 1: the iterate converged with the first held directions */
    double* nw_fa;              /* (n x 9) friction's diagonal blocks */
    double* air_lump;           /* (n x 9) TR-BDF2's implicit air drag blocks (wc_air_lumped, bdf2.h) */
    double* nw_kv0;             /* (n_springs x 9) damping blocks frozen at the substep's start */
    double* nw_partial;         /* (ceil(max(n, n_springs) / 256)) per-chunk sums */
    wc_energy_memo energy_memo; /* the energy judge's last measure and its state (energy_memo.h) */
    /* the springs' energies at the substep's start, from prepare's force evaluation (step.c), and
       the positions they were evaluated at: the line search's first potential takes them where
       its iterate is there (newton.c, "Line search"); valid until Newton's first potential */
    double* nw_spring_e;        /* (n_springs) */
    double* nw_spring_e_x;      /* (n x 3) */
    double nw_spring_e_seam;    /* the seam scale they were evaluated with */
    int nw_spring_e_valid;
    long nw_spring_e_used;      /* potentials that took them (tests) */
    /* for tests: called with every accepted Newton iterate when line_search is on (NULL: none);
       w (n x 3) the velocity change, phi the incremental potential (newton.h) */
    void (*newton_trace)(void* user, const struct wc_state* s, int iterate, double phi, const double* w);
    void* newton_trace_user;

    /* triangle-mesh colliders (mesh_collider.h), borrowed, attached once after creation
       (wc_state_attach_mesh_colliders); their positions move from frame to frame as the host
       sets them. The substep's collider list (step.c) puts them first: contact indices
       0 .. n_mesh - 1 are the meshes, n_mesh + k the analytic collider k. */
    int n_mesh;
    wc_mesh_collider* const* mesh;   /* (n_mesh) */
    wc_collider* all_colliders;      /* (max_colliders + n_mesh) the substep's list */
    const wc_collider* all;          /* the list of the current substep (all_colliders or colliders) */
    int n_all;
    double* x_sub;                   /* (n x 3) positions at the substep's start after the contacts'
                                        correction (m): the crossing test of the projection */
    double sub_alpha0;               /* frame fraction at the start of the current substep */
    /* self-collision scratch (self_collide.h), NULL when def.self_collision is 0; all derived:
       its start positions are copied at the top of every substep */
    struct wc_self* self;
    /* the mesh colliders' feature contacts of the current substep (mesh_pairs.h), allocated by
       wc_state_attach_mesh_colliders (NULL without mesh colliders); derived: re-found every
       substep, not saved by snapshots */
    struct wc_mesh_pairs* pairs;
    /* the self-contact pairs of the current substep (self_pairs.h), NULL unless self-collision
       and def.self_in_solve; derived like the feature pairs */
    struct wc_self_pairs* self_pairs;
} wc_state;

/* y = A x for the substep's system s->A with the self-contact pairs' off-pattern couplings
 * (self_pairs.h, coupling.h): the operator the solvers iterate on. */
void wc_state_mul_system(wc_state* s, const double* x, double* y);

/* Positions start at the model's rest positions, velocities at zero. */
wc_status wc_state_create(wc_state** out, const wc_model* m, const wc_sim_def* def, const wc_allocator* alloc,
                            wc_diag* diag);
void wc_state_destroy(wc_state* s);

/* Replace the pins (validated: count within capacity, particle in range, finite targets, axis
 * zero or unit). A pin whose particle was already pinned keeps moving from its old target;
 * a new pin starts from the particle's current position. On error nothing changes. */
wc_status wc_state_set_pins(wc_state* s, const wc_pin* pins, int n, wc_diag* diag);
/* Replace the colliders (validated: count, type, finite, radius/thickness/friction >= 0, unit
 * plane normal). On error nothing changes. */
wc_status wc_state_set_colliders(wc_state* s, const wc_collider* c, int n, wc_diag* diag);
/* Attach n mesh colliders (borrowed: they must outlive the state), once, at creation time
 * (allocates the substep's collider list). On error nothing changes. */
wc_status wc_state_attach_mesh_colliders(wc_state* s, wc_mesh_collider* const* mesh, int n, wc_diag* diag);
/* Mesh collider k's positions at the end of the next frame (n_verts x 3, m; validated, on error
 * nothing changes); wakes the cloth when they differ from the current ones. */
wc_status wc_state_set_mesh_target(wc_state* s, int k, const double* x, wc_diag* diag);
/* Set every particle's position and velocity (n x 3 each; v may be NULL for zero); refused when
 * any value is non-finite. */
wc_status wc_state_set_positions(wc_state* s, const double* x, const double* v, wc_diag* diag);

/* Wake the cloth (if asleep; the next step reports woke) and restart its rest timer. */
void wc_state_wake(wc_state* s);
/* Set the sleep state (snapshots): asleep 1 zeroes the velocities, asleep 0 wakes it; either
 * way the current gravity and air become the last frame's inputs (a restored state continues
 * exactly as the saved one); rest_time (s; not finite or negative: 0) is the rest timer. */
void wc_state_set_sleep(wc_state* s, int asleep, double rest_time);
/* Largest particle speed |v_i| (m/s). */
double wc_state_max_speed(const wc_state* s);

/* Kinetic energy sum m v^2 / 2 (J). */
double wc_state_kinetic_energy(const wc_state* s);
/* The linear solves' residual floor for a substep whose system has step he (s; solve.h,
 * wc_solver_set_residual_floor): he |g| sqrt(sum of m_i^2 over the particles no pin holds
 * fully), the norm of the impulse gravity gives them (kg m/s). The same on both backends (it
 * reads the pins, not the contacts). */
double wc_state_residual_floor(const wc_state* s, double he);
/* Total mechanical energy: kinetic + springs + gravitational (relative to the origin) (J);
 * *elastic (may be NULL) receives kinetic + springs. */
double wc_state_total_energy(const wc_state* s, double* elastic);

#endif
