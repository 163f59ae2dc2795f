#include "topology.h"
#include <math.h>
#include <string.h>
#include "sort.h"
#include "union_find.h"

double wc_triangle_area(const double* pos, const int* t) {
    const double* a = pos + 3 * t[0];
    const double* b = pos + 3 * t[1];
    const double* c = pos + 3 * t[2];
    double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    double v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    double x = u[1] * v[2] - u[2] * v[1], y = u[2] * v[0] - u[0] * v[2], z = u[0] * v[1] - u[1] * v[0];
    return 0.5 * sqrt(x * x + y * y + z * z);
}

static void sort3(const int* t, int* s) {
    int a = t[0], b = t[1], c = t[2], x;
    if (a > b) { x = a; a = b; b = x; }
    if (b > c) { x = b; b = c; c = x; }
    if (a > b) { x = a; a = b; b = x; }
    s[0] = a; s[1] = b; s[2] = c;
}

int wc_flag_bad_triangles(const int* tris, int n, const double* pos, double min_area,
                          unsigned char* keep, int* degenerate, int* duplicates,
                          const wc_allocator* alloc) {
    *degenerate = *duplicates = 0;
    wc_keyed* items = WC_NEW(alloc, wc_keyed, n > 0 ? n : 1);
    if (!items) return 0;
    int m = 0;
    for (int t = 0; t < n; ++t) {
        const int* v = tris + 3 * t;
        keep[t] = 1;
        if (v[0] == v[1] || v[1] == v[2] || v[0] == v[2] || !(wc_triangle_area(pos, v) > min_area)) {
            keep[t] = 0;
            ++*degenerate;
            continue;
        }
        int s[3];
        sort3(v, s);
        uint64_t h = (uint64_t)s[0] * 0x9E3779B97F4A7C15ull;
        h = (h ^ (uint64_t)s[1]) * 0xC2B2AE3D27D4EB4Full;
        h = (h ^ (uint64_t)s[2]) * 0x165667B19E3779F9ull;
        items[m].key = h ^ (h >> 31);
        items[m].val = t;
        ++m;
    }
    if (!wc_radix_sort(items, m, 64, alloc)) {
        wc_free(alloc, items);
        return 0;
    }
    /* within a run of equal hashes (stable: ascending triangle index), drop exact repeats */
    for (int i = 0; i < m;) {
        int j = i;
        while (j < m && items[j].key == items[i].key) ++j;
        for (int a = i + 1; a < j; ++a) {
            int sa[3];
            sort3(tris + 3 * items[a].val, sa);
            for (int b = i; b < a; ++b) {
                int sb[3];
                if (!keep[items[b].val]) continue;
                sort3(tris + 3 * items[b].val, sb);
                if (sa[0] == sb[0] && sa[1] == sb[1] && sa[2] == sb[2]) {
                    keep[items[a].val] = 0;
                    ++*duplicates;
                    break;
                }
            }
        }
        i = j;
    }
    wc_free(alloc, items);
    return 1;
}

static void flip(int* tri, unsigned char* mask) {
    /* (v0,v1,v2) -> (v0,v2,v1): old side 2 (v2->v0) becomes side 0, side 1 stays, old side 0
       becomes side 2 */
    int x = tri[1];
    tri[1] = tri[2];
    tri[2] = x;
    if (mask) {
        unsigned char m = *mask;
        *mask = (unsigned char)(((m >> 2) & 1) | (m & 2) | ((m & 1) << 2));
    }
}

wc_keyed* wc_sorted_sides(int n_verts, const int* tris, int n, const wc_allocator* alloc) {
    const int ns = 3 * n;
    wc_keyed* sides = WC_NEW(alloc, wc_keyed, ns > 0 ? ns : 1);
    if (!sides) return NULL;
    for (int t = 0; t < n; ++t)
        for (int k = 0; k < 3; ++k) {
            int a = tris[3 * t + k], b = tris[3 * t + (k + 1) % 3];
            uint64_t lo = (uint64_t)(a < b ? a : b), hi = (uint64_t)(a < b ? b : a);
            sides[3 * t + k].key = lo * (uint64_t)n_verts + hi;
            sides[3 * t + k].val = 3 * t + k;
        }
    if (!wc_radix_sort(sides, ns, wc_bits_for((uint64_t)n_verts * (uint64_t)n_verts), alloc)) {
        wc_free(alloc, sides);
        return NULL;
    }
    return sides;
}

int wc_orient_triangles(int* tris, unsigned char* side_mask, int n, wc_keyed* sides, int* flipped,
                        int* non_orientable, const wc_allocator* alloc) {
    *flipped = *non_orientable = 0;
    if (n == 0) return 1;
    const int ns = 3 * n;
    int* nbr = WC_NEW(alloc, int, ns);          /* side -> the matching side across, or -1 */
    signed char* state = WC_NEW(alloc, signed char, n); /* 0 unvisited, 1 keep, 2 flip */
    int* queue = WC_NEW(alloc, int, n);
    int ok = nbr && state && queue;
    if (ok) {
        for (int s = 0; s < ns; ++s) nbr[s] = -1;
        for (int i = 0; i < ns;) {
            int j = i;
            while (j < ns && sides[j].key == sides[i].key) ++j;
            if (j - i == 2) { /* manifold edge only */
                nbr[sides[i].val] = sides[i + 1].val;
                nbr[sides[i + 1].val] = sides[i].val;
            }
            i = j;
        }
        for (int seed = 0; seed < n; ++seed) {
            if (state[seed]) continue;
            int head = 0, tail = 0, n_flip = 0, conflict = 0;
            state[seed] = 1;
            queue[tail++] = seed;
            while (head < tail) {
                int t = queue[head++];
                for (int k = 0; k < 3; ++k) {
                    int o = nbr[3 * t + k];
                    if (o < 0) continue;
                    int u = o / 3, ku = o % 3;
                    /* same traversal direction of the shared edge? */
                    int same = tris[3 * t + k] == tris[3 * u + ku];
                    int want = (state[t] == 2) ^ same ? 2 : 1;
                    if (!state[u]) {
                        state[u] = (signed char)want;
                        if (want == 2) ++n_flip;
                        queue[tail++] = u;
                    } else if (state[u] != want) {
                        conflict = 1;
                    }
                }
            }
            if (conflict) ++*non_orientable;
            int invert = 2 * n_flip > tail; /* flip the minority */
            for (int q = 0; q < tail; ++q) {
                int t = queue[q];
                int do_flip = (state[t] == 2) != invert;
                state[t] = do_flip ? 2 : 1; /* from here on: 2 = was flipped */
                if (do_flip) {
                    flip(tris + 3 * t, side_mask ? side_mask + t : NULL);
                    ++*flipped;
                }
            }
        }
        /* side k of a flipped triangle is now side 2 - k */
        for (int s = 0; s < ns && *flipped; ++s) {
            int t = sides[s].val / 3, k = sides[s].val % 3;
            if (state[t] == 2) sides[s].val = 3 * t + 2 - k;
        }
    }
    wc_free(alloc, nbr);
    wc_free(alloc, state);
    wc_free(alloc, queue);
    return ok;
}

int wc_components(int n_verts, const int* tris, int n, int* comp, const wc_allocator* alloc) {
    int* parent = WC_NEW(alloc, int, n_verts > 0 ? n_verts : 1);
    if (!parent) return -1;
    for (int v = 0; v < n_verts; ++v) {
        parent[v] = v;
        comp[v] = -1;
    }
    for (int t = 0; t < n; ++t)
        for (int k = 0; k < 2; ++k) {
            wc_uf_union(parent, tris[3 * t + k], tris[3 * t + k + 1]);
        }
    for (int t = 0; t < n; ++t)
        for (int k = 0; k < 3; ++k) comp[tris[3 * t + k]] = -2; /* in a triangle */
    int count = 0;
    for (int v = 0; v < n_verts; ++v) {
        if (comp[v] == -1) continue;
        int r = wc_uf_find(parent, v); /* roots are the lowest index of their set */
        comp[v] = (r == v) ? count++ : comp[r];
    }
    wc_free(alloc, parent);
    return count;
}

int wc_boundary_loops(const wc_winged_edge* we, const wc_allocator* alloc) {
    /* Undirected walk over boundary edges (a non-orientable piece has no consistent direction):
     * each walk follows unvisited boundary edges until it is stuck, which closes one loop when
     * every vertex has an even number of boundary edges (always so on a manifold boundary). */
    int nv = we->n_verts, ne = we->n_edges;
    int* start = WC_NEW(alloc, int, nv + 1);
    int* inc = WC_NEW(alloc, int, 2 * (size_t)ne + 1);
    int* fill = WC_NEW(alloc, int, nv + 1);
    unsigned char* seen = WC_NEW(alloc, unsigned char, ne > 0 ? ne : 1);
    int loops = -1;
    if (start && inc && fill && seen) {
        for (int e = 0; e < ne; ++e)
            if (we->edges[e].f[1] < 0) {
                ++start[we->edges[e].v[0] + 1];
                ++start[we->edges[e].v[1] + 1];
            }
        for (int v = 0; v < nv; ++v) start[v + 1] += start[v];
        for (int v = 0; v < nv; ++v) fill[v] = start[v];
        for (int e = 0; e < ne; ++e)
            if (we->edges[e].f[1] < 0) {
                inc[fill[we->edges[e].v[0]]++] = e;
                inc[fill[we->edges[e].v[1]]++] = e;
            }
        loops = 0;
        for (int e0 = 0; e0 < ne; ++e0) {
            if (we->edges[e0].f[1] >= 0 || seen[e0]) continue;
            ++loops;
            int e = e0, v = we->edges[e0].v[1];
            while (e >= 0) {
                seen[e] = 1;
                int next = -1;
                for (int q = start[v]; q < start[v + 1] && next < 0; ++q)
                    if (!seen[inc[q]]) next = inc[q];
                if (next >= 0) v = we->edges[next].v[0] == v ? we->edges[next].v[1] : we->edges[next].v[0];
                e = next;
            }
        }
    }
    wc_free(alloc, start);
    wc_free(alloc, inc);
    wc_free(alloc, fill);
    wc_free(alloc, seen);
    return loops;
}
