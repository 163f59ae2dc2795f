/* Sleeping cloths in core (state.h, step.h): a sheet hanging from two corners comes to rest and
 * falls asleep exactly when its rest timer, computed here from a never-sleeping twin run, reaches
 * sleep_time (not before); until then it is bit-identical to the twin; asleep its positions stay
 * bit-identical, velocities zero, time advances as the twin's; every wake rule wakes it and the
 * waking frame is simulated (with the physics the change asks for); identical inputs do not wake
 * it; sleep_speed 0 and moving pins never sleep. */
#include <stdlib.h>
#include <string.h>
#include "check.h"
#include "step.h"
#include "test_support.h"
#include "vec3.h"

#define N 8
#define DT (1.0 / 60.0)

typedef struct rig {
    wc_model m;
    wc_state* s;
    wc_pin pins[2];
} rig;

/* A vertical 0.5 m sheet pinned at its two top corners (at rest in its rest shape, so it settles
 * within a fraction of a second). */
static void rig_make(rig* r, double sleep_speed, double sleep_time) {
    CHECK(ts_sheet(&r->m, N, 0.5, 1.0, 1, 1.0));
    wc_sim_def sd = wc_default_sim_def();
    sd.threads = 1;
    sd.sleep_speed = sleep_speed;
    sd.sleep_time = sleep_time;
    wc_diag d = {0};
    CHECK_EQ_INT(wc_state_create(&r->s, &r->m, &sd, NULL, &d), WC_OK);
    memset(r->pins, 0, sizeof r->pins);
    r->pins[0].particle = ts_sheet_particle(&r->m, N, 0, N - 1);
    r->pins[1].particle = ts_sheet_particle(&r->m, N, N - 1, N - 1);
    for (int k = 0; k < 2; ++k) v3_copy(r->pins[k].target, r->m.rest_pos + 3 * r->pins[k].particle);
    CHECK_EQ_INT(wc_state_set_pins(r->s, r->pins, 2, &d), WC_OK);
}

static void rig_free(rig* r) {
    wc_state_destroy(r->s);
    wc_model_free(&r->m);
}

static wc_step_stats step(wc_state* s) {
    wc_step_stats st;
    wc_diag d = {0};
    CHECK_EQ_INT(wc_step_frame(s, DT, &st, &d), WC_OK);
    return st;
}

static int same_x(const wc_state* a, const double* x) {
    return memcmp(a->x, x, 3 * sizeof(double) * (size_t)a->model->n_particles) == 0;
}

/* Step until asleep (at most 300 frames); returns the frames stepped. */
static int run_to_sleep(wc_state* s) {
    for (int f = 1; f <= 300; ++f)
        if (step(s).fell_asleep) return f;
    CHECK(!"the cloth never fell asleep");
    return -1;
}

/* The rest timer: asleep exactly at the frame the twin's speed has stayed below sleep_speed for
 * sleep_time, bit-identical to the twin until then; then nothing moves. */
static void test_falls_asleep(void) {
    const double speed = 1e-3, rest = 0.25;
    rig a, twin;
    rig_make(&a, speed, rest);
    rig_make(&twin, 0.0, 0.0);
    const int n3 = 3 * a.m.n_particles;
    double timer = 0.0;
    int expected = -1, fell = -1;
    for (int f = 1; f <= 200 && fell < 0; ++f) {
        wc_step_stats st = step(a.s), tw = step(twin.s);
        CHECK(!tw.fell_asleep && !tw.asleep);
        if (expected < 0) {
            double vmax = wc_state_max_speed(twin.s);
            timer = vmax < speed ? timer + DT : 0.0;
            if (timer >= rest) expected = f;
        }
        if (st.fell_asleep) fell = f;
        else CHECK(same_x(a.s, twin.s->x) && memcmp(a.s->v, twin.s->v, sizeof(double) * (size_t)n3) == 0);
        CHECK(!st.asleep);
    }
    printf("  asleep after frame %d (expected %d)\n", fell, expected);
    CHECK(expected > 0);
    CHECK_EQ_INT(fell, expected);
    CHECK(same_x(a.s, twin.s->x));
    CHECK(a.s->asleep);
    for (int k = 0; k < n3; ++k) CHECK(a.s->v[k] == 0.0);
    /* asleep: nothing moves, time runs as the twin's */
    double* x = malloc(sizeof(double) * (size_t)n3);
    memcpy(x, a.s->x, sizeof(double) * (size_t)n3);
    for (int f = 0; f < 30; ++f) {
        wc_step_stats st = step(a.s);
        step(twin.s);
        CHECK(st.asleep && !st.fell_asleep && !st.woke);
        CHECK_EQ_INT(st.substeps, 0);
        CHECK_EQ_INT(st.iterations, 0);
        CHECK(st.kinetic_energy == 0.0);
        CHECK_NEAR(st.max_strain, wc_max_stretch_strain(&a.m, x), 0.0);
    }
    CHECK(same_x(a.s, x));
    for (int k = 0; k < n3; ++k) CHECK(a.s->v[k] == 0.0);
    CHECK(a.s->time == twin.s->time);
    CHECK(a.s->frame == twin.s->frame);
    /* the twin, which never sleeps, stayed within sleep_speed x elapsed time of the sleeping one */
    double dmax = 0.0;
    for (int i = 0; i < a.m.n_particles; ++i) {
        double dd[3];
        v3_sub(dd, a.s->x + 3 * i, twin.s->x + 3 * i);
        if (v3_norm(dd) > dmax) dmax = v3_norm(dd);
    }
    CHECK(dmax <= speed * 30 * DT);
    free(x);
    rig_free(&a);
    rig_free(&twin);
}

/* A fixed substep length: asleep, time and the accumulator advance exactly as when awake. */
static void test_sleep_time_fixed_substeps(void) {
    rig a;
    rig_make(&a, 1e-3, 0.1);
    a.s->def.substep_dt = 1.0 / 150.0; /* 2.5 substeps a frame: the accumulator carries */
    run_to_sleep(a.s);
    double t = a.s->time, acc = a.s->accumulator;
    for (int f = 0; f < 7; ++f) step(a.s);
    double h = a.s->def.substep_dt;
    for (int f = 0; f < 7; ++f) {   /* the loop of wc_step_frame, done here */
        acc += DT;
        while (acc >= h * (1.0 - 1e-9)) {
            acc -= h;
            t += h;
        }
        if (acc < 0) acc = 0;
    }
    CHECK(a.s->time == t && a.s->accumulator == acc);
    rig_free(&a);
}

typedef enum wake_kind { W_PIN, W_COLLIDER, W_GRAVITY, W_WIND, W_DRAG, W_POSITIONS, W_WAKE, W_COUNT } wake_kind;
static const char* const wake_name[W_COUNT] = {"pin", "collider", "gravity", "wind", "drag", "set_positions", "wake"};

/* From asleep: the same inputs keep it asleep; each change wakes it and the frame is simulated. */
static void test_wake_rules(void) {
    for (int w = 0; w < W_COUNT; ++w) {
        rig a;
        rig_make(&a, 1e-3, 0.25);
        wc_diag d = {0};
        wc_collider far;
        memset(&far, 0, sizeof far);
        far.type = WC_COLLIDER_SPHERE;
        v3_set(far.center, 0.0, -50.0, 0.0);
        far.radius = 1.0;
        CHECK_EQ_INT(wc_state_set_colliders(a.s, &far, 1, &d), WC_OK);
        run_to_sleep(a.s);
        const int n3 = 3 * a.m.n_particles;
        double* x = malloc(sizeof(double) * (size_t)n3);
        memcpy(x, a.s->x, sizeof(double) * (size_t)n3);
        /* unchanged inputs, set again as a host does every frame: still asleep */
        CHECK_EQ_INT(wc_state_set_pins(a.s, a.pins, 2, &d), WC_OK);
        CHECK_EQ_INT(wc_state_set_colliders(a.s, &far, 1, &d), WC_OK);
        a.s->def.gravity[1] = -9.81;
        CHECK(step(a.s).asleep);
        CHECK(same_x(a.s, x));
        /* the change */
        int pinned = a.pins[0].particle;
        switch ((wake_kind)w) {
        case W_PIN:
            a.pins[0].target[0] -= 0.01;
            CHECK_EQ_INT(wc_state_set_pins(a.s, a.pins, 2, &d), WC_OK);
            break;
        case W_COLLIDER:   /* into the sheet (the plane z = 0), from behind */
            v3_set(far.center, 0.0, 0.75, -0.08);
            far.radius = 0.1;
            CHECK_EQ_INT(wc_state_set_colliders(a.s, &far, 1, &d), WC_OK);
            break;
        case W_GRAVITY: a.s->def.gravity[0] = 3.0; break;
        case W_WIND: v3_set(a.s->def.air.wind, 0.0, 0.0, 5.0); break;
        case W_DRAG: a.s->def.air.normal_drag *= 2.0; break;
        case W_POSITIONS: {
            double* y = malloc(sizeof(double) * (size_t)n3);
            memcpy(y, x, sizeof(double) * (size_t)n3);
            for (int i = 0; i < a.m.n_particles; ++i) y[3 * i + 2] += 0.01 * (y[3 * i + 1] - 1.0);
            CHECK_EQ_INT(wc_state_set_positions(a.s, y, NULL, &d), WC_OK);
            memcpy(x, y, sizeof(double) * (size_t)n3);
            free(y);
            break;
        }
        case W_WAKE: wc_state_wake(a.s); break;
        default: break;
        }
        CHECK(!a.s->asleep || w == W_GRAVITY || w == W_WIND || w == W_DRAG); /* def fields: seen by the step */
        wc_step_stats st = step(a.s);
        CHECK(st.woke && !st.asleep);
        CHECK(st.substeps > 0);
        CHECK(!a.s->asleep);
        double dmax = 0.0, dsum[3] = {0, 0, 0};
        for (int i = 0; i < a.m.n_particles; ++i) {
            double dd[3];
            v3_sub(dd, a.s->x + 3 * i, x + 3 * i);
            v3_add(dsum, dsum, dd);
            if (v3_norm(dd) > dmax) dmax = v3_norm(dd);
        }
        /* the physics of the change, independently */
        if (w == W_DRAG || w == W_WAKE) {
            /* at rest without wind drag is no force, and a bare wake changes nothing: the cloth
               stays where it slept (within the motion sleep_speed allows) */
            CHECK(dmax <= 1e-3 * DT);
        } else {
            CHECK(dmax > 1e-6);
        }
        if (w == W_PIN) CHECK(a.s->x[3 * pinned] == a.pins[0].target[0]);
        if (w == W_GRAVITY) CHECK(dsum[0] > 0.0);                   /* pushed along +x */
        if (w == W_WIND || w == W_COLLIDER) CHECK(dsum[2] > 0.0);   /* blown / pushed along +z */
        /* the next frame is not woken again */
        CHECK(!step(a.s).woke);
        printf("  %-14s woke it\n", wake_name[w]);
        free(x);
        rig_free(&a);
    }
}

/* sleep_speed 0 never sleeps; pins that keep moving never let it sleep. */
static void test_never_sleeps(void) {
    rig a, b;
    rig_make(&a, 0.0, 0.25);
    rig_make(&b, 1e-3, 0.25);
    for (int f = 1; f <= 120; ++f) {
        CHECK(!step(a.s).fell_asleep);
        /* the corners move slowly on circles of 2 cm (about 0.06 m/s) */
        wc_pin p[2];
        memcpy(p, b.pins, sizeof p);
        for (int k = 0; k < 2; ++k) {
            p[k].target[0] += 0.02 * sin(3.0 * f * DT);
            p[k].target[2] += 0.02 * (1.0 - cos(3.0 * f * DT));
        }
        wc_diag d = {0};
        CHECK_EQ_INT(wc_state_set_pins(b.s, p, 2, &d), WC_OK);
        CHECK(!step(b.s).fell_asleep);
    }
    CHECK(!a.s->asleep && !b.s->asleep);
    rig_free(&a);
    rig_free(&b);
}

/* wc_state_set_sleep (snapshots): asleep zeroes v; awake restarts nothing but what it is given. */
static void test_set_sleep(void) {
    rig a;
    rig_make(&a, 1e-3, 10.0);
    for (int f = 0; f < 20; ++f) step(a.s);
    CHECK(!a.s->asleep && a.s->rest_time > 0.0);
    double x0 = a.s->x[0];
    wc_state_set_sleep(a.s, 1, 0.75);
    CHECK(a.s->asleep && a.s->rest_time == 0.75);
    for (int k = 0; k < 3 * a.m.n_particles; ++k) CHECK(a.s->v[k] == 0.0);
    CHECK(step(a.s).asleep && a.s->x[0] == x0);
    wc_state_set_sleep(a.s, 0, 0.5);
    CHECK(!a.s->asleep && a.s->rest_time == 0.5);
    wc_step_stats st = step(a.s);
    CHECK(st.woke && st.substeps == 1);
    CHECK_NEAR(a.s->rest_time, 0.5 + DT, 1e-12);
    rig_free(&a);
}

static void test_bad_def(void) {
    wc_model m;
    CHECK(ts_sheet(&m, 3, 0.5, 1.0, 1, 1.0));
    const double bad[3] = {-1e-3, NAN, INFINITY};
    for (int k = 0; k < 6; ++k) {
        wc_sim_def sd = wc_default_sim_def();
        if (k < 3) sd.sleep_speed = bad[k];
        else sd.sleep_time = bad[k - 3];
        wc_state* s = (wc_state*)&m;
        wc_diag d = {0};
        CHECK_EQ_INT(wc_state_create(&s, &m, &sd, NULL, &d), WC_ERROR_INVALID_ARGUMENT);
        CHECK(s == NULL);
        CHECK(strstr(d.message, k < 3 ? "sleep_speed" : "sleep_time") != NULL);
    }
    wc_sim_def sd = wc_default_sim_def();
    CHECK(sd.sleep_speed == 1e-3 && sd.sleep_time == 0.5);
    wc_model_free(&m);
}

int main(void) {
    RUN_TEST(test_falls_asleep);
    RUN_TEST(test_sleep_time_fixed_substeps);
    RUN_TEST(test_wake_rules);
    RUN_TEST(test_never_sleeps);
    RUN_TEST(test_set_sleep);
    RUN_TEST(test_bad_def);
    return TEST_SUMMARY();
}
