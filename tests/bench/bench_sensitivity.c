/* How sensitive is a benchmark scene to its start? (a benchmark: prints a table; with --check it
 * also asserts what must hold.) `weft bench accuracy`'s reference run (the direct solver,
 * TR-BDF2, 3 Newton iterations with line search and tolerance 1e-10, 8 substeps per frame) again
 * from a start whose unpinned particles are each displaced by d along a fixed pseudo-random
 * direction (a hash of the particle's index), its end against the undisplaced run's: RMS and
 * largest particle distance / the bounding-box diagonal. A difference this size owes nothing to
 * the step: a reference halving figure at or below it is the scene's sensitivity at this horizon,
 * and no reference converges below it. Moving particles inside the state (in double) needs core:
 * the public API's positions are floats and cannot be set.
 *
 *   bench_sensitivity [--scene sheet32] [--displace 1e-8[,...]] [--seconds 2] [--fps 30]
 *                     [--substeps 8] [--newton 3] [--threads 1] [--garment FILE] [--check]
 * --check (two displacements d1 < d2 at least): each run's difference is non-zero (the
 * displacement was applied), grows in proportion to it (d2/d1 within 2x: the scene is still
 * linear in so small a change) and is of its size (between 0.01 and 10 times d2 / diagonal). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core_scene.h"
#include "step.h"

#define MAX_DISPLACE 16

/* A fixed pseudo-random number in [-1, 1) from a 64-bit key (splitmix64's finaliser). */
static double hash_unit(unsigned long long z) {
    z += 0x9e3779b97f4a7c15ULL;
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    z ^= z >> 31;
    return (double)(z >> 11) * 0x1.0p-52 - 1.0;
}

/* Every particle the scene does not pin moved by eps along its own direction. */
static void displace_start(wc_state* s, const core_scene* cs, double eps) {
    for (int i = 0; i < cs->model.n_particles; ++i) {
        int pinned = 0;
        for (int k = 0; k < cs->n_pins && !pinned; ++k) pinned = cs->pins[k].particle == i;
        if (pinned) continue;
        double d[3], len = 0.0;
        for (int c = 0; c < 3; ++c) {
            d[c] = hash_unit(3ULL * (unsigned long long)i + (unsigned long long)c);
            len += d[c] * d[c];
        }
        len = sqrt(len);
        if (len > 0)
            for (int c = 0; c < 3; ++c) s->x[3 * i + c] += eps * d[c] / len;
    }
}

/* The reference run from a start displaced by eps (0: none); its end positions into x. */
static int reference(const core_scene* cs, const wc_sim_def* sd, double eps, int frames, double fps, double* x) {
    wc_state* s = NULL;
    wc_diag d = {0};
    if (core_scene_state(&s, cs, sd, &d) != WC_OK) {
        fprintf(stderr, "bench_sensitivity: %s: %s\n", cs->name, d.message);
        return -1;
    }
    if (eps > 0) displace_start(s, cs, eps);
    wc_pin* pins = malloc(sizeof(wc_pin) * (size_t)(cs->n_pins + 1));
    for (int f = 0; f < frames && pins; ++f) {
        if (cs->spin != 0) {
            core_scene_pins_at(cs, (f + 1) / fps, pins);
            wc_state_set_pins(s, pins, cs->n_pins, &d);
        }
        wc_step_frame(s, 1.0 / fps, NULL, &d);
    }
    memcpy(x, s->x, sizeof(double) * 3 * (size_t)cs->model.n_particles);
    free(pins);
    wc_state_destroy(s);
    return 0;
}

int main(int argc, char** argv) {
    const char* name = "sheet32";
    const char* garment = WEFT_SOURCE_DIR "/sample_scenes/skirt.obj";
    double displace[MAX_DISPLACE] = {1e-8}, seconds = 2.0, fps = 30.0;
    int n_displace = 1, substeps = 8, newton = 3, threads = 1, check = 0;
    for (int i = 1; i < argc; ++i) {
        const char* v = i + 1 < argc ? argv[i + 1] : "";
        if (!strcmp(argv[i], "--check")) {
            check = 1;
            continue;
        }
        if (!strcmp(argv[i], "--scene")) name = v;
        else if (!strcmp(argv[i], "--garment")) garment = v;
        else if (!strcmp(argv[i], "--seconds")) seconds = atof(v);
        else if (!strcmp(argv[i], "--fps")) fps = atof(v);
        else if (!strcmp(argv[i], "--substeps")) substeps = atoi(v);
        else if (!strcmp(argv[i], "--newton")) newton = atoi(v);
        else if (!strcmp(argv[i], "--threads")) threads = atoi(v);
        else if (!strcmp(argv[i], "--displace")) {
            n_displace = 0;
            for (const char* p = v; *p && n_displace < MAX_DISPLACE; p += *p == ',') {
                char* end = NULL;
                displace[n_displace++] = strtod(p, &end);
                if (end == p) break;
                p = end;
            }
        } else {
            fprintf(stderr, "bench_sensitivity: unknown option %s\n", argv[i]);
            return 2;
        }
        ++i;
    }
    for (int k = 0; k < n_displace; ++k)
        if (!(displace[k] > 0 && displace[k] <= 0.01)) {
            fprintf(stderr, "bench_sensitivity: --displace values must be in (0, 0.01]\n");
            return 2;
        }
    if (!(seconds > 0) || !(fps > 0) || substeps < 1 || newton < 1 || threads < 0 || n_displace < 1) {
        fprintf(stderr, "bench_sensitivity: bad --seconds, --fps, --substeps, --newton or --threads\n");
        return 2;
    }
    core_scene cs;
    char msg[512];
    if (core_scene_build(&cs, name, garment, msg, sizeof msg) != 0) {
        fprintf(stderr, "bench_sensitivity: %s\n", msg);
        return 1;
    }
    wc_sim_def sd = wc_default_sim_def();
    sd.threads = threads;
    sd.sleep_speed = 0.0;
    sd.solver.type = WC_SOLVER_DIRECT;
    sd.integrator = WC_INTEGRATOR_TRBDF2;
    sd.newton_iterations = newton;
    sd.line_search = newton > 1;
    if (newton > 1) sd.solver.tolerance = 1e-10;
    sd.substeps = substeps;
    const int frames = (int)lround(seconds * fps) > 0 ? (int)lround(seconds * fps) : 1;
    const int n = cs.model.n_particles;
    double* x0 = malloc(sizeof(double) * 3 * (size_t)n);
    double* x = malloc(sizeof(double) * 3 * (size_t)n);
    double rms[MAX_DISPLACE] = {0};
    int rc = x0 && x ? reference(&cs, &sd, 0.0, frames, fps, x0) : -1;
    printf("%s (%d particles), %g s at %g fps, the reference at %d substeps (TR-BDF2, direct, %d Newton)\n\n"
           "| scene | d (m) | RMS diff (%%) | max diff (%%) |\n|---|---|---|---|\n",
           cs.name, n, seconds, fps, substeps, newton);
    for (int k = 0; k < n_displace && rc == 0; ++k) {
        rc = reference(&cs, &sd, displace[k], frames, fps, x);
        double sum = 0.0, max = 0.0;
        for (int i = 0; i < n && rc == 0; ++i) {
            double e2 = 0.0;
            for (int c = 0; c < 3; ++c) e2 += (x[3 * i + c] - x0[3 * i + c]) * (x[3 * i + c] - x0[3 * i + c]);
            sum += e2;
            if (!(sqrt(e2) <= max)) max = sqrt(e2);
        }
        rms[k] = sqrt(sum / n) / cs.diag;
        printf("| %s | %.3g | %.3g | %.3g |\n", cs.name, displace[k], 100 * rms[k], 100 * max / cs.diag);
    }
    int bad = rc != 0;
    if (check && rc == 0) {
        if (n_displace < 2) {
            fprintf(stderr, "bench_sensitivity: --check needs two displacements\n");
            bad = 1;
        }
        for (int k = 1; k < n_displace && !bad; ++k) {
            const double ratio = rms[k] / rms[k - 1], want = displace[k] / displace[k - 1];
            if (!(rms[k - 1] > 0 && rms[k] > 0)) bad = 1, fprintf(stderr, "  check: a displaced run did not move\n");
            else if (!(ratio > 0.5 * want && ratio < 2.0 * want))
                bad = 1, fprintf(stderr, "  check: the difference grows %g x for a %g x larger displacement\n", ratio, want);
            else if (!(rms[k] > 0.01 * displace[k] / cs.diag && rms[k] < 10 * displace[k] / cs.diag))
                bad = 1, fprintf(stderr, "  check: the difference %g is not of the displacement's size\n", rms[k]);
        }
    }
    free(x0);
    free(x);
    core_scene_free(&cs);
    return bad ? 1 : 0;
}
