/* Monotonic wall clock for stage timings. */
#ifndef WEFT_CORE_CLOCK_H
#define WEFT_CORE_CLOCK_H
double wc_now_ms(void);
#endif
