/* Test fixture for test_loader: a library exporting every function of weft.h, as a build of an
 * older ABI would, whose weft_version() reports ABI WEFT_FIXTURE_ABI. The loader must refuse it
 * before calling anything else; the stubs are never called (dlsym does not see types). */
#include "weft_loader_functions.h"

#define FIXTURE_STUB_(ret, name, params)                             \
    __attribute__((visibility("default"))) void name(void);           \
    void name(void) {}
/* weft_version is defined for real below; its stub goes under another name. */
#define weft_version weft_fixture_version_stub
WEFT_LOADER_FUNCTIONS(FIXTURE_STUB_)
#undef weft_version

typedef struct fixture_version_info {
    int major, minor, patch, abi;
} fixture_version_info; /* weft_version_info's layout */

__attribute__((visibility("default"))) fixture_version_info weft_version(void);
fixture_version_info weft_version(void) {
    fixture_version_info v = {0, 1, 0, WEFT_FIXTURE_ABI};
    return v;
}
