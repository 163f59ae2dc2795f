/* Welding by spatial hashing. Cells are WELD_CELL times the weld distance, so a vertex needs to
 * look into a neighbouring cell only along axes where it lies within the distance of a cell
 * face (about 2 / WELD_CELL of vertices per axis); everything else is found inside its own cell.
 * Cell keys (a hash truncated to 44 bits: collisions only add candidates, every pair is checked
 * by distance) are radix-sorted once; pairs are merged with a union-find whose root is the
 * lowest host index, so particle ids follow host order and do not depend on the hash. */
#include "weld.h"
#include <math.h>
#include "sort.h"
#include "union_find.h"

enum { WELD_CELL = 64, KEY_BITS = 44, SMALL_GROUP = 24 };

/* The cell index of coordinate / cell = f, clamped to +-2^52 so that the conversion is defined
 * for any coordinate (a fuzzed mesh had 1e42 m; NaN goes to the lower bound). Clamping only
 * merges cells far beyond any mesh's size into the last one, where the exact distance test still
 * decides; for such a vertex the face test below may look into a neighbouring cell for nothing. */
static int64_t cell_of(double f) {
    const double lim = 4503599627370496.0; /* 2^52 */
    f = floor(f);
    if (!(f > -lim)) f = -lim;
    else if (f > lim) f = lim;
    return (int64_t)f;
}

static uint64_t cell_hash(int64_t x, int64_t y, int64_t z) {
    uint64_t h = (uint64_t)x * 0x9E3779B97F4A7C15ull;
    h ^= (uint64_t)y * 0xC2B2AE3D27D4EB4Full + (h << 6) + (h >> 2);
    h ^= (uint64_t)z * 0x165667B19E3779F9ull + (h << 6) + (h >> 2);
    h ^= h >> 29;
    return h & ((1ull << KEY_BITS) - 1);
}

/* First index in sorted items with key >= k. */
static int lower_bound(const wc_keyed* items, int n, uint64_t k) {
    int lo = 0, hi = n;
    while (lo < hi) {
        int mid = lo + (hi - lo) / 2;
        if (items[mid].key < k) lo = mid + 1;
        else hi = mid;
    }
    return lo;
}

static int close_enough(const double* pos, int a, int b, double d2) {
    const double* p = pos + 3 * a;
    const double* q = pos + 3 * b;
    double dx = p[0] - q[0], dy = p[1] - q[1], dz = p[2] - q[2];
    return dx * dx + dy * dy + dz * dz <= d2;
}

static int cmp_x(const void* a, const void* b, const double* pos) {
    double x = pos[3 * ((const wc_keyed*)a)->val], y = pos[3 * ((const wc_keyed*)b)->val];
    return (x > y) - (x < y);
}

/* Insertion sort of a (large, rare) group by x so it can be swept. */
static void sort_group_by_x(wc_keyed* g, int n, const double* pos) {
    for (int i = 1; i < n; ++i) {
        wc_keyed v = g[i];
        int j = i - 1;
        while (j >= 0 && cmp_x(&g[j], &v, pos) > 0) {
            g[j + 1] = g[j];
            --j;
        }
        g[j + 1] = v;
    }
}

int wc_weld(const double* pos, const unsigned char* used, int n, double distance, int* to_particle,
            const wc_allocator* alloc) {
    int* parent = WC_NEW(alloc, int, n > 0 ? n : 1);
    if (!parent) return -1;
    for (int i = 0; i < n; ++i) parent[i] = i;

    if (distance > 0.0 && n > 1) {
        int m = 0;
        wc_keyed* items = WC_NEW(alloc, wc_keyed, n);
        if (!items) {
            wc_free(alloc, parent);
            return -1;
        }
        const double cell = WELD_CELL * distance, d2 = distance * distance;
        for (int i = 0; i < n; ++i) {
            if (!used[i]) continue;
            const double* p = pos + 3 * i;
            items[m].key = cell_hash(cell_of(p[0] / cell), cell_of(p[1] / cell), cell_of(p[2] / cell));
            items[m].val = i;
            ++m;
        }
        if (!wc_radix_sort(items, m, KEY_BITS, alloc)) {
            wc_free(alloc, items);
            wc_free(alloc, parent);
            return -1;
        }
        /* pairs inside one cell (same key) */
        for (int s = 0; s < m;) {
            int e = s + 1;
            while (e < m && items[e].key == items[s].key) ++e;
            if (e - s <= SMALL_GROUP) {
                for (int a = s + 1; a < e; ++a)
                    for (int b = s; b < a; ++b)
                        if (close_enough(pos, items[a].val, items[b].val, d2)) wc_uf_union(parent, items[a].val, items[b].val);
            } else { /* a crowded cell: sweep along x */
                sort_group_by_x(items + s, e - s, pos);
                for (int a = s + 1; a < e; ++a)
                    for (int b = a - 1; b >= s && pos[3 * items[a].val] - pos[3 * items[b].val] <= distance; --b)
                        if (close_enough(pos, items[a].val, items[b].val, d2)) wc_uf_union(parent, items[a].val, items[b].val);
            }
            s = e;
        }
        /* pairs across cell faces: only vertices within the distance of a face look next door */
        for (int i = 0; i < n; ++i) {
            if (!used[i]) continue;
            const double* p = pos + 3 * i;
            int64_t c[3], s[3];
            int near_any = 0;
            for (int k = 0; k < 3; ++k) {
                double f = p[k] / cell;
                c[k] = cell_of(f);
                double off = (f - (double)c[k]) * cell; /* distance to the lower face */
                s[k] = off <= distance ? -1 : (cell - off <= distance ? 1 : 0);
                near_any |= s[k] != 0;
            }
            if (!near_any) continue;
            for (int q = 1; q < 8; ++q) {
                if (((q & 1) && !s[0]) || ((q & 2) && !s[1]) || ((q & 4) && !s[2])) continue;
                uint64_t key = cell_hash(c[0] + ((q & 1) ? s[0] : 0), c[1] + ((q & 2) ? s[1] : 0),
                                         c[2] + ((q & 4) ? s[2] : 0));
                for (int j = lower_bound(items, m, key); j < m && items[j].key == key; ++j)
                    if (items[j].val != i && close_enough(pos, i, items[j].val, d2)) wc_uf_union(parent, i, items[j].val);
            }
        }
        wc_free(alloc, items);
    }

    int count = 0;
    for (int i = 0; i < n; ++i) {
        if (!used[i]) {
            to_particle[i] = -1;
            continue;
        }
        int r = wc_uf_find(parent, i);
        /* roots are the lowest index of their set, so they are visited first */
        to_particle[i] = (r == i) ? count++ : to_particle[r];
    }
    wc_free(alloc, parent);
    return count;
}
