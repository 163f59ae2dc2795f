/* GLSL programs of the compute passes (see gl_program.h). */
#include "gl_program.h"

#include <stdio.h>
#include <string.h>

#include "gpu_error.h"

const char* const wg_fullscreen_vs =
    "#version 330 core\n"
    "void main() {\n"
    "    vec2 p = vec2(gl_VertexID == 1 ? 3.0 : -1.0, gl_VertexID == 2 ? 3.0 : -1.0);\n"
    "    gl_Position = vec4(p, 0.0, 1.0);\n"
    "}\n";

static GLuint compile(GLenum type, const char* src, const char* name, char* err, size_t err_len) {
    GLuint sh = glCreateShader(type);
    if (!sh) {
        wg_errorf(err, err_len, "glCreateShader(%s) failed: %s", name, wg_gl_error_name(glGetError()));
        return 0;
    }
    glShaderSource(sh, 1, &src, NULL);
    glCompileShader(sh);
    GLint ok = 0;
    glGetShaderiv(sh, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        char log[1024] = "";
        glGetShaderInfoLog(sh, sizeof log, NULL, log);
        wg_errorf(err, err_len, "GLSL %s shader '%s' does not compile: %s",
                  type == GL_VERTEX_SHADER ? "vertex" : type == GL_COMPUTE_SHADER ? "compute" : "fragment", name, log);
        glDeleteShader(sh);
        return 0;
    }
    return sh;
}

/* Sampler uniforms t0..t15 to texture units 0..15. (The previous program is not put back: it may
 * be one deleted while current, whose name dies as soon as another program is used; gpu/ sets its
 * program before every draw and wg_gl_end restores a host's.) */
static void bind_samplers(GLuint prog) {
    glUseProgram(prog);
    for (int k = 0; k < WG_PROGRAM_MAX_SAMPLERS; ++k) {
        char tname[16];
        snprintf(tname, sizeof tname, "t%d", k);
        GLint loc = glGetUniformLocation(prog, tname);
        if (loc >= 0) glUniform1i(loc, k);
    }
    glUseProgram(0);
}

/* After glLinkProgram: the link's verdict (its log in err), then the samplers; p->id on success. */
static int finish(wg_program* p, GLuint prog, const char* what, char* err, size_t err_len) {
    GLint ok = 0;
    glGetProgramiv(prog, GL_LINK_STATUS, &ok);
    if (!ok) {
        char log[1024] = "";
        glGetProgramInfoLog(prog, sizeof log, NULL, log);
        wg_errorf(err, err_len, "GLSL %s '%s' does not link: %s", what, p->name, log);
        glDeleteProgram(prog);
        return 0;
    }
    bind_samplers(prog);
    p->id = prog;
    return 1;
}

int wg_program_build(wg_program* p, const char* name, const char* vs, const char* fs, char* err, size_t err_len) {
    memset(p, 0, sizeof *p);
    p->name = name;
    GLuint v = compile(GL_VERTEX_SHADER, vs, name, err, err_len);
    if (!v) return 0;
    GLuint f = compile(GL_FRAGMENT_SHADER, fs, name, err, err_len);
    if (!f) {
        glDeleteShader(v);
        return 0;
    }
    GLuint prog = glCreateProgram();
    glAttachShader(prog, v);
    glAttachShader(prog, f);
    /* outputs o0..o7 go to draw buffers 0..7 */
    for (int k = 0; k < 8; ++k) {
        char out_name[16];
        snprintf(out_name, sizeof out_name, "o%d", k);
        glBindFragDataLocation(prog, (GLuint)k, out_name);
    }
    glLinkProgram(prog);
    glDeleteShader(v);
    glDeleteShader(f);
    return finish(p, prog, "program", err, err_len);
}

int wg_program_build_compute(wg_program* p, const char* name, const char* cs, char* err, size_t err_len) {
    memset(p, 0, sizeof *p);
    p->name = name;
    GLuint c = compile(GL_COMPUTE_SHADER, cs, name, err, err_len);
    if (!c) return 0;
    GLuint prog = glCreateProgram();
    glAttachShader(prog, c);
    glLinkProgram(prog);
    glDeleteShader(c);
    return finish(p, prog, "compute program", err, err_len);
}

void wg_program_destroy(wg_program* p) {
    if (p->id) glDeleteProgram(p->id);
    memset(p, 0, sizeof *p);
}

GLint wg_program_loc(wg_program* p, const char* name) {
    for (int k = 0; k < p->n_cached; ++k)
        if (p->cached_name[k] == name) return p->cached_loc[k];
    GLint loc = glGetUniformLocation(p->id, name);
    if (p->n_cached < WG_PROGRAM_MAX_UNIFORMS) {
        p->cached_name[p->n_cached] = name;
        p->cached_loc[p->n_cached] = loc;
        ++p->n_cached;
    }
    return loc;
}
