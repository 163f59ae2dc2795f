/* Trajectory error against a reference (bench_traj_error.h). */
#include "bench_traj_error.h"

#include <math.h>
#include <stddef.h>

double bench_traj_diag(const float* xs, int frames, int n) {
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    const size_t count = (size_t)(frames > 0 ? frames : 0) * (size_t)(n > 0 ? n : 0);
    if (count == 0) return 0.0;
    for (size_t k = 0; k < count; ++k)
        for (int c = 0; c < 3; ++c) {
            const double v = xs[3 * k + (size_t)c];
            lo[c] = fmin(lo[c], v);
            hi[c] = fmax(hi[c], v);
        }
    double d2 = 0.0;
    for (int c = 0; c < 3; ++c) d2 += (hi[c] - lo[c]) * (hi[c] - lo[c]);
    return sqrt(d2);
}

/* Sum of squared distances between a and b over n points (NaN when any coordinate is not). */
static double sum_sq(const float* a, const float* b, int n) {
    double s = 0.0;
    for (size_t k = 0; k < 3 * (size_t)n; ++k) {
        const double d = (double)a[k] - (double)b[k];
        s += d * d;
    }
    return s;
}

void bench_traj_error(const float* ref, const float* x, int frames, int n, double* rms_all, double* rms_end) {
    *rms_all = *rms_end = 0.0;
    if (frames < 1 || n < 1) return;
    const size_t stride = 3 * (size_t)n;
    double all = 0.0, last = 0.0;
    for (int f = 0; f < frames; ++f) {
        last = sum_sq(ref + stride * (size_t)f, x + stride * (size_t)f, n);
        all += last;
    }
    *rms_all = sqrt(all / ((double)frames * (double)n));
    *rms_end = sqrt(last / (double)n);
}
