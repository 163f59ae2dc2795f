/* Shared by the GPU contact tests (test_gpu_contacts.c, test_gpu_mesh_contacts.c,
 * test_gpu_trbdf2_contacts.c): a seeded random source, float rounding, and moving a cloth's contact
 * arrays between the GPU and the CPU (uploads, read-backs, the contact state through
 * wg_contacts_download) with their comparisons (CHECKs) to float precision; the analytic
 * colliders' scenario (particles scattered around a plane, sphere or capsule and a crossing plane,
 * a synthetic system, its residual). */
#ifndef WEFT_TESTS_GPU_CONTACTS_SUPPORT_H
#define WEFT_TESTS_GPU_CONTACTS_SUPPORT_H
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "collider.h"
#include "state.h"
#include "wg_sim_impl.h"

#include "test_rng.h"
static inline double srnd(double s) { return s * (2.0 * urand() - 1.0); }
static inline double fr(double a) { return (double)(float)a; }
static inline void frv(double* a, int n) {
    for (int i = 0; i < n; ++i) a[i] = fr(a[i]);
}

static float* g_buf;

static inline void read3(wg_sim* g, const wg_tex* t, double* out) {
    wg_array_read(&g->layout, t, g->n, g_buf);
    for (int i = 0; i < g->n; ++i)
        for (int c = 0; c < 3; ++c) out[3 * i + c] = g_buf[4 * i + c];
}

static inline void upload3(wg_sim* g, const wg_tex* t, const double* a) {
    for (int i = 0; i < g->n; ++i) {
        for (int c = 0; c < 3; ++c) g_buf[4 * i + c] = (float)a[3 * i + c];
        g_buf[4 * i + 3] = 0.0f;
    }
    wg_array_upload(&g->layout, t, g->n, g_buf);
}

static inline void upload_filter(wg_sim* g, const wc_filter* f) {
    int n = g->n;
    for (int i = 0; i < n; ++i) {
        const double* S = f->S + 9 * i;
        float* p = g_buf + 4 * i;
        p[0] = (float)S[0], p[1] = (float)S[1], p[2] = (float)S[2], p[3] = (float)S[4];
    }
    wg_array_upload(&g->layout, &g->S0, n, g_buf);
    for (int i = 0; i < n; ++i) {
        const double* S = f->S + 9 * i;
        float* p = g_buf + 4 * i;
        p[0] = (float)S[5], p[1] = (float)S[8], p[2] = (float)f->ndof[i], p[3] = 0.0f;
    }
    wg_array_upload(&g->layout, &g->S1, n, g_buf);
    upload3(g, &g->z, f->z);
}

/* S (n x 9), ndof (n), z (n x 3) of the GPU filter. */
static inline void read_filter(wg_sim* g, double* S, int* ndof, double* z) {
    int n = g->n;
    float* b1 = malloc((size_t)n * 16);
    wg_array_read(&g->layout, &g->S0, n, g_buf);
    wg_array_read(&g->layout, &g->S1, n, b1);
    for (int i = 0; i < n; ++i) {
        const float* a = g_buf + 4 * i;
        const float* b = b1 + 4 * i;
        double m[9] = {a[0], a[1], a[2], a[1], a[3], b[0], a[2], b[0], b[1]};
        memcpy(S + 9 * i, m, sizeof m);
        ndof[i] = (int)b[2];
    }
    free(b1);
    read3(g, &g->z, z);
}

static inline void upload_A(wg_sim* g, const double* A) {
    int nb = g->nb;
    float* lo = malloc((size_t)nb * 16);
    float* hi = malloc((size_t)nb * 8);
    for (int k = 0; k < nb; ++k) {
        const double* a = A + 9 * k;
        lo[4 * k] = (float)a[0], lo[4 * k + 1] = (float)a[1], lo[4 * k + 2] = (float)a[2], lo[4 * k + 3] = (float)a[4];
        hi[2 * k] = (float)a[5], hi[2 * k + 1] = (float)a[8];
    }
    wg_array_upload(&g->layout, &g->A0, nb, lo);
    wg_array_upload(&g->layout, &g->A1, nb, hi);
    free(lo);
    free(hi);
}

static inline void read_A(wg_sim* g, double* A) {
    int nb = g->nb;
    float* lo = malloc((size_t)nb * 16);
    float* hi = malloc((size_t)nb * 16);
    wg_array_read(&g->layout, &g->A0, nb, lo);
    wg_array_read(&g->layout, &g->A1, nb, hi);
    for (int k = 0; k < nb; ++k) {
        const float* a = lo + 4 * k;
        const float* b = hi + 4 * k;
        double m[9] = {a[0], a[1], a[2], a[1], a[3], b[0], a[2], b[0], b[1]};
        memcpy(A + 9 * k, m, sizeof m);
    }
    free(lo);
    free(hi);
}

/* max |a - b| / scale over n values, scale = 1 + max |b| (absolute near 1, relative above). */
static inline double err_of(const double* a, const double* b, int n) {
    double e = 0, s = 0;
    for (int i = 0; i < n; ++i) {
        double d = fabs(a[i] - b[i]);
        if (d > e) e = d;
        if (fabs(b[i]) > s) s = fabs(b[i]);
    }
    return e / (1.0 + s);
}

/* GPU contact state read back through wg_contacts_download into a scratch wc_contacts. */
typedef struct snap {
    int* collider;
    double* normal;
    unsigned char* released;
    unsigned char* stick;
    int active;
} snap;

static inline void take_gpu(wg_sim* g, wc_state* s, snap* out) {
    /* download into s->contacts_save's arrays (unused by these tests), then copy out */
    wc_contacts keep = s->contacts;
    wc_contacts tmp = keep;
    tmp.collider = out->collider;
    tmp.normal = out->normal;
    tmp.released = out->released;
    tmp.stick = out->stick;
    s->contacts = tmp;
    wg_contacts_download(g->contacts, s);
    out->active = s->contacts.active;
    s->contacts = keep;
}

/* The contact state of the CPU (ct) and of the GPU (gs) alike but for the particles skip marks
 * (NULL: none). */
static inline int compare_contacts(const wc_contacts* ct, const snap* gs, int n, int with_stick, const char* what,
                                   const unsigned char* skip) {
    int bad_id = 0, bad_rel = 0, bad_stick = 0;
    double en = 0;
    for (int i = 0; i < n; ++i) {
        if (skip && skip[i]) continue;
        if (ct->collider[2 * i] != gs->collider[2 * i] || ct->collider[2 * i + 1] != gs->collider[2 * i + 1]) {
            if (bad_id < 3)
                printf("    %s: particle %d colliders cpu (%d %d) gpu (%d %d)\n", what, i, ct->collider[2 * i],
                       ct->collider[2 * i + 1], gs->collider[2 * i], gs->collider[2 * i + 1]);
            ++bad_id;
        }
        bad_rel += ct->released[i] != gs->released[i];
        if (with_stick) bad_stick += ct->stick[i] != gs->stick[i];
        for (int c = 0; c < 6; ++c) {
            double d = fabs(ct->normal[6 * i + c] - gs->normal[6 * i + c]);
            if (ct->collider[2 * i + c / 3] >= 0 && d > en) en = d;
        }
    }
    printf("    %s: collider ids %d differ, released %d, stick %d, normals err %.2g\n", what, bad_id, bad_rel,
           bad_stick, en);
    CHECK_EQ_INT(bad_id, 0);
    CHECK_EQ_INT(bad_rel, 0);
    CHECK_EQ_INT(bad_stick, 0);
    CHECK(en < 2e-5);
    return bad_id + bad_rel + bad_stick;
}

/* The GPU's filter and the CPU's f alike but for the particles skip marks (NULL: none). */
static inline void compare_filter(wg_sim* g, const wc_filter* f, const char* what, int* n_stick,
                                  const unsigned char* skip) {
    int n = g->n;
    double* S = malloc((size_t)n * 9 * sizeof(double));
    double* z = malloc((size_t)n * 3 * sizeof(double));
    int* nd = malloc((size_t)n * sizeof(int));
    read_filter(g, S, nd, z);
    for (int i = 0; i < n; ++i)
        if (skip && skip[i]) {
            memcpy(S + 9 * i, f->S + 9 * i, 9 * sizeof(double));
            memcpy(z + 3 * i, f->z + 3 * i, 3 * sizeof(double));
            nd[i] = f->ndof[i];
        }
    int bad_nd = 0, stick = 0;
    for (int i = 0; i < n; ++i) {
        bad_nd += nd[i] != f->ndof[i];
        stick += f->ndof[i] == 3;
    }
    double eS = err_of(S, f->S, 9 * n), ez = err_of(z, f->z, 3 * n);
    printf("    %s: ndof %d differ (%d particles ndof 3), S err %.2g, z err %.2g\n", what, bad_nd, stick, eS, ez);
    CHECK_EQ_INT(bad_nd, 0);
    CHECK(eS < 1e-5);
    CHECK(ez < 1e-5);
    if (n_stick) *n_stick = stick;
    free(S);
    free(z);
    free(nd);
}

static inline void unit3(double* v) {
    double l = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    for (int k = 0; k < 3; ++k) v[k] = fr(v[k] / l);
}

/* kind 0 plane, 1 sphere, 2 capsule; plus a crossing plane x < 0.25 (collider 1). */
static inline int make_colliders(int kind, int moving, wc_collider* c) {
    memset(c, 0, 2 * sizeof *c);
    c[0].type = kind;
    if (kind == WC_COLLIDER_PLANE) {
        double n[3] = {0.1, 1.0, 0.05};
        unit3(n);
        memcpy(c[0].normal, n, sizeof n);
        c[0].offset = 0.0;
    } else if (kind == WC_COLLIDER_SPHERE) {
        c[0].center[1] = -0.5;
        c[0].radius = 0.5;
    } else {
        c[0].a[0] = -0.6, c[0].a[1] = -0.3;
        c[0].b[0] = 0.6, c[0].b[1] = -0.3, c[0].b[2] = 0.125;
        c[0].radius = 0.3;
    }
    c[0].thickness = 0.01;
    c[0].friction = 0.6;
    if (moving) c[0].velocity[0] = 0.25, c[0].velocity[2] = -0.125;
    c[1].type = WC_COLLIDER_PLANE;
    double n2[3] = {-1.0, 0.25, 0.0};
    unit3(n2);
    memcpy(c[1].normal, n2, sizeof n2);
    c[1].offset = fr(0.25 * n2[0]);   /* through x = 0.25 */
    c[1].thickness = 0.005;
    c[1].friction = 0.3;
    return 2;
}

/* ---- the passes' scenario (test_gpu_contacts.c, test_gpu_trbdf2_contacts.c) --------------------- */

static inline void scatter_analytic(wc_state* s, const wc_collider* c, int nc, double h) {
    int n = s->model->n_particles;
    for (int i = 0; i < n; ++i) {
        double* x = s->x + 3 * i;
        double* v = s->v + 3 * i;
        x[0] = srnd(0.5), x[1] = srnd(0.3), x[2] = srnd(0.5);
        /* onto collider 0's shell, offset along its normal by [-0.03, 0.03] */
        double nrm[3], d = wc_collider_distance(&c[0], x, nrm);
        double off = c[0].thickness + srnd(0.03) - d;
        for (int k = 0; k < 3; ++k) x[k] += off * nrm[k];
        double speed = (i % 3 == 0) ? 0.01 : (i % 3 == 1 ? 0.3 : 2.0);
        for (int k = 0; k < 3; ++k) v[k] = srnd(speed) + c[0].velocity[k];
        /* a few coming in at the right speed to land this substep */
        if (i % 7 == 3)
            for (int k = 0; k < 3; ++k) v[k] -= nrm[k] * (0.02 / h);
    }
    frv(s->x, 3 * n);
    frv(s->v, 3 * n);
    /* the last substep's contact state: held with collider 0 (or both), released, or none */
    wc_contacts* ct = &s->contacts;
    for (int i = 0; i < n; ++i) {
        int r = (int)(urand() * 6);
        ct->collider[2 * i] = ct->collider[2 * i + 1] = -1;
        for (int q = 0; q < 6; ++q) ct->normal[6 * i + q] = 0.0;
        ct->released[i] = 0;
        ct->stick[i] = 0;
        if (r <= 1) {
            ct->collider[2 * i] = 0;
            wc_collider_distance(&c[0], s->x + 3 * i, ct->normal + 6 * i);
            if (r == 1 && nc > 1) {
                ct->collider[2 * i + 1] = 1;
                wc_collider_distance(&c[1], s->x + 3 * i, ct->normal + 6 * i + 3);
            }
        } else if (r == 2) {
            ct->released[i] = 1;
        }
        frv(ct->normal + 6 * i, 6);
    }
    /* pins: particle 0 fixed, 1 on a line, 2 a stale contact row (ndof 1, rewritten) */
    wc_filter* f = &s->filter;
    for (int i = 0; i < n; ++i) wc_filter_free_particle(f, i);
    memset(f->S, 0, 9 * sizeof(double));
    f->z[0] = 0.125;
    f->ndof[0] = 3;
    memset(f->S + 9, 0, 9 * sizeof(double));
    f->S[9] = 1.0;
    f->z[3 + 1] = 0.0625;
    f->ndof[1] = 2;
    f->S[18 + 4] = 0.0;
    f->ndof[2] = 1;
}

/* r = A dv - b over the pattern (n x 3). */
static inline void residual(const wc_model* m, const double* A, const double* b, const double* dv, double* r) {
    for (int i = 0; i < m->n_particles; ++i) {
        double y[3] = {0, 0, 0};
        for (int k = m->pattern.row_start[i]; k < m->pattern.row_start[i + 1]; ++k) {
            const double* a = A + 9 * k;
            const double* xj = dv + 3 * m->pattern.col[k];
            for (int q = 0; q < 3; ++q) y[q] += a[3 * q] * xj[0] + a[3 * q + 1] * xj[1] + a[3 * q + 2] * xj[2];
        }
        for (int q = 0; q < 3; ++q) r[3 * i + q] = y[q] - b[3 * i + q];
    }
}

/* A = M + small symmetric blocks (diagonal ones SPD-ish), b = h f + noise, f = weight into the
 * collider + tangential noise. */
static inline void synth_system(const wc_state* s, const wc_collider* c, double h, double* A, double* b, double* f) {
    const wc_model* m = s->model;
    const wc_bsr_pattern* p = &m->pattern;
    int n = m->n_particles;
    double mass_avg = s->total_mass / n;
    memset(A, 0, (size_t)p->n_blocks * 9 * sizeof(double));
    for (int i = 0; i < n; ++i) {
        for (int k = p->row_start[i]; k < p->row_start[i + 1]; ++k) {
            int j = p->col[k];
            if (j < i) continue;
            double e[9];
            double sc = (j == i ? 0.3 : 0.05) * mass_avg;
            for (int r = 0; r < 3; ++r)
                for (int q = r; q < 3; ++q) e[3 * r + q] = e[3 * q + r] = srnd(sc);
            if (j == i)
                for (int r = 0; r < 3; ++r) e[4 * r] = m->mass[i] + fabs(e[4 * r]) + 0.3 * mass_avg;
            for (int q = 0; q < 9; ++q) A[9 * k + q] = A[9 * p->transpose[k] + q] = fr(e[q]);
        }
        double nrm[3];
        wc_collider_distance(&c[0], s->x + 3 * i, nrm);
        double scale = (i % 4 == 0) ? 0.2 : (i % 4 == 1 ? 3.0 : 30.0);
        for (int k = 0; k < 3; ++k) {
            f[3 * i + k] = fr(-9.81 * m->mass[i] * nrm[k] + srnd(scale * 9.81 * m->mass[i]));
            b[3 * i + k] = fr(h * f[3 * i + k] + srnd(0.05 * m->mass[i]));
        }
    }
}

#endif
