/* Reductions of a whole array to one texel, channel by channel a sum or a maximum, through a
 * chain of textures made once per array size. Fragment passes: 8 x 8 blocks a level (reduce.glsl)
 * until one texel is left; compute passes: one or two dispatches of reduce_groups.glsl, each level
 * as wide as its dispatch's work groups. A reduction reads every texel of its source: passes write
 * zeros past their items. */
#ifndef WEFT_GPU_SOLVER_REDUCE_H
#define WEFT_GPU_SOLVER_REDUCE_H

#include "wg_runner.h"

#define WG_REDUCE_LEVELS 12

typedef struct wg_chain {
    int n_levels;
    wg_tex level[WG_REDUCE_LEVELS];
} wg_chain;

/* The chain for a w x h source; 0 with err when GL fails. */
int wg_chain_create(const wg_runner* r, wg_chain* ch, int w, int h, char* err, size_t err_len);
void wg_chain_destroy(wg_chain* ch);
size_t wg_chain_bytes(const wg_chain* ch);
/* Reduce src down to one texel: channel c summed (mode 0) or maximised (1). Returns the 1 x 1
 * result, the chain's last level (valid until the chain's next reduction). */
const wg_tex* wg_reduce(wg_runner* r, wg_chain* ch, const wg_tex* src, int m0, int m1, int m2, int m3);
/* A sum (every channel) left for its reader to finish: compute passes run every level but the
 * last and return the texture whose first *count texels (layout order, at most 1,024; the source
 * itself when it has that few) sum to the result, for a pass that finishes it in one group
 * (pcg_scalars_groups.glsl); fragment passes run the whole chain (*count = 1). */
const wg_tex* wg_reduce_sums(wg_runner* r, wg_chain* ch, const wg_tex* src, int* count);

#endif
