/* Weft: implicit (Baraff-Witkin) cloth simulation as a shared-object plugin.
 * Public C ABI. Only the weft_ symbols declared here are exported from libweft.so.
 *
 * ---------------------------------------------------------------------------------------------
 * Using it (a host's frame loop):
 *
 *     weft_context_def cd = weft_default_context_def();
 *     weft_context* ctx = NULL;
 *     if (weft_context_create(WEFT_ABI, &cd, &ctx) != WEFT_OK) ...;   // ABI checked here
 *     weft_cloth_def def = weft_default_cloth_def();
 *     def.mesh.path = "shirt.fbx";
 *     weft_cloth cloth;
 *     if (weft_cloth_create(ctx, &def, &cloth) != WEFT_OK) puts(weft_context_last_error(ctx));
 *     for (;;) {                                     // once per host frame
 *         weft_frame fr = weft_default_frame();
 *         fr.dt = 1.0 / 60.0;
 *         fr.object_transform = object_world_matrix;   // float[16], column-major
 *         fr.attachment_transforms = bone_matrices;    // n_attachments x 16
 *         weft_cloth_step(ctx, cloth, &fr, NULL);
 *         weft_cloth_get_vertices(ctx, cloth, WEFT_SPACE_WORLD, positions, normals, n, &count);
 *     }
 *     weft_context_destroy(ctx);                      // destroys its cloths too
 *
 * ---------------------------------------------------------------------------------------------
 * Conventions
 *  - Units: SI (metres, kilograms, seconds). Mesh coordinates are multiplied by
 *    weft_cloth_def.unit_scale (FBX files: their UnitScaleFactor is applied first).
 *  - Y is up in the defaults (gravity (0, -9.81, 0)); nothing else assumes an up axis.
 *  - Host-facing arrays (vertex positions and normals, 4x4 transforms) are float, as in engines'
 *    vertex buffers; parameters are double; the simulation runs in double.
 *  - A 4x4 transform is 16 floats, column-major (OpenGL/glm/Blender convention transposed in
 *    memory): element (row r, column c) is m[4 * c + r]; the translation is m[12], m[13], m[14];
 *    the last row must be (0, 0, 0, 1). Transforms must be rigid (a rotation, |det - 1| and
 *    |R^T R - I| below 1e-3, plus a translation): scale the mesh instead (unit_scale, or bake
 *    the object's scale into the host arrays).
 *  - Vertex order: results come back in the host's own vertex order, split seam vertices
 *    included: welded vertices share one particle and report the same position. Host arrays:
 *    their order. OBJ files: the file's `v` lines in order, one vertex each (used or not; with
 *    mesh.select, the `v` lines the selected faces use, in file order), so results, pins by index
 *    and point caches lay over the user's own mesh. FBX files (binary or ASCII 7.x): each mesh
 *    Geometry's control points (`Vertices`) in file order, used or not (with mesh.select, the
 *    control points the selected polygons use, in file order); a control point several polygons
 *    share is one vertex, and control points at one position (a seam the file splits) stay
 *    separate vertices that weld. Several meshes or instances: one block per (node, Geometry)
 *    in the import's node order (depth first from the root; a Geometry at two nodes gives two
 *    blocks, each with its node's transform). A file whose polygons cannot be matched to
 *    assimp's is refused with WEFT_ERROR_IMPORT. Other files (glTF, PLY, ...): assimp's order
 *    (first use over the polygons), documented in core/source_mesh.h. weft_mesh_read reports
 *    the same order.
 *  - Every fallible call returns a weft_status. On failure nothing changes (the cloth's state,
 *    its outputs and every caller buffer are exactly as before), the context's last error holds
 *    a message naming the argument/field, and the logger (if any) receives it at ERROR level.
 *  - Nothing here calls exit() or abort(), and there is no global state: two contexts (or two
 *    hosts that load the library) in one process never interfere.
 *
 * Threading contract
 *  - A context and everything created from it must be used by one thread at a time (the host
 *    serialises its calls; Weft takes no locks). Different contexts may be used concurrently on
 *    different threads.
 *  - Broken contract: a call that finds another thread inside a call on the same context is
 *    refused at once with WEFT_ERROR_CONCURRENT_CALL (an atomic in-call flag per context): it
 *    changes nothing, writes no output and leaves the context's last error to the thread inside;
 *    weft_context_destroy in that situation logs an ERROR and does not destroy (the context
 *    leaks rather than being freed under the other call). Calls nested on the thread that is
 *    inside (from a logger or allocator callback) pass. Not detectable: any call after
 *    weft_context_destroy, and weft_context_last_error/last_status/backend, which only read.
 *  - Inside a call, Weft may use weft_context_def.threads OpenMP threads of its own; the call
 *    returns only when they are done, and no callback (logger, allocator) runs after it returns.
 *    The logger and allocator may be called from the calling thread only.
 *  - weft_version(), weft_status_string() and the weft_default_*() functions are thread-safe.
 * --------------------------------------------------------------------------------------------- */
#ifndef WEFT_H
#define WEFT_H

#include <stddef.h>
#include <stdint.h>

#include "weft_status.h"

#ifdef __cplusplus
extern "C" {
#endif

#if defined(WEFT_BUILDING_LIBRARY)
#define WEFT_API __attribute__((visibility("default")))
#else
#define WEFT_API
#endif

/* Header version. weft_version() returns the library's; hosts compare the two. */
#define WEFT_VERSION_MAJOR 0
#define WEFT_VERSION_MINOR 10
#define WEFT_VERSION_PATCH 2
/* Incremented on every incompatible change of a struct layout or a signature. The host passes
 * the WEFT_ABI it was compiled with to weft_context_create(); a different number is refused
 * with WEFT_ERROR_ABI_MISMATCH. */
#define WEFT_ABI 10

typedef struct weft_version_info {
    int major, minor, patch;
    int abi;             /* WEFT_ABI the library was built with */
} weft_version_info;

/* Version of the loaded library (never fails). */
WEFT_API weft_version_info weft_version(void);

/* Static English description of a status code; "unknown status" for values outside the list. */
WEFT_API const char* weft_status_string(weft_status status);

/* ============================================================================================= */
/* Context                                                                                       */
/* ============================================================================================= */

typedef struct weft_context weft_context;   /* opaque; one per host (or per host thread) */

typedef enum weft_log_level {
    WEFT_LOG_DEBUG = 0,
    WEFT_LOG_INFO = 1,
    WEFT_LOG_WARN = 2,
    WEFT_LOG_ERROR = 3
} weft_log_level;

/* Receives every message at or above weft_context_def.log_level; message is valid during the
 * call only. */
typedef void (*weft_log_fn)(weft_log_level level, const char* message, void* user);

/* Per-context allocator. Both functions or neither (NULL: malloc/free). alloc returns memory
 * aligned for any type (like malloc), or NULL on failure (then the call reports
 * WEFT_ERROR_OUT_OF_MEMORY and changes nothing). */
typedef struct weft_allocator {
    void* (*alloc)(size_t size, void* user);
    void (*free)(void* ptr, void* user);
    void* user;
} weft_allocator;

typedef enum weft_backend {
    WEFT_BACKEND_AUTO = 0,      /* per cloth: the GPU backend where it is built, a hardware device
                                   works, the GPU runs everything the cloth uses and the cloth has
                                   at least the device's crossover of particles; else CPU (a
                                   software rasteriser such as llvmpipe: CPU for every cloth).
                                   weft_cloth_info.backend_reason says which and why */
    WEFT_BACKEND_CPU = 1,       /* core/: OpenMP CPU solvers */
    WEFT_BACKEND_GPU = 2        /* gpu/: EGL + GLSL; WEFT_ERROR_UNSUPPORTED where it is not built */
} weft_backend;

/* AUTO's crossover: the particles from which a cloth takes the GPU, per device kind (a table,
 * docs/design/cloth.md "AUTO: the backend by the cloth"). The environment variable
 * WEFT_AUTO_CROSSOVER, read by weft_context_create for an AUTO context, replaces it: a whole
 * number of particles from 0 to 10^9 (0: every cloth the GPU runs whole), and then AUTO keeps a
 * software device too (tests, experts). Unset or empty: the table. */

/* Size of weft_cloth_info.backend_reason. */
enum {
    WEFT_BACKEND_REASON_LENGTH = 256   /* bytes, terminating zero included */
};

typedef enum weft_gl_mode {
    WEFT_GL_HEADLESS = 0,       /* the GPU backend creates its own headless EGL context */
    WEFT_GL_HOST_CURRENT = 1    /* it uses the GL context current on the calling thread at every
                                   call, saving and restoring the GL bindings it touches */
} weft_gl_mode;

typedef struct weft_context_def {
    weft_backend backend;       /* AUTO */
    int threads;                /* OpenMP threads per call; 0 = OpenMP's default (the core count) */
    weft_log_fn log;            /* NULL: no logging */
    void* log_user;
    weft_log_level log_level;   /* WEFT_LOG_WARN */
    weft_allocator allocator;   /* zeroed: malloc/free */
    weft_gl_mode gl_mode;       /* GPU backend only: WEFT_GL_HEADLESS */
    uint32_t internal_cookie;   /* set by weft_default_context_def(); do not touch */
} weft_context_def;

WEFT_API weft_context_def weft_default_context_def(void);

/* Create a context. abi: pass WEFT_ABI. Backend: GPU makes the GL context (headless, or the
 * host's current one per gl_mode) and compiles the solver's programs now; AUTO does the same and
 * keeps the device only where it is hardware (or WEFT_AUTO_CROSSOVER is set), to choose each
 * cloth's backend at weft_cloth_create; without one (a software rasteriser such as llvmpipe, or
 * no working device) every cloth runs on the CPU. The device and the renderer are logged at INFO.
 * Errors: ABI_MISMATCH, INVALID_ARGUMENT (NULL, def not from weft_default_context_def(), bad
 * enum, threads < 0, one allocator function without the other, AUTO with a WEFT_AUTO_CROSSOVER
 * that is not a particle count), UNSUPPORTED (GPU asked for and
 * not built), GPU (GPU asked for: no EGL device or context, no current host context, or the
 * device lacks float render targets; the message says which), OUT_OF_MEMORY. *out is NULL on
 * failure; the reason goes to the def's logger (there is no context to hold it). */
WEFT_API weft_status weft_context_create(int abi, const weft_context_def* def, weft_context** out);

/* Destroy the context and every cloth in it. NULL is ignored. Using the pointer afterwards is the
 * one misuse Weft cannot detect (as with free()). */
WEFT_API void weft_context_destroy(weft_context* ctx);

/* Message of the last failed call on this context ("" if none); valid until the next call. */
WEFT_API const char* weft_context_last_error(const weft_context* ctx);
/* Status of the last call on this context (WEFT_OK after a success). */
WEFT_API weft_status weft_context_last_status(const weft_context* ctx);
/* The device the context holds (never AUTO): GPU when its GPU device is open (GPU asked for, or
 * AUTO on a device it keeps), else CPU. Under AUTO a cloth may still run on the CPU: its own
 * backend is weft_cloth_info.backend. */
WEFT_API weft_backend weft_context_backend(const weft_context* ctx);

/* ============================================================================================= */
/* Cloth definition                                                                              */
/* ============================================================================================= */

/* A cloth handle: a value (no pointer) naming a slot of one context, with a generation and a type
 * tag, so that a destroyed, stale, foreign (other context) or forged handle is refused with
 * WEFT_ERROR_INVALID_HANDLE. Zero is the null handle. */
typedef struct weft_cloth {
    uint64_t id;
} weft_cloth;

/* The garment's mesh: either a file (path) or host arrays (positions), not both. */
typedef struct weft_mesh_desc {
    const char* path;           /* OBJ, FBX (ASCII or binary), glTF, ... (assimp); NULL for arrays */
    const char* select;         /* file: node or mesh name to import; NULL imports every mesh */
    const float* positions;     /* (n_vertices x 3) object space, mesh units */
    int n_vertices;
    const int* face_sizes;      /* (n_faces) corners per polygon (>= 3; 1 and 2 are ignored) */
    int n_faces;
    const int* indices;         /* (sum of face_sizes) vertex indices, counter-clockwise */
} weft_mesh_desc;

typedef enum weft_spring_type {
    WEFT_SPRING_STRETCH = 0,    /* mesh edges */
    WEFT_SPRING_SHEAR = 1,      /* quad diagonals and the wing springs of triangles */
    WEFT_SPRING_BEND = 2        /* two edges apart along nearly straight lines */
} weft_spring_type;

typedef struct weft_material {
    double density;             /* kg/m^2 of rest area (0.15) */
    double stiffness[3];        /* N/m per weft_spring_type (5000, 500, 50) */
    double damping[3];          /* N s/m per weft_spring_type (2, 0.5, 0.05) */
} weft_material;

typedef enum weft_solver {
    WEFT_SOLVER_PCG = 0,        /* Baraff-Witkin filtered PCG (default) */
    WEFT_SOLVER_JACOBI = 1,
    WEFT_SOLVER_CHEBYSHEV = 2,  /* Chebyshev-accelerated Jacobi */
    WEFT_SOLVER_DIRECT = 3      /* CHOLMOD sparse Cholesky */
} weft_solver;

/* PCG's preconditioner. */
typedef enum weft_preconditioner {
    WEFT_PRECOND_DEFAULT = 0,       /* the backend's choice: on the CPU (0.9.2) IC0 below 800 particles
                                       (with newton_forcing -1 as 0), AMG from 800; on a GPU AMG with
                                       compute passes (GL 4.3), block Jacobi on fragment passes */
    WEFT_PRECOND_BLOCK_JACOBI = 1,  /* filtered 3x3 block diagonal */
    WEFT_PRECOND_AMG = 2,           /* multigrid V-cycle: smoothed aggregation with rotations (on the
                                       GPU about the rest positions, compute passes only:
                                       gpu/solver/wg_amg.h) */
    WEFT_PRECOND_IC0 = 3            /* since 0.9.1, CPU only (the GPU refuses it; AUTO keeps the cloth on
                                       the CPU): block IC(0) of the filtered matrix; the CPU's default
                                       on small cloths (docs/bench/precond_by_size.md) */
} weft_preconditioner;

/* Time integrator of each substep. */
typedef enum weft_integrator {
    WEFT_INTEGRATOR_DEFAULT = 0,        /* the backend's choice (docs/design/cloth.md, "Defaults") */
    WEFT_INTEGRATOR_BACKWARD_EULER = 1, /* first order (Baraff & Witkin 1998) */
    WEFT_INTEGRATOR_BDF2 = 2,           /* second order (Choi & Ko 2002; both backends) */
    WEFT_INTEGRATOR_TRBDF2 = 3          /* second order, L-stable, one-step: a trapezoidal stage then a
                                           BDF2 stage per substep (Bank et al. 1985; both backends) */
} weft_integrator;

/* Pins: host vertices bound to a host transform (a bone, an object, or the world). At bind time
 * (weft_cloth_create, or weft_cloth_set_attachments later) each vertex's world position is
 * expressed in the frame of bind_transform; every frame it follows that frame's transform
 * (weft_frame.attachment_transforms[i]) rigidly. */
typedef struct weft_attachment_def {
    const int* vertices;        /* (n_vertices) host vertex indices; duplicates and welded twins
                                   merge; a vertex in two attachments is an error */
    int n_vertices;
    float bind_transform[16];   /* world transform of the bone at bind time (identity) */
    float free_axis[3];         /* bone-local unit axis the pinned vertices may slide along;
                                   zero (default): fully pinned */
    uint32_t internal_cookie;   /* set by weft_default_attachment_def() */
} weft_attachment_def;

typedef enum weft_collider_type {
    WEFT_COLLIDER_PLANE = 0,    /* local plane y = 0, free side +y (normal (0, 1, 0)) */
    WEFT_COLLIDER_SPHERE = 1,   /* local sphere at the origin, radius */
    WEFT_COLLIDER_CAPSULE = 2   /* local segment (0, -half_height, 0)..(0, +half_height, 0), radius */
} weft_collider_type;

/* A rigid collider whose world transform the host passes every frame
 * (weft_frame.collider_transforms[i]); its velocity is taken from the motion of its origin. */
typedef struct weft_collider_def {   /* every number finite, even those the type does not use */
    weft_collider_type type;    /* SPHERE */
    double radius;              /* m (0.5); sphere and capsule */
    double half_height;         /* m (0.5); capsule */
    double thickness;           /* m (0.005): the cloth stays this far outside the surface */
    double friction;            /* Coulomb coefficient >= 0 (0.3) */
    float transform[16];        /* world transform at creation (identity) */
    uint32_t internal_cookie;   /* set by weft_default_collider_def() */
} weft_collider_def;

/* A triangle-mesh collider: a body (rigid, or deforming/skinned) the cloth collides with, on
 * either backend (the GPU as the CPU does, the penalty pairs at the body's sharp edges and corners
 * included, except on a body kept on the GPU from a GL buffer: docs/design/gpu_bodies.md). The mesh comes from
 * a file (mesh.path, mesh.select: the same assimp import as a cloth's, polygons triangulated, no
 * welding) or from host arrays (mesh.positions, mesh.n_vertices, mesh.indices; mesh.face_sizes /
 * n_faces as for a cloth, or face_sizes NULL for n_faces triangles of 3 indices each). Winding:
 * the outward side is that of counter-clockwise triangles seen from outside, consistently over
 * the mesh (a closed body imported by assimp has it); an open mesh collides on its front side.
 * Motion, per frame: rigid, weft_frame.mesh_collider_transforms[i] applied to the mesh (world =
 * transform x (mesh x unit_scale)); or deforming, weft_cloth_set_mesh_collider_vertices() with
 * the world positions at the end of the next frame (that call wins over a transform for its
 * collider in that frame). The collider moves linearly from its previous end-of-frame positions
 * to the new ones across the frame, each surface point with its own velocity (friction carries
 * the cloth with it). Cost: a BVH refit per substep, a closest-point and a crossing query per
 * particle near the body. */
typedef struct weft_mesh_collider_def {
    weft_mesh_desc mesh;        /* required: a file or host arrays */
    double unit_scale;          /* metres per mesh unit (1); FBX UnitScaleFactor applied on top */
    float transform[16];        /* world transform at creation (identity), rigid */
    double thickness;           /* m (0.005): the cloth stays this far outside the surface */
    double friction;            /* Coulomb coefficient >= 0 (0.3) */
    double push_speed;          /* m/s >= 0 (0.05): a cloth vertex found inside the collider's
                                   thickness shell or behind its surface (a garment authored
                                   closer to the body than `thickness`, or starting inside it) is
                                   moved out at most this fast, so the implicit solve carries its
                                   neighbours along instead of the springs taking a jump; 0: put
                                   on the shell at once. A vertex that crosses the surface within a
                                   substep is put back at once whatever this says */
    uint32_t internal_cookie;   /* set by weft_default_mesh_collider_def() */
} weft_mesh_collider_def;

typedef struct weft_cloth_def {
    weft_mesh_desc mesh;        /* required */
    double unit_scale;          /* metres per mesh unit (1); FBX UnitScaleFactor applied on top */
    double weld_tolerance;      /* vertices closer than this x the bounding-box diagonal become one
                                   particle (sewn seams, UV splits): 1e-6; 0 disables welding */
    float transform[16];        /* world transform of the object at creation (identity): the
                                   particles start at transform x (mesh x unit_scale) */
    weft_material material;

    double gravity[3];          /* m/s^2, world (0, -9.81, 0) */
    double wind[3];             /* m/s, world (0, 0, 0) */
    double air_drag_normal;     /* kg/(m^2 s): pressure per unit relative normal speed (0.5) */
    double air_drag_tangent;    /* kg/(m^2 s): skin friction per unit tangential speed (0.02) */

    weft_solver solver;         /* PCG */
    double tolerance;           /* relative residual, [0, 1); -1: 1e-3 for BE, CPU DEFAULT, < 5k particles, else 1e-4 */
    int max_iterations;         /* iteration cap per solve (300) */
    weft_preconditioner preconditioner; /* DEFAULT */
    weft_integrator integrator; /* DEFAULT (backward Euler on both backends) */
    int newton_iterations;      /* linearised solves per substep, 1..100; 0 (default): the
                                   backend's choice (2 on both). 1 without line search is
                                   one Baraff-Witkin step */
    int line_search;            /* backtracking line search on the incremental potential:
                                   1 on, 0 off, -1 (default): the backend's choice (on for
                                   both) */
    int substeps;               /* implicit steps per frame (1) */
    double max_frame_time;      /* s: a longer weft_frame.dt is refused (0.25) */
    double strain_limit;        /* 0 off (default); 0.1 caps stretch springs at 110% of rest */

    /* Sleeping: a cloth whose fastest particle stays slower than sleep_speed for sleep_time
     * seconds of simulated time comes to rest: its velocities become zero and its frames cost
     * almost nothing (weft_frame_stats.asleep) until something it must feel changes; then it
     * wakes and that frame is simulated normally. It wakes when: an attachment transform moves
     * a pin (or weft_cloth_set_attachments changes the pins), a collider transform changes (or
     * moved last frame: its velocity changes), fr->wind changes, the object transform moves the
     * cloth through inertia (linear_inertia or angular_inertia below 1), fr->flags has
     * TELEPORT or RESET, or weft_cloth_restore puts back an awake state (a snapshot holds the
     * sleep state). With the default inertia the object transform alone never wakes it (the
     * cloth does not feel it). */
    double sleep_speed;         /* m/s (1e-3); 0: never sleeps */
    double sleep_time;          /* s (0.5) */

    /* Inertia (NvCloth-style), each in [0, 1]: the fraction of the object's own motion
     * (weft_frame.object_transform, frame to frame) the cloth feels. 1 (default): physical, the
     * cloth is simulated in the world. 0: the cloth does not feel that part of the object's
     * motion: it is carried with the object as if simulated in the object's space.
     * linear_inertia: the object's linear acceleration (a constant velocity is felt by no
     * setting). angular_inertia: the object's rotation about its origin. */
    double linear_inertia;      /* 1 */
    double angular_inertia;     /* 1 */

    int n_attachments;
    const weft_attachment_def* attachments;   /* (n_attachments), copied at creation */
    int n_colliders;
    const weft_collider_def* colliders;       /* (n_colliders), copied at creation */
    int n_mesh_colliders;
    const weft_mesh_collider_def* mesh_colliders; /* (n_mesh_colliders), read at creation */

    /* Sewing (docs/design/sewing.md): zero-rest-length springs that join panels (connected
     * components). sew_distance: every boundary vertex sews to the closest point (a vertex or a
     * point on an edge) of ANOTHER panel's boundary within this distance. seam_a[i] sews to
     * seam_b[i] (host vertex indices, vertex to vertex), however far apart they start: the
     * implicit solve pulls them together over the first frames. Seams are part of the model
     * (snapshots of a cloth with other seams are refused). Both backends sew. */
    double sew_distance;        /* m, after unit_scale; 0 (default): off */
    double sew_stiffness;       /* N/m per seam; 0 (default): material.stiffness[STRETCH]. Seam
                                   damping is material.damping[STRETCH] */
    const int* seam_a;          /* (n_seams) host vertex indices, copied at creation */
    const int* seam_b;          /* (n_seams) host vertex indices, != seam_a[i] */
    int n_seams;                /* >= 0 (0) */
    double seam_close_time;     /* s (0.5): a seam pair's rest length shrinks linearly from its
                                   start distance to 0 over this simulated time, so panels that
                                   start apart are drawn together, not snapped; 0: at once */

    /* Self-collision (docs/design/self_collision.md): the cloth against itself, its panels,
     * layers and separate pieces included; a cloth that starts a substep free of crossings ends
     * it free of them. Vertex-triangle and edge-edge pairs closer than the thickness are pushed
     * apart to it. */
    int self_collision;         /* 1 on, 0 off, -1 (default): on for a garment (a cloth with mesh
                                   colliders or seams), off otherwise, on either backend. The GPU
                                   runs the CPU's stage on the host after each substep (its
                                   positions and velocities read back, what it moved sent back)
                                   and has no self-contact pairs in its solve */
    double self_collision_thickness; /* m, finite and > 0 (0.003) */
    uint32_t internal_cookie;   /* set by weft_default_cloth_def() */
    /* Inexact Newton: with newton_iterations > 1, a substep's first linear solve stops at this
     * relative residual when it is above the tolerance (the later solves at the tolerance), so
     * the first, furthest-from-converged iterate costs fewer iterations. */
    double newton_forcing;      /* in [0, 1); 0: every solve to the tolerance; -1 (default): the
                                   backend's: 1e-2, or 0 where the CPU chose IC0 (DEFAULT above) */
} weft_cloth_def;

WEFT_API weft_cloth_def weft_default_cloth_def(void);
WEFT_API weft_attachment_def weft_default_attachment_def(void);
WEFT_API weft_collider_def weft_default_collider_def(void);
WEFT_API weft_mesh_collider_def weft_default_mesh_collider_def(void);

/* Build a cloth: import or read the mesh, weld, build springs and masses, bind the attachments.
 * In an AUTO context the cloth's backend is chosen here, once the mesh is welded (the GPU's
 * refusals and the particle count decide: weft_backend), and logged at INFO with the reason
 * that weft_cloth_info.backend_reason keeps; a cloth the GPU would refuse runs on the CPU.
 * Errors: INVALID_ARGUMENT (NULL, def not from weft_default_cloth_def(), both or neither mesh
 * source, bad enum or parameter, non-rigid transform), NONFINITE, OUT_OF_RANGE (a vertex index
 * outside the mesh, or a vertex beyond 1e30 in world or object space after unit_scale and
 * transform: the outputs are float), IO / IMPORT / EMPTY_MESH (the file or arrays),
 * UNSUPPORTED (GPU backend: the direct solver, which runs on the CPU only, a preconditioner
 * other than block Jacobi and multigrid, or the multigrid on fragment passes),
 * GPU (GPU backend: the model exceeds the device's texture limits, or a GL error; the message
 * says which),
 * OUT_OF_MEMORY. out is the null handle on failure. On the GPU backend every call on the cloth
 * runs inside the context's GL context (WEFT_GL_HOST_CURRENT: the host's, current on the calling
 * thread, its bindings restored); positions are read back only by weft_cloth_get_vertices,
 * weft_cloth_save, weft_cloth_set_attachments and weft_render. */
WEFT_API weft_status weft_cloth_create(weft_context* ctx, const weft_cloth_def* def, weft_cloth* out);
/* Destroy a cloth; its handle (and every copy) becomes stale. */
WEFT_API weft_status weft_cloth_destroy(weft_context* ctx, weft_cloth cloth);

/* Replace the attachments; the binding is taken now, from the cloth's current positions. */
WEFT_API weft_status weft_cloth_set_attachments(weft_context* ctx, weft_cloth cloth,
                                                const weft_attachment_def* attachments, int n);

typedef struct weft_cloth_info {
    int n_vertices;             /* host vertices: the size of every per-vertex output */
    int n_particles;            /* after welding */
    int n_triangles;
    int n_springs[3];           /* per weft_spring_type */
    int n_attachments, n_pinned_particles;
    int n_colliders;
    double total_mass;          /* kg */
    double bbox_min[3], bbox_max[3]; /* m, object space, rest shape */
    size_t snapshot_size;       /* bytes weft_cloth_save() writes */
    weft_backend backend;       /* CPU or GPU: where this cloth runs (why: backend_reason) */
    /* what the def's DEFAULT / 0 / -1 choices resolved to on this backend */
    weft_preconditioner preconditioner; /* BLOCK_JACOBI, AMG or IC0 */
    weft_integrator integrator; /* BACKWARD_EULER, BDF2 or TRBDF2 */
    int newton_iterations;      /* >= 1 */
    int line_search;            /* 0 or 1 */
    int n_seams;                /* seams sewn: by sew_distance plus the host pairs */
    int n_panels;               /* connected components left once seams join them */
    int self_collision;         /* 0 or 1 */
    double self_collision_thickness; /* m */
    double newton_forcing, tolerance; /* what the def's newton_forcing and tolerance resolved to */
    int threads;                /* OpenMP threads a call uses: weft_context_def.threads, or
                                   OpenMP's default (the core count) for 0 */
    char backend_reason[WEFT_BACKEND_REASON_LENGTH]; /* why the cloth runs on `backend`, one line:
                                   "asked for (...)" or "AUTO: ..." (the GPU's refusal, the particle
                                   count against the device's crossover, or why there is no GPU) */
} weft_cloth_info;

WEFT_API weft_status weft_cloth_get_info(weft_context* ctx, weft_cloth cloth, weft_cloth_info* out);

/* Collision check of the cloth's current positions (any backend; self-collision on or off). */
typedef struct weft_collision_check {
    int self_intersections;     /* edge-triangle pairs of the cloth that cross (an edge through a
                                   triangle's interior; pairs sharing a particle excluded) */
    double max_penetration;     /* m: deepest particle behind the surface of a collider (mesh
                                   colliders at their current positions, analytic ones at the
                                   last frame's; thickness not included); 0: none inside */
} weft_collision_check;

/* Errors: INVALID_HANDLE, INVALID_ARGUMENT (out NULL), OUT_OF_MEMORY. On the GPU backend the
 * positions are read back first. */
WEFT_API weft_status weft_cloth_check_collisions(weft_context* ctx, weft_cloth cloth, weft_collision_check* out);

/* Mechanical energy and mass distribution of the cloth's current state (any backend; on the GPU
 * the positions and velocities are read back first). Their sum kinetic + elastic + gravity is
 * the total energy a conservative system keeps. */
typedef struct weft_cloth_energy {
    double kinetic;             /* J: sum of m |v|^2 / 2 over the particles */
    double elastic;             /* J: the springs' potential energy (stretch, shear, bend, seams) */
    double gravity;             /* J: sum of -m g . x (g the cloth's gravity, x world positions:
                                   relative to the world origin) */
    double mass;                /* kg */
    double center_of_mass[3];   /* m, world */
} weft_cloth_energy;

/* Errors: INVALID_HANDLE, INVALID_ARGUMENT (out NULL), GPU (the read-back). Nothing changes. */
WEFT_API weft_status weft_cloth_get_energy(weft_context* ctx, weft_cloth cloth, weft_cloth_energy* out);

/* Sizes of weft_import_report's arrays. */
enum {
    WEFT_REPORT_POLYGON_SIDES = 8,   /* polygons[k] counts k-gons; polygons[8] counts 8 or more */
    WEFT_REPORT_MAX_WARNINGS = 16,   /* warnings kept (more are counted in warnings_dropped) */
    WEFT_REPORT_WARNING_LENGTH = 256 /* bytes of each warning, terminating zero included */
};

/* What weft_cloth_create made of the mesh: the source as read, the simulated model after
 * welding and cleaning, the springs, and the warnings it logged. */
typedef struct weft_import_report {
    int source_vertices;        /* host vertices */
    int unused_vertices;        /* host vertices no polygon uses (not simulated) */
    int welded_vertices;        /* host vertices merged into another one's particle */
    int particles;
    int polygons[WEFT_REPORT_POLYGON_SIDES + 1]; /* source polygons by corner count ([3]
                                   triangles .. [8] 8 or more); [1] points and [2] lines, which
                                   are ignored; [0] is 0 */
    int triangles;              /* kept for the simulation */
    int degenerate_triangles;   /* zero area or a repeated particle: dropped */
    int duplicate_faces;        /* the same three particles as an earlier triangle: dropped */
    int flipped_faces;          /* rewound so that each component's winding agrees */
    int non_orientable_components;
    int edges;
    int boundary_edges;
    int non_manifold_edges;     /* particle pairs shared by more than two triangles */
    int boundary_loops;
    int components;             /* connected components of the triangle mesh */
    int springs[4];             /* per weft_spring_type, then [3] the seam springs */
    int seams;                  /* seams sewn: by sew_distance plus the host pairs */
    int panels;                 /* components left once the seams join them */
    double bbox_min[3], bbox_max[3]; /* m, object space, over the particles */
    double unit_scale;          /* metres per mesh unit applied (FBX's UnitScaleFactor included) */
    double weld_distance;       /* m: the absolute weld distance used */
    /* wall time of each stage of building the model (ms) */
    double ms_weld, ms_triangulate, ms_clean, ms_orient, ms_topology, ms_springs, ms_pattern, ms_total;
    int n_warnings;             /* entries of warnings in use (<= WEFT_REPORT_MAX_WARNINGS) */
    int warnings_dropped;       /* warnings beyond those */
    char warnings[WEFT_REPORT_MAX_WARNINGS][WEFT_REPORT_WARNING_LENGTH]; /* one line each */
} weft_import_report;

/* The import report of the cloth's mesh (the same on every backend). Errors: INVALID_HANDLE,
 * INVALID_ARGUMENT (out NULL). */
WEFT_API weft_status weft_cloth_get_report(weft_context* ctx, weft_cloth cloth, weft_import_report* out);

/* A mesh file read into host arrays, exactly as weft_cloth_create (and a mesh collider) reads it:
 * the same assimp import, vertex order and unit scale, no welding or cleaning. For hosts that
 * need a file's vertices or polygons themselves (picking vertices to pin, writing results with
 * the file's faces). Positions are double: the values the simulation starts from. */
typedef struct weft_mesh_data {
    int n_vertices;
    int n_faces;                /* polygons of 3 or more corners (points and lines are dropped) */
    double* positions;          /* (n_vertices x 3) m: file coordinates x unit_scale */
    int* face_sizes;            /* (n_faces) corners of each polygon */
    int* indices;               /* (sum of face_sizes) vertex indices, in the file's winding */
    double unit_scale;          /* metres per file unit applied: the unit_scale asked for times
                                   FBX's UnitScaleFactor */
} weft_mesh_data;

/* Read path (select: a node or mesh name as weft_mesh_desc.select, NULL for every mesh) with
 * unit_scale metres per unit (finite, > 0). The arrays come from the context's allocator:
 * release them with weft_mesh_free. Errors (*out zeroed): INVALID_ARGUMENT (NULL path or out,
 * empty path, unit_scale out of range), IO, IMPORT, EMPTY_MESH, NONFINITE (a coordinate in the
 * file), OUT_OF_MEMORY. */
WEFT_API weft_status weft_mesh_read(weft_context* ctx, const char* path, const char* select, double unit_scale,
                                    weft_mesh_data* out);
/* Release what weft_mesh_read allocated and zero *mesh (NULL, or a zeroed mesh: nothing). Use the
 * context that read it. */
WEFT_API void weft_mesh_free(weft_context* ctx, weft_mesh_data* mesh);

/* ============================================================================================= */
/* Per frame                                                                                     */
/* ============================================================================================= */

enum {
    WEFT_FRAME_TELEPORT = 1u << 0, /* the object (and its attachments) jumped: carry the cloth
                                      with the object's transform, keep its velocities relative to
                                      the object, no inertia from the jump */
    WEFT_FRAME_RESET = 1u << 1     /* back to the rest shape at this frame's object transform,
                                      zero velocity, contacts cleared, then step */
};

typedef struct weft_frame {
    double dt;                  /* s, in (0, max_frame_time] */
    const float* object_transform;      /* 16: the object's world transform at the end of the
                                           frame; NULL: unchanged */
    const float* attachment_transforms; /* (n_attachments x 16) at the end of the frame; NULL:
                                           unchanged. Pins move linearly across the frame. */
    const float* collider_transforms;   /* (n_colliders x 16) at the end of the frame; NULL:
                                           unchanged */
    const double* wind;         /* 3, m/s world; NULL: unchanged */
    uint32_t flags;             /* WEFT_FRAME_* */
    const float* mesh_collider_transforms; /* (n_mesh_colliders x 16) rigid, at the end of the
                                           frame; NULL: unchanged */
} weft_frame;

WEFT_API weft_frame weft_default_frame(void);

/* Mesh collider `index`'s world vertex positions (m; n_vertices x 3 floats, host order, the
 * count the collider was created with) at the end of the next frame: a deforming (skinned) body.
 * Errors (nothing changes): INVALID_ARGUMENT (NULL positions), OUT_OF_RANGE (index, or a wrong
 * n_vertices), NONFINITE (a NaN or Inf), OUT_OF_RANGE (a coordinate beyond 1e30). TELEPORT or
 * RESET in the next frame puts the collider there at once (no motion across that frame). */
WEFT_API weft_status weft_cloth_set_mesh_collider_vertices(weft_context* ctx, weft_cloth cloth, int index,
                                                           const float* positions, int n_vertices);

/* The same, from a host GL buffer object: GPU cloths in WEFT_GL_HOST_CURRENT mode (a body skinned
 * on the GPU). `buffer` is a name of the host's context, current on the calling thread; vertex i
 * is 3 floats (world, m, as the array call takes them) at byte offset + i * stride (stride 0:
 * 12, packed; other strides read xyz out of interleaved vertices). The buffer's contents are
 * taken at the call: the host may overwrite or delete it afterwards. The host's writes to it must
 * be visible to buffer copies (after a compute shader wrote it as a storage buffer:
 * glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT)); the buffer must not be mapped, except
 * persistently. The host's GL bindings are left as they were.
 * Where the GPU runs compute passes (GL 4.3) the vertices stay on the GPU: copied from the
 * buffer there and checked there (16 bytes read back: the call waits for the GPU to finish the
 * host's commands that write the buffer), and the body's motion across the frame, its normals,
 * its BVH refit and its fastest vertex are computed there every substep, in float; the result
 * agrees with the array call's to float's reach, not bit for bit. Vertices bit-identical to where
 * the body starts the frame (the same floats frame after frame: a body standing still) leave it
 * still, so the cloth may fall asleep on it and sleeps on, as with the array call; any other
 * vertices wake it. The body comes back to the CPU only when the host needs it there:
 * weft_cloth_save, weft_cloth_check_collisions, the array call, a rigid transform for it in a
 * frame without this call, TELEPORT or RESET (until the next call of this one, the body is then
 * moved on the CPU). While a body is kept on the GPU, the cloth's sharp-feature penalty pairs
 * (those of every mesh collider) are not looked for: reading the body back every substep is what
 * this call avoids. With fragment passes (a GL 3.3 context) the vertices are read back and take
 * the array call's path, bit-identical to it.
 * Errors (nothing changes): INVALID_HANDLE, OUT_OF_RANGE (index, or a wrong n_vertices),
 * INVALID_ARGUMENT (buffer 0 or not a buffer object, one smaller than offset + (n_vertices - 1)
 * stride + 12 bytes, offset or stride not a multiple of 4, a stride of 4 or 8, a buffer the host
 * has mapped), UNSUPPORTED (a CPU cloth: use weft_cloth_set_mesh_collider_vertices; a
 * WEFT_GL_HEADLESS context, whose buffer names are not the host's), NONFINITE or OUT_OF_RANGE (a
 * coordinate, as the array call), GPU (no current context, a GL error). */
WEFT_API weft_status weft_cloth_set_mesh_collider_gl_buffer(weft_context* ctx, weft_cloth cloth, int index,
                                                            unsigned buffer, size_t offset, size_t stride,
                                                            int n_vertices);

typedef struct weft_frame_stats {
    double ms_total;            /* wall time of the call */
    double ms_forces, ms_assemble, ms_solve, ms_collide, ms_integrate;
    int substeps;               /* completed (halved retries count each piece) */
    int iterations;             /* solver iterations, summed over substeps */
    int solves;                 /* linear solves (Newton iterations, friction passes included) */
    double ms_precond;          /* wall time building preconditioners (part of ms_solve) */
    int max_iterations;         /* largest in one solve */
    double residual;            /* largest final relative residual */
    int not_converged;          /* solves that stopped at the cap above tolerance */
    weft_solver solver;         /* last solver used */
    int rollbacks, halvings, direct_fallbacks, failures;
    int contacts;               /* particles in contact at the end */
    double max_strain;          /* largest stretch-spring strain at the end */
    double kinetic_energy;      /* J, end of the frame */
    double time;                /* s, simulated since creation or the last reset */
    int64_t frame;              /* frames stepped */
    int asleep;                 /* 1: the cloth slept through this frame: nothing was simulated
                                   (substeps and iterations 0), positions are unchanged and
                                   velocities zero (weft_cloth_def.sleep_speed) */
    int fell_asleep;            /* 1: it came to rest in this frame and sleeps from the next one */
    int woke;                   /* 1: it was asleep and an input change woke it: this frame was
                                   simulated */
    /* self-collision, summed over the frame's substeps (0 when it is off) */
    int self_impacts;           /* colliding pairs found (and given impulses) during the substeps */
    int self_zones;             /* rigid impact zones formed */
    int self_unresolved;        /* pairs left colliding when the zone loop gave up (0 normally) */
    double ms_self_collide;     /* wall time of the self-collision stage (GPU: with its
                                   read-backs and uploads) */
    /* the solve in detail, summed over the frame's substeps */
    int newton_steps;           /* Newton iterations taken after each substep's first solve */
    int line_search_backtracks; /* step halvings of the line search */
    int energy_steps;           /* Newton iterations the energy guard added past newton_iterations */
    int friction_passes;        /* extra solves because sticking contacts had to slide */
    int bdf2_substeps;          /* steps taken as BDF2 (TR-BDF2: its BDF2 stages) */
    /* self-collision in detail, summed over the substeps (0 when it is off) */
    int self_proximity;         /* proximity impulses of the self-collision stage */
    int self_zone_relaxed;      /* stretch-spring corrections around its impact zones */
    int self_pairs;             /* self-contact pairs found for the implicit solve */
    int self_pairs_active;      /* ... of them active in the first system */
    int self_pair_passes;       /* extra solves because their active set changed */
    int self_pair_overflow;     /* pairs past the list's capacity (dropped, logged as a warning) */
    /* the mesh colliders' feature contacts in the solve, summed over the substeps */
    int mesh_pairs;             /* edge-edge and body-vertex/cloth-triangle pairs found */
    int mesh_pairs_active;      /* ... of them active in the first system */
    int mesh_pair_passes;       /* extra solves because their active set changed */
    int mesh_pair_overflow;     /* pairs past the list's capacity (dropped, logged as a warning) */
    int mesh_pair_skipped;      /* pairs whose particles the system has no block for (dropped) */
} weft_frame_stats;

/* Advance by fr->dt. Errors (state unchanged): INVALID_ARGUMENT (NULL, dt <= 0 or above
 * max_frame_time, non-rigid transform, unknown flag), NONFINITE (NaN/Inf in dt, a transform or
 * wind), STEP_FAILED (every recovery failed, or the step would take a vertex beyond 1e30 in world
 * or object space, out of float outputs' reach: the cloth is left as it was before the call).
 * stats may be NULL. */
WEFT_API weft_status weft_cloth_step(weft_context* ctx, weft_cloth cloth, const weft_frame* fr,
                                     weft_frame_stats* stats);

/* Advance n cloths of the context in one call, cloths[i] by frames[i] (arrays of n; stats and
 * statuses may be NULL). Each cloth gets exactly what weft_cloth_step would give it (the same
 * checks, state, statistics and status; its positions bit for bit), so a batch and n single
 * calls are interchangeable. What the batch adds: on the CPU the cloths run at once over the
 * context's threads (with at least as many cloths as threads, one thread each, else one after
 * the other on all of them); on the GPU one switch to the GL context serves every cloth (their
 * pass chains run one after the other). stats[i].ms_total is the wall time of cloth i's own step.
 * A bad entry (a NULL, stale or foreign handle, a cloth named twice: the second, a frame that
 * weft_cloth_step refuses) or a cloth whose step fails is left unchanged and reported at its
 * index: statuses[i] (WEFT_OK for the others), a message "weft_context_step: cloths[i]: ..." or
 * "...: frames[i].dt ..." to the logger; the other cloths still step. Returns WEFT_OK when every
 * cloth stepped, else the status of the lowest failing index, whose message is the context's last
 * error (with how many failed). stats[i] is written for the cloths that stepped only. Refused as
 * a whole (nothing steps, statuses untouched): INVALID_ARGUMENT (n < 0, cloths or frames NULL
 * with n > 0). n = 0 does nothing. What a cloth logs while it steps reaches the logger after the
 * steps, from the calling thread (at most 4 lines per cloth, then a count). */
WEFT_API weft_status weft_context_step(weft_context* ctx, int n, const weft_cloth* cloths, const weft_frame* frames,
                                       weft_frame_stats* stats, weft_status* statuses);

/* ============================================================================================= */
/* Results                                                                                       */
/* ============================================================================================= */

typedef enum weft_space {
    WEFT_SPACE_WORLD = 0,
    WEFT_SPACE_OBJECT = 1       /* the inverse of the last object transform applied, divided by
                                   unit_scale: directly comparable with the host's mesh */
} weft_space;

/* Positions and smooth (area-weighted) unit normals per host vertex, (capacity x 3) floats each;
 * either may be NULL. *count receives n_vertices. Size query: both NULL (capacity ignored).
 * Error OUT_OF_RANGE when capacity < n_vertices (nothing written). */
WEFT_API weft_status weft_cloth_get_vertices(weft_context* ctx, weft_cloth cloth, weft_space space,
                                             float* positions, float* normals, int capacity, int* count);

/* The simulated triangles as host vertex indices, (capacity x 3) ints; *count receives
 * n_triangles; indices NULL: size query. */
WEFT_API weft_status weft_cloth_get_triangles(weft_context* ctx, weft_cloth cloth, int* indices,
                                              int capacity, int* count);

/* GPU cloths in WEFT_GL_HOST_CURRENT mode: the positions and normals of weft_cloth_get_vertices
 * (same space, values and host vertex order) written on the GPU straight into the host's GL
 * buffer objects (names in the host's context, current on the calling thread): 3 floats per host
 * vertex, tightly packed, from byte offset *_offset (a multiple of 4); a name of 0 skips that
 * array. The host's GL bindings are left as they were. Nothing is read back to the CPU.
 * Errors: UNSUPPORTED (a CPU cloth, or a WEFT_GL_HEADLESS context: its buffer names are not the
 * host's), INVALID_ARGUMENT (bad space, a name that is not a buffer object, a buffer smaller than
 * offset + 12 n_vertices bytes, overlapping ranges in one buffer), GPU (no current context, GL
 * error). */
WEFT_API weft_status weft_cloth_write_gl_buffers(weft_context* ctx, weft_cloth cloth, weft_space space,
                                                 unsigned position_buffer, size_t position_offset,
                                                 unsigned normal_buffer, size_t normal_offset);

/* ============================================================================================= */
/* Snapshots (host caches, timeline scrubbing)                                                   */
/* ============================================================================================= */

/* Write the cloth's whole mutable state (positions, velocities, time, pins, colliders, contacts,
 * transforms, the solver's warm start) into buf: weft_cloth_info.snapshot_size bytes
 * (OUT_OF_RANGE if size is smaller). Restoring it and stepping gives bit-identical results. */
WEFT_API weft_status weft_cloth_save(weft_context* ctx, weft_cloth cloth, void* buf, size_t size);
/* Restore a snapshot. Refused with WEFT_ERROR_SNAPSHOT_MISMATCH when it was taken from a cloth
 * with another model (mesh, welding, material, attachments or colliders), or by another
 * library version; INVALID_ARGUMENT when it is truncated or damaged. */
WEFT_API weft_status weft_cloth_restore(weft_context* ctx, weft_cloth cloth, const void* buf, size_t size);

/* ============================================================================================= */
/* Preview rendering (off-screen EGL + OpenGL, llvmpipe without a GPU; PNG through libpng)       */
/* ============================================================================================= */

/* Shaded picture of a cloth (two-sided, front and back coloured differently) and its colliders
 * at their current transforms. The EGL context is created at the first call and kept by the
 * weft_context (a context that never renders pays nothing); in WEFT_GL_HOST_CURRENT mode the
 * host's current context is used and its bindings restored. */
typedef struct weft_render_def {
    int width, height;          /* pixels (640 x 480), 1..8192 */
    float eye[3];               /* camera position, world (m) */
    float target[3];            /* point looked at; eye == target (default zeros): framed
                                   automatically from the cloth's and colliders' bounding box */
    float up[3];                /* (0, 1, 0) */
    float fov_y_deg;            /* vertical field of view, degrees in (0, 180) (40) */
    int draw_colliders;         /* 1 */
    const char* png_path;       /* write an 8-bit RGB PNG here; NULL: no file */
    unsigned char* rgba;        /* (width x height x 4) caller buffer, rows top to bottom; NULL:
                                   no copy */
    uint32_t internal_cookie;   /* set by weft_default_render_def() */
} weft_render_def;

WEFT_API weft_render_def weft_default_render_def(void);

/* Errors: INVALID_ARGUMENT, NONFINITE, UNSUPPORTED (built without WEFT_GPU), GPU (no EGL
 * device, context or framebuffer: the message says which), IO (PNG not written). */
WEFT_API weft_status weft_render(weft_context* ctx, weft_cloth cloth, const weft_render_def* def);

#ifdef __cplusplus
}
#endif
#endif
