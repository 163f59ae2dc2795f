/* weft_loader: load libweft.so at run time (dlopen) into a table of function pointers.
 *
 * For hosts that load plugins by path instead of linking libweft.so: every entry point of
 * weft/weft.h is resolved into a weft_api field named after the function, and the library's
 * ABI (weft_version().abi) is checked against the WEFT_ABI this file was compiled with before
 * anything else is called.
 *
 *     weft_api w;
 *     char err[512];
 *     if (weft_loader_open(&w, "/opt/weft/lib/libweft.so.10", err, sizeof err) != WEFT_OK) {
 *         fprintf(stderr, "%s\n", err);   // "...: cannot open: ...", "...: missing symbol weft_x",
 *         return;                          // "...: ABI 1 != 10 (library 0.1.0 != this host's ..."
 *     }
 *     weft_context_def cd = w.weft_default_context_def();
 *     weft_context* ctx = NULL;
 *     w.weft_context_create(WEFT_ABI, &cd, &ctx);
 *     ...
 *     w.weft_context_destroy(ctx);
 *     weft_loader_close(&w);               // after every context is destroyed
 *
 * Two tables (two hosts, or two versions side by side) never interfere: the library is opened
 * RTLD_LOCAL and the loader keeps no state outside the table. The threading contract is
 * weft.h's; weft_loader_open/close are as thread-safe as dlopen/dlclose. Depends on weft.h and
 * libdl only: a host may copy weft_loader.h, weft_loader_functions.h and weft_loader.c into its
 * own tree. */
#ifndef WEFT_LOADER_H
#define WEFT_LOADER_H

#include <stddef.h>

#include "weft/weft.h"
#include "weft_loader_functions.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The loaded library: its dlopen handle and one pointer per function, named after it. */
typedef struct weft_api {
    void* handle;               /* dlopen handle; NULL when not loaded */
#define WEFT_LOADER_FIELD_(ret, name, params) ret(*name) params;
    WEFT_LOADER_FUNCTIONS(WEFT_LOADER_FIELD_)
#undef WEFT_LOADER_FIELD_
} weft_api;

/* Open the library at path (any dlopen path: absolute, relative, or a bare name searched the
 * dlopen way), resolve every function and check its ABI. On success fills *api and returns
 * WEFT_OK. On failure *api is zeroed (nothing stays open), a one-line message goes to error
 * (error_size bytes, always terminated; error may be NULL) and the status says why:
 *   WEFT_ERROR_INVALID_ARGUMENT  api or path NULL:            "weft_loader_open: api is NULL"
 *   WEFT_ERROR_IO                dlopen failed:               "PATH: cannot open: <dlerror>"
 *   WEFT_ERROR_ABI_MISMATCH      a function is not exported:  "PATH: missing symbol weft_x"
 *                                another ABI:                 "PATH: ABI 1 != 10 (library
 *                                                   0.1.0 != this host's weft.h 0.10.2)"
 * api must not hold an open library (close it first). */
weft_status weft_loader_open(weft_api* api, const char* path, char* error, size_t error_size);

/* Close the library and zero *api. Destroy every context first: their code lives in it.
 * NULL and a zeroed (never opened, or already closed) table are ignored. libweft.so is linked
 * -z nodelete, so this drops the reference but the library stays mapped (its OpenMP worker
 * threads outlive every call); opening it again returns the same copy. */
void weft_loader_close(weft_api* api);

/* Number of functions in weft_api, and the name of the i-th (0 <= i < count; NULL outside). */
int weft_loader_function_count(void);
const char* weft_loader_function_name(int i);

#ifdef __cplusplus
}
#endif
#endif
