/* The named benchmark scenes (bench_scene.c), written as scene files and read by the scene
 * reader, so they are ordinary Weft scenes. */
#ifndef WEFT_CLI_BENCH_SCENE_H
#define WEFT_CLI_BENCH_SCENE_H
#include <stddef.h>

#include "scene.h"

#define BENCH_GARMENT_SPIN 6.283185307179586   /* rad/s: one turn a second */
#define BENCH_GARMENT_RAMP 0.5                 /* s */

typedef struct bench_scene {
    char name[32];
    scene sc;               /* the scene as parsed: mesh, cloth def, pins, colliders */
    double spin;            /* rad/s: the pins turn about the y axis at this rate (0: still) */
} bench_scene;

/* Build a named scene:
 *   "sheetN"   N x N particles (2 <= N <= 2048), 1 m x 1 m, horizontal at first, hanging from the
 *              two corners of one edge;
 *   "drapeN"   an N x N sheet, 1 m x 1 m, 5 cm above a sphere of radius 0.25 m, falling onto it
 *              (no pins); "drape" is drape64;
 *   "hangN"    the sheetN grid hanging upright from its two top corners (at rest at first);
 *   "garment"  the mesh file `garment` (sample_scenes/skirt.obj, Y up), pinned at the waist
 *              (every vertex within 1 mm of its largest y), the waist turning about the y axis,
 *              speeding up evenly to BENCH_GARMENT_SPIN over BENCH_GARMENT_RAMP (a twirl).
 * The library's default material with every spring stiffness times k_scale and the density times
 * mass_scale, its defaults for everything else. 0, or -1 with msg ("unknown scene 'x'", or the
 * scene reader's message). */
int bench_scene_build(bench_scene* out, const char* name, const char* garment, double k_scale, double mass_scale,
                      char* msg, size_t size);
void bench_scene_free(bench_scene* s);

/* The pins' transform at time t (s): a rotation about the y axis by the scene's twirl angle
 * (identity when the scene does not spin), column-major. */
void bench_scene_pin_transform(const bench_scene* bs, double t, float out[16]);

#endif
