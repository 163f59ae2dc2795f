/* Scripted rigid motions: the schema and T(t). */
#include "scene_motion.h"

#include <math.h>
#include <string.h>

#include "scene_xform.h"

#define COUNT(a) ((int)(sizeof(a) / sizeof((a)[0])))

scene_motion scene_motion_still(void) {
    scene_motion m;
    memset(&m, 0, sizeof m);
    m.spin_axis[1] = 1.0;
    return m;
}

int scene_motion_is_still(const scene_motion* m) {
    for (int k = 0; k < 3; ++k)
        if (m->velocity[k] != 0 || (m->hz != 0 && m->amplitude[k] != 0)) return 0;
    return m->spin_deg_per_s == 0;
}

int scene_motion_equal(const scene_motion* a, const scene_motion* b) {
    for (int k = 0; k < 3; ++k)
        if (a->pivot[k] != b->pivot[k] || a->velocity[k] != b->velocity[k] || a->spin_axis[k] != b->spin_axis[k] ||
            a->amplitude[k] != b->amplitude[k])
            return 0;
    return a->spin_deg_per_s == b->spin_deg_per_s && a->hz == b->hz && a->start == b->start;
}

void scene_motion_at(const scene_motion* m, double t, double out[16]) {
    const double tau = t > m->start ? t - m->start : 0.0;
    const double pi = 3.14159265358979323846;
    double rot[16], to_pivot[16], from_pivot[16], tmp[16], shift[16];
    const double neg_pivot[3] = {-m->pivot[0], -m->pivot[1], -m->pivot[2]};
    xf_axis_angle(m->spin_axis, m->spin_deg_per_s * tau * (pi / 180.0), rot);
    xf_translation(m->pivot, to_pivot);
    xf_translation(neg_pivot, from_pivot);
    xf_mul(rot, from_pivot, tmp);
    xf_mul(to_pivot, tmp, rot);   /* rotation about the pivot */
    const double wave = m->hz != 0 ? sin(2.0 * pi * m->hz * tau) : 0.0;
    double d[3];
    for (int k = 0; k < 3; ++k) d[k] = m->velocity[k] * tau + m->amplitude[k] * wave;
    xf_translation(d, shift);
    xf_mul(shift, rot, out);
}

int scene_motion_parse(const sj_ctx* c, const cJSON* value, const char* field, scene_motion* out) {
    static const char* const keys[] = {"pivot", "velocity", "spin_axis", "spin_deg_per_s", "oscillate", "start"};
    *out = scene_motion_still();
    if (sj_check_object(c, value, field, keys, COUNT(keys)) < 0) return -1;
    if (sj_numbers(c, value, field, "pivot", 3, out->pivot) < 0) return -1;
    if (sj_numbers(c, value, field, "velocity", 3, out->velocity) < 0) return -1;
    int r = sj_numbers(c, value, field, "spin_axis", 3, out->spin_axis);
    if (r < 0) return -1;
    if (r > 0) {
        const double* a = out->spin_axis;
        const double len = sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
        char path[256];
        sj_join(path, sizeof path, field, "spin_axis");
        if (!(len > 1e-300) || !isfinite(len)) return sj_fail(c, path, "must be a nonzero vector");
        for (int k = 0; k < 3; ++k) out->spin_axis[k] /= len;
    }
    if (sj_number(c, value, field, "spin_deg_per_s", SJ_FINITE, &out->spin_deg_per_s) < 0) return -1;
    if (sj_number(c, value, field, "start", SJ_NONNEGATIVE, &out->start) < 0) return -1;
    const cJSON* osc = NULL;
    if ((r = sj_object(c, value, field, "oscillate", &osc)) < 0) return -1;
    if (r > 0) {
        static const char* const okeys[] = {"amplitude", "hz"};
        char path[256];
        sj_join(path, sizeof path, field, "oscillate");
        if (sj_check_object(c, osc, path, okeys, COUNT(okeys)) < 0) return -1;
        if (!sj_get(osc, "amplitude")) {
            char sub[300];
            sj_join(sub, sizeof sub, path, "amplitude");
            return sj_fail(c, sub, "missing ([x, y, z] metres)");
        }
        if (!sj_get(osc, "hz")) {
            char sub[300];
            sj_join(sub, sizeof sub, path, "hz");
            return sj_fail(c, sub, "missing (cycles per second, > 0)");
        }
        if (sj_numbers(c, osc, path, "amplitude", 3, out->amplitude) < 0) return -1;
        if (sj_number(c, osc, path, "hz", SJ_POSITIVE, &out->hz) < 0) return -1;
    }
    return 0;
}
