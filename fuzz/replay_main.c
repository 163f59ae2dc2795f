/* Replays inputs through a harness's LLVMFuzzerTestOneInput without libFuzzer: every file named
 * on the command line, and every regular file in every folder named (not recursive), in name
 * order. This is what ctest runs over fuzz/corpus/NAME and fuzz/regressions/NAME, so every input
 * that once crashed stays a test. Exit status 0 when every input ran (a broken guarantee
 * crashes the program, as under the fuzzer), 1 on a file or folder that cannot be read. */
#define _POSIX_C_SOURCE 200809L
#include <dirent.h>
#include <stdlib.h>
#include <sys/stat.h>
#include "fuzz.h"

__attribute__((weak)) int LLVMFuzzerInitialize(int* argc, char*** argv) {
    (void)argc;
    (void)argv;
    return 0;
}

static int run_file(const char* path) {
    FILE* f = fopen(path, "rb");
    if (!f) {
        fprintf(stderr, "replay: cannot open %s\n", path);
        return 1;
    }
    size_t cap = 1 << 16, n = 0;
    uint8_t* buf = malloc(cap);
    for (;;) {
        if (!buf) break;
        size_t got = fread(buf + n, 1, cap - n, f);
        n += got;
        if (n < cap) break;
        uint8_t* grown = realloc(buf, cap * 2);
        if (!grown) { free(buf); buf = NULL; break; }
        buf = grown;
        cap *= 2;
    }
    fclose(f);
    if (!buf) {
        fprintf(stderr, "replay: out of memory reading %s\n", path);
        return 1;
    }
    /* a private copy of exactly n bytes, so that ASan sees any read past the input */
    uint8_t* exact = malloc(n ? n : 1);
    if (!exact) { free(buf); return 1; }
    memcpy(exact, buf, n);
    free(buf);
    printf("replay: %s (%zu bytes)\n", path, n);
    fflush(stdout);
    LLVMFuzzerTestOneInput(exact, n);
    free(exact);
    return 0;
}

static int cmp_names(const void* a, const void* b) {
    return strcmp(*(char* const*)a, *(char* const*)b);
}

static int run_dir(const char* dir, int* count) {
    DIR* d = opendir(dir);
    if (!d) {
        fprintf(stderr, "replay: cannot open folder %s\n", dir);
        return 1;
    }
    char** names = NULL;
    size_t n = 0, cap = 0;
    int bad = 0;
    struct dirent* e;
    while ((e = readdir(d)) != NULL) {
        if (e->d_name[0] == '.') continue;   /* ., .., .gitkeep */
        size_t len = strlen(dir) + strlen(e->d_name) + 2;
        char* path = malloc(len);
        if (!path) { bad = 1; break; }
        snprintf(path, len, "%s/%s", dir, e->d_name);
        struct stat st;
        if (stat(path, &st) != 0 || !S_ISREG(st.st_mode)) { free(path); continue; }
        if (n == cap) {
            cap = cap ? 2 * cap : 64;
            char** grown = realloc(names, cap * sizeof *names);
            if (!grown) { free(path); bad = 1; break; }
            names = grown;
        }
        names[n++] = path;
    }
    closedir(d);
    if (n) qsort(names, n, sizeof *names, cmp_names);
    for (size_t i = 0; i < n; ++i) {
        bad |= run_file(names[i]);
        ++*count;
        free(names[i]);
    }
    free(names);
    return bad;
}

int main(int argc, char** argv) {
    LLVMFuzzerInitialize(&argc, &argv);
    int bad = 0, count = 0;
    for (int i = 1; i < argc; ++i) {
        struct stat st;
        if (stat(argv[i], &st) != 0) {
            fprintf(stderr, "replay: %s does not exist\n", argv[i]);
            bad = 1;
        } else if (S_ISDIR(st.st_mode)) {
            bad |= run_dir(argv[i], &count);
        } else {
            bad |= run_file(argv[i]);
            ++count;
        }
    }
    printf("replay: %d inputs, %s\n", count, bad ? "errors reading some" : "all ran");
    return bad ? 1 : 0;
}
