#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include "test_support.h"
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>
#include "step.h"

static void grid_positions(double* pos, int nx, int ny, double sx, double sy) {
    for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) {
            double* p = pos + 3 * (j * nx + i);
            p[0] = sx * i / (nx - 1);
            p[1] = sy * j / (ny - 1);
            p[2] = 0.0;
        }
}

void ts_quad_grid(wc_source_mesh* out, int nx, int ny, double sx, double sy, int split_uv) {
    int nq = (nx - 1) * (ny - 1);
    double* grid = calloc((size_t)nx * ny * 3, sizeof(double));
    grid_positions(grid, nx, ny, sx, sy);
    int nv = split_uv ? 4 * nq : nx * ny;
    double* pos = calloc((size_t)nv * 3, sizeof(double));
    int* sizes = malloc(sizeof(int) * nq);
    int* idx = malloc(sizeof(int) * 4 * nq);
    if (!split_uv) memcpy(pos, grid, sizeof(double) * 3 * nv);
    int q = 0;
    for (int j = 0; j + 1 < ny; ++j)
        for (int i = 0; i + 1 < nx; ++i, ++q) {
            int c[4] = {j * nx + i, j * nx + i + 1, (j + 1) * nx + i + 1, (j + 1) * nx + i};
            sizes[q] = 4;
            for (int k = 0; k < 4; ++k) {
                if (split_uv) {
                    memcpy(pos + 3 * (4 * q + k), grid + 3 * c[k], 3 * sizeof(double));
                    idx[4 * q + k] = 4 * q + k;
                } else {
                    idx[4 * q + k] = c[k];
                }
            }
        }
    wc_diag d = {0};
    if (wc_source_mesh_from_arrays(out, NULL, pos, nv, sizes, nq, idx, 1.0, &d) != WC_OK)
        fprintf(stderr, "ts_quad_grid: %s\n", d.message);
    free(grid);
    free(pos);
    free(sizes);
    free(idx);
}

void ts_tri_grid(wc_source_mesh* out, int nx, int ny, double sx, double sy) {
    int nv = nx * ny, nt = 2 * (nx - 1) * (ny - 1);
    double* pos = calloc((size_t)nv * 3, sizeof(double));
    grid_positions(pos, nx, ny, sx, sy);
    int* sizes = malloc(sizeof(int) * nt);
    int* idx = malloc(sizeof(int) * 3 * nt);
    int t = 0;
    for (int j = 0; j + 1 < ny; ++j)
        for (int i = 0; i + 1 < nx; ++i) {
            int a = j * nx + i, b = a + 1, c = a + nx + 1, d = a + nx;
            int tri[6] = {a, b, c, a, c, d};
            memcpy(idx + 3 * t, tri, sizeof tri);
            sizes[t] = sizes[t + 1] = 3;
            t += 2;
        }
    wc_diag dg = {0};
    if (wc_source_mesh_from_arrays(out, NULL, pos, nv, sizes, nt, idx, 1.0, &dg) != WC_OK)
        fprintf(stderr, "ts_tri_grid: %s\n", dg.message);
    free(pos);
    free(sizes);
    free(idx);
}

const char* ts_tmp_path(const char* name) {
    static char slots[4][1024];
    static int next = 0;
    char* p = slots[next++ & 3];
    snprintf(p, sizeof slots[0], "%s/%s", WEFT_TEST_TMPDIR, name);
    return p;
}

const char* ts_write_tmp(const char* name, const char* text) {
    const char* path = ts_tmp_path(name);
    FILE* f = fopen(path, "wb");
    if (!f) return NULL;
    fputs(text, f);
    fclose(f);
    return path;
}

int ts_sheet(wc_model* m, int n, double size, double y, int vertical, double k_scale) {
    wc_source_mesh src;
    ts_quad_grid(&src, n, n, size, size, 0);
    for (int v = 0; v < src.n_verts; ++v) {
        double* p = src.pos + 3 * v;
        double gx = p[0], gy = p[1];
        if (vertical) {
            p[0] = gx - 0.5 * size;
            p[1] = y - size + gy;
            p[2] = 0.0;
        } else {
            p[0] = gx - 0.5 * size;
            p[1] = y;
            p[2] = gy - 0.5 * size;
        }
    }
    wc_model_def def = wc_default_model_def();
    for (int t = 0; t < WC_SPRING_TYPE_COUNT; ++t) {
        def.material.k[t] *= k_scale;
        def.material.d[t] *= k_scale;
    }
    wc_diag d = {0};
    wc_status st = wc_model_build(m, &src, &def, NULL, &d);
    if (st != WC_OK) fprintf(stderr, "ts_sheet: %s\n", d.message);
    wc_source_mesh_free(&src);
    return st == WC_OK;
}

int ts_sheet_particle(const wc_model* m, int n, int i, int j) { return m->host_to_particle[i + n * j]; }

void ts_read_text(const char* path, char* buf, size_t cap) {
    buf[0] = '\0';
    FILE* f = fopen(path, "rb");
    if (!f) return;
    size_t n = fread(buf, 1, cap - 1, f);
    buf[n] = '\0';
    fclose(f);
}

void ts_run_cli(const char* args, ts_cli_result* r) {
    char out_path[1024], err_path[1024], cmd[4096], name[64];
    snprintf(name, sizeof name, "cli_%ld_stdout.txt", (long)getpid()); /* tests may run in parallel */
    snprintf(out_path, sizeof out_path, "%s", ts_tmp_path(name));
    snprintf(name, sizeof name, "cli_%ld_stderr.txt", (long)getpid());
    snprintf(err_path, sizeof err_path, "%s", ts_tmp_path(name));
    snprintf(cmd, sizeof cmd, "'%s' %s >'%s' 2>'%s'", WEFT_CLI, args, out_path, err_path);
    int status = system(cmd);
    r->rc = (status != -1 && WIFEXITED(status)) ? WEXITSTATUS(status) : -1;
    ts_read_text(out_path, r->out, sizeof r->out);
    ts_read_text(err_path, r->err, sizeof r->err);
}

int ts_count_lines(const char* s) {
    int n = 0;
    for (; *s; ++s) n += *s == '\n';
    return n;
}

double ts_rel_diff(const double* a, const double* b, int n) {
    double num = 0, den = 0;
    for (int k = 0; k < n; ++k) {
        num += (a[k] - b[k]) * (a[k] - b[k]);
        den += b[k] * b[k];
    }
    return sqrt(num / (den > 0 ? den : 1));
}

wc_status ts_pin_far_corners(wc_state* s, int n, const double* move) {
    wc_pin pins[2];
    memset(pins, 0, sizeof pins);
    pins[0].particle = ts_sheet_particle(s->model, n, 0, n - 1);
    pins[1].particle = ts_sheet_particle(s->model, n, n - 1, n - 1);
    for (int k = 0; k < 2; ++k)
        for (int c = 0; c < 3; ++c) pins[k].target[c] = s->x[3 * pins[k].particle + c] + (move ? move[c] : 0.0);
    wc_diag diag = {0};
    return wc_state_set_pins(s, pins, 2, &diag);
}

wc_state* ts_draped(wc_model* m, int n, const wc_sim_def* def, int frames) {
    if (!ts_sheet(m, n, 1.0, 0.47, 0, 1.0)) return NULL;
    wc_state* s = NULL;
    wc_diag d = {0};
    if (wc_state_create(&s, m, def, NULL, &d) != WC_OK) {
        wc_model_free(m);
        return NULL;
    }
    wc_collider c;
    memset(&c, 0, sizeof c);
    c.type = WC_COLLIDER_SPHERE;
    c.radius = 0.45;
    c.thickness = 0.005;
    c.friction = 0.3;
    wc_state_set_colliders(s, &c, 1, &d);
    for (int f = 0; f < frames; ++f) wc_step_frame(s, 1.0 / 30.0, NULL, &d);
    return s;
}

double ts_max_abs(const double* a, int n) {
    double m = 0.0;
    for (int k = 0; k < n; ++k) m = fmax(m, fabs(a[k]));
    return m;
}

double ts_max_diff(const double* a, const double* b, int n) {
    double m = 0.0;
    for (int k = 0; k < n; ++k) m = fmax(m, fabs(a[k] - b[k]));
    return m;
}

/* A model of nq polygons (sizes, idx) over nv positions, built with the default model definition
 * but its weld tolerance (weld < 0: the default's); frees pos, sizes and idx. */
static wc_status model_from_quads(wc_model* m, double* pos, int nv, int* sizes, int nq, int* idx, double weld,
                                  wc_diag* d) {
    wc_source_mesh src;
    wc_status st = wc_source_mesh_from_arrays(&src, NULL, pos, nv, sizes, nq, idx, 1.0, d);
    free(pos), free(sizes), free(idx);
    if (st != WC_OK) return st;
    wc_model_def mdef = wc_default_model_def();
    if (weld >= 0.0) mdef.weld_tolerance = weld;
    st = wc_model_build(m, &src, &mdef, NULL, d);
    wc_source_mesh_free(&src);
    return st;
}

wc_state* ts_patches(wc_model* m, int count, const wc_sim_def* def) {
    int nv = 9 * count, nq = 4 * count;
    double* pos = calloc((size_t)nv * 3, sizeof(double));
    int* sizes = calloc((size_t)nq, sizeof(int));
    int* idx = calloc((size_t)nq * 4, sizeof(int));
    for (int p = 0; p < count; ++p) {
        for (int v = 0; v < 9; ++v) {
            double* x = pos + 3 * (9 * p + v);
            x[0] = 0.1 * p + 0.02 * (v % 3);
            x[1] = 1.0;
            x[2] = 0.02 * (v / 3);
        }
        for (int q = 0; q < 4; ++q) {
            int i = q % 2, j = q / 2, *c = idx + 4 * (4 * p + q);
            sizes[4 * p + q] = 4;
            c[0] = 9 * p + i + 3 * j;
            c[1] = 9 * p + i + 3 * (j + 1);
            c[2] = 9 * p + i + 1 + 3 * (j + 1);
            c[3] = 9 * p + i + 1 + 3 * j;
        }
    }
    wc_diag d = {0};
    if (model_from_quads(m, pos, nv, sizes, nq, idx, -1.0, &d) != WC_OK) return NULL;
    wc_state* s = NULL;
    if (wc_state_create(&s, m, def, NULL, &d) != WC_OK) return NULL;
    wc_pin* pins = calloc((size_t)count, sizeof *pins);
    for (int p = 0; p < count; ++p) {
        pins[p].particle = m->host_to_particle[9 * p];
        memcpy(pins[p].target, s->x + 3 * pins[p].particle, sizeof pins[p].target);
    }
    wc_state_set_pins(s, pins, count, &d);
    free(pins);
    for (int f = 0; f < 3; ++f) wc_step_frame(s, 1.0 / 30.0, NULL, &d);
    return s;
}

wc_sim_def ts_amg_def(void) {
    wc_sim_def def = wc_default_sim_def();
    def.solver.type = WC_SOLVER_PCG;
    def.solver.preconditioner = WC_PRECOND_AMG;
    def.sleep_speed = 0.0;
    return def;
}

wc_state* ts_hanging_float(wc_model* m, int n, int warm, double k_scale) {
    if (!ts_sheet(m, n, 1.0, 1.0, 1, k_scale)) return NULL;
    wc_sim_def def = ts_amg_def();
    wc_state* s = NULL;
    wc_diag d = {0};
    if (wc_state_create(&s, m, &def, NULL, &d) != WC_OK) return NULL;
    ts_pin_far_corners(s, n, NULL);
    for (int f = 0; f < warm; ++f) wc_step_frame(s, 1.0 / 30.0, NULL, &d);
    for (int k = 0; k < 3 * m->n_particles; ++k) {
        s->x[k] = (float)s->x[k];
        s->v[k] = (float)s->v[k];
    }
    return s;
}

wc_state* ts_dead_pieces(wc_model* m, int n, int pieces, int warm) {
    const int nv = n * n + 4 * pieces, nq = (n - 1) * (n - 1) + pieces;
    double* pos = calloc((size_t)nv * 3, sizeof(double));
    int* sizes = calloc((size_t)nq, sizeof(int));
    int* idx = calloc((size_t)nq * 4, sizeof(int));
    if (!pos || !sizes || !idx) {
        free(pos), free(sizes), free(idx);
        return NULL;
    }
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            pos[3 * (i + n * j)] = 6.0 * i / (n - 1);
            pos[3 * (i + n * j) + 1] = 6.0 * j / (n - 1);
        }
    int f = 0;
    for (int j = 0; j + 1 < n; ++j)
        for (int i = 0; i + 1 < n; ++i, ++f) {
            sizes[f] = 4;
            idx[4 * f] = i + n * j;
            idx[4 * f + 1] = i + 1 + n * j;
            idx[4 * f + 2] = i + 1 + n * (j + 1);
            idx[4 * f + 3] = i + n * (j + 1);
        }
    for (int p = 0; p < pieces; ++p, ++f) {
        const int v0 = n * n + 4 * p;
        const double wx = p % 2 ? 6.0 : 0.3, wy = 0.3, oy = 0.5 * p, far = 4e5;
        for (int c = 0; c < 4; ++c) {
            double* x = pos + 3 * (v0 + c);
            x[0] = far + ((c == 1 || c == 2) ? wx : 0.0);
            x[1] = oy + (c >= 2 ? wy : 0.0);
            x[2] = far;
            idx[4 * f + c] = v0 + c;
        }
        sizes[f] = 4;
    }
    wc_diag d = {0};
    /* weld 0: the pieces' corners are closer than the default's 1e-6 x diagonal */
    if (model_from_quads(m, pos, nv, sizes, nq, idx, 0.0, &d) != WC_OK) {
        fprintf(stderr, "ts_dead_pieces: %s\n", d.message);
        return NULL;
    }
    wc_sim_def def = ts_amg_def();
    wc_state* s = NULL;
    if (wc_state_create(&s, m, &def, NULL, &d) != WC_OK) return NULL;
    ts_pin_far_corners(s, n, NULL);
    for (int k = 0; k < warm; ++k) wc_step_frame(s, 1.0 / 30.0, NULL, &d);
    return s;
}
