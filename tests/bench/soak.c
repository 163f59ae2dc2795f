/* soak: one process, one context, the frame loop for a long time, as a host would run it.
 *
 *   soak [--frames N] [--seed S] [--max-cloths C] [--snapshot-every K] [--windows W] [--check]
 *        [--csv FILE]
 *
 * Several cloths (grids of 6..16 vertices a side, two pinned corners bound to a moving "bone",
 * a sphere collider, a random solver and stiffness) are created and destroyed over time; every
 * frame steps every live cloth with valid host inputs (object, bone and collider transforms that
 * move smoothly, wind changes, now and then a teleport or a reset) and, in about 5 % of frames,
 * one invalid call (dt 0 or NaN, a NaN or non-rigid transform, an unknown flag, a stale handle, a
 * damaged snapshot, a short output buffer) that must be refused with its status and change
 * nothing (a snapshot before and after must be equal). Every K frames a live cloth is saved,
 * stepped 3 frames, restored and stepped the same 3 frames again: the positions must be
 * bit-identical. The process's resident memory (/proc/self/statm) and the bytes Weft holds through
 * the context's allocator are sampled; a table per window of frames shows ms per frame, ms per
 * cloth step, RSS and Weft's live bytes, so growth or drift after warm-up is visible.
 *
 * A benchmark program (it prints tables). With --check (what ctest's soak_short runs) it also
 * fails (exit 1) on a broken guarantee: a snapshot that does not continue bit-exactly, an invalid
 * call accepted or changing the cloth, a valid call failing with anything but STEP_FAILED, an
 * allocation inside weft_cloth_step (weft.h: steps allocate nothing), bytes Weft holds with no
 * cloth after the run differing from before it, or any byte held after weft_context_destroy.
 * Nothing about time or RSS is checked (RSS depends on malloc and sanitizers: it is reported). */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>
#include "weft/weft.h"

#define MAX_CLOTHS 8
#define MAX_SIDE 16
#define CHECK_FRAMES 3

/* ---- a byte-counting allocator (the context's: every byte Weft holds) --------------------------- */

typedef struct counter {
    long long live, peak, allocs;
} counter;

static void* count_alloc(size_t size, void* user) {
    counter* c = user;
    unsigned char* p = malloc(size + 16);
    if (!p) return NULL;
    memcpy(p, &size, sizeof size);
    c->live += (long long)size;
    if (c->live > c->peak) c->peak = c->live;
    ++c->allocs;
    return p + 16;
}

static void count_free(void* ptr, void* user) {
    if (!ptr) return;
    counter* c = user;
    unsigned char* p = (unsigned char*)ptr - 16;
    size_t size;
    memcpy(&size, p, sizeof size);
    c->live -= (long long)size;
    free(p);
}

/* ---- small helpers ---------------------------------------------------------------------------------- */

static uint64_t rng_state;
static uint64_t rnd(void) {   /* xorshift64* */
    rng_state ^= rng_state >> 12;
    rng_state ^= rng_state << 25;
    rng_state ^= rng_state >> 27;
    return rng_state * 0x2545F4914F6CDD1Dull;
}
static double rnd01(void) { return (double)(rnd() >> 11) / 9007199254740992.0; }
static int rnd_int(int n) { return (int)(rnd() % (uint64_t)n); }

static double now_ms(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec * 1e3 + ts.tv_nsec * 1e-6;
}

static double rss_mb(void) {
    FILE* f = fopen("/proc/self/statm", "r");
    if (!f) return 0.0;
    long pages = 0, resident = 0;
    int ok = fscanf(f, "%ld %ld", &pages, &resident) == 2;
    fclose(f);
    return ok ? resident * (double)sysconf(_SC_PAGESIZE) / (1024.0 * 1024.0) : 0.0;
}

/* rigid transform: rotation by angle about Y, then translation */
static void xform(float m[16], double angle, double tx, double ty, double tz) {
    memset(m, 0, 16 * sizeof(float));
    double c = cos(angle), s = sin(angle);
    m[0] = (float)c;
    m[2] = (float)-s;
    m[5] = 1.0f;
    m[8] = (float)s;
    m[10] = (float)c;
    m[12] = (float)tx;
    m[13] = (float)ty;
    m[14] = (float)tz;
    m[15] = 1.0f;
}

/* ---- cloths ------------------------------------------------------------------------------------------- */

typedef struct slot {
    int live;
    weft_cloth cloth;
    weft_cloth stale;       /* a handle of a cloth destroyed earlier in this slot (or null) */
    int n_vertices;
    size_t snap_size;
    double phase;           /* each cloth's motion differs */
    int64_t frames;         /* stepped since creation */
    double jump;            /* accumulated teleports (m along X) */
} slot;

typedef struct soak {
    weft_context* ctx;
    counter mem;
    slot s[MAX_CLOTHS];
    slot sentinel;
    int n_live;
    float pos[MAX_SIDE * MAX_SIDE * 3], pos2[MAX_SIDE * MAX_SIDE * 3];
    unsigned char *snap_a, *snap_b, *snap_c;   /* scratch, the largest snapshot size */
    size_t snap_cap;
    long long steps, step_failed, unexpected, invalid_calls, invalid_failures, snapshot_checks,
        snapshot_failures, created, destroyed, create_failures;
} soak;

/* fixed: the sentinel, a 12 x 12 PCG cloth held at exactly 50 iterations a solve (tolerance 0
 * is refused; 1e-30 is never reached), alive the whole run: its ms per step is the drift figure,
 * free of the pool's changing mix of sizes and solvers. */
static int create_cloth_as(soak* k, slot* sl, int fixed) {
    int n = fixed ? 12 : 6 + rnd_int(MAX_SIDE - 6 + 1);
    static float pos[MAX_SIDE * MAX_SIDE * 3];
    static int sizes[(MAX_SIDE - 1) * (MAX_SIDE - 1)], idx[4 * (MAX_SIDE - 1) * (MAX_SIDE - 1)];
    double size = fixed ? 1.0 : 0.5 + rnd01();
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            float* p = &pos[3 * (j * n + i)];
            p[0] = (float)(size * i / (n - 1) - 0.5 * size);
            p[1] = 0.0f;
            p[2] = (float)(size * j / (n - 1) - 0.5 * size);
        }
    int f = 0;
    for (int j = 0; j + 1 < n; ++j)
        for (int i = 0; i + 1 < n; ++i, ++f) {
            sizes[f] = 4;
            int* q = &idx[4 * f];
            q[0] = j * n + i;
            q[1] = (j + 1) * n + i;
            q[2] = (j + 1) * n + i + 1;
            q[3] = j * n + i + 1;
        }
    weft_cloth_def def = weft_default_cloth_def();
    def.mesh.positions = pos;
    def.mesh.n_vertices = n * n;
    def.mesh.face_sizes = sizes;
    def.mesh.n_faces = f;
    def.mesh.indices = idx;
    static const double k_stretch[3] = {500.0, 5000.0, 20000.0};
    static const weft_solver solvers[4] = {WEFT_SOLVER_PCG, WEFT_SOLVER_PCG, WEFT_SOLVER_JACOBI, WEFT_SOLVER_CHEBYSHEV};
    if (fixed) {
        def.solver = WEFT_SOLVER_PCG;
        def.tolerance = 1e-30;
        def.max_iterations = 50;
        def.sleep_speed = 0.0;
    } else {
        def.material.stiffness[0] = k_stretch[rnd_int(3)];
        def.solver = solvers[rnd_int(4)];
        def.max_iterations = 100;
        def.substeps = 1 + rnd_int(2);
        def.strain_limit = rnd_int(3) == 0 ? 0.1 : 0.0;
    }
    int corners[2] = {n * (n - 1), n * n - 1};
    weft_attachment_def at = weft_default_attachment_def();
    at.vertices = corners;
    at.n_vertices = 2;
    def.attachments = &at;
    def.n_attachments = 1;
    weft_collider_def col = weft_default_collider_def();
    col.type = WEFT_COLLIDER_SPHERE;
    col.radius = 0.2;
    col.transform[13] = -0.5f;
    def.colliders = &col;
    def.n_colliders = 1;
    weft_cloth c;
    if (weft_cloth_create(k->ctx, &def, &c) != WEFT_OK) {
        fprintf(stderr, "soak: create failed: %s\n", weft_context_last_error(k->ctx));
        ++k->create_failures;
        return 0;
    }
    weft_cloth_info info;
    weft_cloth_get_info(k->ctx, c, &info);
    sl->live = 1;
    sl->cloth = c;
    sl->n_vertices = info.n_vertices;
    sl->snap_size = info.snapshot_size;
    sl->phase = rnd01() * 6.28;
    sl->frames = 0;
    sl->jump = 0.0;
    if (info.snapshot_size > k->snap_cap) {   /* grows to the largest grid once, then stays */
        k->snap_cap = info.snapshot_size;
        free(k->snap_a);
        free(k->snap_b);
        free(k->snap_c);
        k->snap_a = malloc(k->snap_cap);
        k->snap_b = malloc(k->snap_cap);
        k->snap_c = malloc(k->snap_cap);
        if (!k->snap_a || !k->snap_b || !k->snap_c) abort();
    }
    ++k->n_live;
    ++k->created;
    return 1;
}

static int create_cloth(soak* k, slot* sl) { return create_cloth_as(k, sl, 0); }

static void destroy_cloth(soak* k, slot* sl) {
    if (weft_cloth_destroy(k->ctx, sl->cloth) != WEFT_OK) ++k->unexpected;
    sl->stale = sl->cloth;
    sl->live = 0;
    --k->n_live;
    ++k->destroyed;
}

/* The valid inputs of frame t for a cloth: a slow sway of the object, the bone following it with a
 * bob, the sphere circling below, the wind changing now and then. */
typedef struct frame_in {
    float object[16], bone[16], sphere[16];
    double wind[3];
    weft_frame fr;
} frame_in;

static void frame_inputs(const slot* sl, int64_t t, frame_in* in, uint32_t flags) {
    double time = t / 60.0, a = 0.4 * sin(0.5 * time + sl->phase);
    xform(in->object, a, sl->jump + 0.3 * sin(0.7 * time), 0.0, 0.0);
    xform(in->bone, a, sl->jump + 0.3 * sin(0.7 * time), 0.05 * sin(2.0 * time), 0.0);
    xform(in->sphere, 0.0, sl->jump + 0.3 * cos(time), -0.4, 0.3 * sin(time));
    in->wind[0] = 2.0 * sin(0.05 * time);
    in->wind[1] = 0.0;
    in->wind[2] = 1.0;
    in->fr = weft_default_frame();
    in->fr.dt = 1.0 / 60.0;
    in->fr.object_transform = in->object;
    in->fr.attachment_transforms = in->bone;
    in->fr.collider_transforms = in->sphere;
    in->fr.wind = (t % 120) == 0 ? in->wind : NULL;
    in->fr.flags = flags;
}

static int step(soak* k, slot* sl, uint32_t flags) {
    frame_in in;
    frame_inputs(sl, sl->frames, &in, flags);
    weft_frame_stats stats;
    memset(&stats, 0, sizeof stats);
    weft_status st = weft_cloth_step(k->ctx, sl->cloth, &in.fr, &stats);
    ++k->steps;
    if (st == WEFT_ERROR_STEP_FAILED) ++k->step_failed;   /* a legitimate answer: the cloth is as before */
    else if (st != WEFT_OK) {
        ++k->unexpected;
        fprintf(stderr, "soak: step: %s\n", weft_context_last_error(k->ctx));
    }
    ++sl->frames;
    return stats.iterations;
}

/* Save, step 3 frames, restore, step the same 3 frames: the positions must be bit-identical. */
static void snapshot_check(soak* k, slot* sl) {
    ++k->snapshot_checks;
    int count = 0;
    int64_t start = sl->frames;
    if (weft_cloth_save(k->ctx, sl->cloth, k->snap_a, sl->snap_size) != WEFT_OK) { ++k->snapshot_failures; return; }
    for (int i = 0; i < CHECK_FRAMES; ++i) step(k, sl, 0);
    weft_cloth_get_vertices(k->ctx, sl->cloth, WEFT_SPACE_WORLD, k->pos, NULL, sl->n_vertices, &count);
    if (weft_cloth_save(k->ctx, sl->cloth, k->snap_b, sl->snap_size) != WEFT_OK ||
        weft_cloth_restore(k->ctx, sl->cloth, k->snap_a, sl->snap_size) != WEFT_OK) {
        ++k->snapshot_failures;
        return;
    }
    sl->frames = start;
    for (int i = 0; i < CHECK_FRAMES; ++i) step(k, sl, 0);
    weft_cloth_get_vertices(k->ctx, sl->cloth, WEFT_SPACE_WORLD, k->pos2, NULL, sl->n_vertices, &count);
    weft_cloth_save(k->ctx, sl->cloth, k->snap_c, sl->snap_size);
    if (memcmp(k->pos, k->pos2, 3 * sizeof(float) * (size_t)sl->n_vertices) != 0 ||
        memcmp(k->snap_b, k->snap_c, sl->snap_size) != 0) {
        ++k->snapshot_failures;
        fprintf(stderr, "soak: a restored snapshot did not continue bit-exactly (frame %lld)\n", (long long)start);
    }
}

/* One invalid call of a random kind on a live cloth: refused with its status, nothing changed. */
static void invalid_call(soak* k, slot* sl) {
    ++k->invalid_calls;
    weft_cloth_save(k->ctx, sl->cloth, k->snap_a, sl->snap_size);
    frame_in in;
    frame_inputs(sl, sl->frames, &in, 0);
    weft_status want = WEFT_OK, got;
    int kind = rnd_int(8);
    switch (kind) {
    case 0: in.fr.dt = 0.0; want = WEFT_ERROR_INVALID_ARGUMENT; break;
    case 1: in.fr.dt = NAN; want = WEFT_ERROR_NONFINITE; break;
    case 2: in.object[13] = NAN; want = WEFT_ERROR_NONFINITE; break;
    case 3: in.bone[0] *= 2.0f; want = WEFT_ERROR_INVALID_ARGUMENT; break;   /* not rigid */
    case 4: in.fr.flags = 1u << 7; want = WEFT_ERROR_INVALID_ARGUMENT; break;
    default: break;
    }
    if (kind <= 4) {
        got = weft_cloth_step(k->ctx, sl->cloth, &in.fr, NULL);
    } else if (kind == 5) {
        want = WEFT_ERROR_INVALID_HANDLE;
        weft_frame_stats st;
        in.fr.dt = 1.0 / 60.0;
        got = sl->stale.id ? weft_cloth_step(k->ctx, sl->stale, &in.fr, &st) : WEFT_ERROR_INVALID_HANDLE;
    } else if (kind == 6) {
        want = WEFT_ERROR_INVALID_ARGUMENT;   /* damaged: one byte of the positions flipped */
        memcpy(k->snap_b, k->snap_a, sl->snap_size);
        k->snap_b[64 + rnd_int(24)] ^= 0x40;
        got = weft_cloth_restore(k->ctx, sl->cloth, k->snap_b, sl->snap_size);
    } else {
        want = WEFT_ERROR_OUT_OF_RANGE;
        int count;
        got = weft_cloth_get_vertices(k->ctx, sl->cloth, WEFT_SPACE_WORLD, k->pos, NULL, sl->n_vertices - 1, &count);
    }
    weft_cloth_save(k->ctx, sl->cloth, k->snap_c, sl->snap_size);
    if (got != want || memcmp(k->snap_a, k->snap_c, sl->snap_size) != 0) {
        ++k->invalid_failures;
        fprintf(stderr, "soak: invalid call %d: status %d (wanted %d)%s\n", kind, (int)got, (int)want,
                got == want ? ", but the cloth changed" : "");
    }
}

static int parse_args(int argc, char** argv, long long* frames, uint64_t* seed, int* max_cloths, int* every,
                      int* windows, int* check, const char** csv) {
    for (int i = 1; i < argc; ++i) {
        const char* a = argv[i];
        const char* v = i + 1 < argc ? argv[i + 1] : NULL;
        if (!strcmp(a, "--check")) { *check = 1; continue; }
        if (!v) return 0;
        if (!strcmp(a, "--frames")) *frames = atoll(v);
        else if (!strcmp(a, "--seed")) *seed = strtoull(v, NULL, 10);
        else if (!strcmp(a, "--max-cloths")) *max_cloths = atoi(v);
        else if (!strcmp(a, "--snapshot-every")) *every = atoi(v);
        else if (!strcmp(a, "--windows")) *windows = atoi(v);
        else if (!strcmp(a, "--csv")) *csv = v;
        else return 0;
        ++i;
    }
    return *frames > 0 && *max_cloths >= 1 && *max_cloths <= MAX_CLOTHS && *every > 0 && *windows >= 2;
}

int main(int argc, char** argv) {
    long long frames = 100000;
    uint64_t seed = 1;
    int max_cloths = 4, every = 500, windows = 10, check = 0;
    const char* csv_path = NULL;
    if (!parse_args(argc, argv, &frames, &seed, &max_cloths, &every, &windows, &check, &csv_path)) {
        fprintf(stderr, "usage: soak [--frames N] [--seed S] [--max-cloths 1..%d] [--snapshot-every K] "
                        "[--windows W>=2] [--check] [--csv FILE]\n", MAX_CLOTHS);
        return 2;
    }
    rng_state = seed * 0x9E3779B97F4A7C15ull + 1;
    static soak k;
    weft_context_def cd = weft_default_context_def();
    cd.backend = WEFT_BACKEND_CPU;
    cd.threads = 1;
    cd.log_level = WEFT_LOG_ERROR;
    cd.allocator.alloc = count_alloc;
    cd.allocator.free = count_free;
    cd.allocator.user = &k.mem;
    if (weft_context_create(WEFT_ABI, &cd, &k.ctx) != WEFT_OK) {
        fprintf(stderr, "soak: no context\n");
        return 1;
    }
    FILE* csv = csv_path ? fopen(csv_path, "w") : NULL;
    if (csv)
        fprintf(csv, "frame,pool_cloths,pool_ms_per_frame,pool_ms_per_cloth_step,sentinel_ms_per_step,"
                     "sentinel_iterations,rss_mb,weft_live_kb\n");

    long long window = frames / windows > 0 ? frames / windows : 1;
    long long warm = window;   /* the first window is the warm-up */
    double t0 = now_ms(), win_ms = 0.0, rss_warm = 0.0, weft_warm_peak = 0.0, first_ms_step = 0.0, last_ms_step = 0.0;
    long long win_steps = 0, win_live = 0;
    printf("soak: %lld frames, seed %llu, up to %d cloths, snapshot check every %d frames\n\n", frames,
           (unsigned long long)seed, max_cloths, every);
    printf("| frames | pool cloths (mean) | pool ms/frame | pool ms/cloth step | sentinel ms/step | sentinel "
           "iterations/step | RSS MB | Weft live KB |\n");
    printf("|---|---|---|---|---|---|---|---|\n");
    /* Weft's bytes with no cloth: the context and its handle table (at most MAX_CLOTHS slots) */
    for (int i = 0; i < max_cloths; ++i) create_cloth(&k, &k.s[i]);
    for (int i = 0; i < max_cloths; ++i) destroy_cloth(&k, &k.s[i]);
    long long weft_base = k.mem.live;
    k.created = k.destroyed = 0;
    for (int i = 0; i < max_cloths; ++i) k.s[i].stale.id = 0;
    for (int i = 0; i < max_cloths / 2 + 1; ++i) create_cloth(&k, &k.s[i]);
    long long step_allocs = 0, win_sentinel_iters = 0;
    double win_sentinel_ms = 0.0, first_sentinel = 0.0, last_sentinel = 0.0;
    if (!create_cloth_as(&k, &k.sentinel, 1)) return 1;
    --k.n_live;   /* the pool's count: the sentinel is apart */
    --k.created;
    for (long long f = 1; f <= frames; ++f) {
        /* now and then a cloth comes or goes (one live at least) */
        if (rnd_int(200) == 0) {
            slot* sl = &k.s[rnd_int(max_cloths)];
            if (!sl->live) create_cloth(&k, sl);
            else if (k.n_live > 1) destroy_cloth(&k, sl);   /* the pool keeps one cloth at least */
        }
        double a = now_ms();
        long long steps_before = k.steps, allocs_before = k.mem.allocs;
        for (int i = 0; i < max_cloths; ++i) {
            slot* sl = &k.s[i];
            if (!sl->live) continue;
            uint32_t flags = 0;
            int r = rnd_int(1000);
            if (r == 0) {
                flags = WEFT_FRAME_TELEPORT;
                sl->jump += 1.0;
            } else if (r == 1) {
                flags = WEFT_FRAME_RESET;
            }
            step(&k, sl, flags);
        }
        win_ms += now_ms() - a;
        step_allocs += k.mem.allocs - allocs_before;
        double b = now_ms();
        allocs_before = k.mem.allocs;
        win_sentinel_iters += step(&k, &k.sentinel, 0);
        win_sentinel_ms += now_ms() - b;
        step_allocs += k.mem.allocs - allocs_before;
        win_steps += k.steps - steps_before;
        win_live += k.n_live;
        if (rnd_int(20) == 0) {   /* ~5 % of frames: one invalid call */
            slot* sl = &k.s[rnd_int(max_cloths)];
            if (sl->live) invalid_call(&k, sl);
        }
        if (f % every == 0) {   /* the pool's cloths in turn; the sentinel when the pool is empty */
            slot* sl = &k.sentinel;
            for (int i = 0; i < max_cloths; ++i)
                if (k.s[(f / every + i) % max_cloths].live) {
                    sl = &k.s[(f / every + i) % max_cloths];
                    break;
                }
            snapshot_check(&k, sl);
        }
        if (f % window == 0 || f == frames) {
            long long n = f % window == 0 ? window : f % window;
            double rss = rss_mb(), ms_step = win_steps ? win_ms / win_steps : 0.0;
            double sent = win_sentinel_ms / n;
            printf("| %lld | %.2f | %.3f | %.3f | %.3f | %.1f | %.1f | %.1f |\n", f, (double)win_live / n, win_ms / n,
                   ms_step, sent, (double)win_sentinel_iters / n, rss, k.mem.live / 1024.0);
            if (csv)
                fprintf(csv, "%lld,%.3f,%.4f,%.4f,%.4f,%.2f,%.2f,%.1f\n", f, (double)win_live / n, win_ms / n, ms_step,
                        sent, (double)win_sentinel_iters / n, rss, k.mem.live / 1024.0);
            fflush(stdout);
            if (f == warm) {
                rss_warm = rss;
                weft_warm_peak = (double)k.mem.peak;
            }
            if (f == 2 * warm) {
                first_ms_step = ms_step;
                first_sentinel = sent;
            }
            last_sentinel = sent;
            win_sentinel_ms = 0.0;
            win_sentinel_iters = 0;
            last_ms_step = ms_step;
            win_ms = 0.0;
            win_steps = win_live = 0;
        }
    }
    double rss_end = rss_mb(), total_s = (now_ms() - t0) / 1e3;
    long long weft_end_live = k.mem.live, weft_peak = k.mem.peak;
    for (int i = 0; i < max_cloths; ++i)
        if (k.s[i].live) destroy_cloth(&k, &k.s[i]);
    if (weft_cloth_destroy(k.ctx, k.sentinel.cloth) != WEFT_OK) ++k.unexpected;
    long long weft_no_cloths = k.mem.live;
    weft_context_destroy(k.ctx);
    long long weft_after_destroy = k.mem.live;
    free(k.snap_a);
    free(k.snap_b);
    free(k.snap_c);
    if (csv) fclose(csv);

    printf("\n| figure | value |\n|---|---|\n");
    printf("| frames, wall time | %lld, %.1f s |\n", frames, total_s);
    printf("| cloth steps (STEP_FAILED among them) | %lld (%lld) |\n", k.steps, k.step_failed);
    printf("| cloths created / destroyed / failed to create | %lld / %lld / %lld |\n", k.created, k.destroyed,
           k.create_failures);
    printf("| invalid calls refused as documented | %lld of %lld |\n", k.invalid_calls - k.invalid_failures,
           k.invalid_calls);
    printf("| snapshot round trips bit-exact | %lld of %lld |\n", k.snapshot_checks - k.snapshot_failures,
           k.snapshot_checks);
    printf("| unexpected statuses | %lld |\n", k.unexpected);
    printf("| RSS after warm-up (frame %lld) / at the end | %.1f MB / %.1f MB (%+.1f MB) |\n", warm, rss_warm, rss_end,
           rss_end - rss_warm);
    printf("| Weft's live bytes: warm-up peak / peak / end | %.0f / %lld / %lld |\n", weft_warm_peak, weft_peak,
           weft_end_live);
    printf("| Weft's live bytes with no cloth: before the run / after it / after weft_context_destroy | %lld / %lld / %lld |\n",
           weft_base, weft_no_cloths, weft_after_destroy);
    printf("| allocations inside weft_cloth_step | %lld |\n", step_allocs);
    printf("| sentinel ms per step: first window after the warm-up one -> last | %.3f -> %.3f (%+.1f %%) |\n",
           first_sentinel, last_sentinel, first_sentinel > 0 ? 100.0 * (last_sentinel / first_sentinel - 1.0) : 0.0);
    printf("| pool ms per cloth step (mix of sizes and solvers): same windows | %.3f -> %.3f |\n", first_ms_step,
           last_ms_step);
    if (!check) return 0;
    int bad = 0;
    if (k.snapshot_failures) { fprintf(stderr, "soak: FAILED: %lld snapshot round trips\n", k.snapshot_failures); bad = 1; }
    if (k.invalid_failures) { fprintf(stderr, "soak: FAILED: %lld invalid calls\n", k.invalid_failures); bad = 1; }
    if (k.unexpected || k.create_failures) { fprintf(stderr, "soak: FAILED: unexpected statuses\n"); bad = 1; }
    if (weft_after_destroy != 0) { fprintf(stderr, "soak: FAILED: %lld bytes held after destroy\n", weft_after_destroy); bad = 1; }
    if (weft_no_cloths != weft_base) {
        fprintf(stderr, "soak: FAILED: %lld bytes with no cloth after the run, %lld before\n", weft_no_cloths, weft_base);
        bad = 1;
    }
    if (step_allocs != 0) { fprintf(stderr, "soak: FAILED: %lld allocations inside steps\n", step_allocs); bad = 1; }
    return bad;
}
