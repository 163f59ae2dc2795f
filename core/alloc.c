#include "alloc.h"
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

void* wc_calloc(const wc_allocator* a, size_t n, size_t sz) {
    if (n == 0 || sz == 0 || n > SIZE_MAX / sz) return NULL;
    size_t bytes = n * sz;
    void* p = (a && a->alloc) ? a->alloc(bytes, a->user) : malloc(bytes);
    if (p) memset(p, 0, bytes);
    return p;
}

void wc_free(const wc_allocator* a, void* p) {
    if (!p) return;
    if (a && a->free) a->free(p, a->user);
    else free(p);
}
