/* What a parsed scene holds (schema: sample_scenes/README.md), in the public API's types
 * (weft/weft.h) and the scene's own: the mesh (a file or a generated grid, transform applied), a
 * cloth def with the material and every simulation setting, pins, colliders, scripted motions of
 * pins, colliders and the object, a camera, and the frame count and rate. scene.h reads it. */
#ifndef WEFT_CLI_SCENE_TYPES_H
#define WEFT_CLI_SCENE_TYPES_H
#include "scene_motion.h"
#include "weft/weft.h"

/* Defaults of the fields the library does not default (see sample_scenes/README.md). */
#define SCENE_DEFAULT_FPS 30.0
#define SCENE_DEFAULT_FRAMES 60
#define SCENE_DEFAULT_THICKNESS 0.005        /* m, colliders */
#define SCENE_DEFAULT_FRICTION 0.3           /* colliders */
#define SCENE_DEFAULT_SELECT_TOLERANCE 1e-6  /* m, pin selects */
#define SCENE_GRID_MAX_SIDE 100000           /* vertices along one side of a grid */
#define SCENE_GRID_MAX_VERTICES 16777216     /* vertices of a grid */
#define SCENE_MAX_FILE_BYTES (64 << 20)      /* scene JSON text */
#define SCENE_DEFAULT_WIDTH 640              /* camera, pixels */
#define SCENE_DEFAULT_HEIGHT 480
#define SCENE_DEFAULT_FOV_DEG 40.0
#define SCENE_MAX_IMAGE_SIDE 8192

/* The host mesh: vertices in the file's (or the grid's) order, in metres, the scene transform
 * applied, and its polygons (3 or more corners each). */
typedef struct scene_mesh {
    int n_vertices;
    double* positions;      /* (n_vertices x 3) */
    int n_faces;
    int* face_sizes;        /* (n_faces) */
    int* face_start;        /* (n_faces + 1) offsets of each polygon's corners in indices */
    int* indices;           /* (face_start[n_faces]) host vertex indices */
} scene_mesh;

/* One entry of "pins": a set of host vertices sharing a free axis and a motion. */
typedef struct scene_pin {
    int n_vertices;
    int* vertices;          /* (n_vertices) host vertex indices: "vertices" as written (duplicates
                               kept), or the vertices "select" chose in ascending order */
    int from_select;        /* 1: chosen by "select" */
    int select_axis;        /* select: 0 x, 1 y, 2 z */
    int select_max;         /* select: 1 the "max" side, 0 the "min" side */
    double select_tolerance;/* select: m, vertices within this of the extreme */
    double free_axis[3];    /* unit vector (line constraint), or zero (fully pinned) */
    scene_motion motion;    /* "motion", or {"velocity": v} for the shorthand "velocity": v */
} scene_pin;

/* The pins as a host's attachments: one group per distinct (free_axis, motion), holding the
 * host vertices of every entry with those values (ascending, each once). A vertex named by two
 * entries with different values is refused at load time. */
typedef struct scene_pin_group {
    int n_vertices;
    int* vertices;          /* (n_vertices) host vertex indices */
    double free_axis[3];
    scene_motion motion;
    int first_pin;          /* index in pins of the group's first entry */
} scene_pin_group;

/* "object.teleport" entries: at the end of frame `frame` (1-based) the object and every pin
 * jump by translate (cumulative), stepped with WEFT_FRAME_TELEPORT. */
typedef struct scene_teleport {
    int frame;
    double translate[3];    /* m, world */
} scene_teleport;

/* "object": how the cloth object itself moves (its world transform is motion(t) times its rest
 * placement, plus the teleports so far) and how much of that motion the cloth feels. */
typedef struct scene_object {
    scene_motion motion;
    double linear_inertia;  /* [0, 1] (1) */
    double angular_inertia; /* [0, 1] (1) */
    int n_teleports;
    scene_teleport* teleports; /* (n_teleports) frames strictly increasing */
} scene_object;

/* "camera": the view for rendered frames (weft run --render). */
typedef struct scene_camera {
    int framed;             /* 1: eye and target given; 0: framed automatically */
    double eye[3];          /* m, world */
    double target[3];       /* m, world, != eye */
    double up[3];           /* unit, not along target - eye: (0, 1, 0) */
    double fov_deg;         /* vertical field of view, (0, 180): 40 */
    int width, height;      /* pixels, [1, SCENE_MAX_IMAGE_SIDE]: 640 x 480 */
} scene_camera;

/* A "colliders" entry of type plane, sphere or capsule, as written (scene_colliders.h places it
 * in the public API's local conventions), at rest until its motion moves it. */
typedef struct scene_collider {
    weft_collider_type type;
    double normal[3];       /* plane: unit normal (its free side) */
    double offset;          /* plane: m, the plane is normal . x = offset */
    double center[3];       /* sphere: m */
    double a[3], b[3];      /* capsule: m, the ends of its segment */
    double radius;          /* m, sphere and capsule */
    double thickness;       /* m (SCENE_DEFAULT_THICKNESS) */
    double friction;        /* (SCENE_DEFAULT_FRICTION) */
    scene_motion motion;
} scene_collider;

/* A "colliders" entry of type "mesh" (scene_mesh_collider.c): a triangle-mesh body from a file,
 * placed by a rigid transform and moved by a scripted motion, optionally animated per vertex by
 * a sequence of OBJ files (every file with the same vertices). World positions at time t:
 * motion(t) x transform x p, p the file's positions (x scale), interpolated linearly between
 * file frames at frames_fps (held at the last one). */
typedef struct scene_mesh_collider {
    char* file;             /* resolved path (the first frame file when only "frames" is given) */
    char* select;           /* node or mesh name, NULL for all */
    double scale;           /* metres per file unit (1) */
    double transform[16];   /* rest placement, rigid, column-major (identity) */
    double thickness;       /* m (SCENE_DEFAULT_THICKNESS) */
    double friction;        /* (SCENE_DEFAULT_FRICTION) */
    double push_speed;      /* m/s, "push_speed"; -1: the library's default */
    scene_motion motion;
    int n_verts;            /* vertices as read */
    int n_frames;           /* file frames of the vertex animation (0: none) */
    double frames_fps;      /* file frames per second */
    double* frames;         /* (n_frames x n_verts x 3) m: each file's positions x scale */
} scene_mesh_collider;

typedef struct scene {
    /* mesh */
    int mesh_is_grid;
    char* mesh_file;        /* file mesh: path resolved against the scene file's folder */
    double mesh_scale;      /* file mesh: metres per file unit (on top of FBX's unit) */
    char* mesh_select;      /* file mesh: node or mesh name, NULL for all */
    int grid_n[2];          /* grid: vertices along X and along Z */
    double grid_size[2];    /* grid: extent along X and along Z (m) */
    int has_transform;
    double transform[16];   /* 4x4 column-major (element (row r, column c) at [4c + r]), affine */
    scene_mesh mesh;        /* the host mesh in metres, transform applied */

    /* The cloth as the library takes it, but for what a host fills in when it creates it (the
     * mesh source and its placement, attachments, colliders, mesh colliders, inertia,
     * max_frame_time): weld tolerance, material, sewing (seam_a/seam_b point at the arrays
     * below), gravity, wind and drags, solver, tolerance, iteration cap, preconditioner,
     * integrator, Newton iterations, line search, substeps, strain limit, self-collision and
     * its thickness. The library's defaults where the scene says nothing. */
    weft_cloth_def def;
    int* seam_a;            /* (def.n_seams) mesh.seams host vertices, or NULL */
    int* seam_b;
    int threads;            /* "threads": OpenMP threads per call (0: OpenMP's default) */

    int n_pins;
    scene_pin* pins;        /* (n_pins) */
    int n_pin_groups;
    scene_pin_group* pin_groups; /* (n_pin_groups) the pins grouped as attachments */
    int n_colliders;
    scene_collider* colliders; /* (n_colliders) "colliders" entries of type plane, sphere, capsule */
    int n_mesh_colliders;
    scene_mesh_collider* mesh_colliders; /* (n_mesh_colliders) "colliders" entries of type "mesh" */
    scene_object object;
    scene_camera camera;
    double fps;             /* frames per simulated second (> 0) */
    int frames;             /* frames to simulate (>= 0) */
} scene;

#endif
