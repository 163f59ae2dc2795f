/* The GPU side of core/collide.c (see wg_contacts.h for the hooks and collide.h for the rules):
 * five per-particle passes (contact_begin, contact_friction, contact_recheck, contact_end,
 * contact_project) and one per block (contact_diag: the friction damping into the diagonal
 * blocks of A); and TR-BDF2's contact rule of core/bdf2.c (integ_contacts: the stages' landing;
 * contact_end's u_stage: the impulses held from stage 1 to stage 2).
 *
 * State, per particle, three arrays in rings of three textures each (RGBA32F, ids as floats):
 *   C0 = (collider 1, collider 2, released, stick)   (-1: no collider)
 *   C1 = (normal 1, in contact)                      (the count of w is wg_contacts_active)
 *   C2 = (normal 2, w: begin's second surface velocity along normal 2, then changed by the last
 *        recheck)
 * A pass writes into wg_ring_other(ring, 0), never the current one nor keep: save and restore
 * move indices only.
 *
 * Colliders: a 5 x (mesh colliders + max_colliders) RGBA32F texture, rewritten by every hook that
 * reads them: the meshes first (core/step.c's order, so the contacts' collider ids are core's),
 * then s->colliders. Rows: (type, radius, thickness, friction), (plane normal, offset), (center
 * or a, -), (b, push_speed), (velocity, -); a mesh's are wg_mesh_row's, its body in wg_mesh's
 * textures, moved to each substep by begin. begin also writes, per particle, the first contact's
 * surface velocity (which friction and recheck take relative velocities to: a mesh's is per
 * point) and the length of its correction (which project's push_speed cap subtracts); with
 * meshes, project starts the particles' paths (the continuous test, the search's reach) at
 * begin's x (x_sub). Everything is float: the results agree with core/collide.c to float
 * precision. One deliberate difference: SLOP (1e-9 m) is below float resolution at metre scale,
 * so the shaders widen it to SLOP + 1e-6 max(1, |p|inf) wherever collide.c uses it (begin's
 * contact tests, project's "on the shell": a particle just pushed out lies within a few ulps of
 * its shell, not within 1e-9). */
#include <string.h>

#include "gpu_error.h"
#include "wg_contacts.h"
#include "bdf2.h"
#include "wg_mesh.h"
#include "wg_pairs.h"

struct wg_contacts {
    wg_runner* run;
    wg_contact_cloth cl;        /* the cloth's textures */
    const wg_pairs* pairs;      /* the cloth's penalty pairs (their blocks in end's residual), or NULL */
    int max_colliders;          /* analytic ones */
    wg_mesh mesh;
    wg_tex cvel;                /* begin's o7 (n): first contact's surface velocity, correction length */
    wg_tex x_sub;               /* x after begin (n; read with meshes only) */
    double h;                   /* begin's substep */
    wg_ring c0, c1, c2;
    wg_tex cols;                /* 5 x (meshes + max_colliders) */
    float* col_buf;             /* 20 x (meshes + max_colliders) */
    wg_tex S0, S1, z, b;        /* scratch of the filter and b (n) */
    wg_tex ad0, ad1;            /* per particle: A_ii (lo, hi) */
    wg_tex A0, A1;              /* scratch of A (nb) */
    wg_chain chain;             /* sums over n */
    wg_tex bk[3];               /* the frame's back-up of c0, c1, c2 (wg_sim_backup) */
    wg_tex held[2];             /* TR-BDF2: stage 1's impulses, read by stage 2's end (n); ping-pong */
    int held_cur;               /* the one stage 1 wrote last */
};

/* Every texture of cs but the meshes' and the chain's into t (room for 25); their count. */
static int textures(wg_contacts* cs, wg_tex** t) {
    wg_ring* rings[3] = {&cs->c0, &cs->c1, &cs->c2};
    int n = 0;
    for (int r = 0; r < 3; ++r)
        for (int j = 0; j < 3; ++j) t[n++] = &rings[r]->t[j];
    for (int r = 0; r < 3; ++r) t[n++] = &cs->bk[r];
    wg_tex* pv[] = {&cs->S0, &cs->S1, &cs->z, &cs->b, &cs->ad0, &cs->ad1, &cs->A0, &cs->A1, &cs->cols,
                    &cs->cvel, &cs->x_sub, &cs->held[0], &cs->held[1]};
    for (size_t k = 0; k < sizeof pv / sizeof pv[0]; ++k) t[n++] = pv[k];
    return n;
}

size_t wg_contacts_bytes(const wg_contacts* cs) {
    if (!cs) return 0;
    wg_tex* t[25];
    int n = textures((wg_contacts*)cs, t);
    size_t bytes = wg_chain_bytes(&cs->chain) + wg_mesh_bytes(&cs->mesh);
    for (int k = 0; k < n; ++k) bytes += t[k]->id ? wg_tex_bytes(t[k]) : 0;
    return bytes;
}

static void release(wg_contacts* cs, int gl) {
    if (!cs) return;
    if (gl) {
        wg_tex* t[25];
        int n = textures(cs, t);
        for (int k = 0; k < n; ++k) wg_tex_destroy(t[k]);
        wg_chain_destroy(&cs->chain);
    }
    const wc_allocator* alloc = &cs->run->layout->alloc;
    wg_mesh_release(&cs->mesh, gl);
    wc_free(alloc, cs->col_buf);
    wc_free(alloc, cs);
}

void wg_contacts_destroy(wg_contacts* cs) { release(cs, 1); }
void wg_contacts_forget(wg_contacts* cs) { release(cs, 0); }

wc_status wg_contacts_create(wg_runner* run, const wg_contact_cloth* cloth, int max_colliders,
                             wc_mesh_collider* const* mesh, int n_mesh, wg_contacts** out, char* err, size_t err_len) {
    *out = NULL;
    int mc = max_colliders + n_mesh;
    if (mc <= 0) return WC_OK;
    const wg_device* dev = run->dev;
    const wg_layout* L = run->layout;
    if (dev->max_draw_buffers < 8) {
        wg_errorf(err, err_len, "the GL context has %d draw buffers; contacts need 8", dev->max_draw_buffers);
        return WC_ERROR_GPU;
    }
    if (mc > dev->max_texture_size) {
        wg_errorf(err, err_len, "%d colliders do not fit in the device's %d-texel textures", mc, dev->max_texture_size);
        return WC_ERROR_GPU;
    }
    wg_contacts* cs = wc_calloc(&L->alloc, 1, sizeof *cs);
    if (!cs) {
        wg_errorf(err, err_len, "out of memory");
        return WC_ERROR_OUT_OF_MEMORY;
    }
    cs->run = run;
    cs->cl = *cloth;
    cs->max_colliders = max_colliders;
    cs->col_buf = wc_calloc(&L->alloc, (size_t)mc * 20u, sizeof(float));
    if (!cs->col_buf) {
        wg_errorf(err, err_len, "out of memory");
        goto fail;
    }
    int n = cloth->n;
    /* no contact anywhere: C0 = (-1, -1, 0, 0) */
    float* init = cloth->scratch;
    for (int i = 0; i < n; ++i) {
        init[4 * i] = -1.0f;
        init[4 * i + 1] = -1.0f;
        init[4 * i + 2] = 0.0f;
        init[4 * i + 3] = 0.0f;
    }
    wg_ring* rings[3] = {&cs->c0, &cs->c1, &cs->c2};
    for (int r = 0; r < 3; ++r) {
        if (r == 1) memset(init, 0, (size_t)n * 4u * sizeof(float));   /* normals 0, not in contact */
        for (int j = 0; j < 3; ++j)
            if (!wg_array_create(L, &rings[r]->t[j], GL_RGBA32F, n, init, err, err_len)) goto fail;
        if (!wg_array_create(L, &cs->bk[r], GL_RGBA32F, n, init, err, err_len)) goto fail;
        rings[r]->cur = rings[r]->keep = 0;
    }
    wg_tex* pv[] = {&cs->S0, &cs->S1, &cs->z, &cs->b, &cs->ad0, &cs->ad1, &cs->cvel, &cs->x_sub, &cs->held[0],
                    &cs->held[1]};
    if (!wg_mesh_init(&cs->mesh, run, mesh, n_mesh, err, err_len)) goto fail;
    for (size_t k = 0; k < sizeof pv / sizeof pv[0]; ++k)
        if (!wg_array_create(L, pv[k], GL_RGBA32F, n, NULL, err, err_len)) goto fail;
    if (!wg_array_create(L, &cs->A0, cloth->a_lo->internal, cloth->nb, NULL, err, err_len)) goto fail;
    if (!wg_array_create(L, &cs->A1, cloth->a_hi->internal, cloth->nb, NULL, err, err_len)) goto fail;
    if (!wg_tex_create(&cs->cols, GL_RGBA32F, 5, mc, NULL, err, err_len)) goto fail;
    if (!wg_chain_create(run, &cs->chain, cs->c1.t[0].w, cs->c1.t[0].h, err, err_len)) goto fail;
    *out = cs;
    return WC_OK;
fail:
    wg_contacts_destroy(cs);
    return strstr(err, "out of memory") ? WC_ERROR_OUT_OF_MEMORY : WC_ERROR_GPU;
}

/* The analytic colliders in use: s->n_colliders clamped to the capacity. */
static int analytic(const wg_contacts* cs, const wc_state* s) {
    return s->n_colliders < cs->max_colliders ? s->n_colliders : cs->max_colliders;
}

/* The meshes and s->colliders into the colliders' texture; returns the count of rows used. */
static int upload_colliders(wg_contacts* cs, const wc_state* s) {
    int nm = cs->mesh.n_mesh, nc = nm + analytic(cs, s);
    if (nc <= 0) return 0;
    for (int k = 0; k < nm; ++k) wg_mesh_row(&cs->mesh, k, cs->col_buf + 20 * k);
    for (int k = nm; k < nc; ++k) {
        const wc_collider* c = &s->colliders[k - nm];
        float* p = cs->col_buf + 20 * k;
        memset(p, 0, 20 * sizeof(float));
        p[0] = (float)c->type;
        p[1] = (float)c->radius;
        p[2] = (float)c->thickness;
        p[3] = (float)c->friction;
        for (int j = 0; j < 3; ++j) {
            p[4 + j] = (float)c->normal[j];
            p[8 + j] = (float)(c->type == WC_COLLIDER_SPHERE ? c->center[j] : c->a[j]);
            p[12 + j] = (float)c->b[j];
            p[16 + j] = (float)c->velocity[j];
        }
        p[7] = (float)c->offset;
        p[15] = (float)c->push_speed;
    }
    wg_tex_upload(&cs->cols, 0, 0, 5, nc, cs->col_buf);
    return nc;
}

/* The diagonal blocks of A from the per-particle A_ii (friction, recheck). */
static void diag_pass(wg_contacts* cs) {
    wg_runner* run = cs->run;
    const wg_contact_cloth* g = &cs->cl;
    WG_USE(run, WGP_CONTACT_DIAG, &(wg_contact_diag_in){.block = g->block, .a_lo = g->a_lo, .a_hi = g->a_hi,
        .aii_lo = &cs->ad0, .aii_hi = &cs->ad1});
    WG_RUN(run, g->nb, &cs->A0, &cs->A1);
    wg_tex_swap(g->a_lo, &cs->A0);
    wg_tex_swap(g->a_hi, &cs->A1);
}

void wg_contacts_begin(wg_contacts* cs, const wc_state* s, double alpha1, double h) {
    if (!cs) return;
    wg_runner* run = cs->run;
    const wg_contact_cloth* g = &cs->cl;
    wg_mesh_substep(&cs->mesh, s->sub_alpha0, alpha1, h);
    cs->h = h;
    int nc = upload_colliders(cs, s);
    int nx = wg_ring_other(g->x, 0);
    int j0 = wg_ring_other(&cs->c0, 0), j1 = wg_ring_other(&cs->c1, 0), j2 = wg_ring_other(&cs->c2, 0);
    WG_USE(run, WGP_CONTACT_BEGIN, &(wg_contact_begin_in){.x = wg_ring_cur(g->x), .v = wg_ring_cur(g->v), .S0 = g->S0,
        .S1 = g->S1, .z = g->z, .c0 = wg_ring_cur(&cs->c0), .colliders = &cs->cols, .mesh_vert = &cs->mesh.vert,
        .mesh_tri = &cs->mesh.tri, .mesh_node = &cs->mesh.node});
    wg_u1f(run, "u_h", h);
    wg_u1i(run, "u_nc", nc);
    WG_RUN(run, g->n, &g->x->t[nx], &cs->S0, &cs->S1, &cs->z, &cs->c0.t[j0], &cs->c1.t[j1], &cs->c2.t[j2], &cs->cvel);
    g->x->cur = nx;
    if (cs->mesh.n_mesh > 0) wg_copy(run, &cs->x_sub, &g->x->t[nx]);   /* project's start of the moves */
    wg_tex_swap(g->S0, &cs->S0);
    wg_tex_swap(g->S1, &cs->S1);
    wg_tex_swap(g->z, &cs->z);
    cs->c0.cur = j0;
    cs->c1.cur = j1;
    cs->c2.cur = j2;
}

void wg_contacts_integ(wg_contacts* cs, const wg_contact_integ* io, int stage, double h, double he) {
    if (!cs) return;
    wg_runner* run = cs->run;
    const wg_contact_cloth* g = &cs->cl;
    int nv = wg_ring_other(g->v, 0), np = wg_ring_other(io->vp, 0);
    WG_USE(run, WGP_INTEG_CONTACTS, &(wg_integ_contacts_in){.x = wg_ring_cur(g->x), .v = wg_ring_cur(g->v),
        .xb = io->xb, .vstar = io->vstar, .mom = io->mom, .vp = wg_ring_cur(io->vp), .z = g->z,
        .c0 = wg_ring_cur(&cs->c0), .c1 = wg_ring_cur(&cs->c1), .c2 = wg_ring_cur(&cs->c2), .cvel = &cs->cvel});
    wg_u1i(run, "u_stage", stage);
    wg_u1f(run, "u_h", h);
    wg_u1f(run, "u_he", he);
    wg_u1f(run, "u_c2", WC_TRBDF2_C2);
    /* S0, S1 and b are free scratch here: they take xb, v* and (stage 2) mom */
    WG_RUN(run, g->n, &g->v->t[nv], &cs->S0, &cs->S1, stage == 1 ? &io->vp->t[np] : &cs->b, &cs->z);
    g->v->cur = nv;
    wg_tex_swap(io->xb, &cs->S0);
    wg_tex_swap(io->vstar, &cs->S1);
    if (stage == 1) io->vp->cur = np;
    else wg_tex_swap(io->mom, &cs->b);
    wg_tex_swap(g->z, &cs->z);
}

void wg_contacts_friction(wg_contacts* cs, const wc_state* s, double h, const wg_tex* mom) {
    if (!cs) return;
    wg_runner* run = cs->run;
    const wg_contact_cloth* g = &cs->cl;
    int nc = upload_colliders(cs, s);
    int j0 = wg_ring_other(&cs->c0, 0);
    WG_USE(run, WGP_CONTACT_FRICTION, &(wg_contact_friction_in){.v = wg_ring_cur(g->v), .mass = g->mass,
        .ftot = g->ftot, .S0 = g->S0, .S1 = g->S1, .z = g->z, .b = g->b, .pblocks = g->pblocks, .a_lo = g->a_lo,
        .a_hi = g->a_hi, .c0 = wg_ring_cur(&cs->c0), .c1 = wg_ring_cur(&cs->c1), .c2 = wg_ring_cur(&cs->c2),
        .cvel = &cs->cvel, .colliders = &cs->cols, .mom = mom ? mom : g->mass});
    wg_u1f(run, "u_h", h);
    wg_u1i(run, "u_nc", nc);
    wg_u1i(run, "u_mom", mom != NULL);
    WG_RUN(run, g->n, &cs->S0, &cs->S1, &cs->z, &cs->b, &cs->c0.t[j0], &cs->ad0, &cs->ad1);
    wg_tex_swap(g->S0, &cs->S0);
    wg_tex_swap(g->S1, &cs->S1);
    wg_tex_swap(g->z, &cs->z);
    wg_tex_swap(g->b, &cs->b);
    cs->c0.cur = j0;
    diag_pass(cs);
}

int wg_contacts_recheck(wg_contacts* cs, const wc_state* s, const wg_tex* dv) {
    if (!cs) return 0;
    wg_runner* run = cs->run;
    const wg_contact_cloth* g = &cs->cl;
    int nc = upload_colliders(cs, s);
    int j0 = wg_ring_other(&cs->c0, 0), j2 = wg_ring_other(&cs->c2, 0);
    WG_USE(run, WGP_CONTACT_RECHECK, &(wg_contact_recheck_in){.v = wg_ring_cur(g->v), .mass = g->mass, .dv = dv,
        .S0 = g->S0, .S1 = g->S1, .z = g->z, .b = g->b, .pblocks = g->pblocks, .block = g->block, .a_lo = g->a_lo,
        .a_hi = g->a_hi, .c0 = wg_ring_cur(&cs->c0), .c1 = wg_ring_cur(&cs->c1), .c2 = wg_ring_cur(&cs->c2),
        .cvel = &cs->cvel, .colliders = &cs->cols});
    wg_u1i(run, "u_nc", nc);
    WG_RUN(run, g->n, &cs->S0, &cs->S1, &cs->z, &cs->b, &cs->c0.t[j0], &cs->c2.t[j2], &cs->ad0, &cs->ad1);
    wg_tex_swap(g->S0, &cs->S0);
    wg_tex_swap(g->S1, &cs->S1);
    wg_tex_swap(g->z, &cs->z);
    wg_tex_swap(g->b, &cs->b);
    cs->c0.cur = j0;
    cs->c2.cur = j2;
    diag_pass(cs);
    float r[4];
    wg_read1(run->layout, wg_reduce(run, &cs->chain, &cs->c2.t[j2], 0, 0, 0, 0), r);
    return r[3] > 0.5f;
}

void wg_contacts_use_pairs(wg_contacts* cs, const struct wg_pairs* pairs) {
    if (cs) cs->pairs = pairs;
}

void wg_contacts_end(wg_contacts* cs, const wc_state* s, const wg_tex* dv, int stage) {
    if (!cs) return;
    wg_runner* run = cs->run;
    const wg_contact_cloth* g = &cs->cl;
    int nc = cs->mesh.n_mesh + analytic(cs, s);
    int j0 = wg_ring_other(&cs->c0, 0), j1 = wg_ring_other(&cs->c1, 0), j2 = wg_ring_other(&cs->c2, 0);
    /* reads the held impulses stage 1 wrote last, writes the other texture (stage 1: its own) */
    int hw = 1 - cs->held_cur;
    WG_USE(run, WGP_CONTACT_END, &(wg_contact_end_in){.pblocks = g->pblocks, .block = g->block, .a_lo = g->a_lo,
        .a_hi = g->a_hi, .dv = dv, .b = g->b, .c0 = wg_ring_cur(&cs->c0), .c1 = wg_ring_cur(&cs->c1),
        .c2 = wg_ring_cur(&cs->c2), .held = &cs->held[cs->held_cur],
        .pairs = wg_pairs_inputs(cs->pairs, g->pblocks, g->mass)});
    wg_u1i(run, "u_pairs", wg_pairs_on(cs->pairs));
    wg_u1i(run, "u_nc", nc);
    wg_u1i(run, "u_stage", stage);
    WG_RUN(run, g->n, &cs->c0.t[j0], &cs->c1.t[j1], &cs->c2.t[j2], &cs->held[hw]);
    if (stage == 1) cs->held_cur = hw;
    cs->c0.cur = j0;
    cs->c1.cur = j1;
    cs->c2.cur = j2;
}

void wg_contacts_project(wg_contacts* cs, const wc_state* s) {
    if (!cs) return;
    wg_runner* run = cs->run;
    const wg_contact_cloth* g = &cs->cl;
    int nc = upload_colliders(cs, s);
    if (nc <= 0) return;
    int nx = wg_ring_other(g->x, 0), nv = wg_ring_other(g->v, 0);
    const wg_tex* x = wg_ring_cur(g->x);
    WG_USE(run, WGP_CONTACT_PROJECT, &(wg_contact_project_in){.x = x, .v = wg_ring_cur(g->v), .S1 = g->S1,
        .c0 = wg_ring_cur(&cs->c0), .colliders = &cs->cols, .x_sub = cs->mesh.n_mesh > 0 ? &cs->x_sub : x,
        .cvel = &cs->cvel, .mesh_vert = &cs->mesh.vert, .mesh_tri = &cs->mesh.tri, .mesh_node = &cs->mesh.node});
    wg_u1i(run, "u_nc", nc);
    wg_u1f(run, "u_h", cs->h);
    WG_RUN(run, g->n, &g->x->t[nx], &g->v->t[nv]);
    g->x->cur = nx;
    g->v->cur = nv;
}

int wg_contacts_active(wg_contacts* cs) {
    if (!cs) return 0;
    float r[4];
    wg_read1(cs->run->layout, wg_reduce(cs->run, &cs->chain, wg_ring_cur(&cs->c1), 0, 0, 0, 0), r);
    return (int)(r[3] + 0.5f);
}

int wg_contacts_stuck(wg_contacts* cs) {
    if (!cs) return 0;
    float r[4];
    wg_read1(cs->run->layout, wg_reduce(cs->run, &cs->chain, wg_ring_cur(&cs->c0), 0, 0, 0, 0), r);
    return (int)(r[3] + 0.5f);
}

void wg_contacts_save(wg_contacts* cs) {
    if (!cs) return;
    wg_ring_save(&cs->c0);
    wg_ring_save(&cs->c1);
    wg_ring_save(&cs->c2);
}

void wg_contacts_restore(wg_contacts* cs) {
    if (!cs) return;
    wg_ring_restore(&cs->c0);
    wg_ring_restore(&cs->c1);
    wg_ring_restore(&cs->c2);
}

wg_mesh* wg_contacts_mesh(wg_contacts* cs) { return cs ? &cs->mesh : NULL; }

void wg_contacts_backup(wg_contacts* cs) {
    if (!cs) return;
    wg_mesh_body_backup(&cs->mesh);
    wg_ring* rings[3] = {&cs->c0, &cs->c1, &cs->c2};
    for (int r = 0; r < 3; ++r) wg_copy(cs->run, &cs->bk[r], wg_ring_cur(rings[r]));
}

void wg_contacts_restore_backup(wg_contacts* cs) {
    if (!cs) return;
    wg_mesh_body_restore_backup(&cs->mesh);
    wg_ring* rings[3] = {&cs->c0, &cs->c1, &cs->c2};
    for (int r = 0; r < 3; ++r) wg_copy(cs->run, wg_ring_cur(rings[r]), &cs->bk[r]);
}

void wg_contacts_download(wg_contacts* cs, wc_state* s) {
    wc_contacts* ct = &s->contacts;
    if (!cs || !ct->collider) return;
    const wg_layout* L = cs->run->layout;
    int n = cs->cl.n, active = 0;
    float* rb = cs->cl.scratch;
    wg_array_read(L, wg_ring_cur(&cs->c0), n, rb);
    for (int i = 0; i < n; ++i) {
        ct->collider[2 * i] = (int)rb[4 * i];
        ct->collider[2 * i + 1] = (int)rb[4 * i + 1];
        ct->released[i] = rb[4 * i + 2] != 0.0f;
        if (ct->stick) ct->stick[i] = rb[4 * i + 3] != 0.0f;
        active += ct->collider[2 * i] >= 0 || ct->collider[2 * i + 1] >= 0;
    }
    for (int r = 0; r < 2; ++r) {
        wg_array_read(L, wg_ring_cur(r == 0 ? &cs->c1 : &cs->c2), n, rb);
        for (int i = 0; i < n; ++i)
            for (int c = 0; c < 3; ++c) ct->normal[6 * i + 3 * r + c] = (double)rb[4 * i + c];
    }
    ct->active = active;
}

void wg_contacts_upload(wg_contacts* cs, const wc_state* s) {
    const wc_contacts* ct = &s->contacts;
    if (!cs || !ct->collider) return;
    const wg_layout* L = cs->run->layout;
    int n = cs->cl.n;
    float* rb = cs->cl.scratch;
    for (int i = 0; i < n; ++i) {
        rb[4 * i] = (float)ct->collider[2 * i];
        rb[4 * i + 1] = (float)ct->collider[2 * i + 1];
        rb[4 * i + 2] = ct->released[i] ? 1.0f : 0.0f;
        rb[4 * i + 3] = ct->stick && ct->stick[i] ? 1.0f : 0.0f;
    }
    wg_array_upload(L, wg_ring_cur(&cs->c0), n, rb);
    for (int r = 0; r < 2; ++r) {
        for (int i = 0; i < n; ++i) {
            for (int c = 0; c < 3; ++c) rb[4 * i + c] = (float)ct->normal[6 * i + 3 * r + c];
            rb[4 * i + 3] = r == 0 && (ct->collider[2 * i] >= 0 || ct->collider[2 * i + 1] >= 0) ? 1.0f : 0.0f;
        }
        wg_array_upload(L, wg_ring_cur(r == 0 ? &cs->c1 : &cs->c2), n, rb);
    }
}
