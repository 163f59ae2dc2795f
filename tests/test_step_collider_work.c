/* The energy judge and the colliders' position corrections (core/step.c): a collider that pushes
 * a particle out of its shell does work on the cloth (a contact force), so the energy that
 * correction puts into the springs is not charged to the step, as the self-collision stage's is
 * not. Found in sample_scenes/suit_on_body.json: the suit starts up to 1.1 cm inside the body,
 * every substep of the first frames pushes it out (+0.10-0.14 J of spring energy), and the judge
 * rolled four of them back although the solve itself dissipated (-0.05 to -0.09 J).
 *
 * Closed form: a 3 x 3 sheet at rest, no gravity, its middle particle 1 cm inside a static sphere
 * (its neighbours outside): begin moves it onto the sphere's surface straight up (the push is
 * along the normal, at once: push_speed 0), which stretches its springs by an energy computed
 * here from the moved positions alone (wc_spring_energy). With the judge on at a tight allowance:
 * no rollback, and the total energy after the step is at most the energy after that push (the
 * step itself dissipates). The judge still charges a step's own gain: test_step_energy.c. */
#include <math.h>
#include <string.h>
#include "check.h"
#include "energy_log.h"
#include "collide.h"
#include "forces.h"
#include "step.h"
#include "test_support.h"
#include "vec3.h"

#define N 3
#define SIZE 0.2   /* m: springs of rest 0.1 m */
#define R 0.04     /* m: the sphere */
#define DEPTH 0.01 /* m: how far the middle particle starts inside it */

static double total_energy(const wc_state* s, const double* x) { return energy_at(s, x); }

static void test_push_out_is_not_charged(void) {
    wc_model m;
    CHECK(ts_sheet(&m, N, SIZE, 0.0, 0, 1.0));
    wc_sim_def d = wc_default_sim_def();
    v3_set(d.gravity, 0.0, 0.0, 0.0);
    d.air.normal_drag = d.air.tangent_drag = 0.0;
    d.solver.type = WC_SOLVER_DIRECT;
    d.fail_energy_gain = 0.01;
    d.threads = 1;
    wc_state* s = NULL;
    log_rec rec = {0};
    wc_diag diag = {WC_OK, "", on_log, &rec};
    CHECK_EQ_INT(wc_state_create(&s, &m, &d, NULL, &diag), WC_OK);
    int mid = ts_sheet_particle(&m, N, 1, 1);
    const double* p = s->x + 3 * mid;
    wc_collider c;
    memset(&c, 0, sizeof c);
    c.type = WC_COLLIDER_SPHERE;
    v3_set(c.center, p[0], p[1] - (R - DEPTH), p[2]);
    c.radius = R;
    CHECK_EQ_INT(wc_state_set_colliders(s, &c, 1, &diag), WC_OK);

    /* the energy after the push, from positions alone: the middle particle DEPTH higher */
    const double e_rest = total_energy(s, s->x);
    double moved[3 * N * N];
    memcpy(moved, s->x, sizeof moved);
    moved[3 * mid + 1] += DEPTH;
    const double e_pushed = total_energy(s, moved);
    /* by hand: its four edge springs (rest r, now sqrt(r^2 + DEPTH^2)) hold most of it */
    const double r = SIZE / (N - 1), stretch = sqrt(r * r + DEPTH * DEPTH) - r;
    CHECK(e_pushed - e_rest >= 4 * 0.5 * m.material.k[WC_SPRING_STRETCH] * stretch * stretch * 0.5);
    /* with no gravity and nothing elastic at rest the allowance is 0 J: any gain charged fails */
    CHECK(e_pushed - e_rest > 1e-4);

    wc_step_stats st;
    CHECK_EQ_INT(wc_step_frame(s, 1.0 / 60, &st, &diag), WC_OK);
    CHECK_EQ_INT(st.rollbacks, 0);
    CHECK_EQ_INT(rec.energy_rollbacks, 0);
    /* the middle particle is on the sphere (not inside it), the step only dissipated */
    double n[3];
    CHECK(wc_collider_distance(&c, s->x + 3 * mid, n) > -1e-9);
    const double e_end = total_energy(s, s->x);
    CHECK(e_end <= e_pushed + 1e-12);
    CHECK(e_end > e_rest);   /* what the collider put in is still largely there after one step */
    wc_state_destroy(s);
    wc_model_free(&m);
}

int main(void) {
    RUN_TEST(test_push_out_is_not_charged);
    return TEST_SUMMARY();
}
