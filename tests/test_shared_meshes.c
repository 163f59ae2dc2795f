/* Imports every mesh in ../shared/meshes (when present) and checks the counts against the
 * independent figures in its MANIFEST.tsv: vertices (distinct positions: the model is welded at
 * exact positions here), faces, face kind, and where the notes state them, boundary edges,
 * components, zero-area triangles and duplicate positions. Exit 77 (ctest: skipped) when the
 * folder is absent: the suite must pass without ../shared. */
#define _POSIX_C_SOURCE 200809L
#include <ctype.h>
#include <stdlib.h>
#include <strings.h>
#include "check.h"
#include "model.h"
#include "source_mesh.h"

/* The number written just before `phrase` in text ("119 boundary edges"), or -1. */
static long number_before(const char* text, const char* phrase) {
    const char* hit = strstr(text, phrase);
    if (!hit) return -1;
    const char* p = hit;
    while (p > text && isdigit((unsigned char)p[-1])) --p;
    return p == hit ? -1 : strtol(p, NULL, 10);
}

static int contains_ci(const char* text, const char* word) {
    size_t n = strlen(word);
    for (const char* p = text; *p; ++p)
        if (strncasecmp(p, word, n) == 0) return 1;
    return 0;
}

static void check_row(const char* dir, char** col) {
    const char* file = col[0];
    long verts = strtol(col[5], NULL, 10), faces = strtol(col[6], NULL, 10);
    const char* notes = col[7];
    char path[2048];
    snprintf(path, sizeof path, "%s/%s", dir, file);
    wc_source_mesh src;
    wc_diag d = {0};
    wc_import_opts o = wc_default_import_opts();
    wc_status st = wc_import_file(&src, NULL, path, &o, &d);
    if (st != WC_OK) fprintf(stderr, "%s: %s\n", file, d.message);
    CHECK_EQ_INT(st, WC_OK);
    if (st != WC_OK) return;
    wc_model m;
    wc_model_def def = wc_default_model_def();
    def.weld_tolerance = 1e-12; /* exact positions: the manifest counts distinct positions */
    st = wc_model_build(&m, &src, &def, NULL, &d);
    CHECK_EQ_INT(st, WC_OK);
    if (st != WC_OK) {
        wc_source_mesh_free(&src);
        return;
    }
    const wc_import_report* r = &m.report;
    long dup = number_before(notes, " duplicate positions");
    long poly_total = 0;
    for (int k = 3; k <= WC_MAX_POLY_SIDES; ++k) poly_total += r->polygons[k];
    printf("  %-48s particles %5d (manifest %ld%s) faces %5ld (%ld) boundary %4d components %3d\n", file,
           r->particles, verts - (dup > 0 ? dup : 0), dup > 0 ? " after duplicates" : "", poly_total, faces,
           r->boundary_edges, r->components);
    CHECK_EQ_INT(r->particles, verts - (dup > 0 ? dup : 0));
    CHECK_EQ_INT(poly_total, faces);
    if (contains_ci(notes, "quad")) CHECK_EQ_INT(r->polygons[4], faces);
    else if (strstr(notes, "tris")) CHECK_EQ_INT(r->polygons[3], faces);
    long zero_area = number_before(notes, " zero-area tris");
    if (zero_area >= 0) CHECK_EQ_INT(r->degenerate_triangles, zero_area);
    /* the notes' topology figures count raw OBJ indices; they equal ours when positions are not
       repeated (welding merges repeated positions) */
    if (dup <= 0) {
        long boundary = number_before(notes, " boundary edges");
        if (boundary >= 0) CHECK_EQ_INT(r->boundary_edges, boundary);
        long comps = number_before(notes, " component");
        if (comps >= 0) CHECK_EQ_INT(r->components, comps);
    }
    CHECK_EQ_INT(r->non_orientable_components, 0);
    wc_model_free(&m);
    wc_source_mesh_free(&src);
}

int main(void) {
    char manifest[2048];
    snprintf(manifest, sizeof manifest, "%s/MANIFEST.tsv", WEFT_SHARED_MESHES);
    FILE* f = fopen(manifest, "r");
    if (!f) {
        printf("skipped: %s not present (the suite does not need ../shared)\n", manifest);
        return 77;
    }
    char line[8192];
    int rows = 0;
    if (!fgets(line, sizeof line, f)) line[0] = 0; /* header */
    while (fgets(line, sizeof line, f)) {
        char* col[11] = {0};
        int n = 0;
        for (char* p = line; n < 11 && p; ++n) {
            col[n] = p;
            p = strchr(p, '\t');
            if (p) *p++ = 0;
        }
        if (n < 8 || !isdigit((unsigned char)col[5][0])) continue; /* companion files (.mtl) */
        check_row(WEFT_SHARED_MESHES, col);
        ++rows;
    }
    fclose(f);
    CHECK(rows >= 1);
    printf("%d manifest rows checked\n", rows);
    return TEST_SUMMARY();
}
