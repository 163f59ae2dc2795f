// One particle's projection of a guess (an include of project.glsl and pcg_group.glsl, not a
// pass): dv = z + S dv where the particle is constrained (s1.z: its constrained DOF count), dv
// unchanged where it is free; a non-finite guess, or to_z, gives z.
vec3 project_row(vec3 d, vec3 zi, vec4 s0, vec4 s1, bool to_z) {
    if (to_z || !finite3(d)) return zi;
    return s1.z != 0.0 ? zi + filter_S(s0, s1) * d : d;
}
