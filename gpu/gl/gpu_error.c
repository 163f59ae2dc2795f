/* Error text for gpu/. */
#include "gpu_error.h"

#include <stdarg.h>
#include <stdio.h>

void wg_errorf(char* err, size_t err_len, const char* fmt, ...) {
    if (!err || err_len == 0) return;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(err, err_len, fmt, ap);
    va_end(ap);
}

const char* wg_egl_error_name(int code) {
    switch (code) {
    case 0x3000: return "EGL_SUCCESS";
    case 0x3001: return "EGL_NOT_INITIALIZED";
    case 0x3002: return "EGL_BAD_ACCESS";
    case 0x3003: return "EGL_BAD_ALLOC";
    case 0x3004: return "EGL_BAD_ATTRIBUTE";
    case 0x3005: return "EGL_BAD_CONFIG";
    case 0x3006: return "EGL_BAD_CONTEXT";
    case 0x3007: return "EGL_BAD_CURRENT_SURFACE";
    case 0x3008: return "EGL_BAD_DISPLAY";
    case 0x3009: return "EGL_BAD_MATCH";
    case 0x300A: return "EGL_BAD_NATIVE_PIXMAP";
    case 0x300B: return "EGL_BAD_NATIVE_WINDOW";
    case 0x300C: return "EGL_BAD_PARAMETER";
    case 0x300D: return "EGL_BAD_SURFACE";
    case 0x300E: return "EGL_CONTEXT_LOST";
    case 0x322B: return "EGL_BAD_DEVICE_EXT";
    default: return "unknown EGL error";
    }
}

const char* wg_gl_error_name(unsigned code) {
    switch (code) {
    case 0x0000: return "GL_NO_ERROR";
    case 0x0500: return "GL_INVALID_ENUM";
    case 0x0501: return "GL_INVALID_VALUE";
    case 0x0502: return "GL_INVALID_OPERATION";
    case 0x0503: return "GL_STACK_OVERFLOW";
    case 0x0504: return "GL_STACK_UNDERFLOW";
    case 0x0505: return "GL_OUT_OF_MEMORY";
    case 0x0506: return "GL_INVALID_FRAMEBUFFER_OPERATION";
    case 0x0507: return "GL_CONTEXT_LOST";
    default: return "unknown GL error";
    }
}

const char* wg_fbo_status_name(unsigned status) {
    switch (status) {
    case 0x8CD5: return "GL_FRAMEBUFFER_COMPLETE";
    case 0x8219: return "GL_FRAMEBUFFER_UNDEFINED";
    case 0x8CD6: return "GL_FRAMEBUFFER_INCOMPLETE_ATTACHMENT";
    case 0x8CD7: return "GL_FRAMEBUFFER_INCOMPLETE_MISSING_ATTACHMENT";
    case 0x8CDB: return "GL_FRAMEBUFFER_INCOMPLETE_DRAW_BUFFER";
    case 0x8CDC: return "GL_FRAMEBUFFER_INCOMPLETE_READ_BUFFER";
    case 0x8CDD: return "GL_FRAMEBUFFER_UNSUPPORTED";
    case 0x8D56: return "GL_FRAMEBUFFER_INCOMPLETE_MULTISAMPLE";
    case 0x8DA8: return "GL_FRAMEBUFFER_INCOMPLETE_LAYER_TARGETS";
    case 0: return "glCheckFramebufferStatus failed (0)";
    default: return "unknown framebuffer status";
    }
}
