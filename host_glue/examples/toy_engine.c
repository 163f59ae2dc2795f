/* toy_engine: scene graph of bones, fixed-step loop of per-phase callbacks, rigid 4x4 helpers. */
#include "toy_engine.h"

#include <math.h>
#include <string.h>

void te_identity(float m[16]) {
    memset(m, 0, 16 * sizeof(float));
    m[0] = m[5] = m[10] = m[15] = 1.0f;
}

void te_rotate_translate(float m[16], double ax, double ay, double az, double angle, double tx,
                         double ty, double tz) {
    double c = cos(angle), s = sin(angle), k = 1.0 - c;
    double R[3][3] = {{k * ax * ax + c, k * ax * ay - s * az, k * ax * az + s * ay},
                      {k * ax * ay + s * az, k * ay * ay + c, k * ay * az - s * ax},
                      {k * ax * az - s * ay, k * ay * az + s * ax, k * az * az + c}};
    te_identity(m);
    for (int r = 0; r < 3; ++r)
        for (int col = 0; col < 3; ++col) m[4 * col + r] = (float)R[r][col];
    m[12] = (float)tx;
    m[13] = (float)ty;
    m[14] = (float)tz;
}

void te_multiply(const float a[16], const float b[16], float out[16]) {
    for (int col = 0; col < 4; ++col)
        for (int r = 0; r < 4; ++r) {
            double sum = 0.0;
            for (int k = 0; k < 4; ++k) sum += (double)a[4 * k + r] * (double)b[4 * col + k];
            out[4 * col + r] = (float)sum;
        }
}

void te_rigid_inverse(const float m[16], float out[16]) {
    te_identity(out);
    for (int r = 0; r < 3; ++r)
        for (int col = 0; col < 3; ++col) out[4 * col + r] = m[4 * r + col];
    for (int r = 0; r < 3; ++r) {
        double t = 0.0;
        for (int k = 0; k < 3; ++k) t -= (double)m[4 * r + k] * (double)m[12 + k];
        out[12 + r] = (float)t;
    }
}

void te_apply_vector(const float m[16], const double v[3], double out[3]) {
    for (int r = 0; r < 3; ++r)
        out[r] = (double)m[r] * v[0] + (double)m[4 + r] * v[1] + (double)m[8 + r] * v[2];
}

void te_apply_point(const float m[16], const double p[3], double out[3]) {
    te_apply_vector(m, p, out);
    for (int r = 0; r < 3; ++r) out[r] += (double)m[12 + r];
}

void te_init(te_engine* e, double dt) {
    memset(e, 0, sizeof *e);
    e->dt = dt;
}

int te_add_bone(te_engine* e, const char* name, int parent, const float local[16]) {
    if (e->n_bones >= TE_MAX_BONES || parent < -1 || parent >= e->n_bones) return -1;
    int i = e->n_bones++;
    te_bone* b = &e->bones[i];
    b->name = name;
    b->parent = parent;
    memcpy(b->local, local, sizeof b->local);
    if (parent < 0)
        memcpy(b->world, b->local, sizeof b->world);
    else
        te_multiply(e->bones[parent].world, b->local, b->world);
    return i;
}

int te_find_bone(const te_engine* e, const char* name) {
    for (int i = 0; i < e->n_bones; ++i)
        if (strcmp(e->bones[i].name, name) == 0) return i;
    return -1;
}

void te_update_world(te_engine* e) {
    for (int i = 0; i < e->n_bones; ++i) {
        te_bone* b = &e->bones[i];
        if (b->parent < 0)
            memcpy(b->world, b->local, sizeof b->world);
        else
            te_multiply(e->bones[b->parent].world, b->local, b->world);
    }
}

int te_register(te_engine* e, te_phase phase, const char* name, te_callback fn, void* user) {
    if (e->n_callbacks >= TE_MAX_CALLBACKS || !fn || (int)phase < 0 || phase >= TE_PHASE_COUNT)
        return -1;
    int i = e->n_callbacks++;
    e->callbacks[i].phase = phase;
    e->callbacks[i].name = name;
    e->callbacks[i].fn = fn;
    e->callbacks[i].user = user;
    return 0;
}

static int run_phase(te_engine* e, te_phase phase, const te_time* time) {
    for (int i = 0; i < e->n_callbacks; ++i) {
        if (e->callbacks[i].phase != phase) continue;
        int rc = e->callbacks[i].fn(e, time, e->callbacks[i].user);
        if (rc != 0) return rc;
    }
    return 0;
}

int te_run(te_engine* e, int64_t n_frames) {
    for (int64_t f = 1; f <= n_frames; ++f) {
        te_time time = {f, (double)f * e->dt, e->dt};
        int rc = run_phase(e, TE_PHASE_ANIMATE, &time);
        if (rc != 0) return rc;
        te_update_world(e);
        rc = run_phase(e, TE_PHASE_PHYSICS, &time);
        if (rc != 0) return rc;
        rc = run_phase(e, TE_PHASE_RENDER, &time);
        if (rc != 0) return rc;
    }
    return 0;
}
