/* Strict readers of scene JSON values (cJSON) that report failures with the field's path.
 * Every failure message has the form "FILE: FIELD: what is wrong" (one line) and is recorded in
 * the context's diag with WEFT_ERROR_SCENE. Readers of optional fields return 0 when the key is
 * absent (the output is left untouched, so callers pre-fill defaults), 1 when it was read, and
 * -1 on error. */
#ifndef WEFT_CLI_SCENE_JSON_H
#define WEFT_CLI_SCENE_JSON_H
#include <cjson/cJSON.h>

#include "cli.h"

typedef struct sj_ctx {
    const char* file;   /* scene file name as the user gave it (message prefix) */
    cli_diag* diag;
} sj_ctx;

/* Bounds of a number field. */
typedef enum sj_range {
    SJ_FINITE = 0,      /* any finite number */
    SJ_POSITIVE,        /* finite, > 0 */
    SJ_NONNEGATIVE      /* finite, >= 0 */
} sj_range;

/* Record "FILE: FIELD: message" and return -1. */
int sj_fail(const sj_ctx* c, const char* field, const char* fmt, ...) __attribute__((format(printf, 3, 4)));

/* Join a parent path and a key: "material" + "k" -> "material.k" ("" + "k" -> "k"). */
void sj_join(char* out, size_t cap, const char* parent, const char* key);

/* obj (at path `field`, "" for the root) must be an object whose keys are all in allowed[0..n)
 * and unique. 0 or -1. */
int sj_check_object(const sj_ctx* c, const cJSON* obj, const char* field, const char* const* allowed, int n);

/* The value of key in obj, NULL when absent. */
const cJSON* sj_get(const cJSON* obj, const char* key);

/* Numbers. */
int sj_number(const sj_ctx* c, const cJSON* obj, const char* parent, const char* key, sj_range range,
              double* out);
/* Integer in [lo, hi] (a JSON number with no fractional part). */
int sj_int(const sj_ctx* c, const cJSON* obj, const char* parent, const char* key, int lo, int hi, int* out);
/* Array of exactly n finite numbers. */
int sj_numbers(const sj_ctx* c, const cJSON* obj, const char* parent, const char* key, int n, double* out);
/* Non-empty string (returned pointer borrowed from the JSON tree). */
int sj_string(const sj_ctx* c, const cJSON* obj, const char* parent, const char* key, const char** out);
/* Object (returned pointer borrowed). Type only; keys are checked by sj_check_object. */
int sj_object(const sj_ctx* c, const cJSON* obj, const char* parent, const char* key, const cJSON** out);
/* Array (returned pointer borrowed), any length. */
int sj_array(const sj_ctx* c, const cJSON* obj, const char* parent, const char* key, const cJSON** out);

/* "PARENT.KEY: missing[ hint]" unless obj has key; 0 or -1. */
int sj_require(const sj_ctx* c, const cJSON* obj, const char* parent, const char* key, const char* hint);
/* An optional nonzero 3-vector, normalised to unit length. */
int sj_unit_vector(const sj_ctx* c, const cJSON* obj, const char* parent, const char* key, double* v);

/* Name of a JSON value's type for messages ("a string", "an array", ...). */
const char* sj_type_name(const cJSON* v);

#endif
