/* The contacts of a substep: begin, end and project (collide.h has the sequence; friction is
 * collide_friction.c's).
 *
 * Choices made here (all deterministic, per particle, no allocation):
 *  - Which particles: begin constrains particles whose filter ndof is 0 or 1 on entry (the step
 *    resets the filter and sets its pins before begin; ndof 1 can only be a contact left over
 *    from an earlier substep and is rewritten). Particles with ndof 2 (line pins) or 3 (pins)
 *    get no contact. project moves every particle except ndof 3 (a line-pinned particle is
 *    still kept out of colliders).
 *  - When a particle is in contact with collider k (d = distance - thickness, vr = v - vc_k):
 *      held:  it was in contact with k last substep (and not released) and d < h |vr| + SLOP
 *             (the band covers the drift of a particle sliding over a curved surface);
 *      new:   d < -SLOP (penetrating), or, unless released last substep, d < h max(0, -vr.n)
 *             + SLOP (it would reach the shell during this substep).
 *    At most two contacts, the two smallest d (lower collider index on ties); a second normal
 *    within ~5.7 degrees of the first (|n2 - (n1.n2) n1| < 0.1) is dropped.
 *  - Position correction: a kept collider whose shell x is inside becomes active; x then takes
 *    the smallest step putting every active shell at distance 0 (exact for planes, the corner of
 *    two shells included; Newton passes for curved colliders, converged to rounding). A collider
 *    with a push_speed (the meshes': a garment authored inside its body's shell) caps the move
 *    at push_speed x h per substep, begin's correction and project's together (ct->pushed
 *    carries begin's share): the particle comes out over several substeps and the solve moves
 *    its neighbours with it.
 *  - Prescribed velocity: after dv the relative normal velocity along each kept normal is
 *    -max(d, 0) / h: a particle on the shell stops moving into it, one approaching within the
 *    reach of this substep lands exactly on the shell at its end (instead of stopping in mid
 *    air). Never outward: a contact adds no separating velocity. project then removes the inward relative
 *    normal velocity left on the shell.
 *  - end: the normal impulse of each contact is the component along its normal of r_i in the
 *    (non-orthogonal) basis of the two normals; a negative one releases that contact.
 *  - project: picks the two deepest colliders and pushes x out of them as above (re-picked up
 *    to PROJECT_ROUNDS times); then the velocity gets the nearest value with no inward relative
 *    normal velocity for the (up to two deepest) colliders whose shell it lies on (distance <
 *    SLOP: a particle that landed in the solve, too). Three or more colliders meeting at
 *    one point may leave a small penetration after the passes. A stuck particle (ndof 3 from its
 *    contact, not a pin) is projected too.
 *  - released: read and cleared by begin, set by end: it means "released at the end of the
 *    previous substep" even when no end ran since (the step skips end when nothing is in
 *    contact; a flag left over would keep the particle from ever being caught again).
 *  - Mesh colliders (mesh_collider.h; WC_COLLIDER_MESH entries, built by the step): the same rules
 *    with the closest point of the mesh (at the substep's start in begin, its end in project;
 *    searched within the particle's reach: thickness + its motion + the fastest vertex's motion
 *    over the substep, farther is "no contact") and the surface velocity of that point (per
 *    point: ct->vel, which friction reads instead of the collider's rigid velocity). Continuous:
 *    in begin, a particle whose path x -> x + h v crosses a moving triangle from its front
 *    (wc_mesh_ccd, earliest crossing) is always taken, on that triangle's plane at the substep's
 *    start (d from the plane, the triangle's normal, the crossing point's velocity): its
 *    prescribed normal velocity lands it on the shell even when the closest point lies on another
 *    face. In project (wc_contacts_project_from, with the substep's start positions), a particle
 *    whose path x0 -> x still crossed a triangle is first moved back in front of the first one it
 *    crossed, at the thickness, its inward velocity relative to it removed; then the closest-point
 *    projection as for every collider. So a thin limb moving several widths per substep neither
 *    passes through the cloth nor leaves it inside. Edge-edge crossings (a cloth edge cutting a
 *    sharp body edge between two particles) are not handled.
 */
#include "collide.h"
#include <math.h>
#include "mesh_collider.h"
#include "vec3.h"

#define SLOP 1e-9              /* m: rounding slack for "on the shell" */
#define PARALLEL_MIN 0.1       /* |n2 - (n1.n2) n1| below this: normals treated as parallel */
#define PROJECT_ROUNDS 3       /* project: re-pick the two deepest colliders this many times */
#define CORRECT_PASSES 4       /* Newton passes of one push out */
#define CCD_ETA 1e-6           /* m: a path passing this close to a mesh triangle crosses it */
#define DEEP_REACH 0.02        /* m: a mesh query also looks this deep behind a particle, so one that
                                  starts (or ends up) up to this far inside a body is found and let
                                  out (at its push_speed); deeper ones are not seen */

/* d - thickness and the normal. */
static double shell_distance(const wc_collider* c, const double* p, double* n) {
    return wc_collider_distance(c, p, n) - c->thickness;
}

/* One collider's contact candidate for a particle: shell distance d, outward normal n, the
 * collider surface's velocity vc at the contact point; plane: a mesh triangle the particle's path
 * crosses (d is then measured from the plane through q along n, the triangle's, not from the
 * closest point). */
typedef struct hit {
    double d, n[3], vc[3], q[3];
    int plane;
} hit;

static double mesh_reach(const wc_collider* c, double move);

/* The candidate of collider c for a particle at p that moves by at most `move` (m) in the
 * substep: analytic colliders as wc_collider_distance; a mesh at its substep start (end 0) or
 * end (end 1), closest points within mesh_reach, through the particle's cached candidates nr
 * (NULL: none). */
static void query(const wc_collider* c, const double* p, int end, double move, hit* H, wc_mesh_near* nr) {
    H->plane = 0;
    if (c->type == WC_COLLIDER_MESH) {
        double d = wc_mesh_closest_near(c->mesh, nr, end, p, mesh_reach(c, move), H->n, H->vc);
        H->d = d < HUGE_VAL ? d - c->thickness : HUGE_VAL;
        if (!(d < HUGE_VAL)) v3_set(H->n, 0.0, 1.0, 0.0); /* up, as wc_collider_distance */
        return;
    }
    H->d = shell_distance(c, p, H->n);
    v3_copy(H->vc, c->velocity);
}

/* Re-measure a candidate at a moved p: a plane candidate keeps its plane, the rest query again. */
static void requery(const wc_collider* c, const double* p, int end, double move, hit* H, wc_mesh_near* nr) {
    if (H->plane) {
        double dp[3];
        v3_sub(dp, p, H->q);
        H->d = v3_dot(dp, H->n) - c->thickness;
        return;
    }
    query(c, p, end, move, H, nr);
}

/* A mesh triangle crossed by the path p0 -> p1 over the substep (the earliest): a plane
 * candidate on it at the substep's start (end 0) or end (end 1), measured at p. Returns 0 when
 * the path crosses nothing. Searched through the particle's cached candidates nr (NULL: the
 * tree), fitted to the query at p for a particle moving by `move` that follows (query's box). */
static int crossing(const wc_collider* c, const double* p0, const double* p1, int end, const double* p,
                    double move, wc_mesh_near* nr, hit* H) {
    const wc_mesh_collider* m = c->mesh;
    double t, w[3];
    int tri;
    if (!wc_mesh_ccd_near(m, nr, p, mesh_reach(c, move), p0, p1, CCD_ETA, &t, &tri, w)) return 0;
    const double* x = end ? m->xb : m->xa;
    const int* v = m->tris + 3 * tri;
    v3_copy(H->n, (end ? m->nrm_b : m->nrm_a) + 3 * tri);
    v3_zero(H->q);
    v3_zero(H->vc);
    for (int k = 0; k < 3; ++k) {
        v3_axpy(H->q, w[k], x + 3 * v[k]);
        v3_axpy(H->vc, w[k], m->vel + 3 * v[k]);
    }
    H->plane = 1;
    requery(c, p, end, 0.0, H, NULL);
    return 1;
}

/* How far a mesh closest-point query must look from a particle that moves by at most `move` (m)
 * in the substep: its shell, its motion and the fastest vertex's, and DEEP_REACH for a particle
 * inside the body. */
static double mesh_reach(const wc_collider* c, double move) {
    const wc_mesh_collider* m = c->mesh;
    return c->thickness + move + m->h * m->max_speed + DEEP_REACH + 1e-6;
}

/* A particle's cached mesh candidates (wc_contacts.near): row[k] for collider k < n. */
typedef struct near_of {
    wc_mesh_near* row;
    int n;
} near_of;

static wc_mesh_near* near_entry(const near_of* nf, int k) {
    return nf && nf->row && k < nf->n ? nf->row + k : NULL;
}

static near_of particle_near(const wc_contacts* ct, int i) {
    near_of nf = {ct->near ? ct->near + (size_t)i * (size_t)ct->n_near : NULL, ct->n_near};
    return nf;
}

/* e = unit part of n2 orthogonal to n1; returns its length before normalising (0..1). */
static double ortho(const double* n1, const double* n2, double* e) {
    v3_copy(e, n2);
    v3_axpy(e, -v3_dot(n1, n2), n1);
    double l = v3_norm(e);
    if (l > 0.0) v3_scale(e, e, 1.0 / l);
    return l;
}

/* Nearest delta to 0 with n_k.delta >= a_k (k < cnt <= 2, normals not parallel when two).
 * Returns 0 when delta = 0 already satisfies them. */
static int halfspaces(const double* n1, double a1, const double* n2, double a2, int cnt, double* delta) {
    v3_zero(delta);
    int bad1 = a1 > 0.0, bad2 = cnt > 1 && a2 > 0.0;
    if (!bad1 && !bad2) return 0;
    if (cnt == 1) {
        v3_scale(delta, n1, a1);
        return 1;
    }
    double c = v3_dot(n1, n2);
    /* one boundary: the projection onto the violated one, when it satisfies the other */
    if (bad1 && a1 * c >= a2) {
        v3_scale(delta, n1, a1);
        return 1;
    }
    if (bad2 && a2 * c >= a1) {
        v3_scale(delta, n2, a2);
        return 1;
    }
    v3_span2(n1, a1, n2, a2, 1, delta);
    return 1;
}

/* Two smallest values among candidates, lower index first on ties. */
typedef struct best2 {
    int k[2];
    hit h[2];
    int cnt;
} best2;

static void best2_init(best2* b) {
    b->k[0] = b->k[1] = -1;
    b->h[0].d = b->h[1].d = HUGE_VAL;
    b->cnt = 0;
}

static void best2_add(best2* b, int k, const hit* H) {
    if (b->cnt == 0 || H->d < b->h[0].d) {
        b->k[1] = b->k[0];
        b->h[1] = b->h[0];
        b->k[0] = k;
        b->h[0] = *H;
    } else if (b->cnt == 1 || H->d < b->h[1].d) {
        b->k[1] = k;
        b->h[1] = *H;
    }
    if (b->cnt < 2) ++b->cnt;
}

/* Drop the second entry when its normal is (nearly) parallel to the first. */
static void best2_prune(best2* b) {
    double e[3];
    if (b->cnt == 2 && ortho(b->h[0].n, b->h[1].n, e) < PARALLEL_MIN) {
        b->cnt = 1;
        b->k[1] = -1;
    }
}

/* Move p out of the shells of colliders ks[0..cnt) (cnt <= 2): a collider found inside becomes
 * active and stays so; each pass moves p by the smallest step that puts every active one at
 * distance 0 (linearised: exact for planes, Newton steps for curved colliders), the whole move
 * being at most cap (m; HUGE_VAL: none): the last step is shortened to it. hs are the
 * candidates measured at p on entry (the first pass does not measure them again) and at p on
 * return when p did not move. *moved_by (may be NULL) gets the length of the path. Returns 1
 * when p moved. */
static int push_out(const wc_collider* c, const int* ks, hit* hs, int cnt, int end, double move, double cap,
                    double* p, double* moved_by, const near_of* nf) {
    int active[2] = {0, 0}, moved = 0;
    double used = 0.0;
    for (int pass = 0; pass < CORRECT_PASSES && used < cap; ++pass) {
        double d[2], n[6], delta[3], e[3];
        int any = 0;
        for (int s = 0; s < cnt; ++s) {
            if (pass > 0) requery(&c[ks[s]], p, end, move, &hs[s], near_entry(nf, ks[s]));
            d[s] = hs[s].d;
            v3_copy(n + 3 * s, hs[s].n);
            if (!(d[s] < HUGE_VAL)) d[s] = 0.0; /* a mesh that moved out of reach: nothing to push */
            if (d[s] < 0.0) active[s] = 1;
            any |= active[s];
        }
        if (!any) break;
        if (active[0] && active[1] && ortho(n, n + 3, e) >= PARALLEL_MIN)
            v3_span2(n, -d[0], n + 3, -d[1], 1, delta);
        else if (active[0])
            v3_scale(delta, n, -d[0]);
        else
            v3_scale(delta, n + 3, -d[1]);
        double len = v3_norm(delta);
        if (len == 0.0) break;
        if (used + len > cap) {
            v3_scale(delta, delta, (cap - used) / len);
            len = cap - used;
        }
        v3_add(p, p, delta);
        used += len;
        moved = 1;
    }
    if (moved_by) *moved_by = used;
    return moved;
}

/* The push_speed cap (m) of a particle in contact with colliders ks[0..cnt) over a substep of
 * length h: the smallest of theirs, HUGE_VAL when none has one. */
static double push_cap(const wc_collider* c, const int* ks, int cnt, double h) {
    double cap = HUGE_VAL;
    for (int s = 0; s < cnt; ++s)
        if (c[ks[s]].push_speed > 0.0) cap = fmin(cap, c[ks[s]].push_speed * h);
    return cap;
}

static int held_contact(const wc_contacts* ct, int i, int k) {
    return ct->collider[2 * i] == k || ct->collider[2 * i + 1] == k;
}

/* ---- shared with the friction (collide.h) ---------------------------------------------------- */

int wc_contacts_sum_counts(const wc_par* par, int used) {
    double s = 0.0;
    for (int t = 0; t < used; ++t) s += par->partial[8 * t];
    return (int)s;
}

void wc_contacts_free_projector(const double* n, int cnt, double* S) {
    double P[9], e2[3];
    m3_identity(S, 1.0);
    m3_outer(P, n, n, 1.0);
    m3_axpy(S, -1.0, P);
    if (cnt == 2) {
        ortho(n, n + 3, e2);
        m3_outer(P, e2, e2, 1.0);
        m3_axpy(S, -1.0, P);
    }
}

void wc_contacts_normal_impulses(const double* r, const double* n, int cnt, double* imp) {
    double r1 = v3_dot(r, n);
    if (cnt == 1) {
        imp[0] = r1;
        return;
    }
    double r2 = v3_dot(r, n + 3), c = v3_dot(n, n + 3), g = 1.0 - c * c;
    imp[0] = (r1 - c * r2) / g;
    imp[1] = (r2 - c * r1) / g;
}

static int begin_particle(wc_contacts* ct, const wc_collider* c, int nc, double* x, const double* v, double h,
                          wc_filter* f, int i) {
    int* cid = ct->collider + 2 * i;
    double* cn = ct->normal + 6 * i;
    near_of nf = particle_near(ct, i);
    if (ct->pushed) ct->pushed[i] = 0.0;
    if (f->ndof[i] >= 2) {
        cid[0] = cid[1] = -1;
        for (int q = 0; q < 6; ++q) cn[q] = 0.0;
        ct->released[i] = 0;
        ct->stick[i] = 0;
        return 0;
    }
    wc_filter_free_particle(f, i);
    ct->stick[i] = 0;
    /* consumed here: end sets it again when it releases (it is not called at all when nothing
       is in contact, so a flag left over would keep the particle from ever being caught again) */
    int released = ct->released[i];
    ct->released[i] = 0;
    double* xi = x + 3 * i;
    const double* vi = v + 3 * i;
    best2 b;
    best2_init(&b);
    double move = h * v3_norm(vi), x1[3];
    v3_copy(x1, xi);
    v3_axpy(x1, h, vi);
    for (int k = 0; k < nc; ++k) {
        double vr[3];
        hit H;
        int take;
        /* a path through a moving triangle: always a contact, on that triangle */
        if (c[k].type == WC_COLLIDER_MESH && crossing(&c[k], xi, x1, 0, xi, move, near_entry(&nf, k), &H)) {
            best2_add(&b, k, &H);
            continue;
        }
        query(&c[k], xi, 0, move, &H, near_entry(&nf, k));
        if (!(H.d < HUGE_VAL)) continue;
        v3_sub(vr, vi, H.vc);
        double vn = v3_dot(vr, H.n);
        if (held_contact(ct, i, k))
            take = H.d < h * v3_norm(vr) + SLOP;
        else
            take = H.d < -SLOP || (!released && H.d < h * fmax(0.0, -vn) + SLOP);
        if (take) best2_add(&b, k, &H);
    }
    best2_prune(&b);
    cid[0] = cid[1] = -1;
    for (int q = 0; q < 6; ++q) cn[q] = 0.0;
    if (b.cnt == 0) return 0;

    /* position correction onto / outside both kept shells (or towards them, by the cap) */
    double cap = ct->pushed ? push_cap(c, b.k, b.cnt, h) : HUGE_VAL;
    int moved = push_out(c, b.k, b.h, b.cnt, 0, move, cap, xi, ct->pushed ? ct->pushed + i : NULL, &nf);
    double d[2] = {0.0, 0.0}, n[6] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
    for (int s = 0; s < b.cnt; ++s) {
        if (moved) requery(&c[b.k[s]], xi, 0, move, &b.h[s], near_entry(&nf, b.k[s]));
        d[s] = b.h[s].d < HUGE_VAL ? b.h[s].d : 0.0;
        v3_copy(n + 3 * s, b.h[s].n);
    }
    int cnt = b.cnt;
    double e2[3];
    if (cnt == 2 && ortho(n, n + 3, e2) < PARALLEL_MIN) cnt = 1; /* curvature turned it parallel */

    /* S = I - n1 n1^T (- e2 e2^T); z sets the relative normal velocities to -max(d, 0) / h */
    double a[2] = {0.0, 0.0};
    for (int s = 0; s < cnt; ++s) {
        double vr[3];
        v3_sub(vr, vi, b.h[s].vc);
        a[s] = (h > 0.0 ? -fmax(d[s], 0.0) / h : 0.0) - v3_dot(vr, n + 3 * s);
        cid[s] = b.k[s];
        v3_copy(cn + 3 * s, n + 3 * s);
        if (ct->vel) v3_copy(ct->vel + 6 * i + 3 * s, b.h[s].vc);
    }
    double* S = f->S + 9 * i;
    wc_contacts_free_projector(n, cnt, S);
    v3_span2(n, a[0], n + 3, cnt > 1 ? a[1] : 0.0, cnt > 1, f->z + 3 * i);
    f->ndof[i] = (unsigned char)cnt;
    return 1;
}

int wc_contacts_begin(wc_contacts* ct, const wc_collider* c, int nc, double* x, const double* v, double h,
                      wc_filter* f, wc_par* par) {
    int n = ct->n, used = par->threads;
    WC_PAR_REGION(par)
    {
        int t = wc_par_tid(), nt = wc_par_nt(), lo, hi, cnt = 0;
        if (t == 0) used = nt;
        wc_par_range(n, t, nt, &lo, &hi);
        for (int i = lo; i < hi; ++i) cnt += begin_particle(ct, c, nc, x, v, h, f, i);
        par->partial[8 * t] = cnt;
    }
    ct->active = wc_contacts_sum_counts(par, used);
    ct->h = h;
    return ct->active;
}

static int end_particle(wc_contacts* ct, int nc, const double* r, int i) {
    int* cid = ct->collider + 2 * i;
    double* cn = ct->normal + 6 * i;
    int cnt = (cid[0] >= 0) + (cid[1] >= 0);
    if (cnt == 0 || cid[0] >= nc || cid[1] >= nc) {
        cid[0] = cid[1] = -1;
        ct->released[i] = 0;
        return 0;
    }
    double imp[2];
    wc_contacts_normal_impulses(r + 3 * i, cn, cnt, imp);
    int released = 0, keep = 0;
    int kid[2] = {-1, -1};
    double kn[6] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
    for (int s = 0; s < cnt; ++s) {
        if (imp[s] < 0.0) {
            released = 1;
            continue;
        }
        kid[keep] = cid[s];
        v3_copy(kn + 3 * keep, cn + 3 * s);
        ++keep;
    }
    cid[0] = kid[0];
    cid[1] = kid[1];
    for (int q = 0; q < 6; ++q) cn[q] = kn[q];
    ct->released[i] = (unsigned char)released;
    return keep > 0;
}

void wc_contacts_end(wc_contacts* ct, int nc, const double* r, wc_par* par) {
    int n = ct->n, used = par->threads;
    WC_PAR_REGION(par)
    {
        int t = wc_par_tid(), nt = wc_par_nt(), lo, hi, cnt = 0;
        if (t == 0) used = nt;
        wc_par_range(n, t, nt, &lo, &hi);
        for (int i = lo; i < hi; ++i) cnt += end_particle(ct, nc, r, i);
        par->partial[8 * t] = cnt;
    }
    ct->active = wc_contacts_sum_counts(par, used);
}

/* The two smallest shell distances over all colliders (parallel second normal dropped). */
/* (at the substep's end; reach: for the meshes) */
static void deepest2(const wc_collider* c, int nc, const double* p, double move, best2* b, const near_of* nf) {
    best2_init(b);
    for (int k = 0; k < nc; ++k) {
        hit H;
        query(&c[k], p, 1, move, &H, near_entry(nf, k));
        if (H.d < HUGE_VAL) best2_add(b, k, &H);
    }
    best2_prune(b);
}

/* The last resort of the meshes: a particle whose path x0 -> xi crossed a moving triangle goes
 * back in front of the first one it crossed (at its end position), at the thickness, with no
 * inward velocity relative to it. */
static int uncross(const wc_collider* c, int nc, const double* x0, double* xi, double* vi, const near_of* nf) {
    int moved = 0;
    double dx[3];
    v3_sub(dx, xi, x0);
    double move = v3_norm(dx); /* the reach of the closest-point queries that follow */
    for (int k = 0; k < nc; ++k) {
        hit H;
        if (c[k].type != WC_COLLIDER_MESH || !crossing(&c[k], x0, xi, 1, xi, move, near_entry(nf, k), &H)) continue;
        if (H.d < 0.0) {
            v3_axpy(xi, -H.d, H.n);
            moved = 1;
        }
        double a = v3_dot(H.vc, H.n) - v3_dot(vi, H.n);
        if (a > 0.0) v3_axpy(vi, a, H.n);
    }
    return moved;
}

/* pushed: how far begin moved it (a cap's share already used; NULL: no cap), h the substep. */
static int project_particle(const wc_collider* c, int nc, const double* x0, const double* pushed, double h,
                           double* xi, double* vi, const near_of* nf) {
    int moved = 0;
    double move = 0.0;
    if (x0) {
        double dx[3];
        moved = uncross(c, nc, x0, xi, vi, nf);
        v3_sub(dx, xi, x0);
        move = v3_norm(dx);
    }
    best2 b;
    double spent = 0.0; /* m moved by this projection (the cap's share) */
    int fresh = 0;      /* b is deepest2 at xi */
    for (int round = 0; round < PROJECT_ROUNDS; ++round) {
        deepest2(c, nc, xi, move, &b, nf);
        fresh = 1;
        if (b.cnt == 0 || !(b.h[0].d < 0.0)) break;
        double cap = pushed ? push_cap(c, b.k, b.cnt, h) : HUGE_VAL, by = 0.0;
        if (cap < HUGE_VAL) cap = fmax(0.0, cap - *pushed - spent);
        if (!(cap > 0.0)) break;
        if (push_out(c, b.k, b.h, b.cnt, 1, move, cap, xi, &by, nf)) {
            moved = 1;
            fresh = 0;
        }
        spent += by;
    }
    /* velocity: no inward relative normal velocity on the shells it lies on */
    if (!fresh) deepest2(c, nc, xi, move, &b, nf);
    int cnt = 0;
    double a[2];
    for (int s = 0; s < b.cnt; ++s) {
        if (!(b.h[s].d < SLOP)) break;
        a[s] = v3_dot(b.h[s].vc, b.h[s].n) - v3_dot(vi, b.h[s].n);
        ++cnt;
    }
    if (cnt > 0) {
        double delta[3];
        if (halfspaces(b.h[0].n, a[0], b.h[1].n, cnt > 1 ? a[1] : 0.0, cnt, delta)) v3_add(vi, vi, delta);
    }
    return moved;
}

int wc_contacts_project(const wc_contacts* ct, const wc_collider* c, int nc, const wc_filter* f, double* x,
                        double* v, wc_par* par) {
    return wc_contacts_project_from(ct, c, nc, f, NULL, x, v, par);
}

int wc_contacts_project_from(const wc_contacts* ct, const wc_collider* c, int nc, const wc_filter* f,
                             const double* x0, double* x, double* v, wc_par* par) {
    int n = ct->n, used = par->threads;
    if (nc <= 0) return 0;
    WC_PAR_REGION(par)
    {
        int t = wc_par_tid(), nt = wc_par_nt(), lo, hi, cnt = 0;
        if (t == 0) used = nt;
        wc_par_range(n, t, nt, &lo, &hi);
        for (int i = lo; i < hi; ++i) {
            if (f && f->ndof[i] == 3 && !ct->stick[i]) continue; /* a pin */
            near_of nf = particle_near(ct, i);
            cnt += project_particle(c, nc, x0 ? x0 + 3 * i : NULL, ct->pushed ? ct->pushed + i : NULL, ct->h,
                                   x + 3 * i, v + 3 * i, &nf);
        }
        par->partial[8 * t] = cnt;
    }
    return wc_contacts_sum_counts(par, used);
}
