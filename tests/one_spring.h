/* The integrators' one-spring model (test_bdf2.c, test_trbdf2.c): one spring of stiffness k (no
 * damping) from pinned particle 0 at the origin to particle 1 (mass m) along +x, 0.5 m long;
 * particle 2 (at (0, 0.7, 0.3)) is to be pinned out of the way by the test. */
#ifndef WEFT_TESTS_ONE_SPRING_H
#define WEFT_TESTS_ONE_SPRING_H
#include "check.h"
#include "model.h"
#include "source_mesh.h"
#include "state.h"
#include "vec3.h"

static inline void spring_model(wc_model* m, double k, double mass) {
    double pos[9] = {0, 0, 0, 0.5, 0, 0, 0, 0.7, 0.3};
    int sizes[1] = {3}, idx[3] = {0, 1, 2};
    wc_source_mesh src;
    wc_diag dg = {0};
    CHECK_EQ_INT(wc_source_mesh_from_arrays(&src, NULL, pos, 3, sizes, 1, idx, 1.0, &dg), WC_OK);
    wc_model_def def = wc_default_model_def();
    def.reorder = 0;
    def.material.uniform_mass = mass;
    def.material.k[WC_SPRING_STRETCH] = k;
    def.material.d[WC_SPRING_STRETCH] = 0.0;
    CHECK_EQ_INT(wc_model_build(m, &src, &def, NULL, &dg), WC_OK);
    int keep = -1;
    for (int s = 0; s < m->n_springs; ++s)
        if (m->springs[s].a == 0 && m->springs[s].b == 1) keep = s;
    CHECK(keep >= 0);
    m->springs[0] = m->springs[keep];
    m->n_springs = 1;
    for (int t = 1; t <= WC_SPRING_TYPE_COUNT; ++t) m->spring_type_start[t] = 1;
    wc_bsr_pattern_free(&m->pattern, &m->alloc);
    CHECK_EQ_INT(wc_bsr_pattern_build(&m->pattern, m, &m->alloc), 0);
    wc_source_mesh_free(&src);
}

/* The model's state for `integ`: no gravity, no air, direct solves, one thread, no sleep, no
 * energy judge, particles 0 and 2 pinned where they are. */
static inline wc_state* spring_state(const wc_model* m, wc_integrator integ) {
    wc_sim_def sd = wc_default_sim_def();
    v3_zero(sd.gravity);
    sd.air.normal_drag = sd.air.tangent_drag = 0.0;
    sd.solver.type = WC_SOLVER_DIRECT;
    sd.integrator = integ;
    sd.threads = 1;
    sd.sleep_speed = 0.0;
    sd.fail_energy_gain = 0.0;
    wc_state* s = NULL;
    wc_diag dg = {0};
    CHECK_EQ_INT(wc_state_create(&s, m, &sd, NULL, &dg), WC_OK);
    wc_pin pins[2] = {{0, {0, 0, 0}, {0, 0, 0}}, {2, {0, 0.7, 0.3}, {0, 0, 0}}};
    CHECK_EQ_INT(wc_state_set_pins(s, pins, 2, &dg), WC_OK);
    return s;
}

#endif
