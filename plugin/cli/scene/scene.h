/* A Weft scene file (JSON; schema in sample_scenes/README.md) read into a scene (scene_types.h).
 * scene_load validates everything it can before any simulation: schema, types, ranges, unknown
 * keys, the mesh itself (read through the public API's weft_mesh_read, or generated; transform
 * applied), pin vertex indices and pin conflicts. Nothing here simulates: `weft run` and
 * `weft bench` hand the result to the library (host/scene_host.h). */
#ifndef WEFT_CLI_SCENE_H
#define WEFT_CLI_SCENE_H
#include <stddef.h>

#include "cli.h"
#include "scene_types.h"

/* Read and validate the scene file at path (errors: IO, or SCENE with "PATH: FIELD: problem",
 * or the reader's status for a mesh file that cannot be read, prefixed "PATH: mesh.file:").
 * On failure *out is zeroed. */
weft_status scene_load(scene* out, const char* path, cli_diag* diag);
/* The same from JSON text; name is used in messages and its folder resolves relative mesh files. */
weft_status scene_parse(scene* out, const char* text, size_t len, const char* name, cli_diag* diag);
void scene_free(scene* s);

#endif
