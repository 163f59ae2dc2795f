/* The 3x3-block row product, the innermost loop of every BSR product, residual and multigrid
 * level product: for rows lo..hi-1,
 *     y_i = s_i + sign * sum_k B_k x_{col[k]}     (k in [row_start[i], row_start[i+1]))
 * with s NULL meaning 0; B_k = val + 9k, row-major. y may alias s (row i reads s_i before it
 * writes y_i), never x. Each row is computed alone, so the result does not depend on how rows are
 * split between threads.
 * On x86-64 CPUs with AVX2 and FMA the loop runs as 4-wide fused multiply-adds (one block row per
 * register, the row's three sums folded at its end), chosen once at run time; elsewhere a scalar
 * loop. The two round differently (a few ulps of the row's sum). */
#ifndef WEFT_CORE_BSR_ROWS_H
#define WEFT_CORE_BSR_ROWS_H

typedef void (*wc_bsr_rows_fn)(const int* row_start, const int* col, const double* val, int lo, int hi,
                               const double* s, double sign, const double* x, double* y);

void wc_bsr_rows(const int* row_start, const int* col, const double* val, int lo, int hi, const double* s,
                 double sign, const double* x, double* y);

/* The two kernels by name (tests compare them): the scalar loop, and the vector one or NULL when
 * this build or CPU has none. */
void wc_bsr_rows_scalar(const int* row_start, const int* col, const double* val, int lo, int hi, const double* s,
                        double sign, const double* x, double* y);
wc_bsr_rows_fn wc_bsr_rows_vector(void);

/* The same with single-precision blocks (the multigrid's V-cycle, amg.h wc_amg_opts.single), summed
 * in double. The vector kernel reads one float past the last block: an array passed here
 * holds WC_BSR_F_PAD more floats, zero. */
#define WC_BSR_F_PAD 4
typedef void (*wc_bsr_rows_f_fn)(const int* row_start, const int* col, const float* val, int lo, int hi,
                                 const double* s, double sign, const double* x, double* y);
void wc_bsr_rows_f(const int* row_start, const int* col, const float* val, int lo, int hi, const double* s,
                   double sign, const double* x, double* y);
void wc_bsr_rows_f_scalar(const int* row_start, const int* col, const float* val, int lo, int hi, const double* s,
                          double sign, const double* x, double* y);
wc_bsr_rows_f_fn wc_bsr_rows_f_vector(void);

/* The same float blocks times a float vector, summed in float (the V-cycle's iterates,
 * wc_amg_opts.single_x): x4 holds 4 floats a node, the 4th zero, and
 *     y_i = s_i + sign * (double)(sum_k B_k x4_col(k))
 * with the row's sums in float fused multiply-adds, widened once; when y4 is not NULL it also
 * gets y_i rounded to float (its 4th float set to 0). About half the double kernel's instructions
 * a block (docs/bench/vcycle_float.md). The AVX2 kernel, or NULL; the scalar one does the same
 * arithmetic in the same order (lane by lane fmaf, the same pairwise folds): the same bits. */
typedef void (*wc_bsr_rows_fx_fn)(const int* row_start, const int* col, const float* val, int lo, int hi,
                                  const double* s, double sign, const float* x4, double* y, float* y4);
void wc_bsr_rows_fx_scalar(const int* row_start, const int* col, const float* val, int lo, int hi, const double* s,
                           double sign, const float* x4, double* y, float* y4);
wc_bsr_rows_fx_fn wc_bsr_rows_fx_vector(void);

#endif
