/* Snapshots: the cloth's whole mutable state in a flat byte buffer (native byte order; meant for
 * the same build on the same machine: host caches, timeline scrubbing).
 *
 * Layout (x starts at byte 64: tests read positions there): a 40-byte header (magic "WEFTSNP2", ABI, library version, total size, model
 * fingerprint, checksum of everything else) then, field by field (no struct padding):
 *   time, accumulator, frame                      wc_state clocks
 *   x, v, dv                                      (n x 3) each; dv is the next solve's initial guess
 *   pins (particle, target, free_axis), pin_from  the pins and their start-of-frame targets
 *   colliders (all wc_collider fields)            world geometry and velocity
 *   contacts (collider, normal, released, active) incl. the released flags
 *   wind                                          the air's wind (weft_frame.wind changes it)
 *   T0, V0, no_history                            the object's transform history (inertia)
 *   attachment and collider transforms            the last applied ones (NULL in a frame keeps them)
 *   Chebyshev rho cache (valid, rho)              wc_solver caches its spectral-radius estimate
 *                                                 until a rollback; a different value changes
 *                                                 every later Chebyshev solve
 *   asleep, rest timer                            the sleep state (core/state.h): restoring an
 *                                                 asleep snapshot puts the cloth to sleep with
 *                                                 the restored wind, an awake one wakes it
 *   BDF2 history (valid, h, x_prev, v_prev)       core/bdf2.h: what the next BDF2 substep reads
 *                                                 (x_prev, v_prev (n x 3) always present, read
 *                                                 only when valid); after the sleep state,
 *                                                 whose restore would invalidate it
 *   mesh colliders (from, to, transform, pending) per mesh collider: its world positions at the
 *                                                 start and end of the next frame (n_verts x 3
 *                                                 each), last rigid transform, and whether the
 *                                                 host set new vertices for the next frame; the
 *                                                 substep positions, normals and BVH boxes are
 *                                                 derived (recomputed at every substep and on
 *                                                 restore)
 * Format 2 (magic "WEFTSNP2", library 0.5.0) added the BDF2 history, format 3 ("WEFTSNP3",
 * library 0.6.0) the mesh colliders; older formats are refused as not Weft snapshots of this format.
 * Nothing else carries over between steps: x0/v0/dv0 and contacts_save are written at every
 * substep's start; the filter, forces, matrix, right-hand side and residual are rebuilt by every
 * substep; the solvers' vectors and preconditioner by every solve (PCG/Jacobi start from dv; the
 * direct solver refactorises); wc_par's partial sums are per-reduction scratch; seam_scale (the
 * host seam pairs' ramp, core/sew.h) is derived from time at every frame's start. Seams are
 * model: their springs (weights, ramp start) and seam_close_time are in the fingerprint.
 * Self-collision (core/self_collide.h) keeps nothing either: its start positions are copied at
 * every substep's start and its trees are refitted by every pass.
 *
 * The fingerprint hashes what must match for the state to mean the same thing: particles (host
 * map, rest positions, masses), triangles, springs, material, the pinned particles and their
 * attachments, the colliders' count, types and sizes, and the mesh colliders' topology, rest
 * shape, thickness and friction. */
#include <math.h>
#include <string.h>
#include "api_internal.h"

#define SNAP_MAGIC "WEFTSNP3"   /* format 3: with the mesh colliders' positions */
#define SNAP_HEADER 40
#define SNAP_VERSION ((uint32_t)(WEFT_VERSION_MAJOR << 16 | WEFT_VERSION_MINOR << 8 | WEFT_VERSION_PATCH))

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

uint64_t wa_model_hash(const wa_cloth* c) {
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
        h = hash_bytes(h, &sp->w, sizeof sp->w); /* seam springs (sew.h) are part of the model */
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
        const wa_collider* q = &c->colliders[k];
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

/* ---- the field list, shared by size, write and read ------------------------------------------ */

typedef struct cursor {
    unsigned char* w;       /* write here (NULL: count only) */
    const unsigned char* r; /* or read from here */
    size_t off;
    int small;              /* skip x, v, dv and the contact arrays (a GPU cloth's step backup) */
} cursor;

static void field(cursor* k, void* data, size_t n) {
    if (n == 0) return;
    if (k->w) memcpy(k->w + k->off, data, n);
    else if (k->r) memcpy(data, k->r + k->off, n);
    k->off += n;
}

static void field_xforms(cursor* k, wa_xform* x, int n) {
    for (int i = 0; i < n; ++i) {
        field(k, x[i].R, sizeof x[i].R);
        field(k, x[i].t, sizeof x[i].t);
    }
}

/* Walks every mutable field of c in order; reading writes into c (the caller has checked). */
static void walk(wa_cloth* c, cursor* k) {
    wc_state* s = c->state;
    int n = c->model.n_particles;
    size_t n3 = 3 * (size_t)n * sizeof(double);
    int64_t frame = s->frame;
    field(k, &s->time, sizeof s->time);
    field(k, &s->accumulator, sizeof s->accumulator);
    field(k, &frame, sizeof frame);
    s->frame = frame;
    if (!k->small) {
        field(k, s->x, n3);
        field(k, s->v, n3);
        field(k, s->dv, n3);
    }
    int32_t np = s->n_pins;
    field(k, &np, sizeof np);
    s->n_pins = np;   /* == c->n_pins: checked before a read */
    for (int i = 0; i < c->n_pins; ++i) {
        int32_t p = s->pins[i].particle;
        field(k, &p, sizeof p);
        s->pins[i].particle = p;
        field(k, s->pins[i].target, sizeof s->pins[i].target);
        field(k, s->pins[i].free_axis, sizeof s->pins[i].free_axis);
    }
    field(k, s->pin_from, 3 * (size_t)c->n_pins * sizeof(double));
    for (int i = 0; i < c->n_colliders; ++i) {
        wc_collider* q = &s->colliders[i];
        int32_t type = q->type;
        field(k, &type, sizeof type);
        q->type = type;
        field(k, q->normal, sizeof q->normal);
        field(k, &q->offset, sizeof q->offset);
        field(k, q->center, sizeof q->center);
        field(k, q->a, sizeof q->a);
        field(k, q->b, sizeof q->b);
        field(k, &q->radius, sizeof q->radius);
        field(k, &q->thickness, sizeof q->thickness);
        field(k, &q->friction, sizeof q->friction);
        field(k, q->velocity, sizeof q->velocity);
    }
    if (!k->small) {
        field(k, s->contacts.collider, 2 * (size_t)n * sizeof(int));
        field(k, s->contacts.normal, 6 * (size_t)n * sizeof(double));
        field(k, s->contacts.released, (size_t)n);
    }
    int32_t active = s->contacts.active;
    field(k, &active, sizeof active);
    s->contacts.active = active;
    field(k, s->def.air.wind, sizeof s->def.air.wind);
    field_xforms(k, &c->object, 1);
    field(k, c->object_velocity, sizeof c->object_velocity);
    int32_t nh = c->no_history;
    field(k, &nh, sizeof nh);
    c->no_history = nh;
    field_xforms(k, c->attachment_xf, c->n_attachments);
    field_xforms(k, c->collider_xf, c->n_colliders);
    double rho = 0.0;
    int32_t rho_valid = wc_solver_rho_cache(s->solver, &rho);
    field(k, &rho_valid, sizeof rho_valid);
    field(k, &rho, sizeof rho);
    if (k->r) wc_solver_set_rho_cache(s->solver, rho_valid, rho);
    int32_t asleep = s->asleep;
    double rest_time = s->rest_time;
    field(k, &asleep, sizeof asleep);
    field(k, &rest_time, sizeof rest_time);
    if (k->r) wc_state_set_sleep(s, asleep != 0, rest_time);   /* after the wind: it sleeps with it */
    int32_t hv = s->hist_valid;
    field(k, &hv, sizeof hv);
    field(k, &s->hist_h, sizeof s->hist_h);
    s->hist_valid = hv != 0;
    if (!k->small) {
        field(k, s->x_prev, n3);
        field(k, s->v_prev, n3);
    }
    for (int i = 0; i < c->n_mesh; ++i) {
        wc_mesh_collider* m = c->mesh[i];
        size_t nv3 = 3 * (size_t)m->n_verts * sizeof(double);
        field(k, m->from, nv3);
        field(k, m->to, nv3);
        field_xforms(k, &c->mesh_xf[i], 1);
        int32_t pending = c->mesh_pending[i];
        field(k, &pending, sizeof pending);
        c->mesh_pending[i] = pending != 0;
        if (k->r) wc_mesh_collider_substep(m, 0.0, 0.0, 0.0); /* derived: substep positions at from */
    }
}

size_t wa_snapshot_size(const wa_cloth* c) {
    cursor k = {NULL, NULL, SNAP_HEADER, 0};
    walk((wa_cloth*)c, &k);   /* counting only: nothing is written */
    return k.off;
}

static uint64_t checksum(const unsigned char* buf, size_t size) {
    unsigned char head[SNAP_HEADER];
    memcpy(head, buf, SNAP_HEADER);
    memset(head + 32, 0, 8);
    uint64_t h = hash_bytes(0x636865636bu, head, SNAP_HEADER);
    return hash_bytes(h, buf + SNAP_HEADER, size - SNAP_HEADER);
}

void wa_snapshot_write(const wa_cloth* c, unsigned char* buf, int with_checksum) {
    uint32_t abi = WEFT_ABI, version = SNAP_VERSION;
    uint64_t size = c->snapshot_size, hash = c->model_hash, sum = 0;
    memcpy(buf, SNAP_MAGIC, 8);
    memcpy(buf + 8, &abi, 4);
    memcpy(buf + 12, &version, 4);
    memcpy(buf + 16, &size, 8);
    memcpy(buf + 24, &hash, 8);
    memcpy(buf + 32, &sum, 8);
    cursor k = {buf, NULL, SNAP_HEADER, 0};
    walk((wa_cloth*)c, &k);
    if (with_checksum) {
        sum = checksum(buf, c->snapshot_size);
        memcpy(buf + 32, &sum, 8);
    }
}

void wa_snapshot_apply(wa_cloth* c, const unsigned char* buf) {
    cursor k = {NULL, buf, SNAP_HEADER, 0};
    walk(c, &k);
}

void wa_snapshot_write_small(const wa_cloth* c, unsigned char* buf) {
    cursor k = {buf, NULL, 0, 1};
    walk((wa_cloth*)c, &k);
}

void wa_snapshot_apply_small(wa_cloth* c, const unsigned char* buf) {
    cursor k = {NULL, buf, 0, 1};
    walk(c, &k);
}

weft_status weft_cloth_save(weft_context* ctx, weft_cloth cloth, void* buf, size_t size) {
    WA_CALL_GUARD(ctx);   /* threading contract: refused if another thread is inside (call_guard.h) */
    static const char fn[] = "weft_cloth_save";
    if (!ctx) return WEFT_ERROR_INVALID_ARGUMENT;
    wa_cloth* c = wa_lookup(ctx, cloth, fn);
    if (!c) return WEFT_ERROR_INVALID_HANDLE;
    if (!buf) return wa_fail(ctx, WEFT_ERROR_INVALID_ARGUMENT, "%s: buf is NULL", fn);
    if (size < c->snapshot_size)
        return wa_fail(ctx, WEFT_ERROR_OUT_OF_RANGE, "%s: size %zu is below the snapshot size %zu (weft_cloth_info)", fn,
                       size, c->snapshot_size);
    /* a GPU cloth's positions, velocities, warm start and contacts are read back first (exact:
     * floats widen to doubles) */
    if (c->gpu) {
        weft_status st = wa_gpu_download(ctx, c, fn);
        if (st != WEFT_OK) return st;
    }
    wa_snapshot_write(c, buf, 1);
    return wa_ok(ctx);
}

/* Content checks after the checksum matched (a buffer built to pass it must still not make the
 * cloth index out of bounds or hold non-finite numbers): pins, contact indices, finiteness. */
static int plausible(const wa_cloth* c, const unsigned char* buf, size_t size) {
    (void)size;
    /* parse into a scratch copy of the counts only: the arrays are checked in place */
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

weft_status weft_cloth_restore(weft_context* ctx, weft_cloth cloth, const void* buf_, size_t size) {
    WA_CALL_GUARD(ctx);   /* threading contract: refused if another thread is inside (call_guard.h) */
    static const char fn[] = "weft_cloth_restore";
    if (!ctx) return WEFT_ERROR_INVALID_ARGUMENT;
    wa_cloth* c = wa_lookup(ctx, cloth, fn);
    if (!c) return WEFT_ERROR_INVALID_HANDLE;
    const unsigned char* buf = buf_;
    if (!buf) return wa_fail(ctx, WEFT_ERROR_INVALID_ARGUMENT, "%s: buf is NULL", fn);
    if (size < SNAP_HEADER)
        return wa_fail(ctx, WEFT_ERROR_INVALID_ARGUMENT, "%s: size %zu is too small for a snapshot (truncated)", fn, size);
    if (memcmp(buf, SNAP_MAGIC, 8) != 0)
        return wa_fail(ctx, WEFT_ERROR_INVALID_ARGUMENT, "%s: buf is not a Weft snapshot (bad magic)", fn);
    uint32_t abi, version;
    uint64_t total, hash, sum;
    memcpy(&abi, buf + 8, 4);
    memcpy(&version, buf + 12, 4);
    memcpy(&total, buf + 16, 8);
    memcpy(&hash, buf + 24, 8);
    memcpy(&sum, buf + 32, 8);
    if (abi != WEFT_ABI || version != SNAP_VERSION)
        return wa_fail(ctx, WEFT_ERROR_SNAPSHOT_MISMATCH,
                       "%s: the snapshot was written by another library version (ABI %u, version 0x%06x; this is ABI %d, "
                       "0x%06x)",
                       fn, abi, version, WEFT_ABI, SNAP_VERSION);
    if (total < SNAP_HEADER || size < total)
        return wa_fail(ctx, WEFT_ERROR_INVALID_ARGUMENT, "%s: size %zu is below the snapshot's %llu bytes (truncated)", fn,
                       size, (unsigned long long)total);
    if (checksum(buf, (size_t)total) != sum)
        return wa_fail(ctx, WEFT_ERROR_INVALID_ARGUMENT, "%s: the snapshot is damaged (checksum mismatch)", fn);
    if (hash != c->model_hash || total != c->snapshot_size)
        return wa_fail(ctx, WEFT_ERROR_SNAPSHOT_MISMATCH,
                       "%s: the snapshot belongs to another model (mesh, welding, material, attachments or colliders)", fn);
    if (!plausible(c, buf, (size_t)total))
        return wa_fail(ctx, WEFT_ERROR_INVALID_ARGUMENT, "%s: the snapshot is damaged (inconsistent content)", fn);
    wa_snapshot_apply(c, buf);
    /* a GPU cloth: the restored arrays go to its textures (doubles written by a GPU cloth round
     * to the same floats) */
    if (c->gpu) {
        weft_status st = wa_gpu_upload(ctx, c, fn);
        if (st != WEFT_OK) return st;
    }
    return wa_ok(ctx);
}
