/* Attachments: host vertices pinned to host transforms (bones).
 *
 * Binding: each attachment's host vertices map to particles (duplicates and welded twins merge
 * into one pin; a particle in two attachments is an error; a vertex referenced by no polygon has
 * no particle and is an error). The pinned particle's current world position x is expressed in
 * the bind transform's frame: local = B^-1 x (exact affine inverse), so B local = x.
 * Every frame: target = A_i local with A_i the attachment's transform at the end of the frame,
 * free axis = A_i's rotation of the bone-local axis (renormalised). The targets go to
 * wc_state_set_pins, whose "an already pinned particle keeps moving from its old target"
 * makes the pin move linearly across the frame. A new binding changes the model's fingerprint
 * and the snapshot's size (cloth_snapshot.c): the backup is reallocated with it. */
#include <string.h>
#include "cloth_internal.h"
#include "vec3.h"

void wc_cloth_pin_targets(const wc_cloth* c, const wc_xform* bones) {
    for (int k = 0; k < c->n_pins; ++k) {
        int a = c->pin_attachment[k];
        wc_pin* p = &c->pins[k];
        p->particle = c->pin_particle[k];
        wc_xform_point(&bones[a], c->pin_local + 3 * k, p->target);
        const double* axis = c->attachments[a].free_axis;
        if (v3_norm(axis) == 0.0) {
            v3_zero(p->free_axis);
        } else {
            double w[3];
            wc_xform_vector(&bones[a], axis, w);
            v3_scale(p->free_axis, w, 1.0 / v3_norm(w));
        }
    }
}

/* The vertex checks, all vertices in range first; mark[] is all -1 on entry and on return.
 * *total receives the number of distinct pinned particles. */
static wc_status count_pins(wc_cloth* c, const wc_cloth_attachment_def* a, int n, const char* what, int* total,
                            wc_diag* d) {
    for (int i = 0; i < n; ++i)
        for (int k = 0; k < a[i].n_vertices; ++k)
            if (a[i].vertices[k] < 0 || a[i].vertices[k] >= c->n_host)
                return wc_fail(d, WC_ERROR_OUT_OF_RANGE, "%s[%d].vertices[%d] = %d is outside [0, %d)", what, i, k,
                               a[i].vertices[k], c->n_host);
    int* mark = c->mark;
    wc_status st = WC_OK;
    *total = 0;
    for (int i = 0; i < n && st == WC_OK; ++i)
        for (int k = 0; k < a[i].n_vertices && st == WC_OK; ++k) {
            int v = a[i].vertices[k], p = c->model.host_to_particle[v];
            if (p < 0) {
                st = wc_fail(d, WC_ERROR_INVALID_ARGUMENT, "%s[%d].vertices[%d] = %d is used by no polygon (no particle)",
                             what, i, k, v);
            } else if (mark[p] == i) {
                continue;   /* duplicate or welded twin within the attachment */
            } else if (mark[p] >= 0) {
                st = wc_fail(d, WC_ERROR_INVALID_ARGUMENT,
                             "%s[%d].vertices[%d] = %d (particle %d) is already pinned by %s[%d]", what, i, k, v, p, what,
                             mark[p]);
            } else {
                mark[p] = i;
                ++*total;
            }
        }
    for (int i = 0; i < c->model.n_particles; ++i) mark[i] = -1;
    return st;
}

/* The new binding's pins from the state's positions (arrays allocated for it). */
static void bind_pins(wc_cloth* c, const wc_cloth_attachment_def* a, int n) {
    const double* x = c->state->x;
    int* mark = c->mark;
    int k = 0;
    for (int i = 0; i < n; ++i) {
        wc_cloth_attachment* at = &c->attachments[i];
        at->first_pin = k;
        wc_xform_from_floats(&c->attachment_xf[i], a[i].bind_transform);
        wc_xform inv;
        wc_xform_inverse(&c->attachment_xf[i], &inv);
        double axis[3] = {a[i].free_axis[0], a[i].free_axis[1], a[i].free_axis[2]};
        double len = v3_norm(axis);
        if (len > 0.0) v3_scale(at->free_axis, axis, 1.0 / len);
        for (int j = 0; j < a[i].n_vertices; ++j) {
            int p = c->model.host_to_particle[a[i].vertices[j]];
            if (mark[p] == i) continue;
            mark[p] = i;
            c->pin_particle[k] = p;
            c->pin_attachment[k] = i;
            wc_xform_point(&inv, x + 3 * p, c->pin_local + 3 * k);
            ++k;
        }
        at->n_pins = k - at->first_pin;
    }
    for (int i = 0; i < c->model.n_particles; ++i) mark[i] = -1;
}

wc_status wc_cloth_bind(wc_cloth* c, const wc_cloth_attachment_def* a, int n, const char* what, wc_diag* d) {
    int total = 0;
    wc_status st = count_pins(c, a, n, what, &total, d);
    if (st != WC_OK) return st;

    /* new arrays; the old ones are kept until everything succeeded */
    wc_cloth old = *c;
    wc_allocator* A = &c->alloc;
    c->attachments = WC_NEW(A, wc_cloth_attachment, (size_t)n + 1);
    c->attachment_xf = WC_NEW(A, wc_xform, (size_t)n + 1);
    c->attachment_next = WC_NEW(A, wc_xform, (size_t)n + 1);
    c->pin_particle = WC_NEW(A, int, (size_t)total + 1);
    c->pin_attachment = WC_NEW(A, int, (size_t)total + 1);
    c->pin_local = WC_NEW(A, double, 3 * (size_t)total + 3);
    c->pins = WC_NEW(A, wc_pin, (size_t)total + 1);
    c->n_attachments = n;
    c->n_pins = total;
    c->snapshot_size = wc_cloth_snapshot_measure(c);
    c->backup = WC_NEW(A, unsigned char, c->snapshot_size);
    void* fresh[] = {c->attachments, c->attachment_xf, c->attachment_next, c->pin_particle, c->pin_attachment,
                     c->pin_local, c->pins, c->backup};
    int ok = 1;
    for (size_t i = 0; i < sizeof fresh / sizeof fresh[0]; ++i) ok = ok && fresh[i];
    if (ok) {
        bind_pins(c, a, n);
        wc_cloth_pin_targets(c, c->attachment_xf);
        st = wc_state_set_pins(c->state, c->pins, total, d);
        if (st != WC_OK) wc_diag_prefix(d, st, "%s: ", what);
    } else {
        st = wc_fail(d, WC_ERROR_OUT_OF_MEMORY, "out of memory (%d pins)", total);
    }
    if (st != WC_OK) {
        for (size_t i = 0; i < sizeof fresh / sizeof fresh[0]; ++i) wc_free(A, fresh[i]);
        *c = old;
        return st;
    }
    void* stale[] = {old.attachments, old.attachment_xf, old.attachment_next, old.pin_particle, old.pin_attachment,
                     old.pin_local, old.pins, old.backup};
    for (size_t i = 0; i < sizeof stale / sizeof stale[0]; ++i) wc_free(A, stale[i]);
    c->model_hash = wc_cloth_fingerprint(c);
    return WC_OK;
}

wc_status wc_cloth_set_attachments(wc_cloth* c, const wc_cloth_attachment_def* a, int n, const char* what,
                                   wc_diag* d) {
    if (n < 0) return wc_fail(d, WC_ERROR_INVALID_ARGUMENT, "n = %d is negative", n);
    if (n > 0 && !a) return wc_fail(d, WC_ERROR_INVALID_ARGUMENT, "%s is NULL with n = %d", what, n);
    /* binding reads the current positions: a device's mirror is refreshed first */
    wc_status st = wc_cloth_download(c, d);
    return st == WC_OK ? wc_cloth_bind(c, a, n, what, d) : st;
}
