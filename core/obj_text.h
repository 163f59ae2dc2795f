/* An OBJ file's own vertex numbering: its `v` lines in file order and, for each `f` line with
 * >= 3 corners, the `v` index of every corner. assimp imports the geometry; this reads only what
 * assimp's output loses (which `v` line each corner came from), so that a file mesh can be
 * reported in the file's order (import_obj_order.c). */
#ifndef WEFT_CORE_OBJ_TEXT_H
#define WEFT_CORE_OBJ_TEXT_H
#include "alloc.h"
#include "diag.h"
#include <stddef.h>

typedef struct wc_obj_text {
    int n_v;              /* `v` lines */
    float* v;             /* (n_v x 3) positions as written (x/w, y/w, z/w for four numbers) */
    int n_faces;          /* `f` lines with >= 3 corners, in file order */
    int* face_start;      /* (n_faces + 1) offsets into face_v */
    int* face_v;          /* 0-based `v` index of each corner (negative indices resolved) */
    wc_allocator alloc;
} wc_obj_text;

/* Read `v` and `f` lines from text (size bytes, need not end in NUL); other lines are skipped,
 * `#` starts a comment, a line ending in a backslash continues on the next. `f` corners are
 * "v", "v/vt", "v/vt/vn" or "v//vn"; a negative v counts back from the last `v` line read.
 * Errors (*out zeroed): IMPORT naming the line for a corner index that is 0, not a number or
 * outside the `v` lines read so far; OUT_OF_MEMORY. */
wc_status wc_obj_text_read(wc_obj_text* out, const wc_allocator* alloc, const char* text,
                             size_t size, const char* name, wc_diag* diag);

void wc_obj_text_free(wc_obj_text* t);

#endif
