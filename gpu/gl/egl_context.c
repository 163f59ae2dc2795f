/* Headless EGL context (device platform, surfaceless fallback) or the host's current context. */
#include "egl_context.h"

#include <GL/glew.h>
#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "gl_state.h"
#include "gpu_error.h"

#define WG_MAX_DEVICES 16
#define WG_LABEL_LEN 192
#define WG_DESCRIPTION_LEN 512
#define WG_TRIED_LEN 1536

struct wg_gl_context {
    int host;
    wc_log_fn log;
    void* log_user;
    wc_allocator alloc;
    /* headless */
    EGLDisplay dpy;
    EGLContext egl_ctx;
    int terminate_display;      /* the display counts references (EGL_KHR_display_reference) */
    /* between wg_gl_begin and wg_gl_end */
    int inside;
    EGLenum prev_api;
    EGLDisplay prev_dpy;
    EGLContext prev_ctx;
    EGLSurface prev_draw, prev_read;
    wg_gl_saved_state saved;    /* host mode */
    char description[WG_DESCRIPTION_LEN];
    char renderer[128];         /* GL_RENDERER alone */
};

/* One way to get a display: a device of eglQueryDevicesEXT or the surfaceless platform. */
typedef struct wg_candidate {
    int surfaceless;
    int index;                  /* device index */
    EGLDeviceEXT device;
    int rank;                   /* 3 NVIDIA (CUDA), 2 other hardware, 1 software, 0 surfaceless */
    char label[WG_LABEL_LEN];
} wg_candidate;

typedef enum { WG_PICK_AUTO, WG_PICK_INDEX, WG_PICK_SOFTWARE, WG_PICK_SURFACELESS } wg_pick;

/* ---- allocation and logging ---- */

static void* default_alloc(size_t size, void* user) {
    (void)user;
    return malloc(size);
}

static void default_free(void* ptr, void* user) {
    (void)user;
    free(ptr);
}

void* wg_gl_alloc(const wg_gl_context* ctx, size_t size) {
    return ctx->alloc.alloc(size ? size : 1, ctx->alloc.user);
}

void wg_gl_free(const wg_gl_context* ctx, void* ptr) {
    if (ptr) ctx->alloc.free(ptr, ctx->alloc.user);
}

static void vlog(wc_log_fn log, void* user, wc_log_level level, const char* fmt, va_list ap) {
    if (!log) return;
    char msg[1024];
    vsnprintf(msg, sizeof msg, fmt, ap);
    log(level, msg, user);
}

void wg_gl_log(const wg_gl_context* ctx, wc_log_level level, const char* fmt, ...) {
    va_list ap;
    va_start(ap, fmt);
    vlog(ctx->log, ctx->log_user, level, fmt, ap);
    va_end(ap);
}

/* ---- small helpers ---- */

/* Whether the space-separated list contains name as a whole word. */
static int has_ext(const char* list, const char* name) {
    if (!list) return 0;
    size_t n = strlen(name);
    for (const char* p = list; (p = strstr(p, name)) != NULL; p += n) {
        int starts = p == list || p[-1] == ' ';
        int ends = p[n] == '\0' || p[n] == ' ';
        if (starts && ends) return 1;
    }
    return 0;
}

static void clear_gl_errors(void) {
    for (int i = 0; i < 64 && glGetError() != GL_NO_ERROR; ++i) {
    }
}

static wc_status parse_pick(const char* s, wg_pick* pick, int* index) {
    *pick = WG_PICK_AUTO;
    *index = -1;
    if (!s || !*s) return WC_OK;
    if (strcmp(s, "software") == 0) {
        *pick = WG_PICK_SOFTWARE;
        return WC_OK;
    }
    if (strcmp(s, "surfaceless") == 0) {
        *pick = WG_PICK_SURFACELESS;
        return WC_OK;
    }
    char* end = NULL;
    long v = strtol(s, &end, 10);
    if (end != s && *end == '\0' && v >= 0 && v < 1000000 && s[0] >= '0' && s[0] <= '9') {
        *pick = WG_PICK_INDEX;
        *index = (int)v;
        return WC_OK;
    }
    return WC_ERROR_GPU;
}

/* ---- candidates ---- */

/* Fill cands with the devices of eglQueryDevicesEXT (in device order) and the surfaceless
 * platform last; returns their count. *n_devices receives the device count. */
static int list_candidates(const wg_gl_context* ctx, wg_candidate* cands, int* n_devices) {
    int n = 0;
    *n_devices = 0;
    const char* client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    if (!client) eglGetError(); /* no client extensions: clear EGL_BAD_DISPLAY */
    int can_enumerate = has_ext(client, "EGL_EXT_device_enumeration") ||
                        has_ext(client, "EGL_EXT_device_base");
    int device_platform = has_ext(client, "EGL_EXT_platform_device");
    PFNEGLQUERYDEVICESEXTPROC query_devices =
        (PFNEGLQUERYDEVICESEXTPROC)eglGetProcAddress("eglQueryDevicesEXT");
    PFNEGLQUERYDEVICESTRINGEXTPROC query_device_string =
        (PFNEGLQUERYDEVICESTRINGEXTPROC)eglGetProcAddress("eglQueryDeviceStringEXT");
    if (can_enumerate && device_platform && query_devices && query_device_string) {
        EGLDeviceEXT devices[WG_MAX_DEVICES];
        EGLint count = 0;
        if (query_devices(WG_MAX_DEVICES, devices, &count) && count > 0) {
            for (int i = 0; i < count && i < WG_MAX_DEVICES; ++i) {
                const char* ext = query_device_string(devices[i], EGL_EXTENSIONS);
                if (!ext) {
                    eglGetError();
                    ext = "";
                }
                wg_candidate* c = &cands[n++];
                c->surfaceless = 0;
                c->index = i;
                c->device = devices[i];
                c->rank = has_ext(ext, "EGL_NV_device_cuda")         ? 3
                          : has_ext(ext, "EGL_MESA_device_software") ? 1
                                                                     : 2;
                snprintf(c->label, sizeof c->label, "EGL device %d [%.150s]", i, ext);
                wg_gl_log(ctx, WC_LOG_DEBUG, "weft gpu: found %s", c->label);
            }
            *n_devices = n;
        } else {
            EGLint e = eglGetError();
            wg_gl_log(ctx, WC_LOG_DEBUG, "weft gpu: eglQueryDevicesEXT found no device (%s)",
                      wg_egl_error_name(e));
        }
    } else {
        wg_gl_log(ctx, WC_LOG_DEBUG,
                  "weft gpu: EGL has no device enumeration / device platform extensions");
    }
    if (has_ext(client, "EGL_MESA_platform_surfaceless")) {
        wg_candidate* c = &cands[n++];
        memset(c, 0, sizeof *c);
        c->surfaceless = 1;
        c->index = -1;
        c->rank = 0;
        snprintf(c->label, sizeof c->label,
                 "EGL surfaceless platform (EGL_PLATFORM_SURFACELESS_MESA)");
    }
    return n;
}

/* ---- opening one candidate ---- */

static wc_status egl_fail(char* err, size_t err_len, const char* label, const char* call) {
    EGLint e = eglGetError();
    wg_errorf(err, err_len, "%s: %s failed: %s (0x%04x)", label, call, wg_egl_error_name(e),
              (unsigned)e);
    return WC_ERROR_GPU;
}

/* After a context is current: GLEW and the GL version. */
static wc_status init_glew(const char* label, char* err, size_t err_len) {
    glewExperimental = GL_TRUE;
    GLenum g = glewInit();
    /* Debian's GLEW is built for GLX: with an EGL context it loads every GL entry point and then
     * reports the missing GLX display (or an old GLX); only a missing GL version is fatal. */
    if (g != GLEW_OK && g != GLEW_ERROR_NO_GLX_DISPLAY && g != GLEW_ERROR_GLX_VERSION_11_ONLY) {
        if (g == GLEW_ERROR_NO_GL_VERSION)
            wg_errorf(err, err_len, "%s: glewInit failed: no OpenGL context is current (%u: %s)",
                      label, (unsigned)g, (const char*)glewGetErrorString(g));
        else
            wg_errorf(err, err_len, "%s: glewInit failed: %s (%u)", label,
                      (const char*)glewGetErrorString(g), (unsigned)g);
        return WC_ERROR_GPU;
    }
    const char* version = (const char*)glGetString(GL_VERSION);
    if (!GLEW_VERSION_3_3) {
        wg_errorf(err, err_len, "%s: OpenGL 3.3 is required, the context has '%s'", label,
                  version ? version : "(no GL_VERSION)");
        return WC_ERROR_GPU;
    }
    /* The entry points gpu/ calls beyond GL 1.1 (GLVND stubs; NULL would mean a broken GLEW). */
    if (!glGenVertexArrays || !glGenFramebuffers || !glBlitFramebuffer ||
        !glRenderbufferStorageMultisample || !glCreateShader || !glBufferData ||
        !glVertexAttribPointer || !glUniformMatrix4fv) {
        wg_errorf(err, err_len, "%s: glewInit left OpenGL 3.3 entry points unresolved", label);
        return WC_ERROR_GPU;
    }
    clear_gl_errors();
    return WC_OK;
}

static wc_status open_candidate(wg_gl_context* ctx, const wg_candidate* c, char* err,
                                  size_t err_len) {
    const char* client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    int references = has_ext(client, "EGL_KHR_display_reference");
    EGLAttrib attrs[3] = {EGL_NONE, EGL_NONE, EGL_NONE};
    if (references) {
        attrs[0] = EGL_TRACK_REFERENCES_KHR;
        attrs[1] = EGL_TRUE;
    }
    EGLDisplay dpy = c->surfaceless
                         ? eglGetPlatformDisplay(EGL_PLATFORM_SURFACELESS_MESA,
                                                 (void*)EGL_DEFAULT_DISPLAY, attrs)
                         : eglGetPlatformDisplay(EGL_PLATFORM_DEVICE_EXT, c->device, attrs);
    if (dpy == EGL_NO_DISPLAY) return egl_fail(err, err_len, c->label, "eglGetPlatformDisplay");
    EGLint major = 0, minor = 0;
    if (!eglInitialize(dpy, &major, &minor))
        return egl_fail(err, err_len, c->label, "eglInitialize");

    wc_status st = WC_ERROR_GPU;
    EGLContext egl_ctx = EGL_NO_CONTEXT;
    const char* ext = eglQueryString(dpy, EGL_EXTENSIONS);
    if (!has_ext(ext, "EGL_KHR_surfaceless_context")) {
        wg_errorf(err, err_len, "%s: the display lacks EGL_KHR_surfaceless_context", c->label);
        goto fail;
    }
    if (!eglBindAPI(EGL_OPENGL_API)) {
        st = egl_fail(err, err_len, c->label, "eglBindAPI(EGL_OPENGL_API)");
        goto fail;
    }
    EGLConfig config = EGL_NO_CONFIG_KHR;
    if (!has_ext(ext, "EGL_KHR_no_config_context")) {
        const EGLint want[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_SURFACE_TYPE, 0, EGL_NONE};
        EGLint n_configs = 0;
        if (!eglChooseConfig(dpy, want, &config, 1, &n_configs)) {
            st = egl_fail(err, err_len, c->label, "eglChooseConfig");
            goto fail;
        }
        if (n_configs < 1) {
            wg_errorf(err, err_len, "%s: eglChooseConfig found no OpenGL config", c->label);
            goto fail;
        }
    }
    static const int versions[][2] = {{4, 5}, {4, 4}, {4, 3}, {4, 2}, {4, 1}, {4, 0}, {3, 3}};
    EGLint create_error = EGL_SUCCESS;
    for (size_t i = 0; i < sizeof versions / sizeof versions[0] && egl_ctx == EGL_NO_CONTEXT; ++i) {
        const EGLint attribs[] = {EGL_CONTEXT_MAJOR_VERSION, versions[i][0],
                                  EGL_CONTEXT_MINOR_VERSION, versions[i][1],
                                  EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                  EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
        egl_ctx = eglCreateContext(dpy, config, EGL_NO_CONTEXT, attribs);
        if (egl_ctx == EGL_NO_CONTEXT) create_error = eglGetError();
    }
    if (egl_ctx == EGL_NO_CONTEXT) {
        wg_errorf(err, err_len, "%s: eglCreateContext (OpenGL 4.5..3.3 core) failed: %s (0x%04x)",
                  c->label, wg_egl_error_name(create_error), (unsigned)create_error);
        goto fail;
    }
    if (!eglMakeCurrent(dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, egl_ctx)) {
        st = egl_fail(err, err_len, c->label, "eglMakeCurrent (no surface)");
        goto fail;
    }
    st = init_glew(c->label, err, err_len);
    if (st != WC_OK) {
        eglMakeCurrent(dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
        goto fail;
    }
    const char* renderer = (const char*)glGetString(GL_RENDERER);
    const char* version = (const char*)glGetString(GL_VERSION);
    snprintf(ctx->description, sizeof ctx->description, "%s: %s, OpenGL %s (EGL %d.%d)", c->label,
             renderer ? renderer : "?", version ? version : "?", (int)major, (int)minor);
    snprintf(ctx->renderer, sizeof ctx->renderer, "%s", renderer ? renderer : "?");
    ctx->dpy = dpy;
    ctx->egl_ctx = egl_ctx;
    ctx->terminate_display = references;
    return WC_OK;

fail:
    if (egl_ctx != EGL_NO_CONTEXT) eglDestroyContext(dpy, egl_ctx);
    /* Without reference counting the display may be someone else's too: leave it initialised. */
    if (references) eglTerminate(dpy);
    return st;
}

/* ---- create / destroy ---- */

static void save_egl_current(wg_gl_context* ctx) {
    ctx->prev_api = eglQueryAPI();
    ctx->prev_dpy = eglGetCurrentDisplay();
    ctx->prev_ctx = eglGetCurrentContext();
    ctx->prev_draw = eglGetCurrentSurface(EGL_DRAW);
    ctx->prev_read = eglGetCurrentSurface(EGL_READ);
}

/* Give the thread back the EGL context (or none) it had before; dpy is the display we used. */
static void restore_egl_current(const wg_gl_context* ctx, EGLDisplay dpy) {
    if (ctx->prev_ctx != EGL_NO_CONTEXT) {
        eglBindAPI(ctx->prev_api);
        eglMakeCurrent(ctx->prev_dpy, ctx->prev_draw, ctx->prev_read, ctx->prev_ctx);
    } else {
        if (dpy != EGL_NO_DISPLAY)
            eglMakeCurrent(dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
        eglBindAPI(ctx->prev_api);
    }
}

static wc_status create_headless(wg_gl_context* ctx, const char* pick_text, char* err,
                                   size_t err_len) {
    wg_pick pick;
    int want_index;
    if (parse_pick(pick_text, &pick, &want_index) != WC_OK) {
        wg_errorf(err, err_len,
                  "WEFT_EGL_DEVICE='%.64s' is not a device index, 'software' or 'surfaceless'",
                  pick_text);
        return WC_ERROR_GPU;
    }
    wg_candidate cands[WG_MAX_DEVICES + 1];
    int n_devices = 0;
    int n = list_candidates(ctx, cands, &n_devices);

    /* The candidates to try, in order. */
    int order[WG_MAX_DEVICES + 1];
    int n_order = 0;
    if (pick == WG_PICK_INDEX) {
        if (want_index >= n_devices) {
            wg_errorf(err, err_len, "WEFT_EGL_DEVICE=%d: eglQueryDevicesEXT found %d device(s)",
                      want_index, n_devices);
            return WC_ERROR_GPU;
        }
        order[n_order++] = want_index;
    } else if (pick == WG_PICK_SOFTWARE) {
        for (int i = 0; i < n_devices; ++i)
            if (cands[i].rank == 1) {
                order[n_order++] = i;
                break;
            }
        if (n_order == 0) {
            wg_errorf(err, err_len,
                      "WEFT_EGL_DEVICE=software: none of the %d EGL device(s) advertises "
                      "EGL_MESA_device_software",
                      n_devices);
            return WC_ERROR_GPU;
        }
    } else if (pick == WG_PICK_SURFACELESS) {
        if (n == n_devices) {
            wg_errorf(err, err_len,
                      "WEFT_EGL_DEVICE=surfaceless: EGL lacks EGL_MESA_platform_surfaceless");
            return WC_ERROR_GPU;
        }
        order[n_order++] = n - 1;
    } else {
        for (int rank = 3; rank >= 0; --rank)
            for (int i = 0; i < n; ++i)
                if (cands[i].rank == rank) order[n_order++] = i;
        if (n_order == 0) {
            wg_errorf(err, err_len,
                      "no EGL device found (eglQueryDevicesEXT: none; no surfaceless platform)");
            return WC_ERROR_GPU;
        }
    }

    save_egl_current(ctx);
    char tried[WG_TRIED_LEN] = "";
    char one[512];
    for (int k = 0; k < n_order; ++k) {
        const wg_candidate* c = &cands[order[k]];
        wc_status st = open_candidate(ctx, c, one, sizeof one);
        if (st == WC_OK) {
            restore_egl_current(ctx, ctx->dpy);
            wg_gl_log(ctx, WC_LOG_INFO, "weft gpu: using %s", ctx->description);
            return WC_OK;
        }
        if (n_order > 1) wg_gl_log(ctx, WC_LOG_WARN, "weft gpu: skipped %s", one);
        size_t used = strlen(tried);
        snprintf(tried + used, sizeof tried - used, "%s%s", used ? "; " : "", one);
    }
    restore_egl_current(ctx, EGL_NO_DISPLAY);
    if (n_order == 1)
        wg_errorf(err, err_len, "%s", tried);
    else
        wg_errorf(err, err_len, "no EGL device could be used: %s", tried);
    return WC_ERROR_GPU;
}

static wc_status create_host(wg_gl_context* ctx, char* err, size_t err_len) {
    const char* label = "host context";
    wc_status st = init_glew(label, err, err_len);
    if (st != WC_OK) return st;
    const char* renderer = (const char*)glGetString(GL_RENDERER);
    const char* version = (const char*)glGetString(GL_VERSION);
    snprintf(ctx->description, sizeof ctx->description, "%s: %s, OpenGL %s", label,
             renderer ? renderer : "?", version ? version : "?");
    snprintf(ctx->renderer, sizeof ctx->renderer, "%s", renderer ? renderer : "?");
    wg_gl_log(ctx, WC_LOG_INFO, "weft gpu: using %s", ctx->description);
    return WC_OK;
}

wc_status wg_gl_context_create(const wg_gl_context_desc* desc, wg_gl_context** out, char* err,
                                 size_t err_len) {
    wg_errorf(err, err_len, "%s", "");
    if (!out) {
        wg_errorf(err, err_len, "wg_gl_context_create: out is NULL");
        return WC_ERROR_INVALID_ARGUMENT;
    }
    *out = NULL;
    if (!desc) {
        wg_errorf(err, err_len, "wg_gl_context_create: desc is NULL");
        return WC_ERROR_INVALID_ARGUMENT;
    }
    if ((desc->allocator.alloc == NULL) != (desc->allocator.free == NULL)) {
        wg_errorf(err, err_len, "wg_gl_context_create: allocator needs both alloc and free");
        return WC_ERROR_INVALID_ARGUMENT;
    }
    wc_allocator alloc = desc->allocator;
    if (!alloc.alloc) {
        alloc.alloc = default_alloc;
        alloc.free = default_free;
        alloc.user = NULL;
    }
    wg_gl_context* ctx = (wg_gl_context*)alloc.alloc(sizeof *ctx, alloc.user);
    if (!ctx) {
        wg_errorf(err, err_len, "wg_gl_context_create: out of memory");
        return WC_ERROR_OUT_OF_MEMORY;
    }
    memset(ctx, 0, sizeof *ctx);
    ctx->host = desc->host_current != 0;
    ctx->log = desc->log;
    ctx->log_user = desc->log_user;
    ctx->alloc = alloc;
    ctx->dpy = EGL_NO_DISPLAY;
    ctx->egl_ctx = EGL_NO_CONTEXT;

    wc_status st;
    if (ctx->host) {
        st = create_host(ctx, err, err_len);
    } else {
        const char* pick = desc->device ? desc->device : getenv("WEFT_EGL_DEVICE");
        st = create_headless(ctx, pick, err, err_len);
    }
    if (st != WC_OK) {
        alloc.free(ctx, alloc.user);
        return st;
    }
    *out = ctx;
    return WC_OK;
}

void wg_gl_context_destroy(wg_gl_context* ctx) {
    if (!ctx) return;
    if (ctx->inside) wg_gl_end(ctx);
    if (!ctx->host && ctx->egl_ctx != EGL_NO_CONTEXT) {
        if (eglGetCurrentContext() == ctx->egl_ctx)
            eglMakeCurrent(ctx->dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
        eglDestroyContext(ctx->dpy, ctx->egl_ctx);
        if (ctx->terminate_display) eglTerminate(ctx->dpy);
    }
    wc_allocator alloc = ctx->alloc;
    alloc.free(ctx, alloc.user);
}

const char* wg_gl_context_renderer(const wg_gl_context* ctx) { return ctx ? ctx->renderer : ""; }

const char* wg_gl_context_description(const wg_gl_context* ctx) {
    return ctx ? ctx->description : "";
}

int wg_gl_context_is_host(const wg_gl_context* ctx) {
    return ctx && ctx->host;
}

/* ---- begin / end ---- */

wc_status wg_gl_begin(wg_gl_context* ctx, char* err, size_t err_len) {
    if (!ctx) {
        wg_errorf(err, err_len, "wg_gl_begin: context is NULL");
        return WC_ERROR_INVALID_ARGUMENT;
    }
    if (ctx->inside) {
        wg_errorf(err, err_len, "wg_gl_begin: already inside wg_gl_begin (not nestable)");
        return WC_ERROR_CALL_ORDER;
    }
    if (ctx->host) {
        if (glGetString(GL_VERSION) == NULL) {
            wg_errorf(err, err_len,
                      "host context: no OpenGL context is current on this thread "
                      "(glGetString(GL_VERSION) returned NULL)");
            return WC_ERROR_GPU;
        }
        wg_gl_state_save(&ctx->saved);
        wg_gl_state_set_defaults(0);   /* the host's buffers, alignments, blending... never reach gpu/'s passes */
    } else {
        save_egl_current(ctx);
        if (!eglBindAPI(EGL_OPENGL_API)) {
            wc_status st =
                egl_fail(err, err_len, "headless context", "eglBindAPI(EGL_OPENGL_API)");
            eglBindAPI(ctx->prev_api);
            return st;
        }
        if (!eglMakeCurrent(ctx->dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, ctx->egl_ctx)) {
            wc_status st = egl_fail(err, err_len, "headless context", "eglMakeCurrent");
            eglBindAPI(ctx->prev_api);
            return st;
        }
    }
    clear_gl_errors();
    ctx->inside = 1;
    return WC_OK;
}

void wg_gl_end(wg_gl_context* ctx) {
    if (!ctx || !ctx->inside) return;
    if (ctx->host)
        wg_gl_state_restore(&ctx->saved);
    else
        restore_egl_current(ctx, ctx->dpy);
    ctx->inside = 0;
}
