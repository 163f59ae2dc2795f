/* The object transform and moving colliders through the public API: inertia (linear 0: an
 * accelerating object = a resting one in object space; angular 0: a spinning object = a resting
 * one), default inertia (the object transform changes nothing, bit-exact), teleport (a 1 km jump
 * with a quarter turn changes nothing in object space), reset (= a fresh cloth at that
 * transform), a sphere moved through transforms (no particle inside its shell).
 *
 * Transforms are built so that every float product the host would form is exact (dyadic
 * translations, rotations about Y with the axis row exactly (0, 1, 0)): differences then come
 * from the simulation alone, and positions are compared in double (read from a snapshot). */
#include <stdint.h>
#include "api_grid.h"
#include "check.h"

#define N 8
#define SIZE 0.5
#define DT (1.0 / 64.0)

typedef struct rig {
    weft_context* ctx;
    weft_cloth cloth;
    int np, nv;
    size_t snap_size;
    unsigned char* snap;
    double* x;        /* (np x 3) world positions after rig_read */
} rig;

static void rig_open(rig* r, const weft_cloth_def* def) {
    memset(r, 0, sizeof *r);
    weft_context_def cd = weft_default_context_def();
    cd.threads = 1;
    CHECK_EQ_INT(weft_context_create(WEFT_ABI, &cd, &r->ctx), WEFT_OK);
    weft_status st = weft_cloth_create(r->ctx, def, &r->cloth);
    if (st != WEFT_OK) fprintf(stderr, "create: %s\n", weft_context_last_error(r->ctx));
    CHECK_EQ_INT(st, WEFT_OK);
    weft_cloth_info info;
    CHECK_EQ_INT(weft_cloth_get_info(r->ctx, r->cloth, &info), WEFT_OK);
    r->np = info.n_particles;
    r->nv = info.n_vertices;
    r->snap_size = info.snapshot_size;
    r->snap = malloc(r->snap_size);
    r->x = malloc(sizeof(double) * 3 * (size_t)r->np);
}

static void rig_read(rig* r) {
    CHECK_EQ_INT(weft_cloth_save(r->ctx, r->cloth, r->snap, r->snap_size), WEFT_OK);
    ag_snapshot_positions(r->snap, r->np, r->x);
}

static void rig_close(rig* r) {
    weft_context_destroy(r->ctx);
    free(r->snap);
    free(r->x);
}

static weft_status rig_step(rig* r, const float* object, const float* bones, const float* colliders, uint32_t flags,
                            weft_frame_stats* stats) {
    weft_frame fr = weft_default_frame();
    fr.dt = DT;
    fr.object_transform = object;
    fr.attachment_transforms = bones;
    fr.collider_transforms = colliders;
    fr.flags = flags;
    weft_status st = weft_cloth_step(r->ctx, r->cloth, &fr, stats);
    if (st != WEFT_OK) fprintf(stderr, "step: %s\n", weft_context_last_error(r->ctx));
    return st;
}

/* A value on the 2^-12 grid (exact in float next to anything below 2^11). */
static double dyadic(double v) { return round(v * 4096.0) / 4096.0; }

/* rotation about Y by (float) cos/sin, then translation */
static void rot_y(float* m, float c, float s, double tx, double ty, double tz) {
    ag_identity(m);
    m[0] = c;
    m[8] = s;
    m[2] = -s;
    m[10] = c;
    m[12] = (float)tx;
    m[13] = (float)ty;
    m[14] = (float)tz;
}

/* p' = T^-1 p for the (rigid, float) transform T, in double */
static void inverse_apply(const float* T, const double* p, double* out) {
    double R[9], d[3];
    for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 3; ++c) R[3 * r + c] = T[4 * c + r];
        d[r] = p[r] - T[12 + r];
    }
    double c0 = R[4] * R[8] - R[5] * R[7], c1 = R[5] * R[6] - R[3] * R[8], c2 = R[3] * R[7] - R[4] * R[6];
    double det = R[0] * c0 + R[1] * c1 + R[2] * c2;
    double I[9] = {c0 / det, (R[2] * R[7] - R[1] * R[8]) / det, (R[1] * R[5] - R[2] * R[4]) / det,
                   c1 / det, (R[0] * R[8] - R[2] * R[6]) / det, (R[2] * R[3] - R[0] * R[5]) / det,
                   c2 / det, (R[1] * R[6] - R[0] * R[7]) / det, (R[0] * R[4] - R[1] * R[3]) / det};
    for (int r = 0; r < 3; ++r) out[r] = I[3 * r] * d[0] + I[3 * r + 1] * d[1] + I[3 * r + 2] * d[2];
}

/* max over particles of |T^-1 xa - xb| */
static double object_gap(const rig* a, const float* Ta, const rig* b) {
    double worst = 0.0;
    for (int i = 0; i < a->np; ++i) {
        double p[3];
        inverse_apply(Ta, a->x + 3 * i, p);
        for (int k = 0; k < 3; ++k) worst = fmax(worst, fabs(p[k] - b->x[3 * i + k]));
    }
    return worst;
}

/* hanging sheet, top row pinned to one attachment bound at the identity */
static int g_top[N];
static weft_attachment_def g_att;
static ag_mesh g_mesh;

static weft_cloth_def sheet_def(void) {
    for (int i = 0; i < N; ++i) g_top[i] = i + N * (N - 1);
    g_att = weft_default_attachment_def();
    g_att.vertices = g_top;
    g_att.n_vertices = N;
    weft_cloth_def def = weft_default_cloth_def();
    def.mesh = ag_desc(&g_mesh);
    def.n_attachments = 1;
    def.attachments = &g_att;
    return def;
}

/* linear_inertia = 0: an accelerating object carries the cloth as if it were at rest. */
static void test_linear_inertia(void) {
    double gaps[2];
    for (int variant = 0; variant < 2; ++variant) {
        weft_cloth_def def = sheet_def();
        def.air_drag_normal = def.air_drag_tangent = 0.0;   /* air would see the object's speed */
        def.linear_inertia = variant == 0 ? 0.0 : 1.0;
        rig a, b;
        rig_open(&a, &def);
        rig_open(&b, &def);
        double worst = 0.0;
        for (int f = 1; f <= 64; ++f) {
            double t = f * DT;
            /* at rest during frame 1, then accelerating at 2 m/s^2 along x and -1 along y */
            double px = (double)(f - 1) * (f - 1) / 4096.0, py = -(double)(f - 1) * (f - 1) / 8192.0;
            double lx = dyadic(0.04 * sin(6 * t)), lz = dyadic(0.05 * sin(9 * t));
            float obj[16], bone_a[16], bone_b[16];
            rot_y(obj, 1.0f, 0.0f, px, py, 0.0);
            rot_y(bone_a, 1.0f, 0.0f, px + lx, py, lz);
            rot_y(bone_b, 1.0f, 0.0f, lx, 0.0, lz);
            CHECK_EQ_INT(rig_step(&a, obj, bone_a, NULL, 0, NULL), WEFT_OK);
            CHECK_EQ_INT(rig_step(&b, NULL, bone_b, NULL, 0, NULL), WEFT_OK);
            rig_read(&a);
            rig_read(&b);
            worst = fmax(worst, object_gap(&a, obj, &b));
        }
        gaps[variant] = worst / SIZE;
        rig_close(&a);
        rig_close(&b);
    }
    printf("  linear inertia 0: object-space gap %.3g (relative); inertia 1 (control): %.3g\n", gaps[0], gaps[1]);
    CHECK(gaps[0] <= 1e-9);
    CHECK(gaps[1] > 1e-3);   /* the physical setting does feel the acceleration */
}

/* angular_inertia = 0 (gravity and air off): a spinning object carries the cloth as if at rest.
 * Variants: 0 a smooth spin (float matrices: cos^2 + sin^2 is 1 only to ~6e-8, so the carried
 * frame is that far from rigid and the gap is bounded by float precision), 1 the same spin with
 * angular_inertia 1 (control: the cloth must feel it), 2 irregular quarter turns (matrices of
 * 0 and +-1, exactly rigid: the gap is round-off). */
static void test_angular_inertia(void) {
    double gaps[3];
    static const float qc[4] = {1, 0, -1, 0}, qs[4] = {0, 1, 0, -1};
    for (int variant = 0; variant < 3; ++variant) {
        weft_cloth_def def = sheet_def();
        def.gravity[1] = 0.0;
        def.air_drag_normal = def.air_drag_tangent = 0.0;
        def.angular_inertia = variant == 1 ? 1.0 : 0.0;
        rig a, b;
        rig_open(&a, &def);
        rig_open(&b, &def);
        double worst = 0.0;
        for (int f = 1; f <= 64; ++f) {
            double t = f * DT, angle = 3.0 * t * t;   /* spinning up about Y */
            float c = (float)cos(angle), s = (float)sin(angle);
            if (variant == 2) {
                int q = (f * (f + 1) / 2) % 4;
                c = qc[q];
                s = qs[q];
            }
            double ly = dyadic(0.03 * sin(11 * t));   /* the pinned edge bounces along the spin axis */
            float obj[16], bone_a[16], bone_b[16];
            rot_y(obj, c, s, 0.0, 0.0, 0.0);
            rot_y(bone_a, c, s, 0.0, ly, 0.0);
            rot_y(bone_b, 1.0f, 0.0f, 0.0, ly, 0.0);
            CHECK_EQ_INT(rig_step(&a, obj, bone_a, NULL, 0, NULL), WEFT_OK);
            CHECK_EQ_INT(rig_step(&b, NULL, bone_b, NULL, 0, NULL), WEFT_OK);
            rig_read(&a);
            rig_read(&b);
            worst = fmax(worst, object_gap(&a, obj, &b));
        }
        gaps[variant] = worst / SIZE;
        rig_close(&a);
        rig_close(&b);
    }
    printf("  angular inertia 0: object-space gap %.3g (relative; smooth float spin), %.3g (quarter turns); "
           "inertia 1 (control): %.3g\n", gaps[0], gaps[2], gaps[1]);
    CHECK(gaps[0] <= 1e-6);
    CHECK(gaps[2] <= 1e-9);
    CHECK(gaps[1] > 1e-3);
}

/* Default inertia: the object transform does not touch the simulation (world space, bit-exact). */
static void test_default_inertia_ignores_object(void) {
    weft_cloth_def def = sheet_def();
    rig a, b;
    rig_open(&a, &def);
    rig_open(&b, &def);
    int same = 1;
    for (int f = 1; f <= 40; ++f) {
        double t = f * DT;
        float obj[16], bone[16];
        ag_transform(obj, 0.0, 0.6, 0.8, 2.0 * t * t, 3.0 * t, -t * t, 0.5 * sin(7 * t));
        ag_transform(bone, 0.0, 1.0, 0.0, 0.2 * sin(3 * t), 0.05 * sin(5 * t), 0.0, 0.0);
        CHECK_EQ_INT(rig_step(&a, obj, bone, NULL, 0, NULL), WEFT_OK);
        CHECK_EQ_INT(rig_step(&b, NULL, bone, NULL, 0, NULL), WEFT_OK);
        rig_read(&a);
        rig_read(&b);
        same = same && memcmp(a.x, b.x, sizeof(double) * 3 * (size_t)a.np) == 0;
    }
    CHECK(same);
    rig_close(&a);
    rig_close(&b);
}

/* Teleport by 1 km and a quarter turn about Y (object and bone jump together): in object space
 * the run equals the one without the jump. */
static void test_teleport(void) {
    weft_cloth_def def = sheet_def();
    rig a, b;
    rig_open(&a, &def);
    rig_open(&b, &def);
    float* pa = malloc(sizeof(float) * 3 * (size_t)a.nv);
    float* pb = malloc(sizeof(float) * 3 * (size_t)a.nv);
    double worst = 0.0, far_x = 0.0;
    for (int f = 1; f <= 50; ++f) {
        double t = f * DT;
        double lx = dyadic(0.04 * sin(6 * t)), lz = dyadic(0.05 * sin(9 * t));
        float bone_b[16], obj_a[16], bone_a[16];
        rot_y(bone_b, 1.0f, 0.0f, lx, 0.0, lz);
        int jumped = f >= 20;
        if (jumped) {   /* J = quarter turn about Y, then (1000, 0, -500): J l = (lz, 0, -lx) + t_J */
            rot_y(obj_a, 0.0f, 1.0f, 1000.0, 0.0, -500.0);
            rot_y(bone_a, 0.0f, 1.0f, 1000.0 + lz, 0.0, -500.0 - lx);
        } else {
            rot_y(obj_a, 1.0f, 0.0f, 0.0, 0.0, 0.0);
            memcpy(bone_a, bone_b, sizeof bone_a);
        }
        CHECK_EQ_INT(rig_step(&a, obj_a, bone_a, NULL, f == 20 ? WEFT_FRAME_TELEPORT : 0, NULL), WEFT_OK);
        CHECK_EQ_INT(rig_step(&b, NULL, bone_b, NULL, 0, NULL), WEFT_OK);
        int n;
        CHECK_EQ_INT(weft_cloth_get_vertices(a.ctx, a.cloth, WEFT_SPACE_OBJECT, pa, NULL, a.nv, &n), WEFT_OK);
        CHECK_EQ_INT(weft_cloth_get_vertices(b.ctx, b.cloth, WEFT_SPACE_OBJECT, pb, NULL, b.nv, &n), WEFT_OK);
        for (int i = 0; i < 3 * a.nv; ++i) worst = fmax(worst, fabs((double)pa[i] - pb[i]));
        if (f == 50) {
            CHECK_EQ_INT(weft_cloth_get_vertices(a.ctx, a.cloth, WEFT_SPACE_WORLD, pa, NULL, a.nv, &n), WEFT_OK);
            far_x = pa[0];
        }
    }
    printf("  teleport: object-space gap %.3g m, world x after the jump %.1f m\n", worst, far_x);
    CHECK(worst <= 1e-6 * SIZE);
    CHECK(fabs(far_x - 1000.0) < 1.0);
    free(pa);
    free(pb);
    rig_close(&a);
    rig_close(&b);
}

/* RESET at a new object transform = a fresh cloth created there; counters restart. */
static void test_reset(void) {
    float T[16];
    rot_y(T, 0.0f, 1.0f, 2.0, 0.5, 1.0);
    weft_cloth_def def = sheet_def();
    rig a, b;
    rig_open(&a, &def);
    memcpy(g_att.bind_transform, T, sizeof T);
    memcpy(def.transform, T, sizeof T);
    rig_open(&b, &def);
    for (int f = 1; f <= 30; ++f) {
        float bone[16];
        rot_y(bone, 1.0f, 0.0f, 0.1 * sin(8 * f * DT), 0.0, 0.1 * f * DT);
        CHECK_EQ_INT(rig_step(&a, NULL, bone, NULL, 0, NULL), WEFT_OK);
    }
    weft_frame_stats sa, sb;
    CHECK_EQ_INT(rig_step(&a, T, T, NULL, WEFT_FRAME_RESET, &sa), WEFT_OK);
    CHECK_EQ_INT(rig_step(&b, NULL, T, NULL, 0, &sb), WEFT_OK);
    CHECK_EQ_INT(sa.frame, 1);
    CHECK_NEAR(sa.time, DT, 1e-15);
    rig_read(&a);
    rig_read(&b);
    double worst = 0.0;
    for (int i = 0; i < 3 * a.np; ++i) worst = fmax(worst, fabs(a.x[i] - b.x[i]));
    /* and in object space, one frame from rest: within the frame's sag of the host mesh */
    float* p = malloc(sizeof(float) * 3 * (size_t)a.nv);
    int n;
    CHECK_EQ_INT(weft_cloth_get_vertices(a.ctx, a.cloth, WEFT_SPACE_OBJECT, p, NULL, a.nv, &n), WEFT_OK);
    double from_rest = 0.0;
    for (int i = 0; i < 3 * a.nv; ++i) from_rest = fmax(from_rest, fabs((double)p[i] - g_mesh.pos[i]));
    printf("  reset: gap to a fresh cloth %.3g m; %.3g m from the rest shape after one frame\n", worst, from_rest);
    CHECK(worst <= 1e-12);
    CHECK(from_rest < 9.81 * DT * DT);
    free(p);
    rig_close(&a);
    rig_close(&b);
}

/* A sphere pushed up through a horizontal sheet pinned at its corners, moved by transforms. */
static void test_moving_sphere(void) {
    ag_mesh m;
    ag_grid(&m, 13, 1.0, 0.0, 0, 0);   /* odd: a vertex at the centre, over the sphere's apex */
    int corners[4] = {0, 12, 12 * 13, 13 * 13 - 1};
    weft_attachment_def att = weft_default_attachment_def();
    att.vertices = corners;
    att.n_vertices = 4;
    weft_collider_def col = weft_default_collider_def();
    col.radius = 0.2;
    col.thickness = 0.005;
    rot_y(col.transform, 1.0f, 0.0f, 0.0, -0.5, 0.0);
    weft_cloth_def def = weft_default_cloth_def();
    def.mesh = ag_desc(&m);
    def.n_attachments = 1;
    def.attachments = &att;
    def.n_colliders = 1;
    def.colliders = &col;
    rig r;
    rig_open(&r, &def);
    float* p = malloc(sizeof(float) * 3 * (size_t)r.nv);
    double worst = 1e9, top = -1e9;
    int contacts = 0;
    for (int f = 1; f <= 64; ++f) {
        double cy = fmin(-0.5 + 1.5 * f * DT, 0.15);
        float T[16];
        rot_y(T, 1.0f, 0.0f, 0.0, cy, 0.0);
        weft_frame_stats st;
        CHECK_EQ_INT(rig_step(&r, NULL, NULL, T, 0, &st), WEFT_OK);
        if (st.contacts > contacts) contacts = st.contacts;
        int n;
        CHECK_EQ_INT(weft_cloth_get_vertices(r.ctx, r.cloth, WEFT_SPACE_WORLD, p, NULL, r.nv, &n), WEFT_OK);
        for (int v = 0; v < r.nv; ++v) {
            double d = sqrt(p[3 * v] * p[3 * v] + (p[3 * v + 1] - cy) * (p[3 * v + 1] - cy) + p[3 * v + 2] * p[3 * v + 2]);
            worst = fmin(worst, d);
            top = fmax(top, p[3 * v + 1]);
        }
    }
    printf("  moving sphere: closest vertex %.5f m from the centre (shell %.3f), top %.3f m, %d contacts\n", worst,
           0.205, top, contacts);
    CHECK(worst >= 0.205 - 1e-5);
    CHECK(top > 0.15 + 0.2 - 0.01);
    CHECK(contacts > 0);
    free(p);
    rig_close(&r);
    ag_free(&m);
}

int main(void) {
    ag_grid(&g_mesh, N, SIZE, 1.0, 1, 0);
    RUN_TEST(test_linear_inertia);
    RUN_TEST(test_angular_inertia);
    RUN_TEST(test_default_inertia_ignores_object);
    RUN_TEST(test_teleport);
    RUN_TEST(test_reset);
    RUN_TEST(test_moving_sphere);
    ag_free(&g_mesh);
    return TEST_SUMMARY();
}
