/* engine_loop: Weft inside a (toy) game engine, loaded at run time through host_glue's loader.
 *
 * A character proxy walks forward in a circle at 60 Hz with a bobbing gait, wearing a garment
 * (sample_scenes/poncho.fbx by default) pinned to its two shoulder bones. Three components
 * register per-frame callbacks with the engine (toy_engine.h):
 *
 *   character  (ANIMATE)  walks and turns the root, bobs the spine, bobs the shoulders out of
 *                         phase, swings the arms and legs: local bone transforms only
 *                         (character.c; it knows nothing about Weft)
 *   cloth      (PHYSICS)  passes the garment's object transform (the root), the two shoulder
 *                         bones (attachments) and the character's capsules, sphere and ground
 *                         plane (colliders, following their bones) to weft_cloth_step
 *   output     (RENDER)   writes the garment as OBJ (world space) every --obj-every frames and a
 *                         PNG through weft_render every --png-every frames, with a camera that
 *                         follows the character; optionally a JSON report of every frame
 *
 * libweft.so is never linked: weft_loader_open() dlopens it by path (--library, default the one
 * this build made) and every call goes through the weft_api table it fills. This file depends on
 * weft/weft.h, host_glue/loader, toy_engine.h and character.h only.
 *
 *   engine_loop [--library PATH] [--mesh FILE] [--frames N] [--out DIR] [--obj-every K]
 *               [--png-every K] [--png-size WxH] [--report FILE] [--friction MU]
 *               [--max-iterations N] [--threads N] [--quiet]
 *
 * Exit status: 0; 1 when the library, the mesh, a step or an output failed (the message says
 * which); 2 for a bad command line. */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "character.h"
#include "toy_engine.h"
#include "weft_loader.h"

#ifndef ENGINE_LOOP_DEFAULT_LIBRARY
#define ENGINE_LOOP_DEFAULT_LIBRARY "libweft.so.10"
#endif
#ifndef ENGINE_LOOP_DEFAULT_MESH
#define ENGINE_LOOP_DEFAULT_MESH "poncho.fbx"
#endif

#define PI 3.14159265358979323846
#define FPS 60.0
/* Colliders' friction: 0 unless --friction says otherwise (what friction changes in the walk:
 * host_glue/README.md). */
#define DEFAULT_FRICTION 0.0
/* A game's budget: each linear solve stops here even when its residual is still above the
 * tolerance (the library's default cap is 300). */
#define DEFAULT_MAX_ITERATIONS 100

/* ============================================================================================= */
/* Command line                                                                                  */
/* ============================================================================================= */

typedef struct options {
    const char* library;
    const char* mesh;
    const char* out_dir;
    const char* report;         /* NULL: no report */
    int frames;
    int obj_every;              /* 0: no OBJ */
    int png_every;              /* 0: no PNG */
    int png_width, png_height;
    double friction;            /* Coulomb coefficient of every collider */
    int max_iterations;         /* iteration cap of each linear solve */
    int threads;                /* weft_context_def.threads (0: OpenMP's default) */
    int quiet;
} options;

static void usage(FILE* f) {
    fprintf(f,
            "usage: engine_loop [options]\n"
            "  --library PATH   libweft.so to load (default %s)\n"
            "  --mesh FILE      garment, Y up, front +Z, shoulders at the top of the mesh with\n"
            "                   0.09 m < |x| < 0.21 m (default %s)\n"
            "  --frames N       frames at 60 Hz (default 240)\n"
            "  --out DIR        output folder, created if missing (default engine_loop_out)\n"
            "  --obj-every K    write DIR/frame_NNNN.obj every K frames, 0: never (default 1)\n"
            "  --png-every K    render DIR/frame_NNNN.png every K frames, 0: never (default 60)\n"
            "  --png-size WxH   PNG size in pixels (default 640x480)\n"
            "  --report FILE    write a JSON report of every frame (transforms, pins, stats)\n"
            "  --friction MU    Coulomb friction of every collider, >= 0 (default %g)\n"
            "  --max-iterations N  iteration cap of each linear solve (default %d)\n"
            "  --threads N      Weft's OpenMP threads, 0: one per core (default 0)\n"
            "  --quiet          print the summary only, not a line per frame\n",
            ENGINE_LOOP_DEFAULT_LIBRARY, ENGINE_LOOP_DEFAULT_MESH, DEFAULT_FRICTION,
            DEFAULT_MAX_ITERATIONS);
}

static int parse_int(const char* s, int min, int* out) {
    char* end = NULL;
    errno = 0;
    long v = strtol(s, &end, 10);
    if (errno || end == s || *end || v < min || v > 1000000000L) return 0;
    *out = (int)v;
    return 1;
}

/* Returns 1 on success; on failure prints the reason and the usage. */
static int parse_options(int argc, char** argv, options* o) {
    o->library = ENGINE_LOOP_DEFAULT_LIBRARY;
    o->mesh = ENGINE_LOOP_DEFAULT_MESH;
    o->out_dir = "engine_loop_out";
    o->report = NULL;
    o->frames = 240;
    o->obj_every = 1;
    o->png_every = 60;
    o->png_width = 640;
    o->png_height = 480;
    o->friction = DEFAULT_FRICTION;
    o->max_iterations = DEFAULT_MAX_ITERATIONS;
    o->threads = 0;
    o->quiet = 0;
    for (int i = 1; i < argc; ++i) {
        const char* a = argv[i];
        const char* v = i + 1 < argc ? argv[i + 1] : NULL;
        int ok = 1, takes_value = 1;
        if (strcmp(a, "--quiet") == 0) {
            o->quiet = 1;
            takes_value = 0;
        } else if (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0) {
            usage(stdout);
            exit(0);
        } else if (!v) {
            ok = 0;
        } else if (strcmp(a, "--library") == 0) {
            o->library = v;
        } else if (strcmp(a, "--mesh") == 0) {
            o->mesh = v;
        } else if (strcmp(a, "--out") == 0) {
            o->out_dir = v;
        } else if (strcmp(a, "--report") == 0) {
            o->report = v;
        } else if (strcmp(a, "--frames") == 0) {
            ok = parse_int(v, 1, &o->frames);
        } else if (strcmp(a, "--obj-every") == 0) {
            ok = parse_int(v, 0, &o->obj_every);
        } else if (strcmp(a, "--png-every") == 0) {
            ok = parse_int(v, 0, &o->png_every);
        } else if (strcmp(a, "--max-iterations") == 0) {
            ok = parse_int(v, 1, &o->max_iterations);
        } else if (strcmp(a, "--threads") == 0) {
            ok = parse_int(v, 0, &o->threads);
        } else if (strcmp(a, "--friction") == 0) {
            char* end = NULL;
            o->friction = strtod(v, &end);
            ok = end != v && !*end && o->friction >= 0.0 && o->friction <= 10.0;
        } else if (strcmp(a, "--png-size") == 0) {
            char tail = 0;
            ok = sscanf(v, "%dx%d%c", &o->png_width, &o->png_height, &tail) == 2 &&
                 o->png_width >= 1 && o->png_width <= 8192 && o->png_height >= 1 &&
                 o->png_height <= 8192;
        } else {
            fprintf(stderr, "engine_loop: unknown option %s\n", a);
            usage(stderr);
            return 0;
        }
        if (!ok) {
            fprintf(stderr, "engine_loop: bad or missing value for %s%s%s\n", a, v ? ": " : "",
                    v ? v : "");
            usage(stderr);
            return 0;
        }
        i += takes_value;
    }
    return 1;
}

/* ============================================================================================= */
/* The cloth component                                                                           */
/* ============================================================================================= */

#define SHOULDER_MIN_X 0.09     /* m: pinned vertices are at the top of the garment with */
#define SHOULDER_MAX_X 0.21     /*    SHOULDER_MIN_X < |x| < SHOULDER_MAX_X */
#define TOP_TOLERANCE 0.001     /* m below the highest vertex that still counts as the top */

typedef struct cloth_component {
    const weft_api* w;
    weft_context* ctx;
    weft_cloth cloth;
    const character* ch;
    weft_cloth_info info;
    int* pinned[2];             /* host vertex indices per shoulder */
    int n_pinned[2];
    float bind[2][16];          /* shoulder world transforms at bind time */
    float object[16];           /* per-frame inputs, filled from the scene graph */
    float attachments[2 * 16];
    float colliders[CHARACTER_N_PROXIES * 16];
    /* statistics */
    weft_frame_stats last;
    double* ms;                 /* (frames) weft_frame_stats.ms_total per frame */
    int frames, frames_run;
    long iterations;
    int max_iterations;
    double max_strain;
    int rollbacks, halvings, not_converged, failed_steps;
} cloth_component;

static void gather_inputs(cloth_component* cc, const te_engine* e) {
    memcpy(cc->object, e->bones[cc->ch->root].world, sizeof cc->object);
    for (int side = 0; side < 2; ++side)
        memcpy(cc->attachments + 16 * side, e->bones[cc->ch->shoulder[side]].world,
               16 * sizeof(float));
    for (int k = 0; k < CHARACTER_N_PROXIES; ++k)
        character_proxy_transform(e, k, cc->colliders + 16 * k);
}

static int weft_failed(const cloth_component* cc, const char* call) {
    fprintf(stderr, "engine_loop: %s failed: %s (%s)\n", call,
            cc->w->weft_context_last_error(cc->ctx),
            cc->w->weft_status_string(cc->w->weft_context_last_status(cc->ctx)));
    return 0;
}

/* Pick the shoulder vertices: read the rest shape in object space (the host's mesh units, so
 * convert with the metres-per-unit ratio of the bounding boxes), keep the top row with
 * SHOULDER_MIN_X < |x| < SHOULDER_MAX_X, and bind them to the shoulder bones as they are now. */
static int bind_shoulders(cloth_component* cc, const te_engine* e) {
    const weft_api* w = cc->w;
    int n = cc->info.n_vertices, count = 0, ok = 0;
    float* p = malloc(sizeof(float) * 3 * (size_t)n);
    for (int s = 0; s < 2; ++s) cc->pinned[s] = malloc(sizeof(int) * (size_t)n);
    if (!p || !cc->pinned[0] || !cc->pinned[1]) {
        fprintf(stderr, "engine_loop: out of memory\n");
        goto done;
    }
    if (w->weft_cloth_get_vertices(cc->ctx, cc->cloth, WEFT_SPACE_OBJECT, p, NULL, n, &count) !=
        WEFT_OK) {
        weft_failed(cc, "weft_cloth_get_vertices");
        goto done;
    }
    float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int i = 0; i < n; ++i)
        for (int k = 0; k < 3; ++k) {
            lo[k] = fminf(lo[k], p[3 * i + k]);
            hi[k] = fmaxf(hi[k], p[3 * i + k]);
        }
    double diag_units = 0.0, diag_m = 0.0;
    for (int k = 0; k < 3; ++k) {
        diag_units += ((double)hi[k] - lo[k]) * ((double)hi[k] - lo[k]);
        diag_m += (cc->info.bbox_max[k] - cc->info.bbox_min[k]) *
                  (cc->info.bbox_max[k] - cc->info.bbox_min[k]);
    }
    double m_per_unit = diag_units > 0.0 ? sqrt(diag_m / diag_units) : 1.0;
    for (int i = 0; i < n; ++i) {
        double x = p[3 * i] * m_per_unit, y = p[3 * i + 1] * m_per_unit;
        if (y < hi[1] * m_per_unit - TOP_TOLERANCE) continue;
        if (fabs(x) <= SHOULDER_MIN_X || fabs(x) >= SHOULDER_MAX_X) continue;
        int side = x > 0.0 ? 0 : 1;   /* +X is the character's left */
        cc->pinned[side][cc->n_pinned[side]++] = i;
    }
    if (cc->n_pinned[0] == 0 || cc->n_pinned[1] == 0) {
        fprintf(stderr,
                "engine_loop: no shoulder vertices in the garment (expected vertices at its top "
                "with %.2f m < |x| < %.2f m on both sides; found %d left, %d right)\n",
                SHOULDER_MIN_X, SHOULDER_MAX_X, cc->n_pinned[0], cc->n_pinned[1]);
        goto done;
    }
    weft_attachment_def att[2];
    for (int s = 0; s < 2; ++s) {
        att[s] = w->weft_default_attachment_def();
        att[s].vertices = cc->pinned[s];
        att[s].n_vertices = cc->n_pinned[s];
        memcpy(att[s].bind_transform, e->bones[cc->ch->shoulder[s]].world,
               sizeof att[s].bind_transform);
        memcpy(cc->bind[s], att[s].bind_transform, sizeof cc->bind[s]);
    }
    if (w->weft_cloth_set_attachments(cc->ctx, cc->cloth, att, 2) != WEFT_OK) {
        weft_failed(cc, "weft_cloth_set_attachments");
        goto done;
    }
    ok = 1;
done:
    free(p);
    return ok;
}

/* Create the garment on the character in its rest pose: object transform = the root's, the
 * colliders at their bones, then the shoulder pins. */
static int cloth_component_create(cloth_component* cc, const weft_api* w, weft_context* ctx,
                                  const te_engine* e, const character* ch, const options* o) {
    memset(cc, 0, sizeof *cc);
    cc->w = w;
    cc->ctx = ctx;
    cc->ch = ch;
    cc->frames = o->frames;
    cc->ms = calloc((size_t)o->frames, sizeof(double));
    if (!cc->ms) {
        fprintf(stderr, "engine_loop: out of memory\n");
        return 0;
    }
    gather_inputs(cc, e);
    weft_collider_def col[CHARACTER_N_PROXIES];
    for (int k = 0; k < CHARACTER_N_PROXIES; ++k) {
        const character_proxy* p = &character_proxies[k];
        col[k] = w->weft_default_collider_def();
        switch (p->shape) {
        case CHARACTER_PLANE: col[k].type = WEFT_COLLIDER_PLANE; break;
        case CHARACTER_SPHERE: col[k].type = WEFT_COLLIDER_SPHERE; break;
        case CHARACTER_CAPSULE: col[k].type = WEFT_COLLIDER_CAPSULE; break;
        }
        if (p->shape != CHARACTER_PLANE) col[k].radius = p->radius;
        if (p->shape == CHARACTER_CAPSULE) col[k].half_height = p->half_height;
        col[k].friction = o->friction;
        memcpy(col[k].transform, cc->colliders + 16 * k, sizeof col[k].transform);
    }
    weft_cloth_def def = w->weft_default_cloth_def();
    def.mesh.path = o->mesh;
    def.max_iterations = o->max_iterations;
    memcpy(def.transform, cc->object, sizeof def.transform);
    def.n_colliders = CHARACTER_N_PROXIES;
    def.colliders = col;
    if (w->weft_cloth_create(ctx, &def, &cc->cloth) != WEFT_OK)
        return weft_failed(cc, "weft_cloth_create");
    if (w->weft_cloth_get_info(ctx, cc->cloth, &cc->info) != WEFT_OK)
        return weft_failed(cc, "weft_cloth_get_info");
    return bind_shoulders(cc, e);
}

static void cloth_component_destroy(cloth_component* cc) {
    free(cc->ms);
    free(cc->pinned[0]);
    free(cc->pinned[1]);
}

/* PHYSICS: one weft_cloth_step with this frame's transforms. A failed step leaves the cloth as
 * it was (weft.h's contract): report it and go on, as a game would. */
static int cloth_update(te_engine* e, const te_time* time, void* user) {
    cloth_component* cc = user;
    gather_inputs(cc, e);
    weft_frame fr = cc->w->weft_default_frame();
    fr.dt = time->dt;
    fr.object_transform = cc->object;
    fr.attachment_transforms = cc->attachments;
    fr.collider_transforms = cc->colliders;
    weft_frame_stats st;
    memset(&st, 0, sizeof st);
    if (cc->w->weft_cloth_step(cc->ctx, cc->cloth, &fr, &st) != WEFT_OK) {
        fprintf(stderr, "engine_loop: frame %lld: ", (long long)time->frame);
        weft_failed(cc, "weft_cloth_step");
        ++cc->failed_steps;
    }
    cc->last = st;
    if (cc->frames_run < cc->frames) cc->ms[cc->frames_run++] = st.ms_total;
    cc->iterations += st.iterations;
    if (st.max_iterations > cc->max_iterations) cc->max_iterations = st.max_iterations;
    if (st.max_strain > cc->max_strain) cc->max_strain = st.max_strain;
    cc->rollbacks += st.rollbacks;
    cc->halvings += st.halvings;
    cc->not_converged += st.not_converged;
    return 0;
}

/* ============================================================================================= */
/* The output component: OBJ, PNG, per-frame line, JSON report                                   */
/* ============================================================================================= */

typedef struct output_component {
    const options* opt;
    cloth_component* cc;
    const character* ch;
    float* positions;           /* (n_vertices x 3) world */
    float* normals;
    int* triangles;             /* (n_triangles x 3) */
    int n_triangles;
    FILE* report;
    int n_obj, n_png, png_disabled;
    int failed;                 /* an output could not be written */
} output_component;

static void json_matrix(FILE* f, const float m[16]) {
    fputc('[', f);
    for (int i = 0; i < 16; ++i) fprintf(f, "%s%.9g", i ? ", " : "", (double)m[i]);
    fputc(']', f);
}

static void json_string(FILE* f, const char* s) {
    fputc('"', f);
    for (; *s; ++s) {
        if (*s == '"' || *s == '\\') fputc('\\', f);
        if ((unsigned char)*s < 0x20)
            fprintf(f, "\\u%04x", (unsigned)(unsigned char)*s);
        else
            fputc(*s, f);
    }
    fputc('"', f);
}

static int write_obj(output_component* oc, const char* path) {
    const cloth_component* cc = oc->cc;
    int n = cc->info.n_vertices, count = 0;
    if (cc->w->weft_cloth_get_vertices(cc->ctx, cc->cloth, WEFT_SPACE_WORLD, oc->positions,
                                       oc->normals, n, &count) != WEFT_OK)
        return weft_failed(cc, "weft_cloth_get_vertices");
    FILE* f = fopen(path, "w");
    if (!f) {
        fprintf(stderr, "engine_loop: cannot write %s: %s\n", path, strerror(errno));
        return 0;
    }
    fprintf(f, "# engine_loop garment, world space (m), host vertex order\no garment\n");
    for (int i = 0; i < n; ++i)
        fprintf(f, "v %.6f %.6f %.6f\n", (double)oc->positions[3 * i],
                (double)oc->positions[3 * i + 1], (double)oc->positions[3 * i + 2]);
    for (int i = 0; i < n; ++i)
        fprintf(f, "vn %.5f %.5f %.5f\n", (double)oc->normals[3 * i],
                (double)oc->normals[3 * i + 1], (double)oc->normals[3 * i + 2]);
    for (int t = 0; t < oc->n_triangles; ++t) {
        const int* v = oc->triangles + 3 * t;
        fprintf(f, "f %d//%d %d//%d %d//%d\n", v[0] + 1, v[0] + 1, v[1] + 1, v[1] + 1, v[2] + 1,
                v[2] + 1);
    }
    if (fclose(f) != 0) {
        fprintf(stderr, "engine_loop: cannot write %s: %s\n", path, strerror(errno));
        return 0;
    }
    ++oc->n_obj;
    return 1;
}

/* A camera that follows the character: ahead of it and to its left, looking at its chest. */
static int write_png(output_component* oc, const te_engine* e, const char* path) {
    const cloth_component* cc = oc->cc;
    const float* root = e->bones[oc->ch->root].world;
    const double eye_local[3] = {1.6, 1.45, 2.6}, target_local[3] = {0.0, 0.9, 0.0};
    double eye[3], target[3];
    te_apply_point(root, eye_local, eye);
    te_apply_point(root, target_local, target);
    weft_render_def rd = cc->w->weft_default_render_def();
    rd.width = oc->opt->png_width;
    rd.height = oc->opt->png_height;
    for (int k = 0; k < 3; ++k) {
        rd.eye[k] = (float)eye[k];
        rd.target[k] = (float)target[k];
    }
    rd.fov_y_deg = 40.0f;
    rd.png_path = path;
    weft_status st = cc->w->weft_render(cc->ctx, cc->cloth, &rd);
    if (st == WEFT_ERROR_UNSUPPORTED || st == WEFT_ERROR_GPU) {
        /* a library built without gpu/, or no EGL device: go on without pictures */
        fprintf(stderr, "engine_loop: no PNGs: %s\n", cc->w->weft_context_last_error(cc->ctx));
        oc->png_disabled = 1;
        return 1;
    }
    if (st != WEFT_OK) return weft_failed(cc, "weft_render");
    ++oc->n_png;
    return 1;
}

static void report_frame(output_component* oc, const te_engine* e, int64_t frame, double t,
                         const char* obj, const char* png) {
    FILE* f = oc->report;
    const cloth_component* cc = oc->cc;
    fprintf(f, "%s\n    {\"frame\": %lld, \"time\": %.9g, \"obj\": ", frame ? "," : "",
            (long long)frame, t);
    if (obj) json_string(f, obj); else fputs("null", f);
    fputs(", \"png\": ", f);
    if (png) json_string(f, png); else fputs("null", f);
    fputs(",\n     \"root\": ", f);
    json_matrix(f, e->bones[oc->ch->root].world);
    fputs(",\n     \"attachments\": [", f);
    for (int s = 0; s < 2; ++s) {
        fputs(s ? ", " : "", f);
        json_matrix(f, cc->attachments + 16 * s);
    }
    fputs("],\n     \"colliders\": [", f);
    for (int k = 0; k < CHARACTER_N_PROXIES; ++k) {
        fputs(k ? ", " : "", f);
        json_matrix(f, cc->colliders + 16 * k);
    }
    const weft_frame_stats* st = &cc->last;
    fprintf(f,
            "],\n     \"ms\": %.4f, \"iterations\": %d, \"max_strain\": %.6g, \"rollbacks\": %d, "
            "\"contacts\": %d}",
            st->ms_total, st->iterations, st->max_strain, st->rollbacks, st->contacts);
}

/* Outputs of one frame (frame 0: the rest state before the loop). */
static int output_frame(output_component* oc, const te_engine* e, int64_t frame, double t) {
    const options* o = oc->opt;
    char obj[64], png[64], path[4096];
    int want_obj = o->obj_every > 0 && frame % o->obj_every == 0;
    int want_png = o->png_every > 0 && frame > 0 && frame % o->png_every == 0 && !oc->png_disabled;
    snprintf(obj, sizeof obj, "frame_%04lld.obj", (long long)frame);
    snprintf(png, sizeof png, "frame_%04lld.png", (long long)frame);
    if (want_obj) {
        snprintf(path, sizeof path, "%s/%s", o->out_dir, obj);
        if (!write_obj(oc, path)) oc->failed = 1;
    }
    if (want_png) {
        snprintf(path, sizeof path, "%s/%s", o->out_dir, png);
        if (!write_png(oc, e, path)) oc->failed = 1;
        if (oc->png_disabled) want_png = 0;
    }
    if (oc->report) report_frame(oc, e, frame, t, want_obj ? obj : NULL, want_png ? png : NULL);
    if (!o->quiet && frame > 0) {
        const weft_frame_stats* st = &oc->cc->last;
        const character* c = oc->ch;
        printf("frame %4lld  t %6.3f s  root (%6.3f, %6.3f) heading %6.1f deg  step %7.2f ms  "
               "it %4d  strain %6.2f%%  contacts %4d  rollbacks %d%s%s\n",
               (long long)frame, t, c->x, c->z, c->heading * 180.0 / PI, st->ms_total,
               st->iterations, 100.0 * st->max_strain, st->contacts, st->rollbacks,
               want_obj ? "  obj" : "", want_png ? "  png" : "");
    }
    return oc->failed ? 1 : 0;
}

/* RENDER */
static int output_update(te_engine* e, const te_time* time, void* user) {
    return output_frame(user, e, time->frame, time->t);
}

static int output_component_create(output_component* oc, const options* o, cloth_component* cc,
                                   const character* ch) {
    memset(oc, 0, sizeof *oc);
    oc->opt = o;
    oc->cc = cc;
    oc->ch = ch;
    const weft_api* w = cc->w;
    int n = cc->info.n_vertices;
    oc->positions = malloc(sizeof(float) * 3 * (size_t)n);
    oc->normals = malloc(sizeof(float) * 3 * (size_t)n);
    oc->n_triangles = cc->info.n_triangles;
    oc->triangles = malloc(sizeof(int) * 3 * (size_t)(oc->n_triangles > 0 ? oc->n_triangles : 1));
    if (!oc->positions || !oc->normals || !oc->triangles) {
        fprintf(stderr, "engine_loop: out of memory\n");
        return 0;
    }
    int count = 0;
    if (w->weft_cloth_get_triangles(cc->ctx, cc->cloth, oc->triangles, oc->n_triangles, &count) !=
        WEFT_OK)
        return weft_failed(cc, "weft_cloth_get_triangles");
    if (mkdir(o->out_dir, 0777) != 0 && errno != EEXIST) {
        fprintf(stderr, "engine_loop: cannot create %s: %s\n", o->out_dir, strerror(errno));
        return 0;
    }
    if (o->report) {
        oc->report = fopen(o->report, "w");
        if (!oc->report) {
            fprintf(stderr, "engine_loop: cannot write %s: %s\n", o->report, strerror(errno));
            return 0;
        }
        FILE* f = oc->report;
        fputs("{\n  \"library\": ", f);
        json_string(f, o->library);
        fputs(",\n  \"mesh\": ", f);
        json_string(f, o->mesh);
        fprintf(f,
                ",\n  \"dt\": %.17g, \"frames\": %d, \"n_vertices\": %d, \"obj_every\": %d, "
                "\"png_every\": %d, \"png_width\": %d, \"png_height\": %d,\n  \"attachments\": [",
                1.0 / FPS, o->frames, n, o->obj_every, o->png_every, o->png_width,
                o->png_height);
        for (int s = 0; s < 2; ++s) {
            fprintf(f, "%s\n    {\"bone\": \"%s\", \"bind_transform\": ", s ? "," : "",
                    s == 0 ? "shoulder_l" : "shoulder_r");
            json_matrix(f, cc->bind[s]);
            fputs(", \"vertices\": [", f);
            for (int i = 0; i < cc->n_pinned[s]; ++i)
                fprintf(f, "%s%d", i ? ", " : "", cc->pinned[s][i]);
            fputs("]}", f);
        }
        fputs("],\n  \"colliders\": [", f);
        for (int k = 0; k < CHARACTER_N_PROXIES; ++k) {
            static const char* const shapes[] = {"plane", "sphere", "capsule"};
            const character_proxy* p = &character_proxies[k];
            fprintf(f,
                    "%s\n    {\"name\": \"%s\", \"type\": \"%s\", \"radius\": %.9g, "
                    "\"half_height\": %.9g, \"friction\": %.9g}",
                    k ? "," : "", p->name, shapes[p->shape], p->radius, p->half_height,
                    o->friction);
        }
        fputs("],\n  \"frame_records\": [", f);
    }
    return 1;
}

static void output_component_destroy(output_component* oc) {
    free(oc->positions);
    free(oc->normals);
    free(oc->triangles);
    if (oc->report) fclose(oc->report);
}

/* ============================================================================================= */
/* main                                                                                          */
/* ============================================================================================= */

static int compare_double(const void* a, const void* b) {
    double x = *(const double*)a, y = *(const double*)b;
    return (x > y) - (x < y);
}

static void log_to_stderr(weft_log_level level, const char* message, void* user) {
    static const char* const names[] = {"debug", "info", "warning", "error"};
    (void)user;
    fprintf(stderr, "weft %s: %s\n",
            (int)level >= 0 && level <= WEFT_LOG_ERROR ? names[level] : "?", message);
}

static void print_summary(const options* o, const cloth_component* cc, const output_component* oc,
                          const character* ch) {
    int frames_run = cc->frames_run;
    double median = 0.0, p90 = 0.0, worst = 0.0;
    if (frames_run > 0) {
        double* ms = malloc(sizeof(double) * (size_t)frames_run);
        if (ms) {
            memcpy(ms, cc->ms, sizeof(double) * (size_t)frames_run);
            qsort(ms, (size_t)frames_run, sizeof(double), compare_double);
            median = frames_run % 2 ? ms[frames_run / 2]
                                    : 0.5 * (ms[frames_run / 2 - 1] + ms[frames_run / 2]);
            p90 = ms[(int)(0.9 * (frames_run - 1) + 0.5)];
            worst = ms[frames_run - 1];
            free(ms);
        }
    }
    printf("engine_loop: %d frames at %.0f Hz, %d vertices, %d + %d pinned, %d colliders, %s "
           "backend\n",
           frames_run, FPS, cc->info.n_vertices, cc->n_pinned[0], cc->n_pinned[1],
           CHARACTER_N_PROXIES, cc->info.backend == WEFT_BACKEND_GPU ? "GPU" : "CPU");
    printf("  step: median %.2f ms/frame, p90 %.2f, max %.2f\n", median, p90, worst);
    printf("  iterations: %.1f per frame (largest solve %d, %d solves stopped at the cap); max "
           "strain %.2f%%; rollbacks %d, halvings %d, failed steps %d\n",
           frames_run ? (double)cc->iterations / frames_run : 0.0, cc->max_iterations,
           cc->not_converged, 100.0 * cc->max_strain, cc->rollbacks, cc->halvings,
           cc->failed_steps);
    printf("  walked %.2f m, turned %.1f deg; wrote %d OBJ and %d PNG to %s\n", ch->distance,
           ch->heading * 180.0 / PI, oc->n_obj, oc->n_png, o->out_dir);
    if (oc->report) {
        fprintf(oc->report,
                "\n  ],\n  \"summary\": {\"frames_run\": %d, \"step_ms_median\": %.4f, "
                "\"iterations\": %ld, \"not_converged\": %d, \"max_strain\": %.6g, "
                "\"rollbacks\": %d, \"halvings\": %d, \"failed_steps\": %d, \"n_obj\": %d, "
                "\"n_png\": %d}\n}\n",
                frames_run, median, cc->iterations, cc->not_converged, cc->max_strain,
                cc->rollbacks, cc->halvings, cc->failed_steps, oc->n_obj, oc->n_png);
    }
}

int main(int argc, char** argv) {
    options o;
    if (!parse_options(argc, argv, &o)) return 2;

    /* 1. Load the plugin by path: the ABI is checked before anything else is called. */
    weft_api w;
    char err[1024];
    if (weft_loader_open(&w, o.library, err, sizeof err) != WEFT_OK) {
        fprintf(stderr, "engine_loop: %s\n", err);
        return 1;
    }
    weft_version_info v = w.weft_version();
    if (!o.quiet) printf("engine_loop: loaded %s (Weft %d.%d.%d, ABI %d)\n", o.library, v.major,
                         v.minor, v.patch, v.abi);
    weft_context_def cd = w.weft_default_context_def();
    cd.log = log_to_stderr;
    cd.threads = o.threads;
    weft_context* ctx = NULL;
    if (w.weft_context_create(WEFT_ABI, &cd, &ctx) != WEFT_OK) {
        fprintf(stderr, "engine_loop: weft_context_create failed (see the message above)\n");
        weft_loader_close(&w);
        return 1;
    }

    /* 2. The scene: a character, the garment on it, the outputs; each registers its callback. */
    te_engine engine;
    te_init(&engine, 1.0 / FPS);
    character ch;
    cloth_component cc;
    output_component oc;
    memset(&cc, 0, sizeof cc);
    memset(&oc, 0, sizeof oc);
    int rc = 1;
    if (!character_create(&engine, &ch)) {
        fprintf(stderr, "engine_loop: too many bones\n");
        goto done;
    }
    if (!cloth_component_create(&cc, &w, ctx, &engine, &ch, &o)) goto done;
    if (!output_component_create(&oc, &o, &cc, &ch)) goto done;
    te_register(&engine, TE_PHASE_ANIMATE, "character", character_update, &ch);
    te_register(&engine, TE_PHASE_PHYSICS, "cloth", cloth_update, &cc);
    te_register(&engine, TE_PHASE_RENDER, "output", output_update, &oc);

    /* 3. Frame 0 (the rest state), then the loop. */
    if (output_frame(&oc, &engine, 0, 0.0) != 0) goto done;
    int stopped = te_run(&engine, o.frames);
    print_summary(&o, &cc, &oc, &ch);
    rc = stopped || cc.failed_steps || oc.failed ? 1 : 0;

done:
    output_component_destroy(&oc);
    cloth_component_destroy(&cc);
    w.weft_context_destroy(ctx);   /* destroys the cloth too */
    weft_loader_close(&w);         /* after the last context */
    return rc;
}
