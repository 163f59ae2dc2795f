/* `weft bench torture`: randomised host inputs thrown at the public API (weft.h only).
 *   cmd_bench_torture.c        the driver: options, one forked child per case, the tables
 *   cmd_bench_torture_cases.c  the case generators and the checks made around every call
 * Every case is reproducible from (seed, case index, kind): its random numbers come from a
 * splitmix64 generator seeded with those three, and nothing else. */
#ifndef WEFT_CLI_CMD_BENCH_TORTURE_H
#define WEFT_CLI_CMD_BENCH_TORTURE_H
#include <stdint.h>

/* Case kinds, in the order cases cycle through them. */
typedef enum torture_kind {
    TK_RANDOM_MESH, /* triangle soups and sheets with degenerate triangles, slivers, stray vertices */
    TK_TELEPORT,    /* object and attachment transforms jumping 1 km, with and without TELEPORT */
    TK_SPIN,        /* object, attachment and collider transforms spinning at 100 rad/s */
    TK_NAN_INJECT,  /* NaN or +-Inf in one host input, at creation or mid-run */
    TK_ZERO_AREA,   /* every vertex coincident, or every vertex on one line */
    TK_ONE_PARTICLE,/* one vertex; one triangle whose vertices coincide */
    TK_EXTREME,     /* parameters at the far ends of their ranges */
    TK_COUNT
} torture_kind;

/* Outcomes, from best to worst (a case reports the worst it met). From TO_NONFINITE on they
 * are defects. */
typedef enum torture_outcome {
    TO_OK,            /* every call WEFT_OK, every output finite */
    TO_REJECTED,      /* a call refused its input with a status and a message, nothing changed */
    TO_STEP_FAILED,   /* WEFT_ERROR_STEP_FAILED, the cloth finite and as before the call */
    TO_NONFINITE,     /* a non-finite output after a call that returned WEFT_OK */
    TO_STATE_CHANGED, /* a refused call changed the cloth (vertices or snapshot) */
    TO_EMPTY_MESSAGE, /* a non-OK status without a message */
    TO_ACCEPTED,      /* a NaN or Inf input was accepted (WEFT_OK) */
    TO_CRASH,         /* the case's process died (a signal, or no result) */
    TO_HANG,          /* the case's process ran past --case-timeout */
    TO_COUNT
} torture_outcome;

#define TO_FIRST_DEFECT TO_NONFINITE

/* What one case reports (written by the child into a pipe: plain data only). */
typedef struct torture_result {
    int outcome;            /* torture_outcome */
    int status;             /* weft_status of the call that decided the outcome (WEFT_OK for ok) */
    int calls;              /* API calls made */
    int frames;             /* frames stepped with WEFT_OK */
    int vertices;           /* host vertices of the cloth (0: none created) */
    char where[48];         /* the call that decided the outcome ("create", "step 3", ...) */
    char detail[200];       /* its message (weft_context_last_error) or what the defect was */
} torture_result;

/* Sizes of the generated cases. */
typedef struct torture_opts {
    int threads;            /* weft_context_def.threads */
    int backend;            /* weft_context_def.backend (weft_backend: 0 AUTO, 1 CPU, 2 GPU) */
    int max_grid;           /* largest sheet side (vertices) */
    int max_frames;         /* most frames per case */
} torture_opts;

const char* torture_kind_name(int kind);
/* -1 when name is no kind */
int torture_kind_from_name(const char* name);
const char* torture_outcome_name(int outcome);

/* Run one case in this process (creates and destroys its own weft_context). */
void torture_run_case(int kind, uint64_t seed, int index, const torture_opts* o, torture_result* out);

#endif
