/* Scripted rigid motions of scene things (pins, colliders, the cloth object), as a host would
 * animate bones and objects. With tau = max(0, t - start):
 *     T(t) = Translate(velocity tau + amplitude sin(2 pi hz tau))
 *            * Translate(pivot) * Rotate(spin_axis, spin_deg_per_s tau) * Translate(-pivot)
 * so T(t) is the identity until start. Schema: sample_scenes/README.md, "Motions". */
#ifndef WEFT_CLI_SCENE_MOTION_H
#define WEFT_CLI_SCENE_MOTION_H
#include "scene_json.h"

typedef struct scene_motion {
    double pivot[3];            /* m, world: the point the spin turns about */
    double velocity[3];         /* m/s */
    double spin_axis[3];        /* unit (0, 1, 0) */
    double spin_deg_per_s;      /* degrees per second, right-handed about spin_axis */
    double amplitude[3];        /* m: oscillation amplitude per axis */
    double hz;                  /* oscillation frequency (0: none) */
    double start;               /* s: the motion begins at this time (>= 0) */
} scene_motion;

/* The motion that never moves (identity at every t). */
scene_motion scene_motion_still(void);
int scene_motion_is_still(const scene_motion* m);
int scene_motion_equal(const scene_motion* a, const scene_motion* b);

/* T(t) as a column-major 4x4 (rigid). */
void scene_motion_at(const scene_motion* m, double t, double out[16]);

/* Read the motion object `value` found at path `field` (strict: unknown keys, types, ranges).
 * *out starts from scene_motion_still(). 0 or -1. */
int scene_motion_parse(const sj_ctx* c, const cJSON* value, const char* field, scene_motion* out);

#endif
