/* The GPU backend through the public API (real EGL: llvmpipe without a GPU): context creation
 * (GPU works headless, AUTO picks the CPU on a software rasteriser), the direct solver refused,
 * a hanging sheet stepped on the GPU close to the CPU backend's, bit-exact snapshot round trips,
 * two GPU contexts in one process, the host-current mode leaving the host's GL bindings alone,
 * weft_cloth_write_gl_buffers matching weft_cloth_get_vertices, and its misuse rows. */
#define _POSIX_C_SOURCE 200809L
#include <GL/glew.h>
#include <string.h>
#include <stdio.h>
#include <stdlib.h>

#include "api_gpu_support.h"
#include "api_grid.h"
#include "check.h"
#include "egl_context.h"
#include "gl_program.h"

#define N 12             /* grid vertices per side: a 1 m sheet */
#define FRAMES 30

static ag_log g_log;

static weft_context* make_ctx(weft_backend backend, weft_gl_mode mode, weft_status want) {
    weft_context_def cd = ap_context_def(backend);
    cd.gl_mode = mode;
    cd.log = ag_log_fn;
    cd.log_user = &g_log;
    cd.log_level = WEFT_LOG_INFO;
    return ap_create(&cd, want, &g_log);
}

/* A horizontal 1 m sheet held by two adjacent corners: it swings down and hangs. One linearised
   step with block Jacobi on both backends, the simplest method they share (the defaults are the
   multigrid and two Newton iterations with line search). */
static ap_pins g_pins;

static weft_cloth_def sheet_def(const ag_mesh* m) { return ap_pinned_sheet_def(m, &g_pins, 1, 0); }

static weft_cloth make_sheet(weft_context* ctx, const ag_mesh* m) {
    weft_cloth_def def = sheet_def(m);
    weft_cloth cloth = {0};
    weft_status st = weft_cloth_create(ctx, &def, &cloth);
    CHECK_EQ_INT(st, WEFT_OK);
    if (st != WEFT_OK) fprintf(stderr, "weft_cloth_create: %s\n", weft_context_last_error(ctx));
    return cloth;
}

static int step(weft_context* ctx, weft_cloth cloth, int frames) {
    weft_frame fr = weft_default_frame();
    fr.dt = 1.0 / 60.0;
    for (int f = 0; f < frames; ++f) {
        weft_status st = weft_cloth_step(ctx, cloth, &fr, NULL);
        if (st != WEFT_OK) {
            fprintf(stderr, "weft_cloth_step frame %d: %s\n", f, weft_context_last_error(ctx));
            return 0;
        }
    }
    return 1;
}

static float* vertices(weft_context* ctx, weft_cloth cloth, weft_space space, float** normals) {
    int n = 0;
    CHECK_EQ_INT(weft_cloth_get_vertices(ctx, cloth, space, NULL, NULL, 0, &n), WEFT_OK);
    float* p = calloc((size_t)n * 3, sizeof(float));
    float* q = normals ? calloc((size_t)n * 3, sizeof(float)) : NULL;
    weft_status st = weft_cloth_get_vertices(ctx, cloth, space, p, q, n, &n);
    CHECK_EQ_INT(st, WEFT_OK);
    if (st != WEFT_OK) fprintf(stderr, "weft_cloth_get_vertices: %s\n", weft_context_last_error(ctx));
    if (normals) *normals = q;
    return p;
}

static int g_software = -1;   /* the GPU context's renderer is a software rasteriser */
static int g_compute = -1;    /* the GPU context runs compute-shader passes */

/* Set an environment variable for a check; returns its old value (NULL: unset) for env_restore. */
static char* env_set(const char* name, const char* value) {
    const char* old = getenv(name);
    char* saved = old ? strdup(old) : NULL;
    setenv(name, value, 1);
    return saved;
}

static void env_restore(const char* name, char* saved) {
    if (saved) setenv(name, saved, 1);
    else unsetenv(name);
    free(saved);
}

/* 1 when a headless context of this driver has OpenGL 4.3 (compute shaders) */
static int driver_has_gl43(void) {
    char err[256];
    wg_gl_context_desc d;
    memset(&d, 0, sizeof d);
    wg_gl_context* gl = NULL;
    if (wg_gl_context_create(&d, &gl, err, sizeof err) != WC_OK) return 0;
    int has = wg_gl_begin(gl, err, sizeof err) == WC_OK && GLEW_VERSION_4_3;
    wg_gl_end(gl);
    wg_gl_context_destroy(gl);
    return has;
}

static void test_backend_choice(void) {
    memset(&g_log, 0, sizeof g_log);
    weft_context* gpu = make_ctx(WEFT_BACKEND_GPU, WEFT_GL_HEADLESS, WEFT_OK);
    if (!gpu) return;
    CHECK_EQ_INT(weft_context_backend(gpu), WEFT_BACKEND_GPU);
    CHECK(strstr(g_log.last, "GPU backend") != NULL);
    /* the passes: compute shaders on GL 4.3, fragment shaders below it (ctest runs this program
       also on a GL 3.3 context: test_api_gpu_gl33), unless WEFT_GPU_PASSES says otherwise */
    const char* passes_env = getenv("WEFT_GPU_PASSES");
    int gl43 = driver_has_gl43(), want_compute = passes_env && *passes_env ? strcmp(passes_env, "compute") == 0 : gl43;
    CHECK(strstr(g_log.last, want_compute ? "(compute-shader passes)" : "(fragment-shader passes)") != NULL);
    g_compute = want_compute;
    g_software = strstr(g_log.last, "llvmpipe") || strstr(g_log.last, "softpipe") || strstr(g_log.last, "swrast");
    printf("GPU context: %s\n", g_log.last);
    weft_context_destroy(gpu);

    memset(&g_log, 0, sizeof g_log);
    weft_context* aut = make_ctx(WEFT_BACKEND_AUTO, WEFT_GL_HEADLESS, WEFT_OK);
    if (!aut) return;
    printf("AUTO context: %s\n", g_log.last);
    if (g_software) {
        CHECK_EQ_INT(weft_context_backend(aut), WEFT_BACKEND_CPU);
        CHECK(strstr(g_log.last, "CPU backend") != NULL && strstr(g_log.last, "software") != NULL);
    } else {
        CHECK_EQ_INT(weft_context_backend(aut), WEFT_BACKEND_GPU);
    }
    weft_context_destroy(aut);

    weft_context* cpu = make_ctx(WEFT_BACKEND_CPU, WEFT_GL_HEADLESS, WEFT_OK);
    CHECK_EQ_INT(weft_context_backend(cpu), WEFT_BACKEND_CPU);
    weft_context_destroy(cpu);

    /* host-current mode with no context current on this thread: GPU refused, AUTO falls back */
    memset(&g_log, 0, sizeof g_log);
    weft_context* none = make_ctx(WEFT_BACKEND_GPU, WEFT_GL_HOST_CURRENT, WEFT_ERROR_GPU);
    CHECK(none == NULL);
    CHECK(strstr(g_log.last, "weft_context_create: def->backend GPU") != NULL);
    weft_context* fallback = make_ctx(WEFT_BACKEND_AUTO, WEFT_GL_HOST_CURRENT, WEFT_OK);
    CHECK_EQ_INT(weft_context_backend(fallback), WEFT_BACKEND_CPU);
    weft_context_destroy(fallback);

    /* WEFT_EGL_DEVICE still picks (or here, refuses) the headless device */
    char* saved = env_set("WEFT_EGL_DEVICE", "no-such-device");
    memset(&g_log, 0, sizeof g_log);
    CHECK(make_ctx(WEFT_BACKEND_GPU, WEFT_GL_HEADLESS, WEFT_ERROR_GPU) == NULL);
    CHECK(strstr(g_log.last, "no-such-device") != NULL);
    fallback = make_ctx(WEFT_BACKEND_AUTO, WEFT_GL_HEADLESS, WEFT_OK);
    CHECK_EQ_INT(weft_context_backend(fallback), WEFT_BACKEND_CPU);
    weft_context_destroy(fallback);
    /* Mesa's software device: where the default device is Mesa's (CI) it must be found; a GPU
       machine may have no Mesa, and then the choice is refused, naming what is missing */
    setenv("WEFT_EGL_DEVICE", "software", 1);
    memset(&g_log, 0, sizeof g_log);
    weft_context_def sd = weft_default_context_def();
    sd.threads = 1;
    sd.backend = WEFT_BACKEND_GPU;
    sd.log = ag_log_fn;
    sd.log_user = &g_log;
    weft_context* sw = NULL;
    weft_status sst = weft_context_create(WEFT_ABI, &sd, &sw);
    CHECK(sst == WEFT_OK || (!g_software && sst == WEFT_ERROR_GPU));
    if (sw) {
        CHECK_EQ_INT(weft_context_backend(sw), WEFT_BACKEND_GPU);
        weft_context_destroy(sw);
    } else {
        printf("no software device here: %s\n", g_log.last);
        CHECK(strstr(g_log.last, "EGL_MESA_device_software") != NULL);
    }
    env_restore("WEFT_EGL_DEVICE", saved);

    /* WEFT_GPU_PASSES picks fragment or compute passes; anything else is refused by name */
    saved = env_set("WEFT_GPU_PASSES", "vertex");
    memset(&g_log, 0, sizeof g_log);
    CHECK(make_ctx(WEFT_BACKEND_GPU, WEFT_GL_HEADLESS, WEFT_ERROR_GPU) == NULL);
    CHECK(strstr(g_log.last, "WEFT_GPU_PASSES='vertex'") != NULL);
    /* compute insisted on: refused below GL 4.3, naming the version; the log says which passes */
    setenv("WEFT_GPU_PASSES", "compute", 1);
    memset(&g_log, 0, sizeof g_log);
    weft_context* cc = make_ctx(WEFT_BACKEND_GPU, WEFT_GL_HEADLESS, gl43 ? WEFT_OK : WEFT_ERROR_GPU);
    CHECK(strstr(g_log.last, gl43 ? "(compute-shader passes)" : "needs OpenGL 4.3") != NULL);
    weft_context_destroy(cc);
    setenv("WEFT_GPU_PASSES", "fragment", 1);
    memset(&g_log, 0, sizeof g_log);
    weft_context_destroy(make_ctx(WEFT_BACKEND_GPU, WEFT_GL_HEADLESS, WEFT_OK));
    CHECK(strstr(g_log.last, "(fragment-shader passes)") != NULL);
    env_restore("WEFT_GPU_PASSES", saved);
}

static void test_direct_refused(void) {
    weft_context* ctx = make_ctx(WEFT_BACKEND_GPU, WEFT_GL_HEADLESS, WEFT_OK);
    if (!ctx) return;
    ag_mesh m;
    ag_grid(&m, N, 1.0, 1.5, 0, 0);
    weft_cloth_def def = sheet_def(&m);
    def.solver = WEFT_SOLVER_DIRECT;
    weft_cloth cloth = {12345};
    CHECK_EQ_INT(weft_cloth_create(ctx, &def, &cloth), WEFT_ERROR_UNSUPPORTED);
    CHECK(cloth.id == 0);
    printf("direct on the GPU: %s\n", weft_context_last_error(ctx));
    CHECK(strstr(weft_context_last_error(ctx), "weft_cloth_create") != NULL);
    CHECK(strstr(weft_context_last_error(ctx), "direct") != NULL);
    /* the multigrid (k == 0): the GPU's own on compute passes, refused on fragment passes;
       Newton and its line search (k == 2, 3: test_api_gpu_newton.c, with colliders
       test_api_gpu_newton_contacts.c), sewing (k == 4), BDF2 (k == 1), self-collision (k == 5:
       core's stage on the host, test_api_gpu_self.c) and TR-BDF2 (k == 6; with colliders
       test_api_gpu_trbdf2_contacts.c) run on the GPU */
    def.solver = WEFT_SOLVER_PCG;
    static const int seam_a[1] = {0}, seam_b[1] = {N * N - 1};
    for (int k = 0; k < 7; ++k) {
        weft_cloth_def d2 = def;
        if (k == 4) {
            d2.seam_a = seam_a;
            d2.seam_b = seam_b;
            d2.n_seams = 1;
        }
        if (k == 0) d2.preconditioner = WEFT_PRECOND_AMG;
        if (k == 1) d2.integrator = WEFT_INTEGRATOR_BDF2;
        if (k == 2) d2.newton_iterations = 3;
        if (k == 3) d2.line_search = 1;
        if (k == 5) d2.self_collision = 1;
        if (k == 6) d2.integrator = WEFT_INTEGRATOR_TRBDF2;
        if ((k == 0 && g_compute == 1) || k >= 1) {
            CHECK_EQ_INT(weft_cloth_create(ctx, &d2, &cloth), WEFT_OK);
            weft_cloth_info mi;
            CHECK_EQ_INT(weft_cloth_get_info(ctx, cloth, &mi), WEFT_OK);
            if (k == 0) CHECK_EQ_INT(mi.preconditioner, WEFT_PRECOND_AMG);
            if (k == 2) CHECK_EQ_INT(mi.newton_iterations, 3);
            if (k == 3) CHECK_EQ_INT(mi.line_search, 1);
            if (k == 4) CHECK_EQ_INT(mi.n_seams, 1);
            CHECK_EQ_INT(mi.self_collision, k == 4 || k == 5);   /* -1 on a garment (seams): on */
            if (k == 1) CHECK_EQ_INT(mi.integrator, WEFT_INTEGRATOR_BDF2);
            if (k == 6) CHECK_EQ_INT(mi.integrator, WEFT_INTEGRATOR_TRBDF2);
            CHECK(step(ctx, cloth, 3));
            CHECK_EQ_INT(weft_cloth_destroy(ctx, cloth), WEFT_OK);
            cloth.id = 0;
            continue;
        }
        CHECK_EQ_INT(weft_cloth_create(ctx, &d2, &cloth), WEFT_ERROR_UNSUPPORTED);
        if (k == 0) CHECK(strstr(weft_context_last_error(ctx), "compute-shader passes") != NULL);
        CHECK(cloth.id == 0);
        printf("CPU-only option %d on the GPU: %s\n", k, weft_context_last_error(ctx));
    }
    CHECK(strstr(weft_context_last_error(ctx), "GPU backend") != NULL);
    /* the context is still usable; DEFAULT resolves to what the GPU has */
    def.preconditioner = WEFT_PRECOND_DEFAULT;
    def.newton_iterations = 0;
    def.line_search = -1;
    CHECK_EQ_INT(weft_cloth_create(ctx, &def, &cloth), WEFT_OK);
    weft_cloth_info info;
    CHECK_EQ_INT(weft_cloth_get_info(ctx, cloth, &info), WEFT_OK);
    CHECK_EQ_INT(info.backend, WEFT_BACKEND_GPU);
    /* the multigrid where the passes have it (compute), block Jacobi on fragment passes */
    CHECK_EQ_INT(info.preconditioner, g_compute == 1 ? WEFT_PRECOND_AMG : WEFT_PRECOND_BLOCK_JACOBI);
    CHECK_EQ_INT(info.integrator, WEFT_INTEGRATOR_BACKWARD_EULER);
    CHECK_EQ_INT(info.newton_iterations, 2);    /* the CPU's method */
    CHECK_EQ_INT(info.line_search, 1);
    CHECK_EQ_INT(info.self_collision, 0);
    weft_collision_check chk = {-1, -1.0};
    CHECK_EQ_INT(weft_cloth_check_collisions(ctx, cloth, &chk), WEFT_OK); /* reads the positions back */
    CHECK_EQ_INT(chk.self_intersections, 0);
    CHECK(chk.max_penetration == 0.0);
    weft_context_destroy(ctx);
    ag_free(&m);
}

static void test_gpu_close_to_cpu(void) {
    ag_mesh m;
    ag_grid(&m, N, 1.0, 1.5, 0, 0);
    weft_context* cpu = make_ctx(WEFT_BACKEND_CPU, WEFT_GL_HEADLESS, WEFT_OK);
    weft_context* gpu = make_ctx(WEFT_BACKEND_GPU, WEFT_GL_HEADLESS, WEFT_OK);
    if (!cpu || !gpu) return;
    weft_cloth cc = make_sheet(cpu, &m), gc = make_sheet(gpu, &m);
    CHECK(step(cpu, cc, FRAMES));
    CHECK(step(gpu, gc, FRAMES));
    float *nc = NULL, *ng = NULL;
    float* pc = vertices(cpu, cc, WEFT_SPACE_WORLD, &nc);
    float* pg = vertices(gpu, gc, WEFT_SPACE_WORLD, &ng);
    double max_d = 0.0, max_drop = 0.0, max_nd = 0.0;
    int finite = 1;
    for (int i = 0; i < m.nv; ++i) {
        double d2 = 0.0, n2 = 0.0;
        for (int k = 0; k < 3; ++k) {
            finite = finite && isfinite(pg[3 * i + k]) && isfinite(ng[3 * i + k]);
            d2 += (pg[3 * i + k] - pc[3 * i + k]) * (double)(pg[3 * i + k] - pc[3 * i + k]);
            n2 += (ng[3 * i + k] - nc[3 * i + k]) * (double)(ng[3 * i + k] - nc[3 * i + k]);
        }
        if (sqrt(d2) > max_d) max_d = sqrt(d2);
        if (sqrt(n2) > max_nd) max_nd = sqrt(n2);
        double drop = fabs(pg[3 * i + 1] - m.pos[3 * i + 1]);
        if (drop > max_drop) max_drop = drop;
    }
    printf("GPU vs CPU after %d frames: max |dx| %.3g m (normals %.3g), max vertical motion %.3g m\n", FRAMES, max_d,
           max_nd, max_drop);
    CHECK(finite);
    CHECK(max_drop > 0.01);      /* it moved */
    CHECK(max_d < 5e-3);         /* float vs double solvers: a few mm */
    CHECK(max_nd < 0.05);
    /* the pinned corners stay */
    for (int k = 0; k < 2; ++k)
        for (int c = 0; c < 3; ++c) CHECK_NEAR(pg[3 * g_pins.v[k] + c], m.pos[3 * g_pins.v[k] + c], 1e-5);
    /* object space with the identity object transform and unit_scale 1: the world positions */
    float* po = vertices(gpu, gc, WEFT_SPACE_OBJECT, NULL);
    double max_o = 0.0;
    for (int i = 0; i < 3 * m.nv; ++i) max_o = fmax(max_o, fabs(po[i] - pg[i]));
    CHECK(max_o < 1e-6);
    /* a teleport moves the cloth rigidly (x' = dT x), on either backend */
    float T[16];
    ag_transform(T, 0, 1, 0, 0.5, 1.0, 0.0, -2.0);
    weft_frame fr = weft_default_frame();
    fr.dt = 1e-6;   /* nearly no motion of its own */
    fr.flags = WEFT_FRAME_TELEPORT;
    fr.object_transform = T;
    fr.attachment_transforms = T;   /* the corners' bone goes along (bound at the identity) */
    float* pt = NULL;
    float* pto = NULL;
    for (int b = 0; b < 2; ++b) {
        weft_context* ctx = b ? gpu : cpu;
        weft_cloth cl = b ? gc : cc;
        const float* p0 = b ? pg : pc;
        CHECK_EQ_INT(weft_cloth_step(ctx, cl, &fr, NULL), WEFT_OK);
        free(pt), free(pto);
        pt = vertices(ctx, cl, WEFT_SPACE_WORLD, NULL);
        pto = vertices(ctx, cl, WEFT_SPACE_OBJECT, NULL);
        double max_t = 0.0, max_to = 0.0;
        for (int i = 0; i < m.nv; ++i) {
            double p[3] = {p0[3 * i], p0[3 * i + 1], p0[3 * i + 2]}, q[3];
            ag_apply(T, p, q);
            for (int k = 0; k < 3; ++k) {
                max_t = fmax(max_t, fabs(pt[3 * i + k] - q[k]));
                max_to = fmax(max_to, fabs(pto[3 * i + k] - p[k]));
            }
        }
        printf("teleport on the %s: max error %.3g m (object space %.3g m)\n", b ? "GPU" : "CPU", max_t, max_to);
        CHECK(max_t < 1e-4);
        CHECK(max_to < 1e-4);
    }
    free(pt), free(pto), free(po);
    free(pc), free(pg), free(nc), free(ng);
    weft_context_destroy(cpu);
    weft_context_destroy(gpu);
    ag_free(&m);
}

/* The object moving and turning with partial inertia (the carry runs on the GPU as one rigid
 * pass), then a RESET: the GPU cloth follows the CPU's. */
static void test_inertia_and_reset(void) {
    ag_mesh m;
    ag_grid(&m, N, 1.0, 1.5, 0, 0);
    weft_context* ctx[2] = {make_ctx(WEFT_BACKEND_CPU, WEFT_GL_HEADLESS, WEFT_OK),
                            make_ctx(WEFT_BACKEND_GPU, WEFT_GL_HEADLESS, WEFT_OK)};
    if (!ctx[0] || !ctx[1]) return;
    weft_cloth cl[2];
    float* p[2];
    for (int b = 0; b < 2; ++b) {
        weft_cloth_def def = sheet_def(&m);
        def.linear_inertia = 0.5;
        def.angular_inertia = 0.5;
        CHECK_EQ_INT(weft_cloth_create(ctx[b], &def, &cl[b]), WEFT_OK);
        for (int f = 0; f < 20; ++f) {
            float T[16];
            ag_transform(T, 0, 1, 0, 0.05 * f, 0.02 * f * f / 20.0, 0.0, 0.0);
            weft_frame fr = weft_default_frame();
            fr.dt = 1.0 / 60.0;
            fr.object_transform = T;
            fr.attachment_transforms = T;
            weft_status st = weft_cloth_step(ctx[b], cl[b], &fr, NULL);
            CHECK_EQ_INT(st, WEFT_OK);
            if (st != WEFT_OK) fprintf(stderr, "%s\n", weft_context_last_error(ctx[b]));
        }
        p[b] = vertices(ctx[b], cl[b], WEFT_SPACE_WORLD, NULL);
    }
    double max_d = 0.0;
    for (int i = 0; i < 3 * m.nv; ++i) max_d = fmax(max_d, fabs(p[0][i] - p[1][i]));
    printf("inertia: GPU vs CPU max |dx| %.3g m\n", max_d);
    CHECK(max_d < 5e-3);
    for (int b = 0; b < 2; ++b) free(p[b]);
    /* RESET: the rest shape at the frame's object transform, then one tiny step */
    float T[16];
    ag_transform(T, 0, 0, 1, 0.3, 0.5, 0.25, 0.0);
    weft_frame fr = weft_default_frame();
    fr.dt = 1e-6;
    fr.flags = WEFT_FRAME_RESET;
    fr.object_transform = T;
    fr.attachment_transforms = T;
    for (int b = 0; b < 2; ++b) {
        CHECK_EQ_INT(weft_cloth_step(ctx[b], cl[b], &fr, NULL), WEFT_OK);
        p[b] = vertices(ctx[b], cl[b], WEFT_SPACE_WORLD, NULL);
    }
    double max_r = 0.0;
    for (int i = 0; i < m.nv; ++i) {
        double r[3] = {m.pos[3 * i], m.pos[3 * i + 1], m.pos[3 * i + 2]}, q[3];
        ag_apply(T, r, q);
        for (int k = 0; k < 3; ++k) max_r = fmax(max_r, fabs(p[1][3 * i + k] - q[k]));
    }
    printf("reset on the GPU: max error %.3g m\n", max_r);
    CHECK(max_r < 1e-5);
    for (int b = 0; b < 2; ++b) {
        free(p[b]);
        weft_context_destroy(ctx[b]);
    }
    ag_free(&m);
}

/* save, step 5, restore, step 5: the same vertices, bit for bit; without and with a collider in
 * contact (the contacts go through the snapshot too) */
static void snapshot_round_trip(int with_collider) {
    ag_mesh m;
    ag_grid(&m, N, 1.0, 1.5, 0, 0);
    weft_context* ctx = make_ctx(WEFT_BACKEND_GPU, WEFT_GL_HEADLESS, WEFT_OK);
    if (!ctx) return;
    weft_cloth_def def = sheet_def(&m);
    weft_collider_def sph = weft_default_collider_def();
    sph.type = WEFT_COLLIDER_SPHERE;
    sph.radius = 0.3;
    sph.friction = 0.3;
    ag_transform(sph.transform, 0, 1, 0, 0.0, 0.0, 1.2, 0.1);
    if (with_collider) {
        def.colliders = &sph;
        def.n_colliders = 1;
    }
    weft_cloth cloth = {0};
    CHECK_EQ_INT(weft_cloth_create(ctx, &def, &cloth), WEFT_OK);
    CHECK(step(ctx, cloth, 10));
    weft_cloth_info info;
    CHECK_EQ_INT(weft_cloth_get_info(ctx, cloth, &info), WEFT_OK);
    unsigned char* snap = malloc(info.snapshot_size);
    unsigned char* snap2 = malloc(info.snapshot_size);
    CHECK_EQ_INT(weft_cloth_save(ctx, cloth, snap, info.snapshot_size), WEFT_OK);
    weft_frame_stats st;
    weft_frame fr = weft_default_frame();
    fr.dt = 1.0 / 60.0;
    CHECK_EQ_INT(weft_cloth_step(ctx, cloth, &fr, &st), WEFT_OK);
    if (with_collider) {
        printf("contacts on the GPU: %d\n", st.contacts);
        CHECK(st.contacts > 0);
    }
    CHECK(step(ctx, cloth, 4));
    float *na = NULL, *nb = NULL;
    float* a = vertices(ctx, cloth, WEFT_SPACE_WORLD, &na);
    CHECK_EQ_INT(weft_cloth_restore(ctx, cloth, snap, info.snapshot_size), WEFT_OK);
    /* saved again right away: the same bytes (the GPU state went back exactly) */
    CHECK_EQ_INT(weft_cloth_save(ctx, cloth, snap2, info.snapshot_size), WEFT_OK);
    CHECK(memcmp(snap, snap2, info.snapshot_size) == 0);
    CHECK(step(ctx, cloth, 5));
    float* b = vertices(ctx, cloth, WEFT_SPACE_WORLD, &nb);
    CHECK(memcmp(a, b, (size_t)m.nv * 3 * sizeof(float)) == 0);
    CHECK(memcmp(na, nb, (size_t)m.nv * 3 * sizeof(float)) == 0);
    /* the snapshot of a GPU cloth restores on the CPU backend too (same layout) */
    weft_context* cpu = make_ctx(WEFT_BACKEND_CPU, WEFT_GL_HEADLESS, WEFT_OK);
    weft_cloth cc = {0};
    CHECK_EQ_INT(weft_cloth_create(cpu, &def, &cc), WEFT_OK);
    CHECK_EQ_INT(weft_cloth_restore(cpu, cc, snap, info.snapshot_size), WEFT_OK);
    weft_context_destroy(cpu);
    free(a), free(b), free(na), free(nb), free(snap), free(snap2);
    weft_context_destroy(ctx);
    ag_free(&m);
}

static void test_snapshot_round_trip(void) {
    snapshot_round_trip(0);
    snapshot_round_trip(1);
}

static void test_two_contexts(void) {
    ag_mesh m;
    ag_grid(&m, N, 1.0, 1.5, 0, 0);
    weft_context* c1 = make_ctx(WEFT_BACKEND_GPU, WEFT_GL_HEADLESS, WEFT_OK);
    weft_context* c2 = make_ctx(WEFT_BACKEND_GPU, WEFT_GL_HEADLESS, WEFT_OK);
    if (!c1 || !c2) return;
    weft_cloth a = make_sheet(c1, &m), b = make_sheet(c2, &m);
    int ok = 1;
    for (int f = 0; f < 10 && ok; ++f) ok = step(c1, a, 1) && step(c2, b, 1);
    CHECK(ok);
    float* pa = vertices(c1, a, WEFT_SPACE_WORLD, NULL);
    float* pb = vertices(c2, b, WEFT_SPACE_WORLD, NULL);
    CHECK(memcmp(pa, pb, (size_t)m.nv * 3 * sizeof(float)) == 0);   /* same scene, same results */
    /* one context's cloth destroyed, the other steps on */
    CHECK_EQ_INT(weft_cloth_destroy(c1, a), WEFT_OK);
    CHECK(step(c2, b, 2));
    weft_context_destroy(c1);
    CHECK(step(c2, b, 2));
    free(pa), free(pb);
    weft_context_destroy(c2);
    ag_free(&m);
}

/* ---- the host's own context ------------------------------------------------------------------- */

typedef struct host_bindings {
    GLint draw_fbo, read_fbo, program, active_texture, tex[8], viewport[4], vao, array_buffer, pack_buffer,
        unpack_buffer, copy_read, copy_write, pack_alignment, renderbuffer;
    GLint image[8], image_access[8], image_format[8];   /* image units (GL 4.2; compute passes write 0..7) */
} host_bindings;

static void record(host_bindings* h) {
    memset(h, 0, sizeof *h);
    glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &h->draw_fbo);
    glGetIntegerv(GL_READ_FRAMEBUFFER_BINDING, &h->read_fbo);
    glGetIntegerv(GL_CURRENT_PROGRAM, &h->program);
    glGetIntegerv(GL_ACTIVE_TEXTURE, &h->active_texture);
    for (int u = 0; u < 8; ++u) {
        glActiveTexture(GL_TEXTURE0 + (GLenum)u);
        glGetIntegerv(GL_TEXTURE_BINDING_2D, &h->tex[u]);
    }
    glActiveTexture((GLenum)h->active_texture);
    glGetIntegerv(GL_VIEWPORT, h->viewport);
    glGetIntegerv(GL_VERTEX_ARRAY_BINDING, &h->vao);
    glGetIntegerv(GL_ARRAY_BUFFER_BINDING, &h->array_buffer);
    glGetIntegerv(GL_PIXEL_PACK_BUFFER_BINDING, &h->pack_buffer);
    glGetIntegerv(GL_PIXEL_UNPACK_BUFFER_BINDING, &h->unpack_buffer);
    glGetIntegerv(GL_COPY_READ_BUFFER_BINDING, &h->copy_read);
    glGetIntegerv(GL_COPY_WRITE_BUFFER_BINDING, &h->copy_write);
    glGetIntegerv(GL_PACK_ALIGNMENT, &h->pack_alignment);
    glGetIntegerv(GL_RENDERBUFFER_BINDING, &h->renderbuffer);
    for (int u = 0; GLEW_VERSION_4_2 && u < 8; ++u) {
        glGetIntegeri_v(GL_IMAGE_BINDING_NAME, (GLuint)u, &h->image[u]);
        glGetIntegeri_v(GL_IMAGE_BINDING_ACCESS, (GLuint)u, &h->image_access[u]);
        glGetIntegeri_v(GL_IMAGE_BINDING_FORMAT, (GLuint)u, &h->image_format[u]);
    }
}

static void compare(const host_bindings* a, const host_bindings* b, const char* when) {
#define SAME(field)                                                                                       \
    do {                                                                                                  \
        CHECK_EQ_INT(a->field, b->field);                                                                 \
        if (a->field != b->field) fprintf(stderr, "  host binding " #field " changed by %s\n", when);     \
    } while (0)
    SAME(draw_fbo);
    SAME(read_fbo);
    SAME(program);
    SAME(active_texture);
    for (int u = 0; u < 8; ++u) SAME(tex[u]);
    for (int k = 0; k < 4; ++k) SAME(viewport[k]);
    SAME(vao);
    SAME(array_buffer);
    SAME(pack_buffer);
    SAME(unpack_buffer);
    SAME(copy_read);
    SAME(copy_write);
    SAME(pack_alignment);
    SAME(renderbuffer);
    for (int u = 0; u < 8; ++u) {
        SAME(image[u]);
        SAME(image_access[u]);
        SAME(image_format[u]);
    }
#undef SAME
}

static GLuint make_buffer(GLenum target, size_t bytes) {
    GLuint b = 0;
    glGenBuffers(1, &b);
    glBindBuffer(target, b);
    glBufferData(target, (GLsizeiptr)bytes, NULL, GL_DYNAMIC_DRAW);
    return b;
}

static void test_host_current(void) {
    char err[512];
    wg_gl_context_desc hd;
    memset(&hd, 0, sizeof hd);
    wg_gl_context* host = NULL;
    CHECK_EQ_INT(wg_gl_context_create(&hd, &host, err, sizeof err), WEFT_OK);
    if (!host) return;
    /* the "host": this EGL context made current by hand, with bindings of its own */
    CHECK_EQ_INT(wg_gl_begin(host, err, sizeof err), WEFT_OK);
    GLuint fbo = 0, rbo = 0, vao = 0, tex[8];
    glGenRenderbuffers(1, &rbo);
    glBindRenderbuffer(GL_RENDERBUFFER, rbo);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, 8, 8);
    glGenFramebuffers(1, &fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, rbo);
    glGenVertexArrays(1, &vao);
    glBindVertexArray(vao);
    glGenTextures(8, tex);
    for (int u = 0; u < 8; ++u) {
        glActiveTexture(GL_TEXTURE0 + (GLenum)u);
        glBindTexture(GL_TEXTURE_2D, tex[u]);
        glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, 4, 4, 0, GL_RGBA, GL_UNSIGNED_BYTE, NULL);
        /* the host's images on the units the compute passes write (GL 4.2; not in test_api_gpu_gl33) */
        if (GLEW_VERSION_4_2) glBindImageTexture((GLuint)u, tex[u], 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA8);
    }
    glActiveTexture(GL_TEXTURE5);
    wg_program prog;
    memset(&prog, 0, sizeof prog);
    const char* fs = "#version 330 core\nout vec4 c;\nvoid main() { c = vec4(1.0); }\n";
    CHECK(wg_program_build(&prog, "host", wg_fullscreen_vs, fs, err, sizeof err));
    glUseProgram(prog.id);
    glViewport(3, 4, 50, 60);
    GLuint array_buf = make_buffer(GL_ARRAY_BUFFER, 64);
    GLuint pack_buf = make_buffer(GL_PIXEL_PACK_BUFFER, 64);
    GLuint copy_buf = make_buffer(GL_COPY_WRITE_BUFFER, 64);
    (void)array_buf, (void)copy_buf;
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    CHECK_EQ_INT(glGetError(), GL_NO_ERROR);
    host_bindings before, after;
    record(&before);

    weft_context* ctx = make_ctx(WEFT_BACKEND_GPU, WEFT_GL_HOST_CURRENT, WEFT_OK);
    (void)pack_buf;
    if (ctx) {
        record(&after);
        compare(&before, &after, "weft_context_create");
        ag_mesh m;
        ag_grid(&m, N, 1.0, 1.5, 0, 0);
        weft_cloth cloth = make_sheet(ctx, &m);
        record(&after);
        compare(&before, &after, "weft_cloth_create");
        CHECK(step(ctx, cloth, 5));
        record(&after);
        compare(&before, &after, "weft_cloth_step");

        /* write_gl_buffers into host buffers (positions at an offset, normals in another buffer) */
        size_t bytes = (size_t)m.nv * 3 * sizeof(float), off = 256;
        GLuint pos_buf = make_buffer(GL_COPY_READ_BUFFER, off + bytes);
        GLuint nrm_buf = make_buffer(GL_COPY_READ_BUFFER, bytes);
        glBindBuffer(GL_COPY_READ_BUFFER, (GLuint)before.copy_read);
        record(&before);
        weft_status st = weft_cloth_write_gl_buffers(ctx, cloth, WEFT_SPACE_WORLD, pos_buf, off, nrm_buf, 0);
        CHECK_EQ_INT(st, WEFT_OK);
        if (st != WEFT_OK) fprintf(stderr, "write_gl_buffers: %s\n", weft_context_last_error(ctx));
        record(&after);
        compare(&before, &after, "weft_cloth_write_gl_buffers");
        float* got_p = calloc((size_t)m.nv * 3, sizeof(float));
        float* got_n = calloc((size_t)m.nv * 3, sizeof(float));
        glBindBuffer(GL_COPY_READ_BUFFER, pos_buf);
        glGetBufferSubData(GL_COPY_READ_BUFFER, (GLintptr)off, (GLsizeiptr)bytes, got_p);
        glBindBuffer(GL_COPY_READ_BUFFER, nrm_buf);
        glGetBufferSubData(GL_COPY_READ_BUFFER, 0, (GLsizeiptr)bytes, got_n);
        glBindBuffer(GL_COPY_READ_BUFFER, (GLuint)before.copy_read);
        float* want_n = NULL;
        float* want_p = vertices(ctx, cloth, WEFT_SPACE_WORLD, &want_n);
        CHECK(memcmp(got_p, want_p, bytes) == 0);
        CHECK(memcmp(got_n, want_n, bytes) == 0);
        record(&after);
        compare(&before, &after, "weft_cloth_get_vertices");
        /* object space, positions only */
        CHECK_EQ_INT(weft_cloth_write_gl_buffers(ctx, cloth, WEFT_SPACE_OBJECT, pos_buf, 0, 0, 0), WEFT_OK);
        float* obj = vertices(ctx, cloth, WEFT_SPACE_OBJECT, NULL);
        glBindBuffer(GL_COPY_READ_BUFFER, pos_buf);
        glGetBufferSubData(GL_COPY_READ_BUFFER, 0, (GLsizeiptr)bytes, got_p);
        glBindBuffer(GL_COPY_READ_BUFFER, (GLuint)before.copy_read);
        CHECK(memcmp(got_p, obj, bytes) == 0);

        /* misuse: a name that is no buffer, a buffer too small, an offset past the end */
        CHECK_EQ_INT(weft_cloth_write_gl_buffers(ctx, cloth, WEFT_SPACE_WORLD, 987654u, 0, 0, 0),
                     WEFT_ERROR_INVALID_ARGUMENT);
        CHECK(strstr(weft_context_last_error(ctx), "987654") != NULL);
        CHECK_EQ_INT(weft_cloth_write_gl_buffers(ctx, cloth, WEFT_SPACE_WORLD, nrm_buf, 4, 0, 0),
                     WEFT_ERROR_INVALID_ARGUMENT);
        CHECK(strstr(weft_context_last_error(ctx), "bytes") != NULL);
        CHECK_EQ_INT(weft_cloth_write_gl_buffers(ctx, cloth, WEFT_SPACE_WORLD, 0, 0, pos_buf, off + bytes),
                     WEFT_ERROR_INVALID_ARGUMENT);
        CHECK_EQ_INT(weft_cloth_write_gl_buffers(ctx, cloth, (weft_space)7, pos_buf, 0, 0, 0),
                     WEFT_ERROR_INVALID_ARGUMENT);
        CHECK_EQ_INT(weft_cloth_write_gl_buffers(ctx, cloth, WEFT_SPACE_WORLD, pos_buf, 0, pos_buf, 12),
                     WEFT_ERROR_INVALID_ARGUMENT);
        record(&after);
        compare(&before, &after, "the refused calls");
        CHECK_EQ_INT(glGetError(), GL_NO_ERROR);

        /* a snapshot round trip in host mode */
        weft_cloth_info info;
        CHECK_EQ_INT(weft_cloth_get_info(ctx, cloth, &info), WEFT_OK);
        unsigned char* snap = malloc(info.snapshot_size);
        CHECK_EQ_INT(weft_cloth_save(ctx, cloth, snap, info.snapshot_size), WEFT_OK);
        CHECK_EQ_INT(weft_cloth_restore(ctx, cloth, snap, info.snapshot_size), WEFT_OK);
        record(&after);
        compare(&before, &after, "weft_cloth_save/restore");
        free(snap);

        free(got_p), free(got_n), free(want_p), free(want_n), free(obj);
        GLuint bufs[2] = {pos_buf, nrm_buf};
        glDeleteBuffers(2, bufs);
        weft_context_destroy(ctx);   /* the host's context is current: GL objects deleted */
        record(&after);
        compare(&before, &after, "weft_context_destroy");
        ag_free(&m);
    }
    wg_program_destroy(&prog);
    wg_gl_end(host);
    wg_gl_context_destroy(host);
}

static void test_misuse(void) {
    ag_mesh m;
    ag_grid(&m, N, 1.0, 1.5, 0, 0);
    /* a CPU cloth */
    weft_context* cpu = make_ctx(WEFT_BACKEND_CPU, WEFT_GL_HEADLESS, WEFT_OK);
    weft_cloth cc = make_sheet(cpu, &m);
    CHECK_EQ_INT(weft_cloth_write_gl_buffers(cpu, cc, WEFT_SPACE_WORLD, 1, 0, 0, 0), WEFT_ERROR_UNSUPPORTED);
    CHECK(strstr(weft_context_last_error(cpu), "CPU backend") != NULL);
    weft_cloth bad = {cc.id ^ 1};
    CHECK_EQ_INT(weft_cloth_write_gl_buffers(cpu, bad, WEFT_SPACE_WORLD, 1, 0, 0, 0), WEFT_ERROR_INVALID_HANDLE);
    CHECK_EQ_INT(weft_cloth_write_gl_buffers(NULL, cc, WEFT_SPACE_WORLD, 1, 0, 0, 0), WEFT_ERROR_INVALID_ARGUMENT);
    weft_context_destroy(cpu);
    /* a GPU cloth of a headless context: its GL context is not the host's */
    weft_context* gpu = make_ctx(WEFT_BACKEND_GPU, WEFT_GL_HEADLESS, WEFT_OK);
    if (gpu) {
        weft_cloth gc = make_sheet(gpu, &m);
        CHECK_EQ_INT(weft_cloth_write_gl_buffers(gpu, gc, WEFT_SPACE_WORLD, 1, 0, 0, 0), WEFT_ERROR_UNSUPPORTED);
        CHECK(strstr(weft_context_last_error(gpu), "HEADLESS") != NULL);
        /* weft_render on a GPU cloth shares the context's GL context */
        unsigned char* img = malloc(64 * 48 * 4);
        weft_render_def rd = weft_default_render_def();
        rd.width = 64;
        rd.height = 48;
        rd.rgba = img;
        rd.eye[2] = 3.0f;
        rd.target[1] = 1.0f;
        CHECK_EQ_INT(weft_render(gpu, gc, &rd), WEFT_OK);
        CHECK(step(gpu, gc, 1));
        free(img);
        weft_context_destroy(gpu);
    }
    ag_free(&m);
}

int main(void) {
    RUN_TEST(test_backend_choice);
    RUN_TEST(test_direct_refused);
    RUN_TEST(test_gpu_close_to_cpu);
    RUN_TEST(test_inertia_and_reset);
    RUN_TEST(test_snapshot_round_trip);
    RUN_TEST(test_two_contexts);
    RUN_TEST(test_host_current);
    RUN_TEST(test_misuse);
    return TEST_SUMMARY();
}
