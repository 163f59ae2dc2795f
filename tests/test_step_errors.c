/* Bad values are refused with a status and a message before anything runs, and leave the state
 * exactly as it was: sim defs, pins, colliders, positions, frame times, materials. */
#include <stdlib.h>
#include <string.h>
#include "check.h"
#include "step.h"
#include "test_support.h"
#include "vec3.h"

static wc_model g_model;
static wc_state* g_state;

/* a snapshot of everything a refused call might touch */
typedef struct snap {
    double* x;
    double* v;
    int n_pins, n_colliders;
    wc_pin pins[4];
    wc_collider colliders[4];
    long long frame;
    double time;
} snap;

static void take(snap* s) {
    int n3 = 3 * g_model.n_particles;
    s->x = malloc(sizeof(double) * n3);
    s->v = malloc(sizeof(double) * n3);
    memcpy(s->x, g_state->x, sizeof(double) * n3);
    memcpy(s->v, g_state->v, sizeof(double) * n3);
    s->n_pins = g_state->n_pins;
    s->n_colliders = g_state->n_colliders;
    memcpy(s->pins, g_state->pins, sizeof(wc_pin) * (size_t)s->n_pins);
    memcpy(s->colliders, g_state->colliders, sizeof(wc_collider) * (size_t)s->n_colliders);
    s->frame = g_state->frame;
    s->time = g_state->time;
}

static int same(const snap* s) {
    int n3 = 3 * g_model.n_particles;
    int ok = memcmp(s->x, g_state->x, sizeof(double) * n3) == 0 && memcmp(s->v, g_state->v, sizeof(double) * n3) == 0 &&
             s->n_pins == g_state->n_pins && s->n_colliders == g_state->n_colliders &&
             memcmp(s->pins, g_state->pins, sizeof(wc_pin) * (size_t)s->n_pins) == 0 &&
             memcmp(s->colliders, g_state->colliders, sizeof(wc_collider) * (size_t)s->n_colliders) == 0 &&
             s->frame == g_state->frame && s->time == g_state->time;
    free(s->x);
    free(s->v);
    return ok;
}

#define EXPECT_REFUSED(call, status)                                      \
    do {                                                                  \
        snap s_;                                                          \
        take(&s_);                                                        \
        wc_diag d_ = {0};                                                 \
        wc_status r_ = (call);                                          \
        CHECK_EQ_INT(r_, status);                                         \
        CHECK(d_.message[0] != '\0');                                     \
        CHECK(same(&s_));                                                 \
        if (r_ != WC_OK) printf("  refused: %s\n", d_.message);         \
    } while (0)

static void test_bad_sim_defs(void) {
    struct { const char* what; wc_sim_def def; } cases[12];
    int n = 0;
    for (int k = 0; k < 12; ++k) cases[k].def = wc_default_sim_def();
    cases[n].what = "NaN gravity"; cases[n++].def.gravity[1] = NAN;
    cases[n].what = "negative drag"; cases[n++].def.air.normal_drag = -1;
    cases[n].what = "zero substeps"; cases[n++].def.substeps = 0;
    cases[n].what = "negative substep"; cases[n++].def.substep_dt = -0.01;
    cases[n].what = "bad solver"; cases[n++].def.solver.type = (wc_solver_type)9;
    cases[n].what = "negative tolerance"; cases[n++].def.solver.tolerance = -1;
    cases[n].what = "zero iterations"; cases[n++].def.solver.max_iterations = 0;
    cases[n].what = "NaN strain limit"; cases[n++].def.strain_limit = NAN;
    cases[n].what = "too many halvings"; cases[n++].def.max_halvings = 40;
    cases[n].what = "negative pin capacity"; cases[n++].def.max_pins = -2;
    cases[n].what = "infinite wind"; cases[n++].def.air.wind[0] = INFINITY;
    for (int k = 0; k < n; ++k) {
        int dummy;
        wc_state* s = (wc_state*)(void*)&dummy; /* must come back NULL */
        wc_diag d = {0};
        wc_status r = wc_state_create(&s, &g_model, &cases[k].def, NULL, &d);
        CHECK(r != WC_OK);
        CHECK(s == NULL);
        CHECK(d.message[0] != '\0');
        printf("  %-22s -> %s\n", cases[k].what, d.message);
    }
}

static void test_bad_materials(void) {
    wc_source_mesh src;
    ts_quad_grid(&src, 4, 4, 1, 1, 0);
    for (int k = 0; k < 4; ++k) {
        wc_model_def def = wc_default_model_def();
        if (k == 0) def.material.uniform_mass = -0.1;   /* negative mass */
        if (k == 1) def.material.density = 0;
        if (k == 2) def.material.k[WC_SPRING_SHEAR] = NAN;
        if (k == 3) def.material.d[WC_SPRING_BEND] = -1;
        wc_model m;
        wc_diag d = {0};
        CHECK_EQ_INT(wc_model_build(&m, &src, &def, NULL, &d), WC_ERROR_INVALID_ARGUMENT);
        CHECK(m.n_particles == 0 && m.rest_pos == NULL);
        printf("  material case %d -> %s\n", k, d.message);
    }
    wc_source_mesh_free(&src);
}

static void test_bad_pins(void) {
    wc_pin good = {0, {0, 1, 0}, {0, 0, 0}};
    wc_diag d = {0};
    CHECK_EQ_INT(wc_state_set_pins(g_state, &good, 1, &d), WC_OK);
    wc_pin p = good;
    p.particle = g_model.n_particles;
    EXPECT_REFUSED(wc_state_set_pins(g_state, &p, 1, &d_), WC_ERROR_OUT_OF_RANGE);
    p.particle = -1;
    EXPECT_REFUSED(wc_state_set_pins(g_state, &p, 1, &d_), WC_ERROR_OUT_OF_RANGE);
    p = good;
    p.target[2] = NAN;
    EXPECT_REFUSED(wc_state_set_pins(g_state, &p, 1, &d_), WC_ERROR_NONFINITE);
    p = good;
    v3_set(p.free_axis, 0, 2, 0);
    EXPECT_REFUSED(wc_state_set_pins(g_state, &p, 1, &d_), WC_ERROR_INVALID_ARGUMENT);
    wc_pin two[2] = {good, good};
    EXPECT_REFUSED(wc_state_set_pins(g_state, two, 2, &d_), WC_ERROR_INVALID_ARGUMENT);
    EXPECT_REFUSED(wc_state_set_pins(g_state, NULL, 1, &d_), WC_ERROR_INVALID_ARGUMENT);
    EXPECT_REFUSED(wc_state_set_pins(g_state, &good, g_model.n_particles + 1, &d_), WC_ERROR_OUT_OF_RANGE);
}

static void test_bad_colliders(void) {
    wc_collider good;
    memset(&good, 0, sizeof good);
    good.type = WC_COLLIDER_SPHERE;
    good.radius = 0.2;
    wc_diag d = {0};
    CHECK_EQ_INT(wc_state_set_colliders(g_state, &good, 1, &d), WC_OK);
    wc_collider c = good;
    c.type = 7;
    EXPECT_REFUSED(wc_state_set_colliders(g_state, &c, 1, &d_), WC_ERROR_INVALID_ARGUMENT);
    c = good;
    c.center[0] = NAN;
    EXPECT_REFUSED(wc_state_set_colliders(g_state, &c, 1, &d_), WC_ERROR_NONFINITE);
    c = good;
    c.radius = -1;
    EXPECT_REFUSED(wc_state_set_colliders(g_state, &c, 1, &d_), WC_ERROR_INVALID_ARGUMENT);
    c = good;
    c.type = WC_COLLIDER_PLANE;
    v3_set(c.normal, 0, 0.5, 0);
    EXPECT_REFUSED(wc_state_set_colliders(g_state, &c, 1, &d_), WC_ERROR_INVALID_ARGUMENT);
    c = good;
    c.friction = -0.1;
    EXPECT_REFUSED(wc_state_set_colliders(g_state, &c, 1, &d_), WC_ERROR_INVALID_ARGUMENT);
    c = good;
    c.push_speed = -0.01;
    EXPECT_REFUSED(wc_state_set_colliders(g_state, &c, 1, &d_), WC_ERROR_INVALID_ARGUMENT);
    c = good;
    c.push_speed = NAN;
    EXPECT_REFUSED(wc_state_set_colliders(g_state, &c, 1, &d_), WC_ERROR_NONFINITE);
    EXPECT_REFUSED(wc_state_set_colliders(g_state, &good, 1000, &d_), WC_ERROR_OUT_OF_RANGE);
}

static void test_bad_frames_and_positions(void) {
    wc_diag d = {0};
    CHECK_EQ_INT(wc_step_frame(g_state, 1.0 / 30, NULL, &d), WC_OK);
    const double bad_dt[] = {0.0, -1.0 / 30, NAN, INFINITY, 1e9};
    for (size_t k = 0; k < sizeof bad_dt / sizeof bad_dt[0]; ++k)
        EXPECT_REFUSED(wc_step_frame(g_state, bad_dt[k], NULL, &d_), WC_ERROR_INVALID_ARGUMENT);
    double* x = malloc(sizeof(double) * 3 * g_model.n_particles);
    memcpy(x, g_model.rest_pos, sizeof(double) * 3 * g_model.n_particles);
    x[7] = NAN;
    EXPECT_REFUSED(wc_state_set_positions(g_state, x, NULL, &d_), WC_ERROR_NONFINITE);
    free(x);
}

int main(void) {
    CHECK(ts_sheet(&g_model, 6, 1.0, 1.0, 1, 1.0));
    wc_sim_def sd = wc_default_sim_def();
    sd.max_pins = 3;
    sd.max_colliders = 2;
    wc_diag d = {0};
    CHECK_EQ_INT(wc_state_create(&g_state, &g_model, &sd, NULL, &d), WC_OK);
    RUN_TEST(test_bad_sim_defs);
    RUN_TEST(test_bad_materials);
    RUN_TEST(test_bad_pins);
    RUN_TEST(test_bad_colliders);
    RUN_TEST(test_bad_frames_and_positions);
    wc_state_destroy(g_state);
    wc_model_free(&g_model);
    return TEST_SUMMARY();
}
