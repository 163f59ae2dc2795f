/* WeftCloth's exported properties: one table of (name, kind, field). They are read when the
 * cloth is built (_ready); a value set later takes effect at the next _ready. A non-finite
 * number is refused at once with an error naming the property (the old value stays); ranges
 * are Weft's to check when the cloth is built (its message names the weft_cloth_def field). */
#include <math.h>
#include <stddef.h>
#include <stdio.h>

#include "weft_cloth_node.h"

typedef enum { P_REAL, P_INT, P_VECTOR3, P_INT_ARRAY, P_NODE_PATH, P_STRING_ARRAY, P_ARRAY } prop_kind;

typedef struct prop {
    const char* name;
    prop_kind kind;
    size_t offset;              /* into wgd_cloth */
    godot_property_hint hint;
    const char* hint_string;
} prop;

#define F(field) offsetof(wgd_cloth, field)
static const prop PROPS[] = {
    {"density", P_REAL, F(density), GODOT_PROPERTY_HINT_NONE, ""},                 /* kg/m^2 */
    {"stiffness_stretch", P_REAL, F(stiffness[0]), GODOT_PROPERTY_HINT_NONE, ""},  /* N/m */
    {"stiffness_shear", P_REAL, F(stiffness[1]), GODOT_PROPERTY_HINT_NONE, ""},
    {"stiffness_bend", P_REAL, F(stiffness[2]), GODOT_PROPERTY_HINT_NONE, ""},
    {"damping_stretch", P_REAL, F(damping[0]), GODOT_PROPERTY_HINT_NONE, ""},      /* N s/m */
    {"damping_shear", P_REAL, F(damping[1]), GODOT_PROPERTY_HINT_NONE, ""},
    {"damping_bend", P_REAL, F(damping[2]), GODOT_PROPERTY_HINT_NONE, ""},
    {"wind", P_VECTOR3, F(wind), GODOT_PROPERTY_HINT_NONE, ""},                    /* m/s world */
    {"substeps", P_INT, F(substeps), GODOT_PROPERTY_HINT_RANGE, "1,64"},
    {"max_iterations", P_INT, F(max_iterations), GODOT_PROPERTY_HINT_RANGE, "1,10000"},
    {"tolerance", P_REAL, F(tolerance), GODOT_PROPERTY_HINT_NONE, ""},
    {"backend", P_INT, F(backend), GODOT_PROPERTY_HINT_ENUM, "Auto,CPU,GPU"},
    {"pinned_vertices", P_INT_ARRAY, F(pinned_vertices), GODOT_PROPERTY_HINT_NONE, ""},
    {"colliders_root", P_NODE_PATH, F(colliders_root), GODOT_PROPERTY_HINT_NONE, ""},
    {"collider_thickness", P_REAL, F(collider_thickness), GODOT_PROPERTY_HINT_NONE, ""},  /* m */
    {"collider_friction", P_REAL, F(collider_friction), GODOT_PROPERTY_HINT_NONE, ""},
    {"attach_skeleton", P_NODE_PATH, F(attach_skeleton), GODOT_PROPERTY_HINT_NONE, ""},
    {"attach_bones", P_STRING_ARRAY, F(attach_bones), GODOT_PROPERTY_HINT_NONE, ""},
    {"attach_vertices", P_ARRAY, F(attach_vertices), GODOT_PROPERTY_HINT_NONE, ""},
    {"body", P_NODE_PATH, F(body), GODOT_PROPERTY_HINT_NONE, ""},
};
#undef F

static godot_variant_type variant_type(prop_kind k) {
    switch (k) {
    case P_REAL: return GODOT_VARIANT_TYPE_REAL;
    case P_INT: return GODOT_VARIANT_TYPE_INT;
    case P_VECTOR3: return GODOT_VARIANT_TYPE_VECTOR3;
    case P_INT_ARRAY: return GODOT_VARIANT_TYPE_POOL_INT_ARRAY;
    case P_NODE_PATH: return GODOT_VARIANT_TYPE_NODE_PATH;
    case P_STRING_ARRAY: return GODOT_VARIANT_TYPE_POOL_STRING_ARRAY;
    case P_ARRAY: return GODOT_VARIANT_TYPE_ARRAY;
    }
    return GODOT_VARIANT_TYPE_NIL;
}

static godot_variant get_value(const prop* p, const wgd_cloth* c) {
    const char* field = (const char*)c + p->offset;
    godot_variant v;
    switch (p->kind) {
    case P_REAL: gd->godot_variant_new_real(&v, *(const double*)field); break;
    case P_INT: gd->godot_variant_new_int(&v, *(const int64_t*)field); break;
    case P_VECTOR3: {
        const double* d = (const double*)field;
        godot_vector3 v3;
        gd->godot_vector3_new(&v3, (godot_real)d[0], (godot_real)d[1], (godot_real)d[2]);
        gd->godot_variant_new_vector3(&v, &v3);
        break;
    }
    case P_INT_ARRAY: gd->godot_variant_new_pool_int_array(&v, (const godot_pool_int_array*)field); break;
    case P_NODE_PATH: gd->godot_variant_new_node_path(&v, (const godot_node_path*)field); break;
    case P_STRING_ARRAY:
        gd->godot_variant_new_pool_string_array(&v, (const godot_pool_string_array*)field);
        break;
    case P_ARRAY: gd->godot_variant_new_array(&v, (const godot_array*)field); break;
    default: gd->godot_variant_new_nil(&v); break;
    }
    return v;
}

static void set_value(godot_object* owner, void* method_data, void* user, godot_variant* value) {
    (void)owner;
    const prop* p = method_data;
    wgd_cloth* c = user;
    char* field = (char*)c + p->offset;
    switch (p->kind) {
    case P_REAL: {
        double x = gd->godot_variant_as_real(value);
        if (!isfinite(x)) {
            gd_error("WeftCloth: property %s = %g is not a finite number; it stays %g", p->name, x, *(double*)field);
            return;
        }
        *(double*)field = x;
        break;
    }
    case P_INT: *(int64_t*)field = gd->godot_variant_as_int(value); break;
    case P_VECTOR3: {
        godot_vector3 v3 = gd->godot_variant_as_vector3(value);
        double x = gd->godot_vector3_get_axis(&v3, GODOT_VECTOR3_AXIS_X);
        double y = gd->godot_vector3_get_axis(&v3, GODOT_VECTOR3_AXIS_Y);
        double z = gd->godot_vector3_get_axis(&v3, GODOT_VECTOR3_AXIS_Z);
        if (!isfinite(x) || !isfinite(y) || !isfinite(z)) {
            gd_error("WeftCloth: property %s = (%g, %g, %g) is not finite; it is unchanged", p->name, x, y, z);
            return;
        }
        double* d = (double*)field;
        d[0] = x;
        d[1] = y;
        d[2] = z;
        break;
    }
    case P_INT_ARRAY: {
        godot_pool_int_array a = gd->godot_variant_as_pool_int_array(value);
        gd->godot_pool_int_array_destroy((godot_pool_int_array*)field);
        *(godot_pool_int_array*)field = a;
        break;
    }
    case P_NODE_PATH: {
        godot_node_path np = gd->godot_variant_as_node_path(value);
        gd->godot_node_path_destroy((godot_node_path*)field);
        *(godot_node_path*)field = np;
        break;
    }
    case P_STRING_ARRAY: {
        godot_pool_string_array a = gd->godot_variant_as_pool_string_array(value);
        gd->godot_pool_string_array_destroy((godot_pool_string_array*)field);
        *(godot_pool_string_array*)field = a;
        break;
    }
    case P_ARRAY: {
        godot_array a = gd->godot_variant_as_array(value);
        gd->godot_array_destroy((godot_array*)field);
        *(godot_array*)field = a;
        break;
    }
    }
}

static godot_variant get_property(godot_object* owner, void* method_data, void* user) {
    (void)owner;
    return get_value(method_data, user);
}

void wgd_cloth_register_properties(void* handle) {
    /* no default_value: the inspector shows a fresh instance's values (Weft's defaults) */
    for (size_t i = 0; i < sizeof PROPS / sizeof PROPS[0]; i++) {
        const prop* p = &PROPS[i];
        godot_property_attributes attr = {0};
        attr.rset_type = GODOT_METHOD_RPC_MODE_DISABLED;
        attr.type = variant_type(p->kind);
        attr.hint = p->hint;
        attr.hint_string = gd->godot_string_chars_to_utf8(p->hint_string);
        attr.usage = GODOT_PROPERTY_USAGE_DEFAULT;
        gd->godot_variant_new_nil(&attr.default_value);
        godot_property_set_func set = {set_value, (void*)p, NULL};
        godot_property_get_func get = {get_property, (void*)p, NULL};
        gdns->godot_nativescript_register_property(handle, "WeftCloth", p->name, &attr, set, get);
        gd->godot_string_destroy(&attr.hint_string);
        gd->godot_variant_destroy(&attr.default_value);
    }
}
