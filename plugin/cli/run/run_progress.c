/* The progress line of `weft run` on a terminal. */
#define _POSIX_C_SOURCE 200809L
#include "run_progress.h"

#include <time.h>
#include <unistd.h>

enum { BAR_WIDTH = 24 };

double run_now_ms(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec * 1e-6;
}

void run_progress_begin(run_progress* p, FILE* out, int enabled, int total) {
    p->out = enabled && out && isatty(fileno(out)) ? out : NULL;
    p->total = total;
    p->start_ms = run_now_ms();
    p->drawn_ms = -1e300;
    p->drawn = 0;
}

void run_progress_format(char* buf, size_t cap, int done, int total, double elapsed_ms) {
    const double frac = total > 0 ? (double)done / total : 1.0;
    char bar[BAR_WIDTH + 1];
    const int filled = (int)(frac * BAR_WIDTH + 0.5);
    for (int i = 0; i < BAR_WIDTH; ++i) bar[i] = i < filled ? '#' : '.';
    bar[BAR_WIDTH] = '\0';
    const double per_frame = done > 0 ? elapsed_ms / done : 0.0;
    long eta = (long)(per_frame * (total - done) / 1000.0 + 0.5);
    snprintf(buf, cap, "[%s] frame %d/%d %3d%%  %.1f ms/frame  ETA %ld:%02ld:%02ld", bar, done, total,
             (int)(100.0 * frac), per_frame, eta / 3600, eta / 60 % 60, eta % 60);
}

void run_progress_update(run_progress* p, int done) {
    if (!p->out) return;
    const double now = run_now_ms();
    if (done < p->total && now - p->drawn_ms < RUN_PROGRESS_PERIOD_MS) return;
    char line[160];
    run_progress_format(line, sizeof line, done, p->total, now - p->start_ms);
    fprintf(p->out, "\r%s\033[K", line);
    fflush(p->out);
    p->drawn_ms = now;
    p->drawn = 1;
}

void run_progress_end(run_progress* p) {
    if (!p->out || !p->drawn) return;
    fputs("\r\033[K", p->out);
    fflush(p->out);
    p->drawn = 0;
}
