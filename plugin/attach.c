/* Attachments: host vertices pinned to host transforms (bones).
 *
 * Binding: each attachment's host vertices map to particles (duplicates and welded twins merge
 * into one pin; a particle in two attachments is an error; a vertex referenced by no polygon has
 * no particle and is an error). The pinned particle's current world position x is expressed in
 * the bind transform's frame: local = B^-1 x (exact affine inverse), so B local = x.
 * Every frame: target = A_i local with A_i the attachment's transform at the end of the frame,
 * free axis = A_i's rotation of the bone-local axis (renormalised). The targets go to
 * wc_state_set_pins, whose "an already pinned particle keeps moving from its old target"
 * makes the pin move linearly across the frame. */
#include <string.h>
#include "api_internal.h"
#include "vec3.h"

void wa_pin_targets(const wa_cloth* c, const wa_xform* bones) {
    for (int k = 0; k < c->n_pins; ++k) {
        int a = c->pin_attachment[k];
        wc_pin* p = &c->pins[k];
        p->particle = c->pin_particle[k];
        wa_xform_point(&bones[a], c->pin_local + 3 * k, p->target);
        const double* axis = c->attachments[a].free_axis;
        if (v3_norm(axis) == 0.0) {
            v3_zero(p->free_axis);
        } else {
            double w[3];
            wa_xform_vector(&bones[a], axis, w);
            v3_scale(p->free_axis, w, 1.0 / v3_norm(w));
        }
    }
}

/* The particle checks (pass 1); mark[] is all -1 on entry and on return. Returns the number of
 * distinct pinned particles, or -1 after recording the failure. */
static int count_pins(weft_context* ctx, wa_cloth* c, const weft_attachment_def* a, int n, const char* fn,
                      const char* prefix) {
    int* mark = c->mark;
    int total = 0, bad = 0;
    for (int i = 0; i < n && !bad; ++i)
        for (int k = 0; k < a[i].n_vertices && !bad; ++k) {
            int v = a[i].vertices[k], p = c->model.host_to_particle[v];
            if (p < 0) {
                wa_fail(ctx, WEFT_ERROR_INVALID_ARGUMENT, "%s: %s[%d].vertices[%d] = %d is used by no polygon (no particle)",
                        fn, prefix, i, k, v);
                bad = 1;
            } else if (mark[p] == i) {
                continue;   /* duplicate or welded twin within the attachment */
            } else if (mark[p] >= 0) {
                wa_fail(ctx, WEFT_ERROR_INVALID_ARGUMENT,
                        "%s: %s[%d].vertices[%d] = %d (particle %d) is already pinned by %s[%d]", fn, prefix, i, k, v, p,
                        prefix, mark[p]);
                bad = 1;
            } else {
                mark[p] = i;
                ++total;
            }
        }
    for (int i = 0; i < c->model.n_particles; ++i) mark[i] = -1;
    return bad ? -1 : total;
}

weft_status wa_bind_attachments(weft_context* ctx, wa_cloth* c, const weft_attachment_def* a, int n, const char* fn,
                                const char* prefix) {
    char msg[400];
    weft_status st = wa_validate_attachments(a, n, c->n_host, prefix, msg, sizeof msg);
    if (st != WEFT_OK) return wa_fail(ctx, st, "%s: %s", fn, msg);
    int total = count_pins(ctx, c, a, n, fn, prefix);
    if (total < 0) return ctx->last_status;

    /* new arrays; the old ones are kept until everything succeeded */
    wa_cloth old = *c;
    wc_allocator* A = &ctx->alloc;
    c->attachments = WC_NEW(A, wa_attachment, (size_t)n + 1);
    c->attachment_xf = WC_NEW(A, wa_xform, (size_t)n + 1);
    c->attachment_next = WC_NEW(A, wa_xform, (size_t)n + 1);
    c->pin_particle = WC_NEW(A, int, (size_t)total + 1);
    c->pin_attachment = WC_NEW(A, int, (size_t)total + 1);
    c->pin_local = WC_NEW(A, double, 3 * (size_t)total + 3);
    c->pins = WC_NEW(A, wc_pin, (size_t)total + 1);
    c->n_attachments = n;
    c->n_pins = total;
    c->snapshot_size = wa_snapshot_size(c);
    c->backup = WC_NEW(A, unsigned char, c->snapshot_size);
    void* fresh[] = {c->attachments, c->attachment_xf, c->attachment_next, c->pin_particle, c->pin_attachment,
                     c->pin_local, c->pins, c->backup};
    int ok = 1;
    for (size_t i = 0; i < sizeof fresh / sizeof fresh[0]; ++i) ok = ok && fresh[i];
    if (ok) {
        const double* x = c->state->x;
        int* mark = c->mark;
        int k = 0;
        for (int i = 0; i < n; ++i) {
            wa_attachment* at = &c->attachments[i];
            at->first_pin = k;
            wa_xform_from_floats(&c->attachment_xf[i], a[i].bind_transform);
            wa_xform inv;
            wa_xform_inverse(&c->attachment_xf[i], &inv);
            double axis[3] = {a[i].free_axis[0], a[i].free_axis[1], a[i].free_axis[2]};
            double len = v3_norm(axis);
            if (len > 0.0) v3_scale(at->free_axis, axis, 1.0 / len);
            for (int j = 0; j < a[i].n_vertices; ++j) {
                int p = c->model.host_to_particle[a[i].vertices[j]];
                if (mark[p] == i) continue;
                mark[p] = i;
                c->pin_particle[k] = p;
                c->pin_attachment[k] = i;
                wa_xform_point(&inv, x + 3 * p, c->pin_local + 3 * k);
                ++k;
            }
            at->n_pins = k - at->first_pin;
        }
        for (int i = 0; i < c->model.n_particles; ++i) mark[i] = -1;
        wa_pin_targets(c, c->attachment_xf);
        wc_diag d = wa_core_diag(ctx);
        st = wa_status(wc_state_set_pins(c->state, c->pins, total, &d));
        if (st != WEFT_OK) wa_fail(ctx, st, "%s: %s: %s", fn, prefix, d.message);
    } else {
        st = wa_fail(ctx, WEFT_ERROR_OUT_OF_MEMORY, "%s: out of memory (%d pins)", fn, total);
    }
    if (st != WEFT_OK) {
        for (size_t i = 0; i < sizeof fresh / sizeof fresh[0]; ++i) wc_free(A, fresh[i]);
        *c = old;
        return st;
    }
    void* stale[] = {old.attachments, old.attachment_xf, old.attachment_next, old.pin_particle, old.pin_attachment,
                     old.pin_local, old.pins, old.backup};
    for (size_t i = 0; i < sizeof stale / sizeof stale[0]; ++i) wc_free(A, stale[i]);
    c->model_hash = wa_model_hash(c);
    return WEFT_OK;
}
