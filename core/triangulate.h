/* Triangulation of one source polygon, remembering which triangle sides are polygon edges. */
#ifndef WEFT_CORE_TRIANGULATE_H
#define WEFT_CORE_TRIANGULATE_H

/* corners: k particle indices of the polygon (k >= 3), pos: particle positions (x 3).
 * Writes k-2 triangles to tris (3 each) and per triangle a 3-bit mask to side_mask: bit s set
 * when side s (tri[s] -> tri[(s+1)%3]) is an edge of the polygon rather than an added diagonal.
 * Quads use the shorter valid diagonal; larger polygons are ear-clipped in their best-fit plane
 * (fan fallback for self-intersecting input). Ear clipping costs O(k^2) to O(k^3), so polygons
 * with more than WC_EAR_CLIP_MAX corners are fanned from their first corner instead (exact for
 * convex polygons; the caller warns). scratch: at least k ints. Returns k - 2. */
#define WC_EAR_CLIP_MAX 1024
int wc_triangulate_polygon(const int* corners, int k, const double* pos, int* tris,
                           unsigned char* side_mask, int* scratch);

#endif
