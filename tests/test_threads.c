/* The threading contract (weft.h), run under ThreadSanitizer by CI (build-tsan, .ci/run) and as
 * an ordinary test everywhere else:
 *  - two contexts stepping on two threads at once (one through weft_cloth_step, one through
 *    weft_context_step) give exactly the results of one thread alone;
 *  - one thread creating and destroying cloths in one context while another steps in another;
 *  - a host breaking the contract (a second thread entering a context while the first is inside
 *    a call) is refused with WEFT_ERROR_CONCURRENT_CALL and nothing of the context changes: the
 *    first thread is held inside weft_cloth_create (in its allocator callback) while the second
 *    calls, so the overlap is certain, not a matter of timing;
 *  - nested calls on the thread that is inside (a callback calling back in) still work. */
#include <pthread.h>
#include <stdint.h>
#include "api_grid.h"
#include "check.h"

#define FRAMES 12
#define GRID 10

static weft_context* new_context(const weft_context_def* base) {
    weft_context_def cd = base ? *base : weft_default_context_def();
    cd.backend = WEFT_BACKEND_CPU;
    cd.threads = 1;
    weft_context* ctx = NULL;
    CHECK_EQ_INT(weft_context_create(WEFT_ABI, &cd, &ctx), WEFT_OK);
    return ctx;
}

static weft_status new_cloth(weft_context* ctx, const ag_mesh* m, weft_cloth* out) {
    weft_cloth_def def = weft_default_cloth_def();
    def.mesh = ag_desc(m);
    static const int corners[2] = {GRID * (GRID - 1), GRID * GRID - 1};
    weft_attachment_def at = weft_default_attachment_def();
    at.vertices = corners;
    at.n_vertices = 2;
    def.attachments = &at;
    def.n_attachments = 1;
    return weft_cloth_create(ctx, &def, out);
}

/* ---- two contexts, two threads ----------------------------------------------------------------- */

typedef struct run {
    weft_context* ctx;
    weft_cloth cloth;
    double phase;          /* each thread moves its pins differently */
    int batch;             /* 1: weft_context_step (a batch of one), 0: weft_cloth_step */
    float out[3 * GRID * GRID];
    int failures;
} run;

static void step_frames(run* r) {
    for (int f = 0; f < FRAMES; ++f) {
        float bone[16];
        ag_transform(bone, 0, 1, 0, 0.1 * f * r->phase, 0.01 * f, 0, 0);
        weft_frame fr = weft_default_frame();
        fr.dt = 1.0 / 30.0;
        fr.attachment_transforms = bone;
        weft_status st = r->batch ? weft_context_step(r->ctx, 1, &r->cloth, &fr, NULL, NULL)
                                  : weft_cloth_step(r->ctx, r->cloth, &fr, NULL);
        if (st != WEFT_OK) ++r->failures;
    }
    int count = 0;
    if (weft_cloth_get_vertices(r->ctx, r->cloth, WEFT_SPACE_WORLD, r->out, NULL, GRID * GRID, &count) != WEFT_OK)
        ++r->failures;
}

static void* step_thread(void* arg) {
    step_frames(arg);
    return NULL;
}

static void test_two_contexts_two_threads(void) {
    ag_mesh m;
    ag_grid(&m, GRID, 1.0, 0.0, 0, 0);
    run r[2], ref[2];
    for (int k = 0; k < 2; ++k) {
        r[k] = (run){.ctx = new_context(NULL), .phase = k ? -1.0 : 1.0, .batch = k};
        ref[k] = (run){.ctx = new_context(NULL), .phase = r[k].phase};
        CHECK_EQ_INT(new_cloth(r[k].ctx, &m, &r[k].cloth), WEFT_OK);
        CHECK_EQ_INT(new_cloth(ref[k].ctx, &m, &ref[k].cloth), WEFT_OK);
    }
    pthread_t t[2];
    for (int k = 0; k < 2; ++k) CHECK_EQ_INT(pthread_create(&t[k], NULL, step_thread, &r[k]), 0);
    for (int k = 0; k < 2; ++k) pthread_join(t[k], NULL);
    for (int k = 0; k < 2; ++k) step_frames(&ref[k]);   /* the same, one at a time */
    for (int k = 0; k < 2; ++k) {
        CHECK_EQ_INT(r[k].failures, 0);
        CHECK(memcmp(r[k].out, ref[k].out, sizeof r[k].out) == 0);
        weft_context_destroy(r[k].ctx);
        weft_context_destroy(ref[k].ctx);
    }
    ag_free(&m);
}

/* ---- one thread creates while another steps ------------------------------------------------------ */

typedef struct creator {
    weft_context* ctx;
    const ag_mesh* mesh;
    int created, failures;
} creator;

static void* create_thread(void* arg) {
    creator* c = arg;
    for (int i = 0; i < 6; ++i) {
        weft_cloth cl[2];
        for (int k = 0; k < 2; ++k) {
            if (new_cloth(c->ctx, c->mesh, &cl[k]) == WEFT_OK) ++c->created;
            else ++c->failures;
        }
        weft_frame fr = weft_default_frame();
        fr.dt = 1.0 / 60.0;
        if (weft_cloth_step(c->ctx, cl[0], &fr, NULL) != WEFT_OK) ++c->failures;
        for (int k = 0; k < 2; ++k)
            if (weft_cloth_destroy(c->ctx, cl[k]) != WEFT_OK) ++c->failures;
    }
    return NULL;
}

static void test_create_while_stepping(void) {
    ag_mesh m;
    ag_grid(&m, GRID, 1.0, 0.0, 0, 0);
    run stepper = {.ctx = new_context(NULL), .phase = 1.0};
    CHECK_EQ_INT(new_cloth(stepper.ctx, &m, &stepper.cloth), WEFT_OK);
    creator c = {.ctx = new_context(NULL), .mesh = &m};
    pthread_t ts, tc;
    CHECK_EQ_INT(pthread_create(&ts, NULL, step_thread, &stepper), 0);
    CHECK_EQ_INT(pthread_create(&tc, NULL, create_thread, &c), 0);
    pthread_join(ts, NULL);
    pthread_join(tc, NULL);
    CHECK_EQ_INT(stepper.failures, 0);
    CHECK_EQ_INT(c.failures, 0);
    CHECK_EQ_INT(c.created, 12);
    weft_context_destroy(stepper.ctx);
    weft_context_destroy(c.ctx);
    ag_free(&m);
}

/* ---- the contract broken: two threads on one context --------------------------------------------- */

/* The allocator of the shared context: on its first call after `armed` is set (inside
 * weft_cloth_create on thread 1) it tells thread 2 to go and waits until thread 2 is done. */
typedef struct gate {
    pthread_mutex_t mu;
    pthread_cond_t cv;
    int armed, inside, done;
    weft_context* ctx;
    weft_cloth existing;
    int nested_status;      /* a call back into the context from the callback (same thread) */
    int log_errors;         /* ERROR messages the logger received (from either thread) */
} gate;

static void* gate_alloc(size_t size, void* user) {
    gate* g = user;
    pthread_mutex_lock(&g->mu);
    int hold = g->armed;
    g->armed = 0;
    pthread_mutex_unlock(&g->mu);
    if (hold) {
        weft_cloth_info info;   /* nested on the thread that is inside: allowed */
        g->nested_status = weft_cloth_get_info(g->ctx, g->existing, &info);
        pthread_mutex_lock(&g->mu);
        g->inside = 1;
        pthread_cond_broadcast(&g->cv);
        while (!g->done) pthread_cond_wait(&g->cv, &g->mu);
        pthread_mutex_unlock(&g->mu);
    }
    return malloc(size);
}

static void gate_free(void* p, void* user) {
    (void)user;
    free(p);
}

static void gate_log(weft_log_level level, const char* message, void* user) {
    gate* g = user;
    (void)message;
    if (level == WEFT_LOG_ERROR) {
        pthread_mutex_lock(&g->mu);
        ++g->log_errors;
        pthread_mutex_unlock(&g->mu);
    }
}

typedef struct intruder {
    gate* g;
    weft_status info, step, batch, batch_status, save, create, destroy_cloth;
} intruder;

static void* intruder_thread(void* arg) {
    intruder* in = arg;
    gate* g = in->g;
    pthread_mutex_lock(&g->mu);
    while (!g->inside) pthread_cond_wait(&g->cv, &g->mu);
    pthread_mutex_unlock(&g->mu);
    /* thread 1 is inside weft_cloth_create on this context now */
    weft_cloth_info info;
    in->info = weft_cloth_get_info(g->ctx, g->existing, &info);
    weft_frame fr = weft_default_frame();
    fr.dt = 1.0 / 60.0;
    in->step = weft_cloth_step(g->ctx, g->existing, &fr, NULL);
    in->batch_status = (weft_status)12345;
    in->batch = weft_context_step(g->ctx, 1, &g->existing, &fr, NULL, &in->batch_status);
    unsigned char buf[64];
    in->save = weft_cloth_save(g->ctx, g->existing, buf, sizeof buf);
    weft_cloth_def def = weft_default_cloth_def();
    weft_cloth other;
    in->create = weft_cloth_create(g->ctx, &def, &other);
    in->destroy_cloth = weft_cloth_destroy(g->ctx, g->existing);
    weft_context_destroy(g->ctx);   /* refused too: logged, the context stays */
    pthread_mutex_lock(&g->mu);
    g->done = 1;
    pthread_cond_broadcast(&g->cv);
    pthread_mutex_unlock(&g->mu);
    return NULL;
}

static void test_two_threads_one_context_refused(void) {
    gate g;
    memset(&g, 0, sizeof g);
    pthread_mutex_init(&g.mu, NULL);
    pthread_cond_init(&g.cv, NULL);
    weft_context_def cd = weft_default_context_def();
    cd.allocator.alloc = gate_alloc;
    cd.allocator.free = gate_free;
    cd.allocator.user = &g;
    cd.log = gate_log;
    cd.log_user = &g;
    g.ctx = new_context(&cd);
    ag_mesh m;
    ag_grid(&m, GRID, 1.0, 0.0, 0, 0);
    CHECK_EQ_INT(new_cloth(g.ctx, &m, &g.existing), WEFT_OK);
    weft_cloth_info info;
    CHECK_EQ_INT(weft_cloth_get_info(g.ctx, g.existing, &info), WEFT_OK);
    unsigned char* before = malloc(info.snapshot_size);
    unsigned char* after = malloc(info.snapshot_size);
    CHECK_EQ_INT(weft_cloth_save(g.ctx, g.existing, before, info.snapshot_size), WEFT_OK);

    intruder in = {.g = &g};
    pthread_t t;
    g.armed = 1;
    CHECK_EQ_INT(pthread_create(&t, NULL, intruder_thread, &in), 0);
    weft_cloth second;
    CHECK_EQ_INT(new_cloth(g.ctx, &m, &second), WEFT_OK);   /* thread 1: held inside until thread 2 is done */
    pthread_join(t, NULL);

    CHECK(g.inside && g.done);
    CHECK_EQ_INT(g.nested_status, WEFT_OK);
    CHECK_EQ_INT(in.info, WEFT_ERROR_CONCURRENT_CALL);
    CHECK_EQ_INT(in.step, WEFT_ERROR_CONCURRENT_CALL);
    CHECK_EQ_INT(in.batch, WEFT_ERROR_CONCURRENT_CALL);
    CHECK_EQ_INT(in.batch_status, 12345);   /* nothing written */
    CHECK_EQ_INT(in.save, WEFT_ERROR_CONCURRENT_CALL);
    CHECK_EQ_INT(in.create, WEFT_ERROR_CONCURRENT_CALL);
    CHECK_EQ_INT(in.destroy_cloth, WEFT_ERROR_CONCURRENT_CALL);
    CHECK_EQ_INT(g.log_errors, 1);   /* the refused weft_context_destroy */
    /* thread 1's call went through; the refused calls left no trace */
    CHECK_EQ_INT(weft_context_last_status(g.ctx), WEFT_OK);
    CHECK_EQ_INT(weft_cloth_save(g.ctx, g.existing, after, info.snapshot_size), WEFT_OK);
    CHECK(memcmp(before, after, info.snapshot_size) == 0);
    CHECK_EQ_INT(weft_cloth_get_info(g.ctx, second, &info), WEFT_OK);
    weft_frame fr = weft_default_frame();
    fr.dt = 1.0 / 60.0;
    CHECK_EQ_INT(weft_cloth_step(g.ctx, g.existing, &fr, NULL), WEFT_OK);   /* the context works on */
    CHECK(strcmp(weft_status_string(WEFT_ERROR_CONCURRENT_CALL), "unknown status") != 0);
    weft_context_destroy(g.ctx);
    free(before);
    free(after);
    ag_free(&m);
    pthread_mutex_destroy(&g.mu);
    pthread_cond_destroy(&g.cv);
}

int main(void) {
    RUN_TEST(test_two_contexts_two_threads);
    RUN_TEST(test_create_while_stepping);
    RUN_TEST(test_two_threads_one_context_refused);
    return TEST_SUMMARY();
}
