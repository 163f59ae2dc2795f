/* Spatial hashing with cells of twice the weld distance: any vertex within the distance of p
 * lies in the 2x2x2 block of cells nearest to p, so eight look-ups per vertex suffice.
 * Cell keys are sorted once (radix), candidates found by binary search, pairs merged with a
 * union-find; particle ids follow host order so the result does not depend on the hash. */
#include "weld.h"
#include <math.h>
#include "sort.h"

static uint64_t cell_hash(int64_t x, int64_t y, int64_t z) {
    uint64_t h = (uint64_t)x * 0x9E3779B97F4A7C15ull;
    h ^= (uint64_t)y * 0xC2B2AE3D27D4EB4Full + (h << 6) + (h >> 2);
    h ^= (uint64_t)z * 0x165667B19E3779F9ull + (h << 6) + (h >> 2);
    h ^= h >> 29;
    return h;
}

static int uf_find(int* parent, int i) {
    while (parent[i] != i) {
        parent[i] = parent[parent[i]];
        i = parent[i];
    }
    return i;
}

static void uf_union(int* parent, int a, int b) {
    a = uf_find(parent, a);
    b = uf_find(parent, b);
    if (a == b) return;
    if (a < b) parent[b] = a; /* the root is always the lowest host index */
    else parent[a] = b;
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
        const double cell = 2.0 * distance;
        for (int i = 0; i < n; ++i) {
            if (!used[i]) continue;
            const double* p = pos + 3 * i;
            items[m].key = cell_hash((int64_t)floor(p[0] / cell), (int64_t)floor(p[1] / cell),
                                     (int64_t)floor(p[2] / cell));
            items[m].val = i;
            ++m;
        }
        if (!wc_radix_sort(items, m, 64, alloc)) {
            wc_free(alloc, items);
            wc_free(alloc, parent);
            return -1;
        }
        const double d2 = distance * distance;
        for (int i = 0; i < n; ++i) {
            if (!used[i]) continue;
            const double* p = pos + 3 * i;
            int64_t c[3], s[3];
            for (int k = 0; k < 3; ++k) {
                double f = p[k] / cell;
                c[k] = (int64_t)floor(f);
                s[k] = (f - (double)c[k] < 0.5) ? -1 : 1;
            }
            for (int q = 0; q < 8; ++q) {
                uint64_t key = cell_hash(c[0] + ((q & 1) ? s[0] : 0), c[1] + ((q & 2) ? s[1] : 0),
                                         c[2] + ((q & 4) ? s[2] : 0));
                for (int j = lower_bound(items, m, key); j < m && items[j].key == key; ++j) {
                    int o = items[j].val;
                    if (o >= i) continue; /* each pair once, from its higher index */
                    const double* r = pos + 3 * o;
                    double dx = p[0] - r[0], dy = p[1] - r[1], dz = p[2] - r[2];
                    if (dx * dx + dy * dy + dz * dz <= d2) uf_union(parent, i, o);
                }
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
        int r = uf_find(parent, i);
        /* roots are the lowest index of their set, so they are visited first */
        to_particle[i] = (r == i) ? count++ : to_particle[r];
    }
    wc_free(alloc, parent);
    return count;
}
