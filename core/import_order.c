/* wc_file_order's storage (import_order.h). */
#include "import_order.h"
#include <string.h>

wc_status wc_file_order_alloc(wc_file_order* out, const wc_allocator* alloc, int n_v,
                                int n_corners, const char* path, wc_diag* diag) {
    memset(out, 0, sizeof *out);
    if (alloc) out->alloc = *alloc;
    out->v = WC_NEW(&out->alloc, double, 3 * (size_t)n_v + 1);
    out->corner_v = WC_NEW(&out->alloc, int, (size_t)n_corners + 1);
    if (!out->v || !out->corner_v) {
        wc_file_order_free(out);
        return wc_fail(diag, WC_ERROR_OUT_OF_MEMORY, "'%s': out of memory for %d vertices", path,
                       n_v);
    }
    out->n_v = n_v;
    out->n_corners = n_corners;
    return WC_OK;
}

void wc_file_order_free(wc_file_order* o) {
    if (!o) return;
    wc_allocator a = o->alloc;
    wc_free(&a, o->v);
    wc_free(&a, o->corner_v);
    memset(o, 0, sizeof *o);
}
