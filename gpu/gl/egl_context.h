/* A GL context for gpu/: either a headless EGL context of our own (a GPU device where one is
 * found, else Mesa's software rasteriser llvmpipe), or the host's context current on the calling
 * thread. GL calls go through GLEW; every GL call in gpu/ happens between wg_gl_begin() and
 * wg_gl_end().
 *
 * Device choice (headless), first that works:
 *   1. WEFT_EGL_DEVICE (or wg_gl_context_desc.device): "<index>" (an eglQueryDevicesEXT index),
 *      "software" (the device advertising EGL_MESA_device_software) or "surfaceless"
 *      (EGL_PLATFORM_SURFACELESS_MESA). When set, only that one is tried; anything else is an
 *      error (WC_ERROR_GPU).
 *   2. Otherwise: devices advertising EGL_NV_device_cuda, then other non-software devices (DRM),
 *      then Mesa's software device, then the surfaceless platform.
 * The context is OpenGL 4.5..3.3 core (the highest the driver gives), created without a config
 * (EGL_KHR_no_config_context; a config is chosen where that is missing) and made current with no
 * surface: rendering goes to framebuffer objects only.
 *
 * Process-wide facts behind this file: GLEW keeps its function pointers in globals (they point at
 * GLVND's dispatch stubs, which follow whichever context is current, so every context may share
 * them); an EGLDisplay is shared by everyone in the process who opens the same device, so it is
 * terminated on destroy only where EGL_KHR_display_reference counts its users. */
#ifndef WEFT_GPU_EGL_CONTEXT_H
#define WEFT_GPU_EGL_CONTEXT_H

#include <stddef.h>

#include "alloc.h"   /* core's wc_allocator */
#include "diag.h"    /* core's wc_log_fn / wc_log_level, and wc_status (status.h) */

#ifdef __cplusplus
extern "C" {
#endif

typedef struct wg_gl_context wg_gl_context;   /* opaque */

typedef struct wg_gl_context_desc {
    int host_current;           /* 0: own headless EGL context; 1: the host's current context at
                                   every wg_gl_begin() (no EGL calls; GL bindings saved there and
                                   restored by wg_gl_end()) */
    const char* device;         /* headless device override, as WEFT_EGL_DEVICE; NULL: read the
                                   environment variable WEFT_EGL_DEVICE (unset or "": automatic) */
    wc_log_fn log;              /* NULL: silent. Levels: WC_LOG_DEBUG each device seen, WC_LOG_INFO
                                   the device and renderer used, WC_LOG_WARN a device that failed
                                   and was skipped (errors come back as statuses, never logged) */
    void* log_user;
    wc_allocator allocator;     /* zeroed: malloc/free; else alloc and free both set */
} wg_gl_context_desc;

/* Create the context and initialise GLEW in it (headless: makes it current for the duration of
 * the call, then restores whatever EGL context the thread had; host_current: the host's context
 * must be current now, and GL 3.3 is checked in it). Errors: WC_ERROR_INVALID_ARGUMENT (NULL),
 * WC_ERROR_OUT_OF_MEMORY, WC_ERROR_GPU (err names the EGL/GLEW call and its error code, or
 * the bad WEFT_EGL_DEVICE value). *out is NULL on failure. err may be NULL. */
wc_status wg_gl_context_create(const wg_gl_context_desc* desc, wg_gl_context** out, char* err,
                                 size_t err_len);

/* Release everything (context, display reference). A headless context must not be inside
 * wg_gl_begin(). NULL is ignored. */
void wg_gl_context_destroy(wg_gl_context* ctx);

/* "EGL device 0 [EGL_MESA_device_software ...]: llvmpipe (LLVM 15.0.6, 256 bits), OpenGL 4.5
 * (Core Profile) Mesa 22.3.6" or "host context: <renderer>, OpenGL <version>". Valid until
 * destroy. */
const char* wg_gl_context_description(const wg_gl_context* ctx);
/* Its GL_RENDERER string alone ("llvmpipe (LLVM 15.0.6, 256 bits)"). Valid until destroy. */
const char* wg_gl_context_renderer(const wg_gl_context* ctx);

int wg_gl_context_is_host(const wg_gl_context* ctx);

/* Make the context usable on the calling thread: headless, make it current (remembering the
 * thread's previous EGL context); host_current, check a context is current and save the GL state
 * gpu/ touches (framebuffers, renderbuffer, program, VAO, array buffer, pixel-pack and -unpack
 * buffers and their alignments, row lengths and skips, the active texture unit and the 2D
 * textures of units 0..15, viewport, clear colour/depth, depth/colour masks and function, front
 * face, polygon mode, enable bits: depth test, cull face, blend, scissor, stencil, multisample,
 * sRGB, polygon offset, rasterizer discard, alpha-to-coverage, primitive restart), then set gpu/'s
 * known values (wg_gl_state_set_defaults(0)). Clears pending glGetError()s. Must be paired with wg_gl_end(); not nestable. Errors: WC_ERROR_GPU. */
wc_status wg_gl_begin(wg_gl_context* ctx, char* err, size_t err_len);
/* Restore what wg_gl_begin() saved (the host's GL state, or the thread's previous EGL context). */
void wg_gl_end(wg_gl_context* ctx);

/* The context's allocator (never NULL functions) and logger, for gpu/'s other objects. */
void* wg_gl_alloc(const wg_gl_context* ctx, size_t size);
void wg_gl_free(const wg_gl_context* ctx, void* ptr);
void wg_gl_log(const wg_gl_context* ctx, wc_log_level level, const char* fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;

#ifdef __cplusplus
}
#endif
#endif
