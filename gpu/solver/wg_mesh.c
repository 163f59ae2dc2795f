/* The mesh colliders' textures (wg_mesh.h). Boxes go to float rounded outwards, so that a box
 * still holds its triangles' float vertices and a query's float box meets every node core's
 * would. */
#include <math.h>
#include <string.h>

#include "gpu_error.h"
#include "wg_mesh.h"

static float down(double x) {
    float f = (float)x;
    return (double)f > x ? nextafterf(f, -INFINITY) : f;
}

static float up(double x) {
    float f = (float)x;
    return (double)f < x ? nextafterf(f, INFINITY) : f;
}

void wg_mesh_release(wg_mesh* g, int gl) {
    wg_mesh_body_release(g, gl);
    if (gl) {
        wg_tex_destroy(&g->vert);
        wg_tex_destroy(&g->tri);
        wg_tex_destroy(&g->node);
    }
    wc_free(&g->alloc, g->vert0);
    wc_free(&g->alloc, g->tri0);
    wc_free(&g->alloc, g->node0);
    wc_free(&g->alloc, g->staging);
    g->vert0 = g->tri0 = g->node0 = NULL;
    g->staging = NULL;
}

size_t wg_mesh_bytes(const wg_mesh* g) {
    const wg_tex* t[] = {&g->vert, &g->tri, &g->node};
    size_t bytes = wg_mesh_body_bytes(g);
    for (size_t k = 0; k < sizeof t / sizeof t[0]; ++k) bytes += t[k]->id ? wg_tex_bytes(t[k]) : 0;
    return bytes;
}

int wg_mesh_init(wg_mesh* g, wg_runner* run, wc_mesh_collider* const* mesh, int n_mesh, char* err,
                 size_t err_len) {
    const wg_layout* L = run->layout;
    memset(g, 0, sizeof *g);
    g->run = run;
    g->alloc = L->alloc;
    g->n_mesh = n_mesh;
    g->mesh = mesh;
    int nm = n_mesh > 0 ? n_mesh : 1;
    g->vert0 = wc_calloc(&g->alloc, (size_t)nm, sizeof(int));
    g->tri0 = wc_calloc(&g->alloc, (size_t)nm, sizeof(int));
    g->node0 = wc_calloc(&g->alloc, (size_t)nm, sizeof(int));
    long long nv = 0, nt = 0, nn = 0;
    for (int k = 0; k < n_mesh; ++k) {
        if (g->vert0) g->vert0[k] = (int)nv;
        if (g->tri0) g->tri0[k] = (int)nt;
        if (g->node0) g->node0[k] = (int)nn;
        nv += mesh[k]->n_verts;
        nt += mesh[k]->n_tris;
        nn += mesh[k]->bvh.n_nodes;
    }
    /* indices travel as floats: exact below 2^24 */
    if (3 * nv >= (1LL << 24) || 3 * nt >= (1LL << 24) || 2 * nn >= (1LL << 24)) {
        wg_errorf(err, err_len, "mesh colliders of %lld vertices and %lld triangles in all: the GPU takes fewer than "
                  "5.5 million of each", nv, nt);
        return 0;
    }
    g->n_vert = (int)nv;
    g->n_tri = (int)nt;
    g->n_node = (int)nn;
    long long most = 3 * nv > 3 * nt ? 3 * nv : 3 * nt;
    if (2 * nn > most) most = 2 * nn;
    if (most < 1) most = 1;
    g->staging = wc_calloc(&g->alloc, (size_t)most * 4u, sizeof(float));
    if (!g->vert0 || !g->tri0 || !g->node0 || !g->staging) {
        wg_errorf(err, err_len, "out of memory");
        return 0;
    }
    if (!wg_array_create(L, &g->vert, GL_RGBA32F, (int)(3 * nv > 0 ? 3 * nv : 1), NULL, err, err_len) ||
        !wg_array_create(L, &g->tri, GL_RGBA32F, (int)(3 * nt > 0 ? 3 * nt : 1), NULL, err, err_len) ||
        !wg_array_create(L, &g->node, GL_RGBA32F, (int)(2 * nn > 0 ? 2 * nn : 1), NULL, err, err_len))
        return 0;
    if (n_mesh == 0) return 1;
    wg_mesh_upload(g, -1);   /* the trees' shapes and the triangles' vertices, which the passes keep */
    return !run->dev->compute || wg_mesh_body_init(g, err, err_len);
}

static void put3(float* o, const double* p, float w) {
    o[0] = (float)p[0];
    o[1] = (float)p[1];
    o[2] = (float)p[2];
    o[3] = w;
}

/* Items [first, first + count) of t from the staging o (item i at o + 4 i); all: items [0, count)
   in one upload. */
static void put(const wg_layout* L, const wg_tex* t, int all, int first, int count, const float* o) {
    if (all) wg_array_upload(L, t, count, o);
    else wg_array_upload_range(L, t, first, count, o + 4 * (size_t)first);
}

void wg_mesh_upload(wg_mesh* g, int which) {
    const wg_layout* L = g->run->layout;
    float* o = g->staging;
    const int all = which < 0;
    const int k0 = all ? 0 : which, k1 = all ? g->n_mesh : which + 1;
    for (int k = k0; k < k1; ++k)   /* 16 bytes a texel: 3 a vertex, 3 a triangle, 2 a node */
        g->up_bytes += 16 * (3LL * g->mesh[k]->n_verts + 3LL * g->mesh[k]->n_tris + 2LL * g->mesh[k]->bvh.n_nodes);
    for (int k = k0; k < k1; ++k) {
        const wc_mesh_collider* m = g->mesh[k];
        for (int i = 0; i < m->n_verts; ++i) {
            float* q = o + 12 * (size_t)(g->vert0[k] + i);
            put3(q, m->xa + 3 * i, 0.0f);
            put3(q + 4, m->xb + 3 * i, 0.0f);
            put3(q + 8, m->vel + 3 * i, 0.0f);
        }
        if (!all) put(L, &g->vert, 0, 3 * g->vert0[k], 3 * m->n_verts, o);
    }
    if (all) put(L, &g->vert, 1, 0, 3 * g->n_vert, o);
    for (int k = k0; k < k1; ++k) {
        const wc_mesh_collider* m = g->mesh[k];
        for (int t = 0; t < m->n_tris; ++t) {
            float* q = o + 12 * (size_t)(g->tri0[k] + t);
            for (int c = 0; c < 3; ++c) q[c] = (float)(g->vert0[k] + m->tris[3 * t + c]);
            q[3] = 0.0f;
            put3(q + 4, m->nrm_a + 3 * t, 0.0f);
            put3(q + 8, m->nrm_b + 3 * t, 0.0f);
        }
        if (!all) put(L, &g->tri, 0, 3 * g->tri0[k], 3 * m->n_tris, o);
    }
    if (all) put(L, &g->tri, 1, 0, 3 * g->n_tri, o);
    for (int k = k0; k < k1; ++k) {
        const wc_bvh* b = &g->mesh[k]->bvh;
        for (int j = 0; j < b->n_nodes; ++j) {
            float* q = o + 8 * (size_t)(g->node0[k] + j);
            const double* bx = b->box + 6 * j;
            const int* ch = b->child + 2 * j;
            int leaf = ch[0] < 0;
            for (int c = 0; c < 3; ++c) {
                q[c] = down(bx[c]);
                q[4 + c] = up(bx[3 + c]);
            }
            q[3] = leaf ? -1.0f : (float)(g->node0[k] + ch[0]);
            q[7] = (float)(leaf ? g->tri0[k] + ch[1] : g->node0[k] + ch[1]);
        }
        if (!all) put(L, &g->node, 0, 2 * g->node0[k], 2 * b->n_nodes, o);
    }
    if (all) put(L, &g->node, 1, 0, 2 * g->n_node, o);
}

void wg_mesh_substep(wg_mesh* g, double a0, double a1, double h) {
    if (g->n_mesh == 0) return;
    if (g->n_resident == 0) {   /* every body on the host: one upload of each texture */
        for (int k = 0; k < g->n_mesh; ++k) wc_mesh_collider_substep(g->mesh[k], a0, a1, h);
        wg_mesh_upload(g, -1);
        return;
    }
    wg_mesh_body_substep(g, a0, a1, h);
    for (int k = 0; k < g->n_mesh; ++k)
        if (!g->resident[k]) {
            wc_mesh_collider_substep(g->mesh[k], a0, a1, h);
            wg_mesh_upload(g, k);
        }
}

void wg_mesh_row(const wg_mesh* g, int k, float* row) {
    const wc_mesh_collider* m = g->mesh[k];
    memset(row, 0, 20 * sizeof(float));
    row[0] = 3.0f;   /* WC_COLLIDER_MESH */
    row[2] = (float)m->thickness;
    row[3] = (float)m->friction;
    row[4] = (float)g->node0[k];
    row[5] = (float)(m->h * m->max_speed);
    row[15] = (float)m->push_speed;
}
