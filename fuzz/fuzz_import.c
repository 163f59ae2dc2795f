/* Fuzz harness (1): mesh import from memory, all the way to a built model.
 *
 * Input: one selector byte, then the file's bytes. The selector picks the format hint assimp's
 * read-from-memory gets (what a host's "open this buffer as .EXT" does): obj, fbx (binary or
 * ASCII: assimp tells them apart by content), gltf, glb, ply. The bytes go through
 * wc_import_memory (assimp, node walk, NaN checks, joining) and, when that succeeds,
 * wc_model_build (weld, triangulate, clean, orient, winged edge, springs, block pattern) with the
 * default model def.
 *
 * Guarantees checked: a status for every input (a crash or sanitizer report is the finding);
 * on success the model is self-consistent (host map and triangles in range). */
#include <stdlib.h>
#include "fuzz.h"
#include "model.h"
#include "source_mesh.h"

static const char* const hints[] = {"obj", "fbx", "gltf", "glb", "ply"};
#define N_HINTS (sizeof hints / sizeof hints[0])

int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    if (size < 1) return 0;
    const char* hint = hints[data[0] % N_HINTS];
    wc_source_mesh src;
    wc_diag d;
    memset(&d, 0, sizeof d);
    wc_import_opts o = wc_default_import_opts();
    wc_status st = wc_import_memory(&src, NULL, data + 1, size - 1, hint, &o, &d);
    if (st != WC_OK) {
        FUZZ_CHECK(d.message[0] != '\0', "status %d without a message", (int)st);
        return 0;
    }
    FUZZ_CHECK(src.n_verts >= 0 && src.n_polys > 0, "%d vertices, %d polygons", src.n_verts, src.n_polys);
    for (int i = 0; i < src.poly_start[src.n_polys]; ++i)
        FUZZ_CHECK(src.poly_verts[i] >= 0 && src.poly_verts[i] < src.n_verts, "index %d", src.poly_verts[i]);

    wc_model_def def = wc_default_model_def();
    wc_model m;
    memset(&d, 0, sizeof d);
    st = wc_model_build(&m, &src, &def, NULL, &d);
    if (st == WC_OK) {
        FUZZ_CHECK(m.n_host_verts == src.n_verts, "%d host vertices of %d", m.n_host_verts, src.n_verts);
        for (int i = 0; i < m.n_host_verts; ++i)
            FUZZ_CHECK(m.host_to_particle[i] >= -1 && m.host_to_particle[i] < m.n_particles, "host map");
        for (int i = 0; i < 3 * m.n_tris; ++i)
            FUZZ_CHECK(m.tris[i] >= 0 && m.tris[i] < m.n_particles, "triangle corner %d", m.tris[i]);
        for (int s = 0; s < m.n_springs; ++s)
            FUZZ_CHECK(m.springs[s].a >= 0 && m.springs[s].b < m.n_particles, "spring %d", s);
        wc_model_free(&m);
    } else {
        FUZZ_CHECK(d.message[0] != '\0', "model status %d without a message", (int)st);
    }
    wc_source_mesh_free(&src);
    return 0;
}
