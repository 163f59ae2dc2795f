/* Writing a rendered picture as a PNG file (libpng). */
#ifndef WEFT_GPU_PNG_WRITE_H
#define WEFT_GPU_PNG_WRITE_H

#include <stddef.h>

#include "status.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Write rgba (w x h x 4 bytes, rows top to bottom) to path as an 8-bit RGB PNG (alpha dropped).
 * Errors: INVALID_ARGUMENT (NULL, w or h outside 1..2^24), IO (the file cannot be opened or
 * written; err names the file and the reason; a partly written file is removed). */
wc_status wg_png_write(const char* path, const unsigned char* rgba, int w, int h, char* err,
                         size_t err_len);

#ifdef __cplusplus
}
#endif
#endif
