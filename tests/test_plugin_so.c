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
    /* internals stay hidden */
    CHECK(dlsym(so, "wc_model_build") == NULL);
    CHECK(dlsym(so, "wc_weld") == NULL);
    CHECK(dlsym(so, "wc_radix_sort") == NULL);
    dlclose(so);
}

int main(void) {
    RUN_TEST(test_dlopen);
    return TEST_SUMMARY();
}
