/* Helpers of the public-API tests (test_api_*.c): grid meshes as host float arrays, 4x4
 * column-major transforms, a counting allocator, a capturing logger, a snapshot comparison and
 * a snapshot's replay.
 * Header-only, public header only. */
#ifndef WEFT_TESTS_API_GRID_H
#define WEFT_TESTS_API_GRID_H
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "weft/weft.h"

typedef struct ag_mesh {
    int n;          /* grid vertices per side */
    int nv, nf;     /* host vertices, quads */
    float* pos;     /* (nv x 3) */
    int* sizes;     /* (nf) all 4 */
    int* idx;       /* (4 nf) */
} ag_mesh;

/* tests/heap_strip.h's strip as host arrays (the GPU self-collision tests' heap): AG_HEAP_X x
 * AG_HEAP_Y vertices, 0.2 m by 1.6 m, standing on its end with a gentle wave just above the floor. */
#define AG_HEAP_X 5
#define AG_HEAP_Y 41
static inline void ag_heap_strip(ag_mesh* m) {
    memset(m, 0, sizeof *m);
    m->nv = AG_HEAP_X * AG_HEAP_Y;
    m->nf = (AG_HEAP_X - 1) * (AG_HEAP_Y - 1);
    m->pos = malloc(3 * sizeof(float) * (size_t)m->nv);
    m->sizes = malloc(sizeof(int) * (size_t)m->nf);
    m->idx = malloc(4 * sizeof(int) * (size_t)m->nf);
    for (int j = 0; j < AG_HEAP_Y; ++j)
        for (int i = 0; i < AG_HEAP_X; ++i) {
            double gx = 0.2 * i / (AG_HEAP_X - 1), gy = 1.6 * j / (AG_HEAP_Y - 1);
            float* p = m->pos + 3 * (i + AG_HEAP_X * j);
            p[0] = (float)(gx - 0.1);
            p[1] = (float)(0.03 + gy);
            p[2] = (float)(0.03 * sin(6.0 * gy) + 0.1 * gy);
        }
    int q = 0;
    for (int j = 0; j + 1 < AG_HEAP_Y; ++j)
        for (int i = 0; i + 1 < AG_HEAP_X; ++i, ++q) {
            m->sizes[q] = 4;
            int* f = m->idx + 4 * q;
            f[0] = i + AG_HEAP_X * j;
            f[1] = i + 1 + AG_HEAP_X * j;
            f[2] = i + 1 + AG_HEAP_X * (j + 1);
            f[3] = i + AG_HEAP_X * (j + 1);
        }
}

/* Grid point (i, j) of an n x n grid of size metres: horizontal (XZ plane at height y, i along
 * X, j along Z) or vertical (XY plane, i along X, j up, top row j = n - 1 at height y). */
static inline void ag_point(int n, double size, double y, int vertical, int i, int j, float* out) {
    double u = size * i / (n - 1) - 0.5 * size, w = size * j / (n - 1);
    if (vertical) {
        out[0] = (float)u;
        out[1] = (float)(y - size + w);
        out[2] = 0.0f;
    } else {
        out[0] = (float)u;
        out[1] = (float)y;
        out[2] = (float)(w - 0.5 * size);
    }
}

/* Quads counter-clockwise seen from +Y (horizontal) or +Z (vertical). Without split, host vertex
 * (i, j) is i + n j; with split every quad has its own 4 vertices (per-quad UVs): quad q = i +
 * (n - 1) j has vertices 4q .. 4q + 3 at (i, j), (i + 1, j), (i + 1, j + 1), (i, j + 1). */
static inline void ag_grid(ag_mesh* m, int n, double size, double y, int vertical, int split) {
    m->n = n;
    m->nf = (n - 1) * (n - 1);
    m->nv = split ? 4 * m->nf : n * n;
    m->pos = calloc((size_t)m->nv * 3, sizeof(float));
    m->sizes = malloc(sizeof(int) * (size_t)m->nf);
    m->idx = malloc(sizeof(int) * 4 * (size_t)m->nf);
    if (!split)
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) ag_point(n, size, y, vertical, i, j, m->pos + 3 * (i + n * j));
    /* horizontal: (i along X, j along Z) is clockwise from +Y; reverse it. The order is chosen
       outside the loops: GCC 12.2's -O3 loop vectorizer got `vertical ? k : 3 - k` inside them
       wrong when vertical is not a constant (some quads came out with two corners swapped). */
    static const int ccw[4] = {0, 1, 2, 3}, cw[4] = {3, 2, 1, 0};
    const int* order = vertical ? ccw : cw;
    int q = 0;
    for (int j = 0; j + 1 < n; ++j)
        for (int i = 0; i + 1 < n; ++i, ++q) {
            int ci[4] = {i, i + 1, i + 1, i}, cj[4] = {j, j, j + 1, j + 1};
            m->sizes[q] = 4;
            for (int k = 0; k < 4; ++k) {
                int kk = order[k];
                if (split) {
                    ag_point(n, size, y, vertical, ci[kk], cj[kk], m->pos + 3 * (4 * q + k));
                    m->idx[4 * q + k] = 4 * q + k;
                } else {
                    m->idx[4 * q + k] = ci[kk] + n * cj[kk];
                }
            }
        }
}

static inline void ag_free(ag_mesh* m) {
    free(m->pos);
    free(m->sizes);
    free(m->idx);
    memset(m, 0, sizeof *m);
}

static inline weft_mesh_desc ag_desc(const ag_mesh* m) {
    weft_mesh_desc d;
    memset(&d, 0, sizeof d);
    d.positions = m->pos;
    d.n_vertices = m->nv;
    d.face_sizes = m->sizes;
    d.n_faces = m->nf;
    d.indices = m->idx;
    return d;
}

static inline void ag_identity(float* m) {
    memset(m, 0, 16 * sizeof(float));
    m[0] = m[5] = m[10] = m[15] = 1.0f;
}

/* Rotation by angle (rad) about the unit axis (ax, ay, az), then translation (tx, ty, tz). */
static inline void ag_transform(float* m, double ax, double ay, double az, double angle, double tx, double ty,
                                double tz) {
    double c = cos(angle), s = sin(angle), t = 1.0 - c;
    double R[3][3] = {{t * ax * ax + c, t * ax * ay - s * az, t * ax * az + s * ay},
                      {t * ax * ay + s * az, t * ay * ay + c, t * ay * az - s * ax},
                      {t * ax * az - s * ay, t * ay * az + s * ax, t * az * az + c}};
    ag_identity(m);
    for (int r = 0; r < 3; ++r)
        for (int col = 0; col < 3; ++col) m[4 * col + r] = (float)R[r][col];
    m[12] = (float)tx;
    m[13] = (float)ty;
    m[14] = (float)tz;
}

/* out = M p (float transform applied in double) */
static inline void ag_apply(const float* M, const double* p, double* out) {
    for (int r = 0; r < 3; ++r)
        out[r] = (double)M[r] * p[0] + (double)M[4 + r] * p[1] + (double)M[8 + r] * p[2] + (double)M[12 + r];
}

/* The largest distance (m) between the vertices of two position arrays of n vertices (n x 3). */
static inline double ag_max_distance(const float* a, const float* b, int n) {
    double most = 0.0;
    for (int i = 0; i < n; ++i) {
        double s = 0.0;
        for (int k = 0; k < 3; ++k) {
            double e = (double)a[3 * i + k] - (double)b[3 * i + k];
            s += e * e;
        }
        most = fmax(most, sqrt(s));
    }
    return most;
}

/* World positions (n_particles x 3, particle order) from a weft_cloth_save buffer: they start at
 * byte 64 (core/cloth_snapshot.c documents the layout). */
static inline void ag_snapshot_positions(const void* snapshot, int n_particles, double* out) {
    memcpy(out, (const unsigned char*)snapshot + 64, sizeof(double) * 3 * (size_t)n_particles);
}

/* ---- counting allocator and capturing logger ---- */

typedef struct ag_alloc_counter {
    long allocs, frees;
    long live;
} ag_alloc_counter;

static inline void* ag_count_alloc(size_t size, void* user) {
    ag_alloc_counter* c = user;
    ++c->allocs;
    ++c->live;
    return malloc(size);
}

static inline void ag_count_free(void* p, void* user) {
    ag_alloc_counter* c = user;
    ++c->frees;
    --c->live;
    free(p);
}

typedef struct ag_log {
    int count[4];
    char last[512];
} ag_log;

static inline void ag_log_fn(weft_log_level level, const char* message, void* user) {
    ag_log* l = user;
    if ((int)level >= 0 && (int)level < 4) ++l->count[level];
    strncpy(l->last, message, sizeof l->last - 1);
    l->last[sizeof l->last - 1] = '\0';
}

/* 1 when the cloth's snapshot now is ref's bytes (sz of them); 0 when it differs or cannot be
 * taken. */
static inline int ag_same_snapshot(weft_context* ctx, weft_cloth c, const unsigned char* ref, size_t sz) {
    unsigned char* now = malloc(sz);
    int same = now && weft_cloth_save(ctx, c, now, sz) == WEFT_OK && memcmp(now, ref, sz) == 0;
    free(now);
    return same;
}

/* A snapshot's replay: frames 0 .. end - 1 (feed, may be NULL, gives frame f's inputs before the
 * snapshot is taken; frame steps it), the state saved before frame `at`'s step; then restored
 * and frames at .. end - 1 run again. */
typedef weft_status (*ag_feed_fn)(weft_context* ctx, weft_cloth c, int f, void* user);
typedef weft_status (*ag_frame_fn)(weft_context* ctx, weft_cloth c, int f, weft_frame_stats* fs, void* user);
typedef struct ag_replay {
    int ok;                    /* every call returned WEFT_OK (feeds, frames, saves, the restore) */
    int restored_same;         /* the restored state saves to the snapshot's bytes */
    int same;                  /* both runs end in the same snapshot bytes */
    size_t bytes;              /* the snapshot's size */
    weft_frame_stats before;   /* the first run's stats of frame at - 1 */
} ag_replay;

static inline ag_replay ag_snapshot_replay(weft_context* ctx, weft_cloth c, int at, int end, ag_feed_fn feed,
                                           ag_frame_fn frame, void* user) {
    ag_replay r = {.ok = 1};
    weft_cloth_info info;
    if (weft_cloth_get_info(ctx, c, &info) != WEFT_OK) {
        r.ok = 0;
        return r;
    }
    size_t sz = r.bytes = info.snapshot_size;
    unsigned char *snap = malloc(sz), *end1 = malloc(sz), *end2 = malloc(sz);
    if (!snap || !end1 || !end2) r.ok = 0;
    for (int pass = 0; pass < 2 && r.ok; ++pass) {
        int f0 = 0;
        if (pass == 1) {
            r.ok &= weft_cloth_restore(ctx, c, snap, sz) == WEFT_OK;
            r.restored_same = ag_same_snapshot(ctx, c, snap, sz);
            f0 = at;
        }
        for (int f = f0; f < end && r.ok; ++f) {
            weft_frame_stats fs;
            if (feed) r.ok &= feed(ctx, c, f, user) == WEFT_OK;
            if (pass == 0 && f == at) r.ok &= weft_cloth_save(ctx, c, snap, sz) == WEFT_OK;
            r.ok &= frame(ctx, c, f, &fs, user) == WEFT_OK;
            if (pass == 0 && f == at - 1) r.before = fs;
        }
        r.ok &= weft_cloth_save(ctx, c, pass == 0 ? end1 : end2, sz) == WEFT_OK;
    }
    r.same = r.ok && memcmp(end1, end2, sz) == 0;
    free(snap);
    free(end1);
    free(end2);
    return r;
}

#endif
