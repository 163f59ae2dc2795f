/* Scene pins -> wc_pin particles (after the model is built), and their moving targets. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "scene.h"

static int same_motion(const scene_pin* a, const scene_pin* b) {
    for (int k = 0; k < 3; ++k)
        if (a->free_axis[k] != b->free_axis[k] || a->velocity[k] != b->velocity[k]) return 0;
    return 1;
}

void scene_pins_free(scene_pins* p) {
    if (!p) return;
    free(p->pins);
    free(p->start);
    free(p->velocity);
    memset(p, 0, sizeof *p);
}

weft_status scene_pins_resolve(scene_pins* out, const scene* s, const wc_model* m, const char* name,
                               wc_diag* diag) {
    memset(out, 0, sizeof *out);
    if (!name) name = "scene";
    if (m->n_host_verts != s->src.n_verts)
        return wc_fail(diag, WEFT_ERROR_INVALID_ARGUMENT, "%s: the model has %d host vertices, the scene mesh %d",
                       name, m->n_host_verts, s->src.n_verts);
    const int np = m->n_particles;
    int* owner = malloc(sizeof(int) * (size_t)(np > 0 ? np : 1));   /* pins entry that pinned each particle */
    out->pins = calloc((size_t)(np > 0 ? np : 1), sizeof(wc_pin));
    out->start = calloc((size_t)(np > 0 ? np : 1), 3 * sizeof(double));
    out->velocity = calloc((size_t)(np > 0 ? np : 1), 3 * sizeof(double));
    weft_status st = WEFT_OK;
    if (!owner || !out->pins || !out->start || !out->velocity)
        st = wc_fail(diag, WEFT_ERROR_OUT_OF_MEMORY, "%s: out of memory for %d pins", name, np);
    for (int p = 0; p < np && owner; ++p) owner[p] = -1;
    for (int i = 0; i < s->n_pins && st == WEFT_OK; ++i) {
        const scene_pin* sp = &s->pins[i];
        for (int k = 0; k < sp->n_vertices && st == WEFT_OK; ++k) {
            const int v = sp->vertices[k];
            const int p = (v >= 0 && v < m->n_host_verts) ? m->host_to_particle[v] : -1;
            if (p < 0) {
                if (!sp->from_select)
                    st = wc_fail(diag, WEFT_ERROR_SCENE, "%s: pins[%d].vertices[%d]: vertex %d has no particle "
                                 "(it is only in dropped degenerate polygons)", name, i, k, v);
                continue;
            }
            if (owner[p] >= 0) {
                if (!same_motion(&s->pins[owner[p]], sp)) {
                    char field[96];
                    if (sp->from_select)
                        snprintf(field, sizeof field, "pins[%d].select", i);
                    else
                        snprintf(field, sizeof field, "pins[%d].vertices[%d]", i, k);
                    st = wc_fail(diag, WEFT_ERROR_SCENE, "%s: %s: vertex %d (particle %d) is already pinned by "
                                 "pins[%d] with a different free_axis or velocity", name, field, v, p, owner[p]);
                }
                continue;
            }
            owner[p] = i;
            wc_pin* pin = &out->pins[out->n];
            pin->particle = p;
            memcpy(pin->free_axis, sp->free_axis, sizeof pin->free_axis);
            memcpy(pin->target, m->rest_pos + 3 * (size_t)p, sizeof pin->target);
            memcpy(out->start + 3 * (size_t)out->n, pin->target, sizeof pin->target);
            memcpy(out->velocity + 3 * (size_t)out->n, sp->velocity, sizeof sp->velocity);
            out->moving |= sp->velocity[0] != 0 || sp->velocity[1] != 0 || sp->velocity[2] != 0;
            ++out->n;
        }
    }
    free(owner);
    if (st != WEFT_OK) scene_pins_free(out);
    return st;
}

void scene_pins_at(scene_pins* p, double t) {
    for (int i = 0; i < p->n; ++i)
        for (int k = 0; k < 3; ++k)
            p->pins[i].target[k] = p->start[3 * (size_t)i + k] + p->velocity[3 * (size_t)i + k] * t;
}
