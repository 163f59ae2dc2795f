/* `weft bench peers`: running Blender's cloth solver on a benchmark scene, as a child process.
 * The driver script is host_glue/blender/peer_cloth_bench.py: this side writes the scene's mesh
 * (one OBJ vertex per particle, in particle order) and a JSON job into a fresh temporary folder,
 * runs `blender -b --factory-startup [-t N] --python-exit-code 1 --python SCRIPT -- JOB RESULT`
 * with a time limit, reads the JSON result (cJSON) and removes the folder. */
#ifndef WEFT_CLI_CMD_BENCH_BLENDER_H
#define WEFT_CLI_CMD_BENCH_BLENDER_H
#include <stddef.h>

#include "cmd_bench.h"

/* What Blender reported. */
typedef struct bench_blender_result {
    char version[32];       /* Blender's version string */
    int threads;            /* threads Blender's scene used (scene.render.threads) */
    int frames;             /* frames simulated and timed */
    double* ms;             /* (frames) wall time of each frame_set (ms) */
    double ms_median;       /* median of ms */
    int n_verts;            /* vertices of the evaluated mesh (== the scene's particles) */
    double* x;              /* (n_verts x 3) positions after the last frame (m) */
    char settings[768];     /* the cloth settings Blender used, "name=value, ..." */
} bench_blender_result;

/* The blender executable: `given` when not NULL (it must be an executable file), else the first
 * `blender` on $PATH. 0 with the path in out, or -1 with the reason in msg. */
int bench_blender_find(const char* given, char* out, size_t size, char* msg, size_t msg_size);

/* Run Blender's cloth on the scene's mesh and pins (held still) for `frames` frames under the
 * scene's gravity, with `threads` threads (0: Blender's default), killing it after timeout_s
 * seconds. 0 on success (out filled; bench_blender_free), or -1 with the reason in msg (and the
 * end of Blender's output when it ran). */
int bench_blender_run(const char* blender, const char* script, const bench_scene* bs, int frames, int threads,
                      double timeout_s, bench_blender_result* out, char* msg, size_t msg_size);

void bench_blender_free(bench_blender_result* r);

#endif
