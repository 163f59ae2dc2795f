/* Blender's cloth solver as a child process for `weft bench peers` (see bench_blender.h). */
#define _POSIX_C_SOURCE 200809L
#include "bench_blender.h"

#include <cjson/cJSON.h>
#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <signal.h>
#include <spawn.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "cli.h"

extern char** environ;

static void say(char* msg, size_t size, const char* fmt, ...) __attribute__((format(printf, 3, 4)));
static void say(char* msg, size_t size, const char* fmt, ...) {
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, size, fmt, ap);
    va_end(ap);
}

static int is_executable_file(const char* path) {
    struct stat st;
    return stat(path, &st) == 0 && S_ISREG(st.st_mode) && access(path, X_OK) == 0;
}

int bench_blender_find(const char* given, char* out, size_t size, char* msg, size_t msg_size) {
    if (given) {
        if (!is_executable_file(given)) {
            say(msg, msg_size, "blender: '%s' is not an executable file", given);
            return -1;
        }
        snprintf(out, size, "%s", given);
        return 0;
    }
    const char* path = getenv("PATH");
    for (const char* p = path ? path : ""; *p;) {
        const char* colon = strchr(p, ':');
        size_t len = colon ? (size_t)(colon - p) : strlen(p);
        if (len > 0 && len + 9 < size) {
            snprintf(out, size, "%.*s/blender", (int)len, p);
            if (is_executable_file(out)) return 0;
        }
        if (!colon) break;
        p = colon + 1;
    }
    say(msg, msg_size,
        "blender is not installed: no `blender` on PATH (Debian: apt-get install blender; or give --blender PATH)");
    return -1;
}

/* ---------- the temporary folder ---------- */

typedef struct work_dir {
    char dir[512];
    char obj[600], job[600], result[600], log[600], frames[600];
} work_dir;

static int work_dir_make(work_dir* w, char* msg, size_t msg_size) {
    const char* tmp = getenv("TMPDIR");
    if (!tmp || !*tmp) tmp = "/tmp";
    snprintf(w->dir, sizeof w->dir, "%s/weft-peers-XXXXXX", tmp);
    if (!mkdtemp(w->dir)) {
        say(msg, msg_size, "cannot create a temporary folder in %s: %s", tmp, strerror(errno));
        return -1;
    }
    snprintf(w->obj, sizeof w->obj, "%s/cloth.obj", w->dir);
    snprintf(w->job, sizeof w->job, "%s/job.json", w->dir);
    snprintf(w->result, sizeof w->result, "%s/result.json", w->dir);
    snprintf(w->log, sizeof w->log, "%s/blender.log", w->dir);
    snprintf(w->frames, sizeof w->frames, "%s/frames.f32", w->dir);
    return 0;
}

static void work_dir_remove(const work_dir* w) {
    remove(w->obj);
    remove(w->job);
    remove(w->result);
    remove(w->log);
    remove(w->frames);
    rmdir(w->dir);
}

/* ---------- the job ---------- */

/* Order of float triples, for merging equal positions (qsort passes no context: the positions
 * sorted are g_sort_x's; the tool runs one thread). */
static const float* g_sort_x;
static int cmp_position(const void* a, const void* b) {
    const float *p = g_sort_x + 3 * (size_t)*(const int*)a, *q = g_sort_x + 3 * (size_t)*(const int*)b;
    for (int k = 0; k < 3; ++k)
        if (p[k] != q[k]) return p[k] < q[k] ? -1 : 1;
    return 0;
}

int bench_peer_mesh_make(bench_peer_mesh* out, const scene* s, const float* rest, int n_vertices, const char* name) {
    memset(out, 0, sizeof *out);
    out->name = name;
    out->mesh = &s->mesh;
    for (int k = 0; k < 3; ++k) out->gravity[k] = s->def.gravity[k];
    const size_t nv = (size_t)(n_vertices > 0 ? n_vertices : 1);
    int* order = malloc(sizeof(int) * nv);
    out->of_vertex = malloc(sizeof(int) * nv);
    out->x = malloc(sizeof(float) * 3 * nv);
    int total = 0;
    for (int g = 0; g < s->n_pin_groups; ++g) total += s->pin_groups[g].n_vertices;
    out->pins = malloc(sizeof(int) * (size_t)(total + 1));
    unsigned char* seen = NULL;
    if (!order || !out->of_vertex || !out->x || !out->pins) goto oom;
    /* welded twins report the same rest position: one particle per distinct position, in the
       order of their first host vertex */
    for (int v = 0; v < n_vertices; ++v) order[v] = v;
    g_sort_x = rest;
    qsort(order, (size_t)n_vertices, sizeof(int), cmp_position);
    for (int v = 0; v < n_vertices; ++v) out->of_vertex[v] = -1;
    for (int k = 0; k < n_vertices;) {   /* each run of equal positions: its smallest host vertex */
        int e = k + 1, first = order[k];
        for (; e < n_vertices && cmp_position(&order[k], &order[e]) == 0; ++e)
            if (order[e] < first) first = order[e];
        for (int j = k; j < e; ++j) out->of_vertex[order[j]] = first;
        k = e;
    }
    for (int v = 0; v < n_vertices; ++v)   /* number the particles in host order */
        if (out->of_vertex[v] == v) {
            memcpy(out->x + 3 * (size_t)out->n, rest + 3 * (size_t)v, 3 * sizeof(float));
            order[v] = out->n++;
        }
    for (int v = 0; v < n_vertices; ++v) out->of_vertex[v] = order[out->of_vertex[v]];
    seen = calloc((size_t)out->n + 1, 1);
    if (!seen) goto oom;
    for (int g = 0; g < s->n_pin_groups; ++g)
        for (int k = 0; k < s->pin_groups[g].n_vertices; ++k) {
            const int p = out->of_vertex[s->pin_groups[g].vertices[k]];
            if (!seen[p]) out->pins[out->n_pins++] = p;
            seen[p] = 1;
        }
    free(seen);
    free(order);
    return 0;
oom:
    free(order);
    bench_peer_mesh_free(out);
    return -1;
}

void bench_peer_mesh_free(bench_peer_mesh* m) {
    free(m->x);
    free(m->of_vertex);
    free(m->pins);
    memset(m, 0, sizeof *m);
}

/* One OBJ vertex per particle (rest positions) and one face per source polygon whose corners are
 * distinct particles. */
static int write_obj(const char* path, const bench_peer_mesh* pm, char* msg, size_t msg_size) {
    const scene_mesh* src = pm->mesh;
    FILE* f = fopen(path, "w");
    if (!f) {
        say(msg, msg_size, "cannot write %s: %s", path, strerror(errno));
        return -1;
    }
    fprintf(f, "# %s: %d particles of weft's cloth\n", pm->name, pm->n);
    for (int i = 0; i < pm->n; ++i) {
        const float* x = pm->x + 3 * (size_t)i;
        fprintf(f, "v %.9g %.9g %.9g\n", (double)x[0], (double)x[1], (double)x[2]);
    }
    int faces = 0;
    for (int k = 0; k < src->n_faces; ++k) {
        const int a = src->face_start[k], b = src->face_start[k + 1];
        int ok = b - a >= 3;
        for (int c = a; c < b && ok; ++c)
            for (int e = a; e < c && ok; ++e) ok = pm->of_vertex[src->indices[e]] != pm->of_vertex[src->indices[c]];
        if (!ok) continue;
        fputc('f', f);
        for (int c = a; c < b; ++c) fprintf(f, " %d", pm->of_vertex[src->indices[c]] + 1);
        fputc('\n', f);
        ++faces;
    }
    const int bad = ferror(f);
    if (fclose(f) != 0 || bad) {
        say(msg, msg_size, "error writing %s", path);
        return -1;
    }
    if (faces == 0) {
        say(msg, msg_size, "%s: no face to give Blender", pm->name);
        return -1;
    }
    return 0;
}

static int write_job(const work_dir* w, const bench_peer_mesh* pm, const bench_blender_job* bj, char* msg,
                     size_t msg_size) {
    cJSON* job = cJSON_CreateObject();
    cJSON* pins = cJSON_AddArrayToObject(job, "pins");
    for (int k = 0; k < pm->n_pins && pins; ++k) cJSON_AddItemToArray(pins, cJSON_CreateNumber(pm->pins[k]));
    cJSON_AddStringToObject(job, "mesh", w->obj);
    cJSON_AddNumberToObject(job, "frames", bj->frames);
    cJSON_AddNumberToObject(job, "quality", bj->quality > 0 ? bj->quality : 5);
    if (bj->all_frames) cJSON_AddStringToObject(job, "frames_out", w->frames);
    cJSON_AddItemToObject(job, "gravity", cJSON_CreateDoubleArray(pm->gravity, 3));
    if (bj->spin != 0) {
        cJSON* twirl = cJSON_AddObjectToObject(job, "twirl");
        cJSON_AddNumberToObject(twirl, "spin", bj->spin);
        cJSON_AddNumberToObject(twirl, "ramp", bj->ramp);
        cJSON_AddNumberToObject(twirl, "fps", bj->fps);
    }
    char* text = cJSON_Print(job);
    cJSON_Delete(job);
    FILE* f = text ? fopen(w->job, "w") : NULL;
    int bad = !f || fputs(text, f) < 0;
    if (f) bad |= fclose(f) != 0;
    cJSON_free(text);
    if (bad) say(msg, msg_size, "cannot write %s", w->job);
    return bad ? -1 : 0;
}

/* ---------- the child ---------- */

static double now_s(void) {
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* The last characters of the log, on one line. */
static void log_tail(const char* path, char* out, size_t size) {
    out[0] = '\0';
    FILE* f = fopen(path, "rb");
    if (!f) return;
    char buf[700];
    long at = 0;
    if (fseek(f, 0, SEEK_END) == 0 && (at = ftell(f)) > (long)sizeof buf - 1) fseek(f, at - (long)sizeof buf + 1, SEEK_SET);
    else fseek(f, 0, SEEK_SET);
    size_t n = fread(buf, 1, sizeof buf - 1, f);
    fclose(f);
    buf[n] = '\0';
    for (size_t k = 0; k < n; ++k)
        if (buf[k] == '\n' || buf[k] == '\r' || buf[k] == '\t') buf[k] = ' ';
    snprintf(out, size, "%s", buf);
}

/* Run argv with stdin from /dev/null and stdout + stderr into log, in the environment envp; kill it
 * after timeout_s. 0 when it exited with status 0, else -1 with msg. */
static int run_child(char* const* argv, char* const* envp, const char* log, double timeout_s, char* msg,
                     size_t msg_size) {
    posix_spawn_file_actions_t fa;
    posix_spawn_file_actions_init(&fa);
    posix_spawn_file_actions_addopen(&fa, 0, "/dev/null", O_RDONLY, 0);
    posix_spawn_file_actions_addopen(&fa, 1, log, O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_adddup2(&fa, 1, 2);
    pid_t pid;
    int err = posix_spawn(&pid, argv[0], &fa, NULL, argv, envp);
    posix_spawn_file_actions_destroy(&fa);
    if (err != 0) {
        say(msg, msg_size, "cannot start %s: %s", argv[0], strerror(err));
        return -1;
    }
    const double t0 = now_s();
    int status = 0;
    for (;;) {
        pid_t r = waitpid(pid, &status, WNOHANG);
        if (r == pid) break;
        if (r < 0 && errno != EINTR) {
            say(msg, msg_size, "waiting for blender: %s", strerror(errno));
            return -1;
        }
        if (now_s() - t0 > timeout_s) {
            kill(pid, SIGKILL);
            while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
            }
            say(msg, msg_size, "blender did not finish within %g s (--timeout): killed", timeout_s);
            return -1;
        }
        const struct timespec nap = {0, 20 * 1000 * 1000};
        nanosleep(&nap, NULL);
    }
    if (WIFEXITED(status) && WEXITSTATUS(status) == 0) return 0;
    char tail[700];
    log_tail(log, tail, sizeof tail);
    if (WIFEXITED(status))
        say(msg, msg_size, "blender exited with status %d; its last output: %s", WEXITSTATUS(status), tail);
    else
        say(msg, msg_size, "blender was killed by signal %d; its last output: %s", WTERMSIG(status), tail);
    return -1;
}

/* ---------- the result ---------- */

static char* read_file(const char* path) {
    FILE* f = fopen(path, "rb");
    if (!f) return NULL;
    char* text = NULL;
    long n = -1;
    if (fseek(f, 0, SEEK_END) == 0) n = ftell(f);
    if (n >= 0 && fseek(f, 0, SEEK_SET) == 0 && (text = malloc((size_t)n + 1)) != NULL) {
        if (fread(text, 1, (size_t)n, f) != (size_t)n) {
            free(text);
            text = NULL;
        } else {
            text[n] = '\0';
        }
    }
    fclose(f);
    return text;
}

/* a[0..n) from a JSON array of n finite numbers; -1 otherwise */
static int number_array(const cJSON* arr, double* a, int n) {
    if (!cJSON_IsArray(arr) || cJSON_GetArraySize(arr) != n) return -1;
    int k = 0;
    for (const cJSON* it = arr->child; it; it = it->next, ++k) {
        if (!cJSON_IsNumber(it) || !isfinite(it->valuedouble)) return -1;
        a[k] = it->valuedouble;
    }
    return 0;
}

static void settings_text(const cJSON* s, char* out, size_t size) {
    size_t at = 0;
    out[0] = '\0';
    for (const cJSON* it = s ? s->child : NULL; it && at + 1 < size; it = it->next) {
        char v[64];
        if (cJSON_IsBool(it)) snprintf(v, sizeof v, "%s", cJSON_IsTrue(it) ? "on" : "off");
        else if (cJSON_IsNumber(it)) snprintf(v, sizeof v, "%.6g", it->valuedouble);
        else if (cJSON_IsString(it)) snprintf(v, sizeof v, "%s", it->valuestring);
        else continue;
        int w = snprintf(out + at, size - at, "%s%s=%s", at ? ", " : "", it->string ? it->string : "?", v);
        if (w < 0) break;
        at += (size_t)w;
    }
}

static int parse_result(const char* path, const bench_peer_mesh* pm, int frames, bench_blender_result* out, char* msg,
                        size_t msg_size) {
    char* text = read_file(path);
    if (!text) {
        say(msg, msg_size, "blender wrote no result (%s)", path);
        return -1;
    }
    cJSON* root = cJSON_Parse(text);
    free(text);
    const int n = pm->n;
    const cJSON* version = cJSON_GetObjectItemCaseSensitive(root, "blender");
    const cJSON* threads = cJSON_GetObjectItemCaseSensitive(root, "threads");
    const cJSON* verts = cJSON_GetObjectItemCaseSensitive(root, "vertices");
    int rc = -1;
    if (!root || !cJSON_IsString(version) || !cJSON_IsNumber(threads) || !cJSON_IsNumber(verts)) {
        say(msg, msg_size, "blender's result %s is not what peer_cloth_bench.py writes", path);
    } else if (verts->valueint != n) {
        say(msg, msg_size, "%s: blender's mesh has %d vertices, weft's %d particles", pm->name, verts->valueint, n);
    } else if (!(out->ms = malloc(sizeof(double) * (size_t)frames)) || !(out->x = malloc(sizeof(double) * 3 * (size_t)n))) {
        say(msg, msg_size, "out of memory");
    } else if (number_array(cJSON_GetObjectItemCaseSensitive(root, "ms"), out->ms, frames) != 0) {
        say(msg, msg_size, "%s: blender's result does not have %d finite frame times", pm->name, frames);
    } else if (number_array(cJSON_GetObjectItemCaseSensitive(root, "positions"), out->x, 3 * n) != 0) {
        say(msg, msg_size, "%s: blender's result does not have %d finite positions", pm->name, n);
    } else {
        snprintf(out->version, sizeof out->version, "%s", version->valuestring);
        out->threads = threads->valueint;
        const cJSON* omp = cJSON_GetObjectItemCaseSensitive(root, "omp_num_threads");
        snprintf(out->omp_threads, sizeof out->omp_threads, "%s", cJSON_IsString(omp) ? omp->valuestring : "");
        out->frames = frames;
        out->n_verts = n;
        settings_text(cJSON_GetObjectItemCaseSensitive(root, "settings"), out->settings, sizeof out->settings);
        double* tmp = malloc(sizeof(double) * (size_t)frames);
        if (tmp) {
            memcpy(tmp, out->ms, sizeof(double) * (size_t)frames);
            out->ms_median = cli_sort_median(tmp, frames);
            const cJSON* cpu = cJSON_GetObjectItemCaseSensitive(root, "cpu_ms");
            out->cpu_ms_median = number_array(cpu, tmp, frames) == 0 ? cli_sort_median(tmp, frames) : NAN;
            free(tmp);
            rc = 0;
        } else {
            say(msg, msg_size, "out of memory");
        }
    }
    cJSON_Delete(root);
    return rc;
}

/* Every frame's positions: frames x n x 3 float32 (the script's frames_out), all finite. */
static int read_frames(const char* path, const bench_peer_mesh* pm, int frames, bench_blender_result* out, char* msg,
                       size_t msg_size) {
    const size_t count = (size_t)frames * (size_t)pm->n * 3;
    FILE* f = fopen(path, "rb");
    out->xs = f ? malloc(sizeof(float) * (count > 0 ? count : 1)) : NULL;
    int rc = -1;
    if (!f) {
        say(msg, msg_size, "blender wrote no frame positions (%s)", path);
    } else if (!out->xs) {
        say(msg, msg_size, "out of memory");
    } else if (fread(out->xs, sizeof(float), count, f) != count || fgetc(f) != EOF) {
        say(msg, msg_size, "%s: blender's frame positions are not %d frames x %d vertices", pm->name, frames, pm->n);
    } else {
        rc = 0;
        for (size_t k = 0; k < count && rc == 0; ++k)
            if (!isfinite(out->xs[k])) {
                say(msg, msg_size, "%s: blender's frame %d has a non-finite position", pm->name, (int)(k / (3 * (size_t)pm->n)) + 1);
                rc = -1;
            }
    }
    if (f) fclose(f);
    return rc;
}

void bench_blender_free(bench_blender_result* r) {
    if (!r) return;
    free(r->ms);
    free(r->x);
    free(r->xs);
    memset(r, 0, sizeof *r);
}

int bench_blender_run(const char* blender, const char* script, const bench_peer_mesh* pm, int frames, int threads,
                      double timeout_s, bench_blender_result* out, char* msg, size_t msg_size) {
    const bench_blender_job job = {frames, threads, 5, 0, timeout_s, 0.0, 0.0, 0.0};
    return bench_blender_run_job(blender, script, pm, &job, out, msg, msg_size);
}

int bench_blender_run_job(const char* blender, const char* script, const bench_peer_mesh* pm,
                          const bench_blender_job* job, bench_blender_result* out, char* msg, size_t msg_size) {
    const int frames = job->frames, threads = job->threads;
    memset(out, 0, sizeof *out);
    if (access(script, R_OK) != 0) {
        say(msg, msg_size, "cannot read the Blender driver script %s (--script)", script);
        return -1;
    }
    work_dir w;
    if (work_dir_make(&w, msg, msg_size) != 0) return -1;
    int rc = write_obj(w.obj, pm, msg, msg_size);
    if (rc == 0) rc = write_job(&w, pm, job, msg, msg_size);
    if (rc == 0) {
        char nthreads[16];
        snprintf(nthreads, sizeof nthreads, "%d", threads);
        char* argv[16];
        int k = 0;
        argv[k++] = (char*)blender;
        argv[k++] = "-b";
        argv[k++] = "--factory-startup";
        if (threads > 0) {
            argv[k++] = "-t";
            argv[k++] = nthreads;
        }
        argv[k++] = "--python-exit-code";
        argv[k++] = "1";
        argv[k++] = "--python";
        argv[k++] = (char*)script;
        argv[k++] = "--";
        argv[k++] = w.job;
        argv[k++] = w.result;
        argv[k] = NULL;
        /* -t N does not reach the OpenMP parts of Debian's Blender (its libgomp takes every core and
           its waiting threads spin): OMP_NUM_THREADS=N too, so that N threads is N threads */
        char omp[32];
        snprintf(omp, sizeof omp, "OMP_NUM_THREADS=%d", threads);
        size_t n_env = 0;
        while (environ[n_env]) ++n_env;
        char** envp = malloc(sizeof(char*) * (n_env + 2));
        if (!envp) {
            say(msg, msg_size, "out of memory");
            rc = -1;
        } else {
            size_t e = 0;
            for (size_t k = 0; k < n_env; ++k)
                if (threads <= 0 || strncmp(environ[k], "OMP_NUM_THREADS=", 16)) envp[e++] = environ[k];
            if (threads > 0) envp[e++] = omp;
            envp[e] = NULL;
            rc = run_child(argv, envp, w.log, job->timeout_s, msg, msg_size);
            free(envp);
        }
    }
    if (rc == 0) rc = parse_result(w.result, pm, frames, out, msg, msg_size);
    if (rc == 0 && job->all_frames) rc = read_frames(w.frames, pm, frames, out, msg, msg_size);
    if (rc != 0) bench_blender_free(out);
    work_dir_remove(&w);
    return rc;
}
