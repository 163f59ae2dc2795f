/* `weft bench torture`: randomised host inputs (cmd_bench_torture_cases.c) run one case per forked
 * process, so that a crash or a hang is counted instead of ending the run: the child runs the
 * case under alarm(--case-timeout) and writes its torture_result into a pipe; the parent reads
 * it, or judges the child by how it died. Then a Markdown table per kind, the defects with the
 * command that reruns each, and a CSV row per case. */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <math.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "bench_args.h"
#include "bench_backend.h"
#include "bench_commands.h"
#include "bench_table.h"
#include "cli.h"
#include "cmd_bench_torture.h"

typedef struct tort_args {
    bench_common com;
    int quick;
    int cases;              /* --cases N */
    uint64_t seed;          /* --seed S */
    int one_case;           /* --case I, -1: all */
    int kinds[TK_COUNT], n_kinds;
    int case_timeout;       /* s */
    int no_fork;
    torture_opts o;
} tort_args;

void bench_torture_usage(FILE* out) {
    fputs("usage: weft bench torture [--quick] [--cases N] [--seed S] [--kinds LIST] [--case I]\n"
          "                          [--case-timeout S] [--no-fork] [--threads N] [--csv FILE]\n"
          "                          [--md FILE] [--backend cpu|gpu|auto] [--quiet]\n"
          "\n"
          "Randomised torture runs of the public API (weft.h), as a host would call it: random\n"
          "meshes with degenerate triangles and slivers, random pins and colliders, transforms that\n"
          "teleport 1 km or spin at 100 rad/s, NaN and Inf in host inputs, zero-area and\n"
          "one-particle cloths, parameters at the ends of their ranges, on the backend --backend\n"
          "names (the direct solver's cases are refused on the GPU: rejected).\n"
          "Each case runs in its own process. Outcomes:\n"
          "  ok             every call returned WEFT_OK and every output was finite\n"
          "  rejected       a call refused its input with a status and a message, changing nothing\n"
          "  step_failed    WEFT_ERROR_STEP_FAILED, the cloth finite and as it was before the call\n"
          "and the defects:\n"
          "  nonfinite      a NaN or Inf output (vertices, normals, frame stats) after WEFT_OK\n"
          "  state_changed  a refused call changed the cloth (vertices or weft_cloth_save bytes)\n"
          "  empty_message  a non-OK status without weft_context_last_error text\n"
          "  accepted_nonfinite  a NaN or Inf input accepted with WEFT_OK\n"
          "  crash          the case's process died (a signal, or no result)\n"
          "  hang           the case ran past --case-timeout\n"
          "Exit status 0 when no case found a defect, 1 otherwise.\n"
          "\n"
          "options:\n"
          "  --quick              seconds-long preset: 140 small cases (sheets up to 6 x 6, up to 4\n"
          "                       frames), 1 thread (later options still apply)\n"
          "  --cases N            number of cases (default 2100), cycling through the kinds\n"
          "  --seed S             seed (default 1): case I of kind K is the same for the same S\n"
          "  --kinds LIST         random_mesh, teleport, spin, nan_inject, zero_area, one_particle,\n"
          "                       extreme (comma-separated; default all)\n"
          "  --case I             run case I only (of kind LIST[I mod count]); the rerun command of\n"
          "                       each defect\n"
          "  --case-timeout S     seconds a case may run before it counts as a hang (default 60)\n"
          "  --no-fork            run the cases in this process (debugging: a crash ends the run)\n"
          "  --threads N          OpenMP threads of each case's context (default 0: OpenMP's default)\n"
          "  --backend NAME       cpu (default), gpu, or auto: each case's weft_context_def.backend\n"
          "  --csv FILE           write one row per case as CSV\n"
          "  --md FILE            write the Markdown tables to FILE instead of stdout\n"
          "  --quiet              no progress lines on stderr\n"
          "  -h, --help           show this help\n",
          out);
}

static int parse_kinds(const char* text, tort_args* a) {
    char buf[256];
    if (!text || strlen(text) >= sizeof buf) return -1;
    snprintf(buf, sizeof buf, "%s", text);
    a->n_kinds = 0;
    char* save = NULL;
    for (char* item = strtok_r(buf, ",", &save); item; item = strtok_r(NULL, ",", &save)) {
        int k = torture_kind_from_name(item);
        if (k < 0 || a->n_kinds == TK_COUNT) return -1;
        a->kinds[a->n_kinds++] = k;
    }
    return a->n_kinds > 0 && text[strlen(text) - 1] != ',' && text[0] != ',' ? 0 : -1;
}

static int parse_u64(const char* text, uint64_t* out) {
    if (!text || !*text || strspn(text, "0123456789") != strlen(text)) return -1;
    errno = 0;
    unsigned long long v = strtoull(text, NULL, 10);
    if (errno) return -1;
    *out = (uint64_t)v;
    return 0;
}

static void defaults(void* args, int quick) {
    tort_args* a = args;
    memset(a, 0, sizeof *a);
    a->quick = quick;
    a->cases = quick ? 140 : 2100;
    a->seed = 1;
    a->one_case = -1;
    for (int k = 0; k < TK_COUNT; ++k) a->kinds[k] = k;
    a->n_kinds = TK_COUNT;
    a->case_timeout = 60;
    a->o.max_grid = quick ? 6 : 16;
    a->o.max_frames = quick ? 4 : 8;
    a->o.backend = 1;   /* WEFT_BACKEND_CPU */
}

static int own_option(void* args, int argc, char** argv, int* i, const char** v) {
    tort_args* a = args;
    int m = 0;
#define OPT(name) ((m = cli_option_value(argc, argv, i, name, v)) != 0)
#define BAD(cond) (m < 0 ? m : (cond) ? -2 : 1)
    if (!strcmp(argv[*i], "--no-fork")) {
        a->no_fork = 1;
        return 1;
    }
    if (OPT("--cases")) return BAD(cli_parse_int(*v, 1, 10000000, &a->cases) != 0);
    if (OPT("--seed")) return BAD(parse_u64(*v, &a->seed) != 0);
    if (OPT("--kinds")) return BAD(parse_kinds(*v, a) != 0);
    if (OPT("--case")) return BAD(cli_parse_int(*v, 0, 0x7fffffff, &a->one_case) != 0);
    if (OPT("--case-timeout")) return BAD(cli_parse_int(*v, 1, 86400, &a->case_timeout) != 0);
    if (OPT("--backend")) return BAD((a->o.backend = bench_parse_backend(*v)) < 0);
#undef OPT
#undef BAD
    return m;
}

/* ---------- one case in a child process ---------- */

static void run_forked(int kind, const tort_args* a, int index, torture_result* out) {
    int fd[2];
    memset(out, 0, sizeof *out);
    fflush(stdout);
    fflush(stderr);
    if (pipe(fd) != 0) {
        out->outcome = TO_CRASH;
        snprintf(out->detail, sizeof out->detail, "pipe: %s", strerror(errno));
        return;
    }
    pid_t pid = fork();
    if (pid < 0) {
        close(fd[0]), close(fd[1]);
        out->outcome = TO_CRASH;
        snprintf(out->detail, sizeof out->detail, "fork: %s", strerror(errno));
        return;
    }
    if (pid == 0) {
        close(fd[0]);
        alarm((unsigned)a->case_timeout);
        torture_result r;
        torture_run_case(kind, a->seed, index, &a->o, &r);
        const char* p = (const char*)&r;
        size_t left = sizeof r;
        while (left > 0) {
            ssize_t w = write(fd[1], p, left);
            if (w < 0 && errno == EINTR) continue;
            if (w <= 0) _exit(3);
            p += w, left -= (size_t)w;
        }
        _exit(0);
    }
    close(fd[1]);
    torture_result r;
    size_t got = 0;
    while (got < sizeof r) {
        ssize_t n = read(fd[0], (char*)&r + got, sizeof r - got);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) break;
        got += (size_t)n;
    }
    close(fd[0]);
    int status = 0;
    while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {}
    if (WIFSIGNALED(status)) {
        const int sig = WTERMSIG(status);
        out->outcome = sig == SIGALRM ? TO_HANG : TO_CRASH;
        if (sig == SIGALRM) snprintf(out->detail, sizeof out->detail, "still running after %d s", a->case_timeout);
        else snprintf(out->detail, sizeof out->detail, "killed by signal %d (%s)", sig, strsignal(sig));
    } else if (got != sizeof r || !WIFEXITED(status) || WEXITSTATUS(status) != 0) {
        out->outcome = TO_CRASH;
        snprintf(out->detail, sizeof out->detail, "exited with status %d without a result",
                 WIFEXITED(status) ? WEXITSTATUS(status) : -1);
    } else {
        *out = r;
    }
}

/* ---------- tables ---------- */

static const char* status_name(int st) {
#define NAME_(name, value, msg) case value: return #name;
    switch (st) { WEFT_STATUS_LIST(NAME_) }
#undef NAME_
    return "unknown";
}

/* Text safe in a CSV cell and a Markdown table: no commas, quotes, pipes or newlines. */
static void sanitise(char* s) {
    for (; *s; ++s) {
        if (*s == ',') *s = ';';
        else if (*s == '"' || *s == '`') *s = '\'';
        else if (*s == '|') *s = '/';
        else if ((unsigned char)*s < 0x20) *s = ' ';
    }
}

enum { C_KIND, C_CASE, C_SEED, C_OUTCOME, C_DEFECT, C_STATUS, C_WHERE, C_CALLS, C_FRAMES, C_VERTICES, C_DETAIL, N_COLS };
static const char* const csv_cols[N_COLS] = {"kind",   "case",  "seed",   "outcome",  "defect", "status",
                                             "where",  "calls", "frames", "vertices", "detail"};

typedef struct summary {
    const tort_args* a;
    int cases;
    int count[TK_COUNT][TO_COUNT];
    int by_status[TK_COUNT][WEFT_STATUS_COUNT_];
    int defects;
    double seconds;
    int threads;
} summary;

static void rerun_command(const tort_args* a, int kind, int index, char* buf, size_t size) {
    static const char* const backends[] = {"auto", "cpu", "gpu"};
    snprintf(buf, size, "weft bench torture --kinds %s --seed %llu --case %d --threads %d --backend %s%s",
             torture_kind_name(kind), (unsigned long long)a->seed, index, a->com.threads, backends[a->o.backend],
             a->quick ? " --quick" : "");
}

static void write_markdown(FILE* out, const summary* s, const bench_table* t) {
    const tort_args* a = s->a;
    static const char* const backends[] = {"AUTO", "CPU", "GPU"};
    fprintf(out, "## weft bench torture\n\nbackend: %s. Random host inputs through the public API (weft.h), %s. "
                 "Seed %llu, %d case(s), sheets up to %d x %d vertices, up to %d frames per case, %d OpenMP "
                 "thread(s) per case; %.1f s.\n\n",
            backends[a->o.backend], a->no_fork ? "in this process" : "one process per case",
            (unsigned long long)a->seed, s->cases, a->o.max_grid, a->o.max_grid, a->o.max_frames, s->threads, s->seconds);
    fputs("| kind | cases |", out);
    for (int o = 0; o < TO_COUNT; ++o) fprintf(out, " %s |", torture_outcome_name(o));
    fputs("\n|---|---|", out);
    for (int o = 0; o < TO_COUNT; ++o) fputs("---|", out);
    fputc('\n', out);
    int total[TO_COUNT] = {0};
    for (int k = 0; k < TK_COUNT; ++k) {
        int n = 0;
        for (int o = 0; o < TO_COUNT; ++o) n += s->count[k][o], total[o] += s->count[k][o];
        if (n == 0) continue;
        fprintf(out, "| %s | %d |", torture_kind_name(k), n);
        for (int o = 0; o < TO_COUNT; ++o) fprintf(out, " %d |", s->count[k][o]);
        fputc('\n', out);
    }
    fprintf(out, "| all | %d |", s->cases);
    for (int o = 0; o < TO_COUNT; ++o) fprintf(out, " %d |", total[o]);
    fputs("\n\nStatuses of the rejected and step_failed cases:\n\n| kind | statuses |\n|---|---|\n", out);
    for (int k = 0; k < TK_COUNT; ++k) {
        int any = 0;
        for (int st = 1; st < WEFT_STATUS_COUNT_; ++st)
            if (s->by_status[k][st]) {
                if (any++ == 0) fprintf(out, "| %s | ", torture_kind_name(k));
                else fputs(", ", out);
                fprintf(out, "%s %d", status_name(st), s->by_status[k][st]);
            }
        if (any) fputs(" |\n", out);
    }
    fprintf(out, "\n%d cases, %d defects\n\n", s->cases, s->defects);
    for (int r = 0; r < t->n_rows; ++r) {
        char* const* row = t->cells + (size_t)r * N_COLS;
        if (strcmp(row[C_DEFECT], "1") != 0) continue;
        char cmd[256];
        int kind = torture_kind_from_name(row[C_KIND]);
        rerun_command(a, kind, atoi(row[C_CASE]), cmd, sizeof cmd);
        fprintf(out, "- %s case %s: **%s** at %s: %s (`%s`)\n", row[C_KIND], row[C_CASE], row[C_OUTCOME],
                row[C_WHERE], row[C_DETAIL], cmd);
    }
}

static double now_s(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

int bench_torture_run(int argc, char** argv) {
    tort_args a;
    int rc = bench_parse_args(argc, argv, "weft bench torture", bench_torture_usage, defaults, own_option, &a, &a.com);
    if (rc >= 0) return rc;
    if (a.com.plot) return cli_usage_error("weft bench torture", bench_torture_usage, "--plot is not used by torture");
    a.o.threads = a.com.threads;
    summary s;
    memset(&s, 0, sizeof s);
    s.a = &a;
    s.threads = a.com.threads;
    bench_table t;
    bench_table_init(&t, N_COLS, csv_cols, csv_cols);
    const int first = a.one_case >= 0 ? a.one_case : 0;
    const int last = a.one_case >= 0 ? a.one_case + 1 : a.cases;
    const double t0 = now_s();
    for (int i = first; i < last && rc < 0; ++i) {
        const int kind = a.kinds[i % a.n_kinds];
        torture_result r;
        if (a.no_fork) torture_run_case(kind, a.seed, i, &a.o, &r);
        else run_forked(kind, &a, i, &r);
        sanitise(r.where);
        sanitise(r.detail);
        const int defect = r.outcome >= TO_FIRST_DEFECT;
        ++s.cases;
        ++s.count[kind][r.outcome];
        if (!defect && r.outcome != TO_OK && r.status > 0 && r.status < WEFT_STATUS_COUNT_) ++s.by_status[kind][r.status];
        s.defects += defect;
        char b[N_COLS][64];
        snprintf(b[C_KIND], 64, "%s", torture_kind_name(kind));
        snprintf(b[C_CASE], 64, "%d", i);
        snprintf(b[C_SEED], 64, "%llu", (unsigned long long)a.seed);
        snprintf(b[C_OUTCOME], 64, "%s", torture_outcome_name(r.outcome));
        snprintf(b[C_DEFECT], 64, "%d", defect);
        snprintf(b[C_STATUS], 64, "%s", r.outcome == TO_OK ? "" : status_name(r.status));
        snprintf(b[C_WHERE], 64, "%s", r.where);
        snprintf(b[C_CALLS], 64, "%d", r.calls);
        snprintf(b[C_FRAMES], 64, "%d", r.frames);
        snprintf(b[C_VERTICES], 64, "%d", r.vertices);
        const char* cell[N_COLS];
        for (int k = 0; k < N_COLS; ++k) cell[k] = b[k];
        cell[C_DETAIL] = r.detail;
        if (bench_table_add(&t, cell) != 0) {
            cli_error("out of memory");
            rc = CLI_EXIT_FAILURE;
        }
        if (defect && !a.com.quiet) {
            char cmd[256];
            rerun_command(&a, kind, i, cmd, sizeof cmd);
            fprintf(stderr, "DEFECT %s case %d: %s at %s: %s\n  rerun: %s\n", torture_kind_name(kind), i,
                    torture_outcome_name(r.outcome), r.where, r.detail, cmd);
        }
        if (!a.com.quiet && ((i + 1) % 100 == 0 || i + 1 == last))
            fprintf(stderr, "[%d/%d] %d defect(s)\n", i + 1 - first, last - first, s.defects);
    }
    s.seconds = now_s() - t0;
    if (rc < 0) {
        FILE* md = a.com.md ? fopen(a.com.md, "w") : stdout;
        if (!md) {
            fprintf(stderr, "weft: cannot write %s\n", a.com.md);
            rc = CLI_EXIT_FAILURE;
        } else {
            write_markdown(md, &s, &t);
            int bad = ferror(md) != 0;
            if (md != stdout) bad |= fclose(md) != 0;
            if (!bad && a.com.csv) {
                FILE* f = fopen(a.com.csv, "w");
                bad = !f || bench_table_write_csv(&t, f) != 0;
                if (f) bad |= fclose(f) != 0;
                if (!f) fprintf(stderr, "weft: cannot write %s\n", a.com.csv);
            }
            if (bad) cli_error("error writing the tables");
            rc = bad ? CLI_EXIT_FAILURE : s.defects ? CLI_EXIT_FAILURE : CLI_EXIT_OK;
        }
        if (!a.com.quiet) fprintf(stderr, "%d cases, %d defects\n", s.cases, s.defects);
    }
    bench_table_free(&t);
    return rc;
}
