/* A program outside the Weft tree that uses an installed Weft (built once with find_package(weft),
 * once with pkg-config, by tests/install/test_install.sh): a 4 x 4 grid cloth from arrays, no air
 * drag, 10 frames of 1/60 s; prints the version and every vertex. Exit 1 on any failure. */
#include <stdio.h>

#include <weft/weft.h>

int main(void) {
    weft_version_info v = weft_version();
    printf("weft %d.%d.%d abi %d header abi %d\n", v.major, v.minor, v.patch, v.abi, WEFT_ABI);

    weft_context_def cd = weft_default_context_def();
    weft_context* ctx = NULL;
    if (weft_context_create(WEFT_ABI, &cd, &ctx) != WEFT_OK) {
        fprintf(stderr, "weft_context_create failed\n");
        return 1;
    }
    enum { N = 4 };
    float positions[N * N * 3];
    int face_sizes[(N - 1) * (N - 1)], indices[(N - 1) * (N - 1) * 4];
    for (int k = 0; k < N; ++k)
        for (int i = 0; i < N; ++i) {
            positions[3 * (k * N + i) + 0] = 0.1f * (float)i;
            positions[3 * (k * N + i) + 1] = 1.0f;
            positions[3 * (k * N + i) + 2] = 0.1f * (float)k;
        }
    for (int k = 0, f = 0; k + 1 < N; ++k)
        for (int i = 0; i + 1 < N; ++i, ++f) {
            face_sizes[f] = 4;
            indices[4 * f + 0] = k * N + i;
            indices[4 * f + 1] = (k + 1) * N + i;
            indices[4 * f + 2] = (k + 1) * N + i + 1;
            indices[4 * f + 3] = k * N + i + 1;
        }
    weft_cloth_def def = weft_default_cloth_def();
    def.mesh.positions = positions;
    def.mesh.n_vertices = N * N;
    def.mesh.face_sizes = face_sizes;
    def.mesh.n_faces = (N - 1) * (N - 1);
    def.mesh.indices = indices;
    def.air_drag_normal = 0.0;
    def.air_drag_tangent = 0.0;
    weft_cloth cloth;
    int ok = weft_cloth_create(ctx, &def, &cloth) == WEFT_OK;
    for (int frame = 0; ok && frame < 10; ++frame) {
        weft_frame fr = weft_default_frame();
        fr.dt = 1.0 / 60.0;
        ok = weft_cloth_step(ctx, cloth, &fr, NULL) == WEFT_OK;
    }
    float out[N * N * 3];
    int count = 0;
    ok = ok && weft_cloth_get_vertices(ctx, cloth, WEFT_SPACE_WORLD, out, NULL, N * N, &count) ==
                   WEFT_OK;
    if (!ok) {
        fprintf(stderr, "weft: %s\n", weft_context_last_error(ctx));
        weft_context_destroy(ctx);
        return 1;
    }
    printf("vertices %d\n", count);
    for (int i = 0; i < count; ++i)
        printf("v %d %.6f %.6f %.6f\n", i, out[3 * i], out[3 * i + 1], out[3 * i + 2]);
    weft_context_destroy(ctx);
    return 0;
}
