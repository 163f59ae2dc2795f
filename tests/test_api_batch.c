/* weft_context_step (many cloths in one call) against weft_cloth_step, the independent reference:
 *  - a batch of different cloths (sizes, solvers, a sphere they land on, a pin's jerk, one that
 *    falls asleep, one teleported whose substeps roll back) gives each cloth the state it has when
 *    stepped alone with weft_cloth_step: the whole snapshot bit for bit, and the same statistics,
 *    on 1 and 2 threads (2: the cloths at once, one thread each, against the single calls' two)
 *    and with 2 cloths on 3 threads (one after the other, each on all three); on the GPU backend
 *    where there is one (llvmpipe) to float precision; the batch allocates nothing and the logger
 *    is called from the calling thread only;
 *  - bad entries (the null handle, a cloth of another context, a cloth named twice, NaN in a
 *    frame) are reported at their index (statuses, the last error, the logger) and left as they
 *    were, while the others step as they would alone; refused calls (n < 0, NULL arrays) change
 *    nothing;
 *  - cloths created and destroyed between batches: a stale handle is reported, a new cloth steps
 *    as it would alone. */
#include <pthread.h>
#include <stdio.h>
#include <string.h>
#include "api_grid.h"
#include "check.h"

#define FRAMES 16
#define DT (1.0 / 60.0)
#define MAX_CLOTHS 8

/* One cloth of the batch and what drives it. */
typedef struct spec {
    int n;              /* grid side */
    weft_solver solver;
    int sphere;         /* a sphere below it, moving up */
    int yank;           /* its pin jumps 0.8 m at frame 5 (no TELEPORT): a jerk */
    int sleepy;         /* sleep_speed 0.05: falls asleep */
    int teleport;       /* TELEPORT at frame 10 */
    int wind;
    int cpu_only;       /* the direct solver */
} spec;

static const spec SPECS[] = {
    {8, WEFT_SOLVER_PCG, 0, 0, 0, 0, 0, 0},
    {12, WEFT_SOLVER_JACOBI, 1, 0, 0, 0, 0, 0},
    {6, WEFT_SOLVER_DIRECT, 0, 0, 0, 0, 1, 1},
    {7, WEFT_SOLVER_PCG, 0, 1, 0, 0, 0, 0},
    {5, WEFT_SOLVER_PCG, 0, 0, 1, 0, 0, 0},
    {9, WEFT_SOLVER_CHEBYSHEV, 0, 0, 0, 1, 0, 0},
};
#define N_SPECS ((int)(sizeof SPECS / sizeof SPECS[0]))

typedef struct scene {
    weft_context* ctx;
    ag_alloc_counter counter;
    ag_mesh mesh[N_SPECS];
    int pins[N_SPECS][2];
    weft_attachment_def att[N_SPECS];
    weft_collider_def col[N_SPECS];
    weft_cloth cloth[N_SPECS];
    int used[N_SPECS];  /* specs made on this backend */
    int n_used;
    /* each frame's transforms, per cloth */
    float object[N_SPECS][16], pin[N_SPECS][16], sphere[N_SPECS][16];
    double wind[N_SPECS][3];
} scene;

/* the logger: counts messages by level and those from another thread than the test's */
static pthread_t main_thread;
static int foreign_log_calls;
static ag_log logged;
static void log_fn(weft_log_level level, const char* message, void* user) {
    if (!pthread_equal(pthread_self(), main_thread)) ++foreign_log_calls;
    ag_log_fn(level, message, user);
}

/* A context and the first `specs` cloths of SPECS (those the backend runs). */
static int scene_make(scene* s, weft_backend backend, int threads, int specs) {
    memset(s, 0, sizeof *s);
    weft_context_def cd = weft_default_context_def();
    cd.backend = backend;
    cd.threads = threads;
    cd.allocator.alloc = ag_count_alloc;
    cd.allocator.free = ag_count_free;
    cd.allocator.user = &s->counter;
    cd.log = log_fn;
    cd.log_user = &logged;
    cd.log_level = WEFT_LOG_DEBUG;
    if (weft_context_create(WEFT_ABI, &cd, &s->ctx) != WEFT_OK) return 0;
    for (int k = 0; k < specs; ++k) {
        const spec* p = &SPECS[k];
        if (p->cpu_only && backend != WEFT_BACKEND_CPU) continue;
        ag_grid(&s->mesh[k], p->n, 0.5, 1.0, !p->sphere, 0);
        weft_cloth_def def = weft_default_cloth_def();
        def.mesh = ag_desc(&s->mesh[k]);
        def.solver = p->solver;
        def.sleep_speed = p->sleepy ? 0.05 : 0.0;
        def.sleep_time = 0.1;
        if (!p->sphere) {   /* hanging from its top corners */
            s->pins[k][0] = p->n * (p->n - 1);
            s->pins[k][1] = p->n * p->n - 1;
            s->att[k] = weft_default_attachment_def();
            s->att[k].vertices = s->pins[k];
            s->att[k].n_vertices = 2;
            def.attachments = &s->att[k];
            def.n_attachments = 1;
        } else {
            s->col[k] = weft_default_collider_def();
            s->col[k].radius = 0.2;
            ag_transform(s->col[k].transform, 1, 0, 0, 0.0, 0.0, 0.7, 0.0);
            def.colliders = &s->col[k];
            def.n_colliders = 1;
        }
        CHECK_EQ_INT(weft_cloth_create(s->ctx, &def, &s->cloth[k]), WEFT_OK);
        s->used[s->n_used++] = k;
    }
    return 1;
}

static void scene_free(scene* s) {
    weft_context_destroy(s->ctx);
    CHECK_EQ_INT(s->counter.live, 0);
    for (int k = 0; k < N_SPECS; ++k) ag_free(&s->mesh[k]);
}

/* Cloth k's frame f (its transforms are kept in s). */
static weft_frame frame_of(scene* s, int k, int f) {
    const spec* p = &SPECS[k];
    weft_frame fr = weft_default_frame();
    fr.dt = DT;
    ag_transform(s->object[k], 0, 1, 0, 0.0, p->teleport && f >= 10 ? 2.0 : 0.0, 0.0, 0.0);
    fr.object_transform = s->object[k];
    if (p->teleport && f == 10) fr.flags = WEFT_FRAME_TELEPORT;
    if (!p->sphere) {
        double shift = p->teleport && f >= 10 ? 2.0 : 0.0, swing = p->sleepy ? 0.0 : 0.05 * sin(0.3 * f);
        double yank = p->yank && f >= 5 ? 0.8 : 0.0;
        ag_transform(s->pin[k], 0, 1, 0, 0.0, shift + swing + yank, 0.0, 0.0);
        fr.attachment_transforms = s->pin[k];
    } else {
        ag_transform(s->sphere[k], 1, 0, 0, 0.0, 0.0, 0.7 + 0.004 * f, 0.0);
        fr.collider_transforms = s->sphere[k];
    }
    if (p->wind) {
        s->wind[k][0] = 2.0 * sin(0.2 * f);
        s->wind[k][1] = 0.0;
        s->wind[k][2] = 1.0;
        fr.wind = s->wind[k];
    }
    return fr;
}

static size_t snapshot_size(scene* s, weft_cloth c) {
    weft_cloth_info info;
    CHECK_EQ_INT(weft_cloth_get_info(s->ctx, c, &info), WEFT_OK);
    return info.snapshot_size;
}

/* Snapshots of every used cloth after each frame: (FRAMES x n_used) buffers of `size` bytes. */
typedef struct trace {
    size_t size[N_SPECS];
    unsigned char* snap[FRAMES][N_SPECS];
    weft_frame_stats stats[FRAMES][N_SPECS];
    float* positions[N_SPECS];   /* world, after the last frame */
} trace;

static void trace_record(scene* s, trace* t, int f) {
    for (int u = 0; u < s->n_used; ++u) {
        int k = s->used[u];
        t->size[k] = snapshot_size(s, s->cloth[k]);
        t->snap[f][k] = malloc(t->size[k]);
        CHECK_EQ_INT(weft_cloth_save(s->ctx, s->cloth[k], t->snap[f][k], t->size[k]), WEFT_OK);
        if (f == FRAMES - 1) {
            int count = 0;
            t->positions[k] = malloc(sizeof(float) * 3 * (size_t)s->mesh[k].nv);
            CHECK_EQ_INT(weft_cloth_get_vertices(s->ctx, s->cloth[k], WEFT_SPACE_WORLD, t->positions[k], NULL,
                                                 s->mesh[k].nv, &count),
                         WEFT_OK);
        }
    }
}

static void trace_free(trace* t) {
    for (int f = 0; f < FRAMES; ++f)
        for (int k = 0; k < N_SPECS; ++k) free(t->snap[f][k]);
    for (int k = 0; k < N_SPECS; ++k) free(t->positions[k]);
}

/* Every cloth alone (weft_cloth_step), frame by frame. */
static void run_alone(scene* s, trace* t) {
    for (int f = 0; f < FRAMES; ++f) {
        for (int u = 0; u < s->n_used; ++u) {
            int k = s->used[u];
            weft_frame fr = frame_of(s, k, f);
            CHECK_EQ_INT(weft_cloth_step(s->ctx, s->cloth[k], &fr, &t->stats[f][k]), WEFT_OK);
        }
        trace_record(s, t, f);
    }
}

/* The same in one weft_context_step per frame; no allocation once the first batch ran. */
static void run_batch(scene* s, trace* t) {
    for (int f = 0; f < FRAMES; ++f) {
        weft_cloth cloths[N_SPECS];
        weft_frame frames[N_SPECS];
        weft_frame_stats stats[N_SPECS];
        weft_status statuses[N_SPECS];
        for (int u = 0; u < s->n_used; ++u) {
            cloths[u] = s->cloth[s->used[u]];
            frames[u] = frame_of(s, s->used[u], f);
        }
        long allocs = s->counter.allocs;
        CHECK_EQ_INT(weft_context_step(s->ctx, s->n_used, cloths, frames, stats, statuses), WEFT_OK);
        if (weft_context_backend(s->ctx) == WEFT_BACKEND_CPU) CHECK_EQ_INT(s->counter.allocs, allocs);
        for (int u = 0; u < s->n_used; ++u) {
            CHECK_EQ_INT(statuses[u], WEFT_OK);
            t->stats[f][s->used[u]] = stats[u];
        }
        trace_record(s, t, f);
    }
}

/* The two traces: bit-identical snapshots (exact) or positions within tol (float precision). */
static void compare(const scene* s, const trace* a, const trace* b, int exact, const char* what) {
    int seen_rollback = 0, seen_asleep = 0, seen_contact = 0;
    for (int f = 0; f < FRAMES; ++f)
        for (int u = 0; u < s->n_used; ++u) {
            int k = s->used[u];
            const weft_frame_stats *x = &a->stats[f][k], *y = &b->stats[f][k];
            seen_rollback |= x->rollbacks > 0;
            seen_asleep |= x->asleep;
            seen_contact |= x->contacts > 0;
            CHECK_EQ_INT(y->frame, x->frame);
            CHECK_EQ_INT(y->asleep, x->asleep);
            if (exact) {
                CHECK_EQ_INT(y->iterations, x->iterations);
                CHECK_EQ_INT(y->rollbacks, x->rollbacks);
                CHECK_EQ_INT(y->substeps, x->substeps);
                CHECK(y->residual == x->residual);
                CHECK(a->size[k] == b->size[k]);
                int same = memcmp(a->snap[f][k], b->snap[f][k], a->size[k]) == 0;
                if (!same) fprintf(stderr, "  %s: cloth %d differs from its single steps at frame %d\n", what, k, f);
                CHECK(same);
            }
        }
    for (int u = 0; u < s->n_used; ++u) {
        int k = s->used[u];
        double worst = 0.0, scale = 1.0;
        for (int i = 0; i < 3 * s->mesh[k].nv; ++i) {
            double d = fabs((double)a->positions[k][i] - (double)b->positions[k][i]);
            if (d > worst) worst = d;
            if (fabs((double)a->positions[k][i]) > scale) scale = fabs((double)a->positions[k][i]);
        }
        if (worst > 1e-5 * scale) fprintf(stderr, "  %s: cloth %d's positions differ by %g m\n", what, k, worst);
        CHECK(worst <= 1e-5 * scale);
    }
    /* the whole batch held what it was meant to: a rollback, a sleeping cloth, contacts */
    if (s->n_used >= N_SPECS - 1) {
        CHECK(seen_rollback);
        CHECK(seen_asleep);
        CHECK(seen_contact);
    }
}

static void same_as_alone(weft_backend backend, int threads, int specs) {
    scene a, b;
    trace ta, tb;
    memset(&ta, 0, sizeof ta);
    memset(&tb, 0, sizeof tb);
    if (!scene_make(&a, backend, threads, specs)) {
        printf("  backend %d not available here: skipped\n", (int)backend);
        weft_context_destroy(a.ctx);
        return;
    }
    CHECK(scene_make(&b, backend, threads, specs));
    run_alone(&a, &ta);
    run_batch(&b, &tb);
    char what[64];
    snprintf(what, sizeof what, "%s, %d threads, %d cloths", backend == WEFT_BACKEND_CPU ? "CPU" : "GPU", threads,
             a.n_used);
    compare(&a, &ta, &tb, backend == WEFT_BACKEND_CPU, what);
    trace_free(&ta);
    trace_free(&tb);
    scene_free(&a);
    scene_free(&b);
}

/* ---- bad entries ---------------------------------------------------------------------------- */

static int contains(const char* text, const char* part) { return strstr(text, part) != NULL; }

static void bad_entries(void) {
    scene s, other, ref;
    CHECK(scene_make(&s, WEFT_BACKEND_CPU, 2, N_SPECS));
    CHECK(scene_make(&other, WEFT_BACKEND_CPU, 2, N_SPECS));
    CHECK(scene_make(&ref, WEFT_BACKEND_CPU, 2, N_SPECS));
    /* entries: 0 good, 1 null, 2 good, 3 foreign, 4 cloth 2 again, 5 NaN dt, 6 good */
    weft_cloth null_handle = {0};
    weft_cloth cloths[7] = {s.cloth[0], null_handle, s.cloth[1], other.cloth[1], s.cloth[1], s.cloth[3], s.cloth[5]};
    weft_frame frames[7];
    int spec_of[7] = {0, 0, 1, 1, 1, 3, 5};
    for (int i = 0; i < 7; ++i) frames[i] = frame_of(&s, spec_of[i], 0);
    frames[5].dt = NAN;
    size_t size3 = snapshot_size(&s, s.cloth[3]), size_o = snapshot_size(&other, other.cloth[1]);
    unsigned char* before3 = malloc(size3), *after3 = malloc(size3);
    unsigned char* before_o = malloc(size_o), *after_o = malloc(size_o);
    CHECK_EQ_INT(weft_cloth_save(s.ctx, s.cloth[3], before3, size3), WEFT_OK);
    CHECK_EQ_INT(weft_cloth_save(other.ctx, other.cloth[1], before_o, size_o), WEFT_OK);

    /* refused as a whole: nothing changes, statuses untouched */
    weft_status statuses[7];
    weft_frame_stats stats[7];
    for (int i = 0; i < 7; ++i) statuses[i] = (weft_status)12345;
    memset(stats, 0xAB, sizeof stats);
    CHECK_EQ_INT(weft_context_step(s.ctx, -1, cloths, frames, stats, statuses), WEFT_ERROR_INVALID_ARGUMENT);
    CHECK(contains(weft_context_last_error(s.ctx), "n = -1"));
    CHECK_EQ_INT(weft_context_step(s.ctx, 7, NULL, frames, stats, statuses), WEFT_ERROR_INVALID_ARGUMENT);
    CHECK(contains(weft_context_last_error(s.ctx), "cloths is NULL"));
    CHECK_EQ_INT(weft_context_step(s.ctx, 7, cloths, NULL, stats, statuses), WEFT_ERROR_INVALID_ARGUMENT);
    CHECK(contains(weft_context_last_error(s.ctx), "frames is NULL"));
    CHECK_EQ_INT(weft_context_step(NULL, 7, cloths, frames, stats, statuses), WEFT_ERROR_INVALID_ARGUMENT);
    for (int i = 0; i < 7; ++i) CHECK_EQ_INT(statuses[i], 12345);
    CHECK_EQ_INT(weft_context_step(s.ctx, 0, NULL, NULL, NULL, NULL), WEFT_OK);
    CHECK_EQ_INT(weft_cloth_save(s.ctx, s.cloth[3], after3, size3), WEFT_OK);
    CHECK(memcmp(before3, after3, size3) == 0);

    int errors_before = logged.count[WEFT_LOG_ERROR];
    CHECK_EQ_INT(weft_context_step(s.ctx, 7, cloths, frames, stats, statuses), WEFT_ERROR_INVALID_HANDLE);
    CHECK_EQ_INT(weft_context_last_status(s.ctx), WEFT_ERROR_INVALID_HANDLE);
    const char* err = weft_context_last_error(s.ctx);
    printf("  last error: %s\n", err);
    CHECK(contains(err, "weft_context_step: cloths[1]: cloth is the null handle"));
    CHECK(contains(err, "4 of the 7 cloths failed"));
    CHECK_EQ_INT(logged.count[WEFT_LOG_ERROR] - errors_before, 4);   /* one message per bad entry */
    weft_status want[7] = {WEFT_OK, WEFT_ERROR_INVALID_HANDLE, WEFT_OK, WEFT_ERROR_INVALID_HANDLE,
                           WEFT_ERROR_INVALID_ARGUMENT, WEFT_ERROR_NONFINITE, WEFT_OK};
    for (int i = 0; i < 7; ++i) CHECK_EQ_INT(statuses[i], want[i]);
    /* the bad ones untouched: their cloths' states, their stats */
    unsigned char pattern[sizeof(weft_frame_stats)];
    memset(pattern, 0xAB, sizeof pattern);
    int bad[4] = {1, 3, 4, 5};
    for (int b = 0; b < 4; ++b) CHECK(memcmp(&stats[bad[b]], pattern, sizeof pattern) == 0);
    CHECK_EQ_INT(weft_cloth_save(s.ctx, s.cloth[3], after3, size3), WEFT_OK);
    CHECK(memcmp(before3, after3, size3) == 0);
    CHECK_EQ_INT(weft_cloth_save(other.ctx, other.cloth[1], after_o, size_o), WEFT_OK);
    CHECK(memcmp(before_o, after_o, size_o) == 0);
    /* the good ones stepped as alone */
    int good[3] = {0, 2, 6};
    for (int g = 0; g < 3; ++g) {
        int i = good[g], k = spec_of[i];
        weft_frame_stats st;
        CHECK_EQ_INT(weft_cloth_step(ref.ctx, ref.cloth[k], &frames[i], &st), WEFT_OK);
        CHECK_EQ_INT(stats[i].frame, 1);
        CHECK_EQ_INT(stats[i].iterations, st.iterations);
        size_t size = snapshot_size(&s, s.cloth[k]);
        unsigned char *x = malloc(size), *y = malloc(size);
        CHECK_EQ_INT(weft_cloth_save(s.ctx, s.cloth[k], x, size), WEFT_OK);
        CHECK_EQ_INT(weft_cloth_save(ref.ctx, ref.cloth[k], y, size), WEFT_OK);
        CHECK(memcmp(x, y, size) == 0);
        free(x);
        free(y);
    }
    /* a frame refused by its field's name, at its index */
    frames[5].dt = DT;
    frames[5].flags = 0x80;
    weft_cloth one[2] = {s.cloth[0], s.cloth[3]};
    weft_frame two[2] = {frames[0], frames[5]};
    CHECK_EQ_INT(weft_context_step(s.ctx, 2, one, two, NULL, NULL), WEFT_ERROR_INVALID_ARGUMENT);
    CHECK(contains(weft_context_last_error(s.ctx), "weft_context_step: frames[1].flags 0x80"));
    CHECK(!contains(weft_context_last_error(s.ctx), "cloths failed"));
    free(before3);
    free(after3);
    free(before_o);
    free(after_o);
    scene_free(&s);
    scene_free(&other);
    scene_free(&ref);
}

/* ---- cloths created and destroyed between batches ------------------------------------------- */

static void add_and_destroy(void) {
    scene s, ref;
    CHECK(scene_make(&s, WEFT_BACKEND_CPU, 2, N_SPECS));
    CHECK(scene_make(&ref, WEFT_BACKEND_CPU, 2, N_SPECS));
    weft_cloth cloths[N_SPECS];
    weft_frame frames[N_SPECS];
    weft_status statuses[N_SPECS];
    for (int u = 0; u < 3; ++u) {
        cloths[u] = s.cloth[u];
        frames[u] = frame_of(&s, u, 0);
    }
    CHECK_EQ_INT(weft_context_step(s.ctx, 3, cloths, frames, NULL, statuses), WEFT_OK);
    /* destroy cloth 1, make a new one like spec 4 (the slot is reused) */
    weft_cloth dead = s.cloth[1];
    CHECK_EQ_INT(weft_cloth_destroy(s.ctx, dead), WEFT_OK);
    weft_cloth_def def = weft_default_cloth_def();
    def.mesh = ag_desc(&s.mesh[4]);
    def.attachments = &s.att[4];
    def.n_attachments = 1;
    def.sleep_speed = 0.05;
    def.sleep_time = 0.1;
    weft_cloth fresh;
    CHECK_EQ_INT(weft_cloth_create(s.ctx, &def, &fresh), WEFT_OK);
    weft_cloth fresh_ref;
    CHECK_EQ_INT(weft_cloth_create(ref.ctx, &def, &fresh_ref), WEFT_OK);
    weft_cloth next[4] = {s.cloth[0], dead, fresh, s.cloth[2]};
    weft_frame next_frames[4] = {frame_of(&s, 0, 1), frame_of(&s, 1, 1), frame_of(&s, 4, 0), frame_of(&s, 2, 1)};
    CHECK_EQ_INT(weft_context_step(s.ctx, 4, next, next_frames, NULL, statuses), WEFT_ERROR_INVALID_HANDLE);
    CHECK(contains(weft_context_last_error(s.ctx), "cloths[1]: cloth handle"));
    CHECK_EQ_INT(statuses[0], WEFT_OK);
    CHECK_EQ_INT(statuses[2], WEFT_OK);
    CHECK_EQ_INT(statuses[3], WEFT_OK);
    weft_frame_stats st;
    CHECK_EQ_INT(weft_cloth_step(ref.ctx, fresh_ref, &next_frames[2], &st), WEFT_OK);
    size_t size = snapshot_size(&s, fresh);
    unsigned char *x = malloc(size), *y = malloc(size);
    CHECK_EQ_INT(weft_cloth_save(s.ctx, fresh, x, size), WEFT_OK);
    CHECK_EQ_INT(weft_cloth_save(ref.ctx, fresh_ref, y, size), WEFT_OK);
    CHECK(memcmp(x, y, size) == 0);
    free(x);
    free(y);
    /* many more cloths than before: the scratch grows with the slots, at creation */
    weft_cloth many[MAX_CLOTHS];
    weft_frame many_frames[MAX_CLOTHS];
    for (int i = 0; i < MAX_CLOTHS; ++i) {
        CHECK_EQ_INT(weft_cloth_create(s.ctx, &def, &many[i]), WEFT_OK);
        many_frames[i] = frame_of(&s, 4, 0);
    }
    long allocs = s.counter.allocs;
    CHECK_EQ_INT(weft_context_step(s.ctx, MAX_CLOTHS, many, many_frames, NULL, NULL), WEFT_OK);
    CHECK_EQ_INT(s.counter.allocs, allocs);
    scene_free(&s);
    scene_free(&ref);
}

static void cpu_1_thread(void) { same_as_alone(WEFT_BACKEND_CPU, 1, N_SPECS); }
static void cpu_2_threads_at_once(void) { same_as_alone(WEFT_BACKEND_CPU, 2, N_SPECS); }
static void cpu_3_threads_in_turn(void) { same_as_alone(WEFT_BACKEND_CPU, 3, 2); }
static void gpu(void) { same_as_alone(WEFT_BACKEND_GPU, 1, N_SPECS); }

int main(void) {
    main_thread = pthread_self();
    RUN_TEST(cpu_1_thread);
    RUN_TEST(cpu_2_threads_at_once);
    RUN_TEST(cpu_3_threads_in_turn);
    RUN_TEST(gpu);
    RUN_TEST(bad_entries);
    RUN_TEST(add_and_destroy);
    CHECK_EQ_INT(foreign_log_calls, 0);
    printf("  messages logged: %d debug, %d info, %d warn, %d error\n", logged.count[0], logged.count[1],
           logged.count[2], logged.count[3]);
    return TEST_SUMMARY();
}
