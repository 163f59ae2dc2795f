/* The 3x3-block row kernel (core/bsr_rows.h), scalar and vector (where this CPU has one), against
 * products computed here in long double: random patterns with empty rows, long rows and the last
 * block at the very end of its array (the vector loop must not read past it: arrays are
 * allocated to their exact size, so ASan would see it), y = s + sign A x with s NULL, s distinct
 * and s aliasing y, rows split in two calls as two threads would; and the vector and scalar
 * results within rounding of each other. The single-precision kernels (wc_bsr_rows_f, the
 * multigrid's V-cycle) the same way on the values rounded to float, their arrays allocated to
 * the block count plus WC_BSR_F_PAD exactly. The float-vector kernels (wc_bsr_rows_fx: float x, float
 * sums) against long-double sums of the rounded values within float's rounding of the row's
 * terms, their float copy of y, and the scalar and vector kernels bit for bit (they do the same
 * arithmetic in the same order). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "bsr_rows.h"
#include "check.h"

static unsigned rng = 12345u;
static unsigned next_bits(void) {
    rng = rng * 1664525u + 1013904223u;
    return rng >> 8;
}
/* in [-1, 1) with a full 48-bit mantissa (products and sums round) */
static double uniform(void) {
    double hi = next_bits(), lo = next_bits();
    return (hi * 16777216.0 + lo) / 140737488355328.0 - 1.0;
}

typedef struct pattern {
    int n, nb;
    int* row_start;
    int* col;
    double* val;
    float* valf; /* val rounded (val then holds the rounded values), NULL: a double pattern */
} pattern;

/* n rows; row i holds up to max_row blocks at random columns (some rows none) */
static pattern make_pattern(int n, int max_row) {
    pattern p = {n, 0, malloc(sizeof(int) * (size_t)(n + 1)), NULL, NULL, NULL};
    p.row_start[0] = 0;
    for (int i = 0; i < n; ++i) {
        int len = (int)((uniform() + 1.0) * 0.5 * (max_row + 1));
        if (len > max_row) len = max_row;
        if (i % 7 == 3) len = 0;
        p.row_start[i + 1] = p.row_start[i] + len;
    }
    p.nb = p.row_start[n];
    p.col = malloc(sizeof(int) * (size_t)(p.nb > 0 ? p.nb : 1));
    p.val = malloc(sizeof(double) * 9 * (size_t)(p.nb > 0 ? p.nb : 1));
    for (int k = 0; k < p.nb; ++k) {
        int c = (int)((uniform() + 1.0) * 0.5 * n);
        p.col[k] = c < n ? c : n - 1;
        for (int e = 0; e < 9; ++e) p.val[9 * k + e] = uniform() * 1e3;
    }
    return p;
}

/* p's values rounded to float, in val (for the reference) and valf (for the kernels) */
static void round_pattern(pattern* p) {
    p->valf = calloc(9 * (size_t)p->nb + WC_BSR_F_PAD, sizeof(float));
    for (size_t k = 0; k < 9 * (size_t)p->nb; ++k) {
        p->valf[k] = (float)p->val[k];
        p->val[k] = p->valf[k];
    }
}

static void free_pattern(pattern* p) {
    free(p->valf);
    free(p->row_start);
    free(p->col);
    free(p->val);
}

/* y = s + sign A x in long double, the reference; returns the largest |term| sum per row */
static void reference(const pattern* p, const double* s, double sign, const double* x, long double* y,
                      double* scale) {
    for (int i = 0; i < p->n; ++i) {
        long double acc[3] = {0, 0, 0};
        double mag[3] = {0, 0, 0};
        for (int k = p->row_start[i]; k < p->row_start[i + 1]; ++k)
            for (int r = 0; r < 3; ++r)
                for (int c = 0; c < 3; ++c) {
                    double t = p->val[9 * k + 3 * r + c] * x[3 * p->col[k] + c];
                    acc[r] += t;
                    mag[r] += fabs(t);
                }
        for (int r = 0; r < 3; ++r) {
            y[3 * i + r] = (s ? (long double)s[3 * i + r] : 0.0L) + sign * acc[r];
            scale[3 * i + r] = mag[r] + (s ? fabs(s[3 * i + r]) : 0.0);
        }
    }
}

/* f (or ff on valf) on rows [lo, hi) in two calls (as two threads would split them), against the
 * reference */
static void check_kernel(wc_bsr_rows_fn f, wc_bsr_rows_f_fn ff, const char* name, const pattern* p, double sign,
                         int with_s, int alias, double* out) {
    const int n = p->n;
    double* x = calloc(3 * (size_t)n, sizeof(double)); /* exact size: the last x_j ends the array */
    double* s = calloc(3 * (size_t)n, sizeof(double));
    double* y = malloc(sizeof(double) * 3 * (size_t)n);
    long double* ref = malloc(sizeof(long double) * 3 * (size_t)n);
    double* scale = malloc(sizeof(double) * 3 * (size_t)n);
    for (int q = 0; q < 3 * n; ++q) {
        x[q] = uniform();
        s[q] = uniform() * 10.0;
        y[q] = NAN;
    }
    reference(p, with_s ? s : NULL, sign, x, ref, scale);
    const double* sp = NULL;
    if (with_s && alias) {
        memcpy(y, s, sizeof(double) * 3 * (size_t)n);
        sp = y;
    } else if (with_s) {
        sp = s;
    }
    int mid = n / 3;
    if (ff) {
        ff(p->row_start, p->col, p->valf, 0, mid, sp, sign, x, y);
        ff(p->row_start, p->col, p->valf, mid, n, sp, sign, x, y);
    } else {
        f(p->row_start, p->col, p->val, 0, mid, sp, sign, x, y);
        f(p->row_start, p->col, p->val, mid, n, sp, sign, x, y);
    }
    double worst = 0.0;
    for (int q = 0; q < 3 * n; ++q) {
        double err = fabs((double)((long double)y[q] - ref[q]));
        double rel = err / (scale[q] > 0 ? scale[q] : 1.0);
        if (rel > worst) worst = rel;
        CHECK(isfinite(y[q]));
    }
    printf("  %-6s n %5d blocks %6d sign %+.0f s %s: largest error %.2e of the row's |terms|\n", name, n, p->nb,
           sign, with_s ? (alias ? "aliasing y" : "given") : "NULL", worst);
    CHECK(worst < 1e-13); /* rounding of a sum of at most 3 x 40 terms (n u = 2.7e-14) */
    if (out) memcpy(out, y, sizeof(double) * 3 * (size_t)n);
    free(x);
    free(s);
    free(y);
    free(ref);
    free(scale);
}

/* The float-vector kernels on rows [lo, hi) in two calls, against the reference on x rounded to
 * float: within (len + 4) float ulps of the row's |terms| (len blocks summed in float, half of them
 * in each of two sets of lanes, then folded); y4 the rounded y with its 4th float 0. The scalar and
 * vector kernels' y and y4 bit for bit. */
static void check_fx(const pattern* p, double sign, int with_s, int alias, int with_y4) {
    const int n = p->n;
    double* x = malloc(sizeof(double) * 3 * (size_t)n);
    float* x4 = malloc(sizeof(float) * 4 * (size_t)n); /* exact size: the last x_j ends the array */
    double* s = malloc(sizeof(double) * 3 * (size_t)n);
    long double* ref = malloc(sizeof(long double) * 3 * (size_t)n);
    double* scale = malloc(sizeof(double) * 3 * (size_t)n);
    double* y[2] = {malloc(sizeof(double) * 3 * (size_t)n), malloc(sizeof(double) * 3 * (size_t)n)};
    float* y4[2] = {malloc(sizeof(float) * 4 * (size_t)n), malloc(sizeof(float) * 4 * (size_t)n)};
    for (int i = 0; i < n; ++i) {
        for (int c = 0; c < 3; ++c) {
            x4[4 * i + c] = (float)uniform();
            x[3 * i + c] = x4[4 * i + c];
            s[3 * i + c] = uniform() * 10.0;
        }
        x4[4 * i + 3] = 0.0f;
    }
    reference(p, with_s ? s : NULL, sign, x, ref, scale);
    wc_bsr_rows_fx_fn kern[2] = {wc_bsr_rows_fx_scalar, wc_bsr_rows_fx_vector()};
    const int mid = n / 3;
    double worst = 0.0;
    int y4_ok = 1;
    for (int v = 0; v < 2 && kern[v]; ++v) {
        for (int q = 0; q < 4 * n; ++q) y4[v][q] = NAN;
        for (int q = 0; q < 3 * n; ++q) y[v][q] = alias && with_s ? s[q] : NAN;
        const double* sp = with_s ? (alias ? y[v] : s) : NULL;
        float* o4 = with_y4 ? y4[v] : NULL;
        kern[v](p->row_start, p->col, p->valf, 0, mid, sp, sign, x4, y[v], o4);
        kern[v](p->row_start, p->col, p->valf, mid, n, sp, sign, x4, y[v], o4);
        for (int i = 0; i < n; ++i) {
            const int len = p->row_start[i + 1] - p->row_start[i];
            for (int c = 0; c < 3; ++c) {
                const int q = 3 * i + c;
                double err = fabs((double)((long double)y[v][q] - ref[q]));
                double rel = err / ((len + 4) * 0x1p-24 * scale[q] + 1e-300);
                if (!(rel <= worst)) worst = rel; /* NaN too */
                if (with_y4) y4_ok &= y4[v][4 * i + c] == (float)y[v][q];
            }
            if (with_y4) y4_ok &= y4[v][4 * i + 3] == 0.0f;
        }
    }
    printf("  fx     n %5d blocks %6d sign %+.0f s %-10s y4 %s: largest error %.2f of the bound%s\n", n, p->nb, sign,
           with_s ? (alias ? "aliasing y" : "given") : "NULL", with_y4 ? "yes" : "no ", worst,
           kern[1] ? ", scalar = vector" : "");
    CHECK(worst <= 1.0);
    CHECK(y4_ok);
    if (kern[1]) {
        CHECK(memcmp(y[0], y[1], sizeof(double) * 3 * (size_t)n) == 0);
        if (with_y4) CHECK(memcmp(y4[0], y4[1], sizeof(float) * 4 * (size_t)n) == 0);
    }
    free(x);
    free(x4);
    free(s);
    free(ref);
    free(scale);
    for (int v = 0; v < 2; ++v) {
        free(y[v]);
        free(y4[v]);
    }
}

int main(void) {
    wc_bsr_rows_fn vec = wc_bsr_rows_vector();
    wc_bsr_rows_f_fn vec_f = wc_bsr_rows_f_vector();
    printf("vector kernel: %s\n", vec ? "yes (AVX2 + FMA)" : "none on this build or CPU");
    const int sizes[][2] = {{1, 1}, {5, 3}, {200, 13}, {1000, 40}, {64, 0}};
    for (size_t t = 0; t < 2 * sizeof sizes / sizeof sizes[0]; ++t) {
        const int single = t >= sizeof sizes / sizeof sizes[0]; /* the float kernels' turn */
        const int* sz = sizes[t % (sizeof sizes / sizeof sizes[0])];
        pattern p = make_pattern(sz[0], sz[1]);
        if (single) round_pattern(&p);
        for (int mode = 0; mode < 4; ++mode) {
            double sign = mode == 0 || mode == 2 ? 1.0 : -1.0;
            int with_s = mode >= 1, alias = mode == 3;
            unsigned seed = rng;
            double* a = malloc(sizeof(double) * 3 * (size_t)p.n);
            double* b = malloc(sizeof(double) * 3 * (size_t)p.n);
            check_kernel(wc_bsr_rows_scalar, single ? wc_bsr_rows_f_scalar : NULL, single ? "scal_f" : "scalar", &p,
                         sign, with_s, alias, a);
            if (single ? vec_f != NULL : vec != NULL) {
                rng = seed; /* the same x and s */
                check_kernel(vec, single ? vec_f : NULL, single ? "vec_f" : "vector", &p, sign, with_s, alias, b);
                double worst = 0.0;
                for (int q = 0; q < 3 * p.n; ++q) {
                    double d = fabs(a[q] - b[q]) / (fabs(a[q]) + 1.0);
                    if (d > worst) worst = d;
                }
                CHECK(worst < 1e-11);
            }
            rng = seed;
            check_kernel(wc_bsr_rows, single ? wc_bsr_rows_f : NULL, single ? "chos_f" : "chosen", &p, sign, with_s,
                         alias, NULL);
            free(a);
            free(b);
        }
        if (single)
            for (int mode = 0; mode < 6; ++mode) /* sign, s NULL / given / aliasing y, with and without y4 */
                check_fx(&p, mode % 2 ? -1.0 : 1.0, mode >= 2 && mode <= 4, mode == 3, mode >= 3);
        free_pattern(&p);
    }
    return TEST_SUMMARY();
}
