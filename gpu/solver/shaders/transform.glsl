// Per particle, a rigid change of the whole state (teleports, inertia): x' = Rx x + tx,
// v' = Rv v + dv; the solver's warm start (a velocity change) turns with the velocities:
// dv' = Rd dv (Rd = Rv, or I when falling asleep zeroes only the velocities). Outputs: o0 = x, o1 = v, o2 = dv.
uniform sampler2D t0;   // x
uniform sampler2D t1;   // v
uniform sampler2D t2;   // dv (warm start)
uniform mat3 u_rx;
uniform vec3 u_tx;
uniform mat3 u_rv;
uniform vec3 u_dv;
uniform mat3 u_rd;
out vec4 o0;
out vec4 o1;
out vec4 o2;

void main() {
    int i = self_index();
    if (i >= u_n) { o0 = vec4(0.0); o1 = vec4(0.0); o2 = vec4(0.0); return; }
    o0 = vec4(u_rx * ld(t0, i).xyz + u_tx, 0.0);
    o1 = vec4(u_rv * ld(t1, i).xyz + u_dv, 0.0);
    o2 = vec4(u_rd * ld(t2, i).xyz, 0.0);
}
