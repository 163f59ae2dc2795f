/* GLSL programs of gpu/'s compute passes: a full-screen triangle and a fragment shader, with a
 * small per-program cache of uniform locations keyed by the name's address (callers pass string
 * literals), so a pass sets its uniforms without string look-ups after the first time.
 * Needs a current context with GLEW initialised. */
#ifndef WEFT_GPU_GL_PROGRAM_H
#define WEFT_GPU_GL_PROGRAM_H

#include <stddef.h>
#include <GL/glew.h>

#define WG_PROGRAM_MAX_UNIFORMS 24
#define WG_PROGRAM_MAX_SAMPLERS 16

typedef struct wg_program {
    GLuint id;
    const char* name;                           /* for messages */
    int n_cached;
    const char* cached_name[WG_PROGRAM_MAX_UNIFORMS];
    GLint cached_loc[WG_PROGRAM_MAX_UNIFORMS];
} wg_program;

/* Compile and link vertex + fragment sources; outputs o0..o7 go to draw buffers 0..7 and sampler
 * uniforms named t0..t15 to texture units 0..15. Leaves program 0 in use. Returns 1, or 0 with
 * the compiler's or linker's log in err. */
int wg_program_build(wg_program* p, const char* name, const char* vs, const char* fs, char* err, size_t err_len);
/* The same for one compute shader (GL 4.3): samplers t0..t15 to units 0..15, images by their
 * own layout(binding). */
int wg_program_build_compute(wg_program* p, const char* name, const char* cs, char* err, size_t err_len);
void wg_program_destroy(wg_program* p);

/* Location of a uniform (-1 when the program does not use it). name must outlive the program
 * (a string literal). */
GLint wg_program_loc(wg_program* p, const char* name);

/* The vertex shader of every compute pass: one triangle covering the viewport. */
extern const char* const wg_fullscreen_vs;

#endif
