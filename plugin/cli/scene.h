/* A Weft scene file (JSON; schema in sample_scenes/README.md): the mesh (a file or a generated
 * grid) with an optional transform, the material, pins, colliders and the simulation settings.
 * scene_load validates everything it can before any simulation: schema, types, ranges, unknown
 * keys, the mesh itself (imported or generated, transform applied) and pin vertex indices.
 * What needs the built model (pins resolved to particles) is done by scene_pins_resolve. */
#ifndef WEFT_CLI_SCENE_H
#define WEFT_CLI_SCENE_H
#include <stddef.h>

#include "collide.h"
#include "model.h"
#include "source_mesh.h"
#include "state.h"

/* Defaults of fields the core does not default (see sample_scenes/README.md). */
#define SCENE_DEFAULT_FPS 30.0
#define SCENE_DEFAULT_FRAMES 60
#define SCENE_DEFAULT_THICKNESS 0.005        /* m, colliders */
#define SCENE_DEFAULT_FRICTION 0.3           /* colliders */
#define SCENE_DEFAULT_SELECT_TOLERANCE 1e-6  /* m, pin selects */
#define SCENE_GRID_MAX_SIDE 100000           /* vertices along one side of a grid */
#define SCENE_GRID_MAX_VERTICES 16777216     /* vertices of a grid */
#define SCENE_MAX_FILE_BYTES (64 << 20)      /* scene JSON text */

/* One entry of "pins": a set of host vertices sharing a free axis and a velocity. */
typedef struct scene_pin {
    int n_vertices;
    int* vertices;          /* (n_vertices) host vertex indices: "vertices" as written (duplicates
                               kept), or the vertices "select" chose in ascending order */
    int from_select;        /* 1: chosen by "select" (vertices with no particle are skipped) */
    int select_axis;        /* select: 0 x, 1 y, 2 z */
    int select_max;         /* select: 1 the "max" side, 0 the "min" side */
    double select_tolerance;/* select: m, vertices within this of the extreme */
    double free_axis[3];    /* unit vector (line constraint), or zero (fully pinned) */
    double velocity[3];     /* m/s: the target moves from the rest position at this speed */
} scene_pin;

typedef struct scene {
    /* mesh */
    int mesh_is_grid;
    char* mesh_file;        /* file mesh: path resolved against the scene file's folder */
    double mesh_scale;      /* file mesh: metres per file unit (on top of FBX's unit) */
    char* mesh_select;      /* file mesh: node or mesh name, NULL for all */
    int grid_n[2];          /* grid: vertices along X and along Z */
    double grid_size[2];    /* grid: extent along X and along Z (m) */
    int has_transform;
    double transform[16];   /* 4x4 column-major (element (row r, column c) at [4c + r]), affine */
    wc_source_mesh src;     /* the host mesh in metres, transform applied */

    wc_model_def model_def; /* weld tolerance and material */
    wc_sim_def sim;         /* gravity, air, solver, substeps, strain limit, threads; capacities
                               (max_pins 0 = all particles, max_colliders >= n_colliders) */
    int n_pins;
    scene_pin* pins;        /* (n_pins) */
    int n_colliders;
    wc_collider* colliders; /* (n_colliders) */
    double fps;             /* frames per simulated second (> 0) */
    int frames;             /* frames to simulate (>= 0) */
} scene;

/* Read and validate the scene file at path (errors: IO, or SCENE with "PATH: FIELD: problem",
 * or the importer's status for a mesh file that cannot be imported, prefixed "PATH: mesh.file:").
 * On failure *out is zeroed. */
weft_status scene_load(scene* out, const char* path, wc_diag* diag);
/* The same from JSON text; name is used in messages and its folder resolves relative mesh files. */
weft_status scene_parse(scene* out, const char* text, size_t len, const char* name, wc_diag* diag);
void scene_free(scene* s);

/* Pins resolved to particles: duplicates (a vertex named twice, welded vertices) merge into one
 * pin; the same particle in two entries with different free_axis or velocity is an error. */
typedef struct scene_pins {
    int n;
    wc_pin* pins;           /* (n) target = start + velocity t after scene_pins_at(t) */
    double* start;          /* (n x 3) the particle's rest position (m) */
    double* velocity;       /* (n x 3) m/s */
    int moving;             /* any velocity is nonzero */
} scene_pins;

/* Resolve s's pins against the model built from s->src. A vertex named in "vertices" that has no
 * particle is an error naming it (SCENE); "select" skips such vertices. Targets start at t = 0. */
weft_status scene_pins_resolve(scene_pins* out, const scene* s, const wc_model* m, const char* name,
                               wc_diag* diag);
/* Set every target to start + velocity t (t in seconds). */
void scene_pins_at(scene_pins* p, double t);
void scene_pins_free(scene_pins* p);

#endif
