/* Strict, path-naming readers of scene JSON values. */
#include "scene_json.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

int sj_fail(const sj_ctx* c, const char* field, const char* fmt, ...) {
    char what[400];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(what, sizeof what, fmt, ap);
    va_end(ap);
    if (field && field[0])
        cli_fail(c->diag, WEFT_ERROR_SCENE, "%s: %s: %s", c->file, field, what);
    else
        cli_fail(c->diag, WEFT_ERROR_SCENE, "%s: %s", c->file, what);
    return -1;
}

void sj_join(char* out, size_t cap, const char* parent, const char* key) {
    if (parent && parent[0])
        snprintf(out, cap, "%s.%s", parent, key);
    else
        snprintf(out, cap, "%s", key);
}

const char* sj_type_name(const cJSON* v) {
    if (cJSON_IsNumber(v)) return "a number";
    if (cJSON_IsString(v)) return "a string";
    if (cJSON_IsArray(v)) return "an array";
    if (cJSON_IsObject(v)) return "an object";
    if (cJSON_IsBool(v)) return "a boolean";
    if (cJSON_IsNull(v)) return "null";
    return "an invalid value";
}

int sj_check_object(const sj_ctx* c, const cJSON* obj, const char* field, const char* const* allowed, int n) {
    if (!cJSON_IsObject(obj))
        return sj_fail(c, field, "must be an object, not %s", sj_type_name(obj));
    for (const cJSON* it = obj->child; it; it = it->next) {
        char path[256];
        sj_join(path, sizeof path, field, it->string ? it->string : "");
        int known = 0;
        for (int i = 0; i < n && !known; ++i) known = strcmp(it->string, allowed[i]) == 0;
        if (!known) {
            char list[512];
            size_t len = 0;
            list[0] = '\0';
            for (int i = 0; i < n && len < sizeof list; ++i)
                len += (size_t)snprintf(list + len, sizeof list - len, "%s%s", i ? ", " : "", allowed[i]);
            return sj_fail(c, path, "unknown key (expected one of: %s)", list);
        }
        for (const cJSON* prev = obj->child; prev != it; prev = prev->next)
            if (strcmp(prev->string, it->string) == 0) return sj_fail(c, path, "duplicate key");
    }
    return 0;
}

const cJSON* sj_get(const cJSON* obj, const char* key) {
    return cJSON_GetObjectItemCaseSensitive(obj, key);
}

static const char* range_text(sj_range r) {
    switch (r) {
    case SJ_POSITIVE: return "a finite number > 0";
    case SJ_NONNEGATIVE: return "a finite number >= 0";
    default: return "a finite number";
    }
}

int sj_number(const sj_ctx* c, const cJSON* obj, const char* parent, const char* key, sj_range range,
              double* out) {
    const cJSON* v = sj_get(obj, key);
    if (!v) return 0;
    char path[256];
    sj_join(path, sizeof path, parent, key);
    if (!cJSON_IsNumber(v)) return sj_fail(c, path, "must be %s, not %s", range_text(range), sj_type_name(v));
    double x = v->valuedouble;
    int ok = isfinite(x) && (range == SJ_FINITE || (range == SJ_POSITIVE && x > 0) ||
                             (range == SJ_NONNEGATIVE && x >= 0));
    if (!ok) return sj_fail(c, path, "must be %s, not %g", range_text(range), x);
    *out = x;
    return 1;
}

int sj_int(const sj_ctx* c, const cJSON* obj, const char* parent, const char* key, int lo, int hi, int* out) {
    const cJSON* v = sj_get(obj, key);
    if (!v) return 0;
    char path[256];
    sj_join(path, sizeof path, parent, key);
    if (!cJSON_IsNumber(v))
        return sj_fail(c, path, "must be an integer in [%d, %d], not %s", lo, hi, sj_type_name(v));
    double x = v->valuedouble;
    if (!isfinite(x) || x != floor(x) || x < lo || x > hi)
        return sj_fail(c, path, "must be an integer in [%d, %d], not %g", lo, hi, x);
    *out = (int)x;
    return 1;
}

int sj_numbers(const sj_ctx* c, const cJSON* obj, const char* parent, const char* key, int n, double* out) {
    const cJSON* v = sj_get(obj, key);
    if (!v) return 0;
    char path[256];
    sj_join(path, sizeof path, parent, key);
    if (!cJSON_IsArray(v) || cJSON_GetArraySize(v) != n)
        return sj_fail(c, path, "must be an array of %d finite numbers, not %s%s", n, sj_type_name(v),
                       cJSON_IsArray(v) ? " of another length" : "");
    double tmp[16];
    if (n > 16) return sj_fail(c, path, "internal: arrays of more than 16 numbers are not read");
    int i = 0;
    for (const cJSON* it = v->child; it; it = it->next, ++i) {
        if (!cJSON_IsNumber(it) || !isfinite(it->valuedouble)) {
            char item[300];
            snprintf(item, sizeof item, "%s[%d]", path, i);
            if (!cJSON_IsNumber(it))
                return sj_fail(c, item, "must be a finite number, not %s", sj_type_name(it));
            return sj_fail(c, item, "must be a finite number, not %g", it->valuedouble);
        }
        tmp[i] = it->valuedouble;
    }
    for (i = 0; i < n; ++i) out[i] = tmp[i];
    return 1;
}

int sj_string(const sj_ctx* c, const cJSON* obj, const char* parent, const char* key, const char** out) {
    const cJSON* v = sj_get(obj, key);
    if (!v) return 0;
    char path[256];
    sj_join(path, sizeof path, parent, key);
    if (!cJSON_IsString(v) || !v->valuestring || !v->valuestring[0])
        return sj_fail(c, path, "must be a non-empty string, not %s", cJSON_IsString(v) ? "\"\"" : sj_type_name(v));
    *out = v->valuestring;
    return 1;
}

int sj_object(const sj_ctx* c, const cJSON* obj, const char* parent, const char* key, const cJSON** out) {
    const cJSON* v = sj_get(obj, key);
    if (!v) return 0;
    char path[256];
    sj_join(path, sizeof path, parent, key);
    if (!cJSON_IsObject(v)) return sj_fail(c, path, "must be an object, not %s", sj_type_name(v));
    *out = v;
    return 1;
}

int sj_array(const sj_ctx* c, const cJSON* obj, const char* parent, const char* key, const cJSON** out) {
    const cJSON* v = sj_get(obj, key);
    if (!v) return 0;
    char path[256];
    sj_join(path, sizeof path, parent, key);
    if (!cJSON_IsArray(v)) return sj_fail(c, path, "must be an array, not %s", sj_type_name(v));
    *out = v;
    return 1;
}

int sj_require(const sj_ctx* c, const cJSON* obj, const char* parent, const char* key, const char* hint) {
    if (sj_get(obj, key)) return 0;
    char path[160];
    sj_join(path, sizeof path, parent, key);
    return sj_fail(c, path, "missing%s%s", hint ? " " : "", hint ? hint : "");
}

int sj_unit_vector(const sj_ctx* c, const cJSON* obj, const char* parent, const char* key, double* v) {
    int r = sj_numbers(c, obj, parent, key, 3, v);
    if (r <= 0) return r;
    double len = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (!(len > 1e-300) || !isfinite(len)) {
        char path[128];
        sj_join(path, sizeof path, parent, key);
        return sj_fail(c, path, "must be a nonzero vector");
    }
    for (int k = 0; k < 3; ++k) v[k] /= len;
    return 1;
}
