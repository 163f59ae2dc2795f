/* The library's GDNative entry points: Godot calls them when the .gdnlib is loaded. */
#include "weft_cloth_node.h"

#define WGD_EXPORT __attribute__((visibility("default")))

WGD_EXPORT void godot_gdnative_init(godot_gdnative_init_options* options);
WGD_EXPORT void godot_gdnative_terminate(godot_gdnative_terminate_options* options);
WGD_EXPORT void godot_nativescript_init(void* handle);

void godot_gdnative_init(godot_gdnative_init_options* options) {
    if (!gd_api_init(options)) {
        gd->godot_print_error("WeftCloth needs Godot's NativeScript extension", __func__, __FILE__, __LINE__);
    }
}

void godot_gdnative_terminate(godot_gdnative_terminate_options* options) {
    (void)options;
}

void godot_nativescript_init(void* handle) {
    if (gdns) wgd_cloth_register(handle);
}
