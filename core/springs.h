/* Spring construction from the winged edge and the source polygons.
 *   stretch: every source-polygon edge (not diagonals added by triangulation);
 *   shear:   both diagonals of every source quad; across every other interior manifold edge,
 *            the pair of wing vertices (skipped when both faces came from quads);
 *   bend:    for each vertex v and each polygon-edge neighbour a, a to the neighbour b of v most
 *            opposite to a, when the rest angle a-v-b is at least min_angle.
 * One spring per particle pair, precedence stretch > shear > bend. */
#ifndef WEFT_CORE_SPRINGS_H
#define WEFT_CORE_SPRINGS_H
#include "model.h"

typedef struct wc_spring_input {
    int n_particles;
    const double* pos;              /* (n_particles x 3) rest positions */
    const wc_winged_edge* we;
    const unsigned char* tri_quad;  /* (we->n_faces) face came from a quad */
    int n_quads;
    const int* quads;               /* (n_quads x 4) particle corners of surviving quads */
    double min_angle_deg;
} wc_spring_input;

/* Allocates *out (n springs, sorted by type then (a, b)); fills type_start. */
wc_status wc_build_springs(const wc_spring_input* in, wc_spring** out, int* n_out,
                             int type_start[WC_SPRING_TYPE_COUNT + 1], const wc_allocator* alloc,
                             wc_diag* diag);

#endif
