/* The backends' contexts of a `weft bench` command (bench_backend.h): one weft_context per
 * backend, made by bench_open_backends and kept until bench_close_backends. The GPU context's
 * device is what the library logs at INFO when it makes it. */
#include "bench_backend.h"

#include <stdio.h>
#include <string.h>

#include "bench_args.h"
#include "cli.h"

/* What a context's logger keeps: the last ERROR (a failed creation) and the last INFO (the
 * backend chosen and its device, at creation). Lives as long as the context. */
typedef struct open_log {
    char error[512];
    char info[512];
} open_log;

static weft_context* g_ctx[BENCH_MAX_BACKENDS + 1];   /* by weft_backend value (CPU 1, GPU 2) */
static open_log g_log[BENCH_MAX_BACKENDS + 1];
static char g_gpu_description[512];

static void capture(weft_log_level level, const char* message, void* user) {
    open_log* l = user;
    snprintf(level >= WEFT_LOG_ERROR ? l->error : l->info, sizeof l->error, "%s", message);
}

int bench_parse_backend(const char* name) {
    static const char* const names[] = {"auto", "cpu", "gpu"};   /* weft_backend's order */
    for (int k = 0; k < 3; ++k)
        if (name && !strcmp(name, names[k])) return k;
    return -1;
}

static int one_backend(const char* item, void* ctx, int k) {
    int* out = ctx;
    const int b = !strcmp(item, "cpu") ? BENCH_CPU : !strcmp(item, "gpu") ? BENCH_GPU : -1;
    if (b < 0 || k >= BENCH_MAX_BACKENDS) return -1;
    for (int j = 0; j < k; ++j)
        if (out[j] == b) return -1; /* each at most once */
    out[k] = b;
    return 0;
}

int bench_parse_backends(const char* text, int* out) {
    int tmp[BENCH_MAX_LIST];
    int n = bench_for_each_item(text, one_backend, tmp);
    for (int k = 0; k < n; ++k) out[k] = tmp[k];
    return n;
}

const char* bench_backend_name(int backend) { return backend == BENCH_GPU ? "gpu" : "cpu"; }

weft_context* bench_backend_context(int backend) {
    return backend == BENCH_CPU || backend == BENCH_GPU ? g_ctx[backend] : NULL;
}

const char* bench_gpu_description(void) { return g_ctx[BENCH_GPU] ? g_gpu_description : ""; }

int bench_open_backends(const int* backends, int n, int threads) {
    for (int k = 0; k < n; ++k) {
        const int b = backends[k];
        if (g_ctx[b]) continue;
        open_log* log = &g_log[b];
        memset(log, 0, sizeof *log);
        weft_context_def cd = weft_default_context_def();
        cd.backend = (weft_backend)b;
        cd.threads = threads;
        cd.log = capture;
        cd.log_user = log;
        cd.log_level = WEFT_LOG_INFO;
        weft_status st = weft_context_create(WEFT_ABI, &cd, &g_ctx[b]);
        if (st != WEFT_OK) {
            char msg[1200];
            if (b == BENCH_GPU)
                snprintf(msg, sizeof msg, "--backend gpu: cannot create a headless GL context for the solver: %s",
                         log->error[0] ? log->error : weft_status_string(st));
            else
                snprintf(msg, sizeof msg, "cannot create a CPU context: %s", log->error[0] ? log->error : weft_status_string(st));
            cli_error(msg);
            return CLI_EXIT_FAILURE;
        }
        if (b == BENCH_GPU) {
            /* "weft_context_create: GPU backend (asked for, headless EGL): <device>" */
            const char* at = strstr(log->info, "): ");
            snprintf(g_gpu_description, sizeof g_gpu_description, "%s", at ? at + 3 : log->info);
        }
    }
    return CLI_EXIT_OK;
}

const char* bench_backend_note(const int* backends, int n, char* buf, size_t size) {
    size_t at = 0;
    buf[0] = '\0';
    for (int k = 0; k < n && at < size; ++k) {
        int w;
        if (backends[k] == BENCH_GPU)
            w = snprintf(buf + at, size - at, "%sGPU (weft_cloth_step on %s; positions read back outside the timed "
                         "steps)", k ? " and " : "", bench_gpu_description());
        else
            w = snprintf(buf + at, size - at, "%sCPU (weft_cloth_step)", k ? " and " : "");
        if (w < 0) break;
        at += (size_t)w;
    }
    if (at >= size && size > 0) buf[size - 1] = '\0';
    /* "backend(s): " first */
    char head[16];
    snprintf(head, sizeof head, "%s: ", n > 1 ? "backends" : "backend");
    const size_t hl = strlen(head), bl = strlen(buf);
    if (hl + bl + 1 <= size) {
        memmove(buf + hl, buf, bl + 1);
        memcpy(buf, head, hl);
    }
    return buf;
}

void bench_close_backends(void) {
    for (int b = 0; b <= BENCH_MAX_BACKENDS; ++b) {
        weft_context_destroy(g_ctx[b]);
        g_ctx[b] = NULL;
    }
    g_gpu_description[0] = '\0';
}
