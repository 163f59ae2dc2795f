/* Fragment-pass sources as compute shaders (see wg_compute.h). */
#include "wg_compute.h"

#include <stdio.h>
#include <string.h>

typedef struct text {
    char* s;
    size_t n, cap;
    int overflow;   /* sized up front, so never set; checked all the same */
} text;

static void put(text* t, const char* p, size_t n) {
    if (t->n + n + 1 > t->cap) {
        t->overflow = 1;
        return;
    }
    memcpy(t->s + t->n, p, n);
    t->n += n;
    t->s[t->n] = '\0';
}

static void puts_(text* t, const char* p) { put(t, p, strlen(p)); }

/* q with every gl_FragCoord written as wg_frag_coord. */
static void put_coord(text* t, const char* q) {
    for (const char* f = strstr(q, "gl_FragCoord"); f; f = strstr(q, "gl_FragCoord")) {
        put(t, q, (size_t)(f - q));
        puts_(t, "wg_frag_coord");
        q = f + strlen("gl_FragCoord");
    }
    puts_(t, q);
}

static const char kPrelude[] =
    "#version 430 core\n"
    "layout(local_size_x = 64, local_size_y = 1) in;\n"
    "uniform ivec2 u_wg_origin;   // the first texel written (wg_run_texel: (x, 0))\n"
    "uniform ivec2 u_wg_size;     // the texels written: the fragment path's viewport\n"
    "uniform int u_wg_nout;       // the outputs bound (images 0 .. u_wg_nout - 1)\n"
    "vec4 wg_frag_coord;          // the fragment path's coordinate of this texel\n";

char* wg_compute_source(wg_gl_context* gl, const char* frag) {
    const char* ver = strncmp(frag, "#version", 8) == 0 ? frag : strstr(frag, "\n#version");
    if (!ver) return NULL;
    if (ver != frag) ++ver;   /* the directive's line, not a comment that names it */
    size_t len = strlen(frag), extra = 4096;
    for (const char* p = strstr(frag, "gl_FragCoord"); p; p = strstr(p + 1, "gl_FragCoord")) extra += 1;
    /* first the lines (out declarations, main's name) into body, then gl_FragCoord into t */
    text body = {wg_gl_alloc(gl, len + 1), 0, len + 1, 0};
    text t = {wg_gl_alloc(gl, len + extra), 0, len + extra, 0};
    if (!body.s || !t.s) {
        wg_gl_free(gl, body.s);
        wg_gl_free(gl, t.s);
        return NULL;
    }
    body.s[0] = t.s[0] = '\0';
    char kind[8] = {0};   /* per output k: 1 float, 2 vec2, 4 vec4; 0 none */
    const char* p = strchr(ver, '\n');
    p = p ? p + 1 : ver + strlen(ver);
    while (*p) {
        const char* e = strchr(p, '\n');
        size_t n = e ? (size_t)(e - p) + 1 : strlen(p);
        char type[8];
        int k = -1;
        if (strncmp(p, "out ", 4) == 0 && sscanf(p + 4, "%7s o%d;", type, &k) == 2 && k >= 0 && k < 8) {
            kind[k] = (char)(strcmp(type, "vec4") == 0 ? 4 : strcmp(type, "vec2") == 0 ? 2 : 1);
            put(&body, p + 4, n - 4);   /* a global: `vec4 o0;` */
        } else if (strncmp(p, "void main()", 11) == 0) {
            puts_(&body, "void wg_main()");
            put(&body, p + 11, n - 11);
        } else {
            put(&body, p, n);
        }
        p += n;
    }
    puts_(&t, kPrelude);   /* first: Mesa wants #version on line 1 (common.glsl's header comment is dropped) */
    put_coord(&t, body.s);
    t.overflow |= body.overflow;
    wg_gl_free(gl, body.s);
    char buf[256];
    for (int k = 0; k < 8; ++k)
        if (kind[k]) {
            snprintf(buf, sizeof buf, "\nlayout(binding = %d) writeonly uniform image2D wg_img%d;", k, k);
            puts_(&t, buf);
        }
    puts_(&t, "\nvoid main() {\n"
              "    ivec2 g = ivec2(gl_GlobalInvocationID.xy);\n"
              "    if (g.x >= u_wg_size.x || g.y >= u_wg_size.y) return;\n"
              "    ivec2 p = u_wg_origin + g;\n"
              "    wg_frag_coord = vec4(vec2(p) + 0.5, 0.5, 1.0);\n");
    static const char* const zero[5] = {"", "0.0", "vec2(0.0)", "", "vec4(0.0)"};
    static const char* const widen[5] = {"", "vec4(o%d, 0.0, 0.0, 0.0)", "vec4(o%d, 0.0, 0.0)", "", "o%d"};
    for (int k = 0; k < 8; ++k)
        if (kind[k]) {
            snprintf(buf, sizeof buf, "    o%d = %s;\n", k, zero[(int)kind[k]]);
            puts_(&t, buf);
        }
    puts_(&t, "    wg_main();\n");
    for (int k = 0; k < 8; ++k)
        if (kind[k]) {
            char v[32];
            snprintf(v, sizeof v, widen[(int)kind[k]], k);
            snprintf(buf, sizeof buf, "    if (u_wg_nout > %d) imageStore(wg_img%d, p, %s);\n", k, k, v);
            puts_(&t, buf);
        }
    puts_(&t, "}\n");
    if (t.overflow) {
        wg_gl_free(gl, t.s);
        return NULL;
    }
    return t.s;
}

/* after a dispatch: its image writes visible to whatever reads them next (texelFetch, read-backs,
   copies) */
static void barrier_after(void) {
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_FRAMEBUFFER_BARRIER_BIT |
                    GL_TEXTURE_UPDATE_BARRIER_BIT | GL_PIXEL_BUFFER_BARRIER_BIT);
}

/* s after its #version line (s itself when it has none) */
static const char* after_version(const char* s) {
    const char* v = strncmp(s, "#version", 8) == 0 ? s : strstr(s, "\n#version");
    if (!v) return s;
    const char* e = strchr(v + 1, '\n');
    return e ? e + 1 : v + strlen(v);
}

char* wg_compute_native_source(wg_gl_context* gl, const char* common, const char* body) {
    static const char kHead[] = "#version 430 core\nvec4 wg_frag_coord;   // common.glsl's gl_FragCoord (unused here)\n";
    common = after_version(common);
    body = after_version(body);
    size_t n = strlen(kHead) + strlen(common) + strlen(body) + 2;
    for (const char* p = strstr(common, "gl_FragCoord"); p; p = strstr(p + 1, "gl_FragCoord")) n += 1;
    text t = {wg_gl_alloc(gl, n), 0, n, 0};
    if (!t.s) return NULL;
    t.s[0] = '\0';
    puts_(&t, kHead);
    put_coord(&t, common);
    puts_(&t, "\n");
    puts_(&t, body);
    if (t.overflow) {
        wg_gl_free(gl, t.s);
        return NULL;
    }
    return t.s;
}

void wg_compute_dispatch(wg_program* p, const wg_tex* const* out, int n_out, int x0, int w, int h) {
    for (int j = 0; j < n_out; ++j)
        glBindImageTexture((GLuint)j, out[j]->id, 0, GL_FALSE, 0, GL_WRITE_ONLY, out[j]->internal);
    glUniform2i(wg_program_loc(p, "u_wg_origin"), x0, 0);
    glUniform2i(wg_program_loc(p, "u_wg_size"), w, h);
    glUniform1i(wg_program_loc(p, "u_wg_nout"), n_out);
    glDispatchCompute((GLuint)((w + 63) / 64), (GLuint)h, 1);
    barrier_after();
}

static void dispatch_groups(int groups, int max_x);

void wg_compute_dispatch_groups(const wg_tex* const* out, int n_out, int groups, int max_x) {
    for (int j = 0; j < n_out; ++j)
        glBindImageTexture((GLuint)j, out[j]->id, 0, GL_FALSE, 0, GL_WRITE_ONLY, out[j]->internal);
    dispatch_groups(groups, max_x);
}

void wg_compute_dispatch_groups_scratch(const wg_tex* const* out, int n_out, const wg_tex* scratch, int groups,
                                        int max_x) {
    for (int j = 0; j < n_out; ++j)
        glBindImageTexture((GLuint)j, out[j]->id, 0, GL_FALSE, 0, GL_WRITE_ONLY, out[j]->internal);
    glBindImageTexture((GLuint)n_out, scratch->id, 0, GL_FALSE, 0, GL_READ_WRITE, scratch->internal);
    dispatch_groups(groups, max_x);
}

void wg_compute_dispatch_groups_rw(const wg_tex* img, int groups, int max_x) {
    glBindImageTexture(0, img->id, 0, GL_FALSE, 0, GL_READ_WRITE, GL_RGBA32F);
    dispatch_groups(groups, max_x);
}

static void dispatch_groups(int groups, int max_x) {
    /* past max_x groups along x (GL guarantees 65535): rows of max_x (the shader's linear group
       id is y * max_x + x; the last row's surplus groups find no texel) */
    const int X = max_x > 0 ? max_x : 65535;
    if (groups <= X)
        glDispatchCompute((GLuint)groups, 1, 1);
    else
        glDispatchCompute((GLuint)X, (GLuint)((groups + X - 1) / X), 1);
    barrier_after();
}

void wg_compute_dispatch_in_place(const wg_tex* img) {
    glBindImageTexture(0, img->id, 0, GL_FALSE, 0, GL_READ_WRITE, GL_RGBA32F);
    glDispatchCompute(1, 1, 1);
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
}
