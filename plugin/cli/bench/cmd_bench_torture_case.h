/* Private to `weft bench torture`'s case files: a case's random numbers, the host's rigid
 * transforms, and the case being run (tc) with the calls that check the API's contract around
 * each call (cmd_bench_torture_check.c). */
#ifndef WEFT_CLI_CMD_BENCH_TORTURE_CASE_H
#define WEFT_CLI_CMD_BENCH_TORTURE_CASE_H
#include <stddef.h>
#include <stdint.h>

#include "cmd_bench_torture.h"
#include "weft/weft.h"

/* splitmix64 */
typedef struct rng {
    uint64_t s;
} rng;

/* a rigid transform, R row-major (xf_to16 makes the host's float[16], column-major) */
typedef struct xf {
    double R[9], t[3];
} xf;

#define TC_MAX_ALLOCS 64
#define TC_MAX_ATT 4
#define TC_MAX_COL 4

/* One case: the host's context, its cloth, its inputs and the checks' buffers. */
typedef struct tc {
    rng r;
    const torture_opts* o;
    torture_result* res;
    weft_context* ctx;
    weft_cloth cloth;
    int stop;                       /* a defect, or no cloth to go on with */
    int poisoned;                   /* the next call carries a NaN or Inf */
    void* allocs[TC_MAX_ALLOCS];
    int n_allocs;
    float* buf[2][4];               /* before/after: world pos, world normals, object pos, object normals */
    unsigned char* snap[2];
    size_t snap_cap[2], snap_size[2];
    int n_host;
    /* the host's current transforms */
    xf obj, att[TC_MAX_ATT], col[TC_MAX_COL];
    int n_att, n_col;
    float obj16[16], att16[16 * TC_MAX_ATT], col16[16 * TC_MAX_COL];
    double wind[3];
    void* motion_data;              /* the kind's own motion state */
} tc;

/* calloc'd memory owned by the case (freed when it ends); NULL when out of memory */
void* tc_alloc(tc* t, size_t size);
/* Record an outcome when it is worse than the one so far (a defect stops the case). */
void tc_mark(tc* t, int outcome, weft_status st, const char* where, const char* fmt, ...)
    __attribute__((format(printf, 5, 6)));
/* weft_cloth_create; a refusal stops the case. where names the call in the result. */
void tc_create_at(tc* t, const weft_cloth_def* def, const char* where);
void tc_create(tc* t, const weft_cloth_def* def);
/* weft_cloth_step / weft_cloth_set_attachments, with the checks before and after */
void tc_step(tc* t, const weft_frame* fr, const char* where);
void tc_set_attachments(tc* t, const weft_attachment_def* a, int n, const char* where);

#endif
