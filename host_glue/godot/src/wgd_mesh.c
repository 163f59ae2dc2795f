/* Godot mesh surfaces as Weft host arrays (wgd_mesh.h). */
#include "wgd_mesh.h"

#include <stdlib.h>

int wgd_mesh_surface(godot_object* mesh, int surface, godot_array* arrays) {
    godot_variant zero;
    gd->godot_variant_new_int(&zero, surface);
    const godot_variant* args[1] = {&zero};
    godot_variant av = gd_call(mesh, "surface_get_arrays", 1, args, NULL);
    *arrays = gd->godot_variant_as_array(&av);
    gd->godot_variant_destroy(&av);
    gd->godot_variant_destroy(&zero);
    return gd->godot_array_size(arrays) > WGD_ARRAY_INDEX;
}

int wgd_mesh_triangles(const godot_array* arrays, const float scale[3], float** pos, int* n_vertices, int** tris,
                       int* n_tris) {
    *pos = NULL;
    *tris = NULL;
    *n_vertices = *n_tris = 0;
    if (gd->godot_array_size(arrays) <= WGD_ARRAY_INDEX) return 0;
    godot_variant vv = gd->godot_array_get(arrays, WGD_ARRAY_VERTEX);
    godot_pool_vector3_array verts = gd->godot_variant_as_pool_vector3_array(&vv);
    godot_variant iv = gd->godot_array_get(arrays, WGD_ARRAY_INDEX);
    godot_pool_int_array idx = gd->godot_variant_as_pool_int_array(&iv);
    int n = (int)gd->godot_pool_vector3_array_size(&verts);
    int ni = (int)gd->godot_pool_int_array_size(&idx);
    int nt = ni > 0 ? ni / 3 : n / 3;
    *pos = malloc((size_t)(n > 0 ? n : 1) * 3 * sizeof(float));
    *tris = malloc((size_t)(nt > 0 ? nt : 1) * 3 * sizeof(int));
    if (*pos && *tris) {
        godot_pool_vector3_array_read_access* r = gd->godot_pool_vector3_array_read(&verts);
        const float* v = (const float*)gd->godot_pool_vector3_array_read_access_ptr(r);
        for (int i = 0; i < n; i++) {
            for (int k = 0; k < 3; k++) (*pos)[3 * i + k] = v[3 * i + k] * scale[k];
        }
        gd->godot_pool_vector3_array_read_access_destroy(r);
        godot_pool_int_array_read_access* ir = gd->godot_pool_int_array_read(&idx);
        const godot_int* ip = gd->godot_pool_int_array_read_access_ptr(ir);
        for (int t = 0; t < nt; t++) {
            int a = ni > 0 ? ip[3 * t] : 3 * t, b = ni > 0 ? ip[3 * t + 1] : 3 * t + 1;
            int d = ni > 0 ? ip[3 * t + 2] : 3 * t + 2;
            (*tris)[3 * t] = a;
            (*tris)[3 * t + 1] = d;
            (*tris)[3 * t + 2] = b;
        }
        gd->godot_pool_int_array_read_access_destroy(ir);
    }
    gd->godot_pool_int_array_destroy(&idx);
    gd->godot_variant_destroy(&iv);
    gd->godot_pool_vector3_array_destroy(&verts);
    gd->godot_variant_destroy(&vv);
    *n_vertices = n;
    *n_tris = nt;
    return *pos && *tris && n > 0 && nt > 0;
}
