/* Core's self-collision stage on a GPU cloth's substep (wg_self.h): read-backs, the stage on the
 * host, the span of what it moved uploaded. */
#include "wg_self.h"

#include <math.h>
#include <string.h>

#include "vec3.h"

struct wg_self {
    const wg_layout* L;
    int n;
    wc_allocator alloc;
    float* fx;                  /* (n x 4) positions read back, then the uploaded span's */
    float* fv;                  /* (n x 4) velocities, the same */
    double* x;                  /* (n x 3) the stage's positions and velocities */
    double* v;
    double* x0;                 /* (n x 3) the read-back's, for the energy the stage put in */
    double* v0;
    unsigned char* ndof;        /* (n) the stage's filter: 3 for a fully pinned particle */
    wg_self_io io;
};

void wg_self_destroy(wg_self* ws) {
    if (!ws) return;
    wc_allocator a = ws->alloc;
    wc_free(&a, ws->fx);
    wc_free(&a, ws->fv);
    wc_free(&a, ws->x);
    wc_free(&a, ws->v);
    wc_free(&a, ws->x0);
    wc_free(&a, ws->v0);
    wc_free(&a, ws->ndof);
    wc_free(&a, ws);
}

wg_self* wg_self_create(const wg_layout* L, int n, wc_allocator alloc) {
    wg_self* ws = WC_NEW(&alloc, wg_self, 1);
    if (!ws) return NULL;
    ws->L = L;
    ws->n = n;
    ws->alloc = alloc;
    size_t n4 = 4 * (size_t)(n > 0 ? n : 1), n3 = 3 * (size_t)(n > 0 ? n : 1);
    ws->fx = WC_NEW(&alloc, float, n4);
    ws->fv = WC_NEW(&alloc, float, n4);
    ws->x = WC_NEW(&alloc, double, n3);
    ws->v = WC_NEW(&alloc, double, n3);
    ws->x0 = WC_NEW(&alloc, double, n3);
    ws->v0 = WC_NEW(&alloc, double, n3);
    ws->ndof = WC_NEW(&alloc, unsigned char, n3 / 3);
    if (!ws->fx || !ws->fv || !ws->x || !ws->v || !ws->x0 || !ws->v0 || !ws->ndof) {
        wg_self_destroy(ws);
        return NULL;
    }
    return ws;
}

const wg_self_io* wg_self_transfers(const wg_self* ws) { return &ws->io; }

void wg_self_count_proof(wg_self* ws, int idle, long long bytes) {
    ++ws->io.proofs;
    ws->io.skipped += idle != 0;
    ws->io.read_bytes += bytes;
}

void wg_self_count_prox(wg_self* ws, int moved, long long up_bytes) {
    ++ws->io.prox_settled;
    ws->io.prox_moved += moved > 0;
    ws->io.upload_bytes += up_bytes;
}

void wg_self_count_untried(wg_self* ws) { ++ws->io.untried; }

void wg_self_count_check(wg_self* ws, int moved) {
    ++ws->io.checked;
    ws->io.broken += moved != 0;
}

/* n RGBA32F items of t into f (n x 4), and their xyz into d (n x 3, NULL: not converted). */
static void read_back(wg_self* ws, const wg_tex* t, float* f, double* d) {
    wg_array_read(ws->L, t, ws->n, f);
    ws->io.read_bytes += 16LL * ws->n;
    if (!d) return;
    for (int i = 0; i < ws->n; ++i)
        for (int c = 0; c < 3; ++c) d[3 * i + c] = (double)f[4 * i + c];
}

void wg_self_begin(wg_self* ws, wc_self* sc, const wg_tex* x) {
    read_back(ws, x, ws->fx, ws->x);
    wc_self_begin(sc, ws->x);
}

static int all_finite(const double* a, int n) {
    for (int k = 0; k < n; ++k)
        if (!isfinite(a[k])) return 0;
    return 1;
}

/* core's wc_state_total_energy of s's cloth at positions x and velocities v */
static double total_energy(const wc_state* s, double* x, double* v) {
    wc_state at = *s;
    at.x = x;
    at.v = v;
    return wc_state_total_energy(&at, NULL);
}

void wg_self_end(wg_self* ws, wc_self* sc, const wc_state* s, int n_pins, double he, const wg_tex* x,
                 const wg_tex* v, int judge_energy, wc_self_stats* st, double* gain) {
    const int n = ws->n;
    *gain = 0.0;
    ++ws->io.runs;
    read_back(ws, x, ws->fx, ws->x);
    read_back(ws, v, ws->fv, ws->v);
    if (!all_finite(ws->x, 3 * n) || !all_finite(ws->v, 3 * n)) return;
    memset(ws->ndof, 0, (size_t)n);
    for (int k = 0; k < n_pins; ++k)
        if (v3_norm(s->pins[k].free_axis) == 0.0) ws->ndof[s->pins[k].particle] = 3;
    const wc_filter pins = {n, NULL, NULL, ws->ndof};
    sc->threads = s->par.threads;
    wc_self_resolve(sc, s->model, &pins, NULL, he, ws->x, ws->v, st);

    /* the span of the particles it moved */
    int lo = n, hi = -1;
    for (int i = 0; i < n; ++i)
        for (int c = 0; c < 3; ++c)
            if (ws->x[3 * i + c] != (double)ws->fx[4 * i + c] || ws->v[3 * i + c] != (double)ws->fv[4 * i + c]) {
                if (lo == n) lo = i;
                hi = i;
                break;
            }
    if (hi < 0) return;
    if (judge_energy) {
        for (int i = 0; i < n; ++i)
            for (int c = 0; c < 3; ++c) {
                ws->x0[3 * i + c] = (double)ws->fx[4 * i + c];
                ws->v0[3 * i + c] = (double)ws->fv[4 * i + c];
            }
        double e = total_energy(s, ws->x, ws->v) - total_energy(s, ws->x0, ws->v0);
        if (e > 0) *gain = e;
    }
    for (int i = lo; i <= hi; ++i)
        for (int c = 0; c < 3; ++c) {
            ws->fx[4 * i + c] = (float)ws->x[3 * i + c];
            ws->fv[4 * i + c] = (float)ws->v[3 * i + c];
        }
    int count = hi - lo + 1;
    wg_array_upload_range(ws->L, x, lo, count, ws->fx + 4 * (size_t)lo);
    wg_array_upload_range(ws->L, v, lo, count, ws->fv + 4 * (size_t)lo);
    ++ws->io.uploads;
    ws->io.upload_bytes += 32LL * count;
}
