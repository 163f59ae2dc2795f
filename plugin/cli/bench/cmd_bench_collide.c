/* `weft bench collide`: what collision detection costs per frame against the cloth's size and the
 * body's. A square sheet (drapeN: 1 m x 1 m, N x N particles, 5 cm above the body, no pins) falls
 * onto a triangle-mesh sphere (bench_body.c: radius 0.25 m, about T triangles) with
 * self-collision on, one step per frame at 30 frames/s, through the public API on each backend's
 * context (weft_cloth_step, the library's defaults otherwise: each backend's own). Per (N, T): frames are stepped until the
 * sheet touches the body (warm-up), then a few frames are timed; the medians of the stage times
 * the frame stats report (total: the whole call; collide: the colliders' passes, the mesh
 * contacts; self-collide; solve) and the collision share (collide + self) / total. The error side
 * of each row, from weft_cloth_check_collisions at the last frame: the deepest penetration of a
 * particle into the body and the self-intersecting edge-triangle pairs. The goal (self-collision
 * and a 20k-triangle body under 30 % of the frame at 25,600 particles) is judged on the row
 * N = 160 with the body nearest 20,000 triangles. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "bench_args.h"
#include "bench_backend.h"
#include "bench_body.h"
#include "bench_commands.h"
#include "bench_run.h"
#include "bench_table.h"
#include "cli.h"
#include "scene_host.h"

#define FPS 30.0
#define BODY_RADIUS 0.25        /* m: the drape scene's sphere */
#define BODY_THICKNESS 0.005    /* m */
#define BODY_FRICTION 0.3
#define GOAL_N 160              /* 25,600 particles */
#define GOAL_TRIS 20000
#define GOAL_SHARE 0.30

typedef struct collide_args {
    int cloth[BENCH_MAX_LIST], n_cloth;     /* sheet sizes N (N x N particles) */
    int body[BENCH_MAX_LIST], n_body;       /* body triangle counts asked for (nearest UV sphere) */
    int frames;                             /* timed frames per configuration */
    int max_warmup;                         /* frames at most before the sheet touches the body */
    int settle;                             /* frames stepped after the first touch, before timing */
    int backends[BENCH_MAX_BACKENDS], n_backends;
    bench_common com;
} collide_args;

void bench_collide_usage(FILE* out) {
    fputs("usage: weft bench collide [--quick] [--cloth LIST] [--body LIST] [--frames N] [--settle N]\n"
          "                          [--max-warmup N] [--backend LIST] [--threads N] [--csv FILE]\n"
          "                          [--md FILE] [--quiet]\n"
          "\n"
          "The cost of collision detection per frame against cloth size and body size (through the\n"
          "public API: weft_cloth_step, on each backend asked for).\n"
          "A 1 m x 1 m sheet of N x N particles (scene drapeN: 5 cm above the body, no pins) falls onto\n"
          "a triangle-mesh sphere (UV sphere, radius 0.25 m, thickness 5 mm, friction 0.3) with\n"
          "self-collision on (thickness 3 mm), one step per frame (substeps 1) at 30 frames/s, each\n"
          "backend's solver defaults (CPU: multigrid-preconditioned PCG, 2 Newton iterations, line\n"
          "search). Per\n"
          "(N, body): frames until the sheet touches the body (at most --max-warmup), --settle more,\n"
          "then --frames timed frames.\n"
          "Columns: median ms per frame of the whole step (total), the colliders' passes (collide: the\n"
          "mesh contacts), self-collision (self) and the solve; the collision share (collide + self)\n"
          "/ total of the medians; the fastest and slowest timed frame; particles in contact and self-\n"
          "collision impulses/zones over the timed frames; the error side at the last frame: the\n"
          "deepest penetration into the body (mm; 0: none) and the self-intersecting edge-triangle\n"
          "pairs (0: none). The issue's goal (self-collision and a 20k-triangle body under 30 % of the\n"
          "frame at 25,600 particles) is judged on the row N = 160, body nearest 20000 triangles.\n"
          "\n"
          "options:\n"
          "  --quick              seconds-long preset: --cloth 16,24 --body 1000,5000 --frames 2, 1 thread\n"
          "  --cloth LIST         sheet sizes N, 4 to 1024 (default 32,64,160,316: 1k to 100k particles)\n"
          "  --body LIST          body triangles, 24 to 4000000, the UV sphere nearest each\n"
          "                       (default 1000,5000,20000,80000)\n"
          "  --frames N           frames timed per configuration (default 3)\n"
          "  --settle N           frames stepped after the first touch, before the timed ones (default 0)\n"
          "  --max-warmup N       frames at most waiting for the first touch (default 30)\n"
          BENCH_BACKEND_HELP
          "  --threads N          OpenMP threads (default 0: OpenMP's default)\n"
          "  --csv FILE           write every configuration as CSV\n"
          "  --md FILE            write the Markdown table to FILE instead of stdout\n"
          "  --quiet              no progress lines on stderr\n"
          "  -h, --help           show this help\n",
          out);
}

static void defaults(void* args, int quick) {
    collide_args* a = args;
    memset(a, 0, sizeof *a);
    static const int cloth[] = {32, 64, 160, 316}, body[] = {1000, 5000, 20000, 80000};
    static const int qcloth[] = {16, 24}, qbody[] = {1000, 5000};
    a->n_cloth = quick ? 2 : 4;
    a->n_body = quick ? 2 : 4;
    memcpy(a->cloth, quick ? qcloth : cloth, sizeof(int) * (size_t)a->n_cloth);
    memcpy(a->body, quick ? qbody : body, sizeof(int) * (size_t)a->n_body);
    a->frames = quick ? 2 : 3;
    a->max_warmup = 30;
    a->settle = 0;
    a->backends[0] = BENCH_CPU;
    a->n_backends = 1;
}

static int own_option(void* args, int argc, char** argv, int* i, const char** v) {
    collide_args* a = args;
    int m = 0;
    if ((m = cli_option_value(argc, argv, i, "--cloth", v)) != 0)
        return m < 0 ? m : (a->n_cloth = bench_parse_ints(*v, 4, 1024, a->cloth)) < 1 ? -2 : 1;
    if ((m = cli_option_value(argc, argv, i, "--body", v)) != 0)
        return m < 0 ? m : (a->n_body = bench_parse_ints(*v, 24, 4000000, a->body)) < 1 ? -2 : 1;
    if ((m = cli_option_value(argc, argv, i, "--frames", v)) != 0)
        return m < 0 ? m : cli_parse_int(*v, 1, 10000, &a->frames) != 0 ? -2 : 1;
    if ((m = cli_option_value(argc, argv, i, "--settle", v)) != 0)
        return m < 0 ? m : cli_parse_int(*v, 0, 10000, &a->settle) != 0 ? -2 : 1;
    if ((m = cli_option_value(argc, argv, i, "--max-warmup", v)) != 0)
        return m < 0 ? m : cli_parse_int(*v, 1, 10000, &a->max_warmup) != 0 ? -2 : 1;
    if ((m = cli_option_value(argc, argv, i, "--backend", v)) != 0)
        return m < 0 ? m : (a->n_backends = bench_parse_backends(*v, a->backends)) < 0 ? -2 : 1;
    return 0;
}

/* One configuration's outcome. */
typedef struct collide_run {
    int backend;            /* BENCH_CPU or BENCH_GPU */
    int n, particles, tris;
    int warmup;             /* frames before the first touch (-1: it never touched) */
    double total, collide, self, solve;   /* medians, ms per frame */
    double share;           /* (collide + self) / total of the medians */
    double total_min, total_max;
    int contacts;           /* particles in contact at the last frame */
    long long self_proximity, self_impacts, self_zones, self_unresolved;
    double iterations;      /* per substep, mean over the timed frames */
    long long substeps_timed;
    double penetration;     /* m, at the last frame */
    int intersections;      /* self-intersecting edge-triangle pairs at the last frame */
    int threads;            /* OpenMP threads of a call (weft_cloth_info) */
} collide_run;

/* The timed frames' medians and the last frame's checks of a created cloth (after the warm-up). */
static int time_frames(scene_host* h, const scene* sc, const collide_args* a, collide_run* out, char* msg,
                       size_t size) {
    const int F = a->frames;
    double* ms = malloc(sizeof(double) * 4 * (size_t)F);
    if (!ms) {
        snprintf(msg, size, "bench collide: out of memory");
        return -1;
    }
    weft_frame_stats st;
    int f = 0, rc = 0;
    out->warmup = -1;
    for (; f < a->max_warmup && out->warmup < 0 && rc == 0; ++f) {
        const weft_frame fr = scene_host_frame(h, sc, f + 1, 1.0 / FPS);
        rc = weft_cloth_step(h->ctx, h->cloth, &fr, &st) == WEFT_OK ? 0 : -1;
        if (rc == 0 && st.contacts > 0) out->warmup = f + 1;
    }
    for (int k = 0; k < a->settle + F && rc == 0; ++k, ++f) {
        const weft_frame fr = scene_host_frame(h, sc, f + 1, 1.0 / FPS);
        memset(&st, 0, sizeof st);
        const weft_status s = weft_cloth_step(h->ctx, h->cloth, &fr, &st);
        rc = s == WEFT_OK || s == WEFT_ERROR_STEP_FAILED ? 0 : -1;
        const int t = k - a->settle;
        if (rc != 0 || t < 0) continue;
        ms[t] = st.ms_total;
        ms[F + t] = st.ms_collide;
        ms[2 * F + t] = st.ms_self_collide;
        ms[3 * F + t] = st.ms_solve;
        out->self_proximity += st.self_proximity;
        out->self_impacts += st.self_impacts;
        out->self_zones += st.self_zones;
        out->self_unresolved += st.self_unresolved;
        out->iterations += st.iterations;
        out->substeps_timed += st.substeps;
        out->contacts = st.contacts;
    }
    weft_collision_check chk;
    if (rc == 0 && weft_cloth_check_collisions(h->ctx, h->cloth, &chk) != WEFT_OK) rc = -1;
    if (rc != 0) {
        snprintf(msg, size, "bench collide: %s", scene_host_error(h));
        free(ms);
        return -1;
    }
    out->total_min = out->total_max = ms[0];
    for (int k = 1; k < F; ++k) {
        out->total_min = fmin(out->total_min, ms[k]);
        out->total_max = fmax(out->total_max, ms[k]);
    }
    out->total = cli_sort_median(ms, F);
    out->collide = cli_sort_median(ms + F, F);
    out->self = cli_sort_median(ms + 2 * F, F);
    out->solve = cli_sort_median(ms + 3 * F, F);
    out->share = out->total > 0 ? (out->collide + out->self) / out->total : NAN;
    out->iterations = out->substeps_timed > 0 ? out->iterations / (double)out->substeps_timed : 0.0;
    out->penetration = chk.max_penetration;
    out->intersections = chk.self_intersections;
    free(ms);
    return 0;
}

/* One (sheet, body) configuration: the drape scene without its sphere, the mesh body under it. */
static int run_one(const bench_scene* bs, int rings, int backend, const collide_args* a, collide_run* out, char* msg,
                   size_t size) {
    memset(out, 0, sizeof *out);
    out->backend = backend;
    bench_body body;
    const double center[3] = {0.0, 0.0, 0.0}, radii[3] = {BODY_RADIUS, BODY_RADIUS, BODY_RADIUS};
    if (bench_body_create(&body, rings, center, radii, msg, size) != 0) return -1;
    scene sc = bs->sc;   /* the library's defaults, self-collision on, the mesh body instead of the sphere */
    sc.def = bench_run_def(bs);
    sc.def.substeps = 1;
    sc.def.self_collision = 1;
    sc.n_colliders = 0;
    sc.fps = FPS;
    const weft_mesh_collider_def mesh = bench_body_collider(&body, BODY_THICKNESS, BODY_FRICTION);
    scene_host_opts ho;
    memset(&ho, 0, sizeof ho);
    ho.ctx = bench_backend_context(backend);
    ho.mesh_colliders = &mesh;
    ho.n_mesh_colliders = 1;
    scene_host h;
    int rc = scene_host_create(&h, &sc, &ho, bs->name, msg, size) == WEFT_OK ? 0 : -1;
    bench_body_free(&body);   /* read at creation */
    if (rc != 0) return -1;
    out->n = (int)lround(sqrt((double)h.info.n_particles));
    out->particles = h.info.n_particles;
    out->tris = 4 * rings * (rings - 1);
    out->threads = h.info.threads;
    rc = time_frames(&h, &sc, a, out, msg, size);
    scene_host_destroy(&h);
    return rc;
}

enum {
    C_BACKEND, C_N, C_PARTICLES, C_TRIS, C_WARMUP, C_FRAMES, C_ITER, C_TOTAL, C_COLLIDE, C_SELF, C_SOLVE, C_SHARE, C_MIN, C_MAX,
    C_CONTACTS, C_PROX, C_IMPACTS, C_ZONES, C_UNRESOLVED, C_PEN, C_INTERSECT, N_COLS
};
static const char* const csv_cols[N_COLS] = {
    "backend", "n", "particles", "body_triangles", "warmup_frames", "frames", "iterations_per_substep", "ms_total",
    "ms_collide", "ms_self", "ms_solve", "collision_share", "ms_total_min", "ms_total_max", "contacts",
    "self_proximity", "self_impacts", "self_zones", "self_unresolved", "max_penetration_mm",
    "self_intersections"};
static const char* const md_cols[N_COLS] = {
    "backend", NULL, "particles", "body tris", "warm-up", NULL, "it./substep", "total ms", "collide", "self", "solve",
    "share", "min", "max", "contacts", NULL, "self impacts", "zones", NULL, "penetration mm", "self-intersections"};

typedef struct header_info {
    const collide_args* a;
    int threads;
    const collide_run* goal[BENCH_MAX_BACKENDS];    /* each backend's goal row, or NULL when not run */
} header_info;

static void print_header(FILE* out, const void* ctx) {
    const header_info* h = ctx;
    char blas[64], note[512];
    fprintf(out,
            "## weft bench collide\n\n%s. %d OpenMP thread(s), %s. A 1 m sheet "
            "of N x N particles (drapeN) falling onto a triangle-mesh sphere (radius 0.25 m), self-collision on "
            "(3 mm), one step per frame at 30 frames/s, each backend's solver defaults (CPU: PCG with the "
            "multigrid preconditioner, two Newton iterations with line search); after the first touch (warm-up: frames until it, "
            "then %d more), %d frames timed per configuration; medians of the stage times weft_cloth_step reports "
            "(ms per frame; total: the whole call). collide: the colliders' passes (mesh contacts: BVH refit and queries); self: "
            "self-collision; share: (collide + self) / total. min/max: the fastest and slowest timed "
            "frame (total). Error side, at the last frame: the deepest penetration into the body and the "
            "self-intersecting edge-triangle pairs (both 0 when the collisions are resolved).\n\n",
            bench_backend_note(h->a->backends, h->a->n_backends, note, sizeof note), h->threads,
            bench_blas_note(&h->a->com, blas, sizeof blas), h->a->settle, h->a->frames);
    for (int b = 0; b < h->a->n_backends; ++b) {
        const collide_run* g = h->goal[b];
        const char* name = bench_backend_name(h->a->backends[b]);
        if (g)
            fprintf(out,
                    "Goal (%s): self-collision plus a 20k-triangle body under %.0f %% of the frame at 25,600 "
                    "particles, one step per frame: %s: %.1f %% (collide %.3f + self %.3f of %.3f ms; body %d "
                    "triangles; %.1f points %s the goal).\n\n",
                    name, 100.0 * GOAL_SHARE, g->share < GOAL_SHARE ? "met" : "NOT met", 100.0 * g->share,
                    g->collide, g->self, g->total, g->tris, 100.0 * fabs(g->share - GOAL_SHARE),
                    g->share < GOAL_SHARE ? "under" : "over");
        else
            fprintf(out, "Goal (%s; a 20k-triangle body at 160 x 160 particles): not run here (needs --cloth "
                         "160 and a --body near 20000).\n\n", name);
    }
}

int bench_collide_run(int argc, char** argv) {
    collide_args a;
    int rc = bench_parse_args(argc, argv, "weft bench collide", bench_collide_usage, defaults, own_option, &a, &a.com);
    if (rc >= 0) return rc;
    if (a.com.plot)
        return cli_usage_error("weft bench collide", bench_collide_usage, "--plot: this command has no plot");
    const int nr = a.n_backends * a.n_cloth * a.n_body;
    collide_run* runs = calloc((size_t)nr, sizeof *runs);
    if (!runs) {
        cli_error("bench collide: out of memory");
        return CLI_EXIT_FAILURE;
    }
    char msg[1024];
    if (bench_open_backends(a.backends, a.n_backends, a.com.threads) != CLI_EXIT_OK) {
        free(runs);
        return CLI_EXIT_FAILURE;
    }
    /* the body nearest GOAL_TRIS triangles among those asked for */
    int goal_body = -1;
    for (int b = 0; b < a.n_body; ++b) {
        const int t = 4 * bench_body_rings(a.body[b]) * (bench_body_rings(a.body[b]) - 1);
        if (goal_body < 0 || abs(t - GOAL_TRIS) < abs(4 * bench_body_rings(a.body[goal_body]) *
                                                                (bench_body_rings(a.body[goal_body]) - 1) -
                                                            GOAL_TRIS))
            goal_body = b;
    }
    header_info hi = {&a, 0, {NULL}};
    for (int c = 0; c < a.n_cloth && rc < 0; ++c) {
        char name[32];
        snprintf(name, sizeof name, "drape%d", a.cloth[c]);
        bench_scene bs;
        if (bench_scene_build(&bs, name, a.com.garment, 1.0, 1.0, msg, sizeof msg) != 0) {
            cli_error(msg);
            rc = CLI_EXIT_FAILURE;
            break;
        }
        for (int k = 0; k < a.n_backends * a.n_body && rc < 0; ++k) {
            const int be = k / a.n_body, b = k % a.n_body;   /* rows: backend, then cloth, then body */
            const int q = (be * a.n_cloth + c) * a.n_body + b;
            collide_run* r = &runs[q];
            const int rings = bench_body_rings(a.body[b]);
            if (!a.com.quiet)
                fprintf(stderr, "[%d/%d] %s: %d x %d particles, body of %d triangles\n",
                        c * a.n_backends * a.n_body + k + 1, nr, bench_backend_name(a.backends[be]), a.cloth[c],
                        a.cloth[c], 4 * rings * (rings - 1));
            if (run_one(&bs, rings, a.backends[be], &a, r, msg, sizeof msg) != 0) {
                cli_error(msg);
                rc = CLI_EXIT_FAILURE;
            }
            if (a.cloth[c] == GOAL_N && b == goal_body) hi.goal[be] = r;
        }
        bench_scene_free(&bs);
    }
    bench_table t;
    bench_table_init(&t, N_COLS, csv_cols, md_cols);
    for (int q = 0; q < nr && rc < 0; ++q) {
        const collide_run* r = &runs[q];
        char c[N_COLS][64];
        snprintf(c[C_BACKEND], 64, "%s", bench_backend_name(r->backend));
        snprintf(c[C_N], 64, "%d", r->n);
        snprintf(c[C_PARTICLES], 64, "%d", r->particles);
        snprintf(c[C_TRIS], 64, "%d", r->tris);
        snprintf(c[C_WARMUP], 64, "%d", r->warmup);
        snprintf(c[C_FRAMES], 64, "%d", a.frames);
        bench_fmt(c[C_ITER], 64, "%.1f", r->iterations);
        bench_fmt(c[C_TOTAL], 64, "%.3f", r->total);
        bench_fmt(c[C_COLLIDE], 64, "%.3f", r->collide);
        bench_fmt(c[C_SELF], 64, "%.3f", r->self);
        bench_fmt(c[C_SOLVE], 64, "%.3f", r->solve);
        bench_fmt(c[C_SHARE], 64, "%.3f", r->share);
        bench_fmt(c[C_MIN], 64, "%.3f", r->total_min);
        bench_fmt(c[C_MAX], 64, "%.3f", r->total_max);
        snprintf(c[C_CONTACTS], 64, "%d", r->contacts);
        snprintf(c[C_PROX], 64, "%lld", r->self_proximity);
        snprintf(c[C_IMPACTS], 64, "%lld", r->self_impacts);
        snprintf(c[C_ZONES], 64, "%lld", r->self_zones);
        snprintf(c[C_UNRESOLVED], 64, "%lld", r->self_unresolved);
        bench_fmt(c[C_PEN], 64, "%.3g", 1e3 * r->penetration);
        snprintf(c[C_INTERSECT], 64, "%d", r->intersections);
        const char* cell[N_COLS];
        for (int j = 0; j < N_COLS; ++j) cell[j] = c[j];
        if (bench_table_add(&t, cell) != 0) rc = CLI_EXIT_FAILURE;
    }
    if (rc < 0) {
        hi.threads = runs[0].threads;
        rc = bench_write_tables(&a.com, &t, print_header, &hi);
    }
    bench_table_free(&t);
    free(runs);
    return rc;
}
