/* The mesh colliders' feature contacts in the implicit solve (core/mesh_pairs.c,
 * core/penalty_pairs.c): a coarse sheet (25 cm between particles) dropped onto a roof-shaped prism
 * whose sharp ridge runs between two columns of particles, and onto a pyramid whose apex is under
 * the middle of one cloth triangle. Every particle stays out of the bodies either way (its own
 * contacts); the ridge and the apex would cut through the cloth between the particles. Checked
 * after every frame, by brute force and independently of the pairs: no body edge intersects a
 * cloth triangle (segment-triangle test), and no particle is behind a body's surface. Also: the
 * pair term's force and Jacobian against finite differences of its energy (one edge-edge, one
 * vertex-triangle pair, found by the detection), its assembly into A and b, and Newton's potential
 * non-increasing along its line search while pairs are active. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "check.h"
#include "geom.h"
#include "mesh_collider.h"
#include "mesh_pairs.h"
#include "newton.h"
#include "step.h"
#include "test_support.h"
#include "vec3.h"

typedef struct tmesh {
    int nv, nt;
    double x[3 * 16];
    int t[3 * 16];
} tmesh;

static int tm_vert(tmesh* m, double x, double y, double z) {
    v3_set(m->x + 3 * m->nv, x, y, z);
    return m->nv++;
}
static void tm_tri(tmesh* m, int a, int b, int c) {
    m->t[3 * m->nt] = a;
    m->t[3 * m->nt + 1] = b;
    m->t[3 * m->nt + 2] = c;
    ++m->nt;
}

/* A prism along z (z in [-len, len]) with a triangular section: base [cx - hw, cx + hw] at y = 0,
 * ridge at (cx, h); closed, wound outwards. */
static void roof(tmesh* m, double cx, double hw, double h, double len) {
    m->nv = m->nt = 0;
    int a0 = tm_vert(m, cx - hw, 0, -len), b0 = tm_vert(m, cx + hw, 0, -len), r0 = tm_vert(m, cx, h, -len);
    int a1 = tm_vert(m, cx - hw, 0, len), b1 = tm_vert(m, cx + hw, 0, len), r1 = tm_vert(m, cx, h, len);
    tm_tri(m, a0, r0, b0);               /* back end (-z) */
    tm_tri(m, a1, b1, r1);               /* front end (+z) */
    tm_tri(m, a0, a1, r1), tm_tri(m, a0, r1, r0); /* left slope */
    tm_tri(m, b0, r0, r1), tm_tri(m, b0, r1, b1); /* right slope */
    tm_tri(m, a0, b0, b1), tm_tri(m, a0, b1, a1); /* base */
}

/* A square pyramid: base [cx -+ hw] x [cz -+ hw] at y = 0, apex (cx, h, cz); closed, outwards. */
static void pyramid(tmesh* m, double cx, double cz, double hw, double h) {
    m->nv = m->nt = 0;
    int c[4];
    c[0] = tm_vert(m, cx - hw, 0, cz - hw);
    c[1] = tm_vert(m, cx + hw, 0, cz - hw);
    c[2] = tm_vert(m, cx + hw, 0, cz + hw);
    c[3] = tm_vert(m, cx - hw, 0, cz + hw);
    int apex = tm_vert(m, cx, h, cz);
    for (int k = 0; k < 4; ++k) tm_tri(m, c[(k + 1) % 4], c[k], apex);
    tm_tri(m, c[0], c[1], c[2]);
    tm_tri(m, c[0], c[2], c[3]);
}

/* Segment p-q against triangle (a, b, c), Moller-Trumbore: 1 when they intersect (strictly
 * inside both, by a margin of 1e-9 in the parameters). */
static int segment_hits_triangle(const double* p, const double* q, const double* a, const double* b,
                                 const double* c) {
    double d[3], e1[3], e2[3], h[3], s[3], qv[3];
    v3_sub(d, q, p);
    v3_sub(e1, b, a);
    v3_sub(e2, c, a);
    v3_cross(h, d, e2);
    double det = v3_dot(e1, h);
    if (fabs(det) < 1e-15) return 0;
    double inv = 1.0 / det;
    v3_sub(s, p, a);
    double u = inv * v3_dot(s, h);
    v3_cross(qv, s, e1);
    double v = inv * v3_dot(d, qv), t = inv * v3_dot(e2, qv);
    const double eps = 1e-9;
    return u > eps && v > eps && u + v < 1.0 - eps && t > eps && t < 1.0 - eps;
}

/* Body edges (each triangle's three) that cut a cloth triangle. */
static int cuts(const tmesh* body, const wc_model* m, const double* x) {
    int count = 0;
    for (int bt = 0; bt < body->nt; ++bt)
        for (int k = 0; k < 3; ++k) {
            const double* p = body->x + 3 * body->t[3 * bt + k];
            const double* q = body->x + 3 * body->t[3 * bt + (k + 1) % 3];
            for (int t = 0; t < m->n_tris; ++t) {
                const int* v = m->tris + 3 * t;
                count += segment_hits_triangle(p, q, x + 3 * v[0], x + 3 * v[1], x + 3 * v[2]);
            }
        }
    return count;
}

static void print_log(wc_log_level level, const char* message, void* user) {
    (void)user;
    if (level >= WC_LOG_WARN) printf("    [log] %s\n", message);
}

typedef struct trace_rec {
    int substep_iterates, rises, traced;
    double last, worst_rise;
} trace_rec;

/* Newton's trace: phi of the accepted iterates of one substep (iterate 0: its first) */
static void on_iterate(void* user, const wc_state* s, int it, double phi, const double* w) {
    (void)w;
    trace_rec* tr = user;
    if (s->pairs && s->pairs->list.n == 0) return;
    if (it > 0) {
        double rise = phi - tr->last;
        if (rise > 1e-12 * fabs(tr->last) + 1e-15) {
            ++tr->rises;
            if (rise > tr->worst_rise) tr->worst_rise = rise;
        }
        ++tr->traced;
    }
    tr->last = phi;
}

typedef struct drop_result {
    int cut_frames, failed, rollbacks, pairs, active, passes, overflow;
    double worst_pen, speed;
    int asleep;
} drop_result;

/* The coarse sheet dropped on body (and a floor) for `frames` frames; newton > 1: Newton
 * iterations with a line search, traced into tr. */
static double drop_tolerance = 0.0; /* the linear solves' tolerance; 0: the default (1e-4) */
static void drop(const char* name, const tmesh* body, int frames, int newton, trace_rec* tr, drop_result* r) {
    wc_model m;
    CHECK(ts_sheet(&m, 5, 1.0, 0.45, 0, 1.0)); /* particles 25 cm apart, at x, z = -0.5 ... 0.5 */
    wc_state* s = NULL;
    wc_diag d = {0};
    d.log = print_log;
    wc_sim_def sd = wc_default_sim_def();
    if (drop_tolerance > 0.0) sd.solver.tolerance = drop_tolerance;
    if (newton > 1) {
        sd.newton_iterations = newton;
        sd.line_search = 1;
    }
    CHECK_EQ_INT(wc_state_create(&s, &m, &sd, NULL, &d), WC_OK);
    if (tr) {
        s->newton_trace = on_iterate;
        s->newton_trace_user = tr;
    }
    wc_mesh_collider* mc = NULL;
    CHECK_EQ_INT(wc_mesh_collider_create(&mc, body->x, body->nv, body->t, body->nt, 0.005, 0.4, NULL, &d), WC_OK);
    CHECK_EQ_INT(wc_state_attach_mesh_colliders(s, &mc, 1, &d), WC_OK);
    wc_collider floor;
    memset(&floor, 0, sizeof floor);
    floor.type = WC_COLLIDER_PLANE;
    v3_set(floor.normal, 0, 1, 0);
    floor.thickness = 0.005;
    floor.friction = 0.5;
    CHECK_EQ_INT(wc_state_set_colliders(s, &floor, 1, &d), WC_OK);
    memset(r, 0, sizeof *r);
    for (int f = 0; f < frames; ++f) {
        wc_step_stats st;
        if (wc_step_frame(s, 1.0 / 30, &st, &d) != WC_OK) ++r->failed;
        r->rollbacks += st.rollbacks;
        r->pairs += st.mesh_pairs;
        r->active += st.mesh_pairs_active;
        r->passes += st.mesh_pair_passes;
        r->overflow += st.mesh_pair_overflow;
        if (cuts(body, &m, s->x) > 0) ++r->cut_frames;
        const wc_mesh_collider* cm = mc;
        double pen = wc_mesh_max_penetration(&cm, 1, s->x, m.n_particles);
        if (pen > r->worst_pen) r->worst_pen = pen;
    }
    r->speed = wc_state_max_speed(s);
    r->asleep = s->asleep;
    printf("  %-8s: %d of %d frames with a body edge through the cloth, %.3g m behind the surface at worst; "
           "%d pairs found, %d active, %d re-solves, %d overflow; %d rollbacks, %d failed frames; fastest %.3g m/s "
           "at the end%s\n",
           name, r->cut_frames, frames, r->worst_pen, r->pairs, r->active, r->passes, r->overflow, r->rollbacks,
           r->failed, r->speed, r->asleep ? " (asleep)" : "");
    wc_state_destroy(s);
    wc_mesh_collider_destroy(mc);
    wc_model_free(&m);
}

static void test_ridge_and_apex(void) {
    tmesh body;
    drop_result r;
    roof(&body, 0.1, 0.3, 0.25, 0.8); /* the ridge at x = 0.1, between the columns x = 0 and 0.25 */
    drop("ridge", &body, 60, 2, NULL, &r);
    CHECK_EQ_INT(r.failed, 0);
    CHECK_EQ_INT(r.cut_frames, 0);
    CHECK_EQ_INT(r.rollbacks, 0);
    CHECK_EQ_INT(r.overflow, 0);
    CHECK(r.worst_pen == 0.0);
    CHECK(r.active > 0);
    /* the same at tighter and looser solves: a cloth edge lying along the ridge's slope once had
       its edge-ridge pair dropped just past the ridge's normal cone (mesh_pairs.c), and the ridge
       cut through it (1e-5: 5 frames, 1e-3: 2) */
    static const double tolerances[] = {1e-5, 1e-3};
    for (int k = 0; k < 2; ++k) {
        drop_tolerance = tolerances[k];
        drop(k == 0 ? "ridge 1e-5" : "ridge 1e-3", &body, 60, 2, NULL, &r);
        CHECK_EQ_INT(r.failed, 0);
        CHECK_EQ_INT(r.cut_frames, 0);
        CHECK_EQ_INT(r.rollbacks, 0);
        CHECK(r.worst_pen == 0.0);
    }
    drop_tolerance = 0.0;
    pyramid(&body, 0.17, 0.05, 0.1, 0.3); /* the apex inside the cell x in [0, 0.25], z in [0, 0.25], off its diagonals */
    drop("apex", &body, 60, 2, NULL, &r);
    CHECK_EQ_INT(r.failed, 0);
    CHECK_EQ_INT(r.cut_frames, 0);
    CHECK_EQ_INT(r.rollbacks, 0);
    CHECK_EQ_INT(r.overflow, 0);
    CHECK(r.worst_pen == 0.0);
    CHECK(r.active > 0);
}

/* One pair's energy at x (n x 3) */
static double pair_energy(const wc_penalty_pairs* pl, int k, const double* x) {
    double f[9], J[81];
    return wc_penalty_pair_eval(pl, k, x, f, J);
}

/* The pair term against finite differences of its energy, and its assembly (A, b), for the first
 * pair of cnt particles found between a 2 x 2 cloth quad at height y and the body. */
static void check_pair(const char* name, const tmesh* body, double y, int cnt) {
    const double th = 0.005, h = 1.0 / 30;
    wc_diag d = {0};
    wc_mesh_collider* mc = NULL;
    CHECK_EQ_INT(wc_mesh_collider_create(&mc, body->x, body->nv, body->t, body->nt, th, 0.4, NULL, &d), WC_OK);
    wc_mesh_collider_substep(mc, 0.0, 1.0, h);
    wc_model m;
    CHECK(ts_sheet(&m, 2, 1.0, y, 0, 1.0));
    int n = m.n_particles;
    double x[12], v[12] = {0};
    memcpy(x, m.rest_pos, sizeof x);
    const wc_mesh_collider* cm = mc;
    wc_mesh_pairs* pp = wc_mesh_pairs_create(64, m.n_particles, &cm, 1, NULL);
    CHECK(pp != NULL);
    wc_mesh_pairs_find(pp, &cm, 1, &m, NULL, NULL, x, v, h, h);
    const wc_penalty_pairs* pl = &pp->list;
    int k = -1;
    for (int j = 0; j < pl->n && k < 0; ++j)
        if (pl->term[j].cnt == cnt) k = j;
    CHECK(k >= 0);
    if (k < 0) goto done;
    const wc_coupling_term* pr = &pl->term[k];
    /* finite differences of E (forces) and of the forces (Jacobian), central, step 1e-7 m */
    double f[9], J[81], worst_f = 0.0, worst_J = 0.0, fmx = 0.0, Jmax = 0.0;
    double e = wc_penalty_pair_eval(pl, k, x, f, J);
    const double eps = 1e-7;
    for (int b = 0; b < cnt; ++b)
        for (int c = 0; c < 3; ++c) {
            double xp[12], xm[12], fp[9], fm[9], Jd[81];
            memcpy(xp, x, sizeof x);
            memcpy(xm, x, sizeof x);
            xp[3 * pr->p[b] + c] += eps;
            xm[3 * pr->p[b] + c] -= eps;
            double fd = -(pair_energy(pl, k, xp) - pair_energy(pl, k, xm)) / (2 * eps);
            worst_f = fmax(worst_f, fabs(fd - f[3 * b + c]));
            fmx = fmax(fmx, fabs(f[3 * b + c]));
            wc_penalty_pair_eval(pl, k, xp, fp, Jd);
            wc_penalty_pair_eval(pl, k, xm, fm, Jd);
            for (int a = 0; a < cnt; ++a)
                for (int r = 0; r < 3; ++r) {
                    double jd = (fp[3 * a + r] - fm[3 * a + r]) / (2 * eps); /* dF_a,r / dx_b,c */
                    double ja = J[9 * (a * cnt + b) + 3 * r + c];
                    worst_J = fmax(worst_J, fabs(jd - ja));
                    Jmax = fmax(Jmax, fabs(ja));
                }
        }
    /* the assembly: this pair alone into zero A and b, linearised at x with v* = 0 */
    wc_penalty_pairs single;
    CHECK(wc_penalty_pairs_init(&single, 1, 1, NULL));
    CHECK_EQ_INT(wc_penalty_pairs_add(&single, &m.pattern, pr->cnt, pr->p, pr->w, pr->n, pl->off[k], pl->k[k]), 1);
    int nb = m.pattern.n_blocks;
    double* A = calloc(9 * (size_t)nb, sizeof(double));
    double bb[12] = {0}, vstar[12] = {0}, worst_A = 0.0, worst_b = 0.0;
    CHECK_EQ_INT(wc_penalty_pairs_assemble(&single, &m, x, vstar, NULL, h, A, bb, NULL), 1);
    for (int a = 0; a < cnt; ++a) {
        for (int r = 0; r < 3; ++r) worst_b = fmax(worst_b, fabs(bb[3 * pr->p[a] + r] - h * f[3 * a + r]));
        for (int c = 0; c < cnt; ++c)
            for (int q = 0; q < 9; ++q)
                worst_A = fmax(worst_A, fabs(A[9 * single.blk[WC_PENALTY_MAX * a + c] + q] +
                                             h * h * J[9 * (a * cnt + c) + q]));
    }
    printf("  %s pair (particles %d %d %d, gap %.3g m, E %.3g J): |f - (-dE/dx)_fd| %.3g of %.3g N, "
           "|J - (df/dx)_fd| %.3g of %.3g N/m; assembled A, b off by %.3g, %.3g\n",
           name, pr->p[0], pr->p[1], cnt == 3 ? pr->p[2] : -1, -sqrt(2 * e / pl->k[k]), e, worst_f, fmx, worst_J,
           Jmax, worst_A, worst_b);
    CHECK(e > 0.0);
    CHECK(worst_f <= 1e-6 * fmx);
    CHECK(worst_J <= 1e-6 * Jmax);
    CHECK(worst_A <= 1e-12 * h * h * Jmax);
    CHECK(worst_b <= 1e-12 * h * fmx);
    free(A);
    wc_penalty_pairs_free(&single, NULL);
done:
    (void)n;
    wc_mesh_pairs_destroy(pp, NULL);
    wc_mesh_collider_destroy(mc);
    wc_model_free(&m);
}

static void test_pair_term(void) {
    tmesh body;
    roof(&body, 0.1, 0.3, 0.25, 0.8);
    check_pair("edge-edge", &body, 0.253, 2); /* 3 mm above the ridge: inside the 5 mm thickness */
    pyramid(&body, 0.17, 0.05, 0.1, 0.3);
    check_pair("vertex-triangle", &body, 0.302, 3);
}

/* 1 when lists a and b hold the same pairs bit for bit, with the same counts */
static int same_list(const wc_penalty_pairs* a, const wc_penalty_pairs* b) {
    if (a->n != b->n || a->overflow != b->overflow || a->skipped != b->skipped) return 0;
    for (int j = 0; j < a->n; ++j)
        if (memcmp(&a->term[j], &b->term[j], sizeof a->term[j]) || a->off[j] != b->off[j] || a->k[j] != b->k[j] ||
            a->active[j] != b->active[j] || memcmp(a->blk + 16 * j, b->blk + 16 * j, 16 * sizeof(int)))
            return 0;
    return 1;
}

/* The number of pairs of list a with the same particles, weights and normal as an earlier one */
static int repeated_pairs(const wc_penalty_pairs* a) {
    int rep = 0;
    for (int j = 0; j < a->n; ++j)
        for (int i = 0; i < j; ++i)
            if (!memcmp(&a->term[i], &a->term[j], sizeof a->term[j])) {
                ++rep;
                break;
            }
    return rep;
}

/* The detection on 2 and 3 threads (each thread's range staged, then appended in order) gives the
 * serial list: a 21 x 21 sheet falling onto a roof ridge and a pyramid's apex, with stages that
 * fill up (the rest of a range found serially) and a list that overflows. No pair is found
 * twice, and no thread's mark of a body feature seen is left set after a detection. */
static void test_pairs_threads(void) {
    const double th = 0.005, h = 1.0 / 30;
    wc_diag d = {0};
    tmesh roof_m, pyr_m;
    roof(&roof_m, 0.125, 0.3, 0.25, 0.8);
    pyramid(&pyr_m, 0.62, 0.57, 0.1, 0.254);
    wc_mesh_collider* mc[2] = {NULL, NULL};
    CHECK_EQ_INT(wc_mesh_collider_create(&mc[0], roof_m.x, roof_m.nv, roof_m.t, roof_m.nt, th, 0.4, NULL, &d), WC_OK);
    CHECK_EQ_INT(wc_mesh_collider_create(&mc[1], pyr_m.x, pyr_m.nv, pyr_m.t, pyr_m.nt, th, 0.4, NULL, &d), WC_OK);
    for (int k = 0; k < 2; ++k) wc_mesh_collider_substep(mc[k], 0.0, 1.0, h);
    const wc_mesh_collider* cm[2] = {mc[0], mc[1]};
    wc_model m;
    CHECK(ts_sheet(&m, 21, 1.0, 0.256, 0, 1.0));
    int n = m.n_particles, nf = m.we.n_edges + m.n_tris;
    double* x = malloc(3 * (size_t)n * sizeof(double));
    double* v = calloc(3 * (size_t)n, sizeof(double));
    memcpy(x, m.rest_pos, 3 * (size_t)n * sizeof(double));
    for (int i = 0; i < n; ++i) v[3 * i + 1] = -0.2 - 0.01 * (i % 7);
    const int caps[2] = {4 * nf, 9}; /* room for all; a list that overflows */
    int found = 0, marks_left = 0;
    for (int ci = 0; ci < 2; ++ci) {
        wc_mesh_pairs* serial = wc_mesh_pairs_create(caps[ci], n, cm, 2, NULL);
        CHECK(serial && wc_mesh_pairs_keep_candidates(serial, nf, NULL));
        wc_mesh_pairs_find(serial, cm, 2, &m, NULL, NULL, x, v, h, h);
        for (int i = 0; i < serial->seen_stride; ++i) marks_left += serial->seen[i] != 0;
        if (ci == 0) {
            found = serial->list.n;
            CHECK_EQ_INT(repeated_pairs(&serial->list), 0);
        } else {
            CHECK(serial->list.overflow > 0);
        }
        const int threads[3] = {2, 3, 2}, stage_caps[3] = {0, 1, 5};
        for (int r = 0; r < 3; ++r) {
            wc_mesh_pairs* par = wc_mesh_pairs_create(caps[ci], n, cm, 2, NULL);
            CHECK(par && wc_mesh_pairs_keep_candidates(par, nf, NULL));
            CHECK(wc_mesh_pairs_set_threads(par, threads[r], stage_caps[r], NULL));
            for (int rep = 0; rep < 2; ++rep) { /* the second time through the kept candidates */
                wc_mesh_pairs_find(par, cm, 2, &m, NULL, NULL, x, v, h, h);
                CHECK(same_list(&serial->list, &par->list));
                for (size_t i = 0; i < (size_t)threads[r] * (size_t)par->seen_stride; ++i)
                    marks_left += par->seen[i] != 0;
            }
            wc_mesh_pairs_destroy(par, NULL);
        }
        wc_mesh_pairs_destroy(serial, NULL);
    }
    printf("  %d pairs (%d features) found alike on 1, 2 and 3 threads, with stages of room 1, 5 and the "
           "default, and with a list of room 9; none twice, %d marks left\n", found, nf, marks_left);
    CHECK(found > 20);
    CHECK_EQ_INT(marks_left, 0);
    free(x);
    free(v);
    for (int k = 0; k < 2; ++k) wc_mesh_collider_destroy(mc[k]);
    wc_model_free(&m);
}

/* The detection's cull of body features beyond the largest contact distance (mesh_pairs.c's
 * reach_box) against the unculled detection (exhaustive colliders): the same list, bit for bit.
 * A flat 21 x 21 sheet over a roof ridge and a pyramid's apex that rise at 0 to 1 m/s, its
 * particles falling at 0 to 3 m/s, at heights just inside and just outside the contact distance
 * d_c = 2 thickness + 1.5 h (fall + rise) (pairs found at the edge of the reach); then the bodies
 * turning and shifting under a crumpled sheet moving every which way. */
static void test_pairs_culled(void) {
    const double th = 0.005, h = 1.0 / 60;
    wc_diag d = {0};
    tmesh body[2];
    roof(&body[0], 0.21, 0.15, 0.25, 0.8);
    pyramid(&body[1], -0.235, 0.28, 0.1, 0.254);
    const double top[2] = {0.25, 0.254};
    wc_mesh_collider* mc[2] = {NULL, NULL};
    for (int k = 0; k < 2; ++k)
        CHECK_EQ_INT(wc_mesh_collider_create(&mc[k], body[k].x, body[k].nv, body[k].t, body[k].nt, th, 0.4, NULL, &d),
                     WC_OK);
    const wc_mesh_collider* cm[2] = {mc[0], mc[1]};
    wc_model m;
    CHECK(ts_sheet(&m, 21, 1.0, 0.0, 0, 1.0));
    int n = m.n_particles, nf = m.we.n_edges + m.n_tris;
    double* x = malloc(3 * (size_t)n * sizeof(double));
    double* v = malloc(3 * (size_t)n * sizeof(double));
    double tgt[3 * 16];
    wc_mesh_pairs* culled = wc_mesh_pairs_create(8 * nf, n, cm, 2, NULL);
    wc_mesh_pairs* full = wc_mesh_pairs_create(8 * nf, n, cm, 2, NULL);
    CHECK(culled && full && wc_mesh_pairs_keep_candidates(culled, nf, NULL));
    unsigned long long rng = 0x9e3779b97f4a7c15ull;
    const double falls[5] = {0, 1, 3, 0, 2}, rises[5] = {0, 0, 0, 0.5, 1}, at[5] = {0.5, 0.99, 0.9999, 1.001, 1.2};
    int trials = 0, same = 0, found = 0, edge_found = 0, tilt_found = 0;
    for (int trial = 0; trial < 2 * 5 * 5 + 30 + 10; ++trial) {
        /* the last 10: the bodies rise tilted (the roof's ridge from still at one end to 1 m/s at
           the other, the pyramid's apex at 1 m/s over a still base), the sheet still at 0.3 to 0.99
           of the d_c of 1 m/s: body features moving at different speeds */
        int tilt = trial >= 80, flat = trial < 50 || tilt, near = trial % 2, speed = trial / 2 % 5;
        double fall = flat && !tilt ? falls[speed] : 0.0, rise = tilt ? 1.0 : flat ? rises[speed] : 0.0;
        const double tilt_at[5] = {0.3, 0.5, 0.7, 0.9, 0.99};
        double dc = 2.0 * th + 1.5 * h * (fall + rise);
        double y = top[near] + (tilt ? tilt_at[trial / 2 % 5] : at[trial / 10 % 5]) * dc;
        double a = flat ? 0.0 : 0.02 * (trial % 5), ca = cos(a), sa = sin(a);
        for (int k = 0; k < 2; ++k) { /* rise, or turn about y and shift */
            for (int i = 0; i < body[k].nv; ++i) {
                const double* p = body[k].x + 3 * i;
                double w = tilt ? (k == 0 ? (p[2] + 0.8) / 1.6 : p[1] / top[1]) : 1.0;
                v3_set(tgt + 3 * i, ca * p[0] + sa * p[2], p[1] + w * rise * h + (flat ? 0.0 : 0.001 * (trial % 3)),
                       -sa * p[0] + ca * p[2] + (flat ? 0.0 : 0.002));
            }
            CHECK_EQ_INT(wc_mesh_collider_set_all(mc[k], body[k].x, &d), WC_OK);
            CHECK_EQ_INT(wc_mesh_collider_set_target(mc[k], tgt, &d), WC_OK);
            wc_mesh_collider_substep(mc[k], 0.0, 1.0, h);
        }
        for (int i = 0; i < n; ++i) {
            double r[4];
            for (int k = 0; k < 4; ++k) {
                rng ^= rng << 13, rng ^= rng >> 7, rng ^= rng << 17;
                r[k] = (double)(rng >> 11) / 9007199254740992.0 * 2.0 - 1.0;
            }
            if (flat) {
                v3_set(x + 3 * i, m.rest_pos[3 * i], y, m.rest_pos[3 * i + 2]);
                v3_set(v + 3 * i, 0.0, -fall, 0.0);
            } else {
                double yi = 0.252 + 0.0015 * (trial - 50) + 0.003 * r[3];
                v3_set(x + 3 * i, m.rest_pos[3 * i], yi, m.rest_pos[3 * i + 2]);
                v3_set(v + 3 * i, r[0], r[1], r[2]);
                v3_scale(v + 3 * i, v + 3 * i, 0.1 * (trial - 50));
            }
        }
        for (int k = 0; k < 2; ++k) mc[k]->exhaustive = 1;
        wc_mesh_pairs_find(full, cm, 2, &m, NULL, NULL, x, v, h, h);
        for (int k = 0; k < 2; ++k) mc[k]->exhaustive = 0;
        wc_mesh_pairs_find(culled, cm, 2, &m, NULL, NULL, x, v, h, h);
        ++trials;
        same += same_list(&full->list, &culled->list);
        found += full->list.n;
        if (flat && !tilt && at[trial / 10 % 5] > 0.9 && at[trial / 10 % 5] < 1.0) edge_found += full->list.n;
        if (tilt) tilt_found += full->list.n;
    }
    printf("  %d of %d detections the same culled as unculled: %d pairs, %d of them at 0.99 and 0.9999 d_c, %d over "
           "tilted bodies\n", same, trials, found, edge_found, tilt_found);
    CHECK_EQ_INT(same, trials);
    CHECK(edge_found > 20 && found > edge_found);
    CHECK(tilt_found > 20);
    wc_mesh_pairs_destroy(culled, NULL);
    wc_mesh_pairs_destroy(full, NULL);
    free(x);
    free(v);
    for (int k = 0; k < 2; ++k) wc_mesh_collider_destroy(mc[k]);
    wc_model_free(&m);
}

/* Newton with a line search, pairs active: Phi never rises from one accepted iterate to the next */
static void test_newton_descends(void) {
    tmesh body;
    trace_rec tr;
    drop_result r;
    memset(&tr, 0, sizeof tr);
    roof(&body, 0.1, 0.3, 0.25, 0.8);
    drop("newton 4", &body, 30, 4, &tr, &r);
    printf("  %d iterates traced with pairs, %d rises of Phi (worst %.3g J)\n", tr.traced, tr.rises, tr.worst_rise);
    CHECK(tr.traced > 0);
    CHECK_EQ_INT(tr.rises, 0);
    CHECK(r.active > 0);
    CHECK_EQ_INT(r.failed, 0);
}

int main(void) {
    RUN_TEST(test_pair_term);
    RUN_TEST(test_pairs_threads);
    RUN_TEST(test_pairs_culled);
    RUN_TEST(test_newton_descends);
    RUN_TEST(test_ridge_and_apex);
    return TEST_SUMMARY();
}
