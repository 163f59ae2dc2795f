/* The self-collision stage: its creation and its sequence of passes and impact zones
 * (self_collide.h). */
#include "self_collide.h"

#include <math.h>
#include <string.h>

#include "self_near.h"
#include "self_pass.h"
#include "union_find.h"

static int count_unique_edges(const wc_winged_edge* we) {
    int k = 0;
    for (int e = 0; e < we->n_edges; ++e)
        if (!wc_we_repeats_previous(we, e)) ++k;
    return k;
}

static void fill_edges(const wc_winged_edge* we, int* edges) {
    int k = 0;
    for (int e = 0; e < we->n_edges; ++e)
        if (!wc_we_repeats_previous(we, e)) {
            edges[2 * k] = we->edges[e].v[0];
            edges[2 * k + 1] = we->edges[e].v[1];
            ++k;
        }
}

typedef struct tangle_ctx {
    const wc_model* m;
    const wc_self* sc;
    unsigned char* tangled;
    int a, b, pairs;
} tangle_ctx;

static int visit_tangle(void* user, int t) {
    tangle_ctx* c = (tangle_ctx*)user;
    if (!wc_self_edge_tri_cross(c->m, c->sc->seam_start, c->sc->seam_nbr, c->m->rest_pos, c->a, c->b, t)) return 0;
    const int* tv = c->m->tris + 3 * t;
    c->tangled[c->a] = c->tangled[c->b] = 1;
    c->tangled[tv[0]] = c->tangled[tv[1]] = c->tangled[tv[2]] = 1;
    ++c->pairs;
    return 0;
}

/* Particles of the edge-triangle pairs that already cross in the rest shape (creation): a mesh
 * that starts tangled (overlapping panels along a seam, layers through each other) cannot be
 * untangled by a method that only prevents new crossings; pairs made only of such particles are
 * left alone, so the stage does not lock them in impact zones. Returns the crossing pairs. */
static int mark_tangled(wc_self* sc, const wc_model* m) {
    tangle_ctx c = {m, sc, sc->tangled, 0, 0, 0};
    for (int e = 0; e < sc->n_edges; ++e) {
        c.a = sc->edges[2 * e];
        c.b = sc->edges[2 * e + 1];
        double b[6];
        wc_box_empty(b);
        wc_box_add(b, m->rest_pos + 3 * c.a);
        wc_box_add(b, m->rest_pos + 3 * c.b);
        wc_bvh_query(&sc->tri_bvh, b, visit_tangle, &c);
    }
    return c.pairs;
}

void wc_self_destroy(wc_self* sc) {
    if (!sc) return;
    wc_allocator a = sc->alloc;
    wc_bvh_free(&sc->tri_bvh);
    wc_bvh_free(&sc->edge_bvh);
    wc_bvh_split_free(&sc->tri_split, &a);
    wc_bvh_split_free(&sc->edge_split, &a);
    wc_free(&a, sc->edges);
    wc_free(&a, sc->tri_box);
    wc_free(&a, sc->edge_box);
    wc_free(&a, sc->part_box);
    wc_free(&a, sc->x_start);
    wc_free(&a, sc->x_old);
    wc_free(&a, sc->inv_mass);
    wc_free(&a, sc->parent);
    wc_free(&a, sc->in_zone);
    wc_free(&a, sc->active);
    wc_free(&a, sc->edge_max);
    wc_free(&a, sc->tri_mask);
    wc_free(&a, sc->edge_mask);
    wc_free(&a, sc->dirty);
    wc_free(&a, sc->dirty_next);
    wc_free(&a, sc->zone);
    wc_free(&a, sc->relax.due);
    wc_free(&a, sc->relax.next);
    wc_free(&a, sc->tangled);
    wc_free(&a, sc->seam_start);
    wc_free(&a, sc->seam_nbr);
    wc_free(&a, sc->tri_grid.cell);
    wc_free(&a, sc->edge_grid.cell);
    wc_self_near_free(sc);
    wc_free(&a, sc);
}

wc_status wc_self_create(wc_self** out, const wc_model* m, double thickness, const wc_allocator* alloc,
                           wc_diag* diag) {
    if (out) *out = NULL;
    if (!out || !m) return wc_fail(diag, WC_ERROR_INVALID_ARGUMENT, "self-collision: NULL argument");
    if (!(thickness > 0) || !isfinite(thickness))
        return wc_fail(diag, WC_ERROR_INVALID_ARGUMENT, "self-collision: thickness %g m must be finite and > 0",
                       thickness);
    wc_allocator A = alloc ? *alloc : (wc_allocator){0};
    wc_self* sc = WC_NEW(&A, wc_self, 1);
    if (!sc) return wc_fail(diag, WC_ERROR_OUT_OF_MEMORY, "self-collision: out of memory");
    sc->alloc = A;
    sc->thickness = thickness;
    sc->eta = thickness / 100.0;
    sc->passes = WC_SELF_PASSES;
    sc->zone_strain = WC_SELF_ZONE_STRAIN;
    int n = m->n_particles;
    sc->n = n;
    sc->n_tris = m->n_tris;
    sc->n_edges = count_unique_edges(&m->we);
    sc->edges = WC_NEW(&A, int, 2 * (size_t)sc->n_edges + 2);
    sc->tri_box = WC_NEW(&A, double, 6 * (size_t)sc->n_tris + 6);
    sc->edge_box = WC_NEW(&A, double, 6 * (size_t)sc->n_edges + 6);
    sc->part_box = WC_NEW(&A, double, 6 * (size_t)n + 6);
    sc->x_start = WC_NEW(&A, double, 3 * (size_t)n);
    sc->x_old = WC_NEW(&A, double, 3 * (size_t)n);
    sc->inv_mass = WC_NEW(&A, double, (size_t)n);
    sc->parent = WC_NEW(&A, int, (size_t)n);
    sc->in_zone = WC_NEW(&A, unsigned char, (size_t)n);
    sc->zone = WC_NEW(&A, double, WC_SELF_ZONE_STRIDE * (size_t)n);
    sc->tangled = WC_NEW(&A, unsigned char, (size_t)n);
    sc->active = WC_NEW(&A, unsigned char, (size_t)n + (size_t)sc->n_edges + 1);
    sc->dirty = WC_NEW(&A, unsigned char, (size_t)n + 1);
    sc->dirty_next = WC_NEW(&A, unsigned char, (size_t)n + 1);
    sc->relax.words = (m->spring_type_start[WC_SPRING_STRETCH + 1] - m->spring_type_start[WC_SPRING_STRETCH] + 63) / 64;
    sc->relax.due = WC_NEW(&A, uint64_t, (size_t)sc->relax.words + 1);
    sc->relax.next = WC_NEW(&A, uint64_t, (size_t)sc->relax.words + 1);
    sc->threads = 1;
    if (!sc->edges || !sc->tri_box || !sc->edge_box || !sc->part_box || !sc->x_start || !sc->x_old || !sc->inv_mass || !sc->parent ||
        !sc->in_zone || !sc->zone || !sc->active || !sc->tangled || !sc->dirty ||
        !sc->dirty_next || !sc->relax.due || !sc->relax.next) {
        wc_self_destroy(sc);
        return wc_fail(diag, WC_ERROR_OUT_OF_MEMORY, "self-collision: out of memory (%d particles)", n);
    }
    if (wc_self_near_alloc(sc) != WC_OK || wc_self_seam_links(m, &A, &sc->seam_start, &sc->seam_nbr) != WC_OK) {
        wc_self_destroy(sc);
        return wc_fail(diag, WC_ERROR_OUT_OF_MEMORY, "self-collision: out of memory (%d particles)", n);
    }
    fill_edges(&m->we, sc->edges);
    wc_self_boxes(m, sc->edges, sc->n_edges, NULL, m->rest_pos, thickness, sc->tri_box, sc->edge_box);
    wc_status st = wc_bvh_build(&sc->tri_bvh, sc->tri_box, sc->n_tris, &A, diag);
    if (st == WC_OK) st = wc_bvh_build(&sc->edge_bvh, sc->edge_box, sc->n_edges, &A, diag);
    if (st == WC_OK) {
        sc->edge_max = WC_NEW(&A, int, (size_t)sc->edge_bvh.n_nodes + 1);
        sc->tri_mask = WC_NEW(&A, unsigned char, (size_t)sc->tri_bvh.n_nodes + 1);
        sc->edge_mask = WC_NEW(&A, unsigned char, (size_t)sc->edge_bvh.n_nodes + 1);
        sc->tri_grid.g = wc_self_grid_side(sc->n_tris);
        sc->edge_grid.g = wc_self_grid_side(sc->n_edges);
        sc->tri_grid.cell = WC_NEW(&A, unsigned char, (size_t)sc->tri_grid.g * sc->tri_grid.g * sc->tri_grid.g);
        sc->edge_grid.cell = WC_NEW(&A, unsigned char, (size_t)sc->edge_grid.g * sc->edge_grid.g * sc->edge_grid.g);
        if (st == WC_OK) st = wc_bvh_split_build(&sc->tri_split, &sc->tri_bvh, WC_SELF_SPLIT_DEPTH, &A);
        if (st == WC_OK) st = wc_bvh_split_build(&sc->edge_split, &sc->edge_bvh, WC_SELF_SPLIT_DEPTH, &A);
        if (st != WC_OK) st = wc_fail(diag, WC_ERROR_OUT_OF_MEMORY, "self-collision: out of memory");
        else if (!sc->edge_max || !sc->tri_mask || !sc->edge_mask || !sc->tri_grid.cell || !sc->edge_grid.cell)
            st = wc_fail(diag, WC_ERROR_OUT_OF_MEMORY, "self-collision: out of memory");
    }
    if (st != WC_OK) {
        wc_self_destroy(sc);
        return st;
    }
    /* children follow their parent (preorder): one backward sweep gives every subtree's maximum */
    for (int k = sc->edge_bvh.n_nodes - 1; k >= 0; --k) {
        const int* ch = sc->edge_bvh.child + 2 * k;
        sc->edge_max[k] = ch[0] < 0 ? ch[1] : (sc->edge_max[ch[0]] > sc->edge_max[ch[1]] ? sc->edge_max[ch[0]] : sc->edge_max[ch[1]]);
    }
    sc->tangled_pairs = mark_tangled(sc, m);
    memcpy(sc->x_start, m->rest_pos, 3 * (size_t)n * sizeof(double));
    *out = sc;
    return WC_OK;
}

void wc_self_begin(wc_self* sc, const double* x) { memcpy(sc->x_start, x, 3 * (size_t)sc->n * sizeof(double)); }

int wc_self_resolve(wc_self* sc, const wc_model* m, const wc_filter* filter, const unsigned char* stick, double he,
                    double* x, double* v, wc_self_stats* st) {
    int n = sc->n;
    if (sc->n_tris == 0) return 0;
    for (int i = 0; i < n; ++i) {
        int pinned = filter && filter->ndof[i] == 3 && !(stick && stick[i]);
        sc->inv_mass[i] = pinned ? 0.0 : m->inv_mass[i];
    }
    memcpy(sc->x_old, x, 3 * (size_t)n * sizeof(double));
    wc_self_stats local = {0, 0, 0, 0, 0};
    /* a pass that moved something (its trees were refitted before the moves, and pairs it checked
       early may have been moved later) proves nothing: only a pass that moved nothing shows the
       substep free of collisions; after WC_SELF_PASSES, the zone loop's detection passes decide.
       The first pass checks every pair; every later one only the pairs with a dirty particle: one
       of a pair that an earlier pass acted on or counted (touch), a zone's member, or one the
       relaxation moved. A pair with no dirty particle has not moved since a pass found it
       needing nothing, so it still needs nothing (tests compare both ways: detect_all). */
    unsigned char *dirty = sc->dirty, *touched = sc->dirty_next;
    memset(touched, 0, (size_t)n);
    local.impacts = wc_self_pass(sc, m, x, WC_SELF_PASS_PROXIMITY, &local.proximity, NULL, touched);
    int left = local.impacts + local.proximity;
    for (int p = 1; p < sc->passes && left; ++p) {
        unsigned char* tmp = dirty; /* this pass's dirty set: the last pass's touched particles */
        dirty = touched;
        touched = tmp;
        memset(touched, 0, (size_t)n);
        sc->refit_dirty = p > 1; /* the first impulse pass's r is not the proximity pass's */
        left = wc_self_pass(sc, m, x, WC_SELF_PASS_IMPULSE, NULL, sc->detect_all ? NULL : dirty, touched);
        local.impacts += left;
    }
    if (left) {
        for (int i = 0; i < n; ++i) {
            sc->parent[i] = i;
            sc->in_zone[i] = 0;
        }
        /* the zone loop's dirty sets: for its first pass the last pass's touched particles, then
           for each later one the particles moved (or joined to a zone) since the pass before it:
           every zone member (re-placed by its zone's rigid motion) and every particle the
           relaxation moved. A pair with none of them has not moved since that pass, which either
           checked it and found it needing nothing (a pair it found colliding joined a zone), or
           skipped it as unmoved since an earlier pass that did; zones only grow, so it still
           needs nothing */
        dirty = touched;
        int it = 0;
        for (; it < WC_SELF_ZONE_ITERS; ++it) {
            /* the dirty set holds every particle moved since the last pass (its touched ones, the
               zones' members, the relaxed ones): the pass refits only their elements, unless the
               last pass was the proximity pass (another r) */
            sc->refit_dirty = it > 0 || sc->passes > 1;
            left = wc_self_pass(sc, m, x, WC_SELF_PASS_DETECT, NULL, sc->detect_all ? NULL : dirty, NULL);
            if (left == 0) break;
            wc_self_rigidify(n, sc->x_start, x, m->mass, sc->inv_mass, sc->parent, sc->in_zone, sc->zone);
            for (int i = 0; i < n; ++i) dirty[i] = sc->in_zone[i];
            if (!(sc->zone_strain < INFINITY)) continue;
            if (sc->relax_all || !m->pattern.row_spring_start) {
                local.relaxed += wc_self_relax_zones(m, sc->x_old, x, sc->in_zone, sc->inv_mass, sc->zone_strain,
                                                     WC_SELF_RELAX_PASSES, dirty);
                continue;
            }
            /* the first relaxation checks every spring (the impulses moved particles anywhere, and
               a spring at its x_old strain may read a rounding over it); each later one the
               springs the last one left due and those of the zones' members, the only particles
               moved (or given in[] = 1) since */
            if (it == 0) {
                int n_stretch = m->spring_type_start[WC_SPRING_STRETCH + 1] - m->spring_type_start[WC_SPRING_STRETCH];
                memset(sc->relax.due, 0xff, (size_t)sc->relax.words * sizeof(uint64_t));
                if (n_stretch & 63) sc->relax.due[sc->relax.words - 1] = ((uint64_t)1 << (n_stretch & 63)) - 1;
            } else
                for (int i = 0; i < n; ++i)
                    if (sc->in_zone[i]) wc_self_relax_mark(m, &sc->relax, i);
            local.relaxed += wc_self_relax_zones_due(m, sc->x_old, x, sc->in_zone, sc->inv_mass, sc->zone_strain,
                                                     WC_SELF_RELAX_PASSES, dirty, &sc->relax);
        }
        if (it == WC_SELF_ZONE_ITERS) local.unresolved = wc_self_pass(sc, m, x, WC_SELF_PASS_DETECT, NULL, NULL, NULL);
        for (int i = 0; i < n; ++i)
            if (sc->in_zone[i] && wc_uf_find(sc->parent, i) == i) ++local.zones;
    }
    for (int k = 0; k < 3 * n; ++k) v[k] += (x[k] - sc->x_old[k]) / he;
    if (st) {
        st->proximity += local.proximity;
        st->impacts += local.impacts;
        st->zones += local.zones;
        st->unresolved += local.unresolved;
        st->relaxed += local.relaxed;
    }
    return local.unresolved;
}
