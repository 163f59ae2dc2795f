/* The mesh colliders' feature contacts in the implicit solve: the cloth's edges against the
 * body's sharp edges and vertices, and the body's sharp vertices against the cloth's triangles, as
 * penalty pairs (penalty_pairs.h; an in-pattern list: a pair's particles are one cloth edge or
 * triangle). The particles' own contacts (collide.h) keep every cloth vertex out of the body, with
 * friction; these keep the body's sharp features (a ridge, a box rim, a thin limb, a corner) out
 * of the cloth between its vertices. This file finds them at each substep's start (the rules are
 * in mesh_pairs.c); the list enters them into the system. Frictionless. Derived, not state:
 * re-found every substep (a rollback, a snapshot restore find them again). Serial, in index
 * order: deterministic on any thread count. */
#ifndef WEFT_CORE_MESH_PAIRS_H
#define WEFT_CORE_MESH_PAIRS_H
#include <stdatomic.h>
#include "alloc.h"
#include "mesh_collider.h"
#include "penalty_pairs.h"

#define WC_MESH_PAIR_SHARP_COS 0.866 /* a body edge is sharp when its triangles' normals turn by
                                       more than 30 degrees over it (cos below this) and it is convex */

typedef struct wc_mesh_sharp {
    int n_edges;               /* distinct edges */
    int* tri_edge;             /* (n_tris x 3) edge of each triangle's edge k (vertices k, k + 1) */
    int* edge_tri;             /* (n_edges x 2) its triangles (second -1: a boundary edge) */
    unsigned char* edge_many;  /* (n_edges) 1: more than two triangles (non-manifold) */
    unsigned char* sharp_edge; /* (n_edges) this substep */
    unsigned char* sharp_vert; /* (n_verts) this substep */
    unsigned char* node_mask;  /* (the BVH's n_nodes) this substep: 1 above a non-degenerate
                                  triangle with a sharp vertex (the only ones that give pairs) */
} wc_mesh_sharp;

typedef struct wc_mesh_pairs {
    wc_penalty_pairs list;     /* the pairs of the current substep (in-pattern) */
    int n_mesh;
    wc_mesh_sharp* sharp;      /* (n_mesh) */
    int n_particles;
    _Atomic signed char* behind; /* (n_particles) scratch of a detection: -1 not looked at, 1 the
                                  particle is behind the body's surface at the start, 0 not
                                  (threads may both fill one in: the same value) */
    int n_features;            /* cloth edges + cloth triangles with kept candidates (0: none) */
    wc_mesh_near* near;        /* (n_mesh x n_features) each cloth feature's candidate body
                                  triangles (mesh_collider.h): the same pairs, cheaper */
    int threads;               /* detection threads (par.h's ranges; 1: serial) */
    int seen_stride;           /* the largest collider's n_edges + n_verts */
    unsigned char* seen;       /* (threads x seen_stride) each thread's marks of the body edges
                                  (first n_edges) and vertices the cloth feature it is at has
                                  seen (each body feature once per cloth feature); all clear
                                  between cloth features */
    int* seen_set;             /* (threads x seen_stride) the marks set, to clear them */
    wc_penalty_pairs* stage;   /* (threads) each thread's pairs before they are appended in order */
    int* resume;               /* (threads x 2) the feature where a thread's stage filled up, its
                                  range's end: the rest of its range is found serially */
} wc_mesh_pairs;

struct wc_model;
struct wc_filter;

/* Capacity cap >= 1, for a cloth of n_particles against the nm mesh colliders mc (their
 * topology; the same colliders, in the same order, at every wc_mesh_pairs_find). NULL on out of
 * memory. */
wc_mesh_pairs* wc_mesh_pairs_create(int cap, int n_particles, const wc_mesh_collider* const* mc, int nm,
                                    const wc_allocator* a);
void wc_mesh_pairs_destroy(wc_mesh_pairs* p, const wc_allocator* a);
/* Keep each cloth feature's candidates between detections: room for n_features (the model's
 * winged edges + its triangles). 0 on out of memory (then none are kept). */
int wc_mesh_pairs_keep_candidates(wc_mesh_pairs* p, int n_features, const wc_allocator* a);
/* Find the pairs on `threads` threads (>= 1; 1: serial): each thread stages the pairs of its
 * fixed range of cloth features in room for stage_cap pairs (<= 0: the list's capacity over the
 * threads, plus 64), and the ranges are appended in order, so the list is the serial one on any
 * thread count. 0 on out of memory (then the detection stays serial). */
int wc_mesh_pairs_set_threads(wc_mesh_pairs* p, int threads, int stage_cap, const wc_allocator* a);

/* Detection against the nm mesh colliders (each after wc_mesh_collider_substep of this substep
 * of length h s; he the system's step, bdf2.h, for k): x, v (n x 3, m, m/s) the cloth at the
 * substep's start; f (NULL: no pins) the filter and stick (NULL: none) the sticking contacts: a
 * particle with ndof 3 that does not stick is pinned (infinite mass). Empties the list first. A
 * collider whose body or substep is on a device (on_device, substep_on_device, mesh_collider.h:
 * core's copy of the substep is stale) is skipped: the device finds its pairs by the same rules
 * and hands them to wc_mesh_pairs_add_found. Returns the pairs found (pp->list.n). */
int wc_mesh_pairs_find(wc_mesh_pairs* pp, const wc_mesh_collider* const* mc, int nm, const struct wc_model* m,
                       const struct wc_filter* f, const unsigned char* stick, const double* x, const double* v,
                       double h, double he);

/* A pair found by the rules above elsewhere (a GPU's detection for a body kept there: its cloth
 * particles p (cnt 2: a cloth edge, 3: a triangle), weights w, normal n and off, the push_speed
 * cap applied), appended to the list as the detection's keep does: not when every particle is
 * pinned (f, stick as wc_mesh_pairs_find's), k by penalty_pairs.h's rule for he. 1 when kept. */
int wc_mesh_pairs_add_found(wc_mesh_pairs* pp, const struct wc_model* m, const struct wc_filter* f,
                            const unsigned char* stick, int cnt, const int* p, const double* w, const double* n,
                            double off, double he);

#endif
