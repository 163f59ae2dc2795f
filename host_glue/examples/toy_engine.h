/* toy_engine: the smallest "game engine" that can host Weft the way a real one does, for the
 * engine_loop example. Nothing in it knows about Weft.
 *
 *  - A scene graph of bones: each has a parent and a local rigid transform; te_update_world()
 *    composes world = parent.world x local (parents are always added before their children).
 *  - A fixed-step loop (60 Hz in the example) that calls the callbacks "components" registered,
 *    phase by phase, every frame:
 *        TE_PHASE_ANIMATE  move bones (set their local transforms)
 *        (the engine then updates every world transform)
 *        TE_PHASE_PHYSICS  read world transforms, simulate (the cloth component lives here)
 *        TE_PHASE_RENDER   draw / write output
 *    A real engine accumulates wall-clock time and runs as many fixed steps as it owes; this one
 *    runs offline, one step per frame, as fast as it can.
 *  - 4x4 rigid-transform helpers in weft.h's convention: 16 floats, column-major (element row r,
 *    column c at m[4 c + r], translation at m[12..14]).
 *
 * Fixed capacities, no allocation: the whole engine is one struct the host owns. */
#ifndef TOY_ENGINE_H
#define TOY_ENGINE_H

#include <stdint.h>

#define TE_MAX_BONES 32
#define TE_MAX_CALLBACKS 16

/* ---- transforms (column-major float[16], rigid) ---- */
void te_identity(float m[16]);
/* Rotation by angle (rad) about the unit axis (ax, ay, az), then translation (tx, ty, tz). */
void te_rotate_translate(float m[16], double ax, double ay, double az, double angle, double tx,
                         double ty, double tz);
/* out = a x b (out may alias neither) */
void te_multiply(const float a[16], const float b[16], float out[16]);
/* out = m^-1 for a rigid m (R^T, -R^T t) */
void te_rigid_inverse(const float m[16], float out[16]);
/* out = m p (point) and m v (direction), computed in double */
void te_apply_point(const float m[16], const double p[3], double out[3]);
void te_apply_vector(const float m[16], const double v[3], double out[3]);

/* ---- scene graph ---- */
typedef struct te_bone {
    const char* name;           /* not copied: a string literal or owned by the host */
    int parent;                 /* index of the parent bone, -1 for a root */
    float local[16];            /* relative to the parent (the world for a root) */
    float world[16];            /* world transform, updated by te_update_world() */
} te_bone;

/* ---- frame loop ---- */
typedef enum te_phase {
    TE_PHASE_ANIMATE = 0,
    TE_PHASE_PHYSICS = 1,
    TE_PHASE_RENDER = 2,
    TE_PHASE_COUNT = 3
} te_phase;

typedef struct te_time {
    int64_t frame;              /* 1, 2, ... (frame 0 is the initial state, before the loop) */
    double t;                   /* s, simulated time at the end of this frame (frame x dt) */
    double dt;                  /* s, the fixed step */
} te_time;

struct te_engine;
/* A component's per-frame callback. Returns 0 to go on; anything else stops the loop after
 * this callback, and te_run() returns it. */
typedef int (*te_callback)(struct te_engine* engine, const te_time* time, void* user);

typedef struct te_engine {
    double dt;                  /* s, fixed step */
    int n_bones;
    te_bone bones[TE_MAX_BONES];
    int n_callbacks;
    struct {
        te_phase phase;
        const char* name;
        te_callback fn;
        void* user;
    } callbacks[TE_MAX_CALLBACKS];
} te_engine;

void te_init(te_engine* e, double dt);
/* Add a bone (parent -1 or an existing bone); returns its index, or -1 when full or the parent is
 * invalid. Its world transform is computed at once. */
int te_add_bone(te_engine* e, const char* name, int parent, const float local[16]);
/* Index of the bone with this name, or -1. */
int te_find_bone(const te_engine* e, const char* name);
/* world = parent.world x local for every bone, in order. */
void te_update_world(te_engine* e);
/* Register a callback for a phase (called in registration order within the phase). Returns 0,
 * or -1 when full. */
int te_register(te_engine* e, te_phase phase, const char* name, te_callback fn, void* user);
/* Run frames 1 .. n_frames. Returns 0, or the first nonzero value a callback returned (the loop
 * stops there). */
int te_run(te_engine* e, int64_t n_frames);

#endif
