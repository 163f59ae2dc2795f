/* Results in the host's vertex order: positions and smooth normals per host vertex (welded twins
 * read their shared particle, so they report identical values), triangles as host vertex
 * indices (each particle's first host vertex, model.particle_to_host).
 *
 * Normals: per particle, the sum over its triangles of (x_b - x_a) x (x_c - x_a) (twice the
 * area times the unit normal: area-weighted), normalised; zero where that sum is zero.
 * Spaces: WORLD as simulated; OBJECT = T^-1 x / unit_scale with T the last object transform
 * applied (exact affine inverse) and unit_scale the metres per mesh unit applied at import, so
 * OBJECT positions compare directly with the host's mesh; normals are rotated back by T^-1 and
 * renormalised. A host vertex used by no polygon has no particle: it is reported at its rest
 * position moved rigidly with the object, with a zero normal.
 * The positions come from the backend (its output operation); these are the CPU's, computed
 * from the state, and the range check every frame and creation make on them. */
#include <math.h>
#include <string.h>
#include "cloth_internal.h"
#include "vec3.h"

static void particle_normals(const wc_cloth* c, double* nrm) {
    const wc_model* m = &c->model;
    const double* x = c->state->x;
    memset(nrm, 0, 3 * (size_t)m->n_particles * sizeof(double));
    for (int t = 0; t < m->n_tris; ++t) {
        const int* tri = m->tris + 3 * t;
        double e1[3], e2[3], n[3];
        v3_sub(e1, x + 3 * tri[1], x + 3 * tri[0]);
        v3_sub(e2, x + 3 * tri[2], x + 3 * tri[0]);
        v3_cross(n, e1, e2);
        for (int k = 0; k < 3; ++k) v3_add(nrm + 3 * tri[k], nrm + 3 * tri[k], n);
    }
    for (int i = 0; i < m->n_particles; ++i) {
        double len = v3_norm(nrm + 3 * i);
        if (len > 0.0) v3_scale(nrm + 3 * i, nrm + 3 * i, 1.0 / len);
    }
}

int wc_cloth_outputs_in_range(const wc_cloth* c, const wc_xform* T, int* vertex, double* value) {
    wc_xform inv;
    wc_xform_inverse(T, &inv);
    const double s = 1.0 / c->settings.unit_scale;
    const int* h2p = c->model.host_to_particle;
    for (int v = 0; v < c->n_host; ++v) {
        const int p = h2p[v];
        double w[3], o[3];
        if (p < 0) {
            wc_xform_point(T, c->host_rest + 3 * v, w);
            v3_copy(o, c->host_rest + 3 * v);
        } else {
            v3_copy(w, c->state->x + 3 * p);
            wc_xform_point(&inv, w, o);
        }
        v3_scale(o, o, s);
        for (int k = 0; k < 6; ++k) {
            const double x = k < 3 ? w[k] : o[k - 3];
            if (!(fabs(x) <= WC_CLOTH_MAX_COORD)) {
                *vertex = v;
                *value = x;
                return 0;
            }
        }
    }
    return 1;
}

int wc_cloth_outputs_bounded(const wc_cloth* c, const wc_xform* T, double M) {
    if (!isfinite(M)) return 0;
    /* |world coordinate| <= M; |object coordinate| <= (sum_j |inv.R_ij| M + |inv.t_i|) / scale */
    wc_xform inv;
    wc_xform_inverse(T, &inv);
    double bound = M;
    for (int i = 0; i < 3; ++i) {
        double b = fabs(inv.t[i]);
        for (int j = 0; j < 3; ++j) b += fabs(inv.R[3 * i + j]) * M;
        b /= c->settings.unit_scale;
        if (!(b <= bound)) bound = b;
    }
    /* host vertices without a particle: rest moved with the object */
    for (int v = 0; v < c->n_host; ++v) {
        if (c->model.host_to_particle[v] >= 0) continue;
        double w[3];
        wc_xform_point(T, c->host_rest + 3 * v, w);
        for (int k = 0; k < 3; ++k) {
            double o = c->host_rest[3 * v + k] / c->settings.unit_scale;
            if (!(fabs(w[k]) <= WC_CLOTH_MAX_COORD) || !(fabs(o) <= WC_CLOTH_MAX_COORD)) return 0;
        }
    }
    return bound <= WC_CLOTH_MAX_COORD;
}

void wc_cloth_host_vertices(wc_cloth* c, const wc_output_request* r) {
    const int object = r->to_object;
    wc_xform inv;
    wc_xform_inverse(&c->object, &inv);
    const double s = 1.0 / c->settings.unit_scale;
    const double* x = c->state->x;
    const int* h2p = c->model.host_to_particle;
    if (r->normals) particle_normals(c, c->scratch);
    for (int v = 0; v < c->n_host; ++v) {
        int p = h2p[v];
        double pos[3], nrm[3] = {0.0, 0.0, 0.0};
        if (p < 0) {
            if (object) v3_scale(pos, c->host_rest + 3 * v, s);
            else wc_xform_point(&c->object, c->host_rest + 3 * v, pos);
        } else {
            if (object) {
                wc_xform_point(&inv, x + 3 * p, pos);
                v3_scale(pos, pos, s);
            } else {
                v3_copy(pos, x + 3 * p);
            }
            if (r->normals) {
                v3_copy(nrm, c->scratch + 3 * p);
                if (object) {
                    wc_xform_vector(&inv, nrm, nrm);
                    double len = v3_norm(nrm);
                    if (len > 0.0) v3_scale(nrm, nrm, 1.0 / len);
                }
            }
        }
        for (int k = 0; k < 3; ++k) {
            if (r->positions) r->positions[3 * v + k] = (float)pos[k];
            if (r->normals) r->normals[3 * v + k] = (float)nrm[k];
        }
    }
}

wc_status wc_cloth_vertices(wc_cloth* c, int to_object, float* positions, float* normals, wc_diag* d) {
    wc_output_request r;
    memset(&r, 0, sizeof r);
    r.to_object = to_object;
    r.positions = positions;
    r.normals = normals;
    wc_status st = c->backend->begin(c->device, d);
    if (st != WC_OK) return st;
    st = c->backend->output(c, &r, d);
    c->backend->end(c->device);
    return st;
}

wc_status wc_cloth_write_gl_buffers(wc_cloth* c, const wc_output_request* r, wc_diag* d) {
    return c->backend->write_gl(c, r, d);
}

void wc_cloth_triangles(const wc_cloth* c, int* indices) {
    const wc_model* m = &c->model;
    for (int k = 0; k < 3 * m->n_tris; ++k) indices[k] = m->particle_to_host[m->tris[k]];
}

void wc_cloth_backend_stats(const wc_cloth* c, wc_backend_stats* out) {
    memset(out, 0, sizeof *out);
    c->backend->stats(c, out);
}
