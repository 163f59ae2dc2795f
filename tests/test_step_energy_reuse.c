/* The energy judge's measures taken over (core/step.c): where a substep measures the total energy
 * of a state it already measured (after the contacts' begin and again for Newton's cap; after the
 * colliders' projection and again before the self-collision stage; after the stage and again for
 * the judge's end), it takes the earlier measure. Checked two ways on a 16 x 16 sheet draped over
 * a sphere with self-collision on (the projection and the stage both move particles, the judge
 * runs: a still collider, no pins, no wind):
 * - the energy the judge took for each frame's end state (wc_step_stats.judged_energy_end) is,
 *   bit for bit, a fresh wc_state_total_energy of the state the frame leaves, and within rounding
 *   of the test's own energy (energy_log.h: the springs' energy summed another way);
 * - the run gives the same positions and velocities, bit for bit, as a twin run that measures
 *   every state afresh (wc_state.judge_fresh), with the same rollbacks. */
#include <math.h>
#include <string.h>
#include "check.h"
#include "energy_log.h"
#include "forces.h"
#include "self_collide.h"
#include "step.h"
#include "test_support.h"

#define N 16
#define FRAMES 40

static wc_state* make(wc_model* m, int fresh) {
    wc_sim_def d = wc_default_sim_def();
    d.self_collision = 1;
    d.self_thickness = 0.05; /* thick next to the 6.7 cm springs: the stage's proximity pass acts */
    d.self_in_solve = 0;
    d.sleep_speed = 0;
    d.threads = 1;
    wc_state* s = ts_draped(m, N, &d, 0);
    if (s) s->judge_fresh = fresh;
    return s;
}

static void test_judged_energy_is_fresh(void) {
    wc_model ma, mb;
    wc_state* a = make(&ma, 0);
    wc_state* b = make(&mb, 1);
    CHECK(a && b);
    if (!a || !b) return;
    CHECK(a->def.fail_energy_gain > 0);
    size_t n3 = 3 * (size_t)ma.n_particles;
    int judged = 0, contacts = 0, proximity = 0, bits_off = 0, unlike_fresh = 0, rollbacks = 0, rollbacks_fresh = 0;
    double worst_rel = 0.0;
    wc_diag d = {0};
    for (int f = 0; f < FRAMES; ++f) {
        wc_step_stats sa, sb;
        CHECK_EQ_INT(wc_step_frame(a, 1.0 / 30.0, &sa, &d), WC_OK);
        CHECK_EQ_INT(wc_step_frame(b, 1.0 / 30.0, &sb, &d), WC_OK);
        rollbacks += sa.rollbacks;
        rollbacks_fresh += sb.rollbacks;
        contacts += sa.contacts;
        proximity += sa.self_proximity;
        if (memcmp(a->x, b->x, n3 * sizeof(double)) || memcmp(a->v, b->v, n3 * sizeof(double))) ++unlike_fresh;
        if (isnan(sa.judged_energy_end)) continue;
        ++judged;
        double e = wc_state_total_energy(a, NULL);
        if (memcmp(&e, &sa.judged_energy_end, sizeof e) != 0) ++bits_off;
        if (memcmp(&sb.judged_energy_end, &sa.judged_energy_end, sizeof e) != 0) ++unlike_fresh;
        if (memcmp(&sb.judged_total, &sa.judged_total, sizeof e) != 0) ++unlike_fresh; /* the gains */
        if (memcmp(&sb.judged_cap, &sa.judged_cap, sizeof e) != 0) ++unlike_fresh;     /* Newton's cap */
        double own = energy_at(a, a->x);
        double rel = fabs(sa.judged_energy_end - own) / fmax(fabs(own), 1e-12);
        if (rel > worst_rel) worst_rel = rel;
    }
    printf("  %d of %d frames judged; %d contacts, %d proximity impulses summed; %d judged ends off a fresh "
           "measure; %d frames unlike the fresh run; %d rollbacks; own energy within %.2g\n",
           judged, FRAMES, contacts, proximity, bits_off, unlike_fresh, rollbacks, worst_rel);
    CHECK(judged > FRAMES / 2);       /* the judge ran */
    CHECK(contacts > 0);              /* the projection had work */
    CHECK(proximity > 0);             /* and so had the self-collision stage */
    CHECK_EQ_INT(bits_off, 0);
    CHECK_EQ_INT(unlike_fresh, 0);
    CHECK_EQ_INT(rollbacks, rollbacks_fresh);
    CHECK(worst_rel < 1e-9);
    wc_state_destroy(a);
    wc_state_destroy(b);
    wc_model_free(&ma);
    wc_model_free(&mb);
}

int main(void) {
    RUN_TEST(test_judged_energy_is_fresh);
    return TEST_SUMMARY();
}
