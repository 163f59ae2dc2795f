/* What the `weft bench` checkers share (check_weft_bench_*.c, one program per subcommand, run
 * as a user would through WEFT_CLI): a GPU context that cannot be made is a clear failure. */
#ifndef WEFT_TESTS_CHECK_WEFT_BENCH_H
#define WEFT_TESTS_CHECK_WEFT_BENCH_H
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "test_support.h"

/* A GPU context that cannot be made: a clear message and exit 1, nothing on stdout. */
static inline void test_gpu_unavailable(const char* sub) {
    static ts_cli_result r;
    char args[256];
    snprintf(args, sizeof args, "bench %s --quick --quiet --backend cpu,gpu", sub);
    setenv("WEFT_EGL_DEVICE", "no-such-device", 1);
    ts_run_cli(args, &r);
    unsetenv("WEFT_EGL_DEVICE");
    CHECK_EQ_INT(r.rc, 1);
    CHECK(strstr(r.err, "--backend gpu: cannot create a headless GL context") != NULL);
    if (!strstr(r.err, "--backend gpu")) fprintf(stderr, "stderr: %s\n", r.err);
    CHECK(r.out[0] == '\0');
}

#endif
