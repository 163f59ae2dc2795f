/* Particle renumbering for memory locality: reverse Cuthill-McKee over the triangle graph, so
 * particles that share a spring sit close in memory (small matrix bandwidth, cache-friendly
 * block rows for assembly and the solvers). */
#ifndef WEFT_CORE_ORDERING_H
#define WEFT_CORE_ORDERING_H
#include "alloc.h"

/* new_index[old] for particles 0..n-1 of the triangles (n x 3 indices in [0, n)). Each connected
 * component starts from a pseudo-peripheral particle; components in order of their lowest
 * particle. Deterministic. Returns 0, or -1 when out of memory. */
int wc_order_rcm(int n, const int* tris, int n_tris, int* new_index, const wc_allocator* a);

#endif
