/* The engine-loop example (host_glue/examples/engine_loop.c) run as a user runs it: 120 frames
 * at 60 Hz of a character walking in a circle with the poncho pinned to its shoulder bones.
 * From its OBJ frames and its --report JSON (the transforms the engine passed), independently of
 * the example's code:
 *  - the pinned vertices, re-selected here from the rest OBJ by position (top row, 0.09 m < |x|
 *    < 0.21 m), are the ones the example pinned, and at every written frame each is at its
 *    shoulder bone's transform x its bind-local position (inverse bind transform x rest), to
 *    1e-4 m: the cloth follows the moving bone;
 *  - the bones really moved (the walk and the turn) and the shoulders bobbed out of phase;
 *  - the garment travelled with the root (centroid near the root's vertical axis), stayed above
 *    the ground and outside the capsules and the sphere (less 5 mm), and holds no NaN;
 *  - the PNGs exist, decode, have the requested size and show the garment.
 * Failure paths: a bad --library path, a library of another ABI, a missing mesh and a bad option
 * each give the loader's or the library's message and a non-zero exit.
 * And libweft.so stays mapped after weft_loader_close (it is linked -z nodelete): unloading it
 * unloaded libgomp under its live worker threads, and the example crashed at exit. */
#define _POSIX_C_SOURCE 200809L
#include <cjson/cJSON.h>
#include <dlfcn.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#ifdef ENGINE_LOOP_PNG
#include <png.h>
#endif

#include "check.h"
#include "weft_loader.h"

#define FRAMES 120
#define OBJ_EVERY 10
#define PNG_EVERY 60
#define IMAGE_W 160   /* PNG size asked for */
#define IMAGE_H 120
#define PIN_TOL 1e-4            /* m */
#define PENETRATION_TOL 0.005   /* m inside a collider's surface still accepted */

static char out_dir[1024];

/* ---- running the example ---- */

typedef struct run_result {
    int rc;
    char* out;                  /* stdout, stderr: malloc'd, "" when empty */
    char* err;
} run_result;

static char* read_file(const char* path, long* size) {
    FILE* f = fopen(path, "rb");
    if (!f) return NULL;
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    char* buf = malloc((size_t)n + 1);
    if (buf && fread(buf, 1, (size_t)n, f) != (size_t)n) {
        free(buf);
        buf = NULL;
    }
    fclose(f);
    if (buf) buf[n] = '\0';
    if (size) *size = n;
    return buf;
}

static void run_example(const char* args, run_result* r) {
    char cmd[4096], out_path[1100], err_path[1100];
    snprintf(out_path, sizeof out_path, "%s.stdout", out_dir);
    snprintf(err_path, sizeof err_path, "%s.stderr", out_dir);
    snprintf(cmd, sizeof cmd, "'%s' %s > '%s' 2> '%s'", ENGINE_LOOP, args, out_path, err_path);
    int status = system(cmd);
    r->rc = status != -1 && WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    r->out = read_file(out_path, NULL);
    r->err = read_file(err_path, NULL);
    if (!r->out) r->out = calloc(1, 1);
    if (!r->err) r->err = calloc(1, 1);
}

static void free_run(run_result* r) {
    free(r->out);
    free(r->err);
}

/* ---- OBJ and JSON ---- */

/* Vertex positions ("v x y z") of an OBJ: returns the count, fills *pos (malloc'd). */
static int read_obj(const char* path, double** pos) {
    char* text = read_file(path, NULL);
    *pos = NULL;
    if (!text) return -1;
    int n = 0, cap = 4096;
    double* p = malloc(sizeof(double) * 3 * (size_t)cap);
    for (char* line = strtok(text, "\n"); line; line = strtok(NULL, "\n")) {
        if (line[0] != 'v' || line[1] != ' ') continue;
        if (n == cap) {
            cap *= 2;
            p = realloc(p, sizeof(double) * 3 * (size_t)cap);
        }
        double* q = p + 3 * n;
        /* strtod reads "nan" too: NaN is checked, not hidden */
        char* s = line + 2;
        for (int k = 0; k < 3; ++k) q[k] = strtod(s, &s);
        ++n;
    }
    free(text);
    *pos = p;
    return n;
}

static int json_matrix(const cJSON* a, double m[16]) {
    if (!cJSON_IsArray(a) || cJSON_GetArraySize(a) != 16) return 0;
    for (int i = 0; i < 16; ++i) {
        const cJSON* x = cJSON_GetArrayItem(a, i);
        if (!cJSON_IsNumber(x)) return 0;
        m[i] = x->valuedouble;
    }
    return 1;
}

/* ---- rigid transforms, column-major (row r, column c at m[4c + r]) ---- */

static void apply(const double m[16], const double p[3], double out[3]) {
    for (int r = 0; r < 3; ++r) out[r] = m[r] * p[0] + m[4 + r] * p[1] + m[8 + r] * p[2] + m[12 + r];
}

/* p in m's frame: R^T (p - t) */
static void apply_inverse(const double m[16], const double p[3], double out[3]) {
    double d[3] = {p[0] - m[12], p[1] - m[13], p[2] - m[14]};
    for (int c = 0; c < 3; ++c) out[c] = m[4 * c] * d[0] + m[4 * c + 1] * d[1] + m[4 * c + 2] * d[2];
}

static double dist3(const double* a, const double* b) {
    return sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
                (a[2] - b[2]) * (a[2] - b[2]));
}

/* Heading (rotation about +Y) of a rigid transform: where its local +Z points. */
static double heading(const double m[16]) { return atan2(m[8], m[10]); }

/* Distance from p to the surface of a sphere or capsule (negative inside), local axis Y. */
static double shape_distance(const char* type, double radius, double half_height, const double m[16],
                             const double* p) {
    double q[3];
    apply_inverse(m, p, q);
    if (strcmp(type, "capsule") == 0) q[1] -= fmax(-half_height, fmin(half_height, q[1]));
    return sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2]) - radius;
}

/* ---- the main run ---- */

typedef struct pins {
    int n[2];
    int* v[2];
    double bind[2][16];
} pins;

static int contains(const int* a, int n, int x) {
    for (int i = 0; i < n; ++i)
        if (a[i] == x) return 1;
    return 0;
}

/* The shoulder vertices chosen here from the rest shape (world = root space at frame 0). */
static void check_pin_selection(const double* rest, int nv, const pins* p) {
    double top = -INFINITY;
    for (int i = 0; i < nv; ++i) top = fmax(top, rest[3 * i + 1]);
    CHECK_NEAR(top, 1.54, 1e-4);   /* the poncho's fold, sample_scenes/make_poncho.py */
    int count[2] = {0, 0}, hosts[2] = {0, 0};
    unsigned columns[2] = {0, 0};   /* bit c: a vertex at |x| = 10 + 2.5 c cm */
    for (int i = 0; i < nv; ++i) {
        double x = rest[3 * i];
        if (rest[3 * i + 1] < top - 1e-4 || fabs(x) <= 0.09 || fabs(x) >= 0.21) continue;
        int side = x > 0 ? 0 : 1;
        ++hosts[side];
        columns[side] |= 1u << (int)lround((fabs(x) - 0.10) / 0.025);
        CHECK(contains(p->v[side], p->n[side], i));
    }
    for (int s = 0; s < 2; ++s)
        for (unsigned c = columns[s]; c; c >>= 1) count[s] += (int)(c & 1u);
    /* 2.5 cm columns: |x| = 10, 12.5, 15, 17.5, 20 cm on each side (the FBX's control points:
     * several polygon corners at each, every one of them pinned) */
    CHECK_EQ_INT(count[0], 5);
    CHECK_EQ_INT(count[1], 5);
    CHECK_EQ_INT(p->n[0], hosts[0]);
    CHECK_EQ_INT(p->n[1], hosts[1]);
}

#ifdef ENGINE_LOOP_PNG
static void check_png(const char* path) {
    png_image img;
    memset(&img, 0, sizeof img);
    img.version = PNG_IMAGE_VERSION;
    int ok = png_image_begin_read_from_file(&img, path) != 0;
    CHECK(ok);
    if (!ok) {
        fprintf(stderr, "%s: %s\n", path, img.message);
        return;
    }
    CHECK_EQ_INT(img.width, IMAGE_W);
    CHECK_EQ_INT(img.height, IMAGE_H);
    img.format = PNG_FORMAT_RGB;
    unsigned char* px = malloc(PNG_IMAGE_SIZE(img));
    CHECK(px && png_image_finish_read(&img, NULL, px, 0, NULL) != 0);
    /* the garment is drawn in warm colours (front yellow, back red), unlike the grey character,
     * the grey floor and the blue sky: some of it must be in the middle third of the picture */
    int warm = 0, total = 0;
    for (unsigned y = 0; y < img.height; ++y)
        for (unsigned x = img.width / 3; x < 2 * img.width / 3; ++x, ++total) {
            const unsigned char* q = px + 3 * ((size_t)y * img.width + x);
            warm += q[0] > q[2] + 60;
        }
    printf("%s: %d of %d middle pixels show the garment\n", path, warm, total);
    CHECK(warm > total / 10);
    free(px);
    png_image_free(&img);
}
#endif

static void test_walk(void) {
    char args[4096], report_path[1100];
    snprintf(report_path, sizeof report_path, "%s/report.json", out_dir);
    snprintf(args, sizeof args,
             "--frames %d --obj-every %d --png-every %d --png-size %dx%d --out '%s' --report '%s' "
             "--quiet",
             FRAMES, OBJ_EVERY, PNG_EVERY, IMAGE_W, IMAGE_H, out_dir, report_path);
    run_result r;
    run_example(args, &r);
    printf("%s", r.out);
    if (r.rc != 0) fprintf(stderr, "engine_loop exited %d:\n%s\n", r.rc, r.err);
    CHECK_EQ_INT(r.rc, 0);
    CHECK(strstr(r.out, "engine_loop: 120 frames at 60 Hz") != NULL);
    CHECK(strstr(r.out, "step: median") != NULL);
#ifndef ENGINE_LOOP_PNG
    CHECK(strstr(r.err, "no PNGs") != NULL);   /* a library without gpu/: said, and goes on */
#endif
    free_run(&r);

    char* text = read_file(report_path, NULL);
    cJSON* rep = text ? cJSON_Parse(text) : NULL;
    free(text);
    CHECK(rep != NULL);
    if (!rep) return;
    const cJSON* recs = cJSON_GetObjectItem(rep, "frame_records");
    const cJSON* atts = cJSON_GetObjectItem(rep, "attachments");
    const cJSON* cols = cJSON_GetObjectItem(rep, "colliders");
    const cJSON* summary = cJSON_GetObjectItem(rep, "summary");
    CHECK_EQ_INT(cJSON_GetArraySize(recs), FRAMES + 1);
    CHECK_EQ_INT(cJSON_GetArraySize(atts), 2);
    CHECK(cJSON_GetArraySize(cols) >= 5);
    CHECK(summary != NULL);
    if (cJSON_GetArraySize(recs) != FRAMES + 1 || cJSON_GetArraySize(atts) != 2 || !summary) {
        cJSON_Delete(rep);
        return;
    }
    CHECK_EQ_INT(cJSON_GetObjectItem(summary, "frames_run")->valueint, FRAMES);
    CHECK_EQ_INT(cJSON_GetObjectItem(summary, "failed_steps")->valueint, 0);

    pins p;
    memset(&p, 0, sizeof p);
    for (int s = 0; s < 2; ++s) {
        const cJSON* a = cJSON_GetArrayItem(atts, s);
        const cJSON* vs = cJSON_GetObjectItem(a, "vertices");
        CHECK(json_matrix(cJSON_GetObjectItem(a, "bind_transform"), p.bind[s]));
        p.n[s] = cJSON_GetArraySize(vs);
        p.v[s] = calloc((size_t)p.n[s] + 1, sizeof(int));
        for (int i = 0; i < p.n[s]; ++i) p.v[s][i] = cJSON_GetArrayItem(vs, i)->valueint;
    }

    char path[1200];
    double* rest = NULL;
    snprintf(path, sizeof path, "%s/frame_0000.obj", out_dir);
    int nv = read_obj(path, &rest);
    CHECK_EQ_INT(nv, cJSON_GetObjectItem(rep, "n_vertices")->valueint);
    if (nv <= 0) {
        cJSON_Delete(rep);
        return;
    }
    check_pin_selection(rest, nv, &p);

    /* bind-local position of each pinned vertex: inverse bind transform x rest (world) */
    double* local[2];
    for (int s = 0; s < 2; ++s) {
        local[s] = malloc(sizeof(double) * 3 * ((size_t)p.n[s] + 1));
        for (int i = 0; i < p.n[s]; ++i) apply_inverse(p.bind[s], rest + 3 * p.v[s][i], local[s] + 3 * i);
    }

    double root0[16], root_end[16], sh0[2][16], sh_end[2][16];
    double worst_pin = 0.0, worst_penetration = INFINITY, worst_centroid = 0.0, lowest = INFINITY;
    double bob_min = INFINITY, bob_max = -INFINITY, centroid0[3] = {0, 0, 0};
    double centroid_end[3] = {0, 0, 0};
    int checked = 0, nonfinite = 0, pngs = 0;
    for (int f = 0; f <= FRAMES; ++f) {
        const cJSON* rec = cJSON_GetArrayItem(recs, f);
        double root[16], sh[2][16];
        CHECK_EQ_INT(cJSON_GetObjectItem(rec, "frame")->valueint, f);
        CHECK(json_matrix(cJSON_GetObjectItem(rec, "root"), root));
        const cJSON* ra = cJSON_GetObjectItem(rec, "attachments");
        for (int s = 0; s < 2; ++s) CHECK(json_matrix(cJSON_GetArrayItem(ra, s), sh[s]));
        if (f == 0) {
            memcpy(root0, root, sizeof root0);
            memcpy(sh0, sh, sizeof sh0);
            for (int s = 0; s < 2; ++s)
                for (int i = 0; i < 16; ++i) CHECK_NEAR(sh[s][i], p.bind[s][i], 1e-6);
        }
        memcpy(root_end, root, sizeof root_end);
        memcpy(sh_end, sh, sizeof sh_end);
        /* out of phase: the left shoulder's height above the right one, in the root's frame */
        double lp[3], rp[3];
        apply_inverse(root, sh[0] + 12, lp);
        apply_inverse(root, sh[1] + 12, rp);
        bob_min = fmin(bob_min, lp[1] - rp[1]);
        bob_max = fmax(bob_max, lp[1] - rp[1]);

        const cJSON* png = cJSON_GetObjectItem(rec, "png");
        if (cJSON_IsString(png)) {
            ++pngs;
            CHECK_EQ_INT(f % PNG_EVERY, 0);
#ifdef ENGINE_LOOP_PNG
            snprintf(path, sizeof path, "%s/%s", out_dir, png->valuestring);
            check_png(path);
#endif
        }
        const cJSON* obj = cJSON_GetObjectItem(rec, "obj");
        if (!cJSON_IsString(obj)) continue;
        snprintf(path, sizeof path, "%s/%s", out_dir, obj->valuestring);
        double* x = NULL;
        int n = read_obj(path, &x);
        CHECK_EQ_INT(n, nv);
        if (n != nv) {
            free(x);
            continue;
        }
        ++checked;
        double centroid[3] = {0, 0, 0};
        for (int i = 0; i < 3 * nv; ++i) {
            nonfinite += !isfinite(x[i]);
            centroid[i % 3] += x[i] / nv;
        }
        for (int s = 0; s < 2; ++s)
            for (int i = 0; i < p.n[s]; ++i) {
                double want[3];
                apply(sh[s], local[s] + 3 * i, want);
                worst_pin = fmax(worst_pin, dist3(want, x + 3 * p.v[s][i]));
            }
        /* with the root: the centroid stays near the root's vertical axis */
        worst_centroid = fmax(worst_centroid, hypot(centroid[0] - root[12], centroid[2] - root[14]));
        if (f == 0) memcpy(centroid0, centroid, sizeof centroid0);
        memcpy(centroid_end, centroid, sizeof centroid_end);
        /* above the ground, outside the capsules and the sphere */
        const cJSON* rc = cJSON_GetObjectItem(rec, "colliders");
        for (int k = 0; k < cJSON_GetArraySize(cols); ++k) {
            const cJSON* c = cJSON_GetArrayItem(cols, k);
            const char* type = cJSON_GetObjectItem(c, "type")->valuestring;
            double m[16];
            CHECK(json_matrix(cJSON_GetArrayItem(rc, k), m));
            if (strcmp(type, "plane") == 0) {
                for (int i = 0; i < nv; ++i) {
                    double q[3];
                    apply_inverse(m, x + 3 * i, q);
                    lowest = fmin(lowest, q[1]);
                }
                continue;
            }
            double radius = cJSON_GetObjectItem(c, "radius")->valuedouble;
            double hh = cJSON_GetObjectItem(c, "half_height")->valuedouble;
            for (int i = 0; i < nv; ++i)
                worst_penetration = fmin(worst_penetration, shape_distance(type, radius, hh, m, x + 3 * i));
        }
        free(x);
    }
    printf("checked %d OBJ frames: pins off their bones by at most %.3g m; centroid at most %.3f m "
           "from the root's axis; lowest vertex %.3f m above the ground; closest to a collider "
           "surface %.4f m; %d PNGs\n",
           checked, worst_pin, worst_centroid, lowest, worst_penetration, pngs);
    CHECK_EQ_INT(checked, FRAMES / OBJ_EVERY + 1);
    CHECK_EQ_INT(nonfinite, 0);
    CHECK(worst_pin <= PIN_TOL);
    CHECK(worst_centroid < 0.25);
    CHECK(lowest > -PENETRATION_TOL);
    CHECK(worst_penetration > -PENETRATION_TOL);
#ifdef ENGINE_LOOP_PNG
    CHECK_EQ_INT(pngs, FRAMES / PNG_EVERY);
#else
    CHECK_EQ_INT(pngs, 0);
#endif

    /* the bones really moved: the root walked and turned, the shoulders went with it and bobbed
     * out of phase; the garment's centroid travelled as far as the root did */
    double walked = hypot(root_end[12] - root0[12], root_end[14] - root0[14]);
    double turned = heading(root_end) - heading(root0);
    printf("root walked %.2f m and turned %.1f deg; shoulder height difference %.3f .. %.3f m\n",
           walked, turned * 180.0 / 3.14159265358979, bob_min, bob_max);
    CHECK(walked > 1.0);
    CHECK(fabs(turned) > 0.3);
    for (int s = 0; s < 2; ++s) {
        CHECK(dist3(sh_end[s] + 12, sh0[s] + 12) > 1.0);
        CHECK(fabs(heading(sh_end[s]) - heading(sh0[s])) > 0.3);
    }
    CHECK(bob_min < -0.01 && bob_max > 0.01);
    double travelled = hypot(centroid_end[0] - centroid0[0], centroid_end[2] - centroid0[2]);
    CHECK_NEAR(travelled, walked, 0.25);

    for (int s = 0; s < 2; ++s) {
        free(p.v[s]);
        free(local[s]);
    }
    free(rest);
    cJSON_Delete(rep);
}

/* ---- failure paths ---- */

static void test_bad_library(void) {
    run_result r;
    char args[2048];
    snprintf(args, sizeof args, "--library /nonexistent/libweft.so.3 --frames 2 --out '%s/bad'", out_dir);
    run_example(args, &r);
    CHECK(r.rc != 0);
    CHECK(strstr(r.err, "/nonexistent/libweft.so.3: cannot open:") != NULL);
    if (!strstr(r.err, "cannot open")) fprintf(stderr, "stderr was: %s\n", r.err);
    free_run(&r);

    snprintf(args, sizeof args, "--library '%s' --frames 2 --out '%s/bad'", WEFT_FIXTURE_OLD_ABI, out_dir);
    run_example(args, &r);
    CHECK(r.rc != 0);
    char want[64];
    snprintf(want, sizeof want, "ABI %d != %d", WEFT_FIXTURE_ABI, WEFT_ABI_EXPECTED);
    CHECK(strstr(r.err, want) != NULL);
    if (!strstr(r.err, want)) fprintf(stderr, "stderr was: %s\n", r.err);
    free_run(&r);

    /* nothing was written: the library was refused before the scene was built */
    char path[1200];
    snprintf(path, sizeof path, "%s/bad/frame_0000.obj", out_dir);
    FILE* f = fopen(path, "r");
    CHECK(f == NULL);
    if (f) fclose(f);
}

static void test_bad_mesh_and_options(void) {
    run_result r;
    char args[2048];
    snprintf(args, sizeof args, "--mesh /nonexistent/garment.fbx --frames 2 --out '%s/bad'", out_dir);
    run_example(args, &r);
    CHECK(r.rc != 0);
    CHECK(strstr(r.err, "weft_cloth_create failed") != NULL);
    CHECK(strstr(r.err, "/nonexistent/garment.fbx") != NULL);
    free_run(&r);

    run_example("--frames 0", &r);
    CHECK_EQ_INT(r.rc, 2);
    CHECK(strstr(r.err, "--frames") != NULL && strstr(r.err, "usage:") != NULL);
    free_run(&r);

    run_example("--png-size 100", &r);
    CHECK_EQ_INT(r.rc, 2);
    free_run(&r);
}

static void test_library_stays_mapped(void) {
    weft_api w;
    char err[512];
    CHECK_EQ_INT(weft_loader_open(&w, WEFT_LIBRARY, err, sizeof err), WEFT_OK);
    weft_loader_close(&w);
    void* h = dlopen(WEFT_LIBRARY, RTLD_NOW | RTLD_NOLOAD);
    CHECK(h != NULL);
    if (h) dlclose(h);
}

int main(void) {
    snprintf(out_dir, sizeof out_dir, "%s/engine_loop", WEFT_TEST_TMPDIR);
    char cmd[1200];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", out_dir);
    if (system(cmd) != 0) fprintf(stderr, "could not clear %s\n", out_dir);
    RUN_TEST(test_walk);
    RUN_TEST(test_bad_library);
    RUN_TEST(test_bad_mesh_and_options);
    RUN_TEST(test_library_stays_mapped);
    return TEST_SUMMARY();
}
