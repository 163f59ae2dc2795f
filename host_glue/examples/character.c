/* character: bones, the walk animator and the collision proxies (see character.h). */
#include "character.h"

#include <math.h>
#include <string.h>

#define PI 3.14159265358979323846

/* Rest pose, metres */
#define SPINE_Y 1.00            /* spine bone above the root */
#define SHOULDER_X 0.15         /* shoulder bones, relative to the spine */
#define SHOULDER_Y 0.45
#define ARM_X 0.07              /* upper-arm bones, relative to the shoulders */
#define ARM_Y (-0.02)
#define HIP_X 0.10              /* leg bones, relative to the root */
#define HIP_Y 0.95

/* Gait. Speed and amplitudes ease in over RAMP_S from standing. */
#define WALK_SPEED 1.2          /* m/s */
#define TURN_RADIUS 2.5         /* m: the root walks a circle, turning left */
#define STRIDE_HZ 0.9           /* strides (two steps) per second */
#define RAMP_S 1.0              /* s */
#define SPINE_BOB 0.025         /* m, up and down twice per stride */
#define SPINE_LEAN 0.06         /* rad forward at full speed */
#define SPINE_TWIST 0.07        /* rad, yaw swing once per stride */
#define SHOULDER_BOB 0.02       /* m, left and right out of phase */
#define SHOULDER_ROLL 0.05      /* rad */
#define ARM_SWING 0.30          /* rad */
#define LEG_SWING 0.35          /* rad */

const character_proxy character_proxies[CHARACTER_N_PROXIES] = {
    {"torso", "spine", CHARACTER_CAPSULE, 0.115, 0.22, 0.20},
    {"head", "spine", CHARACTER_SPHERE, 0.10, 0.0, 0.68},
    {"upper_arm_l", "arm_l", CHARACTER_CAPSULE, 0.05, 0.10, -0.15},
    {"upper_arm_r", "arm_r", CHARACTER_CAPSULE, 0.05, 0.10, -0.15},
    {"leg_l", "leg_l", CHARACTER_CAPSULE, 0.065, 0.385, -0.45},
    {"leg_r", "leg_r", CHARACTER_CAPSULE, 0.065, 0.385, -0.45},
    {"ground", NULL, CHARACTER_PLANE, 0.0, 0.0, 0.0},
};

/* local = translation x rotation about a unit axis */
static void translate_rotate(float m[16], double tx, double ty, double tz, const double axis[3],
                             double angle) {
    te_rotate_translate(m, axis[0], axis[1], axis[2], angle, tx, ty, tz);
}

/* local = translation x rotation_1 x rotation_2 (rotation_2 applied first) */
static void translate_rotate2(float m[16], double tx, double ty, double tz, const double a1[3],
                              double angle1, const double a2[3], double angle2) {
    float r1[16], r2[16];
    te_rotate_translate(r1, a1[0], a1[1], a1[2], angle1, tx, ty, tz);
    te_rotate_translate(r2, a2[0], a2[1], a2[2], angle2, 0, 0, 0);
    te_multiply(r1, r2, m);
}

/* Pose for the walk state: speed factor s in [0, 1] scales the gait. */
static void pose(te_engine* e, const character* c, double s) {
    static const double X[3] = {1, 0, 0}, Y[3] = {0, 1, 0}, Z[3] = {0, 0, 1};
    double ph = c->phase;
    translate_rotate(e->bones[c->root].local, c->x, 0.0, c->z, Y, c->heading);
    translate_rotate2(e->bones[c->spine].local, 0.0, SPINE_Y + SPINE_BOB * s * sin(2.0 * ph), 0.0,
                      X, SPINE_LEAN * s, Y, SPINE_TWIST * s * sin(ph));
    for (int side = 0; side < 2; ++side) {
        double sign = side == 0 ? 1.0 : -1.0;   /* out of phase: one up while the other is down */
        translate_rotate(e->bones[c->shoulder[side]].local, sign * SHOULDER_X,
                         SHOULDER_Y + sign * SHOULDER_BOB * s * sin(ph), 0.0, Z,
                         SHOULDER_ROLL * s * sin(ph));
        /* positive angles about X swing a hanging limb backwards */
        translate_rotate(e->bones[c->arm[side]].local, sign * ARM_X, ARM_Y, 0.0, X,
                         -sign * ARM_SWING * s * sin(ph));
        translate_rotate(e->bones[c->leg[side]].local, sign * HIP_X, HIP_Y, 0.0, X,
                         sign * LEG_SWING * s * sin(ph));
    }
}

static double ease(double t) {
    double u = t / RAMP_S;
    if (u >= 1.0) return 1.0;
    if (u <= 0.0) return 0.0;
    return u * u * (3.0 - 2.0 * u);
}

int character_update(te_engine* e, const te_time* time, void* user) {
    character* c = user;
    double s = ease(time->t);
    double v = WALK_SPEED * s;
    c->heading += v / TURN_RADIUS * time->dt;
    c->x += v * sin(c->heading) * time->dt;   /* R_y(heading) maps +Z to (sin, 0, cos) */
    c->z += v * cos(c->heading) * time->dt;
    c->distance += v * time->dt;
    c->phase += 2.0 * PI * STRIDE_HZ * s * time->dt;
    pose(e, c, s);
    return 0;
}

int character_create(te_engine* e, character* c) {
    float m[16];
    memset(c, 0, sizeof *c);
    te_identity(m);
    c->root = te_add_bone(e, "root", -1, m);
    c->spine = te_add_bone(e, "spine", c->root, m);
    c->shoulder[0] = te_add_bone(e, "shoulder_l", c->spine, m);
    c->shoulder[1] = te_add_bone(e, "shoulder_r", c->spine, m);
    c->arm[0] = te_add_bone(e, "arm_l", c->shoulder[0], m);
    c->arm[1] = te_add_bone(e, "arm_r", c->shoulder[1], m);
    c->leg[0] = te_add_bone(e, "leg_l", c->root, m);
    c->leg[1] = te_add_bone(e, "leg_r", c->root, m);
    if (c->root < 0 || c->spine < 0 || c->shoulder[0] < 0 || c->shoulder[1] < 0 || c->arm[0] < 0 ||
        c->arm[1] < 0 || c->leg[0] < 0 || c->leg[1] < 0)
        return 0;
    pose(e, c, 0.0);
    te_update_world(e);
    return 1;
}

void character_proxy_transform(const te_engine* e, int k, float out[16]) {
    const character_proxy* p = &character_proxies[k];
    int bone = p->bone ? te_find_bone(e, p->bone) : -1;
    if (bone < 0) {
        te_identity(out);
        return;
    }
    float offset[16];
    te_rotate_translate(offset, 0, 1, 0, 0.0, 0.0, p->offset_y, 0.0);
    te_multiply(e->bones[bone].world, offset, out);
}
