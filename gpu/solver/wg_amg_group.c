/* The multigrid's copies for PCG in one work group (wg_amg.h, pcg_group_amg.glsl): the
 * hierarchy's patterns packed into one int texture at creation, each smoothed level's bound,
 * D^-1 and blocks packed into one float texture per solve (amg_group_pack_groups.glsl, one pass
 * a level), and the coarse levels' V-cycle vectors in one texture the group reads and writes:
 * the group's pass has 16 texture units, where the levels' own textures take 10 each. */
#include <string.h>

#include "gpu_error.h"
#include "wg_amg.h"

/* ipack's and fpack's layouts: pcg_group_amg.glsl's header. Counts first (v NULL), then fills. */
static int pack_patterns(const wg_amg* a, const wc_amg* ca, int* v, int* f_size, int* s_size) {
    const int L = ca->n_levels;
    int at = 2 * L, f = 0, s = 0;
    for (int l = 0; l < L; ++l) {
        const wc_amg_level* C = &ca->lev[l];
        const int smoothed = !(l == L - 1 && a->dense);
        int h[8] = {-1, -1, -1, -1, smoothed ? f : -1, l > 0 ? s : -1, C->n, C->n_blocks};
        if (smoothed) f += 1 + 3 * C->n + (l > 0 ? 3 * C->n_blocks : 0);
        if (l > 0) {
            const wc_amg_level* P = &ca->lev[l - 1];
            s += 4 * C->n;
            h[0] = at;
            for (int i = 0; i < C->n; ++i, ++at)
                if (v) {
                    int* t = v + 4 * at;
                    t[0] = C->row_start[i];
                    t[1] = C->row_start[i + 1];
                    t[2] = C->diag[i];
                    t[3] = C->agg ? C->agg[i] : -1;
                }
            h[1] = at;
            for (int i = 0; i < C->n; ++i)
                for (int k = C->row_start[i]; k < C->row_start[i + 1]; ++k, ++at)
                    if (v) {
                        v[4 * at] = i;
                        v[4 * at + 1] = C->col[k];
                    }
            /* each aggregate's members, ascending (wg_amg.c upload_groups' order) */
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
        if (v) memcpy(v + 8 * l, h, sizeof h);
    }
    *f_size = f > 0 ? f : 1;
    *s_size = s > 0 ? s : 1;
    return at;
}

int wg_amg_group_create(wg_amg* a, const wc_amg* ca, char* err, size_t el) {
    const wg_layout* L0 = a->run->layout;
    if (ca->lev[0].n > WG_GROUP_MAX_PARTICLES) return 1;
    int fs = 0, ss = 0;
    const int n = pack_patterns(a, ca, NULL, &fs, &ss);
    int* v = wc_calloc(&L0->alloc, 4u * (size_t)n, sizeof(int));
    if (!v) {
        wg_errorf(err, el, "out of memory");
        return 0;
    }
    pack_patterns(a, ca, v, &fs, &ss);
    for (int l = 0; l < ca->n_levels; ++l) a->group_f[l] = v[8 * l + 4];
    int ok = wg_array_create(L0, &a->group_i, GL_RGBA32I, n, v, err, el) &&
             wg_array_create(L0, &a->group_fp, GL_RGBA32F, fs, NULL, err, el) &&
             wg_array_create(L0, &a->group_v, GL_RGBA32F, ss, NULL, err, el);
    wc_free(&L0->alloc, v);
    return ok;
}

int wg_amg_group_fits(const wg_amg* a) { return a->group_i.id != 0; }

void wg_amg_group_pack(wg_amg* a) {
    wg_runner* run = a->run;
    for (int l = 0; l < a->n_levels; ++l) {
        const wg_amg_level* L = &a->lev[l];
        if (a->group_f[l] < 0) continue;   /* the dense coarsest level: its factor only */
        const int blocks = l > 0;
        WG_USE(run, WGP_AMG_GROUP_PACK_GROUPS, &(wg_amg_in){.dinv0 = &L->dinv[0], .dinv1 = &L->dinv[1],
            .dinv2 = &L->dinv[2], .a0 = blocks ? &L->a[0] : &L->dinv[0], .a1 = blocks ? &L->a[1] : &L->dinv[1],
            .a2 = blocks ? &L->a[2] : &L->dinv[2], .bound = L->bound});
        wg_u1i(run, "u_off", a->group_f[l]);
        wg_u1i(run, "u_nb", L->nb);
        wg_u1i(run, "u_blocks", blocks);
        wg_u1f(run, "u_bound_scale", l == 0 ? (float)a->fine_bound_scale : 1.0f);
        const int items = blocks && L->nb > L->n ? L->nb : L->n;
        wg_run_groups(run, L->n, &a->group_fp, (items + 255) / 256);
    }
}

void wg_amg_group_use(wg_amg* a, const wg_pcg_group_in* sys) {
    wg_runner* run = a->run;
    const wg_tex* factor = a->dense ? &a->coarse_L : &a->group_fp;   /* unread without a factor */
    WG_USE(run, WGP_PCG_GROUP_AMG, &(wg_pcg_group_amg_in){.pblocks = sys->pblocks, .block = sys->block,
        .a_lo = sys->a_lo, .a_hi = sys->a_hi, .b = sys->b, .S0 = sys->S0, .S1 = sys->S1, .z = sys->z, .dv = sys->dv,
        .rows = &a->lev[0].rows, .ipack = &a->group_i, .fpack = &a->group_fp, .factor = factor});
    wg_u1i(run, "u_levels", a->n_levels);
    wg_u1i(run, "u_dense", a->dense);
    wg_u1i(run, "u_sweeps", a->sweeps);
    wg_u1i(run, "u_coarse_sweeps", WG_AMG_COARSE_SWEEPS);
    wg_u1f(run, "u_ratio", a->ratio);
}
