/* The Godot side of the WeftCloth plugin: the GDNative API tables Godot hands the library at
 * load time, and small helpers over them (calling an engine method by name, variants, pool
 * arrays, transforms, error messages). Knows nothing about Weft. */
#ifndef WEFT_GODOT_GD_API_H
#define WEFT_GODOT_GD_API_H

#include <gdnative_api_struct.gen.h>

extern const godot_gdnative_core_api_struct* gd;
extern const godot_gdnative_ext_nativescript_api_struct* gdns;

/* Store the tables from godot_gdnative_init's options. Returns 0 when the NativeScript
 * extension is missing. */
int gd_api_init(const godot_gdnative_init_options* options);

/* obj.method(args...) through the object's dynamic dispatch (scripts included). The result is
 * the caller's to destroy (nil when the call failed; then *ok is 0 when ok is not NULL). */
godot_variant gd_call(godot_object* obj, const char* method, int argc, const godot_variant** args, int* ok);
/* obj.method(arg) with one int argument; the result is the caller's to destroy. */
godot_variant gd_call_int(godot_object* obj, const char* method, int64_t arg);
/* A call whose result is an object (NULL if not one); the variant is destroyed. */
godot_object* gd_call_object(godot_object* obj, const char* method, int argc, const godot_variant** args);
/* obj.get_class() == name, or obj inherits name (obj.is_class(name)). */
int gd_is_class(godot_object* obj, const char* name);
/* node.get_node_or_null(path) for a path given as text. */
godot_object* gd_get_node(godot_object* node, const godot_node_path* path);

/* skeleton.find_bone(name): the bone's index, -1 when there is none. */
int gd_find_bone(godot_object* skeleton, const godot_string* name);

/* A Transform as a column-major rigid 4x4 (weft.h's convention): the basis is orthonormalised,
 * and its column lengths (the scale) go to scale when not NULL. */
void gd_rigid_matrix(const godot_transform* t, float m[16], float scale[3]);
/* A node's global transform, as gd_rigid_matrix makes it. */
void gd_global_transform(godot_object* spatial, float m[16], float scale[3]);
/* A Skeleton bone's world transform (the skeleton's global transform times the bone's global
 * pose: its rest, custom pose and animated pose), rigid. */
void gd_bone_global_transform(godot_object* skeleton, int bone, float m[16]);

/* Errors and warnings through Godot's own (stderr, the editor's Errors tab). printf-style. */
void gd_error(const char* fmt, ...) __attribute__((format(printf, 1, 2)));
void gd_warning(const char* fmt, ...) __attribute__((format(printf, 1, 2)));

/* The text of a NodePath / String into buf (truncated). */
const char* gd_node_path_text(const godot_node_path* path, char* buf, size_t size);
const char* gd_string_text(const godot_string* s, char* buf, size_t size);
/* node.name into buf. */
const char* gd_node_name(godot_object* node, char* buf, size_t size);

#endif
