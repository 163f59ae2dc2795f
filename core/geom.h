/* Proximity and continuous collision queries between points, segments and triangles: the narrow
 * phase of the mesh colliders and of self-collision. Pure functions on double[3] points.
 *
 * Continuous queries take every point at the start (suffix 0) and at the end (suffix 1) of a
 * substep, moving linearly in between (Bridson, Fedkiw & Anderson 2002, section 6): the times at
 * which the four points are coplanar are the roots in [0, 1] of a cubic (found by splitting [0, 1]
 * at the cubic's turning points and bisecting each bracket to 1e-12 of the substep), and a root
 * is a collision when the two features are within eta of each other then. Motion that keeps the
 * four points coplanar throughout (a flat sheet sliding in its plane) has no isolated root: it is
 * judged at the start and the end only. */
#ifndef WEFT_CORE_GEOM_H
#define WEFT_CORE_GEOM_H

/* Closest point q of triangle (a, b, c) to p, with its barycentric weights w (q = w0 a + w1 b +
 * w2 c, each in [0, 1], summing to 1); returns |p - q|^2. Degenerate triangles are handled
 * (the closest point of their edges). q or w may be NULL. */
double wc_closest_on_triangle(const double* p, const double* a, const double* b, const double* c, double* w,
                              double* q);

/* Closest points of segments p0-p1 and q0-q1: p0 + s (p1 - p0) and q0 + t (q1 - q0), s and t in
 * [0, 1]; returns the squared distance. Degenerate (zero-length) segments are handled. */
double wc_closest_on_segments(const double* p0, const double* p1, const double* q0, const double* q1, double* s,
                              double* t);

/* Earliest time t in [0, 1] at which point p comes within eta of triangle (a, b, c) while coplanar
 * with it; 1 and *t, w (barycentric weights of the closest point then; may be NULL) when there is
 * one, else 0. */
int wc_ccd_point_triangle(const double* p0, const double* a0, const double* b0, const double* c0, const double* p1,
                          const double* a1, const double* b1, const double* c1, double eta, double* t, double* w);

/* Earliest time t in [0, 1] at which edge p-q comes within eta of edge r-s while the four points
 * are coplanar; 1 and *t, the edge parameters (*sa on p-q, *sb on r-s; may be NULL) when there is
 * one, else 0. */
int wc_ccd_edge_edge(const double* p0, const double* q0, const double* r0, const double* s0, const double* p1,
                     const double* q1, const double* r1, const double* s1, double eta, double* t, double* sa,
                     double* sb);

/* Roots of c0 + c1 t + c2 t^2 + c3 t^3 in [0, 1], ascending, at most 3 (for the tests). Returns
 * the count; -1 when the cubic vanishes identically (relative to scale, the size of its terms). */
int wc_cubic_roots01(double c0, double c1, double c2, double c3, double scale, double* roots);

#endif
