/* Misuse of the public API, as a table: every bad call must return its documented status, leave a
 * last-error message naming the argument or field, reach the logger once at ERROR level, and
 * change nothing: the cloth's snapshot and its vertices/normals are compared byte for byte before
 * and after, and every caller buffer handed to the failing call still holds its sentinel bytes.
 * Context creation errors (no context to hold them) go to the def's logger. */
#include <stdint.h>
#include <stdio.h>
#include "api_grid.h"
#include "check.h"

#define N 6

typedef struct fx {
    weft_context* ctx;
    weft_context* other_ctx;
    weft_cloth cloth, foreign, stale, victim_other_model;
    ag_mesh mesh;                   /* N x N horizontal grid plus one vertex used by no polygon */
    int nv;
    int a0[2], a1[1];
    weft_attachment_def att[2];
    weft_collider_def col;
    weft_cloth_def def;
    ag_log log;
    size_t snap_size;
    unsigned char* snap;            /* a valid snapshot of cloth */
    unsigned char* other_snap;      /* a valid snapshot of a cloth of another model */
    /* caller buffers handed to failing calls (sentinel-filled) */
    float* pos;
    float* nrm;
    int* tri;
    unsigned char* buf;
    weft_cloth out;
    weft_cloth_info info;
    char path_missing[512], path_garbage[512], path_obj[512];
} fx;

#define SENTINEL 0x7f

static void fill_sentinels(fx* f) {
    memset(f->pos, SENTINEL, sizeof(float) * 3 * (size_t)f->nv);
    memset(f->nrm, SENTINEL, sizeof(float) * 3 * (size_t)f->nv);
    memset(f->tri, SENTINEL, sizeof(int) * 3 * 4 * (size_t)f->nv);
    memset(f->buf, SENTINEL, f->snap_size + 64);
    memset(&f->info, SENTINEL, sizeof f->info);
}

static int sentinels_intact(const fx* f) {
    const unsigned char* blocks[5] = {(const unsigned char*)f->pos, (const unsigned char*)f->nrm,
                                      (const unsigned char*)f->tri, f->buf, (const unsigned char*)&f->info};
    size_t sizes[5] = {sizeof(float) * 3 * (size_t)f->nv, sizeof(float) * 3 * (size_t)f->nv,
                       sizeof(int) * 3 * 4 * (size_t)f->nv, f->snap_size + 64, sizeof f->info};
    for (int b = 0; b < 5; ++b)
        for (size_t i = 0; i < sizes[b]; ++i)
            if (blocks[b][i] != SENTINEL) return 0;
    return 1;
}

static weft_frame good_frame(void) {
    weft_frame fr = weft_default_frame();
    fr.dt = 1.0 / 60.0;
    return fr;
}

/* ---- the table: (name, expected status, text the message must contain, the call) ------------
 * In each call: f (fixture), d (a copy of the good def, its attachments in att, collider in
 * col), fr (a good frame), m / m2 (float[16] / float[32] scratch transforms), h (a handle),
 * st (the status to report). */
#define E_ARG WEFT_ERROR_INVALID_ARGUMENT
#define E_NF WEFT_ERROR_NONFINITE
#define E_RANGE WEFT_ERROR_OUT_OF_RANGE
#define E_HANDLE WEFT_ERROR_INVALID_HANDLE
#define CREATE st = weft_cloth_create(f->ctx, &d, &f->out);
#define STEP st = weft_cloth_step(f->ctx, f->cloth, &fr, NULL);

#define CASES(X)                                                                                           \
    /* weft_cloth_create */                                                                               \
    X(create_def_null, E_ARG, "def is NULL", st = weft_cloth_create(f->ctx, NULL, &f->out);)              \
    X(create_out_null, E_ARG, "out is NULL", st = weft_cloth_create(f->ctx, &d, NULL);)                   \
    X(create_no_cookie, E_ARG, "weft_default_cloth_def", d.internal_cookie = 0; CREATE)                   \
    X(create_two_sources, E_ARG, "both path and positions", d.mesh.path = "x.obj"; CREATE)                \
    X(create_no_source, E_ARG, "neither path nor positions", d.mesh.positions = NULL; CREATE)             \
    X(create_empty_path, E_ARG, "def->mesh.path is empty", d.mesh.positions = NULL; d.mesh.path = ""; CREATE) \
    X(create_no_vertices, E_ARG, "def->mesh.n_vertices", d.mesh.n_vertices = 0; CREATE)                  \
    X(create_no_face_sizes, E_ARG, "def->mesh.face_sizes is NULL", d.mesh.face_sizes = NULL; CREATE)      \
    X(create_no_indices, E_ARG, "def->mesh.indices is NULL", d.mesh.indices = NULL; CREATE)               \
    X(create_nan_position, E_NF, "def->mesh.positions[7] (vertex 2) is NaN", f->mesh.pos[7] = NAN; CREATE; \
      f->mesh.pos[7] = 0.0f;)                                                                             \
    X(create_index_range, E_RANGE, "def->mesh.indices[5] = 999", int save = f->mesh.idx[5];              \
      f->mesh.idx[5] = 999; CREATE; f->mesh.idx[5] = save;)                                              \
    X(create_negative_index, E_RANGE, "def->mesh.indices[5] = -1", int save = f->mesh.idx[5];            \
      f->mesh.idx[5] = -1; CREATE; f->mesh.idx[5] = save;)                                               \
    X(create_face_size_zero, E_ARG, "def->mesh.face_sizes[2] = 0", f->mesh.sizes[2] = 0; CREATE;          \
      f->mesh.sizes[2] = 4;)                                                                              \
    X(create_unit_scale_zero, E_ARG, "def->unit_scale", d.unit_scale = 0.0; CREATE)                       \
    X(create_unit_scale_nan, E_NF, "def->unit_scale is NaN", d.unit_scale = NAN; CREATE)                  \
    X(create_weld_negative, E_ARG, "def->weld_tolerance", d.weld_tolerance = -1.0; CREATE)                \
    X(create_transform_nan, E_NF, "def->transform[13] is NaN", d.transform[13] = NAN; CREATE)             \
    X(create_transform_scaled, E_ARG, "def->transform is not rigid", d.transform[0] = 2.0f; CREATE)       \
    X(create_transform_sheared, E_ARG, "def->transform is not rigid", d.transform[4] = 0.1f; CREATE)      \
    X(create_transform_mirror, E_ARG, "def->transform is not rigid", d.transform[0] = -1.0f; CREATE)      \
    X(create_transform_row, E_ARG, "def->transform has last row", d.transform[3] = 0.5f; CREATE)          \
    X(create_density_zero, E_ARG, "def->material.density", d.material.density = 0.0; CREATE)              \
    X(create_stiffness_negative, E_ARG, "def->material.stiffness[1]", d.material.stiffness[1] = -1.0; CREATE) \
    X(create_damping_nan, E_NF, "def->material.damping[2] is NaN", d.material.damping[2] = NAN; CREATE)   \
    X(create_gravity_inf, E_NF, "def->gravity[0] is Inf", d.gravity[0] = INFINITY; CREATE)                \
    X(create_wind_nan, E_NF, "def->wind[2] is NaN", d.wind[2] = NAN; CREATE)                              \
    X(create_drag_negative, E_ARG, "def->air_drag_normal", d.air_drag_normal = -0.1; CREATE)              \
    X(create_solver_enum, E_ARG, "def->solver = 9", d.solver = (weft_solver)9; CREATE)                    \
    X(create_tolerance, E_ARG, "def->tolerance", d.tolerance = 1.5; CREATE)                               \
    X(create_iterations, E_ARG, "def->max_iterations", d.max_iterations = 0; CREATE)                      \
    X(create_precond_enum, E_ARG, "def->preconditioner = 7", d.preconditioner = (weft_preconditioner)7; CREATE) \
    X(create_precond_next, E_ARG, "def->preconditioner = 4", d.preconditioner = (weft_preconditioner)4; CREATE) \
    X(create_precond_negative, E_ARG, "def->preconditioner = -1", d.preconditioner = (weft_preconditioner)-1; CREATE) \
    X(create_integrator_enum, E_ARG, "def->integrator = 4", d.integrator = (weft_integrator)4; CREATE)     \
    X(create_newton_negative, E_ARG, "def->newton_iterations = -1", d.newton_iterations = -1; CREATE)       \
    X(create_newton_many, E_ARG, "def->newton_iterations = 101", d.newton_iterations = 101; CREATE)         \
    X(create_line_search, E_ARG, "def->line_search = 2", d.line_search = 2; CREATE)                        \
    X(create_line_search_low, E_ARG, "def->line_search = -2", d.line_search = -2; CREATE)                  \
    X(create_substeps, E_ARG, "def->substeps", d.substeps = 0; CREATE)                                    \
    X(create_frame_time, E_ARG, "def->max_frame_time", d.max_frame_time = 0.0; CREATE)                    \
    X(create_strain_limit, E_ARG, "def->strain_limit", d.strain_limit = -0.1; CREATE)                     \
    X(create_sleep_speed, E_ARG, "def->sleep_speed = -0.001", d.sleep_speed = -1e-3; CREATE)             \
    X(create_sleep_speed_inf, E_NF, "def->sleep_speed is Inf", d.sleep_speed = INFINITY; CREATE)           \
    X(create_sleep_time, E_ARG, "def->sleep_time = -1", d.sleep_time = -1.0; CREATE)                      \
    X(create_sleep_time_nan, E_NF, "def->sleep_time is NaN", d.sleep_time = NAN; CREATE)                  \
    X(create_linear_inertia, E_ARG, "def->linear_inertia", d.linear_inertia = 1.5; CREATE)                \
    X(create_angular_inertia, E_NF, "def->angular_inertia is NaN", d.angular_inertia = NAN; CREATE)       \
    X(create_n_attachments, E_ARG, "def->n_attachments = -1", d.n_attachments = -1; CREATE)               \
    X(create_attachments_null, E_ARG, "def->attachments is NULL", d.attachments = NULL; CREATE)           \
    X(create_attachment_cookie, E_ARG, "def->attachments[1] was not initialised", att[1].internal_cookie = 0; \
      CREATE)                                                                                             \
    X(create_attachment_range, E_RANGE, "def->attachments[0].vertices[1] = 999", int v[2] = {0, 999};   \
      att[0].vertices = v; CREATE)                                                                        \
    X(create_attachment_twice, E_ARG, "already pinned by def->attachments[0]", int v[1] = {N - 1};          \
      att[1].vertices = v; CREATE)                                                                        \
    X(create_attachment_unused, E_ARG, "used by no polygon", int v[1] = {N * N}; att[1].vertices = v; CREATE) \
    X(create_attachment_count, E_ARG, "def->attachments[0].n_vertices = -2", att[0].n_vertices = -2; CREATE) \
    X(create_attachment_axis, E_ARG, "def->attachments[0].free_axis", att[0].free_axis[0] = 0.5f; CREATE) \
    X(create_attachment_bind, E_ARG, "def->attachments[1].bind_transform is not rigid",                   \
      att[1].bind_transform[5] = 3.0f; CREATE)                                                            \
    X(create_colliders_null, E_ARG, "def->colliders is NULL", d.colliders = NULL; CREATE)                 \
    X(create_collider_cookie, E_ARG, "def->colliders[0] was not initialised", col.internal_cookie = 1; CREATE) \
    X(create_collider_type, E_ARG, "def->colliders[0].type = 3", col.type = (weft_collider_type)3; CREATE) \
    X(create_collider_radius, E_ARG, "def->colliders[0].radius", col.radius = 0.0; CREATE)                \
    X(create_collider_friction, E_ARG, "def->colliders[0].friction", col.friction = -1.0; CREATE)         \
    X(create_collider_transform, E_NF, "def->colliders[0].transform[12] is NaN", col.transform[12] = NAN; CREATE) \
    X(create_missing_file, WEFT_ERROR_IO, "def->mesh", d.mesh = (weft_mesh_desc){0};                      \
      d.mesh.path = f->path_missing; d.n_attachments = 0; d.n_colliders = 0; CREATE)                      \
    X(create_garbage_file, WEFT_ERROR_IMPORT, "def->mesh", d.mesh = (weft_mesh_desc){0};                  \
      d.mesh.path = f->path_garbage; d.n_attachments = 0; d.n_colliders = 0; CREATE)                      \
    X(create_file_attachment_range, E_RANGE, "def->attachments[0].vertices[0] = 999 is outside [0, 4)",     \
      d.mesh = (weft_mesh_desc){0}; d.mesh.path = f->path_obj; int v[1] = {999}; att[0].vertices = v;    \
      att[0].n_vertices = 1; d.n_attachments = 1; d.n_colliders = 0; CREATE)                              \
    X(create_only_lines, WEFT_ERROR_EMPTY_MESH, "def->mesh", int sizes[1] = {2}; d.mesh.face_sizes = sizes; \
      d.mesh.n_faces = 1; d.n_attachments = 0; CREATE)                                                    \
    /* handles */                                                                                         \
    X(step_null_handle, E_HANDLE, "null handle", fr = good_frame();                                       \
      st = weft_cloth_step(f->ctx, (weft_cloth){0}, &fr, NULL);)                                          \
    X(step_stale_handle, E_HANDLE, "stale", fr = good_frame(); st = weft_cloth_step(f->ctx, f->stale, &fr, NULL);) \
    X(step_foreign_handle, E_HANDLE, "does not belong to this context", fr = good_frame();                \
      st = weft_cloth_step(f->ctx, f->foreign, &fr, NULL);)                                               \
    X(step_forged_slot, E_HANDLE, "stale", h = f->cloth; h.id += 7; fr = good_frame();                    \
      st = weft_cloth_step(f->ctx, h, &fr, NULL);)                                                        \
    X(step_forged_generation, E_HANDLE, "stale", h = f->cloth; h.id ^= (uint64_t)1 << 30; fr = good_frame(); \
      st = weft_cloth_step(f->ctx, h, &fr, NULL);)                                                        \
    X(step_forged_random, E_HANDLE, "does not belong", h.id = 0x0123456789abcdefull; fr = good_frame();   \
      st = weft_cloth_step(f->ctx, h, &fr, NULL);)                                                        \
    X(destroy_stale, E_HANDLE, "weft_cloth_destroy", st = weft_cloth_destroy(f->ctx, f->stale);)          \
    X(destroy_foreign, E_HANDLE, "weft_cloth_destroy", st = weft_cloth_destroy(f->ctx, f->foreign);)      \
    X(destroy_null, E_HANDLE, "null handle", st = weft_cloth_destroy(f->ctx, (weft_cloth){0});)           \
    X(info_stale, E_HANDLE, "weft_cloth_get_info", st = weft_cloth_get_info(f->ctx, f->stale, &f->info);) \
    X(vertices_stale, E_HANDLE, "weft_cloth_get_vertices", int n;                                         \
      st = weft_cloth_get_vertices(f->ctx, f->stale, WEFT_SPACE_WORLD, f->pos, f->nrm, f->nv, &n);)      \
    X(save_foreign, E_HANDLE, "weft_cloth_save", st = weft_cloth_save(f->ctx, f->foreign, f->buf, f->snap_size);) \
    /* weft_cloth_step */                                                                                 \
    X(step_frame_null, E_ARG, "fr is NULL", st = weft_cloth_step(f->ctx, f->cloth, NULL, NULL);)          \
    X(step_dt_zero, E_ARG, "fr->dt = 0", fr.dt = 0.0; STEP)                                               \
    X(step_dt_negative, E_ARG, "fr->dt = -0.01", fr.dt = -0.01; STEP)                                     \
    X(step_dt_nan, E_NF, "fr->dt is NaN", fr.dt = NAN; STEP)                                              \
    X(step_dt_inf, E_NF, "fr->dt is Inf", fr.dt = INFINITY; STEP)                                         \
    X(step_dt_too_long, E_ARG, "max_frame_time", fr.dt = 0.3; STEP)                                       \
    X(step_flags, E_ARG, "fr->flags 0x5 has unknown bits 0x4", fr.flags = 5; STEP)                        \
    X(step_object_nan, E_NF, "fr->object_transform[3] is NaN", ag_identity(m); m[3] = NAN;                \
      fr.object_transform = m; STEP)                                                                      \
    X(step_object_inf, E_NF, "fr->object_transform[14] is Inf", ag_identity(m); m[14] = INFINITY;         \
      fr.object_transform = m; STEP)                                                                      \
    X(step_object_scaled, E_ARG, "fr->object_transform is not rigid", ag_identity(m); m[10] = 1.01f;      \
      fr.object_transform = m; STEP)                                                                      \
    X(step_object_row, E_ARG, "fr->object_transform has last row", ag_identity(m); m[15] = 2.0f;          \
      fr.object_transform = m; STEP)                                                                      \
    X(step_attachment_nan, E_NF, "fr->attachment_transforms (attachment 1, elements 16..31)[5] is NaN",   \
      ag_identity(m2); ag_identity(m2 + 16); m2[21] = NAN; fr.attachment_transforms = m2; STEP)           \
    X(step_attachment_scaled, E_ARG, "attachment 0", ag_identity(m2); ag_identity(m2 + 16); m2[0] = 0.5f; \
      fr.attachment_transforms = m2; STEP)                                                                \
    X(step_collider_nan, E_NF, "fr->collider_transforms (collider 0, elements 0..15)[13] is NaN",         \
      ag_identity(m); m[13] = NAN; fr.collider_transforms = m; STEP)                                      \
    X(step_collider_sheared, E_ARG, "fr->collider_transforms (collider 0", ag_identity(m); m[1] = 0.2f;   \
      fr.collider_transforms = m; STEP)                                                                   \
    X(step_wind_nan, E_NF, "fr->wind[1] is NaN", double w[3] = {0, NAN, 0}; fr.wind = w; STEP)            \
    X(step_late_bad_after_good, E_ARG, "fr->collider_transforms", ag_identity(m2); ag_identity(m2 + 16);   \
      ag_transform(m2 + 16, 0, 1, 0, 0.3, 0.1, 0.2, 0.0); fr.attachment_transforms = m2;                  \
      ag_identity(m); m[0] = 3.0f; fr.collider_transforms = m; fr.flags = WEFT_FRAME_RESET; STEP)          \
    /* results */                                                                                         \
    X(vertices_space, E_ARG, "space = 5", int n;                                                          \
      st = weft_cloth_get_vertices(f->ctx, f->cloth, (weft_space)5, f->pos, f->nrm, f->nv, &n);)         \
    X(vertices_capacity, E_RANGE, "capacity 3 is below", int n;                                           \
      st = weft_cloth_get_vertices(f->ctx, f->cloth, WEFT_SPACE_WORLD, f->pos, f->nrm, 3, &n);)          \
    X(vertices_negative_capacity, E_RANGE, "capacity -1", int n;                                          \
      st = weft_cloth_get_vertices(f->ctx, f->cloth, WEFT_SPACE_OBJECT, f->pos, NULL, -1, &n);)          \
    X(vertices_alias, E_ARG, "same buffer", int n;                                                        \
      st = weft_cloth_get_vertices(f->ctx, f->cloth, WEFT_SPACE_WORLD, f->pos, f->pos, f->nv, &n);)      \
    X(vertices_query_no_count, E_ARG, "count NULL",                                                       \
      st = weft_cloth_get_vertices(f->ctx, f->cloth, WEFT_SPACE_WORLD, NULL, NULL, 0, NULL);)            \
    X(triangles_capacity, E_RANGE, "capacity 2 is below", int n;                                          \
      st = weft_cloth_get_triangles(f->ctx, f->cloth, f->tri, 2, &n);)                                    \
    X(triangles_query_no_count, E_ARG, "count NULL", st = weft_cloth_get_triangles(f->ctx, f->cloth, NULL, 0, NULL);) \
    X(info_out_null, E_ARG, "out is NULL", st = weft_cloth_get_info(f->ctx, f->cloth, NULL);)             \
    /* snapshots */                                                                                       \
    X(save_buf_null, E_ARG, "buf is NULL", st = weft_cloth_save(f->ctx, f->cloth, NULL, f->snap_size);)   \
    X(save_too_small, E_RANGE, "below the snapshot size", st = weft_cloth_save(f->ctx, f->cloth, f->buf, f->snap_size - 1);) \
    X(restore_buf_null, E_ARG, "buf is NULL", st = weft_cloth_restore(f->ctx, f->cloth, NULL, f->snap_size);) \
    X(restore_tiny, E_ARG, "truncated", st = weft_cloth_restore(f->ctx, f->cloth, f->snap, 10);)          \
    X(restore_truncated, E_ARG, "truncated", st = weft_cloth_restore(f->ctx, f->cloth, f->snap, f->snap_size - 8);) \
    X(restore_bad_magic, E_ARG, "bad magic", f->snap[1] ^= 4; st = weft_cloth_restore(f->ctx, f->cloth, f->snap, f->snap_size); \
      f->snap[1] ^= 4;)                                                                                   \
    X(restore_damaged, E_ARG, "damaged", f->snap[f->snap_size / 2] ^= 1;                                  \
      st = weft_cloth_restore(f->ctx, f->cloth, f->snap, f->snap_size); f->snap[f->snap_size / 2] ^= 1;)  \
    X(restore_other_version, WEFT_ERROR_SNAPSHOT_MISMATCH, "another library version", f->snap[12] ^= 1;   \
      st = weft_cloth_restore(f->ctx, f->cloth, f->snap, f->snap_size); f->snap[12] ^= 1;)               \
    X(restore_other_version_format, WEFT_ERROR_SNAPSHOT_MISMATCH, "(format WEFTSNP3, ABI", f->snap[8] ^= 2;  \
      st = weft_cloth_restore(f->ctx, f->cloth, f->snap, f->snap_size); f->snap[8] ^= 2;)                \
    X(restore_other_model, WEFT_ERROR_SNAPSHOT_MISMATCH, "another model",                                 \
      st = weft_cloth_restore(f->ctx, f->cloth, f->other_snap, f->snap_size + 4096);)                     \
    /* weft_cloth_set_attachments */                                                                      \
    X(attach_negative, E_ARG, "n = -1", st = weft_cloth_set_attachments(f->ctx, f->cloth, att, -1);)      \
    X(attach_null, E_ARG, "attachments is NULL", st = weft_cloth_set_attachments(f->ctx, f->cloth, NULL, 1);) \
    X(attach_cookie, E_ARG, "attachments[0] was not initialised", att[0].internal_cookie = 7;             \
      st = weft_cloth_set_attachments(f->ctx, f->cloth, att, 2);)                                         \
    X(attach_range, E_RANGE, "attachments[1].vertices[0] = 999 is outside", int v[1] = {999};             \
      att[1].vertices = v; st = weft_cloth_set_attachments(f->ctx, f->cloth, att, 2);)                    \
    X(attach_twice, E_ARG, "already pinned by attachments[0]", int v[1] = {0}; att[1].vertices = v;       \
      st = weft_cloth_set_attachments(f->ctx, f->cloth, att, 2);)                                         \
    X(attach_unused, E_ARG, "used by no polygon", int v[1] = {N * N}; att[1].vertices = v;               \
      st = weft_cloth_set_attachments(f->ctx, f->cloth, att, 2);)                                         \
    X(attach_transform, E_NF, "attachments[0].bind_transform[0] is NaN", att[0].bind_transform[0] = NAN;   \
      st = weft_cloth_set_attachments(f->ctx, f->cloth, att, 2);)

enum {
#define X_ENUM(name, status, needle, ...) CASE_##name,
    CASES(X_ENUM)
#undef X_ENUM
    CASE_COUNT
};

static const struct {
    const char* name;
    weft_status expect;
    const char* needle;
} table[] = {
#define X_TABLE(name, status, needle, ...) {#name, status, needle},
    CASES(X_TABLE)
#undef X_TABLE
};

static weft_status run_case(fx* f, int id) {
    weft_status st = WEFT_OK;
    weft_attachment_def att[2] = {f->att[0], f->att[1]};
    weft_collider_def col = f->col;
    weft_cloth_def d = f->def;
    d.attachments = att;
    d.colliders = &col;
    weft_frame fr = good_frame();
    float m[16], m2[32];
    weft_cloth h = {0};
    (void)m;
    (void)m2;
    (void)h;
    switch (id) {
#define X_RUN(name, status, needle, ...) \
    case CASE_##name: {                  \
        __VA_ARGS__                      \
    } break;
        CASES(X_RUN)
#undef X_RUN
    default: break;
    }
    return st;
}

/* ---- fixture ---------------------------------------------------------------------------------- */

static void setup(fx* f) {
    memset(f, 0, sizeof *f);
    weft_context_def cd = weft_default_context_def();
    cd.threads = 1;
    cd.log = ag_log_fn;
    cd.log_user = &f->log;
    CHECK_EQ_INT(weft_context_create(WEFT_ABI, &cd, &f->ctx), WEFT_OK);
    CHECK_EQ_INT(weft_context_create(WEFT_ABI, &cd, &f->other_ctx), WEFT_OK);
    ag_grid(&f->mesh, N, 1.0, 0.5, 0, 0);
    /* one extra vertex that no polygon uses */
    f->nv = N * N + 1;
    f->mesh.pos = realloc(f->mesh.pos, sizeof(float) * 3 * (size_t)f->nv);
    f->mesh.pos[3 * N * N] = 5.0f;
    f->mesh.pos[3 * N * N + 1] = 5.0f;
    f->mesh.pos[3 * N * N + 2] = 5.0f;
    f->mesh.nv = f->nv;
    f->a0[0] = 0;
    f->a0[1] = N - 1;
    f->a1[0] = N * N - 1;
    f->att[0] = weft_default_attachment_def();
    f->att[0].vertices = f->a0;
    f->att[0].n_vertices = 2;
    f->att[1] = weft_default_attachment_def();
    f->att[1].vertices = f->a1;
    f->att[1].n_vertices = 1;
    f->col = weft_default_collider_def();
    f->col.radius = 0.2;
    ag_transform(f->col.transform, 1, 0, 0, 0.0, 0.0, 0.2, 0.0);
    f->def = weft_default_cloth_def();
    f->def.mesh = ag_desc(&f->mesh);
    f->def.n_attachments = 2;
    f->def.attachments = f->att;
    f->def.n_colliders = 1;
    f->def.colliders = &f->col;
    CHECK_EQ_INT(weft_cloth_create(f->ctx, &f->def, &f->cloth), WEFT_OK);
    CHECK_EQ_INT(weft_cloth_create(f->other_ctx, &f->def, &f->foreign), WEFT_OK);
    CHECK_EQ_INT(weft_cloth_create(f->ctx, &f->def, &f->stale), WEFT_OK);
    CHECK_EQ_INT(weft_cloth_destroy(f->ctx, f->stale), WEFT_OK);
    for (int k = 0; k < 8; ++k) {
        weft_frame fr = good_frame();
        CHECK_EQ_INT(weft_cloth_step(f->ctx, f->cloth, &fr, NULL), WEFT_OK);
    }
    weft_cloth_info info;
    CHECK_EQ_INT(weft_cloth_get_info(f->ctx, f->cloth, &info), WEFT_OK);
    f->snap_size = info.snapshot_size;
    f->snap = malloc(f->snap_size);
    CHECK_EQ_INT(weft_cloth_save(f->ctx, f->cloth, f->snap, f->snap_size), WEFT_OK);
    /* a cloth of another model (one attachment fewer) in the other context */
    weft_cloth_def od = f->def;
    od.n_attachments = 1;
    weft_cloth other;
    CHECK_EQ_INT(weft_cloth_create(f->other_ctx, &od, &other), WEFT_OK);
    CHECK_EQ_INT(weft_cloth_get_info(f->other_ctx, other, &info), WEFT_OK);
    f->other_snap = calloc(1, f->snap_size + 4096);
    CHECK(info.snapshot_size <= f->snap_size + 4096);
    CHECK_EQ_INT(weft_cloth_save(f->other_ctx, other, f->other_snap, f->snap_size + 4096), WEFT_OK);
    f->pos = malloc(sizeof(float) * 3 * (size_t)f->nv);
    f->nrm = malloc(sizeof(float) * 3 * (size_t)f->nv);
    f->tri = malloc(sizeof(int) * 3 * 4 * (size_t)f->nv);
    f->buf = malloc(f->snap_size + 64);
    snprintf(f->path_missing, sizeof f->path_missing, "%s/no_such_mesh.obj", WEFT_TEST_TMPDIR);
    snprintf(f->path_garbage, sizeof f->path_garbage, "%s/api_misuse_garbage.obj", WEFT_TEST_TMPDIR);
    snprintf(f->path_obj, sizeof f->path_obj, "%s/api_misuse_quad.obj", WEFT_TEST_TMPDIR);
    FILE* o = fopen(f->path_obj, "w");
    CHECK(o != NULL);
    if (o) {
        fputs("v 0 0 0\nv 1 0 0\nv 1 0 1\nv 0 0 1\nf 1 2 3 4\n", o);
        fclose(o);
    }
    FILE* g = fopen(f->path_garbage, "wb");
    CHECK(g != NULL);
    if (g) {
        for (int i = 0; i < 256; ++i) fputc((i * 37 + 11) & 0xff, g);
        fclose(g);
    }
}

static void teardown(fx* f) {
    weft_context_destroy(f->ctx);
    weft_context_destroy(f->other_ctx);
    ag_free(&f->mesh);
    free(f->snap);
    free(f->other_snap);
    free(f->pos);
    free(f->nrm);
    free(f->tri);
    free(f->buf);
}

/* state as bytes: snapshot + world positions and normals + object positions */
static unsigned char* capture(fx* f, size_t* size) {
    size_t nv3 = sizeof(float) * 3 * (size_t)f->nv;
    *size = f->snap_size + 3 * nv3;
    unsigned char* b = malloc(*size);
    int n;
    CHECK_EQ_INT(weft_cloth_save(f->ctx, f->cloth, b, f->snap_size), WEFT_OK);
    CHECK_EQ_INT(weft_cloth_get_vertices(f->ctx, f->cloth, WEFT_SPACE_WORLD, (float*)(b + f->snap_size),
                                         (float*)(b + f->snap_size + nv3), f->nv, &n), WEFT_OK);
    CHECK_EQ_INT(weft_cloth_get_vertices(f->ctx, f->cloth, WEFT_SPACE_OBJECT, (float*)(b + f->snap_size + 2 * nv3),
                                         NULL, f->nv, &n), WEFT_OK);
    return b;
}

static void test_table(void) {
    fx f;
    setup(&f);
    int failed = 0;
    for (int id = 0; id < CASE_COUNT; ++id) {
        size_t s0, s1;
        unsigned char* before = capture(&f, &s0);
        fill_sentinels(&f);
        f.out.id = 0xdeadbeefull;
        int errors_before = f.log.count[WEFT_LOG_ERROR];
        weft_status st = run_case(&f, id);
        int ok = 1;
        const char* msg = weft_context_last_error(f.ctx);
        if (st != table[id].expect) ok = 0;
        if (weft_context_last_status(f.ctx) != st) ok = 0;
        if (!msg[0] || !strstr(msg, table[id].needle)) ok = 0;
        if (f.log.count[WEFT_LOG_ERROR] != errors_before + 1 || strcmp(f.log.last, msg) != 0) ok = 0;
        if (!sentinels_intact(&f)) ok = 0;
        if (strncmp(table[id].name, "create_", 7) == 0 && id != CASE_create_out_null && f.out.id != 0)
            ok = 0;   /* out is the null handle on failure */
        unsigned char* after = capture(&f, &s1);
        if (s0 != s1 || memcmp(before, after, s0) != 0) ok = 0;
        if (!ok) {
            ++failed;
            fprintf(stderr, "case %s: status %d (want %d), message \"%s\" (want \"%s\")\n", table[id].name, (int)st,
                    (int)table[id].expect, msg, table[id].needle);
        }
        CHECK(ok);
        free(before);
        free(after);
    }
    printf("  %d misuse cases, %d failed\n", CASE_COUNT, failed);
    /* after all that, the cloth still steps normally */
    weft_frame fr = good_frame();
    CHECK_EQ_INT(weft_cloth_step(f.ctx, f.cloth, &fr, NULL), WEFT_OK);
    teardown(&f);
}

/* NULL context: a status, no crash; last_error / status / backend of NULL are defined. */
static void test_null_context(void) {
    weft_frame fr = good_frame();
    weft_cloth h = {1};
    weft_cloth_def d = weft_default_cloth_def();
    int n;
    CHECK_EQ_INT(weft_cloth_create(NULL, &d, &h), WEFT_ERROR_INVALID_ARGUMENT);
    CHECK_EQ_INT(weft_cloth_step(NULL, h, &fr, NULL), WEFT_ERROR_INVALID_ARGUMENT);
    CHECK_EQ_INT(weft_cloth_get_vertices(NULL, h, WEFT_SPACE_WORLD, NULL, NULL, 0, &n), WEFT_ERROR_INVALID_ARGUMENT);
    CHECK_EQ_INT(weft_cloth_get_triangles(NULL, h, NULL, 0, &n), WEFT_ERROR_INVALID_ARGUMENT);
    CHECK_EQ_INT(weft_cloth_get_info(NULL, h, NULL), WEFT_ERROR_INVALID_ARGUMENT);
    CHECK_EQ_INT(weft_cloth_save(NULL, h, NULL, 0), WEFT_ERROR_INVALID_ARGUMENT);
    CHECK_EQ_INT(weft_cloth_restore(NULL, h, NULL, 0), WEFT_ERROR_INVALID_ARGUMENT);
    CHECK_EQ_INT(weft_cloth_destroy(NULL, h), WEFT_ERROR_INVALID_ARGUMENT);
    CHECK_EQ_INT(weft_cloth_set_attachments(NULL, h, NULL, 0), WEFT_ERROR_INVALID_ARGUMENT);
    CHECK(weft_context_last_error(NULL)[0] != '\0');
    CHECK_EQ_INT(weft_context_last_status(NULL), WEFT_ERROR_INVALID_ARGUMENT);
    CHECK_EQ_INT(weft_context_backend(NULL), WEFT_BACKEND_AUTO);
    weft_context_destroy(NULL);
}

/* weft_context_create: each bad def refused, *out NULL, the def's logger told (except where the
 * def cannot be trusted: wrong ABI, no cookie). */
static void test_context_create(void) {
    ag_log log;
    struct {
        const char* name;
        int abi;
        weft_status expect;
        const char* needle; /* NULL: the logger is not called */
    } cases[] = {
        {"abi", WEFT_ABI + 1, WEFT_ERROR_ABI_MISMATCH, NULL},
        {"cookie", WEFT_ABI, WEFT_ERROR_INVALID_ARGUMENT, NULL},
        {"backend", WEFT_ABI, WEFT_ERROR_INVALID_ARGUMENT, "def->backend 7"},
#ifdef WEFT_TEST_HAVE_GPU
        {"gpu", WEFT_ABI, WEFT_ERROR_GPU, "def->backend GPU"},   /* host mode, no current context */
#else
        {"gpu", WEFT_ABI, WEFT_ERROR_UNSUPPORTED, "built without WEFT_GPU"},
#endif
        {"threads", WEFT_ABI, WEFT_ERROR_INVALID_ARGUMENT, "def->threads -1"},
        {"log_level", WEFT_ABI, WEFT_ERROR_INVALID_ARGUMENT, "def->log_level 9"},
        {"gl_mode", WEFT_ABI, WEFT_ERROR_INVALID_ARGUMENT, "def->gl_mode 4"},
        {"allocator", WEFT_ABI, WEFT_ERROR_INVALID_ARGUMENT, "def->allocator"},
        {"out", WEFT_ABI, WEFT_ERROR_INVALID_ARGUMENT, "out is NULL"},
    };
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; ++k) {
        memset(&log, 0, sizeof log);
        weft_context_def cd = weft_default_context_def();
        cd.log = ag_log_fn;
        cd.log_user = &log;
        const char* name = cases[k].name;
        if (!strcmp(name, "cookie")) cd.internal_cookie = 0;
        if (!strcmp(name, "backend")) cd.backend = (weft_backend)7;
        if (!strcmp(name, "gpu")) cd.backend = WEFT_BACKEND_GPU, cd.gl_mode = WEFT_GL_HOST_CURRENT;
        if (!strcmp(name, "threads")) cd.threads = -1;
        if (!strcmp(name, "log_level")) cd.log_level = (weft_log_level)9;
        if (!strcmp(name, "gl_mode")) cd.gl_mode = (weft_gl_mode)4;
        if (!strcmp(name, "allocator")) cd.allocator.alloc = ag_count_alloc;
        weft_context* ctx = (weft_context*)&log;
        weft_status st = weft_context_create(cases[k].abi, &cd, strcmp(name, "out") ? &ctx : NULL);
        int ok = st == cases[k].expect && (!strcmp(name, "out") || ctx == NULL);
        if (cases[k].needle) ok = ok && log.count[WEFT_LOG_ERROR] == 1 && strstr(log.last, cases[k].needle) != NULL;
        else ok = ok && log.count[WEFT_LOG_ERROR] == 0;
        if (!ok) fprintf(stderr, "context case %s: status %d, log \"%s\"\n", name, (int)st, log.last);
        CHECK(ok);
    }
    weft_context* ctx = NULL;
    CHECK_EQ_INT(weft_context_create(WEFT_ABI, NULL, &ctx), WEFT_ERROR_INVALID_ARGUMENT);
    CHECK(ctx == NULL);
    /* AUTO runs a real backend (the CPU on a software rasteriser: test_api_gpu) */
    weft_context_def cd = weft_default_context_def();
    CHECK_EQ_INT(weft_context_create(WEFT_ABI, &cd, &ctx), WEFT_OK);
    CHECK(weft_context_backend(ctx) == WEFT_BACKEND_CPU || weft_context_backend(ctx) == WEFT_BACKEND_GPU);
    CHECK_EQ_INT(weft_context_last_status(ctx), WEFT_OK);
    CHECK(weft_context_last_error(ctx)[0] == '\0');
    weft_context_destroy(ctx);
}

/* A step that fails every recovery (gravity of 1e150 m/s^2: non-finite forces in every retry)
 * reports STEP_FAILED and leaves the cloth exactly as before the call, stats untouched. */
static void test_step_failed_restores(void) {
    fx f;
    setup(&f);
    weft_cloth_def d = f.def;
    d.gravity[1] = -1e150;
    weft_cloth c;
    CHECK_EQ_INT(weft_cloth_create(f.ctx, &d, &c), WEFT_OK);
    weft_cloth keep = f.cloth;
    f.cloth = c;   /* capture() reads f.cloth */
    /* the first frames may still be finite (huge but representable); it fails within a few */
    int failed_at = 0;
    for (int frame = 1; frame <= 10 && !failed_at; ++frame) {
        size_t s0, s1;
        unsigned char* before = capture(&f, &s0);
        weft_frame_stats stats;
        memset(&stats, SENTINEL, sizeof stats);
        int errors_before = f.log.count[WEFT_LOG_ERROR];
        weft_frame fr = good_frame();
        weft_status st = weft_cloth_step(f.ctx, c, &fr, &stats);
        if (st == WEFT_OK) {
            free(before);
            continue;
        }
        failed_at = frame;
        CHECK_EQ_INT(st, WEFT_ERROR_STEP_FAILED);
        CHECK(strstr(weft_context_last_error(f.ctx), "restored to its state before the call") != NULL);
        CHECK_EQ_INT(f.log.count[WEFT_LOG_ERROR], errors_before + 1);
        const unsigned char* sb = (const unsigned char*)&stats;
        int untouched = 1;
        for (size_t i = 0; i < sizeof stats; ++i) untouched = untouched && sb[i] == SENTINEL;
        CHECK(untouched);
        unsigned char* after = capture(&f, &s1);
        CHECK(s0 == s1 && memcmp(before, after, s0) == 0);
        free(before);
        free(after);
    }
    printf("  step failed at frame %d, state restored\n", failed_at);
    CHECK(failed_at > 0);
    f.cloth = keep;
    teardown(&f);
}

int main(void) {
    RUN_TEST(test_table);
    RUN_TEST(test_step_failed_restores);
    RUN_TEST(test_null_context);
    RUN_TEST(test_context_create);
    return TEST_SUMMARY();
}
