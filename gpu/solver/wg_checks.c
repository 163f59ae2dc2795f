/* The step's checks of a state as reductions on the GPU (wg_sim_impl.h): check_particles.glsl's
 * sums and maxima over the particles and check_springs.glsl's over the springs, the measures
 * core's judge compares. A state's checks land in two texels of g->lanczos, CHECKS + slot
 * (particles) and CHECKS + slot + 1 (springs); texels 0..19 there are Chebyshev's Lanczos record.
 * The substep puts its start's checks in slot WG_CHECKS_START and its end's in WG_CHECKS_END and
 * reads all four texels at once. */
#include "wg_sim_impl.h"

enum { CHECKS = 28 };

void wg_checks_run(wg_sim* g, const wc_state* s, const wg_tex* x, const wg_tex* v, int slot) {
    wg_runner* run = &g->run;
    WG_USE(run, WGP_CHECK_PARTICLES, &(wg_check_particles_in){.x = x, .v = v, .mass = &g->mass});
    wg_u3f(run, "u_gravity", s->def.gravity);
    WG_RUN(run, g->n, &g->chk_p);
    const wg_tex* rp = wg_reduce(run, &g->red_p[0], &g->chk_p, 0, 0, 1, 1);
    WG_USE(run, WGP_COPY_TEXEL, &(wg_src_in){.src = rp});
    wg_run_texel(run, &g->lanczos, CHECKS + slot);
    WG_USE(run, WGP_CHECK_SPRINGS, &(wg_check_springs_in){.x = x, .spring = &g->spring,
        .spring_rest = &g->spring_rest});
    wg_u4f(run, "u_k", s->model->material.k);
    wg_u1f(run, "u_seam_scale", s->seam_scale);
    WG_RUN(run, g->ns, &g->chk_s);
    const wg_tex* rs = wg_reduce(run, &g->red_s, &g->chk_s, 0, 1, 0, 0);
    WG_USE(run, WGP_COPY_TEXEL, &(wg_src_in){.src = rs});
    wg_run_texel(run, &g->lanczos, CHECKS + slot + 1);
}

/* A slot's two texels (the particles' channels, then the springs') as checks. */
static wg_checks checks_of(const float t[8]) {
    wg_checks c = {.kinetic = t[0], .gravity = t[1], .max_coord = t[2], .max_v2 = t[3], .elastic = t[4],
                   .max_strain = t[5]};
    return c;
}

void wg_checks_read(wg_sim* g, wg_checks* start, wg_checks* end) {
    float t[16];
    wg_read_texels(&g->layout, &g->lanczos, CHECKS, 4, t);
    *start = checks_of(t + 4 * WG_CHECKS_START);
    if (end) *end = checks_of(t + 4 * WG_CHECKS_END);
}

double wg_checks_energy(wg_sim* g, const wc_state* s, const wg_tex* x, const wg_tex* v) {
    wg_checks_run(g, s, x, v, WG_CHECKS_END);
    float t[8];
    wg_read_texels(&g->layout, &g->lanczos, CHECKS + WG_CHECKS_END, 2, t);
    wg_checks c = checks_of(t);
    return (double)c.kinetic + (double)c.elastic + (double)c.gravity;
}

void wg_checks_springs(wg_sim* g, const wc_state* s, double* elastic, double* max_strain) {
    wg_checks_run(g, s, wg_ring_cur(&g->x), wg_ring_cur(&g->v), WG_CHECKS_START);
    wg_checks now;
    wg_checks_read(g, &now, NULL);
    *elastic = now.elastic;
    *max_strain = now.max_strain;
}
