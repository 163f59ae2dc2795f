/* Core's proximity pass on the GPU's listed pairs (wg_self_prox.h). */
#include "wg_self_prox.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "energy_memo.h"
#include "forces.h"
#include "self_pass.h"
#include "vec3.h"

typedef struct prox_pair {
    int q, leaf, elem, marked;
} prox_pair;

struct wg_self_prox {
    const wg_layout* L;
    int n;
    wc_allocator alloc;
    float* buf;                 /* (52 x cap) the list read back */
    prox_pair* order;           /* (cap) the pairs in core's order */
    double* x;                  /* (n x 3) the pass's positions and velocities (listed particles only) */
    double* v;
    float* f;                   /* (n x 8) a listed particle's x and v as read (the restore) */
    int* ids;                   /* (8 cap) the listed particles (both lists), each once */
    int* mv;                    /* (4 cap) the particles the pass moved */
    unsigned char* seen;        /* (n) 1 for a listed particle (cleared after each run) */
    unsigned char* touched;     /* (n) core's touched set of the pass (cleared after each run) */
    unsigned char* pinned;      /* (n) 1 for a fully pinned particle (set and cleared each run) */
    float* rb;                  /* (n x 4) a whole array read back (the energy judge's gain) */
    double *xa, *va;            /* (n x 3) the whole state, for the gain */
    int* sp_first;              /* (n + 1) the springs incident to each particle (CSR) */
    int* sp_of;                 /* (2 n_springs) */
    unsigned char* sp_mark;     /* (n_springs) a spring taken into the local gain (cleared after) */
    int* sp_list;               /* (n_springs) those springs */
    unsigned char* mvf;         /* (n) 1 for a particle the pass moved (cleared after each run) */
    int* gather;                /* (n) the neighbours whose x is read back for the local gain */
    float* gx;                  /* (n x 4) their x read back */
    int refined_mode;           /* WEFT_GPU_SELF_PROX_REFINED: 0 the margin, 1 always walk, 2 check */
    int gain_mode;              /* WEFT_GPU_SELF_PROX_GAIN: 0 local, 1 full, 2 both (compared) */
    wg_self_prox_io io;
};

int wg_self_prox_env(void) {
    const char* e = getenv("WEFT_GPU_SELF_PROX");
    if (!e) return 0;
    if (strcmp(e, "on") == 0) return -1;
    const int room = atoi(e);
    return room > 0 ? (room < WG_SELF_PROX_CAP ? room : WG_SELF_PROX_CAP) : 0;
}

void wg_self_prox_destroy(wg_self_prox* p) {
    if (!p) return;
    wc_allocator a = p->alloc;
    wc_free(&a, p->buf);
    wc_free(&a, p->order);
    wc_free(&a, p->x);
    wc_free(&a, p->v);
    wc_free(&a, p->f);
    wc_free(&a, p->ids);
    wc_free(&a, p->mv);
    wc_free(&a, p->seen);
    wc_free(&a, p->touched);
    wc_free(&a, p->pinned);
    wc_free(&a, p->rb);
    wc_free(&a, p->xa);
    wc_free(&a, p->va);
    wc_free(&a, p->sp_first);
    wc_free(&a, p->sp_of);
    wc_free(&a, p->sp_mark);
    wc_free(&a, p->sp_list);
    wc_free(&a, p->gather);
    wc_free(&a, p->mvf);
    wc_free(&a, p->gx);
    wc_free(&a, p);
}

/* the springs incident to each particle (the local gain's) */
static int build_incidence(wg_self_prox* p, const wc_model* m) {
    const size_t ns = (size_t)(m->n_springs > 0 ? m->n_springs : 1);
    p->sp_first = wc_calloc(&p->alloc, (size_t)p->n + 2, sizeof(int));
    p->sp_of = wc_calloc(&p->alloc, 2 * ns, sizeof(int));
    p->sp_mark = wc_calloc(&p->alloc, ns, 1);
    p->sp_list = wc_calloc(&p->alloc, ns, sizeof(int));
    if (!p->sp_first || !p->sp_of || !p->sp_mark || !p->sp_list) return 0;
    for (int k = 0; k < m->n_springs; ++k) {
        ++p->sp_first[m->springs[k].a + 1];
        ++p->sp_first[m->springs[k].b + 1];
    }
    for (int i = 0; i < p->n; ++i) p->sp_first[i + 1] += p->sp_first[i];
    int* at = p->gather;   /* scratch (n) */
    memcpy(at, p->sp_first, (size_t)p->n * sizeof(int));
    for (int k = 0; k < m->n_springs; ++k) {
        p->sp_of[at[m->springs[k].a]++] = k;
        p->sp_of[at[m->springs[k].b]++] = k;
    }
    return 1;
}

static int env_is(const char* name, const char* value) {
    const char* e = getenv(name);
    return e && strcmp(e, value) == 0;
}

wg_self_prox* wg_self_prox_create(const wg_layout* L, const wc_model* m, wc_allocator alloc) {
    const int n = m->n_particles;
    wg_self_prox* p = wc_calloc(&alloc, 1, sizeof *p);
    if (!p) return NULL;
    p->L = L;
    p->n = n;
    p->alloc = alloc;
    size_t nn = (size_t)(n > 0 ? n : 1), cap = WG_SELF_PROX_CAP;
    p->buf = wc_calloc(&alloc, 52 * cap, sizeof(float));
    p->order = wc_calloc(&alloc, cap, sizeof(prox_pair));
    p->x = wc_calloc(&alloc, 3 * nn, sizeof(double));
    p->v = wc_calloc(&alloc, 3 * nn, sizeof(double));
    p->f = wc_calloc(&alloc, 8 * nn, sizeof(float));
    p->ids = wc_calloc(&alloc, 8 * cap, sizeof(int));
    p->mv = wc_calloc(&alloc, 4 * cap, sizeof(int));
    p->seen = wc_calloc(&alloc, nn, 1);
    p->touched = wc_calloc(&alloc, nn, 1);
    p->pinned = wc_calloc(&alloc, nn, 1);
    p->rb = wc_calloc(&alloc, 4 * nn, sizeof(float));
    p->xa = wc_calloc(&alloc, 3 * nn, sizeof(double));
    p->va = wc_calloc(&alloc, 3 * nn, sizeof(double));
    p->gather = wc_calloc(&alloc, nn, sizeof(int));
    p->gx = wc_calloc(&alloc, 4 * nn, sizeof(float));
    p->mvf = wc_calloc(&alloc, nn, 1);
    p->refined_mode = env_is("WEFT_GPU_SELF_PROX_REFINED", "walk")    ? 1
                      : env_is("WEFT_GPU_SELF_PROX_REFINED", "check") ? 2
                                                                       : 0;
    p->gain_mode = env_is("WEFT_GPU_SELF_PROX_GAIN", "full") ? 1 : env_is("WEFT_GPU_SELF_PROX_GAIN", "both") ? 2 : 0;
    if (!p->gather || !p->gx || !p->mvf || !build_incidence(p, m)) {
        wg_self_prox_destroy(p);
        return NULL;
    }
    if (!p->buf || !p->order || !p->x || !p->v || !p->f || !p->ids || !p->seen || !p->pinned || !p->rb || !p->xa ||
        !p->va || !p->mv || !p->touched) {
        wg_self_prox_destroy(p);
        return NULL;
    }
    return p;
}

int wg_self_prox_cap(int n, int env) {
    if (env > 0) return env;
    return n / 8 < 16 ? 16 : n / 8 > WG_SELF_PROX_CAP ? WG_SELF_PROX_CAP : n / 8;
}

float* wg_self_prox_buffer(wg_self_prox* p) { return p->buf; }

/* core's visit order: by query, then by the element's leaf (preorder) */
static int by_walk(const void* a, const void* b) {
    const prox_pair *u = a, *w = b;
    if (u->q != w->q) return u->q < w->q ? -1 : 1;
    return (u->leaf > w->leaf) - (u->leaf < w->leaf);
}

/* the whole array t (n RGBA32F texels) read back into d (n x 3) */
static void read_all(wg_self_prox* p, const wg_tex* t, double* d, long long* bytes) {
    wg_array_read(p->L, t, p->n, p->rb);
    *bytes += 16LL * p->n;
    for (int i = 0; i < p->n; ++i)
        for (int c = 0; c < 3; ++c) d[3 * i + c] = (double)p->rb[4 * i + c];
}

/* core's wc_state_total_energy of s's cloth at x, v */
static double total_energy(const wc_state* s, double* x, double* v) {
    wc_state at = *s;
    at.x = x;
    at.v = v;
    return wc_state_total_energy(&at, NULL);
}

/* The energy the pass put in, as wg_self_end measures the stage's: the state read back with the
 * moved particles (the first nm of ids) at the pass's double values, less the state before it. */
static double gain(wg_self_prox* p, const wc_state* s, const wg_tex* x, const wg_tex* v, int nm, long long* bytes,
                   double* total) {
    read_all(p, x, p->xa, bytes);
    read_all(p, v, p->va, bytes);
    for (int u = 0; u < nm; ++u) {
        const int i = p->mv[u];
        memcpy(p->xa + 3 * (size_t)i, p->x + 3 * (size_t)i, 3 * sizeof(double));
        memcpy(p->va + 3 * (size_t)i, p->v + 3 * (size_t)i, 3 * sizeof(double));
    }
    const double after = total_energy(s, p->xa, p->va);
    *total = after;
    for (int u = 0; u < nm; ++u) {
        const int i = p->mv[u];
        const float* fo = p->f + 8 * (size_t)i;
        for (int c = 0; c < 3; ++c) {
            p->xa[3 * i + c] = (double)fo[c];
            p->va[3 * i + c] = (double)fo[4 + c];
        }
    }
    return after - total_energy(s, p->xa, p->va);   /* not clamped: judge_gain clamps */
}

/* spring k's energy (core's wc_spring_energy_at term) at a's and b's positions */
static double spring_energy(const wc_model* m, const wc_spring* sp, const double* xa, const double* xb, double seam) {
    double L[3];
    v3_sub(L, xa, xb);
    const double dl = wc_spring_extension(sp, v3_norm(L), seam);
    return 0.5 * m->material.k[sp->type] * sp->w * dl * dl;
}

/* The energy the pass put in, from the moved particles (the first nm of mv) alone: their kinetic
 * and gravitational terms and the springs incident to them, before (as read, f) and after (the
 * pass's doubles); a spring's other end not moved is at its x on the GPU: from the list where it
 * was listed (f), else read back (16 bytes a particle, one synchronisation). The same sum as
 * gain()'s total difference but for rounding: core's total sums every particle and spring. */
static double local_gain(wg_self_prox* p, const wc_state* s, const wg_tex* x, int nm, long long* bytes) {
    const wc_model* m = s->model;
    const double* g = s->def.gravity;
    double e = 0.0;
    int nsp = 0, ng = 0;
    for (int u = 0; u < nm; ++u) {
        const int i = p->mv[u];
        const float* fo = p->f + 8 * (size_t)i;
        const double* xn = p->x + 3 * (size_t)i;
        const double* vn = p->v + 3 * (size_t)i;
        const double xo[3] = {fo[0], fo[1], fo[2]}, vo[3] = {fo[4], fo[5], fo[6]};
        e += 0.5 * m->mass[i] * (v3_dot(vn, vn) - v3_dot(vo, vo)) - m->mass[i] * (v3_dot(g, xn) - v3_dot(g, xo));
        for (int k = p->sp_first[i]; k < p->sp_first[i + 1]; ++k) {
            const int sk = p->sp_of[k];
            if (p->sp_mark[sk]) continue;
            p->sp_mark[sk] = 1;
            p->sp_list[nsp++] = sk;
            const int o = m->springs[sk].a == i ? m->springs[sk].b : m->springs[sk].a;
            if (p->seen[o]) continue;
            p->seen[o] = 2;   /* read back (cleared below) */
            p->gather[ng++] = o;
        }
    }
    if (ng > 0) {
        wg_array_read_items(p->L, x, p->gather, ng, p->gx);
        *bytes += 16LL * ng;
        for (int u = 0; u < ng; ++u) memcpy(p->f + 8 * (size_t)p->gather[u], p->gx + 4 * (size_t)u, 4 * sizeof(float));
    }
    /* p->seen: 1 listed (x in f; moved ones at x after), 2 read back (x in f) */
    for (int u = 0; u < nsp; ++u) {
        const wc_spring* sp = &m->springs[p->sp_list[u]];
        const float *fa = p->f + 8 * (size_t)sp->a, *fb = p->f + 8 * (size_t)sp->b;
        const double xa0[3] = {fa[0], fa[1], fa[2]}, xb0[3] = {fb[0], fb[1], fb[2]};
        const int ma = p->mvf[sp->a], mb = p->mvf[sp->b];
        const double* xa1 = ma ? p->x + 3 * (size_t)sp->a : xa0;
        const double* xb1 = mb ? p->x + 3 * (size_t)sp->b : xb0;
        e += spring_energy(m, sp, xa1, xb1, s->seam_scale) - spring_energy(m, sp, xa0, xb0, s->seam_scale);
        p->sp_mark[p->sp_list[u]] = 0;
    }
    for (int u = 0; u < ng; ++u) p->seen[p->gather[u]] = 0;
    return e;   /* not clamped: judge_gain clamps */
}

/* the pair's particles: a vertex and a triangle's 3, or two edges' 2 */
static void pair_ids(const wc_self* sc, const wc_model* m, int q, int e, int* ids) {
    if (q < sc->n) {
        ids[0] = q;
        for (int k = 0; k < 3; ++k) ids[1 + k] = m->tris[3 * e + k];
    } else {
        ids[0] = sc->edges[2 * (q - sc->n)];
        ids[1] = sc->edges[2 * (q - sc->n) + 1];
        ids[2] = sc->edges[2 * e];
        ids[3] = sc->edges[2 * e + 1];
    }
}

/* uploads particle i's x and v (4 floats each from xv: x then v) */
static void upload(wg_self_prox* p, const wg_tex* x, const wg_tex* v, int i, const float* xv, long long* up) {
    wg_array_upload_range(p->L, x, i, 1, xv);
    wg_array_upload_range(p->L, v, i, 1, xv + 4);
    *up += 32;
}

/* The listed pairs (count, in p->buf) into p->order in core's order, their particles not seen yet
 * taken into the pass's arrays (x, v, core's x_start and masses; the first read kept in f) and
 * p->ids from *nu on. 0 for an entry out of range or a non-finite value (the host's stage). */
static int take(wg_self_prox* p, wc_self* sc, const wc_state* s, int n_pins, int count, int* nu) {
    const wc_model* m = s->model;
    const int* leaf[2] = {sc->tri_bvh.leaf_of, sc->edge_bvh.leaf_of};
    int ok = 1;
    const int first = *nu;
    for (int j = 0; j < count && ok; ++j) {
        const float* b = p->buf + 52 * (size_t)j;
        const int q = (int)b[0], e = (int)b[1];
        if (q < 0 || q >= sc->n + sc->n_edges || e < 0 || e >= (q < sc->n ? sc->n_tris : sc->n_edges)) return 0;
        p->order[j] = (prox_pair){q, leaf[q >= sc->n][e], e, 0};
        int ids[4];
        pair_ids(sc, m, q, e, ids);
        for (int k = 0; k < 4; ++k) {
            const int i = ids[k];
            const float *fx = b + 4 * (1 + k), *fs = b + 4 * (5 + k), *fv = b + 4 * (9 + k);
            for (int c = 0; c < 3; ++c)
                if (!(fx[c] - fx[c] == 0.0f && fs[c] - fs[c] == 0.0f && fv[c] - fv[c] == 0.0f)) ok = 0;
            if (p->seen[i]) continue;
            p->seen[i] = 1;
            p->ids[(*nu)++] = i;
            memcpy(p->f + 8 * (size_t)i, fx, 4 * sizeof(float));
            memcpy(p->f + 8 * (size_t)i + 4, fv, 4 * sizeof(float));
            for (int c = 0; c < 3; ++c) {
                p->x[3 * i + c] = (double)fx[c];
                p->v[3 * i + c] = (double)fv[c];
                sc->x_start[3 * i + c] = (double)fs[c];
            }
        }
    }
    /* core's stage's masses: a fully pinned particle (filter ndof 3) is immovable */
    for (int k = 0; k < n_pins; ++k)
        if (v3_norm(s->pins[k].free_axis) == 0.0) p->pinned[s->pins[k].particle] = 1;
    for (int u = first; u < *nu; ++u) sc->inv_mass[p->ids[u]] = p->pinned[p->ids[u]] ? 0.0 : m->inv_mass[p->ids[u]];
    for (int k = 0; k < n_pins; ++k) p->pinned[s->pins[k].particle] = 0;
    qsort(p->order, (size_t)count, sizeof(prox_pair), by_walk);
    return ok;
}

const wg_self_prox_io* wg_self_prox_transfers(const wg_self_prox* p) { return &p->io; }

/* The energy the pass put in (wg_self_prox_run's gain): local_gain, or gain() with
 * WEFT_GPU_SELF_PROX_GAIN=full, or both compared (=both: local_gain's returned) */
static double judge_gain(wg_self_prox* p, const wc_state* s, const wg_tex* x, const wg_tex* v, int nm,
                         long long* bytes) {
    double total = 0.0, full = 0.0, local = 0.0;
    if (p->gain_mode != 0) {
        long long b = 0;
        full = gain(p, s, x, v, nm, p->gain_mode == 1 ? bytes : &b, &total);
        ++p->io.full_gains;
    }
    if (p->gain_mode != 1) {
        local = local_gain(p, s, x, nm, bytes);
        ++p->io.local_gains;
    }
    if (p->gain_mode == 2) {
        const double d = local > full ? local - full : full - local;
        if (d > p->io.gain_diff_max) p->io.gain_diff_max = d;
        const double a = total < 0 ? -total : total;
        if (a > p->io.total_max) p->io.total_max = a;
        if (fabs(full) > p->io.gain_max) p->io.gain_max = fabs(full);
    }
    const double e = p->gain_mode == 1 ? full : local;
    return e > 0 ? e : 0.0;   /* as wg_self_end: only a gain is excluded from the judge */
}

/* REFINED=check, after a pass the margin proved (its CCD on the first n_first pairs in p->order
 * clean, the touched set still marked): the refined walk at the new end positions lists every pair
 * where too_far may fail; one with a touched particle not among the first list's would have
 * needed the CCD the margin's proof left out. Reads only (x, v unchanged); p->buf is free now. */
static void check_margin(wg_self_prox* p, wg_self_idle* si, const wc_self* sc, const wc_model* m, const wg_tex* x,
                         const wg_tex* v, int cap, int n_first, long long* bytes) {
    ++p->io.margin_checked;
    const int count = wg_self_idle_list(si, x, v, 1, p->buf, bytes);
    int missed = count < 0 || count > cap;
    for (int j = 0; j < count && !missed; ++j) {
        const int q = (int)p->buf[52 * (size_t)j], e = (int)p->buf[52 * (size_t)j + 1];
        if (q < 0 || q >= sc->n + sc->n_edges || e < 0 || e >= (q < sc->n ? sc->n_tris : sc->n_edges)) {
            missed = 1;
            break;
        }
        int ids[4];
        pair_ids(sc, m, q, e, ids);
        if (!(p->touched[ids[0]] | p->touched[ids[1]] | p->touched[ids[2]] | p->touched[ids[3]])) continue;
        ++p->io.margin_pairs;
        int in_first = 0;
        for (int k = 0; k < n_first && !in_first; ++k) in_first = p->order[k].q == q && p->order[k].elem == e;
        missed = !in_first;
    }
    p->io.margin_missed += missed;
}

int wg_self_prox_run(wg_self_prox* p, wg_self_idle* si, wc_self* sc, const wc_state* s, int n_pins, double he,
                     int count, const wg_tex* x, const wg_tex* v, wc_self_stats* st, long long* bytes,
                     long long* up_bytes, int* moved, double* gain_out) {
    const wc_model* m = s->model;
    *moved = 0;
    if (gain_out) *gain_out = 0.0;
    const int cap = wg_self_idle_cap(si) < WG_SELF_PROX_CAP ? wg_self_idle_cap(si) : WG_SELF_PROX_CAP;
    if (count < 1 || count > cap) return 0;
    int nu = 0, prox = 0, nm = 0, refined = -1, skipped = 0;
    double dmax = 0.0;   /* the largest move of a particle's x on the GPU (float as uploaded less as read) */
    /* core's proximity pass on the listed pairs, in its order (a CCD hit: the host's stage) */
    int ok = take(p, sc, s, n_pins, count, &nu);
    const int n_first = count;   /* p->order holds the first list until a refined walk's take */
    /* core's read-only scan first: its serial visit takes only the queries with a pair needing
       action at the end positions (a pair the proof did not list needs none) */
    for (int j = 0; j < count && ok; ++j)
        p->order[j].marked = wc_self_pass_pair(sc, m, p->x, WC_SELF_PASS_PROXIMITY | WC_SELF_PAIR_DRY, p->order[j].q,
                                               p->order[j].elem, NULL, NULL);
    for (int j = 0, k = 0; j < count && ok; j = k) {
        int marked = 0;
        for (k = j; k < count && p->order[k].q == p->order[j].q; ++k) marked |= p->order[k].marked;
        for (int i = j; i < k && ok && marked; ++i)
            if (wc_self_pass_pair(sc, m, p->x, WC_SELF_PASS_PROXIMITY, p->order[i].q, p->order[i].elem, &prox,
                                  p->touched))
                ok = 0;
    }
    /* the moved particles: x and v uploaded (the first read kept in f for a restore) */
    for (int u = 0; u < nu && ok; ++u) {
        const int i = p->ids[u];
        const float* fo = p->f + 8 * (size_t)i;
        if (p->x[3 * i] == (double)fo[0] && p->x[3 * i + 1] == (double)fo[1] && p->x[3 * i + 2] == (double)fo[2])
            continue;
        float xv[8];
        memcpy(xv, fo, sizeof xv);
        double d2 = 0.0;
        for (int c = 0; c < 3; ++c) {
            p->v[3 * i + c] += (p->x[3 * i + c] - (double)fo[c]) / he;
            xv[c] = (float)p->x[3 * i + c];
            xv[4 + c] = (float)p->v[3 * i + c];
            const double dc = (double)xv[c] - (double)fo[c];
            d2 += dc * dc;
        }
        if (d2 > dmax * dmax) dmax = sqrt(d2);
        upload(p, x, v, i, xv, up_bytes);
        p->mv[nm++] = i;
        p->mvf[i] = 1;
    }
    /* core's impulse pass would visit the pairs with a touched particle. Where every particle
       moved by at most half the listing's margin (wg_self_idle_margin), every pair the first walk
       did not list is still too_far, so the listed pairs with a touched particle are the only
       ones that can need core's CCD: it runs on them (in double, IMPULSE mode; a hit: the host's
       stage). Else the refined proof lists those where too_far may fail at the new end positions,
       and each with a touched particle gets core's CCD; a pair with none has not moved since the
       proximity pass found no hit on it (listed then: every pair where too_far may fail). */
    if (ok && prox > 0) {
        const int by_margin = p->refined_mode != 1 && 2.0 * dmax * (1.0 + 1e-6) <= wg_self_idle_margin(si);
        if (by_margin) {
            ++p->io.refined_skipped;
            refined = n_first;
            skipped = 1;
        } else {
            ++p->io.refined_walks;
            refined = wg_self_idle_list(si, x, v, 1, p->buf, bytes);
            if (refined < 0 || refined > cap || (refined > 0 && !take(p, sc, s, n_pins, refined, &nu))) ok = 0;
        }
        for (int j = 0; j < refined && ok; ++j) {
            int ids[4];
            pair_ids(sc, m, p->order[j].q, p->order[j].elem, ids);
            if (!(p->touched[ids[0]] | p->touched[ids[1]] | p->touched[ids[2]] | p->touched[ids[3]])) continue;
            if (wc_self_pass_pair(sc, m, p->x, WC_SELF_PASS_IMPULSE, p->order[j].q, p->order[j].elem, NULL, NULL))
                ok = 0;
        }
    }
    if (ok && skipped && p->refined_mode == 2) check_margin(p, si, sc, m, x, v, cap, n_first, bytes);
    if (!ok)
        for (int u = 0; u < nm; ++u) upload(p, x, v, p->mv[u], p->f + 8 * (size_t)p->mv[u], up_bytes);
    if (ok && gain_out && nm > 0) *gain_out = judge_gain(p, s, x, v, nm, bytes);
    for (int u = 0; u < nu; ++u) p->seen[p->ids[u]] = p->touched[p->ids[u]] = 0;
    for (int u = 0; u < nm; ++u) p->mvf[p->mv[u]] = 0;
    if (!ok) return 0;
    *moved = nm;
    if (st) st->proximity += prox;
    return 1;
}
