/* Test fixture for test_loader: a shared library that opens fine but exports none of weft.h's
 * functions (the loader must answer "missing symbol weft_version"). */
__attribute__((visibility("default"))) int weft_fixture_unrelated(void);
int weft_fixture_unrelated(void) { return 42; }
