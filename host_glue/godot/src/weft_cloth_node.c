/* WeftCloth's life: created with Weft's defaults, the cloth built at _ready from the node's
 * mesh (all its surfaces, triangles: weft_cloth_surfaces.c), stepped in _physics_process with
 * the node's, the colliders' and the body's poses, and the result written into an ArrayMesh the
 * node shows. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "weft_cloth_node.h"
#include "wgd_mesh.h"

static void* cloth_create(godot_object* owner, void* method_data) {
    (void)method_data;
    wgd_cloth* c = calloc(1, sizeof *c);
    if (!c) return NULL;
    c->owner = owner;
    weft_cloth_def d = weft_default_cloth_def();
    c->density = d.material.density;
    for (int i = 0; i < 3; i++) {
        c->stiffness[i] = d.material.stiffness[i];
        c->damping[i] = d.material.damping[i];
        c->wind[i] = d.wind[i];
    }
    c->tolerance = d.tolerance;
    c->substeps = d.substeps;
    c->max_iterations = d.max_iterations;
    c->backend = WEFT_BACKEND_CPU;
    weft_collider_def cd = weft_default_collider_def();
    c->collider_thickness = cd.thickness;
    c->collider_friction = cd.friction;
    gd->godot_pool_int_array_new(&c->pinned_vertices);
    godot_string parent = gd->godot_string_chars_to_utf8("..");
    gd->godot_node_path_new(&c->colliders_root, &parent);
    gd->godot_string_destroy(&parent);
    godot_string empty;
    gd->godot_string_new(&empty);
    godot_node_path* paths[4] = {&c->attach_skeleton, &c->body, &c->skeleton_path, &c->body_path};
    for (int i = 0; i < 4; i++) gd->godot_node_path_new(paths[i], &empty);
    gd->godot_string_destroy(&empty);
    gd->godot_pool_string_array_new(&c->attach_bones);
    gd->godot_array_new(&c->attach_vertices);
    gd->godot_variant_new_nil(&c->mesh);
    return c;
}

static void cloth_release(wgd_cloth* c) {
    if (c->ctx) weft_context_destroy(c->ctx);   /* destroys the cloth */
    c->ctx = NULL;
    c->cloth.id = 0;
    free(c->positions);
    free(c->normals);
    c->positions = c->normals = NULL;
    for (int i = 0; i < c->n_colliders; i++) gd->godot_node_path_destroy(&c->colliders[i].path);
    c->n_colliders = 0;
    c->n_attachments = c->first_bone = 0;
    wgd_cloth_body_release(c);
    wgd_cloth_surfaces_release(c);
}

static void cloth_destroy(godot_object* owner, void* method_data, void* user) {
    (void)owner;
    (void)method_data;
    wgd_cloth* c = user;
    if (!c) return;
    cloth_release(c);
    gd->godot_variant_destroy(&c->mesh);
    gd->godot_pool_int_array_destroy(&c->pinned_vertices);
    gd->godot_node_path_destroy(&c->colliders_root);
    godot_node_path* paths[4] = {&c->attach_skeleton, &c->body, &c->skeleton_path, &c->body_path};
    for (int i = 0; i < 4; i++) gd->godot_node_path_destroy(paths[i]);
    gd->godot_pool_string_array_destroy(&c->attach_bones);
    gd->godot_array_destroy(&c->attach_vertices);
    free(c);
}

static void weft_log(weft_log_level level, const char* message, void* user) {
    wgd_cloth* c = user;
    char name[128];
    gd_node_name(c->owner, name, sizeof name);
    if (level >= WEFT_LOG_ERROR) {
        gd_error("WeftCloth '%s': %s", name, message);
    } else {
        gd_warning("WeftCloth '%s': %s", name, message);
    }
}

static int fetch_result(wgd_cloth* c) {
    int count = 0;
    weft_status s = weft_cloth_get_vertices(c->ctx, c->cloth, WEFT_SPACE_OBJECT, c->positions, c->normals,
                                            c->n_vertices, &count);
    if (s != WEFT_OK) return 0;
    for (int i = 0; i < c->n_vertices; i++) {
        for (int k = 0; k < 3; k++) c->positions[3 * i + k] /= c->scale[k];
    }
    return 1;
}

static godot_variant cloth_ready(godot_object* owner, void* md, void* user, int argc, godot_variant** argv) {
    (void)owner;
    (void)md;
    (void)argc;
    (void)argv;
    wgd_cloth* c = user;
    godot_variant nil;
    gd->godot_variant_new_nil(&nil);
    cloth_release(c);
    float object[16];
    gd_global_transform(c->owner, object, c->scale);

    weft_context_def cd = weft_default_context_def();
    cd.backend = (weft_backend)c->backend;
    cd.log = weft_log;
    cd.log_user = c;
    if (weft_context_create(WEFT_ABI, &cd, &c->ctx) != WEFT_OK) return nil;   /* logged */

    float* pos = NULL;
    int* tris = NULL;
    int n_tris = 0;
    int* pins = NULL;
    int* bone_vertices = NULL;
    int* sizes = NULL;
    int* body_tris = NULL;
    weft_collider_def colliders[WGD_MAX_COLLIDERS];
    weft_attachment_def attachments[1 + WGD_MAX_BONE_ATTACHMENTS];
    weft_mesh_collider_def body;
    if (!wgd_cloth_read_surfaces(c, &pos, &tris, &n_tris)) goto fail;
    c->positions = malloc((size_t)c->n_vertices * 3 * sizeof(float));
    c->normals = malloc((size_t)c->n_vertices * 3 * sizeof(float));
    if (!c->positions || !c->normals) goto fail;

    weft_cloth_def d = weft_default_cloth_def();
    d.mesh.positions = pos;
    d.mesh.n_vertices = c->n_vertices;
    d.mesh.indices = tris;
    d.mesh.n_faces = n_tris;
    sizes = malloc((size_t)n_tris * sizeof(int));
    if (!sizes) goto fail;
    for (int t = 0; t < n_tris; t++) sizes[t] = 3;
    d.mesh.face_sizes = sizes;
    memcpy(d.transform, object, sizeof object);
    d.material.density = c->density;
    for (int i = 0; i < 3; i++) {
        d.material.stiffness[i] = c->stiffness[i];
        d.material.damping[i] = c->damping[i];
        d.wind[i] = c->wind[i];
    }
    d.tolerance = c->tolerance;
    d.substeps = (int)c->substeps;
    d.max_iterations = (int)c->max_iterations;

    godot_pool_int_array_read_access* pr = gd->godot_pool_int_array_read(&c->pinned_vertices);
    int n_pins = (int)gd->godot_pool_int_array_size(&c->pinned_vertices);
    pins = malloc((size_t)(n_pins > 0 ? n_pins : 1) * sizeof(int));
    if (pins) {
        const godot_int* p = gd->godot_pool_int_array_read_access_ptr(pr);
        for (int i = 0; i < n_pins; i++) pins[i] = (int)p[i];
    }
    gd->godot_pool_int_array_read_access_destroy(pr);
    if (!pins) goto fail;
    c->n_attachments = 0;
    if (n_pins > 0) {   /* the pins follow the node: attachment slot 0 */
        attachments[0] = weft_default_attachment_def();
        attachments[0].vertices = pins;
        attachments[0].n_vertices = n_pins;
        memcpy(attachments[0].bind_transform, object, sizeof object);
        c->n_attachments = 1;
    }
    if (wgd_cloth_bone_attachments(c, attachments + c->n_attachments, &bone_vertices) < 0) goto fail;
    d.n_attachments = c->n_attachments;
    d.attachments = attachments;
    d.n_colliders = wgd_cloth_find_colliders(c, colliders);
    d.colliders = colliders;
    d.n_mesh_colliders = wgd_cloth_body_collider(c, &body, &body_tris);
    d.mesh_colliders = &body;

    weft_status s = weft_cloth_create(c->ctx, &d, &c->cloth);   /* a failure is logged */
    if (s != WEFT_OK || !fetch_result(c)) goto fail;
    free(pos);
    free(tris);
    free(sizes);
    free(pins);
    free(bone_vertices);
    free(body_tris);

    godot_class_constructor make = gd->godot_get_class_constructor("ArrayMesh");
    gd->godot_variant_destroy(&c->mesh);
    gd->godot_variant_new_object(&c->mesh, make());   /* the variant holds the reference */
    wgd_cloth_write_surfaces(c);
    const godot_variant* args[1] = {&c->mesh};
    godot_variant r = gd_call(c->owner, "set_mesh", 1, args, NULL);
    gd->godot_variant_destroy(&r);
    c->frames = 0;
    return nil;
fail:
    free(pos);
    free(tris);
    free(sizes);
    free(pins);
    free(bone_vertices);
    free(body_tris);
    cloth_release(c);
    return nil;
}

static godot_variant cloth_physics_process(godot_object* owner, void* md, void* user, int argc, godot_variant** argv) {
    (void)owner;
    (void)md;
    wgd_cloth* c = user;
    godot_variant nil;
    gd->godot_variant_new_nil(&nil);
    if (!c->ctx || argc < 1) return nil;
    float object[16];
    gd_global_transform(c->owner, object, NULL);
    wgd_cloth_collider_transforms(c);
    wgd_cloth_bone_transforms(c);
    wgd_cloth_body_update(c);
    if (c->first_bone > 0) memcpy(c->attach_xf, object, sizeof object);   /* the pins: on the node */
    weft_frame fr = weft_default_frame();
    fr.dt = gd->godot_variant_as_real(argv[0]);
    fr.object_transform = object;
    fr.attachment_transforms = c->n_attachments > 0 ? c->attach_xf : NULL;
    fr.collider_transforms = c->n_colliders > 0 ? c->collider_xf : NULL;
    fr.mesh_collider_transforms = c->has_body && !c->body_skinned ? c->body_xf : NULL;
    if (weft_cloth_step(c->ctx, c->cloth, &fr, NULL) != WEFT_OK) return nil;   /* logged; unchanged */
    if (fetch_result(c)) wgd_cloth_write_surfaces(c);
    c->frames++;
    return nil;
}

/* Methods for scripts: is_simulating() -> bool, get_frames() -> int (frames stepped since
 * _ready), get_body_vertices() -> PoolVector3Array (the body's world vertices the last frame
 * collided with: what a skinned body was skinned to). */
static godot_variant cloth_is_simulating(godot_object* owner, void* md, void* user, int argc, godot_variant** argv) {
    (void)owner;
    (void)md;
    (void)argc;
    (void)argv;
    godot_variant v;
    gd->godot_variant_new_bool(&v, ((wgd_cloth*)user)->ctx != NULL);
    return v;
}

static godot_variant cloth_get_body_vertices(godot_object* owner, void* md, void* user, int argc,
                                            godot_variant** argv) {
    (void)owner;
    (void)md;
    (void)argc;
    (void)argv;
    return wgd_cloth_body_vertices(user);
}

static godot_variant cloth_get_frames(godot_object* owner, void* md, void* user, int argc, godot_variant** argv) {
    (void)owner;
    (void)md;
    (void)argc;
    (void)argv;
    godot_variant v;
    gd->godot_variant_new_int(&v, ((wgd_cloth*)user)->frames);
    return v;
}

void wgd_cloth_register(void* handle) {
    godot_instance_create_func create = {cloth_create, NULL, NULL};
    godot_instance_destroy_func destroy = {cloth_destroy, NULL, NULL};
    gdns->godot_nativescript_register_class(handle, "WeftCloth", "MeshInstance", create, destroy);
    godot_method_attributes attr = {GODOT_METHOD_RPC_MODE_DISABLED};
    struct {
        const char* name;
        godot_variant (*fn)(godot_object*, void*, void*, int, godot_variant**);
    } methods[] = {{"_ready", cloth_ready},
                   {"_physics_process", cloth_physics_process},
                   {"is_simulating", cloth_is_simulating},
                   {"get_frames", cloth_get_frames},
                   {"get_body_vertices", cloth_get_body_vertices}};
    for (size_t i = 0; i < sizeof methods / sizeof methods[0]; i++) {
        godot_instance_method m = {methods[i].fn, NULL, NULL};
        gdns->godot_nativescript_register_method(handle, "WeftCloth", methods[i].name, attr, m);
    }
    wgd_cloth_register_properties(handle);
}
