#include "diag.h"
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

wc_status wc_fail(wc_diag* d, wc_status status, const char* fmt, ...) {
    if (!d) return status;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(d->message, sizeof d->message, fmt, ap);
    va_end(ap);
    d->status = status;
    if (d->log) d->log(WC_LOG_ERROR, d->message, d->log_user);
    return status;
}

void wc_log(const wc_diag* d, wc_log_level level, const char* fmt, ...) {
    if (!d || !d->log) return;
    char buf[512];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(buf, sizeof buf, fmt, ap);
    va_end(ap);
    d->log(level, buf, d->log_user);
}

void wc_diag_clear(wc_diag* d) {
    if (!d) return;
    d->status = WC_OK;
    d->message[0] = '\0';
}

wc_status wc_diag_prefix(wc_diag* d, wc_status status, const char* fmt, ...) {
    if (!d) return status;
    char rest[sizeof d->message];
    memcpy(rest, d->message, sizeof rest);
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(d->message, sizeof d->message, fmt, ap);
    va_end(ap);
    size_t used = strlen(d->message), n = strlen(rest);
    if (n > sizeof d->message - 1 - used) n = sizeof d->message - 1 - used;
    memcpy(d->message + used, rest, n);
    d->message[used + n] = '\0';
    return status;
}

const char* wc_status_string(wc_status status) {
    switch (status) {
#define WC_STATUS_CASE_(name, value, msg) \
    case name: return msg;
        WC_STATUS_LIST(WC_STATUS_CASE_)
#undef WC_STATUS_CASE_
    }
    return "unknown status";
}
