/* The GPU backend of one cloth: core's model uploaded once into textures, the mutable state
 * (positions, velocities, the solver's warm start, contacts) living in textures, and the frame
 * driven by core's wc_step_frame_ops with every substep run as fragment-shader passes into
 * framebuffer objects. Positions and velocities are read back only when asked (outputs,
 * snapshots, wg_sim_download); per substep one small read-back of the step's checks (and of
 * the solver's scalars every check_every iterations). Every call must be made inside
 * wg_gl_begin/wg_gl_end of the device's context.
 *
 * The wc_state stays the cloth's book-keeping: pins, colliders, settings, time, sleep and the
 * contact count live there as on the CPU; its x, v, dv and contact arrays are a mirror that
 * wg_sim_download fills and wg_sim_upload sends (a caller that changes them calls upload). */
#ifndef WEFT_GPU_SOLVER_SIM_H
#define WEFT_GPU_SOLVER_SIM_H

#include "step.h"
#include "wg_device.h"

typedef struct wg_sim wg_sim;

/* What the GPU does not have, for a cloth of model m with settings def and n_mesh mesh colliders:
 * WC_OK, or WC_ERROR_UNSUPPORTED with a message naming it and what to choose instead: the direct
 * solver, the multigrid on fragment passes and other preconditioners, PCG past
 * WG_GROUP_MAX_PARTICLES particles where WEFT_GPU_SOLVE=group forces the one-group solve
 * (wg_device.h). No GL call: the backend table's
 * `supports` (AUTO asks it before it chooses) and wg_sim_create's first check. */
wc_status wg_sim_supports(const wg_device* dev, const wc_model* m, const wc_sim_def* def, int n_mesh, wc_diag* diag);

/* Upload the model and the state; host_rest (n_host_verts x 3, object space, m; NULL: zeros) is
 * where outputs put host vertices no polygon uses. Refused as wg_sim_supports refuses; with
 * WC_ERROR_GPU: arrays beyond the device's texture limits (naming the array, its size and the
 * limit), GL errors. */
wc_status wg_sim_create(wg_device* dev, const wc_state* s, const double* host_rest, wg_sim** out, wc_diag* diag);
void wg_sim_destroy(wg_sim* g);
/* Free the CPU memory only, when the GL context is gone or cannot be made current (the host's
 * context in WEFT_GL_HOST_CURRENT mode: its GL objects go with that context). */
void wg_sim_forget(wg_sim* g);

/* wc_step_frame on the GPU (same schedule, retries, judging, stats, sleeping; the last resorts
 * run the cloth's own solver, with the compressed springs' geometric term dropped, in place of
 * the direct solver: st->direct_fallbacks counts those last-resort tries). */
wc_status wg_sim_step_frame(wg_sim* g, wc_state* s, double dt, wc_step_stats* st, wc_diag* diag);

/* Read x, v, dv, the integrator's history (x_prev, v_prev; BDF2 and TR-BDF2) and the contact
 * arrays back into s (exact: float values widened to double). */
wc_status wg_sim_download(wg_sim* g, wc_state* s, wc_diag* diag);
/* Send s's x, v, dv, history and contact arrays (rounded to float). */
wc_status wg_sim_upload(wg_sim* g, const wc_state* s, wc_diag* diag);

/* The frame's back-up of the state textures, history included (taken before a step the caller
 * may undo), and its restore. */
void wg_sim_backup(wg_sim* g);
void wg_sim_restore_backup(wg_sim* g);

/* x' = Rx x + tx, v' = Rv v + dv for every particle (teleports, inertia), on the GPU; the
 * solver's warm start turns with the velocities (dv' = Rv dv). Row-major 3x3 matrices. */
void wg_sim_transform(wg_sim* g, const double Rx[9], const double tx[3], const double Rv[9], const double dv[3]);
/* The same for BDF2's history (x_prev' = Rx x_prev + tx, v_prev' = Rv v_prev + dv); nothing for a
 * backward-Euler cloth. The caller decides whether the history is valid (s->hist_valid). */
void wg_sim_transform_history(wg_sim* g, const double Rx[9], const double tx[3], const double Rv[9],
                              const double dv[3]);

/* Largest |coordinate| of any position or velocity (+inf when one is not finite), measured on
 * the GPU (one small read-back). */
double wg_sim_max_abs(wg_sim* g);

/* Per host vertex, positions and normals (either may be NULL) in world space, or in object space
 * (to_object: R^-1 (p - t) / scale, R row-major, t the object's transform); host_rest gives the
 * rest positions of host vertices no polygon uses. Computed by two passes; read back through a
 * pixel-pack buffer into float (n_host x 3) arrays, or (gl buffers, non-zero names) written
 * straight into the caller's GL buffer objects at byte offsets, 3 floats per vertex. */
typedef struct wg_output_request {
    int to_object;
    double R[9], t[3], unit_scale;
    float* positions;           /* host memory, or NULL */
    float* normals;
    unsigned position_buffer;   /* GL buffer names (the current context's), or 0 */
    unsigned normal_buffer;
    size_t position_offset, normal_offset;   /* bytes */
} wg_output_request;
wc_status wg_sim_output(wg_sim* g, const wg_output_request* req, wc_diag* diag);

/* n vertices of 3 floats from the host's GL buffer object `buffer` (a name of the current
 * context, checked by the caller: wg_host_buffer_check), vertex i at byte offset + i stride, into
 * out (n x 3): the range copied on the GPU into the cloth's read-back buffer, which is then
 * mapped. INVALID_ARGUMENT (a buffer the host keeps mapped), GPU (a GL error: out's contents
 * are then undefined). The host's buffer bindings are restored. */
/* The cloth's mesh colliders on the GPU (wg_mesh.h); NULL when it has no room for colliders. */
struct wg_mesh* wg_sim_mesh(wg_sim* g);
wc_status wg_sim_read_host_vertices(wg_sim* g, unsigned buffer, size_t offset, size_t stride, int n, float* out,
                                    wc_diag* d);

/* Bytes of GPU memory held (textures). */
size_t wg_sim_gpu_bytes(const wg_sim* g);

/* ---- for tests and benchmarks ---------------------------------------------------------------- */

/* Run a substep's preparation (pins, contacts, the integrator's vectors, forces, assembly) for a
 * substep of length h ending at frame fraction alpha1, as the step does (TR-BDF2: its stage 1;
 * BDF2: a BDF2 step where s's history is valid for h, and the history moves on), then read back: A (pattern.n_blocks x 9, row-major
 * blocks), b (n x 3), the filter S (n x 9), z (n x 3), ndof (n) and x (n x 3; contacts may have
 * moved particles). Any output may be NULL. */
wc_status wg_sim_debug_prepare(wg_sim* g, wc_state* s, double h, double alpha1, double* A, double* b, double* S,
                                 double* z, unsigned char* ndof, double* x, wc_diag* diag);
/* The springs' elastic energy (J, seams at s->seam_scale) and largest stretch strain at the
 * current positions, as the step's checks measure them on the GPU. */
void wg_sim_debug_spring_checks(wg_sim* g, const wc_state* s, double* elastic, double* max_strain);
/* The change Phi(wb) - Phi(wa) (J) of the line search's incremental potential between two
 * iterates (n x 3 velocity changes) of the substep of length h the last prepare built (TR-BDF2:
 * its stage 1), as the
 * line search measures it (a cloth made with Newton iterations or the line search only). */
double wg_sim_debug_phi_change(wg_sim* g, const wc_state* s, double h, const double* wa, const double* wb);
/* Newton's system (a cloth made with Newton iterations or the line search) of the substep of
 * length h the last prepare built, at the iterate w (n x 3): friction's frozen terms taken from
 * what the prepare's friction pass added (once per prepare), then A (pattern.n_blocks x 9) and
 * -grad Phi(w) (n x 3) read back, and friction's Fa (n x 9) and Fb (n x 3; zeros on a cloth
 * without colliders). Any output may be NULL. */
wc_status wg_sim_debug_newton_system(wg_sim* g, const wc_state* s, double h, const double* w, double* A, double* grad,
                                     double* fa, double* fb, wc_diag* diag);
/* Solve the system the last prepare built with the cloth's solver from the initial guess dv
 * (n x 3, in/out, NULL: the state's warm start); the result as core's wc_solve_result. */
wc_status wg_sim_debug_solve(wg_sim* g, wc_solver_type type, double* dv, wc_solve_result* res, wc_diag* diag);
/* Replace the prepared A (pattern.n_blocks x 9, row-major; symmetric blocks), b (n x 3) and,
 * when f is not NULL, the filter (S, z, ndof) with the caller's, rounded to float. */
wc_status wg_sim_debug_set_system(wg_sim* g, const double* A, const double* b, const wc_filter* f, wc_diag* diag);
/* Forget Chebyshev's cached rho (the next Chebyshev solve estimates it again), and set the
 * options wg_sim_debug_solve uses (the state's at creation until then). */
void wg_sim_debug_invalidate_rho(wg_sim* g);
void wg_sim_debug_set_opts(wg_sim* g, const wc_solver_opts* o);
/* Chebyshev's cached rho estimate (0 when none). */
double wg_sim_debug_rho(const wg_sim* g);
/* y = A x with the last prepared A (n x 3 each; the penalty pairs' off-diagonal blocks included
 * while the substep has them). */
wc_status wg_sim_debug_spmv(wg_sim* g, const double* x, double* y, wc_diag* diag);
/* The system as it stands now (A: blocks x 9, b: n x 3; NULL: not read), e.g. after a recheck. */
wc_status wg_sim_debug_read_system(wg_sim* g, double* A, double* b, wc_diag* diag);
/* PCG's fused products over the first `rows` rows (1 <= rows <= particles) with the last prepared
 * system: c and r (n x 3) uploaded, q = S (A c) and t = D^-1 r (the block-Jacobi inverse made from
 * A) read back into q and t (rows x 3), and dots = (c.q, r.t, r.r) as the solve's scalars pass
 * finishes them (compute passes: from the fused passes' per-group partial sums). */
wc_status wg_sim_debug_pcg_dots(wg_sim* g, int rows, const double* c, const double* r, double* q, double* t,
                                double dots[3], wc_diag* diag);
/* Sum (mode 0) or max (mode 1) of n values through the reduction passes (n <= particles). */
double wg_sim_debug_reduce(wg_sim* g, const double* values, int n, int mode);
/* Wall time (ms) of `reps` runs of one SpMV pass and one copy pass of the same size, measured
 * with glFinish around them, and the bytes each moves (for the bandwidth ratio). */
void wg_sim_debug_bandwidth(wg_sim* g, int reps, double* ms_spmv, double* ms_copy, double* bytes_spmv,
                            double* bytes_copy);
/* Passes (draws) run by this cloth since its creation: a step's fixed cost on a GPU is about
 * passes x a per-pass cost (benchmarks difference it around a frame). */
long long wg_sim_debug_passes(const wg_sim* g);

#endif
