/* The CPU substep: backward Euler, BDF2 or TR-BDF2's stages, judged; the CPU's frame (step.h). */
#include "step.h"
#include <math.h>
#include <string.h>
#include "assemble.h"
#include "bdf2.h"
#include "clock.h"
#include "collide.h"
#include "collide_friction.h"
#include "mesh_collider.h"
#include "mesh_pairs.h"
#include "newton.h"
#include "penalty_pairs.h"
#include "self_collide.h"
#include "self_pairs.h"
#include "strain_limit.h"
#include "vec3.h"

#define FRICTION_PASSES 4 /* extra solves of a substep at most, when sticking contacts let go */

/* Target of pin k at fraction alpha of the frame (linear from the frame's start target). */
static void pin_target(const wc_state* s, int k, double alpha, double* out) {
    const double* a = s->pin_from + 3 * k;
    const double* b = s->pins[k].target;
    for (int c = 0; c < 3; ++c) out[c] = a[c] + alpha * (b[c] - a[c]);
}

/* Filter entries of the pins for a substep of length h ending at frame fraction alpha1: the
 * velocity change z takes a pinned particle exactly to its target (a line pin: onto the line);
 * BDF2 and TR-BDF2's stages: x_{n+1} = xb + he v_{n+1} on the target (bdf2.h). */
static void apply_pins(wc_state* s, const wc_integ* ig, double alpha1) {
    double h = ig->h;
    for (int k = 0; k < s->n_pins; ++k) {
        const wc_pin* p = &s->pins[k];
        int i = p->particle;
        double t1[3], want[3];
        pin_target(s, k, alpha1, t1);
        if (ig->xb_form) {
            double xb[3];
            wc_integ_base(s, ig, i, xb);
            for (int c = 0; c < 3; ++c) want[c] = (t1[c] - xb[c]) / ig->he - s->v[3 * i + c];
        } else {
            for (int c = 0; c < 3; ++c) want[c] = (t1[c] - s->x[3 * i + c]) / h - s->v[3 * i + c];
        }
        double* S = s->filter.S + 9 * i;
        double* z = s->filter.z + 3 * i;
        if (v3_norm(p->free_axis) == 0.0) {
            m3_zero(S);
            v3_copy(z, want);
            s->filter.ndof[i] = 3;
        } else {
            m3_outer(S, p->free_axis, p->free_axis, 1.0);
            double along = v3_dot(want, p->free_axis);
            for (int c = 0; c < 3; ++c) z[c] = want[c] - along * p->free_axis[c];
            s->filter.ndof[i] = 2;
        }
    }
}

/* After the positions advance: fully pinned particles sit exactly on their targets. */
static void snap_pins(wc_state* s, const wc_integ* ig, double alpha1) {
    double h = ig->h;
    for (int k = 0; k < s->n_pins; ++k) {
        const wc_pin* p = &s->pins[k];
        if (v3_norm(p->free_axis) != 0.0) continue;
        int i = p->particle;
        double t1[3];
        pin_target(s, k, alpha1, t1);
        if (ig->xb_form)
            for (int c = 0; c < 3; ++c) s->v[3 * i + c] = (t1[c] - ig->xb[3 * i + c]) / ig->he;
        else
            for (int c = 0; c < 3; ++c) s->v[3 * i + c] = (t1[c] - s->x0[3 * i + c]) / h;
        v3_copy(s->x + 3 * i, t1);
    }
}

static int all_finite(const double* a, int n) {
    for (int i = 0; i < n; ++i)
        if (!isfinite(a[i])) return 0;
    return 1;
}

static void save(wc_state* s) {
    size_t n3 = 3 * (size_t)s->model->n_particles * sizeof(double);
    memcpy(s->x0, s->x, n3);
    memcpy(s->v0, s->v, n3);
    memcpy(s->dv0, s->dv, n3);
    int n = s->model->n_particles;
    memcpy(s->contacts_save.collider, s->contacts.collider, 2 * (size_t)n * sizeof(int));
    memcpy(s->contacts_save.normal, s->contacts.normal, 6 * (size_t)n * sizeof(double));
    memcpy(s->contacts_save.released, s->contacts.released, (size_t)n);
    s->contacts_save.active = s->contacts.active;
    wc_integ_save(s);
}

static void restore(wc_state* s) {
    size_t n3 = 3 * (size_t)s->model->n_particles * sizeof(double);
    memcpy(s->x, s->x0, n3);
    memcpy(s->v, s->v0, n3);
    memcpy(s->dv, s->dv0, n3);
    int n = s->model->n_particles;
    memcpy(s->contacts.collider, s->contacts_save.collider, 2 * (size_t)n * sizeof(int));
    memcpy(s->contacts.normal, s->contacts_save.normal, 6 * (size_t)n * sizeof(double));
    memcpy(s->contacts.released, s->contacts_save.released, (size_t)n);
    s->contacts.active = s->contacts_save.active;
    wc_integ_restore(s);
}


/* The colliders of a substep from frame fraction s->sub_alpha0 to alpha1 (length h) into
 * s->all / s->n_all: the mesh colliders first (indices 0 .. n_mesh - 1, moved to this substep:
 * positions, velocities, BVH refit), then the analytic ones. Without mesh colliders s->all is
 * s->colliders. */
static void substep_colliders(wc_state* s, double alpha1, double h) {
    if (s->n_mesh == 0 || !s->all_colliders) {
        s->all = s->colliders;
        s->n_all = s->n_colliders;
        return;
    }
    for (int k = 0; k < s->n_mesh; ++k) {
        wc_mesh_collider* mc = s->mesh[k];
        wc_mesh_collider_substep(mc, s->sub_alpha0, alpha1, h);
        wc_collider* c = &s->all_colliders[k];
        memset(c, 0, sizeof *c);
        c->type = WC_COLLIDER_MESH;
        c->mesh = mc;
        c->thickness = mc->thickness;
        c->friction = mc->friction;
        c->push_speed = mc->push_speed;
    }
    if (s->n_colliders > 0) memcpy(s->all_colliders + s->n_mesh, s->colliders, (size_t)s->n_colliders * sizeof(wc_collider));
    s->all = s->all_colliders;
    s->n_all = s->n_mesh + s->n_colliders;
}

/* Constraints, forces, assembly and friction of a substep of length ig->h ending at frame fraction
 * alpha1: fills s->filter, s->A and s->b (contacts may correct positions) and the integrator's
 * xb, vstar, mom (bdf2.h). begin_gain (J, may be NULL): += the total energy the contacts' position
 * correction (and TR-BDF2's contact velocities, wc_integ_contacts) put in (0 when it lowered it).
 * energy_now (may be NULL): the total energy of the state prepare leaves when it measured it for
 * begin_gain (nothing after that measure moves x or v), else NaN. Returns the contacts that stick. */
static int prepare(wc_state* s, wc_integ* ig, double alpha1, wc_compression compression, double* begin_gain,
                   double* energy_now, wc_step_stats* st) {
    const wc_model* m = s->model;
    int n = m->n_particles;
    double h = ig->h;
    double t0 = wc_now_ms(), t1;
    if (energy_now) *energy_now = NAN;
    for (int i = 0; i < n; ++i) wc_filter_free_particle(&s->filter, i);
    apply_pins(s, ig, alpha1);
    substep_colliders(s, alpha1, h);
    double e0 = begin_gain && s->n_all > 0 ? wc_state_judge_energy(s, s->x, s->v, NULL) : 0.0;
    if (s->n_all > 0) wc_contacts_begin(&s->contacts, s->all, s->n_all, s->x, s->v, h, &s->filter, &s->par);
    /* the substep's start after the contacts' correction: the mesh colliders' crossing test */
    if (s->n_mesh > 0 && s->x_sub) memcpy(s->x_sub, s->x, 3 * (size_t)n * sizeof(double));
    wc_integ_prepare(s, ig);
    if (s->n_all > 0) {
        wc_integ_contacts(s, ig);   /* TR-BDF2: the contacts' normal velocities (bdf2.h) */
        if (begin_gain) {
            double e1 = wc_state_judge_energy(s, s->x, s->v, NULL);
            double gain = e1 - e0;
            if (gain > 0) *begin_gain += gain;
            if (energy_now) *energy_now = e1;
        }
    }
    /* the mesh colliders' feature pairs at the substep's start (mesh_pairs.h) */
    if (s->n_mesh > 0 && s->pairs) {
        wc_mesh_pairs_find(s->pairs, (const wc_mesh_collider* const*)s->mesh, s->n_mesh, m, &s->filter, NULL, s->x,
                           s->v, h, ig->he);
        st->mesh_pairs += s->pairs->list.n;
        st->mesh_pair_overflow += s->pairs->list.overflow;
        st->mesh_pair_skipped += s->pairs->list.skipped;
    }
    /* the self-contact pairs at the substep's start (self_pairs.h) */
    if (s->self_pairs) {
        /* timed as self-collision (ms.self_collide), not as the colliders */
        double ts = wc_now_ms();
        s->self->threads = s->par.threads; /* detection threads (self_pairs.h) */
        wc_self_pairs_find(s->self_pairs, s->self, m, &s->filter, s->x, s->v, h, ig->he);
        st->self_pairs += s->self_pairs->list.n;
        st->self_pair_overflow += s->self_pairs->list.overflow;
        double te = wc_now_ms();
        st->ms.self_collide += te - ts;
        t0 += te - ts;
    }
    t1 = wc_now_ms();
    st->ms.collide += t1 - t0;
    t0 = t1;

    /* with the line search, the springs' energies at x too (its first potential's, newton.c);
       not with contacts: their particles' first iterate moves at the normal velocity, so the
       first potential's state is not this one */
    s->nw_spring_e_valid =
        wc_newton_wanted(&s->def) && s->def.line_search && !(s->n_all > 0 && s->contacts.active > 0);
    if (s->nw_spring_e_valid) {
        wc_eval_springs_energy_at(m, s->x, s->v, compression, s->seam_scale, &s->par, s->se, s->nw_spring_e);
        memcpy(s->nw_spring_e_x, s->x, 3 * (size_t)n * sizeof(double));
        s->nw_spring_e_seam = s->seam_scale;
    } else {
        wc_eval_springs_at(m, s->x, s->v, compression, s->seam_scale, &s->par, s->se);
    }
    wc_eval_external(m, s->x, s->v, s->def.gravity, &s->def.air, &s->par, s->tri_scratch, s->f_ext);
    t1 = wc_now_ms();
    st->ms.forces += t1 - t0;
    t0 = t1;

    wc_assemble(m, s->se, s->f_ext, ig->vstar, ig->he, &s->par, s->A, s->b, s->f); /* s->f: for friction */
    wc_integ_forces(s, ig);
    if (ig->mom)
        for (int i = 0; i < n; ++i) v3_axpy(s->b + 3 * i, m->mass[i], ig->mom + 3 * i);
    if (s->n_mesh > 0 && s->pairs && s->pairs->list.n > 0)
        st->mesh_pairs_active +=
            wc_penalty_pairs_assemble(&s->pairs->list, m, s->x, ig->vstar, s->f_ext, ig->he, s->A, s->b, s->f);
    if (s->self_pairs && s->self_pairs->list.n > 0)
        st->self_pairs_active +=
            wc_penalty_pairs_assemble(&s->self_pairs->list, m, s->x, ig->vstar, s->f_ext, ig->he, s->A, s->b, s->f);
    if (wc_newton_wanted(&s->def)) wc_newton_capture(s);
    t1 = wc_now_ms();
    st->ms.assemble += t1 - t0;
    t0 = t1;

    /* friction: static as constraints (filter), kinetic as implicit damping (A, b): the solve sees both */
    int stuck = 0;
    if (s->n_all > 0 && s->contacts.active > 0)
        stuck = wc_contacts_friction(&s->contacts, s->all, s->n_all, s->v, m->mass, s->f, ig->stage ? ig->mom : NULL,
                                     ig->he, &s->filter, s->A, m->pattern.diag, s->b, &s->par);
    /* the solves' residual floor (solve.h): the impulse gravity gives the unpinned particles in
       this substep, so a cloth at rest does not chase rounding noise */
    wc_solver_set_residual_floor(s->solver, wc_state_residual_floor(s, ig->he));
    st->ms.collide += wc_now_ms() - t0;
    return stuck;
}

void wc_substep_prepare(wc_state* s, double h, double alpha1, wc_step_stats* st) {
    s->sub_alpha0 = alpha1;
    wc_integ ig;
    wc_integ_begin(s, h, &ig);
    (void)prepare(s, &ig, alpha1, s->def.compression, NULL, NULL, st);
}

/* The substep's first solve of its system into s->dv, counted in st. Inexact Newton (newton.h
 * "Inexact"): a first iterate that further iterations correct is solved to forcing x its own
 * residual only, never past tolerance x the floor (the goal tolerance' x max(r0, floor') with
 * tolerance' = forcing, floor' = floor x tolerance / forcing); not where a friction pass reads its
 * contact forces off it (stuck > 0), nor where penalty pairs are in the system (newton.c
 * "Inexact"). res carries the tight solve's scale, Newton's reference. */
static wc_status first_solve(wc_state* s, wc_solver_type solver, int stuck, wc_solve_result* res,
                               wc_step_stats* st) {
    const double tolerance = wc_solver_tolerance(s->solver), floor = wc_solver_residual_floor(s->solver);
    const double forcing = s->def.newton_forcing;
    const int pairs = (s->pairs && s->pairs->list.n > 0) || (s->self_pairs && s->self_pairs->list.n > 0);
    const int loose = solver != WC_SOLVER_DIRECT && stuck == 0 && !pairs && wc_newton_wanted(&s->def) &&
                      s->def.newton_iterations > 1 && forcing > tolerance;
    if (!loose) {
        wc_status status = wc_solve(s->solver, solver, s->A, s->b, &s->filter, s->dv, &s->par, res);
        wc_step_stats_add_solve(st, solver, res);
        return status;
    }
    wc_solver_set_tolerance(s->solver, forcing);
    wc_solver_set_residual_floor(s->solver, floor * tolerance / forcing);
    wc_status status = wc_solve(s->solver, solver, s->A, s->b, &s->filter, s->dv, &s->par, res);
    wc_solver_set_tolerance(s->solver, tolerance);
    wc_solver_set_residual_floor(s->solver, floor);
    res->scale = fmax(res->residual0, floor);
    wc_solve_result counted = *res;
    counted.residual = 0.0;   /* held to the forcing term: counted if it missed that (step_stats.h) */
    wc_step_stats_add_solve(st, solver, &counted);
    return status;
}

/* After the first solve (s->dv) without Newton iterations: the pairs of pp whose solved gap
 * disagrees with their state switch (penalty_pairs.h) and the system is solved again from s->dv,
 * WC_PENALTY_PASSES times at most, each pass counted in *passes and its solve in st and res. With
 * Newton iterations the next iterations see the pairs' exact terms instead: re-solving there as
 * well makes the active set chatter between the passes. */
static wc_status pair_passes(wc_state* s, wc_penalty_pairs* pp, const wc_integ* ig, wc_solver_type solver,
                             wc_solve_result* res, int* passes, wc_step_stats* st) {
    wc_status status = WC_OK;
    for (int pass = 0; pass < WC_PENALTY_PASSES && status == WC_OK; ++pass) {
        if (wc_penalty_pairs_recheck(pp, s->model, s->x, ig->vstar, s->dv, ig->he, s->A, s->b) == 0) break;
        ++*passes;
        status = wc_solve(s->solver, solver, s->A, s->b, &s->filter, s->dv, &s->par, res);
        wc_step_stats_add_solve(st, solver, res);
    }
    return status;
}

/* TR-BDF2's total-energy judgement spans the whole substep (step_judge.h "TR-BDF2's energy"): stage 1
 * fills this in, stage 2 is judged against it. */
typedef struct stage_energy {
    double start_total;     /* J: total energy at the substep's start (stage 1's before.total) */
    double start_elastic;   /* J: its spring part (the allowance's scale) */
    double excluded;        /* J: what stage 1's collider projection and self-collision put in */
} stage_energy;

/* One backward-Euler or BDF2 substep of length h (TR-BDF2: its stage `stage`, 1 or 2, of the
 * substep of length h, with `carry` from stage 1 to stage 2) ending at frame fraction alpha1.
 * Does not roll back: returns non-OK when the result must be discarded, judged as `judge` says.
 * The last resorts use the direct solver with the compressed springs' geometric term dropped (a
 * positive-definite system). */
static wc_status stage_step(wc_state* s, double h, int stage, double alpha1, wc_solver_type solver, int judge,
                              double pin_energy, stage_energy* carry, wc_step_stats* st, wc_diag* diag) {
    const wc_model* m = s->model;
    int n = m->n_particles;
    wc_substep_measure before = {0};
    before.kinetic = wc_state_kinetic_energy(s);
    int judge_energy = wc_substep_judges_energy(s, judge, pin_energy);
    if (judge_energy && stage == 2) {   /* judged from the substep's start */
        before.total = carry->start_total;
        before.elastic = carry->start_elastic;
    } else if (judge_energy) {
        before.total = wc_state_judge_energy(s, s->x, s->v, &before.elastic);
        if (stage == 1) {
            carry->start_total = before.total;
            carry->start_elastic = before.elastic;
        }
    }
    wc_compression compression = judge != WC_JUDGE_ALL ? WC_COMPRESSION_DROP : s->def.compression;
    if (s->self) wc_self_begin(s->self, s->x); /* the previous substep's end: free of crossings */
    wc_integ ig;
    if (stage == 2) wc_integ_begin_stage2(s, h, &ig);
    else wc_integ_begin(s, h, &ig);
    h = ig.h;   /* TR-BDF2: the stage's length */
    double collide_gain = 0.0; /* J */
    /* energy_now: the total energy of the current state where the step last measured it (NaN when
       it has not since the state last changed); the judge's measures of a state an earlier one
       already measured take it instead of measuring again (the same function of the same x and
       v: the same bits) */
    double energy_now = NAN;
    int stuck = prepare(s, &ig, alpha1, compression, judge_energy ? &collide_gain : NULL, &energy_now, st);
    if (s->self_pairs && s->self_pairs->list.overflow > 0)
        wc_log(diag, WC_LOG_WARN, "substep (h = %g s): %d self-contact pairs past the list's capacity %d were left out of the solve",
               h, s->self_pairs->list.overflow, s->self_pairs->list.cap);
    if (s->pairs && (s->pairs->list.overflow > 0 || s->pairs->list.skipped > 0))
        wc_log(diag, WC_LOG_WARN,
               "substep (h = %g s): %d mesh feature pairs past the list's capacity %d and %d without pattern "
               "blocks were left out of the solve",
               h, s->pairs->list.overflow, s->pairs->list.cap, s->pairs->list.skipped);
    /* the colliders' position corrections (begin's push out of the shells, project's at the end)
       are collision responses: a collider pushing a particle out does work on the cloth, which
       the energy judge does not charge to the step (as the self-collision stage's below). The
       Newton energy guard's bound (newton.h): the energy after begin's correction plus the gain
       the judge allows, so that Newton iterates on exactly where the judge would roll back.
       TR-BDF2: stage 1 keeps its own bound (its gain is not judged, but iterating on towards the
       trapezoidal solution makes the stage more accurate); stage 2 has the substep's
       (step_judge.h "TR-BDF2's energy"). */
    double energy_cap = HUGE_VAL;
    if (judge_energy && stage == 2)
        energy_cap = carry->start_total + carry->excluded + collide_gain + wc_substep_energy_allowance(s, &before);
    else if (judge_energy)
        energy_cap = (isnan(energy_now) || s->judge_fresh ? wc_state_judge_energy(s, s->x, s->v, NULL) : energy_now) +
                     wc_substep_energy_allowance(s, &before);
    energy_now = NAN; /* the solves below move the state */
    double t0 = wc_now_ms(), t1;

    wc_solve_result res;
    wc_solver_carry_bounds(s->solver, 1);   /* near an earlier substep's system (solve.h) */
    wc_status status = first_solve(s, solver, stuck, &res, st);
    wc_solver_carry_bounds(s->solver, 0);
    /* sticking contacts whose holding force in the solved cloth exceeds Coulomb's bound slide
       instead, and the system is solved again from this dv (the stuck set only shrinks). With
       Newton iterations to follow, only the first recheck's releases get a solve of their own:
       a later recheck's (the few contacts their released neighbours now overload) go into the
       next Newton iteration's system, which lets them slide (newton.c "Friction") */
    const int newton_takes_tail = wc_newton_wanted(&s->def) && s->def.newton_iterations > 1;
    wc_solver_hold_coarse(s->solver, 1);   /* a pass changes a few contacts' rows (solve.h) */
    for (int pass = 0; pass < FRICTION_PASSES && status == WC_OK && stuck > 0; ++pass) {
        wc_state_mul_system(s, s->dv, s->r);
        for (int k = 0; k < 3 * n; ++k) s->r[k] -= s->b[k];
        int changed = wc_contacts_friction_recheck(&s->contacts, s->all, s->n_all, s->v, m->mass, s->r,
                                                   &s->filter, s->A, m->pattern.diag, s->b, &s->par);
        if (changed == 0) break;
        stuck -= changed;
        if (pass > 0 && newton_takes_tail) break;
        ++st->friction_passes;
        status = wc_solve(s->solver, solver, s->A, s->b, &s->filter, s->dv, &s->par, &res);
        wc_step_stats_add_solve(st, solver, &res);
    }
    wc_solver_hold_coarse(s->solver, 0);
    /* the penalty pairs (the mesh colliders' feature pairs, then the self-contact pairs) whose
       solved gap disagrees with their state switch, and the system is solved again */
    if (status == WC_OK && s->n_mesh > 0 && s->pairs && s->pairs->list.n > 0 && !wc_newton_wanted(&s->def))
        status = pair_passes(s, &s->pairs->list, &ig, solver, &res, &st->mesh_pair_passes, st);
    if (status == WC_OK && s->self_pairs && s->self_pairs->list.n > 0 && !wc_newton_wanted(&s->def))
        status = pair_passes(s, &s->self_pairs->list, &ig, solver, &res, &st->self_pair_passes, st);
    t1 = wc_now_ms();
    st->ms.solve += t1 - t0;
    t0 = t1;
    if (status != WC_OK) {
        wc_fail(diag, status, "substep (h = %g s, %s): the solver failed (status %d)", h, wc_solver_name(solver), (int)status);
        return status;
    }

    int n3 = 3 * n;
    int in_contact = s->n_all > 0 && s->contacts.active > 0;
    int newton = wc_newton_wanted(&s->def);
    if (newton) {
        wc_solver_hold_bounds(s->solver, 1);   /* Newton's systems are near the first solve's */
        status = wc_newton_iterate(s, &ig, solver, compression, res.scale, in_contact, energy_cap, st, diag);
        wc_solver_hold_bounds(s->solver, 0);
        if (status != WC_OK) return status;
    }
    t0 = wc_now_ms();
    if (in_contact) {
        if (!newton) {
            wc_state_mul_system(s, s->dv, s->r);
            for (int k = 0; k < n3; ++k) s->r[k] -= s->b[k];
        }
        for (int k = 0; k < n3; ++k) s->v[k] += s->dv[k];
        if (wc_integ_contact_impulses(s, &ig)) wc_contacts_end(&s->contacts, s->n_all, s->r, &s->par);
    } else {
        for (int k = 0; k < n3; ++k) s->v[k] += s->dv[k];
    }
    t1 = wc_now_ms();
    st->ms.collide += t1 - t0;
    t0 = t1;

    if (ig.xb_form)
        for (int k = 0; k < n3; ++k) s->x[k] = ig.xb[k] + ig.he * s->v[k];
    else
        for (int k = 0; k < n3; ++k) s->x[k] += h * s->v[k];
    snap_pins(s, &ig, alpha1);
    wc_integ_solved(s, &ig);
    t1 = wc_now_ms();
    st->ms.integrate += t1 - t0;
    t0 = t1;
    double strain;
    if (s->def.strain_limit > 0 && s->def.strain_passes > 0)
        strain = wc_strain_limit(m, &s->filter, s->def.strain_limit, s->def.strain_passes, ig.he, s->x, s->v,
                                 s->spring_scratch, &s->par);
    else
        strain = wc_max_stretch_strain(m, s->x);
    t1 = wc_now_ms();
    st->ms.integrate += t1 - t0;
    t0 = t1;
    /* last, so that nothing (strain limiting included) leaves a particle inside a collider */
    if (s->n_all > 0) {
        double e0 = judge_energy ? wc_state_judge_energy(s, s->x, s->v, NULL) : 0.0;
        wc_contacts_project_from(&s->contacts, s->all, s->n_all, &s->filter, s->n_mesh > 0 ? s->x_sub : NULL, s->x,
                                 s->v, &s->par);
        if (s->def.strain_limit > 0) strain = wc_max_stretch_strain(m, s->x);
        if (judge_energy) {
            energy_now = wc_state_judge_energy(s, s->x, s->v, NULL);
            double gain = energy_now - e0;
            if (gain > 0) collide_gain += gain;
        }
    }
    t1 = wc_now_ms();
    st->ms.collide += t1 - t0;
    t0 = t1;
    /* self-collision at the very end: nothing after it may bring a crossing back (the colliders'
       projection and the strain limit run before it; it may leave a particle up to its
       correction inside a collider's thickness shell, never through the cloth) */
    double self_gain = 0.0; /* J: energy the self-collision stage put in (not judged) */
    if (s->self && all_finite(s->x, n3) && all_finite(s->v, n3)) {
        wc_self_stats ss = {0, 0, 0, 0, 0};
        double e0 = !judge_energy ? 0.0 : isnan(energy_now) || s->judge_fresh ? wc_state_judge_energy(s, s->x, s->v, NULL) : energy_now;
        energy_now = judge_energy ? e0 : NAN;
        s->self->threads = s->par.threads; /* detection threads (self_pass.h) */
        wc_self_resolve(s->self, m, &s->filter, s->n_all > 0 ? s->contacts.stick : NULL, ig.he, s->x, s->v, &ss);
        /* moving a vertex out of a collision stretches its springs: that energy comes from the
           collision response (a contact force), not from a failing linearisation, so the
           energy-gain judge does not count it (the kinetic blow-up and strain judges still do) */
        if (judge_energy && ss.proximity + ss.impacts + ss.zones > 0) {
            energy_now = wc_state_judge_energy(s, s->x, s->v, NULL);
            double gain = energy_now - e0;
            if (gain > 0) self_gain = gain;
        }
        /* a stage with nothing counted moved nothing (v += 0 / he: at most -0 -> +0, the same
           kinetic energy), so energy_now is still e0 */
        st->self_proximity += ss.proximity;
        st->self_impacts += ss.impacts;
        st->self_zones += ss.zones;
        st->self_unresolved += ss.unresolved;
        st->self_zone_relaxed += ss.relaxed;
        if (ss.proximity + ss.impacts + ss.zones > 0) strain = wc_max_stretch_strain(m, s->x);
        t1 = wc_now_ms();
        st->ms.self_collide += t1 - t0;
        t0 = t1;
    }

    /* failure checks */
    wc_substep_measure after = {0};
    after.finite = all_finite(s->x, n3) && all_finite(s->v, n3);
    after.strain = strain;
    if (after.finite && judge != WC_JUDGE_FINITE) {
        after.kinetic = wc_state_kinetic_energy(s);
        if (judge_energy) {
            if (isnan(energy_now) || s->judge_fresh) energy_now = wc_state_judge_energy(s, s->x, s->v, NULL);
            after.total = energy_now - self_gain - collide_gain;
        }
        if (judge_energy && stage == 2) after.total -= carry->excluded;
    }
    const int judged = judge_energy && after.finite && judge != WC_JUDGE_FINITE;
    st->judged_energy_end = judged ? energy_now : NAN;
    st->judged_total = judged ? after.total : NAN;
    st->judged_cap = judged ? energy_cap : NAN;
    if (judge_energy && stage == 1) carry->excluded = self_gain + collide_gain;
    status = wc_substep_judge(s, &before, &after, judge, judge_energy && stage != 1, pin_energy, h,
                              wc_solver_name(solver), diag);
    st->max_strain = strain;
    if (status == WC_OK && ig.bdf2) ++st->bdf2_substeps;
    t1 = wc_now_ms();
    st->ms.integrate += t1 - t0;
    return status;
}

/* One substep of length h ending at frame fraction alpha1 (from s->sub_alpha0): a stage_step, or
 * TR-BDF2's two (stage 1 to the fraction gamma of the way, bdf2.h). */
static wc_status substep(wc_state* s, double h, double alpha1, wc_solver_type solver, int judge,
                           double pin_energy, wc_step_stats* st, wc_diag* diag) {
    if (s->def.integrator != WC_INTEGRATOR_TRBDF2)
        return stage_step(s, h, 0, alpha1, solver, judge, pin_energy, NULL, st, diag);
    double a0 = s->sub_alpha0, ag = a0 + WC_TRBDF2_GAMMA * (alpha1 - a0);
    stage_energy carry = {0.0, 0.0, 0.0};
    wc_status status = stage_step(s, h, 1, ag, solver, judge, pin_energy, &carry, st, diag);
    if (status != WC_OK) return status;
    s->sub_alpha0 = ag;
    status = stage_step(s, h, 2, alpha1, solver, judge, pin_energy, &carry, st, diag);
    s->sub_alpha0 = a0;
    return status;
}


/* ---- the CPU backend's operations ------------------------------------------------------------ */

static wc_status cpu_substep(void* user, wc_state* s, double h, double alpha1, wc_solver_type solver, int judge,
                               double pin_energy, wc_step_stats* st, wc_diag* diag) {
    (void)user;
    return substep(s, h, alpha1, solver, judge, pin_energy, st, diag);
}

static void cpu_save(void* user, wc_state* s) {
    (void)user;
    save(s);
}

static void cpu_restore(void* user, wc_state* s) {
    (void)user;
    restore(s);
    wc_solver_invalidate_rho(s->solver);
    wc_solver_invalidate_bounds(s->solver);   /* the retry estimates afresh */
}

static void cpu_measure(void* user, const wc_state* s, double* max_speed, double* kinetic, double* max_strain) {
    (void)user;
    *max_speed = wc_state_max_speed(s);
    *kinetic = wc_state_kinetic_energy(s);
    *max_strain = wc_max_stretch_strain(s->model, s->x);
}

wc_status wc_step_frame(wc_state* s, double dt, wc_step_stats* stats, wc_diag* diag) {
    wc_step_ops ops = {NULL, cpu_substep, cpu_save, cpu_restore, cpu_measure, NULL, WC_SOLVER_DIRECT};
    return wc_step_frame_ops(s, dt, stats, diag, &ops);
}
