/* `weft bench peers`: running Blender's cloth solver on a benchmark scene, as a child process.
 * The driver script is host_glue/blender/peer_cloth_bench.py: this side writes the cloth's mesh
 * (one OBJ vertex per Weft particle) and a JSON job into a fresh temporary folder, runs
 * `blender -b --factory-startup [-t N] --python-exit-code 1 --python SCRIPT -- JOB RESULT` with a
 * time limit, reads the JSON result (cJSON) and removes the folder. */
#ifndef WEFT_CLI_BENCH_BLENDER_H
#define WEFT_CLI_BENCH_BLENDER_H
#include <stddef.h>

#include "scene_types.h"

/* The cloth as Blender gets it: one vertex per Weft particle (the library's rest positions of the
 * host vertices, welded twins merged: they report the same position), the scene's polygons on
 * them, the pinned ones. */
typedef struct bench_peer_mesh {
    const char* name;       /* the scene's, for messages */
    int n;                  /* particles */
    float* x;               /* (n x 3) rest positions, m, world */
    int* of_vertex;         /* (host vertices) the particle of each */
    const scene_mesh* mesh; /* the polygons, on host vertices (borrowed) */
    int n_pins;
    int* pins;              /* (n_pins) pinned particles, each once */
    double gravity[3];      /* m/s^2 */
} bench_peer_mesh;

/* From the host vertices' rest positions (n_vertices x 3, the library's) and the scene's pin
 * groups. 0, or -1 when out of memory. */
int bench_peer_mesh_make(bench_peer_mesh* out, const scene* s, const float* rest, int n_vertices, const char* name);
void bench_peer_mesh_free(bench_peer_mesh* m);

/* What Blender reported. */
typedef struct bench_blender_result {
    char version[32];       /* Blender's version string */
    int threads;            /* threads Blender's scene used (scene.render.threads) */
    char omp_threads[16];   /* OMP_NUM_THREADS as Blender saw it ("": unset) */
    int frames;             /* frames simulated and timed */
    double* ms;             /* (frames) wall time of each frame_set (ms) */
    double ms_median;       /* median of ms */
    double cpu_ms_median;   /* median of each frame_set's process CPU time (ms; NaN: not reported) */
    int n_verts;            /* vertices of the evaluated mesh (== the cloth's particles) */
    double* x;              /* (n_verts x 3) positions after the last frame (m) */
    char settings[768];     /* the cloth settings Blender used, "name=value, ..." */
    float* xs;              /* (frames x n_verts x 3) every frame's positions (m), when the job
                               asked for them (all_frames), else NULL */
} bench_blender_result;

/* The blender executable: `given` when not NULL (it must be an executable file), else the first
 * `blender` on $PATH. 0 with the path in out, or -1 with the reason in msg. */
int bench_blender_find(const char* given, char* out, size_t size, char* msg, size_t msg_size);

/* Run Blender's cloth on the mesh and pins (held still) for `frames` frames under its gravity,
 * with `threads` threads (0: Blender's default; N: `-t N` and OMP_NUM_THREADS=N), killing it after timeout_s seconds. 0 on
 * success (out filled, positions by particle; bench_blender_free), or -1 with the reason in msg
 * (and the end of Blender's output when it ran). */
int bench_blender_run(const char* blender, const char* script, const bench_peer_mesh* pm, int frames, int threads,
                      double timeout_s, bench_blender_result* out, char* msg, size_t msg_size);

/* A run's settings beyond the mesh: bench_blender_run's, plus Blender's quality (steps per frame)
 * and whether every frame's positions come back (read from a float32 file the script writes). */
typedef struct bench_blender_job {
    int frames;
    int threads;            /* 0: Blender's default */
    int quality;            /* the Cloth modifier's steps per frame (0: 5, Blender's default) */
    int all_frames;         /* 1: every frame's positions into the result's xs */
    double timeout_s;
    double spin, ramp, fps; /* spin != 0: the object (so its pins) turned about y as
                               bench_scene_pin_transform turns Weft's pins, frame k at time k / fps */
} bench_blender_job;

int bench_blender_run_job(const char* blender, const char* script, const bench_peer_mesh* pm,
                          const bench_blender_job* job, bench_blender_result* out, char* msg, size_t msg_size);

void bench_blender_free(bench_blender_result* r);

#endif
