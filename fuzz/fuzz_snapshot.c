/* Fuzz harness (3): weft_cloth_restore from arbitrary bytes into a live cloth (a 6 x 6 grid with
 * one attachment of two pins, a sphere and a plane collider, stepped 3 frames so that it moves
 * and touches), through the public API of libweft.so.
 *
 * Input: a flags byte, then either the whole buffer (raw mode) or patches over a valid snapshot
 * of the live cloth (u16 offset, u8 length 0..16, then that many bytes, repeated). Flags:
 *   bit 0  raw mode: the rest of the input is the buffer
 *   bit 1  put the live cloth's ABI, version, size and model fingerprint into the header
 *   bit 2  recompute the checksum (as libpng's fuzzers fix CRCs): without it, almost every
 *          mutation stops at the checksum; with it, the content checks are what is fuzzed
 *   bit 3  step 2 frames after a successful restore and read the vertices
 *   bits 4-7  k: pass k * 7 bytes less than the buffer's size (truncation)
 *
 * Guarantees checked: a refused restore changes nothing (a save before and after are equal);
 * after an accepted restore a step either fails with a status or leaves every output finite and
 * within 1e30 (the header's promise: never NaN). */
#include <math.h>
#include <stdlib.h>
#include "fuzz.h"
#include "fuzz_grid.h"

/* the checksum of core/cloth_snapshot.c (private there; the harness recomputes it to get past it) */
static uint64_t mix(uint64_t h, uint64_t w) {
    h ^= w + 0x9E3779B97F4A7C15ull + (h << 6) + (h >> 2);
    h *= 0xBF58476D1CE4E5B9ull;
    return h ^ (h >> 31);
}
static uint64_t hash_bytes(uint64_t h, const void* data, size_t n) {
    const unsigned char* p = data;
    size_t i = 0;
    for (; i + 8 <= n; i += 8) {
        uint64_t w;
        memcpy(&w, p + i, 8);
        h = mix(h, w);
    }
    uint64_t tail = 0;
    for (size_t k = 0; i + k < n; ++k) tail |= (uint64_t)p[i + k] << (8 * k);
    return mix(mix(h, tail), (uint64_t)n);
}
static uint64_t checksum(const unsigned char* buf, size_t size) {
    unsigned char head[40];
    memcpy(head, buf, 40);
    memset(head + 32, 0, 8);
    uint64_t h = hash_bytes(0x636865636bu, head, 40);
    return hash_bytes(h, buf + 40, size - 40);
}

static weft_context* ctx;
static weft_cloth cloth;
static size_t snap_size;
static unsigned char* pristine;   /* the live cloth's snapshot after 3 frames */
static unsigned char* before;     /* scratch: saves to compare */
static unsigned char* after;
static unsigned char* work;       /* the buffer handed to restore */
static float* out_pos;
static int n_out;

int LLVMFuzzerInitialize(int* argc, char*** argv) {
    (void)argc;
    (void)argv;
    weft_context_def cd = weft_default_context_def();
    cd.backend = WEFT_BACKEND_CPU;
    cd.threads = 1;
    cd.log_level = WEFT_LOG_ERROR;
    if (weft_context_create(WEFT_ABI, &cd, &ctx) != WEFT_OK) abort();
    static fuzz_grid g;
    fuzz_grid_make(&g, 6, 0.3f);
    weft_cloth_def def = weft_default_cloth_def();
    fuzz_grid_mesh(&g, &def.mesh);
    weft_attachment_def at = weft_default_attachment_def();
    static const int pinned[2] = {30, 35};
    at.vertices = pinned;
    at.n_vertices = 2;
    weft_collider_def col[2] = {weft_default_collider_def(), weft_default_collider_def()};
    col[0].type = WEFT_COLLIDER_SPHERE;
    col[0].radius = 0.25;
    col[0].transform[13] = 0.0f;
    col[1].type = WEFT_COLLIDER_PLANE;
    col[1].transform[13] = -0.5f;
    def.attachments = &at;
    def.n_attachments = 1;
    def.colliders = col;
    def.n_colliders = 2;
    if (weft_cloth_create(ctx, &def, &cloth) != WEFT_OK) abort();
    weft_frame fr = weft_default_frame();
    fr.dt = 1.0 / 30.0;
    for (int i = 0; i < 3; ++i) weft_cloth_step(ctx, cloth, &fr, NULL);
    weft_cloth_info info;
    if (weft_cloth_get_info(ctx, cloth, &info) != WEFT_OK) abort();
    snap_size = info.snapshot_size;
    n_out = info.n_vertices;
    pristine = malloc(snap_size);
    before = malloc(snap_size);
    after = malloc(snap_size);
    work = malloc(snap_size + 65536);
    out_pos = malloc(3 * (size_t)n_out * sizeof(float));
    if (!pristine || !before || !after || !work || !out_pos) abort();
    if (weft_cloth_save(ctx, cloth, pristine, snap_size) != WEFT_OK) abort();
    return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    fuzz_reader r = {data, size};
    uint8_t flags = fuzz_u8(&r);
    /* every input starts from the same live state */
    FUZZ_CHECK(weft_cloth_restore(ctx, cloth, pristine, snap_size) == WEFT_OK, "%s", weft_context_last_error(ctx));
    size_t n;
    if (flags & 1) {
        n = r.n < snap_size + 65536 ? r.n : snap_size + 65536;
        memcpy(work, r.p, n);
    } else {
        n = snap_size;
        memcpy(work, pristine, n);
        while (r.n >= 3) {
            size_t off = fuzz_u16(&r) % snap_size;
            size_t len = fuzz_u8(&r) % 17;
            for (size_t k = 0; k < len && off + k < n; ++k) work[off + k] = fuzz_u8(&r);
        }
    }
    if ((flags & 2) && n >= 40) {
        uint32_t abi = WEFT_ABI;
        uint64_t total = snap_size;
        memcpy(work + 8, &abi, 4);
        memcpy(work + 12, pristine + 12, 4);   /* version */
        memcpy(work + 16, &total, 8);
        memcpy(work + 24, pristine + 24, 8);   /* model fingerprint */
    }
    if ((flags & 4) && n >= 40) {
        uint64_t total;
        memcpy(&total, work + 16, 8);
        if (total >= 40 && total <= n) {
            uint64_t sum = checksum(work, (size_t)total);
            memcpy(work + 32, &sum, 8);
        }
    }
    size_t cut = (size_t)(flags >> 4) * 7;
    size_t pass = cut < n ? n - cut : 0;

    FUZZ_CHECK(weft_cloth_save(ctx, cloth, before, snap_size) == WEFT_OK, "save");
    weft_status st = weft_cloth_restore(ctx, cloth, pass ? work : (const void*)"", pass);
    if (st != WEFT_OK) {
        FUZZ_CHECK(weft_context_last_error(ctx)[0] != '\0', "refused without a message");
        FUZZ_CHECK(weft_cloth_save(ctx, cloth, after, snap_size) == WEFT_OK, "save");
        FUZZ_CHECK(memcmp(before, after, snap_size) == 0, "a refused restore (%d) changed the cloth", (int)st);
        return 0;
    }
    if (flags & 8) {
        weft_frame fr = weft_default_frame();
        fr.dt = 1.0 / 30.0;
        for (int i = 0; i < 2; ++i) {
            if (weft_cloth_step(ctx, cloth, &fr, NULL) != WEFT_OK) break;
            int count = 0;
            FUZZ_CHECK(weft_cloth_get_vertices(ctx, cloth, WEFT_SPACE_WORLD, out_pos, NULL, n_out, &count) == WEFT_OK,
                       "get_vertices: %s", weft_context_last_error(ctx));
            for (int k = 0; k < 3 * count; ++k)
                FUZZ_CHECK(isfinite(out_pos[k]) && fabsf(out_pos[k]) <= 1e30f,
                           "a step after a restore returned OK with position %g", (double)out_pos[k]);
        }
    }
    return 0;
}
