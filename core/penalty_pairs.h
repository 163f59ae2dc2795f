/* Penalty pairs: contacts that enter a substep's implicit system as one-sided stiff springs. A
 * pair ties a point of the cloth, sum_a w_a x_a over up to four particles, to something it must
 * stay in front of along a unit normal n:
 *   gap g(x) = n . sum_a w_a x_a - off,   E = k/2 min(g, 0)^2,
 *   f_a = -k g w_a n,   dF_a/dx_b = -k w_a w_b n n^T   (where g < 0; nothing where g >= 0).
 * Its owner finds the pairs (mesh_pairs.h: the cloth against a mesh collider's sharp features;
 * self_pairs.h: the cloth against itself) and freezes w, n, off and k for the substep; this list
 * holds them and does what is common: activation, assembly into A and b, the active-set recheck
 * after a solve, Newton's exact terms, the energy.
 *
 * Two kinds of list, chosen at creation. In-pattern: a pair's particles share blocks of the
 * pattern (bsr.h), every block (a, b) of the term goes into A. Coupled: they share none, the
 * diagonal blocks go into A and the off-diagonal ones into the solvers' products through the
 * coupling terms (coupling.h; term.c = he^2 k while the pair is active, 0 when not).
 *
 * Stiffness: k = WC_PENALTY_KAPPA m_eff / he^2, 1 / m_eff = sum_a w_a^2 / m_a over the pair's
 * unpinned particles: the pair adds KAPPA times its point's own inertia along n to the system,
 * and holds a load F at a penetration F he^2 / (KAPPA m_eff) (a particle's weight: g he^2 /
 * KAPPA). No damping (the integrator's own dissipation damps it), no friction. The capacity is
 * fixed at creation; pairs past it are counted, not silently dropped. Serial, in list order: the
 * result does not depend on the thread count. */
#ifndef WEFT_CORE_PENALTY_PAIRS_H
#define WEFT_CORE_PENALTY_PAIRS_H
#include "alloc.h"
#include "bsr.h"
#include "coupling.h"

#define WC_PENALTY_KAPPA 100.0   /* stiffness over inertia along n */
#define WC_PENALTY_PASSES 3      /* re-solves at most when the active set changes (step.c) */
#define WC_PENALTY_MAX 4         /* particles of a pair at most */

typedef struct wc_penalty_pairs {
    int cap;                   /* capacity (fixed at creation) */
    int n;                     /* pairs of the current substep */
    int overflow;              /* pairs found past cap in the current substep (not kept) */
    int skipped;               /* in-pattern lists: pairs whose particles lack a pattern block (not kept) */
    wc_coupling_term* term;    /* (cap) each pair's cnt, p, w, n; c = he^2 k while active, else 0 */
    double* off;               /* (cap) m: g(x) = n . sum w_a x_a - off */
    double* k;                 /* (cap) N/m */
    unsigned char* active;     /* (cap) 1: the pair's terms are in the current system */
    int* blk;                  /* (cap x 16) in-pattern lists: the pattern block (p[a], p[b]) of pair
                                  j at 16 j + 4 a + b; NULL: a coupled list */
} wc_penalty_pairs;

struct wc_model;
struct wc_filter;

/* An empty list of capacity cap (>= 1; less is taken as 1), in-pattern when in_pattern is
 * nonzero, else coupled. Returns 0 on out of memory (what was allocated is freed). */
int wc_penalty_pairs_init(wc_penalty_pairs* pp, int cap, int in_pattern, const wc_allocator* a);
void wc_penalty_pairs_free(wc_penalty_pairs* pp, const wc_allocator* a);
/* Empties the list (n, overflow, skipped = 0): the start of a detection. */
void wc_penalty_pairs_clear(wc_penalty_pairs* pp);

/* 1 / m_eff of a pair of cnt particles p with weights w: sum w_a^2 / m_a over the unpinned ones
 * (pinned: ndof 3 in f and not sticking, stick NULL: none; f NULL: nothing pinned). 0 when every
 * particle is pinned (the pair can do nothing). */
double wc_penalty_inv_mass(const struct wc_model* m, const struct wc_filter* f, const unsigned char* stick, int cnt,
                           const int* p, const double* w);
/* k for that 1 / m_eff and the system's step he (s). */
double wc_penalty_stiffness(double inv_mass, double he);

/* Appends a pair (cnt <= WC_PENALTY_MAX particles p, weights w, normal n, off, k), inactive. An
 * in-pattern list looks its blocks up in pt first: one missing, the pair is counted in skipped
 * and not kept; past the capacity it is counted in overflow. Returns 1 when kept. */
int wc_penalty_pairs_add(wc_penalty_pairs* pp, const wc_bsr_pattern* pt, int cnt, const int* p, const double* w,
                         const double* n, double off, double k);
/* Appends src's pairs to dst in order, as wc_penalty_pairs_add would have (both in-pattern or both
 * coupled): pairs past dst's capacity counted in its overflow; src's skipped added to dst's. */
void wc_penalty_pairs_append(wc_penalty_pairs* dst, const wc_penalty_pairs* src);
/* Per-thread staging for a parallel detection: *stage = `threads` empty lists of capacity cap
 * (in-pattern or coupled), *resume = 2 x threads ints. 0 on out of memory (both left NULL). */
int wc_penalty_stages_init(wc_penalty_pairs** stage, int** resume, int threads, int cap, int in_pattern,
                           const wc_allocator* a);
/* Frees what wc_penalty_stages_init made (NULL: nothing) and sets both to NULL. */
void wc_penalty_stages_free(wc_penalty_pairs** stage, int** resume, int threads, const wc_allocator* a);
/* Writes pair `at` (< cap) of a coupled list, inactive, without touching n: for detections that
 * place each pair where a serial one would have put it (self_pairs.c's parallel one). */
void wc_penalty_pairs_set(wc_penalty_pairs* pp, int at, int cnt, const int* p, const double* w, const double* n,
                          double off, double k);

/* The first system, linearised at x_n (x, n x 3) with v* (vstar; x(w) = x_n + he (v* + w)): a
 * pair is active when its gap predicted at the substep's end, x_n + he (v* + he f_ext / m)
 * (f_ext, N, NULL: none), is negative. Adds the active pairs' blocks he^2 k w_a w_b n n^T to A
 * (pattern.n_blocks x 9) and he f_a to b (n x 3); f_total (n x 3, NULL: none) gets their forces
 * at x_n. Returns the active pairs. */
int wc_penalty_pairs_assemble(wc_penalty_pairs* pp, const struct wc_model* m, const double* x, const double* vstar,
                              const double* f_ext, double he, double* A, double* b, double* f_total);
/* After a solve of the first system (dv): switches the pairs whose gap at x_n + he (v* + dv)
 * disagrees with their state (activated when negative, released when positive: a penalty never
 * pulls), adding or removing their terms in A and b. Returns the pairs switched. */
int wc_penalty_pairs_recheck(wc_penalty_pairs* pp, const struct wc_model* m, const double* x, const double* vstar,
                             const double* dv, double he, double* A, double* b);

/* Newton (newton.h): the pairs' energy sum k/2 min(g(x), 0)^2 at positions x (J). */
double wc_penalty_pairs_energy(const wc_penalty_pairs* pp, const double* x);
/* Newton's system at positions x: the pairs with g(x) < 0 become the active ones, their blocks
 * he^2 k w_a w_b n n^T go into A and he f_a into g_out (-grad of the potential). Returns them. */
int wc_penalty_pairs_newton(wc_penalty_pairs* pp, const struct wc_model* m, const double* x, double he, double* A,
                            double* g_out);

/* Pair j's energy (J), forces (f, cnt x 3, N) and force Jacobian (J, cnt x cnt blocks of 9,
 * dF_a/dx_b at (a cnt + b) 9, N/m) at positions x: for tests. */
double wc_penalty_pair_eval(const wc_penalty_pairs* pp, int j, const double* x, double* f, double* J);

#endif
