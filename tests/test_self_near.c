/* The self-collision queries' kept candidates (core/self_near.h) against the trees' full walk and
 * against brute force:
 *  - for every vertex and edge query, with and without a random node mask and with a visitor
 *    that stops early, the lists visit exactly the elements, in the same order, with the same
 *    result, that the tree's walk visits (less the pairs the adjacency rules exclude), and those
 *    are the elements brute force finds overlapping, in leaf order; on a folded strip, on two
 *    panels overlapping at rest (tangled) and the same panels sewn, after small motions within
 *    the bound (the lists kept), a teleport (kept), a turn and large motions (gathered again);
 *  - the bound is used: the lists were kept across most of those motions, and regathered on the
 *    others;
 *  - each query's gathered list (the batches' walks, self_near.c) is the one its own walk from
 *    the root with its box gives, element for element, over the cap (count -1) and under it, on 1
 *    and 2 threads, with the cloths squeezed together by up to 20x and jittered;
 *  - the heap's strip folded into 8 layers that settle onto each other on the floor (pairs in
 *    the solve, proximity and CCD impulses) steps to bit for bit the same positions and
 *    velocities, with the same counts, with the lists as without them (every query walking the
 *    trees), on 1 and 2 threads and with the impact zones alone, with a teleport of the whole
 *    cloth half way. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "check.h"
#include "heap_strip.h"
#include "overlap_panels.h"
#include "self_collide.h"
#include "self_near.h"
#include "step.h"
#include "test_support.h"
#define TEST_RNG_SEED 0x2545F4914F6CDD1Dull
#include "test_rng.h"
#include "vec3.h"

#define MAXV 4096

typedef struct rec {
    int seq[MAXV];
    int n, stop_after; /* stop_after > 0: the visitor returns 7 at that visit */
    const wc_self* sc;
    const wc_model* m;
    int query;          /* vertex i, or edge e */
    int filter;         /* 1: skip (record nothing for) the pairs the adjacency rules exclude */
} rec;

static int excluded(const wc_self* sc, const int* a, int na, const int* b, int nb) {
    int all_tangled = 1;
    for (int i = 0; i < na; ++i)
        for (int j = 0; j < nb; ++j)
            if (wc_self_linked(sc, a[i], b[j])) return 1;
    for (int i = 0; i < na; ++i) all_tangled &= sc->tangled[a[i]];
    for (int j = 0; j < nb; ++j) all_tangled &= sc->tangled[b[j]];
    return all_tangled;
}

static int pair_excluded(const rec* r, int elem, int tri) {
    const wc_self* sc = r->sc;
    if (tri) return excluded(sc, &r->query, 1, r->m->tris + 3 * elem, 3);
    return excluded(sc, sc->edges + 2 * r->query, 2, sc->edges + 2 * elem, 2);
}

static int rec_visit(rec* r, int elem, int tri) {
    if (r->filter && pair_excluded(r, elem, tri)) return 0;
    if (r->n < MAXV) r->seq[r->n] = elem;
    ++r->n;
    return r->stop_after > 0 && r->n == r->stop_after ? 7 : 0;
}
static int rec_tri(void* u, int t) { return rec_visit((rec*)u, t, 1); }
static int rec_edge(void* u, int f) { return rec_visit((rec*)u, f, 0); }

/* A random node mask on a tree (leaves at random, then up). */
static void random_mask(const wc_bvh* b, unsigned char* mask) {
    for (int k = 0; k < b->n_nodes; ++k)
        if (b->child[2 * k] < 0) mask[k] = urand() < 0.5;
    wc_bvh_mask_up(b, mask);
}

typedef struct counts {
    long long visits, queries;
} counts;

/* Every query at positions x0, x1 with boxes inflated by r, through the lists and through the
 * trees, compared; and against brute force. */
static void compare_queries(wc_self* sc, const wc_model* m, const double* x0, const double* x1, double r, counts* ct) {
    wc_self_refit(sc, m, x0, x1, r);
    sc->near_wait = 0;
    sc->near_waited = 1; /* gather whenever the lists do not cover (no waiting after a short-lived list) */
    wc_self_near_prepare(sc, m, x0, x1, r, 1);
    CHECK_EQ_INT(sc->near_use, 1);
    static rec a, b;
    unsigned char* tmask = malloc((size_t)sc->tri_bvh.n_nodes + 1);
    unsigned char* emask = malloc((size_t)sc->edge_bvh.n_nodes + 1);
    random_mask(&sc->tri_bvh, tmask);
    random_mask(&sc->edge_bvh, emask);
    int mismatches = 0, brute_mismatches = 0;
    for (int q = 0; q < sc->n + sc->n_edges; ++q) {
        int vertex = q < sc->n, id = vertex ? q : q - sc->n;
        double box[6];
        if (vertex)
            wc_self_swept_box(box, &q, 1, x0, x1, 0.0);
        else
            wc_self_swept_box(box, sc->edges + 2 * id, 2, x0, x1, 0.0);
        for (int variant = 0; variant < 3; ++variant) {
            const unsigned char* mask = variant == 1 ? (vertex ? tmask : emask) : NULL;
            int stop = variant == 2 ? 2 : 0;
            a = (rec){.n = 0, .stop_after = stop, .sc = sc, .m = m, .query = id, .filter = 1};
            b = (rec){.n = 0, .stop_after = stop, .sc = sc, .m = m, .query = id, .filter = 1};
            int ra, rb;
            if (vertex) {
                ra = wc_self_near_tris(sc, id, box, mask, rec_tri, &a);
                rb = wc_bvh_query_masked(&sc->tri_bvh, box, mask, rec_tri, &b);
            } else {
                ra = wc_self_near_edges(sc, id, box, mask, rec_edge, &a);
                rb = wc_self_edges_above_masked(sc, id, box, mask, rec_edge, &b);
            }
            if (ra != rb || a.n != b.n || memcmp(a.seq, b.seq, (size_t)(a.n < MAXV ? a.n : MAXV) * sizeof(int)))
                ++mismatches;
            ct->visits += a.n;
            ++ct->queries;
            if (variant != 0) continue;
            /* brute force: every element whose box overlaps, in leaf order (the trees' preorder) */
            const wc_bvh* tree = vertex ? &sc->tri_bvh : &sc->edge_bvh;
            const double* boxes = vertex ? sc->tri_box : sc->edge_box;
            int nb = 0, ok = 1;
            for (int node = 0; node < tree->n_nodes; ++node) {
                if (tree->child[2 * node] >= 0) continue;
                int p = tree->child[2 * node + 1];
                if (!vertex && p <= id) continue;
                if (!wc_box_overlap(boxes + 6 * p, box) || pair_excluded(&a, p, vertex)) continue;
                if (nb >= a.n || a.seq[nb] != p) ok = 0;
                ++nb;
            }
            if (!ok || nb != a.n) ++brute_mismatches;
        }
    }
    CHECK_EQ_INT(mismatches, 0);
    CHECK_EQ_INT(brute_mismatches, 0);
    free(tmask);
    free(emask);
}

/* Positions y = x moved by a random vector of up to amp on each axis, then turned by `turn`
 * (rad) about the vertical through the origin and shifted by `shift`. */
static void moved(const double* x, int n, double amp, double turn, const double* shift, double* y) {
    double c = cos(turn), s = sin(turn);
    for (int i = 0; i < n; ++i) {
        double p[3];
        for (int k = 0; k < 3; ++k) p[k] = x[3 * i + k] + amp * (2 * urand() - 1);
        y[3 * i] = c * p[0] + s * p[2] + shift[0];
        y[3 * i + 1] = p[1] + shift[1];
        y[3 * i + 2] = -s * p[0] + c * p[2] + shift[2];
    }
}

/* One model through a sequence of motions from positions x (its layers a few mm apart). */
static void motions(const wc_model* m, const double* x, double th, counts* ct, int* kept, int* gathered) {
    wc_self* sc = NULL;
    wc_diag d = {0};
    CHECK(wc_self_create(&sc, m, th, NULL, &d) == WC_OK);
    if (!sc) return;
    int n = m->n_particles;
    double *y0 = malloc(3 * (size_t)n * sizeof(double)), *y1 = malloc(3 * (size_t)n * sizeof(double));
    double zero[3] = {0, 0, 0}, far[3] = {40.0, -7.0, 13.0};
    double slack = sc->near_gap - th; /* what 2T may use */
    /* step: amp of the motion (within the bound: the lists kept; beyond: gathered), turn, shift */
    struct {
        double amp, turn;
        const double* shift;
        double r;
        int expect_kept; /* 1: within the bound, 0: beyond, -1: either */
    } steps[] = {
        {0.0, 0.0, zero, th, -1},           /* the first gathering */
        {0.24 * slack, 0.0, zero, th, 1},   /* 2T <= 0.96 slack (two positions each 0.24 from x) */
        {0.24 * slack, 0.0, zero, th / 100, 1},
        {0.2 * slack, 0.0, far, th, 1},     /* a teleport: one translation */
        {0.0, 0.3, zero, th, 0},            /* a turn */
        {0.0, 0.0, zero, th, 0},            /* back */
        {1.5 * slack, 0.0, zero, th, 0},    /* large motion */
        {0.6 * th, 0.0, zero, th, -1},
        {0.6 * th, 0.0, zero, th / 100, -1},
    };
    for (size_t k = 0; k < sizeof steps / sizeof steps[0]; ++k) {
        moved(x, n, steps[k].amp, steps[k].turn, steps[k].shift, y0);
        moved(x, n, steps[k].amp, steps[k].turn, steps[k].shift, y1);
        int covers = wc_self_near_covers(sc, y0, y1, steps[k].r);
        if (steps[k].expect_kept >= 0) CHECK_EQ_INT(covers, steps[k].expect_kept);
        /* a later pass of the stage (full = 0) after a full phase that used the lists (the last
           compare_queries checked it): the lists exactly when they cover, and never a gathering */
        int gathers = sc->near_gathers;
        wc_self_near_prepare(sc, m, y0, y1, steps[k].r, 0);
        CHECK_EQ_INT(sc->near_use, covers);
        CHECK_EQ_INT(sc->near_gathers, gathers);
        *kept += covers;
        *gathered += !covers;
        compare_queries(sc, m, y0, y1, steps[k].r, ct);
    }
    free(y0);
    free(y1);
    wc_self_destroy(sc);
}

/* fn on the three models the lists are tested on: the heap strip folded (thickness 5 mm), and the
 * two overlapping panels, apart and sewn (3 mm), at their rest positions */
static void for_each_model(void (*fn)(const wc_model* m, const double* x, double th, void* user), void* user) {
    wc_model m;
    wc_collider floor;
    heap_strip(&m, &floor);
    double* x = malloc(3 * (size_t)m.n_particles * sizeof(double));
    heap_strip_folded(&m, x);
    fn(&m, x, 0.005, user);
    free(x);
    wc_model_free(&m);
    for (int sewn = 0; sewn < 2; ++sewn) {
        overlap_panels(&m, sewn);
        CHECK(sewn ? m.n_seams >= 5 : m.n_seams == 0);
        fn(&m, m.rest_pos, 0.003, user);
        wc_model_free(&m);
    }
}

typedef struct motions_tally {
    counts ct;
    int kept, gathered;
} motions_tally;

static void motions_on(const wc_model* m, const double* x, double th, void* user) {
    motions_tally* t = user;
    motions(m, x, th, &t->ct, &t->kept, &t->gathered);
}

static void test_lists_vs_trees(void) {
    motions_tally t = {{0, 0}, 0, 0};
    for_each_model(motions_on, &t);
    printf("  %lld queries, %lld visits; the lists kept over %d motions, gathered again for %d\n", t.ct.queries,
           t.ct.visits, t.kept, t.gathered);
    CHECK(t.ct.visits > t.ct.queries); /* the queries had candidates */
    CHECK(t.kept >= 9);
    CHECK(t.gathered >= 9);
}

/* ---- the gathering against each query's own walk -------------------------------------------- */

/* The lists as each query's own walk from the root gathers them (self_near.c's gathering before
 * the batches): the candidates in the walk's order less the excluded pairs, the walk stopped with
 * count -1 when one more than the cap arrives. */
typedef struct walk_list {
    rec r;
    int count;
    int out[WC_SELF_NEAR_CAP];
} walk_list;

static int walk_keep(void* u, int elem, int tri) {
    walk_list* w = (walk_list*)u;
    if (pair_excluded(&w->r, elem, tri)) return 0;
    if (w->count == WC_SELF_NEAR_CAP) {
        w->count = -1;
        return 1;
    }
    w->out[w->count++] = elem;
    return 0;
}
static int walk_tri(void* u, int t) { return walk_keep(u, t, 1); }
static int walk_edge(void* u, int f) { return walk_keep(u, f, 0); }

/* Gather at x0, x1 (r) on `threads` threads and compare every query's list with its own walk's;
 * counts the lists over the cap (*over) and those under it (*under) */
static void compare_gathering(wc_self* sc, const wc_model* m, const double* x0, const double* x1, double r,
                              int threads, int* over, int* under, int* mismatches) {
    sc->threads = threads;
    sc->near_kept = 0; /* no lists: a full phase gathers */
    sc->near_wait = 0;
    int gathers = sc->near_gathers;
    wc_self_near_prepare(sc, m, x0, x1, r, 1);
    CHECK_EQ_INT(sc->near_gathers, gathers + 1);
    wc_self_refit(sc, m, x0, sc->near_ahead, r); /* the gathering's trees */
    double grow = sc->near_gap - r;
    for (int q = 0; q < sc->n + sc->n_edges; ++q) {
        int vertex = q < sc->n, id = vertex ? q : q - sc->n;
        double box[6];
        static walk_list w;
        w.r = (rec){.sc = sc, .m = m, .query = id, .filter = 1};
        w.count = 0;
        if (vertex) {
            memcpy(box, sc->near_anchor + 6 * q, sizeof box);
            wc_box_inflate(box, grow);
            wc_bvh_query(&sc->tri_bvh, box, walk_tri, &w);
        } else {
            wc_self_swept_box(box, sc->edges + 2 * id, 2, x0, sc->near_ahead, grow);
            wc_self_edges_above(sc, id, box, walk_edge, &w);
        }
        const int* got = sc->near_cand + (size_t)q * WC_SELF_NEAR_CAP;
        if (sc->near_count[q] != w.count ||
            (w.count > 0 && memcmp(got, w.out, (size_t)w.count * sizeof(int)) != 0))
            ++*mismatches;
        if (w.count < 0) ++*over;
        else if (w.count > 0) ++*under;
    }
    wc_self_refit(sc, m, x0, x1, r);
}

static void gatherings(const wc_model* m, const double* x, double th, int* over, int* under, int* mismatches) {
    wc_self* sc = NULL;
    wc_diag d = {0};
    CHECK(wc_self_create(&sc, m, th, NULL, &d) == WC_OK);
    if (!sc) return;
    int n = m->n_particles;
    double *y0 = malloc(3 * (size_t)n * sizeof(double)), *y1 = malloc(3 * (size_t)n * sizeof(double));
    double c[3] = {0, 0, 0};
    for (int i = 0; i < n; ++i)
        for (int k = 0; k < 3; ++k) c[k] += x[3 * i + k] / n;
    for (int trial = 0; trial < 12; ++trial) {
        /* squeezed towards the centre by up to 20x (crowded: lists over the cap), jittered by up to
           a few thicknesses, moving by up to as much over the phase */
        double squeeze = trial % 3 == 0 ? 1.0 : 1.0 / (1.0 + 19.0 * urand()), amp = th * 4.0 * urand();
        for (int i = 0; i < n; ++i)
            for (int k = 0; k < 3; ++k) {
                y0[3 * i + k] = c[k] + squeeze * (x[3 * i + k] - c[k]) + amp * (2 * urand() - 1);
                y1[3 * i + k] = y0[3 * i + k] + amp * (2 * urand() - 1);
            }
        /* a few particles flung across the cloth: their elements' boxes span it (over the cap),
           and the batches that hold them collect more than a batch may (their queries walk) */
        if (trial % 4 == 1)
            for (int j = 0; j < 1 + n / 100; ++j) {
                int i = (int)(urand() * n) % n;
                for (int k = 0; k < 3; ++k) y1[3 * i + k] = c[k] + (2 * urand() - 1) * fabs(x[3 * i + k] - c[k]);
            }
        double r = trial % 2 ? th : th / 100;
        compare_gathering(sc, m, y0, y1, r, 1 + trial % 2, over, under, mismatches);
    }
    free(y0);
    free(y1);
    wc_self_destroy(sc);
}

static void gatherings_on(const wc_model* m, const double* x, double th, void* user) {
    int* t = user;   /* over, under, mismatches */
    gatherings(m, x, th, &t[0], &t[1], &t[2]);
}

static void test_gathering_vs_walks(void) {
    int t[3] = {0, 0, 0};
    for_each_model(gatherings_on, t);
    int over = t[0], under = t[1], mismatches = t[2];
    printf("  %d lists under the cap, %d over it, %d unlike the query's own walk\n", under, over, mismatches);
    CHECK_EQ_INT(mismatches, 0);
    CHECK(over > 100);  /* both kinds of list were gathered */
    CHECK(under > 1000);
}

/* ---- stepping: the heap with and without the lists ------------------------------------------ */

#define FRAMES 12

typedef struct run {
    double* xv;   /* (FRAMES x 2 x n x 3): x then v after each frame */
    int impacts, zones, proximity, pairs, later, failed;
} run;

static run simulate(const wc_model* m, const wc_collider* floor, int threads, int passes, int near_off) {
    run r = {0};
    size_t n3 = 3 * (size_t)m->n_particles;
    r.xv = calloc(FRAMES * 2 * n3, sizeof(double));
    wc_sim_def def = wc_default_sim_def();
    def.substeps = 2;
    def.self_collision = 1;
    def.sleep_speed = 0;
    def.threads = threads;
    wc_state* s = NULL;
    wc_diag d = {0};
    CHECK(wc_state_create(&s, m, &def, NULL, &d) == WC_OK);
    if (!s || !r.xv) {
        r.failed = 1;
        return r;
    }
    s->self->near_off = near_off;
    s->self->passes = passes;
    /* the strip folded into layers 4 mm apart, lying flat just above the floor: they settle onto
       each other */
    double* z = malloc(n3 * sizeof(double));
    heap_strip_folded(m, z);
    for (int i = 0; i < m->n_particles; ++i) v3_set(s->x + 3 * i, z[3 * i], 0.006 + z[3 * i + 2], z[3 * i + 1]);
    free(z);
    wc_collider fl = *floor;
    CHECK(wc_state_set_colliders(s, &fl, 1, &d) == WC_OK);
    for (int f = 0; f < FRAMES; ++f) {
        if (f == FRAMES / 2) {
            /* a teleport of the cloth and its floor: one translation */
            for (int i = 0; i < m->n_particles; ++i) s->x[3 * i + 1] += 3.0;
            fl.offset += 3.0;
            CHECK(wc_state_set_colliders(s, &fl, 1, &d) == WC_OK);
        }
        wc_step_stats st;
        if (wc_step_frame(s, 1.0 / 60, &st, &d) != WC_OK) ++r.failed;
        r.impacts += st.self_impacts;
        r.zones += st.self_zones;
        r.proximity += st.self_proximity;
        r.pairs += st.self_pairs;
        memcpy(r.xv + (2 * f) * n3, s->x, n3 * sizeof(double));
        memcpy(r.xv + (2 * f + 1) * n3, s->v, n3 * sizeof(double));
    }
    r.later = s->self->near_later;
    wc_state_destroy(s);
    return r;
}

static void test_steps_same(void) {
    wc_model m;
    wc_collider floor;
    heap_strip(&m, &floor);
    size_t bytes = FRAMES * 2 * 3 * (size_t)m.n_particles * sizeof(double);
    /* 1 and 2 threads with the CCD impulses, 1 thread with the zones alone (tests' passes 0) */
    for (int variant = 0; variant < 3; ++variant) {
        int threads = variant == 1 ? 2 : 1, passes = variant == 2 ? 0 : WC_SELF_PASSES;
        run trees = simulate(&m, &floor, threads, passes, 1), lists = simulate(&m, &floor, threads, passes, 0);
        printf("  %d thread(s), %d passes: %d proximity, %d impacts, %d zones, %d pairs in the solve, %d later "
               "passes through the lists\n", threads, passes, lists.proximity, lists.impacts, lists.zones, lists.pairs,
               lists.later);
        CHECK_EQ_INT(trees.failed, 0);
        CHECK_EQ_INT(lists.failed, 0);
        CHECK(lists.proximity + lists.impacts > 0 && lists.pairs > 0); /* the stage had work to do */
        if (passes == 0) CHECK(lists.zones > 0);
        CHECK(lists.later > 0);   /* the stage's later passes used the lists too (impulses, zones) */
        CHECK_EQ_INT(trees.later, 0);
        CHECK(memcmp(trees.xv, lists.xv, bytes) == 0);
        CHECK_EQ_INT(lists.impacts, trees.impacts);
        CHECK_EQ_INT(lists.zones, trees.zones);
        CHECK_EQ_INT(lists.proximity, trees.proximity);
        CHECK_EQ_INT(lists.pairs, trees.pairs);
        free(trees.xv);
        free(lists.xv);
    }
    wc_model_free(&m);
}

int main(void) {
    RUN_TEST(test_lists_vs_trees);
    RUN_TEST(test_gathering_vs_walks);
    RUN_TEST(test_steps_same);
    return TEST_SUMMARY();
}
