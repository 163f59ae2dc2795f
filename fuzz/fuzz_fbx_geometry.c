/* Fuzz harness (5): the FBX geometry reader (core/fbx_geometry.c) on raw file bytes, binary or
 * ASCII, without assimp in front of it (assimp refuses most damaged files before the import
 * reaches the reader, so fuzz_import rarely gets this deep).
 *
 * Input: the file's bytes. Guarantees checked: a status with a message for every refused input;
 * on success every polygon's corners name control points of its geometry and the polygon
 * offsets rise from 0 to the corner count. */
#include <stdlib.h>
#include "fbx_geometry.h"
#include "fuzz.h"

int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    wc_fbx_geometries set;
    wc_diag d;
    memset(&d, 0, sizeof d);
    wc_status st = wc_fbx_geometry_read(&set, NULL, data, size, "<fuzz>.fbx", &d);
    if (st != WC_OK) {
        FUZZ_CHECK(d.message[0] != '\0', "status %d without a message", (int)st);
        FUZZ_CHECK(set.n == 0 && set.g == NULL, "refused but %d geometries kept", set.n);
        return 0;
    }
    for (int i = 0; i < set.n; ++i) {
        const wc_fbx_geometry* g = &set.g[i];
        FUZZ_CHECK(g->n_points >= 0 && g->n_polys >= 0, "geometry %d counts", i);
        FUZZ_CHECK(g->poly_start[0] == 0, "geometry %d starts at %d", i, g->poly_start[0]);
        for (int q = 0; q < g->n_polys; ++q)
            FUZZ_CHECK(g->poly_start[q + 1] > g->poly_start[q], "geometry %d polygon %d empty", i, q);
        for (int c = 0; c < g->poly_start[g->n_polys]; ++c)
            FUZZ_CHECK(g->poly_points[c] >= 0 && g->poly_points[c] < g->n_points,
                       "geometry %d corner %d names %d of %d", i, c, g->poly_points[c], g->n_points);
    }
    wc_fbx_geometry_free(&set);
    return 0;
}
