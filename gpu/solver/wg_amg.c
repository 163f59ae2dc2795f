/* The GPU's multigrid preconditioner (wg_amg.h): the hierarchy's textures from core's
 * aggregates, the per-solve setup passes and the V-cycle. */
#include <string.h>

#include "gpu_error.h"
#include "wg_amg.h"
#include "wg_amg_group.h"
#include "wg_pairs.h"

wc_amg_opts wg_amg_opts(void) { return wg_amg_opts_form(WG_AMG_SMOOTHED, WG_AMG_ROTATIONS); }

wc_amg_opts wg_amg_opts_for(int smoothed) { return wg_amg_opts_form(smoothed, 0); }

wc_amg_opts wg_amg_opts_form(int smoothed, int rotations) {
    wc_amg_opts o = wc_default_amg_opts();
    o.coarse_max = WG_AMG_DENSE_NODES;
    o.rotations = smoothed && rotations; /* core's about the rest positions (current_positions 0
                                            below): P_tent uploaded (wg_amg_smooth.c), the rest
                                            form's; the current form makes its own (tent_setup) */
    o.pair_blocks = 1;
    if (!smoothed) o.prolong_weight = 0.0; /* else core's (4/3): the patterns of P, T = A P, P^T T */
    o.lanczos = 0;
    o.power_iterations = WG_AMG_POWER;
    o.coarse_iterations = smoothed ? WG_AMG_POWER_COARSE : WG_AMG_POWER;
    o.current_positions = 0;
    o.couplings = 0;
    o.values = 0; /* patterns and aggregates: the values live in textures */
    return o;
}

#define TRY(x) \
    do { \
        if (!(x)) goto fail; \
    } while (0)

/* int4 items (a, b, c, d) per entry into a new RGBA32I array */
static int upload_i4(const wg_layout* L, wg_tex* t, int count, const int* v, char* err, size_t el) {
    return wg_array_create(L, t, GL_RGBA32I, count, v, err, el);
}

/* The n_items items grouped by key (counting sort, items ascending within a group), uploaded as
 * range (per group: first, end) and list (per position: the item), int4 arrays. start: n_groups
 * + 1 ints of scratch (not key); v: int4 scratch for max(n_groups, n_items) items. */
static int upload_groups(const wg_layout* L, wg_tex* range, wg_tex* list, int n_groups, int n_items, const int* key, int* start,
                         int* v, char* err, size_t el) {
    memset(start, 0, sizeof(int) * (size_t)(n_groups + 1));
    for (int k = 0; k < n_items; ++k) ++start[key[k] + 1];
    for (int K = 0; K < n_groups; ++K) start[K + 1] += start[K];
    memset(v, 0, 4u * sizeof(int) * (size_t)(n_groups > n_items ? n_groups : n_items));
    for (int K = 0; K < n_groups; ++K) {
        v[4 * K] = start[K];
        v[4 * K + 1] = start[K + 1];
    }
    if (!upload_i4(L, range, n_groups, v, err, el)) return 0;
    memset(v, 0, 4u * sizeof(int) * (size_t)n_items);
    for (int k = 0; k < n_items; ++k) v[4 * start[key[k]]++] = k;
    return upload_i4(L, list, n_items, v, err, el);
}

/* One level's textures from core's level L; P: the finer level of core's hierarchy (NULL on level
 * 0) for the Galerkin and member lists. Level 0 has no pattern or blocks of its own: its passes
 * read the system's (use_level). */
static int level_create(wg_runner* run, wg_amg_level* G, const wc_amg_level* P, const wc_amg_level* L, int* buf,
                        int smoothed, char* err, size_t el) {
    const wg_layout* L0 = run->layout;
    G->n = L->n;
    G->nb = L->n_blocks;
    int cap = (L->n > L->n_blocks ? L->n : L->n_blocks);
    if (P && P->n_blocks > cap) cap = P->n_blocks;
    if (P && P->n > cap) cap = P->n;
    int* v = wc_calloc(&L0->alloc, 4u * (size_t)(cap + 1), sizeof(int));
    if (!v) {
        wg_errorf(err, el, "out of memory");
        return 0;
    }
    for (int i = 0; i < L->n; ++i) {
        v[4 * i] = L->row_start[i];
        v[4 * i + 1] = L->row_start[i + 1];
        v[4 * i + 2] = L->diag[i];
        /* a pair level: the block (i, i ^ 1) (wg_amg_level.pair; core's pair_blk, made with values) */
        v[4 * i + 3] = L->group == 2 ? wc_amg_find(L->col, L->row_start[i], L->row_start[i + 1], i ^ 1)
                       : L->agg    ? L->agg[i]
                                   : -1;
        if (L->group == 2 && v[4 * i + 3] < 0) {
            wg_errorf(err, el, "multigrid: node %d has no block to its pair", i);
            goto fail;
        }
    }
    G->pair = L->group == 2;
    TRY(upload_i4(L0, &G->rows, L->n, v, err, el));
    if (P) {   /* the finest level reads the system's own pattern and blocks (amg_level_inputs.glsl) */
        memset(v, 0, 4u * sizeof(int) * (size_t)L->n_blocks);
        for (int i = 0; i < L->n; ++i)
            for (int k = L->row_start[i]; k < L->row_start[i + 1]; ++k) {
                v[4 * k] = i;
                v[4 * k + 1] = L->col[k];
            }
        TRY(upload_i4(L0, &G->cols, L->n_blocks, v, err, el));
    }
    if (P && !smoothed) { /* P = P_tent (else wg_amg_smooth.c's lists) */
        /* each finer block (i, j) sums into this level's block (agg i, agg j) */
        int* start = buf; /* (nb + 1) */
        int* slot = buf + L->n_blocks + 1; /* (P->n_blocks) */
        for (int i = 0; i < P->n; ++i)
            for (int k = P->row_start[i]; k < P->row_start[i + 1]; ++k) {
                int I = P->agg[i], J = P->agg[P->col[k]];
                int K = wc_amg_find(L->col, L->row_start[I], L->row_start[I + 1], J);
                if (K < 0) {
                    wg_errorf(err, el, "multigrid: block (%d, %d) missing from level pattern", I, J);
                    goto fail;
                }
                slot[k] = K;
            }
        TRY(upload_groups(L0, &G->gal_range, &G->gal_list, L->n_blocks, P->n_blocks, slot, start, v, err, el));
        /* members of each aggregate, ascending */
        TRY(upload_groups(L0, &G->mem_range, &G->mem_list, L->n, P->n, P->agg, start, v, err, el));
    }
    if (P) {
        TRY(wg_array_create(L0, &G->r, GL_RGBA32F, L->n, NULL, err, el));
    }
    for (int c = 0; c < 3; ++c) {
        if (P) TRY(wg_array_create(L0, &G->a[c], GL_RGBA32F, L->n_blocks, NULL, err, el));
        TRY(wg_array_create(L0, &G->dinv[c], GL_RGBA32F, (G->pair ? 2 : 1) * L->n, NULL, err, el));
    }
    for (int c = 0; c < 2; ++c) {
        TRY(wg_array_create(L0, &G->x[c], GL_RGBA32F, L->n, NULL, err, el));
        TRY(wg_array_create(L0, &G->d[c], GL_RGBA32F, L->n, NULL, err, el));
        TRY(wg_array_create(L0, &G->v[c], GL_RGBA32F, L->n, NULL, err, el));
    }
    TRY(wg_array_create(L0, &G->part, GL_RGBA32F, L->n, NULL, err, el));
    TRY(wg_chain_create(run, &G->red, G->part.w, G->part.h, err, el));
    /* core's start vector (amg_build.c), so that both backends estimate from the same one */
    double* sv = wc_calloc(&L0->alloc, 3u * (size_t)L->n, sizeof(double));
    float* f = wc_calloc(&L0->alloc, 4u * (size_t)L->n, sizeof(float));
    if (!sv || !f) {
        wc_free(&L0->alloc, sv);
        wc_free(&L0->alloc, f);
        wg_errorf(err, el, "out of memory");
        goto fail;
    }
    wc_amg_start_vector(sv, L->n);
    for (int i = 0; i < L->n; ++i)
        for (int c = 0; c < 3; ++c) f[4 * i + c] = (float)sv[3 * i + c];
    int ok = wg_array_create(L0, &G->v0, GL_RGBA32F, L->n, f, err, el);
    wc_free(&L0->alloc, sv);
    wc_free(&L0->alloc, f);
    TRY(ok);
    wc_free(&L0->alloc, v);
    return 1;
fail:
    wc_free(&L0->alloc, v);
    return 0;
}

static int level_textures(wg_amg_level* G, wg_tex** out) {
    wg_tex* list[] = {&G->rows, &G->cols, &G->a[0], &G->a[1], &G->a[2], &G->dinv[0], &G->dinv[1], &G->dinv[2],
                      &G->gal_range, &G->gal_list, &G->mem_range, &G->mem_list, &G->r, &G->x[0], &G->x[1], &G->d[0],
                      &G->d[1], &G->v0, &G->v[0], &G->v[1], &G->part, &G->cross_i, &G->cross_a,
                      &G->p_ent, &G->p_rows, &G->p_range, &G->p_list, &G->p[0], &G->p[1], &G->p[2],
                      &G->t_range, &G->t_list, &G->t[0], &G->t[1], &G->t[2], &G->pt_range, &G->pt_list, &G->res,
                      &G->tent[0], &G->tent[1], &G->tent[2], &G->tq_range, &G->tq_list, &G->tq_of,
                      &G->nn[0], &G->nn[1], &G->nn[2], &G->nn[3], &G->nn[4], &G->nn[5], &G->nc,
                      &G->tq_t[0], &G->tq_t[1], &G->tq_t[2], &G->tq_t[3], &G->tq_t[4], &G->tq_t[5]};
    int n = (int)(sizeof list / sizeof list[0]);
    for (int k = 0; k < n; ++k) out[k] = list[k];
    return n;
}

/* Every aggregate has at most WG_AMG_TENT_NODES nodes (amg_tent_qr.glsl holds its columns). */
static int tent_fits(const wc_amg* ca) {
    for (int l = 0; l + 1 < ca->n_levels; ++l)
        for (int g = 0; g < ca->lev[l + 1].n / 2; ++g)
            if (ca->lev[l].agg_start[g + 1] - ca->lev[l].agg_start[g] > WG_AMG_TENT_NODES) return 0;
    return 1;
}

/* The rotations about the current positions (wg_amg.current): each level's aggregates' nodes and
 * each node's aggregate (core's agg_start / agg_node), the next levels' near-null rows and centres
 * (made per setup, tent_setup), the positions' reduction. */
static int tent_create(wg_amg* a, const wc_amg* ca, char* err, size_t el) {
    const wg_layout* L0 = a->run->layout;
    int n_max = 1;
    for (int l = 0; l < ca->n_levels; ++l)
        if (ca->lev[l].n > n_max) n_max = ca->lev[l].n;
    int* v = wc_calloc(&L0->alloc, 4u * (size_t)n_max + 4, sizeof(int));
    if (!v) {
        wg_errorf(err, el, "out of memory");
        return 0;
    }
    int ok = 1;
    for (int l = 0; ok && l + 1 < ca->n_levels; ++l) {
        const wc_amg_level *F = &ca->lev[l], *C = &ca->lev[l + 1];
        wg_amg_level *G = &a->lev[l], *N = &a->lev[l + 1];
        const int n_agg = C->n / 2;
        memset(v, 0, sizeof(int) * 4 * (size_t)n_max);
        for (int g = 0; g < n_agg; ++g) {
            v[4 * g] = F->agg_start[g];
            v[4 * g + 1] = F->agg_start[g + 1];
        }
        ok = ok && upload_i4(L0, &G->tq_range, n_agg, v, err, el);
        memset(v, 0, sizeof(int) * 4 * (size_t)n_max);
        for (int i = 0; i < F->n; ++i) v[4 * i] = F->agg_node[i];
        ok = ok && upload_i4(L0, &G->tq_list, F->n, v, err, el);
        memset(v, 0, sizeof(int) * 4 * (size_t)n_max);
        for (int i = 0; i < F->n; ++i) v[4 * i] = F->agg[i];
        ok = ok && upload_i4(L0, &G->tq_of, F->n, v, err, el);
        for (int k = 0; ok && k < 6; ++k) ok = wg_array_create(L0, &N->nn[k], GL_RGBA32F, C->n, NULL, err, el);
        for (int k = 0; ok && k < 6; ++k) ok = wg_array_create(L0, &N->tq_t[k], GL_RGBA32F, C->n, NULL, err, el);
        ok = ok && wg_array_create(L0, &N->nc, GL_RGBA32F, C->n, NULL, err, el);
    }
    const wg_tex* x = &a->sys.x->t[0];
    ok = ok && wg_chain_create(a->run, &a->cen_red, x->w, x->h, err, el);
    wc_free(&L0->alloc, v);
    return ok;
}

int wg_amg_create(wg_runner* run, const wc_model* m, const wg_amg_system* sys, wg_amg** out, char* err,
                  size_t el) {
    return wg_amg_create_with(run, m, sys, WG_AMG_SMOOTHED, out, err, el);
}

int wg_amg_create_with(wg_runner* run, const wc_model* m, const wg_amg_system* sys, int smoothed, wg_amg** out,
                       char* err, size_t el) {
    return wg_amg_create_form(run, m, sys, smoothed, WG_AMG_ROTATIONS, out, err, el);
}

int wg_amg_create_form(wg_runner* run, const wc_model* m, const wg_amg_system* sys, int smoothed, int rotations,
                       wg_amg** out, char* err, size_t el) {
    *out = NULL;
    const wc_allocator* alloc = &run->layout->alloc;
    wc_amg_opts o = wg_amg_opts_form(smoothed, rotations);
    wc_amg* ca = NULL;
    wc_diag d = {0};
    if (wc_amg_create(&ca, m, &o, alloc, &d) != WC_OK) {
        wg_errorf(err, el, "multigrid: %s", d.message);
        return 0;
    }
    wg_amg* a = wc_calloc(alloc, 1, sizeof *a);
    int* buf = NULL;
    if (!a) goto oom;
    a->run = run;
    a->sys = *sys;
    a->n_levels = ca->n_levels;
    a->sweeps = o.sweeps;
    a->fuse = 1;
    a->ratio = o.chebyshev_ratio;
    a->fine_bound_scale = ca->fine_bound_scale;
    a->smoothed = smoothed && ca->n_levels > 1;
    a->prolong_weight = o.prolong_weight;
    a->rotations = o.rotations && a->smoothed;
    a->cross_bound_scale = WG_AMG_CROSS_BOUND;
    a->warm_steps = WG_AMG_POWER_WARM;
    a->warm_floor = WG_AMG_WARM_FLOOR;
    a->cold_steps[0] = WG_AMG_POWER;
    a->cold_steps[1] = WG_AMG_POWER_COARSE;
    a->cross_share[0] = WG_AMG_CROSS_FINE_SHARE;
    a->cross_share[1] = WG_AMG_CROSS_COARSE_SHARE;
    int cap = 1;
    for (int l = 0; l < ca->n_levels; ++l) {
        int c = ca->lev[l].n_blocks + 1 + (l > 0 ? ca->lev[l - 1].n_blocks : 0);
        if (c > cap) cap = c;
    }
    buf = wc_calloc(alloc, (size_t)cap, sizeof(int));
    if (!buf) goto oom;
    for (int l = 0; l < ca->n_levels; ++l) {
        if (!level_create(run, &a->lev[l], l > 0 ? &ca->lev[l - 1] : NULL, &ca->lev[l], buf, a->smoothed, err, el))
            goto fail;
        a->lev[l].v_last = 1;   /* a cold setup's first step writes v[0] */
    }
    if (a->smoothed && !wg_amg_smooth_create(a, ca, err, el)) goto fail;
    a->current = a->rotations && sys->x && run->dev->amg_current && tent_fits(ca);
    if (a->current && !tent_create(a, ca, err, el)) goto fail;
    /* each particle's node on each level (the pairs' cross terms, wg_amg_set_pairs) */
    const int n0 = ca->lev[0].n;
    a->node_of = wc_calloc(alloc, (size_t)ca->n_levels * (size_t)(n0 > 0 ? n0 : 1), sizeof(int));
    if (!a->node_of) goto oom;
    for (int i = 0; i < n0; ++i) a->node_of[i] = i;
    /* (with rotations an aggregate's first coarse node; the terms stay on the finest level with
       the smoothed prolongator, wg_amg_cross.c) */
    for (int l = 1; l < ca->n_levels; ++l)
        for (int i = 0; i < n0; ++i)
            a->node_of[(size_t)l * n0 + i] = ca->lev[l - 1].cpa * ca->lev[l - 1].agg[a->node_of[(size_t)(l - 1) * n0 + i]];
    const wc_amg_level* C = &ca->lev[ca->n_levels - 1];
    a->dense = C->n <= WG_AMG_DENSE_NODES;
    if (a->dense && !wg_tex_create(&a->coarse_L, GL_RGBA32F, 3 * C->n, 3 * C->n, NULL, err, el)) goto fail;
    /* PCG in one work group (where it fits), made only where the device's WEFT_GPU_SOLVE=group
       asks for it, the multigrid's one use of it (wg_solve.c group_wanted): 1.2 of 10.8 MiB on a
       1,024-particle sheet */
    if (run->dev->solve == WG_SOLVE_GROUP && !wg_amg_group_create(a, ca, err, el)) goto fail;
    /* the coarse sub-cycle in one work group, where the chain runs the V-cycle */
    if (!wg_amg_group_fits(a) && !wg_amg_sub_create(a, ca, err, el)) goto fail;
    wc_free(alloc, buf);
    wc_amg_destroy(ca);
    *out = a;
    return 1;
oom:
    wg_errorf(err, el, "out of memory");
fail:
    wc_free(alloc, buf);
    wc_amg_destroy(ca);
    wg_amg_destroy(a);
    return 0;
}

static void release(wg_amg* a, int gl) {
    if (!a) return;
    if (gl) {
        for (int l = 0; l < a->n_levels; ++l) {
            wg_tex* t[64];
            int n = level_textures(&a->lev[l], t);
            for (int k = 0; k < n; ++k) wg_tex_destroy(t[k]);
            wg_chain_destroy(&a->lev[l].red);
        }
        wg_tex_destroy(&a->coarse_L);
        wg_amg_pack* pk[2] = {&a->group, &a->sub};
        for (int k = 0; k < 2; ++k) {
            wg_tex_destroy(&pk[k]->i);
            wg_tex_destroy(&pk[k]->fp);
            wg_tex_destroy(&pk[k]->v);
        }
        wg_tex_destroy(&a->cross_u);
        wg_chain_destroy(&a->cen_red);
    }
    const wc_allocator* al = &a->run->layout->alloc;
    wc_free(al, a->node_of);
    wc_free(al, a->cross_buf);
    wc_free(al, a->cross_cnt);
    wc_free(al, a->cross_scratch);
    wc_free(al, a);
}

void wg_amg_destroy(wg_amg* a) { release(a, 1); }
void wg_amg_forget(wg_amg* a) { release(a, 0); }

size_t wg_amg_bytes(const wg_amg* a) {
    if (!a) return 0;
    size_t bytes = 0;
    const wg_tex* own[] = {&a->coarse_L, &a->group.i, &a->group.fp, &a->group.v,
                           &a->sub.i,    &a->sub.fp,   &a->sub.v,   &a->cross_u};
    for (int k = 0; k < 8; ++k) bytes += own[k]->id ? wg_tex_bytes(own[k]) : 0;
    for (int l = 0; l < a->n_levels; ++l) {
        wg_tex* t[64];
        int n = level_textures((wg_amg_level*)&a->lev[l], t);
        for (int k = 0; k < n; ++k) bytes += t[k]->id ? wg_tex_bytes(t[k]) : 0;
        bytes += wg_chain_bytes(&a->lev[l].red);
    }
    return bytes + wg_chain_bytes(&a->cen_red);
}

/* The pass p (a coarse level's) or its form over the finest level, p's *_FINE. */
static wg_pass_id level_pass(wg_pass_id p, int l) {
    if (l > 0) return p;
    switch (p) {
    case WGP_AMG_GALERKIN: return WGP_AMG_GALERKIN_FINE;
    case WGP_AMG_DINV: return WGP_AMG_DINV_FINE;
    case WGP_AMG_POWER: return WGP_AMG_POWER_FINE;
    case WGP_AMG_SMOOTH: return WGP_AMG_SMOOTH_FINE;
    case WGP_AMG_RESTRICT: return WGP_AMG_RESTRICT_FINE;
    case WGP_AMG_FACTOR_GROUPS: return WGP_AMG_FACTOR_GROUPS_FINE;
    case WGP_AMG_PROLONGATOR: return WGP_AMG_PROLONGATOR_FINE;
    case WGP_AMG_AP: return WGP_AMG_AP_FINE;
    case WGP_AMG_RESIDUAL: return WGP_AMG_RESIDUAL_FINE;
    case WGP_AMG_PROLONG: return WGP_AMG_PROLONG_FINE;
    case WGP_AMG_RESTRICT_RES: return WGP_AMG_RESTRICT_RES_FINE;
    case WGP_AMG_COARSE_RESTRICT_GROUPS: return WGP_AMG_COARSE_RESTRICT_GROUPS_FINE;
    default: return p;
    }
}

/* Level l's inputs (amg_level_inputs.glsl): its pattern, its operator (on the finest level the
 * system's blocks, A and S; on a coarser one the level's blocks) and its D^-1. Each pass's table
 * takes those its shader reads. */
static wg_amg_in level_in(const wg_amg* a, int l) {
    const wg_amg_level* L = &a->lev[l];
    wg_amg_in in = {.rows = &L->rows, .dinv0 = &L->dinv[0], .dinv1 = &L->dinv[1], .dinv2 = &L->dinv[2]};
    if (l == 0) {
        in.cols = a->sys.block;
        in.a_lo = a->sys.a_lo;
        in.a_hi = a->sys.a_hi;
        in.S0 = a->sys.S0;
        in.S1 = a->sys.S1;
    } else {
        in.cols = &L->cols;
        in.a0 = &L->a[0];
        in.a1 = &L->a[1];
        in.a2 = &L->a[2];
    }
    /* the pairs' cross blocks, or textures of their kinds that u_cross 0 leaves unread */
    in.cross_i = a->cross_cap ? &L->cross_i : &L->rows;
    in.cross_a = a->cross_cap ? &L->cross_a : &L->dinv[0];
    return in;
}

/* Level l's form of pass p with its inputs. */
static void use_level(const wg_amg* a, int l, wg_pass_id p, const wg_amg_in* in) {
    WG_USE(a->run, level_pass(p, l), in);
    wg_u1i(a->run, "u_cross", wg_amg_cross_level(a, l));
    if (l > 0) wg_u1i(a->run, "u_pair", a->lev[l].pair);
}


/* The smoothed prolongator from level l to l + 1 (after l's D^-1 and bound), T = A P and level
 * l + 1's operator P^T T (wg_amg_smooth.c's lists). The products read A's pattern's blocks, not
 * the cross blocks: with a smoothed P the coarse levels are the pattern's hierarchy (the pairs'
 * terms stay on the finest level, wg_amg_cross.c). */
static void smoothed_galerkin(wg_amg* a, int l) {
    wg_runner* run = a->run;
    wg_amg_level *F = &a->lev[l], *N = &a->lev[l + 1];
    wg_amg_in in = level_in(a, l);
    in.bound = F->bound;
    in.p_ent = &F->p_ent;
    in.p_rows = &F->p_rows;
    in.p_range = &F->p_range;
    in.p_list = &F->p_list;
    const int tent = a->rotations; /* else identity blocks: stand-ins unread (u_tent 0) */
    in.tent0 = tent ? &F->tent[0] : &F->dinv[0];
    in.tent1 = tent ? &F->tent[1] : &F->dinv[1];
    in.tent2 = tent ? &F->tent[2] : &F->dinv[2];
    use_level(a, l, WGP_AMG_PROLONGATOR, &in);
    wg_u1i(run, "u_tent", tent);
    wg_u1f(run, "u_weight", a->prolong_weight);
    wg_u1f(run, "u_bound_scale", wg_amg_bound_scale(a, l));
    WG_RUN(run, F->np, &F->p[0], &F->p[1], &F->p[2]);
    in.pv0 = &F->p[0];
    in.pv1 = &F->p[1];
    in.pv2 = &F->p[2];
    in.t_range = &F->t_range;
    in.t_list = &F->t_list;
    use_level(a, l, WGP_AMG_AP, &in);
    WG_RUN(run, F->nt, &F->t[0], &F->t[1], &F->t[2]);
    WG_USE(run, WGP_AMG_PTAP, &(wg_amg_in){.pv0 = &F->p[0], .pv1 = &F->p[1], .pv2 = &F->p[2], .tv0 = &F->t[0],
        .tv1 = &F->t[1], .tv2 = &F->t[2], .gal_range = &N->gal_range, .gal_list = &N->gal_list, .cols = &N->cols,
        .nc = a->current ? &N->nc : &N->r});
    wg_u1i(run, "u_dead_nc", a->current);   /* else the rest positions' bits, gal_range's */
    WG_RUN(run, N->nb, &N->a[0], &N->a[1], &N->a[2]);
}

/* P_tent, the next levels' near-null rows (R) and dead unknowns about the current positions
 * (wg_amg.current): the positions' sum, then per level its aggregates' QR twice, once per next
 * level's node for its rows, centre and dead bits (amg_tent_rows) and once for its coefficients of
 * Q (amg_tent_coef), then P_tent's blocks from those (amg_tent_blocks). */
static void tent_setup(wg_amg* a) {
    wg_runner* run = a->run;
    const wg_tex* x = wg_ring_cur(a->sys.x);
    const wg_tex* cen = wg_reduce(run, &a->cen_red, x, 0, 0, 0, 0);
    for (int l = 0; l + 1 < a->n_levels; ++l) {
        wg_amg_level *F = &a->lev[l], *N = &a->lev[l + 1];
        /* stand-ins (cen) where the level's form does not read them */
        wg_amg_in in = {.tq_range = &F->tq_range, .tq_list = &F->tq_list, .tq_of = &F->tq_of, .pos = l ? cen : x,
                        .cen = cen, .nn0 = l ? &F->nn[0] : cen, .nn1 = l ? &F->nn[1] : cen, .nn2 = l ? &F->nn[2] : cen,
                        .nn3 = l ? &F->nn[3] : cen, .nn4 = l ? &F->nn[4] : cen, .nn5 = l ? &F->nn[5] : cen,
                        .nc = l ? &F->nc : cen, .nc_next = &N->nc, .tq_t0 = &N->tq_t[0], .tq_t1 = &N->tq_t[1],
                        .tq_t2 = &N->tq_t[2], .tq_t3 = &N->tq_t[3], .tq_t4 = &N->tq_t[4], .tq_t5 = &N->tq_t[5]};
        const wg_pass_id pass[3] = {WGP_AMG_TENT_ROWS, WGP_AMG_TENT_COEF, WGP_AMG_TENT_BLOCKS};
        for (int p = 0; p < 3; ++p) {
            WG_USE(run, pass[p], &in);
            wg_u1i(run, "u_fine", l == 0);
            if (p < 2) wg_u1f(run, "u_inv_count", 1.0f / (float)a->lev[0].n);
            if (p == 0) WG_RUN(run, N->n, &N->nn[0], &N->nn[1], &N->nn[2], &N->nn[3], &N->nn[4], &N->nn[5], &N->nc);
            else if (p == 1) WG_RUN(run, N->n, &N->tq_t[0], &N->tq_t[1], &N->tq_t[2], &N->tq_t[3], &N->tq_t[4], &N->tq_t[5]);
            else WG_RUN(run, 2 * F->n, &F->tent[0], &F->tent[1], &F->tent[2]);
        }
    }
}

void wg_amg_setup(wg_amg* a) {
    wg_runner* run = a->run;
    if (a->current) tent_setup(a);
    if (wg_amg_cross_on(a)) { /* each pair slot's filtered vector and c, the same on every level */
        const wg_pair_in pi = wg_pairs_inputs(a->pairs, NULL, NULL);
        WG_USE(run, WGP_AMG_CROSS_TERMS, &(wg_amg_in){.pair_p = pi.pr_p, .pair_w = pi.pr_w, .pair_nc = pi.pr_nc,
            .S0 = a->sys.S0, .S1 = a->sys.S1});
        WG_RUN(run, 4 * a->cross_n, &a->cross_u);
        /* each level's cross blocks: the finest from them, each coarser from the finer level's
           (wg_amg_cross.c's lists) */
        int last = -1;   /* the coarsest level whose products read its blocks */
        for (int l = 0; l < a->n_levels; ++l)
            if (a->lev[l].cross_use) last = l;
        for (int l = 0; l <= last; ++l) {
            wg_amg_level* L = &a->lev[l];
            if (L->cross_nb == 0) continue;   /* no pair with two used slots */
            WG_USE(run, WGP_AMG_CROSS_BLOCKS, &(wg_amg_in){.cross_i = &L->cross_i, .cross_u = &a->cross_u,
                .cross_fine = l ? &a->lev[l - 1].cross_a : &L->dinv[0]});
            wg_u1i(run, "u_cross_nodes", L->n);
            wg_u1i(run, "u_cross_fine", l > 0);
            WG_RUN(run, 3 * L->cross_nb, &L->cross_a);
        }
    }
    for (int l = 0; l < a->n_levels; ++l) {
        wg_amg_level* L = &a->lev[l];
        wg_amg_in in = level_in(a, l);
        if (l > 0 && a->smoothed) {
            smoothed_galerkin(a, l - 1);
        } else if (l > 0) {
            wg_amg_in finer = level_in(a, l - 1);
            finer.gal_range = &L->gal_range;
            finer.gal_list = &L->gal_list;
            use_level(a, l - 1, WGP_AMG_GALERKIN, &finer);
            WG_RUN(run, L->nb, &L->a[0], &L->a[1], &L->a[2]);
        }
        if (l == a->n_levels - 1 && a->dense) {
            /* one work group, factoring in place: the image bound read-write (wg_run_groups binds
               its output write-only) */
            use_level(a, l, WGP_AMG_FACTOR_GROUPS, &in);
            wg_run_in_place(run, L->n, &a->coarse_L);
            break;
        }
        use_level(a, l, WGP_AMG_DINV, &in);
        WG_RUN(run, (L->pair ? 2 : 1) * L->n, &L->dinv[0], &L->dinv[1], &L->dinv[2]);
        /* cold: core's start vector, normalised every WG_AMG_POWER_NORM steps by a reduction of
           the last step's sums; warm: the last setup's iterate, its first step normalising it by
           the last reduction's |v|^2, every step carrying the bound's floor (amg_power.glsl) */
        const int warm = a->warm && L->bound;
        const int steps = warm ? a->warm_steps : l > 0 && a->smoothed ? a->cold_steps[1] : a->cold_steps[0];
        in.v = warm ? &L->v[L->v_last] : &L->v0;
        in.v0 = &L->v0;
        in.bound = warm ? L->bound : &L->v0;   /* unread on a cold setup's first step */
        int mid = 0;   /* a reduction within the setup (it replaces the last setup's) */
        for (int it = 0; it < steps; ++it) {
            const int norm = it == 0 ? warm : it % WG_AMG_POWER_NORM == 0;
            if (norm && it > 0) {
                in.bound = wg_reduce(run, &L->red, &L->part, 0, 0, 0, 0);
                mid = 1;
            }
            use_level(a, l, WGP_AMG_POWER, &in);
            wg_u1i(run, "u_norm", norm);
            wg_u1i(run, "u_floor", !warm ? 0 : L->cold_last && !mid ? 1 : 2);
            wg_u1f(run, "u_floor_factor", (float)a->warm_floor);
            L->v_last = 1 - L->v_last;
            WG_RUN(run, L->n, &L->v[L->v_last], &L->part);
            in.v = &L->v[L->v_last];
        }
        L->bound = wg_reduce(run, &L->red, &L->part, 0, 0, 0, 0);
        L->cold_last = !warm;
    }
    if (a->sub.i.id) wg_amg_pack_values(a, &a->sub);
    if (a->warm) ++a->warm_setups;
    else ++a->cold_setups;
    a->warm = a->warm_steps > 0;
}

void wg_amg_cold(wg_amg* a) {
    if (a) a->warm = 0;
}

/* One smoothing step on level l (amg_smooth.glsl): from x (NULL: zero) and d, with the coarse
 * correction xc added first (NULL: none), into xo and dout; and (r.xo, r.r) into dot unless NULL.
 * two: x and d NULL, the first two steps (0 and `step`, 1 or -1) in one pass (u_zero 2). */
static void smooth(const wg_amg* a, int l, const wg_tex* r, const wg_tex* x, const wg_tex* d,
                   const wg_tex* xc, int step, const wg_tex* xo, const wg_tex* dout, const wg_tex* dot, int two) {
    wg_runner* run = a->run;
    const wg_amg_level* L = &a->lev[l];
    wg_amg_in in = level_in(a, l);
    in.r = r;
    in.x = x ? x : r;   /* unread where NULL: u_zero, u_prolong, the first step */
    in.d = d ? d : r;
    in.bound = L->bound;
    in.xc = xc ? xc : r;
    use_level(a, l, WGP_AMG_SMOOTH, &in);
    wg_u1i(run, "u_step", step);
    wg_u1i(run, "u_zero", two ? 2 : x == NULL);
    wg_u1i(run, "u_prolong", xc != NULL);
    wg_u1f(run, "u_ratio", a->ratio);
    wg_u1f(run, "u_bound_scale", wg_amg_bound_scale(a, l));
    wg_u1i(run, "u_dot", dot != NULL);
    if (dot) WG_RUN(run, L->n, xo, dout, dot);
    else WG_RUN(run, L->n, xo, dout);
}

/* The V-cycle from level l on r; returns the texture holding x. dot (level 0): the last smoothing
 * step's (r.x, r.r) go there, or, where level 0 is the coarsest and factored, amg_dot's. */
static const wg_tex* vcycle(wg_amg* a, int l, const wg_tex* r, const wg_tex* dot) {
    wg_runner* run = a->run;
    wg_amg_level* L = &a->lev[l];
    if (l == a->n_levels - 1) {
        if (a->dense) {
            WG_USE(run, WGP_AMG_COARSE_GROUPS, &(wg_amg_in){.factor = &a->coarse_L, .r = r});
            wg_run_groups(run, L->n, &L->x[1], 1);
            if (dot) {
                WG_USE(run, WGP_AMG_DOT, &(wg_amg_in){.r = r, .z = &L->x[1]});
                WG_RUN(run, L->n, dot);
            }
            return &L->x[1];
        }
        int c = 0, s0 = a->fuse ? 2 : 0;   /* fused: sweeps 0 and 1 in one pass */
        if (s0) smooth(a, l, r, NULL, NULL, NULL, -1, &L->x[1], &L->d[1], s0 == WG_AMG_COARSE_SWEEPS ? dot : NULL, 1);
        if (s0) c = 1;
        for (int s = s0; s < WG_AMG_COARSE_SWEEPS; ++s, c = 1 - c)
            smooth(a, l, r, s ? &L->x[c] : NULL, NULL, NULL, -1, &L->x[1 - c], &L->d[1 - c],
                   s == WG_AMG_COARSE_SWEEPS - 1 ? dot : NULL, 0);
        return &L->x[c];
    }
    wg_amg_level* N = &a->lev[l + 1];
    int c = 0, k0 = a->fuse && a->sweeps >= 2 ? 2 : 0;   /* fused: steps 0 and 1 in one pass */
    if (k0) {
        smooth(a, l, r, NULL, NULL, NULL, 1, &L->x[1], &L->d[1], NULL, 1);
        c = 1;
    }
    for (int k = k0; k < a->sweeps; ++k, c = 1 - c)
        smooth(a, l, r, k ? &L->x[c] : NULL, k ? &L->d[c] : NULL, NULL, k, &L->x[1 - c], &L->d[1 - c], NULL, 0);
    wg_amg_in in = level_in(a, l);
    in.r = r;
    in.x = &L->x[c];
    if (a->smoothed) { /* t = r - A x, then P^T t (one pass on a small level); after the coarse
                          level, x + P xc */
        in.pv0 = &L->p[0];
        in.pv1 = &L->p[1];
        in.pv2 = &L->p[2];
        in.pt_range = &L->pt_range;
        in.pt_list = &L->pt_list;
        const wg_tex* xn = NULL;
        if (a->fuse && l + 2 == a->n_levels && a->dense && L->n <= WG_AMG_FOLD_COARSE_ROWS) {
            /* and the coarsest level's solve, in one work group */
            in.factor = &a->coarse_L;
            use_level(a, l, WGP_AMG_COARSE_RESTRICT_GROUPS, &in);
            wg_u1i(run, "u_rows", L->n);
            wg_run_groups(run, N->n, &N->x[1], 1);
            xn = &N->x[1];
        } else if (a->fuse && L->n <= WG_AMG_FOLD_RESIDUAL) {
            use_level(a, l, WGP_AMG_RESTRICT_RES, &in);
        } else {
            use_level(a, l, WGP_AMG_RESIDUAL, &in);
            WG_RUN(run, L->n, &L->res);
            WG_USE(run, WGP_AMG_RESTRICT_P, &(wg_amg_in){.pv0 = &L->p[0], .pv1 = &L->p[1], .pv2 = &L->p[2],
                .pt_range = &L->pt_range, .pt_list = &L->pt_list, .r = &L->res});
        }
        if (!xn) {
            WG_RUN(run, N->n, &N->r);
            if (a->fuse && a->sub.i.id && l + 1 == a->sub.first) {
                /* the V-cycle from the next level down in one work group */
                WG_USE(run, WGP_AMG_SUB_GROUPS, &(wg_amg_sub_in){.r = &N->r, .ipack = &a->sub.i,
                    .fpack = &a->sub.fp, .factor = a->dense ? &a->coarse_L : &a->sub.fp});
                wg_u1i(run, "u_cut", l + 1);
                wg_u1i(run, "u_levels", a->n_levels);
                wg_u1i(run, "u_dense", a->dense);
                wg_u1i(run, "u_smoothed", a->smoothed);
                wg_u1i(run, "u_sweeps", a->sweeps);
                wg_u1i(run, "u_coarse_sweeps", WG_AMG_COARSE_SWEEPS);
                wg_u1f(run, "u_ratio", a->ratio);
                const wg_tex* const out[] = {&N->x[1]};
                wg_run_groups_scratch(run, N->n, 1, out, 1, &a->sub.v);
                xn = &N->x[1];
            } else {
                xn = vcycle(a, l + 1, &N->r, NULL);
            }
        }
        in.xc = xn;
        in.pv0 = &L->p[0];
        in.pv1 = &L->p[1];
        in.pv2 = &L->p[2];
        in.p_ent = &L->p_ent;
        in.p_rows = &L->p_rows;
        use_level(a, l, WGP_AMG_PROLONG, &in);
        WG_RUN(run, L->n, &L->x[1 - c]);
        c = 1 - c;
        for (int k = 0; k < a->sweeps; ++k, c = 1 - c)
            smooth(a, l, r, &L->x[c], k ? &L->d[c] : NULL, NULL, k, &L->x[1 - c], &L->d[1 - c],
                   k == a->sweeps - 1 ? dot : NULL, 0);
        return &L->x[c];
    }
    in.mem_range = &N->mem_range;
    in.mem_list = &N->mem_list;
    use_level(a, l, WGP_AMG_RESTRICT, &in);
    WG_RUN(run, N->n, &N->r);
    const wg_tex* xc = vcycle(a, l + 1, &N->r, NULL);
    for (int k = 0; k < a->sweeps; ++k, c = 1 - c)
        smooth(a, l, r, &L->x[c], k ? &L->d[c] : NULL, k ? NULL : xc, k, &L->x[1 - c], &L->d[1 - c],
               k == a->sweeps - 1 ? dot : NULL, 0);
    return &L->x[c];
}

void wg_amg_apply(wg_amg* a, const wg_tex* r, const wg_tex* dot) { a->z = vcycle(a, 0, r, dot); }
