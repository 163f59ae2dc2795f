/* The named benchmark scenes (bench_scene.h): each is the text of a scene file read by the scene
 * reader, then the material scaled. */
#define _POSIX_C_SOURCE 200809L
#include "bench_scene.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"

/* Copy text into buf as the inside of a JSON string (quotes and backslashes escaped); -1 when it
 * has control characters or does not fit. */
static int json_escape(const char* text, char* buf, size_t size) {
    size_t k = 0;
    for (const char* c = text; *c; ++c) {
        if ((unsigned char)*c < 0x20) return -1;
        if (*c == '"' || *c == '\\') {
            if (k + 1 >= size) return -1;
            buf[k++] = '\\';
        }
        if (k + 1 >= size) return -1;
        buf[k++] = *c;
    }
    buf[k] = '\0';
    return 0;
}

/* The scene's JSON text for name, or -1 (with msg) when the name is unknown. */
static int scene_json(const char* name, const char* garment, char* json, size_t size, char* msg, size_t msg_size) {
    int n = 0;
    if (!strncmp(name, "sheet", 5) && cli_parse_int(name + 5, 2, 2048, &n) == 0) {
        /* grid vertex i + n j lies at x = -0.5 + i / (n - 1), z = -0.5 + j / (n - 1) (scene.h) */
        snprintf(json, size,
                 "{\"mesh\": {\"grid\": {\"n\": [%d, %d], \"size\": [1, 1]}},"
                 " \"pins\": [{\"vertices\": [%d, %d]}]}",
                 n, n, n * (n - 1), n * n - 1);
        return 0;
    }
    if (!strncmp(name, "hang", 4) && cli_parse_int(name + 4, 2, 2048, &n) == 0) {
        /* the grid turned upright (z -> -y): vertices 0 and n - 1 (j = 0) are the top corners */
        snprintf(json, size,
                 "{\"mesh\": {\"grid\": {\"n\": [%d, %d], \"size\": [1, 1]}},"
                 " \"transform\": [1, 0, 0, 0,  0, 0, 1, 0,  0, -1, 0, 0,  0, 0, 0, 1],"
                 " \"pins\": [{\"vertices\": [0, %d]}]}",
                 n, n, n - 1);
        return 0;
    }
    if (!strcmp(name, "drape") || (!strncmp(name, "drape", 5) && cli_parse_int(name + 5, 2, 2048, &n) == 0)) {
        if (n == 0) n = 64;
        snprintf(json, size,
                 "{\"mesh\": {\"grid\": {\"n\": [%d, %d], \"size\": [1, 1]}},"
                 " \"transform\": [1, 0, 0, 0,  0, 1, 0, 0,  0, 0, 1, 0,  0, 0.3, 0, 1],"
                 " \"colliders\": [{\"type\": \"sphere\", \"center\": [0, 0, 0], \"radius\": 0.25}]}",
                 n, n);
        return 0;
    }
    if (!strcmp(name, "garment")) {
        char path[1024];
        if (!garment || json_escape(garment, path, sizeof path) != 0) {
            snprintf(msg, msg_size, "garment: unusable mesh path");
            return -1;
        }
        snprintf(json, size,
                 "{\"mesh\": {\"file\": \"%s\"},"
                 " \"pins\": [{\"select\": {\"axis\": \"y\", \"side\": \"max\", \"tolerance\": 0.001}}]}",
                 path);
        return 0;
    }
    snprintf(msg, msg_size, "unknown scene '%s' (expected sheetN, hangN, drape, drapeN or garment; N from 2 to 2048)",
             name);
    return -1;
}

int bench_scene_build(bench_scene* out, const char* name, const char* garment, double k_scale, double mass_scale,
                      char* msg, size_t size) {
    memset(out, 0, sizeof *out);
    char json[1536];
    if (scene_json(name, garment, json, sizeof json, msg, size) != 0) return -1;
    snprintf(out->name, sizeof out->name, "%s", name);
    cli_diag sd = {0};
    if (scene_parse(&out->sc, json, strlen(json), name, &sd) != WEFT_OK) {
        snprintf(msg, size, "%s", sd.message);
        return -1;
    }
    weft_material* mat = &out->sc.def.material;
    for (int t = 0; t < 3; ++t) mat->stiffness[t] *= k_scale;   /* seams take the stretch stiffness */
    mat->density *= mass_scale;
    if (!strcmp(name, "garment")) out->spin = BENCH_GARMENT_SPIN;
    return 0;
}

void bench_scene_free(bench_scene* s) {
    if (!s) return;
    scene_free(&s->sc);
    memset(s, 0, sizeof *s);
}

void bench_scene_pin_transform(const bench_scene* bs, double t, float out[16]) {
    /* turning about y, the rate ramped up linearly from 0 over the first BENCH_GARMENT_RAMP seconds */
    const double ramp = BENCH_GARMENT_RAMP;
    const double angle = bs->spin * (t < ramp ? 0.5 * t * t / ramp : t - 0.5 * ramp);
    const double c = cos(angle), s = sin(angle);
    memset(out, 0, 16 * sizeof(float));
    out[0] = (float)c;      /* column 0: (c, 0, -s) */
    out[2] = (float)-s;
    out[5] = 1.0f;
    out[8] = (float)s;      /* column 2: (s, 0, c) */
    out[10] = (float)c;
    out[15] = 1.0f;
}
