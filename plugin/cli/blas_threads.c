/* The BLAS behind CHOLMOD runs its own threads: OpenBLAS (the pthread build .ci/deps.sh installs)
 * starts one per core and spins them, whatever Weft's OpenMP thread count. A `--threads N` run
 * would then use more cores than N, and its wall times would measure BLAS threads fighting the
 * OpenMP ones on a loaded machine (docs/bench/collide.md). The library must not change this
 * process-wide setting for its host; the CLI is its own host, so it does. */
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
