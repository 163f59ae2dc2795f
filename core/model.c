/* Model construction: weld -> triangulate -> drop bad triangles -> orient -> compact particles
 * -> winged edge -> springs -> masses, with every oddity counted in the import report. */
#include "model.h"
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>
#include "clock.h"
#include "ordering.h"
#include "springs.h"
#include "topology.h"
#include "triangulate.h"
#include "weld.h"

wc_material wc_default_material(void) {
    wc_material m;
    memset(&m, 0, sizeof m);
    m.density = 0.15;                      /* kg/m^2, a medium cotton */
    m.k[WC_SPRING_STRETCH] = 5000.0;       /* N/m */
    m.k[WC_SPRING_SHEAR] = 500.0;
    m.k[WC_SPRING_BEND] = 50.0;
    m.d[WC_SPRING_STRETCH] = 2.0;          /* N s/m */
    m.d[WC_SPRING_SHEAR] = 0.5;
    m.d[WC_SPRING_BEND] = 0.05;
    m.k[WC_SPRING_SEAM] = 5000.0;          /* sewing: as stiff as stretch */
    m.d[WC_SPRING_SEAM] = 2.0;
    m.uniform_mass = 0.0;
    return m;
}

wc_model_def wc_default_model_def(void) {
    wc_model_def d;
    memset(&d, 0, sizeof d);
    d.weld_tolerance = 1e-6;
    d.degenerate_area = 1e-14;
    d.bend_min_angle_deg = 150.0;
    d.reorder = 1;
    d.material = wc_default_material();
    d.seam_close_time = 0.5;
    return d;
}

void wc_report_warn(wc_import_report* r, const char* fmt, ...) {
    if (r->n_warnings >= WC_MAX_WARNINGS) {
        ++r->warnings_dropped;
        return;
    }
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(r->warnings[r->n_warnings], sizeof r->warnings[0], fmt, ap);
    va_end(ap);
    ++r->n_warnings;
}

void wc_model_free(wc_model* m) {
    if (!m) return;
    wc_allocator a = m->alloc;
    wc_free(&a, m->rest_pos);
    wc_free(&a, m->mass);
    wc_free(&a, m->inv_mass);
    wc_free(&a, m->tris);
    wc_free(&a, m->tri_poly);
    wc_free(&a, m->tri_quad);
    wc_free(&a, m->tri_rest_area);
    wc_winged_edge_free(&m->we, &a);
    wc_bsr_pattern_free(&m->pattern, &a);
    wc_free(&a, m->springs);
    wc_free(&a, m->seams);
    wc_free(&a, m->host_to_particle);
    wc_free(&a, m->particle_to_host);
    wc_free(&a, m->particle_component);
    memset(m, 0, sizeof *m);
}

/* Scratch arrays of the build, freed together. */
typedef struct build_tmp {
    unsigned char* used;
    int* weld_map;     /* host -> welded particle (before compaction) */
    double* wpos;      /* welded particle positions */
    int* tris;         /* triangles over welded particles */
    unsigned char* mask;
    int* tri_poly;
    unsigned char* keep;
    int* remap;        /* welded particle -> final particle */
    int* quads;
    int* scratch;
    wc_keyed* sides;   /* triangle sides sorted by vertex pair (orientation, winged edge) */
} build_tmp;

static void tmp_free(build_tmp* t, const wc_allocator* a) {
    wc_free(a, t->used);
    wc_free(a, t->weld_map);
    wc_free(a, t->wpos);
    wc_free(a, t->tris);
    wc_free(a, t->mask);
    wc_free(a, t->tri_poly);
    wc_free(a, t->keep);
    wc_free(a, t->remap);
    wc_free(a, t->quads);
    wc_free(a, t->scratch);
    wc_free(a, t->sides);
}

static wc_status validate_def(const wc_model_def* d, wc_diag* diag) {
    if (!(d->weld_tolerance >= 0.0) || !isfinite(d->weld_tolerance))
        return wc_fail(diag, WC_ERROR_INVALID_ARGUMENT, "weld_tolerance must be finite and >= 0 (got %g)", d->weld_tolerance);
    if (!(d->degenerate_area >= 0.0) || !isfinite(d->degenerate_area))
        return wc_fail(diag, WC_ERROR_INVALID_ARGUMENT, "degenerate_area must be finite and >= 0 (got %g)", d->degenerate_area);
    if (!(d->bend_min_angle_deg >= 90.0 && d->bend_min_angle_deg <= 180.0))
        return wc_fail(diag, WC_ERROR_INVALID_ARGUMENT, "bend_min_angle_deg must be in [90, 180] (got %g)", d->bend_min_angle_deg);
    const wc_material* m = &d->material;
    if (!(m->density > 0.0) || !isfinite(m->density))
        return wc_fail(diag, WC_ERROR_INVALID_ARGUMENT, "material density must be finite and > 0 (got %g)", m->density);
    if (!(m->uniform_mass >= 0.0) || !isfinite(m->uniform_mass))
        return wc_fail(diag, WC_ERROR_INVALID_ARGUMENT, "material uniform_mass must be finite and >= 0 (got %g)", m->uniform_mass);
    for (int t = 0; t < WC_SPRING_TYPE_COUNT; ++t)
        if (!(m->k[t] >= 0.0) || !isfinite(m->k[t]) || !(m->d[t] >= 0.0) || !isfinite(m->d[t]))
            return wc_fail(diag, WC_ERROR_INVALID_ARGUMENT, "material k and d must be finite and >= 0 (spring type %d)", t);
    if (!(d->sew_distance >= 0.0) || !isfinite(d->sew_distance))
        return wc_fail(diag, WC_ERROR_INVALID_ARGUMENT, "sew_distance must be finite and >= 0 (got %g)", d->sew_distance);
    if (!(d->seam_close_time >= 0.0) || !isfinite(d->seam_close_time))
        return wc_fail(diag, WC_ERROR_INVALID_ARGUMENT, "seam_close_time must be finite and >= 0 (got %g)",
                       d->seam_close_time);
    if (d->n_seam_pairs < 0)
        return wc_fail(diag, WC_ERROR_INVALID_ARGUMENT, "seam pair count must be >= 0 (got %d)", d->n_seam_pairs);
    if (d->n_seam_pairs > 0 && (!d->seam_a || !d->seam_b))
        return wc_fail(diag, WC_ERROR_INVALID_ARGUMENT, "%d seam pairs but seam_a or seam_b is NULL", d->n_seam_pairs);
    return WC_OK;
}

wc_status wc_model_build(wc_model* out, const wc_source_mesh* src, const wc_model_def* def,
                           const wc_allocator* alloc, wc_diag* diag) {
    if (!out) return wc_fail(diag, WC_ERROR_INVALID_ARGUMENT, "model build: out is NULL");
    memset(out, 0, sizeof *out);
    if (!src || !def) return wc_fail(diag, WC_ERROR_INVALID_ARGUMENT, "model build: NULL source or def");
    wc_status st = validate_def(def, diag);
    if (st != WC_OK) return st;
    if (src->n_verts <= 0 || src->n_polys <= 0)
        return wc_fail(diag, WC_ERROR_EMPTY_MESH, "mesh has no polygons (%d vertices, %d polygons)", src->n_verts, src->n_polys);
    for (int i = 0; i < def->n_seam_pairs; ++i) {
        int a = def->seam_a[i], b = def->seam_b[i];
        if (a < 0 || a >= src->n_verts || b < 0 || b >= src->n_verts)
            return wc_fail(diag, WC_ERROR_OUT_OF_RANGE, "seam %d: vertex pair (%d, %d) outside the mesh's %d vertices",
                           i, a, b, src->n_verts);
        if (a == b) return wc_fail(diag, WC_ERROR_INVALID_ARGUMENT, "seam %d sews vertex %d to itself", i, a);
    }

    wc_model* m = out;
    wc_import_report* r = &m->report;
    const double t_start = wc_now_ms();
    double t_mark = t_start;
#define STAGE_DONE(field)            \
    do {                             \
        double now_ = wc_now_ms();   \
        r->ms.field = now_ - t_mark; \
        t_mark = now_;               \
    } while (0)
    if (alloc) m->alloc = *alloc;
    const wc_allocator* A = &m->alloc;
    build_tmp t;
    memset(&t, 0, sizeof t);
    const int nh = src->n_verts, npoly = src->n_polys;
    const int n_corners = src->poly_start[npoly];
    int max_sides = 3, n_tri0 = 0;
    for (int p = 0; p < npoly; ++p) {
        int k = src->poly_start[p + 1] - src->poly_start[p];
        if (k > max_sides) max_sides = k;
        n_tri0 += k - 2;
        ++r->polygons[k < WC_MAX_POLY_SIDES ? k : WC_MAX_POLY_SIDES];
    }
    r->polygons[1] = src->n_points;
    r->polygons[2] = src->n_lines;
    r->source_vertices = nh;
    r->unit_scale = src->unit_scale;

    t.used = WC_NEW(A, unsigned char, nh);
    t.weld_map = WC_NEW(A, int, nh);
    t.wpos = WC_NEW(A, double, 3 * (size_t)nh);
    t.tris = WC_NEW(A, int, 3 * (size_t)n_tri0);
    t.mask = WC_NEW(A, unsigned char, n_tri0);
    t.tri_poly = WC_NEW(A, int, n_tri0);
    t.keep = WC_NEW(A, unsigned char, n_tri0);
    t.remap = WC_NEW(A, int, nh);
    t.quads = WC_NEW(A, int, 4 * (size_t)(r->polygons[4] + 1));
    t.scratch = WC_NEW(A, int, 2 * (size_t)max_sides);
    if (!t.used || !t.weld_map || !t.wpos || !t.tris || !t.mask || !t.tri_poly || !t.keep || !t.remap ||
        !t.quads || !t.scratch)
        goto oom;

    /* 1. weld the vertices that polygons use, by position */
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int i = 0; i < n_corners; ++i) t.used[src->poly_verts[i]] = 1;
    for (int v = 0; v < nh; ++v) {
        if (!t.used[v]) continue;
        for (int k = 0; k < 3; ++k) {
            if (src->pos[3 * v + k] < lo[k]) lo[k] = src->pos[3 * v + k];
            if (src->pos[3 * v + k] > hi[k]) hi[k] = src->pos[3 * v + k];
        }
    }
    double diag2 = 0;
    for (int k = 0; k < 3; ++k) diag2 += (hi[k] - lo[k]) * (hi[k] - lo[k]);
    r->weld_distance = def->weld_tolerance * sqrt(diag2);
    int nw = wc_weld(src->pos, t.used, nh, r->weld_distance, t.weld_map, A);
    if (nw < 0) goto oom;
    for (int v = nh - 1; v >= 0; --v) /* first host vertex of each particle wins */
        if (t.weld_map[v] >= 0) memcpy(t.wpos + 3 * t.weld_map[v], src->pos + 3 * v, 3 * sizeof(double));

    STAGE_DONE(weld);

    /* 2. triangulate the polygons over welded particles */
    int nt = 0, nq = 0;
    for (int p = 0; p < npoly; ++p) {
        int s = src->poly_start[p], k = src->poly_start[p + 1] - s;
        int* corners = t.scratch + max_sides;
        for (int i = 0; i < k; ++i) corners[i] = t.weld_map[src->poly_verts[s + i]];
        int made = wc_triangulate_polygon(corners, k, t.wpos, t.tris + 3 * nt, t.mask + nt, t.scratch);
        for (int i = 0; i < made; ++i) t.tri_poly[nt + i] = p;
        nt += made;
    }

    STAGE_DONE(triangulate);

    /* 3. drop degenerate and duplicate triangles, then compact */
    if (!wc_flag_bad_triangles(t.tris, nt, t.wpos, def->degenerate_area * diag2, t.keep,
                               &r->degenerate_triangles, &r->duplicate_faces, A))
        goto oom;
    int kept = 0;
    for (int i = 0; i < nt; ++i) {
        if (!t.keep[i]) continue;
        memmove(t.tris + 3 * kept, t.tris + 3 * i, 3 * sizeof(int));
        t.mask[kept] = t.mask[i];
        t.tri_poly[kept] = t.tri_poly[i];
        ++kept;
    }
    nt = kept;
    if (nt == 0) {
        tmp_free(&t, A);
        memset(out, 0, sizeof *out);
        return wc_fail(diag, WC_ERROR_EMPTY_MESH,
                       "mesh has no usable triangles (%d polygons, all degenerate or duplicate)", npoly);
    }

    STAGE_DONE(clean);

    /* 4. consistent winding per component */
    t.sides = wc_sorted_sides(nw, t.tris, nt, A);
    if (!t.sides ||
        !wc_orient_triangles(t.tris, t.mask, nt, t.sides, &r->flipped_faces, &r->non_orientable_components, A))
        goto oom;

    STAGE_DONE(orient);

    /* 5. particles = welded vertices that a kept triangle uses, in host order, then (by default)
       renumbered by reverse Cuthill-McKee */
    for (int v = 0; v < nw; ++v) t.remap[v] = -1;
    for (int i = 0; i < 3 * nt; ++i) t.remap[t.tris[i]] = 0;
    int np = 0;
    for (int v = 0; v < nw; ++v)
        if (t.remap[v] == 0) t.remap[v] = np++;
    for (int i = 0; i < 3 * nt; ++i) t.tris[i] = t.remap[t.tris[i]];
    if (def->reorder) { /* renumber for locality: reverse Cuthill-McKee */
        int* order = WC_NEW(A, int, (size_t)np + 1);
        if (!order || wc_order_rcm(np, t.tris, nt, order, A) != 0) {
            wc_free(A, order);
            goto oom;
        }
        for (int v = 0; v < nw; ++v)
            if (t.remap[v] >= 0) t.remap[v] = order[t.remap[v]];
        for (int i = 0; i < 3 * nt; ++i) t.tris[i] = order[t.tris[i]];
        wc_free(A, order);
    }
    for (int p = 0; p < npoly; ++p) { /* surviving quads with four distinct particles */
        int s = src->poly_start[p];
        if (src->poly_start[p + 1] - s != 4) continue;
        int q[4], ok = 1;
        for (int i = 0; i < 4; ++i) {
            int w = t.weld_map[src->poly_verts[s + i]];
            q[i] = t.remap[w];
            if (q[i] < 0) ok = 0;
        }
        for (int i = 0; i < 4 && ok; ++i)
            for (int j = i + 1; j < 4; ++j)
                if (q[i] == q[j]) ok = 0;
        if (ok) memcpy(t.quads + 4 * nq++, q, sizeof q);
    }

    m->n_particles = np;
    m->n_tris = nt;
    m->n_host_verts = nh;
    m->material = def->material;
    m->rest_pos = WC_NEW(A, double, 3 * (size_t)np);
    m->mass = WC_NEW(A, double, np);
    m->inv_mass = WC_NEW(A, double, np);
    m->tris = WC_NEW(A, int, 3 * (size_t)nt);
    m->tri_poly = WC_NEW(A, int, nt);
    m->tri_quad = WC_NEW(A, unsigned char, nt);
    m->tri_rest_area = WC_NEW(A, double, nt);
    m->host_to_particle = WC_NEW(A, int, nh);
    m->particle_to_host = WC_NEW(A, int, np);
    m->particle_component = WC_NEW(A, int, np);
    if (!m->rest_pos || !m->mass || !m->inv_mass || !m->tris || !m->tri_poly || !m->tri_quad ||
        !m->tri_rest_area || !m->host_to_particle || !m->particle_to_host || !m->particle_component)
        goto oom;
    for (int v = 0; v < nw; ++v)
        if (t.remap[v] >= 0) memcpy(m->rest_pos + 3 * t.remap[v], t.wpos + 3 * v, 3 * sizeof(double));
    for (int p = 0; p < np; ++p) m->particle_to_host[p] = -1;
    for (int v = 0; v < nh; ++v) {
        int w = t.weld_map[v];
        int p = w >= 0 ? t.remap[w] : -1;
        m->host_to_particle[v] = p;
        if (p < 0) ++r->unused_vertices;
        else if (m->particle_to_host[p] < 0) m->particle_to_host[p] = v;
        else ++r->welded_vertices;
    }
    memcpy(m->tris, t.tris, 3 * sizeof(int) * (size_t)nt);
    memcpy(m->tri_poly, t.tri_poly, sizeof(int) * (size_t)nt);
    for (int i = 0; i < nt; ++i) {
        int p = m->tri_poly[i];
        m->tri_quad[i] = (src->poly_start[p + 1] - src->poly_start[p]) == 4;
        m->tri_rest_area[i] = wc_triangle_area(m->rest_pos, m->tris + 3 * i);
    }

    /* 6. topology: components, winged edge, boundary loops */
    m->n_components = wc_components(np, m->tris, nt, m->particle_component, A);
    if (m->n_components < 0) goto oom;
    st = wc_winged_edge_build_sorted(&m->we, A, np, m->tris, nt, t.mask, t.sides, diag);
    if (st != WC_OK) goto fail;
    r->boundary_loops = wc_boundary_loops(&m->we, A);
    if (r->boundary_loops < 0) goto oom;
    for (int e = 0; e < m->we.n_edges; ++e) {
        const wc_we_edge* ed = &m->we.edges[e];
        if (ed->f[1] < 0) ++r->boundary_edges;
        if ((ed->flags & WC_EDGE_NON_MANIFOLD) && !wc_we_repeats_previous(&m->we, e)) ++r->non_manifold_edges;
    }

    STAGE_DONE(topology);

    /* 7. springs */
    wc_spring_input spring_in = {np, m->rest_pos, &m->we, m->tri_quad, nq, t.quads, def->bend_min_angle_deg};
    st = wc_build_springs(&spring_in, &m->springs, &m->n_springs, m->spring_type_start, A, diag);
    if (st != WC_OK) goto fail;
    /* 7a. seams: found, then appended as WC_SPRING_SEAM springs */
    st = wc_model_sew(m, def, diag);
    if (st != WC_OK) goto fail;
    STAGE_DONE(springs);

    /* 7b. block pattern of the implicit system and per-row lists */
    if (wc_bsr_pattern_build(&m->pattern, m, A) != 0) goto oom;
    STAGE_DONE(pattern);

    /* 8. lumped masses */
    for (int i = 0; i < nt; ++i)
        for (int k = 0; k < 3; ++k) m->mass[m->tris[3 * i + k]] += m->tri_rest_area[i] * def->material.density / 3.0;
    for (int p = 0; p < np; ++p) {
        if (def->material.uniform_mass > 0) m->mass[p] = def->material.uniform_mass;
        m->inv_mass[p] = 1.0 / m->mass[p];
    }

    /* 9. report */
    r->particles = np;
    r->triangles = nt;
    r->edges = m->we.n_edges;
    r->components = m->n_components;
    r->seams = m->n_seams;
    r->panels = m->n_panels;
    for (int ty = 0; ty < WC_SPRING_TYPE_COUNT; ++ty)
        r->springs[ty] = m->spring_type_start[ty + 1] - m->spring_type_start[ty];
    for (int k = 0; k < 3; ++k) {
        r->bbox_min[k] = INFINITY;
        r->bbox_max[k] = -INFINITY;
    }
    for (int p = 0; p < np; ++p)
        for (int k = 0; k < 3; ++k) {
            double x = m->rest_pos[3 * p + k];
            if (x < r->bbox_min[k]) r->bbox_min[k] = x;
            if (x > r->bbox_max[k]) r->bbox_max[k] = x;
        }
    if (r->polygons[1] || r->polygons[2])
        wc_report_warn(r, "%d point and %d line primitives ignored", r->polygons[1], r->polygons[2]);
    if (r->unused_vertices)
        wc_report_warn(r, "%d host vertices are in no kept triangle (unreferenced, or only in dropped "
                       "triangles): they map to no particle", r->unused_vertices);
    if (r->degenerate_triangles)
        wc_report_warn(r, "%d degenerate triangles (zero area or a repeated particle after welding) dropped",
                       r->degenerate_triangles);
    if (r->duplicate_faces)
        wc_report_warn(r, "%d duplicate faces (same three particles as an earlier face) dropped", r->duplicate_faces);
    if (r->flipped_faces)
        wc_report_warn(r, "%d triangles had inconsistent winding and were flipped (minority per component)",
                       r->flipped_faces);
    if (r->non_orientable_components)
        wc_report_warn(r, "%d components are non-orientable: winding is consistent only up to a seam",
                       r->non_orientable_components);
    if (r->non_manifold_edges)
        wc_report_warn(r, "%d non-manifold edges (vertex pair in more than two triangles): the first two "
                       "triangles share the edge, each further one gets its own copy, no shear spring across it",
                       r->non_manifold_edges);
    if (max_sides > 4)
        wc_report_warn(r, "polygons with up to %d sides were ear-clipped; their diagonals are not stretch springs",
                       max_sides);
    if (max_sides > WC_EAR_CLIP_MAX)
        wc_report_warn(r, "polygons with more than %d sides were fanned from their first corner (overlaps if "
                       "concave)", WC_EAR_CLIP_MAX);
    tmp_free(&t, A);
    r->ms.total = wc_now_ms() - t_start;
#undef STAGE_DONE
    return WC_OK;

oom:
    st = wc_fail(diag, WC_ERROR_OUT_OF_MEMORY, "model build: out of memory (%d vertices, %d polygons)", nh, npoly);
fail:
    tmp_free(&t, A);
    wc_model_free(m);
    return st;
}
