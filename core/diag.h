/* Diagnostics: a status code with a detailed message, and an optional per-instance logger.
 * Callers own a wc_diag; functions that fail fill it and return the same status. */
#ifndef WEFT_CORE_DIAG_H
#define WEFT_CORE_DIAG_H
#include "status.h"

typedef enum wc_log_level { WC_LOG_DEBUG, WC_LOG_INFO, WC_LOG_WARN, WC_LOG_ERROR } wc_log_level;
typedef void (*wc_log_fn)(wc_log_level level, const char* message, void* user);

typedef struct wc_diag {
    wc_status status;
    char message[512];      /* detail of the last failure, "" when ok */
    wc_log_fn log;          /* optional */
    void* log_user;
} wc_diag;

/* Record a failure (printf-style detail) and return status; also logs it at ERROR level. */
wc_status wc_fail(wc_diag* d, wc_status status, const char* fmt, ...)
    __attribute__((format(printf, 3, 4)));
/* Log through the diag's logger if any. */
void wc_log(const wc_diag* d, wc_log_level level, const char* fmt, ...)
    __attribute__((format(printf, 3, 4)));
void wc_diag_clear(wc_diag* d);
/* Put a printf-style prefix before the message of a failure already recorded (nothing is logged
 * again); returns status, the failure's. */
wc_status wc_diag_prefix(wc_diag* d, wc_status status, const char* fmt, ...) __attribute__((format(printf, 3, 4)));

#endif
