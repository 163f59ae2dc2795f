/* What a deforming body costs per frame through weft_cloth_set_mesh_collider_gl_buffer against
 * weft_cloth_set_mesh_collider_vertices: two GPU cloths of one WEFT_GL_HOST_CURRENT context (this
 * program's own EGL context made current, on whatever device EGL gives: llvmpipe without a GPU),
 * an N x N sheet dropped on a UV sphere of k x k slices and stacks (2 k (k - 1) triangles: 100,
 * the default, 19,800) that breathes every frame. The
 * body's floats go to a packed host buffer (glBufferSubData, then glFinish: the host's own work is
 * not timed) and to the array call; each call and each cloth's step is timed with the wall
 * clock, medians over the frames. Beside them, the CPU work the array call's body needs on the
 * host every substep: core's wc_mesh_collider_substep (interpolation, velocities, normals, the
 * BVH's refit) on the same body, and the bytes the GPU backend uploads for it (wg_mesh.c: 3
 * RGBA32F texels a vertex and a triangle, 2 a BVH node); and the bytes the buffer's body moves
 * between host and GPU: with compute passes it stays on the GPU (wg_mesh_body.c: 16 bytes read
 * back by the call's check, 16 a substep for the fastest vertex, nothing uploaded), with fragment
 * passes it is read back (12 bytes a vertex) and uploaded as the array's. Prints one Markdown
 * row; asserts nothing about time.
 *
 *   bench_body_gl [--k K] [--n N] [--frames F]     (defaults 100, 64, 20) */
#define _POSIX_C_SOURCE 200809L
#include <GL/glew.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "api_grid.h"
#include "egl_context.h"
#include "host_gl_passes.h"
#include "mesh_collider.h"

/* The body: a UV sphere, radius 0.3 m at the origin, k slices and k stacks (2 k (k - 1)
 * triangles, outward winding). */
typedef struct body_mesh {
    int nv, nt;
    float* x;
    int* t;
} body_mesh;
static body_mesh g_tm;

static void uv_sphere(body_mesh* m, int k) {
    m->nv = 2 + k * (k - 1);
    m->nt = 2 * k * (k - 1);
    m->x = malloc((size_t)m->nv * 12);
    m->t = malloc((size_t)m->nt * 12);
    const double r = 0.3, pi = 3.14159265358979323846;
    m->x[0] = 0.0f, m->x[1] = (float)r, m->x[2] = 0.0f;               /* north pole */
    for (int s = 1; s < k; ++s)
        for (int j = 0; j < k; ++j) {
            double th = pi * s / k, ph = 2.0 * pi * j / k;
            float* p = m->x + 3 * (1 + (s - 1) * k + j);
            p[0] = (float)(r * sin(th) * cos(ph)), p[1] = (float)(r * cos(th)), p[2] = (float)(r * sin(th) * sin(ph));
        }
    int south = m->nv - 1, at = 0;
    m->x[3 * south] = 0.0f, m->x[3 * south + 1] = (float)-r, m->x[3 * south + 2] = 0.0f;
#define V(s, j) (1 + ((s) - 1) * k + ((j) % k))
#define TRI(a, b, c) (m->t[3 * at] = (a), m->t[3 * at + 1] = (b), m->t[3 * at + 2] = (c), ++at)
    for (int j = 0; j < k; ++j) {
        TRI(0, V(1, j + 1), V(1, j));
        TRI(south, V(k - 1, j), V(k - 1, j + 1));
    }
    for (int s = 1; s + 1 < k; ++s)
        for (int j = 0; j < k; ++j) {
            TRI(V(s, j), V(s, j + 1), V(s + 1, j + 1));
            TRI(V(s, j), V(s + 1, j + 1), V(s + 1, j));
        }
#undef V
#undef TRI
}

static double now_ms(void) {
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return 1e3 * (double)t.tv_sec + 1e-6 * (double)t.tv_nsec;
}

static int cmp(const void* a, const void* b) {
    double x = *(const double*)a, y = *(const double*)b;
    return (x > y) - (x < y);
}

static double median(double* v, int n) {
    qsort(v, (size_t)n, sizeof *v, cmp);
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/* Median ms of core's substep of the body over `reps` substeps, the body moving between them;
 * *bytes: what wg_mesh_substep uploads for it. */
static double core_substep_ms(const float* rest, int reps, double* bytes) {
    double* x = malloc((size_t)g_tm.nv * 3 * sizeof(double));
    for (int i = 0; i < 3 * g_tm.nv; ++i) x[i] = rest[i];
    wc_mesh_collider* m = NULL;
    wc_diag d;
    memset(&d, 0, sizeof d);
    double* t = malloc(sizeof(double) * (size_t)reps);
    *bytes = 0.0;
    if (wc_mesh_collider_create(&m, x, g_tm.nv, g_tm.t, g_tm.nt, 0.005, 0.3, NULL, &d) != WC_OK) {
        free(x), free(t);
        return NAN;
    }
    for (int r = 0; r < reps; ++r) {
        for (int i = 0; i < 3 * g_tm.nv; ++i) x[i] = rest[i] * (1.0 + 0.03 * sin(0.2 * (r + 1)));
        wc_mesh_collider_set_target(m, x, &d);
        double t0 = now_ms();
        wc_mesh_collider_substep(m, 0.0, 1.0, 1.0 / 60.0);
        t[r] = now_ms() - t0;
        wc_mesh_collider_end_frame(m);
    }
    *bytes = 16.0 * (3.0 * m->n_verts + 3.0 * m->n_tris + 2.0 * m->bvh.n_nodes);
    double ms = median(t, reps);
    wc_mesh_collider_destroy(m);
    free(x), free(t);
    return ms;
}

static weft_cloth make_cloth(weft_context* ctx, const ag_mesh* sheet, const float* rest) {
    weft_mesh_collider_def m = weft_default_mesh_collider_def();
    m.mesh.positions = rest;
    m.mesh.n_vertices = g_tm.nv;
    m.mesh.indices = g_tm.t;
    m.mesh.n_faces = g_tm.nt;
    weft_cloth_def def = weft_default_cloth_def();
    def.mesh = ag_desc(sheet);
    def.n_mesh_colliders = 1;
    def.mesh_colliders = &m;
    def.self_collision = 0;
    weft_cloth c = {0};
    if (weft_cloth_create(ctx, &def, &c) != WEFT_OK) fprintf(stderr, "create: %s\n", weft_context_last_error(ctx));
    return c;
}

int main(int argc, char** argv) {
    int k = 100, n = 64, frames = 20;
    for (int i = 1; i + 1 < argc; i += 2) {
        if (!strcmp(argv[i], "--k")) k = atoi(argv[i + 1]);
        else if (!strcmp(argv[i], "--n")) n = atoi(argv[i + 1]);
        else if (!strcmp(argv[i], "--frames")) frames = atoi(argv[i + 1]);
        else {
            fprintf(stderr, "usage: bench_body_gl [--k K] [--n N] [--frames F]\n");
            return 2;
        }
    }
    if (k < 3 || k > 2000 || n < 2 || frames < 1) {
        fprintf(stderr, "bench_body_gl: k in [3, 2000], n >= 2, frames >= 1\n");
        return 2;
    }
    uv_sphere(&g_tm, k);
    const int nv = g_tm.nv;
    const float* rest = g_tm.x;
    float* body = malloc((size_t)nv * 12);
    ag_mesh sheet;
    ag_grid(&sheet, n, 1.0, 0.35, 0, 0);

    char err[512];
    wg_gl_context_desc hd;
    memset(&hd, 0, sizeof hd);
    wg_gl_context* host = NULL;
    if (wg_gl_context_create(&hd, &host, err, sizeof err) != WC_OK || wg_gl_begin(host, err, sizeof err) != WC_OK) {
        fprintf(stderr, "bench_body_gl: %s\n", err);
        return 1;
    }
    weft_context_def cd = weft_default_context_def();
    cd.backend = WEFT_BACKEND_GPU;
    cd.gl_mode = WEFT_GL_HOST_CURRENT;
    weft_context* ctx = NULL;
    if (weft_context_create(WEFT_ABI, &cd, &ctx) != WEFT_OK) {
        fprintf(stderr, "bench_body_gl: no GPU context\n");
        return 1;
    }
    weft_cloth a = make_cloth(ctx, &sheet, rest), b = make_cloth(ctx, &sheet, rest);
    GLuint buf = 0;
    glGenBuffers(1, &buf);
    glBindBuffer(GL_COPY_WRITE_BUFFER, buf);
    glBufferData(GL_COPY_WRITE_BUFFER, (GLsizeiptr)nv * 12, NULL, GL_DYNAMIC_DRAW);
    double *t_arr = malloc(sizeof(double) * (size_t)frames), *t_buf = malloc(sizeof(double) * (size_t)frames);
    double *s_arr = malloc(sizeof(double) * (size_t)frames), *s_buf = malloc(sizeof(double) * (size_t)frames);
    weft_frame fr = weft_default_frame();
    fr.dt = 1.0 / 60.0;
    int failed = 0, substeps = 0;
    for (int f = 0; f < frames; ++f) {
        double s = 1.0 + 0.03 * sin(0.2 * (f + 1));
        for (int i = 0; i < 3 * nv; ++i) body[i] = (float)(s * rest[i]);
        glBindBuffer(GL_COPY_WRITE_BUFFER, buf);
        glBufferSubData(GL_COPY_WRITE_BUFFER, 0, (GLsizeiptr)nv * 12, body);
        glFinish();
        double t0 = now_ms();
        failed |= weft_cloth_set_mesh_collider_vertices(ctx, a, 0, body, nv) != WEFT_OK;
        double t1 = now_ms();
        failed |= weft_cloth_set_mesh_collider_gl_buffer(ctx, b, 0, buf, 0, 0, nv) != WEFT_OK;
        double t2 = now_ms();
        failed |= weft_cloth_step(ctx, a, &fr, NULL) != WEFT_OK;
        double t3 = now_ms();
        weft_frame_stats fs;
        failed |= weft_cloth_step(ctx, b, &fr, &fs) != WEFT_OK;
        substeps += fs.substeps;
        glFinish();
        double t4 = now_ms();
        t_arr[f] = t1 - t0, t_buf[f] = t2 - t1, s_arr[f] = t3 - t2, s_buf[f] = t4 - t3;
    }
    if (failed) fprintf(stderr, "bench_body_gl: a call failed: %s\n", weft_context_last_error(ctx));
    double up = 0.0, core_ms = core_substep_ms(rest, frames, &up);
    const int on_gpu = hg_body_on_gpu();
    const double per_frame = (double)substeps / frames;
    const double read_back = on_gpu ? 16.0 + 16.0 * per_frame : 12.0 * nv, buf_up = on_gpu ? 0.0 : up;
    printf("| body vertices | triangles | particles | buffer's body | GL buffer: bytes read back a frame | GL buffer: "
           "bytes uploaded a substep | array: bytes uploaded a substep | array call ms | GL-buffer call ms | step ms "
           "(array / buffer) | core's body substep ms |\n|---|---|---|---|---|---|---|---|---|---|---|\n");
    printf("| %d | %d | %d | %s | %.0f | %.0f | %.0f | %.3f | %.3f | %.1f / %.1f | %.3f |\n", nv, g_tm.nt, n * n,
           on_gpu ? "on the GPU" : "read back", read_back, buf_up, up, median(t_arr, frames), median(t_buf, frames),
           median(s_arr, frames), median(s_buf, frames), core_ms);
    glDeleteBuffers(1, &buf);
    weft_context_destroy(ctx);
    wg_gl_end(host);
    wg_gl_context_destroy(host);
    free(t_arr), free(t_buf), free(s_arr), free(s_buf), free(g_tm.x), free(g_tm.t), free(body);
    ag_free(&sheet);
    return failed;
}
