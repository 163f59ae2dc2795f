/* The resident bodies' sharp-feature pairs found on the GPU (wg_mesh_sharp.h). */
#include "wg_mesh_sharp.h"

#include <GL/glew.h>
#include <stdlib.h>
#include <string.h>

#include "gpu_error.h"
#include "wg_passes.h"

typedef struct found {
    int q, fid, at;   /* cloth feature, body feature, slot */
} found;

struct wg_mesh_sharp {
    wg_runner* run;
    wg_mesh* mesh;
    wc_allocator alloc;
    int n_edge;                      /* body edges over all meshes (core's, mesh_pairs.h) */
    int* e0;                         /* (n_mesh + 1) each mesh's first edge */
    int n_feat;                      /* cloth features: winged edges (not repeated), triangles */
    int n_we;                        /* the model's winged edges: q below it is a cloth edge */
    int cap;                         /* pair slots: the mesh pairs list's capacity */
    wg_tex bedge, btri, bvrow, bvlist, cfeat, sharp, mask, out, counter;
    float* rb;                       /* (3 cap x 4) the pairs read back */
    found* order;                    /* (cap) their sort */
};

static wg_tex* textures(wg_mesh_sharp* ms, int k) {
    wg_tex* t[] = {&ms->bedge,  &ms->btri, &ms->bvrow, &ms->bvlist, &ms->cfeat,
                   &ms->sharp, &ms->mask, &ms->out,   &ms->counter};
    return k < (int)(sizeof t / sizeof t[0]) ? t[k] : NULL;
}

void wg_mesh_sharp_destroy(wg_mesh_sharp* ms, int gl) {
    if (!ms) return;
    if (gl)
        for (int k = 0; textures(ms, k); ++k) wg_tex_destroy(textures(ms, k));
    wc_allocator a = ms->alloc;
    wc_free(&a, ms->e0);
    wc_free(&a, ms->rb);
    wc_free(&a, ms->order);
    wc_free(&a, ms);
}

size_t wg_mesh_sharp_bytes(const wg_mesh_sharp* ms) {
    size_t bytes = 0;
    for (int k = 0; ms && textures((wg_mesh_sharp*)ms, k); ++k) {
        const wg_tex* t = textures((wg_mesh_sharp*)ms, k);
        bytes += t->id ? wg_tex_bytes(t) : 0;
    }
    return bytes;
}

/* The static tables: the body edges (bedge), each triangle's edges and leaf (btri), each
 * vertex's triangles (bvrow, bvlist), the cloth features (cfeat); staged in o (room for 4 x the
 * largest of them). */
static int tables(wg_mesh_sharp* ms, const wc_mesh_pairs* pp, const wc_model* m, float* o, char* err,
                  size_t err_len) {
    const wg_mesh* g = ms->mesh;
    const wg_layout* L = ms->run->layout;
    for (int k = 0; k < g->n_mesh; ++k) {
        const wc_mesh_sharp* sh = &pp->sharp[k];
        const wc_mesh_collider* mc = g->mesh[k];
        for (int e = 0; e < sh->n_edges; ++e) {
            int t1 = sh->edge_tri[2 * e], t2 = sh->edge_tri[2 * e + 1], c = 0;
            while (c < 2 && sh->tri_edge[3 * t1 + c] != e) ++c;
            float* q = o + 8 * (size_t)(ms->e0[k] + e);
            q[0] = (float)(g->vert0[k] + mc->tris[3 * t1 + c]);
            q[1] = (float)(g->vert0[k] + mc->tris[3 * t1 + (c + 1) % 3]);
            q[2] = (float)(g->tri0[k] + t1);
            q[3] = t2 >= 0 ? (float)(g->tri0[k] + t2) : -1.0f;
            q[4] = (float)sh->edge_many[e];
            q[5] = q[6] = q[7] = 0.0f;
        }
    }
    if (!wg_array_create(L, &ms->bedge, GL_RGBA32F, 2 * (ms->n_edge > 0 ? ms->n_edge : 1), o, err, err_len))
        return 0;
    for (int k = 0; k < g->n_mesh; ++k) {
        const wc_mesh_collider* mc = g->mesh[k];
        for (int t = 0; t < mc->n_tris; ++t) {
            float* q = o + 4 * (size_t)(g->tri0[k] + t);
            for (int c = 0; c < 3; ++c) q[c] = (float)(ms->e0[k] + pp->sharp[k].tri_edge[3 * t + c]);
            q[3] = (float)(g->node0[k] + mc->bvh.leaf_of[t]);
        }
    }
    if (!wg_array_create(L, &ms->btri, GL_RGBA32F, g->n_tri > 0 ? g->n_tri : 1, o, err, err_len)) return 0;
    /* each vertex's triangles: a counting sort (row x: first, y: end) */
    float* row = o;
    memset(row, 0, 4 * ((size_t)g->n_vert + 1) * sizeof(float));
    for (int k = 0; k < g->n_mesh; ++k)
        for (int j = 0; j < 3 * g->mesh[k]->n_tris; ++j) row[4 * (g->vert0[k] + g->mesh[k]->tris[j]) + 1] += 1.0f;
    float sum = 0.0f;
    for (int i = 0; i < g->n_vert; ++i) {
        row[4 * i] = sum;
        sum += row[4 * i + 1];
        row[4 * i + 1] = row[4 * i];
    }
    float* list = o + 4 * ((size_t)g->n_vert + 1);
    for (int k = 0; k < g->n_mesh; ++k)
        for (int j = 0; j < 3 * g->mesh[k]->n_tris; ++j) {
            float* r = row + 4 * (g->vert0[k] + g->mesh[k]->tris[j]);
            float* q = list + 4 * (size_t)r[1];
            r[1] += 1.0f;
            q[0] = (float)(g->tri0[k] + j / 3);
            q[1] = q[2] = q[3] = 0.0f;
        }
    const int entries = 3 * g->n_tri;
    if (!wg_array_create(L, &ms->bvrow, GL_RGBA32F, g->n_vert > 0 ? g->n_vert : 1, row, err, err_len) ||
        !wg_array_create(L, &ms->bvlist, GL_RGBA32F, entries > 0 ? entries : 1, list, err, err_len))
        return 0;
    int nf = 0;
    for (int q = 0; q < m->we.n_edges; ++q) {
        if (wc_we_repeats_previous(&m->we, q)) continue;
        float* f = o + 4 * (size_t)nf++;
        f[0] = (float)m->we.edges[q].v[0];
        f[1] = (float)m->we.edges[q].v[1];
        f[2] = -1.0f;
        f[3] = (float)q;
    }
    for (int t = 0; t < m->n_tris; ++t) {
        float* f = o + 4 * (size_t)nf++;
        for (int c = 0; c < 3; ++c) f[c] = (float)m->tris[3 * t + c];
        f[3] = (float)(m->we.n_edges + t);
    }
    ms->n_feat = nf;
    return wg_array_create(L, &ms->cfeat, GL_RGBA32F, nf > 0 ? nf : 1, o, err, err_len) &&
           wg_array_create(L, &ms->sharp, GL_RGBA32F, ms->n_edge + g->n_vert > 0 ? ms->n_edge + g->n_vert : 1, NULL,
                           err, err_len) &&
           wg_array_create(L, &ms->mask, GL_RGBA32F, g->n_node > 0 ? g->n_node : 1, NULL, err, err_len) &&
           wg_array_create(L, &ms->out, GL_RGBA32F, 3 * ms->cap, NULL, err, err_len) &&
           wg_tex_create(&ms->counter, GL_R32I, 1, 1, NULL, err, err_len);
}

int wg_mesh_sharp_create(wg_runner* run, wg_mesh* g, const wc_mesh_pairs* pp, const wc_model* m, wg_mesh_sharp** out,
                         char* err, size_t err_len) {
    *out = NULL;
    wc_allocator a = g->alloc;
    wg_mesh_sharp* ms = wc_calloc(&a, 1, sizeof *ms);
    if (!ms) {
        wg_errorf(err, err_len, "out of memory");
        return 0;
    }
    ms->run = run;
    ms->mesh = g;
    ms->alloc = a;
    ms->n_we = m->we.n_edges;
    ms->cap = pp->list.cap;
    ms->e0 = wc_calloc(&a, (size_t)g->n_mesh + 1, sizeof(int));
    ms->rb = wc_calloc(&a, 12 * (size_t)ms->cap, sizeof(float));
    ms->order = wc_calloc(&a, (size_t)ms->cap, sizeof(found));
    int ok = ms->e0 && ms->rb && ms->order;
    for (int k = 0; ok && k < g->n_mesh; ++k) ms->e0[k + 1] = ms->e0[k] + pp->sharp[k].n_edges;
    if (ok) ms->n_edge = ms->e0[g->n_mesh];
    size_t room = 8 * (size_t)ms->n_edge;   /* the largest table, 4 floats an item */
    size_t r2 = 4 * ((size_t)g->n_vert + 1 + 3 * (size_t)g->n_tri), r3 = 4 * ((size_t)m->we.n_edges + m->n_tris);
    if (r2 > room) room = r2;
    if (r3 > room) room = r3;
    float* o = ok ? wc_calloc(&a, room + 4, sizeof(float)) : NULL;
    if (!o) {
        wg_mesh_sharp_destroy(ms, 0);
        wg_errorf(err, err_len, "out of memory");
        return 0;
    }
    ok = tables(ms, pp, m, o, err, err_len);
    wc_free(&a, o);
    if (!ok) {
        wg_mesh_sharp_destroy(ms, 1);
        return 0;
    }
    *out = ms;
    return 1;
}

static int by_feature(const void* pa, const void* pb) {
    const found *a = pa, *b = pb;
    if (a->q != b->q) return a->q < b->q ? -1 : 1;
    return a->fid < b->fid ? -1 : a->fid > b->fid;
}

int wg_mesh_sharp_find(wg_mesh_sharp* ms, wc_mesh_pairs* pp, const wc_model* m, const struct wc_filter* f,
                       const unsigned char* stick, const wg_tex* x, const wg_tex* v, double h, double he,
                       size_t* bytes) {
    if (bytes) *bytes = 0;
    wg_mesh* g = ms->mesh;
    if (!g->body || g->n_resident == 0 || ms->n_feat == 0) return 0;
    wg_runner* run = ms->run;
    WG_USE(run, WGP_MESH_SHARP, &(wg_mesh_sharp_in){.mesh_vert = &g->vert, .mesh_tri = &g->tri, .bedge = &ms->bedge,
        .btri = &ms->btri, .bvrow = &ms->bvrow, .bvlist = &ms->bvlist});
    wg_u1i(run, "u_ne", ms->n_edge);
    WG_RUN(run, ms->n_edge + g->n_vert, &ms->sharp);
    WG_USE(run, WGP_MESH_SHARP_MASK_GROUPS, &(wg_mesh_sharp_mask_in){.order = &g->order, .mesh_node = &g->node,
        .mesh_tri = &g->tri, .sharp = &ms->sharp});
    wg_u1i(run, "u_nef", ms->n_edge);
    for (int ht = 0; ht < g->n_heights; ++ht) {   /* the resident bodies' nodes, leaves first (wg_mesh_body.c) */
        int first = g->order_first[ht], count = g->order_first[ht + 1] - first;
        if (count == 0) continue;
        wg_u1i(run, "u_first", first);
        wg_u1i(run, "u_count", count);
        wg_run_groups_rw(run, count, (count + 63) / 64, &ms->mask);
    }
    const GLint zero = 0;
    wg_tex_upload(&ms->counter, 0, 0, 1, 1, &zero);
    for (int k = 0; k < g->n_mesh; ++k) {
        if (!g->resident[k]) continue;
        const wc_mesh_collider* mc = g->mesh[k];
        WG_USE(run, WGP_MESH_PAIRS_FIND_GROUPS, &(wg_mesh_pairs_find_in){.mesh_vert = &g->vert, .mesh_tri = &g->tri,
            .mesh_node = &g->node, .x = x, .v = v, .cfeat = &ms->cfeat, .bedge = &ms->bedge, .bvrow = &ms->bvrow,
            .bvlist = &ms->bvlist, .btri = &ms->btri, .sharp = &ms->sharp, .mask = &ms->mask});
        wg_u1i(run, "u_root", g->node0[k]);
        wg_u1i(run, "u_cap", ms->cap);
        wg_u1i(run, "u_nef", ms->n_edge);
        wg_u1f(run, "u_th", mc->thickness);
        wg_u1f(run, "u_push", mc->push_speed);
        wg_u1f(run, "u_h", h);
        wg_u1f(run, "u_r", 2.0 * mc->thickness + 1.5 * h * mc->max_speed);   /* core's reach */
        wg_run_groups_scratch(run, ms->n_feat, (ms->n_feat + 63) / 64, (const wg_tex* const[]){&ms->out}, 1,
                              &ms->counter);
    }
    GLint count = 0, prev = 0;   /* the counter: a synchronisation with the GPU */
    glGetIntegerv(GL_TEXTURE_BINDING_2D, &prev);
    glBindTexture(GL_TEXTURE_2D, ms->counter.id);
    glGetTexImage(GL_TEXTURE_2D, 0, GL_RED_INTEGER, GL_INT, &count);
    glBindTexture(GL_TEXTURE_2D, (GLuint)prev);
    const int n = count < ms->cap ? count : ms->cap;
    if (n > 0) wg_array_read(run->layout, &ms->out, 3 * n, ms->rb);
    if (bytes) *bytes = sizeof(GLint) + 48 * (size_t)n;
    for (int j = 0; j < n; ++j) {
        const float* r = ms->rb + 12 * (size_t)j;
        ms->order[j] = (found){(int)r[3], (int)r[11], j};
    }
    qsort(ms->order, (size_t)n, sizeof(found), by_feature);
    for (int j = 0; j < n; ++j) {
        const float* r = ms->rb + 12 * (size_t)ms->order[j].at;
        const int cnt = ms->order[j].q < ms->n_we ? 2 : 3;
        int p[3];
        double w[3], nn[3];
        for (int c = 0; c < 3; ++c) {
            p[c] = (int)r[c];
            w[c] = (double)r[4 + c];
            nn[c] = (double)r[8 + c];
        }
        wc_mesh_pairs_add_found(pp, m, f, stick, cnt, p, w, nn, (double)r[7], he);
    }
    pp->list.overflow += count - n;
    return count;
}
