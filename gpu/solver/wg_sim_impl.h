/* Private to gpu/solver: the textures of one cloth and the pass helpers its files share.
 *
 * Layout: item i of every array is texel (i & (W-1), i >> shift), W = 2^shift the same for all
 * of the cloth's arrays (1024, or wider when an array would be taller than the device allows);
 * an array of n < W items is an n x 1 texture. Vectors are RGBA32F (xyz; w free for a partial
 * product), symmetric 3x3 blocks two textures (a00 a01 a02 a11 | a12 a22), indices RGBA32I.
 *
 * State arrays come in threes (wg_ring), named by index: [cur] is the state, a substep writes
 * into the other two and either keeps its result (cur moves) or drops it: a rollback costs
 * nothing. */
#ifndef WEFT_GPU_SOLVER_SIM_IMPL_H
#define WEFT_GPU_SOLVER_SIM_IMPL_H

#include "gl_texture.h"
#include "wg_sim.h"

#define WG_FBO_CACHE 96
#define WG_REDUCE_LEVELS 12
#define WG_MAX_OUT 8
#define WG_MAX_STAMPS 96

typedef struct wg_fbo_entry {
    GLuint fbo;
    int n;
    GLuint tex[WG_MAX_OUT];
} wg_fbo_entry;

/* The levels of a reduction of a w x h array down to one texel: 8 x 8 blocks a level (fragment
 * passes), or one or two dispatches of reduce_groups.glsl (compute passes: a level as wide as its
 * dispatch's work groups). */
typedef struct wg_chain {
    int n_levels;
    wg_tex level[WG_REDUCE_LEVELS];
} wg_chain;

typedef struct wg_ring {
    wg_tex t[3];
    int cur;                    /* the state now */
    int keep;                   /* the substep's start (what a rollback returns to) */
} wg_ring;

static inline wg_tex* wg_ring_cur(wg_ring* r) { return &r->t[r->cur]; }
/* A slot a pass may write: neither cur nor keep (k = 0, or 1 when cur == keep gives a second). */
static inline int wg_ring_other(const wg_ring* r, int k) {
    for (int j = 0; j < 3; ++j)
        if (j != r->cur && j != r->keep && k-- == 0) return j;
    return (r->cur + 1) % 3;
}

typedef enum wg_stage {
    WG_STAGE_COLLIDE, WG_STAGE_FORCES, WG_STAGE_ASSEMBLE, WG_STAGE_SOLVE, WG_STAGE_INTEGRATE, WG_STAGE_COUNT
} wg_stage;

typedef struct wg_contact_sim wg_contact_sim;   /* wg_contacts.c */
typedef struct wg_amg wg_amg;                   /* wg_amg.h */

struct wg_sim {
    wg_device* dev;
    const wc_model* m;
    wc_allocator alloc;
    int shift;                  /* layout width W = 1 << shift */
    int n, ns, nt, nb, nh, pin_cap;

    /* the model, uploaded once */
    wg_tex mass;                /* particles: (m, 1/m) */
    wg_tex rest;                /* particles: rest positions */
    wg_tex spring;              /* springs: (a, b, type, -) */
    wg_tex spring_rest;         /* springs: rest length */
    wg_tex tri;                 /* triangles: (a, b, c, -) */
    wg_tex rows;                /* particles: (spring start, end, triangle start, end) of their lists */
    wg_tex pblocks;             /* particles: (block row start, end, diagonal block, -) */
    wg_tex row_entry;           /* 2 ns: (spring, sign, other particle, block) */
    wg_tex row_tri;             /* 3 nt: triangle */
    wg_tex block;               /* blocks: (row, column, spring list start, end) */
    wg_tex block_list;          /* 4 ns: spring */
    wg_tex host_map;            /* host vertices: particle or -1 */
    wg_tex host_rest;           /* host vertices: rest position, object space (m) */

    /* pins, per frame */
    wg_tex pin_map;             /* particles: pin index or -1 */
    wg_tex pin_from, pin_target, pin_axis;   /* pins */
    int n_pins_uploaded;
    int* pin_particle;          /* (pin_cap) particles of the uploaded pin map */
    int* pin_map_cpu;           /* (n) */
    float* pin_scratch;         /* (3 pin_cap x 4) */

    /* state */
    wg_ring x, v, dv;
    wg_tex x_bak, v_bak, dv_bak;
    int bak_x, bak_v, bak_dv;   /* ring indices the back-up was taken from */

    /* substep scratch */
    wg_tex S0, S1, z;           /* filter */
    wg_tex sf, sw, sj;          /* spring outputs */
    wg_tex fair;                /* triangle air forces */
    wg_tex b, ftot;
    wg_tex A0, A1;              /* blocks */
    wg_tex D0, D1;              /* preconditioner */
    wg_tex sv[3];               /* solver iterates */
    wg_tex r[2], c[2], t, q, part, rz;
    wg_tex sc[2][3];            /* PCG scalars, ping-pong */
    int sc_cur;
    long long passes;           /* draws run (wg_run, wg_run_texel): wg_sim_debug_passes */
    wg_tex lanczos;             /* 32 x 1: (alpha, beta) per Lanczos step */
    wg_tex chk_p, chk_s, corr;
    wg_chain red_p[2], red_s;
    wg_tex nrm, host_pos, host_nrm;
    GLuint pbo;
    float* rb;                  /* read-back scratch: max(n, nh) x 4 floats */

    wg_fbo_entry fbo[WG_FBO_CACHE];
    int n_fbo;
    GLuint scratch_fbo;
    wg_program* prog;           /* program in use */

    /* frame */
    wc_solver_type last_solver;
    wc_solve_result last_solve;
    wc_solver_opts debug_opts;  /* wg_sim_debug_solve's options (the state's at creation) */
    double rho;                 /* Chebyshev's cached estimate */
    double residual_floor;      /* the solves' residual floor of this substep (core/solve.h; 0: none) */
    int rho_valid;
    int prepared;
    wg_contact_sim* contacts;   /* NULL when the cloth never had colliders */
    wg_amg* amg;                /* the multigrid (wg_amg.h) when the preconditioner is amg, else NULL */
    int amg_on;                 /* PCG's solve in progress preconditions with it */
    GLuint stamps[WG_MAX_STAMPS];
    int stamp_stage[WG_MAX_STAMPS];
    int n_stamps;
    int gl_error;               /* a GL error seen in this frame */
    int forget_gl;              /* destroy: free memory only (wg_sim_forget) */
};

/* ---- passes (wg_pass.c) ---------------------------------------------------------------------- */

/* Item count to a texture size in the layout. */
void wg_layout_size(const wg_sim* g, int count, int* w, int* h);
/* Create a texture for `count` items (at least one texel); 0 with err on failure. */
int wg_array_create(wg_sim* g, wg_tex* t, GLenum internal, int count, const void* data, char* err, size_t err_len);
/* Upload items [0, count) of an array from a client buffer laid out item after item. */
void wg_array_upload(wg_sim* g, const wg_tex* t, int count, const void* data);
/* Read items [0, count) (RGBA32F arrays) into out (count x 4 floats). */
void wg_array_read(wg_sim* g, const wg_tex* t, int count, float* out);

void wg_use(wg_sim* g, wg_pass_id p);
void wg_in(wg_sim* g, int unit, const wg_tex* t);
void wg_u1i(wg_sim* g, const char* name, int v);
void wg_u1f(wg_sim* g, const char* name, double v);
void wg_u2f(wg_sim* g, const char* name, double a, double b);
void wg_u3f(wg_sim* g, const char* name, const double* v);
void wg_u2i(wg_sim* g, const char* name, int a, int b);
void wg_u4i(wg_sim* g, const char* name, int a, int b, int c, int d);
void wg_umat3(wg_sim* g, const char* name, const double* row_major);
/* Draw the program in use into the outputs (same size), one fragment per texel; count = items
 * of the output array (u_n). */
void wg_run(wg_sim* g, int count, const wg_tex* const* out, int n_out);
/* Compute passes only: dispatch the native compute program in use (*_groups.glsl) as `groups`
 * work groups writing out (image 0); count = items (u_n). */
void wg_run_groups(wg_sim* g, int count, const wg_tex* out, int groups);
/* Draw the program in use into texel (x, 0) of out only. */
void wg_run_texel(wg_sim* g, const wg_tex* out, int x);
#define WG_RUN(g, count, ...) \
    wg_run((g), (count), (const wg_tex* const[]){__VA_ARGS__}, \
           (int)(sizeof((const wg_tex* const[]){__VA_ARGS__}) / sizeof(const wg_tex*)))
/* Reduce src down to one texel: channel c summed (mode 0) or maximised (1). Returns the 1 x 1
 * result (a level of ch). */
const wg_tex* wg_reduce(wg_sim* g, wg_chain* ch, const wg_tex* src, int m0, int m1, int m2, int m3);
int wg_chain_create(wg_sim* g, wg_chain* ch, int w, int h, char* err, size_t err_len);
void wg_chain_destroy(wg_chain* ch);
/* Read one texel (RGBA32F) at (0, 0): a synchronisation. */
void wg_read1(wg_sim* g, const wg_tex* t, float out[4]);
/* dst = src (same size), a copy pass. */
void wg_copy(wg_sim* g, const wg_tex* dst, const wg_tex* src);
/* A GL timestamp tagged with the stage that starts now (ignored without timer queries). */
void wg_stamp(wg_sim* g, wg_stage stage);

/* x' = Rx x + tx, v' = Rv v + dv, dv' = Rd dv (wg_sim_transform with Rd = Rv). */
void wg_sim_transform_state(wg_sim* g, const double Rx[9], const double tx[3], const double Rv[9], const double dv[3],
                            const double Rd[9]);

/* ---- the substep (wg_step.c), also run alone by the debug entry points ------------------------ */

void wg_step_upload_pins(wg_sim* g, const wc_state* s);
void wg_step_prepare(wg_sim* g, const wc_state* s, double h, double alpha1, wc_compression compression);

/* ---- solvers (wg_solve.c) -------------------------------------------------------------------- */

/* g->q = A x over the prepared blocks; with filter, q = S (A x) and w = x.q (PCG's step). */
void wg_spmv(wg_sim* g, const wg_tex* x, int filter);

/* Solve the prepared system (A0/A1, b, S0/S1, z) from the initial guess in dv_in; the result is
 * left in *out (one of g->sv). */
wc_status wg_solve(wg_sim* g, const wc_solver_opts* o, wc_solver_type type, const wg_tex* dv_in,
                     const wg_tex** out, wc_solve_result* res);

/* ---- contacts (wg_contacts.c): colliders with thickness and friction ------------------------- */

/* The GPU side of core/collide.c's five steps, with the same rules; called by wg_step.c only when
 * the state has colliders (s->n_colliders > 0). Colliders come from s->colliders each substep.
 * Contact state (per particle: colliders, normals, released, stick) lives in the contact sim's
 * own textures (rings, rolled back with the substep through wg_contacts_save/restore). */
wc_status wg_contacts_create(wg_sim* g, const wc_state* s, char* err, size_t err_len);
void wg_contacts_destroy(wg_sim* g);
/* 1: after the pins pass (S0, S1, z hold the pins): find contacts, correct positions (a new
 * g->x.cur), write their constraints into S0/S1/z. */
void wg_contacts_begin(wg_sim* g, const wc_state* s, double h);
/* 2: after assembly (A0/A1 in block layout, b, ftot): Coulomb friction; may change S0/S1/z, the
 * diagonal blocks of A0/A1 and b. */
void wg_contacts_friction(wg_sim* g, const wc_state* s, double h);
/* 3b: after a solve whose result is dv: sticking contacts the solved cloth overloads slide;
 * returns 1 when something changed (the caller solves again). May read back one texel. */
int wg_contacts_recheck(wg_sim* g, const wc_state* s, const wg_tex* dv, double h);
/* 4: after v += dv (dv the solve's result): release contacts whose normal impulse pulls inward. */
void wg_contacts_end(wg_sim* g, const wc_state* s, const wg_tex* dv);
/* 5: after positions advanced and strain limiting: push x out of collider shells, remove inward
 * normal velocity (new g->x.cur / g->v.cur). */
void wg_contacts_project(wg_sim* g, const wc_state* s);
/* Particles in contact now (read back: one texel). */
int wg_contacts_active(wg_sim* g);
void wg_contacts_save(wg_sim* g);      /* substep start */
void wg_contacts_backup(wg_sim* g);    /* the frame's back-up (wg_sim_backup) */
void wg_contacts_restore_backup(wg_sim* g);
void wg_contacts_restore(wg_sim* g);   /* rollback to it */
/* Contact arrays of the CPU mirror (s->contacts) <-> textures (snapshots). */
void wg_contacts_download(wg_sim* g, wc_state* s);
void wg_contacts_upload(wg_sim* g, const wc_state* s);

#endif
