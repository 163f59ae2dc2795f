/* The method axes of the benchmarks (bench_method.h): parsed, expanded per solver, applied to a
 * weft_cloth_def, labelled. */
#define _POSIX_C_SOURCE 200809L
#include "bench_method.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "names.h"

/* Split a comma list into names (each < 32 characters, at most BENCH_MAX_LIST); -1 when empty,
 * too long or with an empty item. */
static int split(const char* text, char names[BENCH_MAX_LIST][32]) {
    if (!text || !*text) return -1;
    int n = 0;
    for (const char* p = text;;) {
        const char* comma = strchr(p, ',');
        const size_t len = comma ? (size_t)(comma - p) : strlen(p);
        if (len == 0 || len >= 32 || n >= BENCH_MAX_LIST) return -1;
        memcpy(names[n], p, len);
        names[n++][len] = '\0';
        if (!comma) return n;
        p = comma + 1;
    }
}

int bench_parse_preconds(const char* text, weft_preconditioner* out) {
    if (text && !strcmp(text, "all")) text = "block_jacobi,amg,ic0";
    char names[BENCH_MAX_LIST][32];
    const int n = split(text, names);
    for (int k = 0; k < n; ++k) {
        const int t = cli_precond_from_name(names[k]);
        if (t < 0) return -1;
        out[k] = (weft_preconditioner)t;
    }
    return n;
}

int bench_parse_integrators(const char* text, weft_integrator* out) {
    if (text && !strcmp(text, "all")) text = "be,bdf2,trbdf2";
    char names[BENCH_MAX_LIST][32];
    const int n = split(text, names);
    for (int k = 0; k < n; ++k) {
        const int t = cli_integrator_from_name(names[k]);
        if (t < 0) return -1;
        out[k] = (weft_integrator)t;
    }
    return n;
}

void bench_methods_default(bench_methods* m, const char* preconds) {
    memset(m, 0, sizeof *m);
    m->n_preconds = bench_parse_preconds(preconds, m->preconds);
    m->n_integrators = bench_parse_integrators("be", m->integrators);
    m->n_newton = bench_parse_ints("1", 1, 100, m->newton);
    m->line_search = -1;
    m->forcing[0] = -1.0;   /* the library's (weft_cloth_def.newton_forcing) */
    m->n_forcing = 1;
}

int bench_methods_option(bench_methods* m, int argc, char** argv, int* i, const char** v) {
    int r = 0;
#define OPT(name) ((r = cli_option_value(argc, argv, i, name, v)) != 0)
#define BAD(cond) (r < 0 ? r : (cond) ? -2 : 1) /* r < 0: the value is missing */
    if (OPT("--preconds")) return BAD((m->n_preconds = bench_parse_preconds(*v, m->preconds)) < 0);
    if (OPT("--integrators")) return BAD((m->n_integrators = bench_parse_integrators(*v, m->integrators)) < 0);
    if (OPT("--newton")) return BAD((m->n_newton = bench_parse_ints(*v, 1, 100, m->newton)) < 0);
    if (OPT("--newton-forcing")) return BAD((m->n_forcing = bench_parse_doubles(*v, 0, 0.999, m->forcing)) < 0);
    if (OPT("--line-search")) {
        if (r < 0) return r;
        m->line_search = !strcmp(*v, "auto") ? -1 : !strcmp(*v, "on") ? 1 : !strcmp(*v, "off") ? 0 : -2;
        return m->line_search == -2 ? -2 : 1;
    }
#undef OPT
#undef BAD
    return r;
}

int bench_methods_max(const bench_methods* m) { return m->n_preconds * m->n_integrators * m->n_newton * m->n_forcing; }

int bench_methods_expand(const bench_methods* m, weft_solver solver, bench_method* out, int cap) {
    const int n_pre = solver == WEFT_SOLVER_PCG ? m->n_preconds : 1;
    int k = 0;
    for (int p = 0; p < n_pre; ++p)
        for (int g = 0; g < m->n_integrators; ++g)
            for (int w = 0; w < m->n_newton; ++w)
                for (int f = 0; f < m->n_forcing && k < cap; ++f) {
                    bench_method* b = &out[k++];
                    b->precond = solver == WEFT_SOLVER_PCG ? m->preconds[p] : WEFT_PRECOND_BLOCK_JACOBI;
                    b->integrator = m->integrators[g];
                    b->newton = m->newton[w];
                    b->line_search = m->line_search >= 0 ? m->line_search : m->newton[w] > 1;
                    b->forcing = m->forcing[f];
                }
    return k;
}

void bench_method_apply(const bench_method* b, weft_cloth_def* def) {
    def->preconditioner = b->precond;
    def->integrator = b->integrator;
    def->newton_iterations = b->newton;
    def->line_search = b->line_search;
    def->newton_forcing = b->forcing;
}

int bench_method_on_gpu(const bench_method* b) {
    return b->precond == WEFT_PRECOND_BLOCK_JACOBI && b->integrator == WEFT_INTEGRATOR_BACKWARD_EULER &&
           b->newton == 1 && !b->line_search;
}

const char* bench_precond_label(weft_solver solver, const bench_method* b) {
    return solver == WEFT_SOLVER_PCG ? cli_precond_name(b->precond) : "-";
}

const char* bench_forcing_label(double forcing, char* buf, size_t size) {
    if (forcing < 0) snprintf(buf, size, "default");
    else snprintf(buf, size, "%g", forcing);
    return buf;
}

const char* bench_method_short(weft_solver solver, const bench_method* b, char* buf, size_t size) {
    size_t at = 0;
    buf[0] = '\0';
#define ADD(...)                                                                    \
    do {                                                                            \
        int w_ = snprintf(buf + at, size - at, "%s", at ? " " : "");                \
        if (w_ > 0 && (size_t)w_ < size - at) at += (size_t)w_;                     \
        w_ = snprintf(buf + at, size - at, __VA_ARGS__);                            \
        if (w_ > 0 && (size_t)w_ < size - at) at += (size_t)w_;                     \
    } while (0)
    if (solver == WEFT_SOLVER_PCG) ADD("%s", cli_precond_name(b->precond));
    if (b->integrator != WEFT_INTEGRATOR_BACKWARD_EULER) ADD("%s", cli_integrator_name(b->integrator));
    if (b->newton != 1) ADD("n%d", b->newton);
    if (b->line_search) ADD("ls");
    if (b->newton > 1 && solver != WEFT_SOLVER_DIRECT && b->forcing >= 0) ADD("f%g", b->forcing);
#undef ADD
    return buf;
}
