/* Many cloths stepped in one call (wc_cloth_step_batch, cloth.h), in groups: the cloths of one
 * backend and device (a context that chose the backend per cloth holds a CPU group and a GPU
 * group), one group after the other.
 *
 * One begin/end of the device holds every frame of its group: on the GPU one switch to its GL context
 * for the whole batch, the cloths' pass chains run one after the other in it. On a backend whose
 * cloths share nothing (`concurrent`: the CPU) the cloths are stepped at once over the cloths'
 * threads T, when there are at least T of them: each cloth then runs on one thread (its state's
 * thread count set to 1 for its step, then put back), the threads taking the next cloth as they
 * finish one (dynamic schedule), the largest cloths first so that a big one does not start last.
 * With fewer cloths than threads each cloth in turn gets all T threads, as in wc_cloth_step:
 * splitting T between a few cloths would need nested parallel regions (inactive by default), and
 * one cloth per thread leaves threads idle. Both give each cloth the bits of wc_cloth_step: core's
 * parallel loops use fixed ranges and ordered reductions, so a step's result does not depend on
 * its thread count (par.h; tests/test_self_threads.c, tests/test_api_batch.c).
 * Nothing is allocated. */
#include <string.h>
#include "clock.h"
#include "cloth_internal.h"

/* Step one item; one_thread: its cloth runs on one thread. */
static void step_item(wc_cloth_batch_item* it, int one_thread) {
    wc_par* par = &it->cloth->state->par;
    const int threads = par->threads;
    if (one_thread) par->threads = 1;
    double t0 = wc_now_ms();
    it->status = wc_cloth_step_grouped(it->cloth, &it->frame, &it->stats, &it->diag);
    it->ms = wc_now_ms() - t0;
    par->threads = threads;
}

/* Larger cloths (particles) first; ties in the caller's order. */
static int larger_first(const wc_cloth_batch_item* x, const wc_cloth_batch_item* y) {
    int nx = x->cloth->model.n_particles, ny = y->cloth->model.n_particles;
    if (nx != ny) return nx > ny ? -1 : 1;
    return (x->index > y->index) - (x->index < y->index);
}

static int by_index(const wc_cloth_batch_item* x, const wc_cloth_batch_item* y) {
    return (x->index > y->index) - (x->index < y->index);
}

/* Insertion sort in place: a batch is tens of cloths, and qsort may call malloc (glibc's merge
 * sort does for arrays over 1 KB), which a step must not. */
static void sort_items(wc_cloth_batch_item* items, int n,
                       int (*cmp)(const wc_cloth_batch_item*, const wc_cloth_batch_item*)) {
    for (int k = 1; k < n; ++k) {
        if (cmp(&items[k - 1], &items[k]) <= 0) continue;
        wc_cloth_batch_item t = items[k];
        int j = k;
        for (; j > 0 && cmp(&items[j - 1], &t) > 0; --j) items[j] = items[j - 1];
        items[j] = t;
    }
}

void wc_cloth_batch_sort_by_index(wc_cloth_batch_item* items, int n) { sort_items(items, n, by_index); }

/* Step one group: items of one backend and device, inside one begin/end of it. */
static wc_status step_group(wc_cloth_batch_item* items, int n, wc_diag* d) {
    const wc_cloth_backend* b = items[0].cloth->backend;
    void* device = items[0].cloth->device;
    wc_status st = b->begin(device, d);
    if (st != WC_OK) {
        for (int k = 0; k < n; ++k) {
            memset(&items[k].stats, 0, sizeof items[k].stats);
            items[k].status = st;
            items[k].ms = 0.0;
            memcpy(items[k].diag.message, d->message, sizeof d->message);
            items[k].diag.status = st;
        }
        return st;
    }
    int threads = 1;
    for (int k = 0; k < n; ++k)
        if (items[k].cloth->state->par.threads > threads) threads = items[k].cloth->state->par.threads;
    if (b->concurrent && threads > 1 && n >= threads) {
        sort_items(items, n, larger_first);
#ifdef _OPENMP
#pragma omp parallel for num_threads(threads) schedule(dynamic, 1)
#endif
        for (int k = 0; k < n; ++k) step_item(&items[k], 1);
    } else {
        for (int k = 0; k < n; ++k) step_item(&items[k], 0);
    }
    b->end(device);
    return WC_OK;
}

static int same_group(const wc_cloth* x, const wc_cloth* y) { return x->backend == y->backend && x->device == y->device; }

wc_status wc_cloth_step_batch(wc_cloth_batch_item* items, int n, wc_diag* d) {
    wc_status result = WC_OK;
    /* the items of the first cloth's backend and device to the front (in place), stepped as one
       group; then the next group from what is left */
    for (int start = 0; start < n;) {
        int end = start + 1;
        for (int k = end; k < n; ++k)
            if (same_group(items[k].cloth, items[start].cloth)) {
                wc_cloth_batch_item t = items[end];
                items[end] = items[k];
                items[k] = t;
                ++end;
            }
        wc_status st = step_group(items + start, end - start, d);
        if (st != WC_OK && result == WC_OK) result = st;
        start = end;
    }
    return result;
}
