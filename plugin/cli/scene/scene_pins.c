/* Scene "pins": the schema of an entry, and the entries grouped as a host's attachments. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "scene_parts.h"

static int parse_vertices(const sj_ctx* c, const cJSON* verts, const char* path, scene_pin* p) {
    char field[128];
    sj_join(field, sizeof field, path, "vertices");
    if (!cJSON_IsArray(verts) || cJSON_GetArraySize(verts) == 0)
        return sj_fail(c, field, "must be a non-empty array of vertex indices, not %s",
                       cJSON_IsArray(verts) ? "an empty array" : sj_type_name(verts));
    p->n_vertices = cJSON_GetArraySize(verts);
    p->vertices = malloc(sizeof(int) * (size_t)p->n_vertices);
    if (!p->vertices) return cli_fail(c->diag, WEFT_ERROR_OUT_OF_MEMORY, "%s: out of memory", c->file), -1;
    int k = 0;
    for (const cJSON* it = verts->child; it; it = it->next, ++k) {
        double v = cJSON_IsNumber(it) ? it->valuedouble : NAN;
        if (!isfinite(v) || v != floor(v) || v < 0 || v > 2147483647.0) {
            char item_path[160];
            snprintf(item_path, sizeof item_path, "%s[%d]", field, k);
            if (!cJSON_IsNumber(it))
                return sj_fail(c, item_path, "must be a vertex index (an integer >= 0), not %s", sj_type_name(it));
            return sj_fail(c, item_path, "must be a vertex index (an integer >= 0), not %g", v);
        }
        p->vertices[k] = (int)v;
    }
    return 0;
}

static int parse_select(const sj_ctx* c, const cJSON* sel, const char* path, scene_pin* p) {
    char field[128], sub[192];
    sj_join(field, sizeof field, path, "select");
    static const char* const skeys[] = {"axis", "side", "tolerance"};
    if (sj_check_object(c, sel, field, skeys, COUNT(skeys)) < 0) return -1;
    const char* axis = NULL;
    const char* side = NULL;
    sj_join(sub, sizeof sub, field, "axis");
    if (sj_require(c, sel, field, "axis", "(\"x\", \"y\" or \"z\")") < 0) return -1;
    if (sj_string(c, sel, field, "axis", &axis) < 0) return -1;
    if (strlen(axis) != 1 || axis[0] < 'x' || axis[0] > 'z')
        return sj_fail(c, sub, "must be \"x\", \"y\" or \"z\", not \"%s\"", axis);
    p->select_axis = axis[0] - 'x';
    sj_join(sub, sizeof sub, field, "side");
    if (sj_require(c, sel, field, "side", "(\"max\" or \"min\")") < 0) return -1;
    if (sj_string(c, sel, field, "side", &side) < 0) return -1;
    if (strcmp(side, "max") != 0 && strcmp(side, "min") != 0)
        return sj_fail(c, sub, "must be \"max\" or \"min\", not \"%s\"", side);
    p->select_max = strcmp(side, "max") == 0;
    p->select_tolerance = SCENE_DEFAULT_SELECT_TOLERANCE;
    if (sj_number(c, sel, field, "tolerance", SJ_NONNEGATIVE, &p->select_tolerance) < 0) return -1;
    p->from_select = 1;
    return 0;
}

/* One pins[i] entry: structure only; vertex ranges and selects are checked once the mesh exists. */
static int parse_pin(const sj_ctx* c, const cJSON* item, const char* path, scene_pin* p) {
    static const char* const keys[] = {"vertices", "select", "free_axis", "velocity", "motion"};
    p->motion = scene_motion_still();
    if (sj_check_object(c, item, path, keys, COUNT(keys)) < 0) return -1;
    const cJSON* verts = sj_get(item, "vertices");
    const cJSON* sel = sj_get(item, "select");
    if (!verts == !sel)
        return sj_fail(c, path, verts ? "give either \"vertices\" or \"select\", not both"
                                      : "needs \"vertices\" or \"select\"");
    if (sj_unit_vector(c, item, path, "free_axis", p->free_axis) < 0) return -1;
    const cJSON* motion = sj_get(item, "motion");
    if (motion && sj_get(item, "velocity")) {
        char field[128];
        sj_join(field, sizeof field, path, "velocity");
        return sj_fail(c, field, "give either \"velocity\" (shorthand) or \"motion\", not both");
    }
    if (sj_numbers(c, item, path, "velocity", 3, p->motion.velocity) < 0) return -1;
    if (motion) {
        char field[128];
        sj_join(field, sizeof field, path, "motion");
        if (scene_motion_parse(c, motion, field, &p->motion) < 0) return -1;
    }
    return verts ? parse_vertices(c, verts, path, p) : parse_select(c, sel, path, p);
}

int scene_parse_pins(const sj_ctx* c, const cJSON* root, scene* s) {
    const cJSON* pins = NULL;
    int r = sj_array(c, root, "", "pins", &pins);
    if (r <= 0) return r;
    int n = cJSON_GetArraySize(pins);
    if (n == 0) return 0;
    s->pins = calloc((size_t)n, sizeof(scene_pin));
    if (!s->pins) return cli_fail(c->diag, WEFT_ERROR_OUT_OF_MEMORY, "%s: out of memory", c->file), -1;
    for (const cJSON* it = pins->child; it; it = it->next) {
        char path[64];
        snprintf(path, sizeof path, "pins[%d]", s->n_pins);
        if (parse_pin(c, it, path, &s->pins[s->n_pins++]) < 0) return -1;
    }
    return 0;
}

static int same_group(const scene_pin* p, const scene_pin_group* g) {
    return p->free_axis[0] == g->free_axis[0] && p->free_axis[1] == g->free_axis[1] &&
           p->free_axis[2] == g->free_axis[2] && scene_motion_equal(&p->motion, &g->motion);
}

weft_status scene_group_pins(scene* s, const char* name, cli_diag* diag) {
    if (s->n_pins == 0) return WEFT_OK;
    const int nv = s->mesh.n_vertices;
    int* owner = malloc(sizeof(int) * (size_t)(nv > 0 ? nv : 1));     /* pins entry of each vertex */
    int* group_of = malloc(sizeof(int) * (size_t)s->n_pins);           /* group of each entry */
    s->pin_groups = calloc((size_t)s->n_pins, sizeof(scene_pin_group));
    if (!owner || !group_of || !s->pin_groups) {
        free(owner);
        free(group_of);
        return cli_fail(diag, WEFT_ERROR_OUT_OF_MEMORY, "%s: out of memory", name);
    }
    for (int v = 0; v < nv; ++v) owner[v] = -1;
    weft_status st = WEFT_OK;
    for (int i = 0; i < s->n_pins && st == WEFT_OK; ++i) {   /* groups, and conflicts */
        const scene_pin* p = &s->pins[i];
        int g = 0;
        while (g < s->n_pin_groups && !same_group(p, &s->pin_groups[g])) ++g;
        if (g == s->n_pin_groups) {
            scene_pin_group* ng = &s->pin_groups[s->n_pin_groups++];
            memcpy(ng->free_axis, p->free_axis, sizeof ng->free_axis);
            ng->motion = p->motion;
            ng->first_pin = i;
        }
        group_of[i] = g;
        for (int k = 0; k < p->n_vertices && st == WEFT_OK; ++k) {
            const int v = p->vertices[k];
            const int o = owner[v];
            if (o >= 0 && group_of[o] != g) {
                char field[96];
                if (p->from_select)
                    snprintf(field, sizeof field, "pins[%d].select", i);
                else
                    snprintf(field, sizeof field, "pins[%d].vertices[%d]", i, k);
                st = cli_fail(diag, WEFT_ERROR_SCENE, "%s: %s: vertex %d is already pinned by pins[%d] with a "
                             "different free_axis or motion", name, field, v, o);
            } else if (o < 0) {
                owner[v] = i;
                ++s->pin_groups[g].n_vertices;
            }
        }
    }
    for (int g = 0; g < s->n_pin_groups && st == WEFT_OK; ++g) {
        scene_pin_group* pg = &s->pin_groups[g];
        pg->vertices = malloc(sizeof(int) * (size_t)(pg->n_vertices > 0 ? pg->n_vertices : 1));
        if (!pg->vertices) st = cli_fail(diag, WEFT_ERROR_OUT_OF_MEMORY, "%s: out of memory", name);
        pg->n_vertices = 0;
    }
    for (int v = 0; v < nv && st == WEFT_OK; ++v)   /* ascending host order */
        if (owner[v] >= 0) {
            scene_pin_group* pg = &s->pin_groups[group_of[owner[v]]];
            pg->vertices[pg->n_vertices++] = v;
        }
    free(owner);
    free(group_of);
    return st;
}
