/* The GPU side of core/collide.c (see wg_sim_impl.h for the hooks and collide.h for the rules):
 * five per-particle passes (contact_begin, contact_friction, contact_recheck, contact_end,
 * contact_project) and one per block (contact_diag: the friction damping into the diagonal
 * blocks of A).
 *
 * State, per particle, three arrays in rings of three textures each (RGBA32F, ids as floats):
 *   C0 = (collider 1, collider 2, released, stick)   (-1: no collider)
 *   C1 = (normal 1, in contact)                      (the count of w is wg_contacts_active)
 *   C2 = (normal 2, changed by the last recheck)
 * (wg_ring: keep is the substep's start). A pass writes into wg_ring_other(ring, 0), never the
 * current one nor keep: save and restore move indices only.
 *
 * The filter (S0, S1, z), b and A0 / A1 are the cloth's textures: a pass that changes them reads
 * them and writes into a scratch texture of the same format, which then trades places with the
 * cloth's (the wg_tex values are swapped; the cloth's fields keep their addresses).
 *
 * Colliders: a 5 x max_colliders RGBA32F texture, rewritten from s->colliders by every hook that
 * reads them (at most 5 x 16 texels by default). Rows: (type, radius, thickness, friction),
 * (plane normal, offset), (center or a, -), (b, -), (velocity, -). Everything is float: the
 * results agree with core/collide.c to float precision. One deliberate difference: SLOP (1e-9 m)
 * is below float resolution at metre scale, so the shaders widen it to SLOP + 1e-6 max(1, |p|inf)
 * wherever collide.c uses it (begin's contact tests, project's "on the shell": a particle just
 * pushed out lies within a few ulps of its shell, not within 1e-9).
 *
 * Positions and velocities: begin and project write a new g->x.cur (project also g->v.cur) into
 * wg_ring_other(.., 0): never the substep's start (the ring's keep, set by the step's save). */
#include <string.h>

#include "gpu_error.h"
#include "wg_sim_impl.h"

struct wg_contact_sim {
    int max_colliders;
    wg_ring c0, c1, c2;
    wg_tex cols;                /* 5 x max_colliders */
    float* col_buf;             /* 20 x max_colliders */
    wg_tex S0, S1, z, b;        /* scratch of the filter and b (n) */
    wg_tex ad0, ad1;            /* per particle: A_ii (lo, hi) */
    wg_tex A0, A1;              /* scratch of A (nb) */
    wg_chain chain;             /* sums over n */
    wg_tex bk[3];               /* the frame's back-up of c0, c1, c2 (wg_sim_backup) */
};

static void swap_tex(wg_tex* a, wg_tex* b) {
    wg_tex t = *a;
    *a = *b;
    *b = t;
}

wc_status wg_contacts_create(wg_sim* g, const wc_state* s, char* err, size_t err_len) {
    g->contacts = NULL;
    int mc = s->def.max_colliders;
    if (mc <= 0) return WC_OK;
    if (g->dev->max_draw_buffers < 8) {
        wg_errorf(err, err_len, "the GL context has %d draw buffers; contacts need 8", g->dev->max_draw_buffers);
        return WC_ERROR_GPU;
    }
    if (mc > g->dev->max_texture_size) {
        wg_errorf(err, err_len, "%d colliders do not fit in the device's %d-texel textures", mc,
                  g->dev->max_texture_size);
        return WC_ERROR_GPU;
    }
    wg_contact_sim* cs = wc_calloc(&g->alloc, 1, sizeof *cs);
    if (!cs) {
        wg_errorf(err, err_len, "out of memory");
        return WC_ERROR_OUT_OF_MEMORY;
    }
    g->contacts = cs;
    cs->max_colliders = mc;
    cs->col_buf = wc_calloc(&g->alloc, (size_t)mc * 20u, sizeof(float));
    if (!cs->col_buf) {
        wg_errorf(err, err_len, "out of memory");
        goto fail;
    }
    int n = g->n;
    /* no contact anywhere: C0 = (-1, -1, 0, 0) */
    float* init = g->rb;
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
            if (!wg_array_create(g, &rings[r]->t[j], GL_RGBA32F, n, init, err, err_len)) goto fail;
        if (!wg_array_create(g, &cs->bk[r], GL_RGBA32F, n, init, err, err_len)) goto fail;
        rings[r]->cur = rings[r]->keep = 0;
    }
    wg_tex* pv[] = {&cs->S0, &cs->S1, &cs->z, &cs->b, &cs->ad0, &cs->ad1};
    for (size_t k = 0; k < sizeof pv / sizeof pv[0]; ++k)
        if (!wg_array_create(g, pv[k], GL_RGBA32F, n, NULL, err, err_len)) goto fail;
    if (!wg_array_create(g, &cs->A0, g->A0.internal, g->nb, NULL, err, err_len)) goto fail;
    if (!wg_array_create(g, &cs->A1, g->A1.internal, g->nb, NULL, err, err_len)) goto fail;
    if (!wg_tex_create(&cs->cols, GL_RGBA32F, 5, mc, NULL, err, err_len)) goto fail;
    if (!wg_chain_create(g, &cs->chain, cs->c1.t[0].w, cs->c1.t[0].h, err, err_len)) goto fail;
    return WC_OK;
fail:
    wg_contacts_destroy(g);
    return strstr(err, "out of memory") ? WC_ERROR_OUT_OF_MEMORY : WC_ERROR_GPU;
}

void wg_contacts_destroy(wg_sim* g) {
    wg_contact_sim* cs = g->contacts;
    if (!cs) return;
    if (!g->forget_gl) {
    wg_ring* rings[3] = {&cs->c0, &cs->c1, &cs->c2};
    for (int r = 0; r < 3; ++r)
        for (int j = 0; j < 3; ++j) wg_tex_destroy(&rings[r]->t[j]);
    for (int r = 0; r < 3; ++r) wg_tex_destroy(&cs->bk[r]);
    wg_tex* pv[] = {&cs->S0, &cs->S1, &cs->z, &cs->b, &cs->ad0, &cs->ad1, &cs->A0, &cs->A1, &cs->cols};
    for (size_t k = 0; k < sizeof pv / sizeof pv[0]; ++k) wg_tex_destroy(pv[k]);
    wg_chain_destroy(&cs->chain);
    }
    wc_free(&g->alloc, cs->col_buf);
    wc_free(&g->alloc, cs);
    g->contacts = NULL;
}

/* s->colliders into the colliders' texture; returns the count used (clamped to the capacity). */
static int upload_colliders(wg_sim* g, const wc_state* s) {
    wg_contact_sim* cs = g->contacts;
    int nc = s->n_colliders < cs->max_colliders ? s->n_colliders : cs->max_colliders;
    if (nc <= 0) return 0;
    for (int k = 0; k < nc; ++k) {
        const wc_collider* c = &s->colliders[k];
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
    }
    wg_tex_upload(&cs->cols, 0, 0, 5, nc, cs->col_buf);
    return nc;
}

/* The diagonal blocks of A from the per-particle A_ii (friction, recheck). */
static void diag_pass(wg_sim* g) {
    wg_contact_sim* cs = g->contacts;
    wg_use(g, WGP_CONTACT_DIAG);
    wg_in(g, 0, &g->block);
    wg_in(g, 1, &g->A0);
    wg_in(g, 2, &g->A1);
    wg_in(g, 3, &cs->ad0);
    wg_in(g, 4, &cs->ad1);
    WG_RUN(g, g->nb, &cs->A0, &cs->A1);
    swap_tex(&g->A0, &cs->A0);
    swap_tex(&g->A1, &cs->A1);
}

void wg_contacts_begin(wg_sim* g, const wc_state* s, double h) {
    wg_contact_sim* cs = g->contacts;
    if (!cs) return;
    int nc = upload_colliders(g, s);
    int nx = wg_ring_other(&g->x, 0);
    int j0 = wg_ring_other(&cs->c0, 0), j1 = wg_ring_other(&cs->c1, 0), j2 = wg_ring_other(&cs->c2, 0);
    wg_use(g, WGP_CONTACT_BEGIN);
    wg_in(g, 0, wg_ring_cur(&g->x));
    wg_in(g, 1, wg_ring_cur(&g->v));
    wg_in(g, 2, &g->S0);
    wg_in(g, 3, &g->S1);
    wg_in(g, 4, &g->z);
    wg_in(g, 5, &cs->c0.t[cs->c0.cur]);
    wg_in(g, 15, &cs->cols);
    wg_u1f(g, "u_h", h);
    wg_u1i(g, "u_nc", nc);
    WG_RUN(g, g->n, &g->x.t[nx], &cs->S0, &cs->S1, &cs->z, &cs->c0.t[j0], &cs->c1.t[j1], &cs->c2.t[j2]);
    g->x.cur = nx;
    swap_tex(&g->S0, &cs->S0);
    swap_tex(&g->S1, &cs->S1);
    swap_tex(&g->z, &cs->z);
    cs->c0.cur = j0;
    cs->c1.cur = j1;
    cs->c2.cur = j2;
}

void wg_contacts_friction(wg_sim* g, const wc_state* s, double h) {
    wg_contact_sim* cs = g->contacts;
    if (!cs) return;
    int nc = upload_colliders(g, s);
    int j0 = wg_ring_other(&cs->c0, 0);
    wg_use(g, WGP_CONTACT_FRICTION);
    wg_in(g, 0, wg_ring_cur(&g->v));
    wg_in(g, 1, &g->mass);
    wg_in(g, 2, &g->ftot);
    wg_in(g, 3, &g->S0);
    wg_in(g, 4, &g->S1);
    wg_in(g, 5, &g->z);
    wg_in(g, 6, &g->b);
    wg_in(g, 7, &g->pblocks);
    wg_in(g, 8, &g->A0);
    wg_in(g, 9, &g->A1);
    wg_in(g, 10, &cs->c0.t[cs->c0.cur]);
    wg_in(g, 11, &cs->c1.t[cs->c1.cur]);
    wg_in(g, 12, &cs->c2.t[cs->c2.cur]);
    wg_in(g, 15, &cs->cols);
    wg_u1f(g, "u_h", h);
    wg_u1i(g, "u_nc", nc);
    WG_RUN(g, g->n, &cs->S0, &cs->S1, &cs->z, &cs->b, &cs->c0.t[j0], &cs->ad0, &cs->ad1);
    swap_tex(&g->S0, &cs->S0);
    swap_tex(&g->S1, &cs->S1);
    swap_tex(&g->z, &cs->z);
    swap_tex(&g->b, &cs->b);
    cs->c0.cur = j0;
    diag_pass(g);
}

int wg_contacts_recheck(wg_sim* g, const wc_state* s, const wg_tex* dv, double h) {
    (void)h;
    wg_contact_sim* cs = g->contacts;
    if (!cs) return 0;
    int nc = upload_colliders(g, s);
    int j0 = wg_ring_other(&cs->c0, 0), j2 = wg_ring_other(&cs->c2, 0);
    wg_use(g, WGP_CONTACT_RECHECK);
    wg_in(g, 0, wg_ring_cur(&g->v));
    wg_in(g, 1, &g->mass);
    wg_in(g, 2, dv);
    wg_in(g, 3, &g->S0);
    wg_in(g, 4, &g->S1);
    wg_in(g, 5, &g->z);
    wg_in(g, 6, &g->b);
    wg_in(g, 7, &g->pblocks);
    wg_in(g, 8, &g->block);
    wg_in(g, 9, &g->A0);
    wg_in(g, 10, &g->A1);
    wg_in(g, 11, &cs->c0.t[cs->c0.cur]);
    wg_in(g, 12, &cs->c1.t[cs->c1.cur]);
    wg_in(g, 13, &cs->c2.t[cs->c2.cur]);
    wg_in(g, 15, &cs->cols);
    wg_u1i(g, "u_nc", nc);
    WG_RUN(g, g->n, &cs->S0, &cs->S1, &cs->z, &cs->b, &cs->c0.t[j0], &cs->c2.t[j2], &cs->ad0, &cs->ad1);
    swap_tex(&g->S0, &cs->S0);
    swap_tex(&g->S1, &cs->S1);
    swap_tex(&g->z, &cs->z);
    swap_tex(&g->b, &cs->b);
    cs->c0.cur = j0;
    cs->c2.cur = j2;
    diag_pass(g);
    float r[4];
    wg_read1(g, wg_reduce(g, &cs->chain, &cs->c2.t[j2], 0, 0, 0, 0), r);
    return r[3] > 0.5f;
}

void wg_contacts_end(wg_sim* g, const wc_state* s, const wg_tex* dv) {
    wg_contact_sim* cs = g->contacts;
    if (!cs) return;
    int nc = s->n_colliders < cs->max_colliders ? s->n_colliders : cs->max_colliders;
    int j0 = wg_ring_other(&cs->c0, 0), j1 = wg_ring_other(&cs->c1, 0), j2 = wg_ring_other(&cs->c2, 0);
    wg_use(g, WGP_CONTACT_END);
    wg_in(g, 0, &g->pblocks);
    wg_in(g, 1, &g->block);
    wg_in(g, 2, &g->A0);
    wg_in(g, 3, &g->A1);
    wg_in(g, 4, dv);
    wg_in(g, 5, &g->b);
    wg_in(g, 6, &cs->c0.t[cs->c0.cur]);
    wg_in(g, 7, &cs->c1.t[cs->c1.cur]);
    wg_in(g, 8, &cs->c2.t[cs->c2.cur]);
    wg_in(g, 15, &cs->cols);
    wg_u1i(g, "u_nc", nc);
    WG_RUN(g, g->n, &cs->c0.t[j0], &cs->c1.t[j1], &cs->c2.t[j2]);
    cs->c0.cur = j0;
    cs->c1.cur = j1;
    cs->c2.cur = j2;
}

void wg_contacts_project(wg_sim* g, const wc_state* s) {
    wg_contact_sim* cs = g->contacts;
    if (!cs) return;
    int nc = upload_colliders(g, s);
    if (nc <= 0) return;
    int nx = wg_ring_other(&g->x, 0), nv = wg_ring_other(&g->v, 0);
    wg_use(g, WGP_CONTACT_PROJECT);
    wg_in(g, 0, wg_ring_cur(&g->x));
    wg_in(g, 1, wg_ring_cur(&g->v));
    wg_in(g, 2, &g->S1);
    wg_in(g, 3, &cs->c0.t[cs->c0.cur]);
    wg_in(g, 15, &cs->cols);
    wg_u1i(g, "u_nc", nc);
    WG_RUN(g, g->n, &g->x.t[nx], &g->v.t[nv]);
    g->x.cur = nx;
    g->v.cur = nv;
}

int wg_contacts_active(wg_sim* g) {
    wg_contact_sim* cs = g->contacts;
    if (!cs) return 0;
    float r[4];
    wg_read1(g, wg_reduce(g, &cs->chain, &cs->c1.t[cs->c1.cur], 0, 0, 0, 0), r);
    return (int)(r[3] + 0.5f);
}

void wg_contacts_save(wg_sim* g) {
    wg_contact_sim* cs = g->contacts;
    if (!cs) return;
    cs->c0.keep = cs->c0.cur;
    cs->c1.keep = cs->c1.cur;
    cs->c2.keep = cs->c2.cur;
}

void wg_contacts_restore(wg_sim* g) {
    wg_contact_sim* cs = g->contacts;
    if (!cs) return;
    cs->c0.cur = cs->c0.keep;
    cs->c1.cur = cs->c1.keep;
    cs->c2.cur = cs->c2.keep;
}

void wg_contacts_backup(wg_sim* g) {
    wg_contact_sim* cs = g->contacts;
    if (!cs) return;
    wg_ring* rings[3] = {&cs->c0, &cs->c1, &cs->c2};
    for (int r = 0; r < 3; ++r) wg_copy(g, &cs->bk[r], wg_ring_cur(rings[r]));
}

void wg_contacts_restore_backup(wg_sim* g) {
    wg_contact_sim* cs = g->contacts;
    if (!cs) return;
    wg_ring* rings[3] = {&cs->c0, &cs->c1, &cs->c2};
    for (int r = 0; r < 3; ++r) wg_copy(g, wg_ring_cur(rings[r]), &cs->bk[r]);
}

void wg_contacts_download(wg_sim* g, wc_state* s) {
    wg_contact_sim* cs = g->contacts;
    wc_contacts* ct = &s->contacts;
    if (!cs || !ct->collider) return;
    int n = g->n, active = 0;
    float* rb = g->rb;
    wg_array_read(g, &cs->c0.t[cs->c0.cur], n, rb);
    for (int i = 0; i < n; ++i) {
        ct->collider[2 * i] = (int)rb[4 * i];
        ct->collider[2 * i + 1] = (int)rb[4 * i + 1];
        ct->released[i] = rb[4 * i + 2] != 0.0f;
        if (ct->stick) ct->stick[i] = rb[4 * i + 3] != 0.0f;
        active += ct->collider[2 * i] >= 0 || ct->collider[2 * i + 1] >= 0;
    }
    for (int r = 0; r < 2; ++r) {
        const wg_ring* ring = r == 0 ? &cs->c1 : &cs->c2;
        wg_array_read(g, &ring->t[ring->cur], n, rb);
        for (int i = 0; i < n; ++i)
            for (int c = 0; c < 3; ++c) ct->normal[6 * i + 3 * r + c] = (double)rb[4 * i + c];
    }
    ct->active = active;
}

void wg_contacts_upload(wg_sim* g, const wc_state* s) {
    wg_contact_sim* cs = g->contacts;
    const wc_contacts* ct = &s->contacts;
    if (!cs || !ct->collider) return;
    int n = g->n;
    float* rb = g->rb;
    for (int i = 0; i < n; ++i) {
        rb[4 * i] = (float)ct->collider[2 * i];
        rb[4 * i + 1] = (float)ct->collider[2 * i + 1];
        rb[4 * i + 2] = ct->released[i] ? 1.0f : 0.0f;
        rb[4 * i + 3] = ct->stick && ct->stick[i] ? 1.0f : 0.0f;
    }
    wg_array_upload(g, &cs->c0.t[cs->c0.cur], n, rb);
    for (int r = 0; r < 2; ++r) {
        const wg_ring* ring = r == 0 ? &cs->c1 : &cs->c2;
        for (int i = 0; i < n; ++i) {
            for (int c = 0; c < 3; ++c) rb[4 * i + c] = (float)ct->normal[6 * i + 3 * r + c];
            rb[4 * i + 3] = r == 0 && (ct->collider[2 * i] >= 0 || ct->collider[2 * i + 1] >= 0) ? 1.0f : 0.0f;
        }
        wg_array_upload(g, &ring->t[ring->cur], n, rb);
    }
}
