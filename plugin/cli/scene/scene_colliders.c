/* Scene "colliders": the schema, and each shape's placement in the public API's conventions. */
#include "scene_colliders.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "scene_parts.h"
#include "scene_xform.h"

static int parse_collider(const sj_ctx* c, const cJSON* item, const char* path, scene_collider* col) {
    static const char* const plane[] = {"type", "normal", "offset", "thickness", "friction", "motion"};
    static const char* const sphere[] = {"type", "center", "radius", "thickness", "friction", "motion"};
    static const char* const capsule[] = {"type", "a", "b", "radius", "thickness", "friction", "motion"};
    memset(col, 0, sizeof *col);
    col->motion = scene_motion_still();
    if (!cJSON_IsObject(item)) return sj_fail(c, path, "must be an object, not %s", sj_type_name(item));
    const char* type = NULL;
    char field[96];
    sj_join(field, sizeof field, path, "type");
    if (sj_string(c, item, path, "type", &type) < 0) return -1;
    if (sj_require(c, item, path, "type", "(\"plane\", \"sphere\", \"capsule\" or \"mesh\")") < 0) return -1;
    col->thickness = SCENE_DEFAULT_THICKNESS;
    col->friction = SCENE_DEFAULT_FRICTION;
    if (strcmp(type, "plane") == 0) {
        col->type = WEFT_COLLIDER_PLANE;
        if (sj_check_object(c, item, path, plane, COUNT(plane)) < 0) return -1;
        if (sj_require(c, item, path, "normal", NULL) < 0) return -1;
        if (sj_unit_vector(c, item, path, "normal", col->normal) < 0) return -1;
        if (sj_number(c, item, path, "offset", SJ_FINITE, &col->offset) < 0) return -1;
    } else if (strcmp(type, "sphere") == 0) {
        col->type = WEFT_COLLIDER_SPHERE;
        if (sj_check_object(c, item, path, sphere, COUNT(sphere)) < 0) return -1;
        if (sj_require(c, item, path, "center", NULL) < 0) return -1;
        if (sj_numbers(c, item, path, "center", 3, col->center) < 0) return -1;
    } else if (strcmp(type, "capsule") == 0) {
        col->type = WEFT_COLLIDER_CAPSULE;
        if (sj_check_object(c, item, path, capsule, COUNT(capsule)) < 0) return -1;
        for (int e = 0; e < 2; ++e) {
            const char* key = e ? "b" : "a";
            if (sj_require(c, item, path, key, NULL) < 0) return -1;
            if (sj_numbers(c, item, path, key, 3, e ? col->b : col->a) < 0) return -1;
        }
    } else {
        return sj_fail(c, field,
                       "unknown collider type \"%s\" (expected \"plane\", \"sphere\", \"capsule\" or \"mesh\")", type);
    }
    if (col->type != WEFT_COLLIDER_PLANE) {
        if (sj_require(c, item, path, "radius", NULL) < 0) return -1;
        if (sj_number(c, item, path, "radius", SJ_POSITIVE, &col->radius) < 0) return -1;
    }
    if (sj_number(c, item, path, "thickness", SJ_NONNEGATIVE, &col->thickness) < 0) return -1;
    if (sj_number(c, item, path, "friction", SJ_NONNEGATIVE, &col->friction) < 0) return -1;
    const cJSON* m = sj_get(item, "motion");
    if (m) {
        sj_join(field, sizeof field, path, "motion");
        if (scene_motion_parse(c, m, field, &col->motion) < 0) return -1;
    }
    return 0;
}

int scene_parse_colliders(const sj_ctx* c, const cJSON* root, scene* s) {
    const cJSON* cols = NULL;
    int r = sj_array(c, root, "", "colliders", &cols);
    if (r <= 0) return r;
    int n = cJSON_GetArraySize(cols);
    if (n == 0) return 0;
    s->colliders = calloc((size_t)n, sizeof(scene_collider));
    if (!s->colliders)
        return cli_fail(c->diag, WEFT_ERROR_OUT_OF_MEMORY, "%s: out of memory", c->file), -1;
    for (const cJSON* it = cols->child; it; it = it->next) {
        char path[64];
        snprintf(path, sizeof path, "colliders[%d]", s->n_colliders + s->n_mesh_colliders);
        const cJSON* type = cJSON_IsObject(it) ? sj_get(it, "type") : NULL;
        if (cJSON_IsString(type) && strcmp(type->valuestring, "mesh") == 0) {
            if (scene_parse_mesh_collider(c, it, path, s, n) < 0) return -1;
            continue;
        }
        const int i = s->n_colliders++;
        if (parse_collider(c, it, path, &s->colliders[i]) < 0) return -1;
    }
    return 0;
}

void scene_collider_placement(const scene_collider* c, double xf[16], double* half_height) {
    *half_height = 0.0;
    if (c->type == WEFT_COLLIDER_PLANE) {   /* +Y onto the normal, the origin onto normal x offset */
        xf_rotate_y_to(c->normal, xf);
        for (int k = 0; k < 3; ++k) xf[12 + k] = c->normal[k] * c->offset;
    } else if (c->type == WEFT_COLLIDER_SPHERE) {
        xf_translation(c->center, xf);
    } else {                               /* +Y along a -> b, the origin at the midpoint */
        double d[3], len = 0.0;
        for (int k = 0; k < 3; ++k) {
            d[k] = c->b[k] - c->a[k];
            len += d[k] * d[k];
        }
        len = sqrt(len);
        if (len > 0) {
            for (int k = 0; k < 3; ++k) d[k] /= len;
            xf_rotate_y_to(d, xf);
        } else {
            xf_identity(xf);               /* a == b: a sphere of the capsule's radius */
        }
        for (int k = 0; k < 3; ++k) xf[12 + k] = 0.5 * (c->a[k] + c->b[k]);
        *half_height = 0.5 * len;
    }
}
