/* The pieces of scene_parse (scene.c), one file per part of the schema: pins (scene_pins.c),
 * colliders (scene_colliders.c), the object (scene_object.c), the camera (scene_camera.c).
 * Each reads its key of the root object (absent: defaults kept) and returns 0 or -1 with the
 * failure recorded in the context's diag. Internal to the scene library. */
#ifndef WEFT_CLI_SCENE_PARTS_H
#define WEFT_CLI_SCENE_PARTS_H
#include "scene.h"
#include "scene_json.h"

#define COUNT(a) ((int)(sizeof(a) / sizeof((a)[0])))

/* "PARENT.KEY: missing[ hint]" unless obj has key; 0 or -1. */
int scene_require(const sj_ctx* c, const cJSON* obj, const char* parent, const char* key, const char* hint);
/* An optional nonzero 3-vector, normalised; 0 absent, 1 read, -1 error. */
int scene_axis_vector(const sj_ctx* c, const cJSON* obj, const char* parent, const char* key, double* v);
/* A copy of s (NULL when out of memory). */
char* scene_strdup(const char* s);

int scene_parse_pins(const sj_ctx* c, const cJSON* root, scene* s);
int scene_parse_colliders(const sj_ctx* c, const cJSON* root, scene* s);
int scene_parse_object(const sj_ctx* c, const cJSON* root, scene* s);
int scene_parse_camera(const sj_ctx* c, const cJSON* root, scene* s);
/* A "colliders" entry of type "mesh" at path, appended to s->mesh_colliders (room for n). */
int scene_parse_mesh_collider(const sj_ctx* c, const cJSON* item, const char* path, scene* s, int room);
void scene_free_mesh_colliders(scene* s);
/* name's folder joined with file (allocated; NULL when out of memory). */
char* scene_resolve_path(const char* name, const char* file);

/* mesh.sew_distance and mesh.seams (scene_seams.c), and the seams' vertices against the made mesh. */
int scene_parse_seams(const sj_ctx* c, const cJSON* mesh, scene* s);
weft_status scene_check_seams(const scene* s, const char* name, cli_diag* diag);

/* After scene_mesh_check_pins: fill s->pin_groups, refusing a host vertex named by two entries
 * with a different free_axis or motion (SCENE, naming the later entry's field). */
weft_status scene_group_pins(scene* s, const char* name, cli_diag* diag);

#endif
