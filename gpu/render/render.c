/* Preview renderer: validation, scene framing, drawing and read-back. */
#include "render.h"

#include <GL/glew.h>
#include <limits.h>
#include <math.h>
#include <stdint.h>
#include <string.h>

#include "camera.h"
#include "gl_state.h"
#include "gpu_error.h"
#include "render_program.h"
#include "render_shapes.h"
#include "render_target.h"

#define WG_ROUND_SLICES 48      /* around a sphere or capsule */
#define WG_ROUND_STACKS 12      /* rings per hemisphere */
#define WG_DEFAULT_SAMPLES 4

struct wg_renderer {
    wg_gl_context* ctx;
    int samples_wanted;         /* after clamping to the driver's maximum */
    int samples_used;
    GLint max_renderbuffer_size, max_viewport[2];
    wg_programs prog;
    wg_target target;
    GLuint vao;
    GLuint pos_vbo, nrm_vbo, ibo;           /* streamed cloth meshes */
    GLuint sphere_vbo, sphere_ibo;          /* unit sphere, static */
    GLsizei sphere_n_indices;
    GLuint shape_vbo, shape_ibo;            /* streamed capsules and planes */
    void* scratch;              /* normals, capsule tessellation, read-back */
    size_t scratch_cap;
};

static const float kIdentity4[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
static const float kIdentity3[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};

/* ---- scratch memory ---- */

static wc_status ensure_scratch(wg_renderer* r, size_t bytes, char* err, size_t err_len) {
    if (bytes <= r->scratch_cap) return WC_OK;
    void* p = wg_gl_alloc(r->ctx, bytes);
    if (!p) {
        wg_errorf(err, err_len, "wg_render: out of memory (%zu bytes of scratch)", bytes);
        return WC_ERROR_OUT_OF_MEMORY;
    }
    wg_gl_free(r->ctx, r->scratch);
    r->scratch = p;
    r->scratch_cap = bytes;
    return WC_OK;
}

/* ---- create / destroy ---- */

static void delete_gl_objects(wg_renderer* r) {
    wg_programs_destroy(&r->prog);
    wg_target_destroy(&r->target);
    GLuint buffers[7] = {r->pos_vbo, r->nrm_vbo, r->ibo, r->sphere_vbo, r->sphere_ibo,
                         r->shape_vbo, r->shape_ibo};
    glDeleteBuffers(7, buffers);
    if (r->vao) glDeleteVertexArrays(1, &r->vao);
    r->vao = r->pos_vbo = r->nrm_vbo = r->ibo = r->sphere_vbo = r->sphere_ibo = 0;
    r->shape_vbo = r->shape_ibo = 0;
}

static wc_status create_gl_objects(wg_renderer* r, int samples, char* err, size_t err_len) {
    wc_status st = wg_programs_create(&r->prog, err, err_len);
    if (st != WC_OK) return st;
    /* Our VAO is bound before any element buffer, so a host's VAO never records ours. */
    glGenVertexArrays(1, &r->vao);
    glBindVertexArray(r->vao);
    GLuint buffers[7];
    glGenBuffers(7, buffers);
    r->pos_vbo = buffers[0];
    r->nrm_vbo = buffers[1];
    r->ibo = buffers[2];
    r->sphere_vbo = buffers[3];
    r->sphere_ibo = buffers[4];
    r->shape_vbo = buffers[5];
    r->shape_ibo = buffers[6];

    int nv = 0, ni = 0;
    wg_capsule_counts(WG_ROUND_SLICES, WG_ROUND_STACKS, &nv, &ni);
    size_t vbytes = (size_t)nv * WG_VERTEX_FLOATS * sizeof(float);
    size_t ibytes = (size_t)ni * sizeof(unsigned);
    st = ensure_scratch(r, vbytes + ibytes, err, err_len);
    if (st != WC_OK) return st;
    float* v = (float*)r->scratch;
    unsigned* idx = (unsigned*)((char*)r->scratch + vbytes);
    wg_capsule_build(1.0f, 0.0f, WG_ROUND_SLICES, WG_ROUND_STACKS, v, idx);
    glBindBuffer(GL_ARRAY_BUFFER, r->sphere_vbo);
    glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)vbytes, v, GL_STATIC_DRAW);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, r->sphere_ibo);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER, (GLsizeiptr)ibytes, idx, GL_STATIC_DRAW);
    r->sphere_n_indices = (GLsizei)ni;
    glBindVertexArray(0);
    glBindBuffer(GL_ARRAY_BUFFER, 0);

    GLint max_samples = 1;
    glGetIntegerv(GL_MAX_SAMPLES, &max_samples);
    glGetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &r->max_renderbuffer_size);
    glGetIntegerv(GL_MAX_VIEWPORT_DIMS, r->max_viewport);
    if (max_samples < 1) max_samples = 1;
    if (samples == 0) samples = WG_DEFAULT_SAMPLES;
    r->samples_wanted = samples < max_samples ? samples : max_samples;

    GLenum e = glGetError();
    if (e != GL_NO_ERROR) {
        wg_errorf(err, err_len, "wg_renderer_create: %s (0x%04x) while creating buffers",
                  wg_gl_error_name(e), (unsigned)e);
        return WC_ERROR_GPU;
    }
    return WC_OK;
}

wc_status wg_renderer_create(wg_gl_context* ctx, const wg_renderer_desc* desc, wg_renderer** out,
                               char* err, size_t err_len) {
    wg_errorf(err, err_len, "%s", "");
    if (!out || !ctx) {
        wg_errorf(err, err_len, "wg_renderer_create: %s is NULL", out ? "ctx" : "out");
        return WC_ERROR_INVALID_ARGUMENT;
    }
    *out = NULL;
    int samples = desc ? desc->samples : 0;
    if (samples < 0 || samples > 64) {
        wg_errorf(err, err_len, "wg_renderer_create: samples = %d must be in 0..64", samples);
        return WC_ERROR_INVALID_ARGUMENT;
    }
    wg_renderer* r = (wg_renderer*)wg_gl_alloc(ctx, sizeof *r);
    if (!r) {
        wg_errorf(err, err_len, "wg_renderer_create: out of memory");
        return WC_ERROR_OUT_OF_MEMORY;
    }
    memset(r, 0, sizeof *r);
    r->ctx = ctx;
    wc_status st = wg_gl_begin(ctx, err, err_len);
    if (st != WC_OK) {
        wg_gl_free(ctx, r);
        return st;
    }
    st = create_gl_objects(r, samples, err, err_len);
    if (st != WC_OK) delete_gl_objects(r);
    wg_gl_end(ctx);
    if (st != WC_OK) {
        wg_gl_free(ctx, r->scratch);
        wg_gl_free(ctx, r);
        return st;
    }
    *out = r;
    return WC_OK;
}

void wg_renderer_destroy(wg_renderer* r) {
    if (!r) return;
    char err[256];
    if (wg_gl_begin(r->ctx, err, sizeof err) == WC_OK) {
        delete_gl_objects(r);
        wg_gl_end(r->ctx);
    } else {
        wg_gl_log(r->ctx, WC_LOG_WARN, "weft gpu: renderer's GL objects not deleted: %s", err);
    }
    wg_gl_free(r->ctx, r->scratch);
    wg_gl_free(r->ctx, r);
}

int wg_renderer_samples(const wg_renderer* r) {
    return r ? r->samples_used : 0;
}

/* ---- validation ---- */

static int finite_n(const float* v, size_t n) {
    for (size_t i = 0; i < n; ++i)
        if (!isfinite(v[i])) return 0;
    return 1;
}

static wc_status validate_meshes(const wg_mesh* meshes, int n_meshes, char* err, size_t err_len) {
    if (n_meshes < 0 || (n_meshes > 0 && !meshes)) {
        wg_errorf(err, err_len, "n_meshes = %d with meshes %s", n_meshes,
                  meshes ? "given" : "NULL");
        return WC_ERROR_INVALID_ARGUMENT;
    }
    for (int k = 0; k < n_meshes; ++k) {
        const wg_mesh* m = &meshes[k];
        if (m->n_vertices < 0 || m->n_triangles < 0 || m->n_vertices > INT_MAX / 3 ||
            m->n_triangles > INT_MAX / 3) {
            wg_errorf(err, err_len, "meshes[%d]: n_vertices = %d / n_triangles = %d out of range",
                      k, m->n_vertices, m->n_triangles);
            return WC_ERROR_INVALID_ARGUMENT;
        }
        if ((m->n_vertices > 0 && !m->positions) || (m->n_triangles > 0 && !m->triangles)) {
            wg_errorf(err, err_len, "meshes[%d]: %s is NULL", k,
                      m->n_vertices > 0 && !m->positions ? "positions" : "triangles");
            return WC_ERROR_INVALID_ARGUMENT;
        }
        for (int i = 0; i < 3 * m->n_triangles; ++i) {
            int v = m->triangles[i];
            if (v < 0 || v >= m->n_vertices) {
                wg_errorf(err, err_len,
                          "meshes[%d].triangles[%d] = %d is outside the %d vertices", k, i, v,
                          m->n_vertices);
                return WC_ERROR_OUT_OF_RANGE;
            }
        }
        size_t n3 = 3 * (size_t)m->n_vertices;
        for (size_t i = 0; i < n3; ++i)
            if (!isfinite(m->positions[i])) {
                wg_errorf(err, err_len, "meshes[%d].positions[%zu] is not finite", k, i);
                return WC_ERROR_NONFINITE;
            }
        if (m->normals && !finite_n(m->normals, n3)) {
            wg_errorf(err, err_len, "meshes[%d].normals has a non-finite value", k);
            return WC_ERROR_NONFINITE;
        }
        if (!finite_n(m->front_rgb, 3) || !finite_n(m->back_rgb, 3)) {
            wg_errorf(err, err_len, "meshes[%d]: front_rgb or back_rgb is not finite", k);
            return WC_ERROR_NONFINITE;
        }
    }
    return WC_OK;
}

static wc_status validate_shapes(const wg_shape* shapes, int n_shapes, char* err,
                                   size_t err_len) {
    if (n_shapes < 0 || (n_shapes > 0 && !shapes)) {
        wg_errorf(err, err_len, "n_shapes = %d with shapes %s", n_shapes,
                  shapes ? "given" : "NULL");
        return WC_ERROR_INVALID_ARGUMENT;
    }
    for (int k = 0; k < n_shapes; ++k) {
        const wg_shape* s = &shapes[k];
        if (s->type != WG_SHAPE_PLANE && s->type != WG_SHAPE_SPHERE &&
            s->type != WG_SHAPE_CAPSULE) {
            wg_errorf(err, err_len,
                      "shapes[%d].type = %d is not plane (0), sphere (1) or capsule (2)", k,
                      (int)s->type);
            return WC_ERROR_INVALID_ARGUMENT;
        }
        if (!finite_n(s->transform, 16) || !isfinite(s->radius) || !isfinite(s->half_height) ||
            !finite_n(s->rgb, 3)) {
            wg_errorf(err, err_len,
                      "shapes[%d]: transform, radius, half_height or rgb is not finite", k);
            return WC_ERROR_NONFINITE;
        }
        const float* m = s->transform;
        float nm[9];
        if (fabsf(m[3]) > 1e-6f || fabsf(m[7]) > 1e-6f || fabsf(m[11]) > 1e-6f ||
            fabsf(m[15] - 1.0f) > 1e-6f) {
            wg_errorf(err, err_len, "shapes[%d].transform: last row (%g %g %g %g) is not (0 0 0 1)",
                      k, (double)m[3], (double)m[7], (double)m[11], (double)m[15]);
            return WC_ERROR_INVALID_ARGUMENT;
        }
        if (!wg_normal_matrix(m, nm)) {
            wg_errorf(err, err_len, "shapes[%d].transform is singular", k);
            return WC_ERROR_INVALID_ARGUMENT;
        }
        if (s->type != WG_SHAPE_PLANE && !(s->radius > 0.0f)) {
            wg_errorf(err, err_len, "shapes[%d].radius = %g must be > 0", k, (double)s->radius);
            return WC_ERROR_INVALID_ARGUMENT;
        }
        if (s->type == WG_SHAPE_CAPSULE && !(s->half_height >= 0.0f)) {
            wg_errorf(err, err_len, "shapes[%d].half_height = %g must be >= 0", k,
                      (double)s->half_height);
            return WC_ERROR_INVALID_ARGUMENT;
        }
    }
    return WC_OK;
}

/* ---- scene layout ---- */

/* Where each plane's square goes, and the depth range of everything. */
typedef struct wg_layout {
    float center[3];            /* of the bounded geometry (or a fallback) */
    float radius;               /* its bounding radius (> 0) */
    float bmin[3], bmax[3];     /* everything, plane squares included */
} wg_layout;

static void grow_box(float bmin[3], float bmax[3], const float p[3]) {
    for (int i = 0; i < 3; ++i) {
        if (p[i] < bmin[i]) bmin[i] = p[i];
        if (p[i] > bmax[i]) bmax[i] = p[i];
    }
}

/* The square of a plane: local centre (cx, cz), half-size and checker cell. */
static void plane_square(const wg_shape* s, const wg_layout* L, float* cx, float* cz, float* half,
                         float* cell) {
    float nm[9];
    wg_normal_matrix(s->transform, nm); /* validated: invertible */
    /* local = A^-1 (c - t), with A^-1 = N^T where N = A^-T is nm (column-major) */
    float d[3];
    for (int i = 0; i < 3; ++i) d[i] = L->center[i] - s->transform[12 + i];
    float local[3];
    for (int r = 0; r < 3; ++r)
        local[r] = nm[3 * r + 0] * d[0] + nm[3 * r + 1] * d[1] + nm[3 * r + 2] * d[2];
    *cx = local[0];
    *cz = local[2];
    *half = 2.5f * L->radius;
    *cell = wg_nice_step(*half / 5.0f);
}

static void layout_scene(const wg_mesh* meshes, int n_meshes, const wg_shape* shapes, int n_shapes,
                         const float fallback[3], wg_layout* L) {
    float bmin[3], bmax[3];
    if (wg_scene_bounds(meshes, n_meshes, shapes, n_shapes, bmin, bmax)) {
        double r2 = 0;
        for (int i = 0; i < 3; ++i) {
            L->center[i] = 0.5f * (bmin[i] + bmax[i]);
            double h = 0.5 * ((double)bmax[i] - (double)bmin[i]);
            r2 += h * h;
        }
        L->radius = (float)sqrt(r2);
        if (!(L->radius > 0.0f)) L->radius = 0.5f;
        for (int i = 0; i < 3; ++i) {
            L->bmin[i] = bmin[i];
            L->bmax[i] = bmax[i];
        }
    } else {
        for (int i = 0; i < 3; ++i) {
            L->center[i] = fallback[i];
            L->bmin[i] = INFINITY;
            L->bmax[i] = -INFINITY;
        }
        L->radius = 0.4f; /* a plane alone: a square of 1 m half-size */
    }
    for (int k = 0; k < n_shapes; ++k) {
        if (shapes[k].type != WG_SHAPE_PLANE) continue;
        float cx, cz, half, cell;
        plane_square(&shapes[k], L, &cx, &cz, &half, &cell);
        for (int c = 0; c < 4; ++c) {
            float local[3] = {cx + (c & 1 ? half : -half), 0.0f, cz + (c & 2 ? half : -half)};
            float world[3];
            wg_transform_point(shapes[k].transform, local, world);
            grow_box(L->bmin, L->bmax, world);
        }
    }
}

/* Near and far distances around the box corners' depths along the view. */
static void depth_range(const wg_camera_basis* b, const wg_layout* L, float* znear, float* zfar) {
    double zmin = INFINITY, zmax = -INFINITY;
    if (L->bmin[0] <= L->bmax[0]) {
        for (int c = 0; c < 8; ++c) {
            double p[3] = {c & 1 ? L->bmax[0] : L->bmin[0], c & 2 ? L->bmax[1] : L->bmin[1],
                           c & 4 ? L->bmax[2] : L->bmin[2]};
            double z = 0;
            for (int i = 0; i < 3; ++i) z += (p[i] - b->eye[i]) * b->f[i];
            if (z < zmin) zmin = z;
            if (z > zmax) zmax = z;
        }
    }
    if (!(zmax > 0)) { /* nothing in front of the camera */
        *znear = 0.1f;
        *zfar = 10.0f;
        return;
    }
    double n = zmin > 0 ? 0.98 * zmin : 0;
    if (n < 1e-3 * zmax) n = 1e-3 * zmax;
    *znear = (float)n;
    *zfar = (float)(1.02 * zmax);
}

/* ---- drawing ---- */

static void normalize3f(float v[3]) {
    float n = sqrtf(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (n > 0) {
        v[0] /= n;
        v[1] /= n;
        v[2] /= n;
    }
}

/* Area-weighted vertex normals (unnormalised sums normalised at the end; unused vertices 0). */
static void mesh_normals(const wg_mesh* m, float* out) {
    memset(out, 0, 3 * (size_t)m->n_vertices * sizeof(float));
    for (int t = 0; t < m->n_triangles; ++t) {
        const int* tri = &m->triangles[3 * t];
        const float* a = &m->positions[3 * tri[0]];
        const float* b = &m->positions[3 * tri[1]];
        const float* c = &m->positions[3 * tri[2]];
        float e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
        float e2[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
        float n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                      e1[0] * e2[1] - e1[1] * e2[0]};
        for (int k = 0; k < 3; ++k)
            for (int i = 0; i < 3; ++i) out[3 * tri[k] + i] += n[i];
    }
    for (int v = 0; v < m->n_vertices; ++v) normalize3f(&out[3 * v]);
}

static void set_material(const wg_renderer* r, const float front[3], const float back[3],
                         float checker) {
    glUniform3fv(r->prog.u_front_rgb, 1, front);
    glUniform3fv(r->prog.u_back_rgb, 1, back);
    glUniform1f(r->prog.u_checker, checker);
}

static void interleaved_attribs(GLuint vbo) {
    glBindBuffer(GL_ARRAY_BUFFER, vbo);
    GLsizei stride = WG_VERTEX_FLOATS * sizeof(float);
    glVertexAttribPointer(WG_ATTRIB_POSITION, 3, GL_FLOAT, GL_FALSE, stride, (const void*)0);
    glVertexAttribPointer(WG_ATTRIB_NORMAL, 3, GL_FLOAT, GL_FALSE, stride,
                          (const void*)(uintptr_t)(3 * sizeof(float)));
}

static void draw_meshes(wg_renderer* r, const wg_mesh* meshes, int n_meshes) {
    glUniformMatrix4fv(r->prog.u_model, 1, GL_FALSE, kIdentity4);
    glUniformMatrix3fv(r->prog.u_normal_matrix, 1, GL_FALSE, kIdentity3);
    for (int k = 0; k < n_meshes; ++k) {
        const wg_mesh* m = &meshes[k];
        if (m->n_triangles == 0) continue;
        GLsizeiptr bytes3 = (GLsizeiptr)(3 * (size_t)m->n_vertices * sizeof(float));
        const float* normals = m->normals;
        if (!normals) {
            mesh_normals(m, (float*)r->scratch);
            normals = (const float*)r->scratch;
        }
        glBindBuffer(GL_ARRAY_BUFFER, r->pos_vbo);
        glBufferData(GL_ARRAY_BUFFER, bytes3, m->positions, GL_STREAM_DRAW);
        glVertexAttribPointer(WG_ATTRIB_POSITION, 3, GL_FLOAT, GL_FALSE, 0, (const void*)0);
        glBindBuffer(GL_ARRAY_BUFFER, r->nrm_vbo);
        glBufferData(GL_ARRAY_BUFFER, bytes3, normals, GL_STREAM_DRAW);
        glVertexAttribPointer(WG_ATTRIB_NORMAL, 3, GL_FLOAT, GL_FALSE, 0, (const void*)0);
        glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, r->ibo);
        glBufferData(GL_ELEMENT_ARRAY_BUFFER,
                     (GLsizeiptr)(3 * (size_t)m->n_triangles * sizeof(int)), m->triangles,
                     GL_STREAM_DRAW);
        set_material(r, m->front_rgb, m->back_rgb, 0.0f);
        glDrawElements(GL_TRIANGLES, 3 * m->n_triangles, GL_UNSIGNED_INT, (const void*)0);
    }
}

static void shape_colours(const wg_shape* s, float front[3], float back[3]) {
    const float shape_default[3] = WG_SHAPE_DEFAULT_RGB;
    const float plane_default[3] = WG_PLANE_DEFAULT_RGB;
    int zero = s->rgb[0] == 0.0f && s->rgb[1] == 0.0f && s->rgb[2] == 0.0f;
    for (int i = 0; i < 3; ++i) {
        float fallback = s->type == WG_SHAPE_PLANE ? plane_default[i] : shape_default[i];
        front[i] = zero ? fallback : s->rgb[i];
        back[i] = 0.5f * front[i];
    }
}

static void draw_shapes(wg_renderer* r, const wg_shape* shapes, int n_shapes, const wg_layout* L) {
    for (int k = 0; k < n_shapes; ++k) {
        const wg_shape* s = &shapes[k];
        float front[3], back[3], nm[9];
        shape_colours(s, front, back);
        wg_normal_matrix(s->transform, nm);
        glUniformMatrix3fv(r->prog.u_normal_matrix, 1, GL_FALSE, nm);
        if (s->type == WG_SHAPE_SPHERE) {
            const float scale[16] = {s->radius, 0, 0, 0, 0, s->radius, 0, 0,
                                     0, 0, s->radius, 0, 0, 0, 0, 1};
            float model[16];
            wg_mat4_mul(model, s->transform, scale);
            glUniformMatrix4fv(r->prog.u_model, 1, GL_FALSE, model);
            set_material(r, front, back, 0.0f);
            interleaved_attribs(r->sphere_vbo);
            glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, r->sphere_ibo);
            glDrawElements(GL_TRIANGLES, r->sphere_n_indices, GL_UNSIGNED_INT, (const void*)0);
            continue;
        }
        int nv = 4, ni = 6;
        float checker = 0.0f;
        if (s->type == WG_SHAPE_CAPSULE)
            wg_capsule_counts(WG_ROUND_SLICES, WG_ROUND_STACKS, &nv, &ni);
        size_t vbytes = (size_t)nv * WG_VERTEX_FLOATS * sizeof(float);
        float* v = (float*)r->scratch;
        unsigned* idx = (unsigned*)((char*)r->scratch + vbytes);
        if (s->type == WG_SHAPE_CAPSULE) {
            wg_capsule_build(s->radius, s->half_height, WG_ROUND_SLICES, WG_ROUND_STACKS, v, idx);
        } else {
            float cx, cz, half;
            plane_square(s, L, &cx, &cz, &half, &checker);
            wg_plane_build(cx, cz, half, v, idx);
            glEnable(GL_POLYGON_OFFSET_FILL);
            glPolygonOffset(1.0f, 4.0f);
        }
        glUniformMatrix4fv(r->prog.u_model, 1, GL_FALSE, s->transform);
        set_material(r, front, back, checker);
        glBindBuffer(GL_ARRAY_BUFFER, r->shape_vbo);
        glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)vbytes, v, GL_STREAM_DRAW);
        interleaved_attribs(r->shape_vbo);
        glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, r->shape_ibo);
        glBufferData(GL_ELEMENT_ARRAY_BUFFER, (GLsizeiptr)((size_t)ni * sizeof(unsigned)), idx,
                     GL_STREAM_DRAW);
        glDrawElements(GL_TRIANGLES, ni, GL_UNSIGNED_INT, (const void*)0);
        glDisable(GL_POLYGON_OFFSET_FILL);
    }
}

static void draw_background(const wg_renderer* r, int height) {
    const float top[3] = WG_SKY_TOP_RGB, bottom[3] = WG_SKY_BOTTOM_RGB;
    glDisable(GL_DEPTH_TEST);
    glDepthMask(GL_FALSE);
    glUseProgram(r->prog.background);
    glUniform3fv(r->prog.u_top_rgb, 1, top);
    glUniform3fv(r->prog.u_bottom_rgb, 1, bottom);
    glUniform1f(r->prog.u_height, (float)height);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glDepthMask(GL_TRUE);
    glEnable(GL_DEPTH_TEST);
}

/* Light directions (toward the lights) in world space, fixed relative to the camera: the key
 * from the upper left, the fill from the lower right, both from the camera's side. */
static void lights(const wg_camera_basis* b, float key[3], float fill[3]) {
    for (int i = 0; i < 3; ++i) {
        key[i] = (float)(-0.5 * b->s[i] + 0.7 * b->u[i] - 0.6 * b->f[i]);
        fill[i] = (float)(0.65 * b->s[i] - 0.2 * b->u[i] - 0.7 * b->f[i]);
    }
    normalize3f(key);
    normalize3f(fill);
}

/* Everything between wg_gl_begin and wg_gl_end; the picture ends up bottom-up in r->scratch. */
static wc_status draw_and_read(wg_renderer* r, const wg_camera* cam, const wg_camera_basis* b,
                                 const float view_proj[16], const wg_mesh* meshes, int n_meshes,
                                 const wg_shape* shapes, int n_shapes, const wg_layout* L,
                                 char* err, size_t err_len) {
    if (wg_gl_context_is_host(r->ctx) && !glIsVertexArray(r->vao)) {
        wg_errorf(err, err_len,
                  "host context: the current GL context is not the one the renderer was "
                  "created in");
        return WC_ERROR_GPU;
    }
    int w = cam->width, h = cam->height;
    if (w > r->max_renderbuffer_size || h > r->max_renderbuffer_size || w > r->max_viewport[0] ||
        h > r->max_viewport[1]) {
        wg_errorf(err, err_len,
                  "picture %d x %d is larger than this driver allows (renderbuffer %d, viewport "
                  "%d x %d)",
                  w, h, (int)r->max_renderbuffer_size, (int)r->max_viewport[0],
                  (int)r->max_viewport[1]);
        return WC_ERROR_GPU;
    }
    wc_status st = wg_target_ensure(&r->target, w, h, r->samples_wanted, err, err_len);
    if (st != WC_OK && r->samples_wanted > 1) {
        wg_gl_log(r->ctx, WC_LOG_WARN, "weft gpu: %s; rendering without MSAA", err);
        st = wg_target_ensure(&r->target, w, h, 1, err, err_len);
    }
    if (st != WC_OK) return st;
    r->samples_used = r->target.samples;

    wg_gl_state_set_defaults(r->target.samples > 1);
    glBindFramebuffer(GL_FRAMEBUFFER, wg_target_draw_fbo(&r->target));
    GLenum draw_buffer = GL_COLOR_ATTACHMENT0;
    glDrawBuffers(1, &draw_buffer);
    glViewport(0, 0, w, h);
    glClearDepth(1.0);
    glClear(GL_DEPTH_BUFFER_BIT);
    glBindVertexArray(r->vao);
    draw_background(r, h);

    float key[3], fill[3], up[3] = {cam->up[0], cam->up[1], cam->up[2]};
    lights(b, key, fill);
    normalize3f(up);
    glUseProgram(r->prog.shade);
    glUniformMatrix4fv(r->prog.u_view_proj, 1, GL_FALSE, view_proj);
    glUniform3fv(r->prog.u_key_dir, 1, key);
    glUniform3fv(r->prog.u_fill_dir, 1, fill);
    glUniform3fv(r->prog.u_up, 1, up);
    glEnableVertexAttribArray(WG_ATTRIB_POSITION);
    glEnableVertexAttribArray(WG_ATTRIB_NORMAL);
    draw_meshes(r, meshes, n_meshes);
    draw_shapes(r, shapes, n_shapes, L);

    wg_target_resolve(&r->target);
    glReadPixels(0, 0, w, h, GL_RGBA, GL_UNSIGNED_BYTE, r->scratch);
    GLenum e = glGetError();
    glBindVertexArray(0);
    if (e != GL_NO_ERROR) {
        wg_errorf(err, err_len, "rendering %d x %d failed: %s (0x%04x)", w, h, wg_gl_error_name(e),
                  (unsigned)e);
        return WC_ERROR_GPU;
    }
    return WC_OK;
}

static size_t scratch_needed(const wg_camera* cam, const wg_mesh* meshes, int n_meshes,
                             int n_shapes) {
    size_t need = 4 * (size_t)cam->width * (size_t)cam->height;
    for (int k = 0; k < n_meshes; ++k) {
        size_t b = 3 * (size_t)meshes[k].n_vertices * sizeof(float);
        if (!meshes[k].normals && b > need) need = b;
    }
    if (n_shapes > 0) {
        int nv, ni;
        wg_capsule_counts(WG_ROUND_SLICES, WG_ROUND_STACKS, &nv, &ni);
        size_t b = (size_t)nv * WG_VERTEX_FLOATS * sizeof(float) + (size_t)ni * sizeof(unsigned);
        if (b > need) need = b;
    }
    return need;
}

wc_status wg_render(wg_renderer* r, const wg_camera* cam_in, const wg_mesh* meshes, int n_meshes,
                      const wg_shape* shapes, int n_shapes, unsigned char* rgba_out, char* err,
                      size_t err_len) {
    wg_errorf(err, err_len, "%s", "");
    if (!r || !cam_in || !rgba_out) {
        wg_errorf(err, err_len, "wg_render: %s is NULL",
                  !r ? "renderer" : !cam_in ? "camera" : "rgba_out");
        return WC_ERROR_INVALID_ARGUMENT;
    }
    wg_camera cam = *cam_in;
    wc_status st = wg_camera_check_lens(&cam, err, err_len);
    if (st == WC_OK) st = validate_meshes(meshes, n_meshes, err, err_len);
    if (st == WC_OK) st = validate_shapes(shapes, n_shapes, err, err_len);
    if (st != WC_OK) return st;
    for (int i = 0; i < 3; ++i)
        if (!isfinite(cam.eye[i]) || !isfinite(cam.target[i])) {
            wg_errorf(err, err_len, "camera eye (%g %g %g) or target (%g %g %g) is not finite",
                      (double)cam.eye[0], (double)cam.eye[1], (double)cam.eye[2],
                      (double)cam.target[0], (double)cam.target[1], (double)cam.target[2]);
            return WC_ERROR_NONFINITE;
        }

    const float* fallback = cam.target;
    for (int k = 0; k < n_shapes; ++k)
        if (shapes[k].type == WG_SHAPE_PLANE) {
            fallback = &shapes[k].transform[12];
            break;
        }
    wg_layout L;
    layout_scene(meshes, n_meshes, shapes, n_shapes, fallback, &L);
    if (cam.eye[0] == cam.target[0] && cam.eye[1] == cam.target[1] && cam.eye[2] == cam.target[2]) {
        float bmin[3], bmax[3];
        if (!wg_scene_bounds(meshes, n_meshes, shapes, n_shapes, bmin, bmax))
            for (int i = 0; i < 3; ++i) {
                bmin[i] = fallback[i] - 0.5f;
                bmax[i] = fallback[i] + 0.5f;
            }
        st = wg_camera_frame_auto(&cam, bmin, bmax, err, err_len);
        if (st != WC_OK) return st;
    }
    wg_camera_basis b;
    st = wg_camera_basis_of(&cam, &b, err, err_len);
    if (st != WC_OK) return st;
    float znear, zfar, view[16], proj[16], view_proj[16];
    depth_range(&b, &L, &znear, &zfar);
    st = wg_camera_matrices(&cam, znear, zfar, view, proj, err, err_len);
    if (st != WC_OK) return st;
    wg_mat4_mul(view_proj, proj, view);

    st = ensure_scratch(r, scratch_needed(&cam, meshes, n_meshes, n_shapes), err, err_len);
    if (st != WC_OK) return st;
    st = wg_gl_begin(r->ctx, err, err_len);
    if (st != WC_OK) return st;
    st = draw_and_read(r, &cam, &b, view_proj, meshes, n_meshes, shapes, n_shapes, &L, err,
                       err_len);
    wg_gl_end(r->ctx);
    if (st != WC_OK) return st;

    /* GL rows run bottom-up; ours top-down. */
    size_t row = 4 * (size_t)cam.width;
    const unsigned char* src = (const unsigned char*)r->scratch;
    for (int y = 0; y < cam.height; ++y)
        memcpy(rgba_out + (size_t)y * row, src + (size_t)(cam.height - 1 - y) * row, row);
    return WC_OK;
}
