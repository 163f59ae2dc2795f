/* Reading a host's mesh description (mesh_desc.h). */
#include "mesh_desc.h"
#include <string.h>

wc_status wc_mesh_desc_read(const wc_mesh_desc* desc, wc_source_mesh* out, const wc_allocator* alloc, wc_diag* d) {
    memset(out, 0, sizeof *out);
    if (desc->path) {
        wc_import_opts o = wc_default_import_opts();
        o.scale = desc->unit_scale;
        o.select = desc->select;
        return wc_import_file(out, alloc, desc->path, &o, d);
    }
    int n = desc->n_vertices, nf = desc->n_faces;
    double* pos = WC_NEW(alloc, double, 3 * (size_t)n);
    int* triangles = desc->face_sizes ? NULL : WC_NEW(alloc, int, (size_t)nf);
    const int* sizes = desc->face_sizes ? desc->face_sizes : triangles;
    wc_status st = WC_ERROR_OUT_OF_MEMORY;
    if (pos && sizes) {
        for (int i = 0; i < 3 * n; ++i) pos[i] = (double)desc->positions[i];
        for (int f = 0; triangles && f < nf; ++f) triangles[f] = 3;
        st = wc_source_mesh_from_arrays(out, alloc, pos, n, sizes, nf, desc->indices, desc->unit_scale, d);
    } else {
        wc_fail(d, st, "out of memory (%d vertices)", n);
    }
    wc_free(alloc, pos);
    wc_free(alloc, triangles);
    return st;
}
