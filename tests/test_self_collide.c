/* Self-collision (core/self_collide.h): the edge-triangle crossing counter against brute force,
 * the impact zones' rigid motion against momentum conservation, the relaxation of the springs
 * they stretch, and whole simulations (a sheet
 * folded onto itself, a sheet dropped in a heap on the floor, two separate layers) checked for
 * zero crossings at the end of EVERY frame, with the same scenes without self-collision shown to
 * cross (so the check can fail). Prints the cost (ms per frame with and without). */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "check.h"
#include "heap_strip.h"
#include "overlap_panels.h"
#include "clock.h"
#include "self_collide.h"
#include "step.h"
#include "test_support.h"
#include "test_rng.h"
#include "two_layers.h"
#include "union_find.h"
#include "vec3.h"


/* A strip folded in a Z: bottom layer u in [0, 0.5] at y = 0, a riser up to y = 0.1 at x = 0.5,
 * a top layer back over the bottom one at y = 0.1. nu x nz vertices (1.1 m along u, 0.4 m along z). */
static int folded_strip(wc_model* m, int nu, int nz) {
    wc_source_mesh src;
    ts_quad_grid(&src, nu, nz, 1.1, 0.4, 0);
    for (int v = 0; v < src.n_verts; ++v) {
        double* p = src.pos + 3 * v;
        double u = p[0], z = p[1];
        if (u <= 0.5 + 1e-9) v3_set(p, u, 0.0, z);
        else if (u <= 0.6 + 1e-9) v3_set(p, 0.5, u - 0.5, z);
        else v3_set(p, 0.5 - (u - 0.6), 0.1, z);
    }
    wc_model_def def = wc_default_model_def();
    wc_diag d = {0};
    wc_status st = wc_model_build(m, &src, &def, NULL, &d);
    if (st != WC_OK) fprintf(stderr, "folded_strip: %s\n", d.message);
    wc_source_mesh_free(&src);
    return st == WC_OK;
}

static int crossings(const wc_model* m, const double* x) {
    int c = -1;
    wc_diag d = {0};
    CHECK(wc_self_intersections(m, x, NULL, &c, &d) == WC_OK);
    return c;
}

/* ---- the counter ---------------------------------------------------------------------------- */

/* overlap_panels.h's panels: built apart, the second's edges pass through the first's triangles
 * along its x = 0.1 edge and the first's edges through the second's; sewn at 5 mm, every such pair
 * has a particle sewn to the other element, which the rules exclude (sewn panels overlap along
 * their seam by construction). */
static void test_sewn_overlap_not_counted(void) {
    for (int sewn = 0; sewn < 2; ++sewn) {
        wc_diag d = {0};
        wc_model m;
        overlap_panels(&m, sewn);
        int c = crossings(&m, m.rest_pos);
        printf("  overlapping panels %s: %d seams, %d crossing pairs (brute force %d)\n", sewn ? "sewn" : "apart",
               m.n_seams, c, wc_self_intersections_brute(&m, m.rest_pos));
        CHECK_EQ_INT(c, wc_self_intersections_brute(&m, m.rest_pos));
        if (sewn) {
            CHECK(m.n_seams >= 5);
            CHECK_EQ_INT(c, 0);
        } else {
            CHECK(c >= 4);
        }
        /* a state created on it: the rest shape's crossings are the tangled pairs left alone */
        wc_self* sc = NULL;
        CHECK(wc_self_create(&sc, &m, 0.003, NULL, &d) == WC_OK);
        if (sc) CHECK_EQ_INT(sc->tangled_pairs, c);
        wc_self_destroy(sc);
        wc_model_free(&m);
    }
}

static void test_counter_vs_brute(void) {
    int total = 0;
    for (int trial = 0; trial < 12; ++trial) {
        wc_model m;
        int n = 4 + trial;
        CHECK(ts_sheet(&m, n, 1.0, 0.0, 0, 1.0));
        double* x = malloc(3 * (size_t)m.n_particles * sizeof(double));
        double noise = 0.05 + 0.05 * trial; /* from a few crossings to many */
        for (int i = 0; i < m.n_particles; ++i)
            for (int k = 0; k < 3; ++k) x[3 * i + k] = m.rest_pos[3 * i + k] + noise * (2 * urand() - 1);
        int bvh = crossings(&m, x), brute = wc_self_intersections_brute(&m, x);
        CHECK_EQ_INT(bvh, brute);
        total += brute;
        CHECK_EQ_INT(crossings(&m, m.rest_pos), 0); /* a flat sheet crosses nothing */
        free(x);
        wc_model_free(&m);
    }
    CHECK(total > 0);
    /* a hand-made crossing: one triangle of a 2-cell sheet folded through another */
    wc_model m;
    CHECK(ts_sheet(&m, 5, 1.0, 0.0, 0, 1.0));
    double* x = malloc(3 * (size_t)m.n_particles * sizeof(double));
    memcpy(x, m.rest_pos, 3 * (size_t)m.n_particles * sizeof(double));
    /* the far edge (3,4)-(4,4) of a 5 x 5 sheet stood up through a near cell */
    v3_set(x + 3 * ts_sheet_particle(&m, 5, 4, 4), -0.3, -0.2, -0.4);
    v3_set(x + 3 * ts_sheet_particle(&m, 5, 3, 4), -0.3, 0.2, -0.4);
    CHECK(crossings(&m, x) > 0);
    CHECK_EQ_INT(crossings(&m, x), wc_self_intersections_brute(&m, x));
    free(x);
    wc_model_free(&m);
}

/* ---- impact zones: rigid motion keeps momentum and distances --------------------------------- */

/* Two zones (particles 0..19 and 20..34; 35..39 outside) of random particles displaced by up to
 * scale: linear momentum kept exactly, distances inside a zone exactly, particles outside
 * untouched. Returns the largest error of a zone's angular momentum relative to its size. */
static double rigidify_case(double scale) {
    enum { N = 40 };
    double x0[3 * N], x[3 * N], xin[3 * N], mass[N], im[N], acc[WC_SELF_ZONE_STRIDE * N];
    int parent[N];
    unsigned char in[N];
    rng_state = 0x9E3779B97F4A7C15ull;
    double u[3 * N];
    for (int i = 0; i < N; ++i) {
        for (int k = 0; k < 3; ++k) {
            x0[3 * i + k] = 2 * urand() - 1;
            u[3 * i + k] = 2 * urand() - 1;
            x[3 * i + k] = x0[3 * i + k] + scale * u[3 * i + k];
        }
        mass[i] = 0.1 + urand();
        im[i] = 1.0 / mass[i];
        parent[i] = i;
        in[i] = i < 35;
    }
    for (int i = 1; i < 20; ++i) wc_uf_union(parent, 0, i);
    for (int i = 21; i < 35; ++i) wc_uf_union(parent, 20, i);
    memcpy(xin, x, sizeof x);
    wc_self_rigidify(N, x0, x, mass, im, parent, in, acc);
    int lo[2] = {0, 20}, hi[2] = {20, 35};
    double worst = 0;
    for (int z = 0; z < 2; ++z) {
        double p0[3] = {0}, p1[3] = {0}, c[3] = {0}, M = 0;
        for (int i = lo[z]; i < hi[z]; ++i) {
            M += mass[i];
            v3_axpy(c, mass[i], x0 + 3 * i);
        }
        v3_scale(c, c, 1.0 / M);
        double L0[3] = {0}, L1[3] = {0};
        for (int i = lo[z]; i < hi[z]; ++i) {
            double d0[3], d1[3], r[3], t[3];
            v3_sub(d0, xin + 3 * i, x0 + 3 * i);
            v3_sub(d1, x + 3 * i, x0 + 3 * i);
            v3_axpy(p0, mass[i], d0);
            v3_axpy(p1, mass[i], d1);
            v3_sub(r, x0 + 3 * i, c);
            v3_cross(t, r, d0);
            v3_axpy(L0, mass[i], t);
            v3_cross(t, r, d1);
            v3_axpy(L1, mass[i], t);
        }
        for (int k = 0; k < 3; ++k) CHECK_NEAR(p1[k], p0[k], 1e-12);
        double dL[3];
        v3_sub(dL, L1, L0);
        if (v3_norm(dL) / v3_norm(L0) > worst) worst = v3_norm(dL) / v3_norm(L0);
        /* rigid: every distance inside the zone is its start distance */
        for (int i = lo[z]; i < hi[z]; ++i)
            for (int j = i + 1; j < hi[z]; ++j) {
                double r0[3], r1[3];
                v3_sub(r0, x0 + 3 * i, x0 + 3 * j);
                v3_sub(r1, x + 3 * i, x + 3 * j);
                CHECK_NEAR(v3_norm(r1), v3_norm(r0), 1e-12);
            }
    }
    for (int i = 35; i < N; ++i) CHECK(v3_equal(x + 3 * i, xin + 3 * i)); /* outside the zones: untouched */
    return worst;
}

static void test_rigidify_momentum(void) {
    /* the rotation is exact, so the angular momentum over the start positions is kept to first
       order in the angle: its error is second order, so relative to the momentum it halves with
       the displacements */
    double e1 = rigidify_case(0.1), e2 = rigidify_case(0.05), e3 = rigidify_case(1e-4);
    printf("rigid zones: angular momentum's relative error %.3g, %.3g, %.3g at displacements 0.1, 0.05, 1e-4\n", e1,
           e2, e3);
    CHECK(e1 < 0.05);
    CHECK(e2 < 0.6 * e1 && e2 > 0.4 * e1);
    CHECK(e3 < 1e-5);
}

/* ---- the springs an impact zone stretches are relaxed around it ---------------------------------- */

static double strain_at(const wc_spring* sp, const double* x) {
    double L[3];
    v3_sub(L, x + 3 * sp->a, x + 3 * sp->b);
    return (v3_norm(L) - sp->rest) / sp->rest;
}

static void test_zone_relax(void) {
    enum { N = 9 };
    wc_model m;
    CHECK(ts_sheet(&m, N, 0.8, 0.0, 0, 1.0)); /* horizontal, 0.1 m cells */
    int n = m.n_particles;
    double *x0 = calloc(3 * (size_t)n, sizeof(double)), *x_old = calloc(3 * (size_t)n, sizeof(double)),
           *x = calloc(3 * (size_t)n, sizeof(double)), *xz = calloc(3 * (size_t)n, sizeof(double)),
           *acc = calloc(WC_SELF_ZONE_STRIDE * (size_t)n, sizeof(double)), *im = calloc((size_t)n, sizeof(double));
    int* parent = calloc((size_t)n, sizeof(int));
    unsigned char* in = calloc((size_t)n, 1);
    for (int i = 0; i < n; ++i) im[i] = m.inv_mass[i];
    int c = ts_sheet_particle(&m, N, 4, 4), c1 = ts_sheet_particle(&m, N, 5, 4);
    int corner = ts_sheet_particle(&m, N, 0, 0);
    im[corner] = 0.0; /* pinned: never moved */
    for (int drop = 0; drop < 2; ++drop) {
        /* the solve moved the sheet down by 0.02 or 0.2 m (the pinned corner stayed); impulses then
           held c and its neighbour c1 where they started, and they became one zone */
        double dy = drop ? -0.2 : -0.02;
        memcpy(x0, m.rest_pos, 3 * (size_t)n * sizeof(double));
        for (int i = 0; i < n; ++i) {
            v3_copy(x_old + 3 * i, x0 + 3 * i);
            if (i != corner) x_old[3 * i + 1] += dy;
            parent[i] = i;
            in[i] = 0;
        }
        memcpy(x, x_old, 3 * (size_t)n * sizeof(double));
        v3_copy(x + 3 * c, x0 + 3 * c);
        v3_copy(x + 3 * c1, x0 + 3 * c1);
        in[c] = in[c1] = 1;
        wc_uf_union(parent, c, c1);
        wc_self_rigidify(n, x0, x, m.mass, im, parent, in, acc);
        memcpy(xz, x, 3 * (size_t)n * sizeof(double));
        int moved = wc_self_relax_zones(&m, x_old, x, in, im, WC_SELF_ZONE_STRAIN, WC_SELF_RELAX_PASSES, NULL);
        double worst_excess = -1, worst_before = -1;
        for (int s = m.spring_type_start[WC_SPRING_STRETCH]; s < m.spring_type_start[WC_SPRING_STRETCH + 1]; ++s) {
            const wc_spring* sp = &m.springs[s];
            if (in[sp->a] && in[sp->b]) {
                CHECK_NEAR(strain_at(sp, x), strain_at(sp, x0), 1e-12); /* the zone is rigid */
                continue;
            }
            double allowed = fmax(strain_at(sp, x_old), WC_SELF_ZONE_STRAIN);
            worst_before = fmax(worst_before, strain_at(sp, xz) - allowed);
            worst_excess = fmax(worst_excess, strain_at(sp, x) - allowed);
        }
        printf("zone relax, drop %g m: %d corrections; worst strain over the allowed %.3g after the rigid motion, "
               "%.3g after the relaxation\n", -dy, moved, worst_before, worst_excess);
        if (drop) { /* the zone held 0.2 m above its neighbours: its springs stretched by ~120 % */
            CHECK(moved > 0 && worst_before > 1.0);
            CHECK(worst_excess < 0.1 * worst_before); /* 8 passes: 20x smaller here */
        } else { /* ~2 %: below the floor, nothing moved */
            CHECK_EQ_INT(moved, 0);
            CHECK(worst_excess <= 0.0);
        }
        for (int i = 0; i < n; ++i)
            if (in[i] || i == corner) CHECK(v3_equal(x + 3 * i, xz + 3 * i)); /* zones and pins are not moved */
    }
    free(x0);
    free(x_old);
    free(x);
    free(xz);
    free(acc);
    free(im);
    free(parent);
    free(in);
    wc_model_free(&m);
}

/* ---- whole simulations (impact zones driven below: one impulse pass only) ----------------------------------------------------------------------- */

typedef struct run_result {
    int max_crossings;      /* over every frame's end */
    int frames_crossing;    /* frames ending with a crossing */
    int failed;             /* frames that returned an error */
    int unresolved;
    double ms_per_frame;
    int impacts, zones, rollbacks;
    int relaxed;            /* stretch-spring corrections around the zones */
    double ms_self;         /* per frame, the self-collision stage alone */
    double x_hash;          /* sum of (k + 1) x[k] over the final positions: equal runs, equal sums */
    double max_strain;      /* largest stretch strain at the end of a frame */
} run_result;

static int verbose = 0;
static void log_fn(wc_log_level level, const char* msg, void* user) {
    (void)user;
    (void)level;
    if (verbose) fprintf(stderr, "log: %s\n", msg);
}

static int impulse_passes = WC_SELF_PASSES; /* the state's self-collision passes (simulate) */
static int detect_all = 0;                   /* the state's self-collision detect_all (simulate) */
static double zone_strain = WC_SELF_ZONE_STRAIN; /* the state's self-collision zone_strain (simulate) */

static run_result simulate(const wc_model* m, wc_sim_def def, const wc_pin* pins, int np, const wc_collider* c, int nc,
                           const double* x_start, int frames, int check_every_frame) {
    run_result r = {0};
    wc_state* s = NULL;
    wc_diag d = {0};
    d.log = log_fn;
    CHECK(wc_state_create(&s, m, &def, NULL, &d) == WC_OK);
    if (!s) {
        fprintf(stderr, "state: %s\n", d.message);
        r.failed = frames;
        return r;
    }
    if (s->self) {
        s->self->passes = impulse_passes;
        s->self->detect_all = detect_all;
        s->self->zone_strain = zone_strain;
    }
    if (x_start) CHECK(wc_state_set_positions(s, x_start, NULL, &d) == WC_OK);
    if (np) CHECK(wc_state_set_pins(s, pins, np, &d) == WC_OK);
    if (nc) CHECK(wc_state_set_colliders(s, c, nc, &d) == WC_OK);
    double ms = 0;
    for (int f = 0; f < frames; ++f) {
        wc_step_stats st;
        double t0 = wc_now_ms();
        if (wc_step_frame(s, 1.0 / 60, &st, &d) != WC_OK) ++r.failed;
        ms += wc_now_ms() - t0;
        r.unresolved += st.self_unresolved;
        r.impacts += st.self_impacts;
        r.zones += st.self_zones;
        r.relaxed += st.self_zone_relaxed;
        if (st.max_strain > r.max_strain) r.max_strain = st.max_strain;
        r.rollbacks += st.rollbacks;
        r.ms_self += st.ms.self_collide / frames;
        if (check_every_frame || f == frames - 1) {
            int k = crossings(m, s->x);
            if (k > r.max_crossings) r.max_crossings = k;
            r.frames_crossing += k > 0;
        }
    }
    r.ms_per_frame = ms / frames;
    for (int k = 0; k < 3 * m->n_particles; ++k) r.x_hash += (k + 1) * s->x[k];
    wc_state_destroy(s);
    return r;
}

/* self: 0 off, 1 on (the stage and the pairs in the solve, the default), 2 the stage alone */
static wc_sim_def sim_def(int self) {
    wc_sim_def def = wc_default_sim_def();
    def.substeps = 2;
    def.self_collision = self != 0;
    def.self_in_solve = self == 1;
    def.sleep_speed = 0;
    return def;
}

static void test_fold(void) {
    wc_model m;
    int nu = 23, nz = 9;
    CHECK(folded_strip(&m, nu, nz));
    /* pin the bottom layer: every particle at y = 0 with x < 0.5 */
    wc_pin* pins = calloc((size_t)m.n_particles, sizeof *pins);
    int np = 0;
    for (int i = 0; i < m.n_particles; ++i)
        if (m.rest_pos[3 * i + 1] == 0.0 && m.rest_pos[3 * i] < 0.49) {
            pins[np].particle = i;
            v3_copy(pins[np].target, m.rest_pos + 3 * i);
            ++np;
        }
    CHECK(np > 0);
    run_result on = simulate(&m, sim_def(1), pins, np, NULL, 0, NULL, 60, 1);
    run_result stage = simulate(&m, sim_def(2), pins, np, NULL, 0, NULL, 60, 1);
    run_result off = simulate(&m, sim_def(0), pins, np, NULL, 0, NULL, 60, 1);
    printf("fold (%d particles): on: max crossings %d, frames crossing %d, impacts %d, zones %d, rollbacks %d, %.2f ms/frame (stage %.2f); "
           "stage alone: max crossings %d, impacts %d, zones %d, rollbacks %d, %.2f ms/frame; "
           "off: max crossings %d in %d frames, %.2f ms/frame\n",
           m.n_particles, on.max_crossings, on.frames_crossing, on.impacts, on.zones, on.rollbacks, on.ms_per_frame, on.ms_self,
           stage.max_crossings, stage.impacts, stage.zones, stage.rollbacks, stage.ms_per_frame,
           off.max_crossings, off.frames_crossing, off.ms_per_frame);
    for (int k = 0; k < 2; ++k) {
        const run_result* r = k ? &stage : &on;
        CHECK_EQ_INT(r->failed, 0);
        CHECK_EQ_INT(r->frames_crossing, 0);
        CHECK_EQ_INT(r->unresolved, 0);
    }
    CHECK(off.frames_crossing > 0); /* the scene does cross without self-collision */
    free(pins);
    wc_model_free(&m);
}

/* The heap (heap_strip.h): it buckles as it lands and piles up on itself. */
static void test_heap(void) {
    wc_model m;
    wc_collider floor;
    heap_strip(&m, &floor);
    double* x = NULL;
    run_result on = simulate(&m, sim_def(1), NULL, 0, &floor, 1, x, 75, 1);
    run_result stage = simulate(&m, sim_def(2), NULL, 0, &floor, 1, x, 75, 1);
    run_result off = simulate(&m, sim_def(0), NULL, 0, &floor, 1, x, 75, 1);
    printf("heap (%d particles): on: max crossings %d, frames crossing %d, impacts %d, zones %d, rollbacks %d, %.2f ms/frame (stage %.2f); "
           "stage alone: max crossings %d, impacts %d, zones %d, rollbacks %d, %.2f ms/frame; "
           "off: max crossings %d in %d frames, %.2f ms/frame\n",
           m.n_particles, on.max_crossings, on.frames_crossing, on.impacts, on.zones, on.rollbacks, on.ms_per_frame, on.ms_self,
           stage.max_crossings, stage.impacts, stage.zones, stage.rollbacks, stage.ms_per_frame,
           off.max_crossings, off.frames_crossing, off.ms_per_frame);
    for (int k = 0; k < 2; ++k) {
        const run_result* r = k ? &stage : &on;
        CHECK_EQ_INT(r->failed, 0);
        CHECK_EQ_INT(r->frames_crossing, 0);
        CHECK_EQ_INT(r->unresolved, 0);
    }
    CHECK(off.frames_crossing > 0);
    /* every pass after the first checks only the pairs with a dirty particle: bit for bit the
       result of checking every pair, impulse passes and zones included */
    detect_all = 1;
    run_result all = simulate(&m, sim_def(2), NULL, 0, &floor, 1, x, 75, 1);
    detect_all = 0;
    printf("heap, stage alone, every pair at every pass: %.2f ms/frame (stage %.2f) against %.2f (stage %.2f)\n",
           all.ms_per_frame, all.ms_self, stage.ms_per_frame, stage.ms_self);
    CHECK(all.x_hash == stage.x_hash);
    CHECK_EQ_INT(all.impacts, stage.impacts);
    wc_model_free(&m);
}

/* The fold and the heap with the stage alone (no pairs in the solve) and without CCD impulses (proximity impulses only): every collision goes to
 * the impact zones, which must then keep every frame free of crossings on their own; on the heap,
 * the zones' later detection passes (dirty pairs only) against every pair, and the relaxation of
 * the springs around the zones against none (the strain it removes). */
static void test_zones_alone(void) {
    impulse_passes = 0;
    wc_model m;
    CHECK(folded_strip(&m, 23, 9));
    wc_pin* pins = calloc((size_t)m.n_particles, sizeof *pins);
    int np = 0;
    for (int i = 0; i < m.n_particles; ++i)
        if (m.rest_pos[3 * i + 1] == 0.0 && m.rest_pos[3 * i] < 0.49) {
            pins[np].particle = i;
            v3_copy(pins[np].target, m.rest_pos + 3 * i);
            ++np;
        }
    run_result r = simulate(&m, sim_def(2), pins, np, NULL, 0, NULL, 60, 1);
    printf("fold, zones alone: max crossings %d, frames crossing %d, zones %d (%d spring corrections around them), "
           "unresolved %d, %.2f ms/frame (stage %.2f)\n", r.max_crossings, r.frames_crossing, r.zones, r.relaxed,
           r.unresolved, r.ms_per_frame, r.ms_self);
    CHECK_EQ_INT(r.failed, 0);
    CHECK_EQ_INT(r.frames_crossing, 0);
    CHECK_EQ_INT(r.unresolved, 0);
    CHECK(r.zones > 0);
    free(pins);
    wc_model_free(&m);
    wc_collider floor;
    heap_strip(&m, &floor);
    r = simulate(&m, sim_def(2), NULL, 0, &floor, 1, NULL, 75, 1);
    printf("heap, zones alone: max crossings %d, frames crossing %d, zones %d (%d spring corrections around them), "
           "unresolved %d, %.2f ms/frame (stage %.2f)\n", r.max_crossings, r.frames_crossing, r.zones, r.relaxed,
           r.unresolved, r.ms_per_frame, r.ms_self);
    /* the zone loop's later detection passes check only the pairs with a particle moved since its
       first: the same result, bit for bit, as checking every pair */
    detect_all = 1;
    run_result all = simulate(&m, sim_def(2), NULL, 0, &floor, 1, NULL, 75, 1);
    detect_all = 0;
    printf("heap, zones alone, every pair at every detection pass: zones %d, %.2f ms/frame (stage %.2f)\n", all.zones,
           all.ms_per_frame, all.ms_self);
    CHECK(all.x_hash == r.x_hash);
    CHECK_EQ_INT(all.zones, r.zones);
    CHECK_EQ_INT(all.relaxed, r.relaxed);
    /* without the relaxation the zones' rigid motions stretch the springs around them */
    zone_strain = INFINITY;
    run_result rigid = simulate(&m, sim_def(2), NULL, 0, &floor, 1, NULL, 75, 1);
    zone_strain = WC_SELF_ZONE_STRAIN;
    printf("heap, zones alone: max strain %.3f with the relaxation, %.3f without (zones %d, crossings %d)\n",
           r.max_strain, rigid.max_strain, rigid.zones, rigid.max_crossings);
    CHECK(r.max_strain < 1.5 * WC_SELF_ZONE_STRAIN);
    CHECK(rigid.max_strain > 2.0 * r.max_strain); /* so the check above can fail */
    CHECK_EQ_INT(rigid.frames_crossing, 0);
    CHECK_EQ_INT(r.failed, 0);
    CHECK_EQ_INT(r.frames_crossing, 0);
    CHECK_EQ_INT(r.unresolved, 0);
    CHECK(r.zones > 0);
    wc_model_free(&m);
    impulse_passes = WC_SELF_PASSES;
}

static void test_two_layers(void) {
    wc_model m;
    int n = 13;
    double s = 0.5, th = 0.003;
    CHECK(two_layers(&m, n, s, 0.01, 0.06));
    CHECK_EQ_INT(m.n_components, 2);
    wc_collider floor = {0};
    floor.type = WC_COLLIDER_PLANE;
    v3_set(floor.normal, 0, 1, 0);
    floor.thickness = 0.002;
    floor.friction = 0.3;
    wc_sim_def def = sim_def(1);
    def.self_thickness = th;
    wc_state* st = NULL;
    wc_diag d = {0};
    CHECK(wc_state_create(&st, &m, &def, NULL, &d) == WC_OK);
    CHECK(wc_state_set_colliders(st, &floor, 1, &d) == WC_OK);
    int crossed = 0;
    for (int f = 0; f < 60; ++f) {
        CHECK(wc_step_frame(st, 1.0 / 60, NULL, &d) == WC_OK);
        crossed += crossings(&m, st->x) > 0;
    }
    CHECK_EQ_INT(crossed, 0);
    /* the top layer rests on the bottom one, about a thickness above it: every top particle is
       above every bottom particle below it (same grid: compare the layers' mean heights and the
       smallest gap at matching grid points) */
    double min_gap = 1e9, mean_gap = 0, min_all = 1e9;
    int nv = n * n, inner = 0;
    for (int v = 0; v < nv; ++v) {
        int a = m.host_to_particle[v], b = m.host_to_particle[v + nv];
        double gap = st->x[3 * b + 1] - st->x[3 * a + 1];
        int i = v % n, j = v / n;
        if (gap < min_all) min_all = gap;
        if (i == 0 || j == 0 || i == n - 1 || j == n - 1) continue; /* the rims may droop */
        if (gap < min_gap) min_gap = gap;
        mean_gap += gap;
        ++inner;
    }
    mean_gap /= inner;
    printf("two layers: gap between matching points: inner min %.4g m, mean %.4g m, all min %.4g m (thickness %g m)\n",
           min_gap, mean_gap, min_all, th);
    CHECK(min_gap > 0.3 * th);
    CHECK(mean_gap > 0.7 * th && mean_gap < 1.5 * th);
    wc_state_destroy(st);
    /* without self-collision they fall through each other onto the floor */
    def.self_collision = 0;
    CHECK(wc_state_create(&st, &m, &def, NULL, &d) == WC_OK);
    CHECK(wc_state_set_colliders(st, &floor, 1, &d) == WC_OK);
    for (int f = 0; f < 60; ++f) CHECK(wc_step_frame(st, 1.0 / 60, NULL, &d) == WC_OK);
    min_gap = 1e9;
    for (int v = 0; v < nv; ++v) {
        int a = m.host_to_particle[v], b = m.host_to_particle[v + nv];
        double gap = st->x[3 * b + 1] - st->x[3 * a + 1];
        if (gap < min_gap) min_gap = gap;
    }
    CHECK(min_gap < 0.3 * th);
    wc_state_destroy(st);
    wc_model_free(&m);
}

static void test_bad_inputs(void) {
    wc_model m;
    CHECK(ts_sheet(&m, 4, 1.0, 0.0, 0, 1.0));
    double bad[] = {-0.001, 0.0, NAN, INFINITY};
    for (int k = 0; k < 4; ++k) {
        wc_sim_def def = sim_def(1);
        def.self_thickness = bad[k];
        wc_state* s = (wc_state*)1;
        wc_diag d = {0};
        CHECK(wc_state_create(&s, &m, &def, NULL, &d) == WC_ERROR_INVALID_ARGUMENT);
        CHECK(s == NULL);
        CHECK(strstr(d.message, "self_thickness") != NULL);
    }
    wc_sim_def def = sim_def(1);
    def.self_collision = 2;
    wc_state* s = NULL;
    wc_diag d = {0};
    CHECK(wc_state_create(&s, &m, &def, NULL, &d) == WC_ERROR_INVALID_ARGUMENT);
    CHECK(strstr(d.message, "self_collision") != NULL);
    def = sim_def(1);
    def.self_in_solve = -1;
    CHECK(wc_state_create(&s, &m, &def, NULL, &d) == WC_ERROR_INVALID_ARGUMENT);
    CHECK(s == NULL);
    CHECK(strstr(d.message, "self_in_solve") != NULL);
    wc_self* sc = NULL;
    CHECK(wc_self_create(&sc, &m, NAN, NULL, &d) == WC_ERROR_INVALID_ARGUMENT && sc == NULL);
    int c = 7;
    CHECK(wc_self_intersections(&m, NULL, NULL, &c, &d) == WC_ERROR_INVALID_ARGUMENT && c == 0);
    wc_model_free(&m);
}

/* The cost on a 64 x 64 sheet that does not touch itself (hanging from its top corners). */
static void test_cost(void) {
    wc_model m;
    int n = 65;
    CHECK(ts_sheet(&m, n, 1.0, 1.0, 1, 1.0));
    wc_pin pins[2] = {{0}};
    pins[0].particle = ts_sheet_particle(&m, n, 0, n - 1);
    pins[1].particle = ts_sheet_particle(&m, n, n - 1, n - 1);
    for (int k = 0; k < 2; ++k) v3_copy(pins[k].target, m.rest_pos + 3 * pins[k].particle);
    run_result on = simulate(&m, sim_def(1), pins, 2, NULL, 0, NULL, 10, 0);
    run_result off = simulate(&m, sim_def(0), pins, 2, NULL, 0, NULL, 10, 0);
    printf("cost, 64x64 sheet not touching itself (%d particles, 2 substeps/frame): %.2f ms/frame on (self-collision "
           "stage %.2f ms), %.2f off\n",
           m.n_particles, on.ms_per_frame, on.ms_self, off.ms_per_frame);
    CHECK_EQ_INT(on.max_crossings, 0);
    wc_model_free(&m);
}

/* argv[1], when given, runs only the tests whose name contains it. */
static const char* only = NULL;
#define RUN(fn) \
    do { \
        if (!only || strstr(#fn, only)) RUN_TEST(fn); \
    } while (0)

int main(int argc, char** argv) {
    if (argc > 1) only = argv[1];
    verbose = getenv("SELF_VERBOSE") != NULL;
    RUN(test_counter_vs_brute);
    RUN(test_sewn_overlap_not_counted);
    RUN(test_rigidify_momentum);
    RUN(test_zone_relax);
    RUN(test_bad_inputs);
    RUN(test_fold);
    RUN(test_heap);
    RUN(test_zones_alone);
    RUN(test_two_layers);
    RUN(test_cost);
    return TEST_SUMMARY();
}
