/* The cloth as Blender gets it, from a bench scene: the scene built by the library (the CPU
 * backend, the bench's definition) and its rest positions, pins and triangles handed to
 * bench_peer_mesh_make. Shared by `weft bench peers` and its --matched mode. */
#include "bench_peer_scene.h"

#include <string.h>

#include "bench_backend.h"
#include "bench_run.h"
#include "cli.h"
#include "scene_host.h"

int bench_peers_mesh(const bench_scene* bs, bench_peer_mesh* pm) {
    scene sc = bs->sc;
    sc.def = bench_run_def(bs);
    scene_host_opts ho;
    memset(&ho, 0, sizeof ho);
    ho.ctx = bench_backend_context(BENCH_CPU);
    scene_host h;
    char msg[1024];
    if (scene_host_create(&h, &sc, &ho, bs->name, msg, sizeof msg) != WEFT_OK) {
        cli_error(msg);
        return -1;
    }
    const int rc = bench_peer_mesh_make(pm, &bs->sc, h.positions, h.info.n_vertices, bs->name);
    scene_host_destroy(&h);
    if (rc != 0) cli_error("out of memory");
    return rc;
}
