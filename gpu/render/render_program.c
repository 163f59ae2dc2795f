/* GLSL programs of the preview renderer. */
#include "render_program.h"

#include <string.h>

#include "gl_program.h"

#define STR_(x) #x
#define STR(x) STR_(x)

static const char* kShadeVs =
    "#version 330 core\n"
    "layout(location = " STR(WG_ATTRIB_POSITION) ") in vec3 a_position;\n"
    "layout(location = " STR(WG_ATTRIB_NORMAL) ") in vec3 a_normal;\n"
    "uniform mat4 u_model;\n"
    "uniform mat3 u_normal_matrix;\n"
    "uniform mat4 u_view_proj;\n"
    "out vec3 v_normal;\n"
    "out vec3 v_local;\n"
    "void main() {\n"
    "    v_local = a_position;\n"
    "    v_normal = u_normal_matrix * a_normal;\n"
    "    gl_Position = u_view_proj * (u_model * vec4(a_position, 1.0));\n"
    "}\n";

/* Two-sided: the back face shows back_rgb and its normal is turned toward the viewer. */
static const char* kShadeFs =
    "#version 330 core\n"
    "in vec3 v_normal;\n"
    "in vec3 v_local;\n"
    "uniform vec3 u_front_rgb;\n"
    "uniform vec3 u_back_rgb;\n"
    "uniform float u_checker;\n"
    "uniform vec3 u_key_dir;\n"
    "uniform vec3 u_fill_dir;\n"
    "uniform vec3 u_up;\n"
    "out vec4 o_color;\n"
    "void main() {\n"
    "    float len = length(v_normal);\n"
    "    vec3 n = len > 1e-20 ? v_normal / len : vec3(0.0);\n"
    "    vec3 base = u_front_rgb;\n"
    "    if (!gl_FrontFacing) { n = -n; base = u_back_rgb; }\n"
    "    if (u_checker > 0.0) {\n"
    "        float c = mod(floor(v_local.x / u_checker) + floor(v_local.z / u_checker), 2.0);\n"
    "        base *= c < 0.5 ? 1.0 : 0.8;\n"
    "    }\n"
    "    float light = " STR(WG_LIGHT_AMBIENT) "\n"
    "                + " STR(WG_LIGHT_HEMI) " * (0.5 + 0.5 * dot(n, u_up))\n"
    "                + " STR(WG_LIGHT_KEY) " * max(dot(n, u_key_dir), 0.0)\n"
    "                + " STR(WG_LIGHT_FILL) " * max(dot(n, u_fill_dir), 0.0);\n"
    "    o_color = vec4(clamp(base * light, 0.0, 1.0), 1.0);\n"
    "}\n";

static const char* kBackgroundFs =
    "#version 330 core\n"
    "uniform vec3 u_top_rgb;\n"
    "uniform vec3 u_bottom_rgb;\n"
    "uniform float u_height;\n"
    "out vec4 o_color;\n"
    "void main() {\n"
    "    float t = clamp(gl_FragCoord.y / u_height, 0.0, 1.0);\n"
    "    o_color = vec4(mix(u_bottom_rgb, u_top_rgb, t), 1.0);\n"
    "}\n";

/* Compile and link through gl/'s program builder (shared with the solver's passes). */
static GLuint link(const char* vs_src, const char* fs_src, const char* name, char* err, size_t err_len) {
    wg_program prog;
    return wg_program_build(&prog, name, vs_src, fs_src, err, err_len) ? prog.id : 0;
}

wc_status wg_programs_create(wg_programs* p, char* err, size_t err_len) {
    memset(p, 0, sizeof *p);
    p->shade = link(kShadeVs, kShadeFs, "shading", err, err_len);
    if (!p->shade) return WC_ERROR_GPU;
    p->background = link(wg_fullscreen_vs, kBackgroundFs, "background", err, err_len);   /* one triangle */
    if (!p->background) {
        wg_programs_destroy(p);
        return WC_ERROR_GPU;
    }
    p->u_model = glGetUniformLocation(p->shade, "u_model");
    p->u_normal_matrix = glGetUniformLocation(p->shade, "u_normal_matrix");
    p->u_view_proj = glGetUniformLocation(p->shade, "u_view_proj");
    p->u_front_rgb = glGetUniformLocation(p->shade, "u_front_rgb");
    p->u_back_rgb = glGetUniformLocation(p->shade, "u_back_rgb");
    p->u_checker = glGetUniformLocation(p->shade, "u_checker");
    p->u_key_dir = glGetUniformLocation(p->shade, "u_key_dir");
    p->u_fill_dir = glGetUniformLocation(p->shade, "u_fill_dir");
    p->u_up = glGetUniformLocation(p->shade, "u_up");
    p->u_top_rgb = glGetUniformLocation(p->background, "u_top_rgb");
    p->u_bottom_rgb = glGetUniformLocation(p->background, "u_bottom_rgb");
    p->u_height = glGetUniformLocation(p->background, "u_height");
    return WC_OK;
}

void wg_programs_destroy(wg_programs* p) {
    if (p->shade) glDeleteProgram(p->shade);
    if (p->background) glDeleteProgram(p->background);
    p->shade = p->background = 0;
}
