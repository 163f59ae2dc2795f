/* `weft run --cache FILE.pc2|FILE.mdd`: a point cache of every frame (frame 0, the rest shape,
 * then frames 1..N), each sample every host vertex in the mesh's own order (an OBJ's `v` lines),
 * in metres and world axes as the OBJ frames. Written to FILE.part and renamed at the end, so a
 * failed run leaves no half-written cache.
 *
 * Layouts, as Blender's Mesh Cache modifier reads them (source/blender/modifiers/intern/
 * MOD_meshcache_pc2 and MOD_meshcache_mdd), also read by 3ds Max and Maya:
 *   PC2, little-endian: char[12] "POINTCACHE2\0", int32 version 1, int32 numPoints,
 *        float startFrame, float sampleRate, int32 numSamples, then numSamples x numPoints x
 *        float[3]. Here startFrame 0 and sampleRate 1 (one sample per frame).
 *   MDD, big-endian: int32 numFrames, int32 numPoints, float times[numFrames] (s), then
 *        numFrames x numPoints x float[3]. Here times[k] = k / fps. */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "run.h"

/* The extension compared without case through POSIX strcasecmp (the tool sees only weft.h, so
 * it cannot share core's matcher). */
int run_cache_kind(const char* path) {
    const char* dot = strrchr(path, '.');
    if (dot && strcasecmp(dot, ".pc2") == 0) return RUN_CACHE_PC2;
    if (dot && strcasecmp(dot, ".mdd") == 0) return RUN_CACHE_MDD;
    return -1;
}

static void put_u32(unsigned char* b, uint32_t v, int big) {
    for (int i = 0; i < 4; ++i) b[big ? 3 - i : i] = (unsigned char)(v >> (8 * i));
}

static int put_float(FILE* f, float x, int big) {
    uint32_t u;
    memcpy(&u, &x, sizeof u);
    unsigned char b[4];
    put_u32(b, u, big);
    return fwrite(b, 1, 4, f) == 4 ? 0 : -1;
}

static int put_int(FILE* f, int32_t x, int big) {
    unsigned char b[4];
    put_u32(b, (uint32_t)x, big);
    return fwrite(b, 1, 4, f) == 4 ? 0 : -1;
}

int run_cache_open(run_cache* c, const char* path, int n_points, int samples, double fps) {
    memset(c, 0, sizeof c[0]);
    c->kind = run_cache_kind(path);
    c->path = path;
    if (c->kind < 0) {
        errno = EINVAL;
        return -1;
    }
    const size_t n = strlen(path) + 8;
    c->part = malloc(n);
    if (!c->part) return -1;
    snprintf(c->part, n, "%s.part", path);
    c->f = fopen(c->part, "wb");
    if (!c->f) return -1;
    const int big = c->kind == RUN_CACHE_MDD;
    c->big = big;
    int bad = 0;
    if (c->kind == RUN_CACHE_PC2) {
        bad |= fwrite("POINTCACHE2", 1, 12, c->f) != 12;   /* with its NUL */
        bad |= put_int(c->f, 1, 0) | put_int(c->f, n_points, 0);
        bad |= put_float(c->f, 0.0f, 0) | put_float(c->f, 1.0f, 0) | put_int(c->f, samples, 0);
    } else {
        bad |= put_int(c->f, samples, 1) | put_int(c->f, n_points, 1);
        for (int k = 0; k < samples; ++k) bad |= put_float(c->f, (float)(k / fps), 1);
    }
    return bad ? -1 : 0;
}

int run_cache_sample(run_cache* c, const float* pos, int n_points) {
    int bad = 0;
    for (int i = 0; i < 3 * n_points && !bad; ++i) bad = put_float(c->f, pos[i], c->big);
    return bad ? -1 : 0;
}

int run_cache_close(run_cache* c, int keep) {
    int rc = 0;
    if (c->f) {
        if (fclose(c->f) != 0) rc = -1;
        c->f = NULL;
        if (keep && rc == 0 && rename(c->part, c->path) != 0) rc = -1;
        if (!keep || rc != 0) {
            int saved = errno;
            remove(c->part);
            errno = saved;
        }
    }
    free(c->part);
    c->part = NULL;
    return rc;
}
