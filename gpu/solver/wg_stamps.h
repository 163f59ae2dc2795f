/* GL timestamps of one cloth's frame, each tagged with what starts at it, resolved into time
 * per tag after the frame's last read-back. Without timer queries (wg_device.has_timer 0) every
 * call does nothing. Calls are made with the cloth's GL context current. */
#ifndef WEFT_GPU_SOLVER_STAMPS_H
#define WEFT_GPU_SOLVER_STAMPS_H

#include <GL/glew.h>

#define WG_MAX_STAMPS 96

typedef struct wg_stamps {
    int on;                     /* the device has timer queries */
    GLuint query[WG_MAX_STAMPS];
    int tag[WG_MAX_STAMPS];
    int n;
} wg_stamps;

void wg_stamps_create(wg_stamps* s, int has_timer);
void wg_stamps_destroy(wg_stamps* s);
/* Forget the last frame's stamps. */
void wg_stamps_reset(wg_stamps* s);
/* A timestamp now, opening a span of `tag` that lasts until the next stamp (ignored past
 * WG_MAX_STAMPS). */
void wg_stamp(wg_stamps* s, int tag);
/* ms[tag] += the span's milliseconds for every span whose tag is in [0, n_tags) (a tag outside
 * it closes the span before it and opens none); waits for the queries. Returns 0, leaving ms
 * alone, when there are fewer than two stamps. */
int wg_stamps_collect(const wg_stamps* s, double* ms, int n_tags);

#endif
