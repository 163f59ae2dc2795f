/* Internal and external forces and their Jacobians (Baraff & Witkin 1998; thesis eq. 4.6).
 * Spring s between particles a and b, L = x_a - x_b, l = |L|, u = L / l:
 *   f_a = -(k (l - rest) + d (v_a - v_b).u) u,   f_b = -f_a
 *   dF_a/dx_a = -k [ u u^T + (1 - rest/l) (I - u u^T) ]      (symmetric)
 *   dF_a/dv_a = -d u u^T                                     (symmetric)
 * and dF_a/dx_b = -dF_a/dx_a etc. The non-symmetric damping part of dF/dx is dropped, as Baraff &
 * Witkin do. For a compressed spring (l < rest) the geometric term (1 - rest/l)(I - u u^T) is
 * negative and makes the system indefinite: by default it is dropped (WC_COMPRESSION_DROP);
 * WC_COMPRESSION_FULL keeps the exact Jacobian. */
#ifndef WEFT_CORE_FORCES_H
#define WEFT_CORE_FORCES_H
#include "model.h"
#include "par.h"

typedef enum wc_compression {
    WC_COMPRESSION_DROP = 0,   /* clamp (1 - rest/l) at 0: SPD system, exact force */
    WC_COMPRESSION_FULL = 1    /* exact Jacobian (may be indefinite under compression) */
} wc_compression;

/* Per-spring force and Jacobian blocks for end a (end b gets -f, and the blocks' signs follow). */
typedef struct wc_spring_eval {
    double f[3];     /* force on particle a (N) */
    double kx[9];    /* dF_a/dx_a (N/m), symmetric, row-major */
    double kv[9];    /* dF_a/dv_a (N s/m), symmetric, row-major */
} wc_spring_eval;

/* Air: wind and drag on each triangle from the relative air velocity u = wind - (v_a+v_b+v_c)/3,
 * with unit normal n and current area A:
 *   f_tri = A ( normal_drag (u.n) n + tangent_drag (u - (u.n) n) ),
 * shared equally among the triangle's three particles. No Jacobian (treated explicitly). */
typedef struct wc_air {
    double wind[3];        /* m/s, world */
    double normal_drag;    /* kg/(m^2 s): pressure per unit relative normal speed */
    double tangent_drag;   /* kg/(m^2 s): skin friction per unit relative tangential speed */
} wc_air;

/* Evaluate every spring (springs in parallel). x, v: (n_particles x 3). out: (n_springs).
 * seam_scale in [0, 1]: host seam pairs' rest length is rest x seam_scale (their ramp, sew.h); a
 * seam spring only pulls (no force beyond damping while l <= rest x seam_scale). wc_eval_springs
 * is seam_scale 0 (every seam closed). */
void wc_eval_springs_at(const wc_model* m, const double* x, const double* v, wc_compression compression,
                        double seam_scale, wc_par* par, wc_spring_eval* out);
void wc_eval_springs(const wc_model* m, const double* x, const double* v, wc_compression compression,
                     wc_par* par, wc_spring_eval* out);
/* wc_eval_springs_at that also writes each spring's energy at x into energy (n_springs; NULL: none): the term
 * wc_spring_energy_at sums, from the same length as the forces (the line search's potential at
 * the substep's start takes them, newton.c). */
void wc_eval_springs_energy_at(const wc_model* m, const double* x, const double* v, wc_compression compression,
                               double seam_scale, wc_par* par, wc_spring_eval* out, double* energy);
/* wc_eval_springs_at with the scalar loops only (where the CPU has AVX, wc_eval_springs_at writes
 * the blocks 4 doubles at a time: the same bits; tests compare the two). */
void wc_eval_springs_scalar(const wc_model* m, const double* x, const double* v, wc_compression compression,
                            double seam_scale, wc_par* par, wc_spring_eval* out);

/* The ramp of host seam pairs at simulated time t (s): max(0, 1 - t / seam_close_time); 0 when
 * that time is 0 or there are no host pairs. */
double wc_seam_scale(const wc_model* m, double t);

/* The extension whose square the spring's energy w k/2 (.)^2 takes at length l (m): l - rest,
 * or for a seam spring max(0, l - rest x seam_scale). */
static inline double wc_spring_extension(const wc_spring* sp, double l, double seam_scale) {
    if (sp->type != WC_SPRING_SEAM) return l - sp->rest;
    double r = sp->rest * seam_scale;
    return l > r ? l - r : 0.0;
}

/* External force per particle: gravity m g, plus air (when normal_drag or tangent_drag > 0;
 * tri_scratch (n_tris x 3) receives per-triangle forces and is then gathered per particle through
 * the model's pattern.row_tri lists). f_ext: (n_particles x 3), overwritten. */
void wc_eval_external(const wc_model* m, const double* x, const double* v, const double gravity[3],
                      const wc_air* air, wc_par* par, double* tri_scratch, double* f_ext);

/* The air force's velocity Jacobian lumped per particle (row sums): out_i (3x3, row-major) =
 * 1/3 sum over the triangles t of i of area_t (normal_drag n n^T + tangent_drag (I - n n^T)), so
 * that f_air(x, v + dv) = f_air(x, v) - out_i dv for a dv shared by the triangle's vertices (and
 * approximately otherwise); symmetric positive semidefinite (kg/s). out: (n_particles x 9). */
void wc_air_lumped(const wc_model* m, const double* x, const wc_air* air, wc_par* par, double* out);

/* Elastic energy of all springs: sum w k/2 extension^2 (J), seams included (seam_scale as in
 * wc_eval_springs_at; wc_spring_energy: 0). */
double wc_spring_energy_at(const wc_model* m, const double* x, double seam_scale);
double wc_spring_energy(const wc_model* m, const double* x);

/* Largest (l - rest) / rest over stretch springs (0 when none is stretched). */
double wc_max_stretch_strain(const wc_model* m, const double* x);

#endif
