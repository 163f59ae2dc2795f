/* The penalty pairs in a GPU cloth's solve (wg_pairs.h): core's detections and active-set rules
 * on the host, the pairs' terms on the GPU. */
#include "wg_pairs.h"

#include <math.h>
#include <string.h>

#include "filter.h"
#include "forces.h"
#include "gpu_error.h"
#include "mesh_pairs.h"
#include "newton.h"
#include "self_collide.h"
#include "self_pairs.h"
#include "vec3.h"

#define LISTS 2   /* 0: the mesh pairs, 1: the self pairs */

struct wg_pairs {
    wg_runner* run;
    wg_pair_cloth cl;
    wc_allocator alloc;
    int cap;                    /* pairs: the lists' capacities together */
    int n;                      /* pairs uploaded this substep: list 0's, then list 1's */
    int first[LISTS], count[LISTS];   /* each list's pairs among them */
    wg_pair_counts counts;
    /* GPU */
    wg_tex p, w, nc;            /* pairs: particles (RGBA32I), weights, (n, c) */
    wg_tex rows, entry;         /* particles: (first entry, end); 4 cap entries: (pair, slot, cnt) */
    wg_tex db, df, da0, da1;    /* particles: the additions to b, f_total, A_ii (lo, hi) */
    wg_tex b2, f2, aii0, aii1;  /* particles: pairs_add's outputs */
    wg_tex A0, A1;              /* blocks: contact_diag's outputs */
    wg_tex gk, nc2, pf;         /* Newton: pairs: (the gap's parts, k, count); pairs_newton's outputs */
    wg_tex e;                   /* Newton: particles: pairs_energy's output */
    /* host */
    float* fx;                  /* (n x 4) read-back and upload staging */
    double *x, *v, *vstar, *dv, *fext, *b, *f;   /* (n x 3) */
    double* xb;                 /* (n x 3) Newton: x(w) = xb + he (v + w)'s base */
    float* fgk;                 /* (cap x 4) Newton: the pairs' gk */
    int newton;                 /* Newton's iterations or the line search: xb kept, pairs in Newton */
    double* A;                  /* (nb x 9) core's assembly scratch */
    double* tri;                /* (3 n_tris + 3) the external forces' scratch */
    unsigned char* ndof;        /* (n) the detections' filter: 3 for a fully pinned particle */
    int* ip;                    /* (cap x 4) pairs' particles */
    float *fw, *fnc;            /* (cap x 4) weights, (n, c) */
    int* ient;                  /* (4 cap x 4) entries */
    int* irow;                  /* (n x 4) rows */
    int* fill;                  /* (n + 1) the CSR's counts */
    float *fdb, *fdf, *fda0, *fda1;   /* (n x 4) the additions' staging */
    int on;                     /* the system has pairs (n > 0 and found this substep) */
    wg_self_pairs* gself;       /* the self pairs' GPU finder (wg_self_pairs.h), or NULL */
    wg_pairs_io io;
};

/* list k of the state (its lists are the state's pointees: core's functions change them) */
static wc_penalty_pairs* list_of(const wc_state* s, int k) {
    if (k == 0) return s->pairs ? &s->pairs->list : NULL;
    return s->self_pairs ? &s->self_pairs->list : NULL;
}

#define TEXTURES 19

/* every texture of p into t (room for TEXTURES); their count */
static int textures(wg_pairs* p, wg_tex** t) {
    wg_tex* all[TEXTURES] = {&p->p, &p->w, &p->nc, &p->rows, &p->entry, &p->db, &p->df, &p->da0, &p->da1, &p->b2,
                             &p->f2, &p->aii0, &p->aii1, &p->A0, &p->A1, &p->gk, &p->nc2, &p->pf, &p->e};
    int k = 0;
    for (; k < (int)(sizeof all / sizeof all[0]); ++k) t[k] = all[k];
    return k;
}

static void free_host(wg_pairs* p) {
    wc_allocator a = p->alloc;
    void* h[] = {p->fx, p->x, p->v, p->vstar, p->dv, p->fext, p->b, p->f, p->xb, p->fgk, p->A, p->tri, p->ndof, p->ip,
                 p->fw, p->fnc, p->ient, p->irow, p->fill, p->fdb, p->fdf, p->fda0, p->fda1};
    for (size_t k = 0; k < sizeof h / sizeof h[0]; ++k) wc_free(&a, h[k]);
    wc_free(&a, p);
}

void wg_pairs_forget(wg_pairs* p) {
    if (p) free_host(p);
}

void wg_pairs_destroy(wg_pairs* p) {
    if (!p) return;
    wg_tex* t[TEXTURES];
    int n = textures(p, t);
    for (int k = 0; k < n; ++k) wg_tex_destroy(t[k]);
    free_host(p);
}

size_t wg_pairs_bytes(const wg_pairs* p) {
    if (!p) return 0;
    wg_tex* t[TEXTURES];
    int n = textures((wg_pairs*)p, t);
    size_t bytes = 0;
    for (int k = 0; k < n; ++k) bytes += t[k]->id ? wg_tex_bytes(t[k]) : 0;
    return bytes;
}

int wg_pairs_create(wg_runner* run, const wg_pair_cloth* cloth, const wc_state* s, wg_pairs** out, char* err,
                    size_t err_len) {
    *out = NULL;
    int cap = (s->pairs ? s->pairs->list.cap : 0) + (s->self_pairs ? s->self_pairs->list.cap : 0);
    if (cap == 0) return 1;
    wc_allocator a = s->alloc;
    wg_pairs* p = WC_NEW(&a, wg_pairs, 1);
    if (!p) {
        wg_errorf(err, err_len, "out of memory");
        return 0;
    }
    memset(p, 0, sizeof *p);
    p->run = run;
    p->cl = *cloth;
    p->alloc = a;
    p->cap = cap;
    p->newton = wc_newton_wanted(&s->def);
    const size_t n = (size_t)(cloth->n > 0 ? cloth->n : 1), n3 = 3 * n, n4 = 4 * n, c4 = 4 * (size_t)cap;
    p->fx = WC_NEW(&a, float, n4);
    double** d3[] = {&p->x, &p->v, &p->vstar, &p->dv, &p->fext, &p->b, &p->f, &p->xb};
    int ok = p->fx != NULL;
    for (size_t k = 0; k < sizeof d3 / sizeof d3[0]; ++k) ok &= (*d3[k] = WC_NEW(&a, double, n3)) != NULL;
    p->A = wc_calloc(&a, 9 * (size_t)(cloth->nb > 0 ? cloth->nb : 1), sizeof(double));
    p->tri = WC_NEW(&a, double, 3 * (size_t)s->model->n_tris + 3);
    p->ndof = WC_NEW(&a, unsigned char, n);
    p->ip = WC_NEW(&a, int, c4);
    p->fw = WC_NEW(&a, float, c4);
    p->fnc = WC_NEW(&a, float, c4);
    p->fgk = WC_NEW(&a, float, c4);
    p->ient = WC_NEW(&a, int, 4 * c4);
    p->irow = WC_NEW(&a, int, n4);
    p->fill = WC_NEW(&a, int, n + 1);
    p->fdb = WC_NEW(&a, float, n4);
    p->fdf = WC_NEW(&a, float, n4);
    p->fda0 = WC_NEW(&a, float, n4);
    p->fda1 = WC_NEW(&a, float, n4);
    ok = ok && p->A && p->tri && p->ndof && p->ip && p->fw && p->fnc && p->fgk && p->ient && p->irow && p->fill &&
         p->fdb && p->fdf && p->fda0 && p->fda1;
    if (!ok) {
        free_host(p);
        wg_errorf(err, err_len, "out of memory");
        return 0;
    }
    memset(p->b, 0, n3 * sizeof(double));
    memset(p->f, 0, n3 * sizeof(double));
    const wg_layout* L = run->layout;
    const int N = cloth->n;
    ok = wg_array_create(L, &p->p, GL_RGBA32I, cap, NULL, err, err_len) &&
         wg_array_create(L, &p->w, GL_RGBA32F, cap, NULL, err, err_len) &&
         wg_array_create(L, &p->nc, GL_RGBA32F, cap, NULL, err, err_len) &&
         wg_array_create(L, &p->rows, GL_RGBA32I, N, NULL, err, err_len) &&
         wg_array_create(L, &p->entry, GL_RGBA32I, 4 * cap, NULL, err, err_len);
    wg_tex* per[] = {&p->db, &p->df, &p->da0, &p->da1, &p->b2, &p->f2, &p->aii0, &p->aii1};
    for (size_t k = 0; ok && k < sizeof per / sizeof per[0]; ++k)
        ok = wg_array_create(L, per[k], GL_RGBA32F, N, NULL, err, err_len);
    ok = ok && wg_array_create(L, &p->A0, cloth->a_lo->internal, cloth->nb, NULL, err, err_len) &&
         wg_array_create(L, &p->A1, cloth->a_hi->internal, cloth->nb, NULL, err, err_len);
    if (p->newton)   /* Newton's terms and energy on the GPU */
        ok = ok && wg_array_create(L, &p->gk, GL_RGBA32F, cap, NULL, err, err_len) &&
             wg_array_create(L, &p->nc2, GL_RGBA32F, cap, NULL, err, err_len) &&
             wg_array_create(L, &p->pf, GL_RGBA32F, cap, NULL, err, err_len) &&
             wg_array_create(L, &p->e, GL_RGBA32F, N, NULL, err, err_len);
    if (!ok) {
        wg_pairs_destroy(p);
        return 0;
    }
    *out = p;
    return 1;
}

void wg_pairs_use_self_finder(wg_pairs* p, wg_self_pairs* gp) { p->gself = gp; }

int wg_pairs_on(const wg_pairs* p) { return p && p->on; }

int wg_pairs_capacity(const wg_pairs* p) { return p ? p->cap : 0; }

int wg_pairs_list_on(const wg_pairs* p, int list) { return p && p->on && p->count[list] > 0; }

const wg_pair_counts* wg_pairs_counts(const wg_pairs* p) { return &p->counts; }

const wg_pairs_io* wg_pairs_transfers(const wg_pairs* p) { return &p->io; }

wg_pair_in wg_pairs_inputs(const wg_pairs* p, const wg_tex* i_any, const wg_tex* f_any) {
    if (!p) return (wg_pair_in){i_any, i_any, i_any, f_any, f_any};
    return (wg_pair_in){&p->rows, &p->entry, &p->p, &p->w, &p->nc};
}

int wg_pairs_debug_list(const wg_pairs* p, const int** pp, const float** w, const float** nc) {
    if (pp) *pp = p->ip;
    if (w) *w = p->fw;
    if (nc) *nc = p->fnc;
    return p->n;
}

/* n RGBA32F items of t read back into d (n x 3) */
static void read_back(wg_pairs* p, const wg_tex* t, double* d) {
    const int n = p->cl.n;
    wg_array_read(p->run->layout, t, n, p->fx);
    p->io.read_bytes += 16 * (long long)n;
    for (int i = 0; i < n; ++i)
        for (int c = 0; c < 3; ++c) d[3 * i + c] = (double)p->fx[4 * i + c];
}

/* pair j of list l as pair `at` of the upload (its c 0: inactive) */
static void stage_pair(wg_pairs* p, const wc_penalty_pairs* l, int j, int at) {
    const wc_coupling_term* t = &l->term[j];
    for (int a = 0; a < 4; ++a) {
        p->ip[4 * at + a] = a < t->cnt ? t->p[a] : t->p[0];
        p->fw[4 * at + a] = a < t->cnt ? (float)t->w[a] : 0.0f;
    }
    for (int c = 0; c < 3; ++c) p->fnc[4 * at + c] = (float)t->n[c];
    p->fnc[4 * at + 3] = (float)t->c;
}

void wg_pairs_find(wg_pairs* p, wc_state* s, const wc_integ* ig, const wg_tex* x, const wg_tex* v,
                   const wg_tex* vstar, const wg_tex* xb, int n_pins, wg_mesh_sharp* sharp) {
    const wc_model* m = s->model;
    const int n = p->cl.n;
    memset(&p->counts, 0, sizeof p->counts);
    p->on = 0;
    p->n = 0;
    ++p->io.substeps;
    read_back(p, x, p->x);
    read_back(p, v, p->v);
    if (vstar != v) read_back(p, vstar, p->vstar);
    else memcpy(p->vstar, p->v, 3 * (size_t)n * sizeof(double));
    if (p->newton && xb != x) read_back(p, xb, p->xb);
    else if (p->newton) memcpy(p->xb, p->x, 3 * (size_t)n * sizeof(double));
    /* the detections' filter: the fully pinned particles (wg_self.h: core's rule reads the same) */
    memset(p->ndof, 0, (size_t)n);
    for (int k = 0; k < n_pins; ++k)
        if (v3_norm(s->pins[k].free_axis) == 0.0) p->ndof[s->pins[k].particle] = 3;
    const wc_filter pins = {n, NULL, NULL, p->ndof};
    if (s->pairs) {
        wc_penalty_pairs_clear(&s->pairs->list);
        wc_mesh_pairs_find(s->pairs, (const wc_mesh_collider* const*)s->mesh, s->n_mesh, m, &pins, NULL, p->x, p->v,
                           ig->h, ig->he);
        if (sharp)   /* the resident bodies' (their copies in core are stale: core skipped them) */
            wg_mesh_sharp_find(sharp, s->pairs, m, &pins, NULL, x, v, ig->h, ig->he, NULL);
        p->counts.mesh = s->pairs->list.n;
        p->counts.mesh_overflow = s->pairs->list.overflow;
        p->counts.mesh_skipped = s->pairs->list.skipped;
    }
    if (s->self_pairs) {
        s->self->threads = s->par.threads;
        if (p->gself) {   /* non-finite values, too many candidates: core's walk (the finder's) */
            size_t bytes = 0;
            wg_self_pairs_find(p->gself, s->self_pairs, s->self, m, &pins, x, v, p->x, p->v, ig->h, ig->he, &bytes,
                               &p->counts.self_candidates);
            p->counts.self_bytes = (long long)bytes;
        } else {
            wc_self_pairs_find(s->self_pairs, s->self, m, &pins, p->x, p->v, ig->h, ig->he);
        }
        p->counts.self = s->self_pairs->list.n;
        p->counts.self_overflow = s->self_pairs->list.overflow;
    }
    /* the pairs, then each particle's entries (counting sort: by particle, then pair order) */
    memset(p->fill, 0, ((size_t)n + 1) * sizeof(int));
    for (int k = 0; k < LISTS; ++k) {
        const wc_penalty_pairs* l = list_of(s, k);
        p->first[k] = p->n;
        p->count[k] = l ? l->n : 0;
        for (int j = 0; j < p->count[k]; ++j) {
            stage_pair(p, l, j, p->n);
            for (int a = 0; a < l->term[j].cnt; ++a) ++p->fill[l->term[j].p[a] + 1];
            ++p->n;
        }
    }
    if (p->n == 0) return;
    for (int i = 0; i < n; ++i) {
        p->fill[i + 1] += p->fill[i];
        p->irow[4 * i] = p->fill[i];
        p->irow[4 * i + 1] = p->fill[i];
        p->irow[4 * i + 2] = p->irow[4 * i + 3] = 0;
    }
    int entries = 0;
    for (int k = 0; k < LISTS; ++k) {
        const wc_penalty_pairs* l = list_of(s, k);
        for (int j = 0; j < p->count[k]; ++j) {
            const wc_coupling_term* t = &l->term[j];
            for (int a = 0; a < t->cnt; ++a) {
                int e = p->irow[4 * t->p[a] + 1]++;
                int* en = p->ient + 4 * (size_t)e;
                en[0] = p->first[k] + j;
                en[1] = a;
                en[2] = t->cnt;
                en[3] = 0;
                ++entries;
            }
        }
    }
    const wg_layout* L = p->run->layout;
    wg_array_upload(L, &p->p, p->n, p->ip);
    wg_array_upload(L, &p->w, p->n, p->fw);
    wg_array_upload(L, &p->nc, p->n, p->fnc);
    wg_array_upload(L, &p->entry, entries, p->ient);
    wg_array_upload(L, &p->rows, n, p->irow);
    if (p->newton) {
        /* each pair's gap at x(w) = xb + he (v + w) in two parts computed here in double,
           n . sum w_a xb_a - off and n . sum w_a v_a, its k and its count (pairs_newton.glsl) */
        for (int k = 0; k < LISTS; ++k) {
            const wc_penalty_pairs* l = list_of(s, k);
            for (int j = 0; j < p->count[k]; ++j) {
                const wc_coupling_term* t = &l->term[j];
                double gx = -l->off[j], gv = 0.0;
                for (int a = 0; a < t->cnt; ++a) {
                    gx += t->w[a] * v3_dot(t->n, p->xb + 3 * t->p[a]);
                    gv += t->w[a] * v3_dot(t->n, p->v + 3 * t->p[a]);
                }
                float* q = p->fgk + 4 * (size_t)(p->first[k] + j);
                q[0] = (float)gx;
                q[1] = (float)gv;
                q[2] = (float)l->k[j];
                q[3] = (float)t->cnt;
            }
        }
        wg_array_upload(L, &p->gk, p->n, p->fgk);
    }
    p->on = 1;
}

/* The additions core's assembly or recheck left in the host scratch (b, f, A's diagonal blocks)
 * up over the span of the particles they touch, added by the passes, the scratch zeroed again;
 * with_f: f_total's too. The pairs' (n, c) of list k up first (k -1: none). */
static void apply(wg_pairs* p, const wc_state* s, int k, int with_f) {
    /* (the lists are the state's pointees) */
    const wc_model* m = s->model;
    const int n = p->cl.n;
    wg_runner* run = p->run;
    const wg_layout* L = run->layout;
    if (k >= 0 && p->count[k] > 0) {
        const wc_penalty_pairs* l = list_of(s, k);
        for (int j = 0; j < p->count[k]; ++j) p->fnc[4 * (p->first[k] + j) + 3] = (float)l->term[j].c;
        wg_array_upload_range(L, &p->nc, p->first[k], p->count[k], p->fnc + 4 * (size_t)p->first[k]);
    }
    int lo = n, hi = -1;
    for (int i = 0; i < n; ++i) {
        const double* a = p->A + 9 * (size_t)m->pattern.diag[i];
        const double* b = p->b + 3 * i;
        const double* f = p->f + 3 * i;
        int touched = b[0] != 0.0 || b[1] != 0.0 || b[2] != 0.0 || f[0] != 0.0 || f[1] != 0.0 || f[2] != 0.0;
        for (int c = 0; c < 9 && !touched; ++c) touched = a[c] != 0.0;
        if (!touched) continue;
        if (lo == n) lo = i;
        hi = i;
    }
    if (hi >= 0) {
        for (int i = lo; i <= hi; ++i) {
            const double* a = p->A + 9 * (size_t)m->pattern.diag[i];
            float* db = p->fdb + 4 * (size_t)i;
            float* df = p->fdf + 4 * (size_t)i;
            float* d0 = p->fda0 + 4 * (size_t)i;
            float* d1 = p->fda1 + 4 * (size_t)i;
            for (int c = 0; c < 3; ++c) {
                db[c] = (float)p->b[3 * i + c];
                df[c] = (float)p->f[3 * i + c];
            }
            db[3] = df[3] = 0.0f;
            /* the symmetric block (a00 a01 a02 a11 | a12 a22), wg_layout.h */
            d0[0] = (float)a[0];
            d0[1] = (float)a[1];
            d0[2] = (float)a[2];
            d0[3] = (float)a[4];
            d1[0] = (float)a[5];
            d1[1] = (float)a[8];
            d1[2] = d1[3] = 0.0f;
        }
        const int count = hi - lo + 1;
        wg_array_upload_range(L, &p->db, lo, count, p->fdb + 4 * (size_t)lo);
        if (with_f) wg_array_upload_range(L, &p->df, lo, count, p->fdf + 4 * (size_t)lo);
        wg_array_upload_range(L, &p->da0, lo, count, p->fda0 + 4 * (size_t)lo);
        wg_array_upload_range(L, &p->da1, lo, count, p->fda1 + 4 * (size_t)lo);
        const wg_pair_cloth* g = &p->cl;
        WG_USE(run, WGP_PAIRS_ADD, &(wg_pairs_add_in){.pblocks = g->pblocks, .a_lo = g->a_lo, .a_hi = g->a_hi,
            .b = g->b, .ftot = g->ftot, .db = &p->db, .df = &p->df, .da_lo = &p->da0, .da_hi = &p->da1});
        wg_u1i(run, "u_lo", lo);
        wg_u1i(run, "u_hi", hi);
        wg_u1i(run, "u_f", with_f);
        WG_RUN(run, n, &p->b2, &p->f2, &p->aii0, &p->aii1);
        wg_tex_swap(g->b, &p->b2);
        wg_tex_swap(g->ftot, &p->f2);
        WG_USE(run, WGP_CONTACT_DIAG, &(wg_contact_diag_in){.block = g->block, .a_lo = g->a_lo, .a_hi = g->a_hi,
            .aii_lo = &p->aii0, .aii_hi = &p->aii1});
        WG_RUN(run, g->nb, &p->A0, &p->A1);
        wg_tex_swap(g->a_lo, &p->A0);
        wg_tex_swap(g->a_hi, &p->A1);
    }
    memset(p->b, 0, 3 * (size_t)n * sizeof(double));
    memset(p->f, 0, 3 * (size_t)n * sizeof(double));
    memset(p->A, 0, 9 * (size_t)p->cl.nb * sizeof(double));
}

void wg_pairs_assemble(wg_pairs* p, wc_state* s, const wc_integ* ig) {
    if (!p->on) return;
    const wc_model* m = s->model;
    /* the external forces at the substep's start, as core's prepare has them (gravity, air) */
    wc_eval_external(m, p->x, p->v, s->def.gravity, &s->def.air, &s->par, p->tri, p->fext);
    int* active[LISTS] = {&p->counts.mesh_active, &p->counts.self_active};
    for (int k = 0; k < LISTS; ++k) {
        wc_penalty_pairs* l = list_of(s, k);
        if (!l || p->count[k] == 0) continue;
        *active[k] = wc_penalty_pairs_assemble(l, m, p->x, p->vstar, p->fext, ig->he, p->A, p->b, p->f);
    }
    /* both lists' (n, c) up at once */
    for (int k = 0; k < LISTS; ++k) {
        const wc_penalty_pairs* l = list_of(s, k);
        for (int j = 0; j < p->count[k]; ++j) p->fnc[4 * (p->first[k] + j) + 3] = (float)l->term[j].c;
    }
    wg_array_upload(p->run->layout, &p->nc, p->n, p->fnc);
    apply(p, s, -1, 1);
}

void wg_pairs_newton(wg_pairs* p, const wc_integ* ig, const wg_tex* w) {
    if (!p->on || !p->newton) return;
    ++p->io.systems;
    wg_runner* run = p->run;
    const wg_pair_cloth* g = &p->cl;
    WG_USE(run, WGP_PAIRS_NEWTON,
           &(wg_pairs_newton_in){.pp = &p->p, .pw = &p->w, .pnc = &p->nc, .pgk = &p->gk, .w = w});
    wg_u1f(run, "u_h", ig->he);
    WG_RUN(run, p->n, &p->nc2, &p->pf);
    wg_tex_swap(&p->nc, &p->nc2);
    WG_USE(run, WGP_PAIRS_NEWTON_ADD, &(wg_pairs_newton_add_in){.pblocks = g->pblocks, .a_lo = g->a_lo, .a_hi = g->a_hi,
        .b = g->b, .pr_rows = &p->rows, .pr_entry = &p->entry, .pw = &p->w, .pnc = &p->nc, .pf = &p->pf});
    WG_RUN(run, g->n, &p->b2, &p->aii0, &p->aii1);
    wg_tex_swap(g->b, &p->b2);
    WG_USE(run, WGP_CONTACT_DIAG, &(wg_contact_diag_in){.block = g->block, .a_lo = g->a_lo, .a_hi = g->a_hi,
        .aii_lo = &p->aii0, .aii_hi = &p->aii1});
    WG_RUN(run, g->nb, &p->A0, &p->A1);
    wg_tex_swap(g->a_lo, &p->A0);
    wg_tex_swap(g->a_hi, &p->A1);
}

const wg_tex* wg_pairs_energy_change(wg_pairs* p, const wc_integ* ig, const wg_tex* wa, const wg_tex* wb,
                                     const wg_tex* base) {
    if (!p->on || !p->newton) return base;
    ++p->io.changes;
    wg_runner* run = p->run;
    WG_USE(run, WGP_PAIRS_ENERGY, &(wg_pairs_energy_in){.pr_rows = &p->rows, .pr_entry = &p->entry, .pp = &p->p,
        .pw = &p->w, .pnc = &p->nc, .pgk = &p->gk, .wa = wa, .wb = wb, .base = base});
    wg_u1f(run, "u_h", ig->he);
    WG_RUN(run, p->cl.n, &p->e);
    return &p->e;
}

int wg_pairs_debug_active(wg_pairs* p) {
    if (!p->on) return 0;
    wg_array_read(p->run->layout, &p->nc, p->n, p->fnc);
    int active = 0;
    for (int j = 0; j < p->n; ++j) active += p->fnc[4 * j + 3] > 0.0f;
    return active;
}

int wg_pairs_recheck(wg_pairs* p, wc_state* s, int list, const wc_integ* ig, const wg_tex* dv) {
    wc_penalty_pairs* l = list_of(s, list);
    if (!p->on || !l || p->count[list] == 0) return 0;
    read_back(p, dv, p->dv);
    /* a recheck that switches nothing leaves the scratch as it was: zero */
    int changed = wc_penalty_pairs_recheck(l, s->model, p->x, p->vstar, p->dv, ig->he, p->A, p->b);
    if (changed > 0) apply(p, s, list, 0);
    return changed;
}
