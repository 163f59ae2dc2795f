/* Benchmark (not a test): import + weld + winged edge + springs of a generated mesh of about
 * 1,000,000 triangles. Prints a Markdown table of median wall times over --runs runs.
 *
 *   bench_import [--triangles N] [--runs R] [--obj]   (--obj also times assimp reading an OBJ)
 *
 * Meshes: "tri grid" (shared vertices), "quad grid, split" (each quad its own 4 vertices, as with
 * per-quad UVs: welding has to merge 4x the vertices). */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "clock.h"
#include "model.h"
#include "sort.h"
#include "source_mesh.h"


/* n x n vertex grid; quads (split: 4 own vertices each) or two triangles per cell. Slight
 * out-of-plane waviness so that nothing is accidentally degenerate-free by symmetry. */
static int make_grid(wc_source_mesh* out, int n, int quads, int split) {
    int cells = (n - 1) * (n - 1);
    int nv = split ? 4 * cells : n * n;
    int npoly = quads ? cells : 2 * cells;
    int corners = quads ? 4 : 3;
    double* pos = malloc(sizeof(double) * 3 * (size_t)nv);
    int* sizes = malloc(sizeof(int) * (size_t)npoly);
    int* idx = malloc(sizeof(int) * (size_t)npoly * corners);
    if (!pos || !sizes || !idx) return 0;
    double h = 1.0 / (n - 1);
    int pv = 0, pp = 0, pi = 0;
    if (!split)
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i, ++pv) {
                pos[3 * pv] = i * h;
                pos[3 * pv + 1] = j * h;
                pos[3 * pv + 2] = 0.01 * sin(7.0 * i * h) * cos(5.0 * j * h);
            }
    for (int j = 0; j + 1 < n; ++j)
        for (int i = 0; i + 1 < n; ++i) {
            int gi[4] = {i, i + 1, i + 1, i}, gj[4] = {j, j, j + 1, j + 1};
            int c[4];
            for (int k = 0; k < 4; ++k) {
                if (split) {
                    pos[3 * pv] = gi[k] * h;
                    pos[3 * pv + 1] = gj[k] * h;
                    pos[3 * pv + 2] = 0.01 * sin(7.0 * gi[k] * h) * cos(5.0 * gj[k] * h);
                    c[k] = pv++;
                } else {
                    c[k] = gj[k] * n + gi[k];
                }
            }
            if (quads) {
                sizes[pp++] = 4;
                for (int k = 0; k < 4; ++k) idx[pi++] = c[k];
            } else {
                int t[6] = {c[0], c[1], c[2], c[0], c[2], c[3]};
                sizes[pp++] = 3;
                sizes[pp++] = 3;
                memcpy(idx + pi, t, sizeof t);
                pi += 6;
            }
        }
    wc_diag d = {0};
    wc_status st = wc_source_mesh_from_arrays(out, NULL, pos, nv, sizes, npoly, idx, 1.0, &d);
    free(pos);
    free(sizes);
    free(idx);
    return st == WC_OK;
}

static int write_obj(const wc_source_mesh* m, const char* path) {
    FILE* f = fopen(path, "w");
    if (!f) return 0;
    for (int v = 0; v < m->n_verts; ++v)
        fprintf(f, "v %.9g %.9g %.9g\n", m->pos[3 * v], m->pos[3 * v + 1], m->pos[3 * v + 2]);
    for (int p = 0; p < m->n_polys; ++p) {
        fputc('f', f);
        for (int c = m->poly_start[p]; c < m->poly_start[p + 1]; ++c) fprintf(f, " %d", m->poly_verts[c] + 1);
        fputc('\n', f);
    }
    return fclose(f) == 0;
}

int main(int argc, char** argv) {
    long target = 1000000;
    int runs = 5, with_obj = 0;
    for (int i = 1; i < argc; ++i) {
        if (!strcmp(argv[i], "--triangles") && i + 1 < argc) target = atol(argv[++i]);
        else if (!strcmp(argv[i], "--runs") && i + 1 < argc) runs = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--obj")) with_obj = 1;
        else {
            fprintf(stderr, "usage: %s [--triangles N] [--runs R] [--obj]\n", argv[0]);
            return 2;
        }
    }
    if (target < 2 || runs < 1 || runs > 100) return 2;
    int n = (int)ceil(sqrt(target / 2.0)) + 1;
    printf("grid %d x %d vertices, %ld triangles, median of %d runs\n\n", n, n, 2L * (n - 1) * (n - 1), runs);
    printf("| mesh | host verts | particles | springs | weld | triangulate | clean | orient | topology | springs | pattern | build total | assimp read |\n");
    printf("|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
    struct { const char* name; int quads, split; } cases[] = {{"tri grid", 0, 0}, {"quad grid, split per quad", 1, 1}};
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; ++c) {
        wc_source_mesh src;
        if (!make_grid(&src, n, cases[c].quads, cases[c].split)) {
            fprintf(stderr, "mesh generation failed\n");
            return 1;
        }
        double* t[9];
        for (int k = 0; k < 9; ++k) t[k] = calloc((size_t)runs, sizeof(double));
        wc_import_report rep = {0};
        int nspr = 0;
        for (int r = 0; r < runs; ++r) {
            wc_model m;
            wc_diag d = {0};
            wc_model_def def = wc_default_model_def();
            if (wc_model_build(&m, &src, &def, NULL, &d) != WC_OK) {
                fprintf(stderr, "build failed: %s\n", d.message);
                return 1;
            }
            rep = m.report;
            nspr = m.n_springs;
            double v[8] = {rep.ms.weld,     rep.ms.triangulate, rep.ms.clean,   rep.ms.orient,
                           rep.ms.topology, rep.ms.springs,     rep.ms.pattern, rep.ms.total};
            for (int k = 0; k < 8; ++k) t[k][r] = v[k];
            wc_model_free(&m);
        }
        double obj_ms = NAN;
        if (with_obj) {
            const char* path = "/tmp/weft_bench_import.obj";
            if (write_obj(&src, path)) {
                for (int r = 0; r < runs; ++r) {
                    wc_source_mesh im;
                    wc_diag d = {0};
                    wc_import_opts o = wc_default_import_opts();
                    double t0 = wc_now_ms();
                    wc_status st = wc_import_file(&im, NULL, path, &o, &d);
                    t[8][r] = wc_now_ms() - t0;
                    if (st == WC_OK) wc_source_mesh_free(&im);
                    else fprintf(stderr, "import failed: %s\n", d.message);
                }
                obj_ms = wc_sort_median(t[8], runs);
                remove(path);
            }
        }
        printf("| %s | %d | %d | %d |", cases[c].name, src.n_verts, rep.particles, nspr);
        for (int k = 0; k < 8; ++k) printf(" %.0f ms |", wc_sort_median(t[k], runs));
        if (with_obj) printf(" %.0f ms |\n", obj_ms);
        else printf(" - |\n");
        for (int k = 0; k < 9; ++k) free(t[k]);
        wc_source_mesh_free(&src);
    }
    return 0;
}
