/* Fuzz harness (4): weft_cloth_create from fuzzed host arrays (positions, face sizes, indices,
 * counts, a few def fields, attachments, a collider), then a few weft_cloth_step calls with
 * fuzzed frames and the outputs, through the public API of libweft.so.
 *
 * Input (bytes read in order; missing bytes read as 0):
 *   n_vertices (0..47; 255: -1), n_faces (0..47; 255: -1), mode flags, parameter byte,
 *   positions (raw float bits when mode bit 0, else int8 x 0.05 m), face sizes (0..7),
 *   indices (mode bit 1: raw int16, else a byte mod n_vertices + 2, so a few are out of range),
 *   attachment vertices (mode bit 6), a collider (mode bit 7), then frames: count (0..3), and
 *   per frame dt, transform and flags selectors.
 *
 * Guarantees checked: every call returns a status (a crash or sanitizer report is the finding);
 * a created cloth reports as many vertices as the host gave; after a step that returned OK every
 * output position is finite and within 1e30 and every normal finite; a snapshot saved from the
 * cloth restores. */
#include <math.h>
#include <stdlib.h>
#include "fuzz.h"
#include "fuzz_grid.h"

#define MAX_V 48
#define MAX_F 48
#define MAX_I (MAX_F * 7)

static weft_context* ctx;

int LLVMFuzzerInitialize(int* argc, char*** argv) {
    (void)argc;
    (void)argv;
    weft_context_def cd = weft_default_context_def();
    cd.backend = WEFT_BACKEND_CPU;
    cd.threads = 1;
    cd.log_level = WEFT_LOG_ERROR;
    if (weft_context_create(WEFT_ABI, &cd, &ctx) != WEFT_OK) abort();
    return 0;
}

static void frame_transform(float m[16], uint8_t sel) {
    memcpy(m, fuzz_identity, sizeof fuzz_identity);
    switch (sel % 6) {
    case 0: break;
    case 1: m[12] = 0.3f; m[14] = -0.2f; break;                       /* moved */
    case 2: m[0] = 0.0f; m[2] = -1.0f; m[8] = 1.0f; m[10] = 0.0f; break; /* turned 90 deg about Y */
    case 3: m[12] = 1e6f; break;                                       /* teleported far */
    case 4: m[0] = 2.0f; break;                                        /* not rigid: refused */
    case 5: m[5] = NAN; break;                                         /* refused */
    }
}

int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    fuzz_reader r = {data, size};
    static float pos[3 * MAX_V];
    static int sizes[MAX_F], idx[MAX_I], pinned[8];
    uint8_t b0 = fuzz_u8(&r), b1 = fuzz_u8(&r);
    int nv = b0 == 255 ? -1 : b0 % MAX_V;
    int nf = b1 == 255 ? -1 : b1 % MAX_F;
    uint8_t mode = fuzz_u8(&r), param = fuzz_u8(&r);
    int nv_arr = nv > 0 ? nv : 0, nf_arr = nf > 0 ? nf : 0;
    for (int i = 0; i < 3 * nv_arr; ++i)
        pos[i] = (mode & 1) ? fuzz_f32_raw(&r) : (float)(int8_t)fuzz_u8(&r) * 0.05f;
    int n_idx = 0;
    for (int f = 0; f < nf_arr; ++f) {
        sizes[f] = fuzz_u8(&r) % 8;
        n_idx += sizes[f];
    }
    for (int i = 0; i < n_idx; ++i)
        idx[i] = (mode & 2) ? (int)(int16_t)fuzz_u16(&r) : (int)(fuzz_u8(&r) % (unsigned)(nv_arr + 2));

    weft_cloth_def def = weft_default_cloth_def();
    def.mesh.positions = (mode & 4) && nv_arr == 0 ? NULL : pos;
    def.mesh.n_vertices = nv;
    def.mesh.face_sizes = (mode & 8) ? NULL : sizes;
    def.mesh.n_faces = nf;
    def.mesh.indices = idx;
    static const double welds[4] = {1e-6, 0.0, 0.2, 1.0};
    static const double scales[4] = {1.0, 0.01, 1e-30, 1e30};
    def.weld_tolerance = welds[param & 3];
    def.unit_scale = scales[(param >> 2) & 3];
    def.solver = (weft_solver)((mode >> 4) & 3);
    def.substeps = 1 + ((param >> 4) & 1);
    def.strain_limit = (param & 32) ? 0.1 : 0.0;
    def.max_iterations = (param & 64) ? 5 : 100;
    def.sleep_speed = (param & 128) ? 0.0 : 1e-3;

    weft_attachment_def at = weft_default_attachment_def();
    if (mode & 64) {
        int na = fuzz_u8(&r) % 5;
        for (int k = 0; k < na; ++k) pinned[k] = (int)(fuzz_u8(&r) % (unsigned)(nv_arr + 1));
        at.vertices = pinned;
        at.n_vertices = na;
        def.attachments = &at;
        def.n_attachments = 1;
    }
    weft_collider_def col = weft_default_collider_def();
    if (mode & 128) {
        uint8_t c = fuzz_u8(&r);
        col.type = (weft_collider_type)(c % 4);   /* 3: not a type, refused */
        static const double radii[4] = {0.5, 0.0, 1e-9, 1e9};
        col.radius = radii[(c >> 2) & 3];
        col.friction = (c & 16) ? 0.0 : 2.0;
        col.transform[13] = (c & 32) ? -0.1f : -2.0f;
        def.colliders = &col;
        def.n_colliders = 1;
    }

    weft_cloth cloth;
    weft_status st = weft_cloth_create(ctx, &def, &cloth);
    if (st != WEFT_OK) {
        FUZZ_CHECK(cloth.id == 0, "a failed create returned a handle");
        FUZZ_CHECK(weft_context_last_error(ctx)[0] != '\0', "refused without a message");
        return 0;
    }
    weft_cloth_info info;
    FUZZ_CHECK(weft_cloth_get_info(ctx, cloth, &info) == WEFT_OK, "info");
    FUZZ_CHECK(info.n_vertices == nv, "%d vertices reported for %d given", info.n_vertices, nv);
    size_t nout = 3 * (size_t)info.n_vertices;
    float* outp = malloc(nout * sizeof(float) + 1);
    float* outn = malloc(nout * sizeof(float) + 1);
    int* tris = malloc(3 * (size_t)info.n_triangles * sizeof(int) + 1);
    unsigned char* snap = malloc(info.snapshot_size);
    FUZZ_CHECK(outp && outn && tris && snap, "out of memory");

    int frames = fuzz_u8(&r) % 4;
    for (int f = 0; f < frames; ++f) {
        uint8_t sel = fuzz_u8(&r);
        static const double dts[8] = {1.0 / 60, 1.0 / 30, 0.25, 0.0, -1.0, 1e-9, 0.3, 1.0 / 60};
        weft_frame fr = weft_default_frame();
        fr.dt = dts[sel & 7];
        float obj[16], bone[16], coll[16];
        frame_transform(obj, sel >> 3);
        frame_transform(bone, fuzz_u8(&r));
        frame_transform(coll, fuzz_u8(&r));
        uint8_t which = fuzz_u8(&r);
        if (which & 1) fr.object_transform = obj;
        if ((which & 2) && def.n_attachments) fr.attachment_transforms = bone;
        if ((which & 4) && def.n_colliders) fr.collider_transforms = coll;
        fr.flags = (which >> 3) & 7;   /* TELEPORT, RESET, and an unknown flag (refused) */
        weft_frame_stats stats;
        st = weft_cloth_step(ctx, cloth, &fr, &stats);
        if (st != WEFT_OK) continue;
        int count = 0;
        FUZZ_CHECK(weft_cloth_get_vertices(ctx, cloth, (which & 64) ? WEFT_SPACE_OBJECT : WEFT_SPACE_WORLD, outp, outn,
                                           info.n_vertices, &count) == WEFT_OK,
                   "get_vertices: %s", weft_context_last_error(ctx));
        for (size_t k = 0; k < 3 * (size_t)count; ++k) {
            FUZZ_CHECK(isfinite(outp[k]) && fabsf(outp[k]) <= 1e30f, "position %g after an OK step", (double)outp[k]);
            FUZZ_CHECK(isfinite(outn[k]), "normal %g after an OK step", (double)outn[k]);
        }
    }
    int nt = 0;
    FUZZ_CHECK(weft_cloth_get_triangles(ctx, cloth, tris, info.n_triangles, &nt) == WEFT_OK, "triangles");
    for (int k = 0; k < 3 * nt; ++k) FUZZ_CHECK(tris[k] >= 0 && tris[k] < info.n_vertices, "triangle index %d", tris[k]);
    FUZZ_CHECK(weft_cloth_save(ctx, cloth, snap, info.snapshot_size) == WEFT_OK, "save");
    FUZZ_CHECK(weft_cloth_restore(ctx, cloth, snap, info.snapshot_size) == WEFT_OK, "restore of its own snapshot: %s",
               weft_context_last_error(ctx));
    FUZZ_CHECK(weft_cloth_destroy(ctx, cloth) == WEFT_OK, "destroy");
    free(outp);
    free(outn);
    free(tris);
    free(snap);
    return 0;
}
