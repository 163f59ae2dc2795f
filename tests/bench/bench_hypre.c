/* Weft's PCG preconditioners beside hypre's BoomerAMG, on the very systems a substep solves.
 *
 * For each size N (N x N particles, 1 m) and each system:
 *   hang   a flat sheet hanging from the two corners of one edge, after --frames frames at one
 *          substep of 1/30 s (direct solver), then the next substep's system (wc_substep_prepare);
 *   stiff  the same with every spring stiffness x 1e4;
 *   drape  a sheet 5 cm above a sphere (radius 0.25 m), after --drape-frames frames: in contact
 *          (plane constraints in the filter) where it lies on the sphere;
 * the filtered system (A, b, the filter S, z) is solved
 *   - by CHOLMOD (WC_SOLVER_DIRECT): the reference dv;
 *   - by Weft's PCG with each wc_precond_type through wc_solve, from dv = z (initial guess 0);
 *   - by hypre's PCG (two-norm, relative residual, initial guess 0) preconditioned by one
 *     BoomerAMG V-cycle in three settings: scalar (hypre's defaults), systems (num_functions 3,
 *     the unknown approach) and nodal (num_functions 3, nodal coarsening on the Frobenius norm of
 *     the 3x3 blocks), on the projected SPD matrix P = S A S + I - S (CSR, 3n rows) with the
 *     right-hand side r = S (b - A z); dv = z + S y.
 * Each row: iterations, setup ms (the preconditioner's), solve ms (the iterations), total, the
 * final relative residual ||r - P y|| / ||r|| recomputed here on P (the same definition for all:
 * Weft's PCG stops on ||S (b - A dv)|| / ||S (b - A z)||, which is it), and the error against
 * CHOLMOD ||dv - dv_direct|| / ||dv_direct||. One process (MPI_COMM_WORLD of one rank), --threads
 * OpenMP threads for Weft (hypre is built without OpenMP). A benchmark program: it prints a
 * Markdown table and asserts nothing.
 *
 *   bench_hypre [--sizes 32,64,128,256] [--systems hang,stiff,drape] [--tolerance 1e-4]
 *               [--iterations 300] [--frames 3] [--drape-frames 8] [--threads 1] [--hypre-print 0] */
#include <HYPRE.h>
#include <HYPRE_parcsr_ls.h>
#include <math.h>
#include <mpi.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "clock.h"
#include "model.h"
#include "solve.h"
#include "state.h"
#include "step.h"

#define MAX_SIZES 16

typedef struct opts {
    int sizes[MAX_SIZES], n_sizes;
    int hang, stiff, drape;
    double tolerance;
    int cap, frames, drape_frames, threads;
    int hypre_print;        /* BoomerAMG's print level (1: its hierarchy and complexities, on stdout) */
} opts;

/* ---- the systems ---- */

/* An n x n grid of quads, 1 m, horizontal (y = 0), vertex i + n j at (-0.5 + i / (n - 1), 0,
 * -0.5 + j / (n - 1)) shifted up by y0; stiffness x k_scale. */
static int build_model(wc_model* m, int n, double y0, double k_scale) {
    const int nv = n * n, nq = (n - 1) * (n - 1);
    double* pos = malloc(sizeof(double) * 3 * (size_t)nv);
    int* sizes = malloc(sizeof(int) * (size_t)nq);
    int* idx = malloc(sizeof(int) * 4 * (size_t)nq);
    if (!pos || !sizes || !idx) return -1;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            double* p = pos + 3 * (j * n + i);
            p[0] = -0.5 + (double)i / (n - 1);
            p[1] = y0;
            p[2] = -0.5 + (double)j / (n - 1);
        }
    int q = 0;
    for (int j = 0; j + 1 < n; ++j)
        for (int i = 0; i + 1 < n; ++i, ++q) {
            sizes[q] = 4;
            const int c[4] = {j * n + i, j * n + i + 1, (j + 1) * n + i + 1, (j + 1) * n + i};
            for (int k = 0; k < 4; ++k) idx[4 * q + k] = c[k];
        }
    wc_source_mesh src;
    wc_diag d = {0};
    wc_status st = wc_source_mesh_from_arrays(&src, NULL, pos, nv, sizes, nq, idx, 1.0, &d);
    free(pos);
    free(sizes);
    free(idx);
    if (st != WC_OK) {
        fprintf(stderr, "bench_hypre: mesh: %s\n", d.message);
        return -1;
    }
    wc_model_def def = wc_default_model_def();
    for (int t = 0; t < WC_SPRING_TYPE_COUNT; ++t) def.material.k[t] *= k_scale;
    st = wc_model_build(m, &src, &def, NULL, &d);
    wc_source_mesh_free(&src);
    if (st != WC_OK) fprintf(stderr, "bench_hypre: model: %s\n", d.message);
    return st == WC_OK ? 0 : -1;
}

/* A state stepped `frames` frames (direct solver, 1/30 s, one substep), then the next substep's
 * system prepared in it. kind: 0 hang, 1 drape. NULL on failure. */
static wc_state* prepare_system(const wc_model* m, int n, int kind, int frames, int threads) {
    wc_sim_def sd = wc_default_sim_def();
    sd.solver.type = WC_SOLVER_DIRECT;
    sd.threads = threads;
    sd.max_pins = 2;
    sd.max_colliders = 1;
    sd.sleep_speed = 0.0;
    wc_state* s = NULL;
    wc_diag d = {0};
    if (wc_state_create(&s, m, &sd, NULL, &d) != WC_OK) {
        fprintf(stderr, "bench_hypre: state: %s\n", d.message);
        return NULL;
    }
    wc_status st = WC_OK;
    if (kind == 0) {
        const int corner[2] = {n * (n - 1), n * n - 1};
        wc_pin pins[2];
        memset(pins, 0, sizeof pins);
        for (int k = 0; k < 2; ++k) {
            pins[k].particle = m->host_to_particle[corner[k]];
            for (int c = 0; c < 3; ++c) pins[k].target[c] = m->rest_pos[3 * pins[k].particle + c];
        }
        st = wc_state_set_pins(s, pins, 2, &d);
    } else {
        wc_collider c;
        memset(&c, 0, sizeof c);
        c.type = WC_COLLIDER_SPHERE;
        c.radius = 0.25;
        c.thickness = 0.005;
        c.friction = 0.3;
        st = wc_state_set_colliders(s, &c, 1, &d);
    }
    for (int f = 0; f < frames && st == WC_OK; ++f) {
        wc_step_stats ss;
        wc_step_frame(s, 1.0 / 30.0, &ss, &d);
    }
    if (st != WC_OK) {
        fprintf(stderr, "bench_hypre: %s\n", d.message);
        wc_state_destroy(s);
        return NULL;
    }
    wc_step_stats ss;
    memset(&ss, 0, sizeof ss);
    wc_substep_prepare(s, 1.0 / 30.0, 1.0, &ss);
    return s;
}

/* ---- P = S A S + I - S as CSR, r = S (b - A z) ---- */

typedef struct csr {
    int n;                  /* rows (3 particles) */
    int* start;             /* (n + 1) */
    int* col;               /* (nnz) */
    double* val;            /* (nnz) */
} csr;

static void mat3_mul(const double* a, const double* b, double* out) {
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) out[3 * i + j] = a[3 * i] * b[j] + a[3 * i + 1] * b[3 + j] + a[3 * i + 2] * b[6 + j];
}

static int csr_build(csr* P, const wc_model* m, const double* A, const wc_filter* f) {
    const wc_bsr_pattern* p = &m->pattern;
    const int n = m->n_particles;
    P->n = 3 * n;
    P->start = malloc(sizeof(int) * (size_t)(3 * n + 1));
    P->col = malloc(sizeof(int) * 9 * (size_t)p->n_blocks);
    P->val = malloc(sizeof(double) * 9 * (size_t)p->n_blocks);
    if (!P->start || !P->col || !P->val) return -1;
    int nnz = 0;
    for (int i = 0; i < n; ++i)
        for (int a = 0; a < 3; ++a) {
            P->start[3 * i + a] = nnz;
            for (int e = p->row_start[i]; e < p->row_start[i + 1]; ++e) {
                const int j = p->col[e];
                double t[9], B[9];
                mat3_mul(f->S + 9 * i, A + 9 * e, t);
                mat3_mul(t, f->S + 9 * j, B);
                if (i == j)
                    for (int k = 0; k < 9; ++k) B[k] += (k % 4 == 0) - f->S[9 * i + k];
                for (int c = 0; c < 3; ++c) {
                    const double v = B[3 * a + c];
                    if (v == 0.0 && !(i == j && a == c)) continue;
                    P->col[nnz] = 3 * j + c;
                    P->val[nnz++] = v;
                }
            }
        }
    P->start[3 * n] = nnz;
    return 0;
}

static void csr_free(csr* P) { free(P->start), free(P->col), free(P->val); }

static void csr_mul(const csr* P, const double* x, double* y) {
    for (int i = 0; i < P->n; ++i) {
        double s = 0.0;
        for (int k = P->start[i]; k < P->start[i + 1]; ++k) s += P->val[k] * x[P->col[k]];
        y[i] = s;
    }
}

static double norm(const double* v, int n) {
    double s = 0.0;
    for (int i = 0; i < n; ++i) s += v[i] * v[i];
    return sqrt(s);
}

/* ||r - P y|| / ||r||. */
static double rel_residual(const csr* P, const double* r, const double* y, double* scratch) {
    csr_mul(P, y, scratch);
    for (int i = 0; i < P->n; ++i) scratch[i] = r[i] - scratch[i];
    const double nr = norm(r, P->n);
    return nr > 0 ? norm(scratch, P->n) / nr : 0.0;
}

/* ---- one row of the table ---- */

typedef struct row {
    const char* method;
    int iterations;
    double setup_ms, solve_ms, residual, error;
} row;

static void print_row(int n, const char* system, int particles, const row* r) {
    printf("| %d | %s | %d | %s | %d | %.3g | %.3g | %.3g | %.2e | %.2e |\n", n, system, particles, r->method,
           r->iterations, r->setup_ms, r->solve_ms, r->setup_ms + r->solve_ms, r->residual, r->error);
    fflush(stdout);
}

static double rel_error(const double* dv, const double* ref, int n3) {
    double num = 0.0, den = 0.0;
    for (int k = 0; k < n3; ++k) {
        num += (dv[k] - ref[k]) * (dv[k] - ref[k]);
        den += ref[k] * ref[k];
    }
    return den > 0 ? sqrt(num / den) : sqrt(num);
}

/* dv = z + S y */
static void lift(const wc_filter* f, const double* y, double* dv, int n) {
    for (int i = 0; i < n; ++i)
        for (int a = 0; a < 3; ++a) {
            const double* S = f->S + 9 * i + 3 * a;
            dv[3 * i + a] = f->z[3 * i + a] + S[0] * y[3 * i] + S[1] * y[3 * i + 1] + S[2] * y[3 * i + 2];
        }
}

/* y = dv - z (dv already z + S y with y in S's range). */
static void unlift(const wc_filter* f, const double* dv, double* y, int n3) {
    for (int k = 0; k < n3; ++k) y[k] = dv[k] - f->z[k];
}

/* hypre PCG + BoomerAMG (variant 0 scalar, 1 systems, 2 nodal) on P y = r. */
static void run_hypre(const opts* o, const csr* P, const double* r, int variant, const wc_filter* f,
                      const double* dv_ref, double* y, double* dv, double* scratch, row* out) {
    const int n3 = P->n;
    HYPRE_IJMatrix A;
    HYPRE_IJVector bv, xv;
    HYPRE_IJMatrixCreate(MPI_COMM_WORLD, 0, n3 - 1, 0, n3 - 1, &A);
    HYPRE_IJMatrixSetObjectType(A, HYPRE_PARCSR);
    int* sizes = malloc(sizeof(int) * (size_t)n3);
    int* rows = malloc(sizeof(int) * (size_t)n3);
    double* zero = calloc((size_t)n3, sizeof(double));
    for (int i = 0; i < n3; ++i) {
        sizes[i] = P->start[i + 1] - P->start[i];
        rows[i] = i;
    }
    HYPRE_IJMatrixSetRowSizes(A, sizes);
    HYPRE_IJMatrixInitialize(A);
    HYPRE_IJMatrixSetValues(A, n3, sizes, rows, P->col, P->val);
    HYPRE_IJMatrixAssemble(A);
    HYPRE_ParCSRMatrix pA;
    HYPRE_IJMatrixGetObject(A, (void**)&pA);
    HYPRE_IJVectorCreate(MPI_COMM_WORLD, 0, n3 - 1, &bv);
    HYPRE_IJVectorSetObjectType(bv, HYPRE_PARCSR);
    HYPRE_IJVectorInitialize(bv);
    HYPRE_IJVectorSetValues(bv, n3, rows, r);
    HYPRE_IJVectorAssemble(bv);
    HYPRE_IJVectorCreate(MPI_COMM_WORLD, 0, n3 - 1, &xv);
    HYPRE_IJVectorSetObjectType(xv, HYPRE_PARCSR);
    HYPRE_IJVectorInitialize(xv);
    HYPRE_IJVectorSetValues(xv, n3, rows, zero);
    HYPRE_IJVectorAssemble(xv);
    HYPRE_ParVector pb, px;
    HYPRE_IJVectorGetObject(bv, (void**)&pb);
    HYPRE_IJVectorGetObject(xv, (void**)&px);

    HYPRE_Solver pcg, amg;
    HYPRE_ParCSRPCGCreate(MPI_COMM_WORLD, &pcg);
    HYPRE_PCGSetTol(pcg, o->tolerance);
    HYPRE_PCGSetMaxIter(pcg, o->cap);
    HYPRE_PCGSetTwoNorm(pcg, 1);
    HYPRE_PCGSetLogging(pcg, 1);
    HYPRE_PCGSetPrintLevel(pcg, 0);
    HYPRE_BoomerAMGCreate(&amg);
    HYPRE_BoomerAMGSetMaxIter(amg, 1);
    HYPRE_BoomerAMGSetTol(amg, 0.0);
    HYPRE_BoomerAMGSetPrintLevel(amg, o->hypre_print);
    if (variant >= 1) HYPRE_BoomerAMGSetNumFunctions(amg, 3);
    if (variant == 2) HYPRE_BoomerAMGSetNodal(amg, 1);
    HYPRE_PCGSetPrecond(pcg, (HYPRE_PtrToSolverFcn)HYPRE_BoomerAMGSolve, (HYPRE_PtrToSolverFcn)HYPRE_BoomerAMGSetup,
                        amg);
    double t0 = wc_now_ms();
    HYPRE_ParCSRPCGSetup(pcg, pA, pb, px);
    double t1 = wc_now_ms();
    HYPRE_ParCSRPCGSolve(pcg, pA, pb, px);
    double t2 = wc_now_ms();
    HYPRE_Int its = 0;
    HYPRE_ParCSRPCGGetNumIterations(pcg, &its);
    HYPRE_IJVectorGetValues(xv, n3, rows, y);
    lift(f, y, dv, n3 / 3);
    static const char* const names[3] = {"hypre BoomerAMG (scalar)", "hypre BoomerAMG (systems, 3 functions)",
                                         "hypre BoomerAMG (nodal, 3 functions)"};
    out->method = names[variant];
    out->iterations = (int)its;
    out->setup_ms = t1 - t0;
    out->solve_ms = t2 - t1;
    out->residual = rel_residual(P, r, y, scratch);
    out->error = rel_error(dv, dv_ref, n3);
    HYPRE_ParCSRPCGDestroy(pcg);
    HYPRE_BoomerAMGDestroy(amg);
    HYPRE_IJMatrixDestroy(A);
    HYPRE_IJVectorDestroy(bv);
    HYPRE_IJVectorDestroy(xv);
    free(sizes);
    free(rows);
    free(zero);
}

/* Every method on one system. */
static int run_system(const opts* o, int n, const char* name, int kind, double k_scale) {
    wc_model m;
    if (build_model(&m, n, kind == 1 ? 0.3 : 0.0, k_scale) != 0) return -1;
    wc_state* s = prepare_system(&m, n, kind, kind == 1 ? o->drape_frames : o->frames, o->threads);
    if (!s) {
        wc_model_free(&m);
        return -1;
    }
    const int np = m.n_particles, n3 = 3 * np;
    double* dv_ref = calloc((size_t)n3, sizeof(double));
    double* dv = calloc((size_t)n3, sizeof(double));
    double* y = calloc((size_t)n3, sizeof(double));
    double* r = calloc((size_t)n3, sizeof(double));
    double* scratch = calloc((size_t)n3, sizeof(double));
    csr P;
    memset(&P, 0, sizeof P);
    int rc = (!dv_ref || !dv || !y || !r || !scratch || csr_build(&P, &m, s->A, &s->filter) != 0) ? -1 : 0;
    if (rc == 0) {
        /* r = S (b - A z) */
        wc_bsr_mul(&m.pattern, s->A, s->filter.z, scratch, &s->par);
        for (int i = 0; i < np; ++i)
            for (int a = 0; a < 3; ++a) {
                const double* S = s->filter.S + 9 * i + 3 * a;
                double acc = 0.0;
                for (int c = 0; c < 3; ++c) acc += S[c] * (s->b[3 * i + c] - scratch[3 * i + c]);
                r[3 * i + a] = acc;
            }
        int contacts = 0;
        for (int i = 0; i < np; ++i) contacts += s->filter.ndof[i] == 1;
        /* CHOLMOD */
        wc_solver_opts so = wc_default_solver_opts();
        so.tolerance = o->tolerance;
        so.max_iterations = o->cap;
        wc_solver* ws = NULL;
        wc_diag d = {0};
        wc_solve_result res;
        if (wc_solver_create(&ws, &m, &so, 1, NULL, &d) != WC_OK) {
            fprintf(stderr, "bench_hypre: solver: %s\n", d.message);
            rc = -1;
        } else {
            double t0 = wc_now_ms();
            wc_solve(ws, WC_SOLVER_DIRECT, s->A, s->b, &s->filter, dv_ref, &s->par, &res);
            double t1 = wc_now_ms();
            unlift(&s->filter, dv_ref, y, n3);
            row rw = {"CHOLMOD (direct)", res.iterations, 0.0, t1 - t0, rel_residual(&P, r, y, scratch), 0.0};
            print_row(n, name, np, &rw);
            wc_solver_destroy(ws);
        }
        /* Weft's PCG, each preconditioner */
        for (int t = 0; t < WC_PRECOND_COUNT && rc == 0; ++t) {
            so.preconditioner = (wc_precond_type)t;
            ws = NULL;
            if (wc_solver_create(&ws, &m, &so, 0, NULL, &d) != WC_OK) {
                fprintf(stderr, "bench_hypre: solver: %s\n", d.message);
                rc = -1;
                break;
            }
            memset(dv, 0, sizeof(double) * (size_t)n3);
            const double t0 = wc_now_ms();
            wc_solve(ws, WC_SOLVER_PCG, s->A, s->b, &s->filter, dv, &s->par, &res);
            const double t1 = wc_now_ms();
            char method[64];
            snprintf(method, sizeof method, "Weft PCG + %s", wc_precond_name((wc_precond_type)t));
            unlift(&s->filter, dv, y, n3);
            row rw = {method, res.iterations, res.setup_ms, t1 - t0 - res.setup_ms, rel_residual(&P, r, y, scratch),
                      rel_error(dv, dv_ref, n3)};
            print_row(n, name, np, &rw);
            wc_solver_destroy(ws);
        }
        for (int v = 0; v < 3 && rc == 0; ++v) {
            row rw;
            run_hypre(o, &P, r, v, &s->filter, dv_ref, y, dv, scratch, &rw);
            print_row(n, name, np, &rw);
        }
        if (kind == 1) fprintf(stderr, "  (%s %d: %d particles in contact)\n", name, n, contacts);
    }
    csr_free(&P);
    free(dv_ref);
    free(dv);
    free(y);
    free(r);
    free(scratch);
    wc_state_destroy(s);
    wc_model_free(&m);
    return rc;
}

/* ---- command line ---- */

static int parse_list(const char* text, int* out, int max) {
    int n = 0;
    for (const char* p = text; *p && n < max;) {
        char* end;
        long v = strtol(p, &end, 10);
        if (end == p || v < 2 || v > 4096) return -1;
        out[n++] = (int)v;
        p = *end == ',' ? end + 1 : end;
        if (*end && *end != ',') return -1;
    }
    return n;
}

static int parse_args(int argc, char** argv, opts* o) {
    memset(o, 0, sizeof *o);
    o->n_sizes = parse_list("32,64,128,256", o->sizes, MAX_SIZES);
    o->hang = o->stiff = o->drape = 1;
    o->tolerance = 1e-4;
    o->cap = 300;
    o->frames = 3;
    o->drape_frames = 8;
    o->threads = 1;
    for (int i = 1; i < argc; ++i) {
        const char* a = argv[i];
        const char* v = i + 1 < argc ? argv[i + 1] : NULL;
        if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
            printf("usage: bench_hypre [--sizes 32,64,128,256] [--systems hang,stiff,drape] [--tolerance 1e-4]\n"
                   "                   [--iterations 300] [--frames 3] [--drape-frames 8] [--threads 1]\n"
                   "                   [--hypre-print 0|1 (BoomerAMG's hierarchy and complexities)]\n");
            exit(0);
        }
        if (!v) {
            fprintf(stderr, "bench_hypre: %s needs a value\n", a);
            return -1;
        }
        ++i;
        if (!strcmp(a, "--sizes")) {
            if ((o->n_sizes = parse_list(v, o->sizes, MAX_SIZES)) <= 0) return -1;
        } else if (!strcmp(a, "--systems")) {
            o->hang = strstr(v, "hang") != NULL;
            o->stiff = strstr(v, "stiff") != NULL;
            o->drape = strstr(v, "drape") != NULL;
        } else if (!strcmp(a, "--tolerance")) {
            o->tolerance = atof(v);
        } else if (!strcmp(a, "--iterations")) {
            o->cap = atoi(v);
        } else if (!strcmp(a, "--frames")) {
            o->frames = atoi(v);
        } else if (!strcmp(a, "--drape-frames")) {
            o->drape_frames = atoi(v);
        } else if (!strcmp(a, "--threads")) {
            o->threads = atoi(v);
        } else if (!strcmp(a, "--hypre-print")) {
            o->hypre_print = atoi(v);
        } else {
            fprintf(stderr, "bench_hypre: unknown option %s\n", a);
            return -1;
        }
    }
    return (o->tolerance > 0 && o->cap > 0 && o->frames >= 0 && o->drape_frames >= 0 && o->threads >= 0) ? 0 : -1;
}

int main(int argc, char** argv) {
    opts o;
    if (parse_args(argc, argv, &o) != 0) {
        fprintf(stderr, "bench_hypre: bad arguments (--help)\n");
        return 2;
    }
    MPI_Init(&argc, &argv);
    HYPRE_Init();
    printf("## Weft's PCG preconditioners beside hypre's BoomerAMG\n\n"
           "One substep's filtered system (1/30 s) of each scene, solved to relative residual %g (cap %d) from an "
           "initial guess of 0: Weft's PCG through wc_solve with each preconditioner (%d thread(s)), hypre's PCG "
           "with one BoomerAMG V-cycle as preconditioner on P = S A S + I - S (one MPI rank, no OpenMP), CHOLMOD "
           "for reference. hang: a sheet hanging from two corners after %d frames; stiff: the same at 1e4 x the "
           "stiffness; drape: a sheet on a sphere after %d frames (contacts in the filter). residual: "
           "||r - P y|| / ||r||, computed here; error: ||dv - dv_CHOLMOD|| / ||dv_CHOLMOD||; ms: wall time "
           "(setup: the preconditioner's; solve: the iterations).\n\n",
           o.tolerance, o.cap, o.threads > 0 ? o.threads : 0, o.frames, o.drape_frames);
    printf("| size | system | particles | method | iterations | setup ms | solve ms | total ms | residual | error |\n"
           "|---|---|---|---|---|---|---|---|---|---|\n");
    int rc = 0;
    for (int k = 0; k < o.n_sizes && rc == 0; ++k) {
        const int n = o.sizes[k];
        if (o.hang && rc == 0) rc = run_system(&o, n, "hang", 0, 1.0);
        if (o.stiff && rc == 0) rc = run_system(&o, n, "stiff", 0, 1e4);
        if (o.drape && rc == 0) rc = run_system(&o, n, "drape", 1, 1.0);
    }
    HYPRE_Finalize();
    MPI_Finalize();
    return rc == 0 ? 0 : 1;
}
