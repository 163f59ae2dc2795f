/* The dirty elements' grid (self_grid.h). */
#include "self_grid.h"
#include <math.h>
#include <string.h>

int wc_self_grid_side(int n_elements) {
    int g = (int)(2.0 * cbrt((double)(n_elements > 0 ? n_elements : 0)));
    return g < 8 ? 8 : (g > WC_SELF_GRID_MAX ? WC_SELF_GRID_MAX : g);
}

void wc_self_grid_reset(wc_self_grid* gr, const double* box) {
    int g = gr->g;
    memset(gr->cell, 0, (size_t)g * (size_t)g * (size_t)g);
    gr->on = 1;
    for (int k = 0; k < 3; ++k) {
        double w = box[3 + k] - box[k];
        gr->lo[k] = box[k];
        gr->inv[k] = w > 0 ? g / w : 0.0;
        if (!isfinite(gr->lo[k]) || !isfinite(gr->inv[k])) gr->on = 0;
    }
}

/* The cells [i0, i1] of the interval [a, b] on axis k; 0 when non-finite. */
static int cells(const wc_self_grid* gr, int k, double a, double b, int* i0, int* i1) {
    double ta = (a - gr->lo[k]) * gr->inv[k], tb = (b - gr->lo[k]) * gr->inv[k];
    if (!(ta == ta) || !(tb == tb)) return 0; /* NaN (infinities clamp) */
    double top = gr->g - 1;
    ta = ta < 0 ? 0 : (ta > top ? top : ta);
    tb = tb < 0 ? 0 : (tb > top ? top : tb);
    *i0 = (int)ta; /* >= 0: the truncation is the floor */
    *i1 = (int)tb;
    return 1;
}

void wc_self_grid_mark(wc_self_grid* gr, const double* box) {
    if (!gr->on) return;
    int lo[3], hi[3];
    for (int k = 0; k < 3; ++k)
        if (!cells(gr, k, box[k], box[3 + k], lo + k, hi + k) || hi[k] < lo[k]) {
            gr->on = 0;
            return;
        }
    long span = (long)(hi[0] - lo[0] + 1) * (hi[1] - lo[1] + 1) * (hi[2] - lo[2] + 1);
    if (span > WC_SELF_GRID_SPAN) {
        gr->on = 0;
        return;
    }
    int g = gr->g;
    for (int z = lo[2]; z <= hi[2]; ++z)
        for (int y = lo[1]; y <= hi[1]; ++y)
            memset(gr->cell + ((size_t)z * g + y) * g + lo[0], 1, (size_t)(hi[0] - lo[0] + 1));
}

int wc_self_grid_hits(const wc_self_grid* gr, const double* box) {
    if (!gr->on) return 1;
    int lo[3], hi[3];
    for (int k = 0; k < 3; ++k)
        if (!cells(gr, k, box[k], box[3 + k], lo + k, hi + k) || hi[k] < lo[k]) return 1;
    int g = gr->g;
    for (int z = lo[2]; z <= hi[2]; ++z)
        for (int y = lo[1]; y <= hi[1]; ++y) {
            const unsigned char* row = gr->cell + ((size_t)z * g + y) * g;
            for (int x = lo[0]; x <= hi[0]; ++x)
                if (row[x]) return 1;
        }
    return 0;
}
