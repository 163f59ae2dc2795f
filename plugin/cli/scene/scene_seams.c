/* Scene sewing (docs/design/sewing.md): mesh.sew_distance (m, >= 0), mesh.seams ([[a, b], ...],
 * host vertex indices of the mesh, a != b) and mesh.seam_close_time (s, >= 0), read into the
 * cloth def; indices are checked against the mesh once it is made. */
#include <stdio.h>
#include <stdlib.h>
#include "scene_parts.h"

int scene_parse_seams(const sj_ctx* c, const cJSON* mesh, scene* s) {
    if (sj_number(c, mesh, "mesh", "sew_distance", SJ_NONNEGATIVE, &s->def.sew_distance) < 0) return -1;
    if (sj_number(c, mesh, "mesh", "seam_close_time", SJ_NONNEGATIVE, &s->def.seam_close_time) < 0) return -1;
    const cJSON* list = NULL;
    int r = sj_array(c, mesh, "mesh", "seams", &list);
    if (r <= 0) return r;
    int n = cJSON_GetArraySize(list);
    s->seam_a = malloc(sizeof(int) * (size_t)(n + 1));
    s->seam_b = malloc(sizeof(int) * (size_t)(n + 1));
    if (!s->seam_a || !s->seam_b) return sj_fail(c, "mesh.seams", "out of memory (%d seams)", n);
    int i = 0;
    for (const cJSON* pair = list->child; pair; pair = pair->next, ++i) {
        char path[64];
        snprintf(path, sizeof path, "mesh.seams[%d]", i);
        if (!cJSON_IsArray(pair) || cJSON_GetArraySize(pair) != 2)
            return sj_fail(c, path, "must be a pair [a, b] of vertex indices, not %s%s", sj_type_name(pair),
                           cJSON_IsArray(pair) ? " of another length" : "");
        int v[2];
        for (int k = 0; k < 2; ++k) {
            const cJSON* x = cJSON_GetArrayItem(pair, k);
            double d = cJSON_IsNumber(x) ? x->valuedouble : -1.0;
            if (!cJSON_IsNumber(x) || d < 0 || d > 2147483647.0 || d != (double)(int)d)
                return sj_fail(c, path, "must be a pair of integer vertex indices >= 0");
            v[k] = (int)d;
        }
        if (v[0] == v[1]) return sj_fail(c, path, "sews vertex %d to itself", v[0]);
        s->seam_a[i] = v[0];
        s->seam_b[i] = v[1];
    }
    s->def.n_seams = n;
    s->def.seam_a = s->seam_a;
    s->def.seam_b = s->seam_b;
    return 0;
}

weft_status scene_check_seams(const scene* s, const char* name, cli_diag* diag) {
    for (int i = 0; i < s->def.n_seams; ++i)
        for (int k = 0; k < 2; ++k) {
            int v = k ? s->seam_b[i] : s->seam_a[i];
            if (v >= s->mesh.n_vertices)
                return cli_fail(diag, WEFT_ERROR_SCENE, "%s: mesh.seams[%d]: vertex %d is outside the mesh's %d vertices",
                               name, i, v, s->mesh.n_vertices);
        }
    return WEFT_OK;
}
