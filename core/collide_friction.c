/* Coulomb friction of the contacts (collide_friction.h). The rules, all deterministic, per
 * particle, no allocation:
 *  - friction (after the assembly), per particle, with m its mass, f its force, u = S (v - vc)
 *    its relative velocity in the free directions S the normal constraints leave (relative to
 *    the first, deepest collider), z the normal velocity change begin prescribed. The constraint
 *    impulse q it would need to stick (to end the substep with no slip) is predicted twice:
 *      alone:            q = m (z - u) - h f   (-S q = m u + h S f is the tangential momentum it
 *                        would have with no friction; less m mom where the integrator adds
 *                        M mom to the momentum: TR-BDF2's stages, collide_friction.h);
 *      held by springs:  q = A_ii (z - u) - b_i, its neighbours keeping their velocities (a
 *                        particle dragged along by the cloth cannot stop by itself).
 *    Coulomb for each: B = sum mu_k max(N_k, 0), N_k the components of q on the normals (the
 *    landing and centripetal changes, and the tension of springs pressing it on the collider: a
 *    capstan, included). It sticks when |S q| <= B for both: S = 0 and z -= u (all three DOF
 *    constrained: it moves with its collider, and the solve carries the holding force to the
 *    springs around it). Otherwise it slides, the friction being the implicit damping force
 *    -c S (v_new - vc), h c = B / w (B of the particle alone), w the slip expected at the end
 *    of the substep: (|S q| - B) / m alone, which leaves the particle alone with exactly
 *    Coulomb's p (1 - B / |p|), never reversed, and a piece of cloth sliding as one too; when
 *    that is not positive (alone it would stop, its springs say no), (|S q| - B) / (t^T A_ii t)
 *    of the held prediction (t = S q / |S q|). A damping, implicit, only takes energy out of the
 *    cloth (an explicit impulse -B p / |p|, the same for the particle alone, fed energy into
 *    cloth particles whose p was mostly spring force the solve then balanced). Two contacts:
 *    their bounds add up. Exact for a particle alone (a plane, an incline, a landing, a groove,
 *    a moving collider dragging it: test_collide).
 *  - friction recheck (after each solve, by the step): the predictions do not see the whole
 *    cloth. A sticking particle whose holding impulse in the solved system (r_i in its free
 *    directions) exceeds mu times its normal impulses (r_i on the normals) slides instead, with
 *    w = (|r_t| - B) / m, and the step solves again (the stuck set only shrinks; a few passes at
 *    most): e.g. a strip over a cylinder that cannot hold (test_step_contacts' capstan) lets go
 *    from its loaded ends inwards.
 */
#include "collide_friction.h"
#include <math.h>
#include "collide.h"
#include "vec3.h"

/* Kinetic friction as the damping force -c S (v_new - vc): A_ii += h c S, b_i -= h c u. Its impulse
 * h c |u_new| is the Coulomb bound B when |u_new| = w, the slip speed expected at the end of the
 * substep: h c = B / w. Implicit damping only ever takes energy out of the cloth. */
static void slide(double bound, double w, const double* S, const double* u, double* Aii, double* bi) {
    if (!(bound > 0.0) || !(w > 0.0)) return;
    double hc = bound / w;
    m3_axpy(Aii, hc, S);
    v3_axpy(bi, -hc, u);
}

/* Coulomb for a predicted or solved constraint impulse q of particle i: returns the bound
 * B = sum mu_k max(N_k, 0) (N_k the components of q on the normals) and rt = Sn q, the part that
 * friction would have to hold. */
static double coulomb(const wc_collider* c, const int* cid, const double* cn, int cnt, const double* Sn,
                      const double* q, double* rt) {
    double imp[2], bound = 0.0;
    wc_contacts_normal_impulses(q, cn, cnt, imp);
    for (int s = 0; s < cnt; ++s) bound += c[cid[s]].friction * fmax(imp[s], 0.0);
    m3_mulv(rt, Sn, q);
    return bound;
}

static int holds(double bound, double held) { return bound > 0.0 && held <= bound * (1.0 + 1e-9); }

/* Write particle i's filter and friction: stick (S = 0, z = z_n - u) or slide (S = Sn, z = z_n,
 * the damping of slide() with bound B and expected slip w). */
static int apply_mode(wc_contacts* ct, int stick, double bound, double w, int cnt, const double* Sn,
                      const double* u, wc_filter* flt, double* Aii, double* bi, int i) {
    double* S = flt->S + 9 * i;
    double* z = flt->z + 3 * i;
    double zt[3];
    m3_mulv(zt, Sn, z);
    v3_sub(z, z, zt); /* the normal part z_n (a stuck particle's z is z_n - u) */
    if (stick) {
        v3_sub(z, z, u);
        m3_zero(S);
        flt->ndof[i] = 3;
        ct->stick[i] = 1;
        return 1;
    }
    for (int k = 0; k < 9; ++k) S[k] = Sn[k];
    flt->ndof[i] = (unsigned char)cnt;
    ct->stick[i] = 0;
    slide(bound, w, Sn, u, Aii, bi);
    return 0;
}

/* The relative velocity of particle i in the free directions Sn of its contacts (relative to
 * the first collider); returns the number of contacts (0: none, or friction 0 on all). */
static int contact_state(const wc_contacts* ct, const wc_collider* c, int nc, const double* v, int i, double* Sn,
                         double* u) {
    const int* cid = ct->collider + 2 * i;
    int cnt = (cid[0] >= 0) + (cid[1] >= 0);
    if (cnt == 0 || cid[0] >= nc || cid[1] >= nc) return 0;
    if (!(c[cid[0]].friction > 0.0) && !(cnt > 1 && c[cid[1]].friction > 0.0)) return 0;
    wc_contacts_free_projector(ct->normal + 6 * i, cnt, Sn);
    double vr[3];
    v3_sub(vr, v + 3 * i, ct->vel ? ct->vel + 6 * i : c[cid[0]].velocity);
    m3_mulv(u, Sn, vr);
    return cnt;
}

static int friction_particle(wc_contacts* ct, const wc_collider* c, int nc, const double* v, const double* mass,
                             const double* f, const double* mom, double h, wc_filter* flt, double* A,
                             const int* diag, double* b, int i) {
    double Sn[9], u[3];
    int cnt = contact_state(ct, c, nc, v, i, Sn, u);
    if (cnt == 0 || flt->ndof[i] != cnt || !(mass[i] > 0.0)) return 0;
    const int* cid = ct->collider + 2 * i;
    const double* cn = ct->normal + 6 * i;
    double m = mass[i], *Aii = A + 9 * (size_t)diag[i], *bi = b + 3 * i;
    /* the impulse to stick, for the particle alone: q = m (z - u - mom) - h f; and with its
       neighbours keeping their velocities: q = A_ii (z - u) - b_i (its springs resist stopping it) */
    double w0[3], qa[3], qn[3], rta[3], rtn[3];
    v3_sub(w0, flt->z + 3 * i, u);
    v3_scale(qa, w0, m);
    v3_axpy(qa, -h, f + 3 * i);
    if (mom) v3_axpy(qa, -m, mom + 3 * i);
    m3_mulv(qn, Aii, w0);
    v3_sub(qn, qn, bi);
    double ba = coulomb(c, cid, cn, cnt, Sn, qa, rta), bn = coulomb(c, cid, cn, cnt, Sn, qn, rtn);
    double ha = v3_norm(rta), hn = v3_norm(rtn);
    int stick = holds(ba, ha) && holds(bn, hn);
    /* expected slip: what friction leaves of the holding impulse of the particle alone (exact
       for it, and for a piece of cloth sliding as one); when that one would stop but its
       springs would not let it, what is left against its springs */
    double w = (ha - ba) / m;
    if (!(w > 0.0) && hn > bn) {
        double t[3], At[3];
        v3_scale(t, rtn, 1.0 / hn);
        m3_mulv(At, Aii, t);
        double stiff = v3_dot(t, At);
        if (stiff > 0.0) w = (hn - bn) / stiff;
    }
    return apply_mode(ct, stick, ba, w, cnt, Sn, u, flt, Aii, bi, i);
}

int wc_contacts_friction(wc_contacts* ct, const wc_collider* c, int nc, const double* v, const double* mass,
                         const double* f, const double* mom, double h, wc_filter* filter, double* A,
                         const int* diag, double* b, wc_par* par) {
    int n = ct->n, used = par->threads;
    WC_PAR_REGION(par)
    {
        int t = wc_par_tid(), nt = wc_par_nt(), lo, hi, cnt = 0;
        if (t == 0) used = nt;
        wc_par_range(n, t, nt, &lo, &hi);
        for (int i = lo; i < hi; ++i) cnt += friction_particle(ct, c, nc, v, mass, f, mom, h, filter, A, diag, b, i);
        par->partial[8 * t] = cnt;
    }
    return wc_contacts_sum_counts(par, used);
}

/* A sticking particle whose holding impulse in the solved system exceeds its Coulomb bound
 * slides instead; returns 1 when it did. */
static int recheck_particle(wc_contacts* ct, const wc_collider* c, int nc, const double* v, const double* mass,
                            const double* r, wc_filter* flt, double* A, const int* diag, double* b, int i) {
    if (!ct->stick[i]) return 0;
    double Sn[9], u[3], rt[3];
    int cnt = contact_state(ct, c, nc, v, i, Sn, u);
    if (cnt == 0) return 0;
    double bound = coulomb(c, ct->collider + 2 * i, ct->normal + 6 * i, cnt, Sn, r + 3 * i, rt), held = v3_norm(rt);
    if (holds(bound, held)) return 0;
    apply_mode(ct, 0, bound, (held - bound) / mass[i], cnt, Sn, u, flt, A + 9 * (size_t)diag[i], b + 3 * i, i);
    return 1;
}

int wc_contacts_friction_recheck(wc_contacts* ct, const wc_collider* c, int nc, const double* v, const double* mass,
                                 const double* r, wc_filter* filter, double* A, const int* diag, double* b,
                                 wc_par* par) {
    int n = ct->n, used = par->threads;
    WC_PAR_REGION(par)
    {
        int t = wc_par_tid(), nt = wc_par_nt(), lo, hi, cnt = 0;
        if (t == 0) used = nt;
        wc_par_range(n, t, nt, &lo, &hi);
        for (int i = lo; i < hi; ++i) cnt += recheck_particle(ct, c, nc, v, mass, r, filter, A, diag, b, i);
        par->partial[8 * t] = cnt;
    }
    return wc_contacts_sum_counts(par, used);
}
