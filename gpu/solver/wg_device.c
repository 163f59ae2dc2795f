/* Programs and capabilities of one GL context (see wg_device.h). */
#include "wg_device.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "gl_texture.h"
#include "gpu_error.h"
#include "wg_amg.h"
#include "wg_compute.h"

typedef struct wg_shader_source {
    const char* name;
    const char* source;
} wg_shader_source;
extern const wg_shader_source wg_shader_sources[];   /* generated: cmake/embed_shaders.cmake */

/* A pass named X_fine is X.glsl compiled with WG_AMG_FINE defined (amg_level_inputs.glsl). */
static const char kFineSuffix[] = "_fine";
static const char kFineDefine[] = "#define WG_AMG_FINE 1\n";

static const char* shader_source(const char* name) {
    for (const wg_shader_source* s = wg_shader_sources; s->name; ++s)
        if (strcmp(s->name, name) == 0) return s->source;
    return NULL;
}

/* common.glsl + body, each "#pragma weft include NAME" line of the body replaced by NAME.glsl
 * (one level), and define (lines of #define) at the body's start, after its #version line where
 * it has one (a native compute shader's). Returns an allocated string, or NULL (out of memory, or
 * an unknown include: then *missing names it). */
static char* compose(wg_gl_context* gl, const char* common, const char* body, const char* define,
                     const char** missing) {
    static const char kTag[] = "#pragma weft include ";
    size_t n = strlen(common) + strlen(body) + strlen(define) + 3;
    for (const char* p = strstr(body, kTag); p; p = strstr(p + 1, kTag)) {
        char name[64];
        if (sscanf(p + sizeof kTag - 1, "%63s", name) != 1) continue;
        const char* inc = shader_source(name);
        if (!inc) {
            *missing = p;
            return NULL;
        }
        n += strlen(inc) + 1;
    }
    char* out = wg_gl_alloc(gl, n);
    if (!out) return NULL;
    size_t at = (size_t)snprintf(out, n, "%s\n", common);
    const char* p = body;
    if (strncmp(body, "#version", 8) == 0) {
        const char* eol = strchr(body, '\n');
        size_t l = eol ? (size_t)(eol - body) + 1 : strlen(body);
        memcpy(out + at, body, l);
        at += l;
        p = body + l;
        if (!eol) out[at++] = '\n';
    }
    size_t dl = strlen(define);
    memcpy(out + at, define, dl);
    at += dl;
    for (const char* q = strstr(p, kTag); q; q = strstr(p, kTag)) {
        memcpy(out + at, p, (size_t)(q - p));
        at += (size_t)(q - p);
        char name[64] = "";
        sscanf(q + sizeof kTag - 1, "%63s", name);
        const char* inc = shader_source(name);
        size_t l = strlen(inc);
        memcpy(out + at, inc, l);
        at += l;
        out[at++] = '\n';
        const char* eol = strchr(q, '\n');
        p = eol ? eol + 1 : q + strlen(q);
    }
    size_t l = strlen(p);
    memcpy(out + at, p, l);
    out[at + l] = '\0';
    return out;
}

int wg_renderer_is_software(const char* r) {
    return r && (strstr(r, "llvmpipe") || strstr(r, "softpipe") || strstr(r, "swrast") || strstr(r, "Software"));
}

/* Render 1.5e-3, -7e20 and 3 into an RGBA32F target and read them back. */
static int float_targets_work(wg_device* d, char* err, size_t err_len) {
    const float in[4] = {1.5e-3f, -7e20f, 3.0f, 0.25f};
    wg_tex a, b;
    if (!wg_tex_create(&a, GL_RGBA32F, 1, 1, in, err, err_len)) return 0;
    if (!wg_tex_create(&b, GL_RGBA32F, 1, 1, NULL, err, err_len)) {
        wg_tex_destroy(&a);
        return 0;
    }
    GLuint fbo = 0;
    glGenFramebuffers(1, &fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, b.id, 0);
    GLenum status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
    int ok = status == GL_FRAMEBUFFER_COMPLETE;
    float out[4] = {0, 0, 0, 0};
    if (ok) {
        glUseProgram(d->prog[WGP_COPY].id);
        glActiveTexture(GL_TEXTURE0);
        glBindTexture(GL_TEXTURE_2D, a.id);
        if (d->compute) {   /* the copy pass as the solver runs it: into an image */
            const wg_tex* const out_b[1] = {&b};
            wg_compute_dispatch(&d->prog[WGP_COPY], out_b, 1, 0, 1, 1);
            glBindImageTexture(0, 0, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
        } else {
            glViewport(0, 0, 1, 1);
            glBindVertexArray(d->vao);
            glDrawArrays(GL_TRIANGLES, 0, 3);
        }
        glReadPixels(0, 0, 1, 1, GL_RGBA, GL_FLOAT, out);
        ok = memcmp(in, out, sizeof in) == 0;
        if (!ok)
            wg_errorf(err, err_len, "RGBA32F render target does not keep float values (wrote %g %g %g, read %g %g %g): "
                      "this GL context lacks float render targets", in[0], in[1], in[2], out[0], out[1], out[2]);
    } else {
        wg_errorf(err, err_len, "an RGBA32F texture is not a complete colour attachment (%s): this GL context "
                  "lacks float render targets", wg_fbo_status_name(status));
    }
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glDeleteFramebuffers(1, &fbo);
    wg_tex_destroy(&a);
    wg_tex_destroy(&b);
    GLenum e = glGetError();
    if (ok && e != GL_NO_ERROR) {
        wg_errorf(err, err_len, "float render target check: %s", wg_gl_error_name(e));
        ok = 0;
    }
    return ok;
}

wc_status wg_device_create(wg_gl_context* gl, wg_device** out, char* err, size_t err_len) {
    *out = NULL;
    wg_device* d = wg_gl_alloc(gl, sizeof *d);
    if (!d) {
        wg_errorf(err, err_len, "out of memory");
        return WC_ERROR_OUT_OF_MEMORY;
    }
    memset(d, 0, sizeof *d);
    d->gl = gl;
    /* compute passes where the context has GL 4.3, unless WEFT_GPU_PASSES says otherwise */
    const char* passes = getenv("WEFT_GPU_PASSES");
    if (passes && strcmp(passes, "compute") == 0) {
        if (!GLEW_VERSION_4_3) {
            wg_errorf(err, err_len, "WEFT_GPU_PASSES=compute needs OpenGL 4.3 compute shaders; this context is %s",
                      (const char*)glGetString(GL_VERSION));
            wg_device_destroy(d);
            return WC_ERROR_GPU;
        }
        d->compute = 1;
    } else if (passes && *passes && strcmp(passes, "fragment") != 0) {
        wg_errorf(err, err_len, "WEFT_GPU_PASSES='%.40s' is not 'fragment' or 'compute'", passes);
        wg_device_destroy(d);
        return WC_ERROR_GPU;
    } else {
        d->compute = !(passes && *passes) && GLEW_VERSION_4_3;
    }
    /* the PCG solve's form: WEFT_GPU_SOLVE=group or =passes forces one (wg_solve_mode) */
    const char* solve = getenv("WEFT_GPU_SOLVE");
    if (solve && strcmp(solve, "group") == 0) {
        if (!d->compute) {
            wg_errorf(err, err_len, "WEFT_GPU_SOLVE=group needs compute-shader passes (OpenGL 4.3, WEFT_GPU_PASSES "
                      "compute); this context runs fragment passes");
            wg_device_destroy(d);
            return WC_ERROR_GPU;
        }
        d->solve = WG_SOLVE_GROUP;
    } else if (solve && strcmp(solve, "passes") == 0) {
        d->solve = WG_SOLVE_PASSES;
    } else if (solve && *solve) {
        wg_errorf(err, err_len, "WEFT_GPU_SOLVE='%.40s' is not 'group' or 'passes'", solve);
        wg_device_destroy(d);
        return WC_ERROR_GPU;
    }
    /* the multigrid's cross terms (wg_amg_pairs_create): WEFT_GPU_AMG_CROSS=1 or 0 (the default) */
    const char* cross = getenv("WEFT_GPU_AMG_CROSS");
    if (cross && *cross && strcmp(cross, "0") != 0 && strcmp(cross, "1") != 0) {
        wg_errorf(err, err_len, "WEFT_GPU_AMG_CROSS='%.40s' is not '0' or '1'", cross);
        wg_device_destroy(d);
        return WC_ERROR_GPU;
    }
    d->amg_cross = cross && strcmp(cross, "1") == 0;
    /* the multigrid's prolongator (wg_amg.smoothed): WEFT_GPU_AMG_SMOOTH=1 (the default) or 0 */
    const char* smooth = getenv("WEFT_GPU_AMG_SMOOTH");
    if (smooth && *smooth && strcmp(smooth, "0") != 0 && strcmp(smooth, "1") != 0) {
        wg_errorf(err, err_len, "WEFT_GPU_AMG_SMOOTH='%.40s' is not '0' or '1'", smooth);
        wg_device_destroy(d);
        return WC_ERROR_GPU;
    }
    d->amg_smooth = smooth && *smooth ? strcmp(smooth, "1") == 0 : WG_AMG_SMOOTHED;
    /* its near-null space (wg_amg.rotations): WEFT_GPU_AMG_ROT=1 (the default) or 0 */
    const char* rot = getenv("WEFT_GPU_AMG_ROT");
    if (rot && *rot && strcmp(rot, "0") != 0 && strcmp(rot, "1") != 0) {
        wg_errorf(err, err_len, "WEFT_GPU_AMG_ROT='%.40s' is not '0' or '1'", rot);
        wg_device_destroy(d);
        return WC_ERROR_GPU;
    }
    d->amg_rot = rot && *rot ? strcmp(rot, "1") == 0 : WG_AMG_ROTATIONS;
    /* the rotations' positions (wg_amg.current): WEFT_GPU_AMG_CURRENT=1 (current) or 0 (rest) */
    const char* cur = getenv("WEFT_GPU_AMG_CURRENT");
    if (cur && *cur && strcmp(cur, "0") != 0 && strcmp(cur, "1") != 0) {
        wg_errorf(err, err_len, "WEFT_GPU_AMG_CURRENT='%.40s' is not '0' or '1'", cur);
        wg_device_destroy(d);
        return WC_ERROR_GPU;
    }
    d->amg_current = cur && *cur ? strcmp(cur, "1") == 0 : WG_AMG_CURRENT;
    /* the V-cycle's fused passes (wg_amg.fuse): WEFT_GPU_AMG_FUSE=1 (the default) or 0 */
    const char* fuse = getenv("WEFT_GPU_AMG_FUSE");
    if (fuse && *fuse && strcmp(fuse, "0") != 0 && strcmp(fuse, "1") != 0) {
        wg_errorf(err, err_len, "WEFT_GPU_AMG_FUSE='%.40s' is not '0' or '1'", fuse);
        wg_device_destroy(d);
        return WC_ERROR_GPU;
    }
    d->amg_fuse = !(fuse && strcmp(fuse, "0") == 0);
    /* where the bodies from the host's arrays or rigid transforms move (wg_mesh_host.c):
       WEFT_GPU_BODY=device (the default) or host; another value is logged when a cloth is made */
    const char* body = getenv("WEFT_GPU_BODY");
    d->body_host = !body || !*body || strcmp(body, "device") == 0 ? 0 : strcmp(body, "host") == 0 ? 1 : -1;
    const char* common = shader_source("common");
    for (int p = 0; p < WGP_COUNT; ++p) {
        char base[64];
        const wg_pass_info* pass = &wg_passes[p];
        const char* name = pass->name;
        size_t nl = strlen(name), sl = sizeof kFineSuffix - 1;
        const int fine = nl > sl && nl - sl < sizeof base && strcmp(name + nl - sl, kFineSuffix) == 0;
        if (fine) {
            memcpy(base, name, nl - sl);
            base[nl - sl] = '\0';
            name = base;
        }
        const char* body = shader_source(name);
        if (!body) continue;   /* a pass whose shader is not in this build is never run */
        /* a native compute shader (*_groups.glsl) has common.glsl put after its #version line
           (wg_compute_native_source); it and the multigrid's passes exist only with compute passes */
        const int native = pass->native;
        if (pass->compute_only && !d->compute) continue;
        const char* missing = NULL;
        char* src = compose(gl, native || !common ? "" : common, body, fine ? kFineDefine : "", &missing);
        if (!src) {
            wg_device_destroy(d);
            if (missing) {
                wg_errorf(err, err_len, "shader '%s': unknown include '%.40s'", pass->name, missing);
                return WC_ERROR_GPU;
            }
            wg_errorf(err, err_len, "out of memory");
            return WC_ERROR_OUT_OF_MEMORY;
        }
        int ok;
        if (d->compute) {
            char* cs = native ? wg_compute_native_source(gl, common ? common : "", src) : wg_compute_source(gl, src);
            ok = cs && wg_program_build_compute(&d->prog[p], pass->name, cs, err, err_len);
            if (!cs) wg_errorf(err, err_len, "shader '%s': out of memory, or no #version line", pass->name);
            wg_gl_free(gl, cs);
        } else {
            ok = wg_program_build(&d->prog[p], pass->name, wg_fullscreen_vs, src, err, err_len);
        }
        wg_gl_free(gl, src);
        if (ok) ok = wg_pass_bind_inputs(d->prog[p].id, pass, err, err_len);
        if (!ok) {
            wg_device_destroy(d);
            return WC_ERROR_GPU;
        }
    }
    if (d->compute) glGetIntegeri_v(GL_MAX_COMPUTE_WORK_GROUP_COUNT, 0, &d->max_groups_x);
    glGenVertexArrays(1, &d->vao);
    glGetIntegerv(GL_MAX_TEXTURE_SIZE, &d->max_texture_size);
    glGetIntegerv(GL_MAX_DRAW_BUFFERS, &d->max_draw_buffers);
    const char* r = (const char*)glGetString(GL_RENDERER);
    snprintf(d->renderer, sizeof d->renderer, "%s", r ? r : "unknown renderer");
    d->software = wg_renderer_is_software(d->renderer);
    if (d->max_draw_buffers < 4) {
        wg_errorf(err, err_len, "the GL context has %d draw buffers; the solver needs 4", d->max_draw_buffers);
        wg_device_destroy(d);
        return WC_ERROR_GPU;
    }
    if (!float_targets_work(d, err, err_len)) {
        wg_device_destroy(d);
        return WC_ERROR_GPU;
    }
    GLuint q = 0;
    glGenQueries(1, &q);
    glQueryCounter(q, GL_TIMESTAMP);
    GLint bits = 0;
    glGetQueryiv(GL_TIMESTAMP, GL_QUERY_COUNTER_BITS, &bits);
    d->has_timer = glGetError() == GL_NO_ERROR && bits > 0;
    glDeleteQueries(1, &q);
    glGetError();
    *out = d;
    return WC_OK;
}

void wg_device_forget(wg_device* d) {
    if (d) wg_gl_free(d->gl, d);
}

void wg_device_destroy(wg_device* d) {
    if (!d) return;
    for (int p = 0; p < WGP_COUNT; ++p) wg_program_destroy(&d->prog[p]);
    if (d->vao) glDeleteVertexArrays(1, &d->vao);
    wg_gl_free(d->gl, d);
}
