/* The self-collision stage's data (wc_self; the stage is self_collide.h): its settings, the
 * model's unique edges, the two trees and their boxes, the seam links, the particles tangled at
 * rest, and the scratch of a substep, all allocated at creation (wc_self_create). Read and
 * written by the stage's parts (self_pass.h, self_broad.h) and by the in-solve pairs
 * (self_pairs.h). */
#ifndef WEFT_CORE_SELF_DATA_H
#define WEFT_CORE_SELF_DATA_H
#include "alloc.h"
#include "bvh.h"
#include "self_grid.h"
#include "self_zones.h"

typedef struct wc_self {
    double thickness;   /* m, > 0 */
    double eta;         /* m: CCD tolerance, thickness / 100 */
    int passes;         /* CCD impulse passes before the zones (WC_SELF_PASSES); tests set 0 (no
                           CCD impulse: every collision goes to the zones) to drive the zones */
    int detect_all;     /* tests: 1 = every pass checks every pair (default 0: after the first,
                           only the pairs with a dirty particle) */
    double zone_strain; /* the springs a zone stretched are relaxed to this strain, or what the
                           solve left, if more (WC_SELF_ZONE_STRAIN; infinity: not relaxed) */
    int n, n_tris, n_edges;
    int* edges;         /* (n_edges x 2) particle pairs, each vertex pair once */
    wc_bvh tri_bvh, edge_bvh;
    wc_bvh_split tri_split, edge_split; /* the trees cut for refits on threads (self_broad.h) */
    double* tri_box;    /* (n_tris x 6) */
    double* edge_box;   /* (n_edges x 6) */
    double* part_box;   /* (n x 6) scratch of wc_self_refit: each particle's box of x0 U x1 */
    double* x_start;    /* (n x 3) m: positions at the start of the substep */
    double* x_old;      /* (n x 3) m: end positions before the stage */
    double* inv_mass;   /* (n) 1/kg, 0 for pinned, this substep */
    int* parent;        /* (n) union-find of the impact zones */
    unsigned char* in_zone; /* (n) 1: the particle is in a zone */
    unsigned char* active;  /* (n + n_edges) 1: the query (vertex i, then edge n + e) has a pair
                               that needs action this pass (parallel scan's result) */
    int* edge_max;      /* (edge_bvh.n_nodes) the largest edge index under each node: an edge's
                           query skips the subtrees of lower edges (each pair visited once) */
    unsigned char* dirty;     /* (n) each: 1 for a particle whose pairs the next pass must check */
    unsigned char* dirty_next; /* (wc_self_resolve: the dirty set and the one being marked) */
    unsigned char* tri_mask;  /* (tri_bvh.n_nodes), edge_mask (edge_bvh.n_nodes): 1 for a node */
    unsigned char* edge_mask; /* with an element of a dirty particle under it */
    int threads;        /* >= 1: detection threads (the state's wc_par; 1 at creation) */
    double* zone;       /* (n x WC_SELF_ZONE_STRIDE) per-zone accumulators (self_zones.h) */
    wc_self_relax_set relax; /* the stretch springs the zones' relaxation must check (self_zones.h) */
    int relax_all;      /* tests: 1 = every relaxation pass checks every stretch spring */
    int* seam_start;    /* (n + 1) CSR of each particle's seam partners (self_broad.h; NULL: none): */
    int* seam_nbr;      /* a particle is never tested against an element it is sewn to */
    unsigned char* tangled; /* (n) 1: the particle belongs to an edge-triangle pair that crosses in
                           the rest shape; pairs made only of such particles are skipped */
    int tangled_pairs;  /* those crossing pairs (0 for a mesh that starts untangled) */
    /* the queries' kept candidates (self_near.h): */
    double* near_anchor; /* (n x 6) each particle's box of its positions at the last gathering */
    int* near_cand;     /* ((n + n_edges) x WC_SELF_NEAR_CAP) each query's candidates, leaf order */
    int* near_count;    /* (n + n_edges) how many; -1: more than the cap (the query walks the tree) */
    double* near_ahead; /* (n x 3) scratch: where the anchors reach ahead to */
    double* near_qbox;  /* ((n + n_edges) x 6) scratch of a gathering: each query's box */
    int* near_vstart;   /* (n_tris + 1) CSR of the vertex queries each triangle carries (a vertex */
    int* near_vlist;    /* by its first triangle; near_vlist[near_vstart[n_tris] ..): in none) */
    int near_vready;    /* 1: near_vstart, near_vlist filled (the model's topology, once) */
    double near_gap;    /* m: the bound's gap (self_near.h) */
    int near_gathers;   /* gatherings so far (a count for tests and measurements) */
    int near_kept;      /* 1: lists gathered */
    int near_served;    /* full phases (self_near.h) the current lists served, the gathering one
                           included */
    int near_wait, near_backoff, near_waited; /* phases to walk the trees before gathering again,
                           that wait's length, 1 right after one (self_near.c) */
    int near_use;       /* 1: the current phase's queries go through the lists */
    int near_full_use;  /* near_use of the last full phase (the stage's later passes check the
                           bound only after one that used the lists) */
    int near_later;     /* the stage's later passes that used the lists (a count for tests) */
    int near_off;       /* tests: 1 = no lists (every query walks the trees) */
    wc_self_grid tri_grid, edge_grid; /* the later passes' dirty triangles and edges (self_grid.h) */
    int grid_off;       /* tests: 1 = no grids (every clean query walks the trees) */
    int refit_dirty;    /* 1 (wc_self_resolve, for the next pass only): since the last pass's refit
                           (at refit_r, the same x_start) only that pass's dirty particles moved:
                           the pass refits only the dirty elements' boxes (self_pass.c) */
    double refit_r;     /* the inflation of the last pass's refit */
    wc_allocator alloc;
} wc_self;

#endif
