/* Triangle-mesh colliders: a body the cloth lies on, rigid or deforming (skinned), moving.
 *
 * Immutable: the topology (n_verts vertices, n_tris triangles of vertex indices) and the BVH's
 * shape (bvh.h), built at creation from the creation positions. Mutable: the vertex positions
 * at the start (from) and at the end (to) of the current frame. The host sets `to` before each
 * frame (a rigid body: its transform applied to the creation positions; a deforming one: new
 * vertex positions); the step interpolates linearly between from and to at each substep's start
 * (xa) and end (xb), as it does the pins, and at the end of the frame from = to. A vertex moves
 * linearly over a substep with velocity (xb - xa) / h, so the collider's surface velocity is per
 * point (barycentric interpolation of its vertices'): a moving body carries the cloth, friction
 * acts relative to the surface under the particle.
 *
 * Sides: the outward side of a triangle (a, b, c) is that of (b - a) x (c - a) (counter-clockwise
 * seen from outside). The body mesh must be consistently wound (a closed mesh: every normal
 * outwards; assimp's import of a closed body gives that). An open mesh (a floor patch) has its
 * front on the normals' side; a particle behind it counts as inside and is pushed to the front.
 * Signed distance to the mesh: the distance to the closest point q; positive when p is on the
 * outward side. Inside a face (q interior to a triangle) the side and the normal are the face's;
 * at an edge or a vertex (several triangles share q) the side is that of the triangle whose
 * plane p is most clearly off (the largest |cos| between p - q and its normal) and the normal is
 * the direction p - q (outwards; q - p when inside). Degenerate triangles (zero area) are
 * skipped.
 *
 * The substep: wc_mesh_collider_substep computes xa, xb, the vertex velocities, the triangle
 * normals at both ends, and refits the BVH over the swept triangle boxes (xa u xb, inflated by
 * the thickness): O(n_verts + n_tris), no allocation. Queries (mesh_query.c) are read-only and
 * may run on many threads. */
#ifndef WEFT_CORE_MESH_COLLIDER_H
#define WEFT_CORE_MESH_COLLIDER_H
#include "bvh.h"
#include "mesh_pose.h"
#include "serial.h"

typedef struct wc_mesh_collider {
    int n_verts, n_tris;
    int* tris;                 /* (n_tris x 3) vertex indices */
    double* rest;              /* (n_verts x 3) creation positions (m) */
    double* from;              /* (n_verts x 3) start of the current frame (m, world) */
    double* to;                /* (n_verts x 3) end of the current frame (m, world) */
    double *xa, *xb;           /* (n_verts x 3) start and end of the current substep (m) */
    double* vel;               /* (n_verts x 3) vertex velocities over the substep (m/s) */
    double *nrm_a, *nrm_b;     /* (n_tris x 3) unit normals at xa and xb (zero: degenerate) */
    double* boxes;             /* (n_tris x 6) scratch of the refit */
    wc_bvh bvh;
    double thickness;          /* m, >= 0: the cloth stays this far outside the surface */
    double friction;           /* Coulomb coefficient, >= 0 */
    double push_speed;         /* m/s, >= 0: wc_collider.push_speed (0 at create; the owner sets it) */
    double h;                  /* s: length of the current substep (0 before any) */
    double max_speed;          /* m/s: fastest vertex of the current substep */
    double travel;             /* m: how far the swept triangle boxes may have moved since creation
                                  (the sum over substeps and jumps of the largest vertex
                                  displacement, max norm; wc_mesh_near's validity) */
    wc_mesh_poses poses;       /* the states' affine fits (mesh_pose.h): wc_mesh_near's validity when
                                  the body moves as a whole */
    int on_device;             /* 0 (create); 1: a backend holds the frame's positions on its device
                                  and moves the body there (a GPU cloth's body from a host GL
                                  buffer): from, to and everything derived here are stale until
                                  the backend brings them back (cloth_backend.h mesh_pull); whether
                                  the body moves is then device_moves */
    int device_moves;          /* on_device: 1 when the device's frame end differs from its frame start
                                  (any bit of a float), as the backend found when it took the end
                                  (cloth_backend.h read_gl); 0 again once a frame ends (from = to) */
    int substep_on_device;     /* 0 (create); 1: a backend moves the body to each substep on its device
                                  from from and to, which stay current here (a GPU cloth's body from
                                  the host's arrays or a rigid transform, uploaded once a frame):
                                  only the substep's arrays (xa, xb, vel, the normals, boxes and
                                  the BVH's) and the feature pairs are the device's, stale here
                                  until mesh_pull hands the body back */
    int exhaustive;            /* 0 (create); 1: the searches skip no triangle they could
                                  (closest points: every one in reach; feature pairs, mesh_pairs.h:
                                  smooth ones too): the reference a test checks the prunes against */
    wc_allocator alloc;
} wc_mesh_collider;

/* x (n_verts x 3, finite, |x| <= 1e30, m), tris (n_tris x 3, in [0, n_verts)), n_tris >= 1,
 * thickness and friction finite and >= 0. from = to = xa = xb = x. */
wc_status wc_mesh_collider_create(wc_mesh_collider** out, const double* x, int n_verts, const int* tris,
                                    int n_tris, double thickness, double friction, const wc_allocator* alloc,
                                    wc_diag* diag);
void wc_mesh_collider_destroy(wc_mesh_collider* m);

/* The positions at the end of the next frame (n_verts x 3, m, world; validated: finite,
 * |x| <= 1e30; on error nothing changes). */
wc_status wc_mesh_collider_set_target(wc_mesh_collider* m, const double* x, wc_diag* diag);
/* Jump (teleport, reset, snapshot restore): from = to = xa = xb = x, velocities zero (validated). */
wc_status wc_mesh_collider_set_all(wc_mesh_collider* m, const double* x, wc_diag* diag);
/* 1 when from != to (the collider moves in this frame); on a device, device_moves. */
int wc_mesh_collider_moving(const wc_mesh_collider* m);
/* End of a frame: from = to. */
void wc_mesh_collider_end_frame(wc_mesh_collider* m);
/* The substep from frame fraction a0 to a1 (0 <= a0 <= a1 <= 1), of length h (s, > 0). */
void wc_mesh_collider_substep(wc_mesh_collider* m, double a0, double a1, double h);
/* Its part of a snapshot (serial.h): from and to (n_verts x 3 each); reading also sets the
 * substep positions to from (the derived arrays are recomputed by every substep). */
void wc_mesh_collider_serial(wc_mesh_collider* m, wc_serial* k);

/* ---- queries (mesh_query.c) ------------------------------------------------------------------ */

/* Closest-point query at the substep's start (end = 0, xa) or end (end = 1, xb): the signed
 * distance from p to the surface (m, thickness not included; see the top for the side rules),
 * the outward unit normal n there and the surface velocity vc (m/s) at the closest point;
 * HUGE_VAL (n, vc untouched) when no triangle is within reach (m) of p. reach HUGE_VAL: no
 * bound (the box grows until it holds the closest triangle). n, vc may be NULL. */
double wc_mesh_closest(const wc_mesh_collider* m, int end, const double* p, double reach, double* n, double* vc);

/* A query box's candidate triangles, kept from query to query (a particle's closest points,
 * over a substep and from substep to substep; a cloth feature's pairs): those whose swept boxes
 * met a gathering box (a query's box grown by a margin), in the BVH's leaf order. A later query
 * box that, grown by how far the boxes may have moved since (travel), still lies inside the
 * gathering box, or that does so mapped back to the gathering's state by the body's fitted motion
 * (mesh_pose.h), needs only these, visited in that order: the tree would visit the same ones in
 * the same order, so the answer is the same, bit for bit. Derived, never state; count -1: empty
 * (wc_mesh_near_clear); -2: more than WC_MESH_NEAR_MAX met the box (the queries it covers go to
 * the tree without gathering again). */
#define WC_MESH_NEAR_MAX 48
typedef struct wc_mesh_near {
    double box[6];             /* m: the gathering box */
    double scale;              /* max(1, |its coordinates|): the cover test's rounding scale */
    double travel;             /* the collider's travel when gathered */
    long long epoch;           /* the collider's state when gathered (mesh_pose.h) */
    int count;
    int hint;                  /* the position in tri of the last closest point's triangle (-1:
                                  none): its distance bounds the next query's from the start */
    int tri[WC_MESH_NEAR_MAX];
} wc_mesh_near;
void wc_mesh_near_clear(wc_mesh_near* e, int n);
/* Makes e cover box (6: min xyz, max xyz), gathering again when it does not; 0 when it cannot
 * (too many candidates: query the tree). */
int wc_mesh_near_fit(const wc_mesh_collider* m, wc_mesh_near* e, const double* box);
/* wc_mesh_closest through e (one point's entry for this collider; NULL: none): the same result. */
double wc_mesh_closest_near(const wc_mesh_collider* m, wc_mesh_near* e, int end, const double* p, double reach,
                            double* n, double* vc);
/* The same through e only when e already covers the query, else through the tree: e is never
 * gathered again, so a caller walking e's list may ask (NULL: the tree). at: a position in e's
 * list (-1: none) whose triangle, when its box meets the query's, is visited first: its distance
 * bounds the search from the start, as a point's hint does (the same result; mesh_query.c
 * search_list). */
double wc_mesh_closest_kept(const wc_mesh_collider* m, const wc_mesh_near* e, int at, int end, const double* p,
                            double reach, double* n, double* vc);

/* 1 when wc_mesh_closest_kept(m, e, at, end, p, reach, ...) is proven >= 0 or, within 0,
 * HUGE_VAL; within 1: proven >= 0 and < HUGE_VAL. Needs e covering the query and at (a position
 * in e's list whose triangle's box meets the query box): its triangle's distance bounds which
 * triangles could decide the sign, and p in front of the planes of those, by a margin over
 * rounding, proves it; only a triangle whose plane p is not clearly in front of has its closest
 * point computed (mesh_query.c). 0: not proven: ask wc_mesh_closest_kept. */
int wc_mesh_front_kept(const wc_mesh_collider* m, const wc_mesh_near* e, int at, int end, const double* p,
                       double reach, int within);

/* Continuous query: the earliest time t in [0, 1] at which a point moving linearly from p0 (at
 * the substep's start) to p1 (at its end) crosses a triangle of the mesh moving from xa to xb,
 * from its front (p0 in front of the triangle's plane at the start) to its back (p1 behind it at
 * the end), passing within eta (m) of the triangle. Returns 1 with *t, *tri and w (3,
 * barycentric weights of the crossing point) when there is one, else 0. */
int wc_mesh_ccd(const wc_mesh_collider* m, const double* p0, const double* p1, double eta, double* t, int* tri,
                double* w);
/* wc_mesh_ccd through e (a point's entry, as wc_mesh_closest_near's; NULL: the tree), first
 * fitted to the query box of p and reach as wc_mesh_closest_near(m, e, ., p, reach) fits it (so
 * that query, next, finds it fitted): when e then covers the path's box, its triangles meeting
 * that box are the ones the tree would visit, in the same order: the same answer, bit for bit. */
int wc_mesh_ccd_near(const wc_mesh_collider* m, wc_mesh_near* e, const double* p, double reach, const double* p0,
                     const double* p1, double eta, double* t, int* tri, double* w);

/* The deepest of n_points points x (n_points x 3, m) behind the surface of any of the nm
 * colliders at their substep end positions (xb: after a frame, the frame's end): max over points
 * and colliders of -signed distance (m, thickness not included), 0 when no point is inside. */
double wc_mesh_max_penetration(const wc_mesh_collider* const* m, int nm, const double* x, int n_points);

#endif
