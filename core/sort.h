/* Stable LSD radix sort of 64-bit keys carrying a 32-bit payload: the O(n) workhorse behind
 * welding, edge extraction, duplicate detection and spring de-duplication. */
#ifndef WEFT_CORE_SORT_H
#define WEFT_CORE_SORT_H
#include <stdint.h>
#include "alloc.h"

typedef struct wc_keyed { /* tagged so headers can forward-declare it */
    uint64_t key;
    int32_t val;
    int32_t pad_;
} wc_keyed;

/* Sort items[0..n) by key, stable. key_bits: the highest set bit any key may have + 1 (passes
 * over digits above it are skipped). Needs a scratch array of n items; returns 0 on allocation
 * failure (items untouched), 1 on success. */
int wc_radix_sort(wc_keyed* items, int n, int key_bits, const wc_allocator* alloc);

/* The same for bare 64-bit keys (half the memory traffic when no payload is needed). */
int wc_radix_sort_u64(uint64_t* keys, int n, int key_bits, const wc_allocator* alloc);

/* Sort v[0..n) ascending in place (qsort) and return its median (mean of the two middle values
 * for even n); 0 for n <= 0. For timings and statistics, not the simulation. */
double wc_sort_median(double* v, int n);

/* Number of bits needed to hold values 0..max_value. */
int wc_bits_for(uint64_t max_value);

#endif
