/* The bodies core's copy moves, kept on the device (wg_mesh.h; compute passes, WEFT_GPU_BODY=device,
 * the default). A mesh collider whose frame end comes from the host's arrays
 * (weft_cloth_set_mesh_collider_vertices) or from a rigid transform x its rest shape reaches
 * core's from / to as on the CPU (the array call's checks and refusals are core's and the
 * plugin's, before anything here). At the frame's start its frame end is uploaded into the
 * resident bodies' to texture (16 bytes a vertex, only when it moves: core's from != to; from and
 * to both when it becomes resident), and every substep the body's passes (wg_mesh_body_substep)
 * and the GPU's sharp-feature pairs (wg_mesh_sharp.c) take it as they take a body from a host GL
 * buffer: core's wc_mesh_collider_substep and wc_mesh_pairs_find skip it (substep_on_device).
 *
 * Core's frame start and end stay current, so what reads them (the snapshot's save, the energy
 * judge's wc_mesh_collider_moving, sleep and wake, the array call, a rigid transform) behaves as
 * on the host; the invariant kept is that the from texture holds core's from rounded to float:
 * both become the end when a frame ends (wg_mesh_body_end_frame, core's driver), a failed frame
 * drops the bodies back to the host (wg_mesh_body_restore_backup: core's rollback restores its copy) and
 * anything that jumps core's copy (a snapshot's restore, TELEPORT, RESET) or reads its substep
 * arrays (the collision check) first pulls the bodies back (core's mesh_pull: no read-back for
 * these, core's substep arrays recomputed at from). The next frame uploads them again. */
#include "wg_mesh.h"

void wg_mesh_host_frame(wg_mesh* g) {
    if (!g || !g->body || !g->host_fed) return;
    for (int k = 0; k < g->n_mesh; ++k) {
        wc_mesh_collider* m = g->mesh[k];
        if (m->on_device) continue;   /* a host buffer's: its end is the buffer call's */
        if (!g->resident[k]) {
            wg_mesh_body_put(g, &g->from, k, m->from);
            wg_mesh_body_put(g, &g->to, k, m->to);
            wg_mesh_body_make_resident(g, k);
            m->substep_on_device = 1;
        } else if (wc_mesh_collider_moving(m)) {
            wg_mesh_body_put(g, &g->to, k, m->to);   /* else to = from already (the frame's end) */
        }
    }
}
