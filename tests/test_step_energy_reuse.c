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
 *   every state afresh (wc_state.judge_fresh), with the same rollbacks.
 * The memo (core/energy_memo.h), which takes over a measure of the same x and v wherever it was
 * taken (the substep's start is the previous one's end; Newton's cap after pins that did not
 * move; Newton's guard at the iterate the substep then ends on), checked on a 16 x 16 sheet
 * hanging from two corners under the defaults (Newton 2 + line search, the guard on):
 * - the run is the fresh run's bit for bit (positions, velocities, judged energies, caps, gains)
 *   and the memo took measures over (hits > 0);
 * - a measure after one bit of x, of v, of gravity or of the seam scale changed is a fresh one
 *   (== wc_state_total_energy), and the same state measured twice is taken over;
 * - the line search's first potential of every substep (its iterate w~0 is the substep's start:
 *   x_n, velocities 0) takes the springs' energies from prepare's force evaluation
 *   (core/newton.c, at_start) and is, bit for bit, the fresh run's, which sums the spring loop. */
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

/* every substep's first potential Phi(w~0), as the line search traced it */
typedef struct phi0_log {
    double phi[4 * FRAMES];
    int n;
} phi0_log;

static void on_iterate(void* user, const wc_state* s, int it, double phi, const double* w) {
    (void)s;
    (void)w;
    phi0_log* lg = user;
    if (it == 0 && lg->n < 4 * FRAMES) lg->phi[lg->n++] = phi;
}

static wc_state* make_hanging(wc_model* m, int fresh) {
    if (!ts_sheet(m, N, 1.0, 0.0, 1, 1.0)) return NULL;
    wc_sim_def d = wc_default_sim_def();
    d.threads = 1;
    d.sleep_speed = 0;
    d.newton_iterations = 2; /* the public defaults (weft_cloth_def): Newton 2 + line search */
    d.line_search = 1;
    wc_state* s = NULL;
    wc_diag diag = {0};
    if (wc_state_create(&s, m, &d, NULL, &diag) != WC_OK) return NULL;
    if (ts_pin_far_corners(s, N, NULL) != WC_OK) return NULL;
    s->judge_fresh = fresh;
    return s;
}

static void test_memo_hanging_sheet(void) {
    wc_model ma, mb;
    wc_state* a = make_hanging(&ma, 0);
    wc_state* b = make_hanging(&mb, 1);
    CHECK(a && b);
    if (!a || !b) return;
    static phi0_log la, lb;
    la.n = lb.n = 0;
    a->newton_trace = on_iterate;
    a->newton_trace_user = &la;
    b->newton_trace = on_iterate;
    b->newton_trace_user = &lb;
    size_t n3 = 3 * (size_t)ma.n_particles;
    int judged = 0, unlike = 0;
    wc_diag d = {0};
    for (int f = 0; f < FRAMES; ++f) {
        wc_step_stats sa, sb;
        CHECK_EQ_INT(wc_step_frame(a, 1.0 / 30.0, &sa, &d), WC_OK);
        CHECK_EQ_INT(wc_step_frame(b, 1.0 / 30.0, &sb, &d), WC_OK);
        if (memcmp(a->x, b->x, n3 * sizeof(double)) || memcmp(a->v, b->v, n3 * sizeof(double))) ++unlike;
        if (sa.rollbacks != sb.rollbacks) ++unlike;
        if (isnan(sa.judged_energy_end)) continue;
        ++judged;
        double e = wc_state_total_energy(a, NULL);
        if (memcmp(&e, &sa.judged_energy_end, sizeof e) != 0) ++unlike;
        if (memcmp(&sb.judged_energy_end, &sa.judged_energy_end, sizeof e) != 0) ++unlike;
        if (memcmp(&sb.judged_total, &sa.judged_total, sizeof e) != 0) ++unlike;
        if (memcmp(&sb.judged_cap, &sa.judged_cap, sizeof e) != 0) ++unlike;
    }
    long hits = a->energy_memo.hits, misses = a->energy_memo.misses;
    printf("  hanging sheet: %d of %d frames judged, memo %ld taken over / %ld measured (fresh run: %ld / %ld), "
           "%d differences from the fresh run\n",
           judged, FRAMES, hits, misses, b->energy_memo.hits, b->energy_memo.misses, unlike);
    CHECK(judged == FRAMES);
    CHECK(hits > misses); /* most of a substep's measures repeat a state */
    CHECK(b->energy_memo.hits == 0);
    CHECK_EQ_INT(unlike, 0);
    /* the line search's first potentials: prepare's spring energies against the loop's sums */
    int phi_off = la.n != lb.n;
    for (int k = 0; k < la.n && k < lb.n; ++k) phi_off += memcmp(&la.phi[k], &lb.phi[k], sizeof(double)) != 0;
    printf("  first potentials: %d traced, %ld from prepare's spring energies (fresh run: %ld), %d unlike the "
           "fresh run's\n",
           la.n, a->nw_spring_e_used, b->nw_spring_e_used, phi_off);
    CHECK(la.n >= FRAMES);
    CHECK(a->nw_spring_e_used == la.n); /* pins still, no contacts: every first iterate is the start */
    CHECK(b->nw_spring_e_used == 0);
    CHECK_EQ_INT(phi_off, 0);

    /* the key: each input's one bit makes a fresh measure */
    int stale = 0;
    double e0 = wc_state_judge_energy(a, a->x, a->v, NULL);
    long h0 = a->energy_memo.hits;
    double e1 = wc_state_judge_energy(a, a->x, a->v, NULL);
    CHECK(a->energy_memo.hits == h0 + 1);
    stale += memcmp(&e0, &e1, sizeof e0) != 0;
    double* fields[] = {a->x + 3 * 7 + 1, a->v + 3 * 11 + 1, &a->def.gravity[1], &a->seam_scale};
    for (int q = 0; q < 4; ++q) {
        wc_state_judge_energy(a, a->x, a->v, NULL); /* the memo holds the state as it is */
        double keep = *fields[q];
        unsigned char* byte = (unsigned char*)fields[q];
        byte[0] ^= 1; /* the last bit of the mantissa */
        long h = a->energy_memo.hits;
        double el = 0.0, ref_el = 0.0;
        double got = wc_state_judge_energy(a, a->x, a->v, &el);
        double ref = wc_state_total_energy(a, &ref_el);
        stale += a->energy_memo.hits != h;
        stale += memcmp(&got, &ref, sizeof got) != 0 || memcmp(&el, &ref_el, sizeof el) != 0;
        *fields[q] = keep;
    }
    printf("  memo key: %d stale measures after one-bit changes of x, v, gravity, seam scale\n", stale);
    CHECK_EQ_INT(stale, 0);
    wc_state_destroy(a);
    wc_state_destroy(b);
    wc_model_free(&ma);
    wc_model_free(&mb);
}

int main(void) {
    RUN_TEST(test_judged_energy_is_fresh);
    RUN_TEST(test_memo_hanging_sheet);
    return TEST_SUMMARY();
}
