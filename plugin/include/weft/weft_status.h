/* Weft status codes. Every fallible call returns one; weft_status_string() names it.
 * Stand-alone header (no other includes) so that core/ and hosts share one list. */
#ifndef WEFT_STATUS_H
#define WEFT_STATUS_H

/* X-macro: (name, value, message). Values are part of the ABI: append only. */
#define WEFT_STATUS_LIST(X)                                                            \
    X(WEFT_OK, 0, "ok")                                                                \
    X(WEFT_ERROR_INVALID_ARGUMENT, 1, "invalid argument")                              \
    X(WEFT_ERROR_OUT_OF_MEMORY, 2, "out of memory")                                    \
    X(WEFT_ERROR_IO, 3, "file could not be read or written")                           \
    X(WEFT_ERROR_IMPORT, 4, "mesh import failed")                                      \
    X(WEFT_ERROR_EMPTY_MESH, 5, "mesh has no usable triangles")                        \
    X(WEFT_ERROR_NONFINITE, 6, "non-finite (NaN or Inf) value")                        \
    X(WEFT_ERROR_OUT_OF_RANGE, 7, "index or value out of range")                       \
    X(WEFT_ERROR_SOLVER_DIVERGED, 8, "linear solver diverged")                         \
    X(WEFT_ERROR_SOLVER_NOT_CONVERGED, 9, "linear solver did not converge")            \
    X(WEFT_ERROR_FACTORIZATION, 10, "direct solver factorisation failed")              \
    X(WEFT_ERROR_STEP_FAILED, 11, "time step failed after every recovery attempt")     \
    X(WEFT_ERROR_SCENE, 12, "invalid scene description")                               \
    X(WEFT_ERROR_ABI_MISMATCH, 13, "ABI version mismatch")                             \
    X(WEFT_ERROR_INVALID_HANDLE, 14, "invalid, stale or destroyed handle")             \
    X(WEFT_ERROR_CALL_ORDER, 15, "call out of order")                                  \
    X(WEFT_ERROR_UNSUPPORTED, 16, "not supported by this build or backend")                 \
    X(WEFT_ERROR_SNAPSHOT_MISMATCH, 17, "snapshot belongs to another model or version") \
    X(WEFT_ERROR_GPU, 18, "EGL/OpenGL failure (no device, context or framebuffer)")                 \
    X(WEFT_ERROR_CONCURRENT_CALL, 19, "another thread is inside a call on this context (threading contract)")

typedef enum weft_status {
#define WEFT_STATUS_ENUM_(name, value, msg) name = value,
    WEFT_STATUS_LIST(WEFT_STATUS_ENUM_)
#undef WEFT_STATUS_ENUM_
    WEFT_STATUS_COUNT_
} weft_status;

#endif
