/* The pieces of scene_parse (scene.c), one file per part of the schema: pins (scene_pins.c),
 * colliders (scene_colliders.c, scene_mesh_collider.c), the object (scene_object.c), the camera
 * (scene_camera.c), sewing (scene_seams.c). Each reads its key of the root object (absent:
 * defaults kept) and returns 0 or -1 with the failure recorded in the context's diag. Internal
 * to the scene library. */
#ifndef WEFT_CLI_SCENE_PARTS_H
#define WEFT_CLI_SCENE_PARTS_H
#include "scene_json.h"
#include "scene_types.h"

#define COUNT(a) ((int)(sizeof(a) / sizeof((a)[0])))

int scene_parse_pins(const sj_ctx* c, const cJSON* root, scene* s);
int scene_parse_colliders(const sj_ctx* c, const cJSON* root, scene* s);
int scene_parse_object(const sj_ctx* c, const cJSON* root, scene* s);
int scene_parse_camera(const sj_ctx* c, const cJSON* root, scene* s);
/* A "colliders" entry of type "mesh" at path, appended to s->mesh_colliders (room for n). */
int scene_parse_mesh_collider(const sj_ctx* c, const cJSON* item, const char* path, scene* s, int room);
void scene_free_mesh_colliders(scene* s);

/* mesh.sew_distance and mesh.seams (scene_seams.c), and the seams' vertices against the made mesh. */
int scene_parse_seams(const sj_ctx* c, const cJSON* mesh, scene* s);
weft_status scene_check_seams(const scene* s, const char* name, cli_diag* diag);

/* After scene_mesh_check_pins: fill s->pin_groups, refusing a host vertex named by two entries
 * with a different free_axis or motion (SCENE, naming the later entry's field). */
weft_status scene_group_pins(scene* s, const char* name, cli_diag* diag);

#endif
