/* WeftCloth's mesh in and out: every surface of the node's mesh joined into one cloth (surface
 * k's vertices after those of surfaces 0..k-1; Weft welds the vertices surfaces share along a
 * seam), and the result written back into each surface of the ArrayMesh the node shows, with
 * that surface's own arrays and material. */
#include <stdlib.h>
#include <string.h>

#include "weft_cloth_node.h"
#include "wgd_mesh.h"

enum { GD_PRIMITIVE_TRIANGLES = 4 };

/* Surface k's arrays, material and triangles appended to *pos / *tris (grown with realloc). */
static int read_one(wgd_cloth* c, godot_object* mesh, int k, const char* name, float** pos, int** tris, int* n_tris) {
    /* ArrayMesh says; other meshes (PrimitiveMesh: triangles) have no such method for scripts */
    godot_variant a;
    gd->godot_variant_new_int(&a, k);
    const godot_variant* args[1] = {&a};
    int called = 0;
    godot_variant pv = gd_call(mesh, "surface_get_primitive_type", 1, args, &called);
    int64_t primitive = called ? gd->godot_variant_as_int(&pv) : GD_PRIMITIVE_TRIANGLES;
    gd->godot_variant_destroy(&pv);
    gd->godot_variant_destroy(&a);
    if (primitive != GD_PRIMITIVE_TRIANGLES) {
        gd_error("WeftCloth '%s': surface %d of its mesh is not triangles (primitive %d)", name, k, (int)primitive);
        return 0;
    }
    c->materials[k] = gd_call_int(mesh, "surface_get_material", k);
    wgd_mesh_surface(mesh, k, &c->surfaces[k]);
    c->n_surfaces = k + 1;
    float* p = NULL;
    int* t = NULL;
    int n = 0, nt = 0;
    int ok = wgd_mesh_triangles(&c->surfaces[k], c->scale, &p, &n, &t, &nt);
    if (!ok) {
        gd_error("WeftCloth '%s': surface %d of its mesh has no triangles", name, k);
    } else {
        int first = c->surface_first[k];
        float* all_p = realloc(*pos, (size_t)(first + n) * 3 * sizeof(float));
        if (all_p) *pos = all_p;
        int* all_t = all_p ? realloc(*tris, (size_t)(*n_tris + nt) * 3 * sizeof(int)) : NULL;
        if (all_t) *tris = all_t;
        ok = all_p && all_t;
        if (ok) {
            memcpy(*pos + 3 * (size_t)first, p, (size_t)n * 3 * sizeof(float));
            for (int i = 0; i < 3 * nt; i++) (*tris)[3 * *n_tris + i] = first + t[i];
            *n_tris += nt;
            c->surface_first[k + 1] = first + n;
        }
    }
    free(p);
    free(t);
    return ok;
}

int wgd_cloth_read_surfaces(wgd_cloth* c, float** pos, int** tris, int* n_tris) {
    char name[128];
    gd_node_name(c->owner, name, sizeof name);
    *pos = NULL;
    *tris = NULL;
    *n_tris = 0;
    godot_object* mesh = gd_call_object(c->owner, "get_mesh", 0, NULL);
    if (!mesh) {
        gd_error("WeftCloth '%s': the MeshInstance has no mesh", name);
        return 0;
    }
    godot_variant cv = gd_call(mesh, "get_surface_count", 0, NULL, NULL);
    int count = (int)gd->godot_variant_as_int(&cv);
    gd->godot_variant_destroy(&cv);
    if (count <= 0) {
        gd_error("WeftCloth '%s': its mesh has no surface", name);
        return 0;
    }
    c->surfaces = malloc((size_t)count * sizeof *c->surfaces);
    c->materials = malloc((size_t)count * sizeof *c->materials);
    c->surface_first = calloc((size_t)count + 1, sizeof *c->surface_first);
    if (!c->surfaces || !c->materials || !c->surface_first) return 0;
    for (int k = 0; k < count; k++) {
        if (!read_one(c, mesh, k, name, pos, tris, n_tris)) return 0;
    }
    c->n_vertices = c->surface_first[count];
    return 1;
}

/* arrays[which] = n vectors from src. */
static void set_vectors(godot_array* arrays, int which, const float* src, int n) {
    godot_pool_vector3_array a;
    gd->godot_pool_vector3_array_new(&a);
    gd->godot_pool_vector3_array_resize(&a, n);
    godot_pool_vector3_array_write_access* w = gd->godot_pool_vector3_array_write(&a);
    memcpy(gd->godot_pool_vector3_array_write_access_ptr(w), src, (size_t)n * 3 * sizeof(float));
    gd->godot_pool_vector3_array_write_access_destroy(w);
    godot_variant v;
    gd->godot_variant_new_pool_vector3_array(&v, &a);
    gd->godot_array_set(arrays, which, &v);
    gd->godot_variant_destroy(&v);
    gd->godot_pool_vector3_array_destroy(&a);
}

void wgd_cloth_write_surfaces(wgd_cloth* c) {
    godot_object* mesh = gd->godot_variant_as_object(&c->mesh);
    godot_variant cv = gd_call(mesh, "get_surface_count", 0, NULL, NULL);
    for (int k = (int)gd->godot_variant_as_int(&cv) - 1; k >= 0; k--) {
        gd->godot_variant_destroy((godot_variant[]){gd_call_int(mesh, "surface_remove", k)});
    }
    gd->godot_variant_destroy(&cv);
    godot_variant prim;
    gd->godot_variant_new_int(&prim, GD_PRIMITIVE_TRIANGLES);
    for (int k = 0; k < c->n_surfaces; k++) {
        int first = c->surface_first[k], n = c->surface_first[k + 1] - first;
        set_vectors(&c->surfaces[k], WGD_ARRAY_VERTEX, c->positions + 3 * (size_t)first, n);
        set_vectors(&c->surfaces[k], WGD_ARRAY_NORMAL, c->normals + 3 * (size_t)first, n);
        godot_variant arrays, index;
        gd->godot_variant_new_array(&arrays, &c->surfaces[k]);
        const godot_variant* add[2] = {&prim, &arrays};
        gd->godot_variant_destroy((godot_variant[]){gd_call(mesh, "add_surface_from_arrays", 2, add, NULL)});
        gd->godot_variant_destroy(&arrays);
        if (gd->godot_variant_get_type(&c->materials[k]) == GODOT_VARIANT_TYPE_OBJECT) {
            gd->godot_variant_new_int(&index, k);
            const godot_variant* setm[2] = {&index, &c->materials[k]};
            gd->godot_variant_destroy((godot_variant[]){gd_call(mesh, "surface_set_material", 2, setm, NULL)});
            gd->godot_variant_destroy(&index);
        }
    }
    gd->godot_variant_destroy(&prim);
}

void wgd_cloth_surfaces_release(wgd_cloth* c) {
    for (int k = 0; k < c->n_surfaces; k++) {
        gd->godot_array_destroy(&c->surfaces[k]);
        gd->godot_variant_destroy(&c->materials[k]);
    }
    free(c->surfaces);
    free(c->materials);
    free(c->surface_first);
    c->surfaces = NULL;
    c->materials = NULL;
    c->surface_first = NULL;
    c->n_surfaces = 0;
}
