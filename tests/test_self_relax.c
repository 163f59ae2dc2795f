/* The zones' relaxation over its due springs only (wc_self_relax_zones_due, self_zones.h) against
 * the relaxation over every stretch spring at every pass (wc_self_relax_zones):
 *  - the stage: the heap's strip folded into 8 layers, pressed together with random motions, the
 *    stage run to its end (with and without CCD impulse passes, so that zones form and grow over
 *    many detection passes) once each way from the same start: the same positions, velocities
 *    and counts (zones, corrections), bit for bit;
 *  - the function alone: random zones grown one particle set at a time on a stretched sheet, the
 *    caller marking only the zones' members after the first call: the same positions, moved
 *    particles and corrections after every call. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "check.h"
#include "heap_strip.h"
#include "self_collide.h"
#include "test_support.h"
#define TEST_RNG_SEED 0x2545F4914F6CDD1Dull
#include "test_rng.h"
#include "union_find.h"

static void test_stage_same(void) {
    wc_model m;
    wc_collider floor;
    heap_strip(&m, &floor);
    int n = m.n_particles;
    wc_self* sc = NULL;
    wc_diag d = {0};
    CHECK(wc_self_create(&sc, &m, 0.005, NULL, &d) == WC_OK);
    if (!sc) return;
    double *x0 = malloc(3 * (size_t)n * sizeof(double)), *x1 = malloc(3 * (size_t)n * sizeof(double));
    double *x[2], *v[2];
    for (int k = 0; k < 2; ++k) {
        x[k] = malloc(3 * (size_t)n * sizeof(double));
        v[k] = calloc(3 * (size_t)n, sizeof(double));
    }
    int differ = 0, zones = 0, relaxed = 0, rounds_relaxed = 0;
    for (int round = 0; round < 24; ++round) {
        heap_strip_folded(&m, x0);
        /* the layers pressed into each other (up to 12 mm) and torn sideways, some rounds fast */
        double amp = round % 3 == 0 ? 0.01 : 0.002;
        for (int i = 0; i < n; ++i)
            for (int k = 0; k < 3; ++k) {
                x0[3 * i + k] += 0.0004 * (2 * urand() - 1);
                x1[3 * i + k] = x0[3 * i + k] + amp * (2 * urand() - 1) - (k == 2 ? 0.012 * urand() : 0.0);
            }
        wc_self_stats st[2];
        for (int k = 0; k < 2; ++k) {
            sc->passes = round % 2 ? 0 : WC_SELF_PASSES;
            sc->relax_all = k;
            memset(&st[k], 0, sizeof st[k]);
            memcpy(x[k], x1, 3 * (size_t)n * sizeof(double));
            memset(v[k], 0, 3 * (size_t)n * sizeof(double));
            wc_self_begin(sc, x0);
            wc_self_resolve(sc, &m, NULL, NULL, 1.0 / 120, x[k], v[k], &st[k]);
        }
        if (memcmp(x[0], x[1], 3 * (size_t)n * sizeof(double)) || memcmp(v[0], v[1], 3 * (size_t)n * sizeof(double)) ||
            memcmp(&st[0], &st[1], sizeof st[0]))
            ++differ;
        zones += st[1].zones;
        relaxed += st[1].relaxed;
        rounds_relaxed += st[1].relaxed > 0;
    }
    printf("  24 stages: %d zones, %d spring corrections (%d stages with some); %d differ\n", zones, relaxed,
           rounds_relaxed, differ);
    CHECK_EQ_INT(differ, 0);
    CHECK(rounds_relaxed >= 4); /* the relaxation had work */
    for (int k = 0; k < 2; ++k) {
        free(x[k]);
        free(v[k]);
    }
    free(x0);
    free(x1);
    wc_self_destroy(sc);
    wc_model_free(&m);
}

/* The function alone: a 24 x 24 sheet stretched at random, zones grown over 12 calls. */
static void test_relax_calls_same(void) {
    wc_model m;
    wc_source_mesh src;
    ts_quad_grid(&src, 24, 24, 0.5, 0.5, 0);
    wc_model_def mdef = wc_default_model_def();
    wc_diag dg = {0};
    CHECK(wc_model_build(&m, &src, &mdef, NULL, &dg) == WC_OK);
    wc_source_mesh_free(&src);
    int n = m.n_particles, ns = m.spring_type_start[WC_SPRING_STRETCH + 1] - m.spring_type_start[WC_SPRING_STRETCH];
    wc_self_relax_set rs = {calloc((size_t)(ns + 63) / 64, 8), calloc((size_t)(ns + 63) / 64, 8), (ns + 63) / 64};
    double *x_old = malloc(3 * (size_t)n * sizeof(double)), *xf = malloc(3 * (size_t)n * sizeof(double));
    double *xd = malloc(3 * (size_t)n * sizeof(double)), *im = malloc((size_t)n * sizeof(double));
    unsigned char *in = calloc((size_t)n, 1), *mf = calloc((size_t)n, 1), *md = calloc((size_t)n, 1);
    int differ = 0, calls = 0, corrections = 0, left_due = 0;
    for (int round = 0; round < 8; ++round) {
        for (int i = 0; i < n; ++i) {
            for (int k = 0; k < 3; ++k) x_old[3 * i + k] = m.rest_pos[3 * i + k] + 0.004 * (2 * urand() - 1);
            im[i] = urand() < 0.05 ? 0.0 : m.inv_mass[i];
            in[i] = 0;
        }
        memcpy(xf, x_old, 3 * (size_t)n * sizeof(double));
        memcpy(xd, x_old, 3 * (size_t)n * sizeof(double));
        memset(mf, 0, (size_t)n);
        memset(md, 0, (size_t)n);
        for (int call = 0; call < 12; ++call) {
            /* a zone: a few particles around a random one joined and moved together by up to 3 cm */
            int c = (int)(urand() * n);
            double dz[3] = {0.03 * (2 * urand() - 1), 0.03 * (2 * urand() - 1), 0.03 * (2 * urand() - 1)};
            for (int i = 0; i < n; ++i) {
                double dd[3];
                v3_sub(dd, m.rest_pos + 3 * i, m.rest_pos + 3 * c);
                if (v3_norm(dd) > 0.05) continue;
                in[i] = 1;
                v3_add(xf + 3 * i, xf + 3 * i, dz);
                v3_add(xd + 3 * i, xd + 3 * i, dz);
            }
            if (call == 0) {
                memset(rs.due, 0xff, (size_t)rs.words * 8);
                if (ns & 63) rs.due[rs.words - 1] = ((uint64_t)1 << (ns & 63)) - 1;
            } else {
                for (int i = 0; i < n; ++i)
                    if (in[i]) wc_self_relax_mark(&m, &rs, i);
            }
            int passes = call % 3 ? WC_SELF_RELAX_PASSES : 2; /* some calls stop short of the fixed point */
            int cf = wc_self_relax_zones(&m, x_old, xf, in, im, WC_SELF_ZONE_STRAIN, passes, mf);
            int cd = wc_self_relax_zones_due(&m, x_old, xd, in, im, WC_SELF_ZONE_STRAIN, passes, md, &rs);
            if (cf != cd || memcmp(xf, xd, 3 * (size_t)n * sizeof(double)) || memcmp(mf, md, (size_t)n)) ++differ;
            for (int w = 0; w < rs.words; ++w) {
                CHECK(rs.next[w] == 0); /* the scratch is left clear */
                left_due += rs.due[w] != 0;
            }
            corrections += cf;
            ++calls;
        }
    }
    printf("  %d calls, %d corrections, %d due words left between calls; %d differ\n", calls, corrections, left_due,
           differ);
    CHECK_EQ_INT(differ, 0);
    CHECK(corrections > 100);
    CHECK(left_due > 0); /* some calls left springs due for the next */
    free(rs.due);
    free(rs.next);
    free(x_old);
    free(xf);
    free(xd);
    free(im);
    free(in);
    free(mf);
    free(md);
    wc_model_free(&m);
}

int main(void) {
    RUN_TEST(test_stage_same);
    RUN_TEST(test_relax_calls_same);
    return TEST_SUMMARY();
}
