/* The self-collision tests' heap: a 1.6 m strip (5 x 41 vertices, 0.2 m wide) standing on its end
 * with a gentle wave, just above a floor plane (thickness 5 mm, friction 0.3), so that it falls
 * and piles onto itself; and the same strip folded into layers. Shared by the self-collision tests. */
#ifndef WEFT_TESTS_HEAP_STRIP_H
#define WEFT_TESTS_HEAP_STRIP_H
#include <math.h>
#include <string.h>
#include "check.h"
#include "collide.h"
#include "model.h"
#include "test_support.h"
#include "vec3.h"

static void heap_strip(wc_model* m, wc_collider* floor) {
    wc_source_mesh src;
    ts_quad_grid(&src, 5, 41, 0.2, 1.6, 0);
    for (int v = 0; v < src.n_verts; ++v) {
        double* p = src.pos + 3 * v;
        double gx = p[0], gy = p[1];
        v3_set(p, gx - 0.1, 0.03 + gy, 0.03 * sin(6.0 * gy) + 0.1 * gy);
    }
    wc_model_def mdef = wc_default_model_def();
    wc_diag dg = {0};
    CHECK(wc_model_build(m, &src, &mdef, NULL, &dg) == WC_OK);
    wc_source_mesh_free(&src);
    memset(floor, 0, sizeof *floor);
    floor->type = WC_COLLIDER_PLANE;
    v3_set(floor->normal, 0, 1, 0);
    floor->thickness = 0.005;
    floor->friction = 0.3;
}

/* x: the heap's strip folded into 8 layers 4 mm apart (a Z of 0.2 m folds). */
static inline void heap_strip_folded(const wc_model* m, double* x) {
    for (int i = 0; i < m->n_particles; ++i) {
        const double* r = m->rest_pos + 3 * i;
        double gy = r[1] - 0.03; /* 0 .. 1.6 along the strip */
        int layer = (int)floor(gy / 0.2 + 1e-9);
        double local = gy - 0.2 * layer;
        if (layer > 7) layer = 7, local = 0.2;
        x[3 * i] = r[0];
        x[3 * i + 1] = layer % 2 ? 0.2 - local : local;
        x[3 * i + 2] = 0.004 * layer + 0.0005 * sin(40.0 * r[0]);
    }
}

#endif
