/* The cases of `weft bench torture` (see cmd_bench_torture.h). A case is a host: it builds host
 * arrays and defs from its own random numbers and calls the public API (weft.h) only, through
 * the checking calls of cmd_bench_torture_check.c (tc_create, tc_step, tc_set_attachments). */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cmd_bench_torture_case.h"

static const char* const kind_names[TK_COUNT] = {"random_mesh", "teleport", "spin", "nan_inject",
                                                 "zero_area", "one_particle", "extreme"};
static const char* const outcome_names[TO_COUNT] = {"ok", "rejected", "step_failed", "nonfinite", "state_changed",
                                                    "empty_message", "accepted_nonfinite", "crash", "hang"};

const char* torture_kind_name(int kind) { return kind >= 0 && kind < TK_COUNT ? kind_names[kind] : "?"; }
const char* torture_outcome_name(int o) { return o >= 0 && o < TO_COUNT ? outcome_names[o] : "?"; }
int torture_kind_from_name(const char* name) {
    for (int k = 0; k < TK_COUNT; ++k)
        if (!strcmp(name, kind_names[k])) return k;
    return -1;
}

/* ---------- random numbers (splitmix64) ---------- */

static uint64_t rng_next(rng* r) {
    uint64_t z = (r->s += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
}
static double rng_u(rng* r) { return (double)(rng_next(r) >> 11) * 0x1.0p-53; }            /* [0, 1) */
static double rng_range(rng* r, double lo, double hi) { return lo + (hi - lo) * rng_u(r); }
static double rng_log(rng* r, double lo, double hi) { return exp(rng_range(r, log(lo), log(hi))); }
static int rng_int(rng* r, int lo, int hi) { return lo + (int)(rng_next(r) % (uint64_t)(hi - lo + 1)); } /* [lo, hi] */
static int rng_chance(rng* r, double p) { return rng_u(r) < p; }

/* ---------- rigid transforms ---------- */

static void xf_identity(xf* x) {
    memset(x, 0, sizeof *x);
    x->R[0] = x->R[4] = x->R[8] = 1.0;
}
static void xf_to16(const xf* x, float* m) {
    for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 3; ++c) m[4 * c + r] = (float)x->R[3 * r + c];
        m[12 + r] = (float)x->t[r];
        m[4 * r + 3] = 0.0f;
    }
    m[15] = 1.0f;
}
static void xf_mul(xf* out, const xf* a, const xf* b) { /* out = a b */
    xf o;
    for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 3; ++c)
            o.R[3 * r + c] = a->R[3 * r] * b->R[c] + a->R[3 * r + 1] * b->R[3 + c] + a->R[3 * r + 2] * b->R[6 + c];
        o.t[r] = a->R[3 * r] * b->t[0] + a->R[3 * r + 1] * b->t[1] + a->R[3 * r + 2] * b->t[2] + a->t[r];
    }
    *out = o;
}
/* rotation by angle about a unit axis (Rodrigues), no translation */
static void xf_rotation(xf* x, const double* a, double angle) {
    const double c = cos(angle), s = sin(angle), k = 1.0 - c;
    xf_identity(x);
    x->R[0] = c + k * a[0] * a[0], x->R[1] = k * a[0] * a[1] - s * a[2], x->R[2] = k * a[0] * a[2] + s * a[1];
    x->R[3] = k * a[1] * a[0] + s * a[2], x->R[4] = c + k * a[1] * a[1], x->R[5] = k * a[1] * a[2] - s * a[0];
    x->R[6] = k * a[2] * a[0] - s * a[1], x->R[7] = k * a[2] * a[1] + s * a[0], x->R[8] = c + k * a[2] * a[2];
}
static void rng_axis(rng* r, double* a) {
    const double z = rng_range(r, -1, 1), phi = rng_range(r, 0, 6.283185307179586), s = sqrt(1 - z * z);
    a[0] = s * cos(phi), a[1] = s * sin(phi), a[2] = z;
}
/* a random rotation (angle up to max_angle) and translation (each component up to +-tmax) */
static void xf_random(rng* r, xf* x, double max_angle, double tmax) {
    double a[3];
    rng_axis(r, a);
    xf_rotation(x, a, rng_range(r, 0, max_angle));
    for (int k = 0; k < 3; ++k) x->t[k] = rng_range(r, -tmax, tmax);
}
/* x <- small random motion x */
static void xf_nudge(rng* r, xf* x, double angle, double dist) {
    xf d;
    xf_random(r, &d, angle, dist);
    xf_mul(x, &d, x);
}

/* ---------- host inputs ---------- */

typedef struct mesh {
    float* pos;
    int* fs;
    int* idx;
    int nv, nf, ni, cap_v, cap_f;
} mesh;

static int mesh_init(tc* t, mesh* m, int cap_v, int cap_f) {
    memset(m, 0, sizeof *m);
    m->pos = tc_alloc(t, 3 * (size_t)cap_v * sizeof(float));
    m->fs = tc_alloc(t, (size_t)cap_f * sizeof(int));
    m->idx = tc_alloc(t, 6 * (size_t)cap_f * sizeof(int));
    m->cap_v = cap_v, m->cap_f = cap_f;
    return m->pos && m->fs && m->idx ? 0 : -1;
}
static int mesh_vert(mesh* m, double x, double y, double z) {
    if (m->nv == m->cap_v) return m->nv - 1;
    m->pos[3 * m->nv] = (float)x, m->pos[3 * m->nv + 1] = (float)y, m->pos[3 * m->nv + 2] = (float)z;
    return m->nv++;
}
static void mesh_face(mesh* m, int n, const int* v) {
    if (m->nf == m->cap_f || n > 6) return;
    m->fs[m->nf++] = n;
    for (int k = 0; k < n; ++k) m->idx[m->ni++] = v[k];
}
static void mesh_tri(mesh* m, int a, int b, int c) { mesh_face(m, 3, (const int[]){a, b, c}); }

/* An nx x ny sheet of side w in the xz plane, jittered; quads or triangles (either diagonal). */
static void mesh_grid(rng* r, mesh* m, int nx, int ny, double w, double jitter) {
    const int base = m->nv;
    for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i)
            mesh_vert(m, w * (i / (nx - 1.0) - 0.5) + rng_range(r, -jitter, jitter), rng_range(r, -jitter, jitter),
                      w * (j / (ny - 1.0) - 0.5) + rng_range(r, -jitter, jitter));
    const int quads = rng_chance(r, 0.3);
    for (int j = 0; j + 1 < ny; ++j)
        for (int i = 0; i + 1 < nx; ++i) {
            int a = base + i + nx * j, b = a + 1, c = a + nx + 1, d = a + nx;
            if (quads) mesh_face(m, 4, (const int[]){a, b, c, d});
            else if (rng_chance(r, 0.5)) mesh_tri(m, a, b, c), mesh_tri(m, a, c, d);
            else mesh_tri(m, a, b, d), mesh_tri(m, b, c, d);
        }
}

/* Triangles of random vertices in a box. */
static void mesh_soup(rng* r, mesh* m, int nv, int nf) {
    for (int i = 0; i < nv; ++i) mesh_vert(m, rng_range(r, -1, 1), rng_range(r, -1, 1), rng_range(r, -1, 1));
    for (int f = 0; f < nf; ++f) mesh_tri(m, rng_int(r, 0, nv - 1), rng_int(r, 0, nv - 1), rng_int(r, 0, nv - 1));
}

/* One awkward addition: repeated indices, collinear or coincident corners, a sliver (aspect up
 * to 1e6), a duplicate vertex, an isolated vertex, an ignored 1- or 2-corner face, a polygon. */
static void mesh_awkward(rng* r, mesh* m) {
    const int n = m->nv;
    if (n < 1) return;
    const int a = rng_int(r, 0, n - 1), b = rng_int(r, 0, n - 1), c = rng_int(r, 0, n - 1);
    const float* pa = m->pos + 3 * a;
    const float* pb = m->pos + 3 * b;
    switch (rng_int(r, 0, 7)) {
    case 0: mesh_tri(m, a, a, rng_chance(r, 0.5) ? b : a); break;
    case 1: {
        double d[3] = {rng_range(r, -1, 1), rng_range(r, -1, 1), rng_range(r, -1, 1)};
        int v0 = mesh_vert(m, pa[0], pa[1], pa[2]);
        int v1 = mesh_vert(m, pa[0] + d[0], pa[1] + d[1], pa[2] + d[2]);
        int v2 = mesh_vert(m, pa[0] + 2.5 * d[0], pa[1] + 2.5 * d[1], pa[2] + 2.5 * d[2]);
        mesh_tri(m, v0, v1, v2);
        break;
    }
    case 2: {
        int v0 = mesh_vert(m, pa[0], pa[1], pa[2]), v1 = mesh_vert(m, pa[0], pa[1], pa[2]);
        mesh_tri(m, v0, v1, rng_chance(r, 0.5) ? a : v1);
        break;
    }
    case 3: { /* a sliver on the edge a-b (or a new one) */
        const double aspect = pow(10.0, rng_range(r, 1, 6));
        double e[3] = {pb[0] - pa[0], pb[1] - pa[1], pb[2] - pa[2]};
        double len = sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2]);
        if (len == 0) e[0] = len = 1.0;
        int v = mesh_vert(m, 0.5 * (pa[0] + pb[0]), 0.5 * (pa[1] + pb[1]) + len / aspect, 0.5 * (pa[2] + pb[2]));
        mesh_tri(m, a, b, v);
        break;
    }
    case 4: mesh_tri(m, mesh_vert(m, pa[0], pa[1], pa[2]), b, c); break;
    case 5: mesh_vert(m, rng_range(r, -2, 2), rng_range(r, -2, 2), rng_range(r, -2, 2)); break;
    case 6: mesh_face(m, rng_int(r, 1, 2), (const int[]){a, b}); break;
    default: {
        int v[6], k = rng_int(r, 4, 6);
        for (int i = 0; i < k; ++i) v[i] = rng_int(r, 0, n - 1);
        mesh_face(m, k, v);
    }
    }
}

static void mesh_to_def(const mesh* m, weft_cloth_def* def) {
    def->mesh.positions = m->pos;
    def->mesh.n_vertices = m->nv;
    def->mesh.face_sizes = m->fs;
    def->mesh.n_faces = m->nf;
    def->mesh.indices = m->idx;
}

/* Valid material and solver settings, often at the edges of their ranges. */
static void random_settings(rng* r, weft_cloth_def* d) {
    d->material.density = rng_chance(r, 0.1) ? 1e-6 : rng_log(r, 1e-3, 10);
    for (int k = 0; k < 3; ++k) {
        d->material.stiffness[k] = rng_chance(r, 0.1) ? 0.0 : rng_log(r, 1e-2, 1e6);
        d->material.damping[k] = rng_chance(r, 0.2) ? 0.0 : rng_log(r, 1e-4, 1e2);
    }
    d->solver = (weft_solver)rng_int(r, 0, 3);
    d->tolerance = rng_chance(r, 0.1) ? 0.0 : rng_chance(r, 0.1) ? 0.999 : rng_log(r, 1e-8, 0.5);
    d->max_iterations = rng_chance(r, 0.1) ? 1 : rng_int(r, 1, 400);
    d->substeps = rng_chance(r, 0.8) ? 1 : rng_int(r, 1, 8);
    d->max_frame_time = rng_chance(r, 0.7) ? 0.25 : rng_log(r, 1e-3, 1.0);
    d->strain_limit = rng_chance(r, 0.7) ? 0.0 : rng_log(r, 1e-3, 1.0);
    d->linear_inertia = rng_chance(r, 0.5) ? 1.0 : rng_chance(r, 0.3) ? 0.0 : rng_u(r);
    d->angular_inertia = rng_chance(r, 0.5) ? 1.0 : rng_chance(r, 0.3) ? 0.0 : rng_u(r);
    static const double weld[5] = {0.0, 1e-6, 1e-3, 0.1, 1.0};
    d->weld_tolerance = weld[rng_chance(r, 0.5) ? 1 : rng_int(r, 0, 4)];
    d->unit_scale = rng_chance(r, 0.8) ? 1.0 : rng_log(r, 1e-2, 1e2);
    for (int k = 0; k < 3; ++k) {
        d->gravity[k] = rng_chance(r, 0.7) ? (k == 1 ? -9.81 : 0.0) : rng_range(r, -30, 30);
        d->wind[k] = rng_chance(r, 0.7) ? 0.0 : rng_range(r, -20, 20);
    }
    d->air_drag_normal = rng_chance(r, 0.2) ? 0.0 : rng_log(r, 1e-3, 10);
    d->air_drag_tangent = rng_chance(r, 0.2) ? 0.0 : rng_log(r, 1e-4, 1);
}

/* n attachments pinning random vertices of m (disjoint, except rarely), bound at the host's
 * transforms (the object's, or random ones). */
static void random_attachments(tc* t, const mesh* m, int n, weft_attachment_def* a) {
    rng* r = &t->r;
    unsigned char* used = tc_alloc(t, (size_t)m->nv + 1);
    const int overlap = rng_chance(r, 0.03);
    for (int i = 0; i < n; ++i) {
        a[i] = weft_default_attachment_def();
        int k = rng_int(r, 1, m->nv < 6 ? m->nv : 6);
        int* v = tc_alloc(t, (size_t)k * sizeof(int));
        int got = 0;
        for (int tries = 0; v && used && got < k && tries < 4 * k; ++tries) {
            int c = rng_int(r, 0, m->nv - 1);
            if (used[c] && !overlap) continue;
            used[c] = 1;
            v[got++] = c;
        }
        a[i].vertices = v;
        a[i].n_vertices = got;
        if (rng_chance(r, 0.5)) t->att[i] = t->obj;
        else xf_random(r, &t->att[i], 3.14, 1.0);
        xf_to16(&t->att[i], a[i].bind_transform);
        if (rng_chance(r, 0.3)) {
            double ax[3];
            rng_axis(r, ax);
            for (int c = 0; c < 3; ++c) a[i].free_axis[c] = (float)ax[c];
        }
    }
}

static void random_colliders(tc* t, int n, weft_collider_def* c) {
    rng* r = &t->r;
    for (int i = 0; i < n; ++i) {
        c[i] = weft_default_collider_def();
        c[i].type = (weft_collider_type)rng_int(r, 0, 2);
        c[i].radius = rng_log(r, 1e-3, 2.0);
        c[i].half_height = rng_chance(r, 0.2) ? 0.0 : rng_range(r, 0, 1);
        c[i].thickness = rng_chance(r, 0.2) ? 0.0 : rng_range(r, 0, 0.05);
        c[i].friction = rng_chance(r, 0.2) ? 0.0 : rng_range(r, 0, 2);
        xf_random(r, &t->col[i], 3.14, 1.0);
        xf_to16(&t->col[i], c[i].transform);
    }
}

static double random_dt(rng* r, const weft_cloth_def* d) {
    if (rng_chance(r, 0.15)) return d->max_frame_time;
    double hi = d->max_frame_time < 0.1 ? d->max_frame_time : 0.1;
    return rng_log(r, hi * 1e-3, hi);
}

/* Frames with the host's transforms moved by motion() (or nudged at random when NULL). */
typedef void (*motion_fn)(tc* t, int frame, weft_frame* fr);

static void nudge_motion(tc* t, int frame, weft_frame* fr) {
    rng* r = &t->r;
    (void)frame;
    if (rng_chance(r, 0.5)) xf_nudge(r, &t->obj, 0.2, 0.05);
    for (int i = 0; i < t->n_att; ++i)
        if (rng_chance(r, 0.7)) xf_nudge(r, &t->att[i], 0.2, 0.05);
    for (int i = 0; i < t->n_col; ++i)
        if (rng_chance(r, 0.7)) xf_nudge(r, &t->col[i], 0.2, 0.1);
    if (rng_chance(r, 0.2))
        for (int k = 0; k < 3; ++k) t->wind[k] = rng_range(r, -20, 20);
    if (rng_chance(r, 0.05)) fr->flags |= rng_chance(r, 0.5) ? WEFT_FRAME_TELEPORT : WEFT_FRAME_RESET;
}

static void run_frames(tc* t, const weft_cloth_def* d, int n, motion_fn motion, double fixed_dt) {
    for (int f = 0; f < n && !t->stop; ++f) {
        weft_frame fr = weft_default_frame();
        fr.dt = fixed_dt > 0 ? fixed_dt : random_dt(&t->r, d);
        motion(t, f, &fr);
        xf_to16(&t->obj, t->obj16);
        for (int i = 0; i < t->n_att; ++i) xf_to16(&t->att[i], t->att16 + 16 * i);
        for (int i = 0; i < t->n_col; ++i) xf_to16(&t->col[i], t->col16 + 16 * i);
        fr.object_transform = rng_chance(&t->r, 0.9) ? t->obj16 : NULL;
        fr.attachment_transforms = t->att16;
        fr.collider_transforms = t->col16;
        fr.wind = rng_chance(&t->r, 0.5) ? t->wind : NULL;
        char where[32];
        snprintf(where, sizeof where, "step %d", f);
        tc_step(t, &fr, where);
    }
}

/* The common start of a case: a mesh, settings, attachments and colliders in def. */
typedef struct scene {
    weft_cloth_def def;
    mesh m;
    weft_attachment_def att[TC_MAX_ATT];
    weft_collider_def col[TC_MAX_COL];
} scene;

static void scene_attach(tc* t, scene* s, int n_att, int n_col) {
    t->n_att = s->m.nv > 0 ? n_att : 0;
    t->n_col = n_col;
    random_attachments(t, &s->m, t->n_att, s->att);
    random_colliders(t, n_col, s->col);
    s->def.attachments = s->att;
    s->def.n_attachments = t->n_att;
    s->def.colliders = s->col;
    s->def.n_colliders = n_col;
}

/* A plain sheet (n x n, 1 m) at the object's transform, with settings near the defaults. */
static int scene_sheet(tc* t, scene* s, int n, int n_att, int n_col) {
    s->def = weft_default_cloth_def();
    if (mesh_init(t, &s->m, n * n + 8, 2 * n * n + 8) != 0) return -1;
    mesh_grid(&t->r, &s->m, n, n, 1.0, 0.0);
    mesh_to_def(&s->m, &s->def);
    xf_random(&t->r, &t->obj, 3.14, 2.0);
    xf_to16(&t->obj, s->def.transform);
    scene_attach(t, s, n_att, n_col);
    return 0;
}

/* ---------- the kinds ---------- */

static void kind_random_mesh(tc* t, scene* s) {
    rng* r = &t->r;
    const int g = t->o->max_grid;
    s->def = weft_default_cloth_def();
    if (mesh_init(t, &s->m, g * g + 64, 2 * g * g + 64) != 0) return;
    if (rng_chance(r, 0.3)) mesh_soup(r, &s->m, rng_int(r, 3, 3 * g), rng_int(r, 1, 3 * g));
    else mesh_grid(r, &s->m, rng_int(r, 2, g), rng_int(r, 2, g), rng_log(r, 0.05, 3), rng_chance(r, 0.5) ? 0 : 0.02);
    for (int k = rng_int(r, 0, 12); k > 0; --k) mesh_awkward(r, &s->m);
    if (s->m.ni > 0 && rng_chance(r, 0.03)) { /* an index outside the mesh */
        static const int bad[3] = {-1, 0, 1 << 30};
        int v = bad[rng_int(r, 0, 2)];
        s->m.idx[rng_int(r, 0, s->m.ni - 1)] = v ? v : s->m.nv;
    }
    mesh_to_def(&s->m, &s->def);
    random_settings(r, &s->def);
    xf_random(r, &t->obj, 3.14, 2.0);
    xf_to16(&t->obj, s->def.transform);
    scene_attach(t, s, rng_int(r, 0, 3), rng_int(r, 0, 3));
    tc_create(t, &s->def);
    const int frames = rng_int(r, 1, t->o->max_frames);
    run_frames(t, &s->def, frames / 2 + 1, nudge_motion, 0);
    if (!t->stop && rng_chance(r, 0.3)) { /* new attachments mid-run */
        weft_attachment_def a[TC_MAX_ATT];
        int n = rng_int(r, 0, 3);
        random_attachments(t, &s->m, n, a);
        tc_set_attachments(t, a, n, "set_attachments");
    }
    run_frames(t, &s->def, frames - frames / 2, nudge_motion, 0);
}

/* teleport: the object and its attachments jump 1 km (with or without WEFT_FRAME_TELEPORT, or
 * with RESET); sometimes only the attachments, or a collider, jump. */
static void teleport_motion(tc* t, int frame, weft_frame* fr) {
    rng* r = &t->r;
    if (frame == 0 || !rng_chance(r, 0.4)) {
        nudge_motion(t, frame, fr);
        fr->flags = 0;
        return;
    }
    double dir[3];
    rng_axis(r, dir);
    const int what = rng_int(r, 0, 3); /* 0, 1: object and attachments; 2: attachments; 3: colliders */
    xf jump;
    xf_identity(&jump);
    for (int k = 0; k < 3; ++k) jump.t[k] = 1000.0 * dir[k];
    if (rng_chance(r, 0.3)) {
        xf_rotation(&jump, dir, rng_range(r, -3.14, 3.14));
        for (int k = 0; k < 3; ++k) jump.t[k] = 1000.0 * dir[k];
    }
    if (what <= 1) xf_mul(&t->obj, &jump, &t->obj);
    if (what <= 2)
        for (int i = 0; i < t->n_att; ++i) xf_mul(&t->att[i], &jump, &t->att[i]);
    if (what == 3)
        for (int i = 0; i < t->n_col; ++i) xf_mul(&t->col[i], &jump, &t->col[i]);
    const int f = rng_int(r, 0, 3);
    fr->flags = f == 0 ? WEFT_FRAME_TELEPORT : f == 1 ? WEFT_FRAME_RESET : 0;
}

static void kind_teleport(tc* t, scene* s) {
    rng* r = &t->r;
    if (scene_sheet(t, s, rng_int(r, 2, t->o->max_grid), rng_int(r, 0, 2), rng_int(r, 0, 2)) != 0) return;
    s->def.linear_inertia = rng_chance(r, 0.5) ? 1.0 : rng_u(r);
    s->def.angular_inertia = rng_chance(r, 0.5) ? 1.0 : rng_u(r);
    s->def.solver = (weft_solver)rng_int(r, 0, 3);
    tc_create(t, &s->def);
    run_frames(t, &s->def, rng_int(r, 2, t->o->max_frames), teleport_motion, 0);
}

/* spin: 100 rad/s about a random axis, for the object, the attachments (about a pivot up to 1 m
 * away) or the colliders. */
typedef struct spin_info {
    double axis[3], pivot[3], rate, t;
    int what;
    xf obj0, att0[TC_MAX_ATT], col0[TC_MAX_COL];
} spin_info;

static void spin_motion(tc* t, int frame, weft_frame* fr) {
    spin_info* sp = t->motion_data;
    (void)frame;
    sp->t += fr->dt;
    xf rot, to, from;
    xf_rotation(&rot, sp->axis, sp->rate * sp->t);
    xf_identity(&to), xf_identity(&from);
    for (int k = 0; k < 3; ++k) to.t[k] = sp->pivot[k], from.t[k] = -sp->pivot[k];
    xf_mul(&rot, &rot, &from);
    xf_mul(&rot, &to, &rot); /* rotation about the pivot */
    if (sp->what == 0 || sp->what == 3) xf_mul(&t->obj, &rot, &sp->obj0);
    if (sp->what == 1 || sp->what == 3)
        for (int i = 0; i < t->n_att; ++i) xf_mul(&t->att[i], &rot, &sp->att0[i]);
    if (sp->what == 2 || sp->what == 3)
        for (int i = 0; i < t->n_col; ++i) xf_mul(&t->col[i], &rot, &sp->col0[i]);
}

static void kind_spin(tc* t, scene* s) {
    rng* r = &t->r;
    if (scene_sheet(t, s, rng_int(r, 2, t->o->max_grid), rng_int(r, 0, 2), rng_int(r, 0, 2)) != 0) return;
    s->def.linear_inertia = rng_chance(r, 0.5) ? 1.0 : rng_u(r);
    s->def.angular_inertia = rng_chance(r, 0.5) ? 1.0 : rng_u(r);
    s->def.solver = (weft_solver)rng_int(r, 0, 3);
    s->def.strain_limit = rng_chance(r, 0.3) ? 0.1 : 0.0;
    tc_create(t, &s->def);
    spin_info* sp = tc_alloc(t, sizeof *sp);
    if (!sp) return;
    t->motion_data = sp;
    rng_axis(r, sp->axis);
    for (int k = 0; k < 3; ++k) sp->pivot[k] = t->obj.t[k] + rng_range(r, -1, 1);
    sp->rate = rng_chance(r, 0.5) ? 100.0 : -100.0;
    sp->what = rng_int(r, 0, 3);
    sp->obj0 = t->obj;
    memcpy(sp->att0, t->att, sizeof t->att);
    memcpy(sp->col0, t->col, sizeof t->col);
    run_frames(t, &s->def, rng_int(r, 2, t->o->max_frames), spin_motion, rng_chance(r, 0.5) ? 1.0 / 60 : 1.0 / 240);
}

/* nan_inject: one host input is NaN, +Inf or -Inf. */
static float poison_f(rng* r) {
    const int k = rng_int(r, 0, 2);
    return k == 0 ? NAN : k == 1 ? INFINITY : -INFINITY;
}

static void kind_nan_inject(tc* t, scene* s) {
    rng* r = &t->r;
    if (scene_sheet(t, s, rng_int(r, 2, 6), 1, 1) != 0) return;
    weft_cloth_def* d = &s->def;
    const float p = poison_f(r);
    const double pd = p;
    const int target = rng_int(r, 0, 31);
    if (target < 24) { /* at creation */
        double* dfield[] = {&d->unit_scale, &d->weld_tolerance, &d->material.density, &d->material.stiffness[0],
                            &d->material.stiffness[2], &d->material.damping[1], &d->gravity[1], &d->wind[2],
                            &d->air_drag_normal, &d->air_drag_tangent, &d->tolerance, &d->max_frame_time,
                            &d->strain_limit, &d->linear_inertia, &d->angular_inertia, &s->col[0].radius,
                            &s->col[0].half_height, &s->col[0].thickness, &s->col[0].friction};
        static const char* const names[] = {
            "unit_scale", "weld_tolerance", "material.density", "material.stiffness[0]", "material.stiffness[2]",
            "material.damping[1]", "gravity[1]", "wind[2]", "air_drag_normal", "air_drag_tangent", "tolerance",
            "max_frame_time", "strain_limit", "linear_inertia", "angular_inertia", "colliders[0].radius",
            "colliders[0].half_height", "colliders[0].thickness", "colliders[0].friction", "mesh.positions",
            "transform", "attachments[0].bind_transform", "attachments[0].free_axis", "colliders[0].transform"};
        const int nd = (int)(sizeof dfield / sizeof dfield[0]);
        if (target < nd) *dfield[target] = pd;
        else if (target == nd) s->m.pos[rng_int(r, 0, 3 * s->m.nv - 1)] = p;
        else if (target == nd + 1) d->transform[rng_int(r, 0, 15)] = p;
        else if (target == nd + 2) s->att[0].bind_transform[rng_int(r, 0, 15)] = p;
        else if (target == nd + 3) s->att[0].free_axis[rng_int(r, 0, 2)] = p;
        else s->col[0].transform[rng_int(r, 0, 15)] = p;
        char where[64];
        snprintf(where, sizeof where, "create (def %s %g)", names[target], pd);
        t->poisoned = 1;
        tc_create_at(t, d, where); /* must be refused */
        return;
    }
    tc_create(t, d);
    run_frames(t, d, rng_int(r, 0, 2), nudge_motion, 0);
    if (t->stop) return;
    const int ok_before = t->res->outcome == TO_OK;
    weft_frame fr = weft_default_frame();
    xf_to16(&t->obj, t->obj16);
    for (int i = 0; i < t->n_att; ++i) xf_to16(&t->att[i], t->att16 + 16 * i);
    for (int i = 0; i < t->n_col; ++i) xf_to16(&t->col[i], t->col16 + 16 * i);
    fr.object_transform = t->obj16;
    fr.attachment_transforms = t->att16;
    fr.collider_transforms = t->col16;
    fr.wind = t->wind;
    static const char* const mid[] = {"fr->dt", "fr->object_transform", "fr->attachment_transforms",
                                       "fr->collider_transforms", "fr->wind", "bind_transform", "free_axis", "free_axis"};
    char where[64];
    snprintf(where, sizeof where, "%s (%s %g)", target < 29 ? "step" : "set_attachments", mid[target - 24], pd);
    t->poisoned = 1;
    switch (target) {
    case 24: fr.dt = pd; break;
    case 25: t->obj16[rng_int(r, 0, 15)] = p; break;
    case 26: t->att16[rng_int(r, 0, 15)] = p; break;
    case 27: t->col16[rng_int(r, 0, 15)] = p; break;
    case 28: t->wind[rng_int(r, 0, 2)] = pd; break;
    default: {
        weft_attachment_def a = s->att[0];
        if (target == 29) a.bind_transform[rng_int(r, 0, 15)] = p;
        else a.free_axis[rng_int(r, 0, 2)] = p;
        tc_set_attachments(t, &a, 1, where);
        break;
    }
    }
    if (target < 29) tc_step(t, &fr, where);
    if (ok_before && t->res->outcome == TO_OK) tc_mark(t, TO_ACCEPTED, WEFT_OK, where, "a NaN/Inf input was accepted");
    t->poisoned = 0;
    for (int k = 0; k < 3; ++k) t->wind[k] = 0.0;
    run_frames(t, d, 1, nudge_motion, 1.0 / 60); /* the cloth still works */
}

/* zero_area: every vertex at one point, or every vertex on one line. */
static void kind_zero_area(tc* t, scene* s) {
    rng* r = &t->r;
    s->def = weft_default_cloth_def();
    const int n = rng_int(r, 3, 16);
    if (mesh_init(t, &s->m, n, 3 * n) != 0) return;
    const int line = rng_chance(r, 0.5);
    double p[3], dir[3];
    for (int k = 0; k < 3; ++k) p[k] = rng_range(r, -1, 1);
    rng_axis(r, dir);
    for (int i = 0; i < n; ++i) {
        const double u = line ? rng_range(r, -1, 1) : 0.0;
        mesh_vert(&s->m, p[0] + u * dir[0], p[1] + u * dir[1], p[2] + u * dir[2]);
    }
    for (int f = rng_int(r, 1, 3 * n); f > 0; --f) mesh_tri(&s->m, rng_int(r, 0, n - 1), rng_int(r, 0, n - 1), rng_int(r, 0, n - 1));
    mesh_to_def(&s->m, &s->def);
    s->def.weld_tolerance = rng_chance(r, 0.5) ? 0.0 : 1e-6;
    xf_identity(&t->obj);
    scene_attach(t, s, rng_int(r, 0, 1), rng_int(r, 0, 1));
    tc_create(t, &s->def);
    run_frames(t, &s->def, rng_int(r, 1, t->o->max_frames), nudge_motion, 0);
}

/* one_particle: one vertex (a triangle of it, or only ignored 1- and 2-corner faces), or one
 * triangle whose three vertices coincide (welded or not). */
static void kind_one_particle(tc* t, scene* s) {
    rng* r = &t->r;
    s->def = weft_default_cloth_def();
    if (mesh_init(t, &s->m, 3, 4) != 0) return;
    const double y = rng_range(r, -1, 1);
    const int variant = rng_int(r, 0, 2);
    if (variant == 0) {
        mesh_vert(&s->m, 0, y, 0);
        mesh_tri(&s->m, 0, 0, 0);
    } else if (variant == 1) {
        mesh_vert(&s->m, 0, y, 0);
        mesh_face(&s->m, 1, (const int[]){0});
        mesh_face(&s->m, 2, (const int[]){0, 0});
    } else {
        for (int k = 0; k < 3; ++k) mesh_vert(&s->m, 0, y, 0);
        mesh_tri(&s->m, 0, 1, 2);
    }
    mesh_to_def(&s->m, &s->def);
    s->def.weld_tolerance = rng_chance(r, 0.5) ? 0.0 : 1e-6;
    s->def.solver = (weft_solver)rng_int(r, 0, 3);
    xf_identity(&t->obj);
    scene_attach(t, s, rng_int(r, 0, 1), rng_int(r, 0, 2));
    tc_create(t, &s->def);
    run_frames(t, &s->def, rng_int(r, 1, t->o->max_frames), nudge_motion, 0);
}

/* extreme: one or two settings at the far ends of their valid ranges. */
static void kind_extreme(tc* t, scene* s) {
    rng* r = &t->r;
    if (scene_sheet(t, s, rng_int(r, 2, t->o->max_grid), rng_int(r, 0, 2), rng_int(r, 0, 2)) != 0) return;
    weft_cloth_def* d = &s->def;
    double dt = 0.0;
    for (int n = rng_int(r, 1, 2); n > 0; --n) {
        const int big = rng_chance(r, 0.5);
        switch (rng_int(r, 0, 13)) {
        case 0: d->material.density = big ? 1e6 : 1e-9; break;
        case 1: for (int k = 0; k < 3; ++k) d->material.stiffness[k] = big ? 1e10 : 0.0; break;
        case 2: for (int k = 0; k < 3; ++k) d->material.damping[k] = big ? 1e8 : 0.0; break;
        case 3: d->max_frame_time = big ? 1000.0 : 1e-6, dt = d->max_frame_time; break;
        case 4: dt = d->max_frame_time; break;
        case 5: d->unit_scale = big ? 1e6 : 1e-6; break;
        case 6: for (int i = 0; i < s->m.nv; ++i) s->m.pos[3 * i] += big ? 1e6f : 1e4f; break;
        case 7: d->transform[12 + rng_int(r, 0, 2)] = big ? 1e6f : -1e6f; t->obj.t[0] = d->transform[12];
            t->obj.t[1] = d->transform[13], t->obj.t[2] = d->transform[14]; break;
        case 8: for (int k = 0; k < 3; ++k) d->gravity[k] = big ? 1e6 : 0.0; break;
        case 9: for (int k = 0; k < 3; ++k) d->wind[k] = big ? 1e5 : -1e5; d->air_drag_normal = big ? 1e6 : 0.5; break;
        case 10: d->tolerance = 0.0, d->max_iterations = big ? 5000 : 1; break;
        case 11: d->substeps = big ? 200 : 1, d->strain_limit = big ? 1e-9 : 0; break;
        case 12: for (int i = 0; i < t->n_col; ++i) {
                s->col[i].radius = big ? 1e6 : 1e-9;
                s->col[i].thickness = big ? 10.0 : 0.0;
                s->col[i].friction = big ? 1e6 : 0.0;
            } break;
        default: d->weld_tolerance = 1.0; break;
        }
    }
    d->solver = (weft_solver)rng_int(r, 0, 3);
    tc_create(t, d);
    run_frames(t, d, rng_int(r, 1, t->o->max_frames), nudge_motion, dt);
}

void torture_run_case(int kind, uint64_t seed, int index, const torture_opts* o, torture_result* out) {
    memset(out, 0, sizeof *out);
    tc* t = calloc(1, sizeof *t);
    scene* s = calloc(1, sizeof *s);
    if (!t || !s) {
        free(t), free(s);
        out->outcome = TO_REJECTED, out->status = WEFT_ERROR_OUT_OF_MEMORY;
        snprintf(out->detail, sizeof out->detail, "the case ran out of memory");
        return;
    }
    rng mix = {seed ^ (0x632be59bd9b4e019ULL * (uint64_t)(kind + 1))};
    for (int k = 0; k <= index % 7; ++k) rng_next(&mix);
    t->r.s = rng_next(&mix) ^ (0xd1b54a32d192ed03ULL * ((uint64_t)index + 1));
    t->o = o;
    t->res = out;
    xf_identity(&t->obj);
    weft_context_def cd = weft_default_context_def();
    cd.backend = (weft_backend)o->backend;
    cd.threads = o->threads;
    if (weft_context_create(WEFT_ABI, &cd, &t->ctx) != WEFT_OK) {
        out->outcome = TO_REJECTED, out->status = WEFT_ERROR_UNSUPPORTED;
        snprintf(out->detail, sizeof out->detail, "weft_context_create failed (backend %d)", o->backend);
    } else {
        static void (*const kinds[TK_COUNT])(tc*, scene*) = {kind_random_mesh, kind_teleport, kind_spin, kind_nan_inject,
                                                             kind_zero_area, kind_one_particle, kind_extreme};
        if (kind >= 0 && kind < TK_COUNT) kinds[kind](t, s);
        if (t->cloth.id) weft_cloth_destroy(t->ctx, t->cloth);
        weft_context_destroy(t->ctx);
    }
    for (int k = 0; k < t->n_allocs; ++k) free(t->allocs[k]);
    free(t->snap[0]), free(t->snap[1]);
    free(t), free(s);
}
