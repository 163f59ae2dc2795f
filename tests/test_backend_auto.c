/* AUTO's rule (core/backend_auto.h) without a device: each branch of wc_auto_choose with its
 * reason (no device, a software device, the GPU's refusal, below, at and above the crossover,
 * the override named), a refusal too long for the reason cut with "...", the crossover table's
 * rows (a listed device, an unlisted one, a software rasteriser), and the override's parsing with
 * every bad text refused and nothing written. */
#include <stdio.h>
#include <string.h>
#include "backend_auto.h"
#include "check.h"

/* A hardware device with the table's row, asked nothing yet. */
static wc_auto_input h100(int particles) {
    wc_auto_input in;
    memset(&in, 0, sizeof in);
    in.device = "NVIDIA H100 80GB HBM3/PCIe/SSE2";
    in.source = WC_AUTO_TABLE;
    in.crossover = 4000;
    in.gpu_status = WC_OK;
    in.particles = particles;
    return in;
}

static int has(const wc_auto_choice* c, const char* text) {
    if (strstr(c->reason, text)) return 1;
    fprintf(stderr, "  reason \"%s\" lacks \"%s\"\n", c->reason, text);
    return 0;
}

static void test_rule(void) {
    wc_auto_choice c;
    /* no device: the CPU, saying why there is none */
    wc_auto_input in = h100(1000000);
    in.device = NULL;
    in.no_device = "this libweft.so was built without WEFT_GPU";
    wc_auto_choose(&in, &c);
    CHECK_EQ_INT(c.gpu, 0);
    CHECK(has(&c, "AUTO: no GPU device (this libweft.so was built without WEFT_GPU)"));

    /* a software rasteriser never wins, however large the cloth */
    in = h100(1000000);
    in.device = "llvmpipe (LLVM 15.0.6, 256 bits)";
    in.crossover = WC_AUTO_NEVER;
    in.source = WC_AUTO_SOFTWARE;
    wc_auto_choose(&in, &c);
    CHECK_EQ_INT(c.gpu, 0);
    CHECK(has(&c, "llvmpipe (LLVM 15.0.6, 256 bits) is a software rasteriser"));

    /* a feature the GPU refuses: the CPU, with the refusal, however large the cloth */
    in = h100(1000000);
    in.gpu_status = WC_ERROR_UNSUPPORTED;
    in.gpu_refusal = "GPU backend: the GPU backend has no direct solver";
    wc_auto_choose(&in, &c);
    CHECK_EQ_INT(c.gpu, 0);
    CHECK(has(&c, "AUTO: the GPU lacks what this cloth uses (GPU backend: the GPU backend has no direct solver)"));

    /* small: the CPU; at the crossover and above: the GPU; the figure and its source named */
    in = h100(3999);
    wc_auto_choose(&in, &c);
    CHECK_EQ_INT(c.gpu, 0);
    CHECK(has(&c, "AUTO: 3999 particles, below the GPU's crossover of 4000 on NVIDIA H100"));
    CHECK(has(&c, "the table's figure for this device"));
    in = h100(4000);
    wc_auto_choose(&in, &c);
    CHECK_EQ_INT(c.gpu, 1);
    CHECK(has(&c, "AUTO: 4000 particles, at or above the GPU's crossover of 4000 on NVIDIA H100"));
    in = h100(250000);
    wc_auto_choose(&in, &c);
    CHECK_EQ_INT(c.gpu, 1);

    /* an unlisted device: its row named */
    in = h100(12000);
    in.device = "NVIDIA GeForce RTX 4070/PCIe/SSE2";
    in.crossover = 10000;
    in.source = WC_AUTO_UNLISTED;
    wc_auto_choose(&in, &c);
    CHECK_EQ_INT(c.gpu, 1);
    CHECK(has(&c, "a device it does not list"));

    /* the override: 0 takes every cloth the GPU runs, a software device included */
    in = h100(1);
    in.device = "llvmpipe (LLVM 15.0.6, 256 bits)";
    in.crossover = 0;
    in.source = WC_AUTO_OVERRIDE;
    wc_auto_choose(&in, &c);
    CHECK_EQ_INT(c.gpu, 1);
    CHECK(has(&c, "(WEFT_AUTO_CROSSOVER)"));
    in.crossover = 2;
    wc_auto_choose(&in, &c);
    CHECK_EQ_INT(c.gpu, 0);
    CHECK(has(&c, "below the GPU's crossover of 2"));
}

/* A refusal longer than the reason: cut, ending in "...", terminated within the array. */
static void test_long_refusal(void) {
    char refusal[600];
    memset(refusal, 'x', sizeof refusal - 1);
    refusal[sizeof refusal - 1] = '\0';
    wc_auto_input in = h100(100000);
    in.gpu_status = WC_ERROR_UNSUPPORTED;
    in.gpu_refusal = refusal;
    wc_auto_choice c;
    memset(&c, 0x55, sizeof c);
    wc_auto_choose(&in, &c);
    CHECK_EQ_INT(c.gpu, 0);
    CHECK_EQ_INT((int)strlen(c.reason), WC_AUTO_REASON_LENGTH - 1);
    CHECK(strcmp(c.reason + WC_AUTO_REASON_LENGTH - 4, "...") == 0);
    CHECK(strncmp(c.reason, "AUTO: the GPU lacks", 19) == 0);
}

static void test_table(void) {
    wc_auto_source src = WC_AUTO_OVERRIDE;
    CHECK_EQ_INT((int)wc_auto_crossover("NVIDIA H100 80GB HBM3/PCIe/SSE2", 0, &src), 4000);
    CHECK_EQ_INT(src, WC_AUTO_TABLE);
    CHECK_EQ_INT((int)wc_auto_crossover("NVIDIA GeForce RTX 4070/PCIe/SSE2", 0, &src), 10000);
    CHECK_EQ_INT(src, WC_AUTO_UNLISTED);
    CHECK_EQ_INT((int)wc_auto_crossover(NULL, 0, &src), 10000);
    CHECK_EQ_INT(src, WC_AUTO_UNLISTED);
    /* software: never, whatever the name says */
    CHECK(wc_auto_crossover("llvmpipe (LLVM 15.0.6, 256 bits)", 1, &src) == WC_AUTO_NEVER);
    CHECK_EQ_INT(src, WC_AUTO_SOFTWARE);
    CHECK(wc_auto_crossover("H100 emulated", 1, &src) == WC_AUTO_NEVER);
}

static void test_parse(void) {
    long v = -7;
    CHECK(wc_auto_parse_crossover("0", &v) && v == 0);
    CHECK(wc_auto_parse_crossover("4000", &v) && v == 4000);
    CHECK(wc_auto_parse_crossover("1000000000", &v) && v == 1000000000L);
    const char* bad[] = {NULL, "", "-1", "+5", " 12", "12 ", "1e4", "12a", "0x10", "4.5", "1000000001",
                         "99999999999999999999999"};
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; ++k) {
        v = -7;
        CHECK_EQ_INT(wc_auto_parse_crossover(bad[k], &v), 0);
        CHECK_EQ_INT((int)v, -7);   /* nothing written */
    }
}

int main(void) {
    RUN_TEST(test_rule);
    RUN_TEST(test_long_refusal);
    RUN_TEST(test_table);
    RUN_TEST(test_parse);
    return TEST_SUMMARY();
}
