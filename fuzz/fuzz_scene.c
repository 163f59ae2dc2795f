/* Fuzz harness (2): the scene JSON reader (scene_parse: schema, types, ranges, pins, colliders,
 * motions, camera, and the mesh it names: a generated grid or a file).
 *
 * Input: the JSON text. It is named "WEFT_SOURCE_DIR/sample_scenes/fuzz.json", so a relative
 * mesh file resolves among the sample meshes (skirt.obj, poncho.fbx). Two kinds of input are
 * skipped before parsing, as resources rather than parser bugs: grids of more than 200,000
 * vertices (the reader allows 16.7M: hundreds of MB per input), and mesh files named with a '/'
 * or starting with '.' (a fuzzer must not open /dev/stdin or read outside the sample folder).
 *
 * Guarantees checked: a status with a message for every input; on success the pins name
 * vertices of the mesh. */
#include <cjson/cJSON.h>
#include <stdlib.h>
#include "fuzz.h"
#include "scene.h"
#include "scene_colliders.h"

#ifndef WEFT_SOURCE_DIR
#error "WEFT_SOURCE_DIR must be defined"
#endif
#define FUZZ_SCENE_MAX_GRID 200000.0

/* 1 when the input asks for more than the harness allows (see above). */
static int too_costly(const uint8_t* data, size_t size) {
    cJSON* root = cJSON_ParseWithLength((const char*)data, size);
    if (!root) return 0;   /* the reader will refuse it */
    int costly = 0;
    cJSON* mesh = cJSON_GetObjectItemCaseSensitive(root, "mesh");
    cJSON* grid = cJSON_GetObjectItemCaseSensitive(mesh, "grid");
    cJSON* n = cJSON_GetObjectItemCaseSensitive(grid, "n");
    if (cJSON_IsArray(n)) {
        double product = 1.0;
        cJSON* e;
        cJSON_ArrayForEach(e, n) if (cJSON_IsNumber(e)) product *= e->valuedouble > 1.0 ? e->valuedouble : 1.0;
        costly |= product > FUZZ_SCENE_MAX_GRID;
    }
    /* a mesh file anywhere in the tree ("mesh" may be repeated: cJSON keeps duplicates) */
    for (cJSON* item = root->child; item; item = item->next) {
        if (!item->string || strcmp(item->string, "mesh") != 0) continue;
        for (cJSON* f = item->child; f; f = f->next) {
            if (!f->string || strcmp(f->string, "file") != 0 || !cJSON_IsString(f)) continue;
            const char* name = f->valuestring;
            if (strchr(name, '/') || name[0] == '.' || name[0] == '\0') costly = 1;
        }
    }
    cJSON_Delete(root);
    return costly;
}

int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    if (too_costly(data, size)) return 0;
    scene s;
    cli_diag d;
    memset(&d, 0, sizeof d);
    weft_status st = scene_parse(&s, (const char*)data, size, WEFT_SOURCE_DIR "/sample_scenes/fuzz.json", &d);
    if (st != WEFT_OK) {
        FUZZ_CHECK(d.message[0] != '\0', "status %d without a message", (int)st);
        return 0;
    }
    for (int p = 0; p < s.n_pins; ++p)
        for (int k = 0; k < s.pins[p].n_vertices; ++k)
            FUZZ_CHECK(s.pins[p].vertices[k] >= 0 && s.pins[p].vertices[k] < s.mesh.n_vertices, "pin vertex %d",
                       s.pins[p].vertices[k]);
    for (int c = 0; c < s.n_colliders; ++c) {
        double xf[16], half_height;
        scene_collider_placement(&s.colliders[c], xf, &half_height);
    }
    scene_free(&s);
    return 0;
}
