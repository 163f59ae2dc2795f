/* Loads the built libweft.so with dlopen as a host would: the public entry points resolve, the
 * version matches the header, and core internals are not exported (hidden visibility + version
 * script). */
#define _POSIX_C_SOURCE 200809L
#include <dlfcn.h>
#include "check.h"
#include "weft/weft.h"

static void test_dlopen(void) {
    void* so = dlopen(WEFT_LIBRARY, RTLD_NOW | RTLD_LOCAL);
    if (!so) fprintf(stderr, "dlopen(%s): %s\n", WEFT_LIBRARY, dlerror());
    CHECK(so != NULL);
    if (!so) return;
    weft_version_info (*version)(void);
    const char* (*status_string)(weft_status);
    *(void**)&version = dlsym(so, "weft_version");
    *(void**)&status_string = dlsym(so, "weft_status_string");
    CHECK(version != NULL);
    CHECK(status_string != NULL);
    if (version) {
        weft_version_info v = version();
        CHECK_EQ_INT(v.major, WEFT_VERSION_MAJOR);
        CHECK_EQ_INT(v.minor, WEFT_VERSION_MINOR);
        CHECK_EQ_INT(v.abi, WEFT_ABI);
    }
    if (status_string) {
        CHECK(strcmp(status_string(WEFT_OK), "ok") == 0);
        CHECK(strcmp(status_string((weft_status)9999), "unknown status") == 0);
        CHECK(strcmp(status_string(WEFT_ERROR_IMPORT), "mesh import failed") == 0);
    }
    /* every entry point of the C ABI resolves (the renderer's are checked with the renderer) */
    static const char* const api[] = {
        "weft_context_create", "weft_context_destroy", "weft_context_last_error", "weft_context_last_status",
        "weft_context_backend", "weft_default_context_def", "weft_default_cloth_def",
        "weft_default_attachment_def", "weft_default_collider_def", "weft_default_frame", "weft_cloth_create",
        "weft_cloth_destroy", "weft_cloth_set_attachments", "weft_cloth_get_info", "weft_cloth_step",
        "weft_cloth_get_vertices", "weft_cloth_get_triangles", "weft_cloth_save", "weft_cloth_restore",
        "weft_default_mesh_collider_def", "weft_cloth_set_mesh_collider_vertices",
        "weft_cloth_set_mesh_collider_gl_buffer"};
    for (size_t i = 0; i < sizeof api / sizeof api[0]; ++i) {
        void* sym = dlsym(so, api[i]);
        if (!sym) fprintf(stderr, "missing %s\n", api[i]);
        CHECK(sym != NULL);
    }
    /* a host compiled against another ABI is refused */
    weft_context_def (*default_def)(void);
    weft_status (*create)(int, const weft_context_def*, weft_context**);
    void (*destroy)(weft_context*);
    *(void**)&default_def = dlsym(so, "weft_default_context_def");
    *(void**)&create = dlsym(so, "weft_context_create");
    *(void**)&destroy = dlsym(so, "weft_context_destroy");
    if (default_def && create && destroy) {
        weft_context_def cd = default_def();
        weft_context* ctx = NULL;
        CHECK_EQ_INT(create(WEFT_ABI - 1, &cd, &ctx), WEFT_ERROR_ABI_MISMATCH);
        CHECK(ctx == NULL);
        CHECK_EQ_INT(create(WEFT_ABI, &cd, &ctx), WEFT_OK);
        CHECK(ctx != NULL);
        destroy(ctx);
    }
    /* internals stay hidden */
    CHECK(dlsym(so, "wc_model_build") == NULL);
    CHECK(dlsym(so, "wc_weld") == NULL);
    CHECK(dlsym(so, "wc_radix_sort") == NULL);
    CHECK(dlsym(so, "wa_lookup") == NULL);
    CHECK(dlsym(so, "wa_snapshot_write") == NULL);
    dlclose(so);
}

int main(void) {
    RUN_TEST(test_dlopen);
    return TEST_SUMMARY();
}
