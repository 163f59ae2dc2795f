/* The tests' random numbers: Marsaglia's xorshift64 (13, 7, 17) from a fixed seed, so every run
 * draws the same sequence. A test that wants another seed defines TEST_RNG_SEED before including
 * this; assigning rng_state replays a sequence. */
#ifndef WEFT_TESTS_TEST_RNG_H
#define WEFT_TESTS_TEST_RNG_H

#ifndef TEST_RNG_SEED
#define TEST_RNG_SEED 0x9E3779B97F4A7C15ull
#endif

static unsigned long long rng_state = TEST_RNG_SEED;

/* Uniform in [0, 1), 53 bits. */
static inline double urand(void) {
    rng_state ^= rng_state << 13;
    rng_state ^= rng_state >> 7;
    rng_state ^= rng_state << 17;
    return (double)(rng_state >> 11) / 9007199254740992.0;
}

#endif
