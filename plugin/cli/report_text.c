/* The import report as aligned text. */
#include "report.h"

static void row_int(FILE* out, const char* label, int value) {
    fprintf(out, "  %-26s %d\n", label, value);
}

static void row_vec(FILE* out, const char* label, const double v[3]) {
    fprintf(out, "  %-26s %.6g  %.6g  %.6g\n", label, v[0], v[1], v[2]);
}

void cli_report_text(FILE* out, const char* file, const weft_import_report* r) {
    static const char* const side_names[WEFT_REPORT_POLYGON_SIDES + 1] = {
        NULL, NULL, NULL, "triangles", "quads", "pentagons", "hexagons", "heptagons", "8+ sides"};
    int n_polys = 0;
    for (int k = 3; k <= WEFT_REPORT_POLYGON_SIDES; ++k) n_polys += r->polygons[k];
    const double size[3] = {r->bbox_max[0] - r->bbox_min[0], r->bbox_max[1] - r->bbox_min[1],
                            r->bbox_max[2] - r->bbox_min[2]};

    fprintf(out, "%s\n", file);
    fputs("source\n", out);
    fprintf(out, "  %-26s %.9g\n", "unit scale (m per unit)", r->unit_scale);
    row_int(out, "vertices", r->source_vertices);
    row_int(out, "  unused", r->unused_vertices);
    row_int(out, "  welded", r->welded_vertices);
    row_int(out, "polygons", n_polys);
    for (int k = 3; k <= WEFT_REPORT_POLYGON_SIDES; ++k)
        if (r->polygons[k]) {
            char label[32];
            snprintf(label, sizeof label, "  %s", side_names[k]);
            row_int(out, label, r->polygons[k]);
        }
    row_int(out, "points (ignored)", r->polygons[1]);
    row_int(out, "lines (ignored)", r->polygons[2]);

    fputs("model\n", out);
    fprintf(out, "  %-26s %.6g\n", "weld distance (m)", r->weld_distance);
    row_int(out, "particles", r->particles);
    row_int(out, "triangles", r->triangles);
    row_int(out, "  degenerate (dropped)", r->degenerate_triangles);
    row_int(out, "  duplicate (dropped)", r->duplicate_faces);
    row_int(out, "  flipped (rewound)", r->flipped_faces);
    row_int(out, "edges", r->edges);
    row_int(out, "  boundary", r->boundary_edges);
    row_int(out, "  non-manifold", r->non_manifold_edges);
    row_int(out, "boundary loops", r->boundary_loops);
    row_int(out, "components", r->components);
    row_int(out, "  non-orientable", r->non_orientable_components);
    row_int(out, "seams", r->seams);
    row_int(out, "panels after sewing", r->panels);
    row_vec(out, "bbox min (m)", r->bbox_min);
    row_vec(out, "bbox max (m)", r->bbox_max);
    row_vec(out, "size (m)", size);

    fputs("springs\n", out);
    row_int(out, "stretch", r->springs[WEFT_SPRING_STRETCH]);
    row_int(out, "shear", r->springs[WEFT_SPRING_SHEAR]);
    row_int(out, "bend", r->springs[WEFT_SPRING_BEND]);
    row_int(out, "seam", r->springs[3]);

    if (r->n_warnings == 0) {
        fputs("warnings: none\n", out);
        return;
    }
    fprintf(out, "warnings: %d\n", r->n_warnings + r->warnings_dropped);
    for (int i = 0; i < r->n_warnings && i < WEFT_REPORT_MAX_WARNINGS; ++i)
        fprintf(out, "  - %s\n", r->warnings[i]);
    if (r->warnings_dropped) fprintf(out, "  (%d more not listed)\n", r->warnings_dropped);
}
