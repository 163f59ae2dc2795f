/* Creation of a cloth's GPU state from core's model and state, its destruction, and the moves of
 * the state between the CPU mirror and the textures (see wg_sim.h). */
#include <math.h>
#include <stdlib.h>
#include <stdio.h>
#include <string.h>

#include "gpu_error.h"
#include "newton.h"
#include "wg_mesh.h"
#include "wg_sim_impl.h"

#define WG_MIN_SHIFT 10

static wg_tex* model_textures(wg_sim* g, int* n) {
    *n = 13;
    return &g->mass;
}

/* Every texture of the cloth, for destruction and the memory count. */
static int all_textures(wg_sim* g, wg_tex** out, int cap) {
    int k = 0, nm;
    wg_tex* mt = model_textures(g, &nm);
    for (int i = 0; i < nm && k < cap; ++i) out[k++] = mt + i;
    wg_tex* list[] = {&g->pin_map, &g->pin_from, &g->pin_target, &g->pin_axis, &g->x_bak, &g->v_bak, &g->dv_bak,
                      &g->S0, &g->S1, &g->z, &g->sf, &g->sw, &g->sj, &g->fair, &g->b, &g->ftot, &g->A0, &g->A1,
                      &g->D0, &g->D1, &g->sv[0], &g->sv[1], &g->sv[2], &g->r[0], &g->r[1], &g->c[0], &g->c[1],
                      &g->t, &g->q, &g->part, &g->gpart[0], &g->gpart[1], &g->rz, &g->lanczos, &g->chk_p, &g->chk_s,
                      &g->corr, &g->nrm,
                      &g->host_pos, &g->host_nrm, &g->nw_w[0], &g->nw_w[1], &g->nw_w[2], &g->nw_zero, &g->nw_hf, &g->nw_gd,
                      &g->nw_wd, &g->nw_d, &g->nw_fext, &g->xp_bak, &g->vp_bak, &g->xs, &g->xb, &g->vstar, &g->mom,
                      &g->air_lo, &g->air_hi, &g->grp, &g->nw_fa[0], &g->nw_fa[1], &g->nw_fb, &g->nw_cap[0],
                      &g->nw_cap[1], &g->nw_cap[2]};
    for (size_t i = 0; i < sizeof list / sizeof list[0] && k < cap; ++i) out[k++] = list[i];
    wg_ring* rings[] = {&g->x, &g->v, &g->dv, &g->xp, &g->vp};
    for (int r = 0; r < 5; ++r)
        for (int j = 0; j < 3 && k < cap; ++j) out[k++] = &rings[r]->t[j];
    for (int a = 0; a < 2; ++a)
        for (int j = 0; j < 3 && k < cap; ++j) out[k++] = &g->sc[a][j];
    return k;
}

size_t wg_sim_gpu_bytes(const wg_sim* g) {
    wg_tex* t[128];
    int n = all_textures((wg_sim*)g, t, 128);
    size_t bytes = 0;
    for (int k = 0; k < n; ++k) bytes += t[k]->id ? wg_tex_bytes(t[k]) : 0;
    bytes += wg_chain_bytes(&g->red_p[0]) + wg_chain_bytes(&g->red_p[1]) + wg_chain_bytes(&g->red_s);
    return bytes + wg_amg_bytes(g->amg) + wg_contacts_bytes(g->contacts) + wg_pairs_bytes(g->pairs) +
           wg_mesh_sharp_bytes(g->sharp) + wg_self_idle_bytes(g->self_idle) + wg_self_pairs_bytes(g->gself);
}

void wg_sim_forget(wg_sim* g) {
    if (!g) return;
    g->forget_gl = 1;
    wg_sim_destroy(g);
}

void wg_sim_destroy(wg_sim* g) {
    if (!g) return;
    if (g->forget_gl) {
        wg_contacts_forget(g->contacts);
        wg_amg_forget(g->amg);
        wg_pairs_forget(g->pairs);
        wg_mesh_sharp_destroy(g->sharp, 0);
        wg_self_idle_destroy(g->self_idle, 0);
        wg_self_prox_destroy(g->self_prox);
        wg_self_pairs_destroy(g->gself, 0);
        goto memory;
    }
    wg_contacts_destroy(g->contacts);
    wg_amg_destroy(g->amg);
    wg_pairs_destroy(g->pairs);
    wg_mesh_sharp_destroy(g->sharp, 1);
    wg_self_idle_destroy(g->self_idle, 1);
    wg_self_prox_destroy(g->self_prox);
    wg_self_pairs_destroy(g->gself, 1);
    wg_tex* t[128];
    int n = all_textures(g, t, 128);
    for (int k = 0; k < n; ++k) wg_tex_destroy(t[k]);
    wg_chain_destroy(&g->red_p[0]);
    wg_chain_destroy(&g->red_p[1]);
    wg_chain_destroy(&g->red_s);
    wg_runner_destroy(&g->run);
    wg_layout_destroy(&g->layout);
    wg_stamps_destroy(&g->stamps);
    if (g->pbo) glDeleteBuffers(1, &g->pbo);
memory:;
    wc_allocator a = g->alloc;
    wg_self_destroy(g->self);
    wc_free(&a, g->pin_particle);
    wc_free(&a, g->pin_map_cpu);
    wc_free(&a, g->pin_scratch);
    wc_free(&a, g->rb);
    wc_free(&a, g);
}

/* Float4 / int4 staging of the model's arrays. */
static float* f4(wg_sim* g, int n) { return wc_calloc(&g->alloc, (size_t)(n > 0 ? n : 1) * 4u, sizeof(float)); }
static int* i4(wg_sim* g, int n) { return wc_calloc(&g->alloc, (size_t)(n > 0 ? n : 1) * 4u, sizeof(int)); }
static int* i1(wg_sim* g, int n) { return wc_calloc(&g->alloc, (size_t)(n > 0 ? n : 1), sizeof(int)); }

#define TRY(expr)                                                                                    \
    do {                                                                                             \
        if (!(expr)) goto fail;                                                                      \
    } while (0)

static int upload_model(wg_sim* g, const double* host_rest, char* err, size_t el) {
    const wg_layout* L = &g->layout;
    const wc_model* m = g->m;
    const wc_bsr_pattern* p = &m->pattern;
    int n = g->n, ns = g->ns, nt = g->nt, nb = g->nb, nh = g->nh, ok = 0;
    float* f = NULL;
    int *ia = NULL, *ib = NULL;
    TRY(f = f4(g, n));
    for (int i = 0; i < n; ++i) {
        f[4 * i] = (float)m->mass[i];
        f[4 * i + 1] = (float)m->inv_mass[i];
    }
    TRY(wg_array_create(L, &g->mass, GL_RGBA32F, n, f, err, el));
    for (int i = 0; i < n; ++i)
        for (int c = 0; c < 4; ++c) f[4 * i + c] = c < 3 ? (float)m->rest_pos[3 * i + c] : 0.0f;
    TRY(wg_array_create(L, &g->rest, GL_RGBA32F, n, f, err, el));
    wc_free(&g->alloc, f);
    f = NULL;

    TRY(ia = i4(g, ns));
    TRY(f = wc_calloc(&g->alloc, (size_t)(ns > 0 ? ns : 1) * 2u, sizeof(float)));
    for (int s = 0; s < ns; ++s) {
        ia[4 * s] = m->springs[s].a;
        ia[4 * s + 1] = m->springs[s].b;
        ia[4 * s + 2] = m->springs[s].type;
        f[2 * s] = (float)m->springs[s].rest;
        f[2 * s + 1] = (float)m->springs[s].w;
    }
    TRY(wg_array_create(L, &g->spring, GL_RGBA32I, ns, ia, err, el));
    TRY(wg_array_create(L, &g->spring_rest, GL_RG32F, ns, f, err, el));
    wc_free(&g->alloc, ia);
    wc_free(&g->alloc, f);
    ia = NULL;
    f = NULL;

    TRY(ia = i4(g, nt));
    for (int t = 0; t < nt; ++t)
        for (int c = 0; c < 3; ++c) ia[4 * t + c] = m->tris[3 * t + c];
    TRY(wg_array_create(L, &g->tri, GL_RGBA32I, nt, ia, err, el));
    wc_free(&g->alloc, ia);
    ia = NULL;

    TRY(ia = i4(g, n));
    TRY(ib = i4(g, n));
    for (int i = 0; i < n; ++i) {
        ia[4 * i] = p->row_spring_start[i];
        ia[4 * i + 1] = p->row_spring_start[i + 1];
        ia[4 * i + 2] = p->row_tri_start[i];
        ia[4 * i + 3] = p->row_tri_start[i + 1];
        ib[4 * i] = p->row_start[i];
        ib[4 * i + 1] = p->row_start[i + 1];
        ib[4 * i + 2] = p->diag[i];
    }
    TRY(wg_array_create(L, &g->rows, GL_RGBA32I, n, ia, err, el));
    TRY(wg_array_create(L, &g->pblocks, GL_RGBA32I, n, ib, err, el));
    wc_free(&g->alloc, ia);
    wc_free(&g->alloc, ib);
    ia = ib = NULL;

    /* row spring entries (spring, sign, other end, block) */
    int ne = 2 * ns;
    TRY(ia = i4(g, ne));
    for (int i = 0; i < n; ++i)
        for (int k = p->row_spring_start[i]; k < p->row_spring_start[i + 1]; ++k) {
            int s = p->row_spring[k];
            ia[4 * k] = s;
            ia[4 * k + 1] = p->row_spring_sign[k];
            ia[4 * k + 2] = p->row_spring_sign[k] > 0 ? m->springs[s].b : m->springs[s].a;
            ia[4 * k + 3] = p->row_spring_block[k];
        }
    TRY(wg_array_create(L, &g->row_entry, GL_RGBA32I, ne, ia, err, el));
    wc_free(&g->alloc, ia);
    ia = NULL;
    TRY(wg_array_create(L, &g->row_tri, GL_R32I, 3 * nt, p->row_tri, err, el));

    /* blocks (row, column, list start, end); the list of a diagonal block is its row's springs,
       of an off-diagonal block (i, j) the springs joining i and j (inverted from row_spring_block) */
    TRY(ia = i4(g, nb));
    TRY(ib = i1(g, 4 * ns));
    int* cnt = i1(g, nb);
    TRY(cnt);
    for (int k = 0; k < ne; ++k)
        if (p->row_spring_block[k] >= 0) ++cnt[p->row_spring_block[k]];
    int pos = 0;
    for (int i = 0; i < n; ++i)
        for (int k = p->row_start[i]; k < p->row_start[i + 1]; ++k) {
            ia[4 * k] = i;
            ia[4 * k + 1] = p->col[k];
            ia[4 * k + 2] = pos;
            if (k == p->diag[i]) {
                for (int e = p->row_spring_start[i]; e < p->row_spring_start[i + 1]; ++e) ib[pos++] = p->row_spring[e];
            } else {
                for (int e = p->row_spring_start[i]; e < p->row_spring_start[i + 1]; ++e)
                    if (p->row_spring_block[e] == k) ib[pos++] = p->row_spring[e];
            }
            ia[4 * k + 3] = pos;
        }
    wc_free(&g->alloc, cnt);
    TRY(wg_array_create(L, &g->block, GL_RGBA32I, nb, ia, err, el));
    TRY(wg_array_create(L, &g->block_list, GL_R32I, pos, ib, err, el));
    wc_free(&g->alloc, ia);
    wc_free(&g->alloc, ib);
    ia = ib = NULL;

    TRY(wg_array_create(L, &g->host_map, GL_R32I, nh, m->host_to_particle, err, el));
    TRY(f = f4(g, nh));
    if (host_rest)
        for (int h = 0; h < nh; ++h)
            for (int c = 0; c < 3; ++c) f[4 * h + c] = (float)host_rest[3 * h + c];
    TRY(wg_array_create(L, &g->host_rest, GL_RGBA32F, nh, f, err, el));
    ok = 1;
fail:
    wc_free(&g->alloc, f);
    wc_free(&g->alloc, ia);
    wc_free(&g->alloc, ib);
    if (!ok && !err[0]) wg_errorf(err, el, "out of memory");
    return ok;
}

static int create_scratch(wg_sim* g, char* err, size_t el) {
    const wg_layout* L = &g->layout;
    int n = g->n, ns = g->ns, nb = g->nb;
    for (int j = 0; j < 3; ++j) {
        TRY(wg_array_create(L, &g->x.t[j], GL_RGBA32F, n, NULL, err, el));
        TRY(wg_array_create(L, &g->v.t[j], GL_RGBA32F, n, NULL, err, el));
        TRY(wg_array_create(L, &g->dv.t[j], GL_RGBA32F, n, NULL, err, el));
        TRY(wg_array_create(L, &g->sv[j], GL_RGBA32F, n, NULL, err, el));
    }
    wg_tex* pv[] = {&g->x_bak, &g->v_bak, &g->dv_bak, &g->S0, &g->S1, &g->z, &g->b, &g->ftot, &g->D0,
                    &g->r[0], &g->r[1], &g->c[0], &g->c[1], &g->t, &g->q, &g->part, &g->rz, &g->chk_p, &g->nrm};
    for (size_t k = 0; k < sizeof pv / sizeof pv[0]; ++k) TRY(wg_array_create(L, pv[k], GL_RGBA32F, n, NULL, err, el));
    TRY(wg_array_create(L, &g->D1, GL_RG32F, n, NULL, err, el));
    if (g->dev->compute) {   /* a partial sum per work group: the SpMV's of 64 rows, the update's of 256 */
        long long texels = (long long)g->q.w * g->q.h;
        TRY(wg_array_create(L, &g->gpart[0], GL_RGBA32F, (int)((texels + 63) / 64), NULL, err, el));
        TRY(wg_array_create(L, &g->gpart[1], GL_RGBA32F, (int)((texels + 255) / 256), NULL, err, el));
        TRY(wg_tex_create(&g->grp, GL_RGBA32F, 1, 1, NULL, err, el));
    }
    if (g->newton) {
        wg_tex* pn[] = {&g->nw_w[0], &g->nw_w[1], &g->nw_w[2], &g->nw_zero, &g->nw_hf, &g->nw_gd, &g->nw_d,
                        &g->nw_fext, &g->nw_wd};
        for (size_t k = 0; k < sizeof pn / sizeof pn[0]; ++k) TRY(wg_array_create(L, pn[k], GL_RGBA32F, n, NULL, err, el));
    }
    if (g->nw_friction) {
        wg_tex* pf[] = {&g->nw_fa[0], &g->nw_fa[1], &g->nw_fb, &g->nw_cap[0], &g->nw_cap[1], &g->nw_cap[2]};
        for (size_t k = 0; k < sizeof pf / sizeof pf[0]; ++k) TRY(wg_array_create(L, pf[k], GL_RGBA32F, n, NULL, err, el));
    }
    if (g->integ) {
        for (int j = 0; j < 3; ++j) {
            TRY(wg_array_create(L, &g->xp.t[j], GL_RGBA32F, n, NULL, err, el));
            TRY(wg_array_create(L, &g->vp.t[j], GL_RGBA32F, n, NULL, err, el));
        }
        wg_tex* pi[] = {&g->xp_bak, &g->vp_bak, &g->xs, &g->xb, &g->vstar, &g->mom, &g->air_lo, &g->air_hi};
        for (size_t k = 0; k < sizeof pi / sizeof pi[0]; ++k) TRY(wg_array_create(L, pi[k], GL_RGBA32F, n, NULL, err, el));
        if (!g->newton) TRY(wg_array_create(L, &g->nw_fext, GL_RGBA32F, n, NULL, err, el));   /* stage 1's o2 */
    }
    wg_tex* ps[] = {&g->sf, &g->sw, &g->sj, &g->chk_s, &g->corr};
    for (size_t k = 0; k < sizeof ps / sizeof ps[0]; ++k) TRY(wg_array_create(L, ps[k], GL_RGBA32F, ns, NULL, err, el));
    TRY(wg_array_create(L, &g->fair, GL_RGBA32F, g->nt, NULL, err, el));
    TRY(wg_array_create(L, &g->A0, GL_RGBA32F, nb, NULL, err, el));
    TRY(wg_array_create(L, &g->A1, GL_RG32F, nb, NULL, err, el));
    TRY(wg_array_create(L, &g->host_pos, GL_RGBA32F, g->nh, NULL, err, el));
    TRY(wg_array_create(L, &g->host_nrm, GL_RGBA32F, g->nh, NULL, err, el));
    TRY(wg_array_create(L, &g->pin_map, GL_R32I, n, g->pin_map_cpu, err, el));
    TRY(wg_array_create(L, &g->pin_from, GL_RGBA32F, g->pin_cap, NULL, err, el));
    TRY(wg_array_create(L, &g->pin_target, GL_RGBA32F, g->pin_cap, NULL, err, el));
    TRY(wg_array_create(L, &g->pin_axis, GL_RGBA32F, g->pin_cap, NULL, err, el));
    for (int a = 0; a < 2; ++a)
        for (int j = 0; j < 3; ++j) TRY(wg_tex_create(&g->sc[a][j], GL_RGBA32F, 1, 1, NULL, err, el));
    TRY(wg_tex_create(&g->lanczos, GL_RGBA32F, 32, 1, NULL, err, el));
    TRY(wg_chain_create(&g->run, &g->red_p[0], g->part.w, g->part.h, err, el));
    TRY(wg_chain_create(&g->run, &g->red_p[1], g->part.w, g->part.h, err, el));
    TRY(wg_chain_create(&g->run, &g->red_s, g->chk_s.w, g->chk_s.h, err, el));
    return 1;
fail:
    return 0;
}

wc_status wg_sim_supports(const wg_device* dev, const wc_model* m, const wc_sim_def* def, int n_mesh, wc_diag* diag) {
    (void)n_mesh; /* every collider kind runs with every integrator */
    if (def->solver.type == WC_SOLVER_DIRECT)
        return wc_fail(diag, WC_ERROR_UNSUPPORTED,
                       "the GPU backend has no direct solver (CHOLMOD runs on the CPU only): choose pcg, jacobi or "
                       "chebyshev, or the CPU backend");
    if (def->solver.preconditioner == WC_PRECOND_AMG && !dev->compute)
        return wc_fail(diag, WC_ERROR_UNSUPPORTED,
                       "the GPU's multigrid preconditioner runs on compute-shader passes (OpenGL 4.3); this context "
                       "runs fragment passes: choose block_jacobi, or the CPU backend");
    if (def->solver.preconditioner != WC_PRECOND_BLOCK_JACOBI && def->solver.preconditioner != WC_PRECOND_AMG)
        return wc_fail(diag, WC_ERROR_UNSUPPORTED,
                       "the GPU backend has the block-Jacobi and multigrid preconditioners only (the %s "
                       "preconditioner runs on the CPU backend)", wc_precond_name(def->solver.preconditioner));
    if (dev->solve == WG_SOLVE_GROUP && m->n_particles > WG_GROUP_MAX_PARTICLES && def->solver.type == WC_SOLVER_PCG)
        return wc_fail(diag, WC_ERROR_UNSUPPORTED,
                       "WEFT_GPU_SOLVE=group solves cloths of at most %d particles in one work group; this one has %d: "
                       "unset it or set WEFT_GPU_SOLVE=passes", WG_GROUP_MAX_PARTICLES, m->n_particles);
    return WC_OK;
}

/* g->nw_force_scale from the model (wg_sim_impl.h); 0 when out of memory. */
static int force_scale(wg_sim* g) {
    const wc_model* m = g->m;
    double* sum = wc_calloc(&g->alloc, (size_t)(g->n > 0 ? g->n : 1), sizeof(double));
    if (!sum) return 0;
    for (int k = 0; k < m->n_springs; ++k) {
        const wc_spring* sp = &m->springs[k];
        const double t = fabs(m->material.k[sp->type] * sp->w) * sp->rest;
        sum[sp->a] += t;
        sum[sp->b] += t;
    }
    double q = 0.0;
    for (int i = 0; i < g->n; ++i) q += sum[i] * sum[i];
    wc_free(&g->alloc, sum);
    g->nw_force_scale = sqrt(q);
    return 1;
}

wc_status wg_sim_create(wg_device* dev, const wc_state* s, const double* host_rest, wg_sim** out, wc_diag* diag) {
    *out = NULL;
    const wc_model* m = s->model;
    wc_status refused = wg_sim_supports(dev, m, &s->def, s->n_mesh, diag);
    if (refused != WC_OK) return refused;
    int colliders = s->def.max_colliders > 0 || s->n_mesh > 0;
    if (s->n_mesh > 0)
        wc_log(diag, WC_LOG_INFO,
               "GPU cloth: %d mesh collider(s): the vertices' contacts run on the GPU, continuous ones included; "
               "the penalty pairs at the body's sharp edges and corners are found on the host (on the GPU for a body "
               "kept there) and solved on the GPU (docs/design/gpu_bodies.md)", s->n_mesh);
    if (s->self)
        wc_log(diag, WC_LOG_INFO,
               "GPU cloth: self-collision: core's stage runs on the host at the end of every substep that a GPU "
               "proof (compute passes) does not show idle (positions and velocities read back, what it moved "
               "uploaded); its in-solve penalty pairs %s "
               "(docs/design/gpu.md)",
               s->self_pairs ? "are found on the host and solved on the GPU" : "are off (self_in_solve 0)");
    wc_allocator alloc = s->alloc;
    wg_sim* g = wc_calloc(&alloc, 1, sizeof *g);
    if (!g) return wc_fail(diag, WC_ERROR_OUT_OF_MEMORY, "GPU cloth: out of memory");
    g->alloc = alloc;
    g->dev = dev;
    g->m = m;
    g->n = m->n_particles;
    g->ns = m->n_springs;
    g->nt = m->n_tris;
    g->nb = m->pattern.n_blocks;
    g->nh = m->n_host_verts;
    g->pin_cap = s->def.max_pins > 0 ? s->def.max_pins : g->n;
    g->debug_opts = s->def.solver;
    g->newton = wc_newton_wanted(&s->def);
    g->nw_friction = g->newton && colliders;
    g->integ = s->def.integrator != WC_INTEGRATOR_BE;
    long long biggest = g->n;
    long long counts[] = {g->ns * 4LL, g->nb, g->nt * 3LL, g->nh, g->pin_cap};
    for (int k = 0; k < 5; ++k)
        if (counts[k] > biggest) biggest = counts[k];
    int shift = WG_MIN_SHIFT;
    while (shift < 30 && ((biggest + (1LL << shift) - 1) >> shift) > dev->max_texture_size) ++shift;
    if ((1LL << shift) > dev->max_texture_size || biggest > 0x7fffffffLL) {
        wc_free(&alloc, g);
        return wc_fail(diag, WC_ERROR_GPU,
                       "GPU cloth: %lld items in one array (%d particles, %d springs, %d blocks) do not fit in the "
                       "device's %d x %d textures", biggest, m->n_particles, m->n_springs, m->pattern.n_blocks,
                       dev->max_texture_size, dev->max_texture_size);
    }
    char err[512] = "";
    glGetError();
    int ok = (g->pin_particle = i1(g, g->pin_cap)) && (g->pin_map_cpu = i1(g, g->n)) &&
             (g->pin_scratch = wc_calloc(&alloc, (size_t)g->pin_cap * 12u, sizeof(float))) &&
             (g->rb = wc_calloc(&alloc, (size_t)(g->n > g->nh ? g->n : g->nh) * 4u, sizeof(float)));
    if (!ok) {
        wg_sim_destroy(g);
        return wc_fail(diag, WC_ERROR_OUT_OF_MEMORY, "GPU cloth: out of memory");
    }
    for (int i = 0; i < g->n; ++i) g->pin_map_cpu[i] = -1;
    ok = wg_layout_init(&g->layout, shift, dev->max_texture_size, alloc, err, sizeof err);
    wg_runner_init(&g->run, dev, &g->layout);
    wg_stamps_create(&g->stamps, dev->has_timer);
    glGenBuffers(1, &g->pbo);
    ok = ok && upload_model(g, host_rest, err, sizeof err) && create_scratch(g, err, sizeof err);
    if (ok && g->newton && !force_scale(g)) {
        wg_errorf(err, sizeof err, "out of memory");
        ok = 0;
    }
    if (ok && s->self && !(g->self = wg_self_create(&g->layout, g->n, alloc))) {
        wg_errorf(err, sizeof err, "out of memory");
        ok = 0;
    }
    if (ok) {
        GLenum e = glGetError();
        if (e != GL_NO_ERROR) {
            wg_errorf(err, sizeof err, "%s", wg_gl_error_name(e));
            ok = 0;
        }
    }
    if (ok) {
        const wg_contact_cloth cloth = {g->n, g->nb, &g->x, &g->v, &g->S0, &g->S1, &g->z, &g->b, &g->A0, &g->A1,
                                        &g->mass, &g->ftot, &g->pblocks, &g->block, g->rb};
        ok = wg_contacts_create(&g->run, &cloth, s->def.max_colliders, s->mesh, s->n_mesh, &g->contacts, err,
                                sizeof err) == WC_OK;
    }
    if (ok) {
        const wg_pair_cloth cloth = {g->n, g->nb, &g->b, &g->ftot, &g->A0, &g->A1, &g->pblocks, &g->block};
        ok = wg_pairs_create(&g->run, &cloth, s, &g->pairs, err, sizeof err);
        wg_contacts_use_pairs(g->contacts, g->pairs);
    }
    if (ok && g->pairs && s->pairs && s->n_mesh > 0 && wg_contacts_mesh(g->contacts) &&
        wg_contacts_mesh(g->contacts)->body)
        ok = wg_mesh_sharp_create(&g->run, wg_contacts_mesh(g->contacts), s->pairs, m, &g->sharp, err, sizeof err);
    if (dev->body_host < 0 && s->n_mesh > 0)   /* WEFT_GPU_BODY (wg_device.h) */
        wc_log(diag, WC_LOG_WARN, "WEFT_GPU_BODY=%.40s is not device or host: the bodies %s", getenv("WEFT_GPU_BODY"),
               dev->compute ? "from the host's arrays and rigid transforms move on the device" : "move on the host");
    const char* idle_env = getenv("WEFT_GPU_SELF_IDLE");
    if (g->self && idle_env && *idle_env && strcmp(idle_env, "on") && strcmp(idle_env, "off") &&
        strcmp(idle_env, "check"))
        wc_log(diag, WC_LOG_WARN, "WEFT_GPU_SELF_IDLE=%s is not on, off or check: the idle proof is off", idle_env);
    if (ok && g->self && dev->compute && wg_self_idle_env() != WG_SELF_IDLE_OFF)
        ok = wg_self_idle_create(&g->run, s->self, m, wg_self_idle_env(), wg_self_prox_env() ? wg_self_prox_cap(m->n_particles, wg_self_prox_env()) : 0,
                                 &g->self_idle, err, sizeof err);
    if (ok && g->self_idle && wg_self_prox_env()) {
        g->self_prox = wg_self_prox_create(g->run.layout, m, s->self->alloc);
        if (!g->self_prox) {
            ok = 0;
            snprintf(err, sizeof err, "out of memory");
        }
    }
    int pairs_known = 1;
    const wg_self_pairs_mode pairs_mode = wg_self_pairs_env(&pairs_known);
    if (g->self && !pairs_known)
        wc_log(diag, WC_LOG_WARN, "WEFT_GPU_SELF_PAIRS=%s is not gpu or host: the self pairs are found on the host",
               getenv("WEFT_GPU_SELF_PAIRS"));
    if (ok && g->pairs && s->self_pairs && dev->compute && pairs_mode == WG_SELF_PAIRS_GPU) {
        ok = wg_self_pairs_create(&g->run, s->self, s->self_pairs, m, g->self_idle, &g->gself, err, sizeof err);
        if (ok) wg_pairs_use_self_finder(g->pairs, g->gself);
    }
    if (ok && s->def.solver.preconditioner == WC_PRECOND_AMG) {
        const wg_amg_system sys = {&g->block, &g->A0, &g->A1, &g->S0, &g->S1, &g->x};
        /* the one-work-group PCG (WEFT_GPU_SOLVE=group) runs the same V-cycle (pcg_group_amg.glsl) */
        ok = wg_amg_create_form(&g->run, g->m, &sys, dev->amg_smooth, dev->amg_rot, &g->amg, err, sizeof err);
        if (ok) g->amg->fuse = dev->amg_fuse;
        if (ok && g->pairs && dev->amg_cross) ok = wg_amg_pairs_create(g->amg, wg_pairs_capacity(g->pairs), err, sizeof err);
        if (ok && g->amg->rotations && dev->amg_current && !g->amg->current)
            wc_log(diag, WC_LOG_INFO,
                   "GPU cloth: the multigrid takes its rotations about the rest positions: an aggregate holds more "
                   "than %d nodes, the most the current positions' QR holds (docs/design/gpu_passes.md)",
                   WG_AMG_TENT_NODES);
    }
    if (!ok) {
        wg_sim_destroy(g);
        return wc_fail(diag, strstr(err, "out of memory") ? WC_ERROR_OUT_OF_MEMORY : WC_ERROR_GPU,
                       "GPU cloth (%d particles, %d springs): %s", m->n_particles, m->n_springs, err);
    }
    wc_status st = wg_sim_upload(g, s, diag);
    if (st != WC_OK) {
        wg_sim_destroy(g);
        return st;
    }
    *out = g;
    return WC_OK;
}

/* ---- state moves ----------------------------------------------------------------------------- */

static void to_f4(const double* a, int n, float* out) {
    for (int i = 0; i < n; ++i) {
        out[4 * i] = (float)a[3 * i];
        out[4 * i + 1] = (float)a[3 * i + 1];
        out[4 * i + 2] = (float)a[3 * i + 2];
        out[4 * i + 3] = 0.0f;
    }
}

static void from_f4(const float* in, int n, double* a) {
    for (int i = 0; i < n; ++i)
        for (int c = 0; c < 3; ++c) a[3 * i + c] = (double)in[4 * i + c];
}

wc_status wg_sim_upload(wg_sim* g, const wc_state* s, wc_diag* diag) {
    to_f4(s->x, g->n, g->rb);
    wg_array_upload(&g->layout, wg_ring_cur(&g->x), g->n, g->rb);
    to_f4(s->v, g->n, g->rb);
    wg_array_upload(&g->layout, wg_ring_cur(&g->v), g->n, g->rb);
    to_f4(s->dv, g->n, g->rb);
    wg_array_upload(&g->layout, wg_ring_cur(&g->dv), g->n, g->rb);
    if (g->integ) {   /* the history (BDF2's; scratch for TR-BDF2), read where s->hist_valid says */
        to_f4(s->x_prev, g->n, g->rb);
        wg_array_upload(&g->layout, wg_ring_cur(&g->xp), g->n, g->rb);
        to_f4(s->v_prev, g->n, g->rb);
        wg_array_upload(&g->layout, wg_ring_cur(&g->vp), g->n, g->rb);
    }
    wg_contacts_upload(g->contacts, s);
    g->rho_valid = 0;
    GLenum e = glGetError();
    if (e != GL_NO_ERROR) return wc_fail(diag, WC_ERROR_GPU, "GPU cloth: state upload: %s", wg_gl_error_name(e));
    return WC_OK;
}

wc_status wg_sim_download(wg_sim* g, wc_state* s, wc_diag* diag) {
    wg_array_read(&g->layout, wg_ring_cur(&g->x), g->n, g->rb);
    from_f4(g->rb, g->n, s->x);
    wg_array_read(&g->layout, wg_ring_cur(&g->v), g->n, g->rb);
    from_f4(g->rb, g->n, s->v);
    wg_array_read(&g->layout, wg_ring_cur(&g->dv), g->n, g->rb);
    from_f4(g->rb, g->n, s->dv);
    if (g->integ) {
        wg_array_read(&g->layout, wg_ring_cur(&g->xp), g->n, g->rb);
        from_f4(g->rb, g->n, s->x_prev);
        wg_array_read(&g->layout, wg_ring_cur(&g->vp), g->n, g->rb);
        from_f4(g->rb, g->n, s->v_prev);
    }
    wg_contacts_download(g->contacts, s);
    GLenum e = glGetError();
    if (e != GL_NO_ERROR) return wc_fail(diag, WC_ERROR_GPU, "GPU cloth: state read-back: %s", wg_gl_error_name(e));
    return WC_OK;
}

void wg_sim_backup(wg_sim* g) {
    wg_copy(&g->run, &g->x_bak, wg_ring_cur(&g->x));
    wg_copy(&g->run, &g->v_bak, wg_ring_cur(&g->v));
    wg_copy(&g->run, &g->dv_bak, wg_ring_cur(&g->dv));
    if (g->integ) {
        wg_copy(&g->run, &g->xp_bak, wg_ring_cur(&g->xp));
        wg_copy(&g->run, &g->vp_bak, wg_ring_cur(&g->vp));
    }
    wg_contacts_backup(g->contacts);
}

void wg_sim_restore_backup(wg_sim* g) {
    wg_copy(&g->run, wg_ring_cur(&g->x), &g->x_bak);
    wg_copy(&g->run, wg_ring_cur(&g->v), &g->v_bak);
    wg_copy(&g->run, wg_ring_cur(&g->dv), &g->dv_bak);
    if (g->integ) {
        wg_copy(&g->run, wg_ring_cur(&g->xp), &g->xp_bak);
        wg_copy(&g->run, wg_ring_cur(&g->vp), &g->vp_bak);
    }
    wg_contacts_restore_backup(g->contacts);
    g->rho_valid = 0;
}

/* The transform pass over the rings x, v and (not NULL) dv: x' = Rx x + tx, v' = Rv v + dvel,
 * dv' = Rd dv, each ring's new slot its state and start. */
static void transform_rings(wg_sim* g, wg_ring* x, wg_ring* v, wg_ring* dv, const double Rx[9], const double tx[3],
                            const double Rv[9], const double dvel[3], const double Rd[9]) {
    wg_runner* run = &g->run;
    int nx = wg_ring_other(x, 0), nv = wg_ring_other(v, 0), nd = dv ? wg_ring_other(dv, 0) : 0;
    WG_USE(run, WGP_TRANSFORM, &(wg_transform_in){.x = wg_ring_cur(x), .v = wg_ring_cur(v),
        .dv = wg_ring_cur(dv ? dv : v)});   /* without dv: its output is not written */
    wg_umat3(run, "u_rx", Rx);
    wg_u3f(run, "u_tx", tx);
    wg_umat3(run, "u_rv", Rv);
    wg_u3f(run, "u_dv", dvel);
    wg_umat3(run, "u_rd", Rd);
    if (dv) WG_RUN(run, g->n, &x->t[nx], &v->t[nv], &dv->t[nd]);
    else WG_RUN(run, g->n, &x->t[nx], &v->t[nv]);
    x->cur = x->keep = nx;
    v->cur = v->keep = nv;
    if (dv) dv->cur = dv->keep = nd;
}

void wg_sim_transform_state(wg_sim* g, const double Rx[9], const double tx[3], const double Rv[9], const double dv[3],
                            const double Rd[9]) {
    transform_rings(g, &g->x, &g->v, &g->dv, Rx, tx, Rv, dv, Rd);
}

void wg_sim_transform(wg_sim* g, const double Rx[9], const double tx[3], const double Rv[9], const double dv[3]) {
    wg_sim_transform_state(g, Rx, tx, Rv, dv, Rv);
}

void wg_sim_transform_history(wg_sim* g, const double Rx[9], const double tx[3], const double Rv[9],
                              const double dv[3]) {
    if (g->integ) transform_rings(g, &g->xp, &g->vp, NULL, Rx, tx, Rv, dv, Rv);
}

double wg_sim_max_abs(wg_sim* g) {
    wg_runner* run = &g->run;
    WG_USE(run, WGP_CHECK_PARTICLES, &(wg_check_particles_in){.x = wg_ring_cur(&g->x), .v = wg_ring_cur(&g->v),
        .mass = &g->mass});
    double zero[3] = {0, 0, 0};
    wg_u3f(run, "u_gravity", zero);
    WG_RUN(run, g->n, &g->chk_p);
    float r[4];
    wg_read1(&g->layout, wg_reduce(run, &g->red_p[0], &g->chk_p, 0, 0, 1, 1), r);
    return (double)r[2];
}

wg_mesh* wg_sim_mesh(wg_sim* g) { return wg_contacts_mesh(g->contacts); }
