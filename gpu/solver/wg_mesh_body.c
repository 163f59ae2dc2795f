/* The mesh colliders' bodies computed on the device (wg_mesh.h, "resident"; compute passes only).
 * A resident body's frame start and end positions are the from / to textures; each substep
 * mesh_verts.glsl interpolates them into the vertex texels (start, end, velocity),
 * mesh_tris.glsl computes the triangle texels (indices, normals at start and end), and
 * mesh_refit_groups.glsl refits the BVH in place one height at a time (the leaves first, a node
 * after both its children: the tree's shape is core's, fixed at creation, so the heights and the
 * order are computed on the host once per set of resident bodies). Each body's fastest vertex is
 * a max reduction of mesh_measure.glsl's speeds, read back (16 bytes): core's judge and the
 * colliders' rows take it on the host. Everything is in float: the results agree with core's
 * double substep to float's reach (the boxes widened so that they hold core's). */
#include <GL/glew.h>
#include <string.h>

#include "gpu_error.h"
#include "wg_host_buffer.h"
#include "wg_mesh.h"
#include "wg_passes.h"

#define BODY_TEXTURES(g) {&(g)->from, &(g)->to, &(g)->to_next, &(g)->from_bk, &(g)->tri_idx, &(g)->order, \
                         &(g)->meas, &(g)->raw}

void wg_mesh_body_release(wg_mesh* g, int gl) {
    if (gl && g->body) {
        wg_tex* t[] = BODY_TEXTURES(g);
        for (size_t k = 0; k < sizeof t / sizeof t[0]; ++k) wg_tex_destroy(t[k]);
        wg_chain_destroy(&g->chain);
    }
    wc_free(&g->alloc, g->resident);
    wc_free(&g->alloc, g->height);
    wc_free(&g->alloc, g->order_first);
    g->resident = NULL;
    g->height = g->order_first = NULL;
    g->body = 0;
}

size_t wg_mesh_body_bytes(const wg_mesh* g) {
    if (!g->body) return 0;
    const wg_tex* t[] = BODY_TEXTURES(g);
    size_t bytes = wg_chain_bytes(&g->chain);
    for (size_t k = 0; k < sizeof t / sizeof t[0]; ++k) bytes += t[k]->id ? wg_tex_bytes(t[k]) : 0;
    return bytes;
}

int wg_mesh_body_init(wg_mesh* g, char* err, size_t err_len) {
    const wg_layout* L = g->run->layout;
    const wc_allocator* A = &g->alloc;
    g->resident = wc_calloc(A, (size_t)g->n_mesh, 1);
    g->height = wc_calloc(A, (size_t)g->n_node, sizeof(int));
    if (!g->resident || !g->height) {
        wg_errorf(err, err_len, "out of memory");
        return 0;
    }
    int top = 0;
    for (int k = 0; k < g->n_mesh; ++k) {
        const int t = wc_bvh_heights(&g->mesh[k]->bvh, g->height + g->node0[k]);
        if (t > top) top = t;
    }
    g->n_heights = top + 1;
    g->order_first = wc_calloc(A, (size_t)top + 2, sizeof(int));
    if (!g->order_first) {
        wg_errorf(err, err_len, "out of memory");
        return 0;
    }
    float* o = g->staging;
    for (int k = 0; k < g->n_mesh; ++k) {
        const wc_mesh_collider* m = g->mesh[k];
        for (int t = 0; t < m->n_tris; ++t) {
            float* q = o + 4 * (size_t)(g->tri0[k] + t);
            for (int c = 0; c < 3; ++c) q[c] = (float)(g->vert0[k] + m->tris[3 * t + c]);
            q[3] = (float)m->thickness;
        }
    }
    g->body = 1;
    g->host_fed = g->run->dev->body_host != 1;
    wg_tex* per_vertex[] = {&g->from, &g->to, &g->to_next, &g->from_bk, &g->meas};
    for (size_t k = 0; k < sizeof per_vertex / sizeof per_vertex[0]; ++k)
        if (!wg_array_create(L, per_vertex[k], GL_RGBA32F, g->n_vert, NULL, err, err_len)) return 0;
    return wg_array_create(L, &g->tri_idx, GL_RGBA32F, g->n_tri, o, err, err_len) &&
           wg_array_create(L, &g->order, GL_RGBA32F, g->n_node, NULL, err, err_len) &&
           wg_chain_create(g->run, &g->chain, g->meas.w, g->meas.h, err, err_len);
}

/* The refit's order: the resident meshes' nodes by height (a counting sort; wg_mesh.h). */
void wg_mesh_body_rebuild_order(wg_mesh* g) {
    int* first = g->order_first;
    memset(first, 0, ((size_t)g->n_heights + 1) * sizeof(int));
    for (int k = 0; k < g->n_mesh; ++k)
        if (g->resident[k])
            for (int j = 0; j < g->mesh[k]->bvh.n_nodes; ++j) ++first[g->height[g->node0[k] + j] + 1];
    for (int h = 0; h < g->n_heights; ++h) first[h + 1] += first[h];
    float* o = g->staging;
    for (int k = 0; k < g->n_mesh; ++k)
        if (g->resident[k])
            for (int j = 0; j < g->mesh[k]->bvh.n_nodes; ++j) {
                int node = g->node0[k] + j;
                float* q = o + 4 * (size_t)first[g->height[node]]++;
                q[0] = (float)node;
                q[1] = q[2] = q[3] = 0.0f;
            }
    for (int h = g->n_heights; h > 0; --h) first[h] = first[h - 1];   /* back to each height's start */
    first[0] = 0;
    if (first[g->n_heights] > 0) wg_array_upload(g->run->layout, &g->order, first[g->n_heights], o);
    g->up_bytes += 16LL * first[g->n_heights];
}

void wg_mesh_body_put(wg_mesh* g, const wg_tex* t, int k, const double* x) {
    const int n = g->mesh[k]->n_verts;
    float* o = g->staging;
    for (int i = 0; i < n; ++i) {
        for (int c = 0; c < 3; ++c) o[4 * i + c] = (float)x[3 * i + c];
        o[4 * i + 3] = 0.0f;
    }
    wg_array_upload_range(g->run->layout, t, g->vert0[k], n, o);
    g->up_bytes += 16LL * n;
}

void wg_mesh_body_make_resident(wg_mesh* g, int k) {
    if (g->resident[k]) return;
    g->resident[k] = 1;
    ++g->n_resident;
    wg_mesh_body_rebuild_order(g);
}

void wg_mesh_body_set(wg_mesh* g, int k, const double* from, const double* to) {
    if (!g->body) return;
    wg_mesh_body_put(g, &g->from, k, from);
    wg_mesh_body_put(g, &g->to, k, to);
    wg_mesh_body_make_resident(g, k);
}

void wg_mesh_body_substep(wg_mesh* g, double a0, double a1, double h) {
    if (!g->body || g->n_resident == 0) return;
    wg_runner* run = g->run;
    WG_USE(run, WGP_MESH_VERTS, &(wg_mesh_verts_in){.body_from = &g->from, .body_to = &g->to});
    wg_u1f(run, "u_a0", a0);
    wg_u1f(run, "u_a1", a1);
    wg_u1f(run, "u_h", h);
    WG_RUN(run, 3 * g->n_vert, &g->vert);
    WG_USE(run, WGP_MESH_TRIS, &(wg_mesh_tris_in){.tri_idx = &g->tri_idx, .vert = &g->vert});
    WG_RUN(run, 3 * g->n_tri, &g->tri);
    WG_USE(run, WGP_MESH_REFIT_GROUPS, &(wg_mesh_refit_in){.order = &g->order, .tri_idx = &g->tri_idx,
        .vert = &g->vert});
    wg_run_by_height(run, g->order_first, g->n_heights, &g->node);
    for (int k = 0; k < g->n_mesh; ++k) {
        if (!g->resident[k]) continue;
        wc_mesh_collider* m = g->mesh[k];
        WG_USE(run, WGP_MESH_MEASURE, &(wg_mesh_measure_in){.src = &g->vert, .ref = &g->vert});
        wg_u1i(run, "u_mode", 0);
        wg_u1i(run, "u_v0", g->vert0[k]);
        wg_u1i(run, "u_v1", g->vert0[k] + m->n_verts);
        WG_RUN(run, g->n_vert, &g->meas);
        float r[4];
        wg_read1(run->layout, wg_reduce(run, &g->chain, &g->meas, 1, 0, 0, 0), r);
        g->read_bytes += sizeof r;
        m->max_speed = (double)r[0];
        m->h = h;
    }
}

void wg_mesh_body_end_frame(wg_mesh* g) {
    if (g && g->body && g->n_resident > 0) wg_copy(g->run, &g->from, &g->to);
}

void wg_mesh_body_backup(wg_mesh* g) {
    if (g && g->body && g->n_resident > 0) wg_copy(g->run, &g->from_bk, &g->from);
}

/* The bodies core's copy moves (g->host_fed, wg_mesh_host.c) back to the host after a failed
 * frame: core's rollback restores their frame and the next frame uploads it again. */
static void drop_host_fed(wg_mesh* g) {
    int dropped = 0;
    for (int k = 0; k < g->n_mesh; ++k)
        if (g->resident[k] && g->mesh[k]->substep_on_device) {
            g->mesh[k]->substep_on_device = 0;
            g->resident[k] = 0;
            --g->n_resident;
            dropped = 1;
        }
    if (dropped) wg_mesh_body_rebuild_order(g);
}

void wg_mesh_body_restore_backup(wg_mesh* g) {
    if (!g || !g->body || g->n_resident == 0) return;
    wg_copy(g->run, &g->from, &g->from_bk);
    drop_host_fed(g);
}

/* Mesh k's positions in t's texels into x (n x 3 doubles); rb holds the whole array's texels. */
static void get_positions(const wg_mesh* g, const float* rb, int k, double* x) {
    const float* p = rb + 4 * (size_t)g->vert0[k];
    for (int i = 0; i < g->mesh[k]->n_verts; ++i)
        for (int c = 0; c < 3; ++c) x[3 * i + c] = (double)p[4 * i + c];
}

void wg_mesh_body_pull(wg_mesh* g) {
    if (!g || !g->body || g->n_resident == 0) return;
    const wg_layout* L = g->run->layout;
    float* rb = g->staging;
    int stale = 0;   /* a body from a host buffer: core's frame is stale (core's is current for the others) */
    for (int k = 0; k < g->n_mesh; ++k) stale |= g->resident[k] && g->mesh[k]->on_device;
    for (int pass = 0; stale && pass < 2; ++pass) {
        wg_array_read(L, pass == 0 ? &g->from : &g->to, g->n_vert, rb);
        g->read_bytes += 16LL * g->n_vert;
        for (int k = 0; k < g->n_mesh; ++k)
            if (g->resident[k] && g->mesh[k]->on_device)
                get_positions(g, rb, k, pass == 0 ? g->mesh[k]->from : g->mesh[k]->to);
    }
    for (int k = 0; k < g->n_mesh; ++k)
        if (g->resident[k]) {
            wc_mesh_collider* m = g->mesh[k];
            m->on_device = 0;
            m->substep_on_device = 0;
            wc_mesh_collider_substep(m, 0.0, 0.0, 0.0);   /* as a snapshot's restore: at from */
            g->resident[k] = 0;
        }
    g->n_resident = 0;
    wg_mesh_body_rebuild_order(g);
}

wc_status wg_mesh_body_take(wg_mesh* g, int k, unsigned buffer, size_t offset, size_t stride, int* bad_vertex,
                            float bad[3], int* moves, wc_diag* d) {
    *bad_vertex = -1;
    *moves = 0;
    if (!g->body) return wc_fail(d, WC_ERROR_UNSUPPORTED, "the bodies are moved on the host with fragment passes");
    wc_mesh_collider* m = g->mesh[k];
    wg_runner* run = g->run;
    const wg_layout* L = run->layout;
    const int W = 1 << L->shift;
    const size_t floats = ((size_t)(m->n_verts - 1) * stride + 3 * sizeof(float)) / sizeof(float);
    const size_t rows = (floats + (size_t)W - 1) / (size_t)W;
    if (rows > (size_t)L->max_size)
        return wc_fail(d, WC_ERROR_UNSUPPORTED, "%zu floats do not fit the device's %d-texel textures", floats,
                       L->max_size);
    wc_status st = wg_host_buffer_unpack(buffer, offset, floats, &g->raw, W, (int)rows, d);
    if (st != WC_OK) return st;
    const int v0 = g->vert0[k], v1 = v0 + m->n_verts;
    if (!g->resident[k]) wg_mesh_body_put(g, &g->from, k, m->from);   /* core's copy is current */
    WG_USE(run, WGP_MESH_GATHER, &(wg_mesh_gather_in){.raw = &g->raw, .body_to = &g->to});
    wg_u1i(run, "u_v0", v0);
    wg_u1i(run, "u_v1", v1);
    wg_u1i(run, "u_stride", (int)(stride / sizeof(float)));
    wg_u1i(run, "u_rw", W);
    WG_RUN(run, g->n_vert, &g->to_next);
    /* the check and whether the body moves: the new end against the frame's start, which is what
       core's wc_mesh_collider_moving asks of a step (after a frame from = to; a second take in the
       same frame still compares with the start) */
    WG_USE(run, WGP_MESH_MEASURE, &(wg_mesh_measure_in){.src = &g->to_next, .ref = &g->from});
    wg_u1i(run, "u_mode", 1);
    wg_u1i(run, "u_v0", v0);
    wg_u1i(run, "u_v1", v1);
    WG_RUN(run, g->n_vert, &g->meas);
    float r[4];
    wg_read1(L, wg_reduce(run, &g->chain, &g->meas, 1, 1, 0, 0), r);
    g->read_bytes += sizeof r;
    if (r[0] > 0.0f) {   /* the first bad vertex's floats, for the caller's message */
        int v = v1 - (int)r[0];
        wg_array_read(L, &g->to_next, v + 1, g->staging);
        memcpy(bad, g->staging + 4 * (size_t)v, 3 * sizeof(float));
        *bad_vertex = v - v0;
        return WC_OK;
    }
    wg_tex t = g->to;
    g->to = g->to_next;
    g->to_next = t;
    wg_mesh_body_make_resident(g, k);
    m->on_device = 1;
    m->substep_on_device = 0;   /* its frame is the device's now, not core's */
    *moves = r[1] > 0.0f;
    return WC_OK;
}
