/* The self-collision queries' kept candidates: for each query of the stage (self_pass.h) and of
 * the in-solve pairs (self_pairs.h), a vertex against the triangle tree or an edge against the
 * edges above it (self_broad.h), the elements whose boxes met its box grown by a margin when
 * they were last gathered, in the tree's leaf order, less the pairs the adjacency rules always
 * exclude (a shared or sewn particle, every particle tangled at rest). A later query visits only
 * those, testing each one's current box (and mask) as the tree's leaf test does, while the
 * particles have not moved far enough since for an element outside the list to reach the query:
 * the same elements in the same order as the tree's walk, so the same answers bit for bit.
 *
 * The bound. At gathering every particle's anchor is a box around its positions then (x0, x1;
 * self_near.c reaches ahead along their motion); the trees' boxes were those inflated by r_g, and each query's box was its anchor box
 * inflated by gap - r_g (gap: wc_self.near_gap). Later, with positions x0', x1' and boxes
 * inflated by r: on each axis k let A_k = max (v - hi) and B_k = min (v - lo) over every particle's
 * positions v and its anchor interval [lo, hi], and T = max_k (A_k - B_k) / 2. Shifting every
 * position by u_k = (A_k + B_k) / 2 (one translation: boxes that overlap still do, those that do
 * not still do not) puts each within T of its anchor box on every axis, so a query's box lies in
 * its anchor box grown by T and an element's in its own grown by T + r; when they overlap, the
 * anchor boxes grown by 2T + r do, and with 2T + r <= gap the gathering saw that element. A cloth
 * that translates as a whole keeps its lists however far it goes; one that turns or deforms
 * gathers again when its particles' spread of displacements reaches the margin. The test adds
 * a margin for rounding (64 ulps of the largest coordinate and the gap).
 *
 * Allocated at the stage's creation (wc_self_create): WC_SELF_NEAR_CAP entries per query; a
 * query with more candidates walks the tree. Not state: a rollback or a restored snapshot only
 * moves the positions, and the bound is measured from the anchors. */
#ifndef WEFT_CORE_SELF_NEAR_H
#define WEFT_CORE_SELF_NEAR_H
#include "bvh.h"
#include "model.h"
#include "self_data.h"

/* candidates kept per query, at most */
#define WC_SELF_NEAR_CAP 24
/* gap = (1 + slack) x thickness: the slack is what the particles' spread of displacements (2T)
 * may use before the lists are gathered again */
#define WC_SELF_NEAR_SLACK 4.0
/* the anchors reach this many times a phase's motion ahead of its end positions */
#define WC_SELF_NEAR_AHEAD 1.0

/* Allocate the lists of sc (its n, n_edges and thickness set; sc->alloc). WC_ERROR_OUT_OF_MEMORY
 * or WC_OK. Freed by wc_self_near_free. */
wc_status wc_self_near_alloc(wc_self* sc);
void wc_self_near_free(wc_self* sc);

/* Before a phase's queries, with the trees just refitted over the boxes of x0 U x1 (n x 3 each)
 * inflated by r <= thickness (wc_self_refit). Only a full phase (one that visits every query:
 * the in-solve pairs' detection, the stage's first pass) gathers lists; the stage's later
 * passes (full = 0), which visit only what is dirty, use the lists as they are when the bound
 * covers them and the last full phase used them (else they walk the trees: the bound is a
 * serial sweep of the particles, not worth checking while the cloth outruns the margin). A full
 * phase uses the lists when the bound above covers x0, x1 and r, or
 * else gathers them again at x0, x1 (on sc->threads threads), unless the last lists served at
 * most one full phase after the one that gathered them (motion faster than the margin: a
 * gathering costs more than a walk): then the next 2, 4, ... 32 full phases walk the trees
 * before gathering again. With sc->near_off every query walks the trees. */
void wc_self_near_prepare(wc_self* sc, const wc_model* m, const double* x0, const double* x1, double r,
                          int full);

/* 1 when the lists gathered cover positions x0, x1 and boxes inflated by r (the bound above). */
int wc_self_near_covers(const wc_self* sc, const double* x0, const double* x1, double r);

/* The trees' queries (wc_bvh_query_masked on the triangle tree for vertex i, and
 * wc_self_edges_above_masked for edge e) through the lists when prepared: the same visits
 * (visit(user, element) for every candidate, with the same early stop), less the pairs the
 * adjacency rules exclude, which every visitor skips anyway. */
int wc_self_near_tris(const wc_self* sc, int i, const double* box, const unsigned char* mask, wc_bvh_visit_fn visit,
                      void* user);
int wc_self_near_edges(const wc_self* sc, int e, const double* box, const unsigned char* mask, wc_bvh_visit_fn visit,
                       void* user);

#endif
