/* Core's status codes. Every fallible core (and gpu/) function returns one, with the detail in a
 * wc_diag (diag.h). The plugin maps them onto the public weft_status (wa_status, plugin/context.c);
 * the values are the same numbers for readability, not by contract. */
#ifndef WEFT_CORE_STATUS_H
#define WEFT_CORE_STATUS_H

/* X-macro: (name, value, message). */
#define WC_STATUS_LIST(X)                                                                    \
    X(WC_OK, 0, "ok")                                                                        \
    X(WC_ERROR_INVALID_ARGUMENT, 1, "invalid argument")                                      \
    X(WC_ERROR_OUT_OF_MEMORY, 2, "out of memory")                                            \
    X(WC_ERROR_IO, 3, "file could not be read or written")                                   \
    X(WC_ERROR_IMPORT, 4, "mesh import failed")                                              \
    X(WC_ERROR_EMPTY_MESH, 5, "mesh has no usable triangles")                                \
    X(WC_ERROR_NONFINITE, 6, "non-finite (NaN or Inf) value")                                \
    X(WC_ERROR_OUT_OF_RANGE, 7, "index or value out of range")                               \
    X(WC_ERROR_SOLVER_DIVERGED, 8, "linear solver diverged")                                 \
    X(WC_ERROR_SOLVER_NOT_CONVERGED, 9, "linear solver did not converge")                    \
    X(WC_ERROR_FACTORIZATION, 10, "direct solver factorisation failed")                      \
    X(WC_ERROR_STEP_FAILED, 11, "time step failed after every recovery attempt")             \
    X(WC_ERROR_CALL_ORDER, 15, "call out of order")                                          \
    X(WC_ERROR_UNSUPPORTED, 16, "not supported by this build or backend")                    \
    X(WC_ERROR_SNAPSHOT_MISMATCH, 17, "snapshot belongs to another model or version")        \
    X(WC_ERROR_GPU, 18, "EGL/OpenGL failure (no device, context or framebuffer)")

typedef enum wc_status {
#define WC_STATUS_ENUM_(name, value, msg) name = value,
    WC_STATUS_LIST(WC_STATUS_ENUM_)
#undef WC_STATUS_ENUM_
} wc_status;

/* Static English description ("unknown status" for a value outside the list). */
const char* wc_status_string(wc_status status);

#endif
