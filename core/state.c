/* State creation (every array a step needs is allocated here), validated setters for pins,
 * colliders and positions. */
#include "state.h"
#include "mesh_pairs.h"
#include <math.h>
#include <string.h>
#include "self_collide.h"
#include "self_pairs.h"
#include "vec3.h"

wc_sim_def wc_default_sim_def(void) {
    wc_sim_def d;
    memset(&d, 0, sizeof d);
    v3_set(d.gravity, 0.0, -9.81, 0.0);
    d.air.normal_drag = 0.5;
    d.air.tangent_drag = 0.02;
    d.solver = wc_default_solver_opts();
    d.integrator = WC_INTEGRATOR_BE;
    d.newton_iterations = 1;
    d.line_search = 0;
    d.newton_forcing = 1e-2;
    d.newton_tolerance = 0.0;
    d.stage1_tolerance = 2e-2;
    d.substeps = 1;
    d.substep_dt = 0.0;
    d.compression = WC_COMPRESSION_DROP;
    d.strain_limit = 0.0;
    d.strain_passes = 4;
    d.max_pins = 0;
    d.max_colliders = 16;
    d.max_halvings = 3;
    d.direct_fallback = 1;
    d.fail_strain = 1.0;
    d.fail_energy_growth = 1e3;
    d.fail_energy_gain = 0.01;
    d.threads = 0;
    d.sleep_speed = 1e-3;
    d.sleep_time = 0.5;
    d.self_collision = 0;
    d.self_thickness = 0.003;
    d.self_in_solve = 1;
    return d;
}

static const char* const integrator_names[WC_INTEGRATOR_COUNT] = {"be", "bdf2", "trbdf2"};

const char* wc_integrator_name(wc_integrator t) {
    return (t >= 0 && t < WC_INTEGRATOR_COUNT) ? integrator_names[t] : "unknown";
}

int wc_integrator_from_name(const char* name) {
    if (!name) return -1;
    for (int t = 0; t < WC_INTEGRATOR_COUNT; ++t)
        if (strcmp(name, integrator_names[t]) == 0) return t;
    return -1;
}

static int finite_n(const double* a, int n) {
    for (int i = 0; i < n; ++i)
        if (!isfinite(a[i])) return 0;
    return 1;
}

static wc_status validate_def(const wc_sim_def* d, wc_diag* diag) {
#define BAD(...) return wc_fail(diag, WC_ERROR_INVALID_ARGUMENT, __VA_ARGS__)
    if (!finite_n(d->gravity, 3)) BAD("sim def: gravity must be finite");
    if (!finite_n(d->air.wind, 3)) BAD("sim def: air.wind must be finite");
    if (!(d->air.normal_drag >= 0 && d->air.normal_drag < INFINITY)) BAD("sim def: air.normal_drag must be finite and >= 0");
    if (!(d->air.tangent_drag >= 0 && d->air.tangent_drag < INFINITY)) BAD("sim def: air.tangent_drag must be finite and >= 0");
    if ((unsigned)d->solver.type >= WC_SOLVER_COUNT) BAD("sim def: solver.type %d is not a solver", (int)d->solver.type);
    if (!(d->solver.tolerance >= 0 && d->solver.tolerance < 1)) BAD("sim def: solver.tolerance must be in [0, 1)");
    if (d->solver.max_iterations < 1) BAD("sim def: solver.max_iterations must be >= 1");
    if (d->substeps < 1 || d->substeps > 100000) BAD("sim def: substeps must be in [1, 100000]");
    if (!(d->substep_dt >= 0 && d->substep_dt < INFINITY)) BAD("sim def: substep_dt must be finite and >= 0");
    if (d->compression != WC_COMPRESSION_DROP && d->compression != WC_COMPRESSION_FULL) BAD("sim def: bad compression mode");
    if (!(d->strain_limit >= 0 && d->strain_limit < INFINITY)) BAD("sim def: strain_limit must be finite and >= 0");
    if (d->strain_passes < 0) BAD("sim def: strain_passes must be >= 0");
    if (d->max_pins < 0 || d->max_colliders < 0) BAD("sim def: max_pins and max_colliders must be >= 0");
    if (d->max_halvings < 0 || d->max_halvings > 12) BAD("sim def: max_halvings must be in [0, 12]");
    if (!(d->fail_strain > 0)) BAD("sim def: fail_strain must be > 0");
    if (!(d->fail_energy_growth > 1)) BAD("sim def: fail_energy_growth must be > 1");
    if (!(d->fail_energy_gain >= 0 && d->fail_energy_gain < INFINITY)) BAD("sim def: fail_energy_gain must be finite and >= 0");
    if (!(d->sleep_speed >= 0 && d->sleep_speed < INFINITY)) BAD("sim def: sleep_speed must be finite and >= 0");
    if (!(d->sleep_time >= 0 && d->sleep_time < INFINITY)) BAD("sim def: sleep_time must be finite and >= 0");
    if ((unsigned)d->integrator >= WC_INTEGRATOR_COUNT) BAD("sim def: integrator %d is not an integrator", (int)d->integrator);
    if (d->newton_iterations < 1 || d->newton_iterations > 100) BAD("sim def: newton_iterations must be in [1, 100]");
    if (d->line_search != 0 && d->line_search != 1) BAD("sim def: line_search must be 0 or 1");
    if (!(d->newton_forcing >= 0.0 && d->newton_forcing < 1.0)) BAD("sim def: newton_forcing must be in [0, 1)");
    if (!(d->newton_tolerance >= 0.0 && d->newton_tolerance < 1.0)) BAD("sim def: newton_tolerance must be in [0, 1)");
    if (!(d->stage1_tolerance >= 0.0 && d->stage1_tolerance < 1.0)) BAD("sim def: stage1_tolerance must be in [0, 1)");
    if (d->self_collision != 0 && d->self_collision != 1) BAD("sim def: self_collision must be 0 or 1");
    if (!(d->self_thickness > 0 && d->self_thickness < INFINITY))
        BAD("sim def: self_thickness %g m must be finite and > 0", d->self_thickness);
    if (d->self_in_solve != 0 && d->self_in_solve != 1) BAD("sim def: self_in_solve must be 0 or 1");
#undef BAD
    return WC_OK;
}

void wc_state_mul_system(wc_state* s, const double* x, double* y) {
    wc_bsr_mul(&s->model->pattern, s->A, x, y, &s->par);
    if (s->self_pairs) wc_coupling_mul_offdiag_add(&s->self_pairs->coupling, 1.0, x, y);
}

void wc_state_destroy(wc_state* s) {
    if (!s) return;
    wc_allocator a = s->alloc;
    double* arrays[] = {s->x, s->v, s->pin_from, s->x0, s->v0, s->dv0, s->f_ext, s->f, s->b, s->dv, s->r,
                        s->tri_scratch, s->spring_scratch, s->A, s->filter.S, s->filter.z,
                        s->contacts.normal, s->contacts_save.normal, s->x_prev, s->v_prev, s->x_prev0, s->v_prev0,
                        s->xb, s->xs, s->vstar, s->mom, s->stage1_impulse, s->nw_w, s->nw_d, s->nw_x, s->nw_v,
                        s->nw_zero, s->nw_g, s->nw_fb, s->nw_wh, s->nw_fa, s->air_lump, s->nw_kv0, s->nw_partial,
                        s->energy_memo.x, s->energy_memo.v, s->nw_spring_e, s->nw_spring_e_x};
    for (size_t i = 0; i < sizeof arrays / sizeof arrays[0]; ++i) wc_free(&a, arrays[i]);
    wc_free(&a, s->pins);
    wc_free(&a, s->pin_scratch);
    wc_free(&a, s->colliders);
    wc_free(&a, s->se);
    wc_free(&a, s->filter.ndof);
    wc_free(&a, s->contacts.collider);
    wc_free(&a, s->contacts.released);
    wc_free(&a, s->contacts_save.collider);
    wc_free(&a, s->contacts_save.released);
    wc_free(&a, s->contacts.stick);
    wc_free(&a, s->contacts.vel);
    wc_free(&a, s->contacts.pushed);
    wc_free(&a, s->contacts.near);
    wc_free(&a, s->all_colliders);
    wc_free(&a, s->x_sub);
    wc_mesh_pairs_destroy(s->pairs, &a);
    wc_solver_destroy(s->solver);
    wc_self_destroy(s->self);
    wc_self_pairs_destroy(s->self_pairs, &a);
    wc_free(&a, s);
}

wc_status wc_state_create(wc_state** out, const wc_model* m, const wc_sim_def* def, const wc_allocator* alloc,
                            wc_diag* diag) {
    if (out) *out = NULL;
    if (!out || !m || !def) return wc_fail(diag, WC_ERROR_INVALID_ARGUMENT, "state create: NULL argument");
    if (m->n_particles < 1) return wc_fail(diag, WC_ERROR_EMPTY_MESH, "state create: the model has no particles");
    wc_status st = validate_def(def, diag);
    if (st != WC_OK) return st;
    wc_allocator A = alloc ? *alloc : (wc_allocator){0};
    wc_state* s = WC_NEW(&A, wc_state, 1);
    if (!s) return wc_fail(diag, WC_ERROR_OUT_OF_MEMORY, "state create: out of memory");
    s->model = m;
    s->def = *def;
    s->seam_scale = wc_seam_scale(m, 0.0);
    s->alloc = A;
    wc_par_init(&s->par, def->threads);
    int n = m->n_particles;
    if (s->def.max_pins == 0) s->def.max_pins = n;
    int np = s->def.max_pins, nc = s->def.max_colliders;
    size_t n3 = 3 * (size_t)n;
    s->x = WC_NEW(&A, double, n3);
    s->v = WC_NEW(&A, double, n3);
    s->x0 = WC_NEW(&A, double, n3);
    s->v0 = WC_NEW(&A, double, n3);
    s->dv0 = WC_NEW(&A, double, n3);
    s->f_ext = WC_NEW(&A, double, n3);
    s->f = WC_NEW(&A, double, n3);
    s->b = WC_NEW(&A, double, n3);
    s->dv = WC_NEW(&A, double, n3);
    s->r = WC_NEW(&A, double, n3);
    s->tri_scratch = WC_NEW(&A, double, 3 * (size_t)m->n_tris + 3);
    s->spring_scratch = WC_NEW(&A, double, 3 * (size_t)m->n_springs + 3);
    s->se = WC_NEW(&A, wc_spring_eval, (size_t)m->n_springs + 1);
    s->A = WC_NEW(&A, double, 9 * (size_t)m->pattern.n_blocks);
    s->pins = WC_NEW(&A, wc_pin, (size_t)np + 1);
    s->pin_from = WC_NEW(&A, double, 3 * (size_t)np + 3);
    s->pin_scratch = WC_NEW(&A, int, (size_t)n + 1);
    if (s->pin_scratch)
        for (int i = 0; i < n; ++i) s->pin_scratch[i] = -1;
    s->colliders = WC_NEW(&A, wc_collider, (size_t)nc + 1);
    s->filter.n = n;
    s->filter.S = WC_NEW(&A, double, 9 * (size_t)n);
    s->filter.z = WC_NEW(&A, double, n3);
    s->filter.ndof = WC_NEW(&A, unsigned char, (size_t)n);
    wc_contacts* cts[2] = {&s->contacts, &s->contacts_save};
    for (int k = 0; k < 2; ++k) {
        cts[k]->n = n;
        cts[k]->collider = WC_NEW(&A, int, 2 * (size_t)n);
        cts[k]->normal = WC_NEW(&A, double, 6 * (size_t)n);
        cts[k]->released = WC_NEW(&A, unsigned char, (size_t)n);
    }
    s->contacts.stick = WC_NEW(&A, unsigned char, (size_t)n); /* per substep: not saved */
    s->contacts.vel = WC_NEW(&A, double, 6 * (size_t)n);      /* per substep: not saved */
    s->contacts.pushed = WC_NEW(&A, double, (size_t)n);       /* per substep: not saved */
    double** vecs[] = {&s->x_prev, &s->v_prev, &s->x_prev0, &s->v_prev0, &s->xb, &s->xs, &s->vstar, &s->mom,
                       &s->stage1_impulse, &s->nw_w, &s->nw_d, &s->nw_x, &s->nw_v, &s->nw_zero, &s->nw_g, &s->nw_fb,
                       &s->nw_wh, &s->energy_memo.x, &s->energy_memo.v, &s->nw_spring_e_x};
    int vecs_ok = 1;
    for (size_t k = 0; k < sizeof vecs / sizeof vecs[0]; ++k) vecs_ok &= (*vecs[k] = WC_NEW(&A, double, n3)) != NULL;
    s->nw_fa = WC_NEW(&A, double, 9 * (size_t)n);
    s->air_lump = WC_NEW(&A, double, 9 * (size_t)n);
    s->nw_kv0 = WC_NEW(&A, double, 9 * (size_t)m->n_springs + 9);
    int most = n > m->n_springs ? n : m->n_springs;
    s->nw_partial = WC_NEW(&A, double, (size_t)most / 256 + 1);
    s->nw_spring_e = WC_NEW(&A, double, (size_t)m->n_springs + 1);
    vecs_ok &= s->nw_fa && s->air_lump && s->nw_kv0 && s->nw_partial && s->nw_spring_e;
    if (!s->x || !s->v || !s->x0 || !s->v0 || !s->dv0 || !s->f_ext || !s->f || !s->b || !s->dv || !s->r ||
        !s->tri_scratch || !s->spring_scratch || !s->se || !s->A || !s->pins || !s->pin_from || !s->pin_scratch || !s->colliders ||
        !s->filter.S || !s->filter.z || !s->filter.ndof || !s->contacts.collider || !s->contacts.normal ||
        !s->contacts.released || !s->contacts_save.collider || !s->contacts_save.normal ||
        !s->contacts_save.released || !s->contacts.stick || !s->contacts.vel || !s->contacts.pushed || !vecs_ok) {
        wc_state_destroy(s);
        return wc_fail(diag, WC_ERROR_OUT_OF_MEMORY, "state create: out of memory (%d particles)", n);
    }
    st = wc_solver_create(&s->solver, m, &s->def.solver, s->def.direct_fallback, &A, diag);
    if (st == WC_OK) wc_solver_set_positions(s->solver, s->x); /* the multigrid's rotations (amg.h) */
    if (st == WC_OK && s->def.self_collision) st = wc_self_create(&s->self, m, s->def.self_thickness, &A, diag);
    if (st == WC_OK && s->def.self_collision && s->def.self_in_solve) {
        /* room for one pair per particle and per edge (self_pairs.h; more are counted) */
        int cap = n + s->self->n_edges + 64;
        s->self_pairs = wc_self_pairs_create(cap, n, s->self->n_edges, s->par.threads, 0, &A);
        if (!s->self_pairs) st = wc_fail(diag, WC_ERROR_OUT_OF_MEMORY, "state create: self-contact pairs");
        else st = wc_solver_set_coupling(s->solver, &s->self_pairs->coupling, cap, diag);
    }
    if (st != WC_OK) {
        wc_state_destroy(s);
        return st;
    }
    memcpy(s->x, m->rest_pos, n3 * sizeof(double));
    for (int i = 0; i < n; ++i) s->total_mass += m->mass[i];
    for (int i = 0; i < n; ++i) wc_filter_free_particle(&s->filter, i);
    for (int i = 0; i < 2 * n; ++i) s->contacts.collider[i] = -1;
    v3_copy(s->input_gravity, s->def.gravity);
    s->input_air = s->def.air;
    s->all = s->colliders;
    *out = s;
    return WC_OK;
}

static int pin_equal(const wc_pin* a, const wc_pin* b) {
    return a->particle == b->particle && v3_equal(a->target, b->target) && v3_equal(a->free_axis, b->free_axis);
}

static int collider_equal(const wc_collider* a, const wc_collider* b) {
    return a->type == b->type && v3_equal(a->normal, b->normal) && a->offset == b->offset &&
           v3_equal(a->center, b->center) && v3_equal(a->a, b->a) && v3_equal(a->b, b->b) && a->radius == b->radius &&
           a->thickness == b->thickness && a->friction == b->friction && v3_equal(a->velocity, b->velocity);
}

wc_status wc_state_set_pins(wc_state* s, const wc_pin* pins, int n, wc_diag* diag) {
    if (!s || (n > 0 && !pins)) return wc_fail(diag, WC_ERROR_INVALID_ARGUMENT, "set pins: NULL argument");
    if (n < 0 || n > s->def.max_pins)
        return wc_fail(diag, WC_ERROR_OUT_OF_RANGE, "set pins: %d pins, capacity is %d", n, s->def.max_pins);
    int np = s->model->n_particles;
    int* at = s->pin_scratch;   /* per particle: -1, or -2 - k for new pin k (O(n) checks) */
    wc_status st = WC_OK;
    int k = 0;
    for (; k < n; ++k) {
        const wc_pin* p = &pins[k];
        if (p->particle < 0 || p->particle >= np) {
            st = wc_fail(diag, WC_ERROR_OUT_OF_RANGE, "set pins: pin %d: particle %d is out of range [0, %d)", k,
                         p->particle, np);
            break;
        }
        if (!v3_finite(p->target) || !v3_finite(p->free_axis)) {
            st = wc_fail(diag, WC_ERROR_NONFINITE, "set pins: pin %d: non-finite target or axis", k);
            break;
        }
        double len = v3_norm(p->free_axis);
        if (len != 0.0 && fabs(len - 1.0) > 1e-6) {
            st = wc_fail(diag, WC_ERROR_INVALID_ARGUMENT, "set pins: pin %d: free_axis must be zero or unit (|a| = %g)",
                         k, len);
            break;
        }
        if (at[p->particle] <= -2) {
            st = wc_fail(diag, WC_ERROR_INVALID_ARGUMENT, "set pins: pins %d and %d both hold particle %d",
                         -2 - at[p->particle], k, p->particle);
            break;
        }
        at[p->particle] = -2 - k;
    }
    for (int j = 0; j < k; ++j) at[pins[j].particle] = -1;
    if (st != WC_OK) return st;
    /* where each new pin starts: its old target if the particle was pinned, else where it is
       (reads s->pins and s->x only, so pin_from can be written in place) */
    for (int j = 0; j < s->n_pins; ++j) at[s->pins[j].particle] = j;
    for (k = 0; k < n; ++k) {
        int old = at[pins[k].particle];
        v3_copy(s->pin_from + 3 * k, old >= 0 ? s->pins[old].target : s->x + 3 * pins[k].particle);
    }
    for (int j = 0; j < s->n_pins; ++j) at[s->pins[j].particle] = -1;
    int changed = n != s->n_pins;
    for (k = 0; k < n && !changed; ++k) changed = !pin_equal(&pins[k], &s->pins[k]);
    if (n > 0) memcpy(s->pins, pins, (size_t)n * sizeof(wc_pin));
    s->n_pins = n;
    if (changed) wc_state_wake(s);
    return WC_OK;
}

wc_status wc_state_set_colliders(wc_state* s, const wc_collider* c, int n, wc_diag* diag) {
    if (!s || (n > 0 && !c)) return wc_fail(diag, WC_ERROR_INVALID_ARGUMENT, "set colliders: NULL argument");
    if (n < 0 || n > s->def.max_colliders)
        return wc_fail(diag, WC_ERROR_OUT_OF_RANGE, "set colliders: %d colliders, capacity is %d", n,
                       s->def.max_colliders);
    for (int k = 0; k < n; ++k) {
        const wc_collider* q = &c[k];
        if (q->type < WC_COLLIDER_PLANE || q->type > WC_COLLIDER_CAPSULE)
            return wc_fail(diag, WC_ERROR_INVALID_ARGUMENT, "set colliders: collider %d: unknown type %d", k, q->type);
        if (!v3_finite(q->normal) || !isfinite(q->offset) || !v3_finite(q->center) || !v3_finite(q->a) ||
            !v3_finite(q->b) || !isfinite(q->radius) || !isfinite(q->thickness) || !isfinite(q->friction) ||
            !v3_finite(q->velocity) || !isfinite(q->push_speed))
            return wc_fail(diag, WC_ERROR_NONFINITE, "set colliders: collider %d: non-finite value", k);
        if (q->radius < 0 || q->thickness < 0 || q->friction < 0 || q->push_speed < 0)
            return wc_fail(diag, WC_ERROR_INVALID_ARGUMENT,
                           "set colliders: collider %d: radius, thickness, friction and push_speed must be >= 0", k);
        if (q->type == WC_COLLIDER_PLANE && fabs(v3_norm(q->normal) - 1.0) > 1e-6)
            return wc_fail(diag, WC_ERROR_INVALID_ARGUMENT, "set colliders: collider %d: plane normal must be unit", k);
    }
    int changed = n != s->n_colliders;
    for (int k = 0; k < n && !changed; ++k) changed = !collider_equal(&c[k], &s->colliders[k]);
    if (changed) wc_state_wake(s);
    if (n > 0) memcpy(s->colliders, c, (size_t)n * sizeof(wc_collider));
    if (n != s->n_colliders)
        for (int i = 0; i < 2 * s->model->n_particles; ++i) s->contacts.collider[i] = -1;
    s->n_colliders = n;
    return WC_OK;
}

wc_status wc_state_attach_mesh_colliders(wc_state* s, wc_mesh_collider* const* mesh, int n, wc_diag* diag) {
    if (!s || (n > 0 && !mesh)) return wc_fail(diag, WC_ERROR_INVALID_ARGUMENT, "attach mesh colliders: NULL argument");
    if (n < 0) return wc_fail(diag, WC_ERROR_INVALID_ARGUMENT, "attach mesh colliders: %d colliders", n);
    if (s->n_mesh > 0) return wc_fail(diag, WC_ERROR_INVALID_ARGUMENT, "attach mesh colliders: already attached");
    for (int k = 0; k < n; ++k)
        if (!mesh[k]) return wc_fail(diag, WC_ERROR_INVALID_ARGUMENT, "attach mesh colliders: collider %d is NULL", k);
    if (n == 0) return WC_OK;
    wc_collider* all = WC_NEW(&s->alloc, wc_collider, (size_t)s->def.max_colliders + (size_t)n + 1);
    double* xs = WC_NEW(&s->alloc, double, 3 * (size_t)s->model->n_particles);
    /* each particle's cached candidate triangles of each mesh (mesh_collider.h) */
    size_t n_near = (size_t)s->model->n_particles * (size_t)n;
    wc_mesh_near* near = WC_NEW(&s->alloc, wc_mesh_near, n_near + 1);
    /* feature pairs: room for two per cloth edge and per cloth triangle (mesh_pairs.h) */
    wc_mesh_pairs* pairs = wc_mesh_pairs_create(2 * (s->model->we.n_edges + s->model->n_tris) + 64,
                                                 s->model->n_particles, (const wc_mesh_collider* const*)mesh, n,
                                                 &s->alloc);
    if (!all || !xs || !pairs || !near ||
        !wc_mesh_pairs_keep_candidates(pairs, s->model->we.n_edges + s->model->n_tris, &s->alloc) ||
        !wc_mesh_pairs_set_threads(pairs, s->par.threads, 0, &s->alloc)) {
        wc_free(&s->alloc, all);
        wc_free(&s->alloc, xs);
        wc_free(&s->alloc, near);
        wc_mesh_pairs_destroy(pairs, &s->alloc);
        return wc_fail(diag, WC_ERROR_OUT_OF_MEMORY, "attach mesh colliders: out of memory");
    }
    s->all_colliders = all;
    s->x_sub = xs;
    s->pairs = pairs;
    wc_mesh_near_clear(near, (int)n_near);
    s->contacts.near = near;
    s->contacts.n_near = n;
    s->mesh = mesh;
    s->n_mesh = n;
    for (int i = 0; i < 2 * s->model->n_particles; ++i) s->contacts.collider[i] = -1; /* indices shift */
    wc_state_wake(s);
    return WC_OK;
}

wc_status wc_state_set_mesh_target(wc_state* s, int k, const double* x, wc_diag* diag) {
    if (!s || !x) return wc_fail(diag, WC_ERROR_INVALID_ARGUMENT, "mesh collider positions: NULL argument");
    if (k < 0 || k >= s->n_mesh)
        return wc_fail(diag, WC_ERROR_OUT_OF_RANGE, "mesh collider positions: index %d, the cloth has %d", k, s->n_mesh);
    wc_mesh_collider* m = s->mesh[k];
    int changed = memcmp(m->to, x, 3 * (size_t)m->n_verts * sizeof(double)) != 0;
    wc_status st = wc_mesh_collider_set_target(m, x, diag);
    if (st != WC_OK) return st;
    if (changed) wc_state_wake(s);
    return WC_OK;
}

wc_status wc_state_set_positions(wc_state* s, const double* x, const double* v, wc_diag* diag) {
    if (!s || !x) return wc_fail(diag, WC_ERROR_INVALID_ARGUMENT, "set positions: NULL argument");
    int n3 = 3 * s->model->n_particles;
    if (!finite_n(x, n3) || (v && !finite_n(v, n3)))
        return wc_fail(diag, WC_ERROR_NONFINITE, "set positions: non-finite position or velocity");
    memcpy(s->x, x, (size_t)n3 * sizeof(double));
    if (v) memcpy(s->v, v, (size_t)n3 * sizeof(double));
    else memset(s->v, 0, (size_t)n3 * sizeof(double));
    memset(s->dv, 0, (size_t)n3 * sizeof(double));
    s->hist_valid = 0;   /* BDF2 starts again with a backward-Euler step */
    wc_state_wake(s);
    return WC_OK;
}

void wc_state_wake(wc_state* s) {
    if (s->asleep) s->woke = 1;
    s->asleep = 0;
    s->rest_time = 0.0;
}

void wc_state_set_sleep(wc_state* s, int asleep, double rest_time) {
    if (!asleep) {
        wc_state_wake(s);
    } else {
        memset(s->v, 0, 3 * (size_t)s->model->n_particles * sizeof(double));
        s->asleep = 1;
        s->hist_valid = 0;   /* velocities zeroed: the BDF2 history no longer leads here */
        s->sleep_strain = wc_max_stretch_strain(s->model, s->x);
    }
    v3_copy(s->input_gravity, s->def.gravity);
    s->input_air = s->def.air;
    s->rest_time = rest_time >= 0 && rest_time < INFINITY ? rest_time : 0.0;
}

double wc_state_max_speed(const wc_state* s) {
    double m2 = 0.0;
    for (int i = 0; i < s->model->n_particles; ++i) {
        double q = v3_dot(s->v + 3 * i, s->v + 3 * i);
        if (q > m2) m2 = q;
    }
    return sqrt(m2);
}

double wc_state_residual_floor(const wc_state* s, double he) {
    const wc_model* m = s->model;
    double m2 = 0.0;
    for (int i = 0; i < m->n_particles; ++i) m2 += m->mass[i] * m->mass[i];
    for (int k = 0; k < s->n_pins; ++k) {
        const wc_pin* p = &s->pins[k];
        if (p->free_axis[0] == 0.0 && p->free_axis[1] == 0.0 && p->free_axis[2] == 0.0)
            m2 -= m->mass[p->particle] * m->mass[p->particle];
    }
    return fabs(he) * v3_norm(s->def.gravity) * sqrt(fmax(m2, 0.0));
}

double wc_state_kinetic_energy(const wc_state* s) {
    double e = 0.0;
    const double* m = s->model->mass;
    for (int i = 0; i < s->model->n_particles; ++i) e += 0.5 * m[i] * v3_dot(s->v + 3 * i, s->v + 3 * i);
    return e;
}

double wc_state_total_energy(const wc_state* s, double* elastic) {
    return wc_total_energy_xv(s->model, s->x, s->v, s->def.gravity, s->seam_scale, elastic);
}
