/* The multigrid's copies for one work group (wg_amg.h wg_amg_pack): PCG in one work group
 * (pcg_group_amg.glsl, every level) and the fused V-cycle's coarse sub-cycle (amg_sub_groups.glsl,
 * the levels from the cut down). The levels' patterns packed into one int texture at creation,
 * each smoothed level's bound, D^-1 and blocks packed into one float texture per solve
 * (amg_group_pack_groups.glsl, one pass a level), and the coarse levels' V-cycle vectors in one
 * texture the group reads and writes: a pass has 16 texture units, where the levels' own textures
 * take 10 each. */
#include <string.h>

#include "gpu_error.h"
#include "wg_amg_group.h"

/* ipack's and fpack's layouts: pcg_group_amg.glsl's header. Counts first (v NULL), then fills.
 * With the smoothed prolongator (a->smoothed) each level above the coarsest also packs P's rows
 * and its columns' entries (wg_amg_smooth.c's p_rows / p_ent and pt_range / pt_list, in their
 * order) and fpack P's blocks; with P = P_tent each coarse level its aggregates' members. */
static int pack_patterns(const wg_amg* a, const wc_amg* ca, int first, int* v, int* f_size, int* s_size) {
    const int L = ca->n_levels, sm = a->smoothed;
    int at = 4 * L, f = 0, s = 0;
    for (int l = 0; l < L; ++l) {
        const wc_amg_level* C = &ca->lev[l];
        if (l < first) {   /* above the cut: unread, offsets -1 */
            if (v)
                for (int k = 0; k < 16; ++k) v[16 * l + k] = -1;
            continue;
        }
        const int smoothed = !(l == L - 1 && a->dense), pair = C->group == 2, dn = pair ? 2 * C->n : C->n;
        const int has_p = sm && l + 1 < L, np = has_p ? C->p_start[C->n] : 0;
        int h[16] = {-1, -1, -1, -1, smoothed ? f : -1, l > 0 ? s : -1, C->n, C->n_blocks, -1, -1, pair, -1, np, 0, 0, 0};
        if (smoothed) f += 1 + 3 * dn + (l > 0 ? 3 * C->n_blocks : 0);
        if (has_p) {
            h[11] = f;
            f += 3 * np;
        }
        if (l > 0) {
            s += 4 * C->n;
            h[0] = at;
            for (int i = 0; i < C->n; ++i, ++at)
                if (v) {
                    int* t = v + 4 * at;
                    t[0] = C->row_start[i];
                    t[1] = C->row_start[i + 1];
                    t[2] = C->diag[i];
                    /* a pair level: the block (i, i ^ 1) (wg_amg.c level_create) */
                    t[3] = pair ? wc_amg_find(C->col, C->row_start[i], C->row_start[i + 1], i ^ 1) : C->agg ? C->agg[i] : -1;
                }
            h[1] = at;
            for (int i = 0; i < C->n; ++i)
                for (int k = C->row_start[i]; k < C->row_start[i + 1]; ++k, ++at)
                    if (v) {
                        v[4 * at] = i;
                        v[4 * at + 1] = C->col[k];
                    }
        }
        if (l > 0 && l > first && !sm) {
            /* each aggregate's members, ascending (wg_amg.c upload_groups' order) */
            const wc_amg_level* P = &ca->lev[l - 1];
            h[2] = at;
            h[3] = at + C->n;
            if (v) {
                int* range = v + 4 * h[2];
                int* list = v + 4 * h[3];
                for (int j = 0; j < P->n; ++j) ++range[4 * P->agg[j] + 1];
                for (int I = 0; I < C->n; ++I) {
                    range[4 * I] = I > 0 ? range[4 * (I - 1) + 1] : 0;
                    range[4 * I + 1] += range[4 * I];
                }
                for (int I = 0; I < C->n; ++I) range[4 * I + 2] = range[4 * I];   /* fill cursor */
                for (int j = 0; j < P->n; ++j) list[4 * range[4 * P->agg[j] + 2]++] = j;
                for (int I = 0; I < C->n; ++I) range[4 * I + 2] = 0;
            }
            at += C->n + P->n;
        }
        if (has_p) {
            /* P's rows (entries first, end) then its entries (row, coarse node): amg_prolong.glsl */
            const wc_amg_level* N = &ca->lev[l + 1];
            h[8] = at;
            for (int i = 0; i < C->n; ++i, ++at)
                if (v) {
                    v[4 * at] = C->p_start[i];
                    v[4 * at + 1] = C->p_start[i + 1];
                }
            for (int i = 0; i < C->n; ++i)
                for (int e = C->p_start[i]; e < C->p_start[i + 1]; ++e)
                    if (v) {
                        v[4 * (at + e)] = i;
                        v[4 * (at + e) + 1] = C->p_col[e];
                    }
            at += np;
            /* each next-level node's entries of P (first, end) then (entry, row): amg_restrict_p.glsl */
            h[9] = at;
            for (int I = 0; I < N->n; ++I, ++at)
                if (v) {
                    v[4 * at] = C->pt_start[I];
                    v[4 * at + 1] = C->pt_start[I + 1];
                }
            for (int e = 0; e < np; ++e)
                if (v) {
                    v[4 * (at + e)] = C->pt_entry[e];
                    v[4 * (at + e) + 1] = C->pt_row[e];
                }
            at += np;
        }
        if (v) memcpy(v + 16 * l, h, sizeof h);
    }
    *f_size = f > 0 ? f : 1;
    *s_size = s > 0 ? s : 1;
    return at;
}

/* k's patterns for the levels from first down, its value and vector textures made. */
static int pack_create(wg_amg* a, const wc_amg* ca, wg_amg_pack* k, int first, char* err, size_t el) {
    const wg_layout* L0 = a->run->layout;
    int fs = 0, ss = 0;
    const int n = pack_patterns(a, ca, first, NULL, &fs, &ss);
    int* v = wc_calloc(&L0->alloc, 4u * (size_t)n, sizeof(int));
    if (!v) {
        wg_errorf(err, el, "out of memory");
        return 0;
    }
    pack_patterns(a, ca, first, v, &fs, &ss);
    k->first = first;
    for (int l = 0; l < ca->n_levels; ++l) {
        k->f[l] = v[16 * l + 4];
        k->p[l] = v[16 * l + 11];
    }
    int ok = wg_array_create(L0, &k->i, GL_RGBA32I, n, v, err, el) &&
             wg_array_create(L0, &k->fp, GL_RGBA32F, fs, NULL, err, el) &&
             wg_array_create(L0, &k->v, GL_RGBA32F, ss, NULL, err, el);
    wc_free(&L0->alloc, v);
    return ok;
}

int wg_amg_group_create(wg_amg* a, const wc_amg* ca, char* err, size_t el) {
    /* every level's nodes within the group's rows (a coarse level of 1- and 2-node aggregates
       with rotations has up to twice the finest level's nodes): else the chain solves it */
    for (int l = 0; l < ca->n_levels; ++l)
        if (ca->lev[l].n > WG_GROUP_MAX_PARTICLES) return 1;
    return pack_create(a, ca, &a->group, 0, err, el);
}

int wg_amg_group_fits(const wg_amg* a) { return a->group.i.id != 0; }

int wg_amg_sub_create(wg_amg* a, const wc_amg* ca, char* err, size_t el) {
    const int L = ca->n_levels;
    if (!a->smoothed) return 1;   /* P = P_tent: the pairs' cross terms are in every level */
    int cut = 1;
    while (cut + 1 < L && ca->lev[cut].n > WG_AMG_SUB_ROWS) ++cut;
    if (cut + 1 >= L) return 1;   /* no coarse level with one below it */
    for (int l = cut; l < L; ++l)
        if (ca->lev[l].n > WG_AMG_SUB_NODES) return 1;
    return pack_create(a, ca, &a->sub, cut, err, el);
}

void wg_amg_group_pack(wg_amg* a) { wg_amg_pack_values(a, &a->group); }

void wg_amg_pack_values(wg_amg* a, wg_amg_pack* k) {
    wg_runner* run = a->run;
    for (int l = k->first; l < a->n_levels; ++l) {
        const wg_amg_level* L = &a->lev[l];
        if (k->f[l] < 0) continue;   /* the dense coarsest level: its factor only */
        const int blocks = l > 0, has_p = k->p[l] >= 0, dn = L->pair ? 2 * L->n : L->n;
        WG_USE(run, WGP_AMG_GROUP_PACK_GROUPS, &(wg_amg_in){.dinv0 = &L->dinv[0], .dinv1 = &L->dinv[1],
            .dinv2 = &L->dinv[2], .a0 = blocks ? &L->a[0] : &L->dinv[0], .a1 = blocks ? &L->a[1] : &L->dinv[1],
            .a2 = blocks ? &L->a[2] : &L->dinv[2], .pv0 = has_p ? &L->p[0] : &L->dinv[0],
            .pv1 = has_p ? &L->p[1] : &L->dinv[1], .pv2 = has_p ? &L->p[2] : &L->dinv[2], .bound = L->bound});
        wg_u1i(run, "u_off", k->f[l]);
        wg_u1i(run, "u_dn", dn);
        wg_u1i(run, "u_nb", L->nb);
        wg_u1i(run, "u_blocks", blocks);
        wg_u1i(run, "u_poff", k->p[l]);
        wg_u1i(run, "u_np", has_p ? L->np : 0);
        wg_u1f(run, "u_bound_scale", (float)wg_amg_bound_scale(a, l));
        int items = dn;
        if (blocks && L->nb > items) items = L->nb;
        if (has_p && L->np > items) items = L->np;
        wg_run_groups(run, L->n, &k->fp, (items + 255) / 256);
    }
}

void wg_amg_group_use(wg_amg* a, const wg_pcg_group_in* sys) {
    wg_runner* run = a->run;
    const wg_tex* factor = a->dense ? &a->coarse_L : &a->group.fp;   /* unread without a factor */
    WG_USE(run, WGP_PCG_GROUP_AMG, &(wg_pcg_group_amg_in){.pblocks = sys->pblocks, .block = sys->block,
        .a_lo = sys->a_lo, .a_hi = sys->a_hi, .b = sys->b, .S0 = sys->S0, .S1 = sys->S1, .z = sys->z, .dv = sys->dv,
        .rows = &a->lev[0].rows, .ipack = &a->group.i, .fpack = &a->group.fp, .factor = factor});
    wg_u1i(run, "u_levels", a->n_levels);
    wg_u1i(run, "u_dense", a->dense);
    wg_u1i(run, "u_smoothed", a->smoothed);
    wg_u1i(run, "u_sweeps", a->sweeps);
    wg_u1i(run, "u_coarse_sweeps", WG_AMG_COARSE_SWEEPS);
    wg_u1f(run, "u_ratio", a->ratio);
}
