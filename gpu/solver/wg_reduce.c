/* Reductions through chains of textures (see wg_reduce.h). */
#include "wg_reduce.h"

#include <string.h>

#include "gpu_error.h"

/* Work groups of reduce_groups.glsl's first dispatch over `texels`: ~1024 texels a group (4 per
   invocation), at most 1024 groups, so that the second dispatch (one group) has at most 1024. */
static int reduce_groups(long long texels) {
    long long k = (texels + 1023) / 1024;
    return k < 1 ? 1 : k > 1024 ? 1024 : (int)k;
}

int wg_chain_create(const wg_runner* r, wg_chain* ch, int w, int h, char* err, size_t err_len) {
    memset(ch, 0, sizeof *ch);
    if (r->dev->compute) {   /* one or two dispatches: each level is as wide as its dispatch's groups */
        int k = reduce_groups((long long)w * h);
        if (k > 1) {
            if (!wg_tex_create(&ch->level[0], GL_RGBA32F, k, 1, NULL, err, err_len)) return 0;
            ++ch->n_levels;
        }
        if (!wg_tex_create(&ch->level[ch->n_levels], GL_RGBA32F, 1, 1, NULL, err, err_len)) return 0;
        ++ch->n_levels;
        return 1;
    }
    do {
        w = (w + 7) / 8;
        h = (h + 7) / 8;
        if (ch->n_levels == WG_REDUCE_LEVELS) {
            wg_errorf(err, err_len, "reduction deeper than %d levels", WG_REDUCE_LEVELS);
            return 0;
        }
        if (!wg_tex_create(&ch->level[ch->n_levels], GL_RGBA32F, w, h, NULL, err, err_len)) return 0;
        ++ch->n_levels;
    } while (w > 1 || h > 1);
    return 1;
}

void wg_chain_destroy(wg_chain* ch) {
    for (int k = 0; k < ch->n_levels; ++k) wg_tex_destroy(&ch->level[k]);
    ch->n_levels = 0;
}

size_t wg_chain_bytes(const wg_chain* ch) {
    size_t bytes = 0;
    for (int k = 0; k < ch->n_levels; ++k) bytes += wg_tex_bytes(&ch->level[k]);
    return bytes;
}

/* levels [0, levels) of the chain over src; returns the last one run (src when none) */
static const wg_tex* run_levels(wg_runner* r, wg_chain* ch, const wg_tex* src, int levels, int m0, int m1, int m2,
                                int m3) {
    const int groups = r->dev->compute;   /* reduce_groups.glsl: a level as wide as its work groups */
    const wg_pass_id pass = groups ? WGP_REDUCE_GROUPS : WGP_REDUCE;
    const wg_tex* in = src;
    for (int k = 0; k < levels; ++k) {
        const wg_tex* out = &ch->level[k];
        WG_USE(r, pass, &(wg_src_in){.src = in});
        wg_u4i(r, "u_mode", m0, m1, m2, m3);
        wg_u2i(r, "u_in", in->w, in->h);
        if (groups) {
            wg_u1i(r, "u_groups", out->w);
            wg_run_groups(r, 1, out, out->w);
        } else {
            WG_RUN(r, out->w * out->h, out);
        }
        in = out;
    }
    return in;
}

const wg_tex* wg_reduce(wg_runner* r, wg_chain* ch, const wg_tex* src, int m0, int m1, int m2, int m3) {
    return run_levels(r, ch, src, ch->n_levels, m0, m1, m2, m3);
}

const wg_tex* wg_reduce_sums(wg_runner* r, wg_chain* ch, const wg_tex* src, int* count) {
    if (!r->dev->compute) {
        *count = 1;
        return wg_reduce(r, ch, src, 0, 0, 0, 0);
    }
    const wg_tex* t = run_levels(r, ch, src, ch->n_levels - 1, 0, 0, 0, 0);
    *count = t->w * t->h;
    return t;
}
