/* Error text for gpu/: formatting into the caller's buffer and names of EGL/GL codes. */
#ifndef WEFT_GPU_ERROR_H
#define WEFT_GPU_ERROR_H

#include <stddef.h>

/* Write a printf-style message into err (err_len bytes, always terminated; NULL/0: nothing). */
void wg_errorf(char* err, size_t err_len, const char* fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;

/* "EGL_BAD_MATCH" for 0x3009, ...; "unknown EGL error" otherwise. */
const char* wg_egl_error_name(int code);
/* "GL_INVALID_OPERATION" for 0x0502, ...; "unknown GL error" otherwise. */
const char* wg_gl_error_name(unsigned code);
/* "GL_FRAMEBUFFER_INCOMPLETE_ATTACHMENT" for glCheckFramebufferStatus results. */
const char* wg_fbo_status_name(unsigned status);

#endif
