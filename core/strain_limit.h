/* Strain limiting (Provot 1995, Jacobi-style so it runs in parallel and deterministically): after
 * a substep, every stretch spring longer than (1 + limit) x rest is shortened to that length by
 * moving its ends in proportion to their inverse masses (pinned particles do not move), a few
 * passes; velocities get the same correction / h. */
#ifndef WEFT_CORE_STRAIN_LIMIT_H
#define WEFT_CORE_STRAIN_LIMIT_H
#include "filter.h"
#include "model.h"
#include "par.h"

/* scratch: (n_springs x 3). Returns the largest strain left over stretch springs. Corrections
 * are projected by each particle's filter S (line pins and contact normals are kept; f may be
 * NULL for none). */
double wc_strain_limit(const wc_model* m, const wc_filter* f, double limit, int passes, double h, double* x,
                       double* v, double* scratch, wc_par* par);

#endif
