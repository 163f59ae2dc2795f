/* Union-find over int indices whose root is always the lowest index of its set, so numbering
 * sets by their root in index order is deterministic (used by welding and components). */
#ifndef WEFT_CORE_UNION_FIND_H
#define WEFT_CORE_UNION_FIND_H

static inline int wc_uf_find(int* parent, int i) {
    while (parent[i] != i) {
        parent[i] = parent[parent[i]]; /* path halving */
        i = parent[i];
    }
    return i;
}

static inline void wc_uf_union(int* parent, int a, int b) {
    a = wc_uf_find(parent, a);
    b = wc_uf_find(parent, b);
    if (a < b) parent[b] = a;
    else if (b < a) parent[a] = b;
}

#endif
