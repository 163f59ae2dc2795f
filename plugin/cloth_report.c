/* weft_cloth_get_report: the model's import report (core/model.h's wc_import_report, kept with
 * the model since weft_cloth_create) in the ABI's layout. */
#include <stdio.h>
#include <string.h>
#include "api_internal.h"
#include "call_guard.h"

_Static_assert(WEFT_REPORT_POLYGON_SIDES == WC_MAX_POLY_SIDES, "polygon histogram sizes differ");
_Static_assert(WEFT_REPORT_MAX_WARNINGS == WC_MAX_WARNINGS, "warning counts differ");
_Static_assert(WC_SPRING_TYPE_COUNT == 4, "the report lists four spring types");

weft_status weft_cloth_get_report(weft_context* ctx, weft_cloth cloth, weft_import_report* out) {
    WA_CALL_GUARD(ctx);   /* threading contract: refused if another thread is inside (call_guard.h) */
    static const char fn[] = "weft_cloth_get_report";
    if (!ctx) return WEFT_ERROR_INVALID_ARGUMENT;
    wc_cloth* c = wa_lookup(ctx, cloth, fn);
    if (!c) return WEFT_ERROR_INVALID_HANDLE;
    if (!out) return wa_fail(ctx, WEFT_ERROR_INVALID_ARGUMENT, "%s: out is NULL", fn);
    const wc_import_report* r = &c->model.report;
    weft_import_report o;
    memset(&o, 0, sizeof o);
    o.source_vertices = r->source_vertices;
    o.unused_vertices = r->unused_vertices;
    o.welded_vertices = r->welded_vertices;
    o.particles = r->particles;
    for (int k = 1; k <= WC_MAX_POLY_SIDES; ++k) o.polygons[k] = r->polygons[k];
    o.triangles = r->triangles;
    o.degenerate_triangles = r->degenerate_triangles;
    o.duplicate_faces = r->duplicate_faces;
    o.flipped_faces = r->flipped_faces;
    o.non_orientable_components = r->non_orientable_components;
    o.edges = r->edges;
    o.boundary_edges = r->boundary_edges;
    o.non_manifold_edges = r->non_manifold_edges;
    o.boundary_loops = r->boundary_loops;
    o.components = r->components;
    for (int t = 0; t < WC_SPRING_TYPE_COUNT; ++t) o.springs[t] = r->springs[t];   /* WEFT_SPRING_* order, seam last */
    o.seams = r->seams;
    o.panels = r->panels;
    for (int k = 0; k < 3; ++k) {
        o.bbox_min[k] = r->bbox_min[k];
        o.bbox_max[k] = r->bbox_max[k];
    }
    o.unit_scale = r->unit_scale;
    o.weld_distance = r->weld_distance;
    o.ms_weld = r->ms.weld;
    o.ms_triangulate = r->ms.triangulate;
    o.ms_clean = r->ms.clean;
    o.ms_orient = r->ms.orient;
    o.ms_topology = r->ms.topology;
    o.ms_springs = r->ms.springs;
    o.ms_pattern = r->ms.pattern;
    o.ms_total = r->ms.total;
    o.n_warnings = r->n_warnings < WC_MAX_WARNINGS ? r->n_warnings : WC_MAX_WARNINGS;
    o.warnings_dropped = r->warnings_dropped;
    for (int k = 0; k < o.n_warnings; ++k) snprintf(o.warnings[k], sizeof o.warnings[k], "%s", r->warnings[k]);
    *out = o;
    return wa_ok(ctx);
}
