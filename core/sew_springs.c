/* Seams -> WC_SPRING_SEAM springs (the decomposition in sew.h): a seam (p, q0, q1, t) gives pair
 * springs (p, q0) weight 1-t, (p, q1) weight t, (q0, q1) weight -t(1-t) (a vertex-to-vertex seam
 * only (p, q0) weight 1); springs on the same pair are merged, weights summed. Host pairs (the
 * last def->n_seam_pairs seams) are not merged: each is one spring of weight 1 whose rest field
 * holds the pair's start distance, where its rest-length ramp starts (sew.h). */
#include <math.h>
#include <string.h>
#include "model.h"
#include "sort.h"

typedef struct pair_w {
    int a, b;
    double w;
} pair_w;

static void add_pair(pair_w* pw, int* n, int a, int b, double w) {
    if (w == 0.0 || a == b) return;
    pw[*n].a = a < b ? a : b;
    pw[*n].b = a < b ? b : a;
    pw[*n].w = w;
    ++*n;
}

wc_status wc_model_sew(wc_model* m, const wc_model_def* def, wc_diag* diag) {
    const wc_allocator* A = &m->alloc;
    const int np = m->n_particles, npairs = def->n_seam_pairs;
    int* pa = WC_NEW(A, int, npairs + 1);
    int* pb = WC_NEW(A, int, npairs + 1);
    if (!pa || !pb) goto oom;
    for (int i = 0; i < npairs; ++i) {
        pa[i] = m->host_to_particle[def->seam_a[i]];
        pb[i] = m->host_to_particle[def->seam_b[i]];
        wc_status st = WC_OK;
        if (pa[i] < 0 || pb[i] < 0)
            st = wc_fail(diag, WC_ERROR_INVALID_ARGUMENT, "seam %d: vertex %d is in no kept triangle (no particle)", i,
                         pa[i] < 0 ? def->seam_a[i] : def->seam_b[i]);
        else if (pa[i] == pb[i])
            st = wc_fail(diag, WC_ERROR_INVALID_ARGUMENT, "seam %d: vertices %d and %d are welded into one particle", i,
                         def->seam_a[i], def->seam_b[i]);
        if (st != WC_OK) {
            wc_free(A, pa);
            wc_free(A, pb);
            return st;
        }
    }
    m->seam_close_time = def->seam_close_time;
    m->n_host_seams = npairs;
    wc_sew_input in = {np, m->rest_pos, &m->we, m->particle_component, m->n_components, def->sew_distance, npairs, pa, pb};
    if (wc_sew_find(&in, &m->seams, &m->n_seams, &m->n_panels, A) != 0) goto oom;
    wc_free(A, pa);
    wc_free(A, pb);
    pa = pb = NULL;
    if (m->n_seams == 0) {
        m->spring_type_start[WC_SPRING_SEAM + 1] = m->n_springs;
        return WC_OK;
    }

    pair_w* pw = WC_NEW(A, pair_w, 3 * (size_t)m->n_seams);
    wc_keyed* keys = WC_NEW(A, wc_keyed, 3 * (size_t)m->n_seams);
    if (!pw || !keys) {
        wc_free(A, pw);
        wc_free(A, keys);
        goto oom;
    }
    int n = 0;
    const int n_dist = m->n_seams - npairs; /* seams found by distance, then the host pairs */
    for (int i = 0; i < n_dist; ++i) {
        const wc_seam* s = &m->seams[i];
        add_pair(pw, &n, s->p, s->q0, 1.0 - s->t);
        add_pair(pw, &n, s->p, s->q1, s->t);
        add_pair(pw, &n, s->q0, s->q1, -s->t * (1.0 - s->t));
    }
    int bits = wc_bits_for((unsigned)np);
    for (int i = 0; i < n; ++i) {
        keys[i].key = ((uint64_t)pw[i].a << bits) | (uint64_t)pw[i].b;
        keys[i].val = i;
    }
    int distinct = 0;
    if (!wc_radix_sort(keys, n, 2 * bits, A)) goto oom_pw;
    for (int i = 0; i < n; ++i) distinct += i == 0 || keys[i].key != keys[i - 1].key;
    wc_spring* sp = WC_NEW(A, wc_spring, (size_t)m->n_springs + distinct + npairs);
    if (!sp) goto oom_pw;
    memcpy(sp, m->springs, (size_t)m->n_springs * sizeof(wc_spring));
    int ns = m->n_springs;
    for (int i = 0; i < n; ++i) {
        const pair_w* q = &pw[keys[i].val];
        if (i > 0 && keys[i].key == keys[i - 1].key) {
            sp[ns - 1].w += q->w;
            continue;
        }
        wc_spring s = {q->a, q->b, WC_SPRING_SEAM, 0.0, q->w};
        sp[ns++] = s;
    }
    for (int i = n_dist; i < m->n_seams; ++i) {
        const wc_seam* h = &m->seams[i];
        double d2 = 0.0;
        for (int k = 0; k < 3; ++k) {
            double e = m->rest_pos[3 * h->p + k] - m->rest_pos[3 * h->q0 + k];
            d2 += e * e;
        }
        wc_spring s = {h->p < h->q0 ? h->p : h->q0, h->p < h->q0 ? h->q0 : h->p, WC_SPRING_SEAM, sqrt(d2), 1.0};
        sp[ns++] = s;
    }
    wc_free(A, m->springs);
    m->springs = sp;
    m->n_springs = ns;
    m->spring_type_start[WC_SPRING_SEAM + 1] = ns;
    wc_free(A, pw);
    wc_free(A, keys);
    return WC_OK;
oom_pw:
    wc_free(A, pw);
    wc_free(A, keys);
oom:
    wc_free(A, pa);
    wc_free(A, pb);
    return wc_fail(diag, WC_ERROR_OUT_OF_MEMORY, "model build: out of memory while sewing (%d seams)", m->n_seams);
}
