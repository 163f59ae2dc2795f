/* Spring forces and Jacobians, gravity and air (formulas in forces.h). Springs and triangles are
 * evaluated in parallel over fixed contiguous ranges; per-particle air forces are gathered by
 * particle through pattern.row_tri, so results do not depend on the thread count. */
#include "forces.h"
#include "vec3.h"

/* Below this fraction of its rest length a spring has no usable direction of its own. */
#define WC_SPRING_DEGENERATE 1e-12

/* Force and blocks of one spring from its unit direction u (a - b), length l, rest length, relative
 * velocity dv = v_a - v_b (3), stiffness k, damping d and the geometric factor c = 1 - rest/l. */
static void spring_blocks(const double* u, double l, double rest, const double* dv, double k, double d, double c,
                          wc_spring_eval* o) {
    double fs = k * (l - rest) + d * v3_dot(dv, u);
    v3_scale(o->f, u, -fs);
    for (int r = 0; r < 3; ++r)
        for (int q = 0; q < 3; ++q) {
            double uu = u[r] * u[q]; /* u_r u_q == u_q u_r exactly: blocks are exactly symmetric */
            o->kx[3 * r + q] = -k * ((1.0 - c) * uu + (r == q ? c : 0.0));
            o->kv[3 * r + q] = -d * uu;
        }
}

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>
#define WC_FORCES_AVX 1
#include <stddef.h>
_Static_assert(sizeof(wc_spring_eval) == 21 * sizeof(double) && offsetof(wc_spring_eval, kx) == 3 * sizeof(double) &&
                   offsetof(wc_spring_eval, kv) == 12 * sizeof(double),
               "a spring's record is f, kx, kv in a row (the AVX stores here and in assemble.c)");
/* spring_blocks a row of 3 at a time in 4 doubles (lane 3 unused), the same products and sums, no
 * FMA: the same bits (the off-diagonal "+ 0.0" is an add of a zero lane). The record is f[3],
 * kx[9], kv[9] in a row: a 4-wide store's 4th lane lands on the next entry, which the next store
 * overwrites; the last row is stored 2 + 1, inside the record. */
__attribute__((target("avx"))) static void spring_blocks_avx(const double* u, double l, double rest, const double* dv,
                                                            double k, double d, double c, wc_spring_eval* o) {
    double fs = k * (l - rest) + d * v3_dot(dv, u);
    /* U = (u_0, u_1, u_2, 0) by loads (valgrind 3.19 does not decode the register vmovq a
       _mm256_set_pd makes of it) */
    const __m256d U = _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_loadu_pd(u)), _mm_load_sd(u + 2), 1);
    _mm256_storeu_pd(o->f, _mm256_mul_pd(U, _mm256_set1_pd(-fs)));
    const __m256d mk = _mm256_set1_pd(-k), md = _mm256_set1_pd(-d), oc = _mm256_set1_pd(1.0 - c);
    const __m256d vc = _mm256_set1_pd(c), zero = _mm256_setzero_pd();
    const __m256d uu[3] = {_mm256_mul_pd(_mm256_set1_pd(u[0]), U), _mm256_mul_pd(_mm256_set1_pd(u[1]), U),
                           _mm256_mul_pd(_mm256_set1_pd(u[2]), U)}; /* u_r u_q, as the scalar's u[r] * u[q] */
    /* row r adds c on lane r and +0.0 elsewhere, as the scalar's (r == q ? c : 0.0) */
    _mm256_storeu_pd(o->kx, _mm256_mul_pd(mk, _mm256_add_pd(_mm256_mul_pd(oc, uu[0]), _mm256_blend_pd(zero, vc, 1))));
    _mm256_storeu_pd(o->kx + 3, _mm256_mul_pd(mk, _mm256_add_pd(_mm256_mul_pd(oc, uu[1]), _mm256_blend_pd(zero, vc, 2))));
    _mm256_storeu_pd(o->kx + 6, _mm256_mul_pd(mk, _mm256_add_pd(_mm256_mul_pd(oc, uu[2]), _mm256_blend_pd(zero, vc, 4))));
    /* after kx: its last row's 4th lane is kv[0] */
    _mm256_storeu_pd(o->kv, _mm256_mul_pd(md, uu[0]));
    _mm256_storeu_pd(o->kv + 3, _mm256_mul_pd(md, uu[1]));
    const __m256d kv2 = _mm256_mul_pd(md, uu[2]);
    _mm_storeu_pd(o->kv + 6, _mm256_castpd256_pd128(kv2));
    _mm_store_sd(o->kv + 8, _mm256_extractf128_pd(kv2, 1));
}
#endif

double wc_seam_scale(const wc_model* m, double t) {
    double T = m->seam_close_time;
    if (!(T > 0.0) || m->n_host_seams == 0) return 0.0;
    double r = 1.0 - t / T;
    return r > 0.0 ? r : 0.0;
}

/* Seam spring (sew.h): only pulls, rest r = rest x seam_scale; linear (f = -kw L) once r = 0;
 * isotropic damping -dw (v_a - v_b). */
static void seam_blocks(const double* L, const double* dv, double r, double kw, double dw, wc_spring_eval* o) {
    double l = v3_norm(L);
    m3_identity(o->kv, -dw);
    for (int q = 0; q < 3; ++q) o->f[q] = -dw * dv[q];
    if (r <= 0.0) {
        v3_axpy(o->f, -kw, L);
        m3_identity(o->kx, -kw);
        return;
    }
    m3_zero(o->kx);
    if (!(l > r)) return; /* slack */
    double u[3], c = 1.0 - r / l;
    v3_scale(u, L, 1.0 / l);
    v3_axpy(o->f, -kw * (l - r), u);
    for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) o->kx[3 * a + b] = -kw * ((1.0 - c) * u[a] * u[b] + (a == b ? c : 0.0));
}

void wc_eval_springs(const wc_model* m, const double* x, const double* v, wc_compression compression,
                     wc_par* par, wc_spring_eval* out) {
    wc_eval_springs_at(m, x, v, compression, 0.0, par, out);
}

static void eval_springs(const wc_model* m, const double* x, const double* v, wc_compression compression,
                         double seam_scale, wc_par* par, wc_spring_eval* out, int vec, double* energy) {
    (void)vec;
    const wc_spring* sp = m->springs;
    const double* k = m->material.k;
    const double* d = m->material.d;
    const double* rp = m->rest_pos;
    WC_PAR_REGION(par)
    {
        int lo, hi;
        wc_par_range(m->n_springs, wc_par_tid(), wc_par_nt(), &lo, &hi);
        for (int s = lo; s < hi; ++s) {
            int a = sp[s].a, b = sp[s].b, t = sp[s].type;
            double rest = sp[s].rest, L[3], u[3] = {0, 0, 0}, dv[3], c = 0.0;
            v3_sub(L, x + 3 * a, x + 3 * b);
            v3_sub(dv, v + 3 * a, v + 3 * b);
            if (t == WC_SPRING_SEAM) { /* zero rest length, linear once closed (sew.h) */
                seam_blocks(L, dv, rest * seam_scale, k[t] * sp[s].w, d[t] * sp[s].w, out + s);
                if (energy) {
                    double dl = wc_spring_extension(&sp[s], v3_norm(L), seam_scale);
                    energy[s] = 0.5 * k[t] * sp[s].w * dl * dl;
                }
                continue;
            }
            double l = v3_norm(L);
            if (energy) { /* wc_spring_energy_at's term, from the same length */
                double dl = l - rest;
                energy[s] = 0.5 * k[t] * sp[s].w * dl * dl;
            }
            if (l > 0.0 && l >= WC_SPRING_DEGENERATE * rest) {
                v3_scale(u, L, 1.0 / l);
                c = 1.0 - rest / l;
                if (compression == WC_COMPRESSION_DROP && c < 0.0) c = 0.0;
            } else {
                /* (nearly) coincident ends have no direction: use the rest direction (pushes them
                 * apart; zero when the rest ends coincide too) with the clamped Jacobian */
                double R[3];
                v3_sub(R, rp + 3 * a, rp + 3 * b);
                double r = v3_norm(R);
                if (r > 0.0) v3_scale(u, R, 1.0 / r);
            }
#ifdef WC_FORCES_AVX
            if (vec) {
                spring_blocks_avx(u, l, rest, dv, k[t], d[t], c, out + s);
                continue;
            }
#endif
            spring_blocks(u, l, rest, dv, k[t], d[t], c, out + s);
        }
    }
}

void wc_eval_springs_at(const wc_model* m, const double* x, const double* v, wc_compression compression,
                        double seam_scale, wc_par* par, wc_spring_eval* out) {
    wc_eval_springs_energy_at(m, x, v, compression, seam_scale, par, out, NULL);
}

void wc_eval_springs_energy_at(const wc_model* m, const double* x, const double* v, wc_compression compression,
                               double seam_scale, wc_par* par, wc_spring_eval* out, double* energy) {
#ifdef WC_FORCES_AVX
    const int vec = __builtin_cpu_supports("avx");
#else
    const int vec = 0;
#endif
    eval_springs(m, x, v, compression, seam_scale, par, out, vec, energy);
}

void wc_eval_springs_scalar(const wc_model* m, const double* x, const double* v, wc_compression compression,
                            double seam_scale, wc_par* par, wc_spring_eval* out) {
    eval_springs(m, x, v, compression, seam_scale, par, out, 0, NULL);
}

/* Air force on triangle t (3): A (cn (u.n) n + ct (u - (u.n) n)), zero for a degenerate one. */
static void air_triangle(const wc_model* m, const double* x, const double* v, const wc_air* air, int t, double* f) {
    const int* tri = m->tris + 3 * t;
    const double *xa = x + 3 * tri[0], *xb = x + 3 * tri[1], *xc = x + 3 * tri[2];
    double e1[3], e2[3], N[3];
    v3_sub(e1, xb, xa);
    v3_sub(e2, xc, xa);
    v3_cross(N, e1, e2);
    double twice_area = v3_norm(N);
    if (!(twice_area > 0.0)) {
        v3_zero(f);
        return;
    }
    double n[3], u[3];
    v3_scale(n, N, 1.0 / twice_area);
    /* u = wind - mean velocity */
    for (int q = 0; q < 3; ++q)
        u[q] = air->wind[q] - (v[3 * tri[0] + q] + v[3 * tri[1] + q] + v[3 * tri[2] + q]) * (1.0 / 3.0);
    double un = v3_dot(u, n), area = 0.5 * twice_area;
    for (int q = 0; q < 3; ++q) f[q] = area * (air->normal_drag * un * n[q] + air->tangent_drag * (u[q] - un * n[q]));
}

void wc_eval_external(const wc_model* m, const double* x, const double* v, const double gravity[3],
                      const wc_air* air, wc_par* par, double* tri_scratch, double* f_ext) {
    int use_air = air && (air->normal_drag != 0.0 || air->tangent_drag != 0.0) && m->n_tris > 0;
    if (use_air) {
        WC_PAR_REGION(par)
        {
            int lo, hi;
            wc_par_range(m->n_tris, wc_par_tid(), wc_par_nt(), &lo, &hi);
            for (int t = lo; t < hi; ++t) air_triangle(m, x, v, air, t, tri_scratch + 3 * t);
        }
    }
    const wc_bsr_pattern* p = &m->pattern;
    WC_PAR_REGION(par)
    {
        int lo, hi;
        wc_par_range(m->n_particles, wc_par_tid(), wc_par_nt(), &lo, &hi);
        for (int i = lo; i < hi; ++i) {
            double* f = f_ext + 3 * i;
            v3_scale(f, gravity, m->mass[i]);
            if (!use_air) continue;
            double acc[3] = {0, 0, 0};
            for (int k = p->row_tri_start[i]; k < p->row_tri_start[i + 1]; ++k)
                v3_add(acc, acc, tri_scratch + 3 * p->row_tri[k]);
            v3_axpy(f, 1.0 / 3.0, acc);
        }
    }
}

void wc_air_lumped(const wc_model* m, const double* x, const wc_air* air, wc_par* par, double* out) {
    const wc_bsr_pattern* p = &m->pattern;
    WC_PAR_REGION(par)
    {
        int lo, hi;
        wc_par_range(m->n_particles, wc_par_tid(), wc_par_nt(), &lo, &hi);
        for (int i = lo; i < hi; ++i) {
            double* L = out + 9 * (size_t)i;
            m3_zero(L);
            for (int k = p->row_tri_start[i]; k < p->row_tri_start[i + 1]; ++k) {
                const int* tri = m->tris + 3 * p->row_tri[k];
                double e1[3], e2[3], N[3], nn[9];
                v3_sub(e1, x + 3 * tri[1], x + 3 * tri[0]);
                v3_sub(e2, x + 3 * tri[2], x + 3 * tri[0]);
                v3_cross(N, e1, e2);
                double twice_area = v3_norm(N);
                if (!(twice_area > 0.0)) continue;
                m3_outer(nn, N, N, 1.0 / (twice_area * twice_area));
                double w = 0.5 * twice_area / 3.0;
                for (int q = 0; q < 9; ++q)
                    L[q] += w * ((air->normal_drag - air->tangent_drag) * nn[q] + (q % 4 == 0 ? air->tangent_drag : 0.0));
            }
        }
    }
}

double wc_spring_energy(const wc_model* m, const double* x) { return wc_spring_energy_at(m, x, 0.0); }

double wc_spring_energy_at(const wc_model* m, const double* x, double seam_scale) {
    double e = 0.0;
    for (int s = 0; s < m->n_springs; ++s) {
        const wc_spring* sp = &m->springs[s];
        double L[3];
        v3_sub(L, x + 3 * sp->a, x + 3 * sp->b);
        double dl = wc_spring_extension(sp, v3_norm(L), seam_scale);
        e += 0.5 * m->material.k[sp->type] * sp->w * dl * dl;
    }
    return e;
}

double wc_max_stretch_strain(const wc_model* m, const double* x) {
    double worst = 0.0;
    for (int s = m->spring_type_start[WC_SPRING_STRETCH]; s < m->spring_type_start[WC_SPRING_STRETCH + 1]; ++s) {
        const wc_spring* sp = &m->springs[s];
        if (!(sp->rest > 0.0)) continue;
        double L[3];
        v3_sub(L, x + 3 * sp->a, x + 3 * sp->b);
        double strain = (v3_norm(L) - sp->rest) / sp->rest;
        if (strain > worst) worst = strain;
    }
    return worst;
}
