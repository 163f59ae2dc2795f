/* Winged-edge construction: the 3F triangle sides sorted by vertex pair (one radix sort, shared
 * with the orientation pass) give the edges in O(F), then faces and wings are filled in one pass. */
#include "winged_edge.h"
#include <string.h>
#include "sort.h"

void wc_winged_edge_free(wc_winged_edge* we, const wc_allocator* alloc) {
    if (!we) return;
    wc_free(alloc, we->vert_edge);
    wc_free(alloc, we->edges);
    wc_free(alloc, we->faces);
    memset(we, 0, sizeof *we);
}

int wc_we_opposite_vertex(const wc_winged_edge* we, int f, int e) {
    if (f < 0 || f >= we->n_faces) return -1;
    const wc_we_face* face = &we->faces[f];
    for (int k = 0; k < 3; ++k)
        if (face->e[k] == e) return face->v[(k + 2) % 3];
    return -1;
}

wc_status wc_winged_edge_build_sorted(wc_winged_edge* we, const wc_allocator* alloc, int n_verts,
                                        const int* tris, int n_faces, const unsigned char* side_polygon,
                                        const wc_keyed* sides, wc_diag* diag) {
    memset(we, 0, sizeof *we);
    if (n_verts < 0 || n_faces < 0 || (n_faces > 0 && (!tris || !sides)))
        return wc_fail(diag, WC_ERROR_INVALID_ARGUMENT, "winged edge: bad arguments");
    const int n_sides = 3 * n_faces;
    for (int f = 0; f < n_faces; ++f) {
        const int* t = tris + 3 * f;
        for (int k = 0; k < 3; ++k)
            if (t[k] < 0 || t[k] >= n_verts || t[k] == t[(k + 1) % 3])
                return wc_fail(diag, WC_ERROR_INVALID_ARGUMENT,
                               "winged edge: face %d has a bad or repeated vertex", f);
    }
    we->vert_edge = WC_NEW(alloc, int, n_verts > 0 ? n_verts : 1);
    we->faces = WC_NEW(alloc, wc_we_face, n_faces > 0 ? n_faces : 1);
    /* at most one edge per side */
    we->edges = WC_NEW(alloc, wc_we_edge, n_sides > 0 ? n_sides : 1);
    if (!we->vert_edge || !we->faces || !we->edges) goto oom;
    for (int f = 0; f < n_faces; ++f)
        for (int k = 0; k < 3; ++k) we->faces[f].v[k] = tris[3 * f + k];

    int ne = 0;
    for (int i = 0; i < n_sides;) {
        int j = i;
        while (j < n_sides && sides[j].key == sides[i].key) ++j;
        int shared = j - i;
        for (int s = i; s < j; ++s) {
            int f = sides[s].val / 3, k = sides[s].val % 3;
            int slot = (s - i < 2) ? s - i : 0;
            if (s - i == 0 || s - i >= 2) { /* open a new edge (copies for faces beyond two) */
                wc_we_edge* e = &we->edges[ne++];
                int a = tris[3 * f + k], b = tris[3 * f + (k + 1) % 3];
                e->v[0] = a < b ? a : b;
                e->v[1] = a < b ? b : a;
                e->f[0] = e->f[1] = -1;
                e->prev[0] = e->prev[1] = e->next[0] = e->next[1] = -1;
                e->flags = shared > 2 ? WC_EDGE_NON_MANIFOLD : 0;
            }
            wc_we_edge* e = &we->edges[ne - 1];
            e->f[slot] = f;
            if (!side_polygon || (side_polygon[f] >> k) & 1) e->flags |= WC_EDGE_POLYGON;
            we->faces[f].e[k] = ne - 1;
        }
        i = j;
    }
    /* Wings: the edges before and after this one in each adjacent face. */
    for (int e = 0; e < ne; ++e) {
        wc_we_edge* ed = &we->edges[e];
        for (int s = 0; s < 2; ++s) {
            int f = ed->f[s];
            if (f < 0) continue;
            for (int k = 0; k < 3; ++k) {
                if (we->faces[f].e[k] != e) continue;
                ed->prev[s] = we->faces[f].e[(k + 2) % 3];
                ed->next[s] = we->faces[f].e[(k + 1) % 3];
            }
        }
    }
    for (int v = 0; v < n_verts; ++v) we->vert_edge[v] = -1;
    for (int e = ne - 1; e >= 0; --e) {
        we->vert_edge[we->edges[e].v[0]] = e;
        we->vert_edge[we->edges[e].v[1]] = e;
    }
    we->n_verts = n_verts;
    we->n_edges = ne;
    we->n_faces = n_faces;
    return WC_OK;

oom:
    wc_winged_edge_free(we, alloc);
    return wc_fail(diag, WC_ERROR_OUT_OF_MEMORY, "winged edge: out of memory (%d faces)", n_faces);
}
