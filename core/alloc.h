/* Per-instance allocator (no global state). A zeroed wc_allocator means malloc/free. */
#ifndef WEFT_CORE_ALLOC_H
#define WEFT_CORE_ALLOC_H
#include <stddef.h>

typedef struct wc_allocator {
    void* (*alloc)(size_t size, void* user);   /* returns NULL on failure */
    void (*free)(void* ptr, void* user);
    void* user;
} wc_allocator;

/* Allocate n elements of size sz (overflow-checked); zero-filled. NULL on failure or n == 0. */
void* wc_calloc(const wc_allocator* a, size_t n, size_t sz);
void wc_free(const wc_allocator* a, void* p);

#define WC_NEW(a, type, n) ((type*)wc_calloc((a), (size_t)(n), sizeof(type)))

#endif
