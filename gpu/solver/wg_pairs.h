/* The penalty pairs (core/penalty_pairs.h) in a GPU cloth's solve: the mesh colliders' sharp
 * feature pairs (core/mesh_pairs.h) and the self-contact pairs (core/self_pairs.h), found and
 * switched on the host by core's own functions, their terms in the GPU's system.
 *
 * At the substep's start (after the contacts' correction and the integrator's vectors, where
 * core/step.c's prepare finds them) the positions, the velocities and (BDF2, TR-BDF2) v* are read
 * back, core's detections run on them (the mesh pairs: every mesh collider moved on the host;
 * a body resident on the GPU, wg_mesh.h, whose copy in core is stale, has its pairs found on the
 * GPU by wg_mesh_sharp.h and appended; the self pairs, on compute passes, from candidates the GPU
 * finds, wg_self_pairs.h, tested by core's rules on the host into core's own list, bit for bit;
 * fragment passes, WEFT_GPU_SELF_PAIRS=host or non-finite values: core's wc_self_pairs_find) and
 * the pairs go up with a CSR of each particle's entries. The read-back of x and v stays: core's
 * assembly and recheck below, and the self pairs' tests, read them. After the assembly,
 * core's wc_penalty_pairs_assemble decides the active set in double (the predicted gap, with the
 * external forces core computes at the same positions) into host scratch; its additions to b,
 * f_total (what friction reads) and A's diagonal blocks go up as per-particle arrays over the
 * span of the particles they touch, and a pass adds them. Every pair is coupled on the GPU: its
 * off-diagonal blocks c w_a w_b n n^T (c = he^2 k while active) enter each product of A in the
 * solve (pairs_row.glsl: the SpMV, the residual, the Jacobi sweep), not A's blocks (the mesh
 * pairs' in-pattern blocks on the CPU: the same sum), and every level of the multigrid (wg_amg.h). Without Newton's iterations, after a solve,
 * core's recheck runs on dv read back and what it switched goes up the same way (core/step.c
 * pair_passes). With them (core/newton.c), each Newton system takes the pairs' exact terms at the
 * iterate, core's wc_penalty_pairs_newton on the GPU's passes (pairs_newton.glsl,
 * pairs_newton_add.glsl), and the line search's potential their energy, core's
 * wc_penalty_pairs_energy (pairs_energy.glsl), from each pair's gap at x(w) = xb + he (v + w) in
 * two parts the host computes at the detection in double (n . sum w xb - off, n . sum w v) and
 * uploads with k (the gk texture) and the iterate's part: nothing is read back for them.
 *
 * Transfers a substep: 32 n bytes read back (x, v; 48 n with v*; Newton: 16 n more for xb with
 * BDF2 and TR-BDF2), the pairs (48 bytes each and 16 an entry) and 16 n bytes of rows up at the
 * start, 64 bytes a particle of the touched span and 16 a pair at the assembly and each recheck
 * pass, 16 a pair (gk) at the detection with Newton, 16 n bytes read back for each recheck (dv);
 * Newton's systems and potential changes none; with a body resident on the GPU, 4 bytes up
 * and 4, plus 48 a pair it has, read back at the start (wg_mesh_sharp.h); with the self pairs'
 * GPU finder, 4 bytes up and 4, plus 8 a candidate, read back (wg_self_pairs.h). Everything is
 * allocated at creation (the lists' capacities); nothing in a step. Calls are made with the
 * cloth's GL context current. */
#ifndef WEFT_GPU_SOLVER_PAIRS_H
#define WEFT_GPU_SOLVER_PAIRS_H

#include "bdf2.h"
#include "state.h"
#include "wg_mesh_sharp.h"
#include "wg_passes.h"
#include "wg_runner.h"
#include "wg_self_pairs.h"

typedef struct wg_pairs wg_pairs;

/* The cloth's textures the pairs read and change (pointers into the cloth, which keep their
 * addresses): b, ftot and A take the pairs' terms through scratch textures that trade values
 * with them. */
typedef struct wg_pair_cloth {
    int n, nb;                  /* particles, blocks */
    wg_tex *b, *ftot;           /* the substep's right-hand side and forces at x_n */
    wg_tex *a_lo, *a_hi;        /* the substep's A (symmetric blocks) */
    const wg_tex *pblocks, *block;
} wg_pair_cloth;

/* What the last substep's detection and assembly found (core's statistics, wc_step_stats). */
typedef struct wg_pair_counts {
    int mesh, mesh_active, mesh_overflow, mesh_skipped;
    int self, self_active, self_overflow;
    int self_candidates;        /* the GPU finder's candidates (wg_self_pairs.h; -1: too many) */
    long long self_bytes;       /* and the bytes it read back */
} wg_pair_counts;

/* The pairs of the state's lists (s->pairs, s->self_pairs; *out NULL and 1 when it has none):
 * 1, or 0 with err (GL, the device's textures, out of memory). */
int wg_pairs_create(wg_runner* run, const wg_pair_cloth* cloth, const wc_state* s, wg_pairs** out, char* err,
                    size_t err_len);
void wg_pairs_destroy(wg_pairs* p);
void wg_pairs_forget(wg_pairs* p);          /* the memory only (the GL context is gone) */
size_t wg_pairs_bytes(const wg_pairs* p);   /* GPU memory held; 0 for NULL */

/* The substep's start (ig its coefficients): x, v and v* (textures; with Newton, xb too) read
 * back, the pairs found (sharp, NULL: none, the resident bodies' mesh pairs on the GPU) and
 * uploaded, none active yet. */
void wg_pairs_find(wg_pairs* p, wc_state* s, const wc_integ* ig, const wg_tex* x, const wg_tex* v,
                   const wg_tex* vstar, const wg_tex* xb, int n_pins, wg_mesh_sharp* sharp);

/* The self pairs found by gp (wg_self_pairs.h) from then on, where x and v are finite (NULL:
 * core's wc_self_pairs_find). */
void wg_pairs_use_self_finder(wg_pairs* p, wg_self_pairs* gp);

/* After the assembly of A, b and ftot: the active set and its terms. */
void wg_pairs_assemble(wg_pairs* p, wc_state* s, const wc_integ* ig);
/* After a solve (dv its result): list 0 (the mesh pairs) or 1 (the self pairs) rechecked (core's
 * wc_penalty_pairs_recheck), its switches' terms added. Returns the pairs switched. */
int wg_pairs_recheck(wg_pairs* p, wc_state* s, int list, const wc_integ* ig, const wg_tex* dv);
/* Newton's system at the iterate w (a texture; x(w) = xb + he (v + w)): core's
 * wc_penalty_pairs_newton on the GPU (pairs_newton.glsl: the pairs with g(x(w)) < 0 active, their
 * c in the products' (n, c); pairs_newton_add.glsl: their force into b and stiffness into A's
 * diagonal blocks) added to the system Newton's passes built. Core's lists' active and c are left
 * as the assembly set them (nothing on the host reads them with Newton). */
void wg_pairs_newton(wg_pairs* p, const wc_integ* ig, const wg_tex* w);
/* The pairs' part of the incremental potential's change from the iterate wa to wb (textures;
 * core's wc_penalty_pairs_energy at x(w) = xb + he (v + w)), per particle (each pair at its first
 * particle) added to base (per particle, n items) by pairs_energy.glsl into a texture of the
 * pairs', which is returned for the caller's reduction (base itself when the system has no
 * pairs; valid until the next call). */
const wg_tex* wg_pairs_energy_change(wg_pairs* p, const wc_integ* ig, const wg_tex* wa, const wg_tex* wb,
                                     const wg_tex* base);
/* 1 when list k (0 mesh, 1 self) has pairs in this substep's system. */
int wg_pairs_list_on(const wg_pairs* p, int list);
const wg_pair_counts* wg_pairs_counts(const wg_pairs* p);

/* The pairs' own transfers since creation (not the sharp pairs' or the self finder's). */
typedef struct wg_pairs_io {
    long long substeps;         /* detections */
    long long read_bytes;       /* bytes read back: x, v, v*, xb at the start, dv at the rechecks */
    long long systems, changes; /* Newton's systems and the line search's potential changes they took
                                   part in (on the GPU: nothing read back for them) */
} wg_pairs_io;
const wg_pairs_io* wg_pairs_transfers(const wg_pairs* p);

/* The pairs the textures hold at most (p NULL: 0). */
int wg_pairs_capacity(const wg_pairs* p);
/* 1 when this substep's system has pairs (p NULL: 0): the products add their blocks. */
int wg_pairs_on(const wg_pairs* p);
/* The products' inputs: the pairs' textures, or (p NULL) i_any and f_any, an integer and a float
 * texture that pairs_row.glsl binds and never reads. */
wg_pair_in wg_pairs_inputs(const wg_pairs* p, const wg_tex* i_any, const wg_tex* f_any);

/* The pairs' data as uploaded (NULL: not wanted): n pairs, their p (n x 4), w and (n, c) (n x 4
 * floats each), from the host copy (the multigrid's cross terms, wg_amg.h; tests). Returns n. */
int wg_pairs_debug_list(const wg_pairs* p, const int** pp, const float** w, const float** nc);
/* Tests: the pairs' (n, c) read back from the GPU into that host copy (after wg_pairs_newton, the
 * GPU's active set); returns the active pairs. */
int wg_pairs_debug_active(wg_pairs* p);

#endif
