#include <stdarg.h>
#include <stdio.h>

#include "cli.h"

weft_status cli_fail(cli_diag* d, weft_status status, const char* fmt, ...) {
    if (!d) return status;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(d->message, sizeof d->message, fmt, ap);
    va_end(ap);
    d->status = status;
    return status;
}
