/* weft_loader: dlopen libweft.so, resolve weft.h's functions, check the ABI (see weft_loader.h). */
#define _POSIX_C_SOURCE 200809L
#include "weft_loader.h"

#include <dlfcn.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

/* The table's signatures are weft.h's: each listed type must be exactly the declared function's.
 * (_Generic does not evaluate its operand, so nothing here references libweft.so.) */
#define WEFT_LOADER_CHECK_(ret, name, params)                                            \
    _Static_assert(_Generic(&name, ret(*) params: 1, default: 0),                        \
                   "weft_loader.h: the signature of " #name " differs from weft/weft.h");
WEFT_LOADER_FUNCTIONS(WEFT_LOADER_CHECK_)
#undef WEFT_LOADER_CHECK_

/* dlsym returns an object pointer; it is copied into the function pointer bit for bit. */
_Static_assert(sizeof(void*) == sizeof(void (*)(void)), "function and object pointers differ");

static const char* const function_names[] = {
#define WEFT_LOADER_NAME_(ret, name, params) #name,
    WEFT_LOADER_FUNCTIONS(WEFT_LOADER_NAME_)
#undef WEFT_LOADER_NAME_
};
enum { FUNCTION_COUNT = (int)(sizeof function_names / sizeof function_names[0]) };

int weft_loader_function_count(void) { return FUNCTION_COUNT; }

const char* weft_loader_function_name(int i) {
    return i >= 0 && i < FUNCTION_COUNT ? function_names[i] : NULL;
}

static weft_status fail(weft_api* api, weft_status status, char* error, size_t error_size,
                        const char* fmt, ...) {
    if (api->handle) dlclose(api->handle);
    memset(api, 0, sizeof *api);
    if (error && error_size > 0) {
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(error, error_size, fmt, ap);
        va_end(ap);
    }
    return status;
}

weft_status weft_loader_open(weft_api* api, const char* path, char* error, size_t error_size) {
    if (error && error_size > 0) error[0] = '\0';
    if (!api) {
        if (error && error_size > 0) snprintf(error, error_size, "weft_loader_open: api is NULL");
        return WEFT_ERROR_INVALID_ARGUMENT;
    }
    memset(api, 0, sizeof *api);
    if (!path)
        return fail(api, WEFT_ERROR_INVALID_ARGUMENT, error, error_size,
                    "weft_loader_open: path is NULL");

    dlerror(); /* clear a stale message */
    api->handle = dlopen(path, RTLD_NOW | RTLD_LOCAL);
    if (!api->handle) {
        const char* why = dlerror();
        return fail(api, WEFT_ERROR_IO, error, error_size, "%s: cannot open: %s", path,
                    why ? why : "unknown dlopen error");
    }

    /* A library that exports a weft_ symbol under another signature is caught by the ABI check
     * below, which runs before any other function is called. */
#define WEFT_LOADER_RESOLVE_(ret, name, params)                                              \
    {                                                                                        \
        void* sym = dlsym(api->handle, #name);                                               \
        if (!sym)                                                                            \
            return fail(api, WEFT_ERROR_ABI_MISMATCH, error, error_size,                     \
                        "%s: missing symbol %s", path, #name);                               \
        memcpy(&api->name, &sym, sizeof sym);                                                \
    }
    WEFT_LOADER_FUNCTIONS(WEFT_LOADER_RESOLVE_)
#undef WEFT_LOADER_RESOLVE_

    weft_version_info v = api->weft_version();
    if (v.abi != WEFT_ABI)
        return fail(api, WEFT_ERROR_ABI_MISMATCH, error, error_size,
                    "%s: ABI %d != %d (library %d.%d.%d != this host's weft.h %d.%d.%d)", path,
                    v.abi, WEFT_ABI, v.major, v.minor, v.patch, WEFT_VERSION_MAJOR,
                    WEFT_VERSION_MINOR, WEFT_VERSION_PATCH);
    return WEFT_OK;
}

void weft_loader_close(weft_api* api) {
    if (!api) return;
    if (api->handle) dlclose(api->handle);
    memset(api, 0, sizeof *api);
}
