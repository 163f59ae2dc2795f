/* The benchmark scenes on core (core_scene.h). */
#include "core_scene.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "test_support.h"

#define SPIN 6.283185307179586   /* rad/s: one turn a second */
#define RAMP 0.5                 /* s */

/* n from "prefixN" (2..2048), else 0. */
static int size_of(const char* name, const char* prefix) {
    const size_t k = strlen(prefix);
    if (strncmp(name, prefix, k) != 0) return 0;
    char* end = NULL;
    const long n = strtol(name + k, &end, 10);
    return end != name + k && *end == '\0' && n >= 2 && n <= 2048 ? (int)n : 0;
}

/* Pin the host vertices of `verts` (their particles, each once) at rest. */
static int pin_vertices(core_scene* cs, const int* verts, int n) {
    cs->pins = calloc((size_t)n + 1, sizeof(wc_pin));
    if (!cs->pins) return -1;
    for (int k = 0; k < n; ++k) {
        const int p = cs->model.host_to_particle[verts[k]];
        int seen = p < 0;
        for (int j = 0; j < cs->n_pins && !seen; ++j) seen = cs->pins[j].particle == p;
        if (seen) continue;
        wc_pin* pin = &cs->pins[cs->n_pins++];
        pin->particle = p;
        memcpy(pin->target, cs->model.rest_pos + 3 * p, sizeof pin->target);
    }
    return 0;
}

static int build_garment(core_scene* cs, const char* path, char* msg, size_t size) {
    wc_source_mesh src;
    wc_import_opts o = wc_default_import_opts();
    wc_diag d = {0};
    if (wc_import_file(&src, NULL, path, &o, &d) != WC_OK) {
        snprintf(msg, size, "%s", d.message);
        return -1;
    }
    const wc_model_def md = wc_default_model_def();
    wc_status st = wc_model_build(&cs->model, &src, &md, NULL, &d);
    int rc = st == WC_OK ? 0 : -1;
    if (rc != 0) snprintf(msg, size, "%s: %s", path, d.message);
    double top = -INFINITY;
    int* waist = malloc(sizeof(int) * (size_t)(src.n_verts + 1));
    for (int v = 0; rc == 0 && v < src.n_verts; ++v)
        if (cs->model.host_to_particle[v] >= 0) top = fmax(top, src.pos[3 * v + 1]);
    int n = 0;
    for (int v = 0; rc == 0 && waist && v < src.n_verts; ++v)
        if (cs->model.host_to_particle[v] >= 0 && fabs(src.pos[3 * v + 1] - top) <= 1e-3) waist[n++] = v;
    if (rc == 0 && (!waist || pin_vertices(cs, waist, n) != 0)) rc = -1, snprintf(msg, size, "out of memory");
    free(waist);
    wc_source_mesh_free(&src);
    cs->spin = SPIN;
    return rc;
}

int core_scene_build(core_scene* out, const char* name, const char* garment, char* msg, size_t size) {
    memset(out, 0, sizeof *out);
    snprintf(out->name, sizeof out->name, "%s", name);
    int n = 0, rc = 0;
    if ((n = size_of(name, "sheet")) > 0 || (n = size_of(name, "hang")) > 0) {
        const int hang = name[0] == 'h';
        if (!ts_sheet(&out->model, n, 1.0, hang ? 0.5 : 0.0, hang, 1.0)) return snprintf(msg, size, "%s: model", name), -1;
        /* (0, n - 1) and (n - 1, n - 1): the far edge's corners, the vertical sheet's top ones */
        const int corners[2] = {n * (n - 1), n * n - 1};
        rc = pin_vertices(out, corners, 2);
    } else if (!strcmp(name, "drape") || (n = size_of(name, "drape")) > 0) {
        if (!ts_sheet(&out->model, n ? n : 64, 1.0, 0.3, 0, 1.0)) return snprintf(msg, size, "%s: model", name), -1;
        out->n_colliders = 1;
        out->sphere.type = WC_COLLIDER_SPHERE;
        out->sphere.radius = 0.25;
        out->sphere.thickness = 0.005;
        out->sphere.friction = 0.3;
    } else if (!strcmp(name, "garment")) {
        rc = build_garment(out, garment, msg, size);
    } else {
        snprintf(msg, size, "unknown scene '%s' (expected sheetN, hangN, drape, drapeN or garment)", name);
        return -1;
    }
    if (rc != 0) {
        core_scene_free(out);
        return -1;
    }
    double d2 = 0.0;
    for (int c = 0; c < 3; ++c) {
        const double e = out->model.report.bbox_max[c] - out->model.report.bbox_min[c];
        d2 += e * e;
    }
    out->diag = sqrt(d2);
    return 0;
}

void core_scene_free(core_scene* cs) {
    if (cs->model.n_particles > 0) wc_model_free(&cs->model);
    free(cs->pins);
    memset(cs, 0, sizeof *cs);
}

wc_status core_scene_state(wc_state** out, const core_scene* cs, const wc_sim_def* sd, wc_diag* diag) {
    wc_sim_def d = *sd;
    d.max_pins = cs->n_pins > 0 ? cs->n_pins : 1;
    d.max_colliders = 1;
    wc_status st = wc_state_create(out, &cs->model, &d, NULL, diag);
    if (st == WC_OK) st = wc_state_set_pins(*out, cs->pins, cs->n_pins, diag);
    if (st == WC_OK) st = wc_state_set_colliders(*out, &cs->sphere, cs->n_colliders, diag);
    if (st != WC_OK) {
        wc_state_destroy(*out);
        *out = NULL;
    }
    return st;
}

void core_scene_pins_at(const core_scene* cs, double t, wc_pin* out) {
    const double angle = cs->spin * (t < RAMP ? 0.5 * t * t / RAMP : t - 0.5 * RAMP);
    const double c = cos(angle), s = sin(angle);
    for (int k = 0; k < cs->n_pins; ++k) {
        const double* r = cs->pins[k].target;
        out[k] = cs->pins[k];
        out[k].target[0] = c * r[0] + s * r[2];
        out[k].target[2] = -s * r[0] + c * r[2];
    }
}
