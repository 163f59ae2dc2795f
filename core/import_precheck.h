/* Cheap checks before a file or buffer goes to assimp, one per input found (by fuzz/fuzz_import)
 * to make assimp 5.2.5 itself hang or crash, where a look at the bytes avoids it. A crash inside
 * assimp cannot be caught in-process, so these refuse such inputs with IMPORT first. The list,
 * with the inputs and assimp's version, is in docs/bench/fuzz.md. */
#ifndef WEFT_CORE_IMPORT_PRECHECK_H
#define WEFT_CORE_IMPORT_PRECHECK_H
#include <stddef.h>
#include "diag.h"

/* Bytes of a PLY header searched for its end_header line. */
#define WC_PRECHECK_PLY_HEADER_MAX (1u << 20)

/* The whole input in memory; name for messages. */
wc_status wc_import_precheck_memory(const unsigned char* data, size_t size, const char* name, wc_diag* diag);
/* A file whose first n_head bytes are head (reads more of it only when a check needs to). */
wc_status wc_import_precheck_file(const char* path, const unsigned char* head, size_t n_head, wc_diag* diag);

#endif
