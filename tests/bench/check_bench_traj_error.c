/* The error metric of `weft bench peers --matched` (plugin/cli/bench/bench_traj_error.c) against
 * cases worked out by hand: the bounding-box diagonal of a trajectory, the RMS over all frames
 * and points, the last frame's, zero against itself, NaN through a non-finite coordinate. */
#include <math.h>

#include "../../plugin/cli/bench/bench_traj_error.h"
#include "check.h"

/* 2 frames x 2 points. The reference: frame 0 at (0,0,0) and (1,0,0); frame 1 at (0,-2,0) and
 * (1,-2,2): its box is [0,1] x [-2,0] x [0,2], diagonal sqrt(1 + 4 + 4) = 3. */
static const float ref[12] = {0, 0, 0, 1, 0, 0, 0, -2, 0, 1, -2, 2};

static void test_diag(void) {
    CHECK_NEAR(bench_traj_diag(ref, 2, 2), 3.0, 1e-12);
    CHECK_NEAR(bench_traj_diag(ref, 1, 2), 1.0, 1e-12);   /* frame 0 alone: a unit segment */
    CHECK_NEAR(bench_traj_diag(ref, 0, 2), 0.0, 0.0);
}

static void test_error(void) {
    double all = -1, end = -1;
    bench_traj_error(ref, ref, 2, 2, &all, &end);
    CHECK(all == 0.0 && end == 0.0);
    /* point 1 of frame 0 moved by (0,0,3), point 0 of frame 1 by (4,0,0): distances 0, 3 | 4, 0.
     * all: sqrt((0 + 9 + 16 + 0) / 4) = 2.5; end: sqrt((16 + 0) / 2) = sqrt(8). */
    float x[12];
    for (int k = 0; k < 12; ++k) x[k] = ref[k];
    x[5] += 3.0f;
    x[6] += 4.0f;
    bench_traj_error(ref, x, 2, 2, &all, &end);
    CHECK_NEAR(all, 2.5, 1e-12);
    CHECK_NEAR(end, sqrt(8.0), 1e-12);
    /* symmetric */
    bench_traj_error(x, ref, 2, 2, &all, &end);
    CHECK_NEAR(all, 2.5, 1e-12);
    /* one frame: only frame 0's distances (0 and 3): sqrt(9 / 2) both */
    bench_traj_error(ref, x, 1, 2, &all, &end);
    CHECK_NEAR(all, sqrt(4.5), 1e-12);
    CHECK_NEAR(end, sqrt(4.5), 1e-12);
    /* a NaN in frame 0: all NaN, the last frame's still finite */
    x[0] = NAN;
    bench_traj_error(ref, x, 2, 2, &all, &end);
    CHECK(isnan(all));
    CHECK_NEAR(end, sqrt(8.0), 1e-12);
    bench_traj_error(ref, x, 0, 2, &all, &end);
    CHECK(all == 0.0 && end == 0.0);
}

int main(void) {
    RUN_TEST(test_diag);
    RUN_TEST(test_error);
    return TEST_SUMMARY();
}
