/* Welding by position: host vertices closer than a distance become one particle (transitively),
 * so UV seams, split normals and sewn panels that share positions are one particle. */
#ifndef WEFT_CORE_WELD_H
#define WEFT_CORE_WELD_H
#include "alloc.h"

/* pos: (n x 3). used: (n) non-zero for vertices to weld; unused ones map to -1. distance: weld
 * radius in metres; 0 welds nothing. Writes to_particle (n) and returns the particle count
 * (particles numbered by first appearance in host order), or -1 on allocation failure. */
int wc_weld(const double* pos, const unsigned char* used, int n, double distance, int* to_particle,
            const wc_allocator* alloc);

#endif
