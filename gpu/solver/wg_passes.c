/* The passes' input tables (see wg_passes.h) and their check against a built program. */
#include "wg_passes.h"

#include <string.h>
#include <GL/glew.h>

#include "gpu_error.h"

#define IN(T, f) {#f, offsetof(T, f)}
#define N(tab) ((int)(sizeof tab / sizeof tab[0]))
/* A table that lists every field of its struct (the struct holds only input pointers). */
/* The penalty pairs' inputs of struct T (its member `pairs`, wg_pair_in). */
#define PAIRS(T)                                                                                    \
    {"pr_rows", offsetof(T, pairs.pr_rows)}, {"pr_entry", offsetof(T, pairs.pr_entry)},           \
        {"pr_p", offsetof(T, pairs.pr_p)}, {"pr_w", offsetof(T, pairs.pr_w)}, {"pr_nc", offsetof(T, pairs.pr_nc)}
#define WHOLE(T, tab) _Static_assert(sizeof(T) == sizeof tab / sizeof tab[0] * sizeof(const wg_tex*), #T)

static const wg_pass_input springs[] = {IN(wg_springs_in, x), IN(wg_springs_in, v), IN(wg_springs_in, vstar),
                                        IN(wg_springs_in, spring), IN(wg_springs_in, spring_rest),
                                        IN(wg_springs_in, rest)};
WHOLE(wg_springs_in, springs);
static const wg_pass_input newton_springs[] = {
    IN(wg_newton_springs_in, x), IN(wg_newton_springs_in, v), IN(wg_newton_springs_in, w),
    IN(wg_newton_springs_in, xb), IN(wg_newton_springs_in, spring), IN(wg_newton_springs_in, spring_rest), IN(wg_newton_springs_in, rest),
    IN(wg_newton_springs_in, wd)};
WHOLE(wg_newton_springs_in, newton_springs);
static const wg_pass_input newton_gradient[] = {IN(wg_newton_gradient_in, hf), IN(wg_newton_gradient_in, w),
                                                IN(wg_newton_gradient_in, mass), IN(wg_newton_gradient_in, xb),
                                                IN(wg_newton_gradient_in, mom), IN(wg_newton_gradient_in, v),
                                                IN(wg_newton_gradient_in, fric_lo), IN(wg_newton_gradient_in, fric_hi),
                                                IN(wg_newton_gradient_in, fric_b), IN(wg_newton_gradient_in, air_lo),
                                                IN(wg_newton_gradient_in, air_hi)};
WHOLE(wg_newton_gradient_in, newton_gradient);
static const wg_pass_input newton_step[] = {IN(wg_newton_step_in, w), IN(wg_newton_step_in, d),
                                            IN(wg_newton_step_in, g)};
WHOLE(wg_newton_step_in, newton_step);
static const wg_pass_input newton_start[] = {IN(wg_newton_start_in, v), IN(wg_newton_start_in, w1),
                                             IN(wg_newton_start_in, S0), IN(wg_newton_start_in, S1),
                                             IN(wg_newton_start_in, z)};
WHOLE(wg_newton_start_in, newton_start);
static const wg_pass_input newton_phi_particles[] = {
    IN(wg_newton_phi_particles_in, wa), IN(wg_newton_phi_particles_in, wb), IN(wg_newton_phi_particles_in, mass),
    IN(wg_newton_phi_particles_in, fext), IN(wg_newton_phi_particles_in, mom),
    IN(wg_newton_phi_particles_in, air_lo), IN(wg_newton_phi_particles_in, air_hi),
    IN(wg_newton_phi_particles_in, fric_lo), IN(wg_newton_phi_particles_in, fric_hi),
    IN(wg_newton_phi_particles_in, fric_b)};
WHOLE(wg_newton_phi_particles_in, newton_phi_particles);
static const wg_pass_input newton_friction[] = {
    IN(wg_newton_friction_in, pblocks), IN(wg_newton_friction_in, a_lo), IN(wg_newton_friction_in, a_hi),
    IN(wg_newton_friction_in, b), IN(wg_newton_friction_in, cap_lo), IN(wg_newton_friction_in, cap_hi),
    IN(wg_newton_friction_in, cap_b)};
WHOLE(wg_newton_friction_in, newton_friction);
static const wg_pass_input newton_phi_springs[] = {
    IN(wg_newton_phi_springs_in, x), IN(wg_newton_phi_springs_in, v), IN(wg_newton_phi_springs_in, wa),
    IN(wg_newton_phi_springs_in, wb), IN(wg_newton_phi_springs_in, xb), IN(wg_newton_phi_springs_in, spring),
    IN(wg_newton_phi_springs_in, spring_rest), IN(wg_newton_phi_springs_in, rest), IN(wg_newton_phi_springs_in, wd)};
WHOLE(wg_newton_phi_springs_in, newton_phi_springs);
static const wg_pass_input integ_prepare[] = {
    IN(wg_integ_prepare_in, x), IN(wg_integ_prepare_in, v), IN(wg_integ_prepare_in, xs),
    IN(wg_integ_prepare_in, xp), IN(wg_integ_prepare_in, vp)};
WHOLE(wg_integ_prepare_in, integ_prepare);
static const wg_pass_input integ_contacts[] = {
    IN(wg_integ_contacts_in, x),  IN(wg_integ_contacts_in, v),  IN(wg_integ_contacts_in, xb),
    IN(wg_integ_contacts_in, vstar), IN(wg_integ_contacts_in, mom), IN(wg_integ_contacts_in, vp),
    IN(wg_integ_contacts_in, z),  IN(wg_integ_contacts_in, c0), IN(wg_integ_contacts_in, c1),
    IN(wg_integ_contacts_in, c2), IN(wg_integ_contacts_in, cvel)};
WHOLE(wg_integ_contacts_in, integ_contacts);
static const wg_pass_input air_lump[] = {IN(wg_air_lump_in, x), IN(wg_air_lump_in, rows),
                                         IN(wg_air_lump_in, row_tri), IN(wg_air_lump_in, tri)};
WHOLE(wg_air_lump_in, air_lump);
static const wg_pass_input air[] = {IN(wg_air_in, x), IN(wg_air_in, v), IN(wg_air_in, tri)};
WHOLE(wg_air_in, air);
static const wg_pass_input assemble_b[] = {
    IN(wg_assemble_b_in, mass), IN(wg_assemble_b_in, rows), IN(wg_assemble_b_in, row_entry),
    IN(wg_assemble_b_in, spring_f), IN(wg_assemble_b_in, spring_w), IN(wg_assemble_b_in, row_tri),
    IN(wg_assemble_b_in, tri_air), IN(wg_assemble_b_in, mom)};
WHOLE(wg_assemble_b_in, assemble_b);
static const wg_pass_input assemble_a[] = {
    IN(wg_assemble_a_in, block), IN(wg_assemble_a_in, block_list), IN(wg_assemble_a_in, mass),
    IN(wg_assemble_a_in, spring_f), IN(wg_assemble_a_in, spring_w), IN(wg_assemble_a_in, spring_j),
    IN(wg_assemble_a_in, air_lo), IN(wg_assemble_a_in, air_hi), IN(wg_assemble_a_in, fric_lo),
    IN(wg_assemble_a_in, fric_hi)};
WHOLE(wg_assemble_a_in, assemble_a);
static const wg_pass_input pins[] = {IN(wg_pins_in, x), IN(wg_pins_in, v), IN(wg_pins_in, xp), IN(wg_pins_in, pin_map),
                                     IN(wg_pins_in, pin_from), IN(wg_pins_in, pin_target), IN(wg_pins_in, pin_axis)};
WHOLE(wg_pins_in, pins);
static const wg_pass_input integrate[] = {
    IN(wg_integrate_in, xb), IN(wg_integrate_in, v), IN(wg_integrate_in, dv), IN(wg_integrate_in, pin_map),
    IN(wg_integrate_in, pin_from), IN(wg_integrate_in, pin_target), IN(wg_integrate_in, pin_axis)};
WHOLE(wg_integrate_in, integrate);
static const wg_pass_input dinv[] = {IN(wg_dinv_in, pblocks), IN(wg_dinv_in, a_lo), IN(wg_dinv_in, a_hi),
                                     IN(wg_dinv_in, S0), IN(wg_dinv_in, S1)};
WHOLE(wg_dinv_in, dinv);
static const wg_pass_input project[] = {IN(wg_project_in, dv), IN(wg_project_in, S0), IN(wg_project_in, S1),
                                        IN(wg_project_in, z)};
WHOLE(wg_project_in, project);
static const wg_pass_input residual[] = {
    IN(wg_residual_in, pblocks), IN(wg_residual_in, block), IN(wg_residual_in, a_lo), IN(wg_residual_in, a_hi),
    IN(wg_residual_in, x), IN(wg_residual_in, b), IN(wg_residual_in, S0), IN(wg_residual_in, S1),
    PAIRS(wg_residual_in)};
WHOLE(wg_residual_in, residual);
static const wg_pass_input spmv[] = {IN(wg_spmv_in, pblocks), IN(wg_spmv_in, block), IN(wg_spmv_in, a_lo),
                                     IN(wg_spmv_in, a_hi), IN(wg_spmv_in, x), IN(wg_spmv_in, S0), IN(wg_spmv_in, S1),
                                     PAIRS(wg_spmv_in)};
WHOLE(wg_spmv_in, spmv);
static const wg_pass_input pcg_update[] = {
    IN(wg_pcg_update_in, dv), IN(wg_pcg_update_in, r), IN(wg_pcg_update_in, c), IN(wg_pcg_update_in, q),
    IN(wg_pcg_update_in, dinv_lo), IN(wg_pcg_update_in, dinv_hi), IN(wg_pcg_update_in, scalars0),
    IN(wg_pcg_update_in, scalars1)};
WHOLE(wg_pcg_update_in, pcg_update);
#define UG(f) IN(wg_pcg_update_groups_in, f)
static const wg_pass_input pcg_update_groups[] = {UG(dv),       UG(r),        UG(c),        UG(q),         UG(dinv_lo),
                                                  UG(dinv_hi),  UG(scalars0), UG(scalars1), UG(scalars2), UG(sum)};
WHOLE(wg_pcg_update_groups_in, pcg_update_groups);
#define DG(f) IN(wg_pcg_direction_groups_in, f)
static const wg_pass_input pcg_direction_groups[] = {DG(t),        DG(c),        DG(S0),       DG(S1),
                                                     DG(scalars0), DG(scalars1), DG(scalars2), DG(dots)};
WHOLE(wg_pcg_direction_groups_in, pcg_direction_groups);
#define PG(f) IN(wg_pcg_group_in, f)
static const wg_pass_input pcg_group[] = {PG(pblocks), PG(block), PG(a_lo), PG(a_hi), PG(b),
                                          PG(S0),      PG(S1),    PG(z),    PG(dv)};
WHOLE(wg_pcg_group_in, pcg_group);
#define PA(f) IN(wg_pcg_group_amg_in, f)
static const wg_pass_input pcg_group_amg[] = {PA(pblocks), PA(block), PA(a_lo), PA(a_hi),  PA(b),     PA(S0),    PA(S1),
                                              PA(z),       PA(dv),    PA(rows), PA(ipack), PA(fpack), PA(factor)};
WHOLE(wg_pcg_group_amg_in, pcg_group_amg);
#define SG(f) IN(wg_amg_sub_in, f)
static const wg_pass_input amg_sub[] = {SG(r), SG(ipack), SG(fpack), SG(factor)};
WHOLE(wg_amg_sub_in, amg_sub);
static const wg_pass_input pcg_direction[] = {
    IN(wg_pcg_direction_in, t), IN(wg_pcg_direction_in, c), IN(wg_pcg_direction_in, S0),
    IN(wg_pcg_direction_in, S1), IN(wg_pcg_direction_in, scalars0), IN(wg_pcg_direction_in, scalars1)};
WHOLE(wg_pcg_direction_in, pcg_direction);
static const wg_pass_input pcg_scalars[] = {
    IN(wg_pcg_scalars_in, scalars0), IN(wg_pcg_scalars_in, scalars1), IN(wg_pcg_scalars_in, sum),
    IN(wg_pcg_scalars_in, dots), IN(wg_pcg_scalars_in, scalars2)};
WHOLE(wg_pcg_scalars_in, pcg_scalars);
static const wg_pass_input jacobi_sweep[] = {
    IN(wg_jacobi_sweep_in, pblocks), IN(wg_jacobi_sweep_in, block),   IN(wg_jacobi_sweep_in, a_lo),
    IN(wg_jacobi_sweep_in, a_hi),    IN(wg_jacobi_sweep_in, x),       IN(wg_jacobi_sweep_in, b),
    IN(wg_jacobi_sweep_in, S0),      IN(wg_jacobi_sweep_in, S1),      IN(wg_jacobi_sweep_in, dinv_lo),
    IN(wg_jacobi_sweep_in, dinv_hi), IN(wg_jacobi_sweep_in, x_prev), PAIRS(wg_jacobi_sweep_in)};
WHOLE(wg_jacobi_sweep_in, jacobi_sweep);
static const wg_pass_input check_particles[] = {IN(wg_check_particles_in, x), IN(wg_check_particles_in, v),
                                                IN(wg_check_particles_in, mass)};
WHOLE(wg_check_particles_in, check_particles);
static const wg_pass_input check_springs[] = {IN(wg_check_springs_in, x), IN(wg_check_springs_in, spring),
                                              IN(wg_check_springs_in, spring_rest)};
WHOLE(wg_check_springs_in, check_springs);
static const wg_pass_input src[] = {IN(wg_src_in, src)};
WHOLE(wg_src_in, src);
static const wg_pass_input strain_springs[] = {
    IN(wg_strain_springs_in, x),    IN(wg_strain_springs_in, spring), IN(wg_strain_springs_in, spring_rest),
    IN(wg_strain_springs_in, mass), IN(wg_strain_springs_in, S0),     IN(wg_strain_springs_in, S1)};
WHOLE(wg_strain_springs_in, strain_springs);
static const wg_pass_input strain_gather[] = {
    IN(wg_strain_gather_in, x),    IN(wg_strain_gather_in, v),  IN(wg_strain_gather_in, rows),
    IN(wg_strain_gather_in, row_entry), IN(wg_strain_gather_in, corr), IN(wg_strain_gather_in, mass),
    IN(wg_strain_gather_in, S0),   IN(wg_strain_gather_in, S1), IN(wg_strain_gather_in, spring)};
WHOLE(wg_strain_gather_in, strain_gather);
static const wg_pass_input mesh_verts[] = {IN(wg_mesh_verts_in, body_from), IN(wg_mesh_verts_in, body_to)};
WHOLE(wg_mesh_verts_in, mesh_verts);
static const wg_pass_input mesh_tris[] = {IN(wg_mesh_tris_in, tri_idx), IN(wg_mesh_tris_in, vert)};
WHOLE(wg_mesh_tris_in, mesh_tris);
static const wg_pass_input mesh_measure[] = {IN(wg_mesh_measure_in, src), IN(wg_mesh_measure_in, ref)};
WHOLE(wg_mesh_measure_in, mesh_measure);
static const wg_pass_input mesh_gather[] = {IN(wg_mesh_gather_in, raw), IN(wg_mesh_gather_in, body_to)};
WHOLE(wg_mesh_gather_in, mesh_gather);
static const wg_pass_input mesh_refit[] = {IN(wg_mesh_refit_in, order), IN(wg_mesh_refit_in, tri_idx),
                                           IN(wg_mesh_refit_in, vert)};
WHOLE(wg_mesh_refit_in, mesh_refit);
static const wg_pass_input mesh_sharp[] = {IN(wg_mesh_sharp_in, mesh_vert), IN(wg_mesh_sharp_in, mesh_tri),
                                           IN(wg_mesh_sharp_in, bedge), IN(wg_mesh_sharp_in, btri),
                                           IN(wg_mesh_sharp_in, bvrow), IN(wg_mesh_sharp_in, bvlist)};
WHOLE(wg_mesh_sharp_in, mesh_sharp);
static const wg_pass_input mesh_pairs_find[] = {
    IN(wg_mesh_pairs_find_in, mesh_vert), IN(wg_mesh_pairs_find_in, mesh_tri), IN(wg_mesh_pairs_find_in, mesh_node),
    IN(wg_mesh_pairs_find_in, x),         IN(wg_mesh_pairs_find_in, v),        IN(wg_mesh_pairs_find_in, cfeat),
    IN(wg_mesh_pairs_find_in, bedge),     IN(wg_mesh_pairs_find_in, bvrow),    IN(wg_mesh_pairs_find_in, bvlist),
    IN(wg_mesh_pairs_find_in, btri),      IN(wg_mesh_pairs_find_in, sharp),    IN(wg_mesh_pairs_find_in, mask)};
WHOLE(wg_mesh_pairs_find_in, mesh_pairs_find);
static const wg_pass_input mesh_sharp_mask[] = {IN(wg_mesh_sharp_mask_in, order), IN(wg_mesh_sharp_mask_in, mesh_node),
                                                IN(wg_mesh_sharp_mask_in, mesh_tri), IN(wg_mesh_sharp_mask_in, sharp)};
WHOLE(wg_mesh_sharp_mask_in, mesh_sharp_mask);
static const wg_pass_input self_idle_refit[] = {IN(wg_self_idle_refit_in, order), IN(wg_self_idle_refit_in, elem),
                                                IN(wg_self_idle_refit_in, x), IN(wg_self_idle_refit_in, xs)};
WHOLE(wg_self_idle_refit_in, self_idle_refit);
static const wg_pass_input self_idle_walk[] = {
    IN(wg_self_idle_walk_in, tnode), IN(wg_self_idle_walk_in, enode), IN(wg_self_idle_walk_in, elem),
    IN(wg_self_idle_walk_in, x),     IN(wg_self_idle_walk_in, xs),    IN(wg_self_idle_walk_in, v),
    IN(wg_self_idle_walk_in, part),
    IN(wg_self_idle_walk_in, seam)};
WHOLE(wg_self_idle_walk_in, self_idle_walk);
static const wg_pass_input self_pairs_refit[] = {IN(wg_self_pairs_refit_in, order), IN(wg_self_pairs_refit_in, elem),
                                                 IN(wg_self_pairs_refit_in, x), IN(wg_self_pairs_refit_in, v)};
WHOLE(wg_self_pairs_refit_in, self_pairs_refit);
static const wg_pass_input self_pairs_walk[] = {
    IN(wg_self_pairs_walk_in, tnode), IN(wg_self_pairs_walk_in, enode), IN(wg_self_pairs_walk_in, elem),
    IN(wg_self_pairs_walk_in, x),     IN(wg_self_pairs_walk_in, v),     IN(wg_self_pairs_walk_in, part),
    IN(wg_self_pairs_walk_in, seam)};
WHOLE(wg_self_pairs_walk_in, self_pairs_walk);
static const wg_pass_input normals[] = {IN(wg_normals_in, x), IN(wg_normals_in, rows), IN(wg_normals_in, row_tri),
                                        IN(wg_normals_in, tri)};
WHOLE(wg_normals_in, normals);
static const wg_pass_input host_output[] = {IN(wg_host_output_in, x), IN(wg_host_output_in, normal),
                                            IN(wg_host_output_in, host_map), IN(wg_host_output_in, host_rest)};
WHOLE(wg_host_output_in, host_output);
static const wg_pass_input lanczos_start[] = {IN(wg_lanczos_start_in, S0), IN(wg_lanczos_start_in, S1)};
WHOLE(wg_lanczos_start_in, lanczos_start);
static const wg_pass_input transform[] = {IN(wg_transform_in, x), IN(wg_transform_in, v), IN(wg_transform_in, dv)};
WHOLE(wg_transform_in, transform);

static const wg_pass_input contact_begin[] = {
    IN(wg_contact_begin_in, x),  IN(wg_contact_begin_in, v), IN(wg_contact_begin_in, S0),
    IN(wg_contact_begin_in, S1), IN(wg_contact_begin_in, z), IN(wg_contact_begin_in, c0),
    IN(wg_contact_begin_in, colliders), IN(wg_contact_begin_in, mesh_vert), IN(wg_contact_begin_in, mesh_tri),
    IN(wg_contact_begin_in, mesh_node)};
WHOLE(wg_contact_begin_in, contact_begin);
static const wg_pass_input contact_friction[] = {
    IN(wg_contact_friction_in, v),    IN(wg_contact_friction_in, mass),    IN(wg_contact_friction_in, ftot),
    IN(wg_contact_friction_in, S0),   IN(wg_contact_friction_in, S1),      IN(wg_contact_friction_in, z),
    IN(wg_contact_friction_in, b),    IN(wg_contact_friction_in, pblocks), IN(wg_contact_friction_in, a_lo),
    IN(wg_contact_friction_in, a_hi), IN(wg_contact_friction_in, c0),      IN(wg_contact_friction_in, c1),
    IN(wg_contact_friction_in, c2),   IN(wg_contact_friction_in, cvel),    IN(wg_contact_friction_in, colliders),
    IN(wg_contact_friction_in, mom)};
WHOLE(wg_contact_friction_in, contact_friction);
static const wg_pass_input contact_recheck[] = {
    IN(wg_contact_recheck_in, v),    IN(wg_contact_recheck_in, mass),  IN(wg_contact_recheck_in, dv),
    IN(wg_contact_recheck_in, S0),   IN(wg_contact_recheck_in, S1),    IN(wg_contact_recheck_in, z),
    IN(wg_contact_recheck_in, b),    IN(wg_contact_recheck_in, pblocks), IN(wg_contact_recheck_in, block),
    IN(wg_contact_recheck_in, a_lo), IN(wg_contact_recheck_in, a_hi),  IN(wg_contact_recheck_in, c0),
    IN(wg_contact_recheck_in, c1),   IN(wg_contact_recheck_in, c2),    IN(wg_contact_recheck_in, cvel),
    IN(wg_contact_recheck_in, colliders)};
WHOLE(wg_contact_recheck_in, contact_recheck);
static const wg_pass_input contact_end[] = {
    IN(wg_contact_end_in, pblocks), IN(wg_contact_end_in, block), IN(wg_contact_end_in, a_lo),
    IN(wg_contact_end_in, a_hi),    IN(wg_contact_end_in, dv),    IN(wg_contact_end_in, b),
    IN(wg_contact_end_in, c0),      IN(wg_contact_end_in, c1),    IN(wg_contact_end_in, c2),
    IN(wg_contact_end_in, held),    PAIRS(wg_contact_end_in)};
WHOLE(wg_contact_end_in, contact_end);
static const wg_pass_input contact_project[] = {
    IN(wg_contact_project_in, x), IN(wg_contact_project_in, v), IN(wg_contact_project_in, S1),
    IN(wg_contact_project_in, c0), IN(wg_contact_project_in, colliders), IN(wg_contact_project_in, x_sub),
    IN(wg_contact_project_in, cvel), IN(wg_contact_project_in, mesh_vert), IN(wg_contact_project_in, mesh_tri),
    IN(wg_contact_project_in, mesh_node)};
WHOLE(wg_contact_project_in, contact_project);
static const wg_pass_input contact_diag[] = {IN(wg_contact_diag_in, block), IN(wg_contact_diag_in, a_lo),
                                             IN(wg_contact_diag_in, a_hi), IN(wg_contact_diag_in, aii_lo),
                                             IN(wg_contact_diag_in, aii_hi)};
WHOLE(wg_contact_diag_in, contact_diag);
static const wg_pass_input pairs_add[] = {
    IN(wg_pairs_add_in, pblocks), IN(wg_pairs_add_in, a_lo), IN(wg_pairs_add_in, a_hi),  IN(wg_pairs_add_in, b),
    IN(wg_pairs_add_in, ftot),    IN(wg_pairs_add_in, db),   IN(wg_pairs_add_in, df),    IN(wg_pairs_add_in, da_lo),
    IN(wg_pairs_add_in, da_hi)};
WHOLE(wg_pairs_add_in, pairs_add);
static const wg_pass_input pairs_newton[] = {IN(wg_pairs_newton_in, pp), IN(wg_pairs_newton_in, pw),
                                             IN(wg_pairs_newton_in, pnc), IN(wg_pairs_newton_in, pgk),
                                             IN(wg_pairs_newton_in, w)};
WHOLE(wg_pairs_newton_in, pairs_newton);
static const wg_pass_input pairs_newton_add[] = {
    IN(wg_pairs_newton_add_in, pblocks), IN(wg_pairs_newton_add_in, a_lo),    IN(wg_pairs_newton_add_in, a_hi),
    IN(wg_pairs_newton_add_in, b),       IN(wg_pairs_newton_add_in, pr_rows), IN(wg_pairs_newton_add_in, pr_entry),
    IN(wg_pairs_newton_add_in, pw),      IN(wg_pairs_newton_add_in, pnc),     IN(wg_pairs_newton_add_in, pf)};
WHOLE(wg_pairs_newton_add_in, pairs_newton_add);
static const wg_pass_input pairs_energy[] = {
    IN(wg_pairs_energy_in, pr_rows), IN(wg_pairs_energy_in, pr_entry), IN(wg_pairs_energy_in, pp),
    IN(wg_pairs_energy_in, pw),      IN(wg_pairs_energy_in, pnc),      IN(wg_pairs_energy_in, pgk),
    IN(wg_pairs_energy_in, wa),      IN(wg_pairs_energy_in, wb),       IN(wg_pairs_energy_in, base)};
WHOLE(wg_pairs_energy_in, pairs_energy);

/* The multigrid's passes: a level's inputs in its form (amg_level_inputs.glsl), then the pass's
   own. On a coarse level the Galerkin sum and D^-1 read the blocks alone (no pattern); D^-1 is
   read by the passes that apply it. */
#define AMG(f) IN(wg_amg_in, f)
#define FINE_OP AMG(cols), AMG(a_lo), AMG(a_hi), AMG(S0), AMG(S1)
#define COARSE_OP AMG(cols), AMG(a0), AMG(a1), AMG(a2)
#define DINV AMG(dinv0), AMG(dinv1), AMG(dinv2)
#define CROSS AMG(cross_i), AMG(cross_a)
static const wg_pass_input amg_galerkin[] = {AMG(a0), AMG(a1), AMG(a2), AMG(gal_range), AMG(gal_list)};
static const wg_pass_input amg_galerkin_fine[] = {FINE_OP, AMG(gal_range), AMG(gal_list)};
static const wg_pass_input amg_dinv[] = {AMG(rows), AMG(a0), AMG(a1), AMG(a2), CROSS};
static const wg_pass_input amg_dinv_fine[] = {AMG(rows), FINE_OP, CROSS};
static const wg_pass_input amg_power[] = {AMG(rows), COARSE_OP, DINV, AMG(v), AMG(v0), AMG(bound), CROSS};
static const wg_pass_input amg_power_fine[] = {AMG(rows), FINE_OP, DINV, AMG(v), AMG(v0), AMG(bound), CROSS};
static const wg_pass_input amg_smooth[] = {AMG(rows), COARSE_OP, DINV, AMG(r), AMG(x), AMG(d), AMG(bound), AMG(xc), CROSS};
static const wg_pass_input amg_smooth_fine[] = {AMG(rows), FINE_OP, DINV,     AMG(r),
                                                AMG(x),    AMG(d),  AMG(bound), AMG(xc), CROSS};
static const wg_pass_input amg_restrict[] = {AMG(rows), COARSE_OP, AMG(mem_range), AMG(mem_list), AMG(r), AMG(x), CROSS};
static const wg_pass_input amg_restrict_fine[] = {AMG(rows), FINE_OP, AMG(mem_range), AMG(mem_list), AMG(r), AMG(x), CROSS};
static const wg_pass_input amg_factor[] = {AMG(rows), COARSE_OP, CROSS};
static const wg_pass_input amg_factor_fine[] = {AMG(rows), FINE_OP, CROSS};
#define PV AMG(pv0), AMG(pv1), AMG(pv2)
#define TENT AMG(tent0), AMG(tent1), AMG(tent2)
static const wg_pass_input amg_prolongator[] = {AMG(a0),     AMG(a1),     AMG(a2),     DINV, AMG(bound), AMG(p_ent),
                                                AMG(p_rows), AMG(p_range), AMG(p_list), TENT};
static const wg_pass_input amg_prolongator_fine[] = {FINE_OP, DINV, AMG(bound), AMG(p_ent), AMG(p_range), AMG(p_list), TENT};
static const wg_pass_input amg_ap[] = {AMG(a0), AMG(a1), AMG(a2), PV, AMG(t_range), AMG(t_list)};
static const wg_pass_input amg_ap_fine[] = {FINE_OP, PV, AMG(t_range), AMG(t_list)};
static const wg_pass_input amg_ptap[] = {PV, AMG(tv0), AMG(tv1), AMG(tv2), AMG(gal_range), AMG(gal_list), AMG(cols), AMG(nc)};
#define TQ AMG(tq_range), AMG(tq_list), AMG(pos), AMG(cen), AMG(nn0), AMG(nn1), AMG(nn2), AMG(nn3), AMG(nn4), AMG(nn5), AMG(nc)
static const wg_pass_input amg_tent_rows[] = {TQ};
static const wg_pass_input amg_tent_blocks[] = {AMG(pos), AMG(nn0), AMG(nn1), AMG(nn2), AMG(nn3), AMG(nn4), AMG(nn5), AMG(nc),
    AMG(tq_of), AMG(nc_next), AMG(tq_t0), AMG(tq_t1), AMG(tq_t2), AMG(tq_t3), AMG(tq_t4), AMG(tq_t5)};
static const wg_pass_input amg_residual[] = {AMG(rows), COARSE_OP, AMG(r), AMG(x), CROSS};
static const wg_pass_input amg_residual_fine[] = {AMG(rows), FINE_OP, AMG(r), AMG(x), CROSS};
static const wg_pass_input amg_restrict_p[] = {PV, AMG(pt_range), AMG(pt_list), AMG(r)};
static const wg_pass_input amg_restrict_res[] = {AMG(rows), COARSE_OP, PV, AMG(pt_range), AMG(pt_list), AMG(r), AMG(x), CROSS};
static const wg_pass_input amg_restrict_res_fine[] = {AMG(rows), FINE_OP, PV, AMG(pt_range), AMG(pt_list), AMG(r), AMG(x), CROSS};
static const wg_pass_input amg_coarse_restrict[] = {AMG(factor), AMG(rows), COARSE_OP, PV, AMG(pt_range), AMG(pt_list),
    AMG(r), AMG(x), CROSS};
static const wg_pass_input amg_coarse_restrict_fine[] = {AMG(factor), AMG(rows), FINE_OP, PV, AMG(pt_range), AMG(pt_list),
    AMG(r), AMG(x), CROSS};
static const wg_pass_input amg_prolong[] = {PV, AMG(p_ent), AMG(p_rows), AMG(x), AMG(xc)};
static const wg_pass_input amg_prolong_fine[] = {AMG(S0), AMG(S1), PV, AMG(p_ent), AMG(p_rows), AMG(x), AMG(xc)};
static const wg_pass_input amg_cross_blocks[] = {AMG(cross_i), AMG(cross_u), AMG(cross_fine)};
static const wg_pass_input amg_cross_terms[] = {AMG(pair_p), AMG(pair_w), AMG(pair_nc), AMG(S0), AMG(S1)};
static const wg_pass_input amg_coarse[] = {AMG(factor), AMG(r)};
static const wg_pass_input amg_dot[] = {AMG(r), AMG(z)};
static const wg_pass_input amg_group_pack[] = {DINV, AMG(a0), AMG(a1), AMG(a2), PV, AMG(bound)};

#define PASS(name, tab, T) {name, tab, N(tab), sizeof(T), 0, 0}
#define COMPUTE(name, tab, T) {name, tab, N(tab), sizeof(T), 0, 1}
#define NATIVE(name, tab, T) {name, tab, N(tab), sizeof(T), 1, 1}

const wg_pass_info wg_passes[WGP_COUNT] = {
    [WGP_SPRINGS] = PASS("springs", springs, wg_springs_in),
    [WGP_AIR] = PASS("air", air, wg_air_in),
    [WGP_ASSEMBLE_B] = PASS("assemble_b", assemble_b, wg_assemble_b_in),
    [WGP_ASSEMBLE_A] = PASS("assemble_a", assemble_a, wg_assemble_a_in),
    [WGP_PINS] = PASS("pins", pins, wg_pins_in),
    [WGP_DINV] = PASS("dinv", dinv, wg_dinv_in),
    [WGP_PROJECT] = PASS("project", project, wg_project_in),
    [WGP_RESIDUAL] = PASS("residual", residual, wg_residual_in),
    [WGP_SPMV] = PASS("spmv", spmv, wg_spmv_in),
    [WGP_PCG_UPDATE] = PASS("pcg_update", pcg_update, wg_pcg_update_in),
    [WGP_PCG_DIRECTION] = PASS("pcg_direction", pcg_direction, wg_pcg_direction_in),
    [WGP_PCG_SCALARS] = PASS("pcg_scalars", pcg_scalars, wg_pcg_scalars_in),
    [WGP_JACOBI_SWEEP] = PASS("jacobi_sweep", jacobi_sweep, wg_jacobi_sweep_in),
    [WGP_INTEGRATE] = PASS("integrate", integrate, wg_integrate_in),
    [WGP_CHECK_PARTICLES] = PASS("check_particles", check_particles, wg_check_particles_in),
    [WGP_CHECK_SPRINGS] = PASS("check_springs", check_springs, wg_check_springs_in),
    [WGP_REDUCE] = PASS("reduce", src, wg_src_in),
    [WGP_COPY] = PASS("copy", src, wg_src_in),
    [WGP_STRAIN_SPRINGS] = PASS("strain_springs", strain_springs, wg_strain_springs_in),
    [WGP_STRAIN_GATHER] = PASS("strain_gather", strain_gather, wg_strain_gather_in),
    [WGP_NORMALS] = PASS("normals", normals, wg_normals_in),
    [WGP_HOST_OUTPUT] = PASS("host_output", host_output, wg_host_output_in),
    [WGP_LANCZOS_START] = PASS("lanczos_start", lanczos_start, wg_lanczos_start_in),
    [WGP_TRANSFORM] = PASS("transform", transform, wg_transform_in),
    [WGP_COPY_TEXEL] = PASS("copy_texel", src, wg_src_in),
    [WGP_CONTACT_BEGIN] = PASS("contact_begin", contact_begin, wg_contact_begin_in),
    [WGP_CONTACT_FRICTION] = PASS("contact_friction", contact_friction, wg_contact_friction_in),
    [WGP_CONTACT_RECHECK] = PASS("contact_recheck", contact_recheck, wg_contact_recheck_in),
    [WGP_CONTACT_END] = PASS("contact_end", contact_end, wg_contact_end_in),
    [WGP_CONTACT_PROJECT] = PASS("contact_project", contact_project, wg_contact_project_in),
    [WGP_CONTACT_DIAG] = PASS("contact_diag", contact_diag, wg_contact_diag_in),
    [WGP_PAIRS_ADD] = PASS("pairs_add", pairs_add, wg_pairs_add_in),
    [WGP_PAIRS_NEWTON] = PASS("pairs_newton", pairs_newton, wg_pairs_newton_in),
    [WGP_PAIRS_NEWTON_ADD] = PASS("pairs_newton_add", pairs_newton_add, wg_pairs_newton_add_in),
    [WGP_PAIRS_ENERGY] = PASS("pairs_energy", pairs_energy, wg_pairs_energy_in),
    [WGP_NEWTON_SPRINGS] = PASS("newton_springs", newton_springs, wg_newton_springs_in),
    [WGP_NEWTON_GRADIENT] = PASS("newton_gradient", newton_gradient, wg_newton_gradient_in),
    [WGP_NEWTON_STEP] = PASS("newton_step", newton_step, wg_newton_step_in),
    [WGP_NEWTON_START] = PASS("newton_start", newton_start, wg_newton_start_in),
    [WGP_NEWTON_PHI_PARTICLES] = PASS("newton_phi_particles", newton_phi_particles, wg_newton_phi_particles_in),
    [WGP_NEWTON_PHI_SPRINGS] = PASS("newton_phi_springs", newton_phi_springs, wg_newton_phi_springs_in),
    [WGP_NEWTON_FRICTION] = PASS("newton_friction", newton_friction, wg_newton_friction_in),
    [WGP_INTEG_PREPARE] = PASS("integ_prepare", integ_prepare, wg_integ_prepare_in),
    [WGP_AIR_LUMP] = PASS("air_lump", air_lump, wg_air_lump_in),
    [WGP_INTEG_CONTACTS] = PASS("integ_contacts", integ_contacts, wg_integ_contacts_in),
    [WGP_MESH_VERTS] = COMPUTE("mesh_verts", mesh_verts, wg_mesh_verts_in),
    [WGP_MESH_TRIS] = COMPUTE("mesh_tris", mesh_tris, wg_mesh_tris_in),
    [WGP_MESH_MEASURE] = COMPUTE("mesh_measure", mesh_measure, wg_mesh_measure_in),
    [WGP_MESH_GATHER] = COMPUTE("mesh_gather", mesh_gather, wg_mesh_gather_in),
    [WGP_MESH_REFIT_GROUPS] = NATIVE("mesh_refit_groups", mesh_refit, wg_mesh_refit_in),
    [WGP_MESH_SHARP] = COMPUTE("mesh_sharp", mesh_sharp, wg_mesh_sharp_in),
    [WGP_MESH_SHARP_MASK_GROUPS] = NATIVE("mesh_sharp_mask_groups", mesh_sharp_mask, wg_mesh_sharp_mask_in),
    [WGP_MESH_PAIRS_FIND_GROUPS] = NATIVE("mesh_pairs_find_groups", mesh_pairs_find, wg_mesh_pairs_find_in),
    [WGP_SELF_IDLE_REFIT_GROUPS] = NATIVE("self_idle_refit_groups", self_idle_refit, wg_self_idle_refit_in),
    [WGP_SELF_IDLE_WALK_GROUPS] = NATIVE("self_idle_walk_groups", self_idle_walk, wg_self_idle_walk_in),
    [WGP_SELF_PAIRS_REFIT_GROUPS] = NATIVE("self_pairs_refit_groups", self_pairs_refit, wg_self_pairs_refit_in),
    [WGP_SELF_PAIRS_WALK_GROUPS] = NATIVE("self_pairs_walk_groups", self_pairs_walk, wg_self_pairs_walk_in),
    [WGP_REDUCE_GROUPS] = NATIVE("reduce_groups", src, wg_src_in),
    [WGP_SPMV_GROUPS] = NATIVE("spmv_groups", spmv, wg_spmv_in),
    [WGP_PCG_UPDATE_GROUPS] = NATIVE("pcg_update_groups", pcg_update_groups, wg_pcg_update_groups_in),
    [WGP_PCG_SCALARS_GROUPS] = NATIVE("pcg_scalars_groups", pcg_scalars, wg_pcg_scalars_in),
    [WGP_PCG_DIRECTION_GROUPS] = NATIVE("pcg_direction_groups", pcg_direction_groups, wg_pcg_direction_groups_in),
    [WGP_PCG_GROUP] = NATIVE("pcg_group", pcg_group, wg_pcg_group_in),
    [WGP_PCG_GROUP_AMG] = NATIVE("pcg_group_amg", pcg_group_amg, wg_pcg_group_amg_in),
    [WGP_AMG_GROUP_PACK_GROUPS] = NATIVE("amg_group_pack_groups", amg_group_pack, wg_amg_in),
    [WGP_AMG_GALERKIN] = COMPUTE("amg_galerkin", amg_galerkin, wg_amg_in),
    [WGP_AMG_DINV] = COMPUTE("amg_dinv", amg_dinv, wg_amg_in),
    [WGP_AMG_POWER] = COMPUTE("amg_power", amg_power, wg_amg_in),
    [WGP_AMG_SMOOTH] = COMPUTE("amg_smooth", amg_smooth, wg_amg_in),
    [WGP_AMG_RESTRICT] = COMPUTE("amg_restrict", amg_restrict, wg_amg_in),
    [WGP_AMG_DOT] = COMPUTE("amg_dot", amg_dot, wg_amg_in),
    [WGP_AMG_FACTOR_GROUPS] = NATIVE("amg_factor_groups", amg_factor, wg_amg_in),
    [WGP_AMG_COARSE_GROUPS] = NATIVE("amg_coarse_groups", amg_coarse, wg_amg_in),
    [WGP_AMG_GALERKIN_FINE] = COMPUTE("amg_galerkin_fine", amg_galerkin_fine, wg_amg_in),
    [WGP_AMG_DINV_FINE] = COMPUTE("amg_dinv_fine", amg_dinv_fine, wg_amg_in),
    [WGP_AMG_POWER_FINE] = COMPUTE("amg_power_fine", amg_power_fine, wg_amg_in),
    [WGP_AMG_SMOOTH_FINE] = COMPUTE("amg_smooth_fine", amg_smooth_fine, wg_amg_in),
    [WGP_AMG_RESTRICT_FINE] = COMPUTE("amg_restrict_fine", amg_restrict_fine, wg_amg_in),
    [WGP_AMG_FACTOR_GROUPS_FINE] = NATIVE("amg_factor_groups_fine", amg_factor_fine, wg_amg_in),
    [WGP_AMG_PROLONGATOR] = COMPUTE("amg_prolongator", amg_prolongator, wg_amg_in),
    [WGP_AMG_AP] = COMPUTE("amg_ap", amg_ap, wg_amg_in),
    [WGP_AMG_PTAP] = COMPUTE("amg_ptap", amg_ptap, wg_amg_in),
    [WGP_AMG_RESIDUAL] = COMPUTE("amg_residual", amg_residual, wg_amg_in),
    [WGP_AMG_RESTRICT_P] = COMPUTE("amg_restrict_p", amg_restrict_p, wg_amg_in),
    [WGP_AMG_TENT_ROWS] = COMPUTE("amg_tent_rows", amg_tent_rows, wg_amg_in),
    [WGP_AMG_TENT_COEF] = COMPUTE("amg_tent_coef", amg_tent_rows, wg_amg_in),
    [WGP_AMG_TENT_BLOCKS] = COMPUTE("amg_tent_blocks", amg_tent_blocks, wg_amg_in),
    [WGP_AMG_PROLONG] = COMPUTE("amg_prolong", amg_prolong, wg_amg_in),
    [WGP_AMG_PROLONGATOR_FINE] = COMPUTE("amg_prolongator_fine", amg_prolongator_fine, wg_amg_in),
    [WGP_AMG_AP_FINE] = COMPUTE("amg_ap_fine", amg_ap_fine, wg_amg_in),
    [WGP_AMG_RESIDUAL_FINE] = COMPUTE("amg_residual_fine", amg_residual_fine, wg_amg_in),
    [WGP_AMG_RESTRICT_RES] = COMPUTE("amg_restrict_res", amg_restrict_res, wg_amg_in),
    [WGP_AMG_RESTRICT_RES_FINE] = COMPUTE("amg_restrict_res_fine", amg_restrict_res_fine, wg_amg_in),
    [WGP_AMG_COARSE_RESTRICT_GROUPS] = NATIVE("amg_coarse_restrict_groups", amg_coarse_restrict, wg_amg_in),
    [WGP_AMG_COARSE_RESTRICT_GROUPS_FINE] = NATIVE("amg_coarse_restrict_groups_fine", amg_coarse_restrict_fine, wg_amg_in),
    [WGP_AMG_SUB_GROUPS] = NATIVE("amg_sub_groups", amg_sub, wg_amg_sub_in),
    [WGP_AMG_PROLONG_FINE] = COMPUTE("amg_prolong_fine", amg_prolong_fine, wg_amg_in),
    [WGP_AMG_CROSS_TERMS] = COMPUTE("amg_cross_terms", amg_cross_terms, wg_amg_in),
    [WGP_AMG_CROSS_BLOCKS] = COMPUTE("amg_cross_blocks", amg_cross_blocks, wg_amg_in),
};

static int is_sampler(GLenum type) {
    return type == GL_SAMPLER_2D || type == GL_INT_SAMPLER_2D || type == GL_UNSIGNED_INT_SAMPLER_2D;
}

int wg_pass_bind_inputs(GLuint program, const wg_pass_info* pass, char* err, size_t err_len) {
    if (pass->n_in > WG_MAX_INPUTS) {
        wg_errorf(err, err_len, "pass '%s': %d inputs, more than the %d texture units a pass may use", pass->name,
                  pass->n_in, WG_MAX_INPUTS);
        return 0;
    }
    int seen[WG_MAX_INPUTS] = {0};
    GLint active = 0;
    glGetProgramiv(program, GL_ACTIVE_UNIFORMS, &active);
    for (GLint k = 0; k < active; ++k) {
        char name[64];
        GLint size = 0;
        GLenum type = 0;
        glGetActiveUniform(program, (GLuint)k, sizeof name, NULL, &size, &type, name);
        if (!is_sampler(type)) continue;
        int j = 0;
        while (j < pass->n_in && strcmp(pass->in[j].name, name) != 0) ++j;
        if (j == pass->n_in) {
            wg_errorf(err, err_len, "pass '%s': its shader reads sampler '%s', which is not in the pass's input table",
                      pass->name, name);
            return 0;
        }
        seen[j] = 1;
    }
    for (int j = 0; j < pass->n_in; ++j)
        if (!seen[j]) {
            wg_errorf(err, err_len, "pass '%s': input '%s' of its table is not a sampler its shader reads", pass->name,
                      pass->in[j].name);
            return 0;
        }
    glUseProgram(program);
    for (int j = 0; j < pass->n_in; ++j) glUniform1i(glGetUniformLocation(program, pass->in[j].name), j);
    glUseProgram(0);
    return 1;
}
