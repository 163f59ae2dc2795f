/* One measured run of a benchmark scene through the public API (bench_run.c): the scene's cloth
 * created on a backend's context (host/scene_host.h), stepped with weft_cloth_step for a number
 * of frames, and per frame the figures a host can read: the frame stats (wall time of the call,
 * stage times, iterations, solves, recoveries, strain), the energies and centre of mass
 * (weft_cloth_get_energy, read outside the timed call) and, at the end, the vertices. */
#ifndef WEFT_CLI_BENCH_RUN_H
#define WEFT_CLI_BENCH_RUN_H
#include <stddef.h>

#include "bench_scene.h"

typedef struct bench_run_opts {
    int backend;            /* BENCH_CPU or BENCH_GPU (its context open: bench_open_backends) */
    weft_cloth_def def;     /* the scene's def with the run's solver, method, substeps...
                               (bench_run_def); the host fills in the mesh, pins and colliders */
    double fps;             /* frames per simulated second */
    int frames;             /* frames to simulate */
    double fail_strain;     /* > 0: stop at the first frame whose strain exceeds this */
    double fail_energy;     /* > 0: stop at the first frame whose energy growth exceeds this */
    int record_frames;      /* 1: every frame's vertices into bench_run.xs (read outside the timed call) */
} bench_run_opts;

/* The scene's def with sleeping off (these benchmarks time active steps). */
weft_cloth_def bench_run_def(const bench_scene* bs);

typedef struct bench_run {
    int frames;             /* frames stepped (fewer than asked when stopped early) */
    int particles;          /* the cloth's (weft_cloth_info) */
    int vertices;           /* host vertices */
    int threads;            /* OpenMP threads of a call (weft_cloth_info) */
    double diag;            /* bounding-box diagonal of the cloth at rest (m) */
    double ms_median;       /* wall time of one weft_cloth_step call (its stats' ms_total), median */
    double cpu_ms_median;   /* the process's CPU time over one weft_cloth_step call, median (ms): with
                               one thread, the wall time an idle machine would give */
    double stage_median[5]; /* forces, assemble, solve, collide, integrate: medians (ms) */
    double iterations;      /* solver iterations per substep, mean */
    int max_iterations;     /* largest in one solve */
    long long substeps;     /* substeps completed */
    int not_converged;      /* solves stopped at the iteration cap */
    int rollbacks, halvings, direct_fallbacks;
    int failures;           /* substeps that failed every retry (a refused frame counts one) */
    int nonfinite;          /* 1 when any position or energy became non-finite */
    double max_strain;      /* largest stretch strain at the end of any frame */
    double energy0;         /* total energy (kinetic + spring + gravity) at the start (J) */
    double energy_end;      /* ... at the end */
    double energy_max;      /* ... largest at the end of any frame */
    double energy_scale;    /* total mass x |g| x bounding-box diagonal (J): energies are reported
                               relative to this */
    long long solves;       /* linear solves (Newton iterations and friction passes included) */
    long long iterations_total; /* solver iterations, summed */
    double precond_ms;      /* preconditioner setup time, summed over the run (ms) */
    double solve_ms;        /* the solve stage's time (setup included), summed over the run (ms) */
    float* x0;              /* (vertices x 3) world positions at rest (owned; bench_run_free) */
    float* x;               /* (vertices x 3) world positions at the end (owned) */
    float* xs;              /* (frames x vertices x 3) world positions at the end of each frame, when
                               record_frames (owned), else NULL */
    double* track;          /* (frames x 4) at the end of each frame: the centre of mass (3, m) and
                               the kinetic energy (J); owned */
} bench_run;

/* Simulate; 0 on success, -1 with msg when the cloth cannot be created or a call fails (a frame
 * whose step fails every recovery, WEFT_ERROR_STEP_FAILED, is counted, not fatal). */
int bench_run_scene(const bench_scene* bs, const bench_run_opts* o, bench_run* out, char* msg, size_t size);
void bench_run_free(bench_run* r);

/* Distances between two position sets (n x 3): RMS and largest. */
void bench_distance(const float* a, const float* b, int n, double* rms, double* max);

/* Per-solve figures of a run: iterations (mean), preconditioner setup and solve-stage ms, the
 * fraction of solves that converged. Solves 0: the substeps stand in (a run with no stats). */
double bench_run_iterations_per_solve(const bench_run* r);
double bench_run_precond_ms_per_solve(const bench_run* r);
double bench_run_solve_ms_per_solve(const bench_run* r);
double bench_run_converged_fraction(const bench_run* r);

#endif
