#include "sort.h"
#include <stdlib.h>
#include <string.h>

int wc_bits_for(uint64_t max_value) {
    int b = 0;
    while (b < 64 && (max_value >> b) != 0) ++b;
    return b > 0 ? b : 1;
}

enum { DIGIT_BITS = 11, RADIX = 1 << DIGIT_BITS };

/* One LSD radix sort body for both element types; KEY(x) reads an element's key. */
#define WC_RADIX_SORT_BODY(TYPE, KEY)                                                    \
    if (n <= 1) return 1;                                                                \
    TYPE* tmp = WC_NEW(alloc, TYPE, n);                                                  \
    if (!tmp) return 0;                                                                  \
    int* count = WC_NEW(alloc, int, RADIX);                                              \
    if (!count) {                                                                        \
        wc_free(alloc, tmp);                                                             \
        return 0;                                                                        \
    }                                                                                    \
    TYPE* src = items;                                                                   \
    TYPE* dst = tmp;                                                                     \
    for (int shift = 0; shift < key_bits; shift += DIGIT_BITS) {                         \
        memset(count, 0, sizeof(int) * RADIX);                                           \
        for (int i = 0; i < n; ++i) ++count[(KEY(src[i]) >> shift) & (RADIX - 1)];      \
        if (count[(KEY(src[0]) >> shift) & (RADIX - 1)] == n) continue;                  \
        int sum = 0;                                                                     \
        for (int d = 0; d < RADIX; ++d) {                                                \
            int c = count[d];                                                            \
            count[d] = sum;                                                              \
            sum += c;                                                                    \
        }                                                                                \
        for (int i = 0; i < n; ++i) dst[count[(KEY(src[i]) >> shift) & (RADIX - 1)]++] = src[i]; \
        TYPE* t = src;                                                                   \
        src = dst;                                                                       \
        dst = t;                                                                         \
    }                                                                                    \
    if (src != items) memcpy(items, src, sizeof(TYPE) * (size_t)n);                      \
    wc_free(alloc, count);                                                               \
    wc_free(alloc, tmp);                                                                 \
    return 1;

#define KEYED_KEY(x) ((x).key)
#define BARE_KEY(x) (x)

int wc_radix_sort(wc_keyed* items, int n, int key_bits, const wc_allocator* alloc) {
    WC_RADIX_SORT_BODY(wc_keyed, KEYED_KEY)
}

int wc_radix_sort_u64(uint64_t* items, int n, int key_bits, const wc_allocator* alloc) {
    WC_RADIX_SORT_BODY(uint64_t, BARE_KEY)
}

static int cmp_double(const void* a, const void* b) {
    double x = *(const double*)a, y = *(const double*)b;
    return (x > y) - (x < y);
}

double wc_sort_median(double* v, int n) {
    if (n <= 0) return 0.0;
    qsort(v, (size_t)n, sizeof(double), cmp_double);
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}
