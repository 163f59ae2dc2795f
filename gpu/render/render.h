/* Off-screen preview renderer: shaded cloth meshes (two-sided, front and back tinted differently)
 * and collider shapes, read back as RGBA8. Plain arrays in; nothing here knows core/ or plugin/.
 *
 * Picture: a light sky gradient behind; a key and a fill directional light placed relative to
 * the camera (key from upper left, fill from lower right) plus a small ambient term brighter on
 * faces turned up; Lambert shading with the normal turned toward the viewer; 4x MSAA where the
 * driver has it (resolved with glBlitFramebuffer). Planes are drawn as a finite checkered square
 * around the rest of the scene. */
#ifndef WEFT_GPU_RENDER_H
#define WEFT_GPU_RENDER_H

#include <stddef.h>

#include "egl_context.h"   /* wg_gl_context; wc_status */

#ifdef __cplusplus
extern "C" {
#endif

#define WG_MAX_IMAGE_SIZE 8192   /* pixels, width and height */

/* Background: a vertical gradient from WG_SKY_BOTTOM_RGB (bottom row) to WG_SKY_TOP_RGB (top row),
 * linear in the pixel centre's height: t = (y + 0.5) / height, y counted from the bottom. */
#define WG_SKY_TOP_RGB {0.56f, 0.70f, 0.86f}
#define WG_SKY_BOTTOM_RGB {0.92f, 0.94f, 0.96f}
/* Shapes whose rgb is all zero; their inside (back faces) is drawn at half brightness. */
#define WG_SHAPE_DEFAULT_RGB {0.62f, 0.64f, 0.68f}
#define WG_PLANE_DEFAULT_RGB {0.80f, 0.79f, 0.76f}

typedef struct wg_camera {
    float eye[3];               /* world position (m) */
    float target[3];            /* point looked at; eye == target: wg_render frames the scene
                                   with wg_camera_frame_auto() */
    float up[3];                /* need not be unit or orthogonal to the view; not parallel to it */
    float fov_y_deg;            /* vertical field of view, in (0, 180) */
    int width, height;          /* pixels, 1..WG_MAX_IMAGE_SIZE */
} wg_camera;

/* A triangle mesh in world coordinates. Front = counter-clockwise seen from the viewer. */
typedef struct wg_mesh {
    const float* positions;     /* (n_vertices x 3) world, m */
    const float* normals;       /* (n_vertices x 3) unit, or NULL: area-weighted from triangles */
    int n_vertices;
    const int* triangles;       /* (n_triangles x 3) vertex indices in [0, n_vertices) */
    int n_triangles;
    float front_rgb[3];         /* linear 0..1 */
    float back_rgb[3];
} wg_mesh;

/* gpu/'s own shape kinds (the plugin maps its collider types onto them). */
typedef enum wg_shape_type {
    WG_SHAPE_PLANE = 0,         /* local plane y = 0, normal +y; drawn as a checkered square */
    WG_SHAPE_SPHERE = 1,        /* local sphere at the origin */
    WG_SHAPE_CAPSULE = 2        /* local segment (0, -half_height, 0)..(0, half_height, 0) */
} wg_shape_type;

typedef struct wg_shape {
    wg_shape_type type;
    float transform[16];        /* local -> world, column-major (m[4 * col + row]); invertible */
    float radius;               /* m, > 0 (sphere, capsule) */
    float half_height;          /* m, >= 0 (capsule) */
    float rgb[3];               /* 0..1; all zero: the default grey */
} wg_shape;

typedef struct wg_renderer wg_renderer;   /* opaque; GL objects of one wg_gl_context */

typedef struct wg_renderer_desc {
    int samples;                /* MSAA samples: 0 = 4 where the driver allows, 1 = none, else
                                   that many (clamped to GL_MAX_SAMPLES) */
} wg_renderer_desc;

/* Compile the shaders and build the static geometry in ctx (which must outlive the renderer).
 * desc may be NULL (defaults). Errors: INVALID_ARGUMENT, OUT_OF_MEMORY, GPU (compile/link log or
 * GL error in err). */
wc_status wg_renderer_create(wg_gl_context* ctx, const wg_renderer_desc* desc, wg_renderer** out,
                               char* err, size_t err_len);
/* Delete the GL objects (inside wg_gl_begin/end of its context: a host_current context's host
 * context must be current) and free. NULL is ignored. */
void wg_renderer_destroy(wg_renderer* r);

/* Render one picture into rgba_out (width x height x 4 bytes, rows top to bottom, alpha 255).
 * The framebuffer is (re)allocated when the size or sample count changes. Near and far planes
 * are fitted to the scene. eye == target: framed automatically (wg_camera_frame_auto) around
 * wg_scene_bounds, or, with nothing bounded, a 1 m box at the first plane's origin or at the
 * target.
 * A plane is drawn as a square around the rest of the scene: half-size 2.5 x the bounding radius
 * of the meshes, spheres and capsules (half-size 1 m without them), centred on the foot of their
 * bounding box's centre on the plane (the first plane's origin when there are none). It is
 * checkered in square cells aligned with the plane's local x and z axes from its origin, of the
 * largest 1, 2 or 5 x 10^k m not above a fifth of the half-size (odd cells 0.8 x as bright), and
 * pushed back by a polygon offset so that cloth resting on it wins.
 * Errors (rgba_out untouched): INVALID_ARGUMENT (NULL, size, fov, up zero or parallel to the
 * view, a negative count, bad shape type/radius, a transform that is singular or not affine),
 * OUT_OF_RANGE (a triangle index outside the mesh's vertices), NONFINITE (NaN/Inf in the camera,
 * positions, normals, colours, transforms, radii), OUT_OF_MEMORY, GPU (no context, framebuffer
 * incomplete or larger than the driver allows, a GL error: err says which). */
wc_status wg_render(wg_renderer* r, const wg_camera* cam, const wg_mesh* meshes, int n_meshes,
                      const wg_shape* shapes, int n_shapes, unsigned char* rgba_out, char* err,
                      size_t err_len);

/* Samples actually used by the last wg_render (1 = no MSAA), 0 before the first. */
int wg_renderer_samples(const wg_renderer* r);

/* Bounding box of the meshes and of the sphere and capsule shapes (planes are unbounded and left
 * out). Returns 0 (box untouched) when there is nothing bounded. Inputs are not validated. */
int wg_scene_bounds(const wg_mesh* meshes, int n_meshes, const wg_shape* shapes, int n_shapes,
                    float bmin[3], float bmax[3]);

/* Place cam->eye and cam->target so that the whole box is inside the picture (with a margin),
 * seen from the front-right and above (relative to cam->up), keeping up, fov and size. A box
 * of zero size is framed as a box of 1 m. Errors: INVALID_ARGUMENT (NULL, fov, size, up zero,
 * min > max), NONFINITE. */
wc_status wg_camera_frame_auto(wg_camera* cam, const float bmin[3], const float bmax[3],
                                 char* err, size_t err_len);

/* Column-major 4x4 view and OpenGL projection matrices (clip = proj * view * world) of cam with
 * the given near/far distances: what wg_render uses, for callers that project points.
 * Errors as wg_camera_frame_auto. */
wc_status wg_camera_matrices(const wg_camera* cam, float znear, float zfar, float view[16],
                               float proj[16], char* err, size_t err_len);

#ifdef __cplusplus
}
#endif
#endif
