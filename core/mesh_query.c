/* Queries of the triangle-mesh colliders (mesh_collider.h): closest point with the side rules
 * (also through a point's kept candidates, wc_mesh_near), continuous crossing, deepest
 * penetration. Read-only on the collider; the visitors' state lives on the caller's stack and a
 * kept query writes only its own entry, so any number of threads may query at once. */
#include <math.h>
#include <string.h>
#include "geom.h"
#include "mesh_collider.h"
#include "vec3.h"

#define FACE_W 1e-9            /* barycentric weight above which the closest point is face-interior */

/* fmax and fmin (a NaN argument loses to a number) without the library call, in the hot loops */
static inline double max_num(double a, double b) { return b > a || isnan(a) ? b : a; }
static inline double min_num(double a, double b) { return b < a || isnan(a) ? b : a; }

typedef struct closest_q {
    const wc_mesh_collider* m;
    const double* x;           /* positions: xa or xb */
    const double* nrm;         /* their normals */
    const double* p;
    double best;               /* squared distance */
    double bound2;             /* prune: no triangle farther than this (squared) can matter */
    double slack;              /* m: rounding allowance of the prune (near_bound2) */
    double cos;                /* |cos| of the side-deciding triangle */
    double side;               /* +1 outside, -1 inside */
    int tri;
    double w[3], q[3];
    double tw[3], tq[3];       /* scratch: a visited triangle's closest point */
} closest_q;

/* The prune's bound for a best squared distance d2: a triangle whose box is farther than this
 * can neither become the closest nor tie with it (closest_visit's tolerance is 1e-10 d2 + 1e-24,
 * far inside the bound's 2e-9 d2 + slack), so skipping it leaves the result bit for bit as a
 * full search: the visits that decide it happen in the same order. */
static double near_bound2(double d2, double slack) {
    double r = sqrt(d2) * (1.0 + 1e-9) + slack;
    return r * r;
}

/* closest_visit's test and update for triangle t whose closest point to p is (d2, w, q): a
 * search that computed it already (search_list's hint) passes it */
static void closest_take(closest_q* c, int t, const double* n, const double* pv, double d2, const double* w,
                         const double* q) {
    double d[3];
    /* the distance to its plane is at most the distance to it: beyond the prune's bound (the
       bound's slack covers the rounding of either), it can neither be the closest nor tie
       (exhaustive: the reference, nothing skipped) */
    v3_sub(d, c->p, pv);
    double pn = v3_dot(d, n);
    if (pn * pn > c->bound2 && !c->m->exhaustive) return;
    if (!w) {
        const int* v = c->m->tris + 3 * t;
        double* cw = c->tw;
        d2 = wc_closest_on_triangle(c->p, c->x + 3 * v[0], c->x + 3 * v[1], c->x + 3 * v[2], cw, c->tq);
        w = cw;
        q = c->tq;
    }
    v3_sub(d, c->p, q);
    double len = sqrt(d2), dn = v3_dot(d, n);
    double cs = len > 0.0 ? dn / len : 0.0;
    double tol = 1e-10 * c->best + 1e-24;
    if (d2 < c->best - tol || c->tri < 0) {
        c->best = d2;
        c->tri = t;
        v3_copy(c->w, w);
        v3_copy(c->q, q);
        c->cos = fabs(cs);
        c->side = dn < 0.0 ? -1.0 : 1.0;
    } else if (d2 <= c->best + tol && fabs(cs) > c->cos) {
        /* the same closest point (an edge or vertex): the most clearly decided side wins */
        c->cos = fabs(cs);
        c->side = dn < 0.0 ? -1.0 : 1.0;
        if (d2 < c->best) c->best = d2;
    }
    c->bound2 = min_num(c->bound2, near_bound2(c->best, c->slack));
}

static int closest_visit(void* user, int t) {
    closest_q* c = user;
    const double* n = c->nrm + 3 * t;
    if (n[0] == 0.0 && n[1] == 0.0 && n[2] == 0.0) return 0; /* degenerate */
    closest_take(c, t, n, c->x + 3 * c->m->tris[3 * t], 0.0, NULL, NULL);
    return 0;
}

static void query_box(const double* p, double r, double* box) {
    for (int k = 0; k < 3; ++k) {
        box[k] = p[k] - r;
        box[3 + k] = p[k] + r;
    }
}

/* The closest triangle among those whose boxes meet box: the BVH's preorder, skipping the boxes
 * beyond the prune's bound (exhaustive: none skipped). */
static void search(closest_q* c, const double* box) {
    const wc_bvh* b = &c->m->bvh;
    c->tri = -1;
    c->best = HUGE_VAL;
    c->bound2 = HUGE_VAL;
    if (c->m->exhaustive)
        wc_bvh_query(b, box, closest_visit, c);
    else
        wc_bvh_query_near(b, box, c->p, &c->bound2, closest_visit, c);
}

/* The same over a cached candidate list (in the tree's leaf order): the triangles whose boxes
 * meet box, in the order the tree visits them, the prune's far ones skipped. hint (a position
 * in tris, -1: none): a candidate whose distance d2 bounds the search from the start (the
 * prune's near_bound2(d2)): it is visited too, so the best found is at most d2 (with
 * closest_visit's tolerance, far inside the bound's), and what the bound skips could neither
 * become the closest nor tie with it: the visits that decide the result are the same, in the
 * same order. Returns the position of the result's triangle (-1: none). */
static int search_list(closest_q* c, const double* box, const int* tris, int count, int hint) {
    const wc_bvh* b = &c->m->bvh;
    c->tri = -1;
    c->best = HUGE_VAL;
    c->bound2 = HUGE_VAL;
    double hd2 = 0.0, hw[3], hq[3];
    int hinted = 0;
    if (hint >= 0 && hint < count) {
        int t = tris[hint];
        const int* v = c->m->tris + 3 * t;
        const double* n = c->nrm + 3 * t;
        if (wc_box_overlap(b->box + 6 * b->leaf_of[t], box) && !(n[0] == 0.0 && n[1] == 0.0 && n[2] == 0.0)) {
            hd2 = wc_closest_on_triangle(c->p, c->x + 3 * v[0], c->x + 3 * v[1], c->x + 3 * v[2], hw, hq);
            c->bound2 = near_bound2(hd2, c->slack);
            hinted = 1;
        }
    }
    int at = -1;
    for (int k = 0; k < count; ++k) {
        int t = tris[k];
        const double* lb = b->box + 6 * b->leaf_of[t];
        if (wc_box_overlap(lb, box) && !(wc_box_dist2(lb, c->p) > c->bound2)) {
            if (hinted && k == hint) /* its closest point computed above: the same bits */
                closest_take(c, t, c->nrm + 3 * t, c->x + 3 * c->m->tris[3 * t], hd2, hw, hq);
            else
                closest_visit(c, t);
            if (c->tri == t) at = k;
        }
    }
    return at;
}

static void closest_init(closest_q* c, const wc_mesh_collider* m, int end, const double* p) {
    c->m = m;
    c->x = end ? m->xb : m->xa;
    c->nrm = end ? m->nrm_b : m->nrm_a;
    c->p = p;
    c->slack = 1e-11 * (1.0 + max_num(fabs(p[0]), max_num(fabs(p[1]), fabs(p[2]))));
}

/* The signed distance, normal and surface velocity of a search's result (closest_visit's). */
static double closest_result(const closest_q* c, double* n, double* vc) {
    const wc_mesh_collider* m = c->m;
    const double* p = c->p;
    double dist = sqrt(c->best), d, nn[3];
    const double* fn = c->nrm + 3 * c->tri;
    if ((c->w[0] > FACE_W && c->w[1] > FACE_W && c->w[2] > FACE_W) || !(dist > 1e-12)) {
        double dp[3];
        v3_sub(dp, p, c->q);
        v3_copy(nn, fn);
        d = v3_dot(dp, fn);
    } else {
        v3_sub(nn, p, c->q);
        v3_scale(nn, nn, c->side / dist);
        d = c->side * dist;
    }
    if (n) v3_copy(n, nn);
    if (vc) {
        const int* v = m->tris + 3 * c->tri;
        v3_zero(vc);
        for (int k = 0; k < 3; ++k) v3_axpy(vc, c->w[k], m->vel + 3 * v[k]);
    }
    return d;
}

double wc_mesh_closest(const wc_mesh_collider* m, int end, const double* p, double reach, double* n, double* vc) {
    closest_q c;
    closest_init(&c, m, end, p);
    if (isfinite(reach)) {
        double box[6];
        query_box(p, reach, box);
        search(&c, box);
        if (c.tri < 0 || sqrt(c.best) > reach) return HUGE_VAL;
    } else {
        /* grow the box until the closest triangle found lies within it (then it is the closest) */
        const double* root = m->bvh.box;
        double diag = 0.0;
        for (int k = 0; k < 3; ++k) {
            double e = fmax(fabs(p[k] - root[k]), fabs(p[k] - root[3 + k]));
            diag += e * e;
        }
        diag = sqrt(diag);
        double r = fmax(m->thickness, 1e-3);
        for (;;) {
            double box[6];
            if (r >= diag) r = HUGE_VAL;
            query_box(p, r, box);
            search(&c, box);
            if ((c.tri >= 0 && sqrt(c.best) <= r) || r == HUGE_VAL) break;
            r *= 4.0;
        }
        if (c.tri < 0) return HUGE_VAL;
    }
    return closest_result(&c, n, vc);
}

/* ---- cached candidates (wc_mesh_near) -------------------------------------------------------- */

#define NEAR_MARGIN 0.5        /* a gathering box: the query's grown by this times its largest half width */

void wc_mesh_near_clear(wc_mesh_near* e, int n) {
    for (int i = 0; i < n; ++i) {
        e[i].count = -1;
        e[i].hint = -1;
    }
}

static int gather_visit(void* user, int t) {
    wc_mesh_near* e = user;
    if (e->count >= WC_MESH_NEAR_MAX) {
        e->count = -2; /* remembered: queries inside this box go to the tree without gathering */
        return 1;
    }
    e->tri[e->count++] = t;
    return 0;
}

/* 1 when every triangle box that meets box now met e's gathering box when it was gathered:
 * box grown by the boxes' travel since lies inside it (with room for rounding), or box mapped
 * back to the gathering's state by the body's fitted motion does (mesh_pose.h). */
static int near_covers(const wc_mesh_collider* m, const wc_mesh_near* e, const double* box) {
    if (e->count == -1) return 0;
    const double scale = e->scale;
    double grow = (m->travel - e->travel) * (1.0 + 1e-12) + 1e-12 * scale;
    for (int k = 0; k < 3; ++k)
        if (!(box[k] - grow >= e->box[k] && box[3 + k] + grow <= e->box[3 + k]))
            return wc_mesh_poses_cover(&m->poses, e->epoch, e->box, box, 1e-12 * scale);
    return 1;
}

int wc_mesh_near_fit(const wc_mesh_collider* m, wc_mesh_near* e, const double* box) {
    if (near_covers(m, e, box)) return e->count >= 0; /* -2: too many there, the tree it is */
    double half = 0.0;
    for (int k = 0; k < 3; ++k) half = fmax(half, 0.5 * (box[3 + k] - box[k]));
    memcpy(e->box, box, sizeof e->box);
    wc_box_inflate(e->box, NEAR_MARGIN * half);
    e->scale = 1.0;
    for (int k = 0; k < 6; ++k) e->scale = max_num(e->scale, fabs(e->box[k]));
    e->travel = m->travel;
    e->epoch = m->poses.epoch;
    e->count = 0;
    e->hint = -1;
    wc_bvh_query(&m->bvh, e->box, gather_visit, e); /* leaves in preorder: the tree's order */
    return e->count >= 0;
}

/* The closest point within reach among e's kept triangles (which cover the query box), from
 * position from of its list (search_list's hint; -1: none); *hint (NULL: none) gets the result's. */
static double closest_listed(const wc_mesh_collider* m, const wc_mesh_near* e, int from, int end, const double* p,
                             const double* box, double reach, double* n, double* vc, int* hint) {
    closest_q c;
    closest_init(&c, m, end, p);
    int at = search_list(&c, box, e->tri, e->count, from);
    if (hint && at >= 0) *hint = at;
    if (c.tri < 0 || sqrt(c.best) > reach) return HUGE_VAL;
    return closest_result(&c, n, vc);
}

double wc_mesh_closest_near(const wc_mesh_collider* m, wc_mesh_near* e, int end, const double* p, double reach,
                            double* n, double* vc) {
    if (!e || m->exhaustive || !isfinite(reach)) return wc_mesh_closest(m, end, p, reach, n, vc);
    double box[6];
    query_box(p, reach, box);
    if (!wc_mesh_near_fit(m, e, box)) return wc_mesh_closest(m, end, p, reach, n, vc);
    return closest_listed(m, e, e->hint, end, p, box, reach, n, vc, &e->hint);
}

double wc_mesh_closest_kept(const wc_mesh_collider* m, const wc_mesh_near* e, int at, int end, const double* p,
                            double reach, double* n, double* vc) {
    double box[6];
    if (!e || m->exhaustive || !isfinite(reach) || e->count < 0) return wc_mesh_closest(m, end, p, reach, n, vc);
    query_box(p, reach, box);
    if (!near_covers(m, e, box)) return wc_mesh_closest(m, end, p, reach, n, vc);
    return closest_listed(m, e, at >= 0 ? at : e->hint, end, p, box, reach, n, vc, NULL);
}

/* The sign of a kept search's result with few closest points. The result's sign is the sign of
 * dn = (p - q) . n of the triangle that decided it (closest_take: the best's own for a
 * face-interior point, the side-deciding one for an edge or vertex), q its closest point. That
 * triangle lies within the prune's bound of the hint's distance, near_bound2(hd2) (search_list:
 * what lies beyond could neither become the closest nor tie). So the result is >= 0, or HUGE_VAL
 * beyond reach, when every listed triangle the search could visit (box meeting the query box,
 * non-degenerate) either lies beyond that bound (its box, or its plane by more than a rounding
 * margin), or has p in front of its plane by more than FRONT_MARGIN (dn is p's distance to that
 * plane up to a rounding of a few ulps of the coordinates: the margin, relative to the
 * coordinates of p and of the triangle's box, is millions of ulps), or has dn >= 0 computed as
 * closest_take computes it (the same function of the same inputs: the same bits). */
#define FRONT_MARGIN 1e-9

int wc_mesh_front_kept(const wc_mesh_collider* m, const wc_mesh_near* e, int at, int end, const double* p,
                       double reach, int within) {
    double box[6];
    if (!e || m->exhaustive || !isfinite(reach) || e->count < 0 || at < 0 || at >= e->count) return 0;
    query_box(p, reach, box);
    if (!near_covers(m, e, box)) return 0;
    const wc_bvh* b = &m->bvh;
    const double* x = end ? m->xb : m->xa;
    const double* nrm = end ? m->nrm_b : m->nrm_a;
    const double ps = max_num(fabs(p[0]), max_num(fabs(p[1]), fabs(p[2])));
    /* the hint: search_list's first closest point, its bound the search's from the start */
    int t = e->tri[at];
    const double* n = nrm + 3 * t;
    const int* v = m->tris + 3 * t;
    if (!wc_box_overlap(b->box + 6 * b->leaf_of[t], box) || (n[0] == 0.0 && n[1] == 0.0 && n[2] == 0.0)) return 0;
    double w[3], q[3], d[3];
    const double hd2 = wc_closest_on_triangle(p, x + 3 * v[0], x + 3 * v[1], x + 3 * v[2], w, q);
    const double bound2 = near_bound2(hd2, 1e-11 * (1.0 + ps));
    const double bound = sqrt(bound2);
    if (within && !(sqrt(hd2) * (1.0 + 1e-8) + 1e-12 <= reach)) return 0; /* best <= hd2: within reach */
    for (int k = 0; k < e->count; ++k) {
        t = e->tri[k];
        const double* lb = b->box + 6 * b->leaf_of[t];
        n = nrm + 3 * t;
        if (!wc_box_overlap(lb, box) || (n[0] == 0.0 && n[1] == 0.0 && n[2] == 0.0) || wc_box_dist2(lb, p) > bound2)
            continue;
        double s = ps;
        for (int j = 0; j < 6; ++j) s = max_num(s, fabs(lb[j]));
        const double margin = FRONT_MARGIN * (1.0 + s);
        v = m->tris + 3 * t;
        v3_sub(d, p, x + 3 * v[0]);
        const double pn = v3_dot(d, n);
        if (pn > margin || -pn > bound + margin) continue; /* in front of its plane, or beyond the bound */
        double d2 = wc_closest_on_triangle(p, x + 3 * v[0], x + 3 * v[1], x + 3 * v[2], w, q);
        if (d2 > bound2) continue;
        v3_sub(d, p, q);
        if (!(v3_dot(d, n) >= 0.0)) return 0; /* it may decide, from behind (or NaN) */
    }
    return 1;
}

typedef struct ccd_q {
    const wc_mesh_collider* m;
    const double *p0, *p1;
    double eta, t, w[3];
    int tri;
} ccd_q;

static int ccd_visit(void* user, int t) {
    ccd_q* c = user;
    const wc_mesh_collider* m = c->m;
    const double *na = m->nrm_a + 3 * t, *nb = m->nrm_b + 3 * t;
    const int* v = m->tris + 3 * t;
    const double *a0 = m->xa + 3 * v[0], *b0 = m->xa + 3 * v[1], *c0 = m->xa + 3 * v[2];
    const double *a1 = m->xb + 3 * v[0], *b1 = m->xb + 3 * v[1], *c1 = m->xb + 3 * v[2];
    double d0[3], d1[3];
    v3_sub(d0, c->p0, a0);
    v3_sub(d1, c->p1, a1);
    /* from the front at the start to the back at the end */
    if (!(v3_dot(d0, na) > 0.0) || !(v3_dot(d1, nb) < 0.0)) return 0;
    double tt, w[3];
    if (!wc_ccd_point_triangle(c->p0, a0, b0, c0, c->p1, a1, b1, c1, c->eta, &tt, w)) return 0;
    if (c->tri < 0 || tt < c->t) {
        c->t = tt;
        c->tri = t;
        v3_copy(c->w, w);
    }
    return 0;
}

/* The path's box: p0 and p1, inflated by eta. */
static void ccd_box(const double* p0, const double* p1, double eta, double* box) {
    wc_box_empty(box);
    wc_box_add(box, p0);
    wc_box_add(box, p1);
    wc_box_inflate(box, eta);
}

static int ccd_result(const ccd_q* c, double* t, int* tri, double* w) {
    if (c->tri < 0) return 0;
    *t = c->t;
    *tri = c->tri;
    v3_copy(w, c->w);
    return 1;
}

int wc_mesh_ccd(const wc_mesh_collider* m, const double* p0, const double* p1, double eta, double* t, int* tri,
                double* w) {
    ccd_q c = {m, p0, p1, eta, 0.0, {0.0, 0.0, 0.0}, -1};
    double box[6];
    ccd_box(p0, p1, eta, box);
    wc_bvh_query(&m->bvh, box, ccd_visit, &c);
    return ccd_result(&c, t, tri, w);
}

int wc_mesh_ccd_near(const wc_mesh_collider* m, wc_mesh_near* e, const double* p, double reach, const double* p0,
                     const double* p1, double eta, double* t, int* tri, double* w) {
    double qbox[6], box[6];
    if (!e || m->exhaustive || !isfinite(reach)) return wc_mesh_ccd(m, p0, p1, eta, t, tri, w);
    query_box(p, reach, qbox);
    ccd_box(p0, p1, eta, box);
    if (!wc_mesh_near_fit(m, e, qbox) || !near_covers(m, e, box)) return wc_mesh_ccd(m, p0, p1, eta, t, tri, w);
    /* the tree visits the leaves meeting box in preorder (a leaf's ancestors contain it): e's
       list, in that order, filtered by the same test */
    const wc_bvh* b = &m->bvh;
    ccd_q c = {m, p0, p1, eta, 0.0, {0.0, 0.0, 0.0}, -1};
    for (int k = 0; k < e->count; ++k)
        if (wc_box_overlap(b->box + 6 * b->leaf_of[e->tri[k]], box)) ccd_visit(&c, e->tri[k]);
    return ccd_result(&c, t, tri, w);
}

double wc_mesh_max_penetration(const wc_mesh_collider* const* m, int nm, const double* x, int n_points) {
    double deepest = 0.0;
    for (int k = 0; k < nm; ++k)
        for (int i = 0; i < n_points; ++i) {
            double d = wc_mesh_closest(m[k], 1, x + 3 * i, HUGE_VAL, NULL, NULL);
            if (d < HUGE_VAL && -d > deepest) deepest = -d;
        }
    return deepest;
}
