/* Weft: implicit (Baraff-Witkin) cloth simulation as a shared-object plugin.
 * Public C ABI. Only symbols declared in plugin/include/weft/ are exported from libweft.so. */
#ifndef WEFT_H
#define WEFT_H

#include "weft_status.h"

#ifdef __cplusplus
extern "C" {
#endif

#if defined(WEFT_BUILDING_LIBRARY)
#define WEFT_API __attribute__((visibility("default")))
#else
#define WEFT_API
#endif

/* Header version. weft_version() returns the library's; hosts compare the two. */
#define WEFT_VERSION_MAJOR 0
#define WEFT_VERSION_MINOR 1
#define WEFT_VERSION_PATCH 0
/* Incremented on every incompatible change of a struct layout or a signature. */
#define WEFT_ABI 1

typedef struct weft_version_info {
    int major, minor, patch;
    int abi;             /* WEFT_ABI the library was built with */
} weft_version_info;

/* Version of the loaded library (never fails). */
WEFT_API weft_version_info weft_version(void);

/* Static English description of a status code; "unknown status" for values outside the list. */
WEFT_API const char* weft_status_string(weft_status status);

#ifdef __cplusplus
}
#endif
#endif
