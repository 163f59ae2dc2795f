/* Assembly of the backward-Euler system (Baraff & Witkin eq. 16-17):
 *   A = M - h dF/dv - h^2 dF/dx,    b = h (f0 + h dF/dx v0)
 * by rows in parallel: row i gathers its incident springs through the model's pattern (no
 * atomics, no allocation). f0 = spring forces + f_ext. */
#ifndef WEFT_CORE_ASSEMBLE_H
#define WEFT_CORE_ASSEMBLE_H
#include "forces.h"

/* A_val: (pattern.n_blocks x 9) overwritten; b: (n x 3) overwritten; f_total (optional, n x 3):
 * receives f0. */
void wc_assemble(const wc_model* m, const wc_spring_eval* se, const double* f_ext, const double* v, double h,
                 wc_par* par, double* A_val, double* b, double* f_total);
/* The same with the scalar loops only (wc_assemble takes AVX where the CPU has it: the same bits;
 * tests/test_assemble_avx.c). */
void wc_assemble_scalar(const wc_model* m, const wc_spring_eval* se, const double* f_ext, const double* v, double h,
                        wc_par* par, double* A_val, double* b, double* f_total);

#endif
