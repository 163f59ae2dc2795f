/* What a host GL context this test program made current gives the GPU backend, for the tests and
 * benchmarks of the host's GL buffers (needs GL/glew.h or GL/gl.h first). */
#ifndef WEFT_TESTS_HOST_GL_PASSES_H
#define WEFT_TESTS_HOST_GL_PASSES_H
#include <stdlib.h>
#include <string.h>

/* 1 where a body from a host GL buffer stays on the GPU: compute passes (GL 4.3, and not
   WEFT_GPU_PASSES=fragment); 0 where it is read back (fragment passes). */
static inline int hg_body_on_gpu(void) {
    GLint major = 0, minor = 0;
    glGetIntegerv(GL_MAJOR_VERSION, &major);
    glGetIntegerv(GL_MINOR_VERSION, &minor);
    const char* passes = getenv("WEFT_GPU_PASSES");
    return (major > 4 || (major == 4 && minor >= 3)) && !(passes && strcmp(passes, "fragment") == 0);
}

/* Where a body given as host arrays moves on compute passes (WEFT_GPU_BODY, read when a context's
   device is made, gpu/solver/wg_mesh_host.c). The buffer tests compare a body from arrays with
   one from a host buffer (which stays on the GPU): hg_body_setting, called first in main, keeps
   the arrays' body on the host's path ("host") unless the environment names a setting;
   hg_arrays_on_gpu (with the host context current) is 1 when "device" puts both bodies on the
   GPU: the same floats through the same passes, the same bits. */
static inline void hg_body_setting(void) {
    const char* e = getenv("WEFT_GPU_BODY");
    if (!e || !*e) setenv("WEFT_GPU_BODY", "host", 1);
}

static inline int hg_arrays_on_gpu(void) {
    const char* e = getenv("WEFT_GPU_BODY");
    return e && strcmp(e, "device") == 0 && hg_body_on_gpu();
}

/* A host buffer (b, resized to fit) holding nv vertices (pos: 3 floats each) at byte offset +
   i * stride, every other byte a pattern that is not the body's floats. */
static inline void hg_fill_buffer(GLuint b, const float* pos, int nv, size_t offset, size_t stride) {
    size_t bytes = offset + (size_t)nv * stride;
    unsigned char* img = malloc(bytes);
    for (size_t i = 0; i < bytes; ++i) img[i] = (unsigned char)(i * 53u);
    for (int i = 0; i < nv; ++i) memcpy(img + offset + (size_t)i * stride, pos + 3 * i, 12);
    glBindBuffer(GL_COPY_WRITE_BUFFER, b);
    glBufferData(GL_COPY_WRITE_BUFFER, (GLsizeiptr)bytes, img, GL_DYNAMIC_DRAW);
    glBindBuffer(GL_COPY_WRITE_BUFFER, 0);
    free(img);
}

#endif
