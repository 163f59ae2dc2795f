/* Private to gpu/solver: one cloth on the GPU, the struct behind wg_sim.h, shared by the files
 * that make up the cloth (wg_sim.c creation and state moves, wg_step.c the substep, wg_integ.c
 * its integrator's terms, wg_newton.c its Newton iterations, wg_checks.c its checks, wg_solve.c
 * the solvers, wg_output.c outputs, wg_debug.c the test entry points). It sits on the pass
 * machinery (wg_layout.h, wg_runner.h, wg_reduce.h, wg_ring.h, wg_stamps.h) and owns the
 * contacts (wg_contacts.h) and the multigrid (wg_amg.h), which see only the textures it hands
 * them. Its arrays follow wg_layout.h; its state arrays are rings (wg_ring.h). */
#ifndef WEFT_GPU_SOLVER_SIM_IMPL_H
#define WEFT_GPU_SOLVER_SIM_IMPL_H

#include "bdf2.h"
#include "wg_amg.h"
#include "wg_contacts.h"
#include "wg_layout.h"
#include "wg_pairs.h"
#include "wg_reduce.h"
#include "wg_ring.h"
#include "wg_runner.h"
#include "wg_self.h"
#include "wg_self_idle.h"
#include "wg_self_prox.h"
#include "wg_self_pairs.h"
#include "wg_sim.h"
#include "wg_stamps.h"

struct wg_sim {
    wg_device* dev;
    const wc_model* m;
    wc_allocator alloc;
    wg_layout layout;           /* of every array of the cloth */
    wg_runner run;              /* its passes */
    wg_stamps stamps;           /* the frame's timestamps, tagged with wg_step.c's stages */
    int n, ns, nt, nb, nh, pin_cap;

    /* the model, uploaded once */
    wg_tex mass;                /* particles: (m, 1/m) */
    wg_tex rest;                /* particles: rest positions */
    wg_tex spring;              /* springs: (a, b, type, -) */
    wg_tex spring_rest;         /* springs: (rest length, stiffness weight w) */
    wg_tex tri;                 /* triangles: (a, b, c, -) */
    wg_tex rows;                /* particles: (spring start, end, triangle start, end) of their lists */
    wg_tex pblocks;             /* particles: (block row start, end, diagonal block, -) */
    wg_tex row_entry;           /* 2 ns: (spring, sign, other particle, block) */
    wg_tex row_tri;             /* 3 nt: triangle */
    wg_tex block;               /* blocks: (row, column, spring list start, end) */
    wg_tex block_list;          /* 4 ns: spring */
    wg_tex host_map;            /* host vertices: particle or -1 */
    wg_tex host_rest;           /* host vertices: rest position, object space (m) */

    /* pins, per frame */
    wg_tex pin_map;             /* particles: pin index or -1 */
    wg_tex pin_from, pin_target, pin_axis;   /* pins */
    int n_pins_uploaded;
    int* pin_particle;          /* (pin_cap) particles of the uploaded pin map */
    int* pin_map_cpu;           /* (n) */
    float* pin_scratch;         /* (3 pin_cap x 4) */

    /* state */
    wg_ring x, v, dv;
    wg_tex x_bak, v_bak, dv_bak;   /* the frame's back-up (wg_sim_backup) */

    /* the integrator's (made only for BDF2 and TR-BDF2, core/bdf2.h) */
    wg_ring xp, vp;             /* history: BDF2's x_{n-1}, v_{n-1}; TR-BDF2's stage 1 start x_n, v_n */
    wg_tex xp_bak, vp_bak;      /* their frame back-up */
    wg_tex xs;                  /* TR-BDF2: stage 1's x_g as its solve gave it */
    wg_tex xb, vstar, mom;      /* the substep's (stage's) base position, v*, momentum term */
    wg_tex air_lo, air_hi;      /* TR-BDF2's implicit air: the lumped drag Jacobian per particle */

    /* substep scratch */
    wg_tex S0, S1, z;           /* filter */
    wg_tex sf, sw, sj;          /* spring outputs */
    wg_tex fair;                /* triangle air forces */
    wg_tex b, ftot;
    wg_tex A0, A1;              /* blocks */
    wg_tex D0, D1;              /* preconditioner */
    wg_tex sv[3];               /* solver iterates */
    wg_tex r[2], c[2], t, q, part, rz;
    wg_tex gpart[2];            /* compute passes: PCG's per-work-group partial sums, the SpMV's and the
                                   update's (wg_solve.c: the update reads the first as it writes the second) */
    wg_tex sc[2][3];            /* PCG scalars, ping-pong */
    wg_tex grp;                 /* compute passes, 1 x 1: the one-group solve's result (pcg_group.glsl) */
    int sc_cur;
    wg_tex lanczos;             /* 32 x 1: Chebyshev's Lanczos steps (texels 0..19, wg_solve.c) and the
                                   substep's checks (28..31, wg_checks.c) */
    wg_tex chk_p, chk_s, corr;
    wg_tex nw_w[3];             /* Newton's iterates and trials (wg_newton.c; made only with Newton) */
    wg_tex nw_wd;               /* TR-BDF2's stage 1: the iterate its damping directions are held at */
    wg_tex nw_zero;             /* zeros: Newton's initial guess and z */
    wg_tex nw_hf, nw_gd;        /* h f_total at the iterate; per-particle scratch of the reductions */
    wg_tex nw_d, nw_fext;       /* the line search's first direction (then the accepted step, the
                                   contacts' residual: wg_newton_iterate); the substep's external force */
    wg_tex nw_fa[2], nw_fb;     /* kinetic friction's frozen terms (per particle: Fa lo, hi; Fb) */
    wg_tex nw_cap[3];           /* their capture before the friction pass (A_ii lo, hi; b) */
    wg_chain red_p[2], red_s;
    wg_tex nrm, host_pos, host_nrm;
    GLuint pbo;
    float* rb;                  /* read-back scratch: max(n, nh) x 4 floats */

    /* frame */
    wc_solver_opts debug_opts;  /* wg_sim_debug_solve's options (the state's at creation) */
    double rho;                 /* Chebyshev's cached estimate */
    double residual_floor;      /* the solves' residual floor of this substep (core/solve.h; 0: none) */
    double nw_force_scale;      /* the size of the terms the elastic forces sum (N): sqrt(sum over
                                   the particles of (sum over their springs of |k w| rest)^2), for
                                   Newton's gradient floor (wg_newton.c); set with Newton only */
    int rho_valid;
    wg_contacts* contacts;      /* NULL when the cloth has no room for colliders */
    wg_amg* amg;                /* the multigrid when the preconditioner is amg, else NULL */
    wg_self* self;              /* core's self-collision stage on the host (wg_self.h) when the state
                                   has one (s->self), else NULL */
    wg_self_idle* self_idle;    /* the stage's idle proof (wg_self_idle.h): compute passes, with
                                   self, unless WEFT_GPU_SELF_IDLE=off; else NULL */
    wg_self_prox* self_prox;    /* core's proximity pass on the proof's listed pairs (wg_self_prox.h):
                                   with self_idle when WEFT_GPU_SELF_PROX=on, else NULL */
    wg_self_pairs* gself;       /* the self pairs found on the GPU (wg_self_pairs.h): compute passes,
                                   with pairs and self pairs, unless WEFT_GPU_SELF_PAIRS is not gpu */
    wg_pairs* pairs;            /* the penalty pairs in the solve (wg_pairs.h) when the state has
                                   lists and Newton is not wanted, else NULL */
    wg_mesh_sharp* sharp;       /* the resident bodies' sharp-feature pairs found on the GPU
                                   (wg_mesh_sharp.h) when there are pairs and bodies may be
                                   resident (compute passes), else NULL */
    int amg_on;                 /* PCG's solve in progress preconditions with it */
    int newton;                 /* Newton iterations above 1 or the line search (core's
                                   wc_newton_wanted): the nw_* textures exist */
    int nw_friction;            /* Newton on a cloth with colliders: nw_fa, nw_fb, nw_cap exist and
                                   Newton's systems and potential take friction's frozen terms */
    int integ;                  /* BDF2 or TR-BDF2: the integrator's textures exist (nw_fext too) */
    int nw_refreshed;           /* Newton in a TR-BDF2 stage: the damping and air were refreshed at
                                   the iterate (core/newton.h "Refreshed"); the potential's terms follow */
    int nw_held;                /* Newton in TR-BDF2's stage 1 past its first system: the damping's
                                   directions are held at nw_wd's x (core/newton.c "Stage 1") */
    int nw_stage1_ok;           /* TR-BDF2's stage 1 may hold its directions: no contact active and no
                                   penalty pair in the stage (core/newton.c "Stage 1") */
    int nw_air_frozen;          /* Newton in a TR-BDF2 stage with a contact active: the implicit air
                                   stays the stage start's (core/newton.h "Refreshed") */
    int gl_error;               /* a GL error seen in this frame */
    int forget_gl;              /* destroy: free memory only (wg_sim_forget) */
};

/* ---- state moves (wg_sim.c) ------------------------------------------------------------------ */

/* x' = Rx x + tx, v' = Rv v + dv, dv' = Rd dv (wg_sim_transform with Rd = Rv). */
void wg_sim_transform_state(wg_sim* g, const double Rx[9], const double tx[3], const double Rv[9], const double dv[3],
                            const double Rd[9]);

/* ---- the substep (wg_step.c), also run alone by the debug entry points ------------------------ */

void wg_step_upload_pins(wg_sim* g, const wc_state* s);
/* Pins, contacts, the integrator's vectors (a BDF2 cloth's history moves on: s->hist_valid,
 * hist_h), springs, air, assembly of the substep (stage) with core's coefficients ig
 * (wc_integ_coefficients) ending at frame fraction alpha1. */
void wg_step_prepare(wg_sim* g, wc_state* s, const wc_integ* ig, double alpha1, wc_compression compression);

/* ---- the integrator's terms (wg_integ.c), for the substep and Newton's systems ----------------- */

/* The textures of ig's xb, v* and mom (backward Euler: x, v and zeros; mom needs Newton's
 * textures there). */
const wg_tex* wg_integ_xb(wg_sim* g, const wc_integ* ig);
const wg_tex* wg_integ_vstar(wg_sim* g, const wc_integ* ig);
const wg_tex* wg_integ_mom(wg_sim* g, const wc_integ* ig);
/* xb, v*, mom after the contacts' correction (x_start: the substep's x before it), a BDF2
 * cloth's history moving on (integ_prepare.glsl; core/bdf2.c wc_integ_prepare). */
void wg_integ_prepare(wg_sim* g, wc_state* s, const wc_integ* ig, const wg_tex* x_start);
/* TR-BDF2's lumped drag Jacobian at positions x into air_lo / air_hi (air_lump.glsl). */
void wg_integ_air_lump(wg_sim* g, const wc_state* s, const wg_tex* x);
/* A from the springs' outputs sf, sw, sj, plus air_he L on the diagonal (0: no air term) and,
 * with friction, kinetic friction's frozen Fa (nw_fa: Newton's systems). */
void wg_integ_assemble_a(wg_sim* g, double air_he, int friction);

/* ---- the step's checks (wg_checks.c) --------------------------------------------------------- */

typedef struct wg_checks {
    float kinetic;              /* sum of m v.v / 2 */
    float gravity;              /* sum of -m g.x: gravity's potential energy */
    float max_coord;            /* largest |coordinate| of x and v; +inf when one is not finite */
    float max_v2;               /* largest v.v */
    float elastic;              /* sum of the springs' w k e^2 / 2 (e: wc_spring_extension) */
    float max_strain;           /* largest stretch strain (l - rest) / rest */
} wg_checks;

enum { WG_CHECKS_START = 0, WG_CHECKS_END = 2 };   /* the slots of a substep's start and end */

/* The checks of the state (x, v) into a slot (passes and reductions, nothing read back). */
void wg_checks_run(wg_sim* g, const wc_state* s, const wg_tex* x, const wg_tex* v, int slot);
/* Read the start's and (end not NULL) the end's checks back: one read-back of four texels. */
void wg_checks_read(wg_sim* g, wg_checks* start, wg_checks* end);
/* The total energy (J: kinetic, springs, gravity's potential; core's wc_state_total_energy) of
 * the state (x, v), through the end's slot, read back. */
double wg_checks_energy(wg_sim* g, const wc_state* s, const wg_tex* x, const wg_tex* v);
/* The springs' checks of the current x, read back: the elastic energy (J) and the largest
 * stretch strain. */
void wg_checks_springs(wg_sim* g, const wc_state* s, double* elastic, double* max_strain);

/* ---- Newton's further iterations (wg_newton.c) ------------------------------------------------ */

/* Kinetic friction's frozen terms (core/newton.c wc_newton_capture, friction_terms; with
 * g->nw_friction): capture A's diagonal blocks and b before the substep's friction pass
 * (terms = 0), or, after its rechecks, turn what they added into nw_fa, nw_fb (terms = 1). */
void wg_newton_friction(wg_sim* g, int terms);
/* Newton's system at the iterate w: A0/A1 (friction's Fa on the diagonal) and b = -grad Phi(w);
 * the iterate's x(w), v(w) into the rings' free slots (the integration after the iterations
 * writes them anew). */
void wg_newton_system(wg_sim* g, const wc_state* s, const wc_integ* ig, const wg_tex* w, wc_compression compression);

/* After the substep's first solve (*dv its result, residual_scale its wc_solve_result.scale) and
 * its friction rechecks: friction's frozen terms (wg_newton_friction), the line search of its step
 * when asked, up to newton_iterations - 1 Newton steps (with the line search when asked;
 * core/newton.c's rules), and up to core's NW_ENERGY_EXTRA more while the iterate's total energy
 * is above energy_cap (J; HUGE_VAL: no guard); solves and iterations added to st; *dv becomes the
 * accepted iterate (g->nw_w). ig: the substep's (stage's) coefficients (x(w) = xb + he (v_n + w),
 * core/newton.h; TR-BDF2's stages refreshed). On return A0/A1 and b hold the last linearisation
 * and *r_dv the vector whose residual A r_dv - b there is core's constraint residual (the
 * contacts' release reads it, wg_contacts_end): the iterate itself when no further system was
 * built, zeros when the last system was built at the accepted iterate, the accepted step
 * alpha d (nw_d) when a step was taken from it. */
void wg_newton_iterate(wg_sim* g, const wc_state* s, const wc_integ* ig, wc_solver_type solver,
                       wc_compression compression, double residual_scale, double energy_cap, const wg_tex** dv,
                       const wg_tex** r_dv, wc_step_stats* st);
/* Phi(wb) - Phi(wa) of the prepared substep with coefficients ig (two reductions read back). */
double wg_newton_phi_change(wg_sim* g, const wc_state* s, const wc_integ* ig, const wg_tex* wa, const wg_tex* wb);

/* ---- solvers (wg_solve.c) -------------------------------------------------------------------- */

/* The penalty pairs' inputs of a product of A (wg_pairs_inputs), for the pass's input struct. */
static inline wg_pair_in wg_sim_pair_in(const wg_sim* g) { return wg_pairs_inputs(g->pairs, &g->pblocks, &g->mass); }
/* Their switch, on the pass in use (pairs_row.glsl's u_pairs). */
static inline void wg_sim_pair_uniform(wg_sim* g) { wg_u1i(&g->run, "u_pairs", wg_pairs_on(g->pairs)); }

/* g->q = A x over the prepared blocks; with filter, q = S (A x) and w = x.q (PCG's step). */
void wg_spmv(wg_sim* g, const wg_tex* x, int filter);
/* wg_sim_debug_pcg_dots: over rows [0, rows), q = S (A c[0]) and c[0].q, then (with D^-1 made
 * from A) the update at a solve's start from r[0], t = D^-1 r, and (r.t, r.r), the sums finished
 * by the scalars pass as PCG's are: out = (c.q, r.t, r.r). */
void wg_solve_debug_dots(wg_sim* g, int rows, double out[3]);

/* Solve the prepared system (A0/A1, b, S0/S1, z) from the initial guess in dv_in; the result is
 * left in *out (one of g->sv). */
wc_status wg_solve(wg_sim* g, const wc_solver_opts* o, wc_solver_type type, const wg_tex* dv_in,
                     const wg_tex** out, wc_solve_result* res);

#endif
