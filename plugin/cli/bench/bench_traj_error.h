/* The error of a simulated trajectory against a reference one (`weft bench peers --matched`):
 * both are frames x n points x 3 floats, point k of one frame being point k of the other. Pure
 * arithmetic, no library call (tests/bench/check_bench_traj_error.c checks it by hand). */
#ifndef WEFT_CLI_BENCH_TRAJ_ERROR_H
#define WEFT_CLI_BENCH_TRAJ_ERROR_H

/* The diagonal of the bounding box of every point of every frame of a trajectory (m). */
double bench_traj_diag(const float* xs, int frames, int n);

/* RMS, over all frames and all points, of the distance between x and ref at the same frame
 * (rms_all), and the same over the last frame's points alone (rms_end), in the positions' unit.
 * A non-finite coordinate makes both NaN (the last frame's: rms_end). frames or n < 1: both 0. */
void bench_traj_error(const float* ref, const float* x, int frames, int n, double* rms_all, double* rms_end);

#endif
