/* Scene "object": the cloth object's own motion, its inertia settings and teleports. */
#include <stdio.h>
#include <stdlib.h>

#include "scene_parts.h"

enum { MAX_TELEPORT_FRAME = 100000000 };

static int parse_teleports(const sj_ctx* c, const cJSON* obj, scene_object* o) {
    const cJSON* list = NULL;
    int r = sj_array(c, obj, "object", "teleport", &list);
    if (r <= 0) return r;
    const int n = cJSON_GetArraySize(list);
    if (n == 0) return 0;
    o->teleports = calloc((size_t)n, sizeof(scene_teleport));
    if (!o->teleports) return cli_fail(c->diag, WEFT_ERROR_OUT_OF_MEMORY, "%s: out of memory", c->file), -1;
    static const char* const keys[] = {"frame", "translate"};
    for (const cJSON* it = list->child; it; it = it->next) {
        char path[64];
        snprintf(path, sizeof path, "object.teleport[%d]", o->n_teleports);
        scene_teleport* t = &o->teleports[o->n_teleports];
        if (sj_check_object(c, it, path, keys, COUNT(keys)) < 0) return -1;
        if (sj_require(c, it, path, "frame", "(the frame it happens in, an integer >= 1)") < 0) return -1;
        if (sj_require(c, it, path, "translate", "([x, y, z] metres)") < 0) return -1;
        if (sj_int(c, it, path, "frame", 1, MAX_TELEPORT_FRAME, &t->frame) < 0) return -1;
        if (sj_numbers(c, it, path, "translate", 3, t->translate) < 0) return -1;
        if (o->n_teleports > 0 && t->frame <= o->teleports[o->n_teleports - 1].frame) {
            char field[96];
            snprintf(field, sizeof field, "%s.frame", path);
            return sj_fail(c, field, "frames must increase from one entry to the next (%d after %d)", t->frame,
                           o->teleports[o->n_teleports - 1].frame);
        }
        ++o->n_teleports;
    }
    return 0;
}

int scene_parse_object(const sj_ctx* c, const cJSON* root, scene* s) {
    scene_object* o = &s->object;
    o->motion = scene_motion_still();
    o->linear_inertia = o->angular_inertia = 1.0;
    const cJSON* obj = NULL;
    int r = sj_object(c, root, "", "object", &obj);
    if (r <= 0) return r;
    static const char* const keys[] = {"motion", "linear_inertia", "angular_inertia", "teleport"};
    if (sj_check_object(c, obj, "object", keys, COUNT(keys)) < 0) return -1;
    const cJSON* m = sj_get(obj, "motion");
    if (m && scene_motion_parse(c, m, "object.motion", &o->motion) < 0) return -1;
    static const char* const inertia[] = {"linear_inertia", "angular_inertia"};
    for (int k = 0; k < 2; ++k) {
        double* v = k ? &o->angular_inertia : &o->linear_inertia;
        if (sj_number(c, obj, "object", inertia[k], SJ_NONNEGATIVE, v) < 0) return -1;
        if (*v > 1) {
            char field[64];
            snprintf(field, sizeof field, "object.%s", inertia[k]);
            return sj_fail(c, field, "must be in [0, 1], not %g", *v);
        }
    }
    return parse_teleports(c, obj, o);
}
