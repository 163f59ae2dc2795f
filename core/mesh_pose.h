/* A mesh collider's motion as a whole: each state of its substep positions (xa, xb) fitted by
 * affine maps from the rest frame (least squares), with the largest residual of any vertex, so
 * that a kept candidate list (wc_mesh_near) gathered in an earlier state can be judged in that
 * state's frame. A body turning or moving rigidly carries the cloth on it: mapped back, the cloth's
 * query boxes stay inside their gathering boxes, where the world-space travel (the fastest vertex's
 * path) would have them regather every substep.
 *
 * The bound (wc_mesh_poses_cover): with M the map from the state g a list was gathered in to the
 * current state n (xa_n = M xa_g + s, xb_n = M xb_g + s, |s| <= sigma from the residuals) and K
 * its inverse, a triangle box at n meeting a query box Q maps back into the box it had at g grown
 * by grow = (|K||L| - I) half_g + |K| 1 (sigma + thickness) - thickness (L, K: the linear parts;
 * half_g the largest half extent of a triangle's box at g); so when the box of K(Q) grown by that
 * lies inside the gathering box, every triangle meeting Q met it: the list holds them, in the
 * tree's order. A deforming body fits badly (a large residual): its lists fall back to the travel.
 * A state is a set of positions: a substep that moves nothing keeps its state. */
#ifndef WEFT_CORE_MESH_POSE_H
#define WEFT_CORE_MESH_POSE_H

#define WC_MESH_POSES 8        /* states remembered; a list gathered before them: the travel only */

typedef struct wc_mesh_pose {
    long long epoch;           /* the state it describes (-1: none) */
    double map[2][12];         /* rest (centred) -> xa and -> xb: 3x3 row-major, then the offset */
    double res[2];             /* m: each map's largest residual (max norm, rounding included) */
    double half[3];            /* m: the largest half extent of a triangle's box of its 6 positions */
    /* from the current state back to this one (the lists gathered in it): */
    double back[12];           /* current world -> this state's world: 3x3 row-major, then the offset */
    double back_abs[9];        /* |back|'s linear part */
    double grow[3];            /* m: how far past its box here a triangle's box now may map back */
    int ok;                    /* 0: no bound (no fit, an ill-conditioned map, a non-finite value) */
} wc_mesh_pose;

typedef struct wc_mesh_poses {
    long long epoch;           /* the current state's */
    int can_fit;               /* 0: the rest positions are flat (no affine fit): no bound */
    double centre[3];          /* the rest positions' centroid */
    double umax[3];            /* the largest |rest - centre| per axis */
    double sinv[9];            /* (sum of (rest - centre)(rest - centre)^T)^-1 */
    wc_mesh_pose ring[WC_MESH_POSES];
} wc_mesh_poses;

struct wc_mesh_collider;
/* At creation, once the boxes are built: the rest frame, the first state. */
void wc_mesh_poses_init(struct wc_mesh_collider* m);
/* After xa, xb and the triangle boxes changed: a new state, fitted, and the bounds back to the
 * states remembered. O(n_verts + n_tris). */
void wc_mesh_poses_update(struct wc_mesh_collider* m);
/* 1 when every triangle box meeting box (6: min xyz, max xyz) now met gbox in state epoch (with
 * slack m of room for rounding); 0 when that is not shown. */
int wc_mesh_poses_cover(const wc_mesh_poses* P, long long epoch, const double* gbox, const double* box, double slack);

#endif
