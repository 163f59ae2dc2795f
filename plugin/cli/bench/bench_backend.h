/* The backends `weft bench` runs on: one weft_context per backend for the whole command (a GPU
 * context makes its GL context and compiles the solver's programs once), opened before the runs
 * and closed by the dispatcher when the subcommand returns. Every run steps the library through
 * weft_cloth_step on its backend's context. */
#ifndef WEFT_CLI_BENCH_BACKEND_H
#define WEFT_CLI_BENCH_BACKEND_H
#include <stddef.h>

#include "weft/weft.h"

/* Backends of accuracy, stability, skip and peers (weft_backend's values). */
enum { BENCH_CPU = WEFT_BACKEND_CPU, BENCH_GPU = WEFT_BACKEND_GPU };
#define BENCH_MAX_BACKENDS 2
/* The usage texts' line on --backend. */
#define BENCH_BACKEND_HELP                                                                              \
    "  --backend LIST       cpu, gpu or cpu,gpu (default cpu): every configuration on each backend,\n" \
    "                       a `backend` column telling the rows apart (weft_cloth_step on a CPU or a\n" \
    "                       GPU context: a headless EGL context, llvmpipe without a GPU; positions\n" \
    "                       read back outside the timed steps).\n"

/* Backend names ("cpu", "gpu", "auto") as weft_backend values; -1 when unknown. */
int bench_parse_backend(const char* name);
/* A --backend list: "cpu", "gpu", "cpu,gpu" (each at most once) -> BENCH_CPU/BENCH_GPU in out
 * (BENCH_MAX_BACKENDS). Returns the count, or -1. */
int bench_parse_backends(const char* text, int* out);
/* "cpu" / "gpu". */
const char* bench_backend_name(int backend);

/* Open the listed backends' contexts with `threads` OpenMP threads per call: CLI_EXIT_OK, or
 * CLI_EXIT_FAILURE with the reason on stderr ("--backend gpu: cannot create a headless GL
 * context ...: the library's message"). */
int bench_open_backends(const int* backends, int n, int threads);
/* The open context of a backend (NULL when not open). */
weft_context* bench_backend_context(int backend);
/* The GPU context's device as the library logged it at creation; "" when not open. */
const char* bench_gpu_description(void);
/* The backends run, for the Markdown notes: "backend: CPU (weft_cloth_step)" and/or "GPU
 * (weft_cloth_step on <device>; ...)", joined. */
const char* bench_backend_note(const int* backends, int n, char* buf, size_t size);
/* Destroy the contexts (and every cloth left in them). */
void bench_close_backends(void);

#endif
