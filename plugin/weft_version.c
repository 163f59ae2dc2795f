/* weft_version() and weft_status_string(): the parts of the ABI that need no context. */
#include "weft/weft.h"

weft_version_info weft_version(void) {
    weft_version_info v = {WEFT_VERSION_MAJOR, WEFT_VERSION_MINOR, WEFT_VERSION_PATCH, WEFT_ABI};
    return v;
}

const char* weft_status_string(weft_status status) {
    switch (status) {
#define WEFT_STATUS_CASE_(name, value, msg) case name: return msg;
        WEFT_STATUS_LIST(WEFT_STATUS_CASE_)
#undef WEFT_STATUS_CASE_
    default: return "unknown status";
    }
}
