/* Finding the mesh colliders' feature pairs (mesh_pairs.h) at a substep's start.
 *
 * Sharp: a body edge is sharp in a substep when it is convex (the other triangle's far vertex
 * behind the first's plane) and its triangles' normals at the substep's start turn by more than
 * 30 degrees (WC_MESH_PAIR_SHARP_COS), or when it is a boundary or non-manifold edge; a body
 * vertex is sharp when one of its edges is. On a smooth or finely tessellated body the
 * particles' contacts carry the cloth, and pairs there would fight them.
 *
 * Detection (wc_mesh_pairs_find, at the substep's start, after wc_contacts_begin and before the
 * forces; serial, in index order): for every cloth edge (p, q) the sharp body edges (r, s) and
 * the sharp body vertices r of the body triangles whose swept box its box (start and inertial
 * end, inflated by the reach) meets, and for every cloth triangle (p, q, u) the sharp body
 * vertices; each body feature once per cloth feature. A pair is kept when the closest points at
 * the start (cloth at x_n, body at xa) are interior to both features (a closest point at a cloth
 * vertex is that particle's own contact; a body vertex nearest a cloth triangle's edge is the
 * vertex-edge pair's) and closer than the contact distance d_c = 2 thickness + 1.5 h (approach
 * speed along the pair's direction, cloth at v_n against the body point's velocity, when
 * positive): the pair is in the system before it touches. The cloth point and every particle
 * of the cloth feature must be in front of the body at the start (signed distance >= minus the
 * ties' band, TIE_REL: a point on the surface is in front however rounding places it), and an
 * edge-edge pair's direction in front of the body edge's two triangles (n . (n1 + n2) >= 0) and
 * within the normal cone between n1 and n2 (up to 15 degrees past it: turned to the nearer of
 * them): a garment that starts through the body comes out by its particles' push-out, which a
 * pair must not fight; and a pair found deeper than push_speed x h inside the thickness is let
 * out at push_speed as the particles are (its rest moved to g0 + push_speed h).
 * Frozen for the substep: the cloth point's weights w (edge: 1 - a, a; triangle: barycentric),
 * the unit normal n from the body point to the cloth point at the start (the visited body
 * triangle's normal when they coincide: nearer than the ties' band, where the direction between
 * them is rounding's; the visited triangle is the first of the feature's the walk reaches), and
 * off = n . b1 + thickness with b1 the body point at the substep's END (xb, the same weights on
 * the body feature: the body moves linearly, the pair sees where it will be); k by penalty_pairs.h's rule. A pair whose particles lack a block in
 * the pattern (bsr.h: blocks exist for particles sharing a spring) is skipped and counted. */
#include "mesh_pairs.h"
#include <math.h>
#include <string.h>
#include "filter.h"
#include "par.h"
#include "geom.h"
#include "sort.h"
#include "model.h"
#include "vec3.h"

#define INTERIOR 1e-6    /* a feature parameter within this of its ends is the end's */
#define TURN_COS 0.9659  /* cos 15 degrees: the farthest an edge pair's direction past its body
                            edge's normal cone is turned to the nearer face's normal (keep) */
#define TIE_REL 1e-5     /* the ties' band, relative to max(thickness, |coordinates|): closest
                            points nearer than it coincide (the pair takes the visited face's
                            normal), a point less than it behind the body is in front. Float's
                            rounding of a point on a rim (a few ulps, 1e-7 relative) stays inside
                            it: the GPU's float find decides these ties as this double one does */

/* The ties' band at point p (thickness th) */
static inline double tie_band(double th, const double* p) {
    double s = th;
    for (int k = 0; k < 3; ++k) s = fabs(p[k]) > s ? fabs(p[k]) : s;
    return TIE_REL * s;
}

/* fmax (a NaN argument loses to a number) without the library call: reach_box takes 4 a particle */
static inline double max_num(double a, double b) { return b > a || isnan(a) ? b : a; }

/* Room for `threads` threads' marks of the body features seen (all clear) and their lists of
 * the marks set; the old ones are kept when there is no memory. */
static int seen_alloc(wc_mesh_pairs* p, int threads, const wc_allocator* a) {
    size_t n = (size_t)threads * (size_t)p->seen_stride + 1;
    unsigned char* seen = WC_NEW(a, unsigned char, n);
    int* set = WC_NEW(a, int, n);
    if (!seen || !set) {
        wc_free(a, seen);
        wc_free(a, set);
        return 0;
    }
    wc_free(a, p->seen);
    wc_free(a, p->seen_set);
    p->seen = seen;
    p->seen_set = set;
    return 1;
}

static void sharp_free(wc_mesh_sharp* t, const wc_allocator* a) {
    wc_free(a, t->tri_edge);
    wc_free(a, t->edge_tri);
    wc_free(a, t->edge_many);
    wc_free(a, t->sharp_edge);
    wc_free(a, t->sharp_vert);
    wc_free(a, t->node_mask);
}

/* The collider's distinct edges: its 3 n_tris triangle edges sorted by (min, max) vertex. */
static int sharp_build(wc_mesh_sharp* t, const wc_mesh_collider* mc, const wc_allocator* a) {
    int nh = 3 * mc->n_tris;
    t->tri_edge = WC_NEW(a, int, (size_t)nh);
    t->edge_tri = WC_NEW(a, int, 2 * (size_t)nh);
    t->edge_many = WC_NEW(a, unsigned char, (size_t)nh);
    t->sharp_edge = WC_NEW(a, unsigned char, (size_t)nh);
    t->sharp_vert = WC_NEW(a, unsigned char, (size_t)mc->n_verts + 1);
    t->node_mask = WC_NEW(a, unsigned char, (size_t)mc->bvh.n_nodes + 1);
    wc_keyed* keys = WC_NEW(a, wc_keyed, (size_t)nh);
    if (!t->tri_edge || !t->edge_tri || !t->edge_many || !t->sharp_edge || !t->sharp_vert || !t->node_mask ||
        !keys) {
        wc_free(a, keys);
        return 0;
    }
    int bits = 1;
    while (bits < 31 && (1 << bits) <= mc->n_verts) ++bits;
    for (int h = 0; h < nh; ++h) {
        int r = mc->tris[h], s = mc->tris[h - h % 3 + (h % 3 + 1) % 3];
        if (r > s) {
            int tmp = r;
            r = s;
            s = tmp;
        }
        keys[h].key = ((uint64_t)r << bits) | (uint64_t)s;
        keys[h].val = h;
    }
    if (!wc_radix_sort(keys, nh, 2 * bits, a)) {
        wc_free(a, keys);
        return 0;
    }
    int ne = -1;
    for (int k = 0; k < nh; ++k) {
        int h = keys[k].val;
        if (k == 0 || keys[k].key != keys[k - 1].key) {
            ++ne;
            t->edge_tri[2 * ne] = h / 3;
            t->edge_tri[2 * ne + 1] = -1;
            t->edge_many[ne] = 0;
        } else if (t->edge_tri[2 * ne + 1] < 0) {
            t->edge_tri[2 * ne + 1] = h / 3;
        } else {
            t->edge_many[ne] = 1;
        }
        t->tri_edge[h] = ne;
    }
    t->n_edges = ne + 1;
    wc_free(a, keys);
    return 1;
}

wc_mesh_pairs* wc_mesh_pairs_create(int cap, int n_particles, const wc_mesh_collider* const* mc, int nm,
                                    const wc_allocator* a) {
    if (n_particles < 0) n_particles = 0;
    if (nm < 0 || (nm > 0 && !mc)) return NULL;
    wc_mesh_pairs* p = WC_NEW(a, wc_mesh_pairs, 1);
    if (!p) return NULL;
    memset(p, 0, sizeof *p);
    p->behind = WC_NEW(a, _Atomic signed char, (size_t)n_particles + 1);
    p->threads = 1;
    p->sharp = WC_NEW(a, wc_mesh_sharp, (size_t)nm + 1);
    if (!wc_penalty_pairs_init(&p->list, cap, 1, a) || !p->behind || !p->sharp) {
        wc_mesh_pairs_destroy(p, a);
        return NULL;
    }
    memset(p->sharp, 0, ((size_t)nm + 1) * sizeof(wc_mesh_sharp));
    p->n_mesh = nm;
    p->n_particles = n_particles;
    for (int k = 0; k < nm; ++k) {
        if (!sharp_build(&p->sharp[k], mc[k], a)) {
            wc_mesh_pairs_destroy(p, a);
            return NULL;
        }
        int features = p->sharp[k].n_edges + mc[k]->n_verts;
        if (features > p->seen_stride) p->seen_stride = features;
    }
    if (!seen_alloc(p, 1, a)) {
        wc_mesh_pairs_destroy(p, a);
        return NULL;
    }
    return p;
}

void wc_mesh_pairs_destroy(wc_mesh_pairs* p, const wc_allocator* a) {
    if (!p) return;
    if (p->sharp)
        for (int k = 0; k < p->n_mesh; ++k) sharp_free(&p->sharp[k], a);
    wc_free(a, p->sharp);
    wc_free(a, (void*)p->behind);
    wc_free(a, p->near);
    wc_free(a, p->seen);
    wc_free(a, p->seen_set);
    wc_penalty_stages_free(&p->stage, &p->resume, p->threads, a);
    wc_penalty_pairs_free(&p->list, a);
    wc_free(a, p);
}

int wc_mesh_pairs_keep_candidates(wc_mesh_pairs* p, int n_features, const wc_allocator* a) {
    size_t n = (size_t)(n_features > 0 ? n_features : 0) * (size_t)p->n_mesh;
    wc_free(a, p->near);
    p->near = WC_NEW(a, wc_mesh_near, n + 1);
    p->n_features = p->near ? n_features : 0;
    if (p->near) wc_mesh_near_clear(p->near, (int)n);
    return p->near != NULL;
}

/* A thread's stage holds a share of the capacity: its pairs are few against it (most features
 * have none), and a stage that fills up hands the rest of its range to the serial pass. */
int wc_mesh_pairs_set_threads(wc_mesh_pairs* p, int threads, int stage_cap, const wc_allocator* a) {
    wc_penalty_stages_free(&p->stage, &p->resume, p->threads, a);
    p->threads = 1;
    if (threads <= 1) return 1;
    if (!wc_penalty_stages_init(&p->stage, &p->resume, threads, stage_cap > 0 ? stage_cap : p->list.cap / threads + 64,
                                1, a))
        return 0;
    if (!seen_alloc(p, threads, a)) {
        wc_penalty_stages_free(&p->stage, &p->resume, threads, a);
        return 0;
    }
    p->threads = threads;
    return 1;
}

/* The vertex of triangle t not on edge (r, s) */
static int opposite(const wc_mesh_collider* mc, int t, int r, int s) {
    for (int k = 0; k < 3; ++k) {
        int v = mc->tris[3 * t + k];
        if (v != r && v != s) return v;
    }
    return mc->tris[3 * t];
}

/* Sharp edges and vertices of this substep, from the normals at its start (nrm_a): a boundary or
 * non-manifold edge is sharp; an interior one when convex (the other triangle's far vertex behind
 * the first's plane) and its normals turn by more than acos(WC_MESH_PAIR_SHARP_COS). A vertex is
 * sharp when one of its edges is. */
static void sharp_update(wc_mesh_sharp* t, const wc_mesh_collider* mc) {
    memset(t->sharp_vert, 0, (size_t)mc->n_verts);
    memset(t->sharp_edge, 0, (size_t)t->n_edges);
    for (int h = 0; h < 3 * mc->n_tris; ++h) {
        int e = t->tri_edge[h];
        if (t->edge_tri[2 * e] != h / 3) continue; /* once per edge, from its first triangle */
        int t1 = t->edge_tri[2 * e], t2 = t->edge_tri[2 * e + 1];
        int r = mc->tris[h], s = mc->tris[h - h % 3 + (h % 3 + 1) % 3];
        int sharp = 1;
        if (t2 >= 0 && !t->edge_many[e]) {
            const double *n1 = mc->nrm_a + 3 * t1, *n2 = mc->nrm_a + 3 * t2;
            double d[3];
            v3_sub(d, mc->xa + 3 * opposite(mc, t2, r, s), mc->xa + 3 * r);
            sharp = v3_dot(n1, n2) < WC_MESH_PAIR_SHARP_COS && v3_dot(d, n1) < 0.0;
        }
        if (!sharp) continue;
        t->sharp_edge[e] = 1;
        t->sharp_vert[r] = t->sharp_vert[s] = 1;
    }
    /* the detection's visitors skip a triangle without a sharp vertex (a sharp edge's vertices
       are sharp) or a degenerate one: the BVH need not go where there are only such */
    const wc_bvh* b = &mc->bvh;
    for (int tr = 0; tr < mc->n_tris; ++tr) {
        const int* v = mc->tris + 3 * tr;
        const double* n = mc->nrm_a + 3 * tr;
        int degenerate = n[0] == 0.0 && n[1] == 0.0 && n[2] == 0.0;
        t->node_mask[b->leaf_of[tr]] =
            (unsigned char)(!degenerate && (t->sharp_vert[v[0]] | t->sharp_vert[v[1]] | t->sharp_vert[v[2]]));
    }
    wc_bvh_mask_up(b, t->node_mask);
}

typedef struct find_ctx {
    wc_mesh_pairs* pp;
    wc_penalty_pairs* out; /* where kept pairs go: the list, or a thread's stage */
    const wc_mesh_collider* mc;
    const wc_mesh_sharp* sh;
    const wc_model* m;
    const wc_filter* f;
    const unsigned char* stick;
    const double *x, *v;
    double h, he;
    int cloth[3];          /* the cloth feature's particles (edge: 2) */
    const wc_mesh_near* near; /* the feature's kept candidates (NULL: none) */
    int at;                /* the visited body triangle's position in near's list (-1: the tree's
                              walk visits it) */
    unsigned char *seen_edge, *seen_vert; /* the thread's marks (wc_mesh_pairs.seen) */
    int* seen_set;         /* the marks this cloth feature set (offsets from seen_edge) */
    int n_set;
    double reach[6];       /* a body point outside this box is beyond every contact distance
                              keep could give the cloth feature (reach_box) */
} find_ctx;

/* 1 when body feature i (marks: the edges' or the vertices') was seen for this cloth feature;
 * marks it */
static int seen_before(find_ctx* c, unsigned char* marks, int i) {
    if (marks[i]) return 1;
    marks[i] = 1;
    c->seen_set[c->n_set++] = (int)(marks - c->seen_edge) + i;
    return 0;
}

/* Keep the pair: cloth weights w (cnt), cloth point cp0 and body point bp0 at the start, body
 * point bp1 at the end and its velocity vb, fallback normal nb (the body triangle's). */
static void keep(find_ctx* c, int cnt, const double* w, const double* cp0, const double* bp0, const double* bp1,
                 const double* vb, const double* nb, const double* cone1, const double* cone2) {
    const double th = c->mc->thickness;
    double n[3], d[3];
    v3_sub(d, cp0, bp0);
    double dist = v3_norm(d);
    const double tie = tie_band(th, cp0);
    if (dist > tie) v3_scale(n, d, 1.0 / dist);
    else v3_copy(n, nb);
    /* an edge pair: n within the edge's normal cone (between its triangles' normals cone1 and
       cone2). A cloth point behind the faces (n . (cone1 + cone2) < 0: a cloth edge that started
       through a box's rim) is its particles' business, not the rim's. Just past one face's normal
       (TURN_COS) n turns to that face's normal: a cloth edge lying along that face's slope over a
       ridge has no other pair there, and the ridge cut it between its particles (the ridge in
       tests/test_mesh_features.c, turns of 0.01 to 13 degrees). Farther past, n is no surface's:
       a cloth edge through a box's rim line within the thickness gave 45 degrees, and turned
       there the float GPU's and double CPU's runs parted by 7 mm (tests/test_api_gpu_mesh.c) */
    if (cone1 && cone2) {
        const double d1 = v3_dot(n, cone1), d2 = v3_dot(n, cone2);
        if (d1 + d2 < 0.0) return;
        double a[3], b[3];
        v3_cross(a, cone1, n);
        v3_cross(b, n, cone2);
        if (v3_dot(a, b) < 0.0) {
            if (!(fmax(d1, d2) >= TURN_COS)) return;
            v3_copy(n, d1 > d2 ? cone1 : cone2);
        }
    }
    /* the cloth point's start velocity against the body point's, along n (approach: negative) */
    double vc[3] = {0, 0, 0};
    for (int k = 0; k < cnt; ++k) v3_axpy(vc, w[k], c->v + 3 * c->cloth[k]);
    double approach = -(v3_dot(vc, n) - v3_dot(vb, n));
    double dc = 2.0 * th + 1.5 * c->h * (approach > 0.0 ? approach : 0.0);
    if (!(dist < dc)) return;
    /* the cloth point and the feature's particles in front of the body at the start */
    if (!wc_mesh_front_kept(c->mc, c->near, c->at, 0, cp0, dc + th, 0) &&
        wc_mesh_closest_kept(c->mc, c->near, c->at, 0, cp0, dc + th, NULL, NULL) < -tie)
        return;
    for (int k = 0; k < cnt; ++k) {
        _Atomic signed char* bh = &c->pp->behind[c->cloth[k]];
        signed char b = atomic_load_explicit(bh, memory_order_relaxed);
        if (b < 0) {
            /* the closest triangle within dc + th through the kept candidates is the closest of
               all; only when there is none within that reach is the whole tree searched */
            const double* xk = c->x + 3 * c->cloth[k];
            if (wc_mesh_front_kept(c->mc, c->near, c->at, 0, xk, dc + th, 1)) {
                b = 0; /* proven in front and within reach: the search's answer, without it */
            } else {
                double d = wc_mesh_closest_kept(c->mc, c->near, c->at, 0, xk, dc + th, NULL, NULL);
                if (!(d < HUGE_VAL)) d = wc_mesh_closest(c->mc, 0, xk, HUGE_VAL, NULL, NULL);
                b = d < -tie_band(th, xk);
            }
            atomic_store_explicit(bh, b, memory_order_relaxed);
        }
        if (b) return;
    }
    double inv = wc_penalty_inv_mass(c->m, c->f, c->stick, cnt, c->cloth, w);
    if (!(inv > 0.0)) return;
    double off = v3_dot(n, bp1) + th;
    /* a pair found deeper than push_speed x h inside the thickness (a garment that started
       through a rim) is let out at push_speed, as its particles are (collide.h): the spring's
       rest is moved to where the cap allows this substep */
    const double cap = c->mc->push_speed * c->h;
    const double g0 = v3_dot(n, cp0) - off;
    if (cap > 0.0 && g0 + cap < 0.0) off += g0 + cap;
    wc_penalty_pairs_add(c->out, &c->m->pattern, cnt, c->cloth, w, n, off, wc_penalty_stiffness(inv, c->he));
}

/* c->reach: the cloth feature's box at the start grown by the largest contact distance keep can
 * give it, d_c = 2 thickness + 1.5 h approach with approach <= |v_cloth point| + |v_body point|
 * <= the fastest of the feature's particles + the body's fastest vertex (max_speed), and a
 * margin for rounding. A body point outside it is farther than d_c from every point of the
 * feature (keep rejects the pair): its closest points need not be computed. Unbounded when the
 * collider is exhaustive (the reference of the prunes). */
static void reach_box(find_ctx* c, int cnt) {
    const wc_mesh_collider* mc = c->mc;
    double vmax = 0.0, scale = 1.0;
    if (mc->exhaustive) {
        for (int k = 0; k < 3; ++k) {
            c->reach[k] = -HUGE_VAL;
            c->reach[3 + k] = HUGE_VAL;
        }
        return;
    }
    wc_box_empty(c->reach);
    for (int k = 0; k < cnt; ++k) {
        const double* xk = c->x + 3 * c->cloth[k];
        wc_box_add(c->reach, xk);
        vmax = max_num(vmax, v3_norm(c->v + 3 * c->cloth[k]));
        scale = max_num(scale, max_num(fabs(xk[0]), max_num(fabs(xk[1]), fabs(xk[2]))));
    }
    double dc = 2.0 * mc->thickness + 1.5 * c->h * (vmax + mc->max_speed);
    wc_box_inflate(c->reach, dc * (1.0 + 1e-9) + 1e-9 * scale);
}

/* 1 when body point p lies outside c->reach */
static int beyond_reach(const find_ctx* c, const double* p) {
    const double* b = c->reach;
    return p[0] < b[0] || p[0] > b[3] || p[1] < b[1] || p[1] > b[4] || p[2] < b[2] || p[2] > b[5];
}

/* 1 when the body segment p-q lies outside c->reach (on one side of it) */
static int segment_beyond_reach(const find_ctx* c, const double* p, const double* q) {
    const double* b = c->reach;
    for (int k = 0; k < 3; ++k)
        if ((p[k] < b[k] && q[k] < b[k]) || (p[k] > b[3 + k] && q[k] > b[3 + k])) return 1;
    return 0;
}

static void lerp(double* o, const double* a, const double* b, double t) {
    for (int k = 0; k < 3; ++k) o[k] = a[k] + t * (b[k] - a[k]);
}

static int visit_edge(void* user, int t) {
    find_ctx* c = user;
    const wc_mesh_collider* mc = c->mc;
    const double* nb = mc->nrm_a + 3 * t;
    if (nb[0] == 0.0 && nb[1] == 0.0 && nb[2] == 0.0) return 0; /* degenerate */
    const int* tv = mc->tris + 3 * t;
    const double *p0 = c->x + 3 * c->cloth[0], *q0 = c->x + 3 * c->cloth[1];
    const int* te = c->sh->tri_edge + 3 * t;
    for (int e = 0; e < 3; ++e) {
        int eid = te[e];
        if (!c->sh->sharp_edge[eid] || seen_before(c, c->seen_edge, eid)) continue;
        int r = tv[e], s = tv[e == 2 ? 0 : e + 1];
        if (segment_beyond_reach(c, mc->xa + 3 * r, mc->xa + 3 * s)) continue;
        double a, b;
        wc_closest_on_segments(p0, q0, mc->xa + 3 * r, mc->xa + 3 * s, &a, &b);
        if (!(a > INTERIOR && a < 1.0 - INTERIOR && b > INTERIOR && b < 1.0 - INTERIOR)) continue;
        double cp0[3], bp0[3], bp1[3], vb[3], w[2] = {1.0 - a, a};
        lerp(cp0, p0, q0, a);
        lerp(bp0, mc->xa + 3 * r, mc->xa + 3 * s, b);
        lerp(bp1, mc->xb + 3 * r, mc->xb + 3 * s, b);
        lerp(vb, mc->vel + 3 * r, mc->vel + 3 * s, b);
        const int t1 = c->sh->edge_tri[2 * eid], t2 = c->sh->edge_tri[2 * eid + 1];
        const int cone = t2 >= 0 && !c->sh->edge_many[eid];
        keep(c, 2, w, cp0, bp0, bp1, vb, nb, cone ? mc->nrm_a + 3 * t1 : NULL, cone ? mc->nrm_a + 3 * t2 : NULL);
    }
    /* the triangle's vertices against the cloth edge (a body corner or apex under a cloth edge:
       its closest point on the cloth's triangles is on this edge, not interior to them) */
    double e[3];
    v3_sub(e, q0, p0);
    double ee = v3_dot(e, e);
    if (!(ee > 0.0)) return 0;
    for (int k = 0; k < 3; ++k) {
        int r = tv[k];
        if (!c->sh->sharp_vert[r] || seen_before(c, c->seen_vert, r)) continue;
        if (beyond_reach(c, mc->xa + 3 * r)) continue;
        double d[3];
        v3_sub(d, mc->xa + 3 * r, p0);
        double a = v3_dot(d, e) / ee;
        if (!(a > INTERIOR && a < 1.0 - INTERIOR)) continue;
        double cp0[3], w[2] = {1.0 - a, a};
        lerp(cp0, p0, q0, a);
        keep(c, 2, w, cp0, mc->xa + 3 * r, mc->xb + 3 * r, mc->vel + 3 * r, nb, NULL, NULL);
    }
    return 0;
}

static int visit_vertex(void* user, int t) {
    find_ctx* c = user;
    const wc_mesh_collider* mc = c->mc;
    const double* nb = mc->nrm_a + 3 * t;
    if (nb[0] == 0.0 && nb[1] == 0.0 && nb[2] == 0.0) return 0;
    const int* T = c->cloth;
    for (int e = 0; e < 3; ++e) {
        int r = mc->tris[3 * t + e];
        if (!c->sh->sharp_vert[r] || seen_before(c, c->seen_vert, r)) continue;
        if (beyond_reach(c, mc->xa + 3 * r)) continue;
        double w[3], cp0[3] = {0, 0, 0};
        wc_closest_on_triangle(mc->xa + 3 * r, c->x + 3 * T[0], c->x + 3 * T[1], c->x + 3 * T[2], w, NULL);
        if (!(w[0] > INTERIOR && w[1] > INTERIOR && w[2] > INTERIOR)) continue;
        for (int k = 0; k < 3; ++k) v3_axpy(cp0, w[k], c->x + 3 * T[k]);
        keep(c, 3, w, cp0, mc->xa + 3 * r, mc->xb + 3 * r, mc->vel + 3 * r, nb, NULL, NULL);
    }
    return 0;
}

/* The body triangles whose boxes meet box and whose mask byte is set (mask NULL: all) to visit,
 * in the BVH's order: through the feature's kept candidates e when they cover box, else the tree. */
static void visit_near(find_ctx* c, wc_mesh_near* e, const unsigned char* mask, const double* box,
                       wc_bvh_visit_fn visit) {
    const wc_bvh* b = &c->mc->bvh;
    if (e && !c->mc->exhaustive && wc_mesh_near_fit(c->mc, e, box)) {
        for (int k = 0; k < e->count; ++k) {
            int leaf = b->leaf_of[e->tri[k]];
            c->at = k;
            if ((!mask || mask[leaf]) && wc_box_overlap(b->box + 6 * leaf, box)) visit(c, e->tri[k]);
        }
        return;
    }
    c->at = -1;
    wc_bvh_query_masked(b, box, mask, visit, c);
}

/* box of the cloth feature at the start and at its inertial end x + h v, inflated by r */
static void feature_box(const find_ctx* c, int cnt, double r, double* box) {
    wc_box_empty(box);
    for (int k = 0; k < cnt; ++k) {
        const double *xi = c->x + 3 * c->cloth[k], *vi = c->v + 3 * c->cloth[k];
        double e[3];
        v3_copy(e, xi);
        v3_axpy(e, c->h, vi);
        wc_box_add(box, xi);
        wc_box_add(box, e);
    }
    wc_box_inflate(box, r);
}

/* The pairs of cloth feature q (the model's winged edges, then its triangles) into c->out. */
static void find_pairs(find_ctx* c, int q, wc_mesh_near* near, const unsigned char* mask, double r) {
    const wc_winged_edge* we = &c->m->we;
    double box[6];
    c->near = near ? near + q : NULL;
    if (q < we->n_edges) {
        if (wc_we_repeats_previous(we, q)) return;
        c->cloth[0] = we->edges[q].v[0];
        c->cloth[1] = we->edges[q].v[1];
        reach_box(c, 2);
        feature_box(c, 2, r, box);
        visit_near(c, near ? near + q : NULL, mask, box, visit_edge);
        return;
    }
    memcpy(c->cloth, c->m->tris + 3 * (q - we->n_edges), 3 * sizeof(int));
    reach_box(c, 3);
    feature_box(c, 3, r, box);
    visit_near(c, near ? near + q : NULL, mask, box, visit_vertex);
}

/* find_pairs, then the marks it set cleared */
static void find_feature(find_ctx* c, int q, wc_mesh_near* near, const unsigned char* mask, double r) {
    c->n_set = 0;
    find_pairs(c, q, near, mask, r);
    for (int k = 0; k < c->n_set; ++k) c->seen_edge[c->seen_set[k]] = 0;
}

/* Features lo..hi-1 of thread t into its stage, until the stage would overflow: resume[2t] is the
 * first feature not staged (the stage holds exactly the features before it), resume[2t + 1] hi. */
static void stage_range(find_ctx c, int t, int lo, int hi, wc_mesh_near* near, const unsigned char* mask, double r) {
    wc_penalty_pairs* st = &c.pp->stage[t];
    wc_penalty_pairs_clear(st);
    c.out = st;
    c.seen_edge = c.pp->seen + (size_t)t * (size_t)c.pp->seen_stride;
    c.seen_vert = c.seen_edge + c.sh->n_edges;
    c.seen_set = c.pp->seen_set + (size_t)t * (size_t)c.pp->seen_stride;
    int q = lo;
    for (; q < hi; ++q) {
        int n0 = st->n, skipped0 = st->skipped;
        find_feature(&c, q, near, mask, r);
        if (st->overflow > 0) { /* undo this feature: the serial pass finds it again */
            st->n = n0;
            st->skipped = skipped0;
            st->overflow = 0;
            break;
        }
    }
    c.pp->resume[2 * t] = q;
    c.pp->resume[2 * t + 1] = hi;
}

int wc_mesh_pairs_find(wc_mesh_pairs* pp, const wc_mesh_collider* const* mc, int nm, const wc_model* m,
                       const wc_filter* f, const unsigned char* stick, const double* x, const double* v, double h, double he) {
    wc_penalty_pairs_clear(&pp->list);
    if (!(h > 0.0) || !(he > 0.0)) return 0;
    const int nq = m->we.n_edges + m->n_tris;
    for (int k = 0; k < nm; ++k) {
        if (k >= pp->n_mesh) break; /* not the colliders it was created for */
        /* the device's detection (wc_mesh_pairs_add_found) */
        if (mc[k]->on_device || mc[k]->substep_on_device) continue;
        for (int i = 0; i < pp->n_particles; ++i) atomic_store_explicit(&pp->behind[i], -1, memory_order_relaxed);
        sharp_update(&pp->sharp[k], mc[k]);
        const unsigned char* mask = mc[k]->exhaustive ? NULL : pp->sharp[k].node_mask;
        wc_mesh_near* near = pp->n_features >= nq && pp->near ? pp->near + (size_t)k * (size_t)pp->n_features : NULL;
        if (mask && !mask[0]) continue; /* nothing sharp: no pairs */
        find_ctx c;
        memset(&c, 0, sizeof c);
        c.pp = pp;
        c.out = &pp->list;
        c.mc = mc[k];
        c.sh = &pp->sharp[k];
        c.m = m;
        c.f = f;
        c.stick = stick;
        c.x = x;
        c.v = v;
        c.h = h;
        c.he = he;
        c.seen_edge = pp->seen; /* thread 0's marks: the serial passes' */
        c.seen_vert = pp->seen + c.sh->n_edges;
        c.seen_set = pp->seen_set;
        /* reach: the contact distance with the body's fastest vertex approaching */
        double r = 2.0 * mc[k]->thickness + 1.5 * h * mc[k]->max_speed;
        if (pp->threads <= 1 || !pp->stage) {
            for (int q = 0; q < nq; ++q) find_feature(&c, q, near, mask, r);
            continue;
        }
        /* each thread stages its fixed range; then, in range order, its staged pairs and the
           rest of its range (where its stage filled up) are appended: the serial list */
        int nt = 1;
        WC_PAR_REGION(pp) {
            int t = wc_par_tid(), lo, hi;
            if (t == 0) nt = wc_par_nt();
            wc_par_range(nq, t, wc_par_nt(), &lo, &hi);
            stage_range(c, t, lo, hi, near, mask, r);
        }
        for (int t = 0; t < nt; ++t) {
            wc_penalty_pairs_append(&pp->list, &pp->stage[t]);
            for (int q = pp->resume[2 * t]; q < pp->resume[2 * t + 1]; ++q) find_feature(&c, q, near, mask, r);
        }
    }
    return pp->list.n;
}

int wc_mesh_pairs_add_found(wc_mesh_pairs* pp, const wc_model* m, const wc_filter* f, const unsigned char* stick,
                            int cnt, const int* p, const double* w, const double* n, double off, double he) {
    double inv = wc_penalty_inv_mass(m, f, stick, cnt, p, w);
    if (!(inv > 0.0)) return 0;
    return wc_penalty_pairs_add(&pp->list, &m->pattern, cnt, p, w, n, off, wc_penalty_stiffness(inv, he));
}
