/* Newton iterations with a backtracking line search (the potential, constraints and stopping
 * rules are in newton.h). */
#include "newton.h"
#include <math.h>
#include <string.h>
#include "assemble.h"
#include "clock.h"
#include "forces.h"
#include "mesh_pairs.h"
#include "self_pairs.h"
#include "vec3.h"

#define NW_CHUNK 256          /* particles or springs per reduction chunk */
#define NW_ARMIJO 1e-4        /* sufficient-decrease constant */
#define NW_BACKTRACKS 12      /* halvings of the step at most */
#define NW_FLAT 1e-13         /* a decrease below this x |Phi| ends the iterations */
#define NW_ENERGY_EXTRA 4     /* iterations past newton_iterations at most while the iterate gains energy */

int wc_newton_wanted(const wc_sim_def* d) { return d->newton_iterations > 1 || d->line_search; }

void wc_newton_capture(wc_state* s) {
    const wc_model* m = s->model;
    const int* diag = m->pattern.diag;
    for (int k = 0; k < m->n_springs; ++k) memcpy(s->nw_kv0 + 9 * (size_t)k, s->se[k].kv, 9 * sizeof(double));
    for (int i = 0; i < m->n_particles; ++i) memcpy(s->nw_fa + 9 * (size_t)i, s->A + 9 * (size_t)diag[i], 9 * sizeof(double));
    memcpy(s->nw_fb, s->b, 3 * (size_t)m->n_particles * sizeof(double));
}

/* Sum of per-chunk partials in chunk order (independent of the thread count). */
static double chunk_total(const double* partial, int chunks) {
    double sum = 0.0;
    for (int c = 0; c < chunks; ++c) sum += partial[c];
    return sum;
}

static int n_chunks(int items) { return (items + NW_CHUNK - 1) / NW_CHUNK; }

/* a . b over n3 = 3 n entries, by particle chunks. */
static double dot3(wc_state* s, const double* a, const double* b) {
    int n = s->model->n_particles, chunks = n_chunks(n);
    double* part = s->nw_partial;
    WC_PAR_REGION(&s->par)
    {
        int c0, c1;
        wc_par_range(chunks, wc_par_tid(), wc_par_nt(), &c0, &c1);
        for (int c = c0; c < c1; ++c) {
            int hi = (c + 1) * NW_CHUNK < n ? (c + 1) * NW_CHUNK : n;
            double acc = 0.0;
            for (int k = 3 * c * NW_CHUNK; k < 3 * hi; ++k) acc += a[k] * b[k];
            part[c] = acc;
        }
    }
    return chunk_total(part, chunks);
}

/* |S g|^2 by particle chunks. */
static double filtered_norm2(wc_state* s, const double* g) {
    int n = s->model->n_particles, chunks = n_chunks(n);
    double* part = s->nw_partial;
    WC_PAR_REGION(&s->par)
    {
        int c0, c1;
        wc_par_range(chunks, wc_par_tid(), wc_par_nt(), &c0, &c1);
        for (int c = c0; c < c1; ++c) {
            int hi = (c + 1) * NW_CHUNK < n ? (c + 1) * NW_CHUNK : n;
            double acc = 0.0;
            for (int i = c * NW_CHUNK; i < hi; ++i) {
                double o[3];
                wc_filter_apply(&s->filter, i, g + 3 * i, o);
                acc += v3_dot(o, o);
            }
            part[c] = acc;
        }
    }
    return chunk_total(part, chunks);
}

/* x = xb + he (v_n + w), v = v_n + w into nw_x, nw_v. */
static void positions(wc_state* s, const wc_integ* ig, const double* w) {
    int n3 = 3 * s->model->n_particles;
    const double *xb = ig->xb, *v = s->v;
    double *x = s->nw_x, *vv = s->nw_v, he = ig->he;
    WC_PAR_REGION(&s->par)
    {
        int lo, hi;
        wc_par_range(n3, wc_par_tid(), wc_par_nt(), &lo, &hi);
        for (int k = lo; k < hi; ++k) {
            vv[k] = v[k] + w[k];
            x[k] = xb[k] + he * vv[k];
        }
    }
}

static int have_friction(const wc_state* s) { return s->n_all > 0 && s->contacts.active > 0; }

double wc_newton_potential(wc_state* s, const wc_integ* ig, const double* w) {
    const wc_model* m = s->model;
    int n = m->n_particles, fric = have_friction(s);
    positions(s, ig, w);
    const double *x = s->nw_x, *vv = s->nw_v, *x0 = s->x, *mom = ig->mom, *fext = s->f_ext;
    const double *fa = s->nw_fa, *fb = s->nw_fb, *kv0 = s->nw_kv0;
    const double* air = ig->air_implicit ? s->air_lump : NULL;
    double he = ig->he;
    int pc = n_chunks(n), sc = n_chunks(m->n_springs);
    double* part = s->nw_partial;
    WC_PAR_REGION(&s->par)
    {
        int c0, c1;
        wc_par_range(pc, wc_par_tid(), wc_par_nt(), &c0, &c1);
        for (int c = c0; c < c1; ++c) {
            int hi = (c + 1) * NW_CHUNK < n ? (c + 1) * NW_CHUNK : n;
            double acc = 0.0;
            for (int i = c * NW_CHUNK; i < hi; ++i) {
                const double* wi = w + 3 * i;
                double dw[3], dx[3];
                v3_copy(dw, wi);
                if (mom) v3_sub(dw, dw, mom + 3 * i);
                v3_sub(dx, x + 3 * i, x0 + 3 * i);
                acc += 0.5 * m->mass[i] * v3_dot(dw, dw) - v3_dot(fext + 3 * i, dx);
                if (fric) {
                    double Fw[3];
                    m3_mulv(Fw, fa + 9 * (size_t)i, wi);
                    acc += 0.5 * v3_dot(wi, Fw) - v3_dot(fb + 3 * i, wi);
                }
                if (air) {
                    double Lw[3];
                    m3_mulv(Lw, air + 9 * (size_t)i, wi);
                    acc += 0.5 * he * v3_dot(wi, Lw);
                }
            }
            part[c] = acc;
        }
    }
    double phi = chunk_total(part, pc);
    WC_PAR_REGION(&s->par)
    {
        int c0, c1;
        wc_par_range(sc, wc_par_tid(), wc_par_nt(), &c0, &c1);
        for (int c = c0; c < c1; ++c) {
            int hi = (c + 1) * NW_CHUNK < m->n_springs ? (c + 1) * NW_CHUNK : m->n_springs;
            double acc = 0.0;
            for (int k = c * NW_CHUNK; k < hi; ++k) {
                const wc_spring* sp = &m->springs[k];
                double L[3], dv[3], Kd[3];
                v3_sub(L, x + 3 * sp->a, x + 3 * sp->b);
                double dl = wc_spring_extension(sp, v3_norm(L), s->seam_scale);
                v3_sub(dv, vv + 3 * sp->a, vv + 3 * sp->b);
                m3_mulv(Kd, kv0 + 9 * (size_t)k, dv);
                acc += 0.5 * m->material.k[sp->type] * sp->w * dl * dl - 0.5 * he * v3_dot(dv, Kd);
            }
            part[c] = acc;
        }
    }
    phi += chunk_total(part, sc);
    /* the mesh colliders' feature pairs (mesh_pairs.h): k/2 min(g(x(w)), 0)^2, serial */
    if (s->n_mesh > 0 && s->pairs && s->pairs->n > 0) phi += wc_mesh_pairs_energy(s->pairs, x);
    if (s->self_pairs && s->self_pairs->n > 0) phi += wc_self_pairs_energy(s->self_pairs, x);
    return phi;
}

/* TR-BDF2's implicit air at the iterate (newton.h "Refreshed"): air_lump = L(x(w)) and
 * f_ext = M g + f_air(x(w), v_n + w) + L(x(w)) w, so that -he f_ext + he L w, the potential's
 * air gradient, is -he (M g + f_air) at w itself. Expects positions(s, ig, w) done. */
static void refresh_air(wc_state* s, const double* w) {
    const wc_model* m = s->model;
    wc_air_lumped(m, s->nw_x, &s->def.air, &s->par, s->air_lump);
    wc_eval_external(m, s->nw_x, s->nw_v, s->def.gravity, &s->def.air, &s->par, s->tri_scratch, s->f_ext);
    for (int i = 0; i < m->n_particles; ++i) {
        double Lw[3];
        m3_mulv(Lw, s->air_lump + 9 * (size_t)i, w + 3 * i);
        v3_add(s->f_ext + 3 * i, s->f_ext + 3 * i, Lw);
    }
}

/* The Newton system at w: springs at x(w); in TR-BDF2's stages their damping blocks refreshed to
 * x(w)'s directions (nw_kv0 := them: the potential's damping term from now on) and the air to
 * x(w) (refresh_air), otherwise the frozen damping; A (friction's Fa on the diagonal) and
 * g = -grad Phi(w) into nw_g. */
static void newton_system(wc_state* s, const wc_integ* ig, const double* w, wc_compression compression,
                          wc_step_stats* st) {
    const wc_model* m = s->model;
    double t0 = wc_now_ms();
    positions(s, ig, w);
    wc_eval_springs_at(m, s->nw_x, s->nw_zero, compression, s->seam_scale, &s->par, s->se);
    const double* vv = s->nw_v;
    double* kv0 = s->nw_kv0;
    const int refresh = ig->stage != 0;   /* TR-BDF2's stages only (newton.h "Refreshed") */
    wc_spring_eval* se = s->se;
    WC_PAR_REGION(&s->par)
    {
        int lo, hi;
        wc_par_range(m->n_springs, wc_par_tid(), wc_par_nt(), &lo, &hi);
        for (int k = lo; k < hi; ++k) {
            const wc_spring* sp = &m->springs[k];
            double dv[3];
            if (refresh) memcpy(kv0 + 9 * (size_t)k, se[k].kv, 9 * sizeof(double));   /* -d u u^T at x(w) */
            else memcpy(se[k].kv, kv0 + 9 * (size_t)k, 9 * sizeof(double));
            v3_sub(dv, vv + 3 * sp->a, vv + 3 * sp->b);
            m3_mulv_add(se[k].f, se[k].kv, dv);
        }
    }
    if (ig->air_implicit && !have_friction(s)) refresh_air(s, w);   /* contacts: frozen (newton.h) */
    double t1 = wc_now_ms();
    st->ms.forces += t1 - t0;
    wc_assemble(m, se, s->f_ext, s->nw_zero, ig->he, &s->par, s->A, s->nw_g, NULL);
    int fric = have_friction(s);
    const int* diag = m->pattern.diag;
    const double *mom = ig->mom, *fa = s->nw_fa, *fb = s->nw_fb;
    const double* air = ig->air_implicit ? s->air_lump : NULL;
    const double he = ig->he;
    double *g = s->nw_g, *A = s->A;
    WC_PAR_REGION(&s->par)
    {
        int lo, hi;
        wc_par_range(m->n_particles, wc_par_tid(), wc_par_nt(), &lo, &hi);
        for (int i = lo; i < hi; ++i) {
            double* gi = g + 3 * i;
            const double* wi = w + 3 * i;
            for (int c = 0; c < 3; ++c) gi[c] -= m->mass[i] * (wi[c] - (mom ? mom[3 * i + c] : 0.0));
            if (fric) {
                double Fw[3];
                m3_mulv(Fw, fa + 9 * (size_t)i, wi);
                for (int c = 0; c < 3; ++c) gi[c] += fb[3 * i + c] - Fw[c];
                m3_axpy(A + 9 * (size_t)diag[i], 1.0, fa + 9 * (size_t)i);
            }
            if (air) {
                double Lw[3];
                m3_mulv(Lw, air + 9 * (size_t)i, wi);
                for (int c = 0; c < 3; ++c) gi[c] -= he * Lw[c];
                m3_axpy(A + 9 * (size_t)diag[i], he, air + 9 * (size_t)i);
            }
        }
    }
    /* the feature pairs touching at x(w): their force and stiffness (serial: rows shared) */
    if (s->n_mesh > 0 && s->pairs && s->pairs->n > 0) wc_mesh_pairs_newton(s->pairs, s->nw_x, he, A, g);
    if (s->self_pairs && s->self_pairs->n > 0) wc_self_pairs_newton(s->self_pairs, m, s->nw_x, he, A, g);
    st->ms.assemble += wc_now_ms() - t1;
}

/* Friction's terms: what wc_contacts_friction (and its rechecks) added to A's diagonal blocks and
 * to b since wc_newton_capture (zero without contacts). */
static void friction_terms(wc_state* s) {
    const wc_model* m = s->model;
    if (!have_friction(s)) return;
    const int* diag = m->pattern.diag;
    for (int i = 0; i < m->n_particles; ++i) {
        double* fa = s->nw_fa + 9 * (size_t)i;
        const double* Ai = s->A + 9 * (size_t)diag[i];
        for (int q = 0; q < 9; ++q) fa[q] = Ai[q] - fa[q];
    }
    for (int k = 0; k < 3 * m->n_particles; ++k) s->nw_fb[k] = s->b[k] - s->nw_fb[k];
}

/* Total energy (J) of the iterate w: kinetic of v_n + w, springs and gravity's potential at x(w)
 * (the measure of wc_state_total_energy, the step's energy judge). Leaves x(w), v(w) in nw_x, nw_v. */
static double iterate_energy(wc_state* s, const wc_integ* ig, const double* w) {
    const wc_model* m = s->model;
    positions(s, ig, w);
    double e = wc_spring_energy_at(m, s->nw_x, s->seam_scale);
    for (int i = 0; i < m->n_particles; ++i)
        e += 0.5 * m->mass[i] * v3_dot(s->nw_v + 3 * i, s->nw_v + 3 * i) - m->mass[i] * v3_dot(s->def.gravity, s->nw_x + 3 * i);
    return e;
}

static void trace(wc_state* s, int it, double phi, const double* w) {
    if (s->newton_trace) s->newton_trace(s->newton_trace_user, s, it, phi, w);
}

enum { R_FIRST, R_STEP, R_GRADIENT };   /* which linearisation the constraint residual comes from */

wc_status wc_newton_iterate(wc_state* s, const wc_integ* ig, wc_solver_type solver, wc_compression compression,
                              double residual_scale, int want_r, double energy_cap, wc_step_stats* st, wc_diag* diag) {
    const wc_model* m = s->model;
    int n = m->n_particles, n3 = 3 * n;
    int ls = s->def.line_search != 0;
    double* w = s->nw_w;
    double* d = s->nw_d;
    double t0 = wc_now_ms();
    friction_terms(s);
    memcpy(w, s->dv, (size_t)n3 * sizeof(double));
    int rmode = R_FIRST;
    double alpha = 1.0, phi = 0.0;

    if (ls) {
        /* the first step, from w~0 = z + S w0 (w0 = -vstar: x(w0) = x_n) along its free part */
        for (int i = 0; i < n; ++i) {
            double w0[3], o[3];
            v3_scale(w0, ig->vstar + 3 * i, -1.0);
            wc_filter_apply(&s->filter, i, w0, o);
            for (int c = 0; c < 3; ++c) {
                double wt = s->filter.z[3 * i + c] + o[c];
                d[3 * i + c] = s->dv[3 * i + c] - wt;
                w[3 * i + c] = wt;
            }
        }
        double phi0 = wc_newton_potential(s, ig, w);
        if (!isfinite(phi0)) return wc_fail(diag, WC_ERROR_NONFINITE, "newton: non-finite potential at the first iterate");
        trace(s, 0, phi0, w);
        wc_state_mul_system(s, w, s->nw_g);
        for (int k = 0; k < n3; ++k) s->nw_g[k] -= s->b[k];
        double slope = dot3(s, s->nw_g, d);
        double phi1 = 0.0;
        int ok = 0;
        for (int b = 0; b <= NW_BACKTRACKS && !ok; ++b, alpha *= 0.5) {
            if (b == 0) memcpy(s->nw_g, s->dv, (size_t)n3 * sizeof(double)); /* alpha = 1: w1 itself */
            else
                for (int k = 0; k < n3; ++k) s->nw_g[k] = w[k] + alpha * d[k];
            phi1 = wc_newton_potential(s, ig, s->nw_g);
            ok = phi1 <= phi0 + NW_ARMIJO * alpha * (slope < 0.0 ? slope : 0.0);
            if (!ok) ++st->backtracks;
        }
        if (ok) {
            alpha *= 2.0;   /* undo the loop's last halving */
            memcpy(w, s->nw_g, (size_t)n3 * sizeof(double));
            phi = phi1;
        } else {
            alpha = 0.0;
            phi = phi0;
        }
        trace(s, 1, phi, w);
    }

    double gref = residual_scale, tol = s->def.solver.tolerance > 1e-12 ? s->def.solver.tolerance : 1e-12;
    int stop = ls && alpha == 0.0;
    wc_filter fz = s->filter;
    fz.z = s->nw_zero;
    double system_ms = 0.0;
    const int guard = energy_cap < HUGE_VAL;
    for (int it = 1; it < s->def.newton_iterations + (guard ? NW_ENERGY_EXTRA : 0) && !stop; ++it) {
        if (it >= s->def.newton_iterations) {
            /* past the configured count only while the iterate holds more energy than the
               substep started with (newton.h, "Energy guard") */
            if (!(iterate_energy(s, ig, w) > energy_cap)) break;
            ++st->energy_iterations;
        }
        double ts = wc_now_ms();
        newton_system(s, ig, w, compression, st);
        system_ms += wc_now_ms() - ts;
        /* the potential was refreshed at w (damping directions, air): the line search compares
           against its value there */
        if (ls && ig->stage != 0) phi = wc_newton_potential(s, ig, w);
        rmode = R_GRADIENT;
        double gn = sqrt(filtered_norm2(s, s->nw_g));
        if (!(gn > tol * gref)) break;
        memset(d, 0, (size_t)n3 * sizeof(double));
        wc_solve_result res;
        wc_status status = wc_solve(s->solver, solver, s->A, s->nw_g, &fz, d, &s->par, &res);
        wc_step_stats_add_solve(st, solver, &res);
        if (status != WC_OK) break;
        double slope = -dot3(s, s->nw_g, d);   /* grad Phi . d */
        if (!(slope < 0.0)) break;
        alpha = 1.0;
        if (ls) {
            int ok = 0;
            double phi1 = 0.0;
            for (int b = 0; b <= NW_BACKTRACKS && !ok; ++b) {
                if (b > 0) {
                    alpha *= 0.5;
                    ++st->backtracks;
                }
                for (int k = 0; k < n3; ++k) s->dv[k] = w[k] + alpha * d[k];   /* the trial (s->dv: free here) */
                phi1 = wc_newton_potential(s, ig, s->dv);
                ok = phi1 <= phi + NW_ARMIJO * alpha * slope;
            }
            if (!ok) break;
            double drop = phi - phi1;
            memcpy(w, s->dv, (size_t)n3 * sizeof(double));
            phi = phi1;
            trace(s, it + 1, phi, w);
            stop = drop <= NW_FLAT * fabs(phi);
        } else {
            for (int k = 0; k < n3; ++k) w[k] += d[k];
        }
        ++st->newton_iterations;
        rmode = R_STEP;
    }
    /* the accepted iterate, and the constraint residual of its linearisation */
    memcpy(s->dv, w, (size_t)n3 * sizeof(double));
    if (want_r) {
        if (rmode == R_FIRST) {
            wc_state_mul_system(s, w, s->r);
            for (int k = 0; k < n3; ++k) s->r[k] -= s->b[k];
        } else if (rmode == R_GRADIENT) {
            for (int k = 0; k < n3; ++k) s->r[k] = -s->nw_g[k];
        } else {
            for (int k = 0; k < n3; ++k) s->nw_x[k] = alpha * d[k];
            wc_state_mul_system(s, s->nw_x, s->r);
            for (int k = 0; k < n3; ++k) s->r[k] -= s->nw_g[k];
        }
    }
    st->ms.solve += wc_now_ms() - t0 - system_ms;   /* solves and line searches (the systems: forces, assemble) */
    return WC_OK;
}
