/* Monotonic wall clock for stage timings. */
#ifndef WEFT_CORE_CLOCK_H
#define WEFT_CORE_CLOCK_H
double wc_now_ms(void);
/* CPU time of the process, all threads (ms): what a computation cost whatever else runs on the
 * machine (for benchmark breakdowns on a shared machine; includes threads spinning in a barrier). */
double wc_cpu_ms(void);
#endif
