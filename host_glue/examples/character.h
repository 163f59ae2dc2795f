/* character: the engine_loop example's walking character proxy, a game-side component that
 * knows nothing about Weft.
 *
 * Bones (toy_engine scene graph), in the root's frame (Y up, the character faces +Z, its left
 * is +X), fitted to sample_scenes/poncho.fbx (shoulder line a half cylinder of radius 0.14 m
 * around y = 1.40 m, top at y = 1.54 m):
 *
 *   root         on the ground; walks forward and turns left: a circle of radius 2.5 m at
 *                1.2 m/s, easing in from standing over the first second
 *   spine        1.0 m above the root; bobs twice per stride, leans forward, twists
 *   shoulder_l/r on the spine at (+-0.15, 0.45); bob and roll out of phase with each other
 *   arm_l/r      on the shoulders; swing forward and back
 *   leg_l/r      on the root at (+-0.10, 0.95); swing against the arms
 *
 * Collision proxies (shapes on bones): a torso capsule, a head sphere, two upper-arm capsules,
 * two leg capsules and the ground plane. */
#ifndef CHARACTER_H
#define CHARACTER_H

#include "toy_engine.h"

typedef struct character {
    int root, spine, shoulder[2], arm[2], leg[2];   /* bone indices; [0] left (+X), [1] right */
    double x, z, heading, phase;    /* integrated walk state: m, m, rad (about +Y), stride rad */
    double distance;                /* m walked */
} character;

/* Add the bones to the engine in the rest pose (at the origin, facing +Z) and update their world
 * transforms. Returns 1, or 0 when the engine has no room for them. */
int character_create(te_engine* e, character* c);

/* The animator: a te_callback for TE_PHASE_ANIMATE (user: the character). Advances the walk by
 * one step and sets the bones' local transforms. */
int character_update(te_engine* e, const te_time* time, void* user);

typedef enum character_shape {
    CHARACTER_PLANE = 0,        /* local plane y = 0, free side +y */
    CHARACTER_SPHERE = 1,       /* at the local origin */
    CHARACTER_CAPSULE = 2       /* local segment (0, -half_height, 0) .. (0, +half_height, 0) */
} character_shape;

typedef struct character_proxy {
    const char* name;
    const char* bone;           /* NULL: static, at the world origin */
    character_shape shape;
    double radius, half_height; /* m */
    double offset_y;            /* m along the bone's local Y */
} character_proxy;

#define CHARACTER_N_PROXIES 7
extern const character_proxy character_proxies[CHARACTER_N_PROXIES];

/* World transform of proxy k: its bone's world transform x its offset. */
void character_proxy_transform(const te_engine* e, int k, float out[16]);

#endif
