/* The benchmark scenes of `weft bench` (plugin/cli/bench/bench_scene.c) built on core directly,
 * for the benchmark programs that need a wc_state (the linear-solve error on the step's own
 * system, a start displaced inside the state): the same geometry, pins and colliders, the core's
 * default material and settings.
 *   sheetN   N x N particles, 1 m, horizontal at y = 0, hanging from the two corners of one edge
 *   hangN    the same sheet upright (XY plane, top edge at y = 0.5) from its two top corners
 *   drapeN   the sheet 0.3 m above a sphere of radius 0.25 m at the origin, no pins; drape: 64
 *   garment  a mesh file (sample_scenes/skirt.obj) pinned at its waist (every vertex within 1 mm
 *            of its largest y), the waist turning about the y axis up to one turn a second over
 *            0.5 s */
#ifndef WEFT_TESTS_BENCH_CORE_SCENE_H
#define WEFT_TESTS_BENCH_CORE_SCENE_H
#include <stddef.h>

#include "state.h"

typedef struct core_scene {
    char name[32];
    wc_model model;
    int n_pins;
    wc_pin* pins;           /* (n_pins) at rest */
    int n_colliders;        /* 0 or 1 */
    wc_collider sphere;
    double spin;            /* rad/s the pins turn at (0: still) */
    double diag;            /* bounding-box diagonal at rest (m) */
} core_scene;

/* 0, or -1 with msg (unknown name, the mesh cannot be read or modelled). */
int core_scene_build(core_scene* out, const char* name, const char* garment, char* msg, size_t size);
void core_scene_free(core_scene* cs);
/* A state of the scene with sd (its capacities set here), its pins and colliders. */
wc_status core_scene_state(wc_state** out, const core_scene* cs, const wc_sim_def* sd, wc_diag* diag);
/* The pins at the end of a frame ending at time t (s): turned about y by the twirl (out: n_pins). */
void core_scene_pins_at(const core_scene* cs, double t, wc_pin* out);

#endif
