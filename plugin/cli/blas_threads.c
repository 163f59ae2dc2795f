/* The BLAS behind CHOLMOD runs its own threads: OpenBLAS (the pthread build .ci/deps.sh installs)
 * starts one per core, whatever Weft's OpenMP thread count, so a `--threads 1` run used every
 * core whenever it factorised, and on a loaded machine its times measured BLAS threads fighting
 * other work (docs/bench/collide.md). On the idle 2-core machine the wall time is the same
 * either way (sheet32's direct TR-BDF2 reference: 161 ms a frame with 1 or 2 BLAS threads): what
 * this changes is the cores a run occupies. The library must not change this process-wide
 * setting for its host; the CLI is its own host, so it does. */
#define _GNU_SOURCE
#include "cli.h"

#include <dlfcn.h>
#include <string.h>

/* dlsym returns an object pointer; it is copied into the function pointer bit for bit. */
_Static_assert(sizeof(void*) == sizeof(void (*)(void)), "function and object pointers differ");

int cli_blas_threads(int threads) {
    void* set_sym = dlsym(RTLD_DEFAULT, "openblas_set_num_threads");
    void* get_sym = dlsym(RTLD_DEFAULT, "openblas_get_num_threads");
    if (!set_sym || !get_sym) return -1;
    void (*set)(int);
    int (*get)(void);
    memcpy(&set, &set_sym, sizeof set_sym);
    memcpy(&get, &get_sym, sizeof get_sym);
    if (threads > 0) set(threads);
    return get();
}
