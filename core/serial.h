/* A cursor over a flat byte buffer that one walker function uses to count, write or read the
 * same fields in the same order (snapshots, the whole-frame backup). Fields are raw native
 * bytes, no padding: meant for the same build on the same machine. Each module walks what it
 * owns (wc_state_serial, wc_mesh_collider_serial, the cloth's walker); reading writes into the
 * walked object, so the caller checks a buffer before reading it. */
#ifndef WEFT_CORE_SERIAL_H
#define WEFT_CORE_SERIAL_H
#include <stddef.h>

typedef struct wc_serial {
    unsigned char* w;           /* write here (NULL: read or count) */
    const unsigned char* r;     /* read from here (NULL: write or count) */
    size_t off;                 /* bytes walked so far */
    int skip_mirror;            /* 1: leave out the particle arrays a device backend keeps for
                                   itself (x, v, dv, contact arrays, BDF2 history; cloth_backend.h) */
} wc_serial;

/* A cursor writing into buf, reading from buf, or counting (both NULL), from offset off. */
wc_serial wc_serial_writer(unsigned char* buf, size_t off);
wc_serial wc_serial_reader(const unsigned char* buf, size_t off);
wc_serial wc_serial_counter(size_t off);

/* n bytes at data: copied out (write), in (read) or counted. */
void wc_serial_bytes(wc_serial* k, void* data, size_t n);
/* An int as 32 bits and a long long as 64 bits (the format's widths). */
void wc_serial_i32(wc_serial* k, int* v);
void wc_serial_i64(wc_serial* k, long long* v);
/* 1 when the cursor reads (the walker then also sets what derives from the fields read). */
static inline int wc_serial_reading(const wc_serial* k) { return k->r != NULL; }

#endif
