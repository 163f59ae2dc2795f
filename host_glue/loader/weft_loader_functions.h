/* The list of every exported function of weft/weft.h, as an X-macro: X(return type, name,
 * (parameters)). weft_loader.h expands it into the weft_api table and weft_loader.c checks each
 * signature against weft.h at compile time; tests/test_loader.c checks that every WEFT_API
 * declaration of weft.h is listed. Stand-alone (no includes, names only until expanded), so a
 * file can list the names without weft.h's types. */
#ifndef WEFT_LOADER_FUNCTIONS_H
#define WEFT_LOADER_FUNCTIONS_H

#define WEFT_LOADER_FUNCTIONS(X)                                                                   \
    X(weft_version_info, weft_version, (void))                                                     \
    X(const char*, weft_status_string, (weft_status status))                                       \
    X(weft_context_def, weft_default_context_def, (void))                                          \
    X(weft_status, weft_context_create, (int abi, const weft_context_def* def,                     \
                                         weft_context** out))                                      \
    X(void, weft_context_destroy, (weft_context* ctx))                                             \
    X(const char*, weft_context_last_error, (const weft_context* ctx))                             \
    X(weft_status, weft_context_last_status, (const weft_context* ctx))                            \
    X(weft_backend, weft_context_backend, (const weft_context* ctx))                               \
    X(weft_cloth_def, weft_default_cloth_def, (void))                                              \
    X(weft_attachment_def, weft_default_attachment_def, (void))                                    \
    X(weft_collider_def, weft_default_collider_def, (void))                                        \
    X(weft_mesh_collider_def, weft_default_mesh_collider_def, (void))                              \
    X(weft_status, weft_cloth_create, (weft_context* ctx, const weft_cloth_def* def,               \
                                       weft_cloth* out))                                           \
    X(weft_status, weft_cloth_destroy, (weft_context* ctx, weft_cloth cloth))                      \
    X(weft_status, weft_cloth_set_attachments, (weft_context* ctx, weft_cloth cloth,               \
                                                const weft_attachment_def* attachments, int n))    \
    X(weft_status, weft_cloth_get_info, (weft_context* ctx, weft_cloth cloth,                      \
                                         weft_cloth_info* out))                                    \
    X(weft_status, weft_cloth_check_collisions, (weft_context* ctx, weft_cloth cloth,              \
                                                 weft_collision_check* out))                       \
    X(weft_status, weft_cloth_get_energy, (weft_context* ctx, weft_cloth cloth,                    \
                                           weft_cloth_energy* out))                                \
    X(weft_status, weft_cloth_get_report, (weft_context* ctx, weft_cloth cloth,                    \
                                           weft_import_report* out))                               \
    X(weft_status, weft_mesh_read, (weft_context* ctx, const char* path, const char* select,       \
                                    double unit_scale, weft_mesh_data* out))                       \
    X(void, weft_mesh_free, (weft_context* ctx, weft_mesh_data* mesh))                             \
    X(weft_frame, weft_default_frame, (void))                                                      \
    X(weft_status, weft_cloth_set_mesh_collider_vertices, (weft_context* ctx, weft_cloth cloth,    \
                                                           int index, const float* positions,      \
                                                           int n_vertices))                        \
    X(weft_status, weft_cloth_set_mesh_collider_gl_buffer, (weft_context* ctx, weft_cloth cloth,   \
                                                            int index, unsigned buffer,            \
                                                            size_t offset, size_t stride,          \
                                                            int n_vertices))                       \
    X(weft_status, weft_cloth_step, (weft_context* ctx, weft_cloth cloth, const weft_frame* fr,    \
                                     weft_frame_stats* stats))                                     \
    X(weft_status, weft_context_step, (weft_context* ctx, int n, const weft_cloth* cloths,         \
                                       const weft_frame* frames, weft_frame_stats* stats,          \
                                       weft_status* statuses))                                     \
    X(weft_status, weft_cloth_get_vertices, (weft_context* ctx, weft_cloth cloth,                  \
                                             weft_space space, float* positions, float* normals,   \
                                             int capacity, int* count))                            \
    X(weft_status, weft_cloth_get_triangles, (weft_context* ctx, weft_cloth cloth,                 \
                                              int* indices, int capacity, int* count))             \
    X(weft_status, weft_cloth_write_gl_buffers, (weft_context* ctx, weft_cloth cloth,              \
                                                 weft_space space, unsigned position_buffer,       \
                                                 size_t position_offset, unsigned normal_buffer,   \
                                                 size_t normal_offset))                            \
    X(weft_status, weft_cloth_save, (weft_context* ctx, weft_cloth cloth, void* buf,               \
                                     size_t size))                                                 \
    X(weft_status, weft_cloth_restore, (weft_context* ctx, weft_cloth cloth, const void* buf,      \
                                        size_t size))                                              \
    X(weft_render_def, weft_default_render_def, (void))                                            \
    X(weft_status, weft_render, (weft_context* ctx, weft_cloth cloth,                              \
                                 const weft_render_def* def))

#endif
