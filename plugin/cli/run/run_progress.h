/* `weft run`'s progress line on a terminal: "frame k/N, percent, ms/frame, ETA", redrawn in
 * place (carriage return) at most every RUN_PROGRESS_PERIOD_MS and at the last frame, erased at
 * the end so the summary starts on a clean line. Disabled: draws nothing. */
#ifndef WEFT_CLI_RUN_PROGRESS_H
#define WEFT_CLI_RUN_PROGRESS_H
#include <stdio.h>

#define RUN_PROGRESS_PERIOD_MS 100.0

typedef struct run_progress {
    FILE* out;              /* NULL: disabled */
    int total;              /* frames */
    double start_ms;        /* run_now_ms() at begin */
    double drawn_ms;        /* last draw */
    int drawn;              /* something is on the line */
} run_progress;

/* Monotonic wall clock (ms). */
double run_now_ms(void);

/* Draw on out only when enabled is nonzero and out is a terminal. */
void run_progress_begin(run_progress* p, FILE* out, int enabled, int total);
/* done frames of total finished (1..total). */
void run_progress_update(run_progress* p, int done);
/* Erase the line (if anything was drawn). */
void run_progress_end(run_progress* p);
/* The line for done of total frames after elapsed_ms (no newline); for tests and drawing. */
void run_progress_format(char* buf, size_t cap, int done, int total, double elapsed_ms);

#endif
