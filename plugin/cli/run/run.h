/* `weft run`: what the frame loop records, and its outputs (OBJ frames, the stats JSON, the
 * summary table). cmd_run.c drives the simulation through the public API (host/scene_host.c);
 * run_record.c accumulates, run_output.c and run_summary.c write. */
#ifndef WEFT_CLI_RUN_H
#define WEFT_CLI_RUN_H
#include <stdio.h>

#include "scene_types.h"
#include "weft/weft.h"

enum { RUN_STAGES = 7 };   /* forces, assemble, solve, collide, integrate, self_collide, total */
extern const char* const run_stage_names[RUN_STAGES];

/* Fixed facts of a run. */
typedef struct run_info {
    const char* scene;          /* scene file as given */
    int particles, triangles, springs;
    const char* solver;         /* configured solver's name */
    const char* preconditioner; /* "block_jacobi", "amg" or "ic0", as the library resolved it */
    const char* integrator;     /* "be", "bdf2" or "trbdf2", as the library resolved it */
    int newton_iterations;      /* >= 1, as resolved */
    int line_search;            /* 0 off, 1 on, as resolved */
    double newton_forcing;      /* in [0, 1), as resolved */
    double tolerance;           /* the linear solves' relative residual, as resolved */
    const char* backend;        /* "cpu" or "gpu": the cloth's (weft_cloth_info.backend) */
    const char* backend_reason; /* why (weft_cloth_info.backend_reason) */
    int substeps;               /* per frame */
    int threads;                /* OpenMP threads per call */
    double fps;
    const char* out_dir;        /* NULL when no OBJ frames are written */
    const char* render_dir;     /* NULL when no PNG frames are written */
    int self_collision;         /* 0 off, 1 on, as the library resolved it */
    double self_thickness;      /* m */
} run_info;

/* Per-frame values written to --stats's "per_frame" arrays (besides "ms"): rollbacks,
 * max_strain, max_iterations, not_converged, self_impacts, contacts (from the frame's stats),
 * then self_intersections and penetration (m) (the collision check of the frame's end,
 * run_record_check; only with --stats). */
#define RUN_FRAME_VALS 8
extern const char* const run_frame_val_names[RUN_FRAME_VALS];

/* What the frame loop measured. */
typedef struct run_record {
    int frames;                 /* frames stepped */
    double* frame_ms;           /* (frames) wall time of each weft_cloth_step call (ms) */
    double* stage_ms;           /* (frames x RUN_STAGES) the library's own stage timings (ms) */
    double* frame_vals;         /* (frames x RUN_FRAME_VALS) each frame's run_frame_val_names */
    long long iterations;       /* solver iterations, all frames */
    long long solves;           /* linear solves (Newton iterations, friction passes), all frames */
    double precond_ms;          /* wall time building preconditioners, all frames (ms) */
    long long substeps;         /* substeps completed, all frames */
    /* the solves by kind, all frames: Newton steps (energy_steps among them), friction passes */
    long long newton_steps, energy_steps, friction_passes;
    int max_iterations;         /* largest in one solve */
    double residual_max;        /* largest final relative residual of a solve */
    int not_converged;          /* solves stopped at the iteration cap */
    int rollbacks, halvings, direct_fallbacks;
    int failures;               /* substeps that failed every retry */
    int failed_frames;          /* frames that returned WEFT_ERROR_STEP_FAILED */
    long long nonfinite_outputs;/* host vertices with a non-finite output position, all frames */
    double max_strain;          /* largest stretch-spring strain at the end of any frame */
    int contacts_max;           /* most particles in contact at the end of a frame */
    int contacts_final;         /* at the end of the last frame */
    double final_kinetic_energy;/* J */
    double bbox_min[3], bbox_max[3]; /* final host vertex positions (m, world) */
    /* self-collision */
    long long self_impacts;     /* all frames */
    long long self_zones;       /* all frames */
    int self_unresolved;        /* all frames (0 normally) */
    double self_ms;             /* wall time of the stage, all frames (ms) */
    int self_intersections;     /* crossing edge-triangle pairs at the last frame (-1: not checked) */
    double max_penetration;     /* m, at the last frame: deepest particle behind a collider surface */
} run_record;

/* Room for `frames` frames (frame_ms, stage_ms). 0, or -1 when out of memory. */
int run_record_init(run_record* r, int frames);
void run_record_free(run_record* r);
/* Frame f (0-based) took ms of wall time and reported s. */
void run_record_frame(run_record* r, int f, double ms, const weft_frame_stats* s);
/* Frame f's step failed every recovery (WEFT_ERROR_STEP_FAILED, no stats; the cloth is as it
 * was): counted in failed_frames and as one failed substep; stage timings zero. */
void run_record_failed_frame(run_record* r, int f, double ms);
/* Frame f's collision check (weft_cloth_check_collisions at its end). */
void run_record_check(run_record* r, int f, const weft_collision_check* chk);
/* The bounding box of n host positions (n x 3); returns how many have a non-finite coordinate
 * (those are left out of the box). */
long long run_record_bbox(run_record* r, const float* pos, int n);

typedef struct run_summary_stats {
    double median, p95, mean, max;
} run_summary_stats;
/* Of n values with the given stride (zeros when n is 0); scratch: n doubles. */
run_summary_stats run_summarise(const double* values, int n, int stride, double* scratch);
/* Solver iterations per linear solve (0 when none). */
double run_mean_iterations(const run_record* r);

/* One frame as OBJ: `v` lines for the n_verts host positions (n_verts x 3, m), then the source
 * polygons as 1-based `f` lines. 0, or -1 when the file cannot be written. */
int run_write_obj(const char* path, const float* pos, const scene_mesh* mesh, int frame, double time);
/* The stats JSON (keys in sample_scenes/README.md). 0, or -1 (cannot write / out of memory). */
int run_write_stats(const char* path, const run_info* info, const run_record* rec);
void run_print_summary(FILE* out, const run_info* info, const run_record* rec);

/* Create a folder and its missing parents (like mkdir -p). 0, or -1 with errno set. */
int run_make_dirs(const char* path);

/* --cache: a point cache (PC2 or MDD, by the file's extension; layouts in run_cache.c). */
enum { RUN_CACHE_PC2 = 0, RUN_CACHE_MDD = 1 };
typedef struct run_cache {
    FILE* f;          /* the .part file being written */
    char* part;       /* path + ".part" */
    const char* path;
    int kind;         /* RUN_CACHE_PC2 or RUN_CACHE_MDD */
    int big;          /* big-endian (MDD) */
} run_cache;
/* The kind for path's extension (.pc2 or .mdd, any case), or -1. */
int run_cache_kind(const char* path);
/* Start path.part with the header for samples samples of n_points points at fps frames per
 * second. 0, or -1 with errno set (EINVAL: not .pc2 or .mdd); run_cache_close(c, 0) after. */
int run_cache_open(run_cache* c, const char* path, int n_points, int samples, double fps);
/* Append one sample: n_points x 3 floats (m). 0, or -1 with errno set. */
int run_cache_sample(run_cache* c, const float* pos, int n_points);
/* keep: rename path.part to path; else remove it. 0, or -1 with errno set (the part removed). */
int run_cache_close(run_cache* c, int keep);

#endif
