/* A mesh collider's states fitted by affine maps from its rest frame, and the bound that lets a
 * kept candidate list gathered in an earlier state serve the current one (mesh_pose.h). */
#include "mesh_pose.h"
#include <math.h>
#include "mesh_collider.h"
#include "vec3.h"

#define ROUND 1e-12            /* relative room for the rounding of the fits and the maps */
#define MAP_NORM_MAX 2.0       /* a map (or its inverse) stretching more than this: no bound */

static double row_sum_abs(const double* a, int k) { return fabs(a[3 * k]) + fabs(a[3 * k + 1]) + fabs(a[3 * k + 2]); }
static double norm_inf(const double* a) { return fmax(row_sum_abs(a, 0), fmax(row_sum_abs(a, 1), row_sum_abs(a, 2))); }

/* The least-squares affine map rest (centred) -> x, and its largest residual (max norm) with
 * room for the rounding of x - (A u + b) (HUGE_VAL when not finite). */
static void fit(const wc_mesh_collider* m, const wc_mesh_poses* P, const double* x, double* map, double* res) {
    double c[9] = {0}, sx[3] = {0}, su[3] = {0}, u[3];
    int n = m->n_verts;
    for (int i = 0; i < n; ++i) {
        const double* xi = x + 3 * i;
        v3_sub(u, m->rest + 3 * i, P->centre);
        for (int a = 0; a < 3; ++a) {
            c[3 * a] += xi[a] * u[0];
            c[3 * a + 1] += xi[a] * u[1];
            c[3 * a + 2] += xi[a] * u[2];
        }
        v3_add(sx, sx, xi);
        v3_add(su, su, u);
    }
    /* with sum u = 0 the least squares' A is (sum x u^T) S^-1 and b the mean of x (any map serves:
       the residual is measured) */
    m3_mul(map, c, P->sinv);
    double au[3];
    v3_scale(sx, sx, 1.0 / n);
    v3_scale(su, su, 1.0 / n);
    m3_mulv(au, map, su);
    v3_sub(map + 9, sx, au);
    double r = 0.0, xmax = 0.0;
    for (int i = 0; i < n; ++i) {
        const double* xi = x + 3 * i;
        double p[3];
        v3_sub(u, m->rest + 3 * i, P->centre);
        m3_mulv(p, map, u);
        for (int k = 0; k < 3; ++k) { /* a NaN makes r NaN: no bound */
            double rk = fabs(xi[k] - (p[k] + map[9 + k])), xk = fabs(xi[k]);
            r = rk > r || rk != rk ? rk : r;
            xmax = xk > xmax ? xk : xmax;
        }
    }
    r = r * (1.0 + ROUND) + ROUND * (1.0 + xmax);
    *res = isfinite(r) ? r : HUGE_VAL;
}

/* g's bound from the current state n back to it (mesh_pose.h). M = P_an P_ag^-1 (linear part L)
 * carries xa exactly up to the two fits' residuals; xb_n - M xb_g adds D = P_bn - M P_bg, bounded
 * over the rest box. */
static void relate(const wc_mesh_poses* P, double thickness, const wc_mesh_pose* n, wc_mesh_pose* g) {
    g->ok = 0;
    if (g->epoch < 0 || !(n->res[0] < HUGE_VAL && n->res[1] < HUGE_VAL && g->res[0] < HUGE_VAL && g->res[1] < HUGE_VAL))
        return;
    const double *aan = n->map[0], *ban = n->map[0] + 9, *abn = n->map[1], *bbn = n->map[1] + 9;
    const double *aag = g->map[0], *bag = g->map[0] + 9, *abg = g->map[1], *bbg = g->map[1] + 9;
    double ian[9], iag[9], l[9], k[9];
    if (m3_inverse(ian, aan) == 0.0 || m3_inverse(iag, aag) == 0.0) return;
    m3_mul(l, aan, iag);
    m3_mul(k, aag, ian);
    double nl = norm_inf(l), nk = norm_inf(k);
    if (!(nl < MAP_NORM_MAX && nk < MAP_NORM_MAX)) return;
    /* back: y -> K (y - b_an) + b_ag */
    double kb[3];
    m3_mulv(kb, k, ban);
    for (int i = 0; i < 9; ++i) g->back[i] = k[i], g->back_abs[i] = fabs(k[i]);
    v3_sub(g->back + 9, bag, kb);
    /* D = P_bn - M P_bg: linear A_bn - L A_bg, offset b_bn - L (b_bg - b_ag) - b_an */
    double lab[9], dl[9], t[3], lt[3], doff[3], dmax = 0.0;
    m3_mul(lab, l, abg);
    for (int i = 0; i < 9; ++i) dl[i] = abn[i] - lab[i];
    v3_sub(t, bbg, bag);
    m3_mulv(lt, l, t);
    for (int i = 0; i < 3; ++i) {
        doff[i] = bbn[i] - lt[i] - ban[i];
        double d = fabs(doff[i]);
        for (int j = 0; j < 3; ++j) d += fabs(dl[3 * i + j]) * P->umax[j];
        dmax = fmax(dmax, d);
    }
    double sigma = fmax(n->res[0] + nl * g->res[0], n->res[1] + nl * g->res[1] + dmax);
    /* room for the maps' rounding: their entries are O(1), the offsets the body's coordinates */
    double room = 1.0 + P->umax[0] + P->umax[1] + P->umax[2];
    for (int i = 0; i < 3; ++i) room += fabs(ban[i]) + fabs(bag[i]) + fabs(bbn[i]) + fabs(bbg[i]);
    int ok = 1;
    for (int i = 0; i < 3; ++i) {
        double gi = row_sum_abs(k, i) * (sigma + thickness) - thickness;
        for (int j = 0; j < 3; ++j) {
            double klij = g->back_abs[3 * i] * fabs(l[j]) + g->back_abs[3 * i + 1] * fabs(l[3 + j]) +
                          g->back_abs[3 * i + 2] * fabs(l[6 + j]);
            gi += fmax(0.0, klij - (i == j ? 1.0 : 0.0)) * g->half[j];
        }
        g->grow[i] = fabs(gi) * ROUND + gi + ROUND * room;
        ok &= isfinite(g->grow[i]);
    }
    for (int i = 0; i < 12; ++i) ok &= isfinite(g->back[i]);
    g->ok = ok;
}

void wc_mesh_poses_update(wc_mesh_collider* m) {
    wc_mesh_poses* P = &m->poses;
    long long e = ++P->epoch;
    wc_mesh_pose* cur = P->ring + e % WC_MESH_POSES;
    cur->epoch = e;
    if (!P->can_fit) {
        for (int s = 0; s < WC_MESH_POSES; ++s) P->ring[s].ok = 0;
        return;
    }
    fit(m, P, m->xa, cur->map[0], &cur->res[0]);
    fit(m, P, m->xb, cur->map[1], &cur->res[1]);
    double half[3] = {0.0, 0.0, 0.0};
    for (int t = 0; t < m->n_tris; ++t)
        for (int k = 0; k < 3; ++k) half[k] = fmax(half[k], m->boxes[6 * t + 3 + k] - m->boxes[6 * t + k]);
    for (int k = 0; k < 3; ++k) cur->half[k] = fmax(0.0, 0.5 * half[k] - m->thickness) * (1.0 + ROUND);
    for (int s = 0; s < WC_MESH_POSES; ++s) relate(P, m->thickness, cur, P->ring + s);
}

void wc_mesh_poses_init(wc_mesh_collider* m) {
    wc_mesh_poses* P = &m->poses;
    P->epoch = 0;
    for (int s = 0; s < WC_MESH_POSES; ++s) {
        P->ring[s].epoch = -1;
        P->ring[s].ok = 0;
    }
    int n = m->n_verts;
    double c[3] = {0.0, 0.0, 0.0}, s[9] = {0}, u[3], uu[9];
    for (int i = 0; i < n; ++i) v3_add(c, c, m->rest + 3 * i);
    v3_scale(P->centre, c, 1.0 / n);
    v3_zero(P->umax);
    for (int i = 0; i < n; ++i) {
        v3_sub(u, m->rest + 3 * i, P->centre);
        m3_outer(uu, u, u, 1.0);
        m3_axpy(s, 1.0, uu);
        for (int k = 0; k < 3; ++k) P->umax[k] = fmax(P->umax[k], fabs(u[k]));
    }
    double tr = (s[0] + s[4] + s[8]) / 3.0, det = m3_inverse(P->sinv, s);
    /* flat (or nearly) rest positions leave a direction unfitted */
    P->can_fit = tr > 0.0 && det > 1e-9 * tr * tr * tr;
    wc_mesh_poses_update(m);
}

int wc_mesh_poses_cover(const wc_mesh_poses* P, long long epoch, const double* gbox, const double* box, double slack) {
    /* in the state it was gathered in (the body still), the travel's test decides */
    if (epoch < 0 || epoch == P->epoch) return 0;
    const wc_mesh_pose* g = P->ring + epoch % WC_MESH_POSES;
    if (g->epoch != epoch || !g->ok) return 0;
    double c[3], e[3];
    for (int k = 0; k < 3; ++k) {
        c[k] = 0.5 * (box[k] + box[3 + k]);
        e[k] = 0.5 * (box[3 + k] - box[k]);
    }
    for (int k = 0; k < 3; ++k) {
        const double *b = g->back + 3 * k, *a = g->back_abs + 3 * k;
        double z = b[0] * c[0] + b[1] * c[1] + b[2] * c[2] + g->back[9 + k];
        double r = a[0] * e[0] + a[1] * e[1] + a[2] * e[2] + g->grow[k] + slack;
        if (!(z - r >= gbox[k] && z + r <= gbox[3 + k])) return 0;
    }
    return 1;
}
