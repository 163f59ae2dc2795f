/* Test helpers for the step's energy judge, shared by test_step_energy and
 * test_step_collider_work: the total energy of a state with its particles at positions x
 * (kinetic of its velocities + springs + gravity's potential, as wc_state_total_energy measures
 * it), and a wc_diag logger that counts the judge's energy rollbacks. */
#ifndef WEFT_TESTS_ENERGY_LOG_H
#define WEFT_TESTS_ENERGY_LOG_H
#include <string.h>
#include "forces.h"
#include "step.h"
#include "vec3.h"

static inline double energy_at(const wc_state* s, const double* x) {
    const wc_model* m = s->model;
    double e = wc_state_kinetic_energy(s) + wc_spring_energy(m, x);
    for (int i = 0; i < m->n_particles; ++i) e -= m->mass[i] * v3_dot(s->def.gravity, x + 3 * i);
    return e;
}

/* Collects the step's warnings: energy_rollbacks counts "total energy rose". */
typedef struct log_rec {
    int energy_rollbacks;
} log_rec;

static inline void on_log(wc_log_level level, const char* msg, void* user) {
    log_rec* r = user;
    if (level == WC_LOG_WARN && strstr(msg, "total energy rose")) ++r->energy_rollbacks;
}

#endif
