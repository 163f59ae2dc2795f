/* GDNative API tables and helpers (gd_api.h). */
#include "gd_api.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

const godot_gdnative_core_api_struct* gd = NULL;
const godot_gdnative_ext_nativescript_api_struct* gdns = NULL;

int gd_api_init(const godot_gdnative_init_options* options) {
    gd = options->api_struct;
    gdns = NULL;
    for (unsigned i = 0; i < gd->num_extensions; i++) {
        if (gd->extensions[i]->type == GDNATIVE_EXT_NATIVESCRIPT) {
            gdns = (const godot_gdnative_ext_nativescript_api_struct*)gd->extensions[i];
        }
    }
    return gdns != NULL;
}

godot_variant gd_call(godot_object* obj, const char* method, int argc, const godot_variant** args, int* ok) {
    godot_variant self, result;
    gd->godot_variant_new_object(&self, obj);
    godot_string name = gd->godot_string_chars_to_utf8(method);
    godot_variant_call_error err;
    result = gd->godot_variant_call(&self, &name, args, argc, &err);
    gd->godot_string_destroy(&name);
    gd->godot_variant_destroy(&self);
    if (ok) *ok = err.error == GODOT_CALL_ERROR_CALL_OK;
    return result;
}

godot_variant gd_call_int(godot_object* obj, const char* method, int64_t arg) {
    godot_variant a;
    gd->godot_variant_new_int(&a, arg);
    const godot_variant* args[1] = {&a};
    godot_variant r = gd_call(obj, method, 1, args, NULL);
    gd->godot_variant_destroy(&a);
    return r;
}

godot_object* gd_call_object(godot_object* obj, const char* method, int argc, const godot_variant** args) {
    godot_variant v = gd_call(obj, method, argc, args, NULL);
    godot_object* o = gd->godot_variant_get_type(&v) == GODOT_VARIANT_TYPE_OBJECT ? gd->godot_variant_as_object(&v) : NULL;
    gd->godot_variant_destroy(&v);
    return o;
}

int gd_is_class(godot_object* obj, const char* name) {
    if (!obj) return 0;
    godot_string s = gd->godot_string_chars_to_utf8(name);
    godot_variant arg;
    gd->godot_variant_new_string(&arg, &s);
    const godot_variant* args[1] = {&arg};
    godot_variant r = gd_call(obj, "is_class", 1, args, NULL);
    int yes = gd->godot_variant_as_bool(&r);
    gd->godot_variant_destroy(&r);
    gd->godot_variant_destroy(&arg);
    gd->godot_string_destroy(&s);
    return yes;
}

godot_object* gd_get_node(godot_object* node, const godot_node_path* path) {
    godot_variant arg;
    gd->godot_variant_new_node_path(&arg, path);
    const godot_variant* args[1] = {&arg};
    godot_object* o = gd_call_object(node, "get_node_or_null", 1, args);
    gd->godot_variant_destroy(&arg);
    return o;
}

int gd_find_bone(godot_object* skeleton, const godot_string* name) {
    godot_variant sv;
    gd->godot_variant_new_string(&sv, name);
    const godot_variant* args[1] = {&sv};
    godot_variant r = gd_call(skeleton, "find_bone", 1, args, NULL);
    int bone = (int)gd->godot_variant_as_int(&r);
    gd->godot_variant_destroy(&r);
    gd->godot_variant_destroy(&sv);
    return bone;
}

void gd_rigid_matrix(const godot_transform* t, float m[16], float scale[3]) {
    float e[12];   /* Transform: basis rows (elements[3], Vector3 each), then the origin */
    _Static_assert(sizeof(godot_transform) == sizeof e, "Godot's real_t is float");
    memcpy(e, t, sizeof e);
    for (int c = 0; c < 3; c++) {
        float col[3] = {e[0 * 3 + c], e[1 * 3 + c], e[2 * 3 + c]};
        float len = sqrtf(col[0] * col[0] + col[1] * col[1] + col[2] * col[2]);
        if (scale) scale[c] = len;
        for (int r = 0; r < 3; r++) m[4 * c + r] = len > 0.0f ? col[r] / len : (r == c ? 1.0f : 0.0f);
        m[4 * c + 3] = 0.0f;
    }
    /* Gram-Schmidt: a sheared basis becomes the nearest rigid frame built from its X and Y axes. */
    float* x = m;
    float* y = m + 4;
    float* z = m + 8;
    float d = x[0] * y[0] + x[1] * y[1] + x[2] * y[2];
    for (int r = 0; r < 3; r++) y[r] -= d * x[r];
    float ly = sqrtf(y[0] * y[0] + y[1] * y[1] + y[2] * y[2]);
    if (ly > 0.0f) for (int r = 0; r < 3; r++) y[r] /= ly;
    float zz[3] = {x[1] * y[2] - x[2] * y[1], x[2] * y[0] - x[0] * y[2], x[0] * y[1] - x[1] * y[0]};
    for (int r = 0; r < 3; r++) z[r] = zz[r];
    m[12] = e[9];
    m[13] = e[10];
    m[14] = e[11];
    m[15] = 1.0f;
}

void gd_global_transform(godot_object* spatial, float m[16], float scale[3]) {
    godot_variant v = gd_call(spatial, "get_global_transform", 0, NULL, NULL);
    godot_transform t = gd->godot_variant_as_transform(&v);
    gd->godot_variant_destroy(&v);
    gd_rigid_matrix(&t, m, scale);
}

void gd_bone_global_transform(godot_object* skeleton, int bone, float m[16]) {
    godot_variant sv = gd_call(skeleton, "get_global_transform", 0, NULL, NULL);
    godot_transform s = gd->godot_variant_as_transform(&sv);
    godot_variant arg;
    gd->godot_variant_new_int(&arg, bone);
    const godot_variant* args[1] = {&arg};
    godot_variant pv = gd_call(skeleton, "get_bone_global_pose", 1, args, NULL);
    godot_transform p = gd->godot_variant_as_transform(&pv);
    godot_transform w = gd->godot_transform_operator_multiply(&s, &p);
    gd_rigid_matrix(&w, m, NULL);
    gd->godot_variant_destroy(&pv);
    gd->godot_variant_destroy(&arg);
    gd->godot_variant_destroy(&sv);
}

static void gd_report(int error, const char* fmt, va_list ap) {
    char buf[1024];
    vsnprintf(buf, sizeof buf, fmt, ap);
    if (error) {
        gd->godot_print_error(buf, "weft_godot", __FILE__, __LINE__);
    } else {
        gd->godot_print_warning(buf, "weft_godot", __FILE__, __LINE__);
    }
}

void gd_error(const char* fmt, ...) {
    va_list ap;
    va_start(ap, fmt);
    gd_report(1, fmt, ap);
    va_end(ap);
}

void gd_warning(const char* fmt, ...) {
    va_list ap;
    va_start(ap, fmt);
    gd_report(0, fmt, ap);
    va_end(ap);
}

const char* gd_string_text(const godot_string* s, char* buf, size_t size) {
    godot_char_string cs = gd->godot_string_utf8(s);
    snprintf(buf, size, "%s", gd->godot_char_string_get_data(&cs));
    gd->godot_char_string_destroy(&cs);
    return buf;
}

const char* gd_node_path_text(const godot_node_path* path, char* buf, size_t size) {
    godot_string s = gd->godot_node_path_as_string(path);
    gd_string_text(&s, buf, size);
    gd->godot_string_destroy(&s);
    return buf;
}

const char* gd_node_name(godot_object* node, char* buf, size_t size) {
    godot_variant v = gd_call(node, "get_name", 0, NULL, NULL);
    godot_string s = gd->godot_variant_as_string(&v);
    gd_string_text(&s, buf, size);
    gd->godot_string_destroy(&s);
    gd->godot_variant_destroy(&v);
    return buf;
}
