#include "bvh.h"

#include <math.h>
#include <string.h>

static void box_union(double* o, const double* a, const double* b) {
    for (int k = 0; k < 3; ++k) {
        o[k] = a[k] < b[k] ? a[k] : b[k];
        o[3 + k] = a[3 + k] > b[3 + k] ? a[3 + k] : b[3 + k];
    }
}

static double centre(const double* boxes, int prim, int axis) { return boxes[6 * prim + axis] + boxes[6 * prim + 3 + axis]; }

/* Reorder prims[lo, hi) so that prims[mid] has the median centre along axis, smaller before it,
 * larger after (Hoare's selection; ties are broken by primitive index for a deterministic tree). */
static void select_median(int* prims, int lo, int hi, int mid, const double* boxes, int axis) {
    while (hi - lo > 1) {
        int pivot = prims[lo + (hi - lo) / 2];
        double pc = centre(boxes, pivot, axis);
        int i = lo, j = hi - 1;
        while (i <= j) {
            while (centre(boxes, prims[i], axis) < pc || (centre(boxes, prims[i], axis) == pc && prims[i] < pivot)) ++i;
            while (centre(boxes, prims[j], axis) > pc || (centre(boxes, prims[j], axis) == pc && prims[j] > pivot)) --j;
            if (i <= j) {
                int t = prims[i];
                prims[i] = prims[j];
                prims[j] = t;
                ++i;
                --j;
            }
        }
        if (mid <= j)
            hi = j + 1;
        else if (mid >= i)
            lo = i;
        else
            return;
    }
}

/* Preorder build without recursion: a stack of (node, lo, hi) ranges. */
typedef struct build_item {
    int node, lo, hi;
} build_item;

wc_status wc_bvh_build(wc_bvh* b, const double* boxes, int n, const wc_allocator* alloc, wc_diag* diag) {
    memset(b, 0, sizeof(*b));
    if (alloc) b->alloc = *alloc;
    if (n < 0) return wc_fail(diag, WC_ERROR_INVALID_ARGUMENT, "bvh: %d primitives", n);
    for (int i = 0; i < 6 * n; ++i)
        if (!isfinite(boxes[i])) return wc_fail(diag, WC_ERROR_NONFINITE, "bvh: box of primitive %d is not finite", i / 6);
    b->n_prims = n;
    if (n == 0) return WC_OK;
    b->n_nodes = 2 * n - 1;
    b->box = WC_NEW(&b->alloc, double, (size_t)b->n_nodes * 6);
    b->child = WC_NEW(&b->alloc, int, (size_t)b->n_nodes * 2);
    b->leaf_of = WC_NEW(&b->alloc, int, n);
    int* prims = WC_NEW(&b->alloc, int, n);
    build_item* stack = WC_NEW(&b->alloc, build_item, WC_BVH_MAX_DEPTH + 1);
    if (!b->box || !b->child || !b->leaf_of || !prims || !stack) {
        wc_free(&b->alloc, prims);
        wc_free(&b->alloc, stack);
        wc_bvh_free(b);
        return wc_fail(diag, WC_ERROR_OUT_OF_MEMORY, "bvh: out of memory for %d primitives", n);
    }
    for (int i = 0; i < n; ++i) prims[i] = i;
    int top = 0;
    stack[top++] = (build_item){0, 0, n};
    while (top > 0) {
        build_item it = stack[--top];
        if (it.hi - it.lo == 1) {
            b->child[2 * it.node] = -1;
            b->child[2 * it.node + 1] = prims[it.lo];
            b->leaf_of[prims[it.lo]] = it.node;
            continue;
        }
        double cb[6];
        wc_box_empty(cb);
        for (int i = it.lo; i < it.hi; ++i) {
            double c[3] = {centre(boxes, prims[i], 0), centre(boxes, prims[i], 1), centre(boxes, prims[i], 2)};
            wc_box_add(cb, c);
        }
        int axis = 0;
        for (int k = 1; k < 3; ++k)
            if (cb[3 + k] - cb[k] > cb[3 + axis] - cb[axis]) axis = k;
        int mid = it.lo + (it.hi - it.lo) / 2;
        select_median(prims, it.lo, it.hi, mid, boxes, axis);
        /* left [lo, mid) right after the node, right [mid, hi) after the whole left subtree */
        int left = it.node + 1, right = it.node + 2 * (mid - it.lo);
        b->child[2 * it.node] = left;
        b->child[2 * it.node + 1] = right;
        /* depth: the right half is the larger one; push it first so the stack stays shallow */
        stack[top++] = (build_item){right, mid, it.hi};
        stack[top++] = (build_item){left, it.lo, mid};
    }
    wc_free(&b->alloc, prims);
    wc_free(&b->alloc, stack);
    wc_bvh_refit(b, boxes);
    return WC_OK;
}

void wc_bvh_free(wc_bvh* b) {
    wc_free(&b->alloc, b->box);
    wc_free(&b->alloc, b->child);
    wc_free(&b->alloc, b->leaf_of);
    wc_allocator a = b->alloc;
    memset(b, 0, sizeof(*b));
    b->alloc = a;
}

void wc_bvh_refit_span(wc_bvh* b, const double* boxes, const unsigned char* mask, int lo, int hi) {
    /* children come after their parent (preorder): one backward sweep */
    for (int node = hi - 1; node >= lo; --node) {
        if (mask && !mask[node]) continue;
        const int* ch = b->child + 2 * node;
        if (ch[0] < 0)
            memcpy(b->box + 6 * node, boxes + 6 * ch[1], 6 * sizeof(double));
        else
            box_union(b->box + 6 * node, b->box + 6 * ch[0], b->box + 6 * ch[1]);
    }
}

void wc_bvh_refit(wc_bvh* b, const double* boxes) { wc_bvh_refit_span(b, boxes, NULL, 0, b->n_nodes); }

void wc_bvh_refit_masked(wc_bvh* b, const double* boxes, const unsigned char* mask) {
    wc_bvh_refit_span(b, boxes, mask, 0, b->n_nodes);
}

void wc_bvh_mask_up_span(const wc_bvh* b, unsigned char* mask, int lo, int hi) {
    for (int node = hi - 1; node >= lo; --node) { /* preorder: children after their parent */
        const int* ch = b->child + 2 * node;
        if (ch[0] >= 0) mask[node] = mask[ch[0]] | mask[ch[1]];
    }
}

void wc_bvh_mask_up(const wc_bvh* b, unsigned char* mask) { wc_bvh_mask_up_span(b, mask, 0, b->n_nodes); }

int wc_bvh_heights(const wc_bvh* b, int* h) {
    int top = -1;
    for (int j = b->n_nodes - 1; j >= 0; --j) {   /* children after their parent (preorder) */
        const int* ch = b->child + 2 * j;
        h[j] = ch[0] < 0 ? 0 : 1 + (h[ch[0]] > h[ch[1]] ? h[ch[0]] : h[ch[1]]);
        if (h[j] > top) top = h[j];
    }
    return top;
}

void wc_bvh_refit_top(wc_bvh* b, const wc_bvh_split* s, const unsigned char* mask) {
    for (int k = 0; k < s->n_top; ++k) { /* descending: children first */
        int node = s->top[k];
        if (mask && !mask[node]) continue;
        const int* ch = b->child + 2 * node;
        box_union(b->box + 6 * node, b->box + 6 * ch[0], b->box + 6 * ch[1]);
    }
}

void wc_bvh_mask_up_top(const wc_bvh* b, const wc_bvh_split* s, unsigned char* mask) {
    for (int k = 0; k < s->n_top; ++k) {
        const int* ch = b->child + 2 * s->top[k];
        mask[s->top[k]] = mask[ch[0]] | mask[ch[1]];
    }
}

wc_status wc_bvh_split_build(wc_bvh_split* s, const wc_bvh* b, int depth, const wc_allocator* a) {
    memset(s, 0, sizeof *s);
    int cap = (2 << depth) + 2; /* at most 2^depth subtrees and 2^depth - 1 nodes above them */
    s->sub = WC_NEW(a, int, 2 * (size_t)cap);
    s->top = WC_NEW(a, int, (size_t)cap);
    int* stack = WC_NEW(a, int, 2 * ((size_t)WC_BVH_MAX_DEPTH + 2));
    if (!s->sub || !s->top || !stack) {
        wc_free(a, stack);
        wc_bvh_split_free(s, a);
        return WC_ERROR_OUT_OF_MEMORY;
    }
    /* preorder walk down to depth: a leaf above it or a node at it starts a subtree, which ends
       where the next subtree or node above starts (preorder) */
    int top = 0, n_above = 0;
    if (b->n_nodes > 0) {
        stack[top++] = 0;
        stack[top++] = 0;
    }
    while (top > 0) {
        int d = stack[--top], node = stack[--top];
        const int* ch = b->child + 2 * node;
        if (s->n_sub > 0 && s->sub[2 * s->n_sub - 1] < 0) s->sub[2 * s->n_sub - 1] = node;
        if (ch[0] < 0 || d == depth) {
            s->sub[2 * s->n_sub] = node;
            s->sub[2 * s->n_sub + 1] = -1;
            ++s->n_sub;
            continue;
        }
        s->top[n_above++] = node;
        stack[top++] = ch[1];
        stack[top++] = d + 1;
        stack[top++] = ch[0];
        stack[top++] = d + 1;
    }
    if (s->n_sub > 0 && s->sub[2 * s->n_sub - 1] < 0) s->sub[2 * s->n_sub - 1] = b->n_nodes;
    for (int i = 0, j = n_above - 1; i < j; ++i, --j) { /* descending */
        int t = s->top[i];
        s->top[i] = s->top[j];
        s->top[j] = t;
    }
    s->n_top = n_above;
    wc_free(a, stack);
    return WC_OK;
}

void wc_bvh_split_free(wc_bvh_split* s, const wc_allocator* a) {
    wc_free(a, s->sub);
    wc_free(a, s->top);
    s->sub = s->top = NULL;
    s->n_sub = s->n_top = 0;
}

int wc_bvh_query(const wc_bvh* b, const double* box, wc_bvh_visit_fn visit, void* user) {
    return wc_bvh_query_masked(b, box, NULL, visit, user);
}


/* The nearest-point queries' preorder walk: nodes outside box, masked out (mask) or farther from p than
 * sqrt(*bound2) (p non-NULL) are skipped. */
static int traverse(const wc_bvh* b, const double* box, const unsigned char* mask, const double* p,
                    const double* bound2, wc_bvh_visit_fn visit, void* user) {
    if (b->n_nodes == 0) return 0;
    /* the mask and the box are tested before a node is pushed (they do not change during the
       walk), the bound (which the visits lower) when it is popped, as before: the same nodes
       entered, in the same preorder, without a push and pop for each one the box rejects */
#define NODE_IN(nd) ((!mask || mask[nd]) && wc_box_overlap(b->box + 6 * (nd), box))
    if (!NODE_IN(0)) return 0;
    int stack[WC_BVH_MAX_DEPTH + 2];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
        int node = stack[--top];
        if (p && wc_box_dist2(b->box + 6 * node, p) > *bound2) continue;
        const int* ch = b->child + 2 * node;
        if (ch[0] < 0) {
            int r = visit(user, ch[1]);
            if (r) return r;
        } else {
            if (NODE_IN(ch[1])) stack[top++] = ch[1];
            if (NODE_IN(ch[0])) stack[top++] = ch[0];
        }
    }
#undef NODE_IN
    return 0;
}

/* The box queries' walk: traverse's visits in its order (preorder, left child first), with each
 * child tested before the walk goes down to it rather than after it is popped, and a lone
 * passing child entered without the stack (only a right child whose left sibling also passed
 * waits there): ~20 % fewer instructions than traverse on the dance's dirty self-collision
 * queries (docs/bench/dance_self.md). Not for the nearest-point queries: their bound may fall
 * between a test and the visit. */
int wc_bvh_query_masked(const wc_bvh* b, const double* box, const unsigned char* mask, wc_bvh_visit_fn visit,
                        void* user) {
    if (b->n_nodes == 0 || (mask && !mask[0]) || !wc_box_overlap(b->box, box)) return 0;
    int stack[WC_BVH_MAX_DEPTH + 2];
    int top = 0, node = 0;
    for (;;) {
        const int* ch = b->child + 2 * node;
        if (ch[0] < 0) {
            int r = visit(user, ch[1]);
            if (r) return r;
            if (top == 0) return 0;
            node = stack[--top];
            continue;
        }
        int l = ch[0], rt = ch[1];
        int in_r = !(mask && !mask[rt]) && wc_box_overlap(b->box + 6 * rt, box);
        int in_l = !(mask && !mask[l]) && wc_box_overlap(b->box + 6 * l, box);
        if (in_l) {
            if (in_r) stack[top++] = rt;
            node = l;
        } else if (in_r) {
            node = rt;
        } else {
            if (top == 0) return 0;
            node = stack[--top];
        }
    }
}

int wc_bvh_query_near(const wc_bvh* b, const double* box, const double* p, const double* bound2,
                      wc_bvh_visit_fn visit, void* user) {
    return traverse(b, box, NULL, p, bound2, visit, user);
}
