/* `weft bench crowd`: N copies of one cloth stepped every frame, one weft_cloth_step per cloth
 * (unbatched) against one weft_context_step for all of them (batched), ms a frame against N, on
 * the CPU at each thread count asked for and on the GPU. Both sets of N cloths live in the same
 * context and get the same frames (the scene's motion), the two timed in turn frame by frame, in
 * alternating order, so that the machine's load weighs on both alike; at the end the first
 * cloth of each set is compared: on the CPU the batch must give the single calls' positions bit
 * for bit (exit status 1 otherwise, and when a step fails). */
#define _POSIX_C_SOURCE 200809L
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "bench_args.h"
#include "bench_backend.h"
#include "bench_commands.h"
#include "bench_run.h"
#include "bench_table.h"
#include "cli.h"
#include "scene_host.h"

#define FPS 60.0
#define WARMUP 3            /* frames stepped before the timed ones (both sets) */

typedef struct crowd_args {
    const char* scene;
    int counts[BENCH_MAX_LIST], n_counts;
    int cpu_threads[BENCH_MAX_LIST], n_threads;
    int frames;
    int backends[BENCH_MAX_BACKENDS];
    int n_backends;
    bench_common com;
} crowd_args;

void bench_crowd_usage(FILE* out) {
    fputs("usage: weft bench crowd [--quick] [--scene NAME] [--counts LIST] [--cpu-threads LIST]\n"
          "                        [--frames N] [--backend LIST] [--csv FILE] [--md FILE] [--quiet]\n"
          "\n"
          "Many copies of one cloth in one context, stepped every frame one call per cloth\n"
          "(weft_cloth_step, `unbatched`) and in one call for all (weft_context_step, `batched`).\n"
          "For every backend, CPU thread count and count N: 2 N cloths are made (N per way), stepped\n"
          "--frames frames at 60 frames/s after 3 warm-up frames, the two ways timed in turn frame\n"
          "by frame. Columns: median ms per frame (all N cloths, the whole calls), the unbatched\n"
          "time over the batched one, ms per cloth batched, and whether the batch gave the first\n"
          "cloth the single calls' positions bit for bit.\n"
          "\n"
          "options:\n"
          "  --quick              seconds-long preset: sheet16, counts 1,4, 5 frames, 1 thread\n"
          "  --scene NAME         sheetN, hangN, drape, drapeN or garment as in `weft bench accuracy`\n"
          "                       (default garment: sample_scenes/skirt.obj, twirled)\n"
          "  --counts LIST        cloth counts N (default 1,2,4,8,16,32,64)\n"
          "  --cpu-threads LIST   OpenMP threads of the CPU contexts (default 1,2); the GPU's: 1\n"
          "  --frames N           frames timed per row (default 20)\n"
          "  --csv FILE           write every row as CSV\n"
          "  --md FILE            write the Markdown table to FILE instead of stdout\n"
          "  --backend LIST       cpu, gpu or cpu,gpu (default cpu; gpu: a headless EGL context,\n"
          "                       llvmpipe without a GPU)\n"
          "  --quiet              no progress lines on stderr\n"
          "  -h, --help           show this help\n",
          out);
}

static void defaults(void* args, int quick) {
    crowd_args* a = args;
    memset(a, 0, sizeof *a);
    a->scene = quick ? "sheet16" : "garment";
    static const int counts[] = {1, 2, 4, 8, 16, 32, 64};
    a->n_counts = quick ? 2 : 7;
    for (int k = 0; k < a->n_counts; ++k) a->counts[k] = quick ? (k ? 4 : 1) : counts[k];
    a->cpu_threads[0] = 1;
    a->cpu_threads[1] = 2;
    a->n_threads = quick ? 1 : 2;
    a->frames = quick ? 5 : 20;
    a->backends[0] = BENCH_CPU;
    a->n_backends = 1;
}

static int own_option(void* args, int argc, char** argv, int* i, const char** v) {
    crowd_args* a = args;
    int m = 0;
    if ((m = cli_option_value(argc, argv, i, "--scene", v)) != 0) {
        if (m > 0) a->scene = *v;
        return m;
    }
    if ((m = cli_option_value(argc, argv, i, "--counts", v)) != 0)
        return m < 0 ? m : (a->n_counts = bench_parse_ints(*v, 1, 4096, a->counts)) < 0 ? -2 : 1;
    if ((m = cli_option_value(argc, argv, i, "--cpu-threads", v)) != 0)
        return m < 0 ? m : (a->n_threads = bench_parse_ints(*v, 1, 64, a->cpu_threads)) < 0 ? -2 : 1;
    if ((m = cli_option_value(argc, argv, i, "--frames", v)) != 0)
        return m < 0 ? m : cli_parse_int(*v, 1, 100000, &a->frames) != 0 ? -2 : 1;
    if ((m = cli_option_value(argc, argv, i, "--backend", v)) != 0)
        return m < 0 ? m : (a->n_backends = bench_parse_backends(*v, a->backends)) < 0 ? -2 : 1;
    return 0;
}

static double now_ms(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return 1e3 * (double)ts.tv_sec + 1e-6 * (double)ts.tv_nsec;
}

/* One row: N cloths each way on one context. */
typedef struct crowd_row {
    int backend, threads, count, particles;
    double ms_single, ms_batch; /* medians, ms a frame for all N */
    int identical;              /* 1: the first cloths' positions bit-identical */
    int failures;               /* steps refused or failed (either way) */
} crowd_row;

/* The two sets of cloths (hosts [0, N) unbatched, [N, 2N) batched) and the batch's arrays. */
typedef struct crowd {
    scene_host* hosts;
    int live;
    weft_cloth* cloths;
    weft_frame* frames;
    weft_status* statuses;
    double *ms_single, *ms_batch;
} crowd;

static void crowd_free(crowd* c) {
    for (int k = 0; k < c->live; ++k) scene_host_destroy(&c->hosts[k]);
    free(c->hosts);
    free(c->cloths);
    free(c->frames);
    free(c->statuses);
    free(c->ms_single);
    free(c->ms_batch);
    memset(c, 0, sizeof *c);
}

/* Host k's frame f (1-based), the scene's twirl on its pins. */
static weft_frame host_frame(scene_host* h, const bench_scene* bs, const scene* sc, int f) {
    weft_frame fr = scene_host_frame(h, sc, f, 1.0 / FPS);
    if (bs->spin != 0)
        for (int i = 0; i < h->n_attachments; ++i) bench_scene_pin_transform(bs, f / FPS, h->attachment_xf + 16 * (size_t)i);
    return fr;
}

/* Frame f of one set: the unbatched one (one call per cloth) or the batched one; its wall time. */
static double step_set(crowd* c, const bench_scene* bs, const scene* sc, int n, int batched, int f, int* failures) {
    const double t0 = now_ms();
    if (batched) {
        for (int k = 0; k < n; ++k) c->frames[k] = host_frame(&c->hosts[n + k], bs, sc, f);
        if (weft_context_step(c->hosts[n].ctx, n, c->cloths, c->frames, NULL, c->statuses) != WEFT_OK)
            for (int k = 0; k < n; ++k) *failures += c->statuses[k] != WEFT_OK;
    } else {
        for (int k = 0; k < n; ++k) {
            weft_frame fr = host_frame(&c->hosts[k], bs, sc, f);
            if (weft_cloth_step(c->hosts[k].ctx, c->hosts[k].cloth, &fr, NULL) != WEFT_OK) ++*failures;
        }
    }
    return now_ms() - t0;
}

static int run_row(weft_context* ctx, const bench_scene* bs, const crowd_args* a, crowd_row* row, char* msg,
                   size_t size) {
    const int n = row->count;
    crowd c;
    memset(&c, 0, sizeof c);
    scene sc = bs->sc;
    sc.def = bench_run_def(bs);   /* sleeping off: active steps are timed */
    c.hosts = calloc(2 * (size_t)n, sizeof *c.hosts);
    c.cloths = calloc((size_t)n, sizeof *c.cloths);
    c.frames = calloc((size_t)n, sizeof *c.frames);
    c.statuses = calloc((size_t)n, sizeof *c.statuses);
    c.ms_single = calloc((size_t)a->frames, sizeof(double));
    c.ms_batch = calloc((size_t)a->frames, sizeof(double));
    if (!c.hosts || !c.cloths || !c.frames || !c.statuses || !c.ms_single || !c.ms_batch) {
        snprintf(msg, size, "bench crowd: out of memory");
        crowd_free(&c);
        return -1;
    }
    scene_host_opts ho;
    memset(&ho, 0, sizeof ho);
    ho.ctx = ctx;
    for (int k = 0; k < 2 * n; ++k, ++c.live)
        if (scene_host_create(&c.hosts[k], &sc, &ho, bs->name, msg, size) != WEFT_OK) {
            crowd_free(&c);
            return -1;
        }
    for (int k = 0; k < n; ++k) c.cloths[k] = c.hosts[n + k].cloth;
    row->particles = c.hosts[0].info.n_particles;
    for (int f = 1; f <= WARMUP; ++f) {
        step_set(&c, bs, &sc, n, 0, f, &row->failures);
        step_set(&c, bs, &sc, n, 1, f, &row->failures);
    }
    for (int f = 0; f < a->frames; ++f) {
        const int first = f % 2;   /* alternate which way goes first */
        const int frame = WARMUP + 1 + f;
        double* ms[2] = {c.ms_single, c.ms_batch};
        ms[first][f] = step_set(&c, bs, &sc, n, first, frame, &row->failures);
        ms[!first][f] = step_set(&c, bs, &sc, n, !first, frame, &row->failures);
    }
    row->ms_single = cli_sort_median(c.ms_single, a->frames);
    row->ms_batch = cli_sort_median(c.ms_batch, a->frames);
    row->identical = scene_host_read_positions(&c.hosts[0]) == WEFT_OK &&
                     scene_host_read_positions(&c.hosts[n]) == WEFT_OK &&
                     memcmp(c.hosts[0].positions, c.hosts[n].positions,
                            3 * sizeof(float) * (size_t)c.hosts[0].info.n_vertices) == 0;
    crowd_free(&c);
    return 0;
}

enum { C_BACKEND, C_THREADS, C_SCENE, C_PARTICLES, C_COUNT, C_SINGLE, C_BATCH, C_RATIO, C_PER_CLOTH, C_SAME,
       C_FAILURES, N_COLS };
static const char* const csv_cols[N_COLS] = {"backend", "threads", "scene", "particles", "cloths",
                                             "ms_unbatched", "ms_batched", "unbatched_over_batched",
                                             "ms_per_cloth_batched", "identical", "failures"};
static const char* const md_cols[N_COLS] = {"backend", "threads", NULL, NULL, "cloths N", "unbatched ms/frame",
                                            "batched ms/frame", "unbatched / batched", "batched ms/cloth",
                                            "same bits", NULL};

typedef struct header_info {
    const crowd_args* a;
    int particles;
} header_info;

static void print_header(FILE* out, const void* ctx) {
    const header_info* h = ctx;
    char note[1024];
    fprintf(out, "## weft bench crowd\n\n%s. Scene %s (%d particles a cloth), N copies in one context, "
                 "%d frames timed at 60 frames/s after %d warm-up frames; median wall time of a frame for "
                 "all N cloths: one weft_cloth_step per cloth (unbatched) against one weft_context_step "
                 "(batched). Same bits: the batch gave its first cloth the single calls' positions bit for "
                 "bit.\n\n",
            bench_backend_note(h->a->backends, h->a->n_backends, note, sizeof note), h->a->scene, h->particles,
            h->a->frames, WARMUP);
}

int bench_crowd_run(int argc, char** argv) {
    crowd_args a;
    int rc = bench_parse_args(argc, argv, "weft bench crowd", bench_crowd_usage, defaults, own_option, &a, &a.com);
    if (rc >= 0) return rc;
    if (a.com.plot) return cli_usage_error("weft bench crowd", bench_crowd_usage, "--plot: this command has no plot");
    bench_scene bs;
    char msg[1024];
    if (bench_scene_build(&bs, a.scene, a.com.garment, 1.0, 1.0, msg, sizeof msg) != 0) {
        cli_error(msg);
        return CLI_EXIT_FAILURE;
    }
    /* rows: every backend, its thread counts (the GPU: 1), every count */
    static crowd_row rows[BENCH_MAX_BACKENDS * BENCH_MAX_LIST * BENCH_MAX_LIST];
    int n_rows = 0;
    for (int b = 0; b < a.n_backends && rc < 0; ++b) {
        const int gpu = a.backends[b] == BENCH_GPU;
        for (int t = 0; t < (gpu ? 1 : a.n_threads) && rc < 0; ++t) {
            weft_context_def cd = weft_default_context_def();
            cd.backend = gpu ? WEFT_BACKEND_GPU : WEFT_BACKEND_CPU;
            cd.threads = gpu ? 1 : a.cpu_threads[t];
            weft_context* ctx = NULL;
            if (gpu) {   /* the shared GPU context: its device is in the notes */
                if (bench_open_backends(&a.backends[b], 1, 1) != CLI_EXIT_OK) rc = CLI_EXIT_FAILURE;
                else ctx = bench_backend_context(BENCH_GPU);
            } else if (weft_context_create(WEFT_ABI, &cd, &ctx) != WEFT_OK) {
                cli_error("bench crowd: cannot create a CPU context");
                rc = CLI_EXIT_FAILURE;
            }
            for (int k = 0; k < a.n_counts && rc < 0; ++k) {
                crowd_row* r = &rows[n_rows];
                memset(r, 0, sizeof *r);
                r->backend = a.backends[b];
                r->threads = cd.threads;
                r->count = a.counts[k];
                if (!a.com.quiet)
                    fprintf(stderr, "%s, %d thread(s): %d + %d cloths\n", bench_backend_name(r->backend), r->threads,
                            r->count, r->count);
                if (run_row(ctx, &bs, &a, r, msg, sizeof msg) != 0) {
                    cli_error(msg);
                    rc = CLI_EXIT_FAILURE;
                } else {
                    ++n_rows;
                }
            }
            if (!gpu) weft_context_destroy(ctx);
        }
    }
    bench_table t;
    bench_table_init(&t, N_COLS, csv_cols, md_cols);
    for (int q = 0; q < n_rows && rc < 0; ++q) {
        const crowd_row* r = &rows[q];
        char c[N_COLS][64];
        snprintf(c[C_BACKEND], 64, "%s", bench_backend_name(r->backend));
        snprintf(c[C_THREADS], 64, "%d", r->threads);
        snprintf(c[C_SCENE], 64, "%s", a.scene);
        snprintf(c[C_PARTICLES], 64, "%d", r->particles);
        snprintf(c[C_COUNT], 64, "%d", r->count);
        bench_fmt(c[C_SINGLE], 64, "%.3f", r->ms_single);
        bench_fmt(c[C_BATCH], 64, "%.3f", r->ms_batch);
        bench_fmt(c[C_RATIO], 64, "%.2f", r->ms_single / r->ms_batch);
        bench_fmt(c[C_PER_CLOTH], 64, "%.3f", r->ms_batch / r->count);
        snprintf(c[C_SAME], 64, "%s", r->identical ? "yes" : "NO");
        snprintf(c[C_FAILURES], 64, "%d", r->failures);
        const char* cells[N_COLS];
        for (int k = 0; k < N_COLS; ++k) cells[k] = c[k];
        if (bench_table_add(&t, cells) != 0) rc = CLI_EXIT_FAILURE;
    }
    if (rc < 0) {
        header_info hi = {&a, n_rows ? rows[0].particles : 0};
        rc = bench_write_tables(&a.com, &t, print_header, &hi);
        for (int q = 0; q < n_rows && rc == CLI_EXIT_OK; ++q)   /* the batch broke its promise (weft.h) */
            if (rows[q].failures || (!rows[q].identical && rows[q].backend == BENCH_CPU)) rc = CLI_EXIT_FAILURE;
    }
    bench_table_free(&t);
    bench_scene_free(&bs);
    return rc;
}
