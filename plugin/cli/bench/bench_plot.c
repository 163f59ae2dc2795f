/* The benchmark plots, drawn with PLplot (Debian libplplot-dev) to PNG through its cairo driver
 * (plplot-driver-cairo, device "pngcairo"). PLplot keeps one global plotting stream: these
 * functions are for the single-threaded CLI only. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <plplot.h>
#include <stdlib.h>
#include <string.h>

#include "bench_plot.h"
#include "names.h"

enum { N_SOLVERS = 4 };   /* weft_solver's values */

/* Colour map 0 entries. */
enum { COL_WHITE = 0, COL_BLACK = 1, COL_SOLVER = 2 /* + weft_solver */, COL_GRID = 6, COL_SURVIVED = 7,
       COL_RECOVERED = 8, COL_FAILED = 9, N_COLOURS = 10 };

static const char* const solver_glyph[N_SOLVERS] = {"#(840)", "#(841)", "#(842)", "#(843)"};

static void set_colours(void) {
    static const int rgb[N_COLOURS][3] = {
        {255, 255, 255}, {0, 0, 0},                                         /* background, text */
        {31, 119, 180}, {255, 127, 14}, {44, 160, 44}, {214, 39, 40},       /* pcg jacobi chebyshev direct */
        {200, 200, 200},                                                    /* grid lines */
        {90, 180, 90}, {245, 200, 60}, {205, 60, 60}};                      /* survived recovered failed */
    plscmap0n(N_COLOURS);
    for (int k = 0; k < N_COLOURS; ++k) plscol0(k, rgb[k][0], rgb[k][1], rgb[k][2]);
}

/* Opens the PNG stream: 0, or -1 (with msg) when the file cannot be written. */
static int begin(const char* path, int width, int height, int nx, int ny, char* msg, size_t msg_size) {
    FILE* f = fopen(path, "wb");   /* PLplot exits the process on an unwritable file: check first */
    if (!f) {
        snprintf(msg, msg_size, "cannot write %s", path);
        return -1;
    }
    fclose(f);
    plsdev("pngcairo");
    plsfnam(path);
    plspage(0, 0, width, height, 0, 0);
    set_colours();
    plssub(nx, ny);
    plinit();
    plfontld(1);
    return 0;
}

/* Grid of panels for n plots: columns and rows. */
static void layout(int n, int* nx, int* ny) {
    *nx = n <= 1 ? 1 : n <= 4 ? 2 : 3;
    *ny = (n + *nx - 1) / *nx;
}

typedef struct xy {
    double x, y;
} xy;

static int cmp_xy(const void* a, const void* b) {
    const xy *p = a, *q = b;
    if (p->x != q->x) return (p->x > q->x) - (p->x < q->x);
    return (p->y > q->y) - (p->y < q->y);
}

/* Sort the points by x and keep the Pareto front (each kept point has a lower y than every point
 * with a smaller x). Returns the front's length; the front is in p[0..k). */
static int pareto(xy* p, int n) {
    qsort(p, (size_t)n, sizeof *p, cmp_xy);
    int k = 0;
    for (int i = 0; i < n; ++i)
        if (k == 0 || p[i].y < p[k - 1].y) p[k++] = p[i];
    return k;
}

static void draw_line(const xy* p, int n) {
    for (int i = 0; i + 1 < n; ++i) {
        PLFLT x[2] = {p[i].x, p[i + 1].x}, y[2] = {p[i].y, p[i + 1].y};
        plline(2, x, y);
    }
}

int bench_plot_accuracy(const char* path, const char* const* panel_names, int n_panels, const bench_point* pts,
                        int n_pts, const char* y_label, char* msg, size_t msg_size) {
    int nx, ny;
    layout(n_panels, &nx, &ny);
    xy* buf = malloc(sizeof *buf * (size_t)(n_pts > 0 ? n_pts : 1));
    if (!buf) {
        snprintf(msg, msg_size, "out of memory");
        return -1;
    }
    if (begin(path, 400 * nx, 330 * ny, nx, ny, msg, msg_size) != 0) {
        free(buf);
        return -1;
    }
    for (int p = 0; p < n_panels; ++p) {
        pladv(0);
        double x0 = INFINITY, x1 = -INFINITY, y0 = INFINITY, y1 = -INFINITY;
        int drawn = 0;
        for (int i = 0; i < n_pts; ++i) {
            const bench_point* q = &pts[i];
            if (q->panel != p || !(q->ms > 0) || !(q->error > 0) || !isfinite(q->ms) || !isfinite(q->error)) continue;
            x0 = fmin(x0, log10(q->ms));
            x1 = fmax(x1, log10(q->ms));
            y0 = fmin(y0, log10(q->error));
            y1 = fmax(y1, log10(q->error));
            ++drawn;
        }
        if (!drawn) x0 = y0 = -1, x1 = y1 = 1;
        x0 = floor(x0 - 0.05), x1 = ceil(x1 + 0.05), y0 = floor(y0 - 0.05), y1 = ceil(y1 + 0.05);
        plschr(0, 0.8);
        plvsta();
        plwind(x0, x1, y0, y1);
        plcol0(COL_GRID);
        plbox("g", 1, 0, "g", 1, 0);
        plcol0(COL_BLACK);
        plbox("bcnstl", 0, 0, "bcnstvl", 0, 0);
        pllab("ms per frame (median)", y_label, panel_names[p]);
        for (int s = 0; s < N_SOLVERS; ++s) {
            int n = 0;
            for (int i = 0; i < n_pts; ++i) {
                const bench_point* q = &pts[i];
                if (q->panel != p || q->solver != s || !(q->ms > 0) || !(q->error > 0) || !isfinite(q->ms) ||
                    !isfinite(q->error))
                    continue;
                buf[n++] = (xy){log10(q->ms), log10(q->error)};
            }
            if (n == 0) continue;
            plcol0(COL_SOLVER + s);
            for (int i = 0; i < n; ++i) {
                PLFLT x = buf[i].x, y = buf[i].y;
                plstring(1, &x, &y, solver_glyph[s]);
            }
            int k = pareto(buf, n);
            plwidth(1.5);
            draw_line(buf, k);
            plwidth(1.0);
        }
        /* the Pareto front over every solver: dashed black line, large open circles */
        int n = 0;
        for (int i = 0; i < n_pts; ++i) {
            const bench_point* q = &pts[i];
            if (q->panel != p || !(q->ms > 0) || !(q->error > 0) || !isfinite(q->ms) || !isfinite(q->error)) continue;
            buf[n++] = (xy){log10(q->ms), log10(q->error)};
        }
        int k = pareto(buf, n);
        plcol0(COL_BLACK);
        pllsty(2);
        draw_line(buf, k);
        pllsty(1);
        plschr(0, 1.6);
        for (int i = 0; i < k; ++i) {
            PLFLT x = buf[i].x, y = buf[i].y;
            plstring(1, &x, &y, "#(840)");
        }
        plschr(0, 0.8);
        if (p == 0) {
            PLINT opt[N_SOLVERS + 1], tcol[N_SOLVERS + 1], lcol[N_SOLVERS + 1],
                lsty[N_SOLVERS + 1], scol[N_SOLVERS + 1], snum[N_SOLVERS + 1];
            PLFLT lwid[N_SOLVERS + 1], sscale[N_SOLVERS + 1];
            const char* text[N_SOLVERS + 1];
            const char* sym[N_SOLVERS + 1];
            for (int s = 0; s <= N_SOLVERS; ++s) {
                int front = s == N_SOLVERS;
                opt[s] = PL_LEGEND_LINE | PL_LEGEND_SYMBOL;
                tcol[s] = COL_BLACK;
                lcol[s] = scol[s] = front ? COL_BLACK : COL_SOLVER + s;
                lsty[s] = front ? 2 : 1;
                lwid[s] = front ? 1.0 : 1.5;
                sscale[s] = front ? 1.4 : 1.0;
                snum[s] = 1;
                sym[s] = front ? "#(840)" : solver_glyph[s];
                text[s] = front ? "Pareto front" : cli_solver_name((weft_solver)s);
            }
            PLFLT lw, lh;
            pllegend(&lw, &lh, PL_LEGEND_BACKGROUND | PL_LEGEND_BOUNDING_BOX,
                     PL_POSITION_TOP | PL_POSITION_RIGHT | PL_POSITION_INSIDE, 0.02, 0.02, 0.08, COL_WHITE,
                     COL_BLACK, 1, 0, 0, N_SOLVERS + 1, opt, 0.6, 0.7, 1.6, 1.0, tcol, text, NULL, NULL,
                     NULL, NULL, lcol, lsty, lwid, scol, sscale, snum, sym);
        }
    }
    plend();
    free(buf);
    return 0;
}

int bench_plot_heatmap(const char* path, const char* const* panel_names, int n_panels, const char* const* col_labels,
                       int n_cols, const char* const* row_labels, int n_rows, const int* outcome,
                       const char* const* cell_text, const char* title, char* msg, size_t msg_size) {
    int nx, ny;
    layout(n_panels, &nx, &ny);
    int height = 120 + 18 * n_rows;
    if (height < 300) height = 300;
    if (begin(path, 520 * nx, height * ny, nx, ny, msg, msg_size) != 0) return -1;
    static const int colour[3] = {COL_SURVIVED, COL_RECOVERED, COL_FAILED};
    for (int p = 0; p < n_panels; ++p) {
        pladv(0);
        plschr(0, 0.7);
        plvpor(0.30, 0.97, 0.14, 0.86);
        plwind(0, n_cols, 0, n_rows);
        for (int r = 0; r < n_rows; ++r)
            for (int c = 0; c < n_cols; ++c) {
                const int idx = (p * n_rows + r) * n_cols + c;
                const int o = outcome[idx];
                PLFLT x[4] = {c, c + 1, c + 1, c}, y[4] = {r, r, r + 1, r + 1};
                plcol0(o >= 0 && o <= 2 ? colour[o] : COL_GRID);
                plfill(4, x, y);
                plcol0(COL_WHITE);
                plline(4, x, y);
                if (cell_text && cell_text[idx] && cell_text[idx][0]) {
                    plcol0(COL_BLACK);
                    plschr(0, 0.55);
                    plptex(c + 0.5, r + 0.35, 1, 0, 0.5, cell_text[idx]);
                    plschr(0, 0.7);
                }
            }
        plcol0(COL_BLACK);
        plbox("bc", 0, 0, "bc", 0, 0);
        for (int c = 0; c < n_cols; ++c) plmtex("b", 1.2, (c + 0.5) / n_cols, 0.5, col_labels[c]);
        for (int r = 0; r < n_rows; ++r) plmtex("lv", 0.6, (r + 0.5) / n_rows, 1.0, row_labels[r]);
        plmtex("b", 2.8, 0.5, 0.5, "step length (s)");
        plschr(0, 0.9);
        plmtex("t", 2.2, 0.5, 0.5, panel_names[p]);
        plschr(0, 0.6);
        plmtex("t", 0.9, 0.5, 0.5, title);
        plschr(0, 0.55);
        plmtex("b", 5.4, 0.5, 0.5, "green: survived, yellow: recovered (rollbacks), red: failed (why)");
    }
    plend();
    return 0;
}
