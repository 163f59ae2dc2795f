/* Reading what `weft run` writes (OBJ frames, stats JSON) in the CLI tests, and scratch folders.
 * Header-only (static inline functions): included by test_cli_run.c and test_cli_motion.c. */
#ifndef WEFT_TESTS_CLI_FRAMES_H
#define WEFT_TESTS_CLI_FRAMES_H
#include <cjson/cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <sys/stat.h>

#include "check.h"
#include "test_support.h"

enum { CF_MAX_VERTS = 4096 };

/* An OBJ frame: its `v` positions and the number of `f` lines. */
typedef struct obj_frame {
    int n_v, n_f;
    double v[3 * CF_MAX_VERTS];
} obj_frame;

static inline int cf_exists(const char* path) {
    struct stat st;
    return stat(path, &st) == 0;
}

/* A fresh, empty scratch folder (removed with its files first); static buffer. */
static inline const char* cf_fresh_dir(const char* name) {
    static char path[1024];
    snprintf(path, sizeof path, "%s", ts_tmp_path(name));
    char cmd[1200];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", path);
    CHECK(system(cmd) == 0);
    return path;
}

static inline int cf_read_obj(const char* path, obj_frame* o) {
    o->n_v = o->n_f = 0;
    FILE* f = fopen(path, "r");
    if (!f) return -1;
    char line[512];
    while (fgets(line, sizeof line, f)) {
        if (line[0] == 'v' && line[1] == ' ' && o->n_v < CF_MAX_VERTS) {
            double* p = o->v + 3 * o->n_v++;
            if (sscanf(line + 2, "%lf %lf %lf", &p[0], &p[1], &p[2]) != 3) p[0] = p[1] = p[2] = NAN;
        } else if (line[0] == 'f' && line[1] == ' ') {
            ++o->n_f;
        }
    }
    fclose(f);
    return 0;
}

/* Frame f (1-based) of a --out folder. */
static inline int cf_read_frame(const char* dir, int f, obj_frame* o) {
    char path[1200];
    snprintf(path, sizeof path, "%s/frame_%04d.obj", dir, f);
    return cf_read_obj(path, o);
}

static inline cJSON* cf_read_json(const char* path) {
    static char text[65536];
    ts_read_text(path, text, sizeof text);
    return cJSON_Parse(text);
}

static inline double cf_num(const cJSON* obj, const char* key) {
    const cJSON* item = cJSON_GetObjectItemCaseSensitive(obj, key);
    return cJSON_IsNumber(item) ? item->valuedouble : NAN;
}

#endif
