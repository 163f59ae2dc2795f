/* A scene collider's rest placement in the public API's local conventions (weft.h: plane y = 0
 * with normal +Y; sphere at the origin; capsule along local Y from -half_height to +half_height). */
#ifndef WEFT_CLI_SCENE_COLLIDERS_H
#define WEFT_CLI_SCENE_COLLIDERS_H
#include "scene_types.h"

/* The rigid transform xf (column-major) that places c, and for a capsule its half height (m; 0
 * otherwise). */
void scene_collider_placement(const scene_collider* c, double xf[16], double* half_height);

#endif
