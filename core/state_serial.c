/* The state's snapshot walkers (state_serial.h). */
#include "state_serial.h"
#include "amg.h"

void wc_state_serial(wc_state* s, wc_serial* k) {
    size_t n = (size_t)s->model->n_particles, n3 = 3 * n * sizeof(double);
    wc_serial_bytes(k, &s->time, sizeof s->time);
    wc_serial_bytes(k, &s->accumulator, sizeof s->accumulator);
    wc_serial_i64(k, &s->frame);
    if (!k->skip_mirror) {
        wc_serial_bytes(k, s->x, n3);
        wc_serial_bytes(k, s->v, n3);
        wc_serial_bytes(k, s->dv, n3);
    }
    wc_serial_i32(k, &s->n_pins);
    for (int i = 0; i < s->n_pins; ++i) {
        wc_pin* p = &s->pins[i];
        wc_serial_i32(k, &p->particle);
        wc_serial_bytes(k, p->target, sizeof p->target);
        wc_serial_bytes(k, p->free_axis, sizeof p->free_axis);
    }
    wc_serial_bytes(k, s->pin_from, 3 * (size_t)s->n_pins * sizeof(double));
    for (int i = 0; i < s->n_colliders; ++i) {
        wc_collider* q = &s->colliders[i];
        wc_serial_i32(k, &q->type);
        wc_serial_bytes(k, q->normal, sizeof q->normal);
        wc_serial_bytes(k, &q->offset, sizeof q->offset);
        wc_serial_bytes(k, q->center, sizeof q->center);
        wc_serial_bytes(k, q->a, sizeof q->a);
        wc_serial_bytes(k, q->b, sizeof q->b);
        wc_serial_bytes(k, &q->radius, sizeof q->radius);
        wc_serial_bytes(k, &q->thickness, sizeof q->thickness);
        wc_serial_bytes(k, &q->friction, sizeof q->friction);
        wc_serial_bytes(k, q->velocity, sizeof q->velocity);
    }
    if (!k->skip_mirror) {
        wc_serial_bytes(k, s->contacts.collider, 2 * n * sizeof(int));
        wc_serial_bytes(k, s->contacts.normal, 6 * n * sizeof(double));
        wc_serial_bytes(k, s->contacts.released, n);
    }
    wc_serial_i32(k, &s->contacts.active);
    wc_serial_bytes(k, s->def.air.wind, sizeof s->def.air.wind);
}

void wc_state_serial_history(wc_state* s, wc_serial* k) {
    double rho = 0.0;
    int rho_valid = wc_solver_rho_cache(s->solver, &rho);
    wc_serial_i32(k, &rho_valid);
    wc_serial_bytes(k, &rho, sizeof rho);
    if (wc_serial_reading(k)) wc_solver_set_rho_cache(s->solver, rho_valid, rho);
    wc_amg_bounds eb; /* the multigrid's carried estimates (amg.h): 3 x 4 + 12 x 8 bytes */
    wc_solver_bounds_get(s->solver, &eb);
    wc_serial_i32(k, &eb.valid);
    wc_serial_i32(k, &eb.age);
    int terms = (int)eb.terms;
    wc_serial_i32(k, &terms);
    eb.terms = (unsigned)terms;
    wc_serial_bytes(k, eb.est, sizeof eb.est);
    if (wc_serial_reading(k)) wc_solver_bounds_set(s->solver, &eb);
    int asleep = s->asleep;
    double rest_time = s->rest_time;
    wc_serial_i32(k, &asleep);
    wc_serial_bytes(k, &rest_time, sizeof rest_time);
    if (wc_serial_reading(k)) wc_state_set_sleep(s, asleep != 0, rest_time);
    wc_serial_i32(k, &s->hist_valid);
    wc_serial_bytes(k, &s->hist_h, sizeof s->hist_h);
    s->hist_valid = s->hist_valid != 0;
    if (!k->skip_mirror) {
        size_t n3 = 3 * (size_t)s->model->n_particles * sizeof(double);
        wc_serial_bytes(k, s->x_prev, n3);
        wc_serial_bytes(k, s->v_prev, n3);
    }
}
