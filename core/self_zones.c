/* Impact zones (self_zones.h): a zone's rigid motion, and the springs it stretched relaxed by
 * moving the particles outside the zones. */
#include <math.h>
#include <string.h>

#include "self_zones.h"
#include "union_find.h"
#include "vec3.h"

#define PIN_WEIGHT 1e8 /* a pinned particle's mass in a zone, relative to its own */

void wc_self_rigidify(int n, const double* x_start, double* x, const double* mass, const double* inv_m, int* parent,
                      const unsigned char* in, double* acc) {
    /* acc per root: 0 M, 1-3 sum w x0, 4-6 sum w d, 7-9 L, 10-18 I (3x3) */
    for (int i = 0; i < n; ++i)
        if (in[i]) memset(acc + WC_SELF_ZONE_STRIDE * (size_t)wc_uf_find(parent, i), 0, WC_SELF_ZONE_STRIDE * sizeof(double));
    for (int i = 0; i < n; ++i) {
        if (!in[i]) continue;
        double* a = acc + WC_SELF_ZONE_STRIDE * (size_t)wc_uf_find(parent, i);
        double w = inv_m[i] > 0 ? mass[i] : PIN_WEIGHT * (mass[i] > 0 ? mass[i] : 1.0);
        double d[3];
        v3_sub(d, x + 3 * i, x_start + 3 * i);
        a[0] += w;
        v3_axpy(a + 1, w, x_start + 3 * i);
        v3_axpy(a + 4, w, d);
    }
    for (int i = 0; i < n; ++i) {
        if (!in[i]) continue;
        int root = wc_uf_find(parent, i);
        double* a = acc + WC_SELF_ZONE_STRIDE * (size_t)root;
        double w = inv_m[i] > 0 ? mass[i] : PIN_WEIGHT * (mass[i] > 0 ? mass[i] : 1.0);
        double xc[3], vc[3], r[3], d[3], rd[3];
        v3_scale(xc, a + 1, 1.0 / a[0]);
        v3_scale(vc, a + 4, 1.0 / a[0]);
        v3_sub(r, x_start + 3 * i, xc);
        v3_sub(d, x + 3 * i, x_start + 3 * i);
        v3_sub(d, d, vc);
        v3_cross(rd, r, d);
        v3_axpy(a + 7, w, rd);
        double rr = v3_dot(r, r);
        for (int p = 0; p < 3; ++p)
            for (int q = 0; q < 3; ++q) a[10 + 3 * p + q] += w * ((p == q ? rr : 0.0) - r[p] * r[q]);
    }
    /* angular velocity of each root: I^-1 L (regularised: a line-shaped zone has no inertia about
       its line, and no angular momentum about it either) */
    for (int i = 0; i < n; ++i) {
        if (!in[i] || wc_uf_find(parent, i) != i) continue;
        double* a = acc + WC_SELF_ZONE_STRIDE * (size_t)i;
        double I[9], Iinv[9] = {0}, om[3];
        memcpy(I, a + 10, sizeof I);
        double tr = I[0] + I[4] + I[8];
        for (int k = 0; k < 3; ++k) I[4 * k] += 1e-12 * tr + 1e-300;
        if (m3_inverse(Iinv, I) == 0.0) memset(Iinv, 0, sizeof Iinv); /* no inertia at all: translate */
        m3_mulv(om, Iinv, a + 7);
        v3_copy(a + 7, om); /* L no longer needed: 7-9 now hold omega */
    }
    for (int i = 0; i < n; ++i) {
        if (!in[i] || !(inv_m[i] > 0)) continue;
        const double* a = acc + WC_SELF_ZONE_STRIDE * (size_t)wc_uf_find(parent, i);
        double xc[3], r[3], wr[3], wwr[3];
        v3_scale(xc, a + 1, 1.0 / a[0]);
        v3_sub(r, x_start + 3 * i, xc);
        /* the rotation by the angle |omega| about omega (Rodrigues: R r = r + sin(t)/t w x r +
           (1 - cos(t))/t^2 w x (w x r), t = |w|), not its linearisation r + w x r, which
           lengthens distances across the zone by up to a factor sqrt(1 + t^2) */
        double t2 = v3_dot(a + 7, a + 7), t = sqrt(t2);
        double s1 = t < 1e-4 ? 1.0 - t2 / 6.0 : sin(t) / t;
        double s2 = t < 1e-4 ? 0.5 - t2 / 24.0 : (1.0 - cos(t)) / t2;
        v3_cross(wr, a + 7, r);
        v3_cross(wwr, a + 7, wr);
        for (int k = 0; k < 3; ++k)
            x[3 * i + k] = x_start[3 * i + k] + a[4 + k] / a[0] + s1 * wr[k] + s2 * wwr[k];
    }
}

static double strain_of(const wc_spring* sp, const double* x) {
    double L[3];
    v3_sub(L, x + 3 * sp->a, x + 3 * sp->b);
    return (v3_norm(L) - sp->rest) / sp->rest;
}

/* one spring's strain limit (Provot): 1 when it moved its ends */
static int relax_spring(const wc_spring* sp, const double* x_old, double* x, const unsigned char* in,
                        const double* inv_m, double floor, unsigned char* moved) {
    int a = sp->a, b = sp->b;
    double wa = in[a] ? 0.0 : inv_m[a], wb = in[b] ? 0.0 : inv_m[b];
    if (!(sp->rest > 0.0) || !(wa + wb > 0.0)) return 0;
    double d[3];
    v3_sub(d, x + 3 * a, x + 3 * b);
    double L = v3_norm(d);
    if (!(L > sp->rest * (1.0 + floor))) return 0; /* within the floor: no need of x_old's strain */
    double limit = sp->rest * (1.0 + fmax(strain_of(sp, x_old), floor));
    if (!(L > limit)) return 0;
    double c = (L - limit) / (L * (wa + wb));
    v3_axpy(x + 3 * a, -wa * c, d);
    v3_axpy(x + 3 * b, wb * c, d);
    if (moved) {
        moved[a] |= wa > 0.0;
        moved[b] |= wb > 0.0;
    }
    return 1;
}

int wc_self_relax_zones(const wc_model* m, const double* x_old, double* x, const unsigned char* in,
                        const double* inv_m, double floor, int passes, unsigned char* moved) {
    int corrections = 0;
    const int s0 = m->spring_type_start[WC_SPRING_STRETCH], s1 = m->spring_type_start[WC_SPRING_STRETCH + 1];
    for (int p = 0; p < passes; ++p) {
        int this_pass = 0;
        for (int s = s0; s < s1; ++s) {
            if (!relax_spring(&m->springs[s], x_old, x, in, inv_m, floor, moved)) continue;
            ++this_pass;
        }
        corrections += this_pass;
        if (this_pass == 0) break;
    }
    return corrections;
}

void wc_self_relax_mark(const wc_model* m, const wc_self_relax_set* rs, int i) {
    const int s0 = m->spring_type_start[WC_SPRING_STRETCH], s1 = m->spring_type_start[WC_SPRING_STRETCH + 1];
    const wc_bsr_pattern* pt = &m->pattern;
    for (int k = pt->row_spring_start[i]; k < pt->row_spring_start[i + 1]; ++k) {
        int t = pt->row_spring[k];
        if (t >= s0 && t < s1) rs->due[(t - s0) >> 6] |= (uint64_t)1 << ((t - s0) & 63);
    }
}

/* a correction at spring s moved its ends: their springs are due in the next pass, and those after
   s in this one (the ends' positions changed since the full pass's check; both ends, whatever
   their weights: a zero weight's step may still flip a zero's sign) */
static void mark_moved(const wc_model* m, wc_self_relax_set* rs, int s0, int s1, int s, int i) {
    const wc_bsr_pattern* pt = &m->pattern;
    for (int k = pt->row_spring_start[i]; k < pt->row_spring_start[i + 1]; ++k) {
        int t = pt->row_spring[k];
        if (t < s0 || t >= s1) continue;
        uint64_t bit = (uint64_t)1 << ((t - s0) & 63);
        rs->next[(t - s0) >> 6] |= bit;
        if (t > s) rs->due[(t - s0) >> 6] |= bit;
    }
}

int wc_self_relax_zones_due(const wc_model* m, const double* x_old, double* x, const unsigned char* in,
                            const double* inv_m, double floor, int passes, unsigned char* moved,
                            wc_self_relax_set* rs) {
    int corrections = 0;
    const int s0 = m->spring_type_start[WC_SPRING_STRETCH], s1 = m->spring_type_start[WC_SPRING_STRETCH + 1];
    for (int p = 0; p < passes; ++p) {
        int this_pass = 0;
        for (int w = 0; w < rs->words; ++w) {
            uint64_t bits;
            while ((bits = rs->due[w]) != 0) { /* re-read: a correction may mark later springs of w */
                int s = s0 + 64 * w + __builtin_ctzll(bits);
                rs->due[w] = bits & (bits - 1);
                const wc_spring* sp = &m->springs[s];
                if (!relax_spring(sp, x_old, x, in, inv_m, floor, moved)) continue;
                mark_moved(m, rs, s0, s1, s, sp->a);
                mark_moved(m, rs, s0, s1, s, sp->b);
                ++this_pass;
            }
        }
        uint64_t* t = rs->due; /* every bit consumed: the due set is the next pass's scratch */
        rs->due = rs->next;
        rs->next = t;
        corrections += this_pass;
        if (this_pass == 0) break;
    }
    return corrections;
}
