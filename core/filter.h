/* Per-particle constraint filter (Baraff & Witkin section 5): S_i projects a particle's velocity
 * change onto its free directions and z_i is the prescribed velocity change along the
 * constrained ones. Free: S = I, z = 0. Contact with a surface of normal n (1 constraint):
 * S = I - n n^T. Line constraint along unit d (2 constraints): S = d d^T. Pinned: S = 0.
 * The solution satisfies dv_i = z_i + S_i y_i, so (I - S_i) dv_i = (I - S_i) z_i exactly. */
#ifndef WEFT_CORE_FILTER_H
#define WEFT_CORE_FILTER_H

typedef struct wc_filter {
    int n;                  /* particles */
    double* S;              /* (n x 9) row-major symmetric projection */
    double* z;              /* (n x 3) prescribed velocity change (m/s), zero along free directions */
    unsigned char* ndof;    /* (n) constrained degrees of freedom: 0 free, 1 plane, 2 line, 3 pinned */
} wc_filter;

/* Reset particle i to free. */
static inline void wc_filter_free_particle(wc_filter* f, int i) {
    double* S = f->S + 9 * i;
    for (int k = 0; k < 9; ++k) S[k] = 0.0;
    S[0] = S[4] = S[8] = 1.0;
    f->z[3 * i] = f->z[3 * i + 1] = f->z[3 * i + 2] = 0.0;
    f->ndof[i] = 0;
}

/* o = S_i v */
static inline void wc_filter_apply(const wc_filter* f, int i, const double* v, double* o) {
    if (f->ndof[i] == 0) {
        o[0] = v[0]; o[1] = v[1]; o[2] = v[2];
        return;
    }
    const double* S = f->S + 9 * i;
    double x = S[0] * v[0] + S[1] * v[1] + S[2] * v[2];
    double y = S[3] * v[0] + S[4] * v[1] + S[5] * v[2];
    double z = S[6] * v[0] + S[7] * v[1] + S[8] * v[2];
    o[0] = x; o[1] = y; o[2] = z;
}

#endif
