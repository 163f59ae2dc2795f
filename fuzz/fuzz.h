/* Shared by the fuzz harnesses (fuzz_*.c): the libFuzzer entry points, a reader that turns the
 * fuzzer's bytes into values (running out of bytes yields zeros, never an error), and the check
 * that turns a broken guarantee into a crash the fuzzer records.
 *
 * Each harness is built twice: with libFuzzer (-DWEFT_FUZZ=ON, clang, ASan + UBSan) and, in every
 * build, as a plain replay program (replay_main.c) that ctest runs over fuzz/corpus/NAME and
 * fuzz/regressions/NAME without libFuzzer. */
#ifndef WEFT_FUZZ_H
#define WEFT_FUZZ_H
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size);
int LLVMFuzzerInitialize(int* argc, char*** argv);

/* A broken guarantee of Weft's (not a refused input): print and crash, so that libFuzzer saves
 * the input and the replay test fails. Harness code only; the library never aborts. */
#define FUZZ_CHECK(cond, ...)                                                        \
    do {                                                                             \
        if (!(cond)) {                                                               \
            fprintf(stderr, "%s:%d: FUZZ_CHECK failed: %s: ", __FILE__, __LINE__, #cond); \
            fprintf(stderr, __VA_ARGS__);                                            \
            fputc('\n', stderr);                                                     \
            __builtin_trap();                                                        \
        }                                                                            \
    } while (0)

typedef struct fuzz_reader {
    const uint8_t* p;
    size_t n;
} fuzz_reader;

static inline uint8_t fuzz_u8(fuzz_reader* r) {
    if (r->n == 0) return 0;
    --r->n;
    return *r->p++;
}

static inline uint16_t fuzz_u16(fuzz_reader* r) {
    uint16_t lo = fuzz_u8(r);
    return (uint16_t)(lo | (uint16_t)fuzz_u8(r) << 8);
}

static inline uint32_t fuzz_u32(fuzz_reader* r) {
    uint32_t lo = fuzz_u16(r);
    return lo | (uint32_t)fuzz_u16(r) << 16;
}

/* Raw bits as a float: NaN, Inf, denormals and huge values included. */
static inline float fuzz_f32_raw(fuzz_reader* r) {
    uint32_t u = fuzz_u32(r);
    float f;
    memcpy(&f, &u, sizeof f);
    return f;
}

#endif
