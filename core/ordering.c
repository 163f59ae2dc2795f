#include "ordering.h"
#include <string.h>

typedef struct graph {
    int n;
    int* start;   /* (n + 1) */
    int* adj;     /* (6 n_tris) neighbours, sorted by (degree, index) per particle */
} graph;

/* BFS from root over unvisited particles, writing the visit order into queue from *tail. Marks
 * level[] and returns the last level's first particle of lowest degree (pseudo-peripheral
 * candidate). */
static int bfs(const graph* g, int root, int* level, int* queue, int* count, int* depth_out) {
    int head = *count, tail = *count;
    queue[tail++] = root;
    level[root] = 0;
    int last = root, depth = 0;
    while (head < tail) {
        int u = queue[head++];
        if (level[u] > depth || (level[u] == depth && g->start[u + 1] - g->start[u] < g->start[last + 1] - g->start[last])) {
            depth = level[u];
            last = u;
        }
        for (int k = g->start[u]; k < g->start[u + 1]; ++k) {
            int w = g->adj[k];
            if (level[w] < 0) {
                level[w] = level[u] + 1;
                queue[tail++] = w;
            }
        }
    }
    *count = tail;
    *depth_out = depth;
    return last;
}

int wc_order_rcm(int n, const int* tris, int n_tris, int* new_index, const wc_allocator* a) {
    graph g = {n, WC_NEW(a, int, (size_t)n + 1), WC_NEW(a, int, 6 * (size_t)n_tris + 1)};
    int* level = WC_NEW(a, int, (size_t)n + 1);
    int* queue = WC_NEW(a, int, (size_t)n + 1);
    int* fill = WC_NEW(a, int, (size_t)n + 1);
    int ok = g.start && g.adj && level && queue && fill;
    if (ok) {
        for (int t = 0; t < n_tris; ++t)
            for (int k = 0; k < 3; ++k) g.start[tris[3 * t + k] + 1] += 2;
        for (int i = 0; i < n; ++i) g.start[i + 1] += g.start[i];
        memcpy(fill, g.start, sizeof(int) * (size_t)n);
        for (int t = 0; t < n_tris; ++t)
            for (int k = 0; k < 3; ++k) {
                int u = tris[3 * t + k];
                g.adj[fill[u]++] = tris[3 * t + (k + 1) % 3];
                g.adj[fill[u]++] = tris[3 * t + (k + 2) % 3];
            }
        /* neighbours by (degree, index), duplicates kept (harmless for BFS): insertion sort,
           rows are short */
        for (int u = 0; u < n; ++u)
            for (int k = g.start[u] + 1; k < g.start[u + 1]; ++k) {
                int w = g.adj[k], dw = g.start[w + 1] - g.start[w], j = k - 1;
                while (j >= g.start[u]) {
                    int x = g.adj[j], dx = g.start[x + 1] - g.start[x];
                    if (dx < dw || (dx == dw && x <= w)) break;
                    g.adj[j + 1] = x;
                    --j;
                }
                g.adj[j + 1] = w;
            }
        for (int i = 0; i < n; ++i) level[i] = -1;
        int count = 0;
        for (int root = 0; root < n; ++root) {
            if (level[root] >= 0) continue;
            /* pseudo-peripheral start: repeat BFS from the far end while the depth grows */
            int start = count, depth = 0;
            int far = bfs(&g, root, level, queue, &count, &depth);
            for (int it = 0; it < 8; ++it) {
                for (int k = start; k < count; ++k) level[queue[k]] = -1;
                count = start;
                int d2 = 0;
                int far2 = bfs(&g, far, level, queue, &count, &d2);
                if (d2 <= depth) break;
                depth = d2;
                far = far2;
            }
        }
        /* reverse: the last visited particle gets index 0 */
        for (int k = 0; k < n; ++k) new_index[queue[k]] = n - 1 - k;
    }
    wc_free(a, g.start);
    wc_free(a, g.adj);
    wc_free(a, level);
    wc_free(a, queue);
    wc_free(a, fill);
    return ok ? 0 : -1;
}
