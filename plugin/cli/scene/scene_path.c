/* File names of a scene (scene_path.h). */
#include "scene_path.h"

#include <stdlib.h>
#include <string.h>

char* scene_strdup(const char* s) {
    size_t n = strlen(s) + 1;
    char* d = malloc(n);
    if (d) memcpy(d, s, n);
    return d;
}

char* scene_resolve_path(const char* name, const char* file) {
    const char* slash = strrchr(name, '/');
    if (file[0] == '/' || !slash) return scene_strdup(file);
    size_t dir = (size_t)(slash - name) + 1, n = strlen(file) + 1;
    char* out = malloc(dir + n);
    if (!out) return NULL;
    memcpy(out, name, dir);
    memcpy(out + dir, file, n);
    return out;
}
