/* Sleeping through the public API (weft_cloth_def.sleep_speed/sleep_time, weft_frame_stats.asleep/
 * fell_asleep/woke): a hanging sheet falls asleep and its vertices then stay bit-identical; every
 * host input it must feel wakes it (attachment, collider, wind, RESET, TELEPORT, inertia) and an
 * object transform it does not feel (default inertia) does not; snapshots carry the sleep state
 * (restore puts it to sleep or wakes it; a round trip across falling asleep is bit-identical);
 * sleep_speed 0 never sleeps; sleeping and waking steps allocate nothing. */
#include <stdint.h>
#include "api_grid.h"
#include "check.h"

#define N 8
#define SIZE 0.5
#define DT (1.0 / 60.0)

typedef struct fixture {
    ag_mesh m;
    ag_alloc_counter counter;
    weft_context* ctx;
    weft_cloth cloth;
    int corners[2];
    weft_attachment_def att;
    weft_collider_def col;
} fixture;

/* A vertical sheet hanging from its two top corners (one attachment); a sphere far below. */
static void fx_make(fixture* f, double sleep_speed, double linear_inertia) {
    memset(f, 0, sizeof *f);
    ag_grid(&f->m, N, SIZE, 1.0, 1, 0);
    weft_context_def cd = weft_default_context_def();
    cd.threads = 1;
    cd.allocator.alloc = ag_count_alloc;
    cd.allocator.free = ag_count_free;
    cd.allocator.user = &f->counter;
    CHECK_EQ_INT(weft_context_create(WEFT_ABI, &cd, &f->ctx), WEFT_OK);
    f->corners[0] = N * (N - 1);
    f->corners[1] = N * N - 1;
    f->att = weft_default_attachment_def();
    f->att.vertices = f->corners;
    f->att.n_vertices = 2;
    f->col = weft_default_collider_def();
    f->col.radius = 0.1;
    ag_transform(f->col.transform, 1, 0, 0, 0.0, 0.0, -20.0, 0.0);
    weft_cloth_def def = weft_default_cloth_def();
    def.mesh = ag_desc(&f->m);
    def.attachments = &f->att;
    def.n_attachments = 1;
    def.colliders = &f->col;
    def.n_colliders = 1;
    def.sleep_speed = sleep_speed;
    def.sleep_time = 0.25;
    def.linear_inertia = linear_inertia;
    CHECK_EQ_INT(weft_cloth_create(f->ctx, &def, &f->cloth), WEFT_OK);
}

static void fx_free(fixture* f) {
    weft_context_destroy(f->ctx);
    CHECK_EQ_INT(f->counter.live, 0);
    ag_free(&f->m);
}

static weft_frame_stats step(fixture* f, const weft_frame* fr_in) {
    weft_frame fr = fr_in ? *fr_in : weft_default_frame();
    fr.dt = DT;
    weft_frame_stats st;
    memset(&st, 0, sizeof st);
    weft_status s = weft_cloth_step(f->ctx, f->cloth, &fr, &st);
    CHECK_EQ_INT(s, WEFT_OK);
    if (s != WEFT_OK) fprintf(stderr, "  %s\n", weft_context_last_error(f->ctx));
    return st;
}

static int run_to_sleep(fixture* f) {
    for (int k = 1; k <= 300; ++k)
        if (step(f, NULL).fell_asleep) return k;
    CHECK(!"never fell asleep");
    return -1;
}

static void vertices(fixture* f, float* out) {
    int count = 0;
    CHECK_EQ_INT(weft_cloth_get_vertices(f->ctx, f->cloth, WEFT_SPACE_WORLD, out, NULL, f->m.nv, &count), WEFT_OK);
}

static void test_default_def(void) {
    weft_cloth_def d = weft_default_cloth_def();
    CHECK(d.sleep_speed == 1e-3 && d.sleep_time == 0.5);
}

/* Falls asleep; asleep: nothing moves, time runs, no allocation; then awake and asleep again. */
static void test_asleep_is_still(void) {
    fixture f;
    fx_make(&f, 1e-3, 1.0);
    int k = run_to_sleep(&f);
    printf("  asleep after %d frames\n", k);
    CHECK(k >= (int)(0.25 / DT));   /* not before the rest timer could have run out */
    float* a = malloc(sizeof(float) * 3 * (size_t)f.m.nv);
    float* b = malloc(sizeof(float) * 3 * (size_t)f.m.nv);
    vertices(&f, a);
    long allocs = f.counter.allocs;
    double t0 = 0.0;
    for (int i = 0; i < 20; ++i) {
        weft_frame_stats st = step(&f, NULL);
        CHECK(st.asleep && !st.woke && !st.fell_asleep);
        CHECK_EQ_INT(st.substeps, 0);
        CHECK_EQ_INT(st.iterations, 0);
        CHECK(st.kinetic_energy == 0.0);
        if (i == 0) t0 = st.time;
        else CHECK_NEAR(st.time, t0 + i * DT, 1e-12);
    }
    vertices(&f, b);
    CHECK(memcmp(a, b, sizeof(float) * 3 * (size_t)f.m.nv) == 0);
    /* a wake (the attachment moves 1 cm) and back to sleep: still no allocation */
    float bone[16];
    ag_transform(bone, 0, 1, 0, 0.0, 0.01, 0.0, 0.0);
    weft_frame fr = weft_default_frame();
    fr.attachment_transforms = bone;
    weft_frame_stats st = step(&f, &fr);
    CHECK(st.woke && !st.asleep && st.substeps == 1);
    run_to_sleep(&f);
    CHECK(step(&f, &fr).asleep);   /* the same bone transform again: still asleep */
    CHECK_EQ_INT(f.counter.allocs, allocs);
    free(a);
    free(b);
    fx_free(&f);
}

typedef enum wake { W_BONE, W_COLLIDER, W_WIND, W_RESET, W_TELEPORT, W_OBJECT_STILL, W_INERTIA, W_COUNT } wake;
static const char* const wake_name[W_COUNT] = {"attachment", "collider", "wind", "reset", "teleport",
                                                "object (inertia 1)", "object (inertia 0.5)"};

static void test_wake_rules(void) {
    for (int w = 0; w < W_COUNT; ++w) {
        fixture f;
        fx_make(&f, 1e-3, w == W_INERTIA ? 0.5 : 1.0);
        run_to_sleep(&f);
        float* a = malloc(sizeof(float) * 3 * (size_t)f.m.nv);
        float* b = malloc(sizeof(float) * 3 * (size_t)f.m.nv);
        vertices(&f, a);
        float m[16], identity[16];
        ag_identity(identity);
        double wind[3] = {0.0, 0.0, 0.0};
        weft_frame fr = weft_default_frame();
        /* the current inputs passed again: still asleep */
        fr.attachment_transforms = identity;
        fr.collider_transforms = f.col.transform;
        fr.wind = wind;
        CHECK(step(&f, &fr).asleep);
        fr = weft_default_frame();
        switch ((wake)w) {
        case W_BONE:
            ag_transform(m, 0, 0, 1, 0.05, 0.0, 0.0, 0.0);
            fr.attachment_transforms = m;
            break;
        case W_COLLIDER:   /* into the sheet (the plane z = 0), from behind */
            ag_transform(m, 1, 0, 0, 0.0, 0.0, 0.75, -0.08);
            fr.collider_transforms = m;
            break;
        case W_WIND:
            wind[2] = 5.0;
            fr.wind = wind;
            break;
        case W_RESET: fr.flags = WEFT_FRAME_RESET; break;
        case W_TELEPORT:
            ag_transform(m, 0, 1, 0, 0.0, 3.0, 0.0, 0.0);
            fr.object_transform = m;
            fr.flags = WEFT_FRAME_TELEPORT;
            break;
        case W_OBJECT_STILL:
        case W_INERTIA:
            /* the object accelerates from rest (its attachments are separate transforms) */
            ag_transform(m, 0, 1, 0, 0.0, 0.02, 0.0, 0.0);
            fr.object_transform = m;
            break;
        default: break;
        }
        weft_frame_stats st = step(&f, &fr);
        vertices(&f, b);
        const int moved = memcmp(a, b, sizeof(float) * 3 * (size_t)f.m.nv) != 0;
        if (w == W_OBJECT_STILL) {
            /* default inertia: the cloth does not feel its object's motion, so it sleeps on */
            CHECK(st.asleep && !st.woke && !moved);
        } else {
            CHECK(st.woke && !st.asleep && st.substeps >= 1);
            if (w != W_RESET) CHECK(moved);   /* RESET puts it back at rest (and it was there) */
        }
        if (w == W_RESET) CHECK(st.time == DT && st.frame == 1);
        printf("  %-20s %s\n", wake_name[w], st.woke ? "woke it" : "did not wake it");
        free(a);
        free(b);
        fx_free(&f);
    }
}

/* Snapshots hold the sleep state: a round trip across falling asleep is bit-identical, restoring
 * an asleep snapshot puts it to sleep, an awake one wakes it. */
static void test_snapshots(void) {
    fixture f;
    fx_make(&f, 1e-3, 1.0);
    weft_cloth_info info;
    CHECK_EQ_INT(weft_cloth_get_info(f.ctx, f.cloth, &info), WEFT_OK);
    unsigned char* early = malloc(info.snapshot_size);
    unsigned char* late = malloc(info.snapshot_size);
    unsigned char* again = malloc(info.snapshot_size);
    for (int k = 0; k < 5; ++k) CHECK(!step(&f, NULL).asleep);
    CHECK_EQ_INT(weft_cloth_save(f.ctx, f.cloth, early, info.snapshot_size), WEFT_OK);
    int slept = 0;
    for (int k = 0; k < 60; ++k) slept += step(&f, NULL).asleep;
    CHECK(slept > 0);
    CHECK_EQ_INT(weft_cloth_save(f.ctx, f.cloth, late, info.snapshot_size), WEFT_OK);
    /* awake snapshot into the sleeping cloth: it wakes and retraces the same frames */
    CHECK_EQ_INT(weft_cloth_restore(f.ctx, f.cloth, early, info.snapshot_size), WEFT_OK);
    weft_frame_stats st = step(&f, NULL);
    CHECK(st.woke && !st.asleep);
    int slept2 = 0;
    for (int k = 1; k < 60; ++k) slept2 += step(&f, NULL).asleep;
    CHECK_EQ_INT(slept2, slept);
    CHECK_EQ_INT(weft_cloth_save(f.ctx, f.cloth, again, info.snapshot_size), WEFT_OK);
    CHECK(memcmp(late, again, info.snapshot_size) == 0);
    /* asleep snapshot into an awake cloth (it was woken by the wind): asleep again, wind back */
    double wind[3] = {2.0, 0.0, 0.0};
    weft_frame fr = weft_default_frame();
    fr.wind = wind;
    CHECK(step(&f, &fr).woke);
    CHECK_EQ_INT(weft_cloth_restore(f.ctx, f.cloth, late, info.snapshot_size), WEFT_OK);
    st = step(&f, NULL);
    CHECK(st.asleep && !st.woke);
    free(early);
    free(late);
    free(again);
    fx_free(&f);
}

static void test_disabled(void) {
    fixture f;
    fx_make(&f, 0.0, 1.0);
    int slept = 0;
    for (int k = 0; k < 90; ++k) {
        weft_frame_stats st = step(&f, NULL);
        slept += st.asleep + st.fell_asleep;
    }
    CHECK_EQ_INT(slept, 0);
    fx_free(&f);
}

int main(void) {
    RUN_TEST(test_default_def);
    RUN_TEST(test_asleep_is_still);
    RUN_TEST(test_wake_rules);
    RUN_TEST(test_snapshots);
    RUN_TEST(test_disabled);
    return TEST_SUMMARY();
}
