/* AUTO's rule and its crossover table (backend_auto.h). The figures and how they were read off
 * the measurements: docs/design/cloth.md, "AUTO: the backend by the cloth". */
#include "backend_auto.h"
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

/* One row: a device kind, named by a part of its GL renderer string. */
typedef struct crossover_row {
    const char* renderer;
    long particles;
} crossover_row;

static const crossover_row rows[] = {
    {"H100", 4000},             /* NVIDIA H100: between the 1k and 10k sheets of bench_gpu */
};

/* A hardware device no row names: the size at which the H100 was clearly ahead, for a device
 * that may be slower. */
#define UNLISTED_PARTICLES 10000L

long wc_auto_crossover(const char* renderer, int software, wc_auto_source* source) {
    if (software) {
        *source = WC_AUTO_SOFTWARE;
        return WC_AUTO_NEVER;
    }
    for (size_t k = 0; renderer && k < sizeof rows / sizeof rows[0]; ++k)
        if (strstr(renderer, rows[k].renderer)) {
            *source = WC_AUTO_TABLE;
            return rows[k].particles;
        }
    *source = WC_AUTO_UNLISTED;
    return UNLISTED_PARTICLES;
}

int wc_auto_parse_crossover(const char* text, long* out) {
    if (!text || !*text) return 0;
    long v = 0;
    for (const char* p = text; *p; ++p) {
        if (*p < '0' || *p > '9') return 0;
        v = 10 * v + (*p - '0');
        if (v > 1000000000L) return 0;
    }
    *out = v;
    return 1;
}

static const char* source_name(wc_auto_source s) {
    switch (s) {
    case WC_AUTO_TABLE: return "the table's figure for this device";
    case WC_AUTO_UNLISTED: return "the table's figure for a device it does not list";
    case WC_AUTO_OVERRIDE: return "WEFT_AUTO_CROSSOVER";
    case WC_AUTO_SOFTWARE: break;
    }
    return "never: a software rasteriser";
}

/* printf into out; a line cut by the size ends in "..." */
static void say(wc_auto_choice* out, const char* fmt, ...) __attribute__((format(printf, 2, 3)));
static void say(wc_auto_choice* out, const char* fmt, ...) {
    va_list ap;
    va_start(ap, fmt);
    int len = vsnprintf(out->reason, sizeof out->reason, fmt, ap);
    va_end(ap);
    if (len >= (int)sizeof out->reason) memcpy(out->reason + sizeof out->reason - 4, "...", 4);
}

void wc_auto_choose(const wc_auto_input* in, wc_auto_choice* out) {
    out->gpu = 0;
    const char* dev = in->device;
    if (!dev)
        say(out, "AUTO: no GPU device (%s)", in->no_device ? in->no_device : "none");
    else if (in->crossover == WC_AUTO_NEVER)
        say(out, "AUTO: %s is a software rasteriser, slower than the CPU backend at every size", dev);
    else if (in->gpu_status != WC_OK)
        say(out, "AUTO: the GPU lacks what this cloth uses (%s)", in->gpu_refusal ? in->gpu_refusal : "refused");
    else if ((long)in->particles < in->crossover)
        say(out, "AUTO: %d particles, below the GPU's crossover of %ld on %s (%s)", in->particles, in->crossover, dev,
            source_name(in->source));
    else {
        out->gpu = 1;
        say(out, "AUTO: %d particles, at or above the GPU's crossover of %ld on %s (%s), and the GPU runs all the "
                 "cloth uses", in->particles, in->crossover, dev, source_name(in->source));
    }
}
