#include "sort.h"
#include <string.h>

int wc_bits_for(uint64_t max_value) {
    int b = 0;
    while (b < 64 && (max_value >> b) != 0) ++b;
    return b > 0 ? b : 1;
}

enum { DIGIT_BITS = 11, RADIX = 1 << DIGIT_BITS };

int wc_radix_sort(wc_keyed* items, int n, int key_bits, const wc_allocator* alloc) {
    if (n <= 1) return 1;
    wc_keyed* tmp = WC_NEW(alloc, wc_keyed, n);
    if (!tmp) return 0;
    int* count = WC_NEW(alloc, int, RADIX);
    if (!count) {
        wc_free(alloc, tmp);
        return 0;
    }
    wc_keyed* src = items;
    wc_keyed* dst = tmp;
    for (int shift = 0; shift < key_bits; shift += DIGIT_BITS) {
        memset(count, 0, sizeof(int) * RADIX);
        for (int i = 0; i < n; ++i) ++count[(src[i].key >> shift) & (RADIX - 1)];
        if (count[(src[0].key >> shift) & (RADIX - 1)] == n) continue; /* one digit value */
        int sum = 0;
        for (int d = 0; d < RADIX; ++d) {
            int c = count[d];
            count[d] = sum;
            sum += c;
        }
        for (int i = 0; i < n; ++i) dst[count[(src[i].key >> shift) & (RADIX - 1)]++] = src[i];
        wc_keyed* t = src;
        src = dst;
        dst = t;
    }
    if (src != items) memcpy(items, src, sizeof(wc_keyed) * (size_t)n);
    wc_free(alloc, count);
    wc_free(alloc, tmp);
    return 1;
}
