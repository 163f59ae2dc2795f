/* The benchmark plots (PLplot, pngcairo device; bench_plot.c). */
#ifndef WEFT_CLI_BENCH_PLOT_H
#define WEFT_CLI_BENCH_PLOT_H
#include <stddef.h>

/* One point of the accuracy plot. */
typedef struct bench_point {
    int panel;              /* panel index (scene, or scene x backend) */
    int solver;             /* weft_solver */
    double ms;              /* ms per frame */
    double error;           /* trajectory error (relative); <= 0 points are not drawn */
} bench_point;

/* Error against ms/frame, log-log, one panel per scene, one curve per solver (its own Pareto
 * front through its points), the Pareto front over all solvers marked. 0, or -1 with msg. */
int bench_plot_accuracy(const char* path, const char* const* panel_names, int n_panels, const bench_point* pts,
                        int n_pts, const char* y_label, char* msg, size_t msg_size);

/* Outcome of one stability cell. */
enum { BENCH_SURVIVED = 0, BENCH_RECOVERED = 1, BENCH_FAILED = 2 };

/* Heat map: one panel per solver; columns are the step lengths, rows the (stiffness, mass) pairs;
 * cells coloured by outcome (index = ((solver * n_rows) + row) * n_cols + col), the text
 * cell_text[same index] drawn in the cell (may be NULL). */
int bench_plot_heatmap(const char* path, const char* const* panel_names, int n_panels, const char* const* col_labels,
                       int n_cols, const char* const* row_labels, int n_rows, const int* outcome,
                       const char* const* cell_text, const char* title, char* msg, size_t msg_size);

#endif
