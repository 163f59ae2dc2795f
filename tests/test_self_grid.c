/* The dirty elements' grid (core/self_grid.h) that lets the self-collision stage's later passes
 * skip the clean queries with no dirty element near:
 *  - against brute force: random boxes marked, random query boxes (touching a marked box exactly
 *    at a face, inside one, outside the grid's box, degenerate), the grid says "no hit" only when
 *    no marked box overlaps the query (wc_box_overlap), and it does say so for most far queries;
 *  - the passes with the grids against those without (every clean query walking its masked
 *    tree): on the heap's strip folded into layers with random motions and random dirty sets,
 *    the impulse passes give the same positions and counts, and the detection passes the same
 *    marked queries (active[]), the same zones and counts, bit for bit; the grids did skip
 *    queries. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "check.h"
#include "heap_strip.h"
#include "self_collide.h"
#include "self_grid.h"
#include "self_pass.h"
#include "test_support.h"
#include "test_rng.h"

static void random_box(double* b, double size) {
    for (int k = 0; k < 3; ++k) {
        double c = 1.4 * urand() - 0.2, w = size * urand(); /* some outside [0, 1] */
        b[k] = c;
        b[3 + k] = c + w;
    }
}

static void test_grid_vs_brute(void) {
    enum { MARKED = 60, QUERIES = 20000 };
    static double marked[MARKED * 6];
    wc_self_grid gr = {0};
    gr.g = 16;
    gr.cell = malloc(16 * 16 * 16);
    double root[6] = {0, 0, 0, 1, 1, 1};
    int missed = 0, skipped = 0, far = 0, touching = 0;
    for (int round = 0; round < 20; ++round) {
        wc_self_grid_reset(&gr, root);
        for (int j = 0; j < MARKED; ++j) {
            random_box(marked + 6 * j, 0.05);
            wc_self_grid_mark(&gr, marked + 6 * j);
        }
        CHECK_EQ_INT(gr.on, 1);
        for (int q = 0; q < QUERIES; ++q) {
            double b[6];
            int kind = q % 4;
            random_box(b, kind == 3 ? 0.0 : 0.02);
            if (kind == 1) { /* touching a marked box at a face on one axis */
                const double* mb = marked + 6 * (q % MARKED);
                int k = q % 3;
                memcpy(b, mb, 6 * sizeof(double));
                double w = 0.01 * urand();
                if (q % 2) {
                    b[k] = mb[3 + k];
                    b[3 + k] = mb[3 + k] + w;
                } else {
                    b[3 + k] = mb[k];
                    b[k] = mb[k] - w;
                }
                ++touching;
            }
            int overlap = 0;
            for (int j = 0; j < MARKED && !overlap; ++j) overlap = wc_box_overlap(marked + 6 * j, b);
            int hit = wc_self_grid_hits(&gr, b);
            if (overlap && !hit) ++missed;
            if (!hit) ++skipped;
            if (!overlap) ++far;
        }
    }
    printf("  %d queries (%d touching a marked box): %d overlap none, %d skipped, %d missed\n", 20 * QUERIES, touching,
           far, skipped, missed);
    CHECK_EQ_INT(missed, 0);
    CHECK(skipped > far / 2);
    /* a box spanning too many cells, and a NaN, turn the grid off: every query hits */
    wc_self_grid_reset(&gr, root);
    double big[6] = {0, 0, 0, 1, 1, 1}, nan_box[6] = {NAN, 0, 0, 0.1, 0.1, 0.1}, q[6] = {0.5, 0.5, 0.5, 0.5, 0.5, 0.5};
    CHECK_EQ_INT(wc_self_grid_hits(&gr, q), 0);
    wc_self_grid_mark(&gr, big);
    CHECK_EQ_INT(gr.on, 0);
    CHECK_EQ_INT(wc_self_grid_hits(&gr, q), 1);
    wc_self_grid_reset(&gr, root);
    wc_self_grid_mark(&gr, nan_box);
    CHECK_EQ_INT(wc_self_grid_hits(&gr, q), 1);
    free(gr.cell);
}

/* One pass of mode with the grids on or off from the same start (x0 -> x1, dirty), its results. */
typedef struct pass_out {
    double* x;
    unsigned char* active;
    unsigned char* touched;
    int* parent;
    int count, prox;
    int grids_on, skippable; /* both grids on; clean vertex queries whose box meets no marked cell */
} pass_out;

static pass_out run_pass(wc_self* sc, const wc_model* m, const double* x0, const double* x1, int mode,
                         const unsigned char* dirty, int grid_off) {
    int n = m->n_particles, nq = n + sc->n_edges;
    pass_out o = {malloc(3 * (size_t)n * sizeof(double)), malloc((size_t)nq), calloc((size_t)n, 1),
                  malloc((size_t)n * sizeof(int)), 0, 0, 0, 0};
    memcpy(o.x, x1, 3 * (size_t)n * sizeof(double));
    memcpy(sc->x_start, x0, 3 * (size_t)n * sizeof(double));
    for (int i = 0; i < n; ++i) {
        sc->inv_mass[i] = m->inv_mass[i];
        sc->parent[i] = i;
        sc->in_zone[i] = 0;
    }
    sc->grid_off = grid_off;
    o.count = wc_self_pass(sc, m, o.x, mode, &o.prox, dirty, mode == WC_SELF_PASS_DETECT ? NULL : o.touched);
    memcpy(o.active, sc->active, (size_t)nq);
    memcpy(o.parent, sc->parent, (size_t)n * sizeof(int));
    o.grids_on = !grid_off && sc->tri_grid.on && sc->edge_grid.on;
    for (int i = 0; i < n && o.grids_on; ++i) {
        double b[6];
        wc_self_swept_box(b, &i, 1, x0, x1, 0.0);
        o.skippable += !dirty[i] && !wc_self_grid_hits(&sc->tri_grid, b);
    }
    return o;
}

static void pass_free(pass_out* o) {
    free(o->x);
    free(o->active);
    free(o->touched);
    free(o->parent);
}

static void test_passes_same(void) {
    wc_model m;
    wc_collider floor;
    heap_strip(&m, &floor);
    int n = m.n_particles;
    wc_self* sc = NULL;
    wc_diag d = {0};
    CHECK(wc_self_create(&sc, &m, 0.005, NULL, &d) == WC_OK);
    if (!sc) return;
    sc->near_off = 1;
    double *x0 = malloc(3 * (size_t)n * sizeof(double)), *x1 = malloc(3 * (size_t)n * sizeof(double));
    unsigned char* dirty = malloc((size_t)n);
    int differ = 0, active_on = 0, grids_on = 0, skippable = 0, compared = 0;
    for (int round = 0; round < 24; ++round) {
        heap_strip_folded(&m, x0);
        /* motion: layers pressed into each other (up to 6 mm down) plus noise, some rounds fast */
        double amp = round % 3 == 0 ? 0.003 : 0.0008;
        for (int i = 0; i < n; ++i)
            for (int k = 0; k < 3; ++k) {
                x0[3 * i + k] += 0.0004 * (2 * urand() - 1);
                x1[3 * i + k] = x0[3 * i + k] + amp * (2 * urand() - 1) - (k == 2 ? 0.006 * urand() : 0.0);
            }
        /* dirty: one or a few patches along the strip, or scattered particles */
        double p = round % 4 == 0 ? 0.02 : 0.0;
        double c0 = urand(), w = 0.05 + 0.1 * urand();
        for (int i = 0; i < n; ++i) {
            double s = (double)i / n;
            dirty[i] = (unsigned char)(urand() < p || (s > c0 && s < c0 + w));
        }
        for (int mode = WC_SELF_PASS_IMPULSE; mode <= WC_SELF_PASS_DETECT; ++mode) {
            pass_out on = run_pass(sc, &m, x0, x1, mode, dirty, 0);
            pass_out off = run_pass(sc, &m, x0, x1, mode, dirty, 1);
            int nq = n + sc->n_edges;
            /* positions, counts, marked queries, the next dirty set, the zones merged */
            if (on.count != off.count || on.prox != off.prox || memcmp(on.x, off.x, 3 * (size_t)n * sizeof(double)) ||
                memcmp(on.active, off.active, (size_t)nq) || memcmp(on.touched, off.touched, (size_t)n) ||
                memcmp(on.parent, off.parent, (size_t)n * sizeof(int)))
                ++differ;
            for (int q = 0; q < nq; ++q) active_on += on.active[q];
            grids_on += on.grids_on;
            skippable += on.skippable;
            ++compared;
            pass_free(&on);
            pass_free(&off);
        }
    }
    printf("  %d passes compared (%d with both grids on, %d clean vertex queries skippable), %d queries marked; "
           "%d differ\n", compared, grids_on, skippable, active_on, differ);
    CHECK_EQ_INT(differ, 0);
    CHECK(active_on > 0);            /* the passes had work */
    CHECK(grids_on > compared / 2);  /* the grids were on */
    CHECK(skippable > 0);            /* and let queries skip */
    free(x0);
    free(x1);
    free(dirty);
    wc_self_destroy(sc);
    wc_model_free(&m);
}

/* The later passes' partial refit (wc_self.refit_dirty): with the trees fitted at x1 and only
 * dirty particles moved since (x2), a pass refits only the dirty elements' boxes and the nodes
 * above them. Its trees' boxes, marked queries, counts and positions equal those of the pass
 * with the full refit, bit for bit. */
static void reset_zones(wc_self* sc, int n) {
    for (int i = 0; i < n; ++i) {
        sc->parent[i] = i;
        sc->in_zone[i] = 0;
    }
}

static void test_partial_refit(void) {
    wc_model m;
    wc_collider floor;
    heap_strip(&m, &floor);
    int n = m.n_particles;
    wc_self* sc = NULL;
    wc_diag d = {0};
    CHECK(wc_self_create(&sc, &m, 0.005, NULL, &d) == WC_OK);
    if (!sc) return;
    sc->near_off = 1;
    for (int i = 0; i < n; ++i) sc->inv_mass[i] = m.inv_mass[i];
    int nq = n + sc->n_edges;
    size_t nt = 6 * (size_t)sc->tri_bvh.n_nodes, ne = 6 * (size_t)sc->edge_bvh.n_nodes, bytes = 3 * (size_t)n * sizeof(double);
    double *x0 = malloc(bytes), *x1 = malloc(bytes), *xp = malloc(bytes), *xf = malloc(bytes);
    double *tb = malloc(nt * sizeof(double)), *eb = malloc(ne * sizeof(double));
    unsigned char *dirty = malloc((size_t)n), *active_p = malloc((size_t)nq);
    int differ = 0, moved = 0, marked = 0;
    for (int round = 0; round < 12; ++round) {
        heap_strip_folded(&m, x0);
        for (int i = 0; i < 3 * n; ++i) x1[i] = x0[i] + 0.001 * (2 * urand() - 1);
        double c0 = urand(), w = 0.03 + 0.1 * urand();
        for (int i = 0; i < n; ++i) {
            double s = (double)i / n;
            dirty[i] = (unsigned char)((s > c0 && s < c0 + w) || urand() < 0.01);
        }
        for (int mode = WC_SELF_PASS_IMPULSE; mode <= WC_SELF_PASS_DETECT; ++mode) {
            memcpy(sc->x_start, x0, bytes);
            wc_self_refit(sc, &m, x0, x1, sc->eta); /* the last pass's trees, at x1 */
            memcpy(xp, x1, bytes);
            for (int i = 0; i < n; ++i)
                if (dirty[i]) {
                    for (int k = 0; k < 3; ++k) xp[3 * i + k] += (round % 2 ? 0.05 : 0.002) * (2 * urand() - 1);
                    ++moved;
                }
            memcpy(xf, xp, bytes);
            reset_zones(sc, n);
            sc->refit_r = sc->eta;
            sc->refit_dirty = 1;
            int cp = wc_self_pass(sc, &m, xp, mode, NULL, dirty, NULL);
            memcpy(active_p, sc->active, (size_t)nq);
            memcpy(tb, sc->tri_bvh.box, nt * sizeof(double));
            memcpy(eb, sc->edge_bvh.box, ne * sizeof(double));
            reset_zones(sc, n);
            int cf = wc_self_pass(sc, &m, xf, mode, NULL, dirty, NULL); /* refit_dirty reset: the full refit */
            if (cp != cf || memcmp(active_p, sc->active, (size_t)nq) || memcmp(xp, xf, bytes) ||
                memcmp(tb, sc->tri_bvh.box, nt * sizeof(double)) || memcmp(eb, sc->edge_bvh.box, ne * sizeof(double)))
                ++differ;
            for (int q = 0; q < nq; ++q) marked += active_p[q];
        }
    }
    printf("  24 passes with the partial refit (%d particle moves, %d queries marked), %d differ from the full refit\n",
           moved, marked, differ);
    CHECK_EQ_INT(differ, 0);
    CHECK(marked > 0);
    free(x0);
    free(x1);
    free(xp);
    free(xf);
    free(tb);
    free(eb);
    free(dirty);
    free(active_p);
    wc_self_destroy(sc);
    wc_model_free(&m);
}

int main(void) {
    RUN_TEST(test_grid_vs_brute);
    RUN_TEST(test_passes_same);
    RUN_TEST(test_partial_refit);
    return TEST_SUMMARY();
}
