/* Compute-shader copies for bench_gpu (see gpu_compute_copy.h). */
#include "gpu_compute_copy.h"

#include <GL/glew.h>
#include <stdio.h>

#include "clock.h"
#include "gl_program.h"

static const char* const k_tex_src =
    "#version 430\n"
    "layout(local_size_x = 256) in;\n"
    "uniform sampler2D t0;   // unit 0 (wg_program_build_compute)\n"
    "layout(rgba32f, binding = 0) writeonly uniform image2D dst;\n"
    "uniform int u_n;\n"
    "void main() {\n"
    "    int i = int(gl_GlobalInvocationID.x);\n"
    "    if (i >= u_n) return;\n"
    "    ivec2 p = ivec2(i & 1023, i >> 10);\n"
    "    imageStore(dst, p, texelFetch(t0, p, 0));\n"
    "}\n";

static const char* const k_buf_src =
    "#version 430\n"
    "layout(local_size_x = 256) in;\n"
    "layout(std430, binding = 0) readonly buffer A { vec4 a[]; };\n"
    "layout(std430, binding = 1) writeonly buffer B { vec4 b[]; };\n"
    "uniform int u_n;\n"
    "void main() {\n"
    "    int i = int(gl_GlobalInvocationID.x);\n"
    "    if (i < u_n) b[i] = a[i];\n"
    "}\n";

static double timed(GLuint prog, int n, int reps) {
    glUseProgram(prog);
    glUniform1i(glGetUniformLocation(prog, "u_n"), n);
    GLuint groups = (GLuint)((n + 255) / 256);
    glDispatchCompute(groups, 1, 1);   /* warm-up */
    glFinish();
    double t0 = wc_now_ms();
    for (int k = 0; k < reps; ++k) {
        glDispatchCompute(groups, 1, 1);
        glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT);
    }
    glFinish();
    return (wc_now_ms() - t0) / reps;
}

int gpu_compute_copy(int n, int reps, double* ms_tex, double* ms_buf) {
    *ms_tex = *ms_buf = -1.0;
    if (!GLEW_VERSION_4_3 || n < 1 || reps < 1) return 0;
    wg_program prog_tex, prog_buf;
    char err[512];
    if (!wg_program_build_compute(&prog_tex, "copy (texture)", k_tex_src, err, sizeof err)) {
        fprintf(stderr, "gpu_compute_copy: %s\n", err);
        return 0;
    }
    if (!wg_program_build_compute(&prog_buf, "copy (buffer)", k_buf_src, err, sizeof err)) {
        fprintf(stderr, "gpu_compute_copy: %s\n", err);
        wg_program_destroy(&prog_tex);
        return 0;
    }
    GLuint pt = prog_tex.id, pb = prog_buf.id;
    int w = n < 1024 ? n : 1024, h = (n + 1023) / 1024;
    GLuint tex[2], buf[2];
    glGenTextures(2, tex);
    for (int k = 0; k < 2; ++k) {
        glBindTexture(GL_TEXTURE_2D, tex[k]);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAX_LEVEL, 0);
        glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, w, h, 0, GL_RGBA, GL_FLOAT, NULL);
    }
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, tex[0]);
    glBindImageTexture(0, tex[1], 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
    *ms_tex = timed(pt, n, reps);
    glGenBuffers(2, buf);
    for (int k = 0; k < 2; ++k) {
        glBindBuffer(GL_SHADER_STORAGE_BUFFER, buf[k]);
        glBufferData(GL_SHADER_STORAGE_BUFFER, (GLsizeiptr)n * 16, NULL, GL_DYNAMIC_COPY);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, (GLuint)k, buf[k]);
    }
    *ms_buf = timed(pb, n, reps);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, 0);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, 0);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
    glDeleteBuffers(2, buf);
    glBindImageTexture(0, 0, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
    glBindTexture(GL_TEXTURE_2D, 0);
    glDeleteTextures(2, tex);
    glUseProgram(0);
    wg_program_destroy(&prog_tex);
    wg_program_destroy(&prog_buf);
    return glGetError() == GL_NO_ERROR;
}
