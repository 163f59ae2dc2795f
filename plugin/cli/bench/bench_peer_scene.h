/* The cloth as Blender gets it, from a bench scene (bench_peer_scene.c). */
#ifndef WEFT_CLI_BENCH_PEER_SCENE_H
#define WEFT_CLI_BENCH_PEER_SCENE_H

#include "bench_blender.h"
#include "bench_scene.h"

/* pm from bs (free it with bench_peer_mesh_free). 0, or -1 with the message on stderr. */
int bench_peers_mesh(const bench_scene* bs, bench_peer_mesh* pm);

#endif
