/* The renderer's GLSL 330 programs and their uniform locations (gpu/ internal). */
#ifndef WEFT_GPU_RENDER_PROGRAM_H
#define WEFT_GPU_RENDER_PROGRAM_H

#include <GL/glew.h>
#include <stddef.h>

#include "status.h"

/* Attribute locations of the shading program. */
#define WG_ATTRIB_POSITION 0
#define WG_ATTRIB_NORMAL 1

typedef struct wg_programs {
    GLuint shade;               /* two-sided Lambert, optional checker */
    GLint u_model, u_normal_matrix, u_view_proj, u_front_rgb, u_back_rgb, u_checker, u_key_dir,
        u_fill_dir, u_up;
    GLuint background;          /* full-screen triangle, vertical gradient */
    GLint u_top_rgb, u_bottom_rgb, u_height;
} wg_programs;

/* Compile and link both (a current context is needed). Errors: WC_ERROR_GPU with the
 * compiler's or linker's log. */
wc_status wg_programs_create(wg_programs* p, char* err, size_t err_len);
void wg_programs_destroy(wg_programs* p);

/* Lighting constants shared by the shader and by documentation/tests: final colour =
 * base * (AMBIENT + HEMI * (0.5 + 0.5 n.up) + KEY * max(n.key, 0) + FILL * max(n.fill, 0)). */
#define WG_LIGHT_AMBIENT 0.16f
#define WG_LIGHT_HEMI 0.12f
#define WG_LIGHT_KEY 0.72f
#define WG_LIGHT_FILL 0.22f

#endif
