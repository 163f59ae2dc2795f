/* A frame's GL timestamps (see wg_stamps.h). */
#include "wg_stamps.h"

void wg_stamps_create(wg_stamps* s, int has_timer) {
    s->on = has_timer;
    s->n = 0;
    if (s->on) glGenQueries(WG_MAX_STAMPS, s->query);
}

void wg_stamps_destroy(wg_stamps* s) {
    if (s->on) glDeleteQueries(WG_MAX_STAMPS, s->query);
    s->on = 0;
    s->n = 0;
}

void wg_stamps_reset(wg_stamps* s) { s->n = 0; }

void wg_stamp(wg_stamps* s, int tag) {
    if (!s->on || s->n >= WG_MAX_STAMPS) return;
    glQueryCounter(s->query[s->n], GL_TIMESTAMP);
    s->tag[s->n++] = tag;
}

int wg_stamps_collect(const wg_stamps* s, double* ms, int n_tags) {
    if (!s->on || s->n < 2) return 0;
    GLuint64 prev = 0;
    for (int k = 0; k < s->n; ++k) {
        GLuint64 t = 0;
        glGetQueryObjectui64v(s->query[k], GL_QUERY_RESULT, &t);
        if (k > 0 && s->tag[k - 1] >= 0 && s->tag[k - 1] < n_tags) ms[s->tag[k - 1]] += (double)(t - prev) * 1e-6;
        prev = t;
    }
    return 1;
}
