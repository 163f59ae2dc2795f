/* The energies of a cloth's current state (state.h's sums), its mass and its centre of mass; a
 * device's particles are read back first. */
#include "cloth_internal.h"

wc_status wc_cloth_energy_of(wc_cloth* c, wc_cloth_energy* out, wc_diag* d) {
    wc_status st = wc_cloth_download(c, d);
    if (st != WC_OK) return st;
    const wc_state* s = c->state;
    const wc_model* m = &c->model;
    wc_cloth_energy e = {0};
    double elastic_and_kinetic = 0.0;
    const double total = wc_state_total_energy(s, &elastic_and_kinetic);
    e.kinetic = wc_state_kinetic_energy(s);
    e.elastic = elastic_and_kinetic - e.kinetic;
    e.gravity = total - elastic_and_kinetic;
    e.mass = s->total_mass;
    for (int i = 0; i < m->n_particles; ++i)
        for (int k = 0; k < 3; ++k) e.center_of_mass[k] += m->mass[i] * s->x[3 * i + k];
    if (e.mass > 0)
        for (int k = 0; k < 3; ++k) e.center_of_mass[k] /= e.mass;
    *out = e;
    return WC_OK;
}
