/* The serialisation cursor (serial.h). */
#include "serial.h"
#include <stdint.h>
#include <string.h>

wc_serial wc_serial_writer(unsigned char* buf, size_t off) {
    wc_serial k = {buf, NULL, off, 0};
    return k;
}

wc_serial wc_serial_reader(const unsigned char* buf, size_t off) {
    wc_serial k = {NULL, buf, off, 0};
    return k;
}

wc_serial wc_serial_counter(size_t off) {
    wc_serial k = {NULL, NULL, off, 0};
    return k;
}

void wc_serial_bytes(wc_serial* k, void* data, size_t n) {
    if (n == 0) return;
    if (k->w) memcpy(k->w + k->off, data, n);
    else if (k->r) memcpy(data, k->r + k->off, n);
    k->off += n;
}

void wc_serial_i32(wc_serial* k, int* v) {
    int32_t x = (int32_t)*v;
    wc_serial_bytes(k, &x, sizeof x);
    *v = (int)x;
}

void wc_serial_i64(wc_serial* k, long long* v) {
    int64_t x = (int64_t)*v;
    wc_serial_bytes(k, &x, sizeof x);
    *v = (long long)x;
}
