/* Every pass of the solver and its inputs by name.
 *
 * A pass is a shader of gpu/solver/shaders (X_fine: X.glsl compiled with WG_AMG_FINE, the
 * multigrid's form over the finest level). Its inputs are its sampler uniforms, declared in the
 * shader by name (`uniform sampler2D x;`) and listed in the pass's table (wg_passes.c) with the
 * field of its input struct (below) that holds the texture. The table is the contract: when the
 * device builds the program it checks that the program's active samplers are exactly the
 * table's names and assigns their texture units in the table's order (wg_pass_bind_inputs); a
 * pass run binds each unit from the caller's struct (wg_runner.h WG_USE), with no look-up by
 * name. Scalar uniforms (u_*) stay set by name through the program's location cache.
 *
 * A field of an input struct points at the texture to read. Fields a pass's table does not name
 * are not read (wg_amg_in serves every multigrid pass, each naming its own); a named field left
 * NULL is a broken contract that the runner reports (wg_runner.h). */
#ifndef WEFT_GPU_SOLVER_PASSES_H
#define WEFT_GPU_SOLVER_PASSES_H

#include <stddef.h>

#include "gl_texture.h"

typedef enum wg_pass_id {
    WGP_SPRINGS, WGP_AIR, WGP_ASSEMBLE_B, WGP_ASSEMBLE_A, WGP_PINS, WGP_DINV, WGP_PROJECT, WGP_RESIDUAL,
    WGP_SPMV, WGP_PCG_UPDATE, WGP_PCG_DIRECTION, WGP_PCG_SCALARS, WGP_JACOBI_SWEEP, WGP_INTEGRATE,
    WGP_CHECK_PARTICLES, WGP_CHECK_SPRINGS, WGP_REDUCE, WGP_COPY, WGP_STRAIN_SPRINGS, WGP_STRAIN_GATHER,
    WGP_NORMALS, WGP_HOST_OUTPUT, WGP_LANCZOS_START, WGP_TRANSFORM, WGP_COPY_TEXEL,
    WGP_CONTACT_BEGIN, WGP_CONTACT_FRICTION, WGP_CONTACT_RECHECK, WGP_CONTACT_END, WGP_CONTACT_PROJECT,
    WGP_CONTACT_DIAG,
    /* the penalty pairs' terms in the system (wg_pairs.h) */
    WGP_PAIRS_ADD,
    /* their exact terms in Newton's systems and their energy in its line search, on the GPU */
    WGP_PAIRS_NEWTON, WGP_PAIRS_NEWTON_ADD, WGP_PAIRS_ENERGY,
    /* Newton's further iterations and line search (wg_newton.c) */
    WGP_NEWTON_SPRINGS, WGP_NEWTON_GRADIENT, WGP_NEWTON_STEP, WGP_NEWTON_START, WGP_NEWTON_PHI_PARTICLES,
    WGP_NEWTON_PHI_SPRINGS, WGP_NEWTON_FRICTION,
    /* BDF2 and TR-BDF2 (core/bdf2.h): the integrator's vectors, TR-BDF2's implicit air */
    WGP_INTEG_PREPARE, WGP_AIR_LUMP, WGP_INTEG_CONTACTS,
    /* compute passes only: a mesh collider's body moved to a substep on the device (wg_mesh_body.c);
       MESH_REFIT_GROUPS native */
    WGP_MESH_VERTS, WGP_MESH_TRIS, WGP_MESH_MEASURE, WGP_MESH_GATHER, WGP_MESH_REFIT_GROUPS,
    /* compute passes only: a resident body's sharp-feature pairs (wg_mesh_sharp.c); *_GROUPS native */
    WGP_MESH_SHARP, WGP_MESH_SHARP_MASK_GROUPS, WGP_MESH_PAIRS_FIND_GROUPS,
    /* compute passes only: the self-collision stage's idle proof (wg_self_idle.c), native */
    WGP_SELF_IDLE_REFIT_GROUPS, WGP_SELF_IDLE_WALK_GROUPS,
    /* compute passes only: the self pairs' candidates (wg_self_pairs.c), native */
    WGP_SELF_PAIRS_REFIT_GROUPS, WGP_SELF_PAIRS_WALK_GROUPS,
    /* compute passes only: native compute shaders (*_groups.glsl); PCG's update, scalars and
       direction with their reductions' levels and scalar steps folded in (wg_solve.c) */
    WGP_REDUCE_GROUPS, WGP_SPMV_GROUPS, WGP_PCG_UPDATE_GROUPS, WGP_PCG_SCALARS_GROUPS, WGP_PCG_DIRECTION_GROUPS,
    /* compute passes only: a small cloth's whole PCG solve in one work group, with block Jacobi or
       the multigrid (and the multigrid's values packed for it) */
    WGP_PCG_GROUP, WGP_PCG_GROUP_AMG, WGP_AMG_GROUP_PACK_GROUPS,
    /* the multigrid preconditioner (wg_amg.h), compute passes only; *_GROUPS native; each *_FINE
       its pass over the finest level (amg_level_inputs.glsl's WG_AMG_FINE form) */
    WGP_AMG_GALERKIN, WGP_AMG_DINV, WGP_AMG_POWER, WGP_AMG_SMOOTH, WGP_AMG_RESTRICT, WGP_AMG_DOT,
    WGP_AMG_FACTOR_GROUPS, WGP_AMG_COARSE_GROUPS,
    WGP_AMG_GALERKIN_FINE, WGP_AMG_DINV_FINE, WGP_AMG_POWER_FINE, WGP_AMG_SMOOTH_FINE, WGP_AMG_RESTRICT_FINE,
    WGP_AMG_FACTOR_GROUPS_FINE,
    /* the smoothed prolongator's passes (wg_amg_smooth.c): its blocks, T = A P, P^T T, the residual,
       the restriction P^T and the prolongation x + P xc */
    WGP_AMG_PROLONGATOR, WGP_AMG_AP, WGP_AMG_PTAP, WGP_AMG_RESIDUAL, WGP_AMG_RESTRICT_P, WGP_AMG_PROLONG,
    WGP_AMG_PROLONGATOR_FINE, WGP_AMG_AP_FINE, WGP_AMG_RESIDUAL_FINE, WGP_AMG_PROLONG_FINE,
    /* the residual and the restriction P^T in one pass (a level of at most WG_AMG_FOLD_RESIDUAL nodes) */
    WGP_AMG_RESTRICT_RES, WGP_AMG_RESTRICT_RES_FINE,
    /* native: those and the coarsest level's solve in one work group */
    WGP_AMG_COARSE_RESTRICT_GROUPS, WGP_AMG_COARSE_RESTRICT_GROUPS_FINE,
    /* native: the V-cycle from a coarse level of at most WG_AMG_SUB_ROWS nodes down, in one work group */
    WGP_AMG_SUB_GROUPS,
    /* the self-contact pairs' cross terms in the multigrid's levels (wg_amg.h) */
    WGP_AMG_CROSS_TERMS, WGP_AMG_CROSS_BLOCKS,
    /* the rotations about the current positions: the next level's near-null rows, Q's
       coefficients, P_tent's blocks */
    WGP_AMG_TENT_ROWS, WGP_AMG_TENT_COEF, WGP_AMG_TENT_BLOCKS,
    WGP_COUNT
} wg_pass_id;

#define WG_MAX_INPUTS 16        /* texture units a pass may use (GL guarantees 16 per stage) */

/* One input: the sampler's name in the shader, and the offset in the pass's input struct of the
 * field that holds its texture (a const wg_tex*). Its texture unit is its index in the table. */
typedef struct wg_pass_input {
    const char* name;
    size_t field;
} wg_pass_input;

typedef struct wg_pass_info {
    const char* name;           /* the pass, for messages; its shader's name (X_fine: X.glsl) */
    const wg_pass_input* in;    /* its inputs in texture-unit order */
    int n_in;
    size_t in_size;             /* sizeof its input struct (checked at each run) */
    int native;                 /* a compute shader of its own (*_groups.glsl) */
    int compute_only;           /* built only where the passes are compute shaders */
} wg_pass_info;

extern const wg_pass_info wg_passes[WGP_COUNT];

/* Check program (linked; its name `pass` for messages) against the pass's input table and bind
 * its samplers to their units: every active sampler uniform must be in the table and every table
 * name an active sampler. Returns 1, or 0 with a message naming the pass and the uniform. Leaves
 * program 0 in use. */
int wg_pass_bind_inputs(GLuint program, const wg_pass_info* pass, char* err, size_t err_len);

/* ---- input structs ----------------------------------------------------------------------------
 * Particle arrays: x, v, dv (positions, velocities, a velocity change), mass (m, 1/m), rest (rest
 * positions); S0, S1, z the constraint filter (S's symmetric block, (s12, s22, ndof, -), z);
 * rows (spring start, end, triangle start, end of the particle's lists), pblocks (block row
 * start, end, diagonal block, -). Springs: spring (a, b, type, -), spring_rest (rest length,
 * stiffness weight w).
 * Blocks: block (row, column, spring list start, end), a_lo / a_hi (A's symmetric blocks). */

typedef struct wg_springs_in {  /* springs.glsl: per spring, force and Jacobian blocks */
    const wg_tex *x, *v, *vstar, *spring, *spring_rest, *rest;   /* vstar: bdf2.h's v* (BE: v) */
} wg_springs_in;

typedef struct wg_newton_springs_in {  /* newton_springs.glsl: per spring, Newton's system at w */
    const wg_tex *x, *v, *w, *xb, *spring, *spring_rest, *rest;   /* xb: bdf2.h's (BE: x) */
    const wg_tex* wd;   /* the iterate held damping directions are at (u_refresh 2) */
} wg_newton_springs_in;

typedef struct wg_newton_gradient_in {  /* newton_gradient.glsl: per particle, -grad Phi(w), x(w), v(w) */
    const wg_tex *hf, *w, *mass, *xb, *mom, *v;   /* hf: assemble_b's h f_total; v: v_n; xb, mom: bdf2.h's */
    const wg_tex *fric_lo, *fric_hi, *fric_b;     /* friction's frozen Fa, Fb (newton_friction.glsl) */
    const wg_tex *air_lo, *air_hi;                /* TR-BDF2's lumped air Jacobian, frozen (u_air) */
} wg_newton_gradient_in;

typedef struct wg_newton_step_in {      /* newton_step.glsl: per particle, w + alpha d and g.d */
    const wg_tex *w, *d, *g;
} wg_newton_step_in;

typedef struct wg_newton_start_in {     /* newton_start.glsl: the line search's first start and direction */
    const wg_tex *v, *w1, *S0, *S1, *z;
} wg_newton_start_in;

typedef struct wg_newton_phi_particles_in {   /* newton_phi_particles.glsl: the potential's change */
    const wg_tex *wa, *wb, *mass, *fext, *mom;
    const wg_tex *air_lo, *air_hi;   /* the lumped drag Jacobian (air_lump.glsl) */
    const wg_tex *fric_lo, *fric_hi, *fric_b;   /* friction's frozen Fa, Fb (newton_friction.glsl) */
} wg_newton_phi_particles_in;

typedef struct wg_newton_friction_in {   /* newton_friction.glsl: friction's frozen terms, or their capture */
    const wg_tex *pblocks, *a_lo, *a_hi, *b;
    const wg_tex *cap_lo, *cap_hi, *cap_b;   /* the capture (read with u_terms = 1) */
} wg_newton_friction_in;

typedef struct wg_newton_phi_springs_in {     /* newton_phi_springs.glsl: the potential's change */
    const wg_tex *x, *v, *wa, *wb, *xb, *spring, *spring_rest, *rest;
    const wg_tex* wd;   /* as newton_springs' */
} wg_newton_phi_springs_in;

typedef struct wg_integ_prepare_in {   /* integ_prepare.glsl: per particle, xb, v*, mom, the history */
    const wg_tex *x, *v;            /* corrected by the contacts */
    const wg_tex* xs;               /* BDF2: x uncorrected; TR-BDF2's stage 2: stage 1's solved x_g */
    const wg_tex *xp, *vp;          /* the history (BDF2's x_{n-1}, v_{n-1}; TR-BDF2's x_n, v_n) */
} wg_integ_prepare_in;

typedef struct wg_integ_contacts_in {   /* integ_contacts.glsl: TR-BDF2's contacts in the xb form */
    const wg_tex *x, *v, *xb, *vstar, *mom, *vp, *z;   /* after contact_begin and integ_prepare */
    const wg_tex *c0, *c1, *c2, *cvel;                 /* contact_begin's state and surface velocity */
} wg_integ_contacts_in;

typedef struct wg_air_lump_in {    /* air_lump.glsl: per particle, the lumped drag Jacobian */
    const wg_tex *x, *rows, *row_tri, *tri;
} wg_air_lump_in;

typedef struct wg_air_in {      /* air.glsl: per triangle, wind and drag */
    const wg_tex *x, *v, *tri;  /* tri: (a, b, c, -) */
} wg_air_in;

typedef struct wg_assemble_b_in {   /* assemble_b.glsl: per particle, b and f_total */
    const wg_tex *mass, *rows;
    const wg_tex* row_entry;        /* per row spring entry: (spring, sign, other particle, block) */
    const wg_tex *spring_f, *spring_w;   /* springs.glsl's outputs 0 (f, J00) and 1 (w, J11) */
    const wg_tex* row_tri;          /* per row triangle entry: triangle */
    const wg_tex* tri_air;          /* air.glsl's output */
    const wg_tex* mom;              /* the integrator's momentum term (read with u_mom 1) */
} wg_assemble_b_in;

typedef struct wg_assemble_a_in {   /* assemble_a.glsl: per block of A */
    const wg_tex *block, *block_list;    /* block_list: the springs of each block's list */
    const wg_tex* mass;
    const wg_tex *spring_f, *spring_w, *spring_j;   /* springs.glsl's outputs 0, 1, 2 */
    const wg_tex *air_lo, *air_hi;  /* air_lump.glsl's outputs (read with u_air_he != 0) */
    const wg_tex *fric_lo, *fric_hi;   /* friction's frozen Fa (newton_friction.glsl; read with u_friction) */
} wg_assemble_a_in;

typedef struct wg_pins_in {     /* pins.glsl: the pins' filter */
    const wg_tex *x, *v, *xp;   /* xp: the integrator's history (pins.glsl) */
    const wg_tex* pin_map;      /* per particle: its pin or -1 */
    const wg_tex *pin_from, *pin_target, *pin_axis;   /* per pin */
} wg_pins_in;

typedef struct wg_integrate_in {    /* integrate.glsl: v += dv, x = xb + he v, pins snapped */
    const wg_tex *xb, *v, *dv;
    const wg_tex *pin_map, *pin_from, *pin_target, *pin_axis;
} wg_integrate_in;

typedef struct wg_dinv_in {     /* dinv.glsl: the block-Jacobi preconditioner */
    const wg_tex *pblocks, *a_lo, *a_hi, *S0, *S1;
} wg_dinv_in;

typedef struct wg_project_in {  /* project.glsl: dv = z + S dv */
    const wg_tex *dv, *S0, *S1, *z;
} wg_project_in;

/* The penalty pairs' inputs of the passes that multiply by A in a solve (pairs_row.glsl,
 * wg_pairs.h wg_pairs_inputs; with no pairs in the system, any textures of those kinds). */
typedef struct wg_pair_in {
    const wg_tex *pr_rows, *pr_entry, *pr_p;   /* integer: particles' entries, entries, pairs' particles */
    const wg_tex *pr_w, *pr_nc;                /* float: pairs' weights, (n, c) */
} wg_pair_in;

typedef struct wg_residual_in { /* residual.glsl: S (b - A x) */
    const wg_tex *pblocks, *block, *a_lo, *a_hi, *x, *b, *S0, *S1;
    wg_pair_in pairs;
} wg_residual_in;

typedef struct wg_spmv_in {     /* spmv.glsl and spmv_groups.glsl: q = A x, or S (A x) */
    const wg_tex *pblocks, *block, *a_lo, *a_hi, *x, *S0, *S1;
    wg_pair_in pairs;
} wg_spmv_in;

typedef struct wg_pcg_update_in {   /* pcg_update.glsl: dv += alpha c, r -= alpha q, t = D~^-1 r */
    const wg_tex *dv, *r, *c, *q;
    const wg_tex *dinv_lo, *dinv_hi;     /* block Jacobi's D~^-1 (symmetric blocks) */
    const wg_tex *scalars0, *scalars1;   /* pcg_scalars.glsl's outputs 0 and 1 */
} wg_pcg_update_in;

typedef struct wg_pcg_update_groups_in {   /* pcg_update_groups.glsl: the update, alpha folded in */
    const wg_tex *dv, *r, *c, *q, *dinv_lo, *dinv_hi, *scalars0, *scalars1;   /* as wg_pcg_update_in */
    const wg_tex* scalars2;
    const wg_tex* sum;          /* u_fold: the SpMV's per-group partials of c.q */
} wg_pcg_update_groups_in;

typedef struct wg_pcg_direction_in {    /* pcg_direction.glsl: c = S (t + beta c) */
    const wg_tex* t;            /* the preconditioned residual */
    const wg_tex *c, *S0, *S1, *scalars0, *scalars1;
} wg_pcg_direction_in;

typedef struct wg_pcg_scalars_in {  /* pcg_scalars(_groups).glsl: the scalars of the next step */
    const wg_tex *scalars0, *scalars1, *scalars2;
    const wg_tex* sum;          /* a reduction (_groups: partials) whose w is the sum wanted (residual0^2, c.q) */
    const wg_tex* dots;         /* a reduction (_groups: partials) whose xy are (delta, r.r) */
} wg_pcg_scalars_in;

typedef struct wg_pcg_direction_groups_in {   /* pcg_direction_groups.glsl: beta folded in */
    const wg_tex *t, *c, *S0, *S1;             /* as wg_pcg_direction_in */
    const wg_tex *scalars0, *scalars1, *scalars2;
    const wg_tex* dots;         /* the update's per-group partials of (r.z, r.r) */
} wg_pcg_direction_groups_in;

typedef struct wg_pcg_group_in {   /* pcg_group.glsl: a whole PCG solve in one work group */
    const wg_tex *pblocks, *block, *a_lo, *a_hi, *b, *S0, *S1, *z;
    const wg_tex* dv;           /* the initial guess */
} wg_pcg_group_in;

typedef struct wg_pcg_group_amg_in {   /* pcg_group_amg.glsl: the same with the multigrid */
    const wg_tex *pblocks, *block, *a_lo, *a_hi, *b, *S0, *S1, *z, *dv;   /* as wg_pcg_group_in */
    const wg_tex* rows;         /* the finest level's nodes (wg_amg_level) */
    const wg_tex *ipack, *fpack;   /* the levels packed (wg_amg_group.c) */
    const wg_tex* factor;       /* the coarsest level's dense factor */
} wg_pcg_group_amg_in;

typedef struct wg_amg_sub_in {   /* amg_sub_groups.glsl: the coarse sub-cycle in one work group */
    const wg_tex* r;            /* the cut level's right-hand side */
    const wg_tex *ipack, *fpack;   /* the levels from the cut down, packed (wg_amg_group.c) */
    const wg_tex* factor;       /* the coarsest level's dense factor */
} wg_amg_sub_in;

typedef struct wg_jacobi_sweep_in { /* jacobi_sweep.glsl */
    const wg_tex *pblocks, *block, *a_lo, *a_hi, *x, *b, *S0, *S1, *dinv_lo, *dinv_hi;
    const wg_tex* x_prev;       /* the iterate before x (Chebyshev) */
    wg_pair_in pairs;
} wg_jacobi_sweep_in;

typedef struct wg_check_particles_in {  /* check_particles.glsl */
    const wg_tex *x, *v, *mass;
} wg_check_particles_in;

typedef struct wg_check_springs_in {    /* check_springs.glsl */
    const wg_tex *x, *spring, *spring_rest;
} wg_check_springs_in;

typedef struct wg_src_in {      /* reduce, reduce_groups, copy, copy_texel: one texture read */
    const wg_tex* src;
} wg_src_in;

typedef struct wg_strain_springs_in {   /* strain_springs.glsl: per spring, its correction */
    const wg_tex *x, *spring, *spring_rest, *mass, *S0, *S1;
} wg_strain_springs_in;

typedef struct wg_strain_gather_in {    /* strain_gather.glsl */
    const wg_tex *x, *v, *rows, *row_entry;
    const wg_tex* corr;         /* strain_springs.glsl's output */
    const wg_tex *mass, *S0, *S1, *spring;
} wg_strain_gather_in;

typedef struct wg_mesh_verts_in {   /* mesh_verts.glsl */
    const wg_tex *body_from, *body_to;
} wg_mesh_verts_in;

typedef struct wg_mesh_tris_in {    /* mesh_tris.glsl */
    const wg_tex *tri_idx, *vert;
} wg_mesh_tris_in;

typedef struct wg_mesh_measure_in { /* mesh_measure.glsl */
    const wg_tex *src, *ref;
} wg_mesh_measure_in;

typedef struct wg_mesh_gather_in {  /* mesh_gather.glsl */
    const wg_tex *raw, *body_to;
} wg_mesh_gather_in;

typedef struct wg_mesh_refit_in {   /* mesh_refit_groups.glsl (the node image: image 0) */
    const wg_tex *order, *tri_idx, *vert;
} wg_mesh_refit_in;

typedef struct wg_mesh_sharp_in {   /* mesh_sharp.glsl */
    const wg_tex *mesh_vert, *mesh_tri, *bedge, *btri, *bvrow, *bvlist;
} wg_mesh_sharp_in;

typedef struct wg_mesh_sharp_mask_in {   /* mesh_sharp_mask_groups.glsl (the mask: image 0) */
    const wg_tex *order, *mesh_node, *mesh_tri, *sharp;
} wg_mesh_sharp_mask_in;

typedef struct wg_mesh_pairs_find_in {   /* mesh_pairs_find_groups.glsl (pairs: image 0, counter: 1) */
    const wg_tex *mesh_vert, *mesh_tri, *mesh_node, *x, *v, *cfeat, *bedge, *bvrow, *bvlist, *btri, *sharp, *mask;
} wg_mesh_pairs_find_in;

typedef struct wg_self_idle_refit_in {   /* self_idle_refit_groups.glsl (the node image: image 0) */
    const wg_tex *order, *elem, *x, *xs;
} wg_self_idle_refit_in;

typedef struct wg_self_idle_walk_in {   /* self_idle_walk_groups.glsl (the list: image 0, the counter: 1) */
    const wg_tex *tnode, *enode, *elem, *x, *xs, *v, *part, *seam;
} wg_self_idle_walk_in;

typedef struct wg_self_pairs_refit_in {   /* self_pairs_refit_groups.glsl (the node image: image 0) */
    const wg_tex *order, *elem, *x, *v;
} wg_self_pairs_refit_in;

typedef struct wg_self_pairs_walk_in {   /* self_pairs_walk_groups.glsl (candidates: image 0, counter: 1) */
    const wg_tex *tnode, *enode, *elem, *x, *v, *part, *seam;
} wg_self_pairs_walk_in;

typedef struct wg_normals_in {  /* normals.glsl */
    const wg_tex *x, *rows, *row_tri, *tri;
} wg_normals_in;

typedef struct wg_host_output_in {  /* host_output.glsl */
    const wg_tex *x;
    const wg_tex* normal;       /* normals.glsl's output */
    const wg_tex* host_map;     /* per host vertex: its particle or -1 */
    const wg_tex* host_rest;    /* per host vertex: rest position, object space */
} wg_host_output_in;

typedef struct wg_lanczos_start_in {    /* lanczos_start.glsl */
    const wg_tex *S0, *S1;
} wg_lanczos_start_in;

typedef struct wg_transform_in {    /* transform.glsl */
    const wg_tex *x, *v, *dv;
} wg_transform_in;

/* The contact passes: c0, c1, c2 the contact state (wg_contacts.c), colliders one row per
 * collider (contact_geometry.glsl), mesh_* the mesh colliders' vertices, triangles and BVH nodes
 * (wg_mesh.c, contact_query.glsl), cvel begin's per-particle output (the first contact's surface
 * velocity, the correction's length). */
typedef struct wg_contact_begin_in {
    const wg_tex *x, *v, *S0, *S1, *z, *c0, *colliders, *mesh_vert, *mesh_tri, *mesh_node;
} wg_contact_begin_in;

typedef struct wg_contact_friction_in {
    const wg_tex *v, *mass, *ftot, *S0, *S1, *z, *b, *pblocks, *a_lo, *a_hi, *c0, *c1, *c2, *cvel, *colliders;
    const wg_tex* mom;              /* TR-BDF2's momentum term (u_mom) */
} wg_contact_friction_in;

typedef struct wg_contact_recheck_in {
    const wg_tex *v, *mass, *dv, *S0, *S1, *z, *b, *pblocks, *block, *a_lo, *a_hi, *c0, *c1, *c2, *cvel, *colliders;
} wg_contact_recheck_in;

typedef struct wg_contact_end_in {
    const wg_tex *pblocks, *block, *a_lo, *a_hi, *dv, *b, *c0, *c1, *c2;
    const wg_tex* held;             /* TR-BDF2's stage 2: stage 1's held impulses */
    wg_pair_in pairs;
} wg_contact_end_in;

typedef struct wg_contact_project_in {
    const wg_tex *x, *v, *S1, *c0, *colliders, *x_sub, *cvel, *mesh_vert, *mesh_tri, *mesh_node;
} wg_contact_project_in;

typedef struct wg_pairs_add_in {  /* pairs_add.glsl: the penalty pairs' terms into b, f_total, A_ii */
    const wg_tex *pblocks, *a_lo, *a_hi, *b, *ftot;
    const wg_tex *db, *df, *da_lo, *da_hi;   /* per particle: the additions */
} wg_pairs_add_in;

typedef struct wg_pairs_newton_in {  /* pairs_newton.glsl: per pair, active or not at the iterate w */
    const wg_tex *pp, *pw, *pnc, *pgk, *w;
} wg_pairs_newton_in;

typedef struct wg_pairs_newton_add_in {  /* pairs_newton_add.glsl: their terms into b and A_ii */
    const wg_tex *pblocks, *a_lo, *a_hi, *b, *pr_rows, *pr_entry, *pw, *pnc, *pf;
} wg_pairs_newton_add_in;

typedef struct wg_pairs_energy_in {  /* pairs_energy.glsl: their energy's change, per particle */
    const wg_tex *pr_rows, *pr_entry, *pp, *pw, *pnc, *pgk, *wa, *wb, *base;
} wg_pairs_energy_in;

typedef struct wg_contact_diag_in {
    const wg_tex *block, *a_lo, *a_hi;
    const wg_tex *aii_lo, *aii_hi;  /* per particle: its diagonal block */
} wg_contact_diag_in;

/* Every multigrid pass (amg_*.glsl): a level's inputs (amg_level_inputs.glsl), in one of two
 * forms, then the pass's own; each pass's table names those its shader reads. */
typedef struct wg_amg_in {
    const wg_tex *rows, *cols;  /* the level's pattern (cols: the system's block on the finest) */
    const wg_tex *a_lo, *a_hi, *S0, *S1;     /* the finest level: the system's A and filter */
    const wg_tex *a0, *a1, *a2;              /* a coarse level: its operator's block rows */
    const wg_tex *dinv0, *dinv1, *dinv2;     /* the level's D^-1, by rows */
    const wg_tex *gal_range, *gal_list;      /* galerkin: the finer blocks of each block */
    const wg_tex *mem_range, *mem_list;      /* restrict: the nodes of each aggregate */
    const wg_tex *r, *x, *d, *xc, *v, *z;    /* vectors: residual, iterate, step, coarse
                                                correction, power iterate, V-cycle result */
    const wg_tex* bound;        /* the power iterations' reduction */
    const wg_tex* v0;           /* power: core's start vector (a warm start's fallback) */
    const wg_tex* factor;       /* the coarsest level's dense factor */
    const wg_tex *cross_i, *cross_a;         /* the pairs' cross blocks on the level (wg_amg.h) */
    const wg_tex *cross_u, *cross_fine;      /* cross_blocks: the pair slots' (u, c), the finer
                                                level's cross blocks */
    const wg_tex *pair_p, *pair_w, *pair_nc; /* cross_terms: the pairs (wg_pairs.h) */
    /* the smoothed prolongator (wg_amg_smooth.c): P's entries (row, column, own aggregate), its
       rows' entries, each entry's blocks of A, P's and T = A P's block rows, T's products, the
       restriction's entries per coarse node */
    const wg_tex *p_ent, *p_rows, *p_range, *p_list, *pv0, *pv1, *pv2;
    const wg_tex *t_range, *t_list, *tv0, *tv1, *tv2, *pt_range, *pt_list;
    const wg_tex *tent0, *tent1, *tent2;     /* rotations: P_tent's 3x3 blocks, by rows */
    /* rotations about the current positions (amg_tent_qr.glsl): the aggregates' nodes, each
       node's aggregate, the positions and their sum (the finest level), a coarse level's
       near-null rows and centres */
    const wg_tex *tq_range, *tq_list, *tq_of, *pos, *cen;
    const wg_tex *nn0, *nn1, *nn2, *nn3, *nn4, *nn5, *nc;
    const wg_tex *nc_next, *tq_t0, *tq_t1, *tq_t2, *tq_t3, *tq_t4, *tq_t5; /* the next level's centres
                                                and Q's coefficients (amg_tent_blocks) */
} wg_amg_in;

#endif
