/* Snapshots: the cloth's whole mutable state in a flat byte buffer (native byte order; meant for
 * the same build on the same machine: host caches, timeline scrubbing), and the whole-frame
 * backup that undoes a failed frame (the same walk without the header, into c->backup).
 *
 * Layout (format 3, magic "WEFTSNP3"; x starts at byte 64): a 40-byte header (magic, ABI,
 * library version, total size, model fingerprint, checksum of everything else) then, field by
 * field (no padding), each module walking what it owns (serial.h):
 *   state (state_serial.h)   time, accumulator, frame; x, v, dv (n x 3 each; dv is the next
 *                            solve's initial guess); pins (particle, target, free_axis) and their
 *                            start-of-frame targets; colliders (all wc_collider fields: world
 *                            geometry and velocity); contacts (collider, normal, released,
 *                            active); the air's wind (a frame's wind changes it)
 *   cloth                    T0, V0, no_history (the object's transform history: inertia);
 *                            the last applied attachment and collider transforms
 *   state history            Chebyshev's rho cache (valid, rho: a different value changes every
 *                            later Chebyshev solve); the multigrid's carried eigenvalue
 *                            estimates (valid, age, terms mask, 12 levels' estimates: amg.h
 *                            bound_carry; a substep's first solve may take them); asleep and the rest timer (restoring an
 *                            asleep snapshot puts the cloth to sleep with the restored wind);
 *                            BDF2's history (valid, h, x_prev, v_prev (n x 3), always present,
 *                            read only when valid; after the sleep state, whose restore would
 *                            invalidate it)
 *   per mesh collider        from, to (n_verts x 3 each: world positions at the start and end
 *                            of the next frame; mesh_collider.h), then the cloth's last rigid
 *                            transform and whether the host set vertices for the next frame
 * Older formats (WEFTSNP1, WEFTSNP2) are refused as not snapshots of this format.
 * Nothing else carries over between steps: x0/v0/dv0 and contacts_save are written at every
 * substep's start; the filter, forces, matrix, right-hand side and residual are rebuilt by every
 * substep; the solvers' vectors and preconditioner by every solve (PCG/Jacobi start from dv, the
 * direct solver refactorises; the multigrid's estimates above aside); wc_par's partial sums are
 * per-reduction scratch; seam_scale (the host seam pairs' ramp, sew.h) is derived from time at
 * every frame's start; self-collision keeps
 * nothing (its start positions are copied at every substep's start, its trees refitted by every
 * pass); a mesh collider's substep positions, normals and boxes are recomputed.
 *
 * The fingerprint hashes what must match for the state to mean the same thing: particles (host
 * map, rest positions, masses), triangles, springs (seam springs included), material, seams'
 * closing time, the pinned particles and their attachments, the colliders' count, types and
 * sizes, and the mesh colliders' topology, rest shape, thickness and friction.
 *
 * On a backend with a mirror (cloth_backend.h) a snapshot is written after a download and
 * uploaded after a restore; the whole-frame backup leaves the mirrored arrays to the backend's
 * own backup. */
#include <math.h>
#include <string.h>
#include "cloth_internal.h"
#include "state_serial.h"

#define SNAP_MAGIC "WEFTSNP3"
#define SNAP_HEADER 40

/* ---- hashing (64-bit, word at a time; not cryptographic) ------------------------------------- */

static uint64_t mix(uint64_t h, uint64_t w) {
    h ^= w + 0x9E3779B97F4A7C15ull + (h << 6) + (h >> 2);
    h *= 0xBF58476D1CE4E5B9ull;
    return h ^ (h >> 31);
}

static uint64_t hash_bytes(uint64_t h, const void* data, size_t n) {
    const unsigned char* p = data;
    size_t i = 0;
    for (; i + 8 <= n; i += 8) {
        uint64_t w;
        memcpy(&w, p + i, 8);
        h = mix(h, w);
    }
    uint64_t tail = 0;
    for (size_t k = 0; i + k < n; ++k) tail |= (uint64_t)p[i + k] << (8 * k);
    return mix(mix(h, tail), (uint64_t)n);
}

static uint64_t hash_int(uint64_t h, int64_t v) { return mix(h, (uint64_t)v); }

uint64_t wc_cloth_fingerprint(const wc_cloth* c) {
    const wc_model* m = &c->model;
    uint64_t h = 0x5745465453u;
    h = hash_int(h, m->n_particles);
    h = hash_int(h, m->n_host_verts);
    h = hash_bytes(h, m->host_to_particle, (size_t)m->n_host_verts * sizeof(int));
    h = hash_bytes(h, m->rest_pos, 3 * (size_t)m->n_particles * sizeof(double));
    h = hash_bytes(h, m->mass, (size_t)m->n_particles * sizeof(double));
    h = hash_int(h, m->n_tris);
    h = hash_bytes(h, m->tris, 3 * (size_t)m->n_tris * sizeof(int));
    h = hash_int(h, m->n_springs);
    for (int s = 0; s < m->n_springs; ++s) {
        const wc_spring* sp = &m->springs[s];
        h = hash_int(h, sp->a);
        h = hash_int(h, sp->b);
        h = hash_int(h, sp->type);
        h = hash_bytes(h, &sp->rest, sizeof sp->rest);
        h = hash_bytes(h, &sp->w, sizeof sp->w);
    }
    h = hash_bytes(h, &m->material.density, sizeof(double));
    h = hash_bytes(h, m->material.k, sizeof m->material.k);
    h = hash_bytes(h, m->material.d, sizeof m->material.d);
    h = hash_bytes(h, &m->material.uniform_mass, sizeof(double));
    h = hash_bytes(h, &m->seam_close_time, sizeof(double));
    h = hash_int(h, c->n_attachments);
    h = hash_int(h, c->n_pins);
    for (int k = 0; k < c->n_pins; ++k) {
        h = hash_int(h, c->pin_particle[k]);
        h = hash_int(h, c->pin_attachment[k]);
    }
    h = hash_int(h, c->n_colliders);
    for (int k = 0; k < c->n_colliders; ++k) {
        const wc_cloth_collider* q = &c->colliders[k];
        h = hash_int(h, q->type);
        h = hash_bytes(h, &q->radius, sizeof(double));
        h = hash_bytes(h, &q->half_height, sizeof(double));
        h = hash_bytes(h, &q->thickness, sizeof(double));
        h = hash_bytes(h, &q->friction, sizeof(double));
    }
    h = hash_int(h, c->n_mesh);
    for (int k = 0; k < c->n_mesh; ++k) {
        const wc_mesh_collider* q = c->mesh[k];
        h = hash_int(h, q->n_verts);
        h = hash_int(h, q->n_tris);
        h = hash_bytes(h, q->tris, 3 * (size_t)q->n_tris * sizeof(int));
        h = hash_bytes(h, q->rest, 3 * (size_t)q->n_verts * sizeof(double));
        h = hash_bytes(h, &q->thickness, sizeof(double));
        h = hash_bytes(h, &q->friction, sizeof(double));
    }
    return h;
}

/* ---- the walk, shared by size, write and read ------------------------------------------------ */

static void walk_xforms(wc_serial* k, wc_xform* x, int n) {
    for (int i = 0; i < n; ++i) {
        wc_serial_bytes(k, x[i].R, sizeof x[i].R);
        wc_serial_bytes(k, x[i].t, sizeof x[i].t);
    }
}

/* Every mutable field of c in the format's order; reading writes into c (the caller checked). */
static void walk(wc_cloth* c, wc_serial* k) {
    wc_state_serial(c->state, k);
    walk_xforms(k, &c->object, 1);
    wc_serial_bytes(k, c->object_velocity, sizeof c->object_velocity);
    wc_serial_i32(k, &c->no_history);
    walk_xforms(k, c->attachment_xf, c->n_attachments);
    walk_xforms(k, c->collider_xf, c->n_colliders);
    wc_state_serial_history(c->state, k);
    for (int i = 0; i < c->n_mesh; ++i) {
        wc_mesh_collider_serial(c->mesh[i], k);
        walk_xforms(k, &c->mesh_xf[i], 1);
        wc_serial_i32(k, &c->mesh_pending[i]);
        c->mesh_pending[i] = c->mesh_pending[i] != 0;
    }
}

size_t wc_cloth_snapshot_measure(wc_cloth* c) {
    /* as it will be once the state holds the cloth's pins (a new binding measures before it sets
       them); counting reads the count only */
    wc_state* s = c->state;
    int held = s->n_pins;
    s->n_pins = c->n_pins;
    wc_serial k = wc_serial_counter(SNAP_HEADER);
    walk(c, &k);
    s->n_pins = held;
    return k.off;
}

void wc_cloth_backup(wc_cloth* c) {
    wc_serial k = wc_serial_writer(c->backup, 0);
    k.skip_mirror = c->backend->mirror;
    walk(c, &k);
    c->backend->backup(c);
}

void wc_cloth_rollback(wc_cloth* c) {
    c->backend->restore_backup(c);
    wc_serial k = wc_serial_reader(c->backup, 0);
    k.skip_mirror = c->backend->mirror;
    walk(c, &k);
}

/* ---- snapshots ------------------------------------------------------------------------------- */

static uint64_t checksum(const unsigned char* buf, size_t size) {
    unsigned char head[SNAP_HEADER];
    memcpy(head, buf, SNAP_HEADER);
    memset(head + 32, 0, 8);
    uint64_t h = hash_bytes(0x636865636bu, head, SNAP_HEADER);
    return hash_bytes(h, buf + SNAP_HEADER, size - SNAP_HEADER);
}

wc_status wc_cloth_save(wc_cloth* c, const wc_snapshot_stamp* stamp, void* buf_, wc_diag* d) {
    if (!buf_) return wc_fail(d, WC_ERROR_INVALID_ARGUMENT, "buf is NULL");
    /* a device's particles are read back first (exact: floats widen to doubles) */
    wc_status st = wc_cloth_download(c, d);
    if (st == WC_OK) st = wc_cloth_mesh_pull(c, d);   /* and the bodies a device moves */
    if (st != WC_OK) return st;
    unsigned char* buf = buf_;
    uint64_t size = c->snapshot_size, hash = c->model_hash, sum = 0;
    memcpy(buf, SNAP_MAGIC, 8);
    memcpy(buf + 8, &stamp->abi, 4);
    memcpy(buf + 12, &stamp->version, 4);
    memcpy(buf + 16, &size, 8);
    memcpy(buf + 24, &hash, 8);
    memcpy(buf + 32, &sum, 8);
    wc_serial k = wc_serial_writer(buf, SNAP_HEADER);
    walk(c, &k);
    sum = checksum(buf, c->snapshot_size);
    memcpy(buf + 32, &sum, 8);
    return WC_OK;
}

/* Content checks after the checksum matched (a buffer built to pass it must still not make the
 * cloth index out of bounds or hold non-finite numbers): pins, contact indices, finiteness. */
static int plausible(const wc_cloth* c, const unsigned char* buf, size_t size) {
    size_t off = SNAP_HEADER + 3 * 8;
    int n = c->model.n_particles;
    for (size_t i = 0; i < 3 * 3 * (size_t)n; ++i) {
        double v;
        memcpy(&v, buf + off + 8 * i, 8);
        if (!isfinite(v)) return 0;
    }
    off += 9 * (size_t)n * 8;
    int32_t np;
    memcpy(&np, buf + off, 4);
    off += 4;
    if (np != c->n_pins) return 0;
    for (int i = 0; i < c->n_pins; ++i) {
        int32_t p;
        memcpy(&p, buf + off, 4);
        if (p != c->pin_particle[i]) return 0;
        off += 4 + 6 * 8;
    }
    off += 3 * (size_t)c->n_pins * 8;
    for (int i = 0; i < c->n_colliders; ++i) {
        int32_t t;
        memcpy(&t, buf + off, 4);
        if (t != c->colliders[i].type) return 0;
        off += 4 + 19 * 8;   /* type, normal, offset, center, a, b, radius, thickness, friction, velocity */
    }
    for (size_t i = 0; i < 2 * (size_t)n; ++i) {
        int32_t q;
        memcpy(&q, buf + off + 4 * i, 4);
        if (q < -1 || q >= c->n_colliders + c->n_mesh) return 0; /* the meshes come first (core/state.h) */
    }
    /* the mesh colliders' positions, at the end of the buffer */
    size_t tail = 0;
    for (int k = 0; k < c->n_mesh; ++k) tail += 2 * 3 * (size_t)c->mesh[k]->n_verts * 8 + 12 * 8 + 4;
    if (tail > size) return 0;
    off = size - tail;
    for (int k = 0; k < c->n_mesh; ++k) {
        for (size_t i = 0; i < 2 * 3 * (size_t)c->mesh[k]->n_verts; ++i) {
            double v;
            memcpy(&v, buf + off + 8 * i, 8);
            if (!isfinite(v) || fabs(v) > 1e30) return 0;
        }
        off += 2 * 3 * (size_t)c->mesh[k]->n_verts * 8 + 12 * 8 + 4;
    }
    return 1;
}

wc_status wc_cloth_restore(wc_cloth* c, const wc_snapshot_stamp* stamp, const void* buf_, size_t size, wc_diag* d) {
    const unsigned char* buf = buf_;
    if (!buf) return wc_fail(d, WC_ERROR_INVALID_ARGUMENT, "buf is NULL");
    if (size < SNAP_HEADER)
        return wc_fail(d, WC_ERROR_INVALID_ARGUMENT, "size %zu is too small for a snapshot (truncated)", size);
    if (memcmp(buf, SNAP_MAGIC, 8) != 0)
        return wc_fail(d, WC_ERROR_INVALID_ARGUMENT, "buf is not a Weft snapshot (bad magic)");
    uint32_t abi, version;
    uint64_t total, hash, sum;
    memcpy(&abi, buf + 8, 4);
    memcpy(&version, buf + 12, 4);
    memcpy(&total, buf + 16, 8);
    memcpy(&hash, buf + 24, 8);
    memcpy(&sum, buf + 32, 8);
    if (abi != stamp->abi || version != stamp->version)
        return wc_fail(d, WC_ERROR_SNAPSHOT_MISMATCH,
                       "the snapshot was written by another library version (format %s, ABI %u, version 0x%06x; this is "
                       "ABI %u, 0x%06x)",
                       SNAP_MAGIC, abi, version, stamp->abi, stamp->version);
    if (total < SNAP_HEADER || size < total)
        return wc_fail(d, WC_ERROR_INVALID_ARGUMENT, "size %zu is below the snapshot's %llu bytes (truncated)", size,
                       (unsigned long long)total);
    if (checksum(buf, (size_t)total) != sum)
        return wc_fail(d, WC_ERROR_INVALID_ARGUMENT, "the snapshot is damaged (checksum mismatch)");
    if (hash != c->model_hash || total != c->snapshot_size)
        return wc_fail(d, WC_ERROR_SNAPSHOT_MISMATCH,
                       "the snapshot belongs to another model (mesh, welding, material, attachments or colliders)");
    if (!plausible(c, buf, (size_t)total))
        return wc_fail(d, WC_ERROR_INVALID_ARGUMENT, "the snapshot is damaged (inconsistent content)");
    /* the bodies a device moves go back to the host, whose copy the snapshot then replaces */
    wc_status pulled = wc_cloth_mesh_pull(c, d);
    if (pulled != WC_OK) return pulled;
    wc_serial k = wc_serial_reader(buf, SNAP_HEADER);
    walk(c, &k);
    /* a device gets the restored particles (doubles written from a device round to the same
     * floats) */
    return wc_cloth_upload(c, d);
}
