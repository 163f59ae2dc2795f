/* The pre-checks before assimp (core/import_precheck.c): inputs that make assimp 5.2.5 itself
 * hang are refused with IMPORT, from a file and from memory, and well-formed ones still import. */
#include <stdio.h>
#include "check.h"
#include "source_mesh.h"

static const char ply_no_end[] = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n";
static const char ply_ok[] =
    "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
    "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 0 1\n3 0 1 2\n";

static void write_file(const char* path, const char* text) {
    FILE* f = fopen(path, "wb");
    CHECK(f != NULL);
    if (!f) return;
    fputs(text, f);
    fclose(f);
}

static void test_ply_without_end_header_file(void) {
    const char* path = WEFT_TEST_TMPDIR "/precheck_no_end.ply";
    write_file(path, ply_no_end);
    wc_source_mesh m;
    wc_diag d = {0};
    CHECK_EQ_INT(wc_import_file(&m, NULL, path, NULL, &d), WC_ERROR_IMPORT);
    CHECK(strstr(d.message, "end_header") != NULL);
    /* also under another extension: assimp recognises PLY by its "ply" signature */
    path = WEFT_TEST_TMPDIR "/precheck_no_end.obj";
    write_file(path, ply_no_end);
    CHECK_EQ_INT(wc_import_file(&m, NULL, path, NULL, &d), WC_ERROR_IMPORT);
}

static void test_ply_without_end_header_memory(void) {
    wc_source_mesh m;
    wc_diag d = {0};
    CHECK_EQ_INT(wc_import_memory(&m, NULL, ply_no_end, sizeof ply_no_end - 1, "ply", NULL, &d), WC_ERROR_IMPORT);
    CHECK(strstr(d.message, "end_header") != NULL);
    CHECK(strstr(d.message, "<memory>.ply") != NULL);
}

/* the other shapes of a header assimp 5.2.5 never finishes, found by fuzz_import */
static void test_end_header_not_a_line(void) {
    static const char inside[] = "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n0 1end_header\n0\n";
    static const char ctrl_z[] = "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nend_header\x1a" "0\n";
    static const char at_end[] =
        "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nelement face 0\n"
        "property list uchar int vertex_indices\nend_header";
    wc_source_mesh m;
    wc_diag d = {0};
    CHECK_EQ_INT(wc_import_memory(&m, NULL, inside, sizeof inside - 1, "ply", NULL, &d), WC_ERROR_IMPORT);
    CHECK_EQ_INT(wc_import_memory(&m, NULL, ctrl_z, sizeof ctrl_z - 1, "ply", NULL, &d), WC_ERROR_IMPORT);
    CHECK(strstr(d.message, "end_header") != NULL);
    /* end_header as the last bytes is a complete header: assimp answers (no faces: not a mesh) */
    wc_status st = wc_import_memory(&m, NULL, at_end, sizeof at_end - 1, "ply", NULL, &d);
    CHECK(st != WC_OK && strstr(d.message, "end_header line") == NULL);
}

/* two "element vertex" lines: assimp 5.2.5 corrupts its heap (a bad free found by fuzz_import) */
static void test_element_declared_twice(void) {
    static const char twice[] =
        "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nelement vertex 3\nproperty float x\n"
        "property float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
        "0\n0 0 0\n1 0 0\n0 0 1\n3 0 1 2\n";
    wc_source_mesh m;
    wc_diag d = {0};
    CHECK_EQ_INT(wc_import_memory(&m, NULL, twice, sizeof twice - 1, "ply", NULL, &d), WC_ERROR_IMPORT);
    CHECK(strstr(d.message, "'vertex' twice") != NULL);
    const char* path = WEFT_TEST_TMPDIR "/precheck_twice.ply";
    write_file(path, twice);
    CHECK_EQ_INT(wc_import_file(&m, NULL, path, NULL, &d), WC_ERROR_IMPORT);
    CHECK(strstr(d.message, "'vertex' twice") != NULL);
}

static void test_good_ply_still_imports(void) {
    wc_source_mesh m;
    wc_diag d = {0};
    CHECK_EQ_INT(wc_import_memory(&m, NULL, ply_ok, sizeof ply_ok - 1, "ply", NULL, &d), WC_OK);
    CHECK_EQ_INT(m.n_polys, 1);
    wc_source_mesh_free(&m);
    const char* path = WEFT_TEST_TMPDIR "/precheck_ok.ply";
    write_file(path, ply_ok);
    CHECK_EQ_INT(wc_import_file(&m, NULL, path, NULL, &d), WC_OK);
    CHECK_EQ_INT(m.n_verts, 3);
    wc_source_mesh_free(&m);
}

static void test_memory_arguments(void) {
    wc_source_mesh m;
    wc_diag d = {0};
    CHECK_EQ_INT(wc_import_memory(&m, NULL, NULL, 3, "obj", NULL, &d), WC_ERROR_INVALID_ARGUMENT);
    CHECK_EQ_INT(wc_import_memory(&m, NULL, "v", 1, NULL, NULL, &d), WC_ERROR_INVALID_ARGUMENT);
    CHECK_EQ_INT(wc_import_memory(&m, NULL, "v", 1, "a_very_long_hint_here", NULL, &d), WC_ERROR_INVALID_ARGUMENT);
    CHECK_EQ_INT(wc_import_memory(&m, NULL, "v", 0, "obj", NULL, &d), WC_ERROR_IMPORT);
}

int main(void) {
    RUN_TEST(test_ply_without_end_header_file);
    RUN_TEST(test_ply_without_end_header_memory);
    RUN_TEST(test_end_header_not_a_line);
    RUN_TEST(test_element_declared_twice);
    RUN_TEST(test_good_ply_still_imports);
    RUN_TEST(test_memory_arguments);
    return TEST_SUMMARY();
}
