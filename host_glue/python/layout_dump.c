/* Prints the C compiler's layout of every public struct of weft.h (size, alignment, and each
 * field's offset and size, in declaration order), the size of every public enum and the value of
 * every public constant, as one JSON object. tests/python/test_python_layout.py compares it with
 * the ctypes mirror in weft/__init__.py. Uses weft.h only (no library). */
#include <stddef.h>
#include <stdio.h>

#include "weft/weft.h"

static int first_struct = 1, first_field = 1, first_entry = 1;

static void struct_begin(const char* name, size_t size, size_t align) {
    printf("%s\n    \"%s\": {\"size\": %zu, \"align\": %zu, \"fields\": [", first_struct ? "" : ",",
           name, size, align);
    first_struct = 0;
    first_field = 1;
}

static void field(const char* name, size_t offset, size_t size) {
    printf("%s\n      [\"%s\", %zu, %zu]", first_field ? "" : ",", name, offset, size);
    first_field = 0;
}

static void struct_end(void) { printf("\n    ]}"); }

static void entry(const char* name, long long value) {
    printf("%s\n    \"%s\": %lld", first_entry ? "" : ",", name, value);
    first_entry = 0;
}

#define STRUCT(T) struct_begin(#T, sizeof(T), _Alignof(T))
#define FIELD(T, f) field(#f, offsetof(T, f), sizeof(((T*)0)->f))

static void dump_structs(void) {
    STRUCT(weft_version_info);
    FIELD(weft_version_info, major);
    FIELD(weft_version_info, minor);
    FIELD(weft_version_info, patch);
    FIELD(weft_version_info, abi);
    struct_end();

    STRUCT(weft_allocator);
    FIELD(weft_allocator, alloc);
    FIELD(weft_allocator, free);
    FIELD(weft_allocator, user);
    struct_end();

    STRUCT(weft_context_def);
    FIELD(weft_context_def, backend);
    FIELD(weft_context_def, threads);
    FIELD(weft_context_def, log);
    FIELD(weft_context_def, log_user);
    FIELD(weft_context_def, log_level);
    FIELD(weft_context_def, allocator);
    FIELD(weft_context_def, gl_mode);
    FIELD(weft_context_def, internal_cookie);
    struct_end();

    STRUCT(weft_cloth);
    FIELD(weft_cloth, id);
    struct_end();

    STRUCT(weft_mesh_desc);
    FIELD(weft_mesh_desc, path);
    FIELD(weft_mesh_desc, select);
    FIELD(weft_mesh_desc, positions);
    FIELD(weft_mesh_desc, n_vertices);
    FIELD(weft_mesh_desc, face_sizes);
    FIELD(weft_mesh_desc, n_faces);
    FIELD(weft_mesh_desc, indices);
    struct_end();

    STRUCT(weft_material);
    FIELD(weft_material, density);
    FIELD(weft_material, stiffness);
    FIELD(weft_material, damping);
    struct_end();

    STRUCT(weft_attachment_def);
    FIELD(weft_attachment_def, vertices);
    FIELD(weft_attachment_def, n_vertices);
    FIELD(weft_attachment_def, bind_transform);
    FIELD(weft_attachment_def, free_axis);
    FIELD(weft_attachment_def, internal_cookie);
    struct_end();

    STRUCT(weft_collider_def);
    FIELD(weft_collider_def, type);
    FIELD(weft_collider_def, radius);
    FIELD(weft_collider_def, half_height);
    FIELD(weft_collider_def, thickness);
    FIELD(weft_collider_def, friction);
    FIELD(weft_collider_def, transform);
    FIELD(weft_collider_def, internal_cookie);
    struct_end();

    STRUCT(weft_mesh_collider_def);
    FIELD(weft_mesh_collider_def, mesh);
    FIELD(weft_mesh_collider_def, unit_scale);
    FIELD(weft_mesh_collider_def, transform);
    FIELD(weft_mesh_collider_def, thickness);
    FIELD(weft_mesh_collider_def, friction);
    FIELD(weft_mesh_collider_def, push_speed);
    FIELD(weft_mesh_collider_def, internal_cookie);
    struct_end();

    STRUCT(weft_cloth_def);
    FIELD(weft_cloth_def, mesh);
    FIELD(weft_cloth_def, unit_scale);
    FIELD(weft_cloth_def, weld_tolerance);
    FIELD(weft_cloth_def, transform);
    FIELD(weft_cloth_def, material);
    FIELD(weft_cloth_def, gravity);
    FIELD(weft_cloth_def, wind);
    FIELD(weft_cloth_def, air_drag_normal);
    FIELD(weft_cloth_def, air_drag_tangent);
    FIELD(weft_cloth_def, solver);
    FIELD(weft_cloth_def, tolerance);
    FIELD(weft_cloth_def, max_iterations);
    FIELD(weft_cloth_def, preconditioner);
    FIELD(weft_cloth_def, integrator);
    FIELD(weft_cloth_def, newton_iterations);
    FIELD(weft_cloth_def, line_search);
    FIELD(weft_cloth_def, substeps);
    FIELD(weft_cloth_def, max_frame_time);
    FIELD(weft_cloth_def, strain_limit);
    FIELD(weft_cloth_def, sleep_speed);
    FIELD(weft_cloth_def, sleep_time);
    FIELD(weft_cloth_def, linear_inertia);
    FIELD(weft_cloth_def, angular_inertia);
    FIELD(weft_cloth_def, n_attachments);
    FIELD(weft_cloth_def, attachments);
    FIELD(weft_cloth_def, n_colliders);
    FIELD(weft_cloth_def, colliders);
    FIELD(weft_cloth_def, n_mesh_colliders);
    FIELD(weft_cloth_def, mesh_colliders);
    FIELD(weft_cloth_def, sew_distance);
    FIELD(weft_cloth_def, sew_stiffness);
    FIELD(weft_cloth_def, seam_a);
    FIELD(weft_cloth_def, seam_b);
    FIELD(weft_cloth_def, n_seams);
    FIELD(weft_cloth_def, seam_close_time);
    FIELD(weft_cloth_def, self_collision);
    FIELD(weft_cloth_def, self_collision_thickness);
    FIELD(weft_cloth_def, internal_cookie);
    FIELD(weft_cloth_def, newton_forcing);
    struct_end();

    STRUCT(weft_cloth_info);
    FIELD(weft_cloth_info, n_vertices);
    FIELD(weft_cloth_info, n_particles);
    FIELD(weft_cloth_info, n_triangles);
    FIELD(weft_cloth_info, n_springs);
    FIELD(weft_cloth_info, n_attachments);
    FIELD(weft_cloth_info, n_pinned_particles);
    FIELD(weft_cloth_info, n_colliders);
    FIELD(weft_cloth_info, total_mass);
    FIELD(weft_cloth_info, bbox_min);
    FIELD(weft_cloth_info, bbox_max);
    FIELD(weft_cloth_info, snapshot_size);
    FIELD(weft_cloth_info, backend);
    FIELD(weft_cloth_info, preconditioner);
    FIELD(weft_cloth_info, integrator);
    FIELD(weft_cloth_info, newton_iterations);
    FIELD(weft_cloth_info, line_search);
    FIELD(weft_cloth_info, n_seams);
    FIELD(weft_cloth_info, n_panels);
    FIELD(weft_cloth_info, self_collision);
    FIELD(weft_cloth_info, self_collision_thickness);
    FIELD(weft_cloth_info, newton_forcing);
    FIELD(weft_cloth_info, tolerance);
    FIELD(weft_cloth_info, threads);
    FIELD(weft_cloth_info, backend_reason);
    struct_end();

    STRUCT(weft_frame);
    FIELD(weft_frame, dt);
    FIELD(weft_frame, object_transform);
    FIELD(weft_frame, attachment_transforms);
    FIELD(weft_frame, collider_transforms);
    FIELD(weft_frame, wind);
    FIELD(weft_frame, flags);
    FIELD(weft_frame, mesh_collider_transforms);
    struct_end();

    STRUCT(weft_frame_stats);
    FIELD(weft_frame_stats, ms_total);
    FIELD(weft_frame_stats, ms_forces);
    FIELD(weft_frame_stats, ms_assemble);
    FIELD(weft_frame_stats, ms_solve);
    FIELD(weft_frame_stats, ms_collide);
    FIELD(weft_frame_stats, ms_integrate);
    FIELD(weft_frame_stats, substeps);
    FIELD(weft_frame_stats, iterations);
    FIELD(weft_frame_stats, solves);
    FIELD(weft_frame_stats, ms_precond);
    FIELD(weft_frame_stats, max_iterations);
    FIELD(weft_frame_stats, residual);
    FIELD(weft_frame_stats, not_converged);
    FIELD(weft_frame_stats, solver);
    FIELD(weft_frame_stats, rollbacks);
    FIELD(weft_frame_stats, halvings);
    FIELD(weft_frame_stats, direct_fallbacks);
    FIELD(weft_frame_stats, failures);
    FIELD(weft_frame_stats, contacts);
    FIELD(weft_frame_stats, max_strain);
    FIELD(weft_frame_stats, kinetic_energy);
    FIELD(weft_frame_stats, time);
    FIELD(weft_frame_stats, frame);
    FIELD(weft_frame_stats, asleep);
    FIELD(weft_frame_stats, fell_asleep);
    FIELD(weft_frame_stats, woke);
    FIELD(weft_frame_stats, self_impacts);
    FIELD(weft_frame_stats, self_zones);
    FIELD(weft_frame_stats, self_unresolved);
    FIELD(weft_frame_stats, ms_self_collide);
    FIELD(weft_frame_stats, newton_steps);
    FIELD(weft_frame_stats, line_search_backtracks);
    FIELD(weft_frame_stats, energy_steps);
    FIELD(weft_frame_stats, friction_passes);
    FIELD(weft_frame_stats, bdf2_substeps);
    FIELD(weft_frame_stats, self_proximity);
    FIELD(weft_frame_stats, self_zone_relaxed);
    FIELD(weft_frame_stats, self_pairs);
    FIELD(weft_frame_stats, self_pairs_active);
    FIELD(weft_frame_stats, self_pair_passes);
    FIELD(weft_frame_stats, self_pair_overflow);
    FIELD(weft_frame_stats, mesh_pairs);
    FIELD(weft_frame_stats, mesh_pairs_active);
    FIELD(weft_frame_stats, mesh_pair_passes);
    FIELD(weft_frame_stats, mesh_pair_overflow);
    FIELD(weft_frame_stats, mesh_pair_skipped);
    struct_end();

    STRUCT(weft_collision_check);
    FIELD(weft_collision_check, self_intersections);
    FIELD(weft_collision_check, max_penetration);
    struct_end();

    STRUCT(weft_cloth_energy);
    FIELD(weft_cloth_energy, kinetic);
    FIELD(weft_cloth_energy, elastic);
    FIELD(weft_cloth_energy, gravity);
    FIELD(weft_cloth_energy, mass);
    FIELD(weft_cloth_energy, center_of_mass);
    struct_end();

    STRUCT(weft_import_report);
    FIELD(weft_import_report, source_vertices);
    FIELD(weft_import_report, unused_vertices);
    FIELD(weft_import_report, welded_vertices);
    FIELD(weft_import_report, particles);
    FIELD(weft_import_report, polygons);
    FIELD(weft_import_report, triangles);
    FIELD(weft_import_report, degenerate_triangles);
    FIELD(weft_import_report, duplicate_faces);
    FIELD(weft_import_report, flipped_faces);
    FIELD(weft_import_report, non_orientable_components);
    FIELD(weft_import_report, edges);
    FIELD(weft_import_report, boundary_edges);
    FIELD(weft_import_report, non_manifold_edges);
    FIELD(weft_import_report, boundary_loops);
    FIELD(weft_import_report, components);
    FIELD(weft_import_report, springs);
    FIELD(weft_import_report, seams);
    FIELD(weft_import_report, panels);
    FIELD(weft_import_report, bbox_min);
    FIELD(weft_import_report, bbox_max);
    FIELD(weft_import_report, unit_scale);
    FIELD(weft_import_report, weld_distance);
    FIELD(weft_import_report, ms_weld);
    FIELD(weft_import_report, ms_triangulate);
    FIELD(weft_import_report, ms_clean);
    FIELD(weft_import_report, ms_orient);
    FIELD(weft_import_report, ms_topology);
    FIELD(weft_import_report, ms_springs);
    FIELD(weft_import_report, ms_pattern);
    FIELD(weft_import_report, ms_total);
    FIELD(weft_import_report, n_warnings);
    FIELD(weft_import_report, warnings_dropped);
    FIELD(weft_import_report, warnings);
    struct_end();

    STRUCT(weft_mesh_data);
    FIELD(weft_mesh_data, n_vertices);
    FIELD(weft_mesh_data, n_faces);
    FIELD(weft_mesh_data, positions);
    FIELD(weft_mesh_data, face_sizes);
    FIELD(weft_mesh_data, indices);
    FIELD(weft_mesh_data, unit_scale);
    struct_end();

    STRUCT(weft_render_def);
    FIELD(weft_render_def, width);
    FIELD(weft_render_def, height);
    FIELD(weft_render_def, eye);
    FIELD(weft_render_def, target);
    FIELD(weft_render_def, up);
    FIELD(weft_render_def, fov_y_deg);
    FIELD(weft_render_def, draw_colliders);
    FIELD(weft_render_def, png_path);
    FIELD(weft_render_def, rgba);
    FIELD(weft_render_def, internal_cookie);
    struct_end();
}

#define ENUM_SIZE(T) entry(#T, (long long)sizeof(T))
#define CONSTANT(c) entry(#c, (long long)(c))
#define STATUS_CONSTANT_(name, value, msg) CONSTANT(name);

int main(void) {
    printf("{\n  \"structs\": {");
    dump_structs();
    printf("\n  },\n  \"enums\": {");
    first_entry = 1;
    ENUM_SIZE(weft_status);
    ENUM_SIZE(weft_log_level);
    ENUM_SIZE(weft_backend);
    ENUM_SIZE(weft_gl_mode);
    ENUM_SIZE(weft_spring_type);
    ENUM_SIZE(weft_solver);
    ENUM_SIZE(weft_collider_type);
    ENUM_SIZE(weft_space);
    printf("\n  },\n  \"constants\": {");
    first_entry = 1;
    CONSTANT(WEFT_ABI);
    CONSTANT(WEFT_VERSION_MAJOR);
    CONSTANT(WEFT_VERSION_MINOR);
    CONSTANT(WEFT_VERSION_PATCH);
    WEFT_STATUS_LIST(STATUS_CONSTANT_)
    CONSTANT(WEFT_LOG_DEBUG);
    CONSTANT(WEFT_LOG_INFO);
    CONSTANT(WEFT_LOG_WARN);
    CONSTANT(WEFT_LOG_ERROR);
    CONSTANT(WEFT_BACKEND_AUTO);
    CONSTANT(WEFT_BACKEND_CPU);
    CONSTANT(WEFT_BACKEND_GPU);
    CONSTANT(WEFT_GL_HEADLESS);
    CONSTANT(WEFT_GL_HOST_CURRENT);
    CONSTANT(WEFT_SPRING_STRETCH);
    CONSTANT(WEFT_SPRING_SHEAR);
    CONSTANT(WEFT_SPRING_BEND);
    CONSTANT(WEFT_SOLVER_PCG);
    CONSTANT(WEFT_SOLVER_JACOBI);
    CONSTANT(WEFT_SOLVER_CHEBYSHEV);
    CONSTANT(WEFT_SOLVER_DIRECT);
    CONSTANT(WEFT_PRECOND_DEFAULT);
    CONSTANT(WEFT_PRECOND_BLOCK_JACOBI);
    CONSTANT(WEFT_PRECOND_AMG);
    CONSTANT(WEFT_PRECOND_IC0);
    CONSTANT(WEFT_INTEGRATOR_DEFAULT);
    CONSTANT(WEFT_INTEGRATOR_BACKWARD_EULER);
    CONSTANT(WEFT_INTEGRATOR_BDF2);
    CONSTANT(WEFT_INTEGRATOR_TRBDF2);
    CONSTANT(WEFT_COLLIDER_PLANE);
    CONSTANT(WEFT_COLLIDER_SPHERE);
    CONSTANT(WEFT_COLLIDER_CAPSULE);
    CONSTANT(WEFT_SPACE_WORLD);
    CONSTANT(WEFT_SPACE_OBJECT);
    CONSTANT(WEFT_FRAME_TELEPORT);
    CONSTANT(WEFT_FRAME_RESET);
    CONSTANT(WEFT_REPORT_POLYGON_SIDES);
    CONSTANT(WEFT_REPORT_MAX_WARNINGS);
    CONSTANT(WEFT_REPORT_WARNING_LENGTH);
    CONSTANT(WEFT_BACKEND_REASON_LENGTH);
    printf("\n  }\n}\n");
    return 0;
}
