/* AUTO's choice of a cloth's backend, as pure functions (no device, no GL): the rule, the
 * crossover table per device kind, and the override's parsing. The facade (plugin/backend.c)
 * gathers the inputs (the GPU device it opened, the GPU table's `supports` answer for the cloth,
 * the cloth's particle count) and stores the answer on the cloth; where the table's figures
 * come from is docs/design/cloth.md ("AUTO: the backend by the cloth"). */
#ifndef WEFT_CORE_BACKEND_AUTO_H
#define WEFT_CORE_BACKEND_AUTO_H
#include "status.h"

/* A crossover no cloth reaches: the device is never faster than the CPU backend. */
#define WC_AUTO_NEVER (-1L)
/* Bytes of a reason, terminating zero included (weft.h's WEFT_BACKEND_REASON_LENGTH). */
#define WC_AUTO_REASON_LENGTH 256

/* Where a crossover comes from. */
typedef enum wc_auto_source {
    WC_AUTO_TABLE = 0,          /* the table's row for the device */
    WC_AUTO_UNLISTED,           /* a hardware device the table does not list: its default row */
    WC_AUTO_SOFTWARE,           /* a software rasteriser: never */
    WC_AUTO_OVERRIDE            /* the host's override (WEFT_AUTO_CROSSOVER) */
} wc_auto_source;

/* The particles from which the GPU backend steps a cloth faster than the CPU backend on the
 * device a GL renderer string names (WC_AUTO_NEVER on a software rasteriser), and where the
 * figure comes from. */
long wc_auto_crossover(const char* renderer, int software, wc_auto_source* source);

/* The override's text: a whole number of particles >= 0 (decimal digits only, at most 10^9).
 * 1 and *out on success; 0 (nothing written) otherwise. */
int wc_auto_parse_crossover(const char* text, long* out);

typedef struct wc_auto_input {
    const char* device;         /* the GPU device's name (its GL renderer); NULL: there is none */
    const char* no_device;      /* why there is none (device NULL): "built without WEFT_GPU", EGL's failure */
    long crossover;             /* particles from which the GPU wins on this device, or WC_AUTO_NEVER */
    wc_auto_source source;      /* where crossover comes from */
    wc_status gpu_status;       /* the GPU table's `supports` for this cloth: WC_OK or its refusal
                                   (not asked, WC_OK, when crossover is WC_AUTO_NEVER) */
    const char* gpu_refusal;    /* the refusal's message (gpu_status not WC_OK) */
    int particles;              /* the cloth's, after welding */
} wc_auto_input;

typedef struct wc_auto_choice {
    int gpu;                    /* 1: the GPU backend; 0: the CPU backend */
    char reason[WC_AUTO_REASON_LENGTH]; /* one line, "AUTO: ..." (long refusals cut with "...") */
} wc_auto_choice;

/* The rule, first match: no GPU device -> CPU; a device that never wins -> CPU; a cloth the GPU
 * refuses -> CPU; fewer particles than the crossover -> CPU; else the GPU. */
void wc_auto_choose(const wc_auto_input* in, wc_auto_choice* out);

#endif
