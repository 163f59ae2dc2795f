/* The import report as one JSON object (Debian's cJSON). Keys are documented in
 * docs/design/model.md. */
#include "report.h"

#include <cjson/cJSON.h>
#include <stdio.h>
#include <stdlib.h>

/* Every cJSON_Add* returns NULL when out of memory; `ok` collects that. */
static void add_int(cJSON* obj, const char* key, int value, int* ok) {
    if (!cJSON_AddNumberToObject(obj, key, value)) *ok = 0;
}

static void add_vec3(cJSON* obj, const char* key, const double v[3], int* ok) {
    cJSON* arr = cJSON_CreateDoubleArray(v, 3);
    if (!arr || !cJSON_AddItemToObject(obj, key, arr)) {
        cJSON_Delete(arr);
        *ok = 0;
    }
}

/* Wall time of each model-build stage (ms): not part of the import facts, but what a user tuning
 * a large import wants to see. */
static void add_timing(cJSON* root, const weft_import_report* r, int* ok) {
    cJSON* t = cJSON_AddObjectToObject(root, "build_ms");
    if (!t) {
        *ok = 0;
        return;
    }
    const char* names[] = {"weld", "triangulate", "clean", "orient", "topology", "springs", "pattern", "total"};
    const double values[] = {r->ms_weld, r->ms_triangulate, r->ms_clean, r->ms_orient,
                             r->ms_topology, r->ms_springs, r->ms_pattern, r->ms_total};
    for (size_t i = 0; i < sizeof names / sizeof names[0]; ++i)
        if (!cJSON_AddNumberToObject(t, names[i], values[i])) *ok = 0;
}

static void add_polygons(cJSON* root, const weft_import_report* r, int* ok) {
    cJSON* polys = cJSON_AddObjectToObject(root, "polygons");
    if (!polys) {
        *ok = 0;
        return;
    }
    for (int k = 3; k <= WEFT_REPORT_POLYGON_SIDES; ++k) {
        if (!r->polygons[k]) continue;
        char key[8];
        snprintf(key, sizeof key, k < WEFT_REPORT_POLYGON_SIDES ? "%d" : "%d+", k);
        add_int(polys, key, r->polygons[k], ok);
    }
}

static void add_springs(cJSON* root, const weft_import_report* r, int* ok) {
    cJSON* springs = cJSON_AddObjectToObject(root, "springs");
    if (!springs) {
        *ok = 0;
        return;
    }
    add_int(springs, "stretch", r->springs[WEFT_SPRING_STRETCH], ok);
    add_int(springs, "shear", r->springs[WEFT_SPRING_SHEAR], ok);
    add_int(springs, "bend", r->springs[WEFT_SPRING_BEND], ok);
    add_int(springs, "seam", r->springs[3]   /* seam */, ok);
}

static void add_warnings(cJSON* root, const weft_import_report* r, int* ok) {
    cJSON* list = cJSON_AddArrayToObject(root, "warnings");
    if (!list) {
        *ok = 0;
        return;
    }
    for (int i = 0; i < r->n_warnings && i < WEFT_REPORT_MAX_WARNINGS; ++i) {
        cJSON* s = cJSON_CreateString(r->warnings[i]);
        if (!s || !cJSON_AddItemToArray(list, s)) {
            cJSON_Delete(s);
            *ok = 0;
        }
    }
    add_int(root, "warnings_dropped", r->warnings_dropped, ok);
}

int cli_report_json(FILE* out, const char* file, const weft_import_report* r) {
    cJSON* root = cJSON_CreateObject();
    int ok = root != NULL;
    if (ok && !cJSON_AddStringToObject(root, "file", file)) ok = 0;
    if (ok) {
        add_int(root, "source_vertices", r->source_vertices, &ok);
        add_int(root, "unused_vertices", r->unused_vertices, &ok);
        add_int(root, "welded_vertices", r->welded_vertices, &ok);
        add_polygons(root, r, &ok);
        add_int(root, "points", r->polygons[1], &ok);
        add_int(root, "lines", r->polygons[2], &ok);
        add_int(root, "particles", r->particles, &ok);
        add_int(root, "triangles", r->triangles, &ok);
        add_int(root, "degenerate_triangles", r->degenerate_triangles, &ok);
        add_int(root, "duplicate_faces", r->duplicate_faces, &ok);
        add_int(root, "flipped_faces", r->flipped_faces, &ok);
        add_int(root, "edges", r->edges, &ok);
        add_int(root, "boundary_edges", r->boundary_edges, &ok);
        add_int(root, "non_manifold_edges", r->non_manifold_edges, &ok);
        add_int(root, "boundary_loops", r->boundary_loops, &ok);
        add_int(root, "seams", r->seams, &ok);
        add_int(root, "panels", r->panels, &ok);
        add_int(root, "components", r->components, &ok);
        add_int(root, "non_orientable_components", r->non_orientable_components, &ok);
        add_springs(root, r, &ok);
        add_vec3(root, "bbox_min", r->bbox_min, &ok);
        add_vec3(root, "bbox_max", r->bbox_max, &ok);
        if (!cJSON_AddNumberToObject(root, "unit_scale", r->unit_scale)) ok = 0;
        if (!cJSON_AddNumberToObject(root, "weld_distance", r->weld_distance)) ok = 0;
        add_warnings(root, r, &ok);
        add_timing(root, r, &ok);
    }
    char* text = ok ? cJSON_Print(root) : NULL;
    cJSON_Delete(root);
    if (!text) return -1;
    fputs(text, out);
    fputc('\n', out);
    cJSON_free(text);
    return 0;
}
