/* Tiny test harness: CHECK records a failure and goes on; CHECK_NEAR for doubles; each test file
 * is its own executable registered with ctest, returning non-zero when any check failed. */
#ifndef WEFT_TESTS_CHECK_H
#define WEFT_TESTS_CHECK_H
#include <math.h>
#include <stdio.h>
#include <string.h>

static int check_failures_ = 0;
static int check_count_ = 0;

/* stdout line by line even into ctest's pipe, so that a test that crashes shows how far it got */
__attribute__((constructor)) static void check_line_buffered_(void) { setvbuf(stdout, NULL, _IOLBF, 0); }

#define CHECK(cond)                                                                 \
    do {                                                                            \
        ++check_count_;                                                             \
        if (!(cond)) {                                                              \
            ++check_failures_;                                                      \
            fprintf(stderr, "%s:%d: CHECK failed: %s\n", __FILE__, __LINE__, #cond); \
        }                                                                           \
    } while (0)

#define CHECK_EQ_INT(a, b)                                                              \
    do {                                                                                \
        long long a_ = (long long)(a), b_ = (long long)(b);                             \
        ++check_count_;                                                                 \
        if (a_ != b_) {                                                                 \
            ++check_failures_;                                                          \
            fprintf(stderr, "%s:%d: CHECK_EQ_INT failed: %s = %lld, %s = %lld\n",       \
                    __FILE__, __LINE__, #a, a_, #b, b_);                                \
        }                                                                               \
    } while (0)

#define CHECK_NEAR(a, b, tol)                                                            \
    do {                                                                                 \
        double a_ = (double)(a), b_ = (double)(b);                                       \
        ++check_count_;                                                                  \
        if (!(fabs(a_ - b_) <= (tol))) {                                                 \
            ++check_failures_;                                                           \
            fprintf(stderr, "%s:%d: CHECK_NEAR failed: %s = %.17g, %s = %.17g (tol %g)\n", \
                    __FILE__, __LINE__, #a, a_, #b, b_, (double)(tol));                  \
        }                                                                                \
    } while (0)

/* Run one test function, printing its name. */
#define RUN_TEST(fn)                                        \
    do {                                                    \
        int before_ = check_failures_;                      \
        fn();                                               \
        printf("%-48s %s\n", #fn, check_failures_ == before_ ? "ok" : "FAILED"); \
    } while (0)

#define TEST_SUMMARY()                                                                   \
    (printf("%d checks, %d failed\n", check_count_, check_failures_), check_failures_ ? 1 : 0)

#endif
